/* tests/io/vdb/test_vdb_read.c - the C volume store's topology against brute force, and the
 * native .vdb reader (volumes/vdb_read.c) against OpenVDB's own reader (the bridge) on the same
 * files: hovox's files, the same grids rewritten by vdb_tool with every codec and as halves,
 * selective loads; files it leaves to OpenVDB (stream format, active tiles, damaged). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hovox/volume.h"
#include "support/support.h"
#include "volumes/volume_internal.h"
#include "io/vdb/vdb_internal.h"

static uint64_t rng = 0x9E3779B97F4A7C15ull;
static uint64_t next(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}

/* ---- the topology against a brute-force set ------------------------------------------------ */

/* voxels in [-64, 64)^3 (leaves on both sides of 0: two root blocks per axis) */
#define SPAN 128
static unsigned char dense_on[SPAN * SPAN * SPAN];
static float dense_val[SPAN * SPAN * SPAN];
static size_t at(int i, int j, int k) { return ((size_t)(i + 64) * SPAN + (size_t)(j + 64)) * SPAN + (size_t)(k + 64); }

static void check_against_dense(hv_volume *v, int f)
{
    size_t n = hv_volume_leaf_count(v);
    const int32_t *o = hv_volume_leaf_origins(v);
    for (size_t l = 1; l < n; ++l)
        cr_assert_lt(hv_leaf_order(o + 3 * (l - 1), o + 3 * l), 0, "leaf %zu out of tree order", l);
    uint64_t on = 0;
    for (size_t i = 0; i < sizeof dense_on; ++i) on += dense_on[i];
    cr_assert_eq(hv_volume_active_count(v), on);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    for (int i = -64; i < 64; ++i)
        for (int j = -64; j < 64; ++j)
            for (int k = -64; k < 64; ++k) {
                cr_assert_eq(hv_accessor_active(&acc, i, j, k), dense_on[at(i, j, k)], "(%d,%d,%d)", i, j, k);
                if (dense_on[at(i, j, k)])
                    cr_assert_eq(hv_accessor_float(&acc, f, i, j, k), dense_val[at(i, j, k)], "(%d,%d,%d)", i, j, k);
            }
}

