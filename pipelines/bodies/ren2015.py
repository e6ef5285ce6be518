#!/usr/bin/python3
"""The floating box of Ren, He, Dong & Wen (2015, Appl. Ocean Res. 50, 1-12) in regular waves against the measured
surge, heave and roll (issue 30 point 6; docs/validation.md section 18). Runs (or, with --reuse, reads) the scene
pipelines/bodies/ren2015_box_in_waves_2d.json and compares its bodies.csv with
tests/data/ren2015_floating_box_regular_waves.csv (107 rows, t = 1.81-8.88 s; provenance in the file's header).

Conventions (the data does not state them; what is assumed here, and why):
  * surge = x - x(0) of the centre of mass, positive down-wave (+x, the waves' direction in both the DualSPHysics
    case and the scene); heave = y - y(0), positive up. The data's own zero is not stated (its first row has a surge
    of -0.10 m): the surge's RMS difference is given as is and with the mean offset over the series removed.
  * roll: the data's roll is compared with SIGN x (the scene's rotation about +z, y up, x down-wave), in degrees.
    SIGN = -1 (--roll-sign): DualSPHysics' 2D cases lie in the x-z plane and turn about +y, which is the scene's
    -z (a positive roll lifts the box's up-wave side); and in the data each roll maximum follows a heave crest by
    0.12 s (0.10 T), in the scene's run by 0.09 s with SIGN = -1 and by 0.75 s with +1 (the harness prints both
    lags, so that the choice can be checked on any run).
  * time: the paddle starts at t = 0, as in the DualSPHysics case (<piston start="0">, no ramp); the data's time is
    taken as the same clock. That is an assumption (the source does not say how its clock relates to the paddle's
    start); a single shift s (the scene's series read at t + s) is also fitted to the heave (the motion free of
    sign and zero conventions) and every figure is given without and with it.
Figures per motion over the data's rows: RMS difference (the scene interpolated at the data's times); over the
steady window (--steady, default 2.5 s to the data's end): amplitude (mean half crest-to-trough range of the zero
up-crossing cycles, after removing a straight-line trend) and period (mean up-crossing period), and the mean surge
drift rate (least-squares slope). Gauges g100 and g150 (x = 1.0, 1.5 m, before the box): zero up-crossing height
and period against the target H = 0.1 m, T = 1.2 s, and the incident and reflected heights of the pair by Goda &
Suzuki (paraview/wave_analysis.py); the pair g350 / g398 behind the box gives the beach's reflection once the
reflected waves are back (from 7.6 s; front at the shoreline, x = 6.5 m, about 5.6 s, back at 3.98 m about 7.8 s),
and over 4-7.6 s, before they are, the method's floor on so short a record (windows cut to whole periods).
Writes RUN/post/ren2015.png (the three motions against the data, and the gauges) and RUN/post/ren2015_motions.csv
(the scene's surge, heave and roll at the data's times).

  /usr/bin/python3 pipelines/bodies/ren2015.py [-o runs/ren2015] [--dx 0.02] [--threads 1] [--set KEY=VALUE ...]
      [--reuse] [--check-heave-amplitude X] [--check-roll-amplitude X] [--check-period X] [--check-heave-rms X]
      [--check-wave X]
  --check-heave-amplitude X, --check-roll-amplitude X: exit 1 when that amplitude differs from the data's by more
      than X (relative); --check-period X: the same for the heave and roll periods (relative to the data's);
  --check-heave-rms X: the heave's RMS difference over the data's rows, without a shift [m];
  --check-wave X: the same for the gauges' incident height (Goda & Suzuki) and period against H and T.
Exit 2 on bad arguments, 3 when the run fails.
"""
import argparse
import csv
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "paraview"))
import wave_analysis as wa  # noqa: E402  (zero up-crossing, Goda & Suzuki)
import harness_common  # noqa: E402  (running a scene)

