/* renderer/camera.c - preview cameras: preset views (z up) or eye/target/up, perspective or
 * orthographic, fitted to the object's bounding box so the whole model shows by default. */
#include <math.h>
#include <string.h>

#include "core/internal.h"
#include "render_internal.h"

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static double norm3(double v[3])
{
    double n = sqrt(dot3(v, v));
    if (n > 0)
        for (int a = 0; a < 3; ++a) v[a] /= n;
    return n;
}

static int finite3(const double v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* Direction from the target towards the eye, and the up vector, of a preset view. */
static void view_dirs(hv_view v, double e[3], double up[3])
{
    static const double E[7][3] = {{1, -1, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, 0},
                                   {1, 0, 0},  {0, 0, 1},  {0, 0, -1}};
    static const double U[7][3] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1},
                                   {0, 0, 1}, {0, 1, 0}, {0, -1, 0}};
    int i = (unsigned)v < 7 ? (int)v : 0;
    memcpy(e, E[i], sizeof E[i]);
    memcpy(up, U[i], sizeof U[i]);
    norm3(e);
}

hv_status r_camera_setup(const hv_render_scene *s, const hv_render_options *opt, rcam *cam)
{
    const hv_camera *c = &opt->camera;
    memset(cam, 0, sizeof *cam);
    cam->width = opt->width;
    cam->height = opt->height;
    cam->ortho = c->ortho != 0;
    if (!cam->ortho && !(c->fov > 0 && c->fov < 179))
        return hv_error_set(HV_ERR_INVALID, "render: field of view %g degrees is outside (0, 179)",
                            c->fov);
    if (!(c->margin >= 0 && c->margin <= 0.45))
        return hv_error_set(HV_ERR_INVALID, "render: margin %g is outside [0, 0.45]", c->margin);
    if (cam->ortho && !(c->ortho_height >= 0 && isfinite(c->ortho_height)))
        return hv_error_set(HV_ERR_INVALID, "render: orthographic height %g must be >= 0",
                            c->ortho_height);
    double aspect = (double)opt->width / (double)opt->height;
    double e[3], up[3], target[3], dist = 0;
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    int have_box = !s->empty;
    if (have_box) r_scene_box(s, lo, hi);
    int fit_needed = !c->use_eye || (cam->ortho && c->ortho_height == 0);
    if (fit_needed && !have_box)
        return hv_error_set(HV_ERR_INVALID,
                            "render: the model has no occupied voxels: nothing to fit the view to");

    if (c->use_eye) {
        if (!finite3(c->eye) || !finite3(c->target) || !finite3(c->up))
            return hv_error_set(HV_ERR_INVALID, "render: camera eye, target and up must be finite");
        for (int a = 0; a < 3; ++a) {
            target[a] = c->target_auto && have_box ? 0.5 * (lo[a] + hi[a]) : c->target[a];
            e[a] = c->eye[a] - target[a];
            up[a] = c->up[a];
        }
        dist = norm3(e);
        if (!(dist > 0))
            return hv_error_set(HV_ERR_INVALID, "render: camera eye (%g, %g, %g) equals the target",
                                c->eye[0], c->eye[1], c->eye[2]);
    } else {
        view_dirs(c->view, e, up);
        for (int a = 0; a < 3; ++a) target[a] = 0.5 * (lo[a] + hi[a]);
    }
    for (int a = 0; a < 3; ++a) cam->fwd[a] = -e[a];
    cross3(cam->fwd, up, cam->right);
    if (!(norm3(cam->right) > 1e-9 * (sqrt(dot3(up, up)) + 1e-300)) && up[0] == 0 && up[1] == 0 &&
        up[2] > 0) {
        /* looking straight down (or up) with the default z up: +y is up on the screen, as in
         * the top view */
        up[1] = 1;
        up[2] = 0;
        cross3(cam->fwd, up, cam->right);
    }
    if (!(norm3(cam->right) > 1e-9 * (sqrt(dot3(up, up)) + 1e-300)))
        return hv_error_set(
            HV_ERR_INVALID, "render: up vector (%g, %g, %g) is zero or parallel to the view direction",
            up[0], up[1], up[2]);
    cross3(cam->right, cam->fwd, cam->up);
    norm3(cam->up);

    /* bounding-box corners in camera coordinates relative to the target */
    double cx[8], cy[8], cz[8], maxx = 0, maxy = 0, maxz = -HUGE_VAL, radius = 0;
    if (have_box) {
        for (int i = 0; i < 8; ++i) {
            double p[3] = {(i & 4 ? hi[0] : lo[0]) - target[0], (i & 2 ? hi[1] : lo[1]) - target[1],
                           (i & 1 ? hi[2] : lo[2]) - target[2]};
            cx[i] = dot3(p, cam->right);
            cy[i] = dot3(p, cam->up);
            cz[i] = dot3(p, e); /* towards the eye */
            maxx = HV_MAX(maxx, fabs(cx[i]));
            maxy = HV_MAX(maxy, fabs(cy[i]));
            maxz = HV_MAX(maxz, cz[i]);
            radius = HV_MAX(radius, sqrt(dot3(p, p)));
        }
    }
    double shrink = 1.0 - 2.0 * c->margin;
    if (cam->ortho) {
        double hh = c->ortho_height * 0.5;
        if (hh == 0) hh = HV_MAX(maxy, maxx / aspect) / shrink;
        if (!(hh > 0)) hh = 1; /* a single voxel seen edge-on cannot happen; stay finite */
        cam->half_h = hh;
        cam->half_w = hh * aspect;
        /* rays start on the plane through the eye; a fitted view puts it outside the box */
        if (!c->use_eye) dist = radius * 2 + 1;
    } else {
        cam->half_h = tan(c->fov * M_PI / 360.0);
        cam->half_w = cam->half_h * aspect;
        if (!c->use_eye) {
            double th = cam->half_h * shrink, tw = cam->half_w * shrink;
            dist = 0;
            for (int i = 0; i < 8; ++i) {
                dist = HV_MAX(dist, cz[i] + fabs(cx[i]) / tw);
                dist = HV_MAX(dist, cz[i] + fabs(cy[i]) / th);
            }
            dist = HV_MAX(dist, maxz + 1e-6 * (radius + 1));
        }
    }
    for (int a = 0; a < 3; ++a) cam->eye[a] = target[a] + e[a] * dist;
    if (!finite3(cam->eye) || !isfinite(cam->half_h) || !isfinite(cam->half_w))
        return hv_error_set(HV_ERR_INVALID, "render: camera is not finite");
    return HV_OK;
}

