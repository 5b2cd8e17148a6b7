/* slicing/scan_source.c - a scanned volume printed straight from its data (issue 30 item 4): a
 * layer source (layers_internal.h) with no model. At every printer pixel centre of a layer the
 * samples are interpolated trilinearly (src/io/scan/level.c's field: the same interpolation,
 * in the same order), the pixel is object where the level g >= 0 (iso, range or the labels'
 * interpolated indicator), and its materials are the lookup table's at the interpolated value.
 * Only the columns of each row whose centres fall inside the samples' cells are evaluated; the
 * index advances along a row by a constant step, so any affine (rotated, flipped) costs the same.
 * The table is tabulated once over its value range (LUT_BINS intervals, linear between them; a
 * colour table's colours through the colour map as hv_lut_paint_scan takes them). Memory: the
 * volume and the table; the job's per-thread images. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/lut.h"
#include "io/scan/scan_internal.h"
#include "layers_internal.h"
#include "scan_source.h"

#define LUT_BINS 8192

static int cmp_i32(const void *a, const void *b)
{
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return x < y ? -1 : x > y;
}

struct hv_scan_source {
    hv_layers_source src;
    const hv_scan *scan;
    hv_scan_level lv;
    int lv_ok;
    hv_material_table *table;
    char *name;
    int cols;
    float *tab; /* (LUT_BINS + 1) x cols */
    double t0, tscale; /* bin = (value - t0) * tscale */
    uint8_t *member; /* labels: per sample, its label is in the set (NULL otherwise) */
    /* a colour table: per tabulated value its requested colour and the pixels that printed it (nearest
     * value), for the manifest's dE2000 (hv_colour_samples_error) */
    uint8_t *rgb;    /* (LUT_BINS + 1) x 3 */
    uint64_t *hits;  /* LUT_BINS + 1 */
    pthread_mutex_t lock;
    int lock_ok;
};

static inline void paint(const hv_scan_source *s, double v, float *frac, size_t plane, size_t p, uint32_t *hist);

/* One row: columns [c0, c1] of row r at height z. */
static void fill_row(const hv_scan_source *s, const hv_raster_grid *grid, double z, int r, uint8_t *mrow,
                     float *frac, size_t plane, size_t rowoff, uint32_t *hist)
{
    const hv_scan_level *lv = &s->lv;
    const double *m = s->scan->m, *inv = lv->inv;
    const int64_t *n = lv->n;
    double px = grid->origin[0] + 0.5 * grid->pixel[0], py = grid->origin[1] + ((double)r + 0.5) * grid->pixel[1];
    double d[3] = {px - m[3], py - m[7], z - m[11]};
    double a[3], st[3];
    for (int q = 0; q < 3; ++q) {
        a[q] = inv[3 * q] * d[0] + inv[3 * q + 1] * d[1] + inv[3 * q + 2] * d[2];
        st[q] = inv[3 * q] * grid->pixel[0];
    }
    /* the columns whose index lies in [-0.5, n - 0.5] on every axis (one column of slack each way;
     * each pixel is checked again) */
    double clo = 0, chi = (double)grid->width - 1;
    for (int q = 0; q < 3; ++q) {
        double lo = -0.5 - a[q], hi = (double)n[q] - 0.5 - a[q];
        if (st[q] == 0) {
            if (lo > 0 || hi < 0) return;
            continue;
        }
        double u = lo / st[q], v = hi / st[q];
        clo = fmax(clo, floor(fmin(u, v)) - 1);
        chi = fmin(chi, ceil(fmax(u, v)) + 1);
    }
    if (clo > chi) return;
    size_t nx = (size_t)n[0], nxy = nx * (size_t)n[1];
    size_t ox = n[0] > 1, oy = n[1] > 1 ? nx : 0, oz = n[2] > 1 ? nxy : 0;
    const size_t off[8] = {0, ox, oy, ox + oy, oz, ox + oz, oy + oz, ox + oy + oz};
    const float *data = s->scan->data;
    const hv_scan_shape *sh = &lv->shape;
    int labels = sh->select == HV_SCAN_SELECT_LABELS;
    int cols = frac ? s->cols : 0;
    for (int c = (int)clo; c <= (int)chi; ++c) {
        double t[3];
        size_t base = 0, mul[3] = {1, nx, nxy};
        int out = 0;
        for (int q = 0; q < 3; ++q) {
            double x = a[q] + st[q] * (double)c;
            out |= !(x >= -0.5 && x <= (double)n[q] - 0.5);
            x = HV_CLAMP(x, 0.0, (double)(n[q] - 1));
            int64_t i = (int64_t)x;
            if (i > n[q] - 2) i = n[q] - 2;
            if (i < 0) i = 0;
            t[q] = n[q] > 1 ? x - (double)i : 0;
            base += (size_t)i * mul[q];
        }
        if (out) continue;
        double cv[8];
        for (int k = 0; k < 8; ++k) cv[k] = (double)data[base + off[k]];
        double x0 = cv[0] + (cv[1] - cv[0]) * t[0], x1 = cv[2] + (cv[3] - cv[2]) * t[0];
        double x2 = cv[4] + (cv[5] - cv[4]) * t[0], x3 = cv[6] + (cv[7] - cv[6]) * t[0];
        double y0 = x0 + (x1 - x0) * t[1], y1 = x2 + (x3 - x2) * t[1];
        double v = y0 + (y1 - y0) * t[2];
        int in;
        if (labels) {
            double mv[8];
            for (int k = 0; k < 8; ++k) mv[k] = s->member[base + off[k]];
            double a0 = mv[0] + (mv[1] - mv[0]) * t[0], a1 = mv[2] + (mv[3] - mv[2]) * t[0];
            double a2 = mv[4] + (mv[5] - mv[4]) * t[0], a3 = mv[6] + (mv[7] - mv[6]) * t[0];
            double b0 = a0 + (a1 - a0) * t[1], b1 = a2 + (a3 - a2) * t[1];
            in = b0 + (b1 - b0) * t[2] - 0.5 >= 0;
        } else if (sh->select == HV_SCAN_SELECT_RANGE) {
            in = fmin(v - sh->range[0], sh->range[1] - v) >= 0;
        } else {
            in = v - sh->iso >= 0;
        }
        if (!in) continue;
        mrow[c] = 1;
        if (cols) paint(s, v, frac, plane, rowoff + (size_t)c, hist);
    }
}

