/* tests/slicing/test_tray.c - trays (slicing/tray.c): a tray of one part holds, inside the part's
 * box, exactly the pixels `hovox layers --place` gives that part (read back by libpng); layer
 * ranges and thread counts give the same bytes; rotations are exact quarter turns (a rotated
 * part's mask against the rotated analytic box); refusals name the part (overlap, off the plate,
 * too tall, too many resins, unknown resin); arrangement keeps footprints apart and inside. */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "hovox/generate.h"
#include "hovox/layers.h"
#include "hovox/material.h"
#include "hovox/scan.h"
#include "hovox/tray.h"
#include "hovox/voxelize.h"
#include "support/support.h"
#include "slicing/layers_internal.h"

/* A small graded part on disk: a box 12 x 8 x 1.2 mm, 0.4 mm voxels, two materials graded
 * along x (axis feature), and its mesh. */
static void make_box_part(const char *dir, const char *stem, double x, double y, double z, char *model, char *mesh,
                          size_t n)
{
    snprintf(mesh, n, "%s/%s.stl", dir, stem);
    snprintf(model, n, "%s/%s.vdb", dir, stem);
    if (t_exists(model)) return;
    double lo[3] = {0, 0, 0}, hi[3] = {x, y, z};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_box(lo, hi, &m), HV_OK);
    cr_assert_eq(hv_mesh_write_stl(m, mesh, 0), HV_OK, "%s", hv_last_error());
    hv_voxelize_options vo;
    hv_voxelize_options_init(&vo);
    vo.voxel_size[0] = vo.voxel_size[1] = vo.voxel_size[2] = 0.4;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &vo, &v), HV_OK, "%s", hv_last_error());
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_create(&t), HV_OK);
    cr_assert_eq(hv_material_add(t, "A", NULL, NULL), HV_OK);
    cr_assert_eq(hv_material_add(t, "B", NULL, NULL), HV_OK);
    double o[3] = {0, 0, 0}, d[3] = {1, 0, 0}, ms[2] = {1, 0}, me[2] = {0, 1};
    hv_frf *frf = NULL;
    cr_assert_eq(hv_frf_plane(o, d, &frf), HV_OK);
    hv_dfn *f = NULL;
    cr_assert_eq(hv_dfn_expr("d/dg", &f), HV_OK);
    hv_ags_desc ad = {frf, 0, x, 0, f, ms, me, 2, NULL};
    hv_ags *a = NULL;
    cr_assert_eq(hv_ags_create(&ad, &a), HV_OK, "%s", hv_last_error());
    hv_object *obj = NULL;
    cr_assert_eq(hv_object_create(v, "occupancy", 2, &obj), HV_OK);
    cr_assert_eq(hv_object_add_ags(obj, a), HV_OK);
    hv_volume *g = NULL;
    cr_assert_eq(hv_object_evaluate(obj, t, 0, NULL, &g), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_save(g, model), HV_OK, "%s", hv_last_error());
    hv_volume_destroy(g);
    hv_object_destroy(obj);
    hv_ags_release(a);
    hv_dfn_destroy(f);
    hv_frf_release(frf);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

static void make_part(const char *dir, char *model, char *mesh, size_t n)
{
    make_box_part(dir, "part", 12, 8, 1.2, model, mesh, n);
}

/* A box from the origin to (x, y, z) written as t_tmpfile(name). */
static const char *box_stl(const char *name, double x, double y, double z)
{
    double lo[3] = {0, 0, 0}, hi[3] = {x, y, z};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_box(lo, hi, &m), HV_OK);
    const char *path = t_tmpfile(name);
    cr_assert_eq(hv_mesh_write_stl(m, path, 0), HV_OK);
    hv_mesh_destroy(m);
    return path;
}

static json_t *manifest(const char *dir)
{
    char p[4200];
    snprintf(p, sizeof p, "%s/manifest.json", dir);
    json_error_t e;
    json_t *j = json_load_file(p, 0, &e);
    cr_assert(j, "%s: %s", p, e.text);
    return j;
}

static void tray_opts(hv_tray_options *o)
{
    hv_tray_options_init(o);
    o->resin[o->nresin++] = "A=VeroCyan-V";
    o->resin[o->nresin++] = "B=VeroMagenta-V";
    o->cache_dir = t_tmpfile("bncache");
}

static hv_tray *one_part_tray(const char *model, const char *mesh, double x, double y, int rot)
{
    hv_tray *t = NULL;
    cr_assert_eq(hv_tray_create(&t), HV_OK);
    hv_tray_part p;
    hv_tray_part_init(&p);
    p.model = model;
    p.mesh = mesh;
    p.at[0] = x;
    p.at[1] = y;
    p.placed = 1;
    p.rotation = rot;
    cr_assert_eq(hv_tray_add(t, &p, NULL), HV_OK, "%s", hv_last_error());
    return t;
}

