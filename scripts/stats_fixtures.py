#!/usr/bin/python3
"""Generate the scipy reference fixtures for src/patlab/stats (tests/data/stats/fixtures.json).

Run with Debian's interpreter, which has python3-scipy 1.10.1:

    /usr/bin/python3 scripts/stats_fixtures.py            # writes tests/data/stats/fixtures.json

Small inputs are stored inline. Large inputs are stored as a generator spec that the C++ tests
reproduce bit for bit (tests/stats/fixtures.h, GenerateSample): splitmix64 -> 53-bit uniforms,
a sum of k of them, optionally centred, times a power-of-two scale, plus a location, optionally
floored to a power-of-two quantum (to make ties and zero differences). Only +, -, * by powers
of two and floor are used, so the doubles are identical in both languages.

Every expected p-value names its reference:
  "scipy"       scipy 1.10 computes the same quantity by the same method;
  "kolmogorov"  scipy.special.kolmogorov(sqrt(n1 n2/(n1+n2)) D): the limiting law that patlab's
                asymptotic two-sided KS uses (scipy's own 'asymp' uses the finite-n law kstwo);
  "lattice-int" exact count of lattice paths with Python integers (scipy's one-sided exact count
                overflowed and it fell back to an approximation).
"""
import json
import math
import os
import sys
import warnings
from fractions import Fraction

import numpy as np
import scipy
from scipy import ndimage, special, stats

MASK = (1 << 64) - 1


def generate(spec):
    """The deterministic sample described by spec (mirrored in tests/stats/fixtures.h)."""
    state = spec["seed"] & MASK
    k = spec.get("sum_of", 1)
    centre = spec.get("centre", False)
    scale = spec.get("scale", 1.0)
    loc = spec.get("loc", 0.0)
    quantum = spec.get("quantum", 0.0)
    out = np.empty(spec["n"])
    for i in range(spec["n"]):
        s = 0.0
        for _ in range(k):
            state = (state + 0x9E3779B97F4A7C15) & MASK
            z = state
            z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
            z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
            z ^= z >> 31
            s += float(z >> 11) * 2.0**-53
        if centre:
            s -= k / 2.0
        v = loc + scale * s
        if quantum:
            v = math.floor(v / quantum) * quantum
        out[i] = v
    return out


def sample(spec_or_values):
    if "gen" in spec_or_values:
        return generate(spec_or_values["gen"])
    return np.asarray(spec_or_values["values"], dtype=float)


def inline(values):
    return {"values": [float(v) for v in values]}


def gen(seed, n, **kw):
    d = {"seed": seed, "n": n}
    d.update(kw)
    return {"gen": d}


def lattice_int(n1, n2, h, two_sided):
    """Exact P(D >= h/lcm) by counting lattice paths with Python integers (Hodges 1958)."""
    g = math.gcd(n1, n2)
    n1g, n2g = n1 // g, n2 // g

    def outside(i, j):
        diff = i * n2g - j * n1g
        return (abs(diff) >= h) if two_sided else (diff >= h)

    # count paths that never touch the boundary
    row = [0] * (n2 + 1)
    for i in range(n1 + 1):
        for j in range(n2 + 1):
            if outside(i, j):
                row[j] = 0
            elif i == 0 and j == 0:
                row[j] = 1
            else:
                row[j] = (row[j] if i > 0 else 0) + (row[j - 1] if j > 0 else 0)
    inside = row[n2]
    total = math.comb(n1 + n2, n1)
    return float(Fraction(total - inside, total))


