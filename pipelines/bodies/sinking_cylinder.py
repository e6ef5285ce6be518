#!/usr/bin/env python3
"""The sinking cylinder of Moyo & Greenhow (2000) and Fekken (2004) (issue 30 point 6; docs/validation.md
section 18): runs pipelines/bodies/sinking_cylinder_2d.json (a 2D circular cylinder, R = 1 m, relative density
1.2, released from rest half-submerged) at the spacings asked for, and compares the vertical displacement and
velocity of its centre against time with the two published reference solutions:

  * Fekken (2004), PhD thesis, University of Groningen (a Navier-Stokes free-surface solver):
    tests/data/fekken2004_sinking_cylinder_{displacement,velocity}.csv;
  * Moyo & Greenhow (2000), Appl. Ocean Res. 22 (a nonlinear potential-flow solution):
    tests/data/moyo_greenhow2000_sinking_cylinder_{displacement,velocity}.csv (its displacement series starts at
    T = 0.5 with 0: it is compared as the displacement since T = 0.5).
  Provenance in each file's header (the DualSPHysics example package's validation files). Units: T = t sqrt(g/R),
  displacement in m = in R (R = 1 m), V = v / sqrt(g R); downward negative.

The two references agree while the body enters the water (displacement within 0.06 R and speed within 16 % up to
T = 2) and part after it: at T = 8 the potential flow has sunk 4.8 R at V = -0.80, Fekken's viscous solution
3.4 R at V = -0.50 (the potential flow has no wake and no drag). Figures per reference: RMS and largest
|difference| of the displacement in R and of V, over the reference's points inside the run, for T <= 2 (both
references) and over the whole series.

  python3 pipelines/bodies/sinking_cylinder.py [--dx 0.1 --dx 0.05 ...] [--threads 1] [-o runs/sinking_cylinder]
      [--set KEY=VALUE ...] [--reuse] [--check-fekken X] [--check-early X]
  --check-fekken X: exit 1 when the RMS displacement difference from Fekken over the whole series exceeds X (in R);
  --check-early X:  exit 1 when the RMS displacement difference from either reference over T <= 2 exceeds X (in R).
Writes per run DIR/sinking.csv (T, displacement, V) and DIR/reference_{fekken,moyo}.csv (each series on the run's
clock as y - y(0) of the centre [m], for pvpython paraview/plot_bodies.py DIR --reference ...).
Exit 2 on bad arguments, 3 when a run fails.
"""
import argparse
import csv
import math
import os
import re
import sys

from harness_common import interp, read_pairs, run_scene

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENE = os.path.join(HERE, "sinking_cylinder_2d.json")
DATA = os.path.join(ROOT, "tests", "data")
G, R = 9.81, 1.0
TS = math.sqrt(G / R)  # T = t * TS
VS = math.sqrt(G * R)  # V = v / VS
T_EARLY = 2.0
REFERENCES = (("Fekken 2004", "fekken2004_sinking_cylinder_%s.csv", 0.0),
              ("Moyo & Greenhow 2000", "moyo_greenhow2000_sinking_cylinder_%s.csv", 0.5))  # displacement from T0


def run_case(dx, threads, outdir, sets, timeout):
    return run_scene(SCENE, outdir, threads, ["particles.spacing=%r" % dx] + list(sets), timeout)


