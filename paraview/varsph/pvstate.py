"""ParaView pipelines behind the states (paraview/states/), the postprocess.py pictures and `varsph paraview`.

Needs ``paraview.simple`` (pvpython, or the GUI's Python); rendering without a display needs
``xvfb-run -a -s -noreset`` (paraview/README.md). Every state reads its run through the plugin's *varsph Run*
source, so a state built with ``run=None`` (what the bundled .pvsm files hold) reads ``$VARSPH_RUN_DIR``
(run B: ``$VARSPH_OTHER_RUN_DIR``) or the working directory when it is loaded, and one saved state opens any run.

What every state shows (issue 17): one full-size render view in its own layout, particles as Point Gaussian
discs of diameter dx, the camera fitted to where the fluid goes during the run with the colour bar beside
it, ParaView's own time annotation (Annotate Time), and colour ranges taken per frame from robust
percentiles of the shown field (a Python animation cue re-applies them whenever the time changes, in the
GUI as in pvpython).

3D runs (issue 35): the same pipeline, styled for the run's dimension by style_for_run: the container's
particles clipped away on the camera's side and drawn light with their box as an outline, obstacles and bodies
in their own colour (the `part` array of varsph Run, varsph/parts.py), every particle a shaded sphere.
"""
import math
import os
import sys

import numpy as np

from .compat import load_plugin, plugin_loaded
from . import openb as _openb
from .io import frames_of_run, point_array, read_vtu, vertical_axis

PRESSURE_LUT = "Cool to Warm"
SPEED_LUT = "Viridis (matplotlib)"
DEVIATION_LUT = "Inferno (matplotlib)"
PRESSURE_PERCENTILES = (1.0, 99.0)     # robust per-frame range of pressure (noise at the walls excluded)
SPEED_PERCENTILES = (0.0, 99.0)
DEVIATION_PERCENTILES = (0.0, 98.0)    # D_max is set by a few particles; the map shows the bulk
ENV_RUN = "VARSPH_RUN_DIR"
ENV_OTHER = "VARSPH_OTHER_RUN_DIR"
WALL_GREY = [0.55, 0.55, 0.55]
FLUID_PALE = [0.72, 0.82, 0.93]
# 3D (issue 35): the container cut away on the camera's side, the rest of it light, its box as an outline;
# obstacles and bodies in a colour none of the maps above uses
WALL_LIGHT = [0.80, 0.80, 0.80]
OUTLINE_GREY = [0.45, 0.45, 0.45]
OBSTACLE_COLOUR = [0.50, 0.35, 0.55]   # mauve: direction cosine < 0.99 to every colour of the three maps


def pv():
    """paraview.simple with the varsph plugin loaded (once) and its proxies as simple.varsphRun, ... (a plugin
    loaded by --plugins, or by LoadPlugin(..., ns=globals()) in the GUI's shell, is not in simple yet)."""
    from paraview import simple
    if not plugin_loaded():
        load_plugin()
    if not hasattr(simple, "varsphRun") and hasattr(simple, "_add_functions"):
        simple._add_functions(vars(simple))
    return simple


# --- the run -----------------------------------------------------------------------------------------
def resolve(run, variable=ENV_RUN):
    """Run directory of ``run``, or of the environment / working directory when ``run`` is None."""
    from .io import resolve_run
    return os.path.dirname(resolve_run(os.path.abspath(run) if run else "", variable))


class RunInfo:
    """What the pictures need to know about a run: dimension, dx, the vertical axis, frame times and the
    box the fluid occupies over the run (union over up to 5 frames spread over the run)."""

    def __init__(self, run):
        self.run = run
        self.frames = frames_of_run(run)
        if not self.frames:
            raise ValueError("run %s has no frames" % run)
        self.times = [t for t, _ in self.frames]
        picks = sorted(set(int(round(k)) for k in np.linspace(0, len(self.frames) - 1, min(5, len(self.frames)))))
        lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
        first = None
        for k in picks:
            f = read_vtu(self.frames[k][1], self.frames[k][0])
            first = first or f
            x = f.points[f.fluid_mask()] if f.fluid_mask().any() else f.points
            if len(x):
                lo, hi = np.minimum(lo, x.min(axis=0)), np.maximum(hi, x.max(axis=0))
        self.arrays = set(first.arrays)          # point arrays of the frames
        self.dimension = first.dimension
        self.dx = first.dx if "dx" in first.fields else float(np.max(hi - lo)) / 50.0
        self.up = vertical_axis(run, self.dimension)
        pad = 3.0 * self.dx   # the first wall layers stay in the picture
        self.lo, self.hi = lo - pad, hi + pad
        if self.dimension == 2:
            self.lo[2] = self.hi[2] = 0.0


