#!/usr/bin/python3
"""The source layout's rules, checked on the tracked files (docs/processes-and-protocol.md#source-layout).

  check_layout.py check SOURCE_DIR   every rule below; exit 1 naming each file that breaks one
  check_layout.py table SOURCE_DIR   the layout table (folder, lines of C++, Python and LCM types)

Rules:
  1. one include root: every #include "..." of the project's C++ names a tracked file by its path
     from the top folder (#include "common/physics/frames.hpp"), or a generated message type
     ("rnav/NAME.hpp" for lcmtypes/NAME.lcm);
  2. arrows point one way: a folder includes only from the folders listed for it in ALLOWED;
  3. every main() of a program is in scripts/compose/mains/ (tests keep theirs in test/);
  4. one home for the Python package: scripts/rnav/, and no symbolic link in the tree;
  5. every source path the README and docs/ quote (`sim/prl/prl_node.cpp`, `common/io/`) exists.
"""
import os
import re
import subprocess
import sys

# Folder -> the folders its C++ may include (besides itself). common/'s jobs stack: physics at
# the bottom, file and option I/O over it, the node runtime over both.
ALLOWED = {
    "common/physics": [],
    "common/io": ["common/physics"],
    "common/node": ["common/io", "common/physics"],
    "sim": ["common"],
    "estimators": ["common"],
    "loggers": ["common", "sim", "estimators"],
    "scripts/compose": ["common", "sim", "estimators", "loggers"],
    "test": ["common", "sim", "estimators", "loggers", "scripts/compose"],
}
MAINS = "scripts/compose/mains/"
PACKAGE = "scripts/rnav/"
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
MAIN = re.compile(r"^\s*int\s+main\s*\(", re.M)
QUOTED_PATH = re.compile(r"`((?:common|sim|estimators|loggers|scripts|test|lcmtypes|docs)/[A-Za-z0-9_./-]*)(.?)")
PLACEHOLDER = re.compile(r"[A-Z]{3,}")  # NAME, EXE: a pattern, not a path


def tracked(src):
    out = subprocess.check_output(["git", "-C", src, "ls-files", "-s"], text=True)
    rows = [line.split(None, 3) for line in out.splitlines()]
    return [(r[0], r[3]) for r in rows]


def owner(path):
    """The ALLOWED folder a file belongs to (the longest prefix), or None."""
    best = None
    for folder in ALLOWED:
        if path.startswith(folder + "/") and (best is None or len(folder) > len(best)):
            best = folder
    return best


def check(src):
    files = tracked(src)
    paths = {p for _, p in files}
    lcm_types = {os.path.splitext(os.path.basename(p))[0] for p in paths if p.startswith("lcmtypes/") and p.endswith(".lcm")}
    problems = []
    for mode, p in files:
        if mode == "120000":
            problems.append("%s: a symbolic link (one home per file: move what it points to)" % p)
    for p in sorted(paths):
        if not p.endswith((".cpp", ".hpp", ".h")) or p.startswith("test/data/"):
            continue
        text = open(os.path.join(src, p), encoding="utf-8").read()
        me = owner(p)
        for inc in INCLUDE.findall(text):
            if inc.startswith("rnav/"):
                if os.path.splitext(inc[5:])[0] not in lcm_types:
                    problems.append('%s: #include "%s" names no message type in lcmtypes/' % (p, inc))
                continue
            if inc not in paths:
                problems.append('%s: #include "%s" is not a path from the top folder (one include root)' % (p, inc))
                continue
            if me is None:
                problems.append("%s: in no folder of the layout" % p)
                continue
            allowed = [me] + ALLOWED[me]
            if not any(inc.startswith(a + "/") for a in allowed):
                problems.append('%s: #include "%s": %s/ may include only from %s' % (p, inc, me, ", ".join(a + "/" for a in allowed)))
        if MAIN.search(text) and not (p.startswith(MAINS) or p.startswith("test/")):
            problems.append("%s: a main() outside %s" % (p, MAINS))
    dirs = {os.path.dirname(p) for p in paths}
    dirs |= {d for p in list(dirs) for d in (p.split("/")[0],)}
    for p in sorted(paths):
        if not (p == "README.md" or (p.startswith("docs/") and p.endswith(".md"))):
            continue
        text = open(os.path.join(src, p), encoding="utf-8").read()
        for q, after in QUOTED_PATH.findall(text):
            if after == "*" or PLACEHOLDER.search(q):
                continue
            q = q.rstrip("./")
            if q in paths or q in dirs or any(d.startswith(q + "/") for d in dirs):
                continue
            problems.append("%s: quotes `%s`, which is no file or folder of the checkout" % (p, q))
    inits = sorted(p for p in paths if p.endswith("/__init__.py"))
    if inits != [PACKAGE + "__init__.py"]:
        problems.append("Python packages: %s (expected only %s)" % (", ".join(inits) or "none", PACKAGE))
    return problems


def table(src):
    """Lines of C++, Python and LCM types per folder of the layout."""
    groups = ["lcmtypes", "common/physics", "common/io", "common/node", "sim", "estimators/prl_bias",
              "estimators/uav_tma", "estimators/model_id", "estimators/diagnosis", "loggers",
              "scripts/compose/mains", "scripts/compose", "scripts", "test"]
    count = {g: 0 for g in groups}
    for _, p in tracked(src):
        if not p.endswith((".cpp", ".hpp", ".h", ".py", ".lcm")) and not (p.startswith("scripts/") and "." not in os.path.basename(p)):
            continue
        if p.startswith("test/data/") or "/corpus/" in p:
            continue
        g = next((g for g in groups if p.startswith(g + "/")), None)
        if g is None:
            continue
        with open(os.path.join(src, p), "rb") as f:
            count[g] += sum(1 for _ in f)
    for g in groups:
        print("| `%s/` | %d |" % (g, count[g]))


def main(argv):
    if len(argv) != 3 or argv[1] not in ("check", "table"):
        print(__doc__, file=sys.stderr)
        return 2
    src = argv[2]
    if argv[1] == "table":
        table(src)
        return 0
    problems = check(src)
    for line in problems:
        print("layout: " + line, file=sys.stderr)
    if problems:
        print("layout: %d problem(s)" % len(problems), file=sys.stderr)
        return 1
    print("layout: every rule holds (%d tracked files)" % len(tracked(src)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
