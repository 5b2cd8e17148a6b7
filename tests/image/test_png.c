/* tests/image/test_png.c - the one PNG encoder (hv_png_encode, src/image/png.c) on printer layers
 * against libpng's own reader: both of its ways to the zlib stream (libdeflate, and the span coder
 * it picks for sparse indexed or sub-byte images), every bit depth, grey and indexed, one pixel a
 * byte and PNG's packing, padded and exact strides, odd widths, blank, full and random images,
 * with and without the caller's row spans, halftone-like layers whose copies the span coder finds;
 * palette and pHYs read back. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/image.h"
#include "support/support.h"

static unsigned g_seed = 12345;
static unsigned rnd(void)
{
    g_seed = g_seed * 1103515245u + 12345u;
    return g_seed >> 16;
}

/* w x h pixels below 2^depth, one a byte: `parts` rectangles of noise on a blank plate (parts < 0:
 * noise everywhere). */
static uint8_t *plate(int w, int h, int depth, int parts)
{
    uint8_t *px = calloc((size_t)w * (size_t)h, 1);
    unsigned nv = 1u << depth;
    for (int k = 0; k < (parts < 0 ? 1 : parts); ++k) {
        int c0 = parts < 0 ? 0 : (int)(rnd() % (unsigned)w), r0 = parts < 0 ? 0 : (int)(rnd() % (unsigned)h);
        int c1 = parts < 0 ? w - 1 : c0 + (int)(rnd() % (unsigned)(w - c0));
        int r1 = parts < 0 ? h - 1 : r0 + (int)(rnd() % (unsigned)(h - r0));
        for (int r = r0; r <= r1; ++r)
            for (int c = c0; c <= c1; ++c) px[(size_t)r * (size_t)w + (size_t)c] = (uint8_t)(rnd() % nv);
    }
    return px;
}

/* w x h pixels below 2^depth, one a byte, as a halftoned tray layer looks: `copies` parts side by
 * side, each a threshold tile of 64 x 64 (local to the part, so copies are equal) against a
 * material fraction that drifts across the part (index 1 where the rank is below it, else the
 * last index, or 0 at 1 bit: holes), one part a single material (runs of one byte), a part on the
 * first and one on the last row. */
static uint8_t *halftone(int w, int h, int depth, int copies)
{
    uint8_t *px = calloc((size_t)w * (size_t)h, 1);
    uint16_t tile[64 * 64];
    for (int i = 0; i < 64 * 64; ++i) tile[i] = (uint16_t)(rnd() % 4096);
    int top = (1 << depth) - 1, pw = w / (2 * copies + 2), ph = h / 5;
    for (int k = 0; k < copies; ++k)
        for (int r = 0; r < ph; ++r)
            for (int c = 0; c < pw; ++c) {
                int frac = 600 + 2800 * c / pw + 300 * r / ph;
                px[(size_t)(h / 3 + r) * (size_t)w + (size_t)(pw / 2 + k * (pw + pw / 3) + c)] =
                    (uint8_t)(tile[(r % 64) * 64 + c % 64] < frac ? 1 : depth == 1 ? 0 : top);
            }
    for (int c = w / 2; c < w / 2 + 300 && c < w; ++c) { /* a single material, on the edges */
        px[(size_t)c] = (uint8_t)top;
        px[(size_t)(h - 1) * (size_t)w + (size_t)c] = (uint8_t)top;
        for (int r = 2 * h / 3; r < 2 * h / 3 + 10; ++r) px[(size_t)r * (size_t)w + (size_t)c] = (uint8_t)top;
    }
    return px;
}

typedef struct shape {
    int w, h, depth, indexed;
    int packed;  /* rows in PNG's packing (depth < 8) */
    int padded;  /* stride 3 bytes beyond the row */
    int spans;   /* 0 none, 1 tight, 2 wider than the nonzero bytes */
} shape;

