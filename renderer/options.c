/* renderer/options.c - the render options (hovox/render.h, hovox/options.h): names, domains,
 * defaults and rules in one table that the library checks and the CLI and Lua read. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "core/internal.h"
#include "render_internal.h"

static const char *const k_view_names[] = {"iso", "front", "back", "left", "right", "top", "bottom", NULL};
static const hv_enum_def k_view = {"view", k_view_names, NULL, NULL};
static const char *const k_mode_names[] = {"volume", "surface", NULL};
static const hv_enum_def k_mode = {"render mode", k_mode_names, NULL, NULL};

hv_status hv_view_parse(const char *name, hv_view *out)
{
    int v;
    hv_status s = hv_enum_parse(&k_view, name, &v);
    if (s == HV_OK) *out = (hv_view)v;
    return s;
}

const char *hv_view_name(hv_view view)
{
    const char *n = hv_enum_name(&k_view, (int)view);
    return n ? n : "?";
}

const char *hv_render_mode_name(hv_render_mode mode)
{
    const char *n = hv_enum_name(&k_mode, (int)mode);
    return n ? n : "?";
}

/* clip: an expression, added to the list */
static hv_status parse_clip(const hv_option *o, void *opts, const hv_opt_value *v)
{
    hv_render_options *r = opts;
    if (v->type != HV_VALUE_TEXT)
        return hv_error_option(HV_ERR_INVALID, "{%s} must be an expression such as 'x>0&y<5'", o->key);
    if (r->clips == HV_RENDER_MAX_CLIPS)
        return hv_error_option(HV_ERR_INVALID, "at most %d {clip} and {clip_box} cuts", HV_RENDER_MAX_CLIPS);
    if (hv_clip_parse(v->text, &r->clip[r->clips]) != HV_OK) {
        char msg[1024];
        snprintf(msg, sizeof msg, "%s", hv_last_error());
        return hv_error_option(HV_ERR_INVALID, "{%s}: %s", o->key, msg);
    }
    r->clips++;
    return HV_OK;
}

/* clip_box: two corners x0,y0,z0,x1,y1,z1 (either first), added to the list */
static hv_status parse_clip_box(const hv_option *o, void *opts, const hv_opt_value *v)
{
    hv_render_options *r = opts;
    static const hv_option six = {.key = "clip_box", .kind = HV_OPT_NUMBER, .count = 6,
                                  .meta = "X0,Y0,Z0,X1,Y1,Z1"};
    double b[6];
    hv_status s = hv_option_set_value(&six, b, v);
    if (s != HV_OK) return s;
    if (r->clips == HV_RENDER_MAX_CLIPS)
        return hv_error_option(HV_ERR_INVALID, "at most %d {clip} and {clip_box} cuts", HV_RENDER_MAX_CLIPS);
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = HV_MIN(b[a], b[a + 3]);
        hi[a] = HV_MAX(b[a], b[a + 3]);
    }
    if (hv_clip_box(lo, hi, &r->clip[r->clips]) != HV_OK) {
        char msg[1024];
        snprintf(msg, sizeof msg, "%s", hv_last_error());
        return hv_error_option(HV_ERR_INVALID, "{%s}: %s", o->key, msg);
    }
    r->clips++;
    return HV_OK;
}

/* size = {width, height}: the two ints are adjacent */
_Static_assert(offsetof(hv_render_options, height) == offsetof(hv_render_options, width) + sizeof(int),
               "width and height must be adjacent");

