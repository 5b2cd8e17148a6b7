/* src/image/image.c - the image module (hovox/image.h): float RGBA images, PNG through libpng
 * (grey, grey+alpha, RGB, RGBA, indexed, 1 to 16 bits; pHYs resolution; to a file atomically or
 * to memory; decoding untrusted PNGs from memory), and EXR/TIFF through the OpenImageIO bridge
 * plugin, loaded only when asked for. */
#include <errno.h>
#include <png.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>
#include <zlib.h>

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

/* ---- PNG -------------------------------------------------------------------------------- */

void hv_png_options_init(hv_png_options *o)
{
    memset(o, 0, sizeof *o);
    o->compression = -1;
}

typedef struct png_sink {
    FILE *fp;          /* file output, or */
    uint8_t *mem;      /* memory output */
    size_t len, cap;
    hv_status status;  /* of the failure that longjmp'd */
    char msg[256];
} png_sink;

static void sink_error(png_structp png, png_const_charp msg)
{
    png_sink *s = png_get_error_ptr(png);
    if (s->status == HV_OK) {
        s->status = HV_ERR_INTERNAL;
        snprintf(s->msg, sizeof s->msg, "libpng: %s", msg);
    }
    png_longjmp(png, 1);
}

static void sink_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg; /* the library never prints */
}

static int put(png_sink *s, const void *p, size_t n);

static void sink_write(png_structp png, png_bytep data, size_t n)
{
    png_sink *s = png_get_io_ptr(png);
    if (!put(s, data, n)) png_error(png, s->status == HV_ERR_IO ? "write failed" : "out of memory");
}

static void sink_flush(png_structp png)
{
    (void)png;
}

static hv_status check_png_args(const uint8_t *pixels, int width, int height, int channels,
                                size_t stride, const hv_png_options *o)
{
    if (width < 1 || height < 1)
        return hv_error_set(HV_ERR_INVALID, "PNG: image size %d x %d must be positive", width,
                            height);
    if (channels < 1 || channels > 4)
        return hv_error_set(HV_ERR_INVALID, "PNG: %d channels (1 to 4)", channels);
    size_t bps = o && o->bit_depth == 16 ? 2 : 1; /* bytes per sample */
    if (stride && stride < (size_t)width * (size_t)channels * bps)
        return hv_error_set(HV_ERR_INVALID, "PNG: row stride %zu is less than %d x %d x %zu bytes",
                            stride, width, channels, bps);
    if (!o) return HV_OK;
    if (o->compression < -1 || o->compression > 9)
        return hv_error_set(HV_ERR_INVALID, "PNG: compression level %d (0..9 or -1)",
                            o->compression);
    for (int a = 0; a < 2; ++a)
        if (!(o->dpi[a] >= 0 && o->dpi[a] < 1e8))
            return hv_error_set(HV_ERR_INVALID, "PNG: resolution %g dpi out of range", o->dpi[a]);
    if (o->palette) {
        if (channels != 1)
            return hv_error_set(HV_ERR_INVALID, "PNG: a palette needs 1 channel (got %d)",
                                channels);
        if (o->palette_size < 1 || o->palette_size > 256)
            return hv_error_set(HV_ERR_INVALID, "PNG: palette of %d colours (1..256)",
                                o->palette_size);
        size_t st = stride ? stride : (size_t)width;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                if (pixels[(size_t)y * st + (size_t)x] >= o->palette_size)
                    return hv_error_set(
                        HV_ERR_INVALID, "PNG: pixel (%d, %d) has index %d beyond the %d-colour palette",
                        x, y, pixels[(size_t)y * st + (size_t)x], o->palette_size);
    }
    int depth = o->bit_depth ? o->bit_depth : 8;
    if (depth != 1 && depth != 2 && depth != 4 && depth != 8 && depth != 16)
        return hv_error_set(HV_ERR_INVALID, "PNG: bit depth %d (1, 2, 4, 8 or 16)", o->bit_depth);
    if (depth == 16 && o->palette)
        return hv_error_set(HV_ERR_INVALID, "PNG: a palette needs at most 8 bits (got 16)");
    if (depth < 8) {
        if (channels != 1)
            return hv_error_set(HV_ERR_INVALID, "PNG: bit depth %d needs 1 channel (got %d)", depth,
                                channels);
        if (o->palette && o->palette_size > (1 << depth))
            return hv_error_set(HV_ERR_INVALID, "PNG: a %d-colour palette needs more than %d bits",
                                o->palette_size, depth);
        size_t st = stride ? stride : (size_t)width;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                if (pixels[(size_t)y * st + (size_t)x] >> depth)
                    return hv_error_set(HV_ERR_INVALID,
                                        "PNG: pixel (%d, %d) value %d does not fit in %d bits", x,
                                        y, pixels[(size_t)y * st + (size_t)x], depth);
    }
    if (o->text_key) {
        size_t n = strlen(o->text_key);
        if (n < 1 || n > 79 || !o->text_value)
            return hv_error_set(HV_ERR_INVALID, "PNG: text key must be 1-79 bytes with a value");
    }
    return HV_OK;
}

