// boolean_ref.cpp: the reference mesh Boolean and the mesh measurements behind
// the oracle of `ccss boolean` (issue #25) and its benchmark. Plain C++17 on
// CGAL 5 (Debian: libcgal-dev); no ccss code, so it can judge ccss.
//
//   boolean_ref boolean union|intersection|difference A.obj B.obj OUT.obj [CURVE.obj] [--exact]
//       CGAL's corefinement Boolean (PMP::corefine_and_compute_*) of two closed
//       triangle meshes (polygons are fanned). Kernel: exact predicates,
//       inexact constructions (Epick), or exact constructions (Epeck) with
//       --exact; the result is written with double coordinates (triangles,
//       shared vertex indices). CURVE.obj receives the intersection polylines
//       of the two inputs (PMP::surface_intersection) as OBJ `l` lines.
//       Prints: triangles=T vertices=V seconds=S
//   boolean_ref check M.obj
//       Reads M by its indices (no vertex merging) and prints
//       triangles= vertices= polygon_mesh=0|1 closed=0|1 outward=0|1
//       self_intersecting=0|1 degenerate_faces=N components=C volume=V area=A
//       polygon_mesh: the faces form an oriented 2-manifold (with boundary)
//       over the file's vertex indices; closed/outward/self_intersecting/
//       volume are computed only when polygon_mesh=1 (else -).
//   boolean_ref hausdorff X.obj Y.obj T
//       Two-sided Hausdorff distance between the triangles of X and Y,
//       decided against the tolerance T by branch and bound (exact
//       point-to-triangle distances from an AABB tree, CGAL AABB_tree):
//       d(., Y) is 1-Lipschitz, so over a triangle of X with centroid c,
//       d <= d(c) + max |vertex - c|; triangles whose bound exceeds T are
//       split into four until they are certified below T, cannot raise the
//       maximum found by more than T/64, or their radius is <= T/64. Prints
//       x_to_y= y_to_x= hausdorff= (largest distances of probed points: true
//       lower bounds), upper= (a certified upper bound, <= max(T, hausdorff +
//       T/64)), certified_below=1 when upper <= T, violation=1 when
//       hausdorff > T, probes=, and the worst points worst_x= worst_y=.
//   boolean_ref distance M.obj POINTS.obj
//       Exact distance from every vertex of POINTS.obj and every midpoint of
//       its `l` segments to the triangles of M. Prints points= max= mean=
//       worst=(x,y,z).
//
// Exit status: 0 success, 1 usage or input error (one line `boolean_ref: error:`).
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Surface_mesh.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace PMP = CGAL::Polygon_mesh_processing;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using KE = CGAL::Exact_predicates_exact_constructions_kernel;
using P3 = K::Point_3;
using Mesh = CGAL::Surface_mesh<P3>;

struct Soup {
    std::vector<std::array<double, 3>> points;
    std::vector<std::vector<std::size_t>> faces;           // fanned to triangles
    std::vector<std::vector<std::size_t>> lines;           // `l` polylines
};

[[noreturn]] static void fail(const std::string &msg) {
    throw std::runtime_error(msg);
}

// OBJ: `v x y z`, `f a[/..] b c ...` (1-based or negative), `l a b ...`;
// everything else ignored. Polygons are fanned from their first corner.
static Soup read_obj(const std::string &path) {
    std::ifstream in(path);
    if (!in) fail(path + ": cannot open");
    Soup s;
    std::string line;
    std::size_t no = 0;
    auto index = [&](const std::string &tok) -> std::size_t {
        long i = 0;
        try {
            i = std::stol(tok.substr(0, tok.find('/')));
        } catch (...) {
            fail(path + ":" + std::to_string(no) + ": bad index '" + tok + "'");
        }
        long n = static_cast<long>(s.points.size());
        long k = i < 0 ? n + i : i - 1;
        if (i == 0 || k < 0 || k >= n)
            fail(path + ":" + std::to_string(no) + ": index " + tok + " out of range");
        return static_cast<std::size_t>(k);
    };
    while (std::getline(in, line)) {
        ++no;
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        if (tag == "v") {
            std::array<double, 3> p{};
            if (!(ls >> p[0] >> p[1] >> p[2]))
                fail(path + ":" + std::to_string(no) + ": bad vertex");
            s.points.push_back(p);
        } else if (tag == "f" || tag == "l") {
            std::vector<std::size_t> idx;
            std::string tok;
            while (ls >> tok) idx.push_back(index(tok));
            if (tag == "l") {
                if (idx.size() < 2) fail(path + ":" + std::to_string(no) + ": line with < 2 points");
                s.lines.push_back(idx);
                continue;
            }
            if (idx.size() < 3) fail(path + ":" + std::to_string(no) + ": face with < 3 corners");
            for (std::size_t k = 1; k + 1 < idx.size(); ++k)
                s.faces.push_back({idx[0], idx[k], idx[k + 1]});
        }
    }
    return s;
}

