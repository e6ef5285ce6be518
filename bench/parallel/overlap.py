#!/usr/bin/env python3
"""Halo refresh overlapped with the interior sweep: the time ranks wait in the refresh with and without
the overlap (a benchmark, not a test).

Runs each scene on --ranks ranks x --threads threads with VARSPH_HALO_OVERLAP=off and =on, interleaved
(off, on, off, on, ...) so that a change of the machine's load hits both alike, and reads run.json:
  parallel.max_refresh_wait_seconds / mean_refresh_wait_seconds  seconds inside the refresh's MPI calls
                                                                  (post + wait), slowest rank / mean
  parallel.max_rebin_wait_seconds      seconds inside rebin()'s MPI calls (migration, ghost rebuild:
                                       not overlappable), slowest rank
  timings.step_seconds                 wall time inside the steps
The hidden fraction is 1 - wait(on) / wait(off) of the mean refresh wait, per round and over the rounds'
medians. The load average is recorded with every run (the machine may be shared).

  python3 bench/parallel/overlap.py                       # 2 ranks x 1 thread, 2D paper scene + 3D box
  python3 bench/parallel/overlap.py --rounds 5 --out bench/parallel/overlap.csv
"""
import argparse
import csv
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
from scaling import initial_dt, mpirun_prefix  # noqa: E402

SCENES = {
    # the paper's 2D dam break: 1682 fluid + 358 walls, repulsive walls, Verlet (two split passes a step)
    "dam2d": (os.path.join(ROOT, "pipelines", "dam_break_2d_paper.json"), [], 300),
    # the same scene with the variational integrator: midpoint refreshes, two split passes per iterate
    "dam2d_var": (os.path.join(ROOT, "pipelines", "dam_break_2d_paper.json"),
                  ["--set", "integrator.type=\"variational\""], 100),
    # the 3D box dam break, dynamic walls, verlet_dsph (one fused pass a step) at ~1e5 fluid particles
    "box3d": (os.path.join(ROOT, "pipelines", "bench_box_3d.json"), ["--set", "particles.spacing=0.0087"], 30),
}


def run_one(a, name, overlap, out):
    scene, sets, steps = SCENES[name]
    steps = a.steps or steps
    dt = initial_dt(a.varsph, sets, scene)
    t_end = steps * dt * 1.0001
    sets = sets + ["--set", "time.end=%.9g" % t_end, "--set", "output.every=%.9g" % t_end,
                   "--set", "output.fields=[\"id\"]"]
    cmd = mpirun_prefix(a.ranks, a.bind) + [a.varsph, "run", scene, "-o", out, "--overwrite", "--quiet",
                                           "--threads", str(a.threads)] + sets
    env = dict(os.environ, OMP_NUM_THREADS=str(a.threads), VARSPH_HALO_OVERLAP=overlap)
    load = os.getloadavg()[0]
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        sys.exit("overlap.py: %s failed (%d):\n%s%s" % (" ".join(cmd), r.returncode, r.stdout, r.stderr))
    j = json.load(open(os.path.join(out, "run.json")))
    shutil.rmtree(out, ignore_errors=True)
    p, t = j["parallel"], j["timings"]
    total = j["resolved"]["fluid_particles"] + j["resolved"]["boundary_particles"]
    return {
        "scene": name, "overlap": overlap, "ranks": a.ranks, "threads": a.threads, "particles": total,
        "steps": t["steps"], "step_seconds": t["step_seconds"],
        "refreshes": p["halo_refreshes"], "overlapped_refreshes": p["overlapped_refreshes"],
        "interior_fraction": p["interior_particles"] / total,
        "max_refresh_wait_seconds": p["max_refresh_wait_seconds"],
        "mean_refresh_wait_seconds": p["mean_refresh_wait_seconds"],
        "max_rebin_wait_seconds": p["max_rebin_wait_seconds"],
        "halo_bytes_per_step_per_rank": p["halo_bytes_sent"] / max(t["steps"], 1) / a.ranks,
        "load_before": load, "load_after": os.getloadavg()[0],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes", default="dam2d,box3d")
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--steps", type=int, default=0, help="steps per run (0: the scene's default)")
    ap.add_argument("--bind", action="store_true", help="one core per rank (--bind-to core); else oversubscribe")
    ap.add_argument("--varsph", default=os.path.join(ROOT, "build", "release", "bin", "varsph"))
    ap.add_argument("--scratch", default="/tmp/varsph_overlap")
    ap.add_argument("--out", default=os.path.join(HERE, "overlap.csv"))
    a = ap.parse_args()
    os.makedirs(a.scratch, exist_ok=True)
    rows = []
    for name in a.scenes.split(","):
        for k in range(a.rounds):
            for overlap in ("off", "on"):
                rows.append(run_one(a, name, overlap, os.path.join(a.scratch, "%s_%s_%d" % (name, overlap, k))))
                rows[-1]["round"] = k
                print({key: (round(v, 4) if isinstance(v, float) else v) for key, v in rows[-1].items()}, flush=True)
    cols = ["scene", "round", "overlap", "ranks", "threads", "particles", "steps", "step_seconds", "refreshes",
            "overlapped_refreshes", "interior_fraction", "max_refresh_wait_seconds", "mean_refresh_wait_seconds",
            "max_rebin_wait_seconds", "halo_bytes_per_step_per_rank", "load_before", "load_after"]
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    print("\n%-6s %7s %11s %11s %11s %11s %8s %s" % ("scene", "overlap", "step_s", "refresh_w", "refresh_max",
                                                    "rebin_w", "hidden", "load"))
    for name in a.scenes.split(","):
        med = {}
        for overlap in ("off", "on"):
            rs = [r for r in rows if r["scene"] == name and r["overlap"] == overlap]
            med[overlap] = {c: statistics.median(r[c] for r in rs) for c in
                            ("step_seconds", "mean_refresh_wait_seconds", "max_refresh_wait_seconds",
                             "max_rebin_wait_seconds", "load_before")}
        for overlap in ("off", "on"):
            m = med[overlap]
            hidden = 1 - med["on"]["mean_refresh_wait_seconds"] / med["off"]["mean_refresh_wait_seconds"]
            print("%-6s %7s %11.3f %11.3f %11.3f %11.3f %8s %.1f" % (
                name, overlap, m["step_seconds"], m["mean_refresh_wait_seconds"], m["max_refresh_wait_seconds"],
                m["max_rebin_wait_seconds"], "%.0f %%" % (100 * hidden) if overlap == "on" else "", m["load_before"]))


if __name__ == "__main__":
    main()
