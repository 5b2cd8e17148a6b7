/* tests/renderer/test_render.c - the ray-cast preview (Wu 2.3) against independent references:
 * analytic transmittance through slabs, a brute-force fine-step ray marcher over a closed-form
 * 64^3 sphere, analytic sphere shading, the radial gradient of Wu's shaft on a cut face, clip
 * regions, view orientation and fitting, determinism across thread counts, stored reference
 * images (compared within a tolerance), options and errors. */
#include <criterion/criterion.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/material.h"
#include "hovox/render.h"
#include "support/support.h"

/* ---- volumes from closed forms --------------------------------------------------------- */

typedef int (*occ_fn)(const double p[3], const void *u);
typedef void (*frac_fn)(const double p[3], const void *u, double *f);

typedef struct model {
    int nmat;
    const char *names[4];
    float colour[4][4];
    occ_fn occ;
    frac_fn frac;
    const void *user;
} model;

static void centre(const hv_transform *xf, int i, int j, int k, double p[3])
{
    p[0] = xf->origin[0] + i * xf->voxel[0];
    p[1] = xf->origin[1] + j * xf->voxel[1];
    p[2] = xf->origin[2] + k * xf->voxel[2];
}

/* Voxels lo..hi (inclusive indices) whose centres satisfy m->occ; bool "occupancy", a float
 * grid per material with m->frac at the centre, and the material table. */
static hv_volume *build(const hv_transform *xf, const int lo[3], const int hi[3], const model *m)
{
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(xf, &v), HV_OK, "%s", hv_last_error());
    int g_occ;
    cr_assert_eq(hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &g_occ), HV_OK);
    size_t cap = 256, n = 0;
    int32_t *org = malloc(cap * 3 * sizeof *org);
    uint64_t *msk = malloc(cap * 8 * sizeof *msk);
    for (int bx = lo[0] & ~7; bx <= hi[0]; bx += 8)
        for (int by = lo[1] & ~7; by <= hi[1]; by += 8)
            for (int bz = lo[2] & ~7; bz <= hi[2]; bz += 8) {
                if (n == cap) {
                    cap *= 2;
                    org = realloc(org, cap * 3 * sizeof *org);
                    msk = realloc(msk, cap * 8 * sizeof *msk);
                }
                memset(msk + 8 * n, 0, 8 * sizeof *msk);
                int any = 0;
                for (int x = 0; x < 8; ++x)
                    for (int y = 0; y < 8; ++y)
                        for (int z = 0; z < 8; ++z) {
                            int i = bx + x, j = by + y, k = bz + z;
                            if (i < lo[0] || i > hi[0] || j < lo[1] || j > hi[1] || k < lo[2] ||
                                k > hi[2])
                                continue;
                            double p[3];
                            centre(xf, i, j, k, p);
                            if (!m->occ(p, m->user)) continue;
                            unsigned off = HV_LEAF_OFFSET(x, y, z);
                            msk[8 * n + off / 64] |= 1ull << (off % 64);
                            any = 1;
                        }
                if (!any) continue;
                org[3 * n] = bx;
                org[3 * n + 1] = by;
                org[3 * n + 2] = bz;
                ++n;
            }
    cr_assert_eq(hv_volume_topology_add(v, n, org, msk), HV_OK, "%s", hv_last_error());
    free(org);
    free(msk);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        uint64_t *b = hv_volume_leaf_bool(v, g_occ, l);
        memcpy(b, hv_volume_leaf_mask(v, l), 8 * sizeof *b);
    }
    if (m->nmat == 0) return v;
    hv_material_table *t;
    cr_assert_eq(hv_material_table_create(&t), HV_OK);
    int g[4];
    for (int j = 0; j < m->nmat; ++j) {
        char name[64];
        cr_assert_eq(hv_material_add(t, m->names[j], m->colour[j], NULL), HV_OK, "%s", hv_last_error());
        snprintf(name, sizeof name, "material.%s", m->names[j]);
        cr_assert_eq(hv_volume_grid_add(v, name, HV_GRID_FLOAT, &g[j]), HV_OK);
    }
    const int32_t *o = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned q = 0; q < HV_LEAF_SIZE; ++q) {
            double p[3], f[4];
            centre(xf, o[3 * l] + (int)(q >> 6), o[3 * l + 1] + (int)((q >> 3) & 7),
                   o[3 * l + 2] + (int)(q & 7), p);
            m->frac(p, m->user, f);
            for (int j = 0; j < m->nmat; ++j) hv_volume_leaf_float(v, g[j], l)[q] = (float)f[j];
        }
    cr_assert_eq(hv_material_table_store(v, t), HV_OK);
    hv_material_table_destroy(t);
    return v;
}

static hv_image *render(const hv_volume *v, const hv_render_options *o)
{
    hv_image *img = NULL;
    hv_status s = hv_render(v, o, NULL, &img);
    cr_assert_eq(s, HV_OK, "render: %s", hv_last_error());
    return img;
}

static void flat(hv_render_options *o)
{
    o->ambient = 1;
    o->diffuse = 0;
    o->specular = 0;
}

/* The default options in mode 0 (volume) or 1 (surface), width x height pixels. */
static hv_render_options mode_options(int mode, int width, int height)
{
    hv_render_options o;
    hv_render_options_init(&o);
    o.mode = mode ? HV_RENDER_SURFACE : HV_RENDER_VOLUME;
    o.width = width;
    o.height = height;
    return o;
}

static void transparent(hv_render_options *o)
{
    for (int k = 0; k < 4; ++k) o->background[k] = 0;
}

static void ortho_eye(hv_render_options *o, const double eye[3], const double target[3],
                      const double up[3], double height)
{
    o->camera.use_eye = 1;
    o->camera.ortho = 1;
    o->camera.ortho_height = height;
    memcpy(o->camera.eye, eye, sizeof o->camera.eye);
    memcpy(o->camera.target, target, sizeof o->camera.target);
    memcpy(o->camera.up, up, sizeof o->camera.up);
}

static const float *px(const hv_image *img, int x, int y)
{
    return img->rgba + 4 * ((size_t)y * (size_t)img->width + (size_t)x);
}

/* ---- slabs: analytic transmittance ---------------------------------------------------- */

/* An infinite slab (in y and z) of N voxels along x: x index 0..N-1. */
typedef struct slab {
    hv_transform xf;
    int n;
} slab;

static int slab_occ(const double p[3], const void *u)
{
    const slab *sl = u;
    double i = (p[0] - sl->xf.origin[0]) / sl->xf.voxel[0];
    return i > -0.5 && i < sl->n - 0.5;
}

static void one_frac(const double p[3], const void *u, double *f)
{
    (void)p;
    (void)u;
    f[0] = 1;
}

static void check_slab(const double voxel[3], int N, double angle_deg, float mat_alpha,
                       double density)
{
    slab sl = {{{voxel[0], voxel[1], voxel[2]}, {0.25, -0.5, 0.75}}, N};
    const hv_transform xf = sl.xf;
    /* colours exactly representable in 8 bits */
    model m = {1, {"solid"}, {{51 / 255.0f, 153 / 255.0f, 204 / 255.0f, mat_alpha}},
               slab_occ, one_frac, &sl};
    int lo[3] = {0, -48 - N, -48}, hi[3] = {N - 1, 47 + N, 47}; /* wide enough for oblique rays */
    hv_volume *v = build(&xf, lo, hi, &m);
    hv_render_options o;
    hv_render_options_init(&o);
    o.width = o.height = 16;
    o.step = 0.25;
    o.density = density; /* per mm */
    flat(&o);
    transparent(&o);
    double a = angle_deg * M_PI / 180, mid[3] = {xf.origin[0] + 0.5 * (N - 1) * voxel[0],
                                                 xf.origin[1], xf.origin[2]};
    double eye[3] = {mid[0] - 60 * cos(a), mid[1] - 60 * sin(a), mid[2]}; /* outside the slab */
    double up[3] = {0, 0, 1};
    ortho_eye(&o, eye, mid, up, 4.0);
    hv_image *img = render(v, &o);
    double T = exp(-o.density * mat_alpha * N * voxel[0] / cos(a));
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const float *p = px(img, x, y);
            cr_expect(fabs(p[3] - (1 - T)) < 2e-3, "pixel %d,%d: alpha %g, analytic %g (angle %g)",
                      x, y, p[3], 1 - T, angle_deg);
            for (int k = 0; k < 3; ++k)
                cr_expect(fabs(p[k] / p[3] - m.colour[0][k]) < 1e-3, "pixel %d,%d channel %d: %g vs %g",
                          x, y, k, p[k] / p[3], m.colour[0][k]);
        }
    hv_image_destroy(img);
    hv_volume_destroy(v);
}

