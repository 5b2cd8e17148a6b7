/* tests/material/test_material.c - material space, distribution functions, grading sources
 * and heterogeneous objects. Wu's three worked examples are built on generated meshes and
 * probed along lines against the formulas evaluated here independently (within 1e-3 plus
 * |dP/dd| * L); the sum-to-one invariant is checked in every voxel after every operator;
 * operator semantics are checked set-wise. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"
#include "support/support.h"
#include "material/material_internal.h"
#include "volumes/schema.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"
#include "mesh/mesh_internal.h"
#include "voxel/voxel_internal.h"
#include "material/material_internal.h"

/* ---- helpers ------------------------------------------------------------------------------ */

static hv_volume *voxelize(const hv_mesh *m, int64_t d0, int64_t d1, int64_t d2)
{
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.dims[0] = d0;
    o.dims[1] = d1;
    o.dims[2] = d2;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_OK, "%s", hv_last_error());
    return v;
}

static hv_material_table *table3(void)
{
    hv_material_table *t;
    cr_assert_eq(hv_material_table_create(&t), HV_OK);
    cr_assert_eq(hv_material_add(t, "A", NULL, NULL), HV_OK);
    cr_assert_eq(hv_material_add(t, "B", NULL, NULL), HV_OK);
    cr_assert_eq(hv_material_add(t, "C", NULL, NULL), HV_OK);
    return t;
}

static hv_ags *make_ags(hv_frf *frf, double dn, double dg, double dp, const char *f, const double *ms,
                        const double *me)
{
    hv_dfn *fn = NULL;
    if (f) cr_assert_eq(hv_dfn_expr(f, &fn), HV_OK, "%s", hv_last_error());
    hv_ags_desc d = {frf, dn, dg, dp, fn, ms, me, 3, NULL};
    hv_ags *a = NULL;
    cr_assert_eq(hv_ags_create(&d, &a), HV_OK, "%s", hv_last_error());
    hv_dfn_destroy(fn);
    return a;
}

/* Every occupied voxel's fractions sum to 1 and lie in [0,1]. */
static void check_sum_to_one(const hv_volume *v, const hv_material_table *t, const char *what)
{
    int m = hv_material_count(t), g[64];
    for (int j = 0; j < m; ++j) {
        g[j] = hv_material_grid(v, t, j);
        cr_assert_geq(g[j], 0);
    }
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const uint64_t *mask = hv_volume_leaf_mask(v, l);
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            if (!HV_BIT_GET(mask, n)) continue;
            double s = 0;
            for (int j = 0; j < m; ++j) {
                float x = hv_volume_leaf_float_c(v, g[j], l)[n];
                cr_assert(x >= -1e-6f && x <= 1 + 1e-6f, "%s: fraction %g out of [0,1]", what, (double)x);
                s += x;
            }
            cr_assert(fabs(s - 1) < 1e-5, "%s: fractions sum to %.9g", what, s);
        }
    }
}

/* Probe points along a..b (n samples) and compare with expected(p, P) within
 * 1e-3 + slope(p) * L, skipping points the expectation marks with NAN. */
typedef void (*expect_fn)(const double p[3], double P[3], double *slope);

static void probe_line(const hv_volume *v, const hv_material_table *t, const double a[3], const double b[3],
                       int n, expect_fn expect, const char *what)
{
    int g[3];
    for (int j = 0; j < 3; ++j) g[j] = hv_material_grid(v, t, j);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    hv_transform xf = hv_volume_get_transform(v);
    double L = fmax(xf.voxel[0], fmax(xf.voxel[1], xf.voxel[2]));
    int checked = 0;
    double worst = 0;
    for (int i = 0; i < n; ++i) {
        double s = (double)i / (n - 1), p[3], want[3], slope = 0, got[3];
        for (int k = 0; k < 3; ++k) p[k] = a[k] + s * (b[k] - a[k]);
        expect(p, want, &slope);
        if (isnan(want[0])) continue;
        int inside;
        hv_model_probe(&acc, t, g, p, &inside, got);
        cr_assert(inside, "%s: probe at (%g, %g, %g) is outside", what, p[0], p[1], p[2]);
        double tol = 1e-3 + slope * L;
        for (int j = 0; j < 3; ++j) {
            double err = fabs(got[j] - want[j]);
            worst = fmax(worst, err / tol);
            cr_assert(err <= tol, "%s: at (%.3f, %.3f, %.3f) material %d is %.5f, formula %.5f (tol %.4f)",
                      what, p[0], p[1], p[2], j, got[j], want[j], tol);
        }
        ++checked;
    }
    cr_assert_gt(checked, n / 2, "%s: too few probe points inside", what);
}

/* ---- material space ------------------------------------------------------------------------ */

Test(material, compositions_are_checked_not_clamped)
{
    double ok[3] = {0.1, 0.7, 0.2}, sum[3] = {0.1, 0.7, 0.3}, neg[3] = {-0.1, 0.9, 0.2};
    cr_assert_eq(hv_composition_check(ok, 3, "Ms"), HV_OK);
    cr_assert_eq(hv_composition_check(sum, 3, "Ms"), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "Ms = [0.1, 0.7, 0.3] sums to 1.1, not 1 (Wu eq. 12)");
    cr_assert_eq(hv_composition_check(neg, 3, "Me"), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "entry 1 is negative (-0.1)"), "%s", hv_last_error());
}

Test(material, table_from_text)
{
    const char *props[] = {"B:density=1180", "A:youngs_modulus=2.5:GPa"};
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_parse("A,B,rubber_1", "#ff0000,#00ff00,#0000ff", props, 2, &t), HV_OK, "%s",
                 hv_last_error());
    cr_assert_eq(hv_material_count(t), 3);
    cr_assert_str_eq(hv_material_name(t, 2), "rubber_1");
    float c[4];
    hv_material_color(t, 1, c);
    cr_assert(c[0] == 0 && c[1] == 1 && c[2] == 0 && c[3] == 1);
    double v;
    const char *unit;
    cr_assert(hv_material_property(t, 1, "density", &v, &unit) && v == 1180 && strcmp(unit, "kg/m^3") == 0);
    cr_assert(hv_material_property(t, 0, "youngs_modulus", &v, &unit) && v == 2.5 && strcmp(unit, "GPa") == 0);
    hv_material_table_destroy(t);
    static const struct { const char *names, *colors, *prop, *msg; } bad[] = {
        {"A,,B", NULL, NULL, "materials 'A,,B': expected comma-separated names"},
        {"A,B", "#ff0000", NULL, "colors: 1 colours for 2 materials"},
        {"A,A", NULL, NULL, "material 'A' is defined twice"},
        {"A,B", NULL, "C:density=1", "property 'C:density=1': no material 'C'"},
        {"A,B", NULL, "A=density", "property 'A=density': expected MATERIAL:KEY=VALUE[:UNIT]"},
        {"A,B", NULL, "A:density=heavy", "property"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; ++i) {
        t = (hv_material_table *)1;
        cr_assert_eq(hv_material_table_parse(bad[i].names, bad[i].colors, &bad[i].prop, bad[i].prop ? 1 : 0, &t),
                     HV_ERR_INVALID, "case %zu", i);
        cr_assert_null(t);
        cr_assert(strstr(hv_last_error(), bad[i].msg), "case %zu: %s", i, hv_last_error());
    }
}

