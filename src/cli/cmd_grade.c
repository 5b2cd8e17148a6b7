/* src/cli/cmd_grade.c - `hovox grade MODEL.vdb -o OUT.vdb --materials A,B,C --frf FRF
 * --ranges D-,DG,D+ --f EXPR --ms ... --me ...`: materials from grading sources (Wu 2.2). A
 * source's values are the library's (hv_ags_option_set, hv_frf_option_set); this file only
 * groups them after each --frf and reads the FRF syntax KIND:A:B. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "core/internal.h"
#include "hovox/model.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"

#define MAX_SOURCES 32
#define MAX_PROPS 64

typedef struct source {
    const char *frf;
    const char *region; /* --region before the --frf: the region it grades; NULL: every region */
    char spec[1024]; /* the split copy of the --frf text: the feature's strings point into it */
    hv_frf_options feature;
    hv_ags_options a;
    hv_optargs args;
} source;

typedef struct grade_cli {
    const char *output, *materials, *colors, *grid;
    const char *props[MAX_PROPS];
    int nprops;
    int blend;
    uint64_t max_memory;
    int ns;
    source src[MAX_SOURCES];
    const char *region; /* a --region waiting for its --frf */
} grade_cli;

/* The features --frf makes, "point, axis, ..." */
static const char *frf_kinds(char *list, size_t size)
{
    size_t n = 0;
    const hv_enum_def *e = hv_frf_kind_enum();
    list[0] = '\0';
    for (int i = 0; e->names[i] && n < size; ++i) {
        hv_frf_kind k;
        if (hv_frf_kind_parse(e->names[i], &k) == HV_OK && hv_frf_option_set(k))
            n += (size_t)snprintf(list + n, size - n, "%s%s", n ? ", " : "", e->names[i]);
    }
    return list;
}

/* "axis:0,0,0:0,0,1" -> the feature's keys in their order (checked as the options are read) */
static hv_status parse_frf(const char *spec, char *buf, size_t size, hv_frf_options *o)
{
    if (strlen(spec) >= size) return hv_error_option(HV_ERR_INVALID, "{frf} is longer than %zu bytes", size - 1);
    snprintf(buf, size, "%s", spec);
    char *kind = buf, *arg = strchr(buf, ':');
    if (arg) *arg++ = '\0';
    hv_frf_kind k;
    const hv_option_set *set = NULL;
    if (hv_frf_kind_parse(kind, &k) != HV_OK || !(set = hv_frf_option_set(k))) {
        char list[256];
        return hv_error_option(HV_ERR_INVALID, "unknown feature '%s' (%s)", kind, frf_kinds(list, sizeof list));
    }
    hv_optargs args;
    hv_optargs_begin(&args, set, o);
    int given = 0;
    for (; arg; ++given) {
        char *next = strchr(arg, ':');
        if (next) *next++ = '\0';
        if (given >= set->count)
            return hv_error_option(HV_ERR_INVALID, "%s takes %d value%s (%s)", kind, set->count,
                                   set->count == 1 ? "" : "s", spec);
        hv_opt_value v = {HV_VALUE_TEXT, arg, NULL, 0, 0};
        if (hv_optargs_set(&args, set->options[given].key, &v) != HV_OK) return HV_ERR_INVALID;
        arg = next;
    }
    /* the values are positional: a missing one is named in the syntax, not as an option */
    for (int i = given; i < set->count; ++i)
        if (set->options[i].flags & HV_OPT_REQUIRED) {
            char syntax[256];
            size_t n = (size_t)snprintf(syntax, sizeof syntax, "%s", kind);
            int same = 1;
            for (int j = 0; j < set->count && n + 2 < sizeof syntax; ++j) {
                syntax[n++] = ':';
                for (const char *c = set->options[j].key; *c && n + 1 < sizeof syntax; ++c)
                    syntax[n++] = (char)toupper((unsigned char)*c);
                syntax[n] = '\0';
                same &= strcmp(set->options[j].meta, set->options[0].meta) == 0;
            }
            char key[64];
            size_t m = 0;
            for (const char *c = set->options[i].key; *c && m + 1 < sizeof key; ++c) key[m++] = (char)toupper((unsigned char)*c);
            key[m] = '\0';
            return hv_error_set(HV_ERR_INVALID, "%s is missing (%s%s%s)", key, syntax, same ? ", each " : "",
                                same ? set->options[0].meta : "");
        }
    return hv_optargs_finish(&args);
}

