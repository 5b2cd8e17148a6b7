/* src/mesh/generate.c - parametric closed meshes for tests, benchmarks and samples. Each
 * builder emits consistently wound facets; the result is flipped as a whole if its signed
 * volume comes out negative, so normals always point outward. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/generate.h"
#include "mesh_internal.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef struct builder {
    float *v;
    uint32_t *t;
    size_t nv, vcap, nt, tcap;
    int failed;
} builder;

static uint32_t vert(builder *b, double x, double y, double z)
{
    if (b->failed || hv_grow((void **)&b->v, &b->vcap, b->nv + 1, 3 * sizeof(float))) {
        b->failed = 1;
        return 0;
    }
    b->v[3 * b->nv] = (float)x;
    b->v[3 * b->nv + 1] = (float)y;
    b->v[3 * b->nv + 2] = (float)z;
    return (uint32_t)b->nv++;
}

static void tri(builder *b, uint32_t a, uint32_t c, uint32_t d)
{
    if (b->failed || hv_grow((void **)&b->t, &b->tcap, b->nt + 1, 3 * sizeof(uint32_t))) {
        b->failed = 1;
        return;
    }
    b->t[3 * b->nt] = a;
    b->t[3 * b->nt + 1] = c;
    b->t[3 * b->nt + 2] = d;
    ++b->nt;
}

static void quad(builder *b, uint32_t a, uint32_t c, uint32_t d, uint32_t e)
{
    tri(b, a, c, d);
    tri(b, a, d, e);
}

static double signed_volume(const builder *b)
{
    double vol = 0;
    for (size_t f = 0; f < b->nt; ++f) {
        const float *p = b->v + 3 * (size_t)b->t[3 * f], *q = b->v + 3 * (size_t)b->t[3 * f + 1],
                    *r = b->v + 3 * (size_t)b->t[3 * f + 2];
        vol += (double)p[0] * ((double)q[1] * r[2] - (double)q[2] * r[1]) -
               (double)p[1] * ((double)q[0] * r[2] - (double)q[2] * r[0]) +
               (double)p[2] * ((double)q[0] * r[1] - (double)q[1] * r[0]);
    }
    return vol / 6.0;
}

static hv_status finish(builder *b, hv_mesh **out)
{
    hv_status s = HV_OK;
    if (b->failed) s = HV_ERR_NOMEM;
    if (s == HV_OK && signed_volume(b) < 0)
        for (size_t f = 0; f < b->nt; ++f) {
            uint32_t x = b->t[3 * f + 1];
            b->t[3 * f + 1] = b->t[3 * f + 2];
            b->t[3 * f + 2] = x;
        }
    if (s == HV_OK) s = hv_mesh_create(b->v, b->nv, b->t, b->nt, out);
    free(b->v);
    free(b->t);
    return s;
}

/* Triangulate the strip between two closed rings listed counter-clockwise by angle around
 * (cx, cy); ring a is inside ring b. Facets are wound like quad(a_i, b_i, b_i+1, a_i+1). */
static void zipper(builder *b, const uint32_t *ra, const double *aa, size_t na, const uint32_t *rb,
                   const double *ab, size_t nb)
{
    size_t i = 0, j = 0;
    while (i < na || j < nb) {
        /* angles of the next points, unwrapped past 2*pi at the end of each ring */
        double ta = i < na ? (i + 1 < na ? aa[i + 1] : aa[0] + 2 * M_PI) : INFINITY;
        double tb = j < nb ? (j + 1 < nb ? ab[j + 1] : ab[0] + 2 * M_PI) : INFINITY;
        uint32_t a0 = ra[i % na], b0 = rb[j % nb];
        if (tb <= ta) {
            tri(b, a0, b0, rb[(j + 1) % nb]);
            ++j;
        } else {
            tri(b, a0, b0, ra[(i + 1) % na]);
            ++i;
        }
    }
}

