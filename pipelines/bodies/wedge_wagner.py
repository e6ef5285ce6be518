#!/usr/bin/env python3
"""Wagner's wedge at constant speed (issue 30 point 6; docs/validation.md section 18): runs
pipelines/bodies/wedge_entry_2d.json at the spacings asked for and compares the fluid's vertical force on the
wedge and its wetted half-width with Wagner's theory (Wagner 1932; e.g. Faltinsen 1990, "Sea loads on ships and
offshore structures", ch. 9):

  c(t) = pi V t / (2 tan beta)                     (wetted half-width, the pile-up included)
  F(t) = d/dt (m_a V) = rho pi c dc/dt V = rho pi^3 V^3 t / (4 tan^2 beta)   (m_a = rho pi c^2 / 2, per metre)

t from the contact of the wedge's surface with the water: the surface of a wall is half a spacing outside its
first particle layer (docs/scene.md), so the effective apex is 0.5 dx / cos(beta) below the polyline's; the
harness places it 3 dx above the still water (contact at t0 = 3 dx / V).

Measured (frames every 0.5 ms, force probe every 0.1 ms): within the window where Wagner's c is 0.2-0.8 of the
half-breadth B (after the first instants; before the knuckle):
  * force: the least-squares slope of F against t (through the origin, as Wagner's) over its slope, and the mean
    and worst of F / F_Wagner over the probe rows of the window;
  * wetted half-width: on each face, the largest distance from the apex (horizontal) of a fluid particle within
    1.5 dx of the face whose pressure exceeds 0.25 rho V^2 (the spray root: the jet along the face carries
    almost no pressure, the wetted part more than rho V^2) and which is joined to the apex by such particles (no
    gap of two spacings), mean of both sides, against Wagner's c.

Against the similarity solution (exact potential flow, Dobrovol'skaya 1969, tabulated by Zhao & Faltinsen 1993; the figures
with their provenance in tests/data/zhao_faltinsen1993_wedge_similarity.csv: recalled, confirmed within a few per cent by
bench/bodies/wedge_similarity_bem, docs/validation.md section 18): the force slope over its
F / (rho V^3 t), and from the face pressure collapsed in the self-similar variable xi = x / (V t) over the frames of the
window (fluid particles within 1.5 dx of the face, bins of 0.1 in xi; written to RUN/face_pressure.csv) the largest
pressure coefficient Cp_max = p / (rho V^2 / 2) and the height of its point above the still water, z_max / (V t) =
xi_max tan(beta) - 1.

  python3 pipelines/bodies/wedge_wagner.py [--dx 0.0025 ...] [--threads 1] [-o runs/wedge] [--set KEY=VALUE ...]
      [--check-force 0.10] [--check-width 0.10] [--force-reference wagner|similarity]   (exit 1 when a figure misses its bound)
  python3 pipelines/bodies/wedge_wagner.py --reference-check   (the similarity table's internal consistency, no run)
Exit 2 on bad arguments, 3 when the run fails.
"""
import argparse
import csv
import math
import os
import re
import struct
import sys

from harness_common import run_scene

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENE = os.path.join(HERE, "wedge_entry_2d.json")
RHO, V, BETA, B, H = 1000.0, 5.0, math.radians(30.0), 0.15, 0.4
X_APEX = 0.5
WINDOW = (0.2, 0.8)  # of B, in Wagner's c
P_ROOT = 0.25  # of rho V^2
SIMILARITY_CSV = os.path.join(ROOT, "tests", "data", "zhao_faltinsen1993_wedge_similarity.csv")
XI_BIN = 0.1  # face-pressure bins in xi = x / (V t)


def wagner_c(t):
    return math.pi * V * t / (2 * math.tan(BETA))


def wagner_f(t):
    return RHO * math.pi ** 3 * V ** 3 * t / (4 * math.tan(BETA) ** 2)


