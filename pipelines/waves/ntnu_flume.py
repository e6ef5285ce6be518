#!/usr/bin/env python3
"""The NTNU wave flume of Sundsdal, Greco, Hanssen & Lugni (2025) (issue 31 point 4: a published flume with
measured gauges and a paddle signal; docs/validation.md section 20, "A published flume").

    /usr/bin/python3 pipelines/waves/ntnu_flume.py [--data tests/data/sundsdal2025_ntnu_flume_1142.csv]
        [--per-height 5] [--h-over-dx 1.7] [--gauges 1,2,3,4] [--waves 6] [--depth D] [--threads 1]
        [-o DIR | --rundir DIR | --write-scene DIR] [--check-height REL]
    /usr/bin/python3 pipelines/waves/ntnu_flume.py --theory-table SRC_1PPH_DIR

The flume (still water 1.0 m deep, a flap hinged 0.1 m above the bottom, probes 3.00-8.50 m from the paddle) is
driven by the measured paddle position of one test (WM_Position: the flap's displacement at the still-water level,
docs/validation.md section 20 says why), given to the solver as a paddle file (`waves: file`, docs/waves.md).
The waves of this test are deep-water waves (kh = 10 at 1.0 m), so the scene keeps only the top `--depth` of
the water (default half a wavelength: tanh(k d) = 0.996) with the flap's hinge 0.9 m below the still-water level,
i.e. below the scene's bed: the paddle face above the bed moves exactly as the real flap's. A damping zone one
wavelength long stands for the beach, 0.5 m beyond the farthest gauge kept.

Clock: the solver's t = 0 is 0.5 s before the paddle starts (the data's first |WM - WM(rest)| > 0.5 mm). Each
gauge's window runs from the arrival of the ramped-up waves (ramp 5 T, the source's, + x / cg + T) over
`--waves` periods, in both records. Metrics per gauge: mean zero up-crossing height and period (paraview/
wave_analysis.py) of the measured and the computed record, their ratio, the time lag of the computed record
(cross-correlation peak) and the RMS difference of the two records over the window divided by the measured height.

--theory-table reads the source's 1PPH/*.csv files (the repository KRSundsdal1/2D-ship-cross-section-in-regular-
waves) and prints, per test, the paddle's stroke, the heights measured at the probes and linear flap theory's
height for that stroke (the ratio that settles what WM_Position is).
Exit 1 when --check-height fails, 2 on bad arguments, 3 when the run fails.
"""
import argparse
import glob
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "validation"))
sys.path.insert(0, os.path.join(HERE, "..", "..", "paraview"))
import make_flume  # noqa: E402
import vcommon as vc  # noqa: E402
import wave_analysis as wa  # noqa: E402

DEPTH = 1.0          # the flume's still-water depth [m]
HINGE_DEPTH = 0.9    # the flap's hinge below the still-water level [m]
PROBES = {"WP_1": 3.00, "WP_2": 4.95, "WP_3": 5.20, "WP_4": 5.50, "WP_6": 8.50}  # [m] from the wavemaker
RAMP_PERIODS = 5     # the source's linear ramp-up
DATA = os.path.join(vc.ROOT, "tests", "data", "sundsdal2025_ntnu_flume_1142.csv")


def fail(msg, code=2):
    print("ntnu_flume: " + msg, file=sys.stderr)
    sys.exit(code)


def flap_hs(k, h, hinge_depth):
    """Linear flap theory H/S for a flap whose displacement is S/2 at the still-water level and zero at the hinge,
    hinge_depth below it (docs/waves.md "Transfer functions": the general paddle integral; the hinge may lie below
    the bed, where the profile is cut off)."""
    z = np.linspace(-h, 0.0, 20001)
    f = np.clip(1.0 + z / hinge_depth, 0.0, None)
    y = f * np.cosh(k * (h + z))
    integral = float(np.sum((y[1:] + y[:-1]) * np.diff(z)) / 2) * k
    return 4 * math.sinh(k * h) * integral / (math.sinh(2 * k * h) + 2 * k * h)


def read_data(path):
    names, rows = None, []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            if names is None:
                names = [c.split(" [")[0].strip() for c in line.strip().split(",")]
                continue
            rows.append([float(v) for v in line.split(",")])
    if names is None or not rows:
        fail("%s: no header or no data rows" % path)
    d = np.array(rows)
    for want in ("Time", "WM_Position"):
        if want not in names:
            fail("%s: no column '%s' (columns: %s)" % (path, want, ", ".join(names)))
    cols = {n: d[:, i] for i, n in enumerate(names)}
    if not np.all(np.diff(cols["Time"]) > 0):
        fail("%s: Time does not increase" % path)
    return cols


