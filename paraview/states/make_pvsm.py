"""Write the states as ParaView XML state files (.pvsm).

    pvpython paraview/states/make_pvsm.py RUN_DIR [--other RUN_B] [-o OUTDIR] [--portable]

writes free_surface.pvsm and pressure.pvsm (and deviation.pvsm with --other) into OUTDIR (default
RUN_DIR/post). They read their runs through the plugin's *varsph Run* source:
- default: the runs given here, by absolute path (a state of these runs);
- --portable: no path at all; at load time the run is $VARSPH_RUN_DIR (run B: $VARSPH_OTHER_RUN_DIR), else
  the working directory; saved at the first frame (a time every run has: loading it then fits the camera
  and the colours to the run found), the deviation state comparing at the last common time whatever the
  animation time. paraview/states/*.pvsm in the repository are written this way, so that
      VARSPH_RUN_DIR=/some/run paraview --state=paraview/states/pressure.pvsm
  opens any run (the plugin must be loaded at start-up: Auto Load, PV_PLUGIN_PATH, or `varsph paraview`).
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from varsph import pvstate  # noqa: E402


def _forget_paths(path):
    """Drop the values of the information-only ResolvedFile property (the runs used to build the state;
    ParaView never reads them back) so that a portable state holds no path of the machine that made it."""
    import re
    with open(path) as f:
        text = f.read()
    text = re.sub(r'(<Property name="ResolvedFile" id="[^"]*") number_of_elements="1">\s*<Element index="0" value="[^"]*"/>',
                  r'\1 number_of_elements="0">', text)
    with open(path, "w") as f:
        f.write(text)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--other", default=None, help="run B: also write deviation.pvsm")
    ap.add_argument("-o", "--outdir", default=None)
    ap.add_argument("--portable", action="store_true", help="store no run path (see above)")
    a = ap.parse_args(argv)
    out = a.outdir or os.path.join(a.run, "post")
    os.makedirs(out, exist_ok=True)
    if a.portable:   # the runs the states are built on, found the way a load will find them
        os.environ[pvstate.ENV_RUN] = os.path.abspath(a.run)
        if a.other:
            os.environ[pvstate.ENV_OTHER] = os.path.abspath(a.other)
    s = pvstate.pv()
    builds = [("free_surface", lambda v: pvstate.free_surface_state(a.run, view=v, portable=a.portable)),
              ("pressure", lambda v: pvstate.pressure_state(a.run, view=v, portable=a.portable))]
    if a.other:
        builds.append(("deviation", lambda v: pvstate.deviation_state(a.run, a.other, view=v, portable=a.portable)))
    for name, build in builds:
        s.ResetSession()
        view = build(pvstate.new_view((1200, 700), name="varsph " + name.replace("_", " ")))
        if a.portable:   # saved at the first frame: a time every run has, so the view updates when loaded
            pvstate.set_time(view, list(s.GetTimeKeeper().TimestepValues)[0])
        path = os.path.join(out, name + ".pvsm")
        s.SaveState(path)
        if a.portable:
            _forget_paths(path)
        print("wrote", path)
    return 0


if __name__ == "__main__":
    pvstate.hard_exit(main())
