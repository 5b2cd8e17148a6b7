/* tests/voxel/test_voxelize.c - the voxelizer against independent references: separability
 * (no 6-/26-connected path of non-surface voxels from inside to outside, with inside decided
 * by a brute-force ray test in world space), convergence of the voxel volume, holes and
 * flipped facets, anisotropic dims, determinism, memory limits, the transform convention. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/voxelize.h"
#include "support/support.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Brute-force inside test: parity of crossings of a ray in a generic direction. */
static int ray_inside(const hv_mesh *m, const double p[3])
{
    const float *v = hv_mesh_vertices(m);
    const uint32_t *t = hv_mesh_facets(m);
    size_t nf = hv_mesh_facet_count(m);
    const double d[3] = {0.57735026918962573, 0.57735103, 0.57734967};
    int c = 0;
    for (size_t f = 0; f < nf; ++f) {
        double a[3], b[3], cc[3];
        for (int k = 0; k < 3; ++k) {
            a[k] = v[3 * t[3 * f] + k];
            b[k] = v[3 * t[3 * f + 1] + k];
            cc[k] = v[3 * t[3 * f + 2] + k];
        }
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double e2[3] = {cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]};
        double h[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
        double det = e1[0] * h[0] + e1[1] * h[1] + e1[2] * h[2];
        if (fabs(det) < 1e-18) continue;
        double s[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        double u = (s[0] * h[0] + s[1] * h[1] + s[2] * h[2]) / det;
        if (u < 0 || u > 1) continue;
        double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
        double vv = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
        if (vv < 0 || u + vv > 1) continue;
        if ((e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det > 0) ++c;
    }
    return c & 1;
}

static hv_volume *voxelize(const hv_mesh *m, int adjacency, int64_t dims, hv_fill_mode fill)
{
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.adjacency = adjacency;
    o.dims[0] = dims;
    o.fill = fill;
    hv_volume *v = NULL;
    hv_status s = hv_voxelize(m, &o, &v);
    cr_assert_eq(s, HV_OK, "%s", hv_last_error());
    return v;
}

/* Count 6- or 26-adjacent pairs (inside, outside) of non-surface voxels: tunnels. Also
 * checks that the flood result agrees with the ray classification away from the surface. */
static void check_separation(const hv_mesh *m, int adjacency, int64_t dims, const char *what)
{
    hv_volume *v = voxelize(m, adjacency, dims, HV_FILL_FLOOD);
    int gs = hv_volume_grid_find(v, "surface"), go = hv_volume_grid_find(v, "occupancy");
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    int32_t lo[3], hi[3];
    cr_assert(hv_volume_index_bbox(v, lo, hi));
    int nx = hi[0] - lo[0] + 3, ny = hi[1] - lo[1] + 3, nz = hi[2] - lo[2] + 3;
    signed char *cls = malloc((size_t)nx * ny * nz);
    long mismatch = 0;
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j)
            for (int k = 0; k < nz; ++k) {
                int I = i + lo[0] - 1, J = j + lo[1] - 1, K = k + lo[2] - 1;
                signed char c;
                if (hv_accessor_bool(&acc, gs, I, J, K)) {
                    c = -1;
                } else {
                    double idx[3] = {I, J, K}, w[3];
                    hv_volume_index_to_world(v, idx, w);
                    c = (signed char)ray_inside(m, w);
                    if (c != hv_accessor_bool(&acc, go, I, J, K)) ++mismatch;
                }
                cls[((size_t)i * ny + j) * nz + k] = c;
            }
    long tunnels = 0;
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j)
            for (int k = 0; k < nz; ++k) {
                if (cls[((size_t)i * ny + j) * nz + k] != 1) continue;
                for (int di = -1; di <= 1; ++di)
                    for (int dj = -1; dj <= 1; ++dj)
                        for (int dk = -1; dk <= 1; ++dk) {
                            int n = abs(di) + abs(dj) + abs(dk);
                            if (!n || (adjacency == 6 && n > 1)) continue;
                            int a = i + di, b = j + dj, c = k + dk;
                            if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) continue;
                            if (cls[((size_t)a * ny + b) * nz + c] == 0) ++tunnels;
                        }
            }
    free(cls);
    hv_volume_destroy(v);
    cr_assert_eq(tunnels, 0, "%s, adjacency %d, dims %lld: %ld tunnels", what, adjacency,
                 (long long)dims, tunnels);
    cr_assert_eq(mismatch, 0, "%s, adjacency %d: %ld non-surface voxels misclassified by the flood",
                 what, adjacency, mismatch);
}

