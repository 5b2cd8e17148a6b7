/* src/cli/cmd_layers.c - `hovox layers MODEL.vdb --mesh MESH.stl -o DIR`: printer slice stacks
 * (Wu 2.4.2): contour-constrained material layers at printer resolution, halftoned or as
 * fractions or masks, PNG layers with manifest.json, optionally a GCVF zip. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/internal.h"
#include "cli.h"
#include "hovox/layers.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"

static const char *LAYERS_HELP =
    "usage: hovox layers MODEL.vdb --mesh MESH.stl -o DIR [options]\n"
    "       hovox layers --mesh MESH.stl -o DIR --mode mask [options]\n"
    "\n"
    "Printer slice stacks after Wu 2.4.2. Layers of the printer's height start at the mesh's\n"
    "lowest z; each is cut at its mid-height z. Per layer the mesh's contour (WDG slicer) is\n"
    "rasterised at printer resolution by pixel centres (nonzero winding rule): that decides\n"
    "object and background, as sharp as the contour. Inside, the material comes from the\n"
    "graded model: the two voxel layers around z interpolated in z over occupied voxels,\n"
    "extended outwards to pixels the voxels miss, then resampled to printer pixels by pixel\n"
    "overlap interpolation (exact area weights, in steps of at most --poi-step) -- or, with\n"
    "--method direct, the grading definition evaluated at every pixel centre.\n"
    "\n"
    "Printer (default j750):\n"
    "  --profile NAME         j750: Stratasys J750 voxel printing, 600 x 300 dpi, 0.027 mm\n"
    "                         j850: Stratasys J850 (High Mix), 600 x 300 dpi, 0.027 mm\n"
    "  --dpi X,Y              a generic printer: dpi along x and y (with --layer-height)\n"
    "  --layer-height H       layer height in mm (with --dpi, or overriding the profile's)\n"
    "Output:\n"
    "  -o, --output DIR       the stack directory (written under a temporary name and renamed\n"
    "                         when complete; must not exist, or be empty)\n"
    "  --mode M               halftone (default): indexed PNG, palette 0 = background, j = the\n"
    "                         j-th material, smallest bit depth that holds the palette;\n"
    "                         fractions: 8-bit grey PNG per material (DIR/<material>/), 255 = 1;\n"
    "                         mask: 1-bit PNG, 1 = object (no model needed)\n"
    "  --method M             resample (default) or direct (also reports the difference)\n"
    "  --compare              with resample: also evaluate direct and report the difference\n"
    "  --halftone H           bluenoise (default): a 64x64x32 void-and-cluster threshold mask,\n"
    "                         cached in $XDG_CACHE_HOME/hovox (or ~/.cache/hovox);\n"
    "                         error: vector error diffusion, serpentine, 1/4 of the error\n"
    "                         carried to the next layer, restarted every 32 layers\n"
    "  --seed N               halftone seed (mask offset, diffusion start noise; default 0)\n"
    "  --layers A:B           only layers A to B-1 of the full plan (A: or :B allowed); file\n"
    "                         names keep the global index, so split runs give the same files\n"
    "  --background COLOR     halftone palette entry 0 (#rrggbb; default #000000)\n"
    "  --gcvf FILE.zip        also a GrabCAD voxel-print style zip: ConfigFile.xml and\n"
    "                         layer_<index>.png (halftone or mask mode)\n"
    "  --force                replace an existing stack (a directory with a hovox manifest)\n"
    "Geometry:\n"
    "  --mesh FILE            the mesh the model was made from (required)\n"
    "  --fill-rule R          nonzero (default) or evenodd\n"
    "  --threshold D          Wu's threshold: pixels outside the contour but within D mm of it\n"
    "                         stay object (default 0)\n"
    "  --margin N             background pixels around the mesh's xy box (default 2)\n"
    "  --close-gap D          join open contour ends at most D mm apart (default 2)\n"
    "Other:\n"
    "  --poi-step R           largest up-sampling ratio of one POI step (default 1.5; 1: one\n"
    "                         exact step)\n"
    "  --compression L        PNG zlib level 0..9 (default 1)\n"
    "  --max-memory SIZE      refuse jobs that would need more (default half of RAM)\n"
    "  --dry-run              print the plan (image size, layers, memory) and stop\n"
    "  --threads N, -q/--quiet, -h/--help\n"
    "\n"
    "DIR/manifest.json: profile, dpi, layer height, materials with palette colours, pixel_mm\n"
    "[sx, sy] and origin_mm [x0, y0] (pixel column c, row r has its centre at x0 + (c+0.5) sx,\n"
    "y0 + (r+0.5) sy; sy < 0: rows run down in y), and layers [{index, file, z_mm}] with z_mm\n"
    "the height of the cutting plane.\n";

#define CMD "layers"

static int parse_range(const char *s, size_t *a, size_t *b)
{
    const char *colon = strchr(s, ':');
    if (!colon) return cli_usage_error(CMD, "--layers: '%s' is not A:B", s);
    char *end;
    *a = 0;
    *b = 0;
    if (colon != s) {
        unsigned long long v = strtoull(s, &end, 10);
        if (end != colon || *s == '-') return cli_usage_error(CMD, "--layers: '%s' is not A:B", s);
        *a = (size_t)v;
    }
    if (colon[1]) {
        unsigned long long v = strtoull(colon + 1, &end, 10);
        if (*end || colon[1] == '-') return cli_usage_error(CMD, "--layers: '%s' is not A:B", s);
        if (v == 0) return cli_usage_error(CMD, "--layers: '%s' is an empty range", s);
        *b = (size_t)v;
    }
    if (*b && *a >= *b) return cli_usage_error(CMD, "--layers: '%s' is an empty range", s);
    return 0;
}

static int parse_choice(const char *opt, const char *s, const char *const *names, int n, int *out)
{
    for (int i = 0; i < n; ++i)
        if (strcmp(s, names[i]) == 0) {
            *out = i;
            return 0;
        }
    hv_buf b;
    hv_buf_init(&b);
    for (int i = 0; i < n; ++i) hv_buf_printf(&b, "%s%s", i ? ", " : "", names[i]);
    int rc = cli_usage_error(CMD, "%s: '%s' is not one of %s", opt, s, b.data ? b.data : "");
    hv_buf_free(&b);
    return rc;
}

static void print_plan(const hv_layers_report *r, const hv_layers_options *o)
{
    printf("printer     %s: %g x %g dpi, %g mm layers\n", o->profile ? o->profile : "custom", o->dpi[0], o->dpi[1],
           o->layer_height);
    printf("image       %d x %d pixels of %.6g x %.6g mm, origin (%.6g, %.6g), %d-bit\n", r->width, r->height,
           r->pixel_mm[0], -r->pixel_mm[1], r->origin_mm[0], r->origin_mm[1], r->bit_depth);
    printf("layers      %zu to %zu of %zu\n", r->first, r->last - 1, r->layers_total);
    printf("memory      about %.1f MiB (%d workers)\n", (double)r->memory_bytes / 1048576.0, r->threads);
}

/* The voxelizer records the mesh it was given (hovox.mesh.json): a --mesh whose box differs
 * from that one by more than a voxel is probably not the model's mesh. A warning, not an
 * error: a repaired or re-exported mesh of the same part is fine. */
