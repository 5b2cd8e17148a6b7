/* tests/io/test_ply.c - the PLY reader: shared meshes written by the test as ASCII and as
 * binary of both byte orders, with odd property types, extra properties, lists and elements,
 * read back with the STL reader's report; headers whose counts lie; one exact message for each
 * kind of bad input. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/mesh.h"
#include "reader_check.h"
#include "support/support.h"

/* Bytes of a value in the byte order asked for (1: big-endian). */
static void put(hv_buf *b, const void *v, size_t n, int big)
{
    unsigned char t[8];
    memcpy(t, v, n);
    for (size_t k = 0; k < n; ++k) hv_buf_append(b, (const char *)&t[big ? n - 1 - k : k], 1);
}
#define PUT(b, type, value, big) \
    do { \
        type v_ = (type)(value); \
        put(b, &v_, sizeof v_, big); \
    } while (0)

/* The mesh as PLY: format 0 ASCII, 1 binary little-endian, 2 binary big-endian. Vertices carry
 * a short before x, y as a double and a list after z; an element edge sits between vertex and
 * face; faces carry a byte before their uint16-counted int list and a float list after. */
static char *as_ply(const hv_mesh *m, int format, size_t *len)
{
    static const char *const fmt[] = {"ascii", "binary_little_endian", "binary_big_endian"};
    size_t nv = hv_mesh_vertex_count(m), nf = hv_mesh_facet_count(m);
    const float *xyz = hv_mesh_vertices(m);
    const uint32_t *t = hv_mesh_facets(m);
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_printf(&b,
                  "ply\nformat %s 1.0\ncomment written by test_ply\nobj_info odd types\n"
                  "element vertex %zu\nproperty int16 junk\nproperty float x\nproperty float64 y\n"
                  "property float32 z\nproperty list uint8 uint32 extra\n"
                  "element edge 2\nproperty int vertex1\nproperty list int uchar data\n"
                  "element face %zu\nproperty uchar flags\nproperty list ushort int vertex_indices\n"
                  "property list uchar float texcoord\nend_header\n",
                  fmt[format], nv, nf);
    int big = format == 2;
    for (size_t v = 0; v < nv; ++v) {
        if (format == 0) {
            hv_buf_printf(&b, "-7 %.9g %.17g %.9g 2 1 2\n", (double)xyz[3 * v], (double)xyz[3 * v + 1], (double)xyz[3 * v + 2]);
            continue;
        }
        PUT(&b, int16_t, -7, big);
        PUT(&b, float, xyz[3 * v], big);
        PUT(&b, double, xyz[3 * v + 1], big);
        PUT(&b, float, xyz[3 * v + 2], big);
        PUT(&b, uint8_t, 2, big);
        PUT(&b, uint32_t, 1, big);
        PUT(&b, uint32_t, 2, big);
    }
    for (int e = 0; e < 2; ++e) {
        if (format == 0) {
            hv_buf_printf(&b, "%d 3 1 2 3\n", e);
            continue;
        }
        PUT(&b, int32_t, e, big);
        PUT(&b, int32_t, 3, big);
        for (int k = 1; k <= 3; ++k) PUT(&b, uint8_t, k, big);
    }
    for (size_t f = 0; f < nf; ++f) {
        if (format == 0) {
            hv_buf_printf(&b, "9 3 %u %u %u 1 0.5\n", t[3 * f], t[3 * f + 1], t[3 * f + 2]);
            continue;
        }
        PUT(&b, uint8_t, 9, big);
        PUT(&b, uint16_t, 3, big);
        for (int c = 0; c < 3; ++c) PUT(&b, int32_t, t[3 * f + c], big);
        PUT(&b, uint8_t, 1, big);
        PUT(&b, float, 0.5f, big);
    }
    cr_assert(!b.failed);
    *len = b.len;
    return b.data;
}

Test(ply, shared_meshes_read_back_with_the_stl_readers_report_in_every_format)
{
    static const char *const names[] = {"helical_gear.stl", "bunny_1500.stl"};
    static const hv_mesh_format formats[] = {HV_MESH_PLY_ASCII, HV_MESH_PLY_BINARY_LE, HV_MESH_PLY_BINARY_BE};
    for (size_t k = 0; k < sizeof names / sizeof *names; ++k) {
        hv_mesh *ref = stl_reference(names[k]);
        for (int f = 0; f < 3; ++f) {
            size_t len;
            char *data = as_ply(ref, f, &len);
            hv_mesh *m = NULL;
            cr_assert_eq(hv_mesh_parse_ply(data, len, "dir/ref.ply", &m), HV_OK, "format %d: %s", f, hv_last_error());
            cr_assert_eq(hv_mesh_get_report(m)->format, formats[f]);
            same_report(m, ref, 0);
            cr_assert_eq(hv_mesh_body_count(m), 1);
            cr_assert_str_eq(hv_mesh_body_at(m, 0)->name, "ref");
            cr_assert_eq(hv_mesh_material_count(m), 0);
            hv_mesh_destroy(m);
            free(data);
        }
        hv_mesh_destroy(ref);
    }
}

