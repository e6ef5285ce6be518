#!/usr/bin/env python3
"""Markdown tables for docs/validation.md from the CSVs the scripts write.

  /usr/bin/python3 pipelines/validation/report_tables.py [--wp runs/work_precision/work_precision.csv]
      [--stability runs/stability] [--convergence runs/convergence/convergence.csv]
"""
import argparse
import csv
import os


def rows(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def fnum(x, fmt="{:.3g}"):
    try:
        v = float(x)
    except (TypeError, ValueError):
        return str(x or "")
    return "nan" if v != v else fmt.format(v)


def wp_table(rs):
    out = []
    for case in dict.fromkeys(r["case"] for r in rs):
        sub = [r for r in rs if r["case"] == case]
        out.append(f"\n**{case}**\n")
        if case == "dam_break":
            out.append("| integrator | dx | f (dt = f h/c0) | dt [s] | exit | wall s per sim. s | load | "
                       "MM RMS unshifted | MM RMS best shift (dT) | KO best shift |")
            out.append("|---|---|---|---|---|---|---|---|---|---|")
            for r in sub:
                out.append(f"| {r['label']} | {r['dx']} | {r['f']} | {fnum(r['dt'])} | {r['rc']} | "
                           f"{fnum(r['wall_per_sim_s'])} | {fnum(r['load'], '{:.1f}')} | "
                           f"{fnum(float(r['mm_rms']) * 100 if r['mm_rms'] not in ('', 'nan') else 'nan', '{:.1f}')} % | "
                           f"{fnum(float(r['mm_rms_shift']) * 100 if r['mm_rms_shift'] not in ('', 'nan') else 'nan', '{:.2f}')} % "
                           f"({r['mm_dT']}) | "
                           f"{fnum(float(r['ko_rms_shift']) * 100 if r['ko_rms_shift'] not in ('', 'nan') else 'nan', '{:.1f}')} % |")
        else:
            out.append("| integrator | dx | f (dt = f h/c0) | dt [s] | exit | wall s per sim. s | load | error |")
            out.append("|---|---|---|---|---|---|---|---|")
            for r in sub:
                out.append(f"| {r['label']} | {r['dx']} | {r['f']} | {fnum(r['dt'])} | {r['rc']} | "
                           f"{fnum(r['wall_per_sim_s'])} | {fnum(r['load'], '{:.1f}')} | {fnum(r['error'])} |")
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--wp", default="runs/work_precision/work_precision.csv")
    ap.add_argument("--stability", default="runs/stability")
    ap.add_argument("--convergence", default="runs/convergence/convergence.csv")
    a = ap.parse_args()
    rs = rows(a.wp)
    if rs:
        print("## Work-precision rows\n" + wp_table(rs))
    st = rows(os.path.join(a.stability, "stability.csv"))
    if st:
        print("\n## Largest stable dt\n\n| case | integrator | largest stable f | dt [s] | first unstable f | runs | NaN frames |")
        print("|---|---|---|---|---|---|---|")
        for r in st:
            print(f"| {r['case']} | {r['integrator']} | {fnum(r['f_stable'])} | {fnum(r['dt_stable'])} | "
                  f"{fnum(r['f_unstable'])} | {r['runs']} | {r['nan_frames_total']} |")
    hc = rows(os.path.join(a.stability, "hard_cases.csv"))
    if hc:
        print("\n## Hard cases\n\n| case | exit | frames | NaN frames | wall [s] | message |\n|---|---|---|---|---|---|")
        for r in hc:
            print(f"| {r['case']} | {r['rc']} | {r['frames']} | {r['nan_frames']} | {fnum(r['wall'])} | "
                  f"{r['message'][:220]} |")
    cv = rows(a.convergence)
    if cv:
        print("\n## Convergence\n\n| case | dx | error | exit | wall [s] | load |\n|---|---|---|---|---|---|")
        for r in cv:
            print(f"| {r['case']} | {r['dx']} | {fnum(r['error'])} | {r['rc']} | {fnum(r['wall'])} | "
                  f"{fnum(r['load'], '{:.1f}')} {r.get('message', '')} |")


if __name__ == "__main__":
    main()
