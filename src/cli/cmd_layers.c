/* src/cli/cmd_layers.c - `hovox layers MODEL.vdb|MODEL.3mf|MESH|VOLUME -o DIR`: printer slice stacks
 * (Wu 2.4.2): contour-constrained material layers at printer resolution, halftoned or as
 * fractions or masks, PNG layers with manifest.json, optionally a GCVF zip. A 3MF Volumetric
 * model brings its mesh. The options are the library's (hv_layers_option_set). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "hovox/colour.h"
#include "core/internal.h"
#include "hovox/model.h"
#include "hovox/dist.h"
#include "hovox/layers.h"
#include "hovox/material.h"
#include "hovox/threemf.h"
#include "hovox/voxelize.h"
#include "scan_opts.h"
#include "slicing/scan_source.h"

typedef struct layers_cli {
    const char *output, *mesh;
    int dry_run, view;
    hv_placement place;
    cli_scan scan;
    hv_body_materials materials; /* --material BODY=MATERIAL, for a mesh sliced in one step */
    double voxel_size;
    double colour_depth;    /* a mesh in one step painted in its colours */
    const char *core;
    hv_colour_options cmap; /* --icc, --intent, --resins: a scan's colour --lut, a painted mesh's colours */
    char cmap_given[40];    /* "--icc, --resins": those given, for a package whose composite ignores them */
} layers_cli;

static const hv_option k_local_opts[] = {
    CLI_OUTPUT(layers_cli, "DIR",
               "the stack directory (written under a temporary name and renamed when complete; must not exist, "
               "or be empty)", 0),
    {.key = "dry_run", .kind = HV_OPT_FLAG, .offset = offsetof(layers_cli, dry_run),
     .help = "print the plan (image size, layers, memory) and stop"},
    {.key = "view", .kind = HV_OPT_FLAG, .offset = offsetof(layers_cli, view),
     .help = "also DIR/index.html, a page to look through the stack in a web browser (see hovox view)"},
    {.key = "mesh", .kind = HV_OPT_STRING, .flags = HV_OPT_IN_PATH, .offset = offsetof(layers_cli, mesh),
     .meta = "FILE", .help = "the mesh the model was made from (required, except for a .3mf model: its own mesh)",
     .section = "Geometry"},
    {.key = "material", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT | HV_OPT_PAIRS, .meta = "BODY=MATERIAL",
     .offset = offsetof(layers_cli, materials), .parse = hv_body_materials_option_parse,
     .section = "A mesh in one step (MESH.stl|.obj|.ply|.3mf instead of a model)",
     .help = "the material of a body (an OBJ group, a 3MF item, a file's one body by its name), whatever the file "
             "says; repeatable"},
    {.key = "voxel_size", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .flags = HV_OPT_LO_OPEN | HV_OPT_UNSET0,
     .offset = offsetof(layers_cli, voxel_size), .meta = "MM", .unit = "mm",
     .help = "the voxels the bodies' materials are evaluated on (default: the printer's coarsest pitch, "
             "coarsened until the model fits half of --max-memory)"},
    {.key = "colour_depth", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .flags = HV_OPT_LO_OPEN | HV_OPT_UNSET0,
     .offset = offsetof(layers_cli, colour_depth), .meta = "MM", .unit = "mm",
     .help = "paint the mesh in its colours this deep (default 1 mm; a coloured mesh whose bodies name no 3MF "
             "material is painted without it), through --icc, --intent, --resins"},
    {.key = "core", .kind = HV_OPT_STRING, .offset = offsetof(layers_cli, core), .meta = "RESIN|COLOUR",
     .help = "what lies deeper than the colour: a resin or a colour (default the white resin)"},
    HV_PLACEMENT_OPTIONS(layers_cli, place),
    CLI_SCAN_OPTIONS(layers_cli, scan),
    CLI_COLOUR_MAP_OPTIONS(layers_cli, cmap),
};
static const hv_option_set k_local = CLI_LOCAL_SET("layers", k_local_opts, layers_cli);


