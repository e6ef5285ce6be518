#!/usr/bin/env python3
"""Surge front Z = x/a against T = t sqrt(2 g / a) of dam-break runs, with Martin & Moyce (1952) n^2 = 2
(a = 2.25 in and 1.125 in) and Koshizuka & Oka (1996).

  /usr/bin/python3 pipelines/validation/plot_fronts.py OUT.png RUNDIR:DX:LABEL [RUNDIR:DX:LABEL ...]
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vcommon as vc  # noqa: E402
import case_dam_break as db  # noqa: E402


def main():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    out = sys.argv[1]
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for spec in sys.argv[2:]:
        d, dx, label = spec.split(":", 2)
        T, Z = db.front_series(d, float(dx))
        m = db.evaluate(d, float(dx))
        ax.plot(T, Z, lw=1.2, label=f"{label} (RMS {100 * m['mm_rms']:.1f} %, shifted {100 * m['mm_rms_shift']:.2f} % "
                                     f"at dT={m['mm_dT']:+.2f})")
        ax.plot(T - m["mm_dT"], Z, lw=0.6, ls=":", color=ax.lines[-1].get_color())
    for name, mk, lab in (("martin_moyce_n2_2_a2.25in_front_pysph.csv", "o", "Martin & Moyce n2=2, a=2.25 in"),
                          ("martin_moyce_n2_2_a1.125in_front_pysph.csv", "s", "Martin & Moyce n2=2, a=1.125 in"),
                          ("koshizuka_oka_1996_front_exp_pysph.csv", "^", "Koshizuka & Oka 1996")):
        r = vc.reference(name)
        ax.plot(r["T"], r["Z"], mk, mfc="none", color="k", label=lab)
    ax.axvspan(0.8, 3.0, color="0.9", zorder=-1)
    ax.set_xlim(0, 3.5)
    ax.set_ylim(1, 4.2)
    ax.set_xlabel("T = t sqrt(2 g / a)")
    ax.set_ylabel("Z = x_front / a")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title("dam break surge front (dotted: shifted by -dT)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
