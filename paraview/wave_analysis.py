"""Wave analysis of water-height gauges (RUN/probes.csv `h_NAME` columns; docs/waves.md).

    pvpython paraview/wave_analysis.py RUN --depth h [--gauges g1,g2,...] [--from T0] [--to T1]
        [--pair g1:x1,g2:x2] [--theory H:T] [--band fmin:fmax]

For each gauge, from the surface elevation eta = h_NAME - depth over [T0, T1]:
  zero up-crossing (IAHR/PIANC 1986): the record is cut where eta crosses its mean upwards; each piece is one
  wave, its height the crest-to-trough range and its period the time between crossings (interpolated
  linearly); reported: number of waves, mean height and period, H1/3, Hmax, and Hm0 = 4 sqrt(m0) of the record.
With --pair: incident and reflected wave heights by the two-gauge method of Goda & Suzuki (1976): for each
  Fourier bin of the two records, with gauge positions x1 < x2 (dl = x2 - x1) and the bin's wave number k from the
  dispersion relation, the complex amplitudes Z_j = I e^{-i k x_j} + R e^{i k x_j} give
  I = (Z1 e^{i k dl} - Z2) / (2 i sin k dl),  R = (Z2 - Z1 e^{-i k dl}) / (2 i sin k dl)  (x1 taken as 0);
  bins with |sin k dl| < sin(0.1 pi) are skipped (Goda & Suzuki's 0.1 pi < k dl < 0.9 pi). Reported: the energies
  E_I, E_R summed over the band, Kr = sqrt(E_R / E_I), and H_I = 2 sqrt(2 E_I), H_R = 2 sqrt(2 E_R) (the height of a
  regular wave of that energy; 4 sqrt(E) is Hm0).
Writes RUN/post/waves.csv (one row per gauge, and the pair's row) and, with matplotlib, RUN/post/gauges.png
(gauges against time, with the linear-theory amplitude of --theory H:T) and RUN/post/spectra.png (periodograms).
Exit status 2 on bad input. Functions are importable (tests/waves/test_wave_analysis.py).
"""
import argparse
import csv
import math
import os
import sys

import numpy as np

G = 9.81


def wave_number(omega, depth, g=G):
    """k of omega^2 = g k tanh(k h) (Newton; the solver's src/waves/wave_theory.cpp does the same)."""
    k0h = omega * omega * depth / g
    kh = k0h / math.tanh(k0h ** 0.75) ** (2.0 / 3.0) if k0h > 0 else 0.0
    for _ in range(50):
        t = math.tanh(kh)
        step = (kh * t - k0h) / (t + kh * (1 - t * t))
        kh -= step
        if abs(step) <= 1e-15 * kh:
            break
    return kh / depth


def zero_upcrossing(t, eta):
    """Waves of a record by zero up-crossing about its mean. Returns (heights, periods) as numpy arrays."""
    t = np.asarray(t, float)
    e = np.asarray(eta, float) - np.mean(eta)
    up = np.nonzero((e[:-1] < 0) & (e[1:] >= 0))[0]
    # crossing times by linear interpolation between the samples that straddle zero
    tc = t[up] - e[up] * (t[up + 1] - t[up]) / (e[up + 1] - e[up])
    heights, periods = [], []
    for a, b, ta, tb in zip(up[:-1], up[1:], tc[:-1], tc[1:]):
        seg = e[a + 1:b + 1]
        heights.append(float(seg.max() - seg.min()))
        periods.append(float(tb - ta))
    return np.array(heights), np.array(periods)


