"""Post-process a varsph run into RUN_DIR/post/.

    xvfb-run -a -s -noreset pvpython paraview/postprocess.py RUN_DIR [--compare OTHER_RUN] [--times t1,t2,...]
        [--gauges x1,x2,...] [--reference-probe NAME=FILE.csv[:H=..][:rho=..][:g=..][:label=..]]...
        [--front-reference measured|FILE.csv]... [--probe-points "x,y[,z];..."] [--no-snapshots]

Writes (and prints each path):
  probes_<type>.png               RUN/probes.csv (the solver's runtime probes, sampled every probes_every):
                                  pressure, water_height, front, force; --compare overlays run B's
  probe_<NAME>_reference.png      a probe beside measured data (--reference-probe, see below)
  surge_front.csv/.png            time,front_x,front_rel,height_x<g>... from the frames (--gauges: heights);
                                  for a dam-break column (below) or with --gauges
  front_dimensionless.csv/.png    Z = (x_front - x_wall)/L against T = t sqrt(2 g/L) (front from probes.csv when
                                  it has one, else from the frames) with Martin & Moyce (1952) and Koshizuka &
                                  Oka (1996) measurements; --compare overlays run B. Only where the run is
                                  their case (a column of H/L = 2 against a wall on a floor; varsph/casefit.py)
                                  or with --front-reference (measured: those; FILE.csv: columns T,Z)
  momentum.csv, momentum_Q.png    time,momentum_x,momentum_y,momentum_z,momentum_Q and Q(t) (+ run B)
  body_<N>_motion.png, body_<N>_loads.png, moorings.png
                                  runs with rigid bodies (bodies.csv): plot_bodies.py; --body-reference overlays
                                  a measured motion
  waves.csv, gauges.png, spectra.png
                                  wave flumes (a piston or flap wavemaker and water-height gauges; docs/waves.md):
                                  wave_analysis.py (heights and periods per gauge, gauges against linear theory)
  deviation.csv/.png              with --compare: time,D_max,D_mean,D_rms over the common times (eq. 70)
  scene_diff.txt                  with --compare: the resolved scene keys in which the runs differ
  free_surface_t<T>.png, pressure_t<T>.png, pressure_smoothed_t<T>.png (raw | smoothed), deviation_t<T>.png,
  open_flow_t<T>.png (runs with inlets and outlets: speed, velocity arrows, inflow and outflow zones)
                                  pictures at --times (nearest frames; default 4 evenly spaced frames;
                                  deviation: the last common time); T is the output time the frame was
                                  written for (k x output.every: 0.4, not an adaptive step's 0.395943)
  pressure_probes.csv/.png        with --probe-points: pressure interpolated from the FRAMES (output rate only;
                                  impacts between frames are missed: prefer runtime probes in the scene)

--reference-probe NAME=FILE: NAME is a probes.csv column (p_wall) or a probe name (wall); FILE has a header
and '#' comments, columns T,P (dimensionless: T = t sqrt(g/H), P = p/(rho g H); the run is converted with
H = the initial water column height, rho0 and |g| of the run, or :H=..:rho=..:g=..) or t,p (s, Pa).
Plots need matplotlib inside pvpython; without it the CSV files are still written and a message says so.
Given a `varsph study` directory (with study.json), it shows every level side by side (study_levels.py).
Exit status 2 on bad input (a missing run, a malformed reference file), naming the file.
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

from varsph import deviation as dev  # noqa: E402
from varsph import io as vio  # noqa: E402
from varsph import casefit, openb, plots, probe, reference, runmeta, surge  # noqa: E402

WRITTEN = []


def note(path):
    if path:
        WRITTEN.append(path)
        print("wrote", path)
    return path


def floats(text):
    return [float(v) for v in text.split(",") if v.strip()] if text else []


def choose_times(all_times, wanted):
    if wanted:
        return [min(all_times, key=lambda t: abs(t - w)) for w in wanted]
    idx = sorted(set(int(round(k)) for k in np.linspace(0, len(all_times) - 1, min(4, len(all_times)))))
    return [all_times[k] for k in idx]


def label_of(run):
    return os.path.basename(os.path.normpath(run))


# --- from the runtime probes ------------------------------------------------------------------------------
def probe_figures(runs, post):
    head, c = runmeta.probes(runs[0])
    if not head:
        print("no probes.csv in %s; no probe plots (add probes to the scene: docs/results.md)" % runs[0])
        return
    others = [runmeta.probes(r) for r in runs[1:]]
    for suffix, title, unit, cols in runmeta.probe_groups(head):
        series = [(label_of(runs[0]), [(h, c["time"], c[h]) for h in cols])]
        for r, (_, oc) in zip(runs[1:], others):
            if "time" in oc:
                series.append((label_of(r), [(h, oc["time"], oc[h]) for h in cols if h in oc]))
        note(plots.lines(os.path.join(post, "probes_%s.png" % suffix), series, "time [s]", unit,
                         "%s (probes.csv, every %.3g s)" % (title, np.median(np.diff(c["time"])) if len(c["time"]) > 1
                                                            else 0)))


def reference_probe_figures(run, post, specs, geom):
    head, c = runmeta.probes(run)
    for spec in specs:
        name, path, opts = reference.parse_reference_probe(spec)
        col = name if name in c else ("p_" + name if "p_" + name in c else None)
        if col is None:
            raise ValueError("--reference-probe %s: probes.csv of %s has no column %s or p_%s (has %s)"
                             % (spec, run, name, name, ", ".join(h for h in head if h != "time") or "none"))
        kind, x, y = reference.load_reference_probe(path)
        H, rho, g = opts.get("H", geom.H), opts.get("rho", geom.rho0), opts.get("g", geom.g)
        t, p = c["time"], c[col]
        if kind == "dimensionless":
            t, p = t * np.sqrt(g / H), p / (rho * g * H)
            xl, yl = "T = t sqrt(g/H)", "P = p / (rho g H)"
            sub = "H = %.4g m, rho = %.5g kg/m3, g = %.4g m/s2" % (H, rho, g)
        else:
            xl, yl, sub = "time [s]", "pressure [Pa]", "SI units"
        ref_label = opts.get("label", os.path.splitext(os.path.basename(path))[0])
        note(plots.lines(os.path.join(post, "probe_%s_reference.png" % name), [(label_of(run), [(col, t, p)])],
                         xl, yl, "probe %s against %s\n(%s)" % (col, ref_label, sub), markers=[(ref_label, x, y)]))


def front_figure(runs, post, frames0, refs):
    """Dimensionless surge front beside measurements ``refs`` ([(label, T, Z)])."""
    series = []
    for run, f0 in zip(runs, frames0):
        geom = reference.ColumnGeometry(f0, run, vertical=vio.vertical_axis(run, f0.dimension))
        head, c = runmeta.probes(run)
        fcol = next((h for h in head if h.startswith("front_x")), None)
        if fcol:
            t, x, src = c["time"], c[fcol], "probes.csv"
        else:
            rows = surge.surge_series(run)[1]
            t, x, src = np.array([r[0] for r in rows]), np.array([r[1] for r in rows]), "frames"
        T, Z = geom.front(t, x)
        if run == runs[0]:
            note(surge.write_table_csv(["time", "T", "Z"], np.column_stack([t, T, Z]),
                                       os.path.join(post, "front_dimensionless.csv")))
        series.append((label_of(run), [("varsph (%s), L = %.4g m, n^2 = H/L = %.3g" % (src, geom.L, geom.n2), T, Z)]))
    note(plots.lines(os.path.join(post, "front_dimensionless.png"), series, "T = t sqrt(2 g / L)",
                     "Z = (x_front - x_wall) / L", "dam-break surge front", markers=refs))


# --- from the frames and diagnostics ----------------------------------------------------------------------
def surge_table(run, post, loaded, gauges):
    vert = vio.vertical_axis(run, loaded[0].dimension)
    cols, rows = surge.surge_series(run, gauges, vertical=vert, frames=loaded)
    note(surge.write_table_csv(cols, rows, os.path.join(post, "surge_front.csv")))
    r = np.asarray(rows, dtype=float)
    note(plots.lines(os.path.join(post, "surge_front.png"),
                     [(label_of(run), [("front x", r[:, 0], r[:, 1])] +
                       [(col, r[:, 0], r[:, k]) for k, col in enumerate(cols) if col.startswith("height_x")])],
                     "time [s]", "position / height [m]", "surge front (max x of the fluid) and gauge heights, "
                     "from the frames"))


def momentum(runs, post):
    head, c = runmeta.diagnostics(runs[0])
    if not head:
        print("no diagnostics.csv in %s; no momentum plot" % runs[0])
        return
    if "time" not in c or "momentum_Q" not in c:
        print("diagnostics.csv lacks time/momentum_Q; no momentum plot")
        return
    have = [h for h in ("time", "momentum_x", "momentum_y", "momentum_z", "momentum_Q") if h in c]
    note(surge.write_table_csv(have, np.column_stack([c[h] for h in have]), os.path.join(post, "momentum.csv")))
    series = [(label_of(runs[0]), [("Q", c["time"], c["momentum_Q"])])]
    for r in runs[1:]:
        _, oc = runmeta.diagnostics(r)
        if "momentum_Q" in oc:
            series.append((label_of(r), [("Q", oc["time"], oc["momentum_Q"])]))
    note(plots.lines(os.path.join(post, "momentum_Q.png"), series, "time [s]", "Q = |sum_i m_i v_i| / M",
                     "linear momentum Q(t) (M = number of fluid particles)"))


def compare(run, other, post):
    drows = dev.deviation_series(run, other)
    note(dev.write_deviation_csv(drows, os.path.join(post, "deviation.csv")))
    d = np.asarray(drows, dtype=float)
    note(plots.lines(os.path.join(post, "deviation.png"),
                     [(label_of(run), [("D_max (eq. 70)", d[:, 0], d[:, 1]), ("D_mean", d[:, 0], d[:, 2]),
                                       ("D_rms", d[:, 0], d[:, 3])])],
                     "time [s]", "deviation [m]", "D(t) = max_i |q_i,A - q_i,B| at the %d common times, B = %s"
                     % (len(d), label_of(other))))
    diff = runmeta.scene_diff(run, other)
    path = os.path.join(post, "scene_diff.txt")
    with open(path, "w") as f:
        f.write("resolved scene keys that differ (run.json 'scene'): A = %s, B = %s\n" % (run, other))
        for k, a, b in diff:
            f.write("%s: A = %s, B = %s\n" % (k, a, b))
        if not diff:
            f.write("(none)\n")
    print("scene keys that differ between %s and %s: %s" % (label_of(run), label_of(other),
          "; ".join("%s (%s vs %s)" % (k, a, b) for k, a, b in diff) or "none"))
    note(path)
    return drows


def front_refs(specs):
    """[(label, T, Z)] of --front-reference: 'measured' (the bundled measurements, n^2 = 2) or a CSV file with
    columns T,Z. ValueError naming the file for anything else."""
    out = []
    for spec in specs:
        if spec == "measured":
            found = [(label + " (n^2 = 2)", T, Z) for label, T, Z in reference.front_references()]
            if not found:
                print("front_dimensionless.png: no reference data found in %s" % " or ".join(reference.DATA_DIRS))
            out += found
            continue
        c = reference.read_columns(spec)
        if "T" not in c or "Z" not in c:
            raise ValueError("--front-reference %s: expected columns T,Z (T = t sqrt(2 g/L), Z = front/L); the "
                             "header is %s" % (spec, ",".join(c)))
        out.append((os.path.splitext(os.path.basename(spec))[0], c["T"], c["Z"]))
    return out


def snapshots(run, other, post, times, size=(1200, 700)):
    try:
        from varsph import pvstate
    except Exception as e:
        print("skipped snapshots: ParaView is not available (%s); run with pvpython" % e)
        return
    s = pvstate.pv()
    every = (runmeta.scene_of(run).get("output") or {}).get("every")

    def label(t):
        return casefit.time_label(t, every)
    states = [("free_surface", lambda: pvstate.free_surface_state(run, view=pvstate.new_view(size))),
              ("pressure", lambda: pvstate.pressure_state(run, view=pvstate.new_view(size)))]
    if openb.zones(run):   # inlets and outlets (issue 32): speed, velocity arrows, inflow and outflow zones
        states.append(("open_flow", lambda: pvstate.open_flow_state(run, view=pvstate.new_view(size))))
    for name, build in states:
        s.ResetSession()
        view = build()
        for t in times:
            pvstate.set_time(view, t)
            note(pvstate.screenshot(view, os.path.join(post, "%s_t%s.png" % (name, label(t))), size))
    s.ResetSession()
    layout = pvstate.pressure_pair(run, size=(2 * size[0], size[1]))
    first = s.FindView("varsph pressure raw view")
    for t in times:
        pvstate.set_time(first, t)
        note(pvstate.screenshot(layout, os.path.join(post, "pressure_smoothed_t%s.png" % label(t)),
                                (2 * size[0], size[1])))
    if other:
        s.ResetSession()
        view = pvstate.deviation_state(run, other, view=pvstate.new_view(size))
        t = s.GetAnimationScene().AnimationTime
        note(pvstate.screenshot(view, os.path.join(post, "deviation_t%s.png" % label(t)), size))


def wave_paddle(run):
    """(depth, H, T) of a run whose scene has a piston or flap wavemaker and water-height gauges, else None."""
    try:
        with open(os.path.join(run, "run.json")) as f:
            sc = json.load(f).get("scene", {})
    except (OSError, ValueError):
        return None
    if not any(p.get("type") == "water_height" for p in sc.get("probes", [])):
        return None
    for b in sc.get("bodies", []):
        m = b.get("motion")
        if isinstance(m, dict) and m.get("type") in ("piston", "flap"):
            fluid = [x for x in sc.get("bodies", []) if x.get("kind") == "fluid" and x.get("shape") == "box"]
            depth = m.get("depth") or (max(x["max"][-1] for x in fluid) - min(x["min"][-1] for x in fluid) if fluid else None)
            if not depth:
                return None
            return depth, m.get("height"), m.get("period")
    return None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="run directory (RUN/NAME.pvd, RUN/frames, probes.csv, diagnostics.csv, ...)")
    ap.add_argument("--compare", default=None, help="second run: overlays, deviation.csv/.png, scene_diff.txt")
    ap.add_argument("--times", default=None, help="snapshot times t1,t2,... (nearest frames)")
    ap.add_argument("--gauges", default=None, help="water-height gauge positions x1,x2,... for surge_front.csv")
    ap.add_argument("--reference-probe", action="append", default=[], metavar="NAME=FILE[:H=..][:rho=..][:g=..]",
                    help="plot probe NAME against measured data in FILE (columns T,P or t,p); repeatable")
    ap.add_argument("--front-reference", action="append", default=[], metavar="measured|FILE.csv",
                    help="draw the dimensionless front against these (measured: Martin & Moyce, Koshizuka & Oka; "
                         "FILE: columns T,Z) even where the run is not their dam-break case; repeatable")
    ap.add_argument("--probe-points", default=None, help="pressure from the frames at 'x,y[,z];...' (output rate)")
    ap.add_argument("--no-snapshots", action="store_true", help="skip the ParaView pictures")
    ap.add_argument("--body-reference", default=None, metavar="FILE[:quantity=y][:scale_t=..][:scale_v=..]",
                    help="a measured body motion to overlay on body_N_motion.png (plot_bodies.py)")
    a = ap.parse_args(argv)
    if os.path.isfile(os.path.join(a.run, "study.json")):  # a `varsph study` directory: every level side by side
        import study_levels
        return study_levels.main([a.run])

    runs = [a.run] + ([a.compare] if a.compare else [])
    try:
        frames = vio.frames_of_run(a.run)
        other_frames = vio.frames_of_run(a.compare) if a.compare else None
        for spec in a.reference_probe:     # check the references before any work
            reference.load_reference_probe(reference.parse_reference_probe(spec)[1])
        given_fronts = front_refs(a.front_reference)
    except (OSError, ValueError) as e:
        print("postprocess: error: %s" % e, file=sys.stderr)
        return 2
    if not frames:
        print("postprocess: error: %s has no frames" % a.run, file=sys.stderr)
        return 2
    post = os.path.join(runmeta.run_dir(a.run), "post")
    os.makedirs(post, exist_ok=True)
    times = [t for t, _ in frames]
    print("run %s: %d frame(s), t = %.6g .. %.6g s" % (a.run, len(times), times[0], times[-1]))

    loaded = [vio.read_vtu(p, t) for t, p in frames]
    frames0 = [loaded[0]] + ([vio.read_vtu(other_frames[0][1], other_frames[0][0])] if other_frames else [])
    probe_figures(runs, post)
    try:
        reference_probe_figures(a.run, post, a.reference_probe, reference.ColumnGeometry(
            loaded[0], a.run, vertical=vio.vertical_axis(a.run, loaded[0].dimension)))
    except ValueError as e:
        print("postprocess: error: %s" % e, file=sys.stderr)
        return 2
    vert = vio.vertical_axis(a.run, loaded[0].dimension)
    dam, why = casefit.dam_break_column(loaded[0], vertical=vert, scene=runmeta.scene_of(a.run))
    if dam or a.gauges:
        surge_table(a.run, post, loaded, floats(a.gauges))
    if dam or given_fronts:
        front_figure(runs, post, frames0, given_fronts or front_refs(["measured"]))
    if not dam:
        skipped = ([] if a.gauges else ["surge_front.csv/.png (--gauges X,... writes it)"]) + \
            ([] if given_fronts else ["front_dimensionless.csv/.png (--front-reference measured|FILE.csv draws it)"])
        print("%s is not the measured dam-break case (%s)%s" % (label_of(a.run), why,
              "; skipped " + ", ".join(skipped) if skipped else ""))
    momentum(runs, post)
    if os.path.isfile(os.path.join(a.run, "bodies.csv")):  # rigid bodies: motion and loads (plot_bodies.py)
        import plot_bodies
        try:
            ref = plot_bodies.parse_reference(a.body_reference) if a.body_reference else None
        except (OSError, ValueError) as e:
            print("postprocess: error: %s" % e, file=sys.stderr)
            return 2
        for path in plot_bodies.figures(a.run, post, ref):
            note(path)
    waves = wave_paddle(a.run)
    if waves:  # a wave flume (docs/waves.md): gauge statistics, gauges against linear theory, spectra
        import wave_analysis
        h, H, T = waves
        args = [a.run, "--depth", repr(h)] + (["--theory", "%r:%r" % (H, T)] if H else [])
        if wave_analysis.main(args) != 0:
            print("postprocess: the wave analysis of %s failed" % a.run, file=sys.stderr)
    if a.probe_points:
        pts = [floats(p) + [0.0] * (3 - len(floats(p))) for p in a.probe_points.split(";") if p.strip()]
        t, v = probe.probe_series(a.run, pts, frames=loaded)
        cols = ["time"] + ["pressure_%d" % k for k in range(len(pts))]
        note(surge.write_table_csv(cols, np.column_stack([t, v]), os.path.join(post, "pressure_probes.csv")))
        note(plots.lines(os.path.join(post, "pressure_probes.png"),
                         [(label_of(a.run), [("(%g, %g, %g)" % tuple(p), t, v[:, k]) for k, p in enumerate(pts)])],
                         "time [s]", "pressure [Pa]", "pressure interpolated from the frames (output rate only)"))
    if a.compare:
        try:
            compare(a.run, a.compare, post)
        except ValueError as e:
            print("postprocess: error: %s" % e, file=sys.stderr)
            return 2
    if not a.no_snapshots:
        snapshots(a.run, a.compare, post, choose_times(times, floats(a.times)))
    print("postprocess: %d file(s) written to %s" % (len(WRITTEN), post))
    return 0


if __name__ == "__main__":
    code = main()
    if "varsph.pvstate" in sys.modules:  # ParaView views were created: skip its crash-prone teardown
        sys.modules["varsph.pvstate"].hard_exit(code)
    sys.exit(code)
