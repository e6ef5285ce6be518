"""ParaView plugin: varsph SPH post-processing filters and the run reader.

This directory (paraview/plugin/) holds only the plugin, so that it can be a plugin search path:
  GUI:      Tools > Manage Plugins > Load New... > paraview/plugin/varsph_filters.py (tick "Auto Load")
  any:      PV_PLUGIN_PATH=/path/to/varsph/paraview/plugin paraview | pvpython | pvbatch
  GUI:      paraview --plugin-search-paths=/path/to/varsph/paraview/plugin --plugins=varsph_filters
  Python:   LoadPlugin('/path/to/varsph/paraview/plugin/varsph_filters.py', ns=globals())
ParaView 5.11 on Python 3.11 (Debian 12) needs the start-up shim installed once by
paraview/install_compat.py (scripts/install-deps.sh does it); ParaView >= 5.12 needs nothing.
The proxies appear under Sources / Filters > varsph (and Alphabetical):

  varsph Run                   a run directory as a time series; empty Run Directory = $VARSPH_RUN_DIR
                               (or the variable named in Run Variable), else the working directory
  varsph Free Surface          port Particles: the input + free_surface (0/1), fs_lambda, fs_normal
                               port Surface: the reconstructed surface (colour field contour), optional
  varsph Smoothed Pressure     the input + pressure_smoothed (Shepard SPH average over fluid neighbours)
  varsph Pressure Probe        table over time of a point array (pressure) SPH-interpolated at points
  varsph Deviation             run A's particles with the deviation from run B at the nearest common time
  varsph Deviation Over Time   table time,D_max,D_mean,D_rms over the common times (as varsph compare)
  varsph Surge Front           table time,front_x,front_rel,height_x<g>... over time

The logic lives in the ``varsph`` package (paraview/varsph/); see paraview/README.md.
"""
import os
import sys

_HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))   # paraview/: the varsph package
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)

from varsph.compat import patch_inspect  # noqa: E402

patch_inspect()  # Python 3.11 + ParaView 5.11: paraview.util.vtkAlgorithm needs inspect.getargspec

import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk  # noqa: E402
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase  # noqa: E402
from vtkmodules.vtkCommonCore import vtkDoubleArray  # noqa: E402
from vtkmodules.vtkCommonDataModel import (vtkDataObject, vtkDataSet, vtkPolyData, vtkTable,  # noqa: E402
                                            vtkUnstructuredGrid)
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as _SDDP  # noqa: E402

from paraview.util.vtkAlgorithm import smdomain, smhint, smproperty, smproxy  # noqa: E402

import varsph  # noqa: E402
from varsph import deviation as _dev  # noqa: E402
from varsph import openb as _openb  # noqa: E402
from varsph import parts as _parts  # noqa: E402
from varsph import surge as _surge  # noqa: E402

_CATEGORY = '<ShowInMenu category="varsph" />'
EXECUTIONS = {}   # RequestData calls per filter class (frames processed), for tests and diagnostics


def _add_point_array(ds, name, values):
    a = numpy_to_vtk(np.ascontiguousarray(values), deep=1)
    a.SetName(name)
    ds.GetPointData().AddArray(a)


def _fill_table(table, columns, rows):
    rows = np.asarray(rows, dtype=float).reshape(len(rows), len(columns))
    for k, c in enumerate(columns):
        a = vtkDoubleArray()
        a.SetName(c)
        a.SetNumberOfTuples(len(rows))
        for r in range(len(rows)):
            a.SetValue(r, rows[r, k])
        table.AddColumn(a)


