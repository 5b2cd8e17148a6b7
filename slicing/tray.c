/* slicing/tray.c - print jobs (hovox/tray.h): parts placed on a printer's plate and sliced into
 * one stack in a single streamed pass over the tray's layers. Each part is a single-part layers
 * job planned on the plate (layers.c, hv_layers_part_*): it is evaluated only inside its own box
 * and its pixels are the ones `hovox layers --place` gives it. Footprints (the xy shadow of a
 * part's facets, on a 0.5 mm grid, as row spans) decide spacing and arrangement. */
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "core/internal.h"
#include "core/json.h"
#include "hovox/generate.h"
#include "hovox/geometry.h"
#include "hovox/image.h"
#include "hovox/lut.h"
#include "hovox/model.h"
#include "hovox/scan.h"
#include "hovox/solid.h"
#include "hovox/tray.h"
#include "hovox/volume.h"
#include "hovox/voxelize.h"
#include "layers_internal.h"
#include "scan_source.h"

#define CELL 0.5        /* footprint grid (mm) */
#define RUN 8           /* consecutive tray layers per share of a process (MPI) */
#define INFLIGHT 4      /* plate images in flight at most (fewer under the budget or threads) */
#define ROW_LOCKS 256   /* plate rows guarded in stripes while threads draw parts into them */
#define MAX_PARTS HV_TRAY_MAX_PARTS /* placed instances */

/* ---- resins -------------------------------------------------------------------------------- */

const hv_resin *hv_tray_resins(const hv_printer_profile *p, int *n)
{
    (void)p; /* the J750 and J850 take the same resins */
    return hv_resin_table(n);
}

/* ---- options ---------------------------------------------------------------------------------- */

#define POFF(f) offsetof(hv_tray_part, f)
static const hv_option k_part[] = {
    {.key = "model", .kind = HV_OPT_STRING, .offset = POFF(model), .meta = "MODEL.vdb",
     .help = "a graded model (absent: a plain mesh in `material`)"},
    {.key = "mesh", .kind = HV_OPT_STRING, .offset = POFF(mesh), .meta = "MESH.stl",
     .help = "the part's mesh (with a model: an override that must be the one it records; absent: the shape "
             "the model records; none for a scan)"},
    {.key = "material", .kind = HV_OPT_STRING, .offset = POFF(material), .meta = "NAME",
     .help = "a plain mesh's material"},
    {.key = "materials", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT | HV_OPT_PAIRS, .offset = POFF(materials),
     .meta = "BODY=MATERIAL", .parse = hv_body_materials_option_parse,
     .help = "the material of a body of the mesh, whatever the file says (repeatable; a job file's {\"BODY\": "
             "\"MATERIAL\", ...})"},
    {.key = "name", .kind = HV_OPT_STRING, .offset = POFF(name), .meta = "NAME", .help = "for messages and the manifest"},
    {.key = "at", .kind = HV_OPT_NUMBER, .count = 2, .lo = -1e5, .hi = 1e5, .offset = POFF(at), .meta = "X,Y",
     .unit = "mm", .help = "plate position of the centre of the part's xy box (absent: arranged)"},
    {.key = "z", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e4, .offset = POFF(z), .meta = "Z", .unit = "mm",
     .help = "lift of the part's bottom above the plate (rounded to layers)"},
    {.key = "rotation", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .lo = 0, .hi = 270, .offset = POFF(rotation),
     .meta = "DEG", .unit = "degrees", .help = "about z: 0, 90, 180 or 270"},
    {.key = "copies", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .lo = 1, .hi = MAX_PARTS, .offset = POFF(copies),
     .meta = "N", .help = "copies in a row along +x"},
    HV_PLACEMENT_OPTIONS(hv_tray_part, place),
    {.key = "scan", .kind = HV_OPT_STRING, .flags = HV_OPT_IN_PATH, .offset = POFF(scan), .meta = "VOLUME",
     .help = "a scanned volume (.nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd, a DICOM directory) in place of mesh and "
             "model, printed from its data"},
    {.key = "iso", .kind = HV_OPT_NUMBER, .offset = POFF(iso), .meta = "VALUE",
     .help = "a scan's solid: where its trilinearly interpolated value is at least VALUE"},
    {.key = "range", .kind = HV_OPT_NUMBER, .count = 2, .offset = POFF(range), .meta = "LO,HI",
     .help = "a scan's solid where the interpolated value lies in [LO, HI]"},
    {.key = "labels", .kind = HV_OPT_STRING, .offset = POFF(labels), .meta = "A,B,...",
     .help = "a segmentation's labels: the solid where their interpolated indicator is at least 1/2"},
    {.key = "lut", .kind = HV_OPT_STRING, .flags = HV_OPT_IN_PATH, .offset = POFF(lut), .meta = "TABLE.csv",
     .help = "a scan's materials from its values (absent: the part prints in its material)"},
    {.key = "keep_largest", .kind = HV_OPT_FLAG, .offset = POFF(keep_largest),
     .help = "a scan's largest connected part only (its model is made in memory)"},
    {.key = "fill_holes", .kind = HV_OPT_FLAG, .offset = POFF(fill_holes),
     .help = "a scan's enclosed cavities filled (its model is made in memory)"},
    {.key = "min_feature", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .offset = POFF(min_feature), .meta = "MM",
     .unit = "mm", .help = "a scan's parts and cavities smaller than a ball of this diameter dropped and filled"},
    {.key = "colour_depth", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .flags = HV_OPT_LO_OPEN | HV_OPT_UNSET0,
     .offset = POFF(colour_depth), .meta = "MM", .unit = "mm", .section = "Colour (a mesh painted in its colours)",
     .help = "paint the mesh in its colours this deep (default 1 mm; a coloured mesh whose bodies name no 3MF "
             "material is painted without it)"},
    {.key = "core", .kind = HV_OPT_STRING, .offset = POFF(core), .meta = "RESIN|COLOUR",
     .help = "what lies deeper than the colour: a resin or a colour (default the white resin)"},
};
#undef POFF

/* {materials} names the bodies' materials of a mesh made a model in memory: not beside a model
 * (which brings its own) nor {material} (one material for the whole mesh). */
static hv_status part_materials_check(const hv_tray_part *p)
{
    if (p->materials.n && p->model)
        return hv_error_option(HV_ERR_INVALID, "{materials} is for a mesh's bodies; a model brings its own materials");
    if (p->materials.n && p->material)
        return hv_error_option(HV_ERR_INVALID, "{materials} gives each body its material, {material} the whole mesh "
                                               "one: give one of them");
    return HV_OK;
}

/* The scan keys besides `scan` itself: refused on a mesh part. */
static const char *const k_scan_keys[] = {"iso", "range", "labels", "lut", "keep_largest", "fill_holes", "min_feature"};

/* What a part's keys say together (job files, the CLI's --part, Lua). */
static hv_status part_check(const hv_tray_part *p)
{
    if (p->rotation % 90) return hv_error_option(HV_ERR_INVALID, "{rotation} must be 0, 90, 180 or 270, got %d", p->rotation);
    if (p->model && p->material)
        return hv_error_option(HV_ERR_INVALID, "{material} is for plain meshes; a model brings its own materials");
    const char *paint = p->core ? "core" : "colour_depth";
    if (p->model && (p->colour_depth > 0 || p->core))
        return hv_error_option(HV_ERR_INVALID, "{%s} is for a mesh painted in its colours; a {model} brings its own "
                               "materials (paint it when it is voxelized)", paint);
    if (p->material && (p->colour_depth > 0 || p->core))
        return hv_error_option(HV_ERR_INVALID, "{%s} is for a mesh painted in its colours; a part with a {material} "
                               "(MESH:MATERIAL) prints in that material", paint);
    return HV_OK;
}

static hv_status part_finish(const hv_optargs *args)
{
    hv_tray_part *p = args->opts;
    p->placed = p->placed || hv_optargs_given(args, "at");
    hv_status st = part_check(p);
    if (st == HV_OK) st = part_materials_check(p);
    if (st != HV_OK) return st;
    if (!p->scan) {
        for (size_t k = 0; k < HV_COUNT(k_scan_keys); ++k)
            if (hv_optargs_given(args, k_scan_keys[k]))
                return hv_error_option(HV_ERR_INVALID, "{%s} is for a scanned volume's part", k_scan_keys[k]);
        return HV_OK;
    }
    /* a scan's shape: the key given picks it, as `hovox layers VOLUME` takes it */
    int iso = hv_optargs_given(args, "iso"), range = hv_optargs_given(args, "range"), labels = hv_optargs_given(args, "labels");
    if (iso + range + labels != 1)
        return hv_error_option(HV_ERR_INVALID, "a scanned volume's part needs one of {iso}, {range} or {labels}");
    p->select = iso ? HV_SCAN_SELECT_ISO : range ? HV_SCAN_SELECT_RANGE : HV_SCAN_SELECT_LABELS;
    return HV_OK;
}

void hv_tray_part_init(hv_tray_part *p)
{
    memset(p, 0, sizeof *p);
    p->copies = 1;
}
static void part_init(void *p) { hv_tray_part_init(p); }
static const hv_option_set k_part_set = {"part", k_part, (int)HV_COUNT(k_part), sizeof(hv_tray_part), part_init,
                                         NULL, 0, part_finish, NULL, NULL, 0};
const hv_option_set *hv_tray_part_option_set(void) { return &k_part_set; }

static const char *const k_mode_names[] = {"halftone", "mask", NULL};
static const int k_mode_values[] = {HV_LAYERS_HALFTONE, HV_LAYERS_MASK};
static const hv_enum_def k_mode = {"tray mode", k_mode_names, k_mode_values, NULL};
static const char *const k_arrange_names[] = {"no", "yes", "all", NULL};
static const hv_enum_def k_arrange = {"arrange", k_arrange_names, NULL, NULL};

static hv_status add_text(const hv_option *o, void *opts, const hv_opt_value *v)
{
    hv_tray_options *t = opts;
    int is_resin = strcmp(o->key, "resin") == 0;
    int *n = is_resin ? &t->nresin : &t->ncolor;
    const char **list = is_resin ? t->resin : t->resin_color;
    if (v->type != HV_VALUE_TEXT || !strchr(v->text, '='))
        return hv_error_option(HV_ERR_INVALID, "{%s} must be %s, got %s", o->key,
                               is_resin ? "MATERIAL=RESIN" : "RESIN=#rrggbb", v->type == HV_VALUE_TEXT ? v->text : "?");
    if (*n == HV_TRAY_MAX_RESINS) return hv_error_option(HV_ERR_INVALID, "at most %d {%s} values", HV_TRAY_MAX_RESINS, o->key);
    list[(*n)++] = v->text;
    return HV_OK;
}

#define TOFF(f) offsetof(hv_tray_options, f)
static const hv_option k_tray[] = {
    {.key = "profile", .kind = HV_OPT_STRING, .offset = TOFF(profile), .meta = "NAME",
     .help = "the printer: j750 or j850 (build volume, dpi, layer height, material slots, resins)"},
    {.key = "mode", .kind = HV_OPT_ENUM, .enumdef = &k_mode, .offset = TOFF(mode), .meta = "MODE",
     .help = "halftone (graded parts by blue noise, plain meshes in their resin) or mask (1-bit)"},
    {.key = "seed", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_UINT64, .offset = TOFF(seed), .meta = "N",
     .help = "halftone seed"},
    {.key = "spacing", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1000, .offset = TOFF(spacing), .meta = "MM", .unit = "mm",
     .help = "least gap between parts' footprints"},
    {.key = "arrange", .kind = HV_OPT_ENUM, .enumdef = &k_arrange, .offset = TOFF(arrange), .meta = "no|yes|all",
     .help = "place the parts given without a position (yes) or all parts (all) on the plate"},
    {.key = "layers", .kind = HV_OPT_RANGE, .offset = TOFF(first), .meta = "A:B",
     .help = "the tray layers to write (B excluded)"},
    {.key = "gcvf", .kind = HV_OPT_STRING, .flags = HV_OPT_OUT_PATH, .offset = TOFF(gcvf_path), .meta = "FILE.zip",
     .help = "also a GrabCAD voxel-print style zip (ZIP64 past 4 GiB)"},
    {.key = "stl", .kind = HV_OPT_STRING, .flags = HV_OPT_OUT_PATH, .offset = TOFF(stl_path), .meta = "FILE.stl",
     .help = "also the placed parts as one STL in plate coordinates (to check the tray in other slicers)"},
    {.key = "force", .kind = HV_OPT_FLAG, .offset = TOFF(force), .help = "replace an existing stack or zip"},
    {.key = "dry_run", .kind = HV_OPT_FLAG, .offset = TOFF(dry_run), .help = "check and print the plan, write nothing"},
    {.key = "resin", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT | HV_OPT_PAIRS, .meta = "MATERIAL=RESIN", .parse = add_text,
     .help = "the resin a material prints in (a material named like a resin needs none)"},
    {.key = "resin_color", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT | HV_OPT_PAIRS, .meta = "RESIN=#rrggbb", .parse = add_text,
     .help = "add a resin to the profile's table, or change its display colour"},
    {.key = "max_memory", .kind = HV_OPT_BYTES, .offset = TOFF(max_memory), .meta = "SIZE",
     .help = "refuse jobs that would need more (default: half of RAM)"},
    HV_COLOUR_OPTIONS(hv_tray_options, colour, "Colour (the parts painted in their colours)"),
};
#undef TOFF

static hv_status tray_validate(const void *opts)
{
    const hv_tray_options *o = opts;
    if (o->profile && !hv_printer_profile_find(o->profile))
        return hv_error_option(HV_ERR_INVALID, "{profile} must be j750 or j850, got '%s'", o->profile);
    if (o->gcvf_path && o->mode != HV_LAYERS_HALFTONE && o->mode != HV_LAYERS_MASK)
        return hv_error_option(HV_ERR_INVALID, "{gcvf} needs {mode} halftone or mask");
    return HV_OK;
}

void hv_tray_options_init(hv_tray_options *o)
{
    memset(o, 0, sizeof *o);
    o->profile = "j750";
    o->mode = HV_LAYERS_HALFTONE;
    o->spacing = 5;
    hv_colour_options_init(&o->colour);
}
static void tray_init(void *o) { hv_tray_options_init(o); }
static const hv_option_set k_tray_set = {"tray", k_tray, (int)HV_COUNT(k_tray), sizeof(hv_tray_options), tray_init,
                                         NULL, 0, NULL, tray_validate, NULL, 0};
const hv_option_set *hv_tray_option_set(void) { return &k_tray_set; }

/* ---- the tray -------------------------------------------------------------------------------- */

/* A footprint: the xy shadow of a mesh on the CELL grid, as one span per row (a row's first and
 * last covered cell; concavities within a row count as covered). */
