// osd_eval: benchmark / oracle harness for OpenSubdiv 3.5 (Far) patch evaluation.
//
// Usage: osd_eval MESH.obj POINTS.txt [--dump OUT.txt] [--repeat R] [--check] [--level L] [--tags]
//                 [--second]
// --second times position, first and second derivatives (EvaluateBasis with
// all six weight arrays) instead of position and first derivatives.
// --tags honours the OBJ's OpenSubdiv tags (creases, corners, holes, boundary,
// creasing and triangle options) and appends to each --dump line a 1 where
// the point lies on a regular (B-spline, exact) patch, 0 on an end cap.
//
//   MESH.obj    closed polygon mesh; only "v x y z" and "f a b c ..." lines are read
//   POINTS.txt  one query per line: "face sub u v class" (class: one capital letter;
//               R and X are always reported, other letters in order of appearance)
//
// See README.md in this directory for the decisions taken.

#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <opensubdiv/version.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#if OPENSUBDIV_VERSION_NUMBER < 30400
#error "osd_eval needs OpenSubdiv >= 3.4 (double-precision EvaluateBasis / stencils)"
#endif

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

namespace {

[[noreturn]] void die(const std::string &msg) {
    std::fprintf(stderr, "osd_eval: error: %s\n", msg.c_str());
    std::exit(1);
}

// ---------------------------------------------------------------------------
// Primvar type usable by PrimvarRefinerReal<double> and StencilTableReal<double>
struct Vtx {
    double p[3];
    void Clear(void * = nullptr) { p[0] = p[1] = p[2] = 0.0; }
    void AddWithWeight(Vtx const &s, double w) {
        p[0] += w * s.p[0];
        p[1] += w * s.p[1];
        p[2] += w * s.p[2];
    }
};

// ---------------------------------------------------------------------------
// Minimal OBJ reader
struct Mesh {
    std::vector<Vtx> verts;
    std::vector<int> faceSizes;   // vertices per face
    std::vector<int> faceVerts;   // concatenated 0-based vertex indices
    std::vector<int> faceOffsets; // start of each face in faceVerts
    // OpenSubdiv tags (`t` lines), used with --tags only.
    std::vector<int> creaseVerts;   // pairs
    std::vector<float> creaseSharp;
    std::vector<int> cornerVerts;
    std::vector<float> cornerSharp;
    std::vector<int> holes;
    int boundary = 1;  // 0 none, 1 edge-only, 2 edge-and-corner
    bool chaikin = false;
    bool smoothTriangles = false;
};

// Parses one `t name nint/nfloat/nstring ints floats strings` line.
void readTag(Mesh &m, std::istringstream &ss, long lineNo) {
    std::string name, counts;
    if (!(ss >> name >> counts)) die("bad tag on line " + std::to_string(lineNo));
    int ni = 0, nf = 0, ns = 0;
    if (std::sscanf(counts.c_str(), "%d/%d/%d", &ni, &nf, &ns) != 3)
        die("bad tag counts on line " + std::to_string(lineNo));
    std::vector<long> ints(ni);
    std::vector<double> floats(nf);
    std::vector<std::string> strings(ns);
    for (auto &x : ints) ss >> x;
    for (auto &x : floats) ss >> x;
    for (auto &x : strings) ss >> x;
    if (!ss) die("tag with too few values on line " + std::to_string(lineNo));
    if (name == "crease" && ni >= 2 && nf == 1) {
        // Vertex pairs, as OpenSubdiv's regression harness reads them.
        for (int k = 0; k + 1 < ni; k += 2) {
            m.creaseVerts.push_back((int)ints[k]);
            m.creaseVerts.push_back((int)ints[k + 1]);
            m.creaseSharp.push_back((float)floats[0]);
        }
    } else if (name == "corner" && nf == 1) {
        for (long v : ints) {
            m.cornerVerts.push_back((int)v);
            m.cornerSharp.push_back((float)floats[0]);
        }
    } else if (name == "hole") {
        for (long f : ints) m.holes.push_back((int)f);
    } else if (name == "interpolateboundary" && ni == 1) {
        // The file's numbering is RenderMan's (1 edge-and-corner, 2
        // edge-only, as regression/common/far_utils.h reads it); m.boundary
        // is ours (1 edge-only, 2 edge-and-corner).
        m.boundary = ints[0] == 1 ? 2 : ints[0] == 2 ? 1 : (int)ints[0];
    } else if (name == "creasemethod" && ns == 1) {
        m.chaikin = strings[0] == "chaikin";
    } else if (name == "smoothtriangles" && ns == 1) {
        m.smoothTriangles = strings[0] == "smooth";
    }
}

Mesh readObj(const char *path) {
    std::ifstream in(path);
    if (!in) die(std::string("cannot open mesh file ") + path);
    Mesh m;
    std::string line;
    long lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        std::istringstream ss(line);
        std::string tag;
        if (!(ss >> tag)) continue;
        if (tag == "v") {
            Vtx v;
            if (!(ss >> v.p[0] >> v.p[1] >> v.p[2]))
                die("bad vertex line " + std::to_string(lineNo));
            m.verts.push_back(v);
        } else if (tag == "f") {
            std::string tok;
            int n = 0;
            m.faceOffsets.push_back((int)m.faceVerts.size());
            while (ss >> tok) {
                // "a", "a/b", "a//c", "a/b/c": only the first number matters
                const char *s = tok.c_str();
                char *end = nullptr;
                long idx = std::strtol(s, &end, 10);
                if (end == s || idx == 0)
                    die("bad face index '" + tok + "' on line " + std::to_string(lineNo));
                long nv = (long)m.verts.size();
                long zi = idx > 0 ? idx - 1 : nv + idx;  // negative: relative
                if (zi < 0 || zi >= nv)
                    die("face index out of range on line " + std::to_string(lineNo));
                m.faceVerts.push_back((int)zi);
                ++n;
            }
            if (n < 3) die("face with fewer than 3 vertices on line " + std::to_string(lineNo));
            m.faceSizes.push_back(n);
        } else if (tag == "t") {
            readTag(m, ss, lineNo);
        }
        // everything else (vt, vn, g, s, usemtl, ...) is ignored
    }
    if (m.verts.empty() || m.faceSizes.empty()) die(std::string("no geometry in ") + path);
    return m;
}

