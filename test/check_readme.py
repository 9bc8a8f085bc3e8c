#!/usr/bin/env python3
"""ctest readme.EXAMPLE (one test per example): the examples of the README and of docs/ run as written and give the
figures they quote.

The documentation is README.md and every docs/*.md page. Each example below is found by the
first line of its command block (an indented block), searched in each of those files; it must be
in exactly one of them, and its block and the prose read after it never reach past the end of
that file. Its commands are taken from the documentation, not from this file, so an edited
command is the one that runs. Two rewrites only, so that parallel tests cannot collide: `/tmp/`
and a leading `out/` become folders of this test's own scratch directory. The figures are read
from the prose and tables after the example by the patterns below and compared with what the
commands wrote: a figure quoted with d decimals matches if it is the value rounded to d decimals
(|value - quoted| <= 0.5e-d, plus 1e-9 for the decimal representation). A documentation edit
that changes a figure without the code, or the code without the documentation, fails here,
naming the figure and the file that quotes it.

Usage: check_readme.py SOURCE_DIR BUILD_DIR [EXAMPLE...]   (no EXAMPLE: all of them)
       check_readme.py --list                                (the examples' names, one a line)

ctest runs each example as a test of its own, readme.EXAMPLE (test/CMakeLists.txt asks --list at
configure time), so that ctest -j2 runs them beside the other tests instead of one after another.
"""
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

LIST = sys.argv[1:] == ["--list"]
if not LIST and len(sys.argv) < 3:
    raise SystemExit("usage: check_readme.py SOURCE_DIR BUILD_DIR [EXAMPLE...] | --list")
SRC, BUILD = (None, None) if LIST else (sys.argv[1], sys.argv[2])
ONLY = [] if LIST else sys.argv[3:]
# The documentation, file by file: (path relative to SRC, text). Each file is searched on its own,
# so a block and the prose after it never cross from one file into the next.
DOCS = [] if LIST else [(name, open(os.path.join(SRC, name), encoding="utf-8").read())
                        for name in ["README.md"] + sorted(os.path.relpath(p, SRC)
                                                           for p in glob.glob(os.path.join(SRC, "docs", "*.md")))]
WHERE = "the documentation"  # the file the current example was found in (named in messages)
FAILS = []


def fail(what):
    FAILS.append(what)
    print("FAIL: " + what, flush=True)


def locate(needle, what):
    """The file holding `needle` (exactly one of README.md and docs/*.md), its text and the index;
    the file becomes WHERE, named in this example's messages."""
    global WHERE
    hits = [(name, text, text.find(needle)) for name, text in DOCS if needle in text]
    if not hits:
        raise SystemExit("check_readme: the documentation (README.md, docs/*.md) no longer has the "
                         "example %s (update test/check_readme.py with it)" % what)
    if len(hits) > 1:
        raise SystemExit("check_readme: the example %s is in %s; keep it in one file (or make "
                         "test/check_readme.py tell them apart)" % (what, " and ".join(h[0] for h in hits)))
    WHERE = hits[0][0]
    return hits[0][1], hits[0][2]


def section(heading):
    """The text of the file whose heading (any level) starts with `heading`, from that heading to
    the end of the file."""
    global WHERE
    pattern = r"^#+ " + re.escape(heading)
    hits = [(name, text, m.start()) for name, text in DOCS for m in [re.search(pattern, text, re.M)] if m]
    if len(hits) != 1:
        raise SystemExit("check_readme: %s heading starting '%s' (README.md, docs/*.md); "
                         "update test/check_readme.py" % ("no" if not hits else "more than one", heading))
    WHERE = hits[0][0]
    return hits[0][1][hits[0][2]:]


def block_after(first_line):
    """The indented command block starting with `first_line` and the text of its file after it."""
    text, i = locate("\n    " + first_line, "'%s'" % first_line)
    lines, rest = [], text[i + 1:]
    while rest.startswith("    ") or rest.startswith("\n    "):
        line, _, rest = rest.lstrip("\n").partition("\n")
        lines.append(line[4:])
        if not rest.startswith("    ") and not rest.startswith("\n    "):
            break
    return lines, rest


def commands(lines):
    """Shell commands of a block, backslash continuations joined."""
    out, cur = [], ""
    for line in lines:
        if line.endswith("\\"):
            cur += line[:-1] + " "
        else:
            out.append(cur + line)
            cur = ""
    return out


