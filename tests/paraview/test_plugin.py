"""The ParaView plugin (paraview/plugin/varsph_filters.py) loaded in pvpython: every filter runs through the
server manager on a synthetic dam-break run (read with ParaView's PVD reader, with the plugin's varsph Run
source, as .pvtu pieces and as a multi-part .pvd) and gives the numbers of the varsph module functions and of
the known synthetic motion; the deviation filter compares only times both runs have."""
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
for name in ("varsphRun", "varsphFreeSurface", "varsphSmoothedPressure", "varsphPressureProbe", "varsphDeviation",
             "varsphDeviationOverTime", "varsphSurgeFront"):
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

# --- varsph Run: a run directory, $VARSPH_RUN_DIR, the working directory; .pvtu pieces; multi-part .pvd ---
run = ns["varsphRun"](RunDirectory=a)
run.UpdatePipelineInformation()
T.check(list(run.TimestepValues) == times, "varsph Run sees the 4 times of the .pvd")
run.UpdatePipeline(0.2)
o = sm.Fetch(run)
ref = V.read_vtu(os.path.join(a, "frames", "dam_000002.vtu"))
T.check(np.array_equal(vtk_to_numpy(o.GetPoints().GetData()), ref.points), "varsph Run at t = 0.2 = frame 2")
run.UpdatePipeline(0.25)
T.check(np.array_equal(vtk_to_numpy(sm.Fetch(run).GetPoints().GetData()), ref.points),
        "varsph Run between frames shows the frame before (t = 0.25 -> 0.2)")
os.environ["VARSPH_TEST_RUN"] = b
envrun = ns["varsphRun"](RunVariable="VARSPH_TEST_RUN")
envrun.UpdatePipelineInformation()
T.check(envrun.GetProperty("ResolvedFile").GetElement(0) == os.path.join(b, "dam.pvd"),
        "empty Run Directory: the run named by $VARSPH_TEST_RUN (%s)" % envrun.GetProperty("ResolvedFile").GetElement(0))
cwd = os.getcwd()
os.chdir(a)
cwdrun = ns["varsphRun"](RunVariable="VARSPH_NOT_SET_ANYWHERE")
cwdrun.UpdatePipelineInformation()
T.check(cwdrun.GetProperty("ResolvedFile").GetElement(0) == os.path.join(a, "dam.pvd"),
        "no Run Directory, no variable: the working directory's run")
os.chdir(cwd)
try:
    V.io.resolve_run("", "VARSPH_NOT_SET_ANYWHERE")
    T.check(False, "resolve_run without any run raises")
except FileNotFoundError as e:
    T.check("VARSPH_NOT_SET_ANYWHERE" in str(e) and "working directory" in str(e), "no run anywhere: %s" % e)

# .pvtu pieces (what a parallel run writes) and a .pvd with two parts per time (a multiblock in ParaView)
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter  # noqa: E402
from vtkmodules.vtkFiltersCore import vtkThreshold  # noqa: E402
pv_dir, mp_dir = os.path.join(tmp, "pieces"), os.path.join(tmp, "parts")
for d in (pv_dir, mp_dir):
    os.makedirs(os.path.join(d, "frames"))
pvtu_entries, part_entries = [], []
for k, (t, path) in enumerate(V.frames_of_run(a)):
    ds = V.read_dataset(path)
    fr_dict = S.frame_dict_of(ds)
    S.write_pvtu(os.path.join(pv_dir, "frames", "dam_%06d.pvtu" % k), fr_dict)
    pvtu_entries.append('<DataSet timestep="%.17g" part="0" file="frames/dam_%06d.pvtu"/>' % (t, k))
    for part, (lo, hi) in enumerate(((0, 0), (1, 1))):
        th = vtkThreshold()
        th.SetInputData(ds)
        th.SetInputArrayToProcess(0, 0, 0, 0, "kind")
        th.SetLowerThreshold(lo)
        th.SetUpperThreshold(hi)
        th.Update()
        th.GetOutput().GetFieldData().ShallowCopy(ds.GetFieldData())
        w2 = vtkXMLUnstructuredGridWriter()
        w2.SetFileName(os.path.join(mp_dir, "frames", "dam_%06d_%d.vtu" % (k, part)))
        w2.SetInputData(th.GetOutput())
        w2.Write()
        part_entries.append('<DataSet timestep="%.17g" part="%d" file="frames/dam_%06d_%d.vtu"/>' % (t, part, k, part))
