/*
 * refine.c: the unified subdivision scheme of Maillot & Stam with libccss.
 *
 * Builds the cube (6 quads) and refines it one level with
 *  1. the Catmull-Clark-equivalent parameters (a = b = 0, g = 1, d = 2,
 *     p = 3, triangles as polygons),
 *  2. the defaults of ccss_unified_params_default (a = b = 0.5, g = 0,
 *     d = 2, p = 3),
 *  3. the defaults with d = 3,
 * and also two Catmull-Clark levels. For each run it prints one line
 * 'refine name=N levels=L bytes=B vertices=V faces=F indices=I
 * first=x,y,z' (sizes from ccss_unified_required_bytes, the first vertex from
 * ccss_unified_refine, %.17g). It checks that the face count grows by d^2 per level
 * and that a one-element-short face array fails with BUFFER_TOO_SMALL
 * without writing anything.
 *
 * Returns 0 on success, 1 on any failure or mismatch.
 *
 * Build: cc -std=c99 -Iinclude c_examples/refine.c target/debug/libccss.a \
 *           -lpthread -ldl -lm -o refine
 */
#include "ccss.h"
#include "example_report.h"

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

/* Refines `topo` with `levels` and prints the line; returns 0 on success. */
static int run(const ccss_topology *topo, const char *name, const ccss_unified_params *levels,
               size_t num_levels)
{
    ccss_error_detail detail;
    size_t bytes = 0, nv = 0, nf = 0, ni = 0, l;
    size_t growth = 1;
    void *mem;
    double *pos;
    uint32_t *sizes, *idx;
    int fail = 0;
    ccss_status st =
        ccss_unified_required_bytes(topo, levels, num_levels, &bytes, &nv, &nf, &ni, &detail);
    if (st != CCSS_OK) {
        return report("ccss_unified_required_bytes", st, &detail);
    }
    for (l = 0; l < num_levels; l++) {
        growth *= (size_t)levels[l].d * (size_t)levels[l].d;
    }
    if (nf != 6 * growth) {
        fprintf(stderr, "%s: %zu faces, expected 6 * %zu\n", name, nf, growth);
        return 1;
    }
    mem = malloc(bytes > 0 ? bytes : 1);
    pos = malloc(3 * nv * sizeof *pos);
    sizes = malloc(nf * sizeof *sizes);
    idx = malloc(ni * sizeof *idx);
    if (mem == NULL || pos == NULL || sizes == NULL || idx == NULL) {
        fprintf(stderr, "out of memory\n");
        fail = 1;
        goto done;
    }

    /* A face array one element short: BUFFER_TOO_SMALL, nothing written. */
    sizes[nf - 1] = 12345u;
    pos[0] = -7.0;
    st = ccss_unified_refine(topo, levels, num_levels, mem, bytes, pos, 3 * nv, sizes, nf - 1, idx, ni,
                     &detail);
    if (st != CCSS_ERR_BUFFER_TOO_SMALL || detail.required != nf || pos[0] != -7.0 ||
        sizes[nf - 1] != 12345u) {
        fprintf(stderr, "%s: short face array: status %d, required %llu\n", name, (int)st,
                (unsigned long long)detail.required);
        fail = 1;
        goto done;
    }

    st = ccss_unified_refine(topo, levels, num_levels, mem, bytes, pos, 3 * nv, sizes, nf, idx, ni,
                     &detail);
    if (st != CCSS_OK) {
        fail = report("ccss_unified_refine", st, &detail);
        goto done;
    }
    printf("refine name=%s levels=%zu bytes=%zu vertices=%zu faces=%zu indices=%zu "
           "first=%.17g,%.17g,%.17g\n",
           name, num_levels, bytes, nv, nf, ni, pos[0], pos[1], pos[2]);
done:
    free(mem);
    free(pos);
    free(sizes);
    free(idx);
    return fail;
}

int main(void)
{
    ccss_error_detail detail;
    size_t n = 0;
    void *gm;
    const ccss_topology *topo = NULL;
    ccss_unified_params cc = { 0.0, 0.0, 1.0, 2u, 3u, 1u };
    ccss_unified_params def, def3, cc2[2];
    int fail = 0;
    ccss_status st;

    st = ccss_unified_params_default(&def, NULL);
    if (st != CCSS_OK) {
        return report("ccss_unified_params_default", st, NULL);
    }
    if (def.a != 0.5 || def.b != 0.5 || def.g != 0.0 || def.d != 2u || def.p != 3u ||
        def.triangles != 0u) {
        fprintf(stderr, "unexpected defaults\n");
        return 1;
    }
    def3 = def;
    def3.d = 3u;
    cc2[0] = cc;
    cc2[1] = cc;

    st = ccss_topology_required_bytes(8, cube_sizes, 6, &n, NULL);
    if (st != CCSS_OK) {
        return report("ccss_topology_required_bytes", st, NULL);
    }
    gm = malloc(n);
    if (gm == NULL) {
        return 1;
    }
    st = ccss_topology_build(cube_positions, 8, cube_sizes, 6, cube_indices, 24, gm, n, &topo,
                             &detail);
    if (st != CCSS_OK) {
        free(gm);
        return report("ccss_topology_build", st, &detail);
    }

    fail |= run(topo, "catmull-clark", &cc, 1);
    fail |= run(topo, "default", &def, 1);
    fail |= run(topo, "default-d3", &def3, 1);
    fail |= run(topo, "catmull-clark-2", cc2, 2);

    /* d = 1 is rejected. */
    def3.d = 1u;
    st = ccss_unified_required_bytes(topo, &def3, 1, &n, &n, &n, &n, &detail);
    if (st != CCSS_ERR_INVALID_ARGUMENT) {
        fprintf(stderr, "d = 1: status %d, expected INVALID_ARGUMENT\n", (int)st);
        fail = 1;
    } else {
        printf("# error: d = 1 rejected (INVALID_ARGUMENT)\n");
    }

    free(gm);
    return fail;
}