Test(render, slab_transmittance_is_analytic)
{
    double iso[3] = {0.5, 0.5, 0.5};
    check_slab(iso, 12, 0, 1.0f, 0.3);
    check_slab(iso, 12, 35, 1.0f, 0.3);
    /* thick: inside, whole blocks of one composition are composited in closed form */
    check_slab(iso, 64, 0, 1.0f, 0.06);
    check_slab(iso, 64, 35, 1.0f, 0.05);
}

Test(render, slab_anisotropic_voxels_and_material_alpha)
{
    double an[3] = {0.5, 0.8, 0.3};
    check_slab(an, 12, 0, 1.0f, 0.3);
    check_slab(an, 12, 28, 1.0f, 0.3);
    check_slab(an, 12, 0, 102 / 255.0f, 0.3); /* material alpha 0.4 scales the extinction */
    check_slab(an, 48, 20, 102 / 255.0f, 0.1);
}

/* ---- the 64^3 sphere against a brute-force reference marcher -------------------------- */

typedef struct sphere {
    double c[3], r;
} sphere;

static int spheres_occ(const double p[3], const void *u)
{
    const sphere *s = u;
    for (; s->r > 0; ++s) {
        double d2 = 0;
        for (int a = 0; a < 3; ++a) d2 += (p[a] - s->c[a]) * (p[a] - s->c[a]);
        if (d2 <= s->r * s->r) return 1;
    }
    return 0;
}

static void x_gradient(const double p[3], const void *u, double *f)
{
    (void)u;
    double t = (p[0] - 8) / 48;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    f[0] = t;
    f[1] = 1 - t;
}

static const model SPHERE_MODEL = {2, {"red", "blue"}, {{0.9f, 0.1f, 0.1f, 1}, {0.1f, 0.2f, 0.9f, 1}},
                                   spheres_occ, x_gradient, NULL};

/* Independent reference: straight from the closed form (occupancy and fractions at the eight
 * voxel centres around a point, trilinear weights, renormalised over occupied corners), fine
 * steps, exact exponentials, no empty-space skipping, no termination. Ortho camera only. */
static void reference_volume(const model *m, const hv_transform *xf, const hv_render_options *o,
                             float *out)
{
    double f[3], r[3], u[3], n;
    for (int a = 0; a < 3; ++a) f[a] = o->camera.target[a] - o->camera.eye[a];
    n = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    const double dist = n;
    for (int a = 0; a < 3; ++a) f[a] /= n;
    const double *up = o->camera.up;
    r[0] = f[1] * up[2] - f[2] * up[1];
    r[1] = f[2] * up[0] - f[0] * up[2];
    r[2] = f[0] * up[1] - f[1] * up[0];
    n = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    for (int a = 0; a < 3; ++a) r[a] /= n;
    u[0] = r[1] * f[2] - r[2] * f[1];
    u[1] = r[2] * f[0] - r[0] * f[2];
    u[2] = r[0] * f[1] - r[1] * f[0];
    double hh = o->camera.ortho_height / 2, hw = hh * o->width / o->height;
    double dt = 0.125 * xf->voxel[0], tmax = 2 * dist;
    for (int y = 0; y < o->height; ++y)
        for (int x = 0; x < o->width; ++x) {
            double su = (2.0 * (x + 0.5) / o->width - 1) * hw, sv = (1 - 2.0 * (y + 0.5) / o->height) * hh;
            double C[3] = {0, 0, 0}, T = 1;
            for (double t = 0; t < tmax; t += dt) {
                double p[3], idx[3];
                for (int a = 0; a < 3; ++a) {
                    p[a] = o->camera.eye[a] + su * r[a] + sv * u[a] + t * f[a];
                    idx[a] = (p[a] - xf->origin[a]) / xf->voxel[a];
                }
                int i0[3];
                double fr[3];
                for (int a = 0; a < 3; ++a) {
                    i0[a] = (int)floor(idx[a]);
                    fr[a] = idx[a] - i0[a];
                }
                double cov = 0, col[3] = {0, 0, 0};
                for (int cnr = 0; cnr < 8; ++cnr) {
                    int ii[3] = {i0[0] + (cnr >> 2), i0[1] + ((cnr >> 1) & 1), i0[2] + (cnr & 1)};
                    double w = (cnr >> 2 ? fr[0] : 1 - fr[0]) * ((cnr >> 1) & 1 ? fr[1] : 1 - fr[1]) *
                               (cnr & 1 ? fr[2] : 1 - fr[2]);
                    double c[3], fj[4];
                    centre(xf, ii[0], ii[1], ii[2], c);
                    if (w <= 0 || !m->occ(c, m->user)) continue;
                    m->frac(c, m->user, fj);
                    cov += w;
                    for (int k = 0; k < 3; ++k)
                        for (int j = 0; j < m->nmat; ++j) col[k] += w * fj[j] * m->colour[j][k];
                }
                if (cov <= 0) continue;
                double alpha = 1 - exp(-o->density * cov * dt);
                for (int k = 0; k < 3; ++k) C[k] += T * alpha * col[k] / cov;
                T *= 1 - alpha;
            }
            float *q = out + 4 * ((size_t)y * o->width + x);
            for (int k = 0; k < 3; ++k) q[k] = (float)C[k];
            q[3] = (float)(1 - T);
        }
}

static void compare_reference(const hv_image *img, const float *ref, double rmse_max, double max_max)
{

    double s = 0, mx = 0;
    size_t n = (size_t)img->width * img->height * 4;
    for (size_t i = 0; i < n; ++i) {
        double d = fabs(img->rgba[i] - ref[i]);
        s += d * d;
        mx = d > mx ? d : mx;
    }
    double rmse = sqrt(s / n);
    cr_expect(rmse < rmse_max, "RMSE %g against the reference marcher (bound %g)", rmse, rmse_max);
    cr_expect(mx < max_max, "largest difference %g against the reference marcher (bound %g)", mx, max_max);
}

Test(render, sphere_64_matches_reference_marcher)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    sphere s[] = {{{31.5, 31.5, 31.5}, 24}, {{0, 0, 0}, 0}};
    model m = SPHERE_MODEL;
    m.user = s;
    int lo[3] = {0, 0, 0}, hi[3] = {63, 63, 63};
    hv_volume *v = build(&xf, lo, hi, &m);
    hv_render_options o;
    hv_render_options_init(&o);
    o.width = o.height = 64;
    o.step = 0.5;
    o.density = 0.08;
    flat(&o);
    transparent(&o);
    double eye[3] = {31.5 + 60, 31.5 - 150, 31.5 + 70}, tgt[3] = {31.5, 31.5, 31.5}, up[3] = {0, 0, 1};
    ortho_eye(&o, eye, tgt, up, 64);
    hv_image *img = render(v, &o);
    float *ref = malloc(sizeof(float) * 4 * 64 * 64);
    reference_volume(&m, &xf, &o, ref);
    compare_reference(img, ref, 0.001, 0.01); /* measured: 0.0002, 0.002 */
    hv_image_destroy(img);
    free(ref);
    hv_volume_destroy(v);
}

