/* hovox/render.h - ray-cast preview of heterogeneous objects (Wu 2.3): direct volume rendering
 * whose sample colour comes from the material composition (sum p_j * colour_j) rather than a
 * scalar transfer function, an opaque surface mode, cut planes and boxes that show the
 * interior. Images and their files are the image module's (hovox/image.h). */
#ifndef HOVOX_RENDER_H
#define HOVOX_RENDER_H

#include "hovox/core.h"
#include "hovox/image.h"
#include "hovox/options.h"
#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ==== cut planes and boxes =============================================================== */

#define HV_CLIP_MAX_PLANES 8
#define HV_RENDER_MAX_CLIPS 16

/* A clip REMOVES a convex region of the object from the picture: the points x where every
 * plane has normal . x > offset (world units). Several clips remove the union of their
 * regions. Where a ray enters the remaining object through a clip face, that face is drawn in
 * the material colours of the composition there (a cut face), so the interior shows. */
typedef struct hv_clip {
    int planes; /* 1..HV_CLIP_MAX_PLANES */
    double normal[HV_CLIP_MAX_PLANES][3];
    double offset[HV_CLIP_MAX_PLANES];
} hv_clip;

/* Parse a clip expression: one or more conditions joined by '&' (or ','), each an axis, '<'
 * or '>' (optionally '<=' / '>=') and a number in world units: "x>10" removes x > 10,
 * "z<5" removes z < 5, "x>0&y>0" removes the quarter where both hold. Spaces are allowed.
 * Errors: HV_ERR_INVALID with the column ("clip 'x>>1': column 3: number expected"). */
HV_API hv_status hv_clip_parse(const char *expr, hv_clip *out);

/* The box lo < x < hi (componentwise) as a clip (6 planes). Errors: HV_ERR_INVALID (lo >= hi
 * on an axis, non-finite values). */
HV_API hv_status hv_clip_box(const double lo[3], const double hi[3], hv_clip *out);

/* ==== rendering ========================================================================== */

typedef enum hv_render_mode {
    HV_RENDER_VOLUME = 0, /* translucent: emission-absorption along the ray */
    HV_RENDER_SURFACE = 1 /* opaque: the first crossing of the occupancy iso-level */
} hv_render_mode;

/* Preset views; z is up. FRONT looks along +y (x to the right), BACK along -y, LEFT along +x
 * (seeing the -x side), RIGHT along -x, TOP down along -z (x right, y up in the image), BOTTOM
 * up along +z (x right, -y up); ISO from the front-right-top, direction (1,-1,1). */
typedef enum hv_view {
    HV_VIEW_ISO = 0, HV_VIEW_FRONT, HV_VIEW_BACK, HV_VIEW_LEFT, HV_VIEW_RIGHT, HV_VIEW_TOP,
    HV_VIEW_BOTTOM
} hv_view;

/* Name <-> view ("iso", "front", ...). hv_view_parse errors: HV_ERR_INVALID. */
HV_API hv_status hv_view_parse(const char *name, hv_view *out);
HV_API const char *hv_view_name(hv_view view);
/* Name of a render mode ("volume", "surface"), as the option takes it. Static text. */
HV_API const char *hv_render_mode_name(hv_render_mode mode);

/* Camera model. fwd = unit(target - eye), right = unit(fwd x up), up' = right x fwd. Pixel
 * (x, y) (y downwards) is sampled at image position (x + 0.5, y + 0.5) (a regular n x n grid
 * inside the pixel with supersampling); with u = (2 (x + 0.5) / W - 1) * hw and
 * v = (1 - 2 (y + 0.5) / H) * hh:
 *   perspective: hh = tan(fov / 2), hw = hh * W / H; the ray leaves the eye along
 *                unit(fwd + u right + v up');
 *   orthographic: hh = ortho_height / 2, hw = hh * W / H; the ray leaves eye + u right + v up'
 *                along fwd (nothing before that plane is seen).
 * Fitted views (use_eye == 0, or an orthographic height of 0) use the world bounding box of the
 * occupied voxels: the target is its centre and the eye distance (perspective) or the height
 * (orthographic) the smallest that keeps all 8 corners inside the image minus `margin` on each
 * side. */
