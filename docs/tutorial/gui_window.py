"""A picture of the whole ParaView window that `varsph paraview RUN [RUN_B] --state NAME` opens (under Xvfb,
from its frame buffer), for docs/tutorial.md.
Usage: pvpython docs/tutorial/gui_window.py VARSPH RUN [RUN_B] --state NAME -o OUT.png"""
import argparse
import os
import shutil
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tests", "paraview"))
import gui  # noqa: E402

ap = argparse.ArgumentParser(description=__doc__)
ap.add_argument("varsph")
ap.add_argument("runs", nargs="+")
ap.add_argument("--state", default="pressure")
ap.add_argument("-o", "--output", required=True)
a = ap.parse_args()
tmp = tempfile.mkdtemp(prefix="varsph_window_")
fb = os.path.join(tmp, "fb")
os.makedirs(fb)
out = os.path.abspath(a.output)
rc, log, rep, _, _ = gui.run(tmp, [os.path.abspath(r) for r in a.runs] + ["--state", a.state, "--"],
                             {"VARSPH_GUI_WINDOW": out, "VARSPH_GUI_FBDIR": fb}, launcher=[a.varsph, "paraview"],
                             screen="1440x900x24", fbdir=fb)
errors = gui.error_lines(log)
if rc != 0 or errors or not rep or not rep.get("ok") or not os.path.isfile(out):
    print(log[-3000:], rep)
    sys.exit("gui_window.py: ParaView exit status %d, errors %s" % (rc, errors[:3]))
print("wrote", out)
shutil.rmtree(tmp, ignore_errors=True)
