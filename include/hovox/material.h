/* hovox/material.h - material space, reference features, grading sources and heterogeneous
 * objects after Wu 2.2 (eq. 4-30): m named material primitives; compositions are vectors of
 * m fractions >= 0 summing to 1 (eq. 12); a fixed reference feature (FRF) gives a distance
 * d; an active grading source (AGS) maps d through ranges d-, dg, d+ and a distribution
 * function f to a composition between Ms and Me (eq. 19-20); objects are lists of regions
 * (geometry mask, AGS set) combined by Wu's Booleans (eq. 27-30). */
#ifndef HOVOX_MATERIAL_H
#define HOVOX_MATERIAL_H

#include <stdio.h>

#include "hovox/mesh.h"
#include "hovox/options.h"
#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

#define HV_MAX_MATERIALS 64

/* ==== material table ==================================================================== */

/* m named primitives with a display colour and physical properties (open-ended keys with SI
 * units: "density" kg/m^3, "youngs_modulus" Pa, "poisson_ratio" 1, ...). Stored in a volume
 * as one float grid per material ("material.<name>") plus this table as JSON in the metadata
 * key "hovox.materials.json". */
typedef struct hv_material_table hv_material_table;

HV_API hv_status hv_material_table_create(hv_material_table **out);
HV_API void hv_material_table_destroy(hv_material_table *t);
HV_API hv_status hv_material_table_clone(const hv_material_table *t, hv_material_table **out);

/* Add a material. Names: 1-64 bytes of [A-Za-z0-9_-], unique. rgba in [0,1] (NULL: the next
 * colour of a distinguishable palette). Errors: HV_ERR_INVALID (name, colour, more than
 * HV_MAX_MATERIALS). *index may be NULL. */
HV_API hv_status hv_material_add(hv_material_table *t, const char *name, const float rgba[4],
                                 int *index);
HV_API int hv_material_count(const hv_material_table *t);
HV_API const char *hv_material_name(const hv_material_table *t, int m);
HV_API int hv_material_find(const hv_material_table *t, const char *name); /* -1: none */
HV_API void hv_material_color(const hv_material_table *t, int m, float rgba[4]);
HV_API hv_status hv_material_set_color(hv_material_table *t, int m, const float rgba[4]);
/* The i-th colour of the default palette (tab10-like), for i >= 0. */
HV_API void hv_material_palette(int i, float rgba[4]);
/* A PolyJet resin: its public product name and the display colour hovox gives it. */
typedef struct hv_resin {
    const char *name;
    uint8_t rgb[3];
} hv_resin;
/* The one table of resin colours (static; *n entries; public names, display colours chosen by
 * hovox, not vendor-confirmed). A material named like a resin (case-insensitively) is shown in
 * that resin's colour everywhere: hv_material_add gives it that colour when none is given, and a
 * tray prints it in that resin. */
HV_API const hv_resin *hv_resin_table(int *n);
/* The resin named `name` (case-insensitive), or NULL. */
HV_API const hv_resin *hv_resin_find(const char *name);
/* Colours are parsed by hv_color_parse (hovox/options.h). */
/* A table from its text form (the CLI's --materials, --colors, --property): `names` "A,B,C",
 * `colors` "#rrggbb,..." one per material (NULL: the palette), and `props[0..nprops)` each
 * "MATERIAL:KEY=VALUE[:UNIT]" (no unit: hv_property_si_unit). Errors: HV_ERR_INVALID naming the
 * option ({materials}, {colors}, {property}) and the text; HV_ERR_NOMEM. */
HV_API hv_status hv_material_table_parse(const char *names, const char *colors, const char *const *props,
                                         int nprops, hv_material_table **out);
/* The colours and properties of the same text form applied to an existing table (one colour per
 * material, in order; NULL: keep them). Errors: as hv_material_table_parse. */
HV_API hv_status hv_material_table_amend(hv_material_table *t, const char *colors, const char *const *props,
                                         int nprops);
/* The material name a file's material text becomes: each byte outside [A-Za-z0-9_-] replaced by
 * '_', cut to 64 bytes, "material" when empty ("Agilus30 Clear" -> "Agilus30_Clear",
 * "#FF8000" -> "_FF8000"). */
HV_API void hv_material_name_from(const char *text, char out[65]);

/* Properties: set (replacing) a value with its SI unit (may be "" or NULL). Keys: 1-64 bytes
 * of [A-Za-z0-9_.-]. Properties keep the order they were first set in (a front end reading them
 * from a table without an order, a Lua table or a Python dict, sets them in key order, so the
 * same table gives the same model). Errors: HV_ERR_INVALID (key, non-finite value). */
HV_API hv_status hv_material_set_property(hv_material_table *t, int m, const char *key,
                                          double value, const char *unit);
/* The SI unit of a property hovox knows by name ("density" -> "kg/m^3"; "youngs_modulus",
 * "shear_modulus", "bulk_modulus" -> "Pa"; "poisson_ratio" -> "1"), "" for any other: the unit
 * of a value given without one. */
HV_API const char *hv_property_si_unit(const char *key);
/* 1 and *value (and *unit, owned by the table, if unit != NULL) when material m has `key`. */
HV_API int hv_material_property(const hv_material_table *t, int m, const char *key,
                                double *value, const char **unit);
HV_API int hv_material_property_count(const hv_material_table *t, int m);
HV_API const char *hv_material_property_key(const hv_material_table *t, int m, int i);

