"""The film down a slope (film_slope.json, docs/validation.md section 19): the velocity profile of a run's last
frame against the Nusselt film, and the film depth along the channel.

    /usr/bin/python3 pipelines/open/plot_film.py RUN [--frame N]

Reads RUN/run.json (the resolved scene: gravity, nu, the inlet's water level H, the fluid box) and a frame of
RUN/frames (the last by default). Analytic steady film on a bed tilted by the gravity vector (x along the bed,
y normal to it; e.g. Bird, Stewart & Lightfoot, Transport Phenomena, sec. 2.2):
u(y) = g_x / nu (H y - y^2 / 2), u_s = g_x H^2 / (2 nu). Profile: the fluid (not buffer) particles of the
middle third of the channel, binned by rows of one spacing, mean u - u(y_i) per row over u_s. Writes
RUN/post/film_profile.png and film_profile.csv (y, mean u, analytic, count) and prints the largest row error.
Exit status 2 on bad input (no run.json, no frames, a scene without a water level).
"""
import argparse
import csv
import json
import os
import sys

import numpy as np


def fail(msg):
    print("plot_film: " + msg, file=sys.stderr)
    sys.exit(2)


def read_frame(path):
    try:
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
        from vtkmodules.util.numpy_support import vtk_to_numpy
    except ImportError:
        from vtk import vtkXMLUnstructuredGridReader  # type: ignore
        from vtk.util.numpy_support import vtk_to_numpy  # type: ignore
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    pd = g.GetPointData()
    out = {"x": vtk_to_numpy(g.GetPoints().GetData())}
    for name in ("velocity", "kind", "open_zone"):
        a = pd.GetArray(name)
        if a is None:
            fail("%s: no point array '%s' (name it in output.fields)" % (path, name))
        out[name] = vtk_to_numpy(a)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run")
    ap.add_argument("--frame", type=int, default=-1, help="frame index (default: the last)")
    a = ap.parse_args()
    try:
        with open(os.path.join(a.run, "run.json")) as f:
            scene = json.load(f)["scene"]
    except (OSError, ValueError, KeyError) as e:
        fail("%s: no readable run.json with a scene (%s)" % (a.run, e))
    inlets = [z for z in scene.get("open_boundaries", []) if "water_level" in z]
    if not inlets or not isinstance(inlets[0]["water_level"], (int, float)):
        fail("%s: the scene has no inlet with a fixed water_level" % a.run)
    H = float(inlets[0]["water_level"]) - float(inlets[0]["min"][1])
    g = float(scene["gravity"][0])
    nu = float(scene["physics"]["laminar_viscosity"]["nu"])
    dx = float(scene["particles"]["spacing"])
    fluid = [b for b in scene["bodies"] if b["kind"] == "fluid"][0]
    x0, L = float(fluid["min"][0]), float(fluid["max"][0]) - float(fluid["min"][0])
    frames = sorted(f for f in os.listdir(os.path.join(a.run, "frames")) if f.endswith(".vtu"))
    if not frames:
        fail("%s: no frames" % a.run)
    d = read_frame(os.path.join(a.run, "frames", frames[a.frame]))
    fl = (d["kind"] == 0) & (d["open_zone"] < 0)
    x, y, u = d["x"][fl, 0], d["x"][fl, 1], d["velocity"][fl, 0]
    us = g * H * H / (2 * nu)
    exact = lambda yy: g / nu * (H * np.clip(yy, 0, H) - np.clip(yy, 0, H) ** 2 / 2)
    mid = (x >= x0 + L / 3) & (x <= x0 + 2 * L / 3)
    rows = np.floor(y[mid] / dx).astype(int)
    table = []
    for r in sorted(set(rows)):
        k = rows == r
        table.append((float(np.mean(y[mid][k])), float(np.mean(u[mid][k])), float(np.mean(u[mid][k] - exact(y[mid][k]))), int(k.sum())))
    err = max(abs(t[2]) for t in table) / us
    cols = np.floor((x - x0) / (2 * dx)).astype(int)  # columns of two spacings: every one holds a top particle
    depth = {c: y[cols == c].max() + dx / 2 for c in sorted(set(cols))}
    post = os.path.join(a.run, "post")
    os.makedirs(post, exist_ok=True)
    with open(os.path.join(post, "film_profile.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["y", "u_mean", "u_exact", "count"])
        for yy, uu, du, n in table:
            w.writerow(["%.6g" % yy, "%.6g" % uu, "%.6g" % float(exact(yy)), n])
    print("%s: frame %s: largest row error %.2f %% of u_s = %.4g m/s (H = %.4g m, %d rows)" %
          (a.run, frames[a.frame], 100 * err, us, H, len(table)))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_film: matplotlib is not available: no plot", file=sys.stderr)
        return
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    yy = np.linspace(0, H, 100)
    ax[0].plot(exact(yy), yy * 1e3, "k-", label="Nusselt film g sin(a)/nu (H y - y^2/2)")
    ax[0].plot([t[1] for t in table], [t[0] * 1e3 for t in table], "o", color="tab:blue", label="SPH, mean per row")
    ax[0].set_xlabel("u [m/s]")
    ax[0].set_ylabel("y above the bed [mm]")
    ax[0].set_title("profile, middle third (row error max %.2f %% of u_s)" % (100 * err))
    ax[0].legend(fontsize=8)
    cs = sorted(depth)
    ax[1].plot([(x0 + (c + 0.5) * 2 * dx) * 1e3 for c in cs], [depth[c] / H for c in cs], "-", color="tab:blue",
               label="SPH: top particle + dx/2 (columns of 2 dx)")
    ax[1].axhline(1.0, color="k", lw=0.8, label="imposed level H")
    ax[1].set_xlabel("x along the bed [mm]")
    ax[1].set_ylabel("film depth / H")
    ax[1].set_ylim(0.9, 1.1)
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    png = os.path.join(post, "film_profile.png")
    fig.savefig(png, dpi=110)
    print(png)


if __name__ == "__main__":
    main()