static void print_plan(const hv_layers_report *r, const hv_layers_options *o)
{
    printf("printer     %s: %g x %g dpi, %g mm layers\n", o->profile ? o->profile : "custom", o->dpi[0], o->dpi[1],
           o->layer_height);
    printf("image       %d x %d pixels of %.6g x %.6g mm, origin (%.6g, %.6g), %d-bit\n", r->width, r->height,
           r->pixel_mm[0], -r->pixel_mm[1], r->origin_mm[0], r->origin_mm[1], r->bit_depth);
    printf("layers      %zu to %zu of %zu\n", r->first, r->last - 1, r->layers_total);
    char mem[32];
    printf("memory      about %s (%d workers)\n", hv_size_text(mem, sizeof mem, (double)r->memory_bytes), r->threads);
}

/* The library's warnings, one line each, from `from` on. */
static void warn(const hv_layers_report *r, size_t from)
{
    for (const char *p = r->warnings + from; *p;) {
        const char *nl = strchr(p, '\n');
        size_t n = nl ? (size_t)(nl - p) : strlen(p);
        cli_warn("%.*s", (int)n, p);
        p += n + (nl ? 1 : 0);
    }
}

/* A model painted in colour (hovox/colour.h): the manifest gets the skin's dE2000 through the
 * profile painting used; a profile no longer there is a warning, not a failure. */
static void colour_hook(hv_layers_options *o, const hv_volume *model, const hv_scan_source *src,
                        hv_colour_map **scan_map, hv_colour_skin *sk)
{
    memset(sk, 0, sizeof *sk);
    if (src && *scan_map && o->mode == HV_LAYERS_HALFTONE &&
        hv_scan_source_colour(src, &sk->samples, &sk->rgb, &sk->fractions, &sk->weight)) {
        /* a scan's colour table (issue 30 item 2): the same dE2000 over the printed voxels' values */
        sk->map = *scan_map;
        *scan_map = NULL; /* the skin's now */
        o->manifest = hv_colour_manifest_hook;
        o->manifest_user = sk;
        return;
    }
    hv_status s = hv_layers_colour_hook(o, model, sk);
    if (s != HV_OK) cli_warn("%s: %s; the manifest leaves out the colour's dE2000", o->model_name, hv_last_error());
}

static void report_colour(const hv_colour_skin *sk)
{
    if (!sk->map) return;
    printf("colour      mean dE2000 ");
    if (sk->has_achieved) printf("%.2f achieved, ", sk->achieved.mean_de2000);
    printf("%.2f target (max %.2f) over %llu %s voxels; %s, intent %s\n", sk->target.mean_de2000,
           sk->target.max_de2000, (unsigned long long)sk->target.voxels, sk->model ? "skin" : "printer",
           hv_colour_map_description(sk->map),
           hv_intent_name(hv_colour_map_intent(sk->map)));
}

