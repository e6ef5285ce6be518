"""Python imports ``usercustomize`` at start-up when it is on sys.path. `varsph paraview` puts this directory on
PYTHONPATH, so the ParaView it starts gets the plugin fix of varsph_paraview_compat (see there) without
paraview/install_compat.py having been run. Not installed anywhere."""
import varsph_paraview_compat  # noqa: F401
