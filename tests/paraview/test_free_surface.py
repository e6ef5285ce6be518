"""FreeSurface (Marrone et al. 2010) on lattice blocks, discs and balls.

Block (2D, 3D): exactly the outer layer of particles is flagged, no interior particle.
Disc / ball: every particle of the lattice rim (a missing axis neighbour) and every particle within dx/2
of the outer radius is flagged; no particle deeper than 1.5 dx (the brief asks < 2 dx).
Fluid resting on boundary particles: the wetted side is not a free surface.
Runs through the written VTU/PVD files (synthetic runs in the solver's format)."""
import os

import numpy as np

import tcommon as T
import synthetic as S
import varsph as V

tmp = T.workdir("fs")
dx = 0.1


def run_frame(name, pts, dim, kernel, hod, kind=None):
    d = os.path.join(tmp, name)
    S.write_run(d, [S.make_frame(pts, dx, dim, kernel=kernel, h_over_dx=hod, kind=kind)], diagnostics=False)
    return next(V.read_run(d))


for dim, n in ((2, (12, 9)), (3, (7, 6, 5))):
    for kern, hod in (("wendland_c2", 1.3), ("cubic_spline", 1.0), ("gaussian", 1.0), ("wendland_c2", 2.0)):
        f = run_frame("block%d_%s_%g" % (dim, kern, hod), S.lattice_block(n, dx), dim, kern, hod)
        flag = V.free_surface(f)
        idx = np.rint(f.points[:, :dim] / dx - 0.5).astype(int)
        outer = np.zeros(len(f), bool)
        for k in range(dim):
            outer |= (idx[:, k] == 0) | (idx[:, k] == n[k] - 1)
        T.check(np.array_equal(flag == 1, outer),
                "block %dD %s h=%gdx: %d flagged, outer layer %d, missed %d, interior flagged %d"
                % (dim, kern, hod, flag.sum(), outer.sum(), (outer & (flag == 0)).sum(),
                   (~outer & (flag == 1)).sum()))

for dim, R in ((2, 1.0), (2, 1.37), (3, 0.8)):
    for kern, hod in (("wendland_c2", 1.3), ("gaussian", 1.0)):
        pts = S.lattice_ball(R, dx, dim)
        f = run_frame("ball%d_%g_%s" % (dim, R, kern), pts, dim, kern, hod)
        flag = V.free_surface(f)
        ij = np.rint(f.points[:, :dim] / dx).astype(int)
        key = {tuple(v) for v in ij}
        rim = np.zeros(len(f), bool)
        for a in range(dim):
            for s in (-1, 1):
                e = np.zeros(dim, int)
                e[a] = s
                rim |= np.array([tuple(v + e) not in key for v in ij])
        depth = np.linalg.norm(f.points, axis=1).max() - np.linalg.norm(f.points, axis=1)
        what = "%s %dD R=%g %s" % ("disc" if dim == 2 else "ball", dim, R, kern)
        T.check(not (rim & (flag == 0)).any(), "%s: all %d lattice-rim particles flagged (missed %d)"
                % (what, rim.sum(), (rim & (flag == 0)).sum()))
        T.check(not ((depth < 0.5 * dx) & (flag == 0)).any(), "%s: all particles within dx/2 of the rim flagged" % what)
        T.check(not ((depth > 1.5 * dx) & (flag == 1)).any(),
                "%s: no particle deeper than 1.5 dx flagged (deepest flagged %.2f dx)" % (what, depth[flag == 1].max() / dx))

# fluid block on a 3-layer floor and against a left wall: bottom and left fluid layers are wetted
fluid = S.lattice_block((10, 8), dx)
floor = S.lattice_block((16, 3), dx, (-3 * dx, -3 * dx, 0))
wall = S.lattice_block((3, 12), dx, (-3 * dx, 0, 0))
pts = np.concatenate([fluid, floor, wall])
kind = np.concatenate([np.zeros(len(fluid)), np.ones(len(floor) + len(wall))])
f = run_frame("tank", pts, 2, "wendland_c2", 1.3, kind=kind)
flag = V.free_surface(f)
idx = np.rint(fluid[:, :2] / dx - 0.5).astype(int)
expect = (idx[:, 0] == 9) | (idx[:, 1] == 7)
T.check(np.array_equal(flag[:len(fluid)] == 1, expect),
        "tank: only the top and right fluid layers flagged (%d vs %d expected)" % (flag[:len(fluid)].sum(), expect.sum()))
T.check(flag[len(fluid):].sum() == 0, "tank: boundary particles never flagged")
flag_nb = V.free_surface(f, include_boundary=False)
T.check(flag_nb[:len(fluid)].sum() == 2 * 10 + 2 * 8 - 4, "tank without boundary neighbours: the full outer layer")

# surface reconstruction: the 0.5 colour contour of the 2D block lies within dx of the block edge
blk = run_frame("blk_surf", S.lattice_block((12, 9), dx), 2, "wendland_c2", 1.3)
mesh = V.surface_mesh(blk)
b = mesh.GetBounds()
T.check(mesh.GetNumberOfPoints() > 20, "surface mesh has %d points" % mesh.GetNumberOfPoints())
T.check(abs(b[0] - 0.0) < dx and abs(b[1] - 1.2) < dx and abs(b[2] - 0.0) < dx and abs(b[3] - 0.9) < dx,
        "surface contour bounds %s within dx of the block [0,1.2]x[0,0.9]" % (tuple(round(v, 3) for v in b[:4]),))
# chunked evaluation and the numpy cell list (no scipy) give the same flags
ball = run_frame("ball_chunks", S.lattice_ball(0.8, dx, 3), 3, "wendland_c2", 1.3)
ref = V.free_surface(ball)
T.check(np.array_equal(V.free_surface(ball, chunk=97), ref), "chunked (97 particles per chunk) = one chunk")
import varsph.neighbors as N  # noqa: E402
saved, N._KDTree = N._KDTree, None
try:
    T.check(np.array_equal(V.free_surface(ball), ref), "numpy cell list = scipy cKDTree")
    T.check(np.array_equal(V.free_surface(blk), V.free_surface(blk)) and V.free_surface(blk).sum() == 38,
            "numpy cell list, 2D block: 38 outer particles")
finally:
    N._KDTree = saved
T.finish(tmp)
