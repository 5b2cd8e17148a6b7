/* src/io/scan/pack.c - a scan's shape as the raw data of a FIELD_ISO leaf of the geometry record
 * (hovox/geometry.h: the record deflates and stores it; its transform is the scan's affine):
 *   "HVFISO1\0", uint32 select (0 iso, 1 range, 2 labels), uint32 label count L,
 *   uint64 nx, ny, nz, float64 iso, lo, hi, int32 labels[L], float32 samples[nx ny nz]
 * little-endian. Unpacking checks every size against the data (a record is input). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/scan/scan_internal.h"

#define MAGIC "HVFISO1"
#define HEAD (8 + 4 + 4 + 24 + 24)

static void put(uint8_t *p, uint64_t v, int n)
{
    for (int k = 0; k < n; ++k) p[k] = (uint8_t)(v >> (8 * k));
}
static uint64_t get(const uint8_t *p, int n)
{
    uint64_t v = 0;
    for (int k = 0; k < n; ++k) v |= (uint64_t)p[k] << (8 * k);
    return v;
}
static void putd(uint8_t *p, double d)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    put(p, u, 8);
}
static double getd(const uint8_t *p)
{
    uint64_t u = get(p, 8);
    double d;
    memcpy(&d, &u, 8);
    return d;
}

hv_status hv_scan_pack(const hv_scan *scan, const hv_scan_shape *shape, uint8_t **data, size_t *size)
{
    *data = NULL;
    size_t L = shape->select == HV_SCAN_SELECT_LABELS ? shape->label_count : 0;
    size_t n = scan->dims[0] * scan->dims[1] * scan->dims[2];
    size_t bytes = HEAD + 4 * L + 4 * n;
    uint8_t *p = hv_malloc_big(bytes, 1);
    if (!p) return HV_ERR_NOMEM;
    memcpy(p, MAGIC, 8);
    put(p + 8, (uint64_t)shape->select, 4);
    put(p + 12, L, 4);
    for (int a = 0; a < 3; ++a) put(p + 16 + 8 * a, scan->dims[a], 8);
    putd(p + 40, shape->select == HV_SCAN_SELECT_ISO ? shape->iso : 0);
    putd(p + 48, shape->select == HV_SCAN_SELECT_RANGE ? shape->range[0] : 0);
    putd(p + 56, shape->select == HV_SCAN_SELECT_RANGE ? shape->range[1] : 0);
    for (size_t i = 0; i < L; ++i) put(p + HEAD + 4 * i, (uint32_t)shape->labels[i], 4);
    uint8_t *q = p + HEAD + 4 * L;
    for (size_t i = 0; i < n; ++i) {
        uint32_t u;
        memcpy(&u, &scan->data[i], 4);
        put(q + 4 * i, u, 4);
    }
    *data = p;
    *size = bytes;
    return HV_OK;
}

hv_status hv_scan_unpack(const uint8_t *p, size_t size, const char *name, const double affine[12], hv_scan **out,
                         hv_scan_shape *shape, int32_t **labels)
{
    *out = NULL;
    *labels = NULL;
    memset(shape, 0, sizeof *shape);
    if (size < HEAD || memcmp(p, MAGIC, 8) != 0)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: not a field iso-surface leaf (bad header)", name);
    uint32_t sel = (uint32_t)get(p + 8, 4), L = (uint32_t)get(p + 12, 4);
    uint64_t d[3];
    for (int a = 0; a < 3; ++a) d[a] = get(p + 16 + 8 * a, 8);
    if (sel > 2 || (sel == 2) != (L > 0) || L > 65536)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: field leaf: selection %u with %u labels", name, sel, L);
    for (int a = 0; a < 3; ++a)
        if (d[a] == 0 || d[a] > ((uint64_t)1 << 31))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: field leaf: %llu samples on an axis", name, (unsigned long long)d[a]);
    if ((double)d[0] * (double)d[1] * (double)d[2] * 4.0 + HEAD + 4.0 * L != (double)size)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: field leaf: %zu bytes do not hold %llu x %llu x %llu samples", name, size,
                            (unsigned long long)d[0], (unsigned long long)d[1], (unsigned long long)d[2]);
    shape->select = (hv_scan_select)sel;
    shape->iso = getd(p + 40);
    shape->range[0] = getd(p + 48);
    shape->range[1] = getd(p + 56);
    hv_scan *s = hv_calloc(1, sizeof *s);
    int32_t *lab = L ? hv_malloc_array(L, sizeof *lab) : NULL;
    if (!s || (L && !lab)) {
        free(s);
        free(lab);
        return HV_ERR_NOMEM;
    }
    for (uint32_t i = 0; i < L; ++i) lab[i] = (int32_t)(uint32_t)get(p + HEAD + 4 * i, 4);
    shape->labels = lab;
    shape->label_count = L;
    s->name = hv_strdup(name);
    size_t n = (size_t)(d[0] * d[1] * d[2]);
    s->data = hv_malloc_big(n, sizeof(float));
    if (!s->name || !s->data) {
        hv_scan_destroy(s);
        free(lab);
        return HV_ERR_NOMEM;
    }
    const uint8_t *q = p + HEAD + 4 * (size_t)L;
    for (size_t i = 0; i < n; ++i) {
        uint32_t u = (uint32_t)get(q + 4 * i, 4);
        float f;
        memcpy(&f, &u, 4);
        if (!isfinite(f)) {
            hv_scan_destroy(s);
            free(lab);
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: field leaf: sample %zu is not finite", name, i);
        }
        s->data[i] = f;
    }
    for (int a = 0; a < 3; ++a) s->dims[a] = (size_t)d[a];
    memcpy(s->m, affine, sizeof s->m);
    s->info.slope = 1;
    s->info.files = 1;
    s->info.format_name = "field leaf";
    hv_status st = scan_check_affine(s, "the leaf's transform");
    if (st != HV_OK) {
        hv_scan_destroy(s);
        free(lab);
        return st;
    }
    *out = s;
    *labels = lab;
    return HV_OK;
}
