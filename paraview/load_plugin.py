"""Load the varsph filters into ParaView.

GUI: View > Python Shell > Run Script > paraview/load_plugin.py  (needed once per session where the
plain Tools > Manage Plugins > Load New fails with "Failed to import paraview.detail.pythonalgorithm",
i.e. ParaView 5.11 on Python 3.11 as shipped by Debian/Ubuntu).
pvpython: exec(open('/path/to/paraview/load_plugin.py').read())
"""
import os
import sys


def _find_here():
    if "__file__" in globals():
        return os.path.dirname(os.path.abspath(__file__))
    for d in (os.environ.get("VARSPH_PARAVIEW_DIR", ""), os.getcwd(), os.path.join(os.getcwd(), "paraview")):
        if d and os.path.isfile(os.path.join(d, "varsph_filters.py")):
            return os.path.abspath(d)
    raise RuntimeError("cannot locate paraview/varsph_filters.py: set VARSPH_PARAVIEW_DIR or run, in the "
                       "Python shell: import sys; sys.path.insert(0, '/path/to/varsph/paraview'); "
                       "from varsph.compat import load_plugin; load_plugin(globals())")


_here = _find_here()
if _here not in sys.path:
    sys.path.insert(0, _here)
from varsph.compat import load_plugin  # noqa: E402

load_plugin(ns=globals())
print("varsph filters loaded from", os.path.join(_here, "varsph_filters.py"))
