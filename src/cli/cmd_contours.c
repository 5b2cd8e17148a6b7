/* src/cli/cmd_contours.c - `hovox contours MESH --layer-height H -o OUT.svg|OUT.cli`: the
 * geometric slicer (Wu 2.4.1 weighted directed graph), contours per layer as SVG or CLI. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/internal.h"
#include "core/json.h"
#include "cli.h"
#include "hovox/slice.h"

static const char *CONTOURS_HELP =
    "usage: hovox contours MESH.stl (--layer-height H | --adaptive MIN,MAX[,CUSP])\n"
    "                      [-o OUT.svg|OUT.cli] [--per-layer DIR] [--json] [options]\n"
    "\n"
    "Slice a mesh into closed contour loops per layer with Wu's weighted directed graph:\n"
    "facets are nodes, shared edges arcs; each plane touches only the facets crossing it and\n"
    "the loops come out in order. Layers start at the mesh's lowest z and each layer\n"
    "[bottom, top] is cut at its mid-height; the last layer is the one whose mid-height is\n"
    "below the mesh top. A vertex exactly on a cutting plane counts as above it. Loops are\n"
    "oriented (outer counter-clockwise, holes clockwise, seen from +z) and nested. Units: mm.\n"
    "\n"
    "Layers (one of):\n"
    "  --layer-height H       uniform layers of H mm\n"
    "  --adaptive MIN,MAX[,CUSP]\n"
    "                         adaptive layers between MIN and MAX mm, thinner where the\n"
    "                         surface is nearly horizontal: a facet with normal n allows\n"
    "                         CUSP/|n_z| (cusp-height criterion; CUSP defaults to MIN)\n"
    "  --first-layer H0       height of the first layer (default: as the others)\n"
    "Output (at least one):\n"
    "  -o, --output FILE      .svg: one file, a <g> per layer (data-z = cut height), paths\n"
    "                         with fill-rule evenodd, 1 user unit = 1 mm, y up;\n"
    "                         .cli: Common Layer Interface 2.0, ASCII ($$LAYER/z is the top of\n"
    "                         the layer; a leading zero layer gives the first layer's\n"
    "                         thickness; $$POLYLINE dir 1 outer, 0 hole, 2 open)\n"
    "  --binary               binary CLI instead of ASCII (with a .cli output)\n"
    "  --per-layer DIR        also one SVG per layer: DIR/layer-00000.svg, ... (DIR is created)\n"
    "  --json                 per-layer statistics as JSON on stdout (z, bottom, top, loops,\n"
    "                         outers, holes, open, gaps_closed, area in mm^2)\n"
    "Options:\n"
    "  --close-gap D          join open polyline ends at most D mm apart (default 2);\n"
    "                         chains of an open mesh that still do not close are reported as\n"
    "                         open polylines (CLI dir 2, SVG class \"open\")\n"
    "  --threads N            worker threads (default: all cores)\n"
    "  -q, --quiet            no progress bar\n"
    "  -h, --help             this text\n"
    "\n"
    "Files are written atomically. Without --json a one-line summary goes to stdout.\n";

#define CMD "contours"

typedef struct run {
    hv_contour_writer *writer;
    const char *dir;
    const double *lo, *hi;
    const char *label;
    int json;
    hv_buf *js;
    size_t loops, holes, open, gaps, dropped;
} run;

static hv_status sink(void *user, size_t index, const hv_layer *layer, hv_slice **slice)
{
    run *r = user;
    const hv_slice_stats *st = hv_slice_get_stats(*slice);
    r->loops += st->loops;
    r->holes += st->holes;
    r->open += st->open;
    r->gaps += st->gaps_closed;
    r->dropped += st->dropped;
    if (r->json) {
        json_t *j = json_pack("{s:I, s:o, s:o, s:o, s:I, s:I, s:I, s:I, s:I, s:o}", "index", (json_int_t)index, "z",
                              hv_json_number(layer->z), "bottom", hv_json_number(layer->bottom), "top",
                              hv_json_number(layer->top), "loops", (json_int_t)st->loops, "outers",
                              (json_int_t)st->outers, "holes", (json_int_t)st->holes, "open", (json_int_t)st->open,
                              "gaps_closed", (json_int_t)st->gaps_closed, "area", hv_json_number(st->area));
        char *text = j ? hv_json_dump(j) : NULL;
        json_decref(j);
        hv_buf_printf(r->js, "%s\n  %s", index ? "," : "", text ? text : "");
        if (!text) r->js->failed = 1;
        free(text);
    }
    hv_status s = HV_OK;
    if (r->writer) s = hv_contour_writer_add(r->writer, layer, *slice);
    if (s == HV_OK && r->dir) {
        char path[4096];
        int n = snprintf(path, sizeof path, "%s/layer-%05zu.svg", r->dir, index);
        if (n < 0 || (size_t)n >= sizeof path)
            return hv_error_set(HV_ERR_IO, "%s: directory name too long", r->dir);
        hv_contour_writer *w = NULL;
        s = hv_contour_writer_open(path, HV_CONTOUR_SVG, 1, r->lo, r->hi, r->label, &w);
        if (s == HV_OK) s = hv_contour_writer_add(w, layer, *slice);
        if (s == HV_OK) s = hv_contour_writer_close(w);
        else hv_contour_writer_abort(w);
    }
    return s;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcasecmp(s + n - k, suffix) == 0;
}

int cmd_contours(int argc, char **argv)
{
    enum { O_LH = 256, O_FIRST, O_ADAPT, O_BIN, O_PER, O_JSON, O_GAP, O_THREADS };
    static const struct option opts[] = {
        {"layer-height", required_argument, NULL, O_LH}, {"first-layer", required_argument, NULL, O_FIRST},
        {"adaptive", required_argument, NULL, O_ADAPT},  {"output", required_argument, NULL, 'o'},
        {"binary", no_argument, NULL, O_BIN},            {"per-layer", required_argument, NULL, O_PER},
        {"json", no_argument, NULL, O_JSON},             {"close-gap", required_argument, NULL, O_GAP},
        {"threads", required_argument, NULL, O_THREADS}, {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},                {NULL, 0, NULL, 0}};
    double lh = 0, first = 0, ad[3] = {0, 0, 0};
    int have_lh = 0, have_ad = 0, binary = 0, json = 0, quiet = 0, c;
    const char *output = NULL, *dir = NULL;
    hv_slice_options sopt;
    hv_slice_options_init(&sopt);
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":o:qh", opts, NULL)) != -1) {
        long n;
        switch (c) {
        case 'o': output = optarg; break;
        case 'q': quiet = 1; break;
        case 'h': fputs(CONTOURS_HELP, stdout); return EXIT_OK;
        case O_LH:
            if (cli_parse_double(CMD, "--layer-height", optarg, &lh)) return EXIT_USAGE;
            if (!(lh > 0)) return cli_usage_error(CMD, "--layer-height: %g must be > 0", lh);
            have_lh = 1;
            break;
        case O_FIRST:
            if (cli_parse_double(CMD, "--first-layer", optarg, &first)) return EXIT_USAGE;
            if (!(first > 0)) return cli_usage_error(CMD, "--first-layer: %g must be > 0", first);
            break;
        case O_ADAPT: {
            int k = 1;
            for (const char *p = optarg; *p; ++p) k += *p == ',';
            if (k != 2 && k != 3)
                return cli_usage_error(CMD, "--adaptive: '%s' is not MIN,MAX or MIN,MAX,CUSP", optarg);
            if (cli_parse_vec(CMD, "--adaptive", optarg, k, ad)) return EXIT_USAGE;
            if (!(ad[0] > 0) || !(ad[0] <= ad[1]) || (k == 3 && !(ad[2] > 0)))
                return cli_usage_error(CMD, "--adaptive: need 0 < MIN <= MAX and CUSP > 0 ('%s')",
                                       optarg);
            have_ad = 1;
            break;
        }
        case O_BIN: binary = 1; break;
        case O_PER: dir = optarg; break;
        case O_JSON: json = 1; break;
        case O_GAP:
            if (cli_parse_double(CMD, "--close-gap", optarg, &sopt.close_gap)) return EXIT_USAGE;
            if (sopt.close_gap < 0)
                return cli_usage_error(CMD, "--close-gap: %g must be >= 0", sopt.close_gap);
            break;
        case O_THREADS:
            if (cli_parse_int(CMD, "--threads", optarg, 1, 1024, &n)) return EXIT_USAGE;
            hv_set_threads((int)n);
            break;
        case ':': return cli_usage_error(CMD, "option '%s' needs a value", argv[optind - 1]);
        default: return cli_usage_error(CMD, "unknown option '%s'", argv[optind - 1]);
        }
    }
    if (optind >= argc) return cli_usage_error(CMD, "missing MESH");
    if (optind + 1 < argc) return cli_usage_error(CMD, "unexpected argument '%s'", argv[optind + 1]);
    const char *mesh_path = argv[optind];
    if (have_lh && have_ad) return cli_usage_error(CMD, "--layer-height and --adaptive exclude each other");
    if (!have_lh && !have_ad) return cli_usage_error(CMD, "missing --layer-height H (or --adaptive MIN,MAX)");
    hv_contour_format fmt = HV_CONTOUR_SVG;
    if (output) {
        if (ends_with(output, ".svg")) fmt = HV_CONTOUR_SVG;
        else if (ends_with(output, ".cli")) fmt = binary ? HV_CONTOUR_CLI_BINARY : HV_CONTOUR_CLI_ASCII;
        else return cli_usage_error(CMD, "-o: '%s': unknown extension (use .svg or .cli)", output);
    }
    if (binary && fmt != HV_CONTOUR_CLI_BINARY) return cli_usage_error(CMD, "--binary needs a .cli output");
    if (!output && !dir && !json)
        return cli_usage_error(CMD, "nothing to write: give -o OUT.svg|OUT.cli, --per-layer DIR or --json");

    cli_progress bar;
    cli_progress_init(&bar, quiet);
    hv_progress prog = {cli_progress_fn, &bar};
    hv_mesh *mesh = NULL;
    hv_slicer *slicer = NULL;
    hv_layer_plan *plan = NULL;
    hv_contour_writer *writer = NULL;
    hv_buf js;
    hv_buf_init(&js);
    int rc = EXIT_OK;
    hv_status s = hv_mesh_load_stl(mesh_path, &mesh);
    if (s == HV_OK) s = hv_slicer_create(mesh, &prog, &slicer);
    hv_mesh_destroy(mesh);
    if (s == HV_OK) {
        s = have_ad ? hv_slicer_plan_adaptive(slicer, first, ad[0], ad[1], ad[2], &plan)
                    : hv_slicer_plan_uniform(slicer, first, lh, &plan);
        if (s != HV_OK) hv_error_prefix(s, "%s: ", mesh_path);
    }
    hv_slicer_info info;
    memset(&info, 0, sizeof info);
    if (s == HV_OK) hv_slicer_get_info(slicer, &info);
    if (s == HV_OK && hv_layer_plan_count(plan) == 0)
        s = hv_error_set(HV_ERR_INVALID, "%s: the mesh is %g mm high: no layer of %g mm has its middle inside it",
                         mesh_path, info.bbox_max[2] - info.bbox_min[2], have_ad ? ad[0] : lh);
    const char *label = hv_basename(mesh_path);
    if (s == HV_OK && output)
        s = hv_contour_writer_open(output, fmt, hv_layer_plan_count(plan), info.bbox_min,
                                   info.bbox_max, label, &writer);
    /* per-layer SVGs go to a temporary directory renamed into place when complete; an
     * existing DIR is replaced when it holds only layer SVGs (an earlier run's) */
    static const char *const svg_files[] = {"layer-*.svg", NULL};
    static const hv_outdir_rules svg_dir = {"per-layer SVG directory", NULL, NULL, svg_files, 0, 0, NULL};
    char *tmpdir = NULL;
    if (s == HV_OK && dir) s = hv_outdir_begin(dir, &svg_dir, 0, &tmpdir);
    run r = {writer, tmpdir, info.bbox_min, info.bbox_max, label, json, &js, 0, 0, 0, 0, 0};
    if (s == HV_OK) s = hv_slicer_slice_plan(slicer, plan, &sopt, sink, &r, &prog);
    cli_progress_done(&bar);
    if (s == HV_OK) {
        s = hv_contour_writer_close(writer);
    } else {
        hv_contour_writer_abort(writer);
    }
    if (s == HV_OK && tmpdir) s = hv_outdir_commit(tmpdir, dir, &svg_dir, 0);
    if (s != HV_OK && tmpdir) hv_outdir_abort(tmpdir);
    free(tmpdir);
    if (s != HV_OK) {
        rc = cli_fail(s);
    } else if (json) {
        json_t *j = json_pack("{s:o, s:s}", "file", hv_json_text(mesh_path), "mode", have_ad ? "adaptive" : "uniform");
        int bad = !j;
        if (have_ad)
            bad |= json_object_update_new(j, json_pack("{s:o, s:o, s:o}", "min", hv_json_number(ad[0]), "max",
                                                       hv_json_number(ad[1]), "cusp",
                                                       hv_json_number(ad[2] > 0 ? ad[2] : ad[0])));
        else
            bad |= json_object_update_new(j, json_pack("{s:o}", "layer_height", hv_json_number(lh)));
        bad |= json_object_update_new(j, json_pack("{s:o, s:o, s:I, s:I, s:I, s:I, s:I, s:I}", "first_layer",
                                                   hv_json_number(first > 0 ? first : have_ad ? 0 : lh), "close_gap",
                                                   hv_json_number(sopt.close_gap), "count",
                                                   (json_int_t)hv_layer_plan_count(plan), "loops", (json_int_t)r.loops,
                                                   "holes", (json_int_t)r.holes, "open", (json_int_t)r.open,
                                                   "gaps_closed", (json_int_t)r.gaps, "dropped", (json_int_t)r.dropped));
        char *head = bad ? NULL : hv_json_dump(j);
        json_decref(j);
        hv_buf b;
        hv_buf_init(&b);
        /* the summary's members, then the layers one per line (the closing brace moves) */
        if (head) hv_buf_append(&b, head, strlen(head) - 1);
        else b.failed = 1;
        free(head);
        hv_buf_puts(&b, ",\n \"layers\": [");
        if (js.data) hv_buf_puts(&b, js.data);
        hv_buf_puts(&b, "\n ]}\n");
        if (b.failed || js.failed) rc = cli_fail(hv_error_set(HV_ERR_NOMEM, "out of memory"));
        else fputs(b.data, stdout);
        hv_buf_free(&b);
    } else {
        printf("%s: %zu layers, %zu loops (%zu holes), %zu open polylines, %zu gaps closed\n",
               mesh_path, hv_layer_plan_count(plan), r.loops, r.holes, r.open, r.gaps);
    }
    hv_buf_free(&js);
    hv_layer_plan_destroy(plan);
    hv_slicer_destroy(slicer);
    return rc;
}
