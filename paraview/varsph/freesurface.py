"""Free-surface detection and surface reconstruction.

Detection: Marrone, Colagrossi, Le Touze, Graziani (2010), "Fast free-surface detection and level-set
function definition in SPH solvers", J. Comput. Phys. 229(10):3652-3663.

1. Renormalisation matrix  L_i = sum_j V_j (x_j - x_i) (x) grad_i W_ij  (identity for a full support).
   lambda_i = min eigenvalue of L_i.  lambda_i <= 0.2: free surface; lambda_i > 0.75: interior;
   in between the particle is only a candidate and goes to step 2.
2. Normal n_i = nu_i/|nu_i|, nu_i = -L_i^-1 sum_j V_j grad_i W_ij, and the "umbrella" scan region with
   apex T = x_i + h n_i: the candidate is on the free surface when NO neighbour j lies in
      |x_ji| >= sqrt(2) h  and |x_j - T| < h                              (both dimensions)
      |x_ji| <  sqrt(2) h  and |n.(x_j - T)| + |tau.(x_j - T)| < h          (2D, tau the tangent)
      |x_ji| <  sqrt(2) h  and angle(n, x_ji) < pi/4                       (3D cone)
Neighbours are all particles (fluid and boundary) so that fluid touching a wall is not a free surface;
only fluid particles are flagged.

Reconstruction: the SPH colour (Shepard) field c(x) = sum_j V_j W(x - x_j) of the fluid particles
sampled on a regular image grid and contoured at c = 0.5 (a line set in 2D, a surface in 3D).
"""
import math

import numpy as np

from .kernels import kernel_from_fields
from .neighbors import NeighbourSearch

LAMBDA_SURFACE = 0.2
LAMBDA_INTERIOR = 0.75
TIE = 1e-9


def free_surface(frame, kernel=None, include_boundary=True, scan=True,
                 lambda_surface=LAMBDA_SURFACE, lambda_interior=LAMBDA_INTERIOR, return_details=False,
                 chunk=100_000):
    """0/1 int array over all particles of ``frame`` (boundary particles are always 0).

    Works on ``chunk`` fluid particles at a time (bounded memory on large 3D runs).
    With ``return_details`` also returns dict(lambda_=..., normal=...)."""
    kernel = kernel or kernel_from_fields(frame.fields)
    d = frame.dimension
    n = len(frame)
    fluid = frame.fluid_mask()
    use = np.ones(n, dtype=bool) if include_boundary else fluid.copy()
    idx = np.nonzero(use)[0]                   # particles taking part (neighbours)
    x = frame.points[idx, :d]
    V = frame.volume()[idx]
    search = NeighbourSearch(x, kernel.support_radius)
    targets = np.nonzero(fluid[idx])[0]        # rows of x that are fluid: the only ones flagged
    out = np.zeros(n, dtype=np.int32)
    lam_all = np.full(n, np.nan)
    nrm_all = np.zeros((n, 3))
    for rows in np.array_split(targets, max(1, int(np.ceil(len(targets) / float(chunk))))):
        if len(rows) == 0:
            continue
        flag, lam, normal = _detect(x, V, rows, search, kernel, d, scan, lambda_surface, lambda_interior)
        out[idx[rows]] = flag
        lam_all[idx[rows]] = lam
        nrm_all[idx[rows], :d] = normal
    if not return_details:
        return out
    return out, {"lambda_": lam_all, "normal": nrm_all}


