"""Waves in ParaView (issue 31, point 5): a short real run of a small piston flume (h = 0.1 m, dx = 1 cm, H = 2 cm,
T = 1 s, no ramp), then the elevation state (paraview/states/elevation.py) renders it headless and the picture is
read back. At t = 0.6 s the piston, past its forward stroke, leaves a trough at the paddle and the crest it made
travels ahead of it: the state's blue (trough) pixels lie left of and below its red (crest) pixels. In-process:
the still-water level is the fluid box's 0.1 m, the Elevation array is each free-surface particle's y - 0.095 m
(its centre above where the top row's centres sit in still water, half a spacing below the level) to round-off, and the colour range is symmetric about 0 and holds the highest crest.
Usage: xvfb-run -a -s -noreset pvpython test_elevation.py VARSPH_EXECUTABLE"""
import json
import os
import subprocess
import sys

import numpy as np

import tcommon as T

exe = sys.argv[1]
tmp = T.workdir("elevation")
scene = {
    "name": "flume", "setup": "paper", "dimension": 2,
    "domain": {"min": [-0.3, -0.1], "max": [1.0, 0.4]}, "particles": {"spacing": 0.01},
    "kernel": {"type": "wendland_c2", "h_over_dx": 1.414}, "gravity": [0, -9.81],
    "physics": {"riemann": {}}, "boundary": {"model": "dummy_adami"},
    "integrator": {"type": "symplectic_euler", "cfl": 0.2}, "time": {"end": 0.6}, "output": {"every": 0.3},
    "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0], "max": [0.8, 0.1], "initial_pressure": "hydrostatic"},
               {"kind": "boundary", "shape": "box", "min": [-0.25, -0.03], "max": [0.83, 0], "layers": 3},
               {"kind": "boundary", "shape": "box", "min": [0.8, 0], "max": [0.83, 0.2], "layers": 3},
               {"kind": "boundary", "shape": "box", "min": [-0.03, 0], "max": [0, 0.16], "layers": 3,
                "motion": {"type": "piston", "height": 0.02, "period": 1.0, "ramp": 0}}]}
path = os.path.join(tmp, "flume.json")
with open(path, "w") as f:
    json.dump(scene, f)
run = os.path.join(tmp, "run")
p = subprocess.run([exe, "run", path, "-o", run, "--overwrite", "--quiet", "--threads", "1"], stdout=subprocess.PIPE,
                   stderr=subprocess.STDOUT, text=True, timeout=300)
T.check(p.returncode == 0, "varsph run exit status 0 (%d): %s" % (p.returncode, p.stdout[-500:]))
if p.returncode != 0:
    T.finish(tmp)

from varsph import io as vio  # noqa: E402
from varsph import pvstate  # noqa: E402

level = pvstate.still_water_level(run)
T.close(level, 0.1, 1e-12, "still-water level of the fluid box (10 rows of 1 cm)")

# in-process: the state's Elevation array against the frame's heights
view = pvstate.elevation_state(run, time=0.6, view=pvstate.new_view((1200, 700), name="varsph elevation"))
s = pvstate.pv()
calc = s.FindSource("Elevation")
out = pvstate._output_at(calc, 0.6)
eta = np.asarray(vio.point_array(out, "elevation")).reshape(-1)
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
y = vtk_to_numpy(out.GetPoints().GetData())[:, 1]
T.check(len(eta) > 60, "free-surface particles at 0.6 s: %d (> 60, the 80 cm surface at dx = 1 cm)" % len(eta))
dx = 0.01
T.check(float(np.max(np.abs(eta - (y - (0.1 - dx / 2))))) < 1e-7,   # float32 frames
        "elevation = y - (0.1 m - dx/2) (the top row's centres at rest) on every free-surface particle")
lo, hi = s.GetColorTransferFunction("elevation").RGBPoints[0], s.GetColorTransferFunction("elevation").RGBPoints[-4]
T.check(abs(lo + hi) < 1e-15 and hi >= float(eta.max()) - 1e-12,
        "colour range symmetric about 0 and holding the highest crest: [%.5f, %.5f], crest %.5f" % (lo, hi, eta.max()))
T.check(eta.max() > 0.004 and eta.min() < -0.004, "a crest and a trough of several mm at 0.6 s (%.4f, %.4f m)"
        % (eta.max(), eta.min()))

# the picture, through the state's command line (what `varsph paraview RUN --state elevation` shows)
png = os.path.join(tmp, "elevation.png")
state = os.path.join(T.PARAVIEW_DIR, "states", "elevation.py")
cmd = [T.pvpython(), state, run, "--time", "0.6", "--screenshot", png, "--size", "1200,700"]
p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=180)
if p.returncode < 0 and not os.path.isfile(png):   # pvpython under Xvfb has been seen to abort at random: once
    print("WARNING: the state died with signal %d; retrying once" % -p.returncode)
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=180)
print(p.stdout[-2000:])
T.check(p.returncode == 0 and os.path.isfile(png), "elevation state wrote %s (exit %d)" % (png, p.returncode))
if not os.path.isfile(png):
    T.finish(tmp)
from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402
r = vtkPNGReader()
r.SetFileName(png)
r.Update()
w, h, _ = r.GetOutput().GetDimensions()
px = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3].astype(int)
T.check((w, h) == (1200, 700), "image size %dx%d" % (w, h))
px = px[::-1]            # VTK's rows run bottom-up: row 0 at the top, as the picture is seen
body = px[:, : int(0.85 * w)]          # left of the colour bar
red = (body[:, :, 0] > 170) & (body[:, :, 2] < 110) & (body[:, :, 0] - body[:, :, 1] > 80)   # the map's warm end
blue = (body[:, :, 2] > 170) & (body[:, :, 0] < 120) & (body[:, :, 2] - body[:, :, 1] > 50)  # its cool end
yr, xr = np.nonzero(red)
yb, xb = np.nonzero(blue)
T.check(len(xr) > 200 and len(xb) > 200, "crest (red) and trough (blue) particles drawn: %d and %d pixels"
        % (len(xr), len(xb)))
if len(xr) and len(xb):
    T.check(np.mean(xb) < np.mean(xr), "the trough at the paddle lies left of the crest ahead of it (x %.0f < %.0f)"
            % (np.mean(xb), np.mean(xr)))
    T.check(np.mean(yr) < np.mean(yb), "crest pixels above trough pixels (row %.0f < %.0f)" % (np.mean(yr), np.mean(yb)))
T.finish(tmp)
