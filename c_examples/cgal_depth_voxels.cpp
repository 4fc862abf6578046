// cgal_depth_voxels.cpp: ccss's subdivision depths checked against CGAL's
// Catmull-Clark subdivision, and ccss's voxelization checked against CGAL's
// point-in-mesh test, on a CGAL Surface_mesh.
//
//   cgal_depth_voxels MESH [--eps E] [--method best|new|tight|old]
//                          [--max-level L] [--res R] [--check-tol T]
//
// Reads MESH with CGAL::IO::read_polygon_mesh into a Surface_mesh with double
// coordinates and hands its points and faces to ccss
// (c_examples/hosts/ccss_host.hpp). Then:
//
// A. Depth. ccss_depth_compute gives, per (face, sub-face) slot s, the depth d(s)
//    for tolerance E (default 0.001, model units): after d(s) uniform
//    Catmull-Clark steps of the base mesh, every control face of the slot,
//    taken as the bilinear map L of its four control points over its
//    parameter cell, is within E of the limit surface at the same parameter:
//    |L(u,v) - S(u,v)| <= E (core/src/depth.rs; ccss.h, ccss_depth_compute). That is
//    what is checked, with CGAL's control points: the base mesh is
//    subdivided by CGAL::Subdivision_method_3::CatmullClark_subdivision one
//    level at a time up to D = max d(s) (at most L, default 6). Every face of
//    every level carries its slot and the (u, v) of its corners, derived from
//    CGAL's numbering (old vertices keep their index, then one vertex per
//    edge in edge order, one per face in face order; checked at every level
//    against the old mesh's edges). At level d(s) (level 1 for a sub-face of
//    an n-gon, which only exists from level 1 on) each control face of slot s
//    is sampled at the 3x3 points s, t in {0, 1/2, 1} of its bilinear map
//    (its corners, i.e. CGAL's control vertices against their own limit
//    points, edge midpoints and centre) against ccss_evaluator_eval at the bilinearly
//    interpolated parameter; a distance above T (default E) is a violation.
//    Also printed, not a guarantee: the largest distance one level before
//    d(s) (how conservative the depth is) and at levels after d(s) up to D.
//
// B. Voxels. ccss_voxel_grid_voxelize (6-adjacency: "no holes") and ccss_voxel_grid_flood on
//    an R^3 grid (default 32), then a ccss tessellation of the same surface
//    to absolute flatness e_t = 1/20 voxel as a CGAL triangle mesh: CGAL's
//    AABB tree gives each voxel centre's distance to it, CGAL's
//    Side_of_triangle_mesh its side. Checked:
//     * white voxels (outside or interior) whose centre is farther than the
//       margin e_t from the triangles (then it is on the same side of the
//       exact limit surface: the triangles are within e_t of it) are
//       interior exactly when CGAL says ON_BOUNDED_SIDE; closer ones are
//       skipped and counted;
//     * the 6-adjacency guarantee behind it: a limit-surface point in a white
//       voxel lies within CCSS_VOXEL_GRID_TAU (1e-6) voxel of a black one, so
//       white centres are at least (0.5 - CCSS_VOXEL_GRID_TAU) voxel from the
//       surface; checked as "at least 0.5 - CCSS_VOXEL_GRID_TAU - e_t voxel from
//       the triangles";
//     * every surface voxel contains a limit point: its centre is at most
//       sqrt(3)/2 voxel + e_t from the triangles;
//     * the exact volume (ccss_mass_properties_compute) lies between the interior voxels'
//       volume and the interior plus surface voxels' volume.
//
// Prints key=value lines and "PASS: 0 failure(s)", or FAIL lines and exits
// with status 2.
//
// Build: see c_examples/hosts/CMakeLists.txt.
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/subdivision_method_3.h>
#include <CGAL/version.h>

#include "ccss_host.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

