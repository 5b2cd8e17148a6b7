/* tests/slicing/test_contours.c - the WDG slicer (Wu 2.4.1): graph weights, cross-section
 * areas against analytic values, degenerate planes, open and non-manifold meshes, nesting and
 * orientation, layer plans, determinism, and the SVG/CLI writers. */
#include <criterion/criterion.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/slice.h"
#include "support/support.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* ---- helpers ---------------------------------------------------------------------------- */

static hv_slicer *slicer_of(const hv_mesh *m)
{
    hv_slicer *s = NULL;
    hv_status st = hv_slicer_create(m, NULL, &s);
    cr_assert_eq(st, HV_OK, "%s", hv_last_error());
    return s;
}

static hv_slice *slice_at(const hv_slicer *s, double z, double gap)
{
    hv_slice_options o;
    hv_slice_options_init(&o);
    o.close_gap = gap;
    hv_slice *sl = NULL;
    hv_status st = hv_slicer_slice(s, z, &o, &sl);
    cr_assert_eq(st, HV_OK, "%s", hv_last_error());
    return sl;
}

static double shoelace(const double *xy, size_t n)
{
    double a = 0;
    for (size_t i = 0; i < n; ++i) {
        size_t j = (i + 1) % n;
        a += xy[2 * i] * xy[2 * j + 1] - xy[2 * j] * xy[2 * i + 1];
    }
    return 0.5 * a;
}

/* Consistency every slice must have: closed first, areas and orientations agree with the
 * points, stats add up. */
static void check_slice(const hv_slice *sl)
{
    const hv_slice_stats *st = hv_slice_get_stats(sl);
    size_t n = hv_slice_loop_count(sl);
    const hv_slice_loop *L = hv_slice_loops(sl);
    cr_assert_eq(n, st->loops + st->open);
    cr_assert_eq(st->loops, st->outers + st->holes);
    double total = 0;
    size_t pts = 0;
    for (size_t i = 0; i < n; ++i) {
        pts += L[i].count;
        if (i < st->loops) {
            cr_assert_eq(L[i].closed, 1);
            cr_assert_geq(L[i].count, 3);
            double a = shoelace(L[i].xy, L[i].count);
            cr_assert(fabs(a - L[i].area) <= 1e-9 * (1 + fabs(a)), "area %g vs %g", a, L[i].area);
            cr_assert_eq(L[i].orientation, a > 0 ? 1 : -1);
            if (L[i].parent >= 0) {
                cr_assert_lt((size_t)L[i].parent, st->loops);
                cr_assert_eq(L[L[i].parent].depth + 1, L[i].depth);
            } else {
                cr_assert_eq(L[i].depth, 0);
            }
            total += L[i].area;
        } else {
            cr_assert_eq(L[i].closed, 0);
            cr_assert_eq(L[i].orientation, 0);
            cr_assert_geq(L[i].count, 2);
        }
        for (size_t k = 1; k < L[i].count; ++k) /* no repeated consecutive points */
            cr_assert(L[i].xy[2 * k] != L[i].xy[2 * k - 2] || L[i].xy[2 * k + 1] != L[i].xy[2 * k - 1]);
    }
    cr_assert_eq(pts, st->points);
    cr_assert(fabs(total - st->area) <= 1e-9 * (1 + fabs(total)));
}

/* Brute force: facets with zmin < h <= zmax. */
static size_t crossing_brute(const hv_mesh *m, double h)
{
    const float *v = hv_mesh_vertices(m);
    const uint32_t *t = hv_mesh_facets(m);
    size_t n = 0;
    for (size_t f = 0; f < hv_mesh_facet_count(m); ++f) {
        double lo = INFINITY, hi = -INFINITY;
        for (int k = 0; k < 3; ++k) {
            double z = v[3 * (size_t)t[3 * f + k] + 2];
            lo = fmin(lo, z);
            hi = fmax(hi, z);
        }
        n += lo < h && h <= hi;
    }
    return n;
}

/* Mesh from the facets of a and b (b flipped if asked); vertices welded by position. */
static hv_mesh *merge(const hv_mesh *a, const hv_mesh *b, int flip_a)
{
    size_t na = hv_mesh_vertex_count(a), nb = b ? hv_mesh_vertex_count(b) : 0;
    size_t fa = hv_mesh_facet_count(a), fb = b ? hv_mesh_facet_count(b) : 0;
    float *xyz = malloc(3 * (na + nb) * sizeof *xyz);
    uint32_t *tri = malloc(3 * (fa + fb) * sizeof *tri);
    memcpy(xyz, hv_mesh_vertices(a), 3 * na * sizeof *xyz);
    if (b) memcpy(xyz + 3 * na, hv_mesh_vertices(b), 3 * nb * sizeof *xyz);
    const uint32_t *ta = hv_mesh_facets(a);
    for (size_t f = 0; f < fa; ++f) {
        tri[3 * f] = ta[3 * f];
        tri[3 * f + 1] = ta[3 * f + (flip_a ? 2 : 1)];
        tri[3 * f + 2] = ta[3 * f + (flip_a ? 1 : 2)];
    }
    if (b) {
        const uint32_t *tb = hv_mesh_facets(b);
        for (size_t i = 0; i < 3 * fb; ++i) tri[3 * fa + i] = tb[i] + (uint32_t)na;
    }
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_create(xyz, na + nb, tri, fa + fb, &m), HV_OK, "%s", hv_last_error());
    free(xyz);
    free(tri);
    return m;
}

static hv_mesh *gen_sphere(double r, int seg, int rings)
{
    double c[3] = {0, 0, 0};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_sphere(c, r, seg, rings, &m), HV_OK);
    return m;
}

static hv_mesh *gen_box(double x0, double y0, double z0, double x1, double y1, double z1)
{
    double lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    return t_box_mesh(lo, hi);
}

static hv_mesh *gen_holed_box(void)
{
    double lo[3] = {0, 0, 0}, hi[3] = {40, 30, 20};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_box_with_hole(lo, hi, 8, 64, &m), HV_OK);
    return m;
}

/* ---- the graph ---------------------------------------------------------------------------- */

