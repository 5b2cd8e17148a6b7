/* tests/fuzz/fuzz_scan_metaimage.c - fuzz target: any bytes through the scan reader as a .mha file
 * (hv_scan_parse) fail cleanly or give a consistent scan (scan_fuzz_check.h). */
#include <stdint.h>

#include "scan_fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_scan(data, size, "fuzz.mha");
    return 0;
}
