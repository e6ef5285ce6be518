#!/usr/bin/env python3
"""SPHERIC Test 2 / Kleefsman et al. (2005): 3D dam break against a box, with the experiment's gauges.

Scene spheric2_kleefsman.json (the geometry of pipelines/dam_break_3d_spheric2.json, water column
1.228 x 1 x 0.55 m against the wall x = 3.22 m, box x in [0.6635, 0.8245] m on the floor). Reference data:
  tests/data/validation/spheric2_kleefsman2005_pressure_pysph.csv  P1 (z = 0.021 m) and P3 (z = 0.101 m) on the
      box's front face, P = p / (rho g H), T = t sqrt(g/H), H = 0.55 m (digitised from Kleefsman 2005 Fig. 17)
  tests/data/validation/spheric2_kleefsman2005_heights_lethe.csv   water heights at x = 1.488, 0.992, 0.496
      (behind the box) and 2.638 m (in the reservoir), MARIN measurements every 10 ms, t <= 1.68 s
A mesh's first boundary layer sits on its surface (docs/geometry.md), so for the walls the fluid sees to be
the experiment's, this script maps the tank mesh outward and the box mesh inward by dx/2 on every side
(`transform` matrices; the box's bottom face then sits dx above the floor's first layer instead of on it).
The pressure sensors are probes.0 (P1) and probes.1 (P3) on the box's front face x = 0.8245 m.

Metrics, per pressure sensor S in (P1, P3), in P units (rho g H = 5395.5 Pa):
  S_arrival_t      first t where p > 0.2 rho g H (linear interpolation), sim and data [s]
  S_peak           max P for 0.3 <= t <= 0.8 s, sim and data
  S_mean           time mean of P over 0.40 <= t <= 0.90 s (the half second after the impact), sim and data,
                   and S_mean_rel = sim / data - 1
  S_rms            RMS of P_sim - P_i over the digitised points with 0.3 s <= t_i <= t_end
per height gauge G: G_rms_H = RMS over the 10 ms samples (t <= t_end) of (h_sim - h_data) / H, and
G_arrival_t (first t where h > 0.02 m) sim and data; the force on the box (no reference) is reported, and as
force_P_mean its time mean over 0.40-0.90 s as a face-mean pressure -Fx / (A rho g H), A = 0.161 x 0.403 m^2 (a
check of the sensors that does not depend on the probe definition; P1 and P3 bracket the face's lower half).
Goals (setup_matrix.py and --check; my engineering bounds, docs/validation.md sections 12 and 14): P1 arrival within 0.05 s,
P1 mean over the half second within 20 %, heights at x = 0.992 and 2.638 m within 0.1 H RMS.

  /usr/bin/python3 pipelines/validation/case_spheric2.py [--dx 0.05] [--t-end 1.5] [--scene FILE] [--setup FILE]
      [--set K=V]... [--threads 2] [-o DIR] [--png FILE] [--check]
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

SCENE = os.path.join(vc.HERE, "spheric2_kleefsman.json")
P_REF, H_REF = "spheric2_kleefsman2005_pressure_pysph.csv", "spheric2_kleefsman2005_heights_lethe.csv"
H, G, RHO0 = 0.55, 9.81, 1000.0
DX, T_END = 0.05, 1.5
FACE_AREA = 0.161 * 0.403
FACE_X, SENSORS = 0.8245, {"P1": (0.471, 0.021, 1), "P3": (0.471, 0.101, 3)}  # y, z, data column
GAUGES = ("x1488", "x0992", "x0496", "x2638")
ARRIVAL_P, PEAK_WIN, MEAN_WIN, RMS_T0, ARRIVAL_H = 0.2, (0.3, 0.8), (0.40, 0.90), 0.3, 0.02
GOALS = {"P1_arrival_dt": 0.05, "P1_mean_rel": 0.20, "x0992_rms_H": 0.10, "x2638_rms_H": 0.10}


def tscale():
    return math.sqrt(G / H)


def first_crossing(t, y, level):
    idx = np.nonzero(y > level)[0]
    if len(idx) == 0:
        return float("nan")
    k = idx[0]
    if k == 0:
        return float(t[0])
    return float(t[k - 1] + (level - y[k - 1]) / (y[k] - y[k - 1]) * (t[k] - t[k - 1]))


def window_mean(t, y, a, b, n=2001):
    if t[0] > a or t[-1] < b:
        return float("nan")
    g = np.linspace(a, b, n)
    return float(np.mean(np.interp(g, t, y)))


def pressure_data(sensor):
    r = vc.reference(P_REF)
    sel = r["sensor"] == SENSORS[sensor][2]
    return r["T"][sel] / tscale(), r["P"][sel]


TANK = ((0.0, 3.22), (0.0, 1.0), (0.0, 1.0))
BOX = ((0.6635, 0.8245), (0.2985, 0.7015), (0.0, 0.161))


def affine(src, dst):
    """Row-major 4 x 4 matrix mapping the axis intervals src[a] onto dst[a]."""
    m = [0.0] * 16
    for a, ((s0, s1), (d0, d1)) in enumerate(zip(src, dst)):
        scale = (d1 - d0) / (s1 - s0)
        m[5 * a] = scale
        m[4 * a + 3] = d0 - scale * s0
    m[15] = 1.0
    return m


def geometry_sets(dx):
    """Tank mesh out and box mesh in by dx/2 (the fluid-side surfaces at the experiment's walls; the box's
    bottom face up by dx/2 too, dx above the floor's first layer), sensors on the box's front face."""
    h = 0.5 * dx
    tank = [(a - h, b + h) for a, b in TANK]
    box = [(a + h, b - h) for a, b in BOX[:2]] + [(BOX[2][0] + h, BOX[2][1] - h)]
    s = {"bodies.1.transform": {"matrix": affine(TANK, tank)}, "bodies.2.transform": {"matrix": affine(BOX, box)}}
    s.update({f"probes.{k}.point": [FACE_X, y, z] for k, (y, z, _) in enumerate(SENSORS.values())})
    return s


def evaluate(rundir, t_end):
    p = vc.read_csv(os.path.join(rundir, "probes.csv"))
    t = p["time"]
    m, series = {}, {"t": t}
    for s in SENSORS:
        P = p[f"p_{s}"] / (RHO0 * G * H)
        td, Pd = pressure_data(s)
        series[s] = P
        m[f"{s}_arrival_t"], m[f"{s}_arrival_t_data"] = first_crossing(t, P, ARRIVAL_P), first_crossing(td, Pd, ARRIVAL_P)
        m[f"{s}_arrival_dt"] = m[f"{s}_arrival_t"] - m[f"{s}_arrival_t_data"]
        for name, (tt, yy) in (("", (t, P)), ("_data", (td, Pd))):
            w = (tt >= PEAK_WIN[0]) & (tt <= PEAK_WIN[1])
            m[f"{s}_peak{name}"] = float(yy[w].max()) if w.any() else float("nan")
            m[f"{s}_mean{name}"] = window_mean(tt, yy, *MEAN_WIN)
        m[f"{s}_mean_rel"] = m[f"{s}_mean"] / m[f"{s}_mean_data"] - 1.0
        sel = (td >= RMS_T0) & (td <= min(t_end, t[-1]))
        m[f"{s}_rms"] = float(np.sqrt(np.mean((np.interp(td[sel], t, P) - Pd[sel]) ** 2))) if sel.any() else float("nan")
    hr = vc.reference(H_REF)
    for g in GAUGES:
        h = p[f"h_{g}"]
        series[g] = h
        sel = hr["t"] <= min(t_end, t[-1])
        hd = hr[f"h_{g}"][sel]
        m[f"{g}_rms_H"] = float(np.sqrt(np.mean((np.interp(hr["t"][sel], t, h) - hd) ** 2)) / H)
        if g != "x2638":
            m[f"{g}_arrival_t"] = first_crossing(t, h, ARRIVAL_H)
            m[f"{g}_arrival_t_data"] = first_crossing(hr["t"], hr[f"h_{g}"], ARRIVAL_H)
    fx = p["Fx_obstacle"]
    series["Fx"] = fx
    m["force_P_mean"] = window_mean(t, -fx / (FACE_AREA * RHO0 * G * H), *MEAN_WIN)
    m["force_x_min"] = float(fx.min())
    m["force_x_min_t"] = float(t[int(np.argmin(fx))])
    m["error"] = abs(m["P1_mean_rel"])
    return m, series


def plot(series, res, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    hr = vc.reference(H_REF)
    t = series["t"]
    fig, axes = plt.subplots(2, 3, figsize=(13, 6.5))
    for ax, s in zip(axes[0][:2], SENSORS):
        td, Pd = pressure_data(s)
        ax.plot(t, series[s], lw=0.7, label="varsph")
        ax.plot(td, Pd, "ko-", ms=3, lw=0.8, label="Kleefsman 2005 (digitised, PySPH)")
        ax.axvspan(*MEAN_WIN, color="0.92", zorder=0)
        ax.set_xlim(0, max(t[-1], 1.0))
        ax.set_ylim(-0.5, 3.0)
        ax.set_title(f"{s}: mean 0.4-0.9 s {res.get(s + '_mean', float('nan')):.2f} (data "
                     f"{res.get(s + '_mean_data', float('nan')):.2f}), arrival {res.get(s + '_arrival_t', float('nan')):.3f} s "
                     f"(data {res.get(s + '_arrival_t_data', float('nan')):.3f})", fontsize=8)
        ax.set_ylabel("P = p / (rho g H)")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    axes[0][2].plot(t, series["Fx"], lw=0.7)
    axes[0][2].set_title("force on the box, Fx [N] (no reference)", fontsize=8)
    axes[0][2].grid(alpha=0.3)
    for ax, g in zip(axes[1], ("x1488", "x0992", "x2638")):
        ax.plot(t, series[g], lw=0.8, label="varsph")
        ax.plot(hr["t"], hr[f"h_{g}"], "k", lw=0.8, label="MARIN (SPHERIC Test 2)")
        ax.set_title(f"height at x = {int(g[1:]) / 1000:.3f} m: RMS {res.get(g + '_rms_H', float('nan')):.3f} H",
                     fontsize=8)
        ax.set_xlabel("t [s]")
        ax.set_ylabel("h [m]")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def run_case(dx=DX, sets=None, threads=2, outdir=None, scene=SCENE, setup=None, t_end=T_END, png=None,
             timeout=None):
    outdir = outdir or os.path.join(vc.ROOT, "runs", "validation", f"spheric2_dx{dx:g}")
    if setup:
        scene = vsetup.scene_with_setup(scene, setup, os.path.abspath(outdir).rstrip("/") + "_scene.json")
    s = {"particles.spacing": dx, "time.end": t_end}
    s.update(geometry_sets(dx))
    s.update(sets or {})
    r = vc.run(scene, outdir, s, threads, timeout=timeout)
    res = {"rc": r.rc, "wall": r.solver_wall, "steps": r.steps, "psps": r.psps, "load": r.load_before,
           "load_after": r.load_after, "dx": dx, "message": r.message() if r.rc else ""}
    if os.path.exists(os.path.join(outdir, "probes.csv")):
        m, series = evaluate(outdir, t_end)
        res.update(m)
        res["t_reached"] = float(series["t"][-1])
        if png is not False:
            plot(series, res, png or os.path.join(outdir, "spheric2.png"))
    if r.rc != 0:
        res["error"] = float("nan")
    return res


def matrix_rows(r, row):
    """setup_matrix.py rows for this case (row: setup_matrix.row)."""
    rows = [row("spheric2", "3D run survives", r["rc"], ("eq", 0), res=r,
                note=(f"stopped at t = {r.get('t_reached', float('nan')):.3f} s: " + r["message"][:100]) if r["rc"]
                else f"dx {r['dx']:g}")]
    if "P1_mean_rel" not in r:
        return rows
    return rows + [
        row("spheric2", "P1 arrival t - data [s]", r["P1_arrival_dt"], ("<=", 0.05), res=r, fmt="{:+.3f}",
            note=f"data {r['P1_arrival_t_data']:.3f} s"),
        row("spheric2", "P1 mean 0.4-0.9 s / data - 1", r["P1_mean_rel"], ("<=", 0.20), res=r, fmt="{:+.1%}",
            note=f"P {r['P1_mean']:.2f} vs {r['P1_mean_data']:.2f}; peak {r['P1_peak']:.2f} vs {r['P1_peak_data']:.2f}"),
        row("spheric2", "P3 mean 0.4-0.9 s / data - 1", r["P3_mean_rel"], None, res=r, fmt="{:+.1%}", note="info"),
        row("spheric2", "face-mean P from the force, 0.4-0.9 s", r["force_P_mean"], None, res=r, fmt="{:.2f}",
            note=f"info: data P1 / P3 means {r['P1_mean_data']:.2f} / {r['P3_mean_data']:.2f}"),
        row("spheric2", "height x = 0.992 m, RMS / H", r["x0992_rms_H"], ("<=", 0.10), res=r, fmt="{:.3f}"),
        row("spheric2", "height x = 2.638 m, RMS / H", r["x2638_rms_H"], ("<=", 0.10), res=r, fmt="{:.3f}",
            note="in the reservoir"),
        row("spheric2", "height x = 1.488 m, RMS / H", r["x1488_rms_H"], None, res=r, fmt="{:.3f}", note="info"),
    ]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, default=DX)
    ap.add_argument("--t-end", type=float, default=T_END)
    ap.add_argument("--scene", default=SCENE)
    ap.add_argument("--setup", help="scene file whose kernel/fluid/physics/boundary/integrator/health blocks are used")
    ap.add_argument("--set", action="append", default=[], help="KEY=VALUE passed to varsph run")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("-o", "--outdir")
    ap.add_argument("--png")
    ap.add_argument("--check", action="store_true", help="exit 1 unless the goals of GOALS are met")
    a = ap.parse_args()
    res = run_case(a.dx, dict(kv.split("=", 1) for kv in a.set), a.threads, a.outdir, a.scene, a.setup, a.t_end,
                   a.png)
    print(json.dumps(res, indent=1))
    if res["rc"] != 0:
        print(f"FAIL: varsph exited {res['rc']}: {res['message']}")
        return 1
    bad = [f"{k} {res[k]:+.3f} beyond {v}" for k, v in GOALS.items() if a.check and not abs(res[k]) <= v]
    if bad:
        print("FAIL: " + "; ".join(bad))
        return 1
    print("OK")
    return 0


if __name__ == "__main__":
    sys.exit(main())
