#!/usr/bin/env python3
"""Set-up matrix: one engineering set-up (the kernel / fluid / physics / boundary / integrator / health blocks
of a scene file, vsetup.py) run on EVERY validation case at once, one table row per metric (a goal "<= b" bounds the magnitude of the value).

Each case keeps its own geometry, probes, time and flow keys (vsetup.CASE_KEYS) and takes the set-up's
method blocks; wall layers follow the set-up's kernel. Without --setup every case runs its own scene (the
baseline of docs/validation.md). This is the tool by which a recommended set-up is chosen across all cases,
never by one metric (issue 13, point 5).

  /usr/bin/python3 pipelines/validation/setup_matrix.py [--setup FILE.json] [--quick] [--cases a,b,...]
      [--sensor '{"radius": 0.005}'] [--threads 2] [-o runs/setup_matrix/NAME] [--timeout 3600]

  /usr/bin/python3 pipelines/validation/setup_matrix.py --compare OUT1 OUT2 ...   # one column per set-up

--update re-runs only --cases in an existing OUT (after a harness fix) and keeps the other cases' rows of
OUT/matrix.json in their places.

--quick runs coarse versions (a few minutes on an idle 2-core machine, no 3D case); the full matrix takes
about an hour (docs/validation.md section 12). --sensor merges keys into every pressure probe of every case
(e.g. the sensor radius of the lead's pressure probe). Writes OUT/matrix.json (rows and every case's raw
metrics) and OUT/matrix.md (the table); prints the table. Exit 0 when every case ran (pass or fail), 1 when
a case could not be evaluated, 2 on bad input.

Cases (goals: issue 13 where it names one, else the stated engineering bound; "info" rows carry none):
  dam_break      n^2 = 2 column in a long tank (case_column_height.py): Martin & Moyce front at best shift
                 (<= 0.9 %; quick, dx 10 mm: <= 3 %), Koshizuka & Oka front (info), back-wall height (<= 10 %)
  hydrostatic    tank at rest (case_hydrostatic.py --settle, 2 s / quick 1 s): centre-line and wall pressure <= 1 %
  buchner        Buchner (2002) wall pressure (case_buchner.py, H/dx 50 / quick 25): RMS <= 0.08, maxima within
                 0.15 / 0.2, survival to T = 8, energy lost before the impact <= 2 %, no energy growth
  jet_plate      jet on a plate (case_jet_plate.py, dx 5 / quick 10 mm): force <= 3 %, stagnation pressure <= 5 %
  spheric2       SPHERIC Test 2 / Kleefsman 2005, 3D (case_spheric2.py, dx 0.05; not in --quick)
  impact         10 m/s block against a wall (case_impact.py): survives, no particle crosses the wall
  taylor_green   periodic vortex, Re 100 (case_taylor_green.py): L1(t = 1) <= 0.03 (quick dx 0.05: <= 0.2)
  poiseuille     start-up between walls (case_poiseuille.py): <= 1.5 % of u_max (quick: <= 2 %)
"""
import argparse
import json
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vcommon as vc  # noqa: E402
import vsetup  # noqa: E402
import case_buchner  # noqa: E402
import case_column_height  # noqa: E402
import case_dam_break  # noqa: E402
import case_hydrostatic  # noqa: E402
import case_impact  # noqa: E402
import case_jet_plate  # noqa: E402
import case_poiseuille  # noqa: E402
import case_taylor_green  # noqa: E402

try:
    import case_spheric2  # noqa: E402
except ImportError:  # the 3D case is optional
    case_spheric2 = None


