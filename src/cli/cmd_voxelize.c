/* src/cli/cmd_voxelize.c - `hovox voxelize MESH -o MODEL.vdb`: surface + interior voxels (Wu 2.1).
 * The options are the library's (hv_voxelize_option_set); a scanned volume (hovox/scan.h) takes
 * its shape options (--iso, --range, --labels, --keep-largest, --fill-holes, --min-feature). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "core/internal.h"
#include "core/json.h"
#include "hovox/colour.h"
#include "hovox/geometry.h"
#include "hovox/model.h"
#include "scan_opts.h"
#include "hovox/voxelize.h"

typedef struct vox_cli {
    const char *output, *like;
    int dry_run, json;
    cli_scan scan;
    hv_placement place;
    hv_body_materials materials; /* --material BODY=NAME */
    const char *colour[64]; /* "BODY=COLOUR" */
    int ncolour;
    double colour_depth;
    const char *core;
    hv_colour_options cmap; /* --icc, --intent, --resins (hv_colour_option_set's) */
} vox_cli;

static hv_status add_colour(const hv_option *o, void *opts, const hv_opt_value *v)
{
    vox_cli *c = opts;
    const char *eq = v->type == HV_VALUE_TEXT ? strchr(v->text, '=') : NULL;
    float rgba[4];
    if (!eq || eq == v->text || hv_color_parse(eq + 1, rgba) != HV_OK)
        return hv_error_option(HV_ERR_INVALID, "{%s} must be BODY=COLOUR (#rrggbb, #rrggbbaa or r,g,b[,a]), got '%s'",
                               o->key, v->type == HV_VALUE_TEXT ? v->text : "a non-text value");
    if (c->ncolour == 64) return hv_error_option(HV_ERR_INVALID, "at most 64 {%s} options", o->key);
    c->colour[c->ncolour++] = v->text;
    return HV_OK;
}

static const hv_option k_local_opts[] = {
    CLI_OUTPUT(vox_cli, "MODEL.vdb", "the .vdb to write (atomically)", 0),
    {.key = "like", .kind = HV_OPT_STRING, .flags = HV_OPT_IN_PATH, .offset = offsetof(vox_cli, like), .meta = "MODEL.vdb",
     .help = "the lattice of another model (to combine them by Booleans)", .section = "Resolution (one of)"},
    {.key = "dry_run", .kind = HV_OPT_FLAG, .offset = offsetof(vox_cli, dry_run),
     .help = "print the plan and its memory estimate, write nothing", .section = "Output"},
    CLI_JSON(vox_cli, "print the summary as JSON"),
    {.key = "material", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT | HV_OPT_PAIRS, .meta = "BODY=MATERIAL",
     .offset = offsetof(vox_cli, materials), .parse = hv_body_materials_option_parse, .section = "Assemblies",
     .help = "the material of a body (an OBJ group, a 3MF item, a file's one body by its name), whatever the file "
             "says; repeatable"},
    {.key = "colour", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT | HV_OPT_PAIRS, .meta = "BODY=COLOUR",
     .parse = add_colour, .section = "Colour (a mesh painted in its colours; --icc, --intent, --resins also for a scan's colour --lut)",
     .help = "the colour of a body (#rrggbb, #rrggbbaa or r,g,b[,a]), whatever its texture or file colours; "
             "repeatable"},
    {.key = "colour_depth", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .flags = HV_OPT_LO_OPEN | HV_OPT_UNSET0,
     .offset = offsetof(vox_cli, colour_depth), .meta = "MM", .unit = "mm",
     .help = "paint the part in its colours (textures, vertex, face and material colours, --colour) this deep "
             "from the surface (default 1 mm when painting)"},
    {.key = "core", .kind = HV_OPT_STRING, .offset = offsetof(vox_cli, core), .meta = "RESIN|COLOUR",
     .help = "what lies deeper than the colour, and under uncoloured facets: a resin (one of the six, or "
             "another such as Agilus30) or a colour (default the white resin)"},
    CLI_COLOUR_MAP_OPTIONS(vox_cli, cmap),
    HV_PLACEMENT_OPTIONS(vox_cli, place),
    CLI_SCAN_OPTIONS(vox_cli, scan),
};
static const hv_option_set k_local = CLI_LOCAL_SET("voxelize", k_local_opts, vox_cli);


