// ccss_host.hpp: the part of the C++ host examples (openmesh_limit.cpp,
// cgal_limit.cpp, openmesh_tessellate.cpp, cgal_depth_voxels.cpp) that does
// not depend on the host's mesh library.
//
//  * ccss_host::Limit   owns the ccss tables, topology and evaluator of one
//                       mesh (malloc'd blocks, sizes asked first, as in
//                       c_examples/eval.c) and evaluates the exact limit
//                       surface at a vertex (a face corner) or a face centre;
//                       its (face, sub-face) slots and their subdivision
//                       depths (c_examples/depth.c).
//  * ccss_host::tessellate  an adaptive tessellation of a Limit, emitted into
//                       std::vectors (c_examples/tessellate.c).
//  * ccss_host::Voxels  a voxelized and flooded grid of a Limit
//                       (c_examples/voxelize.c).
//  * ccss_host::LimitArgs  the command line of openmesh_limit and cgal_limit.
//  * ccss_host::verdict, ccss_host::guarded_main  the programs' common ending
//                       ("PASS"/"FAIL" line, exit status 0 / 2; exceptions
//                       reported on stderr with status 1).
//  * ccss_host::Convergence  collects, per group of vertices (vertex or face
//                       centre, by valence), the largest distance between a
//                       peer subdivider's control points after L levels and
//                       our limit positions, and checks that it shrinks at the
//                       rate the Catmull-Clark spectrum predicts.
//
// Only <ccss.h> and the C++17 standard library. Header-only. (The OpenMesh
// examples' input arrays: openmesh_input.hpp.)
#ifndef CCSS_HOST_HPP
#define CCSS_HOST_HPP

#include <ccss.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ccss_host {

using Vec3 = std::array<double, 3>;

inline double dist(const Vec3& a, const Vec3& b)
{
    const double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return std::sqrt(x * x + y * y + z * z);
}