/* JSON form (the "hovox.materials.json" document): {"schema": 1, "materials": [{"name": ...,
 * "color": [r,g,b,a], "properties": {key: {"value": v, "unit": u}}}]}. to_json: *json is
 * malloc'd (free()); errors HV_ERR_NOMEM. from_json reads documents without "schema" (older
 * hovox) as version 1. Errors: HV_ERR_BAD_INPUT (malformed JSON with line and column, a
 * missing or mistyped member, an invalid name or colour, a schema version this hovox does not
 * read; the message names the member), HV_ERR_NOMEM. */
HV_API hv_status hv_material_table_to_json(const hv_material_table *t, char **json);
HV_API hv_status hv_material_table_from_json(const char *json, hv_material_table **out);

/* The table stored in a volume's metadata. Errors: HV_ERR_NOT_FOUND (no table: not a graded
 * model), HV_ERR_BAD_INPUT (corrupt table, or a material without its "material.<name>" float
 * grid). */
HV_API hv_status hv_material_table_load(const hv_volume *vol, hv_material_table **out);
HV_API hv_status hv_material_table_store(hv_volume *vol, const hv_material_table *t);

/* Float grid index of material m in vol ("material.<name>"), or -1. */
HV_API int hv_material_grid(const hv_volume *vol, const hv_material_table *t, int m);

/* Check a user-given composition: m entries, each >= 0 and summing to 1 within 1e-6 (Wu eq.
 * 12). Errors: HV_ERR_INVALID naming `what` and the vector ("Ms = [0.1, 0.7, 0.3] sums to
 * 1.1, not 1"). Never clamps. */
HV_API hv_status hv_composition_check(const double *p, int m, const char *what);

/* ==== units and calibration tables ======================================================== */

/* Units hovox converts: pressure Pa, kPa, MPa, GPa, N/mm^2 (SI Pa); density kg/m^3 (also
 * kg/m3), g/cm^3 (g/cm3, g/cc) (SI kg/m^3); dimensionless 1 (also -). Any other unit
 * ("ShoreA", "ShoreD", "W/mK") is kept as written and matches only itself (case-sensitive).
 * hv_unit_si: 1 and *si, *factor (value in unit = factor x value in si) for a unit of that list,
 * else 0 (*si = unit, *factor = 1). */
HV_API int hv_unit_si(const char *unit, const char **si, double *factor);
/* 1 and *factor (x in `from` = factor * x in `to`) when a value in `from` converts to `to`:
 * the same text, or two units of one family above; "" converts only to "". */
HV_API int hv_unit_convert(const char *from, const char *to, double *factor);
/* A quantity: a finite number, optionally followed (spaces allowed) by a unit ("2GPa",
 * "5 MPa", "85ShoreA", "1e9"); *value is converted to `unit` (a number without a unit is taken
 * in `unit`). `what` names the value in messages ("Ps"). Errors: HV_ERR_INVALID ("Ps = '2 XPa':
 * unit XPa does not convert to MPa", "Ps = 'abc' is not a number with an optional unit"). */
HV_API hv_status hv_quantity_parse(const char *text, const char *unit, const char *what, double *value);

/* A calibration table: measured values of one property along the composition path of a grading
 * source, property(t) where t in [0, 1] is the position along the segment Ms -> Me (the
 * composition Ms + t (Me - Ms)), so one table serves any number of materials. Rows (t_i, v_i):
 * at least 2, t strictly increasing in [0, 1], values finite and strictly monotone (increasing
 * or decreasing), so the table is invertible. Piecewise linear between rows; the property is
 * unknown (NAN) outside [t_0, t_n-1]. Reference-counted and immutable. */
typedef struct hv_calibration hv_calibration;

/* Make a table. property: 1-64 bytes of [A-Za-z0-9_-]; unit: at most 32 bytes without
 * "[],", may be NULL or "". Copies everything. Errors: HV_ERR_INVALID naming the first bad row
 * ("calibration of youngs_modulus: row 3: value 150 is not greater than row 2's (200): the
 * values must be strictly monotone"), HV_ERR_NOMEM. Release with hv_calibration_release. */
HV_API hv_status hv_calibration_create(const char *property, const char *unit, const double *t,
                                       const double *value, int n, hv_calibration **out);
/* Parse the CSV form (README "Calibration tables"): '#' comment lines and blank lines are
 * skipped; the header "t,<property>" or "t,<property>[<unit>]"; then rows "t,value".
 * `name` names the text in messages (a file name). Errors: HV_ERR_BAD_INPUT naming the file and
 * line ("cal.csv: line 5: youngs_modulus 150 is not greater than line 4's (200): the values
 * must be strictly monotone"; "cal.csv: line 1: header 'x,E' is not 't,<property>[<unit>]'";
 * "cal.csv: line 3: youngs_modulus 'nan' is not a finite number"; "cal.csv: no rows"),
 * HV_ERR_NOMEM. */
HV_API hv_status hv_calibration_parse(const char *text, size_t len, const char *name,
                                      hv_calibration **out);
/* Read and parse a file (at most 16 MiB). Errors: those of hv_calibration_parse, HV_ERR_IO. */
HV_API hv_status hv_calibration_load(const char *path, hv_calibration **out);
HV_API hv_calibration *hv_calibration_retain(hv_calibration *c);
HV_API void hv_calibration_release(hv_calibration *c); /* NULL allowed */
/* The property at t (NAN outside [t_0, t_n-1] or for NAN). */
HV_API double hv_calibration_eval(const hv_calibration *c, double t);
/* The exact inverse of the piecewise-linear table: the t whose value is `value`. Errors:
 * HV_ERR_INVALID ("youngs_modulus 3000 MPa is outside the calibration's range [0.6, 2000]
 * MPa"). */
