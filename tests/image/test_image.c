/* tests/image/test_image.c - image output: float images to 8-bit, the libpng writer (grey,
 * grey+alpha, RGB, RGBA, indexed, pHYs, text; to files atomically and to memory), read back by
 * libpng itself; EXR and TIFF through the OpenImageIO plugin, checked with oiiotool. */
#include <criterion/criterion.h>
#include <sys/wait.h>
#include <unistd.h>
#include <dirent.h>
#include <math.h>
#include <png.h>
#include <zlib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/render.h"
#include "support/support.h"

typedef struct decoded {
    png_uint_32 w, h;
    int bit_depth, colour_type, channels;
    png_uint_32 ppm_x, ppm_y;
    int unit, npalette;
    png_colorp palette;
    char text_key[80], text_value[256];
    uint8_t *pixels;
} decoded;

static size_t g_mem_pos, g_mem_len;
static const uint8_t *g_mem;

static void mem_read(png_structp png, png_bytep out, size_t n)
{
    (void)png;
    cr_assert(g_mem_pos + n <= g_mem_len, "PNG read past the end");
    memcpy(out, g_mem + g_mem_pos, n);
    g_mem_pos += n;
}

/* Decode with the classic libpng API, keeping the stored format (no transformations). */
static void decode(FILE *fp, const uint8_t *mem, size_t len, decoded *d)
{
    memset(d, 0, sizeof *d);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    cr_assert(png && info);
    if (setjmp(png_jmpbuf(png))) cr_assert_fail("libpng could not read the PNG");
    if (fp) {
        png_init_io(png, fp);
    } else {
        g_mem = mem;
        g_mem_len = len;
        g_mem_pos = 0;
        png_set_read_fn(png, NULL, mem_read);
    }
    png_read_info(png, info);
    if (png_get_bit_depth(png, info) < 8) png_set_packing(png); /* one pixel per byte, raw */
    png_read_update_info(png, info);
    d->w = png_get_image_width(png, info);
    d->h = png_get_image_height(png, info);
    d->bit_depth = png_get_bit_depth(png, info);
    d->colour_type = png_get_color_type(png, info);
    d->channels = png_get_channels(png, info);
    png_get_pHYs(png, info, &d->ppm_x, &d->ppm_y, &d->unit);
    png_colorp pal;
    if (png_get_PLTE(png, info, &pal, &d->npalette)) {
        d->palette = malloc(sizeof *pal * (size_t)d->npalette);
        memcpy(d->palette, pal, sizeof *pal * (size_t)d->npalette);
    }
    png_textp text;
    int nt = 0;
    if (png_get_text(png, info, &text, &nt) && nt > 0) {
        snprintf(d->text_key, sizeof d->text_key, "%s", text[0].key);
        snprintf(d->text_value, sizeof d->text_value, "%s", text[0].text);
    }
    size_t rb = png_get_rowbytes(png, info);
    d->pixels = malloc(rb * d->h);
    for (png_uint_32 y = 0; y < d->h; ++y) png_read_row(png, d->pixels + y * rb, NULL);
    png_read_end(png, NULL);
    png_destroy_read_struct(&png, &info, NULL);
}

static void decode_file(const char *path, decoded *d)
{
    FILE *fp = fopen(path, "rb");
    cr_assert_not_null(fp, "cannot open %s", path);
    decode(fp, NULL, 0, d);
    fclose(fp);
}

static void free_decoded(decoded *d)
{
    free(d->pixels);
    free(d->palette);
}

static uint8_t *pattern(int w, int h, int ch, size_t stride)
{
    uint8_t *p = calloc(stride * (size_t)h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < ch; ++c) p[(size_t)y * stride + (size_t)x * ch + c] = (uint8_t)(x * 7 + y * 13 + c * 50);
    return p;
}

Test(image, png_round_trips_every_layout)
{
    static const int types[5] = {0, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                 PNG_COLOR_TYPE_RGB_ALPHA};
    for (int ch = 1; ch <= 4; ++ch) {
        int w = 37, h = 11;
        size_t stride = (size_t)w * ch + 5; /* padded rows */
        uint8_t *p = pattern(w, h, ch, stride);
        char name[32];
        snprintf(name, sizeof name, "layout%d.png", ch);
        const char *path = t_tmpfile(name);
        cr_assert_eq(hv_png_write(path, p, w, h, ch, stride, NULL), HV_OK, "%s", hv_last_error());
        decoded d;
        decode_file(path, &d);
        cr_expect(d.w == (png_uint_32)w && d.h == (png_uint_32)h && d.bit_depth == 8);
        cr_expect_eq(d.colour_type, types[ch]);
        cr_expect_eq(d.ppm_x, 0u); /* no pHYs unless asked */
        for (int y = 0; y < h; ++y)
            cr_expect(memcmp(d.pixels + (size_t)y * w * ch, p + (size_t)y * stride, (size_t)w * ch) == 0,
                      "%d channels: row %d differs", ch, y);
        free_decoded(&d);
        free(p);
    }
}

