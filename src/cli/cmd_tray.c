/* src/cli/cmd_tray.c - `hovox tray [JOB.json] -o DIR [--part SPEC ...]`: a build tray of parts in
 * one stack (hovox/tray.h). The options are the library's (hv_tray_option_set); this file
 * reads the --part shorthand MODEL.vdb[@X,Y[,ROT]][xN] (the shape the model records),
 * MODEL.vdb,MESH[@...], MESH:MATERIAL[@...] or MESH[@...] (an assembly in its bodies' materials). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "core/internal.h"
#include "hovox/dist.h"
#include "hovox/model.h"
#include "hovox/scan.h"
#include "hovox/tray.h"

#define MAX_CLI_PARTS 256

typedef struct tray_cli {
    const char *output;
    const char *part[MAX_CLI_PARTS];
    hv_placement place[MAX_CLI_PARTS]; /* of each --part: the placement options after it */
    unsigned place_given[MAX_CLI_PARTS];
    hv_body_materials materials[MAX_CLI_PARTS]; /* of each --part: the --materials after it */
    hv_tray_part scan[MAX_CLI_PARTS]; /* of each --part: the scan options after it (--iso, --lut, ...) */
    uint64_t scan_given[MAX_CLI_PARTS]; /* their bits in hv_tray_part_option_set (hv_optargs.given) */
    hv_tray_part paint[MAX_CLI_PARTS]; /* of each --part: its --colour-depth and --core */
    int nparts;
    int view;
} tray_cli;

static hv_status add_part(const hv_option *o, void *opts, const hv_opt_value *v)
{
    tray_cli *c = opts;
    if (c->nparts == MAX_CLI_PARTS) return hv_error_option(HV_ERR_INVALID, "at most %d {%s} options", MAX_CLI_PARTS, o->key);
    c->part[c->nparts++] = v->text;
    return HV_OK;
}

/* --unit, --up, --scale, --rotate, --translate place the --part given before them (each once
 * per part; --rotate repeatable). */
static hv_status place_part(const hv_option *o, void *opts, const hv_opt_value *v)
{
    tray_cli *c = opts;
    if (c->nparts == 0)
        return hv_error_option(HV_ERR_INVALID, "{%s} %s the {part} given before it; none is", o->key,
                               strncmp(o->key, "colour", 6) == 0 || strcmp(o->key, "core") == 0 ? "paints" : "places");
    static const char *const keys[] = {"unit", "up", "scale", "translate", "colour_depth", "core"};
    for (unsigned k = 0; k < 6; ++k)
        if (strcmp(o->key, keys[k]) == 0) {
            if (c->place_given[c->nparts - 1] & (1u << k))
                return hv_error_option(HV_ERR_INVALID, "{%s} given twice for the {part} '%s'", o->key,
                                       c->part[c->nparts - 1]);
            c->place_given[c->nparts - 1] |= 1u << k;
        }
    if (strcmp(o->key, "colour_depth") == 0 || strcmp(o->key, "core") == 0) /* the part's own keys */
        return hv_option_set_value(hv_option_find(hv_tray_part_option_set(), o->key), &c->paint[c->nparts - 1], v);
    hv_option one = *o;
    one.offset = 0;
    return hv_placement_option_parse(&one, &c->place[c->nparts - 1], v);
}

/* --materials BODY=MATERIAL: a body of the --part given before it in that material (a job file's
 * "materials"). */
static hv_status part_materials(const hv_option *o, void *opts, const hv_opt_value *v)
{
    tray_cli *c = opts;
    if (c->nparts == 0) return hv_error_option(HV_ERR_INVALID, "{%s} is for the {part} given before it; none is", o->key);
    hv_option one = *o;
    one.offset = 0;
    return hv_body_materials_option_parse(&one, &c->materials[c->nparts - 1], v);
}

/* --iso, --range, --labels, --lut, --keep-largest, --fill-holes, --min-feature: the scan of the
 * --part given before them (each once per part), stored through the part's option set as a job
 * file's keys are (one parser: hv_tray_part_option_set checks them when the part is made). */
