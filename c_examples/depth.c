/*
 * depth.c: subdivision depth for a tolerance with libccss.
 *
 * The depth of a (sub-)face for a tolerance eps is the number of uniform
 * Catmull-Clark steps of the base mesh after which its control faces (as
 * bilinear patches) lie within eps of the limit surface (Cheng & Lai report,
 * ch. 3). Regular patches use Lemma 1; extraordinary ones the old technique
 * (Theorem 6), the matrix technique (Theorem 11), its measured-norm variant
 * (TIGHT), or the best of all (BEST).
 *
 * This example
 *  1. prints the rates r1 = ||A Lambda A^+||, r2 = ||A Lambda^2 A^+|| of
 *     valences 3, 5, 6, 7, 8 (ccss_depth_rates) and checks them against the
 *     report's Table 2 to 4 decimals;
 *  2. builds a cube (6 quads, 8 vertices of valence 3) and a pentagonal
 *     prism (2 pentagons + 5 quads, counter-clockwise seen from outside:
 *     10 vertices of valence 3 and 2 pentagon centres of valence 5), and
 *     prints the depth of every slot for eps = 0.01 with each method: one
 *     line 'face depth' per quad and 'face.sub depth' per sub-face of an
 *     N-gon (ccss_evaluator_slot_count, ccss_evaluator_slot_start,
 *     ccss_evaluator_subface_count, ccss_depth_compute); it checks that TIGHT never
 *     exceeds NEW and BEST never exceeds any method;
 *  3. demonstrates two errors: eps = 0 (CCSS_ERR_INVALID_ARGUMENT) and a
 *     buffer one element too small (CCSS_ERR_BUFFER_TOO_SMALL, with the
 *     required count in the detail), and checks that neither wrote anything.
 *
 * Output: '#' comment lines start each section ('# rates n r1 r2',
 * '# depths mesh=M method=X eps=E slots=S', '# error: ...'); rates are
 * printed with %.17g. Returns 0 on success, 1 on any failure or mismatch.
 *
 * Build: cc -std=c99 -Iinclude c_examples/depth.c target/debug/libccss.a \
 *           -lpthread -ldl -lm -o depth
 */
#include "ccss.h"
#include "example_report.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define EPS 0.01
#define NUM_METHODS 4

static const uint32_t methods[NUM_METHODS] = {
    (uint32_t)CCSS_DEPTH_OLD, (uint32_t)CCSS_DEPTH_NEW, (uint32_t)CCSS_DEPTH_BEST,
    (uint32_t)CCSS_DEPTH_TIGHT,
};
static const char *const method_names[NUM_METHODS] = { "old", "new", "best", "tight" };

/* A closed polygon mesh given by flat arrays. */
typedef struct mesh {
    const char *name;
    const double *positions;
    size_t num_vertices;
    const uint32_t *face_sizes;
    size_t num_faces;
    const uint32_t *indices;
    size_t num_indices;
} mesh;

/*
 * Builds the evaluator of `m` into a new block (*ev_mem, to be freed by the
 * caller) and writes the handle to *ev. The topology block is freed here:
 * the evaluator does not refer to it. Returns 0 on success.
 */
static int build_evaluator(const ccss_tables *tables, const mesh *m, void **ev_mem,
                           const ccss_evaluator **ev)
{
    ccss_error_detail detail;
    const ccss_topology *topo = NULL;
    void *topo_mem = NULL;
    size_t bytes = 0;
    ccss_status st;
    int rc = 1;

    *ev_mem = NULL;
    st = ccss_topology_required_bytes(m->num_vertices, m->face_sizes, m->num_faces, &bytes, NULL);
    if (st != CCSS_OK) return report("ccss_topology_required_bytes", st, NULL);
    topo_mem = malloc(bytes);
    if (topo_mem == NULL) goto out;
    st = ccss_topology_build(m->positions, m->num_vertices, m->face_sizes, m->num_faces,
                             m->indices, m->num_indices, topo_mem, bytes, &topo, &detail);
    if (st != CCSS_OK) { report("ccss_topology_build", st, &detail); goto out; }
    st = ccss_evaluator_required_bytes(topo, tables, &bytes, &detail);
    if (st != CCSS_OK) { report("ccss_evaluator_required_bytes", st, &detail); goto out; }
    *ev_mem = malloc(bytes);
    if (*ev_mem == NULL) goto out;
    st = ccss_evaluator_build(topo, tables, *ev_mem, bytes, ev, &detail);
    if (st != CCSS_OK) { report("ccss_evaluator_build", st, &detail); goto out; }
    rc = 0;
out:
    if (rc != 0) {
        free(*ev_mem);
        *ev_mem = NULL;
    }
    free(topo_mem);
    return rc;
}

/*
 * 1. The rates of valences 3, 5, 6, 7, 8 against the report's Table 2.
 * Returns 0 if all agree to 4 decimals.
 */
