"""Readers for a varsph run directory (RUN/NAME.pvd, RUN/frames/*.vtu, see docs/paraview.md)."""
import glob
import os
import xml.etree.ElementTree as ET

import numpy as np


class Frame:
    """One output frame as numpy arrays.

    points (N, 3); arrays: point arrays by name; fields: field data (scalars as Python numbers,
    the ``kernel`` string array as str); time: simulated time (field ``time``, else the pvd timestep).
    """

    def __init__(self, points, arrays, fields, time=None, path=None):
        self.points = np.asarray(points, dtype=float).reshape(-1, 3)
        self.arrays = arrays
        self.fields = fields
        self.time = float(fields["time"]) if "time" in fields else (float(time) if time is not None else 0.0)
        self.path = path

    def __len__(self):
        return len(self.points)

    @property
    def dimension(self):
        if "dimension" in self.fields:
            return int(self.fields["dimension"])
        return 2 if np.all(self.points[:, 2] == 0.0) else 3

    @property
    def dx(self):
        if "dx" in self.fields:
            return float(self.fields["dx"])
        raise KeyError("field data lacks 'dx'")

    def fluid_mask(self):
        """Fluid particles (``kind`` == 0); all particles when ``kind`` is absent."""
        kind = self.arrays.get("kind")
        if kind is None:
            return np.ones(len(self), dtype=bool)
        return np.asarray(kind).reshape(-1) == 0

    def volume(self):
        """Particle volumes m/rho; dx^d where mass or density is missing or not positive."""
        n = len(self)
        default = self.dx ** self.dimension if "dx" in self.fields else 1.0
        m = self.arrays.get("mass")
        rho = self.arrays.get("density")
        if m is None or rho is None:
            return np.full(n, default)
        m = np.asarray(m, dtype=float).reshape(-1)
        rho = np.asarray(rho, dtype=float).reshape(-1)
        ok = (rho > 0) & (m > 0)
        v = np.full(n, default)
        v[ok] = m[ok] / rho[ok]
        return v


def _field_value(arr):
    """Python value of a vtk field-data array (first tuple; strings as str)."""
    if arr is None:
        return None
    if arr.IsA("vtkStringArray"):
        return arr.GetValue(0) if arr.GetNumberOfValues() else ""
    if arr.GetNumberOfTuples() == 0:
        return None
    if arr.GetNumberOfComponents() == 1 and arr.GetNumberOfTuples() == 1:
        v = arr.GetTuple1(0)
        if arr.GetDataType() in (2, 3, 4, 5, 6, 7, 8, 9, 12, 15, 16, 17):  # VTK integer type ids
            return int(v)
        return float(v)
    from vtkmodules.util.numpy_support import vtk_to_numpy
    return vtk_to_numpy(arr).copy()


