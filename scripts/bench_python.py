#!/usr/bin/python3
"""Speed of the Python module beside the CLI and numpy (docs/performance.md, "Python"):

  PYTHONPATH=build/python /usr/bin/python3 scripts/bench_python.py [--repeat R] [--threads T]
                                                                   [--only fig5|estimate|detect]

1. The Fig. 5 sweep (experiments/fig5.toml, 10^5 trials a point) through
   patlab.simulate_experiment and through `build/patlab simulate` (process start to exit), run
   alternately, wall time: the median of R runs each, their ratio, and whether both wrote the
   same CSV bytes.
2. The fast estimator on a (10^6, 4, 2) float64 array of the triangle pattern's patches:
   patlab.estimate (C++, vectorised, parallel, GIL released) against numpy's best vectorised form
   (the sum of rotated pair displacements is linear in the patches: one (N, 8) x (8, 2) product,
   atan2 and the centroid's correction), and the one-trial-at-a-time path the module had before
   (estimate::Fast per trial, the same bits); medians of R runs, wall and CPU time (the CPU time
   of the process, all threads), their ratios, and the largest difference from numpy.
3. detect on an in-memory 780 x 580 frame (../shared/frames/ssl-field-2008.jpg with its settings
   in tests/data/vision; skipped without it): patlab.Detector.detect's wall time per call in
   Python against the C++ call it makes (FrameDetector::Detect, timed inside the binding), the
   median over 50 R frames, and the difference: the Python overhead.
The machines are shared: read the load lines printed (1, 5, 15 minute averages).
"""
import argparse
import math
import os
import pathlib
import statistics
import subprocess
import tempfile
import time

import numpy as np

import patlab

ROOT = pathlib.Path(__file__).resolve().parent.parent


def runs(repeat, call, clock=time.perf_counter):
    """(times of `repeat` calls, the last value)."""
    times = []
    value = None
    for _ in range(repeat):
        start = clock()
        value = call()
        times.append(clock() - start)
    return times, value


def median(values):
    return statistics.median(values)


def fig5(repeat, threads, binary):
    out = tempfile.mkdtemp()
    args = [str(binary), "simulate", "experiments/fig5.toml", "--out", out, "-q"]
    if threads:
        args += ["--threads", str(threads)]
    cli, python = [], []
    result = None
    for _ in range(repeat):  # alternately, so that a change of load hits both alike
        cli += runs(1, lambda: subprocess.run(args, cwd=ROOT, check=True))[0]
        seconds, result = runs(1, lambda: patlab.simulate_experiment(
            ROOT / "experiments" / "fig5.toml", threads=threads))
        python += seconds
    same = (pathlib.Path(out) / "fig5.csv").read_text() == result.csv
    print(f"load {os.getloadavg()}")
    print(f"fig5 sweep, {result.total_trials} trials (fast + ml) on {result.threads} threads, "
          f"median of {repeat}: python {median(python):.3f} s, cli {median(cli):.3f} s (process "
          f"included), python / cli {median(python) / median(cli):.3f}; same CSV bytes: {same}")
    print(f"  python runs {' '.join(f'{t:.3f}' for t in python)}; "
          f"cli runs {' '.join(f'{t:.3f}' for t in cli)}")


def numpy_fast_matrix(pattern):
    """(2n, 2) matrix M with [sum cos, sum sin] = v.reshape(N, 2n) @ M: each orientation pair's
    displacement v_j - v_i rotated back by its model angle, summed (paper section III)."""
    p = pattern.positions_mm
    m = np.zeros((2 * pattern.size, 2))
    for i, j in pattern.orientation_pairs:
        d = p[j] - p[i]
        c, s = d / math.hypot(*d)
        # rotate (dx, dy) by -angle: (c dx + s dy, -s dx + c dy)
        for k, sign in ((j, 1.0), (i, -1.0)):
            m[2 * k] += sign * np.array([c, -s])
            m[2 * k + 1] += sign * np.array([s, c])
    return m


def numpy_fast(pattern, v, m):
    n = pattern.size
    flat = v.reshape(len(v), 2 * n)
    sums = flat @ m
    theta = np.arctan2(sums[:, 1], sums[:, 0])
    mean = v.mean(axis=1)
    cx, cy = pattern.centroid_mm
    c, s = np.cos(theta), np.sin(theta)
    return np.column_stack([mean[:, 0] - (c * cx - s * cy), mean[:, 1] - (s * cx + c * cy), theta])


