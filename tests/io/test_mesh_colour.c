/* tests/io/test_mesh_colour.c - colour read with meshes (issue 29): OBJ + MTL (Kd, d, map_Kd with
 * -clamp/-o/-s, vt) with PNG and JPEG textures written here by libpng and libjpeg, PLY vertex
 * colours (uchar and float), and each refusal (a missing library or texture, a file that is not an
 * image, values out of range) with its exact message. */
#include <criterion/criterion.h>
#include <jpeglib.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/image.h"
#include "hovox/mesh.h"
#include "io/io_internal.h"
#include "reader_check.h"
#include "support/support.h"

static void write_text(const char *path, const char *text)
{
    FILE *fp = fopen(path, "wb");
    cr_assert_not_null(fp);
    fputs(text, fp);
    fclose(fp);
}

/* A 4 x 2 RGBA PNG: top row red, green, blue, white; bottom row half-transparent grey levels. */
static const uint8_t k_px[32] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255,
                                 0, 0, 0, 128, 85, 85, 85, 128, 170, 170, 170, 128, 255, 255, 255, 128};

static void write_png(const char *path)
{
    cr_assert_eq(hv_png_write(path, k_px, 4, 2, 4, 0, NULL), HV_OK, "%s", hv_last_error());
}

/* An 8 x 8 JPEG of one flat colour (flat blocks survive JPEG almost exactly). */
static void write_jpeg(const char *path, uint8_t r, uint8_t g, uint8_t b)
{
    FILE *fp = fopen(path, "wb");
    cr_assert_not_null(fp);
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr err;
    c.err = jpeg_std_error(&err);
    jpeg_create_compress(&c);
    jpeg_stdio_dest(&c, fp);
    c.image_width = 8;
    c.image_height = 8;
    c.input_components = 3;
    c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 100, TRUE);
    jpeg_start_compress(&c, TRUE);
    uint8_t row[24];
    for (int i = 0; i < 8; ++i) {
        row[3 * i] = r;
        row[3 * i + 1] = g;
        row[3 * i + 2] = b;
    }
    while (c.next_scanline < 8) {
        JSAMPROW p = row;
        jpeg_write_scanlines(&c, &p, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    fclose(fp);
}

/* Two triangles of a square: textured ("skin", every corner with a vt), then flat ("paint"), then
 * one with no material. */
static const char k_obj[] = "mtllib look.mtl\n"
                            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
                            "vt 0.125 0.75\nvt 0.375 0.75\nvt 0.625 0.75\nvt 1.875 0.25\n"
                            "usemtl skin\nf 1/1 2/2 3/3\nf 1/4 3/4 4/4\n"
                            "usemtl paint\nf 1/1 2/2 5/3\nf 2 3 5\n"
                            "usemtl\nf 3 4 5\n";

static hv_mesh *load_ok(const char *path)
{
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_load(path, &m), HV_OK, "%s", hv_last_error());
    return m;
}

static void colour_of(const hv_mesh *m, size_t f, int k, float c[4])
{
    double b[3] = {0, 0, 0};
    b[k] = 1;
    cr_assert(hv_mesh_colour_at(m, f, b, c), "facet %zu has no colour", f);
}

static void near(const float c[4], double r, double g, double b, double a, double tol)
{
    double want[4] = {r, g, b, a};
    for (int k = 0; k < 4; ++k)
        cr_assert(fabs(c[k] - want[k]) <= tol, "channel %d: %g, expected %g", k, (double)c[k], want[k]);
}

