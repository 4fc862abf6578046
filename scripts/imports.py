#!/usr/bin/env python3
"""The import picture of ccss-core: module edges, upward edges, circles.

usage: scripts/imports.py [CORE_SRC]   (default: core/src next to this script)
       scripts/imports.py --edges      (also list every edge)

An edge A -> B is one `crate::`/`super::`/`self::` path in A's code (use
trees expanded, comments and `#[cfg(test)]` modules left out) that resolves
to module B; paths to items a module re-exports (`pub use`) are followed to
the defining module, so `crate::Evaluator` is an edge to the evaluator, and
only items *defined* in `lib.rs` (e.g. `MAX_VALENCE` of the old layout,
included from build.rs) count as edges to the crate root. A module's own
`pub use` lines are re-exports, not edges.

Layers, bottom to top (a module's layer is that of its first path
component; the old flat names are mapped too, so the script reads both the
old and the new tree):

  0 error, config          crate-wide error type and build-time constants
  1 mem (old: arena)       caller memory
  2 math (old: bspline, linalg, simd)
  3 mesh (old: topology, refine, stencil, weights)
  4 eigen (old: tables, corner_fit)
  5 eval (old: evaluator)
  6 bounds (old: cellbound, depth)
  7 tessellate, voxel, unified, interpolate   (siblings: none may import another)
  8 query                  certified queries over the cells of layer 7
  9 boolean                Booleans of two solids over their tessellations
 10 lib.rs                 declares modules and re-exports, nothing below imports it

Also reported: paths that reach an item through the crate root's
re-exports (`crate::Error` instead of `crate::error::Error`), which lower
modules should not use.

Reported: upward edges (to a higher layer, or sideways between two of the
layer-7 siblings), edges between different folders of one layer 0-6 are
fine; circles as strongly connected components of the module graph (file
level, inside folders too) and of the folder graph (first path component).
Exit status 1 when there is an upward edge or a circle.
"""
import os
import re
import sys

LAYER = {
    "error": 0, "config": 0,
    "mem": 1, "arena": 1,
    "math": 2, "bspline": 2, "linalg": 2, "simd": 2,
    "mesh": 3, "topology": 3, "refine": 3, "stencil": 3, "weights": 3,
    "eigen": 4, "tables": 4, "corner_fit": 4,
    "eval": 5, "evaluator": 5,
    "bounds": 6, "cellbound": 6, "depth": 6,
    "tessellate": 7, "voxel": 7, "unified": 7, "interpolate": 7,
    "query": 8,
    "boolean": 9,
}
ROOT_LAYER = 10


