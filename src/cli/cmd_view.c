/* src/cli/cmd_view.c - `hovox view STACK_DIR|MODEL [-o PAGE.html]`: a page to open in a web
 * browser (hovox/viewer.h): a slice stack's or tray's layers at the printer's true aspect with
 * side views, outlines and fractions, or a model's slices and renders. The options are the
 * library's (hv_viewer_option_set). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "core/internal.h"
#include "hovox/render.h"
#include "hovox/viewer.h"

typedef struct view_cli {
    const char *output;
} view_cli;

static const hv_option k_local_opts[] = {
    CLI_OUTPUT(view_cli, "FILE.html",
               "the page (default: STACK_DIR/index.html for a stack, MODEL.html next to a model); a stack's page "
               "reaches its layers by paths relative to it",
               0),
};
static const hv_option_set k_local = CLI_LOCAL_SET("view", k_local_opts, view_cli);

static void warn(const hv_viewer_report *r)
{
    for (const char *p = r->warnings; *p;) {
        const char *nl = strchr(p, '\n');
        size_t n = nl ? (size_t)(nl - p) : strlen(p);
        cli_warn("%.*s", (int)n, p);
        p += n + (nl ? 1 : 0);
    }
}

static void report_stack(const char *dir, const char *page, const hv_viewer_report *r)
{
    char sz[32];
    printf("%-11s %s (%s, %zu layer%s of %d x %d pixels, %.6g x %.6g mm)\n", r->kind == HV_VIEWER_TRAY ? "tray" : "stack",
           dir, r->mode, r->layers, r->layers == 1 ? "" : "s", r->width, r->height, r->pixel_mm[0], -r->pixel_mm[1]);
    if (r->kind == HV_VIEWER_TRAY) printf("parts       %d\n", r->parts);
    if (r->cut_step == 1)
        printf("side views  %d row%s and %d column%s%s (every pixel and layer)\n", r->cut_rows, r->cut_rows == 1 ? "" : "s",
               r->cut_cols, r->cut_cols == 1 ? "" : "s", r->kind == HV_VIEWER_TRAY ? " per part" : "");
    else
        printf("side views  %d row%s and %d column%s%s (one pixel and layer in %d)\n", r->cut_rows,
               r->cut_rows == 1 ? "" : "s", r->cut_cols, r->cut_cols == 1 ? "" : "s",
               r->kind == HV_VIEWER_TRAY ? " per part" : "", r->cut_step);
    printf("layers from %s\n", r->base[0] ? r->base : "the page's directory");
    printf("wrote       %s (%s)\n", page, hv_size_text(sz, sizeof sz, (double)r->bytes));
}

static void report_model(const char *path, const char *page, const hv_viewer_report *r)
{
    char sz[32];
    printf("model       %s (%d x %d x %d voxels of %.6g x %.6g x %.6g, %d material%s)\n", path, r->dims[0], r->dims[1],
           r->dims[2], r->voxel[0], r->voxel[1], r->voxel[2], r->materials, r->materials == 1 ? "" : "s");
    printf("slices      %d x, %d y, %d z", r->slices[0], r->slices[1], r->slices[2]);
    if (r->slice_step > 1) printf(" (one voxel in %d in the plane)", r->slice_step);
    printf("\n");
    printf("renders     %d\n", r->render_count);
    printf("wrote       %s (%s)\n", page, hv_size_text(sz, sizeof sz, (double)r->bytes));
}

/* --view of layers and tray (hv_viewer_stack_finish wrote the page): its warnings and where it is
 * (not with -q) */
void cli_view_report(const hv_viewer_report *r, const char *dir, int quiet)
{
    if (!r->bytes) return;
    char sz[32];
    size_t n = strlen(dir);
    while (n > 1 && dir[n - 1] == '/') --n;
    warn(r);
    if (quiet) return;
    printf("page        %.*s/index.html (%s)\n", (int)n, dir, hv_size_text(sz, sizeof sz, (double)r->bytes));
}

