/* tests/volumes/test_volume.c - the volume store: grids sharing a topology, leaf buffers,
 * accessors, trilinear sampling, mask algebra, metadata, .vdb round trips (read back by the
 * library and listed by vdb_print), cross-volume copies, memory accounting. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/volume.h"
#include "support/support.h"

static hv_volume *make(double vx, double vy, double vz)
{
    hv_transform xf = {{vx, vy, vz}, {0.5, -1.0, 2.0}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK, "%s", hv_last_error());
    return v;
}

/* Activate the voxels [lo, hi] (inclusive) of a box. */
static void add_box(hv_volume *v, const int lo[3], const int hi[3])
{
    cr_assert_eq(t_add_box(v, lo, hi), HV_OK, "%s", hv_last_error());
}

/* Fill float grid g with f(i,j,k) = i + 2j - 3k + 0.5 and bool grid b with (i+j+k) even. */
static void fill(hv_volume *v, int g, int b)
{
    const int32_t *org = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        float *fb = g >= 0 ? hv_volume_leaf_float(v, g, l) : NULL;
        uint64_t *bb = b >= 0 ? hv_volume_leaf_bool(v, b, l) : NULL;
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            int i = org[3 * l] + (int)(n >> 6), j = org[3 * l + 1] + (int)((n >> 3) & 7),
                k = org[3 * l + 2] + (int)(n & 7);
            if (fb) fb[n] = (float)(i + 2 * j - 3 * k) + 0.5f;
            if (bb && ((i + j + k) & 1) == 0) bb[n / 64] |= 1ull << (n % 64);
        }
    }
}

Test(volume, grids_share_one_topology)
{
    hv_volume *v = make(0.5, 0.5, 0.5);
    int lo[3] = {-5, 0, 3}, hi[3] = {12, 9, 20};
    int f, b;
    cr_assert_eq(hv_volume_grid_add(v, "density", HV_GRID_FLOAT, &f), HV_OK);
    add_box(v, lo, hi);
    cr_assert_eq(hv_volume_grid_add(v, "mask", HV_GRID_BOOL, &b), HV_OK);
    cr_assert_eq(hv_volume_active_count(v), 18u * 10u * 18u);
    int32_t a[3], z[3];
    cr_assert(hv_volume_index_bbox(v, a, z));
    cr_assert_eq(a[0], -5);
    cr_assert_eq(z[2], 20);
    cr_assert_eq(hv_volume_grid_find(v, "mask"), b);
    cr_assert_eq(hv_volume_grid_find(v, "nope"), -1);
    /* the grid of a type, or a message listing that type's grids */
    cr_assert_eq(hv_volume_grid_need(v, "mask", HV_GRID_BOOL), b);
    cr_assert_eq(hv_volume_grid_need(v, "density", HV_GRID_BOOL), -1);
    cr_assert_str_eq(hv_last_error(), "no bool grid 'density' (bool grids: mask)");
    cr_assert_eq(hv_volume_grid_need(v, "nope", HV_GRID_FLOAT), -1);
    cr_assert_str_eq(hv_last_error(), "no float grid 'nope' (float grids: density)");
    cr_assert_null(hv_volume_leaf_bool(v, f, 0));
    cr_assert_null(hv_volume_leaf_float(v, b, 0));
    /* a new grid starts at zero everywhere */
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (int n = 0; n < 8; ++n) cr_assert_eq(hv_volume_leaf_bool(v, b, l)[n], 0u);
    cr_assert_eq(hv_volume_grid_add(v, "mask", HV_GRID_FLOAT, NULL), HV_ERR_INVALID);
    cr_assert_eq(hv_volume_grid_add(v, "", HV_GRID_FLOAT, NULL), HV_ERR_INVALID);
    cr_assert_eq(hv_volume_grid_rename(v, f, "rho"), HV_OK);
    cr_assert_str_eq(hv_volume_grid_name(v, f), "rho");
    cr_assert_eq(hv_volume_grid_remove(v, f), HV_OK);
    cr_assert_eq(hv_volume_grid_count(v), 1);
    cr_assert_str_eq(hv_volume_grid_name(v, 0), "mask");
    int32_t bad_origin[3] = {1, 0, 0};
    uint64_t mask[8] = {1};
    cr_assert_eq(hv_volume_topology_add(v, 1, bad_origin, mask), HV_ERR_INVALID);
    hv_volume_destroy(v);
    hv_volume_destroy(NULL);
}

