/* tests/io/test_obj.c - the OBJ reader: shared meshes written as OBJ by the test read back
 * with the STL reader's report, polygons, index forms, bodies from o/g, materials from usemtl,
 * and one exact message for each kind of bad input. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/mesh.h"
#include "reader_check.h"
#include "support/support.h"

/* The mesh as OBJ text; corners written as `form` (0: v, 1: v/vt, 2: v//vn, 3: v/vt/vn), with
 * negative (relative) indices when `relative`. */
static char *as_obj(const hv_mesh *m, int form, int relative, size_t *len)
{
    hv_buf b;
    hv_buf_init(&b);
    size_t nv = hv_mesh_vertex_count(m), nf = hv_mesh_facet_count(m);
    const float *xyz = hv_mesh_vertices(m);
    const uint32_t *t = hv_mesh_facets(m);
    hv_buf_printf(&b, "# written by test_obj\r\nmtllib none.mtl\nvt 0 0\nvn 0 0 1\n");
    for (size_t v = 0; v < nv; ++v)
        hv_buf_printf(&b, "v %.9g %.9g %.9g\n", (double)xyz[3 * v], (double)xyz[3 * v + 1], (double)xyz[3 * v + 2]);
    for (size_t f = 0; f < nf; ++f) {
        hv_buf_puts(&b, "f");
        for (int c = 0; c < 3; ++c) {
            long long i = relative ? (long long)t[3 * f + c] - (long long)nv : (long long)t[3 * f + c] + 1;
            static const char *const suffix[] = {"", "/1", "//1", "/1/1"};
            hv_buf_printf(&b, " %lld%s", i, suffix[form]);
        }
        hv_buf_puts(&b, f % 2 ? "\n" : "   # a comment\r\n");
    }
    cr_assert(!b.failed);
    *len = b.len;
    return b.data;
}

static hv_mesh *parse(const char *text, const char *name)
{
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_parse_obj(text, strlen(text), name, &m), HV_OK, "%s", hv_last_error());
    return m;
}

Test(obj, shared_meshes_read_back_with_the_stl_readers_report)
{
    static const char *const names[] = {"helical_gear.stl", "bunny_1500.stl", "bolt_colored_header.stl"};
    for (size_t k = 0; k < sizeof names / sizeof *names; ++k) {
        hv_mesh *ref = stl_reference(names[k]);
        for (int form = 0; form < 4; ++form) {
            size_t len;
            char *text = as_obj(ref, form, form == 3, &len);
            hv_mesh *m = NULL;
            cr_assert_eq(hv_mesh_parse_obj(text, len, "ref.obj", &m), HV_OK, "%s", hv_last_error());
            cr_assert_eq(hv_mesh_get_report(m)->format, HV_MESH_OBJ);
            same_report(m, ref, 0);
            cr_assert_eq(hv_mesh_body_count(m), 1);
            cr_assert_str_eq(hv_mesh_body_at(m, 0)->name, "ref");
            cr_assert_eq(hv_mesh_material_count(m), 0);
            hv_mesh_destroy(m);
            free(text);
        }
        hv_mesh_destroy(ref);
    }
}

