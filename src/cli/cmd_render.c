/* src/cli/cmd_render.c - `hovox render MODEL.vdb -o IMAGE`: ray-cast preview (Wu 2.3) in the
 * material colours, translucent volume or opaque surface, with cut planes and boxes. The
 * options are the library's (hv_render_option_set). */
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "cli.h"
#include "core/internal.h"
#include "hovox/render.h"

typedef struct render_cli {
    const char *output;
} render_cli;

static hv_status check_image_path(const hv_option *o, const void *opts)
{
    const char *path = *(const char *const *)((const char *)opts + o->offset);
    const char *dot = strrchr(path, '.');
    if (dot && !strchr(dot, '/') &&
        (!strcasecmp(dot, ".png") || !strcasecmp(dot, ".exr") || !strcasecmp(dot, ".tif") || !strcasecmp(dot, ".tiff")))
        return HV_OK;
    return hv_error_option(HV_ERR_INVALID, "{output} '%s' has no known image extension (.png, .exr, .tif, .tiff)", path);
}

static const hv_option k_local_opts[] = {
    {.key = "output", .kind = HV_OPT_STRING, .flags = HV_OPT_REQUIRED, .offset = offsetof(render_cli, output),
     .meta = "FILE", .check = check_image_path,
     .help = ".png: 8-bit RGBA (straight alpha); .exr: half float RGBA (premultiplied) and .tif/.tiff: "
             "8-bit RGBA, through OpenImageIO",
     .section = "Output"},
};
static const hv_option_set k_local = {"render", k_local_opts, 1, sizeof(render_cli), NULL, NULL, 0, NULL, NULL, NULL, 0};


static int report(const char *path, const char *output, const hv_render_options *o, int materials)
{
    if (materials) printf("model       %s (%d material%s)\n", path, materials, materials == 1 ? "" : "s");
    else printf("model       %s (no material table: grey)\n", path);
    printf("image       %d x %d, %s, %s%s\n", o->width, o->height, hv_render_mode_name(o->mode),
           o->camera.use_eye ? "eye" : hv_view_name(o->camera.view), o->camera.ortho ? ", orthographic" : "");
    if (o->clips) printf("clips       %d\n", o->clips);
    printf("wrote       %s\n", output);
    return EXIT_OK;
}

static int run(const cli_args *args, void *lib, void *local)
{
    const hv_render_options *o = lib;
    const render_cli *c = local;
    const char *path = args->pos[0];
    hv_volume *vol = NULL;
    hv_status s = hv_render_volume_load(path, &vol);
    if (s != HV_OK) return cli_fail(s);
    cli_progress bar;
    cli_progress_init(&bar, args->quiet);
    hv_progress prog = {cli_progress_fn, &bar};
    hv_render_scene *scene = NULL;
    s = hv_render_scene_create_lazy(vol, &prog, &scene); /* reads vol as the rays reach it */
    double lo[3], hi[3];
    if (s == HV_OK && !hv_render_scene_bounds(scene, lo, hi))
        s = hv_error_set(HV_ERR_BAD_INPUT, "the model has no occupied voxels: nothing to render");
    if (s != HV_OK) hv_error_prefix(s, "%s: ", path);
    hv_image *img = NULL;
    if (s == HV_OK) s = hv_render_scene_image(scene, o, &prog, &img);
    cli_progress_done(&bar);
    int materials = scene ? hv_render_scene_materials(scene) : 0;
    hv_render_scene_destroy(scene);
    hv_volume_destroy(vol);
    if (s == HV_OK) s = hv_image_write(img, c->output);
    hv_image_destroy(img);
    if (s != HV_OK) return cli_fail(s);
    return args->quiet ? EXIT_OK : report(path, c->output, o, materials);
}

const cli_spec cmd_render = {
    "render", "ray-cast preview image of a model, with cut planes", "MODEL.vdb -o IMAGE [options]",
    "Ray-cast preview of a graded model (Wu 2.3). A sample's colour is its material\n"
    "composition, sum p_j * colour_j of the materials' display colours; its opacity comes\n"
    "from the trilinear occupancy. A model without a material table renders in grey.\n",
    hv_render_option_set, &k_local, "Example: hovox render gear.vdb --surface --clip 'x>0&y<0' -o gear_cut.png\n",
    1, 1, "MODEL argument", CLI_THREADS | CLI_QUIET | CLI_POS_FILES, run, NULL, NULL};