HV_API hv_status hv_calibration_invert(const hv_calibration *c, double value, double *t);
/* The smallest and largest value. */
HV_API void hv_calibration_range(const hv_calibration *c, double *lo, double *hi);
HV_API const char *hv_calibration_property(const hv_calibration *c);
HV_API const char *hv_calibration_unit(const hv_calibration *c); /* "" when none */
HV_API int hv_calibration_rows(const hv_calibration *c);
/* Row i (0 <= i < rows). */
HV_API void hv_calibration_row(const hv_calibration *c, int i, double *t, double *value);

/* ==== distribution functions ============================================================ */

/* f on [0, dg]: evaluated once into a table (4097 samples, linear interpolation) when an AGS
 * is made; never called per voxel. */
typedef struct hv_dfn hv_dfn;

/* f(d) = a*d + b */
HV_API hv_status hv_dfn_linear(double a, double b, hv_dfn **out);
/* f(d) = amplitude * sin(k*d + phase) + offset (Wu's shaft: k = 0.1538) */
HV_API hv_status hv_dfn_sine(double k, double amplitude, double phase, double offset,
                             hv_dfn **out);
/* f(d) = (d/dg)^p, p > 0 */
HV_API hv_status hv_dfn_power(double p, hv_dfn **out);
/* f(d) = 3t^2 - 2t^3, t = d/dg */
HV_API hv_status hv_dfn_smoothstep(hv_dfn **out);
/* Piecewise linear through (d_i, f_i), d strictly increasing, n >= 2; constant beyond the
 * ends. Errors: HV_ERR_INVALID naming the offending point. */
HV_API hv_status hv_dfn_table(const double *d, const double *f, int n, hv_dfn **out);
/* f as a named kind with its parameters (a script's f = {kind = "sine", k = 0.15}): kind
 * linear (a = 1, b = 0), sine (k required, amplitude = 1, phase = 0, offset = 0), power (p
 * required), smoothstep, or table (its points are given to hv_dfn_table by the caller). */
typedef enum hv_dfn_kind { HV_DFN_LINEAR, HV_DFN_SINE, HV_DFN_POWER, HV_DFN_SMOOTHSTEP, HV_DFN_TABLE } hv_dfn_kind;
typedef struct hv_dfn_options {
    int kind; /* hv_dfn_kind */
    double a, b, k, amplitude, phase, offset, p;
} hv_dfn_options;
/* Keys kind (required), a, b, k, amplitude, phase, offset, p; a parameter another kind does not
 * take is refused, and so is a missing required one. Static data. */
HV_API const hv_option_set *hv_dfn_option_set(void);
/* The function the options name (not for HV_DFN_TABLE: HV_ERR_INVALID). */
HV_API hv_status hv_dfn_from_options(const hv_dfn_options *o, hv_dfn **out);
/* An arithmetic expression in d (and dg): numbers, + - * / ^, parentheses, unary minus,
 * sin cos tan exp log sqrt abs min max pow, pi. Errors: HV_ERR_INVALID "f: column 7:
 * unknown name 'sn'". */
HV_API hv_status hv_dfn_expr(const char *expr, hv_dfn **out);
/* A callback (scripting languages): called only while tabulating, on the calling thread;
 * a non-finite return value is an error. `user` must outlive the AGS creation. */
typedef double (*hv_dfn_callback)(void *user, double d);
HV_API hv_status hv_dfn_function(hv_dfn_callback fn, void *user, const char *description,
                                 hv_dfn **out);
HV_API void hv_dfn_destroy(hv_dfn *f);
/* f(d) for a given dg (used by the table); NAN when a callback fails. */
HV_API double hv_dfn_eval(const hv_dfn *f, double d, double dg);
/* Text form for metadata and messages ("linear(0.105, 0)", "expr(sin(0.1538*d))"). */
HV_API const char *hv_dfn_describe(const hv_dfn *f);

/* ==== reference features ================================================================ */

/* A fixed reference feature gives each point a distance d >= 0 (world units; dimensionless
 * for the harmonic feature), or, for the signed features (a half-space, a field of data), a value
 * of either sign. Analytic features are exact; voxel features use the exact
 * Euclidean distance transform of their feature voxels (src/field), computed once per
 * evaluation lattice and cached. FRFs are reference-counted and immutable. */
typedef struct hv_frf hv_frf;

typedef enum hv_frf_kind {
    HV_FRF_POINT, HV_FRF_LINE, HV_FRF_PLANE, HV_FRF_SEGMENT,
    HV_FRF_CONTOUR, HV_FRF_MASK, HV_FRF_FACETS, HV_FRF_HARMONIC,
    HV_FRF_FIELD, /* a stored distance grid ("distance.K" of a graded model) */
    HV_FRF_HALFSPACE /* signed distance to a plane, positive on the side the normal points to */
} hv_frf_kind;

HV_API hv_status hv_frf_point(const double p[3], hv_frf **out);
/* Infinite line (an axis) through origin along dir (non-zero). */
HV_API hv_status hv_frf_line(const double origin[3], const double dir[3], hv_frf **out);
/* Plane through point with normal (non-zero): d = |n.(x - point)| / |n|. */
HV_API hv_status hv_frf_plane(const double point[3], const double normal[3], hv_frf **out);
HV_API hv_status hv_frf_segment(const double a[3], const double b[3], hv_frf **out);
/* The half-space side of a plane, signed: d = n.(x - point) / |n|, positive on the side the normal
 * points to, negative behind (a plane feature is its absolute value). */
