#!/usr/bin/env python3
"""Writes pipelines/open/pipe_3d.json: Hagen-Poiseuille flow in a circular pipe along x (radius R = 0.5 m, length
L = 1.5 m, nu = 1 m^2/s, rho0 = 1000, c0 = 20 m/s, mean speed U = 0.1 m/s, Re = 2 U R / nu = 0.1) with a **disc
inlet** (`radius`, profile `parabolic`: u = 2 U (1 - r^2 / R^2)) and a disc outlet at p = 0 (issue 32,
docs/open_boundaries.md "Polygon and disc interfaces"). The fluid and 4 layers of wall are `points` bodies on the
lattice of the disc's bounding square (the disc zone's own lattice: nodes at -R + (j + 1/2) dx about the axis),
fluid where r < R, wall where R <= r < R + 4 dx, over the zones' length too.

    python3 pipelines/open/make_pipe_3d.py [--per-radius N] [--end T] [-o FILE]

Steady state: u(r) = 2 U (1 - r^2 / R^2), dp/dx = -8 mu U / R^2 = -3200 Pa/m. The test
tests/sim/test_open_polygon.cpp (validation binary test_open_pipe_validation) builds the same scene in memory;
measured figures: docs/validation.md section 19.
"""
import argparse
import json
import math
import os

R, L, U, NU = 0.5, 1.5, 0.1, 1.0
LAYERS = 4  # Wendland C2 at h/dx 1.6: support 3.2 dx


def scene(per_r, t_end):
    dx = R / per_r
    nx, n = round(L / dx), 2 * per_r
    fluid, wall = [], []
    for i in range(-LAYERS, nx + LAYERS):
        for a in range(-LAYERS, n + LAYERS):
            for b in range(-LAYERS, n + LAYERS):
                x, y, z = (i + 0.5) * dx, -R + (a + 0.5) * dx, -R + (b + 0.5) * dx
                r = math.hypot(y, z)
                p = [round(x, 12), round(y, 12), round(z, 12)]
                if r < R:
                    if 0 <= i < nx:
                        fluid.append(p)
                elif r < R + LAYERS * dx:
                    wall.append(p)
    m, e = 0.2, R + LAYERS * dx + 0.2
    return {
        "name": "pipe_3d",
        "setup": "paper",
        "description": ("Hagen-Poiseuille flow in a circular pipe (R = 0.5 m, L = 1.5 m, nu = 1 m^2/s, U = 0.1 m/s, "
                        "R/dx %d) with a disc inlet carrying u = 2 U (1 - r^2/R^2) and a disc outlet at p = 0 (issue 32). "
                        "Steady: dp/dx = -8 mu U / R^2 = -3200 Pa/m. Written by pipelines/open/make_pipe_3d.py; "
                        "docs/open_boundaries.md 'Polygon and disc interfaces', docs/validation.md section 19." % per_r),
        "dimension": 3,
        "domain": {"min": [-LAYERS * dx - m, -e, -e], "max": [L + LAYERS * dx + m, e, e]},
        "particles": {"spacing": dx},
        "kernel": {"type": "wendland_c2", "h_over_dx": 1.6},
        "fluid": {"rho0": 1000.0, "c0": 20.0},
        "bodies": [
            {"kind": "fluid", "shape": "points", "points": fluid},
            {"kind": "boundary", "shape": "points", "points": wall},
        ],
        "open_boundaries": [
            {"name": "inlet", "kind": "inlet", "center": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0],
             "tangent": [0.0, 1.0, 0.0], "depth": LAYERS * dx, "radius": R,
             "velocity": {"profile": "parabolic", "peak": 2 * U}},
            {"name": "outlet", "kind": "outlet", "center": [L, 0.0, 0.0], "direction": [-1.0, 0.0, 0.0],
             "tangent": [0.0, 1.0, 0.0], "depth": LAYERS * dx, "radius": R, "pressure": 0.0},
        ],
        "physics": {"density": "continuity", "laminar_viscosity": {"nu": NU}},
        "boundary": {"model": "dummy_adami", "slip": "no_slip"},
        "integrator": {"type": "verlet", "cfl": 0.2},
        "time": {"end": t_end},
        "output": {"every": 0.1, "fields": ["velocity", "density", "pressure", "mass", "id", "kind", "open_zone"]},
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-radius", type=int, default=6, help="R / dx (default 6: about 6 200 particles)")
    ap.add_argument("--end", type=float, default=1.0, help="time.end [s] (default 1)")
    ap.add_argument("-o", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "pipe_3d.json"))
    a = ap.parse_args()
    with open(a.o, "w") as f:
        json.dump(scene(a.per_radius, a.end), f, separators=(",", ":"))
        f.write("\n")
    print(a.o)


if __name__ == "__main__":
    main()
