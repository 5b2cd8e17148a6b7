/* src/material/source_options.c - grading sources (AGS, Wu 2.2) and reference features as option
 * sets (hovox/material.h, hovox/options.h): the CLI's --frf/--ranges/--f/--ms/--me groups and
 * Lua's hovox.ags{...}, hovox.axis{...} read the same keys, domains and defaults here. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/material.h"

/* ---- features -------------------------------------------------------------------------------- */

static const char *const k_frf_names[] = {"point", "axis", "plane", "halfspace", "segment", "contour", "mask",
                                          "facets", "harmonic", "field", NULL};
static const int k_frf_values[] = {HV_FRF_POINT, HV_FRF_LINE, HV_FRF_PLANE, HV_FRF_HALFSPACE, HV_FRF_SEGMENT,
                                   HV_FRF_CONTOUR, HV_FRF_MASK, HV_FRF_FACETS, HV_FRF_HARMONIC, HV_FRF_FIELD};
static const char *const k_frf_aliases[] = {"line", "axis", NULL};
static const hv_enum_def k_frf = {"feature", k_frf_names, k_frf_values, k_frf_aliases};

const hv_enum_def *hv_frf_kind_enum(void) { return &k_frf; }

hv_status hv_frf_kind_parse(const char *name, hv_frf_kind *out)
{
    int v;
    hv_status s = hv_enum_parse(&k_frf, name, &v);
    if (s == HV_OK) *out = (hv_frf_kind)v;
    return s;
}

const char *hv_frf_kind_name(hv_frf_kind kind)
{
    const char *n = hv_enum_name(&k_frf, (int)kind);
    return n ? n : "?";
}

#define FOFF(f) offsetof(hv_frf_options, f)
#define V3(k_, f, flags_, help_) {.key = k_, .kind = HV_OPT_NUMBER, .count = 3, .flags = flags_, .lo = -1e9, \
                                  .hi = 1e9, .offset = FOFF(f), .meta = "X,Y,Z", .help = help_}
static const hv_option k_point[] = {V3("point", point, HV_OPT_REQUIRED, "the point")};
static const hv_option k_axis[] = {V3("origin", origin, 0, "a point of the line (default 0,0,0)"),
                                   V3("direction", direction, HV_OPT_REQUIRED, "its direction (non-zero)")};
static const hv_option k_plane[] = {V3("point", point, 0, "a point of the plane (default 0,0,0)"),
                                    V3("normal", normal, HV_OPT_REQUIRED, "its normal (non-zero)")};
static const hv_option k_halfspace[] = {V3("point", point, 0, "a point of the plane bounding it (default 0,0,0)"),
                                        V3("normal", normal, HV_OPT_REQUIRED,
                                           "its normal, pointing to where d > 0 (non-zero)")};
static const hv_option k_segment[] = {V3("from", from, HV_OPT_REQUIRED, "one end"),
                                      V3("to", to, HV_OPT_REQUIRED, "the other end")};
static const hv_option k_contour[] = {{.key = "grid", .kind = HV_OPT_STRING, .offset = FOFF(grid), .meta = "GRID",
                                       .help = "the bool grid whose boundary it is (default occupancy)"}};
static const hv_option k_mask[] = {{.key = "grid", .kind = HV_OPT_STRING, .flags = HV_OPT_REQUIRED,
                                    .offset = FOFF(grid), .meta = "GRID", .help = "the bool grid of the feature voxels"}};
static const char *const k_outside_names[] = {"refuse", "nearest", NULL};
static const hv_enum_def k_outside = {"outside rule", k_outside_names, NULL, NULL};
const hv_enum_def *hv_field_outside_enum(void) { return &k_outside; }
static const hv_option k_field[] = {
    {.key = "file", .kind = HV_OPT_STRING, .flags = HV_OPT_REQUIRED | HV_OPT_IN_PATH, .offset = FOFF(file),
     .meta = "FILE", .help = "the data: .vti, .vtu (VTK XML) or .vdb"},
    {.key = "array", .kind = HV_OPT_STRING, .flags = HV_OPT_REQUIRED, .offset = FOFF(array), .meta = "ARRAY",
     .help = "the scalar array (point or cell data), or the .vdb float grid"},
    {.key = "outside", .kind = HV_OPT_ENUM, .offset = FOFF(outside), .enumdef = &k_outside, .meta = "RULE",
     .help = "model voxels the field does not cover: refuse (default, with their count) or nearest (the nearest "
             "covered voxel's value)"},
};
#undef V3

