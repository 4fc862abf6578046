/*
 * voxelize.c: voxelize the limit surface of a bundled torus (OpenSubdiv's
 * catmark_torus, 32 quads) with libccss, classify inside/outside, and
 * measure it exactly.
 *
 * Prints key=value lines (Lines starting with '#' are comments):
 *     res=R adjacency=N surface=S interior=I runs=K flood_inside=C
 *     slab z0=A z1=B surface=S interior=I runs=K
 *     exact volume=V area=A error_bound=E
 * Returns 0 on success.
 *
 * Build: cc -std=c99 -Iinclude c_examples/voxelize.c target/debug/libccss.a \
 *           -lpthread -ldl -lm -o voxelize
 */
#include "ccss.h"
#include "example_report.h"
#include "example_torus.h"

#include <stdio.h>
#include <stdlib.h>

int main(void)
{
    uint32_t face_sizes[TORUS_NF];
    uint32_t res[3] = { 48, 48, 48 };
    uint32_t *stack = NULL;
    ccss_error_detail detail;
    const ccss_tables *tables = NULL;
    const ccss_topology *topo = NULL;
    const ccss_evaluator *ev = NULL;
    ccss_voxel_grid *grid = NULL, *slab = NULL;
    ccss_voxel_grid_transform tr;
    ccss_voxel_grid_voxelize_stats vs;
    ccss_voxel_grid_flood_stats fs;
    ccss_mass_properties mp;
    ccss_voxel_grid_run *runs = NULL;
    void *tables_mem = NULL, *topo_mem = NULL, *ev_mem = NULL, *grid_mem = NULL, *slab_mem = NULL;
    size_t bytes = 0, nruns = 0, written = 0;
    uint64_t surface = 0, interior = 0;
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

    /* 1. The whole grid: size query, init, voxelize (normalised into the
     *    grid), flood with a small stack (any capacity >= 1 works). */
    st = ccss_voxel_grid_required_bytes(res, 0, res[2], &bytes, NULL);
    if (st != CCSS_OK) { rc = report("ccss_voxel_grid_required_bytes", st, NULL); goto out; }
    printf("# grid bytes %lu\n", (unsigned long)bytes);
    if ((grid_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_voxel_grid_build(res, 0, res[2], grid_mem, bytes, &grid, &detail);
    if (st != CCSS_OK) { rc = report("ccss_voxel_grid_build", st, &detail); goto out; }
    st = ccss_voxel_grid_voxelize(ev, grid, 6, 8, NULL, &vs, &detail);
    if (st != CCSS_OK) { rc = report("ccss_voxel_grid_voxelize", st, &detail); goto out; }
    if ((stack = malloc(256 * sizeof *stack)) == NULL) goto out;
    st = ccss_voxel_grid_flood(ev, grid, stack, 256, &fs, &detail);
    if (st != CCSS_OK) { rc = report("ccss_voxel_grid_flood", st, &detail); goto out; }
    ccss_voxel_grid_counts(grid, &surface, &interior, NULL);
    /* Runs: a size query first (BUFFER_TOO_SMALL with the count). */
    st = ccss_voxel_grid_runs(grid, NULL, 0, &written, &detail);
    if (st != CCSS_ERR_BUFFER_TOO_SMALL) { rc = report("ccss_voxel_grid_runs (query)", st, &detail); goto out; }
    nruns = (size_t)detail.required;
    if ((runs = malloc(nruns * sizeof *runs)) == NULL) goto out;
    st = ccss_voxel_grid_runs(grid, runs, nruns, &written, &detail);
    if (st != CCSS_OK) { rc = report("ccss_voxel_grid_runs", st, &detail); goto out; }
    ccss_voxel_grid_last_transform(grid, &tr, NULL);
    printf("res=%u adjacency=6 surface=%llu interior=%llu runs=%lu flood_inside=%u guard_hits=%llu\n",
           res[0], (unsigned long long)surface, (unsigned long long)interior,
           (unsigned long)written, fs.inside_components, (unsigned long long)vs.guard_hits);
    printf("transform scale=%.17g offset=%.17g,%.17g,%.17g\n", tr.scale, tr.offset[0],
           tr.offset[1], tr.offset[2]);
    printf("voxel_volume=%.17g quad_area=%.17g\n",
           (double)(surface + interior) / (tr.scale * tr.scale * tr.scale), vs.quad_area);

    /* 2. One z-slab with memory for the slab only, same transform. */
    st = ccss_voxel_grid_required_bytes(res, 20, 28, &bytes, NULL);
    if (st != CCSS_OK) { rc = report("ccss_voxel_grid_required_bytes", st, NULL); goto out; }
    if ((slab_mem = malloc(bytes)) == NULL) goto out;
    st = ccss_voxel_grid_build(res, 20, 28, slab_mem, bytes, &slab, &detail);
    if (st != CCSS_OK) { rc = report("ccss_voxel_grid_build", st, &detail); goto out; }
    st = ccss_voxel_grid_voxelize(ev, slab, 6, 8, &tr, NULL, &detail);
    if (st != CCSS_OK) { rc = report("ccss_voxel_grid_voxelize (slab)", st, &detail); goto out; }
    st = ccss_voxel_grid_flood(ev, slab, stack, 256, NULL, &detail);
    if (st != CCSS_OK) { rc = report("ccss_voxel_grid_flood (slab)", st, &detail); goto out; }
    ccss_voxel_grid_counts(slab, &surface, &interior, NULL);
    st = ccss_voxel_grid_runs(slab, NULL, 0, &written, &detail);
    printf("slab z0=20 z1=28 bytes=%lu surface=%llu interior=%llu runs=%llu\n",
           (unsigned long)bytes, (unsigned long long)surface, (unsigned long long)interior,
           (unsigned long long)detail.required);
    {
        /* The slab's voxels equal the whole grid's. */
        uint32_t x, y, z, a, b;
        long diff = 0;
        for (z = 20; z < 28; z++)
            for (y = 0; y < res[1]; y++)
                for (x = 0; x < res[0]; x++) {
                    ccss_voxel_grid_class(grid, x, y, z, &a, NULL);
                    ccss_voxel_grid_class(slab, x, y, z, &b, NULL);
                    diff += a != b;
                }
        printf("slab_differences=%ld\n", diff);
    }

    /* 3. Exact integral properties. */
    st = ccss_mass_properties_compute(ev, &mp, &detail);
    if (st != CCSS_OK) { rc = report("ccss_mass_properties_compute", st, &detail); goto out; }
    printf("exact volume=%.17g area=%.17g error_bound=%.3g centroid=%.17g,%.17g,%.17g\n",
           mp.volume, mp.area, mp.volume_error_bound, mp.centroid[0], mp.centroid[1],
           mp.centroid[2]);

    /* 4. An error: adjacency 5 does not exist. */
    st = ccss_voxel_grid_voxelize(ev, grid, 5, 8, NULL, NULL, &detail);
    ccss_error_detail_format(&detail, NULL, 0);
    printf("# adjacency 5: status %d\n", (int)st);
    rc = st == CCSS_ERR_INVALID_ARGUMENT ? 0 : 1;
out:
    free(runs);
    free(stack);
    free(slab_mem);
    free(grid_mem);
    free(ev_mem);
    free(topo_mem);
    free(tables_mem);
    return rc;
}