/* Spheres far apart: most blocks along a ray are empty and skipped. */
Test(render, sparse_spheres_match_reference_marcher)
{
    hv_transform xf = {{0.5, 0.5, 0.5}, {-3, 2, 1}};
    sphere s[] = {{{5, 10, 6}, 4}, {{60, 40, 20}, 6}, {{30, 70, 45}, 3}, {{0, 0, 0}, 0}};
    model m = SPHERE_MODEL;
    m.user = s;
    int lo[3] = {0, 0, 0}, hi[3] = {140, 150, 100};
    hv_volume *v = build(&xf, lo, hi, &m);
    hv_render_options o;
    hv_render_options_init(&o);
    o.width = 72;
    o.height = 56;
    o.step = 0.5;
    o.density = 0.3;
    flat(&o);
    transparent(&o);
    double eye[3] = {120, -80, 90}, tgt[3] = {32, 40, 22}, up[3] = {0, 0, 1};
    ortho_eye(&o, eye, tgt, up, 90);
    hv_image *img = render(v, &o);
    float *ref = malloc(sizeof(float) * 4 * 72 * 56);
    reference_volume(&m, &xf, &o, ref);
    compare_reference(img, ref, 0.001, 0.01); /* measured: 0.0002, 0.003 */
    hv_image_destroy(img);
    free(ref);
    hv_volume_destroy(v);
}

/* ---- surface mode: analytic sphere shading --------------------------------------------- */

static void white(const double p[3], const void *u, double *f)
{
    (void)p;
    (void)u;
    f[0] = 1;
}

Test(render, surface_sphere_matches_analytic_shading)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    sphere s[] = {{{31.5, 31.5, 31.5}, 24}, {{0, 0, 0}, 0}};
    model m = {1, {"white"}, {{1, 1, 1, 1}}, spheres_occ, white, s};
    int lo[3] = {0, 0, 0}, hi[3] = {63, 63, 63};
    hv_volume *v = build(&xf, lo, hi, &m);
    hv_render_options o;
    hv_render_options_init(&o);
    o.mode = HV_RENDER_SURFACE;
    o.width = o.height = 128;
    o.ambient = 0;
    o.diffuse = 1;
    o.specular = 0;
    o.light[0] = 0; /* a head light: brightness = n . view */
    o.light[1] = 0;
    o.light[2] = 1;
    transparent(&o);
    double eye[3] = {31.5 + 30, 31.5 - 100, 31.5 + 20}, tgt[3] = {31.5, 31.5, 31.5}, up[3] = {0, 0, 1};
    ortho_eye(&o, eye, tgt, up, 64);
    hv_image *img = render(v, &o);
    double R = 24, s2 = 0, worst = 0;
    int n = 0;
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x) {
            double u = ((x + 0.5) / 64 - 1) * 32, w = (1 - (y + 0.5) / 64) * 32, rho = sqrt(u * u + w * w);
            const float *p = px(img, x, y);
            if (rho < R - 1.5) cr_expect(p[3] == 1.0f, "pixel %d,%d (rho %.1f) should hit", x, y, rho);
            if (rho > R + 1.5) cr_expect(p[3] == 0.0f, "pixel %d,%d (rho %.1f) should miss", x, y, rho);
            if (rho < 0.9 * R) {
                double expect = sqrt(1 - (rho / R) * (rho / R)), d = p[0] - expect;
                s2 += d * d;
                worst = fabs(d) > worst ? fabs(d) : worst;
                ++n;
            }
        }
    double rmse = sqrt(s2 / n);
    /* the voxel staircase leaves a few degrees of normal error, largest towards the rim */
    cr_expect(rmse < 0.022, "shading RMSE %g against n.v of the analytic sphere", rmse);
    cr_expect(worst < 0.12, "worst shading error %g", worst);
    hv_image_destroy(img);
    hv_volume_destroy(v);
}

/* ---- Wu's shaft: a cut shows the radial gradient --------------------------------------- */

#define SHAFT_R 27.5
#define SHAFT_L 150.0

static int shaft_occ(const double p[3], const void *u)
{
    (void)u;
    return p[0] >= 0 && p[0] <= SHAFT_L - 1 && p[1] * p[1] + p[2] * p[2] <= SHAFT_R * SHAFT_R;
}

/* Wu's shaft (example 2): d = depth below the contour, dg = 20.416, f = sin(0.1538 d),
 * Ms = [0, 0, 1], Me = [0, 0.2, 0.8]. */
static double shaft_f(const double p[3])
{
    double r = sqrt(p[1] * p[1] + p[2] * p[2]);
    double d = SHAFT_R - r;
    double dx = fmin(p[0] + 0.5, SHAFT_L - 0.5 - p[0]);
    d = fmin(d, dx);
    d = d < 0 ? 0 : d > 20.416 ? 20.416 : d;
    return sin(0.1538 * d);
}

static void shaft_frac(const double p[3], const void *u, double *f)
{
    (void)u;
    double s = shaft_f(p);
    f[0] = 0;
    f[1] = 0.2 * s;
    f[2] = 1 - 0.2 * s;
}

static const model SHAFT = {3, {"m1", "m2", "m3"}, {{0, 1, 0, 1}, {1, 0, 0, 1}, {0, 0, 1, 1}},
                            shaft_occ, shaft_frac, NULL};

static hv_volume *shaft_volume(void)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    int lo[3] = {0, -28, -28}, hi[3] = {149, 28, 28};
    return build(&xf, lo, hi, &SHAFT);
}

Test(render, shaft_cut_shows_radial_gradient)
{
    hv_volume *v = shaft_volume();
    for (int mode = 0; mode < 2; ++mode) {
        hv_render_options o = mode_options(mode, 128, 128);
        flat(&o);
        cr_assert_eq(hv_clip_parse("x>75", &o.clip[0]), HV_OK);
        o.clips = 1;
        double eye[3] = {300, 0, 0}, tgt[3] = {0, 0, 0}, up[3] = {0, 0, 1};
        ortho_eye(&o, eye, tgt, up, 64);
        hv_image *img = render(v, &o);
        uint8_t *rgba = malloc(128 * 128 * 4);
        hv_image_to_rgba8(img, rgba);
        int checked = 0, ring = 0;
        for (int y = 0; y < 128; ++y)
            for (int x = 0; x < 128; ++x) {
                /* right = fwd x up = (-1,0,0) x (0,0,1) = (0,1,0) */
                double p[3] = {75, ((x + 0.5) / 64 - 1) * 32, (1 - (y + 0.5) / 64) * 32};
                double r = sqrt(p[1] * p[1] + p[2] * p[2]);
                if (r > 26) continue;
                double s = shaft_f(p), expect[3] = {0.2 * s * 255, 0, (1 - 0.2 * s) * 255};
                const uint8_t *q = rgba + 4 * (y * 128 + x);
                for (int k = 0; k < 3; ++k)
                    cr_expect(fabs(q[k] - expect[k]) <= 3.0,
                              "%s: pixel %d,%d (r = %.2f) channel %d: %d, formula %.1f",
                              mode ? "surface" : "volume", x, y, r, k, q[k], expect[k]);
                cr_expect_eq(q[3], 255);
                ring += s > 0.9;
                ++checked;
            }
        cr_expect(checked > 8000 && ring > 1000, "%d pixels on the cut, %d on the red ring", checked, ring);
        free(rgba);
        hv_image_destroy(img);
    }
    hv_volume_destroy(v);
}