/* --frf starts a source; --ranges, --f, --ms and --me set its keys through the library */
static hv_status start_source(const hv_option *o, void *opts, const hv_opt_value *v)
{
    grade_cli *g = opts;
    if (g->ns == MAX_SOURCES) return hv_error_option(HV_ERR_INVALID, "at most %d grading sources ({%s})", MAX_SOURCES, o->key);
    source *s = &g->src[g->ns++];
    s->frf = v->text;
    s->region = g->region;
    g->region = NULL;
    hv_optargs_begin(&s->args, hv_ags_option_set(), &s->a);
    hv_status st = parse_frf(v->text, s->spec, sizeof s->spec, &s->feature);
    return st == HV_OK ? st : hv_error_prefix(st, "source %d (%s %s): ", g->ns, cli_spell("frf"), v->text);
}

/* --region NAME restricts the next source to that region */
static hv_status set_region(const hv_option *o, void *opts, const hv_opt_value *v)
{
    grade_cli *g = opts;
    if (g->region)
        return hv_error_option(HV_ERR_INVALID, "{%s} %s: a source grades one region; give {%s} once before its {frf}", o->key,
                               g->region, o->key);
    if (v->type != HV_VALUE_TEXT || !*v->text) return hv_error_option(HV_ERR_INVALID, "{%s} needs a region name", o->key);
    g->region = v->text;
    return HV_OK;
}

static hv_status source_value(const hv_option *o, void *opts, const hv_opt_value *v)
{
    grade_cli *g = opts;
    if (g->ns == 0) return hv_error_option(HV_ERR_INVALID, "{%s} must follow a {frf} (it belongs to that source)", o->key);
    hv_status s = hv_optargs_set(&g->src[g->ns - 1].args, o->key, v);
    return s == HV_OK ? s : hv_error_prefix(s, "source %d: ", g->ns);
}

static hv_status parse_blend(const hv_option *o, void *opts, const hv_opt_value *v)
{
    grade_cli *g = opts;
    hv_blend b;
    if (v->type != HV_VALUE_TEXT || hv_blend_parse(v->text, &b) != HV_OK)
        return hv_error_option(HV_ERR_INVALID, "{%s} must be nearest or idw, got '%s'", o->key,
                               v->type == HV_VALUE_TEXT ? v->text : "?");
    g->blend = (int)b;
    return HV_OK;
}

static hv_status add_property(const hv_option *o, void *opts, const hv_opt_value *v)
{
    grade_cli *g = opts;
    if (g->nprops == MAX_PROPS) return hv_error_option(HV_ERR_INVALID, "at most %d {%s} options", MAX_PROPS, o->key);
    g->props[g->nprops++] = v->text;
    return HV_OK;
}

#define OFF(f) offsetof(grade_cli, f)
static const hv_option k_local_opts[] = {
    CLI_OUTPUT(grade_cli, "OUT.vdb", "the graded model to write (atomically)", HV_OPT_REQUIRED),
    {.key = "materials", .kind = HV_OPT_STRING, .offset = OFF(materials), .meta = "A,B,...",
     .help = "material names (letters, digits, _ -); for a model voxelized from an assembly, default: its bodies' "
             "materials, and a list given must name them all",
     .section = "Materials"},
    {.key = "colors", .kind = HV_OPT_STRING, .offset = OFF(colors), .meta = "C1,C2,...",
     .help = "display colours (#rrggbb); default: a distinguishable palette"},
    {.key = "property", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .meta = "M:KEY=VALUE[:UNIT]",
     .parse = add_property, .help = "a physical property (e.g. A:density=1180:kg/m^3); without a unit, the property's SI unit"},
    {.key = "region", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .meta = "NAME", .parse = set_region,
     .section = "Grading sources (each --frf starts one; the options after it belong to it)",
     .help = "before a --frf: that source grades region NAME alone (a body of an assembly); the other regions keep "
             "their own sources or their base material"},
    {.key = "frf", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .meta = "FRF", .parse = start_source,
     .help = "the reference feature: axis:OX,OY,OZ:DX,DY,DZ, plane:PX,PY,PZ:NX,NY,NZ, point:X,Y,Z, "
             "segment:AX,AY,AZ:BX,BY,BZ, contour (depth below the model's boundary), mask:GRID, "
             "field:FILE:ARRAY[:refuse|nearest] (a scalar field from .vti/.vtu point or cell data or a .vdb float "
             "grid, sampled at the voxel centres; its value is d)"},
    /* the source's own options: the library's (help text too), routed to the last --frf */
    {.key = "ranges", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .parse = source_value},
    {.key = "f", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .parse = source_value},
    {.key = "ms", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .parse = source_value},
    {.key = "me", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .parse = source_value},
    {.key = "calibration", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .parse = source_value},
    {.key = "property_grading", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .parse = source_value},
    {.key = "ps", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .parse = source_value},
    {.key = "pe", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .parse = source_value},
    {.key = "log", .kind = HV_OPT_FLAG, .flags = HV_OPT_REPEAT, .parse = source_value},
    {.key = "blend", .kind = HV_OPT_CUSTOM, .parse = parse_blend, .meta = "RULE",
     .help = "AGS union: the nearest source (nearest) or inverse-distance weights 1/(d + L/2)^2 (idw)",
     .section = "The object"},
    {.key = "grid", .kind = HV_OPT_STRING, .offset = OFF(grid), .meta = "NAME",
     .help = "the bool grid holding the geometry, as one region (default: the model's regions when it was voxelized "
             "from an assembly, else occupancy)"},
    {.key = "max_memory", .kind = HV_OPT_BYTES, .offset = OFF(max_memory), .meta = "SIZE",
     .help = "refuse jobs that would need more (default: half of RAM)"},
};
#undef OFF

