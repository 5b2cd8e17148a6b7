/* tests/fuzz/fuzz_vdb_native.c - fuzz target: any bytes as a .vdb file through hovox's native
 * reader alone (volumes/vdb_read.c: header, metadata, descriptors, topology, blosc and zip
 * chunks, half floats), whole and selectively, under ASan and UBSan (fuzz_vdb, which also
 * reaches OpenVDB, runs under UBSan alone and checks the two readers against each other). The
 * reader must take the file as a volume whose grids are readable, leave it to OpenVDB, or fail
 * cleanly. */
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
    const char *path = fuzz_write_file("native", ".vdb", data, size);
    if (!path) return 0;
    static const char *const sel[] = {"occupancy", "material.*"};
    for (int pass = 0; pass < 2; ++pass) {
        hv_volume *v = NULL;
        int half = 0, declined = 0;
        hv_status s = hv_vdb_read(path, pass ? sel : NULL, pass ? 2 : -1, 256u << 20, &v, &half, &declined);
        if (s == HV_OK && !declined) {
            if (!v) abort();
            static volatile uint64_t sink; /* every buffer read, so ASan sees a bad one */
            for (int g = 0; g < hv_volume_grid_count(v); ++g) {
                if (!hv_volume_grid_name(v, g)) abort();
                for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) { /* every buffer readable */
                    const float *f = hv_volume_leaf_float_c(v, g, l);
                    const uint64_t *b = hv_volume_leaf_bool_c(v, g, l);
                    sink += f ? (uint64_t)(f[0] != f[511]) : b[0] ^ b[7];
                }
            }
        } else if (v) {
            abort(); /* declining or failing must not hand out a volume */
        }
        hv_volume_destroy(v);
    }
    remove(path);
    return 0;
}
