/* slicing/stack.c - the slice stack on disk, the one writer of `layers` and `tray`
 * (hv_stack_open, hv_stack_close): a temporary directory renamed into place when complete
 * (nothing half-written under the final name; src/core/outdir.c), manifest.json, the
 * GrabCAD voxel-print (GCVF) archive with its ConfigFile.xml (the archive itself:
 * src/core/zip.c, ZIP64 records when it passes 65,535 entries or 4 GiB, which a full J750 tray
 * does many times over), and the partition of layers among processes. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/internal.h"
#include "core/json.h"
#include "layers_internal.h"

/* ---- directories -------------------------------------------------------------------------- */

hv_status hv_stack_manifest_check(const char *text, size_t size)
{
    json_t *doc;
    const char *gen;
    hv_status s = hv_json_parse(text, size, "manifest.json", &doc);
    if (s == HV_OK && (s = hv_json_get_string(doc, "generator", "manifest.json", &gen)) == HV_OK &&
        strncmp(gen, "hovox", 5) != 0)
        s = hv_error_set(HV_ERR_BAD_INPUT, "manifest.json: generator is \"%s\", not hovox", gen);
    json_decref(doc);
    return s;
}

static int stack_manifest_ok(const char *text, size_t size) { return hv_stack_manifest_check(text, size) == HV_OK; }

/* What a stack holds: manifest.json (written by hovox), layer PNGs, and in fractions mode one
 * subdirectory of layer PNGs per material; index.html is the page `hovox view` (or --view) adds. */
static const char *const k_stack_files[] = {"manifest.json", "layer-*.png", "index.html", NULL};
static const hv_outdir_rules k_stack = {
    "stack", "manifest.json", stack_manifest_ok, k_stack_files, 1, 1};

static hv_status stack_begin(const char *dir, int force, char **tmp)
{
    *tmp = NULL;
    /* layer paths are built in 4200-byte buffers: "<tmp>/<material>/layer-NNNNN.png" */
    if (strlen(dir) > 3900) return hv_error_set(HV_ERR_INVALID, "layers: output directory name of %zu bytes is too long", strlen(dir));
    return hv_outdir_begin(dir, &k_stack, force, tmp);
}

static hv_status stack_commit(const char *tmp, const char *dir, int force)
{
    return hv_outdir_commit(tmp, dir, &k_stack, force);
}

static void stack_abort(const char *tmp) { hv_outdir_abort(tmp); }

/* ---- GCVF ConfigFile.xml ------------------------------------------------------------------------- */

/* The layout third-party GCVF writers use for GrabCAD Voxel Print: resolution, slice size and
 * range, bit depth, colours, then the materials with their RGBA and voxel counts. */
static void gcvf_config_begin(hv_buf *x, const double dpi[2], double layer_height, int W, int H, size_t start,
                          size_t count, int bit_depth, int colors, const uint8_t bg[3])
{
    hv_buf_printf(x,
                  "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                  "<!-- GCVF - GrabCAD Voxel Print File, written by hovox %s -->\n"
                  "<GCVF>\n"
                  "    <Version>2</Version>\n"
                  "    <Resolution>\n"
                  "        <XDpi>%.0f</XDpi>\n"
                  "        <YDpi>%.0f</YDpi>\n"
                  "        <SliceThicknessNanoMeter>%.0f</SliceThicknessNanoMeter>\n"
                  "    </Resolution>\n"
                  "    <SliceDimensions>\n"
                  "        <SliceWidth>%d</SliceWidth>\n"
                  "        <SliceHeight>%d</SliceHeight>\n"
                  "    </SliceDimensions>\n"
                  "    <SliceRange>\n"
                  "        <StartIndex>%zu</StartIndex>\n"
                  "        <NumberOfSlices>%zu</NumberOfSlices>\n"
                  "    </SliceRange>\n"
                  "    <BitDepth>%d</BitDepth>\n"
                  "    <MaxNumberOfColors>%d</MaxNumberOfColors>\n"
                  "    <DataSemantics>Materials</DataSemantics>\n"
                  "    <CreationMode>MODEL_ONLY</CreationMode>\n"
                  "    <ImageFilePrefix>layer_</ImageFilePrefix>\n"
                  "    <MaterialList>\n",
                  hv_version(), dpi[0], dpi[1], layer_height * 1e6, W, H, start, count, bit_depth, colors);
    hv_buf_printf(x, "        <BackGroundMaterialRGBA>%d %d %d 255</BackGroundMaterialRGBA>\n", bg[0], bg[1], bg[2]);
}