Test(obj_colour, mtl_colours_and_a_png_texture_at_the_vt_coordinates)
{
    write_png(t_tmpfile("skin.png"));
    write_text(t_tmpfile("look.mtl"), "# a library\nnewmtl skin\nKd 0.8 0.8 0.8\nmap_Kd -clamp on skin.png\n"
                                      "newmtl paint\nKa 1 1 1\nKd 1 0.5 0\nd 0.5\nillum 2\n"
                                      "newmtl unused\nmap_Kd nowhere.png\n");
    const char *path = t_tmpfile("square.obj");
    write_text(path, k_obj);
    hv_mesh *m = load_ok(path);
    cr_assert_eq(hv_mesh_facet_count(m), 5);
    cr_assert_eq(hv_mesh_texture_count(m), 1); /* the unused material's texture is not read */
    const hv_mesh_texture *t = hv_mesh_texture_at(m, 0);
    cr_assert_str_eq(t->name, "skin.png");
    cr_assert_eq(t->width, 4);
    cr_assert_eq(t->height, 2);
    cr_assert_eq(t->tile_u, HV_TILE_CLAMP);
    cr_assert_eq(memcmp(t->rgba, k_px, 32), 0);
    const int32_t *ft = hv_mesh_facet_textures(m);
    cr_assert_not_null(ft);
    cr_assert_eq(ft[0], 0);
    cr_assert_eq(ft[1], 0);
    cr_assert_eq(ft[2], -1); /* paint has no texture */
    cr_assert_eq(ft[4], -1);
    const float *uv = hv_mesh_corner_uvs(m);
    cr_assert_eq(uv[0], 0.125f);
    cr_assert_eq(uv[5], 0.75f);
    float c[4];
    colour_of(m, 0, 0, c); /* (0.125, 0.75): the centre of the top-left pixel */
    near(c, 1, 0, 0, 1, 1e-6);
    colour_of(m, 0, 1, c);
    near(c, 0, 1, 0, 1, 1e-6);
    colour_of(m, 0, 2, c);
    near(c, 0, 0, 1, 1, 1e-6);
    colour_of(m, 1, 0, c); /* (1.875, 0.25) clamped: the bottom-right pixel */
    near(c, 1, 1, 1, 128 / 255.0, 1e-6);
    colour_of(m, 2, 0, c); /* Kd 1 0.5 0, d 0.5: the material's colour */
    near(c, 1, 128 / 255.0, 0, 128 / 255.0, 1e-6);
    const hv_mesh_material *paint = hv_mesh_material_at(m, 1);
    cr_assert_str_eq(paint->name, "paint");
    cr_assert(paint->has_color);
    cr_assert_eq(paint->rgba, 0xFF800080u);
    cr_assert(hv_mesh_material_at(m, 0)->has_color);
    double b[3] = {1, 0, 0};
    cr_assert_not(hv_mesh_colour_at(m, 4, b, c)); /* no material */

    /* from memory, nothing beside it is read: materials are names only */
    hv_mesh *mem = NULL;
    cr_assert_eq(hv_mesh_parse_obj(k_obj, strlen(k_obj), path, &mem), HV_OK, "%s", hv_last_error());
    cr_assert_not(hv_mesh_has_colour(mem));
    cr_assert_eq(hv_mesh_texture_count(mem), 0);
    hv_mesh_destroy(mem);
    hv_mesh_destroy(m);
}

Test(obj_colour, a_jpeg_texture_wraps_moved_and_scaled_by_the_map_options)
{
    const char *dir = t_tmpdir();
    char sub[512], path[512];
    snprintf(sub, sizeof sub, "%s/maps", dir);
    cr_assert_eq(system(NULL) != 0, 1);
    char cmd[600];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s'", sub);
    cr_assert_eq(t_run(cmd, NULL), 0);
    snprintf(path, sizeof path, "%s/maps/wood grain.jpg", dir);
    write_jpeg(path, 200, 100, 50);
    snprintf(path, sizeof path, "%s/maps/look.mtl", dir);
    write_text(path, "newmtl skin\nmap_Kd -blendu off -s 2 2 1 -o 0.5 -mm 0 1 wood grain.jpg\nnewmtl paint\n");
    snprintf(path, sizeof path, "%s/jpeg.obj", dir);
    char text[sizeof k_obj + 16];
    snprintf(text, sizeof text, "mtllib maps/look.mtl%s", strchr(k_obj, '\n'));
    write_text(path, text);
    hv_mesh *m = load_ok(path);
    cr_assert_eq(hv_mesh_texture_count(m), 1);
    cr_assert_str_eq(hv_mesh_texture_at(m, 0)->name, "wood grain.jpg");
    cr_assert_eq(hv_mesh_texture_at(m, 0)->tile_u, HV_TILE_WRAP);
    const float *uv = hv_mesh_corner_uvs(m);
    cr_assert_float_eq(uv[0], 0.125f * 2 + 0.5f, 1e-6);
    cr_assert_float_eq(uv[1], 0.75f * 2, 1e-6); /* -o 0.5 moves u alone */
    float c[4];
    colour_of(m, 1, 0, c);
    near(c, 200 / 255.0, 100 / 255.0, 50 / 255.0, 1, 2.5 / 255);
    cr_assert_not(hv_mesh_material_at(m, 1)->has_color); /* paint has no Kd */
    hv_mesh_destroy(m);
}

