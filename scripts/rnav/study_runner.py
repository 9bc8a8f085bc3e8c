"""The one runner under scripts/sweep and every study (geometry, UAV, guidance, false-alarm,
power): named jobs, each a short list of commands writing into the job's own folder, run on this
host (J at once) or sharded over K MPI ranks (mpirun or srun). A job that finished is kept and
not run again, so a study that stopped (killed, a machine lost, a failed job) resumes where it
was; a job that failed, or whose rank died, is named.

A job, Job(name, steps, env=None, timeout_s=None, keep=None):
  name       unique within a run, [A-Za-z0-9_.+=-]+ (no '/'); its folder is OUT/NAME
  steps      a list of argv lists run in order, each only if the one before succeeded; every
             '{dir}' inside an argument becomes the job's folder (absolute path)
  env        extra environment variables for the steps (not part of the job's identity)
  timeout_s  a step running longer is killed and the job fails (None: no limit)
  keep       once every step succeeded, only the files matching these patterns (fnmatch, paths
             relative to the job's folder, e.g. 'run/summary.json') stay, with job.json and
             job.log; empty folders go too. None keeps everything. Part of the job's identity.
Outcome of a job (Result.status):
  ok       every step exited 0
  invalid  a step exited 2, the project's status for input it refuses (e.g. a trajectory that
           does not fit); the same input is refused again, so it is kept like an ok job
  failed   any other failure (a crash, a signal, a timeout, a rank that died); not kept: the
           next run runs the job again
The job's folder holds job.log (every step's stderr) and, written last and atomically, job.json:
{"command_id": sha256 of the steps, "status", "message", "wall_s"}. A folder whose job.json is
missing, failed, or of other steps is emptied and the job run again; nothing outside OUT/NAME is
touched.

Progress, through run()'s log callback: 'job NAME' as a job starts on this host, and of the M
jobs this call runs (kept ones are not counted), first '0 of M done; ETA unknown', then as each
job finishes 'N of M done (K failed) — last NAME ok in 3.2 s; ETA 1 min 20 s' (class Progress;
under MPI a job counts as finished when its job.json appears).

Under MPI (ranks=K) rank r of K runs jobs floor(rN/K) ... floor((r+1)N/K)-1 of the N in order,
one at a time; OUT must be on a file system every rank sees (one host, or a shared one on a
cluster). Rank failures are named by scripts/mpi.bash (rank, host, the rank's jobs).
"""
import fnmatch
import hashlib
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor

# scripts/ of this checkout (mpi.bash), also when imported through the link scripts/rnav
SCRIPTS = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__)))), "scripts")
MARKER = "job.json"
LOG = "job.log"
KEPT = ("ok", "invalid")
INVALID_INPUT_STATUS = 2     # the exit status every project program uses for refused input
NAME_RE = re.compile(r"[A-Za-z0-9_.+=-]+")
MPI_POLL_S = 0.5            # how often a run over MPI looks for the jobs finished


class StudyError(Exception):
    """Bad use of the runner (a bad job list, MPI missing); the message names the culprit."""


class Job:
    def __init__(self, name, steps, env=None, timeout_s=None, keep=None):
        if not isinstance(name, str) or not NAME_RE.fullmatch(name) or name in (".", ".."):
            raise StudyError("job name %r: use letters, digits and _.+=- only" % (name,))
        if not steps or not all(isinstance(s, list) and s and all(isinstance(a, str) for a in s) for s in steps):
            raise StudyError("job %s: steps must be a non-empty list of non-empty argv lists of strings" % name)
        if timeout_s is not None and not timeout_s > 0:
            raise StudyError("job %s: timeout_s must be > 0, got %r" % (name, timeout_s))
        if keep is not None and not (isinstance(keep, list) and all(isinstance(k, str) and k for k in keep)):
            raise StudyError("job %s: keep must be None or a list of file patterns" % name)
        self.name, self.steps, self.env, self.timeout_s = name, steps, dict(env or {}), timeout_s
        self.keep = keep

    def command_id(self):
        """What a kept result must have been made with: the steps, {dir} unexpanded (and what
        was kept of their files)."""
        ident = self.steps if self.keep is None else {"steps": self.steps, "keep": self.keep}
        return hashlib.sha256(json.dumps(ident).encode()).hexdigest()

    def to_dict(self):
        return {"name": self.name, "steps": self.steps, "env": self.env, "timeout_s": self.timeout_s,
                "keep": self.keep}


