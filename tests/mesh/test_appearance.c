/* tests/mesh/test_appearance.c - a mesh's colour (hovox/mesh.h "appearance"): corner colours,
 * textures and UVs stored and refused, the colour of a point on a facet against hand-computed
 * bilinear samples and tile styles, and the appearance carried through transform (a mirror
 * included, checked by position), body extraction and join. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/mesh.h"
#include "mesh/mesh_internal.h"
#include "support/support.h"

/* A 2 x 2 texture: top row red, green; bottom row blue, white (alpha 255, 128, 255, 0). */
static const uint8_t TEX[16] = {255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 255, 255, 255, 255, 0};

static int32_t add_tex(hv_mesh *m, hv_tile tu, hv_tile tv, hv_filter f)
{
    int32_t idx = -7;
    cr_assert_eq(hv_mesh_add_texture(m, "t.png", TEX, 2, 2, tu, tv, f, &idx), HV_OK, "%s", hv_last_error());
    return idx;
}

/* Every facet textured with texture t, all corners at (u, v). */
static void uv_everywhere(hv_mesh *m, int32_t t, float u, float v)
{
    size_t nf = hv_mesh_facet_count(m);
    float *uv = malloc(6 * nf * sizeof *uv);
    int32_t *ft = malloc(nf * sizeof *ft);
    for (size_t f = 0; f < nf; ++f) {
        for (int k = 0; k < 3; ++k) {
            uv[6 * f + 2 * (size_t)k] = u;
            uv[6 * f + 2 * (size_t)k + 1] = v;
        }
        ft[f] = t;
    }
    cr_assert_eq(hv_mesh_set_corner_uvs(m, uv, ft), HV_OK, "%s", hv_last_error());
    free(uv);
    free(ft);
}

