"""A run on 3 MPI ranks opens like a serial run: ParaView's reader of the .pvd (frames are .pvtu + pieces),
the bundled varsph Python package, paraview/postprocess.py and `varsph compare`.
Usage: xvfb-run -a pvpython check_pvtu.py VARSPH_EXECUTABLE "MPIRUN -n 3" SCENE.json

Checks: same frames and times; every frame has the serial frame's particles, arrays and field data, and
equal values particle by particle (matched by id; the states are bitwise equal); postprocess.py writes the
same files with the same tables; `varsph compare` of the two runs gives D = 0 at every frame."""
import csv
import os
import shlex
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "paraview"))
import tcommon as T  # noqa: E402
import varsph as V  # noqa: E402

exe, mpirun, scene = sys.argv[1], shlex.split(sys.argv[2]), sys.argv[3]
tmp = T.workdir("pvtu")
runs = {"serial": os.path.join(tmp, "serial"), "mpi": os.path.join(tmp, "mpi")}
args = ["run", scene, "--set", "time.end=0.06", "--set", "output.every=0.02", "--quiet"]
# pvpython initialises its own MPI (a singleton): its OMPI_* / PMIX_* variables would make the launched
# mpiexec and varsph believe they are inside that job, so the runs get a clean environment
env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_", "PRTE_"))}
for name, prefix in (("serial", []), ("mpi", mpirun)):
    p = subprocess.run(prefix + [exe] + args + ["-o", runs[name]], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, timeout=600, env=env)
    print(p.stdout[-2000:])
    T.check(p.returncode == 0, "%s run exit status 0 (%d)" % (name, p.returncode))
    if p.returncode != 0:
        T.finish(tmp)

fs, fm = V.frames_of_run(runs["serial"]), V.frames_of_run(runs["mpi"])
T.check(len(fs) == len(fm) >= 4, "%d frames in both runs" % len(fm))
T.check(all(p.endswith(".pvtu") for _, p in fm), "the MPI run's .pvd lists .pvtu frames")
for (ts, ps), (tm, pm) in zip(fs, fm):
    a, b = V.read_vtu(ps, ts), V.read_vtu(pm, tm)
    T.check(ts == tm, "frame times %g / %g" % (ts, tm))
    T.check(len(a.points) == len(b.points), "t = %g: %d points in both" % (ts, len(b.points)))
    T.check(sorted(a.arrays) == sorted(b.arrays), "t = %g: the same point arrays %s" % (ts, sorted(b.arrays)))
    T.check(set(a.fields) == set(b.fields) and all(str(a.fields[k]) == str(b.fields[k]) for k in a.fields),
            "t = %g: the same field data (%s)" % (ts, ", ".join(sorted(b.fields))))
    ia, ib = np.argsort(a.arrays["id"]), np.argsort(b.arrays["id"])
    same = np.array_equal(a.points[ia], b.points[ib]) and all(
        np.array_equal(a.arrays[k][ia], b.arrays[k][ib]) for k in a.arrays)
    T.check(same, "t = %g: every particle's position and arrays equal (matched by id)" % ts)

# ParaView's own readers through the .pvd (what a user opens)
from paraview import servermanager  # noqa: E402
from paraview.simple import OpenDataFile, UpdatePipeline  # noqa: E402
counts = {}
for name, run in runs.items():
    pvd = [f for f in os.listdir(run) if f.endswith(".pvd")][0]
    src = OpenDataFile(os.path.join(run, pvd))
    times = list(src.TimestepValues)
    UpdatePipeline(time=times[-1], proxy=src)
    data = servermanager.Fetch(src)
    counts[name] = (len(times), data.GetNumberOfPoints(), data.GetPointData().GetNumberOfArrays(),
                    data.GetFieldData().GetArray("time").GetValue(0) if data.GetFieldData().GetArray("time") else None)
T.check(counts["serial"] == counts["mpi"], "ParaView's PVD reader: (times, points, arrays, time) %s / %s"
        % (counts["serial"], counts["mpi"]))

# post-processing: the same files and tables
for name, run in runs.items():
    p = subprocess.run([T.pvpython(), os.path.join(T.PARAVIEW_DIR, "postprocess.py"), run, "--compare",
                        runs["serial"]], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
    print(p.stdout[-1500:])
    T.check(p.returncode == 0, "postprocess.py on the %s run: exit status 0 (%d)" % (name, p.returncode))
post = {name: sorted(os.listdir(os.path.join(run, "post"))) for name, run in runs.items()}
T.check(post["serial"] == post["mpi"], "postprocess.py wrote the same files: %s" % post["mpi"])
for table in ("surge_front.csv", "momentum.csv"):
    rows = {}
    for name, run in runs.items():
        with open(os.path.join(run, "post", table)) as f:
            rows[name] = list(csv.reader(f))
    same = len(rows["serial"]) == len(rows["mpi"]) and all(
        len(r) == len(s) and all(abs(float(x) - float(y)) <= 1e-9 * (1 + abs(float(x))) for x, y in zip(r, s))
        for r, s in zip(rows["serial"][1:], rows["mpi"][1:]))
    T.check(same, "post/%s equal to 1e-9" % table)

out = os.path.join(tmp, "cmp")
p = subprocess.run([exe, "compare", runs["mpi"], runs["serial"], "-o", out, "--quiet"], stdout=subprocess.PIPE,
                   stderr=subprocess.STDOUT, text=True, timeout=300)
T.check(p.returncode == 0, "varsph compare of the .pvtu and .vtu runs: exit 0 (%d) %s" % (p.returncode, p.stdout[-500:]))
with open(os.path.join(out, "deviation.csv")) as f:
    dev = list(csv.DictReader(f))
T.check(len(dev) >= 4 and all(float(r["D_max"]) == 0.0 for r in dev), "D_max = 0 at all %d frames" % len(dev))
T.finish(tmp)
