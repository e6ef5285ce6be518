#!/usr/bin/env python3
"""Seeds the fuzzing corpora from the repository's own files (docs/reliability.md).

  /usr/bin/python3 fuzz/make_corpus.py OUT_DIR [--varsph build/release/bin/varsph]

OUT_DIR/<target>/ for target in scene, stl, obj, off, ply, poly2d, checkpoint:
  scene       every scene of pipelines/ (and pipelines/*/), plus copies with --set overrides appended
  off         geometry/meshes/*.off as they are
  stl/obj/ply the same meshes converted (ASCII and binary STL, OBJ, ASCII and binary PLY)
  poly2d      geometry/meshes/*.poly2d and a closed square with a hole
  checkpoint  checkpoints written by `varsph run` of a 9-particle scene (needs --varsph)
"""
import argparse, glob, json, os, struct, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read_off(path):
    toks = []
    for line in open(path):
        line = line.split("#")[0]
        toks += line.split()
    assert toks[0] == "OFF"
    nv, nf = int(toks[1]), int(toks[2])
    k = 4
    V = []
    for _ in range(nv):
        V.append(tuple(float(t) for t in toks[k:k + 3]))
        k += 3
    F = []
    for _ in range(nf):
        n = int(toks[k])
        F.append(tuple(int(t) for t in toks[k + 1:k + 1 + n]))
        k += 1 + n
    return V, F


def tris(F):
    for f in F:
        for i in range(1, len(f) - 1):
            yield (f[0], f[i], f[i + 1])


def write_meshes(out, name, V, F):
    T = list(tris(F))
    with open(os.path.join(out, "stl", name + "_ascii.stl"), "w") as f:
        f.write("solid %s\n" % name)
        for t in T:
            f.write(" facet normal 0 0 0\n  outer loop\n")
            for i in t:
                f.write("   vertex %r %r %r\n" % V[i])
            f.write("  endloop\n endfacet\n")
        f.write("endsolid %s\n" % name)
    with open(os.path.join(out, "stl", name + "_binary.stl"), "wb") as f:
        f.write(b"binary " + name.encode()[:70] + b"\0" * (73 - min(70, len(name))))
        f.write(struct.pack("<I", len(T)))
        for t in T:
            f.write(struct.pack("<3f", 0, 0, 0))
            for i in t:
                f.write(struct.pack("<3f", *V[i]))
            f.write(b"\0\0")
    with open(os.path.join(out, "obj", name + ".obj"), "w") as f:
        f.write("# %s\n" % name)
        for v in V:
            f.write("v %r %r %r\n" % v)
        for p in F:
            f.write("f " + " ".join(str(i + 1) for i in p) + "\n")
    head = "ply\nformat %s 1.0\nelement vertex %d\nproperty double x\nproperty double y\nproperty double z\n" \
           "element face %d\nproperty list uchar int vertex_indices\nend_header\n"
    with open(os.path.join(out, "ply", name + "_ascii.ply"), "w") as f:
        f.write(head % ("ascii", len(V), len(F)))
        for v in V:
            f.write("%r %r %r\n" % v)
        for p in F:
            f.write("%d %s\n" % (len(p), " ".join(map(str, p))))
    with open(os.path.join(out, "ply", name + "_binary.ply"), "wb") as f:
        f.write((head % ("binary_little_endian", len(V), len(F))).encode())
        for v in V:
            f.write(struct.pack("<3d", *v))
        for p in F:
            f.write(struct.pack("<B", len(p)) + struct.pack("<%di" % len(p), *p))


def scenes(out):
    files = sorted(glob.glob(os.path.join(ROOT, "pipelines", "*.json")) +
                   glob.glob(os.path.join(ROOT, "pipelines", "*", "*.json")))
    for k, p in enumerate(files):
        text = open(p).read()
        base = os.path.basename(p)
        open(os.path.join(out, "scene", base), "w").write(text)
        # the same with overrides (the harness reads them after a line "#--set")
        sets = ["integrator.cfl=0.2", "integrator.dt=null", 'kernel.type="wendland_c2"', "bodies.0.velocity=[1,0]",
                "time.end=0.001", "particles.max_count=1e3", "gravity=[0,-1e30]"]
        open(os.path.join(out, "scene", "set_" + base), "w").write(
            text.rstrip("\n") + "\n#--set\n" + "\n".join(sets[k % len(sets):] + sets[:1]) + "\n")


def checkpoints(out, varsph):
    scene = {"name": "seed", "setup": "paper", "dimension": 2, "domain": {"min": [-0.1, -0.1], "max": [0.2, 0.2]},
             "particles": {"spacing": 0.02}, "fluid": {"rho0": 1000.0, "c0": 10.0}, "gravity": [0.0, -9.81],
             "bodies": [{"kind": "fluid", "shape": "box", "min": [0.0, 0.0], "max": [0.06, 0.06]},
                        {"kind": "boundary", "shape": "points", "points": [[0.0, -0.02], [0.04, -0.02]]}],
             "integrator": {"type": "verlet", "dt": 1e-4}, "time": {"end": 2e-4},
             "output": {"every": 1e-4}, "checkpoint": {"every_steps": 1}}
    with tempfile.TemporaryDirectory() as tmp:
        p = os.path.join(tmp, "seed.json")
        json.dump(scene, open(p, "w"))
        subprocess.run([varsph, "run", p, "-o", os.path.join(tmp, "run"), "--quiet"], check=True)
        for c in sorted(glob.glob(os.path.join(tmp, "run", "checkpoints", "*.h5"))):
            data = open(c, "rb").read()
            open(os.path.join(out, "checkpoint", os.path.basename(c)), "wb").write(data)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--varsph", help="varsph binary, for the checkpoint seeds")
    a = ap.parse_args()
    for t in ("scene", "stl", "obj", "off", "ply", "poly2d", "checkpoint"):
        os.makedirs(os.path.join(a.out, t), exist_ok=True)
    scenes(a.out)
    for p in sorted(glob.glob(os.path.join(ROOT, "geometry", "meshes", "*.off"))):
        name = os.path.splitext(os.path.basename(p))[0]
        open(os.path.join(a.out, "off", name + ".off"), "w").write(open(p).read())
        write_meshes(a.out, name, *read_off(p))
    for p in sorted(glob.glob(os.path.join(ROOT, "geometry", "meshes", "*.poly2d"))):
        open(os.path.join(a.out, "poly2d", os.path.basename(p)), "w").write(open(p).read())
    open(os.path.join(a.out, "poly2d", "square_hole.poly2d"), "w").write(
        "# closed square with a square hole\n0 0\n1 0\n1 1\n0 1\n\n0.25 0.25\n0.25 0.75\n0.75 0.75\n0.75 0.25\n")
    if a.varsph:
        checkpoints(a.out, a.varsph)
    n = sum(len(os.listdir(os.path.join(a.out, t))) for t in os.listdir(a.out))
    print("make_corpus: %d seed files in %s" % (n, a.out))


if __name__ == "__main__":
    sys.exit(main())