/* The materials of value v into pixel p's fractions; hist (a colour table's, or NULL) counts the
 * nearest tabulated value. */
static inline void paint(const hv_scan_source *s, double v, float *frac, size_t plane, size_t p, uint32_t *hist)
{
    double b = HV_CLAMP((v - s->t0) * s->tscale, 0.0, (double)LUT_BINS);
    if (hist) hist[(int)(b + 0.5)]++;
    int bi = (int)b, cols = s->cols;
    if (bi >= LUT_BINS) bi = LUT_BINS - 1;
    float w = (float)(b - (double)bi);
    const float *ta = s->tab + (size_t)bi * (size_t)cols, *tb = ta + cols;
    for (int g = 0; g < cols; ++g) frac[(size_t)g * plane + p] = ta[g] + w * (tb[g] - ta[g]);
}

/* An axis-aligned grid (the sample index along x depends on x alone, along y on y alone, along z
 * on z alone; any spacing, either direction): per layer the columns' sample index and weight once,
 * per row the samples blended in y and z along the row's x range, per pixel one blend in x. */
static int aligned(const hv_scan_source *s)
{
    const double *v = s->lv.inv;
    return v[1] == 0 && v[2] == 0 && v[3] == 0 && v[5] == 0 && v[6] == 0 && v[7] == 0 &&
           s->lv.shape.select != HV_SCAN_SELECT_LABELS;
}

/* An axis's sample index at continuous index x (inside [-0.5, n - 0.5]): the lower sample and the
 * weight of the upper one, as level.c takes them. */
static inline int64_t axis_at(double x, int64_t n, double *t)
{
    x = HV_CLAMP(x, 0.0, (double)(n - 1));
    int64_t i = (int64_t)x;
    if (i > n - 2) i = n - 2;
    if (i < 0) i = 0;
    *t = n > 1 ? x - (double)i : 0;
    return i;
}