Test(image, png_palette_resolution_text_and_memory)
{
    int w = 20, h = 9;
    uint8_t *idx = malloc((size_t)w * h);
    for (int i = 0; i < w * h; ++i) idx[i] = (uint8_t)(i % 3);
    static const uint8_t pal[9] = {255, 0, 0, 0, 255, 0, 0, 0, 255};
    hv_png_options o;
    hv_png_options_init(&o);
    o.palette = pal;
    o.palette_size = 3;
    o.dpi[0] = 600;
    o.dpi[1] = 300;
    o.compression = 1;
    o.text_key = "Software";
    o.text_value = "hovox test";
    uint8_t *mem = NULL;
    size_t len = 0;
    cr_assert_eq(hv_png_encode(idx, w, h, 1, 0, &o, &mem, &len), HV_OK, "%s", hv_last_error());
    cr_assert(len > 8 && memcmp(mem, "\x89PNG\r\n\x1a\n", 8) == 0);
    decoded d;
    decode(NULL, mem, len, &d);
    cr_expect_eq(d.colour_type, PNG_COLOR_TYPE_PALETTE);
    cr_expect_eq(d.npalette, 3);
    cr_expect(d.palette[2].blue == 255 && d.palette[0].red == 255);
    /* 600 dpi = 23622 px/m, 300 dpi = 11811 px/m */
    cr_expect(d.unit == PNG_RESOLUTION_METER && d.ppm_x == 23622 && d.ppm_y == 11811, "pHYs %u %u",
              d.ppm_x, d.ppm_y);
    cr_expect_str_eq(d.text_key, "Software");
    cr_expect_str_eq(d.text_value, "hovox test");
    cr_expect(memcmp(d.pixels, idx, (size_t)w * h) == 0);
    free_decoded(&d);
    free(mem);
    free(idx);
}

/* Sub-byte depths (1-bit masks, 2/4-bit palettes for halftoned layers): one pixel per byte in,
 * packed in the file, unpacked by libpng on the way back. */
Test(image, png_low_bit_depths)
{
    int w = 13, h = 5; /* rows that do not fill whole bytes */
    uint8_t *px = malloc((size_t)w * h);
    static const uint8_t pal[12] = {0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0, 255};
    for (int depth = 1; depth <= 4; depth *= 2)
        for (int indexed = 0; indexed < 2; ++indexed) {
            int levels = indexed ? (depth == 1 ? 2 : 4) : 1 << depth;
            for (int i = 0; i < w * h; ++i) px[i] = (uint8_t)((i * 7 + i / 3) % levels);
            hv_png_options o;
            hv_png_options_init(&o);
            o.bit_depth = depth;
            if (indexed) {
                o.palette = pal;
                o.palette_size = levels;
            }
            uint8_t *mem = NULL;
            size_t len = 0;
            cr_assert_eq(hv_png_encode(px, w, h, 1, 0, &o, &mem, &len), HV_OK, "%s", hv_last_error());
            decoded d;
            decode(NULL, mem, len, &d);
            cr_expect(d.w == (png_uint_32)w && d.h == (png_uint_32)h);
            cr_expect_eq(d.colour_type, indexed ? PNG_COLOR_TYPE_PALETTE : PNG_COLOR_TYPE_GRAY);
            cr_expect(memcmp(d.pixels, px, (size_t)w * h) == 0, "depth %d%s: pixels differ", depth,
                      indexed ? " indexed" : "");
            /* packed: the file is smaller than one byte per pixel would allow */
            cr_expect(len < (size_t)(w * h) + 200, "depth %d: %zu bytes", depth, len);
            free_decoded(&d);
            free(mem);
        }
    hv_png_options o;
    hv_png_options_init(&o);
    uint8_t *mem = NULL;
    size_t len = 0;
    for (int i = 0; i < w * h; ++i) px[i] = (uint8_t)(i % 4);
    o.bit_depth = 3;
    cr_expect_eq(hv_png_encode(px, w, h, 1, 0, &o, &mem, &len), HV_ERR_INVALID);
    o.bit_depth = 2;
    cr_expect_eq(hv_png_encode(px, w, h, 3, 0, &o, &mem, &len), HV_ERR_INVALID);
    px[7] = 4;
    cr_expect_eq(hv_png_encode(px, w, h, 1, 0, &o, &mem, &len), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "value 4 does not fit in 2 bits") != NULL, "%s", hv_last_error());
    static const uint8_t pal8[24] = {0};
    px[7] = 0;
    o.palette = pal8;
    o.palette_size = 8;
    cr_expect_eq(hv_png_encode(px, w, h, 1, 0, &o, &mem, &len), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "8-colour palette needs more than 2 bits") != NULL, "%s",
              hv_last_error());
    cr_expect_null(mem);
    free(px);
}