/* Painting is asked for by any of --colour, --colour-depth, --core. */
static int painting(const vox_cli *c) { return c->ncolour > 0 || c->colour_depth > 0 || c->core; }
static double colour_depth(const vox_cli *c) { return c->colour_depth > 0 ? c->colour_depth : 1.0; }

/* An assembly's regions as JSON records, one per line (for cli_json_end). */
static char *region_lines(const hv_regions *rg)
{
    hv_buf b;
    hv_buf_init(&b);
    for (size_t i = 0; i < hv_regions_count(rg); ++i) {
        const hv_region_info *g = hv_regions_at(rg, i);
        json_t *e = json_object(), *to = json_object();
        int failed = !e || !to;
        for (size_t k = 0; k < g->nlost_to && !failed; ++k)
            failed = hv_json_set(to, hv_regions_at(rg, g->lost_to[k].region)->name,
                                 json_integer((json_int_t)g->lost_to[k].voxels));
        failed = failed || hv_json_set(e, "name", hv_json_text(g->name)) ||
                 hv_json_set(e, "material", g->material ? hv_json_text(g->material) : json_null()) ||
                 hv_json_set(e, "fill", json_string(hv_fill_mode_name(g->fill))) ||
                 hv_json_set(e, "voxels", json_integer((json_int_t)g->voxels)) ||
                 hv_json_set(e, "lost", json_integer((json_int_t)g->lost)) || hv_json_set(e, "lost_to", json_incref(to));
        char *text = failed ? NULL : hv_json_dump(e);
        json_decref(e);
        json_decref(to);
        if (!text) {
            hv_buf_free(&b);
            return NULL;
        }
        hv_buf_printf(&b, "%s\n  %s", i ? "," : "", text);
        free(text);
    }
    if (b.failed) hv_buf_free(&b);
    return b.data ? b.data : hv_strdup("");
}

/* The bodies of an assembly (planned) or its regions (voxelized), as summary lines. */
static void print_regions(const hv_mesh *mesh, const hv_regions *rg, double vv)
{
    for (size_t i = 0; i < hv_mesh_body_count(mesh); ++i) {
        const hv_mesh_body *b = hv_mesh_body_at(mesh, i);
        const char *mat = b->material == HV_MESH_NO_MATERIAL ? NULL : hv_mesh_material_at(mesh, (size_t)b->material)->name;
        printf("region      %s (%s", b->name, mat ? mat : "no material");
        const hv_mesh_material *mm = mat ? hv_mesh_material_at(mesh, (size_t)b->material) : NULL;
        for (size_t q = 0; mm && q < mm->nparts; ++q) /* a mixture: its base materials' fractions */
            printf("%s%s %.4g", q ? " + " : " = ", mm->parts[q].material, mm->parts[q].fraction);
        printf(")");
        const hv_region_info *g = hv_regions_at(rg, i);
        if (g) {
            printf(": %llu voxels, fill %s", (unsigned long long)g->voxels, hv_fill_mode_name(g->fill));
            if (g->lost) printf(", lost %llu", (unsigned long long)g->lost);
            for (size_t k = 0; k < g->nlost_to; ++k)
                printf("%s%llu to %s", k ? ", " : " (overlap: ", (unsigned long long)g->lost_to[k].voxels,
                       hv_regions_at(rg, g->lost_to[k].region)->name);
            if (g->nlost_to) printf(")");
        }
        printf("\n");
    }
    if (rg)
        printf("overlap     %llu voxels, volume %.6g (centres inside two or more bodies: the first in file order "
               "keeps them)\n",
               (unsigned long long)hv_regions_overlap(rg), (double)hv_regions_overlap(rg) * vv);
}