typedef struct footprint {
    int w, h;        /* cells */
    int *lo, *hi;    /* per row; lo > hi: empty row */
    double x0, y0;   /* the mesh's box corner the cells start at (mm) */
    double area;     /* mm^2 */
} footprint;

typedef struct source {   /* one part as given (copies share it) */
    hv_tray_part p;       /* strings owned (strdup) */
    char *where;          /* "job.json: line 7, column 5", or NULL */
    const char **pair_where; /* where each p.materials pair was given (kept by the tray), or NULL */
    int number;           /* part N, in the order added */
    hv_mesh *mesh;        /* rotated; from_model: the leaves that bound the shape; NULL for a scan */
    hv_volume *model;     /* rotated; NULL for plain meshes and a scan printed from its data */
    int from_model;       /* no mesh given: the shape the model records (issue 28) */
    hv_scan *scan;        /* a scan part's volume, placed and turned (NULL once its model is made) */
    hv_scan_source *ssrc; /* a scan printed from its data (issue 30), or NULL */
    hv_colour_map *scan_map; /* a scan's colour table's map (the tray's icc, intent, resins), or NULL */
    int32_t *labels;      /* a scan's labels (its shape points at them) */
    int graded;           /* materials from a table (a model's, a scan's lookup table), not one material */
    double bmin[3], bmax[3];
    footprint fp, dil;    /* dil: dilated by the spacing */
    int resin[HV_MAX_MATERIALS]; /* palette entry of each material (plain meshes: [0]) */
    const char *mat_name[HV_MAX_MATERIALS]; /* kept by the tray */
    int m;
} source;

typedef struct instance {
    int src, copy;
    double x, y;     /* centre of the box on the plate */
    size_t lift;
    hv_layers_part *part;
    int c0, r0, w, h;
    size_t layers;
    int cx, cy;      /* the footprint's cell (0,0) on the plate's CELL grid */
    int arranged;    /* placed by arrange() */
    int coloured;    /* written: its manifest entry has a "colour" (hv_tray_instance_colour) */
    hv_tray_colour colour; /* what hv_tray_instance_colour gives, but its description: */
    char cdesc[128];
} instance;

struct hv_tray {
    source *src;
    int nsrc, cap;
    instance *inst;
    int ninst;
    int planned;
    int loaded; /* a plan began: instances and sources hold what unplan frees */
    const hv_printer_profile *profile;
    double sx, py;
    int W, H, bit_depth;
    size_t nlayers;
    /* palette */
    hv_resin resins[HV_TRAY_MAX_RESINS];
    char resin_names[HV_TRAY_MAX_RESINS][64];
    int nresins;
    int used[HV_TRAY_MAX_RESINS]; /* palette entry of resin r, or 0 */
    int pal_resin[HV_TRAY_MAX_RESINS + 1];
    uint8_t palette[3 * (HV_TRAY_MAX_RESINS + 1)];
    int palette_size;
    double utilisation;
    uint64_t memory;
    int inflight; /* plate images (layers) in flight while writing */
    char **pool; /* strings kept for the tray's life (job files) */
    size_t npool, cap_pool;
    char warnings[2048]; /* of the last plan, one line each */
};

const char *hv_tray_keep(hv_tray *t, const char *s)
{
    if (hv_grow((void **)&t->pool, &t->cap_pool, t->npool + 1, sizeof *t->pool) != HV_OK) return NULL;
    char *d = hv_strdup(s);
    if (d) t->pool[t->npool++] = d;
    return d;
}

hv_status hv_tray_create(hv_tray **out)
{
    *out = hv_calloc(1, sizeof **out);
    return *out ? HV_OK : HV_ERR_NOMEM;
}

static void fp_free(footprint *f)
{
    free(f->lo);
    free(f->hi);
    memset(f, 0, sizeof *f);
}

static void unplan(hv_tray *t)
{
    if (!t->loaded) return; /* nothing read since the last unplan: adding parts stays linear */
    t->loaded = 0;
    for (int i = 0; i < t->ninst; ++i) hv_layers_part_close(t->inst[i].part);
    free(t->inst);
    t->inst = NULL;
    t->ninst = 0;
    for (int i = 0; i < t->nsrc; ++i) {
        source *s = &t->src[i];
        hv_mesh_destroy(s->mesh);
        hv_volume_destroy(s->model);
        hv_scan_source_close(s->ssrc);
        hv_colour_map_destroy(s->scan_map);
        s->scan_map = NULL;
        hv_scan_destroy(s->scan);
        free(s->labels);
        s->mesh = NULL;
        s->model = NULL;
        s->from_model = 0;
        s->ssrc = NULL;
        s->scan = NULL;
        s->labels = NULL;
        fp_free(&s->fp);
        fp_free(&s->dil);
    }
    t->planned = 0;
}

void hv_tray_destroy(hv_tray *t)
{
    if (!t) return;
    unplan(t);
    for (int i = 0; i < t->nsrc; ++i) {
        source *s = &t->src[i];
        free((char *)s->p.model);
        free((char *)s->p.mesh);
        free((char *)s->p.material);
        free((char *)s->p.name);
        for (int k = 0; k < s->p.materials.n; ++k) free((char *)s->p.materials.pair[k]);
        free((char *)s->p.scan);
        free((char *)s->p.lut);
        free((char *)s->p.labels);
        free((char *)s->p.core);
        free(s->where);
        free(s->pair_where);
    }
    free(t->src);
    for (size_t i = 0; i < t->npool; ++i) free(t->pool[i]);
    free(t->pool);
    free(t);
}

int hv_tray_part_count(const hv_tray *t) { return t->nsrc; }
int hv_tray_instance_count(const hv_tray *t) { return t->ninst; }

void hv_tray_instance_box(const hv_tray *t, int i, double box[4])
{
    const instance *in = &t->inst[i];
    const source *s = &t->src[in->src];
    double wx = s->bmax[0] - s->bmin[0], wy = s->bmax[1] - s->bmin[1];
    box[0] = in->x - 0.5 * wx;
    box[1] = in->y - 0.5 * wy;
    box[2] = in->x + 0.5 * wx;
    box[3] = in->y + 0.5 * wy;
}

void hv_tray_instance_get(const hv_tray *t, int i, hv_tray_placement *out)
{
    const instance *in = &t->inst[i];
    const source *s = &t->src[in->src];
    memset(out, 0, sizeof *out);
    out->name = s->p.name;
    out->part = s->number;
    out->copy = in->copy + 1;
    out->copies = s->p.copies;
    out->at[0] = in->x;
    out->at[1] = in->y;
    hv_tray_instance_box(t, i, out->box);
    out->rotation = s->p.rotation;
    out->lift = in->lift;
    out->arranged = in->arranged;
}

static char *dup_or_null(const char *s, int *bad)
{
    if (!s) return NULL;
    char *d = hv_strdup(s);
    if (!d) *bad = 1;
    return d;
}

hv_status hv_tray_add(hv_tray *t, const hv_tray_part *part, const char *where)
{
    return hv_tray_add_at(t, part, where, NULL);
}

hv_status hv_tray_add_at(hv_tray *t, const hv_tray_part *part, const char *where, const char *const *pair_where)
{
    hv_status st = hv_options_check(&k_part_set, part);
    if (st == HV_OK) st = part_check(part);
    if (st == HV_OK && !part->mesh && !part->model && !part->scan)
        st = hv_error_option(HV_ERR_INVALID, "a part needs a {mesh}, a {model} or a {scan}");
    if (st == HV_OK && !part->mesh && !part->scan && hv_placement_given(&part->place))
        st = hv_error_set(HV_ERR_INVALID, "%s: a part from a model alone is placed as the model records it: the "
                                          "placement options move a mesh", part->model);
    if (st == HV_OK) st = part_materials_check(part);
    if (st == HV_OK && part->scan && (part->mesh || part->model))
        st = hv_error_option(HV_ERR_INVALID, "a scanned volume's part is printed from its data: it takes no {mesh} or {model}");
    if (st == HV_OK && part->scan && part->lut && part->material)
        st = hv_error_option(HV_ERR_INVALID, "a scanned volume's part takes its materials from its {lut} or prints "
                             "in one {material}, not both");
    if (st == HV_OK && part->scan && !part->lut && !part->material)
        st = hv_error_option(HV_ERR_INVALID, "a scanned volume's part needs a {lut} (its materials from its values) "
                             "or a {material} to print in");
    if (st != HV_OK) return where ? hv_error_prefix(st, "%s: part %d: ", where, t->nsrc + 1) : st;
    size_t cap = (size_t)t->cap;
    if ((st = hv_grow((void **)&t->src, &cap, (size_t)t->nsrc + 1, sizeof *t->src)) != HV_OK) return st;
    t->cap = (int)cap;
    source *s = &t->src[t->nsrc];
    memset(s, 0, sizeof *s);
    s->p = *part;
    int bad = 0;
    s->p.model = dup_or_null(part->model, &bad);
    s->p.mesh = dup_or_null(part->mesh, &bad);
    s->p.material = dup_or_null(part->material, &bad);
    s->p.scan = dup_or_null(part->scan, &bad);
    s->p.lut = dup_or_null(part->lut, &bad);
    s->p.labels = dup_or_null(part->labels, &bad);
    s->p.name = dup_or_null(part->name ? part->name : hv_basename(part->mesh ? part->mesh : part->scan ? part->scan : part->model), &bad);
    for (int k = 0; k < part->materials.n; ++k) s->p.materials.pair[k] = dup_or_null(part->materials.pair[k], &bad);
    s->p.core = dup_or_null(part->core, &bad);
    s->where = dup_or_null(where, &bad);
    if (pair_where && part->materials.n && !bad) {
        s->pair_where = hv_calloc((size_t)part->materials.n, sizeof *s->pair_where);
        if (s->pair_where) memcpy(s->pair_where, pair_where, (size_t)part->materials.n * sizeof *s->pair_where);
        else bad = 1;
    }
    s->number = t->nsrc + 1;
    t->nsrc++;
    unplan(t);
    return bad ? HV_ERR_NOMEM : HV_OK;
}

/* ---- rotation about z by quarter turns ------------------------------------------------------ */


/* The mesh turned q quarter turns about z, (x, y) -> (-y, x) each; an assembly keeps its bodies
 * (hv_mesh_transform). */
static void quarter_matrix(int q, double a[12])
{
    static const double c[4] = {1, 0, -1, 0}, sn[4] = {0, 1, 0, -1};
    const double m[12] = {c[q & 3], -sn[q & 3], 0, 0, sn[q & 3], c[q & 3], 0, 0, 0, 0, 1, 0};
    memcpy(a, m, sizeof m);
}

static hv_status mesh_rotated(const hv_mesh *m, int q, hv_mesh **out)
{
    double a[12];
    quarter_matrix(q, a);
    return hv_mesh_transform(m, a, out);
}

/* One quarter turn of a volume: voxel (i, j, k) -> (-j - 1, i, k), which maps leaves onto
 * leaves; voxel sizes x and y swap. Grids and the material table come along; the voxelizer's
 * record and the grading definition (in the unrotated frame) do not. */
static hv_status volume_quarter(const hv_volume *v, hv_volume **out)
{
    *out = NULL;
    hv_transform xf = hv_volume_get_transform(v), r = xf;
    r.voxel[0] = xf.voxel[1];
    r.voxel[1] = xf.voxel[0];
    r.origin[0] = -xf.origin[1] + xf.voxel[1];
    r.origin[1] = xf.origin[0];
    hv_volume *d = NULL;
    hv_status s = hv_volume_create(&r, &d);
    int ng = hv_volume_grid_count(v);
    for (int g = 0; g < ng && s == HV_OK; ++g) {
        int idx;
        s = hv_volume_grid_add(d, hv_volume_grid_name(v, g), hv_volume_grid_type(v, g), &idx);
    }
    size_t nl = hv_volume_leaf_count(v);
    const int32_t *org = hv_volume_leaf_origins(v);
    int32_t *norg = s == HV_OK ? hv_malloc_array(nl * 3, sizeof *norg) : NULL;
    uint64_t *masks = norg ? hv_calloc(nl * HV_LEAF_WORDS, sizeof *masks) : NULL;
    if (s == HV_OK && (!norg || !masks)) s = HV_ERR_NOMEM;
    for (size_t l = 0; l < nl && s == HV_OK; ++l) {
        norg[3 * l] = -org[3 * l + 1] - 8;
        norg[3 * l + 1] = org[3 * l];
        norg[3 * l + 2] = org[3 * l + 2];
        const uint64_t *am = hv_volume_leaf_mask(v, l);
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            if (!HV_BIT_GET(am, n)) continue;
            unsigned x = n >> 6, y = (n >> 3) & 7, z = n & 7;
            unsigned m = HV_LEAF_OFFSET(7 - y, x, z);
            masks[l * HV_LEAF_WORDS + (m >> 6)] |= 1ull << (m & 63);
        }
    }
    if (s == HV_OK) s = hv_volume_topology_add(d, nl, norg, masks);
    hv_accessor acc;
    if (s == HV_OK) hv_accessor_init(&acc, d);
    for (size_t l = 0; l < nl && s == HV_OK; ++l) {
        int64_t dl = hv_accessor_leaf(&acc, norg[3 * l], norg[3 * l + 1], norg[3 * l + 2]);
        if (dl < 0) {
            s = hv_error_set(HV_ERR_INTERNAL, "tray: rotated leaf missing");
            break;
        }
        for (int g = 0; g < ng; ++g) {
            if (hv_volume_grid_type(v, g) == HV_GRID_BOOL) {
                const uint64_t *a = hv_volume_leaf_bool_c(v, g, l);
                uint64_t *b = hv_volume_leaf_bool(d, g, (size_t)dl);
                for (unsigned n = 0; n < HV_LEAF_SIZE; ++n)
                    if (HV_BIT_GET(a, n)) {
                        unsigned x = n >> 6, y = (n >> 3) & 7, z = n & 7, m = HV_LEAF_OFFSET(7 - y, x, z);
                        b[m >> 6] |= 1ull << (m & 63);
                    }
            } else {
                const float *a = hv_volume_leaf_float_c(v, g, l);
                float *b = hv_volume_leaf_float(d, g, (size_t)dl);
                for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
                    unsigned x = n >> 6, y = (n >> 3) & 7, z = n & 7;
                    b[HV_LEAF_OFFSET(7 - y, x, z)] = a[n];
                }
            }
        }
    }
    free(norg);
    free(masks);
    for (int i = 0; i < hv_volume_meta_count(v) && s == HV_OK; ++i) {
        const char *key = hv_volume_meta_key(v, i);
        /* the geometry record (issue 28) is in the unrotated frame too: the rotated mesh is the shape */
        if (strcmp(key, "hovox.voxelize.json") == 0 || strcmp(key, "hovox.mesh.json") == 0 ||
            strcmp(key, "hovox.object.json") == 0 || strncmp(key, "hovox.geometry.", 15) == 0)
            continue;
        const char *str = hv_volume_meta_string(v, key);
        double num;
        if (str) {
            size_t n = strlen(key);
            s = n > 5 && strcmp(key + n - 5, ".json") == 0 ? hv_volume_meta_set_json(d, key, str)
                                                            : hv_volume_meta_set_string(d, key, str);
        } else if (hv_volume_meta_number(v, key, &num)) {
            s = hv_volume_meta_set_number(d, key, num);
        }
    }
    if (s != HV_OK) {
        hv_volume_destroy(d);
        return s;
    }
    *out = d;
    return HV_OK;
}