/// A ccss failure as an exception: the function, the status and the detail
/// message (which names the offending face / vertex / edge).
inline std::runtime_error error(const char* what, ccss_status st, const ccss_error_detail* d)
{
    std::string msg = std::string(what) + ": " + ccss_status_message(static_cast<int>(st));
    if (d != nullptr) {
        char buf[CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
        ccss_error_detail_format(d, buf, sizeof buf);
        msg += std::string(" (") + buf + ")";
    }
    return std::runtime_error(msg);
}

/// One ccss memory block (malloc is 8-byte aligned, as ccss requires).
struct Block {
    std::unique_ptr<void, void (*)(void*)> mem{nullptr, std::free};
    size_t bytes = 0;
    void alloc(size_t n)
    {
        mem.reset(std::malloc(n == 0 ? 1 : n));
        if (!mem) throw std::bad_alloc();
        bytes = n;
    }
    void* get() const { return mem.get(); }
};

/// The exact limit surface of one closed polygon mesh.
class Limit {
public:
    /// `positions`: x y z per vertex; `face_sizes`: vertices per face;
    /// `indices`: the faces' vertex indices, counter-clockwise from outside.
    Limit(const std::vector<double>& positions, const std::vector<uint32_t>& face_sizes,
          const std::vector<uint32_t>& indices)
        : face_sizes_(face_sizes)
    {
        ccss_error_detail d;
        size_t n = 0;
        ccss_status st = ccss_tables_required_bytes(&n, nullptr);
        if (st != CCSS_OK) throw error("ccss_tables_required_bytes", st, nullptr);
        tables_mem_.alloc(n);
        st = ccss_tables_build_standard(tables_mem_.get(), n, &tables_, nullptr);
        if (st != CCSS_OK) throw error("ccss_tables_build_standard", st, nullptr);

        const size_t nv = positions.size() / 3;
        st = ccss_topology_required_bytes(nv, face_sizes.data(), face_sizes.size(), &n, nullptr);
        if (st != CCSS_OK) throw error("ccss_topology_required_bytes", st, nullptr);
        // The evaluator does not need the topology; a tessellation does.
        topo_mem_.alloc(n);
        st = ccss_topology_build(positions.data(), nv, face_sizes.data(), face_sizes.size(),
                                 indices.data(), indices.size(), topo_mem_.get(), n, &topo_, &d);
        if (st != CCSS_OK) throw error("ccss_topology_build", st, &d);

        st = ccss_evaluator_required_bytes(topo_, tables_, &n, &d);
        if (st != CCSS_OK) throw error("ccss_evaluator_required_bytes", st, &d);
        eval_mem_.alloc(n);
        st = ccss_evaluator_build(topo_, tables_, eval_mem_.get(), n, &ev_, &d);
        if (st != CCSS_OK) throw error("ccss_evaluator_build", st, &d);
        size_t reg = 0, ext = 0;
        ccss_evaluator_patch_counts(ev_, &reg, &ext, nullptr);
        regular_patches_ = reg;
        extraordinary_patches_ = ext;
    }

    Limit(const Limit&) = delete;
    Limit& operator=(const Limit&) = delete;

    ccss_evaluator_result eval(uint32_t face, uint32_t sub, double u, double v) const
    {
        ccss_evaluator_result r;
        const ccss_status st = ccss_evaluator_eval(ev_, face, sub, u, v, &r, nullptr);
        if (st != CCSS_OK) throw error("ccss_evaluator_eval", st, nullptr);
        return r;
    }

    /// The limit point of the vertex at corner `k` of face `face`: for a quad
    /// the corner's (u, v) (0,0) (1,0) (1,1) (0,1); for an n-gon sub-face k
    /// at (0, 0).
    ccss_evaluator_result corner(uint32_t face, uint32_t k) const
    {
        if (face_sizes_.at(face) == 4) {
            static const double uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            return eval(face, 0, uv[k][0], uv[k][1]);
        }
        return eval(face, k, 0.0, 0.0);
    }

    /// The limit point of the centre of face `face`: (0.5, 0.5) of a quad,
    /// (1, 1) of sub-face 0 of an n-gon.
    ccss_evaluator_result centre(uint32_t face) const
    {
        if (face_sizes_.at(face) == 4) return eval(face, 0, 0.5, 0.5);
        return eval(face, 0, 1.0, 1.0);
    }

    /// One (face, sub-face) slot: a quad, or sub-face `sub` of an n-gon.
    struct Slot {
        uint32_t face = 0, sub = 0;
    };

    /// The slots in ccss_depth_compute order (faces in order, the sub-faces of an
    /// n-gon consecutively).
    std::vector<Slot> slots() const
    {
        std::vector<Slot> s;
        for (uint32_t f = 0; f < face_sizes_.size(); ++f) {
            uint32_t n = 0;
            const ccss_status st = ccss_evaluator_subface_count(ev_, f, &n, nullptr);
            if (st != CCSS_OK) throw error("ccss_evaluator_subface_count", st, nullptr);
            for (uint32_t k = 0; k < n; ++k) s.push_back(Slot{f, k});
        }
        return s;
    }

    /// The first slot of face `face`.
    size_t slot_start(uint32_t face) const
    {
        size_t s = 0;
        const ccss_status st = ccss_evaluator_slot_start(ev_, face, &s, nullptr);
        if (st != CCSS_OK) throw error("ccss_evaluator_slot_start", st, nullptr);
        return s;
    }

    /// Subdivision depth of every slot for tolerance `eps` (ccss_depth_compute).
    std::vector<uint32_t> depths(double eps, ccss_depth_method method) const
    {
        size_t n = 0;
        ccss_status st = ccss_evaluator_slot_count(ev_, &n, nullptr);
        if (st != CCSS_OK) throw error("ccss_evaluator_slot_count", st, nullptr);
        std::vector<uint32_t> d(n);
        ccss_error_detail det;
        st = ccss_depth_compute(ev_, eps, static_cast<uint32_t>(method), d.data(), d.size(), &det);
        if (st != CCSS_OK) throw error("ccss_depth_compute", st, &det);
        return d;
    }

    uint32_t face_size(uint32_t face) const { return face_sizes_.at(face); }
    size_t num_faces() const { return face_sizes_.size(); }
    const ccss_tables* tables() const { return tables_; }
    const ccss_topology* topology() const { return topo_; }
    const ccss_evaluator* evaluator() const { return ev_; }
    size_t regular_patches() const { return regular_patches_; }
    size_t extraordinary_patches() const { return extraordinary_patches_; }

private:
    std::vector<uint32_t> face_sizes_;
    Block tables_mem_, topo_mem_, eval_mem_;
    const ccss_tables* tables_ = nullptr;
    const ccss_topology* topo_ = nullptr;
    const ccss_evaluator* ev_ = nullptr;
    size_t regular_patches_ = 0, extraordinary_patches_ = 0;
};

/// Where each vertex's limit is evaluated: one face and the vertex's corner
/// in it (the first face, in face order, that uses the vertex).
struct Corner {
    uint32_t face = UINT32_MAX, k = 0;
};

inline std::vector<Corner> first_corners(size_t num_vertices,
                                         const std::vector<uint32_t>& face_sizes,
                                         const std::vector<uint32_t>& indices)
{
    std::vector<Corner> c(num_vertices);
    size_t at = 0;
    for (uint32_t f = 0; f < face_sizes.size(); ++f) {
        for (uint32_t k = 0; k < face_sizes[f]; ++k, ++at) {
            Corner& ck = c[indices[at]];
            if (ck.face == UINT32_MAX) ck = Corner{f, k};
        }
    }
    return c;
}

/// The expected factor by which |control point - limit point| of a vertex of
/// valence n shrinks per Catmull-Clark step (once the faces around it are
/// quads, i.e. from level 1 on).
///
/// The one-ring of a vertex maps to itself under subdivision. Its
/// rotationally symmetric part (V, average edge neighbour E, average face
/// vertex F) evolves by M = [[alpha, beta, gamma], [3/8, 1/2, 1/8],
/// [1/4, 1/2, 1/4]]; the other Fourier frequencies vanish at V and in the
/// limit point. M has eigenvalue 1 (the limit point) and the two roots of
/// x^2 - (alpha - 1/4) x + (1 - 2 beta)/16; the larger, mu, is the rate:
/// distance_L ~ c mu^L. Standard rule: mu(4) = 1/4, mu(3) = 1/6,
/// mu(5) = 0.3225, mu(6) = 3/8.
inline double expected_ratio(const ccss_tables* tables, uint32_t n)
{
    ccss_tables_valence_info info;
    if (ccss_tables_valence(tables, n, &info, nullptr) != CCSS_OK) return 0.0;
    const double t = info.alpha - 0.25, d = (1.0 - 2.0 * info.beta) / 16.0;
    const double disc = t * t - 4.0 * d;
    const double mu = disc >= 0.0 ? (std::fabs(t) + std::sqrt(disc)) / 2.0 : std::sqrt(d);
    return mu > 0.0 ? 1.0 / mu : 0.0;
}

/// Per group ("vertex" or "centre", valence n), per level L = 1..levels: the
/// largest distance between the peer's control point after L steps and our
/// limit point.
class Convergence {
public:
    Convergence(int levels, double diag) : levels_(levels), diag_(diag) {}

    /// Records distance `d` at `level` for a point of group (kind, valence)
    /// that exists as a control point from level `born` on (0: an original
    /// vertex, 1: a face point).
    void add(const std::string& kind, uint32_t valence, int born, int level, double d)
    {
        Group& g = groups_[{kind, valence}];
        g.born = born;
        if (g.max.empty()) g.max.assign(static_cast<size_t>(levels_) + 1, 0.0);
        if (level == 1) ++g.count;
        g.max[static_cast<size_t>(level)] = std::max(g.max[static_cast<size_t>(level)], d);
    }

    /// Prints one `conv` line per group and returns the number of failures
    /// (each also printed as a `FAIL` line with the measured numbers).
    ///
    /// A group passes when every ratio d(L-1)/d(L) it is checked on, whose
    /// distance d(L) is above the round-off floor (1e-12 of the bounding-box
    /// diagonal), is within `tol` (relative) of the expected ratio, and the
    /// last one within `tol_last`. Checked from the second step of the
    /// all-quad one-ring dynamics on: original vertices (born at level 0;
    /// level 0 may have non-quads) from L = 2, face centres (born at level 1
    /// as face points) from L = 3. The first step of the one-ring dynamics
    /// still carries the faster-decaying eigen-components at full weight
    /// (e.g. the eigenvalue-0 part of a valence-3 ring); they have decayed
    /// by a factor mu_2/mu <= 1/4 per level after that. A peer converging to
    /// another surface makes the ratios tend to 1 and fails.
    int report(const ccss_tables* tables, double tol, double tol_last, std::FILE* out) const
    {
        int failures = 0;
        const double floor = 1e-12 * diag_;
        for (const auto& [key, g] : groups_) {
            const double want = expected_ratio(tables, key.second);
            std::fprintf(out, "conv %s valence=%u count=%zu expected_ratio=%.4f", key.first.c_str(),
                         key.second, g.count, want);
            for (int l = 1; l <= levels_; ++l)
                std::fprintf(out, " d%d=%.3e", l, g.max[static_cast<size_t>(l)] / diag_);
            for (int l = 2; l <= levels_; ++l) {
                const double a = g.max[static_cast<size_t>(l - 1)], b = g.max[static_cast<size_t>(l)];
                if (b > floor) std::fprintf(out, " r%d=%.4f", l, a / b);
                else std::fprintf(out, " r%d=floor", l);
            }
            std::fprintf(out, "\n");
            for (int l = g.born + 2; l <= levels_; ++l) {
                const double a = g.max[static_cast<size_t>(l - 1)], b = g.max[static_cast<size_t>(l)];
                if (b <= floor) continue; // at round-off: nothing left to measure
                const double r = a / b, t = l == levels_ ? tol_last : tol;
                if (!(std::fabs(r / want - 1.0) <= t)) {
                    std::fprintf(out,
                                 "FAIL %s valence=%u level=%d: distance %.6e -> %.6e (of the "
                                 "bbox diagonal), ratio %.4f, expected %.4f +- %.0f%%\n",
                                 key.first.c_str(), key.second, l, a / diag_, b / diag_, r, want,
                                 100.0 * t);
                    ++failures;
                }
            }
        }
        return failures;
    }

private:
    struct Group {
        size_t count = 0;
        int born = 0;
        std::vector<double> max;
    };
    int levels_;
    double diag_;
    std::map<std::pair<std::string, uint32_t>, Group> groups_;
};

/// An adaptive tessellation, emitted: vertices (exact limit points with
/// normals and their (face, sub, u, v)), polygons counter-clockwise from
/// outside with their parameter cells, and their triangles (polygon p gives
/// size(p) - 2 consecutive triangles).
struct Tessellation {
    ccss_tessellation_counts_info counts{};
    std::vector<double> positions, normals;
    std::vector<ccss_evaluator_query> params;
    std::vector<uint32_t> sizes, indices, triangles;
    std::vector<ccss_tessellation_cell> cells;
};

/// Tessellates the limit surface of `limit` with `options` (size query,
/// build, counts, emit; the tessellation's block is freed on return).
inline Tessellation tessellate(const Limit& limit, const ccss_tessellation_options& options)
{
    ccss_error_detail d;
    size_t n = 0;
    ccss_status st =
        ccss_tessellation_required_bytes(limit.topology(), limit.evaluator(), &options, &n, &d);
    if (st != CCSS_OK) throw error("ccss_tessellation_required_bytes", st, &d);
    Block mem;
    mem.alloc(n);
    ccss_tessellation* tess = nullptr;
    st = ccss_tessellation_build(limit.topology(), limit.evaluator(), &options, mem.get(), n, &tess,
                                 &d);
    if (st != CCSS_OK) throw error("ccss_tessellation_build", st, &d);
    Tessellation t;
    st = ccss_tessellation_counts(tess, &t.counts, nullptr);
    if (st != CCSS_OK) throw error("ccss_tessellation_counts", st, nullptr);
    const ccss_tessellation_counts_info& c = t.counts;
    t.positions.resize(3 * c.vertices);
    t.normals.resize(3 * c.vertices);
    t.params.resize(c.vertices);
    t.sizes.resize(c.polygons);
    t.indices.resize(c.polygon_indices);
    t.triangles.resize(3 * c.triangles);
    t.cells.resize(c.polygons);
    ccss_tessellation_output o{};
    o.positions = t.positions.data();
    o.positions_len = t.positions.size();
    o.normals = t.normals.data();
    o.normals_len = t.normals.size();
    o.params = t.params.data();
    o.params_len = t.params.size();
    o.polygon_sizes = t.sizes.data();
    o.polygon_sizes_len = t.sizes.size();
    o.polygon_indices = t.indices.data();
    o.polygon_indices_len = t.indices.size();
    o.triangles = t.triangles.data();
    o.triangles_len = t.triangles.size();
    o.cells = t.cells.data();
    o.cells_len = t.cells.size();
    st = ccss_tessellation_emit(tess, &o, &d);
    if (st != CCSS_OK) throw error("ccss_tessellation_emit", st, &d);
    return t;
}

/// Absolute-flatness options: every point of the limit surface within `eps`
/// (model units) of the triangles and vice versa.
inline ccss_tessellation_options absolute_flatness(double eps)
{
    ccss_tessellation_options o{};
    o.criterion = CCSS_TESSELLATION_ABSOLUTE;
    o.tolerance = eps;
    o.max_level = 0; // CCSS_TESSELLATION_MAX_LEVEL
    return o;
}

/// A voxelized (ccss_voxel_grid_voxelize) and flooded (ccss_voxel_grid_flood) grid of the
/// limit surface of one Limit, normalised into the grid.
class Voxels {
public:
    Voxels(const Limit& limit, const std::array<uint32_t, 3>& res, uint32_t adjacency,
           uint32_t presplit = 8)
        : res_(res)
    {
        ccss_error_detail d;
        size_t n = 0;
        ccss_status st = ccss_voxel_grid_required_bytes(res.data(), 0, res[2], &n, nullptr);
        if (st != CCSS_OK) throw error("ccss_voxel_grid_required_bytes", st, nullptr);
        mem_.alloc(n);
        st = ccss_voxel_grid_build(res.data(), 0, res[2], mem_.get(), n, &grid_, &d);
        if (st != CCSS_OK) throw error("ccss_voxel_grid_build", st, &d);
        st = ccss_voxel_grid_voxelize(limit.evaluator(), grid_, adjacency, presplit, nullptr, &voxel_stats, &d);
        if (st != CCSS_OK) throw error("ccss_voxel_grid_voxelize", st, &d);
        std::vector<uint32_t> stack(4096);
        st = ccss_voxel_grid_flood(limit.evaluator(), grid_, stack.data(), stack.size(), &flood_stats, &d);
        if (st != CCSS_OK) throw error("ccss_voxel_grid_flood", st, &d);
        st = ccss_voxel_grid_last_transform(grid_, &transform, nullptr);
        if (st != CCSS_OK) throw error("ccss_voxel_grid_last_transform", st, nullptr);
        st = ccss_voxel_grid_counts(grid_, &surface, &interior, nullptr);
        if (st != CCSS_OK) throw error("ccss_voxel_grid_counts", st, nullptr);
    }

    Voxels(const Voxels&) = delete;
    Voxels& operator=(const Voxels&) = delete;

    /// 0 outside, 1 surface, 2 interior.
    uint32_t cls(uint32_t i, uint32_t j, uint32_t k) const
    {
        uint32_t c = 0;
        const ccss_status st = ccss_voxel_grid_class(grid_, i, j, k, &c, nullptr);
        if (st != CCSS_OK) throw error("ccss_voxel_grid_class", st, nullptr);
        return c;
    }

    /// The model-space centre of voxel (i, j, k).
    Vec3 centre(uint32_t i, uint32_t j, uint32_t k) const
    {
        const double ijk[3] = {double(i), double(j), double(k)};
        Vec3 p;
        for (int a = 0; a < 3; ++a) p[a] = (ijk[a] - transform.offset[a]) / transform.scale;
        return p;
    }

    const std::array<uint32_t, 3>& res() const { return res_; }

    ccss_voxel_grid_transform transform{};
    ccss_voxel_grid_voxelize_stats voxel_stats{};
    ccss_voxel_grid_flood_stats flood_stats{};
    uint64_t surface = 0, interior = 0;

private:
    std::array<uint32_t, 3> res_;
    Block mem_;
    ccss_voxel_grid* grid_ = nullptr;
};

/// Bounding-box diagonal of x y z triples.
inline double bbox_diagonal(const std::vector<double>& xyz)
{
    Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (size_t i = 0; i + 2 < xyz.size(); i += 3) {
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], xyz[i + k]);
            hi[k] = std::max(hi[k], xyz[i + k]);
        }
    }
    return dist(lo, hi);
}