static int report(const char *path, const hv_mesh *mesh, const hv_voxel_plan *plan, const hv_voxelize_options *opt,
                   const vox_cli *c, const hv_volume *vol, const hv_colour_map *map)
{
    const hv_mesh_report *r = hv_mesh_get_report(mesh);
    double vv = plan->xf.voxel[0] * plan->xf.voxel[1] * plan->xf.voxel[2];
    uint64_t occupied = vol ? hv_volume_mask_count(vol, hv_volume_grid_find(vol, "occupancy")) : 0;
    uint64_t surface = vol ? hv_volume_mask_count(vol, hv_volume_grid_find(vol, "surface")) : 0;
    size_t nbodies = hv_mesh_body_count(mesh);
    hv_regions *rg = NULL;
    if (vol && nbodies > 1) {
        hv_status s = hv_voxelize_regions_read(vol, &rg);
        if (s != HV_OK) return cli_fail(s);
    }
    if (c->json) {
        char *lines = NULL;
        if (rg && !(lines = region_lines(rg))) {
            hv_regions_destroy(rg);
            return cli_fail(hv_error_set(HV_ERR_NOMEM, "out of memory"));
        }
        cli_json j;
        cli_json_begin(&j);
        cli_json_str(&j, "mesh", path);
        char placed[1024];
        if (hv_placement_given(&c->place))
            cli_json_str(&j, "placement", hv_placement_describe(&c->place, placed, sizeof placed));
        cli_json_ints(&j, "dims", plan->dims, 3);
        cli_json_nums(&j, "voxel", plan->xf.voxel, 3);
        cli_json_nums(&j, "origin", plan->xf.origin, 3);
        cli_json_int(&j, "adjacency", opt->adjacency);
        cli_json_str(&j, "fill", hv_fill_mode_name(plan->fill));
        cli_json_int(&j, "memory_estimate", (long long)plan->memory_bytes);
        if (vol) {
            cli_json_int(&j, "occupied", (long long)occupied);
            cli_json_int(&j, "surface", (long long)surface);
            cli_json_num(&j, "voxel_volume", (double)occupied * vv);
            cli_json_num(&j, "mesh_volume", r->volume);
            cli_json_str(&j, "output", c->output);
        }
        if (map) {
            cli_json_num(&j, "colour_depth", colour_depth(c));
            cli_json_str(&j, "core", c->core ? c->core : hv_colour_map_resin(map, HV_COLOUR_W));
            cli_json_str(&j, "icc", hv_colour_map_icc(map));
            cli_json_str(&j, "intent", hv_intent_name(hv_colour_map_intent(map)));
            char note[512];
            if (vol && hv_colour_paint_note(vol, note, sizeof note)) cli_json_str(&j, "slots", note);
        }
        if (rg) {
            cli_json_int(&j, "overlap", (long long)hv_regions_overlap(rg));
            cli_json_num(&j, "overlap_volume", (double)hv_regions_overlap(rg) * vv);
        }
        int rc = cli_json_end(&j, rg ? "regions" : NULL, lines);
        free(lines);
        hv_regions_destroy(rg);
        return rc;
    }
    if (nbodies > 1)
        printf("mesh        %s (%llu facets, %zu bodies)\n", path, (unsigned long long)r->facets, nbodies);
    else
        printf("mesh        %s (%llu facets)\n", path, (unsigned long long)r->facets);
    char placed[1024];
    if (hv_placement_given(&c->place))
        printf("placed      %s\n", hv_placement_describe(&c->place, placed, sizeof placed));
    printf("grid        %lld x %lld x %lld voxels of %.6g x %.6g x %.6g\n", (long long)plan->dims[0],
           (long long)plan->dims[1], (long long)plan->dims[2], plan->xf.voxel[0], plan->xf.voxel[1], plan->xf.voxel[2]);
    printf("origin      %.6g %.6g %.6g (centre of voxel 0,0,0)\n", plan->xf.origin[0], plan->xf.origin[1],
           plan->xf.origin[2]);
    printf("surface     adjacency %d, fill %s%s\n", opt->adjacency, hv_fill_mode_name(plan->fill),
           plan->fill == HV_FILL_AUTO ? " (decided per body)" : "");
    char mem[32];
    printf("memory      about %s\n", hv_size_text(mem, sizeof mem, (double)plan->memory_bytes));
    if (vol)
        printf("occupied    %llu voxels (%llu surface), volume %.6g (mesh %.6g)\n", (unsigned long long)occupied,
               (unsigned long long)surface, (double)occupied * vv, r->volume);
    if (nbodies > 1) print_regions(mesh, rg, vv);
    if (map) {
        printf("colour      %.6g mm deep, core %s, in", colour_depth(c), c->core ? c->core : hv_colour_map_resin(map, HV_COLOUR_W));
        for (int k = 0; k < HV_COLOUR_SLOTS; ++k) printf("%s%s", k ? ", " : " ", hv_colour_map_resin(map, k));
        printf("\nprofile     %s (%s), intent %s\n", hv_colour_map_icc(map), hv_colour_map_description(map),
               hv_intent_name(hv_colour_map_intent(map)));
        char note[512];
        if (vol && hv_colour_paint_note(vol, note, sizeof note)) printf("slots       %s\n", note);
        hv_buf said; /* an assembly painted by body: the bodies that kept their materials */
        hv_buf_init(&said);
        cli_describe_bodies(mesh, 1, &said);
        if (said.len) fputs(said.data, stdout);
        hv_buf_free(&said);
    }
    if (vol) printf("wrote       %s\n", c->output);
    hv_regions_destroy(rg);
    return EXIT_OK;
}


