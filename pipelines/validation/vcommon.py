"""Shared helpers of the validation suite: running varsph, reading its outputs, reference data, metrics.

Runs with /usr/bin/python3 (numpy, matplotlib) or pvpython. No solver code here: every number comes from a
`varsph run` and its run directory (CONTRACT.md: probes.csv, diagnostics.csv, run.json, frames/).
"""
import csv
import json
import math
import os
import shutil
import subprocess
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
DATA = os.path.join(ROOT, "tests", "data", "validation")


def varsph_binary():
    b = os.environ.get("VARSPH_BIN")
    if b:
        return b
    for c in ("build/release/bin/varsph", "build/native/bin/varsph", "build/debug/bin/varsph"):
        p = os.path.join(ROOT, c)
        if os.path.exists(p):
            return p
    p = shutil.which("varsph")
    if p:
        return p
    raise SystemExit("varsph binary not found: build it (cmake --build --preset release --target varsph) "
                     "or set VARSPH_BIN")


def loadavg():
    try:
        return os.getloadavg()[0]
    except OSError:
        return float("nan")


def set_args(sets):
    """sets: dict KEY -> python value (JSON-encoded) or already-encoded string."""
    out = []
    for k, v in (sets or {}).items():
        val = v if isinstance(v, str) else json.dumps(v)  # a string is passed as typed (varsph parses JSON)
        out += ["--set", f"{k}={val}"]
    return out


class RunResult:
    def __init__(self, rc, outdir, wall, stdout, stderr, load_before, load_after):
        self.rc, self.dir, self.wall, self.stdout, self.stderr = rc, outdir, wall, stdout, stderr
        self.load_before, self.load_after = load_before, load_after
        self.runjson = {}
        p = os.path.join(outdir, "run.json")
        if os.path.exists(p):
            with open(p) as f:
                self.runjson = json.load(f)

    @property
    def timings(self):
        return self.runjson.get("timings", {})

    @property
    def solver_wall(self):
        return float(self.timings.get("wall_seconds", self.wall))

    @property
    def steps(self):
        return self.timings.get("steps")

    @property
    def psps(self):
        return self.timings.get("fluid_particle_steps_per_second")

    def table(self, name):
        return read_csv(os.path.join(self.dir, name))

    def message(self):
        return (self.stderr.strip().splitlines() or [""])[-1]


def run(scene, outdir, sets=None, threads=2, timeout=None, extra=()):
    """varsph run SCENE -o OUTDIR --overwrite --quiet; returns a RunResult (never raises on exit != 0)."""
    os.makedirs(os.path.dirname(os.path.abspath(outdir)), exist_ok=True)
    cmd = [varsph_binary(), "run", scene, "-o", outdir, "--overwrite", "--quiet", "--threads", str(threads)]
    cmd += set_args(sets) + list(extra)
    # The OpenMP wait policy is the caller's: passive waiting keeps oversubscribed (shared, loaded) machines
    # usable but makes every fork/join a sleep/wake-up, 5.8x slower on the idle machine for the 2,040-particle
    # dam break (7.12 s against 1.23 s): export OMP_WAIT_POLICY=passive only when other jobs share the cores.
    env = dict(os.environ)
    l0 = loadavg()
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)
        rc, so, se = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as e:
        rc, so, se = 124, str(e.stdout or ""), "timeout"
    wall = time.monotonic() - t0
    return RunResult(rc, outdir, wall, so, se, l0, loadavg())


def run_generated(scene, outdir, threads=2, timeout=None):
    """Writes a generated scene (a dict) as NAME.json in the folder above OUTDIR, where its relative files (a paddle
    file, a profile) are looked for, and runs it into OUTDIR; returns the RunResult."""
    os.makedirs(outdir, exist_ok=True)
    path = os.path.join(os.path.dirname(os.path.abspath(outdir)), scene["name"] + ".json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return run(path, outdir, threads=threads, timeout=timeout)


def info(scene, sets=None):
    cmd = [varsph_binary(), "info", scene] + set_args(sets)
    p = subprocess.run(cmd, capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


def h_over_c0(scene, sets=None):
    """h / c0 of a scene as `varsph info` resolves it (time steps are fractions f of h / c0)."""
    _, out = info(scene, sets or {})
    h = c0 = None
    for line in out.splitlines():
        if line.startswith("kernel") and "h = " in line:
            h = float(line.split("h = ")[1].split()[0])
        if line.startswith("c0 "):
            c0 = float(line.split()[1])
    return h / c0


def integrator_available(scene, itype, alpha=None):
    sets = {"integrator.type": itype}
    if alpha is not None:
        sets["integrator.alpha"] = alpha
    rc, _ = info(scene, sets)
    return rc == 0


def read_csv(path):
    """CSV with a header row (comment lines starting with # skipped) -> dict of numpy float arrays."""
    with open(path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    if not rows:
        return {}
    head, body = rows[0], rows[1:]
    out = {}
    for j, k in enumerate(head):
        col = []
        for r in body:
            try:
                col.append(float(r[j]) if j < len(r) and r[j] != "" else float("nan"))
            except ValueError:
                col.append(float("nan"))
        out[k.strip()] = np.array(col)
    return out


def reference(name):
    return read_csv(os.path.join(DATA, name))


def write_csv(path, rows, fields=None):
    if not rows:
        return
    fields = fields or list(rows[0].keys())
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def nan_frames(rundir):
    """Number of VTU frames holding a NaN/inf in any float array (reads the XML with vtk if available,
    else scans the appended/ascii data with the VTK reader of pvpython; returns (frames_checked, bad))."""
    frames_dir = os.path.join(rundir, "frames")
    if not os.path.isdir(frames_dir):
        return 0, 0
    files = sorted(f for f in os.listdir(frames_dir) if f.endswith(".vtu"))
    try:
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
        from vtkmodules.util.numpy_support import vtk_to_numpy
    except ImportError:
        try:
            from vtk import vtkXMLUnstructuredGridReader  # type: ignore
            from vtk.util.numpy_support import vtk_to_numpy  # type: ignore
        except ImportError:
            return len(files), -1
    bad = 0
    for fn in files:
        r = vtkXMLUnstructuredGridReader()
        r.SetFileName(os.path.join(frames_dir, fn))
        r.Update()
        g = r.GetOutput()
        arrays = [vtk_to_numpy(g.GetPoints().GetData())] if g.GetPoints() else []
        pd = g.GetPointData()
        for k in range(pd.GetNumberOfArrays()):
            arrays.append(vtk_to_numpy(pd.GetArray(k)))
        if any(a.dtype.kind == "f" and not np.all(np.isfinite(a)) for a in arrays):
            bad += 1
    return len(files), bad


def observed_order(dxs, errs):
    """Least-squares slope of log(err) against log(dx), and pairwise orders."""
    dxs, errs = np.asarray(dxs, float), np.asarray(errs, float)
    ok = (errs > 0) & np.isfinite(errs)
    if ok.sum() < 2:
        return float("nan"), []
    slope = float(np.polyfit(np.log(dxs[ok]), np.log(errs[ok]), 1)[0])
    pairs = [math.log(errs[i] / errs[i + 1]) / math.log(dxs[i] / dxs[i + 1])
             for i in range(len(dxs) - 1) if errs[i] > 0 and errs[i + 1] > 0]
    return slope, pairs
