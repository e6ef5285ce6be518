#!/usr/bin/env python3
"""Strong and weak scaling of `mpirun -n P varsph run` on the 3D dam break (a benchmark, not a test).

  strong: pipelines/bench_box_3d.json at dx = 4 mm: 1.0e6 fluid + 0.4e6 wall particles, on each P
  weak:   the same scene with dx chosen so that every rank holds ~2.5e5 fluid particles

Every run advances the scene by --steps steps (time.end = steps x the initial CFL dt from `varsph info`)
and reads run.json: timings.step_seconds (wall time inside the steps: no setup, frames or checkpoint)
and parallel.halo_bytes_sent. Efficiency: strong T(1) / (P T(P)), weak T(1) / T(P). Prints a table,
writes a CSV next to --out and deletes the run directories. The load average is recorded with every
row (the machine may be shared).

  python3 bench/parallel/scaling.py --ranks 1,2                 # this 2-core machine
  python3 bench/parallel/scaling.py --ranks 1,2,4,8,16 --bind   # the 16-core machine, one core per rank
"""
import argparse
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "pipelines", "bench_box_3d.json")
FLUID_EDGE = 0.4  # the fluid block is 0.4 m on a side: (0.4 / dx)^3 fluid particles


def mpirun_prefix(ranks, bind):
    exe = shutil.which("mpirun") or shutil.which("mpiexec")
    if exe is None:
        sys.exit("scaling.py: no mpirun on PATH")
    flags = []
    version = subprocess.run([exe, "--version"], capture_output=True, text=True).stdout
    if "Open MPI" in version or "OpenRTE" in version:  # 4.x prints "mpiexec (OpenRTE) 4.1.4"
        if os.geteuid() == 0:
            flags.append("--allow-run-as-root")
        flags += ["--bind-to", "core", "--map-by", "core"] if bind else ["--oversubscribe", "--bind-to", "none"]
    return [exe] + flags + ["-n", str(ranks)]


def initial_dt(varsph, sets, scene=SCENE, acoustic=False):
    """The first step's dt from `varsph info`: the scene's fixed dt, else (or with acoustic=True) the acoustic
    CFL limit it prints ("CFL limits  acoustic ...; with C = 0.2: 8e-05 s"). `varsph info` samples (and prints
    the CFL limits) only up to --calibrate-max particles: above that the limit is read at a coarser spacing and
    scaled, as C h / c0 is linear in dx at a fixed h/dx (c0 comes from the depth, not from dx)."""
    def info(s):
        return subprocess.run([varsph, "info", scene] + s, capture_output=True, text=True, check=True).stdout
    out = info(sets)
    m = None if acoustic else re.search(r"^dt\s+([0-9.eE+-]+) s", out, re.M)  # "dt  0.000100 s (fixed)"
    if m:
        return float(m.group(1))
    m = re.search(r"with C = [0-9.eE+-]+: ([0-9.eE+-]+) s", out)
    if m:
        return float(m.group(1))
    spacing = [i for i, s in enumerate(sets) if s.startswith("particles.spacing=")]
    if spacing:
        dx = float(sets[spacing[-1]].split("=", 1)[1])
        coarse = list(sets)
        # a coarser copy's wall layers may not fit the domain: the next factor is tried
        for factor in (2.0, 1.5, 3.0, 1.25, 4.0, 6.0, 8.0):
            coarse[spacing[-1]] = "particles.spacing=%.9g" % (dx * factor)
            try:
                m = re.search(r"with C = [0-9.eE+-]+: ([0-9.eE+-]+) s", info(coarse))
            except subprocess.CalledProcessError:
                continue
            if m:
                return float(m.group(1)) / factor
    sys.exit("scaling.py: could not read dt from `varsph info`:\n" + out)


