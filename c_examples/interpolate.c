/*
 * interpolate.c: similarity-based interpolation with libccss.
 *
 * Interpolates the cube (8 vertices, 6 quads) on the fast path: a
 * ccss_interpolator handle, its normal matrix assembled into a second block
 * (ccss_interpolator_matrix_required_bytes, ccss_interpolator_assemble),
 * then ccss_interpolator_solve (ccss_interpolation_solve does the same
 * matrix-free in one call, several times slower). Q has the topology of the
 * cube after one Catmull-Clark step (26 vertices, 24 quads), and the limit
 * surface of Q passes through the cube's corners. It checks that with the
 * standard limit mask (n^2 V + 4 sum E + sum F) / (n (n + 5)), computed here
 * from Q's quads, and prints
 * 'interpolate vertices=V faces=F iterations=I worst=W first=x,y,z'
 * (W the largest distance of a limit point from its corner, %.17g). It then
 * prescribes a normal at the centre of face 5 (met: line 'normal ...') and
 * a position at a corner that contradicts the interpolation
 * (CONFLICTING_REQUIREMENT for requirement 0, nothing written).
 *
 * Returns 0 on success, 1 on any failure or mismatch.
 *
 * Build: cc -std=c99 -Iinclude c_examples/interpolate.c target/debug/libccss.a \
 *           -lpthread -ldl -lm -o interpolate
 */
#include "ccss.h"
#include "example_report.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static const double cube_positions[24] = {
    -1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
    -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1,
};
static const uint32_t cube_sizes[6] = { 4, 4, 4, 4, 4, 4 };
static const uint32_t cube_indices[24] = {
    0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7,
};

/* Standard limit point of vertex v of the all-quad mesh (pos, idx, nf). */
static void limit_point(const double *pos, const uint32_t *idx, size_t nf, uint32_t v,
                        double out[3])
{
    double n = 0, e[3] = { 0, 0, 0 }, f[3] = { 0, 0, 0 };
    size_t q;
    int k, c;
    for (q = 0; q < nf; q++) {
        for (k = 0; k < 4; k++) {
            if (idx[4 * q + (size_t)k] == v) {
                uint32_t a = idx[4 * q + (size_t)((k + 1) % 4)];
                uint32_t b = idx[4 * q + (size_t)((k + 2) % 4)];
                n += 1;
                for (c = 0; c < 3; c++) {
                    e[c] += pos[3 * a + (size_t)c];
                    f[c] += pos[3 * b + (size_t)c];
                }
            }
        }
    }
    for (c = 0; c < 3; c++) {
        out[c] = (n * n * pos[3 * v + (size_t)c] + 4 * e[c] + f[c]) / (n * (n + 5));
    }
}

