"""Deviation between two runs, the paper's eq. (70): D(t) = max_i ||q_i,A(t) - q_i,B(t)||.

Frames are matched by time (|t_A - t_B| <= 1e-9 s), particles by ``id``; the statistics run over the
fluid particles (kind 0 in run A) present in both frames:
  D_max = max_i |d_i|,  D_mean = mean_i |d_i|,  D_rms = sqrt(mean_i |d_i|^2),   d_i = q_i,A - q_i,B.
Same columns as ``varsph compare``: time,D_max,D_mean,D_rms.
"""
import numpy as np

from .io import frames_of_run, read_vtu

DEVIATION_COLUMNS = ("time", "D_max", "D_mean", "D_rms")
TIME_TOLERANCE = 1e-9


def match_by_id(ids_a, ids_b):
    """(ia, ib): indices into A and B of the ids present in both (in A's order)."""
    ids_a = np.asarray(ids_a).reshape(-1).astype(np.int64)
    ids_b = np.asarray(ids_b).reshape(-1).astype(np.int64)
    order = np.argsort(ids_b, kind="stable")
    sb = ids_b[order]
    pos = np.searchsorted(sb, ids_a)
    pos_c = np.minimum(pos, max(len(sb) - 1, 0))
    ok = (pos < len(sb)) & (sb[pos_c] == ids_a) if len(sb) else np.zeros(len(ids_a), dtype=bool)
    ia = np.nonzero(ok)[0]
    return ia, order[pos_c[ok]]


def deviation_frame(frame_a, frame_b):
    """Per-particle deviation on A's particles and the statistics.

    Returns dict(vector (N_A, 3) with NaN where unmatched, magnitude (N_A,), matched (N_A,) bool,
    D_max, D_mean, D_rms, count)."""
    if "id" not in frame_a.arrays or "id" not in frame_b.arrays:
        raise KeyError("both frames need the point array 'id' to match particles")
    ia, ib = match_by_id(frame_a.arrays["id"], frame_b.arrays["id"])
    n = len(frame_a)
    vec = np.full((n, 3), np.nan)
    vec[ia] = frame_a.points[ia] - frame_b.points[ib]
    mag = np.linalg.norm(vec, axis=1)
    matched = np.zeros(n, dtype=bool)
    matched[ia] = True
    sel = matched & frame_a.fluid_mask()
    m = mag[sel]
    if len(m) == 0:
        stats = dict(D_max=np.nan, D_mean=np.nan, D_rms=np.nan)
    else:
        stats = dict(D_max=float(m.max()), D_mean=float(m.mean()), D_rms=float(np.sqrt((m * m).mean())))
    return dict(vector=vec, magnitude=mag, matched=matched, count=int(sel.sum()), **stats)


def match_times(times_a, times_b, tol=TIME_TOLERANCE):
    """[(ka, kb)] frame index pairs whose times agree within ``tol``."""
    tb = np.asarray(times_b, dtype=float)
    out = []
    for ka, t in enumerate(times_a):
        if len(tb) == 0:
            break
        kb = int(np.argmin(np.abs(tb - t)))
        if abs(tb[kb] - t) <= tol:
            out.append((ka, kb))
    return out


def common_pair(pairs, t, tol=TIME_TOLERANCE):
    """The (t_A, t_B) of ``pairs`` (common times, increasing) compared at time ``t``: the latest at or before
    t, the first one before the first. None when there is no common time."""
    if not pairs:
        return None
    best = pairs[0]
    for p in pairs:
        if p[0] <= t + tol:
            best = p
    return best


def common_times(run_a, run_b, tol=TIME_TOLERANCE):
    """[(t_A, t_B)] of the frames both runs have (|t_A - t_B| <= tol), in A's order."""
    ta = [t for t, _ in frames_of_run(run_a)]
    tb = [t for t, _ in frames_of_run(run_b)]
    return [(ta[i], tb[j]) for i, j in match_times(ta, tb, tol)]


def deviation_series(run_a, run_b, tol=TIME_TOLERANCE):
    """Rows (time, D_max, D_mean, D_rms) over the matched times of two runs (directories or .pvd files)."""
    fa = frames_of_run(run_a)
    fb = frames_of_run(run_b)
    pairs = match_times([t for t, _ in fa], [t for t, _ in fb], tol)
    if not pairs:
        raise ValueError("no frame times of %s match those of %s within %g s" % (run_a, run_b, tol))
    rows = []
    for ka, kb in pairs:
        A = read_vtu(fa[ka][1], fa[ka][0])
        B = read_vtu(fb[kb][1], fb[kb][0])
        r = deviation_frame(A, B)
        rows.append((A.time, r["D_max"], r["D_mean"], r["D_rms"]))
    return rows


def write_deviation_csv(rows, path):
    with open(path, "w") as f:
        f.write(",".join(DEVIATION_COLUMNS) + "\n")
        for row in rows:
            f.write(",".join("%.17g" % v for v in row) + "\n")
    return path
