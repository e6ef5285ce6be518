"""What a run directory says about itself: the resolved scene of run.json, its probes.csv and
diagnostics.csv as columns, and the scene keys in which two runs differ."""
import csv
import json
import os

import numpy as np


def run_dir(run):
    return run if os.path.isdir(run) else os.path.dirname(os.path.abspath(run))


def scene_of(run):
    """The resolved scene (run.json 'scene'), {} when there is none."""
    path = os.path.join(run_dir(run), "run.json")
    try:
        with open(path) as f:
            doc = json.load(f)
    except (OSError, ValueError):
        return {}
    return doc.get("scene", {}) if isinstance(doc, dict) else {}


def flatten(x, prefix=""):
    """{dotted key: value} of nested dicts and lists (list items by index, as `--set` names them)."""
    out = {}
    if isinstance(x, dict):
        for k, v in x.items():
            out.update(flatten(v, "%s.%s" % (prefix, k) if prefix else str(k)))
    elif isinstance(x, list) and any(isinstance(v, (dict, list)) for v in x):
        for k, v in enumerate(x):
            out.update(flatten(v, "%s.%d" % (prefix, k)))
    else:
        out[prefix] = x
    return out


def scene_diff(run_a, run_b, ignore=("name", "description")):
    """[(key, value in A, value in B)] of the resolved scene keys that differ (missing = None)."""
    a, b = flatten(scene_of(run_a)), flatten(scene_of(run_b))
    keys = sorted(set(a) | set(b))
    return [(k, a.get(k), b.get(k)) for k in keys if a.get(k) != b.get(k) and k not in ignore]


def read_table(path):
    """(header, {column: float array}) of a CSV with a header; empty cells are NaN. ([], {}) if absent."""
    if not os.path.isfile(path):
        return [], {}
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return [], {}
    head = [h.strip() for h in rows[0]]
    cols = {h: [] for h in head}
    for r in rows[1:]:
        if not r:
            continue
        for h, v in zip(head, r):
            try:
                cols[h].append(float(v))
            except ValueError:
                cols[h].append(float("nan"))
    return head, {h: np.asarray(v) for h, v in cols.items()}


def probes(run):
    return read_table(os.path.join(run_dir(run), "probes.csv"))


def diagnostics(run):
    return read_table(os.path.join(run_dir(run), "diagnostics.csv"))


PROBE_GROUPS = [  # (file suffix, title, unit, column prefixes) of the probe types of docs/results.md
    ("pressure", "pressure probes", "pressure [Pa]", ("p_",)),
    ("water_height", "water height gauges", "water height [m]", ("h_",)),
    ("front", "surge front", "front x [m]", ("front_x",)),
    ("force", "forces on bodies", "force [N] / moment [N m]", ("F", "M")),
]


def probe_groups(head):
    """[(suffix, title, unit, [columns])] of the probes.csv columns, by probe type."""
    out, used = [], set()
    for suffix, title, unit, prefixes in PROBE_GROUPS:
        cols = [h for h in head if h != "time" and h not in used and h.startswith(prefixes)]
        used.update(cols)
        if cols:
            out.append((suffix, title, unit, cols))
    rest = [h for h in head if h != "time" and h not in used]
    if rest:
        out.append(("other", "other probes", "value", rest))
    return out
