// openmesh_tessellate.cpp: an OpenMesh mesh tessellated by ccss to an
// absolute flatness, written as binary STL, and checked with OpenMesh.
//
//   openmesh_tessellate MESH OUT.stl EPS [--check-tol T]
//
// 1. Reads MESH with OpenMesh (OBJ, OFF, PLY, STL, OM) into a PolyMesh and
//    hands its points and faces to ccss (c_examples/hosts/ccss_host.hpp).
// 2. Tessellates the limit surface with ccss to absolute flatness EPS (model
//    units): for every output triangle and every parameter x of its
//    parameter triangle, |S(x) - T(x)| <= bound <= EPS, S the limit surface
//    and T the triangle's linear interpolant (so both one-sided Hausdorff
//    distances are <= EPS).
// 3. Puts the triangles into an OpenMesh TriMesh, with ccss's exact limit
//    normals as vertex normals, and writes OUT.stl (binary, OpenMesh IO).
// 4. Checks, independently of the tessellator:
//    manifold   every triangle was accepted by OpenMesh's half-edge kernel
//               (no complex edge or vertex), no boundary half-edge, every
//               edge has two faces, every vertex is manifold and used, and
//               the Euler characteristic V - E + F equals the input's;
//    surface    every output vertex is the limit point of its reported
//               (face, sub, u, v): ccss_evaluator_eval there, |difference| <= 1e-12 of
//               the bounding-box diagonal, normals within 1e-8 rad;
//    flatness   for every triangle whose three vertices report parameters
//               in the sub-face of its polygon's parameter cell (and inside
//               that cell), the linear interpolant at 7 points (centroid,
//               edge midpoints, (4,1,1)/6 points) against ccss_evaluator_eval at the
//               interpolated parameter: distance <= T (default EPS). The
//               other triangles (vertices owned by a neighbouring sub-face
//               report that sub-face's parameters) are counted, not
//               sampled. --check-tol makes T smaller to see the check fail;
//    orientation  each sampled triangle's normal against the limit normal
//               at its centroid parameter (positive dot product);
//    stl        the file has 84 + 50 T bytes and reads back (OpenMesh merges
//               the float vertices) as a closed mesh of T triangles;
//    volume     the triangles' enclosed volume against ccss_mass_properties_compute's exact
//               volume (printed; the test bounds the difference).
// 5. Prints key=value lines and "PASS: 0 failure(s)", or FAIL lines and
//    exits with status 2.
//
// Build: see c_examples/hosts/CMakeLists.txt.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "ccss_host.hpp"
#include "openmesh_input.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

namespace {

struct Traits : OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::PolyMesh_ArrayKernelT<Traits> PolyMesh;
typedef OpenMesh::TriMesh_ArrayKernelT<Traits> TriMesh;

OpenMesh::Vec3d om(const double* p) { return OpenMesh::Vec3d(p[0], p[1], p[2]); }

/// Euler characteristic V - E + F.
template <class M> long euler(const M& m)
{
    return static_cast<long>(m.n_vertices()) - static_cast<long>(m.n_edges()) +
           static_cast<long>(m.n_faces());
}

struct Manifold {
    size_t add_face_failures = 0, boundary_halfedges = 0, bad_edges = 0, nonmanifold_vertices = 0,
           isolated_vertices = 0;
    bool ok() const
    {
        return add_face_failures + boundary_halfedges + bad_edges + nonmanifold_vertices +
                   isolated_vertices ==
               0;
    }
};

/// Closed 2-manifold check of a triangle mesh (add_face_failures is the
/// caller's).
Manifold check_manifold(const TriMesh& m, size_t add_face_failures)
{
    Manifold r;
    r.add_face_failures = add_face_failures;
    for (auto h : m.halfedges())
        if (m.is_boundary(h)) ++r.boundary_halfedges;
    for (auto e : m.edges()) {
        const bool two = !m.is_boundary(m.halfedge_handle(e, 0)) && !m.is_boundary(m.halfedge_handle(e, 1)) &&
                         m.face_handle(m.halfedge_handle(e, 0)) != m.face_handle(m.halfedge_handle(e, 1));
        if (!two) ++r.bad_edges;
    }
    for (auto v : m.vertices()) {
        if (m.is_isolated(v)) ++r.isolated_vertices;
        else if (!m.is_manifold(v)) ++r.nonmanifold_vertices;
    }
    return r;
}

int run(int argc, char** argv)
{
    const char* in = nullptr;
    const char* out = nullptr;
    double eps = 0.0, check_tol = 0.0;
    int positional = 0;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--check-tol") == 0 && i + 1 < argc) check_tol = std::atof(argv[++i]);
        else if (positional == 0) in = argv[i], ++positional;
        else if (positional == 1) out = argv[i], ++positional;
        else if (positional == 2) eps = std::atof(argv[i]), ++positional;
        else positional = -100;
    }
    if (positional != 3 || !(eps > 0.0) || check_tol < 0.0) {
        std::fprintf(stderr, "usage: openmesh_tessellate MESH OUT.stl EPS [--check-tol T]\n");
        return 64;
    }
    if (check_tol == 0.0) check_tol = eps;

