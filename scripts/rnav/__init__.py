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
`python3 -m rnav` (scripts/ on PYTHONPATH, or scripts/setup's rnav.pth) lists what a run, sweep
or log holds and converts a log to CSV; see `python3 -m rnav --help`.

Modules: tables (reading), csvio (the CSV + units.json format every writer follows), lcmlog (LCM
event logs), effect_labels (the diagnosis's effects as legend text), figures (what the figure
programs plot_prl.py and plot_uav.py share: matplotlib without a display, their input error),
interpreter (those programs and `python3 -m rnav` handed over to Debian's /usr/bin/python3 when
the python3 running them lacks numpy); for
the programs in scripts/ (which import the package through the link scripts/rnav): cli_args (their
command lines and messages), study_runner (the runner of every study's jobs), clopper_pearson
(binomial intervals).
"""
import importlib
import sys

# The readers need numpy; the programs' helpers (cli_args, study_runner, clopper_pearson) and
# effect_labels do not, so the readers are loaded on first use: scripts/flightgen.py, the
# independent generator, runs on any Python 3.
_READERS = {"CsvError": "csvio", "LogError": "lcmlog", "Folder": "tables", "Table": "tables",
            "read_csv": "tables", "read_log": "tables", "read_run": "tables", "read_sweep": "tables"}
__all__ = list(_READERS)


def __getattr__(name):
    """A reader of the package (see _READERS), imported when first asked for."""
    module = _READERS.get(name)
    if module is None:
        raise AttributeError("module 'rnav' has no attribute %r" % name)
    try:
        import numpy  # noqa: F401
    except ImportError:  # the python3 first on PATH may be another interpreter than Debian's
        raise ImportError("rnav needs numpy, which this interpreter (%s) lacks: use Debian's /usr/bin/python3 "
                          "(scripts/setup installs python3-numpy)" % sys.executable) from None
    return getattr(importlib.import_module("." + module, __name__), name)
