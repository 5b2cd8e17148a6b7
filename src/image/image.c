/* src/image/image.c - the image module (hovox/image.h): float RGBA images, PNG read through libpng
 * (untrusted PNGs from memory; written by png.c), and EXR/TIFF through the OpenImageIO bridge
 * plugin, loaded only when asked for. */
#include <errno.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "core/internal.h"
#include "core/plugin.h"
#include "hovox/image.h"
#include "oiio_bridge.h"

/* ---- float images ----------------------------------------------------------------------- */

static hv_status image_create(int width, int height, int clear, hv_image **out)
{
    *out = NULL;
    if (width < 1 || width > 65535 || height < 1 || height > 65535)
        return hv_error_set(HV_ERR_INVALID, "image size %d x %d is outside 1..65535", width,
                            height);
    hv_image *img = hv_calloc(1, sizeof *img);
    if (!img) return HV_ERR_NOMEM;
    img->width = width;
    img->height = height;
    img->rgba = (clear ? hv_calloc_big : hv_malloc_big)((size_t)width * (size_t)height, 4 * sizeof(float));
    if (!img->rgba) {
        free(img);
        return hv_error_set(HV_ERR_NOMEM, "out of memory for a %d x %d image", width, height);
    }
    *out = img;
    return HV_OK;
}

hv_status hv_image_create(int width, int height, hv_image **out) { return image_create(width, height, 1, out); }

hv_status hv_image_create_unset(int width, int height, hv_image **out) { return image_create(width, height, 0, out); }

void hv_image_destroy(hv_image *img)
{
    if (!img) return;
    free(img->rgba);
    free(img);
}

static uint8_t quant8(float v)
{
    v = v * 255.0f + 0.5f;
    return (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v); /* NaN -> 0 */
}

void hv_image_to_rgba8(const hv_image *img, uint8_t *out)
{
    const long n = (long)img->width * (long)img->height;
    /* on all threads for big images (a 2048^2 render: 4 M pixels before its PNG) */
#pragma omp parallel for schedule(static) num_threads(hv_threads()) if (n >= (1L << 18))
    for (long i = 0; i < n; ++i) {
        const float *p = img->rgba + 4 * i;
        float a = p[3], inv = a > 0 ? 1.0f / a : 0;
        for (int k = 0; k < 3; ++k) out[4 * i + k] = quant8(p[k] * inv);
        out[4 * i + 3] = quant8(a);
    }
}

/* ---- PNG in ------------------------------------------------------------------------------- */

/* libpng's decoder never prints either */
static void sink_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

typedef struct png_source {
    const uint8_t *data;
    size_t size, at;
    uint32_t height;  /* rows of the image, once known */
    int interlaced;
    size_t tail;      /* bytes read after the last row */
    char msg[256];
} png_source;

/* Input libpng may read after the last row: the end of the deflate stream, the CRC and the next
 * chunk's header take a few bytes; more is image data going on past the image. */
#define PNG_TAIL_MAX ((size_t)64 << 10)

static void source_error(png_structp png, png_const_charp msg)
{
    png_source *s = png_get_error_ptr(png);
    if (!s->msg[0]) snprintf(s->msg, sizeof s->msg, "%s", msg);
    png_longjmp(png, 1);
}

static void source_read(png_structp png, png_bytep out, size_t n)
{
    png_source *s = png_get_io_ptr(png);
    if (n > s->size - s->at) png_error(png, "the file ends early");
    /* every row read: libpng inflates what is left of the image data to its end (and only warns if
     * there is any), so a sheet with 400 MB of extra IDAT was inflated silently; it is refused once
     * more than a few KiB follow the last row */
    if (s->height && (s->interlaced ? png_get_current_pass_number(png) >= 7
                                    : png_get_current_row_number(png) >= s->height) &&
        (s->tail += n) > PNG_TAIL_MAX)
        png_error(png, "image data goes on past the image (more than 64 KiB of it after the last row)");
    memcpy(out, s->data + s->at, n);
    s->at += n;
}

void hv_png_pixels_free(hv_png_pixels *p)
{
    if (!p) return;
    free(p->samples);
    memset(p, 0, sizeof *p);
}

/* The decoder keeps everything libpng must clean up in these, untouched between setjmp and a
 * longjmp; `rows` and the output are freed by the caller of decode_png. */
