/* src/image/png.c - the one PNG encoder (hovox/image.h: hv_png_encode, hv_png_write): every PNG
 * hovox writes comes from here. Two ways to the zlib stream inside, picked per image by its content:
 * libdeflate on the filtered rows, or for a sparse layer (an indexed or sub-byte image whose nonzero
 * bytes are under a quarter of it: small parts on a printer plate) one dynamic-Huffman block coded
 * here (RFC 1951 3.2.5-3.2.7) whose cost is the nonzero bytes: copies at the few distances the
 * image repeats at, literals between. Chunks after ISO/IEC 15948. */
#include <libdeflate.h>
#include <pthread.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/image.h"

void hv_png_options_init(hv_png_options *o)
{
    memset(o, 0, sizeof *o);
    o->compression = -1;
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

/* The bytes [*lo, *hi) of row y (n bytes as given) that may be nonzero: opt->row_spans's, or all. */
static void row_range(const hv_png_options *o, int y, size_t n, size_t *lo, size_t *hi)
{
    *lo = 0;
    *hi = n;
    if (!o || !o->row_spans) return;
    *lo = (size_t)HV_CLAMP(o->row_spans[2 * y], 0, (int64_t)n);
    *hi = (size_t)HV_CLAMP(o->row_spans[2 * y + 1], (int64_t)*lo, (int64_t)n);
}

/* ok[b]: whether every index in a byte b of the row as given (per indices of bd bits) lies in a
 * palette of n colours. */
static void palette_table(int bd, int per, int n, uint8_t ok[256])
{
    unsigned mask = (1u << bd) - 1u;
    for (unsigned b = 0; b < 256; ++b) {
        ok[b] = 1;
        for (int k = 0; k < per; ++k)
            if (((b >> (k * bd)) & mask) >= (unsigned)n) ok[b] = 0;
    }
}

/* The first pixel of row y from x0 on (at most per of them, below width) whose index lies beyond
 * the palette, named in the error; HV_OK if none. */
static hv_status bad_index(const uint8_t *row, int y, int x0, int per, int bd, int packed, int width, int n)
{
    for (int x = x0; x < width && x < x0 + per; ++x) {
        unsigned v = packed ? packed_at(row, x, bd) : row[x];
        if (v >= (unsigned)n)
            return hv_error_set(HV_ERR_INVALID, "PNG: pixel (%d, %d) has index %u beyond the %d-colour palette", x, y,
                                v, n);
    }
    return HV_OK;
}

/* Whether a packed index in the bytes p[0 .. n) (bd bits each, bd 1, 2 or 4) is npal or more
 * (npal < 2^bd): eight bytes at a time, each index moved into a byte lane of its own and
 * 128 - npal added, so a lane's top bit is set exactly when its index is npal or more (at most
 * 15 + 127: no carry between lanes). A 4-bit plate's bytes at a few times the speed of a table
 * look-up a byte. */
static inline __attribute__((always_inline)) int packed_beyond(const uint8_t *p, size_t n, int bd, int npal)
{
    const uint64_t ones = 0x0101010101010101ull, lane = ones * ((1u << bd) - 1u), add = ones * (uint64_t)(128 - npal);
    uint64_t acc = 0;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w;
        memcpy(&w, p + i, 8);
        for (int k = 0; k < 8; k += bd) acc |= ((w >> k) & lane) + add;
    }
    if (i < n) {
        uint64_t w = 0; /* the tail in a word of zeros: index 0 is always in the palette */
        memcpy(&w, p + i, n - i);
        for (int k = 0; k < 8; k += bd) acc |= ((w >> k) & lane) + add;
    }
    return (acc & ones * 0x80u) != 0;
}

static int packed_row_beyond(const uint8_t *p, size_t n, int bd, int npal)
{
    switch (bd) {
    case 1: return packed_beyond(p, n, 1, npal);
    case 2: return packed_beyond(p, n, 2, npal);
    default: return packed_beyond(p, n, 4, npal);
    }
}

/* Every index in the rows (the bytes row_range gives) within opt->palette: packed rows through
 * packed_row_beyond, 8-bit indices a byte at a time through palette_table (a J750 plate is 53 M
 * pixels a layer); pixel by pixel only to name the first bad one and for a packed row's last,
 * partial byte. Packed rows: every index fits the depth, so only a palette shorter than 2^depth
 * is checked. */
static hv_status check_palette_pixels(const uint8_t *pixels, int width, int height, size_t stride,
                                      const hv_png_options *o)
{
    int packed = o->packed && o->bit_depth > 0 && o->bit_depth < 8;
    size_t minrow = packed ? png_rowbytes(width, 1, o->bit_depth) : (size_t)width;
    size_t st = stride ? stride : minrow;
    if (packed && o->palette_size >= (1 << o->bit_depth)) return HV_OK;
    int bd = packed ? o->bit_depth : 8, per = 8 % bd ? 0 : 8 / bd; /* not a PNG depth: refused later */
    uint8_t ok[256];
    palette_table(bd, per, o->palette_size, ok);
    size_t whole = per ? (size_t)width / (size_t)per : 0; /* bytes whose every index is a pixel */
    for (int y = 0; y < height && per; ++y) {
        const uint8_t *row = pixels + (size_t)y * st;
        size_t lo, hi, i; /* bytes outside are zero: index 0 */
        row_range(o, y, minrow, &lo, &hi);
        if (packed && !packed_row_beyond(row + lo, HV_MIN(hi, whole) - HV_MIN(lo, whole), bd, o->palette_size))
            lo = HV_MAX(lo, HV_MIN(hi, whole)); /* all good up to the partial byte */
        for (i = lo; i < hi && i < whole && ok[row[i]]; ++i) {}
        hv_status bad = bad_index(row, y, (int)(HV_MIN(i, whole) * (size_t)per), per, bd, packed, width, o->palette_size);
        if (bad != HV_OK) return bad;
    }
    return HV_OK;
}