static hv_status scan_part(const hv_option *o, void *opts, const hv_opt_value *v)
{
    tray_cli *c = opts;
    if (c->nparts == 0) return hv_error_option(HV_ERR_INVALID, "{%s} is for the {part} given before it; none is", o->key);
    const hv_option_set *set = hv_tray_part_option_set();
    const char *key = o->key;
    hv_opt_value flag = {HV_VALUE_BOOL, NULL, NULL, 0, 1};
    if (strcmp(key, "clean") == 0) { /* --keep-largest, --fill-holes: flags of the part's set */
        if (v->type != HV_VALUE_TEXT || (strcmp(v->text, "keep_largest") != 0 && strcmp(v->text, "fill_holes") != 0))
            return hv_error_option(HV_ERR_INVALID, "{clean} must be keep_largest or fill_holes");
        key = v->text;
        v = &flag;
    }
    const hv_option *po = hv_option_find(set, key);
    uint64_t bit = 1ull << (po - set->options);
    int n = c->nparts - 1;
    if (c->scan_given[n] & bit)
        return hv_error_option(HV_ERR_INVALID, "{%s} given twice for the {part} '%s'", key, c->part[n]);
    c->scan_given[n] |= bit;
    return hv_option_set_value(po, &c->scan[n], v);
}

#define SCAN_OPT(key_, kind_, meta_, help_, section_)                                                          \
    {.key = key_, .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT | (kind_), .meta = meta_, .help = help_,       \
     .section = section_, .parse = scan_part}

#define PLACE_OPT(key_, meta_, help_, section_)                                                                 \
    {.key = key_, .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .meta = meta_, .help = help_, .section = section_, \
     .parse = place_part}

static const hv_option k_local_opts[] = {
    CLI_OUTPUT(tray_cli, "DIR", "the stack directory (written under a temporary name and renamed when complete)", 0),
    {.key = "view", .kind = HV_OPT_FLAG, .offset = offsetof(tray_cli, view),
     .help = "also DIR/index.html, a page to look through the tray in a web browser (see hovox view)"},
    {.key = "part", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .meta = "SPEC", .parse = add_part,
     .section = "Parts (besides those of JOB.json)",
     .help = "MODEL.vdb alone (the shape it records), MODEL.vdb,MESH, MESH:MATERIAL or MESH alone, its bodies in their own materials (MESH: .stl, .3mf, .obj or .ply), then @X,Y[,ROT] (plate position of the part's box centre, "
             "rotation 0/90/180/270; absent: arranged) and xN for N copies"},
    PLACE_OPT("unit", "mm|cm|m|in", "the unit of the part before it, a file without one (also um, ft)",
              "Placement of the --part before them (as in voxelize; job files: the part's keys)"),
    PLACE_OPT("up", "y|z", "y: the part before it is Y-up, turned Z-up", NULL),
    PLACE_OPT("scale", "S|SX,SY,SZ", "scale the part before it about the origin", NULL),
    PLACE_OPT("rotate", "AXIS:DEG|DEG@X,Y,Z", "turn the part before it (repeatable, in order), before ROT", NULL),
    PLACE_OPT("translate", "X,Y,Z", "move the part before it (mm), last", NULL),
    /* --material as in layers and voxelize; --materials, the job file's key, the same */
    {.key = "material", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT | HV_OPT_PAIRS, .meta = "BODY=MATERIAL",
     .parse = part_materials, .section = "Materials of the --part before them (job files: the part's \"materials\")",
     .help = "a body of the part before it (an OBJ group, a 3MF item) in that material, whatever the file says; "
             "repeatable (as layers and voxelize --material)"},
    {.key = "materials", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT | HV_OPT_PAIRS, .meta = "BODY=MATERIAL",
     .parse = part_materials, .help = "the same as --material (the job file's key)"},
    SCAN_OPT("iso", 0, "VALUE", "the scan before it: solid where its interpolated value is at least VALUE",
             "A scanned volume's --part (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, a DICOM directory; job files: "
             "the part's keys with \"scan\")"),
    SCAN_OPT("range", 0, "LO,HI", "the scan before it: solid where the value lies in [LO, HI]", NULL),
    SCAN_OPT("labels", 0, "A,B,...", "the scan before it: a segmentation's labels", NULL),
    SCAN_OPT("lut", 0, "TABLE.csv", "the scan before it: materials from its values (absent: SCAN:MATERIAL)", NULL),
    SCAN_OPT("clean", 0, "keep_largest|fill_holes",
             "the scan before it: its largest connected part only, or its cavities filled (repeatable)", NULL),
    SCAN_OPT("min_feature", 0, "MM", "the scan before it: parts and cavities smaller than MM dropped and filled",
             NULL),
    PLACE_OPT("colour_depth", "MM", "paint the mesh of the part before it in its colours this deep (default 1 mm; a "
              "coloured mesh whose bodies name no 3MF material is painted without it)",
              "Colour of the --part before them (job files: the part's keys)"),
    PLACE_OPT("core", "RESIN|COLOUR", "what lies deeper than its colour: a resin or a colour (default the white resin)",
              NULL),
};
static const hv_opt_alias k_aliases[] = {{"keep_largest", "clean", "keep_largest"}, {"fill_holes", "clean", "fill_holes"}};
static const hv_option_set k_local = {"tray", k_local_opts, (int)HV_COUNT(k_local_opts), sizeof(tray_cli), NULL, NULL, 0,
                                      NULL, NULL, k_aliases, (int)HV_COUNT(k_aliases)};