static void report(const hv_layers_report *r, const hv_layers_options *o, const layers_cli *c, const hv_mesh *mesh,
                   const hv_volume *model, const hv_colour_skin *sk)
{
    if (mesh)
        printf("mesh        %s (%zu facets)\n", c->mesh ? c->mesh : o->mesh_name ? o->mesh_name : o->model_name,
               hv_mesh_facet_count(mesh));
    else if (o->source) printf("shape       the data of %s at every pixel (no model)\n", o->model_name);
    else printf("shape       the one %s records\n", o->model_name);
    char placed[1024];
    if (hv_placement_given(&c->place))
        printf("placed      %s\n", hv_placement_describe(&c->place, placed, sizeof placed));
    hv_material_table *t = NULL;
    if (model && hv_material_table_load(model, &t) == HV_OK)
        printf("model       %s (%d material%s)\n", o->model_name, hv_material_count(t),
               hv_material_count(t) == 1 ? "" : "s");
    else if (hv_layers_source_table(o->source) && hv_material_table_clone(hv_layers_source_table(o->source), &t) != HV_OK)
        t = NULL;
    print_plan(r, o);
    if (o->mode != HV_LAYERS_MASK && t) {
        int w = 9; /* the names' column, as wide as the longest name */
        for (int j = 0; j < r->materials; ++j) w = HV_MAX(w, (int)strlen(hv_material_name(t, j)));
        printf("%-*s    %s\n", w - 1, "material", o->mode == HV_LAYERS_HALFTONE ? "target    achieved" : "target    ");
        for (int j = 0; j < r->materials; ++j) {
            printf("  %-*s %.6f", w, hv_material_name(t, j), r->target[j]);
            if (o->mode == HV_LAYERS_HALFTONE) printf("  %.6f", r->achieved[j]);
            printf("\n");
        }
    }
    hv_material_table_destroy(t);
    if (r->compared)
        printf("compare     resample vs direct: mean %.6f, max %.6f (max over materials per pixel; %llu pixels "
               "outside the definition)\n",
               r->diff_mean, r->diff_max, (unsigned long long)r->direct_fallback);
    report_colour(sk);
    char how[64];
    if (o->mode == HV_LAYERS_HALFTONE) snprintf(how, sizeof how, "halftone %s", hv_halftone_method_name(o->halftone));
    else snprintf(how, sizeof how, "%s", hv_layers_mode_name(o->mode));
    printf("wrote       %s (%zu layers, %llu object pixels, %s%s%s)\n", c->output, r->last - r->first,
           (unsigned long long)r->object_pixels, how, o->gcvf_path ? ", " : "", o->gcvf_path ? o->gcvf_path : "");
}

/* A scanned volume's model (issue 30): its iso-surface as the shape, its materials from the lookup
 * table, made in memory under --max-memory and cut like any model. */
static hv_status scan_model(const hv_layers_options *o, const layers_cli *c, hv_scan_voxelize_options *so,
                            int quiet, hv_volume **model, hv_buf *said)
{
    hv_scan *scan = NULL;
    hv_lut *lut = NULL;
    hv_colour_map *map = NULL;
    hv_scan_options sopt = {o->max_memory};
    hv_status s = cli_scan_lut(&c->scan, &c->cmap, &lut, &map); /* colours through --icc, --intent, --resins */
    if (s == HV_OK) s = hv_scan_load(o->model_name, &sopt, &scan);
    if (s == HV_OK) {
        cli_progress bar;
        cli_progress_init(&bar, quiet);
        hv_progress prog = {cli_progress_fn, &bar};
        so->progress = &prog;
        so->max_memory = o->max_memory;
        s = hv_lut_scan_model(scan, so, lut, map, model, NULL);
        so->progress = NULL;
        cli_progress_done(&bar);
    }
    if (s == HV_OK) {
        size_t d[3];
        hv_scan_dims(scan, d);
        hv_buf_printf(said, "volume      %s (%s, %zu x %zu x %zu samples)\n", o->model_name,
                      hv_scan_get_info(scan)->format_name, d[0], d[1], d[2]);
        if (lut) cli_scan_describe_lut(said, c->scan.lut, lut, map);
    }
    hv_lut_destroy(lut);
    hv_colour_map_destroy(map);
    hv_scan_destroy(scan);
    return s;
}

/* A mesh in one step (issue 27 item 2): the mesh placed, its bodies given their --material, and
 * (unless only the mask is printed) its model made in memory: voxelized at the printer's coarsest
 * pitch (or --voxel-size), coarsened by 5/4 until the plan fits half the memory budget, each body
 * 100% its material or mixture (hv_mesh_model). The contours come from the mesh itself, so the
 * outline is exact; the voxels only place the interfaces between bodies. */