/* Whether encode checks the palette's indices (rows read as they are: packed, or 8 bits): the
 * span coder on its literals (every other byte it writes is a zero or a copy of an earlier one),
 * else a scan before libdeflate. A sparse layer's bytes are then read once, not twice. */
static int check_here(const hv_png_options *o)
{
    return o && o->palette && (o->bit_depth == 0 || o->bit_depth == 8 || (o->packed && o->bit_depth > 0 && o->bit_depth < 8));
}

/* The arguments; the palette's indices in the pixels too unless !scan (encode checks them). */
static hv_status check_png_args(const uint8_t *pixels, int width, int height, int channels,
                                size_t stride, const hv_png_options *o, int scan)
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
        if (scan) {
            hv_status bad = check_palette_pixels(pixels, width, height, stride, o);
            if (bad != HV_OK) return bad;
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
        for (int y = 0; y < height && !packed; ++y) {
            size_t lo, hi;
            row_range(o, y, (size_t)width, &lo, &hi);
            for (int x = (int)lo; x < (int)hi; ++x)
                if (pixels[(size_t)y * st + (size_t)x] >> depth)
                    return hv_error_set(HV_ERR_INVALID,
                                        "PNG: pixel (%d, %d) value %d does not fit in %d bits", x,
                                        y, pixels[(size_t)y * st + (size_t)x], depth);
        }
    }
    if (o->text_key) {
        size_t n = strlen(o->text_key);
        if (n < 1 || n > 79 || !o->text_value)
            return hv_error_set(HV_ERR_INVALID, "PNG: text key must be 1-79 bytes with a value");
    }
    return HV_OK;
}

/* ---- PNG out -----------------------------------------------------------------------------------
 * Every PNG hovox writes (slice stacks, trays, renders, the viewer's pages, 3MF image stacks)
 * comes from hv_png_encode, one zlib stream (RFC 1950) in chunks IHDR, PLTE, pHYs, tEXt, IDAT (in
 * 1 MiB pieces), IEND with their CRC-32. The stream is made one of two ways, chosen by `make bench`
 * (scripts/bench/98-png.sh: libpng, libspng, libdeflate and the span coder on the bench tray's and
 * the README tray's layers, and both trays end to end):
 * - libdeflate on the filtered rows, the whole image in one call. Filters: None for indexed and
 *   sub-byte images (PNG spec 12.8: filtering does not help them), Sub on every row with
 *   opt->filter_sub, otherwise per row the filter of least sum of absolute differences (libpng's).
 * - the span coder, for a sparse layer: an indexed or sub-byte image whose nonzero bytes (the
 *   spans from the first to the last nonzero byte of each row) are under a quarter of its bytes.
 *   libdeflate reads every byte (a J750 plate is 26 MB a layer at 4 bits, mostly blank around small
 *   parts); the span coder reads only the spans, writes a blank row as a few bits and the halftone
 *   inside as copies one threshold tile back (or from another copy of the part) and literals: on
 *   the README's tray 0.85 of libdeflate's bytes at a quarter of its time (literals alone were
 *   3.4 times its bytes). Dense images go to libdeflate (the same bytes as before the copies). */

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

/* Bytes of a PNG around a zlib stream of zlen bytes, at most. */
static size_t frame_bound(const hv_png_options *o, size_t zlen)
{
    size_t textn = o && o->text_key ? strlen(o->text_key) + 1 + strlen(o->text_value) : 0;
    return 8 + 25 + (12 + 768) + 21 + (12 + textn) + zlen + 12 * (zlen / IDAT_PIECE + 1) + 12;
}

/* The PNG of the zlib stream zs[0..zlen) into out (frame_bound bytes); zs may lie inside out at
 * or after out + frame_bound - zlen (each IDAT piece moves down, before its source). Returns the
 * size. */
static size_t frame_png(uint8_t *out, int width, int height, int channels, int depth, const hv_png_options *o,
                        const uint8_t *zs, size_t zlen)
{
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
    if (o && o->text_key) { /* key, a zero byte, the text (Latin-1, not terminated) */
        size_t kn = strlen(o->text_key), vn = strlen(o->text_value);
        memcpy(at + 8, o->text_key, kn);
        at[8 + kn] = 0;
        memcpy(at + 9 + kn, o->text_value, vn);
        at = frame_chunk(at, "tEXt", kn + 1 + vn);
    }
    for (size_t done = 0; done < zlen;) {
        size_t n = zlen - done < IDAT_PIECE ? zlen - done : IDAT_PIECE;
        memmove(at + 8, zs + done, n);
        at = frame_chunk(at, "IDAT", n);
        done += n;
    }
    at = put_chunk(at, "IEND", NULL, 0);
    return (size_t)(at - out);
}

/* ---- libdeflate --------------------------------------------------------------------------------- */

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

