"""Load the varsph filters into ParaView.

GUI: View > Python Shell > Run Script > paraview/load_plugin.py  (needed once per session where the
plain Tools > Manage Plugins > Load New fails with "Failed to import paraview.detail.pythonalgorithm",
i.e. ParaView 5.11 on Python 3.11 as shipped by Debian/Ubuntu).
pvpython: exec(open('/path/to/paraview/load_plugin.py').read())
"""
import os
import sys

_here = os.path.dirname(os.path.abspath(__file__)) if "__file__" in globals() else os.getcwd()
if _here not in sys.path:
    sys.path.insert(0, _here)
from varsph.compat import load_plugin  # noqa: E402

load_plugin(ns=globals())
print("varsph filters loaded from", os.path.join(_here, "varsph_filters.py"))
