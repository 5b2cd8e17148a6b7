/* hovox/profile.h - material fractions of a graded model sampled along a line segment (Wu
 * 2.3, Fig. 26: material distribution on sample lines), as CSV and as a plot. */
#ifndef HOVOX_PROFILE_H
#define HOVOX_PROFILE_H

#include <stdio.h>

#include "hovox/material.h"
#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The samples of one line: sample i (0 <= i < n) lies at from + (to - from) * i / (n - 1),
 * at distance t_i = |to - from| * i / (n - 1) from the start (world units: millimetres for
 * models voxelized from STL). Each sample holds what hv_model_probe reports there: inside
 * (trilinear occupancy >= 0.5) and the m material fractions (trilinear over the occupied
 * voxels around the point, renormalised; the fractions of the nearest occupied voxels just
 * outside the boundary, 0 far from the object). Immutable once made. */
typedef struct hv_profile hv_profile;

/* What to sample and how to plot it. */
#define HV_PROFILE_MAX_MARKS 64
typedef struct hv_profile_mark {
    double t;          /* distance along the line (mm) */
    const char *label; /* may be NULL; borrowed */
} hv_profile_mark;
typedef struct hv_profile_options {
    double from[3], to[3];   /* the segment (world units), distinct */
    int samples;             /* 2 .. 10^7 (default 200) */
    const char *title;       /* plot title; NULL: the default (borrowed) */
    int size[2];             /* plot pixels (default 900, 560; 100 .. 8192 each) */
    double y_range[2];       /* plot y range (default 0, 1); NAN, NAN: the data's */
    int marks;               /* dashed vertical lines */
    hv_profile_mark mark[HV_PROFILE_MAX_MARKS];
    const char *property;    /* NULL: none; else a property of the model's calibration table
                                (hv_profile_sample_with), borrowed */
} hv_profile_options;

/* Defaults as noted. */
HV_API void hv_profile_options_init(hv_profile_options *o);
/* The profile options as an option set (hovox/options.h): keys from, to (required), samples,
 * property, title, size, mark (repeatable, "T" or "T=LABEL"), y_range ("LO,HI" or "auto").
 * Static data. */
HV_API const hv_option_set *hv_profile_option_set(void);
/* Every option's domain; from != to. Errors: HV_ERR_INVALID naming the option. */
HV_API hv_status hv_profile_options_check(const hv_profile_options *o);

/* Sample the graded model vol at n >= 2 points from `from` to `to` (finite, distinct).
 * Multi-threaded, the result independent of the thread count. The material table is copied
 * from vol (hv_material_table_load), so vol may be freed afterwards.
 * Errors: HV_ERR_NOT_FOUND (vol has no material table: not graded), HV_ERR_BAD_INPUT (corrupt
 * table), HV_ERR_INVALID (n < 2, end points not finite or equal, length not finite),
 * HV_ERR_NOMEM.
 * Free with hv_profile_destroy. */
HV_API hv_status hv_profile_sample(const hv_volume *vol, const double from[3], const double to[3],
                                   int n, hv_profile **out);

/* hv_profile_sample over o->from .. o->to with o->samples samples and, when o->property is set,
 * that property at every sample, from the calibration table stored with the model's grading
 * sources (hovox.object.json). The rule: the model's sources must hold exactly one table for the
 * property (several sources may share it when their tables, units, Ms and Me are identical).
 * At a sample inside the object whose probed composition p lies on that source's segment
 * Ms -> Me (every fraction within 1e-3 of Ms + t (Me - Ms), hv_ags_segment_t's rule), the value
 * is the table at t = (p - Ms).(Me - Ms) / |Me - Ms|^2; elsewhere (outside the object, another
 * source's or the base composition, a blend of sources, t outside the table's rows) it is NAN.
 * Errors: those of hv_profile_sample, HV_ERR_NOT_FOUND when the model has no table for the
 * property ("no calibration table for youngs_modulus in the model's grading definition (it has
 * tables for shore_a[ShoreA])"), HV_ERR_BAD_INPUT when it has several different ones ("the
 * model's grading definition has different calibration tables for youngs_modulus (sources 1
 * 'core', 2 'skin'): its profile needs exactly one") or a corrupt stored table. */
HV_API hv_status hv_profile_sample_with(const hv_volume *vol, const hv_profile_options *o, hv_profile **out);

/* Free a profile; NULL is allowed. */
HV_API void hv_profile_destroy(hv_profile *p);

/* Number of samples n; number of materials m; the segment length |to - from|. */
HV_API int hv_profile_samples(const hv_profile *p);
HV_API int hv_profile_materials(const hv_profile *p);
HV_API double hv_profile_length(const hv_profile *p);
/* The material table of the model (owned by the profile). */
HV_API const hv_material_table *hv_profile_table(const hv_profile *p);
/* The end points given to hv_profile_sample. */
HV_API void hv_profile_segment(const hv_profile *p, double from[3], double to[3]);

/* Sample i (0 <= i < n): distance from the start, world position, inside flag (0 or 1) and the
 * m fractions (owned by the profile, valid until it is freed). */
HV_API double hv_profile_t(const hv_profile *p, int i);
HV_API void hv_profile_position(const hv_profile *p, int i, double xyz[3]);
HV_API int hv_profile_inside(const hv_profile *p, int i);
HV_API const double *hv_profile_fractions(const hv_profile *p, int i);

/* The property of the profile (hv_profile_sample_with): its name (NULL: none) and unit ("" when
 * the table has none) owned by the profile, and its value at sample i (NAN where undefined). */
HV_API const char *hv_profile_property(const hv_profile *p, const char **unit);
HV_API double hv_profile_property_value(const hv_profile *p, int i);

/* CSV: a header "t,x,y,z,inside,<material names...>" and one row per sample; t, x, y, z with
 * 9 significant digits, fractions with 6 (they are stored as 32-bit floats). A profile with a
 * property has one more column, "<property>[<unit>]" (just "<property>" without a unit), values
 * with 6 significant digits, "nan" where undefined. write_csv writes
 * `path` atomically (a temporary name in the same directory, renamed when complete);
 * write_csv_stream writes to an open stream (e.g. stdout), flushes it and leaves it open.
 * Errors: HV_ERR_IO (cannot write or rename; no file is left under `path`), HV_ERR_NOMEM. */
HV_API hv_status hv_profile_write_csv(const hv_profile *p, const char *path);
HV_API hv_status hv_profile_write_csv_stream(const hv_profile *p, FILE *fp);

#ifdef __cplusplus
}
#endif
#endif
