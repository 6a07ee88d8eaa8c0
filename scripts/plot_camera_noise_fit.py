#!/usr/bin/python3
"""The fit of the camera-level noise mechanisms (patlab fitnoise): draws DIR/profiles.png (the
profile likelihood of every fitted magnitude, the 95% level, the estimate and both intervals) and
DIR/sensitivity.png (the fitted magnitudes with profile intervals against the Butterfly's assumed
ID-dot distance, and the fit quality of the model without a colour excess).

usage: /usr/bin/python3 scripts/plot_camera_noise_fit.py [DIR]   (default: results/camera-noise/fit)

Reads DIR/fit.csv, DIR/profiles.csv and DIR/sensitivity.csv (`patlab fitnoise --out DIR`). A
missing or malformed file ends the script with one line on stderr and exit status 2
(scripts/plotinput.py)."""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import plotinput  # noqa: E402

WHAT = "the {} of `patlab fitnoise --out DIR`"
COLOUR_MODEL = "independent+common+colour"
SENSITIVITY_MECHANISMS = [("colour_mm", "o"), ("common_mm", "s"), ("independent_x_mm", "^"),
                          ("independent_y_mm", "v")]


def read(directory, name, columns, numbers):
    path = os.path.join(directory, name)
    return plotinput.read_csv(path, WHAT.format(name), columns=columns, numbers=numbers)


def read_all(directory):
    fit_table = read(directory, "fit.csv", ["mechanism", "value", "lower", "upper", "boot_lower",
                                            "boot_upper", "verdict", "most_correlated",
                                            "correlation"],
                     ["value", "lower", "upper", "boot_lower", "boot_upper", "correlation"])
    fit = {r["mechanism"]: r for r in fit_table.rows}
    profiles = read(directory, "profiles.csv", ["mechanism", "value", "minus2_delta_log_l"],
                    ["value", "minus2_delta_log_l"])
    prof = {}
    for r, line in zip(profiles.rows, profiles.lines):
        if r["mechanism"] not in fit:
            plotinput.fail(profiles.path, f"line {line}: mechanism '{r['mechanism']}' is not in "
                                          "fit.csv")
        prof.setdefault(r["mechanism"], []).append((float(r["value"]),
                                                    float(r["minus2_delta_log_l"])))
    if "delta_mm" not in fit:
        plotinput.fail(fit_table.path, "no row delta_mm (the fitted Table I spread)")
    sens = read(directory, "sensitivity.csv", ["id_radius_mm", "model", "chi2",
                                               "worst_butterfly_z", "mechanism", "value",
                                               "lower", "upper"],
                ["id_radius_mm", "chi2", "worst_butterfly_z", "value", "lower", "upper"]).rows
    return fit, prof, sens


def profiles_figure(fit, prof):
    names = list(prof)
    cols = 4
    rows = math.ceil(len(names) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.0 * cols, 3.2 * rows), squeeze=False)
    for ax, name in zip(axes.flat, names):
        xs, ys = zip(*prof[name])
        f = fit[name]
        ax.plot(xs, ys, "o-", ms=3, color="tab:blue", label="profile")
        ax.axhline(3.84, color="tab:red", ls="--", lw=1, label="95% level (3.84)")
        ax.axvspan(float(f["lower"]), float(f["upper"]), color="tab:blue", alpha=0.12,
                   label="profile 95% CI")
        ax.axvline(float(f["value"]), color="k", lw=1, label="estimate")
        if f["boot_lower"] not in ("", "nan"):
            v = float(f["value"])
            ax.errorbar([v], [0.3], xerr=[[v - float(f["boot_lower"])],
                                          [float(f["boot_upper"]) - v]],
                        fmt="none", ecolor="tab:green", capsize=3, label="bootstrap 95%")
        corr = f["most_correlated"]
        ax.set_title(f"{name}: {f['verdict']}" +
                     (f"\ncorr {float(f['correlation']):+.2f} with {corr}" if corr else ""),
                     fontsize=9)
        ax.set_ylim(0, max(8.0, min(30.0, max(ys) * 1.05)))
        ax.set_xlabel(name)
        ax.set_ylabel("-2 Δ log L")
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(names):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=7, loc="upper right")
    fig.suptitle("Profile likelihood of each mechanism's magnitude: Table I + section-IV "
                 f"Butterfly (delta {float(fit['delta_mm']['value']):.3f} mm)", fontsize=10)
    fig.tight_layout()
    return fig


def sensitivity_figure(sens):
    models = sorted({r["model"] for r in sens})
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    for mech, marker in SENSITIVITY_MECHANISMS:
        pts = [r for r in sens if r["model"] == COLOUR_MODEL and r["mechanism"] == mech]
        x = [float(r["id_radius_mm"]) for r in pts]
        v = [float(r["value"]) for r in pts]
        lo = [float(r["value"]) - float(r["lower"]) for r in pts]
        hi = [float(r["upper"]) - float(r["value"]) for r in pts]
        axes[0].errorbar(x, v, yerr=[lo, hi], marker=marker, capsize=3, label=mech)
    axes[0].axvline(65, color="grey", ls=":", lw=1)
    axes[0].set_xlabel("assumed Butterfly key-to-dot distance (mm)")
    axes[0].set_ylabel("magnitude (mm), 95% profile CI")
    axes[0].set_title(COLOUR_MODEL, fontsize=10)
    axes[0].legend(fontsize=8)
    axes[0].grid(alpha=0.3)
    for model, colour in zip(models, ["tab:orange", "tab:blue"]):
        pts = {}
        for r in sens:
            if r["model"] == model:
                pts[float(r["id_radius_mm"])] = (float(r["chi2"]), float(r["worst_butterfly_z"]))
        x = sorted(pts)
        axes[1].plot(x, [pts[k][0] for k in x], "o-", color=colour, label=model)
        axes[2].plot(x, [pts[k][1] for k in x], "o-", color=colour, label=model)
    axes[1].set_ylabel("chi2 at the best fit (9 data)")
    axes[2].set_ylabel("worst Butterfly |obs - pred| / se")
    axes[2].axhline(2, color="tab:red", ls="--", lw=1, label="2 se")
    for ax in axes[1:]:
        ax.axvline(65, color="grey", ls=":", lw=1)
        ax.set_xlabel("assumed Butterfly key-to-dot distance (mm)")
        ax.set_yscale("log")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Sensitivity to the Butterfly's size (the paper does not give it; patlab's is "
                 "65 mm)", fontsize=10)
    fig.tight_layout()
    return fig


def main(argv):
    if len(argv) > 2:
        plotinput.usage("[DIR]")
    directory = argv[1] if len(argv) > 1 else "results/camera-noise/fit"
    fit, prof, sens = read_all(directory)
    profiles = os.path.join(directory, "profiles.png")
    sensitivity = os.path.join(directory, "sensitivity.png")
    plotinput.save(profiles_figure(fit, prof), profiles, dpi=110)
    plotinput.save(sensitivity_figure(sens), sensitivity, dpi=110)
    print("wrote", profiles, sensitivity)


if __name__ == "__main__":
    main(sys.argv)