def paddle_start(t, wm, threshold=5e-4):
    """Rest level of the paddle (median of the first second) and the first time it leaves it by threshold."""
    rest = float(np.median(wm[t < t[0] + 1.0]))
    moved = np.nonzero(np.abs(wm - rest) > threshold)[0]
    if len(moved) == 0:
        fail("the paddle never moves by %g m" % threshold)
    return rest, float(t[moved[0]])


def dominant_period(t, x):
    _, periods = wa.zero_upcrossing(t, x)
    return float(np.median(periods))


def theory_table(src):
    files = sorted(glob.glob(os.path.join(src, "1*.csv")))
    if not files:
        fail("no 1PPH csv files in %s" % src)
    print("test  T [s]   kh   stroke S [mm]  H measured at WP_1..WP_6 [mm]             H theory [mm]  theory/measured(WP_1)")
    for path in files:
        d = np.genfromtxt(path, delimiter=",", skip_header=1)
        t, wm = d[:, 1], d[:, 2]
        rest, ts = paddle_start(t, wm)
        T = dominant_period(t[t > ts], wm[t > ts])
        k = wa.wave_number(2 * math.pi / T, DEPTH)
        s0 = ts + (RAMP_PERIODS + 1) * T
        sel = (t >= s0) & (t <= s0 + 6 * T)
        S = wa.statistics(t[sel], wm[sel])["H_mean"]
        cg = group_speed(k, DEPTH, T)
        heights = []
        for j, x in enumerate(PROBES.values()):
            w = (t >= ts + RAMP_PERIODS * T + x / cg + T) & (t <= ts + RAMP_PERIODS * T + x / cg + 7 * T)
            heights.append(wa.statistics(t[w], d[w, 3 + j])["H_mean"])
        Ht = flap_hs(k, DEPTH, HINGE_DEPTH) * S
        print("%s %6.3f %5.2f %9.1f      %s   %8.1f      %.3f" % (os.path.basename(path)[:-4], T, k * DEPTH, 1e3 * S,
              " ".join("%5.1f" % (1e3 * h) for h in heights), 1e3 * Ht, Ht / heights[0]))


def group_speed(k, h, T):
    kh = k * h
    return 0.5 * (1 + 2 * kh / math.sinh(2 * kh)) * (2 * math.pi / T) / k


def build_scene(a, cols, rundir):
    t, wm = cols["Time"], cols["WM_Position"]
    rest, ts = paddle_start(t, wm)
    shift = ts - 0.5
    T = dominant_period(t[t > ts], wm[t > ts])
    H = float(np.median([wa.statistics(*window(cols, name, x, ts, T, a.waves, DEPTH))["H_mean"]
                         for name, x in a.probe_list]))
    k_full = wa.wave_number(2 * math.pi / T, DEPTH)
    L = 2 * math.pi / k_full
    depth = a.depth if a.depth else L / 2
    # the paddle file: the solver's clock, the displacement from rest
    keep = t >= shift
    case = os.path.basename(a.data).rsplit("_", 1)[-1][:-4]  # the source's test number, e.g. 1142
    paddle = os.path.join(os.path.dirname(os.path.abspath(rundir)), "ntnu_paddle_%s.csv" % case)
    with open(paddle, "w") as f:
        f.write("# WM_Position of %s less its rest level %.9g m; time less %.9g s (docs/validation.md section 20)\n"
                % (os.path.basename(a.data), rest, shift))
        f.write("time,displacement\n")
        for ti, xi in zip(t[keep] - shift, wm[keep] - rest):
            f.write("%.6f,%.9g\n" % (ti, xi))
    x_last = max(x for _, x in a.probe_list)
    x_zone = x_last + 0.5
    end = 0.5 + RAMP_PERIODS * T + x_last / group_speed(k_full, DEPTH, T) + (a.waves + 2) * T
    k_t = wa.wave_number(2 * math.pi / T, depth)
    scene = make_flume.flume("ntnu_flume_%s" % a.tag, "flap", depth, H, k_t * depth, a.per_height, end / T,
                             h_over_dx=a.h_over_dx, zone_at=x_zone * k_t / (2 * math.pi), gauges=(), digits=12)
    dx = scene["particles"]["spacing"]
    m = scene["bodies"][3]["motion"]
    for key in ("height", "period", "ramp"):
        m.pop(key, None)
    m.update({"waves": "file", "file": os.path.basename(paddle), "hinge": [m["hinge"][0], round(depth - HINGE_DEPTH, 6)]})
    scene["time"]["end"] = round(end, 6)
    scene["output"] = {"every": round(T, 6), "probes_every": 0.01}
    scene["probes"] = [{"type": "water_height", "name": name, "from": [x, 0.0]} for name, x in a.probe_list]
    scene["description"] = (
        "The NTNU wave flume of Sundsdal et al. (2025) (docs/validation.md section 20): the measured paddle signal of %s "
        "drives a flap hinged %g m below the still-water level; the top %.4f m of the 1.0 m deep flume (tanh(k d) = %.4f), "
        "T = %.4f s, H = %.4f m measured, L = %.4f m; dx = %.5f m (H/dx %.1f); probes %s; a damping zone from x = %.3f m "
        "stands for the beach. Run by pipelines/waves/ntnu_flume.py." %
        (os.path.basename(a.data), HINGE_DEPTH, depth, math.tanh(k_full * depth), T, H, L, dx, H / dx,
         ", ".join("%s %.2f m" % p for p in a.probe_list), x_zone))
    info = {"shift": shift, "rest": rest, "T": T, "H": H, "L": L, "depth": depth, "k": k_full, "dx": dx,
            "stroke_theory_H": flap_hs(k_full, DEPTH, HINGE_DEPTH), "trunc_theory_H": flap_hs(k_t, depth, HINGE_DEPTH)}
    return scene, info