# --- views ---------------------------------------------------------------------------------------------
def _empty_active_view(s):
    """The active render view when it is alone in its layout and shows nothing (the GUI's start-up view)."""
    v = s.GetActiveView()
    if v is None or v.GetXMLName() != "RenderView":
        return None
    if any(r.Visibility for r in v.Representations if hasattr(r, "Visibility")):
        return None
    layout = s.GetLayout(v)
    if layout is not None and len(s.GetViewsInLayout(layout)) > 1:
        return None
    return v


def new_view(size=None, name="varsph"):
    """A render view alone in its own layout (never a split of the user's layout). ``size`` (w, h) sets the
    render size for pvpython; in the GUI the window decides."""
    s = pv()
    view = _empty_active_view(s)
    if view is None:
        view = s.CreateView("RenderView", registrationName=name + " view")
        try:
            layout = s.CreateLayout(name)
            s.AssignViewToLayout(view=view, layout=layout, hint=0)
        except Exception:
            s.AssignViewToLayout(view)
    if size:
        view.ViewSize = list(size)
    view.OrientationAxesVisibility = 0
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.Background = [1.0, 1.0, 1.0]
    s.SetActiveView(view)
    return view


def _aspect(view):
    w, h = list(view.ViewSize) if view.ViewSize else (0, 0)
    return w / h if w > 50 and h > 50 else 1.6


def fit_camera(view, info, bar_fraction=0.18):
    """Fit the camera to the fluid's box over the run, leaving the right ``bar_fraction`` of the view for
    the colour bar and the top 14 % for the labels. 2D: looking down -z, parallel projection; 3D: oblique,
    the axis opposite to gravity up."""
    s = pv()
    s.Render(view)   # paraview.simple resets the camera at a view's first render: let it happen first
    lo, hi = info.lo, info.hi
    c = 0.5 * (lo + hi)
    cam = view.GetActiveCamera()
    if info.dimension == 2:
        view.InteractionMode = "2D"
        view.CameraParallelProjection = 1
        a = _aspect(view)
        w, h = hi[0] - lo[0], hi[1] - lo[1]
        scale = max(h / (2 * 0.82), w / (2 * a * (1.0 - bar_fraction - 0.03)))
        cx = c[0] + (bar_fraction / 2) * 2 * scale * a
        cy = lo[1] + 0.92 * scale
        cam.SetFocalPoint(cx, cy, 0.0)
        cam.SetPosition(cx, cy, 10.0 * max(w, h, 1e-6))
        cam.SetViewUp(0.0, 1.0, 0.0)
        cam.SetParallelScale(scale)
        view.CameraParallelScale = scale
    else:
        up = [0.0, 0.0, 0.0]
        up[info.up] = 1.0
        others = [k for k in range(3) if k != info.up]
        d = [0.0, 0.0, 0.0]
        d[others[0]], d[others[1]], d[info.up] = 0.6, -1.0, 0.7
        cam.SetFocalPoint(*c)
        cam.SetPosition(*(c + np.asarray(d)))
        cam.SetViewUp(*up)
        view.ResetCamera(float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1]), float(lo[2]), float(hi[2]))
        cam.Dolly(0.85)
    style_for_run(view, info, c, d if info.dimension == 3 else None)
    s.Render(view)


def style_for_run(view, info, centre, towards_camera):
    """What differs between a 2D and a 3D run in the same pipeline (_fluid_and_walls), for the run ``info``.

    3D: the walls' cut-away plane through the fluid's centre, facing the camera (``towards_camera``), the
    walls light, the obstacles in their own colour, every particle a shaded sphere, the walls' outline shown.
    2D: nothing clipped, every boundary particle a grey disc, no outline."""
    s = pv()
    three = info.dimension == 3
    cut = s.FindSource("WallsCutaway")
    if cut is not None:
        if three:
            n = np.asarray(towards_camera, dtype=float)
            cut.ClipType.Origin = [float(v) for v in centre]
            cut.ClipType.Normal = [float(v) for v in n / np.linalg.norm(n)]
        else:   # the plane above the z = 0 plane of a 2D run: every wall particle is kept
            cut.ClipType.Origin = [0.0, 0.0, 1.0 + 1e3 * info.dx]
            cut.ClipType.Normal = [0.0, 0.0, 1.0]
    for name, colour in (("WallsCutaway", WALL_LIGHT if three else WALL_GREY),
                         ("Obstacles", OBSTACLE_COLOUR if three else WALL_GREY)):
        d = _display_in(view, s.FindSource(name))
        if d is not None:
            d.AmbientColor = d.DiffuseColor = colour
    d = _display_in(view, s.FindSource("WallsOutline"))
    if d is not None:
        d.Visibility = int(three)
    for d in view.Representations:
        if getattr(d, "Representation", None) == "Point Gaussian":
            d.ShaderPreset = "Sphere" if three else "Plain circle"


def _display_in(view, src):
    """The representation of ``src`` in ``view``, or None (GetDisplayProperties would make one)."""
    if src is None:
        return None
    for d in view.Representations:
        if getattr(d, "Input", None) == src:
            return d
    return None


