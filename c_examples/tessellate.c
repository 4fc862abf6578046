/*
 * tessellate.c: adaptive tessellation of a Catmull-Clark limit surface to an
 * absolute tolerance with libccss, written as a binary STL.
 *
 * Usage: tessellate [OUT.stl [MESH.obj [TOLERANCE]]]
 *   OUT.stl    where to write the triangles (nothing is written without it)
 *   MESH.obj   a closed polygon mesh (v and f lines; e.g. one of the bundled
 *              tests/data/osd/catmark_*.obj); default: a pentagonal prism
 *              built in (two pentagons, five quads, valence-3 vertices)
 *   TOLERANCE  absolute flatness in model units (default 0.01): every point
 *              of the limit surface is within it of the triangles, and
 *              every point of the triangles within it of the surface
 *
 * Prints '# ...' comments and one line
 *     vertices=V polygons=P triangles=T max_level=L bound=B uniform_depth=U
 * then, with OUT.stl, 'stl=OUT.stl triangles=T'. Returns 0 on success.
 *
 * All memory is the caller's: each ccss object is built into a malloc'd
 * block whose size ccss reports first.
 *
 * Build: cc -std=c99 -Iinclude c_examples/tessellate.c target/debug/libccss.a \
 *           -lpthread -ldl -lm -o tessellate
 */
#include "ccss.h"
#include "example_mesh.h"
#include "example_report.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


