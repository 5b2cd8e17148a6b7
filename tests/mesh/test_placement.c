/* tests/mesh/test_placement.c - units and transforms (hovox/placement.h): the matrix against
 * rotations computed here another way (unit quaternions), the documented order of the steps,
 * exact quarter turns, the options as every front end gives them, and the size warning. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/placement.h"
#include "support/support.h"

static void apply(const double m[12], const double p[3], double q[3])
{
    for (int r = 0; r < 3; ++r) q[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
}

/* v rotated by `deg` about the axis k, as the quaternion product q v q* (an independent route). */
static void quat_rotate(const double k_in[3], double deg, const double v[3], double out[3])
{
    double n = sqrt(k_in[0] * k_in[0] + k_in[1] * k_in[1] + k_in[2] * k_in[2]);
    double h = deg * M_PI / 360.0, s = sin(h);
    double w = cos(h), x = s * k_in[0] / n, y = s * k_in[1] / n, z = s * k_in[2] / n;
    /* t = q v */
    double tw = -x * v[0] - y * v[1] - z * v[2];
    double tx = w * v[0] + y * v[2] - z * v[1];
    double ty = w * v[1] + z * v[0] - x * v[2];
    double tz = w * v[2] + x * v[1] - y * v[0];
    /* out = t q* */
    out[0] = -tw * x + tx * w - ty * z + tz * y;
    out[1] = -tw * y + ty * w - tz * x + tx * z;
    out[2] = -tw * z + tz * w - tx * y + ty * x;
}

static void set(hv_placement *p, const char *key, const char *text)
{
    const hv_option *o = hv_option_find(hv_placement_option_set(), key);
    cr_assert(o, "%s", key);
    cr_assert_eq(hv_option_set_text(o, p, text), HV_OK, "%s %s: %s", key, text, hv_last_error());
}

