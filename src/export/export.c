/* src/export/export.c - graded models to VTK: which arrays (occupancy, fractions, derived
 * properties), the exported box, the dense .vti arrays, the VTK plugin (loaded only here) and
 * the atomic write. The .vtu mesh is built in hexmesh.c. */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "export_internal.h"
#include "io/vtk/vtk_bridge.h"

#define FRACTION_TOL 1e-4

const char *hv_export_format_list(void) { return ".vti, .vtu, .3mf, .stl or .obj"; }

hv_export_format hv_export_format_from_path(const char *path)
{
    if (hv_has_extension(path, ".vti")) return HV_EXPORT_VTI;
    if (hv_has_extension(path, ".vtu")) return HV_EXPORT_VTU;
    if (hv_has_extension(path, ".3mf")) return HV_EXPORT_3MF_SHAPE;
    if (hv_has_extension(path, ".stl")) return HV_EXPORT_STL;
    if (hv_has_extension(path, ".obj")) return HV_EXPORT_OBJ;
    return HV_EXPORT_AUTO;
}

/* ---- properties ------------------------------------------------------------------------- */

hv_status ex_check_fractions(const ex_model *md, const double *p, int32_t i, int32_t j, int32_t k)
{
    double sum = 0;
    for (int q = 0; q < md->m; ++q) {
        if (!isfinite(p[q]) || p[q] < -FRACTION_TOL || p[q] > 1 + FRACTION_TOL)
            return hv_error_set(HV_ERR_BAD_INPUT, "voxel (%d, %d, %d): fraction of '%s' is %.9g, "
                                "outside [0, 1] (Wu eq. 12)", i, j, k,
                                hv_material_name(md->table, q), p[q]);
        sum += p[q];
    }
    if (fabs(sum - 1.0) > FRACTION_TOL)
        return hv_error_set(HV_ERR_BAD_INPUT, "voxel (%d, %d, %d): material fractions sum to "
                            "%.9g, not 1 (Wu eq. 12)", i, j, k, sum);
    return HV_OK;
}

void ex_eval_props(const ex_model *md, const double *p, float *const *out, size_t idx)
{
    for (int q = 0; q < md->nprops; ++q) {
        const ex_prop *e = &md->props[q];
        double v = 0;
        switch (e->kind) {
        case EX_VOIGT: v = hv_property_voigt(p, e->x, md->m); break;
        case EX_REUSS: v = hv_property_reuss(p, e->x, md->m); break;
        case EX_TABLE: v = e->scale * hv_linearization_eval(e->lin, p[e->mat]); break;
        case EX_GRID: continue;
        }
        out[q][idx] = (float)v;
    }
}

void ex_grid_values(const ex_model *md, const double *g, float *const *out, size_t idx)
{
    for (int q = 0; q < md->nprops; ++q)
        if (md->props[q].kind == EX_GRID) out[q][idx] = (float)g[q];
}

void ex_grid_add(const ex_model *md, size_t l, unsigned off, double *g)
{
    for (int q = 0; q < md->nprops; ++q)
        if (md->props[q].kind == EX_GRID) g[q] += hv_volume_leaf_float_c(md->vol, md->props[q].grid, l)[off];
}

/* SI units for the arrays: a unit hovox knows is converted ("g/cm^3" -> "kg/m^3" times 1000,
 * "GPa" -> "Pa" times 1e9); a property given without a unit takes the SI unit of its name
 * when hovox knows the name (density kg/m^3; moduli Pa; poisson_ratio 1); any other unit is
 * kept as given. Returns the unit to name the array with; *factor converts the values. */
static const char *si_unit(const char *key, const char *unit, double *factor)
{
    *factor = 1;
    if (unit && *unit) {
        const char *si;
        hv_unit_si(unit, &si, factor); /* the unit table lives with the material table */
        return si;
    }
    return hv_property_si_unit(key);
}

static void array_name(char *dst, size_t size, const char *key, const char *model,
                       const char *unit)
{
    if (unit && *unit) snprintf(dst, size, "%s.%s[%s]", key, model, unit);
    else snprintf(dst, size, "%s.%s", key, model);
}

static hv_status add_prop(ex_model *md, size_t *cap, const ex_prop *p)
{
    for (int q = 0; q < md->nprops; ++q)
        if (strcmp(md->props[q].name, p->name) == 0)
            return hv_error_set(HV_ERR_INVALID, "export: two arrays would be named '%s' (one "
                                "linearization table per property)", p->name);
    hv_status s = hv_grow((void **)&md->props, cap, (size_t)md->nprops + 1, sizeof *md->props);
    if (s != HV_OK) return s;
    md->props[md->nprops++] = *p;
    return HV_OK;
}

/* The mixing-rule properties: every key that all materials define with one unit, in order of
 * first appearance; the others are left out with a note. */
