"""What the figure programs of a run (loggers/plot_prl.py, loggers/plot_uav.py) share: matplotlib
without a display, and the error of a missing or malformed input.

    from rnav import figures
    PROG = "plot_x.py"
    plt = figures.pyplot(PROG)     # exits with a message if numpy or matplotlib is missing
    InputError = figures.InputError
"""

import sys


class InputError(Exception):
    """A missing or malformed input of a figure program: the message names the file (and line,
    column); the program prints it as 'PROG: error: MESSAGE' and exits 2."""


def pyplot(prog):
    """matplotlib.pyplot on the Agg backend (no display needed), numpy checked to be there too.
    Without either (the python3 first on PATH may be a build without them) exits with 'PROG:
    REASON; run with /usr/bin/python3 (Debian python3-numpy, python3-matplotlib)'."""
    try:
        import numpy  # noqa: F401  (every figure program draws numpy arrays)
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        sys.exit("%s: %s; run with /usr/bin/python3 (Debian python3-numpy, "
                 "python3-matplotlib)" % (prog, e))
    return plt