static hv_status frf_validate(const void *opts)
{
    const hv_frf_options *o = opts;
    const double *dir = o->kind == HV_FRF_LINE                                  ? o->direction
                        : o->kind == HV_FRF_PLANE || o->kind == HV_FRF_HALFSPACE ? o->normal
                                                                                 : NULL;
    if (dir && dir[0] == 0 && dir[1] == 0 && dir[2] == 0)
        return hv_error_option(HV_ERR_INVALID, "{%s} must not be zero", o->kind == HV_FRF_LINE ? "direction" : "normal");
    if (o->kind == HV_FRF_SEGMENT && o->from[0] == o->to[0] && o->from[1] == o->to[1] && o->from[2] == o->to[2])
        return hv_error_option(HV_ERR_INVALID, "{from} and {to} are the same point");
    return HV_OK;
}

static void frf_init_point(void *o) { memset(o, 0, sizeof(hv_frf_options)), ((hv_frf_options *)o)->kind = HV_FRF_POINT; }
static void frf_init_axis(void *o) { memset(o, 0, sizeof(hv_frf_options)), ((hv_frf_options *)o)->kind = HV_FRF_LINE; }
static void frf_init_plane(void *o) { memset(o, 0, sizeof(hv_frf_options)), ((hv_frf_options *)o)->kind = HV_FRF_PLANE; }
static void frf_init_halfspace(void *o)
{
    memset(o, 0, sizeof(hv_frf_options));
    ((hv_frf_options *)o)->kind = HV_FRF_HALFSPACE;
}
static void frf_init_segment(void *o) { memset(o, 0, sizeof(hv_frf_options)), ((hv_frf_options *)o)->kind = HV_FRF_SEGMENT; }
static void frf_init_contour(void *o)
{
    memset(o, 0, sizeof(hv_frf_options));
    ((hv_frf_options *)o)->kind = HV_FRF_CONTOUR;
    ((hv_frf_options *)o)->grid = "occupancy";
}
static void frf_init_mask(void *o) { memset(o, 0, sizeof(hv_frf_options)), ((hv_frf_options *)o)->kind = HV_FRF_MASK; }
static void frf_init_field(void *o) { memset(o, 0, sizeof(hv_frf_options)), ((hv_frf_options *)o)->kind = HV_FRF_FIELD; }

#define FSET(name, opts, init) {name, opts, (int)HV_COUNT(opts), sizeof(hv_frf_options), init, NULL, 0, NULL, frf_validate, NULL, 0}
static const hv_option_set k_frf_sets[] = {
    FSET("point", k_point, frf_init_point),       FSET("axis", k_axis, frf_init_axis),
    FSET("plane", k_plane, frf_init_plane),       FSET("halfspace", k_halfspace, frf_init_halfspace),
    FSET("segment", k_segment, frf_init_segment),
    FSET("contour", k_contour, frf_init_contour), FSET("mask", k_mask, frf_init_mask),
    FSET("field", k_field, frf_init_field),
};
#undef FSET

const hv_option_set *hv_frf_option_set(hv_frf_kind kind)
{
    const char *name = hv_enum_name(&k_frf, (int)kind);
    for (size_t i = 0; name && i < HV_COUNT(k_frf_sets); ++i)
        if (strcmp(k_frf_sets[i].name, name) == 0) return &k_frf_sets[i];
    return NULL;
}

