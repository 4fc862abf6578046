/*
 * creases.c: meshes with creases, boundaries and holes (the
 * ccss_feature_evaluator family of libccss).
 *
 *  1. The cube with all 12 edges infinitely sharp (sharpness 10): every
 *     face of the limit surface is its flat bilinear quad. Prints the
 *     largest distance from the bilinear interpolation of the face's
 *     corners over a 9x9 grid on each face:
 *         cube points=N max_deviation=D
 *  2. An open 3x3 grid of quads in the plane z = 0 (boundary mode
 *     EDGE_ONLY): the centre and a boundary point, finite and with z = 0
 *     exactly:
 *         grid centre face=4 u=0.5 v=0.5 p=x y z n=nx ny nz
 *         grid boundary face=1 u=0.5 v=0 p=x y z n=nx ny nz
 *  3. The same grid with face 4 a hole: evaluating it fails with
 *     CCSS_ERR_HOLE_FACE naming the face:
 *         hole status=S face=F
 *  4. A crease tag on vertices 0 and 5, which share no edge: the size query
 *     and the build fail with CCSS_ERR_NOT_AN_EDGE naming both vertices:
 *         not_an_edge status=S vertices=A B
 *  5. Adaptive tessellation of the fully creased cube and of the grid with
 *     its hole (ccss_tessellation_feature_required_bytes / _build, then the
 *     ccss_tessellation_* calls), absolute flatness 0.01: the cube's output
 *     is closed (every edge in two polygons), the holed grid's is open (its
 *     one-polygon edges are its outer and hole borders), every vertex with
 *     z = 0:
 *         tess cube polygons=P vertices=V bound=B boundary_edges=0
 *         tess holed_grid polygons=P vertices=V bound=B boundary_edges=E
 * Lines starting with '#' are comments. Returns 0 if every check holds.
 */
#include "ccss.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static int failures = 0;

static void check(int ok, const char *what)
{
    if (!ok) {
        printf("# FAIL %s\n", what);
        failures++;
    }
}