typedef struct hv_camera {
    hv_view view;        /* used when use_eye == 0 */
    int use_eye;         /* 1: eye, target and up below define the camera */
    int target_auto;     /* with use_eye: aim at the centre of the occupied voxels' box
                            instead of `target` (default 0) */
    double eye[3], target[3], up[3];
    int ortho;           /* orthographic instead of perspective */
    double fov;          /* perspective: vertical field of view in degrees (default 30) */
    double ortho_height; /* orthographic: visible height in world units; 0: fit the object */
    double margin;       /* fitting margin as a fraction of the image (default 0.05) */
} hv_camera;

typedef struct hv_render_options {
    int width, height;    /* pixels (default 512 x 512), 1..65535 each */
    hv_render_mode mode;  /* default HV_RENDER_VOLUME */
    hv_camera camera;     /* default: iso view, perspective, fitted to the object */
    double step;          /* sample spacing along rays in voxels (smallest voxel edge), at
                             most 4; 0 (default): 1 in volume mode, 0.5 in surface mode */
    /* transfer function (volume mode): extinction sigma = density * ramp(coverage) * alpha_mix
     * per world unit, where coverage is the trilinear occupancy in [0,1], ramp rises linearly
     * from 0 at tf_low to 1 at tf_high, and alpha_mix the composition-weighted alpha of the
     * material colours; a sample of length dt has opacity 1 - exp(-sigma * dt). Samples are
     * composited front to back; a ray stops when its transmittance falls below 1/512 and the
     * rest goes to the last sample (an opaque pixel has alpha exactly 1). */
    double density;       /* per world unit; 0 (default): 16 / the largest extent of the object */
    double tf_low, tf_high; /* default 0, 1 */
    double iso;           /* surface mode and cut faces: coverage level of the surface (0.5) */
    /* shading: colour * (ambient + diffuse * max(0, n.l)) + specular * (n.h)^shininess (white),
     * n the outward normal from the gradient of the occupancy smoothed by a 7-tap binomial
     * kernel (sigma 1.2 voxels); in volume mode weighted by the gradient strength, so
     * homogeneous interiors keep their plain colour. Cut faces use the plane's normal.
     * ambient 1, diffuse 0, specular 0 gives the exact composition colours. */
    double ambient, diffuse, specular, shininess; /* default 0.3, 0.7, 0.15, 40 */
    int flat;             /* 1: no lighting, as ambient 1, diffuse 0, specular 0 (default 0) */
    double light[3];      /* direction towards the key light in camera space (x right, y up,
                             z towards the viewer); default (-0.35, 0.5, 1) */
    float background[4];  /* straight RGBA in [0,1]; default opaque white; alpha 0: transparent */
    int clips;            /* number of entries used in clip[] */
    hv_clip clip[HV_RENDER_MAX_CLIPS];
    double cut_opacity;   /* opacity of cut faces in [0,1] (default 1, both modes) */
    int samples;          /* supersampling: samples x samples rays per pixel (1..8, default 1) */
    uint64_t max_memory;  /* refuse images that need more (bytes; 0: hv_memory_budget's default) */
} hv_render_options;

/* Defaults as documented above. */
HV_API void hv_render_options_init(hv_render_options *opt);

/* The render options as an option set (hovox/options.h): keys size, background, aa, mode (and
 * the shorthands surface, volume), flat, density, step, tf_low, tf_high, view, eye, target, up,
 * ortho, fov, clip, clip_box, cut_opacity, with their domains; what the CLI and Lua read.
 * Static data. */
HV_API const hv_option_set *hv_render_option_set(void);
/* Every option's domain and the checks between them. Errors: HV_ERR_INVALID naming the
 * option. */
