"""Deviation (paper eq. 70) between two runs, matched by id and by time (1e-9 s), fluid particles only.

A run against itself: D = 0. Against a copy shifted by a known vector with the particle order
shuffled: D_max = D_mean = D_rms = |shift| to 1e-9 (boundary particles moved elsewhere do not count).
Frames only one run has are skipped. The CSV has exactly the columns of `varsph compare`."""
import os

import numpy as np

import tcommon as T
import synthetic as S
import varsph as V
from varsph import deviation as D

tmp = T.workdir("dev")
dx = 0.05
rng = np.random.default_rng(1)
shift = np.array([0.013, -0.0071, 0.0])


def frames(shifted, times, perm=None, dim=2):
    out = []
    base = S.lattice_block((9, 7) if dim == 2 else (5, 4, 3), dx)
    n = len(base)
    kind = np.zeros(n)
    kind[: n // 5] = 1                      # some boundary particles
    for k, t in enumerate(times):
        p = base + 0.01 * k * np.sin(base * 7.0) * (1 if dim == 3 else np.array([1, 1, 0]))
        if shifted:
            p = p + shift * (1 if dim == 3 else np.array([1, 1, 0]))
            p[kind == 1] += 5.0             # boundary particles far away: must not count
        ids = np.arange(n)
        kk = kind
        if perm is not None:
            p, ids, kk = p[perm], ids[perm], kind[perm]
        out.append(S.make_frame(p, dx, dim, time=t, step=k, ids=ids, kind=kk))
    return out


times = [0.0, 0.1, 0.2, 0.30000000000000004]
a = os.path.join(tmp, "a")
b = os.path.join(tmp, "b")
c = os.path.join(tmp, "c")
S.write_run(a, frames(False, times))
n = 63
S.write_run(b, frames(True, times[:2] + [0.25] + times[3:], perm=rng.permutation(n)))
S.write_run(c, frames(False, times))

rows = D.deviation_series(a, c)
T.check(len(rows) == 4, "self: 4 matched times (%d)" % len(rows))
T.check(all(r[1] == 0 and r[2] == 0 and r[3] == 0 for r in rows), "self: D_max = D_mean = D_rms = 0 at all times")
rows = D.deviation_series(a, a)
T.check(all(r[1] == 0 for r in rows), "run against its own directory: D = 0")

rows = D.deviation_series(a, b)
T.check([r[0] for r in rows] == [0.0, 0.1, 0.30000000000000004],
        "shifted: frames matched by time (0.2 vs 0.25 skipped): %s" % [r[0] for r in rows])
L = float(np.linalg.norm(shift))
for r in rows:
    for k, name in ((1, "D_max"), (2, "D_mean"), (3, "D_rms")):
        T.close(r[k], L, 1e-9, "shifted t=%g %s = |shift|" % (r[0], name))

# per-particle vectors
A = next(V.read_run(a))
B = next(V.read_run(b))
res = D.deviation_frame(A, B)
fl = A.fluid_mask()
T.check(np.allclose(res["vector"][fl], -shift, atol=1e-12), "per-particle deviation = q_A - q_B = -shift")
T.check(res["count"] == fl.sum(), "all %d fluid particles matched" % fl.sum())

# 3D
S.write_run(os.path.join(tmp, "a3"), frames(False, times[:2], dim=3))
S.write_run(os.path.join(tmp, "b3"), frames(True, times[:2], dim=3, perm=rng.permutation(60)))
rows = D.deviation_series(os.path.join(tmp, "a3"), os.path.join(tmp, "b3"))
T.close(rows[-1][1], float(np.linalg.norm(shift)), 1e-9, "3D shifted D_max")

path = D.write_deviation_csv(D.deviation_series(a, b), os.path.join(tmp, "deviation.csv"))
head = open(path).readline().strip()
T.check(head == "time,D_max,D_mean,D_rms", "CSV header '%s'" % head)

try:
    S.write_run(os.path.join(tmp, "late"), frames(False, [1.0, 2.0]))
    D.deviation_series(a, os.path.join(tmp, "late"))
    T.check(False, "runs without common times raise")
except ValueError as e:
    T.check("no frame times" in str(e), "runs without common times raise: %s" % e)
T.finish(tmp)
