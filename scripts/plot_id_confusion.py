#!/usr/bin/python3
"""Plot results/id_confusion.csv (patlab simulate experiments/id_confusion.toml).

One column of panels per pattern. Top row: detection rate (correct ID / robots) against patch
sigma. Bottom row: the two rotation errors on a log scale, ambiguous (ambiguous / robots) and
wrong ID (wrong / (correct + wrong)). Colour says which rate a curve is (detection blue,
ambiguous orange, wrong ID red), marker and line say the false-blob rate (filled circles and a
solid line: none; open squares and a dashed line: the next rate; ...). Error bars are the CSV's
95% Wilson intervals. A rate of zero cannot be drawn on a log axis: it is drawn as an open
down-triangle at 1/N (N robots, or the correct + wrong detections for the wrong-ID rate), "below
1/N", not joined to the measured rates. Each series is shifted slightly in sigma (within
+-0.08 mm) so that equal values do not hide one another. The dotted vertical line is the
rotation-error onset of the first false-blob rate.

Also prints, per pattern and false-blob rate, the rotation-error onset: the smallest sigma whose
rotation-error rate (wrong_id + ambiguous) / robots has a 95% Wilson lower bound above 0.1%.

usage: scripts/plot_id_confusion.py [CSV] [PNG]
       (defaults: results/id_confusion.csv, results/id_confusion.png)
"""
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

import plotinput  # noqa: E402

WHAT = "the CSV of `patlab simulate experiments/id_confusion.toml` (detect mode)"
Z = 1.959963984540054
ONSET_RATE = 1e-3
RATES = [("detection_rate", "tab:blue", "detection rate (correct ID / robots)"),
         ("ambiguous_rate", "tab:orange", "ambiguous / robots (geometry fits several rotations, "
                                          "colours decide none)"),
         ("wrong_id_rate", "tab:red", "wrong ID / (correct + wrong)")]
# Per false-blob rate, in the file's order: marker, whether it is filled, line style.
BLOB_STYLES = [("o", True, "-"), ("s", False, "--"), ("^", False, ":"), ("D", False, "-.")]
SPREAD = 0.16  # mm of sigma over which the series of a panel are shifted
COUNTS = ["frames", "robots", "correct", "wrong_id", "ambiguous"]


def wilson(k, n):
    if n == 0:
        return math.nan, math.nan, math.nan
    p = k / n
    d = 1 + Z * Z / n
    c = (p + Z * Z / (2 * n)) / d
    h = Z / d * math.sqrt(p * (1 - p) / n + Z * Z / (4 * n * n))
    return p, max(0.0, c - h) if k else 0.0, min(1.0, c + h) if k < n else 1.0


def read(path):
    numbers = ["sigma_mm"] + [key + suffix for key, _, _ in RATES for suffix in ("", "_lo", "_hi")]
    table = plotinput.read_csv(path, WHAT, columns=["pattern", "false_blob_rate_per_m2"] + COUNTS,
                               numbers=numbers, integers=COUNTS)
    return table.rows


def number(text):
    return float(text) if text != "" else math.nan


def denominator(row, key):
    """The N of a rate: robots, or correct + wrong detections for the wrong-ID rate."""
    if key == "wrong_id_rate":
        return int(row["correct"]) + int(row["wrong_id"])
    return int(row["robots"])


def series(rows, key):
    """(measured, zeros) of one rate: measured = (sigmas, values, lower bars, upper bars) of the
    rates above zero with NaN at the zeros (so the line breaks there), zeros = (sigmas, 1/N)."""
    sigma = [float(r["sigma_mm"]) for r in rows]
    value = [number(r[key]) for r in rows]
    lo = [number(r[key + "_lo"]) for r in rows]
    hi = [number(r[key + "_hi"]) for r in rows]
    shown = [v if v > 0 else math.nan for v in value]
    below = [v - a for v, a in zip(shown, lo)]
    above = [b - v for v, b in zip(shown, hi)]
    measured = (sigma, shown, below, above)
    zeros = [(s, 1 / denominator(r, key)) for s, v, r in zip(sigma, value, rows)
             if v == 0 and denominator(r, key) > 0]
    return measured, ([s for s, _ in zeros], [f for _, f in zeros])


def onset_of(rows):
    for r in rows:
        k = int(r["wrong_id"]) + int(r["ambiguous"])
        p, lower, _ = wilson(k, int(r["robots"]))
        if lower > ONSET_RATE:
            return float(r["sigma_mm"]), p
    return None


