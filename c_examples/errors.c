/*
 * errors.c: the error behaviour of libccss, seen from C.
 *
 * NULL pointers, too-small and misaligned buffers (the required size is
 * reported and out-parameters stay untouched), invalid meshes (the offending
 * face / vertex / edge is reported), bad face / sub-face indices and NaN
 * parameters. Prints one PASS or FAIL line per check; returns non-zero if
 * any check fails.
 */
#include "ccss.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

#define CHECK(cond, name)                                                   \
    do {                                                                    \
        if (cond) {                                                         \
            printf("PASS %s\n", name);                                      \
        } else {                                                            \
            printf("FAIL %s (line %d)\n", name, __LINE__);                  \
            failures++;                                                     \
        }                                                                   \
    } while (0)

/* The cube [-1, 1]^3 (valence-3 corners, six quads counter-clockwise). */
static const double cube_pos[8 * 3] = {
    -1, -1, -1,  1, -1, -1,  1, 1, -1,  -1, 1, -1,
    -1, -1,  1,  1, -1,  1,  1, 1,  1,  -1, 1,  1,
};
static const uint32_t cube_sizes[6] = { 4, 4, 4, 4, 4, 4 };
static const uint32_t cube_idx[24] = {
    0, 3, 2, 1,  4, 5, 6, 7,  0, 1, 5, 4,
    1, 2, 6, 5,  2, 3, 7, 6,  3, 0, 4, 7,
};

/* A detail filled with garbage, to see what a call writes into it. */
static void poison_detail(ccss_error_detail *d)
{
    memset(d, 0x5a, sizeof *d);
}

static int message_contains(const ccss_error_detail *d, const char *needle)
{
    char buf[CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
    ccss_error_detail_format(d, buf, sizeof buf);
    printf("     message: %s\n", buf);
    return strstr(buf, needle) != NULL;
}

/* Builds a topology of the given mesh into fresh memory; returns the status. */
static ccss_status try_mesh(const double *pos, size_t nv, const uint32_t *sizes, size_t nf,
                            const uint32_t *idx, size_t ni, ccss_error_detail *d)
{
    const ccss_topology *const sentinel = (const ccss_topology *)&failures;
    const ccss_topology *topo = sentinel;
    size_t bytes = 0;
    void *mem;
    ccss_status st = ccss_topology_required_bytes(nv, sizes, nf, &bytes, NULL);
    if (st != CCSS_OK) return st;
    mem = malloc(bytes > 0 ? bytes : 1);
    if (mem == NULL) return CCSS_ERR_INTERNAL;
    poison_detail(d);
    st = ccss_topology_build(pos, nv, sizes, nf, idx, ni, mem, bytes, &topo, d);
    if (st != CCSS_OK && topo != sentinel) {
        printf("FAIL out-parameter written on failure\n");
        failures++;
    }
    free(mem);
    return st;
}

static void check_status_messages(void)
{
    static const int codes[] = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11,
                                 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22,
                                 CCSS_ERR_HOLE_FACE, CCSS_ERR_NOT_AN_EDGE,
                                 CCSS_ERR_NEIGHBOURHOOD_TOO_LARGE, CCSS_ERR_NOT_CLOSED_SOLID,
                                 CCSS_ERR_NOT_CONVERGED, CCSS_ERR_CONFLICTING_REQUIREMENT,
                                 CCSS_ERR_WORK_LIMIT_EXCEEDED, CCSS_ERR_COORDINATE_RANGE,
                                 CCSS_ERR_INVALID_HANDLE, CCSS_ERR_CORRUPTED, CCSS_ERR_OVERLAP,
                                 CCSS_ERR_INTERNAL };
    size_t i;
    int ok = 1;
    for (i = 0; i < sizeof codes / sizeof codes[0]; i++) {
        const char *m = ccss_status_message(codes[i]);
        if (m == NULL || m[0] == '\0' || strcmp(m, "unknown status") == 0) ok = 0;
    }
    CHECK(ok, "every status has a message");
    CHECK(strcmp(ccss_status_message(12345), "unknown status") == 0,
          "unknown status values are safe");
    CHECK(strcmp(ccss_status_message(-1), "unknown status") == 0, "negative status is safe");
    CHECK(ccss_version() != NULL && ccss_version()[0] != '\0', "version string");
    CHECK(CCSS_ERR_INVALID_WEIGHTS == 22 && CCSS_ERR_HOLE_FACE == 23 &&
              CCSS_ERR_NOT_AN_EDGE == 24 && CCSS_ERR_NEIGHBOURHOOD_TOO_LARGE == 25 &&
              CCSS_ERR_NOT_CLOSED_SOLID == 26 && CCSS_ERR_NOT_CONVERGED == 27 &&
                  CCSS_ERR_CONFLICTING_REQUIREMENT == 28,
          "the statuses of 0.2 keep their values; new ones are appended");
    CHECK(CCSS_ERR_WORK_LIMIT_EXCEEDED == 29 && CCSS_ERR_COORDINATE_RANGE == 30 &&
              CCSS_ERR_INVALID_HANDLE == 31 && CCSS_ERR_CORRUPTED == 32 && CCSS_ERR_OVERLAP == 33,
          "hardening statuses appended (29..33)");
    CHECK(CCSS_ERR_INTERNAL == 99 && strstr(ccss_status_message(CCSS_ERR_INTERNAL), "internal"),
          "CCSS_ERR_INTERNAL keeps the value 99 of the former CCSS_ERR_PANIC");
}