/* ---- footprints ------------------------------------------------------------------------------ */

static hv_status fp_alloc(footprint *f, int w, int h)
{
    f->w = w;
    f->h = h;
    f->lo = hv_malloc_array((size_t)h, sizeof *f->lo);
    f->hi = hv_malloc_array((size_t)h, sizeof *f->hi);
    if (!f->lo || !f->hi) return HV_ERR_NOMEM;
    for (int r = 0; r < h; ++r) {
        f->lo[r] = w;
        f->hi[r] = -1;
    }
    return HV_OK;
}

/* The shadow of every facet on the CELL grid over the mesh's box (row 0 at the box's min y).
 * Cells are half-open ([c, c + 1) cells from the box corner), so a box whose sides fall on grid
 * lines covers exactly its own cells and two boxes that touch share none. */
static int cell_lo(double t, int n) { return HV_CLAMP((int)floor(t + 1e-6), 0, n - 1); }
static int cell_hi(double t, int lo, int n) { return HV_CLAMP(HV_MAX((int)ceil(t - 1e-6) - 1, lo), 0, n - 1); }

/* A footprint of cells over the xy box, rows empty, its corner at the box's (fp_from_mesh, fp_box). */
static hv_status fp_start(const double bmin[3], const double bmax[3], footprint *f, int *w, int *h)
{
    *w = HV_MAX((int)ceil((bmax[0] - bmin[0]) / CELL - 1e-6), 1);
    *h = HV_MAX((int)ceil((bmax[1] - bmin[1]) / CELL - 1e-6), 1);
    hv_status s = fp_alloc(f, *w, *h);
    if (s != HV_OK) return s;
    f->x0 = bmin[0];
    f->y0 = bmin[1];
    return HV_OK;
}

static hv_status fp_from_mesh(const hv_mesh *m, const double bmin[3], const double bmax[3], footprint *f)
{
    int w, h;
    hv_status s = fp_start(bmin, bmax, f, &w, &h);
    if (s != HV_OK) return s;
    const float *v = hv_mesh_vertices(m);
    const uint32_t *fc = hv_mesh_facets(m);
    size_t nf = hv_mesh_facet_count(m);
    for (size_t i = 0; i < nf; ++i) {
        double x[3], y[3];
        for (int k = 0; k < 3; ++k) {
            x[k] = (v[3 * fc[3 * i + k]] - bmin[0]) / CELL;
            y[k] = (v[3 * fc[3 * i + k] + 1] - bmin[1]) / CELL;
        }
        /* each covered cell row gets the triangle's x extent over that row (conservative) */
        double ylo = fmin(y[0], fmin(y[1], y[2])), yhi = fmax(y[0], fmax(y[1], y[2]));
        int r0 = cell_lo(ylo, h), r1 = cell_hi(yhi, r0, h);
        for (int r = r0; r <= r1; ++r) {
            double a = fmax(ylo, r), b = fmin(yhi, r + 1.0), xl = 1e300, xr = -1e300;
            if (a > b) a = b = ylo > r ? ylo : yhi; /* a flat triangle on the row's edge */
            for (int e = 0; e < 3; ++e) {
                double x1 = x[e], y1 = y[e], x2 = x[(e + 1) % 3], y2 = y[(e + 1) % 3];
                double e0 = fmin(y1, y2), e1 = fmax(y1, y2);
                double c0 = fmax(a, e0), c1 = fmin(b, e1);
                if (c0 > c1) continue;
                for (int k = 0; k < 2; ++k) {
                    double yy = k ? c1 : c0;
                    double xx = y2 != y1 ? x1 + (x2 - x1) * (yy - y1) / (y2 - y1) : fmin(x1, x2);
                    double xx2 = y2 != y1 ? xx : fmax(x1, x2);
                    xl = fmin(xl, fmin(xx, xx2));
                    xr = fmax(xr, fmax(xx, xx2));
                }
            }
            if (xl > xr) continue;
            int cl = cell_lo(xl, w), cr = cell_hi(xr, cl, w);
            if (cl < f->lo[r]) f->lo[r] = cl;
            if (cr > f->hi[r]) f->hi[r] = cr;
        }
    }
    f->area = 0;
    for (int r = 0; r < h; ++r)
        if (f->lo[r] <= f->hi[r]) f->area += (f->hi[r] - f->lo[r] + 1) * CELL * CELL;
    return HV_OK;
}

/* The cells closer than d mm to f (their closed squares' gap under d) and f's own: the cells
 * another footprint may not take. The result's cell (0,0) is f's (-k,-k), k = ceil(d / CELL). */
static int dilation_cells(double d) { return (int)ceil(d / CELL - 1e-9); }

static hv_status fp_dilate(const footprint *f, double d, footprint *out)
{
    int k = dilation_cells(d);
    hv_status s = fp_alloc(out, f->w + 2 * k, f->h + 2 * k);
    if (s != HV_OK) return s;
    out->x0 = f->x0 - k * CELL;
    out->y0 = f->y0 - k * CELL;
    for (int r = 0; r < f->h; ++r) {
        if (f->lo[r] > f->hi[r]) continue;
        for (int dy = -k; dy <= k; ++dy) {
            /* a cell dx columns over, dy rows up is (|dx| - 1, |dy| - 1) cells away (when >= 0) */
            double gy = HV_MAX(abs(dy) - 1, 0) * CELL;
            if (dy && gy >= d) continue;
            int dx = (int)ceil(sqrt(d * d - gy * gy) / CELL - 1e-9);
            int rr = r + dy + k;
            int lo = f->lo[r] + k - dx, hi = f->hi[r] + k + dx;
            if (lo < out->lo[rr]) out->lo[rr] = lo;
            if (hi > out->hi[rr]) out->hi[rr] = hi;
        }
    }
    return HV_OK;
}

/* The plate's cells taken by placed footprints, with per-row prefix counts to test spans. */
typedef struct occupancy {
    int w, h;
    uint8_t *cell;
    int32_t *pre; /* (w + 1) per row */
} occupancy;

static void occ_row_update(occupancy *o, int r)
{
    int32_t *p = o->pre + (size_t)r * (size_t)(o->w + 1);
    const uint8_t *c = o->cell + (size_t)r * (size_t)o->w;
    p[0] = 0;
    for (int i = 0; i < o->w; ++i) p[i + 1] = p[i] + c[i];
}

/* Does footprint f with its cell (0,0) at plate cell (cx, cy) touch an occupied cell? Cells
 * off the plate count as free here (inside-the-plate is checked on the undilated box). */
static int occ_hits(const occupancy *o, const footprint *f, int cx, int cy)
{
    for (int r = 0; r < f->h; ++r) {
        int y = cy + r;
        if (y < 0 || y >= o->h || f->lo[r] > f->hi[r]) continue;
        int a = HV_MAX(cx + f->lo[r], 0), b = HV_MIN(cx + f->hi[r], o->w - 1);
        if (a > b) continue;
        const int32_t *p = o->pre + (size_t)y * (size_t)(o->w + 1);
        if (p[b + 1] - p[a]) return 1;
    }
    return 0;
}

/* Do footprints a (cell (0,0) at plate cell (ax, ay)) and b (at (bx, by)) share a cell? */
static int fp_meet(const footprint *a, int ax, int ay, const footprint *b, int bx, int by)
{
    for (int r = 0; r < a->h; ++r) {
        int rb = ay + r - by;
        if (rb < 0 || rb >= b->h || a->lo[r] > a->hi[r] || b->lo[rb] > b->hi[rb]) continue;
        if (ax + a->lo[r] <= bx + b->hi[rb] && bx + b->lo[rb] <= ax + a->hi[r]) return 1;
    }
    return 0;
}

static void occ_add(occupancy *o, const footprint *f, int cx, int cy)
{
    for (int r = 0; r < f->h; ++r) {
        int y = cy + r;
        if (y < 0 || y >= o->h || f->lo[r] > f->hi[r]) continue;
        int a = HV_MAX(cx + f->lo[r], 0), b = HV_MIN(cx + f->hi[r], o->w - 1);
        if (a <= b) memset(o->cell + (size_t)y * (size_t)o->w + a, 1, (size_t)(b - a + 1));
        occ_row_update(o, y);
    }
}

/* ---- planning ---------------------------------------------------------------------------------- */

static const char *inst_name(const hv_tray *t, const instance *in, char *buf, size_t n)
{
    const source *s = &t->src[in->src];
    if (s->p.copies > 1) snprintf(buf, n, "part %d (%s, copy %d)", s->number, s->p.name, in->copy + 1);
    else snprintf(buf, n, "part %d (%s)", s->number, s->p.name);
    return buf;
}

/* "job.json: line 7, column 5: " or "" */
static const char *where_of(const hv_tray *t, const instance *in)
{
    return t->src[in->src].where ? t->src[in->src].where : "";
}
#define WHERE_SEP(t, in) (t->src[(in)->src].where ? ": " : "")

/* A mesh part without a model or a material: an assembly in its bodies' materials (issue 27 item
 * 2), its model made in memory (hv_mesh_model) on voxels of the printer's coarsest pitch,
 * coarsened until the voxelization fits a quarter of the budget; or a mesh that prints in its
 * colours (issue 29), its model painted as `layers MESH` paints it, on voxels half the colour's
 * depth or the printer's pitch (hv_colour_mesh_voxels). */
/* The body rule's resins (issue 29 item 1): a material the tray prints in a resin, by its --resin
 * MATERIAL=RESIN mapping (a job file's "resin" object, Lua's and Python's resin = {...}) or a resin
 * of its table named like it (the profile's, hv_resin_find, and --resin-color's), as resin_of
 * maps it. */
static int tray_is_resin(void *user, const char *material)
{
    const hv_tray_options *o = user;
    size_t n = strlen(material);
    for (int i = 0; i < o->nresin; ++i) {
        const char *eq = strchr(o->resin[i], '=');
        if (eq && (size_t)(eq - o->resin[i]) == n && strncmp(o->resin[i], material, n) == 0) return 1;
    }
    for (int i = 0; i < o->ncolor; ++i) {
        const char *eq = strchr(o->resin_color[i], '=');
        if (eq && (size_t)(eq - o->resin_color[i]) == n && strncasecmp(o->resin_color[i], material, n) == 0) return 1;
    }
    return 0;
}

static hv_status bodies_model(const hv_tray *t, const source *s, const hv_mesh *mesh, const hv_tray_options *o,
                              hv_volume **model)
{
    hv_colour_body_rule rule = {s->p.colour_depth > 0 || s->p.core, tray_is_resin, (void *)o};
    int paint = rule.asked || hv_colour_mesh_paints(mesh, &rule);
    for (size_t i = 0; i < hv_mesh_body_count(mesh) && !paint; ++i) {
        const hv_mesh_body *b = hv_mesh_body_at(mesh, i);
        if (b->material == HV_MESH_NO_MATERIAL)
            return hv_error_option(HV_ERR_INVALID, "body '%s' has no material (the mesh names none): give the part a "
                                   "{material} (MESH:MATERIAL), the body one in {materials} (%s=MATERIAL) or "
                                   "one per body in the file", b->name, b->name);
    }
    const hv_printer_profile *pp = t->profile;
    double pitch = HV_MAX(HV_MAX(25.4 / pp->dpi[0], 25.4 / pp->dpi[1]), pp->layer_height);
    hv_voxelize_options vo;
    hv_voxelize_options_init(&vo);
    vo.max_memory = o->max_memory;
    hv_voxel_plan plan;
    uint64_t budget = hv_memory_budget(o->max_memory) / 4;
    if (!paint) {
        hv_status st = hv_mesh_model_voxels(mesh, pitch, budget, &vo, &plan);
        return st == HV_OK ? hv_mesh_model(mesh, &vo, NULL, model) : st;
    }
    double depth = s->p.colour_depth > 0 ? s->p.colour_depth : HV_COLOUR_DEPTH_DEFAULT;
    hv_colour_map *map = NULL;
    hv_status st = hv_colour_mesh_voxels(mesh, pitch, depth, budget, &vo, &plan);
    if (st == HV_OK) st = hv_colour_map_create(&o->colour, &map);
    if (st == HV_OK) st = hv_colour_mesh_model(mesh, &vo, map, depth, s->p.core, &rule, model);
    hv_colour_map_destroy(map);
    return st;
}

/* ---- a part from a model alone (issue 28) ------------------------------------------------------
 * Its shape is the one the model records, which its layers cut (hv_layers_part_open without a
 * mesh). The tray's box is the shape's (hv_solid_bbox, as the layers take it); the footprint, the
 * plan's fingerprint and the tray's STL take the leaves that can bound the shape, joined: every
 * leaf but those a difference or a subtract takes away (a scanned field's leaf as its box). A
 * quarter turn turns the record with the voxels. */
static void bounding_leaves(const hv_geometry *g, size_t node, uint8_t *use)
{
    const hv_geometry_node *n = hv_geometry_node_at(g, node);
    if (n->op < 0) {
        use[n->leaf] = 1;
        return;
    }
    bounding_leaves(g, n->a, use);
    if (n->op != HV_GEOMETRY_DIFFERENCE && n->op != HV_GEOMETRY_SUBTRACT) bounding_leaves(g, n->b, use);
}

static hv_status footprint_mesh(const hv_geometry *g, const hv_solid *solid, hv_mesh **out)
{
    size_t nl = hv_geometry_leaf_count(g), n = 0;
    uint8_t *use = hv_calloc(nl ? nl : 1, 1);
    hv_mesh_part *parts = hv_calloc(nl ? nl : 1, sizeof *parts);
    hv_mesh **boxes = hv_calloc(nl ? nl : 1, sizeof *boxes);
    hv_status st = use && parts && boxes ? HV_OK : HV_ERR_NOMEM;
    if (st == HV_OK) bounding_leaves(g, hv_geometry_node_count(g) - 1, use);
    for (size_t i = 0; i < nl && st == HV_OK; ++i) {
        if (!use[i]) continue;
        const hv_leaf *leaf = hv_solid_leaf(solid, i);
        parts[n].mesh = hv_leaf_mesh(leaf);
        if (!parts[n].mesh) {
            double lo[3], hi[3];
            hv_leaf_bbox(leaf, lo, hi);
            st = hv_generate_box(lo, hi, &boxes[i]);
            parts[n].mesh = boxes[i];
        }
        parts[n++].name = hv_geometry_leaf_at(g, i)->name;
    }
    if (st == HV_OK) st = hv_mesh_join(parts, n, out);
    for (size_t i = 0; boxes && i < nl; ++i) hv_mesh_destroy(boxes[i]);
    free(use);
    free(parts);
    free(boxes);
    return st;
}

