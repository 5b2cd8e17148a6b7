/* tests/colour/test_paint.c - colour carried into the part (hv_colour_paint, src/colour/paint.c):
 * a 10 mm cube whose six faces carry six flat corner colours, voxelized at 0.5 mm and painted 1 mm
 * deep: a voxel near a face holds the colour map's fractions of that face's colour, a voxel deeper
 * than 1 mm the core resin, and the change is sharp at the depth (the voxels' exact distance to
 * the nearest face decides); with a core colour, deep voxels hold its fractions; colour.depth holds
 * each voxel's distance and side for the stack. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/colour.h"
#include "hovox/generate.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"
#include "support/support.h"


static const uint32_t k_face[6] = {0xFF0000FFu, 0x00FF00FFu, 0x0000FFFFu, 0xFFFF00FFu, 0x00FFFFFFu, 0xFF00FFFFu};

/* The face a facet lies on: its normal's axis and sign, 0..5. */
static int face_of(const hv_mesh *m, size_t f)
{
    const float *v = hv_mesh_vertices(m);
    const uint32_t *t = hv_mesh_facets(m) + 3 * f;
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = v[3 * t[1] + k] - v[3 * t[0] + k];
        e2[k] = v[3 * t[2] + k] - v[3 * t[0] + k];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    int a = fabs(n[0]) > fabs(n[1]) ? (fabs(n[0]) > fabs(n[2]) ? 0 : 2) : (fabs(n[1]) > fabs(n[2]) ? 1 : 2);
    return 2 * a + (n[a] > 0);
}

/* The 10 mm cube, each face one flat colour (corner colours), and its voxels at 0.5 mm. */
static hv_mesh *face_cube(const uint32_t face[6])
{
    hv_mesh *m = t_cube_mesh(0, 10);
    size_t nf = hv_mesh_facet_count(m);
    uint32_t *c = malloc(3 * nf * sizeof *c);
    for (size_t f = 0; f < nf; ++f) c[3 * f] = c[3 * f + 1] = c[3 * f + 2] = face[face_of(m, f)];
    cr_assert_eq(hv_mesh_set_corner_colours(m, c), HV_OK);
    free(c);
    return m;
}

static hv_volume *half_mm_voxels(const hv_mesh *m)
{
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_OK, "%s", hv_last_error());
    return v;
}

/* The six-colour cube on 0.5 mm voxels painted 1 mm deep over Agilus30 through the default map. */
static hv_volume *painted_face_cube(hv_mesh **m, hv_colour_map **map)
{
    *m = face_cube(k_face);
    hv_volume *v = half_mm_voxels(*m);
    cr_assert_eq(hv_colour_map_create(NULL, map), HV_OK);
    cr_assert_eq(hv_colour_paint(v, *m, *map, 1.0, "Agilus30", NULL), HV_OK, "%s", hv_last_error());
    return v;
}

