/* hovox/layers.h - printer slice stacks (Wu 2.4.2): material layers at printer resolution by
 * trilinear interpolation between voxel layers and pixel overlap interpolation (POI), the
 * exact contour as the geometric constraint, halftoning to one material per printer voxel,
 * and the stack on disk (PNG layers, manifest.json, GrabCAD-style GCVF zip). */
#ifndef HOVOX_LAYERS_H
#define HOVOX_LAYERS_H

#include "hovox/colour.h"
#include "hovox/lut.h"
#include "hovox/material.h"
#include "hovox/mesh.h"
#include "hovox/options.h"
#include "hovox/scan.h"
#include "hovox/slice.h"
#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ==== printer profiles =====================================================================
 *
 * A profile fixes the printer grid: dpi along x and y (pixel pitch 25.4/dpi mm) and the layer
 * height. Built in:
 *   j750   Stratasys J750 voxel printing: 600 x 300 dpi, 0.027 mm layers
 *   j850   Stratasys J850 voxel printing (High Mix mode): 600 x 300 dpi, 0.027 mm layers
 * (other layer heights of these printers, e.g. 0.014 mm, through a generic dpi and height). */
typedef struct hv_printer_profile {
    const char *name;        /* "j750" */
    const char *description; /* one line for --help and the manifest */
    double dpi[2];           /* x, y */
    double layer_height;     /* mm */
    double build[3];         /* build volume x, y, z (mm; public spec sheets) */
    int material_slots;      /* model materials loaded at once */
} hv_printer_profile;

/* Number of built-in profiles, and profile i (0 <= i < count; NULL otherwise). Static data. */
HV_API int hv_printer_profile_count(void);
HV_API const hv_printer_profile *hv_printer_profile_at(int i);
/* The built-in profile of that name (case-insensitive), or NULL. */
HV_API const hv_printer_profile *hv_printer_profile_find(const char *name);

/* ==== pixel overlap interpolation (Wu 2.4.2) ===============================================
 *
 * Pixels are rectangles; a new pixel is the area-weighted average of the old pixels it
 * overlaps. On rectangular grids the overlap area of two pixels is the product of their
 * overlaps along x and along y, so the operator is separable: exact for any ratio, up or
 * down, and it conserves mass (sum of value x area) when both images cover the same
 * rectangle. Wu's numbers are special cases: 5x5 -> 3x3 gives N1 = 0.36 O1 + 0.24 (O2 + O6)
 * + 0.16 O7; 2x2 -> 3x3 gives N1 = O1, N2 = 0.5 (O1 + O2), N5 = 0.25 (O1 + O2 + O3 + O4).
 *
 * One exact step (Wu's "membrane": the old image stretched over the new one): src is sw x sh
 * floats and dst dw x dh floats, rows first (index y * width + x), both covering the same
 * rectangle. Errors: HV_ERR_INVALID (NULL buffers, sizes < 1 or above 2^24 per axis),
 * HV_ERR_NOMEM. */
HV_API hv_status hv_poi_resample(const float *src, int sw, int sh, float *dst, int dw, int dh);

/* Wu's repeated resampling I0 -> I1 -> ... -> Ik: while the new image is more than
 * `max_ratio` times finer than the current one along an axis, an intermediate image of an
 * exact `max_ratio`-ish step is inserted (each step is one exact POI; the chain is applied as
 * one composed operator per axis, which is mathematically the same thing). max_ratio <= 1
 * means a single step. Down-sampling is always one step (the exact box average).
 * Errors as hv_poi_resample. */
HV_API hv_status hv_poi_resample_steps(const float *src, int sw, int sh, float *dst, int dw,
                                       int dh, double max_ratio);

/* Default step ratio of the layer pipeline (see hv_layers_options.poi_step). */
#define HV_POI_DEFAULT_STEP 1.5

