"""Lean frames (issue 35, point 3): output.static_boundary = "once" on a real 3D solver run (the DualSPHysics
3D dam break, tank + block obstacle, coarsened to dx = 0.04 m) against the same run writing every particle in
every frame. Checks:
- the static walls are written once (frames/NAME_static_000000.vtu), listed as part 1 of every time step of
  the .pvd, and named in each lean frame's field data `static_boundary`;
- a lean frame is under half the bytes of a full one (prints both: the figures of docs/results.md);
- read back, a lean time step is the full frame: the same ids, positions, kinds and bodies, through
  varsph.io (postprocess, filters), through ParaView's own .pvd reader and through the varsph Run source;
- the pressure state draws the walls and the obstacle of the lean run; `varsph compare` of the two runs
  gives D_max = 0 at every common time.
Usage: xvfb-run -a -s "-noreset -screen 0 1280x1024x24" pvpython test_lean_frames.py VARSPH_EXE"""
import glob
import os
import subprocess
import sys

import numpy as np

import tcommon as T
from varsph import io

exe = sys.argv[1]
tmp = T.workdir("lean")
scene = os.path.join(T.REPO, "pipelines", "dam_break_3d_dsph.json")
common = ["--set", "particles.spacing=0.04", "--set", "time.end=0.02", "--set", "output.every=0.01", "--threads", "1",
          "--quiet", "--overwrite"]
runs = {}
for mode in ("every_frame", "once"):
    runs[mode] = os.path.join(tmp, mode)
    p = subprocess.run([exe, "run", scene, "-o", runs[mode], "--set", "output.static_boundary=\"%s\"" % mode] + common,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
    T.check(p.returncode == 0, "varsph run with output.static_boundary = %s exits 0 (%d) %s"
            % (mode, p.returncode, p.stdout[-500:]))
full, lean = runs["every_frame"], runs["once"]
statics = sorted(glob.glob(os.path.join(lean, "frames", "*_static_*.vtu")))
T.check([os.path.basename(s) for s in statics] == ["dam_break_3d_dsph_static_000000.vtu"],
        "the static walls written once: %s" % [os.path.basename(s) for s in statics])
with open(os.path.join(lean, "dam_break_3d_dsph.pvd")) as f:
    pvd = f.read()
T.check(pvd.count('part="1" file="frames/dam_break_3d_dsph_static_000000.vtu"') == 3,
        "the .pvd lists them as part 1 of each of the 3 time steps")
T.check(not glob.glob(os.path.join(full, "frames", "*_static_*")) and 'part="1"' not in
        open(os.path.join(full, "dam_break_3d_dsph.pvd")).read(), "every_frame: no static file, no part 1")

frames_full, frames_lean = io.frames_of_run(full), io.frames_of_run(lean)
T.check([t for t, _ in frames_full] == [t for t, _ in frames_lean] and len(frames_lean) == 3,
        "the same 3 frame times %s" % [t for t, _ in frames_lean])
b_full = np.mean([os.path.getsize(p) for _, p in frames_full])
b_lean = np.mean([os.path.getsize(p) for _, p in frames_lean])
b_static = os.path.getsize(statics[0]) if statics else 0
print("bytes per frame: every_frame %.0f, once %.0f (+ %.0f once for the static walls)" % (b_full, b_lean, b_static))
T.check(b_lean < 0.5 * b_full, "a lean frame is %.0f %% of a full one (< 50 %%)" % (100 * b_lean / b_full))


def by_id(frame):
    order = np.argsort(frame.arrays["id"])
    return {k: np.asarray(frame.arrays[k])[order] for k in ("id", "kind", "body")}, frame.points[order]


for (t, pf), (_, pl) in zip(frames_full, frames_lean):
    a, xa = by_id(io.read_vtu(pf, t))
    b, xb = by_id(io.read_vtu(pl, t))
    same = len(xa) == len(xb) and all(np.array_equal(a[k], b[k]) for k in a) and np.array_equal(xa, xb)
    T.check(same, "t = %g: the lean time step read back is the full frame (%d vs %d particles)" % (t, len(xb), len(xa)))

from varsph import pvstate  # noqa: E402
s = pvstate.pv()
from paraview import servermanager as sm  # noqa: E402
t = frames_full[-1][0]
native = {}
for name, run in (("full", full), ("lean", lean)):
    r = s.OpenDataFile(os.path.join(run, "dam_break_3d_dsph.pvd"))
    r.UpdatePipeline(t)
    native[name] = r.GetDataInformation().GetNumberOfPoints()
T.check(native["full"] == native["lean"] > 0, "ParaView's own .pvd reader: %s points" % native)
rr = s.varsphRun(RunDirectory=lean)
rr.UpdatePipeline(t)
d = sm.Fetch(rr)
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
part = vtk_to_numpy(d.GetPointData().GetArray("part"))
T.check(d.GetNumberOfPoints() == native["full"] and set(np.unique(part)) == {0, 1, 2},
        "varsph Run of the lean run: every particle, parts %s" % sorted(set(np.unique(part))))
s.ResetSession()
view = pvstate.pressure_state(lean, view=pvstate.new_view((800, 500)))
n = {k: s.FindSource(k).GetDataInformation().GetNumberOfPoints() for k in ("Walls", "Obstacles", "Fluid")}
T.check(min(n.values()) > 0, "the pressure state of the lean run draws walls, obstacle and fluid: %s" % n)
p = subprocess.run([exe, "compare", full, lean, "-o", os.path.join(tmp, "cmp")], stdout=subprocess.PIPE,
                   stderr=subprocess.STDOUT, text=True, timeout=120)
rows = np.loadtxt(os.path.join(tmp, "cmp", "deviation.csv"), delimiter=",", skiprows=1, ndmin=2) \
    if p.returncode == 0 else np.zeros((0, 2))
T.check(p.returncode == 0 and len(rows) == 3 and np.all(rows[:, 1] == 0.0),
        "varsph compare full vs lean: D_max = 0 at the 3 common times (%s)" % p.stdout[-300:])
T.finish(tmp)
