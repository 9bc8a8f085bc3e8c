"""What the figure programs of a run (scripts/plot_prl.py, scripts/plot_uav.py) share: matplotlib
without a display, and the error of a missing or malformed input.

    from rnav import figures
    PROG = "plot_x.py"
    plt = figures.pyplot(PROG)     # exits with a message if numpy or matplotlib is missing
    InputError = figures.InputError
"""

import os
import sys

from . import interpreter


class InputError(Exception):
    """A missing or malformed input of a figure program: the message names the file (and line,
    column); the program prints it as 'PROG: error: MESSAGE' and exits 2."""


def pyplot(prog):
    """matplotlib.pyplot on the Agg backend (no display needed), numpy checked to be there too.
    Without either (the python3 first on PATH may be a build without them) the program PROG runs
    again under Debian's /usr/bin/python3 (rnav.interpreter); where that cannot be (it is Debian's
    already, or PROG is not the program running) exits with 'PROG: REASON; run with
    /usr/bin/python3 (Debian python3-numpy, python3-matplotlib)'."""
    try:
        import numpy  # noqa: F401  (every figure program draws numpy arrays)
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        # the python3 first on PATH: the program hands itself over to Debian's (rnav.interpreter)
        if os.path.basename(sys.argv[0]) == prog:
            interpreter.hand_over([os.path.abspath(sys.argv[0])] + sys.argv[1:])
        sys.exit("%s: %s; run with /usr/bin/python3 (Debian python3-numpy, "
                 "python3-matplotlib)" % (prog, e))
    return plt
