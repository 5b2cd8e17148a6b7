/* tests/mesh/test_mesh.c - mesh construction (src/mesh/mesh.c): welding, adjacency and the
 * report, checked on hand-made and analytic meshes. (The STL reader: tests/io/test_stl.c.) */
#include <criterion/criterion.h>
#include <stdio.h>
#include <math.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/mesh.h"
#include "mesh/mesh_internal.h"
#include "support/support.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

Test(report, analytic_volumes_and_areas)
{
    hv_mesh *m;
    double c[3] = {1, 2, 3};
    cr_assert_eq(hv_generate_sphere(c, 10, 256, 128, &m), HV_OK);
    const hv_mesh_report *r = hv_mesh_get_report(m);
    cr_assert_float_eq(r->volume, 4.0 / 3.0 * M_PI * 1000, 4.0 / 3.0 * M_PI * 1000 * 1e-3);
    cr_assert_float_eq(r->area, 4 * M_PI * 100, 4 * M_PI * 100 * 1e-3);
    cr_assert_float_eq(r->bbox_min[2], -7.0, 1e-5);
    cr_assert_eq(r->shells, 1);
    hv_mesh_destroy(m);

    double lo[3] = {0, 0, 0}, hi[3] = {2, 3, 4};
    cr_assert_eq(hv_generate_box(lo, hi, &m), HV_OK);
    cr_assert_float_eq(hv_mesh_get_report(m)->volume, 24.0, 1e-9);
    cr_assert_float_eq(hv_mesh_get_report(m)->area, 52.0, 1e-9);
    cr_assert_eq(hv_mesh_get_report(m)->vertices, 8);
    hv_mesh_destroy(m);
}

Test(report, generated_shapes_are_closed_and_oriented)
{
    hv_mesh *ms[6] = {0};
    double z[3] = {0, 0, 0}, hi[3] = {40, 30, 20};
    cr_assert_eq(hv_generate_box_with_hole(z, hi, 8, 64, &ms[0]), HV_OK);
    cr_assert_eq(hv_generate_torus(z, 20, 6, 64, 32, &ms[1]), HV_OK);
    cr_assert_eq(hv_generate_cylinder(z, 0, 150, 27.5, 96, &ms[2]), HV_OK);
    cr_assert_eq(hv_generate_torus_knot(2, 3, 30, 12, 5, 400, 24, &ms[3]), HV_OK);
    cr_assert_eq(hv_generate_gear(24, 34.5, 39.45, 9.54, 39.45, 0, 12, 1, &ms[4]), HV_OK);
    cr_assert_eq(hv_generate_gear(12, 10, 12, 0, 8, 0.5, 8, 6, &ms[5]), HV_OK);
    for (int i = 0; i < 6; ++i) {
        const hv_mesh_report *r = hv_mesh_get_report(ms[i]);
        cr_assert_eq(r->open_edges, 0, "shape %d", i);
        cr_assert_eq(r->nonmanifold_edges, 0, "shape %d", i);
        cr_assert_eq(r->flipped_facets, 0, "shape %d", i);
        cr_assert_eq(r->degenerate_facets, 0, "shape %d", i);
        cr_assert_eq(r->shells, 1, "shape %d", i);
        cr_assert_gt(r->volume, 0, "shape %d", i);
        hv_mesh_destroy(ms[i]);
    }
}

/* Two unit tetrahedra sharing only an edge: one shell through that edge, which is
 * non-manifold (4 facets). */