static hv_status build_mix_props(ex_model *md, unsigned mix, size_t *cap)
{
    const hv_material_table *t = md->table;
    for (int a = 0; a < md->m; ++a) {
        for (int i = 0; i < hv_material_property_count(t, a); ++i) {
            const char *key = hv_material_property_key(t, a, i);
            int seen = 0;
            for (int b = 0; b < a && !seen; ++b) seen = hv_material_property(t, b, key, NULL, NULL);
            if (seen) continue;
            if (a > 0) {
                hv_buf_printf(&md->notes, "property '%s' left out: material '%s' has no value\n",
                              key, hv_material_name(t, 0));
                continue;
            }
            ex_prop p;
            memset(&p, 0, sizeof p);
            const char *unit0 = NULL;
            int ok = 1;
            for (int b = 0; b < md->m && ok; ++b) {
                const char *unit = NULL;
                double f = 1;
                if (!hv_material_property(t, b, key, &p.x[b], &unit)) {
                    hv_buf_printf(&md->notes, "property '%s' left out: material '%s' has no "
                                  "value\n", key, hv_material_name(t, b));
                    ok = 0;
                    continue;
                }
                const char *si = si_unit(key, unit, &f);
                p.x[b] *= f;
                if (b == 0) {
                    unit0 = si;
                } else if (strcmp(unit0, si) != 0) {
                    hv_buf_printf(&md->notes, "property '%s' left out: units differ ('%s' for "
                                  "'%s', '%s' for '%s')\n", key, unit0, hv_material_name(t, 0),
                                  si, hv_material_name(t, b));
                    ok = 0;
                }
            }
            if (!ok) continue;
            if (mix & HV_MIX_VOIGT) {
                p.kind = EX_VOIGT;
                array_name(p.name, sizeof p.name, key, "voigt", unit0);
                hv_status s = add_prop(md, cap, &p);
                if (s != HV_OK) return s;
            }
            if (mix & HV_MIX_REUSS) {
                int bad = -1;
                for (int b = 0; b < md->m && bad < 0; ++b)
                    if (!(p.x[b] > 0)) bad = b;
                if (bad >= 0) {
                    hv_buf_printf(&md->notes, "'%s.reuss' left out: the inverse rule needs "
                                  "positive values ('%s' has %g)\n", key,
                                  hv_material_name(t, bad), p.x[bad]);
                    continue;
                }
                p.kind = EX_REUSS;
                array_name(p.name, sizeof p.name, key, "reuss", unit0);
                hv_status s = add_prop(md, cap, &p);
                if (s != HV_OK) return s;
            }
        }
    }
    return HV_OK;
}

static hv_status build_table_props(ex_model *md, const hv_export_options *opt, size_t *cap)
{
    for (int i = 0; i < opt->ntables; ++i) {
        const hv_linearization *lin = opt->tables[i];
        const char *prop = hv_linearization_property(lin), *mat = hv_linearization_material(lin);
        if (!md->table)
            return hv_error_set(HV_ERR_NOT_FOUND, "linearization of %s: the model has no "
                                "materials (no material '%s')", prop, mat);
        int j = hv_material_find(md->table, mat);
        if (j < 0) {
            hv_buf names;
            hv_buf_init(&names);
            for (int q = 0; q < md->m; ++q)
                hv_buf_printf(&names, "%s%s", q ? ", " : "", hv_material_name(md->table, q));
            hv_status s = hv_error_set(HV_ERR_NOT_FOUND, "linearization of %s: material '%s' "
                                       "is not in the model (materials: %s)", prop, mat,
                                       names.data ? names.data : "");
            hv_buf_free(&names);
            return s;
        }
        ex_prop p;
        memset(&p, 0, sizeof p);
        /* the table's own unit, converted to SI as the material properties are */
        const char *unit = si_unit(prop, hv_linearization_unit(lin), &p.scale);
        p.kind = EX_TABLE;
        p.lin = lin;
        p.mat = j;
        array_name(p.name, sizeof p.name, prop, "table", unit);
        hv_status s = add_prop(md, cap, &p);
        if (s != HV_OK) return s;
    }
    return HV_OK;
}