def _points(src, view, dx, colour=None, opacity=1.0, scale=1.0):
    """Point Gaussian discs of diameter ``scale`` * dx (the particle spacing); shaded spheres in 3D, where
    shading tells near from far (style_for_run)."""
    s = pv()
    d = s.Show(src, view)
    d.SetRepresentationType("Point Gaussian")
    d.GaussianRadius = 0.5 * dx * scale
    d.ShaderPreset = "Plain circle"
    try:
        d.ScaleByArray = 0
    except AttributeError:
        pass
    if colour is not None:
        d.ColorArrayName = ["POINTS", ""]
        d.AmbientColor = colour
        d.DiffuseColor = colour
    d.Opacity = opacity
    return d


def _colour_bar(display, view, array, component, lut_name, title, fmt="%-.4g"):
    s = pv()
    s.ColorBy(display, ("POINTS", array) if component is None else ("POINTS", array, component))
    lut = s.GetColorTransferFunction(array)
    lut.ApplyPreset(lut_name, True)
    lut.AutomaticRescaleRangeMode = "Never"
    display.SetScalarBarVisibility(view, True)
    bar = s.GetScalarBar(lut, view)
    bar.Title = title
    bar.ComponentTitle = ""
    bar.TitleColor = [0, 0, 0]
    bar.LabelColor = [0, 0, 0]
    bar.TitleFontSize = 16
    bar.LabelFontSize = 14
    bar.Orientation = "Vertical"
    bar.WindowLocation = "Any Location"
    bar.Position = [0.87, 0.12]
    bar.ScalarBarLength = 0.7
    bar.RangeLabelFormat = fmt
    bar.AutomaticLabelFormat = 1
    return lut


def _label_style(d, location, size):
    """Black text on a white, slightly transparent box (readable over walls and particles)."""
    d.Color = [0, 0, 0]
    d.WindowLocation = location
    d.FontSize = size
    try:
        d.BackgroundColor = [1.0, 1.0, 1.0, 0.8]
    except Exception:
        pass
    return d


def _text(view, text, location="Upper Left Corner", size=15, name=None):
    s = pv()
    t = s.Text(registrationName=name, Text=text) if name else s.Text(Text=text)
    _label_style(s.Show(t, view), location, size)
    return t


def time_annotation(view, src):
    """ParaView's own time annotation (Annotate Time Filter) of the data shown: the time of the frame
    ``src`` outputs ('t = 0.300 s'), which is the frame on screen even when the animation time is not a
    frame time of this run."""
    s = pv()
    a = s.AnnotateTimeFilter(registrationName="Time", Input=src)
    a.Format = "t = {time:.3f} s"
    _label_style(s.Show(a, view), "Upper Right Corner", 18)
    return a


# --- robust per-frame colour ranges ----------------------------------------------------------------------
def percentile_range(values, pct, floor0=False):
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if len(v) == 0:
        return 0.0, 1.0
    lo, hi = (float(x) for x in np.percentile(v, pct))
    if floor0:
        lo = 0.0
    if not hi > lo:
        pad = max(abs(hi), 1.0) * 1e-6
        lo, hi = lo - pad, hi + pad
    return lo, hi


def _output_at(src, t):
    """The data of ``src`` at time ``t``: the algorithm's own output in a built-in session (GUI, pvpython),
    else fetched from the server."""
    src.UpdatePipeline(t)
    algo = src.GetClientSideObject()
    if algo is not None and algo.GetOutputDataObject(0) is not None:
        return algo.GetOutputDataObject(0)
    from paraview import servermanager as sm
    return sm.Fetch(src)


def robust_rescale(source_name, array, lut_array, pct, floor0=False, t=None):
    """Set the colour range of ``lut_array`` (one name or several) to the ``pct`` percentiles of ``array``
    (magnitude for vectors) in the output of source ``source_name`` at time ``t``. Returns (lo, hi), or None
    without data."""
    s = pv()
    src = s.FindSource(source_name)
    if src is None:
        return None
    v = point_array(_output_at(src, t), array)
    if v is None:
        return None
    if v.ndim > 1:
        v = np.linalg.norm(v, axis=1)
    lo, hi = percentile_range(v, pct, floor0)
    for name in (lut_array,) if isinstance(lut_array, str) else lut_array:
        s.GetColorTransferFunction(name).RescaleTransferFunction(lo, hi)
    return lo, hi


_FITTED = {}   # view name -> run directory the camera was last fitted to


