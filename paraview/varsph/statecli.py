"""What a state script (paraview/states/*.py) does, wherever it is run.

- GUI: ``paraview --state=paraview/states/NAME.py`` or File > Load State (or the Python Shell's Run
  Script): ParaView passes no arguments, so the run is ``$VARSPH_RUN_DIR`` (run B of the deviation state:
  ``$VARSPH_OTHER_RUN_DIR``) or the working directory; the state is built in its own layout and left to the
  user (no event loop of our own: ParaView has one).
- pvpython: ``pvpython paraview/states/NAME.py RUN [RUN_B] [--time T] [--range lo,hi] [--size w,h]
  [--screenshot out.png]``; with --screenshot the picture is written and pvpython exits, else an interactive
  window opens (needs a display).
"""
import argparse
import os
import sys


def from_command_line():
    """True in pvpython/pvbatch running the script (argv[0] is the script); False in the GUI (argv == [''])."""
    return bool(sys.argv and sys.argv[0])


def parse(name, description, argv=None):
    two = name == "deviation"
    p = argparse.ArgumentParser(prog="pvpython paraview/states/%s.py" % name, description=description,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run", nargs="?", default=None, help="run directory (or its .pvd); default $VARSPH_RUN_DIR, "
                   "else the working directory")
    if two:
        p.add_argument("other", nargs="?", default=None, help="run B; default $VARSPH_OTHER_RUN_DIR")
    p.add_argument("--time", type=float, default=None,
                   help="time to show (nearest frame%s; default the last)" % (" both runs have" if two else ""))
    if name == "free_surface":
        p.add_argument("--surface", action="store_true", help="also draw the reconstructed surface")
    if name == "pressure":
        p.add_argument("--smoothed", action="store_true", help="colour the SPH-smoothed pressure")
    p.add_argument("--range", default=None, help="fixed colour range 'lo,hi' (default: robust, per frame)")
    p.add_argument("--size", default="1200,700", help="image size 'w,h' (default 1200,700)")
    p.add_argument("--screenshot", default=None, help="write a PNG here and exit")
    a = p.parse_args(sys.argv[1:] if argv is None else argv)
    try:
        a.range = tuple(float(v) for v in a.range.split(",")) if a.range else None
        a.size = tuple(int(v) for v in a.size.split(","))
        if (a.range and len(a.range) != 2) or len(a.size) != 2:
            raise ValueError
    except ValueError:
        p.error("--range takes 'lo,hi' and --size 'w,h'")
    return a


def build(name, args=None, view=None):
    from varsph import pvstate
    a = args
    if name == "free_surface":
        return pvstate.free_surface_state(a.run if a else None, time=a.time if a else None,
                                          surface=bool(a and a.surface), view=view)
    if name == "pressure":
        return pvstate.pressure_state(a.run if a else None, time=a.time if a else None,
                                      prange=a.range if a else None, smoothed=bool(a and a.smoothed), view=view)
    if name == "open_flow":
        return pvstate.open_flow_state(a.run if a else None, time=a.time if a else None,
                                       vrange=a.range if a else None, view=view)
    if name == "elevation":
        return pvstate.elevation_state(a.run if a else None, time=a.time if a else None,
                                       erange=a.range if a else None, view=view)
    return pvstate.deviation_state(a.run if a else None, a.other if a else None, time=a.time if a else None,
                                   drange=a.range if a else None, view=view)


def main(name, description):
    from varsph import pvstate
    if not from_command_line():
        try:                 # the GUI: run from the environment / working directory, view in its own layout
            build(name)
        except (OSError, ValueError) as e:
            print("varsph %s state: %s" % (name, e), file=sys.stderr)
        return
    a = parse(name, description)
    try:
        view = build(name, a, view=pvstate.new_view(a.size, name="varsph " + name.replace("_", " ")))
    except (OSError, ValueError) as e:
        print("%s: error: %s" % (name, e), file=sys.stderr)
        pvstate.hard_exit(2)
    if a.screenshot:
        print("wrote", pvstate.screenshot(view, a.screenshot, a.size))
        pvstate.hard_exit(0)
    from paraview import simple
    simple.Interact(view)   # pvpython with a display: an interactive window
