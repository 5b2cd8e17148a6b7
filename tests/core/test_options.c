/* tests/core/test_options.c - option domains (hovox/options.h): parsing every kind from text and
 * from numbers, domains and their messages, rules between options, aliases, spelling of option
 * names by a front end, and the library's own option sets checked against their defaults. */
#include <criterion/criterion.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "hovox/export.h"
#include "hovox/generate.h"
#include "hovox/layers.h"
#include "hovox/material.h"
#include "hovox/options.h"
#include "hovox/profile.h"
#include "hovox/render.h"
#include "hovox/slice.h"
#include "hovox/voxelize.h"

typedef struct demo {
    double step;
    int size[2];
    double eye[3];
    int64_t dims[3];
    int mode;
    uint64_t seed, budget;
    size_t range[2];
    float color[4];
    uint8_t rgb[3];
    int flag;
    const char *name;
} demo;

static const char *const k_modes[] = {"volume", "surface", NULL};
static const char *const k_alias[] = {"opaque", "surface", NULL};
static const hv_enum_def k_mode = {"mode", k_modes, NULL, k_alias};

static const hv_option k_opts[] = {
    {.key = "step", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 4, .flags = HV_OPT_LO_OPEN, .offset = offsetof(demo, step),
     .unit = "voxels"},
    {.key = "size", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .count = 2, .lo = 1, .hi = 65535, .flags = HV_OPT_XSEP,
     .offset = offsetof(demo, size), .meta = "W,H"},
    {.key = "eye", .kind = HV_OPT_NUMBER, .count = 3, .offset = offsetof(demo, eye), .meta = "X,Y,Z"},
    {.key = "dims", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT64, .count = 3, .lo = 1, .hi = 1e9, .flags = HV_OPT_FIRST,
     .offset = offsetof(demo, dims)},
    {.key = "mode", .kind = HV_OPT_ENUM, .enumdef = &k_mode, .offset = offsetof(demo, mode)},
    {.key = "seed", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_UINT64, .offset = offsetof(demo, seed)},
    {.key = "budget", .kind = HV_OPT_BYTES, .offset = offsetof(demo, budget)},
    {.key = "layers", .kind = HV_OPT_RANGE, .offset = offsetof(demo, range)},
    {.key = "background", .kind = HV_OPT_COLOR, .elem = HV_ELEM_FLOAT, .flags = HV_OPT_ALPHA,
     .offset = offsetof(demo, color)},
    {.key = "palette0", .kind = HV_OPT_COLOR, .elem = HV_ELEM_UINT8, .offset = offsetof(demo, rgb)},
    {.key = "flag", .kind = HV_OPT_FLAG, .offset = offsetof(demo, flag)},
    {.key = "name", .kind = HV_OPT_STRING, .offset = offsetof(demo, name)},
};
static const hv_opt_rule k_rules[] = {{HV_RULE_EXCLUDES, "eye", "mode", NULL, NULL},
                                      {HV_RULE_NEEDS, "seed", "flag", NULL, NULL},
                                      {HV_RULE_NEEDS_VALUE, "budget", "mode", "surface", "a reason"}};
static const hv_opt_alias k_aliases[] = {{"surface", "mode", "surface"}};
static void demo_init(void *p)
{
    memset(p, 0, sizeof(demo));
    ((demo *)p)->step = 1;
    ((demo *)p)->size[0] = ((demo *)p)->size[1] = 512;
}
static const hv_option_set k_set = {"demo", k_opts, (int)(sizeof k_opts / sizeof k_opts[0]), sizeof(demo), demo_init,
                                    k_rules, 3, NULL, NULL, k_aliases, 1};

static hv_status set(demo *d, const char *key, const char *text)
{
    return hv_option_set_text(hv_option_find(&k_set, key), d, text);
}