def on_time(view_name, reader_name, calls, t, fitted_for=""):
    """What the state's animation cue does at every time change (GUI, pvpython, after loading a .pvsm):
    fit the camera when the view shows a run other than ``fitted_for`` (the run the saved camera was fitted
    to; "" for a portable state) the first time it shows it, and set the robust colour ranges of ``calls``
    (robust_rescale arguments) for time ``t``."""
    try:
        s = pv()
        view = s.FindView(view_name) or s.GetActiveView()
        reader = s.FindSource(reader_name)
        if view is not None and reader is not None:
            reader.UpdatePipelineInformation()
            pvd = reader.GetProperty("ResolvedFile").GetElement(0) if reader.GetProperty("ResolvedFile") else ""
            run = os.path.dirname(pvd) if pvd else ""
            if run and view_name not in _FITTED and run == fitted_for:
                _FITTED[view_name] = run            # the saved camera is this run's: keep it
            if run and _FITTED.get(view_name) != run:
                info = RunInfo(run)
                for d in view.Representations:   # particles of this run's size
                    if getattr(d, "Representation", None) == "Point Gaussian":
                        d.GaussianRadius = 0.5 * info.dx
                fit_camera(view, info)
                _FITTED[view_name] = run
        for c in calls:
            robust_rescale(*c, t=t)
    except Exception as e:  # a cue must not break the time slider of the GUI: say why and go on
        print("varsph: view not updated at t = %s (%s)" % (t, e), file=sys.stderr)


_CUE_SCRIPT = '''
def start_cue(self):
    pass

def tick(self):
    from varsph import pvstate
    pvstate.on_time({view!r}, {reader!r}, {calls!r}, self.GetClockTime(), {fitted_for!r})

def end_cue(self):
    pass
'''


def add_cue(view_name, reader_name, calls, fitted_for=""):
    """A Python animation cue, saved with the state, that runs ``on_time`` at every time change."""
    s = pv()
    from paraview import servermanager as sm
    cue = sm.animation.PythonAnimationCue()
    sm.ProxyManager().RegisterProxy("animation", "varsph view update", cue)   # saved with the state
    # relative time with an unbounded window: the cue ticks at every time, also at a time beyond the end of
    # a run (a portable state saved at t = 1 s opened on a run that ends earlier)
    cue.TimeMode = "Relative"
    cue.StartTime = -1e30
    cue.EndTime = 1e30
    cue.Script = _CUE_SCRIPT.format(view=view_name, reader=reader_name, calls=[tuple(c) for c in calls],
                                    fitted_for=fitted_for)
    s.GetAnimationScene().Cues.append(cue)
    return cue


# --- time --------------------------------------------------------------------------------------------------
def pick_time(times, time=None):
    """The frame time shown for a requested ``time``: the nearest one (default: the last)."""
    if not times:
        return 0.0
    if time is None:
        return times[-1]
    return min(times, key=lambda t: abs(t - time))


def view_name(view):
    from paraview import servermanager as sm
    return sm.ProxyManager().GetProxyName("views", view)


def set_time(view, t):
    """Show time ``t`` in a view built here (ranges and camera follow through the state's cue)."""
    s = pv()
    scene = s.GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = t
    view.ViewTime = t
    st = _STATES.get(view_name(view))
    if st:
        on_time(view_name(view), st[0], st[1], t)
    s.Render(view)


_STATES = {}   # view name -> (reader name, robust_rescale calls) of the state it shows


def _finish(view, info, reader_name, calls, times, time, portable):
    name = view_name(view)
    _STATES[name] = (reader_name, list(calls))
    add_cue(name, reader_name, calls, "" if portable else info.run)
    fit_camera(view, info)
    _FITTED[name] = info.run
    set_time(view, pick_time(times, time))
    reader = pv().FindSource(reader_name)
    if reader is not None:      # the Properties panel shows the run, not the last label made
        pv().SetActiveSource(reader)
    return view


# --- the states --------------------------------------------------------------------------------------------
def open_run(run=None, name="run", variable=ENV_RUN):
    """The plugin's *varsph Run* source: ``run`` (absolute), or, with ``run=None``, ``$variable`` / the
    working directory at every load (what makes a saved state portable)."""
    s = pv()
    r = s.varsphRun(registrationName=name, RunDirectory=os.path.abspath(run) if run else "", RunVariable=variable)
    r.UpdatePipelineInformation()
    return r


def _select(s, name, src, array, value):
    """Threshold keeping the particles whose point array ``array`` equals ``value``. The range is set after
    the proxy is made: ParaView 5.11 resets a threshold range passed at creation to the array's range when
    the input already holds data and the value equals the property's default (a kind == 0 'Fluid' became
    every particle once the walls were shown first)."""
    t = s.Threshold(registrationName=name, Input=src, Scalars=["POINTS", array])
    t.LowerThreshold = value
    t.UpperThreshold = value
    return t