# ----------------------------------------------------------------------------------------- KS
def ks_case(name, xs, ys, alternative="two-sided", method="auto"):
    x, y = sample(xs), sample(ys)
    n1, n2 = len(x), len(y)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = stats.ks_2samp(x, y, alternative=alternative, method=method)
    scipy_fell_back = any("Switching" in str(w.message) for w in caught)
    ours = method
    if ours == "auto":
        ours = "exact" if max(n1, n2) <= 10000 else "asymp"
    if ours == "exact" and n1 != n2 and n1 * n2 > 200_000_000:
        ours = "asymp"
    expect = {"d": float(res.statistic), "method_used": ours, "scipy_p": float(res.pvalue),
              "sign": int(res.statistic_sign)}
    en = n1 * n2 / (n1 + n2)
    if ours == "asymp" and alternative == "two-sided":
        # our D is not lattice-rounded in asymp mode, same as scipy's
        expect["p"] = float(special.kolmogorov(math.sqrt(en) * res.statistic))
        expect["reference"] = "kolmogorov"
    elif ours == "exact" and scipy_fell_back:
        g = math.gcd(n1, n2)
        lcm = n1 // g * n2
        h = int(round(float(res.statistic) * lcm))
        expect["d"] = h / lcm
        expect["p"] = lattice_int(n1, n2, h, alternative == "two-sided")
        expect["reference"] = "lattice-int"
    else:
        expect["p"] = float(res.pvalue)
        expect["reference"] = "scipy"
    if ours == "exact" and n1 != n2 and n1 * n2 <= 40_000 and expect["reference"] == "scipy":
        g = math.gcd(n1, n2)
        lcm = n1 // g * n2
        h = int(round(float(res.statistic) * lcm))
        expect["p_lattice_int"] = lattice_int(n1, n2, h, alternative == "two-sided")
    return {"name": name, "x": xs, "y": ys, "alternative": alternative, "method": method,
            "expect": expect}


def ks_cases():
    rng = np.random.default_rng(20030601)
    cases = []
    # Hand-sized, with ties inside and across the samples.
    a = [1.0, 2.0, 2.0, 3.0, 5.0]
    b = [2.0, 2.0, 4.0, 6.0, 7.0, 8.0]
    for alt in ("two-sided", "less", "greater"):
        cases.append(ks_case(f"ties_5_6_{alt}", inline(a), inline(b), alt))
        cases.append(ks_case(f"ties_equal_5_{alt}", inline(a), inline(b[:5]), alt))
    # Identical samples: D = 0, p = 1.
    cases.append(ks_case("identical_7", inline([3, 1, 4, 1, 5, 9, 2]), inline([3, 1, 4, 1, 5, 9, 2])))
    # Random sizes, normal vs shifted normal, all alternatives and methods.
    for n1, n2, shift in [(8, 8, 0.0), (10, 15, 0.5), (37, 23, -0.3), (60, 60, 0.8),
                          (100, 120, 0.2), (250, 400, 0.1), (1000, 999, 0.05),
                          (1500, 1500, 0.15), (2000, 3001, 0.1)]:
        x = np.round(rng.normal(0, 1, n1), 3)  # rounding makes ties
        y = np.round(rng.normal(shift, 1, n2), 3)
        for alt in ("two-sided", "less", "greater"):
            for method in ("auto", "asymp"):
                cases.append(ks_case(f"normal_{n1}_{n2}_{alt}_{method}", inline(x), inline(y),
                                     alt, method))
    # Disjoint samples: the smallest possible p (2 / C(n1+n2, n1)), below 1e-200.
    x = np.arange(500, dtype=float)
    y = np.arange(400, dtype=float) + 1000.5
    for alt in ("two-sided", "less", "greater"):
        cases.append(ks_case(f"disjoint_500_400_{alt}", inline(x), inline(y), alt))
    x = np.arange(300, dtype=float)
    y = np.arange(300, dtype=float) + 1000.5
    cases.append(ks_case("disjoint_300_300", inline(x), inline(y)))
    # Large: 100,000 vs 100,000, generated. Exact (reflection sum) and asymptotic.
    big_x = gen(11, 100_000, sum_of=4, centre=True, scale=2.0)
    big_y = gen(12, 100_000, sum_of=4, centre=True, scale=2.0, loc=0.0078125)
    big_z = gen(13, 100_000, sum_of=4, centre=True, scale=2.0, loc=0.21875)
    for alt in ("two-sided", "greater", "less"):
        cases.append(ks_case(f"big_close_{alt}_exact", big_x, big_y, alt, "exact"))
    cases.append(ks_case("big_close_auto", big_x, big_y, "two-sided", "auto"))
    cases.append(ks_case("big_far_exact", big_x, big_z, "two-sided", "exact"))  # p < 1e-200
    cases.append(ks_case("big_far_auto", big_x, big_z, "two-sided", "auto"))
    cases.append(ks_case("big_far_greater_asymp", big_x, big_z, "greater", "asymp"))
    # Unequal large sizes (asymptotic only) and a mid-size exact lattice case.
    cases.append(ks_case("big_unequal_auto", big_x, gen(14, 70_001, sum_of=2, centre=True,
                                                        scale=2.0, quantum=2.0**-10)))
    cases.append(ks_case("lattice_5000_4000", gen(15, 5000, sum_of=2), gen(16, 4000, sum_of=2,
                                                                          loc=0.015625)))
    return cases


