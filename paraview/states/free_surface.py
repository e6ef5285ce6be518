"""State (1): free-surface particles coloured by pressure.

    pvpython paraview/states/free_surface.py RUN_DIR [--time T] [--surface] [--screenshot out.png]
(rendering off-screen: xvfb-run -a pvpython ...).  GUI: View > Python Shell > Run Script, with
VARSPH_RUN_DIR set in the environment of ParaView.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _state_cli  # noqa: E402

surface = "--surface" in sys.argv
args = _state_cli.parse(__doc__, argv=[a for a in sys.argv[1:] if a != "--surface"])
from varsph import pvstate  # noqa: E402

view = pvstate.free_surface_state(args.run, time=args.time, surface=surface, prange=args.range,
                                  view=pvstate.new_view(args.size))
_state_cli.finish(view, args)
