"""What every plotting script (scripts/plot_*.py) does with its files, in one place.

A missing or malformed input file ends the script with one line on stderr and exit status 2, as
patlab's own bad-input errors do:

    plot_fig5.py: results/fig5.csv: no such file; expected the CSV of `patlab simulate`

and a figure or file that cannot be written ends it with one line and exit status 1. No
traceback: a traceback from a plotting script is a bug in the script, not in its input.

    table = plotinput.read_csv(path, "the CSV of `patlab simulate`",
                               columns=["pattern", "sigma_mm"], numbers=["sigma_mm"])
    for row in table.rows: ...          # dicts, column -> text, every listed number checked
    plotinput.save(fig, out)
"""
import csv
import math
import os
import sys

def script_name():
    return os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else "plot"


def fail(path, message, status=2):
    """Prints `SCRIPT: PATH: MESSAGE` on stderr and exits with `status` (2: bad input)."""
    print(f"{script_name()}: {path}: {message}", file=sys.stderr)
    sys.exit(status)


def usage(text):
    """Prints the usage line on stderr and exits 2 (wrong arguments are bad input too)."""
    print(f"usage: {script_name()} {text}", file=sys.stderr)
    sys.exit(2)


class Table:
    """The rows of a CSV file with a header: `rows` are dicts (column -> text), `lines[i]` is the
    file line of rows[i], for messages."""

    def __init__(self, path, columns, rows, lines):
        self.path = path
        self.columns = columns
        self.rows = rows
        self.lines = lines

    def require_numbers(self, names, empty_ok=True):
        """Every cell of the columns `names` is a number (float() syntax: 1e-6, nan, inf; an
        empty cell too when empty_ok); fails naming the line, column and cell otherwise."""
        for name in names:
            if name not in self.columns:
                fail(self.path, f"no column '{name}' in the header")
            for row, line in zip(self.rows, self.lines):
                text = row[name]
                if text == "" and empty_ok:
                    continue
                try:
                    float(text)
                except ValueError:
                    fail(self.path, f"line {line}, column '{name}': '{text}' is not a number")

    def require_integers(self, names):
        """Every cell of the columns `names` is a whole number (counts)."""
        for name in names:
            if name not in self.columns:
                fail(self.path, f"no column '{name}' in the header")
            for row, line in zip(self.rows, self.lines):
                try:
                    int(row[name])
                except ValueError:
                    fail(self.path, f"line {line}, column '{name}': '{row[name]}' is not a "
                                    "whole number")

    def array(self, types):
        """The columns of `types` (name -> "str", "int" or "float") as a numpy structured array,
        the shape np.genfromtxt(names=True) gives; the cells must have been checked."""
        import numpy as np  # only the scripts that need arrays pay for numpy

        dtype = []
        for name, kind in types.items():
            if kind == "str":
                width = max((len(r[name]) for r in self.rows), default=1)
                dtype.append((name, f"<U{max(width, 1)}"))
            else:
                dtype.append((name, {"int": np.int64, "float": np.float64}[kind]))
        convert = {"str": str, "int": int, "float": lambda t: float(t) if t != "" else math.nan}
        cells = [tuple(convert[kind](r[name]) for name, kind in types.items()) for r in self.rows]
        return np.array(cells, dtype=dtype)


def read_csv(path, what, columns=(), numbers=(), integers=(), empty_ok=True):
    """Reads the CSV file `path` (RFC 4180: quoted fields, CRLF and a UTF-8 BOM accepted).

    `what` says what the file should be, for the messages ("the CSV of `patlab compare`"). Fails
    with one line and exit 2 when the file is missing or unreadable, is not UTF-8 text, is empty
    or has only a header, lacks one of `columns`, has a row with another number of fields than
    its header, or has a cell in `numbers` (or `integers`) that is not one.
    """
    if not os.path.exists(path):
        fail(path, f"no such file; expected {what}")
    if os.path.isdir(path):
        fail(path, f"is a directory; expected {what}")
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            records = list(_records(path, f))
    except OSError as e:
        fail(path, f"cannot be read: {e.strerror}")
    except UnicodeDecodeError as e:
        fail(path, f"not UTF-8 text (byte {e.start}); expected {what}")
    if not records:
        fail(path, f"empty; expected {what}")
    (_, header), body = records[0], records[1:]
    for name in columns:
        if name not in header:
            fail(path, f"no column '{name}' in the header; expected {what}")
    rows, lines = [], []
    for line, fields in body:
        if len(fields) != len(header):
            fail(path, f"line {line}: {len(fields)} fields, the header has {len(header)}")
        rows.append(dict(zip(header, fields)))
        lines.append(line)
    if not rows:
        fail(path, f"a header and no rows; expected {what}")
    table = Table(path, header, rows, lines)
    table.require_numbers(numbers, empty_ok)
    table.require_integers(integers)
    return table


def _records(path, f):
    """(line number of the record's start, fields) of every non-blank record."""
    reader = csv.reader(f, strict=True)
    start = 1
    try:
        for fields in reader:
            if fields:
                yield start, fields
            start = reader.line_num + 1
    except csv.Error as e:
        fail(path, f"line {reader.line_num}: {e}")


def save(fig, path, **options):
    """fig.savefig(path), or one line and exit 1 when the file cannot be written."""
    try:
        fig.savefig(path, **options)
    except OSError as e:
        fail(path, f"cannot be written: {e.strerror}", status=1)


def write_text(path, text):
    """Writes a file the script derives (a merged CSV), or one line and exit 1."""
    try:
        with open(path, "w", newline="") as f:
            f.write(text)
    except OSError as e:
        fail(path, f"cannot be written: {e.strerror}", status=1)