typedef struct png_decode {
    png_structp png;
    png_infop info;
    uint8_t *row;
    hv_png_pixels *out;
    int flags; /* HV_PNG_* */
} png_decode;

static hv_status decode_png(png_decode *d, png_source *src, const char *name, uint64_t max_samples)
{
    if (setjmp(png_jmpbuf(d->png))) return hv_error_set(HV_ERR_BAD_INPUT, "%s: not a readable PNG: %s", name, src->msg);
    png_set_read_fn(d->png, src, source_read);
    png_set_user_limits(d->png, 0x7fffffff, 0x7fffffff);
    png_set_chunk_malloc_max(d->png, 8u << 20); /* ancillary chunks (iCCP, zTXt) stay small */
    png_read_info(d->png, d->info);
    png_uint_32 w = png_get_image_width(d->png, d->info), h = png_get_image_height(d->png, d->info);
    int depth = png_get_bit_depth(d->png, d->info), type = png_get_color_type(d->png, d->info);
    if (png_get_interlace_type(d->png, d->info) != PNG_INTERLACE_NONE) png_set_interlace_handling(d->png);
    int indices = type == PNG_COLOR_TYPE_PALETTE && (d->flags & HV_PNG_PALETTE_INDICES);
    if (indices && depth < 8) png_set_packing(d->png); /* one index per byte */
    if (type == PNG_COLOR_TYPE_PALETTE && !indices) png_set_palette_to_rgb(d->png);
    if (type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(d->png);
    if (png_get_valid(d->png, d->info, PNG_INFO_tRNS) && !indices) png_set_tRNS_to_alpha(d->png);
    if (depth == 16) png_set_swap(d->png); /* host order (little-endian machines) */
    png_read_update_info(d->png, d->info);
    int channels = png_get_channels(d->png, d->info);
    int bits = png_get_bit_depth(d->png, d->info);
    if (channels < 1 || channels > 4 || (bits != 8 && bits != 16))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: PNG of %d channels of %d bits", name, channels, bits);
    uint64_t samples = (uint64_t)w * h * (uint64_t)channels;
    if (samples > max_samples)
        return hv_error_set(HV_ERR_LIMIT, "%s: a PNG of %u x %u pixels is larger than allowed here (%llu samples)",
                            name, (unsigned)w, (unsigned)h, (unsigned long long)max_samples);
    size_t rowbytes = png_get_rowbytes(d->png, d->info);
    if (rowbytes != (size_t)w * (size_t)channels * (size_t)(bits / 8))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: PNG rows of %zu bytes", name, rowbytes);
    int passes = png_set_interlace_handling(d->png);
    src->height = h;
    src->interlaced = passes > 1;
    /* interlaced images are combined pass by pass into rows that start out zero */
    d->out->samples = passes > 1 ? hv_calloc((size_t)samples, sizeof(uint16_t))
                                 : hv_malloc_array((size_t)samples, sizeof(uint16_t));
    d->row = hv_malloc(rowbytes ? rowbytes : 1);
    if (!d->out->samples || !d->row) return HV_ERR_NOMEM;
    for (int pass = 0; pass < passes; ++pass)
        for (png_uint_32 y = 0; y < h; ++y) {
            uint16_t *dst = d->out->samples + (size_t)y * w * (size_t)channels;
            if (passes > 1) { /* interlaced: rows are combined with what earlier passes put there */
                if (bits == 16) memcpy(d->row, dst, rowbytes);
                else
                    for (size_t i = 0; i < rowbytes; ++i) d->row[i] = (uint8_t)dst[i];
            }
            png_read_row(d->png, d->row, NULL);
            if (bits == 16) memcpy(dst, d->row, rowbytes);
            else
                for (size_t i = 0; i < rowbytes; ++i) dst[i] = d->row[i];
        }
    /* no png_read_end: the pixels are complete, and chunks after the image are not needed */
    d->out->width = (int)w;
    d->out->height = (int)h;
    d->out->channels = channels;
    d->out->bit_depth = bits;
    return HV_OK;
}

hv_status hv_png_decode(const void *data, size_t size, const char *name, uint64_t max_samples, hv_png_pixels *out)
{
    return hv_png_decode_flags(data, size, name, max_samples, 0, out);
}

hv_status hv_png_decode_flags(const void *data, size_t size, const char *name, uint64_t max_samples, int flags,
                              hv_png_pixels *out)
{
    memset(out, 0, sizeof *out);
    if (size < 8 || png_sig_cmp((png_const_bytep)data, 0, 8) != 0)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: not a PNG (no PNG signature)", name);
    png_source src = {data, size, 0, 0, 0, 0, {0}};
    png_decode d = {NULL, NULL, NULL, out, flags};
    d.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &src, source_error, sink_warning);
    if (d.png) d.info = png_create_info_struct(d.png);
    hv_status s = d.info ? decode_png(&d, &src, name, max_samples) : hv_error_set(HV_ERR_NOMEM, "PNG: out of memory");
    png_destroy_read_struct(&d.png, d.info ? &d.info : NULL, NULL);
    free(d.row);
    if (s != HV_OK) hv_png_pixels_free(out);
    return s;
}