Test(store, topology_add_and_restrict_against_brute_force)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    int f;
    cr_assert_eq(hv_volume_grid_add(v, "value", HV_GRID_FLOAT, &f), HV_OK);
    memset(dense_on, 0, sizeof dense_on);
    for (int round = 0; round < 6; ++round) {
        /* a batch of blocks, some twice, some on leaves that exist, some empty */
        enum { NB = 300 };
        int32_t org[3 * NB];
        uint64_t msk[8 * NB];
        for (int b = 0; b < NB; ++b) {
            for (int a = 0; a < 3; ++a) org[3 * b + a] = (int32_t)(next() % 16) * 8 - 64;
            for (int w = 0; w < 8; ++w) msk[8 * b + w] = b % 17 == 0 ? 0 : next() & next();
            if (b > 0 && b % 5 == 0) memcpy(org + 3 * b, org + 3 * (b - 1), 3 * sizeof *org);
        }
        cr_assert_eq(hv_volume_topology_add(v, NB, org, msk), HV_OK, "%s", hv_last_error());
        for (int b = 0; b < NB; ++b)
            for (unsigned n = 0; n < 512; ++n)
                if (msk[8 * b + n / 64] >> (n % 64) & 1) {
                    size_t d = at(org[3 * b] + (int)(n >> 6), org[3 * b + 1] + (int)((n >> 3) & 7), org[3 * b + 2] + (int)(n & 7));
                    if (!dense_on[d]) dense_val[d] = 0; /* new voxels start at 0 */
                    dense_on[d] = 1;
                }
        check_against_dense(v, f);
        /* new values on every active voxel, for the next round to keep */
        hv_accessor acc;
        hv_accessor_init(&acc, v);
        for (int i = -64; i < 64; ++i)
            for (int j = -64; j < 64; ++j)
                for (int k = -64; k < 64; ++k)
                    if (dense_on[at(i, j, k)]) {
                        dense_val[at(i, j, k)] = (float)(next() % 1000) + 0.25f;
                        cr_assert_eq(hv_accessor_set_float(&acc, f, i, j, k, dense_val[at(i, j, k)]), HV_OK);
                    }
    }
    /* restrict to a random bool grid */
    int keep;
    cr_assert_eq(hv_volume_grid_add(v, "keep", HV_GRID_BOOL, &keep), HV_OK);
    const int32_t *o = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        uint64_t *b = hv_volume_leaf_bool(v, keep, l);
        int whole_leaf_off = l % 7 == 0; /* some leaves lose every voxel and go */
        for (int w = 0; w < 8; ++w) b[w] = whole_leaf_off ? 0 : next();
        for (unsigned n = 0; n < 512; ++n) {
            size_t d = at(o[3 * l] + (int)(n >> 6), o[3 * l + 1] + (int)((n >> 3) & 7), o[3 * l + 2] + (int)(n & 7));
            if (!(b[n / 64] >> (n % 64) & 1)) dense_on[d] = 0;
        }
    }
    size_t before = hv_volume_leaf_count(v);
    cr_assert_eq(hv_volume_topology_restrict(v, keep), HV_OK);
    cr_assert_lt(hv_volume_leaf_count(v), before);
    check_against_dense(v, f);
    /* a restrict that keeps one leaf in ten: the buffers move to a fresh slab (compaction) and
     * keep their values */
    int keep2;
    cr_assert_eq(hv_volume_grid_add(v, "keep2", HV_GRID_BOOL, &keep2), HV_OK);
    o = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        uint64_t *b = hv_volume_leaf_bool(v, keep2, l);
        for (int w = 0; w < 8; ++w) b[w] = l % 10 == 0 ? ~0ull : 0;
        if (l % 10 == 0) continue;
        for (unsigned n = 0; n < 512; ++n)
            dense_on[at(o[3 * l] + (int)(n >> 6), o[3 * l + 1] + (int)((n >> 3) & 7), o[3 * l + 2] + (int)(n & 7))] = 0;
    }
    before = hv_volume_leaf_count(v);
    uint64_t mem_before = hv_volume_memory_bytes(v);
    cr_assert_eq(hv_volume_topology_restrict(v, keep2), HV_OK);
    cr_assert_lt(hv_volume_leaf_count(v) * 5, before);
    cr_assert_lt(hv_volume_memory_bytes(v) * 2, mem_before, "the slabs were compacted");
    check_against_dense(v, f);
    /* voxels that went inactive read 0 when activated again */
    int32_t all[3] = {-64, -64, -64};
    uint64_t full[8];
    memset(full, 0xff, sizeof full);
    cr_assert_eq(hv_volume_topology_add(v, 1, all, full), HV_OK);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    for (int i = -64; i < -56; ++i)
        for (int j = -64; j < -56; ++j)
            for (int k = -64; k < -56; ++k)
                cr_assert_eq(hv_accessor_float(&acc, f, i, j, k), dense_on[at(i, j, k)] ? dense_val[at(i, j, k)] : 0.0f);
    hv_volume_destroy(v);
}

/* ---- the native reader against OpenVDB ------------------------------------------------------ */

/* A model as hovox writes it: anisotropic voxels, leaves on both sides of 0 and far away (other
 * root blocks), an occupancy and a surface, three fractions summing to 1 (stored as halves), a
 * signed distance (floats, every value), metadata. */
static hv_volume *model(void)
{
    hv_transform xf = {{0.5, 0.25, 1.0}, {-3.5, 2.0, 7.0}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    enum { NB = 400 };
    int32_t org[3 * NB];
    uint64_t msk[8 * NB];
    for (int b = 0; b < NB; ++b) {
        for (int a = 0; a < 3; ++a) org[3 * b + a] = (int32_t)(next() % 24) * 8 - 96;
        if (b % 50 == 0) org[3 * b] += 8192, org[3 * b + 2] -= 12288;
        for (int w = 0; w < 8; ++w) msk[8 * b + w] = b % 3 == 0 ? ~0ull : next() | next();
    }
    cr_assert_eq(hv_volume_topology_add(v, NB, org, msk), HV_OK);
    /* and a leaf with no active voxel (a block added empty) */
    int32_t far[3] = {-4096 - 64, 4096, 0};
    uint64_t none[8] = {0};
    cr_assert_eq(hv_volume_topology_add(v, 1, far, none), HV_OK);
    int occ, srf, ma, mb, mc, dist;
    cr_assert_eq(hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &occ), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "material.A", HV_GRID_FLOAT, &ma), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "material.B", HV_GRID_FLOAT, &mb), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "material.C", HV_GRID_FLOAT, &mc), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "surface", HV_GRID_BOOL, &srf), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "distance", HV_GRID_FLOAT, &dist), HV_OK);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const uint64_t *m = hv_volume_leaf_mask(v, l);
        uint64_t *ob = hv_volume_leaf_bool(v, occ, l), *sb = hv_volume_leaf_bool(v, srf, l);
        float *a = hv_volume_leaf_float(v, ma, l), *b = hv_volume_leaf_float(v, mb, l),
              *c = hv_volume_leaf_float(v, mc, l), *d = hv_volume_leaf_float(v, dist, l);
        for (int w = 0; w < 8; ++w) {
            ob[w] = m[w];
            sb[w] = m[w] & next();
        }
        for (unsigned n = 0; n < 512; ++n) {
            if (!(m[n / 64] >> (n % 64) & 1)) continue;
            float x = (float)(next() % 1001) / 1000.0f, y = (1.0f - x) * (float)(next() % 1001) / 1000.0f;
            a[n] = x;
            b[n] = y;
            c[n] = 1.0f - x - y;
            d[n] = (float)((double)(int64_t)next() / 9.2e18 * 40.0);
        }
    }
    cr_assert_eq(hv_volume_meta_set_string(v, "hovox.note", "a \"model\"\nwith lines"), HV_OK);
    cr_assert_eq(hv_volume_meta_set_number(v, "hovox.number", -2.5e-7), HV_OK);
    return v;
}

