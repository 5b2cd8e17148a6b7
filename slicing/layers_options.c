/* slicing/layers_options.c - the options of printer slice stacks (hovox/layers.h,
 * hovox/options.h): the printer profiles, names, domains, defaults and the rules between them,
 * read by the CLI, Lua and job files alike. */
#include <math.h>
#include <stddef.h>
#include <string.h>
#include <strings.h>

#include "core/internal.h"
#include "hovox/layers.h"

/* ---- profiles ------------------------------------------------------------------------------ */

static const hv_printer_profile g_profiles[] = {
    /* build volumes and material slots from Stratasys' public J750/J850 spec sheets */
    {"j750", "Stratasys J750 voxel printing: 600 x 300 dpi, 0.027 mm layers", {600, 300}, 0.027, {490, 390, 200}, 6},
    {"j850", "Stratasys J850 voxel printing (High Mix mode): 600 x 300 dpi, 0.027 mm layers",
     {600, 300}, 0.027, {490, 390, 200}, 7},
};

int hv_printer_profile_count(void) { return (int)HV_COUNT(g_profiles); }

const hv_printer_profile *hv_printer_profile_at(int i)
{
    return i >= 0 && i < (int)HV_COUNT(g_profiles) ? &g_profiles[i] : NULL;
}

const hv_printer_profile *hv_printer_profile_find(const char *name)
{
    for (size_t i = 0; name && i < HV_COUNT(g_profiles); ++i)
        if (strcasecmp(name, g_profiles[i].name) == 0) return &g_profiles[i];
    return NULL;
}

void hv_layers_options_init(hv_layers_options *o)
{
    memset(o, 0, sizeof *o);
    o->mode = HV_LAYERS_HALFTONE;
    o->method = HV_LAYERS_RESAMPLE;
    o->halftone = HV_HALFTONE_BLUE_NOISE;
    o->profile = g_profiles[0].name;
    o->dpi[0] = g_profiles[0].dpi[0];
    o->dpi[1] = g_profiles[0].dpi[1];
    o->layer_height = g_profiles[0].layer_height;
    o->fill_rule = HV_FILL_NONZERO;
    o->margin = 2;
    o->poi_step = HV_POI_DEFAULT_STEP;
    o->close_gap = HV_SLICE_DEFAULT_CLOSE_GAP;
    o->compression = 1;
}

/* ---- the option table ---------------------------------------------------------------------- */

static const char *const k_mode_names[] = {"halftone", "fractions", "mask", NULL};
static const char *const k_method_names[] = {"resample", "direct", NULL};
static const char *const k_halftone_names[] = {"bluenoise", "error", NULL};
static const char *const k_rule_names[] = {"nonzero", "evenodd", NULL};
static const hv_enum_def k_mode = {"layers mode", k_mode_names, NULL, NULL};
static const hv_enum_def k_method = {"layers method", k_method_names, NULL, NULL};
static const hv_enum_def k_halftone = {"halftone method", k_halftone_names, NULL, NULL};
static const hv_enum_def k_rule = {"fill rule", k_rule_names, NULL, NULL};

const char *hv_layers_mode_name(hv_layers_mode m)
{
    const char *n = hv_enum_name(&k_mode, (int)m);
    return n ? n : "?";
}

hv_status hv_layers_mode_parse(const char *name, hv_layers_mode *out)
{
    int v;
    hv_status s = hv_enum_parse(&k_mode, name, &v);
    if (s == HV_OK) *out = (hv_layers_mode)v;
    return s;
}

const char *hv_layers_method_name(hv_layers_method m)
{
    const char *n = hv_enum_name(&k_method, (int)m);
    return n ? n : "?";
}

const char *hv_halftone_method_name(hv_halftone_method m)
{
    const char *n = hv_enum_name(&k_halftone, (int)m);
    return n ? n : "?";
}

const char *hv_fill_rule_name(hv_fill_rule r)
{
    const char *n = hv_enum_name(&k_rule, (int)r);
    return n ? n : "?";
}