# ----------------------------------------------------------------------------------- Wilcoxon
def wilcoxon_case(name, xs, ys, alternative="two-sided", zero_method="wilcox",
                  correction=False, method="auto"):
    x, y = sample(xs), sample(ys)
    d = x - y
    nz = d[d != 0]
    ties = len(np.unique(np.abs(nz))) < len(nz)
    zeros = np.any(d == 0)
    n = len(d)
    ours = "exact" if ((method == "auto" and n <= 50) or (method == "exact" and n <= 500)) \
        else "approx"
    if zeros or ties:
        ours = "approx"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = stats.wilcoxon(x, y, zero_method=zero_method, correction=correction,
                             alternative=alternative, method=ours)
        res_auto = stats.wilcoxon(x, y, zero_method=zero_method, correction=correction,
                                  alternative=alternative, method=method)
    expect = {"statistic": float(res.statistic), "p": float(res.pvalue), "method_used": ours,
              "scipy_same_method": True, "scipy_p_as_requested": float(res_auto.pvalue)}
    if ours == "approx":
        expect["z"] = float(res.zstatistic)
    return {"name": name, "x": xs, "y": ys, "alternative": alternative,
            "zero_method": zero_method, "correction": correction, "method": method,
            "expect": expect}


def wilcoxon_cases():
    rng = np.random.default_rng(20030602)
    cases = []
    alts = ("two-sided", "less", "greater")
    # n = 5 by hand: d = 1, -2, 3, 4, 5 (exact: R+ = 13).
    x = [11.0, 8.0, 13.0, 14.0, 15.0]
    y = [10.0, 10.0, 10.0, 10.0, 10.0]
    for alt in alts:
        cases.append(wilcoxon_case(f"hand5_{alt}", inline(x), inline(y), alt))
    # Ties and zeros, every zero method, with and without correction.
    x = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0]
    y = [1.0, 1.0, 4.0, 2.0, 5.0, 3.0, 7.0, 10.0, 5.0, 10.0, 8.0, 6.0]
    for zm in ("wilcox", "pratt", "zsplit"):
        for corr in (False, True):
            for alt in alts:
                cases.append(wilcoxon_case(f"zeros_ties_{zm}_{corr}_{alt}", inline(x), inline(y),
                                           alt, zm, corr))
    # Ties without zeros at n <= 50: scipy 1.10 'auto' would run its exact branch on truncated
    # ranks; patlab uses the normal approximation (reference: scipy method='approx').
    x = np.round(rng.normal(0.3, 1, 30), 1)
    y = np.round(rng.normal(0, 1, 30), 1) + 0.05
    for alt in alts:
        cases.append(wilcoxon_case(f"ties_n30_{alt}", inline(x), inline(y), alt))
    # Exact, no ties, n from 6 to 50; exact requested at n = 60 and 200.
    for n, shift in [(6, 0.0), (10, 0.5), (20, -0.4), (25, 0.0), (50, 0.7), (60, 0.3),
                     (200, 0.2)]:
        x = rng.normal(shift, 1, n)
        y = rng.normal(0, 1, n)
        for alt in alts:
            method = "exact" if n > 50 else "auto"
            cases.append(wilcoxon_case(f"exact_n{n}_{alt}", inline(x), inline(y), alt,
                                       method=method))
            if n >= 50:
                cases.append(wilcoxon_case(f"approx_n{n}_{alt}", inline(x), inline(y), alt,
                                           method="approx", correction=True))
    # Normal approximation, mid-size, rounded data (many ties and some zeros).
    x = np.round(rng.normal(0.1, 1, 1000), 2)
    y = np.round(rng.normal(0, 1, 1000), 2)
    for zm in ("wilcox", "pratt", "zsplit"):
        for alt in alts:
            cases.append(wilcoxon_case(f"mid1000_{zm}_{alt}", inline(x), inline(y), alt, zm,
                                       correction=(alt == "less")))
    # All differences zero: zsplit only (wilcox/pratt are an error, tested by hand in C++).
    cases.append(wilcoxon_case("all_zero_zsplit", inline([1.0, 2.0, 3.0]),
                               inline([1.0, 2.0, 3.0]), zero_method="zsplit"))
    # 100,000 pairs, generated: null (p ~ 0.5), and shifted (p ~ 1e-270), with quantised ties.
    gx = gen(21, 100_000, sum_of=4, centre=True, scale=2.0, quantum=2.0**-8)
    gy = gen(22, 100_000, sum_of=4, centre=True, scale=2.0, quantum=2.0**-8)
    gy_shift = gen(22, 100_000, sum_of=4, centre=True, scale=2.0, quantum=2.0**-8,
                   loc=-0.0625)
    gy_far = gen(22, 100_000, sum_of=4, centre=True, scale=2.0, quantum=2.0**-8,
                 loc=-0.1875)
    for zm in ("wilcox", "pratt", "zsplit"):
        cases.append(wilcoxon_case(f"big_null_{zm}", gx, gy, "two-sided", zm))
    for alt in alts:
        cases.append(wilcoxon_case(f"big_shift_{alt}", gx, gy_shift, alt, "wilcox", True))
        cases.append(wilcoxon_case(f"big_far_{alt}", gx, gy_far, alt, "pratt", False))
    return cases