// ---------------------------------------------------------------------------
// Query points
struct Queries {
    std::vector<int> face, sub;
    std::vector<double> u, v;
    std::vector<char> cls;
};

Queries readPoints(const char *path) {
    std::ifstream in(path);
    if (!in) die(std::string("cannot open points file ") + path);
    Queries q;
    std::string line;
    long lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        size_t first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        std::istringstream ss(line);
        int f, s;
        double u, v;
        std::string c;
        if (!(ss >> f >> s >> u >> v >> c) || c.size() != 1 || c[0] < 'A' || c[0] > 'Z')
            die("bad points line " + std::to_string(lineNo) + ": '" + line + "'");
        if (!(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0))
            die("u/v outside [0,1] on points line " + std::to_string(lineNo));
        q.face.push_back(f);
        q.sub.push_back(s);
        q.u.push_back(u);
        q.v.push_back(v);
        q.cls.push_back(c[0]);
    }
    return q;
}

// ---------------------------------------------------------------------------
// OpenSubdiv state
constexpr int kMaxPatchCVs = 32;  // regular = 16, Gregory basis = 20

struct Osd {
    std::unique_ptr<Far::TopologyRefiner> refiner;
    std::unique_ptr<Far::PatchTable> patchTable;
    std::unique_ptr<Far::PatchMap> patchMap;
    std::unique_ptr<Far::PtexIndices> ptex;
    std::vector<Vtx> verts;  // refined vertices (all levels) followed by local points
    int maxCVs = 0;
};

bool gTags = false;  // --tags: honour the OBJ's OpenSubdiv tags