/* ==== contour rasterisation at printer resolution ==========================================
 *
 * A printer grid: pixel (c, r) is the rectangle of size |pixel[0]| x |pixel[1]| whose centre
 * is at world (origin[0] + (c + 0.5) * pixel[0], origin[1] + (r + 0.5) * pixel[1]); pixel[1] is
 * negative when rows run down in y (row 0 at the top, as in PNG). */
typedef struct hv_raster_grid {
    int width, height;
    double origin[2]; /* mm: the corner of pixel (0, 0) that the formula above starts from */
    double pixel[2];  /* mm: pitch along x (> 0) and y (!= 0, negative for rows down) */
} hv_raster_grid;

typedef enum hv_fill_rule {
    HV_FILL_NONZERO = 0, /* inside where the winding number of the loops is not 0 */
    HV_FILL_EVENODD = 1  /* inside where a ray crosses the loops an odd number of times */
} hv_fill_rule;

/* Rasterise the closed loops of a slice by centre sampling: a pixel is object (mask value 1)
 * when its centre lies inside the loops under `rule`, else 0. Centres exactly on an edge follow
 * the half-open convention (an edge covers y in [ymin, ymax) and a span x in [xa, xb)), so
 * two loops sharing an edge never both claim a centre. The slicer orients loops by the facet
 * normals (bodies CCW, cavities CW), so both rules agree on well-nested loops; they differ
 * where shells of one body overlap or one lies inside another (nonzero: union, even-odd:
 * exclusive or). Loops of different bodies of an assembly (hv_slice_loop.body) are united under
 * either rule: even-odd is applied to each body's loops alone. Open polylines are not filled.
 * Wu's distance threshold: with threshold > 0 (mm), pixels outside whose centre lies within
 * `threshold` of a closed loop also become object. mask holds height rows of `stride` bytes
 * (stride >= width; 0 means width). Errors: HV_ERR_INVALID (NULL arguments, bad grid,
 * threshold negative or not finite). */
HV_API hv_status hv_slice_rasterize(const hv_slice *slice, const hv_raster_grid *grid,
                                    hv_fill_rule rule, double threshold, uint8_t *mask,
                                    size_t stride);

/* ==== blue noise =============================================================================
 *
 * A 3D threshold mask made by void-and-cluster (Ulichney 1993) on a torus: Gaussian energy
 * (sigma in cells, kernel truncated at 3 sigma), an initial pattern of 10% ones from `seed`
 * relaxed until the tightest cluster and the largest void coincide, then ranks by removing
 * the tightest clusters (phase 1) and filling the largest voids (phases 2 and 3). The result
 * is a permutation of 0 .. nx*ny*nz - 1 in ranks[(z * ny + y) * nx + x]; threshold = (rank
 * + 0.5) / N. Deterministic for given arguments. Errors: HV_ERR_INVALID (sizes < 2 or a
 * total above 2^24, sigma not in [0.5, 8]), HV_ERR_NOMEM, HV_ERR_CANCELLED. */
HV_API hv_status hv_bluenoise_generate(int nx, int ny, int nz, double sigma, uint64_t seed,
                                       uint32_t *ranks, const hv_progress *progress);

/* Tile used by the halftoner. */
#define HV_BLUENOISE_NX 64
#define HV_BLUENOISE_NY 64
#define HV_BLUENOISE_NZ 32

/* The halftoner's tile (HV_BLUENOISE_NX x NY x NZ ranks, sigma 1.5, fixed seed), loaded from
 * the cache file "<cache_dir>/bluenoise-64x64x32-s1.5-v1.bin" when present and valid (magic,
 * sizes, CRC-32, permutation), else generated (a few seconds) and saved there atomically.
 * cache_dir NULL: $XDG_CACHE_HOME/hovox, else $HOME/.cache/hovox; when the cache cannot be
 * written the tile is still returned (*cached = 0). The tile is kept in memory for the rest
 * of the process (shared, read-only; *ranks must not be freed). *cached (may be NULL): 1 when
 * it came from the cache file or memory. Errors: HV_ERR_NOMEM, HV_ERR_CANCELLED. */
HV_API hv_status hv_bluenoise_tile(const char *cache_dir, const hv_progress *progress,
                                   const uint32_t **ranks, int *cached);
