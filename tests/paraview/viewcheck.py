"""What a state shows, read from ParaView itself (pvpython, or the GUI's Python shell during a GUI test):
layouts and views, where the fluid and the colour bar are on screen, colour ranges, particle representation,
the time annotation. ``inspect()`` returns a JSON-able dict; ``image_check()`` reads a screenshot."""
import numpy as np

FLUID_SOURCES = ("FreeSurfaceParticles", "FluidDeviation", "Fluid Interior", "Fluid")


def _display_box(view, bounds):
    """Pixel box (x0, y0, x1, y1), origin bottom left, of a world bounding box in ``view``."""
    from vtkmodules.vtkRenderingCore import vtkCoordinate
    ren = view.GetRenderer()
    c = vtkCoordinate()
    c.SetCoordinateSystemToWorld()
    xs, ys = [], []
    for i in (0, 1):
        for j in (2, 3):
            for k in (4, 5):
                c.SetValue(bounds[i], bounds[j], bounds[k])
                x, y = c.GetComputedDoubleDisplayValue(ren)
                xs.append(x)
                ys.append(y)
    return [min(xs), min(ys), max(xs), max(ys)]


def inspect(simple=None):
    s = simple
    if s is None:
        from paraview import simple as s
    rep = {}
    layouts = s.GetLayouts()
    rep["layouts"] = sorted(k[0] for k in layouts)
    rep["views_per_layout"] = [len(s.GetViewsInLayout(lay)) for lay in layouts.values()]
    view = s.GetActiveView()
    rep["view_size"] = list(view.ViewSize)
    rep["time"] = float(view.ViewTime)
    rep["timesteps"] = [float(t) for t in s.GetTimeKeeper().TimestepValues]
    rep["sources"] = sorted(k[0] for k in s.GetSources())
    fluid = next((s.FindSource(n) for n in FLUID_SOURCES if s.FindSource(n) is not None), None)
    if fluid is not None:
        s.Render(view)
        b = fluid.GetDataInformation().GetBounds()
        rep["fluid_bounds"] = list(b)
        rep["fluid_box_px"] = _display_box(view, b)
        d = s.GetDisplayProperties(fluid, view)
        rep["representation"] = d.SMProxy.GetProperty("Representation").GetElement(0)
        rep["gaussian_radius"] = float(d.GaussianRadius)
        arr = str(d.ColorArrayName[1])
        rep["colour_array"] = arr
        if arr:
            lut = s.GetColorTransferFunction(arr)
            pts = list(lut.RGBPoints)
            rep["colour_range"] = [pts[0], pts[-4]]
            rep["lut_colours"] = lut_colours(lut)
            bar = s.GetScalarBar(lut, view)
            rep["bar_visible"] = bool(bar.Visibility)
            rep["bar_position"] = list(bar.Position)
            rep["bar_length"] = float(bar.ScalarBarLength)
    t = s.FindSource("Time")
    if t is not None:
        from paraview import servermanager as sm
        tab = sm.Fetch(t)
        rep["time_text"] = tab.GetColumn(0).GetValue(0) if tab and tab.GetNumberOfColumns() else None
    note = s.FindSource("DeviationNote")
    if note is not None:
        from paraview import servermanager as sm
        tab = sm.Fetch(note)
        rep["note_text"] = tab.GetColumn(0).GetValue(0) if tab and tab.GetNumberOfColumns() else None
    try:
        from paraview import servermanager as sm
        pdm = sm.vtkSMProxyManager.GetProxyManager().GetActiveSessionProxyManager().GetProxyDefinitionManager()
        rep["plugin"] = bool(pdm.HasDefinition("filters", "varsphFreeSurface"))
    except Exception:
        rep["plugin"] = None
    return rep


