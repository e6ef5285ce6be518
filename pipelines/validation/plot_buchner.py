#!/usr/bin/env python3
"""Wall pressure at Buchner's sensor P1, P = p/(rho g H) against T = t sqrt(g/H), of several case_buchner.py runs
with the digitised experiment (one panel; each run labelled with its RMS over T >= 2).

  /usr/bin/python3 pipelines/validation/plot_buchner.py OUT.png RUNDIR:LABEL [RUNDIR:LABEL ...] [--ymax 3]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import case_buchner as cb  # noqa: E402


def main():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    args = sys.argv[1:]
    ymax = 3.0
    if "--ymax" in args:
        k = args.index("--ymax")
        ymax = float(args[k + 1])
        del args[k:k + 2]
    if len(args) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    fig, ax = plt.subplots(figsize=(9, 4.4))
    for spec in args[1:]:
        d, label = spec.split(":", 1)
        m, (T, P) = cb.evaluate(d, d)
        ax.plot(T, P, lw=0.7, label=f"{label}: RMS {m['rms']:.2f}, maxima {m['first_max']:.2f} / {m['second_max']:.2f}")
    Tr, Pr = cb.reference()
    ax.scatter(Tr, Pr, s=10, color="k", zorder=3, label="Buchner (2002), digitised: maxima 0.686 / 0.879")
    ax.set_xlim(0, 8)
    ax.set_ylim(-0.5, ymax)
    ax.set_xlabel("T = t sqrt(g/H)")
    ax.set_ylabel("P = p / (rho g H) at P1")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(args[0], dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
