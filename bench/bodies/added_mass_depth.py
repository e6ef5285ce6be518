#!/usr/bin/env python3
"""Why a released body accelerates too slowly (issue 30, docs/bodies.md "What is not right yet"): the disc of
pipelines/bodies/added_mass_disc_2d.json (R = 0.05 m, 1200 kg/m^3, potential flow: a = 0.892 m/s^2) released at
three depths below the free surface, plus the same disc held fixed. The error of the fitted acceleration grows
with the hydrostatic pressure at the body, while the fixed disc's buoyancy stays right: the body carries fluid
with it (see --field). A benchmark, not a test: it prints a table.

  python3 bench/bodies/added_mass_depth.py [--varsph build/release/bin/varsph] [--threads 1] [--t-end 0.1]
      [--out runs/added_mass_depth] [--field] [--set KEY=VALUE ...]
      (--field: near-body fluid velocity at t_end, needs pvpython's vtk; --set: applied to every case, e.g.
       --set kernel.h_over_dx=1.7, the wider kernel that weakens the lattice's hold, docs/validation.md section 18)
"""
import argparse, csv, math, os, subprocess, sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENE = os.path.join(ROOT, "pipelines", "bodies", "added_mass_disc_2d.json")
R, RHO, RHO_B, G = 0.05, 1000.0, 1200.0, 9.81
A_POT = (RHO_B - RHO) * G / (RHO_B + RHO)  # C_a = 1 (circle in unbounded potential flow)

CASES = [  # name, depth of the centre below the surface [m], --set overrides
    ("depth 0.15 m", 0.15, ["bodies.2.center=[0.5, 0.65]"]),
    ("depth 0.40 m", 0.40, []),
    ("depth 1.20 m", 1.20, ["domain.max=[1.1, 1.8]", "bodies.0.max=[1.0, 1.6]", "bodies.1.max=[1.0, 1.7]"]),
    ("fixed, 0.40 m", 0.40, ["bodies.2.lock_translation=[true, true]", "bodies.2.lock_rotation=[true]"]),
]


def fit(run):
    rows = list(csv.DictReader(open(os.path.join(run, "bodies.csv"))))
    t = [float(r["time"]) for r in rows]
    y = [float(r["y"]) for r in rows]
    f = [float(r["fluid_fy"]) for r in rows]
    s1 = sum((y[k] - y[0]) * 0.5 * t[k] ** 2 for k in range(len(t)))
    s2 = sum((0.5 * t[k] ** 2) ** 2 for k in range(len(t)))
    return s1 / s2, sum(f[1:]) / max(1, len(f) - 1), float(rows[-1]["vy"]), t[-1]


def near_field(run, t_end):
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    from vtkmodules.util.numpy_support import vtk_to_numpy as v2n
    import numpy as np
    frames = sorted(os.listdir(os.path.join(run, "frames")))
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(os.path.join(run, "frames", frames[-1]))
    r.Update()
    g = r.GetOutput()
    x = v2n(g.GetPoints().GetData())[:, :2]
    v = v2n(g.GetPointData().GetArray("velocity"))[:, :2]
    kind = v2n(g.GetPointData().GetArray("kind"))
    rows = list(csv.DictReader(open(os.path.join(run, "bodies.csv"))))
    c = np.array([float(rows[-1]["x"]), float(rows[-1]["y"])])
    U = float(rows[-1]["vy"])
    d = x[kind == 0] - c
    rr = np.hypot(d[:, 0], d[:, 1])
    ring = (rr >= R) & (rr < R + 0.01)
    # the annulus mean of the potential flow round a moving circle is zero: any mean is fluid carried along
    return float(v[kind == 0][ring, 1].mean()) / U if U else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--varsph", default=os.path.join(ROOT, "build", "release", "bin", "varsph"))
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--t-end", type=float, default=0.1)
    ap.add_argument("--out", default=os.path.join(ROOT, "runs", "added_mass_depth"))
    ap.add_argument("--field", action="store_true")
    ap.add_argument("--set", action="append", default=[], help="scene override for every case (repeatable)")
    a = ap.parse_args()
    print("case            p at centre [kPa]  a fitted [m/s^2]  error vs 0.892   mean fluid Fy [N/m]  v(t)/t"
          + ("   ring v / U" if a.field else ""))
    for name, depth, sets in CASES:
        run = os.path.join(a.out, name.replace(" ", "_").replace(",", "").replace(".", "p"))
        cmd = [a.varsph, "run", SCENE, "-o", run, "--quiet", "--overwrite", "--threads", str(a.threads),
               "--set", "time.end=%g" % a.t_end, "--set", "output.every=%g" % a.t_end]
        for s in a.set + sets:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True)
        acc, fy, v, t = fit(run)
        err = "" if "fixed" in name else "%+.1f %%" % (100 * (-acc / A_POT - 1))
        line = "%-15s %17.1f %17.4f  %14s  %19.2f  %6.3f" % (name, RHO * G * depth / 1e3, -acc, err, fy, -v / t)
        if a.field and "fixed" not in name:
            line += "   %.2f" % near_field(run, a.t_end)
        print(line, flush=True)
    print("buoyancy rho g pi R^2 = %.2f N/m; with C_a = 1 the moving disc's fluid force is %.2f N/m"
          % (RHO * G * math.pi * R * R, RHO * G * math.pi * R * R + RHO * math.pi * R * R * A_POT))


if __name__ == "__main__":
    sys.exit(main())
