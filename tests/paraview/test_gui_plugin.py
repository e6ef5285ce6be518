"""The plugin loaded the ways ParaView users load plugins, in the real GUI (under Xvfb), with the Python 3.11
start-up shim installed by paraview/install_compat.py --user (Debian 12's ParaView 5.11 needs it):
  manage_plugins  Tools > Manage Plugins > Load New... > paraview/plugin/varsph_filters.py; a second start
                  ticks Auto Load in that dialog; a third start loads the plugin by itself
  python_shell    LoadPlugin(".../varsph_filters.py", ns=globals()) typed in View > Python Shell
  launcher        varsph paraview RUN (no shim installed: the launcher brings its own), the pressure state
(PV_PLUGIN_PATH: every state test, test_gui_states.py. --plugins NAME cannot name a Python plugin in ParaView
5.11-5.13: it looks for NAME.so only; see docs/paraview.md.) Each: ParaView exits 0, prints no error or
warning line, the varsph proxies are defined and the Free Surface filter run inside the GUI flags the free
surface of a synthetic run (the count varsph.free_surface gives).
Usage: pvpython test_gui_plugin.py MODE [VARSPH_EXECUTABLE]"""
import os
import sys

import gui
import tcommon as T
import synthetic as S
import varsph as V

mode = sys.argv[1]
tmp = T.workdir("gui_plugin_" + mode)
run = os.path.join(tmp, "run")
S.dam_break_run(run, nframes=3, dx=0.02)
expect = int(V.free_surface(V.read_vtu(V.frames_of_run(run)[1][1])).sum())
plugin_dir = os.path.join(T.PARAVIEW_DIR, "plugin")
plugin = os.path.join(plugin_dir, "varsph_filters.py")
env = {"PYTHONUSERBASE": gui.shim_userbase(tmp), "VARSPH_GUI_APPLY": run, "PV_PLUGIN_PATH": ""}


def verify(label, rc, out, rep):
    print(out[-3000:])
    T.check(rc == 0, "%s: ParaView exits 0 (%d)" % (label, rc))
    T.check(not gui.error_lines(out), "%s: no error or warning lines %s" % (label, gui.error_lines(out)[:5]))
    T.check(rep is not None and rep.get("ok"), "%s: the check ran in the GUI: %s" % (label, (rep or {}).get("error")))
    if rep and rep.get("ok"):
        T.check(rep.get("flagged") == expect, "%s: varsph Free Surface in the GUI flags %s particles (expected %d)"
                % (label, rep.get("flagged"), expect))


def ours(rep):
    """(row, entry) of the plugin in the GUI's list of local plugins."""
    for k, p in enumerate((rep or {}).get("local_plugins", [])):
        if os.path.realpath(p[1] or "/nonexistent") == os.path.realpath(plugin):
            return k, p
    return None, None


if mode == "manage_plugins":
    load = ['<pqevent object="pqClientMainWindow/menubar" command="activate" arguments="menuTools" />',
            '<pqevent object="pqClientMainWindow/menubar/menuTools" command="activate" arguments="actionManage_Plugins" />',
            '<pqevent object="pqClientMainWindow/PluginManagerDialog/splitter/localGroup/loadLocal" '
            'command="activate" arguments="" />',
            '<pqevent object="pqClientMainWindow/PluginManagerDialog/pqFileDialog" command="filesSelected" '
            'arguments="%s" />' % gui.xml_attr(plugin)]
    close = ['<pqevent object="pqClientMainWindow/PluginManagerDialog/buttonBox/1QPushButton0" command="activate" '
             'arguments="" />']
    rc, out, rep, _, home = gui.run(tmp, [], env, events=load + close)
    verify("Manage Plugins > Load New", rc, out, rep)
    row, entry = ours(rep)
    T.check(entry is not None and entry[2], "the dialog lists the plugin as loaded (row %s)" % row)
    if entry is not None:
        # children of a plugin in the dialog: Version, Location, [Required Plugins], Status, Auto Load
        child = 4 if entry[4] else 3
        tick = ['<pqevent object="pqClientMainWindow/menubar" command="activate" arguments="menuTools" />',
                '<pqevent object="pqClientMainWindow/menubar/menuTools" command="activate" '
                'arguments="actionManage_Plugins" />',
                '<pqevent object="pqClientMainWindow/PluginManagerDialog/splitter/localGroup/localPlugins" '
                'command="setCheckState" arguments="%d.0.%d.1,2" />' % (row, child)]
        rc, out, rep, _, _ = gui.run(tmp, [], dict(env, VARSPH_GUI_APPLY=""), events=tick + close, home=home)
        print(out[-2000:])
        T.check(rc == 0 and not gui.error_lines(out), "second start: Auto Load ticked (%d, %s)"
                % (rc, gui.error_lines(out)[:3]))
        row2, entry2 = ours(rep)
        T.check(entry2 is not None and entry2[3], "the plugin is marked Auto Load (%s)" % (entry2,))
        rc, out, rep, _, _ = gui.run(tmp, [], env, home=home)
        verify("third start, nothing asked: Auto Load", rc, out, rep)
elif mode == "python_shell":
    rc, out, rep, _, _ = gui.run(tmp, [], dict(env, VARSPH_GUI_LOADPLUGIN=plugin))
    verify("LoadPlugin in the Python shell", rc, out, rep)
    T.check(rep is not None and rep.get("loadplugin_ns") is True, "LoadPlugin(..., ns=globals()) defines "
            "varsphFreeSurface in the shell")
elif mode == "launcher":
    exe = sys.argv[2]
    bare = os.path.join(tmp, "empty userbase")   # no shim installed for this user: the launcher's own must do
    rc, out, rep, shot, _ = gui.run(tmp, [run, "--"], dict(env, PYTHONUSERBASE=bare, VARSPH_GUI_APPLY=run),
                                    launcher=[exe, "paraview"])
    verify("varsph paraview RUN", rc, out, rep)
    if rep and rep.get("ok"):
        T.check(rep.get("views_per_layout") == [1] and rep.get("colour_array") == "pressure",
                "varsph paraview RUN shows the pressure state in one view (%s, %s)"
                % (rep.get("views_per_layout"), rep.get("colour_array")))
else:
    raise SystemExit("unknown mode " + mode)
T.finish(tmp)
