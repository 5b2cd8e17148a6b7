/* tests/bench/bench_render_model.c - makes the render benchmark's model: reads a voxelized
 * .vdb, grades it with Wu's gear formula (three materials by distance d to the z axis: d- =
 * 9.54, dg = 9.54, linear f, Ms = [0, 0.9, 0.1], Me = [0.9, 0, 0.1]) and adds a float grid
 * "density" = occupancy as 0/1 for vdb_render; writes the graded model. With --density-only the
 * input is already graded (e.g. Wu's shaft by `hovox grade --frf contour`) and only "density"
 * is added. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/material.h"
#include "hovox/volume.h"

static int fail(const char *what)
{
    fprintf(stderr, "bench_render_model: %s: %s\n", what, hv_last_error());
    return 1;
}

int main(int argc, char **argv)
{
    int only = argc == 4 && strcmp(argv[1], "--density-only") == 0;
    if (argc != 3 && !only) {
        fputs("usage: bench_render_model [--density-only] VOXELIZED.vdb GRADED.vdb\n", stderr);
        return 2;
    }
    argv += only;
    hv_volume *v;
    if (hv_volume_load(argv[1], &v) != HV_OK) return fail(argv[1]);
    int occ = hv_volume_grid_find(v, "occupancy");
    if (occ < 0 || hv_volume_grid_type(v, occ) != HV_GRID_BOOL) {
        fprintf(stderr, "bench_render_model: %s has no bool grid 'occupancy'\n", argv[1]);
        return 1;
    }
    if (only) {
        int dens;
        if (hv_volume_grid_add(v, "density", HV_GRID_FLOAT, &dens) != HV_OK) return fail("grid");
        for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
            const uint64_t *ob = hv_volume_leaf_bool_c(v, occ, l);
            float *fd = hv_volume_leaf_float(v, dens, l);
            for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) fd[n] = HV_BIT_GET(ob, n) ? 1.0f : 0.0f;
        }
        if (hv_volume_save(v, argv[2]) != HV_OK) return fail(argv[2]);
        hv_volume_destroy(v);
        return 0;
    }
    static const char *names[3] = {"A", "B", "C"};
    static const double ms[3] = {0, 0.9, 0.1}, me[3] = {0.9, 0, 0.1};
    const double dneg = 9.54, dg = 9.54;
    hv_material_table *t;
    if (hv_material_table_create(&t) != HV_OK) return fail("table");
    int g[3], dens;
    char gname[64];
    for (int m = 0; m < 3; ++m) {
        if (hv_material_add(t, names[m], NULL, NULL) != HV_OK) return fail("material");
        snprintf(gname, sizeof gname, "material.%s", names[m]);
        if (hv_volume_grid_add(v, gname, HV_GRID_FLOAT, &g[m]) != HV_OK) return fail("grid");
    }
    if (hv_volume_grid_add(v, "density", HV_GRID_FLOAT, &dens) != HV_OK) return fail("grid");
    hv_transform xf = hv_volume_get_transform(v);
    const int32_t *org = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const uint64_t *ob = hv_volume_leaf_bool_c(v, occ, l);
        float *fd = hv_volume_leaf_float(v, dens, l), *fm[3];
        for (int m = 0; m < 3; ++m) fm[m] = hv_volume_leaf_float(v, g[m], l);
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            int on = (int)HV_BIT_GET(ob, n);
            fd[n] = on ? 1.0f : 0.0f;
            double x = xf.origin[0] + (org[3 * l] + (int)(n >> 6)) * xf.voxel[0];
            double y = xf.origin[1] + (org[3 * l + 1] + (int)((n >> 3) & 7)) * xf.voxel[1];
            double d = sqrt(x * x + y * y), f = (d - dneg) / dg;
            f = f < 0 ? 0 : f > 1 ? 1 : f;
            for (int m = 0; m < 3; ++m) fm[m][n] = on ? (float)(ms[m] + f * (me[m] - ms[m])) : 0.0f;
        }
    }
    if (hv_material_table_store(v, t) != HV_OK) return fail("table");
    if (hv_volume_save(v, argv[2]) != HV_OK) return fail(argv[2]);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
    return 0;
}