/* issue 32 item 18: one colour table; a resin-named material takes the resin's colour by default */
Test(material, resin_named_materials_take_the_resin_colour)
{
    int n = 0;
    const hv_resin *r = hv_resin_table(&n);
    cr_assert_geq(n, 10);
    cr_assert_eq(hv_resin_find("veropurewhite"), hv_resin_find("VeroPureWhite"));
    cr_assert_null(hv_resin_find("VeroPureWhite2"));
    cr_assert_null(hv_resin_find(NULL));
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_create(&t), HV_OK);
    const float given[4] = {0.25f, 0.5f, 0.75f, 1};
    cr_assert_eq(hv_material_add(t, "A", NULL, NULL), HV_OK);
    cr_assert_eq(hv_material_add(t, "verocyan-v", NULL, NULL), HV_OK);
    cr_assert_eq(hv_material_add(t, "VeroMagenta-V", given, NULL), HV_OK);
    float c[4], p[4];
    hv_material_color(t, 0, c);
    hv_material_palette(0, p);
    cr_assert(memcmp(c, p, sizeof c) == 0);
    hv_material_color(t, 1, c);
    const hv_resin *cyan = hv_resin_find("VeroCyan-V");
    cr_assert_not_null(cyan);
    cr_assert(cyan >= r && cyan < r + n);
    for (int k = 0; k < 3; ++k) cr_assert_eq(lroundf(c[k] * 255.0f), cyan->rgb[k]);
    cr_assert_eq(c[3], 1.0f);
    hv_material_color(t, 2, c);
    cr_assert(memcmp(c, given, sizeof c) == 0);
    hv_material_table_destroy(t);
}

Test(material, table_round_trips_through_a_volume)
{
    hv_material_table *t = table3(), *r;
    float red[4] = {1, 0, 0, 1};
    cr_assert_eq(hv_material_set_color(t, 0, red), HV_OK);
    cr_assert_eq(hv_material_set_property(t, 1, "density", 1180, "kg/m^3"), HV_OK);
    cr_assert_eq(hv_material_set_property(t, 1, "youngs_modulus", 2.0e9, "Pa"), HV_OK);
    cr_assert_eq(hv_material_add(t, "A", NULL, NULL), HV_ERR_INVALID);
    cr_assert_eq(hv_material_add(t, "bad name", NULL, NULL), HV_ERR_INVALID);
    char *json;
    cr_assert_eq(hv_material_table_to_json(t, &json), HV_OK);
    cr_assert_eq(hv_material_table_from_json(json, &r), HV_OK, "%s", hv_last_error());
    free(json);
    float c[4];
    hv_material_color(r, 0, c);
    cr_assert_eq(c[0], 1.0f);
    double v;
    const char *unit;
    cr_assert(hv_material_property(r, 1, "density", &v, &unit));
    cr_assert_eq(v, 1180);
    cr_assert_str_eq(unit, "kg/m^3");
    cr_assert_eq(hv_material_property_count(r, 1), 2);
    hv_material_table_destroy(r);
    cr_assert_eq(hv_material_table_from_json("{\"materials\": [{}]}", &r), HV_ERR_BAD_INPUT);
    float rgba[4];
    cr_assert_eq(hv_color_parse("#1f77b4", rgba), HV_OK);
    cr_assert_float_eq(rgba[2], 0xb4 / 255.0f, 1e-6);
    cr_assert_eq(hv_color_parse("#12", rgba), HV_ERR_INVALID);
    hv_material_table_destroy(t);
}

/* ---- distribution functions --------------------------------------------------------------- */

Test(dfn, expressions)
{
    struct { const char *e; double d, want; } cases[] = {
        {"sin(0.1538*d)", 10, sin(1.538)}, {"0.105*d", 9.54, 1.0017}, {"2^3^2", 0, 512},
        {"-d^2", 3, -9}, {"(d+1)*(d-1)/dg", 3, 8.0 / 6.0}, {"min(d, 1) + max(0, -d)", 5, 1},
        {"pow(d, 0.5) + sqrt(d) - 2*abs(-sqrt(d))", 4, 0}, {"exp(log(d))", 7, 7}, {"pi", 0, M_PI},
        {" d / dg ", 1.5, 0.25}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        hv_dfn *f;
        cr_assert_eq(hv_dfn_expr(cases[i].e, &f), HV_OK, "%s: %s", cases[i].e, hv_last_error());
        cr_assert_float_eq(hv_dfn_eval(f, cases[i].d, 6), cases[i].want, 1e-12, "%s", cases[i].e);
        hv_dfn_destroy(f);
    }
    static const char *bad[][2] = {{"sn(d)", "column 1: unknown function 'sn'"},
                                   {"d + x", "column 5: unknown name 'x'"},
                                   {"(d + 1", "expected ')'"},
                                   {"d 2", "column 3: unexpected '2' after the expression"},
                                   {"", "unexpected end of expression"},
                                   {"min(d)", "min takes two arguments"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        hv_dfn *f = NULL;
        cr_assert_eq(hv_dfn_expr(bad[i][0], &f), HV_ERR_INVALID, "%s", bad[i][0]);
        cr_assert(strstr(hv_last_error(), bad[i][1]), "'%s': %s", bad[i][0], hv_last_error());
        cr_assert_null(f);
    }
}

Test(dfn, kinds)
{
    hv_dfn *f;
    cr_assert_eq(hv_dfn_linear(0.5, 0.1, &f), HV_OK);
    cr_assert_float_eq(hv_dfn_eval(f, 1, 2), 0.6, 1e-15);
    hv_dfn_destroy(f);
    cr_assert_eq(hv_dfn_sine(0.1538, 1, 0, 0, &f), HV_OK);
    cr_assert_float_eq(hv_dfn_eval(f, 10, 20), sin(1.538), 1e-15);
    hv_dfn_destroy(f);
    cr_assert_eq(hv_dfn_power(2, &f), HV_OK);
    cr_assert_float_eq(hv_dfn_eval(f, 1, 2), 0.25, 1e-15);
    hv_dfn_destroy(f);
    cr_assert_eq(hv_dfn_smoothstep(&f), HV_OK);
    cr_assert_float_eq(hv_dfn_eval(f, 1, 2), 0.5, 1e-15);
    cr_assert_float_eq(hv_dfn_eval(f, 0.5, 2), 0.15625, 1e-15);
    hv_dfn_destroy(f);
    double d[3] = {0, 1, 3}, v[3] = {0, 0.5, 1}, bad[3] = {0, 2, 1};
    cr_assert_eq(hv_dfn_table(d, v, 3, &f), HV_OK);
    cr_assert_float_eq(hv_dfn_eval(f, 2, 3), 0.75, 1e-15);
    cr_assert_float_eq(hv_dfn_eval(f, 7, 3), 1.0, 1e-15);
    hv_dfn_destroy(f);
    cr_assert_eq(hv_dfn_table(bad, v, 3, &f), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "point 3 has d = 1 after 2"), "%s", hv_last_error());
}