HV_API hv_status hv_frf_halfspace(const double point[3], const double normal[3], hv_frf **out);
/* 1 when the feature's d may be negative (half-space, field), so a source's d- may be too. */
HV_API int hv_frf_is_signed(const hv_frf *f);
/* The boundary of bool grid `grid` of vol (the model's contour): d = depth below the boundary
 * for voxels inside (estimated from the distance transform to the outside, corrected by half
 * the surface skin, see README), 0 outside. vol is copied (the mask only). */
HV_API hv_status hv_frf_contour(const hv_volume *vol, const char *grid, hv_frf **out);
/* Distance to the true voxels of bool grid `grid` of vol (copied). */
HV_API hv_status hv_frf_mask(const hv_volume *vol, const char *grid, hv_frf **out);

/* Facet selection: facets whose unit normal is within `angle_deg` of `normal` (if
 * use_normal) and whose centroid lies in [box_lo, box_hi] (if use_box). */
typedef struct hv_facet_select {
    int use_normal;
    double normal[3], angle_deg;
    int use_box;
    double box_lo[3], box_hi[3];
} hv_facet_select;
/* Distance to a group of mesh facets (copied). Errors: HV_ERR_INVALID (no facet selected). */
HV_API hv_status hv_frf_facets(const hv_mesh *mesh, const hv_facet_select *sel, hv_frf **out);
/* Number of facets a selection picks (for messages and scripts). */
HV_API size_t hv_facet_select_count(const hv_mesh *mesh, const hv_facet_select *sel);
/* Harmonic field inside bool grid `domain` of vol between facet groups: phi = 1 on group `one`,
 * 0 on group `zero`, Laplace inside, zero normal derivative elsewhere; d = phi in [0, 1]. */
HV_API hv_status hv_frf_harmonic(const hv_volume *vol, const char *domain, const hv_mesh *mesh,
                                 const hv_facet_select *one, const hv_facet_select *zero,
                                 hv_frf **out);

/* Features from options: the kinds point, axis (alias line), plane, halfspace, segment, contour,
 * mask and field, each with its keys (point: point; axis: origin, direction; plane, halfspace: point, normal;
 * segment: from, to; contour, mask: grid; field: file, array, outside). */
typedef struct hv_frf_options {
    hv_frf_kind kind;
    double point[3], origin[3], direction[3], normal[3], from[3], to[3];
    const char *grid; /* borrowed */
    const char *file, *array; /* field: the data file and its array (or .vdb grid); borrowed */
    int outside;              /* field: hv_field_outside */
} hv_frf_options;
/* Name <-> kind ("point", "axis" (or "line"), "plane", "segment", "contour", "mask", "facets",
 * "harmonic", "field"). */
HV_API hv_status hv_frf_kind_parse(const char *name, hv_frf_kind *out);
HV_API const char *hv_frf_kind_name(hv_frf_kind kind);
HV_API const hv_enum_def *hv_frf_kind_enum(void);
/* The option set of a kind made from options (init sets `kind`); NULL for the others. */
HV_API const hv_option_set *hv_frf_option_set(hv_frf_kind kind);
/* Make the feature (contour, mask and field need vol). Errors: those of the hv_frf_* makers and of
 * the options' domains. */
HV_API hv_status hv_frf_from_options(const hv_frf_options *o, const hv_volume *vol, hv_frf **out);
/* Facet selections as options: normal, angle (default 10), box_min, box_max. */
HV_API const hv_option_set *hv_facet_select_option_set(void);

/* ---- field features: a scalar field read from data (FEA results, scans) --------------------
 * The field's value at each voxel centre of the model plays the role of d (so a source's ranges
 * are in the field's units). Files: .vti (VTK image data: point data sampled trilinearly, cell
 * data by the cell holding the point), .vtu (unstructured grid, probed at the voxel centres
 * with its cells' interpolation; cell data takes the cell's value), both through the VTK
 * bridge plugin; .vdb (a float grid, trilinear over its active voxels). Voxels the field does
 * not cover: refused with their count (HV_FIELD_REFUSE), or given the value of the nearest
 * covered voxel (HV_FIELD_NEAREST: Euclidean, by a vector-propagation wave over the model's
 * box, exact up to the rare ties and corners such waves miss). The
 * feature is a stored field ("field" kind) on the model's lattice: it is saved as the model's
 * "distance.K" grid, so the model can be rebuilt without the file. */
typedef enum hv_field_outside { HV_FIELD_REFUSE = 0, HV_FIELD_NEAREST = 1 } hv_field_outside;
HV_API const hv_enum_def *hv_field_outside_enum(void); /* "refuse", "nearest" */
typedef struct hv_field_report {
    double lo, hi;        /* the field's range over the model's voxels (after filling) */
    double file_lo, file_hi; /* the array's range in the file */
    uint64_t voxels;      /* model voxels */
    uint64_t filled;      /* of which not covered by the field, filled by the rule */
} hv_field_report;
/* Read `array` (a grid name for .vdb) of `path` at the voxel centres of bool grid `grid` of vol
 * (NULL: "occupancy"). Errors: HV_ERR_IO (cannot open), HV_ERR_BAD_INPUT (unreadable file, no
 * such array or grid: the message lists those there are, an array of more than 1 component, a
 * field that covers no model voxel, voxels outside the field under HV_FIELD_REFUSE: "s.vti:
 * sigma covers 900 of 1000 model voxels; 100 lie outside it"), HV_ERR_NOT_FOUND (no bool grid
 * `grid`), HV_ERR_UNSUPPORTED (an extension other than .vti, .vtu, .vdb; or the VTK plugin
 * missing), HV_ERR_NOMEM. */