static hv_status encode_deflate(const uint8_t *pixels, int width, int height, int channels, size_t stride,
                                const hv_png_options *o, uint8_t **data, size_t *size)
{
    int depth = o && o->bit_depth ? o->bit_depth : 8;
    int packed = o && o->packed && depth < 8;
    size_t rowbytes = png_rowbytes(width, channels, depth);
    size_t bpp = depth < 8 ? 1 : (size_t)channels * (size_t)depth / 8;
    int fixed = o && o->palette ? 0 : depth < 8 ? 0 : o && o->filter_sub ? 1 : -1; /* -1: per row */
    uint64_t nraw = (uint64_t)height * (1 + (uint64_t)rowbytes);
    if (nraw > ((uint64_t)1 << 40))
        return hv_error_set(HV_ERR_LIMIT, "PNG: an image of %d x %d pixels is too large to write", width, height);
    /* rows that already lie as the compressor takes them: each after its zero filter byte */
    int direct = fixed == 0 && o && o->filter_bytes && (depth >= 8 || packed) && stride == rowbytes + 1;
    for (int y = 0; y < height && direct; ++y) direct = (pixels - 1)[(size_t)y * stride] == 0;
    uint8_t *raw = direct ? NULL : hv_malloc_big((size_t)nraw, 1);
    uint8_t *tmp = direct ? NULL : hv_malloc(5 * (rowbytes + 1) + rowbytes);
    const uint8_t *in = direct ? pixels - 1 : raw;
    int level = o && o->compression >= 0 ? o->compression : 6;
    struct libdeflate_compressor *z = libdeflate_alloc_compressor(level);
    hv_status st = (direct || (raw && tmp)) && z ? HV_OK : hv_error_set(HV_ERR_NOMEM, "PNG: out of memory for a %d x %d image", width, height);
    uint8_t *out = NULL;
    if (st == HV_OK && !direct) {
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
    }
    if (st == HV_OK) {
        size_t zcap = libdeflate_zlib_compress_bound(z, (size_t)nraw), cap = frame_bound(o, zcap);
        out = hv_malloc_big(cap, 1);
        /* the zlib stream at the end of the buffer: frame_png moves its pieces down */
        size_t zlen = out ? libdeflate_zlib_compress(z, in, (size_t)nraw, out + cap - zcap, zcap) : 0;
        if (!out) st = hv_error_set(HV_ERR_NOMEM, "PNG: out of memory for a %zu-byte PNG", cap);
        else if (!zlen) st = hv_error_set(HV_ERR_INTERNAL, "PNG: libdeflate could not compress the image");
        else *size = frame_png(out, width, height, channels, depth, o, out + cap - zcap, zlen);
    }
    libdeflate_free_compressor(z);
    free(raw);
    free(tmp);
    if (st != HV_OK) free(out);
    else *data = out;
    return st;
}

/* ---- the span coder ------------------------------------------------------------------------------
 * One dynamic-Huffman block (RFC 1951 3.2.7) whose codes are fitted to the image: pass 1 counts the
 * symbols, pass 2 writes them. Zero stretches become copies of length 258 at distance 1, so a
 * blank row costs a few bits and, its span empty, no reading. Inside the spans, LZ77 (RFC 1951
 * 2.1, 3.2.5) without a search: copies are tried at distance 1 and at the few distances found to
 * repeat the drawn bytes (find_near: a halftone's tile, its multiples, the gap between copies of a
 * part), the longest taken greedily, literals between. The bytes depend only on the pixels (not on
 * the spans given, which only say where the zeros are). */

typedef struct bits {
    uint8_t *buf;
    size_t len, cap;
    uint64_t acc;
    int n;
    int failed;
} bits;

static void bits_reserve(bits *b, size_t more)
{
    if (b->failed || b->len + more <= b->cap) return;
    size_t cap = b->cap ? b->cap : 1 << 16;
    while (cap < b->len + more) cap *= 2;
    uint8_t *p = realloc(b->buf, cap);
    if (!p) {
        b->failed = 1;
        return;
    }
    b->buf = p;
    b->cap = cap;
}

static inline void put(bits *b, uint32_t code, int len)
{
    b->acc |= (uint64_t)code << b->n;
    b->n += len;
    if (b->n >= 32) {
        bits_reserve(b, 4096);
        if (b->failed) {
            b->n = 0;
            b->acc = 0;
            return;
        }
        uint32_t w = (uint32_t)b->acc;
        memcpy(b->buf + b->len, &w, 4); /* little endian: deflate's bit order */
        b->len += 4;
        b->acc >>= 32;
        b->n -= 32;
    }
}

static void flush_bits(bits *b)
{
    bits_reserve(b, 8);
    while (!b->failed && b->n > 0) {
        b->buf[b->len++] = (uint8_t)b->acc;
        b->acc >>= 8;
        b->n -= 8;
    }
    b->n = 0;
    b->acc = 0;
}

static void put_byte(bits *b, uint8_t v)
{
    bits_reserve(b, 1);
    if (!b->failed) b->buf[b->len++] = v;
}

/* Code lengths (at most maxlen) for n symbols of the given frequencies: Huffman's algorithm on
 * the used symbols; when a length passes maxlen the frequencies are halved (kept nonzero) and
 * the code rebuilt. A single used symbol gets length 1. Deterministic. */
static void code_lengths(const uint64_t *freq, int n, int maxlen, uint8_t *len)
{
    uint64_t f[320];
    int sym[320], used = 0;
    for (int i = 0; i < n; ++i) {
        f[i] = freq[i];
        len[i] = 0;
    }
    for (;;) {
        used = 0;
        for (int i = 0; i < n; ++i)
            if (f[i]) sym[used++] = i;
        if (used == 0) return;
        if (used == 1) {
            len[sym[0]] = 1;
            return;
        }
        /* nodes: leaves 0..used-1, internal used..2*used-2; two-queue merge over sorted leaves */
        uint64_t w[640];
        int parent[640], order[320];
        for (int i = 0; i < used; ++i) order[i] = i;
        for (int i = 1; i < used; ++i) /* insertion sort by (freq, symbol): stable and exact */
            for (int j = i; j > 0; --j) {
                int a = order[j - 1], c = order[j];
                if (f[sym[a]] < f[sym[c]] || (f[sym[a]] == f[sym[c]] && sym[a] < sym[c])) break;
                order[j - 1] = c;
                order[j] = a;
            }
        for (int i = 0; i < used; ++i) w[i] = f[sym[order[i]]];
        int leaf = 0, node = used, next = used;
        for (int k = 0; k < used - 1; ++k) {
            int pick[2];
            for (int t = 0; t < 2; ++t) {
                if (leaf < used && (node >= next || w[leaf] <= w[node])) pick[t] = leaf++;
                else pick[t] = node++;
            }
            w[next] = w[pick[0]] + w[pick[1]];
            parent[pick[0]] = parent[pick[1]] = next;
            ++next;
        }
        int depth[640], maxd = 0;
        depth[next - 1] = 0;
        for (int i = next - 2; i >= 0; --i) depth[i] = depth[parent[i]] + 1;
        for (int i = 0; i < used; ++i) maxd = depth[i] > maxd ? depth[i] : maxd;
        if (maxd <= maxlen) {
            for (int i = 0; i < used; ++i) len[sym[order[i]]] = (uint8_t)depth[i];
            return;
        }
        for (int i = 0; i < n; ++i)
            if (f[i]) f[i] = (f[i] + 1) / 2;
    }
}

