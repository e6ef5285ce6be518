"""postprocess.py on synthetic runs writes the expected files with the right numbers: a 4-frame run with
probes.csv (p_, h_, front_x columns as the solver names them) compared with a shifted copy that ends earlier
and differs in two scene keys, with reference probe data (dimensionless T,P and SI t,p); a single-frame run
without probes.csv (must not crash); a malformed reference file (exit 2 naming it).
Usage: xvfb-run -a -s -noreset pvpython test_postprocess.py"""
import csv
import json
import os
import subprocess

import numpy as np

import tcommon as T
import synthetic as S

tmp = T.workdir("post")
dx = 0.02
a = os.path.join(tmp, "a")
b = os.path.join(tmp, "b")
one = os.path.join(tmp, "single")
S.dam_break_run(a, nframes=4, dx=dx)
S.dam_break_run(b, nframes=3, dx=dx, shift=(0.0, 0.003, 0.0))
S.dam_break_run(one, nframes=1, dx=dx, probes=False)
for run, dt in ((a, 1e-4), (b, 5e-5)):
    with open(os.path.join(run, "run.json"), "w") as f:
        json.dump({"scene": {"name": "dam", "gravity": [0, -9.81], "integrator": {"type": "verlet", "dt": dt},
                             "time": {"end": 0.3 if run == a else 0.2}}}, f)
ref_dimless = os.path.join(tmp, "ref_TP.csv")
with open(ref_dimless, "w") as f:
    f.write("# a measured signal, dimensionless\nT,P\n0.5,0.1\n0.2,0.05\n1.0,0.3\n")
ref_si = os.path.join(tmp, "ref_tp.csv")
with open(ref_si, "w") as f:
    f.write("t,p\n0,0\n0.3,30\n")
bad_ref = os.path.join(tmp, "bad.csv")
with open(bad_ref, "w") as f:
    f.write("T,P\n0.1,abc\n")
script = os.path.join(T.PARAVIEW_DIR, "postprocess.py")


def run(args):
    p = subprocess.run([T.pvpython(), script] + args, cwd=tmp, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, timeout=300)
    print(p.stdout[-4000:])
    return p


def table(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


p = run([a, "--compare", b, "--times", "0.1,0.3", "--gauges", "0.1", "--probe-points", "0.1,0.1;0.05,0.2",
         "--reference-probe", "p0=" + ref_dimless + ":H=0.4:label=test data", "--reference-probe", "p_p1=" + ref_si])
T.check(p.returncode == 0, "postprocess exit status 0 (%d)" % p.returncode)
post = os.path.join(a, "post")
expected = ["probes_pressure.png", "probes_water_height.png", "probes_front.png", "probe_p0_reference.png",
            "probe_p_p1_reference.png", "surge_front.csv", "surge_front.png", "front_dimensionless.csv",
            "front_dimensionless.png", "pressure_probes.csv", "pressure_probes.png", "deviation.csv", "deviation.png",
            "scene_diff.txt", "momentum.csv", "momentum_Q.png", "free_surface_t0.1.png", "free_surface_t0.3.png",
            "pressure_t0.1.png", "pressure_t0.3.png", "pressure_smoothed_t0.1.png", "deviation_t0.2.png"]
for f in expected:
    path = os.path.join(post, f)
    T.check(os.path.isfile(path) and os.path.getsize(path) > 0, "wrote post/%s" % f)
    T.check(("wrote " + path) in p.stdout, "printed post/%s" % f)
if os.path.isfile(os.path.join(post, "surge_front.csv")):
    head, v = table(os.path.join(post, "surge_front.csv"))
    T.check(head == ["time", "front_x", "front_rel", "height_x0.1"], "surge_front.csv header %s" % head)
    s = 1 + 1.5 * v[:, 0]
    T.check(len(v) == 4 and np.allclose(v[:, 1], 9.5 * dx * s, atol=1e-12), "surge_front.csv front_x")
if os.path.isfile(os.path.join(post, "front_dimensionless.csv")):
    head, v = table(os.path.join(post, "front_dimensionless.csv"))
    # column of width L = 10 dx against the wall at x = 0, front from probes.csv (the outermost centre 9.5 dx s)
    L = 10 * dx
    T.check(head == ["time", "T", "Z"] and np.allclose(v[:, 1], v[:, 0] * np.sqrt(2 * 9.81 / L), rtol=1e-12)
            and np.allclose(v[:, 2], (9.5 * dx * (1 + 1.5 * v[:, 0]) + 0.5 * dx) / L, rtol=1e-12) and v[0, 2] == 1.0,
            "front_dimensionless.csv: T = t sqrt(2 g/L), Z = (x_front + dx/2)/L, Z(0) = 1")
if os.path.isfile(os.path.join(post, "deviation.csv")):
    head, v = table(os.path.join(post, "deviation.csv"))
    T.check(head == ["time", "D_max", "D_mean", "D_rms"], "deviation.csv header %s" % head)
    T.check(len(v) == 3 and np.allclose(v[:, 1:], 0.003, atol=1e-9, rtol=0),
            "deviation.csv: the 3 common times, D = 0.003 m")
if os.path.isfile(os.path.join(post, "scene_diff.txt")):
    with open(os.path.join(post, "scene_diff.txt")) as f:
        text = f.read()
    T.check("integrator.dt: A = 0.0001, B = 5e-05" in text and "time.end: A = 0.3, B = 0.2" in text
            and "gravity" not in text, "scene_diff.txt lists the two differing keys:\n" + text)
    T.check("integrator.dt (0.0001 vs 5e-05)" in p.stdout, "the differing keys are printed")
if os.path.isfile(os.path.join(post, "momentum.csv")):
    head, v = table(os.path.join(post, "momentum.csv"))
    T.check(head[0] == "time" and head[-1] == "momentum_Q" and len(v) == 4, "momentum.csv %s, %d rows" % (head, len(v)))
for f in ("free_surface_t0.1.png", "pressure_smoothed_t0.1.png", "deviation_t0.2.png"):
    if os.path.isfile(os.path.join(post, f)):
        w, h, ncol, std, col = T.image_stats(os.path.join(post, f))
        T.check(ncol > 10 and col > 0.005, "%s is not a single colour (%d colours)" % (f, ncol))

# default times: all frames when fewer than 4; single frame, no probes.csv
p = run([one])
T.check(p.returncode == 0, "single-frame run without probes.csv: exit status 0 (%d)" % p.returncode)
T.check("no probes.csv" in p.stdout, "says there is no probes.csv")
post1 = os.path.join(one, "post")
for f in ("surge_front.csv", "momentum.csv", "free_surface_t0.png", "pressure_t0.png", "front_dimensionless.csv"):
    T.check(os.path.isfile(os.path.join(post1, f)), "single frame: wrote post/%s" % f)
T.check(not any(n.startswith("probes_") for n in os.listdir(post1)), "single frame: no probe plots")

# bad input: exit 2, the file and what was expected, nothing else done
p = run([a, "--no-snapshots", "--reference-probe", "p0=" + bad_ref])
T.check(p.returncode == 2 and bad_ref + ":2" in p.stdout and "expected" in p.stdout,
        "malformed reference file: exit 2 naming %s:2 (%d)" % (bad_ref, p.returncode))
p = run([a, "--no-snapshots", "--reference-probe", "nosuch=" + ref_si])
T.check(p.returncode == 2 and "no column nosuch or p_nosuch" in p.stdout, "unknown probe name: exit 2, says which")
T.finish(tmp)
