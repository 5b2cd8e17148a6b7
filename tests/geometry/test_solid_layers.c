/* tests/geometry/test_solid_layers.c - issue 28's checks: a Boolean reaches the print. A plate
 * 40 x 20 x 10 and a rod of radius 5 through it, voxelized at 0.25 mm, combined by Booleans and
 * cut by hv_layers_write without a mesh: every layer's object mask against the exact raster of
 * the analytic shape (pixel centres in the plate and the disc) has IoU >= 0.999, and the hole is
 * empty in every layer of the plate minus the rod. A plain model cut without its mesh gives the
 * same bytes as with it; another mesh is refused naming both, and nothing is written. A tray of the
 * Booleaned model alone (turned and not) keeps the hole too, IoU >= 0.999 per part and layer. */
#include <criterion/criterion.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/layers.h"
#include "hovox/material.h"
#include "hovox/solid.h"
#include "hovox/tray.h"
#include "support/support.h"

static hv_mesh *plate(void)
{
    double lo[3] = {0, 0, 0}, hi[3] = {40, 20, 10};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_box(lo, hi, &m), HV_OK, "%s", hv_last_error());
    return m;
}

/* 256 sides: within 4e-4 mm of the circle, a few pixels of a J750 layer */
static hv_mesh *rod(void)
{
    double base[3] = {20, 10, -1};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_cylinder(base, 2, 12, 5, 256, &m), HV_OK, "%s", hv_last_error());
    return m;
}

static hv_object *object_of(const hv_mesh *m) { return t_object_of(m, 0.25, 2); }

static hv_material_table *table(void)
{
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_parse("A,B", NULL, NULL, 0, &t), HV_OK, "%s", hv_last_error());
    return t;
}

static hv_volume *evaluate(hv_object *obj)
{
    hv_material_table *t = table();
    hv_volume *v = NULL;
    cr_assert_eq(hv_object_evaluate(obj, t, 0, NULL, &v), HV_OK, "%s", hv_last_error());
    hv_material_table_destroy(t);
    return v;
}

static int in_analytic(int op, double x, double y, double z)
{
    int p = x > 0 && x < 40 && y > 0 && y < 20 && z > 0 && z < 10;
    int r = hypot(x - 20, y - 10) < 5 && z > -1 && z < 11;
    switch (op) {
    case HV_OP_SUBTRACT: return p && !r;
    case HV_OP_UNITE: return p || r;
    case HV_OP_INTERSECT: return p && r;
    default: return p;
    }
}

/* Mask layers of `model` (no mesh) at J750 dpi and 0.5 mm layers; per layer IoU against the
 * analytic shape. Returns the smallest IoU; *hole_pixels counts object pixels well inside the
 * disc (d < 4.9) in layers inside the plate. */
static double cut_and_compare(const hv_volume *model, int op, const char *dir, long *hole_pixels, size_t *layers)
{
    hv_layers_options o;
    hv_layers_options_init(&o);
    o.mode = HV_LAYERS_MASK;
    o.layer_height = 0.5;
    hv_layers_report r;
    cr_assert_eq(hv_layers_write(NULL, model, dir, &o, NULL, &r), HV_OK, "%s", hv_last_error());
    double zmin = op == HV_OP_UNITE ? -1 : 0, worst = 1;
    *hole_pixels = 0;
    *layers = r.last - r.first;
    for (size_t i = r.first; i < r.last; ++i) {
        char path[4096];
        snprintf(path, sizeof path, "%s/layer-%05zu.png", dir, i);
        t_png im;
        t_png_load(path, &im);
        cr_assert_eq(im.w, r.width);
        double z = zmin + ((double)i + 0.5) * 0.5;
        long both = 0, either = 0;
        for (int row = 0; row < im.h; ++row)
            for (int c = 0; c < im.w; ++c) {
                double x = r.origin_mm[0] + (c + 0.5) * r.pixel_mm[0], y = r.origin_mm[1] + (row + 0.5) * r.pixel_mm[1];
                int got = im.px[(size_t)row * im.w + c] != 0, want = in_analytic(op, x, y, z);
                both += got && want;
                either += got || want;
                if (got && z > 0 && z < 10 && hypot(x - 20, y - 10) < 4.9) ++*hole_pixels;
            }
        free(im.px);
        double iou = either ? (double)both / (double)either : 1.0;
        if (iou < worst) worst = iou;
    }
    return worst;
}

