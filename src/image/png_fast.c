/* src/image/png_fast.c - PNG for printer layers (png_fast.h): the zlib stream is written here,
 * one dynamic-Huffman block (RFC 1951 3.2.7) whose code is fitted to the image: pass 1 counts
 * the symbols, pass 2 writes them. Zero stretches become copies of length 258 at distance 1, so
 * an empty plate row costs a few bits and is skipped in O(1) when the caller gives spans; the
 * halftone noise inside parts takes about its entropy. Chunks after the PNG specification
 * (ISO/IEC 15948): IHDR, PLTE, pHYs, IDAT, IEND, CRC-32 from zlib. */
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "core/internal.h"
#include "image/png_fast.h"

/* ---- bits ------------------------------------------------------------------------------------ */

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

/* ---- Huffman codes ------------------------------------------------------------------------- */

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

/* ---- the token walk ------------------------------------------------------------------------- */

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

typedef struct walker {
    int emit;                 /* 0: count, 1: write */
    uint64_t freq[286];
    uint16_t code[286];
    uint8_t len[286];
    bits *out;
    uint64_t zeros;           /* pending zero bytes */
    int last_zero;            /* the last byte emitted is a zero */
    uint32_t a, b;            /* Adler-32 */
} walker;

static inline void lit(walker *w, unsigned sym)
{
    if (w->emit) put(w->out, w->code[sym], w->len[sym]);
    else w->freq[sym]++;
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
        unsigned s = g_len_sym[l];
        if (w->emit) {
            put(w->out, w->code[s], w->len[s]);
            if (g_len_xbits[l]) put(w->out, g_len_xval[l], g_len_xbits[l]);
            put(w->out, 0, 1); /* distance code 0: distance 1 */
        } else {
            w->freq[s]++;
        }
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

/* Length of the run of non-zero bytes at p (at most n). */
static size_t nonzero_run(const uint8_t *p, size_t n)
{
    size_t i = 0;
    while (i < n && p[i]) ++i;
    return i;
}

/* The literals of a run of non-zero bytes: counted, or written with the code in registers. */
static void literals(walker *w, const uint8_t *p, size_t n)
{
    if (!w->emit) {
        for (size_t i = 0; i < n; ++i) w->freq[p[i]]++;
        return;
    }
    bits *b = w->out;
    bits_reserve(b, 2 * n + 16);
    if (b->failed) return;
    uint64_t acc = b->acc;
    int nb = b->n;
    uint8_t *o = b->buf + b->len;
    for (size_t i = 0; i < n; ++i) {
        acc |= (uint64_t)w->code[p[i]] << nb;
        nb += w->len[p[i]];
        if (nb >= 32) {
            uint32_t v = (uint32_t)acc;
            memcpy(o, &v, 4);
            o += 4;
            acc >>= 32;
            nb -= 32;
        }
    }
    b->len = (size_t)(o - b->buf);
    b->acc = acc;
    b->n = nb;
}

static void walk(walker *w, const hv_png_fast_image *img)
{
    size_t rb = ((size_t)img->width * (size_t)img->bit_depth + 7) / 8;
    w->zeros = 0;
    w->last_zero = 0;
    w->a = 1;
    w->b = 0;
    for (int r = 0; r < img->height; ++r) {
        const uint8_t *row = img->rows + (size_t)r * img->stride;
        size_t lo = 0, hi = rb;
        if (img->span) {
            lo = (size_t)HV_CLAMP(img->span[2 * r], 0, (int32_t)rb);
            hi = (size_t)HV_CLAMP(img->span[2 * r + 1], 0, (int32_t)rb);
            if (hi < lo) hi = lo;
        }
        /* the filter byte (None) and the zeros before the span */
        w->zeros += 1 + lo;
        adler_zeros(w, 1 + lo);
        for (size_t i = lo; i < hi;) {
            size_t z = zero_run(row + i, hi - i);
            w->zeros += z;
            i += z;
            if (i == hi) break;
            size_t k = nonzero_run(row + i, hi - i);
            flush_zeros(w);
            literals(w, row + i, k);
            w->last_zero = 0;
            i += k;
        }
        if (hi > lo) {
            uLong ad = ((uLong)w->b << 16) | w->a;
            ad = adler32(ad, row + lo, (uInt)(hi - lo));
            w->a = (uint32_t)(ad & 0xffff);
            w->b = (uint32_t)(ad >> 16);
        }
        w->zeros += rb - hi;
        adler_zeros(w, rb - hi);
    }
    flush_zeros(w);
    lit(w, 256);
}

/* ---- the block header -------------------------------------------------------------------- */

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

static void block_header(bits *b, const uint8_t *litlen, int hlit)
{
    uint8_t all[286 + 2];
    memcpy(all, litlen, (size_t)hlit);
    all[hlit] = 1; /* two distance codes of one bit: code 0 (distance 1) and an unused one */
    all[hlit + 1] = 1;
    rle runs[320];
    int nr = rle_lengths(all, hlit + 2, runs);
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
    put(b, 1, 5); /* HDIST - 1: two distance codes */
    put(b, (uint32_t)(hclen - 4), 4);
    for (int i = 0; i < hclen; ++i) put(b, cl[k_clen_order[i]], 3);
    for (int i = 0; i < nr; ++i) {
        put(b, cc[runs[i].sym], cl[runs[i].sym]);
        if (runs[i].sym == 16) put(b, runs[i].extra, 2);
        else if (runs[i].sym == 17) put(b, runs[i].extra, 3);
        else if (runs[i].sym == 18) put(b, runs[i].extra, 7);
    }
}

/* ---- PNG --------------------------------------------------------------------------------------- */

static void be32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

static void chunk(bits *png, const char *type, const uint8_t *data, size_t n)
{
    uint8_t h[8];
    be32(h, (uint32_t)n);
    memcpy(h + 4, type, 4);
    bits_reserve(png, n + 12);
    if (png->failed) return;
    memcpy(png->buf + png->len, h, 8);
    if (n) memcpy(png->buf + png->len + 8, data, n);
    uLong crc = crc32(0L, (const Bytef *)type, 4);
    size_t o = 0;
    while (o < n) { /* crc32 takes uInt lengths */
        uInt k = (uInt)HV_MIN(n - o, (size_t)1 << 30);
        crc = crc32(crc, data + o, k);
        o += k;
    }
    be32(png->buf + png->len + 8 + n, (uint32_t)crc);
    png->len += n + 12;
}

hv_status hv_png_fast_encode(const hv_png_fast_image *img, uint8_t **out, size_t *size)
{
    *out = NULL;
    *size = 0;
    int bd = img->bit_depth;
    if (img->width < 1 || img->height < 1 || img->width > (1 << 30) || img->height > (1 << 30) ||
        (bd != 1 && bd != 2 && bd != 4 && bd != 8))
        return hv_error_set(HV_ERR_INVALID, "png: %d x %d pixels of %d bits", img->width, img->height, bd);
    if (img->palette && (img->palette_size < 1 || img->palette_size > 256 || img->palette_size > (1 << bd)))
        return hv_error_set(HV_ERR_INVALID, "png: a palette of %d colours for %d-bit pixels", img->palette_size, bd);
    static int tables;
    if (!tables) { /* idempotent: racing threads write the same values */
        length_tables();
        tables = 1;
    }
    walker *w = hv_calloc(1, sizeof *w);
    if (!w) return HV_ERR_NOMEM;
    walk(w, img);
    int hlit = 286;
    while (hlit > 257 && w->freq[hlit - 1] == 0) --hlit;
    code_lengths(w->freq, hlit, 15, w->len);
    canonical(w->len, hlit, w->code);

    bits z = {0};
    put_byte(&z, 0x78); /* zlib: deflate, 32K window */
    put_byte(&z, 0x01);
    block_header(&z, w->len, hlit);
    w->emit = 1;
    w->out = &z;
    walk(w, img);
    flush_bits(&z);
    uint32_t adler = (w->b << 16) | w->a;
    for (int k = 3; k >= 0; --k) put_byte(&z, (uint8_t)(adler >> (8 * k)));
    free(w);
    if (z.failed) {
        free(z.buf);
        return hv_error_set(HV_ERR_NOMEM, "png: out of memory for a %d x %d image", img->width, img->height);
    }

    bits png = {0};
    static const uint8_t sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    bits_reserve(&png, z.len + 4096 + (z.len >> 20) * 12);
    for (int i = 0; i < 8; ++i) put_byte(&png, sig[i]);
    uint8_t ihdr[13];
    be32(ihdr, (uint32_t)img->width);
    be32(ihdr + 4, (uint32_t)img->height);
    ihdr[8] = (uint8_t)bd;
    ihdr[9] = img->palette ? 3 : 0;
    ihdr[10] = ihdr[11] = ihdr[12] = 0;
    chunk(&png, "IHDR", ihdr, 13);
    if (img->palette) chunk(&png, "PLTE", img->palette, 3 * (size_t)img->palette_size);
    if (img->dpi[0] > 0 && img->dpi[1] > 0) {
        uint8_t phys[9];
        be32(phys, (uint32_t)(img->dpi[0] / 0.0254 + 0.5));
        be32(phys + 4, (uint32_t)(img->dpi[1] / 0.0254 + 0.5));
        phys[8] = 1; /* metres */
        chunk(&png, "pHYs", phys, 9);
    }
    for (size_t o = 0; o < z.len; o += (size_t)1 << 20) chunk(&png, "IDAT", z.buf + o, HV_MIN(z.len - o, (size_t)1 << 20));
    chunk(&png, "IEND", NULL, 0);
    free(z.buf);
    if (png.failed) {
        free(png.buf);
        return hv_error_set(HV_ERR_NOMEM, "png: out of memory for a %d x %d image", img->width, img->height);
    }
    *out = png.buf;
    *size = png.len;
    return HV_OK;
}
