/* tests/bench/bench_eval.c - material evaluation throughput (issue 4 figure): a solid box of
 * N^3 voxels, 3 materials, one AGS on an axis with a tabulated f, evaluated R times; prints
 * the median time and voxel-evaluations per second. Usage: bench_eval [N] [R] [sources] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "hovox/material.h"

#include "bench.h"

int main(int argc, char **argv)
{
    int N = argc > 1 ? atoi(argv[1]) : 256, R = argc > 2 ? atoi(argv[2]) : 5, K = argc > 3 ? atoi(argv[3]) : 1;
    hv_transform xf = {{0.1, 0.1, 0.1}, {0, 0, 0}};
    hv_volume *v;
    if (hv_volume_create(&xf, &v)) return fprintf(stderr, "%s\n", hv_last_error()), 1;
    size_t nb = (size_t)(N / 8) * (N / 8) * (N / 8), b = 0;
    int32_t *o = malloc(nb * 3 * sizeof *o);
    uint64_t *m = malloc(nb * 8 * sizeof *m);
    for (int x = 0; x < N; x += 8)
        for (int y = 0; y < N; y += 8)
            for (int z = 0; z < N; z += 8, ++b) {
                o[3 * b] = x, o[3 * b + 1] = y, o[3 * b + 2] = z;
                memset(m + 8 * b, 0xFF, 64);
            }
    int g;
    if (hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &g) || hv_volume_topology_add(v, nb, o, m)) return 1;
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) memset(hv_volume_leaf_bool(v, g, l), 0xFF, 64);
    hv_material_table *t;
    hv_material_table_create(&t);
    hv_material_add(t, "A", NULL, NULL);
    hv_material_add(t, "B", NULL, NULL);
    hv_material_add(t, "C", NULL, NULL);
    hv_object *obj;
    if (hv_object_create(v, "occupancy", 3, &obj)) return fprintf(stderr, "%s\n", hv_last_error()), 1;
    double ms[3] = {0, 0.9, 0.1}, me[3] = {0.9, 0, 0.1};
    for (int k = 0; k < K; ++k) {
        double c[3] = {N * 0.05 + k, N * 0.05, 0}, z[3] = {0, 0, 1};
        hv_frf *axis;
        hv_frf_line(c, z, &axis);
        hv_dfn *f;
        hv_dfn_expr("0.5 - 0.5*cos(pi*d/dg)", &f);
        hv_ags_desc d = {axis, 1, N * 0.04, 1, f, ms, me, 3, NULL};
        hv_ags *a;
        if (hv_ags_create(&d, &a)) return fprintf(stderr, "%s\n", hv_last_error()), 1;
        hv_object_add_ags(obj, a);
        hv_ags_release(a);
        hv_frf_release(axis);
        hv_dfn_destroy(f);
    }
    double *times = malloc((size_t)R * sizeof *times), *kern = malloc((size_t)R * sizeof *kern);
    for (int r = 0; r < R; ++r) {
        hv_volume *out;
        double t0 = now();
        if (hv_object_evaluate(obj, t, 0, NULL, &out)) return fprintf(stderr, "%s\n", hv_last_error()), 1;
        times[r] = now() - t0;
        /* the evaluation kernel alone: re-evaluate into the grids just made */
        t0 = now();
        if (hv_object_reevaluate(obj, t, out, NULL)) return fprintf(stderr, "%s\n", hv_last_error()), 1;
        kern[r] = now() - t0;
        hv_volume_destroy(out);
    }
    qsort(times, (size_t)R, sizeof *times, cmp_double);
    qsort(kern, (size_t)R, sizeof *kern, cmp_double);
    double med = times[R / 2], km = kern[R / 2], voxels = (double)N * N * N;
    printf("evaluate %d^3 = %.0f voxels, %d source%s, %d threads:\n", N, voxels, K, K > 1 ? "s" : "", hv_threads());
    printf("  kernel (re-evaluate into existing grids): median %.3f s, %.0f M voxel-evaluations/s\n", km,
           voxels / km / 1e6);
    printf("  end to end (allocate %d material grids + evaluate): median %.3f s, %.0f M voxels/s\n", 3, med,
           voxels / med / 1e6);
    return 0;
}
