/* src/mesh/shapes.c - the parametric shapes by name (hovox/generate.h): each shape's parameters
 * as an option set (hovox/options.h) with its defaults, so `hovox generate SHAPE key=value`, Lua's
 * hovox.generate.SHAPE{...} and job files read the same names and ranges. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/generate.h"

#define OFF(f) offsetof(hv_shape_params, f)
#define OFF1(f, i) (offsetof(hv_shape_params, f) + (i) * sizeof(double))
#define LEN(k_, f, help_) {.key = k_, .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .flags = HV_OPT_LO_OPEN, \
                            .offset = OFF(f), .meta = "MM", .unit = "mm", .help = help_}
#define VEC(k_, f, help_) {.key = k_, .kind = HV_OPT_NUMBER, .count = 3, .lo = -1e6, .hi = 1e6, \
                            .offset = OFF(f), .meta = "X,Y,Z", .unit = "mm", .help = help_}
#define COMP(k_, f, i, help_) {.key = k_, .kind = HV_OPT_NUMBER, .lo = -1e6, .hi = 1e6, .offset = OFF1(f, i), \
                                .meta = "MM", .unit = "mm", .help = help_}
#define COUNT(k_, f, lo_, hi_, help_) {.key = k_, .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .lo = lo_, \
                                        .hi = hi_, .offset = OFF(f), .meta = "N", .help = help_}

static const hv_option k_sphere[] = {
    VEC("center", center, "centre"),
    COMP("cx", center, 0, "centre x"),
    COMP("cy", center, 1, "centre y"),
    COMP("cz", center, 2, "centre z"),
    LEN("radius", radius, "radius"),
    COUNT("segments", segments, 3, 100000, "segments around z"),
    COUNT("rings", rings, 2, 100000, "rings from pole to pole"),
};

static const hv_option k_box[] = {
    VEC("min", min, "lower corner"),
    VEC("max", max, "upper corner (unless a size is given)"),
    {.key = "size", .kind = HV_OPT_NUMBER, .count = 3, .lo = 0, .hi = 1e6, .flags = HV_OPT_LO_OPEN | HV_OPT_UNSET0,
     .offset = OFF(size), .meta = "X,Y,Z", .unit = "mm", .help = "edge lengths from the lower corner"},
    {.key = "sx", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .flags = HV_OPT_LO_OPEN | HV_OPT_UNSET0, .offset = OFF1(size, 0),
     .meta = "MM", .unit = "mm", .help = "edge length along x"},
    {.key = "sy", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .flags = HV_OPT_LO_OPEN | HV_OPT_UNSET0, .offset = OFF1(size, 1),
     .meta = "MM", .unit = "mm", .help = "edge length along y"},
    {.key = "sz", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .flags = HV_OPT_LO_OPEN | HV_OPT_UNSET0, .offset = OFF1(size, 2),
     .meta = "MM", .unit = "mm", .help = "edge length along z"},
    {.key = "hole", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .offset = OFF(hole), .meta = "R", .unit = "mm",
     .help = "radius of a through hole along z, centred (0: none)"},
    COUNT("segments", segments, 8, 100000, "hole polygon vertices (a multiple of 8)"),
};

static const hv_option k_torus[] = {
    VEC("center", center, "centre"),
    LEN("R", R, "major radius"),
    LEN("r", r, "minor radius"),
    COUNT("segments", segments, 3, 100000, "segments around z"),
    COUNT("rings", rings, 3, 100000, "segments around the tube"),
};

static const hv_option k_cylinder[] = {
    VEC("base", base, "centre of the start face"),
    COUNT("axis", axis, 0, 2, "0, 1 or 2: along x, y or z"),
    LEN("length", length, "length"),
    LEN("radius", radius, "radius"),
    COUNT("segments", segments, 3, 1000000, "segments around the axis"),
};

static const hv_option k_knot[] = {
    {.key = "facets", .kind = HV_OPT_NUMBER, .lo = 16, .hi = 1e9, .offset = OFF(facets), .meta = "N",
     .help = "about this many facets"},
    COUNT("p", p, 1, 1000, "turns around the axis"),
    COUNT("q", q, 1, 1000, "turns through the hole"),
    LEN("R", R, "major radius of the torus"),
    LEN("r", r, "minor radius of the torus"),
    LEN("tube", tube, "radius of the tube"),
    COUNT("segments_around", segments_around, 3, 100000, "samples around the tube"),
};

static const hv_option k_gear[] = {
    COUNT("teeth", teeth, 3, 10000, "teeth"),
    LEN("root", root, "root radius"),
    LEN("tip", tip, "tip radius"),
    {.key = "bore", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .offset = OFF(bore), .meta = "MM", .unit = "mm",
     .help = "bore radius (0: none)"},
    LEN("height", height, "height"),
    {.key = "twist", .kind = HV_OPT_NUMBER, .lo = -1e3, .hi = 1e3, .offset = OFF(twist), .meta = "RAD",
     .unit = "radians", .help = "helix twist from bottom to top (0: spur gear)"},
    COUNT("segments", segments, 8, 10000, "angular samples per tooth"),
    COUNT("layers", layers, 1, 100000, "slices in z"),
};

static void init_common(hv_shape_params *p) { memset(p, 0, sizeof *p); }
static void init_sphere(void *v)
{
    hv_shape_params *p = v;
    init_common(p);
    p->radius = 10;
    p->segments = 64;
    p->rings = 32;
}
static void init_box(void *v)
{
    hv_shape_params *p = v;
    init_common(p);
    p->max[0] = p->max[1] = p->max[2] = 20;
    p->segments = 64;
}
static void init_holed_box(void *v)
{
    hv_shape_params *p = v;
    init_common(p);
    p->max[0] = 40;
    p->max[1] = 30;
    p->max[2] = 20;
    p->hole = 8;
    p->segments = 64;
}
static void init_torus(void *v)
{
    hv_shape_params *p = v;
    init_common(p);
    p->R = 20;
    p->r = 6;
    p->segments = 96;
    p->rings = 48;
}
static void init_cylinder(void *v)
{
    hv_shape_params *p = v;
    init_common(p);
    p->length = 150;
    p->radius = 27.5;
    p->segments = 128;
}
static void init_knot(void *v)
{
    hv_shape_params *p = v;
    init_common(p);
    p->facets = 200000;
    p->p = 2;
    p->q = 3;
    p->R = 30;
    p->r = 12;
    p->tube = 5;
    p->segments_around = 64;
}
static void init_gear(void *v)
{
    hv_shape_params *p = v;
    init_common(p);
    p->teeth = 24;
    p->root = 34.5;
    p->tip = 39.45;
    p->bore = 9.54;
    p->height = 39.45;
    p->segments = 12;
    p->layers = 1;
}

static hv_status box_corners(const hv_shape_params *p, double hi[3])
{
    for (int a = 0; a < 3; ++a) hi[a] = p->size[a] > 0 ? p->min[a] + p->size[a] : p->max[a];
    return HV_OK;
}

#define SET(name_, opts, init_, about)                                                                        \
    {{name_, opts, (int)HV_COUNT(opts), sizeof(hv_shape_params), init_, NULL, 0, NULL, NULL, NULL, 0}, about}
static const struct shape {
    hv_option_set set;
    const char *about;
} k_shapes[] = {
    SET("sphere", k_sphere, init_sphere, "UV sphere"),
    SET("box", k_box, init_box, "axis-aligned box, optionally with a through hole along z"),
    SET("holed-box", k_box, init_holed_box, "box 40 x 30 x 20 with a hole of radius 8 along z"),
    SET("torus", k_torus, init_torus, "torus around z"),
    SET("cylinder", k_cylinder, init_cylinder, "cylinder (Wu's 150 x 55 x 55 shaft)"),
    SET("knot", k_knot, init_knot, "tube around a (p,q) torus knot (the bench input)"),
    SET("gear", k_gear, init_gear, "gear with a bore (Wu's gear: bore 9.54, tip radius 39.45)"),
};

int hv_shape_count(void) { return (int)HV_COUNT(k_shapes); }

int hv_shape_find(const char *name)
{
    for (int i = 0; name && i < (int)HV_COUNT(k_shapes); ++i)
        if (strcmp(k_shapes[i].set.name, name) == 0) return i;
    char list[512];
    size_t n = 0;
    list[0] = '\0';
    for (int i = 0; i < (int)HV_COUNT(k_shapes) && n < sizeof list; ++i)
        n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", i ? ", " : "", k_shapes[i].set.name);
    hv_error_set(HV_ERR_NOT_FOUND, "unknown shape '%s' (shapes: %s)", name ? name : "", list);
    return -1;
}

const char *hv_shape_name(int shape)
{
    return shape >= 0 && shape < (int)HV_COUNT(k_shapes) ? k_shapes[shape].set.name : NULL;
}

const char *hv_shape_about(int shape)
{
    return shape >= 0 && shape < (int)HV_COUNT(k_shapes) ? k_shapes[shape].about : NULL;
}

const hv_option_set *hv_shape_option_set(int shape)
{
    return shape >= 0 && shape < (int)HV_COUNT(k_shapes) ? &k_shapes[shape].set : NULL;
}

static hv_status build(int shape, const hv_shape_params *p, hv_mesh **out)
{
    const char *name = k_shapes[shape].set.name;
    double hi[3];
    if (strcmp(name, "sphere") == 0) return hv_generate_sphere(p->center, p->radius, p->segments, p->rings, out);
    if (strcmp(name, "box") == 0 || strcmp(name, "holed-box") == 0) {
        box_corners(p, hi);
        if (p->hole > 0) return hv_generate_box_with_hole(p->min, hi, p->hole, p->segments, out);
        return hv_generate_box(p->min, hi, out);
    }
    if (strcmp(name, "torus") == 0) return hv_generate_torus(p->center, p->R, p->r, p->segments, p->rings, out);
    if (strcmp(name, "cylinder") == 0)
        return hv_generate_cylinder(p->base, p->axis, p->length, p->radius, p->segments, out);
    if (strcmp(name, "knot") == 0) {
        int nv = p->segments_around, nu = (int)lround(p->facets / (2.0 * nv));
        return hv_generate_torus_knot(p->p, p->q, p->R, p->r, p->tube, HV_MAX(nu, 3), nv, out);
    }
    return hv_generate_gear(p->teeth, p->root, p->tip, p->bore, p->height, p->twist, p->segments, p->layers, out);
}

hv_status hv_generate_shape(int shape, const hv_shape_params *p, hv_mesh **out)
{
    *out = NULL;
    const hv_option_set *set = hv_shape_option_set(shape);
    if (!set) return hv_error_set(HV_ERR_INVALID, "no shape %d", shape);
    hv_status s = hv_options_check(set, p);
    if (s != HV_OK) return s;
    s = build(shape, p, out);
    if (s != HV_OK) hv_error_prefix(s, "%s: ", set->name);
    return s;
}
