/* tests/fuzz/fuzz_lut.c - fuzz target: any bytes as a lookup table of a scan's values (hv_lut_parse,
 * src/colour/lut.c, over the CSV row reader of core/csv_table.c): a table is read whole, its values
 * rise, and it evaluates everywhere to fractions in [0, 1] summing to 1 (or to a colour in [0, 1]);
 * or the text is refused with a message and no table; nothing crashes or leaks. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "hovox/lut.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_lut *t = NULL;
    if (hv_lut_parse((const char *)data, size, "fuzz.csv", &t) != HV_OK) {
        if (t || !hv_last_error()[0]) abort(); /* a refusal hands out no table and says why */
        return 0;
    }
    double lo, hi;
    hv_lut_range(t, &lo, &hi);
    if (!(lo <= hi) || hv_lut_rows(t) < 1) abort();
    const double at[] = {-INFINITY, lo - 1, lo, lo / 2 + hi / 2, hi, hi + 1, INFINITY, NAN};
    int cols = hv_lut_columns(t);
    for (size_t i = 0; i < sizeof at / sizeof *at; ++i) {
        float f[64];
        hv_lut_eval(t, at[i], f);
        double sum = 0;
        for (int k = 0; k < cols; ++k) {
            if (!(f[k] >= 0 && f[k] <= 1)) abort();
            sum += f[k];
        }
        if (hv_lut_kind_of(t) == HV_LUT_MATERIALS && fabs(sum - 1) > 1e-3) abort();
    }
    hv_lut_destroy(t);
    return 0;
}
