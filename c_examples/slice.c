/*
 * slice.c: planar slices of a bundled torus (OpenSubdiv's catmark_torus,
 * 32 quads; its axis is y) with libccss, layer by layer into caller
 * buffers with exact size queries: planes y = y0 + k dy; then the same
 * layers again as one band (one walk of the cells for all of them).
 *
 * Prints (lines starting with '#' are comments):
 *     layer k y=Y points=P contours=C
 *     contour outer|hole n=N area=A
 *     band k points=P contours=C area=A      (A: the contours' areas summed)
 *     error eps status=S
 *     error band count status=S
 * Returns 0 on success.
 *
 * Build: cc -std=c99 -Iinclude c_examples/slice.c target/debug/libccss.a \
 *           -lpthread -ldl -lm -o slice
 */
#include "ccss.h"
#include "example_report.h"
#include "example_torus.h"

#include <stdio.h>
#include <stdlib.h>

int main(void)
{
    uint32_t face_sizes[TORUS_NF];
    static const double normal[3] = { 0.0, 1.0, 0.0 };
    ccss_error_detail detail;
    const ccss_tables *tables = NULL;
    const ccss_topology *topo = NULL;
    const ccss_evaluator *ev = NULL;
    ccss_query *q = NULL;
    ccss_query_slice_layer_stats ls, band[5];
    void *tables_mem = NULL, *topo_mem = NULL, *ev_mem = NULL, *q_mem = NULL, *scratch = NULL;
    double *pts = NULL;
    ccss_query_contour *cs = NULL;
    size_t bytes = 0, scratch_len = 0;
    const double eps = 1e-3;
    ccss_status st;
    int i, k, rc = 1;

    for (i = 0; i < TORUS_NF; i++) face_sizes[i] = 4;

    st = ccss_tables_required_bytes(&bytes, NULL);
    if (st != CCSS_OK) return report("ccss_tables_required_bytes", st, NULL);
    if ((tables_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_tables_build_standard(tables_mem, bytes, &tables, NULL);
    if (st != CCSS_OK) { rc = report("ccss_tables_build_standard", st, NULL); goto out; }
    st = ccss_topology_required_bytes(TORUS_NV, face_sizes, TORUS_NF, &bytes, NULL);
    if (st != CCSS_OK) { rc = report("ccss_topology_required_bytes", st, NULL); goto out; }
    if ((topo_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_topology_build(torus_positions, TORUS_NV, face_sizes, TORUS_NF, torus_indices, TORUS_NF * 4, topo_mem, bytes,
                             &topo, &detail);
    if (st != CCSS_OK) { rc = report("ccss_topology_build", st, &detail); goto out; }
    st = ccss_evaluator_required_bytes(topo, tables, &bytes, &detail);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_required_bytes", st, &detail); goto out; }
    if ((ev_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_evaluator_build(topo, tables, ev_mem, bytes, &ev, &detail);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_build", st, &detail); goto out; }

    st = ccss_query_required_bytes(&bytes, &detail);
    if (st != CCSS_OK) { rc = report("ccss_query_required_bytes", st, &detail); goto out; }
    if ((q_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_query_build(q_mem, bytes, &q, &detail);
    if (st != CCSS_OK) { rc = report("ccss_query_build", st, &detail); goto out; }

    for (k = 0; k < 5; k++) {
        double y = -0.3 + 0.15 * k;
        uint32_t c;
        /* Scratch: size query, then the layer; then the exact outputs. */
        st = ccss_query_slice_required_bytes(ev, q, normal, y, eps, &bytes, &detail);
        if (st != CCSS_OK) { rc = report("ccss_query_slice_required_bytes", st, &detail); goto out; }
        if (bytes > scratch_len) {
            free(scratch);
            if ((scratch = malloc(bytes)) == NULL) goto out;
            scratch_len = bytes;
        }
        st = ccss_query_slice_layer(ev, q, normal, y, eps, scratch, scratch_len, &ls, &detail);
        if (st != CCSS_OK) { rc = report("ccss_query_slice_layer", st, &detail); goto out; }
        free(pts);
        free(cs);
        pts = malloc((ls.points ? ls.points : 1) * 2 * sizeof *pts);
        cs = malloc((ls.contours ? ls.contours : 1) * sizeof *cs);
        if (pts == NULL || cs == NULL) goto out;
        st = ccss_query_slice_write(scratch, scratch_len, &ls, pts, (size_t)ls.points, cs,
                                    (size_t)ls.contours, &detail);
        if (st != CCSS_OK) { rc = report("ccss_query_slice_write", st, &detail); goto out; }
        printf("layer %d y=%.17g points=%llu contours=%llu\n", k, y,
               (unsigned long long)ls.points, (unsigned long long)ls.contours);
        for (c = 0; c < ls.contours; c++) {
            double a = 0.0;
            uint32_t j, s = cs[c].start, n = cs[c].len;
            for (j = 0; j < n; j++) {
                const double *p0 = &pts[2 * (s + j)], *p1 = &pts[2 * (s + (j + 1) % n)];
                a += p0[0] * p1[1] - p0[1] * p1[0];
            }
            printf("contour %s n=%u area=%.17g\n", cs[c].outer ? "outer" : "hole", n, 0.5 * a);
        }
    }
    /* The same planes as one band: layers 0 .. 4 of y = -0.3 + 0.15 k. */
    st = ccss_query_slice_band_required_bytes(ev, q, normal, -0.3, 0.15, 0, 5, eps, &bytes, &detail);
    if (st != CCSS_OK) { rc = report("ccss_query_slice_band_required_bytes", st, &detail); goto out; }
    if (bytes > scratch_len) {
        free(scratch);
        if ((scratch = malloc(bytes)) == NULL) goto out;
        scratch_len = bytes;
    }
    st = ccss_query_slice_band(ev, q, normal, -0.3, 0.15, 0, 5, eps, scratch, scratch_len, band, &detail);
    if (st != CCSS_OK) { rc = report("ccss_query_slice_band", st, &detail); goto out; }
    for (k = 0; k < 5; k++) {
        double total = 0.0;
        uint32_t c;
        free(pts);
        free(cs);
        pts = malloc((band[k].points ? band[k].points : 1) * 2 * sizeof *pts);
        cs = malloc((band[k].contours ? band[k].contours : 1) * sizeof *cs);
        if (pts == NULL || cs == NULL) goto out;
        st = ccss_query_slice_band_write(scratch, scratch_len, band, 5, (size_t)k, pts, (size_t)band[k].points,
                                         cs, (size_t)band[k].contours, &detail);
        if (st != CCSS_OK) { rc = report("ccss_query_slice_band_write", st, &detail); goto out; }
        for (c = 0; c < band[k].contours; c++) {
            double a = 0.0;
            uint32_t j, s = cs[c].start, n = cs[c].len;
            for (j = 0; j < n; j++) {
                const double *p0 = &pts[2 * (s + j)], *p1 = &pts[2 * (s + (j + 1) % n)];
                a += p0[0] * p1[1] - p0[1] * p1[0];
            }
            total += 0.5 * a;
        }
        printf("band %d points=%llu contours=%llu area=%.17g\n", k, (unsigned long long)band[k].points,
               (unsigned long long)band[k].contours, total);
    }
    st = ccss_query_slice_required_bytes(ev, q, normal, 0.0, 0.0, &bytes, &detail);
    printf("error eps status=%d\n", (int)st);
    st = ccss_query_slice_band_required_bytes(ev, q, normal, -0.3, 0.15, 0, CCSS_QUERY_MAX_BAND + 1, eps, &bytes,
                                              &detail);
    printf("error band count status=%d\n", (int)st);
    (void)i;
    rc = 0;
out:
    free(cs);
    free(pts);
    free(scratch);
    free(q_mem);
    free(ev_mem);
    free(topo_mem);
    free(tables_mem);
    return rc;
}
