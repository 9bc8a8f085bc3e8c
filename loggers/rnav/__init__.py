"""rnav: the project's outputs in Python (Debian's /usr/bin/python3 with python3-numpy; pandas
optional, python3-pandas).

    import rnav
    run = rnav.read_run("/tmp/run2")              # a scripts/run --out folder
    run["stats_time"]["apoi_rms_x_m"]             # a numpy array
    run["stats_time"].frame()                     # a pandas DataFrame
    run.json["table2"]                            # the run's JSON outputs
    sw = rnav.read_sweep("/tmp/sweep")            # scripts/sweep --out: one row per setting
    log = rnav.read_log("/tmp/run.lcmlog")        # {channel: Table}, every message checked

Every Table is {column: numpy array} with `units`, `meanings` and `frame()`. From the top folder
`python3 -m rnav` (loggers/ on PYTHONPATH, or scripts/setup's rnav.pth) lists what a run, sweep
or log holds and converts a log to CSV; see `python3 -m rnav --help`.

Modules: tables (reading), csvio (the CSV + units.json format every writer follows), lcmlog (LCM
event logs), effect_labels (the diagnosis's effects as legend text).
"""
import sys

try:
    import numpy  # noqa: F401
except ImportError:  # the python3 first on PATH may be another interpreter than Debian's
    _why = ("rnav needs numpy, which this interpreter (%s) lacks: use Debian's /usr/bin/python3 "
            "(scripts/setup installs python3-numpy)" % sys.executable)
    if sys.argv[:1] == ["-m"]:  # python3 -m rnav: a message, not a traceback
        sys.stderr.write("rnav: error: %s\n" % _why)
        raise SystemExit(2)
    raise ImportError(_why) from None

from .csvio import CsvError  # noqa: E402
from .lcmlog import LogError  # noqa: E402
from .tables import Folder, Table, read_csv, read_log, read_run, read_sweep  # noqa: E402

__all__ = ["CsvError", "LogError", "Folder", "Table", "read_csv", "read_log", "read_run", "read_sweep"]
