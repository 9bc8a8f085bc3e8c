"""The package's programs run by whatever python3 comes first on PATH: one that lacks numpy or
matplotlib (a pyenv, conda or venv interpreter) hands the program over to Debian's
/usr/bin/python3, which scripts/setup gives both, with this checkout's package first on its path.

    from rnav import interpreter
    interpreter.hand_over([script_path] + sys.argv[1:])   # returns only if it cannot

Used by the figure programs (rnav.figures.pyplot: `python3 scripts/plot_prl.py DIR`) and by
`python3 -m rnav`; code that imports the package itself (`import rnav` in your program) gets the
readers' message naming the interpreter instead.
"""
import os
import sys

DEBIAN = "/usr/bin/python3"
_MARK = "RNAV_HANDED_OVER_FROM"  # set in the handed-over process: never handed over twice


def hand_over(argv):
    """Replace this process by DEBIAN running `argv` (what follows the interpreter on its command
    line: [SCRIPT, ARG...] or ["-m", "rnav", ARG...]) with the folder holding this package first on
    PYTHONPATH. Returns (doing nothing) when this interpreter is Debian's, when this process was
    handed over already, or when there is no DEBIAN."""
    if os.environ.get(_MARK) or sys.executable == DEBIAN or not os.access(DEBIAN, os.X_OK):
        return
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env = dict(os.environ)
    env[_MARK] = sys.executable or "?"
    env["PYTHONPATH"] = here + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    sys.stdout.flush()
    sys.stderr.flush()
    os.execve(DEBIAN, [DEBIAN] + list(argv), env)