/* MODEL.vdb -> MODEL.html (next to it) */
static char *model_page(const char *path)
{
    size_t n = strlen(path);
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (dot && (!slash || dot > slash + 1)) n = (size_t)(dot - path);
    char *out = malloc(n + 6);
    if (out) {
        memcpy(out, path, n);
        memcpy(out + n, ".html", 6);
    }
    return out;
}

static int run(const cli_args *args, void *lib, void *local)
{
    const hv_viewer_options *o = lib;
    const view_cli *c = local;
    const char *path = args->pos[0];
    struct stat sb;
    hv_status s = HV_OK;
    hv_viewer_report r;
    memset(&r, 0, sizeof r);
    cli_progress bar;
    cli_progress_init(&bar, args->quiet);
    hv_progress prog = {cli_progress_fn, &bar};
    if (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode)) {
        char *page = NULL;
        if (!c->output) {
            size_t n = strlen(path);
            while (n > 1 && path[n - 1] == '/') --n;
            page = malloc(n + 12);
            if (page) snprintf(page, n + 12, "%.*s/index.html", (int)n, path);
        }
        const char *out = c->output ? c->output : page;
        s = out ? hv_viewer_stack_write(path, out, o, &prog, &r) : HV_ERR_NOMEM;
        cli_progress_done(&bar);
        if (s == HV_OK) {
            warn(&r);
            if (!args->quiet) report_stack(path, out, &r);
        }
        free(page);
    } else {
        hv_volume *vol = NULL;
        s = hv_render_volume_load(path, &vol);
        char *page = s == HV_OK && !c->output ? model_page(path) : NULL;
        if (s == HV_OK && !c->output && !page) s = HV_ERR_NOMEM;
        const char *out = c->output ? c->output : page;
        if (s == HV_OK) s = hv_viewer_model_write(vol, path, out, o, &prog, &r);
        cli_progress_done(&bar);
        if (s == HV_OK) {
            warn(&r);
            if (!args->quiet) report_model(path, out, &r);
        }
        hv_volume_destroy(vol);
        free(page);
    }
    return s == HV_OK ? EXIT_OK : cli_fail(s);
}

const cli_spec cmd_view = {
    "view", "a page to look at a stack, tray or model in a web browser",
    "STACK_DIR [-o PAGE.html] [options]\n       hovox view MODEL.vdb [-o PAGE.html] [options]",
    "Writes one HTML file with its script, style and data inside, to open in any web browser\n"
    "(from file://, with no network and nothing to install).\n"
    "\n"
    "A slice stack (hovox layers, hovox tray): every layer at the printer's true aspect (pixel\n"
    "size from manifest.json; a J750 pixel is twice as tall as wide), a layer slider, keys,\n"
    "zoom and pan, the palette's colours with their names, each part's outline, box and name,\n"
    "the target and achieved fractions per material and part, and side views (x-z and y-z cuts\n"
    "through the stack at chosen rows and columns). The page loads the layer PNGs from the\n"
    "stack when they are shown (no copy); every layer is read once here for the side views and\n"
    "outlines, and checked against the manifest.\n"
    "\n"
    "A model (.vdb, .3mf): slices through the occupied box along x, y and z coloured by\n"
    "sum p_j colour_j / sum p_j, the fractions under the pointer, and renders.\n",
    hv_viewer_option_set, &k_local,
    "Keys in a stack's page: left/right (or down/up) step layers, PgUp/PgDn by 10, Home/End,\n"
    "+/- zoom, f fit, 1 one layer pixel per screen pixel across, o outlines, s side-view axis,\n"
    "[ ] previous/next cut, shift-click cuts through a point.\n",
    1, 1, "STACK_DIR or MODEL argument", CLI_THREADS | CLI_QUIET | CLI_POS_FILES, run, NULL, NULL};
