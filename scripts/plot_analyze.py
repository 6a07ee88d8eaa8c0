#!/usr/bin/python3
"""Figs. 2, 3 and 6 of Bruce & Veloso 2003 (section II) from `patlab analyze` results.

usage: /usr/bin/python3 scripts/plot_analyze.py [DIR [NAME]]   (defaults: results/analyze, analyze)

Reads DIR/NAME_errors.csv (per-sample errors: the paper's estimate, sample minus smoothed track,
and with --truth the true error) and writes into DIR:
  NAME_fig2.png  aggregate error distribution, x and y of every subject pooled, with the Gaussian
                 of the same std (linear and log scale); true error dashed when present;
  NAME_fig3.png  cumulative distributions of |error| per subject, x and y;
  NAME_fig6.png  lag-1 scatter (e_t, e_t+1) of adjacent frames' x errors, per subject.

A missing or malformed CSV ends the script with one line on stderr and exit status 2
(scripts/plotinput.py).
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import plotinput  # noqa: E402

WHAT = "the NAME_errors.csv of `patlab analyze --out DIR --name NAME`"
COLUMNS = {"subject": "str", "run": "str", "frame": "int", "est_x_mm": "float",
           "est_y_mm": "float"}
TRUE_COLUMNS = {"true_x_mm": "float", "true_y_mm": "float"}


def read(path):
    table = plotinput.read_csv(path, WHAT, columns=list(COLUMNS), integers=["frame"])
    columns = dict(COLUMNS)
    if all(c in table.columns for c in TRUE_COLUMNS):
        columns.update(TRUE_COLUMNS)
    table.require_numbers([c for c, kind in columns.items() if kind == "float"], empty_ok=False)
    return table.array(columns)


def subjects(data):
    seen = []
    for s in data["subject"]:
        if s not in seen:
            seen.append(s)
    return seen


def kinds(data):
    return ["est", "true"] if "true_x_mm" in data.dtype.names else ["est"]


def gaussian(x, sigma):
    return np.exp(-0.5 * (x / sigma) ** 2) / (sigma * np.sqrt(2 * np.pi))


def fig2(data, out):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    label = {"est": "sample - smoothed (paper's estimate)", "true": "sample - truth"}
    lim = 4 * np.std(np.concatenate([data["est_x_mm"], data["est_y_mm"]]))
    for kind, colour in zip(kinds(data), ("tab:blue", "tab:orange")):
        e = np.concatenate([data[kind + "_x_mm"], data[kind + "_y_mm"]])
        sigma = np.std(e, ddof=1)
        bins = np.linspace(-lim, lim, 81)
        x = np.linspace(-lim, lim, 400)
        for ax in axes:
            ax.hist(e, bins=bins, density=True, histtype="step", color=colour,
                    label=f"{label[kind]}, σ = {sigma:.3f} mm")
            ax.plot(x, gaussian(x, sigma), color=colour, linestyle=":", linewidth=1)
    axes[1].set_yscale("log")
    for ax in axes:
        ax.set_xlabel("error (mm), x and y of every subject pooled")
        ax.set_ylabel("density")
    axes[0].legend(fontsize=8, loc="upper left")
    axes[0].set_title("Fig. 2: aggregate error distribution (dotted: Gaussian, same σ)")
    axes[1].set_title("same, log scale")
    fig.tight_layout()
    plotinput.save(fig, out, dpi=110)
    plt.close(fig)


def fig3(data, out):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, axis in zip(axes, ("x", "y")):
        for colour, subject in zip(colours * 4, subjects(data)):
            rows = data["subject"] == subject
            for kind, style in zip(kinds(data), ("-", "--")):
                e = np.sort(np.abs(data[f"{kind}_{axis}_mm"][rows]))
                f = np.arange(1, e.size + 1) / e.size
                ax.plot(e, f, style, color=colour,
                        label=f"{subject} {'estimated' if kind == 'est' else 'true'}")
        ax.set_xlabel(f"|error| in {axis} (mm)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("fraction of samples")
    axes[0].legend(fontsize=7, loc="lower right")
    fig.suptitle("Fig. 3: cumulative distributions of absolute error "
                 "(solid: sample - smoothed, dashed: sample - truth)")
    fig.tight_layout()
    plotinput.save(fig, out, dpi=110)
    plt.close(fig)


def lag_pairs(rows, column):
    """(e_t, e_t+1) of adjacent frames of the same run."""
    a, b = [], []
    for run in np.unique(rows["run"]):
        r = rows[rows["run"] == run]
        adjacent = np.nonzero(np.diff(r["frame"]) == 1)[0]
        a.append(r[column][adjacent])
        b.append(r[column][adjacent + 1])
    return np.concatenate(a), np.concatenate(b)


def fig6(data, out):
    names = subjects(data)
    fig, axes = plt.subplots(1, len(names), figsize=(4.2 * len(names), 4.4), squeeze=False)
    for ax, subject in zip(axes[0], names):
        a, b = lag_pairs(data[data["subject"] == subject], "est_x_mm")
        lim = max(4 * np.std(a), 1e-3)
        ax.plot(a, b, ".", markersize=2, color="black", alpha=0.4)
        r = np.corrcoef(a, b)[0, 1]
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_aspect("equal")
        ax.set_xlabel("x error at t (mm, sample - smoothed)")
        ax.set_ylabel("x error at t + 1 (mm)")
        ax.set_title(f"{subject}: lag-1 correlation {r:.2f}, n = {a.size}", fontsize=10)
    fig.suptitle("Fig. 6: adjacent readings (uncorrelated errors give a round cloud)")
    fig.tight_layout()
    plotinput.save(fig, out, dpi=110)
    plt.close(fig)


def main():
    if len(sys.argv) > 3:
        plotinput.usage("[DIR [NAME]]")
    directory = sys.argv[1] if len(sys.argv) > 1 else "results/analyze"
    name = sys.argv[2] if len(sys.argv) > 2 else "analyze"
    data = read(os.path.join(directory, f"{name}_errors.csv"))
    fig2(data, os.path.join(directory, f"{name}_fig2.png"))
    fig3(data, os.path.join(directory, f"{name}_fig3.png"))
    fig6(data, os.path.join(directory, f"{name}_fig6.png"))


if __name__ == "__main__":
    main()
