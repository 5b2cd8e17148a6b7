/* tests/mesh/test_bodies.c - bodies and materials of meshes (hovox/mesh.h): the default body,
 * joining meshes into an assembly, extraction checked against the part meshes' own reports,
 * unique names. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/mesh.h"
#include "support/support.h"

static hv_mesh *box(double lo, double hi)
{
    hv_mesh *m = NULL;
    double a[3] = {lo, lo, lo}, b[3] = {hi, hi, hi};
    cr_assert_eq(hv_generate_box(a, b, &m), HV_OK, "%s", hv_last_error());
    return m;
}

Test(bodies, a_loaded_stl_is_one_body_named_after_the_file)
{
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_load(t_mesh_path("helical_gear.stl"), &m), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_mesh_body_count(m), 1);
    const hv_mesh_body *b = hv_mesh_body_at(m, 0);
    cr_assert_str_eq(b->name, "helical_gear");
    cr_assert_eq(b->material, HV_MESH_NO_MATERIAL);
    cr_assert_eq(b->first_facet, 0);
    cr_assert_eq(b->facet_count, hv_mesh_facet_count(m));
    cr_assert_eq(hv_mesh_material_count(m), 0);
    cr_assert_null(hv_mesh_facet_materials(m));
    cr_assert_eq(hv_mesh_body_find(m, "helical_gear"), 0);
    cr_assert_eq(hv_mesh_body_find(m, "gear"), -1);
    cr_assert_null(hv_mesh_body_at(m, 1));
    hv_mesh_destroy(m);
}

Test(bodies, join_makes_named_bodies_with_materials_and_extract_gives_the_parts_back)
{
    hv_mesh *outer = box(0, 10), *inner = box(3, 7), *j = NULL;
    hv_mesh_part parts[3] = {{inner, "core", "Agilus"}, {outer, "shell", "Vero"}, {inner, "core", "Agilus"}};
    cr_assert_eq(hv_mesh_join(parts, 3, &j), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_mesh_body_count(j), 3);
    cr_assert_eq(hv_mesh_material_count(j), 2);
    cr_assert_str_eq(hv_mesh_material_at(j, 0)->name, "Agilus");
    cr_assert_str_eq(hv_mesh_material_at(j, 1)->name, "Vero");
    cr_assert_str_eq(hv_mesh_body_at(j, 0)->name, "core");
    cr_assert_str_eq(hv_mesh_body_at(j, 1)->name, "shell");
    cr_assert_str_eq(hv_mesh_body_at(j, 2)->name, "core (2)"); /* made unique */
    cr_assert_eq(hv_mesh_body_at(j, 0)->material, 0);
    cr_assert_eq(hv_mesh_body_at(j, 1)->material, 1);
    cr_assert_eq(hv_mesh_body_at(j, 1)->first_facet, hv_mesh_facet_count(inner));
    cr_assert_eq(hv_mesh_facet_count(j), 2 * hv_mesh_facet_count(inner) + hv_mesh_facet_count(outer));
    /* the whole report sums the bodies' volumes (one mesh of all facets) */
    double vi = hv_mesh_get_report(inner)->volume, vo = hv_mesh_get_report(outer)->volume;
    cr_assert_float_eq(hv_mesh_get_report(j)->volume, 2 * vi + vo, 1e-9 * vo);
    for (size_t i = 0; i < 3; ++i) {
        hv_mesh *e = NULL;
        cr_assert_eq(hv_mesh_body_extract(j, i, &e), HV_OK, "%s", hv_last_error());
        const hv_mesh *ref = i == 1 ? outer : inner;
        const hv_mesh_report *re = hv_mesh_get_report(e), *rr = hv_mesh_get_report(ref);
        cr_assert_eq(re->facets, rr->facets);
        cr_assert_eq(re->vertices, rr->vertices);
        cr_assert_eq(re->shells, 1);
        cr_assert_eq(re->open_edges, 0);
        cr_assert_float_eq(re->volume, rr->volume, 1e-12 * rr->volume);
        cr_assert_eq(hv_mesh_body_count(e), 1);
        cr_assert_str_eq(hv_mesh_body_at(e, 0)->name, hv_mesh_body_at(j, i)->name);
        cr_assert_eq(hv_mesh_body_at(e, 0)->material, hv_mesh_body_at(j, i)->material);
        cr_assert_eq(hv_mesh_material_count(e), 2);
        hv_mesh_destroy(e);
    }
    hv_mesh *e = NULL;
    cr_assert_eq(hv_mesh_body_extract(j, 3, &e), HV_ERR_INVALID);
    cr_assert_null(e);
    hv_mesh_destroy(j);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
}

