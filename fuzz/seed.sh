#!/bin/sh
# Seed corpora of the fuzz targets from the OpenSubdiv corpus shapes in
# tests/data/osd (nothing is committed: corpus/ is generated and ignored).
#   fuzz/seed.sh [CORPUS_DIR]   (default fuzz/corpus)
# `obj` gets each OBJ file as it is; every other target gets each file
# behind the 16-byte parameter header of fuzz/src/lib.rs: all zeros (the
# shape as it is) and three headers from a fixed generator (scaled or
# shifted shapes, other target parameters).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-$here/corpus}
python3 - "$here/../tests/data/osd" "$out" <<'PY'
import os, random, sys
src, out = sys.argv[1], sys.argv[2]
targets = ["topology", "evaluator", "eval", "tessellate", "voxel", "measure",
           "refine", "feature", "ffi"]
rng = random.Random(27)
objs = sorted(f for f in os.listdir(src) if f.endswith(".obj"))
os.makedirs(os.path.join(out, "obj"), exist_ok=True)
for t in targets:
    os.makedirs(os.path.join(out, t), exist_ok=True)
for f in objs:
    text = open(os.path.join(src, f), "rb").read()
    open(os.path.join(out, "obj", f), "wb").write(text)
    for t in targets:
        heads = [bytes(16)] + [bytes([0, 0]) + bytes(rng.randrange(256) for _ in range(14))
                               for _ in range(3)]
        for k, h in enumerate(heads):
            open(os.path.join(out, t, "%s.%d" % (f, k)), "wb").write(h + text)
print("fuzz/seed.sh: %d shapes -> %s" % (len(objs), out))
PY