class Ctx:
    def __init__(self, setup, setup_path, quick, outdir, threads, sensor, timeout):
        self.setup, self.setup_path, self.quick, self.out = setup, setup_path, quick, outdir
        self.threads, self.sensor, self.timeout = threads, sensor, timeout

    def scene(self, name, scene):
        """Scene (path or dict) with the set-up and sensor applied, written to OUT/scenes/NAME.json."""
        if isinstance(scene, str):
            base = os.path.dirname(os.path.abspath(scene))
            scene = vsetup.load_json(scene)
        else:
            base = vc.ROOT
        if self.setup:
            scene = vsetup.apply_setup(scene, self.setup)
        if self.sensor:
            for p in scene.get("probes", []):
                if p.get("type") == "pressure":
                    p.update(self.sensor)
        for b in scene.get("bodies", []):
            if "mesh" in b and not os.path.isabs(b["mesh"]):
                b["mesh"] = os.path.join(base, b["mesh"])
        path = os.path.join(self.out, "scenes", name + ".json")
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            json.dump(scene, f, indent=1)
        return path

    def run_dir(self, name):
        return os.path.join(self.out, "runs", name)


def row(case, metric, value, goal=None, ok=None, res=None, fmt="{:.4g}", note=""):
    """One table row; goal is (op, bound) with op '<=' on |value| or 'eq' for equality, or None (info)."""
    res = res or {}
    if goal is not None and ok is None:
        op, bound = goal
        ok = (value == bound) if op == "eq" else (value is not None and math.isfinite(value) and abs(value) <= bound)
    gtxt = "" if goal is None else (f"= {goal[1]}" if goal[0] == "eq" else f"<= {fmt.replace('+', '').format(goal[1])}")
    return {"case": case, "metric": metric, "value": value,
            "value_text": (fmt.format(value) if isinstance(value, (int, float)) and value is not None else str(value)),
            "goal": gtxt, "pass": ok, "wall": res.get("wall"), "load": res.get("load"), "rc": res.get("rc"),
            "note": note}


def pct(v):
    return "{:.2%}".format(v) if isinstance(v, float) and math.isfinite(v) else str(v)


# ---- cases -----------------------------------------------------------------------------------------------------

def case_dam_break_rows(ctx):
    dx = 0.01 if ctx.quick else 0.005
    scene = ctx.scene("dam_break", case_dam_break.SCENE)
    r = case_column_height.run_case(dx, None, ctx.threads, ctx.run_dir("dam_break"), scene, timeout=ctx.timeout)
    n = f"dx {dx:g}"
    rows = [row("dam_break", "survives to t = 0.8 s", r["rc"], ("eq", 0), res=r,
                note=(f"stopped at t = {r.get('t_reached', float('nan')):.3f} s: " + r["message"][:100]) if r["rc"] else
                "long tank, no reflection")]
    if "mm_rms_shift" not in r:
        return r, rows
    front_goal = 0.03 if ctx.quick else 0.009
    return r, rows + [
        row("dam_break", "MM front RMS at best shift", r["mm_rms_shift"], ("<=", front_goal), res=r, fmt="{:.2%}",
            note=f"{n}; dT {r['mm_dT']:+.3f}" + ("; quick bound" if ctx.quick else "")),
        row("dam_break", "MM front RMS unshifted", r["mm_rms"], None, res=r, fmt="{:.2%}", note="info: the gate delays the experiment"),
        row("dam_break", "KO front RMS at best shift", r["ko_rms_shift"], None, res=r, fmt="{:.2%}", note="info"),
        row("dam_break", "MM back-wall height RMS (rel.)", r["height_rms"], ("<=", 0.10), res=r, fmt="{:.2%}",
            note=f"mean {r.get('height_mean_rel', float('nan')):+.1%} (+ = falls too slowly)"),
    ]