/// `MESH OUT.txt [LIMIT_MESH] [--levels 2..6]`, the command line of the
/// limit-and-convergence programs.
struct LimitArgs {
    const char* in = nullptr;
    const char* out = nullptr;
    const char* limit_mesh = nullptr;
    int levels = 4;

    /// Parses the arguments; on a bad command line prints the usage of
    /// `program` on stderr and returns false.
    bool parse(int argc, char** argv, const char* program)
    {
        for (int i = 1; i < argc; ++i) {
            if (std::strcmp(argv[i], "--levels") == 0 && i + 1 < argc) levels = std::atoi(argv[++i]);
            else if (in == nullptr) in = argv[i];
            else if (out == nullptr) out = argv[i];
            else if (limit_mesh == nullptr) limit_mesh = argv[i];
            else in = nullptr, i = argc; // too many arguments
        }
        if (in == nullptr || out == nullptr || levels < 2 || levels > 6) {
            std::fprintf(stderr, "usage: %s MESH OUT.txt [LIMIT_MESH] [--levels 2..6]\n", program);
            return false;
        }
        return true;
    }
};

/// Prints "PASS: 0 failure(s)" or "FAIL: N failure(s)" and returns the exit
/// status: 0 without failures, 2 with.
inline int verdict(int failures)
{
    std::printf("%s: %d failure(s)\n", failures == 0 ? "PASS" : "FAIL", failures);
    return failures == 0 ? 0 : 2;
}

/// Runs `run()` (returning the exit status); an exception is reported as
/// "<program>: <what>" on stderr with exit status 1.
template <class F>
int guarded_main(const char* program, F&& run)
{
    try {
        return run();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: %s\n", program, e.what());
        return 1;
    }
}

} // namespace ccss_host

#endif // CCSS_HOST_HPP
