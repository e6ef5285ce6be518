#!/usr/bin/env python3
"""Buchner (2002) wall pressure, the Colagrossi & Landrini (2003) dam break: a water column 2H x H (H = 0.6 m)
against the left wall of a tank 5.366H long; pressure sensor P1 on the right wall at y = 0.2H.
Reference: tests/data/validation/buchner_2002_wall_pressure_p1.csv (digitised scatter, sorted by T here).

T = t sqrt(g/H), P = p / (rho0 g H). The run goes to T = 8 (t = 1.978 s); the probe rows are 1 ms means (a
transducer sampled at 1 kHz, docs/results.md; T step 0.004).
Metrics (docs/validation.md section 10, the goals of issue 13 at H/dx >= 50):
  rms            RMS of P_sim(T_i) - P_i over the digitised points with T_i >= 2 (P_sim linear in T)   goal <= 0.08
  first_max      max P_sim for T in [2, 4] (data 0.686) and first_max_diff = first_max - data      goal |diff| <= 0.15
  second_max     max P_sim for T in [5, 7] (data 0.879, the plunging breaker) and second_max_diff   goal |diff| <= 0.2
  arrival_T      first T where P_sim > 0.1, linearly interpolated (data 2.48)
  energy_*       mechanical + elastic energy E = kinetic + potential + Tait internal (diagnostics.csv) against the
                 available energy E_av = rho0 g A (H - d)/2 (column of area A = 2H^2 levelled to the depth d = A / L):
                 energy_loss_T2 = (E(0) - E(T=2)) / E_av (before the impact; the physics loses almost nothing),
                 energy_loss_end (T = 8), energy_growth_max = max(E(t) - E(0)) / E_av (must not be > 0).

  /usr/bin/python3 pipelines/validation/case_buchner.py --h-over-dx 50 [--scene FILE] [--setup FILE] [--set K=V]...
      [--t-end-T 8] [--threads 2] [-o DIR] [--png FILE] [--check-rms 0.08] [--check-first 0.15] [--check-second 0.2]
`--h-over-dx` is the column height over the particle spacing (dx = H / N); `--setup` takes the method blocks of a
set-up scene (vsetup.py); the pressure sensor is `probes.0` of the scene (change it with --set 'probes.0={...}').
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

SCENE = os.path.join(vc.HERE, "buchner_2002.json")
REF = "buchner_2002_wall_pressure_p1.csv"
H, G, RHO0, L_TANK = 0.6, 9.81, 1000.0, 5.366 * 0.6
FIRST_WIN, SECOND_WIN, T_RMS_MIN, ARRIVAL_P = (2.0, 4.0), (5.0, 7.0), 2.0, 0.1
GOALS = {"rms": 0.08, "first_max_diff": 0.15, "second_max_diff": 0.2}


def tscale():
    return math.sqrt(G / H)


def reference():
    r = vc.reference(REF)
    k = np.argsort(r["T"], kind="stable")
    return r["T"][k], r["P"][k]


def arrival(T, P, level=ARRIVAL_P, t_min=0.0):
    """First T >= t_min where P crosses `level` upwards (linear interpolation between samples)."""
    idx = np.nonzero((P > level) & (T >= t_min))[0]
    if len(idx) == 0:
        return float("nan")
    k = idx[0]
    if k == 0:
        return float(T[0])
    return float(T[k - 1] + (level - P[k - 1]) / (P[k] - P[k - 1]) * (T[k] - T[k - 1]))


def window_max(T, P, win):
    sel = (T >= win[0]) & (T <= win[1])
    if not sel.any():
        return float("nan"), float("nan")
    k = int(np.argmax(np.where(sel, P, -np.inf)))
    return float(P[k]), float(T[k])


def pressure_metrics(T, P):
    Tr, Pr = reference()
    m = {}
    sel = Tr >= T_RMS_MIN
    if T[-1] >= Tr[sel].max() - 1e-9:
        m["rms"] = float(np.sqrt(np.mean((np.interp(Tr[sel], T, P) - Pr[sel]) ** 2)))
    else:
        m["rms"] = float("nan")
    m["rms_points"] = int(sel.sum())
    for name, win in (("first", FIRST_WIN), ("second", SECOND_WIN)):
        pm, tm = window_max(T, P, win)
        pd, td = window_max(Tr, Pr, win)
        m[f"{name}_max"], m[f"{name}_max_T"] = pm, tm
        m[f"{name}_max_data"], m[f"{name}_max_T_data"] = pd, td
        m[f"{name}_max_diff"] = pm - pd
    m["arrival_T"] = arrival(T, P)
    m["arrival_T_data"] = arrival(Tr, Pr)
    # time-window means (what a transducer's mean load would show), sim and data, over the two plateaus
    for a, b in ((3.0, 5.0), (5.5, 7.0)):
        s, d = (T >= a) & (T <= b), (Tr >= a) & (Tr <= b)
        m[f"mean_T{a:g}_{b:g}"] = float(np.mean(P[s])) if s.any() else float("nan")
        m[f"mean_T{a:g}_{b:g}_data"] = float(np.mean(Pr[d])) if d.any() else float("nan")
    return m


def energy_metrics(rundir, T_pre=2.0, area=2 * H * H, length=L_TANK, height=H):
    """Energy lost before the impact and at the end, as fractions of the available energy (module docstring)."""
    d = vc.read_csv(os.path.join(rundir, "diagnostics.csv"))
    t = d["time"]
    E = d["kinetic_energy"] + d["potential_energy"] + d["internal_energy"]
    depth = area / length
    e_av = RHO0 * G * area * (height - depth) / 2.0
    T = t * tscale()
    loss = (E[0] - E) / e_av
    return {"energy_loss_T2": float(np.interp(T_pre, T, loss)) if T[-1] >= T_pre else float("nan"),
            "energy_loss_end": float(loss[-1]), "energy_end_T": float(T[-1]),
            "energy_growth_max": float(max(0.0, -loss.min())), "energy_available_J": e_av}


def probe_column(rundir, scene_path):
    """probes.csv column of the scene's first pressure probe (probes.0 by convention)."""
    with open(os.path.join(rundir, "run.json")) as f:
        probes = json.load(f).get("scene", {}).get("probes", [])
    names = [p.get("name", "") for p in probes if p.get("type") == "pressure"]
    if not names:
        raise SystemExit(f"{scene_path}: the scene has no pressure probe (probes.0 must be the wall sensor P1)")
    return "p_" + names[0]


