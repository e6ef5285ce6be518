"""A bundled state opened the way a ParaView user opens it: ``paraview --state=paraview/states/NAME.{py,pvsm}``
in the real GUI (under Xvfb), runs given by $VARSPH_RUN_DIR / $VARSPH_OTHER_RUN_DIR, the plugin found through
PV_PLUGIN_PATH, the Python 3.11 shim installed by install_compat.py --user. Checks: ParaView exits 0 and prints
no error or warning line; the GUI holds one layout with one view; the fluid is in view, fitted, drawn as Point
Gaussian discs of diameter dx, the colour bar beside it, the time annotated; the screenshot taken in the GUI
shows the fluid (its region differs from the background). Deviation: the last common time, said in the view.
With ``3d`` (issue 35): the runs are a tall 3D tank around shallow water and an obstacle (synthetic.tank3d_run),
and the GUI's screenshot must show the water: at least 5 % of the view left of the colour bar in the fluid's
colour map (viewcheck.colourmap_share; the walls drawn whole, as before issue 35, give 0.0 %: test_view3d.py).
open_flow (issue 32): the run is a short real run of the Poiseuille channel with an inlet and an outlet (the
solver and the scene given after the flavour), and the GUI's screenshot must show the inflow zone's orange.
elevation (issue 31): the same with a short real run of a wave flume (pipelines/bodies/box_in_waves_2d.json).
Usage: pvpython test_gui_states.py {free_surface|pressure|deviation} {py|pvsm} [3d]
       pvpython test_gui_states.py {open_flow|elevation} py VARSPH_EXECUTABLE SCENE.json"""
import os
import sys

import gui
import tcommon as T
import synthetic as S
import viewcheck as C

name, flavour = sys.argv[1], sys.argv[2]
three = sys.argv[3:] == ["3d"]
tmp = T.workdir("gui_%s_%s%s" % (name, flavour, "_3d" if three else ""))
a, b = os.path.join(tmp, "run a"), os.path.join(tmp, "run_b")
dx = 0.02
if name in ("open_flow", "elevation"):
    import subprocess
    p = subprocess.run([sys.argv[3], "run", sys.argv[4], "-o", a, "--set", "time.end=0.2", "--set", "output.every=0.1",
                        "--quiet", "--threads", "1"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    T.check(p.returncode == 0, "varsph run of the open channel: exit %d %s" % (p.returncode, p.stdout[-300:]))
    S.dam_break_run(b, nframes=3, dx=0.02)
    dx = 0.05 if name == "open_flow" else 0.02
elif three:
    S.tank3d_run(a, nframes=4, dx=0.02)
    S.tank3d_run(b, nframes=3, dx=0.02)
else:
    S.dam_break_run(a, nframes=4, dx=0.02)
    S.dam_break_run(b, nframes=3, dx=0.02, shift=(0.004, 0.0, 0.0))     # B ends at 0.2 s, A at 0.3 s
env = {"VARSPH_RUN_DIR": a, "VARSPH_OTHER_RUN_DIR": b, "PV_PLUGIN_PATH": os.path.join(T.PARAVIEW_DIR, "plugin"),
       "PYTHONUSERBASE": gui.shim_userbase(tmp)}
state = os.path.join(T.PARAVIEW_DIR, "states", "%s.%s" % (name, flavour))
rc, out, rep, shot, _ = gui.run(tmp, ["--state=" + state], env)
print(out[-4000:])
T.check(rc == 0, "paraview --state=%s exits 0 (%d)" % (os.path.basename(state), rc))
T.check(not gui.error_lines(out), "no error or warning lines in ParaView's output %s" % gui.error_lines(out)[:5])
T.check(rep is not None and rep.get("ok"), "the check ran in the GUI's Python shell: %s" % (rep or {}).get("error"))
if rep and rep.get("ok"):
    T.check(rep.get("plugin") is True, "the plugin is loaded (PV_PLUGIN_PATH)")
    problems = C.layout_problems(rep)
    if name == "elevation":  # by design the water is a pale surface under the coloured free-surface particles
        problems = [p for p in problems if "Point Gaussian" not in p]
    T.check(not problems, "%s.%s in the GUI: one view, fluid fitted, Point Gaussian, bar beside, time (%s) %s"
            % (name, flavour, rep.get("time_text"), problems))
    if name != "elevation":
        T.close(rep.get("gaussian_radius", 0), 0.5 * dx, 1e-12, "particle discs of diameter dx")
    if name == "deviation":
        T.check(rep.get("time_text") == "t = 0.200 s" and "last time both runs have" in (rep.get("note_text") or ""),
                "deviation at the last common time, said in the view: %s" % rep.get("note_text"))
    if shot:
        frac, wh = C.image_check(shot, rep["fluid_box_px"])
        T.check(frac > 0.3, "GUI screenshot %dx%d: %.0f %% of the fluid region differs from the background"
                % (wh[0], wh[1], 100 * frac))
        if name == "open_flow":
            share = C.colourmap_share(shot, [[0.98, 0.55, 0.10]], rep["bar_position"][0] - 0.01)
            T.check(share >= 0.01, "open_flow in the GUI: the inflow zone's orange covers %.1f %% of the view (>= 1 %%)"
                    % (100 * share))
        if three:
            share = C.colourmap_share(shot, rep["lut_colours"], rep["bar_position"][0] - 0.01)
            T.check(share >= 0.05, "3D run in the GUI: %.1f %% of the view left of the bar in the fluid's colour "
                    "map (>= 5 %%)" % (100 * share))
    else:
        T.check(False, "the GUI wrote a screenshot")
T.finish(tmp)
