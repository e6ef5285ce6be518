"""Post-processing that fits the scene (issue 35, point 2). Checks:
- varsph/casefit.py: the paper's dam break (a synthetic H = 2 L column on a floor against a wall) is the
  measured case; a wider column, a 3D tank with shallow water, a block falling through the air, two fluid
  bodies and a column that starts moving are not, each with its reason;
- picture names by output time: 0.395943 with output.every 0.05 -> 0.4; without `every`, 6 digits;
- postprocess.py on a 3D tank run written at adaptive times (0.1003, 0.1996 for output.every 0.1): no surge
  front table and no Martin & Moyce figure (and says why), pictures named t0.1 and t0.2; with
  --front-reference measured the figure is drawn; a --front-reference file without T,Z columns: exit 2
  naming the file, before anything is written.
Usage: xvfb-run -a -s "-noreset -screen 0 1280x1024x24" pvpython test_casefit.py"""
import os
import subprocess

import numpy as np

import tcommon as T
import synthetic as S
from varsph import casefit, io

tmp = T.workdir("casefit")

# --- which run is the measured dam break --------------------------------------------------------------------
dam = os.path.join(tmp, "dam")
S.dam_break_run(dam, nframes=1)
f = io.read_vtu(io.frames_of_run(dam)[0][1])
ok, why = casefit.dam_break_column(f)
T.check(ok, "H = 2 L column on a floor against a wall: the measured case (%s)" % why)
scene = {"bodies": [{"kind": "fluid", "shape": "box"}, {"kind": "boundary"}]}
T.check(casefit.dam_break_column(f, scene=scene)[0], "... also with its scene (one fluid body at rest)")
two = {"bodies": [{"kind": "fluid"}, {"kind": "fluid"}]}
T.check(not casefit.dam_break_column(f, scene=two)[0], "two fluid bodies: not (%s)" % casefit.dam_break_column(
    f, scene=two)[1])
moving = {"bodies": [{"kind": "fluid", "velocity": [1.0, 0.0]}]}
T.check(not casefit.dam_break_column(f, scene=moving)[0], "a column that starts moving: not")
wide = os.path.join(tmp, "wide")
S.dam_break_run(wide, nframes=2)
fw = io.read_vtu(io.frames_of_run(wide)[1][1])            # t = 0.1: the column spread to H/L = 2/1.15^2
T.check(not casefit.dam_break_column(fw)[0], "the column spread at t = 0.1: not (%s)" % casefit.dam_break_column(fw)[1])
lifted = io.Frame(f.points + np.where(f.arrays["kind"][:, None] == 0, [0.0, 0.2, 0.0], 0.0), f.arrays, f.fields)
T.check(not casefit.dam_break_column(lifted)[0], "the same column 0.2 m above the floor: not (%s)"
        % casefit.dam_break_column(lifted)[1])
tank = os.path.join(tmp, "tank 3d")
S.tank3d_run(tank, nframes=3, times=[0.0, 0.1003, 0.1996], every=0.1)
ft = io.read_vtu(io.frames_of_run(tank)[0][1])
T.check(not casefit.dam_break_column(ft, vertical=2)[0], "3D tank with shallow water: not (%s)"
        % casefit.dam_break_column(ft, vertical=2)[1])

# --- names by output time -----------------------------------------------------------------------------------
T.check(casefit.time_label(0.395943, 0.05) == "0.4", "0.395943 s, output.every 0.05 -> '0.4'")
T.check(casefit.time_label(0.30000000000000004, 0.1) == "0.3", "summed 0.3 -> '0.3'")
T.check(casefit.time_label(0.395943) == "0.395943", "no output.every: 6 digits")

# --- postprocess.py on the 3D tank ------------------------------------------------------------------------------
script = os.path.join(T.PARAVIEW_DIR, "postprocess.py")


def post(*args):
    p = subprocess.run([T.pvpython(), script, tank] + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, timeout=240)
    print(p.stdout[-2500:])
    return p


p = post("--times", "0.1,0.2")
out = os.path.join(tank, "post")
have = set(os.listdir(out)) if os.path.isdir(out) else set()
T.check(p.returncode == 0, "postprocess on the 3D tank exits 0 (%d)" % p.returncode)
T.check(not any(n.startswith(("front_dimensionless", "surge_front")) for n in have),
        "no surge front and no Martin & Moyce figure for a tank that is not a dam break: %s" % sorted(have))
T.check("is not the measured dam-break case" in p.stdout and "--front-reference" in p.stdout, "and it says why")
T.check({"pressure_t0.1.png", "pressure_t0.2.png", "free_surface_t0.1.png"} <= have,
        "pictures named by output time (frames at 0.1003 and 0.1996 s): %s" % sorted(n for n in have if "_t" in n))
p = post("--front-reference", "measured", "--no-snapshots")
T.check(p.returncode == 0 and os.path.isfile(os.path.join(out, "front_dimensionless.png")),
        "--front-reference measured draws the comparison anyway")
bad = os.path.join(tmp, "front.csv")
with open(bad, "w") as fh:
    fh.write("t,x\n0,1\n")
p = post("--front-reference", bad, "--no-snapshots")
T.check(p.returncode == 2 and bad in p.stdout and "T,Z" in p.stdout, "a reference without T,Z: exit 2 naming it")
T.finish(tmp)