static hv_status check_profile(const hv_option *o, const void *opts)
{
    const char *name = *(const char *const *)((const char *)opts + o->offset);
    if (!name || hv_printer_profile_find(name) || strcmp(name, "custom") == 0) return HV_OK;
    char list[256];
    size_t n = 0;
    list[0] = '\0';
    for (int i = 0; i < hv_printer_profile_count() && n < sizeof list; ++i)
        n += (size_t)snprintf(list + n, sizeof list - n, "%s, ", hv_printer_profile_at(i)->name);
    return hv_error_option(HV_ERR_INVALID, "{%s} must be a printer profile (%sor {dpi} with {layer_height}), got '%s'",
                           o->key, list, name);
}

#define OFF(f) offsetof(hv_layers_options, f)
static const hv_option k_opts[] = {
    {.key = "profile", .kind = HV_OPT_STRING, .offset = OFF(profile), .meta = "NAME", .check = check_profile,
     .help = "j750: Stratasys J750 voxel printing, 600 x 300 dpi, 0.027 mm layers; j850: Stratasys J850 "
             "(High Mix), the same grid (default j750)",
     .section = "Printer"},
    {.key = "dpi", .kind = HV_OPT_NUMBER, .count = 2, .lo = 1, .hi = 1e6, .offset = OFF(dpi), .meta = "X,Y",
     .unit = "dpi", .help = "a generic printer: dpi along x and y (with --layer-height)"},
    {.key = "layer_height", .kind = HV_OPT_NUMBER, .lo = 1e-4, .hi = 100, .offset = OFF(layer_height), .meta = "H",
     .unit = "mm", .help = "layer height in mm (with dpi, or overriding the profile's)"},
    {.key = "mode", .kind = HV_OPT_ENUM, .enumdef = &k_mode, .offset = OFF(mode), .meta = "M",
     .help = "halftone: indexed PNG, palette 0 = background, j = the j-th material; fractions: 8-bit grey "
             "PNG per material (DIR/<material>/), 255 = 1; mask: 1-bit PNG, 1 = object (no model needed)",
     .section = "Output"},
    {.key = "method", .kind = HV_OPT_ENUM, .enumdef = &k_method, .offset = OFF(method), .meta = "M",
     .help = "resample (Wu: trilinear + POI from the voxels) or direct (the grading definition at every "
             "pixel; also reports the difference)"},
    {.key = "compare", .kind = HV_OPT_FLAG, .offset = OFF(compare),
     .help = "with resample: also evaluate direct and report the difference"},
    {.key = "halftone", .kind = HV_OPT_ENUM, .enumdef = &k_halftone, .offset = OFF(halftone), .meta = "H",
     .help = "bluenoise: a 64x64x32 void-and-cluster threshold mask; error: vector error diffusion, "
             "serpentine, 1/4 of the error carried to the next layer, restarted every 32 layers"},
    {.key = "seed", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_UINT64, .offset = OFF(seed), .meta = "N",
     .help = "halftone seed (mask offset, diffusion start noise; default 0)"},
    {.key = "layers", .kind = HV_OPT_RANGE, .offset = OFF(first), .meta = "A:B",
     .help = "only layers A to B-1 of the full plan (A: or :B allowed); file names keep the global index, "
             "so split runs give the same files"},
    {.key = "background", .kind = HV_OPT_COLOR, .elem = HV_ELEM_UINT8, .offset = OFF(background), .meta = "COLOR",
     .help = "halftone palette entry 0 (#rrggbb)"},
    {.key = "gcvf", .kind = HV_OPT_STRING, .flags = HV_OPT_OUT_PATH, .offset = OFF(gcvf_path), .meta = "FILE.zip",
     .help = "also a GrabCAD voxel-print style zip: ConfigFile.xml and layer_<index>.png (halftone or mask "
             "mode)"},
    {.key = "force", .kind = HV_OPT_FLAG, .offset = OFF(force),
     .help = "replace an existing stack (a directory with a hovox manifest)"},
    {.key = "fill_rule", .kind = HV_OPT_ENUM, .enumdef = &k_rule, .offset = OFF(fill_rule), .meta = "R",
     .help = "nonzero or evenodd", .section = "Geometry"},
    {.key = "threshold", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1000, .offset = OFF(threshold), .meta = "D",
     .unit = "mm", .help = "Wu's threshold: pixels outside the contour but within D mm of it stay object"},
    {.key = "place", .kind = HV_OPT_NUMBER, .count = 2, .lo = -1e6, .hi = 1e6, .offset = OFF(place), .meta = "X,Y",
     .unit = "mm", .help = "place the part on the profile's plate, the centre of its box at X,Y: the image is its "
                           "box on the plate's pixel grid, with the pixels a tray gives it"},
    {.key = "margin", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .lo = 0, .hi = 100000, .offset = OFF(margin),
     .meta = "N", .unit = "pixels", .help = "background pixels around the mesh's xy box"},
    {.key = "close_gap", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .offset = OFF(close_gap), .meta = "D",
     .unit = "mm", .help = "join open contour ends at most D mm apart"},
    {.key = "poi_step", .kind = HV_OPT_NUMBER, .lo = 1, .hi = 1e6, .flags = HV_OPT_UNSET0, .offset = OFF(poi_step), .meta = "R",
     .help = "largest up-sampling ratio of one POI step (1: one exact step)", .section = "Resources"},
    {.key = "compression", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .lo = 0, .hi = 9,
     .offset = OFF(compression), .meta = "L", .help = "PNG zlib level 0..9"},
    {.key = "max_memory", .kind = HV_OPT_BYTES, .offset = OFF(max_memory), .meta = "SIZE",
     .help = "refuse jobs that would need more (default: half of RAM), e.g. 8G"},
};
#undef OFF