def statistics(t, eta):
    H, T = zero_upcrossing(t, eta)
    e = np.asarray(eta, float) - np.mean(eta)
    out = {"waves": len(H), "H_mean": float(H.mean()) if len(H) else 0.0, "T_mean": float(T.mean()) if len(T) else 0.0,
           "H_max": float(H.max()) if len(H) else 0.0, "Hm0": 4 * float(np.std(e))}
    if len(H):
        n3 = max(1, len(H) // 3)
        out["H_third"] = float(np.sort(H)[::-1][:n3].mean())
    else:
        out["H_third"] = 0.0
    return out


def goda_suzuki(t, eta1, eta2, dl, depth, band=None, g=G):
    """Incident and reflected energies of two gauges dl apart (eta1 nearer the paddle); records sampled unevenly
    are interpolated linearly onto a uniform grid of as many points."""
    t = np.asarray(t, float)
    n = len(t)
    dt = (t[-1] - t[0]) / (n - 1)
    if np.max(np.abs(np.diff(t) - dt)) > 1e-6 * dt:
        # probe rows fall on the first step at or after each sampling time: resample onto a uniform grid
        tu = np.linspace(t[0], t[-1], n)
        eta1, eta2, t = np.interp(tu, t, eta1), np.interp(tu, t, eta2), tu
    z1 = 2 * np.fft.rfft(np.asarray(eta1, float) - np.mean(eta1)) / n
    z2 = 2 * np.fft.rfft(np.asarray(eta2, float) - np.mean(eta2)) / n
    f = np.fft.rfftfreq(n, dt)
    EI = ER = 0.0
    used = 0
    for j in range(1, len(f)):
        if band and not (band[0] <= f[j] <= band[1]):
            continue
        k = wave_number(2 * math.pi * f[j], depth, g)
        s = math.sin(k * dl)
        if abs(s) < math.sin(0.1 * math.pi):
            continue
        e = complex(math.cos(k * dl), math.sin(k * dl))
        I = (z1[j] * e - z2[j]) / (2j * s)
        R = (z2[j] - z1[j] / e) / (2j * s)
        EI += abs(I) ** 2 / 2
        ER += abs(R) ** 2 / 2
        used += 1
    if used == 0 or EI == 0:
        raise ValueError("goda_suzuki: no usable frequency bin (check the band and the gauges' spacing)")
    return {"E_I": EI, "E_R": ER, "Kr": math.sqrt(ER / EI), "H_I": 2 * math.sqrt(2 * EI), "H_R": 2 * math.sqrt(2 * ER),
            "bins": used}


def read_probes(path):
    with open(path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#")) if r]
    header, data = rows[0], np.array([[float(v) for v in r] for r in rows[1:]])
    return {name: data[:, i] for i, name in enumerate(header)}


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run")
    ap.add_argument("--depth", type=float, required=True)
    ap.add_argument("--gauges", default="")
    ap.add_argument("--from", dest="t0", type=float, default=None)
    ap.add_argument("--to", dest="t1", type=float, default=None)
    ap.add_argument("--pair", default="")
    ap.add_argument("--theory", default="")
    ap.add_argument("--band", default="")
    a = ap.parse_args(argv)
    path = os.path.join(a.run, "probes.csv")
    if not os.path.isfile(path):
        print("wave_analysis: no %s" % path, file=sys.stderr)
        return 2
    cols = read_probes(path)
    names = [g for g in a.gauges.split(",") if g] or [c[2:] for c in cols if c.startswith("h_")]
    for g in names:
        if "h_" + g not in cols:
            print("wave_analysis: no column h_%s in %s" % (g, path), file=sys.stderr)
            return 2
    t = cols["time"]
    sel = np.ones(len(t), bool)
    if a.t0 is not None:
        sel &= t >= a.t0
    if a.t1 is not None:
        sel &= t <= a.t1
    ts = t[sel]
    post = os.path.join(a.run, "post")
    os.makedirs(post, exist_ok=True)
    rows = []
    for g in names:
        s = statistics(ts, cols["h_" + g][sel] - a.depth)
        rows.append(dict(gauge=g, **s))
        print("%-10s waves %3d  H_mean %.5f m  T_mean %.4f s  H1/3 %.5f m  Hmax %.5f m  Hm0 %.5f m" %
              (g, s["waves"], s["H_mean"], s["T_mean"], s["H_third"], s["H_max"], s["Hm0"]))
    band = tuple(float(v) for v in a.band.split(":")) if a.band else None
    if a.pair:
        (g1, x1), (g2, x2) = [(p.split(":")[0], float(p.split(":")[1])) for p in a.pair.split(",")]
        r = goda_suzuki(ts, cols["h_" + g1][sel], cols["h_" + g2][sel], x2 - x1, a.depth, band)
        rows.append({"gauge": "%s+%s" % (g1, g2), "H_I": r["H_I"], "H_R": r["H_R"], "Kr": r["Kr"]})
        print("Goda & Suzuki %s, %s (dl = %.4f m): H_I %.5f m  H_R %.5f m  Kr %.4f (%d bins)" %
              (g1, g2, x2 - x1, r["H_I"], r["H_R"], r["Kr"], r["bins"]))
    keys = ["gauge", "waves", "H_mean", "T_mean", "H_third", "H_max", "Hm0", "H_I", "H_R", "Kr"]
    with open(os.path.join(post, "waves.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in keys})
    print(os.path.join(post, "waves.csv"))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("wave_analysis: matplotlib is not available: no plots", file=sys.stderr)
        return 0
    fig, ax = plt.subplots(len(names), 1, figsize=(9, 2.2 * len(names) + 0.5), squeeze=False, sharex=True)
    for i, g in enumerate(names):
        ax[i][0].plot(t, cols["h_" + g] - a.depth, lw=0.8, label="gauge " + g)
        if a.theory:
            H = float(a.theory.split(":")[0])
            ax[i][0].axhline(H / 2, color="k", ls="--", lw=0.6, label="linear theory +-H/2")
            ax[i][0].axhline(-H / 2, color="k", ls="--", lw=0.6)
        ax[i][0].set_ylabel("eta [m]")
        ax[i][0].legend(loc="upper left", fontsize=7)
    ax[-1][0].set_xlabel("t [s]")
    fig.tight_layout()
    fig.savefig(os.path.join(post, "gauges.png"), dpi=110)
    fig, ax = plt.subplots(figsize=(7, 4))
    dt = (ts[-1] - ts[0]) / (len(ts) - 1)
    for g in names:
        e = cols["h_" + g][sel] - a.depth
        z = np.fft.rfft(e - e.mean())
        f = np.fft.rfftfreq(len(e), dt)
        ax.plot(f[1:], (np.abs(z[1:]) ** 2) * 2 * dt / len(e), lw=0.8, label=g)  # one-sided periodogram [m^2/Hz]
    ax.set_xlabel("f [Hz]")
    ax.set_ylabel("S [m^2/Hz]")
    ax.set_xlim(0, min(5.0, 0.5 / dt))
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(post, "spectra.png"), dpi=110)
    print(os.path.join(post, "gauges.png"))
    print(os.path.join(post, "spectra.png"))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except ValueError as e:
        print("wave_analysis: %s" % e, file=sys.stderr)
        sys.exit(2)
