#!/usr/bin/env python3
"""Generate query points for osd_eval.

usage: gen_points.py MESH.obj N SEED > POINTS.txt

Emits up to N random points per class ("face sub u v class", sub = 0):
  X: quad faces with at least one vertex of valence != 4
  R: quad faces whose 1-ring is regular: the 4 face vertices and every vertex
     of every face incident to them have valence 4, and all those faces are quads
Quad faces in neither class (regular corners but an irregular 1-ring) are skipped.
Deterministic for a given (mesh, N, seed). Classes with no faces emit nothing.
"""
import random
import sys


def read_obj(path):
    nverts = 0
    faces = []
    with open(path) as fh:
        for line in fh:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                nverts += 1
            elif t[0] == "f":
                f = []
                for tok in t[1:]:
                    i = int(tok.split("/")[0])
                    f.append(i - 1 if i > 0 else nverts + i)
                faces.append(f)
    return nverts, faces


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    path, n, seed = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    nverts, faces = read_obj(path)

    edges = set()
    vfaces = [[] for _ in range(nverts)]
    for fi, f in enumerate(faces):
        for k, a in enumerate(f):
            b = f[(k + 1) % len(f)]
            edges.add((min(a, b), max(a, b)))
            vfaces[a].append(fi)
    valence = [0] * nverts
    for a, b in edges:
        valence[a] += 1
        valence[b] += 1

    reg, irr = [], []
    for fi, f in enumerate(faces):
        if len(f) != 4:
            continue
        if any(valence[c] != 4 for c in f):
            irr.append(fi)
            continue
        ring = {g for c in f for g in vfaces[c]}
        if all(len(faces[g]) == 4 and all(valence[w] == 4 for w in faces[g]) for g in ring):
            reg.append(fi)

    rng = random.Random(seed)
    out = sys.stdout
    for cls, pool in (("R", reg), ("X", irr)):
        if not pool:
            print("gen_points: no faces for class %s" % cls, file=sys.stderr)
            continue
        for _ in range(n):
            fi = rng.choice(pool)
            out.write("%d 0 %.17g %.17g %s\n" % (fi, rng.random(), rng.random(), cls))
    print("gen_points: R faces=%d X faces=%d" % (len(reg), len(irr)), file=sys.stderr)


if __name__ == "__main__":
    main()