hv_status hv_generate_sphere(const double c[3], double radius, int seg, int rings, hv_mesh **out)
{
    *out = NULL;
    if (!(radius > 0) || !isfinite(radius) || seg < 3 || rings < 2 || seg > 100000 ||
        rings > 100000)
        return hv_error_set(HV_ERR_INVALID,
                            "sphere: radius %g must be > 0, segments %d >= 3, rings %d >= 2",
                            radius, seg, rings);
    builder b = {0};
    uint32_t north = vert(&b, c[0], c[1], c[2] + radius);
    uint32_t first = (uint32_t)b.nv;
    for (int j = 1; j < rings; ++j) {
        double phi = M_PI * j / rings;
        for (int i = 0; i < seg; ++i) {
            double th = 2 * M_PI * i / seg;
            vert(&b, c[0] + radius * sin(phi) * cos(th), c[1] + radius * sin(phi) * sin(th),
                 c[2] + radius * cos(phi));
        }
    }
    uint32_t south = vert(&b, c[0], c[1], c[2] - radius);
    for (int i = 0; i < seg; ++i) {
        uint32_t i1 = (uint32_t)((i + 1) % seg);
        tri(&b, north, first + (uint32_t)i, first + i1);
        for (int j = 0; j + 2 < rings; ++j) {
            uint32_t r0 = first + (uint32_t)(j * seg), r1 = r0 + (uint32_t)seg;
            quad(&b, r0 + (uint32_t)i, r1 + (uint32_t)i, r1 + i1, r0 + i1);
        }
        uint32_t last = first + (uint32_t)((rings - 2) * seg);
        tri(&b, south, last + i1, last + (uint32_t)i);
    }
    return finish(&b, out);
}

hv_status hv_generate_box(const double lo[3], const double hi[3], hv_mesh **out)
{
    *out = NULL;
    for (int a = 0; a < 3; ++a)
        if (!(hi[a] > lo[a]) || !isfinite(lo[a]) || !isfinite(hi[a]))
            return hv_error_set(HV_ERR_INVALID, "box: hi must exceed lo on every axis");
    builder b = {0};
    for (int k = 0; k < 8; ++k)
        vert(&b, (k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]);
    static const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                         {3, 2, 6, 7}, {2, 0, 4, 6}, {1, 3, 7, 5}};
    for (int f = 0; f < 6; ++f) quad(&b, faces[f][0], faces[f][1], faces[f][2], faces[f][3]);
    return finish(&b, out);
}

hv_status hv_generate_box_with_hole(const double lo[3], const double hi[3], double hr, int seg,
                                    hv_mesh **out)
{
    *out = NULL;
    double ax = 0.5 * (hi[0] - lo[0]), ay = 0.5 * (hi[1] - lo[1]);
    double cx = 0.5 * (hi[0] + lo[0]), cy = 0.5 * (hi[1] + lo[1]);
    if (!(hi[2] > lo[2]) || !(ax > 0) || !(ay > 0) || !(hr > 0) || !(hr < HV_MIN(ax, ay)) ||
        seg < 8 || seg % 8 || seg > 100000)
        return hv_error_set(HV_ERR_INVALID,
                            "box with hole: need hi > lo, 0 < hole radius %g < %g, segments %d a "
                            "multiple of 8",
                            hr, HV_MIN(ax, ay), seg);
    size_t n = (size_t)seg, no = n + 4;
    uint32_t *ring = hv_malloc_array(2 * (n + no), sizeof *ring);
    double *ang = hv_malloc_array(n + no, sizeof *ang);
    double *ox = hv_malloc_array(no, sizeof *ox), *oy = hv_malloc_array(no, sizeof *oy);
    if (!ring || !ang || !ox || !oy) {
        free(ring);
        free(ang);
        free(ox);
        free(oy);
        return HV_ERR_NOMEM;
    }
    /* outer ring: radial projections of the hole directions plus the four corners, by angle */
    size_t k = 0;
    double corner[4] = {atan2(ay, ax), M_PI - atan2(ay, ax), M_PI + atan2(ay, ax),
                        2 * M_PI - atan2(ay, ax)};
    int ci = 0;
    for (size_t i = 0; i < n; ++i) {
        double th = 2 * M_PI * (double)i / (double)n;
        while (ci < 4 && corner[ci] < th - 1e-12) {
            ang[n + k] = corner[ci];
            ox[k] = cx + (ci == 0 || ci == 3 ? ax : -ax);
            oy[k] = cy + (ci < 2 ? ay : -ay);
            ++k;
            ++ci;
        }
        if (ci < 4 && fabs(corner[ci] - th) <= 1e-12) ++ci; /* the corner is this direction */
        double cs = cos(th), sn = sin(th);
        double t = HV_MIN(fabs(cs) > 1e-15 ? ax / fabs(cs) : INFINITY,
                          fabs(sn) > 1e-15 ? ay / fabs(sn) : INFINITY);
        ang[n + k] = th;
        ox[k] = HV_CLAMP(cx + t * cs, lo[0], hi[0]); /* exactly on the sides */
        oy[k] = HV_CLAMP(cy + t * sn, lo[1], hi[1]);
        ++k;
    }
    while (ci < 4) {
        ang[n + k] = corner[ci];
        ox[k] = cx + (ci == 0 || ci == 3 ? ax : -ax);
        oy[k] = cy + (ci < 2 ? ay : -ay);
        ++k;
        ++ci;
    }
    no = k;
    builder b = {0};
    for (int level = 0; level < 2; ++level) {
        double z = level ? hi[2] : lo[2];
        uint32_t *hin = ring + (size_t)level * (n + no), *hout = hin + n;
        for (size_t i = 0; i < n; ++i) {
            double th = 2 * M_PI * (double)i / (double)n;
            ang[i] = th;
            hin[i] = vert(&b, cx + hr * cos(th), cy + hr * sin(th), z);
        }
        for (size_t i = 0; i < no; ++i) hout[i] = vert(&b, ox[i], oy[i], z);
    }
    uint32_t *bin = ring, *bout = ring + n, *tin = ring + n + no, *tout = tin + n;
    /* top face (zipper winds like quad(in_i, out_i, ...): CCW seen from +z) */
    zipper(&b, tin, ang, n, tout, ang + n, no);
    /* bottom face: same zipper with the rings' roles mirrored by winding the other way */
    size_t t0 = b.nt;
    zipper(&b, bin, ang, n, bout, ang + n, no);
    for (size_t f = t0; f < b.nt; ++f) {
        uint32_t x = b.t[3 * f + 1];
        b.t[3 * f + 1] = b.t[3 * f + 2];
        b.t[3 * f + 2] = x;
    }
    for (size_t i = 0; i < no; ++i) { /* outer walls */
        size_t j = (i + 1) % no;
        quad(&b, bout[i], bout[j], tout[j], tout[i]);
    }
    for (size_t i = 0; i < n; ++i) { /* hole wall, facing the axis */
        size_t j = (i + 1) % n;
        quad(&b, bin[i], tin[i], tin[j], bin[j]);
    }
    free(ring);
    free(ang);
    free(ox);
    free(oy);
    return finish(&b, out);
}

