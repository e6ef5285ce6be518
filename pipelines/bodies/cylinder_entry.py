#!/usr/bin/env python3
"""Water entry of a free-falling 2D circular cylinder (issue 30 point 6; docs/validation.md section 18):
runs pipelines/bodies/cylinder_entry_2d.json (D = 0.11 m, entering at 2.955 m/s) at the body densities and
spacings asked for, and compares the penetration of the centre against time with the published series:

  * Greenhow & Lin (1983), experiment, as digitised from Sun et al. (2018)
    (tests/data/greenhow_lin1983_cylinder_entry_rho{500,1000}.csv);
  * the BEM (fully nonlinear potential flow) and SPH (D/dx 200) curves of the same figure of Sun et al. (2018)
    (tests/data/sun2018_cylinder_entry_{bem,sph}_rho{500,1000}.csv).
  Provenance in each file's header. Units: T = t sqrt(g/D), penetration (y_entry - y)/D.

t = 0 is the contact: the instant the disc's lowest point (centre - R) reaches the still-water level (the top of
the fluid box, docs/scene.md: the surface is half a spacing above the first particle row), interpolated in
bodies.csv; the penetration is the centre's drop from its height at that instant. The disc starts three
spacings above the water with the speed that becomes 2.955 m/s at contact in free fall; the speed it really has
at contact is printed (the water pushes on it from a kernel support away).

Figures per case: RMS and largest |difference| in units of R against each series, over the series' points inside
the run (T > 0). A published point above the ballistic bound Fr T + T^2/2 (Fr = V / sqrt(g D), no deceleration at
all) cannot be a decelerated body's and is reported and left out of the figures (some of the digitised
neutrally buoyant experiment's points are). Beside them, the early deceleration against momentum theory
((m + m_a(h)) V = m V0, gravity and buoyancy left out, h the penetration of the lowest point): von Karman's
added mass m_a = rho pi R h and Wagner's 2 rho pi R h (c^2 = 2 R h and 4 R h with m_a = rho pi c^2 / 2; e.g.
Faltinsen 1990, "Sea loads on ships and offshore structures", ch. 9) bracket the exact early slamming.

  python3 pipelines/bodies/cylinder_entry.py [--rho 500 --rho 1000] [--dx 0.0055 ...] [--threads 1]
      [-o runs/cylinder_entry] [--set KEY=VALUE ...] [--reuse]
      [--check-bem X] [--check-exp X]   (exit 1 when the RMS difference in R against the BEM curve, or the
                                         largest against the admissible experimental points, exceeds X)
Writes per case DIR/penetration.csv (T, penetration/D, speed/V from the contact) and DIR/reference_{experiment,
bem,sph}.csv (each published series on the run's clock, as the centre's displacement from its start). Plot:
pvpython paraview/plot_bodies.py DIR --reference DIR/reference_experiment.csv:label=Greenhow_Lin_1983
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
SCENE = os.path.join(HERE, "cylinder_entry_2d.json")
DATA = os.path.join(ROOT, "tests", "data")
RHO_F, G, D, V = 1000.0, 9.81, 0.11, 2.955
R = D / 2
X_C, SURFACE = 0.605, 0.605  # the disc's axis and the still-water level of the scene (on lattice lines)
TS = math.sqrt(G / D)  # T = t * TS
FR = V / math.sqrt(G * D)
SERIES = (("experiment", "greenhow_lin1983_cylinder_entry_rho%d.csv"), ("BEM", "sun2018_cylinder_entry_bem_rho%d.csv"),
          ("SPH D/dx 200", "sun2018_cylinder_entry_sph_rho%d.csv"))
T_END = {500: 1.55, 1000: 2.05}  # beyond the last published point (T)


def run_case(rho, dx, threads, outdir, sets, timeout):
    gap = 3 * dx  # out of the kernel's reach (2 h = 2.83 dx at h/dx 1.414; 3.4 dx at 1.7) of the water
    v_start = math.sqrt(V * V - 2 * G * gap)
    t_end = T_END[rho] / TS + gap / V + 0.002
    return run_scene(SCENE, outdir, threads,
                     ["particles.spacing=%r" % dx, "time.end=%.6f" % t_end, "bodies.2.density=%r" % float(rho),
                      "bodies.2.center=[%r, %r]" % (X_C, SURFACE + R + gap),
                      "bodies.2.velocity=[0.0, %r]" % -v_start] + list(sets), timeout)


def trajectory(outdir):
    """(t, y, vy) of the disc from bodies.csv, and the contact: time, centre height, speed."""
    rows = list(csv.DictReader(open(os.path.join(outdir, "bodies.csv"))))  # the scene's only rigid body
    tr = [(float(r["time"]), float(r["y"]), float(r["vy"]), float(r["fluid_fy"])) for r in rows]
    ye = SURFACE + R
    for (t1, y1, v1, _), (t2, y2, v2, _) in zip(tr, tr[1:]):
        if y1 >= ye > y2:
            w = (y1 - ye) / (y1 - y2)
            return tr, t1 + w * (t2 - t1), ye, -(v1 + w * (v2 - v1))
    raise ValueError("%s: the disc never reached the water" % outdir)


def momentum_theory(rho_s, h, factor):
    """V / V0 at a penetration h of the lowest point: (m + m_a) V = m V0, m_a = factor rho pi R h."""
    m = rho_s * math.pi * R * R
    return m / (m + factor * RHO_F * math.pi * R * h)


def evaluate(outdir, rho):
    tr, t0, ye, v_entry = trajectory(outdir)
    T = [(t - t0) * TS for t, _, _, _ in tr if t >= t0]
    P = [(ye - y) / D for t, y, _, _ in tr if t >= t0]
    VV = [-v for t, _, v, _ in tr if t >= t0]
    T, P, VV = [0.0] + T, [0.0] + P, [v_entry] + VV  # the contact itself
    # slamming coefficient C_s = F / (rho R V^2) of the fluid's vertical force (sampled at the probe rate): von
    # Karman's is pi, Wagner's 2 pi at the first instant
    cs = max(((f / (RHO_F * R * v * v), (ye - y) / R) for t, y, v, f in tr if t >= t0 and y > ye - R), default=(0, 0))
    with open(os.path.join(outdir, "penetration.csv"), "w") as f:
        f.write("# cylinder_entry.py: T = (t - t_contact) sqrt(g/D), penetration = (y_contact - y)/D, D = %g m; "
                "t_contact %.6f s, speed at contact %.4f m/s\nT,penetration_over_D,speed_over_V\n" % (D, t0, v_entry))
        for a, b, c in zip(T, P, VV):
            f.write("%.6f,%.6f,%.6f\n" % (a, b, c / V))
    figures = {}
    y_start = tr[0][1]
    for name, pattern in SERIES:
        ref = read_pairs(os.path.join(DATA, pattern % rho))
        # the series on the run's own clock and as the centre's displacement from its start, for
        # paraview/plot_bodies.py RUN --reference RUN/reference_NAME.csv
        with open(os.path.join(outdir, "reference_%s.csv" % re.sub(r"\W", "", name.split()[0].lower())), "w") as f:
            f.write("# %s (tests/data/%s) on this run's clock: time = T / sqrt(g/D) + t_contact [s], y - y(0) of the "
                    "centre [m]\ntime,y\n" % (name, pattern % rho))
            for Tr, pr in ref:
                f.write("%.6f,%.6f\n" % (Tr / TS + t0, (ye - y_start) - pr * D))
        diffs, rows, refused = [], [], []
        for Tr, pr in ref:
            if Tr <= 0:
                continue
            if pr > FR * Tr + Tr * Tr / 2 + 0.02:
                refused.append((Tr, pr, FR * Tr + Tr * Tr / 2))
                continue
            ps = interp(T, P, Tr)
            if ps is None:
                continue
            diffs.append(2 * (ps - pr))  # D -> R
            rows.append((Tr, pr, ps))
        rms = math.sqrt(sum(d * d for d in diffs) / len(diffs)) if diffs else float("nan")
        mx = max(abs(d) for d in diffs) if diffs else float("nan")
        figures[name] = (rms, mx, rows, refused)
    early = []
    for hr in (0.1, 0.25, 0.5, 1.0):  # penetration of the lowest point, in R
        v = interp(P, VV, hr * R / D)
        early.append((hr, v / V if v is not None else float("nan"), momentum_theory(rho, hr * R, 1.0),
                      momentum_theory(rho, hr * R, 2.0)))
    return t0, v_entry, T, P, figures, early, cs


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rho", type=int, action="append", help="body density, 500 or 1000 kg/m^3 (repeatable)")
    ap.add_argument("--dx", type=float, action="append", help="particle spacing [m] (repeatable; 0.0055 = D/20)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("-o", "--out", default=os.path.join(ROOT, "runs", "cylinder_entry"))
    ap.add_argument("--set", action="append", default=[], help="scene override (repeatable)")
    ap.add_argument("--timeout", type=float, default=None)
    ap.add_argument("--reuse", action="store_true", help="evaluate existing runs in --out without running")
    ap.add_argument("--check-bem", type=float, help="bound on the RMS difference (in R) from the BEM curve")
    ap.add_argument("--check-exp", type=float, help="bound on the largest difference (in R) from the admissible "
                                                    "experimental points")
    a = ap.parse_args()
    rhos = a.rho or [500, 1000]
    dxs = a.dx or [0.0055]
    if any(r not in T_END for r in rhos):
        print("cylinder_entry.py: --rho: expected 500 or 1000 (the published cases)", file=sys.stderr)
        raise SystemExit(2)
    if any(not 0 < d <= 0.011 or abs(SURFACE / d - round(SURFACE / d)) > 1e-6 for d in dxs):
        print("cylinder_entry.py: --dx: expected a spacing in (0, 0.011] m that divides 0.605 m (0.0055 = D/20, "
              "0.00275 = D/40: the disc's axis and the water's surface on lattice lines)", file=sys.stderr)
        raise SystemExit(2)
    failed = False
    print("Cylinder water entry: D %.3f m, V %.3f m/s (Fr %.3f), water 1000 kg/m^3" % (D, V, FR))
    for rho in rhos:
        for dx in dxs:
            tag = "rho%d_dx%g" % (rho, dx) + ("_" + "_".join(re.sub(r"\W", "", s) for s in a.set) if a.set else "")
            outdir = os.path.join(a.out, tag)
            if not a.reuse:
                wall, l0, l1 = run_case(rho, dx, a.threads, outdir, a.set, a.timeout)
                print("rho %d, dx %g (D/dx %.0f): run %.0f s wall on %d thread(s), load %.1f -> %.1f"
                      % (rho, dx, D / dx, wall, a.threads, l0, l1))
            else:
                print("rho %d, dx %g (D/dx %.0f): %s" % (rho, dx, D / dx, outdir))
            t0, v_entry, T, P, figures, early, cs = evaluate(outdir, rho)
            print("  contact at t = %.5f s, speed %.4f m/s; run to T = %.3f (penetration %.3f D)"
                  % (t0, v_entry, T[-1], P[-1]))
            for name, (rms, mx, rows, refused) in figures.items():
                print("  against %s: RMS %.3f R, largest %.3f R over %d points" % (name, rms, mx, len(rows)))
                if name == "experiment":
                    for Tr, pr, ps in rows:
                        print("    T %.3f: published %.3f D, varsph %.3f D (%+.3f R)" % (Tr, pr, ps, 2 * (ps - pr)))
                for Tr, pr, b in refused:
                    print("    left out: T %.3f, %.3f D is above the ballistic bound %.3f D" % (Tr, pr, b))
            for hr, v, vk, wg in early:
                print("  speed at a penetration of %.2f R: %.3f V, %.3f of the speed at contact (momentum theory: von "
                      "Karman %.3f, Wagner %.3f)" % (hr, v, v * V / v_entry, vk, wg))
            print("  largest slamming coefficient F / (rho R V^2) before the half-immersion: %.2f at a penetration of "
                  "%.2f R (von Karman pi, Wagner 2 pi at the first instant)" % cs)
            rms_bem = figures["BEM"][0]
            mx_exp = figures["experiment"][1]
            if a.check_bem is not None and not rms_bem <= a.check_bem:
                print("  FAIL: RMS difference from the BEM curve %.3f R (bound %.3f R)" % (rms_bem, a.check_bem))
                failed = True
            if a.check_exp is not None and not mx_exp <= a.check_exp:
                print("  FAIL: largest difference from the experiment %.3f R (bound %.3f R)" % (mx_exp, a.check_exp))
                failed = True
    raise SystemExit(1 if failed else 0)


if __name__ == "__main__":
    main()