def draw(ax, rows, key, colour, style, offset, log):
    marker, filled, line = style
    (sigma, shown, lo, hi), (zero_sigma, floor) = series(rows, key)
    sigma = [s + offset for s in sigma]
    zero_sigma = [s + offset for s in zero_sigma]
    face = colour if filled else "white"
    if all(math.isnan(v) for v in shown):
        shown, lo, hi = [], [], []  # a rate of zero everywhere: only the zero markers
        sigma = []
    ax.errorbar(sigma, shown, yerr=[lo, hi], ls=line, lw=1.2, color=colour, marker=marker, ms=4,
                mfc=face, capsize=2)
    if log and zero_sigma:
        ax.plot(zero_sigma, floor, "v", ms=5, mfc="none", color=colour)


def shift(slot, slots):
    """The sigma offset of series `slot` of `slots`, within +-SPREAD / 2, so that series with
    equal values (both false-blob rates at a detection rate of 1, the zero markers) do not hide
    one another."""
    return (slot - (slots - 1) / 2) * SPREAD / max(slots - 1, 1)


def figure(rows):
    patterns = list(dict.fromkeys(r["pattern"] for r in rows))
    blob_rates = list(dict.fromkeys(r["false_blob_rate_per_m2"] for r in rows))
    fig, axes = plt.subplots(2, len(patterns), figsize=(4.4 * len(patterns), 8.4), sharex=True,
                             squeeze=False)
    onsets = []
    for col, pattern in enumerate(patterns):
        top, bottom = axes[0][col], axes[1][col]
        for i, blob_rate in enumerate(blob_rates):
            sel = [r for r in rows
                   if r["pattern"] == pattern and r["false_blob_rate_per_m2"] == blob_rate]
            style = BLOB_STYLES[i % len(BLOB_STYLES)]
            draw(top, sel, RATES[0][0], RATES[0][1], style, shift(i, len(blob_rates)), log=False)
            for j, (key, colour, _) in enumerate(RATES[1:]):
                slot = i * (len(RATES) - 1) + j
                draw(bottom, sel, key, colour, style,
                     shift(slot, len(blob_rates) * (len(RATES) - 1)), log=True)
            onset = onset_of(sel)
            onsets.append((pattern, blob_rate, onset))
            if onset and i == 0:
                for ax in (top, bottom):
                    ax.axvline(onset[0], color="gray", lw=0.8, ls=":")
        top.set_title(pattern)
        top.set_ylim(-0.02, 1.02)
        top.grid(alpha=0.3)
        bottom.set_yscale("log")
        bottom.set_ylim(5e-6, 1.5)
        bottom.grid(alpha=0.3, which="major")
        bottom.set_xlabel("patch σ (mm)")
    axes[0][0].set_ylabel("detection rate (correct ID / robots)")
    axes[1][0].set_ylabel("rotation errors (rate)")
    fig.legend(handles=key_handles(blob_rates), loc="lower center", ncol=2, fontsize=8,
               frameon=False)
    fig.suptitle("ID confusion: whole frames through the detector (matched tolerance); "
                 "dotted vertical line: rotation-error onset\n"
                 "each series shifted slightly in σ so that none hides another", fontsize=10)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    return fig, onsets


def key_handles(blob_rates):
    """The legend: one entry per rate (its colour), one per false-blob rate (its marker and
    line), and the zero marker."""
    handles = [Line2D([], [], color=colour, lw=6, alpha=0.8, label=label)
               for _, colour, label in RATES]
    for i, blob_rate in enumerate(blob_rates):
        marker, filled, line = BLOB_STYLES[i % len(BLOB_STYLES)]
        handles.append(Line2D([], [], color="black", marker=marker, ms=5, ls=line,
                              mfc="black" if filled else "white",
                              label=f"{blob_rate} false blobs per m²"))
    handles.append(Line2D([], [], color="black", marker="v", ms=5, mfc="none", lw=0,
                          label="rate 0 in N: below 1/N, drawn at 1/N"))
    return handles


def main(argv):
    if len(argv) > 3:
        plotinput.usage("[CSV [PNG]]")
    src = argv[1] if len(argv) > 1 else "results/id_confusion.csv"
    out = argv[2] if len(argv) > 2 else "results/id_confusion.png"
    fig, onsets = figure(read(src))
    print("pattern        false blobs/m^2  onset sigma mm  (rotation errors / robots there)")
    for pattern, blob_rate, onset in onsets:
        text = f"{onset[0]:g}  ({onset[1]:.4f})" if onset else "none in the sweep"
        print(f"{pattern:14s} {blob_rate:>15s}  {text}")
    plotinput.save(fig, out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv)