/* ---- grading sources ---------------------------------------------------------------------- */

Test(ags, evaluation_rules)
{
    double o[3] = {0, 0, 0}, z[3] = {0, 0, 1};
    hv_frf *axis;
    cr_assert_eq(hv_frf_line(o, z, &axis), HV_OK);
    double ms[3] = {0, 0.9, 0.1}, me[3] = {0.9, 0, 0.1}, p[3];
    /* gradient range: continuous, boundary values from f */
    hv_ags *a = make_ags(axis, 2, 4, 1, "0.25*d + 0.5*sin(0)", ms, me);
    hv_ags_eval(a, 1, p); /* NCMR: f(0) = 0 -> Ms */
    cr_assert_float_eq(p[1], 0.9, 1e-6);
    hv_ags_eval(a, 4, p); /* f(2) = 0.5 */
    cr_assert_float_eq(p[0], 0.45, 1e-5);
    cr_assert_float_eq(p[0] + p[1] + p[2], 1.0, 1e-9);
    hv_ags_eval(a, 100, p); /* PCMR: f(4) = 1 -> Me */
    cr_assert_float_eq(p[0], 0.9, 1e-6);
    hv_ags_release(a);
    /* dg = 0: a step at d- (an MMO), f irrelevant */
    a = make_ags(axis, 21.17, 0, 8.83, NULL, ms, me);
    hv_ags_eval(a, 21.16, p);
    cr_assert_float_eq(p[1], 0.9, 1e-9);
    hv_ags_eval(a, 21.17, p);
    cr_assert_float_eq(p[0], 0.9, 1e-9);
    hv_ags_release(a);
    /* Wu's gear f(d) = 0.105 d over dg = 9.54 reaches 1.0017: refused, with the value */
    hv_dfn *f;
    cr_assert_eq(hv_dfn_expr("0.105*d", &f), HV_OK);
    hv_ags_desc d = {axis, 9.54, 9.54, 20.37, f, ms, me, 3, NULL};
    cr_assert_eq(hv_ags_create(&d, &a), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "f(9.54) = 1.0017"), "%s", hv_last_error());
    hv_dfn_destroy(f);
    /* negative ranges and bad vectors */
    double bad[3] = {0.5, 0.6, 0};
    hv_ags_desc d2 = {axis, -1, 1, 1, NULL, ms, me, 3, NULL};
    cr_assert_eq(hv_ags_create(&d2, &a), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "d- (negative constant range) must be >= 0 for a axis feature") &&
                  strstr(hv_last_error(), "(got -1;"),
              "%s", hv_last_error());
    hv_ags_desc d3 = {axis, 0, 0, 0, NULL, bad, me, 3, NULL};
    cr_assert_eq(hv_ags_create(&d3, &a), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "Ms = [0.5, 0.6, 0] sums to 1.1"), "%s", hv_last_error());
    /* move (Wu eq. 26) */
    hv_ags *b = make_ags(axis, 2, 4, 1, "d/dg", ms, me), *c;
    cr_assert_eq(hv_ags_moved(b, 5, &c), HV_OK);
    hv_ags_eval(c, 7, p);
    cr_assert_float_eq(p[0], 0.45, 1e-5);
    hv_ags_release(b);
    hv_ags_release(c);
    hv_frf_release(axis);
}

/* issue 32 item 16: a half-space gives the signed distance to its plane, positive where the normal
 * points; a signed feature takes d- < 0 (a distance feature does not), and round trips through the
 * object document as the options that make it. */
Test(ags, signed_features_take_a_negative_d_neg)
{
    double p0[3] = {10, 0, 0}, n[3] = {2, 0, 0}, q[3];
    hv_frf *hs;
    cr_assert_eq(hv_frf_halfspace(p0, n, &hs), HV_OK);
    cr_assert(hv_frf_is_signed(hs));
    double at[3][2] = {{2.5, -7.5}, {10, 0}, {13, 3}};
    for (int i = 0; i < 3; ++i) {
        q[0] = at[i][0], q[1] = 4, q[2] = -3;
        cr_assert_float_eq(hv_frf_sample(hs, q), at[i][1], 1e-12);
    }
    /* the leaf kernel gives the same signed values */
    hv_transform xf = {{0.5, 0.5, 0.5}, {2, 0, 0}};
    int32_t o[3] = {8, 0, 0};
    float d[HV_LEAF_SIZE];
    hv_frf_leaf_distances(hs, &xf, o, d);
    cr_assert_float_eq(d[0], (2 + 8 * 0.5) - 10, 1e-5);
    cr_assert_float_eq(d[7 << 6], (2 + 15 * 0.5) - 10, 1e-5);
    double ms[3] = {1, 0, 0}, me[3] = {0, 1, 0}, c[3];
    hv_ags *a = make_ags(hs, -5, 10, 0, "d/dg", ms, me), *b;
    hv_ags_eval(a, -7.5, c);
    cr_assert_float_eq(c[0], 1, 1e-9);
    hv_ags_eval(a, -2.5, c);
    cr_assert_float_eq(c[1], 0.25, 1e-6);
    cr_assert_eq(hv_ags_moved(a, -8, &b), HV_OK);
    hv_ags_release(b);
    /* the document: kind halfspace with point and normal, read back to the same distances */
    json_t *doc = hv_frf_to_doc(hs, NULL, NULL);
    cr_assert_not_null(doc);
    cr_assert_str_eq(json_string_value(json_object_get(doc, "kind")), "halfspace");
    hv_frf *back;
    cr_assert_eq(hv_frf_from_doc(doc, NULL, "test", &back), HV_OK, "%s", hv_last_error());
    q[0] = 3, q[1] = 0, q[2] = 0;
    cr_assert_float_eq(hv_frf_sample(back, q), -7, 1e-12);
    json_decref(doc);
    hv_frf_release(back);
    /* a plane is the unsigned distance and refuses d- < 0 */
    hv_frf *pl;
    cr_assert_eq(hv_frf_plane(p0, n, &pl), HV_OK);
    cr_assert(!hv_frf_is_signed(pl));
    q[0] = 2.5;
    cr_assert_float_eq(hv_frf_sample(pl, q), 7.5, 1e-12);
    hv_ags_desc dd = {pl, -5, 10, 0, NULL, ms, me, 3, NULL};
    cr_assert_eq(hv_ags_create(&dd, &b), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "plane feature, whose distances are never negative"), "%s", hv_last_error());
    hv_frf_release(pl);
    hv_ags_release(a);
    hv_frf_release(hs);
}

Test(ags, wu_eq13_three_material_paradigm)
{
    double o[3] = {0, 0, 0}, x[3] = {1, 0, 0};
    hv_frf *plane;
    cr_assert_eq(hv_frf_plane(o, x, &plane), HV_OK);
    hv_dfn *f;
    cr_assert_eq(hv_dfn_expr("0.7*d/dg", &f), HV_OK);
    hv_ags *a;
    cr_assert_eq(hv_ags_wu3(plane, 1, 10, 0, f, 0.2, &a), HV_OK, "%s", hv_last_error());
    double p[3];
    hv_ags_eval(a, 6, p); /* f(5) = 0.35: [0.35, 0.45, 0.2] */
    cr_assert_float_eq(p[0], 0.35, 1e-5);
    cr_assert_float_eq(p[1], 0.45, 1e-5);
    cr_assert_float_eq(p[2], 0.2, 1e-9);
    hv_ags_release(a);
    /* f must stay within 1 - C */
    cr_assert_eq(hv_ags_wu3(plane, 1, 10, 0, f, 0.4, &a), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "leaves [0, 0.6]"), "%s", hv_last_error());
    hv_dfn_destroy(f);
    hv_frf_release(plane);
}