static hv_status aligned_layer(const hv_scan_source *s, double z, const hv_raster_grid *grid, uint8_t *mask,
                               float *frac, size_t plane, uint32_t *hist)
{
    const hv_scan_level *lv = &s->lv;
    const double *m = s->scan->m, *inv = lv->inv;
    const int64_t *n = lv->n;
    double zk = inv[8] * (z - m[11]);
    if (!(zk >= -0.5 && zk <= (double)n[2] - 0.5)) return HV_OK;
    double tz;
    int64_t k0 = axis_at(zk, n[2], &tz);
    int W = grid->width;
    int32_t *ci = hv_malloc_array((size_t)W, sizeof *ci);
    double *ct = hv_malloc_array((size_t)W, sizeof *ct);
    double *line = hv_malloc_array((size_t)n[0], sizeof *line);
    hv_status st = ci && ct && line ? HV_OK : HV_ERR_NOMEM;
    int c0 = W, c1 = -1;
    int64_t ilo = n[0], ihi = -1;
    for (int c = 0; c < W && st == HV_OK; ++c) {
        double x = inv[0] * (grid->origin[0] + ((double)c + 0.5) * grid->pixel[0] - m[3]);
        if (!(x >= -0.5 && x <= (double)n[0] - 0.5)) {
            ci[c] = -1;
            continue;
        }
        int64_t i = axis_at(x, n[0], &ct[c]);
        ci[c] = (int32_t)i;
        c0 = HV_MIN(c0, c);
        c1 = HV_MAX(c1, c);
        ilo = HV_MIN(ilo, i);
        ihi = HV_MAX(ihi, i + (n[0] > 1));
    }
    size_t nx = (size_t)n[0], nxy = nx * (size_t)n[1];
    size_t oy = n[1] > 1 ? nx : 0, oz = n[2] > 1 ? nxy : 0;
    const hv_scan_shape *sh = &lv->shape;
    int range = sh->select == HV_SCAN_SELECT_RANGE;
    for (int r = 0; r < grid->height && st == HV_OK && c0 <= c1; ++r) {
        double y = inv[4] * (grid->origin[1] + ((double)r + 0.5) * grid->pixel[1] - m[7]);
        if (!(y >= -0.5 && y <= (double)n[1] - 0.5)) continue;
        double ty;
        int64_t j0 = axis_at(y, n[1], &ty);
        const float *p00 = s->scan->data + (size_t)j0 * nx + (size_t)k0 * nxy, *p10 = p00 + oy, *p01 = p00 + oz,
                    *p11 = p00 + oy + oz;
        /* y, then z: the x blend of level.c's order comes last here, the same field */
        for (int64_t i = ilo; i <= ihi; ++i) {
            double a = (double)p00[i] + ((double)p10[i] - (double)p00[i]) * ty;
            double b = (double)p01[i] + ((double)p11[i] - (double)p01[i]) * ty;
            line[i] = a + (b - a) * tz;
        }
        size_t rowoff = (size_t)r * (size_t)W;
        uint8_t *mrow = mask + rowoff;
        for (int c = c0; c <= c1; ++c) {
            int32_t i = ci[c];
            if (i < 0) continue;
            double v = line[i] + (line[i + (n[0] > 1)] - line[i]) * ct[c];
            int in = range ? fmin(v - sh->range[0], sh->range[1] - v) >= 0 : v - sh->iso >= 0;
            if (!in) continue;
            mrow[c] = 1;
            if (frac) paint(s, v, frac, plane, rowoff + (size_t)c, hist);
        }
    }
    free(ci);
    free(ct);
    free(line);
    return st;
}

static hv_status source_layer(const hv_layers_source *src, double z, const hv_raster_grid *grid, uint8_t *mask,
                              float *frac, size_t plane)
{
    hv_scan_source *s = src->user;
    memset(mask, 0, plane);
    if (!(z >= src->bbox_min[2] && z <= src->bbox_max[2])) return HV_OK;
    uint32_t *hist = NULL; /* this layer's count per tabulated value (a colour table's) */
    if (frac && s->hits && !(hist = hv_calloc(LUT_BINS + 1, sizeof *hist))) return HV_ERR_NOMEM;
    hv_status st = HV_OK;
    if (aligned(s)) {
        st = aligned_layer(s, z, grid, mask, frac, plane, hist);
    } else {
        for (int r = 0; r < grid->height; ++r) {
            size_t rowoff = (size_t)r * (size_t)grid->width;
            fill_row(s, grid, z, r, mask + rowoff, frac, plane, rowoff, hist);
        }
    }
    if (hist) {
        pthread_mutex_lock(&s->lock);
        for (int b = 0; b <= LUT_BINS; ++b) s->hits[b] += hist[b];
        pthread_mutex_unlock(&s->lock);
        free(hist);
    }
    return st;
}