#define OFF(f) offsetof(hv_render_options, f)
static const hv_option k_opts[] = {
    {.key = "size", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .count = 2, .flags = HV_OPT_XSEP, .lo = 1,
     .hi = 65535, .offset = OFF(width), .meta = "W,H", .unit = "pixels",
     .help = "image size in pixels (W,H; WxH is read too)", .section = "Image"},
    {.key = "background", .kind = HV_OPT_COLOR, .elem = HV_ELEM_FLOAT, .flags = HV_OPT_ALPHA,
     .offset = OFF(background), .meta = "COLOR",
     .help = "'#rrggbb', '#rrggbbaa', 'r,g,b' in 0..1, or 'transparent' (default white)"},
    {.key = "aa", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .lo = 1, .hi = 8, .offset = OFF(samples),
     .meta = "N", .help = "N x N rays per pixel"},
    {.key = "mode", .kind = HV_OPT_ENUM, .enumdef = &k_mode, .offset = OFF(mode), .meta = "M",
     .help = "volume: translucent, opacity from the occupancy; surface: the opaque surface at "
             "occupancy 0.5 in the composition at each point",
     .section = "Mode"},
    {.key = "flat", .kind = HV_OPT_FLAG, .offset = OFF(flat),
     .help = "no lighting: pixels show the exact composition colours"},
    {.key = "density", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e9, .offset = OFF(density), .meta = "D",
     .unit = "per mm", .help = "volume extinction per mm of solid material (default 0: 16 / the model's "
                               "largest extent)"},
    {.key = "step", .kind = HV_OPT_NUMBER, .lo = 0.01, .hi = 4, .flags = HV_OPT_UNSET0, .offset = OFF(step),
     .meta = "S", .unit = "voxels",
     .help = "sample spacing along rays in voxels (default 0: 1 in volume mode, 0.5 in surface mode)"},
    {.key = "tf_low", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1, .offset = OFF(tf_low), .meta = "C",
     .help = "volume transfer ramp: coverage where opacity starts"},
    {.key = "tf_high", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1, .offset = OFF(tf_high), .meta = "C",
     .help = "coverage where the ramp reaches full density"},
    {.key = "view", .kind = HV_OPT_ENUM, .enumdef = &k_view, .offset = OFF(camera.view), .meta = "NAME",
     .help = "iso (default), front (looking along +y), back, left (the -x side), right, top (looking "
             "down), bottom; the view fits the whole model",
     .section = "Camera (z is up)"},
    {.key = "eye", .kind = HV_OPT_NUMBER, .count = 3, .offset = OFF(camera.eye), .meta = "X,Y,Z",
     .unit = "mm", .help = "camera position (instead of a view)"},
    {.key = "target", .kind = HV_OPT_NUMBER, .count = 3, .offset = OFF(camera.target), .meta = "X,Y,Z",
     .unit = "mm", .help = "the point the eye looks at (default: the centre of the model's occupied voxels)"},
    {.key = "up", .kind = HV_OPT_NUMBER, .count = 3, .offset = OFF(camera.up), .meta = "X,Y,Z",
     .help = "up direction with eye (default 0,0,1)"},
    {.key = "ortho", .kind = HV_OPT_FLAG, .offset = OFF(camera.ortho), .help = "orthographic projection"},
    {.key = "fov", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 179, .flags = HV_OPT_LO_OPEN | HV_OPT_HI_OPEN,
     .offset = OFF(camera.fov), .meta = "DEG", .unit = "degrees",
     .help = "perspective vertical field of view"},
    {.key = "clip", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .meta = "EXPR",
     .help = "remove where EXPR holds: 'x>10' removes x > 10, 'x>0&y>0' the quarter where both hold; "
             "repeat for several (up to 16 cuts). Cut faces show the composition there",
     .section = "Cuts (world units, mm)", .parse = parse_clip},
    {.key = "clip_box", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .meta = "X0,Y0,Z0,X1,Y1,Z1",
     .help = "remove the box between two corners", .parse = parse_clip_box},
    {.key = "cut_opacity", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1, .offset = OFF(cut_opacity), .meta = "A",
     .help = "opacity of cut faces"},
    {.key = "max_memory", .kind = HV_OPT_BYTES, .offset = OFF(max_memory), .meta = "SIZE",
     .help = "refuse images that would need more (default: half of RAM), e.g. 1G", .section = "Resources"},
};
#undef OFF

static const hv_opt_rule k_rules[] = {
    {HV_RULE_EXCLUDES, "view", "eye", NULL, NULL},
    {HV_RULE_EXCLUDES, "view", "target", NULL, NULL},
    {HV_RULE_NEEDS, "target", "eye", NULL, NULL},
    {HV_RULE_NEEDS, "up", "eye", NULL, "preset views have their own"},
};

static const hv_opt_alias k_aliases[] = {{"surface", "mode", "surface"}, {"volume", "mode", "volume"}};

