#!/usr/bin/env python3
"""Archimedes in 3D (issue 30 point 6; docs/validation.md section 18): a floating box (0.2 x 0.2 x 0.1 m,
pipelines/bodies/floating_box_3d.json) or vertical cylinder (R = 0.1 m, 0.1 m long, floating_cylinder_3d.json) at
a relative density s settles with its centre of mass at level - s h + h / 2 (draft s h), the level being that of
the fluid's actual volume: level = (V_fluid + a s h) / A (tank plan area A = 0.36 m^2, body water-plane area a).
The issue's goal: within 1 % of the body height h.

The centre heaves about its equilibrium with a period of 0.65-0.85 s and little damping, so a plain mean over a part
of a cycle moves with the phase. The equilibrium (the figure checked, as in the test BodiesValidation/Archimedes3D)
is the height where the fluid's vertical force equals the weight: the least-squares line of fluid_fz against the
centre's height over the second half of the run. Also printed: the mean over whole cycles (from the first to the
last upward crossing of the mean, twice; unreliable with fewer than two cycles in the half) and the plain mean.
V_fluid = sum m / rho over the fluid in the frames of the second half.

  python3 pipelines/bodies/archimedes_3d.py [--shape box|cylinder] [--density 300 500 800] [--t-end 2.0]
      [--threads 1] [-o runs/archimedes_3d] [--reuse] [--check 0.01]   (exit 1 when a case misses --check)
One run is ~10-15 minutes on one core of the shared 2-core machine.
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
from wedge_wagner import read_vtu  # noqa: E402  (raw appended VTU reader)

TANK_AREA, HEIGHT = 0.36, 0.1
SHAPES = {"box": ("floating_box_3d", 0.04), "cylinder": ("floating_cylinder_3d", math.pi * 0.01)}


def whole_cycle_mean(t, y):
    """Time-weighted mean of y over the span between its first and last upward crossing of its own mean."""
    def mean(a, b):
        num = den = 0.0
        for k in range(a + 1, b + 1):
            dt = t[k] - t[k - 1]
            num += 0.5 * (y[k] + y[k - 1]) * dt
            den += dt
        return num / den
    m = mean(0, len(t) - 1)
    for _ in range(2):
        up = [k for k in range(1, len(t)) if y[k - 1] < m <= y[k]]
        if len(up) < 2:
            break
        m = mean(up[0], up[-1])
    return m, (len(up) - 1 if len(up) >= 2 else 0)


def evaluate(run, rel, area, t_end):
    rows = [r for r in csv.DictReader(open(os.path.join(run, "bodies.csv")))]
    t = [float(r["time"]) for r in rows if float(r["time"]) >= 0.5 * t_end]
    z = [float(r["z"]) for r in rows if float(r["time"]) >= 0.5 * t_end]
    mean, cycles = whole_cycle_mean(t, z)
    plain = sum(z) / len(z)
    vols = []
    fdir = os.path.join(run, "frames")
    for f in sorted(os.listdir(fdir)):
        if not f.endswith(".vtu"):
            continue
        tf, a = read_vtu(os.path.join(fdir, f), {"mass", "density", "kind"})
        if tf >= 0.5 * t_end - 1e-9:
            vols.append(sum(m / r for m, r, k in zip(a["mass"], a["density"], a["kind"]) if k == 0))
    v = sum(vols) / len(vols)
    d = rel * HEIGHT
    level = (v + area * d) / TANK_AREA
    expected = level - d + 0.5 * HEIGHT
    ang = max(abs(float(r["angle"])) for r in rows if float(r["time"]) >= 0.5 * t_end)
    # a second estimate: the height where the fluid's vertical force equals the weight (least-squares line of
    # fluid_fz against z over the same half; the heave is slow, so the force is nearly the hydrostatic one)
    fz = [float(r["fluid_fz"]) for r in rows if float(r["time"]) >= 0.5 * t_end]
    weight = rel * 1000.0 * area * HEIGHT * 9.81
    mz, mf = sum(z) / len(z), sum(fz) / len(fz)
    k = sum((a - mz) * (b - mf) for a, b in zip(z, fz)) / sum((a - mz) ** 2 for a in z)
    z_eq = mz + (weight - mf) / k
    amp = 0.5 * (max(z) - min(z))
    return mean, plain, expected, level, cycles, amp, ang, z_eq


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--shape", choices=sorted(SHAPES), default="box")
    ap.add_argument("--density", type=float, nargs="+", default=[300, 500, 800])
    ap.add_argument("--t-end", type=float, default=2.0)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("-o", "--out", default=os.path.join(ROOT, "runs", "archimedes_3d"))
    ap.add_argument("--reuse", action="store_true", help="evaluate the runs in --out (named SCENE_DENSITY)")
    ap.add_argument("--check", type=float, help="bound on |error| / h")
    a = ap.parse_args()
    if any(not 0 < d < 1000 for d in a.density):
        print("archimedes_3d.py: --density: expected a body density in (0, 1000) kg/m^3 (it must float)",
              file=sys.stderr)
        raise SystemExit(2)
    scene, area = SHAPES[a.shape]
    failed = False
    for dens in a.density:
        run = os.path.join(a.out, "%s_%g" % (scene, dens))
        if not a.reuse:
            cmd = [os.environ.get("VARSPH_BIN", os.path.join(ROOT, "build", "release", "bin", "varsph")), "run",
                   os.path.join(HERE, scene + ".json"), "-o", run, "--overwrite", "--quiet", "--threads",
                   str(a.threads), "--set", "bodies.2.density=%g" % dens, "--set", "time.end=%g" % a.t_end,
                   "--set", "output.every=0.25", "--set", "output.probes_every=0.005"]
            w0, l0 = time.monotonic(), os.getloadavg()[0]
            p = subprocess.run(cmd, capture_output=True, text=True)
            if p.returncode != 0:
                print(p.stdout + p.stderr, file=sys.stderr)
                raise SystemExit(3)
            print("%s %g kg/m^3: %.0f s wall, %d thread(s), load %.1f -> %.1f"
                  % (scene, dens, time.monotonic() - w0, a.threads, l0, os.getloadavg()[0]))
        mean, plain, expected, level, cycles, amp, ang, z_eq = evaluate(run, dens / 1000.0, area, a.t_end)
        err = (z_eq - expected) / HEIGHT
        print("%s relative density %.2f: centre where the fluid force equals the weight %.5f m, expected %.5f m "
              "(level %.5f m): error %+.2f %% of h; mean over %d whole cycles %+.2f %%, plain mean %+.2f %%; heave "
              "half-range %.1f mm, largest angle %.4f rad"
              % (scene, dens / 1000, z_eq, expected, level, 100 * err, cycles, 100 * (mean - expected) / HEIGHT,
                 100 * (plain - expected) / HEIGHT, 1000 * amp, ang))
        if a.check is not None and not abs(err) <= a.check:
            print("  FAIL: |error| %.2f %% of h > %.2f %%" % (100 * abs(err), 100 * a.check))
            failed = True
    raise SystemExit(1 if failed else 0)


if __name__ == "__main__":
    main()
