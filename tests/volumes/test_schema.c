/* tests/volumes/test_schema.c - the model metadata schema (volumes/schema.h): every document
 * round-trips, carries "schema" first, refuses unknown and newer versions and malformed JSON
 * with messages naming the key, and models written before schema versions (no "schema") load. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/geometry.h"
#include "support/support.h"
#include "volumes/schema.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"
#include "mesh/mesh_internal.h"
#include "voxel/voxel_internal.h"
#include "material/material_internal.h"

/* tests/data/models/legacy_graded.vdb: written by hovox 0.1.0 (before schema versions). */
static const char *legacy_path(void)
{
    static char path[1024];
    snprintf(path, sizeof path, "%s/models/legacy_graded.vdb", t_shared());
    return path;
}

static hv_volume *load(const char *path)
{
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_load(path, &v), HV_OK, "%s", hv_last_error());
    return v;
}

/* A small voxelized and graded box (point source with an f table, contour step, idw): the
 * graded volume, the object and its table. */
typedef struct graded {
    hv_volume *g;
    hv_object *ob;
    hv_material_table *t;
} graded;

static graded graded_box(void)
{
    double lo[3] = {0, 0, 0}, hi[3] = {6, 4, 3};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_box(lo, hi, &m), HV_OK);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_OK, "%s", hv_last_error());
    hv_mesh_destroy(m);
    hv_material_table *t;
    cr_assert_eq(hv_material_table_create(&t), HV_OK);
    float red[4] = {0.8f, 0.1f, 0.3f, 1};
    cr_assert_eq(hv_material_add(t, "soft", red, NULL), HV_OK);
    cr_assert_eq(hv_material_add(t, "rigid", NULL, NULL), HV_OK);
    cr_assert_eq(hv_material_set_property(t, 1, "density", 1180.5, "kg/m^3"), HV_OK);
    hv_object *ob;
    cr_assert_eq(hv_object_create(v, "occupancy", 2, &ob), HV_OK, "%s", hv_last_error());
    double p[3] = {1, 1, 1}, ms[2] = {1, 0}, me[2] = {0, 1};
    hv_frf *point, *contour;
    cr_assert_eq(hv_frf_point(p, &point), HV_OK);
    cr_assert_eq(hv_frf_contour(v, "occupancy", &contour), HV_OK);
    hv_dfn *f;
    cr_assert_eq(hv_dfn_expr("(d/dg)^2", &f), HV_OK);
    hv_ags_desc d1 = {point, 0.25, 3.3, 0, f, ms, me, 2, "radial"}, d2 = {contour, 1, 0, 0, NULL, me, ms, 2, NULL};
    hv_ags *a1, *a2;
    cr_assert_eq(hv_ags_create(&d1, &a1), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_ags_create(&d2, &a2), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_add_ags(ob, a1), HV_OK);
    cr_assert_eq(hv_object_add_ags(ob, a2), HV_OK);
    cr_assert_eq(hv_object_set_blend(ob, HV_BLEND_IDW, 1.5), HV_OK);
    hv_volume *g;
    cr_assert_eq(hv_object_evaluate(ob, t, 0, NULL, &g), HV_OK, "%s", hv_last_error());
    hv_ags_release(a1);
    hv_ags_release(a2);
    hv_frf_release(point);
    hv_frf_release(contour);
    hv_dfn_destroy(f);
    hv_volume_destroy(v);
    return (graded){g, ob, t};
}

static void graded_free(graded *x)
{
    hv_volume_destroy(x->g);
    hv_object_destroy(x->ob);
    hv_material_table_destroy(x->t);
}

/* Each document written by the current code starts with "schema": its version (the object's
 * the oldest that holds it: 1 without named regions), reads back, and writes again to the same
 * text. The regions of an assembly round-trip in tests/voxel/test_assembly.c; the geometry
 * record's refusals are tested in tests/geometry/test_geometry.c. */