/* Float grids exported as arrays of their names: "NAME[,NAME...]". */
static hv_status build_grid_props(ex_model *md, const char *grids, size_t *cap)
{
    for (const char *s = grids; s && *s;) {
        const char *e = strchr(s, ',');
        size_t n = e ? (size_t)(e - s) : strlen(s);
        ex_prop p;
        memset(&p, 0, sizeof p);
        if (n == 0 || n >= sizeof p.name)
            return hv_error_option(HV_ERR_INVALID, "{grids} '%s': a name is empty or too long", grids);
        memcpy(p.name, s, n);
        p.name[n] = '\0';
        p.kind = EX_GRID;
        p.grid = hv_volume_grid_need(md->vol, p.name, HV_GRID_FLOAT);
        if (p.grid < 0) return hv_error_prefix(HV_ERR_NOT_FOUND, "export: the model has ");
        int clash = strcmp(p.name, "occupancy") == 0 || strncmp(p.name, "fraction.", 9) == 0;
        for (int q = 0; q < md->nprops && !clash; ++q) clash = strcmp(md->props[q].name, p.name) == 0;
        if (clash) return hv_error_option(HV_ERR_INVALID, "{grids}: array '%s' is named twice", p.name);
        hv_status st = add_prop(md, cap, &p);
        if (st != HV_OK) return st;
        md->ngrids++;
        s = e ? e + 1 : s + n;
    }
    return HV_OK;
}

/* A model painted in colour (hovox/colour.h) carries the colours asked for: its grids colour.r,
 * colour.g, colour.b (sRGB in [0, 1]; 0 under a resin core, where colour.mask is 0) become arrays
 * of those names unless --grids named them already (VTK), and md->painted with md->colour the
 * four grids (a 3MF Volumetric package's <v:color>, which writes them in place of the arrays). */
static hv_status build_colour_props(ex_model *md, size_t *cap)
{
    static const char *const k_rgb[3] = {"colour.r", "colour.g", "colour.b"};
    int g[3], mask = hv_volume_grid_find(md->vol, "colour.mask");
    for (int c = 0; c < 3; ++c) {
        g[c] = hv_volume_grid_find(md->vol, k_rgb[c]);
        if (g[c] < 0 || hv_volume_grid_type(md->vol, g[c]) != HV_GRID_FLOAT) return HV_OK;
    }
    if (mask < 0) return HV_OK;
    md->painted = hv_volume_grid_type(md->vol, mask) == HV_GRID_FLOAT;
    memcpy(md->colour, g, sizeof g);
    md->colour[3] = mask;
    for (int c = 0; c < 3; ++c) {
        int named = 0;
        for (int q = 0; q < md->nprops && !named; ++q) named = strcmp(md->props[q].name, k_rgb[c]) == 0;
        if (named) continue;
        ex_prop p;
        memset(&p, 0, sizeof p);
        p.kind = EX_GRID;
        p.grid = g[c];
        p.colour = 1;
        snprintf(p.name, sizeof p.name, "%s", k_rgb[c]);
        hv_status st = add_prop(md, cap, &p);
        if (st != HV_OK) return st;
        md->ngrids++;
    }
    return HV_OK;
}

/* ---- the model: materials, occupancy, box ----------------------------------------------- */

void ex_model_free(ex_model *md)
{
    hv_material_table_destroy(md->table);
    free(md->props);
    free(md->occ);
    hv_buf_free(&md->notes);
    memset(md, 0, sizeof *md);
}

static int world_to_range(double o, double v, double a, double b, int64_t *lo, int64_t *hi)
{
    double l = ceil((a - o) / v - 1e-9), h = floor((b - o) / v + 1e-9);
    if (l < -2147483648.0) l = -2147483648.0;
    if (h > 2147483647.0) h = 2147483647.0;
    *lo = (int64_t)l;
    *hi = (int64_t)h;
    return l <= h;
}

