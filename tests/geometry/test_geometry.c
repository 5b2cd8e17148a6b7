/* tests/geometry/test_geometry.c - the geometry truth (issue 28): a mesh packed into a leaf comes
 * back as the same arrays, bodies and materials; the record survives a .vdb; Booleans combine
 * records (leaves shared, tree in order) as hv_object_boolean does on voxelized models; damaged
 * records are refused with one message; the leaf interface and the solid of a tree answer as
 * the analytic plate 40 x 20 x 10 with a rod of radius 5 through it says. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/material.h"
#include "hovox/solid.h"
#include "hovox/voxelize.h"
#include "support/support.h"

static const double k_move[12] = {1, 0, 0, 5, 0, 1, 0, -2, 0, 0, 1, 1};

static hv_mesh *plate(void)
{
    double lo[3] = {0, 0, 0}, hi[3] = {40, 20, 10};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_box(lo, hi, &m), HV_OK, "%s", hv_last_error());
    return m;
}

static hv_mesh *rod(void)
{
    double base[3] = {20, 10, -1};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_cylinder(base, 2, 12, 5, 96, &m), HV_OK, "%s", hv_last_error());
    return m;
}

static hv_geometry *record_of(const hv_mesh *m, const double *xf)
{
    hv_geometry *g = NULL;
    cr_assert_eq(hv_geometry_from_mesh(m, NULL, xf, 1, &g), HV_OK, "%s", hv_last_error());
    return g;
}

static void same_mesh(const hv_mesh *a, const hv_mesh *b)
{
    cr_assert_eq(hv_mesh_vertex_count(a), hv_mesh_vertex_count(b));
    cr_assert_eq(hv_mesh_facet_count(a), hv_mesh_facet_count(b));
    cr_assert(memcmp(hv_mesh_vertices(a), hv_mesh_vertices(b), 12 * hv_mesh_vertex_count(a)) == 0);
    cr_assert(memcmp(hv_mesh_facets(a), hv_mesh_facets(b), 12 * hv_mesh_facet_count(a)) == 0);
    cr_assert_eq(hv_mesh_body_count(a), hv_mesh_body_count(b));
    for (size_t i = 0; i < hv_mesh_body_count(a); ++i) {
        cr_assert_str_eq(hv_mesh_body_at(a, i)->name, hv_mesh_body_at(b, i)->name);
        cr_assert_eq(hv_mesh_body_at(a, i)->facet_count, hv_mesh_body_at(b, i)->facet_count);
        cr_assert_eq(hv_mesh_body_at(a, i)->material, hv_mesh_body_at(b, i)->material);
    }
    cr_assert_eq(hv_mesh_material_count(a), hv_mesh_material_count(b));
    for (size_t i = 0; i < hv_mesh_material_count(a); ++i)
        cr_assert_str_eq(hv_mesh_material_at(a, i)->name, hv_mesh_material_at(b, i)->name);
}

Test(geometry, mesh_leaf_round_trip)
{
    hv_mesh *gear = NULL;
    cr_assert_eq(hv_generate_gear(24, 34.5, 39.45, 9.54, 10, 0, 12, 1, &gear), HV_OK, "%s", hv_last_error());
    hv_geometry *g = record_of(gear, NULL);
    cr_assert(hv_geometry_is_plain(g));
    const hv_geometry_leaf *l = hv_geometry_leaf_at(g, 0);
    cr_assert_eq(l->kind, HV_LEAF_MESH);
    hv_mesh *back = NULL;
    cr_assert_eq(hv_geometry_leaf_mesh(g, 0, &back), HV_OK, "%s", hv_last_error());
    same_mesh(gear, back);
    cr_assert_float_eq(hv_mesh_get_report(back)->volume, hv_mesh_get_report(gear)->volume, 1e-9);
    hv_mesh_destroy(back);
    hv_geometry_destroy(g);
    hv_mesh_destroy(gear);
}

Test(geometry, assembly_keeps_bodies_and_materials)
{
    hv_mesh *p = plate(), *r = rod(), *joined = NULL;
    hv_mesh_part parts[2] = {{p, "plate", "VeroCyan"}, {r, "rod", "Agilus"}};
    cr_assert_eq(hv_mesh_join(parts, 2, &joined), HV_OK);
    hv_geometry *g = record_of(joined, NULL);
    hv_mesh *back = NULL;
    cr_assert_eq(hv_geometry_leaf_mesh_raw(g, 0, &back), HV_OK, "%s", hv_last_error());
    same_mesh(joined, back);
    cr_assert_eq(hv_mesh_body_count(back), 2);
    cr_assert_str_eq(hv_mesh_material_at(back, hv_mesh_body_at(back, 1)->material)->name, "Agilus");
    hv_mesh_destroy(back);
    hv_geometry_destroy(g);
    hv_mesh_destroy(joined);
    hv_mesh_destroy(p);
    hv_mesh_destroy(r);
}

Test(geometry, transform_places_the_leaf)
{
    hv_mesh *p = plate();
    hv_geometry *g = record_of(p, k_move);
    hv_mesh *raw = NULL, *placed = NULL;
    cr_assert_eq(hv_geometry_leaf_mesh_raw(g, 0, &raw), HV_OK);
    cr_assert_eq(hv_geometry_leaf_mesh(g, 0, &placed), HV_OK);
    same_mesh(p, raw);
    const hv_mesh_report *r = hv_mesh_get_report(placed);
    cr_assert_float_eq(r->bbox_min[0], 5, 1e-6);
    cr_assert_float_eq(r->bbox_max[1], 18, 1e-6);
    cr_assert_float_eq(r->bbox_min[2], 1, 1e-6);
    double bad[12] = {0};
    hv_geometry *none = NULL;
    cr_assert_eq(hv_geometry_from_mesh(p, NULL, bad, 1, &none), HV_ERR_INVALID);
    cr_assert_null(none);
    hv_mesh_destroy(raw);
    hv_mesh_destroy(placed);
    hv_geometry_destroy(g);
    hv_mesh_destroy(p);
}

/* hv_geometry_transformed: every leaf moved by the matrix after its own transform, the tree and
 * the data kept; the placed mesh equals the leaf's placed mesh transformed by the matrix */
