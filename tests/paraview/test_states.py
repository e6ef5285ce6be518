"""Each state script (paraview/states/*.py) loads a small synthetic run from another working directory
and renders a non-empty image: the PNG exists, has the requested size, and is not a single colour; given the
runs on the command line, and given them in $VARSPH_RUN_DIR / $VARSPH_OTHER_RUN_DIR as the GUI does.
Usage: xvfb-run -a -s -noreset pvpython test_states.py {free_surface|pressure|deviation}"""
import os
import subprocess
import sys

import tcommon as T
import synthetic as S

state = sys.argv[1]
tmp = T.workdir("state_" + state)
a = os.path.join(tmp, "run a")          # a space in the path on purpose
b = os.path.join(tmp, "run_b")
S.dam_break_run(a, nframes=3)
S.dam_break_run(b, nframes=3, shift=(0.004, 0.0, 0.0))
script = os.path.join(T.PARAVIEW_DIR, "states", state + ".py")
elsewhere = os.path.join(tmp, "cwd")
os.makedirs(elsewhere)
runs = [a] + ([b] if state == "deviation" else [])
env_runs = dict(os.environ, VARSPH_RUN_DIR=a, VARSPH_OTHER_RUN_DIR=b)
for how, args, env in (("runs as arguments", runs, None), ("runs from the environment", [], env_runs)):
    png = os.path.join(tmp, "shot %s.png" % how)
    cmd = [T.pvpython(), script] + args + ["--time", "0.1", "--screenshot", png, "--size", "640,400"]
    if state == "free_surface":
        cmd.append("--surface")
    p = subprocess.run(cmd, cwd=elsewhere, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120,
                       env=env)
    print(p.stdout[-3000:])
    if p.returncode < 0 and not os.path.isfile(png):
        # pvpython under Xvfb has been seen to abort at random (rarely, SIGABRT in the GL layer); one retry,
        # reported, so that a crash that repeats still fails the test
        print("WARNING: %s died with signal %d; retrying once" % (state, -p.returncode))
        p = subprocess.run(cmd, cwd=elsewhere, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                           timeout=120, env=env)
        print(p.stdout[-3000:])
    T.check(p.returncode == 0, "%s, %s: exits 0 (%d)" % (state, how, p.returncode))
    T.check(os.path.isfile(png), "%s, %s: wrote %s" % (state, how, png))
    if os.path.isfile(png):
        w, h, ncol, std, coloured = T.image_stats(png)
        T.check((w, h) == (640, 400), "image size %dx%d" % (w, h))
        T.check(ncol > 10 and std > 5.0, "image is not a single colour: %d colours, pixel std %.1f" % (ncol, std))
        T.check(coloured > 0.01, "colour-mapped particles cover %.1f %% of the image (> 1 %%)" % (100 * coloured))
T.finish(tmp)
