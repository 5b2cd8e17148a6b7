/* tests/image/test_png_fast.c - the layer PNG writer (src/image/png_fast.c) against libpng's own
 * reader: every bit depth, grey and indexed, empty, full and sparse images, with and without
 * row spans, odd widths; the zero-run coding of empty rows keeps files small. */
#include <criterion/criterion.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>

#include "image/png_fast.h"

/* Decode with libpng into one byte per pixel. */
static uint8_t *decode(const uint8_t *data, size_t size, int *w, int *h, int *depth, int *indexed)
{
    FILE *fp = fmemopen((void *)data, size, "rb");
    png_structp p = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(p);
    cr_assert(fp && p && info);
    if (setjmp(png_jmpbuf(p))) cr_assert_fail("libpng refused the file");
    png_init_io(p, fp);
    png_read_info(p, info);
    *w = (int)png_get_image_width(p, info);
    *h = (int)png_get_image_height(p, info);
    *depth = png_get_bit_depth(p, info);
    *indexed = png_get_color_type(p, info) == PNG_COLOR_TYPE_PALETTE;
    png_set_packing(p);
    png_read_update_info(p, info);
    uint8_t *px = malloc((size_t)*w * (size_t)*h);
    for (int r = 0; r < *h; ++r) png_read_row(p, px + (size_t)r * (size_t)*w, NULL);
    png_read_end(p, NULL);
    png_destroy_read_struct(&p, &info, NULL);
    fclose(fp);
    return px;
}

static void pack(const uint8_t *px, int w, int h, int depth, uint8_t *rows, size_t stride)
{
    for (int r = 0; r < h; ++r) {
        uint8_t *o = rows + (size_t)r * stride;
        memset(o, 0, stride);
        for (int c = 0; c < w; ++c) {
            int per = 8 / depth, shift = 8 - depth * (c % per + 1);
            o[c / per] |= (uint8_t)(px[(size_t)r * (size_t)w + c] << shift);
        }
    }
}

static unsigned g_seed = 12345;
static unsigned rnd(void)
{
    g_seed = g_seed * 1103515245u + 12345u;
    return g_seed >> 16;
}

/* An image of parts (rectangles of noise) on an empty plate. */
static void round_trip(int w, int h, int depth, int indexed, int parts, int use_span)
{
    uint8_t *px = calloc((size_t)w * (size_t)h, 1);
    int maxv = (1 << depth) - 1;
    for (int k = 0; k < parts; ++k) {
        int c0 = (int)(rnd() % (unsigned)w), r0 = (int)(rnd() % (unsigned)h);
        int c1 = c0 + (int)(rnd() % (unsigned)(w - c0)), r1 = r0 + (int)(rnd() % (unsigned)(h - r0));
        for (int r = r0; r <= r1; ++r)
            for (int c = c0; c <= c1; ++c) px[(size_t)r * (size_t)w + c] = (uint8_t)(rnd() % (unsigned)(maxv + 1));
    }
    size_t stride = ((size_t)w * (size_t)depth + 7) / 8 + 3;
    uint8_t *rows = malloc(stride * (size_t)h);
    pack(px, w, h, depth, rows, stride);
    int32_t *span = NULL;
    if (use_span) {
        span = malloc(2 * (size_t)h * sizeof *span);
        size_t rb = ((size_t)w * (size_t)depth + 7) / 8;
        for (int r = 0; r < h; ++r) {
            int lo = (int)rb, hi = 0;
            for (size_t i = 0; i < rb; ++i)
                if (rows[(size_t)r * stride + i]) {
                    if ((int)i < lo) lo = (int)i;
                    hi = (int)i + 1;
                }
            span[2 * r] = lo;
            span[2 * r + 1] = hi;
        }
    }
    uint8_t pal[3 * 256];
    for (int i = 0; i < 3 * 256; ++i) pal[i] = (uint8_t)i;
    hv_png_fast_image img = {w, h, depth, rows, stride, span, indexed ? pal : NULL, maxv + 1, {600, 300}};
    uint8_t *data;
    size_t size;
    cr_assert_eq(hv_png_fast_encode(&img, &data, &size), HV_OK);
    int dw, dh, dd, di;
    uint8_t *back = decode(data, size, &dw, &dh, &dd, &di);
    cr_assert(dw == w && dh == h && dd == depth && di == indexed, "%dx%d d%d i%d", dw, dh, dd, di);
    cr_assert_eq(memcmp(back, px, (size_t)w * (size_t)h), 0, "%d x %d, %d bits, %d parts: pixels differ", w, h, depth,
                 parts);
    free(back);
    free(data);
    free(span);
    free(rows);
    free(px);
}

Test(png_fast, every_depth_grey_and_indexed_with_and_without_spans)
{
    for (int depth = 1; depth <= 8; depth *= 2)
        for (int indexed = 0; indexed < 2; ++indexed)
            for (int span = 0; span < 2; ++span) {
                round_trip(1, 1, depth, indexed, 1, span);
                round_trip(37, 11, depth, indexed, 0, span);  /* all zero */
                round_trip(263, 91, depth, indexed, 3, span); /* odd width, a few parts */
                round_trip(1000, 30, depth, indexed, 40, span);
            }
}

Test(png_fast, a_full_image_and_long_zero_runs)
{
    round_trip(2000, 64, 8, 1, 1, 0);
    round_trip(3, 20000, 2, 1, 2, 1); /* zero runs across many rows */
}

Test(png_fast, an_empty_plate_costs_next_to_nothing)
{
    int w = 11575, h = 4606;
    size_t stride = ((size_t)w * 4 + 7) / 8;
    uint8_t *rows = calloc(stride * (size_t)h, 1);
    int32_t *span = calloc(2 * (size_t)h, sizeof *span);
    uint8_t pal[21] = {0};
    hv_png_fast_image img = {w, h, 4, rows, stride, span, pal, 7, {600, 300}};
    uint8_t *data;
    size_t size;
    cr_assert_eq(hv_png_fast_encode(&img, &data, &size), HV_OK);
    cr_assert_lt(size, 200000, "an empty J750 plate layer takes %zu bytes", size);
    int dw, dh, dd, di;
    uint8_t *back = decode(data, size, &dw, &dh, &dd, &di);
    for (size_t i = 0; i < (size_t)w * (size_t)h; ++i) cr_assert_eq(back[i], 0);
    free(back);
    free(data);
    free(span);
    free(rows);
}