Test(bodies, join_without_names_or_materials)
{
    hv_mesh *a = box(0, 1), *j = NULL;
    hv_mesh_part parts[2] = {{a, NULL, NULL}, {a, "", NULL}};
    cr_assert_eq(hv_mesh_join(parts, 2, &j), HV_OK, "%s", hv_last_error());
    cr_assert_str_eq(hv_mesh_body_at(j, 0)->name, "body 1");
    cr_assert_str_eq(hv_mesh_body_at(j, 1)->name, "body 2");
    cr_assert_eq(hv_mesh_body_at(j, 1)->material, HV_MESH_NO_MATERIAL);
    cr_assert_eq(hv_mesh_material_count(j), 0);
    hv_mesh_destroy(j);
    cr_assert_eq(hv_mesh_join(parts, 0, &j), HV_ERR_INVALID);
    hv_mesh_part none = {NULL, "x", NULL};
    cr_assert_eq(hv_mesh_join(&none, 1, &j), HV_ERR_INVALID);
    cr_assert_null(j);
    hv_mesh_destroy(a);
}

/* Issue 27 item 2: a body's material from the command line (voxelize --material BODY=NAME). */
Test(bodies, a_body_takes_a_material_by_name_new_or_existing)
{
    hv_mesh *a = box(0, 1), *b = box(2, 3), *j = NULL;
    hv_mesh_part parts[2] = {{a, "core", NULL}, {b, "shell", "Vero"}};
    cr_assert_eq(hv_mesh_join(parts, 2, &j), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_mesh_material_count(j), 1);
    cr_assert_eq(hv_mesh_body_material_set(j, "core", "Agilus"), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_mesh_material_count(j), 2); /* a new material */
    cr_assert_str_eq(hv_mesh_material_at(j, (size_t)hv_mesh_body_at(j, 0)->material)->name, "Agilus");
    cr_assert_eq(hv_mesh_body_material_set(j, "core", "Vero"), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_mesh_material_count(j), 2); /* an existing one is reused */
    cr_assert_eq(hv_mesh_body_at(j, 0)->material, hv_mesh_body_at(j, 1)->material);
    cr_assert_str_eq(hv_mesh_body_at(j, 1)->name, "shell"); /* the rest unchanged */
    cr_assert_eq(hv_mesh_body_at(j, 1)->facet_count, hv_mesh_facet_count(b));
    cr_assert_eq(hv_mesh_body_material_set(j, "hub", "Vero"), HV_ERR_NOT_FOUND);
    cr_assert(strstr(hv_last_error(), "no body 'hub' (bodies: core, shell)"), "%s", hv_last_error());
    cr_assert_eq(hv_mesh_body_material_set(j, "core", ""), HV_ERR_INVALID);
    hv_mesh_destroy(j);
    /* a file's one body, by the file's name */
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_load(t_mesh_path("helical_gear.stl"), &m), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_mesh_body_material_set(m, "helical_gear", "VeroCyan-V"), HV_OK, "%s", hv_last_error());
    cr_assert_str_eq(hv_mesh_material_at(m, (size_t)hv_mesh_body_at(m, 0)->material)->name, "VeroCyan-V");
    hv_mesh_destroy(m);
    hv_mesh_destroy(a);
    hv_mesh_destroy(b);
}
