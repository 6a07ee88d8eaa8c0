#!/usr/bin/python3
"""Draws a Fig. 5-style figure (Bruce & Veloso 2003) from `patlab simulate` results.

usage: /usr/bin/python3 scripts/plot_fig5.py results/fig5.csv results/fig5.png

A missing or malformed CSV ends the script with one line on stderr and exit status 2
(scripts/plotinput.py).

Top row: pattern position std (per axis, pooled over x and y) and pattern angle std against the
patch positional std, one colour per pattern; the fast estimator as a line with dots, the
maximum-likelihood estimator as crosses, each with its 95% confidence interval as error bars,
and the Cramer-Rao bound as a wide pale band under the pattern's curves (the estimators lie on
it, so a thin dashed line would be hidden). Bottom row: efficiency, bound / achieved std, with
its 95% interval (bound / CI high .. bound / CI low) for fast (dots, line) and ML (crosses,
shifted right by a small offset so the two can be told apart); 1 is the bound.

Patterns whose rows are identical in every number (the same geometry, so the same random
streams and the same results: butterfly and ssl-standard in the paper's sweep) are drawn once,
with a combined label that says so, instead of one curve hiding the other.
"""
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import plotinput  # noqa: E402

WHAT = "the CSV of `patlab simulate` (known correspondence, e.g. experiments/fig5.toml)"
NUMBERS = ["sigma_mm", "trials", "std_pos_mm", "std_pos_lo_mm", "std_pos_hi_mm", "crlb_pos_mm",
           "std_theta_rad", "std_theta_lo_rad", "std_theta_hi_rad", "crlb_theta_rad"]

STYLES = {
    "fast": dict(marker="o", ms=3.5, lw=1.3, ls="-"),
    "ml": dict(marker="x", ms=6, lw=0, mew=1.3),
    "lsq": dict(marker="+", ms=6, lw=0),
    "key": dict(marker="s", ms=3, lw=0.8, ls=":"),
}


def read(path):
    table = plotinput.read_csv(path, WHAT, columns=["pattern", "estimator"] + NUMBERS,
                               numbers=NUMBERS)
    rows = defaultdict(list)
    for row, line in zip(table.rows, table.lines):
        if row["estimator"] not in STYLES:
            plotinput.fail(path, f"line {line}: estimator '{row['estimator']}'; expected one of "
                                 + ", ".join(STYLES))
        rows[(row["pattern"], row["estimator"])].append(row)
    return rows


def column(rows, name):
    return [float(r[name]) if r[name] != "" else float("nan") for r in rows]


def fingerprint(rows, pattern):
    """Every number of every row of one pattern, to find patterns with identical results."""
    keys = sorted(k for k in rows if k[0] == pattern)
    return tuple((k[1], tuple(tuple(v for c, v in r.items() if c != "pattern") for r in rows[k]))
                 for k in keys)


def groups(rows):
    """Patterns in file order, those with identical results merged into one group."""
    seen = {}
    for pattern in dict.fromkeys(p for p, _ in rows):
        seen.setdefault(fingerprint(rows, pattern), []).append(pattern)
    return list(seen.values())


def label_of(group):
    if len(group) == 1:
        return group[0]
    return " = ".join(group) + " (same geometry)"


def errorbars(values, lo, hi):
    return [[v - l for v, l in zip(values, lo)], [h - v for v, h in zip(values, hi)]]


def draw_std(ax, series, colour, estimator, value, lo, hi, label):
    sigma = column(series, "sigma_mm")
    v = column(series, value)
    ax.errorbar(sigma, v, yerr=errorbars(v, column(series, lo), column(series, hi)),
                color=colour, ecolor=colour, elinewidth=1.0, capsize=2, label=label,
                **STYLES[estimator])