static void report(const char *what, ccss_status st, const ccss_error_detail *d)
{
    char msg[CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
    ccss_error_detail_format(d, msg, sizeof msg);
    fprintf(stderr, "%s failed: %s (status %d): %s\n", what, ccss_status_message((int)st),
            (int)st, msg);
    failures++;
}

/* A mesh with its tags: the inputs of the feature evaluator. */
typedef struct mesh {
    const double *pos;
    size_t nv;
    const uint32_t *sizes;
    size_t nf;
    const uint32_t *idx;
    size_t ni;
    const uint32_t *crease_v; /* pairs */
    const float *crease_s;
    size_t ncreases;
    const uint32_t *holes;
    size_t nholes;
} mesh;

/* Size query, malloc, build. Returns the block (the handle is *out), or NULL
 * with the status in *st and the detail in *d. */
static void *build(const mesh *m, const ccss_feature_options *o,
                   const ccss_feature_evaluator **out, ccss_status *st, ccss_error_detail *d)
{
    size_t bytes = 0;
    void *mem;
    *st = ccss_feature_evaluator_required_bytes(m->pos, m->nv, m->sizes, m->nf, m->idx, m->ni,
                                                m->crease_v, m->crease_s, m->ncreases, NULL,
                                                NULL, 0, m->holes, m->nholes, o, NULL, &bytes, d);
    if (*st != CCSS_OK) return NULL;
    mem = malloc(bytes);
    if (mem == NULL) {
        *st = CCSS_ERR_INTERNAL;
        return NULL;
    }
    *st = ccss_feature_evaluator_build(m->pos, m->nv, m->sizes, m->nf, m->idx, m->ni,
                                       m->crease_v, m->crease_s, m->ncreases, NULL, NULL, 0,
                                       m->holes, m->nholes, o, NULL, mem, bytes, out, d);
    if (*st != CCSS_OK) {
        free(mem);
        return NULL;
    }
    return mem;
}

/* 1. The fully creased cube. */
static void cube(const ccss_feature_options *o)
{
    static const double pos[8 * 3] = {
        -1, -1, -1,  1, -1, -1,  1, 1, -1,  -1, 1, -1,
        -1, -1,  1,  1, -1,  1,  1, 1,  1,  -1, 1,  1,
    };
    static const uint32_t sizes[6] = { 4, 4, 4, 4, 4, 4 };
    static const uint32_t idx[24] = {
        0, 3, 2, 1,  4, 5, 6, 7,  0, 1, 5, 4,
        1, 2, 6, 5,  2, 3, 7, 6,  3, 0, 4, 7,
    };
    /* The 12 edges, each once, infinitely sharp. */
    static const uint32_t crease_v[24] = {
        0, 1,  1, 2,  2, 3,  3, 0,  4, 5,  5, 6,  6, 7,  7, 4,  0, 4,  1, 5,  2, 6,  3, 7,
    };
    static const float crease_s[12] = { 10, 10, 10, 10, 10, 10, 10, 10, 10, 10, 10, 10 };
    const mesh m = { pos, 8, sizes, 6, idx, 24, crease_v, crease_s, 12, NULL, 0 };
    const ccss_feature_evaluator *fe = NULL;
    ccss_error_detail d;
    ccss_status st;
    ccss_evaluator_result r;
    double dev = 0.0;
    int f, i, j, k, points = 0;
    void *mem = build(&m, o, &fe, &st, &d);
    if (mem == NULL) {
        report("cube: build", st, &d);
        return;
    }
    for (f = 0; f < 6; f++) {
        const double *c[4];
        for (k = 0; k < 4; k++) c[k] = &pos[3 * idx[4 * f + k]];
        for (i = 0; i <= 8; i++) {
            for (j = 0; j <= 8; j++) {
                /* (0,0) at corner 0, (1,0) at corner 1, (1,1) at corner 2. */
                const double u = i / 8.0, v = j / 8.0;
                st = ccss_feature_evaluator_eval(fe, (uint32_t)f, 0, u, v, &r, &d);
                if (st != CCSS_OK) {
                    report("cube: eval", st, &d);
                    continue;
                }
                for (k = 0; k < 3; k++) {
                    const double b = (1 - u) * (1 - v) * c[0][k] + u * (1 - v) * c[1][k] +
                                     u * v * c[2][k] + (1 - u) * v * c[3][k];
                    const double e = fabs(r.p[k] - b);
                    if (e > dev) dev = e;
                }
                points++;
            }
        }
    }
    printf("cube points=%d max_deviation=%.3g\n", points, dev);
    check(points == 6 * 81, "cube: every point evaluated");
    check(dev <= 1e-14, "cube: faces are bilinear to 1e-14");
    free(mem);
}

/* The open 3x3 grid of quads: vertices i + 4 j at (i, j, 0), face i + 3 j. */
static double grid_pos[16 * 3];
static uint32_t grid_sizes[9];
static uint32_t grid_idx[36];

static void make_grid(void)
{
    uint32_t i, j;
    for (j = 0; j < 4; j++) {
        for (i = 0; i < 4; i++) {
            grid_pos[3 * (4 * j + i) + 0] = (double)i;
            grid_pos[3 * (4 * j + i) + 1] = (double)j;
            grid_pos[3 * (4 * j + i) + 2] = 0.0;
        }
    }
    for (j = 0; j < 3; j++) {
        for (i = 0; i < 3; i++) {
            const uint32_t f = 3 * j + i, v = 4 * j + i;
            grid_sizes[f] = 4;
            grid_idx[4 * f + 0] = v;
            grid_idx[4 * f + 1] = v + 1;
            grid_idx[4 * f + 2] = v + 5;
            grid_idx[4 * f + 3] = v + 4;
        }
    }
}

static void print_point(const char *name, uint32_t face, double u, double v,
                        const ccss_evaluator_result *r)
{
    printf("grid %s face=%u u=%.17g v=%.17g p=%.17g %.17g %.17g n=%.17g %.17g %.17g\n", name,
           (unsigned)face, u, v, r->p[0], r->p[1], r->p[2], r->normal[0], r->normal[1],
           r->normal[2]);
}

static int finite3(const double *p)
{
    return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

/* 2. The open grid. */
static void grid(const ccss_feature_options *o)
{
    const mesh m = { grid_pos, 16, grid_sizes, 9, grid_idx, 36, NULL, NULL, 0, NULL, 0 };
    const ccss_feature_evaluator *fe = NULL;
    ccss_error_detail d;
    ccss_status st;
    ccss_evaluator_result c, b;
    void *mem = build(&m, o, &fe, &st, &d);
    if (mem == NULL) {
        report("grid: build", st, &d);
        return;
    }
    st = ccss_feature_evaluator_eval(fe, 4, 0, 0.5, 0.5, &c, &d);
    if (st != CCSS_OK) report("grid: eval centre", st, &d);
    st = ccss_feature_evaluator_eval(fe, 1, 0, 0.5, 0.0, &b, &d);
    if (st != CCSS_OK) report("grid: eval boundary", st, &d);
    if (failures == 0) {
        print_point("centre", 4, 0.5, 0.5, &c);
        print_point("boundary", 1, 0.5, 0.0, &b);
        check(finite3(c.p) && finite3(c.normal) && finite3(b.p) && finite3(b.normal),
              "grid: finite");
        check(c.p[2] == 0.0 && b.p[2] == 0.0, "grid: z = 0 exactly");
        check(c.normal[2] == 1.0 && b.normal[2] == 1.0, "grid: normal +z");
        /* By symmetry the centre of the grid is (1.5, 1.5); a boundary edge
         * is infinitely sharp, so the boundary point lies on the edge y = 0. */
        check(fabs(c.p[0] - 1.5) <= 1e-14 && fabs(c.p[1] - 1.5) <= 1e-14, "grid: centre");
        check(b.p[1] == 0.0 && b.p[0] > 1.0 && b.p[0] < 2.0, "grid: boundary point on y = 0");
    }
    free(mem);
}

/* 3. A hole. */
static void hole(const ccss_feature_options *o)
{
    static const uint32_t holes[1] = { 4 };
    const mesh m = { grid_pos, 16, grid_sizes, 9, grid_idx, 36, NULL, NULL, 0, holes, 1 };
    const ccss_feature_evaluator *fe = NULL;
    ccss_error_detail d;
    ccss_status st;
    ccss_evaluator_result r;
    uint8_t is_hole = 0;
    void *mem = build(&m, o, &fe, &st, &d);
    if (mem == NULL) {
        report("hole: build", st, &d);
        return;
    }
    st = ccss_feature_evaluator_eval(fe, 4, 0, 0.5, 0.5, &r, &d);
    printf("hole status=%d face=%lld\n", (int)st, (long long)d.face);
    check(st == CCSS_ERR_HOLE_FACE && d.face == 4, "hole: status and face");
    check(ccss_feature_evaluator_face_is_hole(fe, 4, &is_hole, NULL) == CCSS_OK && is_hole == 1,
          "hole: face 4 is a hole");
    check(ccss_feature_evaluator_eval(fe, 3, 0, 0.5, 0.5, &r, NULL) == CCSS_OK,
          "hole: its neighbour has a surface");
    free(mem);
}

/* Output edges (unordered vertex pairs) in exactly one polygon: a quadratic
 * count, fine for the small outputs here. */
static size_t one_polygon_edges(const uint32_t *sizes, size_t np, const uint32_t *idx)
{
    size_t p, k, q, l, at = 0, at2, n = 0;
    for (p = 0; p < np; p++) {
        for (k = 0; k < sizes[p]; k++) {
            uint32_t a = idx[at + k], b = idx[at + (k + 1) % sizes[p]];
            size_t uses = 0;
            at2 = 0;
            for (q = 0; q < np; q++) {
                for (l = 0; l < sizes[q]; l++) {
                    uint32_t c = idx[at2 + l], e = idx[at2 + (l + 1) % sizes[q]];
                    if ((c == a && e == b) || (c == b && e == a)) uses++;
                }
                at2 += sizes[q];
            }
            if (uses == 1) n++;
        }
        at += sizes[p];
    }
    return n;
}

/* Tessellates the feature evaluator `fe` and prints one 'tess' line. */
static void tessellate_one(const char *name, const ccss_feature_evaluator *fe, int closed)
{
    ccss_tessellation_options to = { CCSS_TESSELLATION_ABSOLUTE, 0.01, 0, 0 };
    ccss_tessellation_counts_info c;
    ccss_tessellation_output out;
    ccss_tessellation *t = NULL;
    ccss_error_detail d;
    ccss_status st;
    size_t bytes = 0, i, edges;
    double *pos;
    uint32_t *sizes, *idx;
    void *mem;
    st = ccss_tessellation_feature_required_bytes(fe, &to, &bytes, &d);
    if (st != CCSS_OK) {
        report("tess: required_bytes", st, &d);
        return;
    }
    mem = malloc(bytes);
    if (mem == NULL) {
        failures++;
        return;
    }
    st = ccss_tessellation_feature_build(fe, &to, mem, bytes, &t, &d);
    if (st != CCSS_OK || ccss_tessellation_counts(t, &c, &d) != CCSS_OK) {
        report("tess: build", st, &d);
        free(mem);
        return;
    }
    pos = malloc(3 * c.vertices * sizeof *pos);
    sizes = malloc(c.polygons * sizeof *sizes);
    idx = malloc(c.polygon_indices * sizeof *idx);
    if (pos == NULL || sizes == NULL || idx == NULL) {
        failures++;
    } else {
        out.positions = pos;
        out.positions_len = 3 * c.vertices;
        out.normals = NULL;
        out.normals_len = 0;
        out.params = NULL;
        out.params_len = 0;
        out.polygon_sizes = sizes;
        out.polygon_sizes_len = c.polygons;
        out.polygon_indices = idx;
        out.polygon_indices_len = c.polygon_indices;
        out.triangles = NULL;
        out.triangles_len = 0;
        out.cells = NULL;
        out.cells_len = 0;
        st = ccss_tessellation_emit(t, &out, &d);
        if (st != CCSS_OK) {
            report("tess: emit", st, &d);
        } else {
            int flat = 1;
            edges = one_polygon_edges(sizes, c.polygons, idx);
            printf("tess %s polygons=%zu vertices=%zu bound=%.17g boundary_edges=%zu\n", name,
                   c.polygons, c.vertices, c.bound, edges);
            check(c.bound <= 0.01, "tess: bound within the tolerance");
            check(closed ? edges == 0 : edges > 0, "tess: closed cube, open grid");
            for (i = 0; !closed && i < c.vertices; i++) flat &= pos[3 * i + 2] == 0.0;
            check(flat, "tess: the grid's output in z = 0");
        }
    }
    free(pos);
    free(sizes);
    free(idx);
    free(mem);
}

/* 5. Tessellations: the creased cube (closed) and the holed grid (open). */
static void tessellate(const ccss_feature_options *o)
{
    static const double pos[8 * 3] = {
        -1, -1, -1,  1, -1, -1,  1, 1, -1,  -1, 1, -1,
        -1, -1,  1,  1, -1,  1,  1, 1,  1,  -1, 1,  1,
    };
    static const uint32_t sizes[6] = { 4, 4, 4, 4, 4, 4 };
    static const uint32_t idx[24] = {
        0, 3, 2, 1,  4, 5, 6, 7,  0, 1, 5, 4,
        1, 2, 6, 5,  2, 3, 7, 6,  3, 0, 4, 7,
    };
    static const uint32_t crease_v[24] = {
        0, 1,  1, 2,  2, 3,  3, 0,  4, 5,  5, 6,  6, 7,  7, 4,  0, 4,  1, 5,  2, 6,  3, 7,
    };
    static const float crease_s[12] = { 10, 10, 10, 10, 10, 10, 10, 10, 10, 10, 10, 10 };
    static const uint32_t holes[1] = { 4 };
    const mesh cube_m = { pos, 8, sizes, 6, idx, 24, crease_v, crease_s, 12, NULL, 0 };
    const mesh grid_m = { grid_pos, 16, grid_sizes, 9, grid_idx, 36, NULL, NULL, 0, holes, 1 };
    const ccss_feature_evaluator *fe = NULL;
    ccss_error_detail d;
    ccss_status st;
    void *mem = build(&cube_m, o, &fe, &st, &d);
    if (mem == NULL) {
        report("tess cube: build", st, &d);
    } else {
        tessellate_one("cube", fe, 1);
        free(mem);
    }
    mem = build(&grid_m, o, &fe, &st, &d);
    if (mem == NULL) {
        report("tess grid: build", st, &d);
    } else {
        tessellate_one("holed_grid", fe, 0);
        free(mem);
    }
}

/* 4. A crease on two vertices that share no edge. */
static void not_an_edge(const ccss_feature_options *o)
{
    static const uint32_t crease_v[2] = { 0, 5 };
    static const float crease_s[1] = { 2.0f };
    const mesh m = { grid_pos, 16, grid_sizes, 9, grid_idx, 36, crease_v, crease_s, 1, NULL, 0 };
    const ccss_feature_evaluator *fe = NULL;
    ccss_error_detail d;
    ccss_status st;
    char msg[CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
    void *mem = build(&m, o, &fe, &st, &d);
    check(mem == NULL && fe == NULL, "not_an_edge: nothing built");
    free(mem);
    printf("not_an_edge status=%d vertices=%lld %lld\n", (int)st, (long long)d.vertex,
           (long long)d.vertex2);
    ccss_error_detail_format(&d, msg, sizeof msg);
    printf("# %s\n", msg);
    check(st == CCSS_ERR_NOT_AN_EDGE && d.vertex == 0 && d.vertex2 == 5,
          "not_an_edge: status and vertices");
}

int main(void)
{
    ccss_feature_options o;
    ccss_error_detail d;
    ccss_status st = ccss_feature_options_default(&o, &d);
    if (st != CCSS_OK) {
        report("ccss_feature_options_default", st, &d);
        return 1;
    }
    printf("# ccss %s\n", ccss_version());
    check(o.boundary == CCSS_FEATURE_BOUNDARY_EDGE_ONLY, "default boundary is EDGE_ONLY");
    make_grid();
    cube(&o);
    grid(&o);
    hole(&o);
    not_an_edge(&o);
    tessellate(&o);
    printf("# %s: %d failure(s)\n", failures == 0 ? "ALL PASS" : "FAILED", failures);
    return failures == 0 ? 0 : 1;
}
