"""3D runs show the water (issue 35): a tall tank of wall particles around a shallow block of water and an
obstacle, in the pressure state (pvpython). Checks:
- varsph/parts.py: the tank is a wall, the obstacle an obstacle; a tank built from separate slabs is all
  walls; without a `body` array every boundary particle is a wall;
- the picture: at least 5 % of the image left of the colour bar is in the pressure colour map; with the fluid hidden (same view)
  under 0.2 % (walls, outline and obstacle are not drawn in map colours); with the walls drawn whole, as
  before issue 35, the share falls below a third (the control that shows the test can fail);
- the obstacle is drawn (in its own colour) and the walls are cut: fewer wall particles drawn than exist;
- a 2D run keeps its picture: nothing clipped, no outline, discs.
Usage: xvfb-run -a -s "-noreset -screen 0 1280x1024x24" pvpython test_view3d.py"""
import os

import numpy as np

import tcommon as T
import synthetic as S
import viewcheck as C
from varsph import parts

tmp = T.workdir("view3d")

# --- classification ---------------------------------------------------------------------------------------
run = os.path.join(tmp, "tank 3d")
S.tank3d_run(run)
from varsph import io  # noqa: E402
f0 = io.read_vtu(io.frames_of_run(run)[0][1])
cls = parts.classify_bodies(f0.points, f0.arrays["kind"], f0.arrays["body"], f0.dx)
T.check(cls == {1: parts.WALL, 2: parts.OBSTACLE}, "tank body 1 is a wall, block body 2 an obstacle: %s" % cls)
dx = 0.02
floor = S.lattice_block((20, 15, 2), dx, (0, 0, -2 * dx))
side = S.lattice_block((2, 15, 10), dx, (-2 * dx, 0, 0))
water = S.lattice_block((5, 15, 4), dx)
ball = S.lattice_ball(0.05, dx, 3) + np.array([0.25, 0.15, 0.15])   # above the floor, away from the water
pts = np.concatenate([water, floor, side, ball])
kind = np.concatenate([np.zeros(len(water)), np.ones(len(floor) + len(side) + len(ball))])
body = np.concatenate([np.zeros(len(water)), np.full(len(floor), 1), np.full(len(side), 2), np.full(len(ball), 3)])
cls = parts.classify_bodies(pts, kind, body, dx)
T.check(cls == {1: parts.WALL, 2: parts.WALL, 3: parts.OBSTACLE},
        "floor and side slabs are walls (they reach the outer box on 3+ sides), the ball an obstacle: %s" % cls)
part = parts.part_array(kind)
T.check(set(np.unique(part[kind != 0])) == {parts.WALL} and (part[kind == 0] == parts.FLUID).all(),
        "without a body array every boundary particle is a wall")

# --- the picture ------------------------------------------------------------------------------------------
from varsph import pvstate  # noqa: E402

s = pvstate.pv()
size = (900, 600)
view = pvstate.pressure_state(run, time=0.2, view=pvstate.new_view(size))
lut = C.lut_colours(s.GetColorTransferFunction("pressure"))
left_of_bar = s.GetScalarBar(s.GetColorTransferFunction("pressure"), view).Position[0] - 0.01
shots = {k: os.path.join(tmp, "%s.png" % k) for k in ("state", "no_fluid", "whole_walls")}
pvstate.screenshot(view, shots["state"], size)
share = C.colourmap_share(shots["state"], lut, left_of_bar)
T.check(share >= 0.05, "3D pressure state: %.1f %% of the image in the pressure colour map (>= 5 %%)" % (100 * share))
fluid = s.GetDisplayProperties(s.FindSource("Fluid"), view)
fluid.Visibility = 0
pvstate.screenshot(view, shots["no_fluid"], size)
share0 = C.colourmap_share(shots["no_fluid"], lut, left_of_bar)
T.check(share0 < 0.002, "fluid hidden: %.2f %% in the colour map (< 0.2 %%: walls, outline, obstacle are not)"
        % (100 * share0))
fluid.Visibility = 1
whole = pvstate._points(s.FindSource("Walls"), view, 0.02, colour=pvstate.WALL_GREY)
pvstate.screenshot(view, shots["whole_walls"], size)
share_whole = C.colourmap_share(shots["whole_walls"], lut, left_of_bar)
T.check(share_whole < share / 3, "control: walls drawn whole hide the water (%.1f %% in the map, < a third of %.1f %%)"
        % (100 * share_whole, 100 * share))
s.Hide(s.FindSource("Walls"), view)
n = {k: s.FindSource(k).GetDataInformation().GetNumberOfPoints() for k in ("Walls", "WallsCutaway", "Obstacles")}
T.check(0 < n["WallsCutaway"] < 0.7 * n["Walls"], "walls cut away on the camera's side: %d of %d drawn"
        % (n["WallsCutaway"], n["Walls"]))
T.check(n["Obstacles"] == 72 and s.GetDisplayProperties(s.FindSource("Obstacles"), view).Visibility == 1,
        "the obstacle's 72 particles drawn: %d" % n["Obstacles"])
T.check(list(s.GetDisplayProperties(s.FindSource("Obstacles"), view).DiffuseColor) == pvstate.OBSTACLE_COLOUR,
        "obstacle in its own colour")

# --- 2D as before -------------------------------------------------------------------------------------------
s.ResetSession()
run2 = os.path.join(tmp, "dam 2d")
S.dam_break_run(run2, nframes=2)
view = pvstate.pressure_state(run2, view=pvstate.new_view(size))
n = {k: s.FindSource(k).GetDataInformation().GetNumberOfPoints() for k in ("Walls", "WallsCutaway")}
T.check(n["Walls"] > 0 and n["WallsCutaway"] == n["Walls"], "2D: every wall particle drawn (%s)" % n)
T.check(s.GetDisplayProperties(s.FindSource("WallsOutline"), view).Visibility == 0, "2D: no outline")
T.check(s.GetDisplayProperties(s.FindSource("Fluid"), view).ShaderPreset == "Plain circle", "2D: discs")
T.finish(tmp)
