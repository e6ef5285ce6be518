#!/usr/bin/env python3
"""2D water jet on a flat plate: steady force and stagnation pressure against the momentum theorem.

A plane jet of width b and speed U deflected by 90 degrees on a plate normal to it loads the plate with
F = rho U^2 b per unit depth (the x-momentum flux it brings; the two sheets leave along the plate with none)
and its stagnation point carries p = rho U^2 / 2 (Bernoulli, gravity off).
varsph has no inflow boundary, so the jet is a slab of length Ls moving at U toward the plate (scene
jet_plate.json): it reaches the plate at t0 = gap / U and its tail at t0 + Ls / U. The quasi-steady window is
  [t0 + 3 b / U, t0 + Ls / U - 2 b / U]:
the stagnation flow, which reaches about one jet width upstream, is set up within a few b / U of the first
contact (the water-hammer transient rho c0 U relaxes across the jet in ~ b / c0 and the flow turns in ~ b / U),
and it starts to feel the approaching tail about 1-2 b / U before the tail arrives. The script reports the
mean over the window, its standard deviation and its linear drift across the window (a steady state has both
small), so the window can be judged from the numbers; the figure shows the whole history.
b is the slab's lattice width (rows x dx) and rho U^2 b its exact momentum flux.

Metrics: force_err = mean Fx / (rho U^2 b) - 1 (goal |.| <= 3 %), p_stag_err = mean p / (rho U^2 / 2) - 1
(goal |.| <= 5 %), from probes.csv: the force probe on the plate (the scene's `force` probe) and its first
pressure probe (probes.0, at the stagnation point on the plate face).

  /usr/bin/python3 pipelines/validation/case_jet_plate.py [--dx 0.005] [--scene FILE] [--setup FILE] [--set K=V]...
      [--threads 2] [-o DIR] [--png FILE] [--check-force 0.03] [--check-pressure 0.05]
"""
import argparse
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vcommon as vc  # noqa: E402
import vsetup  # noqa: E402

SCENE = os.path.join(vc.HERE, "jet_plate.json")
GOALS = {"force_err": 0.03, "p_stag_err": 0.05}
T_AFTER_CONTACT, T_BEFORE_TAIL = 3.0, 2.0  # window margins in units of b / U


def geometry(scene, dx):
    """Slab width b (lattice rows x dx), length, speed U, gap to the plate, rho0 from the scene dict. A scene
    with an inlet (pipelines/open/jet_plate_inlet.json) feeds the jet for ever: b is the inlet zone's width,
    U its uniform speed, and the window runs to the end of the run (Ls = None)."""
    jet = next(b for b in scene["bodies"] if b["kind"] == "fluid")
    plate = scene["bodies"][next(p["body"] for p in scene["probes"] if p["type"] == "force")]
    rows = math.floor((jet["max"][1] - jet["min"][1]) / dx + 1e-6)
    cols = math.floor((jet["max"][0] - jet["min"][0]) / dx + 1e-6)
    U = float(jet["velocity"][0])
    g = {"b": rows * dx, "Ls": cols * dx, "U": U, "gap": plate["min"][0] - (jet["min"][0] + cols * dx),
         "rho0": float(scene.get("fluid", {}).get("rho0", 1000.0))}
    inlet = next((z for z in scene.get("open_boundaries", []) if z["kind"] == "inlet"), None)
    if inlet:
        g.update(b=round((inlet["max"][1] - inlet["min"][1]) / dx) * dx, U=float(inlet["velocity"]["value"]), Ls=None,
                 t_end=float(scene["time"]["end"]))
    return g


def window(g):
    t0 = g["gap"] / g["U"]
    if g["Ls"] is None:  # an inlet: steady from a few b / U after the contact to the end of the run
        return t0, t0 + T_AFTER_CONTACT * g["b"] / g["U"], g["t_end"]
    return t0, t0 + T_AFTER_CONTACT * g["b"] / g["U"], t0 + g["Ls"] / g["U"] - T_BEFORE_TAIL * g["b"] / g["U"]


def stats(t, y, a, b):
    sel = (t >= a) & (t <= b)
    ts, ys = t[sel], y[sel]
    mean = float(np.mean(ys))
    slope = float(np.polyfit(ts, ys, 1)[0]) if len(ts) > 2 else float("nan")
    return mean, float(np.std(ys)), slope * (b - a)


