"""The states as pvpython builds them (varsph.pvstate) on synthetic runs: one full-size view in its own layout,
Point Gaussian particles of diameter dx, the camera fitted to the fluid with the colour bar beside it, the time
annotation of the frame shown, colour ranges from the percentiles of each frame; the deviation state at the
last common time of two runs that end at different times, saying so. Screenshots: the fluid region is drawn.
Usage: xvfb-run -a -s -noreset pvpython test_pvstate.py"""
import os

import numpy as np

import tcommon as T
import synthetic as S
import viewcheck as C
import varsph as V
from varsph import pvstate

tmp = T.workdir("pvstate")
dx = 0.02
a, b = os.path.join(tmp, "a"), os.path.join(tmp, "b")
S.dam_break_run(a, nframes=4, dx=dx)
S.dam_break_run(b, nframes=3, dx=dx, shift=(0.004, 0.0, 0.0))   # B ends at 0.2 s, A at 0.3 s
s = pvstate.pv()
size = (900, 560)


def fluid_pressure(run, k):
    f = V.read_vtu(V.frames_of_run(run)[k][1])
    return np.asarray(f.arrays["pressure"])[f.fluid_mask()]


def check_state(name, rep, png):
    for problem in C.layout_problems(rep):
        T.check(False, "%s: %s" % (name, problem))
    T.check(not C.layout_problems(rep), "%s: one view, Point Gaussian, fluid in view and fitted, bar beside, time "
            "annotation (%s)" % (name, rep.get("time_text")))
    T.close(rep["gaussian_radius"], 0.5 * dx, 1e-12, "%s: Point Gaussian radius = dx/2" % name)
    frac, wh = C.image_check(png, rep["fluid_box_px"])
    T.check(wh == size and frac > 0.3, "%s: %.0f %% of the fluid region differs from the background (> 30 %%)"
            % (name, 100 * frac))


# (2) pressure: per-frame robust range
view = pvstate.pressure_state(a, view=pvstate.new_view(size))
for k, t in ((1, 0.1), (3, 0.30000000000000004)):
    pvstate.set_time(view, t)
    rep = C.inspect(s)
    lo, hi = np.percentile(fluid_pressure(a, k), pvstate.PRESSURE_PERCENTILES)
    T.check(np.allclose(rep["colour_range"], [lo, hi], rtol=1e-9),
            "pressure at t = %g: colour range %s = 1st-99th percentile of the frame (%.6g, %.6g)"
            % (t, np.round(rep["colour_range"], 3), lo, hi))
    T.check(rep["time_text"] == "t = %.3f s" % t, "pressure: time annotation '%s' at t = %g" % (rep["time_text"], t))
png = pvstate.screenshot(view, os.path.join(tmp, "pressure.png"), size)
check_state("pressure", rep, png)

# (1) free surface
s.ResetSession()
view = pvstate.free_surface_state(a, time=0.1, view=pvstate.new_view(size))
rep = C.inspect(s)
T.check(rep["colour_array"] == "velocity" and rep["time"] == 0.1, "free surface: coloured by speed at t = 0.1")
check_state("free_surface", rep, pvstate.screenshot(view, os.path.join(tmp, "fs.png"), size))

# (3) deviation: common times only, default the last common one, said in the picture
s.ResetSession()
view = pvstate.deviation_state(a, b, view=pvstate.new_view(size))
rep = C.inspect(s)
T.check(rep["timesteps"] == [0.0, 0.1, 0.2], "deviation: the animation steps through the common times %s"
        % rep["timesteps"])
T.check(rep["time"] == 0.2 and rep["time_text"] == "t = 0.200 s", "deviation: shows the last common time 0.2")
T.check("last time both runs have" in rep["note_text"] and "B at 0.2 s" in rep["note_text"]
        and "D_max = 0.004 m" in rep["note_text"], "deviation note: %s" % rep["note_text"])
check_state("deviation", rep, pvstate.screenshot(view, os.path.join(tmp, "dev.png"), size))

# a GUI-like start: the active view is the empty one ParaView opens with; the state uses it, no split
s.ResetSession()
v0 = s.CreateView("RenderView")
s.AssignViewToLayout(v0)
pvstate.pressure_state(a)
rep = C.inspect(s)
T.check(rep["views_per_layout"] == [1] and len(rep["layouts"]) == 1,
        "an existing empty view is reused (layouts %s, views %s)" % (rep["layouts"], rep["views_per_layout"]))
T.finish(tmp)
