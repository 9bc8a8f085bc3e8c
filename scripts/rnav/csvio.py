"""The project's CSV files and the column descriptions beside them.

Every CSV the project writes has a header of plain column names (letters, digits and '_', a unit
suffix where there is one: `range_m`, `t_s`, `az_deg`), so `numpy.genfromtxt(path, delimiter=',',
names=True)` and `pandas.read_csv(path)` take it as it is, and beside it `NAME.units.json` (NAME
is the CSV's path without `.csv`) describing every column, in the header's order:

    {"range_m": {"unit": "m", "meaning": "slant range from the radar"}, ...}

`unit` is "" for a count, an index or a dimensionless ratio; `meaning` is never empty. A text
column that may hold commas, quotes or line breaks (a JSON text in an LCM log) has
`"encoding": "percent"`: those characters and '%' are written as %2C, %22, %0A, %0D and %25
(urllib.parse.unquote undoes it; rnav.read_csv does), because numpy's genfromtxt knows no
quoting. The C++ writers produce the same file (common/io/csv_columns.hpp).
"""
import csv
import json
import os
import re

NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


class CsvError(Exception):
    """A CSV file or its description that is not what it claims: the message names the file."""


def units_path(csv_path):
    """PATH.csv -> PATH.units.json (the description beside a CSV)."""
    return (csv_path[:-4] if csv_path.endswith(".csv") else csv_path) + ".units.json"


def percent_encode(text):
    """A text cell without the characters a plain CSV cannot hold (see the module's text)."""
    return (text.replace("%", "%25").replace(",", "%2C").replace('"', "%22")
            .replace("\n", "%0A").replace("\r", "%0D"))


def check_columns(columns, what):
    """columns: [(name, unit, meaning[, encoding]), ...]; names plain and unique, meanings
    non-empty, encoding (a text column's) None or "percent"."""
    seen = set()
    for c in columns:
        if len(c) not in (3, 4) or (len(c) == 4 and c[3] not in (None, "percent")):
            raise CsvError("%s: a column is (name, unit, meaning[, None|'percent']), got %r" % (what, c))
        name, unit, meaning = c[:3]
        if not NAME.match(name):
            raise CsvError("%s: column name %r is not plain (letters, digits, '_')" % (what, name))
        if name in seen:
            raise CsvError("%s: column %r given twice" % (what, name))
        if not isinstance(unit, str) or not meaning:
            raise CsvError("%s: column %r needs a unit text and a meaning" % (what, name))
        seen.add(name)


def _atomic_write(path, write):
    tmp = path + ".partial"
    with open(tmp, "w", newline="", encoding="utf-8") as f:
        write(f)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def write_units(csv_path, columns):
    """Write PATH.units.json for columns [(name, unit, meaning[, encoding]), ...]."""
    check_columns(columns, csv_path)
    lines = []
    for c in columns:
        d = {"unit": c[1], "meaning": c[2]}
        if len(c) == 4 and c[3]:
            d["encoding"] = c[3]
        lines.append(" %s: %s" % (json.dumps(c[0]), json.dumps(d)))
    # one column per line, as the C++ writers (common/io/csv_columns.hpp) write it
    _atomic_write(units_path(csv_path), lambda f: f.write("{\n" + ",\n".join(lines) + "\n}\n"))


def write_csv(path, columns, rows):
    """Write rows (sequences, one value per column; floats in shortest round-trip form, booleans
    1/0, None empty, text percent-encoded in 'percent' columns and refused with a comma, quote
    or line break elsewhere) to PATH with a plain header, and PATH.units.json beside it. Each
    file appears whole or not at all (written to .partial, then renamed)."""
    check_columns(columns, path)
    n = len(columns)
    percent = [len(c) == 4 and c[3] == "percent" for c in columns]

    def text(x, j, i):
        if x is None:
            return ""
        if isinstance(x, bool):
            return "1" if x else "0"
        if isinstance(x, float):
            return repr(x)
        s = str(x)
        if percent[j]:
            return percent_encode(s)
        if any(ch in s for ch in ',"\n\r'):
            raise CsvError("%s: row %d, column %s: %r holds a comma, quote or line break; declare the column "
                           "'percent'" % (path, i + 1, columns[j][0], s))
        return s

    def write(f):
        w = csv.writer(f, lineterminator="\n")
        w.writerow([c[0] for c in columns])
        for i, r in enumerate(rows):
            if len(r) != n:
                raise CsvError("%s: row %d has %d values for %d columns" % (path, i + 1, len(r), n))
            w.writerow([text(x, j, i) for j, x in enumerate(r)])
    _atomic_write(path, write)
    write_units(path, columns)


def read_units(csv_path):
    """{column: {"unit", "meaning"}} from the description beside a CSV, or None if there is none."""
    p = units_path(csv_path)
    if not os.path.exists(p):
        return None
    try:
        with open(p, encoding="utf-8") as f:
            doc = json.load(f)
    except ValueError as e:
        raise CsvError("%s: not JSON: %s" % (p, e))
    if not isinstance(doc, dict):
        raise CsvError("%s: expected an object {column: {unit, meaning}}" % p)
    for k, v in doc.items():
        if not (isinstance(v, dict) and isinstance(v.get("unit"), str) and isinstance(v.get("meaning"), str)
                and v.get("encoding", "percent") == "percent" and set(v) <= {"unit", "meaning", "encoding"}):
            raise CsvError("%s: column %r: expected {\"unit\": text, \"meaning\": text[, \"encoding\": \"percent\"]}"
                           % (p, k))
    return doc
