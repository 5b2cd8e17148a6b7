/* src/colour/colour_options.c - the colour map's options (hovox/colour.h, hovox/options.h): the
 * output profile, the rendering intent and the resin map, one table for the library, the CLI, job
 * files and Lua. */
#include <stddef.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/colour.h"

static const char *const k_intent_names[] = {"perceptual", "relative", "saturation", "absolute", NULL};
static const char *const k_intent_aliases[] = {"relative-colorimetric", "relative", "absolute-colorimetric",
                                               "absolute", NULL};
static const hv_enum_def k_intent = {"rendering intent", k_intent_names, NULL, k_intent_aliases};

const char *hv_intent_name(hv_intent i)
{
    const char *n = hv_enum_name(&k_intent, (int)i);
    return n ? n : "?";
}

int hv_intent_parse(const char *name, hv_intent *out)
{
    int v;
    if (hv_enum_parse(&k_intent, name, &v) != HV_OK) return -1;
    *out = (hv_intent)v;
    return 0;
}

void hv_colour_options_init(hv_colour_options *o)
{
    memset(o, 0, sizeof *o);
    o->intent = HV_INTENT_PERCEPTUAL;
}

#define OFF(f) offsetof(hv_colour_options, f)
static const hv_option k_opts[] = {
    {.key = "icc", .kind = HV_OPT_STRING, .flags = HV_OPT_IN_PATH, .offset = OFF(icc), .meta = "FILE.icc",
     .help = "the printer's output ICC profile (CMYK) that sRGB colours go through (default: Ghostscript's "
             "default_cmyk.icc, a generic SWOP press profile from libgs-common)",
     .section = "Colour"},
    {.key = "intent", .kind = HV_OPT_ENUM, .enumdef = &k_intent, .offset = OFF(intent), .meta = "INTENT",
     .help = "rendering intent: perceptual (default), relative, saturation or absolute (colorimetric)"},
    {.key = "resins", .kind = HV_OPT_STRING, .offset = OFF(resins), .meta = "C,M,Y,K,W,CLEAR",
     .help = "the resins that print cyan, magenta, yellow, black, white and clear (default the J750's: "
             "VeroCyan-V,VeroMagenta-V,VeroYellow-V,VeroBlackPlus,VeroPureWhite,VeroClear)"},
};
#undef OFF

static void init(void *o) { hv_colour_options_init(o); }

static const hv_option_set k_set = {"colour", k_opts, (int)HV_COUNT(k_opts), sizeof(hv_colour_options), init,
                                    NULL, 0, NULL, NULL, NULL, 0};

const hv_option_set *hv_colour_option_set(void) { return &k_set; }

hv_status hv_colour_option_parse(const hv_option *o, void *opts, const hv_opt_value *v)
{
    const hv_option *c = hv_option_find(&k_set, o->key);
    if (!c) return hv_error_option(HV_ERR_INVALID, "{%s} is not a colour option", o->key);
    return hv_option_set_value(c, (char *)opts + o->offset, v);
}
