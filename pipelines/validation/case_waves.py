#!/usr/bin/env python3
"""Waves in a flume (issue 31, docs/validation.md "Waves in a flume"): generated wave height and period against
linear theory, decay along the flume, reflection with the damping zone, mass and paddle leaks.

    pvpython pipelines/validation/case_waves.py [--paddle piston|flap] [--per-height 10] [--kh 1.5] [--periods 10]
        [--depth 0.2] [--h-over-dx 1.414] [--ramp-periods 2] [--zone-at 2.1]
        [--no-damping] [--awas shallow|linear] [--threads 2] [-o DIR | --rundir DIR] [--check-height 0.05] [--check-period 0.01]
        [--check-decay 0.05] [--check-kr 0.10]

The flume is written by pipelines/waves/make_flume.py (h = 0.2 m, H = 0.04 m, the given kh and resolution H/dx)
into the folder above DIR (NAME.json) and run into DIR; --rundir analyses a finished run of such a scene (its run.json).

The scene's paddle motion gives H, T and the depth h; its gauges (water_height probes named gNNN at NNN/100
wavelengths from the paddle) give the surface elevation eta = h_gNNN - h. Metrics:
  H_g, T_g   mean zero up-crossing height and period at each gauge (paraview/wave_analysis.py) over the window from
             the arrival of the ramped-up waves (ramp + x / cg + 2 T; --margin sets the 2) to the first return of waves
             reflected by the far wall (ramp + (2 x_wall - x) / cg), or the run's end (--until-end: the run's end); err_H = H_g / H - 1, err_T = T_g / T - 1 at the
             gauges one to two wavelengths from the paddle
  decay      H at the farthest gauge in front of the damping zone over H at 1 L (the same window length)
  Kr         Goda & Suzuki (1976) on the gauges 1.25 L and 1.5 L (k dl = pi / 2) after the reflected waves returned
             (only when the run is long enough)
  mass       fluid particles at the end / at the start (all have the same mass) and particles removed
  leaks      fluid particles found behind the paddle in any frame (x < the paddle's face)
Exit 1 when a --check fails; the figures are printed and written to DIR/post/case_waves.csv.
"""
import argparse
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "..", "paraview"))
sys.path.insert(0, os.path.join(HERE, "..", "waves"))
import make_flume  # noqa: E402
import vcommon as vc  # noqa: E402
import wave_analysis as wa  # noqa: E402


def paddle_of(scene):
    for i, b in enumerate(scene["bodies"]):
        m = b.get("motion")
        if isinstance(m, dict) and m.get("type") in ("piston", "flap"):
            return i, b, m
    raise SystemExit("case_waves: the scene has no piston or flap")


def leaks(rundir, paddle_body, dx):
    """Fluid particles behind the paddle in any frame: a fluid particle at height y is behind when its x is below
    the paddle particles' largest x among those within dx of y (a piston's face, or the tilted flap's line)."""
    try:
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
        from vtkmodules.util.numpy_support import vtk_to_numpy
    except ImportError:
        return -1
    fr = os.path.join(rundir, "frames")
    worst = 0
    for name in sorted(f for f in os.listdir(fr) if f.endswith(".vtu")):
        r = vtkXMLUnstructuredGridReader()
        r.SetFileName(os.path.join(fr, name))
        r.Update()
        g = r.GetOutput()
        x = vtk_to_numpy(g.GetPoints().GetData())
        kind = vtk_to_numpy(g.GetPointData().GetArray("kind"))
        body = vtk_to_numpy(g.GetPointData().GetArray("body"))
        pad = x[body == paddle_body]
        if not len(pad):
            continue
        xf = x[kind == 0]
        near = xf[(xf[:, 1] >= pad[:, 1].min()) & (xf[:, 1] <= pad[:, 1].max()) & (xf[:, 0] < pad[:, 0].max() + dx)]
        behind = 0
        for p in near:
            band = pad[np.abs(pad[:, 1] - p[1]) <= dx]
            if len(band) and p[0] < band[:, 0].max():
                behind += 1
        worst = max(worst, behind)
    return worst