def localize(cmd, tmp):
    cmd = cmd.replace("/tmp/", tmp + "/")
    return re.sub(r"(?<=\s)out/", tmp + "/out/", cmd)


# [s] One command's limit: five times the longest example's command on a loaded 2-core machine
# (readme.autoferry_pooled, ~190 s with another test beside it), and below ctest's 900 s, so that
# a command that hangs is named here with what it left, not by ctest's bare "Timeout".
COMMAND_TIMEOUT_S = 600


def processes(pgid):
    """ps of a process group: the processes a command started that are still alive."""
    return subprocess.run(["ps", "-o", "pid,ppid,stat,etime,args", "-g", str(pgid)],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True).stdout


def hang_report(cmd, tmp, ps, out, err):
    """What a command that ran past COMMAND_TIMEOUT_S left: its processes still alive (`ps`), the
    tails of its output and of the run logs in the scratch folder."""
    logs = ""
    for log in sorted(glob.glob(os.path.join(tmp, "**", "logs", "*.log"), recursive=True)):
        tail = open(log, errors="replace").read().splitlines()[-5:]
        logs += "\n  %s:\n    %s" % (os.path.relpath(log, tmp), "\n    ".join(tail))
    return ("'%s' did not finish within %d s (COMMAND_TIMEOUT_S); its processes then:\n%s"
            "its stdout ended: %s\nits stderr ended: %s\nlogs:%s"
            % (cmd, COMMAND_TIMEOUT_S, ps, out[-600:], err[-1500:], logs or " none"))