/* The rows as the caller gives them, and their spans when asked (every nonzero byte inside). */
static const uint8_t *rows_of(const shape *s, const uint8_t *px, uint8_t **own, size_t *stride, int32_t **span)
{
    int packed = s->packed && s->depth < 8;
    size_t n = packed ? ((size_t)s->w * (size_t)s->depth + 7) / 8 : (size_t)s->w;
    *stride = n + (s->padded ? 3 : 0);
    *own = calloc(*stride * (size_t)s->h, 1);
    if (packed) t_pack_rows(px, s->w, s->h, s->depth, *own, *stride);
    else
        for (int r = 0; r < s->h; ++r) memcpy(*own + (size_t)r * *stride, px + (size_t)r * (size_t)s->w, (size_t)s->w);
    *span = NULL;
    if (s->spans) {
        *span = malloc(2 * (size_t)s->h * sizeof **span);
        for (int r = 0; r < s->h; ++r) {
            int32_t lo = (int32_t)n, hi = 0;
            for (size_t i = 0; i < n; ++i)
                if ((*own)[(size_t)r * *stride + i]) {
                    if ((int32_t)i < lo) lo = (int32_t)i;
                    hi = (int32_t)i + 1;
                }
            if (s->spans == 2) { /* wider, as tray's drawn spans are */
                lo = lo > 2 ? lo - 2 : 0;
                hi = hi + 5 > (int32_t)n ? (int32_t)n : hi + 5;
            }
            (*span)[2 * r] = lo;
            (*span)[2 * r + 1] = hi;
        }
    }
    return *own;
}

static uint8_t g_pal[3 * 256];

/* Encodes px as s says; returns the PNG (free it). */
static uint8_t *encode(const shape *s, const uint8_t *px, size_t *size)
{
    uint8_t *own;
    size_t stride;
    int32_t *span;
    const uint8_t *rows = rows_of(s, px, &own, &stride, &span);
    for (int i = 0; i < 3 * 256; ++i) g_pal[i] = (uint8_t)(i * 7);
    hv_png_options o;
    hv_png_options_init(&o);
    o.bit_depth = s->depth;
    o.packed = s->packed && s->depth < 8;
    o.compression = 1;
    o.dpi[0] = 600;
    o.dpi[1] = 300;
    o.row_spans = span;
    if (s->indexed) {
        o.palette = g_pal;
        o.palette_size = 1 << s->depth;
    }
    uint8_t *data = NULL;
    cr_assert_eq(hv_png_encode(rows, s->w, s->h, 1, s->padded ? stride : 0, &o, &data, size), HV_OK, "%s",
                 hv_last_error());
    free(own);
    free(span);
    return data;
}

/* libpng reads back the pixels, depth, colour type, palette and pHYs. */
static void check(const shape *s, const uint8_t *px, const uint8_t *data, size_t size)
{
    t_png im;
    t_png_load_mem(data, size, &im);
    cr_assert(im.w == s->w && im.h == s->h && im.bit_depth == s->depth, "%dx%d d%d", im.w, im.h, im.bit_depth);
    cr_assert_eq(im.color_type, s->indexed ? 3 : 0);
    cr_assert(im.ppm_x == 23622 && im.ppm_y == 11811, "pHYs %lu x %lu", im.ppm_x, im.ppm_y);
    if (s->indexed) {
        cr_assert_eq(im.npal, 1 << s->depth);
        cr_assert_eq(memcmp(im.pal, g_pal, 3 * (size_t)im.npal), 0, "palette differs");
    }
    cr_assert_eq(memcmp(im.px, px, (size_t)s->w * (size_t)s->h), 0, "%d x %d, %d bits%s%s: pixels differ", s->w, s->h,
                 s->depth, s->packed ? ", packed" : "", s->spans ? ", spans" : "");
    free(im.px);
}

/* Every layout of one image through the encoder as it picks, then through libdeflate alone: the
 * same pixels every time; the bytes do not depend on the layout, nor on the spans when they are
 * the nonzero bytes' own. */
static void round_trip_px(int w, int h, int depth, int indexed, uint8_t *px);
static void round_trip(int w, int h, int depth, int indexed, int parts)
{
    round_trip_px(w, h, depth, indexed, plate(w, h, depth, parts));
}

