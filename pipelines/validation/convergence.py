#!/usr/bin/env python3
"""Convergence: the error of the hydrostatic tank (pressure profile) and of the Taylor-Green vortex (L1 velocity)
at three resolutions, with the observed order (least-squares slope of log error against log dx, and pairwise).

  /usr/bin/python3 pipelines/validation/convergence.py [--cases hydrostatic,taylor_green] [--quick]
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

RES = {"hydrostatic": [0.02, 0.01, 0.005], "taylor_green": [0.04, 0.02, 0.01]}
RES_QUICK = {"hydrostatic": [0.04, 0.02, 0.01], "taylor_green": [0.1, 0.05, 0.025]}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default="hydrostatic,taylor_green")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--t-end-hydrostatic", type=float, default=2.0)
    ap.add_argument("--t-end-tg", type=float, default=1.0)
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
                r = case_hydrostatic.run_case(dx, sets, 2, out, t_end=a.t_end_hydrostatic)
            else:
                if not case_taylor_green.laminar_available():
                    print("taylor_green: no physics.laminar_viscosity in this build: skipped")
                    break
                r = case_taylor_green.run_case(dx, sets, 2, out, t_end=a.t_end_tg)
            errs.append(r["error"])
            rows.append({"case": case, "dx": dx, "error": r["error"], "rc": r["rc"], "wall": r["wall"],
                         "load": r["load"], "message": r.get("message", "")})
            print(f"{case} dx={dx:g} rc={r['rc']} error={r['error']:.4g} wall={r['wall']:.1f}s load={r['load']:.1f}",
                  flush=True)
        if len(errs) == len(res):
            slope, pairs = vc.observed_order(res, errs)
            print(f"{case}: observed order {slope:.2f} (pairwise {', '.join(f'{p:.2f}' for p in pairs)})")
            rows.append({"case": case + " (order)", "dx": "", "error": slope, "rc": "", "wall": "", "load": "",
                         "message": "pairwise " + " ".join(f"{p:.2f}" for p in pairs)})
            if a.check_order is not None and not slope >= a.check_order:
                ok = False
        vc.write_csv(os.path.join(a.outdir, "convergence.csv"), rows)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