template <class M>
static bool soup_to_mesh(const Soup &s, M &m) {
    using Pt = typename boost::property_traits<
        typename boost::property_map<M, CGAL::vertex_point_t>::type>::value_type;
    std::vector<Pt> pts;
    pts.reserve(s.points.size());
    for (auto &p : s.points) pts.emplace_back(p[0], p[1], p[2]);
    if (!PMP::is_polygon_soup_a_polygon_mesh(s.faces)) return false;
    PMP::polygon_soup_to_polygon_mesh(pts, s.faces, m);
    return true;
}

template <class M>
static M read_closed(const std::string &path) {
    Soup s = read_obj(path);
    M m;
    if (!soup_to_mesh(s, m)) fail(path + ": the faces do not form an oriented 2-manifold");
    if (!CGAL::is_closed(m)) fail(path + ": not closed");
    return m;
}

static void write_obj(const std::string &path, const std::vector<std::array<double, 3>> &pts,
                      const std::vector<std::vector<std::size_t>> &faces, const char *tag) {
    std::FILE *f = std::fopen(path.c_str(), "w");
    if (!f) fail(path + ": cannot write");
    for (auto &p : pts) std::fprintf(f, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
    for (auto &fc : faces) {
        std::fputs(tag, f);
        for (auto i : fc) std::fprintf(f, " %zu", i + 1);
        std::fputc('\n', f);
    }
    if (std::fclose(f) != 0) fail(path + ": write failed");
}

template <class M>
static void write_mesh(const std::string &path, const M &m) {
    std::vector<std::array<double, 3>> pts;
    std::vector<std::vector<std::size_t>> faces;
    std::vector<std::size_t> id(m.number_of_vertices() + m.number_of_removed_vertices(), 0);
    for (auto v : m.vertices()) {
        id[v.idx()] = pts.size();
        auto &p = m.point(v);
        pts.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
    }
    for (auto f : m.faces()) {
        std::vector<std::size_t> fc;
        for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) fc.push_back(id[v.idx()]);
        faces.push_back(fc);
    }
    write_obj(path, pts, faces, "f");
}

template <class Kern>
static int run_boolean(const std::string &op, const std::string &a, const std::string &b,
                       const std::string &out, const std::string &curve) {
    using M = CGAL::Surface_mesh<typename Kern::Point_3>;
    M ma = read_closed<M>(a), mb = read_closed<M>(b), mo;
    auto t0 = std::chrono::steady_clock::now();
    if (!curve.empty()) {
        std::vector<std::vector<typename Kern::Point_3>> polylines;
        PMP::surface_intersection(ma, mb, std::back_inserter(polylines));
        std::vector<std::array<double, 3>> pts;
        std::vector<std::vector<std::size_t>> lines;
        for (auto &pl : polylines) {
            std::vector<std::size_t> l;
            for (auto &p : pl) {
                l.push_back(pts.size());
                pts.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
            }
            lines.push_back(l);
        }
        write_obj(curve, pts, lines, "l");
    }
    bool ok;
    if (op == "union")
        ok = PMP::corefine_and_compute_union(ma, mb, mo);
    else if (op == "intersection")
        ok = PMP::corefine_and_compute_intersection(ma, mb, mo);
    else if (op == "difference")
        ok = PMP::corefine_and_compute_difference(ma, mb, mo);
    else
        fail("unknown operation '" + op + "' (union, intersection, difference)");
    double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!ok) fail("CGAL corefinement could not compute the " + op + " (non-manifold result)");
    // Corefinement of triangle meshes yields triangles.
    write_mesh(out, mo);
    std::printf("triangles=%zu vertices=%zu seconds=%.4f\n", (std::size_t)mo.number_of_faces(),
                (std::size_t)mo.number_of_vertices(), secs);
    return 0;
}