    // 1. The mesh, handed to ccss in OpenMesh's numbering and orientation.
    PolyMesh mesh;
    if (!OpenMesh::IO::read_mesh(mesh, in)) {
        std::fprintf(stderr, "openmesh_tessellate: cannot read %s\n", in);
        return 1;
    }
    std::printf("# ccss %s, OpenMesh %d.%d\n", ccss_version(), OM_GET_VER, OM_GET_MAJ);
    std::printf("mesh %s vertices=%zu faces=%zu edges=%zu euler=%ld\n", in, mesh.n_vertices(),
                mesh.n_faces(), mesh.n_edges(), euler(mesh));
    const auto [positions, sizes, indices] = ccss_host::openmesh_arrays(mesh);
    const ccss_host::Limit limit(positions, sizes, indices);
    const double diag = ccss_host::bbox_diagonal(positions);

    // 2. The tessellation.
    const ccss_host::Tessellation t = ccss_host::tessellate(limit, ccss_host::absolute_flatness(eps));
    const ccss_tessellation_counts_info& c = t.counts;
    std::printf("tess eps=%.6g vertices=%zu polygons=%zu triangles=%zu max_level=%u bound=%.6g\n", eps,
                c.vertices, c.polygons, c.triangles, c.max_level, c.bound);

    // 3. The TriMesh with the limit normals, and the STL file.
    TriMesh tri;
    tri.request_vertex_normals();
    tri.request_face_normals();
    std::vector<TriMesh::VertexHandle> vh(c.vertices);
    for (size_t i = 0; i < c.vertices; ++i) {
        vh[i] = tri.add_vertex(om(&t.positions[3 * i]));
        tri.set_normal(vh[i], om(&t.normals[3 * i]));
    }
    size_t add_face_failures = 0;
    for (size_t k = 0; k < c.triangles; ++k) {
        const auto f = tri.add_face(vh[t.triangles[3 * k]], vh[t.triangles[3 * k + 1]],
                                    vh[t.triangles[3 * k + 2]]);
        if (!f.is_valid()) ++add_face_failures;
    }
    tri.update_face_normals();
    if (!OpenMesh::IO::write_mesh(tri, out, OpenMesh::IO::Options::Binary)) {
        std::fprintf(stderr, "openmesh_tessellate: cannot write %s\n", out);
        return 1;
    }

    int failures = 0;
    auto fail = [&failures](bool bad, const char* what) {
        if (bad) {
            std::printf("FAIL %s\n", what);
            ++failures;
        }
    };

    // 4a. Closed 2-manifold with the input's Euler characteristic.
    const Manifold mf = check_manifold(tri, add_face_failures);
    std::printf("topology manifold=%d add_face_failures=%zu boundary_halfedges=%zu bad_edges=%zu "
                "nonmanifold_vertices=%zu isolated_vertices=%zu euler=%ld euler_input=%ld\n",
                mf.ok() ? 1 : 0, mf.add_face_failures, mf.boundary_halfedges, mf.bad_edges,
                mf.nonmanifold_vertices, mf.isolated_vertices, euler(tri), euler(mesh));
    fail(!mf.ok(), "manifold: the triangles are not a closed 2-manifold");
    fail(euler(tri) != euler(mesh), "manifold: Euler characteristic differs from the input's");
    fail(tri.n_faces() != c.triangles, "manifold: triangle count");