def case_hydrostatic_rows(ctx):
    dx, t_end = (0.02, 1.0) if ctx.quick else (0.01, 2.0)
    scene = ctx.scene("hydrostatic", case_hydrostatic.SCENE)
    # the consistent start (rho0, gravity ramp, damping to t_end / 2): the scene's hydrostatic start carries a
    # ~1-2 % bias at every dx whatever the set-up (inconsistent lattice volumes, docs/validation.md section 5)
    r = case_hydrostatic.run_case(dx, None, ctx.threads, ctx.run_dir("hydrostatic"), t_end, scene=scene, settle=True)
    n = f"dx {dx:g}, {t_end:g} s, settled start, means over the last 20 %"
    if r["rc"] != 0:
        return r, [row("hydrostatic", "survives", r["rc"], ("eq", 0), res=r, note=r["message"][:120])]
    return r, [
        row("hydrostatic", "centre-line pressure L2 error", r["p_err"], ("<=", 0.01), res=r, fmt="{:.2%}", note=n),
        row("hydrostatic", "wall pressure, worst depth", r["p_wall_err_max"], ("<=", 0.01), res=r, fmt="{:.2%}",
            note="8 depths on the side wall"),
        row("hydrostatic", "free-surface drift [m]", r["drift"], None, res=r, fmt="{:.2e}", note="info"),
    ]


def case_buchner_rows(ctx):
    N = 25 if ctx.quick else 50
    scene = ctx.scene("buchner", case_buchner.SCENE)
    r = case_buchner.run_case(N, None, ctx.threads, ctx.run_dir("buchner"), scene,
                              png=os.path.join(ctx.out, "buchner_p1.png"), timeout=ctx.timeout)
    return r, buchner_rows(r, N)


def buchner_rows(r, N):
    """Table rows of a case_buchner.run_case result (also for a run made outside the matrix)."""
    n = f"H/dx {N:g}"
    rows = [row("buchner", "survives to T = 8", r["rc"], ("eq", 0), res=r,
                note=(f"stopped at T = {r['T_reached']:.2f}: " + r["message"][:100]) if r["rc"] else n)]
    if "rms" not in r:
        return rows
    rows += [
        row("buchner", "P1 RMS (T >= 2)", r["rms"], ("<=", 0.08), res=r, fmt="{:.3f}", note=n + "; peers 0.24-0.71"),
        row("buchner", "first max - 0.686", r["first_max_diff"], ("<=", 0.15), res=r, fmt="{:+.3f}",
            note=f"max {r['first_max']:.3f} at T {r['first_max_T']:.2f}"),
        row("buchner", "second max - 0.879", r["second_max_diff"], ("<=", 0.2), res=r, fmt="{:+.3f}",
            note=f"max {r['second_max']:.3f} at T {r['second_max_T']:.2f}"),
        row("buchner", "arrival T (P > 0.1) - 2.48", r["arrival_T"] - r["arrival_T_data"], None, res=r,
            fmt="{:+.3f}", note="info"),
        row("buchner", "mean P, T 3-5 (data 0.553)", r["mean_T3_5"] - r["mean_T3_5_data"], None, res=r,
            fmt="{:+.3f}", note="info: sim - data"),
        row("buchner", "energy lost before impact (T=2)", r["energy_loss_T2"], ("<=", 0.02), res=r, fmt="{:.2%}",
            note="of the available energy"),
        row("buchner", "energy growth (max)", r["energy_growth_max"], ("<=", 0.005), res=r, fmt="{:.2%}",
            note=f"lost by T {r['energy_end_T']:.1f}: {r['energy_loss_end']:.0%} (info)"),
    ]
    return rows


def case_jet_rows(ctx):
    dx = 0.01 if ctx.quick else 0.005
    scene = ctx.scene("jet_plate", case_jet_plate.SCENE)
    r = case_jet_plate.run_case(dx, None, ctx.threads, ctx.run_dir("jet_plate"), scene,
                                png=os.path.join(ctx.out, "jet_plate.png"), timeout=ctx.timeout)
    rows = [row("jet_plate", "survives", r["rc"], ("eq", 0), res=r, note=r["message"][:120])]
    if "force_err" in r:
        rows += [row("jet_plate", "force / (rho U^2 b) - 1", r["force_err"], ("<=", 0.03), res=r, fmt="{:+.2%}",
                     note=f"dx {dx:g}; window std {r.get('force_std_rel', float('nan')):.1%}"),
                 row("jet_plate", "stagnation p / (rho U^2/2) - 1", r["p_stag_err"], ("<=", 0.05), res=r,
                     fmt="{:+.2%}", note=f"window std {r.get('p_stag_std_rel', float('nan')):.1%}")]
    return r, rows