static hv_status finish(const hv_optargs *args)
{
    hv_render_options *o = args->opts;
    o->camera.use_eye = hv_optargs_given(args, "eye");
    o->camera.target_auto = o->camera.use_eye && !hv_optargs_given(args, "target");
    return HV_OK;
}

static hv_status validate(const void *opts)
{
    const hv_render_options *o = opts;
    if (!(o->tf_low < o->tf_high))
        return hv_error_option(HV_ERR_INVALID, "{tf_low} (%g) must be below {tf_high} (%g)", o->tf_low, o->tf_high);
    if (!(o->iso > 0 && o->iso < 1)) return hv_error_set(HV_ERR_INVALID, "render: iso level %g is outside (0, 1)", o->iso);
    if (!(o->ambient >= 0 && o->diffuse >= 0 && o->specular >= 0 && o->shininess >= 1 && isfinite(o->ambient) &&
          isfinite(o->diffuse) && isfinite(o->specular) && isfinite(o->shininess)))
        return hv_error_set(HV_ERR_INVALID,
                            "render: shading (ambient %g, diffuse %g, specular %g, shininess %g) must be "
                            "finite, >= 0 (shininess >= 1)",
                            o->ambient, o->diffuse, o->specular, o->shininess);
    double ll = o->light[0] * o->light[0] + o->light[1] * o->light[1] + o->light[2] * o->light[2];
    if (!(ll > 0 && isfinite(ll))) return hv_error_set(HV_ERR_INVALID, "render: light direction must be finite and non-zero");
    if (o->clips < 0 || o->clips > HV_RENDER_MAX_CLIPS)
        return hv_error_set(HV_ERR_INVALID, "render: %d clips (at most %d)", o->clips, HV_RENDER_MAX_CLIPS);
    for (int i = 0; i < o->clips; ++i) {
        const hv_clip *c = &o->clip[i];
        if (c->planes < 1 || c->planes > HV_CLIP_MAX_PLANES)
            return hv_error_set(HV_ERR_INVALID, "render: clip %d has %d planes (1..%d)", i, c->planes,
                                HV_CLIP_MAX_PLANES);
        for (int p = 0; p < c->planes; ++p) {
            const double *n = c->normal[p];
            double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
            if (!(nn > 0 && isfinite(nn)) || !isfinite(c->offset[p]))
                return hv_error_set(HV_ERR_INVALID,
                                    "render: clip %d plane %d: normal must be finite and non-zero, offset finite", i, p);
        }
    }
    const hv_camera *c = &o->camera;
    if (!(c->margin >= 0 && c->margin <= 0.45))
        return hv_error_set(HV_ERR_INVALID, "render: margin %g is outside [0, 0.45]", c->margin);
    if (c->ortho && !(c->ortho_height >= 0 && isfinite(c->ortho_height)))
        return hv_error_set(HV_ERR_INVALID, "render: orthographic height %g must be >= 0", c->ortho_height);
    return HV_OK;
}

void hv_render_options_init(hv_render_options *o)
{
    memset(o, 0, sizeof *o);
    o->width = o->height = 512;
    o->mode = HV_RENDER_VOLUME;
    o->camera.view = HV_VIEW_ISO;
    o->camera.up[2] = 1;
    o->camera.fov = 30;
    o->camera.margin = 0.05;
    o->step = 0;
    o->density = 0;
    o->tf_low = 0;
    o->tf_high = 1;
    o->iso = 0.5;
    o->ambient = 0.3;
    o->diffuse = 0.7;
    o->specular = 0.15;
    o->shininess = 40;
    o->light[0] = -0.35;
    o->light[1] = 0.5;
    o->light[2] = 1;
    for (int k = 0; k < 4; ++k) o->background[k] = 1.0f;
    o->cut_opacity = 1;
    o->samples = 1;
}

static void init(void *o) { hv_render_options_init(o); }

static const hv_option_set k_set = {"render", k_opts, (int)HV_COUNT(k_opts), sizeof(hv_render_options), init,
                                    k_rules, (int)HV_COUNT(k_rules), finish, validate, k_aliases,
                                    (int)HV_COUNT(k_aliases)};

const hv_option_set *hv_render_option_set(void) { return &k_set; }

hv_status hv_render_options_check(const hv_render_options *o) { return hv_options_check(&k_set, o); }
