#!/usr/bin/env python3
"""Work-precision report: error against wall time for integrators x time steps x resolutions on the
validation cases (pipelines/validation/case_*.py).

  /usr/bin/python3 pipelines/work_precision.py [--quick] [--cases dam_break,hydrostatic,taylor_green,poiseuille]
      [--threads 2] [-o runs/work_precision]

Writes OUT/work_precision.csv (one row per run) and OUT/work_precision.png (error against wall seconds per
simulated second, one panel per case, the Pareto front of each case drawn as a line; the dam-break panel
also shows the peers' published points of the issue: DualSPHysics 5.4 and SPlisHSPlasH 2.16).

Integrators are detected with `varsph info SCENE --set integrator.type=...` (exit 0 = available). `verlet`
is the seed's eq. (60)-(62), i.e. the kick-drift leap-frog, so "leap-frog" is the verlet row. Time steps are
fixed: dt = f h / c0 for the factors f of the matrix (the CFL limit of the solver is 0.2 h / c0 for the
acoustic part); a run that stops with exit 3 is recorded as unstable (error NaN).
"""
import argparse
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "validation"))
import vcommon as vc  # noqa: E402
import case_dam_break  # noqa: E402
import case_hydrostatic  # noqa: E402
import case_taylor_green  # noqa: E402
import case_poiseuille  # noqa: E402

INTEGRATORS = [("verlet", None), ("variational", 0.25), ("variational", 0.5), ("variational", 0.75),
               ("symplectic_euler", None), ("rk4", None), ("predictor_corrector", None), ("verlet_dsph", None)]

# peers of the issue: (label, dx, wall s per simulated s, RMS unshifted, RMS at best shift)
PEERS = [("DualSPHysics 5.4", 0.005, 18.5, 0.127, 0.0088), ("DualSPHysics 5.4", 0.0025, 167, 0.147, 0.0092),
         ("DualSPHysics 5.4", 0.00125, 1389, 0.158, 0.0091),
         ("SPlisHSPlasH DFSPH", 0.005, 11.4, 0.153, 0.017), ("SPlisHSPlasH DFSPH", 0.0025, 61.6, 0.159, 0.0082),
         ("SPlisHSPlasH DFSPH", 0.00125, 370, 0.165, 0.0083),
         ("SPlisHSPlasH WCSPH", 0.005, 14.9, 0.141, 0.017), ("SPlisHSPlasH WCSPH", 0.0025, 99.5, 0.167, 0.016),
         ("SPlisHSPlasH WCSPH", 0.00125, 903, 0.174, 0.013)]


CASES = {
    # the dam break uses the best variant of docs/validation.md (Wendland C2, h = 1.3 dx); t = 0 ... 0.27 s
    "dam_break": dict(scene=case_dam_break.SCENE_WENDLAND, dx=[0.01, 0.005], dx_quick=[0.005],
                      f=[0.2, 0.4, 0.73, 0.92, 1.1], f_quick=[0.4, 0.73],
                      run=lambda dx, sets, thr, out: case_dam_break.run_case(dx, sets, thr, out,
                                                                             case_dam_break.SCENE_WENDLAND)),
    # hydrostatic tank, t = 0 ... 1 s (pressure averaged over 0.8 ... 1 s)
    "hydrostatic": dict(scene=case_hydrostatic.SCENE, dx=[0.02, 0.01], dx_quick=[0.02],
                        f=[0.2, 0.4, 0.8], f_quick=[0.4],
                        run=lambda dx, sets, thr, out: case_hydrostatic.run_case(dx, sets, thr, out, t_end=1.0)),
    "taylor_green": dict(scene=None, dx=[0.04, 0.02], dx_quick=[0.04], f=[0.2, 0.4, 0.8], f_quick=[0.4],
                         run=lambda dx, sets, thr, out: case_taylor_green.run_case(dx, sets, thr, out, t_end=1.0)),
    "poiseuille": dict(scene=None, dx=[0.05, 0.025], dx_quick=[0.05], f=[0.2, 0.4, 0.8], f_quick=[0.4],
                       run=lambda dx, sets, thr, out: case_poiseuille.run_case(dx, sets, thr, out)),
}


def scene_for_info(case, dx):
    if CASES[case]["scene"]:
        return CASES[case]["scene"], {"particles.spacing": dx}
    import json
    d = os.path.join(vc.ROOT, "runs", "validation")
    os.makedirs(d, exist_ok=True)
    p = os.path.join(d, f"wp_{case}_info.json")
    mk = case_taylor_green.make_scene if case == "taylor_green" else case_poiseuille.make_scene
    with open(p, "w") as f:
        json.dump(mk(dx), f)
    return p, {}