def case_spheric2_rows(ctx):
    if case_spheric2 is None:
        return {}, [row("spheric2", "not available", "case_spheric2.py missing", None)]
    if ctx.quick:
        return {}, [row("spheric2", "3D case", "not run in --quick", None, note="run the full matrix or case_spheric2.py")]
    scene = ctx.scene("spheric2", case_spheric2.SCENE)
    r = case_spheric2.run_case(case_spheric2.DX, None, ctx.threads, ctx.run_dir("spheric2"), scene,
                               png=os.path.join(ctx.out, "spheric2.png"), timeout=ctx.timeout)
    return r, case_spheric2.matrix_rows(r, row)


def case_impact_rows(ctx):
    scene = ctx.scene("impact", case_impact.SCENE)
    r = case_impact.run_case(None, ctx.threads, ctx.run_dir("impact"), scene, timeout=ctx.timeout)
    return r, [row("impact", "10 m/s impact survives", r["rc"], ("eq", 0), res=r, note=r["message"][:120]),
               row("impact", "fluid particles behind a wall", r.get("escaped_max"), ("eq", 0), res=r, fmt="{}",
                   note=f"beyond the first wall layer; closest approach {r.get('closest_to_wall_dx', float('nan')):+.2f} dx; "
                        f"max |rho/rho0-1| {r.get('rho_err', float('nan')):.2f}")]


def generated(ctx, name, make):
    """Scene of a case script that generates its own (TG, Poiseuille): flow speed 1 m/s for the c0 rule."""
    d = make()
    if ctx.setup and ctx.setup.get("fluid", {}).get("c0", "auto") == "auto":
        d.setdefault("fluid", {})["reference_speed"] = 1.0
    return ctx.scene(name, d)


def case_tg_rows(ctx):
    dx, t_end = (0.05, 1.0) if ctx.quick else (0.02, 2.0)
    scene = generated(ctx, "taylor_green", lambda: case_taylor_green.make_scene(dx, "laminar", t_end=t_end))
    out = ctx.run_dir("taylor_green")
    r = vc.run(scene, out, {"output.every": 0.1}, ctx.threads, timeout=ctx.timeout)
    res = {"rc": r.rc, "wall": r.solver_wall, "load": r.load_before, "message": r.message() if r.rc else ""}
    if r.rc != 0:
        return res, [row("taylor_green", "survives", r.rc, ("eq", 0), res=res, note=res["message"][:120])]
    res.update(case_taylor_green.evaluate(out, t_end))
    return res, [row("taylor_green", "L1 velocity error at t = 1", res["l1_t1"], ("<=", 0.2 if ctx.quick else 0.03),
                     res=res, fmt="{:.4f}", note=f"dx {dx:g}" + ("; quick bound" if ctx.quick else ""))]


def case_poiseuille_rows(ctx):
    dx = 0.05 if ctx.quick else 0.025
    scene = generated(ctx, "poiseuille", lambda: case_poiseuille.make_scene(dx, 1.0))
    out = ctx.run_dir("poiseuille")
    r = vc.run(scene, out, {}, ctx.threads, timeout=ctx.timeout)
    res = {"rc": r.rc, "wall": r.solver_wall, "load": r.load_before, "message": r.message() if r.rc else ""}
    if r.rc != 0:
        return res, [row("poiseuille", "survives", r.rc, ("eq", 0), res=res, note=res["message"][:120])]
    res.update(case_poiseuille.evaluate(out))
    return res, [row("poiseuille", "max |u - u_series| / u_max", res["error"], ("<=", 0.02 if ctx.quick else 0.015),
                     res=res, fmt="{:.2%}", note=f"dx {dx:g}")]


