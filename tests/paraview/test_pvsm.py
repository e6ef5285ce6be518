"""State files (.pvsm). make_pvsm.py writes them for one run (absolute paths) or --portable (no path: the runs
come from $VARSPH_RUN_DIR / $VARSPH_OTHER_RUN_DIR when loaded). Loaded in pvpython: a run-specific state reads
its run; a portable state, and the ones in paraview/states/, open other runs (another NAME, another directory,
two runs for deviation), and after the first time change (what the GUI does right after loading a state) the
colour range is the frame's, the particles have the run's dx and the camera fits the run.
Part "bundled" (fast tier): the states in paraview/states/ on other runs. Part "make" (validation tier, two more
pvpython sessions): make_pvsm.py writes both kinds, and a run-specific state reads its run.
Usage: xvfb-run -a -s -noreset pvpython test_pvsm.py {bundled|make}"""
import glob
import json
import os
import re
import subprocess
import sys

import numpy as np

import tcommon as T
import synthetic as S
import viewcheck as C
import varsph as V

part = sys.argv[1] if len(sys.argv) > 1 else "bundled"
tmp = T.workdir("pvsm_" + part)
a, b = os.path.join(tmp, "a"), os.path.join(tmp, "b")
S.dam_break_run(a, nframes=3)
S.dam_break_run(b, nframes=3, shift=(0.004, 0.0, 0.0))
other = os.path.join(tmp, "elsewhere", "another run")             # another directory, another NAME, 4 frames
S.dam_break_run(other, nframes=4, dx=0.01, name="wider", shift=(0.05, 0.0, 0.0))
make = os.path.join(T.PARAVIEW_DIR, "states", "make_pvsm.py")
if part == "make":
    for label, extra, out in (("run-specific", [], os.path.join(tmp, "specific")),
                              ("portable", ["--portable"], os.path.join(tmp, "portable"))):
        p = subprocess.run([T.pvpython(), make, a, "--other", b, "-o", out] + extra, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True, timeout=300)
        print(p.stdout[-2000:])
        T.check(p.returncode == 0, "make_pvsm.py %s: exit status 0 (%d)" % (label, p.returncode))
for f in glob.glob(os.path.join(tmp, "portable", "*.pvsm")) + glob.glob(os.path.join(T.PARAVIEW_DIR, "states", "*.pvsm")):
    with open(f) as fh:
        paths = sorted(set(re.findall(r'value="(/[^"/]+/[^"]*)"', fh.read())))
    T.check(not paths, "%s holds no absolute path %s" % (os.path.relpath(f, tmp) if f.startswith(tmp) else f, paths[:3]))

def load(path, env):
    """Load a state in a fresh pvpython (several sessions in one process upset the OpenGL of pvpython 5.11 under
    Xvfb), tick the time as the GUI does after loading, and return viewcheck's report and a screenshot."""
    png = os.path.join(tmp, "%s_%d.png" % (os.path.basename(path), len(os.listdir(tmp))))
    out = png + ".json"
    code = ("import json, os, sys; sys.path[:0] = [%r, %r]\n"
            "import viewcheck as C\nfrom varsph import pvstate\ns = pvstate.pv()\n"
            "s.LoadState(%r)\n"
            "s.GetAnimationScene().SMProxy.UpdateProperty('AnimationTime', 1)  # as the GUI after loading a state\n"
            "rep = C.inspect(s)\nsrc = s.FindSource('run') or s.FindSource('A')\n"
            "rep['resolved'] = src.GetProperty('ResolvedFile').GetElement(0)\n"
            "rep['run_directory'] = src.GetPropertyValue('RunDirectory')\n"
            "s.SaveScreenshot(%r, s.GetActiveView(), ImageResolution=list(rep['view_size']))\n"
            "json.dump(rep, open(%r, 'w'), default=str)\npvstate.hard_exit(0)\n") % (T.HERE, T.PARAVIEW_DIR, path, png, out)
    p = subprocess.run([T.pvpython(), "-c", code], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       timeout=300, env=dict(os.environ, **env))
    if p.returncode != 0 or not os.path.isfile(out):
        print(p.stdout[-3000:])
        T.check(False, "loading %s: exit status %d" % (path, p.returncode))
        return None, None
    with open(out) as f:
        return json.load(f), png


def frame_percentiles(run, k, pct=(1.0, 99.0)):
    f = V.read_vtu(V.frames_of_run(run)[k][1])
    return np.percentile(np.asarray(f.arrays["pressure"])[f.fluid_mask()], pct)


if part == "make":
    rep, _ = load(os.path.join(tmp, "specific", "pressure.pvsm"), {})
    T.check(rep and rep["run_directory"] == a, "run-specific pressure.pvsm reads %s" % (rep or {}).get("run_directory"))
    T.finish(tmp)
    os._exit(0)      # the bundled states are the fast part's
bundled = os.path.join(T.PARAVIEW_DIR, "states")
for name in ("pressure", "free_surface"):
    rep, png = load(os.path.join(bundled, name + ".pvsm"), {"VARSPH_RUN_DIR": other})
    if rep is None:
        continue
    T.check(rep["resolved"] == os.path.join(other, "wider.pvd"),
            "paraview/states/%s.pvsm with $VARSPH_RUN_DIR reads %s" % (name, rep["resolved"]))
    T.check(rep["time"] == 0.0 and rep["time_text"] == "t = 0.000 s", "%s.pvsm opens at the first frame" % name)
    T.check(not C.layout_problems(rep), "%s.pvsm on another run: %s" % (name, C.layout_problems(rep) or "view fitted"))
    T.close(rep["gaussian_radius"], 0.5 * 0.01, 1e-12, "%s.pvsm: particles of that run's dx" % name)
    if name == "pressure":
        T.check(np.allclose(rep["colour_range"], frame_percentiles(other, 0), rtol=1e-9),
                "pressure.pvsm on another run: colour range %s = that run's frame percentiles"
                % np.round(rep["colour_range"], 2))
    frac, _ = C.image_check(png, rep["fluid_box_px"])
    T.check(frac > 0.3, "%s.pvsm: fluid region drawn (%.0f %% non-background)" % (name, 100 * frac))
# deviation of two runs: compared at the last common time, whatever the time saved in the state
rep, _ = load(os.path.join(bundled, "deviation.pvsm"), {"VARSPH_RUN_DIR": a, "VARSPH_OTHER_RUN_DIR": b})
if rep:
    T.check(rep["time_text"] == "t = 0.200 s" and "last time both runs have" in rep["note_text"],
            "deviation.pvsm on runs A, B: %s / %s" % (rep["time_text"], rep["note_text"]))
    T.check(not C.layout_problems(rep), "deviation.pvsm: %s" % (C.layout_problems(rep) or "view fitted"))
T.finish(tmp)