def evaluate(outdir):
    rows = list(csv.DictReader(open(os.path.join(outdir, "bodies.csv"))))  # the scene's only rigid body
    t = [float(r["time"]) for r in rows]
    T = [x * TS for x in t]
    disp = [float(r["y"]) - float(rows[0]["y"]) for r in rows]
    vel = [float(r["vy"]) / VS for r in rows]
    with open(os.path.join(outdir, "sinking.csv"), "w") as f:
        f.write("# sinking_cylinder.py: T = t sqrt(g/R), displacement of the centre y - y(0) [m = R], V = vy / "
                "sqrt(g R); R = 1 m\nT,displacement,V\n")
        for a, b, c in zip(T, disp, vel):
            f.write("%.6f,%.6f,%.6f\n" % (a, b, c))
    figures = {}
    for name, pattern, t0 in REFERENCES:
        d_ref = read_pairs(os.path.join(DATA, pattern % "displacement"))
        v_ref = read_pairs(os.path.join(DATA, pattern % "velocity"))
        base = interp(T, disp, t0) if t0 > 0 else 0.0  # Moyo & Greenhow's displacement counts from T = 0.5
        tag = re.sub(r"\W", "", name.split()[0].lower())
        with open(os.path.join(outdir, "reference_%s.csv" % tag), "w") as f:
            f.write("# %s (tests/data/%s) on this run's clock: time = T / sqrt(g/R) [s], y - y(0) of the centre [m]"
                    "\ntime,y\n" % (name, pattern % "displacement"))
            for Tr, dr in d_ref:
                f.write("%.6f,%.6f\n" % (Tr / TS, dr + base))
        out = {}
        for what, ref, ours, shift in (("displacement", d_ref, disp, base), ("V", v_ref, vel, 0.0)):
            early, whole = [], []
            for Tr, yr in ref:
                ys = interp(T, ours, Tr)
                if ys is None or Tr <= 0:
                    continue
                d = (ys - shift) - yr
                whole.append(d)
                if Tr <= T_EARLY:
                    early.append(d)
            rms = lambda v: math.sqrt(sum(x * x for x in v) / len(v)) if v else float("nan")  # noqa: E731
            out[what] = (rms(early), max((abs(x) for x in early), default=float("nan")), rms(whole),
                         max((abs(x) for x in whole), default=float("nan")), len(whole))
        at = {Tq: (interp(T, disp, Tq), interp([a for a, _ in d_ref], [b + base for _, b in d_ref], Tq),
                   interp(T, vel, Tq), interp([a for a, _ in v_ref], [b for _, b in v_ref], Tq))
              for Tq in (1.0, 2.0, 4.0, 6.0, 7.5)}
        figures[name] = (out, at)
    return T, figures


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, action="append", help="particle spacing [m] (repeatable; 0.1 = R/10)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("-o", "--out", default=os.path.join(ROOT, "runs", "sinking_cylinder"))
    ap.add_argument("--set", action="append", default=[], help="scene override (repeatable)")
    ap.add_argument("--timeout", type=float, default=None)
    ap.add_argument("--reuse", action="store_true", help="evaluate existing runs in --out without running")
    ap.add_argument("--check-fekken", type=float, help="bound on the RMS displacement difference (in R) from "
                                                        "Fekken over the whole series")
    ap.add_argument("--check-early", type=float, help="bound on the RMS displacement difference (in R) from either "
                                                       "reference over T <= 2")
    a = ap.parse_args()
    dxs = a.dx or [0.1]
    if any(not 0 < d <= 0.2 or abs(1.0 / d - round(1.0 / d)) > 1e-6 for d in dxs):
        print("sinking_cylinder.py: --dx: expected a spacing in (0, 0.2] m that divides 1 m (0.1 = R/10, 0.05 = R/20: "
              "the cylinder's axis, the surface and the bed on lattice lines)", file=sys.stderr)
        raise SystemExit(2)
    failed = False
    print("Sinking cylinder: R %.1f m, relative density 1.2, released half-submerged" % R)
    for dx in dxs:
        tag = "dx%g" % dx + ("_" + "_".join(re.sub(r"\W", "", s) for s in a.set) if a.set else "")
        outdir = os.path.join(a.out, tag)
        if not a.reuse:
            wall, l0, l1 = run_case(dx, a.threads, outdir, a.set, a.timeout)
            print("dx %g (R/dx %.0f): run %.0f s wall on %d thread(s), load %.1f -> %.1f"
                  % (dx, R / dx, wall, a.threads, l0, l1))
        else:
            print("dx %g (R/dx %.0f): %s" % (dx, R / dx, outdir))
        T, figures = evaluate(outdir)
        print("  run to T = %.3f" % T[-1])
        for name, (out, at) in figures.items():
            for what, (re_, me, rw, mw, n) in out.items():
                unit = "R" if what == "displacement" else "(V)"
                print("  %s, %s: T <= %g RMS %.3f %s, largest %.3f; whole series RMS %.3f, largest %.3f (%d points)"
                      % (name, what, T_EARLY, re_, unit, me, rw, mw, n))
            print("    " + "; ".join("T %g: y %.3f / %.3f, V %.3f / %.3f" % ((Tq,) + tuple(
                float("nan") if x is None else x for x in v)) for Tq, v in at.items()) + " (varsph / reference)")
        fek = figures["Fekken 2004"][0]["displacement"]
        early_worst = max(figures[n][0]["displacement"][0] for n in figures)
        if a.check_fekken is not None and not fek[2] <= a.check_fekken:
            print("  FAIL: RMS displacement difference from Fekken %.3f R (bound %.3f R)" % (fek[2], a.check_fekken))
            failed = True
        if a.check_early is not None and not early_worst <= a.check_early:
            print("  FAIL: RMS displacement difference over T <= %g %.3f R (bound %.3f R)"
                  % (T_EARLY, early_worst, a.check_early))
            failed = True
    raise SystemExit(1 if failed else 0)


if __name__ == "__main__":
    main()
