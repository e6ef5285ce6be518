#!/usr/bin/env python3
"""Error the single-precision build introduces on the dam break (issue 9a).

Runs pipelines/validation/dam_break_mm_wendland.json (Martin & Moyce dam break, Wendland C2, Verlet) with the
double build and the float build, same scene and thread count, and compares the surge-front series
x_front(t) = max x of the fluid (probes.csv, column front_x, sampled every 1 ms) over 0 <= t <= 0.27 s:
max and RMS of |x_front_float - x_front_double| (in metres and in units of dx), and the Martin & Moyce
best-shift RMS error of each build (case_dam_break.py's metric).

  /usr/bin/python3 pipelines/validation/float_vs_double.py [--dx 0.005] [--threads 2]
      [--double build/release/bin/varsph] [--float build/float/bin/varsph] [-o runs/float_vs_double]
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import case_dam_break as cdb  # noqa: E402
import vcommon as vc  # noqa: E402


def front(rundir):
    p = vc.read_csv(os.path.join(rundir, "probes.csv"))
    return np.asarray(p["time"], float), np.asarray(p["front_x"], float)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, default=0.005)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--double", default=os.path.join(vc.ROOT, "build", "release", "bin", "varsph"))
    ap.add_argument("--float", dest="single", default=os.path.join(vc.ROOT, "build", "float", "bin", "varsph"))
    ap.add_argument("-o", "--outdir", default=os.path.join(vc.ROOT, "runs", "float_vs_double"))
    a = ap.parse_args()
    res, series = {}, {}
    for name, exe in (("double", a.double), ("float", a.single)):
        if not os.path.exists(exe):
            raise SystemExit(f"{exe} not found: build the presets release and float first")
        os.environ["VARSPH_BIN"] = exe
        out = os.path.join(a.outdir, f"{name}_dx{a.dx:g}")
        # the scene's dt = 2e-4 s at dx = 5 mm, scaled with dx (acoustic CFL)
        r = cdb.run_case(a.dx, {"integrator.dt": 2e-4 * a.dx / 0.005}, a.threads, out, cdb.SCENE_WENDLAND)
        if r["rc"] != 0:
            raise SystemExit(f"{name} run failed (exit {r['rc']}): {r['message']}")
        res[name] = r
        series[name] = front(out)
    (td, xd), (tf, xf) = series["double"], series["float"]
    n = min(len(td), len(tf))
    if n == 0 or np.max(np.abs(td[:n] - tf[:n])) > 1e-6:
        raise SystemExit("the two runs sampled the front at different times")
    sel = (td[:n] >= 0.0) & (td[:n] <= 0.27 + 1e-9) & np.isfinite(xd[:n]) & np.isfinite(xf[:n])
    diff = np.abs(xf[:n][sel] - xd[:n][sel])
    dmax, drms = float(diff.max()), float(np.sqrt(np.mean(diff ** 2)))
    print(f"# dam break (dam_break_mm_wendland.json, dx = {a.dx:g} m, {a.threads} threads), "
          f"{int(sel.sum())} front samples over 0 <= t <= 0.27 s")
    print(f"{'build':8s} {'M&M RMS (best shift)':>21s} {'shift dT':>9s} {'M&M RMS (no shift)':>19s} "
          f"{'front at t=0.27 [m]':>20s} {'solver wall [s]':>16s}")
    for name in ("double", "float"):
        r = res[name]
        t, x = series[name]
        print(f"{name:8s} {r['mm_rms_shift']:21.4f} {r['mm_dT']:9.3f} {r['mm_rms']:19.4f} {x[np.isfinite(x)][-1]:20.5f} "
              f"{r['wall']:16.1f}")
    print(f"front difference float - double: max {dmax:.3e} m ({dmax / a.dx:.3f} dx), "
          f"RMS {drms:.3e} m ({drms / a.dx:.3f} dx)")
    print(f"first time the difference exceeds 0.01 dx: "
          f"{next((float(t) for t, d in zip(td[:n][sel], diff) if d > 0.01 * a.dx), float('nan')):.3f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