HV_API hv_status hv_frf_field_file(const hv_volume *vol, const char *grid, const char *path,
                                   const char *array, hv_field_outside outside, hv_frf **out);
/* A field given as an array (a solver's result in a script: a NumPy array): dims[0] x dims[1] x
 * dims[2] point samples, x slowest and z fastest (a C-order (nx, ny, nz) array), sample (i, j, k)
 * at origin + (i, j, k) * spacing (world units), as float (double_values 0) or double values.
 * Sampled at the voxel centres as a .vti's point data is: trilinear in the cell holding the
 * centre (weights in double, the result rounded to float), so the same samples written to a .vti
 * give the same field up to that rounding (bit for bit where the centres' cell coordinates are
 * exact binary fractions); centres outside [origin, origin + (dims - 1) spacing] are not covered
 * and follow `outside`, as for files. An axis of one sample covers only its plane. */
typedef struct hv_field_grid {
    const void *values;  /* read during the call only */
    int double_values;   /* 1: double, 0: float */
    int64_t dims[3];
    double spacing[3], origin[3];
} hv_field_grid;
/* The feature of such an array on bool grid `grid` of vol (NULL: "occupancy"); `name` (may be
 * NULL: "array") names it in messages and in its description ("field(name)"). Errors:
 * HV_ERR_INVALID (dims outside 1..2^24, spacing not > 0, a non-finite value or origin, naming
 * the sample), HV_ERR_LIMIT (more than 2^40 samples), HV_ERR_BAD_INPUT (no voxel covered, or
 * voxels outside under HV_FIELD_REFUSE), HV_ERR_NOT_FOUND (no bool grid `grid`), HV_ERR_NOMEM.
 * hv_frf_field_report works on it (file_lo, file_hi: the array's range). */
HV_API hv_status hv_frf_field_grid(const hv_volume *vol, const char *grid, const hv_field_grid *g,
                                   const char *name, hv_field_outside outside, hv_frf **out);
/* 1 and *r for a feature made by hv_frf_field_file or hv_frf_field_grid; 0 for others. */
HV_API int hv_frf_field_report(const hv_frf *f, hv_field_report *r);

HV_API hv_frf *hv_frf_retain(hv_frf *f);
HV_API void hv_frf_release(hv_frf *f); /* NULL allowed */
HV_API hv_frf_kind hv_frf_get_kind(const hv_frf *f);
/* Text form ("line(0,0,0; 0,0,1)", "contour(occupancy)") for metadata and messages. */
HV_API const char *hv_frf_describe(const hv_frf *f);
/* Distance at a world point (analytic features exactly; voxel features from the cached field on
 * the lattice of `vol`, trilinearly; computing it on first use). */
HV_API hv_status hv_frf_distance(hv_frf *f, const hv_volume *lattice, const double p[3],
                                 double *d);

/* ==== grading sources =================================================================== */

typedef struct hv_ags hv_ags;

/* Property targets of a source, in the calibration table's unit. */
typedef struct hv_property_target {
    const char *property; /* must be the table's property */
    double ps, pe;        /* Ps, Pe: inside the table's range */
    int log;              /* logarithmic interpolation between Ps and Pe */
} hv_property_target;

typedef struct hv_ags_desc {
    hv_frf *frf;
    double d_neg, d_grad, d_pos; /* d-, dg, d+ >= 0 */
    const hv_dfn *f;             /* ignored when d_grad == 0 (a step: an MMO) */
    const double *ms, *me;       /* m fractions each */
    int m;
    const char *name;            /* may be NULL */
} hv_ags_desc;


/* A source as options: ranges (D-,DG,D+) or d_neg, d_grad, d_pos; f (an expression; default
 * d/dg); ms, me (required, as many fractions as materials); name; calibration (a CSV file);
 * property_grading (a property name), ps, pe (quantities in the table's unit or one that
 * converts to it), log. */
typedef struct hv_ags_options {
    double d_neg, d_grad, d_pos;
    const char *f;      /* borrowed; NULL: d/dg */
    double ms[HV_MAX_MATERIALS], me[HV_MAX_MATERIALS];
    int nms, nme;
    const char *name;   /* borrowed; may be NULL */
    double c;           /* Wu's 3-material sources only: the third material's fraction C */
    const char *calibration;         /* a calibration table's CSV file (borrowed; may be NULL) */
    hv_calibration *calibration_table; /* or the table itself, made by a front end from its own
                                          syntax (borrowed; wins over `calibration`) */
    const char *property_grading;    /* grade to property targets: the property's name */
    const char *ps, *pe;             /* Ps, Pe: quantities, "2GPa" (hv_quantity_parse) */
    int log;                         /* logarithmic interpolation between Ps and Pe */
} hv_ags_options;
HV_API void hv_ags_options_init(hv_ags_options *o);
HV_API const hv_option_set *hv_ags_option_set(void);
/* Make an AGS on frf from options; `f` (may be NULL) replaces the expression o->f (a callback
 * from a script). Errors: those of the options and of hv_ags_create. */
HV_API hv_status hv_ags_from_options(hv_frf *frf, const hv_ags_options *o, const hv_dfn *f, hv_ags **out);
/* Wu's 3-material source (hv_ags_wu3) as options: ranges or d_neg, d_grad, d_pos; f (required
 * here, unless given as `f`); c in [0, 1]. */