Test(geometry, transformed_moves_every_leaf)
{
    hv_mesh *p = plate(), *r = rod();
    hv_geometry *a = record_of(p, k_move), *b = record_of(r, NULL), *g = NULL, *t = NULL;
    cr_assert_eq(hv_geometry_combine(a, b, HV_GEOMETRY_SUBTRACT, &g), HV_OK);
    const double quarter[12] = {0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 3};
    cr_assert_eq(hv_geometry_transformed(g, quarter, &t), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_geometry_leaf_count(t), 2);
    cr_assert_eq(hv_geometry_node_count(t), hv_geometry_node_count(g));
    for (size_t i = 0; i < hv_geometry_node_count(g); ++i)
        cr_assert(memcmp(hv_geometry_node_at(g, i), hv_geometry_node_at(t, i), sizeof(hv_geometry_node)) == 0);
    for (size_t i = 0; i < 2; ++i) {
        hv_mesh *before = NULL, *moved = NULL, *after = NULL;
        cr_assert_eq(hv_geometry_leaf_mesh(g, i, &before), HV_OK);
        cr_assert_eq(hv_mesh_transform(before, quarter, &moved), HV_OK);
        cr_assert_eq(hv_geometry_leaf_mesh(t, i, &after), HV_OK);
        cr_assert_eq(hv_geometry_leaf_at(t, i)->hash, hv_geometry_leaf_at(g, i)->hash);
        const hv_mesh_report *x = hv_mesh_get_report(moved), *y = hv_mesh_get_report(after);
        for (int k = 0; k < 3; ++k) {
            cr_expect_float_eq(x->bbox_min[k], y->bbox_min[k], 1e-5);
            cr_expect_float_eq(x->bbox_max[k], y->bbox_max[k], 1e-5);
        }
        hv_mesh_destroy(before);
        hv_mesh_destroy(moved);
        hv_mesh_destroy(after);
    }
    /* the plate (moved by k_move: x 5..45, y -2..18) turned: x -18..2, y 5..45, z 4..14 */
    hv_mesh *pm = NULL;
    cr_assert_eq(hv_geometry_leaf_mesh(t, 0, &pm), HV_OK);
    cr_expect_float_eq(hv_mesh_get_report(pm)->bbox_min[0], -18, 1e-5);
    cr_expect_float_eq(hv_mesh_get_report(pm)->bbox_max[1], 45, 1e-5);
    cr_expect_float_eq(hv_mesh_get_report(pm)->bbox_min[2], 4, 1e-5);
    hv_mesh_destroy(pm);
    const double singular[12] = {0};
    hv_geometry *none = NULL;
    cr_expect_eq(hv_geometry_transformed(g, singular, &none), HV_ERR_INVALID);
    cr_expect_null(none);
    hv_geometry_destroy(t);
    hv_geometry_destroy(g);
    hv_geometry_destroy(a);
    hv_geometry_destroy(b);
    hv_mesh_destroy(p);
    hv_mesh_destroy(r);
}

