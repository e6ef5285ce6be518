#!/usr/bin/env python3
"""Runs that survive (docs/validation.md "Runs that survive"): violent cases that stopped with exit 3 before
the health rules, run twice: with the rules of earlier versions (health.on_violation = "stop",
max_density_error 0.5, no speed or energy rule: where, when and why it stopped) and with the default rules (particles outside the model's states removed and
counted), with the figures that say whether the surviving run is physically sound.

Cases (the shipped scenes' physics; only the geometry changes):
  mm_wendland_wall       pipelines/validation/dam_break_mm_wendland.json as shipped (column 0.145 x 0.29 m, tank
                         0.58 m) run on to t = 1 s: through the impact on the far wall (t ~ 0.3 s) and back
  buchner2002            pipelines/validation/buchner_2002.json as shipped (H/dx 50, DualSPHysics-like physics,
                         to T = 8; it stopped with exit 3 at T = 7.73 before the health rules)
  buchner2002_mmw        the same with dam_break_mm_wendland.json's method blocks (vsetup.py) and dt 0.73 h/c0,
                         as pipelines/work_precision.py runs it (exit 3 at t = 0.93-1.10 s before)
  buchner25, buchner50   Colagrossi & Landrini (2003) / Buchner (2002) set-up: column 2H x H (H = 0.6 m)
                         against the left wall of a tank 5.366H long (open top, 2H high), to t sqrt(g/H) = 8,
                         H/dx = 25 and 50, physics of pipelines/validation/dam_break_mm_wendland.json
                         (dt = 0.73 h/c0 as there); pressure probe P1 on the right wall at 0.2H against
                         tests/data/validation/buchner_2002_wall_pressure_p1.csv.
  square50, square25,    square column 0.145 m x 0.145 m against the left wall of a tank with a 0.58 m
  square50_c88,          floor (open top, 0.6 m high), to 1 s, dx 5 and 2.5 mm, physics of
  square25_c88           pipelines/dam_break_2d_dsph_val.json with c0 = 10 sqrt(2 g H) (auto) or the
                         scene's own 88.4 m/s.

Figures per run: exit code, time reached, steps, the rule and particle that stopped the strict run, particles
removed by rule (with their neighbour counts when removed), largest fluid speed over the run against the
dam-break scale 2 sqrt(g H), largest |rho/rho0 - 1| at the frames, energy at the end / initial, the time the
surge front reaches the far wall, and for the Buchner cases the P1 error against the experiment (RMS over
the digitised points with T >= 2, first-impact maximum).

  /usr/bin/python3 pipelines/validation/runs_that_survive.py [--cases buchner25,square50] [--threads 2]
      [--rules default,stop] [-o runs/survive] [--plot]
Writes OUT/survive.csv and, with --plot, OUT/survive.png (P1 and surge fronts).
"""
import argparse
import copy
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vcommon as vc  # noqa: E402

G = 9.81
H_B = 0.6  # Buchner column height [m]


def buchner_scene(n):
    """Buchner set-up at H/dx = n with dam_break_mm_wendland.json's physics."""
    s = json.load(open(os.path.join(vc.HERE, "dam_break_mm_wendland.json")))
    H, L, dx = H_B, 5.366 * H_B, H_B / n
    g = -s["gravity"][1]
    s["name"] = f"buchner_{n}"
    s["particles"]["spacing"] = dx
    s["domain"] = {"min": [-4 * dx, -4 * dx], "max": [L + 4 * dx, 3 * H]}
    s["bodies"][0]["min"], s["bodies"][0]["max"] = [0.0, 0.0], [2 * H, H]
    s["bodies"][1]["min"], s["bodies"][1]["max"] = [0.0, 0.0], [L, 2 * H]
    h, c0 = s["kernel"]["h_over_dx"] * dx, s["fluid"]["c0_factor"] * math.sqrt(2 * g * H)
    s["integrator"]["dt"] = round(0.73 * h / c0, 8)  # the scene's dt / (h / c0) at dx 5 mm
    s["time"]["end"] = round(8 / math.sqrt(g / H), 4)
    s["output"] = {"every": 0.05, "probes_every": 0.002}
    s["probes"] = [{"type": "front"}, {"type": "pressure", "name": "P1", "point": [L, 0.2 * H]}]
    return s, {"H": H, "wall": L, "g": g, "dx": dx}


def square_scene(dx, c0):
    """Square column 0.145 m in a 0.58 m tank with dam_break_2d_dsph_val.json's physics."""
    s = json.load(open(os.path.join(vc.ROOT, "pipelines", "dam_break_2d_dsph_val.json")))
    H, L = 0.145, 0.58
    s["name"] = f"square_{int(round(dx * 1e4))}"
    s["particles"]["spacing"] = dx
    s["domain"] = {"min": [-0.05, -0.05], "max": [L + 0.05, 0.7]}
    s["bodies"][0]["min"], s["bodies"][0]["max"] = [0.0, 0.0], [H, H]
    s["bodies"][1]["min"], s["bodies"][1]["max"] = [0.0, 0.0], [L, 0.6]
    s["fluid"]["c0"] = c0
    s["time"]["end"] = 1.0
    s["output"] = {"every": 0.01, "probes_every": 0.001}
    s["probes"] = [{"type": "front"}]
    return s, {"H": H, "wall": L, "g": -s["gravity"][1], "dx": dx}