Test(voxelize, separating_on_analytic_shapes, .timeout = 120)
{
    hv_mesh *ms[4];
    double z[3] = {0, 0, 0}, c[3] = {0.3, -0.2, 0.1}, hi[3] = {40, 30, 20};
    cr_assert_eq(hv_generate_sphere(c, 10, 48, 24, &ms[0]), HV_OK);
    cr_assert_eq(hv_generate_box_with_hole(z, hi, 8, 32, &ms[1]), HV_OK);
    cr_assert_eq(hv_generate_torus(z, 20, 6, 48, 24, &ms[2]), HV_OK);
    cr_assert_eq(hv_generate_gear(12, 10, 12.5, 4, 6, 0.4, 8, 4, &ms[3]), HV_OK);
    const char *names[4] = {"sphere", "holed box", "torus", "helical gear"};
    for (int i = 0; i < 4; ++i) {
        check_separation(ms[i], 6, 40, names[i]);
        check_separation(ms[i], 26, 40, names[i]);
        hv_mesh_destroy(ms[i]);
    }
}

/* The holed box at 128 voxels puts its faces exactly halfway between voxel centres: the
 * closed inequalities must mark both layers (a rounding bug once opened a tunnel here). */
Test(voxelize, faces_halfway_between_voxel_centres, .timeout = 120)
{
    hv_mesh *m;
    double z[3] = {0, 0, 0}, hi[3] = {40, 30, 20};
    cr_assert_eq(hv_generate_box_with_hole(z, hi, 8, 64, &m), HV_OK);
    hv_volume *v = voxelize(m, 26, 128, HV_FILL_FLOOD);
    uint64_t occ = hv_volume_mask_count(v, hv_volume_grid_find(v, "occupancy"));
    uint64_t srf = hv_volume_mask_count(v, hv_volume_grid_find(v, "surface"));
    cr_assert_gt(occ, srf * 3, "the interior leaked: %llu occupied, %llu surface",
                 (unsigned long long)occ, (unsigned long long)srf);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

Test(voxelize, separating_on_shared_meshes, .timeout = 240)
{
    static const char *files[] = {"bunny_1500.stl", "bolt_colored_header.stl", "helical_gear.stl"};
    for (int i = 0; i < 3; ++i) {
        hv_mesh *m;
        cr_assert_eq(hv_mesh_load_stl(t_mesh_path(files[i]), &m), HV_OK, "%s", hv_last_error());
        check_separation(m, 26, 36, files[i]);
        check_separation(m, 6, 36, files[i]);
        hv_mesh_destroy(m);
    }
}

static double occupied_volume(const hv_volume *v)
{
    hv_transform xf = hv_volume_get_transform(v);
    return (double)hv_volume_mask_count(v, hv_volume_grid_find(v, "occupancy")) * xf.voxel[0] *
           xf.voxel[1] * xf.voxel[2];
}

Test(voxelize, volume_converges_to_the_mesh_volume)
{
    hv_mesh *m;
    double c[3] = {0, 0, 0};
    cr_assert_eq(hv_generate_sphere(c, 10, 128, 64, &m), HV_OK);
    double ref = hv_mesh_get_report(m)->volume, prev = INFINITY;
    int64_t dims[] = {16, 32, 64, 128, 256};
    for (int a = 0; a < 2; ++a)
        for (int i = 0; i < 5; ++i) {
            hv_volume *v = voxelize(m, a ? 26 : 6, dims[i], HV_FILL_AUTO);
            double err = fabs(occupied_volume(v) - ref) / ref;
            /* the surface skin (about Rc thick around the surface) is what remains: the error
             * must shrink roughly with the voxel size */
            cr_assert_lt(err, prev * 0.75, "adjacency %d dims %lld: error %g did not shrink (%g)",
                         a ? 26 : 6, (long long)dims[i], err, prev);
            prev = err;
            if (dims[i] == 256) cr_assert_lt(err, a ? 0.04 : 0.02, "error %g at 256", err);
            hv_volume_destroy(v);
            if (i == 4) prev = INFINITY;
        }
    hv_mesh_destroy(m);
}

/* The sphere without its facets whose centroid lies within `deg` degrees of direction d
 * (seen from the centre c): a hole facing any way, not only along an axis. */
static hv_mesh *without_cap(const hv_mesh *m, const double c[3], const double d[3], double deg)
{
    size_t nv = hv_mesh_vertex_count(m), nf = hv_mesh_facet_count(m), keep = 0;
    const float *xyz = hv_mesh_vertices(m);
    const uint32_t *all = hv_mesh_facets(m);
    uint32_t *tri = malloc(nf * 3 * sizeof *tri);
    double dl = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (size_t f = 0; f < nf; ++f) {
        double g[3] = {0, 0, 0};
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) g[a] += (xyz[3 * all[3 * f + k] + a] - c[a]) / 3.0;
        double gl = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        if ((g[0] * d[0] + g[1] * d[1] + g[2] * d[2]) / (gl * dl) > cos(deg * M_PI / 180)) continue;
        memcpy(tri + 3 * keep++, all + 3 * f, 3 * sizeof *tri);
    }
    hv_mesh *out = NULL;
    cr_assert_eq(hv_mesh_create(xyz, nv, tri, keep, &out), HV_OK);
    cr_assert_gt(hv_mesh_get_report(out)->open_edges, 0);
    free(tri);
    return out;
}

