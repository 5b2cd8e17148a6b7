/* src/cli/cmd_grade.c - `hovox grade MODEL.vdb -o OUT.vdb --materials A,B,C --frf FRF
 * --ranges D-,DG,D+ --f EXPR --ms ... --me ...`: materials from grading sources (Wu 2.2). */
#include <ctype.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "cli.h"
#include "hovox/material.h"

static const char *GRADE_HELP =
    "usage: hovox grade MODEL.vdb -o OUT.vdb --materials A,B[,C...] [options]\n"
    "                   --frf FRF --ranges D-,DG,D+ [--f EXPR] --ms V,V,... --me V,V,...\n"
    "                  [--frf ... --me ...]...\n"
    "\n"
    "Assign material fractions to a voxelized model with grading sources (AGS, Wu 2.2):\n"
    "each voxel at distance d from the reference feature gets\n"
    "  P = Ms + f(d - D-) (Me - Ms) for D- <= d <= D- + DG (the gradient range),\n"
    "  the boundary values of f below and above it (continuous), and for DG = 0 a step:\n"
    "  Ms below D-, Me from D- on (a multi-material object).\n"
    "Repeating the group --frf ... --me adds sources (AGS union, see --blend).\n"
    "\n"
    "FRF (reference feature):\n"
    "  axis:OX,OY,OZ:DX,DY,DZ     a line through O along D\n"
    "  plane:PX,PY,PZ:NX,NY,NZ    a plane through P with normal N\n"
    "  point:X,Y,Z                a point\n"
    "  segment:AX,AY,AZ:BX,BY,BZ  a segment\n"
    "  contour                    the model's boundary (depth below it)\n"
    "  mask:GRID                  the true voxels of a bool grid of the model\n"
    "EXPR: arithmetic in d (and dg): + - * / ^, parentheses, sin cos tan exp log sqrt\n"
    "  pow min max abs, pi; f must stay in [0, 1] on [0, DG]. Default: d/dg.\n"
    "Ms, Me: fractions >= 0 summing to 1, one per material.\n"
    "\n"
    "Options:\n"
    "  --materials A,B,...     material names (letters, digits, _ -)\n"
    "  --colors C1,C2,...      display colours (#rrggbb); default: a distinguishable palette\n"
    "  --property M:KEY=VALUE[:UNIT]  a physical property (e.g. A:density=1180:kg/m^3)\n"
    "  --blend nearest|idw     AGS union: the nearest source (default) or inverse-distance\n"
    "                          weights 1/(d + L/2)^2\n"
    "  --grid NAME             the bool grid holding the geometry (default occupancy)\n"
    "  --max-memory SIZE       refuse jobs that would need more (default half of RAM)\n"
    "  --threads N, -q/--quiet, -o/--output FILE, -h/--help\n";

typedef struct group {
    char *frf, *f;
    double ranges[3], ms[HV_MAX_MATERIALS], me[HV_MAX_MATERIALS];
    int have_ranges, nms, nme;
} group;

/* Comma-separated numbers; returns the count or -1 (message printed). */
static int parse_list(const char *opt, const char *s, double *out, int max)
{
    int n = 0;
    const char *p = s;
    while (*p) {
        if (n == max) {
            cli_usage_error("grade", "%s: more than %d values in '%s'", opt, max, s);
            return -1;
        }
        char *end;
        double v = strtod(p, &end);
        if (end == p || !isfinite(v)) {
            cli_usage_error("grade", "%s: '%s' is not a list of numbers", opt, s);
            return -1;
        }
        out[n++] = v;
        p = end;
        if (*p == ',') ++p;
        else if (*p) {
            cli_usage_error("grade", "%s: '%s' is not a list of numbers", opt, s);
            return -1;
        }
    }
    return n;
}

static int parse_vec3(const char *what, const char *s, double v[3], const char *frf)
{
    if (parse_list(what, s, v, 3) != 3) {
        fprintf(stderr, "hovox grade: --frf '%s': %s needs three numbers\n", frf, what);
        return -1;
    }
    return 0;
}