/* The --colour BODY=COLOUR options on the mesh as read; then it must have some colour to paint. */
static hv_status set_colours(hv_mesh *raw, const vox_cli *c, const char *path)
{
    for (int i = 0; i < c->ncolour; ++i) {
        const char *eq = strchr(c->colour[i], '=');
        char body[1024];
        snprintf(body, sizeof body, "%.*s", (int)(eq - c->colour[i]), c->colour[i]);
        float f[4];
        hv_color_parse(eq + 1, f); /* checked by add_colour */
        uint32_t v = 0;
        for (int k = 0; k < 4; ++k) v = v << 8 | (uint32_t)lrintf(f[k] * 255.0f);
        hv_status s = hv_mesh_body_colour_set(raw, body, v);
        if (s != HV_OK) return s;
    }
    if (!hv_mesh_has_colour(raw))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: no colour to paint (no texture, vertex, face or material colour); "
                            "give one with %s BODY=COLOUR", path, cli_spell("colour"));
    return HV_OK;
}

/* Painted by the body rule of `layers MESH` (issue 29 item 2: colour asked for; an assembly's
 * bodies of resins and composites keep them); the core a colour when the text reads as one, else a
 * resin; default the map's white resin. */
static hv_status paint(hv_volume *vol, const hv_mesh *mesh, const vox_cli *c, hv_colour_map *map)
{
    hv_colour_body_rule rule = {1, NULL, NULL};
    return hv_colour_mesh_paint(vol, mesh, map, colour_depth(c), c->core, &rule);
}