Test(solid_layers, booleans_reach_the_print, .timeout = 240)
{
    hv_mesh *p = plate(), *r = rod();
    hv_object *op = object_of(p), *orod = object_of(r);
    int ops[3] = {HV_OP_SUBTRACT, HV_OP_UNITE, HV_OP_INTERSECT};
    size_t want_layers[3] = {20, 24, 20};
    for (int k = 0; k < 3; ++k) {
        hv_object *h = NULL;
        cr_assert_eq(hv_object_boolean(op, orod, (hv_bool_op)ops[k], &h), HV_OK, "%s", hv_last_error());
        hv_volume *v = evaluate(h);
        char dir[64];
        snprintf(dir, sizeof dir, "stack%d", k);
        long hole;
        size_t n;
        double iou = cut_and_compare(v, ops[k], t_tmpfile(dir), &hole, &n);
        cr_assert_eq(n, want_layers[k], "op %d: %zu layers", ops[k], n);
        cr_assert_geq(iou, 0.999, "op %d: worst layer IoU %.6f", ops[k], iou);
        if (ops[k] == HV_OP_SUBTRACT) cr_assert_eq(hole, 0, "the hole holds %ld object pixels", hole);
        hv_volume_destroy(v);
        hv_object_destroy(h);
    }
    hv_object_destroy(op);
    hv_object_destroy(orod);
    hv_mesh_destroy(p);
    hv_mesh_destroy(r);
}

/* every file of a stack directory, byte for byte */
static void same_stack(const char *a, const char *b)
{
    DIR *d = opendir(a);
    cr_assert_not_null(d);
    int files = 0;
    for (struct dirent *e; (e = readdir(d));) {
        if (e->d_name[0] == '.') continue;
        char pa[4096], pb[4096];
        snprintf(pa, sizeof pa, "%s/%s", a, e->d_name);
        snprintf(pb, sizeof pb, "%s/%s", b, e->d_name);
        size_t na, nb;
        char *da = t_slurp(pa, &na), *db = t_slurp(pb, &nb);
        cr_assert_not_null(db, "%s missing", pb);
        cr_assert(na == nb && memcmp(da, db, na) == 0, "%s differs", e->d_name);
        free(da);
        free(db);
        ++files;
    }
    closedir(d);
    cr_assert_gt(files, 3);
}

