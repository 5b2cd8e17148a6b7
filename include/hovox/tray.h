/* hovox/tray.h - print jobs: a build tray of parts (graded models with their meshes, or plain
 * meshes in one material), placed on a printer's plate and sliced in one streamed stack
 * (DESIGN.md "Printer conventions"; Wu 2.4.2 for each part's layers).
 *
 * Plate frame: x from 0 to build[0], y from 0 to build[1] (mm); pixel (c, r) covers x in
 * [c sx, (c+1) sx) and y in (build[1] - (r+1) py, build[1] - r py], row 0 at the far edge. Tray
 * layer t covers z in [t h, (t+1) h). A part is placed by the centre of its mesh's xy box and
 * the lift of its bottom (rounded to whole layers); its pixels are exactly those
 * `hovox layers --place X,Y` gives it alone (blue noise anchored to the plate).
 *
 * Resins: each material name maps to a resin of the profile's resin table (a material named
 * like a resin maps to it); the stack's palette is entry 0 (no material) and one entry per resin
 * used, in the table's order. The built-in table is public data (vendor colour names, display
 * colours chosen here), not confirmed by the vendor; a job may add or override resins.
 *
 * Thread safety: a tray is not thread-safe; hv_tray_write uses hv_threads() workers. */
#ifndef HOVOX_TRAY_H
#define HOVOX_TRAY_H

#include <stddef.h>
#include <stdint.h>

#include "hovox/colour.h"
#include "hovox/layers.h"
#include "hovox/material.h"
#include "hovox/options.h"
#include "hovox/placement.h"

