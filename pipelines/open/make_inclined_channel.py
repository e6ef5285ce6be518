#!/usr/bin/env python3
"""Writes pipelines/open/inclined_channel.json: the plane Poiseuille channel of channel_poiseuille.json
(H = 1 m, L = 1.5 m, nu = 1 m^2/s, dx = 0.05 m, inlet parabolic peak 0.15 m/s, outlet p = 0) rotated by an angle
(default 30 degrees) with oblique plane inlet and outlet zones (issue 32, docs/open_boundaries.md "Oblique zones").
The fluid and the 4 layers of wall on each side are `points` bodies on the rotated lattice, so the buffer
lattices of the zones (planes parallel to their interfaces) continue the fluid's lattice.

    python3 pipelines/open/make_inclined_channel.py [--angle DEG] [--dx DX] [-o FILE]

The test tests/sim/test_open_oblique.cpp builds the same scene in memory.
"""
import argparse
import json
import math
import os

H, L, U = 1.0, 1.5, 0.1


def scene(angle_deg, dx, t_end):
    c, s = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))

    def at(along, across):
        return [round(along * c - across * s, 12), round(along * s + across * c, 12)]

    ni, nj, layers, zone = round(L / dx), round(H / dx), 4, round(0.2 / dx)
    fluid, wall = [], []
    for i in range(-zone, ni + zone):
        for j in range(-layers, nj + layers):
            in_fluid = 0 <= i < ni and 0 <= j < nj
            in_wall = j < 0 or j >= nj
            if in_fluid or in_wall:
                (fluid if in_fluid else wall).append(at((i + 0.5) * dx, (j + 0.5) * dx))
    pts = fluid + wall
    lo = [min(p[a] for p in pts) - 0.2 for a in range(2)]
    hi = [max(p[a] for p in pts) + 0.2 for a in range(2)]
    return {
        "name": "inclined_channel",
        "setup": "paper",
        "description": ("Plane Poiseuille flow through a channel inclined at %g degrees with oblique plane inlet and "
                        "outlet zones (issue 32): channel_poiseuille.json rotated (H = 1 m, L = 1.5 m, nu = 1 m^2/s, "
                        "no-slip dummy walls, inlet parabolic peak 0.15 m/s, outlet p = 0, gravity off). Steady state "
                        "across the channel: u = 6 U y (H - y) / H^2 with U = 0.1 m/s, dp/ds = -1200 Pa/m. Written by "
                        "pipelines/open/make_inclined_channel.py; docs/open_boundaries.md 'Oblique zones'." % angle_deg),
        "dimension": 2,
        "domain": {"min": [round(v, 6) for v in lo], "max": [round(v, 6) for v in hi]},
        "particles": {"spacing": dx},
        "kernel": {"type": "gaussian", "h_over_dx": 1.2},
        "fluid": {"rho0": 1000.0, "c0": 20.0},
        "bodies": [
            {"kind": "fluid", "shape": "points", "points": fluid},
            {"kind": "boundary", "shape": "points", "points": wall},
        ],
        "open_boundaries": [
            {"name": "inlet", "kind": "inlet", "center": at(0, H / 2), "direction": at(1, 0), "depth": zone * dx,
             "width": H, "velocity": {"profile": "parabolic", "peak": 1.5 * U}},
            {"name": "outlet", "kind": "outlet", "center": at(L, H / 2), "direction": at(-1, 0), "depth": zone * dx,
             "width": H, "pressure": 0.0},
        ],
        "physics": {"density": "continuity", "laminar_viscosity": {"nu": 1.0}},
        "boundary": {"model": "dummy_adami", "slip": "no_slip"},
        "integrator": {"type": "verlet", "cfl": 0.2},
        "time": {"end": t_end},
        "output": {"every": 0.1, "fields": ["velocity", "density", "pressure", "mass", "id", "kind", "open_zone"]},
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--angle", type=float, default=30.0, help="inclination [deg] (default 30)")
    ap.add_argument("--dx", type=float, default=0.05, help="particle spacing [m] (default 0.05; H / dx integer)")
    ap.add_argument("--end", type=float, default=2.0, help="time.end [s] (default 2)")
    ap.add_argument("-o", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "inclined_channel.json"))
    a = ap.parse_args()
    with open(a.o, "w") as f:
        json.dump(scene(a.angle, a.dx, a.end), f, separators=(",", ":"))
        f.write("\n")
    print(a.o)


if __name__ == "__main__":
    main()
