# Type stubs of the patlab package (docs/python.md), for editors and type checkers.
import os
from typing import Any, Iterable, Mapping, NamedTuple, Sequence, Union, overload

import numpy as np
import numpy.typing as npt

from . import stats as stats

__version__: str
ESTIMATORS: tuple[str, ...]

PathOrName = Union[str, os.PathLike[str]]

class Pattern:
    name: str
    description: str
    key_index: int
    @property
    def size(self) -> int: ...
    @property
    def positions_mm(self) -> npt.NDArray[np.float64]: ...
    @property
    def radii_mm(self) -> npt.NDArray[np.float64]: ...
    @property
    def roles(self) -> list[str]: ...
    @property
    def shapes(self) -> list[str]: ...
    @property
    def colours(self) -> list[str]: ...
    @property
    def orientation_pairs(self) -> npt.NDArray[np.int32]: ...
    @property
    def centroid_mm(self) -> npt.NDArray[np.float64]: ...
    @property
    def spread_mm2(self) -> float: ...
    @staticmethod
    def load(path_or_name: PathOrName) -> Pattern: ...
    @staticmethod
    def from_toml(text: str, source_name: str = ...) -> Pattern: ...

PatternLike = Union[Pattern, PathOrName]

class CrlbResult(NamedTuple):
    position_mm: float
    theta_rad: float

class SimulationResult:
    columns: dict[str, Any]
    table: Any  # pandas.DataFrame, or dict[str, numpy array | list[str]] without pandas
    csv: str
    name: str
    seed: int
    threads: int
    total_trials: int
    wall_seconds: float
    simulate_seconds: float
    errors: npt.NDArray[np.float64] | None

class IdsResult:
    pattern: str
    colours: list[str]
    slots: list[int]
    ids: npt.NDArray[np.int64]
    colourings: npt.NDArray[np.int32]
    count: int
    rotations: int
    accepted_shifts: list[int]
    effective_shifts: list[int]
    summary: str
    symmetry_table: str
    table: Any
    def __len__(self) -> int: ...

class EvaluationResult:
    json: dict[str, Any]
    text: str
    reports: list[dict[str, Any]]

class CompareResult:
    csv: str
    json: dict[str, Any]
    text: str
    table: Any

def simulate(patterns: Union[PatternLike, Sequence[PatternLike]], sigmas: Iterable[float] | float,
             trials: int = ..., estimators: Sequence[str] = ...,
             noise: Mapping[str, float] | None = ..., seed: int = ..., threads: int = ...,
             keep_errors: bool = ..., name: str = ...) -> SimulationResult: ...
def simulate_experiment(path_or_name: PathOrName, trials: int | None = ..., seed: int | None = ...,
                        sigmas: Iterable[float] | None = ..., threads: int = ...,
                        keep_errors: bool = ...) -> SimulationResult: ...
@overload
def estimate(pattern: PatternLike, observed: npt.ArrayLike, method: str = ...,
             max_iterations: int = ..., threads: int = ...) -> npt.NDArray[np.float64]: ...
@overload
def estimate(pattern: PatternLike, observed: npt.ArrayLike, method: str, max_iterations: int,
             return_converged: bool, threads: int = ...) -> Any: ...
def crlb(pattern: PatternLike, sigma: float,
         noise: Mapping[str, float] | None = ...) -> CrlbResult: ...
def predicted_std(pattern: PatternLike, method: str, sigma: float) -> CrlbResult: ...
def ids(pattern: PatternLike, colours: Union[int, Sequence[str]],
        tolerance_mm: float = ...) -> IdsResult: ...
def evaluate(patterns: Union[PatternLike, Sequence[PatternLike]], **options: Any) -> EvaluationResult: ...
def compare(patterns: Sequence[PatternLike], sort_by: str = ..., **options: Any) -> CompareResult: ...

class DetectResult:
    csv: str
    json: dict[str, Any]
    warnings: list[str]
    table: Any
    def __len__(self) -> int: ...

def read_frame(path: PathOrName) -> npt.NDArray[np.uint8]: ...
def detect(image: npt.NDArray[np.uint8], thresholds: PathOrName | None = ...,
           calibration: PathOrName | None = ..., settings: PathOrName | None = ...,
           name: str = ..., blobs: bool = ...,
           setup: str | os.PathLike[str] | None = ..., explain: bool = ...) -> DetectResult: ...
class Detector:
    patterns: list[str]
    palette: list[str]
    warnings: list[str]
    def __init__(self, thresholds: PathOrName | None = ..., calibration: PathOrName | None = ...,
                 settings: PathOrName | None = ...,
                 setup: str | os.PathLike[str] | None = ...) -> None: ...
    def detect(self, image: npt.NDArray[np.uint8], name: str = ...) -> dict[str, Any]: ...

def render(scene: PathOrName) -> tuple[npt.NDArray[np.uint8], str]: ...
def setup(frames: str | os.PathLike[str] | npt.NDArray[np.uint8]
          | Sequence[str | os.PathLike[str] | npt.NDArray[np.uint8]],
          field: str | os.PathLike[str], settings: PathOrName, out: str | os.PathLike[str],
          landmarks: Iterable[str] = ..., robot_height: float = ...,
          line_width: float = ...) -> dict[str, Any]: ...
