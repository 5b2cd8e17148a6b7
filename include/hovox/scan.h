/* hovox/scan.h - scanner and simulation volumes: NIfTI-1/2 (.nii, .nii.gz), NRRD (.nrrd, .nhdr),
 * MetaImage (.mha, .mhd) and DICOM series (a directory of slices) read into one dense scalar
 * field with its index-to-world affine, in millimetres and RAS coordinates (src/io/scan/).
 *
 * World coordinates. hovox's world for scans is RAS+ (+x toward the patient's right, +y anterior,
 * +z superior), NIfTI's convention: NIfTI's sform or
 * qform is taken as it is; DICOM, MetaImage (ITK's physical space) and NRRD files whose space
 * is left-posterior-superior are LPS+ and become RAS+ by negating x and y. A head thus prints
 * standing, its top at +z. Lengths in metres or micrometres are scaled to millimetres. */
#ifndef HOVOX_SCAN_H
#define HOVOX_SCAN_H

#include <stddef.h>
#include <stdint.h>

#include "hovox/core.h"
#include "hovox/options.h"
#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hv_scan hv_scan;

typedef enum hv_scan_format {
    HV_SCAN_NIFTI1 = 1, /* .nii, .nii.gz */
    HV_SCAN_NIFTI2,     /* .nii, .nii.gz */
    HV_SCAN_NRRD,       /* .nrrd (attached data), .nhdr (detached) */
    HV_SCAN_METAIMAGE,  /* .mha (attached), .mhd (detached) */
    HV_SCAN_DICOM       /* a directory of single-frame slices of one series */
} hv_scan_format;

/* Reading options. */
typedef struct hv_scan_options {
    uint64_t max_memory; /* bytes the data may take (0: hv_memory_budget's default) */
} hv_scan_options;

/* The option set (key max_memory) and defaults. */
HV_API const hv_option_set *hv_scan_option_set(void);
HV_API void hv_scan_options_init(hv_scan_options *opts);

/* What was read, for reports. Strings are owned by the scan. */
typedef struct hv_scan_info {
    hv_scan_format format;
    const char *format_name;  /* "NIfTI-1", "NIfTI-2", "NRRD", "MetaImage", "DICOM series" */
    const char *sample_type;  /* the file's sample type: "int16", "uint8", "float32", ... */
    const char *encoding;     /* "raw", "gzip", "zlib", "ascii" */
    const char *space;        /* where the affine came from: "sform (scanner)", "qform (aligned)",
                                 "LPS -> RAS", "pixdim only", ... */
    const char *unit;         /* value unit: "HU" for CT DICOM, else "" */
    double slope, intercept;  /* value = stored * slope + intercept (1, 0 when none) */
    double value_min, value_max; /* over every voxel (after scaling) */
    size_t files;             /* files read (a DICOM series: its slices; .nhdr/.mhd: 2) */
} hv_scan_info;

/* 1 when `path` names a scan by its form: a file ending in .nii, .nii.gz, .nrrd, .nhdr, .mha or
 * .mhd (case-insensitive), or a directory (a DICOM series). Touches the file system only to
 * tell a directory. */
HV_API int hv_scan_path_is_scan(const char *path);

/* Read a scan (the format by the name's extension; a directory is a DICOM series). Every voxel's
 * value becomes a float (scaled as the file says: NIfTI scl_slope/scl_inter, DICOM rescale slope
 * and intercept, giving Hounsfield units for CT). The data's size (4 bytes a voxel) is checked
 * against hv_memory_budget(opts->max_memory) before anything is allocated. Input is hostile:
 * sizes, offsets and counts are checked against the file before they are used. opts may be NULL.
 * Errors: HV_ERR_IO (missing, unreadable), HV_ERR_BAD_INPUT (malformed, truncated, a header
 * that lies about sizes, an unsupported sample type or encoding, a DICOM series with gaps,
 * mixed sizes or orientations, or several series; one message naming the file, the place and
 * the value), HV_ERR_LIMIT (over the memory budget, saying how much is needed),
 * HV_ERR_NOMEM, HV_ERR_UNSUPPORTED (a compressed DICOM transfer syntax, bzip2 NRRD).
 * Free with hv_scan_destroy. */
HV_API hv_status hv_scan_load(const char *path, const hv_scan_options *opts, hv_scan **out);

/* Parse a scan held in memory: the attached forms only (.nii or .nii.gz bytes, .nrrd, .mha, or
 * one DICOM slice as a series of one). `name` (for messages) is also what tells the format by
 * its extension ("x.nii", "x.nrrd", "x.mha", "x.dcm"). Errors: those of hv_scan_load. */
HV_API hv_status hv_scan_parse(const void *data, size_t size, const char *name,
                               const hv_scan_options *opts, hv_scan **out);

/* Free; NULL is allowed. */
HV_API void hv_scan_destroy(hv_scan *scan);

