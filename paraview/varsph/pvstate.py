"""ParaView pipelines behind the state scripts (paraview/states/*.py) and postprocess.py snapshots.

Needs ``paraview.simple`` (pvpython); rendering without a display needs ``xvfb-run -a pvpython``.
Every function takes the run directory (or its .pvd), so the states work from any working directory.
"""
import os
import sys

import numpy as np

from .compat import load_plugin
from .io import find_pvd, frames_of_run, read_vtu, vertical_axis

PRESSURE_LUT = "Cool to Warm"
DEVIATION_LUT = "Viridis (matplotlib)"
_loaded = {"__varsph__": True}   # non-empty: LoadPlugin ignores an empty ns


def pv():
    """paraview.simple with the varsph filters loaded (once)."""
    from paraview import simple
    if "varsphFreeSurface" not in _loaded:
        load_plugin(ns=_loaded)
    return simple


def filters():
    pv()
    return _loaded


def pressure_range(run, frame_index=0):
    """Fixed colour range: fluid pressure of one frame (default the first), widened to include 0."""
    fr = frames_of_run(run)
    f = read_vtu(fr[frame_index][1], fr[frame_index][0])
    p = np.asarray(f.arrays.get("pressure", np.zeros(1)), dtype=float)[f.fluid_mask()]
    lo, hi = (float(min(0.0, p.min())), float(max(0.0, p.max()))) if len(p) else (0.0, 1.0)
    if hi <= lo:
        hi = lo + 1.0
    return lo, hi


def pick_time(reader, time=None):
    ts = list(reader.TimestepValues) if hasattr(reader.TimestepValues, "__len__") else [reader.TimestepValues]
    if not ts:
        return 0.0
    if time is None:
        return ts[-1]
    return min(ts, key=lambda t: abs(t - time))


def open_run(run, name=None):
    s = pv()
    pvd = find_pvd(run)
    r = s.PVDReader(registrationName=name or os.path.basename(os.path.dirname(os.path.abspath(pvd))),
                    FileName=os.path.abspath(pvd))
    r.UpdatePipelineInformation()
    return r


def _dimension_and_dx(run):
    fr = frames_of_run(run)
    f = read_vtu(fr[0][1], fr[0][0])
    return f.dimension, (f.dx if "dx" in f.fields else 1.0)


def _up(run):
    dim, _ = _dimension_and_dx(run)
    return vertical_axis(run, dim)


def new_view(size=(1200, 700)):
    s = pv()
    view = s.CreateView("RenderView")
    view.ViewSize = list(size)
    view.OrientationAxesVisibility = 0
    view.Background = [1.0, 1.0, 1.0]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    try:  # in the GUI the view must sit in a layout to be visible
        s.AssignViewToLayout(view)
    except Exception:
        pass
    s.SetActiveView(view)
    return view


def _points(src, view, dx, color=None, opacity=1.0):
    s = pv()
    d = s.Show(src, view)
    d.SetRepresentationType("Point Gaussian")
    d.GaussianRadius = 0.5 * dx
    d.ShaderPreset = "Plain circle"
    if color is not None:
        d.ColorArrayName = ['POINTS', '']
        d.AmbientColor = color
        d.DiffuseColor = color
    d.Opacity = opacity
    return d


def _color(display, view, array, lut_name, rng, title):
    s = pv()
    s.ColorBy(display, ("POINTS", array))
    lut = s.GetColorTransferFunction(array)
    lut.ApplyPreset(lut_name, True)
    lut.RescaleTransferFunction(rng[0], rng[1])
    lut.AutomaticRescaleRangeMode = "Never"
    display.SetScalarBarVisibility(view, True)
    bar = s.GetScalarBar(lut, view)
    bar.Title = title
    bar.ComponentTitle = ""
    bar.TitleColor = [0, 0, 0]
    bar.LabelColor = [0, 0, 0]
    return lut


def _camera(view, dim, up=2):
    """2D: look down -z. 3D: oblique view with the vertical axis (opposite gravity) up."""
    s = pv()
    view.ResetCamera()
    cam = view.GetActiveCamera()
    fp = cam.GetFocalPoint()
    if dim == 2:
        view.InteractionMode = "2D"
        cam.SetPosition(fp[0], fp[1], fp[2] + 10.0)
        cam.SetViewUp(0, 1, 0)
    else:
        upv = [0.0, 0.0, 0.0]
        upv[up] = 1.0
        # look from +x... rotated so that 'up' is up: a direction with components on the other two axes
        others = [k for k in range(3) if k != up]
        d = [0.0, 0.0, 0.0]
        d[others[0]] = 0.6
        d[others[1]] = -1.0
        d[up] = 0.7
        cam.SetPosition(fp[0] + d[0], fp[1] + d[1], fp[2] + d[2])
        cam.SetViewUp(*upv)
    view.ResetCamera()
    s.Render(view)


def _label(view, text):
    s = pv()
    t = s.Text(Text=text)
    d = s.Show(t, view)
    d.Color = [0, 0, 0]
    d.WindowLocation = "Upper Left Corner"
    d.FontSize = 14
    return t


_STATES = {}


def _set_time(view, t):
    s = pv()
    view.ViewTime = t
    try:
        s.GetAnimationScene().AnimationTime = t
    except Exception:
        pass


def _register(view, label, fmt, **extra):
    _STATES[view.GetGlobalIDAsString()] = dict(label=label, fmt=fmt, **extra)