int main(void)
{
    ccss_error_detail detail;
    size_t n = 0, tn = 0, nv = 0, nf = 0, bytes = 0, i;
    void *gm = NULL, *tm = NULL, *mem = NULL, *mat = NULL;
    size_t mat_bytes = 0;
    ccss_interpolator *it = NULL;
    double *pos = NULL;
    uint32_t *idx = NULL;
    const ccss_topology *topo = NULL;
    const ccss_tables *tables = NULL;
    ccss_interpolation_stats stats;
    ccss_interpolation_requirement req[1];
    double worst = 0;
    int fail = 0, c;
    ccss_status st;

    st = ccss_tables_required_bytes(&tn, NULL);
    if (st != CCSS_OK) {
        return report("ccss_tables_required_bytes", st, NULL);
    }
    tm = malloc(tn);
    st = ccss_topology_required_bytes(8, cube_sizes, 6, &n, NULL);
    if (st != CCSS_OK || tm == NULL) {
        free(tm);
        return report("ccss_topology_required_bytes", st, NULL);
    }
    gm = malloc(n);
    if (gm == NULL) {
        fail = 1;
        goto done;
    }
    st = ccss_tables_build_standard(tm, tn, &tables, &detail);
    if (st != CCSS_OK) {
        fail = report("ccss_tables_build_standard", st, &detail);
        goto done;
    }
    st = ccss_topology_build(cube_positions, 8, cube_sizes, 6, cube_indices, 24, gm, n, &topo,
                             &detail);
    if (st != CCSS_OK) {
        fail = report("ccss_topology_build", st, &detail);
        goto done;
    }
    st = ccss_interpolation_counts(topo, &nv, &nf, &detail);
    if (st != CCSS_OK) {
        fail = report("ccss_interpolation_counts", st, &detail);
        goto done;
    }
    /* Room for one requirement of any kind (a position has the most rows). */
    req[0].face = 5;
    req[0].kind = 0;
    req[0].u = 0.5;
    req[0].v = 0.5;
    req[0].value[0] = req[0].value[1] = req[0].value[2] = 0;
    st = ccss_interpolator_required_bytes(topo, req, 1, &bytes, &detail);
    if (st != CCSS_OK) {
        fail = report("ccss_interpolator_required_bytes", st, &detail);
        goto done;
    }
    mem = malloc(bytes);
    pos = malloc(3 * nv * sizeof *pos);
    idx = malloc(4 * nf * sizeof *idx);
    if (mem == NULL || pos == NULL || idx == NULL) {
        fail = 1;
        goto done;
    }

    /* Build, size and assemble the normal matrix, solve. */
    st = ccss_interpolator_build(topo, tables, NULL, NULL, 0, mem, bytes, &it, &detail);
    if (st != CCSS_OK) {
        fail = report("ccss_interpolator_build", st, &detail);
        goto done;
    }
    st = ccss_interpolator_matrix_required_bytes(it, &mat_bytes, &detail);
    if (st != CCSS_OK) {
        fail = report("ccss_interpolator_matrix_required_bytes", st, &detail);
        goto done;
    }
    mat = malloc(mat_bytes);
    if (mat == NULL) {
        fail = 1;
        goto done;
    }
    st = ccss_interpolator_assemble(it, mat, mat_bytes, &detail);
    if (st != CCSS_OK) {
        fail = report("ccss_interpolator_assemble", st, &detail);
        goto done;
    }
    st = ccss_interpolator_solve(it, pos, 3 * nv, idx, 4 * nf, &stats, &detail);
    if (st != CCSS_OK) {
        fail = report("ccss_interpolator_solve", st, &detail);
        goto done;
    }
    for (i = 0; i < 8; i++) {
        double l[3], d = 0;
        limit_point(pos, idx, nf, (uint32_t)i, l);
        for (c = 0; c < 3; c++) {
            double x = l[c] - cube_positions[3 * i + (size_t)c];
            d += x * x;
        }
        if (sqrt(d) > worst) {
            worst = sqrt(d);
        }
    }
    printf("interpolate vertices=%zu faces=%zu iterations=%u worst=%.17g first=%.17g,%.17g,%.17g\n",
           nv, nf, (unsigned)stats.iterations, worst, pos[0], pos[1], pos[2]);
    if (worst > 1e-12 || !(stats.objective < stats.naive_objective)) {
        fprintf(stderr, "interpolation missed: %g\n", worst);
        fail = 1;
    }

    /* A normal at the centre of face 5 of Q, tilted. */
    req[0].kind = 1;
    req[0].value[0] = 0.2;
    req[0].value[1] = -1.0;
    req[0].value[2] = 0.1;
    /* A new handle in the same blocks: the requirements are not part of
       the matrix, so its size is unchanged (assemble checks it). */
    st = ccss_interpolator_build(topo, tables, NULL, req, 1, mem, bytes, &it, &detail);
    if (st == CCSS_OK) {
        st = ccss_interpolator_assemble(it, mat, mat_bytes, &detail);
    }
    if (st == CCSS_OK) {
        st = ccss_interpolator_solve(it, pos, 3 * nv, idx, 4 * nf, &stats, &detail);
    }
    if (st != CCSS_OK) {
        fail = report("ccss_interpolator (normal)", st, &detail);
        goto done;
    }
    printf("normal iterations=%u objective=%.6g\n", (unsigned)stats.iterations, stats.objective);

    /* A position at corner 0 of face 0 (a vertex of the cube) elsewhere. */
    req[0].face = 0;
    req[0].kind = 0;
    req[0].u = 0;
    req[0].v = 0;
    req[0].value[0] = 5;
    pos[0] = -7.0;
    st = ccss_interpolator_build(topo, tables, NULL, req, 1, mem, bytes, &it, &detail);
    if (st == CCSS_OK) {
        st = ccss_interpolator_solve(it, pos, 3 * nv, idx, 4 * nf, NULL, &detail);
    }
    if (st != CCSS_ERR_CONFLICTING_REQUIREMENT || detail.value != 0 || pos[0] != -7.0) {
        fprintf(stderr, "conflict: status %d value %lld\n", (int)st, (long long)detail.value);
        fail = 1;
    } else {
        printf("# error: conflicting requirement 0 rejected (CONFLICTING_REQUIREMENT)\n");
    }
done:
    free(mat);
    free(mem);
    free(pos);
    free(idx);
    free(gm);
    free(tm);
    return fail;
}