Test(image, png_rejects_bad_arguments)
{
    uint8_t px[64] = {0};
    uint8_t *mem = NULL;
    size_t len = 0;
    hv_png_options o;
    hv_png_options_init(&o);
    cr_expect_eq(hv_png_encode(px, 0, 4, 1, 0, NULL, &mem, &len), HV_ERR_INVALID);
    cr_expect_eq(hv_png_encode(px, 4, 4, 5, 0, NULL, &mem, &len), HV_ERR_INVALID);
    cr_expect_eq(hv_png_encode(px, 4, 4, 3, 11, NULL, &mem, &len), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "stride") != NULL, "%s", hv_last_error());
    static const uint8_t pal[6] = {0, 0, 0, 255, 255, 255};
    o.palette = pal;
    o.palette_size = 2;
    px[13] = 2;
    cr_expect_eq(hv_png_encode(px, 4, 4, 1, 0, &o, &mem, &len), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "pixel (1, 3) has index 2") != NULL, "%s", hv_last_error());
    cr_expect_eq(hv_png_encode(px, 4, 4, 3, 0, &o, &mem, &len), HV_ERR_INVALID);
    hv_png_options_init(&o);
    o.compression = 10;
    cr_expect_eq(hv_png_encode(px, 4, 4, 1, 0, &o, &mem, &len), HV_ERR_INVALID);
    hv_png_options_init(&o);
    o.text_key = "";
    o.text_value = "x";
    cr_expect_eq(hv_png_encode(px, 4, 4, 1, 0, &o, &mem, &len), HV_ERR_INVALID);
    cr_expect_null(mem);
}

static int count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    cr_assert_not_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) ++n;
    closedir(d);
    return n;
}

Test(image, png_write_failures_leave_no_file)
{
    uint8_t px[16] = {0};
    const char *missing = t_tmpfile("no/such/dir/out.png");
    cr_expect_eq(hv_png_write(missing, px, 4, 4, 1, 0, NULL), HV_ERR_IO);
    cr_expect(strstr(hv_last_error(), "out.png") != NULL, "%s", hv_last_error());
    /* a directory in the way of the final name: the rename fails, the temporary goes away */
    char dir[512];
    snprintf(dir, sizeof dir, "%s", t_tmpfile("fails"));
    char cmd[600];
    snprintf(cmd, sizeof cmd, "mkdir -p %s/taken.png/x", dir);
    cr_assert_eq(t_run(cmd, NULL), 0);
    char path[600];
    snprintf(path, sizeof path, "%s/taken.png", dir);
    cr_expect_eq(hv_png_write(path, px, 4, 4, 1, 0, NULL), HV_ERR_IO);
    cr_expect_eq(count_entries(dir), 1, "a temporary file was left behind");
}

Test(image, float_to_rgba8_unpremultiplies)
{
    hv_image *img;
    cr_assert_eq(hv_image_create(3, 1, &img), HV_OK);
    float v[12] = {0.25f, 0.1f, 0.0f, 0.5f, /* premultiplied (0.5, 0.2, 0) at alpha 0.5 */
                   0, 0, 0, 0,
                   1.2f, -0.1f, NAN, 1.0f};
    memcpy(img->rgba, v, sizeof v);
    uint8_t out[12];
    hv_image_to_rgba8(img, out);
    cr_expect(out[0] == 128 && out[1] == 51 && out[2] == 0 && out[3] == 128, "%d %d %d %d", out[0],
              out[1], out[2], out[3]);
    cr_expect(out[4] == 0 && out[7] == 0);
    cr_expect(out[8] == 255 && out[9] == 0 && out[10] == 0 && out[11] == 255);
    hv_image_destroy(img);
    cr_expect_eq(hv_image_create(0, 5, &img), HV_ERR_INVALID);
    cr_expect_null(img);
    cr_expect_eq(hv_image_create(5, 70000, &img), HV_ERR_INVALID);
}

static hv_image *constant(float r, float g, float b, float a)
{
    hv_image *img;
    cr_assert_eq(hv_image_create(16, 8, &img), HV_OK);
    for (int i = 0; i < 16 * 8; ++i) {
        img->rgba[4 * i] = r * a;
        img->rgba[4 * i + 1] = g * a;
        img->rgba[4 * i + 2] = b * a;
        img->rgba[4 * i + 3] = a;
    }
    return img;
}