/* A closed (wrapping in both directions) grid of nu x nv vertices from a parametrisation. */
typedef void (*surface_fn)(const void *ctx, int u, int v, double p[3]);

static hv_status closed_grid(int nu, int nv, surface_fn fn, const void *ctx, hv_mesh **out)
{
    builder b = {0};
    for (int u = 0; u < nu; ++u)
        for (int v = 0; v < nv; ++v) {
            double p[3];
            fn(ctx, u, v, p);
            vert(&b, p[0], p[1], p[2]);
        }
    for (int u = 0; u < nu; ++u)
        for (int v = 0; v < nv; ++v) {
            uint32_t a = (uint32_t)(u * nv + v), c = (uint32_t)(((u + 1) % nu) * nv + v),
                     d = (uint32_t)(((u + 1) % nu) * nv + (v + 1) % nv),
                     e = (uint32_t)(u * nv + (v + 1) % nv);
            quad(&b, a, c, d, e);
        }
    return finish(&b, out);
}

typedef struct torus_ctx {
    double c[3], R, r;
    int nu, nv;
} torus_ctx;

static void torus_fn(const void *vctx, int u, int v, double p[3])
{
    const torus_ctx *t = vctx;
    double a = 2 * M_PI * u / t->nu, b = 2 * M_PI * v / t->nv;
    p[0] = t->c[0] + (t->R + t->r * cos(b)) * cos(a);
    p[1] = t->c[1] + (t->R + t->r * cos(b)) * sin(a);
    p[2] = t->c[2] + t->r * sin(b);
}

hv_status hv_generate_torus(const double c[3], double R, double r, int nu, int nv, hv_mesh **out)
{
    *out = NULL;
    if (!(r > 0) || !(R > r) || nu < 3 || nv < 3 || nu > 100000 || nv > 100000)
        return hv_error_set(HV_ERR_INVALID, "torus: need 0 < r (%g) < R (%g), segments >= 3", r, R);
    torus_ctx t = {{c[0], c[1], c[2]}, R, r, nu, nv};
    return closed_grid(nu, nv, torus_fn, &t, out);
}