/* Without the cut the same view shows the end cap, whose composition is Ms (depth 0). */
Test(render, shaft_end_cap_differs_from_cut)
{
    hv_volume *v = shaft_volume();
    hv_render_options o;
    hv_render_options_init(&o);
    o.mode = HV_RENDER_SURFACE;
    o.width = o.height = 64;
    flat(&o);
    double eye[3] = {300, 0, 0}, tgt[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    ortho_eye(&o, eye, tgt, up, 64);
    hv_image *img = render(v, &o);
    /* pixel 49 sees y = 17.5, where a cut at depth d = 10 would be most red (0.2); the end cap
     * lies at depth ~0.5 */
    int x = 49, y = 32;
    const float *p = px(img, x, y);
    cr_expect(p[0] < 0.03f && p[2] > 0.97f, "end cap at %d,%d: %g %g %g", x, y, p[0], p[1], p[2]);
    hv_image_destroy(img);
    hv_volume_destroy(v);
}

/* ---- clips ------------------------------------------------------------------------------ */

Test(render, clip_parse)
{
    hv_clip c;
    cr_assert_eq(hv_clip_parse("x>10", &c), HV_OK);
    cr_expect(c.planes == 1 && c.normal[0][0] == 1 && c.normal[0][1] == 0 && c.offset[0] == 10);
    cr_assert_eq(hv_clip_parse("z<5", &c), HV_OK);
    cr_expect(c.planes == 1 && c.normal[0][2] == -1 && c.offset[0] == -5);
    cr_assert_eq(hv_clip_parse(" X >= -2.5 & y<1e1 , z>0 ", &c), HV_OK);
    cr_expect(c.planes == 3 && c.normal[0][0] == 1 && c.offset[0] == -2.5 && c.normal[1][1] == -1 &&
              c.offset[1] == -10 && c.normal[2][2] == 1 && c.offset[2] == 0);
    static const struct { const char *expr, *msg; } bad[] = {
        {"", "column 1: axis"},        {"w>1", "column 1: axis"},   {"x=1", "column 2: '<' or '>'"},
        {"x>", "column 3: number"},     {"x>1&", "column 5: axis"}, {"x>abc", "column 3: number"},
        {"x>1;y<2", "column 4: '&'"},  {"x>1e999", "out of range"},
        {"x>1&x>2&x>3&x>4&x>5&x>6&x>7&x>8&x>9", "too many"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        cr_expect_eq(hv_clip_parse(bad[i].expr, &c), HV_ERR_INVALID, "'%s' accepted", bad[i].expr);
        cr_expect(strstr(hv_last_error(), bad[i].msg) != NULL, "'%s': message '%s'", bad[i].expr,
                  hv_last_error());
    }
    double lo[3] = {0, 0, 0}, hi[3] = {1, 0, 1};
    cr_expect_eq(hv_clip_box(lo, hi, &c), HV_ERR_INVALID);
    hi[1] = 2;
    cr_expect_eq(hv_clip_box(lo, hi, &c), HV_OK);
    cr_expect_eq(c.planes, 6);
}

static int box_occ(const double p[3], const void *u)
{
    (void)u;
    return fabs(p[0]) <= 20 && fabs(p[1]) <= 20 && p[2] >= 0 && p[2] <= 20;
}

/* fraction of material 0 grows with height: a cut face's depth shows in its colour */
static void z_frac(const double p[3], const void *u, double *f)
{
    (void)u;
    double t = p[2] / 20;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    f[0] = t;
    f[1] = 1 - t;
}

static const model BOX = {2, {"top", "bottom"}, {{1, 0, 0, 1}, {0, 0, 1, 1}}, box_occ, z_frac, NULL};

static hv_image *box_top_view(hv_volume *v, const char **clips, int nclips, const double *box)
{
    hv_render_options o;
    hv_render_options_init(&o);
    o.mode = HV_RENDER_SURFACE;
    o.width = o.height = 64;
    flat(&o);
    transparent(&o);
    for (int i = 0; i < nclips; ++i) cr_assert_eq(hv_clip_parse(clips[i], &o.clip[o.clips++]), HV_OK);
    if (box) cr_assert_eq(hv_clip_box(box, box + 3, &o.clip[o.clips++]), HV_OK);
    double eye[3] = {0, 0, 100}, tgt[3] = {0, 0, 10}, up[3] = {0, 1, 0};
    ortho_eye(&o, eye, tgt, up, 64);
    return render(v, &o);
}

/* Top view of pixel (x, y): world (x, y) */
static void top_xy(int x, int y, double *wx, double *wy)
{
    *wx = (x + 0.5) - 32;
    *wy = 32 - (y + 0.5);
}

Test(render, clips_remove_the_union_of_their_regions)
{
    hv_transform xf = {{0.5, 0.5, 0.5}, {0, 0, 0}};
    int lo[3] = {-42, -42, -2}, hi[3] = {42, 42, 42};
    hv_volume *v = build(&xf, lo, hi, &BOX);
    const char *two[] = {"x>0", "y>0"}, *both[] = {"x>0&y>0"};
    hv_image *a = box_top_view(v, two, 2, NULL), *b = box_top_view(v, both, 1, NULL);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            double wx, wy;
            top_xy(x, y, &wx, &wy);
            if (fabs(wx) > 19 || fabs(wy) > 19 || fabs(wx) < 1 || fabs(wy) < 1) continue;
            int in_a = !(wx > 0 || wy > 0), in_b = !(wx > 0 && wy > 0);
            cr_expect_eq(px(a, x, y)[3] > 0.5f, in_a, "two clips, pixel at (%g, %g)", wx, wy);
            cr_expect_eq(px(b, x, y)[3] > 0.5f, in_b, "x>0&y>0, pixel at (%g, %g)", wx, wy);
            if (in_b) /* the top face: composition at z = 20 (pure red) */
                cr_expect(px(b, x, y)[0] > 0.97f, "top face at (%g, %g): red %g", wx, wy, px(b, x, y)[0]);
        }
    hv_image_destroy(a);
    hv_image_destroy(b);
    hv_volume_destroy(v);
}

Test(render, clip_box_shows_the_cut_face_at_its_depth)
{
    hv_transform xf = {{0.5, 0.5, 0.5}, {0, 0, 0}};
    int lo[3] = {-42, -42, -2}, hi[3] = {42, 42, 42};
    hv_volume *v = build(&xf, lo, hi, &BOX);
    double box[6] = {-10, -10, 8, 10, 10, 30}; /* a pocket 12 deep from the top */
    hv_image *img = box_top_view(v, NULL, 0, box);
    uint8_t *q = malloc(64 * 64 * 4);
    hv_image_to_rgba8(img, q);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            double wx, wy;
            top_xy(x, y, &wx, &wy);
            if (fabs(wx) > 19 || fabs(wy) > 19) continue;
            int pocket = fabs(wx) < 9 && fabs(wy) < 9, rim = fabs(wx) > 11 || fabs(wy) > 11;
            double t = pocket ? 8.0 / 20 : 1.0; /* the composition at the visible depth */
            const uint8_t *p = q + 4 * (y * 64 + x);
            if (pocket || rim) {
                cr_expect(abs(p[0] - (int)lround(255 * t)) <= 2 && abs(p[2] - (int)lround(255 * (1 - t))) <= 2,
                          "pixel at (%g, %g): %d %d %d, expected t = %g", wx, wy, p[0], p[1], p[2], t);
                cr_expect_eq(p[3], 255);
            }
        }
    free(q);
    hv_image_destroy(img);
    hv_volume_destroy(v);
}

/* ---- views and framing ----------------------------------------------------------------- */

