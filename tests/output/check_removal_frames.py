"""Reads a run whose health rules removed particles (tests/output/thrown_block.json) with pvpython, the way
a user opens it in ParaView: the .pvd series through ParaView's reader, every frame, a Threshold on `kind`
over time and the plugin's Surge Front over all frames. Checks that the particle count of every frame is
the diagnostics.csv count, that a removed particle (removed.csv) is absent from every later frame and
present in every earlier one, that ids stay unique and the survivors' ids only shrink.
Usage: pvpython check_removal_frames.py RUN_DIR NAME DOMAIN_TOP"""
import csv
import json
import os
import sys

import numpy as np
from paraview import servermanager as sm
from paraview import simple
from vtkmodules.util.numpy_support import vtk_to_numpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "paraview"))
from varsph.compat import load_plugin  # noqa: E402

run, name, ymax = sys.argv[1], sys.argv[2], float(sys.argv[3])
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def table(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return rows


diag = table(os.path.join(run, "diagnostics.csv"))
removed = table(os.path.join(run, "removed.csv"))
info = json.load(open(os.path.join(run, "run.json")))
n_boundary = info["resolved"]["boundary_particles"]
n0 = info["health"]["fluid_particles_initial"]
check(len(removed) > 0, "the run removed no particle: the check would not test anything")
check(info["health"]["removed_total"] == len(removed), "run.json removed_total %s != removed.csv rows %d"
      % (info["health"]["removed_total"], len(removed)))

reader = simple.PVDReader(FileName=os.path.join(run, name + ".pvd"))
times = list(reader.TimestepValues)
check(len(times) == len(diag), "%d frames in the pvd, %d diagnostics rows" % (len(times), len(diag)))
fluid_counts, prev = [], None
for k, t in enumerate(times):
    reader.UpdatePipeline(t)
    data = sm.Fetch(reader)
    n = data.GetNumberOfPoints()
    pd = data.GetPointData()
    ids = vtk_to_numpy(pd.GetArray("id"))
    kind = vtk_to_numpy(pd.GetArray("kind"))
    want = int(diag[k]["fluid_particles"])
    fluid_counts.append(want)
    check(n == want + n_boundary, "t=%g: %d points, diagnostics says %d fluid + %d boundary" % (t, n, want, n_boundary))
    check(int((kind == 0).sum()) == want, "t=%g: %d fluid points, expected %d" % (t, (kind == 0).sum(), want))
    check(len(np.unique(ids)) == n, "t=%g: ids are not unique" % t)
    for a in ("velocity", "density", "pressure"):
        check(np.all(np.isfinite(vtk_to_numpy(pd.GetArray(a)))), "t=%g: non-finite %s" % (t, a))
    check(want + sum(int(diag[k]["removed_" + r]) for r in ("domain", "density", "speed")) == n0,
          "t=%g: fluid + removed != initial fluid" % t)
    fluid = set(int(i) for i in ids[kind == 0])
    # by step (VTU field data), not by the .pvd time, which is rounded to the output interval
    step = int(data.GetFieldData().GetArray("step").GetValue(0))
    gone = set(int(r["id"]) for r in removed if int(r["step"]) <= step)
    kept = set(int(r["id"]) for r in removed if int(r["step"]) > step)
    check(not (fluid & gone), "t=%g: removed particles still in the frame: %s" % (t, sorted(fluid & gone)[:5]))
    check(kept <= fluid, "t=%g: particles removed later are missing: %s" % (t, sorted(kept - fluid)[:5]))
    if prev is not None:
        check(fluid <= prev, "t=%g: new fluid ids appeared" % t)
    prev = fluid
check(fluid_counts[0] == n0 and fluid_counts[-1] < n0, "fluid counts over the frames: %s" % fluid_counts)

# a filter pipeline over frames with different point counts
thr = simple.Threshold(Input=reader, Scalars=["POINTS", "kind"])
if hasattr(thr, "LowerThreshold"):
    thr.LowerThreshold, thr.UpperThreshold = 0, 0
else:
    thr.ThresholdRange = [0, 0]
for k, t in enumerate(times):
    thr.UpdatePipeline(t)
    got = sm.Fetch(thr).GetNumberOfPoints()
    check(got == fluid_counts[k], "t=%g: Threshold kind == 0 gives %d points, expected %d" % (t, got, fluid_counts[k]))

# the plugin's Surge Front along y over the whole series: the top of the water, never above the domain
ns = {"_": 1}
load_plugin(ns=ns)
sf = ns["varsphSurgeFront"](Input=reader, Axis=1)
sf.UpdatePipeline(times[-1])
tab = sm.Fetch(sf)
cols = [tab.GetColumnName(i) for i in range(tab.GetNumberOfColumns())]
rows = tab.GetNumberOfRows()
check(rows == len(times), "Surge Front table has %d rows for %d frames" % (rows, len(times)))
top = [tab.GetValue(r, cols.index("front_x")).ToDouble() for r in range(rows)]
check(all(np.isfinite(top)) and max(top) <= ymax + 1e-9, "Surge Front top of the water %s (domain top %g)" % (top, ymax))

if failures:
    print("FAILED:\n  " + "\n  ".join(failures))
    sys.exit(1)
print("ok: %d frames, fluid particles %s, %d removed, Threshold and Surge Front over the series" %
      (len(times), fluid_counts, len(removed)))
