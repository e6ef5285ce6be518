"""Figures 4 and 5 of the seed paper from a paper_alpha_study output directory (run with pvpython,
which has numpy and matplotlib): fig4_deviation.png (D(t), eq. 70, plus mean and rms), fig5_momentum.png
(Q(t) of the alpha = 0.5 and the explicit run), fig_iterations.png (fixed-point iterations of the
implicit run) and summary.csv (the plotted numbers)."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def table(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) if r[k] != "" else np.nan for r in rows]) for k in rows[0].keys()}


def main(out):
    dev = table(os.path.join(out, "deviation", "deviation.csv"))
    imp = table(os.path.join(out, "implicit_alpha0.5", "diagnostics.csv"))
    exp = table(os.path.join(out, "explicit", "diagnostics.csv"))

    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(dev["time"], dev["D_max"], "k-", label="D(t) = max |q_imp - q_exp| (eq. 70)")
    ax.plot(dev["time"], dev["D_rms"], "b--", label="rms")
    ax.plot(dev["time"], dev["D_mean"], "g:", label="mean")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("deviation [m]")
    ax.set_title("alpha = 0.5 against the explicit scheme (cf. paper Fig. 4)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig4_deviation.png"), dpi=120)

    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(imp["time"], imp["momentum_Q"], "k-", label="implicit, alpha = 0.5")
    ax.plot(exp["time"], exp["momentum_Q"], "r-", label="explicit (Verlet)")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("Q = |(1/M) sum m v| [kg m/s]")
    ax.set_title("linear momentum (cf. paper Fig. 5)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig5_momentum.png"), dpi=120)

    fig, ax = plt.subplots(figsize=(6, 3))
    ax.plot(imp["time"], imp["fp_iterations_mean"], "k-", label="mean iterations per step")
    ax.plot(imp["time"], imp["fp_iterations_max"], "r:", label="max")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("fixed-point iterations")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig_iterations.png"), dpi=120)

    with open(os.path.join(out, "summary.csv"), "w") as f:
        w = csv.writer(f)
        w.writerow(["time", "D_max", "D_mean", "D_rms", "Q_implicit", "Q_explicit", "E_kin_implicit", "E_kin_explicit"])
        for k, t in enumerate(dev["time"]):
            i = int(np.argmin(np.abs(imp["time"] - t)))
            e = int(np.argmin(np.abs(exp["time"] - t)))
            w.writerow([t, dev["D_max"][k], dev["D_mean"][k], dev["D_rms"][k], imp["momentum_Q"][i],
                        exp["momentum_Q"][e], imp["kinetic_energy"][i], exp["kinetic_energy"][e]])


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "runs/paper_alpha_study")
