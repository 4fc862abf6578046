/*
 * c_eval_bench: single-threaded timing of exact evaluation through the C ABI
 * (libccss), the C-host peer of `ccss bench eval` and bench/osd/osd_eval on
 * the same points files.
 *
 * usage: c_eval_bench MESH.obj POINTS.txt [--second] [--samples S]
 *
 *   MESH.obj    closed polygon mesh: only "v x y z" and "f a b c ..." lines
 *               (first number of each face token, 1-based or negative)
 *   POINTS.txt  "face sub u v class [subclass]" lines ('#' lines skipped),
 *               the format of `ccss bench eval --write-points`
 *
 * Per class (R and X first, then the other letters in order of appearance)
 * four lines:
 *   cabi class=C points=N ns_per_eval=T        ccss_evaluator_eval (or
 *                                              _eval_second), one call a point
 *   cabi-batch class=C points=N ns_per_eval=T  ccss_evaluator_eval_batch over
 *                                              chunks of 4096 points
 *   cabi-derivs ..., cabi-batch-derivs ...     the same without the unit
 *                                              normal (ccss_evaluator_eval_derivs
 *                                              / _second_derivs, _batch_derivs):
 *                                              what osd_eval computes
 * Each figure is the median of S samples (default 7) after a warm-up pass, a
 * sample being as many whole passes as last at least 20 ms. The checksum
 * (sum of p, du, dv and, with --second, the second derivatives) goes to
 * stderr.
 *
 * Build: bench/run_eval_bench.sh does
 *   cc -O2 -std=c11 -Iinclude bench/c_eval_bench.c -Ltarget/release -lccss -lm
 */
#define _POSIX_C_SOURCE 200809L
#include "ccss.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define CHUNK 4096

static void die(const char *what, const char *more)
{
    fprintf(stderr, "c_eval_bench: error: %s%s\n", what, more ? more : "");
    exit(1);
}

static void check(ccss_status st, const char *what, const ccss_error_detail *d)
{
    char msg[CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
    if (st == CCSS_OK) return;
    ccss_error_detail_format(d, msg, sizeof msg);
    fprintf(stderr, "c_eval_bench: error: %s: %s\n", what, msg);
    exit(1);
}

static void *grow(void *p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap) return p;
    *cap = need * 2 + 16;
    p = realloc(p, *cap * elem);
    if (p == NULL) die("out of memory", NULL);
    return p;
}

typedef struct {
    double *pos;
    size_t nv, cap_v;
    uint32_t *sizes, *idx;
    size_t nf, ni, cap_f, cap_i;
} mesh;

static void read_obj(const char *path, mesh *m)
{
    char line[65536];
    FILE *fh = fopen(path, "r");
    if (fh == NULL) die("cannot open mesh ", path);
    memset(m, 0, sizeof *m);
    while (fgets(line, sizeof line, fh)) {
        if (line[0] == 'v' && line[1] == ' ') {
            m->pos = grow(m->pos, &m->cap_v, 3 * (m->nv + 1), sizeof(double));
            if (sscanf(line + 2, "%lf %lf %lf", &m->pos[3 * m->nv], &m->pos[3 * m->nv + 1],
                       &m->pos[3 * m->nv + 2]) != 3)
                die("bad vertex line in ", path);
            m->nv++;
        } else if (line[0] == 'f' && line[1] == ' ') {
            char *s = line + 2, *end;
            uint32_t n = 0;
            for (;;) {
                long i = strtol(s, &end, 10);
                if (end == s) break;
                if (i == 0) die("bad face index in ", path);
                m->idx = grow(m->idx, &m->cap_i, m->ni + 1, sizeof(uint32_t));
                m->idx[m->ni++] = (uint32_t)(i > 0 ? i - 1 : (long)m->nv + i);
                n++;
                s = end;
                while (*s && *s != ' ' && *s != '\t' && *s != '\n') s++;
            }
            m->sizes = grow(m->sizes, &m->cap_f, m->nf + 1, sizeof(uint32_t));
            m->sizes[m->nf++] = n;
        }
    }
    fclose(fh);
}

typedef struct {
    char name;
    ccss_evaluator_query *q;
    size_t n, cap;
} group;

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double sum(const ccss_evaluator_result *r, int second)
{
    double s = 0;
    int c;
    for (c = 0; c < 3; c++) s += r->p[c] + r->du[c] + r->dv[c];
    if (second)
        for (c = 0; c < 3; c++) s += r->duu[c] + r->duv[c] + r->dvv[c];
    return s;
}

/* The four entry points timed: one call a point or a batch, with the unit
   normal or without it (the _derivs entries). */
enum { PER_CALL = 1, DERIVS = 2 };

