#!/usr/bin/env python3
"""Largest stable time step per integrator (bisection) on the dam break and the hydrostatic tank, and the
hard cases (10 m/s impact, dam break above its stable dt): each must run or stop with exit 3 and a message,
and no frame may hold a NaN.

Stable = `varsph run` exits 0 under the strict definition used since the first report (health rules set to
stop: exit 3 on NaN, a fluid particle leaving the domain, or |rho/rho0 - 1| > 0.5; the speed and energy
rules off), so a run that would only survive by removing particles counts as unstable. dt is fixed,
dt = f h / c0; f is bracketed by doubling from f = 0.2 and bisected to a relative width of --tol. Every
unstable run's frames are checked for NaN. The hard cases run with the default rules (what a user gets:
particles out of bounds removed and counted, exit 3 for a blow-up); hard_cases.csv reports the removals.

  /usr/bin/python3 pipelines/validation/stability.py [--cases dam_break,hydrostatic] [--integrators verlet,...]
      [--hard] [--tol 0.05] [-o runs/stability]
Writes OUT/stability.csv (the largest stable f and dt per case and integrator) and OUT/hard_cases.csv.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vcommon as vc  # noqa: E402
import case_dam_break  # noqa: E402
import case_hydrostatic  # noqa: E402

CASES = {
    # scene, sets (coarse, short), simulated time
    "dam_break": (case_dam_break.SCENE, {"particles.spacing": 0.005, "time.end": 0.4, "output.every": 0.05}),
    "hydrostatic": (case_hydrostatic.SCENE, {"particles.spacing": 0.01, "time.end": 0.5, "output.every": 0.1}),
}
INTEGRATORS = ["verlet", "variational:0.25", "variational:0.5", "variational:0.75", "symplectic_euler", "rk4",
               "predictor_corrector"]


def trial(scene, sets, f, h_c, outdir, log):
    s = {k: v for k, v in sets.items() if not k.startswith("integrator.")}
    # stable = none of NaN, a particle leaving the domain, |rho/rho0 - 1| > 0.5 (the report's definition)
    s.update({"health.on_violation": "stop", "health.max_density_error": 0.5, "health.max_mach": 1e6,
              "health.max_energy_growth": 0})
    s["integrator"] = {"type": sets["integrator.type"], "dt": f * h_c}
    if "integrator.alpha" in sets:
        s["integrator"]["alpha"] = sets["integrator.alpha"]
    r = vc.run(scene, outdir, s, threads=2)
    nf, bad = vc.nan_frames(outdir)
    log.append({"f": f, "dt": f * h_c, "rc": r.rc, "wall": r.solver_wall, "frames": nf, "nan_frames": bad,
                "message": r.message() if r.rc else ""})
    print(f"   f={f:.4g} dt={f * h_c:.3e} rc={r.rc} frames={nf} nan_frames={bad} {log[-1]['message'][:140]}",
          flush=True)
    if r.rc not in (0, 3):
        raise SystemExit(f"unexpected exit {r.rc}: {r.stderr}")
    return r.rc == 0


def largest_stable(case, integ, tol, outroot, start=0.2):
    scene, sets = CASES[case]
    itype, _, alpha = integ.partition(":")
    sets = dict(sets, **{"integrator.type": itype})
    if alpha:
        sets["integrator.alpha"] = float(alpha)
    if vc.info(scene, sets)[0] != 0:
        return None
    h_c = vc.h_over_c0(scene, sets)
    out = os.path.join(outroot, f"{case}_{integ.replace(':', '_')}")
    log = []
    lo, hi = 0.0, start
    while trial(scene, sets, hi, h_c, out, log):
        lo, hi = hi, hi * 2
        if hi > 50:
            break
    if lo == 0.0:
        lo_try = 0.05
        while lo_try > 0.004 and not trial(scene, sets, lo_try, h_c, out, log):
            lo_try /= 2
        lo = lo_try if log[-1]["rc"] == 0 else 0.0
    while lo > 0 and (hi - lo) / lo > tol:
        mid = 0.5 * (lo + hi)
        if trial(scene, sets, mid, h_c, out, log):
            lo = mid
        else:
            hi = mid
    nan = sum(max(e["nan_frames"], 0) for e in log)
    msgs = [e["message"] for e in log if e["rc"] == 3]
    return {"case": case, "integrator": integ, "f_stable": lo, "dt_stable": lo * h_c, "f_unstable": hi,
            "dt_unstable": hi * h_c, "h_over_c0": h_c, "runs": len(log), "nan_frames_total": nan,
            "example_exit3_message": msgs[-1] if msgs else ""}


def removed(r):
    """'domain/density/speed' counts of particles the health rules removed (run.json), '' if none."""
    h = r.runjson.get("health", {})
    c = h.get("removed", {})
    return "/".join(str(c.get(k, 0)) for k in ("domain", "density", "speed")) if h.get("removed_total") else ""


def hard_cases(outroot):
    rows = []
    scene = os.path.join(vc.HERE, "impact_10ms.json")
    for label, sets in (("impact 10 m/s, c0 = 100 m/s, CFL 0.2", {}),
                        ("impact 10 m/s, c0 too low (c0 = 10 sqrt(2gH) = 14 m/s), CFL 0.2",
                         {"fluid.reference_speed": 0.0}),
                        ("impact 10 m/s, c0 = 100 m/s, fixed dt 5x the CFL 0.2 step", {"integrator": {"type": "verlet", "dt": 6e-5}})):
        out = os.path.join(outroot, "hard_" + str(len(rows)))
        r = vc.run(scene, out, sets, threads=2)
        nf, bad = vc.nan_frames(out)
        rows.append({"case": label, "rc": r.rc, "wall": r.solver_wall, "frames": nf, "nan_frames": bad,
                     "removed": removed(r), "message": r.message() if r.rc else ""})
        print(rows[-1], flush=True)
    for f in (1.5, 3.0):
        out = os.path.join(outroot, f"hard_dam_f{f:g}")
        s = dict(CASES["dam_break"][1])
        h_c = vc.h_over_c0(case_dam_break.SCENE, s)
        s["integrator.dt"] = f * h_c
        r = vc.run(case_dam_break.SCENE, out, s, threads=2)
        nf, bad = vc.nan_frames(out)
        rows.append({"case": f"dam break verlet dt = {f:g} h/c0 ({f * h_c:.2e} s)", "rc": r.rc,
                     "wall": r.solver_wall, "frames": nf, "nan_frames": bad, "removed": removed(r),
                     "message": r.message() if r.rc else ""})
        print(rows[-1], flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default="dam_break,hydrostatic")
    ap.add_argument("--integrators", default=",".join(INTEGRATORS))
    ap.add_argument("--tol", type=float, default=0.05)
    ap.add_argument("--start", type=float, default=0.2, help="first f tried (doubled while stable)")
    ap.add_argument("--csv-name", default="stability.csv")
    ap.add_argument("--hard", action="store_true", help="also the hard cases")
    ap.add_argument("--only-hard", action="store_true")
    ap.add_argument("--check", action="store_true", help="exit 1 if a frame holds NaN or a run exits other than 0/3")
    ap.add_argument("-o", "--outdir", default=os.path.join(vc.ROOT, "runs", "stability"))
    a = ap.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    fail = False
    if not a.only_hard:
        rows = []
        for case in a.cases.split(","):
            for integ in a.integrators.split(","):
                print(f"{case} {integ}", flush=True)
                r = largest_stable(case, integ, a.tol, a.outdir, a.start)
                if r is None:
                    print("   not available in this build")
                    continue
                rows.append(r)
                print(f"   largest stable f = {r['f_stable']:.3g} (dt = {r['dt_stable']:.3e} s)", flush=True)
                fail |= r["nan_frames_total"] != 0
                vc.write_csv(os.path.join(a.outdir, a.csv_name), rows)
    if a.hard or a.only_hard:
        rows = hard_cases(a.outdir)
        vc.write_csv(os.path.join(a.outdir, "hard_cases.csv"), rows)
        fail |= any(r["rc"] not in (0, 3) or r["nan_frames"] != 0 or (r["rc"] == 3 and not r["message"])
                    for r in rows)
    if a.check and fail:
        print("FAIL: NaN frames or unexpected exit")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
