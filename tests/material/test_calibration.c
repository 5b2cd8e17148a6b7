/* tests/material/test_calibration.c - units, calibration tables and grading to property targets
 * (issue 18): the inverse of the piecewise-linear table against the table itself, bad tables
 * refused with the first bad line, and a linear modulus ramp through a non-linear table checked
 * voxel by voxel against the target evaluated here from the analytic distance. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/material.h"
#include "hovox/profile.h"
#include "hovox/voxelize.h"
#include "support/support.h"

/* A stiffness curve of a rigid/rubber-like pair: near the rubber for most of the path, then a
 * jump (values in MPa; not linear in t, as PolyJet digital materials are not). */
static const char *k_csv = "# rigid/rubber-like blend, tensile modulus\n"
                           "t,youngs_modulus[MPa]\n"
                           "0,0.6\n0.1,0.9\n0.2,1.5\n0.3,2.6\n0.4,4.8\n0.5,9.5\n"
                           "0.6,20\n0.7,60\n0.8,250\n0.9,900\n1,2000\n";

static hv_calibration *table(void)
{
    hv_calibration *c = NULL;
    cr_assert_eq(hv_calibration_parse(k_csv, strlen(k_csv), "cal.csv", &c), HV_OK, "%s", hv_last_error());
    return c;
}

Test(calibration, parses_header_unit_and_rows)
{
    hv_calibration *c = table();
    cr_assert_str_eq(hv_calibration_property(c), "youngs_modulus");
    cr_assert_str_eq(hv_calibration_unit(c), "MPa");
    cr_assert_eq(hv_calibration_rows(c), 11);
    double lo, hi;
    hv_calibration_range(c, &lo, &hi);
    cr_assert_eq(lo, 0.6);
    cr_assert_eq(hi, 2000);
    cr_assert_eq(hv_calibration_eval(c, 0.75), 155); /* halfway between 60 and 250 */
    cr_assert(isnan(hv_calibration_eval(c, 1.5)));
    hv_calibration_release(c);
}

/* table(inverse(table(t))) == table(t) within 1e-12 relative, increasing and decreasing */
Test(calibration, inverse_reproduces_the_table)
{
    hv_calibration *inc = table(), *dec;
    double t[5] = {0, 0.2, 0.5, 0.9, 1}, v[5] = {85, 80, 62, 45, 40}; /* Shore A, soft at t = 1 */
    cr_assert_eq(hv_calibration_create("shore_hardness", "ShoreA", t, v, 5, &dec), HV_OK, "%s", hv_last_error());
    hv_calibration *cs[2] = {inc, dec};
    srand(18);
    double worst = 0;
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < 100000; ++i) {
            double u = (double)rand() / RAND_MAX, want = hv_calibration_eval(cs[k], u), back;
            cr_assert_eq(hv_calibration_invert(cs[k], want, &back), HV_OK, "%s", hv_last_error());
            double got = hv_calibration_eval(cs[k], back), rel = fabs(got - want) / fabs(want);
            worst = fmax(worst, rel);
            cr_assert(rel <= 1e-12, "t = %.17g: table %.17g, table(inverse) %.17g", u, want, got);
            cr_assert(fabs(back - u) <= 1e-9, "t = %.17g came back as %.17g", u, back);
        }
    /* every row exactly */
    for (int i = 0; i < 11; ++i) {
        double ti, vi, back;
        hv_calibration_row(inc, i, &ti, &vi);
        cr_assert_eq(hv_calibration_invert(inc, vi, &back), HV_OK);
        cr_assert_eq(back, ti);
    }
    cr_assert_eq(hv_calibration_invert(inc, 3000, &t[0]), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "youngs_modulus 3000 MPa is outside the calibration's range [0.6, 2000] MPa");
    hv_calibration_release(inc);
    hv_calibration_release(dec);
}

