#!/usr/bin/env python3
"""The vectorised pair sweep against the scalar one (issue 19 point 1), two ways, both printed as ratios.

  --mode callgrind (default): instructions per fluid particle-step from valgrind's callgrind, repeatable on a
      loaded machine. Each (case, sweep, threads) runs bench_step twice, with S1 and S2 timed steps; the
      difference of the two instruction totals divided by (S2 - S1) x fluid particles is the cost of one step
      alone (set-up, warm-up step and bench_step's neighbour count cancel). 2 threads run with
      OMP_WAIT_POLICY=passive so that waiting threads sleep instead of spinning (spinning would count
      instructions that depend on the scheduling); the 2-thread figure is the sum over both threads, i.e.
      the parallel overhead in instructions, not a speed.
  --mode wall: ns per fluid particle-step from bench_step, scalar and vector runs interleaved (A B A B ...),
      best of the rounds, with the load average before each run (noisy on a shared machine).

  /usr/bin/python3 bench/simd_speedup.py [--bench build/release/bin/bench_step] [--mode callgrind|wall]
      [--cases paper,dsph,engineering,box3d] [--threads 1,2] [--rounds 3]

The sweep is chosen by VARSPH_SIMD (scalar | auto); `auto` is the best of avx512 / avx2 this build and CPU have.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
P = os.path.join(ROOT, "pipelines")

# name: scene, overrides, (S1, S2) timed steps for callgrind, steps for wall
CASES = {
    # the paper's dam break (Gaussian, repulsive walls, AV; 1682 fluid particles), the README's default scene
    "paper": (os.path.join(P, "dam_break_2d_paper.json"), [], (2, 12), 400),
    # the same with verlet_dsph (one fused sweep per step)
    "paper_dsph": (os.path.join(P, "dam_break_2d_paper.json"), ['integrator.type="verlet_dsph"'], (2, 12), 400),
    # DualSPHysics' 2D validation set-up (Wendland, dynamic walls, Fourtakas, verlet_dsph): the peer case
    "dsph": (os.path.join(P, "dam_break_2d_dsph_val.json"), [], (1, 4), 60),
    # the paper's dam break with Morris' laminar viscosity beside the artificial one (nu = 1e-6, water)
    "paper_laminar": (os.path.join(P, "dam_break_2d_paper.json"), ['physics.laminar_viscosity={"nu": 1e-6}'], (2, 12), 400),
    # the recommended engineering set-up (Wendland, dummy walls, Riemann solver, symplectic Euler; 5000 fluid)
    "engineering": (os.path.join(P, "engineering_2d.json"), [], (1, 4), 60),
    # 3D block, cubic spline h = 1.732 dp as DualSPHysics' 3D case, coarsened to ~12k particles for callgrind
    "box3d": (os.path.join(P, "bench_box_3d.json"),
              ['kernel.type="cubic_spline"', "kernel.h_over_dx=1.732", "particles.spacing=0.0172"], (1, 3), 20),
}


def loadavg():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def bench_cmd(exe, case, steps, threads):
    scene, sets, _, _ = CASES[case]
    cmd = [exe, "--scene", scene, "--steps", str(steps), "--repeats", "1", "--threads", str(threads)]
    for s in sets:
        cmd += ["--set", s]
    return cmd


def custom_row(out):
    rows = [ln.split() for ln in out.splitlines() if ln.startswith("custom")]
    if not rows:
        raise SystemExit("bench_step printed no result line:\n" + out)
    r = rows[-1]
    return {"fluid": int(r[1]), "ns": float(r[5]), "sweep": r[11] if len(r) > 11 else "?"}


def run(cmd, sweep, threads, extra_env=None):
    env = dict(os.environ, VARSPH_SIMD=sweep)
    if extra_env:
        env.update(extra_env)
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
    return p.stdout


def instructions(exe, case, steps, sweep, threads):
    with tempfile.TemporaryDirectory() as d:
        out_file = os.path.join(d, "cg.out")
        cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out_file}"] + bench_cmd(exe, case, steps, threads)
        env = {"OMP_WAIT_POLICY": "passive"} if threads > 1 else {}
        stdout = run(cmd, sweep, threads, env)
        total = None
        with open(out_file) as f:
            for ln in f:
                m = re.match(r"(summary|totals):\s+(\d+)", ln)
                if m:
                    total = int(m.group(2))
        if total is None:
            raise SystemExit("no instruction total in the callgrind output")
        return total, custom_row(stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bench", default=os.path.join(ROOT, "build", "release", "bin", "bench_step"))
    ap.add_argument("--mode", choices=["callgrind", "wall"], default="callgrind")
    ap.add_argument("--cases", default="paper,dsph,engineering,box3d")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--rounds", type=int, default=3, help="wall mode: interleaved A/B rounds")
    a = ap.parse_args()
    threads = [int(t) for t in a.threads.split(",")]
    print(f"# {a.bench}, mode {a.mode}, load average {loadavg():.2f} at the start")
    if a.mode == "callgrind":
        print(f"{'case':>10s} {'thr':>3s} {'fluid':>7s} {'scalar Ir/p-step':>16s} {'vector Ir/p-step':>16s} "
              f"{'sweep':>6s} {'ratio':>6s}")
        for case in a.cases.split(","):
            s1, s2 = CASES[case][2]
            for t in threads:
                per = {}
                for sweep in ("scalar", "auto"):
                    i1, r1 = instructions(a.bench, case, s1, sweep, t)
                    i2, r2 = instructions(a.bench, case, s2, sweep, t)
                    per[sweep] = ((i2 - i1) / ((s2 - s1) * r2["fluid"]), r2)
                sc, vc = per["scalar"][0], per["auto"][0]
                print(f"{case:>10s} {t:3d} {per['auto'][1]['fluid']:7d} {sc:16.0f} {vc:16.0f} "
                      f"{per['auto'][1]['sweep']:>6s} {sc / vc:6.2f}", flush=True)
    else:
        print(f"{'case':>10s} {'thr':>3s} {'fluid':>7s} {'scalar ns':>10s} {'vector ns':>10s} {'sweep':>6s} "
              f"{'ratio':>6s} {'loads':>12s}")
        for case in a.cases.split(","):
            steps = CASES[case][3]
            for t in threads:
                best = {"scalar": float("inf"), "auto": float("inf")}
                loads, row = [], None
                for _ in range(a.rounds):
                    for sweep in ("scalar", "auto"):
                        loads.append(loadavg())
                        r = custom_row(run(bench_cmd(a.bench, case, steps, t), sweep, t))
                        best[sweep] = min(best[sweep], r["ns"])
                        if sweep == "auto":
                            row = r
                print(f"{case:>10s} {t:3d} {row['fluid']:7d} {best['scalar']:10.1f} {best['auto']:10.1f} "
                      f"{row['sweep']:>6s} {best['scalar'] / best['auto']:6.2f} {min(loads):5.2f}-{max(loads):5.2f}",
                      flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