def draw_efficiency(ax, series, colour, estimator, value, lo, hi, bound, offset, label):
    kept = [r for r in series if float(r["sigma_mm"]) > 0 and r[bound] != ""]
    if not kept:
        return
    sigma = [s + offset for s in column(kept, "sigma_mm")]
    b = column(kept, bound)
    eff = [x / y for x, y in zip(b, column(kept, value))]
    eff_lo = [x / y for x, y in zip(b, column(kept, hi))]
    eff_hi = [x / y for x, y in zip(b, column(kept, lo))]
    style = dict(STYLES[estimator])
    style["lw"] = min(style["lw"], 0.6)
    ax.errorbar(sigma, eff, yerr=errorbars(eff, eff_lo, eff_hi), color=colour, ecolor=colour,
                elinewidth=0.9, capsize=1.5, label=label, **style)


def main(argv):
    if len(argv) != 3:
        plotinput.usage("RESULTS.csv OUT.png")
    rows = read(argv[1])
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    fig, axes = plt.subplots(2, 2, figsize=(12, 9), gridspec_kw=dict(height_ratios=[3, 2]))
    panels = [("std_pos_mm", "std_pos_lo_mm", "std_pos_hi_mm", "crlb_pos_mm",
               "pattern position std (mm, per axis)", "position"),
              ("std_theta_rad", "std_theta_lo_rad", "std_theta_hi_rad", "crlb_theta_rad",
               "pattern angle std (rad)", "angle")]
    estimators = list(dict.fromkeys(e for _, e in rows))
    pattern_groups = groups(rows)
    # Efficiency-row x offsets: each (pattern, estimator) its own slot within +-0.09 mm, so that
    # the error bars do not cover one another.
    slots = len(pattern_groups) * len(estimators)
    step = 0.18 / max(slots - 1, 1)
    for column_index, (value, lo, hi, bound, label, what) in enumerate(panels):
        top, bottom = axes[0][column_index], axes[1][column_index]
        for k, group in enumerate(pattern_groups):
            colour = colours[k % len(colours)]
            pattern = group[0]
            first = rows.get((pattern, "fast")) or next(
                v for (p, _), v in rows.items() if p == pattern)
            top.plot(column(first, "sigma_mm"), column(first, bound), color=colour, lw=7,
                     alpha=0.18, solid_capstyle="butt", zorder=0)
            for e, estimator in enumerate(estimators):
                offset = (k * len(estimators) + e) * step - 0.09
                series = rows.get((pattern, estimator))
                if not series:
                    continue
                name = f"{label_of(group)} ({estimator})"
                draw_std(top, series, colour, estimator, value, lo, hi, name)
                draw_efficiency(bottom, series, colour, estimator, value, lo, hi, bound,
                                offset, name)
        top.set_xlabel("patch positional std (mm)")
        top.set_ylabel(label)
        top.grid(alpha=0.3)
        top.set_xlim(left=0)
        top.set_ylim(bottom=0)
        bottom.axhline(1.0, color="black", lw=1.0, ls="--", zorder=0)
        bottom.set_xlabel("patch positional std (mm)")
        bottom.set_ylabel(f"{what} efficiency (bound / achieved std)")
        bottom.grid(alpha=0.3)
        bottom.set_xlim(left=0)
    axes[0][0].plot([], [], color="gray", lw=7, alpha=0.3, label="Cramér–Rao bound (pale band)")
    axes[0][0].legend(fontsize=7, ncol=2, loc="upper left")
    trials = rows[next(iter(rows))][0]["trials"]
    fig.suptitle(f"Pattern error vs patch error, {trials} simulated detections per point\n"
                 "fast: dots and lines, ML: crosses; in the efficiency row each series is shifted "
                 "slightly in x so that none hides another; dashed: the bound\n"
                 "error bars: 95% confidence intervals (smaller than the markers in the top row)",
                 fontsize=10)
    fig.tight_layout()
    plotinput.save(fig, argv[2], dpi=130)


if __name__ == "__main__":
    main(sys.argv)
