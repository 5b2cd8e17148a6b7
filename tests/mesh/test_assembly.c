/* tests/mesh/test_assembly.c - assemblies out and moved (hovox/mesh.h): the OBJ writer (bodies as
 * `o` groups with `usemtl`, read back here by a small independent parser), and transforms that
 * keep bodies and materials (a mirror keeps the facets outward). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/mesh.h"
#include "support/support.h"


Test(assembly_out, obj_holds_every_body_in_order_with_its_material)
{
    hv_mesh *outer = t_cube_mesh(0, 10), *inner = t_cube_mesh(3, 7), *j = NULL;
    hv_mesh_part parts[3] = {{inner, "core", "Agilus"}, {outer, "shell", "Vero"}, {inner, "pin\nx", NULL}};
    cr_assert_eq(hv_mesh_join(parts, 3, &j), HV_OK, "%s", hv_last_error());
    const char *path = t_tmpfile("a.obj");
    cr_assert_eq(hv_mesh_write_obj(j, path), HV_OK, "%s", hv_last_error());
    char *text = t_slurp(path, NULL);
    /* parse it back: vertices, then per `o` group its usemtl and facets */
    size_t nv = 0, nf = 0, groups = 0, in_group[3] = {0};
    char names[3][32] = {{0}}, mats[3][32] = {{0}};
    double vol = 0;
    float *v = malloc(3 * sizeof(float) * hv_mesh_vertex_count(j));
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        if (line[0] == 'v' && line[1] == ' ') {
            cr_assert_eq(sscanf(line + 2, "%f %f %f", &v[3 * nv], &v[3 * nv + 1], &v[3 * nv + 2]), 3);
            ++nv;
        } else if (line[0] == 'o') {
            cr_assert(groups < 3);
            snprintf(names[groups++], 32, "%s", line + 2);
        } else if (strncmp(line, "usemtl", 6) == 0) {
            snprintf(mats[groups - 1], 32, "%s", line[6] ? line + 7 : "(none)");
        } else if (line[0] == 'f') {
            unsigned a, b, c;
            cr_assert_eq(sscanf(line + 2, "%u %u %u", &a, &b, &c), 3);
            cr_assert(a >= 1 && a <= nv && b >= 1 && b <= nv && c >= 1 && c <= nv);
            const float *p = v + 3 * (a - 1), *q = v + 3 * (b - 1), *r = v + 3 * (c - 1);
            vol += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
                    p[2] * (q[0] * r[1] - q[1] * r[0])) / 6.0;
            ++in_group[groups - 1];
            ++nf;
        }
    }
    cr_assert_eq(nv, hv_mesh_vertex_count(j));
    cr_assert_eq(nf, hv_mesh_facet_count(j));
    cr_assert_eq(groups, 3);
    cr_assert_str_eq(names[0], "core");
    cr_assert_str_eq(names[1], "shell");
    cr_assert_str_eq(names[2], "pin_x"); /* the newline would end the statement */
    cr_assert_str_eq(mats[0], "Agilus");
    cr_assert_str_eq(mats[1], "Vero");
    cr_assert_str_eq(mats[2], "(none)"); /* a bare usemtl ends Vero */
    for (int g = 0; g < 3; ++g) cr_assert_eq(in_group[g], hv_mesh_body_at(j, (size_t)g)->facet_count);
    cr_assert_float_eq(vol, hv_mesh_get_report(j)->volume, 1e-6 * fabs(vol));
    free(v);
    free(text);
    cr_assert_eq(hv_mesh_write_obj(j, t_tmpfile("a.stl")), HV_ERR_INVALID);
    cr_assert(!t_exists(t_tmpfile("a.stl")));
    hv_mesh_destroy(j);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
}

Test(assembly_out, a_transform_keeps_bodies_and_materials_and_a_mirror_stays_outward)
{
    hv_mesh *outer = t_cube_mesh(0, 10), *inner = t_cube_mesh(3, 7), *j = NULL, *t = NULL, *m = NULL;
    hv_mesh_part parts[2] = {{inner, "core", "Agilus"}, {outer, "shell", "Vero"}};
    cr_assert_eq(hv_mesh_join(parts, 2, &j), HV_OK, "%s", hv_last_error());
    const double quarter[12] = {0, -1, 0, 100, 1, 0, 0, 0, 0, 0, 1, 5}; /* a quarter turn about z, moved */
    cr_assert_eq(hv_mesh_transform(j, quarter, &t), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_mesh_body_count(t), 2);
    cr_assert_str_eq(hv_mesh_body_at(t, 0)->name, "core");
    cr_assert_str_eq(hv_mesh_material_at(t, (size_t)hv_mesh_body_at(t, 1)->material)->name, "Vero");
    const hv_mesh_report *r = hv_mesh_get_report(t), *r0 = hv_mesh_get_report(j);
    cr_assert_float_eq(r->volume, r0->volume, 1e-9 * r0->volume);
    cr_assert_float_eq(r->bbox_min[0], 90, 1e-9);
    cr_assert_float_eq(r->bbox_max[0], 100, 1e-9);
    cr_assert_float_eq(r->bbox_min[2], 5, 1e-9);
    const double mirror[12] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    cr_assert_eq(hv_mesh_transform(j, mirror, &m), HV_OK, "%s", hv_last_error());
    cr_assert(hv_mesh_get_report(m)->volume > 0, "a mirrored assembly keeps its facets outward");
    cr_assert_eq(hv_mesh_get_report(m)->flipped_facets, 0);
    const double flat[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0};
    hv_mesh *f = (hv_mesh *)1;
    cr_assert_eq(hv_mesh_transform(j, flat, &f), HV_ERR_INVALID);
    cr_assert_null(f);
    const double nan_[12] = {NAN, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    cr_assert_eq(hv_mesh_transform(j, nan_, &f), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "not finite"), "%s", hv_last_error());
    hv_mesh_destroy(m);
    hv_mesh_destroy(t);
    hv_mesh_destroy(j);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
}