/* The process-wide cache directory used when a call gives none: NULL restores the default,
 * "" keeps caches in memory only (a sandboxed script writes nothing outside its directory).
 * Set it before starting work. */
HV_API void hv_set_cache_dir(const char *dir);

/* ==== printer slice stacks ==================================================================
 *
 * For each layer of the printer plan (uniform layers of the printer's height from the mesh's
 * lowest z, each cut at its mid-height z; hv_slicer_plan_uniform):
 *  1. contour: the WDG slice at z rasterised at printer resolution (hv_slice_rasterize):
 *     object vs background, as sharp as the contour;
 *  2. material (method RESAMPLE, Wu 2.4.2): the two voxel layers around z interpolated
 *     linearly in z (the z part of Wu's trilinear eq. 31-32) over occupied voxels only,
 *     renormalised by the occupancy coverage; voxels with no coverage take the mean of their
 *     nearest covered neighbours (a breadth-first extension, so pixels inside the contour
 *     but outside the voxel model still get material); then POI up to the printer grid in
 *     steps of at most poi_step per axis (Wu's repeated resampling, applied as one composed
 *     exact operator). Fractions sum to 1 inside.
 *     Method DIRECT: the grading definition itself (hv_object_from_model + hv_object_sample)
 *     at each object pixel centre (x, y, z); pixels the definition does not cover keep the
 *     resampled value.
 *  3. output by mode: MASK 1-bit layers (1 = object); FRACTIONS one 8-bit grey layer per
 *     material (round(255 p)); HALFTONE one palette index per pixel (0 = background, j + 1 =
 *     material j), by error diffusion or blue noise (see hv_halftone_method).
 *
 * The stack goes to a temporary directory next to `dir` (".<name>.tmp-<pid>") that is
 * renamed to `dir` when complete; on failure or cancel it is removed. Layers are processed
 * by hv_threads() workers over runs of consecutive layers; each worker holds one layer's
 * images, so memory does not depend on the number of layers. Output bytes do not depend on
 * the thread count, and a range [first, last) produces the same files as the full run. */

typedef enum hv_layers_mode {
    HV_LAYERS_HALFTONE = 0,  /* indexed PNG, one material per pixel */
    HV_LAYERS_FRACTIONS = 1, /* 8-bit grey PNG per material: the fraction */
    HV_LAYERS_MASK = 2       /* 1-bit grey PNG: geometry only (no model needed) */
} hv_layers_mode;

typedef enum hv_layers_method {
    HV_LAYERS_RESAMPLE = 0, /* trilinear + POI from the voxel model (Wu 2.4.2) */
    HV_LAYERS_DIRECT = 1    /* the grading definition evaluated at every pixel */
} hv_layers_method;

/* Halftoning to one material per printer voxel:
 *  BLUE_NOISE: material j at a pixel when the blue-noise threshold t (the tile repeated over
 *    the stack, x and y by pixel, z by global layer index, offset by the seed) falls in
 *    [p_0 + .. + p_{j-1}, p_0 + .. + p_j). Fully parallel.
 *  ERROR_DIFFUSION: vector error diffusion: at each object pixel (serpentine rows) pick the
 *    material with the largest target + accumulated error, subtract the one-hot choice, send
 *    3/4 of the error to the unvisited object neighbours in the layer (Floyd-Steinberg 7, 3,
 *    5, 1 / 16, renormalised over object pixels) and 1/4 to the same pixel of the next layer.
 *    The error carried across layers restarts every HV_HALFTONE_BLOCK layers (global index),
 *    from a small seeded zero-sum noise, so blocks run in parallel and a range run recomputes
 *    from its block start: byte-identical to the full run. */
typedef enum hv_halftone_method {
    HV_HALFTONE_BLUE_NOISE = 0,
    HV_HALFTONE_ERROR_DIFFUSION = 1
} hv_halftone_method;

#define HV_HALFTONE_BLOCK 32