hv_status hv_frf_from_options(const hv_frf_options *o, const hv_volume *vol, hv_frf **out)
{
    *out = NULL;
    const hv_option_set *set = hv_frf_option_set(o->kind);
    if (!set) return hv_error_set(HV_ERR_INVALID, "a %s feature is not made from options", hv_frf_kind_name(o->kind));
    hv_status s = hv_options_check(set, o);
    if (s != HV_OK) return s;
    switch (o->kind) {
    case HV_FRF_POINT: return hv_frf_point(o->point, out);
    case HV_FRF_LINE: return hv_frf_line(o->origin, o->direction, out);
    case HV_FRF_PLANE: return hv_frf_plane(o->point, o->normal, out);
    case HV_FRF_HALFSPACE: return hv_frf_halfspace(o->point, o->normal, out);
    case HV_FRF_SEGMENT: return hv_frf_segment(o->from, o->to, out);
    case HV_FRF_CONTOUR:
    case HV_FRF_MASK:
        if (!vol) return hv_error_set(HV_ERR_INVALID, "a %s feature needs a model", hv_frf_kind_name(o->kind));
        return o->kind == HV_FRF_CONTOUR ? hv_frf_contour(vol, o->grid, out) : hv_frf_mask(vol, o->grid, out);
    case HV_FRF_FIELD:
        if (!vol) return hv_error_set(HV_ERR_INVALID, "a field feature needs the model whose voxels it samples");
        return hv_frf_field_file(vol, NULL, o->file, o->array, (hv_field_outside)o->outside, out);
    default: return hv_error_set(HV_ERR_INVALID, "a %s feature is not made from options", hv_frf_kind_name(o->kind));
    }
}

/* ---- facet selections -------------------------------------------------------------------------- */

#define SOFF(f) offsetof(hv_facet_select, f)
static const hv_option k_select[] = {
    {.key = "normal", .kind = HV_OPT_NUMBER, .count = 3, .lo = -1e9, .hi = 1e9, .offset = SOFF(normal),
     .meta = "X,Y,Z", .help = "facets whose normal is within angle of this direction"},
    {.key = "angle", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 180, .offset = SOFF(angle_deg), .meta = "DEG",
     .unit = "degrees", .help = "the tolerance of normal"},
    {.key = "box_min", .kind = HV_OPT_NUMBER, .count = 3, .lo = -1e9, .hi = 1e9, .offset = SOFF(box_lo),
     .meta = "X,Y,Z", .help = "facets whose centroid lies in the box from box_min ..."},
    {.key = "box_max", .kind = HV_OPT_NUMBER, .count = 3, .lo = -1e9, .hi = 1e9, .offset = SOFF(box_hi),
     .meta = "X,Y,Z", .help = "... to box_max"},
};
#undef SOFF
static const hv_opt_rule k_select_rules[] = {{HV_RULE_NEEDS, "angle", "normal", NULL, NULL},
                                             {HV_RULE_NEEDS, "box_min", "box_max", NULL, NULL},
                                             {HV_RULE_NEEDS, "box_max", "box_min", NULL, NULL}};

static hv_status select_finish(const hv_optargs *args)
{
    hv_facet_select *s = args->opts;
    s->use_normal = hv_optargs_given(args, "normal");
    s->use_box = hv_optargs_given(args, "box_min");
    if (!s->use_normal && !s->use_box)
        return hv_error_option(HV_ERR_INVALID, "select facets by {normal} (and {angle}) and/or {box_min}, {box_max}");
    if (s->use_normal && s->normal[0] == 0 && s->normal[1] == 0 && s->normal[2] == 0)
        return hv_error_option(HV_ERR_INVALID, "{normal} must not be zero");
    return HV_OK;
}

static void select_init(void *o)
{
    memset(o, 0, sizeof(hv_facet_select));
    ((hv_facet_select *)o)->angle_deg = 10;
}

static const hv_option_set k_select_set = {"facets", k_select, (int)HV_COUNT(k_select), sizeof(hv_facet_select),
                                           select_init, k_select_rules, (int)HV_COUNT(k_select_rules),
                                           select_finish, NULL, NULL, 0};