Far::TopologyRefiner *createRefiner(const Mesh &m) {
    Sdc::Options sdcOpts;
    sdcOpts.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    sdcOpts.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_ALL);

    Far::TopologyDescriptor desc;
    desc.numVertices = (int)m.verts.size();
    desc.numFaces = (int)m.faceSizes.size();
    desc.numVertsPerFace = m.faceSizes.data();
    desc.vertIndicesPerFace = m.faceVerts.data();
    if (gTags) {
        sdcOpts.SetVtxBoundaryInterpolation(
            m.boundary == 0   ? Sdc::Options::VTX_BOUNDARY_NONE
            : m.boundary == 2 ? Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                              : Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
        sdcOpts.SetCreasingMethod(m.chaikin ? Sdc::Options::CREASE_CHAIKIN
                                            : Sdc::Options::CREASE_UNIFORM);
        sdcOpts.SetTriangleSubdivision(m.smoothTriangles ? Sdc::Options::TRI_SUB_SMOOTH
                                                         : Sdc::Options::TRI_SUB_CATMARK);
        desc.numCreases = (int)m.creaseSharp.size();
        desc.creaseVertexIndexPairs = m.creaseVerts.data();
        desc.creaseWeights = m.creaseSharp.data();
        desc.numCorners = (int)m.cornerSharp.size();
        desc.cornerVertexIndices = m.cornerVerts.data();
        desc.cornerWeights = m.cornerSharp.data();
        desc.numHoles = (int)m.holes.size();
        desc.holeIndices = m.holes.data();
    }

    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    Far::TopologyRefiner *r =
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdcOpts));
    if (!r) die("TopologyRefinerFactory::Create failed (invalid topology?)");
    return r;
}

void buildOsd(const Mesh &m, Osd &o, int level) {
    o.refiner.reset(createRefiner(m));

    Far::PatchTableFactory::Options popts(level);
    popts.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    popts.SetPatchPrecision<double>();   // double-precision local point stencils
    popts.generateVaryingTables = false; // vertex data only
    // With tags: infinitely sharp creases and corners as regular patches
    // with boundary masks (exact) instead of smooth patches isolated to
    // the last level (an approximation of order 2^-level).
    if (gTags) popts.useInfSharpPatch = true;

    o.refiner->RefineAdaptive(popts.GetRefineAdaptiveOptions());
    o.patchTable.reset(Far::PatchTableFactory::Create(*o.refiner, popts));
    if (!o.patchTable) die("PatchTableFactory::Create failed");
    o.patchMap.reset(new Far::PatchMap(*o.patchTable));
    o.ptex.reset(new Far::PtexIndices(*o.refiner));

    for (int a = 0; a < o.patchTable->GetNumPatchArrays(); ++a) {
        int n = o.patchTable->GetPatchArrayDescriptor(a).GetNumControlVertices();
        if (n > o.maxCVs) o.maxCVs = n;
    }
    if (o.maxCVs > kMaxPatchCVs) die("patch with too many control vertices");

    // Vertex buffer: all refinement levels, then local (end-cap) points.
    const int nRefined = o.refiner->GetNumVerticesTotal();
    const int nLocal = o.patchTable->GetNumLocalPoints();
    o.verts.assign((size_t)nRefined + nLocal, Vtx{{0, 0, 0}});
    std::copy(m.verts.begin(), m.verts.end(), o.verts.begin());

    Far::PrimvarRefinerReal<double> primvar(*o.refiner);
    Vtx *src = o.verts.data();
    for (int level = 1; level <= o.refiner->GetMaxLevel(); ++level) {
        Vtx *dst = src + o.refiner->GetLevel(level - 1).GetNumVertices();
        primvar.Interpolate(level, src, dst);
        src = dst;
    }
    if (nLocal > 0) {
        if (!o.patchTable->LocalPointStencilPrecisionMatchesType<double>())
            die("local point stencils are not double precision");
        Far::StencilTableReal<double> const *st =
            o.patchTable->GetLocalPointStencilTable<double>();
        if (!st) die("missing local point stencil table");
        st->UpdateValues(o.verts.data(), o.verts.data() + nRefined);
    }
}

// Map (base face, sub-face) to a ptex face id.
int ptexId(const Osd &o, const Mesh &m, int face, int sub) {
    if (face < 0 || face >= (int)m.faceSizes.size()) return -1;
    int n = m.faceSizes[face];
    if (n == 4) return sub == 0 ? o.ptex->GetFaceId(face) : -1;
    return (sub >= 0 && sub < n) ? o.ptex->GetFaceId(face) + sub : -1;
}

