/* tests/fuzz/fuzz_csv_table.c - fuzz target: any bytes as a calibration table (t,<property>) and
 * as a linearization table (fraction.<material>,<property>) through the shared two-column CSV
 * reader (core/csv_table.c): a table is read whole and evaluates to finite values inside its
 * range, or the text is refused with a message; nothing crashes or leaks. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "hovox/export.h"
#include "hovox/material.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_calibration *c = NULL;
    if (hv_calibration_parse((const char *)data, size, "fuzz.csv", &c) == HV_OK) {
        double lo, hi, t = -1;
        hv_calibration_range(c, &lo, &hi);
        /* the middle value has a t in [0, 1], where the table is finite */
        if (hv_calibration_invert(c, lo / 2 + hi / 2, &t) != HV_OK || !(t >= 0 && t <= 1) ||
            !isfinite(hv_calibration_eval(c, t)))
            abort();
        hv_calibration_release(c);
    } else if (c) {
        abort(); /* a refusal hands out no table */
    }
    hv_linearization *lin = NULL;
    if (hv_linearization_parse((const char *)data, size, "fuzz.csv", NULL, &lin) == HV_OK) {
        if (!lin || !isfinite(hv_linearization_eval(lin, 0.5))) abort();
        hv_linearization_destroy(lin);
    } else if (lin) {
        abort();
    }
    return 0;
}
