#!/usr/bin/env python3
"""Moves the X points of a gen_points.py file next to an extraordinary corner.

usage: near_ev_points.py MESH.obj POINTS SCALE > OUT

For every X point (quad face with a vertex of valence != 4) one of the
face's extraordinary corners is picked (seeded, deterministic) and the
point's (u, v) is scaled by SCALE towards that corner: SCALE 0.125 puts
every point within 1/8 of the face size of an extraordinary vertex, the
distance at which the near-feature points of `ccss bench features
--cache-depth 2 --write-points` lie from their boundary, crease or dart
vertex. Corner k of a quad is at (0,0), (1,0), (1,1), (0,1) for k = 0..3
(OpenSubdiv's ptex convention, as in osd_eval).
"""
import random
import sys


def main():
    obj, src, scale = sys.argv[1], sys.argv[2], float(sys.argv[3])
    faces = []
    for line in open(obj):
        if line.startswith('f '):
            faces.append([int(t.split('/')[0]) - 1 for t in line.split()[1:]])
    nbrs = {}
    for f in faces:
        for i, v in enumerate(f):
            w = f[(i + 1) % len(f)]
            nbrs.setdefault(v, set()).add(w)
            nbrs.setdefault(w, set()).add(v)
    rnd = random.Random(7)
    corner = [(0, 0), (1, 0), (1, 1), (0, 1)]
    for line in open(src):
        p = line.split()
        if len(p) < 5 or p[4] != 'X':
            continue
        f = int(p[0])
        evs = [i for i, v in enumerate(faces[f]) if len(nbrs[v]) != 4]
        cu, cv = corner[rnd.choice(evs)]
        u, v = float(p[2]) * scale, float(p[3]) * scale
        u = u if cu == 0 else 1 - u
        v = v if cv == 0 else 1 - v
        print(f, 0, repr(u), repr(v), 'X')


if __name__ == '__main__':
    main()