static void bad(const char *text, const char *message)
{
    hv_calibration *c = (hv_calibration *)1;
    cr_assert_eq(hv_calibration_parse(text, strlen(text), "cal.csv", &c), HV_ERR_BAD_INPUT, "accepted: %s", text);
    cr_assert_null(c);
    cr_assert_str_eq(hv_last_error(), message);
}

Test(calibration, bad_tables_name_the_first_bad_line)
{
    bad("t,youngs_modulus[MPa]\n0,1\n0.5,3\n0.7,2\n1,4\n",
        "cal.csv: line 4: youngs_modulus 2 is not greater than line 3's (3): the values must be strictly monotone");
    bad("t,E\n0,5\n0.5,3\n0.6,3\n", "cal.csv: line 4: E 3 is not less than line 3's (3): the values must be strictly "
                                   "monotone");
    bad("t,E\n0,1\n0.5,nan\n1,3\n", "cal.csv: line 3: E 'nan' is not a finite number");
    bad("", "cal.csv: empty: no header line 't,<property>[<unit>]'");
    bad("# only a comment\n\n", "cal.csv: empty: no header line 't,<property>[<unit>]'");
    bad("t,E[MPa]\n", "cal.csv: line 1: a header and no rows (at least 2 are needed)");
    bad("fraction.A,E\n0,1\n1,2\n", "cal.csv: line 1: header 'fraction.A,E' is not 't,<property>[<unit>]' "
                                    "(property: 1-64 characters of [A-Za-z0-9_-]; unit: at most 32 bytes)");
    bad("t,E\n0,1\n", "cal.csv: needs at least 2 rows (got 1)");
    bad("t,E\n0,1\n1.5,2\n", "cal.csv: line 3: t = 1.5 is outside [0, 1]");
    bad("t,E\n0.5,1\n0.5,2\n", "cal.csv: line 3: t = 0.5 is not greater than line 2's (0.5)");
    bad("t,E\n0,1,2\n", "cal.csv: line 2: expected 2 comma-separated fields, got '0,1,2'");
}

Test(calibration, quantities_convert_units_or_are_refused)
{
    double v;
    cr_assert_eq(hv_quantity_parse("2GPa", "MPa", "Ps", &v), HV_OK, "%s", hv_last_error());
    cr_assert_eq(v, 2000);
    cr_assert_eq(hv_quantity_parse("5 MPa", "Pa", "Pe", &v), HV_OK);
    cr_assert_eq(v, 5e6);
    cr_assert_eq(hv_quantity_parse("1.18g/cm^3", "kg/m^3", "Ps", &v), HV_OK);
    cr_assert_float_eq(v, 1180, 1e-9);
    cr_assert_eq(hv_quantity_parse("85ShoreA", "ShoreA", "Ps", &v), HV_OK);
    cr_assert_eq(v, 85);
    cr_assert_eq(hv_quantity_parse("7", "MPa", "Ps", &v), HV_OK);
    cr_assert_eq(v, 7);
    cr_assert_eq(hv_quantity_parse("85ShoreA", "MPa", "Ps", &v), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "Ps = '85ShoreA': unit ShoreA does not convert to MPa");
    cr_assert_eq(hv_quantity_parse("2GPa", "", "Pe", &v), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "Pe = '2GPa': unit GPa does not convert to the table's (it has no unit)");
    cr_assert_eq(hv_quantity_parse("stiff", "MPa", "Ps", &v), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "Ps = 'stiff' is not a number with an optional unit");
}

/* ---- grading to property targets ------------------------------------------------------------ */

typedef struct graded {
    hv_volume *model, *out;
    hv_material_table *mats;
    hv_ags *src;
} graded;

/* A 40 x 10 x 10 mm bar graded along x from the plane x = 0: the property from Ps at d- to Pe
 * at d- + dg. */
