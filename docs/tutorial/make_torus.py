"""Writes torus.obj: the tutorial's "own mesh", as a CAD program would export it (millimetres, axis along z,
centred on the origin): major radius 80 mm, tube radius 30 mm, 48 x 16 quads split into triangles, faces
outward. Usage: python3 make_torus.py [OUT.obj]"""
import math
import sys

R, r, n_major, n_minor = 80.0, 30.0, 48, 16
out = sys.argv[1] if len(sys.argv) > 1 else "torus.obj"
with open(out, "w") as f:
    f.write("# torus, millimetres: major radius %g, tube radius %g (docs/tutorial/make_torus.py)\n" % (R, r))
    for i in range(n_major):
        u = 2 * math.pi * i / n_major
        for j in range(n_minor):
            v = 2 * math.pi * j / n_minor
            f.write("v %.6f %.6f %.6f\n" % ((R + r * math.cos(v)) * math.cos(u), (R + r * math.cos(v)) * math.sin(u),
                                           r * math.sin(v)))
    for i in range(n_major):
        for j in range(n_minor):
            a = i * n_minor + j + 1
            b = ((i + 1) % n_major) * n_minor + j + 1
            c = ((i + 1) % n_major) * n_minor + (j + 1) % n_minor + 1
            d = i * n_minor + (j + 1) % n_minor + 1
            f.write("f %d %d %d\nf %d %d %d\n" % (a, b, c, a, c, d))
print("wrote", out)
