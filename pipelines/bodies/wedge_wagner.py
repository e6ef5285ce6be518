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

  python3 pipelines/bodies/wedge_wagner.py [--dx 0.0025 ...] [--threads 1] [-o runs/wedge] [--set KEY=VALUE ...]
      [--check-force 0.10] [--check-width 0.10]   (exit 1 when a figure misses its bound)
Exit 2 on bad arguments, 3 when the run fails.
"""
import argparse
import csv
import math
import os
import re
import struct
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENE = os.path.join(HERE, "wedge_entry_2d.json")
RHO, V, BETA, B, H = 1000.0, 5.0, math.radians(30.0), 0.15, 0.4
X_APEX = 0.5
WINDOW = (0.2, 0.8)  # of B, in Wagner's c
P_ROOT = 0.25  # of rho V^2


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


def mlm_coefficient(beta):
    """F / (rho V^3 t) of the modified Logvinovich model (Korobkin 2004) for a wedge at constant speed, derived
    here: Logvinovich's body potential phi = -V sqrt(c^2 - x^2) - V (f(x) - h) (Wagner's flat-plate potential and
    its first Taylor term to the body f(x) = |x| tan(beta) lowered by h = V t), Wagner's c, Bernoulli with the full
    velocity on the body:
      p / (rho V^2) = K / sqrt(1 - xi^2) - [(xi / sqrt(1 - xi^2) - tan(beta))^2 + 1] / (2 (1 + tan^2(beta)))
    with xi = x / c and K = pi / (2 tan(beta)), integrated over the wetted part where p >= 0 (xi = sin(theta))."""
    k, tb = math.pi / (2 * math.tan(beta)), math.tan(beta)
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


def apex_poly(dx):
    return H + 0.5 * dx / math.cos(BETA) + 3 * dx


def run_case(dx, threads, outdir, sets, timeout):
    t0 = 3 * dx / V
    t_end = t0 + WINDOW[1] * B * 2 * math.tan(BETA) / (math.pi * V) + 0.0002
    cmd = [os.environ.get("VARSPH_BIN", os.path.join(ROOT, "build", "release", "bin", "varsph")), "run", SCENE,
           "-o", outdir, "--overwrite", "--quiet", "--threads", str(threads),
           "--set", "particles.spacing=%r" % dx, "--set", "time.end=%.6f" % t_end,
           "--set", "bodies.2.transform={\"translate\": [%r, %r, 0.0]}" % (X_APEX, apex_poly(dx))]
    for s in sets:
        cmd += ["--set", s]
    l0 = os.getloadavg()[0]
    w0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    wall = time.monotonic() - w0
    if p.returncode != 0:
        print(p.stdout + p.stderr, file=sys.stderr)
        raise SystemExit(3)
    return t0, wall, l0, os.getloadavg()[0]


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
    for fr in frames:
        tf, c, sides = wetted_half_width(fr, dx, p_root)
        te = tf - t0
        if lo <= te <= hi:
            widths.append((te, c, wagner_c(te), sides))
    return slope_ratio, ratios, widths


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, action="append", help="particle spacing [m] (repeatable; 0.0025)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("-o", "--out", default=os.path.join(ROOT, "runs", "wedge"))
    ap.add_argument("--set", action="append", default=[], help="scene override (repeatable)")
    ap.add_argument("--timeout", type=float, default=None)
    ap.add_argument("--reuse", action="store_true", help="evaluate existing runs in --out without running")
    ap.add_argument("--p-root", type=float, default=P_ROOT, help="spray root: pressure above this x rho V^2")
    ap.add_argument("--check-force", type=float, help="bound on |F slope / Wagner - 1|")
    ap.add_argument("--check-width", type=float, help="bound on the mean |c / c_Wagner - 1| over the frames")
    a = ap.parse_args()
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
        slope, ratios, widths = evaluate(outdir, dx, t0, a.p_root)
        print("  force: slope / Wagner %.3f (%+.1f %%); F / F_Wagner over the window: mean %.3f, min %.3f, max %.3f"
              % (slope, 100 * (slope - 1), sum(ratios) / len(ratios), min(ratios), max(ratios)))
        print("  force against the modified Logvinovich model (F = %.2f rho V^3 t, %.3f x Wagner's): %+.1f %%"
              % (mlm, mlm / wagner_f(1.0) * RHO * V ** 3, 100 * (slope * wagner_f(1.0) / (mlm * RHO * V ** 3) - 1)))
        werr = []
        for te, c, cw, sides in widths:
            print("  t - t0 %.4f s: c %.4f m (left %.4f, right %.4f), Wagner %.4f m: %+.1f %%"
                  % (te, c, sides[0], sides[1], cw, 100 * (c / cw - 1)))
            werr.append(c / cw - 1)
        mw = sum(werr) / len(werr) if werr else float("nan")
        print("  wetted half-width: mean c / c_Wagner - 1 = %+.1f %%" % (100 * mw))
        if a.check_force is not None and not abs(slope - 1) <= a.check_force:
            print("  FAIL: force slope off Wagner by %+.1f %% (bound %.0f %%)" % (100 * (slope - 1), 100 * a.check_force))
            failed = True
        if a.check_width is not None and not abs(mw) <= a.check_width:
            print("  FAIL: wetted half-width off Wagner by %+.1f %% (bound %.0f %%)" % (100 * mw, 100 * a.check_width))
            failed = True
    raise SystemExit(1 if failed else 0)


if __name__ == "__main__":
    main()
