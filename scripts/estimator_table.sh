#!/usr/bin/env bash
# Every estimator against its Cramer-Rao bound under each noise model: runs the experiments of
# experiments/estimators/ (Butterfly, patch sigma 1 mm, 20,000 trials each, ~10 s in all) and
# prints, per model and estimator, the std of x, y and theta and each over the bound (empty where
# the model has no bound). The table in docs/estimators.md is its output.
#   bash scripts/estimator_table.sh [build/patlab]
set -euo pipefail
cd "$(dirname "$0")/.."
P=${1:-build/patlab}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for m in isotropic anisotropic correlated common-jitter rotation-jitter outliers; do
  "$P" simulate "experiments/estimators/$m.toml" --out "$out/$m" -q
done
/usr/bin/python3 - "$out" <<'PY'
import csv, math, sys
out = sys.argv[1]
models = ["isotropic", "anisotropic", "correlated", "common-jitter", "rotation-jitter", "outliers"]
def ratio(a, b):
    return f"{float(a) / float(b):.3f}" if b else ""
print("| noise | estimator | std x mm | std y mm | std θ mrad | bound pos mm | bound θ mrad "
      "| std_pos / bound | std θ / bound |")
print("|---|---|---|---|---|---|---|---|---|")
for m in models:
    with open(f"{out}/{m}/estimators-{m}.csv") as f:
        for row in csv.DictReader(f):
            b_pos, b_t = row["crlb_pos_mm"], row["crlb_theta_rad"]
            print(f"| {m} | {row['estimator']} | {float(row['std_x_mm']):.4f} "
                  f"| {float(row['std_y_mm']):.4f} | {1e3 * float(row['std_theta_rad']):.3f} "
                  f"| {f'{float(b_pos):.4f}' if b_pos else ''} "
                  f"| {f'{1e3 * float(b_t):.3f}' if b_t else ''} "
                  f"| {ratio(row['std_pos_mm'], b_pos)} | {ratio(row['std_theta_rad'], b_t)} |")
PY
