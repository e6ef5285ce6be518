#!/usr/bin/env python3
"""Cost per particle-step against problem size in 2D (issue 9c: flat within 20 % from 1e4 to 1e7 particles).

Runs bench_step on the paper's dam break (pipelines/dam_break_2d_paper.json, Gaussian kernel, continuity,
Verlet) at spacings giving ~1e4, 1e5, 1e6, 1e7 fluid particles (dt scaled with dx), one process per size and
thread count, and reports the best (minimum) of R timed repeats of S steps after a warm-up step, in ns per
fluid particle-step, with the load average before each measurement (the machine is shared: figures taken
under load are upper bounds). Peak RSS per particle = (peak RSS of the size - peak RSS of the 2,040-particle
scene) / particles, for the solver alone (bench_step writes no frames and keeps no blow-up snapshot).
Writes a CSV and, with matplotlib, a PNG.

  /usr/bin/python3 bench/flatness.py [--bench build/release/bin/bench_step] [--sizes 1e4,1e5,1e6,1e7]
      [--threads 1,2] [-o bench/flatness]   # writes bench/flatness.csv and bench/flatness.png
"""
import argparse
import csv
import math
import os
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCENE = os.path.join(ROOT, "pipelines", "dam_break_2d_paper.json")
FLUID_AREA = 0.145 * 0.29  # the fluid box of the scene [m^2]


def loadavg():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def bench(exe, dx, threads, steps, repeats):
    dt = 1e-4 * dx / 0.005
    # particles.max_count: the 1e7 case is above the default limit (docs/scene.md)
    cmd = [exe, "--scene", SCENE, "--set", f"particles.spacing={dx!r}", "--set", f"integrator.dt={dt!r}",
           "--set", "particles.max_count=1e8", "--steps", str(steps), "--repeats", str(repeats), "--threads", str(threads)]
    load = loadavg()
    # the caller's OpenMP wait policy: passive makes every fork/join a sleep/wake-up (several times slower when idle)
    p = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ))
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
    row = [ln.split() for ln in p.stdout.splitlines() if ln.startswith("custom")][-1]
    return {"fluid": int(row[1]), "boundary": int(row[2]), "threads": int(row[3]), "neighbours": float(row[4]),
            "ns_per_particle_step": float(row[5]), "ms_per_step": float(row[8]), "peak_mb": float(row[9]),
            "load_before": load, "load_after": loadavg()}


def plan(n):
    """steps, repeats for a size: about the same total work per size, at least one timed step."""
    steps = max(1, int(round(3e5 / n)))
    return min(steps, 100), (3 if n <= 1e6 else 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bench", default=os.path.join(ROOT, "build", "release", "bin", "bench_step"))
    ap.add_argument("--sizes", default="1e4,1e5,1e6,1e7")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("-o", "--out", default=os.path.join(ROOT, "bench", "flatness"))
    a = ap.parse_args()
    base = bench(a.bench, 0.005, 1, 1, 1)["peak_mb"]
    rows = []
    print(f"# {a.bench}; baseline peak RSS {base:.1f} MB at 2,040 particles")
    print(f"{'target':>8s} {'fluid':>9s} {'total':>9s} {'thr':>3s} {'steps':>5s} {'ns/p-step':>10s} {'peak MB':>8s} "
          f"{'B/particle':>10s} {'load':>5s}")
    for target in [float(s) for s in a.sizes.split(",")]:
        dx = math.sqrt(FLUID_AREA / target)
        steps, repeats = plan(target)
        for t in [int(x) for x in a.threads.split(",")]:
            r = bench(a.bench, dx, t, steps, repeats)
            total = r["fluid"] + r["boundary"]
            r.update(target=int(target), dx=dx, steps=steps, repeats=repeats, total=total,
                     bytes_per_particle=(r["peak_mb"] - base) * 1048576 / total)
            rows.append(r)
            print(f"{target:8.0e} {r['fluid']:9d} {total:9d} {t:3d} {steps:5d} {r['ns_per_particle_step']:10.1f} "
                  f"{r['peak_mb']:8.1f} {r['bytes_per_particle']:10.1f} {r['load_before']:5.2f}", flush=True)
    fields = ["target", "dx", "fluid", "boundary", "total", "threads", "steps", "repeats", "neighbours",
              "ns_per_particle_step", "ms_per_step", "peak_mb", "bytes_per_particle", "load_before", "load_after"]
    with open(a.out + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    for t in sorted({r["threads"] for r in rows}):
        v = [r["ns_per_particle_step"] for r in rows if r["threads"] == t]
        print(f"{t} thread(s): max/min of ns per particle-step over the sizes = {max(v) / min(v):.2f}")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: no PNG")
        return 0
    fig, ax = plt.subplots(figsize=(6, 4))
    for t in sorted({r["threads"] for r in rows}):
        rr = [r for r in rows if r["threads"] == t]
        ax.semilogx([r["fluid"] for r in rr], [r["ns_per_particle_step"] for r in rr], "o-", label=f"{t} thread(s)")
    ax.set_xlabel("fluid particles")
    ax.set_ylabel("ns per fluid particle-step (best of repeats)")
    ax.set_title("2D dam break (Gaussian, Verlet): cost per particle-step")
    ax.set_ylim(bottom=0)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(a.out + ".png", dpi=120)
    print(f"wrote {a.out}.csv and {a.out}.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