static int markers_occ(const double p[3], const void *u)
{
    (void)u;
    if (fabs(p[0]) <= 10 && fabs(p[1]) <= 10 && fabs(p[2]) <= 10) return 1;
    if (p[0] > 10 && p[0] <= 24 && fabs(p[1]) <= 3 && fabs(p[2]) <= 3) return 1; /* +x: red */
    if (p[1] > 10 && p[1] <= 24 && fabs(p[0]) <= 3 && fabs(p[2]) <= 3) return 1; /* +y: green */
    if (p[2] > 10 && p[2] <= 24 && fabs(p[0]) <= 3 && fabs(p[1]) <= 3) return 1; /* +z: blue */
    return 0;
}

static void markers_frac(const double p[3], const void *u, double *f)
{
    (void)u;
    f[0] = f[1] = f[2] = 0;
    f[3] = 1;
    if (p[0] > 10.5) f[0] = 1, f[3] = 0;
    if (p[1] > 10.5) f[1] = 1, f[3] = 0;
    if (p[2] > 10.5) f[2] = 1, f[3] = 0;
}

/* centroid (in [-1, 1], y up) of the pixels of a pure colour; returns the pixel count */
static int centroid(const hv_image *img, int ch, double *cx, double *cy)
{
    double sx = 0, sy = 0;
    int n = 0;
    for (int y = 0; y < img->height; ++y)
        for (int x = 0; x < img->width; ++x) {
            const float *p = px(img, x, y);
            if (p[3] < 0.99f || p[ch] < 0.9f || p[(ch + 1) % 3] > 0.1f || p[(ch + 2) % 3] > 0.1f) continue;
            sx += 2.0 * (x + 0.5) / img->width - 1;
            sy += 1 - 2.0 * (y + 0.5) / img->height;
            ++n;
        }
    *cx = n ? sx / n : 0;
    *cy = n ? sy / n : 0;
    return n;
}

Test(render, views_orient_the_axes_and_fit_the_model)
{
    hv_transform xf = {{0.5, 0.5, 0.5}, {0, 0, 0}};
    model m = {4, {"x", "y", "z", "core"}, {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {0.5f, 0.5f, 0.5f, 1}},
               markers_occ, markers_frac, NULL};
    int lo[3] = {-22, -22, -22}, hi[3] = {50, 50, 50};
    hv_volume *v = build(&xf, lo, hi, &m);
    /* expected sign of the centroid (x, y) of the red, green and blue markers; 0: not checked */
    static const struct { hv_view view; int rx, ry, gx, gy, bx, by; } E[] = {
        {HV_VIEW_FRONT, 1, 0, 0, 0, 0, 1},  {HV_VIEW_BACK, -1, 0, 0, 0, 0, 1},
        {HV_VIEW_LEFT, 0, 0, -1, 0, 0, 1},  {HV_VIEW_RIGHT, 0, 0, 1, 0, 0, 1},
        {HV_VIEW_TOP, 1, 0, 0, 1, 0, 0},    {HV_VIEW_BOTTOM, 1, 0, 0, -1, 0, 0},
        {HV_VIEW_ISO, 0, 0, 0, 0, 0, 0}};
    for (int ortho = 0; ortho < 2; ++ortho)
        for (size_t i = 0; i < sizeof E / sizeof E[0]; ++i) {
            hv_render_options o;
            hv_render_options_init(&o);
            o.mode = HV_RENDER_SURFACE;
            o.width = 96;
            o.height = 64;
            o.camera.view = E[i].view;
            o.camera.ortho = ortho;
            flat(&o);
            transparent(&o);
            hv_image *img = render(v, &o);
            const char *name = hv_view_name(E[i].view);
            int want[3][2] = {{E[i].rx, E[i].ry}, {E[i].gx, E[i].gy}, {E[i].bx, E[i].by}};
            double mx[3], my[3];
            for (int ch = 0; ch < 3; ++ch) {
                double cx, cy;
                int n = centroid(img, ch, &cx, &cy);
                mx[ch] = cx;
                my[ch] = cy;
                if (!want[ch][0] && !want[ch][1]) continue;
                cr_expect(n > 3, "%s%s: marker %d not visible", name, ortho ? " ortho" : "", ch);
                if (want[ch][0]) cr_expect(cx * want[ch][0] > 0.1, "%s%s: marker %d at x %g", name, ortho ? " ortho" : "", ch, cx);
                if (want[ch][1]) cr_expect(cy * want[ch][1] > 0.1, "%s%s: marker %d at y %g", name, ortho ? " ortho" : "", ch, cy);
            }
            if (E[i].view == HV_VIEW_ISO) { /* from (1,-1,1): +z up, +x right-down, +y right-up */
                cr_expect(mx[0] > mx[2] + 0.1 && mx[1] > mx[2] + 0.1, "%s%s: x %g %g %g", name,
                          ortho ? " ortho" : "", mx[0], mx[1], mx[2]);
                cr_expect(my[2] > my[1] + 0.1 && my[1] > my[0] + 0.1, "%s%s: y %g %g %g", name,
                          ortho ? " ortho" : "", my[0], my[1], my[2]);
            }
            /* fitted: nothing touches the border, and the model fills the frame */
            int x0 = 96, x1 = -1, y0 = 64, y1 = -1;
            for (int y = 0; y < 64; ++y)
                for (int x = 0; x < 96; ++x)
                    if (px(img, x, y)[3] > 0) {
                        x0 = x < x0 ? x : x0;
                        x1 = x > x1 ? x : x1;
                        y0 = y < y0 ? y : y0;
                        y1 = y > y1 ? y : y1;
                    }
            cr_expect(x0 > 0 && y0 > 0 && x1 < 95 && y1 < 63, "%s%s: touches the border (%d..%d, %d..%d)",
                      name, ortho ? " ortho" : "", x0, x1, y0, y1);
            cr_expect(y1 - y0 > 64 * 0.55 || x1 - x0 > 96 * 0.55, "%s%s: loosely framed (%d..%d, %d..%d)",
                      name, ortho ? " ortho" : "", x0, x1, y0, y1);
            hv_image_destroy(img);
        }
    hv_volume_destroy(v);
}

/* ---- determinism, grey models, errors, progress ---------------------------------------- */

Test(render, output_does_not_depend_on_thread_count)
{
    hv_volume *v = shaft_volume();
    for (int mode = 0; mode < 2; ++mode) {
        hv_render_options o = mode_options(mode, 100, 70);
        o.samples = 2;
        cr_assert_eq(hv_clip_parse("x>60&y<0", &o.clip[0]), HV_OK);
        o.clips = 1;
        hv_set_threads(1);
        hv_image *a = render(v, &o);
        hv_set_threads(3);
        hv_image *b = render(v, &o);
        hv_set_threads(0);
        cr_expect(memcmp(a->rgba, b->rgba, sizeof(float) * 4 * 100 * 70) == 0, "mode %d differs", mode);
        hv_image_destroy(a);
        hv_image_destroy(b);
    }
    hv_volume_destroy(v);
}

/* One picture from a scene built eagerly or lazily, with `threads` workers. */
static hv_image *render_scene(const hv_volume *v, const hv_render_options *o, int lazy, int threads)
{
    hv_render_scene *sc = NULL;
    hv_status s = lazy ? hv_render_scene_create_lazy(v, NULL, &sc) : hv_render_scene_create(v, NULL, &sc);
    cr_assert_eq(s, HV_OK, "%s", hv_last_error());
    hv_set_threads(threads);
    hv_image *img = NULL;
    s = hv_render_scene_image(sc, o, NULL, &img);
    hv_set_threads(0);
    cr_assert_eq(s, HV_OK, "%s", hv_last_error());
    hv_render_scene_destroy(sc);
    return img;
}

