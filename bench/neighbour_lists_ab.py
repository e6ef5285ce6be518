#!/usr/bin/env python3
"""Neighbour lists kept between passes (src/physics/simd/list_cache.hpp) against lists rebuilt in every pass:
interleaved A/B runs of bench_step (VARSPH_NEIGHBOUR_LISTS=rebuild | reuse), best of the rounds, ns per fluid
particle-step and the ratio, with the load average (wall clock: noisy on a shared machine).

  /usr/bin/python3 bench/neighbour_lists_ab.py [--cases paper,variational,dsph] [--threads 1,2] [--rounds 5]
      [--bench build/release/bin/bench_step]
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
    a = ap.parse_args()
    for case in a.cases.split(","):
        for thr in a.threads.split(","):
            best, loads = {}, []
            for _ in range(a.rounds):
                for mode in ("rebuild", "reuse"):
                    loads.append(os.getloadavg()[0])
                    env = dict(os.environ, VARSPH_NEIGHBOUR_LISTS=mode)
                    p = subprocess.run([a.bench] + CASES[case] + ["--repeats", "1", "--threads", thr],
                                       capture_output=True, text=True, env=env)
                    if p.returncode != 0:
                        raise SystemExit(f"bench_step exit {p.returncode}:\n{p.stdout}\n{p.stderr}")
                    row = [ln.split() for ln in p.stdout.splitlines() if ln.startswith("custom")][-1]
                    best[mode] = min(best.get(mode, float("inf")), float(row[5]))
            print(f"{case:12s} threads {thr}: rebuild {best['rebuild']:8.1f} ns, reuse {best['reuse']:8.1f} ns per fluid "
                  f"particle-step, ratio {best['rebuild'] / best['reuse']:.3f}  (load {min(loads):.2f}-{max(loads):.2f})",
                  flush=True)


if __name__ == "__main__":
    main()