static void check_mesh_errors(void)
{
    ccss_error_detail d;
    ccss_status st;
    uint32_t idx[24 + 3];
    uint32_t sizes[7];
    double pos[9 * 3];

    /* Cube without its top face (4 5 6 7): the edges of the hole are
     * boundary edges. */
    st = try_mesh(cube_pos, 8, cube_sizes, 5, cube_idx, 4, &d);
    CHECK(st == CCSS_ERR_INDEX_COUNT_MISMATCH && d.required == 20 && d.value == 4,
          "index count mismatch reports expected (required) and given (value)");
    memcpy(idx, cube_idx, sizeof cube_idx);
    memcpy(idx + 4, cube_idx + 8, 16 * sizeof idx[0]); /* drop face 1 */
    st = try_mesh(cube_pos, 8, cube_sizes, 5, idx, 20, &d);
    printf("     boundary edge %lld-%lld\n", (long long)d.vertex, (long long)d.vertex2);
    CHECK(st == CCSS_ERR_BOUNDARY_EDGE && d.status == CCSS_ERR_BOUNDARY_EDGE, "open cube: boundary edge");
    CHECK(d.vertex >= 4 && d.vertex <= 7 && d.vertex2 >= 4 && d.vertex2 <= 7 &&
              (d.vertex + 1 == d.vertex2 || d.vertex2 + 1 == d.vertex ||
               d.vertex + d.vertex2 == 11),
          "boundary edge is an edge of the missing face");
    CHECK(d.face == -1 && d.query_index == UINT64_MAX && d.required == 0,
          "fields that do not apply are -1 / 0 / UINT64_MAX");
    CHECK(message_contains(&d, "boundary"), "boundary message");

    /* Cube plus a triangle (0 1 8) on edge 0-1: that edge has three faces. */
    memcpy(pos, cube_pos, sizeof cube_pos);
    pos[24] = 0; pos[25] = -2; pos[26] = -2;
    memcpy(idx, cube_idx, sizeof cube_idx);
    idx[24] = 0; idx[25] = 1; idx[26] = 8;
    memcpy(sizes, cube_sizes, sizeof cube_sizes);
    sizes[6] = 3;
    st = try_mesh(pos, 9, sizes, 7, idx, 27, &d);
    printf("     non-manifold edge %lld-%lld\n", (long long)d.vertex, (long long)d.vertex2);
    CHECK(st == CCSS_ERR_NON_MANIFOLD_EDGE &&
              ((d.vertex == 0 && d.vertex2 == 1) || (d.vertex == 1 && d.vertex2 == 0)),
          "non-manifold edge 0-1 is reported");
    CHECK(message_contains(&d, "more than two faces"), "non-manifold message");

    /* Face 1 reversed: inconsistent orientation on one of its edges. */
    memcpy(idx, cube_idx, sizeof cube_idx);
    idx[4] = 7; idx[5] = 6; idx[6] = 5; idx[7] = 4;
    st = try_mesh(cube_pos, 8, cube_sizes, 6, idx, 24, &d);
    CHECK(st == CCSS_ERR_INCONSISTENT_ORIENTATION && d.vertex >= 4 && d.vertex2 >= 4,
          "flipped face: inconsistent orientation on an edge of face 1");

    /* Face 2 uses vertex 42. */
    memcpy(idx, cube_idx, sizeof cube_idx);
    idx[9] = 42;
    st = try_mesh(cube_pos, 8, cube_sizes, 6, idx, 24, &d);
    CHECK(st == CCSS_ERR_INDEX_OUT_OF_RANGE && d.face == 2 && d.vertex == 42,
          "index out of range names face 2 and vertex 42");

    /* Face 3 uses vertex 1 twice. */
    memcpy(idx, cube_idx, sizeof cube_idx);
    idx[13] = 1;
    st = try_mesh(cube_pos, 8, cube_sizes, 6, idx, 24, &d);
    CHECK(st == CCSS_ERR_REPEATED_VERTEX && d.face == 3 && d.vertex == 1,
          "repeated vertex names face 3 and vertex 1");

    /* A two-vertex face. */
    memcpy(sizes, cube_sizes, sizeof cube_sizes);
    sizes[4] = 2;
    st = try_mesh(cube_pos, 8, sizes, 6, cube_idx, 22, &d);
    CHECK(st == CCSS_ERR_FACE_TOO_SMALL && d.face == 4 && d.value == 2,
          "face too small names face 4 and its size");

    /* A NaN coordinate at vertex 5. */
    memcpy(pos, cube_pos, sizeof cube_pos);
    pos[3 * 5 + 1] = nan("");
    st = try_mesh(pos, 8, cube_sizes, 6, cube_idx, 24, &d);
    CHECK(st == CCSS_ERR_NON_FINITE_COORDINATE && d.vertex == 5,
          "NaN coordinate names vertex 5");

    st = try_mesh(NULL, 0, NULL, 0, NULL, 0, &d);
    CHECK(st == CCSS_ERR_EMPTY_MESH, "empty mesh (NULL arrays with zero counts are fine)");
}

