/* tests/bench/bench_mask.c - writes a model's bool grid as the raw uint8 mask (1 = true, z
 * fastest) over its voxels' box grown by 2 on each side, the box the contour feature's EDT
 * runs over (src/material/frf.c compute_field), and prints its dims "NX,NY,NZ": the input of
 * the scipy anchor of the contour-grading bench (scripts/bench/42-grade-contour.sh). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/core.h"
#include "hovox/volume.h"

int main(int argc, char **argv)
{
    if (argc != 4) {
        fputs("usage: bench_mask MODEL.vdb GRID OUT.raw\n", stderr);
        return 2;
    }
    hv_volume *v;
    if (hv_volume_load(argv[1], &v) != HV_OK) {
        fprintf(stderr, "bench_mask: %s\n", hv_last_error());
        return 1;
    }
    int g = hv_volume_grid_find(v, argv[2]);
    int32_t lo[3], hi[3];
    if (g < 0 || hv_volume_grid_type(v, g) != HV_GRID_BOOL || !hv_volume_index_bbox(v, lo, hi)) {
        fprintf(stderr, "bench_mask: %s has no non-empty bool grid '%s'\n", argv[1], argv[2]);
        return 1;
    }
    int64_t n[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] -= 2;
        n[k] = (int64_t)hi[k] + 2 - lo[k] + 1;
    }
    uint8_t *m = calloc((size_t)(n[0] * n[1] * n[2]), 1);
    if (!m) return 3;
    const int32_t *org = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const uint64_t *mask = hv_volume_leaf_mask(v, l), *val = hv_volume_leaf_bool_c(v, g, l);
        for (unsigned q = 0; q < HV_LEAF_SIZE; ++q)
            if (HV_BIT_GET(mask, q) && HV_BIT_GET(val, q)) {
                int64_t i = org[3 * l] + (int64_t)(q >> 6) - lo[0], j = org[3 * l + 1] + (int64_t)((q >> 3) & 7) - lo[1],
                        k = org[3 * l + 2] + (int64_t)(q & 7) - lo[2];
                m[(i * n[1] + j) * n[2] + k] = 1;
            }
    }
    FILE *f = fopen(argv[3], "wb");
    if (!f || fwrite(m, 1, (size_t)(n[0] * n[1] * n[2]), f) != (size_t)(n[0] * n[1] * n[2]) || fclose(f) != 0) {
        fprintf(stderr, "bench_mask: cannot write %s\n", argv[3]);
        return 4;
    }
    printf("%lld,%lld,%lld\n", (long long)n[0], (long long)n[1], (long long)n[2]);
    free(m);
    hv_volume_destroy(v);
    return 0;
}