static hv_status mesh_model(const hv_layers_options *o, const layers_cli *c, int quiet, hv_mesh **mesh,
                            hv_volume **model, hv_buf *said)
{
    const hv_printer_profile *pp = o->profile ? hv_printer_profile_find(o->profile) : NULL;
    hv_status s = cli_mesh_load_placed(o->model_name, &c->place, pp ? pp->build : NULL, mesh);
    if (s == HV_OK) s = hv_body_materials_apply(&c->materials, *mesh);
    if (s != HV_OK || o->mode == HV_LAYERS_MASK) return s;
    hv_layers_mesh_options mo; /* the library's one rule: painted in its colours, or its bodies in their materials */
    memset(&mo, 0, sizeof mo);
    mo.materials = c->materials;
    mo.voxel_size = c->voxel_size;
    mo.colour_depth = c->colour_depth;
    mo.core = c->core;
    mo.colour = c->cmap;
    cli_progress bar;
    cli_progress_init(&bar, quiet);
    hv_progress prog = {cli_progress_fn, &bar};
    hv_layers_mesh_voxels v;
    s = hv_layers_mesh_model(*mesh, o, &mo, &prog, model, &v);
    cli_progress_done(&bar);
    if (s != HV_OK) return s;
    hv_buf_printf(said, "voxels      %.6g mm (%lld x %lld x %lld), ", v.size, (long long)v.dims[0],
                  (long long)v.dims[1], (long long)v.dims[2]);
    if (v.painted)
        hv_buf_printf(said, "painted in its colours %.6g mm deep over %s", v.depth, c->core ? c->core : "the white resin");
    else hv_buf_printf(said, "each body in its material");
    hv_buf_printf(said, "%s\n", v.coarsened ? " (coarsened to fit the memory budget)" : "");
    if (v.painted) cli_describe_bodies(*mesh, c->colour_depth > 0 || c->core, said);
    char note[512];
    if (v.painted && hv_colour_paint_note(*model, note, sizeof note)) hv_buf_printf(said, "slots       %s\n", note);
    return HV_OK;
}

/* A scan printed straight from its data (issue 30 item 4): no model, the shape and the table's
 * materials evaluated at every printer pixel (slicing/scan_source.c), when hv_scan_prints_direct
 * says so (--keep-largest, --fill-holes, --min-feature make the model first). */
static hv_status scan_source(hv_layers_options *o, const layers_cli *c, const hv_scan_voxelize_options *so,
                             hv_scan **scan, hv_scan_source **src, hv_colour_map **map_out, hv_buf *said)
{
    hv_lut *lut = NULL;
    hv_colour_map *map = NULL;
    hv_scan_options sopt = {o->max_memory};
    hv_status s = cli_scan_lut(&c->scan, &c->cmap, &lut, &map); /* colours through --icc, --intent, --resins */
    if (s == HV_OK) s = hv_scan_load(o->model_name, &sopt, scan);
    if (s == HV_OK) s = hv_scan_source_open(*scan, &so->shape, o->mode == HV_LAYERS_MASK ? NULL : lut, map, src);
    if (s == HV_OK) {
        o->source = hv_scan_source_layers(*src);
        size_t d[3];
        hv_scan_dims(*scan, d);
        hv_buf_printf(said, "volume      %s (%s, %zu x %zu x %zu samples)\n", o->model_name,
                      hv_scan_get_info(*scan)->format_name, d[0], d[1], d[2]);
        if (lut) cli_scan_describe_lut(said, c->scan.lut, lut, map);
    }
    hv_lut_destroy(lut);
    *map_out = map; /* a colour table's: the manifest's dE2000 */
    return s;
}

