"""The result objects of patlab's Python calls: tables as pandas DataFrames when pandas is
installed, else dicts of numpy arrays (and lists of strings)."""
import collections
import csv
import io
import json

import numpy as np

try:
    import pandas
except ImportError:  # pandas is optional
    pandas = None


def table(columns):
    """A DataFrame of the columns (in order) with pandas, else the dict itself."""
    if pandas is not None:
        return pandas.DataFrame(columns)
    return columns


def _table_from_csv(text):
    """The CLI's CSV text as a table: number columns float64 (empty cells NaN), others str."""
    return table(_columns_from_csv(text))


def _columns_from_csv(text):
    """The CLI's CSV text as a dict of columns: numbers float64 (empty cells NaN), others str."""
    rows = list(csv.reader(io.StringIO(text)))
    header, body = rows[0], rows[1:]
    columns = {}
    for k, name in enumerate(header):
        cells = [r[k] for r in body]
        try:
            columns[name] = np.array([float(c) if c != "" else np.nan for c in cells])
        except ValueError:
            columns[name] = cells
    return columns


CrlbResult = collections.namedtuple("CrlbResult", ["position_mm", "theta_rad"])
CrlbResult.__doc__ = "Per-axis position std (mm) and heading std (rad) of a pattern's origin."


class SimulationResult:
    """The data points of a simulation.

    table:  one row per pattern x sigma x estimator (a detect-mode experiment: per pattern x
            false-blob rate x sigma), columns named as the CLI's CSV columns and holding the
            doubles it prints with 10 significant digits (NaN for an empty cell)
    csv:    the CSV text `patlab simulate` writes for the same run, byte for byte
    errors: with keep_errors=True, every trial's errors (points, estimators, trials, 3)
    total_trials: the trials run (a detect-mode experiment: the frames)
    """

    def __init__(self, raw):
        self.columns = raw["columns"]
        if self.columns is None:  # detect mode: the CSV's columns
            self.columns = _columns_from_csv(raw["csv"])
        self.table = table(dict(self.columns))
        self.csv = raw["csv"]
        self.name = raw["name"]
        self.seed = raw["seed"]
        self.threads = raw["threads"]
        self.total_trials = raw["total_trials"]
        self.wall_seconds = raw["wall_seconds"]
        self.simulate_seconds = raw["simulate_seconds"]
        self.errors = raw.get("errors")

    def __repr__(self):
        rows = len(self.columns["pattern"])
        return (f"<patlab.SimulationResult {self.name!r}: {rows} rows, {self.total_trials} trials"
                f" in {self.wall_seconds:.3f} s on {self.threads} threads>")


class IdsResult:
    """A pattern's codebook: `table` one row per ID (id, then each ID slot's colour name),
    `count` the number of IDs, `rotations` the rotations ID colours must decide, `summary` and
    `symmetry_table` as `patlab ids` prints them."""

    def __init__(self, raw):
        self.pattern = raw["pattern"]
        self.colours = raw["colours"]
        self.slots = raw["slots"]
        self.ids = np.asarray(raw["ids"], dtype=np.int64)
        self.colourings = raw["colourings"]
        self.count = raw["count"]
        self.rotations = raw["rotations"]
        self.accepted_shifts = raw["accepted_shifts"]
        self.effective_shifts = raw["effective_shifts"]
        self.summary = raw["summary"]
        self.symmetry_table = raw["table"]
        columns = {"id": self.ids}
        for k, slot in enumerate(self.slots):
            columns[f"slot_{slot}"] = [self.colours[c] for c in self.colourings[:, k]]
        self.table = table(columns)

    def __len__(self):
        return len(self.ids)

    def __repr__(self):
        return (f"<patlab.IdsResult {self.pattern!r}: {self.count} IDs with "
                f"{len(self.colours)} colours, {self.rotations} rotations>")


class EvaluationResult:
    """`patlab evaluate`'s reports: `json` (the dict of --json), `text` (the report for
    people), `reports` (one dict per pattern) and `table` (one row per pattern and estimator:
    predicted, bound and Monte-Carlo stds)."""

    def __init__(self, json_text, text):
        self.json = json.loads(json_text)
        self.text = text
        self.reports = self.json["patterns"]

    def __repr__(self):
        return f"<patlab.EvaluationResult: {len(self.reports)} patterns>"


class CompareResult:
    """`patlab compare`: `table` the ranked designs (the CSV's columns), `csv`, `json` (dict)
    and `text` as the CLI writes them."""

    def __init__(self, csv_text, json_text, text):
        self.csv = csv_text
        self.json = json.loads(json_text)
        self.text = text
        self.table = _table_from_csv(csv_text)

    def __repr__(self):
        return f"<patlab.CompareResult: {len(self.json.get('rows', []))} designs>"


class DetectResult:
    """One frame through `patlab detect`: `table` (one row per detection, or per blob), `csv` and
    `json` (dict) as the CLI writes them, `warnings` (the detector's, as it prints them)."""

    def __init__(self, csv_text, json_text, warnings):
        self.csv = csv_text
        self.json = json.loads(json_text)
        self.warnings = list(warnings)
        self.table = _table_from_csv(csv_text)

    def __len__(self):
        return len(next(iter(self.table.values())) if isinstance(self.table, dict) else self.table)

    def __repr__(self):
        return f"<patlab.DetectResult: {len(self)} rows>"