def mm_wendland_wall_scene():
    """dam_break_mm_wendland.json unchanged but run on through the far-wall impact to t = 1 s."""
    s = json.load(open(os.path.join(vc.HERE, "dam_break_mm_wendland.json")))
    s["time"]["end"] = 1.0
    s["output"] = {"every": 0.02, "probes_every": 0.001}
    return s, {"H": 0.29, "wall": s["bodies"][1]["max"][0], "g": -s["gravity"][1], "dx": s["particles"]["spacing"]}


def buchner2002_mmw_scene():
    """buchner_2002.json with the method blocks of dam_break_mm_wendland.json merged in by vsetup.py and
    dt = 0.73 h/c0: the Buchner row of pipelines/work_precision.py that stopped with exit 3 at t = 0.93-1.10 s."""
    import vsetup
    out = os.path.join(vc.ROOT, "runs", "survive_scenes", "buchner2002_mmw.json")
    path = vsetup.scene_with_setup(os.path.join(vc.HERE, "buchner_2002.json"),
                                   os.path.join(vc.HERE, "dam_break_mm_wendland.json"), out)
    s = json.load(open(path))
    s["integrator"] = {"type": "verlet", "dt": round(0.73 * vc.h_over_c0(path), 10)}
    s["output"] = {"every": 0.05, "probes_every": 0.002}
    return s, {"H": H_B, "wall": s["bodies"][1]["max"][0], "g": -s["gravity"][1], "dx": s["particles"]["spacing"]}


def buchner2002_scene():
    """pipelines/validation/buchner_2002.json unchanged but for the output cadence (probes every 2 ms)."""
    s = json.load(open(os.path.join(vc.HERE, "buchner_2002.json")))
    s["output"] = {"every": 0.05, "probes_every": 0.002}
    return s, {"H": H_B, "wall": s["bodies"][1]["max"][0], "g": -s["gravity"][1], "dx": s["particles"]["spacing"]}


CASES = {
    "mm_wendland_wall": mm_wendland_wall_scene,
    "buchner2002": buchner2002_scene,
    "buchner2002_mmw": buchner2002_mmw_scene,
    "buchner25": lambda: buchner_scene(25),
    "buchner50": lambda: buchner_scene(50),
    "square50": lambda: square_scene(0.005, "auto"),
    "square25": lambda: square_scene(0.0025, "auto"),
    "square50_c88": lambda: square_scene(0.005, 88.4),
    "square25_c88": lambda: square_scene(0.0025, 88.4),
}


def buchner_p1_error(probes, H, g):
    """RMS of P_sim - P_exp over the digitised points with T >= 2, and the first-impact maxima (T < 3)."""
    ref = vc.reference("buchner_2002_wall_pressure_p1.csv")
    order = np.argsort(ref["T"])
    Te, Pe = ref["T"][order], ref["P"][order]
    T = probes["time"] * math.sqrt(g / H)
    P = probes["p_P1"] / (1000.0 * g * H)
    sel = (Te >= 2) & (Te <= T[-1])
    rms = float(np.sqrt(np.mean((np.interp(Te[sel], T, P) - Pe[sel]) ** 2))) if sel.any() else float("nan")
    first = (T >= 2) & (T < 3)
    return rms, float(P[first].max()) if first.any() else float("nan"), float(Pe[(Te >= 2) & (Te < 3)].max())


