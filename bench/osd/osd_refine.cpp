// OpenSubdiv 3.5 uniform-refinement oracle for the sharp reference
// subdivider (tests/src/sharp.rs): reads a mesh with creases, corners,
// holes and scheme options from stdin, refines it uniformly with Far, and
// prints the refined control points and OpenSubdiv's limit positions.
//
// Input (whitespace separated, written by the Rust test):
//   boundary B      0 none, 1 edge-only, 2 edge-and-corner
//   creasing C      0 uniform, 1 chaikin
//   triangles T     0 catmark, 1 smooth (Sdc TRI_SUB_SMOOTH)
//   level L         uniform refinement depth (>= 1)
//   v N             then N lines "x y z"
//   f F             then F lines "n i_0 ... i_{n-1}"
//   crease K        then K lines "a b sharpness"
//   corner K        then K lines "v sharpness"
//   hole K          then K face indices
// Output: "refined N" then N lines "x y z" (level L, OpenSubdiv's vertex
// order: vertex-vertices first, as the parents), then "limit N" and N lines
// (PrimvarRefiner::Limit at level L). Errors: one line on stderr, exit 1.
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

namespace {

struct Point {
    double p[3];
    void Clear(void * = nullptr) { p[0] = p[1] = p[2] = 0.0; }
    void AddWithWeight(Point const &s, double w) {
        p[0] += w * s.p[0];
        p[1] += w * s.p[1];
        p[2] += w * s.p[2];
    }
};

[[noreturn]] void fail(std::string const &msg) {
    std::cerr << "osd_refine: " << msg << "\n";
    std::exit(1);
}

int expect_count(std::istream &in, char const *key) {
    std::string k;
    int n = -1;
    if (!(in >> k >> n) || k != key || n < 0) fail(std::string("expected '") + key + " N'");
    return n;
}

}  // namespace

int main() {
    std::istream &in = std::cin;
    int boundary = expect_count(in, "boundary");
    int creasing = expect_count(in, "creasing");
    int triangles = expect_count(in, "triangles");
    int level = expect_count(in, "level");
    if (level < 1 || level > 8) fail("level must be 1..8");

    int nv = expect_count(in, "v");
    std::vector<Point> verts(nv);
    for (auto &v : verts)
        if (!(in >> v.p[0] >> v.p[1] >> v.p[2])) fail("bad vertex line");

    int nf = expect_count(in, "f");
    std::vector<int> sizes(nf), indices;
    for (int f = 0; f < nf; ++f) {
        if (!(in >> sizes[f]) || sizes[f] < 3) fail("bad face size");
        for (int k = 0; k < sizes[f]; ++k) {
            int i;
            if (!(in >> i) || i < 0 || i >= nv) fail("bad face index");
            indices.push_back(i);
        }
    }
    int nc = expect_count(in, "crease");
    std::vector<int> crease_pairs(2 * nc);
    std::vector<float> crease_w(nc);
    for (int c = 0; c < nc; ++c)
        if (!(in >> crease_pairs[2 * c] >> crease_pairs[2 * c + 1] >> crease_w[c])) fail("bad crease");
    int nk = expect_count(in, "corner");
    std::vector<int> corner_v(nk);
    std::vector<float> corner_w(nk);
    for (int c = 0; c < nk; ++c)
        if (!(in >> corner_v[c] >> corner_w[c])) fail("bad corner");
    int nh = expect_count(in, "hole");
    std::vector<int> holes(nh);
    for (auto &h : holes)
        if (!(in >> h)) fail("bad hole");

    Sdc::Options opt;
    opt.SetVtxBoundaryInterpolation(boundary == 0   ? Sdc::Options::VTX_BOUNDARY_NONE
                                    : boundary == 1 ? Sdc::Options::VTX_BOUNDARY_EDGE_ONLY
                                                    : Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    opt.SetCreasingMethod(creasing == 1 ? Sdc::Options::CREASE_CHAIKIN : Sdc::Options::CREASE_UNIFORM);
    opt.SetTriangleSubdivision(triangles == 1 ? Sdc::Options::TRI_SUB_SMOOTH : Sdc::Options::TRI_SUB_CATMARK);

    Far::TopologyDescriptor desc;
    desc.numVertices = nv;
    desc.numFaces = nf;
    desc.numVertsPerFace = sizes.data();
    desc.vertIndicesPerFace = indices.data();
    desc.numCreases = nc;
    desc.creaseVertexIndexPairs = crease_pairs.data();
    desc.creaseWeights = crease_w.data();
    desc.numCorners = nk;
    desc.cornerVertexIndices = corner_v.data();
    desc.cornerWeights = corner_w.data();
    desc.numHoles = nh;
    desc.holeIndices = holes.data();

    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    Far::TopologyRefiner *refiner =
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, opt));
    if (!refiner) fail("TopologyRefinerFactory::Create failed");
    Far::TopologyRefiner::UniformOptions uniform(level);
    uniform.fullTopologyInLastLevel = true;  // Limit() needs it
    refiner->RefineUniform(uniform);

    std::vector<Point> buf(refiner->GetNumVerticesTotal());
    std::copy(verts.begin(), verts.end(), buf.begin());
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    Point *src = buf.data();
    for (int l = 1; l <= level; ++l) {
        Point *dst = src + refiner->GetLevel(l - 1).GetNumVertices();
        primvar.Interpolate(l, src, dst);
        src = dst;
    }
    int nfine = refiner->GetLevel(level).GetNumVertices();
    std::vector<Point> limit(nfine);
    primvar.Limit(src, limit);

    std::printf("refined %d\n", nfine);
    for (int i = 0; i < nfine; ++i)
        std::printf("%.17g %.17g %.17g\n", src[i].p[0], src[i].p[1], src[i].p[2]);
    std::printf("limit %d\n", nfine);
    for (int i = 0; i < nfine; ++i)
        std::printf("%.17g %.17g %.17g\n", limit[i].p[0], limit[i].p[1], limit[i].p[2]);
    delete refiner;
    return 0;
}