static void check_null_and_buffers(const ccss_tables *tables)
{
    const ccss_topology *const tsent = (const ccss_topology *)&failures;
    const ccss_topology *topo = tsent;
    const ccss_tables *tab_out = (const ccss_tables *)&failures;
    ccss_error_detail d;
    ccss_status st;
    size_t need = 0, need2 = 0, sentinel_size = 777;
    unsigned char *mem;

    /* NULL pointers. */
    CHECK(ccss_tables_required_bytes(NULL, NULL) == CCSS_ERR_NULL_POINTER, "tables size query: NULL out");
    CHECK(ccss_topology_required_bytes(8, NULL, 6, &sentinel_size, NULL) == CCSS_ERR_NULL_POINTER &&
              sentinel_size == 777,
          "topology size query: NULL face_sizes with a count, out untouched");
    poison_detail(&d);
    st = ccss_topology_build(NULL, 8, cube_sizes, 6, cube_idx, 24, NULL, 0, &topo, &d);
    CHECK(st == CCSS_ERR_NULL_POINTER && d.status == CCSS_ERR_NULL_POINTER && topo == tsent,
          "topology build: NULL positions");
    CHECK(message_contains(&d, "positions"), "NULL message names the argument");
    st = ccss_topology_build(cube_pos, 8, cube_sizes, 6, cube_idx, 24, NULL, 0, NULL, NULL);
    CHECK(st == CCSS_ERR_NULL_POINTER, "topology build: NULL out, NULL detail");
    CHECK(ccss_evaluator_eval(NULL, 0, 0, 0.5, 0.5, NULL, NULL) == CCSS_ERR_NULL_POINTER, "eval: NULL evaluator");
    CHECK(ccss_evaluator_required_bytes(NULL, tables, &need, NULL) == CCSS_ERR_NULL_POINTER,
          "evaluator size query: NULL topology");
    {
        char buf[4] = "abc";
        CHECK(ccss_error_detail_format(NULL, buf, sizeof buf) == 0 && buf[0] == '\0',
              "format: NULL detail is an empty message");
        CHECK(ccss_error_detail_format(NULL, NULL, 0) == 0, "format: NULL buffer of length 0");
    }

    /* Tables: too small and misaligned. */
    CHECK(ccss_tables_required_bytes(&need, NULL) == CCSS_OK && need > 0, "tables size query");
    mem = malloc(need + 8);
    if (mem == NULL) { failures++; return; }
    st = ccss_tables_build_standard(mem, need - 1, &tab_out, NULL);
    CHECK(st == CCSS_ERR_BUFFER_TOO_SMALL && tab_out == (const ccss_tables *)&failures,
          "tables: one byte short -> BUFFER_TOO_SMALL, out untouched");
    st = ccss_tables_build_standard(mem + 4, need, &tab_out, NULL);
    CHECK(st == CCSS_ERR_MISALIGNED && tab_out == (const ccss_tables *)&failures,
          "tables: misaligned block -> MISALIGNED, out untouched");
    st = ccss_tables_build_standard(NULL, 16, &tab_out, NULL);
    CHECK(st == CCSS_ERR_NULL_POINTER, "tables: NULL block with a length");
    free(mem);

    /* Topology: the size is reported through the detail, too. */
    CHECK(ccss_topology_required_bytes(8, cube_sizes, 6, &need, NULL) == CCSS_OK, "topology size query");
    poison_detail(&d);
    st = ccss_topology_build(cube_pos, 8, cube_sizes, 6, cube_idx, 24, NULL, 0, &topo, &d);
    CHECK(st == CCSS_ERR_BUFFER_TOO_SMALL && d.required == need && topo == tsent,
          "topology: NULL block of length 0 -> BUFFER_TOO_SMALL with the size");
    mem = malloc(need + 8);
    if (mem == NULL) { failures++; return; }
    poison_detail(&d);
    st = ccss_topology_build(cube_pos, 8, cube_sizes, 6, cube_idx, 24, mem, need - 8, &topo, &d);
    printf("     required %llu bytes\n", (unsigned long long)d.required);
    CHECK(st == CCSS_ERR_BUFFER_TOO_SMALL && d.required == need && topo == tsent,
          "topology: 8 bytes short -> BUFFER_TOO_SMALL, required reported, out untouched");
    CHECK(message_contains(&d, "buffer too small"), "buffer message");
    st = ccss_topology_build(cube_pos, 8, cube_sizes, 6, cube_idx, 24, mem + 4, need, &topo, &d);
    CHECK(st == CCSS_ERR_MISALIGNED && topo == tsent, "topology: misaligned block");
    st = ccss_topology_build(cube_pos, 8, cube_sizes, 6, cube_idx, 24, mem, need, &topo, &d);
    CHECK(st == CCSS_OK && topo == (const ccss_topology *)(void *)mem,
          "topology: exact size works; the handle is the block");

    /* Evaluator: too small. */
    {
        const ccss_evaluator *const esent = (const ccss_evaluator *)&failures;
        const ccss_evaluator *ev = esent;
        unsigned char *emem;
        CHECK(ccss_evaluator_required_bytes(topo, tables, &need2, &d) == CCSS_OK,
              "evaluator size query");
        emem = malloc(need2);
        if (emem == NULL) { failures++; free(mem); return; }
        poison_detail(&d);
        st = ccss_evaluator_build(topo, tables, emem, need2 - 1, &ev, &d);
        CHECK(st == CCSS_ERR_BUFFER_TOO_SMALL && d.required == need2 && ev == esent,
              "evaluator: one byte short -> BUFFER_TOO_SMALL with the size");
        st = ccss_evaluator_build(topo, tables, emem, need2, &ev, &d);
        CHECK(st == CCSS_OK, "evaluator: exact size works");
        free(emem);
    }
    free(mem);
}

