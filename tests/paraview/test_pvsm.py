"""make_pvsm.py writes .pvsm states for one run; loaded with "search files under specified directory"
(LoadState data_directory) against a copy of the run elsewhere, the reader points into the copy and the
view renders a non-empty image. Usage: xvfb-run -a pvpython test_pvsm.py"""
import os
import shutil
import subprocess

import tcommon as T
import synthetic as S

tmp = T.workdir("pvsm")
a = os.path.join(tmp, "a")
b = os.path.join(tmp, "b")
S.dam_break_run(a, nframes=3)
S.dam_break_run(b, nframes=3, shift=(0.004, 0.0, 0.0))
states = os.path.join(tmp, "states")
p = subprocess.run([T.pvpython(), os.path.join(T.PARAVIEW_DIR, "states", "make_pvsm.py"), a, "--other", b,
                    "-o", states], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
print(p.stdout[-3000:])
T.check(p.returncode == 0, "make_pvsm.py exit status 0 (%d)" % p.returncode)
for n in ("free_surface", "pressure", "deviation"):
    T.check(os.path.isfile(os.path.join(states, n + ".pvsm")), "wrote %s.pvsm" % n)
moved = os.path.join(tmp, "elsewhere", "copy of run")
shutil.copytree(a, moved)
shutil.rmtree(a)                                   # the original is gone: the state must find the copy

from varsph.compat import load_plugin  # noqa: E402
load_plugin(ns={"_": 1})
from paraview import simple  # noqa: E402

for n in ("free_surface", "pressure"):
    simple.ResetSession()
    simple.LoadState(os.path.join(states, n + ".pvsm"), data_directory=moved, restrict_to_data_directory=True)
    reader = simple.FindSource("a")
    T.check(reader is not None and os.path.dirname(reader.FileName) == moved,
            "%s.pvsm: reader now reads %s" % (n, reader.FileName if reader else None))
    png = os.path.join(tmp, n + ".png")
    simple.SaveScreenshot(png, simple.GetActiveViewOrCreate("RenderView"), ImageResolution=[500, 350])
    w, h, ncol, std, col = T.image_stats(png)
    T.check(ncol > 10 and col > 0.01, "%s.pvsm renders %d colours, %.1f %% colour-mapped" % (n, ncol, 100 * col))
T.finish(tmp)