def main(argv):
    ap = argparse.ArgumentParser()
    ap.add_argument("--paddle", choices=("piston", "flap"), default="piston")
    ap.add_argument("--per-height", type=float, default=10, help="particles per wave height H/dx")
    ap.add_argument("--kh", type=float, default=1.5)
    ap.add_argument("--height", type=float, default=0.04)
    ap.add_argument("--depth", type=float, default=0.2, help="still-water depth h (m)")
    ap.add_argument("--h-over-dx", type=float, default=1.414, help="kernel.h_over_dx (above 1.5: walls of 4 layers)")
    ap.add_argument("--ramp-periods", type=float, default=2.0, help="the paddle's ramp in periods")
    ap.add_argument("--zone-at", type=float, default=2.1, help="the damping zone's start in wavelengths")
    ap.add_argument("--periods", type=float, default=10)
    ap.add_argument("--no-damping", action="store_true")
    ap.add_argument("--awas", default=None, metavar="GAIN", choices=("shallow", "linear"),
                    help="active absorption at the paddle with this gain (motion.awas, docs/waves.md)")
    ap.add_argument("--margin", type=float, default=2.0,
                    help="periods after the ramped waves' arrival before a gauge's window opens (2; 1 is enough for the "
                         "nearly non-dispersive front of long waves, kh 0.5: cg / c = 0.93)")
    ap.add_argument("--until-end", action="store_true",
                    help="windows close at the run's end, not at the return of waves reflected by the far wall "
                         "(a damping zone in front of the wall damps them on the way in and out; say so when used)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("-o", dest="out", default=None)
    ap.add_argument("--rundir", default=None, help="analyse this finished run instead of running")
    ap.add_argument("--check-height", type=float, default=None)
    ap.add_argument("--check-period", type=float, default=None)
    ap.add_argument("--check-decay", type=float, default=None)
    ap.add_argument("--check-kr", type=float, default=None)
    a = ap.parse_args(argv)
    if a.rundir:
        with open(os.path.join(a.rundir, "run.json")) as f:
            scene = json.load(f)["scene"]
    else:
        name = "waves_%s_kh%g_H%g%s" % (a.paddle, a.kh, a.per_height, "_awas" if a.awas else "")
        if a.depth != 0.2 or a.h_over_dx != 1.414:
            name += "_d%g_hdx%g" % (a.depth, a.h_over_dx)
        scene = make_flume.flume(name, a.paddle, a.depth, a.height, a.kh, a.per_height, a.periods,
                                 damping=not a.no_damping, awas=None if a.awas is None else {"gain": a.awas},
                                 h_over_dx=a.h_over_dx, ramp_periods=a.ramp_periods, zone_at=a.zone_at)
    pb, body, m = paddle_of(scene)
    h = max(b["max"][1] for b in scene["bodies"] if b["kind"] == "fluid")
    H, T = m["height"], m["period"]
    ramp = m.get("ramp", 2 * T)
    omega = 2 * math.pi / T
    k = wa.wave_number(omega, h)
    L = 2 * math.pi / k
    kh = k * h
    cg = 0.5 * (1 + 2 * kh / math.sinh(2 * kh)) * omega / k
    dx = scene["particles"]["spacing"]
    rundir = a.rundir
    if rundir is None:
        rundir = a.out or os.path.join(vc.ROOT, "runs", "case_waves_" + scene["name"])
        os.makedirs(rundir, exist_ok=True)
        path = os.path.join(os.path.dirname(os.path.abspath(rundir)), scene["name"] + ".json")
        with open(path, "w") as f:
            json.dump(scene, f, indent=1)
        res = vc.run(path, rundir, threads=a.threads)
        if res.rc != 0:
            print(res.stderr[-2000:], file=sys.stderr)
            return 1
    with open(os.path.join(rundir, "run.json")) as f:
        runjson = json.load(f)
    cols = wa.read_probes(os.path.join(rundir, "probes.csv"))
    t = cols["time"]
    t_end = float(t[-1])
    x_wall = max(b["min"][0] for b in scene["bodies"] if b["kind"] == "boundary" and b is not body)
    zone = scene.get("physics", {}).get("damping_zone")
    x_zone = zone["from"][0] if zone else x_wall
    gauges = []
    for p in scene.get("probes", []):
        if p["type"] == "water_height":
            gauges.append((p["name"], p["from"][0]))
    rows = []
    print("linear theory: h %g m, H %g m, T %.5f s, kh %.4f, L %.5f m, cg %.4f m/s; dx %g m (H/dx %.1f)" %
          (h, H, T, kh, L, cg, dx, H / dx))
    window = {}
    for name, x in gauges:
        t0 = ramp + x / cg + a.margin * T
        t1 = t_end if a.until_end else min(t_end, ramp + (2 * x_wall - x) / cg)
        sel = (t >= t0) & (t <= t1)
        if sel.sum() < 10 or t1 - t0 < 1.5 * T:
            print("%-6s x = %.3f m (%.2f L): window %.2f .. %.2f s too short" % (name, x, x / L, t0, t1))
            continue
        s = wa.statistics(t[sel], cols["h_" + name][sel] - h)
        window[name] = (t0, t1)
        row = {"gauge": name, "x_over_L": x / L, "t0": t0, "t1": t1, "waves": s["waves"], "H": s["H_mean"],
               "T": s["T_mean"], "err_H": s["H_mean"] / H - 1, "err_T": s["T_mean"] / T - 1, "in_zone": x >= x_zone}
        rows.append(row)
        print("%-6s x = %.3f m (%.2f L)%s: window %.2f .. %.2f s, %d waves, H %.5f m (%+.1f %%), T %.5f s (%+.2f %%)" %
              (name, x, x / L, " [damping zone]" if x >= x_zone else "", t0, t1, s["waves"], s["H_mean"],
               100 * row["err_H"], s["T_mean"], 100 * row["err_T"]))
    ok = True
    core = [r for r in rows if 0.99 <= r["x_over_L"] <= 2.01 and not r["in_zone"] and r["waves"] >= 1]
    if core:
        eh = max(abs(r["err_H"]) for r in core)
        et = max(abs(r["err_T"]) for r in core)
        print("height error max %.1f %%, period error max %.2f %% (gauges 1-2 L in front of the zone)" % (100 * eh, 100 * et))
        if a.check_height is not None and not eh <= a.check_height:
            print("FAIL height error %.3f > %.3f" % (eh, a.check_height))
            ok = False
        if a.check_period is not None and not et <= a.check_period:
            print("FAIL period error %.4f > %.4f" % (et, a.check_period))
            ok = False
        far = max(core, key=lambda r: r["x_over_L"])
        near = min(core, key=lambda r: r["x_over_L"])
        if far is not near:
            decay = 1 - far["H"] / near["H"]
            print("decay from %.2f L to %.2f L: %.1f %% (%.2f %% per wavelength)" %
                  (near["x_over_L"], far["x_over_L"], 100 * decay, 100 * decay / (far["x_over_L"] - near["x_over_L"])))
            if a.check_decay is not None and not decay <= a.check_decay:
                print("FAIL decay %.3f > %.3f" % (decay, a.check_decay))
                ok = False
    elif a.check_height is not None:
        print("FAIL no gauge 1-2 L from the paddle had a full window")
        ok = False
    # reflection: after the reflected waves are back at the pair
    names = dict(gauges)
    if "g125" in names and "g150" in names:
        t0 = ramp + (2 * x_wall - names["g125"]) / cg + 2 * T
        sel = t >= t0
        if t_end - t0 >= 3 * T:
            n = int(math.floor((t_end - t0) / T))  # whole periods from the end
            sel = t >= t_end - n * T
            r = wa.goda_suzuki(t[sel], cols["h_g125"][sel] - h, cols["h_g150"][sel] - h, names["g150"] - names["g125"], h,
                               band=(0.5 / T, 1.5 / T))
            print("reflection (Goda & Suzuki, g125/g150, %.2f .. %.2f s, %d periods): H_I %.5f m, H_R %.5f m, Kr %.3f" %
                  (t_end - n * T, t_end, n, r["H_I"], r["H_R"], r["Kr"]))
            rows.append({"gauge": "g125+g150", "H": r["H_I"], "Kr": r["Kr"]})
            if a.check_kr is not None and not r["Kr"] <= a.check_kr:
                print("FAIL Kr %.3f > %.3f" % (r["Kr"], a.check_kr))
                ok = False
        else:
            print("reflection: the run ends %.2f s after the reflected waves reach g125 (needs 3 T = %.2f s)" %
                  (t_end - t0, 3 * T))
            if a.check_kr is not None:
                print("FAIL no reflection window")
                ok = False
    d = vc.read_csv(os.path.join(rundir, "diagnostics.csv"))
    n0, n1 = d["fluid_particles"][0], d["fluid_particles"][-1]
    removed = d["removed_domain"][-1] + d["removed_density"][-1] + d["removed_speed"][-1]
    print("fluid particles %d -> %d (mass kept to round-off: all particles have the same mass), removed %d" %
          (n0, n1, removed))
    if n1 != n0:
        ok = False
        print("FAIL fluid particles lost")
    lk = leaks(rundir, pb, dx)
    print("fluid particles behind the paddle in any frame: %s" % (lk if lk >= 0 else "not checked (no vtk)"))
    if lk > 0:
        ok = False
        print("FAIL particles leaked through the paddle")
    timings = runjson.get("timings", {})
    if timings:
        print("cost: %s steps, %.1f s wall, %.3g fluid particle-steps/s" % (timings.get("steps"), timings.get("wall_seconds", 0),
                                                                           timings.get("fluid_particle_steps_per_second", 0)))
    os.makedirs(os.path.join(rundir, "post"), exist_ok=True)
    vc.write_csv(os.path.join(rundir, "post", "case_waves.csv"), rows)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