/* ---- PNG on all threads: 8-bit images with the Sub filter on every row ----------------------
 * What libpng writes for them (PNG spec 9.2: each row a filter byte 1, then each byte less the
 * one a pixel before it), but the zlib stream made as pigz makes it: the filtered rows cut into
 * bands, each band deflated on its own thread as raw deflate primed with the 32 KiB before it
 * (deflateSetDictionary), every band but the last ending in a sync flush (a byte-aligned empty
 * stored block), so the bands joined are one deflate stream (RFC 1951); the zlib header before
 * it and the Adler-32 of all the rows after it (adler32_combine, RFC 1950). Chunks: IHDR, pHYs,
 * tEXt, one IDAT, IEND, each with its CRC-32. Any PNG decoder reads it as it reads libpng's. */

enum { PAR_MIN_PIXELS = 1 << 18, PAR_DICT = 32768 };

/* n bytes to the file or the memory buffer; 0 (status and message set) on failure. */
static int put(png_sink *s, const void *p, size_t n)
{
    if (s->fp) {
        if (fwrite(p, 1, n, s->fp) == n) return 1;
        s->status = HV_ERR_IO;
        snprintf(s->msg, sizeof s->msg, "write failed: %s", strerror(errno));
        return 0;
    }
    if (s->len + n > s->cap) {
        size_t cap = s->cap ? s->cap : 65536;
        while (cap < s->len + n) cap *= 2;
        uint8_t *m = realloc(s->mem, cap);
        if (!m) {
            s->status = HV_ERR_NOMEM;
            snprintf(s->msg, sizeof s->msg, "out of memory for a %zu-byte PNG", cap);
            return 0;
        }
        s->mem = m;
        s->cap = cap;
    }
    memcpy(s->mem + s->len, p, n);
    s->len += n;
    return 1;
}

static void be32(uint8_t *b, uint32_t v)
{
    b[0] = (uint8_t)(v >> 24);
    b[1] = (uint8_t)(v >> 16);
    b[2] = (uint8_t)(v >> 8);
    b[3] = (uint8_t)v;
}

/* A chunk whose data is the nparts pieces of `parts`, one after the other. */
static int put_chunk(png_sink *s, const char *type, const uint8_t *const *parts, const size_t *sizes, int nparts)
{
    uint8_t head[8], tail[4];
    size_t n = 0;
    for (int i = 0; i < nparts; ++i) n += sizes[i];
    be32(head, (uint32_t)n);
    memcpy(head + 4, type, 4);
    uLong crc = crc32(0L, head + 4, 4);
    for (int i = 0; i < nparts; ++i) crc = crc32_z(crc, parts[i], sizes[i]);
    be32(tail, (uint32_t)crc);
    if (!put(s, head, 8)) return 0;
    for (int i = 0; i < nparts; ++i)
        if (!put(s, parts[i], sizes[i])) return 0;
    return put(s, tail, 4);
}

typedef struct par_ctx {
    const uint8_t *pixels;
    size_t stride, rowbytes; /* source stride; filtered row: 1 + width * channels */
    int channels, height, bands, level;
    uint8_t *filtered;       /* height * rowbytes */
    uint8_t **out;           /* per band: its deflate output */
    size_t *len;
    size_t *in;              /* per band: its filtered bytes */
    uLong *adler;
} par_ctx;

