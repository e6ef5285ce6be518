"""Rigid bodies in the post-processing (docs/bodies.md): a short real run of the flap-gate scene, then
plot_bodies.py writes the motion and load plots (and refuses a malformed --reference with exit 2), and the
plugin's *varsph Body Trajectories* source gives one polyline per body with as many points as bodies.csv
has rows up to the requested time.
Usage: pvpython test_bodies.py VARSPH_EXECUTABLE SCENE.json"""
import csv
import os
import subprocess
import sys

import tcommon as T
from varsph.compat import load_plugin

exe, scene = sys.argv[1], sys.argv[2]
here = os.path.dirname(os.path.abspath(__file__))
pvdir = os.path.join(here, "..", "..", "paraview")
tmp = T.workdir("bodies")
run = os.path.join(tmp, "run")
p = subprocess.run([exe, "run", scene, "-o", run, "--set", "time.end=0.04", "--set", "output.every=0.02",
                    "--set", "output.probes_every=0.004", "--quiet"],
                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
T.check(p.returncode == 0, "varsph run exit status 0 (%d): %s" % (p.returncode, p.stdout[-500:]))
if p.returncode != 0:
    T.finish(tmp)
with open(os.path.join(run, "bodies.csv")) as f:
    rows = list(csv.DictReader(f))
T.check(len(rows) == 11, "bodies.csv: a row at t = 0 and every 0.004 s to 0.04 s (%d rows)" % len(rows))
T.check(abs(float(rows[0]["x"]) - 1.01) < 1e-12, "the gate's centre of mass at x = 1.01 (%s)" % rows[0]["x"])
T.check(os.path.isfile(os.path.join(run, "moorings.csv")), "moorings.csv written for the scene's spring")

sys.path.insert(0, pvdir)
import plot_bodies  # noqa: E402
post = os.path.join(tmp, "post")
os.makedirs(post)
ref = os.path.join(tmp, "ref.csv")
with open(ref, "w") as f:
    f.write("# a made-up reference\nt,angle\n0,0\n0.02,-0.01\n")
written = plot_bodies.figures(run, post, plot_bodies.parse_reference(ref + ":quantity=angle"))
names = sorted(os.path.basename(w) for w in written)
T.check(names == ["body_2_loads.png", "body_2_motion.png", "moorings.png"], "plots written: %s" % names)
for w in written:
    T.check(os.path.getsize(w) > 5000, "%s is a picture (%d bytes)" % (w, os.path.getsize(w)))
bad = subprocess.run([T.pvpython(), os.path.join(pvdir, "plot_bodies.py"), run, "--reference", ref + ":qty=y"],
                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
T.check(bad.returncode == 2 and "unknown key 'qty'" in bad.stdout, "a bad --reference key: exit 2 naming it")

ns = {"_": 1}  # non-empty: LoadPlugin ignores an empty namespace
load_plugin(ns=ns)
from paraview import servermanager as sm  # noqa: E402
from paraview import simple  # noqa: E402
src = ns["varsphBodyTrajectories"](RunDirectory=run)
src.UpdatePipeline(0.02)
d = sm.Fetch(src)
T.check(d.GetNumberOfLines() == 1, "one polyline for the one body (%d)" % d.GetNumberOfLines())
T.check(d.GetNumberOfPoints() == 6, "points up to t = 0.02: rows 0, 0.004, ..., 0.02 (%d)" % d.GetNumberOfPoints())
T.check(d.GetPointData().GetArray("fluid_force") is not None, "point array fluid_force")
T.finish(tmp)
