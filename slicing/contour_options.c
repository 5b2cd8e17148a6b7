/* slicing/contour_options.c - the options of contour slicing (hovox/slice.h, hovox/options.h):
 * uniform or adaptive layers, the first layer, the gap rule and the CLI format, for the library,
 * the CLI and Lua. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/slice.h"

/* adaptive: MIN,MAX[,CUSP] */
static hv_status parse_adaptive(const hv_option *o, void *opts, const hv_opt_value *v)
{
    hv_contours_options *c = opts;
    static const hv_option three = {.key = "adaptive", .kind = HV_OPT_NUMBER, .count = 3, .meta = "MIN,MAX[,CUSP]"};
    static const hv_option two = {.key = "adaptive", .kind = HV_OPT_NUMBER, .count = 2, .meta = "MIN,MAX[,CUSP]"};
    double a[3] = {0, 0, 0};
    if (hv_option_set_value(&three, a, v) != HV_OK && hv_option_set_value(&two, a, v) != HV_OK)
        return hv_error_option(HV_ERR_INVALID, "{%s} must be MIN,MAX or MIN,MAX,CUSP (mm)", o->key);
    if (!(a[0] > 0) || !(a[0] <= a[1]) || a[1] > 100 || a[2] < 0)
        return hv_error_option(HV_ERR_INVALID, "{%s} needs 0 < MIN <= MAX <= 100 and CUSP > 0, got %g,%g,%g", o->key,
                               a[0], a[1], a[2]);
    memcpy(c->adaptive, a, sizeof a);
    return HV_OK;
}

static hv_status check_output(const hv_option *o, const void *opts)
{
    hv_contour_format f;
    return hv_contour_format_for_path(*(const char *const *)((const char *)opts + o->offset), 0, &f);
}

#define OFF(f) offsetof(hv_contours_options, f)
static const hv_option k_opts[] = {
    {.key = "layer_height", .kind = HV_OPT_NUMBER, .lo = 1e-4, .hi = 100, .flags = HV_OPT_UNSET0, .offset = OFF(layer_height), .meta = "H",
     .unit = "mm", .help = "uniform layers of H mm", .section = "Layers (one of)"},
    {.key = "adaptive", .kind = HV_OPT_CUSTOM, .meta = "MIN,MAX[,CUSP]", .parse = parse_adaptive,
     .help = "adaptive layers between MIN and MAX mm, thinner where the surface is nearly horizontal: a "
             "facet with normal n allows CUSP/|n_z| (cusp-height criterion; CUSP defaults to MIN)"},
    {.key = "first_layer", .kind = HV_OPT_NUMBER, .lo = 1e-4, .hi = 100, .flags = HV_OPT_UNSET0, .offset = OFF(first_layer), .meta = "H0",
     .unit = "mm", .help = "height of the first layer (default: as the others)"},
    {.key = "close_gap", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .offset = OFF(close_gap), .meta = "D",
     .unit = "mm", .help = "join open polyline ends at most D mm apart; chains of an open mesh that still do not "
                           "close are reported as open polylines (CLI dir 2, SVG class \"open\")",
     .section = "Contours"},
    {.key = "binary", .kind = HV_OPT_FLAG, .offset = OFF(binary), .help = "binary CLI instead of ASCII (a .cli output)"},
    {.key = "output", .kind = HV_OPT_STRING, .flags = HV_OPT_OUT_PATH, .offset = OFF(output), .meta = "FILE",
     .check = check_output, .section = "Output",
     .help = ".svg: one file, a <g> per layer (data-z = cut height), 1 user unit = 1 mm, y up; .cli: Common Layer "
             "Interface 2.0, ASCII ($$LAYER/z is the top of the layer, the first starting at $$DIMENSION's "
             "lowest z; $$LAYERS the count of layers; $$POLYLINE dir 1 outer, 0 hole, 2 open)"},
    {.key = "per_layer", .kind = HV_OPT_STRING, .flags = HV_OPT_OUT_PATH, .offset = OFF(per_layer), .meta = "DIR",
     .help = "also one SVG per layer: DIR/layer-00000.svg, ..."},
};
#undef OFF

static const hv_opt_rule k_rules[] = {{HV_RULE_EXCLUDES, "layer_height", "adaptive", NULL, NULL}};

static hv_status finish(const hv_optargs *args)
{
    const hv_contours_options *c = args->opts;
    if (!(c->layer_height > 0) && !(c->adaptive[0] > 0))
        return hv_error_option(HV_ERR_INVALID, "{layer_height} or {adaptive} is required");
    return HV_OK;
}

static hv_status validate(const void *opts)
{
    const hv_contours_options *c = opts;
    hv_contour_format f;
    if (c->layer_height > 0 && c->adaptive[0] > 0)
        return hv_error_option(HV_ERR_INVALID, "{layer_height} and {adaptive} exclude each other");
    if (c->binary && (!c->output || hv_contour_format_for_path(c->output, 1, &f) != HV_OK))
        return hv_error_option(HV_ERR_INVALID, "{binary} needs a .cli output");
    return HV_OK;
}

void hv_slice_options_init(hv_slice_options *o)
{
    if (o) o->close_gap = HV_SLICE_DEFAULT_CLOSE_GAP;
}

void hv_contours_options_init(hv_contours_options *o)
{
    memset(o, 0, sizeof *o);
    o->close_gap = HV_SLICE_DEFAULT_CLOSE_GAP;
}

static void init(void *o) { hv_contours_options_init(o); }

static const hv_option_set k_set = {"contours", k_opts, (int)HV_COUNT(k_opts), sizeof(hv_contours_options), init,
                                    k_rules, (int)HV_COUNT(k_rules), finish, validate, NULL, 0};

const hv_option_set *hv_contours_option_set(void) { return &k_set; }

hv_status hv_contours_options_check(const hv_contours_options *o) { return hv_options_check(&k_set, o); }

hv_status hv_slicer_plan(const hv_slicer *slicer, const hv_contours_options *o, hv_layer_plan **out)
{
    *out = NULL;
    hv_status s = hv_contours_options_check(o);
    if (s != HV_OK) return s;
    if (!(o->layer_height > 0) && !(o->adaptive[0] > 0))
        return hv_error_option(HV_ERR_INVALID, "{layer_height} or {adaptive} is required");
    if (o->adaptive[0] > 0)
        return hv_slicer_plan_adaptive(slicer, o->first_layer, o->adaptive[0], o->adaptive[1], o->adaptive[2], out);
    return hv_slicer_plan_uniform(slicer, o->first_layer, o->layer_height, out);
}
