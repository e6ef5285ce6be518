"""The ParaView plugin (paraview/varsph_filters.py) loaded in pvpython: every filter runs through the
server manager on a synthetic dam-break run (read with ParaView's PVD reader) and gives the numbers of
the varsph module functions and of the known synthetic motion."""
import os

import numpy as np

import tcommon as T
import synthetic as S
import varsph as V
from varsph.compat import load_plugin

from paraview import servermanager as sm
from paraview import simple

tmp = T.workdir("plugin")
dx = 0.02
a = os.path.join(tmp, "a")
b = os.path.join(tmp, "b")
shift = (0.003, -0.004, 0.0)
S.dam_break_run(a, nframes=4, dx=dx)
S.dam_break_run(b, nframes=4, dx=dx, shift=shift)
times = [0.0, 0.1, 0.2, 0.30000000000000004]

ns = {"_": 1}
load_plugin(ns=ns)
for name in ("varsphFreeSurface", "varsphPressureProbe", "varsphDeviation", "varsphDeviationOverTime",
             "varsphSurgeFront"):
    T.check(name in ns, "plugin defines %s" % name)

ra = simple.PVDReader(FileName=os.path.join(a, "dam.pvd"))
rb = simple.PVDReader(FileName=os.path.join(b, "dam.pvd"))
T.check(list(ra.TimestepValues) == times, "PVD reader sees the 4 times")


def table(proxy):
    t = sm.Fetch(proxy)
    cols = [t.GetColumnName(i) for i in range(t.GetNumberOfColumns())]
    vals = np.array([[t.GetValue(r, c).ToDouble() for c in range(len(cols))] for r in range(t.GetNumberOfRows())])
    return cols, vals


# FreeSurface
fs = ns["varsphFreeSurface"](Input=ra, ReconstructSurface=1)
fs.UpdatePipeline(0.1)
out = sm.Fetch(fs)
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
flag = vtk_to_numpy(out.GetPointData().GetArray("free_surface"))
frame = V.read_vtu(os.path.join(a, "frames", "dam_000001.vtu"))
T.check(np.array_equal(flag, V.free_surface(frame)), "FreeSurface filter = varsph.free_surface at t=0.1 (%d flagged)"
        % flag.sum())
T.check(flag[frame.fluid_mask()].sum() > 0 and flag[~frame.fluid_mask()].sum() == 0, "fluid flagged, boundary not")
surf = sm.Fetch(fs, idx=1)
T.check(surf.IsA("vtkPolyData") and surf.GetNumberOfLines() > 10,
        "FreeSurface port 1 (reconstructed surface) is a contour with %d line segments" % surf.GetNumberOfLines())
ref = V.surface_mesh(frame)
T.check(surf.GetNumberOfPoints() == ref.GetNumberOfPoints(), "port 1 = varsph.surface_mesh (%d points)"
        % ref.GetNumberOfPoints())

# PressureProbe
probes = [0.1, 0.1, 0.0, 0.05, 0.2, 0.0]
pp = ns["varsphPressureProbe"](Input=ra, ProbePoints=probes)
cols, vals = table(pp)
T.check(cols == ["time", "pressure_0", "pressure_1"], "PressureProbe columns %s" % cols)
tt, ref = V.probe_series(a, np.reshape(probes, (-1, 3)))
T.check(vals.shape == (4, 3) and np.allclose(vals[:, 0], tt) and np.allclose(vals[:, 1:], ref, rtol=1e-12),
        "PressureProbe table = varsph.probe_series over the 4 frames")

# Deviation over time and per particle
dv = ns["varsphDeviationOverTime"](Input=ra, Reference=rb)
cols, vals = table(dv)
T.check(cols == ["time", "D_max", "D_mean", "D_rms"], "DeviationOverTime columns %s" % cols)
L = float(np.linalg.norm(shift))
T.check(vals.shape == (4, 4) and np.allclose(vals[:, 1:], L, atol=1e-9, rtol=0),
        "DeviationOverTime: D_max = D_mean = D_rms = |shift| = %g at all 4 times" % L)
dself = ns["varsphDeviationOverTime"](Input=ra, Reference=ra)
cols, vals = table(dself)
T.check(vals.shape == (4, 4) and np.all(vals[:, 1:] == 0), "DeviationOverTime of a run with itself = 0")
dd = ns["varsphDeviation"](Input=ra, Reference=rb)
dd.UpdatePipeline(0.2)
o = sm.Fetch(dd)
mag = vtk_to_numpy(o.GetPointData().GetArray("deviation_magnitude"))
kind = vtk_to_numpy(o.GetPointData().GetArray("kind"))
T.check(np.allclose(mag[kind == 0], L, atol=1e-12), "Deviation filter: |deviation| = |shift| on fluid particles")
T.close(o.GetFieldData().GetArray("D_max").GetValue(0), L, 1e-9, "Deviation filter field data D_max")

# SurgeFront: front = 9.5 dx (1 + 1.5 t); height at x = 0.1: 19.5 dx / (1 + 1.5 t) + dx/2
sf = ns["varsphSurgeFront"](Input=ra, Gauges=[0.1, 5.0])
cols, vals = table(sf)
T.check(cols == ["time", "front_x", "front_rel", "height_x0.1", "height_x5"], "SurgeFront columns %s" % cols)
s = 1 + 1.5 * np.array(times)
T.check(np.allclose(vals[:, 1], 9.5 * dx * s, atol=1e-12), "SurgeFront front_x = 9.5 dx (1 + 1.5 t)")
T.check(np.allclose(vals[:, 2], 9.5 * dx * (s - 1), atol=1e-12), "SurgeFront front_rel from the first frame")
T.check(np.allclose(vals[:, 3], 19.5 * dx / s + 0.5 * dx, atol=1e-12), "SurgeFront water height at x = 0.1")
T.check(np.all(vals[:, 4] == 0), "SurgeFront dry gauge reads 0")
E = __import__("sys").modules["varsph_filters"].EXECUTIONS
before = E.get("SurgeFront", 0)
sf.UpdatePipeline(0.1)
sf.UpdatePipeline(0.2)
T.check(E.get("SurgeFront", 0) == before, "SurgeFront table is not recomputed when the time changes (%d -> %d frames)"
        % (before, E.get("SurgeFront", 0)))
cols2, rows2 = V.surge_series(a, [0.1, 5.0])
T.check(np.allclose(np.asarray(rows2), vals, atol=1e-12), "SurgeFront filter = varsph.surge_series")
T.finish(tmp)
