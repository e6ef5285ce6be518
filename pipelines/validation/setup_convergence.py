#!/usr/bin/env python3
"""Convergence of one set-up on the dam break (issue 33 point 3): what a resolution buys and what it costs.

Two cases, each at several resolutions H/dx, run with the set-up's method blocks (vsetup.py, as setup_matrix.py):
  column   the n^2 = 2 column of case_column_height.py (a = 0.145 m, H = 2a = 0.29 m, dx = H / N): Martin &
           Moyce front unshifted and at its best time shift, the residual height at the back wall (RMS relative,
           unshifted, at the front's shift and at its own best shift);
  buchner  the Buchner (2002) wall-pressure case of case_buchner.py (H = 0.6 m, dx = H / N): P1 RMS over T >= 2,
           the two maxima against the data, the arrival, the T 3-5 plateau mean, the energy lost before impact.
Cost per level: fluid particles, steps, solver wall seconds, the machine load before the run and the
microseconds per fluid particle-step (one thread unless --threads).

  /usr/bin/python3 pipelines/validation/setup_convergence.py [--setup pipelines/engineering_2d.json]
      [--column 25,50,100,200] [--buchner 25,50,100] [--threads 1] [-o runs/setup_convergence/NAME] [--resume]

Writes OUT/convergence.json (one record per case and level, written after every run so that a long study can be
stopped and resumed with --resume) and OUT/convergence.md (the tables). Exit 0 when every run ended (a run that
stopped early is a row with its exit code), 2 on bad input.
"""
import argparse
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vcommon as vc  # noqa: E402
import case_buchner  # noqa: E402
import case_column_height as cch  # noqa: E402


def bad_input(msg):
    print(f"setup_convergence.py: {msg}", file=sys.stderr)
    sys.exit(2)


def levels(text, key):
    try:
        out = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        bad_input(f"--{key} '{text}': expected a comma list of integers H/dx")
    if any(n < 10 or n > 1000 for n in out):
        bad_input(f"--{key} '{text}': every H/dx must lie in [10, 1000]")
    return out


def particles(rundir):
    p = os.path.join(rundir, "diagnostics.csv")
    if not os.path.exists(p):
        return None
    d = vc.read_csv(p)
    return int(d["fluid_particles"][0]) if len(d["fluid_particles"]) else None


def cost(res, rundir):
    n = particles(rundir)
    us = (1e6 / res["psps"]) if res.get("psps") else float("nan")
    return {"particles": n, "steps": res.get("steps"), "wall": res.get("wall"), "load": res.get("load"),
            "us_per_particle_step": us, "rc": res.get("rc"), "message": res.get("message", "")}


def run_column(n, setup, threads, outdir):
    dx = cch.HCOL / n
    rundir = os.path.join(outdir, f"column_N{n}")
    r = cch.run_case(dx, None, threads, rundir, setup=setup)
    keep = ("mm_rms", "mm_rms_shift", "mm_dT", "height_rms", "height_mean_rel", "height_rms_front_shift",
            "height_rms_best_shift", "height_best_dtau", "t_reached")
    rec = {"case": "column", "N": n, "dx": dx}
    rec.update({k: r.get(k, float("nan")) for k in keep})
    rec.update(cost(r, rundir))
    return rec


def run_buchner(n, setup, threads, outdir):
    rundir = os.path.join(outdir, f"buchner_N{n}")
    r = case_buchner.run_case(n, None, threads, rundir, setup=setup)
    keep = ("rms", "first_max_diff", "second_max_diff", "arrival_T", "arrival_T_data", "mean_T3_5",
            "mean_T3_5_data", "energy_loss_T2", "T_reached")
    rec = {"case": "buchner", "N": n, "dx": case_buchner.H / n}
    rec.update({k: r.get(k, float("nan")) for k in keep})
    rec.update(cost(r, rundir))
    return rec


def fmt(v, spec):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "nan"
    return format(v, spec)


