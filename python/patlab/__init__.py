"""patlab from Python: colour-patch fiducial patterns (Bruce & Veloso, ICRA 2003).

Every function is the library call the ``patlab`` tool makes, so for the same inputs and seed
the results are the CLI's, bit for bit. Long calls release the GIL and run on patlab's own
threads; Ctrl-C interrupts a simulation between blocks of trials (KeyboardInterrupt). Bad input
raises ValueError (FileNotFoundError for a missing file) with the message the CLI prints.
See docs/python.md.
"""
import os

import numpy

from . import _data, _patlab, stats
from ._patlab import Pattern
from ._results import (CompareResult, CrlbResult, DetectResult, EvaluationResult, IdsResult,
                       SimulationResult)

__version__ = _patlab.version
__all__ = ["Pattern", "simulate", "simulate_experiment", "estimate", "crlb", "predicted_std",
           "ids", "evaluate", "compare", "detect", "Detector", "read_frame", "render", "setup",
           "pixel_to_floor", "stats",
           "SimulationResult", "ESTIMATORS"]

ESTIMATORS = ("fast", "ml", "lsq", "key")


def _load_checked(loader, path):
    """Runs loader(path); a missing file's ValueError becomes FileNotFoundError (same text)."""
    try:
        return loader(path)
    except ValueError as error:
        if not os.path.exists(path):
            raise FileNotFoundError(str(error)) from None
        raise


def _pattern_load(path_or_name):
    """The pattern file at a path, or a shipped pattern by name ("butterfly")."""
    path = _data.find(path_or_name, "pattern")
    return _load_checked(_patlab.Pattern._load_file, path)


def _pattern_from_toml(text, source_name="<string>"):
    """A pattern from the text of a pattern file; `source_name` stands for the file in messages."""
    return _patlab.Pattern._parse(text, source_name)


def _pattern_repr(self):
    return f"<patlab.Pattern {self.name!r}: {self.size} patches, key {self.key_index}>"


Pattern.load = staticmethod(_pattern_load)
Pattern.from_toml = staticmethod(_pattern_from_toml)
Pattern.__repr__ = _pattern_repr


def _as_pattern(p):
    """(Pattern, file) from a Pattern, a path or a shipped name."""
    if isinstance(p, Pattern):
        return p, ""
    path = _data.find(p, "pattern")
    return _load_checked(_patlab.Pattern._load_file, path), path


def _as_patterns(patterns):
    if isinstance(patterns, (Pattern, str, os.PathLike)):
        patterns = [patterns]
    return [_as_pattern(p) for p in patterns]


def simulate(patterns, sigmas, trials=100000, estimators=("fast", "ml"), noise=None, seed=1,
             threads=0, keep_errors=False, name="python"):
    """Monte-Carlo data points: every pattern x patch sigma (mm), `trials` random poses each.

    patterns: a Pattern, a path or shipped name, or a list of them. sigmas: increasing patch
    sigmas >= 0 (mm). estimators: any of "fast", "ml", "lsq", "key". noise: a dict of the [noise]
    keys of an experiment file (sigma_y_ratio, common_sigma_ratio, outlier_probability, ...;
    default isotropic Gaussian). seed: the experiment seed; a point's trials depend only on the
    seed, the pattern's content, the noise model and sigma, so the rows equal `patlab simulate`'s
    for the same seed, whatever the threads. keep_errors: also return every trial's errors as
    result.errors, shape (points, estimators, trials, 3), float64 (x mm, y mm, theta rad):
    24 bytes per trial and estimator, e.g. 72 MB for 15 points x 2 estimators x 1e5 trials.
    """
    designs = _as_patterns(patterns)
    raw = _patlab._simulate([p for p, _ in designs], [f for _, f in designs],
                            [float(s) for s in _iterable(sigmas)], int(trials), list(estimators),
                            dict(noise or {}), int(seed), int(threads), bool(keep_errors), name)
    return SimulationResult(raw)


