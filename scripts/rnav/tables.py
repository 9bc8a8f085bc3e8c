"""Reading the project's outputs as tables: a CSV with its column description, a run folder, a
sweep folder, an LCM log.

A Table is a dict {column: numpy array} in the file's column order, with `units` and `meanings`
({column: text}, from NAME.units.json beside the CSV, or from the .lcm comments for a log) and
`frame()`, the same as a pandas DataFrame (pandas from Debian: python3-pandas).

Cells are read strictly: every row has the header's number of fields; a column is integer if
every cell is a decimal integer, a float if every cell is a decimal number ('nan' and 'inf'
allowed, as the writers print them; an empty cell is NaN), else text (decoded where the
units.json says "encoding": "percent", csvio.py). A malformed line, a ';'
separated file, a header that is not plain names, or a units.json whose columns are not the
header's is a CsvError naming the file (and the line).
"""
import csv
import json
import os
import re
from urllib.parse import unquote

import numpy as np

from .csvio import CsvError, NAME, read_units

_INT = re.compile(r"^[+-]?[0-9]+$")
_FLOAT = re.compile(r"^[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?$|^[+-]?(?:nan|inf|infinity)$", re.I)


class Table(dict):
    """{column: numpy array} in column order; `path`, `units`, `meanings` ({column: text})."""

    def __init__(self, columns, path="", units=None, meanings=None):
        super().__init__(columns)
        self.path = path
        self.units = dict(units or {})
        self.meanings = dict(meanings or {})

    @property
    def columns(self):
        return list(self.keys())

    @property
    def n_rows(self):
        return len(next(iter(self.values()))) if self else 0

    def frame(self):
        """The table as a pandas DataFrame (units in `.attrs['units']`)."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("pandas is not installed for this interpreter: apt-get install python3-pandas "
                              "(scripts/setup installs it); the numpy columns need no pandas") from None
        f = pd.DataFrame({c: a for c, a in self.items()}, columns=self.columns)
        f.attrs["units"] = dict(self.units)
        f.attrs["meanings"] = dict(self.meanings)
        return f

    def label(self, column):
        """'meaning [unit]' of a column (its name where nothing is known), for plots."""
        m, u = self.meanings.get(column) or column, self.units.get(column, "")
        return "%s [%s]" % (m, u) if u else m


def _column(cells):
    if all(_INT.match(c) for c in cells) and cells:
        return np.array([int(c) for c in cells], dtype=np.int64)
    if all(c == "" or _FLOAT.match(c) for c in cells):
        return np.array([float(c) if c else float("nan") for c in cells], dtype=float)
    return np.array(cells, dtype=str)


def read_csv(path):
    """A Table of one CSV the project wrote (or any CSV with a plain header)."""
    try:
        f = open(path, newline="", encoding="utf-8")
    except OSError as e:
        raise CsvError("%s: cannot open: %s" % (path, e.strerror)) from None
    with f:
        text = f.read()
    if text.startswith("\ufeff"):
        raise CsvError("%s: starts with a byte-order mark; save it as plain UTF-8" % path)
    if text and not text.endswith("\n"):
        raise CsvError("%s: the last line has no newline: the file may have been cut while written" % path)
    rows = list(csv.reader(text.splitlines()))
    if not rows:
        raise CsvError("%s: empty (no header)" % path)
    header = rows[0]
    if len(header) == 1 and ";" in header[0]:
        raise CsvError("%s: the header is separated by ';', not ',' (%s): save it with commas" % (path, header[0][:60]))
    for h in header:
        if not NAME.match(h):
            raise CsvError("%s: line 1: column name %r is not plain (letters, digits, '_')" % (path, h))
    if len(set(header)) != len(header):
        raise CsvError("%s: line 1: a column name given twice" % path)
    body = rows[1:]
    for i, r in enumerate(body):
        if len(r) != len(header):
            raise CsvError("%s: line %d: %d fields, the header has %d" % (path, i + 2, len(r), len(header)))
    cols = {h: _column([r[j].strip() for r in body]) for j, h in enumerate(header)}
    doc = read_units(path)
    units, meanings = {}, {}
    if doc is not None:
        if list(doc) != header:
            raise CsvError("%s: its units.json describes columns %s, the header has %s" % (path, list(doc), header))
        for c, d in doc.items():
            if d.get("encoding") == "percent" and cols[c].dtype.kind == "U":
                cols[c] = np.array([unquote(x) for x in cols[c]], dtype=str)
        units = {c: d["unit"] for c, d in doc.items()}
        meanings = {c: d["meaning"] for c, d in doc.items()}
    return Table(cols, path, units, meanings)


class Folder(dict):
    """A folder's outputs: {stem: Table} of every NAME.csv and {stem: object} of every other
    NAME.json (the units.json files go into their tables), `path`, and `frames()`."""

    def __init__(self, path):
        super().__init__()
        self.path = path
        self.json = {}
        names = sorted(os.listdir(path))
        for n in names:
            full = os.path.join(path, n)
            if not os.path.isfile(full):
                continue
            if n.endswith(".csv"):
                self[n[:-4]] = read_csv(full)
            elif n.endswith(".json") and not n.endswith(".units.json"):
                try:
                    with open(full, encoding="utf-8") as f:
                        self.json[n[:-5]] = json.load(f)
                except ValueError as e:
                    raise CsvError("%s: not JSON: %s" % (full, e)) from None

    def frames(self):
        """{stem: pandas DataFrame} of every table."""
        return {k: t.frame() for k, t in self.items()}


def read_run(path):
    """A run folder (scripts/run --out DIR, a study's run, rnav_log2csv --out DIR): its tables
    ({name: Table}, e.g. run['stats_time']['apoi_rms_x_m']) and `json` ({name: object}, e.g.
    run.json['table2'])."""
    if not os.path.isdir(path):
        raise CsvError("%s: not a folder (a run folder is what scripts/run --out wrote)" % path)
    run = Folder(path)
    if not run and not run.json:
        raise CsvError("%s: holds no CSV or JSON output" % path)
    return run


def read_sweep(path):
    """A sweep folder (scripts/sweep --out DIR): its sweep.csv as a Table (one row per setting:
    the grid keys, then each figure and its standard error `_se`), `json` (sweep.json: the grid,
    the rows, which settings failed) and `run(i)`, the run folder of setting i."""
    csv_path = os.path.join(path, "sweep.csv")
    if not os.path.isfile(csv_path):
        raise CsvError("%s: no sweep.csv (not a sweep folder, or the sweep has not finished)" % path)
    t = read_csv(csv_path)
    with open(os.path.join(path, "sweep.json"), encoding="utf-8") as f:
        t.json = json.load(f)
    t.run = lambda i: read_run(os.path.join(path, "settings", "%03d" % i, "run"))
    return t


def read_log(path, channels=None, all_attempts=False):
    """{channel: Table} of an LCM event log of the project (lcmlog.py: every message checked,
    resent copies and earlier attempts dropped), with units and meanings from lcmtypes/*.lcm."""
    from . import lcmlog
    meanings = {}
    unit_map = lcmlog.units(meanings=meanings)
    raw, _, _ = lcmlog.read(path, channels, all_attempts)
    out = {}
    for ch, t in raw.items():
        out[ch] = Table(t.arrays(), path, lcmlog.column_units(t, unit_map), lcmlog.column_meanings(t, meanings))
    return out