def _as_dataset(obj):
    """A single dataset: the object itself, or the leaves of a composite (a .pvd with several parts per
    time, pieces read by another reader) appended into one unstructured grid."""
    if obj is None or isinstance(obj, vtkDataSet):
        return obj
    if obj.IsA("vtkCompositeDataSet"):
        from vtkmodules.vtkFiltersCore import vtkAppendFilter
        app = vtkAppendFilter()
        it = obj.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            leaf = it.GetCurrentDataObject()
            if isinstance(leaf, vtkDataSet) and leaf.GetNumberOfPoints():
                app.AddInputData(leaf)
            it.GoToNextItem()
        if app.GetNumberOfInputConnections(0) == 0:
            return vtkUnstructuredGrid()
        app.Update()
        out = app.GetOutput()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            leaf = it.GetCurrentDataObject()
            if isinstance(leaf, vtkDataSet):
                out.GetFieldData().ShallowCopy(leaf.GetFieldData())
                break
            it.GoToNextItem()
        return out
    return None


def _input_frame(inInfo, port=0, time=None):
    obj = vtkDataObject.GetData(inInfo[port])
    ds = _as_dataset(obj)
    if ds is None:
        raise RuntimeError("input %d is not a dataset (use the output of varsph Run or of the run's .pvd reader)"
                           % port)
    t = obj.GetInformation().Get(vtkDataObject.DATA_TIME_STEP())
    return varsph.frame_from_vtk(ds, time=t if t is not None else time), ds