/* ---- Wu's worked examples -------------------------------------------------------------------- */

/* Example 1, MMO: a block, feature the y axis, d- = 21.17, dg = 0, d+ = 8.83,
 * Ms = [0.1,0.7,0.2], Me = [0.7,0.1,0.2]. */
static void mmo_expect(const double p[3], double P[3], double *slope)
{
    double r = sqrt(p[0] * p[0] + p[2] * p[2]);
    static const double ms[3] = {0.1, 0.7, 0.2}, me[3] = {0.7, 0.1, 0.2};
    /* at the step the trilinear probe mixes both sides: skip within a voxel of it */
    if (fabs(r - 21.17) < 0.35) {
        P[0] = NAN;
        return;
    }
    for (int j = 0; j < 3; ++j) P[j] = r < 21.17 ? ms[j] : me[j];
    *slope = 0;
}

Test(wu, example1_multi_material_object, .timeout = 60)
{
    hv_mesh *mesh;
    double lo[3] = {-21.2, 0, -21.2}, hi[3] = {21.2, 50, 21.2};
    cr_assert_eq(hv_generate_box(lo, hi, &mesh), HV_OK);
    hv_volume *v = voxelize(mesh, 128, 0, 0);
    hv_material_table *t = table3();
    hv_object *o;
    cr_assert_eq(hv_object_create(v, "occupancy", 3, &o), HV_OK);
    double zero[3] = {0, 0, 0}, y[3] = {0, 1, 0}, ms[3] = {0.1, 0.7, 0.2}, me[3] = {0.7, 0.1, 0.2};
    hv_frf *axis;
    cr_assert_eq(hv_frf_line(zero, y, &axis), HV_OK);
    hv_ags *a = make_ags(axis, 21.17, 0, 8.83, NULL, ms, me);
    cr_assert_eq(hv_object_add_ags(o, a), HV_OK);
    hv_volume *out;
    cr_assert_eq(hv_object_evaluate(o, t, 0, NULL, &out), HV_OK, "%s", hv_last_error());
    check_sum_to_one(out, t, "MMO");
    double a1[3] = {-20.8, 25, 0}, b1[3] = {20.8, 25, 0}, a2[3] = {-20.8, 10, -20.8}, b2[3] = {20.8, 10, 20.8};
    probe_line(out, t, a1, b1, 200, mmo_expect, "MMO line S1");
    probe_line(out, t, a2, b2, 200, mmo_expect, "MMO diagonal S2");
    hv_volume_destroy(out);
    hv_ags_release(a);
    hv_frf_release(axis);
    hv_object_destroy(o);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
    hv_mesh_destroy(mesh);
}

/* Example 2, the 150x55x55 shaft at (256, 97, 97): feature the model's contour, d- = 0,
 * dg = 20.416, f = sin(0.1538 d), Ms = [0,0,1], Me = [0,0.2,0.8]. */
static void shaft_expect(const double p[3], double P[3], double *slope)
{
    double r = sqrt(p[1] * p[1] + p[2] * p[2]);
    double d = fmin(27.5 - r, fmin(p[0], 150 - p[0]));
    if (d < 0.8) { /* the outermost voxel: skip (the probe renormalises over the skin) */
        P[0] = NAN;
        return;
    }
    double u = fmin(fmax(d, 0), 20.416), f = sin(0.1538 * u);
    P[0] = 0;
    P[1] = 0.2 * f;
    P[2] = 1 - 0.2 * f;
    *slope = 0.2 * 0.1538 * fabs(cos(0.1538 * u)) + 0.2 * 0.1538 * 0.5; /* plus a half-voxel kink */
}

Test(wu, example2_shaft_contour_sine, .timeout = 120)
{
    hv_mesh *mesh;
    double base[3] = {0, 0, 0};
    cr_assert_eq(hv_generate_cylinder(base, 0, 150, 27.5, 256, &mesh), HV_OK);
    hv_volume *v = voxelize(mesh, 256, 97, 97);
    hv_material_table *t = table3();
    hv_object *o;
    cr_assert_eq(hv_object_create(v, "occupancy", 3, &o), HV_OK);
    hv_frf *contour;
    cr_assert_eq(hv_frf_contour(v, "occupancy", &contour), HV_OK, "%s", hv_last_error());
    double ms[3] = {0, 0, 1}, me[3] = {0, 0.2, 0.8};
    hv_ags *a = make_ags(contour, 0, 20.416, 0, "sin(0.1538*d)", ms, me);
    cr_assert_eq(hv_object_add_ags(o, a), HV_OK);
    hv_volume *out;
    cr_assert_eq(hv_object_evaluate(o, t, 0, NULL, &out), HV_OK, "%s", hv_last_error());
    check_sum_to_one(out, t, "shaft");
    double r1[3] = {75, -27.5, 0}, r2[3] = {75, 27.5, 0}, d1[3] = {75, -19.4, -19.4}, d2[3] = {75, 19.4, 19.4},
           x1[3] = {0, 10, 0}, x2[3] = {150, 10, 0};
    probe_line(out, t, r1, r2, 220, shaft_expect, "shaft radial S1");
    probe_line(out, t, d1, d2, 220, shaft_expect, "shaft diagonal S2");
    probe_line(out, t, x1, x2, 400, shaft_expect, "shaft axial S3");
    hv_volume_destroy(out);
    hv_ags_release(a);
    hv_frf_release(contour);
    hv_object_destroy(o);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
    hv_mesh_destroy(mesh);
}

/* Example 3, the gear: AGS1 on the z axis (d- = 9.54, dg = 9.54, d+ = 20.37), AGS2 on the bottom
 * plane (3.18, 22.26, 14.01), f normalised (d/dg), Ms = [0,0.9,0.1], Me = [0.9,0,0.1]; AGS union
 * by the nearest source. */
static void gear_ags(double d, double dn, double dg, double P[3], double *slope)
{
    double w = fmin(fmax((d - dn) / dg, 0), 1);
    P[0] = 0.9 * w;
    P[1] = 0.9 * (1 - w);
    P[2] = 0.1;
    *slope = 0.9 / dg;
}

static void gear_expect(const double p[3], double P[3], double *slope)
{
    double r = sqrt(p[0] * p[0] + p[1] * p[1]), z = p[2];
    /* skip near the switch between sources (the nearest feature changes there) and near the
     * bore and the faces, where the probe renormalises over the surface skin */
    if (fabs(r - z) < 0.9 || r < 10.3 || z < 0.8 || z > 38.6) {
        P[0] = NAN;
        return;
    }
    if (r < z) gear_ags(r, 9.54, 9.54, P, slope);
    else gear_ags(z, 3.18, 22.26, P, slope);
}

