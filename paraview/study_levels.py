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
    # one colour range for every view: the finest level's first frame
    prange = pvstate.pressure_range(runs[len([r for r in runs if r[1].startswith("L")]) - 1][0])
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
        view = pvstate.new_view((600, 450))
        try:
            s.RemoveLayout(s.GetLayout(view))  # new_view put it in the active layout; it belongs in ours
        except Exception:
            pass
        layout.AssignView(cells[k], view)
        pvstate.pressure_state(run, a.time, prange=prange, view=view)
        t = s.Text(registrationName="level_%d" % k, Text=label)
        d = s.Show(t, view)
        d.Color = [0, 0, 0]
        d.WindowLocation = "Lower Center"
        d.FontSize = 12
        views.append(view)
    for k, v in enumerate(views[1:], 1):  # one camera for all (the first level's), kept linked in the GUI
        for prop in ("CameraPosition", "CameraFocalPoint", "CameraViewUp", "CameraParallelScale"):
            setattr(v, prop, getattr(views[0], prop))
        s.AddCameraLink(views[0], v, "study_camera_%d" % k)
    size = [int(x) for x in a.size.split(",")] if a.size else [600 * len(views), 450]
    post = os.path.join(a.study, "plots")
    os.makedirs(post, exist_ok=True)
    tshow = views[0].ViewTime
    shot = a.screenshot or os.path.join(post, "levels_t%.4g.png" % tshow)
    s.SaveScreenshot(shot, layout, ImageResolution=size)
    print("wrote", shot)
    state = a.state or os.path.join(post, "levels.pvsm")
    s.SaveState(state)
    print("wrote", state)
    return 0


if __name__ == "__main__":
    pvstate.hard_exit(main())
