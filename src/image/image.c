/* src/image/image.c - the image module (hovox/image.h): float RGBA images, PNG written through
 * libdeflate (grey, grey+alpha, RGB, RGBA, indexed, 1 to 16 bits; pHYs resolution; to a file
 * atomically or to memory) and read through libpng (untrusted PNGs from memory), and EXR/TIFF through the OpenImageIO bridge
 * plugin, loaded only when asked for. */
#include <errno.h>
#include <libdeflate.h>
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

/* ---- PNG -------------------------------------------------------------------------------- */

void hv_png_options_init(hv_png_options *o)
{
    memset(o, 0, sizeof *o);
    o->compression = -1;
}

/* libpng's decoder never prints either */
static void sink_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

/* Bytes in one row of PNG samples: width pixels of `channels` samples of `depth` bits, packed
 * (PNG spec 7.2). */
static size_t png_rowbytes(int width, int channels, int depth)
{
    return ((size_t)width * (size_t)channels * (size_t)depth + 7) / 8;
}

/* The sample (index or grey value) of pixel x in a row packed at `depth` bits, most significant
 * bits first. */
static unsigned packed_at(const uint8_t *row, int x, int depth)
{
    int per = 8 / depth;
    return (unsigned)(row[x / per] >> (8 - depth - depth * (x % per))) & ((1u << depth) - 1);
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
    int packed = o && o->packed && o->bit_depth > 0 && o->bit_depth < 8;
    size_t minrow = packed ? png_rowbytes(width, channels, o->bit_depth) : (size_t)width * (size_t)channels * bps;
    if (stride && stride < minrow)
        return hv_error_set(HV_ERR_INVALID, "PNG: row stride %zu is less than the %zu bytes of a row",
                            stride, minrow);
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
        size_t st = stride ? stride : minrow;
        /* packed rows: every index fits the depth, so only a palette shorter than 2^depth is checked;
         * a whole byte at a time through a table of the byte values whose indices all lie in the
         * palette (a J750 plate is 53 M pixels a layer), pixel by pixel only to name the first bad
         * one and for a packed row's last, partial byte */
        if (!packed || o->palette_size < (1 << o->bit_depth)) {
            int bd = packed ? o->bit_depth : 8, per = 8 / bd;
            if (8 % bd) /* not a PNG depth: refused below, before a row is read */
                per = 0;
            unsigned mask = (1u << bd) - 1u;
            uint8_t ok[256];
            for (unsigned b = 0; b < 256; ++b) {
                ok[b] = 1;
                for (int k = 0; k < per; ++k)
                    if (((b >> (k * bd)) & mask) >= (unsigned)o->palette_size) ok[b] = 0;
            }
            size_t whole = per ? (size_t)width / (size_t)per : 0; /* bytes whose every index is a pixel */
            for (int y = 0; y < height && per; ++y) {
                const uint8_t *row = pixels + (size_t)y * st;
                int x0 = -1;
                for (size_t i = 0; i < whole && x0 < 0; ++i)
                    if (!ok[row[i]]) x0 = (int)(i * (size_t)per);
                if (x0 < 0) x0 = (int)(whole * (size_t)per);
                for (int x = x0; x < width && x < x0 + per; ++x) {
                    unsigned v = packed ? packed_at(row, x, bd) : row[x];
                    if (v >= (unsigned)o->palette_size)
                        return hv_error_set(HV_ERR_INVALID,
                                            "PNG: pixel (%d, %d) has index %u beyond the %d-colour palette", x, y,
                                            v, o->palette_size);
                }
            }
        }
    }
    int depth = o->bit_depth ? o->bit_depth : 8;
    if (depth != 1 && depth != 2 && depth != 4 && depth != 8 && depth != 16)
        return hv_error_set(HV_ERR_INVALID, "PNG: bit depth %d (1, 2, 4, 8 or 16)", o->bit_depth);
    if (depth == 16 && o->palette)
        return hv_error_set(HV_ERR_INVALID, "PNG: a palette needs at most 8 bits (got 16)");
    if (o->packed && depth >= 8)
        return hv_error_set(HV_ERR_INVALID, "PNG: packed rows need a bit depth of 1, 2 or 4 (got %d)", depth);
    if (depth < 8) {
        if (channels != 1)
            return hv_error_set(HV_ERR_INVALID, "PNG: bit depth %d needs 1 channel (got %d)", depth,
                                channels);
        if (o->palette && o->palette_size > (1 << depth))
            return hv_error_set(HV_ERR_INVALID, "PNG: a %d-colour palette needs more than %d bits",
                                o->palette_size, depth);
        size_t st = stride ? stride : (size_t)width;
        for (int y = 0; y < height && !packed; ++y)
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

/* ---- PNG out: the one encoder --------------------------------------------------------------
 * Every PNG hovox writes (slice stacks, trays, renders, the viewer's pages, 3MF image stacks)
 * comes from here: rows filtered (PNG spec 9), the whole image deflated in one call by libdeflate
 * into a zlib stream (RFC 1950), chunks IHDR, PLTE, pHYs, tEXt, IDAT (in 1 MiB pieces), IEND with
 * their CRC-32. Chosen by `make bench` (scripts/bench/98-png.sh: libpng, libspng, this writer and
 * a hand-written Huffman coder on the bench tray's layers). Filters: None for indexed and sub-byte
 * images (PNG spec 12.8: filtering does not help them), Sub on every row with opt->filter_sub,
 * otherwise per row the filter of least sum of absolute differences (libpng's heuristic). */

enum { IDAT_PIECE = 1 << 20 };

static void be32(uint8_t *b, uint32_t v)
{
    b[0] = (uint8_t)(v >> 24);
    b[1] = (uint8_t)(v >> 16);
    b[2] = (uint8_t)(v >> 8);
    b[3] = (uint8_t)v;
}

/* Frames the n data bytes already at at + 8 as a chunk (length, type, data, CRC-32 of type and
 * data); returns the end. */
static uint8_t *frame_chunk(uint8_t *at, const char *type, size_t n)
{
    be32(at, (uint32_t)n);
    memcpy(at + 4, type, 4);
    be32(at + 8 + n, (uint32_t)libdeflate_crc32(0, at + 4, 4 + n));
    return at + 12 + n;
}

static uint8_t *put_chunk(uint8_t *at, const char *type, const uint8_t *data, size_t n)
{
    if (n) memcpy(at + 8, data, n);
    return frame_chunk(at, type, n);
}

static inline int paeth(int a, int b, int c)
{
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* Row `cur` (n bytes, bpp bytes a pixel, `prev` the row above or NULL) filtered with filter f
 * into out[0..n]: the filter byte, then the filtered bytes. Returns libpng's cost, the sum of
 * the filtered bytes read as signed. */
static unsigned long filter_row(int f, const uint8_t *cur, const uint8_t *prev, size_t n, size_t bpp, uint8_t *out)
{
    out[0] = (uint8_t)f;
    uint8_t *d = out + 1;
    unsigned long cost = 0;
    for (size_t i = 0; i < n; ++i) {
        int a = i >= bpp ? cur[i - bpp] : 0, b = prev ? prev[i] : 0, c = prev && i >= bpp ? prev[i - bpp] : 0;
        int p = f == 0 ? 0 : f == 1 ? a : f == 2 ? b : f == 3 ? (a + b) / 2 : paeth(a, b, c);
        d[i] = (uint8_t)(cur[i] - p);
        cost += (unsigned long)(d[i] < 128 ? d[i] : 256 - d[i]);
    }
    return cost;
}

/* Row y of the image in PNG's packing (sub-byte samples packed from one a byte unless
 * opt->packed), into row[0..rowbytes). */
static const uint8_t *png_row(const uint8_t *pixels, size_t stride, int y, int width, int depth, int packed,
                              uint8_t *row, size_t rowbytes)
{
    const uint8_t *src = pixels + (size_t)y * stride;
    if (depth >= 8 || packed) return src;
    memset(row, 0, rowbytes);
    int per = 8 / depth;
    for (int x = 0; x < width; ++x) row[x / per] |= (uint8_t)(src[x] << (8 - depth - depth * (x % per)));
    return row;
}

static hv_status encode(const uint8_t *pixels, int width, int height, int channels, size_t stride,
                        const hv_png_options *o, uint8_t **data, size_t *size)
{
    int depth = o && o->bit_depth ? o->bit_depth : 8;
    int packed = o && o->packed && depth < 8;
    size_t rowbytes = png_rowbytes(width, channels, depth);
    size_t bpp = depth < 8 ? 1 : (size_t)channels * (size_t)depth / 8;
    if (!stride) stride = depth < 8 && !packed ? (size_t)width : rowbytes;
    int fixed = o && o->palette ? 0 : depth < 8 ? 0 : o && o->filter_sub ? 1 : -1; /* -1: per row */
    uint64_t nraw = (uint64_t)height * (1 + (uint64_t)rowbytes);
    if (nraw > ((uint64_t)1 << 40))
        return hv_error_set(HV_ERR_LIMIT, "PNG: an image of %d x %d pixels is too large to write", width, height);
    uint8_t *raw = hv_malloc_big((size_t)nraw, 1);
    uint8_t *tmp = hv_malloc(5 * (rowbytes + 1) + rowbytes);
    int level = o && o->compression >= 0 ? o->compression : 6;
    struct libdeflate_compressor *z = libdeflate_alloc_compressor(level);
    hv_status st = raw && tmp && z ? HV_OK : hv_error_set(HV_ERR_NOMEM, "PNG: out of memory for a %d x %d image", width, height);
    uint8_t *out = NULL;
    if (st == HV_OK) {
        uint8_t *unpacked = tmp + 5 * (rowbytes + 1);
        const uint8_t *prev = NULL; /* the row above (only filters other than None read it: 8 bits and up) */
        for (int y = 0; y < height; ++y) {
            uint8_t *dst = raw + (size_t)y * (1 + rowbytes);
            const uint8_t *cur = png_row(pixels, stride, y, width, depth, packed, unpacked, rowbytes);
            if (fixed == 0) {
                dst[0] = 0;
                memcpy(dst + 1, cur, rowbytes);
            } else if (fixed == 1) {
                filter_row(1, cur, prev, rowbytes, bpp, dst);
            } else { /* the least sum of absolute differences among the five */
                unsigned long best = (unsigned long)-1;
                int bf = 0;
                for (int f = 0; f < 5; ++f) {
                    unsigned long c = filter_row(f, cur, prev, rowbytes, bpp, tmp + (size_t)f * (rowbytes + 1));
                    if (c < best) best = c, bf = f;
                }
                memcpy(dst, tmp + (size_t)bf * (rowbytes + 1), rowbytes + 1);
            }
            prev = cur;
        }
        size_t zcap = libdeflate_zlib_compress_bound(z, (size_t)nraw);
        size_t npieces = zcap / IDAT_PIECE + 1;
        size_t textn = o && o->text_key ? strlen(o->text_key) + 1 + strlen(o->text_value) : 0;
        size_t cap = 8 + 25 + (12 + 768) + 21 + (12 + textn) + zcap + 12 * npieces + 12;
        out = hv_malloc_big(cap, 1);
        size_t zlen = out ? libdeflate_zlib_compress(z, raw, (size_t)nraw, out + cap - zcap, zcap) : 0;
        if (!out) st = hv_error_set(HV_ERR_NOMEM, "PNG: out of memory for a %zu-byte PNG", cap);
        else if (!zlen) st = hv_error_set(HV_ERR_INTERNAL, "PNG: libdeflate could not compress the image");
        else {
            static const uint8_t sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
            uint8_t ihdr[13], phys[9], *at = out + 8;
            memcpy(out, sig, 8);
            be32(ihdr, (uint32_t)width);
            be32(ihdr + 4, (uint32_t)height);
            ihdr[8] = (uint8_t)depth;
            ihdr[9] = o && o->palette ? 3 : channels == 1 ? 0 : channels == 2 ? 4 : channels == 3 ? 2 : 6;
            ihdr[10] = ihdr[11] = ihdr[12] = 0;
            at = put_chunk(at, "IHDR", ihdr, 13);
            if (o && o->palette) at = put_chunk(at, "PLTE", o->palette, 3 * (size_t)o->palette_size);
            if (o && (o->dpi[0] > 0 || o->dpi[1] > 0)) {
                double dx = o->dpi[0] > 0 ? o->dpi[0] : o->dpi[1], dy = o->dpi[1] > 0 ? o->dpi[1] : o->dpi[0];
                be32(phys, (uint32_t)(dx / 0.0254 + 0.5));
                be32(phys + 4, (uint32_t)(dy / 0.0254 + 0.5));
                phys[8] = 1; /* metres */
                at = put_chunk(at, "pHYs", phys, 9);
            }
            if (textn) { /* key, a zero byte, the text (Latin-1, not terminated) */
                size_t kn = strlen(o->text_key);
                memcpy(at + 8, o->text_key, kn);
                at[8 + kn] = 0;
                memcpy(at + 9 + kn, o->text_value, textn - kn - 1);
                at = frame_chunk(at, "tEXt", textn);
            }
            /* the zlib stream sits at the end of the buffer; its IDAT pieces move down in order,
             * each to a place before its source (12 bytes of chunk framing a piece behind) */
            const uint8_t *zs = out + cap - zcap;
            for (size_t done = 0; done < zlen;) {
                size_t n = zlen - done < IDAT_PIECE ? zlen - done : IDAT_PIECE;
                memmove(at + 8, zs + done, n);
                at = frame_chunk(at, "IDAT", n);
                done += n;
            }
            at = put_chunk(at, "IEND", NULL, 0);
            *size = (size_t)(at - out);
        }
    }
    libdeflate_free_compressor(z);
    free(raw);
    free(tmp);
    if (st != HV_OK) free(out);
    else *data = out;
    return st;
}

hv_status hv_png_encode(const uint8_t *pixels, int width, int height, int channels, size_t stride,
                        const hv_png_options *opt, uint8_t **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    hv_status st = check_png_args(pixels, width, height, channels, stride, opt);
    if (st != HV_OK) return st;
    return encode(pixels, width, height, channels, stride, opt, data, size);
}

hv_status hv_png_write(const char *path, const uint8_t *pixels, int width, int height, int channels,
                       size_t stride, const hv_png_options *opt)
{
    uint8_t *png = NULL;
    size_t size = 0;
    hv_status st = check_png_args(pixels, width, height, channels, stride, opt);
    if (st == HV_OK && (st = encode(pixels, width, height, channels, stride, opt, &png, &size)) != HV_OK)
        return hv_error_prefix(st, "%s: ", path);
    if (st != HV_OK) return st;
    /* in_place: inside a directory renamed whole, so no temporary and no sync */
    st = opt && opt->in_place ? hv_write_in_place(path, png, size) : hv_atomic_write(path, png, size);
    free(png);
    return st;
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
