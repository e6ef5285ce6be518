"""Post-process a varsph run into RUN_DIR/post/.

    xvfb-run -a pvpython paraview/postprocess.py RUN_DIR [--compare OTHER_RUN] [--times t1,t2,...]
                 [--gauges x1,x2,...] [--probe-points "x,y[,z];x,y[,z]"] [--no-snapshots]

Writes (and prints each path):
  free_surface_t<time>.png, pressure_t<time>.png   snapshots at --times (default 4 evenly spaced frames)
  surge_front.csv (time,front_x,front_rel,height_x<g>...) + surge_front.png
  probes.png                      plot of RUN_DIR/probes.csv, when the run has one
  pressure_probes.csv/.png        SPH-interpolated pressure at --probe-points, when given
  deviation.csv (time,D_max,D_mean,D_rms, as varsph compare) + deviation.png, with --compare
  momentum.csv (time,momentum_x,momentum_y,momentum_z,momentum_Q) + momentum_Q.png, from diagnostics.csv
Plots need matplotlib inside pvpython; without it the CSV files are still written and a message says so.
Given a `varsph study` directory (with study.json), it shows every level side by side (study_levels.py).
"""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

from varsph import deviation as dev  # noqa: E402
from varsph import io as vio  # noqa: E402
from varsph import probe, surge  # noqa: E402

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except Exception as e:  # pragma: no cover - depends on the installation
    plt = None
    _MPL_ERROR = str(e)

WRITTEN = []


def note(path):
    WRITTEN.append(path)
    print("wrote", path)


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return [], {}
    head = [h.strip() for h in rows[0]]
    cols = {h: [] for h in head}
    for r in rows[1:]:
        if not r:
            continue
        for h, v in zip(head, r):
            try:
                cols[h].append(float(v))
            except ValueError:
                cols[h].append(float("nan"))
    return head, {h: np.asarray(v) for h, v in cols.items()}