def _fluid_and_walls(s, src, info, views, prefix="", fluid=True):
    """The run's boundary particles drawn in ``views`` (one view or several); returns the fluid (kind 0)
    when ``fluid``.

    The `part` array of varsph Run (varsph/parts.py) tells the container (*Walls*, part 1) from obstacles and
    bodies (*Obstacles*, part 2). The walls are drawn through *WallsCutaway*, a clip whose plane
    style_for_run aims at the camera in 3D (the wall particles between the camera and the water go, the
    far walls and the floor stay), with their box as *WallsOutline*. The pipeline is the same for 2D and
    3D runs, so that one saved state opens either; style_for_run sets what differs (2D: nothing clipped,
    no outline, every boundary particle a grey disc, as before issue 35)."""
    views = views if isinstance(views, (list, tuple)) else [views]
    walls = _select(s, prefix + "Walls", src, "part", 1)
    obstacles = _select(s, prefix + "Obstacles", src, "part", 2)
    cut = s.Clip(registrationName=prefix + "WallsCutaway", Input=walls)
    cut.ClipType = "Plane"
    cut.Crinkleclip = 1      # whole particles (vertex cells), nothing interpolated
    cut.Invert = 1           # keep the side away from the camera (the plane's normal points at it)
    outline = s.Outline(registrationName=prefix + "WallsOutline", Input=walls)
    for view in views:
        _points(cut, view, info.dx, colour=WALL_GREY)
        _points(obstacles, view, info.dx, colour=WALL_GREY)
        od = s.Show(outline, view)
        od.ColorArrayName = ["POINTS", ""]
        od.AmbientColor = od.DiffuseColor = OUTLINE_GREY
    if not fluid:
        return None
    return _select(s, prefix + "Fluid", src, "kind", 0)


def free_surface_state(run=None, time=None, surface=False, view=None, portable=False):
    """(1) The free surface (Marrone et al. 2010): free-surface particles coloured by speed over the pale
    fluid, walls grey; ``surface`` adds the reconstructed surface."""
    s = pv()
    run_dir = resolve(None if portable else run)
    info = RunInfo(run_dir)
    view = view or new_view(name="varsph free surface")
    r = open_run(None if portable else run_dir)
    fluid = _fluid_and_walls(s, r, info, view)
    _points(fluid, view, info.dx, colour=FLUID_PALE)
    # on the whole run: walls are neighbours, so fluid wetting a wall is not a free surface
    fs = s.varsphFreeSurface(registrationName="FreeSurface", Input=r, ReconstructSurface=int(bool(surface)))
    surf = _select(s, "FreeSurfaceParticles", s.OutputPort(fs, 0), "free_surface", 1)
    d = _points(surf, view, info.dx, colour=None if "velocity" in info.arrays else [0.1, 0.25, 0.6])
    if "velocity" in info.arrays:      # (`varsph sample` output has no velocity: free surface in dark blue)
        _colour_bar(d, view, "velocity", "Magnitude", SPEED_LUT, "speed [m/s]", fmt="%-.3g")
    if surface:
        sd = s.Show(s.OutputPort(fs, 1), view)
        sd.ColorArrayName = ["POINTS", ""]
        if info.dimension == 2:
            sd.AmbientColor = sd.DiffuseColor = [0.1, 0.1, 0.1]
            sd.LineWidth = 2.0
        else:
            sd.AmbientColor = sd.DiffuseColor = [0.3, 0.55, 0.9]
            sd.Opacity = 0.35
    _text(view, "free surface (Marrone et al. 2010)%s" % (", particles coloured by speed" if "velocity" in info.arrays
                                                           else ""), name="Title")
    time_annotation(view, r)
    calls = [("FreeSurfaceParticles", "velocity", "velocity", SPEED_PERCENTILES, True)] if "velocity" in info.arrays else []
    return _finish(view, info, "run", calls, info.times, time, portable)


def pressure_state(run=None, time=None, prange=None, smoothed=False, view=None, portable=False):
    """(2) Fluid pressure, per-frame colour range from the 1st-99th percentiles (or ``prange``);
    ``smoothed`` colours the Shepard SPH average (varsph Smoothed Pressure) instead of the raw values."""
    s = pv()
    run_dir = resolve(None if portable else run)
    info = RunInfo(run_dir)
    if "pressure" not in info.arrays:
        raise ValueError("the frames of %s have no point array 'pressure' (they have %s)"
                         % (run_dir, ", ".join(sorted(info.arrays))))
    view = view or new_view(name="varsph pressure")
    r = open_run(None if portable else run_dir)
    fluid = _fluid_and_walls(s, r, info, view)
    shown, array = fluid, "pressure"
    if smoothed:
        shown = s.varsphSmoothedPressure(registrationName="SmoothedPressure", Input=fluid)
        array = "pressure_smoothed"
    d = _points(shown, view, info.dx)
    lut = _colour_bar(d, view, array, None, PRESSURE_LUT,
                      "smoothed pressure [Pa]" if smoothed else "pressure [Pa]", fmt="%-.0f")
    _text(view, "pressure (%s)%s" % ("SPH-smoothed" if smoothed else "particle values",
                                     "" if prange else ", colours: 1st-99th percentile of the frame"),
          name="Title")
    time_annotation(view, r)
    calls = [] if prange else [("SmoothedPressure" if smoothed else "Fluid", array, array, PRESSURE_PERCENTILES)]
    if prange:
        lut.RescaleTransferFunction(*prange)
    return _finish(view, info, "run", calls, info.times, time, portable)


