"""End-to-end on a real solver run: varsph runs a short 2D dam break, then the post-processing reads it.
Usage: xvfb-run -a -s -noreset pvpython test_solver_run.py VARSPH_EXECUTABLE SCENE.json

Checks (frame 0 is the initial block of fluid against the left wall and the floor, hydrostatic pressure):
the .pvd frame times are the decimal multiples of output.every (0.02, 0.04, ...), ParaView's PVD reader reads
back exactly those doubles and the frames' field data time is within 1e-9 s of them; free surface = exactly the
top row and the right column of the fluid; SPH pressure probes at interior points read rho0 g (H - y) within
2 % of rho0 g H; the surge front starts at the block's right column and does not move back; the scene's
runtime probes are in probes.csv every 0.0005 s; a run compared with itself gives D = 0; postprocess.py writes
its files, the dimensionless front starting at Z = 1."""
import os
import subprocess
import sys

import numpy as np

import tcommon as T
import varsph as V
from varsph import runmeta  # noqa: F401 (V.runmeta)

exe, scene = sys.argv[1], sys.argv[2]
tmp = T.workdir("solver")
run = os.path.join(tmp, "run")
p = subprocess.run([exe, "run", scene, "-o", run, "--set", "time.end=0.06", "--set", "output.every=0.02",
                    "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
print(p.stdout[-2000:])
T.check(p.returncode == 0, "varsph run exit status 0 (%d)" % p.returncode)
if p.returncode != 0:
    T.finish(tmp)

frames = V.frames_of_run(run)
T.check(len(frames) >= 3, "%d frames" % len(frames))
import re  # noqa: E402
with open(V.find_pvd(run)) as f:
    stamps = re.findall(r'timestep="([^"]+)"', f.read())
T.check(stamps == ["0", "0.02", "0.04", "0.06"], ".pvd frame times written as decimals of output.every: %s" % stamps)
from paraview import simple  # noqa: E402
reader = simple.PVDReader(FileName=V.find_pvd(run))
T.check(list(reader.TimestepValues) == [0.0, 0.02, 0.04, 0.06],
        "ParaView's PVD reader reads back exactly 0, 0.02, 0.04, 0.06: %s" % list(reader.TimestepValues))
drift = max(abs(V.read_vtu(p_).fields["time"] - t) for t, p_ in frames)
T.check(0 < drift <= 1e-9 or drift == 0, "field data time within 1e-9 s of the .pvd time (max %.3g s)" % drift)
f0 = V.read_vtu(frames[0][1], frames[0][0])
dim, dx = f0.dimension, f0.dx
fm = f0.fluid_mask()
x = f0.points[fm]
flag = V.free_surface(f0)[fm] == 1
top, right = x[:, 1].max(), x[:, 0].max()
expect = (np.abs(x[:, 1] - top) < 0.25 * dx) | (np.abs(x[:, 0] - right) < 0.25 * dx)
T.check(np.array_equal(flag, expect), "frame 0: free surface = top row + right column (%d flagged, %d expected)"
        % (flag.sum(), expect.sum()))

rho0 = float(f0.fields["rho0"])
H = top + 0.5 * dx
g = 9.81
gv = V.io.gravity_of_run(run)
if gv is not None:
    g = float(np.linalg.norm(gv))
R = V.kernel_from_fields(f0.fields).support_radius
xs = 0.5 * (x[:, 0].min() + right)
probes = [(xs, y, 0.0) for y in np.linspace(x[:, 1].min() + R, top - R, 4)]
vals, _ = V.probe_pressure(f0, probes)
exact = rho0 * g * (H - np.array([q[1] for q in probes]))
err = np.abs(vals - exact).max() / (rho0 * g * H)
T.check(err < 0.02, "frame 0: hydrostatic probes within 2 %% of rho0 g H (max error %.2e)" % err)

cols, rows = V.surge_series(run)
front = np.array([r[1] for r in rows])
T.close(front[0], right, 1e-12, "surge front at t=0 = right column of the fluid")
T.check(np.all(np.diff(front) >= -0.1 * dx), "surge front does not move back: %s" % np.round(front, 4))
head, pc = V.runmeta.probes(run)
T.check(head == ["time", "p_wall", "h_x2L", "front_x"], "probes.csv of the default scene: %s" % head)
if "time" in pc:
    T.check(len(pc["time"]) == 121 and np.allclose(np.diff(pc["time"]), 0.0005, atol=1e-9),
            "a probe row every 0.0005 s: %d rows" % len(pc["time"]))
    # the probe is computed in double, `right` read from a float32 frame (output.precision): float32 resolution
    T.close(pc["front_x"][0], right, 1e-6 * abs(right), "front probe at t = 0 = the block's right column")
    T.check(pc["h_x2L"][0] == 0 and pc["p_wall"][0] == 0, "dry at x = 2L and at the right wall at t = 0")
dev = V.deviation_series(run, run)
T.check(len(dev) == len(frames) and all(r[1] == 0 for r in dev), "run against itself: D = 0 at every frame")

p = subprocess.run([T.pvpython(), os.path.join(T.PARAVIEW_DIR, "postprocess.py"), run, "--compare", run],
                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
print(p.stdout[-2000:])
T.check(p.returncode == 0, "postprocess.py exit status 0 (%d)" % p.returncode)
for name in ("surge_front.csv", "deviation.csv", "momentum.csv", "free_surface_t0.png", "pressure_t0.png",
             "probes_pressure.png", "probes_water_height.png", "probes_front.png", "front_dimensionless.png",
             "pressure_smoothed_t0.06.png"):
    T.check(os.path.isfile(os.path.join(run, "post", name)), "post/%s" % name)
fd = os.path.join(run, "post", "front_dimensionless.csv")
if os.path.isfile(fd):
    z = np.loadtxt(fd, delimiter=",", skiprows=1)
    # Z from float32 frame positions: 1 to float32 resolution (1.2e-8 measured), not to 1e-12
    T.check(abs(z[0, 2] - 1.0) < 1e-6 and np.all(np.diff(z[:, 2]) >= -1e-6), "dimensionless front starts at "
            "Z = 1 (%.15g) and does not move back" % z[0, 2])
T.finish(tmp)
