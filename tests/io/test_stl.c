/* tests/io/test_stl.c - the STL reader (src/io/stl.c): binary and ASCII told apart by content,
 * the shared meshes' reports, hostile files (every bad file and every truncation fails cleanly,
 * a NUL inside a number), and a write/read round trip. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <string.h>

#include "hovox/mesh.h"
#include "support/support.h"

static hv_mesh *load(const char *path)
{
    hv_mesh *m = NULL;
    hv_status s = hv_mesh_load_stl(path, &m);
    cr_assert_eq(s, HV_OK, "%s: %s", path, hv_last_error());
    return m;
}

Test(stl, shared_meshes_load_with_expected_reports)
{
    hv_mesh *g = load(t_mesh_path("helical_gear.stl"));
    const hv_mesh_report *r = hv_mesh_get_report(g);
    cr_assert_eq(r->format, HV_MESH_STL_ASCII);
    cr_assert_eq(r->facets, 17790);
    cr_assert_eq(r->open_edges, 0);
    cr_assert_eq(r->nonmanifold_edges, 0);
    cr_assert_eq(r->degenerate_facets, 1);
    cr_assert_eq(r->flipped_facets, 0);
    cr_assert_eq(r->normal_mismatch, 15); /* stored normals disagree with the winding */
    cr_assert_eq(r->shells, 1);
    cr_assert_gt(r->volume, 0);
    hv_mesh_destroy(g);

    /* binary whose header starts with COLOR=: detected by size, not by "solid" */
    hv_mesh *b = load(t_mesh_path("bolt_colored_header.stl"));
    cr_assert_eq(hv_mesh_get_report(b)->format, HV_MESH_STL_BINARY);
    cr_assert_eq(hv_mesh_get_report(b)->facets, 3000);
    cr_assert_eq(hv_mesh_get_report(b)->open_edges, 0);
    hv_mesh_destroy(b);

    hv_mesh *u = load(t_mesh_path("bunny_1500.stl"));
    cr_assert_eq(hv_mesh_get_report(u)->facets, 1500);
    cr_assert_eq(hv_mesh_get_report(u)->shells, 1);
    hv_mesh_destroy(u);
}

Test(stl, binary_with_solid_header_is_binary)
{
    hv_mesh *m = load("tests/data/good/tet_binary_solid_header.stl");
    cr_assert_eq(hv_mesh_get_report(m)->format, HV_MESH_STL_BINARY);
    cr_assert_eq(hv_mesh_facet_count(m), 4);
    cr_assert_eq(hv_mesh_vertex_count(m), 4);
    hv_mesh_destroy(m);
    m = load("tests/data/good/tet_ascii_upper_crlf.stl");
    cr_assert_eq(hv_mesh_get_report(m)->format, HV_MESH_STL_ASCII);
    cr_assert_float_eq(hv_mesh_get_report(m)->volume, 1.0 / 6.0, 1e-9);
    hv_mesh_destroy(m);
}