Test(schema, documents_round_trip, .timeout = 60)
{
    graded x = graded_box();
    hv_volume *g = x.g;
    for (int d = 0; d < HV_DOC_COUNT; ++d) {
        if (d == HV_DOC_REGIONS) continue;
        const char *key = hv_schema_key((hv_schema_doc)d);
        const char *text = hv_volume_meta_string(g, key);
        cr_assert_not_null(text, "%s missing", key);
        int version = d == HV_DOC_OBJECT ? 1 : hv_schema_version((hv_schema_doc)d);
        char head[32];
        snprintf(head, sizeof head, "{\"schema\": %d, ", version);
        cr_assert(strncmp(text, head, strlen(head)) == 0, "%s: %.60s", key, text);
        json_t *doc;
        cr_assert_eq(hv_schema_doc_read(g, (hv_schema_doc)d, &doc), HV_OK, "%s", hv_last_error());
        json_t *again = NULL;
        if (d == HV_DOC_MESH) {
            hv_mesh_report r;
            cr_assert_eq(hv_mesh_report_from_doc(doc, key, &r), HV_OK, "%s", hv_last_error());
            cr_assert_eq(r.facets, 12);
            cr_assert_eq(r.bbox_max[0], 6);
            cr_assert_float_eq(r.volume, 72, 1e-9);
            again = hv_mesh_report_to_doc(json_string_value(json_object_get(doc, "file")), &r);
        } else if (d == HV_DOC_VOXELIZE) {
            hv_voxelize_record rec;
            cr_assert_eq(hv_voxelize_from_doc(doc, key, &rec), HV_OK, "%s", hv_last_error());
            cr_assert_eq(rec.adjacency, 26);
            cr_assert_eq(rec.fill, HV_FILL_FLOOD);
            cr_assert_eq(rec.voxel[1], 0.5);
            hv_voxel_plan plan;
            memset(&plan, 0, sizeof plan);
            memcpy(plan.first, rec.first, sizeof plan.first);
            memcpy(plan.dims, rec.dims, sizeof plan.dims);
            memcpy(plan.xf.voxel, rec.voxel, sizeof plan.xf.voxel);
            plan.fill = rec.fill;
            again = hv_voxelize_to_doc(&plan, rec.adjacency);
        } else if (d == HV_DOC_GEOMETRY) {
            hv_geometry *r;
            cr_assert_eq(hv_geometry_read(g, &r), HV_OK, "%s", hv_last_error());
            cr_assert_eq(hv_geometry_leaf_at(r, 0)->kind, HV_LEAF_MESH);
            hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
            hv_volume *w;
            cr_assert_eq(hv_volume_create(&xf, &w), HV_OK);
            cr_assert_eq(hv_geometry_write(r, w), HV_OK);
            cr_assert_eq(hv_schema_doc_read(w, HV_DOC_GEOMETRY, &again), HV_OK);
            json_object_del(again, "schema");
            hv_volume_destroy(w);
            hv_geometry_destroy(r);
        } else if (d == HV_DOC_MATERIALS) {
            hv_material_table *r;
            cr_assert_eq(hv_material_table_from_doc(doc, key, &r), HV_OK, "%s", hv_last_error());
            float c[4];
            hv_material_color(r, 0, c);
            cr_assert_eq(c[0], 0.8f); /* floats read back exactly */
            double v;
            cr_assert(hv_material_property(r, 1, "density", &v, NULL) && v == 1180.5);
            again = hv_material_table_to_doc(r);
            hv_material_table_destroy(r);
        } else {
            hv_object *r;
            cr_assert_eq(hv_object_from_doc(doc, g, &r), HV_OK, "%s", hv_last_error());
            cr_assert_eq(hv_object_voxels(r), hv_object_voxels(x.ob));
            cr_assert_eq(hv_object_to_doc(r, &again), HV_OK);
            hv_object_destroy(r);
        }
        char *out = hv_schema_doc_dump_version((hv_schema_doc)d, again, version);
        cr_assert_str_eq(out, text, "%s does not write back the same", key);
        free(out);
        json_decref(again);
        json_decref(doc);
    }
    hv_voxelize_record rec;
    cr_assert_eq(hv_voxelize_record_read(g, &rec), HV_OK, "%s", hv_last_error());
    cr_assert_eq(rec.mesh.bbox_max[1], 4);
    cr_assert_eq(rec.dims[0], 12, "%lld", (long long)rec.dims[0]); /* 0..6 at 0.5: centres 0.25 .. 5.75 */
    graded_free(&x);
}

/* Replace the document under `key` by `text` and expect every reader of it to refuse it. */
static void expect_refused(hv_volume *g, hv_schema_doc d, const char *text, const char *message)
{
    const char *key = hv_schema_key(d);
    char *old = strdup(hv_volume_meta_string(g, key));
    cr_assert_eq(hv_volume_meta_set_string(g, key, text), HV_OK);
    hv_status s;
    if (d == HV_DOC_MESH || d == HV_DOC_VOXELIZE) {
        hv_voxelize_record rec;
        s = hv_voxelize_record_read(g, &rec);
    } else if (d == HV_DOC_MATERIALS) {
        hv_material_table *t = NULL;
        s = hv_material_table_load(g, &t);
        cr_assert_null(t);
    } else {
        hv_object *o = NULL;
        s = hv_object_from_model(g, &o);
        cr_assert_null(o);
    }
    cr_expect_eq(s, HV_ERR_BAD_INPUT, "%s: %s accepted", key, text);
    cr_expect_str_eq(hv_last_error(), message);
    cr_assert_eq(hv_volume_meta_set_string(g, key, old), HV_OK);
    free(old);
}

