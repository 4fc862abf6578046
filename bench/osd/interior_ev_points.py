#!/usr/bin/env python3
"""Points next to the interior smooth extraordinary vertices of a mesh with
features (creases, corners, boundaries).

usage: interior_ev_points.py MESH.obj N SEED SCALE > POINTS

The reference class of issue #24's "near-feature cost within 2x of the
interior extraordinary cost" taken on the same mesh: points on quad faces
with a corner of valence != 4 that is neither on a boundary edge nor on a
tagged crease edge nor a tagged corner, whose whole 1-ring (every vertex of
every face sharing a vertex with the face) is free of such features and
made of quads, so that the feature evaluator answers them from its
eigen-projection pieces. Each point is (u, v) uniform in the face, scaled
by SCALE towards one of its extraordinary corners (SCALE 0.25 puts it
within 1/4 of the face size of the vertex, as the near-feature X points of
`ccss bench features --cache-depth 2` lie within the irregular level-2
pieces). Output: "face sub u v X" lines (`bench eval`'s points format,
sub = 0), N of them (fewer if the mesh has no such face), deterministic
for (mesh, N, SEED). Corner k of a quad is at (0,0), (1,0), (1,1), (0,1).
"""
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gen_points import read_obj  # noqa: E402


def read_tags(path):
    """The crease edges (vertex pairs, smaller first) and corner vertices
    of the OBJ's `t crease` / `t corner` tags."""
    creases, corners = set(), set()
    with open(path) as fh:
        for line in fh:
            t = line.split()
            if len(t) > 2 and t[0] == "t":
                counts = [int(x) for x in t[2].split("/")]
                ints = [int(x) for x in t[3 : 3 + counts[0]]]
                if t[1] == "crease":
                    for a, b in zip(ints[0::2], ints[1::2]):
                        creases.add((min(a, b), max(a, b)))
                elif t[1] == "corner":
                    corners.update(ints)
    return creases, corners


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    path, n, seed, scale = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
    _, faces = read_obj(path)
    creases, corners = read_tags(path)
    edge_faces, nbrs, vfaces = {}, {}, {}
    for fi, f in enumerate(faces):
        for i, v in enumerate(f):
            w = f[(i + 1) % len(f)]
            e = (min(v, w), max(v, w))
            edge_faces[e] = edge_faces.get(e, 0) + 1
            nbrs.setdefault(v, set()).add(w)
            nbrs.setdefault(w, set()).add(v)
            vfaces.setdefault(v, []).append(fi)
    feature = set(corners)
    for (a, b), k in edge_faces.items():
        if k != 2 or (a, b) in creases:
            feature.update((a, b))
    picked = []
    for fi, f in enumerate(faces):
        if len(f) != 4:
            continue
        evs = [k for k, v in enumerate(f) if len(nbrs[v]) != 4 and v not in feature]
        if not evs:
            continue
        ring = {g for v in f for g in vfaces[v]}
        if any(len(faces[g]) != 4 or any(w in feature for w in faces[g]) for g in ring):
            continue
        picked.append((fi, evs))
    if not picked:
        return
    rnd = random.Random(seed)
    corner = [(0, 0), (1, 0), (1, 1), (0, 1)]
    for _ in range(n):
        fi, evs = picked[rnd.randrange(len(picked))]
        cu, cv = corner[rnd.choice(evs)]
        u, v = rnd.random() * scale, rnd.random() * scale
        u = u if cu == 0 else 1 - u
        v = v if cv == 0 else 1 - v
        print(fi, 0, repr(u), repr(v), "X")


if __name__ == "__main__":
    main()