def layout_problems(rep):
    """Human-readable problems of an inspect() report ([] when the state looks right)."""
    out = []
    if rep.get("views_per_layout") != [1]:
        out.append("expected one layout holding one view, got %s views in %s" % (rep.get("views_per_layout"),
                                                                               rep.get("layouts")))
    if rep.get("representation") != "Point Gaussian":
        out.append("fluid drawn as %s, not Point Gaussian" % rep.get("representation"))
    box, (w, h) = rep.get("fluid_box_px"), rep.get("view_size", (0, 0))
    if box:
        if box[0] < -2 or box[1] < -2 or box[2] > w + 2 or box[3] > h + 2:
            out.append("fluid %s not inside the %dx%d view" % (np.round(box), w, h))
        if max((box[2] - box[0]) / w, (box[3] - box[1]) / h) < 0.3:
            out.append("fluid covers only %.0f%% x %.0f%% of the view (camera not fitted)"
                       % (100 * (box[2] - box[0]) / w, 100 * (box[3] - box[1]) / h))
        if rep.get("bar_visible") and rep["bar_position"][0] * w < box[2] - 2:
            out.append("colour bar at x = %.0f px overlaps the fluid (right edge %.0f px)"
                       % (rep["bar_position"][0] * w, box[2]))
    else:
        out.append("no fluid source found")
    if not rep.get("time_text", "").startswith("t = "):
        out.append("no time annotation (got %r)" % rep.get("time_text"))
    return out


def image_check(path, box_px):
    """(fraction of non-background pixels inside the fluid box, image size) of a PNG; the box has its origin at
    the bottom left (VTK display coordinates)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader
    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    img = r.GetOutput()
    w, h, _ = img.GetDimensions()
    px = vtk_to_numpy(img.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3].astype(int)  # row 0 = bottom
    x0, y0, x1, y1 = (int(round(v)) for v in box_px)
    x0, y0, x1, y1 = max(0, x0), max(0, y0), min(w, x1), min(h, y1)
    if x1 <= x0 or y1 <= y0:
        return 0.0, (w, h)
    region = px[y0:y1, x0:x1]
    background = np.array([255, 255, 255])   # the states draw on white
    differs = np.abs(region - background).sum(axis=2) > 30
    return float(differs.mean()), (w, h)


def lut_colours(lut, n=128):
    """``n`` RGB colours (0..1) evenly over a colour transfer function proxy's range."""
    o = lut.GetClientSideObject()
    o.Build()
    lo, hi = o.GetRange()
    out = []
    for x in np.linspace(lo, hi, n):
        c = [0.0, 0.0, 0.0]
        o.GetColor(float(x), c)
        out.append(c)
    return out


def colourmap_share(path, colours, x_max=1.0, min_saturation=0.15, min_cosine=0.995):
    """Share of the pixels of a PNG drawn in a colour map (``colours``: RGB samples of it, 0..1): pixels with
    some colour (saturation (max - min)/max above ``min_saturation``: not the white background, grey walls,
    black text) whose RGB direction is within acos(``min_cosine``) (5.7 degrees) of a colour of the map.
    Direction, not value: shaded spheres darken a colour without turning it. The greys in the middle of a
    diverging map are not counted (they cannot be told from walls). Only the image left of ``x_max`` (a
    fraction of its width) is read: the colour bar, drawn in the map, sits right of it."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader
    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    img = r.GetOutput()
    w, h, _ = img.GetDimensions()
    px = vtk_to_numpy(img.GetPointData().GetScalars()).reshape(h, w, -1)[:, :int(x_max * w), :3]
    px = px.reshape(-1, 3).astype(float) / 255.0
    mx, mn = px.max(axis=1), px.min(axis=1)
    coloured = (mx > 0.08) & ((mx - mn) > min_saturation * np.maximum(mx, 1e-9))
    c = np.asarray(colours, dtype=float)
    c = c / np.maximum(np.linalg.norm(c, axis=1), 1e-9)[:, None]
    p = px[coloured]
    p = p / np.maximum(np.linalg.norm(p, axis=1), 1e-9)[:, None]
    best = (p @ c.T).max(axis=1) if len(p) else np.zeros(0)
    return float((best >= min_cosine).sum()) / float(len(px))