def evaluate(rundir, scene_path):
    p = vc.read_csv(os.path.join(rundir, "probes.csv"))
    col = probe_column(rundir, scene_path)
    T = p["time"] * tscale()
    P = p[col] / (RHO0 * G * H)
    ok = np.isfinite(P)
    m = pressure_metrics(T[ok], P[ok])
    m.update(energy_metrics(rundir))
    m["samples"] = int(ok.sum())
    m["error"] = m["rms"]
    return m, (T[ok], P[ok])


def plot(T, P, res, path, label="varsph"):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    Tr, Pr = reference()
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(T, P, "-", lw=0.7, label=label)
    ax.scatter(Tr, Pr, s=9, color="k", zorder=3, label="Buchner (2002), digitised (Adami et al. 2012)")
    for win in (FIRST_WIN, SECOND_WIN):
        ax.axvspan(*win, color="0.9", zorder=0)
    ax.set_xlim(0, max(8.0, float(T[-1]) if len(T) else 8.0))
    ax.set_ylim(-0.2, max(1.2, min(3.0, float(np.nanmax(P)) * 1.05 if len(P) else 1.2)))
    ax.set_xlabel("T = t sqrt(g/H)")
    ax.set_ylabel("P = p / (rho g H) at P1 (y = 0.2H)")
    ax.set_title(f"RMS(T>=2) {res.get('rms', float('nan')):.3f}, first max {res.get('first_max', float('nan')):.3f} "
                 f"(data 0.686), second {res.get('second_max', float('nan')):.3f} (data 0.879)", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run_case(h_over_dx=50, sets=None, threads=2, outdir=None, scene=SCENE, setup=None, t_end_T=8.0, png=None,
             timeout=None):
    dx = H / h_over_dx
    outdir = outdir or os.path.join(vc.ROOT, "runs", "validation", f"buchner_N{h_over_dx:g}")
    if setup:
        scene = vsetup.scene_with_setup(scene, setup, os.path.abspath(outdir).rstrip("/") + "_scene.json")
    s = {"particles.spacing": dx, "time.end": t_end_T / tscale()}
    s.update(sets or {})
    r = vc.run(scene, outdir, s, threads, timeout=timeout)
    res = {"rc": r.rc, "wall": r.solver_wall, "steps": r.steps, "psps": r.psps, "load": r.load_before,
           "load_after": r.load_after, "dx": dx, "h_over_dx": h_over_dx, "message": r.message() if r.rc else ""}
    res["T_reached"] = float("nan")
    if os.path.exists(os.path.join(outdir, "probes.csv")):
        m, (T, P) = evaluate(outdir, scene)  # also for a run that stopped: its metrics up to the stop
        res.update(m)
        res["T_reached"] = float(T[-1]) if len(T) else float("nan")
        if png is not False:
            plot(T, P, res, png or os.path.join(outdir, "buchner_p1.png"))
    if r.rc != 0:
        res["error"] = float("nan")
    else:
        res["wall_per_sim_s"] = r.solver_wall / (t_end_T / tscale())
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--h-over-dx", type=float, default=50, help="column height H over the particle spacing")
    ap.add_argument("--scene", default=SCENE)
    ap.add_argument("--setup", help="scene file whose kernel/fluid/physics/boundary/integrator/health blocks are used")
    ap.add_argument("--set", action="append", default=[], help="KEY=VALUE passed to varsph run")
    ap.add_argument("--t-end-T", type=float, default=8.0, help="end time in T = t sqrt(g/H)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("-o", "--outdir")
    ap.add_argument("--png", help="figure path (default OUTDIR/buchner_p1.png)")
    ap.add_argument("--check-rms", type=float)
    ap.add_argument("--check-first", type=float, help="bound on |first max - 0.686|")
    ap.add_argument("--check-second", type=float, help="bound on |second max - 0.879|")
    a = ap.parse_args()
    sets = dict(kv.split("=", 1) for kv in a.set)
    res = run_case(a.h_over_dx, sets, a.threads, a.outdir, a.scene, a.setup, a.t_end_T, a.png)
    print(json.dumps(res, indent=1))
    if res["rc"] != 0:
        print(f"FAIL: varsph exited {res['rc']} at T = {res['T_reached']:.3f}: {res['message']}")
        return 1
    bad = []
    for key, lim in (("rms", a.check_rms), ("first_max_diff", a.check_first), ("second_max_diff", a.check_second)):
        if lim is not None and not abs(res[key]) <= lim:
            bad.append(f"{key} {res[key]:.4f} beyond {lim}")
    if bad:
        print("FAIL: " + "; ".join(bad))
        return 1
    print("OK")
    return 0


if __name__ == "__main__":
    sys.exit(main())
