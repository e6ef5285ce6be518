"""Open boundaries in the pictures (issue 32, docs/open_boundaries.md): which particles are inflow and
outflow buffer particles, and the zones' boxes.

Frames of a scene with inlets and outlets carry the point array `open_zone` (Int32: the index of the zone a
buffer particle belongs to in the scene's `open_boundaries` list, -1 for the fluid). Whether zone k is an
inlet or an outlet is in the resolved scene of run.json. `open_kind` is what the pictures colour by:
0 not a buffer particle (fluid, walls), 1 inlet buffer, 2 outlet buffer.
"""
import numpy as np

from .runmeta import scene_of

NONE, INLET, OUTLET = 0, 1, 2


def zones(run):
    """[{name, kind, min, max, direction}] of the run's open boundaries (run.json), [] without any."""
    out = []
    for z in scene_of(run).get("open_boundaries", []) or []:
        if isinstance(z, dict) and z.get("kind") in ("inlet", "outlet"):
            out.append({"name": str(z.get("name", "")), "kind": z["kind"], "min": list(z.get("min", [])),
                        "max": list(z.get("max", [])), "direction": list(z.get("direction", []))})
        else:
            out.append({"name": "", "kind": "", "min": [], "max": [], "direction": []})
    return out


def open_kind_array(open_zone, zone_list):
    """`open_kind` (int32) of the particles from their `open_zone` and the run's zones: 1 for a particle of an
    inlet, 2 of an outlet, 0 otherwise (-1, or a zone index the scene does not list)."""
    oz = np.asarray(open_zone).reshape(-1).astype(np.int64)
    table = np.array([INLET if z["kind"] == "inlet" else OUTLET if z["kind"] == "outlet" else NONE
                      for z in zone_list] + [NONE], dtype=np.int32)   # the last entry: every index not listed
    idx = np.where((oz >= 0) & (oz < len(zone_list)), oz, len(zone_list))
    return table[idx]
