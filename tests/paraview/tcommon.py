"""Shared test helpers: paths, the varsph module on sys.path, numeric checks that fail the test."""
import os
import shutil
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
PARAVIEW_DIR = os.path.join(REPO, "paraview")
for p in (PARAVIEW_DIR, HERE):
    if p not in sys.path:
        sys.path.insert(0, p)

FAILURES = []


def check(cond, msg):
    if cond:
        print("ok   ", msg)
    else:
        print("FAIL ", msg)
        FAILURES.append(msg)


def close(a, b, tol, msg):
    check(abs(a - b) <= tol, "%s: %.17g vs %.17g (tol %g)" % (msg, a, b, tol))


def workdir(name):
    base = os.environ.get("VARSPH_TEST_TMP") or tempfile.gettempdir()
    d = tempfile.mkdtemp(prefix="varsph_%s_" % name, dir=base)
    return d


def pvpython():
    return os.environ.get("VARSPH_PVPYTHON") or shutil.which("pvpython") or "pvpython"


def finish(tmp=None):
    if tmp and not FAILURES and not os.environ.get("VARSPH_KEEP_TMP"):
        shutil.rmtree(tmp, ignore_errors=True)
    if FAILURES:
        print("%d check(s) failed" % len(FAILURES))
        sys.stdout.flush()
        os._exit(1)
    print("all checks passed")
    sys.stdout.flush()
    os._exit(0)


def image_stats(path):
    """(width, height, number of distinct colours, std of the pixel values, fraction of coloured pixels)
    of a PNG; coloured = channel spread max - min > 40 (the colour-mapped particles, not grey/white)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader
    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    img = r.GetOutput()
    w, h, _ = img.GetDimensions()
    px = vtk_to_numpy(img.GetPointData().GetScalars())
    px = px.reshape(w * h, -1)
    ncol = len({tuple(v) for v in px[:: max(1, len(px) // 20000)]})
    rgb = px[:, :3].astype(int)
    coloured = float(((rgb.max(axis=1) - rgb.min(axis=1)) > 40).mean())
    return w, h, ncol, float(px.astype(float).std()), coloured