static hv_status par_filter(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    const par_ctx *c = vctx;
    for (size_t y = b; y < e; ++y) {
        const uint8_t *src = c->pixels + y * c->stride;
        uint8_t *dst = c->filtered + y * c->rowbytes;
        dst[0] = 1; /* Sub */
        size_t n = c->rowbytes - 1, bpp = (size_t)c->channels;
        memcpy(dst + 1, src, bpp);
        for (size_t i = bpp; i < n; ++i) dst[1 + i] = (uint8_t)(src[i] - src[i - bpp]);
    }
    return HV_OK;
}

static hv_status par_deflate(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    const par_ctx *c = vctx;
    for (size_t k = b; k < e; ++k) {
        size_t y0 = (size_t)c->height * k / (size_t)c->bands, y1 = (size_t)c->height * (k + 1) / (size_t)c->bands;
        const uint8_t *in = c->filtered + y0 * c->rowbytes;
        size_t n = (y1 - y0) * c->rowbytes;
        z_stream z;
        memset(&z, 0, sizeof z);
        /* libpng's settings for filtered rows: 32 KiB window, memLevel 8, Z_FILTERED */
        if (deflateInit2(&z, c->level, Z_DEFLATED, -15, 8, Z_FILTERED) != Z_OK)
            return hv_error_set(HV_ERR_NOMEM, "PNG: out of memory for zlib");
        size_t cap = deflateBound(&z, (uLong)n) + 16;
        c->out[k] = hv_malloc(cap);
        int ok = c->out[k] != NULL;
        if (ok && k > 0) { /* the window the band before leaves */
            size_t d = y0 * c->rowbytes < PAR_DICT ? y0 * c->rowbytes : PAR_DICT;
            ok = deflateSetDictionary(&z, in - d, (uInt)d) == Z_OK;
        }
        z.next_in = (Bytef *)(uintptr_t)in;
        z.avail_in = (uInt)n;
        z.next_out = c->out[k];
        z.avail_out = (uInt)cap;
        int flush = k + 1 == (size_t)c->bands ? Z_FINISH : Z_SYNC_FLUSH;
        int r = ok ? deflate(&z, flush) : Z_MEM_ERROR;
        ok = flush == Z_FINISH ? r == Z_STREAM_END : r == Z_OK && z.avail_in == 0;
        c->len[k] = cap - z.avail_out;
        c->in[k] = n;
        c->adler[k] = adler32_z(1L, in, n);
        deflateEnd(&z);
        if (!ok) return hv_error_set(HV_ERR_NOMEM, "PNG: zlib failed on rows %zu to %zu", y0, y1);
    }
    return HV_OK;
}

static int par_suits(int width, int height, int channels, const hv_png_options *o)
{
    return o && o->filter_sub && (!o->bit_depth || o->bit_depth == 8) && !o->palette && hv_threads() > 1 &&
           (int64_t)width * height >= PAR_MIN_PIXELS && (uint64_t)height * (1 + (uint64_t)width * (uint64_t)channels) < (1u << 31) &&
           (!o->text_key || strlen(o->text_value) < (1u << 20));
}

