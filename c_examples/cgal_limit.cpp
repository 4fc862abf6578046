// cgal_limit.cpp: the exact Catmull-Clark limit surface of a CGAL
// Surface_mesh with ccss, cross-checked against
// CGAL::Subdivision_method_3::CatmullClark_subdivision.
//
//   cgal_limit MESH OUT.txt [LIMIT_MESH] [--levels N]
//
// 1. Reads MESH with CGAL::IO::read_polygon_mesh (OBJ, OFF, PLY, STL, ...;
//    no repair: the file must already be a valid polygon mesh) into a
//    Surface_mesh with double coordinates.
// 2. Hands its points and faces to ccss (c_examples/hosts/ccss_host.hpp) and
//    stores the exact limit position and normal of every vertex and of every
//    face centre as Surface_mesh property maps ("v:ccss_limit",
//    "v:ccss_normal", "f:ccss_limit", "f:ccss_normal").
// 3. Writes them to OUT.txt, one line each:
//        v <index> <control x y z> <limit x y z> <normal x y z>
//        f <index> <centroid x y z> <limit x y z> <normal x y z>
//    and, if LIMIT_MESH is given, the mesh with every vertex moved to its
//    limit position, with the limit normals as vertex normals
//    (CGAL::IO::write_polygon_mesh; the format follows the file name).
// 4. Subdivides a copy with CGAL's Catmull-Clark, levels 1..N (default 4),
//    and prints per level the largest distance between CGAL's control points
//    and our limit points, per valence, for the original vertices and the
//    face centres (face points of level 1). Catmull-Clark control points
//    converge to their limit points at a known rate (4x per level at valence
//    4; ccss_host::expected_ratio and Convergence::report say which levels
//    are checked); a group that misses it by more than 10% (3% at the last
//    level) prints FAIL with the numbers and the program exits with status 2.
//
// Build: see c_examples/hosts/CMakeLists.txt (CGAL and ccss from
// find_package or pkg-config).
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/subdivision_method_3.h>
#include <CGAL/version.h>

