/* tests/fuzz/fuzz_mtl.c - fuzz target: any bytes as a Wavefront material library (src/io/mtl.c):
 * read whole, every material named, its colour in [0, 1] and its map named, or refused with a
 * message; nothing crashes or leaks. No file is opened (textures are read by the OBJ loader). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "io/io_internal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_mtl lib;
    memset(&lib, 0, sizeof lib);
    if (hv_mtl_parse(data, size, "fuzz.mtl", &lib) == HV_OK) {
        for (size_t i = 0; i < lib.n; ++i) {
            const hv_mtl_material *m = &lib.m[i];
            if (!m->name || !*m->name || !(m->alpha >= 0 && m->alpha <= 1)) abort();
            for (int k = 0; k < 3 && m->has_kd; ++k)
                if (!(m->kd[k] >= 0 && m->kd[k] <= 1)) abort();
            if (m->map && (!*m->map || !isfinite(m->scale[0]) || !isfinite(m->offset[1]))) abort();
            if (hv_mtl_find(&lib, m->name) == NULL) abort();
        }
    } else if (!hv_last_error()[0]) {
        abort(); /* a refusal says why */
    }
    hv_mtl_free(&lib);
    return 0;
}
