#!/usr/bin/env python3
"""Schaefer-Turek 2D-1 (issue 32 point 3; docs/validation.md section 19): runs
pipelines/open/schaefer_turek_2d1.json at the resolutions asked for (D/dx, with `--set` overrides for variants)
and reports the drag and lift coefficients and the pressure difference across the cylinder per time window,
beside the noise, the largest speed and density error, the mass balance and the cost.

Reference (Schaefer & Turek 1996, "Benchmark computations of laminar flow around a cylinder", in Flow Simulation
with High-Performance Computers II, Notes on Numerical Fluid Mechanics 52, Vieweg, pp. 547-566; test case 2D-1):
channel 2.2 x 0.41 m, cylinder D = 0.1 m centred at (0.2, 0.2), parabolic inflow of peak 0.3 m/s (mean U = 0.2
m/s), nu = 1e-3 m^2/s, Re = U D / nu = 20, rho = 1 kg/m^3. Cd = 2 F_x / (rho U^2 D) in [5.57, 5.59] (5.5795 the
converged value used here), Cl = 2 F_y / (rho U^2 D) in [0.0104, 0.0110] (0.0106), and
delta p = p(0.15, 0.2) - p(0.25, 0.2) in [0.1172, 0.1176] Pa (0.1175) at rho = 1. The scene's fluid has
rho0 = 1000 kg/m^3: Cd and Cl do not change, the pressure difference scales with rho (117.5 Pa here); the harness
reports delta p / (rho0 U^2) times 1 kg/m^3 x U^2, i.e. the benchmark's 0.1175 Pa figure directly.

Inputs, all from the run directory (docs/contract.md, docs/results.md): probes.csv (force probe `cylinder` on
the disc, pressure probes `front` and `rear` on its surface points (0.15, 0.2) and (0.25, 0.2), each row the mean
over its interval), diagnostics.csv (max_speed, density_error_max, the mass balance and the particle counts at
every frame) and run.json (steps, wall time). A window (A, B] takes the probe rows with A < t <= B: mean and
standard deviation over the rows (the noise at the probe interval, 0.05 s in the scene); max_speed and
density_error_max are the largest over the frames in the window. With frames (`output.fields` velocity and
density), `--regions` prints, for the last frame, |rho/rho0 - 1| (largest and RMS) and the largest speed of the
fluid particles by stretch of the channel (inlet, cylinder, wake, middle, outlet): where the noise lives.

  /usr/bin/python3 pipelines/open/schaefer_turek.py [--ddx 10 --ddx 20 ...] [--t-end 6] [--threads 1]
      [-o runs/schaefer_turek] [--set KEY=VALUE ...] [--window A:B ...] [--reuse | --run DIR ...] [--regions]
      [--check-window A:B --check-cd REL --check-cl ABS --check-dp REL --check-mass REL]
Each D/dx runs in DIR/ddxN (--reuse analyses those directories without running; --run DIR analyses any run
directory of the scene, e.g. a `varsph run` with overrides). Writes DIR/summary.csv
(one row per run and window). Checks (exit 1 when one fails, with the figure and the bound): |Cd/5.5795 - 1|,
|Cl - 0.0106|, |delta p / 0.1175 - 1| over the check window of the finest D/dx, and |mass balance| / M(0) of
every run. Exit 2 on bad arguments, 3 when a run fails.
"""
import argparse
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "validation"))
import vcommon  # noqa: E402

SCENE = os.path.join(HERE, "schaefer_turek_2d1.json")
D, U = 0.1, 0.2  # cylinder diameter [m], mean inflow speed [m/s] (2/3 of the 0.3 peak)
CD_REF, CL_REF, DP_REF = 5.5795, 0.0106, 0.1175  # Schaefer & Turek (1996) 2D-1, delta p at rho = 1 kg/m^3
REGIONS = (("inlet", 0.0, 0.1), ("cylinder", 0.1, 0.35), ("wake", 0.35, 1.0), ("middle", 1.0, 1.9),
           ("outlet", 1.9, 2.2))


def fail(msg, code=2):
    print("schaefer_turek: " + msg, file=sys.stderr)
    sys.exit(code)