static void check_eval_errors(const ccss_tables *tables)
{
    const ccss_topology *topo = NULL;
    const ccss_evaluator *ev = NULL;
    ccss_error_detail d;
    ccss_evaluator_result r, before, res[3], saved[3];
    ccss_evaluator_query q[3];
    ccss_status st;
    size_t tb = 0, eb = 0, i;
    uint32_t nsub = 777;
    void *tmem, *emem;
    int ok;

    if (ccss_topology_required_bytes(8, cube_sizes, 6, &tb, NULL) != CCSS_OK) { failures++; return; }
    tmem = malloc(tb);
    if (tmem == NULL) { failures++; return; }
    st = ccss_topology_build(cube_pos, 8, cube_sizes, 6, cube_idx, 24, tmem, tb, &topo, &d);
    if (st != CCSS_OK) { failures++; free(tmem); return; }
    if (ccss_evaluator_required_bytes(topo, tables, &eb, &d) != CCSS_OK) { failures++; free(tmem); return; }
    emem = malloc(eb);
    if (emem == NULL) { failures++; free(tmem); return; }
    st = ccss_evaluator_build(topo, tables, emem, eb, &ev, &d);
    CHECK(st == CCSS_OK, "cube evaluator");
    if (st != CCSS_OK) { free(emem); free(tmem); return; }

    /* The evaluator does not use the topology block after the build. */
    st = ccss_evaluator_eval_second(ev, 2, 0, 0.3, 0.7, &before, NULL);
    memset(tmem, 0xff, tb);
    free(tmem);
    st = ccss_evaluator_eval_second(ev, 2, 0, 0.3, 0.7, &r, NULL);
    CHECK(st == CCSS_OK && memcmp(&r, &before, sizeof r) == 0,
          "evaluator works after the topology block was wiped and freed");

    /* Integrity check: the untouched block verifies; a flipped byte in it
       (a stray write) is CORRUPTED; restored, it verifies again. */
    CHECK(ccss_evaluator_verify(ev, &d) == CCSS_OK, "untouched evaluator block verifies");
    {
        unsigned char *byte = (unsigned char *)emem + eb - 8;
        *byte ^= 0x20;
        st = ccss_evaluator_verify(ev, &d);
        CHECK(st == CCSS_ERR_CORRUPTED && d.status == st, "a flipped byte -> CORRUPTED");
        *byte ^= 0x20;
        CHECK(ccss_evaluator_verify(ev, NULL) == CCSS_OK, "restored block verifies");
        CHECK(ccss_tables_verify(tables, NULL) == CCSS_OK, "untouched tables verify");
    }

    memset(&r, 0x5a, sizeof r);
    before = r;
    st = ccss_evaluator_eval(ev, 6, 0, 0.5, 0.5, &r, NULL);
    CHECK(st == CCSS_ERR_FACE_OUT_OF_RANGE && memcmp(&r, &before, sizeof r) == 0,
          "bad face index -> FACE_OUT_OF_RANGE, result untouched");
    memset(&d, 0, sizeof d);
    st = ccss_evaluator_eval(ev, 6, 0, 0.5, 0.5, &r, &d);
    CHECK(st == CCSS_ERR_FACE_OUT_OF_RANGE && d.status == st && d.face == 6 &&
              memcmp(&r, &before, sizeof r) == 0,
          "bad face index with a detail -> detail.face = 6");
    st = ccss_evaluator_eval(ev, 0, 1, 0.5, 0.5, &r, NULL);
    CHECK(st == CCSS_ERR_SUBFACE_OUT_OF_RANGE, "sub-face 1 of a quad -> SUBFACE_OUT_OF_RANGE");
    st = ccss_evaluator_eval(ev, 0, 0, nan(""), 0.5, &r, NULL);
    CHECK(st == CCSS_ERR_PARAMETER_OUT_OF_RANGE && memcmp(&r, &before, sizeof r) == 0,
          "NaN u -> PARAMETER_OUT_OF_RANGE, result untouched");
    st = ccss_evaluator_eval_second(ev, 0, 0, 0.5, nan(""), &r, NULL);
    CHECK(st == CCSS_ERR_PARAMETER_OUT_OF_RANGE, "NaN v (second derivatives)");
    st = ccss_evaluator_eval(ev, 0, 0, 1.0 + 1e-12, 0.5, &r, NULL);
    CHECK(st == CCSS_ERR_PARAMETER_OUT_OF_RANGE, "u slightly above 1");
    st = ccss_evaluator_eval(ev, 0, 0, -INFINITY, 0.5, &r, NULL);
    CHECK(st == CCSS_ERR_PARAMETER_OUT_OF_RANGE, "u = -infinity");
    st = ccss_evaluator_eval(ev, 0, 0, -0.0, 1.0, &r, NULL);
    CHECK(st == CCSS_OK, "u = -0.0, v = 1 are in range");
    st = ccss_evaluator_eval(ev, 0, 0, 0.5, 0.5, NULL, NULL);
    CHECK(st == CCSS_ERR_NULL_POINTER, "NULL result pointer");
    CHECK(ccss_evaluator_subface_count(ev, 6, &nsub, NULL) == CCSS_ERR_FACE_OUT_OF_RANGE && nsub == 777,
          "sub-face count of a bad face, out untouched");
    CHECK(ccss_evaluator_subface_count(ev, 5, &nsub, NULL) == CCSS_OK && nsub == 1,
          "a quad has one sub-face");

    /* Batches: validated before anything is written. */
    for (i = 0; i < 3; i++) {
        q[i].face = (uint32_t)i;
        q[i].sub = 0;
        q[i].u = 0.25;
        q[i].v = 0.75;
    }
    q[2].v = nan("");
    memset(res, 0x5a, sizeof res);
    memcpy(saved, res, sizeof res);
    poison_detail(&d);
    st = ccss_evaluator_eval_batch(ev, q, 3, 1, res, 3, &d);
    CHECK(st == CCSS_ERR_PARAMETER_OUT_OF_RANGE && d.query_index == 2 &&
              memcmp(res, saved, sizeof res) == 0,
          "batch: NaN in query 2 -> PARAMETER_OUT_OF_RANGE, query_index 2, out untouched");
    CHECK(message_contains(&d, "query 2"), "batch message names the query");
    q[2].v = 0.75;
    q[1].face = 1000;
    st = ccss_evaluator_eval_batch(ev, q, 3, 0, res, 3, &d);
    CHECK(st == CCSS_ERR_FACE_OUT_OF_RANGE && d.query_index == 1 && d.face == 1000,
          "batch: bad face in query 1");
    q[1].face = 1;
    q[1].sub = 3;
    st = ccss_evaluator_eval_batch(ev, q, 3, 0, res, 3, &d);
    CHECK(st == CCSS_ERR_SUBFACE_OUT_OF_RANGE && d.query_index == 1 && d.face == 1 && d.value == 3,
          "batch: bad sub-face in query 1 (face and sub-face reported)");
    q[1].sub = 0;
    poison_detail(&d);
    st = ccss_evaluator_eval_batch(ev, q, 3, 0, res, 2, &d);
    CHECK(st == CCSS_ERR_BUFFER_TOO_SMALL && d.required == 3 && d.query_index == UINT64_MAX &&
              memcmp(res, saved, sizeof res) == 0,
          "batch: output for 2 of 3 -> BUFFER_TOO_SMALL, required 3 elements, out untouched");
    st = ccss_evaluator_eval_batch(ev, NULL, 3, 0, res, 3, &d);
    CHECK(st == CCSS_ERR_NULL_POINTER, "batch: NULL queries with a count");
    st = ccss_evaluator_eval_batch(ev, NULL, 0, 0, NULL, 0, &d);
    CHECK(st == CCSS_OK, "batch: empty batch with NULL arrays");
    st = ccss_evaluator_eval_batch(ev, q, 3, 1, res, 3, &d);
    ok = st == CCSS_OK;
    for (i = 0; ok && i < 3; i++) {
        if (ccss_evaluator_eval_second(ev, q[i].face, 0, q[i].u, q[i].v, &r, NULL) != CCSS_OK ||
            memcmp(&r, &res[i], sizeof r) != 0)
            ok = 0;
    }
    CHECK(ok, "batch results equal single evaluations");

    /* Messages are truncated safely and the full length is returned. */
    {
        char small[8];
        size_t n;
        st = ccss_evaluator_eval_batch(ev, q, 3, 0, res, 1, &d);
        n = ccss_error_detail_format(&d, small, sizeof small);
        CHECK(st == CCSS_ERR_BUFFER_TOO_SMALL && n > 7 && strlen(small) == 7 &&
                  n == ccss_error_detail_format(&d, NULL, 0),
              "format truncates to the buffer and returns the full length");
    }
    free(emem);
}

