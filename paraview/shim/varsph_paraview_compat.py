"""Lets ParaView 5.11 load Python plugins on Python >= 3.11 (Debian 12 / Ubuntu 23.04+ packages).

ParaView's ``paraview.detail.pythonalgorithm``, which every Python plugin and ``paraview.util.vtkAlgorithm``
go through, does ``from inspect import getargspec``; Python 3.11 removed ``getargspec``, so Tools > Manage
Plugins, ``PV_PLUGIN_PATH``, ``--plugins`` and ``LoadPlugin`` all fail with "Failed to import
paraview.detail.pythonalgorithm". ParaView >= 5.12 uses ``getfullargspec`` and does not need this.

Installed into ParaView's Python site directory with a one-line ``varsph_paraview_compat.pth``
(``paraview/install_compat.py``), so that it runs at interpreter start-up in pvpython, pvbatch and the GUI.
It only registers an import hook: ``inspect`` is patched the moment ``paraview.detail.pythonalgorithm`` is
first imported, and only where ``getargspec`` is missing; other Python programs are not touched.
The plugin does not depend on it being installed (``varsph.compat.load_plugin`` patches by itself).
"""
import sys

_TRIGGER = "paraview.detail.pythonalgorithm"


def patch_inspect():
    """Give ``inspect`` a ``getargspec`` built on ``getfullargspec`` (ParaView reads only ``.args``)."""
    import collections
    import inspect
    if hasattr(inspect, "getargspec"):
        return False
    arg_spec = collections.namedtuple("ArgSpec", "args varargs keywords defaults")

    def getargspec(func):
        s = inspect.getfullargspec(func)
        return arg_spec(s.args, s.varargs, s.varkw, s.defaults)

    inspect.getargspec = getargspec
    return True


class _PatchBeforeParaViewAlgorithms:
    """Meta-path hook: finds nothing itself, patches ``inspect`` just before ParaView's module loads."""

    def find_spec(self, name, path=None, target=None):
        if name == _TRIGGER:
            patch_inspect()
            try:
                sys.meta_path.remove(self)
            except ValueError:
                pass
        return None


def install():
    if sys.version_info >= (3, 11) and not any(isinstance(f, _PatchBeforeParaViewAlgorithms) for f in sys.meta_path):
        if _TRIGGER in sys.modules:
            patch_inspect()
        else:
            sys.meta_path.insert(0, _PatchBeforeParaViewAlgorithms())


install()
