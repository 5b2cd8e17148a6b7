/* src/cli/cmd_contours.c - `hovox contours MESH --layer-height H -o OUT.svg|OUT.cli`: the
 * geometric slicer (Wu 2.4.1 weighted directed graph), contours per layer as SVG or CLI. The
 * options are the library's (hv_contours_option_set). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "cli.h"
#include "core/internal.h"
#include "core/json.h"
#include "hovox/slice.h"

typedef struct contours_cli {
    const char *output, *per_layer;
    int json;
} contours_cli;

static hv_status check_contour_path(const hv_option *o, const void *opts)
{
    hv_contour_format f;
    return hv_contour_format_for_path(*(const char *const *)((const char *)opts + o->offset), 0, &f);
}

static const hv_option k_local_opts[] = {
    {.key = "output", .kind = HV_OPT_STRING, .flags = HV_OPT_OUT_PATH, .offset = offsetof(contours_cli, output),
     .meta = "FILE", .check = check_contour_path, .section = "Output (at least one)",
     .help = ".svg: one file, a <g> per layer (data-z = cut height), 1 user unit = 1 mm, y up; .cli: Common Layer "
             "Interface 2.0, ASCII ($$LAYER/z is the top of the layer; a leading zero layer gives the first "
             "layer's thickness; $$POLYLINE dir 1 outer, 0 hole, 2 open)"},
    {.key = "per_layer", .kind = HV_OPT_STRING, .offset = offsetof(contours_cli, per_layer), .meta = "DIR",
     .help = "also one SVG per layer: DIR/layer-00000.svg, ..."},
    {.key = "json", .kind = HV_OPT_FLAG, .offset = offsetof(contours_cli, json),
     .help = "per-layer statistics as JSON on stdout (z, bottom, top, loops, outers, holes, open, gaps_closed, area "
             "in mm^2)"},
};
static const hv_option_set k_local = CLI_LOCAL_SET("contours", k_local_opts, contours_cli);


typedef struct run {
    hv_contour_writer *writer;
    const char *dir;
    const double *lo, *hi;
    const char *label;
    hv_buf *js;
    size_t loops, holes, open, gaps, dropped;
} run;

static hv_status layer_json(hv_buf *b, size_t index, const hv_layer *layer, const hv_slice_stats *st)
{
    json_t *j = json_pack("{s:I, s:o, s:o, s:o, s:I, s:I, s:I, s:I, s:I, s:o}", "index", (json_int_t)index, "z",
                          hv_json_number(layer->z), "bottom", hv_json_number(layer->bottom), "top",
                          hv_json_number(layer->top), "loops", (json_int_t)st->loops, "outers", (json_int_t)st->outers,
                          "holes", (json_int_t)st->holes, "open", (json_int_t)st->open, "gaps_closed",
                          (json_int_t)st->gaps_closed, "area", hv_json_number(st->area));
    char *text = j ? hv_json_dump(j) : NULL;
    json_decref(j);
    hv_buf_printf(b, "%s\n  %s", index ? "," : "", text ? text : "");
    free(text);
    return !text || b->failed ? hv_error_set(HV_ERR_NOMEM, "out of memory") : HV_OK;
}

static hv_status one_svg(const run *r, size_t index, const hv_layer *layer, const hv_slice *slice)
{
    char path[4096];
    int n = snprintf(path, sizeof path, "%s/layer-%05zu.svg", r->dir, index);
    if (n < 0 || (size_t)n >= sizeof path) return hv_error_set(HV_ERR_IO, "%s: directory name too long", r->dir);
    hv_contour_writer *w = NULL;
    hv_status s = hv_contour_writer_open(path, HV_CONTOUR_SVG, 1, r->lo, r->hi, r->label, &w);
    if (s == HV_OK) s = hv_contour_writer_add(w, layer, slice);
    if (s == HV_OK) s = hv_contour_writer_close(w);
    else hv_contour_writer_abort(w);
    return s;
}

static hv_status sink(void *user, size_t index, const hv_layer *layer, hv_slice **slice)
{
    run *r = user;
    const hv_slice_stats *st = hv_slice_get_stats(*slice);
    r->loops += st->loops;
    r->holes += st->holes;
    r->open += st->open;
    r->gaps += st->gaps_closed;
    r->dropped += st->dropped;
    hv_status s = r->js ? layer_json(r->js, index, layer, st) : HV_OK;
    if (s == HV_OK && r->writer) s = hv_contour_writer_add(r->writer, layer, *slice);
    if (s == HV_OK && r->dir) s = one_svg(r, index, layer, *slice);
    return s;
}

static int report(const char *mesh_path, const hv_contours_options *o, const contours_cli *c, const hv_layer_plan *plan,
                   const run *r)
{
    if (!c->json) {
        printf("%s: %zu layers, %zu loops (%zu holes), %zu open polylines, %zu gaps closed\n", mesh_path,
               hv_layer_plan_count(plan), r->loops, r->holes, r->open, r->gaps);
        return EXIT_OK;
    }
    cli_json j;
    cli_json_begin(&j);
    cli_json_str(&j, "file", mesh_path);
    if (o->adaptive[0] > 0) {
        cli_json_str(&j, "mode", "adaptive");
        cli_json_num(&j, "min", o->adaptive[0]);
        cli_json_num(&j, "max", o->adaptive[1]);
        cli_json_num(&j, "cusp", o->adaptive[2] > 0 ? o->adaptive[2] : o->adaptive[0]);
    } else {
        cli_json_str(&j, "mode", "uniform");
        cli_json_num(&j, "layer_height", o->layer_height);
    }
    cli_json_num(&j, "first_layer", o->first_layer > 0 ? o->first_layer : o->adaptive[0] > 0 ? 0 : o->layer_height);
    cli_json_num(&j, "close_gap", o->close_gap);
    cli_json_int(&j, "count", (long long)hv_layer_plan_count(plan));
    cli_json_int(&j, "loops", (long long)r->loops);
    cli_json_int(&j, "holes", (long long)r->holes);
    cli_json_int(&j, "open", (long long)r->open);
    cli_json_int(&j, "gaps_closed", (long long)r->gaps);
    cli_json_int(&j, "dropped", (long long)r->dropped);
    return cli_json_end(&j, "layers", r->js->data); /* the layers one per line */
}