static const hv_option_set k_local = CLI_LOCAL_SET("grade", k_local_opts, grade_cli);


static hv_status add_sources(const grade_cli *g, const hv_volume *vol, hv_object *obj, int quiet)
{
    hv_status s = HV_OK;
    for (int i = 0; i < g->ns && s == HV_OK; ++i) {
        const source *src = &g->src[i];
        hv_frf *frf = NULL;
        hv_ags *a = NULL;
        hv_frf_options fo = src->feature;
        if (fo.kind == HV_FRF_CONTOUR && g->grid) fo.grid = g->grid;
        s = hv_frf_from_options(&fo, vol, &frf);
        hv_field_report rep;
        if (s == HV_OK && !quiet && hv_frf_field_report(frf, &rep)) /* to choose d-, dg, d+ by */
            printf("field       %s:%s: %.6g to %.6g over %llu voxels (in the file %.6g to %.6g; %llu voxels outside "
                   "it%s)\n", fo.file, fo.array, rep.lo, rep.hi, (unsigned long long)rep.voxels, rep.file_lo,
                   rep.file_hi, (unsigned long long)rep.filled, rep.filled ? ", given the nearest covered value" : "");
        if (s == HV_OK) s = hv_ags_from_options(frf, &src->a, NULL, &a);
        if (s == HV_OK) s = src->region ? hv_object_add_ags_region(obj, src->region, a) : hv_object_add_ags(obj, a);
        if (s == HV_ERR_NOT_FOUND && src->region) { /* a body whose voxels earlier bodies took: say so */
            char why[2048];
            snprintf(why, sizeof why, "%s", hv_last_error());
            hv_regions *rg = NULL;
            int64_t k = hv_voxelize_regions_read(vol, &rg) == HV_OK ? hv_regions_find(rg, src->region) : -1;
            const hv_region_info *ri = k >= 0 ? hv_regions_at(rg, (size_t)k) : NULL;
            if (ri && ri->voxels == 0)
                hv_error_set(s, "region '%s' is empty: other bodies took all its %llu voxels (its centres are all "
                             "inside bodies before it in the file)",
                             src->region, (unsigned long long)ri->lost);
            else
                hv_error_set(s, "%s", why);
            hv_regions_destroy(rg);
        }
        if (s != HV_OK && src->region)
            hv_error_prefix(s, "source %d (%s %s %s %s): ", i + 1, cli_spell("region"), src->region, cli_spell("frf"),
                            src->frf);
        else if (s != HV_OK)
            hv_error_prefix(s, "source %d (%s %s): ", i + 1, cli_spell("frf"), src->frf);
        hv_ags_release(a);
        hv_frf_release(frf);
    }
    return s;
}

static hv_status check_ms(const grade_cli *g, int m)
{
    for (int i = 0; i < g->ns; ++i)
        if (g->src[i].a.nms != m)
            return hv_error_set(HV_ERR_INVALID, "source %d: Ms has %d values for %d materials", i + 1, g->src[i].a.nms, m);
    return HV_OK;
}