SCENE = os.path.join(HERE, "ren2015_box_in_waves_2d.json")
DATA = os.path.join(ROOT, "tests", "data", "ren2015_floating_box_regular_waves.csv")
H_TARGET, T_TARGET, DEPTH = 0.10, 1.2, 0.4


def read_data(path):
    with open(path) as f:
        rows = [r for r in csv.reader(l for l in f if not l.startswith("#")) if r]
    a = np.array([[float(v) for v in r] for r in rows[1:]])
    return a[:, 0], a[:, 1], a[:, 2], a[:, 3]


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(l for l in f if not l.startswith("#")))
    head = rows[0]
    a = np.array([[float(v) for v in r] for r in rows[1:] if r])
    return {h: a[:, i] for i, h in enumerate(head)}


def run_scene(outdir, dx, threads, sets, timeout):
    return harness_common.run_scene(SCENE, outdir, threads, ["particles.spacing=%r" % dx] + list(sets), timeout)


def cycles(t, s, t0, t1):
    """Amplitude (mean half crest-to-trough range) and period (mean) of the zero up-crossing cycles of s over
    [t0, t1] after a straight-line trend is removed; (nan, nan, 0) without a whole cycle."""
    m = (t >= t0) & (t <= t1)
    tt, ss = t[m], s[m]
    if len(tt) < 4:
        return float("nan"), float("nan"), 0
    ss = ss - np.polyval(np.polyfit(tt, ss, 1), tt)
    H, T = wa.zero_upcrossing(tt, ss)
    if len(H) == 0:
        return float("nan"), float("nan"), 0
    return float(H.mean()) / 2, float(T.mean()), len(H)


def peak_lag(t, a, b, t0, t1):
    """Mean time from each maximum of a to the next maximum of b over [t0, t1] (one per cycle of a)."""
    m = (t >= t0) & (t <= t1)
    tt, aa, bb = t[m], a[m], b[m]
    ia = [i for i in range(1, len(aa) - 1) if aa[i] >= aa[i - 1] and aa[i] > aa[i + 1] and aa[i] > np.mean(aa)]
    ib = [i for i in range(1, len(bb) - 1) if bb[i] >= bb[i - 1] and bb[i] > bb[i + 1] and bb[i] > np.mean(bb)]
    lags = []
    for i in ia:
        nxt = [tt[j] for j in ib if tt[j] >= tt[i]]
        if nxt:
            lags.append(nxt[0] - tt[i])
    return float(np.mean(lags)) if lags else float("nan")


def rms(a):
    return float(np.sqrt(np.mean(np.square(a))))


