// ccss_host.hpp: the part of the C++ host examples (openmesh_limit.cpp,
// cgal_limit.cpp) that does not depend on the host's mesh library.
//
//  * ccss_host::Limit   owns the ccss tables, topology and evaluator of one
//                       mesh (malloc'd blocks, sizes asked first, as in
//                       c_examples/eval.c) and evaluates the exact limit
//                       surface at a vertex (a face corner) or a face centre.
//  * ccss_host::Convergence  collects, per group of vertices (vertex or face
//                       centre, by valence), the largest distance between a
//                       peer subdivider's control points after L levels and
//                       our limit positions, and checks that it shrinks at the
//                       rate the Catmull-Clark spectrum predicts.
//
// Only <ccss.h> and the C++17 standard library. Header-only.
#ifndef CCSS_HOST_HPP
#define CCSS_HOST_HPP

#include <ccss.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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
        char buf[CCSS_ERROR_MESSAGE_CAPACITY];
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
        ccss_status st = ccss_tables_required_bytes(&n);
        if (st != CCSS_OK) throw error("ccss_tables_required_bytes", st, nullptr);
        tables_mem_.alloc(n);
        st = ccss_tables_build_standard(tables_mem_.get(), n, &tables_);
        if (st != CCSS_OK) throw error("ccss_tables_build_standard", st, nullptr);

        const size_t nv = positions.size() / 3;
        st = ccss_topology_required_bytes(nv, face_sizes.data(), face_sizes.size(), &n);
        if (st != CCSS_OK) throw error("ccss_topology_required_bytes", st, nullptr);
        Block topo_mem; // only needed until the evaluator is built
        topo_mem.alloc(n);
        const ccss_topology* topo = nullptr;
        st = ccss_topology_build(positions.data(), nv, face_sizes.data(), face_sizes.size(),
                                 indices.data(), indices.size(), topo_mem.get(), n, &topo, &d);
        if (st != CCSS_OK) throw error("ccss_topology_build", st, &d);

        st = ccss_evaluator_required_bytes(topo, tables_, &n, &d);
        if (st != CCSS_OK) throw error("ccss_evaluator_required_bytes", st, &d);
        eval_mem_.alloc(n);
        st = ccss_evaluator_build(topo, tables_, eval_mem_.get(), n, &ev_, &d);
        if (st != CCSS_OK) throw error("ccss_evaluator_build", st, &d);
        size_t reg = 0, ext = 0;
        ccss_evaluator_patch_counts(ev_, &reg, &ext);
        regular_patches_ = reg;
        extraordinary_patches_ = ext;
    }

    Limit(const Limit&) = delete;
    Limit& operator=(const Limit&) = delete;

    ccss_eval_result eval(uint32_t face, uint32_t sub, double u, double v) const
    {
        ccss_eval_result r;
        const ccss_status st = ccss_eval(ev_, face, sub, u, v, &r);
        if (st != CCSS_OK) throw error("ccss_eval", st, nullptr);
        return r;
    }

    /// The limit point of the vertex at corner `k` of face `face`: for a quad
    /// the corner's (u, v) (0,0) (1,0) (1,1) (0,1); for an n-gon sub-face k
    /// at (0, 0).
    ccss_eval_result corner(uint32_t face, uint32_t k) const
    {
        if (face_sizes_.at(face) == 4) {
            static const double uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            return eval(face, 0, uv[k][0], uv[k][1]);
        }
        return eval(face, k, 0.0, 0.0);
    }

    /// The limit point of the centre of face `face`: (0.5, 0.5) of a quad,
    /// (1, 1) of sub-face 0 of an n-gon.
    ccss_eval_result centre(uint32_t face) const
    {
        if (face_sizes_.at(face) == 4) return eval(face, 0, 0.5, 0.5);
        return eval(face, 0, 1.0, 1.0);
    }

    const ccss_tables* tables() const { return tables_; }
    size_t regular_patches() const { return regular_patches_; }
    size_t extraordinary_patches() const { return extraordinary_patches_; }

private:
    std::vector<uint32_t> face_sizes_;
    Block tables_mem_, eval_mem_;
    const ccss_tables* tables_ = nullptr;
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
    ccss_valence_info info;
    if (ccss_tables_valence_info(tables, n, &info) != CCSS_OK) return 0.0;
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

} // namespace ccss_host

#endif // CCSS_HOST_HPP
