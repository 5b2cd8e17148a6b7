/* tests/slicing/test_layers_assembly.c - printer stacks of assemblies: two nested boxes (an Agilus core in
 * a Vero shell) joined, voxelized into regions, graded to the bodies' materials, and written as a
 * halftoned stack from the multi-body mesh: the layer at mid-height holds both materials, each
 * where its region's voxels are (pixels counted per palette index; the object's outline is the
 * union of the bodies' contours), by resampling and by direct evaluation; the Agilus area is the
 * core's true section (16 mm^2) within 10%, the core region holding the voxels whose centres are
 * inside the core. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "core/json.h"
#include "hovox/generate.h"
#include "hovox/layers.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"
#include "support/support.h"

static hv_mesh *box(double lo, double hi)
{
    double a[3] = {lo, lo, lo}, b[3] = {hi, hi, hi};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_box(a, b, &m), HV_OK, "%s", hv_last_error());
    return m;
}

/* lo_core, hi_core: the core region's extent in x and y (its voxels' cells); hi_shell: the
 * shell body's (from 0). */
static void mid_layer_counts(const char *dir, double lo_core, double hi_core, double hi_shell, int method)
{
    char path[1200], *text = NULL;
    size_t n = 0;
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    cr_assert_eq(hv_read_file(path, 1 << 24, &text, &n), HV_OK, "%s", hv_last_error());
    json_t *j = NULL;
    cr_assert_eq(hv_json_parse(text, n, "manifest.json", &j), HV_OK);
    free(text);
    /* palette: 1 Agilus, 2 Vero (the table built from the bodies, in body order) */
    const json_t *mats = json_object_get(j, "materials");
    cr_assert_eq(json_array_size(mats), 2);
    cr_assert_str_eq(json_string_value(json_object_get(json_array_get(mats, 0), "name")), "Agilus");
    cr_assert_str_eq(json_string_value(json_object_get(json_array_get(mats, 1), "name")), "Vero");
    double sx = json_number_value(json_array_get(json_object_get(j, "pixel_mm"), 0)),
           sy = json_number_value(json_array_get(json_object_get(j, "pixel_mm"), 1)),
           x0 = json_number_value(json_array_get(json_object_get(j, "origin_mm"), 0)),
           y0 = json_number_value(json_array_get(json_object_get(j, "origin_mm"), 1));
    const json_t *layers = json_object_get(j, "layers");
    size_t mid = json_array_size(layers) / 2;
    double z = json_number_value(json_object_get(json_array_get(layers, mid), "z_mm"));
    cr_assert(z > lo_core + 0.5 && z < hi_core - 0.5, "mid layer at %g", z);
    snprintf(path, sizeof path, "%s/%s", dir, json_string_value(json_object_get(json_array_get(layers, mid), "file")));
    t_png im;
    t_png_load(path, &im);
    long count[4] = {0}, core_wrong = 0, shell_wrong = 0, core_in = 0, shell_in = 0;
    for (int r = 0; r < im.h; ++r)
        for (int c = 0; c < im.w; ++c) {
            int v = im.px[(size_t)r * im.w + c];
            cr_assert(v <= 2, "palette index %d", v);
            ++count[v];
            double x = x0 + (c + 0.5) * sx, y = y0 + (r + 0.5) * sy;
            /* a voxel (0.5 mm) away from the interface: one material only */
            int in_core = x > lo_core + 0.5 && x < hi_core - 0.5 && y > lo_core + 0.5 && y < hi_core - 0.5;
            int in_shell = x > 0 && x < hi_shell && y > 0 && y < hi_shell &&
                           !(x > lo_core - 0.5 && x < hi_core + 0.5 && y > lo_core - 0.5 && y < hi_core + 0.5);
            core_in += in_core;
            shell_in += in_shell;
            core_wrong += in_core && v != 1;
            shell_wrong += in_shell && v != 2 && x > 0.3 && x < hi_shell - 0.3 && y > 0.3 && y < hi_shell - 0.3;
        }
    free(im.px);
    double px = sx * -sy, core = (hi_core - lo_core) * (hi_core - lo_core), all = hi_shell * hi_shell;
    cr_log_info("%s (method %d): layer %zu at z = %g: Agilus %ld px (%.2f mm^2, region %.2f), Vero %ld px (%.2f mm^2, "
                "region %.2f)",
                dir, method, mid, z, count[1], (double)count[1] * px, core, count[2], (double)count[2] * px, all - core);
    cr_assert(core_in > 100 && shell_in > 500);
    cr_assert_eq(core_wrong, 0, "%ld core pixels not Agilus", core_wrong);
    cr_assert_eq(shell_wrong, 0, "%ld shell pixels not Vero", shell_wrong);
    cr_assert(fabs((double)count[1] * px - core) < 0.1 * core, "Agilus %.2f mm^2 vs %.2f", (double)count[1] * px, core);
    cr_assert(fabs((double)(count[1] + count[2]) * px - all) < 0.03 * all, "object %.2f mm^2 vs %.2f",
              (double)(count[1] + count[2]) * px, all);
    json_decref(j);
}