Test(wu, example3_gear_two_sources, .timeout = 120)
{
    hv_mesh *mesh;
    cr_assert_eq(hv_generate_gear(24, 34.5, 39.45, 9.54, 39.45, 0, 12, 1, &mesh), HV_OK);
    hv_volume *v = voxelize(mesh, 128, 0, 0);
    hv_material_table *t = table3();
    hv_object *o;
    cr_assert_eq(hv_object_create(v, "occupancy", 3, &o), HV_OK);
    double zero[3] = {0, 0, 0}, zax[3] = {0, 0, 1}, ms[3] = {0, 0.9, 0.1}, me[3] = {0.9, 0, 0.1};
    hv_frf *axis, *plane;
    cr_assert_eq(hv_frf_line(zero, zax, &axis), HV_OK);
    cr_assert_eq(hv_frf_plane(zero, zax, &plane), HV_OK);
    hv_ags *a1 = make_ags(axis, 9.54, 9.54, 20.37, "d/dg", ms, me);
    hv_ags *a2 = make_ags(plane, 3.18, 22.26, 14.01, "d/dg", ms, me);
    cr_assert_eq(hv_object_add_ags(o, a1), HV_OK);
    cr_assert_eq(hv_object_add_ags(o, a2), HV_OK);
    hv_volume *out;
    cr_assert_eq(hv_object_evaluate(o, t, 0, NULL, &out), HV_OK, "%s", hv_last_error());
    check_sum_to_one(out, t, "gear");
    double s1a[3] = {0, -34, 20}, s1b[3] = {0, 34, 20}, s2a[3] = {25, 0, 0}, s2b[3] = {25, 0, 39.45},
           s3a[3] = {8, 8, 5}, s3b[3] = {24, 24, 36};
    probe_line(out, t, s1a, s1b, 300, gear_expect, "gear radial");
    probe_line(out, t, s2a, s2b, 300, gear_expect, "gear axial");
    probe_line(out, t, s3a, s3b, 300, gear_expect, "gear oblique");
    hv_volume_destroy(out);
    /* delete and move (Wu eq. 25, 26) */
    cr_assert_eq(hv_object_delete_ags(o, a2), HV_OK);
    cr_assert_eq(hv_object_region_ags_count(o, 0), 1);
    cr_assert_eq(hv_object_delete_ags(o, a2), HV_ERR_NOT_FOUND);
    cr_assert_eq(hv_object_move_ags(o, a1, 12), HV_OK);
    cr_assert_eq(hv_object_evaluate(o, t, 0, NULL, &out), HV_OK);
    int g[3], inside;
    for (int j = 0; j < 3; ++j) g[j] = hv_material_grid(out, t, j);
    hv_accessor acc;
    hv_accessor_init(&acc, out);
    double p[3] = {0, 15, 20}, frac[3];
    hv_model_probe(&acc, t, g, p, &inside, frac);
    cr_assert_float_eq(frac[0], 0.9 * (15 - 12) / 9.54, 1e-3 + 0.9 / 9.54 * 0.31); /* moved d- */
    hv_volume_destroy(out);
    /* the moved source itself, kept by the caller (issue 32.17): it takes a1's place, and can be
     * deleted; a1 is gone; a source over other materials is refused */
    cr_assert_eq(hv_object_move_ags(o, a1, 12), HV_ERR_NOT_FOUND); /* a1 was replaced */
    cr_assert_eq(hv_object_add_ags(o, a1), HV_OK);
    hv_ags *b1;
    cr_assert_eq(hv_ags_moved(a1, 12, &b1), HV_OK);
    cr_assert_eq(hv_object_replace_ags(o, a1, b1), HV_OK);
    cr_assert_eq(hv_object_region_ags_count(o, 0), 2);
    cr_assert_eq(hv_object_delete_ags(o, a1), HV_ERR_NOT_FOUND);
    cr_assert_eq(hv_object_delete_ags(o, b1), HV_OK);
    cr_assert_eq(hv_object_region_ags_count(o, 0), 1);
    cr_assert_eq(hv_object_replace_ags(o, b1, a1), HV_ERR_NOT_FOUND);
    double ms2[2] = {1, 0}, me2[2] = {0, 1};
    hv_ags_desc d2 = {axis, 1, 0, 3, NULL, ms2, me2, 2, NULL}; /* a step: no f */
    hv_ags *two = NULL;
    cr_assert_eq(hv_ags_create(&d2, &two), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_replace_ags(o, a2, two), HV_ERR_INVALID);
    hv_ags_release(two);
    hv_ags_release(b1);
    hv_ags_release(a1);
    hv_ags_release(a2);
    hv_frf_release(axis);
    hv_frf_release(plane);
    hv_object_destroy(o);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
    hv_mesh_destroy(mesh);
}

/* ---- operators --------------------------------------------------------------------------------- */

typedef struct two {
    hv_volume *v1, *v2;
    hv_object *h1, *h2;
    hv_ags *g1, *g2;
    hv_frf *f1, *f2;
    hv_material_table *t;
} two;

/* Two overlapping spheres on the same lattice with different single sources. */
static void two_spheres(two *w)
{
    hv_mesh *m1, *m2;
    double c1[3] = {-4, 0, 0}, c2[3] = {4, 0, 0};
    cr_assert_eq(hv_generate_sphere(c1, 8, 48, 24, &m1), HV_OK);
    cr_assert_eq(hv_generate_sphere(c2, 8, 48, 24, &m2), HV_OK);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    cr_assert_eq(hv_voxelize(m1, &o, &w->v1), HV_OK);
    cr_assert_eq(hv_voxelize(m2, &o, &w->v2), HV_OK);
    hv_mesh_destroy(m1);
    hv_mesh_destroy(m2);
    hv_transform a = hv_volume_get_transform(w->v1), b = hv_volume_get_transform(w->v2);
    cr_assert(hv_transform_same(&a, &b), "the spheres must share a lattice");
    cr_assert_eq(hv_object_create(w->v1, "occupancy", 3, &w->h1), HV_OK);
    cr_assert_eq(hv_object_create(w->v2, "occupancy", 3, &w->h2), HV_OK);
    cr_assert_eq(hv_frf_point(c1, &w->f1), HV_OK);
    cr_assert_eq(hv_frf_point(c2, &w->f2), HV_OK);
    double ma[3] = {1, 0, 0}, mb[3] = {0, 1, 0}, mc[3] = {0, 0, 1};
    w->g1 = make_ags(w->f1, 2, 4, 2, "d/dg", ma, mb);
    w->g2 = make_ags(w->f2, 0, 8, 0, "d/dg", mc, mb);
    cr_assert_eq(hv_object_add_ags(w->h1, w->g1), HV_OK);
    cr_assert_eq(hv_object_add_ags(w->h2, w->g2), HV_OK);
    w->t = table3();
}

static void free_two(two *w)
{
    hv_object_destroy(w->h1);
    hv_object_destroy(w->h2);
    hv_ags_release(w->g1);
    hv_ags_release(w->g2);
    hv_frf_release(w->f1);
    hv_frf_release(w->f2);
    hv_volume_destroy(w->v1);
    hv_volume_destroy(w->v2);
    hv_material_table_destroy(w->t);
}

