/* src/material/material_internal.h - internals shared by the material modules: expressions,
 * reference features' per-leaf distances, grading sources' tables. */
#ifndef HOVOX_MATERIAL_INTERNAL_H
#define HOVOX_MATERIAL_INTERNAL_H

#include <pthread.h>

#include "core/internal.h"
#include "core/json.h"
#include "hovox/material.h"

/* ---- expressions (expr.c) ---------------------------------------------------------------- */
typedef struct hv_expr hv_expr;
/* Errors: HV_ERR_INVALID "column N: ...". */
hv_status hv_expr_parse(const char *text, hv_expr **out);
double hv_expr_eval(const hv_expr *e, double d, double dg);
void hv_expr_free(hv_expr *e);

/* ---- reference features (frf.c) ------------------------------------------------------------ */

/* A dense distance field over a box of a lattice (voxel features), cached in the FRF. */
typedef struct hv_field_cache {
    hv_transform xf;
    int64_t lo[3], n[3]; /* index box: voxels lo .. lo + n - 1 */
    float *d;            /* n[0]*n[1]*n[2], index ((i*ny)+j)*nz+k */
} hv_field_cache;

struct hv_frf {
    int refs;
    hv_frf_kind kind;
    char desc[256];
    double a[3], b[3];   /* point; line origin/unit dir; plane point/unit normal; segment */
    hv_volume *mask;     /* contour, mask, harmonic domain: bool grid 0 = "mask" */
    float *tris;         /* facets, harmonic group "one": 9 floats per triangle */
    size_t ntris;
    float *tris0;        /* harmonic group "zero" */
    size_t ntris0;
    pthread_mutex_t lock;
    hv_field_cache cache;
    int has_report;        /* a field read from a file (hv_frf_field_file) */
    hv_frf_kind derived;   /* a stored field (HV_FRF_FIELD) recomputed on load from `src`:
                            * HV_FRF_CONTOUR or HV_FRF_MASK; else 0 */
    hv_volume *src;        /* its mask (bool grid 0, active = true), for writing it again */
    char src_grid[64];     /* the name of the grid it was read from */
    hv_field_report report;
};

/* Make sure the field of a voxel feature covers index box [lo, lo + n) of lattice xf
 * (computing it if needed). No-op for analytic features. Thread-safe. */
hv_status hv_frf_prepare(hv_frf *f, const hv_transform *xf, const int64_t lo[3],
                         const int64_t n[3], const hv_progress *progress);
/* Distances (world units) at the 512 voxel centres of the leaf at index origin `o` of
 * lattice xf, written to d[HV_LEAF_OFFSET(x,y,z)]. Voxel features must be prepared on a box
 * covering the leaf. */
void hv_frf_leaf_distances(const hv_frf *f, const hv_transform *xf, const int32_t o[3],
                           float *d);
/* A feature backed by float grid `grid` of vol (copied): a stored distance field. */
hv_status hv_frf_field(const hv_volume *vol, const char *grid, const char *description, hv_frf **out);
/* 1 for features whose distances come from a dense field (contour, mask, facets, harmonic). */
int hv_frf_is_voxel(const hv_frf *f);
/* Distance at a world point without preparing anything: analytic exactly, prepared voxel
 * features and stored fields trilinearly. Read-only, thread-safe. */
double hv_frf_sample(const hv_frf *f, const double p[3]);
/* Add float grid `grid` to vol holding the (prepared) field at vol's active voxels. */
hv_status hv_frf_store_field(const hv_frf *f, hv_volume *vol, const char *grid);
/* The name of a bool grid of vol from which f's field is recomputed exactly (f is a contour or
 * mask feature, or a field recomputed so, and its mask holds just that grid's true voxels), or
 * NULL: then the field must be stored. The name points into vol. vol NULL: the grid a
 * recomputed field was read from (pointing into f), else NULL. */
const char *hv_frf_derived_grid(const hv_frf *f, const hv_volume *vol);
/* A feature of the object document (hovox.object.json, volumes/schema.h): analytic ones by
 * kind ("point", "axis", "plane", "segment") and parameters; a contour or mask feature whose
 * field is recomputed on load as {"kind": "contour"|"mask", "grid": derived} (derived from
 * hv_frf_derived_grid); other voxel features as {"kind": "field", "grid": grid}; all with
 * their "text". NULL when out of memory. */
