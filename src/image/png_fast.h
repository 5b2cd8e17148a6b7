/* src/image/png_fast.h - PNG for printer layers: grey or indexed images of 1, 2, 4 or 8 bits
 * whose rows are mostly zero (the plate around the parts, the background around a part) and
 * whose content is halftone noise. Not public API; slicing uses it for its stacks. */
#ifndef HOVOX_PNG_FAST_H
#define HOVOX_PNG_FAST_H

#include <stddef.h>
#include <stdint.h>

#include "hovox/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* An image in PNG's own packing: `height` rows of ceil(width * bit_depth / 8) bytes, `stride`
 * bytes apart, pixels packed most significant bits first. Optional `span` (2 per row, may be
 * NULL): every byte of row r outside [span[2r], span[2r+1]) is zero (an empty span, lo >= hi,
 * for a row that is all zero), so zero stretches cost nothing to find. */
typedef struct hv_png_fast_image {
    int width, height;
    int bit_depth;          /* 1, 2, 4 or 8 */
    const uint8_t *rows;
    size_t stride;
    const int32_t *span;
    const uint8_t *palette; /* RGB triples: an indexed image; NULL: grey */
    int palette_size;       /* 1..256 */
    double dpi[2];          /* > 0: a pHYs chunk */
} hv_png_fast_image;

/* Encode as PNG (filter None on every row) with one zlib stream holding one dynamic-Huffman
 * deflate block: a code fitted to the image's own bytes (halftone noise takes about its entropy)
 * and runs of zeros as length-258 copies at distance 1 (an empty row costs a few bits). Decoders
 * read it as any PNG. The bytes depend only on the image. *out is malloc'd (free()).
 * Errors: HV_ERR_INVALID (sizes, bit depth, palette), HV_ERR_NOMEM, HV_ERR_LIMIT (a stream
 * above 2^31 bytes). */
hv_status hv_png_fast_encode(const hv_png_fast_image *img, uint8_t **out, size_t *size);

#ifdef __cplusplus
}
#endif
#endif