Test(tray, one_part_has_the_pixels_of_layers_placed, .timeout = 120)
{
    char model[4200], mesh[4200];
    make_part(t_tmpdir(), model, mesh, sizeof model);
    /* the part alone, placed at (101.3, 57.9) */
    hv_mesh *m = NULL;
    hv_volume *v = NULL;
    cr_assert_eq(hv_mesh_load_stl(mesh, &m), HV_OK);
    cr_assert_eq(hv_volume_load(model, &v), HV_OK);
    hv_layers_options lo;
    hv_layers_options_init(&lo);
    lo.placed = 1;
    lo.place[0] = 101.3;
    lo.place[1] = 57.9;
    lo.cache_dir = t_tmpfile("bncache");
    const char *ldir = t_tmpfile("alone");
    hv_layers_report lr;
    cr_assert_eq(hv_layers_write(m, v, ldir, &lo, NULL, &lr), HV_OK, "%s", hv_last_error());
    /* the same part as a tray */
    hv_tray *t = one_part_tray(model, mesh, 101.3, 57.9, 0);
    hv_tray_options o;
    tray_opts(&o);
    const char *tdir = t_tmpfile("tray");
    hv_tray_report tr;
    cr_assert_eq(hv_tray_write(t, tdir, &o, NULL, &tr), HV_OK, "%s", hv_last_error());
    cr_expect_eq(tr.layers, lr.layers_total);
    json_t *lm = manifest(ldir);
    int c0 = (int)json_integer_value(json_object_get(json_object_get(lm, "plate"), "column"));
    int r0 = (int)json_integer_value(json_object_get(json_object_get(lm, "plate"), "row"));
    json_decref(lm);
    size_t checked = 0, object = 0;
    for (size_t i = 0; i < lr.layers_total; i += 11) {
        char a[4200], b[4200];
        snprintf(a, sizeof a, "%s/layer-%05zu.png", ldir, i);
        snprintf(b, sizeof b, "%s/layer-%05zu.png", tdir, i);
        t_png pa, pb;
        t_png_load(a, &pa);
        t_png_load(b, &pb);
        cr_assert_eq(pb.w, tr.width);
        cr_assert_eq(pb.h, tr.height);
        for (int r = 0; r < pa.h; ++r)
            for (int c = 0; c < pa.w; ++c) {
                int x = c0 + c, y = r0 + r;
                cr_assert(x >= 0 && y >= 0 && x < pb.w && y < pb.h);
                /* materials A, B are palette entries 1, 2 in both (resins in table order) */
                uint8_t va = pa.px[(size_t)r * pa.w + c], vb = pb.px[(size_t)y * pb.w + x];
                if (va != vb) cr_assert_fail("layer %zu pixel (%d, %d): alone %d, tray %d", i, c, r, va, vb);
                object += va != 0;
                ++checked;
            }
        /* and nothing outside the part's image */
        size_t outside = 0;
        for (int y = 0; y < pb.h; ++y)
            for (int x = 0; x < pb.w; ++x)
                if (pb.px[(size_t)y * pb.w + x] && (x < c0 || y < r0 || x >= c0 + pa.w || y >= r0 + pa.h)) ++outside;
        cr_expect_eq(outside, 0);
        free(pa.px);
        free(pb.px);
    }
    cr_expect_gt(object, checked / 4, "the part was mostly background: %zu of %zu", object, checked);
    hv_tray_destroy(t);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

Test(tray, ranges_and_threads_give_the_same_bytes, .timeout = 120)
{
    char model[4200], mesh[4200];
    make_part(t_tmpdir(), model, mesh, sizeof model);
    hv_tray *t = one_part_tray(model, mesh, 30, 20, 90);
    hv_tray_part p;
    hv_tray_part_init(&p);
    p.mesh = mesh;
    p.material = "VeroPureWhite";
    p.copies = 2;
    cr_assert_eq(hv_tray_add(t, &p, NULL), HV_OK);
    hv_tray_options o;
    tray_opts(&o);
    o.arrange = 1;
    const char *a = t_tmpfile("all"), *b = t_tmpfile("range");
    hv_set_threads(2);
    cr_assert_eq(hv_tray_write(t, a, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    hv_set_threads(1);
    o.first = 20;
    o.last = 30;
    cr_assert_eq(hv_tray_write(t, b, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    hv_set_threads(0);
    for (int i = 20; i < 30; ++i) {
        char cmd[9000];
        snprintf(cmd, sizeof cmd, "cmp -s '%s/layer-%05d.png' '%s/layer-%05d.png'", a, i, b, i);
        cr_expect_eq(t_run(cmd, NULL), 0, "layer %d differs between a full run on 2 threads and a range on 1", i);
    }
    hv_tray_destroy(t);
}

/* A plain box rotated by 90: its mask is the analytic box turned a quarter, pixel by pixel. */
Test(tray, quarter_turns_are_exact, .timeout = 60)
{
    const char *mesh = box_stl("bar.stl", 10, 4, 0.5);
    hv_tray *t = NULL;
    cr_assert_eq(hv_tray_create(&t), HV_OK);
    hv_tray_part p;
    hv_tray_part_init(&p);
    p.mesh = mesh;
    p.material = "VeroPureWhite";
    p.at[0] = 50;
    p.at[1] = 60;
    p.placed = 1;
    p.rotation = 90;
    cr_assert_eq(hv_tray_add(t, &p, NULL), HV_OK);
    hv_tray_options o;
    hv_tray_options_init(&o);
    o.mode = HV_LAYERS_MASK;
    const char *dir = t_tmpfile("rot");
    cr_assert_eq(hv_tray_write(t, dir, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    char path[4200];
    snprintf(path, sizeof path, "%s/layer-00005.png", dir);
    t_png im;
    t_png_load(path, &im);
    double sx = 25.4 / 600, py = 25.4 / 300;
    size_t wrong = 0, inside = 0;
    for (int r = 0; r < im.h; ++r)
        for (int c = 0; c < im.w; ++c) {
            double x = (c + 0.5) * sx, y = 390 - (r + 0.5) * py;
            /* turned a quarter: 4 mm along x, 10 mm along y, centred on (50, 60) */
            int in = fabs(x - 50) < 2 && fabs(y - 60) < 5;
            int on = fabs(fabs(x - 50) - 2) < sx || fabs(fabs(y - 60) - 5) < py; /* boundary pixels */
            inside += in;
            if (!on && (im.px[(size_t)r * im.w + c] != 0) != in) ++wrong;
        }
    cr_expect_eq(wrong, 0, "%zu pixels differ from the turned box", wrong);
    cr_expect_gt(inside, 10000);
    free(im.px);
    hv_tray_destroy(t);
}

static hv_status plan_boxes(const double (*at)[2], int n, const char *material, hv_tray_options *o)
{
    const char *mesh = box_stl("b20.stl", 20, 20, 2);
    hv_tray *t = NULL;
    cr_assert_eq(hv_tray_create(&t), HV_OK);
    for (int i = 0; i < n; ++i) {
        hv_tray_part p;
        hv_tray_part_init(&p);
        p.mesh = mesh;
        p.material = material;
        if (at) {
            p.at[0] = at[i][0];
            p.at[1] = at[i][1];
            p.placed = 1;
        }
        cr_assert_eq(hv_tray_add(t, &p, NULL), HV_OK);
    }
    hv_tray_report r;
    hv_status s = hv_tray_plan(t, o, NULL, &r);
    if (s == HV_OK) { /* every box on the plate, every pair at least the spacing apart */
        int k = hv_tray_instance_count(t);
        cr_expect_eq(k, n);
        for (int i = 0; i < k; ++i) {
            double a[4], b[4];
            hv_tray_instance_box(t, i, a);
            cr_expect(a[0] >= -1e-9 && a[1] >= -1e-9 && a[2] <= 490 + 1e-9 && a[3] <= 390 + 1e-9,
                      "part %d off the plate: %g %g %g %g", i + 1, a[0], a[1], a[2], a[3]);
            for (int j = 0; j < i; ++j) {
                hv_tray_instance_box(t, j, b);
                double gx = fmax(a[0] - b[2], b[0] - a[2]), gy = fmax(a[1] - b[3], b[1] - a[3]);
                cr_expect(fmax(gx, gy) >= o->spacing - 1e-6, "parts %d and %d are %g mm apart", j + 1, i + 1,
                          fmax(gx, gy));
            }
        }
        cr_expect_gt(r.utilisation, 0);
    }
    hv_tray_destroy(t);
    return s;
}

Test(tray, refusals_name_the_part)
{
    hv_tray_options o;
    hv_tray_options_init(&o);
    const double close[2][2] = {{50, 50}, {72, 50}}; /* 2 mm apart, spacing 5 */
    cr_expect_eq(plan_boxes(close, 2, "VeroPureWhite", &o), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "part 2") && strstr(hv_last_error(), "closer than 5 mm to part 1"), "%s",
              hv_last_error());
    const double off[1][2] = {{485, 50}};
    cr_expect_eq(plan_boxes(off, 1, "VeroPureWhite", &o), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "part 1") && strstr(hv_last_error(), "off the j750 plate"), "%s", hv_last_error());
    const double ok[1][2] = {{100, 100}};
    cr_expect_eq(plan_boxes(ok, 1, "Unobtainium", &o), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "material 'Unobtainium' has no resin") && strstr(hv_last_error(), "VeroCyan-V"),
              "%s", hv_last_error());
    o.resin[o.nresin++] = "X=NoSuchResin";
    cr_expect_eq(plan_boxes(ok, 1, "X", &o), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "unknown resin 'NoSuchResin'"), "%s", hv_last_error());
}

/* parts may stand above one another: the spacing applies where their heights come close */
Test(tray, stacked_parts_keep_the_spacing_in_z)
{
    const char *mesh = box_stl("s20.stl", 20, 20, 2);
    for (int k = 0; k < 2; ++k) {
        hv_tray *t = NULL;
        cr_assert_eq(hv_tray_create(&t), HV_OK);
        for (int i = 0; i < 2; ++i) {
            hv_tray_part p;
            hv_tray_part_init(&p);
            p.mesh = mesh;
            p.material = "VeroPureWhite";
            p.at[0] = 50;
            p.at[1] = 50;
            p.placed = 1;
            p.z = i ? (k ? 10 : 6) : 0; /* 8 mm above the first one's top, or 4 */
            cr_assert_eq(hv_tray_add(t, &p, NULL), HV_OK);
        }
        hv_tray_options o;
        hv_tray_options_init(&o);
        hv_status s = hv_tray_plan(t, &o, NULL, NULL);
        if (k) cr_expect_eq(s, HV_OK, "%s", hv_last_error());
        else cr_expect(s == HV_ERR_INVALID && strstr(hv_last_error(), "heights that overlap"), "%s", hv_last_error());
        hv_tray_destroy(t);
    }
}

Test(tray, too_many_resins_for_the_slots)
{
    const char *mesh = box_stl("b10.stl", 10, 10, 1);
    static const char *resins[] = {"VeroCyan-V", "VeroMagenta-V", "VeroYellow-V", "VeroBlackPlus",
                                   "VeroPureWhite", "VeroClear", "Agilus30Clear"};
    hv_tray *t = NULL;
    cr_assert_eq(hv_tray_create(&t), HV_OK);
    for (int i = 0; i < 7; ++i) {
        hv_tray_part p;
        hv_tray_part_init(&p);
        p.mesh = mesh;
        p.material = resins[i];
        p.at[0] = 20 + 20 * i;
        p.at[1] = 20;
        p.placed = 1;
        cr_assert_eq(hv_tray_add(t, &p, NULL), HV_OK);
    }
    hv_tray_options o;
    hv_tray_options_init(&o);
    cr_expect_eq(hv_tray_plan(t, &o, NULL, NULL), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "7 resins") && strstr(hv_last_error(), "6 material slots"), "%s", hv_last_error());
    o.profile = "j850"; /* 7 slots */
    cr_expect_eq(hv_tray_plan(t, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    hv_tray_destroy(t);
}

Test(tray, arrangement_keeps_parts_apart_and_on_the_plate)
{
    hv_tray_options o;
    hv_tray_options_init(&o);
    o.arrange = 2;
    cr_expect_eq(plan_boxes(NULL, 40, "VeroPureWhite", &o), HV_OK, "%s", hv_last_error());
    /* 40 boxes of 20 x 20 with 5 mm spacing fit; 400 do not, and the refusal names them */
    cr_expect_eq(plan_boxes(NULL, 400, "VeroPureWhite", &o), HV_ERR_LIMIT);
    cr_expect(strstr(hv_last_error(), "no room left on the j750 plate for part "), "%s", hv_last_error());
}

static int cancel_soon(void *user, const char *stage, double f)
{
    (void)stage;
    int *n = user;
    return f > 0 && ++*n > 1; /* after the first layers */
}

/* An interrupted tray leaves no final directory, no temporary and no zip. */
Test(tray, cancelled_leaves_nothing, .timeout = 60)
{
    char model[4200], mesh[4200];
    make_part(t_tmpdir(), model, mesh, sizeof model);
    hv_tray *t = one_part_tray(model, mesh, 60, 60, 0);
    hv_tray_options o;
    tray_opts(&o);
    o.gcvf_path = t_tmpfile("cancelled.zip");
    int n = 0;
    hv_progress p = {cancel_soon, &n};
    hv_set_threads(1);
    hv_status s = hv_tray_write(t, t_tmpfile("cancelled"), &o, &p, NULL);
    hv_set_threads(0);
    cr_expect_eq(s, HV_ERR_CANCELLED, "%s", hv_last_error());
    cr_expect_not(t_exists(t_tmpfile("cancelled")));
    cr_expect_not(t_exists(t_tmpfile("cancelled.zip")));
    char cmd[4400], *out = NULL;
    snprintf(cmd, sizeof cmd, "ls -A '%s' | grep -c 'tmp' ", t_tmpdir());
    t_run(cmd, &out);
    cr_expect_str_eq(out, "0\n", "a temporary was left behind");
    free(out);
    hv_tray_destroy(t);
}

/* The tray goes through the same stack writer: its manifest hook adds members. */
static hv_status add_source(void *user, void *manifest)
{
    return json_object_set_new(manifest, "source", json_string(user)) ? HV_ERR_NOMEM : HV_OK;
}

Test(tray, manifest_hook_adds_to_the_manifest, .timeout = 60)
{
    char model[4200], mesh[4200];
    make_part(t_tmpdir(), model, mesh, sizeof model);
    hv_tray *t = one_part_tray(model, mesh, 60, 60, 0);
    hv_tray_options o;
    tray_opts(&o);
    o.manifest = add_source;
    o.manifest_user = "scanner.nii";
    cr_assert_eq(hv_tray_write(t, t_tmpfile("hooked_tray"), &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    json_t *doc = manifest(t_tmpfile("hooked_tray"));
    cr_expect_str_eq(json_string_value(json_object_get(doc, "source")), "scanner.nii");
    cr_expect_str_eq(json_string_value(json_object_get(doc, "kind")), "tray");
    json_decref(doc);
    hv_tray_destroy(t);
}

/* Mask mode: graded and plain parts in one 1-bit stack, the manifest naming their materials. */
Test(tray, mask_mode_manifest_names_materials, .timeout = 60)
{
    char model[4200], mesh[4200];
    make_part(t_tmpdir(), model, mesh, sizeof model);
    hv_tray *t = one_part_tray(model, mesh, 40, 40, 0);
    hv_tray_part p;
    hv_tray_part_init(&p);
    p.mesh = mesh;
    p.material = "VeroPureWhite";
    p.at[0] = 80;
    p.at[1] = 40;
    p.placed = 1;
    cr_assert_eq(hv_tray_add(t, &p, NULL), HV_OK);
    hv_tray_options o;
    tray_opts(&o);
    o.mode = HV_LAYERS_MASK;
    o.first = 0;
    o.last = 4;
    const char *dir = t_tmpfile("maskmode");
    cr_assert_eq(hv_tray_write(t, dir, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    json_t *m = manifest(dir);
    json_t *parts = json_object_get(m, "parts");
    cr_assert_eq(json_array_size(parts), 2);
    cr_expect(json_object_get(json_object_get(json_array_get(parts, 0), "materials"), "A"));
    cr_expect(json_object_get(json_object_get(json_array_get(parts, 1), "materials"), "VeroPureWhite"));
    cr_expect_eq(json_integer_value(json_object_get(m, "bit_depth")), 1);
    json_decref(m);
    hv_tray_destroy(t);
}

/* Packing a part's pixels into the plate's rows, against packing pixel by pixel: every bit depth,
 * every start within a byte, runs shorter and longer than a byte, onto a row already holding
 * pixels (values are ORed in, never erased). */
Test(tray, packed_rows_match_pixel_by_pixel)
{
    uint8_t lut[16], sp[40];
    for (int i = 0; i < 16; ++i) lut[i] = (uint8_t)((i * 5 + 3) & 15);
    for (int i = 0; i < 40; ++i) sp[i] = (uint8_t)((i * 7 + i / 3) % 16);
    for (int bits = 1; bits <= 4; bits *= 2) {
        uint8_t lb[16]; /* palette indices fit the depth */
        for (int i = 0; i < 16; ++i) lb[i] = (uint8_t)(lut[i] & ((1 << bits) - 1));
        for (int x0 = 0; x0 < 9; ++x0)
            for (int n = 0; n <= 40 - x0; ++n) {
                uint8_t row[24], want[24];
                for (int b = 0; b < 24; ++b) row[b] = want[b] = (uint8_t)(b % 3 == 0 ? 0x81 : 0);
                hv_tray_or_packed(row, bits, x0, sp, n, lb);
                for (int k = 0; k < n; ++k) {
                    int x = x0 + k, per = 8 / bits;
                    want[x / per] |= (uint8_t)(lb[sp[k]] << (8 - bits * (x % per + 1)));
                }
                for (int b = 0; b < 24; ++b)
                    cr_assert_eq(row[b], want[b], "bits %d x0 %d n %d byte %d: %02x, want %02x", bits, x0, n, b, row[b],
                                 want[b]);
            }
    }
}

/* ---- memory does not grow with the parts per thread (issue 32 item 21) ---------------------- */

/* A tray of `copies` arranged copies of the 40 x 30 x 2 mm graded box. */
static hv_tray *copies_tray(int copies, hv_tray_options *o)
{
    char model[4200], mesh[4200];
    make_box_part(t_tmpdir(), "slab", 40, 30, 2, model, mesh, sizeof model);
    hv_tray *t = NULL;
    cr_assert_eq(hv_tray_create(&t), HV_OK);
    hv_tray_part p;
    hv_tray_part_init(&p);
    p.model = model;
    p.mesh = mesh;
    p.copies = copies;
    cr_assert_eq(hv_tray_add(t, &p, NULL), HV_OK, "%s", hv_last_error());
    tray_opts(o);
    o->arrange = 1;
    return t;
}

static uint64_t planned_memory(hv_tray *t, const hv_tray_options *o, int threads)
{
    hv_tray_report r;
    hv_set_threads(threads);
    cr_assert_eq(hv_tray_plan(t, o, NULL, &r), HV_OK, "%s", hv_last_error());
    hv_set_threads(0);
    return r.memory;
}

/* At most 4 layers in flight (packed plate images, fewer with fewer threads or a smaller budget),
 * shared by the threads, and per thread ONE part's buffers (slabs included), whatever the number
 * of parts: past 4 threads the plan grows by that scratch alone, bounded by what the part alone
 * needs (its own `layers --place` plan on one thread, an independent figure) plus its slabs.
 * Before, each thread held a plate and every part's slabs (the bench tray: about 55 MiB a thread;
 * earlier every part's buffers, about 350 MiB). */
Test(tray, memory_per_thread_is_one_part, .timeout = 120)
{
    hv_tray_options o;
    hv_tray *t = copies_tray(10, &o);
    uint64_t m1 = planned_memory(t, &o, 1), m2 = planned_memory(t, &o, 2), m4 = planned_memory(t, &o, 4),
             m5 = planned_memory(t, &o, 5), m16 = planned_memory(t, &o, 16);
    uint64_t sc = m5 - m4; /* a thread past the plates in flight: its scratch alone */
    cr_expect_eq(m16 - m4, 12 * sc, "not linear past 4 threads: %llu, %llu, %llu", (unsigned long long)m4,
                 (unsigned long long)m5, (unsigned long long)m16);
    hv_tray_report r;
    cr_assert_eq(hv_tray_plan(t, &o, NULL, &r), HV_OK);
    /* a plate: its packed rows, each after its PNG filter byte, and two spans a row */
    uint64_t plate = (((uint64_t)r.width * (uint64_t)r.bit_depth + 7) / 8 + 1) * (uint64_t)r.height + 8 * (uint64_t)r.height;
    /* the part alone, placed on the same printer, one thread */
    char model[4200], mesh[4200];
    make_box_part(t_tmpdir(), "slab", 40, 30, 2, model, mesh, sizeof model);
    hv_mesh *m = NULL;
    hv_volume *v = NULL;
    cr_assert_eq(hv_mesh_load_stl(mesh, &m), HV_OK);
    cr_assert_eq(hv_volume_load(model, &v), HV_OK, "%s", hv_last_error());
    hv_layers_options lo;
    hv_layers_options_init(&lo);
    lo.placed = 1; /* the defaults are the J750's, as one_part_has_the_pixels_of_layers_placed */
    lo.place[0] = 100;
    lo.place[1] = 100;
    lo.cache_dir = o.cache_dir;
    hv_layers_report lr;
    hv_set_threads(1);
    cr_assert_eq(hv_layers_plan(m, v, &lo, &lr), HV_OK, "%s", hv_last_error());
    hv_set_threads(0);
    /* and each part's two voxel slabs kept between its layers: 100 x 75 voxels of 0.4 mm with
     * the window's 3-voxel pad (8 allowed), occupancy and two fractions */
    uint64_t slabs = 2 * (uint64_t)(100 + 8) * (75 + 8) * (1 + 4 * 2);
    cr_expect_gt(sc, 0, "a thread's scratch is not counted");
    cr_expect_leq(sc, lr.memory_bytes + slabs,
                  "a thread needs %llu bytes: more than one part (%llu) and its slabs (%llu)", (unsigned long long)sc,
                  (unsigned long long)lr.memory_bytes, (unsigned long long)slabs);
    /* up to 4 threads each adds a plate in flight too */
    cr_expect_eq(m2 - m1, sc + plate, "2 threads: %llu more than 1, want %llu + %llu", (unsigned long long)(m2 - m1),
                 (unsigned long long)sc, (unsigned long long)plate);
    cr_expect_eq(m4 - m1, 3 * (sc + plate));
    /* the budget picks the layers in flight: one byte short of 4 plates leaves 3 */
    o.max_memory = m4 - 1;
    cr_expect_eq(planned_memory(t, &o, 4), m4 - plate, "under a budget of %llu", (unsigned long long)o.max_memory);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
    hv_tray_destroy(t);
}

/* Peak RSS (KiB) of `hovox tray JOB -o DIR --threads N` (the binary, as a user runs it: a
 * forked copy of this process could not start OpenMP's threads again), or -1. */
static long tray_peak_kib(const char *job, const char *dir, int threads)
{
    const char *build = getenv("HOVOX_BUILD");
    char exe[1024], th[16];
    snprintf(exe, sizeof exe, "%s/hovox", build ? build : "build");
    cr_assert(t_exists(exe), "%s is not built", exe);
    snprintf(th, sizeof th, "%d", threads);
    fflush(NULL);
    pid_t pid = fork();
    cr_assert_geq(pid, 0);
    if (pid == 0) {
        char *argv[] = {exe, "tray", (char *)job, "-o", (char *)dir, "--threads", th, "--force", "-q", NULL};
        if (!freopen("/dev/null", "w", stdout)) _exit(126);
        execv(exe, argv);
        _exit(127);
    }
    int status = 0;
    struct rusage ru;
    cr_assert_eq(wait4(pid, &status, 0, &ru), pid);
    cr_assert(WIFEXITED(status) && WEXITSTATUS(status) == 0, "hovox tray on %d threads failed", threads);
    return ru.ru_maxrss;
}

/* Measured: 10 parts, 1 thread against 8 (every thread gets layers: 10 runs of 8 layers). The
 * peak grows by no more than the plan's 7 extra threads (a plate and one part each) and 32 MiB
 * of allocator slack; holding every part per thread it grew by about 7 x 10 parts' buffers. The
 * stacks are the same bytes. */
Test(tray, peak_rss_follows_the_plan_not_the_parts, .timeout = 300)
{
    hv_tray_options o;
    hv_tray *t = copies_tray(10, &o);
    uint64_t per_thread = planned_memory(t, &o, 2) - planned_memory(t, &o, 1);
    hv_tray_destroy(t);
    const char *job = t_tmpfile("slabs.json");
    FILE *f = fopen(job, "w");
    cr_assert(f);
    fprintf(f, "{\"schema\": 1, \"profile\": \"j750\", \"arrange\": \"all\",\n"
               " \"resin\": {\"A\": \"VeroCyan-V\", \"B\": \"VeroMagenta-V\"},\n"
               " \"parts\": [{\"model\": \"slab.vdb\", \"mesh\": \"slab.stl\", \"copies\": 10}]}\n");
    cr_assert_eq(fclose(f), 0);
    const char *a = t_tmpfile("rss1"), *b = t_tmpfile("rss8");
    long k1 = tray_peak_kib(job, a, 1), k8 = tray_peak_kib(job, b, 8);
    double grew = (double)(k8 - k1) * 1024.0, allowed = 7.0 * (double)per_thread + 32.0 * 1048576.0;
    cr_log_info("peak RSS: 1 thread %ld KiB, 8 threads %ld KiB (plan: %.1f MiB a thread)", k1, k8,
                (double)per_thread / 1048576.0);
    cr_expect_leq(grew, allowed, "peak RSS 1 thread %ld KiB, 8 threads %ld KiB: grew %.0f MiB, the plan allows %.0f MiB",
                  k1, k8, grew / 1048576.0, allowed / 1048576.0);
    char cmd[9000];
    snprintf(cmd, sizeof cmd, "diff -r '%s' '%s' >/dev/null", a, b);
    cr_expect_eq(t_run(cmd, NULL), 0, "1 and 8 threads wrote different stacks");
}

/* Add part p at (x, y) on the plate. */
static void add_at(hv_tray *t, hv_tray_part *p, double x, double y)
{
    p->at[0] = x;
    p->at[1] = y;
    p->placed = 1;
    cr_assert_eq(hv_tray_add(t, p, NULL), HV_OK, "%s", hv_last_error());
}

/* A tray's default options for its layers [first, last), the blue-noise cache in the test's dir. */
static hv_tray_options window_options(size_t first, size_t last)
{
    hv_tray_options o;
    hv_tray_options_init(&o);
    o.cache_dir = t_tmpfile("bncache");
    o.first = first;
    o.last = last;
    return o;
}

/* Issue 29 item 3: a painted part's dE2000, as its manifest entry's "colour" gives it, for the
 * CLI's colour line (hv_tray_instance_colour); a plain part has none, nor has a mask stack written
 * after. */
Test(tray, a_painted_parts_colour_is_reported, .timeout = 120)
{
    FILE *f = fopen(t_tmpfile("red.mtl"), "w");
    fputs("newmtl red\nKd 1 0 0\n", f);
    fclose(f);
    f = fopen(t_tmpfile("red.obj"), "w");
    fputs("mtllib red.mtl\nv 0 0 0\nv 6 0 0\nv 0 6 0\nv 0 0 6\nusemtl red\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n", f);
    fclose(f);
    char model[4200], mesh[4200];
    make_part(t_tmpdir(), model, mesh, sizeof model);
    hv_tray *t = NULL;
    cr_assert_eq(hv_tray_create(&t), HV_OK);
    hv_tray_part p;
    hv_tray_part_init(&p);
    p.mesh = t_tmpfile("red.obj");
    add_at(t, &p, 40, 40);
    hv_tray_part_init(&p);
    p.mesh = mesh;
    p.material = "VeroPureWhite";
    add_at(t, &p, 80, 40);
    hv_tray_options o = window_options(40, 42);
    hv_tray_colour c;
    cr_assert_eq(hv_tray_instance_colour(t, 0, &c), 0); /* not written yet */
    const char *dir = t_tmpfile("painted_tray");
    cr_assert_eq(hv_tray_write(t, dir, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_tray_instance_colour(t, 0, &c), 1);
    json_t *m = manifest(dir);
    json_t *col = json_object_get(json_array_get(json_object_get(m, "parts"), 0), "colour");
    cr_assert(col);
    cr_assert_eq((json_int_t)c.target.voxels, json_integer_value(json_object_get(col, "skin_voxels")));
    cr_assert_float_eq(c.target.mean_de2000, json_number_value(json_object_get(col, "mean_de2000_target")), 1e-12);
    cr_assert_float_eq(c.achieved.mean_de2000, json_number_value(json_object_get(col, "mean_de2000_achieved")), 1e-12);
    cr_assert(c.target.voxels > 0 && c.target.mean_de2000 > 15 && !c.printer_voxels && c.intent == HV_INTENT_PERCEPTUAL);
    cr_assert_str_eq(c.description, "Artifex CMYK SWOP Profile");
    cr_assert_null(json_object_get(json_array_get(json_object_get(m, "parts"), 1), "colour"));
    json_decref(m);
    cr_assert_eq(hv_tray_instance_colour(t, 1, &c), 0);
    cr_assert_eq(hv_tray_instance_colour(t, 2, &c), 0);
    /* a mask written after: no colour, none reported */
    o.mode = HV_LAYERS_MASK;
    cr_assert_eq(hv_tray_write(t, t_tmpfile("painted_mask"), &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_tray_instance_colour(t, 0, &c), 0);
    hv_tray_destroy(t);
}

/* One truth for whose voxels a colour counts (issue 26 review): each coloured copy's
 * hv_tray_instance_colour says printer voxels exactly when its manifest entry names them so, with
 * the same count: the painted cube's skin voxels, the scan's colour table's printer voxels, in one
 * tray. */
Test(tray, a_coloured_parts_voxels_are_the_kind_its_manifest_names, .timeout = 120)
{
    char cmd[5000];
    snprintf(cmd, sizeof cmd,
             "/usr/bin/python3 tests/io/scan/make_phantom.py %s --size 20,24,18 --spacing 4,4,6 --formats nii "
             ">/dev/null && cp samples/colour_cube.obj samples/colour_cube.mtl %s",
             t_tmpfile("ph"), t_tmpdir());
    cr_assert_eq(t_run(cmd, NULL), 0, "%s", cmd);
    FILE *f = fopen(t_tmpfile("col.csv"), "w");
    fputs("HU,colour\n-1000,#ffffff00\n30,#d08070\n1000,#f0f0e0\n", f);
    fclose(f);
    hv_tray *t = NULL;
    cr_assert_eq(hv_tray_create(&t), HV_OK);
    hv_tray_part p;
    hv_tray_part_init(&p);
    p.mesh = t_tmpfile("colour_cube.obj");
    p.copies = 2;
    add_at(t, &p, 40, 30);
    hv_tray_part_init(&p);
    p.scan = t_tmpfile("ph/phantom.nii");
    p.lut = t_tmpfile("col.csv");
    p.select = HV_SCAN_SELECT_ISO;
    p.iso = -480;
    add_at(t, &p, 120, 60);
    hv_tray_options o = window_options(20, 22);
    const char *dir = t_tmpfile("kinds_tray");
    cr_assert_eq(hv_tray_write(t, dir, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    json_t *m = manifest(dir);
    json_t *parts = json_object_get(m, "parts");
    cr_assert_eq(json_array_size(parts), 3, "one entry per copy");
    for (int i = 0; i < 3; ++i) {
        hv_tray_colour c;
        cr_assert_eq(hv_tray_instance_colour(t, i, &c), 1, "copy %d is coloured", i);
        cr_assert_eq(c.printer_voxels, i == 2, "copy %d: %s voxels", i, c.printer_voxels ? "printer" : "skin");
        json_t *col = json_object_get(json_array_get(parts, (size_t)i), "colour");
        const char *kind = c.printer_voxels ? "printer_voxels" : "skin_voxels";
        cr_assert(json_is_integer(json_object_get(col, kind)), "copy %d: the manifest has no %s", i, kind);
        cr_assert_null(json_object_get(col, c.printer_voxels ? "skin_voxels" : "printer_voxels"));
        cr_assert_eq(json_integer_value(json_object_get(col, kind)), (json_int_t)c.target.voxels);
        cr_assert(c.target.voxels > 0);
    }
    json_decref(m);
    hv_tray_destroy(t);
}