def evaluate(outdir, roll_sign, steady, shift_range):
    td, sd, hd, rd = read_data(DATA)
    b = read_csv(os.path.join(outdir, "bodies.csv"))
    t = b["time"]
    surge, heave, roll = b["x"] - b["x"][0], b["y"] - b["y"][0], roll_sign * np.degrees(b["angle"])
    t1 = min(td[-1], t[-1])
    if t[-1] < td[-1] - 1e-9:
        print("  note: the run ends at %.3f s, before the data's last row (%.3f s): figures over the overlap"
              % (t[-1], td[-1]))
    keep = td <= t1
    td, sd, hd, rd = td[keep], sd[keep], hd[keep], rd[keep]

    def at(series, s):
        return np.interp(td + s, t, series)

    # the shift that best lines up the heave (the scene's series read at t + s); a grid of 1 ms
    shifts = np.arange(-shift_range, shift_range + 5e-4, 1e-3)
    costs = [rms(at(heave, s) - hd) if td[-1] + s <= t[-1] else np.inf for s in shifts]
    s_best = float(shifts[int(np.argmin(costs))])
    fig = {"shift": s_best, "t_end": t1}
    for name, sim, dat in (("surge", surge, sd), ("heave", heave, hd), ("roll", roll, rd)):
        r = {}
        for tag, s in (("", 0.0), ("_shifted", s_best)):
            d = at(sim, s) - dat
            r["rms" + tag] = rms(d)
            r["rms_offset_removed" + tag] = rms(d - d.mean())
            r["mean_diff" + tag] = float(d.mean())
        r["amp"], r["period"], r["n"] = cycles(t, sim, steady, t1)
        r["amp_data"], r["period_data"], r["n_data"] = cycles(td, dat, steady, t1)
        m = (t >= td[0]) & (t <= t1)
        r["drift"] = float(np.polyfit(t[m], sim[m], 1)[0])
        r["drift_data"] = float(np.polyfit(td, dat, 1)[0])
        r["range"] = (float(sim[m].min()), float(sim[m].max()))
        r["range_data"] = (float(dat.min()), float(dat.max()))
        fig[name] = r
    fig["lag"] = peak_lag(t, heave, roll, steady, t1)
    fig["lag_data"] = peak_lag(td, hd, rd, steady, t1)
    fig["lag_neg"] = peak_lag(t, heave, -roll, steady, t1)
    # the scene's motions at the data's times (no shift), for other tools
    os.makedirs(os.path.join(outdir, "post"), exist_ok=True)
    with open(os.path.join(outdir, "post", "ren2015_motions.csv"), "w") as f:
        f.write("# ren2015.py: the scene's surge x - x(0) [m], heave y - y(0) [m] and roll %+d x angle [deg] at the "
                "data's times (tests/data/ren2015_floating_box_regular_waves.csv), paddle start t = 0, no shift\n"
                "time_s,surge_m,heave_m,roll_deg,surge_exp_m,heave_exp_m,roll_exp_deg\n" % roll_sign)
        for row in zip(td, at(surge, 0), at(heave, 0), at(roll, 0), sd, hd, rd):
            f.write(",".join("%.6g" % v for v in row) + "\n")
    # gauges
    p = read_csv(os.path.join(outdir, "probes.csv"))
    tp = p["time"]
    eta = {g: p["h_" + g] - p["h_" + g][0] for g in ("g100", "g150", "g350", "g398") if "h_" + g in p}
    gauges = {}
    for g in ("g100", "g150"):
        if g in eta:
            m = (tp >= steady) & (tp <= t1)
            gauges[g] = wa.statistics(tp[m], eta[g][m])
    pairs = {}
    for (g1, x1, g2, x2, a0, a1, label) in (("g100", 1.0, "g150", 1.5, steady, t1, "before the box"),
                                            ("g350", 3.5, "g398", 3.984, 4.0, 7.6,
                                             "behind the box, before the beach's reflection"),
                                            ("g350", 3.5, "g398", 3.984, 7.6, tp[-1], "behind the box, beach")):
        a1 = min(a1, tp[-1])  # a run that stopped early (or is still running)
        a1 = a0 + math.floor(max(a1 - a0, 0.0) / T_TARGET + 1e-9) * T_TARGET  # whole periods: no leakage
        if g1 in eta and g2 in eta and a1 - a0 > 1.5 * T_TARGET:
            m = (tp >= a0) & (tp <= a1)
            try:
                pairs[label] = (a0, a1, wa.goda_suzuki(tp[m], eta[g1][m], eta[g2][m], x2 - x1, DEPTH,
                                                       band=(0.5 / T_TARGET, 1.5 / T_TARGET)))
            except ValueError as e:
                print("  %s: %s" % (label, e))
    fig["gauges"], fig["pairs"] = gauges, pairs
    plot(outdir, t, surge, heave, roll, td, sd, hd, rd, s_best, tp, eta, roll_sign)
    return fig