def evaluate(rundir, scene, dx):
    g = geometry(scene, dx)
    p = vc.read_csv(os.path.join(rundir, "probes.csv"))
    t = p["time"]
    fname = next(q["name"] for q in scene["probes"] if q["type"] == "force")
    pname = next(q["name"] for q in scene["probes"] if q["type"] == "pressure")
    Fx, ps = p[f"Fx_{fname}"], p[f"p_{pname}"]
    F_ref = g["rho0"] * g["U"] ** 2 * g["b"]
    p_ref = 0.5 * g["rho0"] * g["U"] ** 2
    t0, a, b = window(g)
    m = {"b": g["b"], "U": g["U"], "F_ref": F_ref, "p_ref": p_ref, "t_contact": t0, "window": [a, b]}
    if t[-1] < b - 1e-9:
        m.update(force_err=float("nan"), p_stag_err=float("nan"), error=float("nan"))
        return m, (t, Fx / F_ref, ps / p_ref)
    fm, fs, fd = stats(t, Fx, a, b)
    pm, pstd, pd = stats(t, ps, a, b)
    pre = (t >= t0) & (t < a)
    m.update({"force_mean": fm, "force_err": fm / F_ref - 1.0, "force_std_rel": fs / F_ref,
              "force_drift_rel": fd / F_ref, "p_stag_mean": pm, "p_stag_err": pm / p_ref - 1.0,
              "p_stag_std_rel": pstd / p_ref, "p_stag_drift_rel": pd / p_ref,
              "force_peak_impact_rel": float(Fx[pre].max() / F_ref) if pre.any() else float("nan"),
              "p_peak_impact_rel": float(ps[pre].max() / p_ref) if pre.any() else float("nan"),
              "Fy_mean_rel": float(np.mean(p[f"Fy_{fname}"][(t >= a) & (t <= b)]) / F_ref)})
    m["error"] = abs(m["force_err"])
    return m, (t, Fx / F_ref, ps / p_ref)


def plot(series, res, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t, F, P = series
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(t, F, lw=0.8, label="Fx / (rho U^2 b)")
    ax.plot(t, P, lw=0.8, label="p_stag / (rho U^2 / 2)")
    ax.axhline(1.0, color="k", lw=0.8)
    if "window" in res:
        ax.axvspan(*res["window"], color="0.9", zorder=0, label="quasi-steady window")
    ax.set_ylim(-0.5, 3.0)
    ax.set_xlabel("t [s]")
    ax.set_title(f"jet on a plate: force {100 * res.get('force_err', float('nan')):+.1f} %, stagnation pressure "
                 f"{100 * res.get('p_stag_err', float('nan')):+.1f} % (window mean)", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run_case(dx=0.005, sets=None, threads=2, outdir=None, scene=SCENE, setup=None, png=None, timeout=None):
    outdir = outdir or os.path.join(vc.ROOT, "runs", "validation", f"jet_plate_dx{dx:g}")
    if setup:
        scene = vsetup.scene_with_setup(scene, setup, os.path.abspath(outdir).rstrip("/") + "_scene.json")
    s = {"particles.spacing": dx}
    s.update(sets or {})
    r = vc.run(scene, outdir, s, threads, timeout=timeout)
    res = {"rc": r.rc, "wall": r.solver_wall, "steps": r.steps, "psps": r.psps, "load": r.load_before,
           "load_after": r.load_after, "dx": dx, "message": r.message() if r.rc else ""}
    if os.path.exists(os.path.join(outdir, "probes.csv")) and r.runjson:
        m, series = evaluate(outdir, r.runjson["scene"], dx)
        res.update(m)
        if png is not False:
            plot(series, res, png or os.path.join(outdir, "jet_plate.png"))
    if r.rc != 0:
        res["error"] = float("nan")
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, default=0.005)
    ap.add_argument("--scene", default=SCENE)
    ap.add_argument("--setup", help="scene file whose kernel/fluid/physics/boundary/integrator/health blocks are used")
    ap.add_argument("--set", action="append", default=[], help="KEY=VALUE passed to varsph run")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("-o", "--outdir")
    ap.add_argument("--png")
    ap.add_argument("--check-force", type=float, help="bound on |mean force / (rho U^2 b) - 1|")
    ap.add_argument("--check-pressure", type=float, help="bound on |mean p_stag / (rho U^2 / 2) - 1|")
    a = ap.parse_args()
    res = run_case(a.dx, dict(kv.split("=", 1) for kv in a.set), a.threads, a.outdir, a.scene, a.setup, a.png)
    print(json.dumps(res, indent=1))
    if res["rc"] != 0:
        print(f"FAIL: varsph exited {res['rc']}: {res['message']}")
        return 1
    bad = []
    for key, lim in (("force_err", a.check_force), ("p_stag_err", a.check_pressure)):
        if lim is not None and not abs(res[key]) <= lim:
            bad.append(f"{key} {res[key]:+.4f} beyond {lim}")
    if bad:
        print("FAIL: " + "; ".join(bad))
        return 1
    print("OK")
    return 0


if __name__ == "__main__":
    sys.exit(main())
