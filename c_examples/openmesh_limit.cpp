// openmesh_limit.cpp: the exact Catmull-Clark limit surface of an OpenMesh
// mesh with ccss, cross-checked against OpenMesh's own CatmullClarkT.
//
//   openmesh_limit MESH OUT.txt [LIMIT_MESH] [--levels N]
//
// 1. Reads MESH (any format OpenMesh reads: OBJ, OFF, PLY, STL, OM) into a
//    PolyMesh with double coordinates.
// 2. Hands its points and faces to ccss (c_examples/hosts/ccss_host.hpp) and
//    stores the exact limit position and normal of every vertex and of every
//    face centre as OpenMesh properties ("ccss:limit", "ccss:normal").
// 3. Writes them to OUT.txt, one line each:
//        v <index> <control x y z> <limit x y z> <normal x y z>
//        f <index> <centroid x y z> <limit x y z> <normal x y z>
//    and, if LIMIT_MESH is given, the mesh with every vertex moved to its
//    limit position and the limit normals as vertex normals (OpenMesh writer;
//    the format follows the file name).
// 4. Subdivides a copy with OpenMesh::Subdivider::Uniform::CatmullClarkT,
//    levels 1..N (default 4), and prints per level the largest distance
//    between OpenMesh's control points and our limit points, per valence,
//    for the original vertices and the face centres (face points of level
//    1). Catmull-Clark control points converge to their limit points at a
//    known rate (4x per level at valence 4; ccss_host::expected_ratio and
//    Convergence::report say which levels are checked); a group that misses
//    it by more than 10% (3% at the last level) prints FAIL with the numbers
//    and the program exits with status 2.
//
// Build: see c_examples/hosts/CMakeLists.txt (OpenMesh and ccss from
// find_package or pkg-config).
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>