static int print_rates(const ccss_tables *tables)
{
    static const struct { uint32_t n; double r1, r2; } table2[5] = {
        { 3, 0.6667, 0.2917 }, { 5, 0.7200, 0.4016 }, { 6, 0.8889, 0.5098 },
        { 7, 0.8010, 0.5121 }, { 8, 1.0078, 0.5691 },
    };
    ccss_depth_rates_info r;
    ccss_status st;
    int i, bad = 0;

    printf("# rates n r1 r2\n");
    for (i = 0; i < 5; i++) {
        st = ccss_depth_rates(tables, table2[i].n, &r, NULL);
        if (st != CCSS_OK) return report("ccss_depth_rates", st, NULL);
        printf("%u %.17g %.17g\n", (unsigned)r.valence, r.r1, r.r2);
        /* "To 4 decimals": within half a unit of the 4th decimal. */
        if (r.valence != table2[i].n || fabs(r.r1 - table2[i].r1) >= 5e-5 ||
            fabs(r.r2 - table2[i].r2) >= 5e-5) {
            fprintf(stderr, "depth: n = %u: r1 = %.6f, r2 = %.6f; Table 2 says %.4f, %.4f\n",
                    (unsigned)table2[i].n, r.r1, r.r2, table2[i].r1, table2[i].r2);
            bad = 1;
        }
    }
    return bad;
}

/*
 * 2. The depths of every slot of `ev` for eps = EPS with each method, and the
 * order TIGHT <= NEW, BEST <= every method per slot. Returns 0 on success.
 */
static int print_depths(const char *name, const ccss_evaluator *ev)
{
    ccss_error_detail detail;
    uint32_t *d[NUM_METHODS] = { NULL, NULL, NULL, NULL };
    size_t slots = 0, faces = 0, start = 0, s;
    uint32_t f, k, subs = 0;
    ccss_status st;
    int m, rc = 1;

    st = ccss_evaluator_slot_count(ev, &slots, NULL);
    if (st != CCSS_OK) return report("ccss_evaluator_slot_count", st, NULL);
    st = ccss_evaluator_face_count(ev, &faces, NULL);
    if (st != CCSS_OK) return report("ccss_evaluator_face_count", st, NULL);
    for (m = 0; m < NUM_METHODS; m++) {
        d[m] = malloc(slots * sizeof *d[m]);
        if (d[m] == NULL) goto out;
        st = ccss_depth_compute(ev, EPS, methods[m], d[m], slots, &detail);
        if (st != CCSS_OK) { report("ccss_depth_compute", st, &detail); goto out; }
        printf("# depths mesh=%s method=%s eps=%g slots=%lu\n", name, method_names[m], EPS,
               (unsigned long)slots);
        for (f = 0; f < (uint32_t)faces; f++) {
            st = ccss_evaluator_slot_start(ev, f, &start, NULL);
            if (st != CCSS_OK) { report("ccss_evaluator_slot_start", st, NULL); goto out; }
            st = ccss_evaluator_subface_count(ev, f, &subs, NULL);
            if (st != CCSS_OK) { report("ccss_evaluator_subface_count", st, NULL); goto out; }
            if (subs == 1) {
                printf("%u %u\n", (unsigned)f, (unsigned)d[m][start]);
            } else {
                for (k = 0; k < subs; k++)
                    printf("%u.%u %u\n", (unsigned)f, (unsigned)k, (unsigned)d[m][start + k]);
            }
        }
    }
    /* d[0] old, d[1] new, d[2] best, d[3] tight. */
    for (s = 0; s < slots; s++) {
        if (d[3][s] > d[1][s] || d[2][s] > d[0][s] || d[2][s] > d[1][s] || d[2][s] > d[3][s]) {
            fprintf(stderr, "depth: %s slot %lu: old %u new %u best %u tight %u out of order\n",
                    name, (unsigned long)s, (unsigned)d[0][s], (unsigned)d[1][s],
                    (unsigned)d[2][s], (unsigned)d[3][s]);
            goto out;
        }
    }
    rc = 0;
out:
    for (m = 0; m < NUM_METHODS; m++) free(d[m]);
    return rc;
}

/*
 * 3. The two errors. Returns 0 if both fail as documented without writing
 * to the output array.
 */
