#!/usr/bin/env python3
"""Checks of pipelines/validation/vsetup.py, the merge of an engineering set-up into a validation case (no solver
run; CTest `validation_vsetup`, fast tier, well under a second):
  * the set-up's method blocks replace the case's, the case keeps its geometry, probes and flow keys;
  * a flow key the set-up names but the case does not is dropped (a set-up cannot give a case a body force);
  * box, tank and mesh walls get ceil(support / dx) layers for a pressure wall, never fewer than they had, and
    keep theirs for the repulsive wall;
  * bad set-up files stop with exit 2 and a message naming the file and the key;
  * setup_matrix.py --compare (metric rows, then wall s and load per case) and --update (re-run cases replace
    their rows, the others keep theirs; without an earlier matrix.json exit 2).
"""
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
VDIR = os.path.join(HERE, "..", "..", "pipelines", "validation")
sys.path.insert(0, VDIR)
import vsetup  # noqa: E402

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


case = {
    "name": "c", "dimension": 2, "particles": {"spacing": 0.01},
    "kernel": {"type": "gaussian", "h_over_dx": 1.2},
    "fluid": {"rho0": 1.0, "c0": 10.0, "reference_speed": 2.0},
    "physics": {"density": "continuity", "laminar_viscosity": {"nu": 0.1}, "body_force": [0.8, 0.0]},
    "boundary": {"model": "repulsive"}, "integrator": {"type": "verlet", "cfl": 0.2},
    "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0], "max": [1, 1]},
               {"kind": "boundary", "shape": "tank", "min": [0, 0], "max": [1, 1], "layers": 1},
               {"kind": "boundary", "mesh": "x.off", "layers": 5}],
    "probes": [{"type": "pressure", "name": "p", "point": [0.5, 0.5]}], "time": {"end": 1.0},
}
setup = {"kernel": {"type": "wendland_c2", "h_over_dx": 1.5}, "fluid": {"rho0": 1000.0, "c0": "auto", "c0_factor": 12},
         "physics": {"density": "continuity", "artificial_viscosity": {"alpha": 0.02}, "damping": {"mu": 1.0}},
         "boundary": {"model": "dynamic"}, "integrator": {"type": "verlet_dsph", "cfl": 0.2},
         "health": {"max_density_error": 0.4}}

m = vsetup.apply_setup(case, setup)
check(m["kernel"] == setup["kernel"] and m["boundary"] == setup["boundary"] and m["health"] == setup["health"],
      "set-up blocks replace the case's")
check(m["integrator"] == setup["integrator"], "integrator from the set-up")
check(m["fluid"] == {"rho0": 1.0, "c0": "auto", "c0_factor": 12, "reference_speed": 2.0},
      f"fluid: set-up's c0 rule with the case's rho0 and reference speed, got {m['fluid']}")
check(m["physics"].get("laminar_viscosity") == {"nu": 0.1} and m["physics"].get("body_force") == [0.8, 0.0],
      "the case's physical viscosity and body force are kept")
check("artificial_viscosity" in m["physics"], "the set-up's terms are used")
check("damping" not in m["physics"], "a flow key only the set-up names (damping) is dropped")
check(m["bodies"][1]["layers"] == 3, f"Wendland 1.5 dx needs 3 wall layers, got {m['bodies'][1]['layers']}")
check(m["bodies"][2]["layers"] == 5, "a wall never loses layers")
check(m["probes"] == case["probes"] and m["time"] == case["time"], "probes and time stay the case's")
check(case["kernel"]["type"] == "gaussian", "the case dict is not modified")
rep = vsetup.apply_setup(case, dict(setup, boundary={"model": "repulsive"}))
check(rep["bodies"][1]["layers"] == 1, "repulsive walls keep their layers")
g = vsetup.apply_setup(case, {"kernel": {"type": "gaussian", "h_over_dx": 1.2}, "boundary": {"model": "dummy_adami"}})
check(g["bodies"][1]["layers"] == 4, "Gaussian 1.2 dx (3h = 3.6 dx) needs 4 layers")
boxed = dict(case, domain={"min": [-0.02, -0.02], "max": [1.02, 1.5]})
gd = vsetup.apply_setup(boxed, {"kernel": {"type": "gaussian", "h_over_dx": 1.2}, "boundary": {"model": "dummy_adami"}})
check(gd["domain"] == {"min": [-0.04, -0.04], "max": [1.04, 1.5]},
      f"the domain grows to hold the tank's 4 outer layers (and never shrinks), got {gd['domain']}")