/* Load path both ways (names/n as hv_volume_load_grids; n < 0: all), the native reader taking it
 * (not leaving it to OpenVDB) as `native` says, and compare bit for bit. */
static hv_volume *both_ways(const char *path, const char *const *names, int n, int native)
{
    hv_volume *direct = NULL;
    int half = 0, declined = 0;
    cr_assert_eq(hv_vdb_read(path, names, n, 0, &direct, &half, &declined), HV_OK, "%s", hv_last_error());
    cr_assert_eq(declined, !native, "%s: the native reader %s the file", path, declined ? "left" : "took");
    hv_volume_destroy(direct);
    hv_volume *a = NULL, *b = NULL;
    cr_assert_eq(n < 0 ? hv_volume_load(path, &a) : hv_volume_load_grids(path, names, n, &a), HV_OK, "%s",
                 hv_last_error());
    cr_assert_eq(hv_volume_load_openvdb(path, names, n, &b), HV_OK, "%s", hv_last_error());
    char why[256];
    cr_assert(hv_volume_identical(a, b, why, sizeof why), "%s: native and OpenVDB loads differ: %s", path, why);
    hv_volume_destroy(b);
    return a;
}

static void tmp_path(char *buf, size_t n, const char *name) { snprintf(buf, n, "/tmp/hovox-test-vdbread-%ld-%s", (long)getpid(), name); }

Test(vdb_read, native_load_equals_openvdb_and_the_saved_volume)
{
    hv_volume *v = model();
    char path[256];
    tmp_path(path, sizeof path, "model.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
    hv_volume *r = both_ways(path, NULL, -1, 1);
    /* against what was saved: leaves in the same (tree) order, bools and 32-bit floats exact,
     * fractions within 2^-12 summing to 1 */
    cr_assert_eq(hv_volume_leaf_count(r), hv_volume_leaf_count(v));
    cr_assert_eq(memcmp(hv_volume_leaf_origins(r), hv_volume_leaf_origins(v), 3 * sizeof(int32_t) * hv_volume_leaf_count(v)), 0);
    cr_assert_eq(hv_volume_grid_count(r), 6);
    for (int g = 0; g < 6; ++g) cr_assert_str_eq(hv_volume_grid_name(r, g), hv_volume_grid_name(v, g));
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const uint64_t *m = hv_volume_leaf_mask(v, l);
        cr_assert_eq(memcmp(m, hv_volume_leaf_mask(r, l), 64), 0);
        cr_assert_eq(memcmp(hv_volume_leaf_bool_c(v, 4, l), hv_volume_leaf_bool_c(r, 4, l), 64), 0);
        for (unsigned n = 0; n < 512; ++n) {
            if (!(m[n / 64] >> (n % 64) & 1)) continue;
            cr_assert_eq(hv_volume_leaf_float_c(r, 5, l)[n], hv_volume_leaf_float_c(v, 5, l)[n]);
            float sum = 0;
            for (int g = 1; g <= 3; ++g) {
                float x = hv_volume_leaf_float_c(r, g, l)[n];
                cr_assert_leq(fabsf(x - hv_volume_leaf_float_c(v, g, l)[n]), 1.0f / 4096 + 1e-6f);
                sum += x;
            }
            cr_assert_float_eq(sum, 1.0f, 1e-6f);
        }
    }
    cr_assert_str_eq(hv_volume_meta_string(r, "hovox.note"), "a \"model\"\nwith lines");
    hv_volume_destroy(r);
    /* selective loads: the fractions, one grid, nothing */
    const char *const fr[] = {"material.*"}, *const one[] = {"surface"}, *const none[] = {"nope"};
    r = both_ways(path, fr, 1, 1);
    cr_assert_eq(hv_volume_grid_count(r), 3);
    hv_volume_destroy(r);
    r = both_ways(path, one, 1, 1);
    cr_assert_eq(hv_volume_grid_count(r), 1);
    hv_volume_destroy(r);
    r = both_ways(path, none, 1, 1);
    cr_assert_eq(hv_volume_grid_count(r), 0);
    cr_assert_eq(hv_volume_leaf_count(r), 0);
    hv_volume_destroy(r);
    remove(path);
    hv_volume_destroy(v);
}

