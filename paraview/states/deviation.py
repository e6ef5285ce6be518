"""State (3): deviation between two runs, run A's fluid coloured by |q_A - q_B| (particles matched by id).

    pvpython paraview/states/deviation.py RUN_A RUN_B [--time T] [--range lo,hi] [--screenshot out.png]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _state_cli  # noqa: E402

args = _state_cli.parse(__doc__, two_runs=True)
from varsph import pvstate  # noqa: E402

view = pvstate.deviation_state(args.run, args.other, time=args.time, drange=args.range,
                               view=pvstate.new_view(args.size))
_state_cli.finish(view, args)
