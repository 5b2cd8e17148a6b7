/* hovox/image.h - the image module: float RGBA images and their files (PNG through libpng;
 * EXR and TIFF through the OpenImageIO plugin, loaded only when one is asked for), and 8-bit
 * PNG for any module that writes pictures (the renderer, slice stacks, plots). */
#ifndef HOVOX_IMAGE_H
#define HOVOX_IMAGE_H

#include <stddef.h>
#include <stdint.h>

#include "hovox/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ==== images ============================================================================ */

/* A float RGBA image: width*height pixels of 4 floats, rows top to bottom, PREMULTIPLIED
 * alpha (r,g,b <= a). Colours are display values (the materials' colours as given, no
 * colour-space conversion). Free with hv_image_destroy. */
typedef struct hv_image {
    int width, height;
    float *rgba;
} hv_image;

/* A transparent black image. Errors: HV_ERR_INVALID (size outside 1..65535), HV_ERR_NOMEM. */
HV_API hv_status hv_image_create(int width, int height, hv_image **out);
/* Free an image; NULL is allowed. */
HV_API void hv_image_destroy(hv_image *img);

/* 8-bit RGBA with STRAIGHT (unpremultiplied) alpha, rounded: out holds width*height*4 bytes. */
HV_API void hv_image_to_rgba8(const hv_image *img, uint8_t *out);

/* Write an image; the format follows the file extension (case-insensitive):
 *   .png          8-bit RGBA, straight alpha (libpng, zlib level 3, rows Sub-filtered)
 *   .exr          half-float RGBA, premultiplied alpha (OpenImageIO plugin)
 *   .tif, .tiff   8-bit RGBA, straight (unassociated) alpha (OpenImageIO plugin)
 * The OpenImageIO plugin (plugins/hovox-oiio.so) is loaded only for EXR and TIFF. Written to a
 * temporary name next to `path` and renamed when complete: a failure leaves no file.
 * Errors: HV_ERR_UNSUPPORTED (unknown extension, or EXR/TIFF without the plugin), HV_ERR_IO,
 * HV_ERR_NOMEM. */
HV_API hv_status hv_image_write(const hv_image *img, const char *path);

/* ---- PNG: the project's 8-bit image output ---------------------------------------------- */

typedef struct hv_png_options {
    int compression;        /* zlib level 0..9, or -1 (default) for libpng's default (6) */
    double dpi[2];          /* > 0: physical resolution (pHYs chunk, x and y); 0: none */
    const uint8_t *palette; /* with channels == 1: indexed colour, palette_size RGB triples */
    int palette_size;       /* 1..256 */
    const char *text_key;   /* optional tEXt chunk (1-79 Latin-1 bytes) ... */
    const char *text_value; /* ... and its value */
    int bit_depth;          /* 1, 2, 4, 8 or 16 (0 means 8); below 8 only with channels == 1
                               (grey or indexed): pixels stay one per byte, values < 2^bit_depth;
                               16 (no palette): two bytes per sample, most significant first
                               (PNG's order) */
    int in_place;           /* 1: hv_png_write writes the file under its name, unsynced, and
                               removes it on failure: for files inside a directory that is
                               itself written whole and renamed (a slice stack) */
    int filter_sub;         /* 1: every row with the Sub filter (PNG spec 9.2) instead of the
                               choice among the five per row: a third of the time to encode a
                               render, files a few per cent larger */
    int packed;             /* 1, with bit_depth 1, 2 or 4: rows come as PNG stores them,
                               ceil(width * bit_depth / 8) bytes, the first pixel in the most
                               significant bits (stride 0 means that many bytes) */
    const int32_t *row_spans; /* optional, 2 per row: every byte of row y (as given: pixels for
                               one a byte, bytes for packed rows) outside [row_spans[2y],
                               row_spans[2y+1]) is zero (lo >= hi: the row is all zero); the
                               encoder then reads no byte outside them. Without it the encoder
                               finds them itself for indexed and sub-byte images. */
    int filter_bytes;       /* 1, for rows PNG stores unfiltered (indexed, or packed below 8
                               bits): each row is preceded by a zero byte that is the caller's
                               (pixels[y * stride - 1]) and stride is the row's bytes + 1, so
                               the compressor reads the rows where they lie, with no copy (a
                               tray's plate). Rows whose bytes differ from that are copied. */
} hv_png_options;

/* Defaults: compression -1, no pHYs, no palette, no text, bit depth 8, one pixel a byte, the
 * filter of least cost per row (None for indexed and sub-byte images). */
HV_API void hv_png_options_init(hv_png_options *opt);

