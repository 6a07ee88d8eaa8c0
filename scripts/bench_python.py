#!/usr/bin/python3
"""Speed of the Python module beside the CLI and numpy (docs/performance.md, "Python"):

  PYTHONPATH=build/python /usr/bin/python3 scripts/bench_python.py [--repeat R] [--threads T]

1. The Fig. 5 sweep (experiments/fig5.toml, 10^5 trials a point) through
   patlab.simulate_experiment and through `build/patlab simulate` (process start to exit), wall
   time, the best of R runs each, and whether both wrote the same CSV bytes.
2. The fast estimator on a (10^6, 4, 2) float64 array of the triangle pattern's patches:
   patlab.estimate (C++, parallel, GIL released) against numpy's best vectorised form (the sum of
   rotated pair displacements is linear in the patches: one (N, 8) x (8, 2) product, atan2 and the
   centroid's correction), the best of R runs each, and their largest difference.
The machines are shared: read the load line printed first.
"""
import argparse
import math
import os
import pathlib
import subprocess
import tempfile
import time

import numpy as np

import patlab

ROOT = pathlib.Path(__file__).resolve().parent.parent


def best_of(repeat, call):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        value = call()
        times.append(time.perf_counter() - start)
    return min(times), value


def fig5(repeat, threads, binary):
    out = tempfile.mkdtemp()
    args = [str(binary), "simulate", "experiments/fig5.toml", "--out", out, "-q"]
    if threads:
        args += ["--threads", str(threads)]
    cli_seconds, _ = best_of(repeat, lambda: subprocess.run(args, cwd=ROOT, check=True))
    py_seconds, result = best_of(
        repeat, lambda: patlab.simulate_experiment(ROOT / "experiments" / "fig5.toml",
                                                   threads=threads))
    same = (pathlib.Path(out) / "fig5.csv").read_text() == result.csv
    print(f"fig5 sweep, {result.total_trials} trials (fast + ml) on {result.threads} threads: "
          f"python {py_seconds:.3f} s, cli {cli_seconds:.3f} s (process included), "
          f"ratio {py_seconds / cli_seconds:.3f}; same CSV bytes: {same}")


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


def estimate(repeat, trials):
    pattern = patlab.Pattern.load(ROOT / "patterns" / "triangle.toml")
    rng = np.random.default_rng(1)
    t = rng.uniform(-math.pi, math.pi, trials)
    c, s = np.cos(t)[:, None], np.sin(t)[:, None]
    p = pattern.positions_mm
    v = np.stack([rng.uniform(-1400, 1400, (trials, 1)) + c * p[:, 0] - s * p[:, 1],
                  rng.uniform(-1150, 1150, (trials, 1)) + s * p[:, 0] + c * p[:, 1]], axis=-1)
    v += rng.normal(0.0, 2.0, v.shape)
    m = numpy_fast_matrix(pattern)
    np_seconds, np_poses = best_of(repeat, lambda: numpy_fast(pattern, v, m))
    pl_seconds, pl_poses = best_of(repeat, lambda: patlab.estimate(pattern, v, "fast"))
    ml_seconds, _ = best_of(repeat, lambda: patlab.estimate(pattern, v, "ml"))
    diff = np.abs(np_poses - pl_poses).max()
    print(f"fast estimator on {v.shape} float64: patlab {pl_seconds * 1e3:.1f} ms "
          f"({trials / pl_seconds / 1e6:.1f} M poses/s), numpy {np_seconds * 1e3:.1f} ms "
          f"({trials / np_seconds / 1e6:.1f} M poses/s), patlab {np_seconds / pl_seconds:.2f}x; "
          f"largest difference {diff:.2e}; ml {ml_seconds * 1e3:.1f} ms")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--trials", type=int, default=1_000_000)
    parser.add_argument("--binary", default=os.environ.get("PATLAB_BINARY", ROOT / "build" / "patlab"))
    args = parser.parse_args()
    print(f"load: {os.getloadavg()}, numpy {np.__version__}, patlab {patlab.__version__}")
    fig5(args.repeat, args.threads, args.binary)
    estimate(args.repeat, args.trials)


if __name__ == "__main__":
    main()
