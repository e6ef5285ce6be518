"""`varsph paraview` without starting ParaView (--dry-run): the environment and the command it would run, and
the clear exit-2 errors for what it cannot open. Usage: pvpython test_launcher.py VARSPH_EXECUTABLE"""
import os
import subprocess
import sys

import tcommon as T
import synthetic as S

exe = sys.argv[1]
tmp = T.workdir("launcher")
a, b = os.path.join(tmp, "run a"), os.path.join(tmp, "b")
S.dam_break_run(a, nframes=2)
S.dam_break_run(b, nframes=2)


def launch(*args):
    p = subprocess.run([exe, "paraview"] + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                       timeout=60, cwd=tmp)
    return p.returncode, p.stdout, p.stderr


rc, out, err = launch("run a", "--dry-run")
lines = dict(line.split("=", 1) for line in out.splitlines() if "=" in line and not line.startswith("paraview"))
T.check(rc == 0, "dry run exits 0 (%d) %s" % (rc, err))
T.check(lines.get("VARSPH_RUN_DIR") == a, "VARSPH_RUN_DIR = the absolute run directory (%s)" % lines.get("VARSPH_RUN_DIR"))
T.check(lines.get("PV_PLUGIN_PATH", "").split(":")[0] == os.path.join(T.PARAVIEW_DIR, "plugin"),
        "PV_PLUGIN_PATH starts with paraview/plugin (%s)" % lines.get("PV_PLUGIN_PATH"))
T.check(lines.get("PYTHONPATH", "").split(":")[0] == os.path.join(T.PARAVIEW_DIR, "shim"),
        "PYTHONPATH starts with paraview/shim (the launcher's own getargspec fix)")
T.check(out.strip().splitlines()[-1] == "paraview --state=" + os.path.join(T.PARAVIEW_DIR, "states", "pressure.py"),
        "default: the pressure state (%s)" % out.strip().splitlines()[-1])
rc, out, err = launch(a, b, "--dry-run")
T.check(rc == 0 and out.strip().endswith("states/deviation.py") and ("VARSPH_OTHER_RUN_DIR=" + b) in out,
        "two runs: the deviation state, run B in VARSPH_OTHER_RUN_DIR")
rc, out, err = launch(a, "--state", "free_surface.pvsm", "--paraview", "/opt/pv/bin/paraview", "--dry-run")
T.check(rc == 0 and out.strip().endswith("/opt/pv/bin/paraview --state=" + os.path.join(T.PARAVIEW_DIR, "states",
                                                                                    "free_surface.pvsm")),
        "--state NAME.pvsm and --paraview EXE: %s" % out.strip().splitlines()[-1])
for args, what in (([os.path.join(tmp, "nothing here"), "--dry-run"], "is not a run directory"),
                   ([a, "--state", "nonsense", "--dry-run"], "no such state"),
                   ([a, "--state", "deviation", "--dry-run"], "give RUN_B"),
                   ([a, "--paraview", os.path.join(tmp, "no-paraview")], "cannot start")):
    rc, out, err = launch(*args)
    T.check(rc == 2 and what in err and "error" in err, "%s: exit 2, '%s' (%s)" % (args[:3], what, err.strip()))
T.finish(tmp)