Test(volume, accessor_and_trilinear_sampling)
{
    hv_volume *v = make(0.5, 0.25, 2.0); /* anisotropic voxels */
    int lo[3] = {0, 0, 0}, hi[3] = {15, 15, 15};
    add_box(v, lo, hi);
    int g;
    cr_assert_eq(hv_volume_grid_add(v, "f", HV_GRID_FLOAT, &g), HV_OK);
    fill(v, g, -1);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    cr_assert_float_eq(hv_accessor_float(&acc, g, 3, 4, 5), 3 + 8 - 15 + 0.5, 1e-6);
    cr_assert_eq(hv_accessor_float(&acc, g, 16, 0, 0), 0.0f);
    cr_assert(hv_accessor_active(&acc, 15, 15, 15));
    cr_assert(!hv_accessor_active(&acc, -1, 0, 0));
    cr_assert_eq(hv_accessor_set_float(&acc, g, 99, 0, 0, 1.0f), HV_ERR_INVALID);
    /* a linear field is reproduced exactly inside; world (x,y,z) -> index via the transform */
    for (int t = 0; t < 200; ++t) {
        double idx[3] = {1 + 13.0 * rand() / RAND_MAX, 1 + 13.0 * rand() / RAND_MAX,
                         1 + 13.0 * rand() / RAND_MAX};
        double w[3], back[3];
        hv_volume_index_to_world(v, idx, w);
        hv_volume_world_to_index(v, w, back);
        for (int a = 0; a < 3; ++a) cr_assert_float_eq(back[a], idx[a], 1e-9);
        float out, cov;
        hv_volume_sample(&acc, &g, 1, w, &out, &cov);
        cr_assert_float_eq(out, idx[0] + 2 * idx[1] - 3 * idx[2] + 0.5, 1e-4);
        cr_assert_float_eq(cov, 1.0f, 1e-6);
    }
    /* half a voxel outside the boundary: coverage 1/2, value renormalised from inside */
    double w[3], idx[3] = {15.5, 5, 5};
    hv_volume_index_to_world(v, idx, w);
    float out, cov;
    hv_volume_sample(&acc, &g, 1, w, &out, &cov);
    cr_assert_float_eq(cov, 0.5f, 1e-6);
    cr_assert_float_eq(out, 15 + 10 - 15 + 0.5, 1e-4);
    idx[0] = 40;
    hv_volume_index_to_world(v, idx, w);
    hv_volume_sample(&acc, &g, 1, w, &out, &cov);
    cr_assert_eq(cov, 0.0f);
    cr_assert_eq(out, 0.0f);
    hv_volume_destroy(v);
}

Test(volume, mask_algebra_and_restrict)
{
    hv_volume *v = make(1, 1, 1);
    int lo[3] = {0, 0, 0}, hi[3] = {9, 9, 9};
    add_box(v, lo, hi);
    int a, b, d, f;
    hv_volume_grid_add(v, "a", HV_GRID_BOOL, &a);
    hv_volume_grid_add(v, "b", HV_GRID_BOOL, &b);
    hv_volume_grid_add(v, "d", HV_GRID_BOOL, &d);
    hv_volume_grid_add(v, "f", HV_GRID_FLOAT, &f);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    /* a: x < 5, b: y < 5 */
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const int32_t *o = hv_volume_leaf_origins(v) + 3 * l;
        uint64_t *wa = hv_volume_leaf_bool(v, a, l), *wb = hv_volume_leaf_bool(v, b, l);
        for (unsigned n = 0; n < 512; ++n) {
            if (o[0] + (int)(n >> 6) < 5) wa[n / 64] |= 1ull << (n % 64);
            if (o[1] + (int)((n >> 3) & 7) < 5) wb[n / 64] |= 1ull << (n % 64);
        }
    }
    cr_assert_eq(hv_volume_mask_count(v, a), 500u);
    cr_assert_eq(hv_volume_mask_combine(v, d, a, b, HV_MASK_UNION), HV_OK);
    cr_assert_eq(hv_volume_mask_count(v, d), 750u);
    cr_assert_eq(hv_volume_mask_combine(v, d, a, b, HV_MASK_INTERSECT), HV_OK);
    cr_assert_eq(hv_volume_mask_count(v, d), 250u);
    cr_assert_eq(hv_volume_mask_combine(v, d, a, b, HV_MASK_DIFFERENCE), HV_OK);
    cr_assert_eq(hv_volume_mask_count(v, d), 250u);
    cr_assert(hv_accessor_bool(&acc, d, 2, 7, 1));
    cr_assert(!hv_accessor_bool(&acc, d, 2, 2, 1));
    cr_assert_eq(hv_volume_mask_combine(v, d, a, f, HV_MASK_UNION), HV_ERR_INVALID);
    /* restrict the topology to the difference: 250 voxels remain, values kept */
    hv_accessor_set_float(&acc, f, 2, 7, 1, 42.0f);
    cr_assert_eq(hv_volume_topology_restrict(v, d), HV_OK);
    cr_assert_eq(hv_volume_active_count(v), 250u);
    hv_accessor_init(&acc, v);
    cr_assert_float_eq(hv_accessor_float(&acc, f, 2, 7, 1), 42.0f, 0);
    cr_assert(!hv_accessor_active(&acc, 7, 7, 1));
    cr_assert_eq(hv_volume_topology_restrict(v, f), HV_ERR_INVALID);
    hv_volume_destroy(v);
}

