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
#include "hovox/model.h"
#include "hovox/slice.h"
#include "hovox/solid.h"

typedef struct contours_cli {
    int json;
    hv_placement place;
} contours_cli;

static const hv_option k_local_opts[] = {
    {.key = "json", .kind = HV_OPT_FLAG, .offset = offsetof(contours_cli, json), .section = "Output",
     .help = "per-layer statistics as JSON on stdout (z, bottom, top, loops, outers, holes, open, gaps_closed, area "
             "in mm^2)"},
    HV_PLACEMENT_OPTIONS(contours_cli, place),
};
static const hv_option_set k_local = CLI_LOCAL_SET("contours", k_local_opts, contours_cli);

typedef struct json_run {
    hv_buf b;
    size_t nbodies; /* > 1: an assembly, loops counted per body */
} json_run;

/* The layer records of --json, one per line. */
static hv_status layer_json(void *user, size_t index, const hv_layer *layer, const hv_slice *slice)
{
    json_run *run = user;
    hv_buf *b = &run->b;
    const hv_slice_stats *st = hv_slice_get_stats(slice);
    json_t *j = json_pack("{s:I, s:o, s:o, s:o, s:I, s:I, s:I, s:I, s:I, s:o}", "index", (json_int_t)index, "z",
                          hv_json_number(layer->z), "bottom", hv_json_number(layer->bottom), "top",
                          hv_json_number(layer->top), "loops", (json_int_t)st->loops, "outers", (json_int_t)st->outers,
                          "holes", (json_int_t)st->holes, "open", (json_int_t)st->open, "gaps_closed",
                          (json_int_t)st->gaps_closed, "area", hv_json_number(st->area));
    if (j && run->nbodies > 1) { /* the closed loops of each body, in body order */
        json_t *per = json_array();
        for (size_t k = 0; per && k < run->nbodies; ++k) {
            json_int_t n = 0;
            for (size_t l = 0; l < hv_slice_loop_count(slice); ++l)
                n += hv_slice_loops(slice)[l].closed && (size_t)hv_slice_loops(slice)[l].body == k;
            if (json_array_append_new(per, json_integer(n))) {
                json_decref(per);
                per = NULL;
            }
        }
        if (hv_json_set(j, "body_loops", per)) {
            json_decref(j);
            j = NULL;
        }
    }
    char *text = j ? hv_json_dump(j) : NULL;
    json_decref(j);
    hv_buf_printf(b, "%s\n  %s", index ? "," : "", text ? text : "");
    free(text);
    return !text || b->failed ? hv_error_set(HV_ERR_NOMEM, "out of memory") : HV_OK;
}

static int report(const char *mesh_path, const hv_mesh *mesh, const hv_contours_options *o, const hv_contours_summary *r,
                  const hv_buf *js)
{
    size_t nb = mesh ? hv_mesh_body_count(mesh) : 1;
    if (!js) {
        printf("%s: %zu layers, %zu loops (%zu holes), %zu open polylines, %zu gaps closed", mesh_path, r->layers,
               r->loops, r->holes, r->open, r->gaps_closed);
        if (nb > 1) { /* an assembly: contours per body, each a part of its own in the files */
            printf(", %zu bodies:", nb);
            for (size_t b = 0; b < nb; ++b) printf("%s %s", b ? "," : "", hv_mesh_body_at(mesh, b)->name);
        }
        printf("\n");
        return EXIT_OK;
    }
    cli_json j;
    cli_json_begin(&j);
    cli_json_str(&j, "file", mesh_path);
    if (nb > 1) {
        json_t *names = json_array();
        for (size_t b = 0; names && b < nb; ++b)
            if (json_array_append_new(names, hv_json_text(hv_mesh_body_at(mesh, b)->name))) {
                json_decref(names);
                names = NULL;
            }
        j.failed |= hv_json_set(j.obj, "bodies", names);
    }
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
    cli_json_int(&j, "count", (long long)r->layers);
    cli_json_int(&j, "loops", (long long)r->loops);
    cli_json_int(&j, "holes", (long long)r->holes);
    cli_json_int(&j, "open", (long long)r->open);
    cli_json_int(&j, "gaps_closed", (long long)r->gaps_closed);
    cli_json_int(&j, "dropped", (long long)r->dropped);
    return cli_json_end(&j, "layers", js->data); /* the layers one per line */
}

static int run_cli(const cli_args *args, void *lib, void *local)
{
    const hv_contours_options *o = lib;
    const contours_cli *c = local;
    const char *mesh_path = args->pos[0];
    if (!o->output && !o->per_layer && !c->json)
        return cli_usage_error("contours", "nothing to write: give -o OUT.svg|OUT.cli, --per-layer DIR or --json");
    cli_progress bar;
    cli_progress_init(&bar, args->quiet);
    hv_progress prog = {cli_progress_fn, &bar};
    json_run js;
    hv_buf_init(&js.b);
    hv_contours_summary sum;
    hv_mesh *mesh = NULL;
    hv_volume *model = NULL;
    hv_status s;
    if (hv_has_extension(mesh_path, ".vdb")) { /* a model: the shape it records (issue 28) */
        s = hv_model_load(mesh_path, &model);
        js.nbodies = 1;
        if (s == HV_OK) s = hv_contours_write_model(model, o, mesh_path, c->json ? layer_json : NULL, &js, &prog, &sum);
    } else {
        s = cli_mesh_load_placed(mesh_path, &c->place, NULL, &mesh);
        js.nbodies = mesh ? hv_mesh_body_count(mesh) : 0;
        if (s == HV_OK) s = hv_contours_write(mesh, o, mesh_path, c->json ? layer_json : NULL, &js, &prog, &sum);
    }
    cli_progress_done(&bar);
    int rc = s != HV_OK                 ? cli_fail(s)
             : args->quiet && !c->json ? EXIT_OK
                                       : report(mesh_path, mesh, o, &sum, c->json ? &js.b : NULL);
    hv_mesh_destroy(mesh);
    hv_volume_destroy(model);
    hv_buf_free(&js.b);
    return rc;
}

const cli_spec cmd_contours = {
    "contours", "slice a mesh or a model's shape into contour loops (SVG, CLI)",
    "MESH|MODEL.vdb (--layer-height H | --adaptive MIN,MAX[,CUSP])\n"
    "                      [-o OUT.svg|OUT.cli] [--per-layer DIR] [--json] [options]",
    "Slice a mesh into closed contour loops per layer with Wu's weighted directed graph:\n"
    "facets are nodes, shared edges arcs; each plane touches only the facets crossing it and\n"
    "the loops come out in order. Layers start at the mesh's lowest z and each layer\n"
    "[bottom, top] is cut at its mid-height; the last layer is the one whose mid-height is\n"
    "below the mesh top. A vertex exactly on a cutting plane counts as above it. Loops are\n"
    "oriented (outer counter-clockwise, holes clockwise, seen from +z) and nested. Units: mm.\n"
    "A model (.vdb) is cut as the shape it records: the meshes it was voxelized from combined by\n"
    "its Booleans (Clipper), on uniform layers when it holds a Boolean of several meshes.\n",
    hv_contours_option_set, &k_local, "Files are written atomically. Without --json a one-line summary goes to stdout.\n",
    1, 1, "MESH", CLI_THREADS | CLI_QUIET | CLI_POS_FILES, run_cli, NULL, NULL};