static double pass(const ccss_evaluator *ev, const group *g, int second, int mode,
                   ccss_evaluator_result *buf)
{
    double s = 0;
    size_t i, j;
    if (!(mode & PER_CALL)) {
        for (i = 0; i < g->n; i += CHUNK) {
            size_t n = g->n - i < CHUNK ? g->n - i : CHUNK;
            if (mode & DERIVS)
                check(ccss_evaluator_eval_batch_derivs(ev, g->q + i, n, second, buf, CHUNK, NULL),
                      "ccss_evaluator_eval_batch_derivs", NULL);
            else
                check(ccss_evaluator_eval_batch(ev, g->q + i, n, second, buf, CHUNK, NULL),
                      "ccss_evaluator_eval_batch", NULL);
            for (j = 0; j < n; j++) s += sum(&buf[j], second);
        }
        return s;
    }
    for (i = 0; i < g->n; i++) {
        const ccss_evaluator_query *q = &g->q[i];
        ccss_status st;
        if (mode & DERIVS)
            st = second ? ccss_evaluator_eval_second_derivs(ev, q->face, q->sub, q->u, q->v, buf, NULL)
                        : ccss_evaluator_eval_derivs(ev, q->face, q->sub, q->u, q->v, buf, NULL);
        else
            st = second ? ccss_evaluator_eval_second(ev, q->face, q->sub, q->u, q->v, buf, NULL)
                        : ccss_evaluator_eval(ev, q->face, q->sub, q->u, q->v, buf, NULL);
        if (st == CCSS_OK) s += sum(buf, second);
    }
    return s;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median ns per point over `samples` samples; adds one pass's checksum. */
static double measure(const ccss_evaluator *ev, const group *g, int second, int mode,
                      int samples, ccss_evaluator_result *buf, double *checksum)
{
    double t0 = now_s(), one, ns[1000];
    long reps, r;
    int k;
    *checksum += pass(ev, g, second, mode, buf);
    one = now_s() - t0;
    reps = (long)(0.02 / (one > 1e-9 ? one : 1e-9)) + 1;
    for (k = 0; k < samples; k++) {
        volatile double sink = 0;
        double t = now_s();
        for (r = 0; r < reps; r++) sink += pass(ev, g, second, mode, buf);
        ns[k] = (now_s() - t) * 1e9 / ((double)reps * (double)g->n);
        (void)sink;
    }
    qsort(ns, (size_t)samples, sizeof(double), cmp);
    return samples % 2 ? ns[samples / 2] : 0.5 * (ns[samples / 2 - 1] + ns[samples / 2]);
}

int main(int argc, char **argv)
{
    const char *mesh_path = NULL, *pts_path = NULL;
    int second = 0, samples = 7, i, ng = 2;
    group g[32];
    mesh m;
    ccss_error_detail d;
    const ccss_tables *tables;
    const ccss_topology *topo;
    const ccss_evaluator *ev;
    size_t bytes;
    void *tm, *gm, *em;
    char line[1024];
    FILE *fh;
    double checksum = 0;
    static ccss_evaluator_result buf[CHUNK];

    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--second")) second = 1;
        else if (!strcmp(argv[i], "--samples") && i + 1 < argc) samples = atoi(argv[++i]);
        else if (!mesh_path) mesh_path = argv[i];
        else if (!pts_path) pts_path = argv[i];
        else die("usage: c_eval_bench MESH.obj POINTS.txt [--second] [--samples S]", NULL);
    }
    if (!pts_path || samples < 1 || samples > 1000)
        die("usage: c_eval_bench MESH.obj POINTS.txt [--second] [--samples S]", NULL);
    read_obj(mesh_path, &m);

    check(ccss_tables_required_bytes(&bytes, &d), "tables size", &d);
    tm = malloc(bytes);
    check(ccss_tables_build_standard(tm, bytes, &tables, &d), "tables", &d);
    check(ccss_topology_required_bytes(m.nv, m.sizes, m.nf, &bytes, &d), "topology size", &d);
    gm = malloc(bytes);
    check(ccss_topology_build(m.pos, m.nv, m.sizes, m.nf, m.idx, m.ni, gm, bytes, &topo, &d),
          "topology", &d);
    check(ccss_evaluator_required_bytes(topo, tables, &bytes, &d), "evaluator size", &d);
    em = malloc(bytes);
    check(ccss_evaluator_build(topo, tables, em, bytes, &ev, &d), "evaluator", &d);

    memset(g, 0, sizeof g);
    g[0].name = 'R';
    g[1].name = 'X';
    fh = fopen(pts_path, "r");
    if (fh == NULL) die("cannot open points ", pts_path);
    while (fgets(line, sizeof line, fh)) {
        ccss_evaluator_query q;
        char c;
        int k;
        unsigned face, sub;
        if (line[0] == '#' || line[0] == '\n') continue;
        if (sscanf(line, "%u %u %lf %lf %c", &face, &sub, &q.u, &q.v, &c) != 5)
            die("bad points line: ", line);
        q.face = face;
        q.sub = sub;
        for (k = 0; k < ng && g[k].name != c; k++) {}
        if (k == ng) {
            if (ng == 32) die("too many classes", NULL);
            g[ng++].name = c;
        }
        g[k].q = grow(g[k].q, &g[k].cap, g[k].n + 1, sizeof q);
        g[k].q[g[k].n++] = q;
    }
    fclose(fh);

    for (i = 0; i < ng; i++) {
        static const int modes[4] = {PER_CALL, 0, PER_CALL | DERIVS, DERIVS};
        static const char *tools[4] = {"cabi", "cabi-batch", "cabi-derivs", "cabi-batch-derivs"};
        int k;
        for (k = 0; k < 4; k++) {
            const char *tool = tools[k];
            if (g[i].n == 0) {
                printf("%s class=%c points=0 ns_per_eval=nan\n", tool, g[i].name);
                continue;
            }
            printf("%s class=%c points=%zu ns_per_eval=%.1f\n", tool, g[i].name, g[i].n,
                   measure(ev, &g[i], second, modes[k], samples, buf, &checksum));
            fflush(stdout);
        }
        free(g[i].q);
    }
    fprintf(stderr, "cabi checksum=%.17g\n", checksum);
    free(em);
    free(gm);
    free(tm);
    free(m.pos);
    free(m.sizes);
    free(m.idx);
    return 0;
}