def estimate(repeat, trials, threads):
    pattern = patlab.Pattern.load(ROOT / "patterns" / "triangle.toml")
    rng = np.random.default_rng(1)
    t = rng.uniform(-math.pi, math.pi, trials)
    c, s = np.cos(t)[:, None], np.sin(t)[:, None]
    p = pattern.positions_mm
    v = np.stack([rng.uniform(-1400, 1400, (trials, 1)) + c * p[:, 0] - s * p[:, 1],
                  rng.uniform(-1150, 1150, (trials, 1)) + s * p[:, 0] + c * p[:, 1]], axis=-1)
    v += rng.normal(0.0, 2.0, v.shape)
    m = numpy_fast_matrix(pattern)
    calls = {
        "numpy": lambda: numpy_fast(pattern, v, m),
        "patlab": lambda: patlab.estimate(pattern, v, "fast", threads=threads),
        "patlab, 1 thread": lambda: patlab.estimate(pattern, v, "fast", threads=1),
        "patlab, one trial at a time (before)":
            lambda: patlab._patlab._estimate(pattern, v, "fast", 20, threads, True)[0],
    }
    wall = {name: [] for name in calls}
    cpu = {name: [] for name in calls}
    poses = {}
    for _ in range(repeat):  # interleaved, so that a change of load hits every one alike
        for name, call in calls.items():
            start_cpu, start = time.process_time(), time.perf_counter()
            poses[name] = call()
            wall[name].append(time.perf_counter() - start)
            cpu[name].append(time.process_time() - start_cpu)
    diff = np.abs(poses["numpy"] - poses["patlab"]).max()
    same = np.array_equal(poses["patlab"], poses["patlab, one trial at a time (before)"])
    print(f"load {os.getloadavg()}")
    print(f"fast estimator on {v.shape} float64, median of {repeat} (wall ms, CPU ms of all "
          f"threads; numpy / it):")
    np_wall, np_cpu = median(wall["numpy"]), median(cpu["numpy"])
    for name in calls:
        w, c = median(wall[name]), median(cpu[name])
        print(f"  {name:40s} wall {w * 1e3:7.1f} ms ({trials / w / 1e6:5.1f} M poses/s, "
              f"{np_wall / w:5.2f}x)   cpu {c * 1e3:7.1f} ms ({np_cpu / c:5.2f}x)")
    print(f"  largest difference from numpy {diff:.2e}; vectorised and one-at-a-time poses "
          f"bit-identical: {same}")


def detect(repeat):
    frames = ROOT.parent / "shared" / "frames"
    data = ROOT / "tests" / "data" / "vision"
    path = frames / "ssl-field-2008.jpg"
    if not path.exists():
        print(f"detect: no {path}; skipped")
        return
    image = patlab.read_frame(path)
    detector = patlab.Detector(data / "ssl-2008.thresholds.toml",
                               data / "ssl-2008.calibration.toml", data / "ssl-2008.detector.toml")
    call = detector.detect
    for _ in range(20):  # warm: the segmenter's buffers are sized on the first frame
        call(image)
    python, cpp = [], []
    for _ in range(50 * repeat):
        start = time.perf_counter()
        found = call(image)
        python.append(time.perf_counter() - start)
        cpp.append(found["cpp_seconds"])
    overhead = [p - c for p, c in zip(python, cpp)]
    print(f"load {os.getloadavg()}")
    print(f"detect on an in-memory {image.shape[1]} x {image.shape[0]} frame "
          f"({len(found['id'])} detections), median of {len(python)} frames: python call "
          f"{median(python) * 1e6:.1f} us, C++ call {median(cpp) * 1e6:.1f} us, python overhead "
          f"{median(overhead) * 1e6:.1f} us (quartiles {np.percentile(overhead, 25) * 1e6:.1f}"
          f"..{np.percentile(overhead, 75) * 1e6:.1f} us)")
    once, _ = runs(5, lambda: patlab.detect(image, data / "ssl-2008.thresholds.toml",
                                            data / "ssl-2008.calibration.toml",
                                            data / "ssl-2008.detector.toml"))
    print(f"  patlab.detect (loads the three files, writes CSV and JSON each call): median "
          f"{median(once) * 1e3:.2f} ms")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--trials", type=int, default=1_000_000)
    parser.add_argument("--only", choices=["fig5", "estimate", "detect"])
    parser.add_argument("--binary", default=os.environ.get("PATLAB_BINARY", ROOT / "build" / "patlab"))
    args = parser.parse_args()
    print(f"load {os.getloadavg()}, numpy {np.__version__}, patlab {patlab.__version__}, "
          f"{os.cpu_count()} cores")
    if args.only in (None, "fig5"):
        fig5(args.repeat, args.threads, args.binary)
    if args.only in (None, "estimate"):
        estimate(args.repeat, args.trials, args.threads)
    if args.only in (None, "detect"):
        detect(args.repeat)


if __name__ == "__main__":
    main()
