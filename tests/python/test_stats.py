"""patlab.stats against scipy.stats 1.10 on the same samples (docs/stats.md: where patlab differs
on purpose the test compares with the independent formula instead)."""
import math

import numpy as np
import pytest
from scipy import stats as scipy_stats

from patlab import stats

RTOL = 1e-9  # p-values: the precision of docs/stats.md's fixtures


def samples(n1, n2, shift=0.0, seed=0, quantum=None):
    rng = np.random.default_rng(seed)
    x, y = rng.normal(0.0, 1.0, n1), rng.normal(shift, 1.0, n2)
    if quantum:  # ties
        x, y = np.round(x / quantum) * quantum, np.round(y / quantum) * quantum
    return x, y


# One-sided with n1 != n2 only where scipy's path counts fit a double (n1 + n2 below ~1030): beyond,
# scipy falls back to Hodges' approximation and patlab stays exact (docs/stats.md difference 2).
KS_CASES = [(n1, n2, shift, quantum, alternative)
            for n1, n2, shift, quantum in [(50, 50, 0.3, None), (40, 70, 0.5, None),
                                           (300, 300, 0.0, 0.5), (4000, 4000, 0.05, None),
                                           (800, 1200, 0.1, None), (9000, 10000, 0.05, None)]
            for alternative in ["two-sided", "less", "greater"]
            if n1 == n2 or n1 + n2 < 1000 or alternative == "two-sided"]


@pytest.mark.parametrize("n1, n2, shift, quantum, alternative", KS_CASES)
def test_ks_exact_and_auto_equal_scipy(n1, n2, shift, quantum, alternative):
    x, y = samples(n1, n2, shift, seed=n1 + n2, quantum=quantum)
    ours = stats.ks_2samp(x, y, alternative=alternative)
    theirs = scipy_stats.ks_2samp(x, y, alternative=alternative, method="auto")
    assert ours.statistic == theirs.statistic
    assert math.isclose(ours.pvalue, theirs.pvalue, rel_tol=RTOL, abs_tol=1e-300)
    assert ours.statistic_location == theirs.statistic_location
    assert ours.statistic_sign == theirs.statistic_sign


@pytest.mark.parametrize("alternative", ["less", "greater"])
def test_ks_one_sided_asymptotic_equals_scipy(alternative):
    x, y = samples(30000, 20000, 0.02, seed=3)
    ours = stats.ks_2samp(x, y, alternative=alternative, method="asymp")
    theirs = scipy_stats.ks_2samp(x, y, alternative=alternative, method="asymp")
    assert ours.statistic == theirs.statistic and ours.method == "asymp"
    assert math.isclose(ours.pvalue, theirs.pvalue, rel_tol=RTOL)


def test_ks_two_sided_asymptotic_is_the_limiting_law():
    """docs/stats.md difference 1: the Kolmogorov limit, scipy's kstwobign."""
    x, y = samples(30000, 20000, 0.02, seed=4)
    ours = stats.ks_2samp(x, y, method="asymp")
    assert ours.statistic == scipy_stats.ks_2samp(x, y, method="asymp").statistic
    en = math.sqrt(30000 * 20000 / 50000)
    assert math.isclose(ours.pvalue, scipy_stats.kstwobign.sf(en * ours.statistic), rel_tol=RTOL)


@pytest.mark.parametrize("n, method, zero_method, correction", [
    (20, "exact", "wilcox", False), (45, "auto", "wilcox", False), (200, "approx", "wilcox", True),
    (200, "approx", "pratt", False), (200, "approx", "zsplit", False),
    (5000, "auto", "wilcox", False)])
@pytest.mark.parametrize("alternative", ["two-sided", "less", "greater"])
def test_wilcoxon_equals_scipy(n, method, zero_method, correction, alternative):
    x, y = samples(n, n, 0.2, seed=n)
    if zero_method != "wilcox" or method == "approx":
        x, y = np.round(x, 1), np.round(y, 1)  # zeros and ties
    ours = stats.wilcoxon(x, y, zero_method=zero_method, correction=correction,
                          alternative=alternative, method=method)
    theirs = scipy_stats.wilcoxon(x, y, zero_method=zero_method, correction=correction,
                                  alternative=alternative, method=method)
    assert ours.statistic == theirs.statistic
    assert math.isclose(ours.pvalue, theirs.pvalue, rel_tol=RTOL)


def test_wilcoxon_of_differences_equals_the_pairs():
    x, y = samples(300, 300, 0.1, seed=9)
    assert stats.wilcoxon(x - y) == stats.wilcoxon(x - y, None)
    assert stats.wilcoxon(x - y).pvalue == scipy_stats.wilcoxon(x - y).pvalue or math.isclose(
        stats.wilcoxon(x - y).pvalue, scipy_stats.wilcoxon(x - y).pvalue, rel_tol=RTOL)


@pytest.mark.parametrize("n, level", [(2, 0.95), (30, 0.95), (1000, 0.9), (100000, 0.99)])
def test_chi2_std_ci_is_scipys_chi2_interval(n, level):
    x = np.random.default_rng(n).normal(3.0, 2.0, n)
    ours = stats.chi2_std_ci(x, confidence_level=level)
    s = x.std(ddof=1)
    alpha = 1.0 - level
    low = s * math.sqrt((n - 1) / scipy_stats.chi2.ppf(1 - alpha / 2, n - 1))
    high = s * math.sqrt((n - 1) / scipy_stats.chi2.ppf(alpha / 2, n - 1))
    assert math.isclose(ours.statistic, s, rel_tol=1e-12)
    assert math.isclose(ours.low, low, rel_tol=RTOL) and math.isclose(ours.high, high, rel_tol=RTOL)
    assert ours.confidence_interval() == (ours.low, ours.high)


@pytest.mark.parametrize("call, message", [
    (lambda: stats.ks_2samp([1.0, math.nan], [1.0]), "finite"),
    (lambda: stats.ks_2samp([1.0], [2.0], method="fast"), 'method is "fast"'),
    (lambda: stats.wilcoxon([1.0, 2.0], [1.0]), ""),
    (lambda: stats.wilcoxon([1.0, 2.0], alternative="both"), 'alternative is "both"'),
    (lambda: stats.chi2_std_ci([1.0]), ""),
    (lambda: stats.chi2_std_ci([[1.0, 2.0]]), "expected a 1-dimensional sample"),
])
def test_bad_input_is_a_value_error(call, message):
    with pytest.raises(ValueError, match=message):
        call()