class _OverTime(VTKPythonAlgorithmBase):
    """Runs ``frame_rows`` on every time step of input 0 (the CONTINUE_EXECUTING loop) and emits a table."""

    def __init__(self, nInputPorts=1):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=nInputPorts, nOutputPorts=1, outputType="vtkTable")
        self._times = None
        self._k = 0
        self._rows = []

    def FillInputPortInformation(self, port, info):
        info.Set(self.INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject")
        return 1

    def RequestInformation(self, request, inInfo, outInfo):
        info = inInfo[0].GetInformationObject(0)
        self._times = list(info.Get(_SDDP.TIME_STEPS())) if info.Has(_SDDP.TIME_STEPS()) else None
        oi = outInfo.GetInformationObject(0)
        oi.Remove(_SDDP.TIME_STEPS())
        oi.Remove(_SDDP.TIME_RANGE())
        return 1

    def RequestUpdateExtent(self, request, inInfo, outInfo):
        if self._times:
            t = self._times[min(self._k, len(self._times) - 1)]
            for port in range(self.GetNumberOfInputPorts()):
                inInfo[port].GetInformationObject(0).Set(_SDDP.UPDATE_TIME_STEP(), t)
        return 1

    def RequestData(self, request, inInfo, outInfo):
        EXECUTIONS[type(self).__name__] = EXECUTIONS.get(type(self).__name__, 0) + 1
        if self._k == 0:
            self._rows = []
        t = self._times[self._k] if self._times else None
        row = self.frame_row(inInfo, t)
        if row is not None:
            self._rows.append(row)
        self._k += 1
        if self._times and self._k < len(self._times):
            request.Set(_SDDP.CONTINUE_EXECUTING(), 1)
            return 1
        request.Remove(_SDDP.CONTINUE_EXECUTING())
        self._k = 0
        _fill_table(vtkTable.GetData(outInfo), self.columns(), self._rows)
        return 1


# --------------------------------------------------------------------------------------------------
@smproxy.source(name="varsphRun", label="varsph Run")
@smhint.xml(_CATEGORY)
class RunReader(VTKPythonAlgorithmBase):
    """A varsph run directory as a time series (the frames its .pvd lists: .vtu, or .pvtu pieces).

    *Run Directory* may be the directory or its .pvd. Left empty, the run comes from the environment
    variable named by *Run Variable* (VARSPH_RUN_DIR; the deviation states use VARSPH_OTHER_RUN_DIR for
    run B), else from the working directory: that is what lets one saved state (.pvsm) open any run."""

    def __init__(self):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=0, nOutputPorts=1, outputType="vtkUnstructuredGrid")
        self._dir = ""
        self._variable = "VARSPH_RUN_DIR"
        self._pvd = ""
        self._entries = []
        self._cache = (None, None)
        self._classes = (None, {})   # (.pvd, {body: part}) from the run's first frame (varsph/parts.py)

    @smproperty.stringvector(name="RunDirectory", label="Run Directory", default_values="")
    def SetRunDirectory(self, d):
        if d != self._dir:
            self._dir = d or ""
            self.Modified()

    @smproperty.stringvector(name="RunVariable", label="Run Variable", default_values="VARSPH_RUN_DIR")
    def SetRunVariable(self, v):
        if v != self._variable:
            self._variable = v or ""
            self.Modified()

    @smproperty.stringvector(name="ResolvedFile", information_only="1")
    def GetResolvedFile(self):
        return self._pvd

    @smproperty.doublevector(name="TimestepValues", information_only="1", si_class="vtkSITimeStepsProperty")
    def GetTimestepValues(self):
        return [t for t, _ in self._entries]

    def RequestInformation(self, request, inInfo, outInfo):
        try:
            self._pvd = varsph.io.resolve_run(self._dir, self._variable)
            self._entries = varsph.io.entries_of(self._pvd)
        except (OSError, ValueError) as e:
            self._pvd, self._entries = "", []
            print("varsph Run: %s" % e, file=sys.stderr)
            return 0
        _set_times(outInfo.GetInformationObject(0), [t for t, _ in self._entries])
        return 1

    def RequestData(self, request, inInfo, outInfo):
        if not self._entries:
            return 0
        oi = outInfo.GetInformationObject(0)
        t = oi.Get(_SDDP.UPDATE_TIME_STEP()) if oi.Has(_SDDP.UPDATE_TIME_STEP()) else self._entries[0][0]
        t_frame, path = varsph.io.entry_at(self._entries, t)
        if self._cache[0] != path:
            self._cache = (path, self._with_part(varsph.io.read_dataset(path)))
        out = vtkDataSet.GetData(outInfo)
        out.ShallowCopy(self._cache[1])
        out.GetInformation().Set(vtkDataObject.DATA_TIME_STEP(), t_frame)
        return 1

    def _with_part(self, ds):
        """The frame plus `part` (0 fluid, 1 wall, 2 obstacle or body; varsph/parts.py), which the states
        use to cut the container away in 3D, and, in runs with open boundaries, `open_kind` (0 none, 1 inlet,
        2 outlet buffer particle; varsph/openb.py). Bodies are classified once per run, on its first frame."""
        if self._classes[0] != self._pvd:
            f0 = varsph.io.read_vtu(self._entries[0][1], self._entries[0][0])
            classes = {}
            if "kind" in f0.arrays and "body" in f0.arrays and "dx" in f0.fields:
                classes = _parts.classify_bodies(f0.points, f0.arrays["kind"], f0.arrays["body"], f0.dx)
            self._classes = (self._pvd, classes)
        kind = varsph.io.point_array(ds, "kind")
        if kind is None:
            kind = np.zeros(ds.GetNumberOfPoints(), dtype=np.int32)
        _add_point_array(ds, "part", _parts.part_array(kind, varsph.io.point_array(ds, "body"), self._classes[1]))
        open_zone = varsph.io.point_array(ds, "open_zone")
        if open_zone is not None:   # open boundaries: 1 inlet, 2 outlet buffer particles, 0 the rest (varsph/openb.py)
            _add_point_array(ds, "open_kind", _openb.open_kind_array(open_zone, _openb.zones(self._pvd)))
        return ds


# --------------------------------------------------------------------------------------------------
@smproxy.filter(name="varsphSmoothedPressure", label="varsph Smoothed Pressure")
@smhint.xml(_CATEGORY)
@smproperty.input(name="Input", port_index=0)
@smdomain.datatype(dataTypes=["vtkDataSet", "vtkCompositeDataSet"])
class SmoothedPressure(VTKPythonAlgorithmBase):
    """The input plus ``<array>_smoothed``: each fluid particle's value replaced by the Shepard-normalised SPH
    average over its fluid neighbours, sum_j V_j f_j W_ij / sum_j V_j W_ij (the probe interpolation of
    varsph.probe at the particle positions); boundary particles keep their value."""

    def __init__(self):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=1, nOutputPorts=1, inputType="vtkDataObject",
                                        outputType="vtkUnstructuredGrid")
        self._array = "pressure"

    @smproperty.stringvector(name="ArrayName", label="Array Name", default_values="pressure")
    def SetArrayName(self, name):
        self._array = str(name)
        self.Modified()

    def RequestData(self, request, inInfo, outInfo):
        frame, ds = _input_frame(inInfo)
        out = vtkDataSet.GetData(outInfo)
        out.ShallowCopy(ds)
        _add_point_array(out, self._array + "_smoothed", varsph.smooth_field(frame, self._array))
        return 1


