/* tests/fuzz/scan_fuzz_check.h - what the scan readers' fuzz targets share: any bytes through
 * hv_scan_parse under a 64 MiB limit must fail cleanly (no scan handed out, a message set) or give
 * a scan whose samples are finite, whose value range holds them and whose affine is finite. */
#ifndef HOVOX_SCAN_FUZZ_CHECK_H
#define HOVOX_SCAN_FUZZ_CHECK_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "hovox/scan.h"

static void fuzz_scan(const uint8_t *data, size_t size, const char *name)
{
    hv_scan_options o;
    hv_scan_options_init(&o);
    o.max_memory = (uint64_t)64 << 20;
    hv_scan *s = (hv_scan *)&o;
    hv_status st = hv_scan_parse(data, size, name, &o, &s);
    if (st != HV_OK) {
        if (s != NULL || !hv_last_error()[0]) abort();
        return;
    }
    size_t d[3];
    double m[12];
    hv_scan_dims(s, d);
    hv_scan_affine(s, m);
    const hv_scan_info *in = hv_scan_get_info(s);
    const float *v = hv_scan_data(s);
    size_t n = d[0] * d[1] * d[2];
    if (!n || !v) abort();
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(v[i]) || v[i] < in->value_min || v[i] > in->value_max) abort();
    for (int i = 0; i < 12; ++i)
        if (!isfinite(m[i])) abort();
    hv_scan_destroy(s);
}

#endif