static int run_check(const std::string &path) {
    Soup s = read_obj(path);
    Mesh m;
    bool pm = soup_to_mesh(s, m);
    std::size_t used = 0;
    {
        std::vector<char> u(s.points.size(), 0);
        for (auto &f : s.faces)
            for (auto i : f) u[i] = 1;
        for (char c : u) used += c;
    }
    std::printf("triangles=%zu vertices=%zu polygon_mesh=%d", s.faces.size(), used, pm ? 1 : 0);
    if (!pm) {
        std::printf(" closed=- outward=- self_intersecting=- degenerate_faces=- components=- volume=- area=-\n");
        return 0;
    }
    bool closed = CGAL::is_closed(m);
    std::size_t degenerate = 0;
    for (auto f : m.faces())
        if (PMP::is_degenerate_triangle_face(f, m)) ++degenerate;
    auto fcc = m.add_property_map<Mesh::Face_index, std::size_t>("f:cc", 0).first;
    std::size_t comps = PMP::connected_components(m, fcc);
    bool si = PMP::does_self_intersect(m);
    double area = CGAL::to_double(PMP::area(m));
    if (closed) {
        bool outward = PMP::is_outward_oriented(m);
        double vol = CGAL::to_double(PMP::volume(m));
        std::printf(" closed=1 outward=%d", outward ? 1 : 0);
        std::printf(" self_intersecting=%d degenerate_faces=%zu components=%zu volume=%.12g area=%.12g\n",
                    si ? 1 : 0, degenerate, comps, vol, area);
    } else {
        std::printf(" closed=0 outward=- self_intersecting=%d degenerate_faces=%zu components=%zu volume=- area=%.12g\n",
                    si ? 1 : 0, degenerate, comps, area);
    }
    return 0;
}

using Prim = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Prim>>;

static Mesh read_soup_mesh(const std::string &path) {
    // Distances only need the triangles: any soup is accepted (faces that do
    // not form a 2-manifold are added as separate triangles).
    Soup s = read_obj(path);
    Mesh m;
    std::vector<Mesh::Vertex_index> v;
    for (auto &p : s.points) v.push_back(m.add_vertex(P3(p[0], p[1], p[2])));
    for (auto &f : s.faces) {
        if (m.add_face(v[f[0]], v[f[1]], v[f[2]]) == Mesh::null_face()) {
            auto a = m.add_vertex(m.point(v[f[0]])), b = m.add_vertex(m.point(v[f[1]])),
                 c = m.add_vertex(m.point(v[f[2]]));
            m.add_face(a, b, c);
        }
    }
    if (m.number_of_faces() == 0) fail(path + ": no faces");
    return m;
}

struct OneSided {
    double lower = 0;      // largest distance found (a true distance)
    double upper = 0;      // certified bound on the sup over all points
    std::size_t probes = 0;
    P3 worst{0, 0, 0};
};

// One-sided distance sup_{p in X} d(p, Y) by branch and bound. d(., Y) is
// 1-Lipschitz, so over a triangle with centroid c and vertices v_i,
// d(p) <= d(c) + max_i |v_i - c|. A triangle is dropped when that bound is
// <= T (certified), or <= lower + T/64 (it cannot raise the maximum by more
// than the precision), or its radius is <= T/64, or once a distance above
// 2T has been found (a clear violation; `upper` stays an upper bound but
// loses its precision); others are split into four
// (edge midpoints). `upper`, the largest bound of a dropped triangle, is a
// certified upper bound (<= max(T, lower + T/64)); `lower`, the largest
// distance of a probed point, is a true distance. So upper <= T certifies
// the distance below T, lower > T proves a violation, and above T the
// distance is known within T/64.
static OneSided one_sided(const Mesh &x, const Tree &ty, double tol) {
    OneSided r;
    auto dist = [&](const P3 &p) {
        double d = std::sqrt(ty.squared_distance(p));
        ++r.probes;
        if (d > r.lower) {
            r.lower = d;
            r.worst = p;
        }
        return d;
    };
    for (auto v : x.vertices()) dist(x.point(v));
    struct Tri { P3 a, b, c; };
    std::vector<Tri> stack;
    const double leaf = tol / 64;
    for (auto f : x.faces()) {
        auto h0 = x.halfedge(f);
        stack.push_back({x.point(x.source(h0)), x.point(x.target(h0)), x.point(x.target(x.next(h0)))});
        while (!stack.empty()) {
            Tri t = stack.back();
            stack.pop_back();
            P3 c = CGAL::centroid(t.a, t.b, t.c);
            double rad = std::sqrt(std::max({CGAL::squared_distance(c, t.a), CGAL::squared_distance(c, t.b),
                                             CGAL::squared_distance(c, t.c)}));
            double bound = dist(c) + rad;
            // Pruned: certified below T, or unable to raise the maximum by
            // more than the precision T/64; leaves are T/64 small.
            if (bound <= tol || bound <= r.lower + leaf || rad <= leaf || r.lower > 2 * tol) {
                r.upper = std::max(r.upper, bound);
                continue;
            }
            P3 ab = CGAL::midpoint(t.a, t.b), bc = CGAL::midpoint(t.b, t.c), ca = CGAL::midpoint(t.c, t.a);
            stack.push_back({t.a, ab, ca});
            stack.push_back({ab, t.b, bc});
            stack.push_back({ca, bc, t.c});
            stack.push_back({ab, bc, ca});
        }
    }
    r.upper = std::max(r.upper, r.lower);
    return r;
}