/* A binary tetrahedron: vertex_index with an int32 count and uint8 items, integer coordinates,
 * an element after the faces, quads fan-triangulated. */
Test(ply, vertex_index_integer_coordinates_and_quads)
{
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_puts(&b, "ply\r\nformat binary_big_endian 1.0\r\nelement vertex 5\r\nproperty char x\r\nproperty uint y\r\n"
                    "property short z\r\nelement face 3\r\nproperty list int uint8 vertex_index\r\n"
                    "element material 2\r\nproperty uchar red\r\nend_header\r\n");
    int v[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int i = 0; i < 5; ++i) {
        PUT(&b, int8_t, v[i][0], 1);
        PUT(&b, uint32_t, v[i][1], 1);
        PUT(&b, int16_t, v[i][2], 1);
    }
    int faces[3][4] = {{0, 3, 2, 1}, {0, 1, 4, -1}, {1, 2, 4, -1}};
    for (int f = 0; f < 3; ++f) {
        int n = faces[f][3] < 0 ? 3 : 4;
        PUT(&b, int32_t, n, 1);
        for (int k = 0; k < n; ++k) PUT(&b, uint8_t, faces[f][k], 1);
    }
    PUT(&b, uint8_t, 1, 1);
    PUT(&b, uint8_t, 2, 1);
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_parse_ply(b.data, b.len, "quad.ply", &m), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_mesh_facet_count(m), 4);
    cr_assert_eq(hv_mesh_vertex_count(m), 5);
    cr_assert_float_eq(hv_mesh_get_report(m)->area, 1.0 + 0.5 + sqrt(2) / 2, 1e-9);
    hv_mesh_destroy(m);
    hv_buf_free(&b);
}

Test(ply, a_header_that_lies_about_its_counts_fails_before_allocating)
{
    static const char lie[] = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\n"
                              "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                              "end_header\n";
    size_t n = sizeof lie - 1 + 900;
    char *data = calloc(1, n);
    memcpy(data, lie, sizeof lie - 1);
    refused(hv_mesh_parse_ply, "lie.ply", data, n, HV_ERR_BAD_INPUT,
            "lie.ply: header declares 1000000000000 vertices but the 900 bytes after the header hold at most 75");
    static const char faces[] = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                "property float y\nproperty float z\nelement face 100\nproperty list uchar int vertex_indices\n"
                                "end_header\n";
    memcpy(data, faces, sizeof faces - 1);
    refused(hv_mesh_parse_ply, "lie.ply", data, sizeof faces - 1 + 36 + 50, HV_ERR_BAD_INPUT,
            "lie.ply: header declares 100 faces but the 86 bytes after the header hold at most 50");
    free(data);
    static const char ascii[] = "ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n";
    refused(hv_mesh_parse_ply, "lie.ply", ascii, sizeof ascii - 1, HV_ERR_BAD_INPUT,
            "lie.ply: header declares 99999999999 vertices but the 6 bytes after the header hold at most 1");
    /* one face that claims more indices than the bytes left */
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_puts(&b, "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n");
    for (int k = 0; k < 9; ++k) PUT(&b, float, k == 3 || k == 7, 0);
    PUT(&b, uint32_t, 4000000000u, 0);
    PUT(&b, int32_t, 0, 0);
    char msg[160];
    snprintf(msg, sizeof msg, "lie.ply: face 0 (byte %zu): declares 4000000000 vertices but the 4 bytes left hold at most 1",
             b.len - 8);
    refused(hv_mesh_parse_ply, "lie.ply", b.data, b.len, HV_ERR_BAD_INPUT, msg);
    hv_buf_free(&b);
}

#define HEAD_ASCII "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n" \
                   "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
#define BAD(text, msg) refused(hv_mesh_parse_ply, "bad.ply", text, strlen(text), HV_ERR_BAD_INPUT, msg)

