"""Start the real ParaView GUI under Xvfb and look at it from inside.

``run(args, env)`` starts ``paraview ARGS --test-script=CHECK.xml --exit`` (CHECK.xml: optional events of
``events``, then gui_check.py run in the GUI's Python shell) with a fresh HOME (the welcome dialog off, no
settings of the user), and returns (exit status, output, report of gui_check.py). ``error_lines(output)``:
the lines of ParaView's output that report an error or a warning."""
import json
import os
import re
import subprocess
import tempfile

import tcommon as T

BENIGN = (re.compile(r"QStandardPaths: XDG_RUNTIME_DIR not set"), re.compile(r"^debug: "),
          re.compile(r"^Playing: "))
BAD = re.compile(r"ERR\||WARN\||Traceback|(?i:\berror\b|\bwarning\b|\bfailed\b|cannot import|not defined)")


def paraview_version():
    p = subprocess.run(["paraview", "--version"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       timeout=120, env=dict(os.environ, QT_QPA_PLATFORM="offscreen"))
    m = re.search(r"(\d+\.\d+\.\d+)", p.stdout)
    return m.group(1) if m else "5.11.0"


def fresh_home(base, version):
    home = tempfile.mkdtemp(prefix="home_", dir=base)
    cfg = os.path.join(home, ".config", "ParaView")
    os.makedirs(cfg)
    with open(os.path.join(cfg, "ParaView%s.ini" % version), "w") as f:   # no welcome dialog (it is modal)
        f.write("[General]\nGeneralSettings.ShowWelcomeDialog=false\n")
    return home


def run(base, args, env=None, events=(), home=None, timeout=300, launcher=None, screen="1600x1000x24",
        fbdir=None):
    """``launcher``: a command that starts ParaView itself and passes further arguments on (varsph paraview).
    ``fbdir``: Xvfb keeps its screen in DIR/Xvfb_screen0 (XWD), for window_png()."""
    n = len(os.listdir(base))
    report, shot, script = (os.path.join(base, "gui%d.%s" % (n, e)) for e in ("json", "png", "xml"))
    check = os.path.join(T.HERE, "gui_check.py")
    with open(script, "w") as f:
        f.write('<?xml version="1.0" ?>\n<pqevents>\n')
        for ev in events:
            f.write("  %s\n" % ev)
        f.write('  <pqevent object="pqClientMainWindow/pythonShellDock/pythonShell/consoleWidget" '
                'command="executeCommand" arguments="exec(open(%s).read())" />\n</pqevents>\n'
                % xml_attr(repr(check)))
    e = dict(os.environ)
    e.update(HOME=home or fresh_home(base, paraview_version()), VARSPH_GUI_REPORT=report, VARSPH_GUI_SHOT=shot,
             VARSPH_TESTS_DIR=T.HERE)
    e.update(env or {})
    gui = (launcher or ["paraview"]) + list(args) + ["--test-script=" + script, "--exit"]
    server = "-noreset -screen 0 %s" % screen + (" -fbdir %s" % fbdir if fbdir else "")
    cmd = ["xvfb-run", "-a", "-s", server] + gui
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout, env=e)
    rep = None
    if os.path.isfile(report):
        with open(report) as f:
            rep = json.load(f)
    return p.returncode, p.stdout, rep, (shot if os.path.isfile(shot) else None), e["HOME"]


def xml_attr(text):
    return text.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")


def error_lines(output):
    out = []
    for line in output.splitlines():
        if any(b.search(line) for b in BENIGN):
            continue
        if BAD.search(line):
            out.append(line.strip())
    return out


def shim_userbase(base):
    """A PYTHONUSERBASE with the getargspec shim installed by paraview/install_compat.py --user."""
    ub = os.path.join(base, "userbase")
    p = subprocess.run([T.pvpython(), os.path.join(T.PARAVIEW_DIR, "install_compat.py"), "--user"],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60,
                       env=dict(os.environ, PYTHONUSERBASE=ub))
    if p.returncode != 0:
        raise RuntimeError("install_compat.py --user failed: " + p.stdout)
    return ub


def window_png(xwd_path, png_path):
    """The Xvfb screen (an XWD file, ZPixmap, 24/32 bits per pixel) as a PNG: a picture of the whole ParaView
    window as a user sees it."""
    import struct
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOImage import vtkPNGWriter
    with open(xwd_path, "rb") as f:
        data = f.read()
    h = struct.unpack(">25I", data[:100])
    header_size, width, height, byte_order, bpp, bpl, ncolors = h[0], h[4], h[5], h[7], h[11], h[12], h[19]
    if bpp != 32:
        raise ValueError("%s: %d bits per pixel, expected 32" % (xwd_path, bpp))
    start = header_size + 12 * ncolors
    px = np.frombuffer(data, dtype=np.uint8, count=bpl * height, offset=start).reshape(height, bpl)[:, :4 * width]
    px = px.reshape(height, width, 4)
    rgb = px[:, :, [2, 1, 0]] if byte_order == 0 else px[:, :, [1, 2, 3]]
    img = vtkImageData()
    img.SetDimensions(width, height, 1)
    arr = numpy_to_vtk(np.ascontiguousarray(rgb[::-1]).reshape(-1, 3), deep=1)
    img.GetPointData().SetScalars(arr)
    w = vtkPNGWriter()
    w.SetFileName(png_path)
    w.SetInputData(img)
    w.Write()
    return png_path