// Evaluate position and first derivatives at (ptex face, u, v): the timed kernel.
// Returns the patch handle (nullptr if there is no patch). Derivatives are exactly
// what EvaluateBasis yields (see evalPointPtex for the non-quad correction).
inline Far::PatchMap::Handle const *evalPoint(const Osd &o, int ptexFace, double u, double v,
                                              double out[9]) {
    Far::PatchMap::Handle const *h = o.patchMap->FindPatch(ptexFace, u, v);
    if (!h) return nullptr;
    double wP[kMaxPatchCVs], wDu[kMaxPatchCVs], wDv[kMaxPatchCVs];
    o.patchTable->EvaluateBasis(*h, u, v, wP, wDu, wDv);
    Far::ConstIndexArray cvs = o.patchTable->GetPatchVertices(*h);
    double p0 = 0, p1 = 0, p2 = 0, a0 = 0, a1 = 0, a2 = 0, b0 = 0, b1 = 0, b2 = 0;
    const Vtx *V = o.verts.data();
    for (int k = 0; k < cvs.size(); ++k) {
        const double *x = V[cvs[k]].p;
        p0 += wP[k] * x[0];  p1 += wP[k] * x[1];  p2 += wP[k] * x[2];
        a0 += wDu[k] * x[0]; a1 += wDu[k] * x[1]; a2 += wDu[k] * x[2];
        b0 += wDv[k] * x[0]; b1 += wDv[k] * x[1]; b2 += wDv[k] * x[2];
    }
    out[0] = p0; out[1] = p1; out[2] = p2;
    out[3] = a0; out[4] = a1; out[5] = a2;
    out[6] = b0; out[7] = b1; out[8] = b2;
    return h;
}

// Same, but derivatives are w.r.t. the (u,v) of the ptex face that was queried.
// OSD 3.5 scales derivatives by 2^depth of the patch, while the (u,v) of a
// non-quad sub-face only spans 2^(depth-1) (PatchParam::NonQuadRoot): for patches
// descending from non-quad faces EvaluateBasis derivatives are therefore 2x the
// derivative w.r.t. the sub-face (u,v); verified by central differences (--check).
inline bool evalPointPtex(const Osd &o, int ptexFace, double u, double v, double out[9]) {
    Far::PatchMap::Handle const *h = evalPoint(o, ptexFace, u, v, out);
    if (!h) return false;
    if (o.patchTable->GetPatchParam(*h).NonQuadRoot())
        for (int c = 3; c < 9; ++c) out[c] *= 0.5;
    return true;
}

// With --second: position, first and second derivatives (18 values).
inline void evalPointSecond(const Osd &o, int ptexFace, double u, double v, double out[18]) {
    Far::PatchMap::Handle const *h = o.patchMap->FindPatch(ptexFace, u, v);
    if (!h) return;
    double w[6][kMaxPatchCVs];
    o.patchTable->EvaluateBasis(*h, u, v, w[0], w[1], w[2], w[3], w[4], w[5]);
    Far::ConstIndexArray cvs = o.patchTable->GetPatchVertices(*h);
    double acc[18] = {0};
    const Vtx *V = o.verts.data();
    for (int k = 0; k < cvs.size(); ++k) {
        const double *x = V[cvs[k]].p;
        for (int d = 0; d < 6; ++d) {
            acc[3 * d] += w[d][k] * x[0];
            acc[3 * d + 1] += w[d][k] * x[1];
            acc[3 * d + 2] += w[d][k] * x[2];
        }
    }
    for (int c = 0; c < 18; ++c) out[c] = acc[c];
}

bool gSecond = false;  // --second