check(boxed["domain"]["min"] == [-0.02, -0.02], "the case's domain is not modified")

with tempfile.TemporaryDirectory() as d:
    for body, expect in (('{"kernel": 3}', "key 'kernel' must be an object"), ("{oops", "not valid JSON"),
                         ('{"name": "x"}', "none of the set-up keys"), (None, "cannot read")):
        path = os.path.join(d, "s.json") if body is not None else os.path.join(d, "missing.json")
        if body is not None:
            with open(path, "w") as f:
                f.write(body)
        p = subprocess.run([sys.executable, os.path.join(VDIR, "setup_matrix.py"), "--setup", path, "--quick",
                            "-o", os.path.join(d, "out")], capture_output=True, text=True, timeout=60)
        check(p.returncode == 2 and expect in p.stderr and path in p.stderr,
              f"bad set-up {body!r}: exit {p.returncode}, stderr {p.stderr.strip()!r}")
        check(not os.path.exists(os.path.join(d, "out")), "nothing written for a bad set-up")
    good = os.path.join(d, "good.json")
    with open(good, "w") as f:
        json.dump(setup, f)
    p = subprocess.run([sys.executable, os.path.join(VDIR, "setup_matrix.py"), "--setup", good, "--cases", "nope"],
                       capture_output=True, text=True, timeout=60)
    check(p.returncode == 2 and "unknown case" in p.stderr, f"unknown case: exit {p.returncode}")
    # --update without an earlier result: exit 2 naming the file, nothing run
    p = subprocess.run([sys.executable, os.path.join(VDIR, "setup_matrix.py"), "--setup", good, "--cases", "poiseuille",
                        "--update", "-o", os.path.join(d, "none")], capture_output=True, text=True, timeout=60)
    check(p.returncode == 2 and "matrix.json" in p.stderr and "--update" in p.stderr,
          f"--update without matrix.json: exit {p.returncode}, stderr {p.stderr.strip()!r}")
    check(not os.path.exists(os.path.join(d, "none")), "nothing written for --update without a result")
    # --compare: one column per set-up, then each case's solver wall time and load
    for name, val, wall in (("s1", 0.5, 12.0), ("s2", 0.7, None)):
        os.makedirs(os.path.join(d, name))
        rows = [{"case": "hydrostatic", "metric": "m", "value": val, "value_text": f"{val}", "goal": "<= 0.6",
                 "pass": val <= 0.6, "wall": wall, "load": 3.0}]
        with open(os.path.join(d, name, "matrix.json"), "w") as f:
            json.dump({"setup": name, "description": "d", "rows": rows}, f)
    p = subprocess.run([sys.executable, os.path.join(VDIR, "setup_matrix.py"), "--compare", os.path.join(d, "s1"),
                        os.path.join(d, "s2")], capture_output=True, text=True, timeout=60)
    check(p.returncode == 0 and "| hydrostatic | m | <= 0.6 | 0.5 ok | 0.7 **x** |" in p.stdout
          and "| hydrostatic | solver wall s (load) |  | 12 (3.0) |  |" in p.stdout, f"--compare table: {p.stdout!r}")

# --update keeps the other cases' rows in their places and replaces the re-run case's
import setup_matrix  # noqa: E402
kept = {"order": ["a", "b", "c"], "old": [{"case": "a", "v": 1}, {"case": "b", "v": 2}, {"case": "b", "v": 3},
                                          {"case": "c", "v": 4}], "fresh": {"b": [{"case": "b", "v": 9}]}, "cases": {}}
check(setup_matrix.merged_rows(kept) == [{"case": "a", "v": 1}, {"case": "b", "v": 9}, {"case": "c", "v": 4}],
      f"--update merge: {setup_matrix.merged_rows(kept)}")

if failures:
    print("FAIL:\n  " + "\n  ".join(failures))
    sys.exit(1)
print("OK: vsetup merges set-ups as documented")
