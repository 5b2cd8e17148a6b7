/* tests/data/models/make_models.c - writes the small graded models the CLI tests of probe and
 * profile read. Built by hand, not by the Makefile (see README in this directory):
 *   cc -std=c11 -D_GNU_SOURCE -Iinclude -Itests tests/data/models/make_models.c \
 *      tests/support/support.c build/libhovox.a \
 *      $(pkg-config --libs libpng zlib lua5.4 cairo) -lm -ldl -lpthread -fopenmp -o /tmp/make_models
 *   /tmp/make_models tests/data/models
 * Every fraction is a linear function of the voxel index, so trilinear samples inside the
 * object equal the same formula at the sample point (the tests' reference). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/material.h"
#include "support/support.h"
#include "hovox/volume.h"

static void die(hv_status s, const char *what)
{
    fprintf(stderr, "make_models: %s: %s\n", what, hv_last_error());
    exit(s ? (int)s : 1);
}

#define CHECK(call, what)                 \
    do {                                  \
        hv_status st_ = (call);           \
        if (st_ != HV_OK) die(st_, what); \
    } while (0)

/* Activate the voxels [lo, hi] (inclusive) of a box. */
static void add_box(hv_volume *v, const int lo[3], const int hi[3])
{
    CHECK(t_add_box(v, lo, hi), "topology");
}

typedef void (*fraction_fn)(int i, int j, int k, double *f);

/* occupancy = every active voxel; material grids from fn and the table stored (t != NULL). */
static void grade(hv_volume *v, const hv_material_table *t, fraction_fn fn)
{
    int m = t ? hv_material_count(t) : 0, occ, g[8];
    CHECK(hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &occ), "occupancy");
    for (int k = 0; k < m; ++k) {
        char name[80];
        snprintf(name, sizeof name, "material.%s", hv_material_name(t, k));
        CHECK(hv_volume_grid_add(v, name, HV_GRID_FLOAT, &g[k]), name);
    }
    const int32_t *org = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const uint64_t *mask = hv_volume_leaf_mask(v, l);
        uint64_t *ob = hv_volume_leaf_bool(v, occ, l);
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            if (!HV_BIT_GET(mask, n)) continue;
            ob[n / 64] |= 1ull << (n % 64);
            double f[8];
            if (m == 0) continue;
            fn(org[3 * l] + (int)(n >> 6), org[3 * l + 1] + (int)((n >> 3) & 7), org[3 * l + 2] + (int)(n & 7), f);
            /* rounding leaves -5.6e-17 where a formula is 0: fractions are >= 0 */
            for (int k = 0; k < m; ++k) hv_volume_leaf_float(v, g[k], l)[n] = (float)(f[k] < 1e-12 ? 0.0 : f[k]);
        }
    }
    if (t) CHECK(hv_material_table_store(v, t), "table");
}

/* linear2: 16^3 voxels of 0.5 mm, voxel (0,0,0) centred at (1, 2, 3); rigid = i/15,
 * soft = 1 - i/15, i.e. rigid = (x - 1) / 7.5 in world x. */
static void linear2(int i, int j, int k, double *f)
{
    (void)j, (void)k;
    f[1] = i / 15.0;
    f[0] = 1.0 - f[1];
}

/* gap3: two 10 x 8 x 8 blocks of 1 mm voxels at i in [0, 9] and [14, 23] (a 4-voxel gap),
 * origin (0, 0, 0); u = i/23, v = j/7: rigid = 0.2 + 0.6u, flexible = 0.6 - 0.4u - 0.2v,
 * tough = 0.2 - 0.2u + 0.2v (all >= 0, summing to 1). */
static void gap3(int i, int j, int k, double *f)
{
    (void)k;
    double u = i / 23.0, v = j / 7.0;
    f[0] = 0.2 + 0.6 * u;
    f[1] = 0.6 - 0.4 * u - 0.2 * v;
    f[2] = 0.2 - 0.2 * u + 0.2 * v;
}

static void save(hv_volume *v, const char *dir, const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    CHECK(hv_volume_save(v, path), path);
    printf("wrote %s\n", path);
    hv_volume_destroy(v);
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : ".";
    hv_volume *v;
    hv_material_table *t;

    hv_transform xf1 = {{0.5, 0.5, 0.5}, {1.0, 2.0, 3.0}};
    CHECK(hv_volume_create(&xf1, &v), "create");
    add_box(v, (int[3]){0, 0, 0}, (int[3]){15, 15, 15});
    CHECK(hv_material_table_create(&t), "table");
    CHECK(hv_material_add(t, "soft", (float[4]){1.0f, 0.498f, 0.055f, 1.0f}, NULL), "soft");
    CHECK(hv_material_add(t, "rigid", (float[4]){0.122f, 0.467f, 0.706f, 1.0f}, NULL), "rigid");
    grade(v, t, linear2);
    hv_material_table_destroy(t);
    save(v, dir, "linear2.vdb");

    hv_transform xf2 = {{1.0, 1.0, 1.0}, {0.0, 0.0, 0.0}};
    CHECK(hv_volume_create(&xf2, &v), "create");
    add_box(v, (int[3]){0, 0, 0}, (int[3]){9, 7, 7});
    add_box(v, (int[3]){14, 0, 0}, (int[3]){23, 7, 7});
    CHECK(hv_material_table_create(&t), "table");
    CHECK(hv_material_add(t, "rigid", NULL, NULL), "rigid");
    CHECK(hv_material_add(t, "flexible", NULL, NULL), "flexible");
    CHECK(hv_material_add(t, "tough", NULL, NULL), "tough");
    grade(v, t, gap3);
    hv_material_table_destroy(t);
    save(v, dir, "gap3.vdb");

    /* ungraded: occupancy only, as hovox voxelize leaves it */
    CHECK(hv_volume_create(&xf2, &v), "create");
    add_box(v, (int[3]){0, 0, 0}, (int[3]){7, 7, 7});
    grade(v, NULL, NULL);
    save(v, dir, "ungraded.vdb");
    return 0;
}