Test(render, lazy_scene_gives_the_eager_image)
{
    /* the scene filled block by block as rays reach it, by whichever thread gets there first,
     * gives exactly the picture of the scene filled before rendering: views seeing a little
     * (a small image, a clipped corner) or all of the model, both modes, 1 to 4 threads */
    hv_volume *v = shaft_volume();
    struct {
        int w, h, mode, view, samples;
        const char *clip;
    } cases[] = {
        {8, 6, HV_RENDER_VOLUME, HV_VIEW_ISO, 1, NULL},
        {96, 64, HV_RENDER_VOLUME, HV_VIEW_FRONT, 1, NULL},
        {80, 80, HV_RENDER_SURFACE, HV_VIEW_ISO, 1, "x>60&y<0"},
        {64, 48, HV_RENDER_VOLUME, HV_VIEW_TOP, 2, "z>0"},
        {72, 40, HV_RENDER_SURFACE, HV_VIEW_RIGHT, 1, NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        hv_render_options o;
        hv_render_options_init(&o);
        o.width = cases[i].w;
        o.height = cases[i].h;
        o.mode = (hv_render_mode)cases[i].mode;
        o.camera.view = (hv_view)cases[i].view;
        o.samples = cases[i].samples;
        if (cases[i].clip) {
            cr_assert_eq(hv_clip_parse(cases[i].clip, &o.clip[0]), HV_OK);
            o.clips = 1;
        }
        hv_image *eager = render_scene(v, &o, 0, 1);
        size_t bytes = sizeof(float) * 4 * (size_t)o.width * (size_t)o.height;
        for (int threads = 1; threads <= 4; ++threads) {
            hv_image *lazy = render_scene(v, &o, 1, threads);
            cr_expect(memcmp(eager->rgba, lazy->rgba, bytes) == 0, "case %zu, %d threads: the lazy scene differs", i,
                      threads);
            hv_image_destroy(lazy);
        }
        hv_image *via = render(v, &o); /* hv_render: a lazy scene too */
        cr_expect(memcmp(eager->rgba, via->rgba, bytes) == 0, "case %zu: hv_render differs", i);
        hv_image_destroy(via);
        hv_image_destroy(eager);
    }
    hv_volume_destroy(v);
}

Test(render, lazy_scene_renders_again_and_keeps_its_blocks)
{
    /* one lazy scene, several pictures: a small view fills a few blocks, a wider one the rest;
     * each picture equals that of the eager scene, which no longer needs its model */
    hv_volume *v = shaft_volume(), *copy = NULL;
    hv_render_scene *lazy = NULL, *eager = NULL;
    cr_assert_eq(hv_render_scene_create_lazy(v, NULL, &lazy), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_clone(v, &copy), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_render_scene_create(copy, NULL, &eager), HV_OK, "%s", hv_last_error());
    hv_volume_destroy(copy);
    double a[3], b[3], c[3], d[3];
    cr_assert(hv_render_scene_bounds(lazy, a, b));
    cr_assert(hv_render_scene_bounds(eager, c, d));
    for (int k = 0; k < 3; ++k) cr_assert(a[k] == c[k] && b[k] == d[k]);
    cr_assert_eq(hv_render_scene_materials(lazy), hv_render_scene_materials(eager));
    for (int pass = 0; pass < 3; ++pass) {
        hv_render_options o;
        hv_render_options_init(&o);
        o.width = pass == 0 ? 6 : 90;
        o.height = pass == 0 ? 4 : 50;
        o.mode = pass == 2 ? HV_RENDER_SURFACE : HV_RENDER_VOLUME;
        hv_set_threads(pass + 1);
        hv_image *x = NULL, *y = NULL;
        cr_assert_eq(hv_render_scene_image(lazy, &o, NULL, &x), HV_OK, "%s", hv_last_error());
        cr_assert_eq(hv_render_scene_image(eager, &o, NULL, &y), HV_OK, "%s", hv_last_error());
        hv_set_threads(0);
        cr_expect(memcmp(x->rgba, y->rgba, sizeof(float) * 4 * (size_t)o.width * (size_t)o.height) == 0, "pass %d differs",
                  pass);
        hv_image_destroy(x);
        hv_image_destroy(y);
    }
    hv_render_scene_destroy(lazy);
    hv_render_scene_destroy(eager);
    hv_volume_destroy(v);
}

Test(render, volume_load_reads_what_the_scene_needs)
{
    /* hv_render_volume_load: occupancy and materials, the same picture as the whole model read
     * from the same file (the file holds the fractions as half floats) */
    hv_volume *v = shaft_volume();
    cr_assert_eq(hv_volume_grid_add(v, "surface", HV_GRID_BOOL, NULL), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "density", HV_GRID_FLOAT, NULL), HV_OK);
    const char *path = t_tmpfile("render_load.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
    hv_volume *r = NULL;
    cr_assert_eq(hv_render_volume_load(path, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_grid_count(r), 1 + SHAFT.nmat);
    cr_assert_eq(hv_volume_grid_find(r, "surface"), -1);
    cr_assert_eq(hv_volume_grid_find(r, "density"), -1);
    hv_render_options o;
    hv_render_options_init(&o);
    o.width = 64;
    o.height = 40;
    hv_volume *whole = NULL;
    cr_assert_eq(hv_volume_load(path, &whole), HV_OK, "%s", hv_last_error());
    hv_image *a = render(whole, &o), *b = render(r, &o);
    cr_expect(memcmp(a->rgba, b->rgba, sizeof(float) * 4 * 64 * 40) == 0);
    hv_image_destroy(a);
    hv_image_destroy(b);
    hv_volume_destroy(r);
    hv_volume_destroy(whole);
    /* without "occupancy", every active voxel is occupied: all grids are read */
    cr_assert_eq(hv_volume_grid_remove(v, hv_volume_grid_find(v, "occupancy")), HV_OK);
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_render_volume_load(path, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_grid_count(r), hv_volume_grid_count(v));
    hv_volume_destroy(r);
    hv_volume_destroy(v);
}

Test(render, volume_load_leaves_the_colour_depth)
{
    /* a painted model (issue 26 review): hv_render_volume_load reads the colour grids the scene
     * paints with (colour.r, .g, .b, .mask), not colour.depth (a float per voxel only the stack
     * uses); the same picture as the whole model read from the same file */
    const uint32_t rgba[2] = {0xff2020ffu, 0x20ff20ffu};
    hv_mesh *m = NULL;
    hv_volume *v = t_painted_cube(6, rgba, 2, &m);
    cr_assert_geq(hv_volume_grid_find(v, "colour.depth"), 0, "painting writes colour.depth");
    const char *path = t_tmpfile("painted_load.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
    hv_volume *r = NULL, *whole = NULL;
    cr_assert_eq(hv_render_volume_load(path, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_load(path, &whole), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_grid_find(r, "colour.depth"), -1, "the render loaded colour.depth");
    cr_assert_geq(hv_volume_grid_find(r, "colour.mask"), 0, "the render left the colours");
    for (int g = 0; g < hv_volume_grid_count(whole); ++g) { /* every other grid read is one the scene uses */
        const char *n = hv_volume_grid_name(whole, g);
        int wanted = strncmp(n, "material.", 9) == 0 || (strncmp(n, "colour.", 7) == 0 && strcmp(n, "colour.depth") != 0) ||
                     strcmp(n, "occupancy") == 0;
        cr_expect_eq(hv_volume_grid_find(r, n) >= 0, wanted, "%s: %s", n, wanted ? "not loaded" : "loaded");
    }
    for (int mode = 0; mode < 2; ++mode) {
        hv_render_options o = mode_options(mode, 64, 48);
        hv_image *a = render(whole, &o), *b = render(r, &o);
        cr_expect(memcmp(a->rgba, b->rgba, sizeof(float) * 4 * 64 * 48) == 0, "mode %d: other pixels", mode);
        hv_image_destroy(a);
        hv_image_destroy(b);
    }
    hv_volume_destroy(r);
    hv_volume_destroy(whole);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

extern int r_render_base; /* renderer/render_internal.h */

Test(render, instruction_set_variants_agree)
{
    /* the AVX2 ray caster (where the CPU has it) and the general one: the same floats */
    hv_volume *v = shaft_volume();
    for (int mode = 0; mode < 2; ++mode) {
        hv_render_options o = mode_options(mode, 120, 90);
        cr_assert_eq(hv_clip_parse("x>60&z>0", &o.clip[0]), HV_OK);
        o.clips = 1;
        hv_image *a = render(v, &o);
        r_render_base = 1;
        hv_image *b = render(v, &o);
        r_render_base = 0;
        cr_expect(memcmp(a->rgba, b->rgba, sizeof(float) * 4 * 120 * 90) == 0, "mode %d differs", mode);
        hv_image_destroy(a);
        hv_image_destroy(b);
    }
    hv_volume_destroy(v);
}

Test(render, model_without_materials_is_grey)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    sphere s[] = {{{10, 10, 10}, 8}, {{0, 0, 0}, 0}};
    model m = {0, {NULL}, {{0}}, spheres_occ, NULL, s};
    int lo[3] = {0, 0, 0}, hi[3] = {20, 20, 20};
    hv_volume *v = build(&xf, lo, hi, &m);
    hv_render_scene *sc;
    cr_assert_eq(hv_render_scene_create(v, NULL, &sc), HV_OK, "%s", hv_last_error());
    cr_expect_eq(hv_render_scene_materials(sc), 0);
    double blo[3], bhi[3];
    cr_assert(hv_render_scene_bounds(sc, blo, bhi));
    cr_expect(fabs(blo[0] - 1.5) < 1e-9 && fabs(bhi[2] - 18.5) < 1e-9, "bounds %g..%g", blo[0], bhi[2]);
    hv_render_options o;
    hv_render_options_init(&o);
    o.mode = HV_RENDER_SURFACE;
    o.width = o.height = 32;
    flat(&o);
    hv_image *img;
    cr_assert_eq(hv_render_scene_image(sc, &o, NULL, &img), HV_OK, "%s", hv_last_error());
    const float *p = px(img, 16, 16);
    cr_expect(fabs(p[0] - 0.7) < 0.003 && fabs(p[1] - 0.7) < 0.003 && fabs(p[2] - 0.7) < 0.003,
              "centre %g %g %g", p[0], p[1], p[2]);
    hv_image_destroy(img);
    hv_render_scene_destroy(sc);
    hv_volume_destroy(v);
}

Test(render, corrupt_material_table_is_bad_input)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    sphere s[] = {{{10, 10, 10}, 8}, {{0, 0, 0}, 0}};
    model m = {0, {NULL}, {{0}}, spheres_occ, NULL, s};
    int lo[3] = {0, 0, 0}, hi[3] = {20, 20, 20};
    hv_volume *v = build(&xf, lo, hi, &m);
    cr_assert_eq(hv_volume_meta_set_string(v, "hovox.materials.json", "{\"materials\": [{\"name\": \"a\", "
                                           "\"color\": [1, 0, 0, 1]}]}"), HV_OK);
    hv_render_scene *sc = (hv_render_scene *)1;
    cr_expect_eq(hv_render_scene_create(v, NULL, &sc), HV_ERR_BAD_INPUT);
    cr_expect_null(sc);
    cr_expect(strstr(hv_last_error(), "material.a") != NULL, "%s", hv_last_error());
    hv_volume_destroy(v);
}

Test(render, empty_model)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    hv_volume *v;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    hv_render_options o;
    hv_render_options_init(&o);
    o.width = o.height = 8;
    hv_image *img = (hv_image *)1;
    cr_expect_eq(hv_render(v, &o, NULL, &img), HV_ERR_INVALID);
    cr_expect_null(img);
    cr_expect(strstr(hv_last_error(), "no occupied voxels") != NULL, "%s", hv_last_error());
    double eye[3] = {10, 0, 0}, tgt[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    ortho_eye(&o, eye, tgt, up, 5);
    o.background[0] = 0.25f;
    img = render(v, &o);
    cr_expect(px(img, 3, 3)[0] == 0.25f && px(img, 3, 3)[3] == 1.0f);
    hv_image_destroy(img);
    hv_volume_destroy(v);
}

Test(render, bad_options_are_rejected)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    sphere s[] = {{{10, 10, 10}, 6}, {{0, 0, 0}, 0}};
    model m = {0, {NULL}, {{0}}, spheres_occ, NULL, s};
    int lo[3] = {0, 0, 0}, hi[3] = {20, 20, 20};
    hv_volume *v = build(&xf, lo, hi, &m);
    hv_render_scene *sc;
    cr_assert_eq(hv_render_scene_create(v, NULL, &sc), HV_OK);
    for (int c = 0; c < 16; ++c) {
        hv_render_options o;
        hv_render_options_init(&o);
        o.width = o.height = 8;
        const char *want = "render:";
        switch (c) {
        case 0: o.width = 0; want = "size must be"; break;
        case 1: o.height = 70000; want = "size must be"; break;
        case 2: o.step = -1; want = "step"; break;
        case 3: o.step = 5; want = "step"; break;
        case 4: o.density = NAN; want = "density"; break;
        case 5: o.tf_low = 0.6; o.tf_high = 0.5; want = "tf_low"; break;
        case 6: o.iso = 1; want = "iso"; break;
        case 7: o.camera.use_eye = 1; want = "equals the target"; break;
        case 8: o.camera.use_eye = 1; o.camera.eye[2] = 5; o.camera.up[2] = -1; want = "parallel"; break;
        case 9: o.camera.fov = 0; want = "fov"; break;
        case 10: o.samples = 9; want = "aa"; break;
        case 11: o.clips = 17; want = "clips"; break;
        case 12: o.clips = 1; o.clip[0].planes = 0; want = "planes"; break;
        case 13: o.clips = 1; o.clip[0].planes = 1; want = "non-zero"; break;
        case 14: o.background[1] = 2; want = "background"; break;
        case 15: o.cut_opacity = -0.5; want = "cut_opacity"; break;
        }
        hv_image *img = (hv_image *)1;
        cr_expect_eq(hv_render_scene_image(sc, &o, NULL, &img), HV_ERR_INVALID, "case %d accepted", c);
        cr_expect_null(img, "case %d", c);
        cr_expect(strstr(hv_last_error(), want) != NULL, "case %d: '%s' lacks '%s'", c, hv_last_error(), want);
    }
    hv_render_scene_destroy(sc);
    hv_volume_destroy(v);
}

Test(render, volumes_from_other_tools_and_spread_out_volumes)
{
    /* no "occupancy" grid (a plain density grid, as other tools write): active voxels count */
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    hv_volume *v;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "density", HV_GRID_FLOAT, NULL), HV_OK);
    int32_t org[6] = {0, 0, 0, 1 << 22, 1 << 22, 1 << 22};
    uint64_t msk[16];
    memset(msk, 0xFF, sizeof msk);
    cr_assert_eq(hv_volume_topology_add(v, 1, org, msk), HV_OK);
    hv_render_scene *sc;
    cr_assert_eq(hv_render_scene_create(v, NULL, &sc), HV_OK, "%s", hv_last_error());
    double lo[3], hi[3];
    cr_assert(hv_render_scene_bounds(sc, lo, hi));
    cr_expect(lo[0] == -0.5 && hi[0] == 7.5, "bounds %g..%g", lo[0], hi[0]);
    hv_render_scene_destroy(sc);
    /* a second block 2^22 voxels away on every axis: the block table would be too large */
    cr_assert_eq(hv_volume_topology_add(v, 1, org + 3, msk + 8), HV_OK);
    sc = (hv_render_scene *)1;
    cr_expect_eq(hv_render_scene_create(v, NULL, &sc), HV_ERR_LIMIT);
    cr_expect_null(sc);
    cr_expect(strstr(hv_last_error(), "too spread out") != NULL, "%s", hv_last_error());
    hv_volume_destroy(v);
}