def pareto(rows):
    pts = sorted((r for r in rows if np.isfinite(r["error"])), key=lambda r: r["wall_per_sim_s"])
    front, best = [], float("inf")
    for r in pts:
        if r["error"] < best:
            front.append(r)
            best = r["error"]
    return front


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cases = [c for c in CASES if any(r["case"] == c for r in rows)]
    fig, axes = plt.subplots(1, len(cases), figsize=(5.2 * len(cases), 4.4), squeeze=False)
    markers = {"verlet": "o", "variational": "s", "symplectic_euler": "^", "rk4": "D", "predictor_corrector": "v",
               "verlet_dsph": "P"}
    for ax, case in zip(axes[0], cases):
        rs = [r for r in rows if r["case"] == case and np.isfinite(r["error"])]
        labels = sorted({r["label"] for r in rs})
        for lab in labels:
            sub = [r for r in rs if r["label"] == lab]
            ax.scatter([r["wall_per_sim_s"] for r in sub], [r["error"] for r in sub],
                       marker=markers.get(sub[0]["integrator"], "x"), label=lab, s=28)
        fr = pareto(rs)
        if fr:
            ax.plot([r["wall_per_sim_s"] for r in fr], [r["error"] for r in fr], "k--", lw=1, label="Pareto front")
        if case == "dam_break":
            for name, col in (("DualSPHysics 5.4", "tab:gray"), ("SPlisHSPlasH DFSPH", "tab:olive"),
                              ("SPlisHSPlasH WCSPH", "tab:brown")):
                p = [q for q in PEERS if q[0] == name]
                ax.plot([q[2] for q in p], [q[4] for q in p], "x:", color=col, label=name + " (issue)")
            ax.axhline(0.009, color="r", lw=0.8)
            ax.axvline(9.0, color="r", lw=0.8)
            ax.set_ylabel("RMS rel. front error at best shift |dT|<=0.3")
        else:
            ax.set_ylabel({"hydrostatic": "rel. L2 pressure error", "taylor_green": "L1 velocity error (t=1)",
                           "poiseuille": "max |u - u_series| / u_max"}.get(case, "error"))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall s per simulated s (2 threads)")
        ax.set_title(case)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="one resolution and two dt factors per case")
    ap.add_argument("--cases", default="dam_break,hydrostatic,taylor_green,poiseuille")
    ap.add_argument("--integrators", help="comma list, e.g. verlet,variational:0.5 (default: all available)")
    ap.add_argument("--dx", help="comma list of resolutions overriding the matrix's")
    ap.add_argument("--factors", help="comma list of dt factors f (dt = f h / c0) overriding the matrix's")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("-o", "--outdir", default=os.path.join(vc.ROOT, "runs", "work_precision"))
    ap.add_argument("--append", action="store_true", help="keep the rows of an existing work_precision.csv")
    ap.add_argument("--plot-only", action="store_true")
    a = ap.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    csv_path = os.path.join(a.outdir, "work_precision.csv")
    fields = ["case", "label", "integrator", "alpha", "dx", "f", "dt", "rc", "wall", "wall_per_sim_s", "psps",
              "steps", "error", "mm_rms", "mm_rms_shift", "mm_dT", "ko_rms_shift", "drift", "l1_t1",
              "vmax_rel_err_t1", "load", "message"]
    rows = []
    if (a.append or a.plot_only) and os.path.exists(csv_path):
        import csv
        with open(csv_path) as f:
            for r in csv.DictReader(f):
                for k in ("dx", "f", "dt", "wall", "wall_per_sim_s", "error"):
                    r[k] = float(r[k]) if r.get(k) not in (None, "", "nan") else float("nan")
                rows.append(r)
    if not a.plot_only:
        integs = INTEGRATORS
        if a.integrators:
            integs = [(s.split(":")[0], float(s.split(":")[1]) if ":" in s else None)
                      for s in a.integrators.split(",")]
        for case in a.cases.split(","):
            cfg = CASES[case]
            dxs = [float(x) for x in a.dx.split(",")] if a.dx else (cfg["dx_quick"] if a.quick else cfg["dx"])
            fs = [float(x) for x in a.factors.split(",")] if a.factors else (cfg["f_quick"] if a.quick else cfg["f"])
            info_scene, info_sets = scene_for_info(case, dxs[0])
            if vc.info(info_scene, info_sets)[0] != 0:
                print(f"{case}: scene not runnable in this build (missing physics term?): skipped", flush=True)
                continue
            for itype, alpha in integs:
                sets = {"integrator.type": itype}
                if alpha is not None:
                    sets["integrator.alpha"] = alpha
                if not vc.integrator_available(info_scene, itype, alpha):
                    print(f"{case}: integrator {itype} not available in this build or not applicable to the scene "
                          f"(`varsph info` refuses it): skipped", flush=True)
                    continue
                label = itype + (f" a={alpha:g}" if alpha is not None else "")
                for dx in dxs:
                    sc, ss = scene_for_info(case, dx)
                    hc = vc.h_over_c0(sc, dict(ss, **sets))
                    for f in fs:
                        dt = f * hc
                        # the whole integrator object, so that a scene's integrator.cfl does not clash with dt
                        s = {"integrator": {"type": itype, "dt": dt}}
                        if alpha is not None:
                            s["integrator"]["alpha"] = alpha
                        out = os.path.join(a.outdir, "runs", f"{case}_{label.replace(' ', '_')}_dx{dx:g}_f{f:g}")
                        t0 = time.monotonic()
                        res = cfg["run"](dx, s, a.threads, out)
                        row = {"case": case, "label": label, "integrator": itype, "alpha": alpha, "dx": dx, "f": f,
                               "dt": dt}
                        row.update({k: res.get(k) for k in fields if k in res})
                        row["error"] = res.get("error", float("nan"))
                        row.setdefault("wall_per_sim_s", float("nan"))
                        rows.append(row)
                        print(f"{case:12s} {label:22s} dx={dx:<7g} f={f:<4g} rc={res['rc']} "
                              f"wall={res.get('wall', 0):7.1f}s ({time.monotonic() - t0:5.1f}) "
                              f"err={row['error']:.4g} load={res.get('load', 0):.1f} {res.get('message', '')}",
                              flush=True)
                        vc.write_csv(csv_path, rows, fields)
    vc.write_csv(csv_path, rows, fields)
    if rows:
        plot(rows, os.path.join(a.outdir, "work_precision.png"))
        for case in CASES:
            fr = pareto([r for r in rows if r["case"] == case])
            if fr:
                print(f"Pareto front {case}: " + "; ".join(
                    f"{r['label']} dx={r['dx']} f={r['f']} ({r['wall_per_sim_s']:.3g} s/s, {r['error']:.3g})"
                    for r in fr))
    print(f"wrote {csv_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
