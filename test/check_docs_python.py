#!/usr/bin/python3
"""ctest python.docs_snippets: every Python command of the README and docs/ runs as written, with a
python3 first on PATH that has neither numpy nor matplotlib.

A Python command is a line of an indented command block of README.md or docs/*.md that runs
`python3` or `/usr/bin/python3` (backslash continuations joined; in a block of `$ ` lines, those
lines). The commands are found here, not copied: an edited or new one is the one that runs. Every
block holding one runs whole, in its file's order (a later block may read what an earlier one of
its file wrote), from the top folder, inside a private network namespace (unshare -n: no traffic
leaves the machine); its other commands make the Python commands' inputs, except those STAND_INS
names (a cluster launcher), which are replaced by a small run writing the same --out. As in
test/check_readme.py, `/tmp/` and a leading `out/` or `results/` become folders of this test's
scratch directory.

The python3 first on PATH is a virtual environment of Debian's interpreter (a pyvenv.cfg and a
link: no numpy, no matplotlib, no user site-packages), as a pyenv, conda or venv python3 would
be; PYTHONPATH names this checkout's scripts/ (scripts/setup's rnav.pth may name another
checkout). A command fails the test if it exits non-zero or prints a traceback; fewer than
MIN_COMMANDS Python commands found means the pattern is out of date.

Usage: check_docs_python.py SOURCE_DIR BUILD_DIR
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

SRC, BUILD = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
MIN_COMMANDS = 5
PYTHON = re.compile(r"(^|[\s;&|(])(/usr/bin/)?python3(\s|$)")
# Commands that cannot run here, by their start: what makes their outputs instead ({out}: their --out).
STAND_INS = {"mpirun ": "scripts/run paper --inproc --realizations 2 --seed 1 --no-plots --out {out}"}


def blocks(text):
    """The indented blocks of a Markdown text: lists of lines, indentation removed."""
    out, cur, prev_blank = [], None, True
    for line in text.split("\n"):
        if cur is not None and (line.startswith("    ") or not line.strip()):
            cur.append(line[4:])
            continue
        if cur is not None:
            out.append(cur)
            cur = None
        if line.startswith("    ") and prev_blank:
            cur = [line[4:]]
        prev_blank = not line.strip()
    if cur is not None:
        out.append(cur)
    return [[l for l in b] for b in out]


def commands(lines):
    """The commands of a block: `$ ` lines if it has any (the rest is their output), else every
    non-empty line; backslash continuations joined."""
    if any(l.startswith("$ ") for l in lines):
        lines = [l[2:] for l in lines if l.startswith("$ ")]
    out, cur = [], ""
    for line in lines:
        if not line.strip() and not cur:
            continue
        if line.rstrip().endswith("\\"):
            cur += line.rstrip()[:-1] + " "
        else:
            out.append((cur + line).strip())
            cur = ""
    return out


def localize(cmd, tmp):
    cmd = cmd.replace("/tmp/", tmp + "/")
    return re.sub(r"(?<=\s)(out|results)/", tmp + r"/\1/", cmd)


def numpy_less_python(where):
    """A virtual environment of Debian's python3: WHERE/bin/python3, no numpy, no user site."""
    os.makedirs(where + "/bin")
    os.symlink("/usr/bin/python3", where + "/bin/python3")
    ver = subprocess.run(["/usr/bin/python3", "-c", "import sys; print('%d.%d.%d' % sys.version_info[:3])"],
                         stdout=subprocess.PIPE, text=True, check=True).stdout.strip()
    with open(where + "/pyvenv.cfg", "w") as f:
        f.write("home = /usr/bin\ninclude-system-site-packages = false\nversion = %s\n" % ver)
    r = subprocess.run([where + "/bin/python3", "-c", "import numpy"], stderr=subprocess.PIPE)
    if r.returncode == 0:
        raise SystemExit("check_docs_python: the test's python3 (%s) imports numpy: it cannot stand for one "
                         "without" % where)
    return where + "/bin"


def main():
    tmp = tempfile.mkdtemp(prefix="rnav-docs-python-")
    try:
        env = dict(os.environ, RNAV_BUILD=BUILD, PYTHONPATH=os.path.join(SRC, "scripts"),
                   PATH=numpy_less_python(tmp + "/venv") + os.pathsep + os.environ["PATH"])
        env.pop("PYTHONHOME", None)
        fails, found = [], 0
        docs = ["README.md"] + sorted(os.path.relpath(p, SRC) for p in glob.glob(os.path.join(SRC, "docs", "*.md")))
        for name in docs:
            text = open(os.path.join(SRC, name), encoding="utf-8").read()
            work = os.path.join(tmp, name.replace("/", "_"))
            os.makedirs(work)
            for block in blocks(text):
                cmds = commands(block)
                if not any(PYTHON.search(c) for c in cmds):
                    continue
                for c in cmds:
                    run = c
                    for start, stand_in in STAND_INS.items():
                        if c.startswith(start):
                            m = re.search(r"--out (\S+)", c)
                            if not m:
                                raise SystemExit("check_docs_python: %s: '%s' has no --out for its stand-in" % (name, c))
                            run = stand_in.format(out=m.group(1))
                    is_python = bool(PYTHON.search(c))
                    found += is_python
                    script = ("ip link set lo up && ip route add 224.0.0.0/4 dev lo || exit 9\n" + localize(run, work))
                    r = subprocess.run(["unshare", "-n", "bash", "-c", script], cwd=SRC, env=env,
                                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                    if r.returncode == 9:
                        raise SystemExit("check_docs_python: cannot set up a private network namespace (needs root)")
                    ok = r.returncode == 0 and "Traceback" not in r.stderr
                    print("check_docs_python: %s: %s%s: %s" % (name, "" if is_python else "(its input) ", c[:100],
                                                               "ok" if ok else "FAILED"), flush=True)
                    if not ok:
                        fails.append("%s: '%s' exited %d: %s" % (name, c, r.returncode, r.stderr.strip()[-800:]))
        if found < MIN_COMMANDS:
            fails.append("only %d Python commands found in README.md and docs/*.md (the pattern is out of date?)" % found)
        for f in fails:
            print("FAIL: " + f)
        print("%d Python command(s) of the documentation, %d failure(s)" % (found, len(fails)))
        return 1 if fails else 0
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