class Result:
    """A job's outcome: name, status (ok / invalid / failed), folder, message (which step
    failed and how, with its last error line, or ''), wall_s (its run time, also for a kept
    result), reused (True when kept from an earlier run), exit_code (0 ok; the failing step's
    exit status; -N for signal N; None when it timed out or could not start) and error (the
    failing step's last error line alone, or '')."""

    def __init__(self, name, status, folder, message="", wall_s=0.0, reused=False, exit_code=0, error=""):
        self.name, self.status, self.folder = name, status, folder
        self.message, self.wall_s, self.reused = message, wall_s, reused
        self.exit_code, self.error = exit_code, error

    @property
    def ok(self):
        return self.status == "ok"


def _read_marker(folder):
    try:
        with open(os.path.join(folder, MARKER)) as f:
            m = json.load(f)
        return m if isinstance(m, dict) else None
    except (OSError, ValueError):
        return None


def kept(job, out):
    """The Result of an earlier run of this job in OUT, or None when it must run."""
    folder = os.path.join(out, job.name)
    m = _read_marker(folder)
    if m and m.get("command_id") == job.command_id() and m.get("status") in KEPT:
        code = 0 if m["status"] == "ok" else INVALID_INPUT_STATUS
        return Result(job.name, m["status"], folder, m.get("message", ""), m.get("wall_s", 0.0), True,
                      code, m.get("error", m.get("message", "")))
    return None


def _error_line(text):
    lines = [l for l in text.strip().splitlines() if l.strip()]
    return next((l for l in reversed(lines) if "error" in l.lower()), lines[-1] if lines else "")


def run_one(job, out):
    """Run one job now (its earlier folder, if any, emptied first) and record its outcome."""
    folder = os.path.join(out, job.name)
    if os.path.lexists(folder):
        if os.path.islink(folder) or not os.path.isdir(folder):
            raise StudyError("%s is not a job folder (a link or a file): remove it" % folder)
        shutil.rmtree(folder)
    os.makedirs(folder)
    env = dict(os.environ, **job.env)
    t0 = time.time()
    status, message, code, error = "ok", "", 0, ""
    with open(os.path.join(folder, LOG), "w") as log:
        for step in job.steps:
            argv = [a.replace("{dir}", folder) for a in step]
            log.write("$ %s\n" % " ".join(argv))
            log.flush()
            with tempfile.TemporaryFile("w+") as err:
                try:
                    p = subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=err, env=env,
                                       timeout=job.timeout_s)
                    rc = p.returncode
                except subprocess.TimeoutExpired:
                    rc = None
                except OSError as e:
                    rc, message = 127, "cannot start %s: %s" % (argv[0], e)
                err.seek(0)
                text = err.read()
            log.write(text)
            if rc == 0:
                continue
            code, error = rc, _error_line(text)
            if rc is None:
                status, message = "failed", "%s timed out after %g s" % (os.path.basename(argv[0]), job.timeout_s)
            elif rc == INVALID_INPUT_STATUS:
                status, message = "invalid", error
            else:
                why = "exit status %d" % rc if rc > 0 else "signal %d" % -rc
                if not error:  # e.g. "cannot start ...": no error output, the reason is the message
                    error, code = message, (None if rc == 127 and message else rc)
                status, message = "failed", "%s: %s%s" % (os.path.basename(argv[0]), why,
                                                          (": " + error) if error else "")
            break
    if status == "ok" and job.keep is not None:
        _prune(folder, job.keep)
    wall = round(time.time() - t0, 3)
    marker = {"command_id": job.command_id(), "status": status, "message": message, "wall_s": wall,
              "exit_code": code, "error": error}
    tmp = os.path.join(folder, MARKER + ".partial")
    with open(tmp, "w") as f:
        json.dump(marker, f)
    os.replace(tmp, os.path.join(folder, MARKER))
    return Result(job.name, status, folder, message, wall, False, code, error)


def _prune(folder, keep):
    """Remove every file under folder but job.json, job.log and those matching keep."""
    for root, dirs, files in os.walk(folder, topdown=False):
        for f in files:
            rel = os.path.relpath(os.path.join(root, f), folder)
            if rel not in (MARKER, LOG) and not any(fnmatch.fnmatchcase(rel, k) for k in keep):
                os.remove(os.path.join(root, f))
        if root != folder and not os.listdir(root):
            os.rmdir(root)


def _check_jobs(jobs):
    names = set()
    for j in jobs:
        if not isinstance(j, Job):
            raise StudyError("not a Job: %r" % (j,))
        if j.name in names:
            raise StudyError("job name %s given twice" % j.name)
        names.add(j.name)


