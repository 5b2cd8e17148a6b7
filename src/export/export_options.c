/* src/export/export_options.c - the export options (hovox/export.h, hovox/options.h): names,
 * domains and defaults for the library, the CLI and Lua. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "core/internal.h"
#include "export_internal.h"

static const char *const k_keep_names[] = {"majority", "any", NULL};
static const hv_enum_def k_keep = {"coarsen rule", k_keep_names, NULL, NULL};
static const char *const k_mix_names[] = {"both", "voigt", "reuss", "none", NULL};
static const int k_mix_values[] = {HV_MIX_VOIGT | HV_MIX_REUSS, HV_MIX_VOIGT, HV_MIX_REUSS, 0};
static const hv_enum_def k_mix = {"mixing rules", k_mix_names, k_mix_values, NULL};

const char *hv_coarsen_rule_name(hv_coarsen_rule rule)
{
    const char *n = hv_enum_name(&k_keep, (int)rule);
    return n ? n : "?";
}

/* box: two corners, either first */
static hv_status parse_box(const hv_option *o, void *opts, const hv_opt_value *v)
{
    hv_export_options *e = opts;
    static const hv_option six = {.key = "box", .kind = HV_OPT_NUMBER, .count = 6, .meta = "X0,Y0,Z0,X1,Y1,Z1"};
    double b[6];
    hv_status s = hv_option_set_value(&six, b, v);
    if (s != HV_OK) return s;
    (void)o;
    for (int a = 0; a < 3; ++a) {
        e->box_lo[a] = HV_MIN(b[a], b[a + 3]);
        e->box_hi[a] = HV_MAX(b[a], b[a + 3]);
    }
    e->use_box = 1;
    return HV_OK;
}

/* linearize: PROPERTY=FILE.csv, repeatable */
static hv_status parse_linearize(const hv_option *o, void *opts, const hv_opt_value *v)
{
    hv_export_options *e = opts;
    const char *eq = v->type == HV_VALUE_TEXT ? strchr(v->text, '=') : NULL;
    if (!eq || eq == v->text || !eq[1] || (size_t)(eq - v->text) >= sizeof e->linearize[0].property)
        return hv_error_option(HV_ERR_INVALID, "{%s} must be PROPERTY=FILE.csv, got '%s'", o->key,
                               v->type == HV_VALUE_TEXT ? v->text : "?");
    if (e->nlinearize == HV_EXPORT_MAX_TABLES)
        return hv_error_option(HV_ERR_INVALID, "{%s}: at most %d tables", o->key, HV_EXPORT_MAX_TABLES);
    memcpy(e->linearize[e->nlinearize].property, v->text, (size_t)(eq - v->text));
    e->linearize[e->nlinearize].property[eq - v->text] = '\0';
    e->linearize[e->nlinearize].path = eq + 1;
    e->nlinearize++;
    return HV_OK;
}

static hv_status check_bits(const hv_option *o, const void *opts)
{
    int b = ((const hv_export_options *)opts)->bits;
    if (b == 0 || b == 8 || b == 16) return HV_OK;
    return hv_error_option(HV_ERR_INVALID, "{%s} must be 8 or 16, got %d", o->key, b);
}