static int run(hv_layers_options *o, const layers_cli *c, hv_scan_voxelize_options *so, int quiet)
{
    hv_mesh *mesh = NULL;
    hv_volume *model = NULL;
    hv_scan *scan = NULL;
    hv_scan_source *src = NULL;
    hv_colour_map *scan_map = NULL;
    hv_status s;
    hv_buf said; /* what making a scan's model has to say, printed when the job succeeds */
    hv_buf_init(&said);
    if (so && hv_scan_prints_direct(o, so)) {
        s = scan_source(o, c, so, &scan, &src, &scan_map, &said);
    } else if (so) {
        s = scan_model(o, c, so, quiet, &model, &said);
    } else if (!c->mesh && o->model_name && hv_model_file_is_mesh(o->model_name)) {
        s = mesh_model(o, c, quiet, &mesh, &model, &said);
        o->mesh_name = o->model_name;
        if (o->mode == HV_LAYERS_MASK) o->model_name = NULL;
    } else if (!c->mesh && hv_3mf_sniff(o->model_name)) { /* a 3MF Volumetric model: its mesh and its model in one read */
        s = hv_3mf_load_colour(o->model_name, &c->cmap, &model, &mesh); /* a colour alone: through --icc ... */
        o->mesh_name = o->model_name;
    } else {
        /* without --mesh the shape is the one the model records (issue 28) */
        const hv_printer_profile *pp = o->profile ? hv_printer_profile_find(o->profile) : NULL;
        s = c->mesh ? cli_mesh_load_placed(c->mesh, &c->place, pp ? pp->build : NULL, &mesh) : HV_OK;
        if (s == HV_OK && o->model_name) s = hv_model_load_colour(o->model_name, &c->cmap, &model);
    }
    if (s == HV_OK && model && c->cmap_given[0] && !hv_3mf_colour_mapped(model))
        cli_warn("%s: its <v:composite> gives the material fractions, so %s %s no effect (%s the colour of a package "
                 "without a composite)", o->model_name, c->cmap_given, strchr(c->cmap_given, ' ') ? "have" : "has",
                 strchr(c->cmap_given, ' ') ? "they map" : "it maps");
    hv_layers_report r;
    memset(&r, 0, sizeof r);
    if (s == HV_OK) {
        s = hv_layers_plan(mesh, model, o, &r);
        warn(&r, 0); /* also when the plan fails: a mismatching mesh explains why */
    }
    size_t seen = strlen(r.warnings);
    if (s == HV_OK && c->dry_run) {
        if (said.data) fputs(said.data, stdout);
        print_plan(&r, o);
        if (cli_dist) { /* hovox-mpi: how the ranks share the layers */
            int n = cli_dist->size;
            size_t *ranges = malloc((size_t)n * 2 * sizeof *ranges);
            double *share = malloc((size_t)n * sizeof *share);
            s = ranges && share ? hv_layers_partition(mesh, model, o, n, ranges, share) : HV_ERR_NOMEM;
            for (int k = 0; k < n && s == HV_OK; ++k)
                printf("rank %-6d layers %zu to %zu (%zu), %.1f%% of the estimated cost\n", k, ranges[2 * k],
                       ranges[2 * k + 1] ? ranges[2 * k + 1] - 1 : 0, ranges[2 * k + 1] - ranges[2 * k], 100.0 * share[k]);
            free(ranges);
            free(share);
        }
    } else if (s == HV_OK) {
        cli_progress bar;
        cli_progress_init(&bar, quiet);
        hv_progress prog = {cli_progress_fn, &bar};
        hv_viewer_report page;
        memset(&page, 0, sizeof page);
        if (c->view) {
            o->finish = hv_viewer_stack_finish;
            o->finish_user = &page;
        }
        hv_colour_skin skin;
        colour_hook(o, model, src, &scan_map, &skin);
        s = hv_layers_write(mesh, model, c->output, o, &prog, &r);
        cli_progress_done(&bar);
        if (s == HV_OK) warn(&r, HV_MIN(seen, strlen(r.warnings)));
        if (s == HV_OK && said.data && !quiet) fputs(said.data, stdout);
        if (s == HV_OK && !quiet) report(&r, o, c, mesh, model, &skin);
        hv_colour_map_destroy(skin.map);
        if (s == HV_OK) cli_view_report(&page, c->output, quiet);
    }
    hv_buf_free(&said);
    hv_volume_destroy(model);
    hv_mesh_destroy(mesh);
    o->source = NULL;
    hv_scan_source_close(src);
    hv_scan_destroy(scan);
    hv_colour_map_destroy(scan_map);
    return s == HV_OK ? EXIT_OK : cli_fail(s);
}