/* Build the FRF of a group. Returns a status (message set) or -1 for a usage error printed. */
static int make_frf(const char *spec, const hv_volume *vol, const char *grid, hv_frf **out, hv_status *st)
{
    char buf[512];
    *st = HV_OK;
    snprintf(buf, sizeof buf, "%s", spec);
    char *kind = buf, *a = strchr(buf, ':'), *b = NULL;
    if (a) {
        *a++ = '\0';
        b = strchr(a, ':');
        if (b) *b++ = '\0';
    }
    double p[3], q[3];
    if (strcmp(kind, "axis") == 0 || strcmp(kind, "plane") == 0 || strcmp(kind, "segment") == 0) {
        if (!a || !b) return cli_usage_error("grade", "--frf '%s': expected %s:X,Y,Z:X,Y,Z", spec, kind);
        if (parse_vec3("the first point", a, p, spec) || parse_vec3("the second vector", b, q, spec)) return EXIT_USAGE;
        if (kind[0] == 'a') *st = hv_frf_line(p, q, out);
        else if (kind[0] == 'p') *st = hv_frf_plane(p, q, out);
        else *st = hv_frf_segment(p, q, out);
        return 0;
    }
    if (strcmp(kind, "point") == 0) {
        if (!a || b) return cli_usage_error("grade", "--frf '%s': expected point:X,Y,Z", spec);
        if (parse_vec3("the point", a, p, spec)) return EXIT_USAGE;
        *st = hv_frf_point(p, out);
        return 0;
    }
    if (strcmp(kind, "contour") == 0) {
        if (a) return cli_usage_error("grade", "--frf '%s': contour takes no arguments", spec);
        *st = hv_frf_contour(vol, grid, out);
        return 0;
    }
    if (strcmp(kind, "mask") == 0) {
        if (!a || b) return cli_usage_error("grade", "--frf '%s': expected mask:GRID", spec);
        *st = hv_frf_mask(vol, a, out);
        return 0;
    }
    return cli_usage_error("grade", "--frf '%s': unknown feature '%s' (axis, plane, point, segment, contour, mask)",
                           spec, kind);
}

static int split_names(const char *s, char names[][65], int max)
{
    int n = 0;
    const char *p = s;
    while (n < max) {
        const char *c = strchr(p, ',');
        size_t len = c ? (size_t)(c - p) : strlen(p);
        if (len == 0 || len > 64) return -1;
        memcpy(names[n], p, len);
        names[n][len] = '\0';
        ++n;
        if (!c) return n;
        p = c + 1;
    }
    return -1;
}

