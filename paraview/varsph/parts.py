"""Which particles a 3D picture shows how: the `part` array (0 fluid, 1 wall, 2 obstacle or body).

A 3D tank drawn as opaque particles hides the water inside it (issue 35: "one grey cube"). A ParaView user
cuts the container away and keeps what stands in the water. Frames carry `kind` (0 fluid, 1 boundary) and,
since issue 35, `body` (the index of the scene body a particle was built from); which boundary bodies are
the container is decided here from the geometry alone, so that a saved state opens any run:

- a boundary body is a **wall** (part 1) when its bounding box, grown by dx, holds the fluid's bounding box
  (a tank, a cylinder, a sloshing tank: the water is inside it), or when it reaches the outer box of all
  boundary particles on 3 or more of its 6 sides (one slab of a tank built from separate floor and wall
  bodies);
- any other boundary body is an **obstacle** (part 2): a torus under falling water, a block on the floor,
  a floating body;
- without a `body` array (frames of older runs, a scene whose `output.fields` leaves it out) every boundary
  particle is a wall.
Bodies are classified once per run, on its first frame (the fluid's box at the start), so a particle keeps
its part in every frame.
"""
import numpy as np

FLUID, WALL, OBSTACLE = 0, 1, 2


def _box(x):
    return x.min(axis=0), x.max(axis=0)


def classify_bodies(points, kind, body, dx):
    """{body id: WALL or OBSTACLE} for the boundary bodies of one frame (points (N, 3), kind, body (N,))."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    kind = np.asarray(kind).reshape(-1)
    body = np.asarray(body).reshape(-1)
    wall = kind != 0
    if not wall.any():
        return {}
    fluid = points[~wall]
    hull_lo, hull_hi = _box(points[wall])
    tol = 1.0 * dx
    out = {}
    for b in np.unique(body[wall]):
        lo, hi = _box(points[wall & (body == b)])
        holds_fluid = False
        if len(fluid):
            flo, fhi = _box(fluid)
            holds_fluid = bool(np.all(lo - tol <= flo) and np.all(fhi <= hi + tol))
        touching = int(np.sum(np.abs(lo - hull_lo) <= tol) + np.sum(np.abs(hi - hull_hi) <= tol))
        out[int(b)] = WALL if (holds_fluid or touching >= 3) else OBSTACLE
    return out


def part_array(kind, body=None, classes=None):
    """The `part` value of every particle: FLUID for kind 0, else the class of its body (WALL when unknown)."""
    kind = np.asarray(kind).reshape(-1)
    part = np.where(kind == 0, FLUID, WALL).astype(np.int32)
    if body is not None and classes:
        body = np.asarray(body).reshape(-1)
        for b, c in classes.items():
            part[(kind != 0) & (body == b)] = c
    return part
