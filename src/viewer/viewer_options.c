/* src/viewer/viewer_options.c - the options of viewer pages (hovox/viewer.h, hovox/options.h):
 * names, domains and defaults, read by the CLI (hovox view, and --view of layers and tray). */
#include <stddef.h>

#include "viewer_internal.h"

void hv_viewer_options_init(hv_viewer_options *o)
{
    o->title = NULL;
    o->cuts = 32;
    o->max_samples = 48u << 20;
    o->size[0] = 480;
    o->size[1] = 360;
    o->no_renders = 0;
}

#define OFF(f) offsetof(hv_viewer_options, f)
static const hv_option k_opts[] = {
    {.key = "title", .kind = HV_OPT_STRING, .offset = OFF(title), .meta = "TEXT",
     .help = "the page's title (default: the stack directory's or the model's name)", .section = "Page"},
    {.key = "cuts", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .lo = 1, .hi = 4096, .offset = OFF(cuts), .meta = "N",
     .help = "stacks: side views through at most N evenly spaced rows and N columns of each part (default 32; "
             "every row and column of a smaller image)"},
    {.key = "max_samples", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_UINT64, .lo = 1e4, .hi = 1e11,
     .offset = OFF(max_samples), .meta = "N",
     .help = "samples embedded at most: stacks' side views (pixels x layers x files per layer; past it fewer cuts, "
             "down to 4, then every s-th pixel and layer), models' slices (voxels x (materials + 1); past it fewer "
             "slices, then every q-th voxel); default 50331648"},
    {.key = "size", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .count = 2, .flags = HV_OPT_XSEP, .lo = 16, .hi = 4096,
     .offset = OFF(size), .meta = "W,H", .unit = "pixels", .help = "models: the renders' size (default 480,360)"},
    {.key = "no_renders", .kind = HV_OPT_FLAG, .offset = OFF(no_renders), .help = "models: leave the renders out"},
};
#undef OFF

static void init(void *o) { hv_viewer_options_init(o); }

static const hv_option_set k_set = {"view", k_opts, (int)HV_COUNT(k_opts), sizeof(hv_viewer_options), init,
                                    NULL, 0, NULL, NULL, NULL, 0};

const hv_option_set *hv_viewer_option_set(void) { return &k_set; }