static void grade_bar(graded *g, const char *ps, const char *pe, int log, double dn, double dg)
{
    double lo[3] = {0, 0, 0}, hi[3] = {40, 10, 10};
    hv_mesh *mesh;
    cr_assert_eq(hv_generate_box(lo, hi, &mesh), HV_OK);
    hv_voxelize_options vo;
    hv_voxelize_options_init(&vo);
    vo.voxel_size[0] = vo.voxel_size[1] = vo.voxel_size[2] = 0.5;
    cr_assert_eq(hv_voxelize(mesh, &vo, &g->model), HV_OK, "%s", hv_last_error());
    hv_mesh_destroy(mesh);
    cr_assert_eq(hv_material_table_create(&g->mats), HV_OK);
    cr_assert_eq(hv_material_add(g->mats, "rigid", NULL, NULL), HV_OK);
    cr_assert_eq(hv_material_add(g->mats, "rubber", NULL, NULL), HV_OK);
    double p0[3] = {0, 0, 0}, nx[3] = {1, 0, 0};
    hv_frf *plane;
    cr_assert_eq(hv_frf_plane(p0, nx, &plane), HV_OK);
    const char *path = t_tmpfile("cal.csv");
    FILE *fp = fopen(path, "w");
    fputs(k_csv, fp);
    fclose(fp);
    hv_ags_options o;
    hv_ags_options_init(&o);
    o.d_neg = dn;
    o.d_grad = dg;
    /* the table's t runs from Ms to Me: Ms = rubber, Me = rigid, so t = 0 is soft as in k_csv */
    o.ms[0] = 0, o.ms[1] = 1, o.me[0] = 1, o.me[1] = 0;
    o.nms = o.nme = 2;
    o.calibration = path;
    o.property_grading = ps ? "youngs_modulus" : NULL; /* no targets: fractions by f = d/dg */
    o.ps = ps;
    o.pe = pe;
    o.log = log;
    cr_assert_eq(hv_ags_from_options(plane, &o, NULL, &g->src), HV_OK, "%s", hv_last_error());
    hv_frf_release(plane);
    hv_object *obj;
    cr_assert_eq(hv_object_create(g->model, "occupancy", 2, &obj), HV_OK);
    cr_assert_eq(hv_object_add_ags(obj, g->src), HV_OK);
    cr_assert_eq(hv_object_evaluate(obj, g->mats, 0, NULL, &g->out), HV_OK, "%s", hv_last_error());
    hv_object_destroy(obj);
}

static void graded_free(graded *g)
{
    hv_ags_release(g->src);
    hv_volume_destroy(g->out);
    hv_volume_destroy(g->model);
    hv_material_table_destroy(g->mats);
}

/* Every occupied voxel: the modulus its composition has by the table (t recovered from the
 * fractions, independent of hovox's inverse) against the target at the voxel centre's exact
 * distance. Returns the worst relative error. */
static double worst_voxel_error(const graded *g, double ps, double pe, int log, double dn, double dg,
                                const hv_calibration *c)
{
    hv_transform xf = hv_volume_get_transform(g->out);
    int rigid = hv_material_grid(g->out, g->mats, 0);
    const int32_t *org = hv_volume_leaf_origins(g->out);
    double worst = 0;
    size_t n = 0;
    for (size_t l = 0; l < hv_volume_leaf_count(g->out); ++l) {
        const uint64_t *mask = hv_volume_leaf_mask(g->out, l);
        for (unsigned q = 0; q < HV_LEAF_SIZE; ++q) {
            if (!HV_BIT_GET(mask, q)) continue;
            double x = xf.origin[0] + (org[3 * l] + (int)(q >> 6)) * xf.voxel[0];
            double f = fmin(fmax((fabs(x) - dn) / dg, 0.0), 1.0);
            double want = log ? ps * pow(pe / ps, f) : ps + f * (pe - ps);
            double t = hv_volume_leaf_float_c(g->out, rigid, l)[q]; /* Ms = rubber, Me = rigid: t = rigid fraction */
            double got = hv_calibration_eval(c, t);
            worst = fmax(worst, fabs(got - want) / want);
            ++n;
        }
    }
    cr_assert_gt(n, 1000);
    return worst;
}

