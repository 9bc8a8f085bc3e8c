"""Shared by the checks that run the diagnosis on scripts/flightgen.py's data
(check_discovery.py, check_shipradar.py): the checks' tally, a quiet subprocess and the
generator call.

  checks = Checks("check_name"); checks.check(ok, what); ...; sys.exit(checks.finish())
"""
import os
import subprocess


class Checks:
    def __init__(self, prog):
        self.prog, self.failures = prog, []

    def check(self, ok, what):
        """Print ok/FAIL with `what`; a failure is counted."""
        print("%s  %s" % ("ok  " if ok else "FAIL", what))
        if not ok:
            self.failures.append(what)

    def finish(self):
        """The exit status: 1 with the count of failures printed, else 0."""
        if self.failures:
            print("%s: %d check(s) failed" % (self.prog, len(self.failures)))
            return 1
        print("%s: all checks passed" % self.prog)
        return 0


def run(*argv):
    return subprocess.run(list(argv), capture_output=True, text=True)


def gen(src, prog, mode, out, seed, keys):
    """scripts/flightgen.py MODE OUT --seed SEED --set KEY... (SystemExit naming prog on failure)."""
    args = [os.path.join(src, "scripts", "flightgen.py"), mode, out, "--seed", str(seed)]
    for k in keys:
        args += ["--set", k]
    r = run(*args)
    if r.returncode != 0:
        raise SystemExit("%s: flightgen failed: %s" % (prog, r.stderr))
