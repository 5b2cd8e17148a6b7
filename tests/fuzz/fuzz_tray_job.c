/* tests/fuzz/fuzz_tray_job.c - fuzz target: tray job files (slicing/tray_job.c), which come from
 * other people: any bytes are read or refused with a message, never a crash, a leak or an
 * unbounded allocation. The parts' files are not opened (parsing only). */
#include <stdint.h>
#include <stdlib.h>

#include "hovox/tray.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_tray *t = NULL;
    hv_tray_options o;
    if (hv_tray_parse_job((const char *)data, size, "job.json", "base", &t, &o) == HV_OK) {
        if (hv_tray_part_count(t) < 1) abort(); /* a job that parses has parts */
        hv_tray_destroy(t);
    }
    return 0;
}