    // 4b. Every vertex is the limit point of its parameters.
    double max_vertex_dist = 0.0, max_normal_angle = 0.0;
    size_t bad_params = 0;
    for (size_t i = 0; i < c.vertices; ++i) {
        const ccss_evaluator_query& q = t.params[i];
        if (q.face >= limit.num_faces() || !(q.u >= 0.0 && q.u <= 1.0 && q.v >= 0.0 && q.v <= 1.0)) {
            ++bad_params;
            continue;
        }
        const ccss_evaluator_result r = limit.eval(q.face, q.sub, q.u, q.v);
        const ccss_host::Vec3 a{t.positions[3 * i], t.positions[3 * i + 1], t.positions[3 * i + 2]};
        max_vertex_dist = std::max(max_vertex_dist, ccss_host::dist(a, {r.p[0], r.p[1], r.p[2]}));
        const OpenMesh::Vec3d n = om(&t.normals[3 * i]), m = om(r.normal);
        const double angle = std::atan2(OpenMesh::cross(n, m).norm(), OpenMesh::dot(n, m));
        max_normal_angle = std::max(max_normal_angle, angle);
    }
    std::printf("surface vertices=%zu bad_params=%zu max_dist=%.3e max_dist_rel=%.3e "
                "max_normal_angle=%.3e\n",
                c.vertices, bad_params, max_vertex_dist, max_vertex_dist / diag, max_normal_angle);
    fail(bad_params != 0, "surface: vertex parameters out of range");
    fail(!(max_vertex_dist <= 1e-12 * diag), "surface: a vertex is not its limit point");
    fail(!(max_normal_angle <= 1e-8), "surface: a vertex normal is not the limit normal");

    // 4c. Flatness, sampled: triangles whose vertices all report parameters
    // in their polygon's cell.
    static const double bary[7][3] = {
        {1.0 / 3, 1.0 / 3, 1.0 / 3}, {0.5, 0.5, 0.0}, {0.0, 0.5, 0.5}, {0.5, 0.0, 0.5},
        {4.0 / 6, 1.0 / 6, 1.0 / 6}, {1.0 / 6, 4.0 / 6, 1.0 / 6}, {1.0 / 6, 1.0 / 6, 4.0 / 6},
    };
    size_t sampled = 0, skipped = 0, outside_cell = 0, samples = 0, violations = 0, flipped = 0;
    double max_dist = 0.0;
    size_t tri_at = 0;
    for (size_t p = 0; p < c.polygons; ++p) {
        const ccss_tessellation_cell& cell = t.cells[p];
        const double w = std::ldexp(1.0, -static_cast<int>(cell.level));
        const double u0 = cell.i * w, v0 = cell.j * w;
        for (uint32_t k = 0; k + 2 < t.sizes[p]; ++k, ++tri_at) {
            const uint32_t* tv = &t.triangles[3 * tri_at];
            bool same = true;
            for (int a = 0; a < 3; ++a) {
                const ccss_evaluator_query& q = t.params[tv[a]];
                same = same && q.face == cell.face && q.sub == cell.sub;
            }
            if (!same) {
                ++skipped;
                continue;
            }
            bool inside = true;
            for (int a = 0; a < 3; ++a) {
                const ccss_evaluator_query& q = t.params[tv[a]];
                inside = inside && q.u >= u0 && q.u <= u0 + w && q.v >= v0 && q.v <= v0 + w;
            }
            if (!inside) {
                ++outside_cell;
                continue;
            }
            ++sampled;
            for (const auto& b : bary) {
                double x[3] = {0, 0, 0}, u = 0, v = 0;
                for (int a = 0; a < 3; ++a) {
                    for (int d = 0; d < 3; ++d) x[d] += b[a] * t.positions[3 * tv[a] + d];
                    u += b[a] * t.params[tv[a]].u;
                    v += b[a] * t.params[tv[a]].v;
                }
                const ccss_evaluator_result r = limit.eval(cell.face, cell.sub, u, v);
                const double d = ccss_host::dist({x[0], x[1], x[2]}, {r.p[0], r.p[1], r.p[2]});
                max_dist = std::max(max_dist, d);
                ++samples;
                if (!(d <= check_tol)) ++violations;
                if (&b == &bary[0]) {
                    const OpenMesh::Vec3d A = om(&t.positions[3 * tv[0]]), B = om(&t.positions[3 * tv[1]]),
                                          C = om(&t.positions[3 * tv[2]]);
                    if (!(OpenMesh::dot(OpenMesh::cross(B - A, C - A), om(r.normal)) > 0.0)) ++flipped;
                }
            }
        }
    }
    std::printf("flatness eps=%.6g check_tol=%.6g triangles=%zu sampled=%zu skipped=%zu "
                "coverage=%.3f samples=%zu violations=%zu outside_cell=%zu max_dist=%.3e "
                "max_ratio=%.4f\n",
                eps, check_tol, c.triangles, sampled, skipped,
                c.triangles ? double(sampled) / double(c.triangles) : 0.0, samples, violations,
                outside_cell, max_dist, max_dist / eps);
    std::printf("orientation sampled=%zu flipped=%zu\n", sampled, flipped);
    fail(tri_at != c.triangles, "flatness: triangles per polygon do not add up");
    fail(violations != 0, "flatness: a triangle is farther than the tolerance from the limit surface");
    fail(outside_cell != 0, "flatness: a vertex lies outside its polygon's parameter cell");
    fail(sampled == 0, "flatness: nothing sampled");
    fail(flipped != 0, "orientation: a triangle faces against the limit normal");