/* A step run once a stack is complete in its temporary directory `tmp`, before that is renamed
 * to `dir` (by the one process that commits, with several): it may add files to `tmp` (the
 * --view page of the CLI, hovox/viewer.h). A status other than HV_OK (its message set) fails the
 * job and nothing is left. `progress` is the job's. */
typedef hv_status (*hv_stack_finish_fn)(void *user, const char *tmp, const char *dir, const hv_progress *progress);
/* Adds to a stack's manifest before it is written: `manifest` is the manifest.json document, a
 * jansson `json_t *` object (add members; do not take it over). Errors stop the stack. */
typedef hv_status (*hv_stack_manifest_fn)(void *user, void *manifest);

typedef struct hv_layers_options {
    hv_layers_mode mode;           /* default HALFTONE */
    hv_layers_method method;       /* default RESAMPLE */
    hv_halftone_method halftone;   /* default BLUE_NOISE */
    const char *profile;           /* name written to the manifest ("j750", "custom"); may be
                                      NULL. Does not set dpi/layer_height: fill those from
                                      hv_printer_profile_find. */
    double dpi[2];                 /* printer dpi x, y (> 0) */
    double layer_height;           /* mm (> 0) */
    uint64_t seed;                 /* halftone seed (default 0) */
    size_t first, last;            /* layer range [first, last) of the full plan; last == 0
                                      means "to the end" (default: all layers) */
    double threshold;              /* Wu's distance threshold in mm (default 0) */
    hv_fill_rule fill_rule;        /* default NONZERO */
    int margin;                    /* background pixels around the mesh's xy box (default 2) */
    double poi_step;               /* largest up-sampling ratio per POI step (default
                                      HV_POI_DEFAULT_STEP; <= 1: one step) */
    uint8_t background[3];         /* halftone palette entry 0 (default black) */
    int compare;                   /* also evaluate the other method and report the
                                      difference (always on with DIRECT) */
    double close_gap;              /* slicer gap rule (default HV_SLICE_DEFAULT_CLOSE_GAP) */
    int compression;               /* PNG zlib level 0..9 (default 1: halftone layers are noise,
                                      higher levels cost time for little) */
    int force;                     /* replace an existing stack at dir (a directory holding a
                                      hovox manifest.json); never other non-empty directories */
    uint64_t max_memory;           /* refuse plans above this (bytes; 0: half of RAM) */
    const char *cache_dir;         /* blue-noise cache (NULL: default, see hv_bluenoise_tile) */
    const char *gcvf_path;         /* also write a GCVF zip there (HALFTONE or MASK); NULL: no */
    const char *mesh_name;         /* for the manifest (may be NULL) */
    const char *model_name;        /* for the manifest (may be NULL) */
    const struct hv_dist *dist;    /* several processes write one stack (hovox/dist.h); NULL: one */
    int placed;                    /* place the part on the profile's plate (see place) */
    double place[2];               /* plate position (mm) of the centre of the mesh's xy box: the
                                      image is then the part's box on the plate's pixel grid
                                      (row 0 at the plate's far edge y = build[1]), as in a tray */
    hv_stack_finish_fn finish;     /* run before the stack is renamed into place; NULL: none */
    void *finish_user;
    hv_stack_manifest_fn manifest; /* adds to manifest.json (colour, scan data source); NULL: none */
    void *manifest_user;
    const struct hv_layers_source *source; /* the shape and materials straight from data at every
                                      pixel (a scanned volume, slicing/layers_internal.h) instead of
                                      a model and its shape; NULL: the model */
} hv_layers_options;

/* Defaults as noted above; dpi and layer height from the j750 profile. */
HV_API void hv_layers_options_init(hv_layers_options *o);

/* The layers options as an option set (hovox/options.h): keys profile, dpi, layer_height,
 * mode, method, compare, halftone, seed, layers, background, gcvf, force, fill_rule, threshold,
 * margin, close_gap, poi_step, compression, max_memory; their domains and rules (a profile or
 * dpi, seed and halftone only in halftone mode, ...). A profile sets dpi and layer height.
 * Static data. */