for d, entries in ((pv_dir, pvtu_entries), (mp_dir, part_entries)):
    with open(os.path.join(d, "dam.pvd"), "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n<Collection>\n%s\n'
                '</Collection>\n</VTKFile>\n' % "\n".join(entries))
frame1 = V.read_vtu(os.path.join(a, "frames", "dam_000001.vtu"))
expect = int(V.free_surface(frame1).sum())
for label, src in (("varsph Run on .pvtu pieces", ns["varsphRun"](RunDirectory=pv_dir)),
                   ("PVD reader on .pvtu pieces", simple.PVDReader(FileName=os.path.join(pv_dir, "dam.pvd"))),
                   ("PVD reader, two parts per time (multiblock)",
                    simple.PVDReader(FileName=os.path.join(mp_dir, "dam.pvd")))):
    f = ns["varsphFreeSurface"](Input=src)
    f.UpdatePipeline(0.1)
    got = vtk_to_numpy(sm.Fetch(f).GetPointData().GetArray("free_surface"))
    T.check(int(got.sum()) == expect and len(got) == len(frame1),
            "%s: Free Surface flags %d of %d particles (single .vtu: %d of %d)"
            % (label, got.sum(), len(got), expect, len(frame1)))

# --- Free Surface port names; Smoothed Pressure --------------------------------------------------------
T.check([fs.SMProxy.GetOutputPortName(i) for i in range(2)] == ["Particles", "Surface"],
        "Free Surface output ports are named Particles, Surface")
sp = ns["varsphSmoothedPressure"](Input=ra)
sp.UpdatePipeline(0.0)
o = sm.Fetch(sp)
got = vtk_to_numpy(o.GetPointData().GetArray("pressure_smoothed"))
f0 = V.read_vtu(os.path.join(a, "frames", "dam_000000.vtu"))
T.check(np.allclose(got, V.smooth_field(f0, "pressure"), rtol=1e-12, atol=1e-9), "Smoothed Pressure = varsph.smooth_field")
# hydrostatic block: away from the free surface and the walls the smoothed field is the hydrostatic line
R = V.kernel_from_fields(f0.fields).support_radius
x = f0.points
inner = f0.fluid_mask() & (x[:, 0] > x[f0.fluid_mask(), 0].min() + R) & (x[:, 0] < x[f0.fluid_mask(), 0].max() - R) \
    & (x[:, 1] > R) & (x[:, 1] < x[f0.fluid_mask(), 1].max() - R)
H = x[f0.fluid_mask(), 1].max() + 0.5 * dx
err = np.abs(got[inner] - 1000 * 9.81 * (20 * dx - x[inner, 1])).max() / (1000 * 9.81 * H)
T.check(inner.sum() > 10 and err < 0.01, "smoothed hydrostatic pressure within 1 %% of rho g H at %d interior particles "
        "(max error %.2e)" % (inner.sum(), err))

# --- Deviation: only common times ----------------------------------------------------------------------
c = os.path.join(tmp, "c")
S.dam_break_run(c, nframes=3, dx=dx, shift=shift)       # B ends at 0.2, A at 0.3
rc = simple.PVDReader(FileName=os.path.join(c, "dam.pvd"))
dv = ns["varsphDeviation"](Input=ra, Reference=rc)
dv.UpdatePipelineInformation()
T.check(list(dv.TimestepValues) == times[:3], "Deviation time steps = the 3 common times %s" % list(dv.TimestepValues))
dv.UpdatePipeline(0.3)
o = sm.Fetch(dv)
fd = o.GetFieldData()
T.check(fd.GetArray("t_compared").GetValue(0) == 0.2 and fd.GetArray("t_end_B").GetValue(0) == 0.2
        and fd.GetArray("t_end_A").GetValue(0) == times[-1] and fd.GetArray("n_common").GetValue(0) == 3,
        "asked for t = 0.3 (B has no frame): compares at 0.2, the last common time, and says so")
T.close(fd.GetArray("D_max").GetValue(0), L, 1e-9, "D_max at the last common time = |shift|")
dv.UpdatePipeline(0.15)
T.check(sm.Fetch(dv).GetFieldData().GetArray("t_compared").GetValue(0) == 0.1, "t = 0.15 -> common time 0.1")
dv.CompareAt = "Last Common Time"
dv.UpdatePipeline(0.0)
T.check(sm.Fetch(dv).GetFieldData().GetArray("t_compared").GetValue(0) == 0.2,
        "Compare At = Last Common Time: 0.2 whatever the animation time")
T.finish(tmp)
