"""Synthetic varsph runs in the solver's exact output format (for tests, before the solver exists).

RUN/NAME.pvd + RUN/frames/NAME_000000.vtu (vtkUnstructuredGrid, one VTK_VERTEX per point, appended raw
binary), point arrays velocity, density, pressure, mass, id, kind, normal, field data time, dx, h, rho0, c0,
support_radius, step, dimension, kernel; optionally diagnostics.csv and probes.csv.
"""
import math
import os

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkLongLongArray, vtkPoints, vtkStringArray
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid, VTK_VERTEX
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

SUPPORT = {"gaussian": 3.0, "cubic_spline": 2.0, "wendland_c2": 2.0}


def lattice_block(n, dx, origin=(0.0, 0.0, 0.0)):
    """Square lattice of n = (nx, ny) or (nx, ny, nz) particles at spacing dx; (N, 3) points."""
    axes = [origin[k] + dx * (0.5 + np.arange(n[k])) for k in range(len(n))]
    grid = np.meshgrid(*axes, indexing="ij")
    pts = np.zeros((grid[0].size, 3))
    for k in range(len(n)):
        pts[:, k] = grid[k].ravel()
    return pts


def lattice_ball(radius, dx, dimension):
    """Lattice points (spacing dx, a lattice point at the centre) with |x| <= radius; (N, 3)."""
    m = int(math.floor(radius / dx))
    ax = dx * np.arange(-m, m + 1)
    grid = np.meshgrid(*([ax] * dimension), indexing="ij")
    pts = np.zeros((grid[0].size, 3))
    for k in range(dimension):
        pts[:, k] = grid[k].ravel()
    keep = np.linalg.norm(pts, axis=1) <= radius + 1e-12
    return pts[keep]


def make_frame(points, dx, dimension, time=0.0, step=0, kernel="wendland_c2", h_over_dx=1.3, rho0=1000.0,
               c0=20.0, kind=None, velocity=None, pressure=None, density=None, ids=None, normal=None, body=None):
    n = len(points)
    h = h_over_dx * dx
    extra = {} if body is None else {"body": np.asarray(body, dtype=np.int32)}
    return {**extra,
        "points": np.asarray(points, dtype=float),
        "velocity": np.zeros((n, 3)) if velocity is None else np.asarray(velocity, dtype=float),
        "density": np.full(n, rho0) if density is None else np.asarray(density, dtype=float),
        "pressure": np.zeros(n) if pressure is None else np.asarray(pressure, dtype=float),
        "mass": np.full(n, rho0 * dx ** dimension),
        "id": np.arange(n, dtype=np.int64) if ids is None else np.asarray(ids, dtype=np.int64),
        "kind": np.zeros(n, dtype=np.int32) if kind is None else np.asarray(kind, dtype=np.int32),
        "normal": np.zeros((n, 3)) if normal is None else np.asarray(normal, dtype=float),
        "fields": {"time": float(time), "dx": float(dx), "h": float(h), "rho0": float(rho0), "c0": float(c0),
                   "support_radius": SUPPORT[kernel] * h, "step": int(step), "dimension": int(dimension),
                   "kernel": kernel},
    }


def _grid(fr):
    ug = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(fr["points"]), deep=1))
    ug.SetPoints(pts)
    n = len(fr["points"])
    conn = np.empty(2 * n, dtype=np.int64)
    conn[0::2] = 1
    conn[1::2] = np.arange(n)
    cells = vtkCellArray()
    cells.SetCells(n, numpy_to_vtkIdTypeArray(conn, deep=1))
    ug.SetCells(VTK_VERTEX, cells)
    pd = ug.GetPointData()
    for name in ("velocity", "density", "pressure", "mass", "normal"):
        a = numpy_to_vtk(np.ascontiguousarray(fr[name], dtype=np.float64), deep=1)
        a.SetName(name)
        pd.AddArray(a)
    a = vtkLongLongArray()
    a.SetName("id")
    for v in fr["id"]:
        a.InsertNextValue(int(v))
    pd.AddArray(a)
    for name in ("kind", "body") if "body" in fr else ("kind",):
        a = vtkIntArray()
        a.SetName(name)
        for v in fr[name]:
            a.InsertNextValue(int(v))
        pd.AddArray(a)
    fd = ug.GetFieldData()
    for k, v in fr["fields"].items():
        if k == "kernel":
            a = vtkStringArray()
            a.SetName(k)
            a.InsertNextValue(v)
        elif k == "step":
            a = vtkLongLongArray()
            a.SetName(k)
            a.InsertNextValue(v)
        elif k == "dimension":
            a = vtkIntArray()
            a.SetName(k)
            a.InsertNextValue(v)
        else:
            a = vtkDoubleArray()
            a.SetName(k)
            a.InsertNextValue(v)
        fd.AddArray(a)
    return ug