/* The model turned q quarter turns with its record (*model replaced), the shape's box and the
 * footprint mesh. */
static hv_status model_shape(const source *s, int q, hv_volume **model, hv_mesh **mesh, double bmin[3], double bmax[3])
{
    hv_geometry *g = NULL, *r = NULL;
    hv_solid *solid = NULL;
    hv_status st = HV_OK;
    if (!hv_geometry_present(*model)) { /* its message: no record, give the mesh */
        st = hv_solid_for_model(*model, NULL, "tray", s->p.model, NULL, NULL, &solid);
        hv_solid_close(solid);
        solid = NULL;
        if (st == HV_OK) st = hv_error_set(HV_ERR_INTERNAL, "tray: %s: no geometry record", s->p.model);
    }
    if (st == HV_OK && (st = hv_geometry_read(*model, &g)) != HV_OK) st = hv_error_prefix(st, "tray: ");
    if (st == HV_OK && q) {
        double a[12];
        quarter_matrix(q, a);
        st = hv_geometry_transformed(g, a, &r);
        for (int i = 0; i < q && st == HV_OK; ++i) {
            hv_volume *turned = NULL;
            st = volume_quarter(*model, &turned);
            hv_volume_destroy(*model);
            *model = turned;
        }
        if (st == HV_OK) st = hv_geometry_write(r, *model);
    }
    if (st == HV_OK) st = hv_solid_for_model(*model, NULL, "tray", s->p.model, NULL, NULL, &solid);
    if (st == HV_OK) {
        hv_solid_bbox(solid, bmin, bmax);
        st = footprint_mesh(r ? r : g, solid, mesh);
    }
    hv_solid_close(solid);
    hv_geometry_destroy(g);
    hv_geometry_destroy(r);
    return st;
}

/* A message about a job file's part names options as the file's keys ("unit m"), not as the front
 * end reading the job spells its own options ("--unit m"). */
static hv_status as_keys(const source *s, hv_status st)
{
    if (!s->where) return st;
    char m[2048];
    snprintf(m, sizeof m, "%s", hv_last_error());
    return hv_error_set(st, "%s", m);
}

/* A part whose mesh, as placed, is under 1 mm or fits no orientation of the build volume: a
 * warning naming the likely unit (issue 27 item 3; the rule of voxelize and layers,
 * hv_placement_size_warning), for job files, --part, Lua and Python alike. */
static void size_warning(hv_tray *t, const source *s, const hv_mesh *mesh, const hv_tray_options *o)
{
    if (!hv_placement_size_warning(mesh, t->profile->build)) return;
    if (s->where) hv_error_prefix(HV_OK, "%s: part %d (%s): ", s->where, s->number, s->p.name);
    else hv_error_prefix(HV_OK, "part %d (%s): ", s->number, s->p.name);
    as_keys(s, HV_OK);
    size_t n = strlen(t->warnings);
    snprintf(t->warnings + n, sizeof t->warnings - n, "%s\n", hv_last_error());
    if (o->warn) o->warn(o->warn_user);
    hv_error_clear();
}

/* A footprint that covers the box (a scan's: its shape's xy box). */
static hv_status fp_box(const double bmin[3], const double bmax[3], footprint *f)
{
    int w, h;
    hv_status s = fp_start(bmin, bmax, f, &w, &h);
    if (s != HV_OK) return s;
    for (int r = 0; r < h; ++r) {
        f->lo[r] = 0;
        f->hi[r] = w - 1;
    }
    f->area = w * h * CELL * CELL;
    return HV_OK;
}

/* A scan's shape and materials (issue 30): the scan read under the budget, placed and turned (its
 * affine moved), then printed from its data (hv_scan_source, as `layers VOLUME`), or, with a
 * clean-up that needs the whole volume, its model made in memory (hv_lut_scan_model) and the scan
 * let go. Its box is its shape's. */
static hv_status load_scan(source *s, const hv_tray_options *o)
{
    const hv_tray_part *p = &s->p;
    hv_scan_options so = {o->max_memory};
    hv_status st = hv_scan_load(p->scan, &so, &s->scan);
    double a[12];
    if (st == HV_OK && hv_placement_given(&p->place) && (st = hv_placement_matrix(&p->place, a)) == HV_OK)
        st = hv_scan_transform(s->scan, a);
    if (st == HV_OK && (p->rotation / 90) % 4) {
        quarter_matrix((p->rotation / 90) % 4, a);
        st = hv_scan_transform(s->scan, a);
    }
    hv_scan_shape shape = {(hv_scan_select)p->select, p->iso, {p->range[0], p->range[1]}, NULL, 0};
    if (st == HV_OK && p->select == HV_SCAN_SELECT_LABELS) {
        st = hv_scan_labels_parse(p->labels, &s->labels, &shape.label_count);
        shape.labels = s->labels;
    }
    hv_lut *lut = NULL;
    hv_colour_map *map = NULL;
    if (st == HV_OK && p->lut) st = hv_lut_load(p->lut, &lut);
    if (st == HV_OK && lut && hv_lut_kind_of(lut) == HV_LUT_COLOUR) /* the tray's --icc, --intent, --resins */
        st = hv_colour_map_create(&o->colour, &map);
    s->graded = lut != NULL;
    if (st == HV_OK && (p->keep_largest || p->fill_holes || p->min_feature > 0)) {
        hv_scan_voxelize_options vo;
        hv_scan_voxelize_options_init(&vo);
        vo.shape = shape;
        vo.keep_largest = p->keep_largest;
        vo.fill_holes = p->fill_holes;
        vo.min_feature = p->min_feature;
        vo.max_memory = o->max_memory;
        st = hv_lut_scan_model(s->scan, &vo, lut, map, &s->model, NULL);
        hv_solid *solid = NULL;
        if (st == HV_OK) st = hv_solid_for_model(s->model, NULL, "tray", p->scan, NULL, NULL, &solid);
        if (st == HV_OK) hv_solid_bbox(solid, s->bmin, s->bmax);
        hv_solid_close(solid);
        hv_scan_destroy(s->scan); /* the model's shape holds its samples */
        s->scan = NULL;
    } else if (st == HV_OK) {
        st = hv_scan_source_open(s->scan, &shape, lut, map, &s->ssrc);
        if (st == HV_OK) {
            const hv_layers_source *ls = hv_scan_source_layers(s->ssrc);
            memcpy(s->bmin, ls->bbox_min, sizeof s->bmin);
            memcpy(s->bmax, ls->bbox_max, sizeof s->bmax);
        }
    }
    hv_lut_destroy(lut);
    if (s->ssrc && map) s->scan_map = map; /* the manifest's dE2000 over the printed values */
    else hv_colour_map_destroy(map);
    if (st == HV_OK && !(s->bmax[2] > s->bmin[2]))
        st = hv_error_set(HV_ERR_INVALID, "%s: no sample is inside the shape (%s)", p->scan,
                          p->select == HV_SCAN_SELECT_ISO ? "iso" : p->select == HV_SCAN_SELECT_RANGE ? "range" : "labels");
    if (st == HV_OK) st = fp_box(s->bmin, s->bmax, &s->fp);
    if (st == HV_OK) st = fp_dilate(&s->fp, o->spacing, &s->dil);
    return st;
}

static hv_status load_source(hv_tray *t, source *s, const hv_tray_options *o)
{
    if (s->p.scan) {
        hv_status st = load_scan(s, o);
        return st == HV_OK ? st
               : s->where ? hv_error_prefix(st, "%s: part %d (%s): ", s->where, s->number, s->p.name)
                          : hv_error_prefix(st, "part %d (%s): ", s->number, s->p.name);
    }
    hv_mesh *mesh = NULL;
    hv_volume *model = NULL;
    int q = (s->p.rotation / 90) % 4;
    if (!s->p.mesh) {
        double bmin[3], bmax[3];
        hv_status st = hv_model_load_colour(s->p.model, &o->colour, &model); /* a 3MF colour: the tray's map */
        if (st == HV_OK) st = model_shape(s, q, &model, &mesh, bmin, bmax);
        if (st == HV_OK) {
            s->mesh = mesh;
            s->model = model;
            s->from_model = 1;
            s->graded = 1; /* its materials are the model's */
            memcpy(s->bmin, bmin, sizeof s->bmin);
            memcpy(s->bmax, bmax, sizeof s->bmax);
            st = fp_from_mesh(mesh, s->bmin, s->bmax, &s->fp);
            if (st == HV_OK) st = fp_dilate(&s->fp, o->spacing, &s->dil);
            return st;
        }
        hv_mesh_destroy(mesh);
        hv_volume_destroy(model);
        return s->where ? hv_error_prefix(st, "%s: part %d (%s): ", s->where, s->number, s->p.name)
                        : hv_error_prefix(st, "part %d (%s): ", s->number, s->p.name);
    }
    hv_status st = hv_mesh_load(s->p.mesh, &mesh);
    if (st == HV_OK) st = hv_placement_apply(&s->p.place, &mesh);
    if (st == HV_OK) size_warning(t, s, mesh, o);
    const char *where = s->where; /* a body the mesh lacks: at its "materials" entry */
    for (int k = 0; k < s->p.materials.n && st == HV_OK; ++k) {
        hv_body_materials one = {1, {s->p.materials.pair[k]}};
        st = hv_body_materials_apply(&one, mesh);
        if (st != HV_OK && s->pair_where && s->pair_where[k]) where = s->pair_where[k];
    }
    if (st == HV_OK && s->p.model) st = hv_model_load_colour(s->p.model, &o->colour, &model);
    else if (st == HV_OK && !s->p.material) st = bodies_model(t, s, mesh, o, &model);
    for (int i = 0; i < q && st == HV_OK && model; ++i) {
        hv_volume *r = NULL;
        st = volume_quarter(model, &r);
        hv_volume_destroy(model);
        model = r;
    }
    if (st == HV_OK && q) {
        hv_mesh *r = NULL;
        st = mesh_rotated(mesh, q, &r);
        hv_mesh_destroy(mesh);
        mesh = r;
    }
    if (st != HV_OK) {
        hv_mesh_destroy(mesh);
        hv_volume_destroy(model);
        return where ? as_keys(s, hv_error_prefix(st, "%s: part %d (%s): ", where, s->number, s->p.name))
                     : hv_error_prefix(st, "part %d (%s): ", s->number, s->p.name);
    }
    s->mesh = mesh;
    s->model = model;
    s->graded = model != NULL;
    const hv_mesh_report *mr = hv_mesh_get_report(mesh);
    memcpy(s->bmin, mr->bbox_min, sizeof s->bmin);
    memcpy(s->bmax, mr->bbox_max, sizeof s->bmax);
    st = fp_from_mesh(mesh, s->bmin, s->bmax, &s->fp);
    if (st == HV_OK) st = fp_dilate(&s->fp, o->spacing, &s->dil);
    (void)t;
    return st;
}

/* The resin of material `name`: the job's map, else a resin of that name. Returns its index in
 * t->resins or raises. */
static hv_status resin_of(hv_tray *t, const hv_tray_options *o, const char *name, const char *where, int *out)
{
    const char *resin = name;
    for (int i = 0; i < o->nresin; ++i) {
        const char *eq = strchr(o->resin[i], '=');
        if ((size_t)(eq - o->resin[i]) == strlen(name) && strncmp(o->resin[i], name, strlen(name)) == 0) resin = eq + 1;
    }
    for (int r = 0; r < t->nresins; ++r)
        if (strcasecmp(t->resins[r].name, resin) == 0) {
            *out = r;
            return HV_OK;
        }
    char list[1024];
    size_t n = 0;
    list[0] = '\0';
    for (int r = 0; r < t->nresins && n < sizeof list; ++r)
        n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", r ? ", " : "", t->resins[r].name);
    if (resin == name)
        return hv_error_option(HV_ERR_INVALID, "%s: material '%s' has no resin: map it with {resin} %s=RESIN (resins: %s)",
                               where, name, name, list);
    return hv_error_option(HV_ERR_INVALID, "%s: material '%s' maps to the unknown resin '%s' (resins: %s)", where, name,
                           resin, list);
}

static hv_status setup_resins(hv_tray *t, const hv_tray_options *o)
{
    int n;
    const hv_resin *base = hv_tray_resins(t->profile, &n);
    t->nresins = 0;
    for (int i = 0; i < n; ++i) t->resins[t->nresins++] = base[i];
    for (int i = 0; i < o->ncolor; ++i) {
        const char *eq = strchr(o->resin_color[i], '=');
        size_t len = (size_t)(eq - o->resin_color[i]);
        float c[4];
        if (len == 0 || len >= 64 || hv_color_parse(eq + 1, c) != HV_OK)
            return hv_error_option(HV_ERR_INVALID, "{resin_color} must be RESIN=#rrggbb, got '%s'", o->resin_color[i]);
        int r = 0;
        while (r < t->nresins && !(strlen(t->resins[r].name) == len && strncasecmp(t->resins[r].name, o->resin_color[i], len) == 0))
            ++r;
        if (r == t->nresins) {
            if (r == HV_TRAY_MAX_RESINS) return hv_error_option(HV_ERR_LIMIT, "at most %d resins", HV_TRAY_MAX_RESINS);
            memcpy(t->resin_names[r], o->resin_color[i], len);
            t->resin_names[r][len] = '\0';
            t->resins[r].name = t->resin_names[r];
            t->nresins++;
        }
        for (int k = 0; k < 3; ++k) t->resins[r].rgb[k] = (uint8_t)lroundf(HV_CLAMP(c[k], 0.0f, 1.0f) * 255.0f);
    }
    return HV_OK;
}

/* Materials of every source to palette entries (resins in the table's order). */
static const char *src_label(const source *s, char *buf, size_t n)
{
    if (s->where) snprintf(buf, n, "%s: part %d (%s)", s->where, s->number, s->p.name);
    else snprintf(buf, n, "part %d (%s)", s->number, s->p.name);
    return buf;
}

/* How to fit the slots: a material printed in a resin --resin-color added (else a plain part's),
 * mapped onto the used resin nearest in display colour. Returns that resin, or -1 (*material NULL). */
