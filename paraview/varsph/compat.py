"""Compatibility shims for the ParaView in use.

Debian/Ubuntu's ParaView 5.11 runs on Python 3.11, where ``inspect.getargspec`` no longer exists, but
``paraview.detail.pythonalgorithm`` (behind every Python plugin and ``paraview.util.vtkAlgorithm``) still
imports it: loading any Python plugin then fails with "Failed to import paraview.detail.pythonalgorithm".
``patch_inspect()`` restores a ``getargspec`` built on ``getfullargspec`` (the plugin code only reads
``.args``); it must run in the process before the plugin is loaded.
"""
import collections
import inspect

_ArgSpec = collections.namedtuple("ArgSpec", "args varargs keywords defaults")


def patch_inspect():
    if not hasattr(inspect, "getargspec"):
        def getargspec(func):
            s = inspect.getfullargspec(func)
            return _ArgSpec(s.args, s.varargs, s.varkw, s.defaults)
        inspect.getargspec = getargspec


def plugin_path():
    import os
    return os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "varsph_filters.py")


def load_plugin(ns=None):
    """Patch inspect if needed and load the varsph ParaView plugin (filters appear in ``ns`` if given)."""
    patch_inspect()
    from paraview.simple import LoadPlugin
    return LoadPlugin(plugin_path(), remote=False, ns=ns)