Test(report, nonmanifold_edge_open_edges_and_flips)
{
    float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, /* tet A: 0..3 */
                 0, -1, 0, 0, 0, -1}; /* tet B = 0, 1, 4, 5 shares edge 0-1 */
    uint32_t f[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3, /* A outward */
                    0, 1, 4, 0, 5, 1, 0, 4, 5, 1, 5, 4};
    hv_mesh *m;
    cr_assert_eq(hv_mesh_create(v, 6, f, 8, &m), HV_OK, "%s", hv_last_error());
    const hv_mesh_report *r = hv_mesh_get_report(m);
    cr_assert_eq(r->nonmanifold_edges, 1);
    cr_assert_eq(r->shells, 1);
    cr_assert_eq(r->open_edges, 0);
    const uint8_t *fl = hv_mesh_edge_flags(m);
    int flagged = 0;
    for (int i = 0; i < 8; ++i) flagged += __builtin_popcount(fl[i]);
    cr_assert_eq(flagged, 4);
    hv_mesh_destroy(m);

    /* drop one facet of A: three open edges */
    cr_assert_eq(hv_mesh_create(v, 4, f, 3, &m), HV_OK);
    cr_assert_eq(hv_mesh_get_report(m)->open_edges, 3);
    const int32_t *nb = hv_mesh_neighbors(m);
    int open = 0;
    for (int i = 0; i < 9; ++i) open += nb[i] == HV_MESH_OPEN;
    cr_assert_eq(open, 3);
    hv_mesh_destroy(m);

    /* flip one facet of A: one flipped facet, volume no longer 1/6 */
    uint32_t g[] = {0, 2, 1, 0, 1, 3, 0, 2, 3, 1, 2, 3};
    cr_assert_eq(hv_mesh_create(v, 4, g, 4, &m), HV_OK);
    cr_assert_eq(hv_mesh_get_report(m)->flipped_facets, 1);
    hv_mesh_destroy(m);
}

Test(report, separate_parts_and_degenerate_facets)
{
    hv_mesh *a, *b;
    double c1[3] = {0, 0, 0};
    cr_assert_eq(hv_generate_sphere(c1, 1, 8, 4, &a), HV_OK);
    /* second copy shifted: two shells */
    size_t nv = hv_mesh_vertex_count(a), nf = hv_mesh_facet_count(a);
    float *v = malloc(2 * nv * 3 * sizeof(float) + 9 * sizeof(float));
    uint32_t *f = malloc((2 * nf + 1) * 3 * sizeof(uint32_t));
    memcpy(v, hv_mesh_vertices(a), nv * 3 * sizeof(float));
    for (size_t i = 0; i < nv * 3; ++i) v[nv * 3 + i] = hv_mesh_vertices(a)[i] + (i % 3 == 0 ? 5.0f : 0.0f);
    memcpy(f, hv_mesh_facets(a), nf * 3 * sizeof(uint32_t));
    for (size_t i = 0; i < nf * 3; ++i) f[nf * 3 + i] = hv_mesh_facets(a)[i] + (uint32_t)nv;
    /* plus a collinear sliver on three new collinear points */
    float sl[9] = {10, 0, 0, 11, 0, 0, 12, 0, 0};
    memcpy(v + 2 * nv * 3, sl, sizeof sl);
    f[6 * nf] = (uint32_t)(2 * nv);
    f[6 * nf + 1] = (uint32_t)(2 * nv + 1);
    f[6 * nf + 2] = (uint32_t)(2 * nv + 2);
    cr_assert_eq(hv_mesh_create(v, 2 * nv + 3, f, 2 * nf + 1, &b), HV_OK);
    cr_assert_eq(hv_mesh_get_report(b)->shells, 3);
    cr_assert_eq(hv_mesh_get_report(b)->degenerate_facets, 1);
    cr_assert_eq(hv_mesh_get_report(b)->open_edges, 3);
    hv_mesh_destroy(a);
    hv_mesh_destroy(b);
    free(v);
    free(f);
}

Test(report, welding_is_exact_and_merges_signed_zero)
{
    float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, -0.0f, 0, 0, 1, 0, 0, 0, 0, 1, 1e-7f, 0, 0};
    uint32_t f[] = {0, 1, 2, 3, 4, 5, 6, 1, 2};
    hv_mesh *m;
    cr_assert_eq(hv_mesh_create(v, 7, f, 3, &m), HV_OK);
    /* -0 welds with 0; 1e-7 does not weld with 0 */
    cr_assert_eq(hv_mesh_vertex_count(m), 5);
    hv_mesh_destroy(m);
}