/* Handles carry a magic word: garbage memory, a handle of another type and
 * a block whose header was overwritten give CCSS_ERR_INVALID_HANDLE. */
static void check_bad_handles(const ccss_tables *tables)
{
    static uint64_t junk[4096];
    size_t n = 0;
    ccss_error_detail d;
    ccss_evaluator_result r;
    memset(junk, 0xa5, sizeof junk);
    CHECK(ccss_evaluator_face_count((const ccss_evaluator *)(void *)junk, &n, &d) ==
                  CCSS_ERR_INVALID_HANDLE &&
              d.status == CCSS_ERR_INVALID_HANDLE,
          "garbage evaluator handle is INVALID_HANDLE");
    CHECK(ccss_evaluator_eval((const ccss_evaluator *)(const void *)tables, 0, 0, 0.5, 0.5, &r,
                              &d) == CCSS_ERR_INVALID_HANDLE,
          "tables passed as an evaluator is INVALID_HANDLE");
    {
        ccss_tables_valence_info info;
        memset(junk, 0, sizeof junk);
        CHECK(ccss_tables_valence((const ccss_tables *)(void *)junk, 3, &info, &d) ==
                  CCSS_ERR_INVALID_HANDLE,
              "zeroed memory as tables is INVALID_HANDLE");
        CHECK(ccss_tables_valence(tables, 3, &info, &d) == CCSS_OK, "the real tables still work");
    }
}

int main(void)
{
    const ccss_tables *tables = NULL;
    size_t bytes = 0;
    size_t maxv = 0;
    void *mem;

    check_status_messages();
    CHECK(ccss_max_valence(&maxv, NULL) == CCSS_OK && maxv >= 5, "max valence");
    check_mesh_errors();

    if (ccss_tables_required_bytes(&bytes, NULL) != CCSS_OK) return 1;
    mem = malloc(bytes);
    if (mem == NULL) return 1;
    CHECK(ccss_tables_build_standard(mem, bytes, &tables, NULL) == CCSS_OK, "tables");
    if (tables == NULL) { free(mem); return 1; }

    check_null_and_buffers(tables);
    check_eval_errors(tables);
    check_bad_handles(tables);
    free(mem);

    printf("%s: %d failure(s)\n", failures == 0 ? "ALL PASS" : "FAILED", failures);
    return failures == 0 ? 0 : 1;
}
