/*
 * weights.c: general vertex-rule weights with libccss.
 *
 * The vertex rule of valence n moves a vertex V to
 *     alpha V + beta/n sum(E_i) + gamma/n sum(F_i)
 * (E_i edge neighbours, F_i face-diagonal vertices); standard Catmull-Clark
 * is alpha = 1 - 7/(4n), beta = 3/(2n), gamma = 1/(4n).
 *
 * This example
 *  1. shows three rejected rules: non-standard weights for valence 4 (which
 *     must stay standard: regular patches are bicubic B-splines), a negative
 *     weight, and weights that do not add up to 1; each fails with
 *     CCSS_ERR_INVALID_WEIGHTS naming the entry and its valence;
 *  2. builds tables with alpha = 0.5, beta = 0.3, gamma = 0.2 for every
 *     valence 3..=ccss_max_valence except 4, and prints the tangent-plane
 *     continuity of that rule per valence (ccss_weight_entry_check) and the
 *     valence-3 table facts (ccss_tables_valence);
 *  3. evaluates the cube of eval.c (all 8 vertices of valence 3) with those
 *     tables at the corner of face 0 (u = v = 0) and at its centre
 *     (u = v = 1/2), and checks the corner against the general limit formula
 *     (Cheng & Lai, eq. 2.7) computed here in C:
 *         S = (5 V + (12b + 8g) Ebar + (2b + 8g) Fbar) / (5 + 14b + 16g)
 *     (Ebar, Fbar: averages of the 3 edge neighbours and of the 3
 *     face-diagonal vertices of the corner).
 *
 * Output: '#' comment lines, then 'key value...' lines (%.17g). Returns 0 on
 * success, 1 on any failure or if the corner differs from the formula by
 * more than 1e-12.
 *
 * Build: cc -std=c99 -Iinclude c_examples/weights.c target/debug/libccss.a \
 *           -lpthread -ldl -lm -o weights
 */
#include "ccss.h"
#include "example_report.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define ALPHA 0.5
#define BETA 0.3
#define GAMMA 0.2

