"""Reads a varsph run directory with pvpython (data only) and checks it against CONTRACT.md:
the .pvd time series, VTU point arrays and field data, particle counts, diagnostics.csv columns, run.json.
Usage: pvpython check_run_output.py RUN_DIR NAME N_FLUID N_BOUNDARY N_FRAMES"""
import csv
import json
import os
import sys

from paraview import simple
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy
import numpy as np

run, name = sys.argv[1], sys.argv[2]
n_fluid, n_boundary, n_frames = (int(a) for a in sys.argv[3:6])
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


reader = simple.OpenDataFile(os.path.join(run, name + ".pvd"))
times = list(reader.TimestepValues) if hasattr(reader.TimestepValues, "__len__") else [reader.TimestepValues]
check(len(times) == n_frames, "expected %d frames, the pvd lists %d" % (n_frames, len(times)))
check(all(b > a for a, b in zip(times, times[1:])), "frame times must increase: %s" % times)

for t in (times[0], times[-1]):
    reader.UpdatePipeline(t)
    data = servermanager.Fetch(reader)
    if data.IsA("vtkMultiBlockDataSet"):
        data = data.GetBlock(0)
    n = data.GetNumberOfPoints()
    check(n == n_fluid + n_boundary, "t=%g: %d points, expected %d" % (t, n, n_fluid + n_boundary))
    pd = data.GetPointData()
    comps = {"velocity": 3, "density": 1, "pressure": 1, "mass": 1, "id": 1, "kind": 1, "normal": 3}
    for arr, c in comps.items():
        a = pd.GetArray(arr)
        check(a is not None, "t=%g: point array '%s' missing" % (t, arr))
        if a is not None:
            check(a.GetNumberOfComponents() == c, "'%s' has %d components, expected %d" % (arr, a.GetNumberOfComponents(), c))
    kind = vtk_to_numpy(pd.GetArray("kind"))
    check(int((kind == 0).sum()) == n_fluid and int((kind == 1).sum()) == n_boundary, "kind counts wrong")
    ids = vtk_to_numpy(pd.GetArray("id"))
    check(len(np.unique(ids)) == n, "ids are not unique")
    check(np.all(np.isfinite(vtk_to_numpy(pd.GetArray("pressure")))), "non-finite pressure")
    nrm = vtk_to_numpy(pd.GetArray("normal"))
    check(np.allclose(np.linalg.norm(nrm[kind == 1], axis=1), 1.0, atol=1e-5), "boundary normals are not unit vectors")
    fd = data.GetFieldData()
    for key in ("time", "step", "dx", "h", "kernel", "rho0", "c0", "dimension"):
        check(fd.GetAbstractArray(key) is not None, "field data '%s' missing" % key)
    if fd.GetArray("time") is not None:
        check(abs(fd.GetArray("time").GetValue(0) - t) < 1e-9, "field data time %g != pvd time %g" % (fd.GetArray("time").GetValue(0), t))
    check(abs(fd.GetArray("dx").GetValue(0) - 0.005) < 1e-12, "dx field data")
    check(fd.GetArray("dimension").GetValue(0) == 2, "dimension field data")
    check(fd.GetAbstractArray("kernel").GetValue(0) == "gaussian", "kernel field data")
    check(abs(fd.GetArray("rho0").GetValue(0) - 1000.0) < 1e-12, "rho0 field data")

with open(os.path.join(run, "diagnostics.csv")) as f:
    rows = list(csv.reader(f))
expected = ("frame,step,time,dt,momentum_x,momentum_y,momentum_z,momentum_Q,angular_momentum,kinetic_energy,"
            "potential_energy,internal_energy,max_speed,density_error_max,wall_seconds,fp_iterations_mean,"
            "fp_iterations_max,fp_residual_max,fp_contraction_max,dt_bound,"
            "fluid_particles,removed_domain,removed_density,removed_speed,imbalance,"
            "particles_created,removed_outlet,buffer_particles,mass_in,mass_out,fluid_mass,mass_balance,"
            "bodies_momentum_x,bodies_momentum_y,bodies_momentum_z,bodies_kinetic_energy,bodies_potential_energy").split(",")
check(rows[0] == expected, "diagnostics.csv header %s" % rows[0])
check(len(rows) - 1 == n_frames, "diagnostics.csv has %d rows, expected %d" % (len(rows) - 1, n_frames))
check(all(int(r[20]) == n_fluid and r[21:24] == ["0", "0", "0"] for r in rows[1:]),
      "diagnostics.csv: all fluid particles kept, nothing removed")
with open(os.path.join(run, "removed.csv")) as f:
    removed_rows = list(csv.reader(f))
check(removed_rows == [("time,step,id,rule,x,y,z,vx,vy,vz,density,pressure,fluid_neighbours,"
                        "boundary_neighbours").split(",")], "removed.csv holds only its header")
info = json.load(open(os.path.join(run, "run.json")))
check(info.get("status") == "completed", "run.json status %s" % info.get("status"))
check(info["resolved"]["fluid_particles"] == n_fluid, "run.json fluid count")
check(info["health"]["removed_total"] == 0 and info["health"]["fluid_particles_initial"] == n_fluid,
      "run.json health block %s" % info.get("health"))

if failures:
    print("FAILED:\n  " + "\n  ".join(failures))
    sys.exit(1)
print("run output OK: %d frames, %d + %d particles, arrays, field data, diagnostics, run.json" % (n_frames, n_fluid, n_boundary))