static hv_volume *empty_model(void)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    return v;
}

static void same_record(const hv_geometry *a, const hv_geometry *b)
{
    cr_assert_eq(hv_geometry_leaf_count(a), hv_geometry_leaf_count(b));
    cr_assert_eq(hv_geometry_node_count(a), hv_geometry_node_count(b));
    for (size_t i = 0; i < hv_geometry_leaf_count(a); ++i) {
        const hv_geometry_leaf *x = hv_geometry_leaf_at(a, i), *y = hv_geometry_leaf_at(b, i);
        cr_assert_str_eq(x->name, y->name);
        cr_assert_eq(x->size, y->size);
        cr_assert_eq(x->hash, y->hash);
        cr_assert(memcmp(x->transform, y->transform, sizeof x->transform) == 0);
        cr_assert(memcmp(hv_geometry_leaf_data(a, i), hv_geometry_leaf_data(b, i), x->size) == 0);
    }
    for (size_t i = 0; i < hv_geometry_node_count(a); ++i) {
        const hv_geometry_node *x = hv_geometry_node_at(a, i), *y = hv_geometry_node_at(b, i);
        cr_assert_eq(x->op, y->op);
        if (x->op < 0) cr_assert_eq(x->leaf, y->leaf);
        else cr_assert(x->a == y->a && x->b == y->b);
    }
}

