/* src/io/scan/scan_internal.h - what the scan readers share (scan.c): the scan itself, a byte
 * source (a file or memory, optionally inflated), sample types and their conversion to float,
 * the memory budget, header-text helpers. Internal. */
#ifndef HOVOX_SCAN_INTERNAL_H
#define HOVOX_SCAN_INTERNAL_H

#include <stdio.h>
#include <zlib.h>

#include "core/internal.h"
#include "hovox/scan.h"

struct hv_scan {
    char *name;
    size_t dims[3];
    float *data;
    double m[12];
    hv_scan_info info;
    char sample_type[16], encoding[16], space[96], unit[24];
};

/* ---- sample types --------------------------------------------------------------------------- */
typedef enum scan_type {
    SCAN_NONE = 0, SCAN_U8, SCAN_I8, SCAN_U16, SCAN_I16, SCAN_U32, SCAN_I32, SCAN_U64, SCAN_I64,
    SCAN_F32, SCAN_F64
} scan_type;
size_t scan_type_size(scan_type t);
const char *scan_type_name(scan_type t);

/* ---- a byte source -------------------------------------------------------------------------- */
typedef struct scan_src {
    const char *name;        /* for messages */
    FILE *fp;                /* a file, or */
    const uint8_t *mem;      /* memory */
    uint64_t size, pos;      /* raw size and position */
    int inflating;           /* bytes pass through zlib (gzip or zlib streams) */
    z_stream zs;
    uint8_t *zin;            /* inflate's input buffer */
    int zend;                /* the compressed stream ended */
    uint64_t out;            /* bytes delivered so far (after inflating) */
} scan_src;

/* Open a file at raw offset `offset`. Errors: HV_ERR_IO naming the path. */
hv_status scan_src_open_file(scan_src *s, const char *path, const char *name, uint64_t offset);
/* Memory from `offset` (clamped to size). */
void scan_src_open_mem(scan_src *s, const uint8_t *data, size_t size, const char *name, uint64_t offset);
/* From now on the bytes are a zlib or gzip stream, inflated (windowBits 15 + 32). */
hv_status scan_src_inflate(scan_src *s);
/* Up to n bytes; *got < n only at the end of the data. Errors: HV_ERR_BAD_INPUT (damaged
 * compressed stream), HV_ERR_IO. */
hv_status scan_src_read(scan_src *s, void *buf, size_t n, size_t *got);
/* Raw bytes left (meaningful when not inflating). */
uint64_t scan_src_left(const scan_src *s);
void scan_src_close(scan_src *s);
/* After the data: an inflated stream must have reached its end (a gzip or zlib stream cut before
 * its end marker and checksum is truncated). Errors: HV_ERR_BAD_INPUT. */
hv_status scan_src_end(scan_src *s);

/* ---- the data ------------------------------------------------------------------------------- */
/* Check the budget for dims and allocate scan->data; dims are the header's (checked > 0).
 * Errors: HV_ERR_LIMIT (naming {max_memory}), HV_ERR_BAD_INPUT (a product that overflows),
 * HV_ERR_NOMEM. */
hv_status scan_alloc(hv_scan *scan, const size_t dims[3], const hv_scan_options *opts);
/* Read count samples of type t (big: big-endian) from s into out, as value * slope + intercept.
 * A source that ends early: HV_ERR_BAD_INPUT "NAME: truncated: the data ends after A of B
 * bytes"; a value that is NaN or infinite after scaling is refused naming the sample. */
hv_status scan_read_samples(scan_src *s, scan_type t, int big, double slope, double intercept,
                            float *out, size_t count);
/* Convert count samples from memory (bytes at p). */
void scan_convert(const uint8_t *p, scan_type t, int big, double slope, double intercept, float *out,
                  size_t count);
/* After the data is in: value range, sample type, encoding names. Refuses non-finite values. */
hv_status scan_finish(hv_scan *scan);
/* An affine must be finite and invertible: HV_ERR_BAD_INPUT naming `what` otherwise. */
hv_status scan_check_affine(const hv_scan *scan, const char *what);
/* RAS from LPS: negate the x and y rows. */
void scan_lps_to_ras(double m[12]);

