"""Fixed-radius neighbour search: scipy's cKDTree when available, else a numpy cell list."""
import numpy as np

try:
    from scipy.spatial import cKDTree as _KDTree
except Exception:  # scipy missing in this ParaView build
    _KDTree = None

_EMPTY = np.zeros(0, dtype=np.int64)


class NeighbourSearch:
    """Points within ``radius`` of query points; the tree / cell list is built once for many queries."""

    def __init__(self, points, radius):
        pts = np.ascontiguousarray(points, dtype=float)
        self.dim = pts.shape[1] if pts.ndim == 2 else 3
        self.radius = float(radius)
        self.n = len(pts)
        self.tree = None
        if self.n == 0:
            return
        if _KDTree is not None:
            self.tree = _KDTree(pts)
            return
        if pts.shape[1] < 3:
            pts = np.pad(pts, ((0, 0), (0, 3 - pts.shape[1])))
        self.pts = pts
        self.origin = pts.min(axis=0) - 2 * self.radius
        pk = np.floor((pts - self.origin) / self.radius).astype(np.int64)
        self.dims = pk.max(axis=0) + 3
        lin = self._lin(pk)
        self.order = np.argsort(lin, kind="stable")
        self.sorted_lin = lin[self.order]

    def _lin(self, k):
        return k[:, 0] + self.dims[0] * (k[:, 1] + self.dims[1] * k[:, 2])

    def query(self, queries):
        """(k, j): query index k and point index j with |q_k - x_j| <= radius."""
        q = np.ascontiguousarray(np.atleast_2d(queries), dtype=float)
        if self.n == 0 or len(q) == 0:
            return _EMPTY, _EMPTY
        if self.tree is not None:
            # dual-tree search in C (keeps zero distances); much faster than query_ball_point's lists
            res = _KDTree(q[:, :self.dim]).sparse_distance_matrix(self.tree, self.radius, output_type="ndarray")
            return res["i"].astype(np.int64), res["j"].astype(np.int64)
        if q.shape[1] < 3:
            q = np.pad(q, ((0, 0), (0, 3 - q.shape[1])))
        qk = np.floor((q - self.origin) / self.radius).astype(np.int64)
        inside = np.all((qk >= 1) & (qk <= self.dims - 2), axis=1)
        ks, js = [], []
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    c = self._lin(qk + np.array([dx, dy, dz]))
                    c[~inside] = -1
                    lo = np.searchsorted(self.sorted_lin, c, side="left")
                    hi = np.searchsorted(self.sorted_lin, c, side="right")
                    cnt = hi - lo
                    tot = int(cnt.sum())
                    if tot == 0:
                        continue
                    k = np.repeat(np.arange(len(q)), cnt)
                    start = np.repeat(lo - np.concatenate([[0], np.cumsum(cnt)[:-1]]), cnt)
                    ks.append(k)
                    js.append(self.order[start + np.arange(tot)])
        if not ks:
            return _EMPTY, _EMPTY
        k = np.concatenate(ks)
        j = np.concatenate(js)
        keep = ((q[k] - self.pts[j]) ** 2).sum(axis=1) <= self.radius * self.radius
        return k[keep], j[keep]


def neighbours_of(points, queries, radius, exclude_self=False):
    """Pairs (k, j): query k and point j within ``radius`` (exclude_self drops k == j)."""
    k, j = NeighbourSearch(points, radius).query(queries)
    if exclude_self:
        keep = k != j
        return k[keep], j[keep]
    return k, j


def pairs(points, radius):
    """All ordered pairs (i, j), i != j, with |x_i - x_j| <= radius."""
    return neighbours_of(points, points, radius, exclude_self=True)