Test(options, numbers_from_text_and_domains)
{
    demo d;
    demo_init(&d);
    cr_assert_eq(set(&d, "step", "0.5"), HV_OK);
    cr_assert_float_eq(d.step, 0.5, 0);
    cr_assert_eq(set(&d, "step", "5"), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "step must be in (0, 4] voxels, got 5");
    cr_assert(hv_last_error_names_option());
    cr_assert_eq(set(&d, "step", "0"), HV_ERR_INVALID, "the open end is refused");
    /* hex, inf and nan are not numbers here, though strtod takes them */
    cr_assert_eq(set(&d, "step", "0x1"), HV_ERR_INVALID);
    cr_assert_eq(set(&d, "step", "inf"), HV_ERR_INVALID);
    cr_assert_eq(set(&d, "step", "nan"), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "step must be a number, got 'nan'");
    cr_assert_float_eq(d.step, 0.5, 0, "a refused value leaves the old one");
}

Test(options, vectors_sizes_and_the_old_wxh)
{
    demo d;
    demo_init(&d);
    cr_assert_eq(set(&d, "size", "640,480"), HV_OK);
    cr_assert_eq(d.size[0], 640);
    cr_assert_eq(d.size[1], 480);
    cr_assert_eq(set(&d, "size", "1024x768"), HV_OK, "WxH stays readable where it was documented");
    cr_assert_eq(d.size[1], 768);
    cr_assert_eq(set(&d, "size", "0x10"), HV_ERR_INVALID);
    cr_assert_eq(set(&d, "size", "640"), HV_ERR_INVALID);
    cr_assert_eq(set(&d, "size", "2.5,3"), HV_ERR_INVALID, "integers");
    cr_assert_eq(set(&d, "eye", "1,2"), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "eye must be 3 numbers (X,Y,Z), got '1,2'");
    cr_assert_eq(set(&d, "eye", " -1, 2.5e1 ,3"), HV_OK);
    cr_assert_float_eq(d.eye[1], 25, 0);
    /* FIRST: one number sets the first component and clears the others */
    d.dims[1] = d.dims[2] = 7;
    cr_assert_eq(set(&d, "dims", "128"), HV_OK);
    cr_assert(d.dims[0] == 128 && d.dims[1] == 0 && d.dims[2] == 0);
    cr_assert_eq(set(&d, "dims", "64,64,45"), HV_OK);
    cr_assert(d.dims[2] == 45);
    /* numbers from a script */
    double v[2] = {100, 200};
    hv_opt_value nv = {HV_VALUE_NUMBERS, NULL, v, 2, 0};
    cr_assert_eq(hv_option_set_value(hv_option_find(&k_set, "size"), &d, &nv), HV_OK);
    cr_assert_eq(d.size[1], 200);
}

Test(options, enums_aliases_seeds_bytes_ranges_colours)
{
    demo d;
    demo_init(&d);
    cr_assert_eq(set(&d, "mode", "surface"), HV_OK);
    cr_assert_eq(d.mode, 1);
    cr_assert_eq(set(&d, "mode", "opaque"), HV_OK, "an alias");
    cr_assert_eq(set(&d, "mode", "rainbow"), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "mode must be volume or surface, got 'rainbow'");
    cr_assert_eq(set(&d, "seed", "18446744073709551615"), HV_OK);
    cr_assert_eq(d.seed, UINT64_MAX, "64-bit seeds survive exactly");
    cr_assert_eq(set(&d, "seed", "-1"), HV_ERR_INVALID);
    cr_assert_eq(set(&d, "budget", "1.5G"), HV_OK);
    cr_assert_eq(d.budget, (uint64_t)(1.5 * 1073741824.0));
    cr_assert_eq(set(&d, "budget", "lots"), HV_ERR_INVALID);
    cr_assert_eq(set(&d, "layers", "3:10"), HV_OK);
    cr_assert(d.range[0] == 3 && d.range[1] == 10);
    cr_assert_eq(set(&d, "layers", ":10"), HV_OK);
    cr_assert(d.range[0] == 0 && d.range[1] == 10);
    cr_assert_eq(set(&d, "layers", "5:"), HV_OK);
    cr_assert(d.range[0] == 5 && d.range[1] == 0);
    cr_assert_eq(set(&d, "layers", "5:3"), HV_ERR_INVALID);
    cr_assert_eq(set(&d, "layers", "5:5"), HV_ERR_INVALID);
    cr_assert_eq(set(&d, "layers", "-1:3"), HV_ERR_INVALID);
    cr_assert_eq(set(&d, "background", "transparent"), HV_OK);
    cr_assert_float_eq(d.color[3], 0, 0);
    cr_assert_eq(set(&d, "background", "#ff000080"), HV_OK);
    cr_assert_float_eq(d.color[0], 1, 1e-6);
    cr_assert_eq(set(&d, "palette0", "#102030"), HV_OK);
    cr_assert(d.rgb[0] == 0x10 && d.rgb[2] == 0x30);
    cr_assert_eq(set(&d, "palette0", "transparent"), HV_ERR_INVALID, "no alpha in a palette entry");
    char buf[64];
    cr_assert_str_eq(hv_option_format(hv_option_find(&k_set, "palette0"), &d, buf, sizeof buf), "#102030");
    cr_assert_str_eq(hv_option_format(hv_option_find(&k_set, "budget"), &d, buf, sizeof buf), "1536M");
    cr_assert_str_eq(hv_option_format(hv_option_find(&k_set, "layers"), &d, buf, sizeof buf), "5:");
}