/* `fmt` with every "DIR" replaced by the temporary directory. */
static void in_dir(char *out, size_t cap, const char *fmt)
{
    size_t n = 0;
    for (const char *p = fmt; *p && n + 1 < cap;) {
        if (strncmp(p, "DIR", 3) == 0) {
            n += (size_t)snprintf(out + n, cap - n, "%s", t_tmpdir());
            p += 3;
        } else {
            out[n++] = *p++;
        }
    }
    out[n < cap ? n : cap - 1] = '\0';
}

/* hv_mesh_load(obj) with this library text must fail with exactly `message` (DIR: the directory). */
static void mtl_refused(const char *mtl, hv_status status, const char *fmt)
{
    write_png(t_tmpfile("skin.png"));
    write_text(t_tmpfile("look.mtl"), mtl);
    const char *path = t_tmpfile("square.obj");
    write_text(path, k_obj);
    hv_mesh *m = (hv_mesh *)1;
    cr_assert_eq(hv_mesh_load(path, &m), status, "%s", hv_last_error());
    cr_assert_null(m);
    char want[1024];
    in_dir(want, sizeof want, fmt);
    cr_assert_str_eq(hv_last_error(), want);
}

Test(obj_colour, a_missing_or_bad_library_or_texture_is_one_message)
{
    mtl_refused("newmtl skin\nmap_Kd gone.png\n", HV_ERR_BAD_INPUT,
                "DIR/look.mtl: line 2: map_Kd: DIR/gone.png: cannot open: No such file or directory");
    write_text(t_tmpfile("fake.png"), "this is text\n");
    mtl_refused("newmtl skin\n\nmap_Kd fake.png\n", HV_ERR_BAD_INPUT,
                "DIR/look.mtl: line 3: map_Kd: DIR/fake.png: not an image (neither PNG nor JPEG)");
    uint8_t trunc[64];
    memcpy(trunc, "\377\330\377\340", 4);
    memset(trunc + 4, 0, sizeof trunc - 4);
    FILE *fp = fopen(t_tmpfile("broken.jpg"), "wb");
    fwrite(trunc, 1, sizeof trunc, fp);
    fclose(fp);
    hv_mesh *m = (hv_mesh *)1;
    write_text(t_tmpfile("look.mtl"), "newmtl skin\nmap_Kd broken.jpg\n");
    cr_assert_eq(hv_mesh_load(t_tmpfile("square.obj"), &m), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "look.mtl: line 2: map_Kd: ") && strstr(hv_last_error(), "broken.jpg: not a readable JPEG: "),
              "%s", hv_last_error());
    mtl_refused("newmtl skin\nKd 1.5 0 0\n", HV_ERR_BAD_INPUT, "DIR/look.mtl: line 2: Kd red 1.5 outside [0, 1]");
    mtl_refused("newmtl skin\nKd 1 x 0\n", HV_ERR_BAD_INPUT, "DIR/look.mtl: line 2: Kd green is not a finite number: 'x'");
    mtl_refused("newmtl skin\nKd spectral steel.rfl\n", HV_ERR_BAD_INPUT,
                "DIR/look.mtl: line 2: Kd spectral is not supported (give r g b)");
    mtl_refused("Kd 1 1 1\n", HV_ERR_BAD_INPUT, "DIR/look.mtl: line 1: 'Kd' before any newmtl");
    mtl_refused("newmtl skin\nd 2\n", HV_ERR_BAD_INPUT, "DIR/look.mtl: line 2: d 2 outside [0, 1]");
    mtl_refused("newmtl skin\nmap_Kd -zoom 2 skin.png\n", HV_ERR_BAD_INPUT,
                "DIR/look.mtl: line 2: map_Kd: unknown option '-zoom'");
    mtl_refused("newmtl skin\nmap_Kd -clamp\n", HV_ERR_BAD_INPUT, "DIR/look.mtl: line 2: map_Kd -clamp takes on or off");
    mtl_refused("newmtl skin\nmap_Kd -clamp on\n", HV_ERR_BAD_INPUT, "DIR/look.mtl: line 2: map_Kd names no file");
    /* a name that a NUL byte would cut short (to nothing: found by fuzz_mtl, corpus newmtl_nul_name) */
    static const char nul_name[] = "newmtl \0skin\nKd 1 0 0\n";
    hv_mtl lib;
    memset(&lib, 0, sizeof lib);
    cr_assert_eq(hv_mtl_parse(nul_name, sizeof nul_name - 1, "nul.mtl", &lib), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "nul.mtl: line 1: newmtl name holds a NUL byte");
    hv_mtl_free(&lib);

    /* a library that is not there leaves the materials names only */
    const char *path = t_tmpfile("lost.obj");
    write_text(path, "mtllib lost.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    m = load_ok(path);
    cr_assert_eq(hv_mesh_material_count(m), 1);
    cr_assert_not(hv_mesh_has_colour(m));
    hv_mesh_destroy(m);
    /* one that is a directory cannot be read */
    write_text(path, "mtllib .\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    m = (hv_mesh *)1;
    cr_assert_eq(hv_mesh_load(path, &m), HV_ERR_BAD_INPUT);
    cr_assert_null(m);
    cr_assert(strstr(hv_last_error(), "lost.obj: line 1: material library "), "%s", hv_last_error());
}

Test(obj_colour, texture_coordinates_are_checked)
{
    refused(hv_mesh_parse_obj, "bad.obj", "vt 0 nan\n", 9, HV_ERR_BAD_INPUT,
            "bad.obj: line 1: texture coordinate v is not a finite number: 'nan'");
    refused(hv_mesh_parse_obj, "bad.obj", "vt\n", 3, HV_ERR_BAD_INPUT, "bad.obj: line 1: texture coordinate has no values");
    refused(hv_mesh_parse_obj, "bad.obj", "vt 0 0 0 0\n", 11, HV_ERR_BAD_INPUT,
            "bad.obj: line 1: texture coordinate has more than 3 values (u v w)");
}

/* ---- PLY ------------------------------------------------------------------------------------- */

static const char k_ply_head[] = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                 "property float z\n";

static hv_mesh *ply(const char *colour_props, const char *vertices)
{
    char text[2048];
    snprintf(text, sizeof text, "%s%selement face 4\nproperty list uchar int vertex_indices\nend_header\n%s"
             "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n", k_ply_head, colour_props, vertices);
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_parse_ply(text, strlen(text), "tet.ply", &m), HV_OK, "%s", hv_last_error());
    return m;
}

