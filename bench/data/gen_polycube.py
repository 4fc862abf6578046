#!/usr/bin/env python3
"""Writes the boundary quads of a polycube (unit cubes on a grid) as OBJ.

usage: gen_polycube.py NX NY NZ HOLES OUT.obj
HOLES: comma-separated x:y columns left empty through all z layers (each
makes a handle). Vertices on the surface only, faces outward (CCW seen from
outside). The surface has vertices of valence 3, 4, 5 and 6. Used for
bench/data/genus2_polycube*.obj (see bench/data/README.md).
"""
import sys

nx, ny, nz = (int(a) for a in sys.argv[1:4])
holes = {tuple(int(c) for c in h.split(':')) for h in sys.argv[4].split(',') if h}
out = sys.argv[5]
full = {(x, y, z) for x in range(nx) for y in range(ny) for z in range(nz)
        if (x, y) not in holes}
# Each cube face whose neighbour is empty, as 4 lattice corners, CCW from
# outside (normal along +axis when s = 1).
quads = []
for (x, y, z) in sorted(full):
    for axis in range(3):
        for s in (-1, 1):
            n = [x, y, z]
            n[axis] += s
            if tuple(n) in full:
                continue
            a, b = (axis + 1) % 3, (axis + 2) % 3
            base = [x, y, z]
            if s == 1:
                base[axis] += 1
            corners = []
            for da, db in ((0, 0), (1, 0), (1, 1), (0, 1)):
                c = list(base)
                c[a] += da
                c[b] += db
                corners.append(tuple(c))
            if s == -1:
                corners.reverse()
            quads.append(corners)
index = {}
for q in quads:
    for c in q:
        index.setdefault(c, len(index) + 1)
with open(out, 'w') as f:
    f.write('# polycube %dx%dx%d, empty columns %s (bench/data/gen_polycube.py)\n'
            % (nx, ny, nz, sys.argv[4]))
    for c, _ in sorted(index.items(), key=lambda kv: kv[1]):
        f.write('v %d %d %d\n' % c)
    for q in quads:
        f.write('f %s\n' % ' '.join(str(index[c]) for c in q))
