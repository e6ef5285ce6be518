#!/usr/bin/env python3
"""Thread scaling of the solver step (issue 19 point 3: 2D and 3D dam breaks at 1e5-1e7 particles, threads 1-16,
>= 12x one thread at 16). Written to run unchanged on the 16-core machine: it only needs bench_step.

For each case and size it runs `bench_step --scene ... --threads T` once per thread count (one process each, so
every run places its pages by its own first touch), best of R repeats of S steps after a warm-up step, and reports
ns per fluid particle-step, the speed-up over one thread and the parallel efficiency, with the load average before
each run. OpenMP placement: OMP_PROC_BIND=close and OMP_PLACES=cores unless the caller sets them (threads stay on
the cores whose memory they first touched; the store, the grid and the scratch are first-touched in parallel with
the loops' static schedule). Writes OUT.csv and, with matplotlib, OUT.png.

  /usr/bin/python3 bench/scaling.py [--bench build/release/bin/bench_step] [--cases 2d,3d]
      [--sizes 1e5,1e6,1e7] [--threads 1-16] [-o bench/scaling]
  e.g. on the 16-core machine:  /usr/bin/python3 bench/scaling.py --threads 1,2,4,8,12,16
"""
import argparse
import csv
import math
import os
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

# case: scene, the fluid's size (area or volume, m^D), the scene's spacing and dt (dt is scaled with dx)
CASES = {
    # DualSPHysics' 2D validation set-up (Wendland, dynamic walls, Fourtakas diffusion, verlet_dsph)
    "2d": (os.path.join(ROOT, "pipelines", "dam_break_2d_dsph_val.json"), 1.0 * 2.0, 2, 0.01, 3.2e-5),
    # the 3D block (Wendland h = 1.3 dx, dynamic walls, verlet_dsph)
    "3d": (os.path.join(ROOT, "pipelines", "bench_box_3d.json"), 0.4 ** 3, 3, 0.0086, 3.0e-5),
}


def loadavg():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def parse_threads(s):
    out = []
    for part in s.split(","):
        if "-" in part:
            a, b = part.split("-")
            out += list(range(int(a), int(b) + 1))
        else:
            out.append(int(part))
    return out


def bench(exe, scene, dx, dt, threads, steps, repeats):
    cmd = [exe, "--scene", scene, "--set", f"particles.spacing={dx!r}", "--set", f"integrator.dt={dt!r}",
           "--steps", str(steps), "--repeats", str(repeats), "--threads", str(threads)]
    env = dict(os.environ)
    env.setdefault("OMP_PROC_BIND", "close")
    env.setdefault("OMP_PLACES", "cores")
    load = loadavg()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
    row = [ln.split() for ln in p.stdout.splitlines() if ln.startswith("custom")][-1]
    return {"fluid": int(row[1]), "boundary": int(row[2]), "threads": int(row[3]), "neighbours": float(row[4]),
            "ns_per_particle_step": float(row[5]), "ms_per_step": float(row[8]), "peak_mb": float(row[9]),
            "load_before": load, "load_after": loadavg()}


def plan(n):
    """steps, repeats: about the same work per size, at least one timed step after the warm-up."""
    return max(1, min(50, int(round(2e6 / n)))), (3 if n <= 1e6 else 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bench", default=os.path.join(ROOT, "build", "release", "bin", "bench_step"))
    ap.add_argument("--cases", default="2d,3d")
    ap.add_argument("--sizes", default="1e5,1e6,1e7")
    ap.add_argument("--threads", default="1-16")
    ap.add_argument("-o", "--out", default=os.path.join(ROOT, "bench", "scaling"))
    a = ap.parse_args()
    threads = parse_threads(a.threads)
    rows = []
    print(f"# {a.bench}; {os.cpu_count()} CPUs; OMP_PROC_BIND={os.environ.get('OMP_PROC_BIND', 'close')} "
          f"OMP_PLACES={os.environ.get('OMP_PLACES', 'cores')}")
    print(f"{'case':>4s} {'target':>7s} {'fluid':>9s} {'thr':>3s} {'steps':>5s} {'ns/p-step':>10s} {'speed-up':>8s} "
          f"{'effic.':>6s} {'peak MB':>8s} {'load':>5s}")
    for case in a.cases.split(","):
        scene, size, dim, dx0, dt0 = CASES[case]
        for target in [float(s) for s in a.sizes.split(",")]:
            dx = (size / target) ** (1.0 / dim)
            dt = dt0 * dx / dx0
            steps, repeats = plan(target)
            one = None
            for t in threads:
                r = bench(a.bench, scene, dx, dt, t, steps, repeats)
                if t == threads[0]:
                    one = r["ns_per_particle_step"] * threads[0]
                speedup = one / r["ns_per_particle_step"]
                r.update(case=case, target=int(target), dx=dx, steps=steps, repeats=repeats, speedup=speedup,
                         efficiency=speedup / t)
                rows.append(r)
                print(f"{case:>4s} {target:7.0e} {r['fluid']:9d} {t:3d} {steps:5d} {r['ns_per_particle_step']:10.1f} "
                      f"{speedup:8.2f} {speedup / t:6.2f} {r['peak_mb']:8.1f} {r['load_before']:5.2f}", flush=True)
    fields = ["case", "target", "dx", "fluid", "boundary", "threads", "steps", "repeats", "neighbours",
              "ns_per_particle_step", "ms_per_step", "speedup", "efficiency", "peak_mb", "load_before", "load_after"]
    with open(a.out + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    for case in a.cases.split(","):
        for target in sorted({r["target"] for r in rows if r["case"] == case}):
            rr = [r for r in rows if r["case"] == case and r["target"] == target]
            best = max(rr, key=lambda r: r["threads"])
            print(f"{case} {target:.0e}: {best['speedup']:.2f}x at {best['threads']} threads "
                  f"({'meets' if best['threads'] < 16 or best['speedup'] >= 12 else 'misses'} the 12x-at-16 goal)")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: no PNG")
        return 0
    fig, ax = plt.subplots(figsize=(6, 4))
    for case in a.cases.split(","):
        for target in sorted({r["target"] for r in rows if r["case"] == case}):
            rr = [r for r in rows if r["case"] == case and r["target"] == target]
            ax.plot([r["threads"] for r in rr], [r["speedup"] for r in rr], "o-", label=f"{case} {target:.0e}")
    tmax = max(threads)
    ax.plot([1, tmax], [1, tmax], "k:", lw=0.8, label="ideal")
    ax.axhline(12, color="grey", lw=0.8, ls="--")
    ax.set_xlabel("threads")
    ax.set_ylabel("speed-up over one thread")
    ax.set_title("bench_step: dam breaks, speed-up per thread count")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.out + ".png", dpi=120)
    print(f"wrote {a.out}.csv and {a.out}.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