void r_camera_ray(const rcam *cam, double x, double y, double o[3], double d[3])
{
    double u = (2.0 * x / cam->width - 1.0) * cam->half_w;
    double v = (1.0 - 2.0 * y / cam->height) * cam->half_h;
    if (cam->ortho) {
        for (int a = 0; a < 3; ++a) {
            o[a] = cam->eye[a] + u * cam->right[a] + v * cam->up[a];
            d[a] = cam->fwd[a];
        }
    } else {
        for (int a = 0; a < 3; ++a) {
            o[a] = cam->eye[a];
            d[a] = cam->fwd[a] + u * cam->right[a] + v * cam->up[a];
        }
        norm3(d);
    }
}

int r_camera_footprint(const rcam *cam, const double lo[3], const double hi[3], double rect[4])
{
    double u0 = HUGE_VAL, u1 = -HUGE_VAL, v0 = HUGE_VAL, v1 = -HUGE_VAL;
    for (int i = 0; i < 8; ++i) {
        double p[3] = {(i & 4 ? hi[0] : lo[0]) - cam->eye[0], (i & 2 ? hi[1] : lo[1]) - cam->eye[1],
                       (i & 1 ? hi[2] : lo[2]) - cam->eye[2]};
        double u = dot3(p, cam->right), v = dot3(p, cam->up);
        if (!cam->ortho) { /* a corner beside or behind the eye: no bound */
            double d = dot3(p, cam->fwd);
            if (!(d > 1e-6 * sqrt(dot3(p, p)))) return 0;
            u /= d;
            v /= d;
        }
        u0 = HV_MIN(u0, u);
        u1 = HV_MAX(u1, u);
        v0 = HV_MIN(v0, v);
        v1 = HV_MAX(v1, v);
    }
    /* image position x = (u / half_w + 1) W / 2, y = (1 - v / half_h) H / 2; two pixels of
     * margin leave the rounding of the rays' own arithmetic far behind */
    rect[0] = (u0 / cam->half_w + 1.0) * 0.5 * cam->width - 2.0;
    rect[2] = (u1 / cam->half_w + 1.0) * 0.5 * cam->width + 2.0;
    rect[1] = (1.0 - v1 / cam->half_h) * 0.5 * cam->height - 2.0;
    rect[3] = (1.0 - v0 / cam->half_h) * 0.5 * cam->height + 2.0;
    for (int k = 0; k < 4; ++k)
        if (!isfinite(rect[k])) return 0;
    return 1;
}
