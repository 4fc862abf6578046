/*
 * slice.c: planar slices of a bundled torus (OpenSubdiv's catmark_torus,
 * 32 quads; its axis is y) with libccss, layer by layer into caller
 * buffers with exact size queries: planes y = y0 + k dy.
 *
 * Prints (lines starting with '#' are comments):
 *     layer k y=Y points=P contours=C
 *     contour outer|hole n=N area=A
 *     error eps status=S
 * Returns 0 on success.
 *
 * Build: cc -std=c99 -Iinclude c_examples/slice.c target/debug/libccss.a \
 *           -lpthread -ldl -lm -o slice
 */
#include "ccss.h"

#include <stdio.h>
#include <stdlib.h>

static int report(const char *what, ccss_status st, const ccss_error_detail *d)
{
    char msg[CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
    fprintf(stderr, "%s failed: %s (status %d)\n", what, ccss_status_message((int)st), (int)st);
    if (d != NULL) {
        ccss_error_detail_format(d, msg, sizeof msg);
        fprintf(stderr, "  detail: %s\n", msg);
    }
    return 1;
}

#define NV 32
#define NF 32

int main(void)
{
    static const double positions[NV * 3] = {
        1.250520, -0.353553, 0.517982,
        0.597239, -0.353553, 0.247384,
        0.597239, 0.353553, 0.247384,
        1.250520, 0.353553, 0.517982,
        0.517982, -0.353553, 1.250520,
        0.247384, -0.353553, 0.597239,
        0.247384, 0.353553, 0.597239,
        0.517982, 0.353553, 1.250520,
        -0.517982, -0.353553, 1.250520,
        -0.247384, -0.353553, 0.597239,
        -0.247384, 0.353553, 0.597239,
        -0.517982, 0.353553, 1.250520,
        -1.250520, -0.353553, 0.517982,
        -0.597239, -0.353553, 0.247384,
        -0.597239, 0.353553, 0.247384,
        -1.250520, 0.353553, 0.517982,
        -1.250520, -0.353553, -0.517982,
        -0.597239, -0.353553, -0.247384,
        -0.597239, 0.353553, -0.247384,
        -1.250520, 0.353553, -0.517982,
        -0.517982, -0.353553, -1.250520,
        -0.247384, -0.353553, -0.597239,
        -0.247384, 0.353553, -0.597239,
        -0.517982, 0.353553, -1.250520,
        0.517982, -0.353553, -1.250520,
        0.247384, -0.353553, -0.597239,
        0.247384, 0.353553, -0.597239,
        0.517982, 0.353553, -1.250520,
        1.250520, -0.353553, -0.517982,
        0.597239, -0.353553, -0.247384,
        0.597239, 0.353553, -0.247384,
        1.250520, 0.353553, -0.517982
    };
    static const uint32_t indices[NF * 4] = {
        4, 5, 1, 0,
        5, 6, 2, 1,
        6, 7, 3, 2,
        7, 4, 0, 3,
        8, 9, 5, 4,
        9, 10, 6, 5,
        10, 11, 7, 6,
        11, 8, 4, 7,
        12, 13, 9, 8,
        13, 14, 10, 9,
        14, 15, 11, 10,
        15, 12, 8, 11,
        16, 17, 13, 12,
        17, 18, 14, 13,
        18, 19, 15, 14,
        19, 16, 12, 15,
        20, 21, 17, 16,
        21, 22, 18, 17,
        22, 23, 19, 18,
        23, 20, 16, 19,
        24, 25, 21, 20,
        25, 26, 22, 21,
        26, 27, 23, 22,
        27, 24, 20, 23,
        28, 29, 25, 24,
        29, 30, 26, 25,
        30, 31, 27, 26,
        31, 28, 24, 27,
        0, 1, 29, 28,
        1, 2, 30, 29,
        2, 3, 31, 30,
        3, 0, 28, 31
    };
    uint32_t face_sizes[NF];
    static const double normal[3] = { 0.0, 1.0, 0.0 };
    ccss_error_detail detail;
    const ccss_tables *tables = NULL;
    const ccss_topology *topo = NULL;
    const ccss_evaluator *ev = NULL;
    ccss_query *q = NULL;
    ccss_query_slice_layer_stats ls;
    void *tables_mem = NULL, *topo_mem = NULL, *ev_mem = NULL, *q_mem = NULL, *scratch = NULL;
    double *pts = NULL;
    ccss_query_contour *cs = NULL;
    size_t bytes = 0, scratch_len = 0;
    const double eps = 1e-3;
    ccss_status st;
    int i, k, rc = 1;

    for (i = 0; i < NF; i++) face_sizes[i] = 4;

    st = ccss_tables_required_bytes(&bytes, NULL);
    if (st != CCSS_OK) return report("ccss_tables_required_bytes", st, NULL);
    if ((tables_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_tables_build_standard(tables_mem, bytes, &tables, NULL);
    if (st != CCSS_OK) { rc = report("ccss_tables_build_standard", st, NULL); goto out; }
    st = ccss_topology_required_bytes(NV, face_sizes, NF, &bytes, NULL);
    if (st != CCSS_OK) { rc = report("ccss_topology_required_bytes", st, NULL); goto out; }
    if ((topo_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_topology_build(positions, NV, face_sizes, NF, indices, NF * 4, topo_mem, bytes,
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
    st = ccss_query_slice_required_bytes(ev, q, normal, 0.0, 0.0, &bytes, &detail);
    printf("error eps status=%d\n", (int)st);
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
