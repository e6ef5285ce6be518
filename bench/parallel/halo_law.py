#!/usr/bin/env python3
"""Halo bytes per step per rank against particles per rank (a benchmark, not a test): the surface-to-volume
law behind the cluster projection in docs/performance.md ("Beyond one machine").

For the 2D paper dam break and the 3D box dam break at several spacings and rank counts, two runs of
`mpirun -n P varsph run` that differ only in their number of steps give the halo traffic of the steps alone
(the set-up exchange cancels): bytes/step/rank = (B(long) - B(short)) / (steps(long) - steps(short)) / P,
with B = run.json parallel.halo_bytes_sent (ghost rebuilds at the rebins and every pass's refresh, summed
over ranks). Probes are switched off (in a distributed run they add one refresh per step), the 2D scene
runs at a fixed step of the acoustic CFL limit (C = 0.2) so that every spacing is stable. Then, per dimension and rank
count, a least-squares fit of bytes = c n^((D-1)/D) (n = particles per rank, walls included) and of the
free exponent, and the serial cost per particle-step (1 rank, 1 thread: the step seconds of the two runs'
difference). Rank counts above the core count are oversubscribed: their bytes are exact, their times are
not used.

  python3 bench/parallel/halo_law.py                      # ~12 min on 2 shared cores (load 3-6)
  python3 bench/parallel/halo_law.py --dims 3 --ranks 2,4 --scales3 1,10
"""
import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scaling import initial_dt, mpirun_prefix  # noqa: E402

# scene, the spacing of scale 1
SCENES = {
    2: ("dam_break_2d_paper.json", 0.005),
    3: ("bench_box_3d.json", 0.0186),  # ~1e4 fluid particles at scale 1
}


def run(args, dim, ranks, dx, steps, tag):
    scene = os.path.join(ROOT, "pipelines", SCENES[dim][0])
    out = os.path.join(args.scratch, "%dd_%s_p%d_%d" % (dim, tag, ranks, steps))
    sets = ["particles.spacing=%.6g" % dx, "probes=[]", "output.fields=[\"id\"]"]
    if dim == 2:  # the scene's fixed dt is too long for the finer spacings: the acoustic CFL step instead
        dt = initial_dt(args.varsph, ["--set", sets[0]], scene, acoustic=True)
        sets.append("integrator.dt=%.9g" % dt)
    else:
        dt = initial_dt(args.varsph, ["--set", sets[0]], scene)
    t_end = steps * dt * 1.0001
    sets += ["time.end=%.9g" % t_end, "output.every=%.9g" % t_end]
    cmd = (mpirun_prefix(ranks, False) if ranks > 1 else []) + [args.varsph, "run", scene, "-o", out, "--overwrite",
                                                                 "--quiet", "--threads", "1"]
    for s in sets:
        cmd += ["--set", s]
    load = os.getloadavg()[0]
    r = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    if r.returncode != 0:
        sys.exit("halo_law.py: %s failed (%d):\n%s%s" % (" ".join(cmd), r.returncode, r.stdout, r.stderr))
    j = json.load(open(os.path.join(out, "run.json")))
    shutil.rmtree(out, ignore_errors=True)
    par = j.get("parallel", {})
    return {"steps": j["timings"]["steps"], "step_seconds": j["timings"]["step_seconds"],
            "fluid": j["resolved"]["fluid_particles"],
            "total": j["resolved"]["fluid_particles"] + j["resolved"]["boundary_particles"],
            "bytes": par.get("halo_bytes_sent", 0.0), "refreshes": par.get("halo_refreshes", 0),
            "rebins": par.get("rebins", 0), "ghosts": par.get("ghost_particles", 0),
            "max_ghosts": par.get("max_ghost_particles_per_rank", 0),
            "max_owned": par.get("max_particles_per_rank", j["resolved"]["fluid_particles"]), "load": load}


