"""What the body harnesses (cylinder_entry.py, sinking_cylinder.py) share: reading a published series, linear
interpolation, and running the solver on a scene with --set overrides."""
import csv
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def read_pairs(path):
    """(x, y) rows of a two-column CSV with '#' comment lines and one header line (tests/data convention)."""
    with open(path) as f:
        rows = [r for r in csv.reader(l for l in f if not l.startswith("#")) if r]
    return [(float(a), float(b)) for a, b in rows[1:]]


def interp(xs, ys, x):
    """ys at x, linear between the points of increasing xs; None outside them."""
    if x < xs[0] or x > xs[-1]:
        return None
    k = 0
    while xs[k + 1] < x:
        k += 1
    w = (x - xs[k]) / (xs[k + 1] - xs[k])
    return ys[k] + w * (ys[k + 1] - ys[k])


def run_scene(scene, outdir, threads, sets, timeout):
    """varsph run SCENE -o OUTDIR with each of `sets` as --set; $VARSPH_BIN or the release build. Returns (wall s,
    load before, load after); on a failed run prints its output and exits 3."""
    cmd = [os.environ.get("VARSPH_BIN", os.path.join(ROOT, "build", "release", "bin", "varsph")), "run", scene,
           "-o", outdir, "--overwrite", "--quiet", "--threads", str(threads)]
    for s in sets:
        cmd += ["--set", s]
    l0 = os.getloadavg()[0]
    w0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    wall = time.monotonic() - w0
    if p.returncode != 0:
        print(p.stdout + p.stderr, file=sys.stderr)
        raise SystemExit(3)
    return wall, l0, os.getloadavg()[0]