static void round_trip_px(int w, int h, int depth, int indexed, uint8_t *px)
{
    uint8_t *first = NULL;
    size_t first_size = 0;
    for (int off = 0; off < 2; ++off) {
        setenv("HOVOX_PNG_SPARSE", off ? "0" : "1", 1);
        for (int packed = 0; packed < (depth < 8 ? 2 : 1); ++packed)
            for (int padded = 0; padded < 2; ++padded)
                for (int spans = 0; spans < 3; ++spans) {
                    shape s = {w, h, depth, indexed, packed, padded, spans};
                    size_t size;
                    uint8_t *data = encode(&s, px, &size);
                    check(&s, px, data, size);
                    if (!first) {
                        first = data;
                        first_size = size;
                        continue;
                    }
                    if (!off && spans < 2) /* wider spans may count as dense: libdeflate's bytes */
                        cr_assert(size == first_size && memcmp(data, first, size) == 0,
                                  "%d x %d, %d bits, packed %d padded %d spans %d: the bytes change with the layout or the spans", w, h, depth, packed, padded, spans);
                    free(data);
                }
    }
    unsetenv("HOVOX_PNG_SPARSE");
    free(first);
    free(px);
}

Test(png, every_depth_grey_and_indexed_blank_sparse_dense_and_full)
{
    for (int depth = 1; depth <= 8; depth *= 2)
        for (int indexed = 0; indexed < 2; ++indexed) {
            if (depth == 8 && !indexed) continue; /* filtered rows: below */
            round_trip(1, 1, depth, indexed, 1);
            round_trip(37, 11, depth, indexed, 0);  /* blank */
            round_trip(263, 91, depth, indexed, 3); /* odd width, a few parts */
            round_trip(1000, 30, depth, indexed, 40);
            round_trip(333, 40, depth, indexed, -1); /* noise everywhere */
        }
}

/* The span coder's copies (one byte back, the tile's period and its multiples, the distance
 * between copies of a part) on halftone-like layers at every depth: the same pixels and bytes
 * whatever the layout, and files about as small as libdeflate's (3.4 times larger with literals
 * only, before its copies). */
Test(png, halftone_layers_take_copies_and_stay_small)
{
    for (int depth = 1; depth <= 8; depth *= 2) {
        int w = 3001, h = 203;
        round_trip_px(w, h, depth, 1, halftone(w, h, depth, 2));
        uint8_t *px = halftone(w, h, depth, 3);
        shape s = {w, h, depth, 1, depth < 8, 0, 1};
        size_t a, b;
        uint8_t *span = encode(&s, px, &a);
        setenv("HOVOX_PNG_SPARSE", "0", 1);
        uint8_t *deflate = encode(&s, px, &b);
        unsetenv("HOVOX_PNG_SPARSE");
        cr_assert(a != b || memcmp(span, deflate, a) != 0, "%d bits: the span coder was not used", depth);
        check(&s, px, span, a);
        cr_assert_leq((double)a, 1.15 * (double)b, "%d bits: the span coder's %zu bytes against libdeflate's %zu", depth, a, b);
        free(span);
        free(deflate);
        free(px);
    }
}

Test(png, eight_bit_grey_goes_through_libdeflate_with_filters)
{
    uint8_t *px = plate(301, 57, 8, 5);
    shape s = {301, 57, 8, 0, 0, 1, 1};
    size_t size;
    uint8_t *data = encode(&s, px, &size);
    check(&s, px, data, size);
    free(data);
    free(px);
}

Test(png, long_zero_runs_across_rows)
{
    round_trip(3, 20000, 2, 1, 2);
    round_trip(2000, 64, 8, 1, 1);
}

/* A sparse layer goes through the span coder: other bytes than libdeflate's, the same pixels. */
Test(png, a_sparse_layer_takes_the_span_coder)
{
    int w = 2000, h = 300;
    uint8_t *px = calloc((size_t)w * (size_t)h, 1);
    for (int r = 100; r < 120; ++r)
        for (int c = 500; c < 560; ++c) px[(size_t)r * (size_t)w + (size_t)c] = (uint8_t)(1 + rnd() % 3);
    shape s = {w, h, 2, 1, 1, 0, 0};
    size_t a, b;
    uint8_t *span = encode(&s, px, &a);
    setenv("HOVOX_PNG_SPARSE", "0", 1);
    uint8_t *deflate = encode(&s, px, &b);
    cr_assert(a != b || memcmp(span, deflate, a) != 0, "the same bytes: the span coder was not used");
    check(&s, px, span, a);
    check(&s, px, deflate, b);
    free(span);
    free(deflate);
    free(px);
}