def strip(text):
    """Code without comments, string literals or `#[cfg(test)]` modules."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    i += 1
        elif c == '"':
            i += 1
            while i < n and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
            i += 1
            out.append('""')
        elif c == "'" and re.match(r"'(\\.|[^\\'])'", text[i:i + 4]):
            m = re.match(r"'(\\.|[^\\'])'", text[i:i + 4])
            i += len(m.group(0))
            out.append("' '")
        else:
            out.append(c)
            i += 1
    code = "".join(out)
    m = re.search(r"#\[cfg\(test\)\]\s*(pub(\([^)]*\))?\s+)?mod\s+\w+\s*\{", code)
    if m:
        code = code[:m.start()]
    return code


def expand(tree):
    """`a::{b, c::{d, e}}` -> ['a::b', 'a::c::d', 'a::c::e']."""
    tree = re.sub(r"\s+", "", tree)
    depth, top, cur = 0, [], ""
    for ch in tree:
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        if ch == "," and depth == 0:
            top.append(cur)
            cur = ""
        else:
            cur += ch
    if cur:
        top.append(cur)
    paths = []
    for t in top:
        b = t.find("{")
        if b < 0:
            paths.append(re.sub(r"as\w+$", "", t))
        else:
            prefix = t[:b]
            for sub in expand(t[b + 1:-1]):
                paths.append(prefix + sub if sub != "self" else prefix.rstrip(":"))
    return paths


def module_of(rel):
    rel = rel[:-3]
    if rel == "lib":
        return ()
    parts = rel.split("/")
    if parts[-1] == "mod":
        parts = parts[:-1]
    return tuple(parts)


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    show_edges = "--edges" in sys.argv
    src = args[0] if args else os.path.join(os.path.dirname(__file__), "..", "core", "src")
    mods, code = {}, {}
    for dirpath, _, files in os.walk(src):
        for f in files:
            if f.endswith(".rs"):
                rel = os.path.relpath(os.path.join(dirpath, f), src).replace(os.sep, "/")
                m = module_of(rel)
                mods[m] = rel
                with open(os.path.join(dirpath, f), encoding="utf-8") as fh:
                    code[m] = strip(fh.read())

    use_re = re.compile(r"\b(pub(\([^)]*\))?\s+)?use\s+([^;]+);")
    reexports = {m: {} for m in mods}
    uses = {m: [] for m in mods}
    for m, c in code.items():
        for u in use_re.finditer(c):
            for p in expand(u.group(3)):
                if u.group(1):
                    name = p.split("::")[-1]
                    alias = re.search(r"as(\w+)$", re.sub(r"\s+", "", u.group(3)))
                    reexports[m][name] = p
                else:
                    uses[m].append(p)
        # inline paths outside `use` statements
        rest = use_re.sub(" ", c)
        for p in re.finditer(r"\b(crate|super|self)((::\w+)+)", rest):
            uses[m].append(p.group(0))

    def absolute(m, p, in_mod_rs):
        parts = p.split("::")
        if parts[0] == "crate":
            return tuple(parts[1:])
        base = list(m)
        # in a file `a/b.rs` (module a::b) `super` is `a`; `self` is `a::b`
        while parts and parts[0] in ("super", "self"):
            if parts[0] == "super":
                base = base[:-1]
            parts = parts[1:]
        return tuple(base) + tuple(parts)

    def resolve(path, hops=0):
        """Defining module of `path` (a tuple of names)."""
        best = ()
        for k in range(len(path), 0, -1):
            if path[:k] in mods:
                best = path[:k]
                break
        rest = path[len(best):]
        if rest and hops < 8 and rest[0] in reexports.get(best, {}):
            target = reexports[best][rest[0]]
            return resolve(absolute(best, target, True) + rest[1:], hops + 1)
        if not best and rest and rest[0] not in ("glam", "core", "libm", "heapless"):
            return ()
        return best

    edges = {}
    via_root = []
    for m, ps in uses.items():
        for p in ps:
            if not (p.startswith("crate") or p.startswith("super") or p.startswith("self")):
                continue
            a = absolute(m, p, mods[m].endswith("mod.rs"))
            if m and a and a[:1] not in mods and a[0] in reexports[()]:
                via_root.append((m, p))
            t = resolve(a)
            if t == m:
                continue
            # a module's own descendants are its business (mod.rs using its files)
            edges.setdefault((m, t), 0)
            edges[(m, t)] += 1

    def name(m):
        return "::".join(m) if m else "lib"

    def layer(m):
        return LAYER.get(m[0], None) if m else ROOT_LAYER

    upward = []
    for (a, b) in sorted(edges):
        la, lb = layer(a), layer(b)
        if la is None or lb is None:
            print(f"warning: no layer for {name(a)} or {name(b)}", file=sys.stderr)
            continue
        if lb > la or (la == lb == 7 and a[0] != b[0]):
            upward.append((a, b))

    def sccs(nodes, adj):
        index, low, on, stack, out, counter = {}, {}, set(), [], [], [0]
        for v in nodes:
            if v in index:
                continue
            work = [(v, iter(adj.get(v, ())))]
            index[v] = low[v] = counter[0]
            counter[0] += 1
            stack.append(v)
            on.add(v)
            while work:
                node, it = work[-1]
                nxt = next(it, None)
                if nxt is not None:
                    if nxt not in index:
                        index[nxt] = low[nxt] = counter[0]
                        counter[0] += 1
                        stack.append(nxt)
                        on.add(nxt)
                        work.append((nxt, iter(adj.get(nxt, ()))))
                    elif nxt in on:
                        low[node] = min(low[node], index[nxt])
                else:
                    work.pop()
                    if work:
                        low[work[-1][0]] = min(low[work[-1][0]], low[node])
                    if low[node] == index[node]:
                        comp = []
                        while True:
                            w = stack.pop()
                            on.discard(w)
                            comp.append(w)
                            if w == node:
                                break
                        if len(comp) > 1:
                            out.append(sorted(comp))
        return out

    adj = {}
    for (a, b) in edges:
        adj.setdefault(a, set()).add(b)
    file_cycles = sccs(sorted(mods), {k: sorted(v) for k, v in adj.items()})
    fadj = {}
    for (a, b) in edges:
        fa, fb = (a[:1] or ("lib",)), (b[:1] or ("lib",))
        if fa != fb:
            fadj.setdefault(fa, set()).add(fb)
    folders = sorted({(m[:1] or ("lib",)) for m in mods})
    folder_cycles = sccs(folders, {k: sorted(v) for k, v in fadj.items()})

    if show_edges:
        print("edges (from -> to: references):")
        for (a, b), k in sorted(edges.items()):
            print(f"  {name(a)} -> {name(b)}: {k}")
    print(f"modules: {len(mods)}  edges: {len(edges)}")
    print(f"upward edges: {len(upward)}")
    for a, b in upward:
        print(f"  {name(a)} (layer {layer(a)}) -> {name(b)} (layer {layer(b)})")
    print(f"imports through the crate root's re-exports: {len(via_root)}")
    for m, p in via_root:
        print(f"  {name(m)}: {p}")
    print(f"circles between files: {len(file_cycles)}")
    for c in file_cycles:
        print("  " + " <-> ".join(name(m) for m in c))
    print(f"circles between folders/top-level modules: {len(folder_cycles)}")
    for c in folder_cycles:
        print("  " + " <-> ".join(name(m) for m in c))
    return 1 if upward or via_root or file_cycles or folder_cycles else 0


if __name__ == "__main__":
    sys.exit(main())
