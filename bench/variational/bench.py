#!/usr/bin/env python3
"""Speed against error for the variational integrator on the paper's dam break (docs/variational.md).

1. cost per step and mean fixed-point iterations for alpha = 0.5 at dt = 1e-4, 2e-4, 4e-4 (default
   tolerance 1e-6 dx), and the explicit scheme at 1e-4, each to --t-cost simulated seconds;
2. the largest stable dt of the explicit (verlet) and the alpha = 0.5 schemes: a run to --t-stable s
   counts as stable when it exits 0 (no NaN, particles inside, |rho/rho0 - 1| < 0.5, fixed point
   converged with on_failure = fail).

Usage: bench.py [--varsph build/release/bin/varsph] [--out bench_out] [--threads 1]
Only the Python standard library is needed. Prints a Markdown table and writes OUT/results.json.
"""
import argparse
import csv
import json
import os
import resource
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "pipelines", "dam_break_2d_paper.json")


def run(exe, out, sets, threads):
    cmd = [exe, "run", SCENE, "-o", out, "--overwrite", "--quiet", "--threads", str(threads)]
    for s in sets:
        cmd += ["--set", s]
    t0 = time.time()
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, capture_output=True, text=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall = time.time() - t0
    # CPU seconds of the (single-threaded) run: robust on a machine shared with other jobs
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    info = {"exit": p.returncode, "wall": wall, "cpu": cpu, "stderr": p.stderr.strip()[-400:]}
    rj = os.path.join(out, "run.json")
    if os.path.exists(rj):
        with open(rj) as f:
            j = json.load(f)
        t = j.get("timings", {})
        info["steps"] = t.get("steps", 0)
        info["seconds"] = t.get("wall_seconds", wall)
        info["ms_per_step_wall"] = 1e3 * info["seconds"] / max(info["steps"], 1)
        info["ms_per_step"] = 1e3 * cpu / max(info["steps"], 1)  # includes setup and frame output
    dg = os.path.join(out, "diagnostics.csv")
    if os.path.exists(dg):
        with open(dg) as f:
            rows = [r for r in csv.DictReader(f) if r.get("fp_iterations_mean")]
        if rows:
            # mean over frames weighted by steps between rows
            steps, its, prev = 0, 0.0, 0
            for r in rows:
                n = int(r["step"]) - prev
                prev = int(r["step"])
                steps += n
                its += n * float(r["fp_iterations_mean"])
            info["iterations_mean"] = its / max(steps, 1)
            info["iterations_max"] = max(int(r["fp_iterations_max"]) for r in rows)
            info["dt_bound"] = float(rows[-1]["dt_bound"])
    return info


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--varsph", default=os.path.join(ROOT, "build", "release", "bin", "varsph"))
    ap.add_argument("--out", default=os.path.join(ROOT, "runs", "bench_variational"))
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--t-cost", type=float, default=0.2)
    ap.add_argument("--t-stable", type=float, default=0.25)
    ap.add_argument("--dts", default="2e-4,3e-4,4e-4,5e-4,6e-4")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    res = {"cost": [], "stability": []}
    common = [f"time.end={a.t_cost}", f"output.every={a.t_cost / 4}"]
    cases = [("verlet", 1.0, 1e-4, "fail"), ("verlet", 1.0, 2e-4, "fail")] + \
        [("variational", 0.5, dt, "fail") for dt in (1e-4, 2e-4, 4e-4)] + [("variational", 0.5, 4e-4, "halve_dt")]
    for typ, alpha, dt, fail in cases:
        out = os.path.join(a.out, f"cost_{typ}_{dt:g}_{fail}")
        r = run(a.varsph, out, common + [f'integrator.type="{typ}"', f"integrator.alpha={alpha}",
                                          f"integrator.dt={dt}", f'integrator.fixed_point.on_failure="{fail}"'],
                a.threads)
        r.update(type=typ, alpha=alpha, dt=dt, on_failure=fail)
        res["cost"].append(r)
        print(json.dumps(r), file=sys.stderr)
    for typ, alpha in (("verlet", 1.0), ("variational", 0.5)):
        for dt in [float(x) for x in a.dts.split(",")]:
            out = os.path.join(a.out, f"stable_{typ}_{dt:g}")
            r = run(a.varsph, out, [f"time.end={a.t_stable}", f"output.every={a.t_stable / 4}",
                                    f'integrator.type="{typ}"', f"integrator.alpha={alpha}",
                                    f"integrator.dt={dt}"], a.threads)
            r.update(type=typ, alpha=alpha, dt=dt)
            res["stability"].append(r)
            print(json.dumps(r), file=sys.stderr)
            if r["exit"] != 0:
                break  # larger dt will not be stable either
    with open(os.path.join(a.out, "results.json"), "w") as f:
        json.dump(res, f, indent=1)
    print("| scheme | dt [s] | on_failure | exit | CPU ms/step | CPU s per simulated s | mean iterations | "
          "max iterations | dt bound [s] |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in res["cost"]:
        name = "explicit (verlet)" if r["type"] == "verlet" else f"alpha = {r['alpha']}"
        ms = r.get("ms_per_step", float("nan"))
        sps = ms * 1e-3 * r.get("steps", 0) / a.t_cost if r.get("steps") else float("nan")
        print(f"| {name} | {r['dt']:g} | {r['on_failure']} | {r['exit']} | {ms:.2f} | {sps:.1f} | "
              f"{r.get('iterations_mean', 0):.2f} | {r.get('iterations_max', 0)} | {r.get('dt_bound', 0):.3g} |")
    print()
    for typ in ("verlet", "variational"):
        ok = [r["dt"] for r in res["stability"] if r["type"] == typ and r["exit"] == 0]
        bad = [(r["dt"], r["exit"], r["stderr"][-200:]) for r in res["stability"] if r["type"] == typ and r["exit"] != 0]
        print(f"{typ}: largest stable dt tried: {max(ok) if ok else None}; first failure: {bad[0] if bad else None}")


if __name__ == "__main__":
    main()