Test(schema, unknown_and_newer_versions_are_refused, .timeout = 60)
{
    graded x = graded_box();
    hv_volume *g = x.g;
    expect_refused(g, HV_DOC_OBJECT, "{\"schema\": 3, \"materials\": 2}",
                   "hovox.object.json: schema 3 is newer than this hovox reads (2): written by a newer hovox");
    expect_refused(g, HV_DOC_MATERIALS, "{\"schema\": 0, \"materials\": []}",
                   "hovox.materials.json: schema 0 is not a version hovox knows (it reads 1)");
    expect_refused(g, HV_DOC_MESH, "{\"schema\": \"1\"}",
                   "hovox.mesh.json: schema \"1\" is not a version hovox knows (it reads 1)");
    expect_refused(g, HV_DOC_VOXELIZE, "{\"schema\": 1.5}",
                   "hovox.voxelize.json: schema 1.5 is not a version hovox knows (it reads 1)");
    expect_refused(g, HV_DOC_OBJECT, "{\"schema\": -1}",
                   "hovox.object.json: schema -1 is not a version hovox knows (it reads 1 to 2)");
    expect_refused(g, HV_DOC_OBJECT, "{\"schema\": 99999999999999999999}",
                   "hovox.object.json: line 1, column 31: too big integer near '99999999999999999999'");
    expect_refused(g, HV_DOC_MATERIALS, "[1, 2]", "hovox.materials.json: the document is not a JSON object");
    graded_free(&x);
}

Test(schema, malformed_documents_say_where, .timeout = 60)
{
    graded x = graded_box();
    hv_volume *g = x.g;
    expect_refused(g, HV_DOC_OBJECT, "{\"schema\": 1,\n \"materials\" 2}",
                   "hovox.object.json: line 2, column 14: ':' expected near '2'");
    expect_refused(g, HV_DOC_MATERIALS, "{\"materials\": [{\"name\": \"A\", \"color\": [1, 0]}]}",
                   "hovox.materials.json: materials[0]: color has 2 values, not 4");
    expect_refused(g, HV_DOC_MATERIALS,
                   "{\"materials\": [{\"name\": \"A\", \"properties\": {\"density\": {\"unit\": \"kg\"}}}]}",
                   "hovox.materials.json: materials[0]: properties: density: value is missing");
    expect_refused(g, HV_DOC_MESH, "{\"format\": \"ply\"}",
                   "hovox.mesh.json: format \"ply\" is not one of generated, binary, ascii, 3mf, obj, ply_ascii, ply_binary_le or "
                   "ply_binary_be");
    expect_refused(g, HV_DOC_VOXELIZE,
                   "{\"adjacency\": 26, \"fill\": \"wet\", \"first\": [0, 0, 0], \"dims\": [1, 1, 1], \"voxel\": [1, 1, 1]}",
                   "hovox.voxelize.json: fill \"wet\" is not one of auto, flood, vote or none");
    /* a model without the documents: not found, not malformed */
    hv_volume_meta_set_string(g, "hovox.mesh.json", NULL);
    hv_voxelize_record rec;
    cr_expect_eq(hv_voxelize_record_read(g, &rec), HV_ERR_NOT_FOUND);
    cr_expect_str_eq(hv_last_error(), "the model has no hovox.mesh.json");
    graded_free(&x);
}

/* Enum names are refused on read: a definition whose blend is "bogus" does not rebuild (it
 * used to become "nearest"), nor does a feature of an unknown kind. */