hv_status ex_model_init(ex_model *md, const hv_volume *vol, const hv_export_options *opt)
{
    memset(md, 0, sizeof *md);
    hv_buf_init(&md->notes);
    md->vol = vol;
    hv_status s = hv_material_table_load(vol, &md->table);
    if (s == HV_ERR_NOT_FOUND) {
        hv_error_clear();
        s = HV_OK;
        md->table = NULL;
        hv_buf_puts(&md->notes, "the model has no material table: occupancy only\n");
    } else if (s != HV_OK) {
        return s;
    }
    if (md->table) {
        md->m = hv_material_count(md->table);
        for (int j = 0; j < md->m; ++j) md->grids[j] = hv_material_grid(vol, md->table, j);
    }
    size_t cap = 0;
    if (md->table && opt->mix) s = build_mix_props(md, opt->mix, &cap);
    if (s == HV_OK) s = build_table_props(md, opt, &cap);
    if (s == HV_OK) s = build_grid_props(md, opt->grids, &cap);
    if (s == HV_OK) s = build_colour_props(md, &cap);
    if (s != HV_OK) return s;

    /* occupied voxels per leaf */
    md->nleaves = hv_volume_leaf_count(vol);
    md->occ = hv_calloc(md->nleaves ? md->nleaves * 8 : 1, sizeof(uint64_t));
    if (!md->occ) return HV_ERR_NOMEM;
    int og = hv_volume_grid_find(vol, "occupancy");
    if (og >= 0 && hv_volume_grid_type(vol, og) != HV_GRID_BOOL) og = -1;
    const int32_t *orig = hv_volume_leaf_origins(vol);
    hv_transform xf = hv_volume_get_transform(vol);
    int64_t blo[3] = {0, 0, 0}, bhi[3] = {0, 0, 0};
    if (opt->use_box) {
        for (int a = 0; a < 3; ++a)
            if (!world_to_range(xf.origin[a], xf.voxel[a], opt->box_lo[a], opt->box_hi[a],
                                &blo[a], &bhi[a]))
                return hv_error_set(HV_ERR_INVALID, "export: the box [%g, %g] on %c holds no "
                                    "voxel centre (voxels at %g + i * %g)", opt->box_lo[a],
                                    opt->box_hi[a], "xyz"[a], xf.origin[a], xf.voxel[a]);
    }
    int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    for (size_t l = 0; l < md->nleaves; ++l) {
        uint64_t *w = md->occ + 8 * l;
        const uint64_t *act = hv_volume_leaf_mask(vol, l);
        const uint64_t *ob = og >= 0 ? hv_volume_leaf_bool_c(vol, og, l) : NULL;
        const int32_t *o = orig + 3 * l;
        int inside = 1, outside = 0;
        if (opt->use_box)
            for (int a = 0; a < 3; ++a) {
                if (o[a] < blo[a] || o[a] + 7 > bhi[a]) inside = 0;
                if (o[a] + 7 < blo[a] || o[a] > bhi[a]) outside = 1;
            }
        if (outside) continue;
        uint64_t any = 0;
        for (int q = 0; q < 8; ++q) {
            w[q] = act[q] & (ob ? ob[q] : ~0ull);
            any |= w[q];
        }
        if (!any) continue;
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            if (!HV_BIT_GET(w, n)) continue;
            int64_t v[3] = {o[0] + (int)(n >> 6), o[1] + (int)((n >> 3) & 7), o[2] + (int)(n & 7)};
            if (!inside && (v[0] < blo[0] || v[0] > bhi[0] || v[1] < blo[1] || v[1] > bhi[1] ||
                            v[2] < blo[2] || v[2] > bhi[2])) {
                w[n >> 6] &= ~(1ull << (n & 63));
                continue;
            }
            md->occupied++;
            for (int a = 0; a < 3; ++a) {
                if (v[a] < lo[a]) lo[a] = v[a];
                if (v[a] > hi[a]) hi[a] = v[a];
            }
        }
    }
    for (int a = 0; a < 3; ++a) {
        md->olo[a] = md->occupied ? lo[a] : 0;
        md->ohi[a] = md->occupied ? hi[a] : -1;
        md->lo[a] = opt->use_box ? blo[a] : md->olo[a];
        md->hi[a] = opt->use_box ? bhi[a] : md->ohi[a];
    }
    return HV_OK;
}

/* ---- the VTK plugin ---------------------------------------------------------------------- */


static int vtk_progress(void *user, double fraction)
{
    const hv_progress *p = user;
    return p && p->fn ? p->fn(p->user, "export write", fraction) : 0;
}

/* ---- arrays --------------------------------------------------------------------------- */

typedef struct ex_out {
    int narrays;
    hv_vtk_array arrays[EX_MAX_ARRAYS];
    char names[1 + HV_MAX_MATERIALS][80];
    void *buffers[EX_MAX_ARRAYS];
    float *frac[HV_MAX_MATERIALS];
    float **props;
} ex_out;

static void out_free(ex_out *o)
{
    for (int i = 0; i < o->narrays; ++i) free(o->buffers[i]);
    free(o->props);
}

/* Names of the arrays, in file order, into the report. */
static void report_names(const ex_model *md, hv_export_report *r)
{
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_puts(&b, "occupancy");
    for (int j = 0; j < md->m; ++j) hv_buf_printf(&b, ",fraction.%s", hv_material_name(md->table, j));
    for (int q = 0; q < md->nprops; ++q) hv_buf_printf(&b, ",%s", md->props[q].name);
    snprintf(r->names, sizeof r->names, "%s", b.data ? b.data : "");
    hv_buf_free(&b);
    snprintf(r->notes, sizeof r->notes, "%s", md->notes.data ? md->notes.data : "");
    r->arrays = 1 + md->m + md->nprops;
    r->materials = md->m;
    r->occupied = md->occupied;
    for (int a = 0; a < 3; ++a) {
        r->lo[a] = md->lo[a];
        r->hi[a] = md->hi[a];
    }
}

/* Allocate the arrays (n tuples each): occupancy (uint8 for .vti, float for .vtu), fractions,
 * properties. */