static int run_cli(const cli_args *args, void *lib, void *local)
{
    hv_layers_options *o = lib;
    layers_cli *c = local;
    if (!c->output && !c->dry_run) return cli_usage_error("layers", "missing -o DIR");
    if (!c->mesh && args->npos == 0)
        return cli_usage_error("layers", "missing the input: MODEL.vdb, MODEL.3mf, a mesh (.stl, .obj, .ply, .3mf) or a "
                                         "scanned volume");
    if (args->npos == 0 && o->mode != HV_LAYERS_MASK)
        return cli_usage_error("layers", "missing MODEL.vdb (--mesh alone prints only --mode mask; a mesh given in place "
                                         "of MODEL.vdb prints in one step)");
    int mesh_in = !c->mesh && args->npos && !hv_scan_path_is_scan(args->pos[0]) && hv_model_file_is_mesh(args->pos[0]);
    if (!c->mesh && !mesh_in && hv_placement_given(&c->place))
        return cli_usage_error("layers", "--unit, --up, --scale, --rotate and --translate place a --mesh; a model is "
                                         "sliced where its recorded shape is");
    if (!mesh_in && (c->materials.n || c->voxel_size > 0))
        return cli_usage_error("layers", "--material and --voxel-size are for a mesh sliced in one step (MESH.stl, "
                               ".obj, .ply or a 3MF without volume data in place of MODEL.vdb)");
    o->mesh_name = c->mesh;
    o->model_name = args->npos ? args->pos[0] : NULL;
    o->dist = cli_dist;
    if (!o->model_name || !hv_scan_path_is_scan(o->model_name)) {
        int rc = cli_scan_refuse(args, "layers", "is for scanned volumes (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, a "
                                               "DICOM directory)");
        static const char *const colour[] = {"icc", "intent", "resins", "colour_depth", "core"};
        int package = o->model_name && hv_3mf_sniff(o->model_name); /* its colour without a composite takes them */
        for (int k = 0, n = 0; package && !mesh_in && k < 3; ++k) /* "--icc", "--icc and --resins", ... */
            if (cli_given(args, colour[k])) {
                int later = 0;
                for (int j = k + 1; j < 3; ++j) later |= cli_given(args, colour[j]);
                size_t at = strlen(c->cmap_given);
                snprintf(c->cmap_given + at, sizeof c->cmap_given - at, "%s%s", n++ ? later ? ", " : " and " : "",
                         cli_spell(colour[k]));
            }
        for (int k = package ? 3 : 0; k < 5 && rc < 0 && !mesh_in; ++k)
            if (cli_given(args, colour[k]))
                rc = cli_usage_error("layers", "%s is for a mesh painted in one step, a 3MF package's colour or a "
                                               "scanned volume's colour --lut (a model's colours were mapped to resins "
                                               "when it was painted)", cli_spell(colour[k]));
        for (int k = 3; k < 5 && rc < 0 && c->materials.n; ++k)
            if (cli_given(args, colour[k]))
                rc = cli_usage_error("layers", "%s paints the mesh in its colours; --material prints its bodies in "
                                               "materials", cli_spell(colour[k]));
        return rc >= 0 ? rc : run(o, c, NULL, args->quiet);
    }
    if (c->mesh) return cli_usage_error("layers", "--mesh is for models; a scanned volume is cut at its own iso-surface");
    if (cli_given(args, "colour_depth") || cli_given(args, "core"))
        return cli_usage_error("layers", "%s is for a mesh painted in its colours; a scanned volume's colours come "
                                         "from its --lut", cli_spell(cli_given(args, "core") ? "core" : "colour_depth"));
    if (!c->scan.lut && o->mode != HV_LAYERS_MASK)
        return cli_usage_error("layers", "a scanned volume's materials come from --lut TABLE.csv (or print its shape "
                                         "alone with --mode mask)");
    hv_scan_voxelize_options so;
    hv_scan_voxelize_options_init(&so);
    int32_t *labels = NULL;
    int rc = cli_scan_shape(args, "layers", &c->scan, &so, &labels);
    if (rc < 0) rc = run(o, c, &so, args->quiet);
    free(labels);
    return rc;
}