static int occ(hv_accessor *a, int g, int i, int j, int k) { return hv_accessor_bool(a, g, i, j, k); }

Test(operators, semantics_and_invariants, .timeout = 120)
{
    two w;
    two_spheres(&w);
    hv_volume *e1, *e2;
    cr_assert_eq(hv_object_evaluate(w.h1, w.t, 0, NULL, &e1), HV_OK);
    cr_assert_eq(hv_object_evaluate(w.h2, w.t, 0, NULL, &e2), HV_OK);
    hv_bool_op ops[5] = {HV_OP_INTERSECT, HV_OP_UNITE, HV_OP_DIFFERENCE, HV_OP_MERGE, HV_OP_SUBTRACT};
    const char *names[5] = {"intersect", "unite", "difference", "merge", "subtract"};
    hv_accessor a1, a2, ar;
    hv_accessor_init(&a1, e1);
    hv_accessor_init(&a2, e2);
    int g1[3], g2[3], gr[3];
    for (int j = 0; j < 3; ++j) {
        g1[j] = hv_material_grid(e1, w.t, j);
        g2[j] = hv_material_grid(e2, w.t, j);
    }
    for (int op = 0; op < 5; ++op) {
        hv_object *h;
        cr_assert_eq(hv_object_boolean(w.h1, w.h2, ops[op], &h), HV_OK, "%s: %s", names[op], hv_last_error());
        hv_volume *r;
        cr_assert_eq(hv_object_evaluate(h, w.t, 0, NULL, &r), HV_OK, "%s", hv_last_error());
        check_sum_to_one(r, w.t, names[op]);
        hv_accessor_init(&ar, r);
        int go = hv_volume_grid_find(r, "occupancy");
        for (int j = 0; j < 3; ++j) gr[j] = hv_material_grid(r, w.t, j);
        long bad_geom = 0, bad_mat = 0;
        for (int i = -30; i <= 30; ++i)
            for (int j = -20; j <= 20; ++j)
                for (int k = -20; k <= 20; ++k) {
                    /* sphere lattices: index ranges differ per volume but the lattice is shared */
                    int o1 = occ(&a1, 0, i, j, k), o2 = occ(&a2, 0, i, j, k), o = occ(&ar, go, i, j, k);
                    int want = op == 0 ? (o1 && o2) : op == 1 || op == 3 ? (o1 || o2)
                             : op == 2 ? o1 : (o1 && !o2);
                    if (o != want) ++bad_geom;
                    if (!o) continue;
                    /* material: only-H1 voxels carry H1's composition; for the difference the
                     * overlap carries H2's (Wu eq. 29) */
                    int only1 = o1 && !o2, both = o1 && o2;
                    const int *gs = NULL;
                    hv_accessor *src = NULL;
                    if (only1 && op != 3) { src = &a1; gs = g1; }
                    if (both && op == 2) { src = &a2; gs = g2; }
                    if (!o1 && o2 && (op == 1)) { src = &a2; gs = g2; }
                    if (!src) continue;
                    for (int m = 0; m < 3; ++m)
                        if (fabsf(hv_accessor_float(&ar, gr[m], i, j, k) - hv_accessor_float(src, gs[m], i, j, k)) > 1e-6f)
                            ++bad_mat;
                }
        cr_assert_eq(bad_geom, 0, "%s: %ld voxels with the wrong occupancy", names[op], bad_geom);
        cr_assert_eq(bad_mat, 0, "%s: %ld voxels with the wrong composition", names[op], bad_mat);
        /* region structure */
        int want_regions[5] = {1, 3, 2, 1, 1};
        cr_assert_eq(hv_object_region_count(h), want_regions[op], "%s", names[op]);
        if (op == 0 || op == 3) cr_assert_eq(hv_object_region_ags_count(h, 0), 2, "%s", names[op]);
        hv_volume_destroy(r);
        hv_object_destroy(h);
    }
    hv_volume_destroy(e1);
    hv_volume_destroy(e2);
    free_two(&w);
}

Test(operators, blends_keep_the_sum)
{
    two w;
    two_spheres(&w);
    hv_object *h;
    cr_assert_eq(hv_object_boolean(w.h1, w.h2, HV_OP_MERGE, &h), HV_OK);
    cr_assert_eq(hv_object_set_blend(h, HV_BLEND_IDW, 2), HV_OK);
    hv_volume *r;
    cr_assert_eq(hv_object_evaluate(h, w.t, 0, NULL, &r), HV_OK);
    check_sum_to_one(r, w.t, "idw");
    /* midway between the two points the inverse-distance blend gives equal weights */
    int g[3], inside;
    for (int j = 0; j < 3; ++j) g[j] = hv_material_grid(r, w.t, j);
    hv_accessor acc;
    hv_accessor_init(&acc, r);
    double p[3] = {0, 3, 0}, f[3], P1[3], P2[3];
    hv_model_probe(&acc, w.t, g, p, &inside, f);
    double d = 5.0; /* |(0,3,0) - (+-4,0,0)| */
    hv_ags_eval(w.g1, d, P1);
    hv_ags_eval(w.g2, d, P2);
    for (int j = 0; j < 3; ++j) cr_assert_float_eq(f[j], 0.5 * (P1[j] + P2[j]), 0.03);
    cr_assert_eq(hv_object_set_blend(h, (hv_blend)7, 2), HV_ERR_INVALID);
    hv_volume_destroy(r);
    hv_object_destroy(h);
    free_two(&w);
}

/* Wu's AGS operators (eq. 24-26) keep the sum-to-one invariant in every voxel: add a second
 * source to one object, move one, delete one, evaluating after each. */
Test(operators, ags_add_move_delete_keep_the_sum, .timeout = 60)
{
    two w;
    two_spheres(&w);
    hv_volume *r;
    cr_assert_eq(hv_object_add_ags(w.h1, w.g2), HV_OK); /* two sources: nearest wins */
    cr_assert_eq(hv_object_evaluate(w.h1, w.t, 0, NULL, &r), HV_OK, "%s", hv_last_error());
    check_sum_to_one(r, w.t, "after add");
    hv_volume_destroy(r);
    cr_assert_eq(hv_object_move_ags(w.h1, w.g1, 1.5), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_evaluate(w.h1, w.t, 0, NULL, &r), HV_OK, "%s", hv_last_error());
    check_sum_to_one(r, w.t, "after move");
    hv_volume_destroy(r);
    cr_assert_eq(hv_object_delete_ags(w.h1, w.g2), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_evaluate(w.h1, w.t, 0, NULL, &r), HV_OK, "%s", hv_last_error());
    check_sum_to_one(r, w.t, "after delete");
    hv_volume_destroy(r);
    free_two(&w);
}