/* Encode pixels as PNG. channels: 1 grey (indexed when opt->palette is set; values must
 * then be < palette_size), 2 grey+alpha, 3 RGB, 4 RGBA (straight alpha). `stride` is the byte
 * distance between rows (0: width*channels, times 2 at 16 bits). opt may be NULL.
 * hv_png_write writes the file atomically (temporary name, sync, rename; opt->in_place: see
 * there). hv_png_encode returns a
 * malloc'd buffer in *data (free() it) of *size bytes.
 * One encoder writes every PNG: rows filtered, deflated by libdeflate at opt->compression (zlib's
 * scale, -1 meaning 6), one zlib stream cut into IDAT chunks of 1 MiB; a sparse indexed or
 * sub-byte image (nonzero bytes under a quarter of it, level above 0) goes through a coder whose
 * cost is its nonzero bytes instead (one Huffman block of copies at the distances the image repeats
 * at and literals; environment HOVOX_PNG_SPARSE=0: never).
 * Errors: HV_ERR_INVALID (size 0, channels, stride, compression level, palette, an index
 * beyond the palette, bit depth, a value beyond the bit depth, packed rows of 8 bits or more,
 * bad text key), HV_ERR_IO (path not writable, disk full), HV_ERR_NOMEM, HV_ERR_LIMIT (an image
 * of more than 2^40 bytes). */
HV_API hv_status hv_png_write(const char *path, const uint8_t *pixels, int width, int height,
                              int channels, size_t stride, const hv_png_options *opt);
HV_API hv_status hv_png_encode(const uint8_t *pixels, int width, int height, int channels,
                               size_t stride, const hv_png_options *opt, uint8_t **data,
                               size_t *size);

/* A decoded PNG: every sample widened to 16 bits, rows top to bottom. Palettes become RGB
 * (RGBA with a tRNS chunk), grey of 1, 2 or 4 bits becomes 8-bit grey by bit replication (so
 * value / (2^bit_depth - 1) is the stored value normalised to [0, 1] in every case); gamma
 * and colour chunks are not applied. */
typedef struct hv_png_pixels {
    int width, height;
    int channels;      /* 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA */
    int bit_depth;     /* 8 or 16: samples lie in [0, 2^bit_depth - 1] */
    uint16_t *samples; /* width * height * channels; free with hv_png_pixels_free */
} hv_png_pixels;

/* Decode a PNG held in memory, treated as hostile: the image is refused before its buffer is
 * allocated when it has more than max_samples samples (width x height x channels); ancillary
 * chunks are limited to 8 MiB. `name` prefixes messages. Errors: HV_ERR_BAD_INPUT ("name: not
 * a PNG (no PNG signature)", "name: not a readable PNG: <libpng's reason>": truncated, bad CRC,
 * damaged data), HV_ERR_LIMIT, HV_ERR_NOMEM. On error *out holds nothing. */
HV_API hv_status hv_png_decode(const void *data, size_t size, const char *name, uint64_t max_samples,
                               hv_png_pixels *out);
/* hv_png_decode with flags: HV_PNG_PALETTE_INDICES decodes a palette image as its indices (one
 * channel, 8 bits, one index per pixel whatever the bit depth; no transparency), as a slice stack's
 * halftoned layers hold them (palette index j + 1 = material j). */
#define HV_PNG_PALETTE_INDICES 1
HV_API hv_status hv_png_decode_flags(const void *data, size_t size, const char *name, uint64_t max_samples,
                                     int flags, hv_png_pixels *out);
/* Free the samples; NULL and a zeroed struct are allowed. */
HV_API void hv_png_pixels_free(hv_png_pixels *p);

/* ---- textures: 8-bit RGBA pictures read from PNG or JPEG ---------------------------------- */

/* A decoded picture: width*height pixels of 4 bytes (R, G, B, A; straight alpha; the file's
 * own colour values, no colour management), rows top to bottom. `icc` holds the ICC profile the
 * file embeds (PNG iCCP, JPEG APP2), or is NULL. Free with hv_rgba8_free. */
typedef struct hv_rgba8 {
    int width, height;
    uint8_t *rgba;
    uint8_t *icc;
    size_t icc_size;
} hv_rgba8;

/* Decode a PNG or a JPEG (chosen by signature) held in memory, treated as hostile: refused before
 * the pixels are allocated when width x height exceeds max_pixels. PNG: grey, grey+alpha, RGB,
 * RGBA, palettes (tRNS gives alpha), 16-bit samples rounded to 8. JPEG (libjpeg): grey or YCbCr,
 * opaque; CMYK JPEGs are refused. Errors: HV_ERR_BAD_INPUT ("name: not an image (neither PNG
 * nor JPEG)", "name: not a readable JPEG: <libjpeg's reason>", the PNG decoder's messages),
 * HV_ERR_LIMIT, HV_ERR_NOMEM. On error *out holds nothing. */
HV_API hv_status hv_rgba8_decode(const void *data, size_t size, const char *name, uint64_t max_pixels,
                                 hv_rgba8 *out);
/* Free the pixels and the profile; NULL and a zeroed struct are allowed. */
HV_API void hv_rgba8_free(hv_rgba8 *img);

#ifdef __cplusplus
}
#endif
#endif
