/* slicing/layers_internal.h - pieces of the printer-layer pipeline shared between its files
 * and the tests (not public): separable POI axis operators, halftoning kernels, the stack
 * directory, manifest and GCVF zip writers. */
#ifndef HOVOX_LAYERS_INTERNAL_H
#define HOVOX_LAYERS_INTERNAL_H

#include <stdint.h>
#include <stdio.h>

#include "hovox/layers.h"
#include "hovox/dist.h"
#include "hovox/material.h"

/* ---- POI (poi.c) ---------------------------------------------------------------------------
 * One axis of a separable area-weighted operator: output cell o averages input cells
 * start[o] .. start[o] + len[o] - 1 with weights w[off[o] ...] (summing to 1). Every area
 * weighted operator has contiguous support, and so has any composition of them. */
typedef struct hv_poi_axis {
    int n_in, n_out;
    int *start, *len;
    size_t *off;
    double *w;
    int steps; /* exact POI steps composed into this operator */
} hv_poi_axis;

void hv_poi_axis_free(hv_poi_axis *ax);

/* One exact step: input cells [in_lo + i * in_pitch, in_lo + (i + 1) * in_pitch], i < n_in
 * (in_pitch > 0); output cell o covers [min(a, b), max(a, b)] with a = out_origin +
 * o * out_pitch, b = a + out_pitch (out_pitch may be negative). Weight = overlap / (sum of
 * the cell's overlaps). An output cell outside the input takes the nearest input cell. */
hv_status hv_poi_axis_step(double in_lo, double in_pitch, int n_in, double out_origin,
                           double out_pitch, int n_out, hv_poi_axis *ax);

/* Wu's repeated resampling along one axis: from the input cells to the output cells through
 * intermediate grids that cover the input extent, each at most max_ratio times finer than the
 * previous one (up-sampling only; max_ratio <= 1 or down-sampling: one step), composed into
 * one operator. */
hv_status hv_poi_axis_chain(double in_lo, double in_pitch, int n_in, double out_origin,
                            double out_pitch, int n_out, double max_ratio, hv_poi_axis *ax);

/* c = b o a (apply a, then b); b->n_in must equal a->n_out. */
hv_status hv_poi_axis_compose(const hv_poi_axis *b, const hv_poi_axis *a, hv_poi_axis *c);

/* Apply x then y operators to a src image (ax->n_in x ay->n_in floats, rows first) giving
 * ax->n_out x ay->n_out floats. tmp holds ay->n_in * ax->n_out doubles. */
void hv_poi_apply(const hv_poi_axis *ax, const hv_poi_axis *ay, const float *src, float *dst,
                  double *tmp);

/* ---- halftoning (halftone.c) ---------------------------------------------------------------- */

/* 64-bit mix (splitmix64 finaliser) for seeds and per-pixel noise. */
uint64_t hv_hash64(uint64_t x);

/* Blue-noise offsets derived from a seed (x, y, z within the tile). */
void hv_bluenoise_offsets(uint64_t seed, int off[3]);

/* Blue-noise halftone of one layer: frac holds m planes of w*h floats (plane j at j*w*h),
 * inside the object mask (1 = object). out[y*w+x] = 0 outside, else 1 + chosen material.
 * `layer` is the global layer index, off the seed's tile offset. counts[j] += pixels given j;
 * tsum (may be NULL) += the fractions summed over the object pixels. */
void hv_halftone_bluenoise(const float *frac, int m, int w, int h, const uint8_t *mask,
                           const uint32_t *ranks, const int off[3], size_t layer, uint8_t *out,
                           uint64_t *counts, double *tsum);

/* Vector error diffusion of one layer. err: m planes of w*h floats holding the error carried
 * into this layer (read and cleared); next: m planes receiving the share for the next layer
 * (added to). `serp` picks the direction of row 0. counts and tsum as above. */
void hv_halftone_diffuse(const float *frac, int m, int w, int h, const uint8_t *mask,
                         float *err, float *next, int serp, uint8_t *out, uint64_t *counts,
                         double *tsum);

/* Seeded zero-sum start error of a block of layers (m planes of w*h floats). */
void hv_halftone_seed_error(float *err, int m, int w, int h, uint64_t seed, size_t block);

/* Start a block of error diffusion on its first layer (frac, mask): the seeded error, then two
 * discarded passes so the carried error is in its steady state; *err and *next are swapped as
 * the passes go (use them afterwards as returned). scratch: w*h bytes. */
void hv_halftone_diffuse_start(const float *frac, int m, int w, int h, const uint8_t *mask,
                               float **err, float **next, uint64_t seed, size_t block, int serp,
                               uint8_t *scratch);

/* ---- the stack on disk (stack.c) ------------------------------------------------------------ */

/* Is `text` (size bytes) the manifest.json of a hovox stack: a JSON object whose "generator"
 * is a string starting with "hovox"? HV_OK when it is; else HV_ERR_BAD_INPUT saying why
 * ("manifest.json: line 3, column 1: ...", "manifest.json: generator is \"slic3r\", not
 * hovox"), HV_ERR_NOMEM. */
