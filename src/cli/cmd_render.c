/* src/cli/cmd_render.c - `hovox render MODEL.vdb -o IMAGE`: ray-cast preview (Wu 2.3) in the
 * material colours, translucent volume or opaque surface, with cut planes and boxes. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/internal.h"
#include "cli.h"
#include "hovox/material.h"
#include "hovox/render.h"

static const char *RENDER_HELP =
    "usage: hovox render MODEL.vdb -o IMAGE [options]\n"
    "\n"
    "Ray-cast preview of a graded model (Wu 2.3). A sample's colour is its material\n"
    "composition, sum p_j * colour_j of the materials' display colours; its opacity comes\n"
    "from the trilinear occupancy. Volume mode (default) is translucent; --surface draws the\n"
    "opaque surface in the composition at each point. A model without a material table\n"
    "renders in grey.\n"
    "\n"
    "Output (by extension):\n"
    "  -o, --output FILE      .png 8-bit RGBA (straight alpha); .exr half float RGBA\n"
    "                         (premultiplied) and .tif/.tiff 8-bit RGBA need OpenImageIO\n"
    "  --size WxH             image size in pixels (default 512x512)\n"
    "  --background C         '#rrggbb', '#rrggbbaa', 'r,g,b' in 0..1, or 'transparent'\n"
    "                         (default white)\n"
    "Mode:\n"
    "  --surface              opaque surface at occupancy 0.5, coloured by composition\n"
    "  --volume               translucent volume (default)\n"
    "  --density D            volume extinction per unit length (mm) of solid material\n"
    "                         (default 16 / the model's largest extent)\n"
    "  --step S               sample spacing in voxels, at most 4 (default 1; 0.5 with\n"
    "                         --surface)\n"
    "  --flat                 no lighting: pixels show the exact composition colours\n"
    "  --aa N                 N x N rays per pixel (default 1)\n"
    "Camera (z is up; the default view fits the whole model):\n"
    "  --view NAME            iso (default), front (looking along +y), back, left (the -x\n"
    "                         side), right, top (looking down), bottom\n"
    "  --eye X,Y,Z            camera position; with --target X,Y,Z (default: model centre)\n"
    "  --target X,Y,Z         and --up X,Y,Z (default 0,0,1)\n"
    "  --up X,Y,Z\n"
    "  --ortho                orthographic projection (default perspective)\n"
    "  --fov DEG              perspective vertical field of view (default 30)\n"
    "Cuts (world units; a clip REMOVES the region its expression describes):\n"
    "  --clip EXPR            remove where EXPR holds: 'x>10' removes x > 10, 'z<5' removes\n"
    "                         z < 5, 'x>0&y>0' removes the quarter where both hold; repeat\n"
    "                         to remove several regions (up to 16). Cut faces are drawn in\n"
    "                         the composition there, so inner gradients show.\n"
    "  --clip-box X0,Y0,Z0,X1,Y1,Z1  remove the box between the two corners\n"
    "  --cut-opacity A        opacity of cut faces, 0..1 (default 1)\n"
    "Other:\n"
    "  --threads N            worker threads (default: all cores)\n"
    "  -q, --quiet            no progress bar\n"
    "  -h, --help             this text\n"
    "\n"
    "Example: hovox render gear.vdb --surface --clip 'x>0&y<0' -o gear_cut.png\n";

#define CMD "render"

static int parse_vec3(const char *opt, const char *s, double v[3])
{
    return cli_parse_vec(CMD, opt, s, 3, v);
}

static int parse_size(const char *s, int *w, int *h)
{
    char *end;
    long a = strtol(s, &end, 10), b;
    if (end == s || (*end != 'x' && *end != 'X')) goto bad;
    const char *p = end + 1;
    b = strtol(p, &end, 10);
    if (end == p || *end != '\0') goto bad;
    if (a < 1 || a > 65535 || b < 1 || b > 65535)
        return cli_usage_error(CMD, "--size: %ldx%ld is outside 1..65535 per side", a, b);
    *w = (int)a;
    *h = (int)b;
    return 0;
bad:
    return cli_usage_error(CMD, "--size: '%s' is not WxH (e.g. 1024x768)", s);
}

static int known_extension(const char *path)
{
    const char *dot = strrchr(path, '.');
    if (!dot || strchr(dot, '/')) return 0;
    return !strcasecmp(dot, ".png") || !strcasecmp(dot, ".exr") || !strcasecmp(dot, ".tif") ||
           !strcasecmp(dot, ".tiff");
}

int cmd_render(int argc, char **argv)
{
    enum {
        O_SURFACE = 256, O_VOLUME, O_VIEW, O_EYE, O_TARGET, O_UP, O_ORTHO, O_FOV, O_SIZE, O_STEP,
        O_CLIP, O_CLIPBOX, O_CUTOP, O_BG, O_DENSITY, O_FLAT, O_AA, O_THREADS
    };
    static const struct option opts[] = {
        {"output", required_argument, NULL, 'o'},    {"surface", no_argument, NULL, O_SURFACE},
        {"volume", no_argument, NULL, O_VOLUME},     {"view", required_argument, NULL, O_VIEW},
        {"eye", required_argument, NULL, O_EYE},     {"target", required_argument, NULL, O_TARGET},
        {"up", required_argument, NULL, O_UP},       {"ortho", no_argument, NULL, O_ORTHO},
        {"fov", required_argument, NULL, O_FOV},     {"size", required_argument, NULL, O_SIZE},
        {"step", required_argument, NULL, O_STEP},   {"clip", required_argument, NULL, O_CLIP},
        {"clip-box", required_argument, NULL, O_CLIPBOX},
        {"cut-opacity", required_argument, NULL, O_CUTOP},
        {"background", required_argument, NULL, O_BG},
        {"density", required_argument, NULL, O_DENSITY},
        {"flat", no_argument, NULL, O_FLAT},         {"aa", required_argument, NULL, O_AA},
        {"threads", required_argument, NULL, O_THREADS},
        {"quiet", no_argument, NULL, 'q'},           {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0}};
    hv_render_options opt;
    hv_render_options_init(&opt);
    const char *output = NULL;
    int quiet = 0, c, have_eye = 0, have_target = 0, have_view = 0, have_up = 0;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":o:qh", opts, NULL)) != -1) {
        long n;
        double v6[6];
        switch (c) {
        case 'o': output = optarg; break;
        case 'q': quiet = 1; break;
        case 'h': fputs(RENDER_HELP, stdout); return EXIT_OK;
        case O_SURFACE: opt.mode = HV_RENDER_SURFACE; break;
        case O_VOLUME: opt.mode = HV_RENDER_VOLUME; break;
        case O_VIEW:
            if (hv_view_parse(optarg, &opt.camera.view) != HV_OK)
                return cli_usage_error(CMD, "--view: '%s' is not iso, front, back, left, right, top "
                                            "or bottom", optarg);
            have_view = 1;
            break;
        case O_EYE:
            if (parse_vec3("--eye", optarg, opt.camera.eye)) return EXIT_USAGE;
            have_eye = 1;
            break;
        case O_TARGET:
            if (parse_vec3("--target", optarg, opt.camera.target)) return EXIT_USAGE;
            have_target = 1;
            break;
        case O_UP:
            if (parse_vec3("--up", optarg, opt.camera.up)) return EXIT_USAGE;
            have_up = 1;
            break;
        case O_ORTHO: opt.camera.ortho = 1; break;
        case O_FOV:
            if (cli_parse_double(CMD, "--fov", optarg, &opt.camera.fov)) return EXIT_USAGE;
            if (!(opt.camera.fov > 0 && opt.camera.fov < 179))
                return cli_usage_error(CMD, "--fov: %s is outside (0, 179) degrees", optarg);
            break;
        case O_SIZE:
            if (parse_size(optarg, &opt.width, &opt.height)) return EXIT_USAGE;
            break;
        case O_STEP:
            if (cli_parse_double(CMD, "--step", optarg, &opt.step)) return EXIT_USAGE;
            if (!(opt.step > 0 && opt.step <= 4))
                return cli_usage_error(CMD, "--step: %s voxels is outside (0, 4]", optarg);
            break;
        case O_CLIP:
        case O_CLIPBOX:
            if (opt.clips == HV_RENDER_MAX_CLIPS)
                return cli_usage_error(CMD, "at most %d --clip/--clip-box options",
                                       HV_RENDER_MAX_CLIPS);
            if (c == O_CLIP) {
                if (hv_clip_parse(optarg, &opt.clip[opt.clips]) != HV_OK)
                    return cli_usage_error(CMD, "--clip: %s", hv_last_error());
            } else {
                if (cli_parse_vec(CMD, "--clip-box", optarg, 6, v6)) return EXIT_USAGE;
                double lo[3], hi[3];
                for (int a = 0; a < 3; ++a) {
                    lo[a] = HV_MIN(v6[a], v6[a + 3]);
                    hi[a] = HV_MAX(v6[a], v6[a + 3]);
                }
                if (hv_clip_box(lo, hi, &opt.clip[opt.clips]) != HV_OK)
                    return cli_usage_error(CMD, "--clip-box: %s", hv_last_error());
            }
            opt.clips++;
            break;
        case O_CUTOP:
            if (cli_parse_double(CMD, "--cut-opacity", optarg, &opt.cut_opacity)) return EXIT_USAGE;
            if (!(opt.cut_opacity >= 0 && opt.cut_opacity <= 1))
                return cli_usage_error(CMD, "--cut-opacity: %s is outside [0, 1]", optarg);
            break;
        case O_BG:
            if (strcmp(optarg, "transparent") == 0 || strcmp(optarg, "none") == 0) {
                for (int k = 0; k < 4; ++k) opt.background[k] = 0;
            } else if (hv_color_parse(optarg, opt.background) != HV_OK) {
                return cli_usage_error(CMD, "--background: '%s' is not a colour ('#rrggbb', "
                                            "'#rrggbbaa', 'r,g,b' or 'transparent')", optarg);
            }
            break;
        case O_DENSITY:
            if (cli_parse_double(CMD, "--density", optarg, &opt.density)) return EXIT_USAGE;
            if (!(opt.density > 0))
                return cli_usage_error(CMD, "--density: %s must be positive", optarg);
            break;
        case O_FLAT:
            opt.ambient = 1;
            opt.diffuse = 0;
            opt.specular = 0;
            break;
        case O_AA:
            if (cli_parse_int(CMD, "--aa", optarg, 1, 8, &n)) return EXIT_USAGE;
            opt.samples = (int)n;
            break;
        case O_THREADS:
            if (cli_parse_int(CMD, "--threads", optarg, 1, 1024, &n)) return EXIT_USAGE;
            hv_set_threads((int)n);
            break;
        case ':': return cli_usage_error(CMD, "option '%s' needs a value", argv[optind - 1]);
        default: return cli_usage_error(CMD, "unknown option '%s'", argv[optind - 1]);
        }
    }
    if (optind >= argc) return cli_usage_error(CMD, "missing MODEL argument");
    if (argc - optind > 1)
        return cli_usage_error(CMD, "one MODEL at a time (got '%s' too)", argv[optind + 1]);
    if (!output) return cli_usage_error(CMD, "missing -o IMAGE");
    if (!known_extension(output))
        return cli_usage_error(CMD,
                               "-o: '%s' has no known image extension (.png, .exr, .tif, .tiff)",
                               output);
    if ((have_target || have_eye) && have_view)
        return cli_usage_error(CMD, "give either --view or --eye/--target, not both");
    if (have_target && !have_eye) return cli_usage_error(CMD, "--target needs --eye");
    if (have_up && !have_eye) return cli_usage_error(CMD, "--up needs --eye (preset views have their own)");
    const char *path = argv[optind];

    hv_volume *vol = NULL;
    hv_status s = hv_volume_load(path, &vol);
    if (s != HV_OK) return cli_fail(s);
    cli_progress bar;
    cli_progress_init(&bar, quiet);
    hv_progress prog = {cli_progress_fn, &bar};
    hv_render_scene *scene = NULL;
    s = hv_render_scene_create(vol, &prog, &scene);
    hv_volume_destroy(vol); /* the scene holds what it needs */
    if (s != HV_OK) {
        cli_progress_done(&bar);
        return cli_fail(hv_error_prefix(s, "%s: ", path));
    }
    double lo[3], hi[3];
    int has_box = hv_render_scene_bounds(scene, lo, hi);
    if (!has_box) {
        cli_progress_done(&bar);
        hv_render_scene_destroy(scene);
        hv_error_set(HV_ERR_BAD_INPUT, "%s: the model has no occupied voxels: nothing to render",
                     path);
        return cli_fail(HV_ERR_BAD_INPUT);
    }
    if (have_eye) {
        opt.camera.use_eye = 1;
        if (!have_target)
            for (int a = 0; a < 3; ++a) opt.camera.target[a] = 0.5 * (lo[a] + hi[a]);
    }
    hv_image *img = NULL;
    s = hv_render_scene_image(scene, &opt, &prog, &img);
    cli_progress_done(&bar);
    int materials = hv_render_scene_materials(scene);
    hv_render_scene_destroy(scene);
    if (s == HV_OK) s = hv_image_write(img, output);
    hv_image_destroy(img);
    if (s != HV_OK) return cli_fail(s);
    if (materials)
        printf("model       %s (%d material%s)\n", path, materials, materials == 1 ? "" : "s");
    else
        printf("model       %s (no material table: grey)\n", path);
    printf("image       %d x %d, %s, %s%s\n", opt.width, opt.height,
           opt.mode == HV_RENDER_SURFACE ? "surface" : "volume",
           opt.camera.use_eye ? "eye" : hv_view_name(opt.camera.view),
           opt.camera.ortho ? ", orthographic" : "");
    if (opt.clips) printf("clips       %d\n", opt.clips);
    printf("wrote       %s\n", output);
    return EXIT_OK;
}