static int run_hausdorff(const std::string &xp, const std::string &yp, double tol) {
    if (!(tol > 0) || !std::isfinite(tol)) fail("the tolerance T must be positive");
    Mesh x = read_soup_mesh(xp), y = read_soup_mesh(yp);
    Tree tx(faces(x).first, faces(x).second, x), ty(faces(y).first, faces(y).second, y);
    tx.accelerate_distance_queries();
    ty.accelerate_distance_queries();
    OneSided xy = one_sided(x, ty, tol), yx = one_sided(y, tx, tol);
    double lower = std::max(xy.lower, yx.lower), upper = std::max(xy.upper, yx.upper);
    std::printf("x_to_y=%.9g y_to_x=%.9g hausdorff=%.9g upper=%.9g certified_below=%d violation=%d "
                "probes=%zu worst_x=(%.6g,%.6g,%.6g) worst_y=(%.6g,%.6g,%.6g)\n",
                xy.lower, yx.lower, lower, upper, upper <= tol ? 1 : 0, lower > tol ? 1 : 0,
                xy.probes + yx.probes, xy.worst.x(), xy.worst.y(), xy.worst.z(), yx.worst.x(),
                yx.worst.y(), yx.worst.z());
    return 0;
}

static int run_distance(const std::string &mp, const std::string &pp) {
    Mesh m = read_soup_mesh(mp);
    Soup pts = read_obj(pp);
    Tree t(faces(m).first, faces(m).second, m);
    t.accelerate_distance_queries();
    double mx = 0, sum = 0;
    std::size_t n = 0;
    P3 worst(0, 0, 0);
    auto probe = [&](const P3 &p) {
        double d = std::sqrt(t.squared_distance(p));
        sum += d;
        ++n;
        if (d > mx) {
            mx = d;
            worst = p;
        }
    };
    auto pt = [&](std::size_t i) { return P3(pts.points[i][0], pts.points[i][1], pts.points[i][2]); };
    for (std::size_t i = 0; i < pts.points.size(); ++i) probe(pt(i));
    for (auto &l : pts.lines)
        for (std::size_t k = 0; k + 1 < l.size(); ++k)
            probe(CGAL::midpoint(pt(l[k]), pt(l[k + 1])));
    if (n == 0) fail(pp + ": no points");
    std::printf("points=%zu max=%.9g mean=%.9g worst=(%.6g,%.6g,%.6g)\n", n, mx, sum / n, worst.x(),
                worst.y(), worst.z());
    return 0;
}

static int usage() {
    std::fprintf(stderr,
                 "usage: boolean_ref boolean union|intersection|difference A.obj B.obj OUT.obj [CURVE.obj] [--exact]\n"
                 "       boolean_ref check M.obj\n"
                 "       boolean_ref hausdorff X.obj Y.obj T\n"
                 "       boolean_ref distance M.obj POINTS.obj\n");
    return 1;
}

int main(int argc, char **argv) {
    std::vector<std::string> a(argv + 1, argv + argc);
    try {
        if (a.size() >= 5 && a[0] == "boolean") {
            bool exact = false;
            std::vector<std::string> rest;
            for (std::size_t i = 1; i < a.size(); ++i) {
                if (a[i] == "--exact")
                    exact = true;
                else
                    rest.push_back(a[i]);
            }
            if (rest.size() != 4 && rest.size() != 5) return usage();
            std::string curve = rest.size() == 5 ? rest[4] : "";
            return exact ? run_boolean<KE>(rest[0], rest[1], rest[2], rest[3], curve)
                         : run_boolean<K>(rest[0], rest[1], rest[2], rest[3], curve);
        }
        if (a.size() == 2 && a[0] == "check") return run_check(a[1]);
        if (a.size() == 4 && a[0] == "hausdorff") return run_hausdorff(a[1], a[2], std::atof(a[3].c_str()));
        if (a.size() == 3 && a[0] == "distance") return run_distance(a[1], a[2]);
        return usage();
    } catch (const std::exception &e) {
        std::fprintf(stderr, "boolean_ref: error: %s\n", e.what());
        return 1;
    }
}
