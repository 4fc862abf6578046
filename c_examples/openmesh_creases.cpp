// openmesh_creases.cpp: the exact limit surface of an OpenMesh mesh with
// sharp features: open borders (boundary edges), and creases found the way
// CAD tools find them (edges whose dihedral angle exceeds a threshold),
// evaluated by ccss's feature evaluator (OpenSubdiv's rules, exact).
//
//   openmesh_creases MESH OUT.txt [--angle DEG]
//
// 1. Reads MESH with OpenMesh (OBJ, OFF, PLY, STL, OM) into a PolyMesh.
// 2. Marks every interior edge whose face normals differ by more than DEG
//    degrees (default 40) as infinitely sharp (sharpness 10); boundary edges
//    are infinitely sharp by OpenSubdiv's EDGE_ONLY rule.
// 3. Builds a ccss_feature_evaluator (with standard eigen tables) and writes
//    the exact limit position and normal of every vertex (through one of
//    its face corners) to OUT.txt:
//        v <index> <sharp edges> <control x y z> <limit x y z> <normal x y z>
// 4. Checks against closed forms that do not depend on the rest of the mesh
//    (OpenSubdiv's limit masks): a vertex on exactly two sharp edges (a
//    crease, or an open border) has the limit (a + 4 v + b) / 6 of its two
//    sharp neighbours a, b; a vertex on three or more stays where it is (a
//    corner). Prints
//        features edges=E sharp=S crease_vertices=C corners=K max_error=X
//    and "PASS: 0 failure(s)" (every checked vertex within 1e-12 of the
//    bounding-box diagonal), or FAIL lines and exit status 2.
//
// Build: see c_examples/hosts/CMakeLists.txt.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include "ccss_host.hpp"
#include "openmesh_input.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

struct Traits : OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::PolyMesh_ArrayKernelT<Traits> Mesh;

ccss_host::Vec3 v3(const OpenMesh::Vec3d& p) { return {p[0], p[1], p[2]}; }

/// The parameters of corner `k` of a face with `n` corners: (sub, u, v).
void corner_param(size_t n, size_t k, uint32_t& sub, double& u, double& v)
{
    static const double uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    if (n == 4) {
        sub = 0;
        u = uv[k][0];
        v = uv[k][1];
    } else {
        sub = static_cast<uint32_t>(k);
        u = 0;
        v = 0;
    }
}

