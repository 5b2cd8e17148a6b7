/* tests/image/test_png_packed.c - the one PNG encoder (hv_png_encode, src/image/image.c) on
 * printer layers in PNG's own packing (opt->packed, as tray writes them) against libpng's own
 * reader: every bit depth, grey and indexed, empty, full and sparse images, padded and exact row
 * strides, odd widths, the pHYs resolution; an empty plate stays small. */
#include <criterion/criterion.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/image.h"

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
    png_uint_32 rx = 0, ry = 0;
    int unit = -1;
    cr_assert(png_get_pHYs(p, info, &rx, &ry, &unit), "no pHYs chunk");
    cr_assert(rx == 23622 && ry == 11811 && unit == PNG_RESOLUTION_METER, "pHYs %u x %u unit %d", rx, ry, unit);
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
static void round_trip(int w, int h, int depth, int indexed, int parts, int padded)
{
    uint8_t *px = calloc((size_t)w * (size_t)h, 1);
    int maxv = (1 << depth) - 1;
    for (int k = 0; k < parts; ++k) {
        int c0 = (int)(rnd() % (unsigned)w), r0 = (int)(rnd() % (unsigned)h);
        int c1 = c0 + (int)(rnd() % (unsigned)(w - c0)), r1 = r0 + (int)(rnd() % (unsigned)(h - r0));
        for (int r = r0; r <= r1; ++r)
            for (int c = c0; c <= c1; ++c) px[(size_t)r * (size_t)w + c] = (uint8_t)(rnd() % (unsigned)(maxv + 1));
    }
    size_t stride = ((size_t)w * (size_t)depth + 7) / 8 + (padded ? 3 : 0);
    uint8_t *rows = malloc(stride * (size_t)h);
    pack(px, w, h, depth, rows, stride);
    uint8_t pal[3 * 256];
    for (int i = 0; i < 3 * 256; ++i) pal[i] = (uint8_t)i;
    hv_png_options o;
    hv_png_options_init(&o);
    o.bit_depth = depth;
    o.packed = depth < 8;
    o.compression = 1;
    o.dpi[0] = 600;
    o.dpi[1] = 300;
    if (indexed) {
        o.palette = pal;
        o.palette_size = maxv + 1;
    }
    uint8_t *data;
    size_t size;
    const uint8_t *in = depth < 8 ? rows : px; /* 8 bits: one pixel a byte, packed or not */
    cr_assert_eq(hv_png_encode(in, w, h, 1, depth < 8 ? (padded ? stride : 0) : 0, &o, &data, &size), HV_OK, "%s",
                 hv_last_error());
    int dw, dh, dd, di;
    uint8_t *back = decode(data, size, &dw, &dh, &dd, &di);
    cr_assert(dw == w && dh == h && dd == depth && di == indexed, "%dx%d d%d i%d", dw, dh, dd, di);
    cr_assert_eq(memcmp(back, px, (size_t)w * (size_t)h), 0, "%d x %d, %d bits, %d parts: pixels differ", w, h, depth,
                 parts);
    free(back);
    free(data);
    free(rows);
    free(px);
}

Test(png_packed, every_depth_grey_and_indexed_padded_and_exact_rows)
{
    for (int depth = 1; depth <= 8; depth *= 2)
        for (int indexed = 0; indexed < 2; ++indexed)
            for (int padded = 0; padded < 2; ++padded) {
                round_trip(1, 1, depth, indexed, 1, padded);
                round_trip(37, 11, depth, indexed, 0, padded);  /* all zero */
                round_trip(263, 91, depth, indexed, 3, padded); /* odd width, a few parts */
                round_trip(1000, 30, depth, indexed, 40, padded);
            }
}

Test(png_packed, a_short_palette_is_checked_in_packed_rows)
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
    uint8_t zero[2] = {0, 0};
    o.bit_depth = 8;
    cr_assert_eq(hv_png_encode(zero, 2, 1, 1, 0, &o, &data, &size), HV_ERR_INVALID, "packed rows of 8 bits");
    cr_assert(strstr(hv_last_error(), "packed rows need a bit depth of 1, 2 or 4"), "%s", hv_last_error());
}

Test(png_packed, a_full_image_and_long_zero_runs)
{
    round_trip(2000, 64, 8, 1, 1, 0);
    round_trip(3, 20000, 2, 1, 2, 1); /* zero runs across many rows */
}

Test(png_packed, an_empty_plate_costs_next_to_nothing)
{
    int w = 11575, h = 4606;
    size_t stride = ((size_t)w * 4 + 7) / 8;
    uint8_t *rows = calloc(stride * (size_t)h, 1);
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
    uint8_t *data;
    size_t size;
    cr_assert_eq(hv_png_encode(rows, w, h, 1, 0, &o, &data, &size), HV_OK, "%s", hv_last_error());
    cr_assert_lt(size, 200000, "an empty J750 plate layer takes %zu bytes", size);
    int dw, dh, dd, di;
    uint8_t *back = decode(data, size, &dw, &dh, &dd, &di);
    for (size_t i = 0; i < (size_t)w * (size_t)h; ++i) cr_assert_eq(back[i], 0);
    free(back);
    free(data);
    free(rows);
}
