#!/usr/bin/python3
"""ctest python.rnav_package: the package's strict reading and its command line, on hand-made files.

  * rnav.read_csv names the file and line of a malformed row, a ';'-separated header, a header
    name that is not plain, a last line without its newline (a file cut while written), a
    byte-order mark, and a units.json whose columns are not the header's;
  * integer, float (nan, empty = NaN) and text columns get their numpy kinds; a percent-encoded
    text column is decoded; units and meanings come from the units.json;
  * csvio.write_csv refuses a column name that is not plain and a row of the wrong length,
    and what it writes reads back equal;
  * `python3 -m rnav show` lists a folder's tables, exits 2 naming a bad file; with numpy made
    unimportable `import rnav` raises an ImportError naming the interpreter, and `-m rnav`
    prints one line, no traceback;
  * lcmlog.holds_close (scripts/run stops its recorder by it) finds a run's SIM_WINDOW CLOSE
    amid other traffic, from a start inside an event, and not another run's, another command,
    one before the start, nor one the file cuts short.
Usage: PYTHONPATH=SOURCE_DIR/scripts check_rnav_package.py SOURCE_DIR BUILD_DIR (ctest sets PYTHONPATH)
"""
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import rnav
from rnav import csvio

SRC = os.path.abspath(sys.argv[1])
os.environ["RNAV_BUILD"] = os.path.abspath(sys.argv[2])  # its generated message types (lcmlog)

bad = []
T = tempfile.mkdtemp(prefix="rnav_pkg.")


def write(name, text):
    p = os.path.join(T, name)
    with open(p, "w", encoding="utf-8", newline="") as f:
        f.write(text)
    return p


def refused(path, *words):
    try:
        rnav.read_csv(path)
    except rnav.CsvError as e:
        if not all(w in str(e) for w in words):
            bad.append("%s: message %r lacks %r" % (os.path.basename(path), str(e), words))
        return
    bad.append("%s: read without error" % os.path.basename(path))


