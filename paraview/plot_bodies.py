"""Plots of rigid bodies (RUN/bodies.csv, RUN/moorings.csv; docs/bodies.md) into RUN/post/.

    python3 paraview/plot_bodies.py RUN [--reference FILE.csv[:quantity=y][:scale_t=..][:scale_v=..][:label=..]]

Writes (and prints each path), per body N:
  body_N_motion.png    displacement of the centre of mass from t = 0 (x, y, z) and the rotation angle
  body_N_loads.png     fluid force, contact force and mooring force against time
  moorings.png         tension of every mooring (when the run has moorings)
--reference FILE: a measured or published series to overlay on the motion plot: '#' comments, a header, then
two columns; the first is time [s] (times scale_t: e.g. scale_t=0.3193 turns T = t sqrt(g/R) into seconds
for R = 1 m), the second the body's `quantity` (x, y, z: displacement from t = 0 [m]; angle [rad]) times
scale_v. postprocess.py calls figures() when a run has bodies.csv. Exit status 2 on bad input.
"""
import argparse
import csv
import os
import sys


def read_table(path):
    with open(path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#")) if r]
    header, data = rows[0], rows[1:]
    return header, [[float(v) for v in r] for r in data]


def parse_reference(spec):
    parts = spec.split(":")
    ref = {"file": parts[0], "quantity": "y", "scale_t": 1.0, "scale_v": 1.0, "label": os.path.basename(parts[0])}
    for p in parts[1:]:
        if "=" not in p:
            raise ValueError("--reference %s: expected key=value after ':', got '%s'" % (spec, p))
        k, v = p.split("=", 1)
        if k not in ref:
            raise ValueError("--reference %s: unknown key '%s' (quantity, scale_t, scale_v, label)" % (spec, k))
        ref[k] = v if k in ("quantity", "label") else float(v)
    if ref["quantity"] not in ("x", "y", "z", "angle"):
        raise ValueError("--reference %s: quantity must be x, y, z or angle" % spec)
    _, data = read_table(ref["file"])
    if not data or len(data[0]) < 2:
        raise ValueError("%s: expected two numeric columns (time, value)" % ref["file"])
    ref["t"] = [r[0] * ref["scale_t"] for r in data]
    ref["v"] = [r[1] * ref["scale_v"] for r in data]
    return ref


def figures(run, post, reference=None):
    """Writes the body plots of RUN into POST; returns the paths (none without matplotlib)."""
    header, rows = read_table(os.path.join(run, "bodies.csv"))
    col = {name: k for k, name in enumerate(header)}
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_bodies: matplotlib is not available: no body plots", file=sys.stderr)
        return []
    written = []
    for body in sorted({int(r[col["body"]]) for r in rows}):
        mine = [r for r in rows if int(r[col["body"]]) == body]
        t = [r[col["time"]] for r in mine]
        fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
        for q in ("x", "y", "z"):
            v0 = mine[0][col[q]]
            ax1.plot(t, [r[col[q]] - v0 for r in mine], label=q + " - " + q + "(0)")
        ax2.plot(t, [r[col["angle"]] for r in mine], label="angle")
        if reference:
            ax = ax2 if reference["quantity"] == "angle" else ax1
            ax.plot(reference["t"], reference["v"], "k.", label=reference["label"])
        ax1.set_ylabel("displacement [m]")
        ax2.set_ylabel("angle [rad]")
        ax2.set_xlabel("time [s]")
        ax1.legend()
        ax2.legend()
        ax1.set_title("body %d: motion of the centre of mass" % body)
        path = os.path.join(post, "body_%d_motion.png" % body)
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)
        fig, ax = plt.subplots(figsize=(8, 4))
        for kind in ("fluid", "contact", "mooring"):
            for q in ("x", "y", "z"):
                v = [r[col["%s_f%s" % (kind, q)]] for r in mine]
                if any(abs(x) > 0 for x in v):
                    ax.plot(t, v, label="%s F%s" % (kind, q))
        ax.set_xlabel("time [s]")
        ax.set_ylabel("force [N] (2D: N/m)")
        ax.set_title("body %d: loads" % body)
        ax.legend()
        path = os.path.join(post, "body_%d_loads.png" % body)
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)
    mpath = os.path.join(run, "moorings.csv")
    if os.path.isfile(mpath):
        mh, mrows = read_table(mpath)
        mc = {name: k for k, name in enumerate(mh)}
        fig, ax = plt.subplots(figsize=(8, 4))
        for m in sorted({int(r[mc["mooring"]]) for r in mrows}):
            sel = [r for r in mrows if int(r[mc["mooring"]]) == m]
            ax.plot([r[mc["time"]] for r in sel], [r[mc["tension"]] for r in sel], label="mooring %d" % m)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("tension [N]")
        ax.legend()
        path = os.path.join(post, "moorings.png")
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)
    return written


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--reference", default=None)
    a = ap.parse_args(argv)
    try:
        if not os.path.isfile(os.path.join(a.run, "bodies.csv")):
            raise ValueError("%s: no bodies.csv (the run has no rigid bodies)" % a.run)
        ref = parse_reference(a.reference) if a.reference else None
    except (OSError, ValueError) as e:
        print("plot_bodies: error: %s" % e, file=sys.stderr)
        return 2
    post = os.path.join(a.run, "post")
    os.makedirs(post, exist_ok=True)
    for p in figures(a.run, post, ref):
        print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