namespace {

typedef CGAL::Simple_cartesian<double> Kernel;
typedef Kernel::Point_3 Point;
typedef CGAL::Surface_mesh<Point> Mesh;
typedef Mesh::Vertex_index Vertex;
typedef Mesh::Face_index Face;
typedef CGAL::AABB_face_graph_triangle_primitive<Mesh> Primitive;
typedef CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>> Tree;

std::vector<uint32_t> face_vertices(const Mesh& m, Face f)
{
    std::vector<uint32_t> v;
    for (Vertex x : CGAL::vertices_around_face(m.halfedge(f), m)) v.push_back(static_cast<uint32_t>(x.idx()));
    return v;
}

/// A face of the level-k mesh: its slot (-1 for an n-gon of level 0, which
/// has no chart of its own) and its corners in CGAL's order around it, each
/// a vertex index and its (u, v) in the slot.
struct Rec {
    int slot = -1;
    std::vector<uint32_t> v;
    std::vector<std::array<double, 2>> uv;
};

/// Largest distance and sample count of one kind of check.
struct Worst {
    double max = 0.0, vertex_max = 0.0;
    size_t samples = 0, violations = 0;
};

// -------------------------------------------------------------------------
// A. Depth.

int check_depth(const Mesh& mesh, const ccss_host::Limit& limit, double eps, ccss_depth_method method,
                const char* method_name, int max_level, double check_tol)
{
    const auto slots = limit.slots();
    const std::vector<uint32_t> depth = limit.depths(eps, method);
    // The level at which slot s is checked: its depth, at least 1 for a
    // sub-face of an n-gon.
    std::vector<int> need(slots.size());
    int top = 0;
    size_t ngon_depth0 = 0;
    for (size_t s = 0; s < slots.size(); ++s) {
        if (depth[s] == UINT32_MAX) throw std::runtime_error("ccss_depth_compute gave no bound for a slot");
        need[s] = static_cast<int>(depth[s]);
        if (limit.face_size(slots[s].face) != 4 && need[s] == 0) {
            need[s] = 1;
            ++ngon_depth0;
        }
        top = std::max(top, need[s]);
    }
    std::vector<size_t> hist(static_cast<size_t>(top) + 1, 0);
    for (int n : need) ++hist[static_cast<size_t>(n)];
    std::printf("depth method=%s eps=%.6g slots=%zu max_depth=%d ngon_depth0=%zu histogram=", method_name,
                eps, slots.size(), top, ngon_depth0);
    for (size_t l = 0; l < hist.size(); ++l) std::printf("%s%zu", l ? "," : "", hist[l]);
    std::printf("\n");
    for (const auto& [name, m] : {std::pair<const char*, ccss_depth_method>{"old", CCSS_DEPTH_OLD},
                                  {"new", CCSS_DEPTH_NEW},
                                  {"tight", CCSS_DEPTH_TIGHT},
                                  {"best", CCSS_DEPTH_BEST}}) {
        const auto d = limit.depths(eps, m);
        std::printf("depth_%s max=%u\n", name, *std::max_element(d.begin(), d.end()));
    }
    if (top > max_level) {
        std::fprintf(stderr, "cgal_depth_voxels: depth %d > --max-level %d (choose a larger --eps)\n", top,
                     max_level);
        return -1;
    }

    // Level 0: quads are their own slot; n-gons get theirs at level 1.
    Mesh cur = mesh;
    std::vector<Rec> recs;
    for (Face f : cur.faces()) {
        Rec r;
        r.v = face_vertices(cur, f);
        if (r.v.size() == 4) {
            r.slot = static_cast<int>(limit.slot_start(static_cast<uint32_t>(f.idx())));
            r.uv = {{{0, 0}}, {{1, 0}}, {{1, 1}}, {{0, 1}}};
        }
        recs.push_back(std::move(r));
    }

    Worst at, before, after;
    std::vector<bool> checked(slots.size(), false);
    for (int level = 0;; ++level) {
        // Sample every control face of this level whose slot is due.
        for (const Rec& r : recs) {
            if (r.slot < 0) continue;
            const int n = need[static_cast<size_t>(r.slot)];
            Worst* w = level == n ? &at : level == n - 1 ? &before : level > n ? &after : nullptr;
            if (w == nullptr) continue;
            if (level == n) checked[static_cast<size_t>(r.slot)] = true;
            const auto& sl = slots[static_cast<size_t>(r.slot)];
            for (int a = 0; a <= 2; ++a) {
                for (int b = 0; b <= 2; ++b) {
                    const double s = 0.5 * a, t = 0.5 * b;
                    const double wt[4] = {(1 - s) * (1 - t), s * (1 - t), s * t, (1 - s) * t};
                    ccss_host::Vec3 p{0, 0, 0};
                    double u = 0, v = 0;
                    for (int c = 0; c < 4; ++c) {
                        const Point& q = cur.point(Vertex(r.v[static_cast<size_t>(c)]));
                        for (int k = 0; k < 3; ++k) p[k] += wt[c] * q[k];
                        u += wt[c] * r.uv[static_cast<size_t>(c)][0];
                        v += wt[c] * r.uv[static_cast<size_t>(c)][1];
                    }
                    const ccss_evaluator_result e = limit.eval(sl.face, sl.sub, u, v);
                    const double d = ccss_host::dist(p, {e.p[0], e.p[1], e.p[2]});
                    w->max = std::max(w->max, d);
                    if (a != 1 && b != 1) w->vertex_max = std::max(w->vertex_max, d);
                    ++w->samples;
                    if (level == n && !(d <= check_tol)) ++w->violations;
                }
            }
        }
        std::printf("level %d vertices=%zu faces=%zu\n", level, static_cast<size_t>(cur.number_of_vertices()),
                    static_cast<size_t>(cur.number_of_faces()));
        if (level == top) break;

        // One CGAL step, and the new faces' slots and corner parameters.
        const size_t nv = cur.number_of_vertices(), ne = cur.number_of_edges(), nf = cur.number_of_faces();
        std::vector<std::array<uint32_t, 2>> edge(ne);
        for (auto e : cur.edges())
            edge[e.idx()] = {static_cast<uint32_t>(cur.source(cur.halfedge(e)).idx()),
                             static_cast<uint32_t>(cur.target(cur.halfedge(e)).idx())};
        CGAL::Subdivision_method_3::CatmullClark_subdivision(cur, CGAL::parameters::number_of_iterations(1));
        if (cur.number_of_vertices() != nv + ne + nf)
            throw std::runtime_error("CGAL's Catmull-Clark step made an unexpected number of vertices");
        auto joins = [&](uint32_t edge_point, uint32_t a, uint32_t b) {
            if (edge_point < nv || edge_point >= nv + ne) return false;
            const auto& e = edge[edge_point - nv];
            return (e[0] == a && e[1] == b) || (e[0] == b && e[1] == a);
        };
        std::vector<Rec> next;
        next.reserve(cur.number_of_faces());
        for (Face g : cur.faces()) {
            Rec r;
            r.v = face_vertices(cur, g);
            size_t a = 0;
            while (a < r.v.size() && r.v[a] >= nv) ++a;
            if (r.v.size() != 4 || a == 4 || r.v[(a + 2) % 4] < nv + ne)
                throw std::runtime_error("CGAL's Catmull-Clark face is not (old vertex, edge, face, edge point)");
            const Rec& f = recs.at(r.v[(a + 2) % 4] - nv - ne);
            const size_t n = f.v.size();
            const size_t j = static_cast<size_t>(std::find(f.v.begin(), f.v.end(), r.v[a]) - f.v.begin());
            if (j == n || !joins(r.v[(a + 1) % 4], f.v[j], f.v[(j + 1) % n]) ||
                !joins(r.v[(a + 3) % 4], f.v[(j + n - 1) % n], f.v[j]))
                throw std::runtime_error("CGAL's Catmull-Clark numbering is not the expected one");
            std::array<double, 2> pv, e1, c, e2;
            if (f.slot >= 0) { // same slot, one quadrant of the parent's cell
                r.slot = f.slot;
                const auto &p0 = f.uv[j], &pn = f.uv[(j + 1) % 4], &pp = f.uv[(j + 3) % 4];
                pv = p0;
                e1 = {(p0[0] + pn[0]) / 2, (p0[1] + pn[1]) / 2};
                e2 = {(p0[0] + pp[0]) / 2, (p0[1] + pp[1]) / 2};
                c = {(f.uv[0][0] + f.uv[1][0] + f.uv[2][0] + f.uv[3][0]) / 4,
                     (f.uv[0][1] + f.uv[1][1] + f.uv[2][1] + f.uv[3][1]) / 4};
            } else { // sub-face j of an n-gon: (0,0) vertex j, (1,0) towards j+1, (1,1) centre
                r.slot = static_cast<int>(limit.slot_start(static_cast<uint32_t>(&f - recs.data())) + j);
                pv = {0, 0}, e1 = {1, 0}, c = {1, 1}, e2 = {0, 1};
            }
            r.uv.resize(4);
            r.uv[a] = pv, r.uv[(a + 1) % 4] = e1, r.uv[(a + 2) % 4] = c, r.uv[(a + 3) % 4] = e2;
            next.push_back(std::move(r));
        }
        recs.swap(next);
    }

    size_t unchecked = 0;
    for (bool c : checked) unchecked += c ? 0 : 1;
    std::printf("depth_check check_tol=%.6g slots_checked=%zu unchecked=%zu samples=%zu violations=%zu "
                "max_dist=%.3e max_ratio=%.4f vertex_max_ratio=%.4f\n",
                check_tol, slots.size() - unchecked, unchecked, at.samples, at.violations, at.max,
                at.max / eps, at.vertex_max / eps);
    std::printf("depth_info before_max_ratio=%.4f after_max_ratio=%.4f (one level before the depth; "
                "levels after it up to %d)\n",
                before.max / eps, after.max / eps, top);
    int failures = 0;
    if (at.violations != 0) {
        std::printf("FAIL depth: %zu samples farther than %.6g from the limit surface (max %.6g)\n",
                    at.violations, check_tol, at.max);
        ++failures;
    }
    if (unchecked != 0) {
        std::printf("FAIL depth: %zu slots never checked\n", unchecked);
        ++failures;
    }
    return failures;
}

// -------------------------------------------------------------------------
// B. Voxels.

int check_voxels(const ccss_host::Limit& limit, uint32_t res)
{
    const ccss_host::Voxels vox(limit, {res, res, res}, 6);
    const double scale = vox.transform.scale; // voxels per model unit
    const uint64_t total = uint64_t(res) * res * res;
    std::printf("voxels res=%u adjacency=6 surface=%llu interior=%llu outside=%llu scale=%.6g "
                "guard_hits=%llu enclosed_components=%u inside_components=%u unresolved=%u\n",
                res, static_cast<unsigned long long>(vox.surface), static_cast<unsigned long long>(vox.interior),
                static_cast<unsigned long long>(total - vox.surface - vox.interior), scale,
                static_cast<unsigned long long>(vox.voxel_stats.guard_hits), vox.flood_stats.enclosed_components,
                vox.flood_stats.inside_components, vox.flood_stats.unresolved);

    // The tessellation, 1/20 voxel flat, as a CGAL triangle mesh.
    const double eps_t = 0.05 / scale;
    const ccss_host::Tessellation t = ccss_host::tessellate(limit, ccss_host::absolute_flatness(eps_t));
    Mesh tm;
    for (size_t i = 0; i < t.counts.vertices; ++i)
        tm.add_vertex(Point(t.positions[3 * i], t.positions[3 * i + 1], t.positions[3 * i + 2]));
    size_t add_failures = 0;
    for (size_t k = 0; k < t.counts.triangles; ++k) {
        const Face f = tm.add_face(Vertex(t.triangles[3 * k]), Vertex(t.triangles[3 * k + 1]),
                                   Vertex(t.triangles[3 * k + 2]));
        if (f == Mesh::null_face()) ++add_failures;
    }
    const bool closed = add_failures == 0 && CGAL::is_closed(tm);
    std::printf("voxel_tess eps=%.6g (%.3f voxel) triangles=%zu bound=%.6g closed=%d\n", eps_t, eps_t * scale,
                t.counts.triangles, t.counts.bound, closed ? 1 : 0);
    if (!closed) {
        std::printf("FAIL voxels: the tessellation is not a closed triangle mesh\n");
        return 1;
    }
    Tree tree(faces(tm).first, faces(tm).second, tm);
    tree.accelerate_distance_queries();
    const CGAL::Side_of_triangle_mesh<Mesh, Kernel> side(tm);

    // Distances below in voxel units.
    const double margin = eps_t * scale, clearance = 0.5 - CCSS_VOXEL_GRID_TAU - margin, reach = std::sqrt(3.0) / 2 + margin;
    size_t checked_interior = 0, checked_outside = 0, disagree = 0, skipped = 0, surface_far = 0,
           clearance_violations = 0;
    double surface_max = 0.0, white_min = HUGE_VAL;
    for (uint32_t k = 0; k < res; ++k) {
        for (uint32_t j = 0; j < res; ++j) {
            for (uint32_t i = 0; i < res; ++i) {
                const uint32_t c = vox.cls(i, j, k);
                const ccss_host::Vec3 p = vox.centre(i, j, k);
                const Point q(p[0], p[1], p[2]);
                const double d = std::sqrt(tree.squared_distance(q)) * scale;
                if (c == 1) {
                    surface_max = std::max(surface_max, d);
                    if (!(d <= reach)) ++surface_far;
                    continue;
                }
                white_min = std::min(white_min, d);
                if (!(d >= clearance)) ++clearance_violations;
                if (!(d > margin)) {
                    ++skipped;
                    continue;
                }
                const bool inside = side(q) == CGAL::ON_BOUNDED_SIDE;
                if (inside != (c == 2)) ++disagree;
                ++(c == 2 ? checked_interior : checked_outside);
            }
        }
    }
    std::printf("voxel_check margin_vox=%.3f checked_interior=%zu checked_outside=%zu disagree=%zu "
                "skipped=%zu\n",
                margin, checked_interior, checked_outside, disagree, skipped);
    std::printf("voxel_surface far=%zu max_dist_vox=%.4f limit_vox=%.4f\n", surface_far, surface_max, reach);
    std::printf("voxel_clearance violations=%zu min_white_dist_vox=%.4f limit_vox=%.4f\n", clearance_violations,
                white_min, clearance);

    ccss_mass_properties mp;
    ccss_error_detail det;
    const ccss_status st = ccss_mass_properties_compute(limit.evaluator(), &mp, &det);
    if (st != CCSS_OK) throw ccss_host::error("ccss_mass_properties_compute", st, &det);
    const double cell = 1.0 / (scale * scale * scale);
    const double lo = double(vox.interior) * cell, hi = double(vox.interior + vox.surface) * cell;
    const double tri_vol = CGAL::Polygon_mesh_processing::volume(tm);
    const bool bracket = lo <= mp.volume + mp.volume_error_bound && mp.volume - mp.volume_error_bound <= hi;
    std::printf("voxel_volume interior=%.6g interior_plus_surface=%.6g exact=%.6g triangles=%.6g bracket=%d\n",
                lo, hi, mp.volume, tri_vol, bracket ? 1 : 0);

    int failures = 0;
    auto fail = [&failures](bool bad, const char* what) {
        if (bad) {
            std::printf("FAIL voxels: %s\n", what);
            ++failures;
        }
    };
    fail(disagree != 0, "ccss's interior differs from CGAL's Side_of_triangle_mesh");
    fail(checked_interior + checked_outside == 0, "no white voxel checked");
    fail(surface_far != 0, "a surface voxel is too far from the surface");
    fail(clearance_violations != 0, "a white voxel's centre is too close to the surface");
    fail(!bracket, "the exact volume is not between the voxel volumes");
    fail(vox.voxel_stats.guard_hits != 0 || vox.flood_stats.unresolved != 0,
         "voxelization or flood not certified (guard hits / unresolved regions)");
    return failures;
}

int run(int argc, char** argv)
{
    const char* in = nullptr;
    double eps = 0.001, check_tol = 0.0;
    int max_level = 6, res = 32;
    std::string method = "best";
    bool bad = false;
    for (int i = 1; i < argc; ++i) {
        const bool more = i + 1 < argc;
        if (std::strcmp(argv[i], "--eps") == 0 && more) eps = std::atof(argv[++i]);
        else if (std::strcmp(argv[i], "--method") == 0 && more) method = argv[++i];
        else if (std::strcmp(argv[i], "--max-level") == 0 && more) max_level = std::atoi(argv[++i]);
        else if (std::strcmp(argv[i], "--res") == 0 && more) res = std::atoi(argv[++i]);
        else if (std::strcmp(argv[i], "--check-tol") == 0 && more) check_tol = std::atof(argv[++i]);
        else if (in == nullptr) in = argv[i];
        else bad = true;
    }
    const ccss_depth_method m = method == "old"     ? CCSS_DEPTH_OLD
                                : method == "new"   ? CCSS_DEPTH_NEW
                                : method == "tight" ? CCSS_DEPTH_TIGHT
                                                    : CCSS_DEPTH_BEST;
    if (method != "old" && method != "new" && method != "tight" && method != "best") bad = true;
    if (bad || in == nullptr || !(eps > 0.0) || check_tol < 0.0 || max_level < 0 || max_level > 8 || res < 4 ||
        res > 256) {
        std::fprintf(stderr, "usage: cgal_depth_voxels MESH [--eps E] [--method best|new|tight|old] "
                             "[--max-level 0..8] [--res 4..256] [--check-tol T]\n");
        return 64;
    }
    if (check_tol == 0.0) check_tol = eps;

    Mesh mesh;
    if (!CGAL::IO::read_polygon_mesh(in, mesh) || !CGAL::is_valid_polygon_mesh(mesh)) {
        std::fprintf(stderr, "cgal_depth_voxels: cannot read %s as a valid polygon mesh\n", in);
        return 1;
    }
    std::printf("# ccss %s, CGAL %s\n", ccss_version(), CGAL_VERSION_STR);
    std::printf("mesh %s vertices=%zu faces=%zu edges=%zu\n", in, static_cast<size_t>(mesh.number_of_vertices()),
                static_cast<size_t>(mesh.number_of_faces()), static_cast<size_t>(mesh.number_of_edges()));
    // Points and faces for ccss in CGAL's numbering (a freshly read
    // Surface_mesh has dense indices).
    std::vector<double> positions;
    std::vector<uint32_t> sizes, indices;
    for (Vertex v : mesh.vertices())
        for (int k = 0; k < 3; ++k) positions.push_back(mesh.point(v)[k]);
    for (Face f : mesh.faces()) {
        const auto fv = face_vertices(mesh, f);
        indices.insert(indices.end(), fv.begin(), fv.end());
        sizes.push_back(static_cast<uint32_t>(fv.size()));
    }
    const ccss_host::Limit limit(positions, sizes, indices);
    std::printf("ccss patches regular=%zu extraordinary=%zu\n", limit.regular_patches(),
                limit.extraordinary_patches());

    const int depth_failures = check_depth(mesh, limit, eps, m, method.c_str(), max_level, check_tol);
    if (depth_failures < 0) return 1;
    const int failures = depth_failures + check_voxels(limit, static_cast<uint32_t>(res));
    return ccss_host::verdict(failures);
}

} // namespace

int main(int argc, char** argv)
{
    return ccss_host::guarded_main("cgal_depth_voxels", [&] { return run(argc, argv); });
}