try:
    refused(write("short.csv", "t_s,x_m\n1,2\n3\n"), "short.csv", "line 3", "1 fields")
    refused(write("semi.csv", "t_s;x_m\n1;2\n"), "separated by ';'")
    refused(write("name.csv", "t [s],x_m\n1,2\n"), "line 1", "'t [s]'")
    refused(write("cut.csv", "t_s,x_m\n1,2\n3,4"), "no newline")
    refused(write("bom.csv", "\ufefft_s,x_m\n1,2\n"), "byte-order mark")
    p = write("units.csv", "t_s,x_m\n1,2\n")
    write("units.units.json", '{"t_s": {"unit": "s", "meaning": "time"}, "y_m": {"unit": "m", "meaning": "y"}}\n')
    refused(p, "units.json", "y_m")

    rows = [(0, 1.5, "a,b", 7), (1, float("nan"), 'say "x"\n%', -2)]
    cols = [("i", "", "row index"), ("v_m", "m", "a value"), ("note", "", "free text", "percent"),
            ("k", "", "a count")]
    p = os.path.join(T, "good.csv")
    csvio.write_csv(p, cols, rows)
    t = rnav.read_csv(p)
    if [t[c].dtype.kind for c in t.columns] != ["i", "f", "U", "i"]:
        bad.append("good.csv: kinds %s" % [t[c].dtype.kind for c in t.columns])
    if list(t["note"]) != ["a,b", 'say "x"\n%'] or t["v_m"][0] != 1.5 or not np.isnan(t["v_m"][1]):
        bad.append("good.csv: read back %s %s" % (list(t["note"]), t["v_m"]))
    if t.units["v_m"] != "m" or t.meanings["note"] != "free text" or t.label("v_m") != "a value [m]":
        bad.append("good.csv: units %s meanings %s" % (t.units, t.meanings))
    if np.genfromtxt(p, delimiter=",", names=True, dtype=None, encoding="utf-8").dtype.names != ("i", "v_m", "note", "k"):
        bad.append("good.csv: numpy does not read the header as it is")
    if t.frame().shape != (2, 4):
        bad.append("good.csv: frame shape %s" % (t.frame().shape,))
    for c, r, words in ((cols + [("x y", "", "bad")], rows, "'x y'"), (cols, [(1, 2.0)], "row 1")):
        try:
            csvio.write_csv(os.path.join(T, "w.csv"), c, r)
            bad.append("write_csv accepted %s" % words)
        except csvio.CsvError as e:
            if words not in str(e):
                bad.append("write_csv: %r lacks %r" % (str(e), words))

    env = dict(os.environ, PYTHONPATH=os.path.join(SRC, "scripts"))
    os.makedirs(os.path.join(T, "run"))
    csvio.write_csv(os.path.join(T, "run", "a.csv"), cols, rows)
    out = subprocess.run([sys.executable, "-m", "rnav", "show", os.path.join(T, "run"), "--columns"], env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if out.returncode != 0 or "a: 2 rows x 4 columns" not in out.stdout or "[m]" not in out.stdout:
        bad.append("-m rnav show: %d %s" % (out.returncode, out.stdout))
    out = subprocess.run([sys.executable, "-m", "rnav", "show", os.path.join(T, "short.csv")], env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if out.returncode != 2 or "short.csv" not in out.stdout or "Traceback" in out.stdout:
        bad.append("-m rnav show of a bad file: %d %s" % (out.returncode, out.stdout))
    no_numpy = "import sys; sys.modules['numpy'] = None; %s"
    out = subprocess.run([sys.executable, "-c", no_numpy % "import rnav; rnav.read_run"], env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if out.returncode == 0 or "ImportError: rnav needs numpy" not in out.stdout or "/usr/bin/python3" not in out.stdout:
        bad.append("rnav.read_run without numpy: %d %s" % (out.returncode, out.stdout[-400:]))
    # the programs' helpers need no numpy (flightgen.py, the independent generator, uses them)
    out = subprocess.run([sys.executable, "-c", no_numpy % "from rnav import cli_args, study_runner, clopper_pearson"],
                         env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if out.returncode != 0:
        bad.append("the programs' helpers without numpy: %d %s" % (out.returncode, out.stdout[-400:]))
    out = subprocess.run([sys.executable, "-c", no_numpy % "import runpy; sys.argv = ['-m']; runpy.run_module('rnav')"],
                         env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if out.returncode != 2 or "Traceback" in out.stdout or "rnav: error: rnav needs numpy" not in out.stdout:
        bad.append("-m rnav without numpy: %d %s" % (out.returncode, out.stdout[-400:]))
    # lcmlog.holds_close on a hand-made recording: another run's traffic (bytes of no type on
    # TRAFFIC_X, SIM_WINDOW of run 8), this run's (7) FINISH, then its CLOSE, then more traffic
    from rnav import lcmlog
    window = {c.__name__: c for c in lcmlog.message_types().values()}["sim_window_t"]

    def event(num, channel, data):
        head = lcmlog._HEADER.pack(lcmlog.SYNC, num, 1000 + num, len(channel), len(data))
        return head + channel.encode("ascii") + data

    def command(cmd, run_id):
        m = window()
        m.command, m.run_id = cmd, run_id
        return m.encode()

    CLOSE, FINISH = 6, 2
    parts = [event(1, "TRAFFIC_X", b"SIM_WINDOW" * 3), event(2, "SIM_WINDOW", command(CLOSE, 8)),
             event(3, "SIM_WINDOW", command(FINISH, 7))]
    at_close = sum(len(x) for x in parts)
    parts += [event(4, "SIM_WINDOW", command(CLOSE, 7)), event(5, "TRAFFIC_X", b"\x00" * 40)]
    whole = b"".join(parts)
    log = os.path.join(T, "close.lcmlog")

    def holds(data, run_id, start=0):
        with open(log, "wb") as f:
            f.write(data)
        return lcmlog.holds_close(log, run_id, start)

    checks = {"the run's CLOSE": holds(whole, 7), "from a byte inside the event before it": holds(whole, 7, at_close - 5),
              "not another run's": not holds(whole, 9), "not FINISH": not holds(b"".join(parts[:3]), 7),
              "not before the start": not holds(whole, 7, at_close + 1),
              "not cut short": not holds(whole[:at_close + len(parts[3]) - 1], 7),
              "another run's CLOSE": holds(whole, 8)}
    for what, ok in checks.items():
        if not ok:
            bad.append("lcmlog.holds_close: " + what)
finally:
    shutil.rmtree(T, ignore_errors=True)

if bad:
    print("FAIL:\n  " + "\n  ".join(bad))
    sys.exit(1)
print("check_rnav_package: strict reading, writing and the command line as documented")