def run(cmd, tmp, what):
    """The command's CompletedProcess; one that runs past COMMAND_TIMEOUT_S is killed with every
    process it started (its own process group: a process still holding the output pipes would
    keep the read waiting) and fails the example with hang_report's account."""
    # the package of this checkout (scripts/setup's rnav.pth names the last checkout set up)
    env = dict(os.environ, RNAV_BUILD=BUILD, PYTHONPATH=os.path.join(os.path.abspath(SRC), "scripts"))
    p = subprocess.Popen(["bash", "-c", localize(cmd, tmp)], cwd=SRC, env=env, stdin=subprocess.DEVNULL,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = p.communicate(timeout=COMMAND_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        ps = processes(p.pid)
        os.killpg(p.pid, 9)
        out, err = p.communicate()
        fail("%s (%s): %s" % (what, WHERE, hang_report(cmd, tmp, ps, out, err)))
        raise RuntimeError(what)
    return subprocess.CompletedProcess(p.args, p.returncode, out, err)


def run_ok(cmd, tmp, what):
    r = run(cmd, tmp, what)
    if r.returncode != 0:
        fail("%s (%s): '%s' exited %d: %s" % (what, WHERE, cmd, r.returncode, r.stderr.strip()[-600:]))
        raise RuntimeError(what)
    return r.stdout


def number(text):
    """A quoted figure: its value and the half-width of its last decimal."""
    t = text.replace("−", "-").replace(" ", "")
    decimals = len(t.split(".")[1]) if "." in t else 0
    return float(t), 0.5 * 10 ** -decimals + 1e-9


def agree(what, quoted, value, scale=1.0):
    q, tol = number(quoted)
    if abs(value / scale - q) > tol:
        fail("%s: %s quotes %s, the run gives %.10g" % (what, WHERE, quoted, value / scale))


def find(pattern, text, what, flags=0):
    m = re.search(pattern, text, flags)
    if not m:
        raise SystemExit("check_readme: the wording for %s in %s changed (pattern %r); "
                         "update test/check_readme.py" % (what, WHERE, pattern))
    return m


def effect(report, name):
    for e in report["effects"]:
        if e["name"] == name:
            return e
    return None


# ---- the examples ----

def ex_errors(tmp):
    """'$ command' lines followed by the error they print ('...' stands for any text)."""
    lines, _ = block_after("$ scripts/run pape")
    i = 0
    while i < len(lines):
        cmd = lines[i][2:]
        expected = []
        i += 1
        while i < len(lines) and not lines[i].startswith("$ "):
            expected.append(lines[i])
            i += 1
        r = run(cmd, tmp, cmd)
        got = (r.stdout + r.stderr).strip().splitlines()
        pattern = "^" + ".*".join(re.escape(p) for p in "\n".join(expected).split("...")) + "$"
        if r.returncode == 0 or not re.match(pattern, "\n".join(got), re.S):
            fail("'%s' prints %r (exit %d); %s shows %r" % (cmd, got, r.returncode, WHERE, expected))


def ex_table2(tmp):
    results = section("Results: the paper scenario")
    cmd = find(r"`(scripts/run paper [^`]*)`", results, "Table 2's command").group(1)
    run_ok(cmd, tmp, "Table 2")
    out = find(r"--out (\S+)", cmd, "Table 2's --out").group(1)
    d = json.load(open(os.path.join(localize(" " + out, tmp).strip(), "table2_detail.json")))
    if "| range from threshold" not in results:
        raise SystemExit("check_readme: Table 2 ('| range from threshold') is no longer under its "
                         "heading in %s; update test/check_readme.py" % WHERE)
    table = results[results.index("| range from threshold"):]
    table = table[:table.index("\n\n")]  # the first table of the section: Table 2
    rows = re.findall(r"^\| (\d+) km +\| (APOI|TOI) +\| ([^|]+)\| ([^|]+)\| ([^|]+)\|", table, re.M)
    if len(rows) != 4:
        raise SystemExit("check_readme: expected 4 rows of Table 2 in %s, found %d" % (WHERE, len(rows)))
    for km, row, *cells in rows:
        b = d[row][str(int(km) * 1000)]
        for axis, cell in enumerate(cells):
            mean, band = cell.split("±")
            what = "Table 2 %s km %s %s" % (km, row, "XZY"[axis])
            agree(what + " mean", mean, b["mean"][axis])
            agree(what + " 95 % band", band, b["band95_halfwidth"][axis])


def ex_diagnose_csv(tmp):
    lines, after = block_after("build/bin/rnav_export_prl --scenario sim/scenarios/paper.json --seed 5")
    text = ""
    for c in commands(lines):
        text += run_ok(c, tmp, "the diagnosis example")
    rep = json.load(open(tmp + "/flight.json"))
    m = find(r"finds `time_offset` ([\d.]+) ± ([\d.]+) s", after, "the time offset")
    e = effect(rep, "time_offset")
    if e is None:
        fail("diagnosis example: time_offset not named")
    else:
        agree("time_offset", m.group(1), e["estimate"])
        agree("time_offset SE", m.group(2), e["stderr"])
    m = find(r"`elevation_refraction` \(([\d.]+) ± ([\d.]+)\)·10⁻⁴ rad", after, "the refraction")
    e = effect(rep, "elevation_refraction")
    if e is None:
        fail("diagnosis example: elevation_refraction not named")
    else:
        agree("elevation_refraction [1e-4 rad]", m.group(1), e["estimate"], 1e-4)
        agree("elevation_refraction SE [1e-4 rad]", m.group(2), e["stderr"], 1e-4)
    m = find(r"`(k_deg=[\d.]+ \+- [\d.]+)`", after, "the text report's k_deg")
    if m.group(1) not in text:
        fail("diagnosis example: the text report does not show '%s'" % m.group(1))
    m = find(r"from ([\d.]+) m to ([\d.]+) m RMS", after, "the out-of-sample gain")
    g = find(r"gain truth_position_m: RMS ([\d.]+) -> ([\d.]+) m", text, "the report's truth gain")
    agree("truth position RMS, nominal", m.group(1), float(g.group(1)))
    agree("truth position RMS, extended", m.group(2), float(g.group(2)))


def ex_diagnose_log(tmp):
    lines, after = block_after("scripts/run paper --realizations 2 --set prl_effects.range_gain=0.002")
    text = ""
    for c in commands(lines):
        text += run_ok(c, tmp, "the LCM log example")
    m = find(r"names `(\w+)` ([−\-\d.]+) ± ([\d.]+) \(the [\d.]+ hidden\) and lists `(\w+)` as\s+"
             r"`confounded_with`", after, "the LCM log example's finding")
    f = find(r"EFFECT +%s: g=(\S+) \+- (\S+) .*confounded with (.*)" % m.group(1), text,
             "the named effect in the report")
    agree(m.group(1), m.group(2), float(f.group(1)))
    agree(m.group(1) + " SE", m.group(3), float(f.group(2)))
    if m.group(4) not in f.group(3):
        fail("LCM log example: %s is not listed as confounded with %s (%s)" % (m.group(1), m.group(4), f.group(3)))


def ex_autoferry(tmp):
    lines, after = block_after("build/bin/rnav_import_autoferry test/data/autoferry/scenario4")
    for c in commands(lines):
        run_ok(c, tmp, "the Autoferry example")
    rep = json.load(open(tmp + "/out/af4.json"))
    row = [c.strip() for c in find(r"^\| 4 \| ([^|]+)\| ([^|]+)\| ([^|]+)\| ([^|]+)\|", after, "scenario 4's row", re.M).groups()]
    # The row as scripts/autoferry_study --multi words it (the documentation says it regenerates the table).
    mean = [e for e in rep["effects"] if e["name"] not in ("noise_scale", "correlated_noise", "outliers", "target_maneuver")]
    scope = lambda e: ":".join(x for x in (e["scope"]["sensor"], e["scope"]["target"]) if x) or "common"
    named = ", ".join("%s[%s]" % (e["name"], scope(e)) for e in mean) or "–"
    clock = next((q["supported"] for q in rep["scope_support"] if q["question"].startswith("which clock")), "–")
    rc = next((e for e in mean if e["name"] == "time_offset" and e["scope"]["sensor"] == "radar"), None)
    radar = "%.2f ± %.2f" % (rc["estimate"], rc["stderr"]) if rc else "—"
    for what, quoted, got in (("named effects", row[0], named), ("clock question", row[1], clock),
                              ("radar time_offset", row[2], radar)):
        if quoted != got:
            fail("Autoferry scenario 4, %s: %s shows '%s', the diagnosis gives '%s'" % (what, WHERE, quoted, got))
    quoted_gain = dict(p.strip().split(" ", 1) for p in row[3].split(","))
    for k in sorted(rep["gain"]):
        g = rep["gain"][k]
        if g["n"] < 5:
            continue
        if k not in quoted_gain:
            fail("Autoferry scenario 4: held-out channel %s is missing from the row in %s" % (k, WHERE))
            continue
        before, after_ = quoted_gain.pop(k).split("→")
        agree("Autoferry scenario 4 %s nominal RMS" % k, before, g["nominal_rms"])
        agree("Autoferry scenario 4 %s extended RMS" % k, after_, g["extended_rms"])
    for k in quoted_gain:
        fail("Autoferry scenario 4: %s quotes held-out channel %s, the diagnosis has none" % (WHERE, k))


def ex_autoferry_pooled(tmp):
    """The pooled diagnosis of the nine recordings: the documentation quotes the study's hardware
    table rows and its leave-one-out summary line as the study prints them."""
    lines, after = block_after("scripts/autoferry_study --pooled --out out/autoferry")
    printed = "".join(run_ok(c, tmp, "the pooled Autoferry example") for c in commands(lines))
    # up to the next recording-at-a-time heading (any level), or the end of the file
    m = re.search(r"^#+ One recording at a time", after, re.M)
    section = after[:m.start()] if m else after
    hardware = [l for l in printed.splitlines() if l.startswith("| ") and " | " in l and l.count("|") == 6
                and not l.startswith("| effect") and not l.startswith("|---")]
    if not hardware:
        fail("pooled Autoferry example: the study printed no hardware row")
    for row in hardware:
        if row not in section:
            fail("pooled Autoferry example: %s lacks the hardware row '%s'" % (WHERE, row))
    # the carried shares: the rows of the table after "Carried to a new recording"
    lines_out = printed.splitlines()
    start = next((i for i, l in enumerate(lines_out) if l.startswith("Carried to a new recording")), None)
    if start is None:
        fail("pooled Autoferry example: the study printed no carried shares")
    else:
        carried = []
        for l in lines_out[start + 1:]:
            if l.startswith("| ") and not l.startswith("| effect"):
                carried.append(l)
            elif carried and not l.startswith("|"):
                break
        if not carried:
            fail("pooled Autoferry example: the study's carried-shares table is empty")
        for row in carried:
            if row not in section:
                fail("pooled Autoferry example: %s lacks the carried row '%s'" % (WHERE, row))
    summary = next((l for l in printed.splitlines() if "pairs with >= 5 detections" in l), None)
    if summary is None or summary not in section:
        fail("pooled Autoferry example: %s lacks the leave-one-out summary '%s'" % (WHERE, summary))


def ex_replay(tmp):
    """No figures quoted: the commands run and the replay writes its log."""
    lines, _ = block_after("scripts/run paper --realizations 3 --lcm-log /tmp/run.lcmlog")
    for c in commands(lines):
        run_ok(c, tmp, "the replay example")
    if not os.path.getsize(tmp + "/free.lcmlog"):
        fail("the replay example wrote an empty log")


def ex_python(tmp):
    """The Python example prints what the documentation quotes; rnav_log2csv writes as many rows."""
    lines, after = block_after("scripts/run paper --realizations 2 --seed 1 --lcm-log /tmp/run.lcmlog")
    out = [run_ok(c, tmp, "the Python example") for c in commands(lines)]
    printed = next((o.strip() for c, o in zip(commands(lines), out) if "python3" in c), "")
    quoted = find(r"prints `([^`]*)`", after, "the Python example's output").group(1)
    if printed != quoted:
        fail("Python example: %s quotes '%s', it prints '%s'" % (WHERE, quoted, printed))
    rows = sum(1 for _ in open(tmp + "/run_csv/PRL_BIAS.csv")) - 1
    if str(rows) != quoted.split()[0]:
        fail("Python example: rnav_log2csv wrote %d PRL_BIAS rows, %s quotes %s" % (rows, WHERE, quoted.split()[0]))
    # its CSVs load with numpy by their header's names, the units beside them
    import numpy
    a = numpy.genfromtxt(tmp + "/run_csv/PRL_BIAS.csv", delimiter=",", names=True)
    units = json.load(open(tmp + "/run_csv/PRL_BIAS.units.json"))
    if a.shape != (rows,) or "eta_0" not in a.dtype.names or units.get("eta_0", {}).get("unit") != "m" \
            or list(units) != list(a.dtype.names):
        fail("Python example: numpy.genfromtxt(names=True) reads PRL_BIAS.csv as %s rows, columns %s; units %s"
             % (a.shape, a.dtype.names[:4], list(units.items())[:4]))


def ex_python_run(tmp):
    """The run folder through rnav.read_run, and python3 -m rnav show: what the page quotes."""
    lines, _ = block_after("scripts/run paper --realizations 2 --seed 1 --lcm-log /tmp/run.lcmlog")
    run_ok(commands(lines)[0], tmp, "the Python run example")
    lines, after = block_after("/usr/bin/python3 -c \"import rnav; r = rnav.read_run('/tmp/run2')")
    printed = run_ok(commands(lines)[0], tmp, "the read_run example").strip()
    quoted = find(r"prints `([^`]*)`", after, "the read_run example's output").group(1)
    if printed != quoted:
        fail("read_run example: %s quotes '%s', it prints '%s'" % (WHERE, quoted, printed))
    lines, after = block_after("/usr/bin/python3 -m rnav show /tmp/run2")
    printed = run_ok(commands(lines)[0], tmp, "the rnav show example").strip().splitlines()
    quoted_lines, _ = block_after(printed[0] if printed else "(nothing printed)")
    if printed != quoted_lines:
        fail("rnav show example: %s quotes %s, it prints %s" % (WHERE, quoted_lines, printed))


def ex_shards(tmp):
    """Shards run with --first-realization and joined by rnav_merge equal one run (the block's
    last command compares them with cmp, so run_ok fails on a difference)."""
    lines, _ = block_after("scripts/run paper --inproc --realizations 200 --first-realization 0")
    cmds = commands(lines)
    if not any(c.startswith("cmp ") for c in cmds):
        fail("the shards example in %s no longer compares the merged and the whole run" % WHERE)
    for c in cmds:
        run_ok(c, tmp, "the shards example")


UAV_TABLE_RUNS = 3  # the commands of each UAV estimator table's block: one ctest test each


# The particle filter's table quotes runs of 200 realizations (about 40 s of CPU each, the suite's
# longest tests when each ran in full). The suite checks its rows against a record of those runs
# instead (test/data/uav_pf/OUT: their summary.json, and the rows of realizations.csv at the
# evaluation time), and runs each command with RECORD_SAMPLE realizations: their rows must equal
# the record's first RECORD_SAMPLE byte for byte (a realization's numbers do not depend on how
# many are run: its random streams are (seed, realization)'s), and the record's summary must agree
# with its own rows (RMSE, mean NEES, runs). test/data/uav_pf/README.md says how it is made.
RECORD_SAMPLE = 20
RECORD_AGREE = 1e-8  # relative: the summary against the rows' 9-significant-digit text


def eval_rows(path, below=None):
    """The header and the rows at the evaluation time (at_eval 1) of a realizations.csv, those of
    realizations below `below` only when given; each row as its text."""
    with open(path) as f:
        header = f.readline()
        cols = header.rstrip("\n").split(",")
        ia, ir = cols.index("at_eval"), cols.index("realization")
        rows = [l for l in f if l.split(",")[ia] == "1" and (below is None or int(l.split(",")[ir]) < below)]
    return header, rows


def check_record(record, n_full, fresh_csv, what):
    """The record of a full run (test/data/uav_pf/OUT) against its own rows, and the fresh sample
    run's rows against the record's first RECORD_SAMPLE realizations; its summary returned."""
    summary = json.load(open(os.path.join(record, "summary.json")))
    header, rows = eval_rows(os.path.join(record, "eval_rows.csv"))
    cols = header.rstrip("\n").split(",")
    ie, ip, inn = cols.index("estimator"), cols.index("pos_err_m"), cols.index("nees")
    if summary["realizations"] != n_full:
        fail("%s: the record %s has %d realizations, the command runs %d" % (what, record, summary["realizations"], n_full))
    for name, e in summary["estimators"].items():
        mine = [r.split(",") for r in rows if r.split(",")[ie] == name]
        if len(mine) != e["runs"] or e["runs"] != n_full:
            fail("%s %s: the record holds %d rows, its summary %d runs of %d" % (what, name, len(mine), e["runs"], n_full))
            continue
        rmse = (sum(float(r[ip]) ** 2 for r in mine) / len(mine)) ** 0.5
        nees = sum(float(r[inn]) for r in mine) / len(mine)
        for field, got in (("rmse_pos_m", rmse), ("nees_mean", nees)):
            if abs(got / e[field] - 1) > RECORD_AGREE:
                fail("%s %s: the record's summary says %s %.10g, its rows give %.10g" % (what, name, field, e[field], got))
    fresh_header, fresh = eval_rows(fresh_csv)
    _, first = eval_rows(os.path.join(record, "eval_rows.csv"), RECORD_SAMPLE)
    if fresh_header != header or fresh != first or len(first) != RECORD_SAMPLE * len(summary["estimators"]):
        diff = next((i for i, (a, b) in enumerate(zip(fresh, first)) if a != b), min(len(fresh), len(first)))
        fail("%s: the first %d realizations no longer give the recorded rows (%s; first difference at row %d: "
             "%s); run the block's commands and renew %s (its README)"
             % (what, RECORD_SAMPLE, "header differs" if fresh_header != header else "%d rows, %d recorded"
                % (len(fresh), len(first)), diff, (fresh[diff:diff + 1] or ["none"])[0].strip()[:200], record))
    return summary


def uav_estimator_table(tmp, first_command, what, part, record=None):
    """A documentation table of UAV estimators: its block's command number `part` (1-based) runs,
    and every row naming that command's --out is checked against the summary.json it wrote (with
    `record`, a folder of records of full runs: the command runs RECORD_SAMPLE realizations, and
    the rows are checked against the record's summary: check_record). The block must hold
    UAV_TABLE_RUNS commands and every row must name one of their --out folders, so that the parts
    together run every command and check every row."""
    lines, after = block_after(first_command)
    cmds = commands(lines)
    if len(cmds) != UAV_TABLE_RUNS:
        raise SystemExit("check_readme: the %s block in %s has %d commands, not %d; update UAV_TABLE_RUNS in "
                         "test/check_readme.py" % (what, WHERE, len(cmds), UAV_TABLE_RUNS))
    outs = [find(r"--out (\S+)", c, "the --out of a %s command" % what).group(1) for c in cmds]
    cmd = cmds[part - 1]
    if record:
        n_full = int(find(r"--realizations (\d+)", cmd, "the --realizations of a %s command" % what).group(1))
        cmd = cmd.replace("--realizations %d" % n_full, "--realizations %d" % RECORD_SAMPLE, 1)
    run_ok(cmd, tmp, "%s example, run %d" % (what, part))
    out_dir = os.path.join(tmp, outs[part - 1])
    summary = (check_record(os.path.join(record, os.path.basename(outs[part - 1])), n_full,
                            os.path.join(out_dir, "realizations.csv"), "%s %s" % (what, outs[part - 1]))
               if record else json.load(open(os.path.join(out_dir, "summary.json"))))
    table = after[after.index("| run (`--out`)"):]
    table = table[:table.index("\n\n")]
    rows = re.findall(r"^\| `(out/[^`]+)` \| `(\w+)` \| ([\d.]+) m \| ([\d.]+) \| ([\d. ]+) \((inside|outside)\) "
                      r"\| (\d+) / (\d+) \|$", table, re.M)
    if len(rows) != table.count("\n") - 1:
        raise SystemExit("check_readme: a row of the %s table in %s does not parse; update test/check_readme.py" % (what, WHERE))
    for out, *_ in rows:
        if out not in outs:
            fail("%s table: %s quotes a row of %s, which none of its commands writes" % (what, WHERE, out))
    for out, name, rmse, ratio, nees, inside, diverged, runs in rows:
        if out != outs[part - 1]:
            continue
        e = summary["estimators"][name]
        row = "%s table %s %s" % (what, out, name)
        agree(row + " RMSE", rmse, e["rmse_pos_m"])
        agree(row + " RMSE/PCRB", ratio, e["rmse_pos_over_pcrb"])
        agree(row + " mean NEES", nees, e["nees_mean"])
        if (inside == "inside") != e["nees_within_band"]:
            fail(row + ": %s says NEES %s the band, the run says within_band=%s" % (WHERE, inside, e["nees_within_band"]))
        if int(diverged) != e["diverged"] or int(runs) != e["runs"]:
            fail(row + ": %s quotes %s / %s diverged, the run gives %d / %d" % (WHERE, diverged, runs, e["diverged"], e["runs"]))


def uav_table_part(first_command, what, part, record=None):
    """The example checking part `part` of a UAV estimator table (uav_estimator_table)."""
    return lambda tmp: uav_estimator_table(tmp, first_command, what, part, record)


UAV_ML = "scripts/run uav --inproc --realizations 200 --seed 1 --set 'tma.estimators=[\"ekf\""   # the batch estimator's table
UAV_PF = "scripts/run uav --inproc --realizations 200 --seed 1 --set 'tma.estimators=[\"rpekf\""  # the particle filter's


EXAMPLES = {"errors": ex_errors, "table2": ex_table2, "diagnose_csv": ex_diagnose_csv,
            "diagnose_log": ex_diagnose_log, "autoferry": ex_autoferry,
            "autoferry_pooled": ex_autoferry_pooled,
            "replay": ex_replay, "python": ex_python, "python_run": ex_python_run, "shards": ex_shards}
for k in range(1, UAV_TABLE_RUNS + 1):  # a test per run: each is tens of seconds
    EXAMPLES["uav_ml.%d" % k] = uav_table_part(UAV_ML, "UAV ml", k)
    EXAMPLES["uav_pf.%d" % k] = uav_table_part(UAV_PF, "UAV pf", k, os.path.join(SRC or "", "test", "data", "uav_pf"))

if LIST:
    print("\n".join(EXAMPLES))
    sys.exit(0)
unknown = [x for x in ONLY if x not in EXAMPLES]
if unknown:
    raise SystemExit("check_readme: unknown example(s) %s; the examples are %s" % (", ".join(unknown), ", ".join(EXAMPLES)))
for name, f in EXAMPLES.items():
    if ONLY and name not in ONLY:
        continue
    tmp = tempfile.mkdtemp(prefix="rnav-readme-")
    WHERE = "the documentation"
    try:
        n = len(FAILS)
        try:
            f(tmp)
        except RuntimeError:
            pass
        print("readme: %s %s (%s)" % (name, "ok" if len(FAILS) == n else "FAILED", WHERE), flush=True)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
print("%d failure(s)" % len(FAILS))
sys.exit(1 if FAILS else 0)
