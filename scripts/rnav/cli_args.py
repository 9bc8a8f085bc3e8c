"""Command-line handling shared by the Python programs in scripts/ (the studies, sweep,
flightgen.py, ...): argparse with the project's conventions, the Python twin of scripts/cli.bash
and common/io/cli.hpp.

* -h/--help prints the usage and every option with its default on stdout;
* --list-options prints each option name (and its value's placeholder), one per line;
* errors print as "PROGRAM: error: message" (once; exit status 2), an unknown option with the
  nearest known one (the edit-distance rule of common/io/did_you_mean.hpp);
* no abbreviations: an option is spelt out or is unknown.
The scripts' messages on stderr go through die(), log() and progress(), each given the program
name that prefixes its lines (e.g. die = functools.partial(cli_args.die, PROG)).
"""

import argparse
import sys


def die(prog, msg, code=2):
    """Print 'PROG: error: MSG' on stderr and exit with CODE (2: input refused)."""
    sys.stderr.write("%s: error: %s\n" % (prog, msg))
    sys.exit(code)


def log(prog, msg):
    """Print 'PROG: MSG' on stderr at once."""
    sys.stderr.write("%s: %s\n" % (prog, msg))
    sys.stderr.flush()


def progress(prog, msg):
    """A study_runner progress line (one per job done, with the ETA) as log() prints it; not the
    'job NAME' line of each start."""
    if not msg.startswith("job "):
        log(prog, msg)


def doc_help(doc, argv):
    """For the figure programs, whose help is their docstring: with -h or --help among argv[1:],
    print the docstring on stdout with its "Usage:" line first, and exit 0. Called before
    matplotlib is imported, so the help needs neither it nor numpy."""
    if not any(a in ("-h", "--help") for a in argv[1:]):
        return
    lines = doc.strip().splitlines()
    usage = next((i for i, l in enumerate(lines) if l.lower().startswith("usage:")), None)
    if usage is not None:
        head = "Usage: " + lines[usage].split(":", 1)[1].strip()
        rest = lines[:usage] + lines[usage + 1:]
        lines = [head, ""] + [l for l in rest]
    sys.stdout.write("\n".join(lines).rstrip() + "\n")
    sys.exit(0)


def edit_distance(a, b):
    """Fewest insertions, deletions, substitutions and swaps of adjacent characters from a to b."""
    d = [[0] * (len(b) + 1) for _ in range(len(a) + 1)]
    for i in range(len(a) + 1):
        d[i][0] = i
    for j in range(len(b) + 1):
        d[0][j] = j
    for i in range(1, len(a) + 1):
        for j in range(1, len(b) + 1):
            cost = 0 if a[i - 1] == b[j - 1] else 1
            d[i][j] = min(d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost)
            if i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                d[i][j] = min(d[i][j], d[i - 2][j - 2] + 1)
    return d[len(a)][len(b)]


def closest(word, candidates):
    """The candidate at most max(1, n // 3) edits from word (n: its length without leading '-'),
    the first of equally near ones; None if there is none."""
    limit = max(1, len(word.lstrip("-")) // 3)
    best, best_d = None, limit + 1
    for c in candidates:
        if c == word:
            continue
        x = edit_distance(word, c)
        if x < best_d:
            best, best_d = c, x
    return best


def did_you_mean(word, candidates):
    c = closest(word, candidates)
    return " (did you mean '%s'?)" % c if c else ""


class _Formatter(argparse.RawDescriptionHelpFormatter):
    """Descriptions as written; '(default: X)' after every option that has a value default."""

    def _get_help_string(self, action):
        h = action.help or ""
        d = action.default
        if "%(default)" not in h and action.nargs != 0 and d not in (None, "", argparse.SUPPRESS):
            h += " (default: %(default)s)"
        return h


class _ListOptions(argparse.Action):
    def __call__(self, parser, namespace, values, option_string=None):
        for a in parser._actions:
            for s in a.option_strings:
                takes = a.nargs != 0
                meta = a.metavar or (a.dest.upper() if takes else None)
                print(s + (" " + meta if meta else ""))
        parser.exit(0)


class ArgumentParser(argparse.ArgumentParser):
    def __init__(self, prog, description, epilog=None):
        super().__init__(prog=prog, description=description, epilog=epilog,
                         formatter_class=_Formatter, allow_abbrev=False)
        self.add_argument("--list-options", action=_ListOptions, nargs=0, default=argparse.SUPPRESS,
                          help="print the option names, one per line, and exit")

    def error(self, message):
        sys.stderr.write("%s: error: %s\n" % (self.prog, message))
        sys.exit(2)

    def parse_args(self, args=None, namespace=None):
        ns, rest = self.parse_known_args(args, namespace)
        if rest:
            # every unknown option named in one error (a word after one may be its value: the
            # unexpected arguments are named only when there is no unknown option)
            names = [s for a in self._actions for s in a.option_strings]
            unknown = [(r, did_you_mean(r.split("=", 1)[0], names)) for r in rest
                       if r.startswith("-") and len(r) > 1 and not r[1].isdigit()]
            if unknown:
                self.error("unknown option%s %s%s" % (
                    "s" if len(unknown) > 1 else "", ", ".join("'%s'%s" % u for u in unknown),
                    "" if all(h for _, h in unknown) else " (see %s --help)" % self.prog))
            self.error("unexpected argument '%s' (see %s --help)" % (rest[0], self.prog))
        return ns