Test(image, write_png_by_extension)
{
    hv_image *img = constant(0.2f, 0.4f, 0.6f, 0.8f);
    const char *path = t_tmpfile("const.PNG");
    cr_assert_eq(hv_image_write(img, path), HV_OK, "%s", hv_last_error());
    decoded d;
    decode_file(path, &d);
    cr_expect_eq(d.colour_type, PNG_COLOR_TYPE_RGB_ALPHA);
    cr_expect(d.pixels[0] == 51 && d.pixels[1] == 102 && d.pixels[2] == 153 && d.pixels[3] == 204,
              "%d %d %d %d", d.pixels[0], d.pixels[1], d.pixels[2], d.pixels[3]);
    free_decoded(&d);
    cr_expect_eq(hv_image_write(img, t_tmpfile("const.bmp")), HV_ERR_UNSUPPORTED);
    cr_expect(strstr(hv_last_error(), "'.bmp'") != NULL, "%s", hv_last_error());
    cr_expect_eq(hv_image_write(img, t_tmpfile("noext")), HV_ERR_UNSUPPORTED);
    hv_image_destroy(img);
}

/* "Stats Avg: a b c d" of oiiotool (integer formats print 0..255); straight: read the alpha as
 * stored (unassociated). Returns the number of values read. */
static int oiio_avg(const char *path, int straight, double avg[4])
{
    char cmd[700], *out = NULL;
    snprintf(cmd, sizeof cmd, "oiiotool %s '%s' --printstats 2>&1",
             straight ? "--iconfig oiio:UnassociatedAlpha 1" : "", path);
    if (t_run(cmd, &out) != 0) {
        free(out);
        return -1;
    }
    const char *p = out ? strstr(out, "Stats Avg:") : NULL;
    int n = p ? sscanf(p, "Stats Avg: %lf %lf %lf %lf", &avg[0], &avg[1], &avg[2], &avg[3]) : 0;
    free(out);
    return n;
}

/* The OpenImageIO writes run in a child that ends with _exit: OIIO's worker threads make
 * LeakSanitizer's stop-the-world tracer crash at the exit of a Criterion test process (the CLI
 * is unaffected and is checked by the render_* CLI cases under the sanitizers). */
Test(image, exr_and_tiff_through_openimageio)
{
    hv_image *img = constant(0.2f, 0.4f, 0.6f, 0.5f);
    const char *exr = t_tmpfile("const.exr"), *tif = t_tmpfile("const.tiff");
    const char *bad = t_tmpfile("no/such/dir/x.exr");
    int fd[2];
    cr_assert_eq(pipe(fd), 0);
    pid_t pid = fork();
    cr_assert_geq(pid, 0);
    if (pid == 0) {
        /* child: codes 0 ok, 2 no plugin, 1 failure; the message goes through the pipe */
        close(fd[0]);
        int code = 0;
        hv_status s = hv_image_write(img, exr);
        if (s == HV_ERR_UNSUPPORTED && strstr(hv_last_error(), "needs OpenImageIO")) code = 2;
        else if (s != HV_OK || (s = hv_image_write(img, tif)) != HV_OK) code = 1;
        else if (hv_image_write(img, bad) != HV_ERR_IO || !strstr(hv_last_error(), "x.exr")) code = 3;
        const char *msg = hv_last_error();
        if (write(fd[1], msg, strlen(msg)) < 0) code = 4;
        _exit(code);
    }
    close(fd[1]);
    char msg[2048] = "";
    ssize_t n = read(fd[0], msg, sizeof msg - 1);
    msg[n > 0 ? n : 0] = '\0';
    close(fd[0]);
    int st = 0;
    waitpid(pid, &st, 0);
    cr_assert(WIFEXITED(st), "the OIIO child crashed");
    if (WEXITSTATUS(st) == 2) {
        hv_image_destroy(img);
        cr_skip_test("OpenImageIO plugin not built: %s", msg);
    }
    cr_assert_eq(WEXITSTATUS(st), 0, "OIIO write failed (%d): %s", WEXITSTATUS(st), msg);
    double a[4];
    if (oiio_avg(exr, 0, a) != 4) {
        hv_image_destroy(img);
        cr_skip_test("oiiotool is not available");
    }
    /* EXR: premultiplied half floats */
    cr_expect(fabs(a[0] - 0.1) < 1e-3 && fabs(a[1] - 0.2) < 1e-3 && fabs(a[2] - 0.3) < 1e-3 &&
              fabs(a[3] - 0.5) < 1e-3, "EXR averages %g %g %g %g", a[0], a[1], a[2], a[3]);
    /* TIFF: 8-bit straight alpha, as the PNG */
    cr_assert_eq(oiio_avg(tif, 1, a), 4);
    cr_expect(a[0] == 51 && a[1] == 102 && a[2] == 153 && a[3] == 128,
              "TIFF averages %g %g %g %g", a[0], a[1], a[2], a[3]);
    /* the unwritable EXR (checked in the child) left nothing */
    cr_expect(!t_exists(bad));
    hv_image_destroy(img);
}