HV_API const hv_option_set *hv_layers_option_set(void);
/* Every option's domain. Errors: HV_ERR_INVALID naming the option. */
HV_API hv_status hv_layers_options_check(const hv_layers_options *o);
/* Names of the enum values, the one spelling options take and manifests and messages print
 * ("halftone", "resample", "bluenoise", "evenodd"); "?" for a value without one. Static text. */
HV_API const char *hv_layers_mode_name(hv_layers_mode mode);
/* The mode of that name (the spelling above; a manifest's "mode", as `hovox view` reads it).
 * Errors: HV_ERR_INVALID ("layers mode must be halftone, fractions or mask, got 'x'"). */
HV_API hv_status hv_layers_mode_parse(const char *name, hv_layers_mode *out);
HV_API const char *hv_layers_method_name(hv_layers_method method);
HV_API const char *hv_halftone_method_name(hv_halftone_method method);
HV_API const char *hv_fill_rule_name(hv_fill_rule rule);

/* What a job does or did. Filled by hv_layers_plan (plan fields) and hv_layers_write (all). */
typedef struct hv_layers_report {
    /* plan */
    int width, height;            /* pixels of every layer */
    double pixel_mm[2];           /* sx = 25.4/dpi_x, sy = -25.4/dpi_y */
    double origin_mm[2];          /* pixel (c, r) centre: origin + (c + 0.5, r + 0.5) * pixel */
    size_t layers_total;          /* layers of the full plan */
    size_t first, last;           /* the range produced, [first, last) */
    int materials;                /* 0 in MASK mode */
    int bit_depth;                /* of the PNG layers */
    uint64_t memory_bytes;        /* planned peak for the job (model and mesh excluded) */
    int threads;
    /* results (hv_layers_write) */
    uint64_t object_pixels;       /* over the layers produced */
    double target[64];            /* mean fraction per material over the object pixels */
    double achieved[64];          /* HALFTONE: share of object pixels given each material */
    int compared;                 /* 1 when diff_* hold a comparison */
    double diff_mean, diff_max;   /* max_j |p_j(resample) - p_j(direct)| per object pixel:
                                     mean and max over the stack */
    uint64_t direct_fallback;     /* DIRECT: object pixels the definition did not cover */
    size_t open_polylines;        /* open chains the slicer left (not filled) */
    char warnings[2048];          /* what a person should know, one line each ("" if none):
                                     a mesh whose box differs from the one the model was
                                     voxelized from, open contours */
    int bluenoise_cached;         /* the blue-noise tile came from the cache */
} hv_layers_report;

/* Compute the grid, the layer range and the memory a job needs, without writing. model may be
 * NULL only in MASK mode. Errors: HV_ERR_INVALID (options out of range, range beyond the
 * plan, no model for a material mode), HV_ERR_BAD_INPUT (model without material table or
 * occupancy, mesh's xy/z box outside the model's voxels), HV_ERR_LIMIT (image above 2^31-1
 * pixels a side, or memory above max_memory: the message says how much is needed),
 * HV_ERR_NOMEM. */
HV_API hv_status hv_layers_plan(const hv_mesh *mesh, const hv_volume *model,
                                const hv_layers_options *opt, hv_layers_report *report);

/* Write the stack to directory `dir` (see above). `report` (may be NULL) receives the plan and
 * the results. `progress` (may be NULL) is called with stages "bluenoise", "layers", "gcvf";
 * a nonzero return cancels (HV_ERR_CANCELLED, nothing left under `dir`).
 * Layout of `dir`:
 *   manifest.json                       (see README "hovox layers")
 *   layer-NNNNN.png                     HALFTONE and MASK, NNNNN = global layer index (at
 *                                       least 5 digits)
 *   <material>/layer-NNNNN.png          FRACTIONS, one directory per material
 * GCVF (opt->gcvf_path): a zip (deflate or stored) of ConfigFile.xml and layer_<index>.png,
 * written atomically.
 * Errors: those of hv_layers_plan, HV_ERR_IO (dir exists and is not empty and not a
 * replaceable stack, parent not writable, write failed; naming the path), HV_ERR_NOMEM,
 * HV_ERR_CANCELLED. */