CASES = {"dam_break": case_dam_break_rows, "hydrostatic": case_hydrostatic_rows, "buchner": case_buchner_rows,
         "jet_plate": case_jet_rows, "spheric2": case_spheric2_rows, "impact": case_impact_rows,
         "taylor_green": case_tg_rows, "poiseuille": case_poiseuille_rows}


def cell(text):
    return str(text).replace("|", "\\|")


def table(rows):
    head = "| case | metric | value | goal | pass | wall s (load) | note |\n|---|---|---|---|---|---|---|\n"
    lines = []
    for r in rows:
        p = {True: "PASS", False: "FAIL", None: ""}[r["pass"]]
        w = f"{r['wall']:.1f} ({r['load']:.1f})" if isinstance(r.get("wall"), (int, float)) and r.get("load") is not None else ""
        lines.append(f"| {r['case']} | {cell(r['metric'])} | {cell(r['value_text'])} | {cell(r['goal'])} | {p} | {w} | "
                     f"{cell(r['note'])} |")
    return head + "\n".join(lines) + "\n"


def compare(dirs):
    """Markdown table of several matrix.json files side by side: one row per (case, metric), one column per set-up."""
    runs = []
    for d in dirs:
        p = os.path.join(d, "matrix.json")
        try:
            with open(p) as f:
                runs.append(json.load(f))
        except (OSError, json.JSONDecodeError) as e:
            vsetup.die(f"{p}: cannot read a matrix result ({e})")
    keys, goals = [], {}
    for m in runs:
        for r in m["rows"]:
            k = (r["case"], r["metric"])
            if k not in goals:
                keys.append(k)
                goals[k] = r["goal"]
    names = [os.path.basename(os.path.normpath(d)) for d in dirs]
    out = "| case | metric | goal | " + " | ".join(names) + " |\n|---|---|---|" + "---|" * len(names) + "\n"
    for k in keys:
        cells = []
        for m in runs:
            r = next((r for r in m["rows"] if (r["case"], r["metric"]) == k), None)
            cells.append("" if r is None else cell(r["value_text"]) + {True: " ok", False: " **x**", None: ""}[r["pass"]])
        out += f"| {k[0]} | {cell(k[1])} | {cell(goals[k])} | " + " | ".join(cells) + " |\n"
    for case in dict.fromkeys(k[0] for k in keys):  # the cost of each case, from its first row
        cells = []
        for m in runs:
            r = next((r for r in m["rows"] if r["case"] == case), None)
            ok = r is not None and isinstance(r.get("wall"), (int, float)) and r.get("load") is not None
            cells.append(f"{r['wall']:.0f} ({r['load']:.1f})" if ok else "")
        if any(cells):
            out += f"| {case} | solver wall s (load) |  | " + " | ".join(cells) + " |\n"
    out += "\n" + "; ".join(f"{n}: {m.get('setup') or 'own scenes'} ({m.get('description', '')})" for n, m in
                             zip(names, runs)) + "\n"
    return out


def load_kept(out, names):
    """--update: the earlier matrix.json's rows, in order, with the cases about to be re-run marked for replacement."""
    p = os.path.join(out, "matrix.json")
    try:
        with open(p) as f:
            old = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        vsetup.die(f"{p}: --update needs an earlier matrix result ({e})")
    order = []
    for r in old["rows"]:
        if r["case"] not in order:
            order.append(r["case"])
    order += [n for n in names if n not in order]
    return {"order": order, "old": old["rows"], "fresh": {}, "cases": old.get("cases", {})}