    // 4d. The STL file: size, and read back.
    std::ifstream stl(out, std::ios::binary | std::ios::ate);
    const long long bytes = stl ? static_cast<long long>(stl.tellg()) : -1;
    TriMesh back;
    OpenMesh::IO::Options ropt(OpenMesh::IO::Options::Binary);
    const bool read_ok = OpenMesh::IO::read_mesh(back, out, ropt);
    const Manifold bm = check_manifold(back, 0);
    std::printf("stl file=%s bytes=%lld expected_bytes=%lld readback_faces=%zu readback_vertices=%zu "
                "readback_manifold=%d\n",
                out, bytes, 84 + 50 * static_cast<long long>(c.triangles), back.n_faces(),
                back.n_vertices(), read_ok && bm.ok() ? 1 : 0);
    fail(bytes != 84 + 50 * static_cast<long long>(c.triangles), "stl: file size");
    fail(!read_ok || back.n_faces() != c.triangles || !bm.ok(), "stl: read back");

    // 4e. Volume of the triangles against the exact volume.
    double vol = 0.0;
    for (size_t k = 0; k < c.triangles; ++k) {
        const OpenMesh::Vec3d A = om(&t.positions[3 * t.triangles[3 * k]]),
                              B = om(&t.positions[3 * t.triangles[3 * k + 1]]),
                              C = om(&t.positions[3 * t.triangles[3 * k + 2]]);
        vol += OpenMesh::dot(A, OpenMesh::cross(B, C)) / 6.0;
    }
    ccss_mass_properties mp;
    ccss_error_detail det;
    const ccss_status st = ccss_mass_properties_compute(limit.evaluator(), &mp, &det);
    if (st != CCSS_OK) throw ccss_host::error("ccss_mass_properties_compute", st, &det);
    std::printf("volume triangles=%.10g exact=%.10g error_bound=%.3g area=%.10g diff=%.3e "
                "diff_over_area_eps=%.4f\n",
                vol, mp.volume, mp.volume_error_bound, mp.area, vol - mp.volume,
                std::fabs(vol - mp.volume) / (mp.area * eps));

    return ccss_host::verdict(failures);
}

} // namespace

int main(int argc, char** argv)
{
    return ccss_host::guarded_main("openmesh_tessellate", [&] { return run(argc, argv); });
}
