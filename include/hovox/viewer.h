/* hovox/viewer.h - pages a person opens in a web browser to look at what hovox made: a slice
 * stack or tray (every layer at the printer's true aspect, side views through the height, the
 * parts and their fractions) and a graded model (orthogonal slices of the fractions, renders).
 * A page is one HTML file with its script, style and data inside; it needs no network, no
 * server and nothing installed, and it works opened from file://. */
#ifndef HOVOX_VIEWER_H
#define HOVOX_VIEWER_H

#include <stddef.h>
#include <stdint.h>

#include "hovox/core.h"
#include "hovox/options.h"
#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ==== options ================================================================================ */

typedef struct hv_viewer_options {
    const char *title;    /* the page's title; NULL: the stack directory's or the model's name */
    int cuts;             /* stacks: side-view cuts per axis and part, evenly spaced rows and
                             columns (default 32; an image with fewer rows or columns gets one per
                             row or column) */
    uint64_t max_samples; /* stacks: side-view samples (pixels x layers x channels) embedded at
                             most; models: slice samples (voxels x (materials + 1)) embedded at
                             most (default 48M). Past it stacks get fewer cuts (down to 4), then
                             every s-th pixel and layer; models fewer slices, then every q-th
                             voxel in the slice's plane */
    int size[2];          /* models: the renders' size in pixels (default 480 x 360) */
    int no_renders;       /* models: 1 leaves the renders out (default 0: four renders) */
} hv_viewer_options;

/* Defaults as noted above. */
HV_API void hv_viewer_options_init(hv_viewer_options *o);

/* The options as an option set (hovox/options.h): keys title, cuts, max_samples, size and
 * no_renders. Static data. */
HV_API const hv_option_set *hv_viewer_option_set(void);

/* ==== what a page shows ======================================================================= */

typedef enum hv_viewer_kind {
    HV_VIEWER_STACK = 0, /* hovox layers */
    HV_VIEWER_TRAY = 1,  /* hovox tray */
    HV_VIEWER_MODEL = 2  /* a .vdb or .3mf model */
} hv_viewer_kind;

typedef struct hv_viewer_report {
    hv_viewer_kind kind;
    /* stacks and trays */
    const char *mode;      /* "halftone", "fractions" or "mask" (static text) */
    int width, height;     /* pixels of a layer */
    double pixel_mm[2];    /* x pitch and y pitch (y negative: rows run down in y) */
    size_t layers;         /* layers in the stack */
    int channels;          /* PNG files per layer (fractions: one per material) */
    int parts;             /* trays: placed parts; stacks: 1 */
    int cut_rows, cut_cols;/* side-view cuts per part (rows, columns) */
    int cut_step;          /* 1: every pixel and layer; s: every s-th */
    uint64_t samples;      /* side-view samples embedded */
    /* models */
    int dims[3];           /* voxels of the occupied box */
    double voxel[3];       /* voxel size */
    int materials;
    int slices[3];         /* slices embedded per axis (x, y, z) */
    int slice_step;        /* 1: every voxel of a slice; q: every q-th */
    int render_count;      /* renders embedded */
    /* both */
    uint64_t bytes;        /* of the page */
    char base[1024];       /* the stack's directory as the page reaches it ("" when the page is
                              inside it, "../gear_j750/"), so its layers load from there */
    char warnings[2048];   /* what a person should know, one line each ("" if none) */
} hv_viewer_report;

/* ==== stacks and trays ========================================================================
 *
 * Write a page for the slice stack in directory `stack_dir` (manifest.json and its layers, as
 * hovox layers or hovox tray write them) to `html_path` (.html), written atomically. The page
 * loads the stack's layer PNGs from their place, by paths relative to the page (no copy):
 * moving the page and the stack together keeps it working; `html_path`'s directory must exist.
 * Every layer is read once (threads over layers): each must be the PNG the manifest says (size,
 * bit depth, colour type); what the page needs pixels for is taken from them and embedded,
 * since a page opened from file:// may draw but not read images from other files: the side
 * views (cuts through the stack at rows and columns, see hv_viewer_options), each part's
 * outline (the union of its object pixels over its layers, traced on a grid of at most 1024
 * cells a side) and the palette. A layer's pHYs that disagrees with the manifest's pixel size
 * is a warning (the page draws the manifest's).
 * `report` (may NULL) receives what was written. Progress stage "view".
 * Errors: HV_ERR_IO (stack_dir missing or unreadable, a layer missing, the page not writable;
 * naming the file), HV_ERR_BAD_INPUT (no manifest.json: not a stack; a manifest that does not
 * parse or lacks what a page needs, naming the key; a layer that is not the PNG the manifest
 * says), HV_ERR_INVALID (options, html_path not ending in .html), HV_ERR_LIMIT (a layer larger
 * than the memory budget allows), HV_ERR_NOMEM, HV_ERR_CANCELLED. Nothing is written on error. */
HV_API hv_status hv_viewer_stack_write(const char *stack_dir, const char *html_path,
                                       const hv_viewer_options *opt, const hv_progress *progress,
                                       hv_viewer_report *report);

/* The step layers and trays take to write their page with the stack (an hv_stack_finish_fn,
 * hovox/layers.h: hv_layers_options.finish, hv_tray_options.finish): `tmp`/index.html, the page of
 * the stack in its temporary directory, titled with the last component of `dir`, with default
 * options. `user` (may be NULL) is an hv_viewer_report that receives the page's report. Errors:
 * those of hv_viewer_stack_write. */
HV_API hv_status hv_viewer_stack_finish(void *user, const char *tmp, const char *dir, const hv_progress *progress);

/* ==== models ==================================================================================
 *
 * Write a page for a graded model to `html_path`: for each axis, slices of the occupied box
 * through voxel centres (all of them, or evenly spaced ones within max_samples), each carrying
 * the occupancy and every material's fraction quantised to 8 bits, which the page composites as
 * sum p_j colour_j / sum p_j of the materials' display colours (as hv_render colours a voxel)
 * and reads back under the pointer; and renders of the model (surface, a cut-away, a
 * translucent volume, a cut at mid-height seen from the top). `vol` as hv_render_volume_load
 * reads it (occupancy and material grids); `name` titles the page (may be NULL).
 * Errors: HV_ERR_BAD_INPUT (no occupied voxels, a damaged material table), HV_ERR_INVALID,
 * HV_ERR_IO, HV_ERR_LIMIT, HV_ERR_NOMEM, HV_ERR_CANCELLED; those of hv_render. Nothing is
 * written on error. */
HV_API hv_status hv_viewer_model_write(const hv_volume *vol, const char *name, const char *html_path,
                                       const hv_viewer_options *opt, const hv_progress *progress,
                                       hv_viewer_report *report);

#ifdef __cplusplus
}
#endif
#endif