def fit(rows, dim):
    """bytes = c n^e: c with e = (D-1)/D fixed, and the free (c, e) by log-log least squares."""
    xs = [math.log(r["particles_per_rank"]) for r in rows]
    ys = [math.log(r["halo_bytes_per_step_per_rank"]) for r in rows]
    e0 = (dim - 1) / dim
    c_fixed = math.exp(sum(y - e0 * x for x, y in zip(xs, ys)) / len(xs))
    if len(xs) < 2:
        return c_fixed, float("nan"), float("nan")
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    e = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    return c_fixed, e, math.exp(my - e * mx)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dims", default="2,3")
    ap.add_argument("--ranks", default="2,3,4")
    ap.add_argument("--scales2", default="1,4,16,64", help="2D particle counts, multiples of 1682 fluid")
    ap.add_argument("--scales3", default="1,3,10", help="3D particle counts, multiples of ~1e4 fluid")
    ap.add_argument("--short", type=int, default=10)
    ap.add_argument("--long", type=int, default=40)
    ap.add_argument("--varsph", default=os.path.join(ROOT, "build", "release", "bin", "varsph"))
    ap.add_argument("--scratch", default="/tmp/varsph_halo_law")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "parallel", "halo_law.csv"))
    a = ap.parse_args()
    os.makedirs(a.scratch, exist_ok=True)
    rows = []
    for dim in [int(d) for d in a.dims.split(",")]:
        scales = [float(s) for s in (a.scales2 if dim == 2 else a.scales3).split(",")]
        for s in scales:
            dx = SCENES[dim][1] / s ** (1.0 / dim)  # s: multiple of the particle count of scale 1
            for p in [1] + [int(r) for r in a.ranks.split(",")]:
                lo = run(a, dim, p, dx, a.short, "s")
                hi = run(a, dim, p, dx, a.long, "l")
                ds = hi["steps"] - lo["steps"]
                row = {"dim": dim, "dx": dx, "ranks": p, "fluid": hi["fluid"], "particles": hi["total"],
                       "particles_per_rank": hi["total"] / p, "max_owned_per_rank": hi["max_owned"],
                       "ghosts_per_rank": hi["ghosts"] / p, "max_ghosts_per_rank": hi["max_ghosts"],
                       "halo_bytes_per_step_per_rank": (hi["bytes"] - lo["bytes"]) / max(ds, 1) / p,
                       "refreshes_per_step": (hi["refreshes"] - lo["refreshes"]) / max(ds, 1),
                       "rebins_per_step": (hi["rebins"] - lo["rebins"]) / max(ds, 1),
                       "ns_per_particle_step": (hi["step_seconds"] - lo["step_seconds"]) / max(ds, 1) /
                                               hi["total"] * 1e9 * p,
                       "steps": ds, "load": 0.5 * (lo["load"] + hi["load"])}
                if row["ghosts_per_rank"] > 0:
                    row["bytes_per_ghost_per_step"] = row["halo_bytes_per_step_per_rank"] / row["ghosts_per_rank"]
                rows.append(row)
                print(row, flush=True)
    cols = ["dim", "dx", "ranks", "fluid", "particles", "particles_per_rank", "max_owned_per_rank", "ghosts_per_rank",
            "max_ghosts_per_rank", "halo_bytes_per_step_per_rank", "bytes_per_ghost_per_step", "refreshes_per_step",
            "rebins_per_step", "ns_per_particle_step", "steps", "load"]
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    print("\n%3s %5s %10s %10s %10s %12s %8s %6s %8s %5s" % ("D", "ranks", "n/rank", "ghosts/r", "B/step/r", "B/ghost/step",
                                                           "refr/st", "rebin", "ns/p-st", "load"))
    for r in rows:
        print("%3d %5d %10.0f %10.0f %10.0f %12.1f %8.2f %6.3f %8.0f %5.1f" % (
            r["dim"], r["ranks"], r["particles_per_rank"], r["ghosts_per_rank"], r["halo_bytes_per_step_per_rank"],
            r.get("bytes_per_ghost_per_step", 0), r["refreshes_per_step"], r["rebins_per_step"],
            r["ns_per_particle_step"], r["load"]))
    print("\nfits bytes/step/rank = c n^e (n: particles per rank)")
    for dim in sorted({r["dim"] for r in rows}):
        for p in sorted({r["ranks"] for r in rows if r["dim"] == dim and r["ranks"] > 1}):
            sel = [r for r in rows if r["dim"] == dim and r["ranks"] == p and r["halo_bytes_per_step_per_rank"] > 0]
            if not sel:
                continue
            c, e, ce = fit(sel, dim)
            print("  %dD, %d ranks: c = %.1f B (e = %.3f fixed); free fit e = %.3f, c = %.1f B" % (
                dim, p, c, (dim - 1) / dim, e, ce))
    print("wrote", a.out)


if __name__ == "__main__":
    main()
