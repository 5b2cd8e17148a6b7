/* tests/bench/bench_png.c - issue 26 item 3: the PNG encoders on real stack layers (the bench
 * tray's, scripts/bench/98-png.sh). Each layer is read back, then encoded by every encoder the
 * way a stack would write it (same depth, palette, pHYs, zlib level), RUNS times; prints the
 * median time of all layers and the bytes per encoder, and checks that every output decodes
 * (libpng) to the layer's pixels.
 *   bench_png RUNS LEVEL LAYER.png...
 * Encoders: hovox (hv_png_encode, the one encoder: the span coder on sparse layers, libdeflate on
 * the others), the same with the span coder off (HOVOX_PNG_SPARSE=0: libdeflate on every layer),
 * libpng and libspng as anchors. */
#include <png.h>
#include <spng.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "hovox/core.h"
#include "hovox/image.h"

typedef struct layer {
    int w, h, depth, palette_size, indexed;
    uint8_t palette[768];
    double dpi[2];
    uint8_t *px;     /* one sample a byte */
    uint8_t *packed; /* PNG's packing, rowbytes a row */
    size_t rowbytes;
} layer;

static uint32_t be32(const uint8_t *b) { return (uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | b[3]; }

static int load(const char *path, layer *L)
{
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *d = malloc((size_t)n);
    if (!d || fread(d, 1, (size_t)n, f) != (size_t)n) return fclose(f), free(d), 0;
    fclose(f);
    memset(L, 0, sizeof *L);
    for (size_t at = 8; at + 12 <= (size_t)n;) { /* IHDR, PLTE, pHYs */
        uint32_t len = be32(d + at);
        const uint8_t *c = d + at + 8;
        if (!memcmp(d + at + 4, "IHDR", 4)) {
            L->w = (int)be32(c);
            L->h = (int)be32(c + 4);
            L->depth = c[8];
            L->indexed = c[9] == 3;
        } else if (!memcmp(d + at + 4, "PLTE", 4)) {
            L->palette_size = (int)len / 3;
            memcpy(L->palette, c, len);
        } else if (!memcmp(d + at + 4, "pHYs", 4)) {
            L->dpi[0] = be32(c) * 0.0254;
            L->dpi[1] = be32(c + 4) * 0.0254;
        }
        at += 12 + len;
    }
    hv_png_pixels p;
    if (hv_png_decode_flags(d, (size_t)n, path, UINT64_MAX, HV_PNG_PALETTE_INDICES, &p) != HV_OK || p.channels != 1) {
        free(d);
        return 0;
    }
    free(d);
    size_t np = (size_t)L->w * (size_t)L->h;
    L->px = malloc(np);
    L->rowbytes = ((size_t)L->w * (size_t)L->depth + 7) / 8;
    L->packed = calloc((size_t)L->h, L->rowbytes);
    int per = 8 / L->depth;
    for (size_t i = 0; i < np; ++i) {
        /* grey below 8 bits comes back widened by bit replication; indices come back as they are */
        unsigned v = p.samples[i];
        if (!L->indexed && L->depth < 8) v >>= 8 - L->depth;
        L->px[i] = (uint8_t)v;
    }
    for (int y = 0; y < L->h; ++y)
        for (int x = 0; x < L->w && L->depth < 8; ++x)
            L->packed[(size_t)y * L->rowbytes + (size_t)(x / per)] |=
                (uint8_t)(L->px[(size_t)y * (size_t)L->w + (size_t)x] << (8 - L->depth - L->depth * (x % per)));
    hv_png_pixels_free(&p);
    return 1;
}

/* ---- encoders ----------------------------------------------------------------------------- */

static int enc_hovox(const layer *L, int level, uint8_t **out, size_t *size)
{
    hv_png_options o;
    hv_png_options_init(&o);
    o.compression = level;
    o.dpi[0] = L->dpi[0];
    o.dpi[1] = L->dpi[1];
    o.bit_depth = L->depth;
    o.packed = L->depth < 8;
    if (L->indexed) {
        o.palette = L->palette;
        o.palette_size = L->palette_size;
    }
    return hv_png_encode(L->depth < 8 ? L->packed : L->px, L->w, L->h, 1, 0, &o, out, size) == HV_OK;
}

typedef struct membuf {
    uint8_t *d;
    size_t n, cap;
} membuf;

static void mem_write(png_structp png, png_bytep data, size_t n)
{
    membuf *m = png_get_io_ptr(png);
    if (m->n + n > m->cap) {
        m->cap = (m->n + n) * 2;
        m->d = realloc(m->d, m->cap);
    }
    memcpy(m->d + m->n, data, n);
    m->n += n;
}

static void mem_flush(png_structp png) { (void)png; }

/* libpng as hovox used it before issue 26 (layers: filters of libpng's choice, which for indexed
 * and sub-byte images is None) */
static int enc_libpng(const layer *L, int level, uint8_t **out, size_t *size)
{
    membuf m = {0};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        free(m.d);
        return 0;
    }
    png_set_write_fn(png, &m, mem_write, mem_flush);
    png_set_IHDR(png, info, (png_uint_32)L->w, (png_uint_32)L->h, L->depth, L->indexed ? PNG_COLOR_TYPE_PALETTE : PNG_COLOR_TYPE_GRAY,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (L->indexed) png_set_PLTE(png, info, (png_const_colorp)L->palette, L->palette_size);
    png_set_pHYs(png, info, (png_uint_32)(L->dpi[0] / 0.0254 + 0.5), (png_uint_32)(L->dpi[1] / 0.0254 + 0.5), PNG_RESOLUTION_METER);
    png_set_compression_level(png, level);
    png_write_info(png, info);
    const uint8_t *rows = L->depth < 8 ? L->packed : L->px;
    size_t rb = L->depth < 8 ? L->rowbytes : (size_t)L->w;
    for (int y = 0; y < L->h; ++y) png_write_row(png, rows + (size_t)y * rb);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    *out = m.d;
    *size = m.n;
    return 1;
}

static int enc_spng(const layer *L, int level, uint8_t **out, size_t *size)
{
    spng_ctx *c = spng_ctx_new(SPNG_CTX_ENCODER);
    spng_set_option(c, SPNG_ENCODE_TO_BUFFER, 1);
    spng_set_option(c, SPNG_IMG_COMPRESSION_LEVEL, level);
    spng_set_option(c, SPNG_FILTER_CHOICE, L->indexed || L->depth < 8 ? SPNG_DISABLE_FILTERING : SPNG_FILTER_CHOICE_ALL);
    struct spng_ihdr ih = {(uint32_t)L->w, (uint32_t)L->h, (uint8_t)L->depth,
                           (uint8_t)(L->indexed ? SPNG_COLOR_TYPE_INDEXED : SPNG_COLOR_TYPE_GRAYSCALE), 0, 0, 0};
    spng_set_ihdr(c, &ih);
    if (L->indexed) {
        struct spng_plte pl;
        pl.n_entries = (uint32_t)L->palette_size;
        for (int i = 0; i < L->palette_size; ++i) {
            pl.entries[i].red = L->palette[3 * i];
            pl.entries[i].green = L->palette[3 * i + 1];
            pl.entries[i].blue = L->palette[3 * i + 2];
            pl.entries[i].alpha = 255;
        }
        spng_set_plte(c, &pl);
    }
    struct spng_phys ph = {(uint32_t)(L->dpi[0] / 0.0254 + 0.5), (uint32_t)(L->dpi[1] / 0.0254 + 0.5), 1};
    spng_set_phys(c, &ph);
    const uint8_t *rows = L->depth < 8 ? L->packed : L->px;
    size_t n = (L->depth < 8 ? L->rowbytes : (size_t)L->w) * (size_t)L->h;
    int r = spng_encode_image(c, rows, n, SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
    int err = 0;
    *out = r ? NULL : spng_get_png_buffer(c, size, &err);
    spng_ctx_free(c);
    return !r && !err && *out;
}

/* hovox's encoder with its span path off: libdeflate on every image */
static int enc_libdeflate(const layer *L, int level, uint8_t **out, size_t *size)
{
    setenv("HOVOX_PNG_SPARSE", "0", 1);
    int ok = enc_hovox(L, level, out, size);
    unsetenv("HOVOX_PNG_SPARSE");
    return ok;
}

typedef int (*encoder)(const layer *, int, uint8_t **, size_t *);

int main(int argc, char **argv)
{
    if (argc < 4) {
        fputs("usage: bench_png RUNS LEVEL LAYER.png...\n", stderr);
        return 2;
    }
    int runs = atoi(argv[1]), level = atoi(argv[2]), nl = argc - 3;
    layer *L = calloc((size_t)nl, sizeof *L);
    for (int i = 0; i < nl; ++i)
        if (!load(argv[3 + i], &L[i])) {
            fprintf(stderr, "bench_png: cannot read %s as a 1-channel PNG\n", argv[3 + i]);
            return 1;
        }
    static const char *names[] = {"hovox", "hovox libdeflate only", "libpng", "libspng"};
    static const encoder enc[] = {enc_hovox, enc_libdeflate, enc_libpng, enc_spng};
    double *t = calloc((size_t)runs, sizeof *t);
    printf("  %d layers of %d x %d, %d-bit %s, zlib level %d; median of %d runs (one thread)\n", nl, L[0].w, L[0].h,
           L[0].depth, L[0].indexed ? "indexed" : "grey", level, runs);
    for (int e = 0; e < 4; ++e) {
        size_t bytes = 0;
        int ok = 1;
        for (int r = 0; r < runs; ++r) {
            t[r] = 0; /* encoding only: the check below is not timed */
            for (int i = 0; i < nl; ++i) {
                uint8_t *png = NULL;
                size_t size = 0;
                double t0 = now();
                if (!enc[e](&L[i], level, &png, &size)) ok = 0;
                t[r] += now() - t0;
                if (r == 0) { /* every output decodes to the layer's pixels */
                    bytes += size;
                    hv_png_pixels p;
                    if (!png || hv_png_decode_flags(png, size, names[e], UINT64_MAX, HV_PNG_PALETTE_INDICES, &p) != HV_OK) ok = 0;
                    else {
                        for (size_t k = 0; ok && k < (size_t)L[i].w * (size_t)L[i].h; ++k) {
                            unsigned v = p.samples[k];
                            if (!L[i].indexed && L[i].depth < 8) v >>= 8 - L[i].depth;
                            if (v != L[i].px[k]) ok = 0;
                        }
                        hv_png_pixels_free(&p);
                    }
                }
                free(png);
            }
        }
        double m = median(t, runs);
        printf("  %-22s %8.3f s  %8.1f ms/layer  %8.2f MiB  %s\n", names[e], m, 1e3 * m / nl, bytes / 1048576.0,
               ok ? "pixels identical" : "PIXELS DIFFER or failed");
    }
    return 0;
}
