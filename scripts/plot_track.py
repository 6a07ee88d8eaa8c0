#!/usr/bin/python3
"""Draws Figs. 2, 3 and 6 of Bruce & Veloso 2003 (section II) from `patlab track` results.

usage: /usr/bin/python3 scripts/plot_track.py [RESULTS_DIR [QUANTISATION_DIR]]
       (defaults: results and results/track_quantisation)

Reads RESULTS_DIR/track_errors.csv (and QUANTISATION_DIR/track_errors.csv, the same experiment
without sensor noise or camera jitter, for Fig. 6) and writes into RESULTS_DIR:
  fig2.png  aggregate error distribution of the three diameters, x and y pooled, with the
            Gaussian of the same std: the paper's estimate (sample - smoothed track) and the true
            error (sample - truth), log scale on the right to show the tails;
  fig3.png  cumulative distributions of |error| per diameter, x (along the travel) and y
            (across it); solid: the paper's estimate, dashed: the true error;
  fig6.png  lag-1 scatter of adjacent along-track errors (e_t, e_t+1): a single 40 mm patch (top)
            and the Butterfly pattern (bottom), quantisation only (left) and with noise (right).

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

WHAT = "the track_errors.csv of `patlab track` (e.g. experiments/table1.toml)"
COLUMNS = {"subject": "str", "run": "int", "frame": "int", "est_x_mm": "float",
           "est_y_mm": "float", "true_x_mm": "float", "true_y_mm": "float"}


def read(path):
    numbers = [c for c, kind in COLUMNS.items() if kind == "float"]
    integers = [c for c, kind in COLUMNS.items() if kind == "int"]
    table = plotinput.read_csv(path, WHAT, columns=list(COLUMNS), numbers=numbers,
                               integers=integers, empty_ok=False)
    data = table.array(COLUMNS)
    if not discs(data):
        plotinput.fail(path, "no single-patch subject (a name ending in mm, e.g. 40mm); "
                             f"expected {WHAT}")
    return data


def subjects(data):
    seen = []
    for s in data["subject"]:
        if s not in seen:
            seen.append(s)
    return seen


def discs(data):
    return [s for s in subjects(data) if s.endswith("mm")]


def gaussian(x, sigma):
    return np.exp(-0.5 * (x / sigma) ** 2) / (sigma * np.sqrt(2 * np.pi))


def fig2(data, out):
    mask = np.isin(data["subject"], discs(data))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for kind, colour in (("est", "tab:blue"), ("true", "tab:orange")):
        e = np.concatenate([data[kind + "_x_mm"][mask], data[kind + "_y_mm"][mask]])
        sigma = np.std(e, ddof=1)
        bins = np.linspace(-2.5, 2.5, 101)
        label = {"est": "sample - smoothed (paper's estimate)", "true": "sample - truth"}[kind]
        for ax in axes:
            ax.hist(e, bins=bins, density=True, histtype="step", color=colour,
                    label=f"{label}, σ = {sigma:.3f} mm")
            x = np.linspace(-2.5, 2.5, 400)
            ax.plot(x, gaussian(x, sigma), color=colour, linestyle=":", linewidth=1)
    axes[1].set_yscale("log")
    axes[1].set_ylim(1e-4, None)
    for ax in axes:
        ax.set_xlabel("error (mm), x and y pooled, 40/50/60 mm patches")
        ax.set_ylabel("density")
    axes[0].legend(fontsize=8, loc="upper left")
    axes[0].set_title("Fig. 2: aggregate error distribution (dotted: Gaussian, same σ)")
    axes[1].set_title("same, log scale")
    fig.tight_layout()
    plotinput.save(fig, out, dpi=120)
    plt.close(fig)


def fig3(data, out):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    colours = ["tab:blue", "tab:green", "tab:red", "tab:purple", "tab:brown"]
    for ax, axis in zip(axes, ("x", "y")):
        for colour, subject in zip(colours, discs(data)):
            rows = data["subject"] == subject
            for kind, style in (("est", "-"), ("true", "--")):
                e = np.sort(np.abs(data[f"{kind}_{axis}_mm"][rows]))
                f = np.arange(1, e.size + 1) / e.size
                ax.plot(e, f, style, color=colour,
                        label=f"{subject} {'estimated' if kind == 'est' else 'true'}")
        ax.set_xlim(0, 1.6)
        ax.set_xlabel(f"|error| in {axis} (mm)" +
                      (" along the travel" if axis == "x" else " across the travel"))
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("fraction of samples")
    axes[0].legend(fontsize=8, loc="lower right")
    fig.suptitle("Fig. 3: cumulative distributions of absolute error "
                 "(solid: sample - smoothed, dashed: sample - truth)")
    fig.tight_layout()
    plotinput.save(fig, out, dpi=120)
    plt.close(fig)


def lag_pairs(data, subject, column):
    """(e_t, e_t+1) for adjacent frames of the same run."""
    rows = data[data["subject"] == subject]
    a, b = [], []
    for run in np.unique(rows["run"]):
        r = rows[rows["run"] == run]
        frame = r["frame"]
        adjacent = np.nonzero(np.diff(frame) == 1)[0]
        a.append(r[column][adjacent])
        b.append(r[column][adjacent + 1])
    return np.concatenate(a), np.concatenate(b)


def fig6(panels, out):
    fig, axes = plt.subplots(2, len(panels), figsize=(5 * len(panels), 9.5), squeeze=False)
    for col, (title, data) in enumerate(panels):
        names = subjects(data)
        pattern = [s for s in names if not s.endswith("mm")]
        rows = [("40mm" if "40mm" in names else discs(data)[0], "single patch")]
        if pattern:
            rows.append((pattern[0], "full pattern"))
        for row, (subject, what) in enumerate(rows):
            ax = axes[row][col]
            a, b = lag_pairs(data, subject, "est_x_mm")
            lim = max(4 * np.std(a), 1e-3)
            ax.plot(a, b, ",", color="black", alpha=0.6)
            ax.plot(a, b, ".", markersize=1, color="black", alpha=0.25)
            r = np.corrcoef(a, b)[0, 1]
            ax.set_xlim(-lim, lim)
            ax.set_ylim(-lim, lim)
            ax.set_aspect("equal")
            ax.set_xlabel("error at t (mm, along travel, sample - smoothed)")
            ax.set_ylabel("error at t + 1 (mm)")
            ax.set_title(f"{subject} ({what}), {title}\nlag-1 correlation {r:.2f}, n = {a.size}",
                         fontsize=10)
        if len(rows) < 2:
            axes[1][col].axis("off")
    fig.suptitle("Fig. 6: adjacent readings (uncorrelated errors would give a round cloud)")
    fig.tight_layout()
    plotinput.save(fig, out, dpi=120)
    plt.close(fig)


def main():
    if len(sys.argv) > 3:
        plotinput.usage("[RESULTS_DIR [QUANTISATION_DIR]]")
    results = sys.argv[1] if len(sys.argv) > 1 else "results"
    quant = sys.argv[2] if len(sys.argv) > 2 else os.path.join(results, "track_quantisation")
    data = read(os.path.join(results, "track_errors.csv"))
    fig2(data, os.path.join(results, "fig2.png"))
    fig3(data, os.path.join(results, "fig3.png"))
    panels = []
    quant_csv = os.path.join(quant, "track_errors.csv")
    if os.path.exists(quant_csv):
        panels.append(("quantisation only", read(quant_csv)))
    panels.append(("with noise (table1.toml)", data))
    fig6(panels, os.path.join(results, "fig6.png"))
    print("wrote", ", ".join(os.path.join(results, f) for f in ("fig2.png", "fig3.png",
                                                              "fig6.png")))


if __name__ == "__main__":
    main()