Test(volume, metadata)
{
    hv_volume *v = make(1, 1, 1);
    cr_assert_eq(hv_volume_meta_set_string(v, "b", "two"), HV_OK);
    cr_assert_eq(hv_volume_meta_set_number(v, "a", 1.5), HV_OK);
    cr_assert_eq(hv_volume_meta_set_json(v, "c.json", "{\"x\": [1, 2]}"), HV_OK);
    cr_assert_eq(hv_volume_meta_set_json(v, "d.json", "{x}"), HV_ERR_INVALID);
    cr_assert_eq(hv_volume_meta_set_string(v, "", "x"), HV_ERR_INVALID);
    cr_assert_eq(hv_volume_meta_count(v), 3);
    cr_assert_str_eq(hv_volume_meta_key(v, 0), "a");
    double d;
    cr_assert(hv_volume_meta_number(v, "a", &d));
    cr_assert_eq(d, 1.5);
    cr_assert_null(hv_volume_meta_string(v, "a"));
    cr_assert_str_eq(hv_volume_meta_string(v, "b"), "two");
    cr_assert_eq(hv_volume_meta_set_string(v, "b", NULL), HV_OK);
    cr_assert_null(hv_volume_meta_string(v, "b"));
    cr_assert_eq(hv_volume_meta_count(v), 2);
    hv_volume_destroy(v);
}

Test(volume, save_load_round_trip_and_vdb_print)
{
    hv_volume *v = make(0.5, 0.5, 0.75);
    int lo[3] = {-3, -3, -3}, hi[3] = {20, 11, 9};
    add_box(v, lo, hi);
    int g, b;
    hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &b);
    hv_volume_grid_add(v, "material.steel", HV_GRID_FLOAT, &g);
    fill(v, g, b);
    hv_volume_meta_set_json(v, "hovox.materials.json", "[{\"name\": \"steel\"}]");
    hv_volume_meta_set_number(v, "hovox.version", 1);
    const char *path = t_tmpfile("round.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());

    hv_volume *r = NULL;
    cr_assert_eq(hv_volume_load(path, &r), HV_OK, "%s", hv_last_error());
    hv_transform a = hv_volume_get_transform(v), c = hv_volume_get_transform(r);
    cr_assert(hv_transform_same(&a, &c));
    cr_assert_eq(hv_volume_grid_count(r), 2);
    cr_assert_str_eq(hv_volume_grid_name(r, 0), "occupancy");
    cr_assert_eq(hv_volume_grid_type(r, 0), HV_GRID_BOOL);
    cr_assert_eq(hv_volume_grid_type(r, 1), HV_GRID_FLOAT);
    cr_assert_eq(hv_volume_active_count(r), hv_volume_active_count(v));
    cr_assert_eq(hv_volume_mask_count(r, 0), hv_volume_mask_count(v, b));
    hv_accessor x, y;
    hv_accessor_init(&x, v);
    hv_accessor_init(&y, r);
    for (int i = -4; i <= 21; ++i)
        for (int j = -4; j <= 12; j += 3)
            for (int k = -4; k <= 10; k += 2) {
                cr_assert_eq(hv_accessor_float(&x, g, i, j, k), hv_accessor_float(&y, 1, i, j, k));
                cr_assert_eq(hv_accessor_bool(&x, b, i, j, k), hv_accessor_bool(&y, 0, i, j, k));
            }
    cr_assert_str_eq(hv_volume_meta_string(r, "hovox.materials.json"), "[{\"name\": \"steel\"}]");
    double d;
    cr_assert(hv_volume_meta_number(r, "hovox.version", &d));
    cr_assert_eq(d, 1.0);

    /* the file is a real OpenVDB file: vdb_print lists both grids with their types */
    char cmd[1024], *out = NULL;
    snprintf(cmd, sizeof cmd, "vdb_print '%s' 2>&1", path);
    cr_assert_eq(t_run(cmd, &out), 0, "vdb_print failed: %s", out);
    cr_assert(strstr(out, "occupancy") && strstr(out, "bool"), "%s", out);
    cr_assert(strstr(out, "material.steel") && strstr(out, "float"), "%s", out);
    free(out);
    hv_volume_destroy(v);
    hv_volume_destroy(r);
}

Test(volume, load_errors)
{
    hv_volume *v = (hv_volume *)0x1;
    cr_assert_eq(hv_volume_load("/nonexistent/x.vdb", &v), HV_ERR_IO);
    cr_assert_null(v);
    cr_assert_eq(hv_volume_load("/tmp", &v), HV_ERR_IO);
    cr_assert_eq(hv_volume_load("tests/data/good/tet_ascii.stl", &v), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "not an OpenVDB file") != NULL);
    /* a VDB file cut short */
    hv_volume *s = make(1, 1, 1);
    int lo[3] = {0, 0, 0}, hi[3] = {30, 30, 30};
    add_box(s, lo, hi);
    hv_volume_grid_add(s, "f", HV_GRID_FLOAT, NULL);
    const char *p = t_tmpfile("cut.vdb");
    cr_assert_eq(hv_volume_save(s, p), HV_OK);
    char cmd[600];
    snprintf(cmd, sizeof cmd, "truncate -s 300 '%s'", p);
    cr_assert_eq(t_run(cmd, NULL), 0);
    cr_assert_eq(hv_volume_load(p, &v), HV_ERR_BAD_INPUT, "%s", hv_last_error());
    cr_assert_null(v);
    cr_assert(strstr(hv_last_error(), p) != NULL);
    hv_volume_destroy(s);
}