def set_time(view, t):
    """Show time ``t`` (nearest frame) in a view built by one of the *_state functions."""
    st = _STATES.get(view.GetGlobalIDAsString())
    _set_time(view, t)
    if st:
        extra = {}
        if "deviation" in st:
            extra["dmax"] = _dmax(st["deviation"], t)
        st["label"].Text = st["fmt"].format(t=t, **extra)
    pv().Render(view)


def free_surface_state(run, time=None, surface=False, prange=None, view=None):
    """(1) free-surface particles coloured by pressure over the (faded) fluid; boundary in grey."""
    s = pv()
    f = filters()
    dim, dx = _dimension_and_dx(run)
    view = view or new_view()
    r = open_run(run)
    t = pick_time(r, time)
    fs = f["varsphFreeSurface"](registrationName="FreeSurface", Input=r, ReconstructSurface=int(bool(surface)))
    walls = s.Threshold(registrationName="Boundary", Input=r, Scalars=["POINTS", "kind"],
                        LowerThreshold=1, UpperThreshold=1)
    fluid = s.Threshold(registrationName="Fluid", Input=r, Scalars=["POINTS", "kind"],
                        LowerThreshold=0, UpperThreshold=0)
    surf = s.Threshold(registrationName="FreeSurfaceParticles", Input=fs, Scalars=["POINTS", "free_surface"],
                       LowerThreshold=1, UpperThreshold=1)
    _points(walls, view, dx, color=[0.45, 0.45, 0.45])
    _points(fluid, view, dx, color=[0.75, 0.85, 0.95], opacity=1.0)
    d = _points(surf, view, dx * 1.4)
    _color(d, view, "pressure", PRESSURE_LUT, prange or pressure_range(run), "pressure [Pa]")
    if surface:
        sd = s.Show(s.OutputPort(fs, 1), view)
        sd.ColorArrayName = ['POINTS', '']
        if dim == 2:
            sd.AmbientColor = sd.DiffuseColor = [0.1, 0.1, 0.1]
            sd.LineWidth = 2.0
        else:
            sd.AmbientColor = sd.DiffuseColor = [0.3, 0.55, 0.9]
            sd.Opacity = 0.35
    lab = _label(view, "")
    _register(view, lab, "free surface (Marrone et al. 2010)  t = {t:.4g} s")
    set_time(view, t)
    _camera(view, dim, _up(run))
    return view


def pressure_state(run, time=None, prange=None, view=None):
    """(2) fluid pressure with a fixed colour map (range of the first frame unless given) and colour bar."""
    s = pv()
    dim, dx = _dimension_and_dx(run)
    view = view or new_view()
    r = open_run(run)
    t = pick_time(r, time)
    walls = s.Threshold(registrationName="Boundary", Input=r, Scalars=["POINTS", "kind"],
                        LowerThreshold=1, UpperThreshold=1)
    fluid = s.Threshold(registrationName="Fluid", Input=r, Scalars=["POINTS", "kind"],
                        LowerThreshold=0, UpperThreshold=0)
    _points(walls, view, dx, color=[0.45, 0.45, 0.45])
    d = _points(fluid, view, dx)
    _color(d, view, "pressure", PRESSURE_LUT, prange or pressure_range(run), "pressure [Pa]")
    lab = _label(view, "")
    _register(view, lab, "pressure  t = {t:.4g} s")
    set_time(view, t)
    _camera(view, dim, _up(run))
    return view


def deviation_state(run_a, run_b, time=None, drange=None, view=None):
    """(3) run A's fluid particles coloured by |q_A - q_B| (matched by id), D_max in the title."""
    s = pv()
    f = filters()
    dim, dx = _dimension_and_dx(run_a)
    view = view or new_view()
    ra = open_run(run_a, "A")
    rb = open_run(run_b, "B")
    t = pick_time(ra, time)
    dev = f["varsphDeviation"](registrationName="Deviation", Input=ra, Reference=rb)
    fluid = s.Threshold(registrationName="FluidDeviation", Input=dev, Scalars=["POINTS", "kind"],
                        LowerThreshold=0, UpperThreshold=0)
    walls = s.Threshold(registrationName="Boundary", Input=ra, Scalars=["POINTS", "kind"],
                        LowerThreshold=1, UpperThreshold=1)
    _points(walls, view, dx, color=[0.45, 0.45, 0.45])
    d = _points(fluid, view, dx)
    dmax = _dmax(dev, t)
    rng = drange or (0.0, dmax if dmax > 0 else 1.0)
    _color(d, view, "deviation_magnitude", DEVIATION_LUT, rng, "|q_A - q_B| [m]")
    lab = _label(view, "")
    _register(view, lab, "deviation A - B (eq. 70)  t = {t:.4g} s  D_max = {dmax:.4g} m", deviation=dev)
    set_time(view, t)
    _camera(view, dim, _up(run_a))
    return view


def _dmax(dev, t):
    from paraview import servermanager as sm
    dev.UpdatePipeline(t)
    a = sm.Fetch(dev).GetFieldData().GetArray("D_max")
    return a.GetValue(0) if a is not None else float("nan")


def screenshot(view, path, size=(1200, 700)):
    s = pv()
    os.makedirs(os.path.dirname(os.path.abspath(path)) or ".", exist_ok=True)
    s.Render(view)
    s.SaveScreenshot(path, view, ImageResolution=list(size))
    return path


def hard_exit(code=0):
    """Exit without ParaView's interpreter teardown.

    pvpython 5.11 under xvfb-run intermittently crashes (SIGSEGV/SIGABRT) while tearing down render views
    at interpreter exit, after all files are written, which turns a successful run into a failed exit status.
    Everything is written and closed by now, so flush and leave with the real status."""
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