/* A sphere with a hole (facing an axis, a face diagonal or a space diagonal) and a sphere
 * with flipped facets voxelize like the repaired sphere: no leak to the outside, no hollow
 * inside. A diagonal hole is crossed by two or three of a voxel's axis lines. */
Test(voxelize, holes_and_flipped_facets_do_not_leak_or_hollow, .timeout = 60)
{
    hv_mesh *good;
    double c[3] = {1, 2, 3};
    cr_assert_eq(hv_generate_sphere(c, 10, 40, 20, &good), HV_OK);
    size_t nv = hv_mesh_vertex_count(good), nf = hv_mesh_facet_count(good);
    const float *xyz = hv_mesh_vertices(good);
    uint32_t *tri = malloc(nf * 3 * sizeof *tri);
    memcpy(tri, hv_mesh_facets(good), nf * 3 * sizeof *tri);
    /* hole: drop 6 facets on the side */
    hv_mesh *holed, *flipped;
    size_t keep = 0;
    for (size_t f = 0; f < nf; ++f) {
        if (f >= 400 && f < 406) continue;
        memcpy(tri + 3 * keep++, hv_mesh_facets(good) + 3 * f, 3 * sizeof *tri);
    }
    cr_assert_eq(hv_mesh_create(xyz, nv, tri, keep, &holed), HV_OK);
    cr_assert_gt(hv_mesh_get_report(holed)->open_edges, 0);
    memcpy(tri, hv_mesh_facets(good), nf * 3 * sizeof *tri);
    for (size_t f = 0; f < nf; f += 7) { /* flip every 7th facet */
        uint32_t x = tri[3 * f + 1];
        tri[3 * f + 1] = tri[3 * f + 2];
        tri[3 * f + 2] = x;
    }
    cr_assert_eq(hv_mesh_create(xyz, nv, tri, nf, &flipped), HV_OK);
    cr_assert_gt(hv_mesh_get_report(flipped)->flipped_facets, 0);
    free(tri);

    hv_volume *ref = voxelize(good, 26, 64, HV_FILL_AUTO);
    const double d111[3] = {1, 1, 1}, d110[3] = {1, -1, 0};
    hv_mesh *cap111 = without_cap(good, c, d111, 14), *cap110 = without_cap(good, c, d110, 10);
    hv_mesh *bad[4] = {holed, flipped, cap111, cap110};
    const char *what[4] = {"holed", "flipped", "diagonal hole (1,1,1)", "diagonal hole (1,-1,0)"};
    for (int b = 0; b < 4; ++b) {
        hv_voxel_plan plan;
        hv_voxelize_options o;
        hv_voxelize_options_init(&o);
        o.dims[0] = 64;
        cr_assert_eq(hv_voxelize_plan(bad[b], &o, &plan), HV_OK);
        cr_assert_eq(plan.fill, HV_FILL_VOTE, "auto must pick the robust fill");
        hv_volume *v = voxelize(bad[b], 26, 64, HV_FILL_AUTO);
        hv_accessor ar, av;
        hv_accessor_init(&ar, ref);
        hv_accessor_init(&av, v);
        int go = hv_volume_grid_find(v, "occupancy");
        long leak = 0, hollow = 0;
        hv_transform xf = hv_volume_get_transform(v);
        for (int i = -4; i < 68; ++i)
            for (int j = -4; j < 68; ++j)
                for (int k = -4; k < 68; ++k) {
                    double idx[3] = {i, j, k}, w[3];
                    hv_volume_index_to_world(v, idx, w);
                    double r = sqrt((w[0] - 1) * (w[0] - 1) + (w[1] - 2) * (w[1] - 2) + (w[2] - 3) * (w[2] - 3));
                    int occ = hv_accessor_bool(&av, go, i, j, k);
                    if (occ && r > 10 + 1.5 * xf.voxel[0]) ++leak;
                    if (!occ && r < 10 * cos(M_PI / 20) - 1.5 * xf.voxel[0]) ++hollow;
                }
        cr_assert_eq(leak, 0, "%s: %ld voxels leaked outside", what[b], leak);
        cr_assert_eq(hollow, 0, "%s: %ld voxels hollow inside", what[b], hollow);
        if (b == 1) /* flips change nothing: same voxels as the repaired sphere */
            cr_assert_eq(hv_volume_mask_count(v, go), hv_volume_mask_count(ref, 0));
        hv_volume_destroy(v);
    }
    hv_volume_destroy(ref);
    hv_mesh_destroy(good);
    hv_mesh_destroy(holed);
    hv_mesh_destroy(flipped);
    hv_mesh_destroy(cap111);
    hv_mesh_destroy(cap110);
}