static void gcvf_config_material(hv_buf *x, const char *name, const uint8_t rgb[3], uint64_t voxels)
{
    hv_buf_printf(x,
                  "        <Material>\n            <Name>%s</Name>\n            <RGBA>%d %d %d 255</RGBA>\n"
                  "            <VoxelCount>%llu</VoxelCount>\n        </Material>\n",
                  name, rgb[0], rgb[1], rgb[2], (unsigned long long)voxels);
}

/* ---- the one stack writer: open, layer files, close (manifest, GCVF, rename) ---------------- */

hv_status hv_stack_open(hv_stack_out *s, hv_status st, const char *dir, int force, const char *gcvf_path,
                        const char *const *subs, const hv_dist *d)
{
    memset(s, 0, sizeof *s);
    s->dist = d;
    s->root = !d || d->rank == 0;
    if (st == HV_OK && gcvf_path && !force && !hv_path_is_special(gcvf_path)) {
        /* like the stack: an existing archive is replaced only when asked */
        struct stat sb;
        if (stat(gcvf_path, &sb) == 0) st = hv_error_option(HV_ERR_IO, "%s: exists ({force} replaces it)", gcvf_path);
    }
    /* the archive's temporary is made before the layers run: an unwritable place fails now */
    if (st == HV_OK && gcvf_path && s->root) st = hv_zip_open(gcvf_path, &s->zip);
    if (st == HV_OK && s->root) st = stack_begin(dir, force, &s->tmp);
    for (size_t i = 0; st == HV_OK && s->root && subs && subs[i]; ++i) {
        char path[4200];
        snprintf(path, sizeof path, "%s/%s", s->tmp, subs[i]);
        if (mkdir(path, 0777) != 0) st = hv_error_set(HV_ERR_IO, "%s: cannot create directory", path);
    }
    if (d) { /* rank 0 made the directory: every process writes its layers into it */
        st = hv_dist_agree(d, st);
        char name[4200] = "";
        if (s->root && s->tmp) snprintf(name, sizeof name, "%s", s->tmp);
        if (st == HV_OK) hv_dist_bcast_string(d, name, sizeof name);
        if (st == HV_OK && !s->root && !(s->tmp = hv_strdup(name))) st = HV_ERR_NOMEM;
        st = hv_dist_agree(d, st); /* the same on every process: the caller's collectives match */
    }
    return st;
}

void hv_stack_layer_path(const hv_stack_out *s, const char *sub, size_t index, char *buf, size_t size)
{
    if (sub) snprintf(buf, size, "%s/%s/layer-%05zu.png", s->tmp, sub, index);
    else snprintf(buf, size, "%s/layer-%05zu.png", s->tmp, index);
}

void hv_gcvf_init(hv_gcvf *g, const double dpi[2], double layer_height, int width, int height, size_t first,
                  size_t last, int bit_depth, int colors)
{
    memset(g, 0, sizeof *g);
    memcpy(g->dpi, dpi, sizeof g->dpi);
    g->layer_height = layer_height;
    g->width = width;
    g->height = height;
    g->first = first;
    g->last = last;
    g->bit_depth = bit_depth;
    g->colors = colors;
}

void hv_gcvf_add(hv_gcvf *g, const char *name, const uint8_t rgb[3], uint64_t voxels)
{
    if (g->materials == (int)HV_COUNT(g->name)) return;
    g->name[g->materials] = name;
    memcpy(g->rgb[g->materials], rgb, 3);
    g->voxels[g->materials++] = voxels;
}

json_t *hv_stack_manifest_done(json_t *doc, int failed)
{
    if (!failed) return doc;
    json_decref(doc);
    return NULL;
}

/* ConfigFile.xml, then the layers copied from the stack's files while the archive is written
 * (stored: PNG data is deflated already). */
static hv_status stack_gcvf(const hv_stack_out *s, const hv_gcvf *g, const hv_progress *progress)
{
    hv_buf x;
    hv_buf_init(&x);
    gcvf_config_begin(&x, g->dpi, g->layer_height, g->width, g->height, g->first, g->last - g->first,
                         g->bit_depth, g->colors, g->background);
    for (int k = 0; k < g->materials; ++k) gcvf_config_material(&x, g->name[k], g->rgb[k], g->voxels[k]);
    hv_buf_puts(&x, "    </MaterialList>\n</GCVF>\n");
    hv_status st = x.failed ? hv_error_set(HV_ERR_NOMEM, "out of memory") : hv_zip_add_data(s->zip, "ConfigFile.xml", x.data, x.len, 1);
    hv_buf_free(&x);
    for (size_t i = g->first; i < g->last && st == HV_OK; ++i) {
        char path[4200], name[64];
        hv_stack_layer_path(s, NULL, i, path, sizeof path);
        snprintf(name, sizeof name, "layer_%zu.png", i);
        st = hv_zip_add_file(s->zip, name, path, 0);
    }
    if (st == HV_OK) st = hv_zip_write(s->zip, progress, "gcvf");
    return st;
}

