#!/usr/bin/python3
"""ctest python.study_runner: scripts/rnav/study_runner.py, the runner under scripts/sweep and every
study, on small shell jobs whose outcome is known: each job's result in its own folder, kept
results not run again (counted by a file each run appends to), a job of other steps run again,
exit status 2 kept as 'invalid', any other failure named and rerun, the progress lines (counts,
an ETA 'unknown' before the first job ends and above 0 until the last, kept jobs neither counted
nor timed), the same results and progress on 1 and 3 MPI ranks, and a rank killed outright named
with its jobs. Usage: PYTHONPATH=SOURCE_DIR/scripts check_study_runner.py (ctest sets it)
"""
import json
import os
import re
import shutil
import sys
import tempfile

from rnav import study_runner as sr

T = tempfile.mkdtemp()
COUNT = os.path.join(T, "count")


def fail(msg):
    sys.stderr.write("FAIL: %s\n" % msg)
    shutil.rmtree(T, ignore_errors=True)
    sys.exit(1)


def job(i, extra=""):
    # Writes i*i into its folder and appends its name to COUNT (one line per time it ran).
    return sr.Job("j%02d" % i, [["sh", "-c", "echo %d > {dir}/sq; echo j%02d >> %s%s" % (i * i, i, COUNT, extra)]])


def values(results):
    return [open(os.path.join(r.folder, "sq")).read().strip() if r.ok else r.status for r in results]


def runs():
    return open(COUNT).read().split() if os.path.exists(COUNT) else []


def check(cond, msg):
    if not cond:
        fail(msg)


# Local, 2 at once: every job run once, its result in its folder, order kept.
jobs = [job(i) for i in range(7)]
out = os.path.join(T, "local")
res = sr.run(jobs, out, parallel=2)
check(values(res) == [str(i * i) for i in range(7)], "local results %s" % values(res))
check(sorted(runs()) == ["j%02d" % i for i in range(7)], "each job once: %s" % runs())
check(sr.summary(res) == "7 jobs: 7 run, 0 from an earlier run, 0 failed", sr.summary(res))

# Rerun: all kept, nothing runs; a job with other steps and a job without its marker run again.
os.remove(COUNT)
res = sr.run(jobs, out)
check(runs() == [] and all(r.reused for r in res), "a rerun ran %s" % runs())
os.remove(os.path.join(out, "j03", "job.json"))
jobs[5] = job(5, "; true")
res = sr.run(jobs, out)
check(sorted(runs()) == ["j03", "j05"], "expected j03 and j05 rerun, got %s" % runs())
check(values(res) == [str(i * i) for i in range(7)], "after resume %s" % values(res))

# Exit 2 is kept as invalid input (not rerun); exit 3 and a signal are failures, named, rerun.
os.remove(COUNT)
bad = [sr.Job("inv", [["sh", "-c", "echo 'x: error: radar.x_m out of range' >&2; exit 2"]]),
       sr.Job("crash", [["sh", "-c", "echo ran >> %s; echo 'y: error: disk full' >&2; exit 3" % COUNT]]),
       sr.Job("sig", [["sh", "-c", "kill -SEGV $$"]]),
       sr.Job("second", [["true"], ["sh", "-c", "exit 4"], ["sh", "-c", "echo never >> %s" % COUNT]])]
res = sr.run(bad, os.path.join(T, "bad"))
st = {r.name: (r.status, r.message) for r in res}
check(st["inv"] == ("invalid", "x: error: radar.x_m out of range"), st["inv"])
check(st["crash"] == ("failed", "sh: exit status 3: y: error: disk full"), st["crash"])
check(st["sig"][0] == "failed" and "signal 11" in st["sig"][1], st["sig"])
check(st["second"][0] == "failed" and "exit status 4" in st["second"][1], "a failed step stops its job: %s" % (st["second"],))
check(runs() == ["ran"], "the step after a failed one ran: %s" % runs())
# The outcome as numbers: the failing step's exit status (-N for signal N) and its error line.
codes = {r.name: (r.exit_code, r.error) for r in res}
check(codes["inv"] == (2, "x: error: radar.x_m out of range"), codes["inv"])
check(codes["crash"] == (3, "y: error: disk full"), codes["crash"])
check(codes["sig"][0] == -11 and codes["second"][0] == 4, codes)
nostart = sr.run([sr.Job("nostart", [["/nonexistent/prog"]])], os.path.join(T, "nostart"))[0]
check(nostart.status == "failed" and nostart.exit_code is None and "cannot start /nonexistent/prog" in nostart.error
      and nostart.message.startswith("prog: exit status 127: cannot start"), (nostart.exit_code, nostart.message))