static int cancel_after(void *user, const char *stage, double f)
{
    (void)f;
    int *calls = user;
    return strcmp(stage, "render") == 0 && ++*calls > 1;
}

Test(render, progress_can_cancel)
{
    hv_volume *v = shaft_volume();
    hv_render_options o;
    hv_render_options_init(&o);
    o.width = o.height = 256;
    int calls = 0;
    hv_progress p = {cancel_after, &calls};
    hv_image *img = (hv_image *)1;
    hv_set_threads(1);
    cr_expect_eq(hv_render(v, &o, &p, &img), HV_ERR_CANCELLED);
    hv_set_threads(0);
    cr_expect_null(img);
    hv_volume_destroy(v);
}

Test(render, supersampling_softens_edges_only)
{
    hv_volume *v = shaft_volume();
    hv_render_options o;
    hv_render_options_init(&o);
    o.mode = HV_RENDER_SURFACE;
    o.width = o.height = 48;
    o.camera.view = HV_VIEW_FRONT;
    transparent(&o);
    hv_image *a = render(v, &o);
    o.samples = 3;
    hv_image *b = render(v, &o);
    int partial_a = 0, partial_b = 0;
    for (int i = 0; i < 48 * 48; ++i) {
        partial_a += a->rgba[4 * i + 3] > 0 && a->rgba[4 * i + 3] < 1;
        partial_b += b->rgba[4 * i + 3] > 0.01f && b->rgba[4 * i + 3] < 0.99f;
    }
    cr_expect_eq(partial_a, 0);
    cr_expect(partial_b > 20, "%d edge pixels with partial coverage", partial_b);
    hv_image_destroy(a);
    hv_image_destroy(b);
    hv_volume_destroy(v);
}