/* The shorthand into a part; `buf` holds the pieces the part points into. */
static hv_status parse_part(const char *spec, char *buf, size_t size, hv_tray_part *p)
{
    snprintf(buf, size, "%s", spec);
    char *x = strrchr(buf, 'x');
    char *atp = strrchr(buf, '@');
    if (x && x > buf && (!atp || x > atp) && x[1] >= '0' && x[1] <= '9' && !strchr(x, '.') && !strchr(x, '/')) {
        char *end;
        long n = strtol(x + 1, &end, 10);
        if (*end || n < 1) return hv_error_option(HV_ERR_INVALID, "{part} '%s': copies xN need N >= 1", spec);
        p->copies = (int)n;
        *x = '\0';
    }
    if (atp) {
        *atp = '\0';
        double v[3];
        int n = 0;
        for (char *q = atp + 1; n < 3;) {
            char *end;
            v[n++] = strtod(q, &end);
            if (end == q || (*end && *end != ',')) return hv_error_option(HV_ERR_INVALID, "{part} '%s': expected @X,Y[,ROT]", spec);
            if (!*end) break;
            q = end + 1;
        }
        if (n < 2) return hv_error_option(HV_ERR_INVALID, "{part} '%s': expected @X,Y[,ROT]", spec);
        p->at[0] = v[0];
        p->at[1] = v[1];
        p->placed = 1;
        p->rotation = n == 3 ? (int)v[2] : 0;
    }
    char *comma = strchr(buf, ',');
    if (comma) {
        *comma = '\0';
        p->model = buf;
        p->mesh = comma + 1;
    } else if (access(buf, F_OK) == 0 && !hv_model_file_is_mesh(buf) && !hv_scan_path_is_scan(buf)) {
        p->model = buf; /* a model alone: its recorded shape (issue 28) */
    } else {
        char *colon = strrchr(buf, ':');
        p->mesh = buf;
        if (colon) { /* without: a mesh in its bodies' materials (an assembly) */
            *colon = '\0';
            p->material = colon + 1;
        }
    }
    return HV_OK;
}

/* The tray's warnings (a part's mesh whose size suggests a wrong unit) as they arise, spelt for
 * the command line. */
static void warn_now(void *user)
{
    (void)user;
    char msg[2048];
    cli_warn("%s", cli_message(msg, sizeof msg));
}

static void print_plan(const hv_tray_report *r, const hv_tray_options *o)
{
    char mem[32];
    printf("printer     %s, %s\n", o->profile ? o->profile : "j750", hv_layers_mode_name(o->mode));
    printf("plate       %d x %d pixels, %d-bit, %d resin%s\n", r->width, r->height, r->bit_depth, r->resins,
           r->resins == 1 ? "" : "s");
    printf("parts       %d, %.1f%% of the plate\n", r->parts, 100.0 * r->utilisation);
    printf("layers      %zu to %zu of %zu\n", r->first, r->last - 1, r->layers);
    printf("memory      about %s\n", hv_size_text(mem, sizeof mem, (double)r->memory));
}

/* Where every part went (the dry run's list): given or arranged, its box on the plate. */
static void print_parts(const hv_tray *t)
{
    for (int i = 0; i < hv_tray_instance_count(t); ++i) {
        hv_tray_placement p;
        hv_tray_instance_get(t, i, &p);
        char copy[48] = "", turn[32] = "", lift[48] = "";
        if (p.copies > 1) snprintf(copy, sizeof copy, " copy %d of %d", p.copy, p.copies);
        if (p.rotation) snprintf(turn, sizeof turn, ", turned %d", p.rotation);
        if (p.lift) snprintf(lift, sizeof lift, ", lifted %zu layers", p.lift);
        printf("part %-6d %s%s at %.6g, %.6g mm%s%s%s (box x %.6g to %.6g, y %.6g to %.6g)\n", p.part, p.name, copy,
               p.at[0], p.at[1], turn, lift, p.arranged ? ", arranged" : "", p.box[0], p.box[2], p.box[1], p.box[3]);
    }
}

