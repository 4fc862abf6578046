/*
 * example_mesh.h: what the file-based C examples share: a polygon mesh in
 * the arrays libccss takes (positions, face sizes, indices), a small OBJ
 * reader ('v' and 'f' lines), the built-in pentagonal prism, and a binary
 * STL writer. Include after ccss.h.
 */
#ifndef CCSS_EXAMPLE_MESH_H
#define CCSS_EXAMPLE_MESH_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
static int write_stl(const char *path, const char *title, const double *pos, const uint32_t *tri,
                     size_t nt)
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
    size_t title_len = strlen(title);
    memcpy(head, title, title_len < 80 ? title_len : 80);
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

#endif