#include "ccss_host.hpp"

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace {

typedef CGAL::Simple_cartesian<double> Kernel;
typedef Kernel::Point_3 Point;
typedef Kernel::Vector_3 Vector;
typedef CGAL::Surface_mesh<Point> Mesh;
typedef Mesh::Vertex_index Vertex;
typedef Mesh::Face_index Face;

ccss_host::Vec3 v3(const Point& p) { return {p.x(), p.y(), p.z()}; }

Point centroid(const Mesh& m, Face f)
{
    double c[3] = {0, 0, 0};
    int n = 0;
    for (Vertex v : CGAL::vertices_around_face(m.halfedge(f), m)) {
        for (int k = 0; k < 3; ++k) c[k] += m.point(v)[k];
        ++n;
    }
    return Point(c[0] / n, c[1] / n, c[2] / n);
}

/// Area-weighted vertex normals (sum of the Newell normals of the faces
/// around each vertex), for the information line about normals.
std::vector<Vector> vertex_normals(const Mesh& m)
{
    std::vector<Vector> vn(m.number_of_vertices(), Vector(0, 0, 0));
    for (Face f : m.faces()) {
        double n[3] = {0, 0, 0};
        const auto h0 = m.halfedge(f);
        for (auto h : CGAL::halfedges_around_face(h0, m)) {
            const Point& a = m.point(m.source(h));
            const Point& b = m.point(m.target(h));
            n[0] += (a.y() - b.y()) * (a.z() + b.z());
            n[1] += (a.z() - b.z()) * (a.x() + b.x());
            n[2] += (a.x() - b.x()) * (a.y() + b.y());
        }
        for (Vertex v : CGAL::vertices_around_face(h0, m)) vn[v] = vn[v] + Vector(n[0], n[1], n[2]);
    }
    for (Vector& v : vn) {
        const double l = std::sqrt(v.squared_length());
        if (l > 0) v = v / l;
    }
    return vn;
}

int run(int argc, char** argv)
{
    ccss_host::LimitArgs args;
    if (!args.parse(argc, argv, "cgal_limit")) return 64;
    const char* in = args.in;
    const char* out = args.out;
    const char* limit_mesh = args.limit_mesh;
    const int levels = args.levels;

    // 1. The mesh.
    Mesh mesh;
    if (!CGAL::IO::read_polygon_mesh(in, mesh) || !CGAL::is_valid_polygon_mesh(mesh)) {
        std::fprintf(stderr, "cgal_limit: cannot read %s as a valid polygon mesh\n", in);
        return 1;
    }
    std::printf("# ccss %s, CGAL %s\n", ccss_version(), CGAL_VERSION_STR);
    std::printf("mesh %s vertices=%zu faces=%zu edges=%zu\n", in,
                static_cast<size_t>(mesh.number_of_vertices()), static_cast<size_t>(mesh.number_of_faces()),
                static_cast<size_t>(mesh.number_of_edges()));

    // 2. Points and faces for ccss, in CGAL's numbering and orientation (a
    // freshly read Surface_mesh has no removed elements: indices are dense).
    std::vector<double> positions;
    std::vector<uint32_t> sizes, indices;
    for (Vertex v : mesh.vertices())
        for (int k = 0; k < 3; ++k) positions.push_back(mesh.point(v)[k]);
    for (Face f : mesh.faces()) {
        uint32_t n = 0;
        for (Vertex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
            indices.push_back(static_cast<uint32_t>(v.idx()));
            ++n;
        }
        sizes.push_back(n);
    }
    const ccss_host::Limit limit(positions, sizes, indices);
    std::printf("ccss patches regular=%zu extraordinary=%zu\n", limit.regular_patches(),
                limit.extraordinary_patches());

    // Limit positions and normals as Surface_mesh property maps.
    auto v_limit = mesh.add_property_map<Vertex, Point>("v:ccss_limit", CGAL::ORIGIN).first;
    auto v_normal = mesh.add_property_map<Vertex, Vector>("v:ccss_normal", CGAL::NULL_VECTOR).first;
    auto f_limit = mesh.add_property_map<Face, Point>("f:ccss_limit", CGAL::ORIGIN).first;
    auto f_normal = mesh.add_property_map<Face, Vector>("f:ccss_normal", CGAL::NULL_VECTOR).first;
    const auto corners = ccss_host::first_corners(mesh.number_of_vertices(), sizes, indices);
    std::vector<bool> used(mesh.number_of_vertices(), false);
    for (Vertex v : mesh.vertices()) {
        const ccss_host::Corner c = corners[v.idx()];
        if (c.face == UINT32_MAX) continue; // isolated vertex: not on the surface
        used[v.idx()] = true;
        const ccss_evaluator_result r = limit.corner(c.face, c.k);
        v_limit[v] = Point(r.p[0], r.p[1], r.p[2]);
        v_normal[v] = Vector(r.normal[0], r.normal[1], r.normal[2]);
    }
    for (Face f : mesh.faces()) {
        const ccss_evaluator_result r = limit.centre(static_cast<uint32_t>(f.idx()));
        f_limit[f] = Point(r.p[0], r.p[1], r.p[2]);
        f_normal[f] = Vector(r.normal[0], r.normal[1], r.normal[2]);
    }

    // 3. The output file, from the property maps.
    std::FILE* fo = std::fopen(out, "w");
    if (fo == nullptr) {
        std::fprintf(stderr, "cgal_limit: cannot write %s\n", out);
        return 1;
    }
    std::fprintf(fo, "# ccss limit of %s (CGAL Surface_mesh numbering)\n", in);
    std::fprintf(fo, "# v index control(3) limit(3) normal(3); f index centroid(3) limit(3) normal(3)\n");
    for (Vertex v : mesh.vertices()) {
        if (!used[v.idx()]) continue;
        const Point &c = mesh.point(v), &p = v_limit[v];
        const Vector& n = v_normal[v];
        std::fprintf(fo, "v %u %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                     static_cast<unsigned>(v.idx()), c.x(), c.y(), c.z(), p.x(), p.y(), p.z(), n.x(),
                     n.y(), n.z());
    }
    for (Face f : mesh.faces()) {
        const Point c = centroid(mesh, f), &p = f_limit[f];
        const Vector& n = f_normal[f];
        std::fprintf(fo, "f %u %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                     static_cast<unsigned>(f.idx()), c.x(), c.y(), c.z(), p.x(), p.y(), p.z(), n.x(),
                     n.y(), n.z());
    }
    if (std::fclose(fo) != 0) {
        std::fprintf(stderr, "cgal_limit: error writing %s\n", out);
        return 1;
    }
    std::printf("wrote %s\n", out);

    if (limit_mesh != nullptr) {
        Mesh lm = mesh; // same connectivity, points moved onto the limit surface
        for (Vertex v : lm.vertices())
            if (used[v.idx()]) lm.point(v) = v_limit[v];
        auto lm_normal = lm.property_map<Vertex, Vector>("v:ccss_normal").first;
        if (!CGAL::IO::write_polygon_mesh(limit_mesh, lm,
                                          CGAL::parameters::vertex_normal_map(lm_normal).stream_precision(17))) {
            std::fprintf(stderr, "cgal_limit: cannot write %s\n", limit_mesh);
            return 1;
        }
        std::printf("wrote %s\n", limit_mesh);
    }

    // 4. CGAL's Catmull-Clark subdivision, one level at a time.
    const size_t nv0 = mesh.number_of_vertices(), ne0 = mesh.number_of_edges(),
                 nf0 = mesh.number_of_faces();
    const double diag = ccss_host::bbox_diagonal(positions);
    std::vector<unsigned> valence(nv0);
    for (Vertex v : mesh.vertices()) valence[v.idx()] = mesh.degree(v);

    Mesh sub = mesh;
    ccss_host::Convergence conv(levels, diag);
    std::vector<double> normal_angle(static_cast<size_t>(levels) + 1, 0.0);
    for (int level = 1; level <= levels; ++level) {
        CGAL::Subdivision_method_3::CatmullClark_subdivision(
            sub, CGAL::parameters::number_of_iterations(1));
        if (level == 1) {
            // PQQ_1step keeps the old vertices, then inserts one vertex per
            // edge (edge order) and one per face (face order). Check it: the
            // face point of face f is its centroid and has its size as degree.
            if (sub.number_of_vertices() != nv0 + ne0 + nf0) {
                std::fprintf(stderr, "cgal_limit: level 1 has %zu vertices, expected %zu\n",
                             static_cast<size_t>(sub.number_of_vertices()), nv0 + ne0 + nf0);
                return 1;
            }
            for (Face f : mesh.faces()) {
                const Vertex fp(static_cast<Mesh::size_type>(nv0 + ne0 + f.idx()));
                const double e = ccss_host::dist(v3(sub.point(fp)), v3(centroid(mesh, f)));
                if (e > 1e-12 * diag || sub.degree(fp) != mesh.degree(f)) {
                    std::fprintf(stderr, "cgal_limit: vertex %u is not the face point of face %u\n",
                                 static_cast<unsigned>(fp.idx()), static_cast<unsigned>(f.idx()));
                    return 1;
                }
            }
            for (Vertex v : mesh.vertices()) {
                if (sub.degree(v) != valence[v.idx()]) {
                    std::fprintf(stderr, "cgal_limit: vertex %u changed valence\n",
                                 static_cast<unsigned>(v.idx()));
                    return 1;
                }
            }
        }
        const std::vector<Vector> vn = vertex_normals(sub);
        for (Vertex v : mesh.vertices()) {
            if (!used[v.idx()]) continue;
            const double d = ccss_host::dist(v3(sub.point(v)), v3(v_limit[v]));
            conv.add("vertex", valence[v.idx()], 0, level, d);
            const double c = std::max(-1.0, std::min(1.0, vn[v.idx()] * v_normal[v]));
            normal_angle[static_cast<size_t>(level)] =
                std::max(normal_angle[static_cast<size_t>(level)], std::acos(c));
        }
        for (Face f : mesh.faces()) {
            const Vertex fp(static_cast<Mesh::size_type>(nv0 + ne0 + f.idx()));
            const double d = ccss_host::dist(v3(sub.point(fp)), v3(f_limit[f]));
            conv.add("centre", mesh.degree(f), 1, level, d);
        }
        std::printf("level %d vertices=%zu faces=%zu\n", level,
                    static_cast<size_t>(sub.number_of_vertices()), static_cast<size_t>(sub.number_of_faces()));
    }

    // Distances are printed relative to the bounding-box diagonal.
    std::printf("bbox_diagonal %.17g\n", diag);
    const int failures = conv.report(limit.tables(), 0.10, 0.03, stdout);
    std::printf("normals vertex max_angle_rad");
    for (int l = 1; l <= levels; ++l) std::printf(" a%d=%.3e", l, normal_angle[static_cast<size_t>(l)]);
    std::printf(" (area-weighted vertex normals of CGAL's level L vs the exact limit normals)\n");
    return ccss_host::verdict(failures);
}

} // namespace

int main(int argc, char** argv)
{
    return ccss_host::guarded_main("cgal_limit", [&] { return run(argc, argv); });
}