static hv_status encode_parallel(png_sink *s, const uint8_t *pixels, int width, int height, int channels,
                                 size_t stride, const hv_png_options *o)
{
    par_ctx c;
    memset(&c, 0, sizeof c);
    c.pixels = pixels;
    c.channels = channels;
    c.height = height;
    c.rowbytes = 1 + (size_t)width * (size_t)channels;
    c.stride = stride ? stride : (size_t)width * (size_t)channels;
    c.level = o->compression >= 0 ? o->compression : Z_DEFAULT_COMPRESSION;
    c.bands = 2 * hv_threads();
    if (c.bands > height / 16) c.bands = height / 16 > 0 ? height / 16 : 1;
    c.filtered = hv_malloc_array((size_t)height, c.rowbytes);
    c.out = hv_calloc((size_t)c.bands, sizeof *c.out);
    c.len = hv_calloc((size_t)c.bands, sizeof *c.len);
    c.in = hv_calloc((size_t)c.bands, sizeof *c.in);
    /* the IDAT's pieces: the zlib header, the bands, the Adler-32 */
    const uint8_t **parts = hv_calloc((size_t)c.bands + 2, sizeof *parts);
    size_t *sizes = hv_calloc((size_t)c.bands + 2, sizeof *sizes);
    c.adler = hv_calloc((size_t)c.bands, sizeof *c.adler);
    hv_status st = c.filtered && c.out && c.len && c.in && c.adler && parts && sizes ? HV_OK : HV_ERR_NOMEM;
    if (st == HV_OK) st = hv_parallel_for((size_t)height, 64, par_filter, &c, NULL, NULL);
    if (st == HV_OK) st = hv_parallel_for((size_t)c.bands, 1, par_deflate, &c, NULL, NULL);
    if (st == HV_OK) {
        static const uint8_t sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
        uint8_t ihdr[13], phys[9], zhead[2], ztail[4];
        be32(ihdr, (uint32_t)width);
        be32(ihdr + 4, (uint32_t)height);
        ihdr[8] = 8;
        ihdr[9] = channels == 1 ? 0 : channels == 2 ? 4 : channels == 3 ? 2 : 6;
        ihdr[10] = ihdr[11] = ihdr[12] = 0;
        /* zlib header: deflate with a 32 KiB window, the level class, no dictionary */
        int flevel = c.level == Z_DEFAULT_COMPRESSION ? 2 : c.level < 2 ? 0 : c.level < 6 ? 1 : c.level == 6 ? 2 : 3;
        zhead[0] = 0x78;
        zhead[1] = (uint8_t)(flevel << 6);
        zhead[1] = (uint8_t)(zhead[1] + 31 - (zhead[0] * 256 + zhead[1]) % 31);
        uLong adler = c.adler[0];
        for (int k = 1; k < c.bands; ++k) adler = adler32_combine(adler, c.adler[k], (z_off_t)c.in[k]);
        be32(ztail, (uint32_t)adler);
        const uint8_t *p1[1] = {ihdr};
        size_t n1[1] = {13};
        int ok = put(s, sig, 8) && put_chunk(s, "IHDR", p1, n1, 1);
        if (ok && (o->dpi[0] > 0 || o->dpi[1] > 0)) {
            double dx = o->dpi[0] > 0 ? o->dpi[0] : o->dpi[1], dy = o->dpi[1] > 0 ? o->dpi[1] : o->dpi[0];
            be32(phys, (uint32_t)(dx / 0.0254 + 0.5));
            be32(phys + 4, (uint32_t)(dy / 0.0254 + 0.5));
            phys[8] = 1; /* metres */
            const uint8_t *pp[1] = {phys};
            size_t np[1] = {9};
            ok = put_chunk(s, "pHYs", pp, np, 1);
        }
        if (ok && o->text_key) {
            const uint8_t *pt[3] = {(const uint8_t *)o->text_key, (const uint8_t *)"", (const uint8_t *)o->text_value};
            size_t nt[3] = {strlen(o->text_key), 1, strlen(o->text_value)};
            ok = put_chunk(s, "tEXt", pt, nt, 3);
        }
        parts[0] = zhead;
        sizes[0] = 2;
        for (int k = 0; k < c.bands; ++k) {
            parts[k + 1] = c.out[k];
            sizes[k + 1] = c.len[k];
        }
        parts[c.bands + 1] = ztail;
        sizes[c.bands + 1] = 4;
        ok = ok && put_chunk(s, "IDAT", parts, sizes, c.bands + 2);
        ok = ok && put_chunk(s, "IEND", NULL, NULL, 0);
        if (!ok) st = hv_error_set(s->status, "PNG: %s", s->msg);
    }
    for (int k = 0; c.out && k < c.bands; ++k) free(c.out[k]);
    free(c.out);
    free(c.len);
    free(c.in);
    free(c.adler);
    free(parts);
    free(sizes);
    free(c.filtered);
    return st;
}

/* libpng reports errors by longjmp; everything it needs to clean up lives in *s and the two
 * structs, which are not modified between setjmp and the jump. */