Test(image, png_in_place_writes_the_same_bytes_and_leaves_nothing_on_failure)
{
    uint8_t px[6 * 4];
    for (int i = 0; i < 24; ++i) px[i] = (uint8_t)(i * 10);
    hv_png_options o;
    hv_png_options_init(&o);
    uint8_t *want = NULL;
    size_t n = 0;
    cr_assert_eq(hv_png_encode(px, 6, 4, 1, 0, &o, &want, &n), HV_OK);
    o.in_place = 1;
    const char *path = t_tmpfile("in_place.png");
    cr_assert_eq(hv_png_write(path, px, 6, 4, 1, 0, &o), HV_OK, "%s", hv_last_error());
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f);
    uint8_t got[4096];
    size_t m = fread(got, 1, sizeof got, f);
    fclose(f);
    cr_assert_eq(m, n);
    cr_assert_eq(memcmp(got, want, n), 0, "in place or not, the same PNG");
    free(want);
    cr_assert_eq(hv_png_write("/nonexistent-dir/x.png", px, 6, 4, 1, 0, &o), HV_ERR_IO);
    uint8_t pal[3] = {1, 2, 3};
    o.palette = pal;
    o.palette_size = 1; /* values up to 230 exceed the one-colour palette */
    const char *bad = t_tmpfile("in_place_bad.png");
    cr_assert_eq(hv_png_write(bad, px, 6, 4, 1, 0, &o), HV_ERR_INVALID);
    cr_assert_null(fopen(bad, "rb"), "a refused image leaves no file");
}

/* ---- PNG in ------------------------------------------------------------------------------- */

/* A PNG made by libpng's simplified writer (independent of hovox's encoder). */
static uint8_t *simple_png(png_uint_32 format, int w, int h, const void *px, size_t *n)
{
    png_image im;
    memset(&im, 0, sizeof im);
    im.version = PNG_IMAGE_VERSION;
    im.width = (png_uint_32)w;
    im.height = (png_uint_32)h;
    im.format = format;
    png_alloc_size_t size = 0;
    cr_assert(png_image_write_to_memory(&im, NULL, &size, 0, px, 0, NULL));
    uint8_t *buf = malloc(size);
    cr_assert(png_image_write_to_memory(&im, buf, &size, 0, px, 0, NULL), "%s", im.message);
    *n = size;
    return buf;
}

Test(image, png_16_bit_grey_round_trip)
{
    enum { W = 7, H = 5 };
    uint8_t be[W * H * 2];
    uint16_t want[W * H];
    for (int i = 0; i < W * H; ++i) {
        want[i] = (uint16_t)(i * 1871 + 3);
        be[2 * i] = (uint8_t)(want[i] >> 8);
        be[2 * i + 1] = (uint8_t)want[i];
    }
    hv_png_options o;
    hv_png_options_init(&o);
    o.bit_depth = 16;
    uint8_t *png = NULL;
    size_t n = 0;
    cr_assert_eq(hv_png_encode(be, W, H, 1, 0, &o, &png, &n), HV_OK, "%s", hv_last_error());
    cr_expect_eq(png[24], 16, "IHDR bit depth");
    cr_expect_eq(png[25], 0, "IHDR colour type grey");
    hv_png_pixels px;
    cr_assert_eq(hv_png_decode(png, n, "g16.png", 1000, &px), HV_OK, "%s", hv_last_error());
    cr_assert(px.width == W && px.height == H && px.channels == 1 && px.bit_depth == 16);
    for (int i = 0; i < W * H; ++i) cr_assert_eq(px.samples[i], want[i], "sample %d", i);
    hv_png_pixels_free(&px);
    /* a palette cannot have 16 bits */
    uint8_t pal[3] = {0, 0, 0};
    o.palette = pal;
    o.palette_size = 1;
    uint8_t *bad = NULL;
    cr_expect_eq(hv_png_encode(be, W, H, 1, 0, &o, &bad, &n), HV_ERR_INVALID);
    free(png);
}

