#!/usr/bin/python3
"""Plot the CSV of `patlab compare ... --out DIR` (DIR/compare.csv) for a person to look at.

Four panels, one bar (or marker) per design in the compare ranking:
  1. angle std per mm of patch sigma: CRLB, fast and ML (Monte-Carlo, 95% interval);
  2. position std per axis per mm of patch sigma: CRLB, fast and ML;
  3. ID capacity per palette size (log scale);
  4. rotation errors (wrong ID + ambiguous) per robot vs patch sigma with 95% Wilson intervals,
     and each design's predicted onset (rotation_onset_mm) as a dotted line.

usage: scripts/plot_compare.py DIR/compare.csv DIR/compare.png
"""
import csv
import math
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def num(text):
    try:
        return float(text)
    except ValueError:
        return math.nan


def bars(ax, rows, names, labels, ylabel, title):
    width = 0.8 / len(names)
    for k, (name, label) in enumerate(zip(names, labels)):
        xs = [i + (k - (len(names) - 1) / 2) * width for i in range(len(rows))]
        ys = [num(r[name]) for r in rows]
        err = None
        if name + "_lo" in rows[0]:
            err = [[y - num(r[name + "_lo"]) for y, r in zip(ys, rows)],
                   [num(r[name + "_hi"]) - y for y, r in zip(ys, rows)]]
        ax.bar(xs, ys, width, yerr=err, label=label, capsize=2)
    ax.set_xticks(range(len(rows)))
    ax.set_xticklabels([r["design"] for r in rows], rotation=45, ha="right", fontsize=7)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)


def rotation_errors(ax, rows):
    sigmas = sorted({float(m.group(1)) for m in
                     (re.fullmatch(r"wrong_id_([0-9.e+-]+)mm", c) for c in rows[0]) if m})
    # Each design shifted a little in sigma and given its own marker, so that designs with the
    # same counts (often zero, drawn at the floor) do not hide one another.
    step = 0.05 * (sigmas[-1] - sigmas[0]) / max(len(rows), 1) if len(sigmas) > 1 else 0.02
    markers = "osD^vP*X"
    for k, r in enumerate(rows):
        ys = [num(r["rotation_errors_%gmm" % s]) for s in sigmas]
        his = [num(r["rotation_errors_%gmm_hi" % s]) for s in sigmas]
        floor = [max(y, 1e-6) for y in ys]
        err = [[0] * len(ys), [max(h, 1e-6) - f for h, f in zip(his, floor)]]
        xs = [s + (k - (len(rows) - 1) / 2) * step for s in sigmas]
        line = ax.errorbar(xs, floor, yerr=err, marker=markers[k % len(markers)], ms=5,
                           capsize=2, lw=1, mfc="none", label=r["design"]).lines[0]
        onset = num(r["rotation_onset_mm"])
        if math.isfinite(onset):
            ax.axvline(onset, color=line.get_color(), linestyle=":", linewidth=0.8)
    ax.set_yscale("log")
    ax.set_xlabel("patch sigma (mm)")
    ax.set_ylabel("rotation errors per robot (0 drawn at the floor 1e-6)")
    ax.set_title("wrong ID + ambiguous, 95% Wilson upper bars; dotted: predicted onset;\n"
                 "designs shifted slightly in sigma so none hides another", fontsize=8)
    ax.legend(fontsize=6)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("%s: no designs" % sys.argv[1])
    fig, axes = plt.subplots(2, 2, figsize=(13, 9))
    bars(axes[0][0], rows, ["crlb_theta_mrad_per_mm", "fast_theta_mrad_per_mm",
                            "ml_theta_mrad_per_mm"], ["CRLB", "fast", "ML"],
         "angle std, mrad per mm of sigma", "angle accuracy (lower is better)")
    bars(axes[0][1], rows, ["crlb_pos_per_mm", "fast_pos_per_mm", "ml_pos_per_mm"],
         ["CRLB", "fast", "ML"], "position std per axis, mm per mm of sigma",
         "position accuracy (lower is better)")
    ids = [c for c in rows[0] if re.fullmatch(r"ids_\d+c", c)]
    bars(axes[1][0], rows, ids, [c[4:-1] + " colours" for c in ids], "IDs",
         "ID capacity (higher is better)")
    axes[1][0].set_yscale("log")
    rotation_errors(axes[1][1], rows)
    fig.suptitle("patlab compare: %s" % sys.argv[1])
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=100)


if __name__ == "__main__":
    main()