int main(int argc, char **argv)
{
    const char *out_path = argc > 1 ? argv[1] : NULL;
    const char *mesh_path = argc > 2 ? argv[2] : NULL;
    double tol = argc > 3 ? strtod(argv[3], NULL) : 0.01;
    mesh m;
    ccss_error_detail detail;
    const ccss_tables *tables = NULL;
    const ccss_topology *topo = NULL;
    const ccss_evaluator *ev = NULL;
    ccss_tessellation *tess = NULL;
    void *tables_mem = NULL, *topo_mem = NULL, *ev_mem = NULL, *tess_mem = NULL;
    double *pos = NULL, *nrm = NULL;
    uint32_t *sizes = NULL, *idx = NULL, *tri = NULL;
    size_t bytes = 0;
    uint32_t uniform = 0;
    ccss_status st = CCSS_OK;
    ccss_tessellation_options opt;
    ccss_tessellation_counts_info c;
    ccss_tessellation_output o;
    int rc = 1;

    memset(&m, 0, sizeof m);
    printf("# ccss %s\n", ccss_version());
    if (mesh_path != NULL ? read_obj(mesh_path, &m) : builtin_prism(&m)) goto out;
    printf("# mesh %s: %lu vertices, %lu faces\n", mesh_path ? mesh_path : "(built-in prism)",
           (unsigned long)m.nv, (unsigned long)m.nf);

    /* 1. Tables, topology, evaluator (see eval.c). */
    st = ccss_tables_required_bytes(&bytes, NULL);
    if (st != CCSS_OK) { rc = report("ccss_tables_required_bytes", st, NULL); goto out; }
    if ((tables_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_tables_build_standard(tables_mem, bytes, &tables, NULL);
    if (st != CCSS_OK) { rc = report("ccss_tables_build_standard", st, NULL); goto out; }
    st = ccss_topology_required_bytes(m.nv, m.sizes, m.nf, &bytes, NULL);
    if (st != CCSS_OK) { rc = report("ccss_topology_required_bytes", st, NULL); goto out; }
    if ((topo_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_topology_build(m.pos, m.nv, m.sizes, m.nf, m.idx, m.ni, topo_mem, bytes, &topo,
                             &detail);
    if (st != CCSS_OK) { rc = report("ccss_topology_build", st, &detail); goto out; }
    st = ccss_evaluator_required_bytes(topo, tables, &bytes, &detail);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_required_bytes", st, &detail); goto out; }
    if ((ev_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_evaluator_build(topo, tables, ev_mem, bytes, &ev, &detail);
    if (st != CCSS_OK) { rc = report("ccss_evaluator_build", st, &detail); goto out; }

    /* 2. The tessellation: size query, build (marking), counts. */
    memset(&opt, 0, sizeof opt);
    opt.criterion = CCSS_TESSELLATION_ABSOLUTE;
    opt.tolerance = tol;
    opt.max_level = 0; /* CCSS_TESSELLATION_MAX_LEVEL */
    st = ccss_tessellation_required_bytes(topo, ev, &opt, &bytes, &detail);
    if (st != CCSS_OK) { rc = report("ccss_tessellation_required_bytes", st, &detail); goto out; }
    if ((tess_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_tessellation_build(topo, ev, &opt, tess_mem, bytes, &tess, &detail);
    if (st != CCSS_OK) { rc = report("ccss_tessellation_build", st, &detail); goto out; }
    free(topo_mem); /* the tessellation copied what it needs */
    topo_mem = NULL;
    st = ccss_tessellation_counts(tess, &c, NULL);
    if (st != CCSS_OK) { rc = report("ccss_tessellation_counts", st, NULL); goto out; }

    /* 3. Emission into arrays of exactly the counted sizes. */
    pos = malloc(3 * c.vertices * sizeof *pos);
    nrm = malloc(3 * c.vertices * sizeof *nrm);
    sizes = malloc(c.polygons * sizeof *sizes);
    idx = malloc(c.polygon_indices * sizeof *idx);
    tri = malloc(3 * c.triangles * sizeof *tri);
    if (!pos || !nrm || !sizes || !idx || !tri) goto out;
    memset(&o, 0, sizeof o);
    o.positions = pos;
    o.positions_len = 3 * c.vertices;
    o.normals = nrm;
    o.normals_len = 3 * c.vertices;
    o.polygon_sizes = sizes;
    o.polygon_sizes_len = c.polygons;
    o.polygon_indices = idx;
    o.polygon_indices_len = c.polygon_indices;
    o.triangles = tri;
    o.triangles_len = 3 * c.triangles;
    st = ccss_tessellation_emit(tess, &o, &detail);
    if (st != CCSS_OK) { rc = report("ccss_tessellation_emit", st, &detail); goto out; }

    /* 4. How deep would a uniform tessellation with the same bound be? */
    st = ccss_tessellation_uniform_depth(ev, &opt, c.max_level, &uniform, &detail);
    if (st != CCSS_OK) { rc = report("ccss_tessellation_uniform_depth", st, &detail); goto out; }
    printf("vertices=%lu polygons=%lu triangles=%lu max_level=%u bound=%.6g uniform_depth=%u\n",
           (unsigned long)c.vertices, (unsigned long)c.polygons, (unsigned long)c.triangles,
           (unsigned)c.max_level, c.bound, (unsigned)uniform);

    /* A buffer one element short is an error naming the required size. */
    o.triangles_len -= 1;
    st = ccss_tessellation_emit(tess, &o, &detail);
    printf("# one triangle index short: status %d, required %lu\n", (int)st,
           (unsigned long)detail.required);
    if (st != CCSS_ERR_BUFFER_TOO_SMALL || detail.required != 3 * c.triangles) goto out;

    if (out_path != NULL) {
        if (write_stl(out_path, "ccss tessellate.c: exact limit-surface points", pos, tri, c.triangles)) goto out;
        printf("stl=%s triangles=%lu\n", out_path, (unsigned long)c.triangles);
    }
    rc = 0;
out:
    if (rc != 0 && st == CCSS_OK) fprintf(stderr, "tessellate: failed\n");
    free(pos);
    free(nrm);
    free(sizes);
    free(idx);
    free(tri);
    free(tess_mem);
    free(ev_mem);
    free(topo_mem);
    free(tables_mem);
    mesh_free(&m);
    return rc;
}