static void colour_at(const hv_mesh *m, size_t f, float out[4])
{
    double third[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
    cr_assert(hv_mesh_colour_at(m, f, third, out), "facet %zu has no colour", f);
}

static void expect(const float got[4], double r, double g, double b, double a)
{
    double want[4] = {r, g, b, a};
    for (int k = 0; k < 4; ++k)
        cr_assert(fabs(got[k] - want[k]) < 1e-5, "channel %d: %g, expected %g", k, (double)got[k], want[k]);
}

Test(appearance, none_by_default_and_stored_when_set)
{
    hv_mesh *m = t_cube_mesh(0, 1);
    size_t nf = hv_mesh_facet_count(m);
    cr_assert_null(hv_mesh_corner_colours(m));
    cr_assert_null(hv_mesh_corner_uvs(m));
    cr_assert_null(hv_mesh_facet_textures(m));
    cr_assert_eq(hv_mesh_texture_count(m), 0);
    cr_assert_not(hv_mesh_has_colour(m));
    float c[4] = {-1, -1, -1, -1};
    double b[3] = {1, 0, 0};
    cr_assert_not(hv_mesh_colour_at(m, 0, b, c));
    cr_assert_eq(c[0], -1);

    uint32_t *rgba = malloc(3 * nf * sizeof *rgba);
    for (size_t i = 0; i < 3 * nf; ++i) rgba[i] = (uint32_t)i * 0x01020304u;
    cr_assert_eq(hv_mesh_set_corner_colours(m, rgba), HV_OK);
    rgba[0] = 99; /* copied, not kept */
    cr_assert_eq(hv_mesh_corner_colours(m)[0], 0);
    cr_assert_eq(hv_mesh_corner_colours(m)[3 * nf - 1], (uint32_t)(3 * nf - 1) * 0x01020304u);
    cr_assert(hv_mesh_has_colour(m));
    cr_assert_eq(hv_mesh_set_corner_colours(m, NULL), HV_OK);
    cr_assert_null(hv_mesh_corner_colours(m));
    cr_assert_not(hv_mesh_has_colour(m));

    cr_assert_eq(add_tex(m, HV_TILE_WRAP, HV_TILE_CLAMP, HV_FILTER_NEAREST), 0);
    cr_assert_eq(add_tex(m, HV_TILE_NONE, HV_TILE_NONE, HV_FILTER_AUTO), 1);
    const hv_mesh_texture *t = hv_mesh_texture_at(m, 1);
    cr_assert_str_eq(t->name, "t.png");
    cr_assert_eq(t->width, 2);
    cr_assert_eq(t->tile_u, HV_TILE_NONE);
    cr_assert_eq(memcmp(t->rgba, TEX, 16), 0);
    cr_assert_neq(t->rgba, TEX);
    cr_assert_null(hv_mesh_texture_at(m, 2));
    cr_assert_not(hv_mesh_has_colour(m)); /* textures no facet uses */
    uv_everywhere(m, 1, 0.25f, 0.75f);
    cr_assert(hv_mesh_has_colour(m));
    cr_assert_eq(hv_mesh_facet_textures(m)[nf - 1], 1);
    cr_assert_eq(hv_mesh_corner_uvs(m)[6 * nf - 1], 0.75f);
    cr_assert_eq(hv_mesh_set_corner_uvs(m, NULL, NULL), HV_OK);
    cr_assert_null(hv_mesh_facet_textures(m));
    free(rgba);
    hv_mesh_destroy(m);
}

Test(appearance, refusals_name_the_facet_and_leave_the_mesh_as_it_was)
{
    hv_mesh *m = t_cube_mesh(0, 1);
    size_t nf = hv_mesh_facet_count(m);
    uint8_t px[4] = {0};
    cr_assert_eq(hv_mesh_add_texture(m, "z.png", px, 0, 1, HV_TILE_WRAP, HV_TILE_WRAP, HV_FILTER_AUTO, NULL), HV_ERR_INVALID);
    cr_assert_eq(hv_mesh_add_texture(m, "z.png", NULL, 1, 1, HV_TILE_WRAP, HV_TILE_WRAP, HV_FILTER_AUTO, NULL), HV_ERR_INVALID);
    cr_assert_eq(hv_mesh_add_texture(m, "z.png", px, 1, 1, (hv_tile)9, HV_TILE_WRAP, HV_FILTER_AUTO, NULL), HV_ERR_INVALID);
    cr_assert_eq(hv_mesh_texture_count(m), 0);
    float *uv = calloc(6 * nf, sizeof *uv);
    int32_t *ft = calloc(nf, sizeof *ft);
    cr_assert_eq(hv_mesh_set_corner_uvs(m, uv, NULL), HV_ERR_INVALID);
    cr_assert_eq(hv_mesh_set_corner_uvs(m, uv, ft), HV_ERR_INVALID); /* texture 0 does not exist */
    cr_assert(strstr(hv_last_error(), "facet 0: texture 0 out of range"), "%s", hv_last_error());
    add_tex(m, HV_TILE_WRAP, HV_TILE_NONE, HV_FILTER_AUTO);
    uv[6 * 5 + 3] = 1.5f; /* facet 5, corner 1, v */
    cr_assert_eq(hv_mesh_set_corner_uvs(m, uv, ft), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "facet 5: texture coordinate (0, 1.5) outside [0, 1]"), "%s", hv_last_error());
    cr_assert_null(hv_mesh_corner_uvs(m));
    uv[6 * 5 + 3] = 0;
    uv[6 * 5 + 2] = -3.5f; /* u wraps */
    cr_assert_eq(hv_mesh_set_corner_uvs(m, uv, ft), HV_OK, "%s", hv_last_error());
    uv[0] = NAN;
    cr_assert_eq(hv_mesh_set_corner_uvs(m, uv, ft), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "facet 0: texture coordinate (nan, 0) is not finite"), "%s", hv_last_error());
    cr_assert_eq(hv_mesh_corner_uvs(m)[2 * 5 * 3 + 2], -3.5f); /* the earlier table stays */
    for (size_t f = 0; f < nf; ++f) ft[f] = -1; /* untextured facets are not checked */
    cr_assert_eq(hv_mesh_set_corner_uvs(m, uv, ft), HV_OK, "%s", hv_last_error());
    free(uv);
    free(ft);
    hv_mesh_destroy(m);
}

Test(appearance, corner_colours_interpolate_by_barycentric_weight)
{
    hv_mesh *m = t_cube_mesh(0, 1);
    size_t nf = hv_mesh_facet_count(m);
    uint32_t *rgba = calloc(3 * nf, sizeof *rgba);
    rgba[0] = 0xFF000000u; /* red, alpha 0 */
    rgba[1] = 0x00FF00FFu;
    rgba[2] = 0x0000FF80u;
    cr_assert_eq(hv_mesh_set_corner_colours(m, rgba), HV_OK);
    float c[4];
    double b[3] = {0.5, 0.25, 0.25};
    cr_assert(hv_mesh_colour_at(m, 0, b, c));
    expect(c, 0.5, 0.25, 0.25, (0.25 * 255 + 0.25 * 128) / 255);
    cr_assert_not(hv_mesh_colour_at(m, nf, b, c)); /* out of range */
    free(rgba);
    hv_mesh_destroy(m);
}