/* How `ranks` processes would share the stack (hovox/dist.h): ranges[2r], ranges[2r+1] are
 * rank r's layers [a, b); share[r] its fraction of the estimated cost (may be NULL). Errors:
 * those of hv_layers_plan, HV_ERR_NOMEM. */
HV_API hv_status hv_layers_partition(const hv_mesh *mesh, const hv_volume *model, const hv_layers_options *o,
                                     int ranks, size_t *ranges, double *share);

HV_API hv_status hv_layers_write(const hv_mesh *mesh, const hv_volume *model, const char *dir,
                                 const hv_layers_options *opt, const hv_progress *progress,
                                 hv_layers_report *report);

/* ==== one step from a mesh (issue 27) ================================================
 *
 * A mesh (STL, OBJ, PLY, a 3MF without volume data: an assembly of bodies) printed with no model
 * file, as `hovox layers PART.3mf -o DIR` prints it. The options of the step besides the layers'
 * (zero-initialised: none; hv_layers_mesh_option_set: their keys, static data):
 *   materials     repeatable BODY=MATERIAL (a map {BODY = MATERIAL} in Lua, Python and job files):
 *                 a body's material whatever the file says, as `hovox layers --material`;
 *   voxel_size    mm; 0: the printer's pitch, coarsened to fit;
 *   colour_depth  mm; paint the mesh in its colours this deep (0: HV_COLOUR_DEPTH_DEFAULT when it
 *                 is painted), core what lies deeper (a resin or a colour; NULL: the white
 *                 resin), colour the colour map (icc, intent, resins; zero: the defaults); not
 *                 with materials (HV_ERR_INVALID). */
typedef struct hv_layers_mesh_options {
    hv_body_materials materials;
    double voxel_size;
    double colour_depth;
    const char *core;
    hv_colour_options colour;
} hv_layers_mesh_options;
HV_API const hv_option_set *hv_layers_mesh_option_set(void);

/* The model a mesh prints with, made in memory. One rule for the CLI, Lua, Python (issue 29):
 * the mesh is painted in its colours when mo gives no materials and either gives colour_depth or
 * core or the mesh prints in its colours by itself (hv_colour_mesh_paints): hv_colour_mesh_model
 * through mo->colour's map, on voxels of the coarser of the printer's pitch and half the depth
 * (hv_colour_mesh_voxels); otherwise as `hovox voxelize` then `hovox grade` without sources make
 * it (hv_mesh_model: each body 100% its material or its 3MF composite's mixture) on voxels of the
 * printer's coarsest pitch (the larger of 25.4/dpi and the layer height of `o`). Either way
 * coarsened by 5/4 until it fits half of o->max_memory's budget, or on voxels of mo->voxel_size
 * (> 0). The outline is the mesh's contours, exact; the voxels only place the interfaces between
 * bodies and carry the colour. mo may be NULL (none). *voxels (may be NULL) gets the voxel size
 * used, the lattice, whether it was coarsened and whether (and how deep) it was painted. Errors:
 * HV_ERR_INVALID (colour_depth or core with materials), those of hv_mesh_model_voxels and
 * hv_mesh_model (a body without a material, naming it), of hv_colour_map_create and
 * hv_colour_mesh_model. Free *model with hv_volume_destroy. */
typedef struct hv_layers_mesh_voxels {
    double size;     /* mm */
    int64_t dims[3];
    int coarsened;   /* 1: coarser than the printer's pitch (or half the colour depth), to fit the memory budget */
    int painted;     /* 1: painted in its colours */
    double depth;    /* painted: the colour's depth (mm) */
} hv_layers_mesh_voxels;
HV_API hv_status hv_layers_mesh_model(const hv_mesh *mesh, const hv_layers_options *o, const hv_layers_mesh_options *mo,
                                      const hv_progress *progress, hv_volume **model, hv_layers_mesh_voxels *voxels);