#include "ccss_host.hpp"
#include "openmesh_input.hpp"

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace {

struct Traits : OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::PolyMesh_ArrayKernelT<Traits> Mesh;

ccss_host::Vec3 v3(const OpenMesh::Vec3d& p) { return {p[0], p[1], p[2]}; }
OpenMesh::Vec3d om(const double* p) { return OpenMesh::Vec3d(p[0], p[1], p[2]); }

int run(int argc, char** argv)
{
    ccss_host::LimitArgs args;
    if (!args.parse(argc, argv, "openmesh_limit")) return 64;
    const char* in = args.in;
    const char* out = args.out;
    const char* limit_mesh = args.limit_mesh;
    const int levels = args.levels;

    // 1. The mesh.
    Mesh mesh;
    if (!OpenMesh::IO::read_mesh(mesh, in)) {
        std::fprintf(stderr, "openmesh_limit: cannot read %s\n", in);
        return 1;
    }
    std::printf("# ccss %s, OpenMesh %d.%d\n", ccss_version(), OM_GET_VER, OM_GET_MAJ);
    std::printf("mesh %s vertices=%zu faces=%zu edges=%zu\n", in, mesh.n_vertices(),
                mesh.n_faces(), mesh.n_edges());

    // 2. Points and faces for ccss, in OpenMesh's numbering and orientation.
    const auto [positions, sizes, indices] = ccss_host::openmesh_arrays(mesh);
    const ccss_host::Limit limit(positions, sizes, indices);
    std::printf("ccss patches regular=%zu extraordinary=%zu\n", limit.regular_patches(),
                limit.extraordinary_patches());

    // Limit positions and normals as OpenMesh properties.
    OpenMesh::VPropHandleT<OpenMesh::Vec3d> v_limit, v_normal;
    OpenMesh::FPropHandleT<OpenMesh::Vec3d> f_limit, f_normal;
    mesh.add_property(v_limit, "ccss:limit");
    mesh.add_property(v_normal, "ccss:normal");
    mesh.add_property(f_limit, "ccss:limit");
    mesh.add_property(f_normal, "ccss:normal");
    const auto corners = ccss_host::first_corners(mesh.n_vertices(), sizes, indices);
    std::vector<bool> used(mesh.n_vertices(), false);
    for (auto vh : mesh.vertices()) {
        const ccss_host::Corner c = corners[vh.idx()];
        if (c.face == UINT32_MAX) continue; // isolated vertex: not on the surface
        used[vh.idx()] = true;
        const ccss_evaluator_result r = limit.corner(c.face, c.k);
        mesh.property(v_limit, vh) = om(r.p);
        mesh.property(v_normal, vh) = om(r.normal);
    }
    for (auto fh : mesh.faces()) {
        const ccss_evaluator_result r = limit.centre(static_cast<uint32_t>(fh.idx()));
        mesh.property(f_limit, fh) = om(r.p);
        mesh.property(f_normal, fh) = om(r.normal);
    }

    // 3. The output file, from the properties.
    std::FILE* f = std::fopen(out, "w");
    if (f == nullptr) {
        std::fprintf(stderr, "openmesh_limit: cannot write %s\n", out);
        return 1;
    }
    std::fprintf(f, "# ccss limit of %s (OpenMesh numbering)\n", in);
    std::fprintf(f, "# v index control(3) limit(3) normal(3); f index centroid(3) limit(3) normal(3)\n");
    for (auto vh : mesh.vertices()) {
        if (!used[vh.idx()]) continue;
        const auto &c = mesh.point(vh), &p = mesh.property(v_limit, vh), &n = mesh.property(v_normal, vh);
        std::fprintf(f, "v %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", vh.idx(), c[0],
                     c[1], c[2], p[0], p[1], p[2], n[0], n[1], n[2]);
    }
    for (auto fh : mesh.faces()) {
        const OpenMesh::Vec3d c = mesh.calc_face_centroid(fh);
        const auto &p = mesh.property(f_limit, fh), &n = mesh.property(f_normal, fh);
        std::fprintf(f, "f %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", fh.idx(), c[0],
                     c[1], c[2], p[0], p[1], p[2], n[0], n[1], n[2]);
    }
    if (std::fclose(f) != 0) {
        std::fprintf(stderr, "openmesh_limit: error writing %s\n", out);
        return 1;
    }
    std::printf("wrote %s\n", out);

    if (limit_mesh != nullptr) {
        Mesh lm = mesh; // same connectivity, points moved onto the limit surface
        lm.request_vertex_normals();
        for (auto vh : lm.vertices()) {
            if (!used[vh.idx()]) continue;
            lm.set_point(vh, mesh.property(v_limit, vh));
            lm.set_normal(vh, mesh.property(v_normal, vh));
        }
        OpenMesh::IO::Options opt(OpenMesh::IO::Options::VertexNormal);
        if (!OpenMesh::IO::write_mesh(lm, limit_mesh, opt, 17)) {
            std::fprintf(stderr, "openmesh_limit: cannot write %s\n", limit_mesh);
            return 1;
        }
        std::printf("wrote %s\n", limit_mesh);
    }

    // 4. OpenMesh's Catmull-Clark subdivider, one level at a time.
    const size_t nv0 = mesh.n_vertices(), ne0 = mesh.n_edges(), nf0 = mesh.n_faces();
    const double diag = ccss_host::bbox_diagonal(positions);
    std::vector<unsigned> valence(nv0);
    for (auto vh : mesh.vertices()) valence[vh.idx()] = mesh.valence(vh);

    Mesh sub = mesh;
    sub.request_face_normals();
    sub.request_vertex_normals();
    OpenMesh::Subdivider::Uniform::CatmullClarkT<Mesh> cc;
    cc.attach(sub);
    ccss_host::Convergence conv(levels, diag);
    std::vector<double> normal_angle(static_cast<size_t>(levels) + 1, 0.0);
    for (int level = 1; level <= levels; ++level) {
        cc(1);
        if (level == 1) {
            // OpenMesh keeps the old vertex handles, then adds one vertex per
            // edge (edge order) and one per face (face order). Check it: the
            // face point of face f is its centroid and has its size as valence.
            if (sub.n_vertices() != nv0 + ne0 + nf0) {
                std::fprintf(stderr, "openmesh_limit: level 1 has %zu vertices, expected %zu\n",
                             sub.n_vertices(), nv0 + ne0 + nf0);
                return 1;
            }
            for (auto fh : mesh.faces()) {
                const Mesh::VertexHandle fp(static_cast<int>(nv0 + ne0 + fh.idx()));
                const double e = ccss_host::dist(v3(sub.point(fp)), v3(mesh.calc_face_centroid(fh)));
                if (e > 1e-12 * diag || sub.valence(fp) != mesh.valence(fh)) {
                    std::fprintf(stderr, "openmesh_limit: vertex %d is not the face point of face %d\n",
                                 fp.idx(), fh.idx());
                    return 1;
                }
            }
            for (auto vh : mesh.vertices()) {
                if (sub.valence(vh) != valence[vh.idx()]) {
                    std::fprintf(stderr, "openmesh_limit: vertex %d changed valence\n", vh.idx());
                    return 1;
                }
            }
        }
        for (auto vh : mesh.vertices()) {
            if (!used[vh.idx()]) continue;
            const double d = ccss_host::dist(v3(sub.point(vh)), v3(mesh.property(v_limit, vh)));
            conv.add("vertex", valence[vh.idx()], 0, level, d);
            const double c = std::max(-1.0, std::min(1.0, OpenMesh::dot(sub.normal(vh),
                                                                          mesh.property(v_normal, vh))));
            normal_angle[static_cast<size_t>(level)] =
                std::max(normal_angle[static_cast<size_t>(level)], std::acos(c));
        }
        for (auto fh : mesh.faces()) {
            const Mesh::VertexHandle fp(static_cast<int>(nv0 + ne0 + fh.idx()));
            const double d = ccss_host::dist(v3(sub.point(fp)), v3(mesh.property(f_limit, fh)));
            conv.add("centre", mesh.valence(fh), 1, level, d);
        }
        std::printf("level %d vertices=%zu faces=%zu\n", level, sub.n_vertices(), sub.n_faces());
    }
    cc.detach();

    // Distances are printed relative to the bounding-box diagonal.
    std::printf("bbox_diagonal %.17g\n", diag);
    const int failures = conv.report(limit.tables(), 0.10, 0.03, stdout);
    std::printf("normals vertex max_angle_rad");
    for (int l = 1; l <= levels; ++l) std::printf(" a%d=%.3e", l, normal_angle[static_cast<size_t>(l)]);
    std::printf(" (OpenMesh vertex normals of level L vs the exact limit normals)\n");
    return ccss_host::verdict(failures);
}

} // namespace

int main(int argc, char** argv)
{
    return ccss_host::guarded_main("openmesh_limit", [&] { return run(argc, argv); });
}