const hv_option_set *hv_facet_select_option_set(void) { return &k_select_set; }

/* ---- sources ------------------------------------------------------------------------------------ */

/* ranges: D-,DG,D+ in one value */
static hv_status parse_ranges(const hv_option *o, void *opts, const hv_opt_value *v)
{
    hv_ags_options *a = opts;
    static const hv_option three = {.key = "ranges", .kind = HV_OPT_NUMBER, .count = 3, .lo = -1e9, .hi = 1e9,
                                    .meta = "D-,DG,D+"};
    double r[3];
    hv_status s = hv_option_set_value(&three, r, v);
    if (s != HV_OK) return s;
    (void)o;
    a->d_neg = r[0];
    a->d_grad = r[1];
    a->d_pos = r[2];
    return HV_OK;
}

/* ms, me: one fraction per material */
static hv_status parse_composition(const hv_option *o, void *opts, const hv_opt_value *v)
{
    hv_ags_options *a = opts;
    int is_ms = strcmp(o->key, "ms") == 0;
    double *p = is_ms ? a->ms : a->me;
    int *n = is_ms ? &a->nms : &a->nme;
    static const hv_option one = {.key = "fraction", .kind = HV_OPT_NUMBER};
    if (v->type == HV_VALUE_NUMBERS) {
        if (v->n < 1 || v->n > HV_MAX_MATERIALS)
            return hv_error_option(HV_ERR_INVALID, "{%s} must be 1 to %d fractions, got %d", o->key, HV_MAX_MATERIALS, v->n);
        memcpy(p, v->numbers, (size_t)v->n * sizeof(double));
        *n = v->n;
        return HV_OK;
    }
    if (v->type != HV_VALUE_TEXT) return hv_error_option(HV_ERR_INVALID, "{%s} must be a list of fractions", o->key);
    int k = 0;
    const char *s = v->text;
    while (1) {
        const char *c = strchr(s, ',');
        size_t len = c ? (size_t)(c - s) : strlen(s);
        char num[64];
        if (k == HV_MAX_MATERIALS || len == 0 || len >= sizeof num)
            return hv_error_option(HV_ERR_INVALID, "{%s} must be 1 to %d comma-separated fractions, got '%s'", o->key,
                                   HV_MAX_MATERIALS, v->text);
        memcpy(num, s, len);
        num[len] = '\0';
        if (hv_option_set_text(&one, &p[k], num) != HV_OK)
            return hv_error_option(HV_ERR_INVALID, "{%s} must be comma-separated numbers, got '%s'", o->key, v->text);
        ++k;
        if (!c) break;
        s = c + 1;
    }
    *n = k;
    return HV_OK;
}

#define AOFF(f) offsetof(hv_ags_options, f)
/* the ranges and f, shared by AGS and Wu's 3-material sources */
#define AGS_RANGES_AND_F \
    {.key = "ranges", .kind = HV_OPT_CUSTOM, .meta = "D-,DG,D+", .parse = parse_ranges, \
     .help = "the negative constant, gradient and positive constant ranges (Wu eq. 11); DG = 0 is a step"}, \
    {.key = "d_neg", .kind = HV_OPT_NUMBER, .lo = -1e9, .hi = 1e9, .offset = AOFF(d_neg), .meta = "D", \
     .help = "d-: the negative constant range (below 0 only for a signed feature: halfspace, field)"}, \
    {.key = "d_grad", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e9, .offset = AOFF(d_grad), .meta = "D", \
     .help = "dg: the gradient range (0: a step, a multi-material object)"}, \
    {.key = "d_pos", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e9, .offset = AOFF(d_pos), .meta = "D", \
     .help = "d+: the positive constant range"}, \
    {.key = "f", .kind = HV_OPT_STRING, .offset = AOFF(f), .meta = "EXPR", \
     .help = "the distribution function on [0, dg]: arithmetic in d and dg (+ - * / ^, sin cos tan exp log sqrt " \
             "pow min max abs, pi); it must stay in [0, 1] (default d/dg)"},
