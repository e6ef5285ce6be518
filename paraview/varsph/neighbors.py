"""Fixed-radius neighbour search: scipy's cKDTree when available, else a numpy cell list."""
import numpy as np

try:
    from scipy.spatial import cKDTree as _KDTree
except Exception:  # scipy missing in this ParaView build
    _KDTree = None


def pairs(points, radius):
    """All ordered pairs (i, j), i != j, with |x_i - x_j| <= radius. Returns (i, j) int arrays."""
    points = np.ascontiguousarray(points, dtype=float)
    if len(points) == 0:
        e = np.zeros(0, dtype=np.int64)
        return e, e
    if _KDTree is not None:
        p = _KDTree(points).query_pairs(radius, output_type="ndarray")
        if len(p) == 0:
            e = np.zeros(0, dtype=np.int64)
            return e, e
        return np.concatenate([p[:, 0], p[:, 1]]), np.concatenate([p[:, 1], p[:, 0]])
    return neighbours_of(points, points, radius, exclude_self=True)


def neighbours_of(points, queries, radius, exclude_self=False):
    """Pairs (k, j): query k and point j within ``radius``. Returns (k, j) int arrays."""
    points = np.ascontiguousarray(points, dtype=float)
    queries = np.ascontiguousarray(np.atleast_2d(queries), dtype=float)
    if points.shape[1] < 3 and _KDTree is None:  # the cell list works in 3D
        points = np.pad(points, ((0, 0), (0, 3 - points.shape[1])))
        queries = np.pad(queries, ((0, 0), (0, 3 - queries.shape[1])))
    if len(points) == 0 or len(queries) == 0:
        e = np.zeros(0, dtype=np.int64)
        return e, e
    if _KDTree is not None and not exclude_self:
        lists = _KDTree(points).query_ball_point(queries, radius)
        k = np.repeat(np.arange(len(queries)), [len(l) for l in lists])
        j = np.fromiter((x for l in lists for x in l), dtype=np.int64, count=len(k))
        return k, j
    # cell list: bin the points, visit the 27 neighbouring cells of each query
    origin = np.minimum(points.min(axis=0), queries.min(axis=0))
    pk = np.floor((points - origin) / radius).astype(np.int64) + 1
    qk = np.floor((queries - origin) / radius).astype(np.int64) + 1
    dims = np.maximum(pk.max(axis=0), qk.max(axis=0)) + 2
    lin = pk[:, 0] + dims[0] * (pk[:, 1] + dims[1] * pk[:, 2])
    order = np.argsort(lin, kind="stable")
    sorted_lin = lin[order]
    ks, js = [], []
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dz in (-1, 0, 1):
                c = (qk[:, 0] + dx) + dims[0] * ((qk[:, 1] + dy) + dims[1] * (qk[:, 2] + dz))
                lo = np.searchsorted(sorted_lin, c, side="left")
                hi = np.searchsorted(sorted_lin, c, side="right")
                cnt = hi - lo
                if cnt.sum() == 0:
                    continue
                k = np.repeat(np.arange(len(queries)), cnt)
                start = np.repeat(lo - np.concatenate([[0], np.cumsum(cnt)[:-1]]), cnt)
                j = order[start + np.arange(cnt.sum())]
                ks.append(k)
                js.append(j)
    if not ks:
        e = np.zeros(0, dtype=np.int64)
        return e, e
    k = np.concatenate(ks)
    j = np.concatenate(js)
    d2 = ((queries[k] - points[j]) ** 2).sum(axis=1)
    keep = d2 <= radius * radius
    if exclude_self:
        keep &= k != j
    return k[keep], j[keep]
