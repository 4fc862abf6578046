/*
 * boolean.c: union / intersection / difference of two Catmull-Clark limit
 * solids within a tolerance with libccss, written as a binary STL.
 *
 * Usage: boolean [OUT.stl [A.obj B.obj [EPS [OP]]]]
 *   OUT.stl    where to write the triangles (nothing is written without it)
 *   A.obj B.obj closed polygon meshes; default (or '-'): a built-in
 *              pentagonal prism and a rotated, shifted copy of it
 *   EPS        tolerance in model units (default 0.01)
 *   OP         union (default), intersection or difference
 *
 * Both limit surfaces are tessellated with a guaranteed bound t, the two
 * triangle meshes are combined by ccss_boolean_*, and t is reduced to
 * eps / (1.05 amplification) until amplification x bound <= eps (see
 * ccss_boolean_counts_info.amplification).
 *
 * Prints '# ...' comments and one line
 *     triangles=T vertices=V curve_loops=L curve_points=P amplification=A bound=B
 * then, with OUT.stl, 'stl=OUT.stl triangles=T'. Returns 0 on success.
 *
 * Build: cc -std=c99 -Iinclude c_examples/boolean.c target/debug/libccss.a \
 *           -lpthread -ldl -lm -o boolean
 */
#include "ccss.h"
#include "example_mesh.h"
#include "example_report.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>



/* A tessellation as triangles. */
typedef struct trimesh {
    double *pos;
    size_t nv;
    uint32_t *tri;
    size_t nt;
    double bound;
} trimesh;

static void trimesh_free(trimesh *t)
{
    free(t->pos);
    free(t->tri);
    memset(t, 0, sizeof *t);
}

/* Topology, evaluator and tessellation of m at absolute tolerance tol. */
static int tessellate_solid(const ccss_tables *tables, const mesh *m, double tol, trimesh *out)
{
    ccss_error_detail detail;
    const ccss_topology *topo = NULL;
    const ccss_evaluator *ev = NULL;
    ccss_tessellation *tess = NULL;
    void *topo_mem = NULL, *ev_mem = NULL, *tess_mem = NULL;
    uint32_t *sizes = NULL, *idx = NULL;
    size_t bytes = 0;
    ccss_status st = CCSS_OK;
    ccss_tessellation_options opt;
    ccss_tessellation_counts_info c;
    ccss_tessellation_output o;
    int rc = 1;

    memset(out, 0, sizeof *out);
    st = ccss_topology_required_bytes(m->nv, m->sizes, m->nf, &bytes, NULL);
    if (st != CCSS_OK) { rc = report("ccss_topology_required_bytes", st, NULL); goto done; }
    if ((topo_mem = malloc(bytes)) == NULL) goto done;
    st = ccss_topology_build(m->pos, m->nv, m->sizes, m->nf, m->idx, m->ni, topo_mem, bytes, &topo,
                             &detail);
    if (st != CCSS_OK) { rc = report("ccss_topology_build", st, &detail); goto done; }
    st = ccss_evaluator_required_bytes(topo, tables, &bytes, &detail);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_required_bytes", st, &detail); goto done; }
    if ((ev_mem = malloc(bytes)) == NULL) goto done;
    st = ccss_evaluator_build(topo, tables, ev_mem, bytes, &ev, &detail);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_build", st, &detail); goto done; }
    memset(&opt, 0, sizeof opt);
    opt.criterion = CCSS_TESSELLATION_ABSOLUTE;
    opt.tolerance = tol;
    st = ccss_tessellation_required_bytes(topo, ev, &opt, &bytes, &detail);
    if (st != CCSS_OK) { rc = report("ccss_tessellation_required_bytes", st, &detail); goto done; }
    if ((tess_mem = malloc(bytes)) == NULL) goto done;
    st = ccss_tessellation_build(topo, ev, &opt, tess_mem, bytes, &tess, &detail);
    if (st != CCSS_OK) { rc = report("ccss_tessellation_build", st, &detail); goto done; }
    st = ccss_tessellation_counts(tess, &c, NULL);
    if (st != CCSS_OK) { rc = report("ccss_tessellation_counts", st, NULL); goto done; }
    out->nv = c.vertices;
    out->nt = c.triangles;
    out->bound = c.bound;
    out->pos = malloc(3 * c.vertices * sizeof *out->pos);
    out->tri = malloc(3 * c.triangles * sizeof *out->tri);
    sizes = malloc(c.polygons * sizeof *sizes);
    idx = malloc(c.polygon_indices * sizeof *idx);
    if (!out->pos || !out->tri || !sizes || !idx) goto done;
    memset(&o, 0, sizeof o);
    o.positions = out->pos;
    o.positions_len = 3 * c.vertices;
    o.polygon_sizes = sizes;
    o.polygon_sizes_len = c.polygons;
    o.polygon_indices = idx;
    o.polygon_indices_len = c.polygon_indices;
    o.triangles = out->tri;
    o.triangles_len = 3 * c.triangles;
    st = ccss_tessellation_emit(tess, &o, &detail);
    if (st != CCSS_OK) { rc = report("ccss_tessellation_emit", st, &detail); goto done; }
    rc = 0;
done:
    if (rc != 0) trimesh_free(out);
    free(sizes);
    free(idx);
    free(tess_mem);
    free(ev_mem);
    free(topo_mem);
    return rc;
}

