/* tests/io/test_mesh_load.c - the one mesh loader (src/io/mesh_load.c): the reader is chosen by a
 * signature in the content, else by the extension, else by what the text looks like; a file that
 * is none of the formats is refused naming them. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <string.h>

#include "hovox/mesh.h"
#include "support/support.h"

static const char *write_file(const char *name, const void *data, size_t n)
{
    const char *path = t_tmpfile(name);
    FILE *fp = fopen(path, "wb");
    cr_assert_not_null(fp);
    cr_assert_eq(fwrite(data, 1, n, fp), n);
    fclose(fp);
    return path;
}

static const char k_obj[] = "# a tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
static const char k_ply[] = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                            "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";

static hv_mesh_format load_format(const char *path)
{
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_load(path, &m), HV_OK, "%s: %s", path, hv_last_error());
    cr_assert_eq(hv_mesh_facet_count(m), 4);
    hv_mesh_format f = hv_mesh_get_report(m)->format;
    hv_mesh_destroy(m);
    return f;
}

Test(mesh_load, a_signature_decides_whatever_the_extension_says_and_text_decides_without_one)
{
    cr_assert_eq(load_format(write_file("tet.mesh", k_obj, strlen(k_obj))), HV_MESH_OBJ);
    cr_assert_eq(load_format(write_file("tet", k_obj, strlen(k_obj))), HV_MESH_OBJ);
    cr_assert_eq(load_format(write_file("tet.obj", k_ply, strlen(k_ply))), HV_MESH_PLY_ASCII);
    /* a binary STL under another name: 84 + 50 n bytes */
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_load(write_file("tet2.obj", k_obj, strlen(k_obj)), &m), HV_OK);
    cr_assert_eq(hv_mesh_write_stl(m, t_tmpfile("tet_bin.stl"), 0), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_mesh_write_stl(m, t_tmpfile("tet_ascii.stl"), 1), HV_OK, "%s", hv_last_error());
    hv_mesh_destroy(m);
    size_t n;
    char *bin = t_slurp(t_tmpfile("tet_bin.stl"), &n);
    cr_assert_eq(load_format(write_file("tet.dat", bin, n)), HV_MESH_STL_BINARY);
    free(bin);
    char *asc = t_slurp(t_tmpfile("tet_ascii.stl"), &n);
    cr_assert_eq(load_format(write_file("tet.txt", asc, n)), HV_MESH_STL_ASCII);
    free(asc);
}

Test(mesh_load, content_without_a_signature_goes_to_the_reader_of_the_extension)
{
    hv_mesh *m = NULL;
    /* text that looks like an STL in a .3mf: the 3MF reader says it is no ZIP */
    const char solid[] = "solid not a 3mf\n";
    cr_assert_eq(hv_mesh_load(write_file("x.3mf", solid, strlen(solid)), &m), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "ZIP"), "%s", hv_last_error());
    /* an empty .stl is the STL reader's to refuse, with its own message */
    cr_assert_eq(hv_mesh_load(write_file("empty.stl", "", 0), &m), HV_ERR_BAD_INPUT);
    cr_assert_null(m);
    cr_assert(strstr(hv_last_error(), "empty.stl"), "%s", hv_last_error());
    cr_assert_null(strstr(hv_last_error(), "unsupported mesh format"), "%s", hv_last_error());
}

Test(mesh_load, a_file_of_no_known_format_is_refused_listing_the_known_ones)
{
    hv_mesh *m = NULL;
    const char step[] = "ISO-10303-21;\nHEADER;\nENDSEC;\n";
    cr_assert_eq(hv_mesh_load(write_file("part.step", step, strlen(step)), &m), HV_ERR_BAD_INPUT);
    cr_assert_null(m);
    cr_assert(strstr(hv_last_error(), "part.step") && strstr(hv_last_error(), "'step'") &&
                  strstr(hv_last_error(), hv_mesh_load_extensions()),
              "%s", hv_last_error());
    cr_assert_str_eq(hv_mesh_format_name(HV_MESH_STL_BINARY), "binary STL");
    cr_assert_eq(hv_mesh_load(t_tmpfile("missing.stl"), &m), HV_ERR_IO);
}