def plot(outdir, t, surge, heave, roll, td, sd, hd, rd, s_best, tp, eta, roll_sign):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("  (no matplotlib: no plot)")
        return
    fig, ax = plt.subplots(4, 1, figsize=(9, 11), sharex=True)
    for a, sim, dat, lab in ((ax[0], surge, sd, "surge [m]"), (ax[1], heave, hd, "heave [m]"),
                             (ax[2], roll, rd, "roll [deg] (%+d x angle about z)" % roll_sign)):
        a.plot(t, sim, "b-", lw=1.2, label="varsph (paddle starts at t = 0)")
        if abs(s_best) > 0:
            a.plot(t - s_best, sim, "b:", lw=0.9, label="varsph shifted by %+.3f s" % -s_best)
        a.plot(td, dat, "ko", ms=3, label="Ren et al. (2015), measured")
        a.set_ylabel(lab)
        a.grid(alpha=0.3)
    ax[0].legend(fontsize=8, loc="upper left")
    for g, c in (("g100", "g"), ("g150", "m")):
        if g in eta:
            ax[3].plot(tp, eta[g], c + "-", lw=1, label="gauge %s (x = %s m)" % (g, {"g100": "1.0", "g150": "1.5"}[g]))
    ax[3].axhline(H_TARGET / 2, color="k", ls="--", lw=0.8)
    ax[3].axhline(-H_TARGET / 2, color="k", ls="--", lw=0.8, label="+-H/2 (H = 0.1 m)")
    ax[3].set_ylabel("elevation [m]")
    ax[3].set_xlabel("time [s]")
    ax[3].legend(fontsize=8, loc="upper left")
    ax[3].grid(alpha=0.3)
    ax[0].set_title("Floating box in regular waves (H 0.1 m, T 1.2 s, h 0.4 m): Ren et al. 2015")
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "post", "ren2015.png"), dpi=110)