Test(operators, lattices_and_counts_must_match)
{
    two w;
    two_spheres(&w);
    hv_mesh *m;
    double c[3] = {0, 0, 0};
    cr_assert_eq(hv_generate_sphere(c, 5, 16, 8, &m), HV_OK);
    hv_volume *v = voxelize(m, 33, 0, 0);
    hv_object *other, *h = NULL;
    cr_assert_eq(hv_object_create(v, "occupancy", 3, &other), HV_OK);
    cr_assert_eq(hv_object_boolean(w.h1, other, HV_OP_UNITE, &h), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "different voxel lattices"), "%s", hv_last_error());
    cr_assert_null(h);
    hv_object_destroy(other);
    cr_assert_eq(hv_object_create(v, "nope", 3, &other), HV_ERR_NOT_FOUND);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
    free_two(&w);
}

Test(evaluate, deterministic_and_planned, .timeout = 60)
{
    two w;
    two_spheres(&w);
    hv_volume *r[2];
    for (int t = 0; t < 2; ++t) {
        hv_set_threads(t ? 3 : 1);
        cr_assert_eq(hv_object_evaluate(w.h1, w.t, 0, NULL, &r[t]), HV_OK);
    }
    hv_set_threads(0);
    int g = hv_material_grid(r[0], w.t, 1);
    for (size_t l = 0; l < hv_volume_leaf_count(r[0]); ++l)
        cr_assert_eq(memcmp(hv_volume_leaf_float_c(r[0], g, l), hv_volume_leaf_float_c(r[1], g, l), 2048), 0);
    hv_volume *x = NULL;
    cr_assert_eq(hv_object_evaluate(w.h1, w.t, 4096, NULL, &x), HV_ERR_LIMIT);
    cr_assert(strstr(hv_last_error(), "needs about"), "%s", hv_last_error());
    cr_assert_null(x);
    /* metadata records the sources */
    const char *js = hv_volume_meta_string(r[0], "hovox.object.json");
    cr_assert(js && strstr(js, "point(-4,0,0)") && strstr(js, "\"d_grad\": 4"), "%s", js ? js : "(none)");
    hv_material_table *back;
    cr_assert_eq(hv_material_table_load(r[0], &back), HV_OK);
    cr_assert_eq(hv_material_count(back), 3);
    hv_material_table_destroy(back);
    hv_volume_destroy(r[0]);
    hv_volume_destroy(r[1]);
    free_two(&w);
}

/* The contour distance (EDT to the outside less the skin) against the exact depth in a sphere. */
Test(frf, contour_depth_is_accurate_to_a_voxel, .timeout = 60)
{
    hv_mesh *m;
    double c[3] = {0.3, -0.1, 0.2};
    cr_assert_eq(hv_generate_sphere(c, 20, 128, 64, &m), HV_OK);
    for (int adj = 0; adj < 2; ++adj) {
        hv_voxelize_options o;
        hv_voxelize_options_init(&o);
        o.dims[0] = 80;
        o.adjacency = adj ? 26 : 6;
        hv_volume *v;
        cr_assert_eq(hv_voxelize(m, &o, &v), HV_OK);
        hv_frf *f;
        cr_assert_eq(hv_frf_contour(v, "occupancy", &f), HV_OK);
        double L = hv_volume_get_transform(v).voxel[0], worst = 0, mean = 0;
        int n = 0;
        for (double x = -18; x <= 18; x += 0.77)
            for (double y = -18; y <= 18; y += 1.31) {
                double p[3] = {x + c[0], y + c[1], 0.4 + c[2]}, d;
                double r = sqrt(x * x + y * y + 0.16);
                if (r > 19.5) continue;
                cr_assert_eq(hv_frf_distance(f, v, p, &d), HV_OK);
                double err = d - (20 - r);
                worst = fmax(worst, fabs(err));
                mean += err;
                ++n;
            }
        mean /= n;
        /* measured: mean -0.15 (26) and -0.5 (6) voxels here, +0.5 when faces sit on voxel
         * boundaries; worst 1.3 voxels (README: accuracy of the contour depth) */
        cr_assert_lt(worst, 1.35 * L, "adjacency %d: worst depth error %.3f voxels", o.adjacency, worst / L);
        cr_assert_lt(fabs(mean), 0.6 * L, "adjacency %d: mean depth bias %.3f voxels", o.adjacency, mean / L);
        hv_frf_release(f);
        hv_volume_destroy(v);
    }
    hv_mesh_destroy(m);
}