Test(placement, rotation_about_any_axis_matches_quaternions)
{
    const char *rot[] = {"30@1,1,0", "-75.5@0.2,-3,1", "123@0,0,-2", "x:17", "y:-200", "z:359"};
    const double axes[][3] = {{1, 1, 0}, {0.2, -3, 1}, {0, 0, -2}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const double deg[] = {30, -75.5, 123, 17, -200, 359};
    const double pts[][3] = {{1, 2, 3}, {-4, 0.5, 7}, {0, 0, 1}, {10, -10, 0.25}};
    for (size_t i = 0; i < 6; ++i) {
        hv_placement p;
        hv_placement_init(&p);
        set(&p, "rotate", rot[i]);
        double m[12];
        cr_assert_eq(hv_placement_matrix(&p, m), HV_OK);
        for (size_t k = 0; k < 4; ++k) {
            double a[3], b[3];
            apply(m, pts[k], a);
            quat_rotate(axes[i], deg[i], pts[k], b);
            for (int r = 0; r < 3; ++r) cr_assert_float_eq(a[r], b[r], 1e-12, "%s point %zu axis %d", rot[i], k, r);
        }
    }
}

Test(placement, quarter_turns_are_exact_and_up_y_is_x90)
{
    hv_placement p, q;
    hv_placement_init(&p);
    hv_placement_init(&q);
    set(&p, "up", "y");
    set(&q, "rotate", "x:90");
    double a[12], b[12];
    cr_assert_eq(hv_placement_matrix(&p, a), HV_OK);
    cr_assert_eq(hv_placement_matrix(&q, b), HV_OK);
    cr_assert_eq(memcmp(a, b, sizeof a), 0);
    /* a Y-up point (x, up, toward the viewer) goes to (x, -toward, up), exactly */
    const double v[3] = {1.25, 7, 3}, want[3] = {1.25, -3, 7};
    double w[3];
    apply(a, v, w);
    for (int r = 0; r < 3; ++r) cr_assert_eq(w[r], want[r]);
    /* four quarter turns about any coordinate axis: the identity, bit for bit */
    const char *axes[] = {"x:90", "y:-90", "z:270"};
    for (int k = 0; k < 3; ++k) {
        hv_placement r;
        hv_placement_init(&r);
        for (int t = 0; t < 4; ++t) set(&r, "rotate", axes[k]);
        double m[12];
        cr_assert_eq(hv_placement_matrix(&r, m), HV_OK);
        const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
        for (int e = 0; e < 12; ++e) cr_assert_eq(m[e], id[e], "%s entry %d", axes[k], e);
    }
}

Test(placement, steps_compose_in_the_documented_order)
{
    /* given in the "wrong" order on purpose: the result is unit, up, scale, rotations, translate */
    hv_placement p;
    hv_placement_init(&p);
    set(&p, "translate", "100,200,300");
    set(&p, "rotate", "z:90");
    set(&p, "rotate", "x:90");
    set(&p, "scale", "2,3,4");
    set(&p, "up", "y");
    set(&p, "unit", "cm");
    double m[12];
    cr_assert_eq(hv_placement_matrix(&p, m), HV_OK);
    const double v[3] = {1, 2, 3};
    /* by hand: cm (10,20,30); up y (10,-30,20); scale (20,-90,80); z:90 (90,20,80);
     * x:90 (90,-80,20); translate (190,120,320) */
    const double want[3] = {190, 120, 320};
    double w[3];
    apply(m, v, w);
    for (int r = 0; r < 3; ++r) cr_assert_float_eq(w[r], want[r], 1e-9, "axis %d: %g", r, w[r]);
    /* the rotations do not commute: the other order gives another point */
    hv_placement q;
    hv_placement_init(&q);
    set(&q, "rotate", "x:90");
    set(&q, "rotate", "z:90");
    double mq[12], u[3];
    cr_assert_eq(hv_placement_matrix(&q, mq), HV_OK);
    apply(mq, v, u);
    cr_assert(fabs(u[0] - 3) < 1e-12 && fabs(u[1] - 1) < 1e-12 && fabs(u[2] - 2) < 1e-12, "%g %g %g", u[0], u[1], u[2]);
}

Test(placement, description_reads_back_to_the_same_map)
{
    hv_placement p;
    hv_placement_init(&p);
    set(&p, "unit", "in");
    set(&p, "up", "y");
    set(&p, "scale", "1.5,1.5,2");
    set(&p, "rotate", "x:90");
    set(&p, "rotate", "12.5@1,-2,0.5");
    set(&p, "translate", "-1,0,2.75");
    char text[512];
    cr_assert_str_eq(hv_placement_describe(&p, text, sizeof text),
                     "unit in, up y, scale 1.5,1.5,2, rotate x:90, rotate 12.5@1,-2,0.5, translate -1,0,2.75");
    hv_placement q;
    hv_placement_init(&q);
    char *save, *copy = strdup(text);
    for (char *item = strtok_r(copy, ",", &save); item;) { /* "key value" items, values may hold commas */
        char key[32], value[128];
        cr_assert_eq(sscanf(item, " %31s %127s", key, value), 2, "%s", item);
        char *next = strtok_r(NULL, ",", &save);
        while (next && !strchr(next, ' ')) { /* "1.5" of "1.5,1.5,2": the value goes on */
            strncat(value, ",", sizeof value - strlen(value) - 1);
            strncat(value, next, sizeof value - strlen(value) - 1);
            next = strtok_r(NULL, ",", &save);
        }
        set(&q, key, value);
        item = next;
    }
    free(copy);
    double a[12], b[12];
    cr_assert_eq(hv_placement_matrix(&p, a), HV_OK);
    cr_assert_eq(hv_placement_matrix(&q, b), HV_OK);
    cr_assert_eq(memcmp(a, b, sizeof a), 0);
    hv_placement_init(&q);
    cr_assert_str_eq(hv_placement_describe(&q, text, sizeof text), "");
    cr_assert_eq(hv_placement_given(&q), 0);
}

Test(placement, lists_of_numbers_as_lua_and_json_give_them)
{
    hv_optargs args;
    hv_placement p;
    hv_optargs_begin(&args, hv_placement_option_set(), &p);
    const double one[1] = {2}, three[3] = {1, 2, 3};
    hv_opt_value s = {HV_VALUE_NUMBERS, NULL, one, 1, 0}, t = {HV_VALUE_NUMBERS, NULL, three, 3, 0};
    cr_assert_eq(hv_optargs_set(&args, "scale", &s), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_optargs_set(&args, "translate", &t), HV_OK, "%s", hv_last_error());
    cr_assert_neq(hv_optargs_set(&args, "translate", &t), HV_OK); /* not repeatable */
    hv_opt_value r1 = {HV_VALUE_TEXT, "z:90", NULL, 0, 0}, r2 = {HV_VALUE_TEXT, "x:180", NULL, 0, 0};
    cr_assert_eq(hv_optargs_set(&args, "rotate", &r1), HV_OK);
    cr_assert_eq(hv_optargs_set(&args, "rotate", &r2), HV_OK); /* repeatable */
    cr_assert_eq(hv_optargs_finish(&args), HV_OK);
    cr_assert_eq(p.scale[0], 2);
    cr_assert_eq(p.scale[2], 2);
    cr_assert_eq(p.nrotate, 2);
    hv_opt_value bad = {HV_VALUE_NUMBERS, NULL, three, 2, 0};
    cr_assert_eq(hv_optargs_set(&args, "scale", &bad), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "scale"), "%s", hv_last_error());
}