static void warn_other_mesh(const char *mesh_path, const hv_mesh *mesh, const char *model_path,
                            const hv_volume *model)
{
    hv_voxelize_record rec;
    if (hv_voxelize_record_read(model, &rec) != HV_OK) return;
    const hv_mesh_report *r = hv_mesh_get_report(mesh);
    const double *lo = rec.mesh.bbox_min, *hi = rec.mesh.bbox_max;
    hv_transform xf = hv_volume_get_transform(model);
    double tol = HV_MAX(xf.voxel[0], HV_MAX(xf.voxel[1], xf.voxel[2]));
    int differs = 0;
    for (int a = 0; a < 3; ++a) differs |= fabs(lo[a] - r->bbox_min[a]) > tol || fabs(hi[a] - r->bbox_max[a]) > tol;
    if (differs)
        fprintf(stderr,
                "hovox: warning: %s spans (%g, %g, %g)-(%g, %g, %g), but %s was voxelized from a mesh "
                "spanning (%g, %g, %g)-(%g, %g, %g): is this its mesh?\n",
                mesh_path, r->bbox_min[0], r->bbox_min[1], r->bbox_min[2], r->bbox_max[0], r->bbox_max[1],
                r->bbox_max[2], model_path, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
}

int cmd_layers(int argc, char **argv)
{
    enum {
        O_MESH = 256, O_PROFILE, O_DPI, O_LH, O_MODE, O_METHOD, O_COMPARE, O_HALFTONE, O_SEED, O_LAYERS,
        O_BG, O_GCVF, O_FORCE, O_FILL, O_THRESH, O_MARGIN, O_GAP, O_STEP, O_COMP, O_MEM, O_DRY, O_THREADS
    };
    static const struct option opts[] = {
        {"mesh", required_argument, NULL, O_MESH},         {"profile", required_argument, NULL, O_PROFILE},
        {"dpi", required_argument, NULL, O_DPI},           {"layer-height", required_argument, NULL, O_LH},
        {"output", required_argument, NULL, 'o'},          {"mode", required_argument, NULL, O_MODE},
        {"method", required_argument, NULL, O_METHOD},     {"compare", no_argument, NULL, O_COMPARE},
        {"halftone", required_argument, NULL, O_HALFTONE}, {"seed", required_argument, NULL, O_SEED},
        {"layers", required_argument, NULL, O_LAYERS},     {"background", required_argument, NULL, O_BG},
        {"gcvf", required_argument, NULL, O_GCVF},         {"force", no_argument, NULL, O_FORCE},
        {"fill-rule", required_argument, NULL, O_FILL},    {"threshold", required_argument, NULL, O_THRESH},
        {"margin", required_argument, NULL, O_MARGIN},     {"close-gap", required_argument, NULL, O_GAP},
        {"poi-step", required_argument, NULL, O_STEP},     {"compression", required_argument, NULL, O_COMP},
        {"max-memory", required_argument, NULL, O_MEM},    {"dry-run", no_argument, NULL, O_DRY},
        {"threads", required_argument, NULL, O_THREADS},   {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},                  {NULL, 0, NULL, 0}};
    static const char *const modes[] = {"halftone", "fractions", "mask"};
    static const char *const methods[] = {"resample", "direct"};
    static const char *const halftones[] = {"bluenoise", "error"};
    static const char *const rules[] = {"nonzero", "evenodd"};
    hv_layers_options o;
    hv_layers_options_init(&o);
    const char *mesh_path = NULL, *out = NULL, *profile = NULL;
    int have_dpi = 0, have_lh = 0, have_bg = 0, quiet = 0, dry = 0, c, choice;
    double dpi[2] = {0, 0}, lh = 0;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":o:qh", opts, NULL)) != -1) {
        long n;
        switch (c) {
        case 'o': out = optarg; break;
        case 'q': quiet = 1; break;
        case 'h': fputs(LAYERS_HELP, stdout); return EXIT_OK;
        case O_MESH: mesh_path = optarg; break;
        case O_PROFILE:
            if (!hv_printer_profile_find(optarg))
                return cli_usage_error(CMD, "--profile: unknown printer '%s' (j750, j850, or --dpi X,Y --layer-height H)",
                                       optarg);
            profile = optarg;
            break;
        case O_DPI:
            if (cli_parse_vec(CMD, "--dpi", optarg, 2, dpi)) return EXIT_USAGE;
            if (!(dpi[0] >= 1 && dpi[0] <= 1e6 && dpi[1] >= 1 && dpi[1] <= 1e6))
                return cli_usage_error(CMD, "--dpi: '%s' out of range (1 to 1000000 each)", optarg);
            have_dpi = 1;
            break;
        case O_LH:
            if (cli_parse_double(CMD, "--layer-height", optarg, &lh)) return EXIT_USAGE;
            if (!(lh >= 1e-6 && lh <= 1000))
                return cli_usage_error(CMD, "--layer-height: %g mm out of range (1e-6 to 1000)", lh);
            have_lh = 1;
            break;
        case O_MODE:
            if (parse_choice("--mode", optarg, modes, 3, &choice)) return EXIT_USAGE;
            o.mode = (hv_layers_mode)choice;
            break;
        case O_METHOD:
            if (parse_choice("--method", optarg, methods, 2, &choice)) return EXIT_USAGE;
            o.method = (hv_layers_method)choice;
            break;
        case O_COMPARE: o.compare = 1; break;
        case O_HALFTONE:
            if (parse_choice("--halftone", optarg, halftones, 2, &choice)) return EXIT_USAGE;
            o.halftone = (hv_halftone_method)choice;
            break;
        case O_SEED: {
            char *end;
            if (!*optarg || *optarg == '-') return cli_usage_error(CMD, "--seed: '%s' is not a non-negative integer", optarg);
            unsigned long long v = strtoull(optarg, &end, 10);
            if (*end) return cli_usage_error(CMD, "--seed: '%s' is not a non-negative integer", optarg);
            o.seed = v;
            break;
        }
        case O_LAYERS:
            if (parse_range(optarg, &o.first, &o.last)) return EXIT_USAGE;
            break;
        case O_BG: {
            float rgba[4];
            if (hv_color_parse(optarg, rgba) != HV_OK)
                return cli_usage_error(CMD, "--background: '%s' is not a colour (#rrggbb)", optarg);
            for (int k = 0; k < 3; ++k) o.background[k] = (uint8_t)(rgba[k] * 255.0f + 0.5f);
            have_bg = 1;
            break;
        }
        case O_GCVF: o.gcvf_path = optarg; break;
        case O_FORCE: o.force = 1; break;
        case O_FILL:
            if (parse_choice("--fill-rule", optarg, rules, 2, &choice)) return EXIT_USAGE;
            o.fill_rule = (hv_fill_rule)choice;
            break;
        case O_THRESH:
            if (cli_parse_double(CMD, "--threshold", optarg, &o.threshold)) return EXIT_USAGE;
            if (!(o.threshold >= 0 && o.threshold <= 1000))
                return cli_usage_error(CMD, "--threshold: %g mm out of range (0 to 1000)", o.threshold);
            break;
        case O_MARGIN:
            if (cli_parse_int(CMD, "--margin", optarg, 0, 100000, &n)) return EXIT_USAGE;
            o.margin = (int)n;
            break;
        case O_GAP:
            if (cli_parse_double(CMD, "--close-gap", optarg, &o.close_gap)) return EXIT_USAGE;
            if (o.close_gap < 0) return cli_usage_error(CMD, "--close-gap: %g must be >= 0", o.close_gap);
            break;
        case O_STEP:
            if (cli_parse_double(CMD, "--poi-step", optarg, &o.poi_step)) return EXIT_USAGE;
            if (!(o.poi_step >= 1 && o.poi_step <= 1e6))
                return cli_usage_error(CMD, "--poi-step: %g out of range (1 to 1000000)", o.poi_step);
            break;
        case O_COMP:
            if (cli_parse_int(CMD, "--compression", optarg, 0, 9, &n)) return EXIT_USAGE;
            o.compression = (int)n;
            break;
        case O_MEM: {
            unsigned long long v;
            if (cli_parse_size(CMD, "--max-memory", optarg, &v)) return EXIT_USAGE;
            o.max_memory = v;
            break;
        }
        case O_DRY: dry = 1; break;
        case O_THREADS:
            if (cli_parse_int(CMD, "--threads", optarg, 1, 1024, &n)) return EXIT_USAGE;
            hv_set_threads((int)n);
            break;
        case ':': return cli_usage_error(CMD, "option '%s' needs a value", argv[optind - 1]);
        default: return cli_usage_error(CMD, "unknown option '%s'", argv[optind - 1]);
        }
    }
    const char *model_path = NULL;
    if (optind < argc) model_path = argv[optind++];
    if (optind < argc) return cli_usage_error(CMD, "unexpected argument '%s'", argv[optind]);
    if (!mesh_path) return cli_usage_error(CMD, "missing --mesh MESH.stl");
    if (!out && !dry) return cli_usage_error(CMD, "missing -o DIR");
    if (!model_path && o.mode != HV_LAYERS_MASK)
        return cli_usage_error(CMD, "missing MODEL.vdb (only --mode mask works from the mesh alone)");
    if (profile && have_dpi) return cli_usage_error(CMD, "--profile and --dpi exclude each other");
    if (have_dpi && !have_lh) return cli_usage_error(CMD, "--dpi needs --layer-height");
    if (o.mode != HV_LAYERS_HALFTONE && (o.seed || o.halftone != HV_HALFTONE_BLUE_NOISE))
        return cli_usage_error(CMD, "--seed and --halftone apply to --mode halftone");
    if (o.mode == HV_LAYERS_MASK && (o.method != HV_LAYERS_RESAMPLE || o.compare))
        return cli_usage_error(CMD, "--method and --compare need a material mode (halftone or fractions)");
    if (o.gcvf_path && o.mode == HV_LAYERS_FRACTIONS)
        return cli_usage_error(CMD, "--gcvf needs --mode halftone or mask");
    if (have_bg && o.mode != HV_LAYERS_HALFTONE)
        return cli_usage_error(CMD, "--background is the halftone palette's entry 0: it needs --mode halftone");
    if (have_dpi) {
        o.profile = "custom";
        o.dpi[0] = dpi[0];
        o.dpi[1] = dpi[1];
        o.layer_height = lh;
    } else {
        const hv_printer_profile *p = hv_printer_profile_find(profile ? profile : "j750");
        o.profile = p->name;
        o.dpi[0] = p->dpi[0];
        o.dpi[1] = p->dpi[1];
        o.layer_height = have_lh ? lh : p->layer_height;
    }
    o.mesh_name = mesh_path;
    o.model_name = model_path;

    cli_progress bar;
    cli_progress_init(&bar, quiet);
    hv_progress prog = {cli_progress_fn, &bar};
    hv_mesh *mesh = NULL;
    hv_volume *model = NULL;
    hv_status s = hv_mesh_load_stl(mesh_path, &mesh);
    if (s != HV_OK) return cli_fail(s);
    if (model_path && o.mode != HV_LAYERS_MASK) {
        s = hv_volume_load(model_path, &model);
        if (s != HV_OK) {
            hv_mesh_destroy(mesh);
            return cli_fail(s);
        }
    }
    if (model) warn_other_mesh(mesh_path, mesh, model_path, model);
    hv_layers_report r;
    s = hv_layers_plan(mesh, model, &o, &r);
    if (s != HV_OK) {
        if (s == HV_ERR_BAD_INPUT && model_path) hv_error_prefix(s, "%s: ", model_path);
        else if (s == HV_ERR_INVALID && strncmp(hv_last_error(), "layers: the mesh", 16) == 0)
            hv_error_prefix(s, "%s: ", mesh_path);
        int rc = cli_fail(s);
        hv_volume_destroy(model);
        hv_mesh_destroy(mesh);
        return rc;
    }
    if (dry) {
        print_plan(&r, &o);
        hv_volume_destroy(model);
        hv_mesh_destroy(mesh);
        return EXIT_OK;
    }
    s = hv_layers_write(mesh, model, out, &o, &prog, &r);
    cli_progress_done(&bar);
    int rc = EXIT_OK;
    if (s != HV_OK) {
        if (s == HV_ERR_BAD_INPUT && model_path) hv_error_prefix(s, "%s: ", model_path);
        rc = cli_fail(s);
    } else {
        printf("mesh        %s (%zu facets)\n", mesh_path, hv_mesh_facet_count(mesh));
        if (model) {
            hv_material_table *t = NULL;
            if (hv_material_table_load(model, &t) == HV_OK) {
                printf("model       %s (%d materials)\n", model_path, hv_material_count(t));
                hv_material_table_destroy(t);
            }
        }
        print_plan(&r, &o);
        if (o.mode != HV_LAYERS_MASK) {
            printf("material    target    %s\n", o.mode == HV_LAYERS_HALFTONE ? "achieved" : "");
            hv_material_table *t = NULL;
            if (hv_material_table_load(model, &t) == HV_OK) {
                for (int j = 0; j < r.materials; ++j) {
                    printf("  %-9s %.6f", hv_material_name(t, j), r.target[j]);
                    if (o.mode == HV_LAYERS_HALFTONE) printf("  %.6f", r.achieved[j]);
                    printf("\n");
                }
                hv_material_table_destroy(t);
            }
        }
        if (r.compared)
            printf("compare     resample vs direct: mean %.6f, max %.6f (max over materials per pixel; %llu pixels "
                   "outside the definition)\n",
                   r.diff_mean, r.diff_max, (unsigned long long)r.direct_fallback);
        if (r.open_polylines)
            fprintf(stderr, "hovox: warning: %s is open: %zu contour polylines stayed open and were not filled "
                            "(--close-gap %g; a larger gap joins wider holes)\n",
                    mesh_path, r.open_polylines, o.close_gap);
        printf("wrote       %s (%zu layers, %llu object pixels, %s%s%s)\n", out, r.last - r.first,
               (unsigned long long)r.object_pixels,
               o.mode == HV_LAYERS_HALFTONE ? (o.halftone == HV_HALFTONE_BLUE_NOISE ? "halftone blue-noise"
                                                                                   : "halftone error-diffusion")
               : o.mode == HV_LAYERS_FRACTIONS ? "fractions" : "mask",
               o.gcvf_path ? ", " : "", o.gcvf_path ? o.gcvf_path : "");
    }
    hv_volume_destroy(model);
    hv_mesh_destroy(mesh);
    return rc;
}
