"""State (5): waves (issue 31, docs/waves.md): the free-surface particles coloured by their elevation above the
still-water level (troughs blue, crests red; a range symmetric about 0, fixed over the run), the fluid pale.

    GUI:      VARSPH_RUN_DIR=RUN paraview --state=/path/to/varsph/paraview/states/elevation.py
              (or varsph paraview RUN --state elevation; without the variables: the working directory)
    pvpython: pvpython paraview/states/elevation.py RUN [--time T] [--range lo,hi] [--screenshot out.png]
See varsph/statecli.py and paraview/README.md.
"""
import os
import sys


def _varsph_on_path():
    """Put paraview/ (the varsph package) on sys.path: next to this file, else where the loaded plugin or
    $VARSPH_PARAVIEW_DIR / $PV_PLUGIN_PATH say (the GUI may run a state without __file__)."""
    here = [os.path.dirname(os.path.dirname(os.path.abspath(__file__)))] if "__file__" in globals() else []
    env = [os.environ.get("VARSPH_PARAVIEW_DIR", "")] + [os.path.dirname(os.path.normpath(p)) for p in
                                                         os.environ.get("PV_PLUGIN_PATH", "").split(os.pathsep) if p]
    for d in here + [p for p in sys.path if p] + env:
        if d and os.path.isfile(os.path.join(d, "varsph", "pvstate.py")):
            if d not in sys.path:
                sys.path.insert(0, d)
            return
    raise ImportError("cannot find the varsph package: load the varsph plugin (paraview/plugin/varsph_filters.py) "
                      "or set VARSPH_PARAVIEW_DIR=/path/to/varsph/paraview")


_varsph_on_path()
from varsph import statecli  # noqa: E402

statecli.main("elevation", __doc__)
