#!/usr/bin/env python3
"""Peak memory per particle of a run (issue 9b): (peak RSS of the big run - peak RSS of a tiny run) / particles.

Both runs are `varsph run pipelines/dam_break_2d_paper.json` for one step (dt scaled with dx, time.end = dt)
with the default output, so two frames are written (t = 0 and the end) and the blow-up snapshot is taken;
peak RSS is the child's ru_maxrss (os.wait4). Default: dx = 0.2 mm (1,060,152 particles) against dx = 5 mm
(2,040 particles).

  /usr/bin/python3 bench/memory_per_particle.py [--bin build/release/bin/varsph] [--dx 0.0002]
      [--set domain.neighbor_search=hash]... [--threads 1]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCENE = os.path.join(ROOT, "pipelines", "dam_break_2d_paper.json")


def run(exe, dx, sets, threads, outdir):
    dt = 1e-4 * dx / 0.005  # the scene's dt = 1e-4 s at dx = 5 mm, scaled with dx (CFL)
    cmd = [exe, "run", SCENE, "-o", outdir, "--overwrite", "--quiet", "--threads", str(threads),
           "--set", f"particles.spacing={dx!r}", "--set", f"integrator.dt={dt!r}", "--set", f"time.end={dt!r}"]
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    _, status, ru = os.wait4(p.pid, 0)
    out, err = p.stdout.read().decode(), p.stderr.read().decode()
    rc = os.waitstatus_to_exitcode(status)
    if rc != 0:
        raise SystemExit(f"{' '.join(cmd)}: exit {rc}\n{out}\n{err}")
    with open(os.path.join(outdir, "run.json")) as f:
        rj = json.load(f)
    n = rj.get("particles", {}).get("total") if isinstance(rj.get("particles"), dict) else None
    if n is None:
        import glob
        frames = sorted(glob.glob(os.path.join(outdir, "frames", "*.vtu")))
        with open(frames[0], "rb") as f:
            head = f.read(4096).decode("latin-1")
        n = int(head.split('NumberOfPoints="')[1].split('"')[0])
    return ru.ru_maxrss * 1024, int(n)  # ru_maxrss in KiB


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "release", "bin", "varsph"))
    ap.add_argument("--dx", type=float, default=0.0002)
    ap.add_argument("--tiny-dx", type=float, default=0.005)
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--threads", type=int, default=1)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="varsph_mem_") as tmp:
        rss0, n0 = run(a.bin, a.tiny_dx, a.set, a.threads, os.path.join(tmp, "tiny"))
        rss1, n1 = run(a.bin, a.dx, a.set, a.threads, os.path.join(tmp, "big"))
    with open("/proc/loadavg") as f:
        load = f.read().split()[0]
    print(f"# {a.bin} {' '.join(a.set)} (load average {load})")
    print(f"tiny run: {n0} particles, peak RSS {rss0 / 1e6:.1f} MB")
    print(f"big run:  {n1} particles, peak RSS {rss1 / 1e6:.1f} MB")
    print(f"bytes per particle: {(rss1 - rss0) / (n1 - n0):.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