hv_status hv_generate_cylinder(const double base[3], int axis, double length, double radius,
                               int seg, hv_mesh **out)
{
    *out = NULL;
    if (axis < 0 || axis > 2 || !(length > 0) || !(radius > 0) || seg < 3 || seg > 1000000)
        return hv_error_set(HV_ERR_INVALID,
                            "cylinder: axis %d must be 0..2, length and radius > 0, segments >= 3",
                            axis);
    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    builder b = {0};
    uint32_t ring[2] = {0, 0}, cap[2];
    for (int end = 0; end < 2; ++end) {
        double p[3] = {base[0], base[1], base[2]};
        p[axis] += end * length;
        cap[end] = vert(&b, p[0], p[1], p[2]);
        ring[end] = (uint32_t)b.nv;
        for (int i = 0; i < seg; ++i) {
            double th = 2 * M_PI * i / seg, q[3] = {p[0], p[1], p[2]};
            q[a1] += radius * cos(th);
            q[a2] += radius * sin(th);
            vert(&b, q[0], q[1], q[2]);
        }
    }
    for (int i = 0; i < seg; ++i) {
        uint32_t i1 = (uint32_t)((i + 1) % seg), ii = (uint32_t)i;
        tri(&b, cap[0], ring[0] + i1, ring[0] + ii);
        tri(&b, cap[1], ring[1] + ii, ring[1] + i1);
        quad(&b, ring[0] + ii, ring[0] + i1, ring[1] + i1, ring[1] + ii);
    }
    return finish(&b, out);
}

/* ---- torus knot tube --------------------------------------------------------------------- */

typedef struct knot_ctx {
    int nu, nv;
    double tube;
    double *c, *n, *bn; /* centre, normal, binormal per u */
} knot_ctx;

static void knot_fn(const void *vctx, int u, int v, double p[3])
{
    const knot_ctx *k = vctx;
    double a = 2 * M_PI * v / k->nv;
    for (int i = 0; i < 3; ++i)
        p[i] = k->c[3 * u + i] + k->tube * (cos(a) * k->n[3 * u + i] + sin(a) * k->bn[3 * u + i]);
}

static void knot_point(int p, int q, double R, double r, double t, double out[3])
{
    double rr = R + r * cos(q * t);
    out[0] = rr * cos(p * t);
    out[1] = rr * sin(p * t);
    out[2] = r * sin(q * t);
}

static void normalize3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
        for (int i = 0; i < 3; ++i) v[i] /= l;
}

static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

hv_status hv_generate_torus_knot(int p, int q, double R, double r, double tube, int nu, int nv,
                                 hv_mesh **out)
{
    *out = NULL;
    if (p < 1 || q < 1 || !(R > r) || !(r > 0) || !(tube > 0) || nu < 8 || nv < 3 ||
        nu > 10000000 || nv > 100000)
        return hv_error_set(HV_ERR_INVALID,
                            "torus knot: need p, q >= 1, R > r > 0, tube > 0, segments >= 8, 3");
    knot_ctx k = {nu, nv, tube, hv_malloc_array((size_t)nu, 3 * sizeof(double)),
                  hv_malloc_array((size_t)nu, 3 * sizeof(double)),
                  hv_malloc_array((size_t)nu, 3 * sizeof(double))};
    double *tan = hv_malloc_array((size_t)nu, 3 * sizeof(double));
    if (!k.c || !k.n || !k.bn || !tan) {
        free(k.c);
        free(k.n);
        free(k.bn);
        free(tan);
        return HV_ERR_NOMEM;
    }
    for (int u = 0; u < nu; ++u) {
        double t = 2 * M_PI * u / nu, h = 1e-5, a[3], b[3];
        knot_point(p, q, R, r, t, k.c + 3 * u);
        knot_point(p, q, R, r, t + h, a);
        knot_point(p, q, R, r, t - h, b);
        for (int i = 0; i < 3; ++i) tan[3 * u + i] = a[i] - b[i];
        normalize3(tan + 3 * u);
    }
    /* rotation-minimising frame by projection transport, then the closing twist spread
     * evenly so the tube joins without a seam */
    double n0[3] = {0, 0, 1}, tmp[3];
    cross3(tan, n0, tmp);
    cross3(tmp, tan, n0);
    normalize3(n0);
    memcpy(k.n, n0, sizeof n0);
    for (int u = 1; u <= nu; ++u) {
        const double *tu = tan + 3 * (u % nu), *prev = k.n + 3 * (u - 1);
        double d = prev[0] * tu[0] + prev[1] * tu[1] + prev[2] * tu[2], nn[3];
        for (int i = 0; i < 3; ++i) nn[i] = prev[i] - d * tu[i];
        normalize3(nn);
        if (u < nu) memcpy(k.n + 3 * u, nn, sizeof nn);
        else memcpy(tmp, nn, sizeof nn); /* transported back to the start */
    }
    double bn0[3];
    cross3(tan, k.n, bn0);
    double twist = atan2(tmp[0] * bn0[0] + tmp[1] * bn0[1] + tmp[2] * bn0[2],
                         tmp[0] * k.n[0] + tmp[1] * k.n[1] + tmp[2] * k.n[2]);
    for (int u = 0; u < nu; ++u) {
        double *n = k.n + 3 * u, *bn = k.bn + 3 * u, b0[3];
        cross3(tan + 3 * u, n, b0);
        double a = -twist * u / nu, rot[3];
        for (int i = 0; i < 3; ++i) rot[i] = cos(a) * n[i] + sin(a) * b0[i];
        memcpy(n, rot, sizeof rot);
        cross3(tan + 3 * u, n, bn);
    }
    hv_status s = closed_grid(nu, nv, knot_fn, &k, out);
    free(k.c);
    free(k.n);
    free(k.bn);
    free(tan);
    return s;
}