def shard(n, k, r):
    """Rank r of k runs items shard(n, k, r) = range(floor(rn/k), floor((r+1)n/k))."""
    return range(n * r // k, n * (r + 1) // k)


def eta_text(seconds):
    """A time left as it prints in a progress line: 'unknown' (None), '45 s', '1 min 20 s',
    '2 h 5 min'; whole seconds rounded up, so a time left above 0 never reads 0 s."""
    if seconds is None:
        return "unknown"
    s = int(math.ceil(seconds - 1e-9)) if seconds > 0 else 0
    if s < 60:
        return "%d s" % s
    if s < 3600:
        return "%d min %d s" % divmod(s, 60)
    return "%d h %d min" % (s // 3600, s % 3600 // 60)


class Progress:
    """The progress lines of one run() call, through its log callback. Counts are of the jobs
    this call runs (M); a job kept from an earlier run is neither counted nor timed. As each
    job finishes:
        N of M done (K failed) — last NAME STATUS in 3.2 s; ETA 1 min 20 s
    ETA = the jobs left x the mean wall time of the jobs finished in this call / the jobs run
    at once (parallel, or MPI ranks; at most the jobs left), rounded up to whole seconds: above
    0 s until the last job is done, 0 s after it. Before any job finished it is 'unknown'
    (the first line, '0 of M done ...; ETA unknown')."""

    def __init__(self, log, total, kept_n, width):
        self.log, self.total, self.width = log, total, max(1, width)
        self.done, self.failed, self.walls = 0, 0, []
        kept_text = (", %d kept from an earlier run" % kept_n) if kept_n else ""
        self.log("0 of %d done%s; ETA unknown" % (total, kept_text))

    def eta(self):
        left = self.total - self.done
        if left == 0:
            return 0.0
        if not self.walls:
            return None
        mean = sum(self.walls) / len(self.walls)
        return max(left * mean / min(self.width, left), 1e-3)   # never 0 before the end

    def finished(self, result):
        self.done += 1
        self.failed += result.status == "failed"
        self.walls.append(max(0.0, float(result.wall_s or 0.0)))
        self.log("%d of %d done (%d failed) \u2014 last %s %s in %.1f s; ETA %s"
                 % (self.done, self.total, self.failed, result.name, result.status, result.wall_s or 0.0,
                    eta_text(self.eta())))


def _mpi_result(job, out, failure):
    """A job's Result once its MPI rank is done with it (None while it has no marker)."""
    r = kept(job, out)
    if r is not None:
        r.reused = False
        return r
    m = _read_marker(os.path.join(out, job.name))
    if m is None and failure is None:
        return None
    m = m or {}
    return Result(job.name, "failed", os.path.join(out, job.name),
                  m.get("message") or "no result: " + (failure or "its rank ended without one"),
                  m.get("wall_s", 0.0), False, m.get("exit_code"), m.get("error", ""))


def _run_mpi(jobs, todo, out, ranks, log, progress, results):
    """The jobs `todo` (indices into jobs) over `ranks` MPI ranks, filling results[i] and
    reporting each job to progress as its marker appears; returns '' or the failure."""
    # A todo job's old marker (failed, or of other steps) goes first, so that a marker seen
    # while the ranks run is this run's (run_one empties the folder anyway).
    for i in todo:
        try:
            os.remove(os.path.join(out, jobs[i].name, MARKER))
        except OSError:
            pass
    plan = os.path.join(out, ".study_plan.json")
    with open(plan, "w") as f:
        json.dump({"out": out, "jobs": [jobs[i].to_dict() for i in todo]}, f)
    describe = os.path.join(out, ".study_ranks.txt")
    with open(describe, "w") as f:
        for r in range(ranks):
            s = shard(len(todo), ranks, r)
            f.write(("jobs %s ... %s" % (jobs[todo[s[0]]].name, jobs[todo[s[-1]]].name) if len(s) else "no jobs") + "\n")
    log("%d jobs over %d MPI ranks" % (len(todo), ranks))
    # Inside describe, $1 is the rank; the script's own arguments are $1 ... $6 outside it. Each
    # rank learns its number and the rank count from mpi.bash (mpi_rank_exec appends them).
    script = ('source "$1/mpi.bash"; describe() { sed -n "$(($1 + 1))p" "$DESCRIBE"; }; '
              'mpi_run "$2" "$3" describe bash -c \'source "$0"; mpi_rank_exec "$@"\' "$1/mpi.bash" '
              '"$4" "$5" --worker "$6" && exit 0; echo "$MPI_FAILURE" >&2; exit 1')
    pending = list(todo)

    def collect(failure=None):
        for i in list(pending):
            r = _mpi_result(jobs[i], out, failure)
            if r is not None:
                results[i] = r
                pending.remove(i)
                progress.finished(r)

    with tempfile.TemporaryFile("w+") as err:
        p = subprocess.Popen(["bash", "-c", script, "study_runner", SCRIPTS, str(ranks), os.path.join(out, ".study_mpi.log"),
                              sys.executable, os.path.abspath(__file__), plan],
                             stdout=subprocess.DEVNULL, stderr=err, text=True,
                             env=dict(os.environ, DESCRIBE=describe))
        while True:
            try:
                p.wait(timeout=MPI_POLL_S)
                break
            except subprocess.TimeoutExpired:
                collect()
        err.seek(0)
        text = err.read()
    failure = "" if p.returncode == 0 else (text.strip() or "mpirun failed (exit %d)" % p.returncode)
    collect(failure)
    return failure


def run(jobs, out, parallel=1, ranks=0, log=None):
    """Run the jobs not kept from an earlier run into OUT/NAME; returns a Result per job, in the
    order given. parallel: jobs at once on this host (>= 1); ranks: > 0 shards the jobs over
    that many MPI ranks instead. Raises StudyError on bad use; failed jobs are Results.
    log(text) hears 'job NAME' as a job starts on this host, and the progress lines (Progress):
    '0 of M done; ETA unknown' first, then one as each job finishes."""
    log = log or (lambda msg: None)
    _check_jobs(jobs)
    if not (isinstance(parallel, int) and parallel >= 1):
        raise StudyError("parallel must be an integer >= 1, got %r" % (parallel,))
    if not (isinstance(ranks, int) and 0 <= ranks <= 1024):
        raise StudyError("ranks must be an integer in 0 ... 1024, got %r" % (ranks,))
    out = os.path.abspath(out)
    os.makedirs(out, exist_ok=True)
    results = [kept(j, out) for j in jobs]
    todo = [i for i, r in enumerate(results) if r is None]
    if not todo:
        return results
    progress = Progress(log, len(todo), len(jobs) - len(todo), ranks if ranks > 0 else parallel)
    if ranks > 0:
        _run_mpi(jobs, todo, out, ranks, log, progress, results)
    else:
        lock = threading.Lock()   # one job's lines at a time, its end before the next one's start

        def one(i):
            with lock:
                log("job %s" % jobs[i].name)
            r = run_one(jobs[i], out)
            with lock:
                results[i] = r
                progress.finished(r)
        with ThreadPoolExecutor(max_workers=parallel) as ex:
            for fut in [ex.submit(one, i) for i in todo]:
                fut.result()
    return results


def summary(results):
    """'N jobs: R run, K from an earlier run, F failed' (I of them invalid input when any)."""
    ran = sum(1 for r in results if not r.reused)
    reused = len(results) - ran
    failed = sum(1 for r in results if r.status == "failed")
    invalid = sum(1 for r in results if r.status == "invalid")
    return "%d jobs: %d run, %d from an earlier run, %d failed%s" % (
        len(results), ran, reused, failed, (", %d invalid input" % invalid) if invalid else "")


def failures(results):
    """'NAME: message' for every failed job (invalid input is an outcome, not a failure)."""
    return ["%s: %s" % (r.name, r.message) for r in results if r.status == "failed"]


def _worker(plan_path, rank, size):
    """An MPI rank (rank of size, from mpi.bash): its shard of the plan's jobs, one at a time.
    Job failures are recorded in the jobs' folders (exit 0); only a broken plan makes the rank
    fail."""
    with open(plan_path) as f:
        plan = json.load(f)
    jobs = [Job(d["name"], d["steps"], d["env"], d["timeout_s"], d["keep"]) for d in plan["jobs"]]
    for i in shard(len(jobs), size, rank):
        run_one(jobs[i], plan["out"])
    return 0


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "--worker" and sys.argv[3].isdigit() and sys.argv[4].isdigit():
        sys.exit(_worker(sys.argv[2], int(sys.argv[3]), int(sys.argv[4])))
    sys.stderr.write("study_runner: a library (import it); '--worker PLAN RANK SIZE' is how MPI ranks run it\n")
    sys.exit(2)