# ------------------------------------------------------------------------ summary & smoothing
def summary_cases():
    rng = np.random.default_rng(20030603)
    cases = []
    for n, level in [(2, 0.95), (5, 0.95), (30, 0.99), (1000, 0.95), (1000, 0.5),
                     (100_000, 0.95)]:
        x = rng.normal(3.0, 0.52, n)
        s = float(np.std(x, ddof=1))
        alpha = 1 - level
        lo = s * math.sqrt((n - 1) / stats.chi2.ppf(1 - alpha / 2, n - 1))
        hi = s * math.sqrt((n - 1) / stats.chi2.ppf(alpha / 2, n - 1))
        m = float(np.mean(x))
        t = stats.t.ppf(1 - alpha / 2, n - 1) * s / math.sqrt(n)
        xs = inline(x) if n <= 1000 else None
        if xs is None:
            continue
        cases.append({"name": f"normal_{n}_{level}", "x": xs, "level": level,
                      "expect": {"std": s, "lower": lo, "upper": hi, "mean": m,
                                 "mean_lower": m - t, "mean_upper": m + t}})
    return cases


def smoothing_cases():
    rng = np.random.default_rng(20030604)
    cases = []
    for n, sigma in [(1, 2.0), (20, 10.0), (50, 10.0), (300, 10.0), (300, 2.5), (300, 0.3),
                     (7, 0.0)]:
        t = np.arange(n)
        x = 100.0 * np.sin(t / 40.0) + rng.normal(0, 0.52, n)
        sm = ndimage.gaussian_filter1d(x, sigma, mode="reflect", truncate=4.0) if sigma > 0 \
            else x.copy()
        cases.append({"name": f"smooth_{n}_{sigma}", "x": inline(x), "sigma": sigma,
                      "expect": {"smoothed": [float(v) for v in sm]}})
    return cases


def acf_cases():
    rng = np.random.default_rng(20030605)
    cases = []
    e = rng.normal(0, 1, 501)
    x = e[1:] + 0.6 * e[:-1]  # MA(1): lag-1 correlation 0.6/1.36
    for lag in (0, 1, 2, 5, 499):
        m = x.mean()
        r = float(np.sum((x[: len(x) - lag] - m) * (x[lag:] - m)) / np.sum((x - m) ** 2))
        cases.append({"name": f"ma1_lag{lag}", "x": inline(x), "lag": lag, "expect": r})
    return cases


def kolmogorov_table():
    xs = [0.01, 0.1, 0.2, 0.3, 0.5, 0.7, 0.82, 0.9, 0.99, 1.0, 1.01, 1.18, 1.36, 1.5, 2.0, 3.0,
          5.0, 8.0, 12.0, 15.0, 17.0, 18.0]
    return [[x, float(special.kolmogorov(x))] for x in xs]


def main():
    out_dir = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data",
                           "stats")
    os.makedirs(out_dir, exist_ok=True)
    fixtures = {
        "generated_by": "scripts/stats_fixtures.py",
        "scipy_version": scipy.__version__,
        "numpy_version": np.__version__,
        "ks": ks_cases(),
        "wilcoxon": wilcoxon_cases(),
        "std_ci": summary_cases(),
        "smoothing": smoothing_cases(),
        "autocorrelation": acf_cases(),
        "kolmogorov_limit": kolmogorov_table(),
    }
    path = os.path.join(out_dir, "fixtures.json")
    with open(path, "w") as f:
        json.dump(fixtures, f, separators=(",", ":"))
        f.write("\n")
    print(f"wrote {os.path.normpath(path)} ({os.path.getsize(path)} bytes)", file=sys.stderr)


if __name__ == "__main__":
    main()
