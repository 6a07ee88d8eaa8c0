#!/usr/bin/python3
"""A vectorised numpy version of one Fig. 5 data point, for the speed comparison in docs/performance.md.

usage: /usr/bin/python3 scripts/numpy_baseline.py [TRIALS] [SIGMA_MM]

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


def run(trials, sigma, rng):
    n = len(MODEL)
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


def main(argv):
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
