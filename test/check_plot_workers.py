#!/usr/bin/python3
"""ctest python.plot_workers: scripts/plot_prl.py draws its figures in forked processes
(draw_all); every job runs once, and a drawing process that dies fails the plotting with
BrokenProcessPool instead of leaving scripts/run waiting for it. Usage: check_plot_workers.py
SOURCE_DIR (loads SOURCE_DIR/scripts/plot_prl.py as the module plot_prl)."""
import importlib.util
import os
import sys
import tempfile
import time
from concurrent.futures.process import BrokenProcessPool

SRC = sys.argv[1]
sys.path.insert(0, os.path.join(SRC, "scripts"))
spec = importlib.util.spec_from_file_location("plot_prl", os.path.join(SRC, "scripts", "plot_prl.py"))
plot_prl = importlib.util.module_from_spec(spec)
sys.modules["plot_prl"] = plot_prl  # the forked workers find draw_all's function by this name
spec.loader.exec_module(plot_prl)

fails = []
tmp = tempfile.mkdtemp()


def touch(path):
    time.sleep(0.05)
    with open(path, "w") as f:
        f.write(str(os.getpid()))


def die():
    os._exit(9)  # as a process killed by the kernel: no exception, no result


# every job drawn once, whichever process draws it (more jobs than cores)
paths = [os.path.join(tmp, "fig%d" % i) for i in range(7)]
plot_prl.draw_all([(touch, (p,), p) for p in paths])
missing = [p for p in paths if not os.path.exists(p)]
if missing:
    fails.append("draw_all left %d of %d figures undrawn: %s" % (len(missing), len(paths), missing))

# a worker that dies: an error within seconds (multiprocessing.Pool waits for ever); the cap of
# 60 s is far above the pool's start-up and the jobs' 0.1 s
if (os.cpu_count() or 1) > 1:
    t0 = time.time()
    try:
        plot_prl.draw_all([(touch, (paths[0],), "a"), (die, (), "b"), (touch, (paths[1],), "c")])
        fails.append("a drawing process that died went unnoticed")
    except BrokenProcessPool:
        pass
    if time.time() - t0 > 60:
        fails.append("the dead drawing process was noticed only after %.0f s" % (time.time() - t0))
else:
    print("one core: draw_all draws in this process, no worker to die (not tested)")

for f in fails:
    print("FAIL: " + f)
print("%d failure(s)" % len(fails))
sys.exit(1 if fails else 0)