Test(schema, unknown_names_are_refused_on_read, .timeout = 60)
{
    hv_volume *g = load(legacy_path());
    char *text = strdup(hv_volume_meta_string(g, "hovox.object.json")); /* setting the key frees it */
    const char *at = strstr(text, "\"blend\": \"idw\"");
    cr_assert_not_null(at);
    size_t n = strlen(text);
    char *bogus = malloc(n + 8);
    memcpy(bogus, text, (size_t)(at - text));
    strcpy(bogus + (at - text), "\"blend\": \"bogus\"");
    strcat(bogus, at + strlen("\"blend\": \"idw\""));
    expect_refused(g, HV_DOC_OBJECT, bogus, "hovox.object.json: blend \"bogus\" is not one of nearest or idw");
    at = strstr(text, "\"kind\": \"point\"");
    cr_assert_not_null(at);
    memcpy(bogus, text, (size_t)(at - text));
    strcpy(bogus + (at - text), "\"kind\": \"torus\"");
    strcat(bogus, at + strlen("\"kind\": \"point\""));
    expect_refused(g, HV_DOC_OBJECT, bogus,
                   "hovox.object.json: features[0]: kind \"torus\" is not one of point, axis, plane, halfspace, segment, contour, mask, facets, harmonic or field");
    free(bogus);
    free(text);
    hv_blend b;
    cr_assert_eq(hv_blend_parse("idw", &b), HV_OK);
    cr_assert_eq(b, HV_BLEND_IDW);
    cr_assert_str_eq(hv_blend_name(HV_BLEND_NEAREST), "nearest");
    cr_assert_eq(hv_blend_parse("Nearest", &b), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "blend must be nearest or idw, got 'Nearest'");
    hv_fill_mode f;
    cr_assert_eq(hv_fill_mode_parse("vote", &f), HV_OK);
    cr_assert_eq(f, HV_FILL_VOTE);
    cr_assert_eq(hv_fill_mode_parse("winding", &f), HV_OK, "the documented alias of vote");
    cr_assert_eq(f, HV_FILL_VOTE);
    cr_assert_eq(hv_fill_mode_parse("wet", &f), HV_ERR_INVALID);
    hv_volume_destroy(g);
}

/* A model hovox 0.1.0 wrote (no "schema" in any document, "version": 1 in the definition) loads:
 * its record, its table, and its definition, which evaluates to the grids stored with it. */
Test(schema, models_without_schema_versions_load, .timeout = 60)
{
    hv_volume *g = load(legacy_path());
    for (int d = 0; d < HV_DOC_COUNT; ++d)
        if (d != HV_DOC_REGIONS && d != HV_DOC_GEOMETRY) /* 0.1.0 had no assemblies nor geometry records */
            cr_assert_null(strstr(hv_volume_meta_string(g, hv_schema_key((hv_schema_doc)d)), "\"schema\""));
    hv_voxelize_record rec;
    cr_assert_eq(hv_voxelize_record_read(g, &rec), HV_OK, "%s", hv_last_error());
    cr_assert_eq(rec.mesh.facets, 120);
    cr_assert_eq(rec.mesh.bbox_min[0], 1.5);
    cr_assert_eq(rec.fill, HV_FILL_FLOOD);
    cr_assert_eq(rec.dims[2], 6);
    hv_material_table *t;
    cr_assert_eq(hv_material_table_load(g, &t), HV_OK, "%s", hv_last_error());
    cr_assert_str_eq(hv_material_name(t, 1), "B");
    hv_object *o;
    cr_assert_eq(hv_object_from_model(g, &o), HV_OK, "%s", hv_last_error());
    hv_volume *again;
    cr_assert_eq(hv_object_evaluate(o, t, 0, NULL, &again), HV_OK, "%s", hv_last_error());
    long compared = 0;
    for (int m = 0; m < 2; ++m) {
        int ga = hv_material_grid(g, t, m), gb = hv_material_grid(again, t, m);
        hv_accessor aa, ab;
        hv_accessor_init(&aa, g);
        hv_accessor_init(&ab, again);
        for (int i = 0; i < 8; ++i)
            for (int j = 0; j < 8; ++j)
                for (int k = 0; k < 8; ++k) {
                    cr_assert_eq(hv_accessor_active(&aa, i, j, k), hv_accessor_active(&ab, i, j, k));
                    if (!hv_accessor_active(&aa, i, j, k)) continue;
                    cr_assert_float_eq(hv_accessor_float(&aa, ga, i, j, k), hv_accessor_float(&ab, gb, i, j, k), 1e-6);
                    ++compared;
                }
    }
    cr_assert_gt(compared, 200);
    /* graded again: the definition and table carry the current version, the model's own record
     * is carried over as the model has it */
    cr_assert(strncmp(hv_volume_meta_string(again, "hovox.object.json"), "{\"schema\": 1, \"materials\": 2, ", 30) == 0);
    cr_assert(strncmp(hv_volume_meta_string(again, "hovox.materials.json"), "{\"schema\": 1, ", 14) == 0);
    cr_assert_str_eq(hv_volume_meta_string(again, "hovox.mesh.json"), hv_volume_meta_string(g, "hovox.mesh.json"));
    cr_assert_geq(hv_volume_grid_find(again, "surface"), 0);
    hv_volume_destroy(again);
    hv_object_destroy(o);
    hv_material_table_destroy(t);
    hv_volume_destroy(g);
}
