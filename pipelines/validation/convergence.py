#!/usr/bin/env python3
"""Convergence: the error of the hydrostatic tank (pressure profile) and of the Taylor-Green vortex (L1 velocity)
at three resolutions, with the observed order (least-squares slope of log error against log dx, and pairwise).

Every metric a case reports is tabulated with its own order: hydrostatic `p_err` (against rho0 g (H - y)),
`p_err_tait` (against the compressible, mass-conserving Tait column), `p_err_hmeas` (against rho0 g (h - y) with
the measured water height h); Taylor-Green `l1_t1`, `l1_t2`, `vmax_rel_err_t1`, `vmax_rel_err_t2`.

  /usr/bin/python3 pipelines/validation/convergence.py [--cases hydrostatic,taylor_green] [--quick] [--no-settle]
      [--set KEY=VALUE]... [-o runs/convergence]
Writes OUT/convergence.csv.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vcommon as vc  # noqa: E402
import case_hydrostatic  # noqa: E402
import case_taylor_green  # noqa: E402

# hydrostatic: dx divides H = 0.3 (10 / 20 / 40 rows; the metric uses the particles' own column width and mass)
RES = {"hydrostatic": [0.03, 0.015, 0.0075], "taylor_green": [0.04, 0.02, 0.01]}
RES_QUICK = {"hydrostatic": [0.06, 0.03, 0.015], "taylor_green": [0.1, 0.05, 0.025]}
METRICS = {"hydrostatic": ["p_err", "p_err_tait", "p_err_hmeas"],
           "taylor_green": ["l1_t1", "l1_t2", "vmax_rel_err_t1", "vmax_rel_err_t2"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default="hydrostatic,taylor_green")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--t-end-hydrostatic", type=float, default=2.0)
    ap.add_argument("--t-end-tg", type=float, default=2.0)
    ap.add_argument("--no-settle", action="store_true",
                    help="hydrostatic: the scene's inconsistent hydrostatic start instead of case_hydrostatic.SETTLE")
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("-o", "--outdir", default=os.path.join(vc.ROOT, "runs", "convergence"))
    ap.add_argument("--check-order", type=float, help="exit 1 if an observed (fitted) order is below this")
    a = ap.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    sets = dict(kv.split("=", 1) for kv in a.set)
    rows, ok = [], True
    for case in a.cases.split(","):
        res = (RES_QUICK if a.quick else RES)[case]
        errs = []
        for dx in res:
            out = os.path.join(a.outdir, f"{case}_dx{dx:g}")
            if case == "hydrostatic":
                r = case_hydrostatic.run_case(dx, sets, 2, out, t_end=a.t_end_hydrostatic, settle=not a.no_settle)
            else:
                if not case_taylor_green.laminar_available():
                    print("taylor_green: no physics.laminar_viscosity in this build: skipped")
                    break
                r = case_taylor_green.run_case(dx, sets, 2, out, t_end=a.t_end_tg)
            errs.append(r)
            row = {"case": case, "dx": dx, "error": r["error"], "rc": r["rc"], "wall": r["wall"],
                   "load": r["load"], "message": r.get("message", "")}
            for m in METRICS[case]:
                row[m] = r.get(m, float("nan"))
            rows.append(row)
            print(f"{case} dx={dx:g} rc={r['rc']} error={r['error']:.4g} "
                  + " ".join(f"{m}={r.get(m, float('nan')):.4g}" for m in METRICS[case])
                  + f" wall={r['wall']:.1f}s load={r['load']:.1f}", flush=True)
        if len(errs) == len(res):
            for m in ["error"] + METRICS[case]:
                vals = [e.get(m, float("nan")) for e in errs]
                slope, pairs = vc.observed_order(res, vals)
                print(f"{case} {m}: observed order {slope:.2f} (pairwise {', '.join(f'{p:.2f}' for p in pairs)})")
                rows.append({"case": f"{case} (order of {m})", "dx": "", "error": slope, "rc": "", "wall": "",
                             "load": "", "message": "pairwise " + " ".join(f"{p:.2f}" for p in pairs)})
                if m == "error" and a.check_order is not None and not slope >= a.check_order:
                    ok = False
        fields = ["case", "dx", "error"] + sorted({k for r in rows for k in r} - {"case", "dx", "error"})
        vc.write_csv(os.path.join(a.outdir, "convergence.csv"), rows, fields)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
