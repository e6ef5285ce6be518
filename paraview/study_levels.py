"""Every level of a `varsph study` side by side in ParaView: one view per level (fluid coloured by pressure on
one colour range, boundary grey), cameras linked, the level's dx and dt in each view.

    xvfb-run -a pvpython paraview/study_levels.py STUDY_DIR [--time T] [--ablation] [--size W,H]
                 [--screenshot OUT.png] [--state OUT.pvsm]

Defaults: time = the last frame, screenshot STUDY_DIR/plots/levels_t<T>.png and state STUDY_DIR/plots/levels.pvsm
(File > Load State in the GUI; the varsph plugin need not be loaded for this state). --ablation adds the ablation
runs (STUDY_DIR/ablation/*) after the levels. `paraview/postprocess.py STUDY_DIR` calls this script.
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from varsph import pvstate  # noqa: E402
from varsph.io import frames_of_run, read_vtu  # noqa: E402


def pressure_range(run, frame_index=0):
    """One colour range for every view: the fluid pressure of one frame of a run, widened to include 0."""
    import numpy as np
    fr = frames_of_run(run)
    f = read_vtu(fr[frame_index][1], fr[frame_index][0])
    p = np.asarray(f.arrays.get("pressure", np.zeros(1)), dtype=float)[f.fluid_mask()]
    lo, hi = (float(min(0.0, p.min())), float(max(0.0, p.max()))) if len(p) else (0.0, 1.0)
    return (lo, hi) if hi > lo else (lo, lo + 1.0)


def runs_of(study_dir, with_ablation):
    with open(os.path.join(study_dir, "study.json")) as f:
        s = json.load(f)
    out = []
    for k, lv in enumerate(s["levels"]):
        if lv["exit_code"] == 0:
            dt = "dt %.3g s" % lv["dt"] if lv.get("dt") else "CFL %.3g" % (lv.get("cfl") or 0)
            out.append((lv["dir"], "L%d: dx %.4g m, %s, %d fluid" % (k, lv["dx"], dt, lv["fluid_particles"])))
    if with_ablation:
        for v in s["ablation"]["variants"]:
            if v["run"]["exit_code"] == 0:
                out.append((v["run"]["dir"], "%s (%s)" % (v["label"], v["verdict"])))
    # a study directory moved since it ran: its run directories are relative to it
    fixed = []
    for d, label in out:
        for sub in ("levels", "ablation"):
            c = os.path.join(study_dir, sub, os.path.basename(os.path.normpath(d)))
            if not os.path.isdir(d) and os.path.isdir(c):
                d = c
        fixed.append((d, label))
    return fixed


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("study", help="study directory (with study.json)")
    ap.add_argument("--time", type=float, default=None, help="time to show (nearest frame; default the last)")
    ap.add_argument("--ablation", action="store_true", help="also the ablation runs")
    ap.add_argument("--size", default=None, help="image size 'w,h' (default 600 x 450 per view)")
    ap.add_argument("--screenshot", default=None)
    ap.add_argument("--state", default=None)
    a = ap.parse_args(argv)
    runs = runs_of(a.study, a.ablation)
    if not runs:
        print("error: %s has no finished level" % a.study, file=sys.stderr)
        return 2
    s = pvstate.pv()
    # one time and one colour range for every view: the finest level's frame at --time (default its last)
    finest = runs[len([r for r in runs if r[1].startswith("L")]) - 1][0]
    times = [t for t, _ in frames_of_run(finest)]
    show = times[-1] if a.time is None else min(times, key=lambda t: abs(t - a.time))
    prange = pressure_range(finest, times.index(show))
    # the views share one animation time and a reader shows its last frame at or before it: take the latest of
    # the runs' frames nearest to the time, so every run shows its own nearest frame (frame times differ a little)
    target = show
    for run, _ in runs:
        show = max(show, min((t for t, _ in frames_of_run(run)), key=lambda t: abs(t - target)))
    layout = s.CreateLayout("study levels")
    # equal columns: split the right-hand cell off the remaining width, one level at a time
    cells, cell = [], 0
    for k in range(len(runs) - 1):
        left = layout.SplitHorizontal(cell, 1.0 / (len(runs) - k))
        cells.append(left)
        cell = left + 1
    cells.append(cell)
    views = []
    for k, (run, label) in enumerate(runs):
        view = pvstate.new_view((600, 450), name="study %d" % k)
        try:
            s.RemoveLayout(s.GetLayout(view))  # new_view put it in the active layout; it belongs in ours
        except Exception:
            pass
        layout.AssignView(cells[k], view)
        pvstate.pressure_state(run, show, prange=prange, view=view)
        t = s.Text(registrationName="level_%d" % k, Text=label)
        d = s.Show(t, view)
        d.Color = [0, 0, 0]
        d.WindowLocation = "Lower Center"
        d.FontSize = 12
        views.append(view)
    ref = views[runs.index(next(r for r in runs if r[0] == finest))]
    for k, v in enumerate(views):  # one camera for all (the finest level's), kept linked in the GUI
        if v is ref:
            continue
        for prop in ("CameraPosition", "CameraFocalPoint", "CameraViewUp", "CameraParallelScale"):
            setattr(v, prop, getattr(ref, prop))
        s.AddCameraLink(ref, v, "study_camera_%d" % k)
    size = [int(x) for x in a.size.split(",")] if a.size else [600 * len(views), 450]
    post = os.path.join(a.study, "plots")
    os.makedirs(post, exist_ok=True)
    tshow = show
    shot = a.screenshot or os.path.join(post, "levels_t%.4g.png" % target)
    s.SaveScreenshot(shot, layout, ImageResolution=size)
    print("wrote", shot)
    state = a.state or os.path.join(post, "levels.pvsm")
    s.SaveState(state)
    print("wrote", state)
    return 0


if __name__ == "__main__":
    pvstate.hard_exit(main())
