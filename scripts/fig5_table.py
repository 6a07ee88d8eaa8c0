#!/usr/bin/python3
"""Prints the Fig. 5 summary table of docs/paper-reproduction.md (markdown) from `patlab simulate` results.

usage: /usr/bin/python3 scripts/fig5_table.py results/fig5.csv [SIGMA_MM]

One row per pattern at the chosen patch sigma (default 1 mm): fast and ML position and angle
std, the Cramer-Rao bound, the efficiencies (bound^2 / std^2), and the fast-vs-ML tests (KS on
the theta errors, Wilcoxon signed-rank on the paired |theta| errors).
"""
import csv
import sys


def main(argv):
    if len(argv) not in (2, 3):
        sys.exit("usage: fig5_table.py RESULTS.csv [SIGMA_MM]")
    sigma = float(argv[2]) if len(argv) == 3 else 1.0
    rows = {}
    with open(argv[1], newline="") as f:
        for row in csv.DictReader(f):
            if abs(float(row["sigma_mm"]) - sigma) < 1e-12:
                rows[(row["pattern"], row["estimator"])] = row
    patterns = list(dict.fromkeys(p for p, _ in rows))
    print(f"| pattern (sigma = {sigma:g} mm) | position std fast / ML / CRLB (mm) | "
          "angle std fast / ML / CRLB (mrad) | efficiency fast pos, angle | "
          "KS fast vs ML, theta: D, p | Wilcoxon paired abs(theta): p |")
    print("|---|---|---|---|---|---|")
    for p in patterns:
        fast, ml = rows[(p, "fast")], rows.get((p, "ml"))
        if ml is None:
            continue
        f = lambda r, k, s=1.0: float(r[k]) * s  # noqa: E731
        print(f"| {p} | {f(fast, 'std_pos_mm'):.4f} / {f(ml, 'std_pos_mm'):.4f} / "
              f"{f(fast, 'crlb_pos_mm'):.4f} | {f(fast, 'std_theta_rad', 1e3):.3f} / "
              f"{f(ml, 'std_theta_rad', 1e3):.3f} / {f(fast, 'crlb_theta_rad', 1e3):.3f} | "
              f"{f(fast, 'efficiency_pos'):.3f}, {f(fast, 'efficiency_theta'):.3f} | "
              f"{f(ml, 'ks_theta_d'):.5f}, {f(ml, 'ks_theta_p'):.3g} | "
              f"{f(ml, 'wilcoxon_theta_p'):.3g} |")


if __name__ == "__main__":
    main(sys.argv)