static hv_status out_alloc(ex_out *o, const ex_model *md, size_t n, int occ_float)
{
    memset(o, 0, sizeof *o);
    if (md->m + md->nprops + 1 > (int)HV_COUNT(o->arrays))
        return hv_error_set(HV_ERR_LIMIT, "export: too many arrays (%d)", md->m + md->nprops + 1);
    o->props = hv_calloc((size_t)md->nprops + 1, sizeof *o->props);
    if (!o->props) return HV_ERR_NOMEM;
    size_t nn = n ? n : 1;
    hv_vtk_array *a = &o->arrays[o->narrays];
    void *buf = hv_calloc(nn, occ_float ? sizeof(float) : 1);
    if (!buf) return HV_ERR_NOMEM;
    o->buffers[o->narrays++] = buf;
    *a = (hv_vtk_array){"occupancy", occ_float ? HV_VTK_FLOAT32 : HV_VTK_UINT8, 1, (int64_t)n, buf};
    for (int j = 0; j < md->m; ++j) {
        snprintf(o->names[j], sizeof o->names[j], "fraction.%s", hv_material_name(md->table, j));
        float *f = hv_calloc(nn, sizeof(float));
        if (!f) return HV_ERR_NOMEM;
        o->frac[j] = f;
        o->buffers[o->narrays] = f;
        o->arrays[o->narrays++] = (hv_vtk_array){o->names[j], HV_VTK_FLOAT32, 1, (int64_t)n, f};
    }
    for (int q = 0; q < md->nprops; ++q) {
        float *f = hv_calloc(nn, sizeof(float));
        if (!f) return HV_ERR_NOMEM;
        o->props[q] = f;
        o->buffers[o->narrays] = f;
        o->arrays[o->narrays++] =
            (hv_vtk_array){md->props[q].name, HV_VTK_FLOAT32, 1, (int64_t)n, f};
    }
    return HV_OK;
}

/* ---- .vti ------------------------------------------------------------------------------- */

typedef struct vti_ctx {
    const ex_model *md;
    int64_t nx, ny;
    uint8_t *occ;
    float *const *frac;
    float *const *props;
} vti_ctx;

static hv_status vti_range(void *ctx, size_t b, size_t e, int thread)
{
    (void)thread;
    const vti_ctx *c = ctx;
    const ex_model *md = c->md;
    const int32_t *orig = hv_volume_leaf_origins(md->vol);
    double p[HV_MAX_MATERIALS];
    const float *fr[HV_MAX_MATERIALS];
    for (size_t l = b; l < e; ++l) {
        const uint64_t *w = md->occ + 8 * l;
        if (!(w[0] | w[1] | w[2] | w[3] | w[4] | w[5] | w[6] | w[7])) continue;
        for (int j = 0; j < md->m; ++j) fr[j] = hv_volume_leaf_float_c(md->vol, md->grids[j], l);
        const int32_t *o = orig + 3 * l;
        for (unsigned q = 0; q < 8; ++q) {
            for (uint64_t bits = w[q]; bits; bits &= bits - 1) {
                unsigned n = q * 64 + (unsigned)__builtin_ctzll(bits);
                int32_t i = o[0] + (int32_t)(n >> 6), j = o[1] + (int32_t)((n >> 3) & 7),
                        k = o[2] + (int32_t)(n & 7);
                size_t idx = (size_t)((i - md->lo[0]) +
                                      c->nx * ((j - md->lo[1]) + c->ny * (k - md->lo[2])));
                c->occ[idx] = 1;
                if (md->ngrids) {
                    double g[EX_MAX_ARRAYS] = {0};
                    ex_grid_add(md, l, n, g);
                    ex_grid_values(md, g, c->props, idx);
                }
                if (!md->m) continue;
                for (int m = 0; m < md->m; ++m) p[m] = fr[m][n];
                hv_status s = ex_check_fractions(md, p, i, j, k);
                if (s != HV_OK) return s;
                for (int m = 0; m < md->m; ++m) c->frac[m][idx] = fr[m][n];
                ex_eval_props(md, p, c->props, idx);
            }
        }
    }
    return HV_OK;
}

static hv_status vti_plan(const ex_model *md, hv_export_report *r)
{
    double pts = 1;
    for (int a = 0; a < 3; ++a) {
        r->dims[a] = md->hi[a] - md->lo[a] + 1;
        pts *= (double)r->dims[a];
    }
    if (md->occupied == 0 && md->hi[0] < md->lo[0])
        return hv_error_set(HV_ERR_INVALID, "export: the model has no occupied voxel (give a box "
                            "to export an empty image)");
    double bytes = pts * (1.0 + 4.0 * (md->m + md->nprops));
    if (pts > 9.0e18 || bytes > 1.8e19)
        return hv_error_set(HV_ERR_LIMIT, "export: the image would have %.3g points", pts);
    r->points = (uint64_t)pts;
    r->cells = 0;
    r->memory_bytes = (uint64_t)bytes;
    return HV_OK;
}

/* ---- .vtu --------------------------------------------------------------------------- */