// One timed pass over a class; returns the checksum contribution.
double runPass(const Osd &o, const std::vector<int> &pf, const std::vector<double> &pu,
               const std::vector<double> &pv) {
    double sum = 0.0;
    const size_t n = pf.size();
    if (gSecond) {
        double r[18];
        for (size_t i = 0; i < n; ++i) {
            evalPointSecond(o, pf[i], pu[i], pv[i], r);
            for (int c = 0; c < 18; ++c) sum += r[c];
        }
        return sum;
    }
    double r[9];
    for (size_t i = 0; i < n; ++i) {
        evalPoint(o, pf[i], pu[i], pv[i], r);  // validity checked before timing
        sum += r[0] + r[1] + r[2] + r[3] + r[4] + r[5] + r[6] + r[7] + r[8];
    }
    return sum;
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---------------------------------------------------------------------------
// --check: verify the (u,v) convention against limit positions of base vertices.
//   * quads: (0,0)->v0, (1,0)->v1, (1,1)->v2, (0,1)->v3 of the face as listed in the OBJ
//   * N-gons: (0,0) of sub-face k -> v_k
// Reference limit positions come from a separate uniformly refined (level 1)
// refiner + PrimvarRefiner::Limit, and, for vertices whose incident faces are
// all quads, from the closed form (n^2 V + 4 sum E + sum D) / (n (n+5)).
// Derivatives are checked by central differences at an interior point.
int runCheck(const Mesh &m, const Osd &o) {
    const int nv = (int)m.verts.size();
    const int nf = (int)m.faceSizes.size();

    // Reference 1: PrimvarRefiner::Limit on level 1 (vertex-children come first,
    // so the child of base vertex i has level-1 index i).
    std::unique_ptr<Far::TopologyRefiner> uref(createRefiner(m));
    Far::TopologyRefiner::UniformOptions uopts(1);
    uopts.fullTopologyInLastLevel = true;  // required by PrimvarRefiner::Limit
    uref->RefineUniform(uopts);
    std::vector<Vtx> lvl1(uref->GetLevel(1).GetNumVertices());
    Far::PrimvarRefinerReal<double> pr(*uref);
    const Vtx *base = m.verts.data();
    Vtx *l1 = lvl1.data();
    pr.Interpolate(1, base, l1);
    std::vector<Vtx> limit(lvl1.size());
    Vtx *lim = limit.data();
    pr.Limit(l1, lim);

    // Reference 2: closed-form mask on base mesh for all-quad 1-rings.
    std::vector<Vtx> acc(nv, Vtx{{0, 0, 0}});
    std::vector<int> valence(nv, 0), nonQuad(nv, 0);
    for (int f = 0; f < nf; ++f) {
        int n = m.faceSizes[f];
        const int *fv = &m.faceVerts[m.faceOffsets[f]];
        for (int k = 0; k < n; ++k) {
            int c = fv[k];
            valence[c] += 1;  // interior manifold vertex: #faces == #edges
            if (n != 4) { nonQuad[c] = 1; continue; }
            // each incident quad contributes: 2 edge neighbours (each shared by
            // two quads, so weight 4 is split 2+2) and 1 diagonal vertex.
            acc[c].AddWithWeight(m.verts[fv[(k + 1) % 4]], 2.0);
            acc[c].AddWithWeight(m.verts[fv[(k + 3) % 4]], 2.0);
            acc[c].AddWithWeight(m.verts[fv[(k + 2) % 4]], 1.0);
        }
    }
    // Vertices usable as references: interior (no boundary edge) and valence >= 3.
    // Sdc (hence PrimvarRefiner::Limit) treats a smooth interior valence-2 vertex
    // like a corner (limit = the vertex itself), while the patches give the true
    // limit, so valence-2 vertices are skipped.
    std::vector<char> usable(nv, 1);
    {
        std::map<std::pair<int, int>, int> edgeUse;
        for (int f = 0; f < nf; ++f) {
            int n = m.faceSizes[f];
            const int *fv = &m.faceVerts[m.faceOffsets[f]];
            for (int k = 0; k < n; ++k) {
                int a = fv[k], b = fv[(k + 1) % n];
                edgeUse[std::make_pair(std::min(a, b), std::max(a, b))] += 1;
            }
        }
        for (auto const &e : edgeUse)
            if (e.second != 2) usable[e.first.first] = usable[e.first.second] = 0;
        for (int i = 0; i < nv; ++i)
            if (valence[i] < 3) usable[i] = 0;
    }
    auto formula = [&](int c, Vtx &out) {
        double n = valence[c];
        out = acc[c];
        out.AddWithWeight(m.verts[c], n * n);
        for (double &x : out.p) x /= n * (n + 5.0);
    };
    auto dist = [](const double *a, const double *b) {
        return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                         (a[2] - b[2]) * (a[2] - b[2]));
    };

    const double cu[4] = {0, 1, 1, 0}, cv[4] = {0, 0, 1, 1};
    double maxErrLimit = 0, maxErrFormula = 0, maxErrFD = 0, maxErrWrong = 1e300;
    double r[9];
    int nCorners = 0, nFormula = 0, nSkipped = 0;
    for (int f = 0; f < nf; ++f) {
        int n = m.faceSizes[f];
        const int *fv = &m.faceVerts[m.faceOffsets[f]];
        for (int k = 0; k < n; ++k) {
            int pid, corner;
            if (n == 4) { pid = ptexId(o, m, f, 0); corner = k; }
            else        { pid = ptexId(o, m, f, k); corner = 0; }
            if (!evalPointPtex(o, pid, cu[corner], cv[corner], r)) die("FindPatch failed in check");
            int vi = fv[k];
            if (!usable[vi]) { ++nSkipped; continue; }
            maxErrLimit = std::fmax(maxErrLimit, dist(r, limit[vi].p));
            ++nCorners;
            if (!nonQuad[vi]) {
                Vtx ref;
                formula(vi, ref);
                maxErrFormula = std::fmax(maxErrFormula, dist(r, ref.p));
                ++nFormula;
                if (f == 0 && k == 0)
                    std::printf("check face0 (u,v)=(0,0): osd=(%.17g %.17g %.17g) "
                                "mask(v%d,valence %d)=(%.17g %.17g %.17g)\n",
                                r[0], r[1], r[2], vi, valence[vi], ref.p[0], ref.p[1], ref.p[2]);
            }
            // alternative (transposed) convention (1,0)->v3 for quads: must NOT match
            if (n == 4 && (k == 1 || k == 3)) {
                int other = fv[k == 1 ? 3 : 1];
                if (usable[other] && dist(limit[other].p, limit[vi].p) > 1e-9)
                    maxErrWrong = std::fmin(maxErrWrong, dist(r, limit[other].p));
            }
        }
        // derivative check at an interior point of each (sub-)face
        int nsub = (n == 4) ? 1 : n;
        for (int s = 0; s < nsub; ++s) {
            int pid = ptexId(o, m, f, s);
            const double u = 0.3, v = 0.6, h = 1e-6;
            double pu1[9], pu0[9], pv1[9], pv0[9];
            evalPointPtex(o, pid, u, v, r);
            evalPointPtex(o, pid, u + h, v, pu1);
            evalPointPtex(o, pid, u - h, v, pu0);
            evalPointPtex(o, pid, u, v + h, pv1);
            evalPointPtex(o, pid, u, v - h, pv0);
            const double zero[3] = {0, 0, 0};
            double scale = 1.0 + std::fmax(dist(r + 3, zero), dist(r + 6, zero));
            for (int c = 0; c < 3; ++c) {
                maxErrFD = std::fmax(maxErrFD, std::fabs((pu1[c] - pu0[c]) / (2 * h) - r[3 + c]) / scale);
                maxErrFD = std::fmax(maxErrFD, std::fabs((pv1[c] - pv0[c]) / (2 * h) - r[6 + c]) / scale);
            }
        }
    }
    std::printf("check corners=%d (skipped %d at boundary/valence<3 vertices) "
                "max|P(corner)-Limit(v)|=%.3g\n", nCorners, nSkipped, maxErrLimit);
    std::printf("check corners_with_quad_ring=%d max|P(corner)-mask(v)|=%.3g\n", nFormula, maxErrFormula);
    if (maxErrWrong < 1e300)
        std::printf("check transposed convention (1,0)->v3: min distance=%.3g (should be large)\n",
                    maxErrWrong);
    std::printf("check derivative vs central difference: max rel err=%.3g\n", maxErrFD);
    bool ok = maxErrLimit < 1e-9 && maxErrFormula < 1e-9 && maxErrFD < 1e-5;
    std::printf("check %s\n", ok ? "PASSED" : "FAILED");
    return ok ? 0 : 2;
}