/* Issue 26 item 2: a reader of indexed facets (3MF) welds its points, not the corners they
 * expand to; the mesh must be the soup's, vertex for vertex: points repeated under other indices
 * (one spelt -0), unused, in any order, degenerate and non-manifold facets; small (one weld
 * partition) and large (several, when threads > 1). */
static void indexed_matches_soup(size_t npts, size_t nf, unsigned seed)
{
    float *xyz = malloc(3 * npts * sizeof *xyz), *soup = malloc(9 * nf * sizeof *soup);
    uint32_t *tri = malloc(3 * nf * sizeof *tri);
    cr_assert(xyz && soup && tri);
    uint32_t x = seed;
    for (size_t i = 0; i < npts; ++i) {
        x = x * 1664525u + 1013904223u;
        size_t src = i > 0 && (x >> 28) < 5 ? (x >> 8) % i : i; /* about a third repeat an earlier point */
        for (int k = 0; k < 3; ++k) {
            x = x * 1664525u + 1013904223u;
            xyz[3 * i + (size_t)k] = src != i ? xyz[3 * src + (size_t)k] : (x >> 29) == 0 ? 0.0f : (float)(x >> 20) / 64.0f;
        }
        if (src != i && xyz[3 * i] == 0.0f) xyz[3 * i] = -0.0f;
    }
    for (size_t r = 0; r < 3 * nf; ++r) {
        x = x * 1664525u + 1013904223u;
        tri[r] = (uint32_t)((x >> 4) % (npts - npts / 8)); /* the last eighth unused */
        memcpy(soup + 3 * r, xyz + 3 * (size_t)tri[r], 3 * sizeof *soup);
    }
    hv_mesh *a, *b;
    cr_assert_eq(hv_mesh_from_soup(soup, NULL, nf, "m", HV_MESH_3MF, &a), HV_OK);
    cr_assert_eq(hv_mesh_from_indexed(xyz, npts, tri, nf, "m", HV_MESH_3MF, &b), HV_OK);
    size_t nv = hv_mesh_vertex_count(a);
    cr_assert_eq(hv_mesh_vertex_count(b), nv);
    cr_assert_lt(nv, npts - npts / 8);
    cr_assert_eq(memcmp(hv_mesh_vertices(a), hv_mesh_vertices(b), 3 * nv * sizeof(float)), 0, "same bits, signs of zero too");
    cr_assert_eq(memcmp(hv_mesh_facets(a), hv_mesh_facets(b), 12 * nf), 0);
    cr_assert_eq(memcmp(hv_mesh_neighbors(a), hv_mesh_neighbors(b), 12 * nf), 0);
    cr_assert_eq(memcmp(hv_mesh_edge_flags(a), hv_mesh_edge_flags(b), nf), 0);
    cr_assert_eq(memcmp(hv_mesh_get_report(a), hv_mesh_get_report(b), sizeof(hv_mesh_report)), 0);
    hv_mesh_destroy(a);
    hv_mesh_destroy(b);
    free(xyz);
    free(soup);
    free(tri);
}

Test(report, welding_points_gives_the_soup_mesh)
{
    indexed_matches_soup(40, 60, 1);
    hv_set_threads(4);
    indexed_matches_soup(300000, 200000, 2);
    hv_set_threads(0);
}

Test(report, deterministic_across_thread_counts)
{
    hv_mesh *m1, *m2;
    hv_set_threads(1);
    cr_assert_eq(hv_generate_torus_knot(2, 3, 30, 12, 5, 2000, 64, &m1), HV_OK);
    hv_set_threads(4);
    cr_assert_eq(hv_generate_torus_knot(2, 3, 30, 12, 5, 2000, 64, &m2), HV_OK);
    hv_set_threads(0);
    cr_assert_eq(memcmp(hv_mesh_get_report(m1), hv_mesh_get_report(m2), sizeof(hv_mesh_report)), 0);
    cr_assert_eq(memcmp(hv_mesh_facets(m1), hv_mesh_facets(m2), 12 * hv_mesh_facet_count(m1)), 0);
    cr_assert_eq(memcmp(hv_mesh_neighbors(m1), hv_mesh_neighbors(m2), 12 * hv_mesh_facet_count(m1)), 0);
    hv_mesh_destroy(m1);
    hv_mesh_destroy(m2);
}

