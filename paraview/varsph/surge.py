"""Surge front and water height gauges of a dam break.

Front: the largest coordinate of the fluid particles along ``axis`` (x), as in the dam-break literature
(Martin & Moyce 1952; Koshizuka & Oka 1996; Colagrossi & Landrini 2003 plot the front position Z(t)
against time), also given relative to a reference (default: the front of the first frame).
Water height at a gauge x_g: the top of the highest fluid particle in the strip |x - x_g| <= w/2
(w = 2 dx by default), i.e. max(y_j) + dx/2, measured from the bottom of the fluid in the first frame
(min y_j - dx/2); 0 when the strip is empty (the gauges of Lobovsky et al. 2014 / the SPHERIC dam break).
"""
import numpy as np

from .io import frames_of_run, read_vtu


def surge_front(frame, axis=0):
    fl = frame.fluid_mask()
    if not fl.any():
        return float("nan")
    return float(frame.points[fl, axis].max())


def water_height(frame, gauges, axis=0, vertical=1, width=None, bottom=None):
    fl = frame.fluid_mask()
    x = frame.points[fl]
    dx = frame.dx if "dx" in frame.fields else 0.0
    width = 2.0 * dx if width is None else width
    if bottom is None:
        bottom = (x[:, vertical].min() - 0.5 * dx) if len(x) else 0.0
    out = []
    for g in np.atleast_1d(gauges):
        s = np.abs(x[:, axis] - g) <= 0.5 * width + 1e-12 * max(1.0, abs(g))
        out.append(float(x[s, vertical].max() + 0.5 * dx - bottom) if s.any() else 0.0)
    return np.asarray(out)


def default_vertical(dimension):
    return 1 if dimension == 2 else 2


def surge_series(run, gauges=(), axis=0, vertical=None, reference=None, width=None, frames=None):
    """Table over time: (columns, rows); columns time, front_x, front_rel, height_x<g> per gauge."""
    frames = frames if frames is not None else [read_vtu(p, t) for t, p in frames_of_run(run)]
    if not frames:
        raise ValueError("run %s has no frames" % run)
    gauges = list(np.atleast_1d(gauges)) if gauges is not None else []
    f0 = frames[0]
    vert = default_vertical(f0.dimension) if vertical is None else vertical
    ref = surge_front(f0, axis) if reference is None else float(reference)
    fl0 = f0.fluid_mask()
    dx = f0.dx if "dx" in f0.fields else 0.0
    bottom = float(f0.points[fl0, vert].min() - 0.5 * dx) if fl0.any() else 0.0
    cols = ["time", "front_x", "front_rel"] + ["height_x%g" % g for g in gauges]
    rows = []
    for fr in frames:
        front = surge_front(fr, axis)
        hs = list(water_height(fr, gauges, axis, vert, width, bottom)) if gauges else []
        rows.append([fr.time, front, front - ref] + hs)
    return cols, rows


def write_table_csv(cols, rows, path):
    with open(path, "w") as f:
        f.write(",".join(cols) + "\n")
        for r in rows:
            f.write(",".join("%.17g" % v for v in r) + "\n")
    return path
