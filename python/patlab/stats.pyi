# Type stubs of patlab.stats (docs/python.md).
from typing import NamedTuple

import numpy.typing as npt

class KsResult(NamedTuple):
    statistic: float
    pvalue: float
    statistic_location: float
    statistic_sign: int
    method: str

class WilcoxonResult(NamedTuple):
    statistic: float
    pvalue: float
    zstatistic: float
    method: str
    n_zero: int

class StdInterval(NamedTuple):
    statistic: float
    low: float
    high: float
    confidence_level: float
    n: int
    def confidence_interval(self) -> tuple[float, float]: ...

def ks_2samp(x: npt.ArrayLike, y: npt.ArrayLike, alternative: str = ...,
             method: str = ...) -> KsResult: ...
def wilcoxon(x: npt.ArrayLike, y: npt.ArrayLike | None = ..., zero_method: str = ...,
             correction: bool = ..., alternative: str = ..., method: str = ...) -> WilcoxonResult: ...
def chi2_std_ci(x: npt.ArrayLike, confidence_level: float = ...) -> StdInterval: ...