HV_API const hv_option_set *hv_wu3_option_set(void);
HV_API hv_status hv_ags_wu3_from_options(hv_frf *frf, const hv_ags_options *o, const hv_dfn *f, hv_ags **out);

/* Make an AGS: validates the ranges (finite, >= 0), Ms and Me (hv_composition_check), and
 * tabulates f over [0, dg], requiring 0 <= f <= 1 (within 1e-9) at every sample. Evaluation:
 *   dg > 0:  P(d) = Ms + f(clamp(d - d-, 0, dg)) (Me - Ms)   (boundary values from f, eq. 14)
 *   dg = 0:  P(d) = Ms for d < d-, Me for d >= d-            (a step: multi-material object)
 * d+ is the extent of the positive constant range (Wu eq. 11), kept and reported.
 * Errors: HV_ERR_INVALID, e.g. "f leaves [0, 1]: f(9.54) = 1.0017 (max over [0, 9.54])". */
HV_API hv_status hv_ags_create(const hv_ags_desc *desc, hv_ags **out);
/* hv_ags_create with a calibration table along Ms -> Me (may be NULL; the source keeps a
 * reference) and property targets (may be NULL; need the calibration, dg > 0 and f): the
 * property at distance d is Ps + f(clamp(d - d-, 0, dg)) (Pe - Ps), or Ps (Pe/Ps)^f with log
 * (Ps, Pe > 0), and the source gives the composition Ms + t (Me - Ms) whose table value that is
 * (t from the exact inverse of the piecewise-linear table, tabulated with f). Errors: those of
 * hv_ags_create, and HV_ERR_INVALID for targets for another property, outside the table's range
 * ("Ps = 3000 MPa is outside the calibration table's youngs_modulus range [0.6, 2000] MPa"), or
 * without a table or a gradient range. */
HV_API hv_status hv_ags_create_calibrated(const hv_ags_desc *desc, hv_calibration *calibration,
                                          const hv_property_target *target, hv_ags **out);
/* Wu's move operator: the same source with d- replaced. */
HV_API hv_status hv_ags_moved(const hv_ags *a, double d_neg, hv_ags **out);
HV_API hv_ags *hv_ags_retain(hv_ags *a);
HV_API void hv_ags_release(hv_ags *a);
/* Composition at distance d (m values). */
HV_API void hv_ags_eval(const hv_ags *a, double d, double *p);
HV_API int hv_ags_materials(const hv_ags *a);
HV_API const hv_frf *hv_ags_frf(const hv_ags *a);
HV_API void hv_ags_ranges(const hv_ags *a, double *d_neg, double *d_grad, double *d_pos);
HV_API const char *hv_ags_name(const hv_ags *a);
/* The source's calibration table (NULL: none; owned by the source) and its property targets
 * (0: none; else *t filled, t->property owned by the source). */
HV_API const hv_calibration *hv_ags_calibration(const hv_ags *a);
HV_API int hv_ags_target(const hv_ags *a, hv_property_target *t);
/* Where composition p (m fractions) lies on the source's segment Ms -> Me: t = (p - Ms).(Me - Ms)
 * / |Me - Ms|^2. Returns 1 when p is on the segment (every fraction within 1e-3 of
 * Ms + t (Me - Ms), -1e-3 <= t <= 1 + 1e-3; t is then clamped to [0, 1]), 0 otherwise (Ms == Me
 * included). */
HV_API int hv_ags_segment_t(const hv_ags *a, const double *p, double *t);
/* Wu's 3-material distance-field paradigm (eq. 13): P = [f, 1 - f - C, C] over the gradient
 * range, as an AGS with Ms = [f(0), 1 - f(0) - C, C], Me = [f(dg), 1 - f(dg) - C, C] and
 * the same f. Checks 0 <= f <= 1 - C on [0, dg]. */
HV_API hv_status hv_ags_wu3(hv_frf *frf, double d_neg, double d_grad, double d_pos,
                            const hv_dfn *f, double C, hv_ags **out);

/* ==== heterogeneous objects ============================================================== */

typedef enum hv_blend {
    HV_BLEND_NEAREST = 0, /* each voxel takes the source whose feature is nearest (ties: the
                             first added) */
    HV_BLEND_IDW = 1      /* inverse-distance weights 1 / (d_i + eps)^power, eps = voxel/2 */
} hv_blend;

/* Name <-> blend ("nearest", "idw"); an unknown name is HV_ERR_INVALID listing the names. */
HV_API hv_status hv_blend_parse(const char *name, hv_blend *out);
HV_API const char *hv_blend_name(hv_blend blend);
HV_API const hv_enum_def *hv_blend_enum(void);

/* An object: regions (geometry mask on a shared lattice, AGS set, base composition for voxels
 * where the region has no source) over m materials. Regions may be named (the regions of an
 * assembly are named after its bodies); a name is unique within the object. */
typedef struct hv_object hv_object;

/* A one-region object: bool grid `grid` of vol (copied) with no AGS; base = material 0. The
 * object also keeps vol's record (its metadata other than "hovox.materials.json" and
 * "hovox.object.json": the mesh report and voxelization; and its bool grid "surface") for the
 * volumes it evaluates to. Errors: HV_ERR_NOT_FOUND (no such bool grid), HV_ERR_INVALID (m out
 * of range). */