Test(png, a_short_palette_is_checked_in_packed_rows)
{
    uint8_t rows[2] = {0x1b, 0x00}; /* 2 bits: indices 0, 1, 2, 3 then zeros */
    uint8_t pal[9] = {0};
    hv_png_options o;
    hv_png_options_init(&o);
    o.bit_depth = 2;
    o.packed = 1;
    o.palette = pal;
    o.palette_size = 3;
    uint8_t *data = NULL;
    size_t size = 0;
    cr_assert_eq(hv_png_encode(rows, 8, 1, 1, 0, &o, &data, &size), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "pixel (3, 0) has index 3 beyond the 3-colour palette"), "%s", hv_last_error());
    int32_t span[2] = {0, 1}; /* the spans do not hide it */
    o.row_spans = span;
    cr_assert_eq(hv_png_encode(rows, 8, 1, 1, 0, &o, &data, &size), HV_ERR_INVALID);
    o.row_spans = NULL;
    uint8_t zero[2] = {0, 0};
    o.bit_depth = 8;
    cr_assert_eq(hv_png_encode(zero, 2, 1, 1, 0, &o, &data, &size), HV_ERR_INVALID, "packed rows of 8 bits");
    cr_assert(strstr(hv_last_error(), "packed rows need a bit depth of 1, 2 or 4"), "%s", hv_last_error());
}

/* The span coder checks the palette on its literals (every other byte is a zero or a copy of an
 * earlier one): the first pixel beyond the palette is named as libdeflate's scan names it, inside
 * a halftone's copies, in a row's last partial byte, packed or 8 bits a pixel. */
Test(png, a_sparse_layer_names_the_first_index_beyond_the_palette)
{
    static const int at[][2] = {{1500, 60}, {1501, 61}, {2999, 150}, {3000, 150}, {0, 0}, {3000, 202}};
    for (int depth = 2; depth <= 8; depth *= 2) /* (at 1 bit every drawn pixel would be beyond) */
        for (size_t t = 0; t < sizeof at / sizeof at[0]; ++t) {
            int w = 3001, h = 203, top = (1 << depth) - 1;
            uint8_t *px = halftone(w, h, depth, 2);
            if (depth > 1)
                for (size_t i = 0; i < (size_t)w * (size_t)h; ++i) /* palette of top colours: index top is beyond */
                    if (px[i] == top) px[i] = (uint8_t)(top - 1);
            px[(size_t)at[t][1] * (size_t)w + (size_t)at[t][0]] = (uint8_t)top;
            if (at[t][1] + 1 < h) px[(size_t)(at[t][1] + 1) * (size_t)w + 7] = (uint8_t)top; /* a later one, not named */
            uint8_t *own;
            size_t stride;
            int32_t *span;
            shape s = {w, h, depth, 1, depth < 8, 0, 1};
            const uint8_t *rows = rows_of(&s, px, &own, &stride, &span);
            hv_png_options o;
            hv_png_options_init(&o);
            o.bit_depth = depth;
            o.packed = depth < 8;
            o.compression = 1;
            o.palette = g_pal;
            o.palette_size = top;
            char msg[2][256];
            for (int off = 0; off < 2; ++off) {
                setenv("HOVOX_PNG_SPARSE", off ? "0" : "1", 1);
                o.row_spans = off ? NULL : span;
                uint8_t *data = NULL;
                size_t size = 0;
                cr_assert_eq(hv_png_encode(rows, w, h, 1, 0, &o, &data, &size), HV_ERR_INVALID, "%d bits, at %d, %d",
                             depth, at[t][0], at[t][1]);
                cr_assert_null(data);
                snprintf(msg[off], sizeof msg[off], "%s", hv_last_error());
            }
            unsetenv("HOVOX_PNG_SPARSE");
            char want[128];
            snprintf(want, sizeof want, "pixel (%d, %d) has index %d beyond", at[t][0], at[t][1], top);
            cr_assert(strstr(msg[0], want) && strcmp(msg[0], msg[1]) == 0, "%d bits: span coder '%s', scan '%s'", depth,
                      msg[0], msg[1]);
            free(own);
            free(span);
            free(px);
        }
}

