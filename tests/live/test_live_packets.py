"""patlab live's packets decoded by Python: the repository's proto/ files compiled with
protoc --python_out into a temporary folder, the packets of `patlab live` on the golden frame
received on 127.0.0.1 and decoded with python3-protobuf, every robot equal to `patlab detect`'s
output for the same frame. Run by ctest (live_python) with PATLAB_BINARY and PATLAB_SOURCE_DIR."""
import csv
import io
import os
import socket
import subprocess
import sys

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
