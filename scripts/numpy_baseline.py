#!/usr/bin/python3
"""A vectorised numpy version of one Fig. 5 data point, for the speed comparison in docs/performance.md.

usage: /usr/bin/python3 scripts/numpy_baseline.py [TRIALS] [SIGMA_MM]
       /usr/bin/python3 scripts/numpy_baseline.py --sweep EXPERIMENT.toml [TRIALS]

The second form runs every data point of an experiment file's sweep (its patterns, read from
patterns/*.toml with their orientation pairs, and its sigma grid), TRIALS trials each (default: the
file's), and prints one line with the total trials per second; scripts/bench_numpy.sh times it
beside patlab on the same sweep.

Same experiment as `patlab simulate` (Butterfly / SSL geometry, random poses over 2800 x 2300 mm,
isotropic Gaussian patch noise, the paper's fast estimator, then Newton's method on the
sum-squared error from the fast estimate, 3 steps), written the way a numpy user would: whole
arrays, no Python loops over trials. Prints the trials per second and the angle stds, which
should agree with results/fig5.csv within their confidence intervals.
"""
import sys
import time

import numpy as np

MODEL = np.array([[0.0, 0.0], [35.0, 54.772], [35.0, -54.772], [-54.772, 35.0], [-54.772, -35.0]])
PAIRS = [(i, j) for i in range(1, 5) for j in range(i + 1, 5)]


def run(trials, sigma, rng, model=MODEL, pairs=PAIRS):
    n = len(model)
    MODEL = model  # noqa: N806 (the name of the module constant the body was written with)
    PAIRS = pairs  # noqa: N806
    x = rng.uniform(-1400, 1400, trials)
    y = rng.uniform(-1150, 1150, trials)
    t = rng.uniform(-np.pi, np.pi, trials)
    c, s = np.cos(t), np.sin(t)
    vx = x[:, None] + c[:, None] * MODEL[:, 0] - s[:, None] * MODEL[:, 1]
    vy = y[:, None] + s[:, None] * MODEL[:, 0] + c[:, None] * MODEL[:, 1]
    vx += rng.normal(0.0, sigma, (trials, n))
    vy += rng.normal(0.0, sigma, (trials, n))
    # Fast estimator.
    mx, my = vx.mean(axis=1), vy.mean(axis=1)
    sa = np.zeros(trials)
    sb = np.zeros(trials)
    for i, j in PAIRS:
        d = MODEL[j] - MODEL[i]
        cu, su = d / np.hypot(*d)
        dx, dy = vx[:, j] - vx[:, i], vy[:, j] - vy[:, i]
        sa += cu * dx + su * dy
        sb += -su * dx + cu * dy
    fast_t = np.arctan2(sb, sa)
    pbar = MODEL.mean(axis=0)
    # Newton on E(x, y, theta) from the fast estimate (paper's gradient, exact Hessian).
    rx = mx - (np.cos(fast_t) * pbar[0] - np.sin(fast_t) * pbar[1])
    ry = my - (np.sin(fast_t) * pbar[0] + np.cos(fast_t) * pbar[1])
    rt = fast_t.copy()
    for _ in range(3):
        c, s = np.cos(rt), np.sin(rt)
        xi = rx[:, None] + c[:, None] * MODEL[:, 0] - s[:, None] * MODEL[:, 1] - vx
        yi = ry[:, None] + s[:, None] * MODEL[:, 0] + c[:, None] * MODEL[:, 1] - vy
        ddx = -s[:, None] * MODEL[:, 0] - c[:, None] * MODEL[:, 1]
        ddy = c[:, None] * MODEL[:, 0] - s[:, None] * MODEL[:, 1]
        gx, gy = 2 * xi.sum(1), 2 * yi.sum(1)
        gt = 2 * (xi * ddx + yi * ddy).sum(1)
        hxt, hyt = 2 * ddx.sum(1), 2 * ddy.sum(1)
        htt = (2 * (ddx**2 + ddy**2) - 2 * (xi * ddy - yi * ddx)).sum(1)
        schur = htt - (hxt**2 + hyt**2) / (2 * n)
        st = -(gt - (hxt * gx + hyt * gy) / (2 * n)) / schur
        rx += -(gx + hxt * st) / (2 * n)
        ry += -(gy + hyt * st) / (2 * n)
        rt += st
    wrap = lambda a: (a + np.pi) % (2 * np.pi) - np.pi  # noqa: E731
    return np.std(wrap(fast_t - t), ddof=1), np.std(wrap(rt - t), ddof=1)


def load_pattern(name):
    """Model positions and orientation pairs of patterns/NAME.toml (core/pattern.cpp's default
    pairs: every pair of non-key patches, or key -> the other patch when there is only one)."""
    import tomllib
    from pathlib import Path

    path = Path(__file__).resolve().parent.parent / "patterns" / f"{name}.toml"
    data = tomllib.loads(path.read_text())
    patches = data["patch"]
    model = np.array([[p["x"], p["y"]] for p in patches], dtype=float)
    key = next(i for i, p in enumerate(patches) if p.get("role") == "key")
    if "orientation_pairs" in data:
        pairs = [tuple(p) for p in data["orientation_pairs"]]
    else:
        others = [i for i in range(len(patches)) if i != key]
        pairs = [(key, others[0])] if len(others) == 1 else [
            (others[a], others[b]) for a in range(len(others)) for b in range(a + 1, len(others))]
    return model, pairs


def sweep(experiment, trials):
    """Every (pattern, sigma) point of the experiment file, fast + ml; returns (trials, seconds)."""
    import tomllib

    with open(experiment, "rb") as f:
        exp = tomllib.load(f)
    trials = trials or exp["trials"]
    grid = exp["sigma"]
    sigmas = np.linspace(grid["from"], grid["to"], grid["steps"])
    models = [load_pattern(name) for name in exp["patterns"]]
    rng = np.random.default_rng(exp.get("seed", 2003))
    run(1000, 1.0, rng, *models[0])  # warm-up
    start = time.perf_counter()
    for model, pairs in models:
        for sigma in sigmas:
            with np.errstate(divide="ignore", invalid="ignore"):  # sigma 0: schur may be 0
                run(trials, sigma, rng, model, pairs)
    seconds = time.perf_counter() - start
    total = trials * len(models) * len(sigmas)
    print(f"numpy sweep: {len(models)} patterns x {len(sigmas)} sigmas x {trials} trials = {total} "
          f"trials (fast + ml) in {seconds:.3f} s = {total / seconds / 1e6:.3f} M trials/s "
          f"(one process, numpy {np.__version__})")
    return total, seconds


def main(argv):
    if len(argv) > 2 and argv[1] == "--sweep":
        sweep(argv[2], int(argv[3]) if len(argv) > 3 else 0)
        return
    trials = int(argv[1]) if len(argv) > 1 else 1_000_000
    sigma = float(argv[2]) if len(argv) > 2 else 1.0
    rng = np.random.default_rng(2003)
    run(1000, sigma, rng)  # warm-up
    start = time.perf_counter()
    fast_std, ml_std = run(trials, sigma, rng)
    seconds = time.perf_counter() - start
    print(f"numpy baseline: {trials} butterfly trials (fast + ml) in {seconds:.3f} s = "
          f"{trials / seconds / 1e6:.2f} M trials/s (one process, numpy {np.__version__})")
    print(f"angle std at sigma {sigma:g} mm: fast {fast_std * 1e3:.3f} mrad, ml {ml_std * 1e3:.3f} mrad")


if __name__ == "__main__":
    main(sys.argv)
