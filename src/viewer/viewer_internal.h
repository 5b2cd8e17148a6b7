/* src/viewer/viewer_internal.h - pieces of the viewer pages shared between its files and the
 * tests (not public): a stack's manifest read into what a page needs, outlines of bitmaps,
 * base64, and the page itself (the embedded HTML, CSS and JavaScript around a data document). */
#ifndef HOVOX_VIEWER_INTERNAL_H
#define HOVOX_VIEWER_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "core/internal.h"
#include "core/json.h"
#include "hovox/layers.h"
#include "hovox/viewer.h"

/* ---- a stack's manifest (manifest.c) ---------------------------------------------------------- */

/* A part: a tray's placed instance, or the whole image of a `hovox layers` stack. */
typedef struct vw_part {
    const char *name;      /* borrowed from the manifest */
    int copy;              /* trays: the copy number (1, 2, ...); stacks: 0 */
    int box[4];            /* its image on the layer: column, row, width, height (inside the layer) */
    size_t l0, l1;         /* its layers: positions [l0, l1) in the stack's list (may be empty) */
    const json_t *info;    /* trays: the manifest's part object; stacks: NULL */
} vw_part;

typedef struct vw_stack {
    json_t *doc;           /* the manifest (owns the strings below) */
    int tray;              /* kind "tray" */
    hv_layers_mode mode;   /* halftone, fractions (not in a tray) or mask */
    int width, height;     /* pixels of every layer */
    int bit_depth;         /* of the layer PNGs: 1, 2, 4 or 8 */
    double pixel_mm[2];    /* x pitch > 0, y pitch != 0 (negative: rows run down in y) */
    double origin_mm[2];   /* pixel (c, r) centre: origin + (c + 0.5, r + 0.5) * pixel */
    double dpi[2];
    double layer_height;   /* mm */
    size_t nlayers;        /* layers listed (the range written) */
    size_t *index;         /* per layer: global index */
    double *z;             /* per layer: the cutting plane's height (mm) */
    int channels;          /* PNG files per layer: fractions: one per material; else 1 */
    const char **files;    /* nlayers * channels paths relative to the stack (layer li, channel
                              ch at li * channels + ch), checked by vw_path_ok */
    char *names;           /* trays: storage of the generated file names */
    int nchannel_names;
    const char **channel;  /* fractions: the materials' names (channels of them) */
    uint8_t (*channel_rgb)[3];
    int nparts;
    vw_part *parts;
    const char *mesh;      /* stacks: the manifest's mesh (may be NULL) */
} vw_stack;

/* Read `size` bytes of manifest.json (`name` in messages) into *out. Everything the page will
 * use is checked: generator hovox, mode, sizes, pixel pitch, layers (paths relative to the stack
 * that stay inside it: no "..", no leading '/', no control characters or backslashes), a tray's
 * parts (boxes inside the plate), colours "#rrggbb". Errors: HV_ERR_BAD_INPUT naming the file,
 * the key and the value; HV_ERR_NOMEM. On error *out holds nothing; else free with
 * vw_stack_free. */
hv_status vw_stack_parse(const char *text, size_t size, const char *name, vw_stack *out);
void vw_stack_free(vw_stack *s);
/* 1 when `path` is a relative path inside a directory, as vw_stack_parse requires. */
int vw_path_ok(const char *path);
/* "#rrggbb" (exactly) into rgb; 0 when it is not one. */
int vw_color_parse(const char *text, uint8_t rgb[3]);

/* ---- outlines (outline.c) ---------------------------------------------------------------------- */

/* The boundary of the set cells of a w x h bitmap (cells[y * w + x] != 0, row 0 first) as closed
 * loops of cell corners: corner (x, y) is the top-left corner of cell (x, y). Each loop keeps the
 * set cells on its right as it is walked in image coordinates (x right, y down): outer
 * boundaries run clockwise on screen, holes counter-clockwise; diagonal neighbours are separate
 * (4-connected). Collinear corners are dropped. *xy holds the corners (x, y pairs) of all loops
 * one after another, *starts[i] is loop i's first corner and *starts[nloops] the total. Free
 * both with free(). Errors: HV_ERR_NOMEM, HV_ERR_LIMIT (sizes past 2^30 cells). */
hv_status vw_outline_trace(const uint8_t *cells, int w, int h, int32_t **xy, size_t **starts,
                           size_t *nloops);

/* ---- base64 and the page (page.c) ----------------------------------------------------------------- */

/* "data:<mime>;base64,<data>" appended to b. */
void vw_data_uri(hv_buf *b, const char *mime, const uint8_t *data, size_t size);
/* A JSON value as the page's data: serialised with every '<' written as \u003c, so nothing in
 * it can close the <script> element that holds it. NULL when out of memory (recorded). */
char *vw_json_for_script(const json_t *doc);
/* The page: the embedded template with `title` (HTML-escaped), the style, the data document and
 * the script, written atomically to `path`. *bytes (may be NULL) receives its size. Errors:
 * HV_ERR_IO naming the path, HV_ERR_NOMEM. */
hv_status vw_page_write(const char *path, const char *title, const char *data_json, uint64_t *bytes);
/* The start of every page: *opt (NULL: the defaults, kept in *defaults) checked, and html_path
 * ending in .html. Errors: HV_ERR_INVALID naming the option or the path. */
hv_status vw_page_begin(const hv_viewer_options **opt, hv_viewer_options *defaults, const char *html_path);
/* Add a line to a report's warnings (truncated when full). */
void vw_warn(hv_viewer_report *r, const char *fmt, ...) HV_PRINTF(2, 3);

/* The assets, embedded by the build from src/viewer/assets/ (scripts/embed.sh writes
 * <build>/gen/viewer_assets.c), NUL-terminated. */
extern const unsigned char vw_asset_page_html[], vw_asset_viewer_css[], vw_asset_viewer_js[];

#endif