static const hv_option k_ags[] = {
    AGS_RANGES_AND_F
    {.key = "ms", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REQUIRED, .meta = "V,V,...", .parse = parse_composition,
     .help = "Ms: the start composition, one fraction >= 0 per material, summing to 1"},
    {.key = "me", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REQUIRED, .meta = "V,V,...", .parse = parse_composition,
     .help = "Me: the end composition"},
    {.key = "name", .kind = HV_OPT_STRING, .offset = AOFF(name), .meta = "NAME", .help = "a name for the source"},
    {.key = "calibration", .kind = HV_OPT_STRING, .flags = HV_OPT_IN_PATH, .offset = AOFF(calibration),
     .meta = "FILE.csv", .help = "a calibration table: rows t,value of a property measured along Ms -> Me "
                                 "(header t,<property>[<unit>]); kept with the source"},
    {.key = "property_grading", .kind = HV_OPT_STRING, .offset = AOFF(property_grading), .meta = "PROPERTY",
     .help = "grade to property targets: the property Ps + f (Pe - Ps) at distance d, through the exact inverse of "
             "the calibration table"},
    {.key = "ps", .kind = HV_OPT_STRING, .offset = AOFF(ps), .meta = "VALUE[UNIT]",
     .help = "Ps: the property at the start (e.g. 2GPa; without a unit, the table's)"},
    {.key = "pe", .kind = HV_OPT_STRING, .offset = AOFF(pe), .meta = "VALUE[UNIT]", .help = "Pe: at the end"},
    {.key = "log", .kind = HV_OPT_FLAG, .offset = AOFF(log),
     .help = "interpolate the property logarithmically, Ps (Pe/Ps)^f (common for moduli)"},
};

static const hv_opt_rule k_ags_rules[] = {{HV_RULE_EXCLUDES, "ranges", "d_neg", NULL, NULL},
                                          {HV_RULE_EXCLUDES, "ranges", "d_grad", NULL, NULL},
                                          {HV_RULE_EXCLUDES, "ranges", "d_pos", NULL, NULL},
                                          {HV_RULE_NEEDS, "property_grading", "ps", NULL, NULL},
                                          {HV_RULE_NEEDS, "property_grading", "pe", NULL, NULL},
                                          {HV_RULE_NEEDS, "ps", "property_grading", NULL, NULL},
                                          {HV_RULE_NEEDS, "pe", "property_grading", NULL, NULL},
                                          {HV_RULE_NEEDS, "log", "property_grading", NULL, NULL}};
static const hv_opt_rule k_wu3_rules[] = {{HV_RULE_EXCLUDES, "ranges", "d_neg", NULL, NULL},
                                          {HV_RULE_EXCLUDES, "ranges", "d_grad", NULL, NULL},
                                          {HV_RULE_EXCLUDES, "ranges", "d_pos", NULL, NULL}};

static hv_status ags_validate(const void *opts)
{
    const hv_ags_options *a = opts;
    if (a->nms != a->nme)
        return hv_error_option(HV_ERR_INVALID, "{ms} has %d values and {me} %d", a->nms, a->nme);
    if (a->nms == 0) return HV_OK; /* not given yet: required, checked when a source is made */
    /* a composition off the simplex is a bad definition (exit 1), named as Wu names it */
    hv_status s = hv_composition_check(a->ms, a->nms, "Ms");
    if (s == HV_OK) s = hv_composition_check(a->me, a->nme, "Me");
    return s;
}

void hv_ags_options_init(hv_ags_options *o) { memset(o, 0, sizeof *o); }
static void ags_init(void *o) { hv_ags_options_init(o); }

static const hv_option_set k_ags_set = {"source", k_ags, (int)HV_COUNT(k_ags), sizeof(hv_ags_options), ags_init,
                                        k_ags_rules, (int)HV_COUNT(k_ags_rules), NULL, ags_validate, NULL, 0};