check(len(sr.failures(res)) == 3 and sr.failures(res)[0].startswith("crash: "), sr.failures(res))
res = sr.run(bad, os.path.join(T, "bad"))
check([r.reused for r in res] == [True, False, False, False], "invalid kept, failures rerun: %s" % [r.reused for r in res])
check((res[0].exit_code, res[0].error) == (2, "x: error: radar.x_m out of range"), "kept invalid: %s" % res[0].error)

# keep: once the job succeeded only the matching files (and the job's own two) stay.
kj = sr.Job("kept", [["sh", "-c", "mkdir -p {dir}/run/sub; echo 1 > {dir}/run/a.json; echo 2 > {dir}/run/b.csv; echo 3 > {dir}/run/sub/c"]],
            keep=["run/*.json"])
r = sr.run([kj], os.path.join(T, "keep"))[0]
left = sorted(os.path.relpath(os.path.join(d, f), r.folder) for d, _, fs in os.walk(r.folder) for f in fs)
check(r.ok and left == ["job.json", "job.log", "run/a.json"], "keep left %s" % left)
check(not sr.run([sr.Job("kept", kj.steps, keep=["run/*.csv"])], os.path.join(T, "keep"))[0].reused,
      "a job keeping other files was not run again")

# Progress through log: '0 of M done; ETA unknown' before any job has finished, then one line
# per finished job with its count, failures, name, status and time, an ETA above 0 until the
# last, 0 s after it; jobs kept from an earlier run are neither counted nor timed.
PROGRESS = re.compile(r"^(\d+) of (\d+) done \((\d+) failed\) \u2014 last (\S+) (ok|invalid|failed) in "
                      r"(\d+\.\d) s; ETA (\d+ s|\d+ min \d+ s|\d+ h \d+ min)$")


def eta_s(text):
    parts = text.split()
    unit = {"s": 1, "min": 60, "h": 3600}
    return sum(int(parts[i]) * unit[parts[i + 1]] for i in range(0, len(parts), 2))


def progress_run(jobs, out, **kw):
    """run() and its log lines, each with whether no job had finished (no marker come or gone) when it came."""
    def markers():
        return sorted(j.name for j in jobs if os.path.exists(os.path.join(out, j.name, sr.MARKER)))
    before, lines = markers(), []

    def log(msg):
        lines.append((msg, markers() == before))
    return sr.run(jobs, out, log=log, **kw), lines


def check_progress(lines, total, kept_n, failed_names, what):
    prog = [(m, seen) for m, seen in lines if not m.startswith("job ") and "MPI ranks" not in m]
    first = "0 of %d done%s; ETA unknown" % (total, ", %d kept from an earlier run" % kept_n if kept_n else "")
    check(prog and prog[0][0] == first, "%s: first progress line %r, expected %r" % (what, prog[:1], first))
    check(prog[0][1], "%s: 'ETA unknown' came after a job had finished" % what)
    done = [PROGRESS.match(m) for m, _ in prog[1:]]
    check(len(done) == total and all(done), "%s: expected %d progress lines, got %s" % (what, total, [m for m, _ in prog[1:]]))
    names, failed = [], 0
    for k, g in enumerate(done, 1):
        failed += g.group(4) in failed_names
        names.append(g.group(4))
        check((int(g.group(1)), int(g.group(2)), int(g.group(3))) == (k, total, failed), "%s: counts in %r" % (what, g.group(0)))
        check(g.group(5) == ("failed" if g.group(4) in failed_names else "ok"), "%s: status in %r" % (what, g.group(0)))
        check((eta_s(g.group(7)) > 0) == (k < total), "%s: ETA in %r" % (what, g.group(0)))
    return names, [eta_s(g.group(7)) for g in done]


pj = [sr.Job("p%d" % i, [["sh", "-c", "sleep 0.2" + ("; exit 3" if i == 2 else "")]]) for i in range(4)]
pout = os.path.join(T, "progress")
res, lines = progress_run(pj, pout)
names, _ = check_progress(lines, 4, 0, {"p2"}, "4 jobs, one failing")
check(sorted(names) == ["p0", "p1", "p2", "p3"], "progress names %s" % names)
check(lines[1][0] == "job p0", "no 'job NAME' line as the first job starts: %s" % lines[:3])
# The ok ones kept, as if each had taken 1000 s: the rerun counts and times only p2 and two new jobs.
for n in ("p0", "p1", "p3"):
    mp = os.path.join(pout, n, sr.MARKER)
    m = json.load(open(mp))
    json.dump(dict(m, wall_s=1000.0), open(mp, "w"))