/* Each coloured part's dE2000 (issue 29), as `layers` prints a painted model's: a painted part's
 * skin, a scan's colour table over the values it printed (its copies together). */
static void print_colour(const hv_tray *t)
{
    for (int i = 0; i < hv_tray_instance_count(t); ++i) {
        hv_tray_colour c;
        if (!hv_tray_instance_colour(t, i, &c)) continue;
        hv_tray_placement p;
        hv_tray_instance_get(t, i, &p);
        char copy[48] = "";
        if (p.copies > 1) snprintf(copy, sizeof copy, " copy %d of %d", p.copy, p.copies);
        printf("colour      part %d (%s%s): mean dE2000 %.2f achieved, %.2f target (max %.2f) over %llu %s voxels; "
               "%s, intent %s\n", p.part, p.name, copy, c.achieved.mean_de2000, c.target.mean_de2000,
               c.target.max_de2000, (unsigned long long)c.target.voxels, c.printer_voxels ? "printer" : "skin",
               c.description, hv_intent_name(c.intent));
    }
}

static int run(const cli_args *args, void *lib, void *local)
{
    hv_tray_options *o = lib;
    const tray_cli *c = local;
    hv_tray_options job;
    hv_tray *t = NULL;
    hv_status s = HV_OK;
    if (args->npos) { /* the job file's options; the command line's override them (resins are added) */
        hv_tray_options_init(&job);
        s = hv_tray_load_job(args->pos[0], &t, &job);
        const hv_option_set *set = hv_tray_option_set();
        for (int i = 0; i < set->count && s == HV_OK; ++i) {
            const char *key = set->options[i].key;
            if (!cli_given(args, key)) continue;
            if (set->options[i].kind != HV_OPT_CUSTOM) s = hv_option_copy(set, key, &job, o);
            else if (set->options[i].parse == hv_colour_option_parse) /* --icc, --intent, --resins */
                s = hv_option_copy(hv_colour_option_set(), key, &job.colour, &o->colour);
        }
        for (int i = 0; i < o->nresin && s == HV_OK && job.nresin < HV_TRAY_MAX_RESINS; ++i) job.resin[job.nresin++] = o->resin[i];
        for (int i = 0; i < o->ncolor && s == HV_OK && job.ncolor < HV_TRAY_MAX_RESINS; ++i)
            job.resin_color[job.ncolor++] = o->resin_color[i];
        if (s == HV_OK) o = &job;
    } else {
        s = hv_tray_create(&t);
    }
    if (s == HV_OK && !c->output && !o->dry_run) {
        hv_tray_destroy(t);
        return cli_usage_error("tray", "missing -o DIR");
    }
    char bufs[MAX_CLI_PARTS][1024];
    for (int i = 0; i < c->nparts && s == HV_OK; ++i) {
        hv_tray_part p;
        hv_optargs pa; /* through the part's option set, as a job file's part: its checks are the same */
        hv_optargs_begin(&pa, hv_tray_part_option_set(), &p);
        s = parse_part(c->part[i], bufs[i], sizeof bufs[i], &p);
        p.place = c->place[i];
        if (s == HV_OK && hv_scan_path_is_scan(p.mesh)) { /* a scanned volume: SCAN[:MATERIAL][@X,Y[,ROT]][xN] */
            p.scan = p.mesh;
            p.mesh = NULL;
        }
        const hv_tray_part *sc = &c->scan[i];
        p.iso = sc->iso;
        p.range[0] = sc->range[0];
        p.range[1] = sc->range[1];
        p.labels = sc->labels;
        p.lut = sc->lut;
        p.keep_largest = sc->keep_largest;
        p.fill_holes = sc->fill_holes;
        p.min_feature = sc->min_feature;
        p.materials = c->materials[i];
        p.colour_depth = c->paint[i].colour_depth;
        p.core = c->paint[i].core;
        pa.given |= c->scan_given[i];
        if (s == HV_OK && (s = hv_optargs_finish(&pa)) != HV_OK) s = hv_error_prefix(s, "--part '%s': ", c->part[i]);
        if (s == HV_OK && (s = hv_tray_add(t, &p, NULL)) != HV_OK) /* "part N", counted after the job file's */
            s = hv_error_prefix(s, "--part '%s': ", c->part[i]);
    }
    if (s == HV_OK && hv_tray_part_count(t) == 0) {
        hv_tray_destroy(t);
        return cli_usage_error("tray", "no parts: give JOB.json or --part SPEC");
    }
    hv_tray_report r;
    memset(&r, 0, sizeof r);
    hv_viewer_report page;
    memset(&page, 0, sizeof page);
    if (s == HV_OK) {
        cli_progress bar;
        cli_progress_init(&bar, args->quiet);
        hv_progress prog = {cli_progress_fn, &bar};
        o->dist = cli_dist;
        o->warn = warn_now;
        if (c->view) {
            o->finish = hv_viewer_stack_finish;
            o->finish_user = &page;
        }
        s = hv_tray_write(t, c->output, o, &prog, &r);
        cli_progress_done(&bar);
    }
    if (s == HV_OK && (!args->quiet || o->dry_run)) { /* -q: no summary; a dry run's plan is what was asked for */
        print_plan(&r, o);
        if (o->dry_run) {
            char sz[32];
            if (r.est_seconds < 1)
                printf("estimate    under 1 s on 2 cores, about %s of PNG\n", hv_size_text(sz, sizeof sz, r.est_bytes));
            else
                printf("estimate    about %.0f s on 2 cores, about %s of PNG\n", r.est_seconds,
                       hv_size_text(sz, sizeof sz, r.est_bytes));
            print_parts(t);
        }
        if (o->dry_run && cli_dist) { /* hovox-mpi: how the ranks share the layers */
            int n = cli_dist->size;
            size_t *ranges = malloc((size_t)n * 2 * sizeof *ranges);
            double *share = malloc((size_t)n * sizeof *share);
            s = ranges && share ? hv_tray_partition(t, o, n, ranges, share) : HV_ERR_NOMEM;
            for (int k = 0; k < n && s == HV_OK; ++k)
                printf("rank %-6d layers %zu to %zu (%zu), %.1f%% of the estimated cost\n", k, ranges[2 * k],
                       ranges[2 * k + 1] ? ranges[2 * k + 1] - 1 : 0, ranges[2 * k + 1] - ranges[2 * k], 100.0 * share[k]);
            free(ranges);
            free(share);
        }
        if (!o->dry_run && o->mode == HV_LAYERS_HALFTONE) print_colour(t);
        char sz[32];
        if (!o->dry_run)
            printf("wrote       %s (%zu layers, %llu object pixels, %s%s%s)\n", c->output, r.last - r.first,
                   (unsigned long long)r.object_pixels, hv_size_text(sz, sizeof sz, (double)r.bytes),
                   o->gcvf_path ? ", " : "", o->gcvf_path ? o->gcvf_path : "");
    }
    if (s == HV_OK && !o->dry_run) cli_view_report(&page, c->output, args->quiet);
    hv_tray_destroy(t);
    return s == HV_OK ? EXIT_OK : cli_fail(s);
}