static int demonstrate_errors(const ccss_evaluator *ev)
{
    ccss_error_detail detail;
    char msg[CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
    uint32_t *d = NULL;
    size_t slots = 0, s;
    ccss_status st;
    int rc = 1;

    st = ccss_evaluator_slot_count(ev, &slots, NULL);
    if (st != CCSS_OK) return report("ccss_evaluator_slot_count", st, NULL);
    d = malloc(slots * sizeof *d);
    if (d == NULL) return 1;
    for (s = 0; s < slots; s++) d[s] = 12345u;

    st = ccss_depth_compute(ev, 0.0, (uint32_t)CCSS_DEPTH_BEST, d, slots, &detail);
    ccss_error_detail_format(&detail, msg, sizeof msg);
    printf("# error: ccss_depth_compute(eps = 0) -> %d %s; detail: %s\n", (int)st,
           ccss_status_message((int)st), msg);
    if (st != CCSS_ERR_INVALID_ARGUMENT || detail.status != CCSS_ERR_INVALID_ARGUMENT) {
        fprintf(stderr, "depth: eps = 0 was not rejected as an invalid argument\n");
        goto out;
    }

    st = ccss_depth_compute(ev, EPS, (uint32_t)CCSS_DEPTH_BEST, d, slots - 1, &detail);
    ccss_error_detail_format(&detail, msg, sizeof msg);
    printf("# error: ccss_depth_compute(out_len = %lu) -> %d %s; detail: required %llu: %s\n",
           (unsigned long)(slots - 1), (int)st, ccss_status_message((int)st),
           (unsigned long long)detail.required, msg);
    if (st != CCSS_ERR_BUFFER_TOO_SMALL || detail.required != (uint64_t)slots) {
        fprintf(stderr, "depth: a short buffer was not rejected with the slot count\n");
        goto out;
    }
    for (s = 0; s < slots; s++) {
        if (d[s] != 12345u) {
            fprintf(stderr, "depth: a failed ccss_depth_compute wrote slot %lu\n", (unsigned long)s);
            goto out;
        }
    }
    rc = 0;
out:
    free(d);
    return rc;
}

int main(void)
{
    /* The cube [-1, 1]^3 of eval.c: v0..v3 at z = -1, v4..v7 at z = +1. */
    static const double cube_positions[8 * 3] = {
        -1, -1, -1,  1, -1, -1,  1, 1, -1,  -1, 1, -1,
        -1, -1,  1,  1, -1,  1,  1, 1,  1,  -1, 1,  1,
    };
    static const uint32_t cube_sizes[6] = { 4, 4, 4, 4, 4, 4 };
    static const uint32_t cube_indices[24] = {
        0, 3, 2, 1,  4, 5, 6, 7,  0, 1, 5, 4,
        1, 2, 6, 5,  2, 3, 7, 6,  3, 0, 4, 7,
    };
    /* A pentagonal prism: b0..b4 at z = -0.8 and t0..t4 (= 5..9) at z = +0.8
     * over the pentagon (1, 0), (0.3, 0.95), (-0.8, 0.6), (-0.8, -0.6),
     * (0.3, -0.95). Face 0 is the bottom (b4 b3 b2 b1 b0: counter-clockwise
     * seen from below), face 1 the top, faces 2..6 the sides b_k b_k+1
     * t_k+1 t_k. */
    static const double prism_positions[10 * 3] = {
        1.0, 0.0, -0.8,  0.3, 0.95, -0.8,  -0.8, 0.6, -0.8,  -0.8, -0.6, -0.8,  0.3, -0.95, -0.8,
        1.0, 0.0,  0.8,  0.3, 0.95,  0.8,  -0.8, 0.6,  0.8,  -0.8, -0.6,  0.8,  0.3, -0.95,  0.8,
    };
    static const uint32_t prism_sizes[7] = { 5, 5, 4, 4, 4, 4, 4 };
    static const uint32_t prism_indices[30] = {
        4, 3, 2, 1, 0,  5, 6, 7, 8, 9,
        0, 1, 6, 5,  1, 2, 7, 6,  2, 3, 8, 7,  3, 4, 9, 8,  4, 0, 5, 9,
    };
    const mesh meshes[2] = {
        { "cube", cube_positions, 8, cube_sizes, 6, cube_indices, 24 },
        { "prism", prism_positions, 10, prism_sizes, 7, prism_indices, 30 },
    };
    const ccss_tables *tables = NULL;
    const ccss_evaluator *ev[2] = { NULL, NULL };
    void *tables_mem = NULL, *ev_mem[2] = { NULL, NULL };
    size_t bytes = 0;
    ccss_status st;
    int i, rc = 1;

    printf("# ccss %s\n", ccss_version());
    st = ccss_tables_required_bytes(&bytes, NULL);
    if (st != CCSS_OK) return report("ccss_tables_required_bytes", st, NULL);
    tables_mem = malloc(bytes);
    if (tables_mem == NULL) goto out;
    st = ccss_tables_build_standard(tables_mem, bytes, &tables, NULL);
    if (st != CCSS_OK) { report("ccss_tables_build_standard", st, NULL); goto out; }

    if (print_rates(tables) != 0) goto out;
    for (i = 0; i < 2; i++) {
        if (build_evaluator(tables, &meshes[i], &ev_mem[i], &ev[i]) != 0) goto out;
        if (print_depths(meshes[i].name, ev[i]) != 0) goto out;
    }
    if (demonstrate_errors(ev[1]) != 0) goto out;
    rc = 0;
out:
    for (i = 0; i < 2; i++) free(ev_mem[i]);
    free(tables_mem);
    if (rc != 0) fprintf(stderr, "depth: FAILED\n");
    return rc;
}