/* ---- stored reference images ----------------------------------------------------------- */

static uint8_t *read_png(const char *path, int *w, int *h)
{
    png_image im;
    memset(&im, 0, sizeof im);
    im.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&im, path)) return NULL;
    im.format = PNG_FORMAT_RGBA;
    uint8_t *buf = malloc(PNG_IMAGE_SIZE(im));
    if (!png_image_finish_read(&im, NULL, buf, 0, NULL)) {
        free(buf);
        return NULL;
    }
    *w = (int)im.width;
    *h = (int)im.height;
    return buf;
}

/* Compare with tests/renderer/data/NAME.png within a tolerance: RMSE <= 1.5 (8-bit units) and
 * at most 0.5% of the values off by more than 16. HOVOX_UPDATE_REFERENCE=1 rewrites it. */
static void check_reference(const char *name, const hv_image *img)
{
    char path[512];
    snprintf(path, sizeof path, "tests/renderer/data/%s.png", name);
    if (getenv("HOVOX_UPDATE_REFERENCE")) {
        cr_assert_eq(hv_image_write(img, path), HV_OK, "%s", hv_last_error());
        return;
    }
    /* also exercises the PNG writer: compare what was written */
    const char *mine = t_tmpfile(name);
    cr_assert_eq(hv_image_write(img, mine), HV_ERR_UNSUPPORTED); /* no extension */
    char mine_png[600];
    snprintf(mine_png, sizeof mine_png, "%s.png", mine);
    cr_assert_eq(hv_image_write(img, mine_png), HV_OK, "%s", hv_last_error());
    int w, h, w2, h2;
    uint8_t *ref = read_png(path, &w, &h), *got = read_png(mine_png, &w2, &h2);
    cr_assert_not_null(ref, "cannot read %s (run from the repository root)", path);
    cr_assert_not_null(got);
    cr_assert(w == w2 && h == h2, "%s: size %dx%d, reference %dx%d", name, w2, h2, w, h);
    double s = 0;
    size_t n = (size_t)w * h * 4, big = 0;
    for (size_t i = 0; i < n; ++i) {
        int d = abs(ref[i] - got[i]);
        s += d * d;
        big += d > 16;
    }
    double rmse = sqrt(s / n);
    cr_expect(rmse <= 1.5 && big <= n / 200, "%s: RMSE %.3f, %zu values off by > 16", name, rmse, big);
    free(ref);
    free(got);
}

static void radial(const double p[3], const void *u, double *f)
{
    (void)u;
    double r = sqrt((p[0] - 31.5) * (p[0] - 31.5) + (p[1] - 31.5) * (p[1] - 31.5) +
                    (p[2] - 31.5) * (p[2] - 31.5));
    double t = r / 24;
    t = t > 1 ? 1 : t;
    f[0] = (1 - t) * (1 - t);
    f[1] = 2 * t * (1 - t);
    f[2] = t * t;
}

Test(render, reference_images)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    sphere s[] = {{{31.5, 31.5, 31.5}, 24}, {{0, 0, 0}, 0}};
    model m = SPHERE_MODEL;
    m.user = s;
    model mr = {3, {"core", "middle", "shell"}, {{0.95f, 0.45f, 0.1f, 1}, {0.95f, 0.9f, 0.3f, 1}, {0.1f, 0.5f, 0.6f, 1}},
                spheres_occ, radial, s};
    int lo[3] = {0, 0, 0}, hi[3] = {63, 63, 63};
    hv_volume *sph = build(&xf, lo, hi, &m), *rad = build(&xf, lo, hi, &mr), *shaft = shaft_volume();
    hv_render_options o;
    hv_render_options_init(&o);
    o.width = o.height = 128;
    o.mode = HV_RENDER_SURFACE;
    hv_image *img = render(sph, &o);
    check_reference("sphere_surface_iso", img);
    hv_image_destroy(img);

    o.mode = HV_RENDER_VOLUME;
    img = render(sph, &o);
    check_reference("sphere_volume_iso", img);
    hv_image_destroy(img);

    /* the classic cut-away: the octant facing the iso camera removed */
    cr_assert_eq(hv_clip_parse("x>31.5&y<31.5&z>31.5", &o.clip[0]), HV_OK);
    o.clips = 1;
    o.mode = HV_RENDER_SURFACE;
    img = render(rad, &o);
    check_reference("radial_cutaway_surface_iso", img);
    hv_image_destroy(img);

    o.mode = HV_RENDER_VOLUME;
    img = render(rad, &o);
    check_reference("radial_cutaway_volume_iso", img);
    hv_image_destroy(img);

    /* Wu's shaft cut lengthwise, seen from the front */
    hv_render_options_init(&o);
    o.width = 192;
    o.height = 80;
    o.camera.view = HV_VIEW_FRONT;
    o.camera.ortho = 1;
    cr_assert_eq(hv_clip_parse("y<0", &o.clip[0]), HV_OK);
    o.clips = 1;
    img = render(shaft, &o);
    check_reference("shaft_cut_volume_front", img);
    hv_image_destroy(img);
    o.mode = HV_RENDER_SURFACE;
    o.camera.view = HV_VIEW_ISO;
    o.camera.ortho = 0;
    cr_assert_eq(hv_clip_parse("x>75&y<0", &o.clip[0]), HV_OK);
    img = render(shaft, &o);
    check_reference("shaft_cutaway_surface_iso", img);
    hv_image_destroy(img);
    hv_volume_destroy(sph);
    hv_volume_destroy(rad);
    hv_volume_destroy(shaft);
}