/* ---- gear ------------------------------------------------------------------------------- */

/* Polar profile of a trapezoidal tooth: root for the first 30% of the pitch, a flank over 20%,
 * the tip over 30%, the other flank over 20%. */
static double gear_radius(double frac, double rr, double rt)
{
    if (frac < 0.30) return rr;
    if (frac < 0.50) return rr + (rt - rr) * (frac - 0.30) / 0.20;
    if (frac < 0.80) return rt;
    return rt - (rt - rr) * (frac - 0.80) / 0.20;
}

hv_status hv_generate_gear(int teeth, double rr, double rt, double bore, double height,
                           double twist, int spt, int layers, hv_mesh **out)
{
    *out = NULL;
    if (teeth < 3 || teeth > 10000 || !(rr > 0) || !(rt > rr) || bore < 0 || !(bore < rr) ||
        !(height > 0) || !isfinite(twist) || spt < 8 || spt > 10000 || layers < 1 ||
        layers > 100000)
        return hv_error_set(HV_ERR_INVALID,
                            "gear: need teeth >= 3, 0 <= bore (%g) < root (%g) < tip (%g), "
                            "height > 0, segments per tooth >= 8, layers >= 1",
                            bore, rr, rt);
    int n = teeth * spt;
    builder b = {0};
    /* per layer: outer ring of n, then bore ring of n (or one centre vertex) */
    int per = bore > 0 ? 2 * n : n + 1;
    for (int l = 0; l <= layers; ++l) {
        double z = height * l / layers, rot = twist * l / layers;
        for (int i = 0; i < n; ++i) {
            double frac = (double)(i % spt) / spt, th = 2 * M_PI * i / n + rot;
            double rad = gear_radius(frac, rr, rt);
            vert(&b, rad * cos(th), rad * sin(th), z);
        }
        if (bore > 0)
            for (int i = 0; i < n; ++i) {
                double th = 2 * M_PI * i / n + rot;
                vert(&b, bore * cos(th), bore * sin(th), z);
            }
        else
            vert(&b, 0, 0, z);
    }
    for (int l = 0; l < layers; ++l) {
        uint32_t o0 = (uint32_t)(l * per), o1 = (uint32_t)((l + 1) * per);
        for (int i = 0; i < n; ++i) {
            uint32_t i0 = (uint32_t)i, i1 = (uint32_t)((i + 1) % n);
            quad(&b, o0 + i0, o0 + i1, o1 + i1, o1 + i0); /* outer flank */
            if (bore > 0)
                quad(&b, o0 + (uint32_t)n + i0, o1 + (uint32_t)n + i0, o1 + (uint32_t)n + i1,
                     o0 + (uint32_t)n + i1);
        }
    }
    for (int end = 0; end < 2; ++end) {
        uint32_t o = (uint32_t)(end * layers * per);
        for (int i = 0; i < n; ++i) {
            uint32_t i0 = (uint32_t)i, i1 = (uint32_t)((i + 1) % n);
            if (bore > 0) {
                if (end) quad(&b, o + (uint32_t)n + i0, o + i0, o + i1, o + (uint32_t)n + i1);
                else quad(&b, o + (uint32_t)n + i0, o + (uint32_t)n + i1, o + i1, o + i0);
            } else {
                if (end) tri(&b, o + (uint32_t)n, o + i0, o + i1);
                else tri(&b, o + (uint32_t)n, o + i1, o + i0);
            }
        }
    }
    return finish(&b, out);
}
