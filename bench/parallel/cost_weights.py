#!/usr/bin/env python3
"""Partition weights by count against weights by measured cost, in instructions (repeatable on a shared
machine, where busy times are not): docs/parallel.md "Load balance".

For a scene on P ranks (valgrind's callgrind, one thread per rank, no rebalancing):
  1. weights by count (parallel.weights.fluid 4, boundary 1): the instructions of each rank's steps outside
     the MPI libraries (where a rank waiting for its peer spins)
     (a run of S2 steps minus a run of S1 steps: set-up and start-up cancel) and each rank's owned fluid
     and wall particles (the last frame's pieces);
  2. the fit of parallel/cost_fit.hpp on those instructions: I_r ~ c_f F_r + c_w W_r -> c_w / c_f;
  3. weights by that cost (fluid 64, boundary round(64 c_w / c_f)), measured the same way.
Prints the instructions per rank and the imbalance (slowest / mean) of both.

  python3 bench/parallel/cost_weights.py [--scene S] [--ranks 2] [--steps 10,40] [--set KEY=VALUE ...]
"""
import argparse
import glob
import json
import os
import re
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def kinds_of_piece(path):
    """(fluid, boundary) counts of one .vtu piece written by varsph (raw appended data, UInt64 headers)."""
    data = open(path, "rb").read()
    head = data[: data.index(b"<AppendedData")].decode()
    off = int(re.search(r'Name="kind" format="appended" offset="(\d+)"', head).group(1))
    start = data.index(b"_", data.index(b"<AppendedData")) + 1 + off
    nbytes = struct.unpack("<Q", data[start : start + 8])[0]
    kinds = struct.unpack("<%di" % (nbytes // 4), data[start + 8 : start + 8 + nbytes])
    fluid = sum(1 for k in kinds if k == 0)
    return fluid, len(kinds) - fluid


MPI_OBJECTS = re.compile(r"\[[^\]]*(openmpi|libmpi|libopen-|pmix|libevent|hwloc|mca_)[^\]]*\]\s*$")


def work_instructions(path):
    """Instructions outside the MPI libraries: a rank waiting for its peer spins in them (opal_progress),
    which is waiting, not work."""
    text = subprocess.run(["callgrind_annotate", "--inclusive=no", "--threshold=100", path], check=True,
                          capture_output=True, text=True).stdout
    total = 0
    for line in text.splitlines():
        m = re.match(r"^\s*([\d,]+) \(\s*[\d.]+%\)\s+(.*)$", line)
        if not m or "PROGRAM TOTALS" in line or MPI_OBJECTS.search(m.group(2)):
            continue
        total += int(m.group(1).replace(",", ""))
    return total


def run(args, out, steps, fluid_w, boundary_w):
    """Instructions per rank (callgrind totals) and the last frame's (fluid, boundary) per rank."""
    os.makedirs(out, exist_ok=True)
    dt_sets = ["--set", "time.end=%g" % (steps * args.dt), "--set", "output.every=%g" % (steps * args.dt)]
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-n", str(args.ranks),
           "valgrind", "--tool=callgrind", "--callgrind-out-file=%s/cg.%%q{OMPI_COMM_WORLD_RANK}" % out,
           os.path.join(ROOT, "build/release/bin/varsph"), "run", args.fixed_dt_scene, "-o", out + "/run",
           "--overwrite", "--quiet", "--threads", "1",
           "--set", "parallel.rebalance_check_every=0",
           "--set", "parallel.weights.fluid=%d" % fluid_w, "--set", "parallel.weights.boundary=%d" % boundary_w]
    for s in args.set:
        cmd += ["--set", s]
    subprocess.run(cmd + dt_sets, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    ir = [work_instructions("%s/cg.%d" % (out, r)) for r in range(args.ranks)]
    pieces = sorted(glob.glob(out + "/run/frames/*/*.vtu"))
    last = sorted({os.path.dirname(p) for p in pieces})[-1]
    counts = [kinds_of_piece(p) for p in sorted(glob.glob(last + "/*.vtu"), key=lambda p: int(p[:-4].rsplit("_", 1)[1]))]
    return ir, counts


def measure(args, tmp, fluid_w, boundary_w):
    s1, s2 = args.steps
    ir1, _ = run(args, tmp + "/a%d_%d" % (fluid_w, boundary_w), s1, fluid_w, boundary_w)
    ir2, counts = run(args, tmp + "/b%d_%d" % (fluid_w, boundary_w), s2, fluid_w, boundary_w)
    per_step = [(b - a) / (s2 - s1) for a, b in zip(ir1, ir2)]
    return per_step, counts


def imbalance(v):
    return max(v) / (sum(v) / len(v))


def fit(per_step, counts):
    ff = sum(f * f for f, w in counts)
    ww = sum(w * w for f, w in counts)
    fw = sum(f * w for f, w in counts)
    fb = sum(f * b for (f, w), b in zip(counts, per_step))
    wb = sum(w * b for (f, w), b in zip(counts, per_step))
    det = ff * ww - fw * fw
    cf = (fb * ww - wb * fw) / det
    cw = (ff * wb - fw * fb) / det
    return cf, cw


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default=os.path.join(ROOT, "pipelines/dam_break_2d_dsph_val.json"))
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--steps", default="10,40")
    ap.add_argument("--dt", type=float, default=5e-5)
    ap.add_argument("--set", action="append", default=None, help="scene keys (default particles.spacing=0.02)")
    args = ap.parse_args()
    args.steps = [int(s) for s in args.steps.split(",")]
    args.set = args.set if args.set is not None else ["particles.spacing=0.02"]
    with tempfile.TemporaryDirectory(prefix="cost_weights_") as tmp:
        # a fixed dt, so that both runs make exactly the steps asked for (mesh paths: scenes without meshes)
        scene = json.load(open(args.scene))
        scene["integrator"].pop("cfl", None)
        scene["integrator"].pop("cfl_criteria", None)
        scene["integrator"]["dt"] = args.dt
        args.fixed_dt_scene = tmp + "/scene.json"
        json.dump(scene, open(args.fixed_dt_scene, "w"))
        a, ca = measure(args, tmp, 4, 1)
        cf, cw = fit(a, ca)
        ratio = min(max(cw / cf, 0.0), 4.0)
        bw = round(64 * ratio)
        b, cb = measure(args, tmp, 64, bw)
    print("scene %s, %d ranks, steps %s, %s" % (os.path.basename(args.scene), args.ranks, args.steps, " ".join(args.set)))
    print("count weights 4:1   instructions per step per rank %s  (fluid, walls) %s  imbalance %.3f"
          % ([round(x / 1e6, 2) for x in a], ca, imbalance(a)))
    print("fit: c_f %.0f, c_w %.0f instructions per particle-step; c_w / c_f = %.3f" % (cf, cw, cw / cf))
    print("cost weights 64:%d  instructions per step per rank %s  (fluid, walls) %s  imbalance %.3f"
          % (bw, [round(x / 1e6, 2) for x in b], cb, imbalance(b)))


if __name__ == "__main__":
    sys.exit(main())