static hv_status vtu_plan(const ex_model *md, const hv_export_options *opt, ex_hexmesh *h,
                          hv_export_report *r)
{
    hv_status s = ex_hexmesh_plan(h, md, opt->coarsen, opt->coarsen_rule, opt->progress);
    if (s != HV_OK) return s;
    if (h->ncells == 0)
        return hv_error_set(HV_ERR_INVALID, "export: nothing to export: no %s inside the box",
                            opt->coarsen > 1 ? "coarse cell is occupied enough" : "occupied voxel");
    r->cells = h->ncells;
    r->points = h->npoints;
    for (int a = 0; a < 3; ++a) {
        r->lo[a] = md->olo[a];
        r->hi[a] = md->ohi[a];
    }
    r->dims[0] = r->dims[1] = r->dims[2] = 0;
    /* connectivity (8 ids) + offsets (1 id) + cell type (1 byte) + arrays, points (3 floats) */
    double id = ex_hexmesh_ids64(h) ? 8.0 : 4.0;
    double bytes = (double)h->ncells * (9.0 * id + 1.0 + 4.0 * (1 + md->m + md->nprops)) +
                   (double)h->npoints * 12.0;
    r->memory_bytes = (uint64_t)bytes;
    return HV_OK;
}

/* ---- entry points ------------------------------------------------------------------------ */

static hv_status check_options(const char *path, const hv_export_options *opt,
                               hv_export_format *fmt)
{
    *fmt = opt->format;
    if (*fmt == HV_EXPORT_AUTO) {
        *fmt = hv_export_format_from_path(path);
        if (*fmt == HV_EXPORT_AUTO)
            return hv_error_set(HV_ERR_INVALID, "%s: unknown extension (use %s)", path, hv_export_format_list());
    }
    if (*fmt < HV_EXPORT_VTI || *fmt > HV_EXPORT_3MF_SHAPE)
        return hv_error_set(HV_ERR_INVALID, "export: unknown format %d", (int)*fmt);
    hv_status s = hv_export_options_check(opt);
    if (s != HV_OK) return s;
    if (opt->volumetric && *fmt == HV_EXPORT_3MF_SHAPE) *fmt = HV_EXPORT_3MF;
    if (opt->volumetric && *fmt != HV_EXPORT_3MF)
        return hv_error_option(HV_ERR_INVALID, "{volumetric} applies to .3mf output only");
    if (opt->coarsen > 1 && *fmt != HV_EXPORT_VTU)
        return hv_error_option(HV_ERR_INVALID, "{coarsen} applies to .vtu output only");
    if (opt->bits && *fmt == HV_EXPORT_3MF_SHAPE)
        return hv_error_option(HV_ERR_INVALID, "{bits} applies to the Volumetric package only (.3mf with {volumetric})");
    if (opt->bits && *fmt != HV_EXPORT_3MF)
        return hv_error_option(HV_ERR_INVALID, "{bits} applies to .3mf output only");
    if (opt->use_box && ex_format_is_shape(*fmt))
        return hv_error_option(HV_ERR_INVALID, "{box} cuts voxel exports (.vti, .vtu, .3mf with {volumetric}); .stl, "
                               ".obj and .3mf write the whole shape");
    return HV_OK;
}

static hv_status plan_all(const hv_volume *vol, const char *path, const hv_export_options *opt,
                          ex_model *md, ex_hexmesh *h, hv_export_report *r)
{
    memset(r, 0, sizeof *r);
    hv_export_format fmt;
    hv_status s = check_options(path, opt, &fmt);
    if (s != HV_OK) return s;
    r->format = fmt;
    if (ex_format_is_shape(fmt)) return ex_shape_plan(vol, opt, r);
    s = ex_model_init(md, vol, opt);
    if (s != HV_OK) return s;
    report_names(md, r);
    if (fmt == HV_EXPORT_3MF) return ex_3mf_plan(md, opt, r);
    return fmt == HV_EXPORT_VTI ? vti_plan(md, r) : vtu_plan(md, opt, h, r);
}

static hv_status plan_impl(const hv_volume *vol, const char *path, const hv_export_options *opt,
                           hv_export_report *report)
{
    hv_export_options defaults;
    if (!opt) {
        hv_export_options_init(&defaults);
        opt = &defaults;
    }
    ex_model md;
    ex_hexmesh h;
    memset(&md, 0, sizeof md);
    memset(&h, 0, sizeof h);
    hv_export_report tmp;
    hv_status s = plan_all(vol, path, opt, &md, &h, report ? report : &tmp);
    ex_hexmesh_free(&h);
    ex_model_free(&md);
    return s;
}