/* The same grids written by OpenVDB's vdb_tool with each codec, as floats and as halves. */
Test(vdb_read, every_codec_vdb_tool_writes)
{
    if (system("vdb_tool -version >/dev/null 2>&1") != 0) cr_skip_test("needs vdb_tool (libopenvdb-tools)");
    hv_volume *v = model();
    char path[256], out[256], cmd[1024];
    tmp_path(path, sizeof path, "codec_in.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
    static const char *const codecs[] = {"none", "zip", "blosc", "active"};
    for (int c = 0; c < 4; ++c)
        for (int bits = 16; bits <= 32; bits += 16) {
            tmp_path(out, sizeof out, "codec_out.vdb");
            snprintf(cmd, sizeof cmd, "vdb_tool -quiet -read %s -write codec=%s bits=%d %s >/dev/null 2>&1", path,
                     codecs[c], bits, out);
            cr_assert_eq(system(cmd), 0, "%s", cmd);
            hv_volume *r = both_ways(out, NULL, -1, 1);
            cr_assert_eq(hv_volume_grid_count(r), 6, "codec %s, %d bits", codecs[c], bits);
            hv_volume_destroy(r);
            remove(out);
        }
    remove(path);
    hv_volume_destroy(v);
}

/* Files it leaves to OpenVDB: the stream format (no grid offsets), active tiles, damage. */
Test(vdb_read, leaves_other_files_to_openvdb)
{
    static const char *const taken_by_openvdb[] = {"tests/fuzz/corpus/vdb/linear2_stream.vdb"};
    hv_volume *r = both_ways(taken_by_openvdb[0], NULL, -1, 0);
    hv_volume_destroy(r);
    /* active tiles (expanded by the bridge) */
    hv_volume *direct = NULL;
    int half = 0, declined = 0;
    cr_assert_eq(hv_vdb_read("tests/fuzz/corpus/vdb/huge_tile.vdb", NULL, -1, 0, &direct, &half, &declined), HV_OK);
    cr_assert(declined);
    cr_assert_null(direct);
    /* a hovox file cut short: left to OpenVDB, which says what is wrong */
    hv_volume *v = model();
    char path[256];
    tmp_path(path, sizeof path, "cut.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK);
    FILE *fp = fopen(path, "r+b");
    cr_assert_not_null(fp);
    cr_assert_eq(fseek(fp, 0, SEEK_END), 0);
    long size = ftell(fp);
    fclose(fp);
    cr_assert_eq(truncate(path, size - 100), 0);
    cr_assert_eq(hv_vdb_read(path, NULL, -1, 0, &direct, &half, &declined), HV_OK);
    cr_assert(declined);
    hv_volume *bad = NULL;
    cr_assert_eq(hv_volume_load(path, &bad), HV_ERR_BAD_INPUT);
    cr_assert_null(bad);
    cr_assert(strstr(hv_last_error(), path) != NULL, "%s", hv_last_error());
    /* more than the budget: left to OpenVDB, which refuses it with the figure */
    cr_assert_eq(truncate(path, 0), 0);
    cr_assert_eq(hv_volume_save(v, path), HV_OK);
    cr_assert_eq(hv_vdb_read(path, NULL, -1, 4096, &direct, &half, &declined), HV_OK);
    cr_assert(declined);
    remove(path);
    hv_volume_destroy(v);
}

/* An origin of -0 (OpenVDB's affine map makes it +0): native and OpenVDB loads still agree. */
Test(vdb_read, minus_zero_origin)
{
    hv_transform xf = {{0.5, 0.5, 0.5}, {-0.0, 1.0, -0.0}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    int32_t o[3] = {0, 8, -16};
    uint64_t m[8] = {~0ull, 1, 2, 3, 4, 5, 6, 7};
    cr_assert_eq(hv_volume_topology_add(v, 1, o, m), HV_OK);
    cr_assert_eq(hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, NULL), HV_OK);
    char path[256];
    tmp_path(path, sizeof path, "minus0.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
    hv_volume *r = both_ways(path, NULL, -1, 1);
    cr_assert(!signbit(hv_volume_get_transform(r).origin[0]));
    hv_volume_destroy(r);
    remove(path);
    hv_volume_destroy(v);
}