def run_one(args, ranks, dx, tag):
    sets = ["--set", "particles.spacing=%.6g" % dx]
    dt = initial_dt(args.varsph, sets)
    t_end = args.steps * dt * 1.0001
    out = os.path.join(args.scratch, "%s_p%d" % (tag, ranks))
    sets += ["--set", "time.end=%.9g" % t_end, "--set", "output.every=%.9g" % t_end,
             "--set", "output.fields=[\"id\"]"]
    cmd = mpirun_prefix(ranks, args.bind) + [args.varsph, "run", SCENE, "-o", out, "--overwrite", "--quiet",
                                            "--threads", str(args.threads)] + sets
    env = dict(os.environ, OMP_NUM_THREADS=str(args.threads))
    load = os.getloadavg()[0]
    t0 = time.time()
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    wall = time.time() - t0
    if r.returncode != 0:
        sys.exit("scaling.py: %s failed (%d):\n%s%s" % (" ".join(cmd), r.returncode, r.stdout, r.stderr))
    j = json.load(open(os.path.join(out, "run.json")))
    shutil.rmtree(out, ignore_errors=True)
    t = j["timings"]
    par = j.get("parallel", {})
    steps = t["steps"]
    fluid = j["resolved"]["fluid_particles"]
    total = fluid + j["resolved"]["boundary_particles"]
    return {
        "mode": tag, "ranks": ranks, "threads": args.threads, "fluid_particles": fluid, "particles": total,
        "particles_per_rank": total / ranks, "steps": steps, "step_seconds": t["step_seconds"],
        "seconds_per_step": t["step_seconds"] / max(steps, 1),
        "ns_per_particle_step_per_core": t["step_seconds"] * ranks * args.threads / max(steps * total, 1) * 1e9,
        "halo_bytes_per_step_per_rank": par.get("halo_bytes_sent", 0) / max(steps, 1) / ranks,
        "max_particles_per_rank": par.get("max_particles_per_rank", total),
        "repartitions": par.get("repartitions", 0), "run_wall_seconds": wall, "load_before": load,
        "load_after": os.getloadavg()[0],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ranks", default="1,2", help="rank counts, e.g. 1,2,4,8,16")
    ap.add_argument("--threads", type=int, default=1, help="OpenMP threads per rank")
    ap.add_argument("--mode", choices=["strong", "weak", "both"], default="both")
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--strong-fluid", type=float, default=1.0e6, help="fluid particles of the strong case")
    ap.add_argument("--weak-fluid-per-rank", type=float, default=2.5e5)
    ap.add_argument("--bind", action="store_true", help="one core per rank (--bind-to core); else oversubscribe")
    ap.add_argument("--varsph", default=os.path.join(ROOT, "build", "release", "bin", "varsph"))
    ap.add_argument("--scratch", default="/tmp/varsph_scaling")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "parallel", "scaling.csv"))
    a = ap.parse_args()
    os.makedirs(a.scratch, exist_ok=True)
    ranks = [int(r) for r in a.ranks.split(",")]
    rows = []
    if a.mode in ("strong", "both"):
        dx = FLUID_EDGE / a.strong_fluid ** (1.0 / 3.0)
        for p in ranks:
            rows.append(run_one(a, p, dx, "strong"))
            print(rows[-1], flush=True)
    if a.mode in ("weak", "both"):
        for p in ranks:
            dx = FLUID_EDGE / (a.weak_fluid_per_rank * p) ** (1.0 / 3.0)
            rows.append(run_one(a, p, dx, "weak"))
            print(rows[-1], flush=True)
    for mode in ("strong", "weak"):
        base = [r for r in rows if r["mode"] == mode and r["ranks"] == min(ranks)]
        for r in rows:
            if r["mode"] != mode or not base:
                continue
            b = base[0]
            if mode == "strong":
                r["efficiency"] = b["seconds_per_step"] * b["ranks"] / (r["seconds_per_step"] * r["ranks"])
            else:
                r["efficiency"] = b["seconds_per_step"] / r["seconds_per_step"]
    cols = ["mode", "ranks", "threads", "particles", "particles_per_rank", "steps", "seconds_per_step",
            "efficiency", "ns_per_particle_step_per_core", "halo_bytes_per_step_per_rank", "max_particles_per_rank",
            "repartitions", "load_before", "load_after"]
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    print("%-6s %5s %4s %10s %10s %9s %6s %9s %12s %6s" % ("mode", "ranks", "thr", "particles", "per_rank", "s/step",
                                                          "eff", "ns/p-step", "halo_B/step", "load"))
    for r in rows:
        print("%-6s %5d %4d %10d %10.0f %9.4f %6.2f %9.1f %12.0f %6.2f" % (
            r["mode"], r["ranks"], r["threads"], r["particles"], r["particles_per_rank"], r["seconds_per_step"],
            r.get("efficiency", float("nan")), r["ns_per_particle_step_per_core"], r["halo_bytes_per_step_per_rank"],
            r["load_before"]))
    print("wrote", a.out)


if __name__ == "__main__":
    main()