Test(paint, six_faces_six_colours_a_sharp_depth_and_the_core)
{
    hv_mesh *m = NULL;
    hv_colour_map *map = NULL;
    hv_volume *v = painted_face_cube(&m, &map);
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_load(v, &t), HV_OK, "%s", hv_last_error());
    /* six slots: Agilus30 takes one; no colour here is translucent, so VeroClear gives way */
    cr_assert_eq(hv_material_count(t), 6);
    static const char *const k_names[7] = {"VeroCyan-V", "VeroMagenta-V", "VeroYellow-V", "VeroBlackPlus",
                                           "VeroPureWhite", "VeroClear", "Agilus30"};
    int grid[7];
    for (int k = 0; k < 7; ++k) grid[k] = hv_material_find(t, k_names[k]) < 0 ? -1 : hv_material_grid(v, t, hv_material_find(t, k_names[k]));
    cr_assert_eq(grid[HV_COLOUR_CLEAR], -1);
    char note[512];
    cr_assert_eq(hv_colour_paint_note(v, note, sizeof note), 1);
    cr_assert_str_eq(note, "VeroClear gave way to the core Agilus30 (six slots): no painted voxel used it; folded into "
                           "VeroPureWhite");
    double *xyz = NULL;
    size_t n = 0;
    cr_assert_eq(hv_volume_centres(v, "occupancy", &xyz, &n), HV_OK);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    size_t skin = 0, deep = 0;
    for (size_t i = 0; i < n; ++i) {
        const double *p = xyz + 3 * i;
        double dmin = INFINITY;
        int face = -1;
        for (int a = 0; a < 3; ++a)
            for (int s = 0; s < 2; ++s) {
                double d = s ? 10 - p[a] : p[a];
                if (p[0] < 0 || p[0] > 10 || p[1] < 0 || p[1] > 10 || p[2] < 0 || p[2] > 10) d = fabs(d);
                if (d < dmin - 1e-9) {
                    dmin = d;
                    face = 2 * a + s;
                }
            }
        /* a voxel at equal distance from two faces (an edge) may take either: skip those */
        int tie = 0;
        for (int a = 0; a < 3; ++a)
            for (int s = 0; s < 2; ++s)
                if (2 * a + s != face && fabs((s ? 10 - p[a] : p[a]) - dmin) < 1e-9) tie = 1;
        double idx[3];
        hv_volume_world_to_index(v, p, idx);
        float got[7];
        for (int k = 0; k < 7; ++k)
            got[k] = grid[k] < 0 ? 0.0f
                                 : hv_accessor_float(&acc, grid[k], (int32_t)lrint(idx[0]), (int32_t)lrint(idx[1]),
                                                     (int32_t)lrint(idx[2]));
        if (fabs(dmin) <= 1.0 - 1e-9 && p[0] > 0 && p[0] < 10 && p[1] > 0 && p[1] < 10 && p[2] > 0 && p[2] < 10) {
            if (tie) continue;
            uint8_t rgba[4] = {(uint8_t)(k_face[face] >> 24), (uint8_t)(k_face[face] >> 16), (uint8_t)(k_face[face] >> 8), 255};
            float want[HV_COLOUR_SLOTS];
            hv_colour_map_fractions(map, rgba, want);
            for (int k = 0; k < HV_COLOUR_SLOTS; ++k)
                cr_assert(fabs(got[k] - want[k]) < 0.01, "voxel at %g,%g,%g (face %d): slot %d %g, want %g", p[0], p[1], p[2], face, k, (double)got[k], (double)want[k]);
            cr_assert_eq(got[6], 0);
            ++skin;
        } else if (dmin > 1.0 + 1e-9) {
            cr_assert_eq(got[6], 1, "voxel at %g,%g,%g, %g deep: core %g", p[0], p[1], p[2], dmin, (double)got[6]);
            ++deep;
        }
    }
    cr_assert_gt(skin, 1000);
    cr_assert_gt(deep, 1000);
    /* a core colour: the deep voxels hold its fractions; refusals */
    hv_volume *v2 = half_mm_voxels(m);
    const float grey[4] = {0.5f, 0.5f, 0.5f, 1};
    cr_assert_eq(hv_colour_paint(v2, m, map, 1.0, NULL, grey), HV_OK, "%s", hv_last_error());
    float gf[HV_COLOUR_SLOTS];
    hv_colour_map_fractions(map, (const uint8_t[4]){128, 128, 128, 255}, gf);
    double centre[3] = {5.25, 5.25, 5.25}, ci[3];
    hv_volume_world_to_index(v2, centre, ci);
    hv_accessor acc2;
    hv_accessor_init(&acc2, v2);
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
        int gk = hv_volume_grid_find(v2, k == 0 ? "material.VeroCyan-V" : k == 4 ? "material.VeroPureWhite" : "material.VeroBlackPlus");
        int slot = k == 0 ? 0 : k == 4 ? 4 : 3;
        cr_assert_geq(gk, 0);
        cr_assert_float_eq(hv_accessor_float(&acc2, gk, (int32_t)lrint(ci[0]), (int32_t)lrint(ci[1]), (int32_t)lrint(ci[2])), gf[slot], 1e-6);
    }
    cr_assert_eq(hv_colour_paint(v2, m, map, 0, "Agilus30", NULL), HV_ERR_INVALID);
    cr_assert_eq(hv_colour_paint(v2, m, map, 1, NULL, NULL), HV_ERR_INVALID);
    cr_assert_neq(hv_colour_paint(v2, m, map, 1, "Agilus30", NULL), HV_OK); /* the grids are there already */
    hv_volume_destroy(v2);
    free(xyz);
    hv_material_table_destroy(t);
    hv_colour_map_destroy(map);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