def read_vtu(path, names):
    """Points and the named point arrays of a varsph frame (raw appended data, UInt64 headers)."""
    data = open(path, "rb").read()
    a0 = data.index(b"<AppendedData")
    head = data[:a0].decode()
    base = data.index(b"_", a0) + 1
    types = {"Float32": "f", "Float64": "d", "Int32": "i", "Int64": "q", "UInt8": "B"}

    def block(off, typ):
        start = base + off
        nbytes = struct.unpack("<Q", data[start:start + 8])[0]
        fmt = types[typ]
        n = nbytes // struct.calcsize(fmt)
        return struct.unpack("<%d%s" % (n, fmt), data[start + 8:start + 8 + nbytes])

    out = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="(\w+)"(?: NumberOfComponents="(\d+)")? format="appended" '
                         r'offset="(\d+)"', head):
        typ, name, ncomp, off = m.group(1), m.group(2), int(m.group(3) or 1), int(m.group(4))
        if name in names or name == "Points":
            vals = block(off, typ)
            out[name] = [vals[k * ncomp:(k + 1) * ncomp] for k in range(len(vals) // ncomp)] if ncomp > 1 else vals
    if "Points" not in out:  # the points array has no Name in some writers: take the one inside <Points>
        m = re.search(r'<Points>\s*<DataArray type="(\w+)"[^>]*NumberOfComponents="(\d+)"[^>]*offset="(\d+)"', head)
        vals = block(int(m.group(3)), m.group(1))
        n = int(m.group(2))
        out["Points"] = [vals[k * n:(k + 1) * n] for k in range(len(vals) // n)]
    t = float(re.search(r'Name="time"[^>]*>([^<]+)<', head).group(1))
    return t, out


def mlm_coefficient(beta, k=None):
    """F / (rho V^3 t) of the modified Logvinovich model (Korobkin 2004) for a wedge at constant speed, derived
    here: Logvinovich's body potential phi = -V sqrt(c^2 - x^2) - V (f(x) - h) (Wagner's flat-plate potential and
    its first Taylor term to the body f(x) = |x| tan(beta) lowered by h = V t), Wagner's c, Bernoulli with the full
    velocity on the body:
      p / (rho V^2) = K / sqrt(1 - xi^2) - [(xi / sqrt(1 - xi^2) - tan(beta))^2 + 1] / (2 (1 + tan^2(beta)))
    with xi = x / c and K = pi / (2 tan(beta)), integrated over the wetted part where p >= 0 (xi = sin(theta)).
    The wetted half-width is c = k V t with Wagner's k = pi / (2 tan(beta)) unless k is given (then K = k above: the
    term K comes from d(phi)/dt = -V c dc/dt / sqrt(c^2 - x^2) and dc/dt = k V)."""
    k = math.pi / (2 * math.tan(beta)) if k is None else k
    tb = math.tan(beta)
    n, f = 200000, 0.0
    for j in range(n):
        th = (j + 0.5) / n * math.pi / 2
        xi, s = math.sin(th), math.cos(th)
        p = k / s - 0.5 * ((xi / s - tb) ** 2 + 1) / (1 + tb * tb)
        if p < 0:
            break
        f += p * s * (math.pi / 2 / n)
    return 2 * k * f


def wetted_half_width(frame, dx, p_root):
    """Mean over both faces of the spray root's horizontal distance from the apex (see the module text)."""
    tf, a = read_vtu(frame, {"pressure", "kind"})
    apex_y = apex_poly(dx) - V * tf  # polyline apex at the frame's time
    off = 0.5 * dx / math.cos(BETA)  # the effective surface is half a spacing outside the polyline
    sb, cb = math.sin(BETA), math.cos(BETA)
    wet = [{}, {}]  # per face: horizontal bins of one spacing from the apex holding a loaded particle
    for (x, y, _z), p, k in zip(a["Points"], a["pressure"], a["kind"]):
        if k != 0 or p < p_root * RHO * V ** 2:
            continue
        dxa, dya = x - X_APEX, y - (apex_y - off)
        side = 1 if dxa >= 0 else 0
        # distance below the face line y = |x| tan(beta) of the effective wedge
        d = (abs(dxa) * sb - dya * cb)
        if 0 <= d <= 1.5 * dx:
            j = int(abs(dxa) / dx)
            wet[side][j] = max(wet[side].get(j, 0.0), abs(dxa))
    # the wetted part is contiguous from the apex: walk out bin by bin and stop at the first empty one (an isolated
    # loaded particle up in the jet, seen at B/dx 120, is not the spray root)
    best = [0.0, 0.0]
    for side in (0, 1):
        j = 0
        while j in wet[side] or j + 1 in wet[side]:  # a one-bin gap is the particles' spacing along the face
            best[side] = max(best[side], wet[side].get(j, 0.0))
            j += 1
    return tf, 0.5 * (best[0] + best[1]), best


def face_pressure(frame, dx, t0, bins):
    """Adds the pressures of the fluid particles within 1.5 dx of either face (the wall-normal distance below the
    effective face line) to bins of xi = |x - x_apex| / (V (t - t0)) of width XI_BIN: bins[j] = [sum of Cp, count]."""
    tf, a = read_vtu(frame, {"pressure", "kind"})
    te = tf - t0
    apex_y = apex_poly(dx) - V * tf
    off = 0.5 * dx / math.cos(BETA)
    sb, cb = math.sin(BETA), math.cos(BETA)
    q = 0.5 * RHO * V ** 2
    for (x, y, _z), p, k in zip(a["Points"], a["pressure"], a["kind"]):
        if k != 0:
            continue
        dxa, dya = x - X_APEX, y - (apex_y - off)
        d = abs(dxa) * sb - dya * cb
        if 0 <= d <= 1.5 * dx:
            j = int(abs(dxa) / (V * te) / XI_BIN)
            b = bins.setdefault(j, [0.0, 0])
            b[0] += p / q
            b[1] += 1


def load_similarity(beta_deg):
    """The row of tests/data/zhao_faltinsen1993_wedge_similarity.csv for beta_deg: (Cp_max, z_max/(V t), F/(rho V^3 t))."""
    for r in similarity_rows():
        if abs(r[0] - beta_deg) < 1e-9:
            return r[1:]
    return None


def similarity_rows():
    rows = []
    for line in open(SIMILARITY_CSV):
        if line.startswith("#") or line.startswith("beta"):
            continue
        rows.append(tuple(float(v) for v in line.split(",")))
    return rows


def reference_check():
    """The internal-consistency checks quoted in the header of the similarity table (no run)."""
    print("similarity table (%s): internal consistency" % os.path.relpath(SIMILARITY_CSV, ROOT))
    print("  beta  (1 + k^2) / Cp_max  MLM(k) / F   F / Wagner   (k = (1 + z_max/(V t)) / tan(beta))")
    for bd, cp, z, f in similarity_rows():
        b = math.radians(bd)
        k = (1 + z) / math.tan(b)
        print("  %4.1f  %.4f             %.4f       %.4f" % (bd, (1 + k * k) / cp, mlm_coefficient(b, k) / f,
                                                         f / (math.pi ** 3 / (4 * math.tan(b) ** 2))))


def apex_poly(dx):
    return H + 0.5 * dx / math.cos(BETA) + 3 * dx


def run_case(dx, threads, outdir, sets, timeout):
    t0 = 3 * dx / V
    t_end = t0 + WINDOW[1] * B * 2 * math.tan(BETA) / (math.pi * V) + 0.0002
    wall, l0, l1 = run_scene(SCENE, outdir, threads,
                             ["particles.spacing=%r" % dx, "time.end=%.6f" % t_end,
                              "bodies.2.transform={\"translate\": [%r, %r, 0.0]}" % (X_APEX, apex_poly(dx))]
                             + list(sets), timeout)
    return t0, wall, l0, l1


def evaluate(outdir, dx, t0, p_root):
    rows = list(csv.DictReader(open(os.path.join(outdir, "probes.csv"))))
    lo, hi = (WINDOW[0] * B * 2 * math.tan(BETA) / (math.pi * V), WINDOW[1] * B * 2 * math.tan(BETA) / (math.pi * V))
    # probe rows are means over the interval before them: compare with Wagner's mean over the same interval
    sft = stt = 0.0
    ratios = []
    prev = None
    for r in rows:
        t = float(r["time"]) - t0
        if prev is not None and lo <= 0.5 * (prev + t) <= hi:
            f = float(r["Fy_wedge"])
            fw = wagner_f(0.5 * (prev + t))
            tm = 0.5 * (prev + t)
            sft += f * tm
            stt += tm * tm
            ratios.append(f / fw)
        prev = t
    slope_ratio = (sft / stt) / wagner_f(1.0)
    frames = sorted(os.path.join(outdir, "frames", f) for f in os.listdir(os.path.join(outdir, "frames"))
                    if f.endswith(".vtu"))
    widths = []
    bins = {}
    for fr in frames:
        tf, c, sides = wetted_half_width(fr, dx, p_root)
        te = tf - t0
        if lo <= te <= hi:
            widths.append((te, c, wagner_c(te), sides))
            face_pressure(fr, dx, t0, bins)
    with open(os.path.join(outdir, "face_pressure.csv"), "w") as f:
        f.write("xi_x_over_Vt,z_over_Vt,cp_mean,samples\n")
        for j in sorted(bins):
            xi = (j + 0.5) * XI_BIN
            f.write("%.3f,%.4f,%.4f,%d\n" % (xi, xi * math.tan(BETA) - 1, bins[j][0] / bins[j][1], bins[j][1]))
    return slope_ratio, ratios, widths, bins


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, action="append", help="particle spacing [m] (repeatable; 0.0025)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("-o", "--out", default=os.path.join(ROOT, "runs", "wedge"))
    ap.add_argument("--set", action="append", default=[], help="scene override (repeatable)")
    ap.add_argument("--timeout", type=float, default=None)
    ap.add_argument("--reuse", action="store_true", help="evaluate existing runs in --out without running")
    ap.add_argument("--p-root", type=float, default=P_ROOT, help="spray root: pressure above this x rho V^2")
    ap.add_argument("--check-force", type=float, help="bound on |F slope / reference - 1| (--force-reference)")
    ap.add_argument("--force-reference", choices=["wagner", "similarity"], default="wagner",  # the test: similarity
                    help="what --check-force judges against (wagner: the issue's goal; similarity: the table in tests/data)")
    ap.add_argument("--reference-check", action="store_true", help="print the similarity table's consistency checks")
    ap.add_argument("--check-width", type=float, help="bound on the mean |c / c_Wagner - 1| over the frames")
    a = ap.parse_args()
    if a.reference_check:
        reference_check()
        raise SystemExit(0)
    sim = load_similarity(round(math.degrees(BETA), 6))
    if sim is None:
        print("wedge_wagner.py: %s: no row for beta = %g deg" % (SIMILARITY_CSV, math.degrees(BETA)), file=sys.stderr)
        raise SystemExit(2)
    dxs = a.dx or [0.0025]
    if any(d <= 0 or d > 0.02 for d in dxs):
        print("wedge_wagner.py: --dx: expected a spacing in (0, 0.02] m", file=sys.stderr)
        raise SystemExit(2)
    failed = False
    mlm = mlm_coefficient(BETA)
    print("Wagner's wedge: beta 30 deg, V %.1f m/s, B %.2f m; window: Wagner's c in %.1f-%.1f B" % (V, B, *WINDOW))
    for dx in dxs:
        outdir = os.path.join(a.out, "dx%g" % dx + ("_" + "_".join(re.sub(r"\W", "", s) for s in a.set) if a.set else ""))
        t0 = 3 * dx / V
        if not a.reuse:
            t0, wall, l0, l1 = run_case(dx, a.threads, outdir, a.set, a.timeout)
            print("dx %g (B/dx %.0f): run %.0f s wall on %d thread(s), load %.1f -> %.1f" % (dx, B / dx, wall, a.threads,
                                                                                           l0, l1))
        slope, ratios, widths, bins = evaluate(outdir, dx, t0, a.p_root)
        print("  force: slope / Wagner %.3f (%+.1f %%); F / F_Wagner over the window: mean %.3f, min %.3f, max %.3f"
              % (slope, 100 * (slope - 1), sum(ratios) / len(ratios), min(ratios), max(ratios)))
        print("  force against the modified Logvinovich model (F = %.2f rho V^3 t, %.3f x Wagner's): %+.1f %%"
              % (mlm, mlm / wagner_f(1.0) * RHO * V ** 3, 100 * (slope * wagner_f(1.0) / (mlm * RHO * V ** 3) - 1)))
        sim_ratio = slope * wagner_f(1.0) / (sim[2] * RHO * V ** 3)
        print("  force against the similarity solution (F = %.3f rho V^3 t, %.3f x Wagner's; recalled table, BEM-confirmed): "
              "slope %.3f (%+.1f %%)" % (sim[2], sim[2] * RHO * V ** 3 / wagner_f(1.0), sim_ratio, 100 * (sim_ratio - 1)))
        # face pressure collapsed in xi = x / (V t); bins with fewer samples than a tenth of the fullest are noise
        nmax = max(b[1] for b in bins.values())
        good = {j: b[0] / b[1] for j, b in bins.items() if b[1] >= 0.1 * nmax}
        jmax = max(good, key=good.get)
        cpmax, ximax = good[jmax], (jmax + 0.5) * XI_BIN
        zmax = ximax * math.tan(BETA) - 1
        print("  face pressure over the window in xi = x/(V t) (RUN/face_pressure.csv): Cp_max %.2f at xi %.2f, "
              "z_max/(V t) %.3f; similarity %.3f at z_max/(V t) %.4f (xi %.3f): Cp_max %+.1f %%, xi_max %+.1f %%; "
              "Wagner's 1 + pi^2/(4 tan^2 beta) = %.2f at xi %.3f" % (
                  cpmax, ximax, zmax, sim[0], sim[1], (1 + sim[1]) / math.tan(BETA), 100 * (cpmax / sim[0] - 1),
                  100 * (ximax / ((1 + sim[1]) / math.tan(BETA)) - 1), 1 + math.pi ** 2 / (4 * math.tan(BETA) ** 2),
                  math.pi / (2 * math.tan(BETA))))
        fint = sum(max(good[j], 0.0) * XI_BIN for j in good)  # F / (rho V^3 t) = integral of Cp d(xi) over both faces
        print("  the face pressure integrated, sum of Cp d(xi) = %.2f (= F / (rho V^3 t) from the fluid's pressure at the "
              "face; the probe's slope %.2f, the similarity solution %.3f)" % (fint, slope * wagner_f(1.0) / (RHO * V ** 3),
                                                                              sim[2]))
        print("  Cp along the face: " + ", ".join("%.1f:%.2f" % ((j + 0.5) * XI_BIN, good[j]) for j in sorted(good)
                                                  if j % 2 == 0))
        werr = []
        for te, c, cw, sides in widths:
            print("  t - t0 %.4f s: c %.4f m (left %.4f, right %.4f), Wagner %.4f m: %+.1f %%"
                  % (te, c, sides[0], sides[1], cw, 100 * (c / cw - 1)))
            werr.append(c / cw - 1)
        mw = sum(werr) / len(werr) if werr else float("nan")
        print("  wetted half-width: mean c / c_Wagner - 1 = %+.1f %%" % (100 * mw))
        fref = slope if a.force_reference == "wagner" else sim_ratio
        if a.check_force is not None and not abs(fref - 1) <= a.check_force:
            print("  FAIL: force slope off %s by %+.1f %% (bound %.0f %%)" % (
                "Wagner" if a.force_reference == "wagner" else "the similarity solution", 100 * (fref - 1),
                100 * a.check_force))
            failed = True
        if a.check_width is not None and not abs(mw) <= a.check_width:
            print("  FAIL: wetted half-width off Wagner by %+.1f %% (bound %.0f %%)" % (100 * mw, 100 * a.check_width))
            failed = True
    raise SystemExit(1 if failed else 0)


if __name__ == "__main__":
    main()
