"""patlab live's packets decoded by Python: the repository's proto/ files compiled with
protoc --python_out into a temporary folder, the packets of `patlab live` on the golden frame
received on 127.0.0.1 and decoded with python3-protobuf, every robot equal to `patlab detect`'s
output for the same frame; and `patlab live --log` stopped by SIGINT or SIGKILL at random moments,
its log read back by an independent reader. Run by ctest (live_python) with PATLAB_BINARY and
PATLAB_SOURCE_DIR."""
import csv
import io
import os
import random
import signal
import socket
import struct
import subprocess
import sys
import time

SOURCE = os.environ["PATLAB_SOURCE_DIR"]
BINARY = os.environ["PATLAB_BINARY"]
GOLDEN = os.path.join(SOURCE, "tests", "data", "golden", "ssl-frame.")
FILES = ["-t", GOLDEN + "thresholds.toml", "-c", GOLDEN + "calibration.toml",
         "-s", GOLDEN + "detector.toml"]


def compile_protos(out_dir):
    proto_dir = os.path.join(SOURCE, "proto")
    protos = sorted(os.path.join(proto_dir, p) for p in os.listdir(proto_dir)
                    if p.endswith(".proto"))
    subprocess.run(["protoc", "--python_out=" + str(out_dir), "-I", proto_dir] + protos,
                   check=True)
    sys.path.insert(0, str(out_dir))
    import messages_robocup_ssl_wrapper_pb2  # noqa: E402 (generated just now)
    return messages_robocup_ssl_wrapper_pb2


def detect_rows():
    out = subprocess.run([BINARY, "detect", GOLDEN + "png"] + FILES, check=True,
                         capture_output=True, text=True).stdout
    return {(r["team"], int(r["id"])): r for r in csv.DictReader(io.StringIO(out))}


def receive_all(sock):
    sock.settimeout(0.3)
    packets = []
    while True:
        try:
            packets.append(sock.recv(65536))
        except socket.timeout:
            return packets


def test_packets_decode_to_detect_output(tmp_path):
    wrapper = compile_protos(tmp_path)
    rows = detect_rows()
    assert len(rows) == 10
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", 0))
    port = sock.getsockname()[1]
    run = subprocess.run([BINARY, "live", GOLDEN + "png", "--loop", "--max-frames", "3",
                          "--list-rate", "100", "--send", "127.0.0.1:%d" % port] + FILES,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    packets = receive_all(sock)
    sock.close()
    assert packets
    for data in packets:
        packet = wrapper.SSL_WrapperPacket()
        packet.ParseFromString(data)
        assert packet.HasField("detection")
        frame = packet.detection
        assert frame.camera_id == 0
        assert frame.t_sent >= frame.t_capture > 1e9
        seen = 0
        for team, robots in (("blue", frame.robots_blue), ("yellow", frame.robots_yellow)):
            for robot in robots:
                for field in ("confidence", "robot_id", "x", "y", "orientation", "pixel_x",
                              "pixel_y", "height"):
                    assert robot.HasField(field), field
                row = rows[(team, robot.robot_id)]
                assert abs(robot.x - float(row["x_mm"])) <= 0.006
                assert abs(robot.y - float(row["y_mm"])) <= 0.006
                assert abs(robot.orientation - float(row["theta_rad"])) <= 0.00006
                assert abs(robot.confidence - float(row["confidence"])) <= 0.00006
                seen += 1
        assert seen == 10
        assert len(frame.balls) == 1


def read_log(path):
    """The SSL log at `path` read by this file's own reader (docs/live.md, "SSL log files"):
    (whole messages as (time_ns, type, bytes), bytes of a cut last record)."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:12] == b"SSL_LOG_FILE" and struct.unpack(">i", data[12:16])[0] == 1, data[:16]
    messages, at = [], 16
    while at + 16 <= len(data):
        time_ns, kind, size = struct.unpack(">qii", data[at:at + 16])
        if at + 16 + size > len(data):
            break
        messages.append((time_ns, kind, data[at + 16:at + 16 + size]))
        at += 16 + size
    return messages, len(data) - at


def whole_messages_so_far(path):
    """The whole messages in the log being written at `path` (0 before its header is whole)."""
    if not os.path.exists(path) or os.path.getsize(path) < 16:
        return 0
    return len(read_log(path)[0])


def test_a_stopped_or_killed_live_leaves_a_log_of_whole_messages(tmp_path):
    """SIGINT stops `patlab live` cleanly: exit 0 and a log of whole messages only. SIGKILL at
    any moment leaves a log that reads back to its last whole message (at most the record being
    written is cut), every whole message a wrapper packet with a detection. 16 rounds, seeded."""
    wrapper = compile_protos(tmp_path)
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", 0))
    port = sock.getsockname()[1]
    rng = random.Random(7)
    for round_ in range(16):
        log = tmp_path / ("round%d.log" % round_)
        process = subprocess.Popen(
            [BINARY, "live", GOLDEN + "png", "--loop", "--list-rate", "200", "--log", str(log),
             "--send", "127.0.0.1:%d" % port] + FILES,
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        # The signal lands a random moment after the first whole message, not after the start: a
        # loaded machine may take longer than any fixed delay to write one.
        deadline = time.monotonic() + 30.0
        while time.monotonic() < deadline and whole_messages_so_far(log) == 0:
            time.sleep(0.02)
        time.sleep(rng.uniform(0.0, 0.9))
        sig = signal.SIGINT if round_ % 2 == 0 else signal.SIGKILL
        process.send_signal(sig)
        _, stderr = process.communicate(timeout=30)
        if sig == signal.SIGINT:
            assert process.returncode == 0, (round_, process.returncode, stderr)
        else:
            assert process.returncode == -signal.SIGKILL, (round_, process.returncode, stderr)
        if sig == signal.SIGKILL and log.stat().st_size == 0:
            continue  # killed between creating the log and writing its header
        messages, cut = read_log(log)
        assert messages, (round_, sig)
        assert cut == 0 or sig == signal.SIGKILL, (round_, cut)
        for time_ns, kind, data in messages:
            assert kind == 2 and time_ns > 0
            packet = wrapper.SSL_WrapperPacket()
            packet.ParseFromString(data)
            assert packet.HasField("detection") or packet.HasField("geometry")
        receive_all(sock)
    sock.close()