Test(appearance, textures_sample_bilinearly_between_pixel_centres_with_tile_styles)
{
    hv_mesh *m = t_cube_mesh(0, 1);
    float c[4];
    /* pixel centres: u 0.25 / 0.75, v 0.75 (top row) / 0.25 */
    int32_t lin = add_tex(m, HV_TILE_WRAP, HV_TILE_WRAP, HV_FILTER_LINEAR);
    uv_everywhere(m, lin, 0.25f, 0.75f);
    colour_at(m, 3, c);
    expect(c, 1, 0, 0, 1);
    uv_everywhere(m, lin, 0.75f, 0.25f);
    colour_at(m, 3, c);
    expect(c, 1, 1, 1, 0);
    uv_everywhere(m, lin, 0.5f, 0.5f); /* the mean of the four */
    colour_at(m, 3, c);
    expect(c, 0.5, 0.5, 0.5, (255 + 128 + 255 + 0) / 4.0 / 255);
    uv_everywhere(m, lin, 0.5f, 0.75f); /* halfway along the top row */
    colour_at(m, 3, c);
    expect(c, 0.5, 0.5, 0, (255 + 128) / 2.0 / 255);
    /* wrap: u = 0 lies between the last column and the first */
    uv_everywhere(m, lin, 0.0f, 0.75f);
    colour_at(m, 3, c);
    expect(c, 0.5, 0.5, 0, (255 + 128) / 2.0 / 255);
    uv_everywhere(m, lin, 1.75f, -0.75f); /* = (0.75, 0.25) */
    colour_at(m, 3, c);
    expect(c, 1, 1, 1, 0);

    int32_t clamp = add_tex(m, HV_TILE_CLAMP, HV_TILE_CLAMP, HV_FILTER_LINEAR);
    uv_everywhere(m, clamp, 0.0f, 0.75f); /* the edge column alone */
    colour_at(m, 3, c);
    expect(c, 1, 0, 0, 1);
    uv_everywhere(m, clamp, 7.0f, -2.0f); /* the bottom-right pixel */
    colour_at(m, 3, c);
    expect(c, 1, 1, 1, 0);

    int32_t mir = add_tex(m, HV_TILE_MIRROR, HV_TILE_MIRROR, HV_FILTER_LINEAR);
    uv_everywhere(m, mir, 1.25f, 0.75f); /* mirrored back onto u = 0.75 */
    colour_at(m, 3, c);
    expect(c, 0, 1, 0, 128 / 255.0);
    uv_everywhere(m, mir, -0.25f, 0.75f); /* onto u = 0.25 */
    colour_at(m, 3, c);
    expect(c, 1, 0, 0, 1);
    uv_everywhere(m, mir, 1.0f, 0.75f); /* the edge: the last column twice */
    colour_at(m, 3, c);
    expect(c, 0, 1, 0, 128 / 255.0);

    int32_t near = add_tex(m, HV_TILE_WRAP, HV_TILE_WRAP, HV_FILTER_NEAREST);
    uv_everywhere(m, near, 0.49f, 0.51f);
    colour_at(m, 3, c);
    expect(c, 1, 0, 0, 1);
    uv_everywhere(m, near, 0.51f, 0.49f);
    colour_at(m, 3, c);
    expect(c, 1, 1, 1, 0);
    hv_mesh_destroy(m);
}

/* Corner colours that tell the corners apart: a hash of the corner's position. */
static uint32_t pos_colour(const float *p)
{
    uint32_t h = 2166136261u;
    for (int k = 0; k < 3; ++k) h = (h ^ (uint32_t)lrintf(p[k] * 16 + 64)) * 16777619u;
    return h | 1u;
}