def parse_window(s, what):
    try:
        a, b = (float(v) for v in s.split(":"))
    except ValueError:
        fail("%s '%s': expected A:B in seconds (e.g. 4:6)" % (what, s))
    if not b > a >= 0:
        fail("%s '%s': expected 0 <= A < B" % (what, s))
    return a, b


def read_frame(path):
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    pd = g.GetPointData()
    out = {"x": vtk_to_numpy(g.GetPoints().GetData())}
    for name in ("velocity", "density", "kind", "open_zone"):
        a = pd.GetArray(name)
        if a is None:
            fail("%s: no point array '%s' (name it in output.fields)" % (path, name))
        out[name] = vtk_to_numpy(a)
    return out


def regions(rundir, rho0):
    frames = sorted(f for f in os.listdir(os.path.join(rundir, "frames")) if f.endswith(".vtu"))
    if not frames:
        fail("%s: no frames to read" % rundir)
    fr = read_frame(os.path.join(rundir, "frames", frames[-1]))
    fluid = (fr["kind"] == 0) & (fr["open_zone"] < 0)
    x = fr["x"][fluid, 0]
    err = np.abs(fr["density"][fluid] / rho0 - 1.0)
    spd = np.linalg.norm(fr["velocity"][fluid], axis=1)
    # particles where none may be: inside the disc (fluid that went through the boundary ball), and the sum of
    # the particle volumes m / rho against the channel's fluid area (> 1: over-packed, the continuity density no
    # longer measures the particles' spacing)
    allf = fr["kind"] == 0
    xa = fr["x"][allf]
    inside = int((np.hypot(xa[:, 0] - 0.2, xa[:, 1] - 0.2) < D / 2).sum())
    out = [("in the disc", inside, float("nan"), float("nan"), float("nan"))]
    for name, a, b in REGIONS:
        m = (x >= a) & (x < b)
        if m.any():
            out.append((name, int(m.sum()), float(err[m].max()), float(np.sqrt(np.mean(err[m] ** 2))),
                        float(spd[m].max())))
    return frames[-1], out


