/* tests/model/test_check.c - src/model: the model loader picks the reader by content, and every
 * load checks the grids against each other (hv_model_check, issue 32 item 11), against voxels
 * set by hand: a fraction off by more than 16-bit storage explains, outside [0, 1] or outside the
 * occupancy is found, named by its voxel, wherever it is in the tree. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <string.h>

#include "hovox/model.h"
#include "support/support.h"

/* A graded 8 x 8 x 8 model (one leaf) plus a second leaf far away: occupancy everywhere,
 * A = 0.25 and B = 0.75. */
static hv_volume *graded(int *ga, int *gb)
{
    hv_transform xf = {{0.5, 0.5, 0.5}, {0, 0, 0}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    const int lo[3] = {0, 0, 0}, hi[3] = {7, 7, 7}, lo2[3] = {64, 0, 8}, hi2[3] = {71, 7, 15};
    cr_assert_eq(t_add_box(v, lo, hi), HV_OK);
    cr_assert_eq(t_add_box(v, lo2, hi2), HV_OK);
    int occ;
    cr_assert_eq(hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &occ), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "material.A", HV_GRID_FLOAT, ga), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "material.B", HV_GRID_FLOAT, gb), HV_OK);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        uint64_t *o = hv_volume_leaf_bool(v, occ, l);
        float *a = hv_volume_leaf_float(v, *ga, l), *b = hv_volume_leaf_float(v, *gb, l);
        for (int w = 0; w < HV_LEAF_SIZE / 64; ++w) o[w] = ~UINT64_C(0);
        for (int n = 0; n < HV_LEAF_SIZE; ++n) {
            a[n] = 0.25f;
            b[n] = 0.75f;
        }
    }
    return v;
}

static void set(hv_volume *v, int g, int i, int j, int k, float x)
{
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    cr_assert_eq(hv_accessor_set_float(&acc, g, i, j, k, x), HV_OK);
}

Test(check, a_consistent_model_passes)
{
    int ga, gb;
    hv_volume *v = graded(&ga, &gb);
    cr_assert_eq(hv_model_check(v), HV_OK);
    /* within 16-bit storage's rounding (2^-12 per material): still fine */
    set(v, ga, 3, 4, 5, 0.25f + 1.0f / 8192.0f);
    cr_assert_eq(hv_model_check(v), HV_OK);
    hv_volume_destroy(v);
}

Test(check, a_sum_off_one_is_named_by_its_voxel)
{
    int ga, gb;
    hv_volume *v = graded(&ga, &gb);
    set(v, gb, 66, 5, 12, 0.70f); /* in the far leaf */
    cr_assert_eq(hv_model_check(v), HV_ERR_BAD_INPUT);
    const char *m = hv_last_error();
    cr_assert(strstr(m, "voxel 66,5,12 (at 33, 2.5, 6)") && strstr(m, "sum to 0.95"), "%s", m);
    hv_volume_destroy(v);
}

Test(check, a_fraction_out_of_range_is_refused)
{
    int ga, gb;
    hv_volume *v = graded(&ga, &gb);
    set(v, ga, 1, 2, 3, -0.5f);
    set(v, gb, 1, 2, 3, 1.5f); /* sums to 1, but neither is a fraction */
    cr_assert_eq(hv_model_check(v), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "voxel 1,2,3") && strstr(hv_last_error(), "outside [0, 1]"), "%s",
              hv_last_error());
    hv_volume_destroy(v);
}

Test(check, a_fraction_outside_the_occupancy_is_refused)
{
    int ga, gb;
    hv_volume *v = graded(&ga, &gb);
    int occ = hv_volume_grid_find(v, "occupancy");
    uint64_t *o = hv_volume_leaf_bool(v, occ, 0);
    o[0] &= ~UINT64_C(1); /* voxel 0,0,0 leaves the part but keeps its fractions */
    cr_assert_eq(hv_model_check(v), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "voxel 0,0,0") && strstr(hv_last_error(), "outside it"), "%s",
              hv_last_error());
    /* emptied there too: fine again */
    set(v, ga, 0, 0, 0, 0.0f);
    set(v, gb, 0, 0, 0, 0.0f);
    cr_assert_eq(hv_model_check(v), HV_OK);
    hv_volume_destroy(v);
}

Test(check, ungraded_models_pass)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    const int lo[3] = {0, 0, 0}, hi[3] = {3, 3, 3};
    cr_assert_eq(t_add_box(v, lo, hi), HV_OK);
    cr_assert_eq(hv_model_check(v), HV_OK); /* no occupancy */
    cr_assert_eq(hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, NULL), HV_OK);
    cr_assert_eq(hv_model_check(v), HV_OK); /* no materials */
    hv_volume_destroy(v);
}

Test(load, the_reader_is_chosen_by_content)
{
    int ga, gb;
    hv_volume *v = graded(&ga, &gb);
    /* a .vdb named .3mf is read as what it is */
    char path[4200];
    snprintf(path, sizeof path, "%s", t_tmpfile("model_is_vdb.3mf"));
    const char *saved = t_tmpfile("model_is_vdb.vdb");
    cr_assert_eq(hv_volume_save(v, saved), HV_OK, "%s", hv_last_error());
    cr_assert_eq(rename(saved, path), 0);
    hv_volume_destroy(v);
    hv_volume *w = NULL;
    cr_assert_eq(hv_model_load(path, &w), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_grid_count(w), 3);
    hv_volume_destroy(w);
    cr_assert_eq(hv_model_file_is_mesh(path), 0);
    /* a mesh is told it is one (hv_model_file_is_mesh: the front ends name their mesh loader) */
    const char *mesh = t_tmpfile("not_a_model.vdb");
    FILE *f = fopen(mesh, "w");
    cr_assert(f);
    fputs("solid nothing\nendsolid nothing\n", f);
    fclose(f);
    cr_assert_eq(hv_model_load(mesh, &w), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "not_a_model.vdb: a mesh, not a model"), "%s", hv_last_error());
    cr_assert_null(w);
    cr_assert_eq(hv_model_file_is_mesh(mesh), 1);
    /* neither format, a directory, a missing file */
    const char *text = t_tmpfile("notes.txt");
    f = fopen(text, "w");
    cr_assert(f);
    fputs("nothing here\n", f);
    fclose(f);
    cr_assert_eq(hv_model_load(text, &w), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "not an OpenVDB file"), "%s", hv_last_error());
    cr_assert_null(w);
    cr_assert_eq(hv_model_file_is_mesh(text), 0);
    cr_assert_eq(hv_model_file_is_mesh(t_tmpfile("missing.vdb")), 0);
    cr_assert_eq(hv_model_load(t_tmpdir(), &w), HV_ERR_IO);
    cr_assert_eq(hv_model_load(t_tmpfile("missing.vdb"), &w), HV_ERR_IO);
}

Test(load, a_model_whose_grids_disagree_is_refused_on_load)
{
    int ga, gb;
    hv_volume *v = graded(&ga, &gb);
    set(v, gb, 2, 2, 2, 0.5f);
    const char *path = t_tmpfile("disagree.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK);
    hv_volume_destroy(v);
    hv_volume *w = NULL;
    cr_assert_eq(hv_model_load(path, &w), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "voxel 2,2,2") && strstr(hv_last_error(), "disagree.vdb"), "%s",
              hv_last_error());
    cr_assert_null(w);
}