/* ---- OpenImageIO plugin ----------------------------------------------------------------- */

static hv_plugin g_oiio_plugin = HV_PLUGIN_DEF("hovox-oiio", HV_OIIO_ENTRY, HV_OIIO_ABI, "OpenImageIO bridge");

static hv_status write_oiio(const hv_image *img, const char *path, const char *format, int exr)
{
    const void *api = NULL;
    if (hv_plugin_api(&g_oiio_plugin, &api) != HV_OK)
        return hv_error_set(HV_ERR_UNSUPPORTED, "%s: %s output needs OpenImageIO: %s", path,
                            exr ? "EXR" : "TIFF", hv_last_error());
    const hv_oiio_api *g_oiio = api;
    size_t n = (size_t)img->width * (size_t)img->height;
    const float *px = img->rgba;
    float *straight = NULL;
    if (!exr) { /* TIFF: 8-bit straight alpha, like the PNG */
        straight = hv_malloc_array(n, 4 * sizeof(float));
        if (!straight) return HV_ERR_NOMEM;
        for (size_t i = 0; i < n; ++i) {
            float a = img->rgba[4 * i + 3], inv = a > 0 ? 1.0f / a : 0;
            for (int k = 0; k < 3; ++k) straight[4 * i + k] = img->rgba[4 * i + k] * inv;
            straight[4 * i + 3] = a;
        }
        px = straight;
    }
    char *tmp = hv_temp_path(path);
    if (!tmp) {
        free(straight);
        return HV_ERR_NOMEM;
    }
    int rc = g_oiio->write(tmp, format, img->width, img->height, 4, px,
                           exr ? HV_OIIO_HALF : HV_OIIO_UINT8, !exr);
    free(straight);
    hv_status st = HV_OK;
    if (rc != 0) {
        st = hv_error_set((hv_status)rc, "%s: %s", path, g_oiio->last_error());
        unlink(tmp);
    } else if ((st = hv_temp_commit(tmp, path)) != HV_OK) {
        unlink(tmp);
    }
    free(tmp);
    return st;
}

hv_status hv_image_write(const hv_image *img, const char *path)
{
    const char *base = hv_basename(path), *dot = strrchr(base, '.');
    const char *ext = dot ? dot + 1 : "";
    if (strcasecmp(ext, "png") == 0) {
        uint8_t *px = hv_malloc_array((size_t)img->width * (size_t)img->height, 4);
        if (!px) return HV_ERR_NOMEM;
        hv_image_to_rgba8(img, px);
        /* zlib level 3: a quarter of the default level's time for files ~20% larger; the Sub
         * filter on every row: a third of libpng's time to choose filters, files ~4% larger */
        hv_png_options o;
        hv_png_options_init(&o);
        o.compression = 3;
        o.filter_sub = 1;
        hv_status st = hv_png_write(path, px, img->width, img->height, 4, 0, &o);
        free(px);
        return st;
    }
    if (strcasecmp(ext, "exr") == 0) return write_oiio(img, path, "exr", 1);
    if (strcasecmp(ext, "tif") == 0 || strcasecmp(ext, "tiff") == 0)
        return write_oiio(img, path, "tiff", 0);
    return hv_error_set(HV_ERR_UNSUPPORTED, "%s: unknown image format '%s' (png, exr, tif, tiff)",
                        path, dot ? dot : "(no extension)");
}