Test(calibration, linear_modulus_ramp_through_a_nonlinear_table)
{
    graded g;
    grade_bar(&g, "5MPa", "2GPa", 0, 5, 30);
    double worst = worst_voxel_error(&g, 5, 2000, 0, 5, 30, hv_ags_calibration(g.src));
    cr_assert(worst < 0.01, "worst modulus error %.3g%%", 100 * worst);
    /* the same fraction ramp without the table would be far off: the check can fail */
    double t_mid = 0.5, lin = hv_calibration_eval(hv_ags_calibration(g.src), t_mid), want = 5 + 0.5 * (2000 - 5);
    cr_assert_gt(fabs(lin - want) / want, 0.5);
    graded_free(&g);
}

Test(calibration, log_ramp_and_decreasing_targets)
{
    graded g;
    grade_bar(&g, "2GPa", "0.8MPa", 1, 2, 34);
    double worst = worst_voxel_error(&g, 2000, 0.8, 1, 2, 34, hv_ags_calibration(g.src));
    cr_assert(worst < 0.01, "worst modulus error %.3g%%", 100 * worst);
    hv_property_target t;
    cr_assert(hv_ags_target(g.src, &t));
    cr_assert_str_eq(t.property, "youngs_modulus");
    cr_assert_eq(t.ps, 2000);
    cr_assert_float_eq(t.pe, 0.8, 1e-12);
    cr_assert(t.log);
    graded_free(&g);
}

/* The model keeps the table and the targets: the rebuilt source has both, and evaluates the same. */
Test(calibration, stored_in_the_model_and_rebuilt)
{
    graded g;
    grade_bar(&g, "5MPa", "2GPa", 0, 5, 30);
    const char *path = t_tmpfile("cal_model.vdb");
    cr_assert_eq(hv_volume_save(g.out, path), HV_OK, "%s", hv_last_error());
    hv_volume *back;
    cr_assert_eq(hv_volume_load(path, &back), HV_OK, "%s", hv_last_error());
    hv_object *obj;
    cr_assert_eq(hv_object_from_model(back, &obj), HV_OK, "%s", hv_last_error());
    hv_volume *again;
    cr_assert_eq(hv_object_evaluate(obj, g.mats, 0, NULL, &again), HV_OK, "%s", hv_last_error());
    const char *doc = hv_volume_meta_string(back, "hovox.object.json");
    cr_assert_not_null(doc);
    cr_assert(strstr(doc, "\"calibration\""), "%s", doc);
    cr_assert(strstr(doc, "\"target\""), "%s", doc);
    double worst = worst_voxel_error(&(graded){g.model, again, g.mats, g.src}, 5, 2000, 0, 5, 30,
                                     hv_ags_calibration(g.src));
    cr_assert(worst < 0.01, "rebuilt: worst modulus error %.3g%%", 100 * worst);
    hv_volume_destroy(again);
    hv_object_destroy(obj);
    hv_volume_destroy(back);
    graded_free(&g);
}