# --------------------------------------------------------------------------------------------------
@smproxy.filter(name="varsphFreeSurface", label="varsph Free Surface")
@smhint.xml(_CATEGORY)
@smproperty.input(name="Input", port_index=0)
@smdomain.datatype(dataTypes=["vtkDataSet", "vtkCompositeDataSet"])
class FreeSurface(VTKPythonAlgorithmBase):
    """Free-surface particles by Marrone et al. (2010), J. Comput. Phys. 229:3652, and optionally the
    surface reconstructed as the 0.5 contour of the SPH colour field sampled on an image grid."""

    def __init__(self):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=1, nOutputPorts=2, inputType="vtkDataObject")
        self._include_boundary = True
        self._lambda_surface = 0.2
        self._lambda_interior = 0.75
        self._reconstruct = False
        self._spacing_factor = 0.5
        self._iso = 0.5

    def FillOutputPortInformation(self, port, info):
        info.Set(vtkDataObject.DATA_TYPE_NAME(), "vtkUnstructuredGrid" if port == 0 else "vtkPolyData")
        return 1

    @smproperty.xml('<OutputPort name="Particles" index="0" /><OutputPort name="Surface" index="1" />')
    def _output_port_names(self):
        """Not a property: puts the port names into the proxy definition."""

    def RequestDataObject(self, request, inInfo, outInfo):
        inp = vtkDataObject.GetData(inInfo[0])
        if inp is not None:
            # a composite input (several parts per time) comes out as one unstructured grid
            cls = inp.GetClassName() if isinstance(inp, vtkDataSet) else "vtkUnstructuredGrid"
            out0 = vtkDataObject.GetData(outInfo, 0)
            if out0 is None or out0.GetClassName() != cls:
                out0 = inp.NewInstance() if isinstance(inp, vtkDataSet) else vtkUnstructuredGrid()
                outInfo.GetInformationObject(0).Set(vtkDataObject.DATA_OBJECT(), out0)
        out1 = vtkDataObject.GetData(outInfo, 1)
        if out1 is None:
            outInfo.GetInformationObject(1).Set(vtkDataObject.DATA_OBJECT(), vtkPolyData())
        return 1

    @smproperty.intvector(name="IncludeBoundary", label="Include Boundary", default_values=1)
    @smdomain.xml('<BooleanDomain name="bool"/>')
    def SetIncludeBoundary(self, v):
        self._include_boundary = bool(v)
        self.Modified()

    @smproperty.doublevector(name="LambdaSurface", label="Lambda Surface", default_values=0.2)
    def SetLambdaSurface(self, v):
        self._lambda_surface = float(v)
        self.Modified()

    @smproperty.doublevector(name="LambdaInterior", label="Lambda Interior", default_values=0.75)
    def SetLambdaInterior(self, v):
        self._lambda_interior = float(v)
        self.Modified()

    @smproperty.intvector(name="ReconstructSurface", label="Reconstruct Surface", default_values=0)
    @smdomain.xml('<BooleanDomain name="bool"/>')
    def SetReconstructSurface(self, v):
        self._reconstruct = bool(v)
        self.Modified()

    @smproperty.doublevector(name="GridSpacing", label="Grid Spacing", default_values=0.5)
    def SetGridSpacing(self, v):
        self._spacing_factor = float(v)
        self.Modified()

    @smproperty.doublevector(name="IsoValue", label="Iso Value", default_values=0.5)
    def SetIsoValue(self, v):
        self._iso = float(v)
        self.Modified()

    def RequestData(self, request, inInfo, outInfo):
        frame, ds = _input_frame(inInfo)
        out = vtkDataSet.GetData(outInfo, 0)
        out.ShallowCopy(ds)
        flag, det = varsph.free_surface(frame, include_boundary=self._include_boundary,
                                        lambda_surface=self._lambda_surface,
                                        lambda_interior=self._lambda_interior, return_details=True)
        _add_point_array(out, "free_surface", flag.astype(np.int32))
        _add_point_array(out, "fs_lambda", det["lambda_"])
        _add_point_array(out, "fs_normal", det["normal"])
        surf = vtkPolyData.GetData(outInfo, 1)
        if self._reconstruct:
            surf.ShallowCopy(varsph.surface_mesh(frame, spacing=self._spacing_factor * frame.dx, iso=self._iso))
        else:
            surf.Initialize()
        return 1


