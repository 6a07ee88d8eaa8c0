#!/usr/bin/python3
"""Plot the CSV of `patlab compare ... --out DIR` (DIR/compare.csv) for a person to look at.

Top row, one group of bars per design in the compare ranking:
  1. angle std per mm of patch sigma: CRLB, fast and ML (Monte-Carlo, 95% interval);
  2. position std per axis per mm of patch sigma: CRLB, fast and ML;
  3. ID capacity per palette size (log scale).
Below, one small panel per design (same axes in all): the rotation errors (wrong ID + ambiguous)
per robot in whole frames against patch sigma, with 95% Wilson intervals, and the design's
predicted onset (rotation_onset_mm) as a dotted line. A rate of zero cannot be drawn on a log
axis: it is drawn as an open down-triangle at 1/N (N robots at that sigma), "below 1/N", and is
not joined to the measured rates.

usage: scripts/plot_compare.py DIR/compare.csv DIR/compare.png
"""
import math
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

import plotinput  # noqa: E402

WHAT = "the CSV of `patlab compare ... --out DIR` (DIR/compare.csv)"
Z95 = 1.959963984540054  # the 95% normal quantile of patlab's Wilson intervals
ACCURACY = [("crlb_theta_mrad_per_mm", "fast_theta_mrad_per_mm", "ml_theta_mrad_per_mm"),
            ("crlb_pos_per_mm", "fast_pos_per_mm", "ml_pos_per_mm")]
PANEL_COLUMNS = 6  # small panels per row
RATE_COLOUR = "tab:red"


def num(text):
    return float(text) if text != "" else math.nan


def robots_behind_zero(upper):
    """N of a 95% Wilson interval [0, upper] of a count of 0: its upper end is z^2 / (N + z^2),
    so N = z^2 (1 - upper) / upper. patlab writes `upper` to 6 significant digits, which gives N
    to within 0.5 for any N up to 10^5; rounded. NaN when upper is not in (0, 1)."""
    if not 0 < upper < 1:
        return math.nan
    return round(Z95 * Z95 * (1 - upper) / upper)


def sigmas_of(columns):
    """The sigmas of the detect-mode columns (detection_<s>mm, ..., rotation_errors_<s>mm_hi)."""
    pattern = r"(?:detection|wrong_id|ambiguous|rotation_errors)_([0-9.e+-]+)mm(?:_lo|_hi)?"
    return sorted({float(m.group(1)) for m in (re.fullmatch(pattern, c) for c in columns) if m})


def rate_column(sigma):
    return "rotation_errors_%gmm" % sigma


def read(path):
    """The rows and the sigmas of the rotation-error columns; exits 2 on a malformed file."""
    ids_columns = lambda cols: [c for c in cols if re.fullmatch(r"ids_\d+c", c)]  # noqa: E731
    needed = ["design", "rotation_onset_mm"] + [c for group in ACCURACY for c in group]
    table = plotinput.read_csv(path, WHAT, columns=needed)
    sigmas = sigmas_of(table.columns)
    if not sigmas:
        plotinput.fail(path, f"no rotation_errors_<sigma>mm columns; expected {WHAT}")
    if not ids_columns(table.columns):
        plotinput.fail(path, f"no ids_<n>c columns; expected {WHAT}")
    numeric = needed[1:] + ids_columns(table.columns)
    numeric += [c + suffix for group in ACCURACY for c in group[1:] for suffix in ("_lo", "_hi")]
    numeric += [rate_column(s) + suffix for s in sigmas for suffix in ("", "_lo", "_hi")]
    for name in numeric:
        if name not in table.columns:
            plotinput.fail(path, f"no column '{name}' in the header; expected {WHAT}")
    table.require_numbers(numeric)
    return table.rows, sigmas


def rotation_points(row, sigmas):
    """(measured, zeros): measured = [(sigma, rate, lo, hi)] of the rates above zero,
    zeros = [(sigma, 1/N)] of the rates of zero, each at 1/N for its N robots."""
    measured, zeros = [], []
    for s in sigmas:
        rate = num(row[rate_column(s)])
        lo, hi = num(row[rate_column(s) + "_lo"]), num(row[rate_column(s) + "_hi"])
        if rate > 0:
            measured.append((s, rate, lo, hi))
        elif rate == 0:
            n = robots_behind_zero(hi)
            if n > 0:
                zeros.append((s, 1 / n))
    return measured, zeros


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
    ax.set_ylabel(ylabel, fontsize=9)
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)