Test(voxelize, vote_agrees_with_flood_on_closed_meshes, .timeout = 60)
{
    hv_mesh *m;
    cr_assert_eq(hv_mesh_load_stl(t_mesh_path("helical_gear.stl"), &m), HV_OK);
    hv_volume *a = voxelize(m, 26, 64, HV_FILL_FLOOD), *b = voxelize(m, 26, 64, HV_FILL_VOTE);
    cr_assert_eq(hv_volume_leaf_count(a), hv_volume_leaf_count(b));
    size_t diff = 0;
    for (size_t l = 0; l < hv_volume_leaf_count(a); ++l)
        for (int w = 0; w < 8; ++w)
            diff += (size_t)__builtin_popcountll(hv_volume_leaf_mask(a, l)[w] ^ hv_volume_leaf_mask(b, l)[w]);
    cr_assert_eq(diff, 0, "flood and vote differ in %zu voxels", diff);
    hv_volume_destroy(a);
    hv_volume_destroy(b);
    hv_mesh_destroy(m);
}

/* Wu's (64,64,45): explicit dims per axis give anisotropic voxels covering the box. */
Test(voxelize, anisotropic_dims)
{
    hv_mesh *m;
    double lo[3] = {0, 0, 0}, hi[3] = {20, 20, 20};
    cr_assert_eq(hv_generate_box(lo, hi, &m), HV_OK);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.dims[0] = 64;
    o.dims[1] = 64;
    o.dims[2] = 45;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_OK, "%s", hv_last_error());
    hv_transform xf = hv_volume_get_transform(v);
    cr_assert_float_eq(xf.voxel[0], 20.0 / 64, 1e-12);
    cr_assert_float_eq(xf.voxel[2], 20.0 / 45, 1e-12);
    cr_assert_float_eq(xf.origin[2], 0.5 * 20.0 / 45, 1e-9); /* voxel 0 centred half a voxel in */
    int32_t a[3], b[3];
    cr_assert(hv_volume_index_bbox(v, a, b));
    /* the box fills voxels 0..dims-1 exactly; the surface reaches one voxel beyond */
    cr_assert_eq(a[2], -1);
    cr_assert_eq(b[2], 45);
    cr_assert_eq(b[0], 64);
    /* interior voxels: all of [0, dims) */
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    int go = hv_volume_grid_find(v, "occupancy");
    for (int i = 0; i < 64; i += 7)
        for (int k = 0; k < 45; k += 4) cr_assert(hv_accessor_bool(&acc, go, i, 31, k));
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