_Static_assert(offsetof(hv_layers_options, last) == offsetof(hv_layers_options, first) + sizeof(size_t),
               "first and last must be adjacent");

static const hv_opt_rule k_rules[] = {
    {HV_RULE_EXCLUDES, "profile", "dpi", NULL, NULL},
    {HV_RULE_NEEDS, "dpi", "layer_height", NULL, NULL},
    {HV_RULE_NEEDS_VALUE, "seed", "mode", "halftone", NULL},
    {HV_RULE_NEEDS_VALUE, "halftone", "mode", "halftone", NULL},
    {HV_RULE_NEEDS_VALUE, "background", "mode", "halftone", "it is the halftone palette's entry 0"},
    {HV_RULE_NEEDS_VALUE, "method", "mode", "halftone|fractions", NULL},
    {HV_RULE_NEEDS_VALUE, "compare", "mode", "halftone|fractions", NULL},
    {HV_RULE_NEEDS_VALUE, "gcvf", "mode", "halftone|mask", NULL},
};

/* The printer: a named profile (its dpi and height; layer_height may override the height) or a
 * generic one from dpi and layer_height. */
static hv_status finish(const hv_optargs *args)
{
    hv_layers_options *o = args->opts;
    o->placed = hv_optargs_given(args, "place");
    if (hv_optargs_given(args, "dpi")) {
        o->profile = "custom";
        return HV_OK;
    }
    const hv_printer_profile *p = hv_printer_profile_find(o->profile ? o->profile : "j750");
    if (!p) return HV_OK; /* check_profile said so */
    o->profile = p->name;
    o->dpi[0] = p->dpi[0];
    o->dpi[1] = p->dpi[1];
    if (!hv_optargs_given(args, "layer_height")) o->layer_height = p->layer_height;
    return HV_OK;
}

static hv_status validate(const void *opts)
{
    const hv_layers_options *o = opts;
    if (o->gcvf_path && o->mode == HV_LAYERS_FRACTIONS)
        return hv_error_option(HV_ERR_INVALID, "{gcvf} needs {mode} halftone or mask: a GCVF archive holds halftone "
                                               "or mask layers, not fractions");
    return HV_OK;
}

static void init(void *o) { hv_layers_options_init(o); }

static const hv_option_set k_set = {"layers", k_opts, (int)HV_COUNT(k_opts), sizeof(hv_layers_options), init,
                                    k_rules, (int)HV_COUNT(k_rules), finish, validate, NULL, 0};

const hv_option_set *hv_layers_option_set(void) { return &k_set; }

hv_status hv_layers_options_check(const hv_layers_options *o)
{
    if (!o) return hv_error_set(HV_ERR_INVALID, "layers: options are NULL");
    return hv_options_check(&k_set, o);
}
