/* tests/fuzz/fuzz_scan_leaf.c - fuzz target: any bytes as the raw data of a FIELD_ISO leaf (a model's
 * geometry record is input: hv_scan_unpack) fail cleanly or give a scan whose shape evaluates. */
#include <stdint.h>
#include <stdlib.h>

#include "io/scan/scan_internal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    hv_scan *s = NULL;
    hv_scan_shape shape;
    int32_t *labels = NULL;
    if (size > ((size_t)64 << 20)) return 0;
    if (hv_scan_unpack(data, size, "fuzz leaf", id, &s, &shape, &labels) != HV_OK) {
        if (s || labels) abort();
        return 0;
    }
    hv_scan_level lv;
    if (hv_scan_level_init(s, &shape, &lv) == HV_OK) {
        double p[3] = {0.25, 0.5, 0.75};
        (void)hv_scan_level_at(&lv, p);
        hv_scan_level_free(&lv);
    }
    hv_scan_destroy(s);
    free(labels);
    return 0;
}