Test(wdg, tetrahedron_arcs_carry_wu_weights)
{
    /* Wu's Fig. 10: a tetrahedron, every facet has three neighbours */
    const float xyz[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const uint32_t tri[] = {1, 2, 3, 0, 2, 1, 0, 3, 2, 0, 1, 3};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_create(xyz, 4, tri, 4, &m), HV_OK);
    hv_slicer *s = slicer_of(m);
    hv_slicer_info in;
    hv_slicer_get_info(s, &in);
    cr_assert_eq(in.arcs, 12);
    cr_assert_eq(in.open_edges, 0);
    const uint32_t *t = hv_mesh_facets(m);
    for (size_t f = 0; f < 4; ++f)
        for (int w = 1; w <= 3; ++w) {
            int32_t g;
            int wg;
            cr_assert_eq(hv_slicer_arc(s, f, w, &g, &wg), HV_OK);
            cr_assert(g >= 0 && g < 4 && (size_t)g != f);
            cr_assert(wg >= 1 && wg <= 3);
            /* weight = sum of the local subscripts: the edge opposite vertex 3 - w */
            uint32_t a = t[3 * f + (w == 3 ? 1 : 0)], b = t[3 * f + (w == 1 ? 1 : 2)];
            uint32_t c = t[3 * (size_t)g + (wg == 3 ? 1 : 0)], d = t[3 * (size_t)g + (wg == 1 ? 1 : 2)];
            cr_assert((a == c && b == d) || (a == d && b == c), "facet %zu weight %d", f, w);
            int32_t back;
            int wb;
            hv_slicer_arc(s, (size_t)g, wg, &back, &wb);
            cr_assert_eq(back, (int32_t)f);
            cr_assert_eq(wb, w);
        }
    int32_t g;
    cr_assert_eq(hv_slicer_arc(s, 4, 1, &g, NULL), HV_ERR_INVALID);
    cr_assert_eq(hv_slicer_arc(s, 0, 0, &g, NULL), HV_ERR_INVALID);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

Test(wdg, crossing_facets_match_brute_force)
{
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_load_stl(t_mesh_path("helical_gear.stl"), &m), HV_OK, "%s", hv_last_error());
    hv_slicer *s = slicer_of(m);
    hv_slicer_info in;
    hv_slicer_get_info(s, &in);
    const float *v = hv_mesh_vertices(m);
    for (int i = 0; i < 60; ++i) {
        /* planes at vertex heights and in between */
        double h = i % 2 ? v[3 * (size_t)(i * 97 % hv_mesh_vertex_count(m)) + 2]
                         : in.bbox_min[2] + (in.bbox_max[2] - in.bbox_min[2]) * (i + 0.37) / 60;
        hv_slice *sl = slice_at(s, h, 0);
        cr_assert_eq(hv_slice_get_stats(sl)->facets, crossing_brute(m, h), "h = %.9g", h);
        hv_slice_destroy(sl);
    }
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

/* ---- areas against analytic values --------------------------------------------------------- */

Test(areas, sphere_sections_between_inscribed_and_circumscribed)
{
    const double R = 10;
    hv_mesh *m = gen_sphere(R, 64, 32);
    hv_slicer *s = slicer_of(m);
    /* the polyhedron lies between the sphere and the ball of radius r_in (the nearest facet
     * plane), so pi (r_in^2 - z^2) <= area <= pi (R^2 - z^2) */
    const float *v = hv_mesh_vertices(m);
    const uint32_t *t = hv_mesh_facets(m);
    double rin = R;
    for (size_t f = 0; f < hv_mesh_facet_count(m); ++f) {
        const float *a = v + 3 * t[3 * f], *b = v + 3 * t[3 * f + 1], *c = v + 3 * t[3 * f + 2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len > 0) rin = fmin(rin, fabs(n[0] * a[0] + n[1] * a[1] + n[2] * a[2]) / len);
    }
    cr_assert(rin > 0.99 * R && rin < R);
    for (int i = 0; i < 41; ++i) {
        double z = -0.95 * R + 1.9 * R * i / 40 + 0.0123;
        hv_slice *sl = slice_at(s, z, 0);
        check_slice(sl);
        const hv_slice_stats *st = hv_slice_get_stats(sl);
        cr_assert_eq(st->loops, 1);
        cr_assert_eq(st->open, 0);
        cr_assert_eq(hv_slice_loops(sl)[0].orientation, 1);
        double hi = M_PI * (R * R - z * z), lo = M_PI * (rin * rin - z * z);
        cr_assert(st->area <= hi * (1 + 1e-6) && st->area >= lo * (1 - 1e-6),
                  "z %g: area %.6f not in [%.6f, %.6f]", z, st->area, lo, hi);
        hv_slice_destroy(sl);
    }
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

Test(areas, shaft_150x55_sections)
{
    /* Wu's shaft: cylinder along x, length 150, diameter 55, 128 segments */
    const double r = 27.5, len = 150;
    const int seg = 128;
    double base[3] = {0, 0, 0};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_cylinder(base, 0, len, r, seg, &m), HV_OK);
    hv_slicer *s = slicer_of(m);
    double rin = r * cos(M_PI / seg);
    for (int i = 0; i < 25; ++i) {
        double z = -0.9 * rin + 1.8 * rin * i / 24 + 0.0071;
        hv_slice *sl = slice_at(s, z, 0);
        check_slice(sl);
        const hv_slice_stats *st = hv_slice_get_stats(sl);
        cr_assert_eq(st->loops, 1);
        cr_assert_eq(st->holes, 0);
        double hi = len * 2 * sqrt(r * r - z * z), lo = len * 2 * sqrt(rin * rin - z * z);
        cr_assert(st->area <= hi * (1 + 1e-6) && st->area >= lo * (1 - 1e-6),
                  "z %g: area %.6f not in [%.6f, %.6f]", z, st->area, lo, hi);
        hv_slice_destroy(sl);
    }
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

Test(areas, holed_box_outer_minus_hole_and_nesting)
{
    hv_mesh *m = gen_holed_box();
    hv_slicer *s = slicer_of(m);
    double hole = 0.5 * 64 * 8.0 * 8.0 * sin(2 * M_PI / 64); /* the inscribed 64-gon */
    for (int i = 0; i < 7; ++i) {
        double z = 0.5 + 19.0 * i / 6;
        hv_slice *sl = slice_at(s, z, 0);
        check_slice(sl);
        const hv_slice_stats *st = hv_slice_get_stats(sl);
        cr_assert_eq(st->loops, 2);
        cr_assert_eq(st->outers, 1);
        cr_assert_eq(st->holes, 1);
        cr_assert_float_eq(st->area, 1200 - hole, 1e-4, "%.9f", st->area);
        const hv_slice_loop *L = hv_slice_loops(sl);
        int o = L[0].orientation > 0 ? 0 : 1, h = 1 - o;
        cr_assert_eq(L[o].orientation, 1);
        cr_assert_float_eq(L[o].area, 1200, 1e-4);
        cr_assert_eq(L[o].parent, -1);
        cr_assert_eq(L[h].orientation, -1);
        cr_assert(shoelace(L[h].xy, L[h].count) < 0); /* clockwise seen from +z */
        cr_assert_float_eq(L[h].area, -hole, 1e-4);
        cr_assert_eq(L[h].parent, o);
        cr_assert_eq(L[h].depth, 1);
        hv_slice_destroy(sl);
    }
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

Test(areas, island_in_a_hole_and_inside_out_mesh)
{
    hv_mesh *hb = gen_holed_box();
    hv_mesh *isl = gen_box(18, 13, 5, 22, 17, 15);
    hv_mesh *m = merge(hb, isl, 0);
    hv_slicer *s = slicer_of(m);
    hv_slice *sl = slice_at(s, 10, 0);
    check_slice(sl);
    const hv_slice_stats *st = hv_slice_get_stats(sl);
    cr_assert_eq(st->loops, 3);
    cr_assert_eq(st->outers, 2);
    cr_assert_eq(st->holes, 1);
    const hv_slice_loop *L = hv_slice_loops(sl);
    int found = 0;
    for (size_t i = 0; i < 3; ++i)
        if (L[i].depth == 2) {
            found = 1;
            cr_assert_float_eq(L[i].area, 16, 1e-6);
            cr_assert_eq(L[i].orientation, 1);
            cr_assert_eq(L[L[i].parent].depth, 1);
            cr_assert_eq(L[L[i].parent].orientation, -1);
        }
    cr_assert(found);
    hv_slice_destroy(sl);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);

    /* all facets flipped (an inside-out mesh): still outer CCW, hole CW */
    m = merge(hb, NULL, 1);
    s = slicer_of(m);
    sl = slice_at(s, 7.3, 0);
    check_slice(sl);
    cr_assert_eq(hv_slice_get_stats(sl)->outers, 1);
    cr_assert_eq(hv_slice_get_stats(sl)->holes, 1);
    cr_assert_float_eq(hv_slice_get_stats(sl)->area, 1200 - 0.5 * 64 * 64 * sin(2 * M_PI / 64), 1e-4);
    hv_slice_destroy(sl);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
    hv_mesh_destroy(isl);
    hv_mesh_destroy(hb);
}

/* Slice the union of two boxes at z = 1 (a flipped if asked) and check the loop count by kind
 * and the total area; the two loops are nested when `nested`. */
static void two_bodies(const hv_mesh *a, const hv_mesh *b, int flip_a, size_t outers, size_t holes,
                       double area, int nested)
{
    hv_mesh *m = merge(a, b, flip_a);
    hv_slicer *s = slicer_of(m);
    hv_slice *sl = slice_at(s, 1, 0);
    check_slice(sl);
    const hv_slice_stats *st = hv_slice_get_stats(sl);
    cr_assert_eq(st->outers, outers, "outers %zu, want %zu", st->outers, outers);
    cr_assert_eq(st->holes, holes, "holes %zu, want %zu", st->holes, holes);
    cr_assert_float_eq(st->area, area, 1e-9, "area %g, want %g", st->area, area);
    const hv_slice_loop *L = hv_slice_loops(sl);
    if (nested) cr_assert_eq(L[0].depth + L[1].depth, 1, "one loop inside the other");
    hv_slice_destroy(sl);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

Test(areas, facet_winding_decides_body_or_cavity)
{
    hv_mesh *big = gen_box(0, 0, 0, 10, 10, 2), *small = gen_box(3, 3, 0, 7, 7, 2);
    hv_mesh *side = gen_box(5, 2, 0, 12, 8, 2);
    /* a second body inside the first, facing outwards too: both are outers (nonzero = union) */
    two_bodies(small, big, 0, 2, 0, 100 + 16, 1);
    /* the same inner box facing inwards is a cavity: a hole */
    two_bodies(small, big, 1, 1, 1, 100 - 16, 1);
    /* overlapping bodies: two outers, the area counts the overlap once per body */
    two_bodies(side, big, 0, 2, 0, 100 + 42, 0);
    hv_mesh_destroy(big);
    hv_mesh_destroy(small);
    hv_mesh_destroy(side);
}

Test(areas, a_few_flipped_facets_do_not_turn_a_loop)
{
    /* flip every 7th facet of the holed box, the start facet of some loops among them */
    hv_mesh *hb = gen_holed_box();
    size_t nv = hv_mesh_vertex_count(hb), nf = hv_mesh_facet_count(hb);
    uint32_t *tri = malloc(3 * nf * sizeof *tri);
    memcpy(tri, hv_mesh_facets(hb), 3 * nf * sizeof *tri);
    for (size_t f = 0; f < nf; f += 7) {
        uint32_t t = tri[3 * f + 1];
        tri[3 * f + 1] = tri[3 * f + 2];
        tri[3 * f + 2] = t;
    }
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_create(hv_mesh_vertices(hb), nv, tri, nf, &m), HV_OK);
    free(tri);
    hv_slicer *s = slicer_of(m);
    double hole = 0.5 * 64 * 8.0 * 8.0 * sin(2 * M_PI / 64);
    for (int i = 0; i < 9; ++i) {
        hv_slice *sl = slice_at(s, 0.5 + 19.0 * i / 8, 0);
        check_slice(sl);
        const hv_slice_stats *st = hv_slice_get_stats(sl);
        if (st->open == 0) {
            cr_assert_eq(st->outers, 1, "z %g", 0.5 + 19.0 * i / 8);
            cr_assert_eq(st->holes, 1);
            cr_assert_float_eq(st->area, 1200 - hole, 1e-4);
        }
        hv_slice_destroy(sl);
    }
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
    hv_mesh_destroy(hb);
}

/* ---- closed meshes, degenerate planes ------------------------------------------------------ */

Test(closed, shared_meshes_have_no_open_loops_and_areas_integrate_to_volume, .timeout = 60)
{
    char dirpath[1024];
    snprintf(dirpath, sizeof dirpath, "%s/meshes", t_shared());
    DIR *d = opendir(dirpath);
    cr_assert(d, "cannot open %s", dirpath);
    struct dirent *e;
    int meshes = 0;
    while ((e = readdir(d))) {
        size_t n = strlen(e->d_name);
        if (n < 4 || strcmp(e->d_name + n - 4, ".stl") != 0) continue;
        hv_mesh *m = NULL;
        cr_assert_eq(hv_mesh_load_stl(t_mesh_path(e->d_name), &m), HV_OK, "%s", hv_last_error());
        const hv_mesh_report *r = hv_mesh_get_report(m);
        if (r->open_edges || r->nonmanifold_edges) {
            hv_mesh_destroy(m);
            continue;
        }
        ++meshes;
        hv_slicer *s = slicer_of(m);
        /* midpoint rule: sum of areas times layer height approximates the volume */
        hv_layer_plan *plan = NULL;
        double zr = r->bbox_max[2] - r->bbox_min[2];
        cr_assert_eq(hv_slicer_plan_uniform(s, 0, zr / 400, &plan), HV_OK);
        double vol = 0;
        for (size_t i = 0; i < hv_layer_plan_count(plan); ++i) {
            const hv_layer *L = &hv_layer_plan_layers(plan)[i];
            hv_slice *sl = slice_at(s, L->z, 0);
            check_slice(sl);
            cr_assert_eq(hv_slice_get_stats(sl)->open, 0, "%s z %g", e->d_name, L->z);
            vol += hv_slice_get_stats(sl)->area * (L->top - L->bottom);
            hv_slice_destroy(sl);
        }
        cr_assert(fabs(vol - r->volume) <= 0.01 * fabs(r->volume), "%s: %g vs %g", e->d_name,
                  vol, r->volume);
        /* planes exactly through vertices */
        const float *v = hv_mesh_vertices(m);
        for (size_t i = 0; i < 50; ++i) {
            double h = v[3 * ((i * 7919) % hv_mesh_vertex_count(m)) + 2];
            hv_slice *sl = slice_at(s, h, 0);
            check_slice(sl);
            cr_assert_eq(hv_slice_get_stats(sl)->open, 0, "%s at vertex z %.9g", e->d_name, h);
            hv_slice_destroy(sl);
        }
        hv_layer_plan_destroy(plan);
        hv_slicer_destroy(s);
        hv_mesh_destroy(m);
    }
    closedir(d);
    cr_assert_geq(meshes, 3);
}

static int cmp_angle(const void *a, const void *b)
{
    const double *p = a, *q = b;
    double u = atan2(p[1], p[0]), w = atan2(q[1], q[0]);
    return u < w ? -1 : u > w;
}

Test(degenerate, plane_through_a_ring_of_vertices)
{
    const int seg = 48;
    hv_mesh *m = gen_sphere(10, seg, 24);
    hv_slicer *s = slicer_of(m);
    const float *v = hv_mesh_vertices(m);
    /* a ring of vertices: the vertices with the z of a chosen one */
    double h = 0;
    for (size_t i = 0; i < hv_mesh_vertex_count(m); ++i)
        if (v[3 * i + 2] > 3 && v[3 * i + 2] < 6) {
            h = v[3 * i + 2];
            break;
        }
    double *ring = malloc(2 * hv_mesh_vertex_count(m) * sizeof *ring);
    size_t k = 0;
    for (size_t i = 0; i < hv_mesh_vertex_count(m); ++i)
        if (v[3 * i + 2] == (float)h) {
            ring[2 * k] = v[3 * i];
            ring[2 * k + 1] = v[3 * i + 1];
            ++k;
        }
    cr_assert_eq(k, (size_t)seg);
    qsort(ring, k, 2 * sizeof *ring, cmp_angle);
    double expect = shoelace(ring, k);
    hv_slice *sl = slice_at(s, h, 0);
    check_slice(sl);
    const hv_slice_stats *st = hv_slice_get_stats(sl);
    cr_assert_eq(st->loops, 1);
    cr_assert_eq(st->open, 0);
    /* the vertex on the plane counts as above: the section just below the ring, i.e. the
     * ring polygon itself, each vertex once */
    cr_assert_eq(hv_slice_loops(sl)[0].count, (size_t)seg);
    cr_assert_float_eq(st->area, expect, 1e-9 * expect);
    hv_slice_destroy(sl);
    /* the poles: a plane through the top apex gives the section just below it (a point,
     * dropped); through the bottom apex nothing */
    sl = slice_at(s, 10, 0);
    cr_assert_eq(hv_slice_get_stats(sl)->loops, 0);
    cr_assert_eq(hv_slice_get_stats(sl)->open, 0);
    hv_slice_destroy(sl);
    sl = slice_at(s, -10, 0);
    cr_assert_eq(hv_slice_get_stats(sl)->facets, 0);
    hv_slice_destroy(sl);
    free(ring);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

Test(degenerate, plane_on_flat_faces)
{
    hv_mesh *m = gen_box(0, 0, 0, 20, 20, 20);
    hv_slicer *s = slicer_of(m);
    hv_slice *sl = slice_at(s, 20, 0); /* the top face: the outline just below it */
    check_slice(sl);
    cr_assert_eq(hv_slice_get_stats(sl)->loops, 1);
    cr_assert_eq(hv_slice_loops(sl)[0].count, 4);
    cr_assert_float_eq(hv_slice_get_stats(sl)->area, 400, 1e-9);
    hv_slice_destroy(sl);
    sl = slice_at(s, 0, 0); /* the bottom face: nothing below it */
    cr_assert_eq(hv_slice_get_stats(sl)->loops, 0);
    cr_assert_eq(hv_slice_get_stats(sl)->facets, 0);
    hv_slice_destroy(sl);
    sl = slice_at(s, 25, 0);
    cr_assert_eq(hv_slice_loop_count(sl), 0);
    hv_slice_destroy(sl);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);

    m = gen_holed_box();
    s = slicer_of(m);
    sl = slice_at(s, 20, 0);
    check_slice(sl);
    cr_assert_eq(hv_slice_get_stats(sl)->outers, 1);
    cr_assert_eq(hv_slice_get_stats(sl)->holes, 1);
    cr_assert_float_eq(hv_slice_get_stats(sl)->area, 1200 - 0.5 * 64 * 64 * sin(2 * M_PI / 64), 1e-4);
    hv_slice_destroy(sl);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

Test(degenerate, nonmanifold_edge_between_two_cubes)
{
    hv_mesh *a = gen_box(0, 0, 0, 1, 1, 1), *b = gen_box(1, 1, 0, 2, 2, 1);
    hv_mesh *m = merge(a, b, 0);
    cr_assert_eq(hv_mesh_get_report(m)->nonmanifold_edges, 1);
    hv_slicer *s = slicer_of(m);
    hv_slicer_info in;
    hv_slicer_get_info(s, &in);
    cr_assert_gt(in.nonmanifold_arcs, 0);
    for (int i = 0; i < 3; ++i) {
        hv_slice *sl = slice_at(s, i == 0 ? 0.5 : i == 1 ? 1 : 0.25, 0);
        check_slice(sl);
        const hv_slice_stats *st = hv_slice_get_stats(sl);
        cr_assert_eq(st->loops, 2);
        cr_assert_eq(st->open, 0);
        cr_assert_eq(st->outers, 2);
        cr_assert_float_eq(st->area, 2, 1e-9);
        hv_slice_destroy(sl);
    }
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
    hv_mesh_destroy(a);
    hv_mesh_destroy(b);
}

/* ---- open meshes --------------------------------------------------------------------------- */

static hv_mesh *sphere_with_hole(void)
{
    hv_mesh *sp = gen_sphere(10, 64, 32);
    const float *v = hv_mesh_vertices(sp);
    const uint32_t *t = hv_mesh_facets(sp);
    size_t nf = hv_mesh_facet_count(sp), k = 0;
    uint32_t *tri = malloc(3 * nf * sizeof *tri);
    for (size_t f = 0; f < nf; ++f) {
        double c[3] = {0, 0, 0};
        for (int j = 0; j < 3; ++j)
            for (int a = 0; a < 3; ++a) c[a] += v[3 * t[3 * f + j] + a] / 3.0;
        double dx = c[0] - 10, d = sqrt(dx * dx + c[1] * c[1] + c[2] * c[2]);
        if (d < 1.5) continue; /* a hole around (10, 0, 0) */
        memcpy(tri + 3 * k++, t + 3 * f, 3 * sizeof *tri);
    }
    cr_assert_lt(k, nf);
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_create(v, hv_mesh_vertex_count(sp), tri, k, &m), HV_OK);
    free(tri);
    hv_mesh_destroy(sp);
    cr_assert_gt(hv_mesh_get_report(m)->open_edges, 0);
    return m;
}

Test(open, mesh_with_a_hole_reports_open_polylines, .timeout = 20)
{
    hv_mesh *m = sphere_with_hole();
    hv_slicer *s = slicer_of(m);
    hv_slicer_info in;
    hv_slicer_get_info(s, &in);
    cr_assert_gt(in.open_edges, 0);
    /* through the hole, no gap closing: one open polyline, no loop */
    hv_slice *sl = slice_at(s, 0.1, 0);
    check_slice(sl);
    const hv_slice_stats *st = hv_slice_get_stats(sl);
    cr_assert_eq(st->open, 1);
    cr_assert_eq(st->loops, 0);
    cr_assert_eq(st->area, 0);
    const hv_slice_loop *L = hv_slice_loops(sl);
    double gx = L[0].xy[0] - L[0].xy[2 * L[0].count - 2], gy = L[0].xy[1] - L[0].xy[2 * L[0].count - 1];
    double gap = sqrt(gx * gx + gy * gy);
    cr_assert(gap > 1 && gap < 4, "gap %g", gap);
    hv_slice_destroy(sl);
    /* a gap rule wider than the hole closes it into one loop */
    sl = slice_at(s, 0.1, 5);
    check_slice(sl);
    st = hv_slice_get_stats(sl);
    cr_assert_eq(st->open, 0);
    cr_assert_eq(st->loops, 1);
    cr_assert_eq(st->gaps_closed, 1);
    cr_assert_eq(hv_slice_loops(sl)[0].gaps, 1);
    cr_assert(st->area > 0.97 * M_PI * 100 && st->area < M_PI * 100);
    hv_slice_destroy(sl);
    /* away from the hole the sections are closed */
    sl = slice_at(s, 5, 0);
    check_slice(sl);
    cr_assert_eq(hv_slice_get_stats(sl)->open, 0);
    cr_assert_eq(hv_slice_get_stats(sl)->loops, 1);
    hv_slice_destroy(sl);
    /* every layer of a plan, no hang */
    hv_layer_plan *plan = NULL;
    cr_assert_eq(hv_slicer_plan_uniform(s, 0, 0.1, &plan), HV_OK);
    for (size_t i = 0; i < hv_layer_plan_count(plan); ++i) {
        sl = slice_at(s, hv_layer_plan_layers(plan)[i].z, 0);
        check_slice(sl);
        hv_slice_destroy(sl);
    }
    hv_layer_plan_destroy(plan);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

Test(open, unwelded_soup_is_rejoined_by_the_gap_rule, .timeout = 20)
{
    /* every facet gets its own vertices, nudged by up to ~1e-4 mm: no edge is shared, every
     * crossing facet is an open chain of its own; the gap rule joins them back */
    const double R = 10;
    hv_mesh *sp = gen_sphere(R, 96, 48);
    const float *v = hv_mesh_vertices(sp);
    const uint32_t *t = hv_mesh_facets(sp);
    size_t nf = hv_mesh_facet_count(sp);
    float *xyz = malloc(9 * nf * sizeof *xyz);
    uint32_t *tri = malloc(3 * nf * sizeof *tri);
    for (size_t f = 0; f < nf; ++f)
        for (int j = 0; j < 3; ++j) {
            for (int a = 0; a < 3; ++a)
                xyz[9 * f + 3 * (size_t)j + (size_t)a] =
                    v[3 * t[3 * f + (size_t)j] + (size_t)a] +
                    (float)(1e-4 * fmod(0.6180339887 * (double)(3 * f + (size_t)a), 1.0));
            tri[3 * f + (size_t)j] = (uint32_t)(3 * f + (size_t)j);
        }
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_create(xyz, 3 * nf, tri, nf, &m), HV_OK);
    cr_assert_eq(hv_mesh_get_report(m)->open_edges, 3 * nf);
    hv_slicer *s = slicer_of(m);
    for (int i = 0; i < 9; ++i) {
        double z = -8 + 2 * i + 0.013;
        hv_slice *sl = slice_at(s, z, HV_SLICE_DEFAULT_CLOSE_GAP);
        check_slice(sl);
        const hv_slice_stats *st = hv_slice_get_stats(sl);
        cr_assert_eq(st->open, 0, "z %g", z);
        cr_assert_eq(st->loops, 1);
        cr_assert_gt(st->gaps_closed, 96);
        double a = M_PI * (R * R - z * z);
        cr_assert(fabs(st->area - a) < 0.01 * a, "z %g: %g vs %g", z, st->area, a);
        hv_slice_destroy(sl);
        sl = slice_at(s, z, 0); /* without the gap rule: one open polyline per facet */
        cr_assert_eq(hv_slice_get_stats(sl)->loops, 0);
        cr_assert_eq(hv_slice_get_stats(sl)->open, hv_slice_get_stats(sl)->facets);
        hv_slice_destroy(sl);
    }
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
    hv_mesh_destroy(sp);
    free(xyz);
    free(tri);
}

Test(open, single_facet_and_open_square)
{
    const float xyz[] = {0, 0, 0, 1, 0, 0, 0, 0, 1};
    const uint32_t tri[] = {0, 1, 2};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_create(xyz, 3, tri, 1, &m), HV_OK);
    hv_slicer *s = slicer_of(m);
    hv_slice *sl = slice_at(s, 0.5, 0);
    check_slice(sl);
    cr_assert_eq(hv_slice_get_stats(sl)->open, 1);
    cr_assert_eq(hv_slice_loops(sl)[0].count, 2);
    hv_slice_destroy(sl);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

/* ---- plans ----------------------------------------------------------------------------------- */

Test(plan, uniform_layers_and_first_layer)
{
    hv_mesh *m = gen_box(0, 0, 0, 20, 20, 10);
    hv_slicer *s = slicer_of(m);
    hv_layer_plan *p = NULL;
    cr_assert_eq(hv_slicer_plan_uniform(s, 0.3, 0.5, &p), HV_OK);
    /* first [0, 0.3], then [0.3 + 0.5 (i-1), 0.3 + 0.5 i] while the mid-height is below 10 */
    size_t n = hv_layer_plan_count(p);
    const hv_layer *L = hv_layer_plan_layers(p);
    cr_assert_eq(n, 20); /* last: [9.3, 9.8]; [9.8, 10.3] has its mid-height 10.05 above 10 */
    cr_assert_float_eq(L[0].bottom, 0, 1e-12);
    cr_assert_float_eq(L[0].top, 0.3, 1e-12);
    cr_assert_float_eq(L[0].z, 0.15, 1e-12);
    for (size_t i = 1; i < n; ++i) {
        cr_assert_float_eq(L[i].bottom, L[i - 1].top, 1e-12);
        cr_assert_float_eq(L[i].top - L[i].bottom, 0.5, 1e-12);
        cr_assert_float_eq(L[i].z, 0.5 * (L[i].bottom + L[i].top), 1e-12);
    }
    cr_assert_float_eq(L[n - 1].top, 9.8, 1e-12);
    hv_layer_plan_destroy(p);
    cr_assert_eq(hv_slicer_plan_uniform(s, 0, 0, &p), HV_ERR_INVALID);
    cr_assert_eq(hv_slicer_plan_uniform(s, 0, -1, &p), HV_ERR_INVALID);
    cr_assert_eq(hv_slicer_plan_uniform(s, 0, NAN, &p), HV_ERR_INVALID);
    cr_assert_eq(hv_slicer_plan_uniform(s, 0, 1e-9, &p), HV_ERR_LIMIT);
    cr_assert(strstr(hv_last_error(), "layers"));
    cr_assert_null(p);
    /* explicit plans are validated */
    hv_layer ok[2] = {{0, 1, 0.5}, {1, 2, 1.5}}, bad[2] = {{0, 1, 0.5}, {1, 2, 0.5}};
    cr_assert_eq(hv_layer_plan_create(ok, 2, &p), HV_OK);
    cr_assert_eq(hv_layer_plan_count(p), 2);
    hv_layer_plan_destroy(p);
    cr_assert_eq(hv_layer_plan_create(bad, 2, &p), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "layer 1"));
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

Test(plan, adaptive_is_thin_where_flat_and_thick_where_steep)
{
    hv_mesh *m = gen_sphere(10, 64, 32);
    hv_slicer *s = slicer_of(m);
    hv_layer_plan *p = NULL;
    const double hmin = 0.05, hmax = 0.5;
    cr_assert_eq(hv_slicer_plan_adaptive(s, 0, hmin, hmax, 0, &p), HV_OK);
    size_t n = hv_layer_plan_count(p);
    const hv_layer *L = hv_layer_plan_layers(p);
    cr_assert_gt(n, 20);
    double near_pole = 0, near_equator = 0;
    for (size_t i = 0; i < n; ++i) {
        double t = L[i].top - L[i].bottom;
        cr_assert(t >= hmin * (1 - 1e-12) && t <= hmax * (1 + 1e-12));
        if (i) cr_assert_float_eq(L[i].bottom, L[i - 1].top, 1e-12);
        if (fabs(L[i].z) < 1) near_equator = fmax(near_equator, t);
        if (L[i].z < -9.5) near_pole = fmax(near_pole, t);
    }
    cr_assert_float_eq(near_equator, hmax, 1e-9);
    cr_assert_lt(near_pole, 0.2);
    cr_assert_float_eq(L[0].bottom, -10, 1e-6);
    /* uniform slicing at hmin would need far more layers */
    cr_assert_lt(n, (size_t)(0.75 * 20 / hmin), "%zu layers", n);
    hv_layer_plan_destroy(p);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);

    /* a box: vertical walls take max; the flat top ends a layer exactly at its height */
    m = gen_box(0, 0, 0, 10, 10, 10);
    s = slicer_of(m);
    cr_assert_eq(hv_slicer_plan_adaptive(s, 0.2, 0.1, 0.7, 0, &p), HV_OK);
    n = hv_layer_plan_count(p);
    L = hv_layer_plan_layers(p);
    cr_assert_float_eq(L[0].top, 0.2, 1e-12);
    cr_assert_float_eq(L[1].top - L[1].bottom, 0.7, 1e-12);
    cr_assert_float_eq(L[n - 1].top, 10, 1e-9);
    hv_layer_plan_destroy(p);
    cr_assert_eq(hv_slicer_plan_adaptive(s, 0, 0.5, 0.1, 0, &p), HV_ERR_INVALID);
    cr_assert_eq(hv_slicer_plan_adaptive(s, 0, 0, 0.1, 0, &p), HV_ERR_INVALID);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

/* ---- batch: determinism, order, cancel ------------------------------------------------------- */

typedef struct collect {
    size_t n;
    hv_slice **kept;
    int cancel_at;
    size_t calls;
} collect;

static hv_status keep_sink(void *user, size_t index, const hv_layer *layer, hv_slice **slice)
{
    (void)layer;
    collect *c = user;
    cr_assert_eq(index, c->n);
    c->kept[c->n++] = *slice;
    *slice = NULL; /* take ownership */
    return HV_OK;
}

static int cancel_fn(void *user, const char *stage, double f)
{
    (void)stage;
    collect *c = user;
    ++c->calls;
    return c->cancel_at >= 0 && f > 0 && (int)c->calls > c->cancel_at;
}

static void same_slices(const hv_slice *a, const hv_slice *b)
{
    cr_assert_eq(hv_slice_loop_count(a), hv_slice_loop_count(b));
    for (size_t i = 0; i < hv_slice_loop_count(a); ++i) {
        const hv_slice_loop *x = &hv_slice_loops(a)[i], *y = &hv_slice_loops(b)[i];
        cr_assert_eq(x->count, y->count);
        cr_assert_eq(x->parent, y->parent);
        cr_assert_eq(x->area, y->area);
        cr_assert_eq(memcmp(x->xy, y->xy, 2 * x->count * sizeof *x->xy), 0);
    }
}

Test(batch, deterministic_across_threads_and_equal_to_single_slices, .timeout = 60)
{
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_torus_knot(2, 3, 30, 12, 5, 400, 32, &m), HV_OK);
    hv_slicer *s = slicer_of(m);
    hv_layer_plan *p = NULL;
    cr_assert_eq(hv_slicer_plan_uniform(s, 0.2, 0.3, &p), HV_OK);
    size_t n = hv_layer_plan_count(p);
    collect a = {0, calloc(n, sizeof(hv_slice *)), -1, 0}, b = {0, calloc(n, sizeof(hv_slice *)), -1, 0};
    hv_set_threads(1);
    cr_assert_eq(hv_slicer_slice_plan(s, p, NULL, keep_sink, &a, NULL), HV_OK);
    hv_set_threads(3);
    cr_assert_eq(hv_slicer_slice_plan(s, p, NULL, keep_sink, &b, NULL), HV_OK);
    hv_set_threads(0);
    cr_assert_eq(a.n, n);
    cr_assert_eq(b.n, n);
    size_t loops = 0;
    for (size_t i = 0; i < n; ++i) {
        same_slices(a.kept[i], b.kept[i]);
        hv_slice *one = slice_at(s, hv_layer_plan_layers(p)[i].z, HV_SLICE_DEFAULT_CLOSE_GAP);
        same_slices(a.kept[i], one);
        check_slice(one);
        cr_assert_eq(hv_slice_get_stats(one)->open, 0);
        loops += hv_slice_get_stats(one)->loops;
        hv_slice_destroy(one);
        hv_slice_destroy(a.kept[i]);
        hv_slice_destroy(b.kept[i]);
    }
    cr_assert_gt(loops, n);
    free(a.kept);
    free(b.kept);
    /* cancel */
    collect c = {0, calloc(n, sizeof(hv_slice *)), 2, 0};
    hv_progress prog = {cancel_fn, &c};
    cr_assert_eq(hv_slicer_slice_plan(s, p, NULL, keep_sink, &c, &prog), HV_ERR_CANCELLED);
    cr_assert_lt(c.n, n);
    for (size_t i = 0; i < c.n; ++i) hv_slice_destroy(c.kept[i]);
    free(c.kept);
    hv_layer_plan_destroy(p);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

Test(batch, bad_arguments)
{
    hv_mesh *m = gen_box(0, 0, 0, 1, 1, 1);
    hv_slicer *s = slicer_of(m);
    hv_slice *sl = NULL;
    hv_slice_options o = {-1};
    cr_assert_eq(hv_slicer_slice(s, NAN, NULL, &sl), HV_ERR_INVALID);
    cr_assert_eq(hv_slicer_slice(s, 0.5, &o, &sl), HV_ERR_INVALID);
    cr_assert_null(sl);
    hv_slicer *none = (hv_slicer *)1;
    cr_assert_eq(hv_slicer_create(NULL, NULL, &none), HV_ERR_INVALID);
    cr_assert_null(none);
    hv_slicer_destroy(s);
    hv_slice_destroy(NULL);
    hv_slicer_destroy(NULL);
    hv_layer_plan_destroy(NULL);
    hv_contour_writer_abort(NULL);
    cr_assert_eq(hv_contour_writer_close(NULL), HV_OK);
    hv_mesh_destroy(m);
}

/* ---- files ----------------------------------------------------------------------------------- */

typedef struct write_ctx {
    hv_contour_writer *w;
} write_ctx;

static hv_status write_sink(void *user, size_t index, const hv_layer *layer, hv_slice **slice)
{
    (void)index;
    return hv_contour_writer_add(((write_ctx *)user)->w, layer, *slice);
}

static size_t write_file(const char *path, hv_contour_format fmt, const hv_mesh *m, double lh)
{
    hv_slicer *s = slicer_of(m);
    hv_layer_plan *p = NULL;
    cr_assert_eq(hv_slicer_plan_uniform(s, 0, lh, &p), HV_OK);
    hv_slicer_info in;
    hv_slicer_get_info(s, &in);
    write_ctx c = {NULL};
    cr_assert_eq(hv_contour_writer_open(path, fmt, hv_layer_plan_count(p), in.bbox_min,
                                        in.bbox_max, "a&b<c>.stl", &c.w),
                 HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_slicer_slice_plan(s, p, NULL, write_sink, &c, NULL), HV_OK);
    cr_assert_eq(hv_contour_writer_close(c.w), HV_OK, "%s", hv_last_error());
    size_t n = hv_layer_plan_count(p);
    hv_layer_plan_destroy(p);
    hv_slicer_destroy(s);
    return n;
}


Test(files, svg_parses_as_xml)
{
    hv_mesh *m = gen_holed_box();
    const char *path = t_tmpfile("box.svg");
    size_t n = write_file(path, HV_CONTOUR_SVG, m, 2.5);
    char cmd[1200];
    snprintf(cmd, sizeof cmd,
             "/usr/bin/python3 -c \"import xml.etree.ElementTree as E,sys; r=E.parse(sys.argv[1]).getroot(); "
             "g=[e for e in r.iter('{http://www.w3.org/2000/svg}g') if e.get('class')=='layer']; "
             "print(len(g), g[0].get('data-z'), len(g[0].findall('{http://www.w3.org/2000/svg}path')))\" '%s'",
             path);
    char *out = NULL;
    cr_assert_eq(t_run(cmd, &out), 0);
    char expect[64];
    snprintf(expect, sizeof expect, "%zu 1.25 1\n", n);
    cr_assert_str_eq(out, expect);
    free(out);
    hv_mesh_destroy(m);
}

Test(files, cli_ascii_follows_the_format)
{
    hv_mesh *m = gen_holed_box();
    const char *path = t_tmpfile("box.cli");
    size_t n = write_file(path, HV_CONTOUR_CLI_ASCII, m, 2.5);
    size_t len;
    char *text = t_slurp(path, &len);
    cr_assert(strncmp(text, "$$HEADERSTART\n$$ASCII\n$$UNITS/00000001.000000\n$$VERSION/200\n", 60) == 0);
    char *save = NULL;
    size_t layers_declared = 0, layer_lines = 0, polylines = 0;
    int in_geom = 0, header_end = 0, geom_end = 0;
    double last_z = -INFINITY;
    for (char *line = strtok_r(text, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        if (strncmp(line, "$$LAYERS/", 9) == 0) layers_declared = strtoul(line + 9, NULL, 10);
        else if (strcmp(line, "$$HEADEREND") == 0) header_end = 1;
        else if (strcmp(line, "$$GEOMETRYSTART") == 0) in_geom = 1;
        else if (strcmp(line, "$$GEOMETRYEND") == 0) geom_end = 1;
        else if (strncmp(line, "$$LAYER/", 8) == 0) {
            cr_assert(in_geom);
            double z = strtod(line + 8, NULL);
            cr_assert_gt(z, last_z);
            last_z = z;
            ++layer_lines;
        } else if (strncmp(line, "$$POLYLINE/", 11) == 0) {
            ++polylines;
            char *p = line + 11, *e;
            long id = strtol(p, &e, 10);
            cr_assert_eq(id, 1);
            long dir = strtol(e + 1, &e, 10);
            long np = strtol(e + 1, &e, 10);
            cr_assert(dir == 0 || dir == 1);
            double *xy = malloc(2 * (size_t)np * sizeof *xy);
            for (long k = 0; k < 2 * np; ++k) {
                cr_assert_eq(*e, ',');
                xy[k] = strtod(e + 1, &e);
            }
            cr_assert_eq(*e, '\0');
            cr_assert(xy[0] == xy[2 * np - 2] && xy[1] == xy[2 * np - 1]); /* closed */
            double a = shoelace(xy, (size_t)np - 1);
            cr_assert_eq(dir == 1, a > 0);
            free(xy);
        }
    }
    cr_assert(header_end && geom_end);
    cr_assert_eq(layers_declared, n); /* as many as the summary counts, no zero layer */
    cr_assert_eq(layer_lines, n);
    cr_assert_eq(polylines, 2 * n);
    free(text);
    hv_mesh_destroy(m);
}

Test(files, cli_binary_follows_the_format)
{
    hv_mesh *m = gen_holed_box();
    const char *path = t_tmpfile("box_bin.cli");
    size_t n = write_file(path, HV_CONTOUR_CLI_BINARY, m, 5);
    size_t len;
    char *data = t_slurp(path, &len);
    cr_assert(strncmp(data, "$$HEADERSTART\n$$BINARY\n", 23) == 0);
    char *he = strstr(data, "$$HEADEREND");
    cr_assert(he);
    const unsigned char *p = (const unsigned char *)he + 11, *end = (const unsigned char *)data + len;
    size_t layers = 0, polys = 0;
    while (p < end) {
        unsigned cmd = p[0] | (unsigned)p[1] << 8;
        p += 2;
        if (cmd == 127) {
            p += 4;
            ++layers;
        } else {
            cr_assert_eq(cmd, 130);
            int32_t v[3];
            memcpy(v, p, 12);
            p += 12;
            cr_assert_eq(v[0], 1);
            cr_assert(v[1] == 0 || v[1] == 1);
            p += 8 * (size_t)v[2];
            ++polys;
        }
    }
    cr_assert(p == end);
    cr_assert_eq(layers, n);
    cr_assert_eq(polys, 2 * n);
    free(data);
    hv_mesh_destroy(m);
}

Test(files, unwritable_path_and_layer_count_mismatch)
{
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    hv_contour_writer *w = NULL;
    cr_assert_eq(hv_contour_writer_open("/nonexistent-dir/x.cli", HV_CONTOUR_CLI_ASCII, 1, lo, hi,
                                        NULL, &w),
                 HV_ERR_IO);
    cr_assert(strstr(hv_last_error(), "/nonexistent-dir/x.cli"));
    const char *path = t_tmpfile("short.cli");
    cr_assert_eq(hv_contour_writer_open(path, HV_CONTOUR_CLI_ASCII, 3, lo, hi, NULL, &w), HV_OK);
    cr_assert_eq(hv_contour_writer_close(w), HV_ERR_INVALID);
    cr_assert_not(t_exists(path)); /* no partial file under the final name */
}

/* ---- the contour job (hv_contours_write) ---- */

typedef struct job_count {
    size_t layers, loops;
} job_count;

static hv_status count_layer(void *user, size_t index, const hv_layer *layer, const hv_slice *slice)
{
    job_count *c = user;
    (void)layer;
    cr_assert_eq(index, c->layers);
    ++c->layers;
    c->loops += hv_slice_get_stats(slice)->loops;
    return HV_OK;
}


Test(job, file_per_layer_svgs_and_summary_agree_with_single_slices)
{
    hv_mesh *m = gen_holed_box();
    hv_contours_options o;
    hv_contours_options_init(&o);
    o.layer_height = 5;
    o.output = t_tmpfile("job.cli");
    o.per_layer = t_tmpfile("job_layers");
    job_count c = {0, 0};
    hv_contours_summary sum;
    cr_assert_eq(hv_contours_write(m, &o, "dir/holed.stl", count_layer, &c, NULL, &sum), HV_OK, "%s", hv_last_error());
    hv_slicer *s = slicer_of(m);
    hv_layer_plan *p = NULL;
    cr_assert_eq(hv_slicer_plan_uniform(s, 0, 5, &p), HV_OK);
    size_t loops = 0;
    for (size_t i = 0; i < hv_layer_plan_count(p); ++i) {
        hv_slice *one = slice_at(s, hv_layer_plan_layers(p)[i].z, HV_SLICE_DEFAULT_CLOSE_GAP);
        loops += hv_slice_get_stats(one)->loops;
        hv_slice_destroy(one);
        char path[4096];
        snprintf(path, sizeof path, "%s/layer-%05zu.svg", o.per_layer, i);
        cr_assert(t_exists(path), "%s", path);
    }
    cr_assert_eq(sum.layers, hv_layer_plan_count(p));
    cr_assert_eq(c.layers, sum.layers);
    cr_assert_eq(sum.loops, loops);
    cr_assert_eq(c.loops, loops);
    FILE *f = fopen(o.output, "r");
    char line[256] = "";
    int labelled = 0;
    while (f && fgets(line, sizeof line, f)) labelled |= strstr(line, "$$LABEL/1,holed.stl") != NULL;
    if (f) fclose(f);
    cr_assert(labelled, "the file is labelled with the mesh's base name");
    hv_layer_plan_destroy(p);
    hv_slicer_destroy(s);
    hv_mesh_destroy(m);
}

Test(job, refusals_leave_nothing)
{
    hv_mesh *m = gen_holed_box();
    hv_contours_options o;
    hv_contours_options_init(&o);
    o.layer_height = 50; /* the box is 20 mm high: no layer has its middle inside */
    o.output = t_tmpfile("none.svg");
    cr_assert_eq(hv_contours_write(m, &o, "holed.stl", NULL, NULL, NULL, NULL), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "holed.stl: the mesh is 20 mm high"), "%s", hv_last_error());
    o.layer_height = 5;
    o.binary = 1;
    cr_assert_eq(hv_contours_write(m, &o, NULL, NULL, NULL, NULL, NULL), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "needs a .cli output"), "%s", hv_last_error());
    /* the per-layer directory cannot be made: the contour file is not left either */
    o.binary = 0;
    o.per_layer = "/proc/hovox-no/such-dir";
    cr_assert_neq(hv_contours_write(m, &o, NULL, NULL, NULL, NULL, NULL), HV_OK);
    cr_assert(!t_exists(o.output));
    hv_mesh_destroy(m);
}