def pressure_pair(run=None, time=None, size=None):
    """Raw particle pressure beside the SPH-smoothed pressure (varsph Smoothed Pressure), one layout of two
    views with the same colour range (1st-99th percentile of the raw values of the frame). Returns the
    layout; the views follow the animation time like the states."""
    s = pv()
    run_dir = resolve(run)
    info = RunInfo(run_dir)
    layout = s.CreateLayout("varsph pressure raw | smoothed")
    layout.SplitHorizontal(0, 0.5)
    r = open_run(run_dir)
    views = []
    for cell, smoothed in ((1, False), (2, True)):
        view = s.CreateView("RenderView", registrationName="varsph pressure %s view" % ("smoothed" if smoothed else "raw"))
        s.AssignViewToLayout(view=view, layout=layout, hint=cell)
        if size:
            view.ViewSize = [size[0] // 2, size[1]]
        view.OrientationAxesVisibility = 0
        try:
            view.UseColorPaletteForBackground = 0
        except AttributeError:
            pass
        view.Background = [1.0, 1.0, 1.0]
        views.append(view)
    fluid = _fluid_and_walls(s, r, info, views)
    sm = s.varsphSmoothedPressure(registrationName="SmoothedPressure", Input=fluid)
    for view, src, array, title in ((views[0], fluid, "pressure", "particle pressure"),
                                    (views[1], sm, "pressure_smoothed",
                                     "SPH-smoothed pressure (Shepard average over neighbours)")):
        d = _points(src, view, info.dx)
        _colour_bar(d, view, array, None, PRESSURE_LUT, "pressure [Pa]", fmt="%-.0f")
        t = s.Text(registrationName="Title " + array, Text=title)
        _label_style(s.Show(t, view), "Upper Left Corner", 15)
        a = s.AnnotateTimeFilter(registrationName="Time " + array, Input=r)
        a.Format = "t = {time:.3f} s"
        _label_style(s.Show(a, view), "Upper Right Corner", 18)
    calls = [("Fluid", "pressure", ("pressure", "pressure_smoothed"), PRESSURE_PERCENTILES)]
    for view in views:
        _STATES[view_name(view)] = ("run", calls)
        fit_camera(view, info)
        _FITTED[view_name(view)] = info.run
    add_cue(view_name(views[0]), "run", calls, info.run)
    set_time(views[0], pick_time(info.times, time))
    return layout


DEVIATION_NOTE = (
    "'A - B at t = %.4g s (%s)   D_max = %.3g m' % (t_compared[0], "
    "('last time both runs have' + ('; A ends at %.4g s, B at %.4g s' % (t_end_A[0], t_end_B[0]) "
    "if abs(t_end_A[0] - t_end_B[0]) > 1e-9 else '')) if abs(t_compared[0] - t_last_common[0]) <= 1e-9 "
    "else ('a time both runs have, %d in common' % n_common[0]), D_max[0])")


def deviation_state(run_a=None, run_b=None, time=None, drange=None, view=None, portable=False):
    """(3) Run A's fluid coloured by |q_A - q_B| (particles matched by id) at times both runs have (default
    the last common frame), colour range 0 .. 98th percentile of the frame (or ``drange``); the picture says
    which time is compared and D_max there."""
    s = pv()
    a_dir = resolve(None if portable else run_a, ENV_RUN)
    b_dir = resolve(None if portable else run_b, ENV_OTHER)
    from .deviation import common_times
    pairs = common_times(a_dir, b_dir)
    if not pairs:
        raise ValueError("runs %s and %s have no frame times in common" % (a_dir, b_dir))
    info = RunInfo(a_dir)
    view = view or new_view(name="varsph deviation")
    ra = open_run(None if portable else a_dir, "A", ENV_RUN)
    rb = open_run(None if portable else b_dir, "B", ENV_OTHER)
    try:  # the animation steps through the common times only (the deviation filter's), not A's or B's
        s.GetTimeKeeper().SuppressedTimeSources = [ra, rb]
    except AttributeError:
        pass
    dev = s.varsphDeviation(registrationName="Deviation", Input=ra, Reference=rb)
    if portable:   # a saved state opens at its first frame (see make_pvsm.py): show the end state regardless
        dev.CompareAt = "Last Common Time"
    _fluid_and_walls(s, ra, info, view, fluid=False)   # run A's walls and obstacles
    fluid = _select(s, "FluidDeviation", dev, "kind", 0)
    d = _points(fluid, view, info.dx)
    lut = _colour_bar(d, view, "deviation_magnitude", None, DEVIATION_LUT, "distance A - B [m]", fmt="%-.3g")
    note = s.PythonAnnotation(registrationName="DeviationNote", Input=dev)
    note.ArrayAssociation = "Field Data"
    note.Expression = DEVIATION_NOTE
    _label_style(s.Show(note, view), "Upper Left Corner", 15)
    time_annotation(view, dev)
    calls = [] if drange else [("FluidDeviation", "deviation_magnitude", "deviation_magnitude",
                                DEVIATION_PERCENTILES, True)]
    if drange:
        lut.RescaleTransferFunction(*drange)
    return _finish(view, info, "A", calls, [a for a, _ in pairs], time, portable)


INLET_COLOUR = [0.98, 0.55, 0.10]    # orange: inflow buffer particles (not in Viridis, the speed map)
OUTLET_COLOUR = [0.85, 0.15, 0.45]   # crimson: outflow buffer particles
ARROW_COLOUR = [0.0, 0.0, 0.0]
ARROWS_ACROSS = 15                    # about this many velocity arrows along the longer side of the fluid


def open_flow_state(run=None, time=None, vrange=None, view=None, portable=False):
    """(4) Open boundaries (issue 32, docs/open_boundaries.md): the fluid coloured by speed (0 .. 99th
    percentile of the frame, or ``vrange``), the inflow zones' buffer particles orange and the outflow zones'
    crimson (`open_kind` of varsph Run), walls grey, and black velocity arrows on a subset of the fluid
    (Glyph, every n-th particle, length proportional to the speed: ``ARROWS_ACROSS`` arrows along the
    fluid's longer side, the longest about 3 spacings)."""
    s = pv()
    run_dir = resolve(None if portable else run)
    info = RunInfo(run_dir)
    if "open_zone" not in info.arrays or "velocity" not in info.arrays:
        raise ValueError("the frames of %s have no point array 'open_zone' and 'velocity': not a run with open "
                         "boundaries (they have %s)" % (run_dir, ", ".join(sorted(info.arrays))))
    view = view or new_view(name="varsph open flow")
    r = open_run(None if portable else run_dir)
    fluid_all = _fluid_and_walls(s, r, info, view)
    fluid = _select(s, "Fluid Interior", fluid_all, "open_kind", 0)
    inflow = _select(s, "Inflow Zones", r, "open_kind", 1)
    outflow = _select(s, "Outflow Zones", r, "open_kind", 2)
    _points(inflow, view, info.dx, colour=INLET_COLOUR)
    _points(outflow, view, info.dx, colour=OUTLET_COLOUR)
    d = _points(fluid, view, info.dx)
    lut = _colour_bar(d, view, "velocity", "Magnitude", SPEED_LUT, "speed [m/s]", fmt="%-.3g")
    # arrows: n such that about ARROWS_ACROSS^2 (2D) arrows cover the fluid; length 3 dx at the largest speed
    last = _output_at(r, info.times[-1])
    v = point_array(last, "velocity")
    oz = point_array(last, "open_zone")
    kind = point_array(last, "kind")
    inner = (np.asarray(kind).reshape(-1) == 0) & (np.asarray(oz).reshape(-1) < 0)
    speed = np.linalg.norm(np.asarray(v).reshape(len(inner), -1)[inner], axis=1) if inner.any() else np.zeros(1)
    umax = float(np.percentile(speed, 99)) if len(speed) else 0.0
    extent = float(np.max(info.hi - info.lo)) if np.all(np.isfinite(info.hi - info.lo)) else 1.0
    cells = max(1.0, (extent / info.dx) / ARROWS_ACROSS) ** info.dimension
    glyph = s.Glyph(registrationName="Velocity Arrows", Input=fluid, GlyphType="Arrow")
    glyph.OrientationArray = ["POINTS", "velocity"]
    glyph.ScaleArray = ["POINTS", "velocity"]
    glyph.ScaleFactor = 3.0 * info.dx / umax if umax > 0 else info.dx
    glyph.GlyphMode = "Every Nth Point"
    glyph.Stride = max(1, int(round(cells)))
    gd = s.Show(glyph, view)
    gd.ColorArrayName = ["POINTS", ""]
    gd.AmbientColor = gd.DiffuseColor = ARROW_COLOUR
    names = _openb.zones(run_dir)
    legend = "; ".join("%s '%s' %s" % (z["kind"], z["name"], "orange" if z["kind"] == "inlet" else "crimson")
                       for z in names if z["kind"])
    _text(view, "open boundaries: fluid coloured by speed, arrows = velocity\n%s" % legend, name="Title")
    time_annotation(view, r)
    calls = [] if vrange else [("Fluid Interior", "velocity", "velocity", SPEED_PERCENTILES, True)]
    if vrange:
        lut.RescaleTransferFunction(*vrange)
    return _finish(view, info, "run", calls, info.times, time, portable)


ELEVATION_LUT = "Cool to Warm"          # diverging: troughs blue, still water white-grey, crests red


def still_water_level(run, up=None):
    """The still-water level of a run [m] along the vertical axis ``up`` (default: opposite to gravity), as the
    solver's wavemakers take it (src/sim/boundary_motion.cpp): the top of the particle rows the scene's fluid
    boxes hold (a box holds floor(height / dx) rows: its water is that deep), or the bed plus a wavemaker's
    ``depth`` where one names it. ValueError when the resolved scene (RUN/run.json) has no fluid box."""
    import json
    d = run if os.path.isdir(run) else os.path.dirname(run)
    with open(os.path.join(d, "run.json")) as f:
        scene = json.load(f).get("scene", {})
    dim = int(scene.get("dimension", 2))
    up = vertical_axis(d, dim) if up is None else up
    dx = float(scene["particles"]["spacing"])
    tops, beds = [], []
    for b in scene.get("bodies", []):
        if b.get("kind") == "fluid" and b.get("shape") == "box" and len(b.get("min", [])) == dim:
            rows = math.floor((b["max"][up] - b["min"][up]) / dx + 1e-6)
            tops.append(b["min"][up] + rows * dx)
            beds.append(b["min"][up])
    if not tops:
        raise ValueError("%s: the scene has no fluid box, so no still-water level to measure the elevation from" % d)
    for b in scene.get("bodies", []):
        m = b.get("motion") or {}
        if m.get("type") in ("piston", "flap") and "depth" in m:
            return min(beds) + float(m["depth"])
    return max(tops)


def elevation_state(run=None, time=None, erange=None, view=None, portable=False):
    """(5) Waves (issue 31, docs/waves.md): the free-surface particles (Marrone et al. 2010) coloured by their
    elevation above still water: eta = y - (level - dx/2) in 2D (z in 3D), level the still-water level
    (still_water_level) and level - dx/2 where the top row's centres sit at rest (the surface lies half a spacing
    above the surface particles' centres: still water shows 0), on a
    diverging map symmetric about 0 (troughs blue, crests red) whose range is fixed over the run (the largest
    |eta| of the fluid's highest particles in up to 5 frames, or ``erange``), the fluid pale under them, walls
    grey."""
    s = pv()
    run_dir = resolve(None if portable else run)
    info = RunInfo(run_dir)
    level = still_water_level(run_dir, info.up)
    view = view or new_view(name="varsph elevation")
    r = open_run(None if portable else run_dir)
    fluid = _fluid_and_walls(s, r, info, view)
    _points(fluid, view, info.dx, colour=FLUID_PALE)
    fs = s.varsphFreeSurface(registrationName="FreeSurface", Input=r, ReconstructSurface=0)
    surf = _select(s, "FreeSurfaceParticles", s.OutputPort(fs, 0), "free_surface", 1)
    calc = s.Calculator(registrationName="Elevation", Input=surf)
    calc.ResultArrayName = "elevation"
    rest = level - 0.5 * info.dx      # the top row's centres in still water
    calc.Function = "coords%s - (%.17g)" % ("XYZ"[info.up], rest)
    d = _points(calc, view, info.dx, scale=1.4)
    lut = _colour_bar(d, view, "elevation", None, ELEVATION_LUT, "elevation above still water [m]", fmt="%-.3g")
    if erange:
        lo, hi = erange
    else:      # symmetric: the crests' height above still water over the run (at least half a spacing)
        a = 0.5 * info.dx
        picks = sorted(set(int(round(k)) for k in np.linspace(0, len(info.frames) - 1, min(5, len(info.frames)))))
        for k in picks:
            f = read_vtu(info.frames[k][1], info.frames[k][0])
            x = f.points[f.fluid_mask()]
            if len(x):
                a = max(a, abs(float(x[:, info.up].max()) - rest))
        lo, hi = -a, a
    lut.RescaleTransferFunction(lo, hi)
    _text(view, "free surface coloured by elevation above still water (level %.4g m; particle centres, 0 at rest)"
          % level, name="Title")
    time_annotation(view, r)
    return _finish(view, info, "run", [], info.times, time, portable)


STATES = {"free_surface": free_surface_state, "pressure": pressure_state, "deviation": deviation_state,
          "open_flow": open_flow_state, "elevation": elevation_state}


def screenshot(view, path, size=None):
    """PNG of a view or a layout (``size``: pixels of the whole image)."""
    s = pv()
    os.makedirs(os.path.dirname(os.path.abspath(path)) or ".", exist_ok=True)
    if view.GetXMLName() == "RenderView":
        s.Render(view)
    if size:
        s.SaveScreenshot(path, view, ImageResolution=list(size))
    else:
        s.SaveScreenshot(path, view)
    return path


def hard_exit(code=0):
    """Exit without ParaView's interpreter teardown.

    pvpython 5.11 under xvfb-run intermittently crashes (SIGSEGV/SIGABRT) while tearing down render views
    at interpreter exit, after all files are written, which turns a successful run into a failed exit status.
    Everything is written and closed by now, so flush and leave with the real status."""
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