HV_API hv_status hv_object_create(const hv_volume *vol, const char *grid, int m,
                                  hv_object **out);
/* An object with one region per region of a model voxelized from an assembly (hv_voxelize of a
 * multi-body mesh, hv_voxelize_regions_read; regions that lost every voxel to earlier bodies are
 * left out), named after the bodies, without sources, each region's base 100% its body's
 * material. The materials: `given` (may be NULL), which must name every region's material, its
 * text made a material name by hv_material_name_from (a region without one then takes material
 * 0); without `given`, the regions' materials in first-use order, in the file's colours (else the
 * palette). *table receives the object's material table (a copy of `given`, or the one built;
 * free with hv_material_table_destroy). The object keeps vol's record (see hv_object_create).
 * Errors: HV_ERR_NOT_FOUND (not an assembly), HV_ERR_BAD_INPUT (a region grid missing, every
 * region empty, a damaged regions document), HV_ERR_INVALID ("region 'core' is material
 * Agilus, which the materials given (A, B) do not name"; a region without a material and no
 * `given`: naming the option {materials}; more than HV_MAX_MATERIALS), HV_ERR_NOMEM. */
HV_API hv_status hv_object_from_regions(const hv_volume *vol, const hv_material_table *given,
                                        hv_material_table **table, hv_object **out);
HV_API void hv_object_destroy(hv_object *o);
HV_API hv_status hv_object_clone(const hv_object *o, hv_object **out);
HV_API int hv_object_materials(const hv_object *o);
HV_API int hv_object_region_count(const hv_object *o);
/* Voxels of region r, and of the whole object. */
HV_API uint64_t hv_object_region_voxels(const hv_object *o, int r);
HV_API uint64_t hv_object_voxels(const hv_object *o);
HV_API int hv_object_region_ags_count(const hv_object *o, int r);
/* Name of region r (owned by the object), NULL when unnamed or out of range. */
HV_API const char *hv_object_region_name(const hv_object *o, int r);
/* The region of this exact name, or -1. */
HV_API int hv_object_region_find(const hv_object *o, const char *name);
/* Region r's base composition (m values). */
HV_API void hv_object_region_base(const hv_object *o, int r, double *p);

/* The base of every region (and of regions Booleans make from none), checked. */
HV_API hv_status hv_object_set_base(hv_object *o, const double *p);
/* The base of region r alone, checked. Errors: HV_ERR_INVALID (r out of range, p not a
 * composition). */
HV_API hv_status hv_object_set_region_base(hv_object *o, int r, const double *p);
HV_API hv_status hv_object_set_blend(hv_object *o, hv_blend blend, double power);

/* AGS operators (Wu 2.2.3) on every region: add (eq. 24), delete (25: HV_ERR_NOT_FOUND when
 * absent), move (26: replaces the source by one with d- changed). The object keeps a reference. */
HV_API hv_status hv_object_add_ags(hv_object *o, hv_ags *a);
/* Add a source to the region of this name alone (the other regions keep their sources or
 * base). Errors: HV_ERR_INVALID (material count), HV_ERR_NOT_FOUND ("the object has no region
 * 'x' (regions: core, shell)"). */
HV_API hv_status hv_object_add_ags_region(hv_object *o, const char *region, hv_ags *a);
HV_API hv_status hv_object_delete_ags(hv_object *o, const hv_ags *a);
HV_API hv_status hv_object_move_ags(hv_object *o, const hv_ags *a, double d_neg);
/* Put source b in the place of a in every region that holds a (the order kept, so the blend's
 * ties fall as before); the object keeps a reference to b. Move is hv_ags_moved then this, for
 * callers that keep the moved source (to delete or move it later). Errors: HV_ERR_NOT_FOUND (a
 * absent), HV_ERR_INVALID (b over another material count). */
HV_API hv_status hv_object_replace_ags(hv_object *o, const hv_ags *a, hv_ags *b);

/* Heterogeneous Booleans (Wu eq. 27-30) and plain CSG subtraction; a and b must share the
 * lattice and the material count (HV_ERR_INVALID otherwise). Results are new objects:
 *   intersect  H1 n H2 = (O1 n O2, G1 u G2)
 *   unite      H1 u H2 = {(O1 - O2, G1), (O1 n O2, G1 u G2), (O2 - O1, G2)}
 *   difference H1 - H2 = {(O1 - O2, G1), (O1 n O2, G2)}   (Wu: H2's material in the overlap)
 *   merge      H1 + H2 = (O1 u O2, G1 u G2)
 *   subtract   (O1 - O2, G1)                             (CSG)
 * Empty regions are dropped. A result region keeps the name and base of the operand region it
 * comes from (a's region for the pieces of O1, also O1 n O2 of intersect and unite; b's for the
 * pieces of O2 only and for difference's O1 n O2, whose sources are H2's); a name already taken
 * by an earlier result region is dropped (the region is then unnamed); merge's one region is
 * unnamed with a's default base. The result keeps the model metadata both operands keep alike and
 * the union of their surfaces (see hv_object_create). */
typedef enum hv_bool_op {
    HV_OP_INTERSECT, HV_OP_UNITE, HV_OP_DIFFERENCE, HV_OP_MERGE, HV_OP_SUBTRACT
} hv_bool_op;
HV_API hv_status hv_object_boolean(const hv_object *a, const hv_object *b, hv_bool_op op,
                                   hv_object **out);

