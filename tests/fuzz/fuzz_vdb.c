/* tests/fuzz/fuzz_vdb.c - fuzz target: any bytes as a .vdb file through the native reader
 * (volumes/vdb_read.c) and the OpenVDB bridge (checked streams, grid offsets and skipped grids,
 * tile costing, grid conversion, metadata) must load, whole and selectively, as a volume whose
 * grids are readable or fail cleanly, within the process's memory budget. Differential: what
 * the native reader takes, OpenVDB must read to the same volume, bit for bit. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "hovox/volume.h"
#include "volumes/volume_internal.h"
#include "io/vdb/vdb_internal.h"
#include "fuzz_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_file("vdb", ".vdb", data, size);
    if (!path) return 0;
    /* the whole file, then what a render reads (files with grid offsets skip the rest) */
    static const char *const sel[] = {"occupancy", "material.*"};
    for (int pass = 0; pass < 2; ++pass) {
        hv_volume *v = NULL;
        hv_status s = pass == 0 ? hv_volume_load(path, &v) : hv_volume_load_grids(path, sel, 2, &v);
        /* the native reader against OpenVDB on the same bytes */
        hv_volume *native = NULL;
        int half = 0, declined = 0;
        const char *const *names = pass == 0 ? NULL : sel;
        int n = pass == 0 ? -1 : 2;
        if (hv_vdb_read(path, names, n, hv_memory_budget(0), &native, &half, &declined) == HV_OK && !declined) {
            hv_volume *ref = NULL;
            char why[256];
            if (hv_volume_load_openvdb(path, names, n, &ref) != HV_OK) {
                fprintf(stderr, "native reader took a file OpenVDB refuses: %s\n", hv_last_error());
                abort();
            }
            hv_volume *mine = NULL; /* as loaded (sums of halves restored), to compare like with like */
            if ((pass == 0 ? hv_volume_load(path, &mine) : hv_volume_load_grids(path, sel, 2, &mine)) != HV_OK) abort();
            if (!hv_volume_identical(mine, ref, why, sizeof why)) {
                fprintf(stderr, "native reader and OpenVDB differ: %s\n", why);
                abort();
            }
            hv_volume_destroy(mine);
            hv_volume_destroy(ref);
        }
        hv_volume_destroy(native);
        if (s == HV_OK) {
            int32_t lo[3], hi[3];
            (void)hv_volume_index_bbox(v, lo, hi);
            for (int g = 0; g < hv_volume_grid_count(v); ++g)
                if (!hv_volume_grid_name(v, g)) abort();
            hv_volume_destroy(v);
        } else if (v) {
            abort(); /* failures must not hand out a volume */
        }
    }
    remove(path);
    return 0;
}