def rotation_panel(ax, row, sigmas):
    measured, zeros = rotation_points(row, sigmas)
    # The measured rates joined only where they are consecutive in sigma: a zero between two
    # measured rates breaks the line (NaN), so no segment runs down to a made-up floor.
    by_sigma = {s: rate for s, rate, _, _ in measured}
    ax.plot(sigmas, [by_sigma.get(s, math.nan) for s in sigmas], color=RATE_COLOUR, lw=1)
    if measured:
        s, rate, lo, hi = zip(*measured)
        ax.errorbar(s, rate, yerr=[[r - a for r, a in zip(rate, lo)],
                                   [b - r for r, b in zip(rate, hi)]],
                    fmt="o", ms=4, color=RATE_COLOUR, capsize=2, lw=1)
    if zeros:
        s, floor = zip(*zeros)
        ax.plot(s, floor, "v", ms=6, mfc="none", color=RATE_COLOUR)
    onset = num(row["rotation_onset_mm"])
    if math.isnan(onset):
        ax.text(0.04, 0.92, "colours decide every rotation: no onset", transform=ax.transAxes,
                fontsize=7, va="top")
    elif onset > sigmas[-1] + 0.25:
        ax.text(0.96, 0.92, f"onset {onset:.2f} mm →", transform=ax.transAxes, fontsize=7,
                ha="right", va="top")
    else:
        ax.axvline(onset, color="black", ls=":", lw=1)
    ax.set_title(f"{row['rank']}. {row['design']}" if "rank" in row else row["design"],
                 fontsize=9)
    ax.set_yscale("log")
    ax.grid(alpha=0.3, which="major")


def figure(rows, sigmas, title):
    panel_rows = math.ceil(len(rows) / PANEL_COLUMNS)
    panel_columns = min(len(rows), PANEL_COLUMNS)
    fig = plt.figure(figsize=(15, 5.2 + 2.2 * panel_rows), layout="constrained")
    top, bottom, under = fig.subfigures(3, 1, height_ratios=[5.2, 2.2 * panel_rows + 0.3, 0.3])
    accuracy = top.subplots(1, 3)
    bars(accuracy[0], rows, ACCURACY[0], ["CRLB", "fast", "ML"],
         "angle std, mrad per mm of sigma", "angle accuracy (lower is better)")
    bars(accuracy[1], rows, ACCURACY[1], ["CRLB", "fast", "ML"],
         "position std per axis, mm per mm of sigma", "position accuracy (lower is better)")
    ids = [c for c in rows[0] if re.fullmatch(r"ids_\d+c", c)]
    bars(accuracy[2], rows, ids, [c[4:-1] + " colours" for c in ids], "IDs",
         "ID capacity (higher is better)")
    accuracy[2].set_yscale("log")
    most = max(num(r[c]) for r in rows for c in ids)
    accuracy[2].set_ylim(0.8, most * 4)  # bars from 1 ID, room above them for the legend
    panels = bottom.subplots(panel_rows, panel_columns, sharex=True, sharey=True, squeeze=False)
    for ax, row in zip(panels.flat, rows):
        rotation_panel(ax, row, sigmas)
    floors = [f for row in rows for _, f in rotation_points(row, sigmas)[1]]
    lowest = min(floors + [num(row[rate_column(s)]) for row in rows for s in sigmas
                           if num(row[rate_column(s)]) > 0])
    panels[0][0].set_ylim(lowest / 3, 1.5)
    panels[0][0].set_xticks(sigmas)
    panels[0][0].set_xlim(sigmas[0] - 0.35, sigmas[-1] + 0.35)
    for ax in panels.flat[len(rows):]:
        ax.axis("off")
    for ax in panels[-1]:
        ax.set_xlabel("patch σ (mm)", fontsize=8)
    for ax in panels[:, 0]:
        ax.set_ylabel("per robot", fontsize=8)
    key = [Line2D([], [], color=RATE_COLOUR, marker="o", ms=4, lw=1,
                  label="rotation errors / robots, 95% Wilson interval"),
           Line2D([], [], color=RATE_COLOUR, marker="v", ms=6, mfc="none", lw=0,
                  label="none in N robots: below 1/N, drawn at 1/N"),
           Line2D([], [], color="black", ls=":", lw=1,
                  label="predicted onset (rotation_onset_mm)")]
    under.legend(handles=key, loc="center", ncol=3, fontsize=8, frameon=False)
    bottom.suptitle("Rotation errors (wrong ID + ambiguous) in whole frames through the detector, "
                    "one panel per design (same axes)", fontsize=10)
    fig.suptitle(title, fontsize=11)
    return fig


def main(argv):
    if len(argv) != 3:
        plotinput.usage("DIR/compare.csv DIR/compare.png")
    rows, sigmas = read(argv[1])
    fig = figure(rows, sigmas, "patlab compare: %s" % argv[1])
    plotinput.save(fig, argv[2], dpi=100)


if __name__ == "__main__":
    main(sys.argv)