def window(cols, name, x, ts, T, waves, depth):
    """(t, eta) of the measured probe over the gauge's window (source clock)."""
    k = wa.wave_number(2 * math.pi / T, depth)
    t0 = ts + RAMP_PERIODS * T + x / group_speed(k, depth, T) + T
    t = cols["Time"]
    sel = (t >= t0) & (t <= t0 + waves * T)
    rest = float(np.median(cols[name][t < t[0] + 1.0]))
    return t[sel], cols[name][sel] - rest


def lag_and_rms(tm, em, tc, ec, T):
    """Lag of the computed record behind the measured one (cross-correlation over +-T/2 on a 1 ms grid) and the
    RMS of their difference, unshifted."""
    grid = np.arange(tm[0], tm[-1], 1e-3)
    m = np.interp(grid, tm, em)
    best, lag = -np.inf, 0.0
    for s in np.arange(-T / 2, T / 2, 2e-3):
        c = np.interp(grid + s, tc, ec)
        v = float(np.dot(m - m.mean(), c - c.mean()))
        if v > best:
            best, lag = v, s
    rms = float(np.sqrt(np.mean((np.interp(grid, tc, ec) - m) ** 2)))
    return lag, rms


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=DATA)
    ap.add_argument("--per-height", type=float, default=5, help="particles per measured wave height H/dx")
    ap.add_argument("--h-over-dx", type=float, default=1.7)
    ap.add_argument("--gauges", default="1", help="probe numbers to keep, e.g. 1,2,3,4 (the farthest sets the flume's length)")
    ap.add_argument("--waves", type=int, default=6, help="periods per gauge window")
    ap.add_argument("--depth", type=float, default=None, help="depth kept [m] (default half a wavelength)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("-o", dest="out", default=None)
    ap.add_argument("--rundir", default=None, help="analyse this finished run")
    ap.add_argument("--check-height", type=float, default=None, help="bound on |H computed / H measured - 1|")
    ap.add_argument("--theory-table", default=None, metavar="SRC_1PPH_DIR")
    ap.add_argument("--write-scene", default=None, metavar="DIR",
                    help="write the scene (NAME.json) and its paddle file into DIR and stop (pipelines/waves/ holds one)")
    a = ap.parse_args(argv)
    if a.theory_table:
        theory_table(a.theory_table)
        return 0
    if a.per_height <= 0 or a.waves < 1 or (a.depth is not None and not 0 < a.depth <= DEPTH):
        fail("--per-height > 0, --waves >= 1 and 0 < --depth <= 1.0 expected")
    cols = read_data(a.data)
    try:
        a.probe_list = [("WP_%d" % int(g), PROBES["WP_%d" % int(g)]) for g in a.gauges.split(",")]
    except (KeyError, ValueError):
        fail("--gauges: probe numbers among 1, 2, 3, 4, 6 expected, got '%s'" % a.gauges)
    for name, _ in a.probe_list:
        if name not in cols:
            fail("%s: no column %s" % (a.data, name))
    a.tag = "hdx%g_Hdx%g_g%s" % (a.h_over_dx, a.per_height, a.gauges.replace(",", ""))
    rundir = a.rundir or a.out or os.path.join(vc.ROOT, "runs", "ntnu_flume_" + a.tag)
    if a.write_scene:
        a.tag = "%s_Hdx%g" % (os.path.basename(a.data).rsplit("_", 1)[-1][:-4], a.per_height)  # test number
        scene, _ = build_scene(a, cols, os.path.join(a.write_scene, "run"))
        scene["name"] = "ntnu_flume_" + a.tag + "_2d"
        with open(os.path.join(a.write_scene, scene["name"] + ".json"), "w") as f:
            json.dump(scene, f, indent=1)
            f.write("\n")
        print(os.path.join(a.write_scene, scene["name"] + ".json"))
        return 0
    scene, inf = build_scene(a, cols, rundir)
    if not a.rundir:
        res = vc.run_generated(scene, rundir, threads=a.threads)
        if res.rc != 0:
            print(res.stderr[-2000:], file=sys.stderr)
            return 3
    with open(os.path.join(rundir, "run.json")) as f:
        runjson = json.load(f)
    probes = wa.read_probes(os.path.join(rundir, "probes.csv"))
    T, H, shift, depth = inf["T"], inf["H"], inf["shift"], inf["depth"]
    _, ts = paddle_start(cols["Time"], cols["WM_Position"])
    print("test %s: T %.4f s, H %.4f m measured (median of the probes kept), L %.4f m; depth kept %.4f m, dx %.5f m "
          "(H/dx %.1f, h/dx %g); linear flap theory for the measured stroke: H/S %.4f (1.0 m deep), %.4f (the depth kept)"
          % (os.path.basename(a.data), T, H, inf["L"], depth, inf["dx"], H / inf["dx"], a.h_over_dx,
             inf["stroke_theory_H"], inf["trunc_theory_H"]))
    ok, rows = True, []
    for name, x in a.probe_list:
        tm, em = window(cols, name, x, ts, T, a.waves, DEPTH)
        tc_all, ec_all = probes["time"] + shift, probes["h_" + name] - depth
        sel = (tc_all >= tm[0] - T) & (tc_all <= tm[-1] + T)
        if tc_all[-1] < tm[-1]:
            print("%s: the run ends at %.2f s, before the window's end %.2f s (source clock)" % (name, tc_all[-1], tm[-1]))
            ok = False
            continue
        sm = wa.statistics(tm, em)
        win = (tc_all >= tm[0]) & (tc_all <= tm[-1])
        sc = wa.statistics(tc_all[win], ec_all[win])
        lag, rms = lag_and_rms(tm, em, tc_all[sel], ec_all[sel], T)
        err = sc["H_mean"] / sm["H_mean"] - 1
        rows.append({"probe": name, "x": x, "H_measured": sm["H_mean"], "H_computed": sc["H_mean"], "err_H": err,
                     "T_measured": sm["T_mean"], "T_computed": sc["T_mean"], "lag": lag, "rms_over_H": rms / sm["H_mean"]})
        print("%s x = %.2f m: window %.2f-%.2f s (%d / %d waves): H %.2f mm measured, %.2f mm computed (%+.1f %%); "
              "T %.4f / %.4f s; computed lags by %+.3f s (%+.2f T); RMS difference %.2f H" %
              (name, x, tm[0] - shift, tm[-1] - shift, sm["waves"], sc["waves"], 1e3 * sm["H_mean"], 1e3 * sc["H_mean"],
               100 * err, sm["T_mean"], sc["T_mean"], lag, lag / T, rms / sm["H_mean"]))
        if a.check_height is not None and not abs(err) <= a.check_height:
            print("FAIL %s height error %.3f > %.3f" % (name, abs(err), a.check_height))
            ok = False
    os.makedirs(os.path.join(rundir, "post"), exist_ok=True)
    vc.write_csv(os.path.join(rundir, "post", "ntnu_flume.csv"), rows)
    tm = runjson.get("timings", {})
    print("cost: %s steps, %.0f s wall on %s thread(s), %.3g fluid particle-steps/s" %
          (tm.get("steps", "?"), tm.get("wall_seconds", float("nan")), tm.get("threads", "?"),
           tm.get("fluid_particle_steps_per_second", float("nan"))))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