const hv_option_set *hv_ags_option_set(void) { return &k_ags_set; }

static const hv_option k_wu3[] = {
    AGS_RANGES_AND_F
    {.key = "c", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1, .offset = offsetof(hv_ags_options, c), .meta = "C",
     .help = "C: the constant fraction of the third material (Wu eq. 13: P = [f, 1 - f - C, C])"},
};
static const hv_option_set k_wu3_set = {"wu3 source", k_wu3, (int)HV_COUNT(k_wu3), sizeof(hv_ags_options), ags_init,
                                        k_wu3_rules, (int)HV_COUNT(k_wu3_rules), NULL, NULL, NULL, 0};
const hv_option_set *hv_wu3_option_set(void) { return &k_wu3_set; }

hv_status hv_ags_wu3_from_options(hv_frf *frf, const hv_ags_options *o, const hv_dfn *f, hv_ags **out)
{
    *out = NULL;
    hv_status s = hv_options_check(&k_wu3_set, o);
    if (s != HV_OK) return s;
    if (!f && !o->f) return hv_error_option(HV_ERR_INVALID, "{f} is required (Wu eq. 13: P = [f, 1 - f - c, c])");
    hv_dfn *own = NULL;
    if (!f && (s = hv_dfn_expr(o->f, &own)) != HV_OK) return s;
    s = hv_ags_wu3(frf, o->d_neg, o->d_grad, o->d_pos, f ? f : own, o->c, out);
    hv_dfn_destroy(own);
    return s;
}

hv_status hv_ags_from_options(hv_frf *frf, const hv_ags_options *o, const hv_dfn *f, hv_ags **out)
{
    *out = NULL;
    hv_status s = hv_options_check(&k_ags_set, o);
    if (s != HV_OK) return s;
    if (o->nms < 1) return hv_error_option(HV_ERR_INVALID, "{ms} and {me} are required");
    hv_dfn *own = NULL;
    if (!f && o->d_grad > 0) {
        s = hv_dfn_expr(o->f ? o->f : "d/dg", &own);
        if (s != HV_OK) return hv_error_option(s, "{f}: %s", hv_last_error());
        f = own;
    }
    hv_calibration *calib = NULL;
    hv_property_target target = {o->property_grading, 0, 0, o->log};
    if (o->calibration_table) calib = hv_calibration_retain(o->calibration_table);
    else if (o->calibration) s = hv_calibration_load(o->calibration, &calib);
    if (s == HV_OK && o->property_grading && !calib)
        s = hv_error_set(HV_ERR_INVALID, "grading to %s targets needs a calibration table", o->property_grading);
    const char *unit = calib ? hv_calibration_unit(calib) : "";
    if (s == HV_OK && o->property_grading) s = hv_quantity_parse(o->ps, unit, "Ps", &target.ps);
    if (s == HV_OK && o->property_grading) s = hv_quantity_parse(o->pe, unit, "Pe", &target.pe);
    if (s == HV_OK) {
        hv_ags_desc d = {frf, o->d_neg, o->d_grad, o->d_pos, f, o->ms, o->me, o->nms, o->name};
        s = hv_ags_create_calibrated(&d, calib, o->property_grading ? &target : NULL, out);
    }
    hv_calibration_release(calib);
    hv_dfn_destroy(own);
    return s;
}

/* ---- blending --------------------------------------------------------------------------------- */

static const char *const k_blend_names[] = {"nearest", "idw", NULL};
static const hv_enum_def k_blend = {"blend", k_blend_names, NULL, NULL};

const hv_enum_def *hv_blend_enum(void) { return &k_blend; }

hv_status hv_blend_parse(const char *name, hv_blend *out)
{
    int v;
    hv_status s = hv_enum_parse(&k_blend, name ? name : "", &v);
    if (s == HV_OK) *out = (hv_blend)v;
    return s;
}

const char *hv_blend_name(hv_blend blend)
{
    const char *n = hv_enum_name(&k_blend, (int)blend);
    return n ? n : "?";
}
