"""SPH interpolation of a point field at probe points (Shepard-normalised, fluid particles only).

  p(x) = sum_j V_j p_j W(|x - x_j|, h) / sum_j V_j W(|x - x_j|, h),   V_j = m_j / rho_j,
with the kernel, h and support radius the frame's field data carry (Shepard 1968 normalisation as
used for SPH pressure probes, e.g. Monaghan 2005, Rep. Prog. Phys. 68:1703, sec. 2; Colagrossi & Landrini 2003).
A probe with no fluid particle within the support gets NaN.
"""
import numpy as np

from .io import frames_of_run, read_vtu
from .kernels import kernel_from_fields
from .neighbors import neighbours_of


def probe_pressure(frame, probes, kernel=None, array="pressure", fluid_only=True):
    """Values of point array ``array`` at ``probes`` ((P, 2|3) coordinates). Returns (values, shepard_sum)."""
    kernel = kernel or kernel_from_fields(frame.fields)
    d = frame.dimension
    probes = np.atleast_2d(np.asarray(probes, dtype=float))
    q = np.zeros((len(probes), 3))
    q[:, :probes.shape[1]] = probes
    if array not in frame.arrays:
        raise KeyError("frame has no point array '%s' (has %s)" % (array, ", ".join(sorted(frame.arrays))))
    f = np.asarray(frame.arrays[array], dtype=float)
    if f.ndim > 1:
        f = f[:, 0] if f.shape[1] == 1 else np.linalg.norm(f, axis=1)
    mask = frame.fluid_mask() if fluid_only else np.ones(len(frame), dtype=bool)
    idx = np.nonzero(mask)[0]
    x = frame.points[idx, :d]
    V = frame.volume()[idx]
    k, j = neighbours_of(x, q[:, :d], kernel.support_radius)
    w = V[j] * kernel.W(np.linalg.norm(q[k, :d] - x[j], axis=1))
    num = np.bincount(k, weights=w * f[idx][j], minlength=len(q))
    den = np.bincount(k, weights=w, minlength=len(q))
    with np.errstate(invalid="ignore", divide="ignore"):
        val = np.where(den > 0, num / np.where(den > 0, den, 1.0), np.nan)
    return val, den


def probe_series(run, probes, array="pressure", frames=None):
    """Time series at ``probes`` over all frames of ``run`` (directory or .pvd).

    Returns (times (T,), values (T, P))."""
    frames = frames if frames is not None else [read_vtu(p, t) for t, p in frames_of_run(run)]
    times, vals = [], []
    for fr in frames:
        v, _ = probe_pressure(fr, probes, array=array)
        times.append(fr.time)
        vals.append(v)
    return np.asarray(times), np.asarray(vals).reshape(len(times), len(np.atleast_2d(probes)))


def smooth_field(frame, array="pressure", kernel=None):
    """Per-particle Shepard SPH average of ``array`` over the fluid neighbours (the probe interpolation
    above evaluated at each fluid particle): sum_j V_j f_j W_ij / sum_j V_j W_ij. Boundary particles keep
    their own value. Damps the particle-scale pressure noise of weakly compressible SPH for pictures."""
    f = np.asarray(frame.arrays[array], dtype=float).reshape(len(frame), -1)[:, 0].copy()
    fl = np.nonzero(frame.fluid_mask())[0]
    if len(fl):
        vals, _ = probe_pressure(frame, frame.points[fl, :frame.dimension], kernel=kernel, array=array)
        f[fl] = np.where(np.isfinite(vals), vals, f[fl])
    return f