def report(fig):
    print("  time origin: the paddle starts at t = 0 (assumed to be the data's clock); best shift on the heave: the "
          "scene read at t %+.3f s" % fig["shift"])
    for name, unit in (("surge", "m"), ("heave", "m"), ("roll", "deg")):
        r = fig[name]
        print("  %s: RMS difference %.4f %s (offset removed %.4f; mean difference %+.4f); shifted: %.4f (offset "
              "removed "
              "%.4f)" % (name, r["rms"], unit, r["rms_offset_removed"], r["mean_diff"], r["rms_shifted"],
                         r["rms_offset_removed_shifted"]))
        print("    amplitude %.4f %s against %.4f (%+.1f %%), period %.4f s against %.4f (%+.2f %%) over %d / %d "
              "cycles; "
              "drift %+.4f %s/s against %+.4f; range %.4f..%.4f against %.4f..%.4f"
              % (r["amp"], unit, r["amp_data"], 100 * (r["amp"] / r["amp_data"] - 1), r["period"], r["period_data"],
                 100 * (r["period"] / r["period_data"] - 1), r["n"], r["n_data"], r["drift"], unit, r["drift_data"],
                 r["range"][0], r["range"][1], r["range_data"][0], r["range_data"][1]))
    c = 2 * math.pi / T_TARGET / wa.wave_number(2 * math.pi / T_TARGET, DEPTH)
    print("  encounter period T / (1 - U / c) of a box drifting at the surge drift U (c = %.3f m/s): %.4f s "
          "(data %.4f s)"
          % (c, T_TARGET / (1 - fig["surge"]["drift"] / c), T_TARGET / (1 - fig["surge"]["drift_data"] / c)))
    print("  roll peak after heave crest: %.3f s (data %.3f s); with the other roll sign: %.3f s"
          % (fig["lag"], fig["lag_data"], fig["lag_neg"]))
    for g, st in fig["gauges"].items():
        print("  gauge %s: %d waves, mean height %.4f m (%+.1f %% of H), period %.4f s (%+.2f %% of T), H1/3 %.4f m"
              % (g, st["waves"], st["H_mean"], 100 * (st["H_mean"] / H_TARGET - 1), st["T_mean"],
                 100 * (st["T_mean"] / T_TARGET - 1), st["H_third"]))
    for label, (a0, a1, gs) in fig["pairs"].items():
        print("  Goda & Suzuki %s (%.2f-%.2f s): incident H %.4f m (%+.1f %% of H), reflected %.4f m, Kr %.3f"
              % (label, a0, a1, gs["H_I"], 100 * (gs["H_I"] / H_TARGET - 1), gs["H_R"], gs["Kr"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--out", default=os.path.join(ROOT, "runs", "ren2015"))
    ap.add_argument("--dx", type=float, default=0.02)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--timeout", type=float, default=None)
    ap.add_argument("--reuse", action="store_true", help="evaluate the run in --out without running")
    ap.add_argument("--roll-sign", type=int, default=-1, choices=(-1, 1))
    ap.add_argument("--steady", type=float, default=2.5, help="start of the steady window [s]")
    ap.add_argument("--shift-range", type=float, default=0.6, help="largest |shift| searched [s]")
    ap.add_argument("--check-heave-amplitude", type=float)
    ap.add_argument("--check-roll-amplitude", type=float)
    ap.add_argument("--check-heave-rms", type=float)
    ap.add_argument("--check-period", type=float)
    ap.add_argument("--check-wave", type=float)
    a = ap.parse_args()
    if not 0 < a.dx <= 0.05 or any(abs(L / a.dx - round(L / a.dx)) > 1e-6 for L in (1.66, 0.3, 0.1)):
        print("ren2015.py: --dx: expected a spacing in (0, 0.05] m that divides 1.66, 0.3 and 0.1 m (the box's faces "
              "on "
              "lines of the fluid's lattice, which starts at the paddle's face x = 0.19 m: 0.02, 0.01, 0.005)",
              file=sys.stderr)
        raise SystemExit(2)
    if not a.reuse:
        wall, l0, l1 = run_scene(a.out, a.dx, a.threads, a.set, a.timeout)
        print("ren2015: run dx %g (H/dx %.0f) %.0f s wall on %d thread(s), load %.1f -> %.1f"
              % (a.dx, H_TARGET / a.dx, wall, a.threads, l0, l1))
    elif not os.path.exists(os.path.join(a.out, "bodies.csv")):
        print("ren2015.py: --reuse: %s has no bodies.csv" % a.out, file=sys.stderr)
        raise SystemExit(2)
    print("Ren et al. (2015) floating box, H 0.1 m, T 1.2 s, h 0.4 m: %s" % a.out)
    fig = evaluate(a.out, a.roll_sign, a.steady, a.shift_range)
    report(fig)
    failed = []
    for n, bound in (("heave", a.check_heave_amplitude), ("roll", a.check_roll_amplitude)):
        if bound is not None:
            e = abs(fig[n]["amp"] / fig[n]["amp_data"] - 1)
            if not e <= bound:
                failed.append("%s amplitude off by %.1f %% (bound %.1f %%)" % (n, 100 * e, 100 * bound))
    if a.check_heave_rms is not None and not fig["heave"]["rms"] <= a.check_heave_rms:
        failed.append("heave RMS difference %.4f m (bound %.4f m)" % (fig["heave"]["rms"], a.check_heave_rms))
    if a.check_period is not None:
        for n in ("heave", "roll"):
            e = abs(fig[n]["period"] / fig[n]["period_data"] - 1)
            if not e <= a.check_period:
                failed.append("%s period off by %.2f %% (bound %.2f %%)" % (n, 100 * e, 100 * a.check_period))
    if a.check_wave is not None:
        gs = fig["pairs"].get("before the box")
        e = abs(gs[2]["H_I"] / H_TARGET - 1) if gs else float("inf")
        if not e <= a.check_wave:
            failed.append("incident wave height off by %.1f %% (bound %.1f %%)" % (100 * e, 100 * a.check_wave))
        for g, st in fig["gauges"].items():
            e = abs(st["T_mean"] / T_TARGET - 1)
            if not e <= a.check_wave:
                failed.append("gauge %s period off by %.2f %%" % (g, 100 * e))
    for f in failed:
        print("  FAIL: " + f)
    raise SystemExit(1 if failed else 0)


if __name__ == "__main__":
    main()
