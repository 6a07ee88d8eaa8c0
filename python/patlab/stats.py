"""Statistics of patlab (stats/), named and shaped as scipy.stats' (docs/stats.md lists where
they differ on purpose): results with .statistic and .pvalue."""
import collections

import numpy as np

from . import _patlab

KsResult = collections.namedtuple(
    "KsResult", ["statistic", "pvalue", "statistic_location", "statistic_sign", "method"])
WilcoxonResult = collections.namedtuple(
    "WilcoxonResult", ["statistic", "pvalue", "zstatistic", "method", "n_zero"])


class StdInterval(collections.namedtuple("StdInterval", ["statistic", "low", "high",
                                                         "confidence_level", "n"])):
    """The sample std (divisor n - 1) and its chi-square confidence interval."""

    def confidence_interval(self):
        return (self.low, self.high)


def _sample(x):
    return np.ascontiguousarray(x, dtype=np.float64)


def ks_2samp(x, y, alternative="two-sided", method="auto"):
    """Two-sample Kolmogorov-Smirnov test as scipy.stats.ks_2samp (method "auto", "exact" or
    "asymp")."""
    return KsResult(**_patlab._ks_2samp(_sample(x), _sample(y), alternative, method))


def wilcoxon(x, y=None, zero_method="wilcox", correction=False, alternative="two-sided",
             method="auto"):
    """Wilcoxon signed-rank test as scipy.stats.wilcoxon (method "auto", "exact" or "approx")."""
    return WilcoxonResult(**_patlab._wilcoxon(_sample(x), None if y is None else _sample(y),
                                              zero_method, bool(correction), alternative, method))


def chi2_std_ci(x, confidence_level=0.95):
    """Sample std and its interval from (n-1) s^2 / sigma^2 ~ chi^2(n-1): the intervals of the
    paper's Table I and of every std in patlab's results. .statistic is the std; .pvalue is not
    defined for an interval and is absent."""
    return StdInterval(**_patlab._chi2_std_ci(_sample(x), float(confidence_level)))