Test(placement, mesh_moves_and_a_mirror_stays_outward)
{
    hv_mesh *m = t_cube_mesh(0, 10);
    double v0 = hv_mesh_get_report(m)->volume;
    hv_placement p;
    hv_placement_init(&p);
    set(&p, "scale", "-1,2,1");
    set(&p, "rotate", "z:90");
    set(&p, "translate", "5,0,-1");
    cr_assert_eq(hv_placement_apply(&p, &m), HV_OK, "%s", hv_last_error());
    const hv_mesh_report *r = hv_mesh_get_report(m);
    /* x in [-10,0], y in [0,20] -> z:90 -> x in [-20,0], y in [-10,0] -> +5,0,-1 */
    const double lo[3] = {-15, -10, -1}, hi[3] = {5, 0, 9};
    for (int k = 0; k < 3; ++k) {
        cr_assert_float_eq(r->bbox_min[k], lo[k], 1e-6, "min %d: %g", k, r->bbox_min[k]);
        cr_assert_float_eq(r->bbox_max[k], hi[k], 1e-6, "max %d: %g", k, r->bbox_max[k]);
    }
    cr_assert_float_eq(r->volume, 2 * v0, 1e-6, "%g", r->volume); /* positive: still outward */
    cr_assert_eq(r->flipped_facets, 0);
    hv_mesh_destroy(m);
}

Test(placement, size_warning_names_the_likely_unit)
{
    hv_mesh *m = t_cube_mesh(0, 0.155); /* a part in metres */
    cr_assert_eq(hv_placement_size_warning(m, NULL), 1);
    cr_assert(strstr(hv_last_error(), "if its unit is metres, unit m makes it 155 mm across"), "%s", hv_last_error());
    hv_mesh_destroy(m);
    const double j750[3] = {490, 390, 200};
    m = t_cube_mesh(0, 30);
    cr_assert_eq(hv_placement_size_warning(m, j750), 0);
    hv_mesh_destroy(m);
    m = t_cube_mesh(0, 300); /* 300 mm cube: taller than 200 whichever way it lies */
    cr_assert_eq(hv_placement_size_warning(m, j750), 1);
    cr_assert(strstr(hv_last_error(), "larger than the build volume"), "%s", hv_last_error());
    hv_mesh_destroy(m);
    m = t_cube_mesh(0, 0.9); /* 0.9 in metres would not fit: inches */
    cr_assert_eq(hv_placement_size_warning(m, j750), 1);
    cr_assert(strstr(hv_last_error(), "unit in makes it 22.9 mm"), "%s", hv_last_error());
    hv_mesh_destroy(m);
}

Test(placement, singular_and_non_finite_maps_are_refused)
{
    hv_placement p;
    hv_placement_init(&p);
    p.scale[0] = 1, p.scale[1] = 0, p.scale[2] = 1; /* filled in C, past the parser */
    double m[12];
    cr_assert_eq(hv_placement_matrix(&p, m), HV_ERR_INVALID);
    hv_placement_init(&p);
    p.translate[1] = NAN;
    cr_assert_eq(hv_placement_matrix(&p, m), HV_ERR_INVALID);
    hv_placement_init(&p);
    p.nrotate = 1; /* a zero axis */
    cr_assert_eq(hv_placement_matrix(&p, m), HV_ERR_INVALID);
    hv_placement_init(&p);
    for (int i = 0; i < HV_PLACEMENT_MAX_ROTATIONS; ++i) set(&p, "rotate", "z:1");
    const hv_option *o = hv_option_find(hv_placement_option_set(), "rotate");
    cr_assert_eq(hv_option_set_text(o, &p, "z:1"), HV_ERR_INVALID);
    double mm;
    cr_assert_eq(hv_placement_unit_parse("inch", &mm), HV_OK);
    cr_assert_eq(mm, 25.4);
    cr_assert_eq(hv_placement_unit_parse("furlong", &mm), HV_ERR_INVALID);
}