static hv_mesh *coloured_by_position(double lo, double hi)
{
    hv_mesh *m = t_cube_mesh(lo, hi);
    size_t nf = hv_mesh_facet_count(m);
    const float *xyz = hv_mesh_vertices(m);
    const uint32_t *tri = hv_mesh_facets(m);
    uint32_t *rgba = malloc(3 * nf * sizeof *rgba);
    float *uv = malloc(6 * nf * sizeof *uv);
    int32_t *ft = malloc(nf * sizeof *ft);
    add_tex(m, HV_TILE_WRAP, HV_TILE_WRAP, HV_FILTER_AUTO);
    for (size_t f = 0; f < nf; ++f) {
        ft[f] = f % 2 ? 0 : -1;
        for (int k = 0; k < 3; ++k) {
            const float *p = xyz + 3 * (size_t)tri[3 * f + (size_t)k];
            rgba[3 * f + (size_t)k] = pos_colour(p);
            uv[6 * f + 2 * (size_t)k] = p[0] + 2 * p[1];
            uv[6 * f + 2 * (size_t)k + 1] = p[2] - p[1];
        }
    }
    cr_assert_eq(hv_mesh_set_corner_colours(m, rgba), HV_OK);
    cr_assert_eq(hv_mesh_set_corner_uvs(m, uv, ft), HV_OK);
    free(rgba);
    free(uv);
    free(ft);
    return m;
}

/* Every corner of `out` (its leading facets, as many as src has from `first`) carries the colour and UV of the corner of `src` at the position that
 * maps onto it (x -> -x when mirrored, else identity plus a shift). */
static void check_carried(const hv_mesh *src, size_t first, const hv_mesh *out, double sx, double dx,
                          int32_t tex_shift)
{
    const float *xs = hv_mesh_vertices(src), *xo = hv_mesh_vertices(out);
    const uint32_t *ts = hv_mesh_facets(src), *to = hv_mesh_facets(out);
    const uint32_t *cs = hv_mesh_corner_colours(src), *co = hv_mesh_corner_colours(out);
    const float *us = hv_mesh_corner_uvs(src), *uo = hv_mesh_corner_uvs(out);
    cr_assert_not_null(co);
    cr_assert_not_null(uo);
    for (size_t f = 0; f < hv_mesh_facet_count(src) - first && f < hv_mesh_facet_count(out); ++f) {
        int32_t ts_f = hv_mesh_facet_textures(src)[first + f];
        cr_assert_eq(hv_mesh_facet_textures(out)[f], ts_f >= 0 ? ts_f + tex_shift : ts_f);
        for (int k = 0; k < 3; ++k) {
            const float *q = xo + 3 * (size_t)to[3 * f + (size_t)k];
            int found = 0;
            for (int j = 0; j < 3; ++j) {
                const float *p = xs + 3 * (size_t)ts[3 * (first + f) + (size_t)j];
                if (fabs(sx * p[0] + dx - q[0]) < 1e-5 && fabs(p[1] - q[1]) < 1e-5 && fabs(p[2] - q[2]) < 1e-5) {
                    found = 1;
                    cr_assert_eq(co[3 * f + (size_t)k], cs[3 * (first + f) + (size_t)j], "facet %zu corner %d", f, k);
                    cr_assert_eq(uo[6 * f + 2 * (size_t)k], us[6 * (first + f) + 2 * (size_t)j]);
                    cr_assert_eq(uo[6 * f + 2 * (size_t)k + 1], us[6 * (first + f) + 2 * (size_t)j + 1]);
                }
            }
            cr_assert(found, "facet %zu corner %d has no source", f, k);
        }
    }
}

Test(appearance, transform_carries_it_and_a_mirror_swaps_corners_with_their_colours)
{
    hv_mesh *m = coloured_by_position(0, 1), *moved = NULL, *mirrored = NULL;
    double shift[12] = {1, 0, 0, 5, 0, 1, 0, 0, 0, 0, 1, 0};
    double mirror[12] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    cr_assert_eq(hv_mesh_transform(m, shift, &moved), HV_OK);
    cr_assert_eq(hv_mesh_transform(m, mirror, &mirrored), HV_OK);
    cr_assert_eq(hv_mesh_texture_count(mirrored), 1);
    cr_assert_eq(memcmp(hv_mesh_texture_at(mirrored, 0)->rgba, TEX, 16), 0);
    check_carried(m, 0, moved, 1, 5, 0);
    check_carried(m, 0, mirrored, -1, 0, 0);
    cr_assert_gt(hv_mesh_get_report(mirrored)->volume, 0);
    hv_mesh_destroy(m);
    hv_mesh_destroy(moved);
    hv_mesh_destroy(mirrored);
}