static hv_status encode(png_sink *s, const uint8_t *pixels, int width, int height, int channels,
                        size_t stride, const hv_png_options *o)
{
    if (par_suits(width, height, channels, o)) return encode_parallel(s, pixels, width, height, channels, stride, o);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, s, sink_error, sink_warning);
    if (!png) return hv_error_set(HV_ERR_NOMEM, "PNG: out of memory");
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, NULL);
        return hv_error_set(HV_ERR_NOMEM, "PNG: out of memory");
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return hv_error_set(s->status, "PNG: %s", s->msg);
    }
    png_set_user_limits(png, 0x7fffffff, 0x7fffffff);
    png_set_write_fn(png, s, sink_write, sink_flush);
    int type = channels == 1 ? (o && o->palette ? PNG_COLOR_TYPE_PALETTE : PNG_COLOR_TYPE_GRAY)
               : channels == 2 ? PNG_COLOR_TYPE_GRAY_ALPHA
               : channels == 3 ? PNG_COLOR_TYPE_RGB
                               : PNG_COLOR_TYPE_RGB_ALPHA;
    int depth = o && o->bit_depth ? o->bit_depth : 8;
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, depth, type,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (o && o->palette) {
        png_color pal[256];
        for (int i = 0; i < o->palette_size; ++i) {
            pal[i].red = o->palette[3 * i];
            pal[i].green = o->palette[3 * i + 1];
            pal[i].blue = o->palette[3 * i + 2];
        }
        png_set_PLTE(png, info, pal, o->palette_size);
    }
    if (o && (o->dpi[0] > 0 || o->dpi[1] > 0)) {
        double dx = o->dpi[0] > 0 ? o->dpi[0] : o->dpi[1];
        double dy = o->dpi[1] > 0 ? o->dpi[1] : o->dpi[0];
        png_set_pHYs(png, info, (png_uint_32)(dx / 0.0254 + 0.5), (png_uint_32)(dy / 0.0254 + 0.5),
                     PNG_RESOLUTION_METER);
    }
    if (o && o->text_key) {
        png_text t;
        memset(&t, 0, sizeof t);
        t.compression = PNG_TEXT_COMPRESSION_NONE;
        t.key = (png_charp)(uintptr_t)o->text_key;
        t.text = (png_charp)(uintptr_t)o->text_value;
        png_set_text(png, info, &t, 1);
    }
    if (o && o->compression >= 0) png_set_compression_level(png, o->compression);
    if (o && o->filter_sub) png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_write_info(png, info);
    /* rows stay one pixel per byte; set after png_write_info, which resets the user depth */
    if (depth < 8) png_set_packing(png);
    size_t st = stride ? stride : (size_t)width * (size_t)channels * (depth == 16 ? 2u : 1u);
    for (int y = 0; y < height; ++y) png_write_row(png, pixels + (size_t)y * st);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return HV_OK;
}

hv_status hv_png_encode(const uint8_t *pixels, int width, int height, int channels, size_t stride,
                        const hv_png_options *opt, uint8_t **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    hv_status st = check_png_args(pixels, width, height, channels, stride, opt);
    if (st != HV_OK) return st;
    png_sink s;
    memset(&s, 0, sizeof s);
    st = encode(&s, pixels, width, height, channels, stride, opt);
    if (st != HV_OK) {
        free(s.mem);
        return st;
    }
    *data = s.mem;
    *size = s.len;
    return HV_OK;
}

hv_status hv_png_write(const char *path, const uint8_t *pixels, int width, int height, int channels,
                       size_t stride, const hv_png_options *opt)
{
    hv_status st = check_png_args(pixels, width, height, channels, stride, opt);
    if (st != HV_OK) return st;
    png_sink s;
    memset(&s, 0, sizeof s);
    if (opt && opt->in_place) { /* inside a directory renamed whole: no temporary, no sync */
        if (!(s.fp = fopen(path, "wb"))) return hv_error_set(HV_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
        st = encode(&s, pixels, width, height, channels, stride, opt);
        int e = errno, bad = st == HV_OK && (ferror(s.fp) || fflush(s.fp) != 0);
        bad |= fclose(s.fp) != 0 && st == HV_OK;
        if (st == HV_OK && bad) st = hv_error_set(HV_ERR_IO, "%s: write failed: %s", path, strerror(e ? e : errno));
        else if (st != HV_OK) hv_error_prefix(st, "%s: ", path);
        if (st != HV_OK) remove(path);
        return st;
    }
    hv_atomic_file af;
    st = hv_atomic_open(&af, path, "wb");
    if (st != HV_OK) return st;
    s.fp = af.fp;
    st = encode(&s, pixels, width, height, channels, stride, opt);
    if (st != HV_OK) {
        hv_atomic_abort(&af);
        return hv_error_prefix(st, "%s: ", path);
    }
    return hv_atomic_commit(&af);
}

/* ---- PNG in ------------------------------------------------------------------------------- */

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