Test(calibration, targets_outside_the_table_are_refused_with_the_range)
{
    double p0[3] = {0, 0, 0}, nx[3] = {1, 0, 0};
    hv_frf *plane;
    cr_assert_eq(hv_frf_plane(p0, nx, &plane), HV_OK);
    hv_calibration *c = table();
    hv_ags_options o;
    hv_ags_options_init(&o);
    o.d_grad = 10;
    o.ms[0] = 0, o.ms[1] = 1, o.me[0] = 1, o.me[1] = 0;
    o.nms = o.nme = 2;
    o.calibration_table = c;
    o.property_grading = "youngs_modulus";
    o.ps = "3GPa";
    o.pe = "5MPa";
    hv_ags *a = NULL;
    cr_assert_eq(hv_ags_from_options(plane, &o, NULL, &a), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(),
                     "Ps = 3000 MPa is outside the calibration table's youngs_modulus range [0.6, 2000] MPa");
    o.ps = "2GPa";
    o.pe = "40ShoreA";
    cr_assert_eq(hv_ags_from_options(plane, &o, NULL, &a), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "Pe = '40ShoreA': unit ShoreA does not convert to MPa");
    o.pe = "5MPa";
    o.property_grading = "density";
    cr_assert_eq(hv_ags_from_options(plane, &o, NULL, &a), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "property targets for 'density', but the calibration table is for "
                                      "'youngs_modulus'");
    o.property_grading = "youngs_modulus";
    o.calibration_table = NULL;
    cr_assert_eq(hv_ags_from_options(plane, &o, NULL, &a), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "grading to youngs_modulus targets needs a calibration table");
    cr_assert_null(a);
    hv_calibration_release(c);
    hv_frf_release(plane);
}

/* ---- the property along a profile ------------------------------------------------------------ */

/* k_csv's rows, interpolated here: the reference does not use hovox's table code */
static double k_table(double t)
{
    static const double ts[11] = {0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1};
    static const double vs[11] = {0.6, 0.9, 1.5, 2.6, 4.8, 9.5, 20, 60, 250, 900, 2000};
    int i = 0;
    while (i < 9 && t > ts[i + 1]) ++i;
    return vs[i] + (t - ts[i]) / (ts[i + 1] - ts[i]) * (vs[i + 1] - vs[i]);
}

/* A fraction ramp (f = d/dg, no targets) with the table attached: at the voxel centres of a line
 * along x the profile's modulus is the table at the t the grading gives there, t = clamp((x - 5)
 * / 30, 0, 1), within the 32-bit storage of the fractions; NAN outside the object; the CSV has the
 * column with its unit. */
Test(calibration, profile_shows_the_property_from_the_table)
{
    graded g;
    grade_bar(&g, NULL, NULL, 0, 5, 30);
    hv_profile_options o;
    hv_profile_options_init(&o);
    o.from[0] = -0.75, o.from[1] = 5.25, o.from[2] = 5.25; /* 2 samples at the boundary, 80 voxel centres */
    o.to[0] = 39.75, o.to[1] = 5.25, o.to[2] = 5.25;
    o.samples = 82;
    o.property = "youngs_modulus";
    hv_profile *p;
    cr_assert_eq(hv_profile_sample_with(g.out, &o, &p), HV_OK, "%s", hv_last_error());
    const char *unit;
    cr_assert_str_eq(hv_profile_property(p, &unit), "youngs_modulus");
    cr_assert_str_eq(unit, "MPa");
    double worst = 0, lin_worst = 0;
    for (int i = 0; i < 82; ++i) {
        double xyz[3];
        hv_profile_position(p, i, xyz);
        double v = hv_profile_property_value(p, i);
        if (i == 0) cr_assert(!hv_profile_inside(p, i) && isnan(v), "sample %d at x = %g: %g", i, xyz[0], v);
        if (i < 2) continue; /* x = -0.25: the surface voxels reach there */
        cr_assert(hv_profile_inside(p, i), "x = %g", xyz[0]);
        double t = fmin(fmax((xyz[0] - 5) / 30, 0.0), 1.0), want = k_table(t);
        worst = fmax(worst, fabs(v - want) / want);
        /* the modulus a linear blend of the end values would give: far off, so the check can fail */
        lin_worst = fmax(lin_worst, fabs(0.6 + t * (2000 - 0.6) - want) / want);
    }
    cr_assert(worst < 1e-5, "worst relative error %.3g", worst);
    cr_assert_gt(lin_worst, 1.0);
    const char *csv = t_tmpfile("prop_profile.csv");
    cr_assert_eq(hv_profile_write_csv(p, csv), HV_OK, "%s", hv_last_error());
    FILE *fp = fopen(csv, "r");
    char line[256];
    cr_assert(fgets(line, sizeof line, fp));
    cr_assert_str_eq(line, "t,x,y,z,inside,rigid,rubber,youngs_modulus[MPa]\n");
    cr_assert(fgets(line, sizeof line, fp));
    cr_assert_str_eq(line, "0,-0.75,5.25,5.25,0,0,0,nan\n");
    fclose(fp);
    hv_profile_destroy(p);
    graded_free(&g);
}