static int run(const char *path, hv_voxelize_options *opt, const vox_cli *c, int quiet)
{
    hv_transform lattice;
    if (c->like) {
        hv_volume *ref;
        hv_status s = hv_model_load(c->like, &ref);
        if (s != HV_OK) return cli_fail(s);
        lattice = hv_volume_get_transform(ref);
        hv_volume_destroy(ref);
        opt->lattice = &lattice;
    }
    /* the mesh as read (raw) and as placed: the model records the raw mesh and the placement
     * (DESIGN-ROUND "Placement": one record, geometry's leaf) */
    hv_mesh *mesh = NULL, *raw = NULL;
    hv_status s = hv_mesh_load(path, &raw);
    if (s == HV_OK) cli_mesh_notes(raw);
    hv_colour_map *map = NULL;
    if (s == HV_OK && painting(c)) s = set_colours(raw, c, path);
    if (s == HV_OK && painting(c)) s = hv_colour_map_create(&c->cmap, &map);
    if (s == HV_OK) s = hv_body_materials_apply(&c->materials, raw);
    if (s == HV_OK && hv_placement_given(&c->place)) s = hv_placement_transform(&c->place, raw, &mesh);
    else if (s == HV_OK) {
        mesh = raw;
        raw = NULL;
    }
    if (s != HV_OK) {
        hv_colour_map_destroy(map);
        hv_mesh_destroy(raw);
        return cli_fail(s);
    }
    cli_warn_mesh_size(mesh, NULL);
    hv_voxel_plan plan;
    s = hv_voxelize_plan(mesh, opt, &plan);
    if (s != HV_OK) {
        hv_colour_map_destroy(map);
        hv_mesh_destroy(mesh);
        hv_mesh_destroy(raw);
        return cli_fail(s);
    }
    const hv_mesh_report *r = hv_mesh_get_report(mesh);
    if (plan.fill == HV_FILL_FLOOD && r->open_edges > 0)
        cli_warn("%s is open (%zu open edges): %s flood leaks through its holes and may leave it hollow; %s vote "
                 "(auto's choice for open meshes) does not",
                 path, (size_t)r->open_edges, cli_spell("fill"), cli_spell("fill"));
    hv_volume *vol = NULL;
    if (!c->dry_run) {
        cli_progress bar;
        cli_progress_init(&bar, quiet);
        hv_progress prog = {cli_progress_fn, &bar};
        opt->progress = &prog;
        s = hv_voxelize(mesh, opt, &vol);
        cli_progress_done(&bar);
        opt->progress = NULL;
        if (s == HV_OK && map) s = paint(vol, mesh, c, map);
        if (s == HV_OK && raw) { /* the leaf: the raw mesh and the placement's matrix */
            double m[12];
            hv_geometry *g = NULL;
            s = hv_placement_matrix(&c->place, m);
            if (s == HV_OK) s = hv_geometry_from_mesh(raw, NULL, m, c->place.unit > 0 ? c->place.unit : 1.0, &g);
            if (s == HV_OK) s = hv_geometry_write(g, vol);
            hv_geometry_destroy(g);
        }
        if (s == HV_OK) s = hv_volume_save(vol, c->output);
        if (s != HV_OK) {
            hv_colour_map_destroy(map);
            hv_volume_destroy(vol);
            hv_mesh_destroy(mesh);
            hv_mesh_destroy(raw);
            return cli_fail(s);
        }
    }
    /* -q: no summary (the plan of a dry run and --json are what was asked for) */
    int rc = quiet && !c->json && !c->dry_run ? EXIT_OK : report(path, mesh, &plan, opt, c, vol, map);
    hv_colour_map_destroy(map);
    hv_volume_destroy(vol);
    hv_mesh_destroy(mesh);
    hv_mesh_destroy(raw);
    return rc;
}

