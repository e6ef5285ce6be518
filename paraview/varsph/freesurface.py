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
from .neighbors import pairs

LAMBDA_SURFACE = 0.2
LAMBDA_INTERIOR = 0.75


def free_surface(frame, kernel=None, include_boundary=True, scan=True,
                 lambda_surface=LAMBDA_SURFACE, lambda_interior=LAMBDA_INTERIOR, return_details=False):
    """0/1 int array over all particles of ``frame`` (boundary particles are always 0).

    With ``return_details`` also returns dict(lambda_=..., normal=...)."""
    kernel = kernel or kernel_from_fields(frame.fields)
    d = frame.dimension
    h = kernel.h
    n = len(frame)
    fluid = frame.fluid_mask()
    use = np.ones(n, dtype=bool) if include_boundary else fluid.copy()
    idx = np.nonzero(use)[0]
    x = frame.points[idx, :d]
    V = frame.volume()[idx]
    i, j = pairs(x, kernel.support_radius)
    xij = x[i] - x[j]
    r = np.sqrt((xij * xij).sum(axis=1))
    good = r > 0
    i, j, xij, r = i[good], j[good], xij[good], r[good]
    gradW = (kernel.dWdr(r) / r)[:, None] * xij          # grad_i W_ij
    m = len(idx)
    # L_i = sum_j V_j (x_j - x_i) (x) grad_i W_ij
    L = np.zeros((m, d, d))
    contrib = V[j][:, None, None] * (-xij)[:, :, None] * gradW[:, None, :]
    np.add.at(L, i, contrib)
    Ls = 0.5 * (L + np.transpose(L, (0, 2, 1)))
    lam = np.linalg.eigvalsh(Ls)[:, 0]
    g = np.zeros((m, d))
    np.add.at(g, i, V[j][:, None] * gradW)
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
        T = x[ci] + h * normal[ci]
        xjT = x[cj] - T
        xji = x[cj] - x[ci]
        rji = np.linalg.norm(xji, axis=1)
        far = rji >= math.sqrt(2.0) * h
        cov = far & (np.linalg.norm(xjT, axis=1) < h)
        nrm = normal[ci]
        if d == 2:
            tau = np.stack([-nrm[:, 1], nrm[:, 0]], axis=1)
            near = (~far) & (np.abs((nrm * xjT).sum(1)) + np.abs((tau * xjT).sum(1)) < h)
        else:
            cosang = (nrm * xji).sum(1) / np.maximum(rji, 1e-300)
            near = (~far) & (cosang > math.cos(math.pi / 4.0))
        cov |= near
        covered = np.zeros(m, dtype=bool)
        covered[ci[cov]] = True
        flag |= cand & ~covered
    else:
        flag |= cand
    out = np.zeros(n, dtype=np.int32)
    out[idx] = flag.astype(np.int32)
    out[~fluid] = 0
    if not return_details:
        return out
    lam_all = np.full(n, np.nan)
    lam_all[idx] = lam
    nrm_all = np.zeros((n, 3))
    nrm_all[idx, :d] = normal
    return out, {"lambda_": lam_all, "normal": nrm_all}


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
