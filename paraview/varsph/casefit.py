"""Which post-processing fits a run (issue 35, point 2): comparisons with measurements only where the scene
is the measured case, and picture names by output time.

The bundled dam-break front measurements (Martin & Moyce 1952, Koshizuka & Oka 1996) are for a column of
height H = 2 L (n^2 = 2) released against a wall on a dry floor. dam_break_column() says whether a run's first
frame is that case; postprocess.py draws the dimensionless front against them only then, or when the user asks
(--front-reference). A torus under falling water has no surge front to compare.
"""
import numpy as np

N2_MEASURED = 2.0        # H / L of the bundled measurements
N2_TOLERANCE = 0.15      # relative: 1.7 <= n^2 <= 2.3
FILL = 0.9               # the column holds at least this share of the particles a full H x L (x W) block would


def dam_break_column(frame0, axis=0, vertical=1, scene=None):
    """(True, why) when ``frame0`` is a dam-break column of n^2 = H / L near 2 standing on a floor against a
    wall behind it (the case of the bundled measurements), else (False, why not)."""
    kind = frame0.arrays.get("kind")
    if kind is None or "dx" not in frame0.fields:
        return False, "the frames have no kind array or dx"
    kind = np.asarray(kind).reshape(-1)
    if scene and scene.get("bodies"):
        fluids = [b for b in scene.get("bodies", []) if isinstance(b, dict) and b.get("kind") == "fluid"]
        if len(fluids) != 1:
            return False, "the scene has %d fluid bodies, a dam break one" % len(fluids)
        if any(abs(float(v)) > 0 for v in fluids[0].get("velocity", []) or []):
            return False, "the fluid starts moving (velocity %s)" % fluids[0].get("velocity")
    x = frame0.points[kind == 0]
    wall = frame0.points[kind != 0]
    if not len(x) or not len(wall):
        return False, "no fluid or no walls"
    dx = float(frame0.dx)
    lo, hi = x.min(axis=0) - 0.5 * dx, x.max(axis=0) + 0.5 * dx
    L, H = hi[axis] - lo[axis], hi[vertical] - lo[vertical]
    n2 = H / L
    if abs(n2 / N2_MEASURED - 1.0) > N2_TOLERANCE:
        return False, "the column's H/L = %.3g, the measurements' 2" % n2
    dims = [k for k in range(frame0.dimension)]
    full = np.prod([(hi[k] - lo[k]) / dx for k in dims])
    if len(x) < FILL * full:
        return False, "the fluid is not one block (%d particles in a %.0f-particle box)" % (len(x), full)
    across = [k for k in dims if k not in (axis, vertical)]
    beside = np.all([(wall[:, k] >= lo[k] - dx) & (wall[:, k] <= hi[k] + dx) for k in across], axis=0) \
        if across else np.ones(len(wall), dtype=bool)
    behind = beside & (wall[:, axis] < lo[axis]) & (wall[:, axis] >= lo[axis] - 2 * dx) & \
        (wall[:, vertical] > lo[vertical]) & (wall[:, vertical] < hi[vertical])
    under = beside & (wall[:, vertical] < lo[vertical]) & (wall[:, vertical] >= lo[vertical] - 2 * dx) & \
        (wall[:, axis] > lo[axis]) & (wall[:, axis] < hi[axis])
    if not behind.any() or not under.any():
        return False, "no %s within 2 dx of the column" % ("wall behind" if not behind.any() else "floor")
    return True, "a dam-break column of H/L = %.3g against a wall" % n2


def time_label(t, every=None):
    """A frame's time for a file name: the output time k * ``every`` it was written for (an adaptive step
    writes the frame up to a step after it: 0.395943 -> 0.4), else the time to 6 digits."""
    if every and every > 0:
        k = round(t / every)
        if abs(t - k * every) <= 0.25 * every:
            return "%.12g" % (k * every)
    return "%.6g" % t
