#!/usr/bin/python3
"""Plot results/id_confusion.csv (patlab simulate experiments/id_confusion.toml).

Top row: detection rate vs patch sigma, one panel per pattern, one line per false-blob rate.
Bottom row: rotation errors: ambiguous rate (ambiguous / robots) and wrong-ID rate (wrong /
(correct + wrong)), log scale. Error bars are the CSV's 95% Wilson intervals.

Also prints, per pattern and false-blob rate, the rotation-error onset: the smallest sigma whose
rotation-error rate (wrong_id + ambiguous) / robots has a 95% Wilson lower bound above 0.1%.

usage: scripts/plot_id_confusion.py [CSV] [PNG]
"""
import csv
import math
import sys
import warnings

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# A series that is zero everywhere has nothing to draw on a log axis; matplotlib warns about it.
warnings.filterwarnings("ignore", message="All-NaN axis encountered")

Z = 1.959963984540054
ONSET_RATE = 1e-3


def wilson(k, n):
    if n == 0:
        return math.nan, math.nan, math.nan
    p = k / n
    d = 1 + Z * Z / n
    c = (p + Z * Z / (2 * n)) / d
    h = Z / d * math.sqrt(p * (1 - p) / n + Z * Z / (4 * n * n))
    return p, max(0.0, c - h) if k else 0.0, min(1.0, c + h) if k < n else 1.0


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else "results/id_confusion.csv"
    out = sys.argv[2] if len(sys.argv) > 2 else "results/id_confusion.png"
    rows = list(csv.DictReader(open(src)))
    patterns = list(dict.fromkeys(r["pattern"] for r in rows))
    rates = list(dict.fromkeys(r["false_blob_rate_per_m2"] for r in rows))
    fig, axes = plt.subplots(2, len(patterns), figsize=(4.2 * len(patterns), 7.5), sharex=True,
                             squeeze=False)
    styles = ["-", "--", ":", "-."]
    print("pattern        false blobs/m^2  onset sigma mm  (rotation errors / robots there)")
    for col, pattern in enumerate(patterns):
        top, bottom = axes[0][col], axes[1][col]
        for i, rate in enumerate(rates):
            sel = [r for r in rows if r["pattern"] == pattern and r["false_blob_rate_per_m2"] == rate]
            sigma = [float(r["sigma_mm"]) for r in sel]
            ls = styles[i % len(styles)]
            label = f"{rate} false blobs/m²"

            def series(key):
                v = [float(r[key]) if r[key] else math.nan for r in sel]
                lo = [float(r[key + "_lo"]) if r[key + "_lo"] else math.nan for r in sel]
                hi = [float(r[key + "_hi"]) if r[key + "_hi"] else math.nan for r in sel]
                return v, [a - b for a, b in zip(v, lo)], [b - a for a, b in zip(v, hi)]

            v, lo, hi = series("detection_rate")
            top.errorbar(sigma, v, yerr=[lo, hi], ls=ls, color="C0", marker="o", ms=3,
                         capsize=2, label=label)
            for key, color, name in [("ambiguous_rate", "C1", "ambiguous"),
                                     ("wrong_id_rate", "C3", "wrong ID")]:
                v, lo, hi = series(key)
                # Zero rates cannot be drawn on a log axis: plot their upper bound as a marker.
                bottom.errorbar(sigma, [x if x > 0 else math.nan for x in v], yerr=[lo, hi],
                                ls=ls, color=color, marker="o", ms=3, capsize=2,
                                label=f"{name}, {rate}/m²")
            onset = None
            for r in sel:
                k = int(r["wrong_id"]) + int(r["ambiguous"])
                p, lower, _ = wilson(k, int(r["robots"]))
                if lower > ONSET_RATE:
                    onset = (float(r["sigma_mm"]), p)
                    break
            text = f"{onset[0]:g}  ({onset[1]:.4f})" if onset else "none in the sweep"
            print(f"{pattern:14s} {rate:>15s}  {text}")
            if onset and i == 0:
                for ax in (top, bottom):
                    ax.axvline(onset[0], color="gray", lw=0.8, ls=":")
        top.set_title(pattern)
        top.set_ylim(-0.02, 1.02)
        top.grid(alpha=0.3)
        bottom.set_yscale("log")
        bottom.set_ylim(1e-5, 1.5)
        bottom.grid(alpha=0.3, which="both")
        bottom.set_xlabel("patch σ (mm)")
        if col == 0:
            top.set_ylabel("detection rate (correct ID)")
            bottom.set_ylabel("rotation errors")
        top.legend(fontsize=7, loc="lower left")
        bottom.legend(fontsize=7, loc="lower right")
    fig.suptitle("ID confusion: whole frames through the detector (matched tolerance); "
                 "dotted line: rotation-error onset", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