Test(voxelize, deterministic_for_any_thread_count, .timeout = 60)
{
    hv_mesh *m;
    cr_assert_eq(hv_generate_torus_knot(2, 3, 30, 12, 5, 600, 32, &m), HV_OK);
    hv_volume *v[3];
    int threads[3] = {1, 2, 7};
    for (int t = 0; t < 3; ++t) {
        hv_set_threads(threads[t]);
        v[t] = voxelize(m, 26, 96, t == 2 ? HV_FILL_VOTE : HV_FILL_FLOOD);
    }
    hv_set_threads(0);
    hv_volume *w = voxelize(m, 26, 96, HV_FILL_VOTE);
    cr_assert_eq(hv_volume_leaf_count(v[0]), hv_volume_leaf_count(v[1]));
    for (size_t l = 0; l < hv_volume_leaf_count(v[0]); ++l) {
        cr_assert_eq(memcmp(hv_volume_leaf_origins(v[0]) + 3 * l, hv_volume_leaf_origins(v[1]) + 3 * l, 12), 0);
        cr_assert_eq(memcmp(hv_volume_leaf_mask(v[0], l), hv_volume_leaf_mask(v[1], l), 64), 0);
        cr_assert_eq(memcmp(hv_volume_leaf_bool_c(v[0], 1, l), hv_volume_leaf_bool_c(v[1], 1, l), 64), 0);
    }
    for (size_t l = 0; l < hv_volume_leaf_count(w); ++l)
        cr_assert_eq(memcmp(hv_volume_leaf_mask(v[2], l), hv_volume_leaf_mask(w, l), 64), 0);
    for (int t = 0; t < 3; ++t) hv_volume_destroy(v[t]);
    hv_volume_destroy(w);
    hv_mesh_destroy(m);
}

Test(voxelize, plans_refuse_and_validate)
{
    hv_mesh *m;
    double lo[3] = {0, 0, 0}, hi[3] = {10, 10, 10};
    cr_assert_eq(hv_generate_box(lo, hi, &m), HV_OK);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.dims[0] = 4096;
    o.max_memory = 64u << 20;
    hv_volume *v = (hv_volume *)0x1;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_ERR_LIMIT);
    cr_assert_null(v);
    cr_assert(strstr(hv_last_error(), "needs about") && strstr(hv_last_error(), "GiB"), "%s",
              hv_last_error());
    hv_voxelize_options_init(&o);
    o.adjacency = 7;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_ERR_INVALID);
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = -1;
    o.voxel_size[1] = o.voxel_size[2] = 1;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_ERR_INVALID);
    hv_voxelize_options_init(&o);
    o.dims[0] = -3; /* all zero is the default (128 on the longest axis); negative is refused */
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_ERR_INVALID);
    /* voxel size: 2.5 on a 10 box -> 4 voxels, centres at 1.25, 3.75, ... */
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 2.5;
    hv_voxel_plan plan;
    cr_assert_eq(hv_voxelize_plan(m, &o, &plan), HV_OK);
    cr_assert_eq(plan.dims[0], 4);
    cr_assert_eq(plan.first[0], 0);
    cr_assert_float_eq(plan.xf.origin[0], 1.25, 1e-12);
    /* the same voxel size on a shifted mesh: the same global lattice, other indices */
    hv_mesh *m2;
    double lo2[3] = {-7.4, 3, 0}, hi2[3] = {1, 9, 4};
    cr_assert_eq(hv_generate_box(lo2, hi2, &m2), HV_OK);
    hv_voxel_plan p2;
    cr_assert_eq(hv_voxelize_plan(m2, &o, &p2), HV_OK);
    cr_assert(hv_transform_same(&plan.xf, &p2.xf));
    cr_assert_eq(p2.first[0], -3); /* centre -6.25 holds x = -7.4 */
    cr_assert_eq(p2.dims[0], 4);
    /* and on an explicit lattice */
    hv_transform lat = {{0.4, 0.4, 0.4}, {0.1, 0.1, 0.1}};
    hv_voxelize_options_init(&o);
    o.lattice = &lat;
    cr_assert_eq(hv_voxelize_plan(m2, &o, &p2), HV_OK);
    cr_assert(hv_transform_same(&lat, &p2.xf));
    cr_assert_eq(p2.first[0], -19); /* cell of -7.5 .. -7.1 */
    hv_mesh_destroy(m2);
    hv_mesh_destroy(m);
}

static int cancel_at(void *user, const char *stage, double f)
{
    (void)f;
    return strcmp(stage, (const char *)user) == 0;
}