static int slots_hint(const hv_tray *t, const char **material)
{
    int base, culprit = -1;
    hv_tray_resins(t->profile, &base);
    for (int r = base; r < t->nresins && culprit < 0; ++r)
        if (t->used[r]) culprit = r;
    for (int i = 0; i < t->nsrc && culprit < 0; ++i)
        if (!t->src[i].graded) culprit = t->src[i].resin[0];
    *material = NULL;
    for (int i = 0; i < t->nsrc && !*material; ++i)
        for (int j = 0; j < t->src[i].m && !*material; ++j)
            if (t->src[i].resin[j] == culprit) *material = t->src[i].mat_name[j];
    int near = -1;
    long best = 0;
    for (int r = 0; r < t->nresins && *material; ++r) {
        if (!t->used[r] || r == culprit) continue;
        long d = 0;
        for (int k = 0; k < 3; ++k) d += (long)(t->resins[r].rgb[k] - t->resins[culprit].rgb[k]) *
                                         (t->resins[r].rgb[k] - t->resins[culprit].rgb[k]);
        if (near < 0 || d < best) near = r, best = d;
    }
    if (near < 0) *material = NULL;
    return near;
}

static hv_status setup_palette(hv_tray *t, const hv_tray_options *o)
{
    char lb[512];
    memset(t->used, 0, sizeof t->used);
    for (int i = 0; i < t->nsrc; ++i) {
        source *s = &t->src[i];
        hv_status st;
        if (!s->graded) {
            s->m = 1;
            s->mat_name[0] = s->p.material;
            if ((st = resin_of(t, o, s->p.material, src_label(s, lb, sizeof lb), &s->resin[0])) != HV_OK) return st;
        } else {
            hv_material_table *tab = NULL;
            st = s->ssrc ? hv_material_table_clone(hv_layers_source_table(hv_scan_source_layers(s->ssrc)), &tab)
                         : hv_material_table_load(s->model, &tab);
            if (st == HV_ERR_NOT_FOUND)
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s has no materials (grade it first, or print the mesh "
                                                      "alone with a material)", src_label(s, lb, sizeof lb), s->p.model);
            if (st != HV_OK) return hv_error_prefix(st, "%s: ", src_label(s, lb, sizeof lb));
            s->m = hv_material_count(tab);
            for (int j = 0; j < s->m && st == HV_OK; ++j) {
                st = resin_of(t, o, hv_material_name(tab, j), src_label(s, lb, sizeof lb), &s->resin[j]);
                if (st == HV_OK && !(s->mat_name[j] = hv_tray_keep(t, hv_material_name(tab, j)))) st = HV_ERR_NOMEM;
            }
            hv_material_table_destroy(tab);
            if (st != HV_OK) return st;
        }
        for (int j = 0; j < s->m; ++j) t->used[s->resin[j]] = 1;
    }
    int slots = 0;
    for (int r = 0; r < t->nresins; ++r) slots += t->used[r] != 0;
    if (slots > t->profile->material_slots) {
        char list[1024];
        size_t n = 0;
        for (int r = 0; r < t->nresins && n < sizeof list; ++r)
            if (t->used[r]) n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", n ? ", " : "", t->resins[r].name);
        const char *material;
        int near = slots_hint(t, &material);
        if (near < 0)
            return hv_error_set(HV_ERR_INVALID, "tray: %d resins (%s) exceed the %s's %d material slots", slots, list,
                                t->profile->name, t->profile->material_slots);
        return hv_error_option(HV_ERR_INVALID, "tray: %d resins (%s) exceed the %s's %d material slots; print %s in a "
                               "resin already used, e.g. {resin} %s=%s (the nearest in display colour)", slots, list,
                               t->profile->name, t->profile->material_slots, material, material, t->resins[near].name);
    }
    /* palette: 0 is no material (black), then the resins used, in the table's order */
    memset(t->palette, 0, 3);
    t->palette_size = 1;
    for (int r = 0; r < t->nresins; ++r)
        if (t->used[r]) {
            t->pal_resin[t->palette_size] = r;
            memcpy(t->palette + 3 * t->palette_size, t->resins[r].rgb, 3);
            t->used[r] = t->palette_size++;
        }
    for (int i = 0; i < t->nsrc; ++i)
        for (int j = 0; j < t->src[i].m; ++j) t->src[i].resin[j] = t->used[t->src[i].resin[j]];
    if (o->mode == HV_LAYERS_MASK) t->bit_depth = 1;
    else t->bit_depth = t->palette_size <= 2 ? 1 : t->palette_size <= 4 ? 2 : t->palette_size <= 16 ? 4 : 8;
    return HV_OK;
}

/* Place every instance without a position: largest footprint first, the first free spot
 * scanning rows from the plate's far edge and columns from x = 0 in 1 mm steps, the spacing
 * kept from the plate's edges too. */
static hv_status arrange(hv_tray *t, occupancy *occ, const int *order, int n)
{
    for (int k = 0; k < n; ++k) {
        instance *in = &t->inst[order[k]];
        const source *s = &t->src[in->src];
        const footprint *f = &s->fp, *d = &s->dil;
        int found = 0, kk = (f->x0 - d->x0) > 0 ? (int)lround((f->x0 - d->x0) / CELL) : 0;
        for (int cy = occ->h - f->h - kk; cy >= kk && !found; cy -= 2)
            for (int cx = kk; cx + f->w + kk <= occ->w && !found; cx += 2) {
                if (occ_hits(occ, d, cx - kk, cy - kk)) continue;
                occ_add(occ, f, cx, cy);
                in->cx = cx;
                in->cy = cy;
                in->x = cx * CELL + 0.5 * (s->bmax[0] - s->bmin[0]);
                in->y = cy * CELL + 0.5 * (s->bmax[1] - s->bmin[1]);
                in->arranged = 1;
                found = 1;
            }
        if (!found) {
            char list[2048], nb[256];
            size_t m = 0;
            for (int j = k; j < n && m < sizeof list; ++j)
                m += (size_t)snprintf(list + m, sizeof list - m, "%s%s", j > k ? ", " : "",
                                      inst_name(t, &t->inst[order[j]], nb, sizeof nb));
            return hv_error_set(HV_ERR_LIMIT, "tray: no room left on the %s plate for %s", t->profile->name, list);
        }
    }
    return HV_OK;
}

static int cmp_area_desc(const void *a, const void *b, void *ctx)
{
    const hv_tray *t = ctx;
    const instance *x = &t->inst[*(const int *)a], *y = &t->inst[*(const int *)b];
    double ax = t->src[x->src].fp.area, ay = t->src[y->src].fp.area;
    if (ax != ay) return ax > ay ? -1 : 1;
    return *(const int *)a - *(const int *)b;
}

/* a deterministic insertion sort (qsort_r is not portable C11) */
static void sort_order(int *order, int n, hv_tray *t)
{
    for (int i = 1; i < n; ++i)
        for (int j = i; j > 0 && cmp_area_desc(&order[j - 1], &order[j], t) > 0; --j) {
            int x = order[j];
            order[j] = order[j - 1];
            order[j - 1] = x;
        }
}

/* Positions, plate bounds and spacing. */
static hv_status place_all(hv_tray *t, const hv_tray_options *o)
{
    const double *B = t->profile->build;
    occupancy occ = {(int)floor(B[0] / CELL), (int)floor(B[1] / CELL), NULL, NULL};
    occ.cell = hv_calloc((size_t)occ.w * (size_t)occ.h, 1);
    occ.pre = hv_calloc((size_t)(occ.w + 1) * (size_t)occ.h, sizeof *occ.pre);
    int *order = hv_malloc_array((size_t)t->ninst + 1, sizeof *order);
    hv_status st = occ.cell && occ.pre && order ? HV_OK : HV_ERR_NOMEM;
    int n_arr = 0;
    char nb[256], nb2[256];
    /* given positions first, each checked against the ones before it */
    for (int i = 0; i < t->ninst && st == HV_OK; ++i) {
        instance *in = &t->inst[i];
        const source *s = &t->src[in->src];
        if (o->arrange == 2 || (!s->p.placed && o->arrange == 1)) {
            order[n_arr++] = i;
            continue;
        }
        if (!s->p.placed) {
            st = hv_error_set(HV_ERR_INVALID, "%s%s%s has no position: give it one (--part PART@X,Y; \"at\": [X, Y] in a job file; at = {X, Y} in "
                              "Lua) or arrange the tray",
                              where_of(t, in), WHERE_SEP(t, in), inst_name(t, in, nb, sizeof nb));
            break;
        }
        double wx = s->bmax[0] - s->bmin[0], wy = s->bmax[1] - s->bmin[1];
        /* copies in a row: the width plus the spacing on the footprint grid, so the spacing check
         * below passes for them by construction */
        int pitch = s->fp.w + dilation_cells(o->spacing);
        in->x = s->p.at[0] + in->copy * pitch * CELL;
        in->y = s->p.at[1];
        double x0 = in->x - 0.5 * wx, y0 = in->y - 0.5 * wy;
        if (x0 < -1e-9 || y0 < -1e-9 || x0 + wx > B[0] + 1e-9 || y0 + wy > B[1] + 1e-9) {
            st = hv_error_set(HV_ERR_INVALID, "%s%s%s is off the %s plate: its box spans x %.4g..%.4g, y %.4g..%.4g mm "
                              "(the plate is %g x %g mm)", where_of(t, in), WHERE_SEP(t, in),
                              inst_name(t, in, nb, sizeof nb), t->profile->name, x0,
                              x0 + wx, y0, y0 + wy, B[0], B[1]);
            break;
        }
        in->cx = (int)lround((s->p.at[0] - 0.5 * wx) / CELL) + in->copy * pitch;
        in->cy = (int)lround(y0 / CELL);
        /* against every part placed before it whose heights come within the spacing: parts may
         * stand above one another (the printer builds support under them) */
        double z0 = s->p.z, z1 = z0 + s->bmax[2] - s->bmin[2];
        int kk = (int)lround((s->fp.x0 - s->dil.x0) / CELL);
        for (int j = 0; j < i && st == HV_OK; ++j) {
            const instance *oj = &t->inst[j];
            const source *sj = &t->src[oj->src];
            if (o->arrange == 2 || (!sj->p.placed && o->arrange == 1)) continue; /* arranged later */
            double w0 = sj->p.z, w1 = w0 + sj->bmax[2] - sj->bmin[2];
            if (z0 >= w1 + o->spacing || w0 >= z1 + o->spacing) continue;
            if (!fp_meet(&s->dil, in->cx - kk, in->cy - kk, &sj->fp, oj->cx, oj->cy)) continue;
            if (o->spacing > 0)
                st = hv_error_set(HV_ERR_INVALID, "%s%s%s comes closer than %g mm to %s (their footprints, at heights "
                                  "that overlap)", where_of(t, in), WHERE_SEP(t, in), inst_name(t, in, nb, sizeof nb),
                                  o->spacing, inst_name(t, oj, nb2, sizeof nb2));
            else
                st = hv_error_set(HV_ERR_INVALID, "%s%s%s overlaps %s (their footprints, at heights that overlap)",
                                  where_of(t, in), WHERE_SEP(t, in), inst_name(t, in, nb, sizeof nb),
                                  inst_name(t, oj, nb2, sizeof nb2));
        }
        if (st != HV_OK) break;
        occ_add(&occ, &s->fp, in->cx, in->cy);
    }
    if (st == HV_OK && n_arr) {
        sort_order(order, n_arr, t);
        st = arrange(t, &occ, order, n_arr);
    }
    /* height and utilisation */
    double area = 0;
    for (int i = 0; i < t->ninst && st == HV_OK; ++i) {
        instance *in = &t->inst[i];
        const source *s = &t->src[in->src];
        area += s->fp.area;
        double lift = s->p.z, top = lift + s->bmax[2] - s->bmin[2];
        if (top > B[2] + 1e-9)
            st = hv_error_set(HV_ERR_INVALID, "%s%s%s is %g mm tall at a lift of %g mm: above the %s's %g mm build height",
                              where_of(t, in), WHERE_SEP(t, in), inst_name(t, in, nb, sizeof nb), s->bmax[2] - s->bmin[2], lift, t->profile->name, B[2]);
        in->lift = (size_t)llround(lift / t->profile->layer_height);
    }
    t->utilisation = area / (B[0] * B[1]);
    free(occ.cell);
    free(occ.pre);
    free(order);
    return st;
}

static void part_options(const hv_tray *t, const hv_tray_options *o, const source *s, hv_layers_options *lo)
{
    hv_layers_options_init(lo);
    lo->profile = t->profile->name;
    lo->dpi[0] = t->profile->dpi[0];
    lo->dpi[1] = t->profile->dpi[1];
    lo->layer_height = t->profile->layer_height;
    lo->mode = o->mode == HV_LAYERS_MASK || !s->graded ? HV_LAYERS_MASK : HV_LAYERS_HALFTONE;
    lo->seed = o->seed;
    lo->margin = 0;
    lo->cache_dir = o->cache_dir;
    lo->mesh_name = s->p.mesh;
    lo->model_name = s->p.scan ? s->p.scan : s->p.model;
    lo->source = s->ssrc ? hv_scan_source_layers(s->ssrc) : NULL;
    lo->max_memory = o->max_memory;
}

/* Bytes of a drawn layer as png.c encodes it, measured (scripts/bench/98-png.sh). Sparse layers
 * (the span coder): a part's row costs about its first threshold tile's width of literals (64
 * pixels; after it, copies one tile back or from the other copies of a part), so bytes per part
 * row and bit of depth: fitted on the README's tray (4-bit, 1,461 layers), the bench tray's
 * sparse tops (2-bit, its knots, layers 1700:1760) and the small graded boxes of the CLI case
 * tray_estimate_fits_the_stack (2-bit): 0.91, 1.11 and 0.90 of the bytes written (box pixels,
 * as before the copies, were 0.71 to 1.41: a knot's box is mostly empty, a gear's full). Mask
 * mode (1 bit) adds a little per box pixel: the README's tray 0.94, the CLI case 1.00. Dense
 * layers (libdeflate at level 1): per part-box pixel and per plate row, on the bench tray. */
#define EST_SPAN_ROW_HALFTONE (60.4 / 8) /* per part row and bit of depth */
#define EST_SPAN_ROW_MASK (35.0 / 8)
#define EST_SPAN_BOX_MASK (0.01 / 8) /* per box pixel and bit of depth */
#define EST_DEFLATE_HALFTONE 0.0158 /* bench tray: 0.0147 over its 1,461 dense layers */
#define EST_DEFLATE_MASK 0.0031
#define EST_DEFLATE_ROW 1.5 /* a blank row of a dense layer, bytes */

/* The stack's PNG bytes, layer by layer: png.c sends a layer whose drawn spans (here the part
 * boxes' extent row by row) hold under a quarter of the plate's bytes to its span coder, which
 * writes each blank stretch as 258-byte copies of about 2 bits, the others to libdeflate. */