static int run_scan(const cli_args *args, const char *path, const hv_voxelize_options *vopt, const vox_cli *c)
{
    static const char *const mesh_only[] = {"adjacency", "fill", "dims", "like", "material", "colour",
                                            "colour_depth", "core"};
    for (size_t i = 0; i < sizeof mesh_only / sizeof *mesh_only; ++i)
        if (cli_given(args, mesh_only[i]))
            return cli_usage_error("voxelize", "%s is for meshes; a scanned volume takes --iso, --range or --labels",
                                   cli_spell(mesh_only[i]));
    static const char *const map_only[] = {"icc", "intent", "resins"};
    for (size_t i = 0; i < sizeof map_only / sizeof *map_only && !c->scan.lut; ++i)
        if (cli_given(args, map_only[i]))
            return cli_usage_error("voxelize", "%s is for a colour lookup table (--lut)", cli_spell(map_only[i]));
    hv_scan_voxelize_options o;
    hv_scan_voxelize_options_init(&o);
    int32_t *labels = NULL;
    int rc = cli_scan_shape(args, "voxelize", &c->scan, &o, &labels);
    if (rc >= 0) return rc;
    if (cli_given(args, "voxel_size")) memcpy(o.voxel_size, vopt->voxel_size, sizeof o.voxel_size);
    o.max_memory = vopt->max_memory;
    hv_scan *scan = NULL;
    hv_lut *lut = NULL;
    hv_colour_map *map = NULL;
    hv_status s = cli_scan_lut(&c->scan, &c->cmap, &lut, &map); /* --icc, --intent, --resins as for painting */
    if (s == HV_OK) s = hv_scan_load(path, NULL, &scan);
    hv_volume *vol = NULL;
    hv_scan_voxelize_report r;
    if (s == HV_OK) {
        cli_progress bar;
        cli_progress_init(&bar, args->quiet);
        hv_progress prog = {cli_progress_fn, &bar};
        o.progress = &prog;
        s = hv_lut_scan_model(scan, &o, lut, map, &vol, &r);
        cli_progress_done(&bar);
    }
    if (s == HV_OK && !c->dry_run) s = hv_volume_save(vol, c->output);
    if (s != HV_OK) {
        hv_lut_destroy(lut);
        hv_colour_map_destroy(map);
        free(labels);
        hv_volume_destroy(vol);
        hv_scan_destroy(scan);
        return cli_fail(s);
    }
    const hv_scan_info *in = hv_scan_get_info(scan);
    size_t d[3];
    hv_scan_dims(scan, d);
    char shape[160];
    if (o.shape.select == HV_SCAN_SELECT_ISO) snprintf(shape, sizeof shape, "value >= %.6g", o.shape.iso);
    else if (o.shape.select == HV_SCAN_SELECT_RANGE)
        snprintf(shape, sizeof shape, "%.6g <= value <= %.6g", o.shape.range[0], o.shape.range[1]);
    else snprintf(shape, sizeof shape, "labels %s", c->scan.labels);
    rc = EXIT_OK;
    if (c->json) {
        cli_json j;
        cli_json_begin(&j);
        cli_json_str(&j, "volume", path);
        cli_json_str(&j, "format", in->format_name);
        cli_json_str(&j, "shape", shape);
        cli_json_ints(&j, "dims", r.dims, 3);
        cli_json_ints(&j, "first", r.first, 3);
        cli_json_nums(&j, "voxel", r.voxel, 3);
        cli_json_int(&j, "occupied", (long long)r.occupied);
        cli_json_int(&j, "surface", (long long)r.surface);
        cli_json_num(&j, "voxel_volume", r.volume);
        cli_json_int(&j, "dropped_parts", (long long)r.dropped_parts);
        cli_json_int(&j, "filled_cavities", (long long)r.filled_cavities);
        if (lut) cli_json_str(&j, "lut", c->scan.lut);
        if (!c->dry_run) cli_json_str(&j, "output", c->output);
        rc = cli_json_end(&j, NULL, NULL);
    } else if (!args->quiet || c->dry_run) {
        printf("volume      %s (%s, %zu x %zu x %zu samples)\n", path, in->format_name, d[0], d[1], d[2]);
        printf("shape       %s, trilinear%s%s%s\n", shape, o.keep_largest ? ", largest part" : "",
               o.fill_holes ? ", holes filled" : "", o.min_feature > 0 ? ", minimum feature" : "");
        printf("grid        %lld x %lld x %lld voxels of %.6g x %.6g x %.6g\n", (long long)r.dims[0], (long long)r.dims[1],
               (long long)r.dims[2], r.voxel[0], r.voxel[1], r.voxel[2]);
        if (r.dropped_parts || r.filled_cavities)
            printf("cleaned     dropped %llu parts (%llu voxels), filled %llu cavities (%llu voxels)\n",
                   (unsigned long long)r.dropped_parts, (unsigned long long)r.dropped_voxels,
                   (unsigned long long)r.filled_cavities, (unsigned long long)r.filled_voxels);
        printf("occupied    %llu voxels (%llu surface), volume %.6g\n", (unsigned long long)r.occupied,
               (unsigned long long)r.surface, r.volume);
        if (lut) cli_scan_print_lut(c->scan.lut, lut, map);
        if (!c->dry_run) printf("wrote       %s\n", c->output);
    }
    free(labels);
    hv_lut_destroy(lut);
    hv_colour_map_destroy(map);
    hv_volume_destroy(vol);
    hv_scan_destroy(scan);
    return rc;
}