def summarise(case, rules, r, geo):
    out = {"case": case, "rules": rules, "rc": r.rc, "load": round(0.5 * (r.load_before + r.load_after), 1)}
    diag = r.table("diagnostics.csv")
    t = diag.get("time", np.array([0.0]))
    out["t_end"] = float(t[-1]) if len(t) else 0.0
    out["steps"] = int(diag["step"][-1]) if "step" in diag and len(diag["step"]) else 0
    out["wall_s"] = round(r.solver_wall, 1)
    h = r.runjson.get("health", {})
    rem = h.get("removed", {})
    out["fluid0"] = h.get("fluid_particles_initial", "")
    for k in ("domain", "density", "speed"):
        out["removed_" + k] = rem.get(k, 0)
    scale = 2 * math.sqrt(geo["g"] * geo["H"])
    vmax = float(np.nanmax(diag["max_speed"])) if "max_speed" in diag else float("nan")
    out["max_speed"] = vmax
    out["max_speed_over_2sqrt_gH"] = vmax / scale
    out["max_density_error"] = float(np.nanmax(diag["density_error_max"])) if "density_error_max" in diag else float("nan")
    e = diag["kinetic_energy"] + diag["potential_energy"] + diag["internal_energy"]
    out["energy_end_over_start"] = float(e[-1] / e[0]) if len(e) > 1 else float("nan")
    probes = r.table("probes.csv")
    front = next((k for k in probes if k.startswith("front_x")), None)
    if front:
        hit = np.nonzero(probes[front] >= geo["wall"] - geo["dx"])[0]
        out["front_at_wall_t"] = float(probes["time"][hit[0]]) if len(hit) else float("nan")
        out["front_at_wall_T"] = out["front_at_wall_t"] * math.sqrt(geo["g"] / geo["H"])
    if "p_P1" in probes:
        rms, pmax, pexp = buchner_p1_error(probes, geo["H"], geo["g"])
        out["P1_rms_T2"] = rms
        out["P1_first_max"] = pmax
        out["P1_first_max_exp"] = pexp
    removed = r.table("removed.csv") if os.path.exists(os.path.join(r.dir, "removed.csv")) else {}
    if "time" in removed and len(removed["time"]):
        tr = removed["time"]
        out["removed_first_t"], out["removed_last_t"] = float(tr.min()), float(tr.max())
        out["removed_first_T"] = out["removed_first_t"] * math.sqrt(geo["g"] / geo["H"])
        out["removed_median_fluid_neighbours"] = float(np.median(removed["fluid_neighbours"]))
        out["removed_at_t"] = " ".join(f"{v:.3f}" for v in removed["time"][:6])
        out["removed_fluid_neighbours"] = " ".join(str(int(v)) for v in removed["fluid_neighbours"][:6])
        out["removed_rho"] = " ".join(f"{v:.0f}" for v in removed["density"][:6])
    out["message"] = r.message()[:300] if r.rc else ""
    return out


def plot(rows, outdir, runs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.2))
    ref = vc.reference("buchner_2002_wall_pressure_p1.csv")
    ax[0].plot(ref["T"], ref["P"], "k.", ms=3, label="Buchner (2002), P1")
    for (case, rules), d in runs.items():
        pr = vc.read_csv(os.path.join(d, "probes.csv"))
        geo = CASES[case]()[1]
        if case.startswith("buchner") and "p_P1" in pr:
            ax[0].plot(pr["time"] * math.sqrt(geo["g"] / geo["H"]), pr["p_P1"] / (1000 * geo["g"] * geo["H"]),
                       lw=0.8, label=f"{case} ({rules} rules)")
        front = next((k for k in pr if k.startswith("front_x")), None)
        if case.startswith("square") and front:
            ax[1].plot(pr["time"], pr[front] / geo["H"], lw=0.9, label=f"{case} ({rules} rules)")
    ax[0].set_xlabel("T = t sqrt(g/H)")
    ax[0].set_ylabel("P1 = p / (rho g H)")
    ax[0].set_xlim(0, 8)
    ax[0].legend(fontsize=7)
    ax[1].set_xlabel("t [s]")
    ax[1].set_ylabel("front x / a (a = 0.145 m; far wall at 4)")
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(outdir, "survive.png")
    fig.savefig(path, dpi=110)
    print("wrote", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default="mm_wendland_wall,buchner2002_mmw,buchner50,square50,square50_c88,buchner2002")
    ap.add_argument("--rules", default="stop,default", help="stop (strict), default (remove and count)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--t-end", type=float, default=None, help="stop every case at this time [s] (default: the case's)")
    ap.add_argument("--plot", action="store_true")
    ap.add_argument("-o", "--outdir", default=os.path.join(vc.ROOT, "runs", "survive"))
    a = ap.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    rows, runs = [], {}
    for case in a.cases.split(","):
        scene, geo = CASES[case]()
        if a.t_end is not None:
            scene["time"]["end"] = a.t_end
        path = os.path.join(a.outdir, case + ".json")
        with open(path, "w") as f:
            json.dump(scene, f, indent=1)
        for rules in a.rules.split(","):
            # "stop": the behaviour before the health rules (exit 3 on NaN, a particle leaving the domain or
            # |rho/rho0 - 1| > 0.5; no speed or energy rule), as stability.py's bisection uses it
            sets = {"health.on_violation": "stop", "health.max_density_error": 0.5, "health.max_mach": 1e6,
                    "health.max_energy_growth": 0} if rules == "stop" else {}
            out = os.path.join(a.outdir, f"{case}_{rules}")
            r = vc.run(path, out, sets, threads=a.threads)
            row = summarise(case, rules, r, geo)
            rows.append(row)
            runs[(case, rules)] = out
            print(json.dumps(row), flush=True)
            vc.write_csv(os.path.join(a.outdir, "survive.csv"), rows, fields=list(dict.fromkeys(
                k for rr in rows for k in rr)))
    if a.plot:
        plot(rows, a.outdir, runs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