def merged_rows(kept):
    """Rows of every case in the earlier order: the re-run cases' fresh rows, the others' old ones."""
    rows = []
    for case in kept["order"]:
        rows += kept["fresh"].get(case) or [r for r in kept["old"] if r["case"] == case]
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--compare", nargs="+", metavar="OUT", help="print the results of earlier runs side by side")
    ap.add_argument("--setup", help="scene file whose method blocks are the set-up (default: every case's own scene)")
    ap.add_argument("--quick", action="store_true", help="coarse versions, no 3D case")
    ap.add_argument("--cases", default=",".join(CASES), help="comma list of " + ", ".join(CASES))
    ap.add_argument("--sensor", help="JSON object merged into every pressure probe, e.g. '{\"radius\": 0.005}'")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=None, help="seconds per varsph run (default none)")
    ap.add_argument("--update", action="store_true",
                    help="keep the rows of the cases not run now from an existing OUT/matrix.json")
    ap.add_argument("-o", "--outdir")
    a = ap.parse_args()
    if a.compare:
        print(compare(a.compare))
        return 0
    names = [c.strip() for c in a.cases.split(",") if c.strip()]
    unknown = [c for c in names if c not in CASES]
    if unknown:
        print(f"setup_matrix.py: --cases: unknown case(s) {', '.join(unknown)}; expected some of {', '.join(CASES)}",
              file=sys.stderr)
        return 2
    sensor = None
    if a.sensor:
        try:
            sensor = json.loads(a.sensor)
        except json.JSONDecodeError as e:
            print(f"setup_matrix.py: --sensor: not valid JSON ({e.msg}); expected an object such as "
                  "'{\"radius\": 0.005}'", file=sys.stderr)
            return 2
        if not isinstance(sensor, dict):
            print("setup_matrix.py: --sensor: expected a JSON object", file=sys.stderr)
            return 2
    setup = vsetup.load_setup(a.setup) if a.setup else None
    tag = os.path.splitext(os.path.basename(a.setup))[0] if a.setup else "own_scenes"
    out = a.outdir or os.path.join(vc.ROOT, "runs", "setup_matrix", tag + ("_quick" if a.quick else ""))
    kept = load_kept(out, names) if a.update else None  # before anything is written
    os.makedirs(out, exist_ok=True)
    ctx = Ctx(setup, a.setup, a.quick, out, a.threads, sensor, a.timeout)
    desc = vsetup.describe(setup) if setup else "each case's own scene"
    print(f"set-up: {a.setup or '(none)'}: {desc}; {'quick' if a.quick else 'full'}; output {out}", flush=True)
    rows, raw, t0 = [], {}, time.monotonic()
    broken = False
    for name in names:
        t1 = time.monotonic()
        try:
            res, rs = CASES[name](ctx)
        except Exception as e:  # a case that cannot be evaluated is reported, the others still run
            res, rs = {"exception": repr(e)}, [row(name, "evaluation", "error", None, note=repr(e)[:160])]
            broken = True
        raw[name] = res
        rows += rs
        if kept is not None:
            kept["fresh"][name] = rs
        for r in rs:
            print(f"  {r['case']:12s} {r['metric']:36s} {r['value_text']:>10s}  {r['goal']:14s} "
                  f"{ {True: 'PASS', False: 'FAIL', None: ''}[r['pass']]:4s}  {r['note']}", flush=True)
        print(f"  ({name}: {time.monotonic() - t1:.0f} s elapsed, load {vc.loadavg():.1f})", flush=True)
        if kept is not None:
            rows, raw = merged_rows(kept), dict(kept["cases"], **raw)
        with open(os.path.join(out, "matrix.json"), "w") as f:
            json.dump({"setup": a.setup, "description": desc, "quick": a.quick, "sensor": sensor, "rows": rows,
                       "cases": raw, "elapsed_s": time.monotonic() - t0}, f, indent=1, default=str)
    md = table(rows)
    with open(os.path.join(out, "matrix.md"), "w") as f:
        f.write(f"Set-up `{a.setup or '(each case its own scene)'}`: {desc}; {'quick' if a.quick else 'full'}\n\n" + md)
    print()
    print(md)
    npass = sum(1 for r in rows if r["pass"] is True)
    nfail = sum(1 for r in rows if r["pass"] is False)
    print(f"{npass} pass, {nfail} fail, {len(rows) - npass - nfail} info rows; {time.monotonic() - t0:.0f} s; "
          f"wrote {os.path.join(out, 'matrix.json')} and matrix.md")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