/* Squared distance from p to triangle abc (Ericson 5.1.5, written again here as the oracle). */
static double tri_d2(const double p[3], const float *a, const float *b, const float *c)
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], q[3];
    for (int k = 0; k < 3; ++k) {
        ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k], bp[k] = p[k] - b[k], cp[k] = p[k] - c[k];
    }
#define D(u, w) ((u)[0] * (w)[0] + (u)[1] * (w)[1] + (u)[2] * (w)[2])
    double d1 = D(ab, ap), d2 = D(ac, ap), d3 = D(ab, bp), d4 = D(ac, bp), d5 = D(ab, cp), d6 = D(ac, cp);
#undef D
    double u = 0, v = 0, w = 0, vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
    if (d1 <= 0 && d2 <= 0) u = 1;
    else if (d3 >= 0 && d4 <= d3) v = 1;
    else if (d6 >= 0 && d5 <= d6) w = 1;
    else if (vc <= 0 && d1 >= 0 && d3 <= 0) v = d1 / (d1 - d3), u = 1 - v;
    else if (vb <= 0 && d2 >= 0 && d6 <= 0) w = d2 / (d2 - d6), u = 1 - w;
    else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) w = (d4 - d3) / ((d4 - d3) + (d5 - d6)), v = 1 - w;
    else v = vb / (va + vb + vc), w = vc / (va + vb + vc), u = 1 - v - w;
    double d = 0;
    for (int k = 0; k < 3; ++k) {
        q[k] = u * a[k] + v * b[k] + w * c[k] - p[k];
        d += q[k] * q[k];
    }
    return d;
}

/* The facet search (a bounding volume hierarchy) against every facet tried, and threads: a sphere
 * of 1,152 facets, each its own colour, all skin; every voxel holds the colour of its nearest facet
 * (voxels with a second facet within 1e-6 mm skipped), and 1 and 3 threads give the same grids. */