/* The built-in prism, rotated about z and x and shifted. */
static void move_mesh(mesh *m)
{
    size_t v;
    const double cz = cos(0.41), sz = sin(0.41), cx = cos(0.27), sx = sin(0.27);
    for (v = 0; v < m->nv; v++) {
        double *p = m->pos + 3 * v;
        double x = cz * p[0] - sz * p[1], y = sz * p[0] + cz * p[1], z = p[2];
        double y2 = cx * y - sx * z, z2 = sx * y + cx * z;
        p[0] = x + 0.37;
        p[1] = y2 + 0.21;
        p[2] = z2 + 0.13;
    }
}

int main(int argc, char **argv)
{
    const char *out_path = argc > 1 ? argv[1] : NULL;
    const char *a_path = argc > 3 && strcmp(argv[2], "-") != 0 ? argv[2] : NULL;
    const char *b_path = argc > 3 && strcmp(argv[3], "-") != 0 ? argv[3] : NULL;
    double eps = argc > 4 ? strtod(argv[4], NULL) : 0.01;
    const char *op_name = argc > 5 ? argv[5] : "union";
    uint32_t op = CCSS_BOOLEAN_UNION;
    mesh ma, mb;
    trimesh ta, tb;
    ccss_error_detail detail;
    const ccss_tables *tables = NULL;
    ccss_boolean *bo = NULL;
    void *tables_mem = NULL, *bo_mem = NULL;
    double *pos = NULL;
    uint32_t *tri = NULL, *csizes = NULL, *cidx = NULL;
    size_t bytes = 0;
    ccss_status st = CCSS_OK;
    ccss_boolean_mesh ia, ib;
    ccss_boolean_options bopt;
    ccss_boolean_counts_info c;
    ccss_boolean_output o;
    double tol, bound = 0.0;
    int pass, rc = 1;

    memset(&ma, 0, sizeof ma);
    memset(&mb, 0, sizeof mb);
    memset(&ta, 0, sizeof ta);
    memset(&tb, 0, sizeof tb);
    memset(&c, 0, sizeof c);
    if (strcmp(op_name, "intersection") == 0) op = CCSS_BOOLEAN_INTERSECTION;
    else if (strcmp(op_name, "difference") == 0) op = CCSS_BOOLEAN_DIFFERENCE;
    else if (strcmp(op_name, "union") != 0) {
        fprintf(stderr, "boolean: unknown operation '%s'\n", op_name);
        return 2;
    }
    if (!(eps > 0.0)) {
        fprintf(stderr, "boolean: EPS must be positive\n");
        return 2;
    }
    printf("# ccss %s\n", ccss_version());
    if (a_path != NULL ? read_obj(a_path, &ma) : builtin_prism(&ma)) goto out;
    if (b_path != NULL ? read_obj(b_path, &mb) : builtin_prism(&mb)) goto out;
    if (b_path == NULL) move_mesh(&mb);

    st = ccss_tables_required_bytes(&bytes, NULL);
    if (st != CCSS_OK) { rc = report("ccss_tables_required_bytes", st, NULL); goto out; }
    if ((tables_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_tables_build_standard(tables_mem, bytes, &tables, NULL);
    if (st != CCSS_OK) { rc = report("ccss_tables_build_standard", st, NULL); goto out; }

    memset(&bopt, 0, sizeof bopt); /* max_amplification 0: the default */
    tol = eps / 1.25;
    for (pass = 1; pass <= 6; pass++) {
        trimesh_free(&ta);
        trimesh_free(&tb);
        free(bo_mem);
        bo_mem = NULL;
        if (tessellate_solid(tables, &ma, tol, &ta) || tessellate_solid(tables, &mb, tol, &tb))
            goto out;
        ia.positions = ta.pos;
        ia.num_vertices = ta.nv;
        ia.triangles = ta.tri;
        ia.num_triangles = ta.nt;
        ib.positions = tb.pos;
        ib.num_vertices = tb.nv;
        ib.triangles = tb.tri;
        ib.num_triangles = tb.nt;
        /* The size before the crossings are known; the build names the rest. */
        st = ccss_boolean_required_bytes(&ia, &ib, &bytes, &detail);
        if (st != CCSS_OK) { rc = report("ccss_boolean_required_bytes", st, &detail); goto out; }
        if ((bo_mem = malloc(bytes)) == NULL) goto out;
        st = ccss_boolean_build(&ia, &ib, op, &bopt, bo_mem, bytes, &bo, &detail);
        if (st == CCSS_ERR_BUFFER_TOO_SMALL) {
            printf("# pass %d: boolean needs %lu bytes\n", pass, (unsigned long)detail.required);
            free(bo_mem);
            bytes = (size_t)detail.required;
            if ((bo_mem = malloc(bytes)) == NULL) goto out;
            st = ccss_boolean_build(&ia, &ib, op, &bopt, bo_mem, bytes, &bo, &detail);
        }
        if (st != CCSS_OK) { rc = report("ccss_boolean_build", st, &detail); goto out; }
        st = ccss_boolean_counts(bo, &c, NULL);
        if (st != CCSS_OK) { rc = report("ccss_boolean_counts", st, NULL); goto out; }
        bound = c.amplification * (ta.bound > tb.bound ? ta.bound : tb.bound);
        printf("# pass %d: tolerance %.6g, amplification %.6g, bound %.6g\n", pass, tol,
               c.amplification, bound);
        if (bound <= eps) break;
        tol = eps / (1.05 * c.amplification);
    }
    if (bound > eps) {
        fprintf(stderr, "boolean: eps not reached\n");
        goto out;
    }

    pos = malloc((3 * c.vertices + 1) * sizeof *pos);
    tri = malloc((3 * c.triangles + 1) * sizeof *tri);
    csizes = malloc((c.curve_loops + 1) * sizeof *csizes);
    cidx = malloc((c.curve_points + 1) * sizeof *cidx);
    if (!pos || !tri || !csizes || !cidx) goto out;
    memset(&o, 0, sizeof o);
    o.positions = pos;
    o.positions_len = 3 * c.vertices;
    o.triangles = tri;
    o.triangles_len = 3 * c.triangles;
    o.curve_sizes = csizes;
    o.curve_sizes_len = c.curve_loops;
    o.curve_indices = cidx;
    o.curve_indices_len = c.curve_points;
    /* One element short: an error naming the required size, nothing written. */
    o.triangles_len -= 1;
    st = ccss_boolean_emit(bo, &o, &detail);
    printf("# one triangle index short: status %d, required %lu\n", (int)st,
           (unsigned long)detail.required);
    if (st != CCSS_ERR_BUFFER_TOO_SMALL || detail.required != 3 * c.triangles) goto out;
    o.triangles_len += 1;
    st = ccss_boolean_emit(bo, &o, &detail);
    if (st != CCSS_OK) { rc = report("ccss_boolean_emit", st, &detail); goto out; }
    printf("triangles=%lu vertices=%lu curve_loops=%lu curve_points=%lu amplification=%.6g "
           "bound=%.6g\n",
           (unsigned long)c.triangles, (unsigned long)c.vertices, (unsigned long)c.curve_loops,
           (unsigned long)c.curve_points, c.amplification, bound);
    if (out_path != NULL) {
        if (write_stl(out_path, "ccss boolean.c: limit solids within eps", pos, tri, c.triangles)) goto out;
        printf("stl=%s triangles=%lu\n", out_path, (unsigned long)c.triangles);
    }
    rc = 0;
out:
    if (rc != 0 && st == CCSS_OK) fprintf(stderr, "boolean: failed\n");
    free(pos);
    free(tri);
    free(csizes);
    free(cidx);
    free(bo_mem);
    trimesh_free(&ta);
    trimesh_free(&tb);
    free(tables_mem);
    mesh_free(&ma);
    mesh_free(&mb);
    return rc;
}