def analyse(rundir, windows):
    """Per window: Cd, Cl, delta p (mean, sd), largest speed and density error; per run: mass balance, cost."""
    try:
        with open(os.path.join(rundir, "run.json")) as f:
            rj = json.load(f)
        scene = rj["scene"]
    except (OSError, ValueError, KeyError) as e:
        fail("%s: no readable run.json with a scene (%s)" % (rundir, e), 3)
    rho0 = float(scene["fluid"]["rho0"])
    pr = vcommon.read_csv(os.path.join(rundir, "probes.csv"))
    dg = vcommon.read_csv(os.path.join(rundir, "diagnostics.csv"))
    for k in ("Fx_cylinder", "Fy_cylinder", "p_front", "p_rear"):
        if k not in pr:
            fail("%s/probes.csv: no column %s (the scene's probes: force `cylinder`, pressure `front`, `rear`)"
                 % (rundir, k), 3)
    t = pr["time"]
    q = 0.5 * rho0 * U * U * D
    cd, cl = pr["Fx_cylinder"] / q, pr["Fy_cylinder"] / q
    dp = (pr["p_front"] - pr["p_rear"]) / rho0  # at rho = 1 kg/m^3, the benchmark's units
    rows = []
    for a, b in windows:
        m = (t > a + 1e-9) & (t <= b + 1e-9)
        md = (dg["time"] > a + 1e-9) & (dg["time"] <= b + 1e-9)
        if m.sum() < 2:
            rows.append({"window": "%g-%g" % (a, b), "rows": int(m.sum())})
            continue
        rows.append({"window": "%g-%g" % (a, b), "rows": int(m.sum()),
                     "cd": float(cd[m].mean()), "cd_sd": float(cd[m].std()),
                     "cl": float(cl[m].mean()), "cl_sd": float(cl[m].std()),
                     "dp": float(dp[m].mean()), "dp_sd": float(dp[m].std()),
                     "max_speed": float(dg["max_speed"][md].max()) if md.any() else float("nan"),
                     "rho_err_max": float(dg["density_error_max"][md].max()) if md.any() else float("nan")})
    m0 = float(dg["fluid_mass"][0])
    run = {"fluid0": int(dg["fluid_particles"][0]), "steps": int(dg["step"][-1]), "t_end": float(dg["time"][-1]),
           "mass_balance": float(np.max(np.abs(dg["mass_balance"]))) / m0,
           "mass_ratio": float(dg["fluid_mass"][-1]) / m0,
           "mass_lo": float(dg["fluid_mass"].min()) / m0, "mass_hi": float(dg["fluid_mass"].max()) / m0,
           "created": int(dg["particles_created"][-1]), "removed_outlet": int(dg["removed_outlet"][-1]),
           "removed_health": int(dg["removed_domain"][-1] + dg["removed_density"][-1] + dg["removed_speed"][-1]),
           "wall": float(rj.get("timings", {}).get("wall_seconds", float("nan"))), "rho0": rho0}
    return rows, run


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ddx", type=float, action="append", help="D/dx (repeatable; default 10)")
    ap.add_argument("--t-end", type=float, default=None, help="end time [s] (default: the scene's)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("-o", "--out", default=os.path.join("runs", "schaefer_turek"))
    ap.add_argument("--set", action="append", default=[], help="KEY=VALUE scene override (repeatable)")
    ap.add_argument("--window", action="append", default=[], help="A:B [s] (repeatable; default 2:3 3:4 ... )")
    ap.add_argument("--reuse", action="store_true", help="analyse existing run directories, run nothing")
    ap.add_argument("--run", action="append", default=[], help="analyse this run directory (repeatable; no runs)")
    ap.add_argument("--regions", action="store_true", help="density error and speed by stretch, last frame")
    ap.add_argument("--timeout", type=float, default=None, help="seconds per run")
    ap.add_argument("--check-window", default=None, help="A:B of the checks (default: the last window)")
    ap.add_argument("--check-cd", type=float, default=None, help="bound on |Cd / 5.5795 - 1|")
    ap.add_argument("--check-cl", type=float, default=None, help="bound on |Cl - 0.0106|")
    ap.add_argument("--check-dp", type=float, default=None, help="bound on |delta p / 0.1175 - 1|")
    ap.add_argument("--check-mass", type=float, default=None, help="bound on |mass balance| / M(0)")
    a = ap.parse_args()
    ddxs = a.ddx or [10.0]
    for n in ddxs:
        if not 2 <= n <= 1000:
            fail("--ddx %g: expected a number of spacings across the cylinder in [2, 1000]" % n)
    for s in a.set:
        if "=" not in s:
            fail("--set '%s': expected KEY=VALUE" % s)
    if a.threads < 1:
        fail("--threads %d: expected a positive count" % a.threads)
    windows = [parse_window(w, "--window") for w in a.window]
    check_w = parse_window(a.check_window, "--check-window") if a.check_window else None
    if not windows:
        end = a.t_end
        if end is None:
            with open(SCENE) as f:
                end = float(json.load(f)["time"]["end"])
        windows = [(float(k), float(k + 1)) for k in range(2, int(math.floor(end + 1e-9)))]
    if check_w and check_w not in windows:
        windows.append(check_w)

    for rundir in a.run:
        if not os.path.isfile(os.path.join(rundir, "run.json")):
            fail("--run %s: expected a run directory of the scene (no run.json there)" % rundir)
    results = []
    for rundir in a.run:
        rows, run = analyse(rundir, windows)
        with open(os.path.join(rundir, "run.json")) as f:
            n = D / float(json.load(f)["scene"]["particles"]["spacing"])
        results.append((round(n, 3), rundir, rows, run, "-"))
    for n in ([] if a.run else ddxs):
        dx = D / n
        rundir = os.path.join(a.out, "ddx%g" % n)
        if not a.reuse:
            sets = ["particles.spacing=%r" % dx] + (["time.end=%r" % a.t_end] if a.t_end else []) + a.set
            extra = [x for s in sets for x in ("--set", s)]
            print("D/dx %g: running %s (load %.2f)" % (n, rundir, vcommon.loadavg()), flush=True)
            r = vcommon.run(SCENE, rundir, threads=a.threads, timeout=a.timeout, extra=extra)
            if r.rc != 0:
                fail("D/dx %g: varsph exited %d: %s" % (n, r.rc, r.message()), 3)
            load = "%.2f-%.2f" % (r.load_before, r.load_after)
        else:
            load = "-"
        rows, run = analyse(rundir, windows)
        results.append((n, rundir, rows, run, load))

    print("\nSchaefer-Turek 2D-1: reference Cd %.4f, Cl %.4f, delta p %.4f Pa (rho = 1)" % (CD_REF, CL_REF, DP_REF))
    print("| D/dx | window [s] | Cd (sd) | Cl (sd) | delta p [Pa, rho 1] (sd) | max speed | max rho err |")
    print("|---|---|---|---|---|---|---|")
    csv_rows = []
    for n, rundir, rows, run, load in results:
        for w in rows:
            if "cd" not in w:
                print("| %g | %s | (%d probe rows) | | | | |" % (n, w["window"], w["rows"]))
                continue
            print("| %g | %s | %.3f (%.3f) | %.4f (%.3f) | %.4f (%.4f) | %.3f | %.3f |" % (
                n, w["window"], w["cd"], w["cd_sd"], w["cl"], w["cl_sd"], w["dp"], w["dp_sd"], w["max_speed"],
                w["rho_err_max"]))
            csv_rows.append(dict(ddx=n, **w, **{k: v for k, v in run.items()}))
    print("\n| D/dx | fluid particles (t=0) | steps | t end | created / removed (outlet, health) | "
          "max |mass balance| / M0 | M/M0 at end (range) | wall [s] | load |")
    print("|---|---|---|---|---|---|---|---|---|")
    for n, rundir, rows, run, load in results:
        print("| %g | %d | %d | %.3g | %d / %d, %d | %.1e | %.4f (%.4f-%.4f) | %.0f | %s |" % (
            n, run["fluid0"], run["steps"], run["t_end"], run["created"], run["removed_outlet"],
            run["removed_health"], run["mass_balance"], run["mass_ratio"], run["mass_lo"], run["mass_hi"],
            run["wall"], load))
    if a.regions:
        for n, rundir, rows, run, load in results:
            frame, reg = regions(rundir, run["rho0"])
            print("\nD/dx %g, %s: | stretch | particles | max |rho/rho0-1| | RMS | max speed |" % (n, frame))
            print("  fluid particles inside the disc: %d" % reg[0][1])
            for name, cnt, emax, erms, smax in reg[1:]:
                print("  | %s | %d | %.4f | %.4f | %.3f |" % (name, cnt, emax, erms, smax))
    os.makedirs(a.out, exist_ok=True)
    if csv_rows:
        vcommon.write_csv(os.path.join(a.out, "summary.csv"), csv_rows)

    bad = []
    n, rundir, rows, run, load = results[-1]
    w = rows[windows.index(check_w)] if check_w else rows[-1]
    if any(c is not None for c in (a.check_cd, a.check_cl, a.check_dp)) and "cd" not in w:
        bad.append("window %s of D/dx %g has no probe rows" % (w["window"], n))
    elif "cd" in w:
        if a.check_cd is not None and abs(w["cd"] / CD_REF - 1) > a.check_cd:
            bad.append("Cd %.4f: %.1f %% from %.4f (bound %.1f %%)" % (
                w["cd"], 100 * (w["cd"] / CD_REF - 1), CD_REF, 100 * a.check_cd))
        if a.check_cl is not None and abs(w["cl"] - CL_REF) > a.check_cl:
            bad.append("Cl %.4f: %.4f from %.4f (bound %.4f)" % (w["cl"], w["cl"] - CL_REF, CL_REF, a.check_cl))
        if a.check_dp is not None and abs(w["dp"] / DP_REF - 1) > a.check_dp:
            bad.append("delta p %.4f Pa: %.1f %% from %.4f (bound %.1f %%)" % (
                w["dp"], 100 * (w["dp"] / DP_REF - 1), DP_REF, 100 * a.check_dp))
    if a.check_mass is not None:
        for n2, _, _, run2, _ in results:
            if run2["mass_balance"] > a.check_mass:
                bad.append("D/dx %g: mass balance %.2e M0 (bound %.1e)" % (n2, run2["mass_balance"], a.check_mass))
    for b in bad:
        print("FAIL: " + b)
    if bad:
        sys.exit(1)
    if any(c is not None for c in (a.check_cd, a.check_cl, a.check_dp, a.check_mass)):
        print("OK: D/dx %g window %s within the bounds" % (n, w["window"]))


if __name__ == "__main__":
    main()