Test(layers_assembly, the_mid_layer_shows_both_materials_where_their_bodies_are, .timeout = 120)
{
    hv_mesh *outer = box(0, 10), *inner = box(3, 7), *a = NULL;
    hv_mesh_part parts[2] = {{inner, "core", "Agilus"}, {outer, "shell", "Vero"}};
    cr_assert_eq(hv_mesh_join(parts, 2, &a), HV_OK, "%s", hv_last_error());
    hv_voxelize_options vo;
    hv_voxelize_options_init(&vo);
    vo.voxel_size[0] = vo.voxel_size[1] = vo.voxel_size[2] = 0.5;
    hv_volume *v = NULL, *g = NULL;
    cr_assert_eq(hv_voxelize(a, &vo, &v), HV_OK, "%s", hv_last_error());
    hv_material_table *t = NULL;
    hv_object *o = NULL;
    cr_assert_eq(hv_object_from_regions(v, NULL, &t, &o), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_evaluate(o, t, 0, NULL, &g), HV_OK, "%s", hv_last_error());
    /* the core region's extent: its voxels' cells, the voxels whose centres are inside the core:
     * on the 0.5 mm lattice (centres at 0.25 + 0.5 n) exactly the body's 3 .. 7 */
    int gc = hv_volume_grid_find(v, "region.core");
    cr_assert_geq(gc, 0);
    hv_transform xf = hv_volume_get_transform(v);
    double clo = 1e9, chi = -1e9;
    const int32_t *org = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned q = 0; q < 512; ++q)
            if (HV_BIT_GET(hv_volume_leaf_bool_c(v, gc, l), q) && HV_BIT_GET(hv_volume_leaf_mask(v, l), q)) {
                double x = xf.origin[0] + (org[3 * l] + (int)(q >> 6)) * xf.voxel[0];
                clo = fmin(clo, x - 0.5 * xf.voxel[0]);
                chi = fmax(chi, x + 0.5 * xf.voxel[0]);
            }
    cr_assert(fabs(clo - 3) < 1e-9 && fabs(chi - 7) < 1e-9, "core region cells %g .. %g", clo, chi);
    for (int method = 0; method < 2; ++method) {
        hv_layers_options lo;
        hv_layers_options_init(&lo);
        lo.profile = "test";
        lo.dpi[0] = lo.dpi[1] = 100;
        lo.layer_height = 0.5;
        lo.method = method ? HV_LAYERS_DIRECT : HV_LAYERS_RESAMPLE;
        lo.cache_dir = t_tmpfile("bncache");
        const char *dir = t_tmpfile(method ? "direct" : "resample");
        hv_layers_report rep;
        cr_assert_eq(hv_layers_write(a, g, dir, &lo, NULL, &rep), HV_OK, "%s", hv_last_error());
        cr_assert_eq(rep.materials, 2);
        mid_layer_counts(dir, clo, chi, 10, method);
    }
    hv_volume_destroy(g);
    hv_object_destroy(o);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
    hv_mesh_destroy(a);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
}