static double est_png_bytes(const hv_tray *t, int mask, size_t first, size_t last)
{
    size_t rowbytes = ((size_t)t->W * (size_t)t->bit_depth + 7) / 8;
    double plate = (double)rowbytes * t->H, blank = t->H * (double)(rowbytes + 1) / 258.0 * 0.25;
    int n = t->ninst;
    int *on = hv_malloc((size_t)(n ? n : 1) * 3 * sizeof *on), *edge = on + n;
    if (!on) return 0;
    double total = 0;
    for (size_t li = first; li < last; ++li) {
        int k = 0, ne = 0;
        double box = 0, rows = 0;
        for (int i = 0; i < n; ++i)
            if (t->inst[i].lift <= li && li < t->inst[i].lift + t->inst[i].layers) {
                on[k++] = i;
                box += (double)t->inst[i].w * t->inst[i].h;
                rows += t->inst[i].h;
                edge[ne++] = t->inst[i].r0;
                edge[ne++] = t->inst[i].r0 + t->inst[i].h;
            }
        /* the drawn bytes: between the row bands' edges, from the leftmost box to the rightmost */
        double drawn = 0;
        for (int a = 0; a < ne && k <= 32; ++a) { /* many parts: the boxes' own bytes below */
            int y0 = edge[a], y1 = INT_MAX;
            for (int b = 0; b < ne; ++b)
                if (edge[b] > y0 && edge[b] < y1) y1 = edge[b];
            int dup = 0;
            for (int b = 0; b < a; ++b) dup |= edge[b] == y0;
            if (dup || y1 == INT_MAX) continue;
            int x0 = INT_MAX, x1 = 0;
            for (int j = 0; j < k; ++j) {
                const instance *in = &t->inst[on[j]];
                if (in->r0 <= y0 && y0 < in->r0 + in->h) x0 = HV_MIN(x0, in->c0), x1 = HV_MAX(x1, in->c0 + in->w);
            }
            if (x1 > x0) drawn += (double)(x1 - x0) * t->bit_depth / 8.0 * (y1 - y0);
        }
        if (k > 32) drawn = box * t->bit_depth / 8.0;
        if (drawn * 4 < plate)
            total += (mask ? rows * EST_SPAN_ROW_MASK + box * EST_SPAN_BOX_MASK : rows * EST_SPAN_ROW_HALFTONE) *
                         t->bit_depth + blank;
        else
            total += box * (mask ? EST_DEFLATE_MASK : EST_DEFLATE_HALFTONE) + EST_DEFLATE_ROW * t->H;
    }
    free(on);
    return total;
}

hv_status hv_tray_plan(hv_tray *t, const hv_tray_options *o, const hv_progress *progress, hv_tray_report *rep)
{
    hv_status st = hv_options_check(&k_tray_set, o);
    if (st != HV_OK) return st;
    unplan(t);
    t->loaded = 1;
    t->warnings[0] = '\0';
    if (t->nsrc == 0) return hv_error_set(HV_ERR_INVALID, "tray: no parts");
    t->profile = hv_printer_profile_find(o->profile ? o->profile : "j750");
    t->sx = 25.4 / t->profile->dpi[0];
    t->py = 25.4 / t->profile->dpi[1];
    t->W = (int)lround(t->profile->build[0] / t->sx); /* 490 mm at 600 dpi: 11,575 pixels */
    t->H = (int)lround(t->profile->build[1] / t->py);
    st = setup_resins(t, o);
    int total = 0;
    for (int i = 0; i < t->nsrc && st == HV_OK; ++i) {
        total += t->src[i].p.copies;
        if (total > MAX_PARTS) st = hv_error_set(HV_ERR_LIMIT, "tray: more than %d parts", MAX_PARTS);
    }
    for (int i = 0; i < t->nsrc && st == HV_OK; ++i) {
        if (o->stl_path && t->src[i].p.scan) {
            char lb[512];
            st = hv_error_option(HV_ERR_INVALID, "{stl} writes the parts' meshes; %s is a scan, which has none",
                                 src_label(&t->src[i], lb, sizeof lb));
        }
        if (st == HV_OK) st = load_source(t, &t->src[i], o);
    }
    if (st == HV_OK) st = setup_palette(t, o);
    if (st == HV_OK && !(t->inst = hv_calloc((size_t)total, sizeof *t->inst))) st = HV_ERR_NOMEM;
    for (int i = 0; i < t->nsrc && st == HV_OK; ++i)
        for (int c = 0; c < t->src[i].p.copies; ++c) {
            instance *in = &t->inst[t->ninst++];
            in->src = i;
            in->copy = c;
        }
    if (st == HV_OK) st = place_all(t, o);
    /* each instance as a part job on the plate: its box, its layers, its memory */
    t->nlayers = 0;
    t->memory = 0;
    hv_layers_scratch_need need;
    memset(&need, 0, sizeof need);
    for (int i = 0; i < t->ninst && st == HV_OK; ++i) {
        instance *in = &t->inst[i];
        const source *s = &t->src[in->src];
        hv_layers_options lo;
        part_options(t, o, s, &lo);
        hv_layers_place pl = {in->x, in->y, t->profile->build[1], in->lift, t->profile->build[0], t->profile->name, 1};
        st = hv_layers_part_open(s->from_model ? NULL : s->mesh, s->model, &lo, &pl, progress, &in->part);
        if (st != HV_OK) {
            char nb[256];
            st = hv_error_prefix(st, "%s%s%s: ", where_of(t, in), WHERE_SEP(t, in), inst_name(t, in, nb, sizeof nb));
            break;
        }
        hv_layers_part_geometry(in->part, &in->c0, &in->r0, &in->w, &in->h, &in->layers);
        t->nlayers = HV_MAX(t->nlayers, in->lift + in->layers);
        /* the part's decoded voxel layers, which the threads read (hv_layers_part_prepare) */
        t->memory += hv_layers_part_memory(in->part) + (3 * INFLIGHT + 1) * hv_layers_part_slab_bytes(in->part);
        if (in->copy && s->ssrc) t->memory -= hv_scan_source_layers(s->ssrc)->memory; /* copies share the data */
        hv_layers_scratch_need_add(&need, in->part);
    }
    /* issue 32 item 21: a bounded number of layers in flight (packed plate images and their
     * spans), which the threads share by drawing parts into them, and per thread only the buffers
     * of the one part it renders (the largest part's). The plates are as many as the budget
     * holds, at most INFLIGHT and the threads; memory no longer grows a plate per thread. */
    size_t stride = ((size_t)t->W * (size_t)t->bit_depth + 7) / 8 + 1; /* the filter byte */
    uint64_t plate = (uint64_t)stride * (uint64_t)t->H + (uint64_t)t->H * 8;
    int threads = HV_MAX(hv_threads(), 1);
    uint64_t scratch = (uint64_t)threads * hv_layers_scratch_need_total(&need);
    uint64_t budget = hv_memory_budget(o->max_memory);
    t->inflight = HV_MIN(INFLIGHT, threads);
    while (t->inflight > 1 && budget && t->memory + scratch + (uint64_t)t->inflight * plate > budget) --t->inflight;
    t->memory += scratch + (uint64_t)t->inflight * plate;
    if (st == HV_OK && budget && t->memory > budget) { /* issue 30: a scan's data is most of it */
        char nt[32], bt[32];
        st = hv_error_option(HV_ERR_LIMIT, "tray: the job needs about %s (the parts' data and tables, %d worker%s' "
                             "buffers, %d plate image%s), more than the budget of %s ({max_memory})",
                             hv_size_text(nt, sizeof nt, (double)t->memory), threads, threads == 1 ? "" : "s",
                             t->inflight, t->inflight == 1 ? "" : "s", hv_size_text(bt, sizeof bt, (double)budget));
    }
    if (st == HV_OK && (o->first >= t->nlayers || (o->last && o->last > t->nlayers)))
        st = hv_error_option(HV_ERR_INVALID, "tray: {layers} %zu:%zu is outside the tray's %zu layers", o->first,
                             o->last, t->nlayers);
    if (st != HV_OK) {
        unplan(t);
        return st;
    }
    t->planned = 1;
    if (rep) {
        memset(rep, 0, sizeof *rep);
        rep->width = t->W;
        rep->height = t->H;
        rep->layers = t->nlayers;
        rep->first = o->first;
        rep->last = o->last ? o->last : t->nlayers;
        rep->parts = t->ninst;
        rep->resins = t->palette_size - 1;
        rep->bit_depth = t->bit_depth;
        rep->utilisation = t->utilisation;
        rep->memory = t->memory;
        memcpy(rep->warnings, t->warnings, sizeof rep->warnings);
        double obj = 0; /* the part boxes' voxels in the window's layers only */
        for (int i = 0; i < t->ninst; ++i) {
            size_t lo = HV_MAX(rep->first, t->inst[i].lift), hi = HV_MIN(rep->last, t->inst[i].lift + t->inst[i].layers);
            if (hi > lo) obj += (double)t->inst[i].w * t->inst[i].h * (double)(hi - lo);
        }
        double all = (double)t->W * t->H * (double)(rep->last - rep->first);
        /* the bench tray's rates on 2 cores (box voxels 3.7e10 of a 1.09e11 plate: 72 s halftone,
         * 16 s mask; an empty plate 1.9 s), a little under */
        rep->est_seconds = obj / (o->mode == HV_LAYERS_MASK ? 2e9 : 4.5e8) + all / 4e10;
        rep->est_bytes = est_png_bytes(t, o->mode == HV_LAYERS_MASK, rep->first, rep->last);
    }
    return HV_OK;
}

/* ---- writing ------------------------------------------------------------------------------------ */

typedef struct tplate {
    uint8_t *rows; /* packed plate image, each row after a zero byte (PNG's filter None: the
                      encoder compresses the rows where they lie, hv_png_options.filter_bytes) */
    int32_t *span; /* 2 per row, in bytes: the drawn columns (empty when span[0] >= span[1]) */
} tplate;

/* The layers run_lo..run_hi as one ordered sequence of items: per layer each part that meets it
 * drawn into the layer's plate (largest image first), then the layer encoded and written. The
 * threads take the items in order and wait (blocking, not spinning) only for what an item needs:
 * a draw for its plate (one of `inflight`, in turn) to be written and cleared, an encode for its
 * layer's draws. Every item waits only for earlier ones, so the sequence always moves on; no
 * barrier between layers (the layers in flight in lockstep left a core idle while the other drew
 * a large part, and spun on loaded machines: the README's tray 6.9-9.9 s -> 11.2-15.9 s). */
typedef struct wjob {
    hv_tray *t;
    const hv_tray_options *o;
    const char *tmp;
    size_t first, last;
    size_t run_lo, run_hi; /* the layers this process writes */
    size_t stride;
    int k;                 /* plates in flight: layer li draws into plate[(li - run_lo) % k] */
    tplate *plate;
    int *order;            /* every instance, largest image first */
    hv_layers_scratch **scratch; /* per thread: the buffers of the part it renders */
    pthread_mutex_t lock[ROW_LOCKS];
    uint64_t *st_bytes;
    atomic_int cancel;
    const hv_progress *progress;
    /* the sequence, under mu: the next item (layer cur_li, from order[cur_o] on; ninst: its
     * encode), per plate the layer that may draw into it, per layer its draws not finished */
    pthread_mutex_t mu;
    pthread_cond_t cv;
    size_t cur_li;
    int cur_o;
    size_t *free_for;
    uint32_t *draws_left;
    size_t encoded;
} wjob;

/* whole bytes at a time where the run covers them; BITS a constant where it is inlined, so the
 * bytes' inner loop unrolls (a 4-bit plate, six colour resins, packed at the 2-bit plate's cost per
 * pixel, where the loop over a run-time depth took it 1.45 times as long) */
static inline __attribute__((always_inline)) void or_packed(uint8_t *row, int BITS, int x0, const uint8_t *sp, int n,
                                                            const uint8_t *lut)
{
    int per = 8 / BITS, k = 0, x = x0;
    for (; k < n && x % per; ++k, ++x)
        row[x / per] |= (uint8_t)(lut[sp[k]] << (8 - BITS - BITS * (x % per)));
    uint8_t *byte = row + x / per;
    for (; k + per <= n; k += per, x += per) {
        unsigned v = 0;
        for (int i = 0; i < per; ++i) v = v << BITS | lut[sp[k + i]];
        *byte++ |= (uint8_t)v;
    }
    for (; k < n; ++k, ++x)
        row[x / per] |= (uint8_t)(lut[sp[k]] << (8 - BITS - BITS * (x % per)));
}

void hv_tray_or_packed(uint8_t *row, int bits, int x0, const uint8_t *sp, int n, const uint8_t *lut)
{
    switch (bits) {
    case 1: or_packed(row, 1, x0, sp, n, lut); break;
    case 2: or_packed(row, 2, x0, sp, n, lut); break;
    default: or_packed(row, 4, x0, sp, n, lut); break;
    }
}

/* Part i's layer li drawn into its plate (threads draw parts of one layer at once: OR and the
 * span's min/max are order-free, so the bytes do not depend on the threads). */
static hv_status draw_part(wjob *J, hv_layers_scratch *sc, int i, size_t li)
{
    hv_tray *t = J->t;
    int bits = t->bit_depth;
    tplate *pl = &J->plate[(li - J->run_lo) % (size_t)J->k];
    instance *in = &t->inst[i];
    const uint8_t *px;
    hv_status st = hv_layers_part_render(in->part, sc, li - in->lift, &px);
    if (st != HV_OK) return st;
    const source *s = &t->src[in->src];
    uint8_t lut[HV_MAX_MATERIALS + 2];
    lut[0] = 0;
    for (int j = 0; j < s->m; ++j) lut[j + 1] = (uint8_t)(J->o->mode == HV_LAYERS_MASK ? 1 : s->resin[j]);
    if (!s->graded) lut[1] = (uint8_t)(J->o->mode == HV_LAYERS_MASK ? 1 : s->resin[0]);
    /* the columns of the part's image that fall on the plate */
    int ca = HV_MAX(0, -in->c0), cb = HV_MIN(in->w, t->W - in->c0);
    for (int r = 0; r < in->h && ca < cb; ++r) {
        int y = in->r0 + r;
        if (y < 0 || y >= t->H) continue;
        const uint8_t *src = px + (size_t)r * (size_t)in->w;
        int a = ca, b = cb;
        while (a < b && !src[a]) ++a;
        if (a == b) continue;
        while (!src[b - 1]) --b;
        uint8_t *row = pl->rows + (size_t)y * J->stride;
        int x0 = in->c0 + a;
        const uint8_t *sp = src + a;
        int n = b - a;
        int32_t b0 = (int32_t)((size_t)x0 * (size_t)bits / 8);
        int32_t b1 = (int32_t)((size_t)(x0 + n - 1) * (size_t)bits / 8 + 1);
        pthread_mutex_t *lk = &J->lock[y % ROW_LOCKS];
        pthread_mutex_lock(lk);
        /* OR the packed values in (background stays 0, so parts never erase each other) */
        if (bits == 8)
            for (int k = 0; k < n; ++k) row[x0 + k] |= lut[sp[k]];
        else
            hv_tray_or_packed(row, bits, x0, sp, n, lut);
        int32_t *spn = pl->span + 2 * y;
        if (spn[0] >= spn[1]) {
            spn[0] = b0;
            spn[1] = b1;
        } else {
            spn[0] = HV_MIN(spn[0], b0);
            spn[1] = HV_MAX(spn[1], b1);
        }
        pthread_mutex_unlock(lk);
    }
    return HV_OK;
}