def _detect(x, V, rows, search, kernel, d, scan, lambda_surface, lambda_interior):
    """Marrone's two steps for the particles x[rows] (neighbours: all of x)."""
    h = kernel.h
    m = len(rows)
    i, j = search.query(x[rows])               # i: local row, j: index into x
    xij = x[rows][i] - x[j]
    r = np.sqrt((xij * xij).sum(axis=1))
    good = r > 0                                # drops the particle itself
    i, j, xij, r = i[good], j[good], xij[good], r[good]
    gradW = (kernel.dWdr(r) / r)[:, None] * xij          # grad_i W_ij
    # L_i = sum_j V_j (x_j - x_i) (x) grad_i W_ij
    L = np.zeros((m, d, d))
    for a in range(d):
        for b in range(d):
            L[:, a, b] = np.bincount(i, weights=V[j] * (-xij[:, a]) * gradW[:, b], minlength=m)
    Ls = 0.5 * (L + np.transpose(L, (0, 2, 1)))
    lam = np.linalg.eigvalsh(Ls)[:, 0]
    g = np.stack([np.bincount(i, weights=V[j] * gradW[:, a], minlength=m) for a in range(d)], axis=1)
    # nu = -L^-1 g (fall back to -g where L is singular)
    nu = -g.copy()
    det = np.linalg.det(L)
    ok = np.abs(det) > 1e-12 * np.maximum(1.0, np.abs(L).max(axis=(1, 2))) ** d
    if ok.any():
        nu[ok] = -np.linalg.solve(L[ok], g[ok][:, :, None])[:, :, 0]
    nn = np.linalg.norm(nu, axis=1)
    normal = np.zeros((m, d))
    nz = nn > 0
    normal[nz] = nu[nz] / nn[nz][:, None]

    flag = lam <= lambda_surface
    cand = (lam > lambda_surface) & (lam <= lambda_interior)
    if scan:
        # scan test for candidates: covered (= not surface) if any neighbour lies in the umbrella region
        c = cand[i]
        ci, cj = i[c], j[c]
        xi = x[rows][ci]
        T = xi + h * normal[ci]
        xjT = x[cj] - T
        xji = x[cj] - xi
        rji = np.linalg.norm(xji, axis=1)
        # ties (exact on lattices) count as outside the region, whatever the round-off: tolerance TIE
        far = rji >= math.sqrt(2.0) * h
        cov = far & (np.linalg.norm(xjT, axis=1) < h * (1.0 - TIE))
        nrm = normal[ci]
        if d == 2:
            tau = np.stack([-nrm[:, 1], nrm[:, 0]], axis=1)
            near = (~far) & (np.abs((nrm * xjT).sum(1)) + np.abs((tau * xjT).sum(1)) < h * (1.0 - TIE))
        else:
            cosang = (nrm * xji).sum(1) / np.maximum(rji, 1e-300)
            near = (~far) & (cosang > math.cos(math.pi / 4.0) + TIE)
        cov |= near
        covered = np.zeros(m, dtype=bool)
        covered[ci[cov]] = True
        flag |= cand & ~covered
    else:
        flag |= cand
    return flag.astype(np.int32), lam, normal


def colour_field_image(frame, kernel=None, spacing=None, max_cells=4_000_000):
    """Colour field of the fluid on a grid: returns (values array shaped (nz, ny, nx), origin, spacing, dims).

    Grid spacing defaults to dx/2 (coarsened to keep at most ``max_cells`` samples); the grid covers the
    fluid plus one support radius."""
    kernel = kernel or kernel_from_fields(frame.fields)
    d = frame.dimension
    fl = frame.fluid_mask()
    x = frame.points[fl]
    V = frame.volume()[fl]
    if spacing is None:
        spacing = 0.5 * frame.dx
    R = kernel.support_radius
    if len(x) == 0:
        raise ValueError("no fluid particles in the frame")
    lo = x.min(axis=0) - R
    hi = x.max(axis=0) + R
    if d == 2:
        lo[2] = hi[2] = x[0, 2]
    while True:
        dims = np.ones(3, dtype=np.int64)
        dims[:d] = np.floor((hi[:d] - lo[:d]) / spacing).astype(np.int64) + 1
        if dims.prod() <= max_cells:
            break
        spacing *= 1.25
    img = np.zeros(dims[::-1])                       # (nz, ny, nx)
    st = int(math.ceil(R / spacing))
    base = np.floor((x - lo) / spacing).astype(np.int64)
    offs = range(-st, st + 2)
    zoffs = offs if d == 3 else [0]
    flat = img.reshape(-1)
    for oz in zoffs:
        for oy in offs:
            for ox in offs:
                g = base + np.array([ox, oy, oz])
                inside = np.all((g >= 0) & (g < dims), axis=1)
                if not inside.any():
                    continue
                gi = g[inside]
                gp = lo + gi * spacing
                rr = np.linalg.norm((gp - x[inside])[:, :d], axis=1)
                w = V[inside] * kernel.W(rr)
                lin = gi[:, 0] + dims[0] * (gi[:, 1] + dims[1] * gi[:, 2])
                np.add.at(flat, lin, w)
    return img, lo, spacing, dims


def surface_mesh(frame, kernel=None, spacing=None, iso=0.5):
    """vtkPolyData: iso-line (2D) / iso-surface (3D) of the colour field at ``iso`` (needs vtk)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkFiltersCore import vtkContourFilter
    img, lo, sp, dims = colour_field_image(frame, kernel, spacing)
    im = vtkImageData()
    im.SetDimensions(int(dims[0]), int(dims[1]), int(dims[2]))
    im.SetOrigin(*[float(v) for v in lo])
    im.SetSpacing(sp, sp, sp)
    arr = numpy_to_vtk(np.ascontiguousarray(img.reshape(-1)), deep=1)
    arr.SetName("colour")
    im.GetPointData().SetScalars(arr)
    cf = vtkContourFilter()
    cf.SetInputData(im)
    cf.SetValue(0, iso)
    cf.Update()
    out = cf.GetOutput()
    return out
