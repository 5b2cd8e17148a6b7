/* tests/fuzz/fuzz_3mf_volumetric.c - fuzz target: any bytes through the 3MF Volumetric reader (ZIP,
 * relationships, the model part's XML, references, PNG sheets, the voxelization of the mesh) must
 * fail cleanly or give a graded model whose fractions are finite and sum to 1 on every voxel, and
 * a mesh. Memory is capped at 64 MiB per input, so a package that declares more is refused. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "hovox/material.h"
#include "hovox/threemf.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_set_memory_cap((uint64_t)64 << 20);
    hv_volume *v = NULL;
    hv_mesh *mesh = NULL;
    hv_status s = hv_3mf_parse(data, size, "fuzz.3mf", &v, &mesh);
    if (s != HV_OK) {
        if (v || mesh) abort(); /* failures must not hand out a model */
        return 0;
    }
    hv_material_table *t = NULL;
    if (!mesh || hv_material_table_load(v, &t) != HV_OK) abort();
    int m = hv_material_count(t), g[HV_MAX_MATERIALS];
    for (int j = 0; j < m; ++j)
        if ((g[j] = hv_material_grid(v, t, j)) < 0) abort();
    int og = hv_volume_grid_find(v, "occupancy");
    if (og < 0) abort();
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            if (!HV_BIT_GET(hv_volume_leaf_bool_c(v, og, l), n)) continue;
            double sum = 0;
            for (int j = 0; j < m; ++j) {
                float f = hv_volume_leaf_float_c(v, g[j], l)[n];
                if (!(f >= 0 && f <= 1)) abort();
                sum += f;
            }
            if (fabs(sum - 1) > 1e-5) abort();
        }
    hv_material_table_destroy(t);
    hv_mesh_destroy(mesh);
    hv_volume_destroy(v);
    return 0;
}