static int cmp_image_desc(const int *a, const int *b, const hv_tray *t)
{
    const instance *x = &t->inst[*a], *y = &t->inst[*b];
    double ax = (double)x->w * x->h, ay = (double)y->w * y->h;
    if (ax != ay) return ax > ay ? -1 : 1;
    return (*a > *b) - (*a < *b);
}

static int meets(const instance *in, size_t li) { return li >= in->lift && li < in->lift + in->layers; }

/* Layer li encoded, written and its plate cleared. */
static hv_status encode_layer(wjob *J, size_t li)
{
    hv_tray *t = J->t;
    hv_status st = HV_OK;
    {
        tplate *pl = &J->plate[(li - J->run_lo) % (size_t)J->k];
        char path[4200];
        snprintf(path, sizeof path, "%s/layer-%05zu.png", J->tmp, li);
        uint8_t *png = NULL;
        size_t size = 0;
        /* the one encoder; the drawn spans tell it where the nonzero bytes are, so a sparse plate
         * (small parts on a J750 plate, the tops of tall parts) costs its parts, not its 26 MB */
        hv_png_options po;
        hv_png_options_init(&po);
        po.compression = 1; /* layers' default level: halftone noise gains little above it */
        po.dpi[0] = t->profile->dpi[0];
        po.dpi[1] = t->profile->dpi[1];
        po.bit_depth = t->bit_depth;
        po.packed = t->bit_depth < 8;
        po.row_spans = pl->span;
        po.filter_bytes = 1;
        if (J->o->mode != HV_LAYERS_MASK) {
            po.palette = t->palette;
            po.palette_size = t->palette_size;
        }
        st = hv_png_encode(pl->rows, t->W, t->H, 1, J->stride, &po, &png, &size);
        /* in the stack's temporary directory, synced once and renamed whole (as layers writes) */
        if (st == HV_OK) st = hv_write_in_place(path, png, size);
        free(png);
        J->st_bytes[li - J->first] = size;
        /* clear what was drawn */
        for (int r = 0; r < t->H; ++r) {
            int32_t *spn = pl->span + 2 * r;
            if (spn[0] < spn[1]) memset(pl->rows + (size_t)r * J->stride + spn[0], 0, (size_t)(spn[1] - spn[0]));
            spn[0] = spn[1] = 0;
        }
    }
    return st;
}

/* The next item under J->mu: an instance to draw into layer *li, -1 the encode of *li, -2 none. */
static int next_item(wjob *J, size_t *li)
{
    hv_tray *t = J->t;
    if (J->cur_li >= J->run_hi) return -2;
    *li = J->cur_li;
    while (J->cur_o < t->ninst) {
        int i = J->order[J->cur_o++];
        if (meets(&t->inst[i], *li)) return i;
    }
    J->cur_li++;
    J->cur_o = 0;
    return -1;
}

static hv_status failed(wjob *J, hv_status st)
{
    pthread_mutex_lock(&J->mu);
    atomic_store(&J->cancel, 1);
    pthread_cond_broadcast(&J->cv);
    pthread_mutex_unlock(&J->mu);
    return st;
}

/* A thread's share: items in sequence until none is left. */
static hv_status tray_worker(void *ctx, size_t b, size_t e, int thread)
{
    (void)b, (void)e;
    wjob *J = ctx;
    hv_layers_scratch **sc = &J->scratch[thread];
    hv_status st = HV_OK;
    for (;;) {
        if (hv_cancel_requested()) return failed(J, hv_error_set(HV_ERR_CANCELLED, "tray: cancelled"));
        size_t li = 0, plate;
        pthread_mutex_lock(&J->mu);
        int item = atomic_load(&J->cancel) ? -2 : next_item(J, &li);
        plate = (li - J->run_lo) % (size_t)J->k;
        /* a draw waits for its plate, an encode for its layer's draws */
        while (item != -2 && !atomic_load(&J->cancel) &&
               (item >= 0 ? J->free_for[plate] != li : J->draws_left[li - J->run_lo] != 0))
            pthread_cond_wait(&J->cv, &J->mu);
        int stop = atomic_load(&J->cancel);
        pthread_mutex_unlock(&J->mu);
        if (item == -2 || stop) return HV_OK; /* the failing item returns its error */
        if (item >= 0) {
            if (!*sc && !(*sc = hv_layers_scratch_create())) return failed(J, hv_error_set(HV_ERR_NOMEM, "tray: out of memory"));
            st = draw_part(J, *sc, item, li);
        } else {
            st = encode_layer(J, li);
        }
        if (st != HV_OK) return failed(J, st);
        pthread_mutex_lock(&J->mu);
        int wake;
        if (item >= 0) {
            wake = --J->draws_left[li - J->run_lo] == 0;
        } else {
            J->free_for[plate] = li + (size_t)J->k;
            J->encoded++;
            wake = 1;
        }
        size_t done = J->encoded;
        if (wake) pthread_cond_broadcast(&J->cv);
        pthread_mutex_unlock(&J->mu);
        if (thread == 0 && item < 0 && J->progress &&
            (st = hv_progress_report(J->progress, "tray", (double)done / (double)(J->run_hi - J->run_lo))) != HV_OK)
            return failed(J, st);
    }
}

/* The layers run_lo..run_hi through `inflight` plates, the threads taking the items in order. */
static hv_status tray_run(wjob *J, const hv_progress *progress)
{
    hv_tray *t = J->t;
    int threads = HV_MAX(hv_threads(), 1), k = HV_MAX(t->inflight, 1);
    size_t n = J->run_hi - J->run_lo;
    hv_status st = HV_OK;
    J->k = k;
    J->progress = progress;
    J->cur_li = J->run_lo;
    J->plate = hv_calloc((size_t)k, sizeof *J->plate);
    J->scratch = hv_calloc((size_t)threads, sizeof *J->scratch);
    J->order = hv_calloc((size_t)HV_MAX(t->ninst, 1), sizeof *J->order);
    J->free_for = hv_calloc((size_t)k, sizeof *J->free_for);
    J->draws_left = hv_calloc(n, sizeof *J->draws_left);
    if (!J->plate || !J->scratch || !J->order || !J->free_for || !J->draws_left) st = HV_ERR_NOMEM;
    for (int i = 0; i < k && st == HV_OK; ++i) {
        J->plate[i].rows = hv_calloc((size_t)t->H, J->stride);
        if (J->plate[i].rows) J->plate[i].rows++; /* row y at rows + y * stride, its filter byte before it */
        J->plate[i].span = hv_calloc((size_t)t->H * 2, sizeof *J->plate[i].span);
        if (!J->plate[i].rows || !J->plate[i].span) st = hv_error_set(HV_ERR_NOMEM, "tray: out of memory for a plate image");
        J->free_for[i] = J->run_lo + (size_t)i;
    }
    for (int i = 0; i < t->ninst && st == HV_OK; ++i) {
        J->order[i] = i;
        const instance *in = &t->inst[i];
        for (size_t li = HV_MAX(J->run_lo, in->lift); li < HV_MIN(J->run_hi, in->lift + in->layers); ++li)
            J->draws_left[li - J->run_lo]++;
    }
    for (int i = 1; i < t->ninst && st == HV_OK; ++i) /* at most 4,096 instances, once */
        for (int j = i; j > 0 && cmp_image_desc(&J->order[j - 1], &J->order[j], t) > 0; --j) {
            int x = J->order[j];
            J->order[j] = J->order[j - 1];
            J->order[j - 1] = x;
        }
    for (int i = 0; i < ROW_LOCKS; ++i) pthread_mutex_init(&J->lock[i], NULL);
    pthread_mutex_init(&J->mu, NULL);
    pthread_cond_init(&J->cv, NULL);
    if (st == HV_OK) st = hv_parallel_for((size_t)threads, 1, tray_worker, J, NULL, "tray");
    pthread_cond_destroy(&J->cv);
    pthread_mutex_destroy(&J->mu);
    for (int i = 0; i < ROW_LOCKS; ++i) pthread_mutex_destroy(&J->lock[i]);
    for (int i = 0; i < k && J->plate; ++i) {
        free(J->plate[i].rows ? J->plate[i].rows - 1 : NULL);
        free(J->plate[i].span);
    }
    for (int i = 0; i < threads && J->scratch; ++i) hv_layers_scratch_destroy(J->scratch[i]);
    free(J->plate);
    free(J->scratch);
    free(J->order);
    free(J->free_for);
    free(J->draws_left);
    return st;
}

static json_t *num2(double a, double b)
{
    json_t *x = json_array();
    json_array_append_new(x, hv_json_number(a));
    json_array_append_new(x, hv_json_number(b));
    return x;
}

/* The "colour" of each copy of source si when it is a painted part's skin dE2000 (issue 29) or a
 * scan's colour table's over the values it printed (issue 30; copies share the source, so its
 * figures are the copies' together), into colour[i] per instance i (the manifest's, kept for
 * hv_tray_instance_colour): the map made and the skin read once for all copies
 * (hv_colour_skin_manifests). A profile no longer readable: the part goes without. Returns
 * nonzero when out of memory. */
static int source_colour(hv_tray *t, int si, void **colour)
{
    const source *s = &t->src[si];
    hv_colour_skin base;
    memset(&base, 0, sizeof base);
    hv_status st = HV_OK;
    if (s->model) {
        if (!hv_volume_meta_string(s->model, "hovox.colour.json")) return 0; /* not painted */
        st = hv_colour_map_for_model(s->model, &base.map);
        base.model = s->model;
    } else if (s->ssrc && s->scan_map && hv_scan_source_colour(s->ssrc, &base.samples, &base.rgb, &base.fractions, &base.weight)) {
        base.map = s->scan_map;
    }
    int n = 0;
    for (int i = 0; i < t->ninst; ++i) n += t->inst[i].src == si;
    hv_colour_skin *sk = hv_calloc((size_t)HV_MAX(n, 1), sizeof *sk);
    hv_layers_report *pr = hv_calloc((size_t)HV_MAX(n, 1), sizeof *pr);
    const double **tg = hv_calloc((size_t)HV_MAX(n, 1), sizeof *tg), **ac = hv_calloc((size_t)HV_MAX(n, 1), sizeof *ac);
    int *of = hv_calloc((size_t)HV_MAX(n, 1), sizeof *of);
    void **out = hv_calloc((size_t)HV_MAX(n, 1), sizeof *out);
    int failed = !sk || !pr || !tg || !ac || !of || !out;
    if (st == HV_OK && base.map && !failed) {
        for (int i = 0, c = 0; i < t->ninst; ++i) {
            if (t->inst[i].src != si) continue;
            hv_layers_part_report(t->inst[i].part, &pr[c]);
            sk[c] = base;
            tg[c] = pr[c].target;
            ac[c] = pr[c].achieved;
            of[c++] = i;
        }
        st = hv_colour_skin_manifests(sk, n, s->m, s->mat_name, tg, ac, out);
    }
    if (st != HV_OK && st != HV_ERR_NOMEM) hv_error_clear();
    failed |= st == HV_ERR_NOMEM;
    for (int c = 0; c < n && out && out[c]; ++c) {
        instance *in = &t->inst[of[c]];
        colour[of[c]] = out[c];
        in->coloured = 1;
        in->colour = (hv_tray_colour){.intent = hv_colour_map_intent(sk[c].map),
                                      .printer_voxels = sk[c].printer_voxels,
                                      .target = sk[c].target,
                                      .achieved = sk[c].achieved};
        snprintf(in->cdesc, sizeof in->cdesc, "%s", hv_colour_map_description(sk[c].map));
    }
    if (base.model) hv_colour_map_destroy(base.map);
    free(sk);
    free(pr);
    free(tg);
    free(ac);
    free(of);
    free(out);
    return failed;
}

int hv_tray_instance_colour(const hv_tray *t, int i, hv_tray_colour *out)
{
    memset(out, 0, sizeof *out);
    if (i < 0 || i >= t->ninst || !t->inst[i].coloured) return 0;
    const instance *in = &t->inst[i];
    *out = in->colour;
    out->description = in->cdesc; /* here: instances move when the tray grows */
    return 1;
}

