"""Command line shared by the state scripts: RUN_DIR [OTHER_RUN] [--time T] [--screenshot out.png]."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def parse(description, two_runs=False, argv=None):
    p = argparse.ArgumentParser(description=description)
    p.add_argument("run", nargs="?", default=os.environ.get("VARSPH_RUN_DIR"),
                   help="run directory (or its .pvd); default $VARSPH_RUN_DIR")
    if two_runs:
        p.add_argument("other", nargs="?", default=os.environ.get("VARSPH_OTHER_RUN_DIR"),
                       help="second run (B), default $VARSPH_OTHER_RUN_DIR")
    p.add_argument("--time", type=float, default=None, help="time to show (nearest frame; default the last)")
    p.add_argument("--screenshot", default=None, help="write a PNG here and exit")
    p.add_argument("--range", default=None, help="colour range 'lo,hi' (default: see docs/paraview.md)")
    p.add_argument("--size", default="1200,700", help="image size 'w,h'")
    args = p.parse_args(sys.argv[1:] if argv is None else argv)
    if not args.run or (two_runs and not args.other):
        p.error("give the run director%s on the command line (or $VARSPH_RUN_DIR%s)"
                % (("ies A and B", " / $VARSPH_OTHER_RUN_DIR") if two_runs else ("y", "")))
    args.range = tuple(float(v) for v in args.range.split(",")) if args.range else None
    args.size = tuple(int(v) for v in args.size.split(","))
    return args


def finish(view, args):
    from varsph import pvstate
    if args.screenshot:
        print("wrote", pvstate.screenshot(view, args.screenshot, args.size))
        pvstate.hard_exit(0)
    else:
        from paraview import simple
        simple.Render(view)
        try:  # interactive window when run from plain pvpython with a display
            simple.Interact(view)
        except Exception:
            pass
