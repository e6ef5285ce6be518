#!/usr/bin/env python3
"""Work-precision report: error against wall time for integrators x time steps x resolutions on the
validation cases (pipelines/validation/case_*.py).

  /usr/bin/python3 pipelines/work_precision.py [--quick] [--cases dam_break,buchner,hydrostatic,taylor_green,poiseuille]
      [--setup FILE] [--threads 2] [-o runs/work_precision]

Writes OUT/work_precision.csv (one row per run) and OUT/work_precision.png (error against wall seconds per
simulated second, one panel per case, the Pareto front of each case drawn as a line; the dam-break panel
also shows the peers' published points of the issue: DualSPHysics 5.4 and SPlisHSPlasH 2.16).

Integrators are detected with `varsph info SCENE --set integrator.type=...` (exit 0 = available). `verlet`
is the seed's eq. (60)-(62), i.e. the kick-drift leap-frog, so "leap-frog" is the verlet row. Time steps are
fixed: dt = f h / c0 for the factors f of the matrix (the CFL limit of the solver is 0.2 h / c0 for the
acoustic part); a run that stops with exit 3 is recorded as unstable (error NaN).

Pressure error as the second error axis (issue 13): the `buchner` case runs the Buchner (2002) wall-pressure
case (case_buchner.py, H/dx = 25 and 50, to T = 8) with the same physics blocks as the dam-break rows
(dam_break_mm_wendland.json, or --setup FILE for both), so each integrator and dt has a front error (dam_break
panel) and a wall-pressure error (RMS of P1 over T >= 2, buchner panel) against the same wall-time axis;
work_precision_errors.png plots both errors of each (integrator, f) pair against each other.
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
import case_buchner  # noqa: E402
import vsetup  # noqa: E402

INTEGRATORS = [("verlet", None), ("variational", 0.25), ("variational", 0.5), ("variational", 0.75),
               ("symplectic_euler", None), ("rk4", None), ("predictor_corrector", None), ("verlet_dsph", None)]

# peers of the issue: (label, dx, wall s per simulated s, RMS unshifted, RMS at best shift)
PEERS = [("DualSPHysics 5.4", 0.005, 18.5, 0.127, 0.0088), ("DualSPHysics 5.4", 0.0025, 167, 0.147, 0.0092),
         ("DualSPHysics 5.4", 0.00125, 1389, 0.158, 0.0091),
         ("SPlisHSPlasH DFSPH", 0.005, 11.4, 0.153, 0.017), ("SPlisHSPlasH DFSPH", 0.0025, 61.6, 0.159, 0.0082),
         ("SPlisHSPlasH DFSPH", 0.00125, 370, 0.165, 0.0083),
         ("SPlisHSPlasH WCSPH", 0.005, 14.9, 0.141, 0.017), ("SPlisHSPlasH WCSPH", 0.0025, 99.5, 0.167, 0.016),
         ("SPlisHSPlasH WCSPH", 0.00125, 903, 0.174, 0.013)]


_BUCHNER = {"scene": None, "setup": case_dam_break.SCENE_WENDLAND, "dam": None}


def dam_scene():
    """The dam-break scene: dam_break_mm_wendland.json, or dam_break_mm.json with the blocks of --setup."""
    if _BUCHNER["setup"] == case_dam_break.SCENE_WENDLAND:
        return case_dam_break.SCENE_WENDLAND
    if _BUCHNER["dam"] is None:
        out = os.path.join(vc.ROOT, "runs", "work_precision", "dam_break_scene.json")
        _BUCHNER["dam"] = vsetup.scene_with_setup(case_dam_break.SCENE, _BUCHNER["setup"], out)
    return _BUCHNER["dam"]


def buchner_scene():
    """Buchner scene with the physics blocks of the dam-break rows (or of --setup), written once."""
    if _BUCHNER["scene"] is None:
        out = os.path.join(vc.ROOT, "runs", "work_precision", "buchner_scene.json")
        _BUCHNER["scene"] = vsetup.scene_with_setup(case_buchner.SCENE, _BUCHNER["setup"], out)
    return _BUCHNER["scene"]


CASES = {
    # the dam break uses the best variant of docs/validation.md (Wendland C2, h = 1.3 dx); t = 0 ... 0.27 s
    "dam_break": dict(scene=dam_scene, dx=[0.01, 0.005], dx_quick=[0.005],
                      f=[0.2, 0.4, 0.73, 0.92, 1.1], f_quick=[0.4, 0.73],
                      run=lambda dx, sets, thr, out: case_dam_break.run_case(dx, sets, thr, out, dam_scene())),
    # Buchner wall pressure, H/dx = 25 and 50 (dx = H / N), T = 0 ... 8, physics of the dam-break rows
    "buchner": dict(scene=buchner_scene, dx=[0.024, 0.012], dx_quick=[0.024], f=[0.4, 0.73, 0.92], f_quick=[0.73],
                    run=lambda dx, sets, thr, out: case_buchner.run_case(case_buchner.H / dx, sets, thr, out,
                                                                         buchner_scene(), png=False)),
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
    sc = CASES[case]["scene"]
    if callable(sc):
        sc = sc()
    if sc:
        return sc, {"particles.spacing": dx}
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
        elif case == "buchner":
            # issue 13: the goal and the peers' RMS at H/dx = 50 measured by the team (no wall times known)
            ax.axhline(0.08, color="r", lw=0.8, label="goal 0.08")
            for val, lab, col in ((0.26, "SPHinXsys 0.24-0.28", "tab:olive"), (0.35, "DualSPHysics 5.4 DBC", "tab:gray"),
                                  (0.71, "DualSPHysics 5.4 mDBC", "tab:brown")):
                ax.axhline(val, color=col, lw=0.8, ls=":", label=lab + " (H/dx 50)")
            ax.set_ylabel("Buchner P1 RMS (T >= 2), P = p/(rho g H)")
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


def plot_errors(rows, path):
    """Front error (dam break) against wall-pressure error (Buchner) for each (integrator, f) pair run on both."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    db = {(r["label"], float(r["f"])): r for r in rows if r["case"] == "dam_break" and np.isfinite(r["error"])}
    bu = [r for r in rows if r["case"] == "buchner" and np.isfinite(r["error"])]
    pairs = [(db[(r["label"], float(r["f"]))], r) for r in bu if (r["label"], float(r["f"])) in db]
    if not pairs:
        return False
    fig, ax = plt.subplots(figsize=(6, 4.5))
    sc = ax.scatter([a["error"] for a, _ in pairs], [b["error"] for _, b in pairs],
                    c=[math.log10(b["wall_per_sim_s"]) for _, b in pairs], cmap="viridis", s=30)
    for a, b in pairs:
        ax.annotate(f"{b['label']} f={float(b['f']):g} dx={float(b['dx']):g}", (a["error"], b["error"]), fontsize=5)
    fig.colorbar(sc, label="log10 Buchner wall s per simulated s")
    ax.set_xlabel("dam-break front error (MM, best shift)")
    ax.set_ylabel("Buchner P1 RMS (T >= 2)")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="one resolution and two dt factors per case")
    ap.add_argument("--cases", default="dam_break,buchner,hydrostatic,taylor_green,poiseuille")
    ap.add_argument("--setup", help="scene file whose method blocks the dam-break and Buchner rows use "
                                    "(default: dam_break_mm_wendland.json's)")
    ap.add_argument("--integrators", help="comma list, e.g. verlet,variational:0.5 (default: all available)")
    ap.add_argument("--dx", help="comma list of resolutions overriding the matrix's")
    ap.add_argument("--factors", help="comma list of dt factors f (dt = f h / c0) overriding the matrix's")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("-o", "--outdir", default=os.path.join(vc.ROOT, "runs", "work_precision"))
    ap.add_argument("--append", action="store_true", help="keep the rows of an existing work_precision.csv")
    ap.add_argument("--plot-only", action="store_true")
    a = ap.parse_args()
    unknown = [c for c in a.cases.split(",") if c not in CASES]
    if unknown:
        print(f"work_precision.py: --cases: unknown case(s) {', '.join(unknown)}; expected some of {', '.join(CASES)}",
              file=sys.stderr)
        return 2
    if a.setup:
        vsetup.load_setup(a.setup)  # exit 2 on a bad file before anything runs
        _BUCHNER["setup"] = a.setup
    os.makedirs(a.outdir, exist_ok=True)
    csv_path = os.path.join(a.outdir, "work_precision.csv")
    fields = ["case", "label", "integrator", "alpha", "dx", "f", "dt", "rc", "wall", "wall_per_sim_s", "psps",
              "steps", "error", "mm_rms", "mm_rms_shift", "mm_dT", "ko_rms_shift", "rms", "first_max_diff",
              "second_max_diff", "drift", "l1_t1",
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
        plot_errors(rows, os.path.join(a.outdir, "work_precision_errors.png"))
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
