#!/usr/bin/env python3
"""ctest meta.no_shared_paths and meta.data_checksums: the repository stands alone.

  paths  No file of the checkout (tracked, or new and not ignored: `git ls-files --cached
         --others --exclude-standard`; without git, every file outside build folders) names the
         folder `shared` beside the checkout, which a clone does not have, nor its subfolders
         (data, docs, seed) by any other route. The patterns are assembled below from pieces, so
         this file does not name them itself.
  data   The real recordings in test/data: every folder's README.md lists its files in a table
         with their size in bytes and SHA-256, and the files match it; every file of the folder
         is listed; the folders the tests and docs use (autoferry, adsb) are there.

Usage: check_standalone.py paths|data SOURCE_DIR
"""
import hashlib
import os
import re
import subprocess
import sys

MODE, SRC = sys.argv[1], os.path.abspath(sys.argv[2])
DATA = os.path.join(SRC, "test", "data")
FOLDERS = ["autoferry", "adsb", "uav_pf"]  # read by the tests, docs and scripts
fails = []


def fail(what):
    fails.append(what)
    print("FAIL: " + what, flush=True)


def checkout_files():
    """The files of the checkout, relative to SRC."""
    try:
        r = subprocess.run(["git", "-C", SRC, "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                           stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        if r.returncode == 0 and r.stdout:
            return [p for p in r.stdout.decode("utf-8", "surrogateescape").split("\0") if p]
    except FileNotFoundError:  # no git
        pass
    out = []  # not a git checkout (e.g. an unpacked archive): every file but build output
    for root, dirs, files in os.walk(SRC):
        dirs[:] = [d for d in dirs if d != ".git" and d != "out" and not d.startswith("build")
                   and d != "__pycache__" and not os.path.exists(os.path.join(root, d, "CMakeCache.txt"))]
        out += [os.path.relpath(os.path.join(root, f), SRC) for f in files]
    return out


def check_paths():
    sib = "shar" + "ed"
    patterns = [b".." + b"/" + sib.encode()] + [(sib + "/" + sub + "/").encode() for sub in ("data", "docs", "seed")]
    files = checkout_files()
    if len(files) < 100:
        fail("only %d files found in %s (the listing is broken?)" % (len(files), SRC))
    for rel in sorted(files):
        path = os.path.join(SRC, rel)
        if not os.path.isfile(path) or os.path.islink(path):
            continue
        with open(path, "rb") as f:
            data = f.read()
        for pat in patterns:
            i = data.find(pat)
            if i >= 0:
                line = data.count(b"\n", 0, i) + 1
                fail("%s:%d names '%s', outside the checkout (use the path in the repository: test/data/..., "
                     "docs/method.md)" % (rel, line, pat.decode()))
                break
    print("check_standalone: %d files read" % len(files))


# A table row: | file | ... | bytes | `sha256` |  (one line; the cells between are free)
ROW = re.compile(r"^\|[ \t]*([^|\s]+)[ \t]*\|(?:[^|\n]*\|)*?[ \t]*([\d,]+)[ \t]*\|[ \t]*`([0-9a-f]{64})`[ \t]*\|[ \t]*$",
                 re.M)


def check_data():
    if not os.path.isdir(DATA):
        fail("no %s: the recordings the tests and docs use are missing" % DATA)
        return
    folders = sorted(d for d in os.listdir(DATA) if os.path.isdir(os.path.join(DATA, d)))
    for need in FOLDERS:
        if need not in folders:
            fail("test/data/%s is missing" % need)
    for d in folders:
        top = os.path.join(DATA, d)
        readme = os.path.join(top, "README.md")
        if not os.path.isfile(readme):
            fail("test/data/%s has no README.md (licence, provenance, checksums)" % d)
            continue
        text = open(readme, encoding="utf-8").read()
        if not re.search(r"^#+ Licen[cs]e", text, re.M):
            fail("test/data/%s/README.md has no licence section" % d)
        rows = ROW.findall(text)
        if not rows:
            fail("test/data/%s/README.md lists no file with its bytes and sha256" % d)
        listed = set()
        for name, size, sha in rows:
            listed.add(name)
            path = os.path.join(top, name)
            if not os.path.isfile(path):
                fail("test/data/%s/%s: listed in its README, missing" % (d, name))
                continue
            data = open(path, "rb").read()
            if len(data) != int(size.replace(",", "")):
                fail("test/data/%s/%s: %d bytes, its README says %s" % (d, name, len(data), size))
            got = hashlib.sha256(data).hexdigest()
            if got != sha:
                fail("test/data/%s/%s: sha256 %s, its README says %s" % (d, name, got, sha))
        for root, _, files in os.walk(top):
            for f in files:
                rel = os.path.relpath(os.path.join(root, f), top)
                if rel != "README.md" and rel not in listed:
                    fail("test/data/%s/%s is not listed in its README (with bytes and sha256)" % (d, rel))
        print("check_standalone: test/data/%s: %d files checked" % (d, len(rows)))


{"paths": check_paths, "data": check_data}[MODE]()
print("%d failure(s)" % len(fails))
sys.exit(1 if fails else 0)