def write_run(run_dir, frames, name="run", diagnostics=True, probes=False):
    """Write ``frames`` (dicts from make_frame) as a run directory; returns the .pvd path."""
    os.makedirs(os.path.join(run_dir, "frames"), exist_ok=True)
    entries = []
    for k, fr in enumerate(frames):
        rel = "frames/%s_%06d.vtu" % (name, k)
        w = vtkXMLUnstructuredGridWriter()
        w.SetFileName(os.path.join(run_dir, rel))
        w.SetInputData(_grid(fr))
        w.SetDataModeToAppended()
        w.EncodeAppendedDataOff()
        if not w.Write():
            raise RuntimeError("could not write " + rel)
        entries.append('    <DataSet timestep="%.17g" group="" part="0" file="%s"/>' % (fr["fields"]["time"], rel))
    pvd = os.path.join(run_dir, name + ".pvd")
    with open(pvd, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
                "  <Collection>\n" + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
    if diagnostics:
        cols = ("frame,step,time,dt,momentum_x,momentum_y,momentum_z,momentum_Q,angular_momentum,kinetic_energy,"
                "potential_energy,internal_energy,max_speed,density_error_max,wall_seconds")
        with open(os.path.join(run_dir, "diagnostics.csv"), "w") as f:
            f.write(cols + ",fp_iterations_mean,fp_iterations_max,fp_residual_max,fp_contraction_max,dt_bound\n")
            for k, fr in enumerate(frames):
                fl = fr["kind"] == 0
                mv = (fr["mass"][fl][:, None] * fr["velocity"][fl]).sum(axis=0)
                Q = np.linalg.norm(mv) / max(1, fl.sum())
                ke = 0.5 * (fr["mass"][fl] * (fr["velocity"][fl] ** 2).sum(1)).sum()
                sp = np.linalg.norm(fr["velocity"][fl], axis=1).max() if fl.any() else 0.0
                f.write("%d,%d,%.17g,1e-4,%.17g,%.17g,%.17g,%.17g,0,%.17g,0,0,%.17g,0,%g,,,,,\n"
                        % (k, fr["fields"]["step"], fr["fields"]["time"], mv[0], mv[1], mv[2], Q, ke, sp, 0.1 * k))
    if probes:
        with open(os.path.join(run_dir, "probes.csv"), "w") as f:
            # columns as the solver names them (docs/results.md): p_NAME, h_NAME, front_x
            f.write("time,p_p0,p_p1,h_g1,front_x\n")
            for fr in frames:
                t = fr["fields"]["time"]
                fx = fr["points"][fr["kind"] == 0, 0].max()
                f.write("%.17g,%.17g,%.17g,%.17g,%.17g\n" % (t, 100 * math.sin(t), 50 * math.cos(t), 0.1 * t, fx))
    return pvd


def dam_break_run(run_dir, nframes=4, dimension=2, dx=0.02, name="dam", with_walls=True, kernel="wendland_c2",
                  shift=(0.0, 0.0, 0.0), probes=True):
    """A small 'collapsing column' run: a fluid block that spreads to the right, plus a floor and a left wall.

    Pressure is hydrostatic (rho0 g (H - y)); positions are a simple affine spreading with time:
    x = x0 (1 + 1.5 t), y = y0 / (1 + 1.5 t); the fluid is then moved by ``shift``."""
    nx, ny = 10, 20
    nz = 4 if dimension == 3 else None
    n = (nx, ny) if dimension == 2 else (nx, ny, nz)
    base = lattice_block(n, dx)
    H = ny * dx
    walls = np.zeros((0, 3))
    if with_walls:
        fl = lattice_block((3 * nx + 6, 3) if dimension == 2 else (3 * nx + 6, 3, nz), dx, (-3 * dx, -3 * dx, 0))
        lw = lattice_block((3, ny + 5) if dimension == 2 else (3, ny + 5, nz), dx, (-3 * dx, 0, 0))
        walls = np.concatenate([fl, lw])
    frames = []
    for k in range(nframes):
        t = 0.1 * k
        s = 1.0 + 1.5 * t
        p = base.copy()
        p[:, 0] *= s
        p[:, 1] /= s
        p += np.asarray(shift, dtype=float)
        vel = np.zeros_like(p)
        vel[:, 0] = 1.5 * base[:, 0]
        vel[:, 1] = -0.5 * base[:, 1]
        pts = np.concatenate([p, walls])
        kind = np.concatenate([np.zeros(len(p)), np.ones(len(walls))])
        velocity = np.concatenate([vel, np.zeros_like(walls)])
        pres = 1000.0 * 9.81 * np.clip(H / s - pts[:, 1], 0, None)
        normal = np.zeros_like(pts)
        normal[len(p):, 1] = 1.0
        frames.append(make_frame(pts, dx, dimension, time=t, step=100 * k, kind=kind, velocity=velocity,
                                 pressure=pres, normal=normal, kernel=kernel))
    return write_run(run_dir, frames, name=name, probes=probes)


def tank3d_run(run_dir, nframes=3, dx=0.02, name="tank3d", with_body=True, layers=2, times=None, every=None):
    """A 3D run a user would make (issue 35): a tall open-top box tank (body 1, ``layers`` layers outside its
    walls) holding a shallow block of water (body 0) and a block obstacle standing in it (body 2). The water
    spreads with time as in dam_break_run; pressure hydrostatic. ``with_body=False``: frames without `body`.
    ``times``: the frames' times (default 0.1 k); ``every``: output.every written to run.json."""
    L, W, Ht = 0.4, 0.3, 0.4                    # tank inside [0, L] x [0, W] x [0, Ht]
    n_in = (int(round(L / dx)), int(round(W / dx)), int(round(Ht / dx)))
    tank = lattice_block((n_in[0] + 2 * layers, n_in[1] + 2 * layers, n_in[2] + layers), dx,
                         (-layers * dx, -layers * dx, -layers * dx))
    inside = np.all((tank > 0) & (tank < np.array([L, W, 10.0])), axis=1)
    tank = tank[~inside]
    obstacle = lattice_block((3, 3, 8), dx, (0.28, 0.12, 0.0))
    base = lattice_block((8, n_in[1], 6), dx)      # water against the x = 0 wall, 0.12 m deep
    H = 6 * dx
    frames = []
    for k in range(nframes):
        t = 0.1 * k if times is None else times[k]
        s = 1.0 + 1.0 * t
        p = base.copy()
        p[:, 0] *= s
        p[:, 2] /= s
        pts = np.concatenate([p, tank, obstacle])
        nf, nt = len(p), len(tank)
        kind = np.concatenate([np.zeros(nf), np.ones(nt + len(obstacle))])
        body = np.concatenate([np.zeros(nf), np.ones(nt), np.full(len(obstacle), 2)])
        vel = np.zeros_like(pts)
        vel[:nf, 0] = base[:, 0]
        pres = 1000.0 * 9.81 * np.clip(H / s - pts[:, 2], 0, None)
        frames.append(make_frame(pts, dx, 3, time=t, step=100 * k, kind=kind, velocity=vel, pressure=pres,
                                 body=body if with_body else None))
    pvd = write_run(run_dir, frames, name=name, probes=False)
    with open(os.path.join(run_dir, "run.json"), "w") as f:    # the vertical axis comes from gravity
        f.write('{"scene": {"name": "%s", "dimension": 3, "gravity": [0, 0, -9.81]%s}}\n'
                % (name, ', "output": {"every": %r}' % every if every else ""))
    return pvd


def write_pvtu(path, frame, nparts=2):
    """One frame as ``nparts`` .vtu pieces (consecutive shares of the particles) and the .pvtu that lists them,
    the layout a parallel (MPI) run writes; returns ``path``."""
    base = os.path.splitext(path)[0]
    n = len(frame["points"])
    cuts = np.linspace(0, n, nparts + 1).astype(int)
    sources = []
    for k in range(nparts):
        sl = slice(cuts[k], cuts[k + 1])
        part = {key: (v[sl] if isinstance(v, np.ndarray) else v) for key, v in frame.items()}
        piece = "%s_p%d.vtu" % (base, k)
        w = vtkXMLUnstructuredGridWriter()
        w.SetFileName(piece)
        w.SetInputData(_grid(part))
        if not w.Write():
            raise RuntimeError("could not write " + piece)
        sources.append(os.path.basename(piece))
    arrays = [("velocity", "Float64", 3), ("density", "Float64", 1), ("pressure", "Float64", 1),
              ("mass", "Float64", 1), ("normal", "Float64", 3), ("id", "Int64", 1), ("kind", "Int32", 1)]
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="PUnstructuredGrid" version="0.1" byte_order="LittleEndian" '
                'header_type="UInt32">\n  <PUnstructuredGrid GhostLevel="0">\n    <PPointData>\n')
        for name, typ, nc in arrays:
            f.write('      <PDataArray type="%s" Name="%s" NumberOfComponents="%d"/>\n' % (typ, name, nc))
        f.write('    </PPointData>\n    <PPoints>\n      <PDataArray type="Float64" NumberOfComponents="3"/>\n'
                '    </PPoints>\n')
        for src in sources:
            f.write('    <Piece Source="%s"/>\n' % src)
        f.write("  </PUnstructuredGrid>\n</VTKFile>\n")
    return path


def frame_dict_of(ds):
    """The make_frame dict of a frame dataset read back (to re-write it in another layout)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    pd = ds.GetPointData()
    fr = {"points": vtk_to_numpy(ds.GetPoints().GetData()).astype(float)}
    for name in ("velocity", "density", "pressure", "mass", "id", "kind", "normal"):
        fr[name] = vtk_to_numpy(pd.GetArray(name)).copy()
    fields = {}
    fd = ds.GetFieldData()
    for i in range(fd.GetNumberOfArrays()):
        arr = fd.GetAbstractArray(i)
        fields[arr.GetName()] = arr.GetValue(0) if arr.IsA("vtkStringArray") else (
            int(arr.GetTuple1(0)) if arr.GetName() in ("step", "dimension") else arr.GetTuple1(0))
    fr["fields"] = fields
    return fr
