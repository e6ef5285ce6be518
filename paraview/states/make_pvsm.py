"""Write ParaView state files (.pvsm) of the three states for a run, to reuse on other runs.

    pvpython paraview/states/make_pvsm.py RUN_DIR [--other RUN_B] [-o OUTDIR]      (OUTDIR default RUN_DIR/post)

writes free_surface.pvsm, pressure.pvsm and, with --other, deviation.pvsm. Load one in the GUI with
File > Load State, "Load State Data File Options": "Search files under specified directory" and pick another
run directory whose .pvd has the same NAME (ParaView matches the files by name); "Choose File Names" for any
other run, and always for deviation.pvsm (two readers). The varsph plugin must be loaded first (the free
surface and deviation states use its filters). In pvpython:
    from varsph.compat import load_plugin; load_plugin(globals())
    LoadState("free_surface.pvsm", data_directory="/path/to/other/run")
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from varsph import pvstate  # noqa: E402

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("run")
ap.add_argument("--other", default=None, help="run B for deviation.pvsm")
ap.add_argument("-o", "--outdir", default=None)
a = ap.parse_args()
out = a.outdir or os.path.join(a.run, "post")
os.makedirs(out, exist_ok=True)
s = pvstate.pv()
builds = [("free_surface", lambda v: pvstate.free_surface_state(a.run, view=v)),
          ("pressure", lambda v: pvstate.pressure_state(a.run, view=v))]
if a.other:
    builds.append(("deviation", lambda v: pvstate.deviation_state(a.run, a.other, view=v)))
for name, build in builds:
    s.ResetSession()
    build(pvstate.new_view())
    path = os.path.join(out, name + ".pvsm")
    s.SaveState(path)
    print("wrote", path)
pvstate.hard_exit(0)