static void print_detail(const char *what, ccss_status st, const ccss_error_detail *d)
{
    char msg[CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
    ccss_error_detail_format(d, msg, sizeof msg);
    printf("rejected %s status=%d entry=%llu valence=%lld message=%s\n", what, (int)st,
           (unsigned long long)d->query_index, (long long)d->value, msg);
}

/*
 * Builds tables from `entries` where entry `bad` is invalid and checks the
 * failure: CCSS_ERR_INVALID_WEIGHTS, the entry index and valence in the
 * detail, and no handle written. Returns 0 if all is as expected.
 */
static int expect_rejected(const char *what, const ccss_weight_entry *entries, size_t count,
                           size_t bad, void *mem, size_t len)
{
    ccss_error_detail detail;
    const ccss_tables *t = NULL;
    int tpc = -1;
    ccss_status st = ccss_tables_build(entries, count, mem, len, &t, &detail);
    print_detail(what, st, &detail);
    if (st != CCSS_ERR_INVALID_WEIGHTS || detail.query_index != (uint64_t)bad ||
        detail.value != (int64_t)entries[bad].valence || t != NULL) {
        fprintf(stderr, "weights: %s: expected CCSS_ERR_INVALID_WEIGHTS for entry %zu\n", what,
                bad);
        return 1;
    }
    /* The same entry alone, without building anything. */
    st = ccss_weight_entry_check(&entries[bad], &tpc, &detail);
    if (st != CCSS_ERR_INVALID_WEIGHTS || tpc != -1 ||
        detail.value != (int64_t)entries[bad].valence) {
        fprintf(stderr, "weights: %s: ccss_weight_entry_check did not reject it\n", what);
        return 1;
    }
    return 0;
}

int main(void)
{
    /* The cube [-1, 1]^3 of eval.c: v0..v3 at z = -1, v4..v7 at z = +1. */
    static const double positions[8 * 3] = {
        -1, -1, -1,  1, -1, -1,  1, 1, -1,  -1, 1, -1,
        -1, -1,  1,  1, -1,  1,  1, 1,  1,  -1, 1,  1,
    };
    static const uint32_t face_sizes[6] = { 4, 4, 4, 4, 4, 4 };
    static const uint32_t indices[24] = {
        0, 3, 2, 1,  4, 5, 6, 7,  0, 1, 5, 4,
        1, 2, 6, 5,  2, 3, 7, 6,  3, 0, 4, 7,
    };
    /* Corner v0 of face 0 (u = v = 0): its edge neighbours and the vertices
     * diagonally opposite it in its three quads. */
    static const int corner = 0, edge_nb[3] = { 1, 3, 4 }, diag_nb[3] = { 2, 5, 7 };

    ccss_error_detail detail;
    const ccss_tables *tables = NULL;
    const ccss_topology *topo = NULL;
    const ccss_evaluator *ev = NULL;
    void *tables_mem = NULL, *topo_mem = NULL, *ev_mem = NULL;
    ccss_weight_entry *entries = NULL;
    size_t bytes = 0, maxv = 0, count = 0, n, k;
    ccss_status st = CCSS_OK;
    ccss_tables_valence_info info;
    ccss_evaluator_result r_corner, r_centre;
    double formula[3], diff = 0.0;
    int rc = 1, tpc = 0;

    printf("# ccss %s\n", ccss_version());
    st = ccss_max_valence(&maxv, NULL);
    if (st != CCSS_OK) return report("ccss_max_valence", st, NULL);
    st = ccss_tables_required_bytes(&bytes, NULL);
    if (st != CCSS_OK) return report("ccss_tables_required_bytes", st, NULL);
    tables_mem = malloc(bytes);
    /* One entry per valence 3..=maxv (valence 4 only in the rejected cases). */
    entries = malloc((maxv + 1) * sizeof *entries);
    if (tables_mem == NULL || entries == NULL) goto out;

    /* 1. Three rejected rules. Each list is the full list of the example with
     *    one bad entry at index 1. */
    entries[0].valence = 3;
    entries[0].alpha = ALPHA; entries[0].beta = BETA; entries[0].gamma = GAMMA;
    entries[1].valence = 4; /* valence 4 must keep (9/16, 3/8, 1/16) */
    entries[1].alpha = ALPHA; entries[1].beta = BETA; entries[1].gamma = GAMMA;
    count = 2;
    for (n = 5; n <= maxv; n++) {
        entries[count].valence = (uint32_t)n;
        entries[count].alpha = ALPHA; entries[count].beta = BETA; entries[count].gamma = GAMMA;
        count++;
    }
    if (expect_rejected("valence4", entries, count, 1, tables_mem, bytes) != 0) goto out;
    entries[1].valence = 5; /* a negative weight (the sum is still 1) */
    entries[1].alpha = 0.9; entries[1].beta = 0.3; entries[1].gamma = -0.2;
    if (expect_rejected("negative", entries, count, 1, tables_mem, bytes) != 0) goto out;
    entries[1].valence = 5; /* alpha + beta + gamma = 1.1 */
    entries[1].alpha = 0.6; entries[1].beta = 0.3; entries[1].gamma = 0.2;
    if (expect_rejected("sum", entries, count, 1, tables_mem, bytes) != 0) goto out;

    /* 2. The valid rule: 3, 5, 6, ..., maxv. */
    count = 0;
    for (n = 3; n <= maxv; n++) {
        if (n == 4) continue;
        entries[count].valence = (uint32_t)n;
        entries[count].alpha = ALPHA; entries[count].beta = BETA; entries[count].gamma = GAMMA;
        st = ccss_weight_entry_check(&entries[count], &tpc, &detail);
        if (st != CCSS_OK) { rc = report("ccss_weight_entry_check", st, &detail); goto out; }
        printf("weights n=%zu alpha=%.17g beta=%.17g gamma=%.17g tangent_plane_continuous=%d\n", n,
               ALPHA, BETA, GAMMA, tpc);
        count++;
    }
    st = ccss_tables_build(entries, count, tables_mem, bytes, &tables, &detail);
    if (st != CCSS_OK) { rc = report("ccss_tables_build", st, &detail); goto out; }
    free(entries); /* not referred to by the tables */
    entries = NULL;

    st = ccss_tables_valence(tables, 3, &info, NULL);
    if (st != CCSS_OK) { rc = report("ccss_tables_valence", st, NULL); goto out; }
    printf("info n=%u points=%u alpha=%.17g beta=%.17g gamma=%.17g subdominant=%.17g "
           "tangent_plane_continuous=%d complex_pair=%d limit_v=%.17g limit_e=%.17g "
           "limit_f=%.17g\n",
           (unsigned)info.valence, (unsigned)info.num_points, info.alpha, info.beta, info.gamma,
           info.subdominant, info.tangent_plane_continuous, info.complex_pair, info.limit_v,
           info.limit_e, info.limit_f);

    /* 3. The cube with these tables. */
    st = ccss_topology_required_bytes(8, face_sizes, 6, &bytes, NULL);
    if (st != CCSS_OK) { rc = report("ccss_topology_required_bytes", st, NULL); goto out; }
    topo_mem = malloc(bytes);
    if (topo_mem == NULL) goto out;
    st = ccss_topology_build(positions, 8, face_sizes, 6, indices, 24, topo_mem, bytes, &topo,
                             &detail);
    if (st != CCSS_OK) { rc = report("ccss_topology_build", st, &detail); goto out; }
    st = ccss_evaluator_required_bytes(topo, tables, &bytes, &detail);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_required_bytes", st, &detail); goto out; }
    ev_mem = malloc(bytes);
    if (ev_mem == NULL) goto out;
    st = ccss_evaluator_build(topo, tables, ev_mem, bytes, &ev, &detail);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_build", st, &detail); goto out; }

    st = ccss_evaluator_eval(ev, 0, 0, 0.0, 0.0, &r_corner, NULL);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_eval(corner, NULL)", st, NULL); goto out; }
    st = ccss_evaluator_eval(ev, 0, 0, 0.5, 0.5, &r_centre, NULL);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_eval(centre, NULL)", st, NULL); goto out; }
    printf("corner %.17g %.17g %.17g\n", r_corner.p[0], r_corner.p[1], r_corner.p[2]);
    printf("centre %.17g %.17g %.17g\n", r_centre.p[0], r_centre.p[1], r_centre.p[2]);

    /* The corner from the limit formula, independently of the library. */
    for (k = 0; k < 3; k++) {
        double ebar = 0.0, fbar = 0.0, d;
        int i;
        for (i = 0; i < 3; i++) {
            ebar += positions[3 * edge_nb[i] + k] / 3.0;
            fbar += positions[3 * diag_nb[i] + k] / 3.0;
        }
        formula[k] = (5.0 * positions[3 * corner + k] + (12.0 * BETA + 8.0 * GAMMA) * ebar +
                      (2.0 * BETA + 8.0 * GAMMA) * fbar) /
                     (5.0 + 14.0 * BETA + 16.0 * GAMMA);
        d = fabs(formula[k] - r_corner.p[k]);
        if (!(d <= diff)) diff = d; /* NaN-safe maximum */
    }
    printf("corner_formula %.17g %.17g %.17g\n", formula[0], formula[1], formula[2]);
    printf("# corner max |library - formula| = %.3g\n", diff);
    if (!(diff <= 1e-12)) {
        fprintf(stderr, "weights: corner differs from the limit formula by %g\n", diff);
        goto out;
    }
    rc = 0;

out:
    if (rc != 0 && st == CCSS_OK) fprintf(stderr, "weights: out of memory or check failed\n");
    free(entries);
    free(ev_mem); /* the evaluator first, then the tables it refers to */
    free(topo_mem);
    free(tables_mem);
    return rc;
}