def frame_from_vtk(dataset, time=None, path=None):
    """Frame from a vtkDataSet (e.g. the ParaView pipeline input of a plugin filter)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    n = dataset.GetNumberOfPoints()
    pts = dataset.GetPoints()
    points = vtk_to_numpy(pts.GetData()).astype(float).copy() if (pts is not None and n) else np.zeros((0, 3))
    arrays = {}
    pd = dataset.GetPointData()
    for i in range(pd.GetNumberOfArrays()):
        a = pd.GetArray(i)
        if a is None:
            continue
        arrays[a.GetName()] = vtk_to_numpy(a).copy()
    fields = {}
    fd = dataset.GetFieldData()
    for i in range(fd.GetNumberOfArrays()):
        a = fd.GetAbstractArray(i)
        if a is not None and a.GetName():
            fields[a.GetName()] = _field_value(a)
    return Frame(points, arrays, fields, time=time, path=path)


_EXTRA_PARTS = {}    # frame file -> the other parts of its time step in the .pvd (read_pvd)
_STATIC_CACHE = {}   # static walls file -> (mtime, dataset): written once per run, read for every frame


def _static_walls(path):
    """The dataset of a static-walls file (output.static_boundary = "once"), read once per change."""
    mtime = os.path.getmtime(path)
    hit = _STATIC_CACHE.get(path)
    if hit is None or hit[0] != mtime:
        hit = (mtime, _read_one(path))
        _STATIC_CACHE[path] = hit
    return hit[1]


def read_dataset(path):
    """The vtkDataSet of one frame: the frame file (.vtu, .pvtu pieces, any VTK XML dataset a .pvd lists)
    with the other parts of its time step appended: the static walls a lean frame names in its field data
    `static_boundary` (output.static_boundary = "once", issue 35) and any further part the .pvd lists."""
    ds = _read_one(path)
    fd = ds.GetFieldData()
    name = fd.GetAbstractArray("static_boundary") if fd is not None else None
    extras = []
    if name is not None and name.GetNumberOfValues():
        extras.append(os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(path)), name.GetValue(0))))
    for p in _EXTRA_PARTS.get(os.path.normpath(os.path.abspath(path)), []):
        if p not in extras:
            extras.append(p)
    if not extras:
        return ds
    from vtkmodules.vtkFiltersCore import vtkAppendFilter
    app = vtkAppendFilter()
    app.MergePointsOff()
    app.AddInputData(ds)
    for p in extras:
        if not os.path.isfile(p):
            raise FileNotFoundError("%s: the static walls file it names is missing: %s" % (path, p))
        app.AddInputData(_static_walls(p))
    app.Update()
    out = app.GetOutput()
    out.GetFieldData().ShallowCopy(fd)       # time, dx, ... of the frame
    own = out.NewInstance()
    own.ShallowCopy(out)
    return own


def _read_one(path):
    """The vtkDataSet of one file: .vtu, or .pvtu pieces (merged by VTK's parallel reader), or any
    other VTK XML dataset a .pvd may list."""
    from vtkmodules.vtkIOXML import (vtkXMLGenericDataObjectReader, vtkXMLPUnstructuredGridReader,
                                     vtkXMLUnstructuredGridReader)
    if not os.path.isfile(path):
        raise FileNotFoundError("frame file not found: %s" % path)
    ext = os.path.splitext(path)[1].lower()
    if ext == ".pvtu":
        return _read_pvtu_pieces(path)
    r = {".vtu": vtkXMLUnstructuredGridReader, ".pvtu": vtkXMLPUnstructuredGridReader}.get(
        ext, vtkXMLGenericDataObjectReader)()
    r.SetFileName(path)
    r.Update()
    out = r.GetOutputDataObject(0)
    if out is None or not out.IsA("vtkDataSet"):
        raise ValueError("%s: not a readable VTK dataset" % path)
    return out


def _read_pvtu_pieces(path):
    """A .pvtu frame as one grid: each piece read by the serial reader and appended in piece order (the
    order vtkXMLPUnstructuredGridReader gives). ParaView 5.11 crashes intermittently in Threshold on
    series read through its parallel reader (docs/parallel.md), not on the same grid read this way."""
    import xml.etree.ElementTree as ET
    from vtkmodules.vtkFiltersCore import vtkAppendFilter
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    root = ET.parse(path).getroot()
    grid = root.find("PUnstructuredGrid")
    sources = [p.get("Source") for p in grid.findall("Piece")] if grid is not None else []
    if not sources:
        raise ValueError("%s: a .pvtu without pieces" % path)
    app = vtkAppendFilter()
    app.MergePointsOff()
    readers = []
    for src in sources:
        piece = os.path.join(os.path.dirname(path), src)
        if not os.path.isfile(piece):
            raise FileNotFoundError("%s: piece not found: %s" % (path, piece))
        r = vtkXMLUnstructuredGridReader()
        r.SetFileName(piece)
        r.Update()
        readers.append(r)
        app.AddInputData(r.GetOutput())
    app.Update()
    out = app.GetOutput()
    field = readers[0].GetOutput().GetFieldData()  # time, step, dx, h, ... (the same on every piece)
    out.GetFieldData().ShallowCopy(field)
    own = out.NewInstance()
    own.ShallowCopy(out)
    return own


def point_array(data, name):
    """numpy copy of point array ``name`` of a vtkDataSet or of all leaves of a composite; None if absent."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    if data is None:
        return None
    if data.IsA("vtkCompositeDataSet"):
        parts = []
        it = data.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            v = point_array(it.GetCurrentDataObject(), name)
            if v is not None:
                parts.append(v)
            it.GoToNextItem()
        return np.concatenate(parts) if parts else None
    a = data.GetPointData().GetArray(name) if data.IsA("vtkDataSet") else None
    return vtk_to_numpy(a).copy() if a is not None else None


def read_vtu(path, time=None):
    """Read one frame written by the solver (.vtu, or .pvtu with its pieces)."""
    return frame_from_vtk(read_dataset(path), time=time, path=path)


def read_pvd(path):
    """[(timestep, absolute vtu path)] sorted by time, from a ParaView collection file."""
    if not os.path.isfile(path):
        raise FileNotFoundError("pvd file not found: %s" % path)
    root = ET.parse(path).getroot()
    base = os.path.dirname(os.path.abspath(path))
    out, first = [], {}
    for ds in root.iter("DataSet"):
        f = ds.get("file")
        if f is None:
            continue
        t, p = float(ds.get("timestep", "0")), os.path.normpath(os.path.join(base, f))
        if t in first:   # another part of this time step (a lean frame's static walls): read with the frame
            extra = _EXTRA_PARTS.setdefault(first[t], [])
            if p not in extra:
                extra.append(p)
            continue
        first[t] = p
        out.append((t, p))
    out.sort(key=lambda x: x[0])
    return out


def find_pvd(run):
    """The run's time series: ``run`` itself if it is a file (.pvd, or one frame file), else the single
    RUN/*.pvd (not deviation.pvd), else the single RUN/*.vtu (what `varsph sample` writes)."""
    if os.path.isfile(run):
        return run
    cands = sorted(p for p in glob.glob(os.path.join(run, "*.pvd")) if os.path.basename(p) != "deviation.pvd")
    if not cands:
        vtus = sorted(glob.glob(os.path.join(run, "*.vtu")))
        if len(vtus) == 1:
            return vtus[0]
        raise FileNotFoundError("no .pvd time series in run directory %s" % run)
    if len(cands) > 1:
        name = os.path.basename(os.path.normpath(run)) + ".pvd"
        for c in cands:
            if os.path.basename(c) == name:
                return c
    return cands[0]


def entries_of(path):
    """[(time, frame file)] of a .pvd, or of a single frame file (its field data time, else 0)."""
    if path.lower().endswith(".pvd"):
        return read_pvd(path)
    f = read_vtu(path)
    return [(float(f.fields.get("time", 0.0)), os.path.abspath(path))]


def resolve_run(directory="", variable="VARSPH_RUN_DIR"):
    """The .pvd of a run: ``directory`` (a run directory or its .pvd) when given, else the directory named by
    the environment variable ``variable``, else the working directory when it holds a .pvd.
    Raises FileNotFoundError naming what was tried."""
    if directory:
        return os.path.abspath(find_pvd(os.path.expanduser(directory)))
    from_env = os.environ.get(variable, "") if variable else ""
    if from_env:
        try:
            return os.path.abspath(find_pvd(os.path.expanduser(from_env)))
        except FileNotFoundError as e:
            raise FileNotFoundError("%s (from $%s)" % (e, variable)) from None
    try:
        return os.path.abspath(find_pvd(os.getcwd()))
    except FileNotFoundError:
        raise FileNotFoundError("no run given: set Run Directory, or $%s, or start ParaView in a run directory "
                                "(the working directory %s has no .pvd)" % (variable or "VARSPH_RUN_DIR", os.getcwd())) \
            from None


def entry_at(entries, t, tol=1e-9):
    """The (time, path) entry shown at time ``t``: the latest at or before t (ParaView's convention for a
    time between frames), the first one before the first."""
    best = entries[0]
    for e in entries:
        if e[0] <= t + tol:
            best = e
        else:
            break
    return best


def frames_of_run(run):
    """[(time, vtu path)] of a run directory or .pvd file."""
    return entries_of(find_pvd(run))


def read_run(run, times=None, tol=1e-9):
    """Generator of Frames of a run (all, or those whose pvd time is within ``tol`` of one of ``times``)."""
    for t, path in frames_of_run(run):
        if times is not None and not any(abs(t - s) <= tol for s in times):
            continue
        yield read_vtu(path, time=t)


def gravity_of_run(run):
    """The gravity vector from RUN/run.json (the resolved scene), or None."""
    import json
    d = run if os.path.isdir(run) else os.path.dirname(run)
    path = os.path.join(d, "run.json")
    if not os.path.isfile(path):
        return None
    try:
        with open(path) as f:
            doc = json.load(f)
    except (OSError, ValueError):
        return None
    stack = [doc]
    while stack:
        x = stack.pop()
        if isinstance(x, dict):
            g = x.get("gravity")
            if isinstance(g, list) and len(g) in (2, 3) and all(isinstance(v, (int, float)) for v in g):
                return [float(v) for v in g] + [0.0] * (3 - len(g))
            stack.extend(x.values())
        elif isinstance(x, list):
            stack.extend(v for v in x if isinstance(v, (dict, list)))
    return None


def vertical_axis(run, dimension):
    """Axis opposite to gravity (run.json), else y in 2D and z in 3D."""
    g = gravity_of_run(run)
    if g is not None and any(v != 0 for v in g[:dimension]):
        return int(np.argmax(np.abs(g[:dimension])))
    return 1 if dimension == 2 else 2