Test(volume, copy_union_clone)
{
    hv_volume *a = make(1, 1, 1), *b = make(1, 1, 1), *c = make(2, 1, 1);
    int lo1[3] = {0, 0, 0}, hi1[3] = {9, 9, 9}, lo2[3] = {5, 5, 5}, hi2[3] = {14, 14, 14};
    add_box(a, lo1, hi1);
    add_box(b, lo2, hi2);
    int ga, gb;
    hv_volume_grid_add(a, "f", HV_GRID_FLOAT, &ga);
    hv_volume_grid_add(b, "f", HV_GRID_FLOAT, &gb);
    fill(b, gb, -1);
    cr_assert_eq(hv_volume_grid_copy(a, "fromb", b, gb), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_active_count(a), 1000u + 1000u - 125u);
    int gc = hv_volume_grid_find(a, "fromb");
    hv_accessor acc;
    hv_accessor_init(&acc, a);
    cr_assert_float_eq(hv_accessor_float(&acc, gc, 12, 12, 12), 12 + 24 - 36 + 0.5, 0);
    cr_assert_eq(hv_accessor_float(&acc, gc, 1, 1, 1), 0.0f); /* a's own voxel, not in b */
    cr_assert_eq(hv_accessor_float(&acc, ga, 12, 12, 12), 0.0f);
    cr_assert_eq(hv_volume_grid_copy(c, "x", b, gb), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "different voxel lattices") != NULL);
    /* copy within a volume */
    cr_assert_eq(hv_volume_grid_copy(a, "again", a, gc), HV_OK);
    hv_accessor_init(&acc, a);
    cr_assert_float_eq(hv_accessor_float(&acc, hv_volume_grid_find(a, "again"), 12, 12, 12),
                       12 + 24 - 36 + 0.5, 0);
    /* clones are independent */
    hv_volume *k = NULL;
    cr_assert_eq(hv_volume_clone(a, &k), HV_OK);
    hv_accessor ak;
    hv_accessor_init(&ak, k);
    hv_accessor_set_float(&ak, gc, 12, 12, 12, 7.0f);
    cr_assert_float_eq(hv_accessor_float(&acc, gc, 12, 12, 12), 12 + 24 - 36 + 0.5, 0);
    cr_assert_eq(hv_accessor_float(&ak, gc, 12, 12, 12), 7.0f);
    cr_assert_eq(hv_volume_grid_count(k), hv_volume_grid_count(a));
    hv_volume_destroy(a);
    hv_volume_destroy(b);
    hv_volume_destroy(c);
    hv_volume_destroy(k);
}

Test(volume, memory_estimate_matches_use)
{
    hv_volume *v = make(1, 1, 1);
    int lo[3] = {0, 0, 0}, hi[3] = {127, 127, 63};
    add_box(v, lo, hi);
    for (int i = 0; i < 3; ++i) {
        char name[16];
        snprintf(name, sizeof name, "m%d", i);
        hv_volume_grid_add(v, name, HV_GRID_FLOAT, NULL);
    }
    hv_volume_grid_add(v, "occ", HV_GRID_BOOL, NULL);
    uint64_t used = hv_volume_memory_bytes(v);
    uint64_t est = hv_volume_memory_estimate(hv_volume_leaf_count(v), 3, 1);
    cr_assert_gt(used, 3u * 128 * 128 * 64 * 4);
    cr_assert(est > used * 0.8 && est < used * 1.5, "estimate %llu vs used %llu",
              (unsigned long long)est, (unsigned long long)used);
    hv_volume_destroy(v);
}

/* The grids of `a` named in `names` equal those of `b` of the same names (values and voxels). */
static void same_grids(const hv_volume *a, const hv_volume *b)
{
    cr_assert_eq(hv_volume_leaf_count(a), hv_volume_leaf_count(b));
    cr_assert_eq(hv_volume_active_count(a), hv_volume_active_count(b));
    for (int g = 0; g < hv_volume_grid_count(a); ++g) {
        int h = hv_volume_grid_find(b, hv_volume_grid_name(a, g));
        cr_assert_geq(h, 0, "grid '%s' missing", hv_volume_grid_name(a, g));
        cr_assert_eq(hv_volume_grid_type(a, g), hv_volume_grid_type(b, h));
        for (size_t l = 0; l < hv_volume_leaf_count(a); ++l) {
            cr_assert_eq(memcmp(hv_volume_leaf_origins(a) + 3 * l, hv_volume_leaf_origins(b) + 3 * l, 12), 0);
            const uint64_t *m = hv_volume_leaf_mask(a, l);
            cr_assert_eq(memcmp(m, hv_volume_leaf_mask(b, l), 64), 0);
            for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
                if (!HV_BIT_GET(m, n)) continue;
                if (hv_volume_grid_type(a, g) == HV_GRID_FLOAT)
                    cr_assert_eq(hv_volume_leaf_float_c(a, g, l)[n], hv_volume_leaf_float_c(b, h, l)[n]);
                else
                    cr_assert_eq(HV_BIT_GET(hv_volume_leaf_bool_c(a, g, l), n), HV_BIT_GET(hv_volume_leaf_bool_c(b, h, l), n));
            }
        }
    }
}