const cli_spec cmd_layers = {
    "layers", "printer slice stacks (PNG) from a model, a mesh or a scanned volume",
    "MODEL.vdb -o DIR [--mesh MESH] [options]\n       hovox layers MODEL.3mf -o DIR [options]\n"
    "       hovox layers PART.stl|.obj|.ply|.3mf -o DIR [--material BODY=MATERIAL]... [options]\n"
    "       hovox layers --mesh MESH -o DIR --mode mask [options]\n"
    "       hovox layers VOLUME (--iso V | --range LO,HI | --labels A,B,...) --lut TABLE.csv -o DIR [options]",
    "Printer slice stacks after Wu 2.4.2. Layers of the printer's height start at the part's\n"
    "lowest z; each is cut at its mid-height z. Per layer the part's contour is rasterised at\n"
    "printer resolution by pixel centres: that decides object and background, as sharp as the\n"
    "contour. The contour is the shape the model records: the WDG contours of the meshes it was\n"
    "voxelized from, combined by its Booleans (Clipper); --mesh is an override that must be the\n"
    "recorded mesh (needed only for models made before hovox recorded their shape). Inside, the material comes from the graded model: the two voxel\n"
    "layers around z interpolated in z over occupied voxels, extended outwards to pixels the\n"
    "voxels miss, then resampled to printer pixels by pixel overlap interpolation (exact area\n"
    "weights, in steps of at most --poi-step) -- or, with --method direct, the grading\n"
    "definition evaluated at every pixel centre.\n"
    "A scanned volume (NIfTI, NRRD, MetaImage, a DICOM series directory) prints straight from its\n"
    "data, with no model: at every printer pixel centre of a layer the samples are interpolated\n"
    "trilinearly, the pixel is object where the shape's test holds (--iso, --range, --labels) and\n"
    "its materials are the lookup table's at the interpolated value. With --keep-largest,\n"
    "--fill-holes or --min-feature (which need the whole volume), --threshold, --method direct or\n"
    "--compare, its model is made in memory as 'hovox voxelize VOLUME --lut' makes it and cut as\n"
    "above (marching squares on the interpolated field, materials resampled from the voxels).\n"
    "A mesh (STL, OBJ, PLY, a 3MF package without volume data: an assembly of bodies) prints in\n"
    "one step: its model is made in memory as 'hovox voxelize' then 'hovox grade' without sources\n"
    "make it (each body 100% its material or its 3MF composite's mixture; --material BODY=NAME\n"
    "names or overrides one), on voxels of the printer's coarsest pitch (--voxel-size to choose);\n"
    "the outline is the mesh's contours, exact; the voxels only place the interfaces between bodies.\n",
    hv_layers_option_set, &k_local,
    "DIR/manifest.json: profile, dpi, layer height, materials with palette colours, pixel_mm\n"
    "[sx, sy] and origin_mm [x0, y0] (pixel column c, row r has its centre at x0 + (c+0.5) sx,\n"
    "y0 + (r+0.5) sy; sy < 0: rows run down in y), and layers [{index, file, z_mm}] with z_mm\n"
    "the height of the cutting plane.\n",
    0, 1, "MODEL argument", CLI_THREADS | CLI_QUIET | CLI_POS_FILES, run_cli, NULL, hv_colour_option_set};