def simulate_experiment(path_or_name, trials=None, seed=None, sigmas=None, threads=0,
                        keep_errors=False):
    """Runs an experiment file (or a shipped experiment by name, "fig5") as `patlab simulate`
    does, with the same overrides as its --trials, --seed and --sigmas. A detect-mode experiment
    (correspondence = "detect", e.g. "id_confusion") runs whole frames through the detector;
    `trials` is then the frames per point, and the table has the CLI's detect-mode columns."""
    path = _data.find(path_or_name, "experiment")
    return SimulationResult(_load_checked(
        lambda p: _patlab._simulate_experiment(p, trials, seed,
                                               [float(s) for s in _iterable(sigmas or [])],
                                               int(threads), bool(keep_errors)), path))


def estimate(pattern, observed, method="fast", max_iterations=20, return_converged=False,
             threads=0):
    """Poses (trials, 3) = (x mm, y mm, theta rad) from observed patches (trials, patches, 2),
    float64 in the pattern's patch order, any strides (read in place). method: "fast", "ml"
    (Newton from the fast pose, max_iterations steps), "lsq" or "key"; fast, lsq and key run
    vectorised over blocks of trials (estimate::EstimateMany), each pose the one-trial
    estimator's to the last bit. Runs in parallel with the GIL released on `threads` threads
    (0: every core; the poses do not depend on it). With return_converged (ml only) also a bool
    array per trial."""
    pattern, _ = _as_pattern(pattern)
    poses, converged = _patlab._estimate(pattern, observed, method, int(max_iterations),
                                         int(threads))
    return (poses, converged) if return_converged else poses


def crlb(pattern, sigma, noise=None):
    """The Cramer-Rao bound at patch sigma (mm): per-axis position std (mm) and theta std (rad)
    of the origin under the noise model; NaN where it has none (as in the CLI's results)."""
    pattern, _ = _as_pattern(pattern)
    return CrlbResult(**_patlab._crlb(pattern, float(sigma), dict(noise or {})))


def predicted_std(pattern, method, sigma):
    """An estimator's first-order predicted std at patch sigma (mm), independent patch noise
    (NaN for "robust", as in the CLI's results)."""
    pattern, _ = _as_pattern(pattern)
    return CrlbResult(**_patlab._predicted(pattern, method, float(sigma)))


def ids(pattern, colours, tolerance_mm=10.0):
    """The IDs of a pattern (paper Table II): its codebook for the ID colours `colours` (names,
    or a number n for the letters A, B, ... as `patlab ids --list`), with the symmetry about its
    key that geometry (within tolerance_mm) cannot decide."""
    pattern, _ = _as_pattern(pattern)
    if isinstance(colours, int):
        colours = [chr(ord("A") + c) for c in range(colours)]
    return IdsResult(_patlab._ids(pattern, list(colours), float(tolerance_mm)))


def evaluate(patterns, **options):
    """`patlab evaluate`: per pattern its accuracy against the bound, Monte-Carlo check, ID
    capacity and misidentification rate. options: sigma_mm, trials, colour_counts, tolerance_mm,
    sigmas_mm, frames, id_colours, seed, threads (the fields of design::EvaluateOptions)."""
    json_text, text = _patlab._evaluate(_as_patterns(patterns), options)
    return EvaluationResult(json_text, text)


def compare(patterns, sort_by="fast_theta_mrad_per_mm", **options):
    """`patlab compare`: the designs ranked by `sort_by`, one row per design (a DataFrame when
    pandas is installed); the options are evaluate's."""
    return CompareResult(*_patlab._compare(_as_patterns(patterns), sort_by, options))


def read_frame(path):
    """A PNG, JPEG or PPM frame as an (H, W, 3) uint8 RGB array, decoded as `patlab detect`
    decodes it."""
    path = os.fspath(path)
    return _load_checked(_patlab._read_frame, path)


def _detector_files(thresholds, calibration, settings, setup, settings_required):
    """The (thresholds, calibration, settings) paths: a `patlab setup` folder's, or the files
    given (paths or shipped names)."""
    if setup is not None:
        if any(f is not None for f in (thresholds, calibration, settings)):
            raise ValueError("setup names the thresholds, calibration and settings files; "
                             "expected setup= or the three files, not both")
        setup = os.fspath(setup)
        if not os.path.isdir(setup):
            raise FileNotFoundError(f"setup {setup}: no such folder; expected a folder written "
                                    "by patlab setup")
        return list(_patlab._setup_files(setup))
    if thresholds is None or calibration is None or (settings_required and settings is None):
        raise ValueError("expected setup= (a folder written by patlab setup) or the thresholds, "
                         "calibration" + (" and settings" if settings_required else "") +
                         " files")
    return [_data.find(f, "settings") if f is not None else "" for f in
            (thresholds, calibration, settings)]