def plot(path, x, series, xlabel, ylabel, title):
    if plt is None:
        print("skipped %s: matplotlib does not import in this Python (%s); install python3-matplotlib"
              % (path, _MPL_ERROR))
        return
    fig, ax = plt.subplots(figsize=(7, 4))
    for label, y in series:
        ax.plot(x, y, marker="o" if len(x) < 30 else None, ms=3, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    if len(series) > 1:
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    note(path)


def floats(text):
    return [float(v) for v in text.split(",") if v.strip()] if text else []


def choose_times(all_times, wanted):
    if wanted:
        return [min(all_times, key=lambda t: abs(t - w)) for w in wanted]
    idx = sorted(set(int(round(k)) for k in np.linspace(0, len(all_times) - 1, min(4, len(all_times)))))
    return [all_times[k] for k in idx]


def snapshots(run, post, times):
    try:
        from varsph import pvstate
    except Exception as e:
        print("skipped snapshots: ParaView is not available (%s); run with pvpython" % e)
        return
    prange = pvstate.pressure_range(run)
    for name, build in (("free_surface", lambda v: pvstate.free_surface_state(run, times[0], prange=prange, view=v)),
                        ("pressure", lambda v: pvstate.pressure_state(run, times[0], prange=prange, view=v))):
        view = build(pvstate.new_view())
        for t in times:
            pvstate.set_time(view, t)
            note(pvstate.screenshot(view, os.path.join(post, "%s_t%.6g.png" % (name, t))))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="run directory (RUN/NAME.pvd, RUN/frames, diagnostics.csv, ...)")
    ap.add_argument("--compare", default=None, help="second run: writes deviation.csv/.png (eq. 70)")
    ap.add_argument("--times", default=None, help="snapshot times t1,t2,... (nearest frames)")
    ap.add_argument("--gauges", default=None, help="water-height gauge positions x1,x2,... for surge_front.csv")
    ap.add_argument("--probe-points", default=None, help="pressure probes 'x,y[,z];...' -> pressure_probes.csv")
    ap.add_argument("--no-snapshots", action="store_true", help="skip the ParaView renderings")
    a = ap.parse_args(argv)
    if os.path.isfile(os.path.join(a.run, "study.json")):  # a `varsph study` directory: every level side by side
        import study_levels
        return study_levels.main([a.run])

    run = a.run
    post = os.path.join(run if os.path.isdir(run) else os.path.dirname(run), "post")
    os.makedirs(post, exist_ok=True)
    frames = vio.frames_of_run(run)
    if not frames:
        print("error: %s has no frames" % run, file=sys.stderr)
        return 2
    times = [t for t, _ in frames]
    print("run %s: %d frame(s), t = %.6g .. %.6g s" % (run, len(times), times[0], times[-1]))

    # frames read once for the tables
    loaded = [vio.read_vtu(p, t) for t, p in frames]

    vert = vio.vertical_axis(run, loaded[0].dimension)   # opposite gravity in run.json, else y (2D) / z (3D)
    cols, rows = surge.surge_series(run, floats(a.gauges), vertical=vert, frames=loaded)
    note(surge.write_table_csv(cols, rows, os.path.join(post, "surge_front.csv")))
    r = np.asarray(rows, dtype=float)
    plot(os.path.join(post, "surge_front.png"), r[:, 0], [("front x", r[:, 1])] +
         [(c, r[:, k]) for k, c in enumerate(cols) if c.startswith("height_x")],
         "time [s]", "position / height [m]", "surge front (max x of the fluid) and gauge heights")

    pcsv = os.path.join(run, "probes.csv")
    if os.path.isfile(pcsv):
        head, c = read_csv(pcsv)
        if "time" in c and len(head) > 1:
            plot(os.path.join(post, "probes.png"), c["time"], [(h, c[h]) for h in head if h != "time"],
                 "time [s]", "probe value", "probes.csv")
        else:
            print("probes.csv has no 'time' column or no probe column; no plot")
    else:
        print("no probes.csv in %s; no probe plot" % run)

    if a.probe_points:
        pts = [floats(p) + [0.0] * (3 - len(floats(p))) for p in a.probe_points.split(";") if p.strip()]
        t, v = probe.probe_series(run, pts, frames=loaded)
        cols = ["time"] + ["pressure_%d" % k for k in range(len(pts))]
        note(surge.write_table_csv(cols, np.column_stack([t, v]), os.path.join(post, "pressure_probes.csv")))
        plot(os.path.join(post, "pressure_probes.png"), t,
             [("(%g, %g, %g)" % tuple(p), v[:, k]) for k, p in enumerate(pts)],
             "time [s]", "pressure [Pa]", "SPH pressure probes")

    if a.compare:
        drows = dev.deviation_series(run, a.compare)
        note(dev.write_deviation_csv(drows, os.path.join(post, "deviation.csv")))
        d = np.asarray(drows, dtype=float)
        plot(os.path.join(post, "deviation.png"), d[:, 0],
             [("D_max (eq. 70)", d[:, 1]), ("D_mean", d[:, 2]), ("D_rms", d[:, 3])],
             "time [s]", "deviation [m]", "D(t) = max_i |q_i,A - q_i,B|, B = %s" % os.path.basename(
                 os.path.normpath(a.compare)))

    dcsv = os.path.join(run, "diagnostics.csv")
    if os.path.isfile(dcsv):
        head, c = read_csv(dcsv)
        need = ["time", "momentum_x", "momentum_y", "momentum_z", "momentum_Q"]
        have = [h for h in need if h in c]
        if "time" in c and "momentum_Q" in c:
            note(surge.write_table_csv(have, np.column_stack([c[h] for h in have]),
                                       os.path.join(post, "momentum.csv")))
            plot(os.path.join(post, "momentum_Q.png"), c["time"], [("Q", c["momentum_Q"])],
                 "time [s]", "Q = |sum_i m_i v_i| / M", "linear momentum Q(t) (M = number of fluid particles)")
        else:
            print("diagnostics.csv lacks time/momentum_Q; no momentum plot")
    else:
        print("no diagnostics.csv in %s; no momentum plot" % run)

    if not a.no_snapshots:
        snapshots(run, post, choose_times(times, floats(a.times)))

    print("postprocess: %d file(s) written to %s" % (len(WRITTEN), post))
    return 0


if __name__ == "__main__":
    code = main()
    if "varsph.pvstate" in sys.modules:  # ParaView views were created: skip its crash-prone teardown
        sys.modules["varsph.pvstate"].hard_exit(code)
    sys.exit(code)