static const char k_cube[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
static const char k_cube_quads[] = "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

Test(obj, polygons_are_fans_and_the_cube_is_closed)
{
    char text[512];
    snprintf(text, sizeof text, "%s%s", k_cube, k_cube_quads);
    hv_mesh *m = parse(text, "cube.obj");
    const hv_mesh_report *r = hv_mesh_get_report(m);
    cr_assert_eq(r->facets, 12);
    cr_assert_eq(r->vertices, 8);
    cr_assert_eq(r->open_edges, 0);
    cr_assert_eq(r->flipped_facets, 0);
    cr_assert_float_eq(r->volume, 1.0, 1e-12);
    /* the fan of f 1 4 3 2: (1 4 3), (1 3 2) */
    const uint32_t *t = hv_mesh_facets(m);
    const float *x = hv_mesh_vertices(m);
    cr_assert_eq(x[3 * t[5] + 0], 1.0f);
    cr_assert_eq(x[3 * t[5] + 1], 0.0f);
    hv_mesh_destroy(m);
    /* a hexagon as one face: 4 triangles */
    m = parse("v 0 0 0\nv 2 0 0\nv 3 1 0\nv 2 2 0\nv 0 2 0\nv -1 1 0\nf 1 2 3 4 5 6\n", "hex.obj");
    cr_assert_eq(hv_mesh_facet_count(m), 4);
    cr_assert_float_eq(hv_mesh_get_report(m)->area, 6.0, 1e-12);
    hv_mesh_destroy(m);
}

Test(obj, groups_become_bodies_and_usemtl_names_their_materials)
{
    char text[2048];
    snprintf(text, sizeof text,
             "%s"
             "f 1 2 3\n"                       /* before any group: the file's body */
             "o outer\nusemtl Vero\n%s"        /* 12 facets of Vero */
             "g unused\n"                      /* holds no face: dropped */
             "usemtl never_used\n"
             "g  inner part  # named with a blank\n"
             "usemtl Agilus\nf 1 2 6\nf 1 6 5\n"
             "o outer\nf 1 3 4\n"              /* outer again: continues its body, Agilus */
             "usemtl\nf 2 3 7\n"               /* a bare usemtl: no material */
             "g\nf 5 6 \\\n 7\n",             /* a group without a name, a continued line */
             k_cube, k_cube_quads);
    hv_mesh *m = parse(text, "dir/parts.obj");
    cr_assert_eq(hv_mesh_facet_count(m), 18);
    cr_assert_eq(hv_mesh_body_count(m), 4);
    const char *names[] = {"parts", "outer", "inner part", "body 4"};
    size_t counts[] = {1, 14, 2, 1};
    for (size_t i = 0; i < 4; ++i) {
        cr_assert_str_eq(hv_mesh_body_at(m, i)->name, names[i]);
        cr_assert_eq(hv_mesh_body_at(m, i)->facet_count, counts[i], "body %zu: %zu", i, hv_mesh_body_at(m, i)->facet_count);
    }
    cr_assert_eq(hv_mesh_material_count(m), 2); /* first use order; never_used is not one */
    cr_assert_str_eq(hv_mesh_material_at(m, 0)->name, "Vero");
    cr_assert_str_eq(hv_mesh_material_at(m, 1)->name, "Agilus");
    cr_assert_eq(hv_mesh_material_at(m, 0)->has_color, 0);
    cr_assert_eq(hv_mesh_body_at(m, 0)->material, HV_MESH_NO_MATERIAL);
    cr_assert_eq(hv_mesh_body_at(m, 1)->material, 0); /* 12 Vero, 1 Agilus, 1 none */
    cr_assert_eq(hv_mesh_body_at(m, 2)->material, 1);
    const int32_t *fm = hv_mesh_facet_materials(m);
    cr_assert_not_null(fm);
    cr_assert_eq(fm[0], HV_MESH_NO_MATERIAL);
    cr_assert_eq(fm[1], 0);
    cr_assert_eq(fm[13], 1); /* outer's late facet keeps the current material */
    cr_assert_eq(fm[14], HV_MESH_NO_MATERIAL);
    /* each body is its own mesh */
    hv_mesh *outer = NULL;
    cr_assert_eq(hv_mesh_body_extract(m, 1, &outer), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_mesh_facet_count(outer), 14);
    cr_assert_str_eq(hv_mesh_name(outer), "dir/parts.obj#outer");
    hv_mesh_destroy(outer);
    hv_mesh_destroy(m);
}

Test(obj, relative_indices_count_back_from_the_last_vertex_defined)
{
    hv_mesh *m = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf -4 -3 -1\n", "rel.obj");
    const float *x = hv_mesh_vertices(m);
    const uint32_t *t = hv_mesh_facets(m);
    cr_assert_eq(x[3 * t[5] + 2], 1.0f); /* -1 in the second face: the fourth vertex */
    hv_mesh_destroy(m);
}

Test(obj, a_bom_crlf_tabs_and_w_or_colour_values_are_read)
{
    hv_mesh *m = parse("\xEF\xBB\xBFv\t0 0 0 1\r\nv 1 0 0 1.0\r\nv 0 1 0 0.5 0.5 0.5\r\ns off\r\nf 1 2 3\r\n", "w.obj");
    cr_assert_eq(hv_mesh_facet_count(m), 1);
    cr_assert_eq(hv_mesh_vertex_count(m), 3);
    hv_mesh_destroy(m);
}

#define BAD(text, msg) refused(hv_mesh_parse_obj, "bad.obj", text, strlen(text), HV_ERR_BAD_INPUT, msg)

Test(obj, bad_input_is_refused_with_the_line_and_the_value)
{
    BAD("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
        "bad.obj: line 4: face vertex 3: vertex index 4 out of range (3 defined above the face)");
    BAD("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", /* a forward reference */
        "bad.obj: line 3: face vertex 3: vertex index 3 out of range (2 defined above the face)");
    BAD("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n",
        "bad.obj: line 4: face vertex 3: vertex index -4 out of range (3 defined above the face)");
    BAD("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
        "bad.obj: line 4: face vertex 1: vertex index 0 (indices count from 1, or back from -1)");
    BAD("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n", "bad.obj: line 4: face vertex 3: bad vertex index '3x'");
    BAD("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n",
        "bad.obj: line 4: face vertex 3: vertex index 99999999999999999999999 out of range (3 defined above the face)");
    BAD("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/1\n",
        "bad.obj: line 4: face vertex 3: texture coordinate index 1 out of range (0 defined above the face)");
    BAD("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1 2 3//2\n",
        "bad.obj: line 5: face vertex 3: normal index 2 out of range (1 defined above the face)");
    BAD("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2/ 3\n", "bad.obj: line 4: face vertex 2: bad texture coordinate index ''");
    BAD("v 0 0 0\nv 1 0 0\nf 1 2\n", "bad.obj: line 3: face has 2 vertices, at least 3 needed");
    BAD("v 0 0 nan\n", "bad.obj: line 1: vertex z is not a finite float: 'nan'");
    BAD("v 0 -inf 0\n", "bad.obj: line 1: vertex y is not a finite float: '-inf'");
    BAD("v 1e39 0 0\n", "bad.obj: line 1: vertex x is not a finite float: '1e39'");
    BAD("v 0 0 1,5\n", "bad.obj: line 1: vertex z is not a number: '1,5'");
    BAD("v 0 0\n", "bad.obj: line 1: vertex has 2 coordinates, 3 needed");
    BAD("v 0 0 0 1 2 3 4 5\n", "bad.obj: line 1: vertex has more than 7 values (x y z [w], or x y z and a colour)");
    BAD("\n\nvv 0 0 0\n", "bad.obj: line 3: unknown statement 'vv'");
    BAD("curv 0 1 1 2\n", "bad.obj: line 1: 'curv': free-form curves and surfaces are not supported (polygon faces only)");
    BAD("v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 3\n", "bad.obj: contains no faces (3 vertices; lines and points are not read)");
    BAD("# nothing\n", "bad.obj: contains no faces (0 vertices)");
    BAD("v 0 0 0\nv 1 0 \\\n\\\n x\n", "bad.obj: line 2: vertex z is not a number: 'x'");
    refused(hv_mesh_parse_obj, "bad.obj", "", 0, HV_ERR_BAD_INPUT, "bad.obj: empty file (0 bytes)");
    /* a NUL byte inside a number */
    refused(hv_mesh_parse_obj, "bad.obj", "v 0 0 1\0002\n", 10, HV_ERR_BAD_INPUT, "bad.obj: line 1: vertex z is not a number: '1?2'");
}

Test(obj, load_reads_a_file_by_its_extension)
{
    const char *path = t_tmpfile("tet.OBJ");
    FILE *fp = fopen(path, "w");
    cr_assert_not_null(fp);
    fputs("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n", fp);
    fclose(fp);
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_load(path, &m), HV_OK, "%s", hv_last_error());
    cr_assert_float_eq(hv_mesh_get_report(m)->volume, 1.0 / 6, 1e-12);
    cr_assert_str_eq(hv_mesh_body_at(m, 0)->name, "tet");
    hv_mesh_destroy(m);
    cr_assert_eq(hv_mesh_load(t_tmpfile("missing.obj"), &m), HV_ERR_IO);
}