int run(int argc, char** argv)
{
    if (argc < 3) {
        std::fprintf(stderr, "usage: openmesh_creases MESH OUT.txt [--angle DEG]\n");
        return 64;
    }
    double angle = 40.0;
    for (int i = 3; i < argc; ++i) {
        if (std::strcmp(argv[i], "--angle") == 0 && i + 1 < argc) {
            angle = std::atof(argv[++i]);
        } else {
            std::fprintf(stderr, "openmesh_creases: unknown argument '%s'\n", argv[i]);
            return 64;
        }
    }
    Mesh mesh;
    if (!OpenMesh::IO::read_mesh(mesh, argv[1])) {
        std::fprintf(stderr, "openmesh_creases: cannot read %s\n", argv[1]);
        return 1;
    }
    mesh.request_face_normals();
    mesh.update_face_normals();
    const ccss_host::MeshArrays arrays = ccss_host::openmesh_arrays(mesh);

    // Creases: interior edges with a dihedral angle above the threshold.
    const double cos_max = std::cos(angle * M_PI / 180.0);
    std::vector<uint32_t> crease_v;
    std::vector<float> crease_s;
    std::vector<int> sharp_edges(mesh.n_vertices(), 0);
    size_t sharp = 0;
    for (auto eh : mesh.edges()) {
        const auto h = mesh.halfedge_handle(eh, 0);
        const auto a = mesh.from_vertex_handle(h), b = mesh.to_vertex_handle(h);
        bool is_sharp = mesh.is_boundary(eh);
        if (!is_sharp) {
            const auto f0 = mesh.face_handle(h), f1 = mesh.opposite_face_handle(h);
            is_sharp = OpenMesh::dot(mesh.normal(f0), mesh.normal(f1)) < cos_max;
            if (is_sharp) {
                crease_v.push_back(static_cast<uint32_t>(a.idx()));
                crease_v.push_back(static_cast<uint32_t>(b.idx()));
                crease_s.push_back(10.0f);
            }
        }
        if (is_sharp) {
            ++sharp;
            ++sharp_edges[a.idx()];
            ++sharp_edges[b.idx()];
        }
    }

    // Tables and the feature evaluator (sizes asked first).
    ccss_error_detail d;
    size_t n = 0;
    ccss_status st = ccss_tables_required_bytes(&n, &d);
    if (st != CCSS_OK) throw ccss_host::error("ccss_tables_required_bytes", st, &d);
    ccss_host::Block tables_mem;
    tables_mem.alloc(n);
    const ccss_tables* tables = nullptr;
    st = ccss_tables_build_standard(tables_mem.get(), n, &tables, &d);
    if (st != CCSS_OK) throw ccss_host::error("ccss_tables_build_standard", st, &d);
    ccss_feature_options opts;
    st = ccss_feature_options_default(&opts, &d);
    if (st != CCSS_OK) throw ccss_host::error("ccss_feature_options_default", st, &d);
    const size_t nv = arrays.positions.size() / 3;
    st = ccss_feature_evaluator_required_bytes(
        arrays.positions.data(), nv, arrays.sizes.data(), arrays.sizes.size(),
        arrays.indices.data(), arrays.indices.size(), crease_v.data(), crease_s.data(),
        crease_s.size(), nullptr, nullptr, 0, nullptr, 0, &opts, tables, &n, &d);
    if (st != CCSS_OK) throw ccss_host::error("ccss_feature_evaluator_required_bytes", st, &d);
    ccss_host::Block fe_mem;
    fe_mem.alloc(n);
    const ccss_feature_evaluator* fe = nullptr;
    st = ccss_feature_evaluator_build(
        arrays.positions.data(), nv, arrays.sizes.data(), arrays.sizes.size(),
        arrays.indices.data(), arrays.indices.size(), crease_v.data(), crease_s.data(),
        crease_s.size(), nullptr, nullptr, 0, nullptr, 0, &opts, tables, fe_mem.get(), n, &fe,
        &d);
    if (st != CCSS_OK) throw ccss_host::error("ccss_feature_evaluator_build", st, &d);

    // Bounding-box diagonal.
    ccss_host::Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (auto vh : mesh.vertices())
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], mesh.point(vh)[k]);
            hi[k] = std::max(hi[k], mesh.point(vh)[k]);
        }
    const double diag = ccss_host::dist(lo, hi);

    std::FILE* out = std::fopen(argv[2], "w");
    if (out == nullptr) {
        std::fprintf(stderr, "openmesh_creases: cannot write %s\n", argv[2]);
        return 1;
    }
    int failures = 0;
    size_t crease_vertices = 0, corners = 0;
    double max_error = 0.0;
    for (auto vh : mesh.vertices()) {
        // One face corner of the vertex: its face and position in the face.
        auto fh = Mesh::FaceHandle();
        for (auto f : mesh.vf_range(vh)) {
            fh = f;
            break;
        }
        if (!fh.is_valid()) continue; // an isolated vertex has no surface
        size_t k = 0, size = 0;
        for (auto w : mesh.fv_range(fh)) {
            if (w == vh) k = size;
            ++size;
        }
        uint32_t sub;
        double u, v;
        corner_param(size, k, sub, u, v);
        ccss_evaluator_result r;
        st = ccss_feature_evaluator_eval(fe, static_cast<uint32_t>(fh.idx()), sub, u, v, &r,
                                         &d);
        if (st != CCSS_OK) throw ccss_host::error("ccss_feature_evaluator_eval", st, &d);
        const ccss_host::Vec3 p = v3(mesh.point(vh));
        const ccss_host::Vec3 lim{r.p[0], r.p[1], r.p[2]};
        std::fprintf(out, "v %d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                     vh.idx(), sharp_edges[vh.idx()], p[0], p[1], p[2], lim[0], lim[1], lim[2],
                     r.normal[0], r.normal[1], r.normal[2]);
        // The closed forms.
        ccss_host::Vec3 want;
        if (sharp_edges[vh.idx()] >= 3) {
            want = p;
            ++corners;
        } else if (sharp_edges[vh.idx()] == 2) {
            std::vector<ccss_host::Vec3> ends;
            for (auto h : mesh.voh_range(vh)) {
                const auto eh = mesh.edge_handle(h);
                bool s = mesh.is_boundary(eh);
                if (!s) {
                    const auto f0 = mesh.face_handle(h), f1 = mesh.opposite_face_handle(h);
                    s = OpenMesh::dot(mesh.normal(f0), mesh.normal(f1)) < cos_max;
                }
                if (s) ends.push_back(v3(mesh.point(mesh.to_vertex_handle(h))));
            }
            for (int c = 0; c < 3; ++c) want[c] = (ends[0][c] + 4.0 * p[c] + ends[1][c]) / 6.0;
            ++crease_vertices;
        } else {
            continue;
        }
        const double e = ccss_host::dist(want, lim);
        max_error = std::max(max_error, e / diag);
        if (e > 1e-12 * diag) {
            std::printf("FAIL vertex %d (%d sharp edges): limit %.17g %.17g %.17g, closed form "
                        "%.17g %.17g %.17g\n",
                        vh.idx(), sharp_edges[vh.idx()], lim[0], lim[1], lim[2], want[0],
                        want[1], want[2]);
            ++failures;
        }
    }
    std::fclose(out);
    std::printf("features edges=%zu sharp=%zu crease_vertices=%zu corners=%zu max_error=%.3g\n",
                mesh.n_edges(), sharp, crease_vertices, corners, max_error);
    if (crease_vertices + corners == 0) {
        std::printf("FAIL no vertex on a sharp feature: nothing was checked\n");
        ++failures;
    }
    return ccss_host::verdict(failures);
}

} // namespace

int main(int argc, char** argv)
{
    return ccss_host::guarded_main("openmesh_creases", [&] { return run(argc, argv); });
}