hv_status hv_stack_close(hv_stack_out *s, hv_status st, const char *dir, int force, json_t *manifest,
                         hv_stack_manifest_fn hook, void *hook_user, const hv_gcvf *gcvf,
                         hv_stack_finish_fn finish, void *finish_user, const hv_progress *progress)
{
    if (s->root) {
        if (st == HV_OK && manifest && hook) st = hook(hook_user, manifest);
        char *text = st == HV_OK && manifest ? hv_json_dump_lines(manifest) : NULL;
        if (st == HV_OK && !text) st = hv_error_set(HV_ERR_NOMEM, "out of memory for the stack's manifest");
        if (st == HV_OK) {
            char path[4200];
            snprintf(path, sizeof path, "%s/manifest.json", s->tmp);
            st = hv_atomic_write(path, text, strlen(text));
        }
        free(text);
        if (st == HV_OK && s->zip && gcvf) st = stack_gcvf(s, gcvf, progress);
        if (st == HV_OK && finish) st = finish(finish_user, s->tmp, dir, progress);
        if (st == HV_OK) st = stack_commit(s->tmp, dir, force);
        if (s->zip) {
            if (st == HV_OK) st = hv_zip_commit(s->zip);
            else hv_zip_abort(s->zip);
        }
        if (st != HV_OK && s->tmp) stack_abort(s->tmp);
    }
    json_decref(manifest);
    if (s->dist) st = hv_dist_agree(s->dist, st);
    free(s->tmp);
    memset(s, 0, sizeof *s);
    return st;
}

/* ---- several processes ---------------------------------------------------------------------- */

void hv_dist_partition(const double *cost, size_t first, size_t last, size_t block, int size, size_t *out)
{
    double total = 0;
    for (size_t i = first; i < last; ++i) total += cost[i - first];
    size_t at = first;
    double done = 0;
    for (int r = 0; r < size; ++r) {
        out[2 * r] = at;
        if (r == size - 1) {
            at = last;
        } else {
            /* the block boundary whose prefix cost comes closest to (r + 1) / size of the total */
            double target = total * (double)(r + 1) / (double)size;
            size_t best = at;
            double best_d = fabs(done - target), acc = done;
            for (size_t i = at; i < last; ++i) {
                acc += cost[i - first];
                size_t b = i + 1;
                if (b % block && b != last) continue;
                double d = fabs(acc - target);
                if (d < best_d) {
                    best_d = d;
                    best = b;
                }
                if (acc > target) break;
            }
            for (size_t i = at; i < best; ++i) done += cost[i - first];
            at = best;
        }
        out[2 * r + 1] = at;
    }
}

hv_status hv_dist_agree(const hv_dist *d, hv_status local)
{
    int worst = d->max_all(d->ctx, (int)local);
    if (worst != HV_OK && local == HV_OK)
        hv_error_set((hv_status)worst, "another process of the job failed (it reported why)");
    return (hv_status)worst;
}

void hv_dist_bcast_string(const hv_dist *d, char *buf, size_t size)
{
    d->bcast(d->ctx, buf, size, 0);
    buf[size - 1] = '\0';
}

uint64_t hv_plan_hash(uint64_t h, const void *data, size_t size)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < size; ++i) h = (h ^ p[i]) * UINT64_C(0x100000001b3);
    return h;
}

hv_status hv_dist_same_plan(const hv_dist *d, uint64_t hash, hv_status local)
{
    uint64_t h0 = hash;
    d->bcast(d->ctx, &h0, sizeof h0, 0);
    double differs = local == HV_OK && h0 != hash ? 1.0 : 0.0;
    d->sum_to_root(d->ctx, &differs, 1);
    if (d->rank == 0 && local == HV_OK && differs > 0)
        local = hv_error_set(HV_ERR_BAD_INPUT,
                             "%.0f of the job's %d processes planned a different job from rank 0's (other options, layer "
                             "heights or input files): every process must be given the same command and the same files",
                             differs, d->size);
    return hv_dist_agree(d, local);
}