/* Facet 0's corners red, blue and green, opaque (its centre grey), corner 5 `c5`. */
static void red_blue_green_then(const hv_mesh *m, uint32_t c5)
{
    const uint32_t *c = hv_mesh_corner_colours(m);
    cr_assert_not_null(c);
    cr_assert_eq(c[0], 0xFF0000FFu);
    cr_assert_eq(c[1], 0x0000FFFFu);
    cr_assert_eq(c[2], 0x00FF00FFu);
    cr_assert_eq(c[5], c5, "%08x", c[5]);
    float col[4];
    double third[3] = {1 / 3.0, 1 / 3.0, 1 / 3.0};
    cr_assert(hv_mesh_colour_at(m, 0, third, col));
    near(col, 1 / 3.0, 1 / 3.0, 1 / 3.0, 1, 1e-6);
}

Test(ply_colour, uchar_and_float_vertex_colours_become_corner_colours)
{
    hv_mesh *m = ply("property uchar red\nproperty uchar green\nproperty uchar blue\n",
                     "0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n0 0 1 10 20 30\n");
    red_blue_green_then(m, 0x0A141EFFu); /* facet 0 is 0 2 1 */
    hv_mesh_destroy(m);

    m = ply("property float alpha\nproperty double red\nproperty float green\nproperty float blue\n",
            "0 0 0 0.5 1 0 0\n1 0 0 1 0 1 0\n0 1 0 0 0 0 1\n0 0 1 0 0.5 0.5 0.5\n");
    const uint32_t *c = hv_mesh_corner_colours(m);
    cr_assert_eq(c[0], 0xFF000080u);
    cr_assert_eq(c[5], 0x80808000u);
    hv_mesh_destroy(m);

    m = ply("", "0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
    cr_assert_null(hv_mesh_corner_colours(m));
    hv_mesh_destroy(m);
}

/* OBJ vertex colours as MeshLab, Blender (its "Colors" export) and scanners write them, `v x y z r g
 * b` in [0, 1]: the corners' colours, as PLY's (before, read and not used: a coloured scan printed
 * without its colour). Used only when every vertex has one in [0, 1]; else not, with a note. */
Test(obj_colour, vertex_colours_become_corner_colours)
{
    static const char faces[] = "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
    char text[512];
    snprintf(text, sizeof text, "# OBJ File Generated by Meshlab\nv 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\n"
                                "v 0 0 1 0.752941 0.501961 0.25098\n%s", faces);
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_parse_obj(text, strlen(text), "scan.obj", &m), HV_OK, "%s", hv_last_error());
    red_blue_green_then(m, 0xC08040FFu); /* facet 0 is 1 3 2; facet 1's third corner 192 128 64 (MeshLab's x/255) */
    cr_assert_eq(hv_mesh_note_count(m), 0);
    hv_mesh_destroy(m);
    static const struct {
        const char *vertices, *note;
    } none[] = {
        {"v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0 0 0 1\nv 0 0 1 1 1 1\n",
         "part.obj: 3 of the 4 vertices have a colour (v x y z r g b): the vertex colours are not used"},
        {"v 0 0 0 255 0 0\nv 1 0 0 0 255 0\nv 0 1 0 0 0 255\nv 0 0 1 9 9 9\n",
         "part.obj: line 1: vertex colour 255 is outside [0, 1]: the vertex colours are not used"},
        {"v 0 0 0 1\nv 1 0 0 1\nv 0 1 0 1\nv 0 0 1 1 0.5 0.5 0.5\n", NULL}, /* w, and seven values: no colour */
    };
    for (size_t k = 0; k < sizeof none / sizeof *none; ++k) {
        snprintf(text, sizeof text, "%s%s", none[k].vertices, faces);
        cr_assert_eq(hv_mesh_parse_obj(text, strlen(text), "part.obj", &m), HV_OK, "%s", hv_last_error());
        cr_assert_null(hv_mesh_corner_colours(m), "%zu", k);
        cr_assert_eq(hv_mesh_note_count(m), none[k].note ? 1u : 0u, "%zu", k);
        if (none[k].note) cr_assert_str_eq(hv_mesh_note_at(m, 0), none[k].note);
        hv_mesh_destroy(m);
    }
}

static void ply_refused(const char *props, const char *vertices, const char *message)
{
    char text[2048];
    snprintf(text, sizeof text, "%s%selement face 1\nproperty list uchar int vertex_indices\nend_header\n%s3 0 2 1\n",
             k_ply_head, props, vertices);
    refused(hv_mesh_parse_ply, "bad.ply", text, strlen(text), HV_ERR_BAD_INPUT, message);
}

Test(ply_colour, bad_colours_are_refused_with_the_place)
{
    ply_refused("property uchar red\nproperty uchar green\n", "",
                "bad.ply: header: vertex colour needs red, green and blue (blue missing)");
    ply_refused("property ushort red\nproperty ushort green\nproperty ushort blue\n", "",
                "bad.ply: header: vertex colour red must be a uchar, float or double scalar");
    ply_refused("property uchar alpha\n", "", "bad.ply: header: vertex alpha without red, green and blue");
    ply_refused("property float red\nproperty float green\nproperty float blue\n",
                "0 0 0 1 0 0\n1 0 0 0 1.5 0\n0 1 0 0 0 1\n0 0 1 0 0 0\n",
                "bad.ply: line 14: vertex 1: green 1.5 outside [0, 1]");
}