Test(geometry, combine_shares_leaves_and_orders_the_tree)
{
    hv_mesh *p = plate(), *r = rod();
    hv_geometry *gp = record_of(p, NULL), *gr = record_of(r, NULL), *g1 = NULL, *g2 = NULL;
    cr_assert_eq(hv_geometry_combine(gp, gr, HV_GEOMETRY_SUBTRACT, &g1), HV_OK);
    cr_assert_eq(hv_geometry_leaf_count(g1), 2);
    cr_assert_eq(hv_geometry_node_count(g1), 3);
    cr_assert_eq(hv_geometry_node_at(g1, 2)->op, HV_GEOMETRY_SUBTRACT);
    /* (plate - rod) u rod: the rod's leaf is shared */
    cr_assert_eq(hv_geometry_combine(g1, gr, HV_GEOMETRY_UNITE, &g2), HV_OK);
    cr_assert_eq(hv_geometry_leaf_count(g2), 2);
    cr_assert_eq(hv_geometry_node_count(g2), 5);
    const hv_geometry_node *root = hv_geometry_node_at(g2, 4);
    cr_assert_eq(root->a, 2);
    cr_assert_eq(root->b, 3);
    cr_assert_eq(hv_geometry_node_at(g2, 3)->leaf, 1);
    cr_assert_str_eq(hv_geometry_op_name(HV_GEOMETRY_DIFFERENCE), "difference");
    /* one part combined with itself (Wu's union of two gradings of his gear) is that part */
    hv_geometry *self_u = NULL, *self_s = NULL;
    cr_assert_eq(hv_geometry_combine(gp, gp, HV_GEOMETRY_UNITE, &self_u), HV_OK);
    cr_assert_eq(hv_geometry_combine(gp, gp, HV_GEOMETRY_SUBTRACT, &self_s), HV_OK);
    cr_assert_eq(hv_geometry_leaf_count(self_u), 1);
    cr_assert(hv_geometry_shape_is_leaf(self_u) && !hv_geometry_is_plain(self_u));
    cr_assert_not(hv_geometry_shape_is_leaf(self_s));
    cr_assert_not(hv_geometry_shape_is_leaf(g1));
    hv_solid *su = NULL;
    cr_assert_eq(hv_solid_open(self_u, NULL, &su), HV_OK);
    cr_assert(hv_solid_is_plain(su));
    hv_solid_close(su);
    hv_geometry_destroy(self_u);
    hv_geometry_destroy(self_s);
    /* in a model, and through a .vdb file */
    hv_volume *v = empty_model(), *back = NULL;
    int lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    cr_assert_eq(t_add_box(v, lo, hi), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, NULL), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_geometry_write(g2, v), HV_OK, "%s", hv_last_error());
    const char *path = t_tmpfile("record.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_load(path, &back), HV_OK, "%s", hv_last_error());
    hv_geometry *g3 = NULL;
    cr_assert_eq(hv_geometry_read(back, &g3), HV_OK, "%s", hv_last_error());
    same_record(g2, g3);
    /* writing another record replaces every leaf key */
    cr_assert_eq(hv_geometry_write(gp, back), HV_OK);
    int leaves = 0;
    for (int i = 0; i < hv_volume_meta_count(back); ++i)
        leaves += strncmp(hv_volume_meta_key(back, i), "hovox.geometry.leaf.", 20) == 0;
    cr_assert_eq(leaves, 1);
    cr_assert_eq(hv_geometry_write(NULL, back), HV_OK);
    cr_assert_not(hv_geometry_present(back));
    cr_assert_eq(hv_geometry_read(back, &g1 /* untouched on failure: set NULL */), HV_ERR_NOT_FOUND);
    cr_assert_null(g1);
    hv_geometry_destroy(g3);
    hv_geometry_destroy(g2);
    hv_geometry_destroy(gp);
    hv_geometry_destroy(gr);
    hv_volume_destroy(v);
    hv_volume_destroy(back);
    hv_mesh_destroy(p);
    hv_mesh_destroy(r);
}

/* A model holding the plate's record, with its document or a leaf replaced. */
static hv_status read_damaged(const char *key, const char *find, const char *repl)
{
    hv_mesh *p = plate();
    hv_geometry *g = record_of(p, NULL);
    hv_volume *v = empty_model();
    cr_assert_eq(hv_geometry_write(g, v), HV_OK);
    if (!key) key = hv_volume_meta_key(v, 1); /* the leaf's (keys are sorted: the doc first) */
    cr_assert(strncmp(hv_volume_meta_key(v, 1), "hovox.geometry.leaf.", 20) == 0);
    char *text = strdup(hv_volume_meta_string(v, key)), *k = strdup(key);
    if (find) {
        char *at = strstr(text, find);
        cr_assert_not_null(at, "%s in %s", find, text);
        char *fixed = malloc(strlen(text) + strlen(repl) + 1);
        memcpy(fixed, text, (size_t)(at - text));
        strcpy(fixed + (at - text), repl);
        strcat(fixed, at + strlen(find));
        cr_assert_eq(hv_volume_meta_set_string(v, k, fixed), HV_OK);
        free(fixed);
    } else {
        cr_assert_eq(hv_volume_meta_set_string(v, k, NULL), HV_OK);
    }
    hv_geometry *none = NULL;
    hv_status s = hv_geometry_read(v, &none);
    cr_assert_null(none);
    free(text);
    free(k);
    hv_volume_destroy(v);
    hv_geometry_destroy(g);
    hv_mesh_destroy(p);
    return s;
}