static hv_status check_budget(const hv_export_options *opt, const hv_export_report *r)
{
    uint64_t budget = hv_memory_budget(opt->max_memory);
    if (!budget || r->memory_bytes <= budget) return HV_OK;
    char need[32], have[32];
    hv_size_text(need, sizeof need, (double)r->memory_bytes);
    hv_size_text(have, sizeof have, (double)budget);
    if (r->format == HV_EXPORT_3MF)
        return hv_error_option(HV_ERR_LIMIT, "export: the 3MF package (a mesh of %llu triangles, %d image stacks of "
                               "%lld x %lld pixels per sheet) needs %s, more than the limit of %s ({max_memory})",
                               (unsigned long long)r->cells, r->arrays, (long long)r->dims[0], (long long)r->dims[1],
                               need, have);
    if (r->format == HV_EXPORT_VTI)
        return hv_error_option(HV_ERR_LIMIT, "export: the image of %lld x %lld x %lld points x %d "
                            "arrays needs %s, more than the limit of %s ({max_memory}); export "
                            "a smaller box or a .vtu", (long long)r->dims[0],
                            (long long)r->dims[1], (long long)r->dims[2], r->arrays, need, have);
    return hv_error_option(HV_ERR_LIMIT, "export: the mesh of %llu hexahedra and %llu points needs "
                        "%s, more than the limit of %s ({max_memory}); coarsen it or export a "
                        "smaller box", (unsigned long long)r->cells,
                        (unsigned long long)r->points, need, have);
}

static hv_status write_impl(const hv_volume *vol, const char *path, const hv_export_options *opt,
                            hv_export_report *report)
{
    hv_export_options defaults;
    if (!opt) {
        hv_export_options_init(&defaults);
        opt = &defaults;
    }
    hv_export_report tmp_report;
    hv_export_report *r = report ? report : &tmp_report;
    ex_model md;
    ex_hexmesh h;
    ex_out out;
    memset(&md, 0, sizeof md);
    memset(&h, 0, sizeof h);
    memset(&out, 0, sizeof out);
    char *tmp = NULL;
    float *points = NULL;
    void *conn = NULL;
    int created = 0;

    hv_export_format fmt;
    hv_status s = check_options(path, opt, &fmt);
    if (s == HV_OK && ex_format_is_shape(fmt)) {
        memset(r, 0, sizeof *r); /* the shape, not the voxels: nothing of md is needed */
        r->format = fmt;
        return ex_shape_write(vol, path, opt, r);
    }
    if (s == HV_OK) s = plan_all(vol, path, opt, &md, &h, r);
    if (s == HV_OK) s = check_budget(opt, r);
    if (s == HV_OK && r->format == HV_EXPORT_3MF) {
        s = ex_3mf_write(&md, path, opt, r);
        ex_hexmesh_free(&h);
        ex_model_free(&md);
        return s;
    }
    const hv_vtk_api *g_vtk = NULL;
    if (s == HV_OK) s = hv_vtk_bridge(&g_vtk);
    /* claim the temporary name now, so an unwritable place fails before the work */
    if (s == HV_OK) {
        tmp = hv_temp_path(path);
        if (!tmp) s = HV_ERR_NOMEM;
    }
    if (s == HV_OK) {
        int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0) {
            int e = errno;
            s = hv_error_set(HV_ERR_IO, "%s: cannot write: %s", path, strerror(e));
        } else {
            close(fd);
            created = 1;
        }
    }

    hv_vtk_array field[2];
    int nfield = 0;
    int32_t index_lo[3] = {(int32_t)md.lo[0], (int32_t)md.lo[1], (int32_t)md.lo[2]};
    char *table_json = NULL;
    if (s == HV_OK && md.table) {
        s = hv_material_table_to_json(md.table, &table_json);
        if (s == HV_OK) field[nfield++] = (hv_vtk_array){"hovox.materials.json", HV_VTK_STRING, 1, 1, table_json};
    }
    hv_vtk_write_opts wo = {opt->zlib_level ? opt->zlib_level : 1, vtk_progress,
                            (void *)opt->progress, 0, field};
    int rc = 0;
    if (s == HV_OK && r->format == HV_EXPORT_VTI) {
        field[nfield++] = (hv_vtk_array){"hovox.index_lo", HV_VTK_INT32, 3, 1, index_lo};
        wo.nfield = nfield;
        s = out_alloc(&out, &md, (size_t)r->points, 0);
        if (s == HV_OK) {
            vti_ctx c = {&md, r->dims[0], r->dims[1], out.buffers[0], out.frac, out.props};
            s = hv_parallel_for(md.nleaves, 16, vti_range, &c, opt->progress, "export fill");
        }
        if (s == HV_OK) {
            hv_transform xf = hv_volume_get_transform(vol);
            double origin[3];
            for (int a = 0; a < 3; ++a) origin[a] = xf.origin[a] + (double)md.lo[a] * xf.voxel[a];
            rc = g_vtk->write_image(tmp, r->dims, origin, xf.voxel, out.narrays, out.arrays, &wo);
        }
    } else if (s == HV_OK) {
        wo.nfield = nfield;
        s = out_alloc(&out, &md, (size_t)r->cells, 1);
        if (s == HV_OK) {
            points = hv_malloc_array((size_t)r->points, 3 * sizeof(float));
            conn = hv_malloc_array((size_t)r->cells, 8 * (ex_hexmesh_ids64(&h) ? 8u : 4u));
            if (!points || !conn) s = HV_ERR_NOMEM;
        }
        if (s == HV_OK)
            s = ex_hexmesh_fill(&h, &md, points, conn, ex_hexmesh_ids64(&h), out.buffers[0],
                                out.frac, out.props, opt->progress);
        if (s == HV_OK)
            rc = g_vtk->write_hexes(tmp, (int64_t)r->points, points, (int64_t)r->cells, conn,
                                    ex_hexmesh_ids64(&h), out.narrays, out.arrays, &wo);
    }
    if (s == HV_OK && rc != 0) {
        if (rc == HV_ERR_CANCELLED) s = hv_error_set(HV_ERR_CANCELLED, "export write: cancelled");
        else s = hv_error_set((hv_status)rc, "%s: %s", path, g_vtk->last_error());
    }
    if (s == HV_OK) {
        struct stat st;
        r->file_bytes = stat(tmp, &st) == 0 ? (uint64_t)st.st_size : 0;
        if ((s = hv_temp_commit(tmp, path)) == HV_OK) created = 0;
    }
    if (created) unlink(tmp);
    if (s != HV_OK) r->file_bytes = 0;
    free(tmp);
    free(table_json);
    free(points);
    free(conn);
    out_free(&out);
    ex_hexmesh_free(&h);
    ex_model_free(&md);
    return s;
}

