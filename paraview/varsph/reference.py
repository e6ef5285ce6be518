"""Reference data beside a run: the dimensionless dam-break front and measured wall-pressure signals.

Dam break (column of width L and height H against a wall, released at t = 0; Martin & Moyce 1952,
Phil. Trans. R. Soc. A 244:312; Koshizuka & Oka 1996, Nucl. Sci. Eng. 123:421):
    T = t sqrt(2 g / L),   Z = (x_front - x_wall) / L,
with x_front the leading edge of the water (the outermost particle centre + dx/2, so that Z(0) = 1) and
n^2 = H / L (the bundled data are for n^2 = 2). Wall pressure (Buchner 2002 as used by Adami et al. 2012):
    T = t sqrt(g / H),   P = p / (rho g H).
Reference files: CSV with '#' comment lines, then a header naming the columns (T,Z / T,P dimensionless,
t,p in s and Pa), then numbers.
"""
import os

import numpy as np

from .io import gravity_of_run

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
DATA_DIRS = [os.path.join(REPO, "tests", "data", "validation"),
             os.path.join(os.path.dirname(REPO), "shared", "validation")]
FRONT_DATA = [("Martin & Moyce 1952, a = 2.25 in", "martin_moyce_n2_2_a2.25in_front_pysph.csv"),
              ("Martin & Moyce 1952, a = 1.125 in", "martin_moyce_n2_2_a1.125in_front_pysph.csv"),
              ("Koshizuka & Oka 1996", "koshizuka_oka_1996_front_exp_pysph.csv")]


def read_columns(path):
    """{column name: array} of a CSV with '#' comment lines and a header. ValueError naming the file and line
    for anything else."""
    if not os.path.isfile(path):
        raise ValueError("%s: file not found" % path)
    head, rows = None, []
    with open(path) as f:
        for k, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            cells = [c.strip() for c in s.split(",")]
            if head is None:
                head = cells
                continue
            try:
                rows.append([float(c) for c in cells])
            except ValueError:
                raise ValueError("%s:%d: expected %d numbers (columns %s), got '%s'" % (path, k, len(head),
                                                                                      ",".join(head), s))
            if len(cells) != len(head):
                raise ValueError("%s:%d: expected %d values (columns %s), got %d" % (path, k, len(head),
                                                                                   ",".join(head), len(cells)))
    if head is None or not rows:
        raise ValueError("%s: expected a header line and at least one row of numbers" % path)
    a = np.asarray(rows, dtype=float)
    return {h: a[:, j] for j, h in enumerate(head)}


def find_data(name):
    for d in DATA_DIRS:
        p = os.path.join(d, name)
        if os.path.isfile(p):
            return p
    return None


def front_references():
    """[(label, T, Z)] of the bundled dam-break front measurements that can be found."""
    out = []
    for label, name in FRONT_DATA:
        p = find_data(name)
        if p:
            c = read_columns(p)
            out.append((label, c["T"], c["Z"]))
    return out


class ColumnGeometry:
    """The initial water column of a dam-break run, from its first frame: width L, height H, the wall
    behind it (x_wall = left edge), the bottom, dx, rho0 and g (|gravity| from run.json, else 9.81)."""

    def __init__(self, frame0, run=None, axis=0, vertical=1):
        fl = frame0.fluid_mask()
        x = frame0.points[fl]
        self.dx = frame0.dx if "dx" in frame0.fields else 0.0
        half = 0.5 * self.dx
        self.x_wall = float(x[:, axis].min() - half)
        self.L = float(x[:, axis].max() + half - self.x_wall)
        self.bottom = float(x[:, vertical].min() - half)
        self.H = float(x[:, vertical].max() + half - self.bottom)
        self.rho0 = float(frame0.fields.get("rho0", 1000.0))
        g = gravity_of_run(run) if run else None
        self.g = float(np.linalg.norm(g)) if g is not None and np.linalg.norm(g) > 0 else 9.81

    @property
    def n2(self):
        return self.H / self.L

    def front(self, t, front_x):
        """(T, Z) of front positions (outermost particle centres) at times t."""
        t = np.asarray(t, dtype=float)
        z = (np.asarray(front_x, dtype=float) + 0.5 * self.dx - self.x_wall) / self.L
        return t * np.sqrt(2.0 * self.g / self.L), z


def parse_reference_probe(spec):
    """'NAME=FILE[:H=..][:rho=..][:g=..][:label=..]' -> (NAME, FILE, {key: value})."""
    if "=" not in spec:
        raise ValueError("--reference-probe %s: expected NAME=FILE.csv[:H=...][:rho=...][:g=...][:label=...]" % spec)
    name, rest = spec.split("=", 1)
    parts = rest.split(":")
    opts = {}
    for p in parts[1:]:
        if "=" not in p:
            raise ValueError("--reference-probe %s: option '%s' is not KEY=VALUE (H, rho, g, label)" % (spec, p))
        k, v = p.split("=", 1)
        if k not in ("H", "rho", "g", "label"):
            raise ValueError("--reference-probe %s: unknown option '%s' (H, rho, g, label)" % (spec, k))
        opts[k] = v if k == "label" else float(v)
    if not name.strip() or not parts[0]:
        raise ValueError("--reference-probe %s: expected NAME=FILE.csv" % spec)
    return name.strip(), parts[0], opts


def load_reference_probe(path):
    """('dimensionless', T, P) for T,P columns, ('SI', t, p) for t,p columns (s, Pa); sorted by time (digitised
    signals can be out of order)."""
    c = read_columns(path)
    if "T" in c and "P" in c:
        kind, x, y = "dimensionless", c["T"], c["P"]
    elif "t" in c and "p" in c:
        kind, x, y = "SI", c["t"], c["p"]
    else:
        raise ValueError("%s: expected columns T,P (dimensionless: T = t sqrt(g/H), P = p/(rho g H)) or t,p "
                         "(s, Pa); the header is %s" % (path, ",".join(c)))
    order = np.argsort(x, kind="stable")
    return kind, x[order], y[order]
