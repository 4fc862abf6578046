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

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* A growable array of T (pointer, count, capacity). */
#define GROW(ptr, n, cap)                                                   \
    do {                                                                    \
        if ((n) == (cap)) {                                                 \
            size_t c2_ = (cap) ? 2 * (cap) : 64;                            \
            void *p2_ = realloc((ptr), c2_ * sizeof *(ptr));                \
            if (p2_ == NULL) goto oom;                                      \
            (ptr) = p2_;                                                    \
            (cap) = c2_;                                                    \
        }                                                                   \
    } while (0)

typedef struct mesh {
    double *pos;
    size_t nv, cap_v; /* nv counts vertices; pos holds 3 * cap_v doubles */
    uint32_t *sizes;
    size_t nf, cap_f;
    uint32_t *idx;
    size_t ni, cap_i;
} mesh;

static void mesh_free(mesh *m)
{
    free(m->pos);
    free(m->sizes);
    free(m->idx);
    memset(m, 0, sizeof *m);
}

/* Reads 'v x y z' and 'f a b c ...' lines (a may be 'a/t/n'; negative
 * indices count back). Returns 0 on success. */
static int read_obj(const char *path, mesh *m)
{
    char line[4096];
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        fprintf(stderr, "cannot open %s\n", path);
        return 1;
    }
    while (fgets(line, sizeof line, f) != NULL) {
        if (line[0] == 'v' && line[1] == ' ') {
            double x, y, z;
            if (sscanf(line + 2, "%lf %lf %lf", &x, &y, &z) != 3) goto bad;
            if (m->nv == m->cap_v) {
                size_t c2 = m->cap_v ? 2 * m->cap_v : 64;
                void *p2 = realloc(m->pos, 3 * c2 * sizeof *m->pos);
                if (p2 == NULL) goto oom;
                m->pos = p2;
                m->cap_v = c2;
            }
            m->pos[3 * m->nv] = x;
            m->pos[3 * m->nv + 1] = y;
            m->pos[3 * m->nv + 2] = z;
            m->nv++;
        } else if (line[0] == 'f' && line[1] == ' ') {
            char *s = line + 2;
            uint32_t count = 0;
            for (;;) {
                char *end;
                long k = strtol(s, &end, 10);
                if (end == s) break;
                if (k < 0) k += (long)m->nv + 1;
                if (k < 1 || (size_t)k > m->nv) goto bad;
                GROW(m->idx, m->ni, m->cap_i);
                m->idx[m->ni++] = (uint32_t)(k - 1);
                count++;
                s = end;
                while (*s != '\0' && *s != ' ' && *s != '\t' && *s != '\n' && *s != '\r') s++;
            }
            GROW(m->sizes, m->nf, m->cap_f);
            m->sizes[m->nf++] = count;
        }
    }
    fclose(f);
    return 0;
bad:
    fprintf(stderr, "%s: cannot parse: %s", path, line);
    fclose(f);
    return 1;
oom:
    fprintf(stderr, "out of memory\n");
    fclose(f);
    return 1;
}

/* The pentagonal prism: b0..b4 at z = -0.8, t0..t4 at z = +0.8. */
static int builtin_prism(mesh *m)
{
    static const double ring[5][2] = {
        { 1.0, 0.0 }, { 0.3, 0.95 }, { -0.8, 0.6 }, { -0.8, -0.6 }, { 0.3, -0.95 },
    };
    static const uint32_t faces[] = {
        4, 3, 2, 1, 0,  5, 6, 7, 8, 9,
        0, 1, 6, 5,  1, 2, 7, 6,  2, 3, 8, 7,  3, 4, 9, 8,  4, 0, 5, 9,
    };
    static const uint32_t sizes[7] = { 5, 5, 4, 4, 4, 4, 4 };
    int k;
    m->pos = malloc(30 * sizeof *m->pos);
    m->sizes = malloc(sizeof sizes);
    m->idx = malloc(sizeof faces);
    if (m->pos == NULL || m->sizes == NULL || m->idx == NULL) return 1;
    for (k = 0; k < 10; k++) {
        m->pos[3 * k] = ring[k % 5][0];
        m->pos[3 * k + 1] = ring[k % 5][1];
        m->pos[3 * k + 2] = k < 5 ? -0.8 : 0.8;
    }
    memcpy(m->sizes, sizes, sizeof sizes);
    memcpy(m->idx, faces, sizeof faces);
    m->nv = 10;
    m->nf = 7;
    m->ni = sizeof faces / sizeof faces[0];
    return 0;
}

static void put_f32(unsigned char *p, float x)
{
    uint32_t u;
    memcpy(&u, &x, 4);
    p[0] = (unsigned char)(u & 0xff);
    p[1] = (unsigned char)((u >> 8) & 0xff);
    p[2] = (unsigned char)((u >> 16) & 0xff);
    p[3] = (unsigned char)(u >> 24);
}

/* Binary STL: 80-byte header, little-endian count, 50 bytes per triangle. */
static int write_stl(const char *path, const double *pos, const uint32_t *tri, size_t nt)
{
    unsigned char head[84] = { 0 };
    unsigned char rec[50];
    size_t t;
    int k, c;
    FILE *f = fopen(path, "wb");
    if (f == NULL) {
        fprintf(stderr, "cannot create %s\n", path);
        return 1;
    }
    memcpy(head, "ccss tessellate.c: exact limit-surface points", 45);
    head[80] = (unsigned char)(nt & 0xff);
    head[81] = (unsigned char)((nt >> 8) & 0xff);
    head[82] = (unsigned char)((nt >> 16) & 0xff);
    head[83] = (unsigned char)((nt >> 24) & 0xff);
    if (fwrite(head, 1, 84, f) != 84) goto fail;
    for (t = 0; t < nt; t++) {
        const double *a = pos + 3 * tri[3 * t];
        const double *b = pos + 3 * tri[3 * t + 1];
        const double *cc = pos + 3 * tri[3 * t + 2];
        double u[3], v[3], n[3], l;
        for (k = 0; k < 3; k++) {
            u[k] = b[k] - a[k];
            v[k] = cc[k] - a[k];
        }
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        l = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        if (l > 0) {
            l = sqrt(l);
            for (k = 0; k < 3; k++) n[k] /= l;
        }
        for (k = 0; k < 3; k++) put_f32(rec + 4 * k, (float)n[k]);
        for (c = 0; c < 3; c++) {
            const double *p = c == 0 ? a : c == 1 ? b : cc;
            for (k = 0; k < 3; k++) put_f32(rec + 12 + 12 * c + 4 * k, (float)p[k]);
        }
        rec[48] = rec[49] = 0;
        if (fwrite(rec, 1, 50, f) != 50) goto fail;
    }
    if (fclose(f) != 0) {
        fprintf(stderr, "cannot write %s\n", path);
        return 1;
    }
    return 0;
fail:
    fprintf(stderr, "cannot write %s\n", path);
    fclose(f);
    return 1;
}

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
        if (write_stl(out_path, pos, tri, c.triangles)) goto out;
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