static int run_cli(const cli_args *args, void *lib, void *local)
{
    const vox_cli *c = local;
    if (!c->output && !c->dry_run) return cli_usage_error("voxelize", "missing -o MODEL.vdb");
    if (hv_scan_path_is_scan(args->pos[0])) {
        if (hv_placement_given(&c->place))
            return cli_usage_error("voxelize", "placement options are for meshes; a scanned volume is placed by its own "
                                   "affine (world RAS millimetres)");
        return run_scan(args, args->pos[0], lib, c);
    }
    int rc = cli_scan_refuse(args, "voxelize", "is for scanned volumes (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, a "
                                               "DICOM directory), not meshes");
    if (rc >= 0) return rc;
    static const char *const map_only[] = {"icc", "intent", "resins"};
    for (size_t i = 0; i < sizeof map_only / sizeof *map_only && !painting(c); ++i)
        if (cli_given(args, map_only[i]))
            return cli_usage_error("voxelize", "%s is for painting the part in colour: give %s, %s or %s too",
                                   cli_spell(map_only[i]), cli_spell("colour_depth"), cli_spell("colour"),
                                   cli_spell("core"));
    return run(args->pos[0], lib, c, args->quiet);
}

const cli_spec cmd_voxelize = {
    "voxelize", "voxelize a mesh or a scanned volume into a .vdb model (surface + interior)",
    "MESH -o MODEL.vdb [options]\n       hovox voxelize VOLUME (--iso V | --range LO,HI | --labels A,B,...) -o MODEL.vdb [options]",
    "Voxelize a mesh (Wu 2.1; Huang et al. 1998): triangles mark the voxels in their face\n"
    "slab, edge cylinders and vertex spheres; the interior is filled. Writes bool grids\n"
    "'occupancy' (surface and interior) and 'surface', voxel (i,j,k) centred at\n"
    "origin + (i*Lx, j*Ly, k*Lz). A mesh of several bodies (an assembly) gives a bool grid\n"
    "'region.<body name>' per body: a voxel goes to the body that holds its centre; where\n"
    "bodies overlap, the first in file order keeps the voxels, and the summary reports the\n"
    "overlap.\n"
    "A scanned volume (NIfTI, NRRD, MetaImage, a DICOM series directory; see 'hovox info')\n"
    "gives a model without a mesh: a voxel is occupied where the volume's trilinearly\n"
    "interpolated value passes --iso, --range or --labels at its centre (world RAS mm,\n"
    "cubic voxels of the smallest sample spacing unless --voxel-size), and the model\n"
    "records the samples and the shape as its geometry, so layers, trays and contours cut\n"
    "the iso-surface itself. --lut gives it materials from the volume's values: each voxel\n"
    "takes the table at the trilinearly interpolated value at its centre (fractions of the\n"
    "table's materials, or a colour as the six colour resins' fractions through --icc).\n",
    hv_voxelize_option_set, &k_local, NULL, 1, 1, "MESH argument", CLI_THREADS | CLI_QUIET | CLI_POS_FILES, run_cli, NULL,
    hv_colour_option_set};
