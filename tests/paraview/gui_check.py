"""Runs inside the ParaView GUI (its Python shell, driven by the XML test script of gui.py): optionally loads
the plugin with LoadPlugin (VARSPH_GUI_LOADPLUGIN), then writes viewcheck's report of what the GUI shows
(VARSPH_GUI_REPORT) and a screenshot of the active view at its size in the window (VARSPH_GUI_SHOT)."""
import json
import os
import sys
import traceback

sys.path.insert(0, os.environ["VARSPH_TESTS_DIR"])
_rep = {"ok": False}
try:
    import viewcheck
    from paraview import simple as _s
    if os.environ.get("VARSPH_GUI_LOADPLUGIN"):
        LoadPlugin(os.environ["VARSPH_GUI_LOADPLUGIN"], remote=False, ns=globals())  # noqa: F821 (the shell's)
        _rep["loadplugin_ns"] = "varsphFreeSurface" in globals()
    if os.environ.get("VARSPH_GUI_APPLY"):      # run the plugin's filters on a run inside the GUI
        from paraview import servermanager as _sm
        from varsph import pvstate as _pvstate   # importable: the plugin put paraview/ on sys.path
        _s = _pvstate.pv()
        _run = _s.varsphRun(RunDirectory=os.environ["VARSPH_GUI_APPLY"])
        _fs = _s.varsphFreeSurface(Input=_run)
        _fs.UpdatePipeline(0.1)
        _arr = _sm.Fetch(_fs).GetPointData().GetArray("free_surface")
        _rep["flagged"] = int(sum(_arr.GetValue(i) for i in range(_arr.GetNumberOfTuples())))
        _s.Delete(_fs)
        _s.Delete(_run)
    from paraview import servermanager as _sm
    _info = _sm.vtkSMProxyManager.GetProxyManager().GetPluginManager().GetLocalInformation()
    _rep["local_plugins"] = [[_info.GetPluginName(i), _info.GetPluginFileName(i) or "",
                              bool(_info.GetPluginLoaded(i)), bool(_info.GetAutoLoad(i)),
                              _info.GetRequiredPlugins(i) is not None]
                             for i in range(_info.GetNumberOfPlugins())]
    if _s.GetActiveView() is not None and _s.GetSources():
        _rep.update(viewcheck.inspect(_s))
        if os.environ.get("VARSPH_GUI_SHOT"):
            _s.SaveScreenshot(os.environ["VARSPH_GUI_SHOT"], _s.GetActiveView())
    else:
        from paraview import servermanager as _sm
        _pdm = _sm.vtkSMProxyManager.GetProxyManager().GetActiveSessionProxyManager().GetProxyDefinitionManager()
        _rep["plugin"] = bool(_pdm.HasDefinition("filters", "varsphFreeSurface"))
    if os.environ.get("VARSPH_GUI_WINDOW"):    # the whole window, from the Xvfb frame buffer
        import gui as _gui
        _s.Render()
        _gui.window_png(os.path.join(os.environ["VARSPH_GUI_FBDIR"], "Xvfb_screen0"), os.environ["VARSPH_GUI_WINDOW"])
    _rep["ok"] = True
except Exception:
    _rep["error"] = traceback.format_exc()
with open(os.environ["VARSPH_GUI_REPORT"], "w") as _f:
    json.dump(_rep, _f, indent=1, default=str)