/* The table at LUT_BINS + 1 values over its rows' range: materials as they are, colours as
 * hv_lut_paint_scan gives them (rounded to 8 bits, through the map). */
static hv_status tabulate(hv_scan_source *s, const hv_lut *lut, hv_colour_map *map)
{
    int colour = hv_lut_kind_of(lut) == HV_LUT_COLOUR;
    if (colour && !map) return hv_error_set(HV_ERR_INVALID, "a colour lookup table needs a colour map");
    s->cols = colour ? HV_COLOUR_SLOTS : hv_lut_columns(lut);
    double lo, hi;
    hv_lut_range(lut, &lo, &hi);
    s->t0 = lo;
    s->tscale = hi > lo ? LUT_BINS / (hi - lo) : 0;
    s->tab = hv_malloc_array(LUT_BINS + 1, (size_t)s->cols * sizeof *s->tab);
    if (!s->tab) return HV_ERR_NOMEM;
    if (colour) {
        s->rgb = hv_malloc_array(LUT_BINS + 1, 3);
        s->hits = hv_calloc(LUT_BINS + 1, sizeof *s->hits);
        if (!s->rgb || !s->hits) return HV_ERR_NOMEM;
        s->lock_ok = pthread_mutex_init(&s->lock, NULL) == 0;
        if (!s->lock_ok) return hv_error_set(HV_ERR_NOMEM, "scan: no mutex");
    }
    for (int b = 0; b <= LUT_BINS; ++b) {
        float col[HV_MAX_MATERIALS];
        hv_lut_eval(lut, hi > lo ? lo + (hi - lo) * b / LUT_BINS : lo, col);
        if (colour) {
            uint8_t c8[4];
            for (int k = 0; k < 4; ++k) c8[k] = (uint8_t)lrintf(HV_CLAMP(col[k], 0.0f, 1.0f) * 255.0f);
            memcpy(s->rgb + 3 * (size_t)b, c8, 3);
            hv_colour_map_fractions(map, c8, col);
        }
        memcpy(s->tab + (size_t)b * (size_t)s->cols, col, (size_t)s->cols * sizeof *col);
    }
    hv_status st = hv_material_table_create(&s->table);
    for (int k = 0; k < s->cols && st == HV_OK; ++k)
        st = hv_material_add(s->table, colour ? hv_colour_map_resin(map, k) : hv_lut_material(lut, k), NULL, NULL);
    return st;
}

hv_status hv_scan_source_open(const hv_scan *scan, const hv_scan_shape *shape, const hv_lut *lut, hv_colour_map *map,
                              hv_scan_source **out)
{
    *out = NULL;
    hv_scan_source *s = hv_calloc(1, sizeof *s);
    if (!s) return HV_ERR_NOMEM;
    s->scan = scan;
    hv_status st = hv_scan_level_init(scan, shape, &s->lv);
    s->lv_ok = st == HV_OK;
    size_t count = (size_t)s->lv.n[0] * (size_t)s->lv.n[1] * (size_t)s->lv.n[2];
    if (st == HV_OK && shape->select == HV_SCAN_SELECT_LABELS) {
        s->member = hv_malloc(count ? count : 1);
        if (!s->member) st = HV_ERR_NOMEM;
        for (size_t i = 0; i < count && st == HV_OK; ++i) {
            double r = rint((double)scan->data[i]);
            int32_t key = (int32_t)HV_CLAMP(r, -2147483648.0, 2147483647.0);
            s->member[i] = r == (double)scan->data[i] && fabs(r) <= 2147483647.0 &&
                           bsearch(&key, s->lv.labels, shape->label_count, sizeof key, cmp_i32) != NULL;
        }
    }
    if (st == HV_OK) st = hv_scan_inside_box(&s->lv, s->src.bbox_min, s->src.bbox_max);
    if (st == HV_OK && lut) st = tabulate(s, lut, map);
    if (st == HV_OK && !(s->name = hv_strdup(hv_scan_name(scan)))) st = HV_ERR_NOMEM;
    if (st != HV_OK) {
        hv_scan_source_close(s);
        return st;
    }
    s->src.table = s->table;
    s->src.name = s->name;
    s->src.memory = (uint64_t)count * (4 + (s->member ? 1 : 0)) + (uint64_t)(LUT_BINS + 1) * (uint64_t)s->cols * 4 +
                    (s->hits ? (uint64_t)(LUT_BINS + 1) * 11 : 0);
    s->src.layer = source_layer;
    s->src.user = s;
    *out = s;
    return HV_OK;
}