Test(image, png_decode_reads_what_libpng_wrote)
{
    /* 8-bit RGBA */
    uint8_t rgba[3 * 2 * 4];
    for (int i = 0; i < 24; ++i) rgba[i] = (uint8_t)(i * 11);
    size_t n;
    uint8_t *png = simple_png(PNG_FORMAT_RGBA, 3, 2, rgba, &n);
    hv_png_pixels px;
    cr_assert_eq(hv_png_decode(png, n, "rgba.png", 100, &px), HV_OK, "%s", hv_last_error());
    cr_assert(px.channels == 4 && px.bit_depth == 8 && px.width == 3 && px.height == 2);
    for (int i = 0; i < 24; ++i) cr_assert_eq(px.samples[i], rgba[i]);
    hv_png_pixels_free(&px);
    /* the limit is checked before the buffer is made */
    cr_expect_eq(hv_png_decode(png, n, "rgba.png", 23, &px), HV_ERR_LIMIT);
    cr_expect_null(px.samples);
    /* truncated and damaged */
    cr_expect_eq(hv_png_decode(png, n - 20, "cut.png", 100, &px), HV_ERR_BAD_INPUT);
    cr_expect(strstr(hv_last_error(), "cut.png: not a readable PNG") != NULL, "%s", hv_last_error());
    png[40] ^= 0x55; /* inside IDAT or IHDR's CRC: libpng refuses */
    cr_expect_eq(hv_png_decode(png, n, "crc.png", 100, &px), HV_ERR_BAD_INPUT);
    cr_expect_eq(hv_png_decode("abc", 3, "t.png", 100, &px), HV_ERR_BAD_INPUT);
    cr_expect_str_eq(hv_last_error(), "t.png: not a PNG (no PNG signature)");
    free(png);
    /* 16-bit grey through the simplified API's linear format */
    uint16_t g[4] = {0, 1, 40000, 65535};
    png = simple_png(PNG_FORMAT_LINEAR_Y, 2, 2, g, &n);
    cr_assert_eq(hv_png_decode(png, n, "g.png", 100, &px), HV_OK, "%s", hv_last_error());
    cr_assert(px.channels == 1 && px.bit_depth == 16);
    for (int i = 0; i < 4; ++i) cr_expect_eq(px.samples[i], g[i]);
    hv_png_pixels_free(&px);
    free(png);
}

Test(image, png_decode_expands_palettes_and_low_bit_grey)
{
    /* indexed, 2 bits: hovox's writer, decoded to RGB */
    uint8_t idx[4] = {0, 1, 2, 1};
    uint8_t pal[9] = {10, 20, 30, 40, 50, 60, 70, 80, 90};
    hv_png_options o;
    hv_png_options_init(&o);
    o.palette = pal;
    o.palette_size = 3;
    o.bit_depth = 2;
    uint8_t *png;
    size_t n;
    cr_assert_eq(hv_png_encode(idx, 2, 2, 1, 0, &o, &png, &n), HV_OK);
    hv_png_pixels px;
    cr_assert_eq(hv_png_decode(png, n, "p.png", 100, &px), HV_OK, "%s", hv_last_error());
    cr_assert(px.channels == 3 && px.bit_depth == 8);
    for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c) cr_expect_eq(px.samples[3 * i + c], pal[3 * idx[i] + c]);
    hv_png_pixels_free(&px);
    free(png);
    /* grey of 2 bits: 0..3 become 0, 85, 170, 255 (value / 3 == sample / 255) */
    uint8_t grey[4] = {0, 1, 2, 3};
    hv_png_options_init(&o);
    o.bit_depth = 2;
    cr_assert_eq(hv_png_encode(grey, 4, 1, 1, 0, &o, &png, &n), HV_OK);
    cr_assert_eq(hv_png_decode(png, n, "g2.png", 100, &px), HV_OK, "%s", hv_last_error());
    cr_assert(px.channels == 1 && px.bit_depth == 8);
    for (int i = 0; i < 4; ++i) cr_expect_eq(px.samples[i], 85 * i);
    hv_png_pixels_free(&px);
    free(png);
}

/* The zlib stream of a PNG's IDAT chunks, inflated: each row starts with its filter type. */
static uint8_t *idat_rows(const uint8_t *png, size_t len, size_t rows_bytes)
{
    uint8_t *z = malloc(len), *out = malloc(rows_bytes);
    size_t zn = 0;
    for (size_t at = 8; at + 12 <= len;) {
        uint32_t n = (uint32_t)png[at] << 24 | (uint32_t)png[at + 1] << 16 | (uint32_t)png[at + 2] << 8 | png[at + 3];
        if (memcmp(png + at + 4, "IDAT", 4) == 0) {
            memcpy(z + zn, png + at + 8, n);
            zn += n;
        }
        at += 12 + n;
    }
    uLongf outn = rows_bytes;
    cr_assert_eq(uncompress(out, &outn, z, zn), Z_OK);
    cr_assert_eq(outn, rows_bytes);
    free(z);
    return out;
}