HV_API hv_status hv_render_options_check(const hv_render_options *opt);

/* A scene: the render-ready form of a model, built once and rendered any number of times
 * (views, clips, sizes); read-only once built, so several threads may render it at once. It
 * copies what it needs: the volume may be freed or changed after hv_render_scene_create
 * returns. Occupied voxels are the active voxels where the bool grid "occupancy" (if present)
 * is true. Each occupied voxel gets the colour sum p_j * colour_j / sum p_j of the model's
 * material table (hovox.materials.json with "material.<name>" grids; negative or NaN
 * fractions count as 0), kept with 8 bits per channel; trilinear interpolation of these
 * colours equals the colour of the interpolated fractions, as the map is linear. A model
 * without a table renders in grey (0.7). Memory: 5.8 KB per 8^3 block that holds or touches
 * occupied voxels. Progress stage "prepare". Errors: HV_ERR_BAD_INPUT (corrupt material table,
 * or a material without its grid), HV_ERR_LIMIT (occupied voxels spread over more than 2^26
 * blocks of 64^3 voxels), HV_ERR_NOMEM, HV_ERR_CANCELLED. Free with hv_render_scene_destroy. */
typedef struct hv_render_scene hv_render_scene;
HV_API hv_status hv_render_scene_create(const hv_volume *vol, const hv_progress *progress,
                                        hv_render_scene **out);
/* The same scene, filled as it is rendered: only the block table is built here (a few
 * milliseconds), and each block's colours and gradients are computed from the volume when a ray
 * first reaches it, so a small or partial image pays only for the blocks it sees. The images are
 * exactly those of hv_render_scene_create, for any thread count. `vol` must stay alive and
 * unchanged until the scene is destroyed; several threads may still render the scene at once
 * (a block is filled once, by the first thread that reaches it). Memory: that of the blocks
 * filled, plus 100 bytes per occupied block. Errors: as hv_render_scene_create. */
HV_API hv_status hv_render_scene_create_lazy(const hv_volume *vol, const hv_progress *progress,
                                             hv_render_scene **out);
HV_API void hv_render_scene_destroy(hv_render_scene *scene); /* NULL allowed */

/* Load from an OpenVDB file what a scene reads: the "occupancy" grid and the "material.*" grids,
 * with the file's metadata (hv_volume_load_grids: files hovox writes skip the other grids
 * unread). A file without an "occupancy" grid is loaded whole, as its occupied voxels are then
 * the active voxels of all its grids. Free with hv_volume_destroy. Errors: those of
 * hv_volume_load. */
HV_API hv_status hv_render_volume_load(const char *path, hv_volume **out);

/* World-space bounding box of the scene's occupied voxel cells; 0 when the scene is empty. */
HV_API int hv_render_scene_bounds(const hv_render_scene *scene, double lo[3], double hi[3]);
/* Number of materials coloured (0: grey occupancy-only model). */
HV_API int hv_render_scene_materials(const hv_render_scene *scene);

/* Ray-cast the scene into a new image (*out, free with hv_image_destroy). Multi-threaded over
 * 32x32 tiles (smaller for images of fewer than 4 tiles per thread; hv_threads()); the result
 * does not depend on the thread count. Progress stage
 * "render". Errors: HV_ERR_INVALID (an option out of its domain, named in the message; a
 * degenerate camera; a fitted view of an empty scene), HV_ERR_NOMEM, HV_ERR_CANCELLED. */
HV_API hv_status hv_render_scene_image(const hv_render_scene *scene,
                                       const hv_render_options *opt,
                                       const hv_progress *progress, hv_image **out);

/* hv_render_scene_create_lazy + hv_render_scene_image + destroy, for one picture; the errors
 * of both. */
HV_API hv_status hv_render(const hv_volume *vol, const hv_render_options *opt,
                           const hv_progress *progress, hv_image **out);

#ifdef __cplusplus
}
#endif
#endif