pj[2] = sr.Job("p2", [["sleep", "0.2"]])
pj += [sr.Job("p%d" % i, [["sleep", "0.2"]]) for i in (4, 5)]
res, lines = progress_run(pj, pout, parallel=2)
names, etas = check_progress(lines, 3, 3, set(), "a rerun with 3 kept, 2 at once")
check(sorted(names) == ["p2", "p4", "p5"], "rerun progress names %s" % names)
check(etas[0] <= 5, "a kept job's 1000 s counted toward the ETA: %s" % etas)
res, lines = progress_run(pj, pout)
check(lines == [], "all kept: progress lines %s" % lines)
check(sr.eta_text(None) == "unknown" and sr.eta_text(0.01) == "1 s" and sr.eta_text(80) == "1 min 20 s"
      and sr.eta_text(7500) == "2 h 5 min" and sr.eta_text(0) == "0 s", "eta_text")

# Bad use is refused naming the culprit.
for jobs_bad, want in (([sr.Job("a", [["true"]]), sr.Job("a", [["true"]])], "job name a given twice"),):
    try:
        sr.run(jobs_bad, os.path.join(T, "x"))
        fail("accepted: %s" % want)
    except sr.StudyError as e:
        check(want in str(e), "%s: %s" % (want, e))
for name, steps, want in (("a/b", [["true"]], "job name 'a/b'"), ("a", [], "steps must be"), ("a", [[]], "steps must be")):
    try:
        sr.Job(name, steps)
        fail("accepted job %r %r" % (name, steps))
    except sr.StudyError as e:
        check(want in str(e), "%s: %s" % (want, e))

# MPI: 3 ranks give the same results as one process; a killed rank is named with its jobs.
if shutil.which("mpirun"):
    os.remove(COUNT)
    jobs = [job(i) for i in range(7)]
    res, lines = progress_run(jobs, os.path.join(T, "mpi"), ranks=3)
    check(values(res) == [str(i * i) for i in range(7)], "3 ranks: %s" % values(res))
    names, _ = check_progress(lines, 7, 0, set(), "3 MPI ranks")
    check(sorted(names) == ["j%02d" % i for i in range(7)], "MPI progress names %s" % names)
    check(sorted(runs()) == ["j%02d" % i for i in range(7)], "3 ranks, each job once: %s" % runs())
    # Rank 1 of 3 holds jobs floor(7/3)=2 ... floor(14/3)-1=3: its job j02 kills its rank, once
    # the other ranks' last jobs (j01, j06) are done: mpirun ends every rank when one dies, so a
    # kill any earlier would, on a loaded machine, also take rank 0's or rank 2's jobs with it
    # (at most 20 s of waiting: the kill comes anyway).
    kill_dir = os.path.join(T, "mpi_kill")
    jobs[2] = sr.Job("j02", [["sh", "-c", "for i in $(seq 400); do [ -e %s/j01/job.json ] && [ -e %s/j06/job.json ] && break; "
                                           "sleep 0.05; done; kill -KILL $PPID" % (kill_dir, kill_dir)]])
    res = sr.run(jobs, kill_dir, ranks=3)
    dead = [r for r in res if r.status == "failed"]
    check([r.name for r in dead] == ["j02", "j03"],
          "the killed rank's jobs j02 and j03 (and only they) should have failed: %s" % [(r.name, r.status) for r in res])
    check("MPI rank 1" in dead[0].message and "jobs j02 ... j03" in dead[0].message and "signal 9" in dead[0].message,
          "the killed rank is not named: %s" % dead[0].message)
    # mpirun ends the other ranks too: a rerun with the job mended finishes what is missing.
    jobs[2] = job(2)
    res = sr.run(jobs, os.path.join(T, "mpi_kill"), ranks=3)
    check(values(res) == [str(i * i) for i in range(7)], "the rerun after a killed rank: %s" % values(res))
else:
    print("study_runner: mpirun not installed; the MPI part is not run")
shutil.rmtree(T, ignore_errors=True)
print("study_runner: ok")