Test(image, png_sub_filter_keeps_the_pixels)
{
    /* filter_sub: every row Sub-filtered (type 1), the same pixels read back */
    int w = 61, h = 23;
    uint8_t *p = pattern(w, h, 4, (size_t)w * 4);
    hv_png_options o;
    hv_png_options_init(&o);
    o.compression = 3;
    o.filter_sub = 1;
    uint8_t *mem = NULL;
    size_t len = 0;
    cr_assert_eq(hv_png_encode(p, w, h, 4, 0, &o, &mem, &len), HV_OK, "%s", hv_last_error());
    decoded d;
    decode(NULL, mem, len, &d);
    cr_assert(d.w == (png_uint_32)w && d.h == (png_uint_32)h && d.channels == 4);
    cr_expect(memcmp(d.pixels, p, (size_t)w * h * 4) == 0);
    uint8_t *rows = idat_rows(mem, len, (size_t)h * (1 + (size_t)w * 4));
    for (int y = 0; y < h; ++y) cr_expect_eq(rows[(size_t)y * (1 + (size_t)w * 4)], 1, "row %d: filter %d", y, rows[(size_t)y * (1 + (size_t)w * 4)]);
    free(rows);
    free_decoded(&d);
    free(mem);
    free(p);
}

/* Big 8-bit images with the Sub filter are deflated in bands on all threads (image.c): libpng
 * reads them back exactly, for every channel count, with pHYs and text, band edges and a
 * stride; a file in place and one in memory hold the same bytes. */
Test(image, png_in_parallel_bands_read_back_by_libpng)
{
    int w = 700, h = 521; /* 364,700 pixels: above the parallel threshold; rows not a multiple of
                             the bands */
    for (int ch = 1; ch <= 4; ++ch) {
        size_t stride = (size_t)w * ch + 13;
        uint8_t *px = malloc(stride * h);
        uint32_t r = 12345u * (uint32_t)ch;
        for (int y = 0; y < h; ++y)
            for (size_t x = 0; x < stride; ++x) {
                r = r * 1103515245u + 12345u;
                /* smooth ramps with noise: long matches across band edges and literals */
                px[(size_t)y * stride + x] = (uint8_t)((x / 7 + (size_t)y / 3) + ((r >> 24) & 3));
            }
        hv_png_options o;
        hv_png_options_init(&o);
        o.compression = 3;
        o.filter_sub = 1;
        o.dpi[0] = 96;
        o.text_key = "Software";
        o.text_value = "hovox parallel";
        uint8_t *mem = NULL;
        size_t len = 0;
        cr_assert_eq(hv_png_encode(px, w, h, ch, stride, &o, &mem, &len), HV_OK, "%s", hv_last_error());
        decoded d;
        decode(NULL, mem, len, &d);
        cr_assert_eq(d.w, (png_uint_32)w);
        cr_assert_eq(d.channels, ch);
        cr_expect(d.unit == PNG_RESOLUTION_METER && d.ppm_x == 3780 && d.ppm_y == 3780, "pHYs %u %u", d.ppm_x, d.ppm_y);
        cr_expect_str_eq(d.text_value, "hovox parallel");
        for (int y = 0; y < h; ++y)
            cr_assert_eq(memcmp(d.pixels + (size_t)y * w * ch, px + (size_t)y * stride, (size_t)w * ch), 0, "%d channels, row %d", ch,
                         y);
        free_decoded(&d);
        /* the same file through hv_png_write */
        char path[64];
        snprintf(path, sizeof path, "/tmp/hovox-par-%d-%d.png", (int)getpid(), ch);
        cr_assert_eq(hv_png_write(path, px, w, h, ch, stride, &o), HV_OK, "%s", hv_last_error());
        size_t flen = 0;
        uint8_t *file = (uint8_t *)t_slurp(path, &flen);
        cr_assert(file && flen == len && memcmp(file, mem, len) == 0);
        free(file);
        remove(path);
        free(mem);
        free(px);
    }
}

/* hv_png_decode_flags(HV_PNG_PALETTE_INDICES): a palette image of any bit depth reads back as the
 * indices it was written with (the form of a halftoned layer); without the flag, as RGB. */