void usage() {
    std::fprintf(stderr,
                 "usage: osd_eval MESH.obj POINTS.txt [--dump OUT.txt] [--repeat R] [--check] [--level L] [--tags] [--second]\n");
    std::exit(1);
}

}  // namespace

int main(int argc, char **argv) {
    const char *meshPath = nullptr, *pointsPath = nullptr, *dumpPath = nullptr;
    long repeat = 0;  // 0 = auto
    bool check = false;
    int level = 10;  // adaptive isolation level (max 10 for PatchTableFactory)
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--dump")) {
            if (++i >= argc) usage();
            dumpPath = argv[i];
        } else if (!std::strcmp(argv[i], "--repeat")) {
            if (++i >= argc) usage();
            repeat = std::atol(argv[i]);
            if (repeat <= 0) die("--repeat needs a positive integer");
        } else if (!std::strcmp(argv[i], "--level")) {
            if (++i >= argc) usage();
            level = std::atoi(argv[i]);
            if (level < 1 || level > 10) die("--level must be in 1..10");
        } else if (!std::strcmp(argv[i], "--check")) {
            check = true;
        } else if (!std::strcmp(argv[i], "--tags")) {
            gTags = true;
        } else if (!std::strcmp(argv[i], "--second")) {
            gSecond = true;
        } else if (argv[i][0] == '-' && argv[i][1] == '-') {
            usage();
        } else if (!meshPath) {
            meshPath = argv[i];
        } else if (!pointsPath) {
            pointsPath = argv[i];
        } else {
            usage();
        }
    }
    if (!meshPath || !pointsPath) usage();

    Mesh mesh = readObj(meshPath);
    Queries q = readPoints(pointsPath);

    // ---- setup (timed): refiner, adaptive refinement, patch table, patch map,
    //      ptex indices, refined vertices + local points
    Osd o;
    auto t0 = std::chrono::steady_clock::now();
    buildOsd(mesh, o, level);
    double setupMs = secondsSince(t0) * 1e3;

    // ---- resolve queries to ptex ids, validate, split by class (input order kept)
    const size_t nq = q.face.size();
    std::vector<int> ptexOf(nq);
    // Classes: R and X first (always reported), then other letters in the
    // order of their first point.
    std::vector<char> names = {'R', 'X'};
    std::vector<std::vector<int>> f(2);
    std::vector<std::vector<double>> u(2), v(2);
    for (size_t i = 0; i < nq; ++i) {
        int pid = ptexId(o, mesh, q.face[i], q.sub[i]);
        if (pid < 0)
            die("invalid (face, sub) = (" + std::to_string(q.face[i]) + ", " +
                std::to_string(q.sub[i]) + ") at point " + std::to_string(i));
        if (!o.patchMap->FindPatch(pid, q.u[i], q.v[i]))
            die("no patch for point " + std::to_string(i));
        ptexOf[i] = pid;
        size_t c = std::find(names.begin(), names.end(), q.cls[i]) - names.begin();
        if (c == names.size()) {
            names.push_back(q.cls[i]);
            f.emplace_back();
            u.emplace_back();
            v.emplace_back();
        }
        f[c].push_back(pid);
        u[c].push_back(q.u[i]);
        v[c].push_back(q.v[i]);
    }

    int rc = 0;
    if (check) rc = runCheck(mesh, o);

    // ---- dump (not timed)
    if (dumpPath) {
        FILE *out = std::fopen(dumpPath, "w");
        if (!out) die(std::string("cannot write ") + dumpPath);
        double r[9];
        for (size_t i = 0; i < nq; ++i) {
            evalPointPtex(o, ptexOf[i], q.u[i], q.v[i], r);
            std::fprintf(out, "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g", r[0],
                         r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8]);
            if (gTags) {
                // 1 where the point lies on a regular (B-spline) patch, on
                // which OpenSubdiv is exact; 0 on an end cap.
                const Far::PatchTable::PatchHandle *h =
                    o.patchMap->FindPatch(ptexOf[i], q.u[i], q.v[i]);
                int regular = o.patchTable->GetPatchDescriptor(*h).GetType() ==
                              Far::PatchDescriptor::REGULAR;
                std::fprintf(out, " %d", regular);
            }
            std::fprintf(out, "\n");
        }
        std::fclose(out);
    }

    // ---- timing, per class
    std::printf("osd setup_ms=%.3f\n", setupMs);
    double checksum = 0.0;
    for (size_t c = 0; c < names.size(); ++c) {
        const size_t n = f[c].size();
        if (n == 0) {
            std::printf("osd class=%c points=0 ns_per_eval=nan\n", names[c]);
            continue;
        }
        long reps = repeat;
        if (reps == 0) {
            // warm-up + calibration pass, then choose R so the timed run is >= 0.3 s
            auto tc = std::chrono::steady_clock::now();
            checksum += runPass(o, f[c], u[c], v[c]);
            double one = secondsSince(tc);
            reps = (long)std::ceil(0.3 / std::fmax(one, 1e-9) * 1.05);
            if (reps < 1) reps = 1;
        }
        auto tt = std::chrono::steady_clock::now();
        for (long r = 0; r < reps; ++r) checksum += runPass(o, f[c], u[c], v[c]);
        double secs = secondsSince(tt);
        std::printf("osd class=%c points=%zu ns_per_eval=%.1f\n", names[c], n,
                    secs * 1e9 / ((double)reps * (double)n));
    }
    std::fprintf(stderr, "osd checksum=%.17g\n", checksum);
    return rc;
}