const cli_spec cmd_tray = {
    "tray", "a build tray of parts in one printer stack",
    "[JOB.json] -o DIR [--part SPEC ...] [options]",
    "Slice a tray: graded models (the shape each records, Booleans included, or a mesh given as\n"
    "an override that must match), or plain meshes in one material, placed on\n"
    "the printer's plate (positions in mm of each part's box centre, rotations in quarter\n"
    "turns, copies in a row), checked (inside the build volume, --spacing apart, materials\n"
    "within the printer's slots and mapped to resins), then written as one stack: indexed PNG\n"
    "layers whose palette is the tray's resins, and manifest.json with the parts. Each part's\n"
    "pixels are those 'hovox layers --place X,Y' gives it alone.\n",
    hv_tray_option_set, &k_local,
    "JOB.json: {\"schema\": 1, <the options above as keys, e.g. \"profile\": \"j750\", \"resin\":\n"
    "{\"A\": \"VeroCyan-V\"}>, \"parts\": [{\"model\": ..., \"mesh\": ..., \"at\": [X, Y], \"rotation\": 90,\n"
    "\"copies\": 2}, ...]}; paths relative to the job file.\n",
    0, 1, "JOB argument", CLI_THREADS | CLI_QUIET | CLI_POS_FILES, run, NULL, NULL};