Test(image, png_decode_palette_indices)
{
    int w = 13, h = 5;
    uint8_t px[13 * 5];
    static const uint8_t pal[12] = {0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0, 255};
    for (int depth = 1; depth <= 8; depth *= 2) {
        int levels = depth == 1 ? 2 : 4;
        for (int i = 0; i < w * h; ++i) px[i] = (uint8_t)((i * 7 + i / 3) % levels);
        hv_png_options o;
        hv_png_options_init(&o);
        o.bit_depth = depth;
        o.palette = pal;
        o.palette_size = levels;
        uint8_t *mem = NULL;
        size_t len = 0;
        cr_assert_eq(hv_png_encode(px, w, h, 1, 0, &o, &mem, &len), HV_OK, "%s", hv_last_error());
        hv_png_pixels p;
        cr_assert_eq(hv_png_decode_flags(mem, len, "mem", 1 << 20, HV_PNG_PALETTE_INDICES, &p), HV_OK, "%s",
                     hv_last_error());
        cr_assert(p.width == w && p.height == h && p.channels == 1 && p.bit_depth == 8, "depth %d", depth);
        for (int i = 0; i < w * h; ++i) cr_assert_eq(p.samples[i], px[i], "depth %d pixel %d", depth, i);
        hv_png_pixels_free(&p);
        cr_assert_eq(hv_png_decode(mem, len, "mem", 1 << 20, &p), HV_OK);
        cr_assert_eq(p.channels, 3);
        for (int i = 0; i < w * h; ++i) cr_assert_eq(p.samples[3 * i], pal[3 * px[i]]);
        hv_png_pixels_free(&p);
        free(mem);
    }
}

/* issue 32 item 12: image data that goes on past the image is refused once more than 64 KiB of it
 * follow the last row: here a second IDAT chunk continues the deflate stream with 100 KiB of
 * random bytes (stored), as a bomb's continues with gigabytes of zeros. Before, libpng inflated it
 * all and only warned (400 MB of extra IDAT were inflated silently). */
Test(image, png_decode_refuses_image_data_past_the_last_row)
{
    enum { W = 8, H = 8 };
    enum { EXTRA = 100 << 10 };
    static uint8_t raw[H * (W + 1) + EXTRA];
    unsigned seed = 7;
    for (size_t i = 0; i < sizeof raw; ++i) raw[i] = (uint8_t)((seed = seed * 1103515245u + 12345u) >> 16);
    for (int y = 0; y < H; ++y) raw[y * (W + 1)] = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) raw[y * (W + 1) + 1 + x] = (uint8_t)(16 * y + x);
    /* the rows, a full flush ending the first IDAT, then the same stream goes on in a second */
    static uint8_t z[EXTRA + 4096];
    z_stream zs;
    memset(&zs, 0, sizeof zs);
    cr_assert_eq(deflateInit(&zs, 6), Z_OK);
    zs.next_in = raw, zs.avail_in = H * (W + 1), zs.next_out = z, zs.avail_out = sizeof z;
    cr_assert_eq(deflate(&zs, Z_FULL_FLUSH), Z_OK);
    size_t n1 = sizeof z - zs.avail_out;
    zs.next_in = raw + H * (W + 1), zs.avail_in = EXTRA;
    cr_assert_eq(deflate(&zs, Z_FINISH), Z_STREAM_END);
    size_t nz = sizeof z - zs.avail_out;
    deflateEnd(&zs);
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    static uint8_t png[EXTRA + 8192];
    uint8_t ihdr[13] = {0, 0, 0, W, 0, 0, 0, H, 8, 0, 0, 0, 0};
    size_t n = 0;
    memcpy(png, sig, 8), n = 8;
    n += t_png_chunk(png + n, "IHDR", ihdr, 13);
    size_t idat1 = n;
    n += t_png_chunk(png + n, "IDAT", z, (uint32_t)n1);
    size_t tail = n;
    n += t_png_chunk(png + n, "IDAT", z + n1, (uint32_t)(nz - n1));
    n += t_png_chunk(png + n, "IEND", NULL, 0);
    hv_png_pixels px;
    cr_assert_eq(hv_png_decode(png, n, "tail.png", 1000, &px), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "tail.png") && strstr(hv_last_error(), "goes on past the image"), "%s",
              hv_last_error());
    /* the same stream ended where the image ends reads, pixel for pixel */
    memset(&zs, 0, sizeof zs);
    cr_assert_eq(deflateInit(&zs, 6), Z_OK);
    zs.next_in = raw, zs.avail_in = H * (W + 1), zs.next_out = z, zs.avail_out = sizeof z;
    cr_assert_eq(deflate(&zs, Z_FINISH), Z_STREAM_END);
    nz = sizeof z - zs.avail_out;
    deflateEnd(&zs);
    n = idat1;
    n += t_png_chunk(png + n, "IDAT", z, (uint32_t)nz);
    n += t_png_chunk(png + n, "IEND", NULL, 0);
    (void)tail;
    cr_assert_eq(hv_png_decode(png, n, "ok.png", 1000, &px), HV_OK, "%s", hv_last_error());
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) cr_assert_eq(px.samples[y * W + x], 16 * y + x);
    hv_png_pixels_free(&px);
}