static const char *dashes(const char *key, void *user)
{
    (void)user;
    static char b[64];
    snprintf(b, sizeof b, "--%s", key);
    return b;
}

Test(options, rules_aliases_and_spelling)
{
    demo d;
    hv_optargs a;
    hv_opt_value t = {HV_VALUE_TEXT, "1,2,3", NULL, 0, 0}, yes = {HV_VALUE_BOOL, NULL, NULL, 0, 1};
    hv_optargs_begin(&a, &k_set, &d);
    cr_assert_eq(hv_optargs_set(&a, "eye", &t), HV_OK);
    cr_assert_eq(hv_optargs_set(&a, "surface", &yes), HV_OK, "an alias sets mode");
    cr_assert_eq(d.mode, 1);
    cr_assert_eq(hv_optargs_finish(&a), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "eye and mode exclude each other");
    char spelled[256];
    cr_assert_str_eq(hv_error_spell(dashes, NULL, spelled, sizeof spelled), "--eye and --mode exclude each other");
    /* given twice; unknown keys */
    cr_assert_eq(hv_optargs_set(&a, "eye", &t), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "eye given twice");
    cr_assert_eq(hv_optargs_set(&a, "colour", &t), HV_ERR_NOT_FOUND);
    cr_assert(strstr(hv_last_error(), "unknown option 'colour'"));
    /* needs, needs a value (with a reason) */
    hv_optargs_begin(&a, &k_set, &d);
    hv_opt_value seed = {HV_VALUE_TEXT, "7", NULL, 0, 0}, budget = {HV_VALUE_TEXT, "1G", NULL, 0, 0};
    cr_assert_eq(hv_optargs_set(&a, "seed", &seed), HV_OK);
    cr_assert_eq(hv_optargs_finish(&a), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "seed needs flag");
    hv_optargs_begin(&a, &k_set, &d);
    cr_assert_eq(hv_optargs_set(&a, "budget", &budget), HV_OK);
    cr_assert_eq(hv_optargs_finish(&a), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "budget needs mode surface: a reason");
    /* braces in a value are text, not option names */
    hv_opt_value odd = {HV_VALUE_TEXT, "{step}", NULL, 0, 0};
    hv_optargs_begin(&a, &k_set, &d);
    cr_assert_eq(hv_optargs_set(&a, "mode", &odd), HV_ERR_INVALID);
    cr_assert_str_eq(hv_error_spell(dashes, NULL, spelled, sizeof spelled),
                     "--mode must be volume or surface, got '{step}'");
    /* a message that only mentions an option is not a refusal of it */
    hv_error_option(HV_ERR_INVALID, "gear.stl: flat along z; give {voxel_size}");
    cr_assert(!hv_last_error_names_option());
    hv_error_set(HV_ERR_INVALID, "plain");
    cr_assert(!hv_last_error_names_option());
}

/* Every library option set: its defaults pass its own check, every option has a key, a help
 * text and a unique key, and every option can be set from the text of its default. */