Test(appearance, join_renumbers_textures_and_extract_gives_a_body_its_own)
{
    hv_mesh *a = coloured_by_position(0, 1), *b = coloured_by_position(2, 3), *plain = t_cube_mesh(5, 6);
    int32_t extra = add_tex(b, HV_TILE_CLAMP, HV_TILE_CLAMP, HV_FILTER_NEAREST);
    cr_assert_eq(extra, 1);
    /* b's odd facets use its second texture */
    size_t nf = hv_mesh_facet_count(b);
    int32_t *ft = malloc(nf * sizeof *ft);
    memcpy(ft, hv_mesh_facet_textures(b), nf * sizeof *ft);
    for (size_t f = 1; f < nf; f += 2) ft[f] = 1;
    cr_assert_eq(hv_mesh_set_corner_uvs(b, hv_mesh_corner_uvs(b), ft), HV_OK);
    hv_mesh_part parts[3] = {{a, "a", NULL}, {plain, "plain", NULL}, {b, "b", NULL}};
    hv_mesh *j = NULL, *eb = NULL, *ep = NULL;
    cr_assert_eq(hv_mesh_join(parts, 3, &j), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_mesh_texture_count(j), 3);
    cr_assert_eq(hv_mesh_texture_at(j, 2)->filter, HV_FILTER_NEAREST);
    size_t na = hv_mesh_facet_count(a), np = hv_mesh_facet_count(plain);
    const int32_t *jt = hv_mesh_facet_textures(j);
    for (size_t f = 0; f < np; ++f) cr_assert_eq(jt[na + f], HV_MESH_NO_COLOUR);
    for (size_t f = 0; f < nf; ++f) cr_assert_eq(jt[na + np + f], f % 2 ? 2 : -1);
    float c[4];
    double bc[3] = {1, 0, 0};
    cr_assert_not(hv_mesh_colour_at(j, na, bc, c));
    cr_assert(hv_mesh_colour_at(j, 0, bc, c));

    cr_assert_eq(hv_mesh_body_extract(j, 2, &eb), HV_OK);
    check_carried(b, 0, eb, 1, 0, 1); /* b's textures follow a's one */
    cr_assert_eq(hv_mesh_facet_textures(eb)[1], 2); /* the whole mesh's textures */
    cr_assert_eq(hv_mesh_texture_count(eb), 3);
    cr_assert_eq(hv_mesh_body_extract(j, 1, &ep), HV_OK);
    cr_assert_not(hv_mesh_has_colour(ep));
    check_carried(a, 0, j, 1, 0, 0); /* the first part's facets lead the joined mesh */
    free(ft);
    hv_mesh_destroy(a);
    hv_mesh_destroy(b);
    hv_mesh_destroy(plain);
    hv_mesh_destroy(j);
    hv_mesh_destroy(eb);
    hv_mesh_destroy(ep);
}

Test(appearance, join_keeps_a_material_colour_as_corner_colours)
{
    hv_mesh *red = t_cube_mesh(0, 1), *plain = t_cube_mesh(2, 3), *j = NULL;
    size_t nf = hv_mesh_facet_count(red);
    hv_mesh_body body = {"red", HV_MESH_NO_MATERIAL, 0, nf, 0};
    hv_mesh_material mat = {"Red", 0xFF000080u, 1, 0, NULL};
    int32_t *fm = calloc(nf, sizeof *fm);
    cr_assert_eq(hv_mesh_set_bodies(red, &body, 1, &mat, 1, fm), HV_OK);
    cr_assert(hv_mesh_has_colour(red));
    float c[4];
    double bc[3] = {0.2, 0.3, 0.5};
    cr_assert(hv_mesh_colour_at(red, 4, bc, c));
    expect(c, 1, 0, 0, 128 / 255.0);
    hv_mesh_part parts[2] = {{plain, "plain", NULL}, {red, "red", "Vero"}};
    cr_assert_eq(hv_mesh_join(parts, 2, &j), HV_OK);
    cr_assert_not_null(hv_mesh_corner_colours(j));
    cr_assert(hv_mesh_colour_at(j, hv_mesh_facet_count(plain) + 4, bc, c));
    expect(c, 1, 0, 0, 128 / 255.0);
    cr_assert_not(hv_mesh_colour_at(j, 0, bc, c));
    free(fm);
    hv_mesh_destroy(red);
    hv_mesh_destroy(plain);
    hv_mesh_destroy(j);
}