/* No table for the property, another property's table, two different tables: one message each. */
Test(calibration, profile_property_refusals)
{
    graded g;
    grade_bar(&g, NULL, NULL, 0, 5, 30);
    hv_profile_options o;
    hv_profile_options_init(&o);
    o.from[0] = 1, o.to[0] = 30;
    o.from[1] = o.to[1] = o.from[2] = o.to[2] = 5;
    o.property = "shore_hardness";
    hv_profile *p = (hv_profile *)&o;
    cr_assert_eq(hv_profile_sample_with(g.out, &o, &p), HV_ERR_NOT_FOUND);
    cr_assert_null(p);
    cr_assert_str_eq(hv_last_error(), "no calibration table for shore_hardness in the model's grading definition "
                                      "(it has tables for youngs_modulus[MPa])");
    /* a model graded without tables */
    hv_object *obj;
    cr_assert_eq(hv_object_create(g.model, "occupancy", 2, &obj), HV_OK);
    double p0[3] = {0, 0, 0}, nx[3] = {1, 0, 0}, ms[2] = {0, 1}, me[2] = {1, 0};
    hv_frf *plane;
    cr_assert_eq(hv_frf_plane(p0, nx, &plane), HV_OK);
    hv_ags_desc d = {plane, 5, 30, 5, NULL, ms, me, 2, "plain"};
    hv_dfn *lin;
    cr_assert_eq(hv_dfn_linear(1.0 / 30, 0, &lin), HV_OK);
    d.f = lin;
    hv_ags *plain;
    cr_assert_eq(hv_ags_create(&d, &plain), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_add_ags(obj, plain), HV_OK);
    hv_volume *v;
    cr_assert_eq(hv_object_evaluate(obj, g.mats, 0, NULL, &v), HV_OK, "%s", hv_last_error());
    o.property = "youngs_modulus";
    cr_assert_eq(hv_profile_sample_with(v, &o, &p), HV_ERR_NOT_FOUND);
    cr_assert_str_eq(hv_last_error(), "no calibration table for youngs_modulus in the model's grading definition "
                                      "(it has no calibration tables)");
    hv_volume_destroy(v);
    /* two sources with different tables for the same property */
    double t2[2] = {0, 1}, v2[2] = {1, 1000};
    hv_calibration *c2;
    cr_assert_eq(hv_calibration_create("youngs_modulus", "MPa", t2, v2, 2, &c2), HV_OK);
    hv_ags *other;
    d.name = "other";
    d.d_neg = 20;
    cr_assert_eq(hv_ags_create_calibrated(&d, c2, NULL, &other), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_delete_ags(obj, plain), HV_OK);
    cr_assert_eq(hv_object_add_ags(obj, g.src), HV_OK);
    cr_assert_eq(hv_object_add_ags(obj, other), HV_OK);
    cr_assert_eq(hv_object_evaluate(obj, g.mats, 0, NULL, &v), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_profile_sample_with(v, &o, &p), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "the model's grading definition has different calibration tables for "
                                      "youngs_modulus (sources 1, 2 'other'): its profile needs exactly one");
    hv_volume_destroy(v);
    hv_calibration_release(c2);
    hv_ags_release(other);
    hv_ags_release(plain);
    hv_dfn_destroy(lin);
    hv_frf_release(plane);
    hv_object_destroy(obj);
    graded_free(&g);
}