Test(generate, rejects_bad_parameters)
{
    hv_mesh *m = NULL;
    double c[3] = {0, 0, 0};
    cr_assert_eq(hv_generate_sphere(c, -1, 8, 4, &m), HV_ERR_INVALID);
    cr_assert_eq(hv_generate_torus(c, 5, 6, 8, 8, &m), HV_ERR_INVALID);
    cr_assert_eq(hv_generate_gear(24, 10, 12, 11, 5, 0, 12, 1, &m), HV_ERR_INVALID);
    cr_assert_eq(hv_generate_box_with_hole(c, c, 1, 8, &m), HV_ERR_INVALID);
    cr_assert_null(m);
}

/* A number is its whole token: a NUL byte inside one ("1\0" "2"; past the first KiB, where
 * the format check looks for binary bytes) is not the number 1. */
/* The pairing of half-edges around a non-manifold edge (hv_mesh_neighbors), against the rule
 * written out by brute force: in facet order, each unpaired half-edge takes the next unpaired one
 * of opposite direction, else the next unpaired one; a last odd one stays open. Facets fan around
 * the edge v0 v1, each wound one way or the other at random. */
Test(report, nonmanifold_pairing_follows_the_rule_for_any_fan)
{
    unsigned seed = 12345;
    for (int round = 0; round < 40; ++round) {
        size_t k = 3 + (size_t)(round * 7 % 97);
        float *xyz = malloc((k + 2) * 3 * sizeof *xyz);
        uint32_t *tri = malloc(k * 3 * sizeof *tri);
        int *dir = malloc(k * sizeof *dir);
        xyz[0] = 0, xyz[1] = 0, xyz[2] = 0, xyz[3] = 1, xyz[4] = 0, xyz[5] = 0;
        for (size_t i = 0; i < k; ++i) {
            double a = 6.283185307179586 * (double)i / (double)k;
            xyz[3 * (i + 2)] = 0.5f, xyz[3 * (i + 2) + 1] = (float)cos(a), xyz[3 * (i + 2) + 2] = (float)sin(a);
            seed = seed * 1103515245u + 12345u;
            dir[i] = (int)((seed >> 16) & 1u);
            tri[3 * i] = dir[i] ? 1 : 0, tri[3 * i + 1] = dir[i] ? 0 : 1, tri[3 * i + 2] = (uint32_t)(i + 2);
        }
        hv_mesh *m = NULL;
        cr_assert_eq(hv_mesh_create(xyz, k + 2, tri, k, &m), HV_OK, "%s", hv_last_error());
        /* the rule, quadratic, over the facets in order (edge 0 of every facet is v0 v1) */
        int32_t *want = malloc(k * sizeof *want);
        char *used = calloc(k, 1);
        for (size_t i = 0; i < k; ++i) {
            if (used[i]) continue;
            used[i] = 1;
            size_t pick = k;
            for (size_t j = i + 1; j < k && pick == k; ++j)
                if (!used[j] && dir[j] != dir[i]) pick = j;
            for (size_t j = i + 1; j < k && pick == k; ++j)
                if (!used[j]) pick = j;
            want[i] = pick == k ? HV_MESH_OPEN : (int32_t)pick;
            if (pick < k) used[pick] = 1, want[pick] = (int32_t)i;
        }
        const int32_t *nbr = hv_mesh_neighbors(m);
        for (size_t i = 0; i < k; ++i)
            cr_assert_eq(nbr[3 * i], want[i], "fan of %zu, facet %zu: %d, the rule says %d", k, i, nbr[3 * i], want[i]);
        free(want), free(used), free(dir), free(tri), free(xyz);
        hv_mesh_destroy(m);
    }
}
