/* slicing/scan_source.h - a scanned volume as a layer source (scan_source.c; issue 30 item 4): its
 * shape and its lookup table's materials evaluated at the printer's pixel centres, no model. Set
 * hv_layers_options.source to hv_scan_source_layers(s) and pass no mesh and no model. */
#ifndef HOVOX_SCAN_SOURCE_H
#define HOVOX_SCAN_SOURCE_H

#include "hovox/colour.h"
#include "hovox/lut.h"
#include "hovox/material.h"
#include "hovox/scan.h"

typedef struct hv_scan_source hv_scan_source;
struct hv_layers_source;

/* The source of `scan` (kept by the caller while the source lives) cut at `shape`, materials from
 * `lut` (NULL: a mask only) with `map` for a colour table. Its box is the inside's
 * (hv_scan_inside_box). Errors: HV_ERR_INVALID (a bad shape, a colour table without a map),
 * HV_ERR_NOMEM, those of hv_material_add. */
hv_status hv_scan_source_open(const hv_scan *scan, const hv_scan_shape *shape, const hv_lut *lut, hv_colour_map *map,
                              hv_scan_source **out);
const struct hv_layers_source *hv_scan_source_layers(const hv_scan_source *s);
/* 1 when `layers VOLUME` with these options prints from the data (a source): no whole-volume
 * clean-up (keep_largest, fill_holes, min_feature), no threshold band, the resample method and no
 * comparison; else the scan's model is made (hv_lut_scan_model) and cut like any model. The CLI's
 * and Lua's one rule. */
struct hv_layers_options;
int hv_scan_prints_direct(const struct hv_layers_options *o, const hv_scan_voxelize_options *so);
/* A colour table's samples for hv_colour_samples_error (hovox/colour.h; issue 30 item 2): per
 * tabulated value (*n of them) its requested sRGB colour, the six fractions it prints and the
 * printer voxels evaluated nearest to it so far (over every layer this process evaluated). Returns 0
 * (nothing set) without a colour table. Owned by the source. */
int hv_scan_source_colour(const hv_scan_source *s, size_t *n, const uint8_t **rgb, const float **fractions,
                          const uint64_t **weight);
/* A source's materials (NULL: a mask only). */
const hv_material_table *hv_layers_source_table(const struct hv_layers_source *src);
void hv_scan_source_close(hv_scan_source *s);

#endif
