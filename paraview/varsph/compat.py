"""Compatibility with the ParaView in use, and loading the plugin from Python.

Debian/Ubuntu's ParaView 5.11 runs on Python 3.11, where ``inspect.getargspec`` no longer exists, but
``paraview.detail.pythonalgorithm`` (behind every Python plugin and ``paraview.util.vtkAlgorithm``) still
imports it. ``paraview/install_compat.py`` installs a start-up shim for the GUI and every ParaView Python
(paraview/shim/varsph_paraview_compat.py); ``patch_inspect()`` here does the same inside the current
process, so pvpython scripts work without the shim. ParaView 5.12 and later need neither.
"""
import collections
import inspect
import os

_ArgSpec = collections.namedtuple("ArgSpec", "args varargs keywords defaults")

PARAVIEW_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))   # .../paraview
PLUGIN_DIR = os.path.join(PARAVIEW_DIR, "plugin")                           # PV_PLUGIN_PATH points here


def patch_inspect():
    if not hasattr(inspect, "getargspec"):
        def getargspec(func):
            s = inspect.getfullargspec(func)
            return _ArgSpec(s.args, s.varargs, s.varkw, s.defaults)
        inspect.getargspec = getargspec


def plugin_path():
    return os.path.join(PLUGIN_DIR, "varsph_filters.py")


def plugin_loaded():
    """True when the varsph proxies are defined in the active ParaView session."""
    from paraview import servermanager as sm
    pxm = sm.vtkSMProxyManager.GetProxyManager().GetActiveSessionProxyManager()
    return bool(pxm) and bool(pxm.GetProxyDefinitionManager().HasDefinition("filters", "varsphFreeSurface"))


def load_plugin(ns=None):
    """Patch inspect if needed and load the varsph ParaView plugin (filters appear in ``ns`` if given).
    Loading twice is harmless (ParaView skips a plugin it has)."""
    patch_inspect()
    from paraview.simple import LoadPlugin
    return LoadPlugin(plugin_path(), remote=False, ns=ns)