/* ---- linearization files named in the options ------------------------------------------- */

/* The options with the tables of opt->linearize[] loaded and appended to opt->tables. */
typedef struct resolved {
    hv_export_options o;
    const hv_linearization *all[2 * HV_EXPORT_MAX_TABLES];
    hv_linearization *own[HV_EXPORT_MAX_TABLES];
    int nown;
} resolved;

static void resolved_free(resolved *r)
{
    for (int i = 0; i < r->nown; ++i) hv_linearization_destroy(r->own[i]);
    r->nown = 0;
}

static hv_status resolve(const hv_export_options *opt, resolved *r)
{
    r->nown = 0;
    if (!opt) hv_export_options_init(&r->o);
    else r->o = *opt;
    if (r->o.nlinearize <= 0) return HV_OK;
    if (r->o.ntables < 0 || r->o.ntables > HV_EXPORT_MAX_TABLES || r->o.nlinearize > HV_EXPORT_MAX_TABLES)
        return hv_export_options_check(&r->o);
    for (int i = 0; i < r->o.ntables; ++i) r->all[i] = r->o.tables[i];
    for (int i = 0; i < r->o.nlinearize; ++i) {
        hv_status s = hv_linearization_load(r->o.linearize[i].path, r->o.linearize[i].property, &r->own[r->nown]);
        if (s != HV_OK) {
            resolved_free(r);
            return s;
        }
        r->all[r->o.ntables + r->nown] = r->own[r->nown];
        r->nown++;
    }
    r->o.tables = r->all;
    r->o.ntables += r->nown;
    r->o.nlinearize = 0;
    return HV_OK;
}

/* Failures about the model's content name its file. */
static hv_status name_model(const hv_volume *vol, hv_status s)
{
    if (s == HV_OK || s == HV_ERR_IO || s == HV_ERR_CANCELLED || s == HV_ERR_UNSUPPORTED || s == HV_ERR_NOMEM ||
        (s == HV_ERR_INVALID && hv_last_error_names_option()) || !*hv_volume_name(vol))
        return s;
    return hv_error_prefix(s, "%s: ", hv_volume_name(vol));
}

hv_status hv_export_plan(const hv_volume *vol, const char *path, const hv_export_options *opt,
                         hv_export_report *report)
{
    resolved *r = hv_malloc(sizeof *r);
    if (!r) return HV_ERR_NOMEM;
    hv_status s = resolve(opt, r);
    if (s == HV_OK) s = name_model(vol, plan_impl(vol, path, &r->o, report));
    resolved_free(r);
    free(r);
    return s;
}

hv_status hv_export_write(const hv_volume *vol, const char *path, const hv_export_options *opt,
                          hv_export_report *report)
{
    resolved *r = hv_malloc(sizeof *r);
    if (!r) return HV_ERR_NOMEM;
    hv_status s = resolve(opt, r);
    if (s == HV_OK) s = name_model(vol, write_impl(vol, path, &r->o, report));
    resolved_free(r);
    free(r);
    return s;
}