Test(geometry, damaged_records_are_refused)
{
    cr_assert_eq(read_damaged(NULL, NULL, NULL), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "refers to mesh 'box'") || strstr(hv_last_error(), "which the model does not hold"),
              "%s", hv_last_error());
    cr_assert_eq(read_damaged(NULL, "A", "B"), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "damaged"), "%s", hv_last_error());
    cr_assert_eq(read_damaged("hovox.geometry.json", "\"tree\": 0", "\"tree\": 3"), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "leaf 3, but the record has 1 leaves"), "%s", hv_last_error());
    cr_assert_eq(read_damaged("hovox.geometry.json", "\"tree\": 0", "\"tree\": {\"op\": \"xor\", \"a\": 0, \"b\": 0}"),
                 HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "xor"), "%s", hv_last_error());
    cr_assert_eq(read_damaged("hovox.geometry.json", "\"tree\": 0", "\"tree\": {\"op\": \"unite\", \"a\": 0}"), HV_ERR_BAD_INPUT);
    cr_assert_eq(read_damaged("hovox.geometry.json", "\"schema\": 1", "\"schema\": 7"), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "newer"), "%s", hv_last_error());
    cr_assert_eq(read_damaged("hovox.geometry.json", "\"size\": ", "\"size\": 1"), HV_ERR_BAD_INPUT);
}

Test(geometry, damaged_packed_meshes_are_refused)
{
    hv_mesh *p = plate();
    hv_geometry *g = record_of(p, NULL);
    size_t n = hv_geometry_leaf_at(g, 0)->size;
    uint8_t *d = malloc(n);
    /* every truncation, and a count or index made wrong, fails cleanly */
    for (size_t cut = 0; cut < n; cut += 7) {
        memcpy(d, hv_geometry_leaf_data(g, 0), n);
        hv_geometry *h = NULL;
        cr_assert_eq(hv_geometry_from_leaf(HV_LEAF_MESH, "cut", d, cut ? cut : 1, NULL, 1, &h), HV_OK);
        hv_mesh *m = NULL;
        cr_assert_eq(hv_geometry_leaf_mesh(h, 0, &m), HV_ERR_BAD_INPUT, "cut at %zu", cut);
        cr_assert_null(m);
        cr_assert(strstr(hv_last_error(), "recorded mesh 'cut'"), "%s", hv_last_error());
        hv_geometry_destroy(h);
    }
    memcpy(d, hv_geometry_leaf_data(g, 0), n);
    uint32_t big = 1000;
    memcpy(d + 24 + 12 * 8, &big, 4); /* facet 0's first vertex */
    hv_geometry *h = NULL;
    cr_assert_eq(hv_geometry_from_leaf(HV_LEAF_MESH, "idx", d, n, NULL, 1, &h), HV_OK);
    hv_mesh *m = NULL;
    cr_assert_eq(hv_geometry_leaf_mesh(h, 0, &m), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "names vertex 1000"), "%s", hv_last_error());
    hv_geometry_destroy(h);
    /* a material count of 2^32 - 1 is refused before its table is allocated (found by
     * fuzz_geometry: calloc of 17 GB; corpus entry mesh_material_count_2e32) */
    memcpy(d, hv_geometry_leaf_data(g, 0), n);
    uint32_t many = UINT32_MAX;
    memcpy(d + 16, &many, 4); /* after the magic and the vertex, facet and body counts */
    cr_assert_eq(hv_geometry_from_leaf(HV_LEAF_MESH, "mats", d, n, NULL, 1, &h), HV_OK);
    cr_assert_eq(hv_geometry_leaf_mesh(h, 0, &m), HV_ERR_BAD_INPUT, "%s", hv_last_error());
    cr_assert(strstr(hv_last_error(), "4294967295 materials in the"), "%s", hv_last_error());
    hv_geometry_destroy(h);
    free(d);
    hv_geometry_destroy(g);
    hv_mesh_destroy(p);
}