# --------------------------------------------------------------------------------------------------
@smproxy.filter(name="varsphPressureProbe", label="varsph Pressure Probe")
@smhint.xml(_CATEGORY)
@smproperty.input(name="Input", port_index=0)
@smdomain.datatype(dataTypes=["vtkDataSet", "vtkCompositeDataSet"])
class PressureProbe(_OverTime):
    """Shepard-normalised SPH interpolation of a point array (fluid particles) at user points, over time."""

    def __init__(self):
        _OverTime.__init__(self)
        self._points = []
        self._array = "pressure"

    @smproperty.doublevector(name="ProbePoints", label="Probe Points", default_values=[0.0, 0.0, 0.0],
                             number_of_elements_per_command=3, repeat_command=1, use_index=0,
                             clean_command="ClearProbePoints")
    def AddProbePoint(self, x, y, z):
        self._points.append((float(x), float(y), float(z)))
        self.Modified()

    def ClearProbePoints(self):
        self._points = []
        self.Modified()

    @smproperty.stringvector(name="ArrayName", label="Array Name", default_values="pressure")
    def SetArrayName(self, name):
        self._array = str(name)
        self.Modified()

    def columns(self):
        return ["time"] + ["%s_%d" % (self._array, k) for k in range(len(self._points))]

    def frame_row(self, inInfo, t):
        frame, _ = _input_frame(inInfo, 0, t)
        vals, _ = varsph.probe_pressure(frame, np.asarray(self._points).reshape(-1, 3), array=self._array) \
            if self._points else (np.zeros(0), None)
        return [frame.time] + list(vals)


# --------------------------------------------------------------------------------------------------
def _field(fd, name, value):
    a = vtkDoubleArray()
    a.SetName(name)
    a.InsertNextValue(float(value))
    fd.AddArray(a)


def _times_of(info):
    return list(info.Get(_SDDP.TIME_STEPS())) if info.Has(_SDDP.TIME_STEPS()) else []


def _set_times(info, times):
    info.Remove(_SDDP.TIME_STEPS())
    info.Remove(_SDDP.TIME_RANGE())
    if times:
        info.Set(_SDDP.TIME_STEPS(), times, len(times))
        info.Set(_SDDP.TIME_RANGE(), [times[0], times[-1]], 2)


