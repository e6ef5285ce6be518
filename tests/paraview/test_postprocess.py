"""postprocess.py on synthetic runs writes the expected files with the right numbers:
a 4-frame run with probes.csv and --compare against a shifted copy, and a single-frame run without
probes.csv (must not crash). Usage: xvfb-run -a pvpython test_postprocess.py"""
import csv
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
S.dam_break_run(b, nframes=4, dx=dx, shift=(0.0, 0.003, 0.0))
S.dam_break_run(one, nframes=1, dx=dx, probes=False)
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


p = run([a, "--compare", b, "--times", "0.1,0.3", "--gauges", "0.1", "--probe-points", "0.1,0.1;0.05,0.2"])
T.check(p.returncode == 0, "postprocess exit status 0 (%d)" % p.returncode)
post = os.path.join(a, "post")
expected = ["surge_front.csv", "surge_front.png", "probes.png", "pressure_probes.csv", "pressure_probes.png",
            "deviation.csv", "deviation.png", "momentum.csv", "momentum_Q.png",
            "free_surface_t0.1.png", "free_surface_t0.3.png", "pressure_t0.1.png", "pressure_t0.3.png"]
for f in expected:
    path = os.path.join(post, f)
    T.check(os.path.isfile(path) and os.path.getsize(path) > 0, "wrote post/%s" % f)
    T.check(("wrote " + path) in p.stdout, "printed post/%s" % f)
if os.path.isfile(os.path.join(post, "surge_front.csv")):
    head, v = table(os.path.join(post, "surge_front.csv"))
    T.check(head == ["time", "front_x", "front_rel", "height_x0.1"], "surge_front.csv header %s" % head)
    s = 1 + 1.5 * v[:, 0]
    T.check(len(v) == 4 and np.allclose(v[:, 1], 9.5 * dx * s, atol=1e-12), "surge_front.csv front_x")
if os.path.isfile(os.path.join(post, "deviation.csv")):
    head, v = table(os.path.join(post, "deviation.csv"))
    T.check(head == ["time", "D_max", "D_mean", "D_rms"], "deviation.csv header %s" % head)
    T.check(len(v) == 4 and np.allclose(v[:, 1:], 0.003, atol=1e-9, rtol=0), "deviation.csv D = 0.003 m")
if os.path.isfile(os.path.join(post, "momentum.csv")):
    head, v = table(os.path.join(post, "momentum.csv"))
    T.check(head[0] == "time" and head[-1] == "momentum_Q" and len(v) == 4, "momentum.csv %s, %d rows" % (head, len(v)))
if os.path.isfile(os.path.join(post, "free_surface_t0.1.png")):
    w, h, ncol, std, col = T.image_stats(os.path.join(post, "free_surface_t0.1.png"))
    T.check(ncol > 10 and col > 0.005, "snapshot is not a single colour (%d colours)" % ncol)

# default times: all frames when fewer than 4; single frame, no probes.csv
p = run([one])
T.check(p.returncode == 0, "single-frame run without probes.csv: exit status 0 (%d)" % p.returncode)
T.check("no probes.csv" in p.stdout, "says there is no probes.csv")
post1 = os.path.join(one, "post")
for f in ("surge_front.csv", "momentum.csv", "free_surface_t0.png", "pressure_t0.png"):
    T.check(os.path.isfile(os.path.join(post1, f)), "single frame: wrote post/%s" % f)
T.check(not os.path.exists(os.path.join(post1, "probes.png")), "single frame: no probes.png")
T.finish(tmp)