Test(png, an_empty_plate_costs_next_to_nothing)
{
    int w = 11575, h = 4606;
    size_t stride = ((size_t)w * 4 + 7) / 8;
    uint8_t *rows = calloc(stride * (size_t)h, 1);
    int32_t *span = calloc(2 * (size_t)h, sizeof *span);
    uint8_t pal[21] = {0};
    hv_png_options o;
    hv_png_options_init(&o);
    o.bit_depth = 4;
    o.packed = 1;
    o.compression = 1;
    o.palette = pal;
    o.palette_size = 7;
    o.dpi[0] = 600;
    o.dpi[1] = 300;
    for (int hint = 0; hint < 2; ++hint) {
        o.row_spans = hint ? span : NULL;
        uint8_t *data;
        size_t size;
        cr_assert_eq(hv_png_encode(rows, w, h, 1, 0, &o, &data, &size), HV_OK, "%s", hv_last_error());
        cr_assert_lt(size, 30000, "an empty J750 plate layer takes %zu bytes", size);
        t_png im;
        t_png_load_mem(data, size, &im);
        for (size_t i = 0; i < (size_t)w * (size_t)h; ++i) cr_assert_eq(im.px[i], 0);
        free(im.px);
        free(data);
    }
    free(span);
    free(rows);
}

/* hv_png_options.filter_bytes (a tray's plate): rows that each follow a zero byte of the caller's
 * go to libdeflate where they lie and give the bytes of the rows copied; a row whose byte before it
 * is not zero sends the image the copying way, with the same bytes. Packed 1, 2 and 4 bits and
 * 8-bit indices, dense (libdeflate) and sparse (the span coder). */
Test(png, rows_after_their_filter_bytes_are_compressed_where_they_lie)
{
    for (int depth = 1; depth <= 8; depth *= 2)
        for (int sparse = 0; sparse < 2; ++sparse) {
            int w = 1203, h = 97;
            uint8_t *px = sparse ? halftone(w, h, depth, 2) : plate(w, h, depth, -1);
            shape s = {w, h, depth, 1, depth < 8, 0, 0};
            size_t want_size;
            setenv("HOVOX_PNG_SPARSE", "1", 1);
            uint8_t *want = encode(&s, px, &want_size);
            size_t n = depth < 8 ? ((size_t)w * (size_t)depth + 7) / 8 : (size_t)w, stride = n + 1;
            uint8_t *base = calloc(stride * (size_t)h + 1, 1), *rows = base + 1; /* t_pack_rows clears a stride */
            if (depth < 8) t_pack_rows(px, w, h, depth, rows, stride);
            else
                for (int r = 0; r < h; ++r) memcpy(rows + (size_t)r * stride, px + (size_t)r * (size_t)w, (size_t)w);
            hv_png_options o;
            hv_png_options_init(&o);
            o.bit_depth = depth;
            o.packed = depth < 8;
            o.compression = 1;
            o.dpi[0] = 600;
            o.dpi[1] = 300;
            o.palette = g_pal;
            o.palette_size = 1 << depth;
            o.filter_bytes = 1;
            for (int dirty = 0; dirty < 2; ++dirty) {
                if (dirty) base[5 * stride] = 7; /* row 5's filter byte: not PNG's None */
                uint8_t *data = NULL;
                size_t size = 0;
                cr_assert_eq(hv_png_encode(rows, w, h, 1, stride, &o, &data, &size), HV_OK, "%s", hv_last_error());
                cr_assert(size == want_size && memcmp(data, want, size) == 0,
                          "%d bits, %s, filter byte %s: the bytes differ from the rows copied", depth,
                          sparse ? "sparse" : "dense", dirty ? "7" : "0");
                free(data);
            }
            unsetenv("HOVOX_PNG_SPARSE");
            check(&s, px, want, want_size);
            free(want);
            free(base);
            free(px);
        }
}