#ifdef __cplusplus
extern "C" {
#endif

#define HV_TRAY_MAX_RESINS 64
/* Most parts a tray places (copies counted). */
#define HV_TRAY_MAX_PARTS 4096

/* The built-in resin table of a profile (count in *n; static data, not vendor-confirmed): the
 * one table of hovox/material.h (hv_resin_table), which the J750 and J850 share. */
HV_API const hv_resin *hv_tray_resins(const hv_printer_profile *p, int *n);

/* A part as options (hv_tray_part_option_set): model (a graded .vdb; absent for a plain mesh),
 * mesh (.stl, .obj, .ply, .3mf; with a model an override that must be the mesh it records; absent for a
 * scan; absent with a model:
 * the shape the model records, its Booleans included, cut as hv_layers_write cuts it, and no
 * placement options; a model without a record is refused naming the part), material (a plain mesh's one material; without a model
 * and a material, the mesh's bodies in their own materials: its model is made in memory as
 * hv_mesh_model makes it, on voxels of the printer's coarsest pitch coarsened until they fit a
 * quarter of max_memory; a body without a material is refused naming it), materials (repeatable
 * BODY=MATERIAL, a job file's {"BODY": "MATERIAL", ...}: a body's material whatever the file
 * says, as `hovox layers --material BODY=MATERIAL`; not with model or material;
 * a mesh that prints in
 * its colours, hv_colour_mesh_paints, or a part given colour_depth or core, is painted instead:
 * hv_colour_mesh_model through the tray's colour map, colour_depth mm deep, default
 * HV_COLOUR_DEPTH_DEFAULT, over core, a resin or a colour, default the map's white resin), name,
 * at = X,Y (plate position of the centre of its xy box; absent: arranged), z (lift, mm, >= 0),
 * rotation (0, 90, 180, 270 degrees about z), copies (>= 1, placed in a row along +x), and the
 * placement of the mesh (hovox/placement.h: unit, up, scale, rotate, translate; applied to the mesh
 * when it is read, before `rotation`; a model must have been voxelized from the mesh so placed).
 * A scanned volume (issue 30) is a part with `scan` (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, a
 * DICOM directory) in place of mesh and model: its shape is one of iso, range or labels ("A,B,...";
 * a job file may give a list), as `hovox layers VOLUME` takes them, its materials those of `lut`
 * (a lookup table: materials, or a colour table's resins through the default colour map) or, without
 * one, `material`. It is printed straight from its data at the printer's pixel centres as
 * hv_scan_source prints `layers VOLUME` (no model); with keep_largest, fill_holes or min_feature
 * its model is made in memory as hv_lut_scan_model makes it. The placement and `rotation` move its
 * index-to-world affine; its footprint is its shape's xy box. Paths are borrowed. */
typedef struct hv_tray_part {
    const char *model, *mesh, *material, *name;
    double at[2];
    double z;
    int rotation;
    int copies;
    int placed; /* `at` given */
    hv_placement place;
    hv_body_materials materials;
    const char *scan, *lut, *labels; /* a scanned volume, its lookup table, its labels "A,B,..." */
    int select;                      /* hv_scan_select: set by the key given (iso, range, labels) */
    double iso, range[2], min_feature;
    int keep_largest, fill_holes;
    double colour_depth; /* mm; 0: HV_COLOUR_DEPTH_DEFAULT when painted */
    const char *core;    /* a painted part's core (resin or colour); NULL: the white resin */
} hv_tray_part;
HV_API void hv_tray_part_init(hv_tray_part *p);
HV_API const hv_option_set *hv_tray_part_option_set(void);

/* The job's options (hv_tray_option_set): profile (j750, j850), mode (halftone: blue noise;
 * mask), seed, spacing (mm between footprints, default 5), arrange (place the parts without
 * `at`; with arrange = all, every part), layers (A:B of the tray's layers), gcvf (also a GCVF
 * zip), force, max_memory, dry_run, resin (repeatable MATERIAL=RESIN), resin_color (repeatable
 * RESIN=#rrggbb: add or override a resin), and the colour map of painted parts (icc, intent,
 * resins: hovox/colour.h). */
typedef struct hv_tray_options {
    const char *profile;
    hv_layers_mode mode;
    uint64_t seed;
    double spacing;
    int arrange; /* 0: no, 1: the parts without `at`, 2: all */
    size_t first, last;
    const char *gcvf_path;
    const char *stl_path; /* also the placed parts as one STL, plate coordinates (other slicers) */
    int force, dry_run;
    uint64_t max_memory;
    int nresin, ncolor;
    const char *resin[HV_TRAY_MAX_RESINS];       /* "MATERIAL=RESIN" (borrowed) */
    const char *resin_color[HV_TRAY_MAX_RESINS]; /* "RESIN=#rrggbb" (borrowed) */
    hv_colour_options colour;                    /* painted parts' colour map */
    const char *cache_dir;                       /* blue-noise cache (see hv_layers_options) */
    const struct hv_dist *dist;                  /* several processes (hovox/dist.h); NULL: one */
    hv_stack_finish_fn finish;                   /* run before the stack is renamed into place
                                                    (see hovox/layers.h); NULL: none */
    void *finish_user;
    hv_stack_manifest_fn manifest;               /* adds to manifest.json; NULL: none */
    void *manifest_user;
    void (*warn)(void *user);                    /* called as each warning arises (planning), the
                                                    warning the thread's last message (hv_last_error,
                                                    hv_error_spell); NULL: none. The report has them
                                                    all. */
    void *warn_user;
} hv_tray_options;
HV_API void hv_tray_options_init(hv_tray_options *o);
HV_API const hv_option_set *hv_tray_option_set(void);

typedef struct hv_tray hv_tray;

/* A new empty tray. Errors: HV_ERR_NOMEM. */
HV_API hv_status hv_tray_create(hv_tray **out);
HV_API void hv_tray_destroy(hv_tray *t);
/* Add a part (its options are copied; files are read by hv_tray_plan). Parts are named "part N"
 * (in the order added) with their name; `where` (may be NULL) is where the part was given
 * ("job.json: line 7, column 5") and starts every message about it. Errors:
 * HV_ERR_INVALID (options), HV_ERR_NOMEM. */
HV_API hv_status hv_tray_add(hv_tray *t, const hv_tray_part *part, const char *where);
HV_API int hv_tray_part_count(const hv_tray *t);

/* Read a JSON job file: {"schema": 1, "profile": ..., <the keys of hv_tray_option_set>,
 * "parts": [{<the keys of hv_tray_part_option_set>}, ...]}. Relative paths resolve against the
 * file's directory. Unknown keys and wrong types are refused; every message gives the file,
 * line and column. The options' strings live as long as the tray. Errors: HV_ERR_IO,
 * HV_ERR_BAD_INPUT, HV_ERR_INVALID, HV_ERR_NOMEM. */
HV_API hv_status hv_tray_load_job(const char *path, hv_tray **out, hv_tray_options *o);
/* The same from text (`name` in messages, `base` the directory for relative paths). */
HV_API hv_status hv_tray_parse_job(const char *text, size_t size, const char *name, const char *base,
                                   hv_tray **out, hv_tray_options *o);

/* What a tray job will do (filled by hv_tray_plan and hv_tray_write). */
typedef struct hv_tray_report {
    int width, height;          /* plate image (pixels) */
    size_t layers, first, last; /* tray layers, the range written */
    int parts;                  /* placed instances (copies counted) */
    int resins, bit_depth;
    double utilisation;         /* footprint area / plate area */
    uint64_t memory;            /* bytes planned: the parts' statistics and tables, and per
                                   thread one plate image and one part's buffers (shared by
                                   the parts in turn) plus every part's two voxel slabs */
    uint64_t object_pixels;     /* over the layers written */
    uint64_t bytes;             /* the stack's PNG bytes (after writing) */
    double est_seconds;         /* rough estimates (plan), from the bench tray on 2 cores: */
    double est_bytes;           /* part-box voxels/s 4.5e8 (halftone) or 2e9 (mask), plate
                                 * voxels/s 4e10; PNG bytes layer by layer as the encoder
                                 * writes them (sparse or dense), within ~25% on the bench and
                                 * README trays */
    char warnings[2048];        /* what a person should know, one line each ("" if none): a part
                                   whose mesh, as placed, is under 1 mm or fits no orientation of
                                   the build volume, naming the likely unit
                                   (hv_placement_size_warning) */
} hv_tray_report;

/* Load every part's files, place them (arranging when asked), and check the tray: every part
 * inside the build volume, footprints at least `spacing` apart, materials within the profile's
 * slots, each mapped to a known resin, models matching their meshes, memory within the budget.
 * Nothing is written. Errors name the part: HV_ERR_INVALID, HV_ERR_BAD_INPUT, HV_ERR_IO,
 * HV_ERR_LIMIT, HV_ERR_NOMEM. */
HV_API hv_status hv_tray_plan(hv_tray *t, const hv_tray_options *o, const hv_progress *progress,
                              hv_tray_report *report);
/* After planning: the placed instances (copies counted) and the xy box of instance i on the
 * plate (x0, y0, x1, y1 mm). */
HV_API int hv_tray_instance_count(const hv_tray *t);
HV_API void hv_tray_instance_box(const hv_tray *t, int i, double box[4]);
/* Where instance i (0 <= i < hv_tray_instance_count) went, after planning. */
typedef struct hv_tray_placement {
    const char *name;  /* the part's name (owned by the tray) */
    int part, copy;    /* part N (in the order added) and its copy, both from 1 */
    int copies;        /* the part's copies */
    double at[2];      /* the centre of its xy box on the plate (mm) */
    double box[4];     /* its xy box on the plate: x0, y0, x1, y1 (mm) */
    int rotation;      /* degrees about z */
    size_t lift;       /* tray layers below its first layer */
    int arranged;      /* 1: placed by `arrange`, 0: where it was given */
} hv_tray_placement;
HV_API void hv_tray_instance_get(const hv_tray *t, int i, hv_tray_placement *out);

/* A part's colour in the stack hv_tray_write last wrote in halftone mode (issue 29): instance i
 * (copies counted) painted in its colours (its skin's voxels), or a scan printed from a colour
 * table through the tray's colour map (the printer voxels of its tabulated values, its copies
 * together), as its manifest entry's "colour" gives it: the mean and max dE2000 of the fractions
 * against the colours asked for, and with each resin's fractions scaled by the halftone's
 * achieved over target share. Returns 1 and fills *out, or 0 (out zeroed) when it has none.
 * description is owned by the tray. */
typedef struct hv_tray_colour {
    const char *description; /* the output profile's ("Artifex CMYK SWOP Profile") */
    hv_intent intent;
    int printer_voxels;      /* 1: voxels are printer voxels (a scan's colour table); 0: a model's skin voxels */
    hv_colour_skin_report target, achieved;
} hv_tray_colour;
HV_API int hv_tray_instance_colour(const hv_tray *t, int i, hv_tray_colour *out);

/* How `ranks` processes would share the tray's layers (hovox/dist.h): rank r writes layers
 * [ranges[2r], ranges[2r+1]), share[r] of the estimated cost (may be NULL). Plans the tray. */
HV_API hv_status hv_tray_partition(hv_tray *t, const hv_tray_options *o, int ranks, size_t *ranges, double *share);

/* Plan (if not yet), then write the stack into `dir` (a temporary directory renamed when
 * complete; PNG layers layer-NNNNN.png indexed by the resin palette, manifest.json with the
 * parts) and the GCVF zip when asked. Layer ranges and thread counts give the same bytes. */
HV_API hv_status hv_tray_write(hv_tray *t, const char *dir, const hv_tray_options *o,
                               const hv_progress *progress, hv_tray_report *report);

#ifdef __cplusplus
}
#endif
#endif