/* A painted model's colour in its stack (issue 29; the CLI, Lua and Python alike): when `model`
 * is painted (hv_colour_map_for_model) and o has no manifest hook yet, sk (zeroed here) gets the
 * model and its colour map and o's manifest hook becomes hv_colour_manifest_hook over sk, which
 * hv_layers_write then fills: the skin's dE2000 in manifest.json and in sk. Returns HV_OK also
 * when the model is NULL or not painted (sk->map NULL, o untouched). Errors: those of
 * hv_colour_map_for_model but HV_ERR_NOT_FOUND (a damaged record, a profile no longer readable;
 * o untouched: a front end may warn and write the stack without the colour). The caller frees
 * sk->map with hv_colour_map_destroy after hv_layers_write. */
HV_API hv_status hv_layers_colour_hook(hv_layers_options *o, const hv_volume *model, hv_colour_skin *sk);

/* The whole step for a front end (Lua mesh:layers, Python mesh.layers): a copy of `mesh` with
 * each body in its material of mo->materials (hv_body_materials_apply; mo may be NULL), its model
 * (hv_layers_mesh_model; none in MASK mode), then hv_layers_write with the colour's manifest hook
 * when it is painted (hv_layers_colour_hook; o's own hook otherwise). The report's warnings begin
 * with the size warning of hv_placement_size_warning against the profile's build volume (a mesh
 * under 1 mm or larger than the printer, naming the likely unit). The manifest names the mesh
 * (o->mesh_name, else the mesh's name) as mesh and model. colour (may be NULL) gets a painted
 * part's figures (target, achieved, has_achieved) and its colour map (map: free it with
 * hv_colour_map_destroy; NULL when the part is not painted); its model is NULL (the model is
 * gone). *table (may be NULL) the stack's material table, as hv_layers_write_scan's (NULL in mask
 * mode; free with hv_material_table_destroy). Errors: those of hv_body_materials_apply,
 * hv_layers_mesh_model, hv_layers_colour_hook, hv_layers_write and hv_material_table_load. */
HV_API hv_status hv_layers_write_mesh(const hv_mesh *mesh, const hv_layers_mesh_options *mo, const char *dir,
                                      const hv_layers_options *o, const hv_progress *progress,
                                      hv_layers_report *report, hv_colour_skin *colour, hv_material_table **table);

/* A scanned volume printed as `hovox layers VOLUME` prints it (issue 30; the Lua and Python
 * front ends' one path, the same bytes as the CLI's): straight from its data at the printer's
 * pixel centres, no model (slicing/scan_source.c), or, with a clean-up in `shape` (keep_largest,
 * fill_holes, min_feature), a threshold band, the direct method or a comparison in `opt`, through
 * its model made in memory (hv_lut_scan_model) cut like any model. `shape` gives the shape (its
 * progress and max_memory are set from these arguments); `lut` the materials (NULL: mode mask
 * only), `map` a colour table's colour map (borrowed). opt's source and manifest hook are the
 * function's own (a colour table adds the mean dE2000 to the manifest, hv_colour_manifest_hook).
 * colour (may be NULL) gets a colour table's figures (target, achieved, has_achieved; voxels:
 * printer voxels; map: `map` when they were computed, else NULL; model and samples NULL); *table (may be NULL) the stack's material
 * table (NULL in mask mode; free with hv_material_table_destroy). Errors: those of
 * hv_layers_write, hv_lut_scan_model and the scan source (HV_ERR_INVALID: a colour table
 * without a map). */
HV_API hv_status hv_layers_write_scan(const hv_scan *scan, const hv_scan_voxelize_options *shape, const hv_lut *lut,
                                      hv_colour_map *map, const char *dir, const hv_layers_options *opt,
                                      const hv_progress *progress, hv_layers_report *report, hv_colour_skin *colour,
                                      hv_material_table **table);

#ifdef __cplusplus
}
#endif
#endif
