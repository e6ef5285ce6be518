"""The ParaView 5.11 / Python 3.11 plugin shim (paraview/shim/varsph_paraview_compat.py) and its installer
(paraview/install_compat.py): installed into a user site it is active at start-up, lazily (inspect untouched
until ParaView's pythonalgorithm is imported), makes ParaView's own LoadPlugin and PV_PLUGIN_PATH load the
plugin in pvpython, and uninstalls cleanly; the launcher's usercustomize.py on PYTHONPATH does the same
without an installation. Usage: pvpython test_compat.py"""
import os
import subprocess

import tcommon as T

tmp = T.workdir("compat")
installer = os.path.join(T.PARAVIEW_DIR, "install_compat.py")
plugin_dir = os.path.join(T.PARAVIEW_DIR, "plugin")
ub = os.path.join(tmp, "user base")
empty = os.path.join(tmp, "empty")


def py(code, **env):
    e = dict(os.environ, PV_PLUGIN_PATH="", PYTHONPATH="")
    e.update(env)
    p = subprocess.run([T.pvpython(), "-c", code], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       timeout=120, env=e)
    return p.returncode, p.stdout


def installer_run(*args):
    p = subprocess.run([T.pvpython(), installer] + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, timeout=120, env=dict(os.environ, PYTHONUSERBASE=ub))
    return p.returncode, p.stdout


rc, out = installer_run("--user", "--check")
T.check(rc == 1, "--check before installing: exit 1 (%d) %s" % (rc, out.strip()))
rc, out = installer_run("--user")
T.check(rc == 0 and "installed" in out, "install_compat.py --user: %s" % out.strip())
rc, out = installer_run("--user")
T.check(rc == 0, "installing twice is harmless")
rc, out = installer_run("--user", "--check")
T.check(rc == 0, "--check after installing: exit 0 (%s)" % out.strip())

probe = ("import inspect; before = hasattr(inspect, 'getargspec'); import paraview.detail.pythonalgorithm; "
         "print('SHIM', before, hasattr(inspect, 'getargspec'))")
rc, out = py(probe, PYTHONUSERBASE=ub)
T.check(rc == 0 and "SHIM False True" in out,
        "with the shim: inspect untouched until ParaView's pythonalgorithm is imported, which then imports (%s)"
        % out.strip()[-200:])
rc, out = py("import paraview.detail.pythonalgorithm; print('IMPORTED')", PYTHONUSERBASE=empty)
rc_sys, _ = subprocess.run([T.pvpython(), installer, "--check"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           text=True, timeout=120).returncode, None
needs = "getargspec" in open(__import__("paraview.detail", fromlist=["x"]).__path__[0] + "/pythonalgorithm.py").read()
if needs and rc_sys != 0:
    T.check(rc != 0 and "getargspec" in out, "without any shim this ParaView cannot import its pythonalgorithm "
            "(the failure the shim fixes): %s" % out.strip().splitlines()[-1:])
else:
    print("note: the shim is installed system-wide or this ParaView needs none; the failure without it is not shown")

load = ("from paraview.simple import *\nLoadPlugin(%r, remote=False, ns=globals())\n"
        "print('DEFINED', 'varsphFreeSurface' in globals())" % os.path.join(plugin_dir, "varsph_filters.py"))
rc, out = py(load, PYTHONUSERBASE=ub)
T.check(rc == 0 and "DEFINED True" in out, "with the shim, ParaView's own LoadPlugin loads the plugin: %s"
        % out.strip()[-200:])
defined = ("from paraview import servermanager as sm\nimport paraview.simple\n"
           "pdm = sm.vtkSMProxyManager.GetProxyManager().GetActiveSessionProxyManager().GetProxyDefinitionManager()\n"
           "print('DEFINED', bool(pdm.HasDefinition('filters', 'varsphFreeSurface')))")
rc, out = py(defined, PYTHONUSERBASE=ub, PV_PLUGIN_PATH=plugin_dir)
T.check(rc == 0 and "DEFINED True" in out, "with the shim, PV_PLUGIN_PATH=paraview/plugin loads the plugin at "
        "start-up: %s" % out.strip()[-200:])
rc, out = py(probe, PYTHONUSERBASE=empty, PYTHONPATH=os.path.join(T.PARAVIEW_DIR, "shim"))
T.check(rc == 0 and "SHIM False True" in out, "no installation, paraview/shim on PYTHONPATH (what varsph paraview "
        "does): usercustomize.py activates the shim (%s)" % out.strip()[-200:])
site_dir = os.path.join(ub, "lib", "python%d.%d" % __import__("sys").version_info[:2], "site-packages")
T.check(sorted(os.listdir(site_dir)) == ["varsph_paraview_compat.pth", "varsph_paraview_compat.py"],
        "installed exactly the module and the .pth into %s" % site_dir)
rc, out = installer_run("--user", "--uninstall")
T.check(rc == 0 and os.listdir(site_dir) == [], "--uninstall removes both files (%s)" % os.listdir(site_dir))
T.finish(tmp)