hv_status hv_stack_manifest_check(const char *text, size_t size);

/* ---- a source in place of a model (issue 30) ------------------------------------------------
 * The shape and the materials evaluated straight at the printer's pixel centres, layer by layer,
 * with no model: a scanned volume printed from its data (slicing/scan_source.c). The job takes
 * its box, materials and name from it; per layer `layer` fills the object mask (W*H bytes, 1 =
 * object, every byte written) and, when frac is not NULL, the materials' fractions at the object
 * pixels (m planes of `plane` floats). Called from several threads at once. */
typedef struct hv_layers_source {
    double bbox_min[3], bbox_max[3]; /* the shape's box (mm) */
    const hv_material_table *table;  /* its materials (NULL: mask only) */
    const char *name;                /* the shape's name in the manifest */
    uint64_t memory;                 /* bytes it holds (the data) */
    hv_status (*layer)(const struct hv_layers_source *src, double z, const hv_raster_grid *grid, uint8_t *mask,
                       float *frac, size_t plane);
    void *user;
} hv_layers_source;

/* ---- parts on a plate (trays) ---------------------------------------------------------------- */

/* Where a part's image sits: the centre of its mesh's xy box at (x, y) mm on a plate whose far
 * edge is y = plate_y (row 0), and `lift` tray layers below its first layer. */
typedef struct hv_layers_place {
    double x, y, plate_y;
    size_t lift;
    double plate_x;     /* the plate's width (mm): the part's box must lie on the plate */
    const char *plate;  /* the plate's name in messages ("j750") */
    int tray;           /* a tray's part: rendered in its threads' scratch (hv_layers_scratch),
                           which the tray counts; the part's plan counts one worker */
} hv_layers_place;

/* One part of a tray: the single-part job planned on the plate, rendering layers into a
 * caller's scratch instead of files. */
typedef struct hv_layers_part hv_layers_part;
/* A thread's buffers for rendering parts one after another (a tray thread renders the parts' layers
 * in flight in turn): the printer-resolution buffers grow to the largest part's need and are
 * shared, so a thread holds one part's images, not one set per part; the voxel slabs are the
 * parts' own (hv_layers_part_prepare). Not thread-safe: one per thread. */
typedef struct hv_layers_scratch hv_layers_scratch;
hv_layers_scratch *hv_layers_scratch_create(void);
void hv_layers_scratch_destroy(hv_layers_scratch *s);
/* Planning one scratch for a set of parts rendered in turn (a tray's threads): per buffer the
 * largest part's bytes. */
typedef struct hv_layers_scratch_need {
    uint64_t bytes[16];
} hv_layers_scratch_need;
void hv_layers_scratch_need_add(hv_layers_scratch_need *n, const hv_layers_part *p);
uint64_t hv_layers_scratch_need_total(const hv_layers_scratch_need *n);
hv_status hv_layers_part_open(const hv_mesh *mesh, const hv_volume *model, const hv_layers_options *o,
                              const hv_layers_place *pl, const hv_progress *progress, hv_layers_part **out);
void hv_layers_part_close(hv_layers_part *p);
/* The image's place and size on the plate's grid, its layer count, materials and palette
 * (palette entry 0 is the background; halftone: 1 + material index; mask: 1). */
void hv_layers_part_geometry(const hv_layers_part *p, int *c0, int *r0, int *w, int *h, size_t *layers);
int hv_layers_part_materials(const hv_layers_part *p);
const hv_material_table *hv_layers_part_table(const hv_layers_part *p);
/* The bytes of one decoded voxel layer the part holds; it holds as many as the layers being
 * rendered at once read (two each, three while one looks for the nearest occupied voxel layer). */
uint64_t hv_layers_part_slab_bytes(const hv_layers_part *p);
/* Render the part's own layer `index` in scratch `s` (the calling thread's): *pixels (w*h bytes,
 * row 0 at the top, valid until s renders again) holds palette indices (0: background). Several
 * threads render layers of one part at once, each its own layer, sharing the part's decoded voxel
 * layers. Statistics are kept per layer, as hv_layers_write keeps them. */
hv_status hv_layers_part_render(hv_layers_part *p, hv_layers_scratch *s, size_t index, const uint8_t **pixels);
/* The part's totals over the layers rendered (object pixels, target and achieved fractions). */
void hv_layers_part_report(const hv_layers_part *p, hv_layers_report *r);
/* Several processes: every part's per-layer statistics into rank 0's (a collective). */
hv_status hv_layers_part_gather(hv_layers_part *p, const hv_dist *d);
/* Memory the part needs besides the scratch that renders it (bytes), from its plan. */
uint64_t hv_layers_part_memory(const hv_layers_part *p);
/* OR n pixels' values lut[sp[k]] into a row packed at `bits` (1, 2 or 4) bits per pixel from
 * pixel x0 on, the first pixel of a byte in its high bits (PNG's order). */
void hv_tray_or_packed(uint8_t *row, int bits, int x0, const uint8_t *sp, int n, const uint8_t *lut);