Test(voxelize, cancels_and_records_metadata)
{
    hv_mesh *m;
    double c[3] = {0, 0, 0};
    cr_assert_eq(hv_generate_sphere(c, 5, 32, 16, &m), HV_OK);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    hv_progress p = {cancel_at, (void *)"interior"};
    o.progress = &p;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_ERR_CANCELLED);
    cr_assert_null(v);
    o.progress = NULL;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_OK);
    cr_assert_not_null(hv_volume_meta_string(v, "hovox.mesh.json"));
    cr_assert(strstr(hv_volume_meta_string(v, "hovox.voxelize.json"), "\"fill\": \"flood\""));
    cr_assert_str_eq(hv_volume_grid_name(v, 0), "occupancy");
    cr_assert_eq(hv_volume_grid_type(v, 1), HV_GRID_BOOL);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

/* A hollow part (an outer shell and an inward-facing cavity, both closed): AUTO must not flood,
 * which would fill the cavity; it votes, and every voxel centre in the cavity stays empty while
 * the wall is solid. Checked against the boxes' bounds, voxel by voxel. */
Test(voxelize, auto_keeps_a_hollow_parts_cavity_empty)
{
    hv_mesh *outer, *inner, *m;
    double lo[3] = {0, 0, 0}, hi[3] = {10, 10, 10}, clo[3] = {3, 3, 3}, chi[3] = {7, 7, 7};
    cr_assert_eq(hv_generate_box(lo, hi, &outer), HV_OK);
    cr_assert_eq(hv_generate_box(clo, chi, &inner), HV_OK);
    /* one mesh: the outer box's facets and the cavity's, reversed */
    size_t no = hv_mesh_facet_count(outer), ni = hv_mesh_facet_count(inner);
    size_t vo = hv_mesh_vertex_count(outer), vi = hv_mesh_vertex_count(inner);
    float *xyz = malloc((vo + vi) * 3 * sizeof *xyz);
    uint32_t *f = malloc((no + ni) * 3 * sizeof *f);
    memcpy(xyz, hv_mesh_vertices(outer), vo * 3 * sizeof *xyz);
    memcpy(xyz + 3 * vo, hv_mesh_vertices(inner), vi * 3 * sizeof *xyz);
    memcpy(f, hv_mesh_facets(outer), no * 3 * sizeof *f);
    const uint32_t *fi = hv_mesh_facets(inner);
    for (size_t t = 0; t < ni; ++t) {
        f[3 * (no + t)] = (uint32_t)vo + fi[3 * t];
        f[3 * (no + t) + 1] = (uint32_t)vo + fi[3 * t + 2];
        f[3 * (no + t) + 2] = (uint32_t)vo + fi[3 * t + 1];
    }
    cr_assert_eq(hv_mesh_create(xyz, vo + vi, f, no + ni, &m), HV_OK, "%s", hv_last_error());
    const hv_mesh_report *r = hv_mesh_get_report(m);
    cr_assert_eq(r->shells, 2);
    cr_assert_eq(r->open_edges + r->nonmanifold_edges + r->flipped_facets, 0);
    cr_assert_float_eq(r->volume, 1000.0 - 64.0, 1e-6);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.5;
    hv_voxel_plan plan;
    cr_assert_eq(hv_voxelize_plan(m, &o, &plan), HV_OK, "%s", hv_last_error());
    cr_assert_eq(plan.fill, HV_FILL_VOTE);
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_OK, "%s", hv_last_error());
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    int go = hv_volume_grid_find(v, "occupancy");
    hv_transform xf = hv_volume_get_transform(v);
    uint64_t cavity = 0, wall = 0;
    for (int i = 0; i < 20; ++i)
        for (int j = 0; j < 20; ++j)
            for (int k = 0; k < 20; ++k) {
                double c[3] = {xf.origin[0] + i * 0.5, xf.origin[1] + j * 0.5, xf.origin[2] + k * 0.5};
                int in_cavity = 1, deep_cavity = 1;
                for (int a = 0; a < 3; ++a) {
                    in_cavity &= c[a] > 3 && c[a] < 7;
                    deep_cavity &= c[a] > 3.6 && c[a] < 6.4; /* beyond the cavity's surface voxels */
                }
                int occ = hv_accessor_bool(&acc, go, i, j, k);
                if (deep_cavity) cr_assert(!occ, "cavity voxel %d %d %d is filled", i, j, k);
                if (!in_cavity) {
                    cr_assert(occ, "wall voxel %d %d %d is empty", i, j, k);
                    ++wall;
                }
                cavity += deep_cavity;
            }
    cr_assert_eq(wall, 8000 - 512);
    cr_assert_gt(cavity, 0);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
    hv_mesh_destroy(outer);
    hv_mesh_destroy(inner);
    free(xyz);
    free(f);
}