/* Canonical codes for the lengths, bit-reversed for deflate's LSB-first stream. */
static void canonical(const uint8_t *len, int n, uint16_t *code)
{
    int count[16] = {0}, next[16] = {0};
    for (int i = 0; i < n; ++i) count[len[i]]++;
    count[0] = 0;
    for (int b = 1, c = 0; b < 16; ++b) {
        c = (c + count[b - 1]) << 1;
        next[b] = c;
    }
    for (int i = 0; i < n; ++i) {
        if (!len[i]) continue;
        unsigned c = (unsigned)next[len[i]]++, r = 0;
        for (int k = 0; k < len[i]; ++k) r |= ((c >> k) & 1u) << (len[i] - 1 - k);
        code[i] = (uint16_t)r;
    }
}

/* Length symbols of copies 3..258 (RFC 1951 3.2.5). */
static uint16_t g_len_sym[259];
static uint8_t g_len_xbits[259];
static uint16_t g_len_xval[259];

static void length_tables(void)
{
    static const int base[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                 31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
    static const int xb[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
    for (int s = 0; s < 29; ++s)
        for (int l = base[s]; l < (s == 28 ? 259 : base[s + 1]) && l <= 258; ++l) {
            g_len_sym[l] = (uint16_t)(257 + s);
            g_len_xbits[l] = (uint8_t)xb[s];
            g_len_xval[l] = (uint16_t)(l - base[s]);
        }
}

/* The image as PNG's packed rows, each with its span: every nonzero byte of row r lies in
 * [span[2r], span[2r+1]) (in packed bytes), the first and the last of them. */
enum { NEAR = 6 }; /* copy distances inside a row tried besides 1 */

typedef struct span_image {
    const uint8_t *pixels;
    size_t stride, rowbytes;
    int width, height, depth, packed;
    int32_t *span;
    uint8_t *scratch;   /* rowbytes, given one pixel a byte: a row's span packed */
    size_t near[NEAR];  /* the distances inside a row at which the drawn bytes repeat most */
    int nnear;
} span_image;

/* Row r's bytes: p[lo..hi) hold the span (p is the row as given, or buf with the span packed). */
static const uint8_t *span_row(const span_image *im, int r, uint8_t *buf, size_t *lo, size_t *hi)
{
    *lo = (size_t)im->span[2 * r];
    *hi = (size_t)im->span[2 * r + 1];
    const uint8_t *src = im->pixels + (size_t)r * im->stride;
    if (im->depth >= 8 || im->packed || *hi <= *lo) return src;
    int per = 8 / im->depth;
    memset(buf + *lo, 0, *hi - *lo);
    size_t x1 = HV_MIN(*hi * (size_t)per, (size_t)im->width);
    for (size_t x = *lo * (size_t)per; x < x1; ++x)
        buf[x / (size_t)per] |= (uint8_t)(src[x] << (8 - im->depth - im->depth * (int)(x % (size_t)per)));
    return buf;
}

/* Copy distances: [0] one byte back (zero runs, runs of one value), [1..nnear] the image's
 * distances inside a row. */
enum { NDIST = NEAR + 1 };

/* The symbols as found, then written: a literal or the end of block (0..256), or a copy
 * (TOK_COPY | distance index << 9 | length). */
enum { TOK_COPY = 0x8000 };

typedef struct walker {
    uint64_t freq[286], dfreq[30];
    uint16_t code[286], dcode[30];
    uint8_t len[286], dlen[30];
    uint16_t *tok;            /* the symbols in order */
    size_t ntok, captok;
    int failed;               /* out of memory for them */
    const uint8_t *ok;        /* palette_table of the bytes, or NULL: no check */
    int bd, per, width, npal; /* bits an index, indices a byte, pixels a row, palette colours */
    size_t whole;             /* bytes of a row whose every index is a pixel */
    int row;                  /* the row being walked */
    int bad_x, bad_y;         /* the first pixel beyond the palette (bad_x -1: none) */
    unsigned bad_v;           /* and its index */
    uint64_t zeros;           /* pending zero bytes */
    int last_zero;            /* the last byte emitted is a zero */
    uint32_t a, b;            /* Adler-32 */
    int nd;                   /* distances in use: dist[0..nd) */
    size_t dist[NDIST];
    uint8_t dsym[NDIST], dxbits[NDIST];
    uint16_t dxval[NDIST];
} walker;

/* Room for n more symbols. */
static int tok_reserve(walker *w, size_t n)
{
    if (w->ntok + n <= w->captok) return 1;
    if (w->failed) return 0;
    size_t cap = w->captok ? w->captok : 1 << 16;
    while (cap < w->ntok + n) cap *= 2;
    uint16_t *t = realloc(w->tok, cap * sizeof *t);
    if (!t) {
        w->failed = 1;
        return 0;
    }
    w->tok = t;
    w->captok = cap;
    return 1;
}

static inline void lit(walker *w, unsigned sym)
{
    w->freq[sym]++;
    if (tok_reserve(w, 1)) w->tok[w->ntok++] = (uint16_t)sym;
}

/* A copy of l bytes (3..258) from distance dist[k]. */
static inline void copy(walker *w, unsigned l, int k)
{
    w->freq[g_len_sym[l]]++;
    w->dfreq[w->dsym[k]]++;
    if (tok_reserve(w, 1)) w->tok[w->ntok++] = (uint16_t)(TOK_COPY | (unsigned)k << 9 | l);
}

static void flush_zeros(walker *w)
{
    uint64_t n = w->zeros;
    if (!n) return;
    w->zeros = 0;
    if (!w->last_zero) {
        lit(w, 0);
        --n;
        w->last_zero = 1;
    }
    while (n >= 3) {
        unsigned l = n >= 258 ? 258 : (unsigned)n;
        if (n > 258 && n - 258 < 3) l = (unsigned)n - 3; /* leave a copy of at least 3 */
        copy(w, l, 0);
        n -= l;
    }
    while (n--) lit(w, 0);
}

/* Adler-32 over n zero bytes: s1 stays, s2 grows by n * s1. */
static void adler_zeros(walker *w, uint64_t n)
{
    w->b = (uint32_t)((w->b + (n % 65521) * w->a) % 65521);
}


/* Length of the run of zero bytes at p (at most n), a word at a time. */
static size_t zero_run(const uint8_t *p, size_t n)
{
    size_t i = 0;
    while (i < n && ((uintptr_t)(p + i) & 7)) {
        if (p[i]) return i;
        ++i;
    }
    for (; i + 8 <= n; i += 8) {
        uint64_t v;
        memcpy(&v, p + i, 8);
        if (v) return i + (size_t)(__builtin_ctzll(v) >> 3);
    }
    while (i < n && !p[i]) ++i;
    return i;
}

/* The literals of a run of non-zero bytes, row[at..at+n). Checked against the palette here: every
 * other byte of the stream is a zero or a copy of an earlier one, so the first byte in raster
 * order beyond the palette is a literal, and the first such literal is it. */
static void literals(walker *w, const uint8_t *row, size_t at, size_t n)
{
    const uint8_t *p = row + at;
    for (size_t i = 0; i < n; ++i) w->freq[p[i]]++;
    for (size_t i = 0; i < n && w->ok && w->bad_x < 0; ++i)
        if (!w->ok[p[i]] || at + i >= w->whole) /* a bad index, or a row's last, partial byte */
            for (int k = 0, x = (int)(at + i) * w->per; k < w->per && x + k < w->width; ++k) {
                unsigned v = (unsigned)(p[i] >> (8 - w->bd - w->bd * k)) & ((1u << w->bd) - 1u);
                if (v >= (unsigned)w->npal) {
                    w->bad_x = x + k;
                    w->bad_y = w->row;
                    w->bad_v = v;
                    break;
                }
            }
    if (!tok_reserve(w, n)) return;
    uint16_t *t = w->tok + w->ntok;
    for (size_t i = 0; i < n; ++i) t[i] = p[i];
    w->ntok += n;
}

/* Four whole bytes of the bit buffer out when it holds 32 bits or more; returns the new end. */
static inline uint8_t *flush32(uint8_t *o, uint64_t *acc, int *nb)
{
    if (*nb < 32) return o;
    uint32_t v = (uint32_t)*acc;
    memcpy(o, &v, 4);
    *acc >>= 32;
    *nb -= 32;
    return o + 4;
}

/* The symbols written with the codes, the bit buffer in registers. */
static void emit(const walker *w, bits *b)
{
    enum { STEP = 4096 };
    for (size_t at = 0; at < w->ntok && !b->failed; at += STEP) {
        size_t end = HV_MIN(w->ntok, at + STEP);
        bits_reserve(b, 8 * (end - at) + 16); /* a copy takes at most 48 bits */
        if (b->failed) return;
        uint64_t acc = b->acc;
        int nb = b->n;
        uint8_t *o = b->buf + b->len;
        for (size_t i = at; i < end; ++i) {
            unsigned t = w->tok[i];
            if (t < TOK_COPY) {
                acc |= (uint64_t)w->code[t] << nb;
                nb += w->len[t];
            } else {
                unsigned l = t & 511, k = (t >> 9) & 63, s = g_len_sym[l], ds = w->dsym[k];
                acc |= (uint64_t)w->code[s] << nb;
                nb += w->len[s];
                acc |= (uint64_t)g_len_xval[l] << nb;
                nb += g_len_xbits[l];
                o = flush32(o, &acc, &nb);
                acc |= (uint64_t)w->dcode[ds] << nb;
                nb += w->dlen[ds];
                acc |= (uint64_t)w->dxval[k] << nb;
                nb += w->dxbits[k];
            }
            o = flush32(o, &acc, &nb);
        }
        b->len = (size_t)(o - b->buf);
        b->acc = acc;
        b->n = nb;
    }
}

/* Bytes from a and b that agree, at most n, a word at a time. */
static inline size_t match_len(const uint8_t *a, const uint8_t *b, size_t n)
{
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t x, y;
        memcpy(&x, a + i, 8);
        memcpy(&y, b + i, 8);
        if (x != y) return i + (size_t)(__builtin_ctzll(x ^ y) >> 3);
    }
    while (i < n && a[i] == b[i]) ++i;
    return i;
}

/* The longest copy (at most cap bytes) at row[i] from the distances in use, its index in *k:
 * copies read inside the span row[lo..) only, so they depend on the pixels alone. */
static inline size_t best_copy(const walker *w, const uint8_t *row, size_t lo, size_t i, size_t cap, int *k)
{
    size_t best = 0;
    for (int j = 0; j < w->nd && best < cap; ++j) {
        size_t d = w->dist[j];
        if (i < lo + d || row[i] != row[i - d]) continue;
        size_t m = match_len(row + i, row + i - d, cap);
        if (m > best) best = m, *k = j;
    }
    return best;
}

/* Whether a copy of at least 3 bytes starts at row[i] (i + 3 <= the span's end). */
static inline int copy_at(const walker *w, const uint8_t *row, size_t lo, size_t i)
{
    const uint8_t *p = row + i;
    for (int j = 0; j < w->nd; ++j) {
        ptrdiff_t d = (ptrdiff_t)w->dist[j];
        if (i >= lo + (size_t)d && p[0] == p[-d] && p[1] == p[1 - d] && p[2] == p[2 - d]) return 1;
    }
    return 0;
}

/* The span row[lo..hi) as zeros, copies and literals, greedily: a run of zeros joins the pending
 * ones (copies one byte back, which carry across blank rows) unless it is short and a copy is
 * longer; at a nonzero byte the longest copy of 3 or more, else literals up to the next zero or
 * copy. (The row above, 1 + rowbytes back, made the files larger: its 11 extra bits a copy.) */
static void walk_span(walker *w, const uint8_t *row, size_t lo, size_t hi)
{
    for (size_t i = lo; i < hi;) {
        size_t n = hi - i, cap = n < 258 ? n : 258, m = 0;
        int k = 0;
        if (!row[i]) {
            size_t z = zero_run(row + i, n);
            if (z >= 8 || z == n || (m = best_copy(w, row, lo, i, cap, &k)) < 3 || m <= z) {
                w->zeros += z;
                i += z;
                continue;
            }
        } else {
            m = best_copy(w, row, lo, i, cap, &k);
        }
        if (m >= 3) {
            flush_zeros(w);
            copy(w, (unsigned)m, k);
            w->last_zero = !row[i + m - 1];
            i += m;
            continue;
        }
        size_t j = i + 1;
        while (j < hi && row[j] && !(j + 3 <= hi && copy_at(w, row, lo, j))) ++j;
        flush_zeros(w);
        literals(w, row, i, j - i);
        w->last_zero = 0;
        i = j;
    }
}

static void walk(walker *w, const span_image *im)
{
    size_t rb = im->rowbytes;
    w->zeros = 0;
    w->last_zero = 0;
    w->a = 1;
    w->b = 0;
    for (int r = 0; r < im->height; ++r) {
        size_t lo, hi;
        const uint8_t *row = span_row(im, r, im->scratch, &lo, &hi);
        w->row = r;
        /* the filter byte (None) and the zeros before the span */
        w->zeros += 1 + lo;
        adler_zeros(w, 1 + lo);
        if (hi > lo) {
            walk_span(w, row, lo, hi);
            uint32_t ad = libdeflate_adler32(((uint32_t)w->b << 16) | w->a, row + lo, hi - lo);
            w->a = ad & 0xffff;
            w->b = ad >> 16;
        }
        w->zeros += rb - hi;
        adler_zeros(w, rb - hi);
    }
    flush_zeros(w);
    lit(w, 256);
}

static const uint8_t k_clen_order[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};

typedef struct rle {
    uint8_t sym, extra;
} rle;

/* The code lengths as the code-length alphabet's runs (16: repeat previous 3-6, 17: zeros
 * 3-10, 18: zeros 11-138). */
static int rle_lengths(const uint8_t *lens, int n, rle *out)
{
    int k = 0;
    for (int i = 0; i < n;) {
        int v = lens[i], run = 1;
        while (i + run < n && lens[i + run] == v) ++run;
        i += run;
        if (v == 0) {
            while (run >= 11) {
                int t = run > 138 ? 138 : run;
                out[k++] = (rle){18, (uint8_t)(t - 11)};
                run -= t;
            }
            if (run >= 3) {
                out[k++] = (rle){17, (uint8_t)(run - 3)};
                run = 0;
            }
            while (run--) out[k++] = (rle){0, 0};
        } else {
            out[k++] = (rle){(uint8_t)v, 0};
            --run;
            while (run >= 3) {
                int t = run > 6 ? 6 : run;
                out[k++] = (rle){16, (uint8_t)(t - 3)};
                run -= t;
            }
            while (run--) out[k++] = (rle){(uint8_t)v, 0};
        }
    }
    return k;
}

static void block_header(bits *b, const uint8_t *litlen, int hlit, const uint8_t *dist, int hdist)
{
    uint8_t all[286 + 30];
    memcpy(all, litlen, (size_t)hlit);
    memcpy(all + hlit, dist, (size_t)hdist);
    rle runs[320];
    int nr = rle_lengths(all, hlit + hdist, runs);
    uint64_t cf[19] = {0};
    for (int i = 0; i < nr; ++i) cf[runs[i].sym]++;
    uint8_t cl[19];
    uint16_t cc[19];
    code_lengths(cf, 19, 7, cl);
    canonical(cl, 19, cc);
    int hclen = 19;
    while (hclen > 4 && cl[k_clen_order[hclen - 1]] == 0) --hclen;
    put(b, 1, 1); /* BFINAL */
    put(b, 2, 2); /* dynamic Huffman */
    put(b, (uint32_t)(hlit - 257), 5);
    put(b, (uint32_t)(hdist - 1), 5);
    put(b, (uint32_t)(hclen - 4), 4);
    for (int i = 0; i < hclen; ++i) put(b, cl[k_clen_order[i]], 3);
    for (int i = 0; i < nr; ++i) {
        put(b, cc[runs[i].sym], cl[runs[i].sym]);
        if (runs[i].sym == 16) put(b, runs[i].extra, 2);
        else if (runs[i].sym == 17) put(b, runs[i].extra, 3);
        else if (runs[i].sym == 18) put(b, runs[i].extra, 7);
    }
}

/* The distance code of d (1..32768) and its extra bits (RFC 1951 3.2.5). */
static void dist_code(size_t d, unsigned *sym, unsigned *xbits, unsigned *xval)
{
    static const uint16_t base[30] = {1,    2,    3,    4,    5,    7,     9,     13,    17,  25,
                                      33,   49,   65,   97,   129,  193,   257,   385,   513, 769,
                                      1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
    unsigned s = 0;
    while (s < 29 && base[s + 1] <= d) ++s;
    *sym = s;
    *xbits = s < 4 ? 0 : (s - 2) / 2;
    *xval = (unsigned)(d - base[s]);
}

static pthread_once_t g_tables_once = PTHREAD_ONCE_INIT;

/* Huffman lengths for symbols 0..n-1 of the given frequencies, a complete code of two or more
 * (a lone symbol gets a partner, no symbol two of them): some inflaters refuse a code of one. */
static void complete_lengths(const uint64_t *freq, int n, int maxlen, uint8_t *len)
{
    uint64_t f[320];
    int used = 0;
    for (int i = 0; i < n; ++i) used += (f[i] = freq[i]) != 0;
    for (int i = 0; i < n && used < 2; ++i)
        if (!f[i]) f[i] = 1, ++used;
    code_lengths(f, n, maxlen, len);
}

static hv_status encode_spans(const span_image *im, const hv_png_options *o, uint8_t **data, size_t *size)
{
    pthread_once(&g_tables_once, length_tables);
    walker *w = hv_calloc(1, sizeof *w);
    if (!w) return hv_error_set(HV_ERR_NOMEM, "PNG: out of memory");
    w->dist[w->nd++] = 1;
    for (int j = 0; j < im->nnear; ++j) w->dist[w->nd++] = im->near[j];
    for (int j = 0; j < w->nd; ++j) {
        unsigned s, xb, xv;
        dist_code(w->dist[j], &s, &xb, &xv);
        w->dsym[j] = (uint8_t)s;
        w->dxbits[j] = (uint8_t)xb;
        w->dxval[j] = (uint16_t)xv;
    }
    uint8_t ok[256];
    w->bad_x = -1;
    if (check_here(o) && !(im->depth < 8 && o->palette_size >= (1 << im->depth))) {
        w->bd = im->depth;
        w->per = 8 / im->depth;
        w->width = im->width;
        w->npal = o->palette_size;
        w->whole = (size_t)im->width / (size_t)w->per;
        palette_table(w->bd, w->per, w->npal, ok);
        w->ok = ok;
    }
    walk(w, im);
    if (w->bad_x >= 0) {
        hv_status bad = hv_error_set(HV_ERR_INVALID, "PNG: pixel (%d, %d) has index %u beyond the %d-colour palette",
                                     w->bad_x, w->bad_y, w->bad_v, w->npal);
        free(w->tok);
        free(w);
        return bad;
    }
    int hlit = 286, hdist = 30;
    while (hlit > 257 && w->freq[hlit - 1] == 0) --hlit;
    complete_lengths(w->freq, hlit, 15, w->len);
    canonical(w->len, hlit, w->code);
    complete_lengths(w->dfreq, 30, 15, w->dlen);
    while (hdist > 1 && w->dlen[hdist - 1] == 0) --hdist;
    canonical(w->dlen, hdist, w->dcode);
    bits z = {0};
    z.failed = w->failed;
    put_byte(&z, 0x78); /* zlib: deflate, 32K window, no dictionary, "fastest" */
    put_byte(&z, 0x01);
    block_header(&z, w->len, hlit, w->dlen, hdist);
    emit(w, &z);
    flush_bits(&z);
    uint32_t adler = (w->b << 16) | w->a;
    for (int k = 3; k >= 0; --k) put_byte(&z, (uint8_t)(adler >> (8 * k)));
    free(w->tok);
    free(w);
    uint8_t *out = z.failed ? NULL : hv_malloc_big(frame_bound(o, z.len), 1);
    if (!out) {
        free(z.buf);
        return hv_error_set(HV_ERR_NOMEM, "PNG: out of memory for a %d x %d image", im->width, im->height);
    }
    *size = frame_png(out, im->width, im->height, 1, im->depth, o, z.buf, z.len);
    *data = out;
    free(z.buf);
    return HV_OK;
}

/* Finds the span of every row (inside opt->row_spans's, or the whole row) into im->span, from
 * its first to its last nonzero byte, in packed bytes; returns 1 if they hold under a quarter of
 * the image's bytes, 0 at the first row that makes them more. */
static int find_spans(span_image *im, const int32_t *hint)
{
    int per = im->depth < 8 && !im->packed ? 8 / im->depth : 1; /* pixels a byte of the row as given */
    size_t n = per > 1 ? (size_t)im->width : im->rowbytes, drawn = 0, total = im->rowbytes * (size_t)im->height;
    for (int r = 0; r < im->height; ++r) {
        const uint8_t *row = im->pixels + (size_t)r * im->stride;
        size_t lo = 0, hi = n;
        if (hint) {
            lo = (size_t)HV_CLAMP(hint[2 * r], 0, (int64_t)n);
            hi = (size_t)HV_CLAMP(hint[2 * r + 1], (int64_t)lo, (int64_t)n);
        }
        lo += zero_run(row + lo, hi - lo);
        while (hi > lo && !row[hi - 1]) --hi;
        if (per > 1 && hi > lo) { /* pixels to packed bytes */
            lo /= (size_t)per;
            hi = (hi - 1) / (size_t)per + 1;
        }
        if (hi <= lo) lo = hi = 0;
        im->span[2 * r] = (int32_t)lo;
        im->span[2 * r + 1] = (int32_t)hi;
        drawn += hi - lo;
        if (drawn * 4 >= total) return 0;
    }
    return 1;
}

/* The NEAR distances (2..8191 bytes) at which the drawn bytes repeat inside a row, from eight
 * drawn rows spread over the image, one at a time: at every 4 bytes not all zero that no distance
 * chosen so far repeats, the distance back to the last 4 bytes like them (a hash table), counted;
 * the most counted is the next, if it repeats 1/64 of the bytes looked at. A halftone's threshold
 * tile gives the first (hovox's blue noise is 64 pixels wide: 32 bytes at 4 bits) and its
 * multiples where the materials' fractions drift, copies of a part another (the README tray's
 * two gears, 992 bytes apart): copies at these few distances find about what a full LZ77 search
 * finds, for a few comparisons a byte. Returns 0 when out of memory. */
static int find_near(span_image *im)
{
    enum { ROWS = 8, MAXD = 8192, HBITS = 12 };
    im->nnear = 0;
    size_t nd = 0;
    for (int r = 0; r < im->height; ++r) nd += im->span[2 * r] < im->span[2 * r + 1];
    if (!nd) return 1;
    uint32_t *count = hv_malloc((MAXD + (1u << HBITS)) * sizeof *count);
    if (!count) return 0;
    uint32_t *last = count + MAXD; /* position + 1 of the last 4 bytes of each hash in the row */
    int rows[ROWS], nrows = 0;
    for (int r = 0, seen = 0; r < im->height && nrows < ROWS; ++r)
        if (im->span[2 * r] < im->span[2 * r + 1] && (size_t)seen++ == (2 * (size_t)nrows + 1) * nd / (2 * ROWS))
            rows[nrows++] = r;
    while (im->nnear < NEAR) {
        memset(count, 0, MAXD * sizeof *count);
        size_t looked = 0;
        for (int k = 0; k < nrows; ++k) {
            size_t lo, hi;
            const uint8_t *row = span_row(im, rows[k], im->scratch, &lo, &hi);
            memset(last, 0, sizeof *last << HBITS);
            for (size_t i = lo; i + 4 <= hi; ++i) {
                uint32_t v;
                memcpy(&v, row + i, 4);
                if (!v) continue;
                int done = 0;
                for (int j = 0; j < im->nnear && !done; ++j)
                    done = i >= lo + im->near[j] && memcmp(row + i - im->near[j], row + i, 4) == 0;
                uint32_t h = (v * 2654435761u) >> (32 - HBITS);
                size_t p = last[h];
                last[h] = (uint32_t)(i + 1);
                if (done) continue;
                ++looked;
                size_t d = i + 1 - p;
                if (p && d >= 2 && d < MAXD && memcmp(row + p - 1, row + i, 4) == 0) count[d]++;
            }
        }
        size_t best = 0;
        for (size_t d = 2; d < MAXD; ++d)
            if (count[d] > count[best]) best = d;
        if (!best || (uint64_t)count[best] * 64 < looked) break;
        im->near[im->nnear++] = best;
    }
    free(count);
    return 1;
}

/* The span coder takes images whose rows go unfiltered (indexed or sub-byte) at a level above 0,
 * when they are sparse; HOVOX_PNG_SPARSE=0 turns it off (for the bench's comparison). */
static hv_status encode_sparse(const uint8_t *pixels, int width, int height, int channels, size_t stride,
                               const hv_png_options *o, uint8_t **data, size_t *size, int *done)
{
    *done = 0;
    int depth = o && o->bit_depth ? o->bit_depth : 8;
    const char *env = getenv("HOVOX_PNG_SPARSE");
    if (channels != 1 || !o || depth > 8 || !(o->palette || depth < 8) || o->compression == 0 || width > (1 << 28) ||
        (env && strcmp(env, "0") == 0))
        return HV_OK;
    span_image im = {pixels, stride, png_rowbytes(width, 1, depth), width, height, depth, o->packed && depth < 8,
                     hv_malloc((size_t)height * 2 * sizeof(int32_t)), NULL, {0}, 0};
    if (!im.span) return hv_error_set(HV_ERR_NOMEM, "PNG: out of memory");
    hv_status st = HV_OK;
    if (find_spans(&im, o->row_spans)) {
        im.scratch = hv_malloc(im.rowbytes);
        st = im.scratch && find_near(&im) ? encode_spans(&im, o, data, size)
                                          : hv_error_set(HV_ERR_NOMEM, "PNG: out of memory");
        *done = 1;
    }
    free(im.scratch);
    free(im.span);
    return st;
}

/* encode: the image's bytes (pixels or packed rows as given, *bad 1 on an index beyond the palette) */
static hv_status encode(const uint8_t *pixels, int width, int height, int channels, size_t stride,
                        const hv_png_options *o, uint8_t **data, size_t *size, int *bad)
{
    *bad = 0;
    int depth = o && o->bit_depth ? o->bit_depth : 8;
    if (!stride) stride = depth < 8 && !(o && o->packed) ? (size_t)width : png_rowbytes(width, channels, depth);
    int done = 0;
    hv_status st = encode_sparse(pixels, width, height, channels, stride, o, data, size, &done);
    if (st == HV_OK && !done && check_here(o)) st = check_palette_pixels(pixels, width, height, stride, o);
    if (st != HV_OK || done) {
        *bad = st == HV_ERR_INVALID;
        return st;
    }
    return encode_deflate(pixels, width, height, channels, stride, o, data, size);
}

hv_status hv_png_encode(const uint8_t *pixels, int width, int height, int channels, size_t stride,
                        const hv_png_options *opt, uint8_t **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    int bad;
    hv_status st = check_png_args(pixels, width, height, channels, stride, opt, !check_here(opt));
    if (st != HV_OK) return st;
    return encode(pixels, width, height, channels, stride, opt, data, size, &bad);
}

hv_status hv_png_write(const char *path, const uint8_t *pixels, int width, int height, int channels,
                       size_t stride, const hv_png_options *opt)
{
    uint8_t *png = NULL;
    size_t size = 0;
    int bad = 0;
    hv_status st = check_png_args(pixels, width, height, channels, stride, opt, !check_here(opt));
    if (st == HV_OK && (st = encode(pixels, width, height, channels, stride, opt, &png, &size, &bad)) != HV_OK)
        return bad ? st : hv_error_prefix(st, "%s: ", path);
    if (st != HV_OK) return st;
    /* in_place: inside a directory renamed whole, so no temporary and no sync */
    st = opt && opt->in_place ? hv_write_in_place(path, png, size) : hv_atomic_write(path, png, size);
    free(png);
    return st;
}
