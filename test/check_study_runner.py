#!/usr/bin/python3
"""ctest python.study_runner: scripts/study_runner.py, the runner under scripts/sweep and every
study, on small shell jobs whose outcome is known: each job's result in its own folder, kept
results not run again (counted by a file each run appends to), a job of other steps run again,
exit status 2 kept as 'invalid', any other failure named and rerun, the same results on 1 and 3
MPI ranks, and a rank killed outright named with its jobs. Usage: check_study_runner.py SOURCE_DIR
"""
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.join(sys.argv[1], "scripts"))
import study_runner as sr  # noqa: E402

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
    res = sr.run(jobs, os.path.join(T, "mpi"), ranks=3)
    check(values(res) == [str(i * i) for i in range(7)], "3 ranks: %s" % values(res))
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