/* Evaluate into a new volume on the object's lattice: bool grid "occupancy" (union of the
 * regions), one float grid "material.<name>" per material holding fractions that sum to 1 in
 * every occupied voxel, float grids "distance.K" holding the fields of voxel features (facets,
 * harmonic, fields from files; contour and mask features too unless their mask is exactly one
 * of the result's bool grids, such as its occupancy or a region: those fields are recomputed
 * from that grid by hv_object_from_model instead, bit for bit), bool grids "region.<name>" for
 * named regions and "region.R" for unnamed ones when there are several, and metadata
 * "hovox.materials.json" and "hovox.object.json": the complete grading definition (features,
 * sources with their tabulated f, regions with their names and bases), so hv_object_from_model
 * can rebuild the object (schema version 1 when no region has a name or a base of its own, as
 * older hovox wrote; else 2);
 * plus the record of the object's model (hv_object_create): its other metadata and its bool
 * grid "surface" restricted to the occupied voxels. So a model graded by `hovox grade` and one
 * graded from Lua hold the same grids and metadata.
 * Multi-threaded over leaves, deterministic. Memory is planned first:
 * HV_ERR_LIMIT when it would exceed max_memory (0: half of RAM), saying how much it needs.
 * Errors: HV_ERR_INVALID (table has a different material count), HV_ERR_NOMEM,
 * HV_ERR_CANCELLED. */
HV_API hv_status hv_object_evaluate(hv_object *o, const hv_material_table *t,
                                    uint64_t max_memory, const hv_progress *progress,
                                    hv_volume **out);
/* Evaluate again into `vol`, a volume hv_object_evaluate made for an object with the same
 * regions (after AGS add/delete/move, a new base or blend): only material values change, no
 * allocation. Errors: HV_ERR_INVALID (vol lacks a material grid, or a region voxel is not in
 * vol), HV_ERR_CANCELLED. */
HV_API hv_status hv_object_reevaluate(hv_object *o, const hv_material_table *t, hv_volume *vol,
                                      const hv_progress *progress);

/* Peak bytes hv_object_evaluate would need. */
HV_API uint64_t hv_object_evaluate_estimate(const hv_object *o);

/* Rebuild the object that graded `vol` (hv_object_evaluate's output, possibly saved and loaded)
 * from its metadata and grids: analytic features exactly, voxel features as their stored
 * fields or recomputed from the bool grid they name (the exact EDT, as grading computed it), sources with their tabulated f, regions, base and blend, and vol's record (as
 * hv_object_create). Definitions written by older hovox (without "schema") read as version 1.
 * Errors: HV_ERR_NOT_FOUND (not a graded model), HV_ERR_BAD_INPUT (incomplete or corrupt
 * definition: malformed JSON, a missing member, an unknown feature kind or blend name, a schema
 * version this hovox does not read; the message names the member and the value). */
HV_API hv_status hv_object_from_model(const hv_volume *vol, hv_object **out);

/* Compute the fields of the object's voxel features over its box (once; evaluation does it
 * too). Needed before hv_object_sample. */
HV_API hv_status hv_object_prepare(hv_object *o, const hv_progress *progress);

/* The composition the grading definition gives at a world point (direct evaluation, e.g. at
 * printer resolution): the region whose voxel holds the point (or, within the surface skin, a
 * neighbouring voxel's region), its sources at the exact distance (analytic features) or the
 * trilinearly interpolated field (voxel features), blended as in evaluation. *inside = 0 (and
 * fractions 0) when no region is within a voxel. Read-only and thread-safe after
 * hv_object_prepare. fractions: hv_object_materials(o) values. */
HV_API void hv_object_sample(const hv_object *o, const double p[3], int *inside,
                             double *fractions);

/* ==== sampling a graded model ============================================================ */

/* Material fractions at a world point of a graded volume: trilinear over the occupied voxels
 * around it (renormalised, hv_volume_sample); *inside = 1 when the trilinear occupancy is at
 * least 0.5. fractions: hv_material_count(t) values (all 0 far outside). */
HV_API void hv_model_probe(hv_accessor *acc, const hv_material_table *t, const int *grids,
                           const double p[3], int *inside, double *fractions);
/* hv_model_probe at n points (xyz: 3n doubles, mm) as CSV on fp: a header
 * "x,y,z,inside,<material names>" and one row per point (coordinates %.9g, fractions %.6g).
 * Errors: those of hv_material_table_load (HV_ERR_NOT_FOUND: "model has no materials: grade it
 * first"), HV_ERR_IO (a write failed), HV_ERR_NOMEM. */
HV_API hv_status hv_model_probe_csv(const hv_volume *vol, const double *xyz, size_t n, FILE *fp);

/* Points from CSV text of x,y,z rows (`path` names it in messages): a header line (three
 * non-numeric fields before any row) allowed, blank lines and lines starting with '#' skipped,
 * CRLF accepted, a NUL byte refused (the CSV rows of every hovox table). Appends to *xyz (3 doubles per point, grown with realloc; the caller frees)
 * and counts them in *n. Errors: HV_ERR_BAD_INPUT ("p.csv: line 4: expected 3 values x,y,z,
 * found 2", "p.csv: line 5: y = 'abc' is not a finite number"), HV_ERR_NOMEM; the points read
 * before an error stay appended. read_csv reads the file first (at most 256 MiB; HV_ERR_IO,
 * HV_ERR_LIMIT). */
HV_API hv_status hv_points_parse_csv(const char *data, size_t size, const char *path, double **xyz, size_t *n);
HV_API hv_status hv_points_read_csv(const char *path, double **xyz, size_t *n);

#ifdef __cplusplus
}
#endif
#endif
