#!/usr/bin/env python3
"""10 m/s impact (impact_10ms.json): a 0.1 x 0.1 m water block thrown at 10 m/s against the right wall of a
closed 0.4 x 0.3 m tank. The run must survive (exit 0) and no fluid particle may cross a wall.

Metrics (frames every 2 ms): rc (0 = survived); escaped_max = the largest number of fluid particles in any
frame that are behind the first layer of wall particles, i.e. more than dx/2 beyond a wall surface of the tank
[0, 0.4] x [0, 0.3] (goal 0; a particle within dx/2 of the surface has not crossed the wall's particles, and
the bottom row of the block sags that far into the floor of a dynamic wall under gravity alone);
closest_to_wall_dx = the smallest signed distance of a fluid particle to a wall surface over all frames, in
units of dx (negative: beyond the surface); nan_frames; rho_err = max |rho/rho0 - 1| (diagnostics.csv).

  /usr/bin/python3 pipelines/validation/case_impact.py [--scene FILE] [--setup FILE] [--set K=V]... [-o DIR]
"""
import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vcommon as vc  # noqa: E402
import vsetup  # noqa: E402

SCENE = os.path.join(vc.HERE, "impact_10ms.json")
BOX = (0.0, 0.4, 0.0, 0.3)


def frame_checks(rundir, dx):
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    fr = os.path.join(rundir, "frames")
    escaped, closest = 0, float("inf")
    for fn in sorted(f for f in os.listdir(fr) if f.endswith(".vtu")):
        r = vtkXMLUnstructuredGridReader()
        r.SetFileName(os.path.join(fr, fn))
        r.Update()
        g = r.GetOutput()
        x = vtk_to_numpy(g.GetPoints().GetData()).astype(float)
        kind = vtk_to_numpy(g.GetPointData().GetArray("kind"))
        xf = x[kind == 0]
        d = np.minimum.reduce([xf[:, 0] - BOX[0], BOX[1] - xf[:, 0], xf[:, 1] - BOX[2], BOX[3] - xf[:, 1]]) / dx
        out = ~np.isfinite(d) | (d < -0.5)
        escaped = max(escaped, int(out.sum()))
        closest = min(closest, float(np.nanmin(d)))
    return escaped, closest


def run_case(sets=None, threads=2, outdir=None, scene=SCENE, setup=None, timeout=None):
    outdir = outdir or os.path.join(vc.ROOT, "runs", "validation", "impact_10ms")
    if setup:
        scene = vsetup.scene_with_setup(scene, setup, os.path.abspath(outdir).rstrip("/") + "_scene.json")
    s = {"output.every": 0.002}
    s.update(sets or {})
    r = vc.run(scene, outdir, s, threads, timeout=timeout)
    res = {"rc": r.rc, "wall": r.solver_wall, "steps": r.steps, "load": r.load_before, "load_after": r.load_after,
           "message": r.message() if r.rc else ""}
    nf, bad = vc.nan_frames(outdir)
    res["frames"], res["nan_frames"] = nf, bad
    if nf:
        dx = float(r.runjson.get("scene", {}).get("particles", {}).get("spacing", 0.005)) if r.runjson else 0.005
        res["escaped_max"], res["closest_to_wall_dx"] = frame_checks(outdir, dx)
    d = os.path.join(outdir, "diagnostics.csv")
    if os.path.exists(d):
        res["rho_err"] = float(np.nanmax(vc.read_csv(d)["density_error_max"]))
    res["error"] = float(res.get("escaped_max", float("nan"))) if r.rc == 0 else float("nan")
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=SCENE)
    ap.add_argument("--setup", help="scene file whose kernel/fluid/physics/boundary/integrator/health blocks are used")
    ap.add_argument("--set", action="append", default=[], help="KEY=VALUE passed to varsph run")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("-o", "--outdir")
    a = ap.parse_args()
    res = run_case(dict(kv.split("=", 1) for kv in a.set), a.threads, a.outdir, a.scene, a.setup)
    print(json.dumps(res, indent=1))
    ok = res["rc"] == 0 and res.get("escaped_max", 1) == 0 and res["nan_frames"] == 0
    print("OK" if ok else "FAIL: the run did not survive or a particle crossed a wall")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