Test(paint, nearest_facet_exact_and_the_same_on_any_threads)
{
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_sphere((const double[3]){0, 0, 0}, 5, 48, 13, &m), HV_OK);
    size_t nf = hv_mesh_facet_count(m);
    cr_assert_gt(nf, 1000);
    uint32_t *c = malloc(3 * nf * sizeof *c);
    for (size_t f = 0; f < nf; ++f)
        c[3 * f] = c[3 * f + 1] = c[3 * f + 2] = (uint32_t)((f * 2654435761u) & 0xFFFFFF00u) | 0xFFu;
    cr_assert_eq(hv_mesh_set_corner_colours(m, c), HV_OK);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.4;
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_create(NULL, &map), HV_OK);
    hv_volume *v[2] = {NULL, NULL};
    for (int r = 0; r < 2; ++r) {
        hv_set_threads(r ? 3 : 1);
        cr_assert_eq(hv_voxelize(m, &o, &v[r]), HV_OK, "%s", hv_last_error());
        cr_assert_eq(hv_colour_paint(v[r], m, map, 20.0, "VeroPureWhite", NULL), HV_OK, "%s", hv_last_error());
    }
    hv_set_threads(0);
    double *xyz = NULL;
    size_t n = 0;
    cr_assert_eq(hv_volume_centres(v[0], "occupancy", &xyz, &n), HV_OK);
    const float *vert = hv_mesh_vertices(m);
    const uint32_t *t = hv_mesh_facets(m);
    hv_accessor acc[2];
    hv_accessor_init(&acc[0], v[0]);
    hv_accessor_init(&acc[1], v[1]);
    static const char *const names[HV_COLOUR_SLOTS] = {"material.VeroCyan-V", "material.VeroMagenta-V", "material.VeroYellow-V",
                                                       "material.VeroBlackPlus", "material.VeroPureWhite", "material.VeroClear"};
    size_t checked = 0;
    for (size_t i = 0; i < n; ++i) {
        const double *p = xyz + 3 * i;
        double best = INFINITY, second = INFINITY;
        size_t bf = 0;
        for (size_t f = 0; f < nf; ++f) {
            double d = tri_d2(p, vert + 3 * t[3 * f], vert + 3 * t[3 * f + 1], vert + 3 * t[3 * f + 2]);
            if (d < best) second = best, best = d, bf = f;
            else if (d < second) second = d;
        }
        double idx[3];
        hv_volume_world_to_index(v[0], p, idx);
        int32_t I = (int32_t)lrint(idx[0]), J = (int32_t)lrint(idx[1]), K = (int32_t)lrint(idx[2]);
        float want[HV_COLOUR_SLOTS];
        uint8_t rgba[4] = {(uint8_t)(c[3 * bf] >> 24), (uint8_t)(c[3 * bf] >> 16), (uint8_t)(c[3 * bf] >> 8), 255};
        hv_colour_map_fractions(map, rgba, want);
        int close = sqrt(second) - sqrt(best) < 1e-6;
        for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
            float a = hv_accessor_float(&acc[0], hv_volume_grid_find(v[0], names[k]), I, J, K);
            float b = hv_accessor_float(&acc[1], hv_volume_grid_find(v[1], names[k]), I, J, K);
            cr_assert_eq(a, b, "voxel %d,%d,%d slot %d: %g on 1 thread, %g on 3", I, J, K, k, (double)a, (double)b);
            if (!close) cr_assert_eq(a, want[k], "voxel at %g,%g,%g: slot %d %g, want %g (facet %zu)", p[0], p[1], p[2], k, (double)a, (double)want[k], bf);
        }
        checked += !close;
    }
    cr_assert_gt(checked, n / 2);
    free(xyz);
    free(c);
    hv_volume_destroy(v[0]);
    hv_volume_destroy(v[1]);
    hv_colour_map_destroy(map);
    hv_mesh_destroy(m);
}

/* The six slots (issue 29: a colour shares them with graded materials): a core resin beyond the
 * six takes a slot and a colour role gives way, so the model has six materials whose fractions
 * sum to 1 at every voxel. Translucent faces use Clear and no black: black gives way (nothing
 * lost). Translucent and black faces: the lesser used of the two gives way, folded (black into
 * equal cyan, magenta, yellow; clear into white). */
static void six_slots_case(const uint32_t face[6], const char *gives, const char *into)
{
    hv_mesh *m = face_cube(face);
    hv_volume *v = half_mm_voxels(m);
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_create(NULL, &map), HV_OK);
    cr_assert_eq(hv_colour_paint(v, m, map, 1.0, "Agilus30", NULL), HV_OK, "%s", hv_last_error());
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_load(v, &t), HV_OK);
    cr_assert_eq(hv_material_count(t), 6);
    cr_assert_lt(hv_material_find(t, gives), 0, "%s should have given way", gives);
    cr_assert_geq(hv_material_find(t, "Agilus30"), 0);
    char note[512];
    cr_assert_eq(hv_colour_paint_note(v, note, sizeof note), 1);
    cr_assert(strstr(note, gives) == note && strstr(note, into), "%s", note);
    double *xyz = NULL;
    size_t n = 0;
    cr_assert_eq(hv_volume_centres(v, "occupancy", &xyz, &n), HV_OK);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    for (size_t i = 0; i < n; ++i) {
        double idx[3];
        hv_volume_world_to_index(v, xyz + 3 * i, idx);
        double sum = 0;
        for (int k = 0; k < 6; ++k)
            sum += hv_accessor_float(&acc, hv_material_grid(v, t, k), (int32_t)lrint(idx[0]), (int32_t)lrint(idx[1]),
                                     (int32_t)lrint(idx[2]));
        cr_assert_float_eq(sum, 1.0, 1e-5, "voxel %zu: fractions sum to %g", i, sum);
    }
    free(xyz);
    hv_material_table_destroy(t);
    hv_colour_map_destroy(map);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

