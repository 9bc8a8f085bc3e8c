"""python3 -m rnav: what a run, sweep, CSV or LCM log holds; an LCM log as CSV files.

  python3 -m rnav show PATH [--columns]   PATH: a run folder (scripts/run --out), a sweep folder
                                          (scripts/sweep --out), a CSV, or an LCM event log; lists
                                          its tables (rows x columns) and JSON outputs; --columns
                                          adds every column's unit and meaning
  python3 -m rnav csv LOG --out DIR ...   every channel of an LCM log as DIR/CHANNEL.csv with its
                                          units.json (the same as scripts/rnav_log2csv)

Exit status 0, 2 for bad input (named on stderr).
"""
import os
import sys

try:
    from . import CsvError, LogError, read_csv, read_log, read_run, read_sweep
except ImportError as e:  # numpy missing: Debian's python3 takes over, else a message, not a traceback
    from . import interpreter
    interpreter.hand_over(["-m", "rnav"] + sys.argv[1:])
    sys.stderr.write("rnav: error: %s\n" % e)
    raise SystemExit(2)

_REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _show_table(name, t, columns):
    print("%s: %d rows x %d columns" % (name, t.n_rows, len(t.columns)))
    if columns:
        for c in t.columns:
            u = t.units.get(c, "")
            print("  %-28s %-10s %s" % (c, "[%s]" % u if u else "", t.meanings.get(c, "")))


def show(path, columns):
    if os.path.isdir(path):
        if os.path.isfile(os.path.join(path, "sweep.csv")):
            t = read_sweep(path)
            _show_table("sweep", t, columns)
            print("settings: %d; complete: %s" % (t.n_rows, t.json.get("complete")))
            return
        run = read_run(path)
        for name, t in sorted(run.items()):
            _show_table(name, t, columns)
        if run.json:
            print("json: " + ", ".join(sorted(run.json)))
        return
    if path.endswith(".csv"):
        _show_table(os.path.basename(path)[:-4], read_csv(path), columns)
        return
    for ch, t in sorted(read_log(path).items()):
        _show_table(ch, t, columns)


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if argv else 2
    cmd, rest = argv[0], argv[1:]
    if cmd == "csv":
        script = os.path.join(_REPO, "scripts", "rnav_log2csv")
        os.execv(sys.executable, [sys.executable, script] + rest)
    if cmd != "show":
        sys.stderr.write("rnav: error: unknown command '%s' (show, csv; see python3 -m rnav --help)\n" % cmd)
        return 2
    paths = [a for a in rest if a != "--columns"]
    bad = [a for a in paths if a.startswith("-")]
    if len(paths) != 1 or bad:
        sys.stderr.write("rnav: error: show takes one PATH and optionally --columns%s\n"
                         % (" (unknown option %s)" % bad[0] if bad else ""))
        return 2
    if not os.path.exists(paths[0]):
        sys.stderr.write("rnav: error: %s: no such file or folder\n" % paths[0])
        return 2
    try:
        show(paths[0], "--columns" in rest)
    except (CsvError, LogError) as e:
        sys.stderr.write("rnav: error: %s\n" % e)
        return 2
    return 0


sys.exit(main(sys.argv[1:]))