static void check_set(const hv_option_set *set)
{
    char *opts = calloc(1, set->size), *copy = calloc(1, set->size);
    set->init(opts);
    cr_assert_eq(hv_options_check(set, opts), HV_OK, "%s: defaults: %s", set->name, hv_last_error());
    for (int i = 0; i < set->count; ++i) {
        const hv_option *o = &set->options[i];
        cr_assert(o->key && *o->key, "%s: option %d has no key", set->name, i);
        cr_assert(o->help && *o->help, "%s: %s has no help", set->name, o->key);
        for (int k = 0; k < i; ++k) cr_assert_str_neq(set->options[k].key, o->key, "%s: key %s twice", set->name, o->key);
        if (o->kind == HV_OPT_CUSTOM || o->kind == HV_OPT_FLAG || o->kind == HV_OPT_STRING) continue;
        char text[256];
        hv_option_format(o, opts, text, sizeof text);
        if ((o->flags & (HV_OPT_UNSET0 | HV_OPT_ZERO_OK | HV_OPT_FIRST | HV_OPT_SCALAR)) &&
            (strcmp(text, "0") == 0 || strcmp(text, "0,0,0") == 0))
            continue; /* "not given" is not a value a user types */
        memcpy(copy, opts, set->size);
        cr_assert_eq(hv_option_set_text(o, copy, text), HV_OK, "%s: %s = '%s' does not read back: %s", set->name,
                     o->key, text, hv_last_error());
        cr_assert_eq(memcmp(copy, opts, set->size), 0, "%s: %s = '%s' reads back different", set->name, o->key, text);
    }
    free(opts);
    free(copy);
}

Test(options, library_sets_are_consistent)
{
    check_set(hv_render_option_set());
    check_set(hv_layers_option_set());
    check_set(hv_voxelize_option_set());
    check_set(hv_export_option_set());
    check_set(hv_profile_option_set());
    check_set(hv_contours_option_set());
    check_set(hv_ags_option_set());
    check_set(hv_facet_select_option_set());
    check_set(hv_dfn_option_set());
    for (int i = 0; i < hv_shape_count(); ++i) check_set(hv_shape_option_set(i));
}

Test(options, layers_profile_sets_the_printer)
{
    hv_layers_options o;
    hv_optargs a;
    hv_optargs_begin(&a, hv_layers_option_set(), &o);
    hv_opt_value v = {HV_VALUE_TEXT, "j850", NULL, 0, 0}, lh = {HV_VALUE_TEXT, "0.014", NULL, 0, 0};
    cr_assert_eq(hv_optargs_set(&a, "profile", &v), HV_OK);
    cr_assert_eq(hv_optargs_set(&a, "layer_height", &lh), HV_OK);
    cr_assert_eq(hv_optargs_finish(&a), HV_OK);
    cr_assert_str_eq(o.profile, "j850");
    cr_assert_float_eq(o.dpi[0], 600, 0);
    cr_assert_float_eq(o.layer_height, 0.014, 0, "the given height overrides the profile's");
    hv_optargs_begin(&a, hv_layers_option_set(), &o);
    hv_opt_value bad = {HV_VALUE_TEXT, "j999", NULL, 0, 0};
    cr_assert_eq(hv_optargs_set(&a, "profile", &bad), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "j750, j850"));
}

/* hv_option_known: options, aliases and a front end's own keys are known; anything else is refused
 * with every key listed (the message Lua and Python give for a misspelt option). */
Test(options, known_keys_and_the_unknown_key_message)
{
    static const char *const extra[] = {"path", "mesh", NULL};
    cr_assert_eq(hv_option_known(&k_set, NULL, "step"), HV_OK);
    cr_assert_eq(hv_option_known(&k_set, NULL, "surface"), HV_OK); /* an alias */
    cr_assert_eq(hv_option_known(&k_set, extra, "mesh"), HV_OK);
    cr_assert_eq(hv_option_known(&k_set, NULL, "mesh"), HV_ERR_NOT_FOUND);
    cr_assert_eq(hv_option_known(&k_set, extra, "stepp"), HV_ERR_NOT_FOUND);
    cr_assert_str_eq(hv_last_error(), "unknown option 'stepp' (options: step, size, eye, dims, mode, seed, budget, "
                                      "layers, background, palette0, flag, name, surface, path, mesh)");
}
