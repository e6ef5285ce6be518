"""paraview/wave_analysis.py on synthetic gauge records with known answers (fast tier):
zero up-crossing heights and periods of a regular wave with a second harmonic, Goda & Suzuki's incident and
reflected heights of regular and multi-component seas, and the command on a probes.csv written here."""
import math
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "paraview"))
import wave_analysis as wa  # noqa: E402

failures = []


def check(cond, msg):
    print(("ok   " if cond else "FAIL ") + msg)
    if not cond:
        failures.append(msg)


h = 0.3
# dispersion: the same relation as the solver's
for T in (0.8, 1.5, 4.0):
    w = 2 * math.pi / T
    k = wa.wave_number(w, h)
    check(abs(9.81 * k * math.tanh(k * h) / (w * w) - 1) < 1e-12, "dispersion residual at T = %g" % T)

# 1. zero up-crossing: eta = (H/2) cos(w t) + a2 cos(2 w t) (a Stokes-like crest), 20 periods at 200 samples per period
H, T = 0.02, 1.1
a2 = 0.1 * H / 2
t = np.arange(0, 20 * T, T / 200)
eta = H / 2 * np.cos(2 * math.pi * t / T + 0.3) + a2 * np.cos(4 * math.pi * t / T + 0.6)
Hs, Ts = wa.zero_upcrossing(t, eta)
# the crest-to-trough range of the two-harmonic wave, by brute force on a fine grid
ph = np.linspace(0, 2 * math.pi, 200001)
prof = H / 2 * np.cos(ph + 0.3) + a2 * np.cos(2 * ph + 0.6)
H_exact = prof.max() - prof.min()
check(len(Hs) == 19, "19 whole waves between the 20 up-crossings (got %d)" % len(Hs))
check(np.max(np.abs(Hs / H_exact - 1)) < 2e-4, "heights within 0.02 %% of the profile's range (max err %.2e)" %
      np.max(np.abs(Hs / H_exact - 1)))
check(np.max(np.abs(Ts / T - 1)) < 1e-5, "periods within 1e-5 of T (max err %.2e)" % np.max(np.abs(Ts / T - 1)))
s = wa.statistics(t, eta)
check(abs(s["Hm0"] - 4 * math.sqrt((H / 2) ** 2 / 2 + a2 ** 2 / 2)) < 1e-3 * H, "Hm0 = 4 sqrt(m0)")

# 2. Goda & Suzuki, regular: incident aI, reflected aR = 0.25 aI with its own phase, gauges 0.3 L apart
T = 1.2
w = 2 * math.pi / T
k = wa.wave_number(w, h)
L = 2 * math.pi / k
aI, aR = 0.01, 0.0025
dt = T / 100
t = np.arange(0, 30 * T, dt)  # whole periods: one bin, no leakage
x1, x2 = 1.0, 1.0 + 0.3 * L
def eta_at(x, comps):
    return sum(a * np.cos(w_ * t - k_ * x + p) + b * np.cos(w_ * t + k_ * x + q) for a, b, w_, k_, p, q in comps)
comps = [(aI, aR, w, k, 0.4, 1.9)]
r = wa.goda_suzuki(t, eta_at(x1, comps), eta_at(x2, comps), x2 - x1, h)
check(abs(r["H_I"] / (2 * aI) - 1) < 1e-9, "regular: H_I = 2 aI (%.6g vs %.6g)" % (r["H_I"], 2 * aI))
check(abs(r["Kr"] - 0.25) < 1e-9, "regular: Kr = 0.25 (%.9f)" % r["Kr"])
# swapped roles: a wave travelling the other way is all 'reflected'
r0 = wa.goda_suzuki(t, eta_at(x1, [(0.0, aI, w, k, 0, 0.7)]) + 1e-6 * eta_at(x1, [(1.0, 0, w, k, 0, 0)]),
                    eta_at(x2, [(0.0, aI, w, k, 0, 0.7)]) + 1e-6 * eta_at(x2, [(1.0, 0, w, k, 0, 0)]), x2 - x1, h)
check(abs(r0["H_R"] / (2 * aI) - 1) < 1e-6, "a wave towards -x is reflected: H_R = 2 a")

# 3. multi-component sea on exact bins: Kr of the energies
rng = np.random.default_rng(7)
Trec = 40.0
dt = 0.02
t = np.arange(0, Trec, dt)
comps, EI, ER = [], 0.0, 0.0
for j in range(30, 70):  # f = j / Trec: 0.75 .. 1.75 Hz
    wj = 2 * math.pi * j / Trec
    kj = wa.wave_number(wj, h)
    a, b = 0.004 * rng.random(), 0.001 * rng.random()
    comps.append((a, b, wj, kj, 2 * math.pi * rng.random(), 2 * math.pi * rng.random()))
    EI += a * a / 2
    ER += b * b / 2
dl = 0.2  # 0.1 pi < k dl < 0.9 pi over the whole band
r = wa.goda_suzuki(t, eta_at(0.5, comps), eta_at(0.5 + dl, comps), dl, h, band=(0.7, 1.8))
skipped = sum(1 for c in comps if abs(math.sin(c[3] * dl)) < math.sin(0.1 * math.pi))
check(skipped == 0, "no bin in the band is skipped at dl = %.2f" % dl)
check(abs(r["Kr"] / math.sqrt(ER / EI) - 1) < 1e-9, "irregular: Kr = sqrt(E_R / E_I) (%.6f vs %.6f)" %
      (r["Kr"], math.sqrt(ER / EI)))

# 4. the command on a probes.csv (depth 0.3, gauges at 1.0 and 1.0 + 0.3 L of the regular case)
T = 1.2
w = 2 * math.pi / T
k = wa.wave_number(w, h)
t = np.arange(0, 30 * T + 1e-9, T / 100)
comps = [(aI, aR, w, k, 0.4, 1.9)]
with tempfile.TemporaryDirectory() as d:
    with open(os.path.join(d, "probes.csv"), "w") as f:
        f.write("time,h_g1,h_g2\n")
        e1, e2 = eta_at(x1, comps), eta_at(x2, comps)
        for i in range(len(t)):
            f.write("%.10g,%.12g,%.12g\n" % (t[i], h + e1[i], h + e2[i]))
    rc = wa.main([d, "--depth", "0.3", "--pair", "g1:%.12g,g2:%.12g" % (x1, x2), "--to", "%.10g" % (30 * T - T / 200),
                  "--theory", "0.02:1.2"])
    check(rc == 0, "command exit 0")
    rows = open(os.path.join(d, "post", "waves.csv")).read().splitlines()
    check(rows[0].startswith("gauge,waves,H_mean,T_mean"), "waves.csv header")
    g1 = dict(zip(rows[0].split(","), rows[1].split(",")))
    check(abs(float(g1["T_mean"]) / T - 1) < 1e-4, "gauge g1 period %.5f s" % float(g1["T_mean"]))
    pair = dict(zip(rows[0].split(","), rows[3].split(",")))
    check(abs(float(pair["Kr"]) - 0.25) < 1e-6, "pair row Kr %.6f" % float(pair["Kr"]))
    check(wa.main([d, "--depth", "0.3", "--gauges", "nope"]) == 2, "an unknown gauge: exit 2")

print("%d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
