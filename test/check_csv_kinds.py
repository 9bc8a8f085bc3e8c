#!/usr/bin/python3
"""ctest python.csv_kinds: every kind of CSV the project writes loads as it is into Python.

Each kind is made by the command a user runs (small sizes): a landing-radar and an azimuth-only
ensemble, one with the data link, an LCM log turned into CSV, a flight exported for the
diagnosis and diagnosed with --plots, the independent generator's three kinds of flight, an Autoferry recording imported (multi-sensor and EO
bearings) and diagnosed with --plots, an ADS-B approach as a replay CSV, a sweep and a code
study. Every CSV found under the outputs must be a kind listed below, and every listed kind must
have been made (a kind that stops being written, or a new one without a load test, fails). Then
for each file:
  * numpy.genfromtxt(names=True) gives exactly the header's names (numpy changes names that are
    not plain: spaces, brackets, commas, a leading digit);
  * pandas.read_csv gives the same names, and the same numbers in every numeric column (read
    with float_precision="round_trip": the writers print shortest round-trip or %.Ng text);
  * rnav.read_csv reads it strictly, with its units.json (keys = the header, in order; every
    meaning non-empty);
  * rnav.read_run / read_sweep / read_log open the folders and the log;
  * every file a landing-radar, azimuth-only and data-link run writes (plots included) is named
    in the README's table of outputs.
Usage: PYTHONPATH=SOURCE_DIR/scripts check_csv_kinds.py SOURCE_DIR BUILD_DIR DATA_DIR (ctest sets
PYTHONPATH)
"""
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import pandas as pd
import rnav

SRC, BUILD, DATA = (os.path.abspath(a) for a in sys.argv[1:4])

BIN = os.path.join(BUILD, "bin")
ENV = dict(os.environ, RNAV_BUILD=BUILD, PYTHONPATH=os.path.join(SRC, "scripts"))

# The kinds: (path pattern relative to the outputs, what writes it).
KINDS = [
    ("paper/realizations.csv", "landing-radar logger: per realization and range bin"),
    ("paper/stats_time.csv", "landing-radar logger: statistics over time"),
    ("paper/stats_range.csv", "landing-radar logger: statistics per range bin"),
    ("logged/*.csv", "the same kinds from a run over LCM (separate processes)"),
    ("link/datalink.csv", "data link: messages sent and lost per realization"),
    ("link/*.csv", "the landing-radar kinds of a run with the data link"),
    ("uav/realizations.csv", "azimuth-only logger: per realization and time"),
    ("uav/track.csv", "azimuth-only logger: one realization's track"),
    ("uav/uav_stats_time.csv", "azimuth-only logger: statistics over time"),
    ("logcsv/*.csv", "rnav_log2csv: one per LCM channel"),
    ("flight/radar.csv", "rnav_export_prl: radar plots"),
    ("flight/nav.csv", "rnav_export_prl: nav solution"),
    ("flight/truth.csv", "rnav_export_prl: aircraft truth"),
    ("diag/residuals.csv", "scripts/diagnose prl --plots: residuals"),
    ("af4/observer.csv", "rnav_import_autoferry: own ship"),
    ("af4/detections.csv", "rnav_import_autoferry: detections"),
    ("af4/truth.csv", "rnav_import_autoferry: targets' GNSS"),
    ("af4eo/observer.csv", "rnav_import_autoferry --sensor eo: own ship"),
    ("af4eo/bearings.csv", "rnav_import_autoferry --sensor eo: bearings"),
    ("af4eo/truth.csv", "rnav_import_autoferry --sensor eo: target truth"),
    ("multidiag/residuals*.csv", "scripts/diagnose multi --plots: residuals"),
    ("replay.csv", "rnav_import_adsb --approach: replay trajectory"),
    ("sweep/sweep.csv", "scripts/sweep: one row per setting"),
    ("fg_landing/*.csv", "scripts/flightgen.py landing: radar, nav, truth"),
    ("fg_uav/*.csv", "scripts/flightgen.py uav: observer, bearings, truth"),
    ("fg_shipradar/*.csv", "scripts/flightgen.py shipradar: observer, detections, truth"),
    ("codes/codes.csv", "scripts/code_study: one row per code"),
    ("codes/spectrum.csv", "scripts/code_study: family-mean spectra"),
]


