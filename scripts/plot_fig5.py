#!/usr/bin/python3
"""Draws a Fig. 5-style figure (Bruce & Veloso 2003) from `patlab simulate` results.

usage: /usr/bin/python3 scripts/plot_fig5.py results/fig5.csv results/fig5.png

Left: pattern position std (per axis, pooled over x and y) against patch std. Right: pattern
angle std against patch std. One colour per pattern; the fast estimator as a solid line with
dots, the maximum-likelihood estimator as crosses, the Cramer-Rao bound dashed. Shaded bands are
the 95% confidence intervals of the stds (narrower than the lines at 100,000 trials).
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    rows = defaultdict(list)
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            rows[(row["pattern"], row["estimator"])].append(row)
    return rows


def column(rows, name):
    return [float(r[name]) if r[name] != "" else float("nan") for r in rows]


def main(argv):
    if len(argv) != 3:
        sys.exit("usage: plot_fig5.py RESULTS.csv OUT.png")
    rows = read(argv[1])
    patterns = list(dict.fromkeys(p for p, _ in rows))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6))
    panels = [("std_pos_mm", "std_pos_lo_mm", "std_pos_hi_mm", "crlb_pos_mm",
               "pattern position std (mm, per axis)"),
              ("std_theta_rad", "std_theta_lo_rad", "std_theta_hi_rad", "crlb_theta_rad",
               "pattern angle std (rad)")]
    for ax, (value, lo, hi, bound, label) in zip(axes, panels):
        for k, pattern in enumerate(patterns):
            colour = colours[k % len(colours)]
            for estimator, style in (("fast", dict(marker="o", ms=3, lw=1.4)),
                                     ("ml", dict(marker="x", ms=5, lw=0)),
                                     ("lsq", dict(marker="+", ms=5, lw=0)),
                                     ("key", dict(marker="s", ms=3, lw=0.8, ls=":"))):
                series = rows.get((pattern, estimator))
                if not series:
                    continue
                sigma = column(series, "sigma_mm")
                ax.plot(sigma, column(series, value), color=colour,
                        label=f"{pattern} ({estimator})", **style)
                ax.fill_between(sigma, column(series, lo), column(series, hi), color=colour,
                                alpha=0.2, lw=0)
            first = rows.get((pattern, "fast")) or next(v for (p, _), v in rows.items() if p == pattern)
            ax.plot(column(first, "sigma_mm"), column(first, bound), color=colour, ls="--",
                    lw=0.9, alpha=0.8)
        ax.set_xlabel("patch positional std (mm)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.set_xlim(left=0)
        ax.set_ylim(bottom=0)
    axes[0].plot([], [], color="gray", ls="--", lw=0.9, label="Cramér–Rao bound")
    axes[0].legend(fontsize=7, ncol=2, loc="upper left")
    trials = rows[next(iter(rows))][0]["trials"]
    fig.suptitle(f"Pattern error vs patch error ({trials} simulated detections per point; "
                 "fast: dots and lines, ML: crosses, bound: dashed)", fontsize=10)
    fig.tight_layout()
    fig.savefig(argv[2], dpi=130)


if __name__ == "__main__":
    main(sys.argv)
