/* hovox/lut.h - lookup tables from data values to materials (issue 30): a CSV table maps a scan's
 * value (a Hounsfield unit, an MRI intensity, a simulation's field) to material fractions or to
 * an sRGB colour, linearly interpolated between rows, so bone, soft tissue and air become resins
 * and colours. A colour becomes the six colour resins' fractions through a colour map
 * (hovox/colour.h). src/colour/lut.c.
 *
 * The file (README "Lookup tables"):
 *   # a comment; blank lines are skipped, spaces around fields trimmed, CRLF accepted
 *   HU,VeroClear,Agilus30,VeroWhite       <- header: the value's name, then 1-64 material names
 *   -1000,1,0,0                            <- rows: a value, then each material's fraction
 *   300,0,1,0
 *   1500,0,0,1
 * or, for colour, the header "<value name>,colour" (or "color") and rows "value,#rrggbb" (or
 * "#rrggbbaa"; alpha becomes the clear resin, as everywhere in hovox's colour path).
 * The value's name is 1-32 characters of [A-Za-z0-9_-] ("value", "HU", ...); material names
 * follow hv_material_add (1-64 of [A-Za-z0-9_-], unique). Values rise strictly from row to row;
 * fractions are in [0, 1] and each row's sum to 1 (within 1e-4); at most 4096 rows. A value below
 * the first row takes the first row, one above the last row the last. */
#ifndef HOVOX_LUT_H
#define HOVOX_LUT_H

#include <stddef.h>
#include <stdint.h>

#include "hovox/colour.h"
#include "hovox/core.h"
#include "hovox/scan.h"
#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hv_lut hv_lut;

typedef enum hv_lut_kind {
    HV_LUT_MATERIALS = 0, /* value -> fractions of the named materials */
    HV_LUT_COLOUR = 1     /* value -> an sRGB colour with alpha */
} hv_lut_kind;

#define HV_LUT_MAX_ROWS 4096

/* Parse a table (`name` prefixes every message). Errors: HV_ERR_BAD_INPUT, one message naming
 * the file, the line and the value: "bone.csv: line 4: value 300 is not greater than line 3's
 * (300)", "bone.csv: line 5: fractions sum to 0.9, not 1", "bone.csv: line 6: expected 4 fields
 * (HU and 3 materials), got 3", "bone.csv: line 2: colour '#12' is not #rrggbb or #rrggbbaa",
 * "bone.csv: line 1: header 'HU' needs a value name and at least one material or 'colour'",
 * "bone.csv: line 1: material 'a b' is not 1-64 characters of [A-Za-z0-9_-]", "bone.csv: line 1:
 * material 'x' twice", "bone.csv: line 1: a header and no rows"; HV_ERR_NOMEM. */
HV_API hv_status hv_lut_parse(const char *text, size_t len, const char *name, hv_lut **out);
/* Read and parse a file (at most 16 MiB). Errors: HV_ERR_IO naming the path, those of parse. */
HV_API hv_status hv_lut_load(const char *path, hv_lut **out);
HV_API void hv_lut_destroy(hv_lut *lut);

HV_API hv_lut_kind hv_lut_kind_of(const hv_lut *lut);
/* The header's first field ("HU"); owned by the table. */
HV_API const char *hv_lut_value_name(const hv_lut *lut);
/* Columns hv_lut_eval writes: the materials (HV_LUT_MATERIALS) or 4 (R, G, B, A in [0, 1]). */
HV_API int hv_lut_columns(const hv_lut *lut);
/* Material k's name (NULL for a colour table or k out of range); owned by the table. */
HV_API const char *hv_lut_material(const hv_lut *lut, int k);
HV_API size_t hv_lut_rows(const hv_lut *lut);
/* The first and last rows' values. */
HV_API void hv_lut_range(const hv_lut *lut, double *lo, double *hi);
/* The columns at `value`: linear between the two rows around it, the end rows beyond them. */
HV_API void hv_lut_eval(const hv_lut *lut, double value, float *out);

/* Materials from a scan's values: every occupied voxel of `model` (a model hv_scan_voxelize made
 * from `scan`, or any model in the scan's world coordinates) takes the table at the scan's value
 * interpolated trilinearly at its centre (centres beyond the samples take the nearest edge
 * value). A materials table adds its materials; a colour table the six resins of `map` (the
 * colour's fractions, hv_colour_map_fractions, of the interpolated colour rounded to 8 bits);
 * float grids "material.<name>" over "occupancy" and the material table (hovox/material.h).
 * Memory is planned: HV_ERR_LIMIT over hv_memory_budget(max_memory), saying how much is needed.
 * Errors: HV_ERR_INVALID (a colour table without a map), HV_ERR_NOT_FOUND (no occupancy),
 * HV_ERR_LIMIT, those of hv_volume_grid_set and hv_material_add (the model has materials
 * already), HV_ERR_NOMEM, HV_ERR_CANCELLED. */
HV_API hv_status hv_lut_paint_scan(hv_volume *model, const hv_scan *scan, const hv_lut *lut, hv_colour_map *map,
                                   uint64_t max_memory, const hv_progress *progress);

/* A scan's model with materials: hv_scan_voxelize with `opts` (the shape, voxel size, clean-ups,
 * max_memory, progress), then, when `lut` is given, hv_lut_paint_scan with it and `map` under the
 * same memory limit. What `hovox voxelize VOLUME --lut` writes and `hovox layers VOLUME` prints
 * from. report may be NULL. Errors: those of the two. */
HV_API hv_status hv_lut_scan_model(const hv_scan *scan, const hv_scan_voxelize_options *opts, const hv_lut *lut,
                                   hv_colour_map *map, hv_volume **out, hv_scan_voxelize_report *report);

#ifdef __cplusplus
}
#endif
#endif