@smproxy.filter(name="varsphDeviation", label="varsph Deviation")
@smhint.xml(_CATEGORY)
@smproperty.input(name="Reference", port_index=1)
@smdomain.datatype(dataTypes=["vtkDataSet", "vtkCompositeDataSet"])
@smproperty.input(name="Input", port_index=0)
@smdomain.datatype(dataTypes=["vtkDataSet", "vtkCompositeDataSet"])
class Deviation(VTKPythonAlgorithmBase):
    """Run A's particles with ``deviation`` = q_A - q_B (matched by id) and ``deviation_magnitude``;
    field data D_max, D_mean, D_rms over the fluid particles (paper eq. 70).

    Only times both runs have are compared: the output's time steps are the common times (|t_A - t_B|
    <= 1e-9 s), a requested time is taken to the latest common time at or before it (the first one before
    the first), or always to the last common time (*Compare At*), and the field data says which:
    t_compared, t_last_common, t_end_A, t_end_B, n_common; the output's data time is t_compared."""

    def __init__(self):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=2, nOutputPorts=1, outputType="vtkUnstructuredGrid")
        self._pairs = []
        self._ends = (float("nan"), float("nan"))
        self._last_common = False

    @smproperty.intvector(name="CompareAt", label="Compare At", default_values=0)
    @smdomain.xml('<EnumerationDomain name="enum"><Entry value="0" text="Animation Time"/>'
                  '<Entry value="1" text="Last Common Time"/></EnumerationDomain>')
    def SetCompareAt(self, v):
        """Animation Time: the latest common time at or before the animation time; Last Common Time: always
        the last time both runs have, whatever the animation time (a fixed picture of the end state)."""
        if bool(v) != self._last_common:
            self._last_common = bool(v)
            self.Modified()

    def FillInputPortInformation(self, port, info):
        info.Set(self.INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject")
        return 1

    @smproperty.doublevector(name="TimestepValues", information_only="1", si_class="vtkSITimeStepsProperty")
    def GetTimestepValues(self):
        return [ta for ta, _ in self._pairs]

    def RequestInformation(self, request, inInfo, outInfo):
        ta = _times_of(inInfo[0].GetInformationObject(0))
        tb = _times_of(inInfo[1].GetInformationObject(0))
        self._pairs = [(ta[i], tb[j]) for i, j in _dev.match_times(ta, tb)]
        self._ends = (ta[-1] if ta else float("nan"), tb[-1] if tb else float("nan"))
        _set_times(outInfo.GetInformationObject(0), [a for a, _ in self._pairs])
        return 1

    def _pair_for(self, t):
        return self._pairs[-1] if self._last_common else _dev.common_pair(self._pairs, t)

    def RequestUpdateExtent(self, request, inInfo, outInfo):
        oi = outInfo.GetInformationObject(0)
        if self._pairs:
            t = oi.Get(_SDDP.UPDATE_TIME_STEP()) if oi.Has(_SDDP.UPDATE_TIME_STEP()) else self._pairs[-1][0]
            ta, tb = self._pair_for(t)
            inInfo[0].GetInformationObject(0).Set(_SDDP.UPDATE_TIME_STEP(), ta)
            inInfo[1].GetInformationObject(0).Set(_SDDP.UPDATE_TIME_STEP(), tb)
        return 1

    def RequestData(self, request, inInfo, outInfo):
        out = vtkDataSet.GetData(outInfo)
        if not self._pairs:
            print("varsph Deviation: the two runs have no frame times in common (A ends at %.6g s, B at %.6g s)"
                  % self._ends, file=sys.stderr)
            return 0
        A, ds_a = _input_frame(inInfo, 0)
        B, _ = _input_frame(inInfo, 1)
        out.ShallowCopy(ds_a)
        r = varsph.deviation_frame(A, B)
        _add_point_array(out, "deviation", r["vector"])
        _add_point_array(out, "deviation_magnitude", r["magnitude"])
        fd = out.GetFieldData()
        for k in ("D_max", "D_mean", "D_rms"):
            _field(fd, k, r[k])
        oi = outInfo.GetInformationObject(0)
        t = oi.Get(_SDDP.UPDATE_TIME_STEP()) if oi.Has(_SDDP.UPDATE_TIME_STEP()) else self._pairs[-1][0]
        _field(fd, "t_compared", self._pair_for(t)[0])
        _field(fd, "t_last_common", self._pairs[-1][0])
        _field(fd, "t_end_A", self._ends[0])
        _field(fd, "t_end_B", self._ends[1])
        _field(fd, "n_common", len(self._pairs))
        out.GetInformation().Set(vtkDataObject.DATA_TIME_STEP(), self._pair_for(t)[0])
        return 1


@smproxy.filter(name="varsphDeviationOverTime", label="varsph Deviation Over Time")
@smhint.xml(_CATEGORY)
@smproperty.input(name="Reference", port_index=1)
@smdomain.datatype(dataTypes=["vtkDataSet", "vtkCompositeDataSet"])
@smproperty.input(name="Input", port_index=0)
@smdomain.datatype(dataTypes=["vtkDataSet", "vtkCompositeDataSet"])
class DeviationOverTime(_OverTime):
    """Table time,D_max,D_mean,D_rms over the times of run A that run B also has (within 1e-9 s)."""

    def __init__(self):
        _OverTime.__init__(self, nInputPorts=2)

    def RequestInformation(self, request, inInfo, outInfo):
        _OverTime.RequestInformation(self, request, inInfo, outInfo)
        ib = inInfo[1].GetInformationObject(0)
        tb = list(ib.Get(_SDDP.TIME_STEPS())) if ib.Has(_SDDP.TIME_STEPS()) else None
        if self._times and tb is not None:
            self._times = [self._times[ka] for ka, _ in _dev.match_times(self._times, tb)]
        return 1

    def columns(self):
        return list(_dev.DEVIATION_COLUMNS)

    def frame_row(self, inInfo, t):
        A, _ = _input_frame(inInfo, 0, t)
        B, _ = _input_frame(inInfo, 1, t)
        if abs(A.time - B.time) > _dev.TIME_TOLERANCE:
            return None
        r = varsph.deviation_frame(A, B)
        return [A.time, r["D_max"], r["D_mean"], r["D_rms"]]


# --------------------------------------------------------------------------------------------------
@smproxy.filter(name="varsphSurgeFront", label="varsph Surge Front")
@smhint.xml(_CATEGORY)
@smproperty.input(name="Input", port_index=0)
@smdomain.datatype(dataTypes=["vtkDataSet", "vtkCompositeDataSet"])
class SurgeFront(_OverTime):
    """Largest fluid coordinate along Axis (the dam-break front), relative to a reference, and water
    heights at gauge positions, over time."""

    def __init__(self):
        _OverTime.__init__(self)
        self._gauges = []
        self._axis = 0
        self._vertical = -1
        self._reference = 0.0
        self._use_reference = False

    @smproperty.doublevector(name="Gauges", label="Gauges", default_values=[],
                             number_of_elements=0, number_of_elements_per_command=1, repeat_command=1,
                             use_index=0, clean_command="ClearGauges")
    def AddGauge(self, x):
        self._gauges.append(float(x))
        self.Modified()

    def ClearGauges(self):
        self._gauges = []
        self.Modified()

    @smproperty.intvector(name="Axis", label="Axis", default_values=0)
    @smdomain.intrange(min=0, max=2)
    def SetAxis(self, v):
        self._axis = int(v)
        self.Modified()

    @smproperty.intvector(name="VerticalAxis", label="Vertical Axis", default_values=-1)
    @smdomain.intrange(min=-1, max=2)
    def SetVerticalAxis(self, v):
        self._vertical = int(v)
        self.Modified()

    @smproperty.intvector(name="UseReference", label="Use Reference", default_values=0)
    @smdomain.xml('<BooleanDomain name="bool"/>')
    def SetUseReference(self, v):
        self._use_reference = bool(v)
        self.Modified()

    @smproperty.doublevector(name="Reference", label="Reference", default_values=0.0)
    def SetReference(self, v):
        self._reference = float(v)
        self.Modified()

    def columns(self):
        return ["time", "front_x", "front_rel"] + ["height_x%g" % g for g in self._gauges]

    def frame_row(self, inInfo, t):
        fr, _ = _input_frame(inInfo, 0, t)
        if self._k == 0:
            fl = fr.fluid_mask()
            vert = _surge.default_vertical(fr.dimension) if self._vertical < 0 else self._vertical
            dx = fr.dx if "dx" in fr.fields else 0.0
            self._state = dict(
                vert=vert,
                ref=self._reference if self._use_reference else _surge.surge_front(fr, self._axis),
                bottom=float(fr.points[fl, vert].min() - 0.5 * dx) if fl.any() else 0.0)
        s = self._state
        front = _surge.surge_front(fr, self._axis)
        hs = list(_surge.water_height(fr, self._gauges, self._axis, s["vert"], None, s["bottom"])) \
            if self._gauges else []
        return [fr.time, front, front - s["ref"]] + hs


# --------------------------------------------------------------------------------------------------
@smproxy.source(name="varsphBodyTrajectories", label="varsph Body Trajectories")
@smhint.xml(_CATEGORY)
class BodyTrajectories(VTKPythonAlgorithmBase):
    """The paths of a run's rigid bodies (RUN/bodies.csv, docs/bodies.md) up to the current time: one
    polyline per body through its centre of mass, with point arrays time, body, speed, angle and the fluid
    force's magnitude. *Run Directory* as for *varsph Run* (empty: VARSPH_RUN_DIR, else the working
    directory). Show it beside the run: the bodies' particles are in the frames (kind 1, `part` 2)."""

    def __init__(self):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=0, nOutputPorts=1, outputType="vtkPolyData")
        self._dir = ""
        self._rows = None
        self._csv = ""

    @smproperty.stringvector(name="RunDirectory", label="Run Directory", default_values="")
    def SetRunDirectory(self, d):
        if d != self._dir:
            self._dir = d or ""
            self.Modified()

    def _load(self):
        run = self._dir or os.environ.get("VARSPH_RUN_DIR", "") or os.getcwd()
        if run.endswith(".pvd"):
            run = os.path.dirname(run)
        path = os.path.join(run, "bodies.csv")
        if path != self._csv:
            data = np.genfromtxt(path, delimiter=",", names=True)
            self._rows, self._csv = np.atleast_1d(data), path
        return self._rows

    def RequestInformation(self, request, inInfo, outInfo):
        try:
            rows = self._load()
        except (OSError, ValueError) as e:
            print("varsph Body Trajectories: %s" % e, file=sys.stderr)
            return 0
        _set_times(outInfo.GetInformationObject(0), sorted(set(float(t) for t in rows["time"])))
        return 1

    def RequestData(self, request, inInfo, outInfo):
        from vtkmodules.vtkCommonCore import vtkPoints
        from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyLine
        rows = self._rows
        if rows is None:
            return 0
        oi = outInfo.GetInformationObject(0)
        t = oi.Get(_SDDP.UPDATE_TIME_STEP()) if oi.Has(_SDDP.UPDATE_TIME_STEP()) else float(rows["time"].max())
        rows = rows[rows["time"] <= t + 1e-12]
        pts, lines = vtkPoints(), vtkCellArray()
        arrays = {k: [] for k in ("time", "body", "speed", "angle", "fluid_force")}
        for b in sorted(set(int(v) for v in rows["body"])):
            mine = rows[rows["body"] == b]
            line = vtkPolyLine()
            for r in mine:
                line.GetPointIds().InsertNextId(pts.InsertNextPoint(r["x"], r["y"], r["z"]))
                arrays["time"].append(r["time"])
                arrays["body"].append(b)
                arrays["speed"].append(np.sqrt(r["vx"] ** 2 + r["vy"] ** 2 + r["vz"] ** 2))
                arrays["angle"].append(r["angle"])
                arrays["fluid_force"].append(np.sqrt(r["fluid_fx"] ** 2 + r["fluid_fy"] ** 2 + r["fluid_fz"] ** 2))
            lines.InsertNextCell(line)
        out = vtkPolyData.GetData(outInfo)
        out.SetPoints(pts)
        out.SetLines(lines)
        for k, v in arrays.items():
            _add_point_array(out, k, np.asarray(v, dtype=float))
        out.GetInformation().Set(vtkDataObject.DATA_TIME_STEP(), t)
        return 1
