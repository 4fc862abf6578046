/*
 * raycast.c: certified queries on the limit surface of a bundled torus
 * (OpenSubdiv's catmark_torus, 32 quads) with libccss: the first hit and
 * all hits of a few rays (one batch call for the first hits), inside/outside
 * of points, and closest points, through the torus' slot index (built once,
 * attached to the query area: the queries then visit only the slots they
 * can reach, with the same answers).
 *
 * Prints (lines starting with '#' are comments):
 *     first i found=F t=T face=F sub=S u=U v=V point=X,Y,Z transversal=B
 *     all i n=N t=T1,T2,...
 *     inside i value=B
 *     closest i dist=D face=F sub=S u=U v=V point=X,Y,Z
 *     error zero_direction status=S
 * Returns 0 on success.
 *
 * Build: cc -std=c99 -Iinclude c_examples/raycast.c target/debug/libccss.a \
 *           -lpthread -ldl -lm -o raycast
 */
#include "ccss.h"
#include "example_report.h"
#include "example_torus.h"

#include <stdio.h>
#include <stdlib.h>

int main(void)
{
    uint32_t face_sizes[TORUS_NF];
    static const ccss_query_ray rays[4] = {
        { { -3.0, 0.01, 0.02 }, { 1.0, 0.0, 0.0 } },    /* through the ring: 4 hits */
        { { 0.9, 2.0, 0.1 }, { 0.0, -1.0, 0.0 } },     /* through the tube: 2 hits */
        { { 0.0, 0.0, 0.0 }, { 0.3, 0.05, 1.0 } },     /* from the hole outwards: 2 hits */
        { { 5.0, 5.0, 5.0 }, { 1.0, 0.0, 0.0 } }       /* a miss */
    };
    static const double points[3 * 3] = {
        0.9, 0.0, 0.05,   /* in the tube */
        0.0, 0.0, 0.0,    /* in the hole */
        3.0, 1.0, -2.0    /* far outside */
    };
    ccss_query_hit first[4], hits[8];
    ccss_query_closest_info near[3];
    int found[4], inside = 0;
    ccss_error_detail detail;
    const ccss_tables *tables = NULL;
    const ccss_topology *topo = NULL;
    const ccss_evaluator *ev = NULL;
    ccss_query *q = NULL;
    ccss_query_index *index = NULL;
    void *tables_mem = NULL, *topo_mem = NULL, *ev_mem = NULL, *q_mem = NULL, *index_mem = NULL;
    size_t bytes = 0, n = 0, k;
    const double tol = 1e-9;
    ccss_status st;
    int i, rc = 1;

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
    printf("# query bytes %lu\n", (unsigned long)bytes);
    if ((q_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_query_build(q_mem, bytes, &q, &detail);
    if (st != CCSS_OK) { rc = report("ccss_query_build", st, &detail); goto out; }
    st = ccss_query_index_required_bytes(ev, &bytes, &detail);
    if (st != CCSS_OK) { rc = report("ccss_query_index_required_bytes", st, &detail); goto out; }
    printf("# index bytes %lu\n", (unsigned long)bytes);
    if ((index_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_query_index_build(ev, index_mem, bytes, &index, &detail);
    if (st != CCSS_OK) { rc = report("ccss_query_index_build", st, &detail); goto out; }
    st = ccss_query_set_index(q, index, &detail);
    if (st != CCSS_OK) { rc = report("ccss_query_set_index", st, &detail); goto out; }

    /* First hits of the batch. */
    st = ccss_query_ray_first(ev, q, rays, 4, tol, first, found, &detail);
    if (st != CCSS_OK) { rc = report("ccss_query_ray_first", st, &detail); goto out; }
    for (i = 0; i < 4; i++) {
        if (!found[i]) { printf("first %d found=0\n", i); continue; }
        printf("first %d found=1 t=%.17g face=%u sub=%u u=%.17g v=%.17g point=%.17g,%.17g,%.17g transversal=%d\n",
               i, first[i].t, first[i].face, first[i].sub, first[i].u, first[i].v,
               first[i].point[0], first[i].point[1], first[i].point[2], first[i].transversal);
    }
    /* All hits: a size query (BUFFER_TOO_SMALL with the count), then the call. */
    for (i = 0; i < 4; i++) {
        st = ccss_query_ray_all(ev, q, &rays[i], tol, NULL, 0, &n, &detail);
        if (st == CCSS_ERR_BUFFER_TOO_SMALL) n = (size_t)detail.required;
        else if (st != CCSS_OK) { rc = report("ccss_query_ray_all (size)", st, &detail); goto out; }
        if (n > 8) { fprintf(stderr, "too many hits\n"); goto out; }
        st = ccss_query_ray_all(ev, q, &rays[i], tol, hits, 8, &n, &detail);
        if (st != CCSS_OK) { rc = report("ccss_query_ray_all", st, &detail); goto out; }
        printf("all %d n=%lu t=", i, (unsigned long)n);
        for (k = 0; k < n; k++) printf("%s%.17g", k ? "," : "", hits[k].t);
        printf("\n");
    }
    for (i = 0; i < 3; i++) {
        st = ccss_query_inside(ev, q, &points[3 * i], tol, &inside, &detail);
        if (st != CCSS_OK) { rc = report("ccss_query_inside", st, &detail); goto out; }
        printf("inside %d value=%d\n", i, inside);
    }
    st = ccss_query_closest(ev, q, points, 3, tol, near, &detail);
    if (st != CCSS_OK) { rc = report("ccss_query_closest", st, &detail); goto out; }
    for (i = 0; i < 3; i++)
        printf("closest %d dist=%.17g face=%u sub=%u u=%.17g v=%.17g point=%.17g,%.17g,%.17g\n", i,
               near[i].dist, near[i].face, near[i].sub, near[i].u, near[i].v, near[i].point[0],
               near[i].point[1], near[i].point[2]);
    {
        /* Bad input: a zero direction is INVALID_ARGUMENT naming the ray. */
        ccss_query_ray bad[2] = { { { 0, 0, 0 }, { 1, 0, 0 } }, { { 0, 0, 0 }, { 0, 0, 0 } } };
        st = ccss_query_ray_first(ev, q, bad, 2, tol, first, found, &detail);
        printf("error zero_direction status=%d index=%llu\n", (int)st,
               (unsigned long long)detail.query_index);
    }
    rc = 0;
out:
    free(q_mem);
    free(index_mem);
    free(ev_mem);
    free(topo_mem);
    free(tables_mem);
    return rc;
}