/* The manifest's document (NULL: out of memory). */
static json_t *manifest_doc(hv_tray *t, const hv_tray_options *o, const hv_tray_report *rep, const uint64_t *obj_px)
{
    json_t *doc = json_object();
    int failed = 0;
    char gen[64];
    snprintf(gen, sizeof gen, "hovox %s", hv_version());
    failed |= hv_json_set(doc, "generator", hv_json_text(gen));
    failed |= hv_json_set(doc, "kind", hv_json_text("tray"));
    failed |= hv_json_set(doc, "profile", hv_json_text(t->profile->name));
    failed |= hv_json_set(doc, "dpi", num2(t->profile->dpi[0], t->profile->dpi[1]));
    failed |= hv_json_set(doc, "layer_height_mm", hv_json_number(t->profile->layer_height));
    failed |= hv_json_set(doc, "plate_mm", num2(t->profile->build[0], t->profile->build[1]));
    failed |= hv_json_set(doc, "width", json_integer(t->W));
    failed |= hv_json_set(doc, "height", json_integer(t->H));
    failed |= hv_json_set(doc, "bit_depth", json_integer(t->bit_depth));
    failed |= hv_json_set(doc, "mode", hv_json_text(hv_layers_mode_name(o->mode)));
    failed |= hv_json_set(doc, "layers_total", json_integer((json_int_t)t->nlayers));
    failed |= hv_json_set(doc, "first", json_integer((json_int_t)rep->first));
    failed |= hv_json_set(doc, "last", json_integer((json_int_t)rep->last));
    failed |= hv_json_set(doc, "utilisation", hv_json_number(t->utilisation));
    json_t *pal = json_array();
    for (int k = 0; k < t->palette_size && o->mode != HV_LAYERS_MASK; ++k) {
        json_t *e = json_object();
        char hex[8];
        snprintf(hex, sizeof hex, "#%02x%02x%02x", t->palette[3 * k], t->palette[3 * k + 1], t->palette[3 * k + 2]);
        failed |= hv_json_set(e, "index", json_integer(k));
        failed |= hv_json_set(e, "resin", k ? hv_json_text(t->resins[t->pal_resin[k]].name) : json_null());
        failed |= hv_json_set(e, "color", hv_json_text(hex));
        failed |= json_array_append_new(pal, e);
    }
    failed |= hv_json_set(doc, "palette", pal);
    failed |= hv_json_set(doc, "resin_colors_note",
                          hv_json_text("public resin names; display colours chosen by hovox, not vendor-confirmed"));
    json_t *parts = json_array();
    void **colour = hv_calloc((size_t)HV_MAX(t->ninst, 1), sizeof *colour);
    failed |= !colour;
    for (int i = 0; i < t->ninst; ++i) t->inst[i].coloured = 0;
    for (int si = 0; si < t->nsrc && colour && o->mode == HV_LAYERS_HALFTONE; ++si) failed |= source_colour(t, si, colour);
    for (int i = 0; i < t->ninst; ++i) {
        const instance *in = &t->inst[i];
        const source *s = &t->src[in->src];
        json_t *p = json_object();
        failed |= hv_json_set(p, "name", hv_json_text(s->p.name));
        failed |= hv_json_set(p, "copy", json_integer(in->copy + 1));
        failed |= hv_json_set(p, "mesh", s->p.mesh ? hv_json_text(s->p.mesh) : json_null()); /* null: the model's own */
        if (s->p.scan) failed |= hv_json_set(p, "scan", hv_json_text(s->p.scan));
        failed |= hv_json_set(p, "model", s->p.model ? hv_json_text(s->p.model) : json_null());
        failed |= hv_json_set(p, "at_mm", num2(in->x, in->y));
        failed |= hv_json_set(p, "lift_layers", json_integer((json_int_t)in->lift));
        failed |= hv_json_set(p, "rotation", json_integer(s->p.rotation));
        if (hv_placement_given(&s->p.place)) {
            char placed[1024];
            failed |= hv_json_set(p, "placement", hv_json_text(hv_placement_describe(&s->p.place, placed, sizeof placed)));
        }
        double wx = s->bmax[0] - s->bmin[0], wy = s->bmax[1] - s->bmin[1];
        json_t *box = json_array();
        json_array_append_new(box, hv_json_number(in->x - 0.5 * wx));
        json_array_append_new(box, hv_json_number(in->y - 0.5 * wy));
        json_array_append_new(box, hv_json_number(in->x + 0.5 * wx));
        json_array_append_new(box, hv_json_number(in->y + 0.5 * wy));
        failed |= hv_json_set(p, "box_mm", box);
        json_t *px = json_array();
        json_array_append_new(px, json_integer(in->c0));
        json_array_append_new(px, json_integer(in->r0));
        json_array_append_new(px, json_integer(in->w));
        json_array_append_new(px, json_integer(in->h));
        failed |= hv_json_set(p, "image_px", px);
        failed |= hv_json_set(p, "layers", num2((double)in->lift, (double)(in->lift + in->layers)));
        failed |= hv_json_set(p, "object_pixels", json_integer((json_int_t)obj_px[i]));
        hv_layers_report pr;
        hv_layers_part_report(in->part, &pr);
        json_t *mats = json_object();
        for (int j = 0; j < s->m; ++j) {
            json_t *mj = json_object();
            failed |= hv_json_set(mj, "resin", hv_json_text(t->resins[t->pal_resin[s->resin[j]]].name));
            if (s->graded && o->mode == HV_LAYERS_HALFTONE) {
                failed |= hv_json_set(mj, "target", hv_json_number(pr.target[j]));
                failed |= hv_json_set(mj, "achieved", hv_json_number(pr.achieved[j]));
            }
            failed |= hv_json_set(mats, s->mat_name[j], mj);
        }
        failed |= hv_json_set(p, "materials", mats);
        if (colour && colour[i]) failed |= hv_json_set(p, "colour", colour[i]);
        failed |= json_array_append_new(parts, p);
    }
    free(colour);
    failed |= hv_json_set(doc, "parts", parts);
    return hv_stack_manifest_done(doc, failed);
}

/* GCVF: ConfigFile.xml's resins (or the mask's one material); stack.c writes the rest. */
static void gcvf_of(const hv_tray *t, const hv_tray_options *o, const hv_tray_report *rep, hv_gcvf *g)
{
    hv_gcvf_init(g, t->profile->dpi, t->profile->layer_height, t->W, t->H, rep->first, rep->last, t->bit_depth,
                 o->mode == HV_LAYERS_MASK ? 2 : t->palette_size);
    if (o->mode == HV_LAYERS_MASK) {
        hv_gcvf_add(g, "model", (const uint8_t *)"\xff\xff\xff", rep->object_pixels);
        return;
    }
    for (int k = 1; k < t->palette_size; ++k) hv_gcvf_add(g, t->resins[t->pal_resin[k]].name, t->palette + 3 * k, 0);
}

/* Layer costs: the boxes of the parts a layer holds, and a fiftieth of the plate (its empty
 * pixels); then the ranges of `size` processes and their shares. */
/* The plan's fingerprint: plate image, layers, palette, every instance's place and size, every
 * part's mesh (its vertices and facets) and model (its lattice and leaves). */
static uint64_t tray_hash(const hv_tray *t, size_t first, size_t last)
{
    uint64_t h = HV_PLAN_HASH0;
    int64_t v[] = {t->W, t->H, t->bit_depth, (int64_t)t->nlayers, (int64_t)first, (int64_t)last, t->nresins,
                   t->ninst, t->nsrc};
    h = hv_plan_hash(h, v, sizeof v);
    h = hv_plan_hash(h, t->used, sizeof t->used);
    for (int k = 0; k < t->ninst; ++k) {
        const instance *I = &t->inst[k];
        int64_t w[] = {I->src, I->copy, (int64_t)I->lift, I->c0, I->r0, I->w, I->h, (int64_t)I->layers};
        h = hv_plan_hash(h, w, sizeof w);
    }
    for (int i = 0; i < t->nsrc; ++i) {
        const source *S = &t->src[i];
        h = hv_plan_hash(h, S->bmin, sizeof S->bmin);
        h = hv_plan_hash(h, S->bmax, sizeof S->bmax);
        if (S->mesh) {
            h = hv_plan_hash(h, hv_mesh_vertices(S->mesh), 3 * sizeof(float) * hv_mesh_vertex_count(S->mesh));
            h = hv_plan_hash(h, hv_mesh_facets(S->mesh), 3 * sizeof(uint32_t) * hv_mesh_facet_count(S->mesh));
        }
        if (S->model) {
            hv_transform xf = hv_volume_get_transform(S->model);
            uint64_t leaves = hv_volume_leaf_count(S->model);
            h = hv_plan_hash(h, &xf, sizeof xf);
            h = hv_plan_hash(h, &leaves, sizeof leaves);
        }
    }
    return h;
}

static hv_status tray_partition(const hv_tray *t, size_t first, size_t last, int size, size_t *ranges, double *share)
{
    size_t n = last - first;
    double *cost = hv_calloc(n ? n : 1, sizeof *cost), total = 0;
    if (!cost) return HV_ERR_NOMEM;
    for (size_t i = 0; i < n; ++i) {
        size_t li = first + i;
        cost[i] = 0.02 * (double)t->W * t->H;
        for (int k = 0; k < t->ninst; ++k)
            if (li >= t->inst[k].lift && li < t->inst[k].lift + t->inst[k].layers)
                cost[i] += (double)t->inst[k].w * t->inst[k].h;
        total += cost[i];
    }
    hv_dist_partition(cost, first, last, RUN, size, ranges);
    for (int r = 0; share && r < size; ++r) {
        double part = 0;
        for (size_t i = ranges[2 * r]; i < ranges[2 * r + 1]; ++i) part += cost[i - first];
        share[r] = total > 0 ? part / total : 0;
    }
    free(cost);
    return HV_OK;
}

hv_status hv_tray_partition(hv_tray *t, const hv_tray_options *o, int ranks, size_t *ranges, double *share)
{
    hv_tray_report rep;
    if (ranks < 1) return hv_error_set(HV_ERR_INVALID, "tray: %d processes", ranks);
    hv_status st = hv_tray_plan(t, o, NULL, &rep);
    return st == HV_OK ? tray_partition(t, rep.first, rep.last, ranks, ranges, share) : st;
}

/* Every instance's (turned) mesh moved to its place: one STL in plate coordinates. */
static hv_status write_stl(const hv_tray *t, const char *path)
{
    size_t nv = 0, nf = 0;
    for (int i = 0; i < t->ninst; ++i) {
        nv += hv_mesh_vertex_count(t->src[t->inst[i].src].mesh);
        nf += hv_mesh_facet_count(t->src[t->inst[i].src].mesh);
    }
    float *xyz = hv_malloc_array(nv * 3, sizeof *xyz);
    uint32_t *f = hv_malloc_array(nf * 3, sizeof *f);
    hv_status st = xyz && f && nv < UINT32_MAX ? HV_OK : HV_ERR_NOMEM;
    size_t v0 = 0, f0 = 0;
    for (int i = 0; i < t->ninst && st == HV_OK; ++i) {
        const instance *in = &t->inst[i];
        const source *s = &t->src[in->src];
        double d[3] = {in->x - 0.5 * (s->bmin[0] + s->bmax[0]), in->y - 0.5 * (s->bmin[1] + s->bmax[1]),
                       (double)in->lift * t->profile->layer_height - s->bmin[2]};
        size_t n = hv_mesh_vertex_count(s->mesh), m = hv_mesh_facet_count(s->mesh);
        const float *v = hv_mesh_vertices(s->mesh);
        const uint32_t *fc = hv_mesh_facets(s->mesh);
        for (size_t k = 0; k < 3 * n; ++k) xyz[3 * v0 + k] = (float)(v[k] + d[k % 3]);
        for (size_t k = 0; k < 3 * m; ++k) f[3 * f0 + k] = (uint32_t)(fc[k] + v0);
        v0 += n;
        f0 += m;
    }
    hv_mesh *all = NULL;
    if (st == HV_OK) st = hv_mesh_create(xyz, nv, f, nf, &all);
    if (st == HV_OK) st = hv_mesh_write_stl(all, path, 0);
    hv_mesh_destroy(all);
    free(xyz);
    free(f);
    return st;
}

hv_status hv_tray_write(hv_tray *t, const char *dir, const hv_tray_options *o, const hv_progress *progress,
                        hv_tray_report *report)
{
    hv_tray_report rep;
    hv_status st = hv_tray_plan(t, o, progress, &rep);
    if (st != HV_OK) return st;
    if (o->dry_run) {
        if (report) *report = rep;
        return HV_OK;
    }
    if (!dir || !*dir) return hv_error_set(HV_ERR_INVALID, "tray: no output directory");
    /* outputs that are inputs are refused before anything is written (the parts are read now) */
    if ((st = hv_output_check(dir, 1)) != HV_OK || (o->stl_path && (st = hv_output_check(o->stl_path, 0)) != HV_OK) ||
        (o->gcvf_path && (st = hv_output_check(o->gcvf_path, 0)) != HV_OK))
        return st;
    const hv_dist *D = o->dist;
    hv_stack_out out;
    wjob J;
    memset(&J, 0, sizeof J);
    J.t = t;
    J.o = o;
    J.first = J.run_lo = rep.first;
    J.last = J.run_hi = rep.last;
    J.stride = ((size_t)t->W * (size_t)t->bit_depth + 7) / 8 + 1; /* a row's bytes after its filter byte */
    J.st_bytes = hv_calloc(rep.last - rep.first, sizeof *J.st_bytes);
    if (st == HV_OK && !J.st_bytes) st = HV_ERR_NOMEM;
    st = hv_stack_open(&out, st, dir, o->force, o->gcvf_path, NULL, D);
    if (D) { /* rank 0 made the directory; each process takes a share of the layers by cost */
        const hv_status agreed = st; /* the same on every process: the collectives below match */
        size_t *ranges = hv_malloc_array((size_t)D->size * 2, sizeof *ranges);
        if (st == HV_OK && !ranges) st = HV_ERR_NOMEM;
        if (st == HV_OK) st = tray_partition(t, rep.first, rep.last, D->size, ranges, NULL);
        if (agreed == HV_OK) st = hv_dist_same_plan(D, tray_hash(t, rep.first, rep.last), st);
        if (st == HV_OK) {
            J.run_lo = ranges[2 * D->rank];
            J.run_hi = ranges[2 * D->rank + 1];
        }
        free(ranges);
    }
    J.tmp = out.tmp;
    if (st == HV_OK) st = hv_progress_report(progress, "tray", 0.0);
    if (st == HV_OK && J.run_hi > J.run_lo) st = tray_run(&J, progress);
    if (D) { /* rank 0 gets every part's statistics and the layers' sizes */
        st = hv_dist_agree(D, st);
        for (int i = 0; i < t->ninst && st == HV_OK; ++i) st = hv_layers_part_gather(t->inst[i].part, D);
        size_t n = rep.last - rep.first;
        double *b = st == HV_OK ? hv_malloc_array(n, sizeof *b) : NULL;
        if (st == HV_OK && !b) st = HV_ERR_NOMEM; /* NOTE: agreed below */
        for (size_t i = 0; b && i < n; ++i) b[i] = (double)J.st_bytes[i];
        if (b) D->sum_to_root(D->ctx, b, n);
        for (size_t i = 0; b && out.root && i < n; ++i) J.st_bytes[i] = (uint64_t)b[i];
        free(b);
    }
    /* rank 0 writes the manifest, the zip and the STL and renames; the others wait for it */
    uint64_t *obj_px = out.root ? hv_calloc((size_t)t->ninst + 1, sizeof *obj_px) : NULL;
    if (st == HV_OK && out.root && !obj_px) st = HV_ERR_NOMEM;
    json_t *doc = NULL;
    hv_gcvf g;
    if (st == HV_OK && out.root) {
        for (size_t i = 0; i < rep.last - rep.first; ++i) rep.bytes += J.st_bytes[i];
        for (int i = 0; i < t->ninst; ++i) {
            hv_layers_report pr;
            hv_layers_part_report(t->inst[i].part, &pr);
            obj_px[i] = pr.object_pixels;
            rep.object_pixels += pr.object_pixels;
        }
        if (!(doc = manifest_doc(t, o, &rep, obj_px))) st = hv_error_set(HV_ERR_NOMEM, "tray: out of memory for the manifest");
    }
    if (st == HV_OK && out.root && o->stl_path) st = write_stl(t, o->stl_path);
    gcvf_of(t, o, &rep, &g);
    st = hv_stack_close(&out, st, dir, o->force, doc, o->manifest, o->manifest_user, &g, o->finish, o->finish_user,
                        progress);
    free(J.st_bytes);
    free(obj_px);
    if (report) *report = rep;
    return st;
}