Test(appearance, body_colour_overrides_its_texture_and_keeps_the_others_colours)
{
    /* three bodies: "tex" textured, "red" coloured by its material, "plain" without colour; the
     * user colours "tex" blue: its facets turn blue, "red" keeps its red (now as corner colours),
     * "plain" stays without colour; a body that is not there is named with those there are */
    hv_mesh *a = t_cube_mesh(0, 1), *b = t_cube_mesh(2, 3), *c = t_cube_mesh(4, 5), *j = NULL;
    add_tex(a, HV_TILE_CLAMP, HV_TILE_CLAMP, HV_FILTER_NEAREST);
    uv_everywhere(a, 0, 0.1f, 0.9f);
    size_t nb = hv_mesh_facet_count(b);
    hv_mesh_body body = {"red", HV_MESH_NO_MATERIAL, 0, nb, 0};
    hv_mesh_material mat = {"Red", 0xFF0000FFu, 1, 0, NULL};
    int32_t *fm = calloc(nb, sizeof *fm);
    cr_assert_eq(hv_mesh_set_bodies(b, &body, 1, &mat, 1, fm), HV_OK);
    hv_mesh_part parts[3] = {{a, "tex", NULL}, {b, "red", "Red"}, {c, "plain", NULL}};
    cr_assert_eq(hv_mesh_join(parts, 3, &j), HV_OK, "%s", hv_last_error());
    float col[4];
    colour_at(j, 0, col);
    expect(col, 1, 0, 0, 1); /* the texture's top-left texel */
    cr_assert_eq(hv_mesh_body_colour_set(j, "tex", 0x0000FFFFu), HV_OK, "%s", hv_last_error());
    size_t na = hv_mesh_facet_count(a);
    for (size_t f = 0; f < na; ++f) {
        colour_at(j, f, col);
        expect(col, 0, 0, 1, 1);
    }
    colour_at(j, na + 3, col);
    expect(col, 1, 0, 0, 1);
    cr_assert_not(hv_mesh_colour_at(j, na + nb + 1, (double[3]){1, 0, 0}, col));
    cr_assert_eq(hv_mesh_body_colour_set(j, "hub", 0x000000FFu), HV_ERR_NOT_FOUND);
    cr_assert_str_eq(hv_last_error(), "the mesh: no body 'hub' (bodies: tex, red, plain)");
    /* a mesh coloured by its material alone: the body's colour replaces it */
    cr_assert_eq(hv_mesh_body_colour_set(b, "red", 0x00FF0080u), HV_OK);
    colour_at(b, 2, col);
    expect(col, 0, 1, 0, 128 / 255.0);
    free(fm);
    hv_mesh_destroy(a);
    hv_mesh_destroy(b);
    hv_mesh_destroy(c);
    hv_mesh_destroy(j);
}

/* A texture's embedded ICC profile (issue 29 item 4) is kept, cleared, refused out of range and
 * carried with the texture through a transform. */
Test(appearance, a_textures_icc_profile_is_kept_and_carried)
{
    hv_mesh *m = t_cube_mesh(0, 1);
    int32_t t = add_tex(m, HV_TILE_WRAP, HV_TILE_WRAP, HV_FILTER_AUTO);
    uv_everywhere(m, t, 0.25f, 0.75f);
    cr_assert_null(hv_mesh_texture_at(m, 0)->icc);
    static const uint8_t icc[5] = {1, 2, 3, 4, 5};
    cr_assert_eq(hv_mesh_texture_set_icc(m, 0, icc, sizeof icc), HV_OK);
    cr_assert_eq(hv_mesh_texture_set_icc(m, 1, icc, sizeof icc), HV_ERR_INVALID);
    hv_mesh *moved = NULL;
    double xf[12] = {1, 0, 0, 5, 0, 1, 0, 0, 0, 0, 1, 0};
    cr_assert_eq(hv_mesh_transform(m, xf, &moved), HV_OK, "%s", hv_last_error());
    const hv_mesh_texture *tx = hv_mesh_texture_at(moved, 0);
    cr_assert_eq(tx->icc_size, sizeof icc);
    cr_assert_arr_eq(tx->icc, icc, sizeof icc);
    cr_assert_eq(hv_mesh_texture_set_icc(m, 0, NULL, 0), HV_OK);
    cr_assert_null(hv_mesh_texture_at(m, 0)->icc);
    cr_assert_eq(hv_mesh_texture_at(m, 0)->icc_size, 0);
    hv_mesh_destroy(moved);
    hv_mesh_destroy(m);
}