/* ---- several processes (hovox/dist.h) ----------------------------------------------------------- */
#include "hovox/dist.h"
/* Split layers [first, last) into d->size contiguous ranges whose bounds are multiples of
 * `block` (or first, last), balanced by cost[i - first]; rank r's range is
 * [out[2r], out[2r+1]) (possibly empty). Deterministic: every process gets the same ranges. */
void hv_dist_partition(const double *cost, size_t first, size_t last, size_t block, int size, size_t *out);
/* Agree on a status: the largest over the processes; a process that did not fail gets the
 * message "another process of the job failed". */
hv_status hv_dist_agree(const hv_dist *d, hv_status local);
/* Rank 0's string (at most size - 1 bytes) on every process. */
void hv_dist_bcast_string(const hv_dist *d, char *buf, size_t size);
/* FNV-1a over bytes, chained from h (start with HV_PLAN_HASH0): the fingerprint of a plan. */
#define HV_PLAN_HASH0 UINT64_C(0xcbf29ce484222325)
uint64_t hv_plan_hash(uint64_t h, const void *data, size_t size);
/* Every process planned the same job: rank 0's fingerprint is broadcast, each compares its own,
 * and rank 0 fails the job with one message when any differs (another --layer-height, another
 * mesh or model on one rank); then as hv_dist_agree. Called by every process whatever `local`. */
hv_status hv_dist_same_plan(const hv_dist *d, uint64_t hash, hv_status local);

/* A copy of s kept as long as tray t (job files' strings); NULL when out of memory. */
struct hv_tray;
const char *hv_tray_keep(struct hv_tray *t, const char *s);
/* hv_tray_add, with where each of the part's "materials" pairs was given (a job file's "job.json:
 * line 3, column 40", strings kept by the tray; pair_where NULL, or an entry NULL: at the part's
 * `where`): a body the mesh lacks is reported at its entry. */
struct hv_tray_part;
hv_status hv_tray_add_at(struct hv_tray *t, const struct hv_tray_part *part, const char *where,
                         const char *const *pair_where);

#include "core/internal.h"
#include "core/zip.h"
#include "core/json.h"

/* ---- the one stack writer (stack.c), for layers and trays -------------------------------------
 * hv_stack_open, the layers' files (hv_stack_layer_path), hv_stack_close: the temporary
 * directory renamed into place when complete, manifest.json, the GCVF zip, several processes. */
typedef struct hv_stack_out {
    char *tmp;           /* the temporary directory, on every process once open */
    hv_zip *zip;         /* the GCVF archive's temporary (rank 0, when asked) */
    const hv_dist *dist; /* several processes, or NULL */
    int root;            /* this process writes the manifest and the zip and renames */
} hv_stack_out;

/* What ConfigFile.xml says: the slices and one entry per material (or resin). */
typedef struct hv_gcvf {
    double dpi[2], layer_height;
    int width, height;
    size_t first, last;
    int bit_depth, colors;
    uint8_t background[3];
    int materials;
    const char *name[HV_MAX_MATERIALS + 1];
    uint8_t rgb[HV_MAX_MATERIALS + 1][3];
    uint64_t voxels[HV_MAX_MATERIALS + 1];
} hv_gcvf;

/* The header of ConfigFile.xml (no materials yet; black background); then one hv_gcvf_add per
 * material, in palette order (at most HV_MAX_MATERIALS + 1). */
void hv_gcvf_init(hv_gcvf *g, const double dpi[2], double layer_height, int width, int height, size_t first,
                  size_t last, int bit_depth, int colors);
void hv_gcvf_add(hv_gcvf *g, const char *name, const uint8_t rgb[3], uint64_t voxels);
/* A manifest document built with `failed` set by any member that could not be added: the
 * document, or NULL (freed) when something failed. */
json_t *hv_stack_manifest_done(json_t *doc, int failed);

/* Open `dir` for writing a stack: an existing gcvf_path is refused without force; rank 0 makes
 * the zip's temporary, the stack's temporary directory and its subdirectories `subs` (NULL, or
 * NULL-terminated); several processes agree on the status and share the directory's name. `st`
 * is the caller's status so far (a failure is agreed and returned, nothing is made). */
hv_status hv_stack_open(hv_stack_out *s, hv_status st, const char *dir, int force, const char *gcvf_path,
                        const char *const *subs, const hv_dist *d);
/* "<tmp>[/<sub>]/layer-NNNNN.png" */
void hv_stack_layer_path(const hv_stack_out *s, const char *sub, size_t index, char *buf, size_t size);
/* Finish (every process calls it with its status): rank 0 lets `hook` add to the manifest, writes
 * manifest.json (the document is taken over), the GCVF zip (gcvf, when the zip is open), runs
 * `finish`, renames the directory into place and commits the zip; on failure removes both.
 * Returns the status every process agrees on. */
hv_status hv_stack_close(hv_stack_out *s, hv_status st, const char *dir, int force, json_t *manifest,
                         hv_stack_manifest_fn hook, void *hook_user, const hv_gcvf *gcvf,
                         hv_stack_finish_fn finish, void *finish_user, const hv_progress *progress);

#endif