/* The harmonic feature on a bar between its end faces is linear along the bar. */
Test(frf, harmonic_bar_is_linear, .timeout = 120)
{
    hv_mesh *m;
    double lo[3] = {0, 0, 0}, hi[3] = {40, 8, 8};
    cr_assert_eq(hv_generate_box(lo, hi, &m), HV_OK);
    hv_volume *v = voxelize(m, 80, 0, 0);
    hv_facet_select one = {1, {-1, 0, 0}, 10, 0, {0}, {0}}, zero = {1, {1, 0, 0}, 10, 0, {0}, {0}};
    cr_assert_eq(hv_facet_select_count(m, &one), 2);
    hv_frf *f;
    cr_assert_eq(hv_frf_harmonic(v, "occupancy", m, &one, &zero, &f), HV_OK, "%s", hv_last_error());
    double L = hv_volume_get_transform(v).voxel[0];
    for (double x = 2; x <= 38; x += 1.7) {
        double p[3] = {x, 4, 4}, d;
        cr_assert_eq(hv_frf_distance(f, v, p, &d), HV_OK, "%s", hv_last_error());
        /* phi = 1 at x = 0, 0 at x = 40; the labelled voxel layers sit about half a voxel out */
        cr_assert_float_eq(d, 1 - x / 40, 0.02 + L / 40, "phi(%g) = %g", x, d);
    }
    hv_frf_release(f);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

/* A saved model carries its grading definition: rebuilt from the file it evaluates to the same
 * grids, and sampled at voxel centres it gives the stored fractions. */
Test(model, definition_round_trips_through_a_file, .timeout = 120)
{
    two w;
    two_spheres(&w);
    /* a voxel feature (the contour of sphere 2) next to the analytic ones */
    hv_frf *contour;
    cr_assert_eq(hv_frf_contour(w.v2, "occupancy", &contour), HV_OK);
    double ms[3] = {0, 0, 1}, me[3] = {1, 0, 0};
    hv_ags *g3 = make_ags(contour, 0, 3, 0, "sin(d/dg*pi/2)", ms, me);
    cr_assert_eq(hv_object_add_ags(w.h2, g3), HV_OK);
    hv_object *u;
    cr_assert_eq(hv_object_boolean(w.h1, w.h2, HV_OP_UNITE, &u), HV_OK);
    cr_assert_eq(hv_object_set_blend(u, HV_BLEND_IDW, 1.5), HV_OK);
    hv_volume *v;
    cr_assert_eq(hv_object_evaluate(u, w.t, 0, NULL, &v), HV_OK, "%s", hv_last_error());
    cr_assert_geq(hv_volume_grid_find(v, "region.2"), 0);
    cr_assert_geq(hv_volume_grid_find(v, "distance.2"), 0); /* point, point, contour */
    cr_assert_lt(hv_volume_grid_find(v, "distance.0"), 0);  /* analytic: no stored field */
    const char *path = t_tmpfile("defn.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK);
    hv_volume *back;
    cr_assert_eq(hv_volume_load(path, &back), HV_OK);
    hv_object *r;
    cr_assert_eq(hv_object_from_model(back, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_region_count(r), 3);
    cr_assert_eq(hv_object_voxels(r), hv_object_voxels(u));
    hv_volume *again;
    cr_assert_eq(hv_object_evaluate(r, w.t, 0, NULL, &again), HV_OK, "%s", hv_last_error());
    int ga[3], gb[3];
    for (int j = 0; j < 3; ++j) {
        ga[j] = hv_material_grid(v, w.t, j);
        gb[j] = hv_material_grid(again, w.t, j);
    }
    hv_accessor aa, ab;
    hv_accessor_init(&aa, v);
    hv_accessor_init(&ab, again);
    long diff = 0, sampled = 0, sample_bad = 0;
    cr_assert_eq(hv_object_prepare(r, NULL), HV_OK);
    const int32_t *org = hv_volume_leaf_origins(v);
    hv_transform xf = hv_volume_get_transform(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned n = 0; n < HV_LEAF_SIZE; n += 7) {
            if (!HV_BIT_GET(hv_volume_leaf_mask(v, l), n)) continue;
            int32_t i = org[3 * l] + (int32_t)(n >> 6), j = org[3 * l + 1] + (int32_t)((n >> 3) & 7),
                    k = org[3 * l + 2] + (int32_t)(n & 7);
            double p[3] = {xf.origin[0] + i * xf.voxel[0], xf.origin[1] + j * xf.voxel[1], xf.origin[2] + k * xf.voxel[2]},
                   f[3];
            int inside;
            hv_object_sample(r, p, &inside, f);
            cr_assert(inside);
            ++sampled;
            for (int m = 0; m < 3; ++m) {
                float x = hv_accessor_float(&aa, ga[m], i, j, k);
                if (fabsf(x - hv_accessor_float(&ab, gb[m], i, j, k)) > 1e-6f) ++diff;
                if (fabs(f[m] - x) > 2e-3) ++sample_bad;
            }
        }
    cr_assert_gt(sampled, 1000);
    cr_assert_eq(diff, 0, "%ld values differ after the round trip", diff);
    cr_assert_eq(sample_bad, 0, "%ld sampled values differ from the grid", sample_bad);
    hv_volume_destroy(again);
    hv_object_destroy(r);
    hv_volume_destroy(back);
    hv_volume_destroy(v);
    hv_object_destroy(u);
    hv_ags_release(g3);
    hv_frf_release(contour);
    free_two(&w);
}

/* issue 17: a contour feature of the model's own occupancy stores no float grid: its field is
 * recomputed from the occupancy on load, and gives the fractions a model that stored the field
 * (as hovox wrote them before) gives, exactly, at voxel centres and between them. */
Test(model, contour_field_is_recomputed_not_stored, .timeout = 120)
{
    two w;
    two_spheres(&w);
    hv_frf *contour;
    cr_assert_eq(hv_frf_contour(w.v2, "occupancy", &contour), HV_OK);
    double ms[3] = {0, 0, 1}, me[3] = {1, 0, 0};
    hv_ags *g = make_ags(contour, 0.5, 3, 0, "sin(d/dg*pi/2)", ms, me);
    hv_object *o;
    cr_assert_eq(hv_object_create(w.v2, "occupancy", 3, &o), HV_OK);
    cr_assert_eq(hv_object_add_ags(o, g), HV_OK);
    hv_volume *v;
    cr_assert_eq(hv_object_evaluate(o, w.t, 0, NULL, &v), HV_OK, "%s", hv_last_error());
    cr_assert_lt(hv_volume_grid_find(v, "distance.0"), 0, "the contour's field is stored");
    json_t *doc;
    cr_assert_eq(hv_schema_doc_read(v, HV_DOC_OBJECT, &doc), HV_OK);
    json_t *f0 = json_array_get(json_object_get(doc, "features"), 0);
    cr_assert_str_eq(json_string_value(json_object_get(f0, "kind")), "contour");
    cr_assert_str_eq(json_string_value(json_object_get(f0, "grid")), "occupancy");
    json_decref(doc);
    /* the model as the previous version wrote it: the float field and a "field" feature */
    hv_volume *old;
    cr_assert_eq(hv_volume_clone(v, &old), HV_OK);
    cr_assert_eq(hv_frf_store_field(contour, old, "distance.0"), HV_OK);
    cr_assert_eq(hv_object_to_doc(o, &doc), HV_OK);
    cr_assert_str_eq(json_string_value(json_object_get(json_array_get(json_object_get(doc, "features"), 0), "kind")), "field");
    cr_assert_eq(hv_schema_doc_write(old, HV_DOC_OBJECT, doc), HV_OK);
    const char *pn = t_tmpfile("contour_new.vdb"), *po = t_tmpfile("contour_old.vdb");
    cr_assert_eq(hv_volume_save(v, pn), HV_OK);
    cr_assert_eq(hv_volume_save(old, po), HV_OK);
    FILE *fn = fopen(pn, "rb"), *fo = fopen(po, "rb");
    fseek(fn, 0, SEEK_END);
    fseek(fo, 0, SEEK_END);
    cr_assert_lt(ftell(fn), ftell(fo), "the new file is not smaller");
    fclose(fn);
    fclose(fo);
    hv_volume *bn, *bo;
    hv_object *rn, *ro;
    cr_assert_eq(hv_volume_load(pn, &bn), HV_OK);
    cr_assert_eq(hv_volume_load(po, &bo), HV_OK);
    cr_assert_eq(hv_object_from_model(bn, &rn), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_from_model(bo, &ro), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_prepare(rn, NULL), HV_OK);
    cr_assert_eq(hv_object_prepare(ro, NULL), HV_OK);
    /* points on a lattice offset from the voxels, across the boundary and outside */
    long n = 0, inside_n = 0, bad = 0;
    for (double x = -0.3; x <= 12.7; x += 0.37)
        for (double y = -8.6; y <= 8.6; y += 0.41)
            for (double z = -8.6; z <= 8.6; z += 0.43) {
                double p[3] = {x, y, z}, a[3], b[3];
                int ia, ib;
                hv_object_sample(rn, p, &ia, a);
                hv_object_sample(ro, p, &ib, b);
                ++n;
                inside_n += ia;
                if (ia != ib || a[0] != b[0] || a[1] != b[1] || a[2] != b[2]) ++bad;
            }
    cr_assert_gt(inside_n, 5000);
    cr_assert_eq(bad, 0, "%ld of %ld samples differ", bad, n);
    /* grading the loaded model again keeps it recomputed, not stored */
    hv_volume *again;
    cr_assert_eq(hv_object_evaluate(rn, w.t, 0, NULL, &again), HV_OK, "%s", hv_last_error());
    cr_assert_lt(hv_volume_grid_find(again, "distance.0"), 0);
    hv_volume_destroy(again);
    hv_object_destroy(rn);
    hv_object_destroy(ro);
    hv_volume_destroy(bn);
    hv_volume_destroy(bo);
    hv_volume_destroy(old);
    hv_volume_destroy(v);
    hv_object_destroy(o);
    hv_ags_release(g);
    hv_frf_release(contour);
    free_two(&w);
}