static hv_object *object_of(const hv_mesh *m)
{
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 1.0;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_OK, "%s", hv_last_error());
    hv_geometry *g = NULL;
    cr_assert_eq(hv_geometry_read(v, &g), HV_OK, "voxelize records its mesh: %s", hv_last_error());
    hv_mesh *back = NULL;
    cr_assert_eq(hv_geometry_leaf_mesh(g, 0, &back), HV_OK);
    same_mesh(m, back);
    hv_mesh_destroy(back);
    hv_geometry_destroy(g);
    hv_object *obj = NULL;
    cr_assert_eq(hv_object_create(v, "occupancy", 2, &obj), HV_OK);
    hv_volume_destroy(v);
    return obj;
}

Test(geometry, booleans_record_their_tree)
{
    hv_mesh *p = plate(), *r = rod();
    hv_object *op = object_of(p), *orod = object_of(r);
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_parse("A,B", NULL, NULL, 0, &t), HV_OK, "%s", hv_last_error());
    for (int op_ = HV_OP_INTERSECT; op_ <= HV_OP_SUBTRACT; ++op_) {
        hv_object *h = NULL;
        cr_assert_eq(hv_object_boolean(op, orod, (hv_bool_op)op_, &h), HV_OK, "%s", hv_last_error());
        hv_volume *v = NULL;
        cr_assert_eq(hv_object_evaluate(h, t, 0, NULL, &v), HV_OK, "%s", hv_last_error());
        hv_geometry *g = NULL;
        cr_assert_eq(hv_geometry_read(v, &g), HV_OK, "%s", hv_last_error());
        cr_assert_eq(hv_geometry_leaf_count(g), 2);
        cr_assert_eq(hv_geometry_node_at(g, 2)->op, op_);
        cr_assert_str_eq(hv_geometry_leaf_at(g, 1)->name, hv_mesh_name(r));
        hv_geometry_destroy(g);
        hv_volume_destroy(v);
        hv_object_destroy(h);
    }
    hv_material_table_destroy(t);
    hv_object_destroy(op);
    hv_object_destroy(orod);
    hv_mesh_destroy(p);
    hv_mesh_destroy(r);
}

Test(geometry, leaf_interface_on_a_mesh)
{
    hv_mesh *p = plate();
    hv_geometry *g = record_of(p, k_move);
    hv_leaf *l = NULL;
    cr_assert_eq(hv_leaf_open(g, 0, NULL, &l), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_leaf_get_kind(l), HV_LEAF_MESH);
    double lo[3], hi[3];
    hv_leaf_bbox(l, lo, hi);
    double want_lo[3] = {5, -2, 1}, want_hi[3] = {45, 18, 11};
    for (int a = 0; a < 3; ++a) {
        cr_assert_float_eq(lo[a], want_lo[a], 1e-6);
        cr_assert_float_eq(hi[a], want_hi[a], 1e-6);
    }
    hv_slice *sl = NULL;
    cr_assert_eq(hv_leaf_slice(l, 6, NULL, &sl), HV_OK);
    cr_assert_eq(hv_slice_get_stats(sl)->loops, 1);
    cr_assert_float_eq(hv_slice_get_stats(sl)->area, 800, 1e-6);
    hv_slice_destroy(sl);
    double in[3] = {6, 0, 2}, out_x[3] = {4.9, 0, 2}, out_z[3] = {6, 0, 11.5};
    cr_assert(hv_leaf_inside(l, in));
    cr_assert_not(hv_leaf_inside(l, out_x));
    cr_assert_not(hv_leaf_inside(l, out_z));
    cr_assert_not_null(hv_leaf_slicer(l));
    cr_assert_eq(hv_leaf_slice(l, NAN, NULL, &sl), HV_ERR_INVALID);
    hv_leaf_close(l);
    /* a kind this build cannot cut */
    uint8_t bytes[4] = {1, 2, 3, 4};
    hv_geometry *f = NULL;
    cr_assert_eq(hv_geometry_from_leaf(HV_LEAF_FIELD_ISO, "ct.nrrd", bytes, 4, NULL, 1, &f), HV_OK);
    hv_leaf *fl = NULL;
    hv_status s = hv_leaf_open(f, 0, NULL, &fl);
    cr_assert(s == HV_ERR_UNSUPPORTED || s == HV_OK || s == HV_ERR_BAD_INPUT);
    if (s == HV_OK) hv_leaf_close(fl);
    hv_geometry_destroy(f);
    hv_geometry_destroy(g);
    hv_mesh_destroy(p);
}