def detect(image, thresholds=None, calibration=None, settings=None, name="frame", blobs=False,
           setup=None, explain=False):
    """`patlab detect` on one frame: an (H, W, 3) uint8 RGB array (any strides, read in place:
    the detector reads the array's own memory, no copy), with the thresholds and
    calibration files and, for detections, the detector settings (paths or shipped names), or
    instead of the three, ``setup``: a folder written by `patlab setup` (`detect --setup DIR`).
    Returns the CLI's CSV and JSON (`name` stands for the frame's path in them) and the table of
    detections (or, with blobs=True or no settings, of the calibrated blobs). With
    explain=True the JSON frame also holds "explanations": per key blob and pattern the
    rejecting stage, its measures against their bounds, the nearest rotation and the setting
    change that accepts the robot (`patlab detect --explain --format json`)."""
    files = _detector_files(thresholds, calibration, settings, setup, settings_required=False)
    try:
        return DetectResult(*_patlab._detect(image, *files, str(name), bool(blobs),
                                             bool(explain)))
    except ValueError as error:
        if any(f and not os.path.exists(f) for f in files):
            raise FileNotFoundError(str(error)) from None
        raise


class Detector:
    """The front end of `patlab detect` built once from its files (thresholds, calibration,
    detector settings: paths or shipped names), for frame after frame in memory, e.g. a camera
    loop: ``detect(image, name="frame")`` reads the (H, W, 3) uint8 RGB array in place (any
    strides, no copy) and returns the detections as a dict of numpy columns -- pattern (index
    into ``patterns``), team_colour (index into ``palette``), id (-1: unknown), x_mm, y_mm,
    theta_rad, confidence -- and cpp_seconds, the time of the C++ call alone. The detections
    are those `patlab detect` prints for the frame. ``warnings``: the palette mismatches.
    ``Detector(setup=DIR)`` takes the three files from a folder written by `patlab setup`."""

    def __init__(self, thresholds=None, calibration=None, settings=None, setup=None):
        files = _detector_files(thresholds, calibration, settings, setup, settings_required=True)
        try:
            self._detector = _patlab._Detector(*files)
        except ValueError as error:
            if any(not os.path.exists(f) for f in files):
                raise FileNotFoundError(str(error)) from None
            raise
        self.patterns = self._detector.patterns
        self.palette = self._detector.palette
        self.warnings = list(self._detector.warnings)
        self.detect = self._detector.detect  # the C++ method itself: no Python frame per call

    def __repr__(self):
        return f"<patlab.Detector: patterns {self.patterns}, palette {self.palette}>"


def render(scene):
    """`patlab render SCENE -o DIR` (without --camera): the scene file's frame as an (H, W, 3)
    uint8 array, and its true poses as the CSV DIR/truth.csv. Returns (image, truth_csv)."""
    path = _data.find(scene, "settings")
    return _load_checked(_patlab._render, path)