static int slice_mesh(const char *mesh_path, const hv_contours_options *o, const contours_cli *c, int quiet)
{
    static const char *const svg_files[] = {"layer-*.svg", NULL};
    static const hv_outdir_rules svg_dir = {"per-layer SVG directory", NULL, NULL, svg_files, 0, 0};
    cli_progress bar;
    cli_progress_init(&bar, quiet);
    hv_progress prog = {cli_progress_fn, &bar};
    hv_mesh *mesh = NULL;
    hv_slicer *slicer = NULL;
    hv_layer_plan *plan = NULL;
    hv_buf js;
    hv_buf_init(&js);
    run r = {NULL, NULL, NULL, NULL, hv_basename(mesh_path), c->json ? &js : NULL, 0, 0, 0, 0, 0};
    char *tmpdir = NULL;
    hv_slicer_info info;
    hv_status s = hv_mesh_load_stl(mesh_path, &mesh);
    if (s == HV_OK) s = hv_slicer_create(mesh, &prog, &slicer);
    hv_mesh_destroy(mesh);
    if (s == HV_OK && (s = hv_slicer_plan(slicer, o, &plan)) != HV_OK) hv_error_prefix(s, "%s: ", mesh_path);
    if (s == HV_OK) hv_slicer_get_info(slicer, &info);
    if (s == HV_OK && hv_layer_plan_count(plan) == 0)
        s = hv_error_set(HV_ERR_INVALID, "%s: the mesh is %g mm high: no layer of %g mm has its middle inside it",
                         mesh_path, info.bbox_max[2] - info.bbox_min[2], o->adaptive[0] > 0 ? o->adaptive[0] : o->layer_height);
    if (s == HV_OK && c->output) {
        hv_contour_format fmt;
        s = hv_contour_format_for_path(c->output, o->binary, &fmt);
        if (s == HV_OK)
            s = hv_contour_writer_open(c->output, fmt, hv_layer_plan_count(plan), info.bbox_min, info.bbox_max, r.label,
                                   &r.writer);
    }
    /* per-layer SVGs go to a temporary directory renamed into place when complete; an existing
     * DIR is replaced when it holds only layer SVGs (an earlier run's) */
    if (s == HV_OK && c->per_layer) s = hv_outdir_begin(c->per_layer, &svg_dir, 0, &tmpdir);
    r.dir = tmpdir;
    r.lo = info.bbox_min;
    r.hi = info.bbox_max;
    hv_slice_options so;
    hv_slice_options_init(&so);
    so.close_gap = o->close_gap;
    if (s == HV_OK) s = hv_slicer_slice_plan(slicer, plan, &so, sink, &r, &prog);
    cli_progress_done(&bar);
    if (s == HV_OK) s = hv_contour_writer_close(r.writer);
    else hv_contour_writer_abort(r.writer);
    if (s == HV_OK && tmpdir) s = hv_outdir_commit(tmpdir, c->per_layer, &svg_dir, 0);
    if (s != HV_OK && tmpdir) hv_outdir_abort(tmpdir);
    free(tmpdir);
    int rc = s == HV_OK ? report(mesh_path, o, c, plan, &r) : cli_fail(s);
    hv_buf_free(&js);
    hv_layer_plan_destroy(plan);
    hv_slicer_destroy(slicer);
    return rc;
}

static int run_cli(const cli_args *args, void *lib, void *local)
{
    const hv_contours_options *o = lib;
    const contours_cli *c = local;
    hv_contour_format fmt;
    if (o->binary && (!c->output || hv_contour_format_for_path(c->output, 1, &fmt) != HV_OK))
        return cli_usage_error("contours", "--binary needs a .cli output");
    if (!c->output && !c->per_layer && !c->json)
        return cli_usage_error("contours", "nothing to write: give -o OUT.svg|OUT.cli, --per-layer DIR or --json");
    return slice_mesh(args->pos[0], o, c, args->quiet);
}

const cli_spec cmd_contours = {
    "contours", "slice a mesh into contour loops (SVG, CLI)",
    "MESH.stl (--layer-height H | --adaptive MIN,MAX[,CUSP])\n"
    "                      [-o OUT.svg|OUT.cli] [--per-layer DIR] [--json] [options]",
    "Slice a mesh into closed contour loops per layer with Wu's weighted directed graph:\n"
    "facets are nodes, shared edges arcs; each plane touches only the facets crossing it and\n"
    "the loops come out in order. Layers start at the mesh's lowest z and each layer\n"
    "[bottom, top] is cut at its mid-height; the last layer is the one whose mid-height is\n"
    "below the mesh top. A vertex exactly on a cutting plane counts as above it. Loops are\n"
    "oriented (outer counter-clockwise, holes clockwise, seen from +z) and nested. Units: mm.\n",
    hv_contours_option_set, &k_local, "Files are written atomically. Without --json a one-line summary goes to stdout.\n",
    1, 1, "MESH", CLI_THREADS | CLI_QUIET | CLI_POS_FILES, run_cli, NULL};