/* Samples along i, j, k. */
HV_API void hv_scan_dims(const hv_scan *scan, size_t dims[3]);
/* The values, i fastest: value(i, j, k) = data[i + nx * (j + ny * k)]. Owned by the scan. */
HV_API const float *hv_scan_data(const hv_scan *scan);
/* The index-to-world affine, 3x4 row-major (as hv_mesh_transform): the centre of sample (i,j,k)
 * is at world x = m[0] i + m[1] j + m[2] k + m[3], y = m[4] i + ..., z = m[8] i + ... + m[11]
 * (RAS, mm). */
HV_API void hv_scan_affine(const hv_scan *scan, double m[12]);
HV_API const hv_scan_info *hv_scan_get_info(const hv_scan *scan);
/* The path (or name) it was read from; owned by the scan. */
HV_API const char *hv_scan_name(const hv_scan *scan);

/* Move the scan in the world: x' = A x + t for every sample centre, `a` 3x4 row-major as
 * hv_mesh_transform takes it (a placement's matrix, a quarter turn on a tray). The samples stay.
 * Errors: HV_ERR_INVALID (a non-finite or singular map; the scan is unchanged). */
HV_API hv_status hv_scan_transform(hv_scan *scan, const double a[12]);

/* ==== the shape of a scan ======================================================================
 * Which part of the field is solid: the level function g >= 0, evaluated by trilinear
 * interpolation of the samples at any world point (not blocky thresholding), so the surface sits
 * between samples where the data says. */
typedef enum hv_scan_select {
    HV_SCAN_SELECT_ISO = 0,   /* value >= iso */
    HV_SCAN_SELECT_RANGE = 1, /* lo <= value <= hi */
    HV_SCAN_SELECT_LABELS = 2 /* a segmentation's labels: the interpolated indicator of "the
                                 sample's label is in the set" >= 1/2 (labels never average) */
} hv_scan_select;

typedef struct hv_scan_shape {
    hv_scan_select select;
    double iso;
    double range[2];
    const int32_t *labels; /* label_count of them (1..65536); the caller's */
    size_t label_count;
} hv_scan_shape;

/* A segmentation's label list as text, "1,2,5" (integers of 32 bits, 1 to 65536 of them), into
 * *labels (malloc'd, *count of them; free() it). Errors: HV_ERR_INVALID naming {labels} ("{labels}
 * must be integers A,B,..., got '1,x'", "{labels} must name at least one label"), HV_ERR_NOMEM. */
HV_API hv_status hv_scan_labels_parse(const char *text, int32_t **labels, size_t *count);

/* ==== a model from a scan, no mesh (src/voxel/scan_voxelize.c) ==================================== */
typedef struct hv_scan_voxelize_options {
    hv_scan_shape shape;
    double voxel_size[3]; /* mm; voxel_size[0] == 0: cubic voxels of the scan's smallest spacing */
    int keep_largest;     /* keep the largest 6-connected part only */
    int fill_holes;       /* fill every cavity (empty parts that do not reach the grid's border) */
    double min_feature;   /* mm (0: none): parts and cavities smaller than a ball of this
                             diameter are dropped and filled */
    uint64_t max_memory;  /* bytes (0: hv_memory_budget's default) */
    const hv_progress *progress;
} hv_scan_voxelize_options;

typedef struct hv_scan_voxelize_report {
    int64_t first[3], dims[3]; /* the lattice box (voxel index space) */
    double voxel[3];
    uint64_t occupied, surface;
    double volume;             /* occupied voxels times the voxel volume, mm^3 */
    uint64_t dropped_parts, dropped_voxels, filled_cavities, filled_voxels;
} hv_scan_voxelize_report;

/* Defaults: iso 0, the scan's smallest spacing, nothing cleaned. */
HV_API void hv_scan_voxelize_options_init(hv_scan_voxelize_options *opts);
/* The options as one table for Lua (hovox.voxelize_scan) and job files: keys iso, range (the
 * selection follows which one is given: range makes it RANGE; both given are refused),
 * voxel_size (L or X,Y,Z mm), keep_largest, fill_holes, min_feature (mm), max_memory. Labels
 * (a list) are read by the front end. Static data. */
HV_API const hv_option_set *hv_scan_voxelize_option_set(void);

/* The model: a voxel (on the global lattice of hv_voxelize with a voxel size: centres at
 * (n + 1/2) L, world RAS mm) is occupied when g >= 0 at its centre; then min_feature, keep_largest
 * and fill_holes in that order. Bool grids "occupancy" and "surface" (occupied voxels with an
 * empty 6-neighbour), and the geometry record (hovox/geometry.h): one FIELD_ISO leaf holding the
 * samples and the shape, its transform the scan's affine, so layers, trays and contours cut the
 * iso-surface itself (hovox/solid.h). report may be NULL. Errors: HV_ERR_INVALID (shape or
 * options out of range, naming the option), HV_ERR_LIMIT (over max_memory, saying how much),
 * HV_ERR_NOMEM, HV_ERR_CANCELLED. Free the volume with hv_volume_destroy. */
HV_API hv_status hv_scan_voxelize(const hv_scan *scan, const hv_scan_voxelize_options *opts, hv_volume **out,
                                  hv_scan_voxelize_report *report);

#ifdef __cplusplus
}
#endif
#endif
