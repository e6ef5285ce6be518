"""Engineering set-ups applied to validation cases.

A set-up is the method part of a scene: its `kernel`, `fluid`, `physics`, `boundary`, `integrator` and
`health` blocks (issue 13, point 5: e.g. `pipelines/engineering_2d.json`; any scene file works). A case
owns everything else: geometry (`domain`, `bodies`, `particles.spacing`, `gravity`), `time`, `output`
and `probes`, plus the few keys inside the method blocks that describe the flow rather than the method
(CASE_KEYS: the expected speed of an impact, the physical viscosity of a viscous case, a body force).

apply_setup(case_scene, setup) returns the case scene with the set-up's blocks in place of its own,
the case-owned keys put back, and the wall layers of box, tank and mesh boundary bodies raised to cover the
set-up kernel's support (a pressure wall needs a full support of wall particles; the one-layer
`repulsive` wall does not).
"""
import copy
import json
import math
import os
import sys

SETUP_BLOCKS = ("kernel", "fluid", "physics", "boundary", "integrator", "health")

# keys inside the method blocks that belong to the case's flow, never to the set-up
CASE_KEYS = ("fluid.rho0", "fluid.reference_speed", "fluid.reference_height", "physics.body_force",
             "physics.laminar_viscosity", "physics.gravity_ramp", "physics.damping")

# kernel support radius in units of h (docs/scene.md: kernel.type)
SUPPORT_OVER_H = {"gaussian": 3.0, "wendland_c2": 2.0, "cubic_spline": 2.0, "paper_literal": 1.0}


def die(msg):
    """Bad input: the message on stderr, exit 2 (CONTRACT.md)."""
    print(msg, file=sys.stderr)
    raise SystemExit(2)


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except OSError as e:
        die(f"{path}: cannot read the set-up/scene file: {e.strerror}")
    except json.JSONDecodeError as e:
        die(f"{path}: not valid JSON (line {e.lineno}, column {e.colno}): {e.msg}")


def load_setup(path):
    """The set-up blocks of a scene file (at least one of SETUP_BLOCKS must be present)."""
    d = load_json(path)
    if not isinstance(d, dict):
        die(f"{path}: a set-up must be a JSON object with some of the keys {', '.join(SETUP_BLOCKS)}")
    blocks = {k: d[k] for k in SETUP_BLOCKS if k in d}
    if not blocks:
        die(f"{path}: none of the set-up keys {', '.join(SETUP_BLOCKS)} found")
    for k, v in blocks.items():
        if not isinstance(v, dict):
            die(f"{path}: key '{k}' must be an object, found {type(v).__name__}")
    return blocks


def _get(d, dotted):
    for part in dotted.split("."):
        if not isinstance(d, dict) or part not in d:
            return None, False
        d = d[part]
    return d, True


def _put(d, dotted, value):
    parts = dotted.split(".")
    for part in parts[:-1]:
        d = d.setdefault(part, {})
    d[parts[-1]] = value


def _drop(d, dotted):
    parts = dotted.split(".")
    for part in parts[:-1]:
        if part not in d:
            return
        d = d[part]
    d.pop(parts[-1], None)


def wall_layers(scene):
    """Particle layers a pressure wall (dynamic, dummy) needs for the scene's kernel: ceil(support / dx)."""
    k = scene.get("kernel", {})
    dx = float(scene["particles"]["spacing"])
    h = float(k["h"]) if "h" in k else float(k.get("h_over_dx", 1.2)) * dx
    return max(1, math.ceil(SUPPORT_OVER_H.get(k.get("type", "gaussian"), 3.0) * h / dx - 1e-9))


def apply_setup(case_scene, setup, case_keys=CASE_KEYS):
    """Case scene (dict) with the set-up's blocks; see the module docstring."""
    out = copy.deepcopy(case_scene)
    for block, value in setup.items():
        out[block] = copy.deepcopy(value)
    for key in case_keys:
        v, present = _get(case_scene, key)
        if present:
            _put(out, key, copy.deepcopy(v))
        else:
            _drop(out, key)
    model = out.get("boundary", {}).get("model", "repulsive")
    if model != "repulsive":
        need = wall_layers(out)
        for b in out.get("bodies", []):
            shape = b.get("shape", "mesh" if "mesh" in b else "box")
            if b.get("kind") == "boundary" and shape in ("box", "tank", "mesh") and b.get("layers", 1) < need:
                b["layers"] = need
                if shape == "tank" and "domain" in out:  # a tank's layers grow outwards: keep them in the domain
                    margin = need * float(out["particles"]["spacing"])
                    dom = out["domain"]
                    for a in range(len(b["min"])):
                        dom["min"][a] = min(dom["min"][a], b["min"][a] - margin)
                        dom["max"][a] = max(dom["max"][a], b["max"][a] + margin)
    return out


def scene_with_setup(scene_path, setup_path, out_path):
    """Write scene_path with the blocks of setup_path applied to out_path (mesh paths made absolute)."""
    scene = load_json(scene_path)
    merged = apply_setup(scene, load_setup(setup_path))
    base = os.path.dirname(os.path.abspath(scene_path))
    for b in merged.get("bodies", []):
        if "mesh" in b and not os.path.isabs(b["mesh"]):
            b["mesh"] = os.path.join(base, b["mesh"])
    os.makedirs(os.path.dirname(os.path.abspath(out_path)), exist_ok=True)
    with open(out_path, "w") as f:
        json.dump(merged, f, indent=1)
    return out_path


def describe(setup):
    """One line naming the set-up's main choices (for tables)."""
    k, b, i, p, fl = (setup.get(x, {}) for x in ("kernel", "boundary", "integrator", "physics", "fluid"))
    terms = [t for t in p if t not in ("density",)]
    step = f"dt {i['dt']:g}" if "dt" in i else f"cfl {i.get('cfl', '?')}"
    return (f"{k.get('type', 'gaussian')} h={k.get('h_over_dx', 1.2)}dx, {b.get('model', 'repulsive')} walls, "
            f"c0 {fl.get('c0', 'auto')}x{fl.get('c0_factor', 10) if fl.get('c0', 'auto') == 'auto' else ''}, "
            f"{i.get('type', 'verlet')} {step}, {p.get('density', 'continuity')}"
            + (", " + "+".join(terms) if terms else ""))
