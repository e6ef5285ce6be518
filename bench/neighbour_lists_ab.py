#!/usr/bin/env python3
"""Interleaved A/B runs of bench_step with an environment switch, best of the rounds, ns per fluid
particle-step and the ratio A/B, with the load average (wall clock: noisy on a shared machine). By default
the neighbour lists kept between passes (src/physics/simd/list_cache.hpp; VARSPH_NEIGHBOUR_LISTS=rebuild |
reuse); `--switch VARSPH_STEP_REGION=per_loop,one` compares one parallel region per loop with one per step
(src/core/team.hpp).

  /usr/bin/python3 bench/neighbour_lists_ab.py [--cases paper,variational,dsph] [--threads 1,2] [--rounds 5]
      [--switch NAME=A,B] [--steps-scale S] [--bench build/release/bin/bench_step]
"""
import argparse
import os
import subprocess

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
P = os.path.join(ROOT, "pipelines")
CASES = {  # the paper's Verlet (two passes per configuration), variational alpha 0.5, the peer case (one fused pass)
    "paper": ["--scene", os.path.join(P, "dam_break_2d_paper.json"), "--steps", "400"],
    "variational": ["--scene", os.path.join(P, "dam_break_2d_paper.json"), "--set", 'integrator.type="variational"',
                    "--steps", "150"],
    "dsph": ["--scene", os.path.join(P, "dam_break_2d_dsph_val.json"), "--steps", "60"],
}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bench", default=os.path.join(ROOT, "build", "release", "bin", "bench_step"))
    ap.add_argument("--cases", default="paper,variational,dsph")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--switch", default="VARSPH_NEIGHBOUR_LISTS=rebuild,reuse")
    ap.add_argument("--steps-scale", type=float, default=1.0, help="multiplies each case's step count")
    a = ap.parse_args()
    var, values = a.switch.split("=", 1)
    A, B = values.split(",")
    for case in a.cases.split(","):
        for thr in a.threads.split(","):
            best, loads = {}, []
            for _ in range(a.rounds):
                for mode in (A, B):
                    loads.append(os.getloadavg()[0])
                    env = dict(os.environ, **{var: mode})
                    args = list(CASES[case])
                    k = args.index("--steps") + 1
                    args[k] = str(max(1, int(int(args[k]) * a.steps_scale)))
                    p = subprocess.run([a.bench] + args + ["--repeats", "1", "--threads", thr],
                                       capture_output=True, text=True, env=env)
                    if p.returncode != 0:
                        raise SystemExit(f"bench_step exit {p.returncode}:\n{p.stdout}\n{p.stderr}")
                    row = [ln.split() for ln in p.stdout.splitlines() if ln.startswith("custom")][-1]
                    best[mode] = min(best.get(mode, float("inf")), float(row[5]))
            print(f"{case:12s} threads {thr}: {A} {best[A]:8.1f} ns, {B} {best[B]:8.1f} ns per fluid "
                  f"particle-step, ratio {best[A] / best[B]:.3f}  (load {min(loads):.2f}-{max(loads):.2f})",
                  flush=True)


if __name__ == "__main__":
    main()