const hv_layers_source *hv_scan_source_layers(const hv_scan_source *s) { return &s->src; }

hv_status hv_layers_write_scan(const hv_scan *scan, const hv_scan_voxelize_options *shape, const hv_lut *lut,
                               hv_colour_map *map, const char *dir, const hv_layers_options *opt,
                               const hv_progress *progress, hv_layers_report *report, hv_colour_skin *colour,
                               hv_material_table **table)
{
    hv_layers_options o = *opt;
    hv_scan_voxelize_options so = *shape;
    hv_colour_skin skin;
    memset(&skin, 0, sizeof skin);
    memset(report, 0, sizeof *report);
    if (table) *table = NULL;
    o.source = NULL;
    o.manifest = NULL;
    o.manifest_user = NULL;
    hv_scan_source *src = NULL;
    hv_volume *vol = NULL;
    hv_status s;
    if (hv_scan_prints_direct(&o, &so)) {
        s = hv_scan_source_open(scan, &so.shape, o.mode == HV_LAYERS_MASK ? NULL : lut, map, &src);
        if (s == HV_OK) o.source = hv_scan_source_layers(src);
        if (s == HV_OK && map && o.mode == HV_LAYERS_HALFTONE &&
            hv_scan_source_colour(src, &skin.samples, &skin.rgb, &skin.fractions, &skin.weight))
            skin.map = map; /* the dE2000 of the colours asked for, as a painted mesh's */
    } else {
        so.progress = progress;
        so.max_memory = o.max_memory;
        /* (a scan's model records no requested colours: no dE2000, as the CLI's model path) */
        s = hv_lut_scan_model(scan, &so, lut, map, &vol, NULL);
    }
    if (skin.map) {
        o.manifest = hv_colour_manifest_hook;
        o.manifest_user = &skin;
    }
    if (s == HV_OK) s = hv_layers_write(NULL, vol, dir, &o, progress, report);
    if (s == HV_OK && table && report->materials > 0) {
        const hv_material_table *t = src ? hv_layers_source_table(o.source) : NULL;
        s = t ? hv_material_table_clone(t, table) : hv_material_table_load(vol, table);
    }
    if (colour) {
        *colour = skin;
        colour->model = NULL;
        colour->map = s == HV_OK ? skin.map : NULL; /* `map` when the figures are there */
        colour->samples = 0;
        colour->rgb = NULL;
        colour->fractions = NULL;
        colour->weight = NULL;
    }
    hv_scan_source_close(src);
    hv_volume_destroy(vol);
    return s;
}

int hv_scan_prints_direct(const hv_layers_options *o, const hv_scan_voxelize_options *so)
{
    return !so->keep_largest && !so->fill_holes && so->min_feature == 0 && o->threshold == 0 &&
           o->method == HV_LAYERS_RESAMPLE && !o->compare;
}

int hv_scan_source_colour(const hv_scan_source *s, size_t *n, const uint8_t **rgb, const float **fractions,
                          const uint64_t **weight)
{
    if (!s || !s->hits) return 0;
    *n = LUT_BINS + 1;
    *rgb = s->rgb;
    *fractions = s->tab;
    *weight = s->hits;
    return 1;
}
const hv_material_table *hv_layers_source_table(const hv_layers_source *src) { return src ? src->table : NULL; }

void hv_scan_source_close(hv_scan_source *s)
{
    if (!s) return;
    if (s->lv_ok) hv_scan_level_free(&s->lv);
    hv_material_table_destroy(s->table);
    free(s->tab);
    free(s->member);
    free(s->rgb);
    free(s->hits);
    if (s->lock_ok) pthread_mutex_destroy(&s->lock);
    free(s->name);
    free(s);
}