/* ---- the readers ------------------------------------------------------------------------------
 * path: the file (NULL when reading from memory: mem/size); name for messages. */
hv_status scan_read_nifti(hv_scan *scan, const char *path, const uint8_t *mem, size_t size,
                          const hv_scan_options *opts);
hv_status scan_read_nrrd(hv_scan *scan, const char *path, const uint8_t *mem, size_t size,
                         const hv_scan_options *opts);
hv_status scan_read_metaimage(hv_scan *scan, const char *path, const uint8_t *mem, size_t size,
                              const hv_scan_options *opts);
hv_status scan_read_dicom_dir(hv_scan *scan, const char *dir, const hv_scan_options *opts);
hv_status scan_read_dicom_mem(hv_scan *scan, const uint8_t *mem, size_t size, const hv_scan_options *opts);

/* ---- header text (NRRD, MetaImage) ----------------------------------------------------------- */
/* Up to `max` bytes of the start of a file or memory, NUL-terminated (caller frees). */
hv_status scan_head(const char *path, const uint8_t *mem, size_t size, size_t max, char **text, size_t *len);
/* Parse n numbers separated by spaces, commas or parentheses as NRRD and MetaImage write them;
 * returns how many were read (stops at n); *end after the last. Non-finite numbers stop it. */
int scan_numbers(const char *s, double *v, int n, const char **end);
/* A detached data file named in a header: relative to the header's directory (caller frees). */
char *scan_sibling(const char *header_path, const char *file);



/* For reports: the spacing along each index axis, the nearest anatomical code of each axis
 * ("RAS", "LPS", ...) and the world box of the voxel cells (RAS, mm). */
void hv_scan_geometry(const hv_scan *scan, double spacing[3], char axes[4], double lo[3], double hi[3]);
/* ---- the level function (level.c) --------------------------------------------------------------- */
typedef struct hv_scan_level {
    const hv_scan *scan;
    hv_scan_shape shape;
    int32_t *labels; /* sorted copy */
    int64_t n[3];
    double inv[9];   /* the affine's 3x3 part inverted */
} hv_scan_level;
/* Errors: HV_ERR_INVALID naming {iso}, {range} or {labels}; HV_ERR_NOMEM. Free with _free. */
hv_status hv_scan_level_init(const hv_scan *scan, const hv_scan_shape *shape, hv_scan_level *lv);
void hv_scan_level_free(hv_scan_level *lv);
/* World -> continuous sample index. */
void hv_scan_level_index(const hv_scan_level *lv, const double world[3], double idx[3]);
/* g at a sample index / a world point: >= 0 inside; -INFINITY outside the samples' cells. */
double hv_scan_level_at_index(const hv_scan_level *lv, const double idx[3]);
double hv_scan_level_at(const hv_scan_level *lv, const double world[3]);

/* The box (world, mm) of the inside g >= 0: every inside sample's crossings toward its outside
 * neighbours (half a sample beyond the data's last samples) through the affine, so a rotated grid
 * gives the box of the shape, not of its index box turned; all 0 when nothing is inside. On
 * hv_threads() threads. Errors: HV_ERR_NOMEM. */
hv_status hv_scan_inside_box(const hv_scan_level *lv, double lo[3], double hi[3]);

/* ---- a FIELD_ISO leaf's raw data (pack.c) --------------------------------------------------------- */
hv_status hv_scan_pack(const hv_scan *scan, const hv_scan_shape *shape, uint8_t **data, size_t *size);
/* A scan (samples and affine) and its shape from packed data; *labels holds the labels shape
 * points at (free it after the scan). Errors: HV_ERR_BAD_INPUT naming `name`, HV_ERR_NOMEM. */
hv_status hv_scan_unpack(const uint8_t *data, size_t size, const char *name, const double affine[12], hv_scan **out,
                         hv_scan_shape *shape, int32_t **labels);

#endif