#define OFF(f) offsetof(hv_export_options, f)
static const hv_option k_opts[] = {
    {.key = "box", .kind = HV_OPT_CUSTOM, .meta = "X0,Y0,Z0,X1,Y1,Z1", .parse = parse_box,
     .help = "export the voxels whose centres lie in this world box (two corners, mm)"},
    {.key = "coarsen", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .lo = 1, .hi = 4096, .offset = OFF(coarsen),
     .meta = "N", .help = ".vtu: one hexahedron per NxNxN block (aligned to multiples of N), fractions averaged "
                         "over its occupied voxels"},
    {.key = "keep", .kind = HV_OPT_ENUM, .enumdef = &k_keep, .offset = OFF(coarsen_rule), .meta = "RULE",
     .help = ".vtu with coarsen: keep a block when at least half of its voxels are occupied (majority) or any "
             "is (any)"},
    {.key = "properties", .kind = HV_OPT_ENUM, .enumdef = &k_mix, .offset = OFF(mix), .meta = "RULES",
     .help = "mixing rules for the derived properties: both, voigt (sum p_j X_j), reuss (1 / sum p_j / X_j) "
             "or none"},
    {.key = "linearize", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT | HV_OPT_PAIRS, .meta = "PROPERTY=FILE.csv",
     .parse = parse_linearize,
     .help = "a measured table PROPERTY(fraction of one material); CSV header 'fraction.<material>,"
             "<property>[<unit>]', then rows 'fraction,value'; repeatable"},
    {.key = "grids", .kind = HV_OPT_STRING, .offset = OFF(grids), .meta = "NAME[,NAME...]",
     .help = "also export these float grids of the model (e.g. a field a script computed) as arrays of "
             "their names"},
    {.key = "level", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .lo = 1, .hi = 9, .flags = HV_OPT_UNSET0,
     .offset = OFF(zlib_level), .meta = "N", .help = "zlib level: 1 (fastest, default) to 9 (smallest)"},
    {.key = "bits", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .lo = 8, .hi = 16, .flags = HV_OPT_UNSET0,
     .offset = OFF(bits), .meta = "N", .check = check_bits,
     .help = ".3mf --volumetric: bits per PNG sample of the image stacks, 8 (default) or 16"},
    {.key = "volumetric", .kind = HV_OPT_FLAG, .offset = OFF(volumetric),
     .help = ".3mf: the 3MF Volumetric package of the voxels (the grading as image stacks, the voxel "
             "boundary as mesh) instead of the shape's mesh"},
    {.key = "max_memory", .kind = HV_OPT_BYTES, .offset = OFF(max_memory), .meta = "SIZE",
     .help = "refuse exports whose buffers need more (default: half of RAM), e.g. 2G"},
};
#undef OFF

static const hv_opt_rule k_rules[] = {{HV_RULE_NEEDS, "keep", "coarsen", NULL, NULL}};

static hv_status validate(const void *opts)
{
    const hv_export_options *o = opts;
    if (o->mix & ~(unsigned)(HV_MIX_VOIGT | HV_MIX_REUSS))
        return hv_error_set(HV_ERR_INVALID, "export: unknown mixing rule bits 0x%x", o->mix);
    if (o->ntables < 0 || (o->ntables > 0 && !o->tables))
        return hv_error_set(HV_ERR_INVALID, "export: %d tables but no table list", o->ntables);
    if (o->nlinearize < 0 || o->nlinearize > HV_EXPORT_MAX_TABLES)
        return hv_error_set(HV_ERR_INVALID, "export: %d linearization files (at most %d)", o->nlinearize,
                            HV_EXPORT_MAX_TABLES);
    if ((o->format == HV_EXPORT_VTI || o->format == HV_EXPORT_3MF) && o->coarsen > 1)
        return hv_error_option(HV_ERR_INVALID, "{coarsen} applies to .vtu output only");
    if ((o->format == HV_EXPORT_VTI || o->format == HV_EXPORT_VTU) && o->bits)
        return hv_error_option(HV_ERR_INVALID, "{bits} applies to .3mf output only");
    if (o->format != HV_EXPORT_AUTO && o->format != HV_EXPORT_3MF && o->format != HV_EXPORT_3MF_SHAPE &&
        o->volumetric)
        return hv_error_option(HV_ERR_INVALID, "{volumetric} applies to .3mf output only");
    if (o->use_box)
        for (int a = 0; a < 3; ++a)
            if (!isfinite(o->box_lo[a]) || !isfinite(o->box_hi[a]) || o->box_lo[a] > o->box_hi[a])
                return hv_error_option(HV_ERR_INVALID, "{box} [%g, %g] on %c is empty or not finite", o->box_lo[a],
                                       o->box_hi[a], "xyz"[a]);
    return HV_OK;
}

void hv_export_options_init(hv_export_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->format = HV_EXPORT_AUTO;
    opt->coarsen = 1;
    opt->coarsen_rule = HV_COARSEN_MAJORITY;
    opt->mix = HV_MIX_VOIGT | HV_MIX_REUSS;
}

static void init(void *o) { hv_export_options_init(o); }

static const hv_option_set k_set = {"export", k_opts, (int)HV_COUNT(k_opts), sizeof(hv_export_options), init,
                                    k_rules, (int)HV_COUNT(k_rules), NULL, validate, NULL, 0};

const hv_option_set *hv_export_option_set(void) { return &k_set; }

hv_status hv_export_options_check(const hv_export_options *o) { return hv_options_check(&k_set, o); }
