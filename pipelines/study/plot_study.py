#!/usr/bin/env python3
"""Plots of a `varsph study` directory (called by the command; also usable by hand).

  /usr/bin/python3 pipelines/study/plot_study.py STUDY_DIR

Reads STUDY_DIR/study.json and STUDY_DIR/series/*.csv and writes into STUDY_DIR/plots/:
  error_vs_cost.png        each quantity's defended relative error (safety factor x the Richardson estimate)
                           at each level against the level's wall seconds, one panel per kind of quantity
                           (peak, time of peak, mean, end value, whole series); hollow markers: flagged estimates
  convergence_SERIES.png   per series: peak, time of peak, mean and end value against the refined parameter with
                           error bars (the defended error) and the extrapolated value, and the series of every
                           level with the extrapolated series (first window)
Exit 77 when matplotlib is missing (the command then says so in its report).
"""
import csv
import json
import math
import os
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except Exception as e:  # the command reports "no matplotlib"
    print("plot_study.py: matplotlib not available: %s" % e, file=sys.stderr)
    sys.exit(77)

KINDS = ["peak", "t_peak", "mean", "end", "series"]
TITLES = {"peak": "peak value", "t_peak": "time of peak", "mean": "mean over the window", "end": "end value",
          "series": "whole series (norm of the difference)"}


def finite(x):
    return x is not None and isinstance(x, (int, float)) and math.isfinite(x)


def read_series(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    head, body = rows[0], rows[1:]
    cols = {h: [] for h in head}
    for r in body:
        for h, v in zip(head, r):
            cols[h].append(float(v) if v not in ("", None) else float("nan"))
    return cols


def error_vs_cost(study, out):
    levels = study["levels"]
    wall = [lv["wall_seconds"] for lv in levels]
    fig, axes = plt.subplots(1, len(KINDS), figsize=(4.2 * len(KINDS), 4.2), squeeze=False)
    w0 = study["windows"][0] if study["windows"] else None
    for ax, kind in zip(axes[0], KINDS):
        n = 0
        for q in study["quantities"]:
            if q["kind"] != kind or (w0 and q["window"] != w0):
                continue
            rel = q["relative_error_bound"]
            pts = [(wall[k], rel[k]) for k in range(min(len(wall), len(rel))) if finite(rel[k]) and rel[k] > 0]
            if len(pts) < 1:
                continue
            xs, ys = zip(*pts)
            line, = ax.plot(xs, ys, "-", lw=1)
            ax.plot(xs, ys, "o", ms=5, color=line.get_color(),
                    mfc=line.get_color() if q["trusted"] else "none", label=q["series"])
            n += 1
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall seconds of the level")
        ax.set_ylabel("defended relative error")
        ax.set_title(TITLES[kind], fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        if n:
            ax.legend(fontsize=6)
    fig.suptitle("speed against error: %s (hollow: flagged estimate)" % study["levels"][0]["scene"], fontsize=9)
    fig.tight_layout()
    p = os.path.join(out, "error_vs_cost.png")
    fig.savefig(p, dpi=100)
    plt.close(fig)
    return p


def convergence(study, sdir, out):
    written = []
    levels = study["levels"]
    h = [lv["refined"] for lv in levels]
    unit = "dt [s]" if study["refine"] == "dt" else "dx [m]"
    w0 = study["windows"][0]
    series = []
    for q in study["quantities"]:
        if q["series"] not in series:
            series.append(q["series"])
    for name in series:
        qs = {q["kind"]: q for q in study["quantities"] if q["series"] == name and q["window"] == w0}
        kinds = [k for k in ("peak", "t_peak", "mean", "end") if k in qs]  # a series without a peak event: no gap
        fig, axes = plt.subplots(1, len(kinds) + 1, figsize=(4.2 * (len(kinds) + 1), 3.8), squeeze=False)
        axes = axes[0]
        for ax, kind in zip(axes[:-1], kinds):
            q = qs[kind]
            v, b = q["values"], q["error_bound"]
            pts = [(h[k], v[k], b[k] if finite(b[k]) else 0.0) for k in range(len(v)) if finite(v[k])]
            if pts:
                xs, ys, es = zip(*pts)
                ax.errorbar(xs, ys, yerr=es, fmt="o-", capsize=3, label="levels (error bars: defended error)")
            if finite(q["extrapolated"]):
                ax.axhline(q["extrapolated"], color="k" if q["trusted"] else "0.6", ls="--", lw=1,
                           label="extrapolated" + ("" if q["trusted"] else " (flagged: not to be trusted)"))
            ax.set_xscale("log")
            ax.invert_xaxis()
            ax.set_xlabel(unit)
            ax.set_title("%s %s: order %s%s" % (name, TITLES[kind],
                                                "%.2f" % q["order"] if finite(q["order"]) else "-",
                                                "" if q["trusted"] else " (flagged)"), fontsize=8)
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=6)
        ax = axes[-1]
        qser = [q for q in study["quantities"] if q["series"] == name and q["window"] == w0
                and q["kind"] not in ("peak", "t_peak", "mean", "end")]
        ser_trusted = bool(qser) and qser[0]["trusted"]
        fn = os.path.join(sdir, "%s__%s.csv" % (name, ("%g:%g" % tuple(w0)).replace(":", "_")))
        if os.path.exists(fn):
            c = read_series(fn)
            for k in range(len(levels)):
                if ("L%d" % k) in c:
                    ax.plot(c["time"], c["L%d" % k], lw=1, label="L%d (%s %.3g)" % (k, unit.split()[0], h[k]))
            if any(finite(x) for x in c.get("extrapolated", [])):
                ax.plot(c["time"], c["extrapolated"], "--", color="k" if ser_trusted else "0.6", lw=1,
                        label="extrapolated" + ("" if ser_trusted else " (flagged: not to be trusted)"))
            ax.set_xlabel("time [s]")
            ax.set_title(name + " (common time base)", fontsize=8)
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=6)
        else:
            ax.set_visible(False)
        fig.tight_layout()
        p = os.path.join(out, "convergence_%s.png" % name)
        fig.savefig(p, dpi=90)
        plt.close(fig)
        written.append(p)
    return written


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    d = sys.argv[1]
    with open(os.path.join(d, "study.json")) as f:
        study = json.load(f)
    out = os.path.join(d, "plots")
    os.makedirs(out, exist_ok=True)
    if not study["levels"]:
        print("plot_study.py: no level in %s" % d, file=sys.stderr)
        return 1
    paths = [error_vs_cost(study, out)] + convergence(study, os.path.join(d, "series"), out)
    for p in paths:
        print("wrote", p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