json_t *hv_frf_to_doc(const hv_frf *f, const char *grid, const char *derived);
/* The feature back; "field" features take float grid "grid" of vol; "contour" and "mask"
 * features recompute their field from bool grid "grid" of vol (the exact EDT, as when graded)
 * into a stored field on vol's active voxels. Unknown kinds are refused.
 * Errors: HV_ERR_BAD_INPUT naming `what` and the member, those of the hv_frf_* makers. */
hv_status hv_frf_from_doc(const json_t *j, const hv_volume *vol, const char *what, hv_frf **out);

/* Geometric mean voxel size of a lattice. */
double hv_voxel_scale(const hv_transform *xf);

/* ---- grading sources (ags.c) --------------------------------------------------------------- */

#define HV_AGS_TABLE 4096 /* intervals: 4097 samples of f over [0, dg] */

struct hv_ags {
    int refs;
    hv_frf *frf;
    double d_neg, d_grad, d_pos;
    int m;
    double ms[HV_MAX_MATERIALS], me[HV_MAX_MATERIALS];
    float table[HV_AGS_TABLE + 1]; /* f at dg * i / HV_AGS_TABLE */
    char fdesc[256];
    char name[64];
    hv_calibration *calib; /* may be NULL */
    int has_target;        /* property targets (the table above is then t(d), composed) */
    double ps, pe;
    int log;
};

/* f at distance d (world units) through the table: 0 .. 1 weight of Me. For dg == 0: the
 * step (0 below d-, 1 at and above). */
static inline float hv_ags_weight(const hv_ags *a, float d)
{
    float u = (float)(d - (float)a->d_neg);
    if (a->d_grad <= 0) return u >= 0 ? 1.0f : 0.0f;
    float s = u * (float)(HV_AGS_TABLE / a->d_grad);
    if (s <= 0) return a->table[0];
    if (s >= (float)HV_AGS_TABLE) return a->table[HV_AGS_TABLE];
    int i = (int)s;
    float t = s - (float)i;
    return a->table[i] + t * (a->table[i + 1] - a->table[i]);
}

/* A source of the object document: ranges, f's text and table (floats, hv_json_float), Ms, Me,
 * and the index of its feature in the object's feature list. NULL when out of memory. */
json_t *hv_ags_to_doc(const hv_ags *a, int feature);
/* The source back, its feature taken from feats[0..nf-1], m materials. Errors:
 * HV_ERR_BAD_INPUT naming `what` and the member (also an f table entry outside [0, 1]). */
hv_status hv_ags_from_doc(const json_t *j, hv_frf *const *feats, size_t nf, int m, const char *what,
                          hv_ags **out);
/* The calibration table of source document j (*calib = NULL when it has none; release it) and the
 * source's Ms and Me (m fractions each, filled when it has one). Errors: HV_ERR_BAD_INPUT naming
 * `what` and the member. */
hv_status hv_ags_doc_calibration(const json_t *j, int m, const char *what, hv_calibration **calib, double *ms,
                                 double *me);
/* Where composition p lies on the segment ms -> me (m fractions each): hv_ags_segment_t's rule. */
int hv_segment_t(const double *ms, const double *me, int m, const double *p, double *t);
/* A source from stored parts: the f table (HV_AGS_TABLE + 1 values in [0,1]) when dg > 0. */
hv_status hv_ags_from_parts(hv_frf *frf, double d_neg, double d_grad, double d_pos, const float *table,
                            const char *fdesc, const double *ms, const double *me, int m,
                            const char *name, hv_ags **out);

/* The documents grading writes (volumes/schema.h). to_doc: a new object without "schema" (NULL
 * when out of memory); from_doc: `what` names the document in messages, errors HV_ERR_BAD_INPUT
 * naming the member, HV_ERR_NOMEM. */
/* hovox.materials.json (table.c) */
json_t *hv_material_table_to_doc(const hv_material_table *t);
hv_status hv_material_table_from_doc(const json_t *doc, const char *what, hv_material_table **out);

/* hovox.object.json (object.c; features in frf.c, sources in ags.c): from_doc rebuilds the object
 * on vol's lattice, taking stored fields and region masks from vol. */
hv_status hv_object_to_doc(const hv_object *o, json_t **out);
hv_status hv_object_from_doc(const json_t *doc, const hv_volume *vol, hv_object **out);

#endif