/* The solid of plate op rod against the analytic answer at points on a grid. */
Test(geometry, solid_of_a_tree_is_the_analytic_shape)
{
    hv_mesh *p = plate(), *r = rod();
    hv_geometry *gp = record_of(p, NULL), *gr = record_of(r, NULL);
    hv_geometry_op ops[4] = {HV_GEOMETRY_SUBTRACT, HV_GEOMETRY_UNITE, HV_GEOMETRY_INTERSECT, HV_GEOMETRY_DIFFERENCE};
    for (int k = 0; k < 4; ++k) {
        hv_geometry *g = NULL;
        cr_assert_eq(hv_geometry_combine(gp, gr, ops[k], &g), HV_OK);
        hv_solid *s = NULL;
        cr_assert_eq(hv_solid_open(g, NULL, &s), HV_OK, "%s", hv_last_error());
        cr_assert_not(hv_solid_is_plain(s));
        cr_assert_eq(hv_solid_leaf_count(s), 2);
        int wrong = 0, n = 0;
        for (double z = -0.75; z < 11.5; z += 1.5)
            for (double y = -1.3; y < 21; y += 0.7)
                for (double x = -1.1; x < 41; x += 0.9) {
                    double q[3] = {x, y, z}, d = hypot(x - 20, y - 10);
                    int in_p = x > 0 && x < 40 && y > 0 && y < 20 && z > 0 && z < 10;
                    int in_r = d < 5 && z > -1 && z < 11;
                    if (fabs(d - 5) < 0.02) continue; /* the 96-gon is within 0.0134 of the circle */
                    int want = k == 0 ? in_p && !in_r : k == 1 ? in_p || in_r : k == 2 ? in_p && in_r : in_p;
                    wrong += hv_solid_inside(s, q) != want;
                    ++n;
                }
        cr_assert_eq(wrong, 0, "op %s: %d of %d points wrong", hv_geometry_op_name(ops[k]), wrong, n);
        double lo[3], hi[3];
        hv_solid_bbox(s, lo, hi);
        double want_z[4][2] = {{0, 10}, {-1, 11}, {0, 10}, {0, 10}};
        cr_assert_float_eq(lo[2], want_z[k][0], 1e-6);
        cr_assert_float_eq(hi[2], want_z[k][1], 1e-6);
        hv_solid_close(s);
        hv_geometry_destroy(g);
    }
    hv_geometry_destroy(gp);
    hv_geometry_destroy(gr);
    hv_mesh_destroy(p);
    hv_mesh_destroy(r);
}

Test(geometry, slice_from_loops_nests)
{
    double outer[8] = {0, 0, 10, 0, 10, 10, 0, 10}, hole[8] = {2, 2, 2, 8, 8, 8, 8, 2}, dup[8] = {1, 1, 1, 1, 2, 2, 1, 1};
    const double *xy[3] = {hole, outer, dup};
    size_t count[3] = {4, 4, 4};
    hv_slice *sl = NULL;
    cr_assert_eq(hv_slice_from_loops(3, xy, count, 3, &sl), HV_OK);
    const hv_slice_stats *st = hv_slice_get_stats(sl);
    cr_assert_eq(st->loops, 2);
    cr_assert_eq(st->dropped, 1);
    cr_assert_eq(st->outers, 1);
    cr_assert_eq(st->holes, 1);
    cr_assert_float_eq(st->area, 64, 1e-12);
    const hv_slice_loop *L = hv_slice_loops(sl);
    cr_assert_eq(L[0].parent, 1);
    cr_assert_eq(L[0].depth, 1);
    hv_slice_destroy(sl);
    double nan_xy[2] = {NAN, 0};
    const double *bad[1] = {nan_xy};
    size_t one = 1;
    cr_assert_eq(hv_slice_from_loops(3, bad, &one, 1, &sl), HV_ERR_INVALID);
}