Test(ply, bad_ascii_and_headers_are_refused_with_the_place_and_the_value)
{
    BAD(HEAD_ASCII "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "bad.ply: line 13: face 0: vertex index 3 out of range (3 vertices)");
    BAD(HEAD_ASCII "0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n", "bad.ply: line 13: face 0: vertex index -1 out of range (3 vertices)");
    BAD(HEAD_ASCII "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", "bad.ply: line 11: vertex 1: y is not a finite float (nan)");
    BAD(HEAD_ASCII "0 0 0\n1 1e39 0\n0 1 0\n3 0 1 2\n", "bad.ply: line 11: vertex 1: y is not a finite float (1e+39)");
    BAD(HEAD_ASCII "0 0 0\n1 0x 0\n0 1 0\n3 0 1 2\n", "bad.ply: line 11: vertex 1: y is not a number: '0x'");
    BAD(HEAD_ASCII "0 0 0\n1 0\n0 1 0\n3 0 1 2\n", "bad.ply: line 11: vertex 1: z is missing (the line ends)");
    BAD(HEAD_ASCII "0 0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "bad.ply: line 10: vertex 0: more values than its 3 properties: '0'");
    BAD(HEAD_ASCII "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n4\n", "bad.ply: line 14: data after the last element");
    BAD(HEAD_ASCII "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "bad.ply: line 13: face 0: 2 vertices, at least 3 needed");
    BAD(HEAD_ASCII "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n",
        "bad.ply: line 13: face 0: the count of list vertex_indices is 300, out of range for uchar");
    BAD(HEAD_ASCII "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n", "bad.ply: line 13: face 0: corner 3 is not an integer: '2.5'");
    BAD("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
        "bad.ply: header: no element vertex");
    BAD("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
        "bad.ply: header: no element face (a point cloud has no surface)");
    BAD("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nelement face 0\n"
        "property list uchar int vertex_indices\nend_header\n",
        "bad.ply: header: element vertex has no property z");
    BAD("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement face 0\n"
        "property list uchar float vertex_indices\nend_header\n",
        "bad.ply: header: face property vertex_indices must be a list of integers (for example 'property list uchar int vertex_indices')");
    BAD("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement face 0\n"
        "property list float int vertex_indices\nend_header\n",
        "bad.ply: header line 8: a list count must have an integer type, not 'float'");
    BAD("ply\nformat ascii 1.0\nelement vertex 0\nproperty half x\n", "bad.ply: header line 4: unknown property type 'half'");
    BAD("ply\nformat ascii 2.0\n", "bad.ply: header line 2: unsupported PLY version '2.0'");
    BAD("ply\nformat binary 1.0\n", "bad.ply: header line 2: unknown format 'binary'");
    BAD("ply\nelement vertex 3\n", "bad.ply: header line 2: expected the format line, got 'element vertex 3'");
    BAD("ply\nformat ascii 1.0\nelement vertex -3\n", "bad.ply: header line 3: element count is not a count: '-3'");
    BAD("ply\nformat ascii 1.0\nelement vertex 3 4\n", "bad.ply: header line 3: expected 'element NAME COUNT', got 'element vertex 3 4'");
    BAD("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float x\n",
        "bad.ply: header line 5: property declared twice: 'x'");
    BAD("ply\nformat ascii 1.0\nbogus\n", "bad.ply: header line 3: unknown header keyword 'bogus'");
    BAD("ply\nformat ascii 1.0\nelement vertex 3\n", "bad.ply: header has no end_header line");
    BAD("PLY\n", "bad.ply: not a PLY file: the first line is not 'ply'");
    BAD("solid x\n", "bad.ply: not a PLY file: the first line is not 'ply'");
    refused(hv_mesh_parse_ply, "bad.ply", "", 0, HV_ERR_BAD_INPUT, "bad.ply: empty file (0 bytes)");
}

Test(ply, bad_binary_is_refused_with_the_element_and_the_byte)
{
    static const char head[] = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\nelement face 1\nproperty list char int vertex_indices\nproperty float quality\n"
                               "end_header\n";
    size_t h = sizeof head - 1;
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_puts(&b, head);
    for (int k = 0; k < 9; ++k) PUT(&b, float, k == 3 || k == 7, 0);
    size_t faces = b.len;
    PUT(&b, int8_t, 3, 0);
    PUT(&b, int32_t, 0, 0);
    PUT(&b, int32_t, 1, 0);
    PUT(&b, int32_t, 9, 0);
    PUT(&b, float, 0.5f, 0);
    char msg[160];
    snprintf(msg, sizeof msg, "bad.ply: face 0 (byte %zu): vertex index 9 out of range (3 vertices)", faces + 9);
    refused(hv_mesh_parse_ply, "bad.ply", b.data, b.len, HV_ERR_BAD_INPUT, msg);
    memcpy(b.data + faces + 9, "\2\0\0\0", 4);
    /* truncated: the face's quality cut */
    snprintf(msg, sizeof msg, "bad.ply: face 0 (byte %zu): quality ends past the end of the file (truncated)", faces + 13);
    refused(hv_mesh_parse_ply, "bad.ply", b.data, b.len - 2, HV_ERR_BAD_INPUT, msg);
    /* a negative count */
    b.data[faces] = (char)-3;
    snprintf(msg, sizeof msg, "bad.ply: face 0 (byte %zu): list vertex_indices has a negative count (-3)", faces);
    refused(hv_mesh_parse_ply, "bad.ply", b.data, b.len, HV_ERR_BAD_INPUT, msg);
    b.data[faces] = 3;
    hv_buf_append(&b, "xy", 2); /* trailing data */
    snprintf(msg, sizeof msg, "bad.ply: 2 bytes of trailing data after the last element (byte %zu)", b.len - 2);
    refused(hv_mesh_parse_ply, "bad.ply", b.data, b.len, HV_ERR_BAD_INPUT, msg);
    b.len -= 2;
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_parse_ply(b.data, b.len, "good.ply", &m), HV_OK, "%s", hv_last_error());
    hv_mesh_destroy(m);
    /* a NaN vertex */
    float nan = NAN;
    memcpy(b.data + h + 4, &nan, 4);
    snprintf(msg, sizeof msg, "bad.ply: vertex 0 (byte %zu): y is not a finite float (nan)", h + 4);
    refused(hv_mesh_parse_ply, "bad.ply", b.data, b.len, HV_ERR_BAD_INPUT, msg);
    hv_buf_free(&b);
}
