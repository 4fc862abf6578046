/*
 * eval.c: evaluate the Catmull-Clark limit surface of a cube with libccss.
 *
 * Builds the eigen tables, the topology and the evaluator in malloc'd
 * memory (after asking each size), prints a 5x5 grid of (u, v) on face 0 as
 *     u v px py pz nx ny nz
 * lines (%.17g), then demonstrates an error. A second evaluator built with
 * ccss_evaluator_options_compact (least memory) must give the same grid bit
 * for bit ('# compact: ...'), and ccss_evaluator_eval_derivs (no normal,
 * cheaper per call) the same positions and derivatives ('# derivs: ...').
 * Lines starting with '#' are comments. Returns 0 on success.
 *
 * Build: cc -std=c99 -Iinclude c_examples/eval.c target/debug/libccss.a \
 *           -lpthread -ldl -lm -o eval
 */
#include "ccss.h"
#include "example_report.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(void)
{
    /* The cube [-1, 1]^3: v0..v3 at z = -1, v4..v7 at z = +1. */
    static const double positions[8 * 3] = {
        -1, -1, -1,  1, -1, -1,  1, 1, -1,  -1, 1, -1,
        -1, -1,  1,  1, -1,  1,  1, 1,  1,  -1, 1,  1,
    };
    /* Six quads, counter-clockwise seen from outside; face 0 is z = -1. */
    static const uint32_t face_sizes[6] = { 4, 4, 4, 4, 4, 4 };
    static const uint32_t indices[24] = {
        0, 3, 2, 1,  4, 5, 6, 7,  0, 1, 5, 4,
        1, 2, 6, 5,  2, 3, 7, 6,  3, 0, 4, 7,
    };
    ccss_error_detail detail;
    const ccss_tables *tables = NULL;
    const ccss_topology *topo = NULL;
    const ccss_evaluator *ev = NULL;
    const ccss_evaluator *small = NULL;
    void *tables_mem = NULL, *topo_mem = NULL, *ev_mem = NULL, *small_mem = NULL;
    size_t bytes = 0, small_bytes = 0, faces = 0;
    ccss_evaluator_options compact;
    ccss_evaluator_result rs;
    int same = 0, same_derivs = 0;
    ccss_status st = CCSS_OK;
    ccss_evaluator_result r;
    char msg[CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
    int i, j, rc = 1;

    printf("# ccss %s\n", ccss_version());

    /* 1. Eigen tables (independent of the mesh; build once, share). */
    st = ccss_tables_required_bytes(&bytes, NULL);
    if (st != CCSS_OK) return report("ccss_tables_required_bytes", st, NULL);
    tables_mem = malloc(bytes);
    if (tables_mem == NULL) goto out;
    st = ccss_tables_build_standard(tables_mem, bytes, &tables, NULL);
    if (st != CCSS_OK) { rc = report("ccss_tables_build_standard", st, NULL); goto out; }

    /* 2. Topology: validates the mesh and copies the arrays. */
    st = ccss_topology_required_bytes(8, face_sizes, 6, &bytes, NULL);
    if (st != CCSS_OK) { rc = report("ccss_topology_required_bytes", st, NULL); goto out; }
    topo_mem = malloc(bytes);
    if (topo_mem == NULL) goto out;
    st = ccss_topology_build(positions, 8, face_sizes, 6, indices, 24, topo_mem, bytes, &topo,
                             &detail);
    if (st != CCSS_OK) { rc = report("ccss_topology_build", st, &detail); goto out; }

    /* 3. Evaluator: needs the tables for its whole life, not the topology. */
    st = ccss_evaluator_required_bytes(topo, tables, &bytes, &detail);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_required_bytes", st, &detail); goto out; }
    ev_mem = malloc(bytes);
    if (ev_mem == NULL) goto out;
    st = ccss_evaluator_build(topo, tables, ev_mem, bytes, &ev, &detail);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_build", st, &detail); goto out; }

    /* The same surface in less memory: nothing precomputed per
       extraordinary patch beyond its eigen projection (slower queries). */
    st = ccss_evaluator_options_compact(&compact, NULL);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_options_compact", st, NULL); goto out; }
    st = ccss_evaluator_required_bytes_with_options(topo, tables, &compact, &small_bytes, &detail);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_required_bytes_with_options", st, &detail); goto out; }
    small_mem = malloc(small_bytes);
    if (small_mem == NULL) goto out;
    st = ccss_evaluator_build_with_options(topo, tables, &compact, small_mem, small_bytes, &small,
                                           &detail);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_build_with_options", st, &detail); goto out; }
    free(topo_mem); /* allowed: the evaluator does not refer to the topology */
    topo_mem = NULL;
    topo = NULL;

    st = ccss_evaluator_face_count(ev, &faces, NULL);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_face_count", st, NULL); goto out; }
    printf("# faces %zu\n", faces);

    /* 4. A 5x5 grid on face 0. */
    printf("# u v px py pz nx ny nz\n");
    for (j = 0; j <= 4; j++) {
        for (i = 0; i <= 4; i++) {
            double u = i / 4.0, v = j / 4.0;
            st = ccss_evaluator_eval(ev, 0, 0, u, v, &r, NULL);
            if (st != CCSS_OK) { rc = report("ccss_evaluator_eval", st, NULL); goto out; }
            printf("%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", u, v, r.p[0], r.p[1],
                   r.p[2], r.normal[0], r.normal[1], r.normal[2]);
            st = ccss_evaluator_eval(small, 0, 0, u, v, &rs, NULL);
            if (st != CCSS_OK) { rc = report("ccss_evaluator_eval (compact)", st, NULL); goto out; }
            same += memcmp(&r, &rs, sizeof r) == 0;
            /* Without the normal (cheaper per call): the same position and
               derivatives, a zero normal. */
            st = ccss_evaluator_eval_derivs(ev, 0, 0, u, v, &rs, NULL);
            if (st != CCSS_OK) { rc = report("ccss_evaluator_eval_derivs", st, NULL); goto out; }
            same_derivs += memcmp(r.p, rs.p, sizeof r.p) == 0 && memcmp(r.du, rs.du, sizeof r.du) == 0 &&
                           memcmp(r.dv, rs.dv, sizeof r.dv) == 0 && rs.normal[0] == 0.0 &&
                           rs.normal[1] == 0.0 && rs.normal[2] == 0.0;
        }
    }
    printf("# derivs: %d of 25 points bit for bit, normal zero\n", same_derivs);

    printf("# compact: %d of 25 points bit for bit, %lu of %lu bytes\n", same,
           (unsigned long)small_bytes, (unsigned long)bytes);
    if (same != 25 || same_derivs != 25) {
        fprintf(stderr, "eval: the compact evaluator or ccss_evaluator_eval_derivs differs\n");
        goto out;
    }

    /* 5. An error: face 99 does not exist. */
    st = ccss_evaluator_eval(ev, 99, 0, 0.5, 0.5, &r, NULL);
    printf("# error: ccss_evaluator_eval(face 99, NULL) -> %d %s\n", (int)st, ccss_status_message((int)st));
    if (st != CCSS_ERR_FACE_OUT_OF_RANGE) {
        fprintf(stderr, "eval: expected CCSS_ERR_FACE_OUT_OF_RANGE\n");
        goto out;
    }
    {
        ccss_evaluator_query q[2];
        ccss_evaluator_result res[2];
        q[0].face = 0;  q[0].sub = 0; q[0].u = 0.5; q[0].v = 0.5;
        q[1].face = 99; q[1].sub = 0; q[1].u = 0.5; q[1].v = 0.5;
        st = ccss_evaluator_eval_batch(ev, q, 2, 0, res, 2, &detail);
        ccss_error_detail_format(&detail, msg, sizeof msg);
        printf("# error: ccss_evaluator_eval_batch -> %d %s; detail: query %lu face %ld: %s\n", (int)st,
               ccss_status_message((int)st), (unsigned long)detail.query_index,
               (long)detail.face, msg);
        if (st != CCSS_ERR_FACE_OUT_OF_RANGE || detail.query_index != 1 || detail.face != 99) {
            fprintf(stderr, "eval: unexpected batch error detail\n");
            goto out;
        }
    }
    rc = 0;

out:
    if (rc != 0 && st == CCSS_OK) fprintf(stderr, "eval: out of memory\n");
    free(ev_mem); /* the evaluators first, then the tables they refer to */
    free(small_mem);
    free(topo_mem);
    free(tables_mem);
    return rc;
}
