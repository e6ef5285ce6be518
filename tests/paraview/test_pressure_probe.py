"""PressureProbe on a synthetic hydrostatic run: p = rho0 g (H - y) on a lattice (fluid block on a floor
of boundary particles carrying a different pressure, which must be ignored).

At interior points (one support radius from the block's sides and top) the Shepard-normalised SPH
interpolation reads rho0 g (H - y) within 2 % of rho0 g H, for all three kernels, in 2D and 3D."""
import os

import numpy as np

import tcommon as T
import synthetic as S
import varsph as V

tmp = T.workdir("probe")
rho0, g, dx = 1000.0, 9.81, 0.02

for dim in (2, 3):
    for kern, hod in (("wendland_c2", 1.3), ("cubic_spline", 1.2), ("gaussian", 1.0)):
        n = (20, 30) if dim == 2 else (10, 15, 6)
        fluid = S.lattice_block(n, dx)
        H = n[1] * dx
        floor = S.lattice_block((n[0], 3) if dim == 2 else (n[0], 3, n[2]), dx, (0, -3 * dx, 0))
        pts = np.concatenate([fluid, floor])
        kind = np.concatenate([np.zeros(len(fluid)), np.ones(len(floor))])
        p = rho0 * g * (H - pts[:, 1])
        p[kind == 1] = -1e6                       # boundary values must not leak into the probe
        frames = []
        for k, scale in enumerate((1.0, 0.5)):   # second frame: half the pressure
            frames.append(S.make_frame(pts, dx, dim, time=0.05 * k, step=k, kernel=kern, h_over_dx=hod,
                                       kind=kind, pressure=scale * p))
        run = os.path.join(tmp, "hydro%d_%s" % (dim, kern))
        S.write_run(run, frames)
        R = S.SUPPORT[kern] * hod * dx
        W = n[0] * dx
        ys = np.linspace(R + 0.01, H - R - 0.01, 5)
        zc = 0.5 * n[2] * dx if dim == 3 else 0.0
        probes = [(0.5 * W, y, zc) for y in ys] + [(R + 0.003, 0.5 * H, zc)]
        times, vals = V.probe_series(run, probes)
        T.check(list(times) == [0.0, 0.05], "%dD %s: table over the 2 frames" % (dim, kern))
        exact = rho0 * g * (H - np.array([q[1] for q in probes]))
        err0 = np.abs(vals[0] - exact).max() / (rho0 * g * H)
        err1 = np.abs(vals[1] - 0.5 * exact).max() / (rho0 * g * H)
        T.check(err0 < 0.02 and err1 < 0.02,
                "%dD %s: max |p - rho0 g (H-y)| / (rho0 g H) = %.2e, %.2e (< 2 %%)" % (dim, kern, err0, err1))
        # a probe far outside the fluid has no neighbours
        v, den = V.probe_pressure(next(V.read_run(run)), [(10.0, 10.0, 0.0)])
        T.check(np.isnan(v[0]) and den[0] == 0, "%dD %s: probe outside the fluid -> NaN" % (dim, kern))
T.finish(tmp)