def run(argv, cwd=None):
    p = subprocess.run(argv, cwd=cwd or SRC, env=ENV, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        sys.exit("FAIL: %s exited %d:\n%s" % (" ".join(argv), p.returncode, p.stdout[-3000:]))
    return p.stdout


def make(T):
    run(["scripts/run", "paper", "--realizations", "2", "--seed", "1", "--inproc", "--out", T + "/paper"])
    run(["scripts/run", "paper", "--realizations", "2", "--seed", "1", "--inproc", "--no-plots",
         "--set", "datalink.enabled=true", "--set", "datalink.peak_power_w=0.03", "--out", T + "/link"])
    run(["scripts/run", "uav", "--realizations", "2", "--seed", "1", "--inproc", "--out", T + "/uav"])
    run(["scripts/run", "paper", "--realizations", "1", "--seed", "1", "--no-plots", "--lcm-log", T + "/run.lcmlog",
         "--out", T + "/logged"])
    run(["scripts/rnav_log2csv", T + "/run.lcmlog", "--out", T + "/logcsv"])
    run([BIN + "/rnav_export_prl", "--scenario", "sim/scenarios/paper.json", "--seed", "5", "--out", T + "/flight"])
    run(["scripts/diagnose", "prl", T + "/flight", "--injections", "0", "--plots", T + "/diag"])
    af = os.path.join(DATA, "autoferry", "scenario4")
    run([BIN + "/rnav_import_autoferry", af, "--out", T + "/af4"])
    run([BIN + "/rnav_import_autoferry", af, "--sensor", "eo", "--target", "1", "--out", T + "/af4eo"])
    run(["scripts/diagnose", "multi", T + "/af4", "--plots", T + "/multidiag"])
    run([BIN + "/rnav_import_adsb", os.path.join(DATA, "adsb", "vienna.json.gz"), "--approach", "1", "--out", T + "/replay.csv"])
    run(["scripts/sweep", "paper", "--grid", "prl.period_s=1,2", "--realizations", "2", "--seed", "1", "--out", T + "/sweep"])
    for mode in ("landing", "uav", "shipradar"):
        run(["/usr/bin/python3", "scripts/flightgen.py", mode, T + "/fg_" + mode, "--seed", "1",
             "--set", "duration_s=600"] if mode == "shipradar" else
            ["/usr/bin/python3", "scripts/flightgen.py", mode, T + "/fg_" + mode, "--seed", "1"])
    run(["/usr/bin/python3", "scripts/code_study", "--lengths", "127", "--codes", "4", "--partners", "2", "--no-plots",
         "--out", T + "/codes"])


def readme_outputs():
    """The first-column names of the README's table of what a run writes ('logs/', '*.units.json')."""
    with open(os.path.join(SRC, "README.md"), encoding="utf-8") as f:
        text = f.read()
    section = text.split("## What a run writes", 1)[1].split("\n## ", 1)[0]
    names = []
    for line in section.splitlines():
        if line.startswith("| `"):
            names += re.findall(r"`([^`]+)`", line.split("|")[1])
    return names


def check_listed(folder, names, bad):
    """Every file and folder a run wrote is named in the README's table."""
    import fnmatch
    for n in sorted(os.listdir(folder)):
        key = n + "/" if os.path.isdir(os.path.join(folder, n)) else n
        if not any(fnmatch.fnmatch(key, pat) for pat in names):
            bad.append("%s: the run wrote %s, which the README's table of outputs does not list" % (folder, key))


def header(path):
    with open(path, encoding="utf-8") as f:
        return f.readline().rstrip("\n").split(",")


def check_file(path, bad):
    names = header(path)
    try:
        a = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    except ValueError as e:
        bad.append("%s: numpy.genfromtxt: %s" % (path, " ".join(str(e).split())[:200]))
        return
    if list(a.dtype.names) != names:
        bad.append("%s: numpy names %s, header %s" % (path, list(a.dtype.names), names))
    f = pd.read_csv(path, float_precision="round_trip")
    if list(f.columns) != names:
        bad.append("%s: pandas columns %s, header %s" % (path, list(f.columns), names))
    try:
        t = rnav.read_csv(path)
    except rnav.CsvError as e:
        bad.append(str(e))
        return
    if not t.units and not t.meanings:
        bad.append("%s: no units.json beside it" % path)
    for c in names:
        if not t.meanings.get(c):
            bad.append("%s: column %s has no meaning in its units.json" % (path, c))
            break
    for c in names:
        x = t[c]
        if x.dtype.kind in "if" and pd.api.types.is_numeric_dtype(f[c]):
            if not np.array_equal(np.asarray(f[c], dtype=float), x.astype(float), equal_nan=True):
                bad.append("%s: column %s: pandas and rnav.read_csv differ" % (path, c))
        elif x.dtype.kind in "if":
            bad.append("%s: column %s: numbers for rnav, %s for pandas" % (path, c, f[c].dtype))


def main():
    T = tempfile.mkdtemp(prefix="csv_kinds.")
    try:
        make(T)
        found = sorted(os.path.relpath(p, T) for p in glob.glob(T + "/**/*.csv", recursive=True)
                       if "/settings/" not in p and "/job" not in p)
        bad = []
        import fnmatch
        for pat, what in KINDS:
            if not any(fnmatch.fnmatch(p, pat) for p in found):
                bad.append("no %s (%s) was written" % (pat, what))
        for p in found:
            if not any(fnmatch.fnmatch(p, pat) for pat, _ in KINDS):
                bad.append("%s: a CSV kind this test does not know: add it to KINDS" % p)
            check_file(os.path.join(T, p), bad)
        names = readme_outputs()
        for run_dir in ("paper", "uav", "link"):
            check_listed(os.path.join(T, run_dir), names, bad)
        # the folders and the log through the package
        try:
            run_ = rnav.read_run(T + "/paper")
            if run_["stats_time"].units.get("apoi_rms_x_m") != "m":
                bad.append("read_run: stats_time apoi_rms_x_m unit %r, not 'm'" % run_["stats_time"].units.get("apoi_rms_x_m"))
            if "table2" not in run_.json:
                bad.append("read_run: no table2 among the JSON outputs %s" % sorted(run_.json))
            sw = rnav.read_sweep(T + "/sweep")
            if sw.n_rows != 2 or sorted(sw["prl_period_s"] if "prl_period_s" in sw else sw[sw.columns[0]]) != [1, 2]:
                bad.append("read_sweep: %d rows, first column %s" % (sw.n_rows, sw[sw.columns[0]]))
            log = rnav.read_log(T + "/run.lcmlog")
            apoi = rnav.read_csv(T + "/logcsv/PRL_APOI.csv")
            if not np.array_equal(log["PRL_APOI"]["range_m"], apoi["range_m"]):
                bad.append("read_log and the log's CSV differ on PRL_APOI range_m")
            if log["PRL_APOI"].units.get("range_m") != "m" or not log["PRL_APOI"].meanings.get("range_m"):
                bad.append("read_log: PRL_APOI range_m unit/meaning %r/%r" % (log["PRL_APOI"].units.get("range_m"),
                                                                              log["PRL_APOI"].meanings.get("range_m")))
        except (rnav.CsvError, rnav.LogError, KeyError) as e:
            bad.append("the package: %s: %s" % (type(e).__name__, e))
        if bad:
            print("FAIL:\n  " + "\n  ".join(bad))
            return 1
        print("check_csv_kinds: %d CSV files of %d kinds load with numpy, pandas and rnav" % (len(found), len(KINDS)))
        return 0
    finally:
        shutil.rmtree(T, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
