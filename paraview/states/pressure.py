"""State (2): fluid pressure with a fixed colour map (range of the first frame, or --range lo,hi) and bar.

    pvpython paraview/states/pressure.py RUN_DIR [--time T] [--range lo,hi] [--screenshot out.png]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _state_cli  # noqa: E402

args = _state_cli.parse(__doc__)
from varsph import pvstate  # noqa: E402

view = pvstate.pressure_state(args.run, time=args.time, prange=args.range, view=pvstate.new_view(args.size))
_state_cli.finish(view, args)