int cmd_grade(int argc, char **argv)
{
    enum { O_MAT = 256, O_COL, O_PROP, O_FRF, O_RANGES, O_F, O_MS, O_ME, O_BLEND, O_GRID, O_MEM, O_THREADS };
    static const struct option opts[] = {
        {"output", required_argument, NULL, 'o'},     {"materials", required_argument, NULL, O_MAT},
        {"colors", required_argument, NULL, O_COL},   {"property", required_argument, NULL, O_PROP},
        {"frf", required_argument, NULL, O_FRF},      {"ranges", required_argument, NULL, O_RANGES},
        {"f", required_argument, NULL, O_F},          {"ms", required_argument, NULL, O_MS},
        {"me", required_argument, NULL, O_ME},        {"blend", required_argument, NULL, O_BLEND},
        {"grid", required_argument, NULL, O_GRID},    {"max-memory", required_argument, NULL, O_MEM},
        {"threads", required_argument, NULL, O_THREADS}, {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},             {NULL, 0, NULL, 0}};
    const char *output = NULL, *materials = NULL, *colors = NULL, *grid = "occupancy";
    const char *props[64];
    int nprops = 0, quiet = 0, c;
    hv_blend blend = HV_BLEND_NEAREST;
    unsigned long long max_memory = 0;
    group groups[32];
    int ng = 0;
    memset(groups, 0, sizeof groups);
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":o:qh", opts, NULL)) != -1) {
        group *g = ng ? &groups[ng - 1] : NULL;
        long n;
        switch (c) {
        case 'o': output = optarg; break;
        case 'q': quiet = 1; break;
        case 'h': fputs(GRADE_HELP, stdout); return EXIT_OK;
        case O_MAT: materials = optarg; break;
        case O_COL: colors = optarg; break;
        case O_PROP:
            if (nprops == 64) return cli_usage_error("grade", "too many --property options");
            props[nprops++] = optarg;
            break;
        case O_FRF:
            if (ng == 32) return cli_usage_error("grade", "at most 32 grading sources");
            groups[ng++].frf = optarg;
            break;
        case O_RANGES:
        case O_F:
        case O_MS:
        case O_ME:
            if (!g)
                return cli_usage_error("grade", "%s must follow a --frf (it belongs to that source)",
                                       c == O_RANGES ? "--ranges" : c == O_F ? "--f" : c == O_MS ? "--ms" : "--me");
            if (c == O_RANGES) {
                if (g->have_ranges) return cli_usage_error("grade", "source %d: --ranges given twice", ng);
                int k = parse_list("--ranges", optarg, g->ranges, 3);
                if (k < 0) return EXIT_USAGE; /* parse_list said why */
                if (k != 3) return cli_usage_error("grade", "--ranges '%s': expected D-,DG,D+", optarg);
                g->have_ranges = 1;
            } else if (c == O_F) {
                if (g->f) return cli_usage_error("grade", "source %d: --f given twice", ng);
                g->f = optarg;
            } else {
                if (c == O_MS ? g->nms : g->nme)
                    return cli_usage_error("grade", "source %d: %s given twice", ng, c == O_MS ? "--ms" : "--me");
                int k = parse_list(c == O_MS ? "--ms" : "--me", optarg, c == O_MS ? g->ms : g->me, HV_MAX_MATERIALS);
                if (k < 0) return EXIT_USAGE;
                if (c == O_MS) g->nms = k;
                else g->nme = k;
            }
            break;
        case O_BLEND:
            if (strcmp(optarg, "nearest") == 0) blend = HV_BLEND_NEAREST;
            else if (strcmp(optarg, "idw") == 0) blend = HV_BLEND_IDW;
            else return cli_usage_error("grade", "--blend must be nearest or idw (got '%s')", optarg);
            break;
        case O_GRID: grid = optarg; break;
        case O_MEM:
            if (cli_parse_size("grade", "--max-memory", optarg, &max_memory)) return EXIT_USAGE;
            break;
        case O_THREADS:
            if (cli_parse_int("grade", "--threads", optarg, 1, 1024, &n)) return EXIT_USAGE;
            hv_set_threads((int)n);
            break;
        case ':': return cli_usage_error("grade", "option '%s' needs a value", argv[optind - 1]);
        default: return cli_usage_error("grade", "unknown option '%s'", argv[optind - 1]);
        }
    }
    if (optind >= argc) return cli_usage_error("grade", "missing MODEL argument");
    if (argc - optind > 1) return cli_usage_error("grade", "unexpected argument '%s'", argv[optind + 1]);
    if (!output) return cli_usage_error("grade", "missing -o OUT.vdb");
    if (!materials) return cli_usage_error("grade", "missing --materials A,B,...");
    if (ng == 0) return cli_usage_error("grade", "missing --frf (at least one grading source)");
    char names[HV_MAX_MATERIALS][65];
    int m = split_names(materials, names, HV_MAX_MATERIALS);
    if (m < 1) return cli_usage_error("grade", "--materials '%s': expected comma-separated names", materials);
    for (int i = 0; i < ng; ++i) {
        if (!groups[i].have_ranges) return cli_usage_error("grade", "source %d (--frf %s): missing --ranges", i + 1, groups[i].frf);
        if (!groups[i].nms || !groups[i].nme)
            return cli_usage_error("grade", "source %d (--frf %s): missing --ms or --me", i + 1, groups[i].frf);
    }

    /* everything the user typed is checked before the model is read */
    hv_material_table *t = NULL;
    hv_status s = hv_material_table_create(&t);
    for (int j = 0; j < m && s == HV_OK; ++j) s = hv_material_add(t, names[j], NULL, NULL);
    if (s == HV_OK && colors) {
        char cols[HV_MAX_MATERIALS][65];
        int nc = split_names(colors, cols, HV_MAX_MATERIALS);
        if (nc != m) {
            hv_material_table_destroy(t);
            return cli_usage_error("grade", "--colors: %d colours for %d materials", nc < 0 ? 0 : nc, m);
        }
        for (int j = 0; j < m && s == HV_OK; ++j) {
            float rgba[4];
            if ((s = hv_color_parse(cols[j], rgba)) == HV_OK) s = hv_material_set_color(t, j, rgba);
        }
    }
    for (int i = 0; i < nprops && s == HV_OK; ++i) {
        char buf[256];
        snprintf(buf, sizeof buf, "%s", props[i]);
        char *colon = strchr(buf, ':'), *eq = colon ? strchr(colon, '=') : NULL;
        if (!colon || !eq) {
            hv_material_table_destroy(t);
            return cli_usage_error("grade", "--property '%s': expected MATERIAL:KEY=VALUE[:UNIT]", props[i]);
        }
        *colon = '\0';
        *eq = '\0';
        char *colon2 = strchr(eq + 1, ':');
        const char *unit = NULL;
        if (colon2) {
            *colon2 = '\0';
            unit = colon2 + 1;
        }
        int mi = hv_material_find(t, buf);
        if (mi < 0) {
            hv_material_table_destroy(t);
            return cli_usage_error("grade", "--property '%s': no material '%s'", props[i], buf);
        }
        double v;
        if (cli_parse_double("grade", "--property", eq + 1, &v)) {
            hv_material_table_destroy(t);
            return EXIT_USAGE;
        }
        /* as in Lua: a known property without a unit is in its SI unit */
        const char *key = colon + 1;
        if (!unit) unit = hv_property_si_unit(key);
        s = hv_material_set_property(t, mi, key, v, unit);
    }
    for (int i = 0; i < ng && s == HV_OK; ++i) {
        if (groups[i].nms != m || groups[i].nme != m) {
            s = hv_error_set(HV_ERR_INVALID, "source %d: %s has %d values for %d materials", i + 1,
                             groups[i].nms != m ? "Ms" : "Me", groups[i].nms != m ? groups[i].nms : groups[i].nme, m);
            break;
        }
        if ((s = hv_composition_check(groups[i].ms, m, "Ms")) != HV_OK ||
            (s = hv_composition_check(groups[i].me, m, "Me")) != HV_OK)
            s = hv_error_prefix(s, "source %d: ", i + 1);
    }
    if (s != HV_OK) {
        hv_material_table_destroy(t);
        return cli_fail(s);
    }

    hv_volume *vol = NULL, *graded = NULL;
    hv_object *obj = NULL;
    s = hv_volume_load(argv[optind], &vol);
    if (s == HV_OK) s = hv_object_create(vol, grid, m, &obj);
    if (s == HV_OK) s = hv_object_set_blend(obj, blend, 2.0);
    for (int i = 0; i < ng && s == HV_OK; ++i) {
        hv_frf *frf = NULL;
        int rc = make_frf(groups[i].frf, vol, grid, &frf, &s);
        if (rc) {
            hv_object_destroy(obj);
            hv_volume_destroy(vol);
            hv_material_table_destroy(t);
            return rc;
        }
        if (s != HV_OK) break;
        hv_dfn *f = NULL;
        s = hv_dfn_expr(groups[i].f ? groups[i].f : "d/dg", &f);
        if (s == HV_OK) {
            hv_ags_desc d = {frf, groups[i].ranges[0], groups[i].ranges[1], groups[i].ranges[2], f,
                             groups[i].ms, groups[i].me, m, NULL};
            hv_ags *a = NULL;
            s = hv_ags_create(&d, &a);
            if (s == HV_OK) s = hv_object_add_ags(obj, a);
            hv_ags_release(a);
        }
        if (s != HV_OK) hv_error_prefix(s, "source %d (--frf %s): ", i + 1, groups[i].frf);
        hv_dfn_destroy(f);
        hv_frf_release(frf);
    }
    cli_progress bar;
    cli_progress_init(&bar, quiet);
    hv_progress prog = {cli_progress_fn, &bar};
    if (s == HV_OK) s = hv_object_evaluate(obj, t, max_memory, &prog, &graded);
    cli_progress_done(&bar);
    if (s == HV_OK) s = hv_volume_save(graded, output);
    if (s != HV_OK) {
        int rc = cli_fail(s);
        hv_volume_destroy(graded);
        hv_object_destroy(obj);
        hv_volume_destroy(vol);
        hv_material_table_destroy(t);
        return rc;
    }
    if (!quiet) {
        printf("graded      %s: %llu voxels, %d materials, %d source%s\n", argv[optind],
               (unsigned long long)hv_object_voxels(obj), m, ng, ng > 1 ? "s" : "");
        printf("wrote       %s\n", output);
    }
    hv_volume_destroy(graded);
    hv_object_destroy(obj);
    hv_volume_destroy(vol);
    hv_material_table_destroy(t);
    return EXIT_OK;
}