Test(stl, every_bad_file_fails_cleanly)
{
    static const struct { const char *file; hv_status status; const char *needle; } cases[] = {
        {"empty.stl", HV_ERR_BAD_INPUT, "empty file"},
        {"header_only.stl", HV_ERR_BAD_INPUT, "no facets"},
        {"header_only_count5.stl", HV_ERR_BAD_INPUT, "declares 5 facets"},
        {"count_too_large.stl", HV_ERR_BAD_INPUT, "declares 3 facets (234 bytes)"},
        {"count_absurd.stl", HV_ERR_BAD_INPUT, "declares 4000000000 facets"},
        {"trailing_garbage.stl", HV_ERR_BAD_INPUT, "7 bytes of trailing data"},
        {"binary_nan.stl", HV_ERR_BAD_INPUT, "facet 1 (byte 158): vertex 1 has a non-finite x"},
        {"binary_inf.stl", HV_ERR_BAD_INPUT, "facet 3"},
        {"ascii_nan.stl", HV_ERR_BAD_INPUT, "line 5: facet 0: vertex 1 has a non-finite x"},
        {"ascii_inf.stl", HV_ERR_BAD_INPUT, "(-inf)"},
        {"ascii_missing_endloop.stl", HV_ERR_BAD_INPUT, "expected 'endloop', got 'endfacet'"},
        {"ascii_missing_endfacet.stl", HV_ERR_BAD_INPUT, "expected 'endfacet', got 'facet'"},
        {"ascii_missing_vertex.stl", HV_ERR_BAD_INPUT, "expected 'vertex', got 'endloop'"},
        {"ascii_non_numeric.stl", HV_ERR_BAD_INPUT, "is not a number: 'abc'"},
        {"ascii_truncated.stl", HV_ERR_BAD_INPUT, "unexpected end of file inside facet 1"},
        {"ascii_no_facets.stl", HV_ERR_BAD_INPUT, "no facets"},
        {"ascii_trailing_garbage.stl", HV_ERR_BAD_INPUT, "after 'endsolid'"},
        {"ascii_missing_endsolid.stl", HV_ERR_BAD_INPUT, "expected 'facet' or 'endsolid'"},
        {"too_short.stl", HV_ERR_BAD_INPUT, "not an STL file"},
        {"a_directory.stl", HV_ERR_IO, "is a directory"},
        {"no_such_file.stl", HV_ERR_IO, "No such file"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char path[256];
        snprintf(path, sizeof path, "tests/data/bad/%s", cases[i].file);
        hv_mesh *m = (hv_mesh *)0x1;
        hv_status s = hv_mesh_load_stl(path, &m);
        cr_assert_eq(s, cases[i].status, "%s: got %s (%s)", path, hv_status_name(s), hv_last_error());
        cr_assert_null(m, "%s: out not cleared", path);
        cr_assert(strstr(hv_last_error(), cases[i].needle) != NULL, "%s: message '%s' lacks '%s'",
                  path, hv_last_error(), cases[i].needle);
        cr_assert(strstr(hv_last_error(), path) != NULL, "%s: message does not name the file", path);
    }
}

/* Truncating a valid file at every length must never crash or succeed falsely. */
Test(stl, every_truncation_of_a_valid_file_fails_cleanly)
{
    static const char *files[] = {"tests/data/good/tet_ascii.stl",
                                  "tests/data/good/tet_binary_solid_header.stl"};
    for (int f = 0; f < 2; ++f) {
        FILE *fp = fopen(files[f], "rb");
        cr_assert_not_null(fp);
        char buf[4096];
        size_t n = fread(buf, 1, sizeof buf - 1, fp);
        fclose(fp);
        buf[n] = '\0';
        /* an ASCII file stays valid once its "endsolid" keyword is complete */
        char *end = strstr(buf, "endsolid");
        size_t valid_from = f == 0 ? (size_t)(end - buf) + 8 : n;
        for (size_t len = 0; len < valid_from; ++len) {
            hv_mesh *m = NULL;
            hv_status s = hv_mesh_parse_stl(buf, len, "cut.stl", &m);
            cr_assert_neq(s, HV_OK, "%s cut at %zu accepted", files[f], len);
            cr_assert_null(m);
        }
    }
}

Test(stl, write_read_round_trip)
{
    hv_mesh *m = load(t_mesh_path("bunny_1500.stl"));
    for (int ascii = 0; ascii < 2; ++ascii) {
        const char *p = t_tmpfile(ascii ? "b.ascii.stl" : "b.bin.stl");
        cr_assert_eq(hv_mesh_write_stl(m, p, ascii), HV_OK, "%s", hv_last_error());
        hv_mesh *r = load(p);
        cr_assert_eq(hv_mesh_facet_count(r), hv_mesh_facet_count(m));
        cr_assert_eq(hv_mesh_vertex_count(r), hv_mesh_vertex_count(m));
        cr_assert_eq(memcmp(hv_mesh_vertices(r), hv_mesh_vertices(m),
                            3 * sizeof(float) * hv_mesh_vertex_count(m)),
                     0, "coordinates changed (ascii=%d)", ascii);
        cr_assert_eq(hv_mesh_get_report(r)->normal_mismatch, 0);
        hv_mesh_destroy(r);
    }
    hv_mesh_destroy(m);
}

Test(stl, a_nul_byte_inside_a_number_is_refused)
{
    static const char tail[] = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1\0" "2 0 0\n"
                               "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
    char text[2048];
    memset(text, 'x', 1200);
    memcpy(text, "solid ", 6);
    text[1200] = '\n';
    memcpy(text + 1201, tail, sizeof tail - 1);
    hv_mesh *m = NULL;
    hv_status s = hv_mesh_parse_stl(text, 1201 + sizeof tail - 1, "nul.stl", &m);
    cr_assert_eq(s, HV_ERR_BAD_INPUT, "accepted");
    cr_assert_null(m);
    cr_assert(strstr(hv_last_error(), "line 5") && strstr(hv_last_error(), "is not a number: '1?2'"), "%s",
              hv_last_error());
}