def setup(frames, field, settings, out, landmarks=(), robot_height=140.0, camera_height=None,
          line_width=4.0, colour_options=None, binning=0):
    """`patlab setup FRAME... --field FIELD --settings S -o OUT` (formats::SetupCamera): a new
    camera from its frames -- paths, or (H, W, 3) uint8 RGB arrays (named frame0, frame1, ...)
    -- written into the folder ``out`` that ``detect(image, setup=out)`` reads. ``field``: a
    field model (fitted alone, the rest of its family lending it views) or a family ("ssl",
    "vss"); ``settings``: detector settings (a path or a shipped
    name); ``landmarks``: "NAME=X,Y" strings (four or more replace the lines); ``robot_height``,
    ``camera_height`` and ``line_width`` as --robot-height (mm), --camera-height (mm; None:
    unknown, the lines or the robots decide) and --line-width (px); ``colour_options``: a dict
    NAME -> number of the colour fit's options (as --colour-option NAME=VALUE; docs/setup.md
    lists them); ``binning`` as --binning (0: frames over 1024 px binned to that or below).
    Returns the report as a
    dict: binning and frame_size_px (the frames binned binning x binning from their size: the
    pixel figures below are the binned frames'), field (the model kept), tried (each model: field, fitted, score_px, screen_px,
    held_out_mapping_mm: the kept model's only, NaN for the others; same_as, failure;
    screen_view_of, the model whose search found the view screen_px scores, "" its own; best
    first), undecided (the cameras the lines did
    not decide between, the kept one first: field, score_px, floor_difference_mm, robots; empty
    when the lines decided), robots_decided (the kept one decoded the most robots) and
    lines_overruled (no robot decoded through the lines' cameras, and the robots chose among
    them and the runners-up the lines decided against narrowly, all listed in undecided),
    camera_height (decided_by: "given", "lines", "robots" or "undetermined"; height_mm,
    focal_px, sd_mm, robots; lines_height_mm, lines_focal_px, lines_sd_mm, lines_robots: the
    lines' own camera; scan: the heights tried, each height_mm, focal_px, robots),
    few_lines (where the lines matched too few marks and the robots placed the field: used;
    lines_failure; floor_mm_per_px and robots, the floor scale the robots decoded at;
    small_patches, the scan's colours fitted for patches down to 2 px radius;
    placements and on_field, the crossings placed and those keeping the robots on the field;
    crossing, score_px, runner_up_px of the one kept; position_sd_mm, the stated error of a
    robot's position, and limit_mm, a pattern's radius; used False otherwise),
    mapping_error_mm (held-out line pixels, cross-validated landmarks, or, where the robots set
    the height and it is larger, floor_sd_mm), mapping_error_source ("" or "the fit's spread over
    the field"), floor_sd_mm (the fit with the robots' own uncertainty over the floor inside the
    field's lines, RMS mm; NaN where that fit was not made),
    mapping_resolution_mm, mm_per_px, smallest_patch_px, carpet_pixels, colour_classes (name,
    pixels, blobs, separability, nearest, widened_levels: Y, U, V levels the blob fit widened
    the box by towards the noise, thin_alike: pixels of regions too narrow for a blob, holding
    the class's colour within the noise, not counted against its box), colour_noise_levels (the
    camera's noise, Y, U, V), colour_fit ("blobs" or "pixels", the one that decodes more robots)
    with robots_by_blobs and robots_by_pixels, segment_k (the blobs' segmentation scale kept)
    and robots_by_segment_k (each scale tried: segment_k, robots), tolerances, robots (per frame:
    frame, robots with team, id,
    x_mm, y_mm, theta_rad), report (the CLI's text), seconds."""
    if isinstance(frames, (str, os.PathLike)) or hasattr(frames, "__array_interface__"):
        frames = [frames]
    frames = [os.fspath(f) if isinstance(f, (str, os.PathLike)) else f for f in frames]
    for f in frames:
        if isinstance(f, str) and not os.path.exists(f):
            raise FileNotFoundError(f"frame {f}: no such file; expected a PNG, JPEG or PPM frame")
    settings_path = _data.find(settings, "settings")
    return _patlab._setup(frames, os.fspath(field), _data._binary_dir(), settings_path,
                          os.fspath(out), [str(mark) for mark in _iterable(landmarks)],
                          float(robot_height),
                          None if camera_height is None else float(camera_height),
                          float(line_width),
                          {str(k): float(v) for k, v in (colour_options or {}).items()},
                          int(binning))


def pixel_to_floor(calibration, pixels, height_mm=None):
    """Pixels to the floor through a calibration file (a path, e.g. a setup folder's
    calibration.toml): ``pixels`` (N, 2) as (u, v) px -> (N, 2) as (x, y) mm on the plane
    ``height_mm`` above the floor (default: the calibration's default height), NaN where a
    pixel's ray does not reach the plane."""
    pixels = numpy.asarray(pixels, dtype=float).reshape(-1, 2)
    height = float("nan") if height_mm is None else float(height_mm)
    return _patlab._pixel_to_floor(os.fspath(calibration), pixels, height)


def _iterable(values):
    try:
        return list(values)
    except TypeError:
        return [values]