def tables(records, setup):
    col = sorted((r for r in records if r["case"] == "column"), key=lambda r: r["N"])
    buc = sorted((r for r in records if r["case"] == "buchner"), key=lambda r: r["N"])
    out = [f"Set-up: `{setup}`", ""]
    if col:
        out += ["| column H/dx | dx [mm] | particles | MM front unshifted | best shift (dT) | back-wall height RMS "
                "(mean) | at the front's shift | best shift (dtau) | exit | wall s (load) | us/particle-step |",
                "|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in col:
            out.append(f"| {r['N']} | {r['dx'] * 1e3:.2f} | {r['particles']} | {fmt(r['mm_rms'], '.2%')} | "
                       f"{fmt(r['mm_rms_shift'], '.2%')} ({fmt(r['mm_dT'], '+.3f')}) | "
                       f"{fmt(r['height_rms'], '.1%')} ({fmt(r['height_mean_rel'], '+.1%')}) | "
                       f"{fmt(r.get('height_rms_front_shift'), '.1%')} | {fmt(r['height_rms_best_shift'], '.1%')} "
                       f"({fmt(r['height_best_dtau'], '+.3f')}) | {r['rc']} | {fmt(r['wall'], '.0f')} "
                       f"({fmt(r['load'], '.1f')}) | {fmt(r['us_per_particle_step'], '.2f')} |")
        out.append("")
    if buc:
        out += ["| Buchner H/dx | dx [mm] | particles | P1 RMS (T >= 2) | first max - 0.686 | second max - 0.879 | "
                "arrival - data | mean T 3-5 - data | energy lost at T = 2 | T reached | wall s (load) | "
                "us/particle-step |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in buc:
            arr = r["arrival_T"] - r["arrival_T_data"] if r["arrival_T"] is not None else float("nan")
            mean = r["mean_T3_5"] - r["mean_T3_5_data"] if r["mean_T3_5"] is not None else float("nan")
            out.append(f"| {r['N']} | {r['dx'] * 1e3:.1f} | {r['particles']} | {fmt(r['rms'], '.3f')} | "
                       f"{fmt(r['first_max_diff'], '+.3f')} | {fmt(r['second_max_diff'], '+.3f')} | "
                       f"{fmt(arr, '+.3f')} | {fmt(mean, '+.3f')} | {fmt(r['energy_loss_T2'], '.2%')} | "
                       f"{fmt(r['T_reached'], '.2f')} | {fmt(r['wall'], '.0f')} ({fmt(r['load'], '.1f')}) | "
                       f"{fmt(r['us_per_particle_step'], '.2f')} |")
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--setup", default=os.path.join(vc.ROOT, "pipelines", "engineering_2d.json"))
    ap.add_argument("--column", default="25,50,100,200")
    ap.add_argument("--buchner", default="25,50,100")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("-o", "--outdir")
    ap.add_argument("--resume", action="store_true", help="keep the records of OUT/convergence.json, run the rest")
    ap.add_argument("--check-converges", action="store_true",
                    help="exit 1 unless every run ended and the column's best-shift front error and the Buchner "
                         "plateau-mean error do not grow from one level to the next finer one (CTest)")
    a = ap.parse_args()
    if not os.path.isfile(a.setup):
        bad_input(f"--setup '{a.setup}': no such file")
    col, buc = levels(a.column, "column"), levels(a.buchner, "buchner")
    name = os.path.splitext(os.path.basename(a.setup))[0]
    outdir = os.path.abspath(a.outdir or os.path.join(vc.ROOT, "runs", "setup_convergence", name))
    os.makedirs(outdir, exist_ok=True)
    jpath = os.path.join(outdir, "convergence.json")
    records = []
    if a.resume and os.path.exists(jpath):
        with open(jpath) as f:
            records = json.load(f)["records"]
    done = {(r["case"], r["N"]) for r in records}
    plan = [("column", n) for n in col] + [("buchner", n) for n in buc]
    for case, n in plan:
        if (case, n) in done:
            continue
        print(f"{case} H/dx {n} ...", flush=True)
        rec = (run_column if case == "column" else run_buchner)(n, a.setup, a.threads, outdir)
        records.append(rec)
        with open(jpath, "w") as f:
            json.dump({"setup": a.setup, "records": records}, f, indent=1)
        print(json.dumps(rec), flush=True)
    md = tables(records, a.setup)
    with open(os.path.join(outdir, "convergence.md"), "w") as f:
        f.write(md)
    print(md)
    if a.check_converges:
        return check_converges(records)
    return 0


def check_converges(records):
    bad = [f"{r['case']} H/dx {r['N']}: exit {r['rc']}" for r in records if r["rc"] != 0]
    # what converges (docs/validation.md section 21): the front's shape and the load's plateau. The P1 RMS, maxima
    # and threshold arrival do not (0.215 / 0.218 / 0.251, arrival +0.038 / +0.013 / +0.159 at H/dx 25 / 50 / 100:
    # an acoustic oscillation and a thin leading sheet at the sensor), so they are tabulated, not checked
    metrics = {"column": {"front best-shift RMS": lambda r: r["mm_rms_shift"]},
               "buchner": {"|mean T 3-5 - data|": lambda r: abs(r["mean_T3_5"] - r["mean_T3_5_data"])}}
    for case, checks in metrics.items():
        rs = sorted((r for r in records if r["case"] == case), key=lambda r: r["N"])
        for name, f_of in checks.items():
            for c, f in zip(rs, rs[1:]):
                if not f_of(f) <= f_of(c):
                    bad.append(f"{case} {name} grows from H/dx {c['N']} ({f_of(c):.4f}) to {f['N']} ({f_of(f):.4f})")
    print("FAIL: " + "; ".join(bad) if bad else "OK: every level ran and the errors do not grow with resolution")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