Test(paint, six_slots_a_role_gives_way_to_a_seventh_resin)
{
    static const uint32_t translucent[6] = {0xFF000080u, 0x00FF0080u, 0x0000FFFFu, 0xFFFF00FFu, 0x00FFFFFFu, 0xFF00FFFFu};
    six_slots_case(translucent, "VeroBlackPlus", "no painted voxel used it; folded into cyan, magenta and yellow");
    /* one black face, two nearly opaque ones (alpha 240): black is used more than clear */
    static const uint32_t both[6] = {0x000000FFu, 0x00FF00F0u, 0x0000FFF0u, 0xFFFF00FFu, 0x00FFFFFFu, 0xFF00FFFFu};
    six_slots_case(both, "VeroClear", "folded into VeroPureWhite");
}

/* colour.depth (the stack's per-pixel depth): every voxel inside the cube holds its distance to the
 * nearest face within 1e-5 mm up to the depth and two voxels (1 + 2 x 0.5 mm), the depth and three
 * voxels beyond; on the skin's side of the depth (<= it as a float) exactly where painting gave the
 * voxel the skin (no core resin); hv_colour_depth_grid finds it with the recorded depth, and does
 * not without the record (a model painted before). */
Test(paint, colour_depth_holds_each_voxels_distance_and_side)
{
    hv_mesh *m = NULL;
    hv_colour_map *map = NULL;
    hv_volume *v = painted_face_cube(&m, &map);
    float depth = 0;
    int g = hv_colour_depth_grid(v, &depth);
    cr_assert_geq(g, 0);
    cr_assert_eq(depth, 1.0f);
    int core = hv_volume_grid_find(v, "material.Agilus30");
    double *xyz = NULL;
    size_t n = 0, exact = 0, far = 0;
    cr_assert_eq(hv_volume_centres(v, "occupancy", &xyz, &n), HV_OK);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    for (size_t i = 0; i < n; ++i) {
        const double *p = xyz + 3 * i;
        if (p[0] < 0 || p[0] > 10 || p[1] < 0 || p[1] > 10 || p[2] < 0 || p[2] > 10) continue;
        double dmin = INFINITY, idx[3];
        for (int a = 0; a < 3; ++a) dmin = fmin(dmin, fmin(p[a], 10 - p[a]));
        hv_volume_world_to_index(v, p, idx);
        int32_t x = (int32_t)lrint(idx[0]), y = (int32_t)lrint(idx[1]), z = (int32_t)lrint(idx[2]);
        float d = hv_accessor_float(&acc, g, x, y, z), c = hv_accessor_float(&acc, core, x, y, z);
        if (dmin <= 2.0 - 1e-9) {
            cr_assert(fabs(d - dmin) < 1e-5, "voxel at %g,%g,%g: depth %g, distance %g", p[0], p[1], p[2], (double)d, dmin);
            ++exact;
        } else {
            cr_assert_eq(d, 2.5f, "voxel at %g,%g,%g, %g deep: %g", p[0], p[1], p[2], dmin, (double)d);
            ++far;
        }
        cr_assert_eq(d <= depth, c == 0, "voxel at %g,%g,%g: depth %g, core %g", p[0], p[1], p[2], (double)d, (double)c);
    }
    cr_assert_gt(exact, 3000);
    cr_assert_gt(far, 100);
    cr_assert_eq(hv_volume_meta_set_json(v, "hovox.colour.json", "{}"), HV_OK);
    cr_assert_eq(hv_colour_depth_grid(v, &depth), -1, "a record without the depth");
    free(xyz);
    hv_colour_map_destroy(map);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}
