/* tests/fuzz/fuzz_viewer_manifest.c - fuzz target: a slice stack's manifest.json as hovox view
 * reads it (src/viewer/manifest.c); the directory a person points the viewer at may hold anything:
 * any bytes are read or refused with a message, never a crash, a leak or an unbounded allocation.
 * A manifest that reads has layers, paths that stay inside the stack and parts inside the image. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "viewer/viewer_internal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vw_stack s;
    if (vw_stack_parse((const char *)data, size, "manifest.json", &s) != HV_OK) {
        if (!hv_last_error()[0]) abort(); /* a refusal says why */
        return 0;
    }
    if (s.nlayers < 1 || s.channels < 1 || s.width < 1 || s.height < 1) abort();
    for (size_t i = 0; i < s.nlayers * (size_t)s.channels; ++i)
        if (!s.files[i] || !vw_path_ok(s.files[i])) abort();
    for (int p = 0; p < s.nparts; ++p) {
        const vw_part *P = &s.parts[p];
        if (P->box[0] < 0 || P->box[1] < 0 || P->box[2] < 1 || P->box[3] < 1 || P->box[0] + P->box[2] > s.width ||
            P->box[1] + P->box[3] > s.height || P->l1 > s.nlayers || P->l0 > P->l1)
            abort();
    }
    vw_stack_free(&s);
    return 0;
}