/* Byte range [*blocks, *end) of grid `name`'s tree in a .vdb file with grid offsets: its
 * descriptor (name, type, no instance parent) ends with grid, blocks and end position. */
static void grid_bytes(const unsigned char *d, size_t n, const char *name, const char *type, int64_t *blocks,
                       int64_t *end)
{
    unsigned char pat[128];
    size_t ln = strlen(name), lt = strlen(type), k = 0;
    uint32_t u = (uint32_t)ln;
    memcpy(pat + k, &u, 4), k += 4, memcpy(pat + k, name, ln), k += ln;
    u = (uint32_t)lt;
    memcpy(pat + k, &u, 4), k += 4, memcpy(pat + k, type, lt), k += lt;
    memset(pat + k, 0, 4), k += 4;
    for (size_t i = 0; i + k + 24 <= n; ++i)
        if (memcmp(d + i, pat, k) == 0) {
            memcpy(blocks, d + i + k + 8, 8);
            memcpy(end, d + i + k + 16, 8);
            return;
        }
    cr_assert_fail("no descriptor of grid '%s' in the file", name);
}

Test(volume, load_selected_grids)
{
    hv_volume *v = make(0.5, 0.5, 0.5);
    int lo[3] = {-3, 0, 2}, hi[3] = {25, 17, 13};
    add_box(v, lo, hi);
    int occ, a, b, surf, dens;
    hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &occ);
    hv_volume_grid_add(v, "material.a", HV_GRID_FLOAT, &a);
    hv_volume_grid_add(v, "surface", HV_GRID_BOOL, &surf);
    hv_volume_grid_add(v, "material.b", HV_GRID_FLOAT, &b);
    hv_volume_grid_add(v, "density", HV_GRID_FLOAT, &dens);
    fill(v, a, occ);
    fill(v, b, surf);
    fill(v, dens, -1);
    hv_volume_meta_set_json(v, "hovox.materials.json", "[{\"name\": \"a\"}, {\"name\": \"b\"}]");
    const char *path = t_tmpfile("selected.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
    /* hovox writes OpenVDB's grid offsets: the flag after magic, format and library version */
    FILE *fp = fopen(path, "rb");
    cr_assert_not_null(fp);
    fseek(fp, 0, SEEK_END);
    size_t size = (size_t)ftell(fp);
    unsigned char *data = malloc(size);
    rewind(fp);
    cr_assert_eq(fread(data, 1, size, fp), size);
    fclose(fp);
    cr_assert_eq(data[20], 1, "no grid offsets in the header");

    static const char *const sel[] = {"occupancy", "material.*"};
    hv_volume *r = NULL;
    cr_assert_eq(hv_volume_load_grids(path, sel, 2, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_grid_count(r), 3);
    cr_assert_str_eq(hv_volume_grid_name(r, 0), "occupancy"); /* in the model's order */
    cr_assert_str_eq(hv_volume_grid_name(r, 1), "material.a");
    cr_assert_str_eq(hv_volume_grid_name(r, 2), "material.b");
    cr_assert_eq(hv_volume_grid_find(r, "surface"), -1);
    cr_assert_eq(hv_volume_grid_find(r, "density"), -1);
    cr_assert_str_eq(hv_volume_meta_string(r, "hovox.materials.json"), "[{\"name\": \"a\"}, {\"name\": \"b\"}]");
    hv_transform x = hv_volume_get_transform(v), y = hv_volume_get_transform(r);
    cr_assert(hv_transform_same(&x, &y));
    same_grids(r, v);
    hv_volume_destroy(r);

    /* the grids not selected are not read: damage "density" and the selection still loads */
    int64_t blocks, end;
    grid_bytes(data, size, "density", "Tree_float_5_4_3", &blocks, &end);
    cr_assert(blocks > 0 && end > blocks + 200 && (size_t)end <= size);
    memset(data + (blocks + end) / 2 - 64, 0xff, 128);
    const char *bad = t_tmpfile("selected_bad.vdb");
    fp = fopen(bad, "wb");
    cr_assert_eq(fwrite(data, 1, size, fp), size);
    fclose(fp);
    cr_assert_eq(hv_volume_load(bad, &r), HV_ERR_BAD_INPUT, "the damage was not seen: %s", hv_last_error());
    cr_assert_null(r);
    cr_assert_eq(hv_volume_load_grids(bad, sel, 2, &r), HV_OK, "%s", hv_last_error());
    same_grids(r, v);
    hv_volume_destroy(r);

    /* a single name; a selector matching nothing; nothing at all selected */
    static const char *const one[] = {"density", "nothing.*"};
    cr_assert_eq(hv_volume_load_grids(path, one, 2, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_grid_count(r), 1);
    cr_assert_str_eq(hv_volume_grid_name(r, 0), "density");
    same_grids(r, v);
    hv_volume_destroy(r);
    cr_assert_eq(hv_volume_load_grids(path, one + 1, 1, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_grid_count(r), 0);
    cr_assert_eq(hv_volume_leaf_count(r), 0);
    cr_assert_eq(hv_volume_get_transform(r).voxel[0], 1.0);
    cr_assert_not_null(hv_volume_meta_string(r, "hovox.materials.json"));
    hv_volume_destroy(r);
    /* bad arguments */
    static const char *const empty[] = {""};
    r = (hv_volume *)0x1;
    cr_assert_eq(hv_volume_load_grids(path, empty, 1, &r), HV_ERR_INVALID);
    cr_assert_null(r);
    cr_assert_eq(hv_volume_load_grids(path, sel, -1, &r), HV_ERR_INVALID);
    free(data);
    hv_volume_destroy(v);
}

Test(volume, load_selected_grids_from_a_stream)
{
    /* an OpenVDB stream (no grid offsets, as hovox wrote models before): read whole, the grids
     * not selected dropped; the same grids as from the file with offsets */
    const char *stream = "tests/data/models/linear2_stream.vdb", *file = "tests/data/models/linear2.vdb";
    hv_volume *all = NULL, *r = NULL, *f = NULL;
    cr_assert_eq(hv_volume_load(file, &all), HV_OK, "%s", hv_last_error());
    static const char *const sel[] = {"material.*"};
    cr_assert_eq(hv_volume_load_grids(stream, sel, 1, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_load_grids(file, sel, 1, &f), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_grid_count(r), hv_volume_grid_count(all) - 1);
    cr_assert_eq(hv_volume_grid_find(r, "occupancy"), -1);
    same_grids(r, all);
    same_grids(f, r);
    same_grids(r, f);
    hv_volume_destroy(r);
    hv_volume_destroy(f);
    hv_volume_destroy(all);
}

Test(volume, load_selected_instance_reads_its_parent)
{
    /* OpenVDB writes a grid sharing another's tree as an instance of it (no tree of its own):
     * selecting only the instance reads the parent's tree too */
    const char *path = t_tmpfile("instance.vdb");
    char cmd[1024], *out = NULL;
    snprintf(cmd, sizeof cmd,
             "/usr/bin/python3 -c \"import pyopenvdb as vdb; g = vdb.FloatGrid(); g.name = 'material.a'; "
             "g.fill((0, 0, 0), (9, 9, 9), 0.25, True); h = g.copy(); h.name = 'material.b'; "
             "o = vdb.BoolGrid(); o.name = 'occupancy'; o.fill((0, 0, 0), (9, 9, 9), True, True); "
             "vdb.write('%s', grids=[g, o, h])\" 2>&1",
             path);
    cr_assert_eq(t_run(cmd, &out), 0, "pyopenvdb: %s", out);
    free(out);
    static const char *const sel[] = {"material.b"};
    hv_volume *r = NULL;
    cr_assert_eq(hv_volume_load_grids(path, sel, 1, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_grid_count(r), 1);
    cr_assert_str_eq(hv_volume_grid_name(r, 0), "material.b");
    cr_assert_eq(hv_volume_active_count(r), 1000u);
    hv_accessor a;
    hv_accessor_init(&a, r);
    cr_assert_eq(hv_accessor_float(&a, 0, 3, 3, 3), 0.25f);
    hv_volume_destroy(r);
}

/* Half floats of the IEEE 754 binary16 format, by hand (round to nearest even), for numbers in
 * [0, 1]: the values the file must give back for fractions, computed apart from OpenVDB. */
static float to_half(float x)
{
    if (x == 0) return 0;
    int e;
    frexpf(x, &e);                    /* x = m 2^e, m in [0.5, 1) */
    int bits = e - 1 < -14 ? -24 : e - 11; /* the unit in the last place: 10 bits below the leading one */
    return ldexpf(rintf(ldexpf(x, -bits)), bits);
}

/* Fractions ("material.*") are stored as half floats: the file is smaller, every reader gets the
 * halves back, hovox restores the sum of 1 in each voxel (the largest fraction takes the rest);
 * other float grids keep their 32 bits; a load of some fraction grids only gives the halves. */
Test(volume, fractions_are_stored_as_halves_and_sum_to_one)
{
    hv_volume *v = make(0.5, 0.5, 0.5);
    int lo[3] = {0, 0, 0}, hi[3] = {23, 15, 15};
    add_box(v, lo, hi);
    int g[3], d, occ;
    hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &occ);
    hv_volume_grid_add(v, "material.A", HV_GRID_FLOAT, &g[0]);
    hv_volume_grid_add(v, "material.B", HV_GRID_FLOAT, &g[1]);
    hv_volume_grid_add(v, "material.C", HV_GRID_FLOAT, &g[2]);
    hv_volume_grid_add(v, "density", HV_GRID_FLOAT, &d);
    const int32_t *org = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            int i = org[3 * l] + (int)(n >> 6), j = org[3 * l + 1] + (int)((n >> 3) & 7);
            double a = 0.5 + 0.45 * sin(0.37 * i + 0.11 * j), b = (1 - a) * (0.3 + 0.2 * cos(0.23 * j));
            hv_volume_leaf_float(v, g[0], l)[n] = (float)a;
            hv_volume_leaf_float(v, g[1], l)[n] = (float)b;
            hv_volume_leaf_float(v, g[2], l)[n] = (float)(1 - a - b);
            hv_volume_leaf_float(v, d, l)[n] = (float)(1000.0 / 3.0 + i * 0.001);
        }
    const char *path = t_tmpfile("halves.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
    hv_volume *r = NULL, *a_only = NULL;
    cr_assert_eq(hv_volume_load(path, &r), HV_OK, "%s", hv_last_error());
    const char *one[] = {"material.A"};
    cr_assert_eq(hv_volume_load_grids(path, one, 1, &a_only), HV_OK, "%s", hv_last_error());
    int rg[3] = {hv_volume_grid_find(r, "material.A"), hv_volume_grid_find(r, "material.B"),
                 hv_volume_grid_find(r, "material.C")};
    int rd = hv_volume_grid_find(r, "density"), ra = hv_volume_grid_find(a_only, "material.A");
    hv_accessor x, y, z;
    hv_accessor_init(&x, v);
    hv_accessor_init(&y, r);
    hv_accessor_init(&z, a_only);
    double worst = 0;
    size_t adjusted = 0, voxels = 0;
    for (int i = 0; i <= 23; ++i)
        for (int j = 0; j <= 15; ++j)
            for (int k = 0; k <= 15; k += 5) {
                float f0[3], f1[3], h[3];
                double sum = 0;
                int big = 0;
                for (int q = 0; q < 3; ++q) {
                    f0[q] = hv_accessor_float(&x, g[q], i, j, k);
                    f1[q] = hv_accessor_float(&y, rg[q], i, j, k);
                    h[q] = to_half(f0[q]);
                    sum += f1[q];
                    if (h[q] > h[big]) big = q;
                    worst = fmax(worst, fabs(f1[q] - f0[q]));
                }
                cr_assert_float_eq(sum, 1.0, 1e-6, "voxel (%d, %d, %d): sum %.9g", i, j, k, sum);
                /* the others are the halves; the largest is what they leave */
                for (int q = 0; q < 3; ++q)
                    if (q != big) cr_assert_eq(f1[q], h[q], "voxel (%d, %d, %d) fraction %d: %.9g, half %.9g", i, j, k, q, f1[q], h[q]);
                adjusted += f1[big] != h[big];
                ++voxels;
                /* a load of material.A alone: its halves, untouched */
                cr_assert_eq(hv_accessor_float(&z, ra, i, j, k), h[0]);
                cr_assert_eq(hv_accessor_float(&y, rd, i, j, k), hv_accessor_float(&x, d, i, j, k));
            }
    cr_expect_leq(worst, 2.0 / 4096, "a fraction moved by %.3g", worst);
    cr_expect_gt(adjusted, voxels / 10, "the sums were already 1 in %zu of %zu voxels", voxels - adjusted, voxels);
    hv_volume_destroy(v);
    hv_volume_destroy(r);
    hv_volume_destroy(a_only);
}

/* The same with two and six materials (the unrolled path and the general one). */
Test(volume, fractions_of_two_and_six_materials_sum_to_one)
{
    for (int m = 2; m <= 6; m += 4) {
        hv_volume *v = make(0.5, 0.5, 0.5);
        int lo[3] = {0, 0, 0}, hi[3] = {15, 15, 7};
        add_box(v, lo, hi);
        int g[6];
        for (int q = 0; q < m; ++q) {
            char name[32];
            snprintf(name, sizeof name, "material.M%d", q);
            hv_volume_grid_add(v, name, HV_GRID_FLOAT, &g[q]);
        }
        const int32_t *org = hv_volume_leaf_origins(v);
        for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
            for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
                int i = org[3 * l] + (int)(n >> 6), j = org[3 * l + 1] + (int)((n >> 3) & 7);
                double w[6], s = 0;
                for (int q = 0; q < m; ++q) s += w[q] = 1.3 + sin(0.31 * i * (q + 1) + 0.17 * j);
                for (int q = 0; q < m; ++q) hv_volume_leaf_float(v, g[q], l)[n] = (float)(w[q] / s);
            }
        const char *path = t_tmpfile("halves_m.vdb");
        cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
        hv_volume *r = NULL;
        cr_assert_eq(hv_volume_load(path, &r), HV_OK, "%s", hv_last_error());
        hv_accessor x, y;
        hv_accessor_init(&x, v);
        hv_accessor_init(&y, r);
        for (int i = 0; i <= 15; ++i)
            for (int j = 0; j <= 15; ++j) {
                double sum = 0;
                for (int q = 0; q < m; ++q) {
                    float a = hv_accessor_float(&x, g[q], i, j, 3), b = hv_accessor_float(&y, q, i, j, 3);
                    cr_assert_leq(fabs(a - b), 2.0 / 4096, "m %d voxel (%d, %d) fraction %d: %g vs %g", m, i, j, q, b, a);
                    sum += b;
                }
                cr_assert_float_eq(sum, 1.0, 1e-6, "m %d voxel (%d, %d): sum %.9g", m, i, j, sum);
            }
        hv_volume_destroy(v);
        hv_volume_destroy(r);
    }
}

/* Dense copies (hv_volume_dense, hv_volume_dense_mask) against the accessor voxel by voxel, over
 * the whole box, a box cutting leaves on every side (negative indices included) and a box beyond
 * the active voxels; any thread count gives the same array. */
Test(volume, dense_copies_over_boxes)
{
    hv_volume *v = make(0.5, 0.5, 0.5);
    int lo[3] = {-11, -3, 2}, hi[3] = {20, 9, 27};
    add_box(v, lo, hi);
    int a[3] = {30, 1, 40}, b[3] = {33, 4, 41};
    add_box(v, a, b);
    int g = -1, g2 = -1, bg = -1;
    cr_assert_eq(hv_volume_grid_add(v, "f", HV_GRID_FLOAT, &g), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "g", HV_GRID_FLOAT, &g2), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "b", HV_GRID_BOOL, &bg), HV_OK);
    fill(v, g, bg);
    const int32_t *org = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) /* g = -f, inactive voxels poisoned */
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n)
            hv_volume_leaf_float(v, g2, l)[n] = HV_BIT_GET(hv_volume_leaf_mask(v, l), n)
                                                    ? -hv_volume_leaf_float(v, g, l)[n] : 1e9f;
    (void)org;
    int32_t boxes[3][6] = {{-11, -3, 2, 33, 9, 41}, {-9, -2, 5, 31, 3, 40}, {-20, -10, -5, 45, 15, 50}};
    for (int bi = 0; bi < 3; ++bi)
        for (int threads = 1; threads <= 3; threads += 2) {
            hv_set_threads(threads);
            int32_t *bx = boxes[bi];
            size_t nx = (size_t)(bx[3] - bx[0] + 1), ny = (size_t)(bx[4] - bx[1] + 1), nz = (size_t)(bx[5] - bx[2] + 1);
            float *out = malloc(nx * ny * nz * 2 * sizeof(float));
            uint8_t *act = malloc(nx * ny * nz), *bits = malloc(nx * ny * nz);
            memset(out, 0x7f, nx * ny * nz * 2 * sizeof(float)); /* garbage: the call writes every value */
            memset(act, 7, nx * ny * nz);
            int grids[2] = {g, g2};
            cr_assert_eq(hv_volume_dense(v, grids, 2, bx, bx + 3, out), HV_OK, "%s", hv_last_error());
            cr_assert_eq(hv_volume_dense_mask(v, -1, bx, bx + 3, act), HV_OK);
            cr_assert_eq(hv_volume_dense_mask(v, bg, bx, bx + 3, bits), HV_OK);
            hv_accessor acc;
            hv_accessor_init(&acc, v);
            size_t q = 0;
            for (int32_t i = bx[0]; i <= bx[3]; ++i)
                for (int32_t j = bx[1]; j <= bx[4]; ++j)
                    for (int32_t k = bx[2]; k <= bx[5]; ++k, ++q) {
                        int on = hv_accessor_active(&acc, i, j, k);
                        cr_assert_eq(act[q], on, "box %d (%d,%d,%d)", bi, i, j, k);
                        cr_assert_eq(bits[q], on && hv_accessor_bool(&acc, bg, i, j, k));
                        cr_assert_eq(out[2 * q], on ? hv_accessor_float(&acc, g, i, j, k) : 0.0f);
                        cr_assert_eq(out[2 * q + 1], on ? -hv_accessor_float(&acc, g, i, j, k) : 0.0f);
                    }
            free(out);
            free(act);
            free(bits);
        }
    hv_set_threads(0);
    float one;
    int32_t p[3] = {0, 0, 0}, m[3] = {0, -1, 0};
    cr_expect_eq(hv_volume_dense(v, &bg, 1, p, p, &one), HV_ERR_INVALID);
    cr_expect_eq(hv_volume_dense(v, &g, 1, p, m, &one), HV_ERR_INVALID);
    cr_expect_eq(hv_volume_dense_mask(v, g, p, p, (uint8_t *)&one), HV_ERR_INVALID);
    hv_volume_destroy(v);
}