Test(solid_layers, a_plain_model_cuts_the_same_without_its_mesh, .timeout = 120)
{
    hv_mesh *p = plate(), *r = rod();
    hv_object *obj = object_of(p);
    hv_volume *v = evaluate(obj);
    hv_layers_options o;
    hv_layers_options_init(&o);
    o.dpi[0] = o.dpi[1] = 100;
    o.layer_height = 0.5;
    o.mesh_name = NULL;
    const char *with = t_tmpfile("with"), *without = t_tmpfile("without"), *other = t_tmpfile("other");
    cr_assert_eq(hv_layers_write(NULL, v, without, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_layers_write(p, v, with, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    same_stack(with, without);
    same_stack(without, with);
    o.mesh_name = "rod.stl";
    cr_assert_eq(hv_layers_write(r, v, other, &o, NULL, NULL), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "rod.stl differs from the mesh the model records"), "%s", hv_last_error());
    cr_assert_not(t_exists(other));
    hv_volume_destroy(v);
    hv_object_destroy(obj);
    hv_mesh_destroy(p);
    hv_mesh_destroy(r);
}

/* A tray of the plate minus the rod from the model alone (no mesh: the shape it records), once as
 * it is and once turned a quarter: in every layer of three windows (bottom, middle, top) each
 * part's pixels against the exact raster of the plate minus the disc, turned and moved as the
 * tray placed it: IoU >= 0.999, and nothing in the hole. */
Test(solid_layers, a_boolean_in_a_tray_keeps_its_hole, .timeout = 300)
{
    hv_mesh *p = plate(), *r = rod();
    hv_object *op = object_of(p), *orod = object_of(r), *h = NULL;
    cr_assert_eq(hv_object_boolean(op, orod, HV_OP_SUBTRACT, &h), HV_OK, "%s", hv_last_error());
    hv_volume *v = evaluate(h);
    const char *model = t_tmpfile("holed.vdb");
    cr_assert_eq(hv_volume_save(v, model), HV_OK, "%s", hv_last_error());
    hv_tray *t = NULL;
    cr_assert_eq(hv_tray_create(&t), HV_OK);
    const double at[2][2] = {{100, 100}, {200, 150}};
    for (int k = 0; k < 2; ++k) {
        hv_tray_part tp;
        hv_tray_part_init(&tp);
        tp.model = model;
        tp.at[0] = at[k][0];
        tp.at[1] = at[k][1];
        tp.placed = 1;
        tp.rotation = 90 * k;
        cr_assert_eq(hv_tray_add(t, &tp, NULL), HV_OK, "%s", hv_last_error());
    }
    hv_tray_options o;
    hv_tray_options_init(&o);
    o.mode = HV_LAYERS_MASK;
    o.resin[o.nresin++] = "A=VeroCyan-V";
    o.resin[o.nresin++] = "B=VeroMagenta-V";
    const hv_printer_profile *pp = hv_printer_profile_find("j750");
    double sx = 25.4 / pp->dpi[0], py = 25.4 / pp->dpi[1], lh = pp->layer_height;
    size_t windows[3][2] = {{0, 4}, {183, 187}, {366, 370}};
    double worst = 1;
    long hole = 0;
    for (int w = 0; w < 3; ++w) {
        o.first = windows[w][0];
        o.last = windows[w][1];
        char dir[64];
        snprintf(dir, sizeof dir, "tray%d", w);
        hv_tray_report rep;
        cr_assert_eq(hv_tray_write(t, t_tmpfile(dir), &o, NULL, &rep), HV_OK, "%s", hv_last_error());
        cr_assert_eq(rep.layers, 370);
        for (size_t l = o.first; l < o.last; ++l) {
            char path[4096];
            snprintf(path, sizeof path, "%s/layer-%05zu.png", t_tmpfile(dir), l);
            t_png im;
            t_png_load(path, &im);
            double z = ((double)l + 0.5) * lh;
            for (int k = 0; k < 2; ++k) {
                hv_tray_placement tp;
                hv_tray_instance_get(t, k, &tp);
                long both = 0, either = 0;
                int c0 = (int)floor((tp.box[0] - 1) / sx), c1 = (int)ceil((tp.box[2] + 1) / sx);
                int r0 = (int)floor((pp->build[1] - tp.box[3] - 1) / py), r1 = (int)ceil((pp->build[1] - tp.box[1] + 1) / py);
                for (int row = r0; row < r1; ++row)
                    for (int c = c0; c < c1; ++c) {
                        double X = (c + 0.5) * sx - tp.at[0], Y = pp->build[1] - (row + 0.5) * py - tp.at[1];
                        /* back to the part's frame: the box centre (20, 10), turned (x, y) -> (-y, x) for k = 1 */
                        double x = k ? Y + 20 : X + 20, y = k ? -X + 10 : Y + 10;
                        int got = im.px[(size_t)row * im.w + c] != 0, want = in_analytic(HV_OP_SUBTRACT, x, y, z);
                        both += got && want;
                        either += got || want;
                        if (got && hypot(x - 20, y - 10) < 4.9) ++hole;
                    }
                double iou = either ? (double)both / (double)either : 0;
                if (iou < worst) worst = iou;
            }
            free(im.px);
        }
    }
    cr_expect_geq(worst, 0.999, "worst layer IoU %.6f", worst);
    cr_expect_eq(hole, 0, "the hole holds %ld object pixels", hole);
    hv_tray_destroy(t);
    hv_volume_destroy(v);
    hv_object_destroy(h);
    hv_object_destroy(op);
    hv_object_destroy(orod);
    hv_mesh_destroy(p);
    hv_mesh_destroy(r);
}