static int grade(const char *model, grade_cli *g, int quiet)
{
    hv_material_table *given = NULL, *t = NULL;
    hv_volume *vol = NULL, *graded = NULL;
    hv_object *obj = NULL;
    hv_status s = HV_OK;
    /* everything the user typed is checked before the model is read */
    if (g->materials && (s = hv_material_table_parse(g->materials, g->colors, g->props, g->nprops, &given)) == HV_OK)
        s = check_ms(g, hv_material_count(given));
    if (s == HV_OK) s = hv_model_load(model, &vol);
    int assembly = 0;
    if (s == HV_OK && !g->grid) {
        /* a model voxelized from an assembly: one region per body, each of its body's material */
        s = hv_object_from_regions(vol, given, &t, &obj);
        assembly = s == HV_OK;
        if (s == HV_ERR_NOT_FOUND) s = HV_OK;
        else if (s != HV_OK) hv_error_prefix(s, "%s: ", model);
        if (assembly && !given && (s = hv_material_table_amend(t, g->colors, g->props, g->nprops)) == HV_OK)
            s = check_ms(g, hv_material_count(t));
    }
    if (s == HV_OK && !assembly) {
        if (!given) s = hv_error_option(HV_ERR_INVALID, "{materials} is required (the model has no regions with materials)");
        else if (g->ns == 0) s = hv_error_option(HV_ERR_INVALID, "{frf} is required (the model has no regions to grade "
                                                               "to their materials)");
        else if ((s = hv_material_table_clone(given, &t)) == HV_OK)
            s = hv_object_create(vol, g->grid ? g->grid : "occupancy", hv_material_count(t), &obj);
    }
    int m = t ? hv_material_count(t) : 0;
    if (s == HV_OK) s = hv_object_set_blend(obj, (hv_blend)g->blend, 2.0);
    if (s == HV_OK) s = add_sources(g, vol, obj, quiet);
    cli_progress bar;
    cli_progress_init(&bar, quiet);
    hv_progress prog = {cli_progress_fn, &bar};
    if (s == HV_OK) s = hv_object_evaluate(obj, t, g->max_memory, &prog, &graded);
    cli_progress_done(&bar);
    if (s == HV_OK) s = hv_volume_save(graded, g->output);
    if (s == HV_OK && !quiet) {
        if (assembly)
            for (int r = 0; r < hv_object_region_count(obj); ++r) {
                double base[HV_MAX_MATERIALS];
                hv_object_region_base(obj, r, base);
                int j = 0;
                while (j < m && base[j] != 1.0) ++j;
                printf("region      %s: %llu voxels, base %s, %d source%s\n", hv_object_region_name(obj, r),
                       (unsigned long long)hv_object_region_voxels(obj, r), j < m ? hv_material_name(t, j) : "mixed",
                       hv_object_region_ags_count(obj, r), hv_object_region_ags_count(obj, r) == 1 ? "" : "s");
            }
        printf("graded      %s: %llu voxels, %d materials, %d source%s\n", model,
               (unsigned long long)hv_object_voxels(obj), m, g->ns, g->ns == 1 ? "" : "s");
        printf("wrote       %s\n", g->output);
    }
    hv_volume_destroy(graded);
    hv_object_destroy(obj);
    hv_volume_destroy(vol);
    hv_material_table_destroy(t);
    hv_material_table_destroy(given);
    return s == HV_OK ? EXIT_OK : cli_fail(s);
}

static int run(const cli_args *args, void *lib, void *local)
{
    grade_cli *g = local;
    (void)lib;
    if (g->region)
        return cli_usage_error("grade", "%s %s must come before the %s of the source it restricts", cli_spell("region"),
                               g->region, cli_spell("frf"));
    for (int i = 0; i < g->ns; ++i)
        if (hv_optargs_finish(&g->src[i].args) != HV_OK) {
            hv_error_prefix(HV_ERR_INVALID, "source %d (%s %s): ", i + 1, cli_spell("frf"), g->src[i].frf);
            return cli_fail(HV_ERR_INVALID);
        }
    return grade(args->pos[0], g, args->quiet);
}

const cli_spec cmd_grade = {
    "grade", "assign materials by grading sources (AGS) on reference features",
    "MODEL.vdb -o OUT.vdb --materials A,B[,C...] [options]\n"
    "                   --frf FRF --ranges D-,DG,D+ [--f EXPR] --ms V,V,... --me V,V,...\n"
    "                  [--frf ... --me ...]...\n"
    "       hovox grade ASSEMBLY.vdb -o OUT.vdb [--materials A,B,...] [[--region NAME] --frf ... --me ...]...",
    "Assign material fractions to a voxelized model with grading sources (AGS, Wu 2.2):\n"
    "each voxel at distance d from the reference feature gets\n"
    "  P = Ms + f(d - D-) (Me - Ms) for D- <= d <= D- + DG (the gradient range),\n"
    "  the boundary values of f below and above it (continuous), and for DG = 0 a step:\n"
    "  Ms below D-, Me from D- on (a multi-material object).\n"
    "Repeating the group --frf ... --me adds sources (AGS union, see --blend).\n"
    "A model voxelized from an assembly has a region per body, each 100% its body's\n"
    "material where no source applies; --region NAME before a --frf grades that region\n"
    "alone.\n",
    NULL, &k_local, NULL, 1, 1, "MODEL argument", CLI_THREADS | CLI_QUIET | CLI_POS_FILES, run, NULL,
    hv_ags_option_set};
