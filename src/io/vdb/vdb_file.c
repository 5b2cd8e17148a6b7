/* src/io/vdb/vdb_file.c - .vdb files of the volume store: hv_volume_save (OpenVDB writes them, through
 * the bridge plugin vdb_bridge.cpp, loaded on first use) and hv_volume_load (hovox's own reader
 * vdb_read.c first; what it leaves, OpenVDB). Fractions stored as half floats get their sums
 * restored on load (Wu eq. 12). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/internal.h"
#include "core/plugin.h"
#include "hovox/volume.h"
#include "vdb_bridge.h"
#include "volumes/volume_internal.h"
#include "vdb_internal.h"

static hv_plugin g_vdb_plugin = HV_PLUGIN_DEF("hovox-vdb", HV_VDB_ENTRY, HV_VDB_ABI, "OpenVDB bridge");
/* the table, once api() returned HV_OK */
#define g_api ((const hv_vdb_api *)g_vdb_plugin.api)

static int cancel_poll(void) { return hv_cancel_requested(); }

/* The bridge, its OpenVDB held to hv_threads() (--threads) threads: the count may change
 * between calls (Lua, Python). */
static hv_status api(void)
{
    const void *t = NULL;
    hv_status s = hv_plugin_api(&g_vdb_plugin, &t);
    int rc = s == HV_OK ? g_api->threads(hv_threads()) : 0;
    if (rc) s = hv_error_set((hv_status)rc, "OpenVDB bridge: %s", g_api->last_error());
    return s;
}

/* ---- files ------------------------------------------------------------------------------ */

/* The grids of material fractions, stored as half floats (hovox/volume.h). */
static int is_fraction_grid(const char *name) { return strncmp(name, "material.", 9) == 0; }

hv_status hv_volume_save(const hv_volume *v, const char *path)
{
    if (hv_check_extension(path, ".vdb", "a model") != HV_OK) return HV_ERR_INVALID;
    hv_status s = hv_output_check(path, 0);
    if (s == HV_OK) s = api();
    if (s != HV_OK) return s;
    int ngrids = hv_volume_grid_count(v), nmeta = hv_volume_meta_count(v);
    size_t ng = (size_t)ngrids + 1, nm = (size_t)nmeta + 1;
    const char **names = hv_calloc(ng, sizeof *names);
    int *types = hv_calloc(ng, sizeof *types);
    const void *const **buffers = hv_calloc(ng, sizeof *buffers);
    unsigned char *half = hv_calloc(ng, 1);
    const char **keys = hv_calloc(nm, sizeof *keys);
    const char **strs = hv_calloc(nm, sizeof *strs);
    int *kinds = hv_calloc(nm, sizeof *kinds);
    double *nums = hv_calloc(nm, sizeof *nums);
    int special = hv_path_is_special(path); /* /dev/null and the like: write in place */
    char *tmp = special ? hv_strdup(path) : hv_temp_path(path);
    if (!names || !types || !buffers || !half || !keys || !strs || !kinds || !nums || !tmp) {
        s = HV_ERR_NOMEM;
        goto done;
    }
    {
        /* fail early, with the final name and the system's reason, if we cannot write here */
        FILE *probe = fopen(tmp, "wb");
        if (!probe) {
            s = hv_error_set(HV_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
            goto done;
        }
        fclose(probe);
    }
    for (int g = 0; g < ngrids; ++g) {
        names[g] = hv_volume_grid_name(v, g);
        types[g] = (int)hv_volume_grid_type(v, g);
        buffers[g] = (const void *const *)hv_volume_grid_buffers(v, g);
        half[g] = types[g] == HV_GRID_FLOAT && is_fraction_grid(names[g]);
    }
    for (int i = 0; i < nmeta; ++i) {
        keys[i] = hv_volume_meta_key(v, i);
        const char *str = hv_volume_meta_string(v, keys[i]);
        kinds[i] = str ? HV_META_STRING : HV_META_NUMBER;
        strs[i] = str ? str : "";
        if (!str) hv_volume_meta_number(v, keys[i], &nums[i]);
    }
    hv_transform xf = hv_volume_get_transform(v);
    size_t nleaves = hv_volume_leaf_count(v);
    const uint64_t *masks = nleaves ? hv_volume_leaf_mask(v, 0) : NULL;
    int rc = g_api->save(tmp, xf.voxel, xf.origin, nleaves, hv_volume_leaf_origins(v), masks, ngrids, names, types,
                         half, buffers, nmeta, keys, kinds, strs, nums, cancel_poll);
    if (rc == HV_ERR_CANCELLED) s = hv_error_set(HV_ERR_CANCELLED, "%s: writing cancelled", path);
    else if (rc) s = hv_error_set((hv_status)rc, "%s: cannot write: %s", path, g_api->last_error());
    else if (!special) s = hv_fsync_path(tmp);
    if (s != HV_OK) {
        if (!special) remove(tmp);
        goto done;
    }
    if (!special && (s = hv_output_check(path, 0)) != HV_OK) {
        remove(tmp);
        goto done;
    }
    if (!special && rename(tmp, path) != 0) {
        s = hv_error_set(HV_ERR_IO, "%s: cannot rename into place: %s", path, strerror(errno));
        remove(tmp);
    }
done:
    free(names);
    free(types);
    free(buffers);
    free(half);
    free(keys);
    free(strs);
    free(kinds);
    free(nums);
    free(tmp);
    return s;
}
/* What the plugin's load says of each grid, kept until the topology is known. */
typedef struct load_grid_info {
    char *name;
    hv_grid_type type;
} load_grid_info;

typedef struct load_ctx {
    hv_volume *v;
    int half_fractions; /* a material.* grid was stored as half floats */
    int n;
    size_t cap;
    load_grid_info *grids;
} load_ctx;


/* a model holds at most 64 materials (HV_MAX_MATERIALS, hovox/material.h); the sums of the first 64
 * fraction grids of a file are restored */
#define VDB_MAX_FRACTIONS 64

/* ---- fractions stored as half floats ------------------------------------------------------
 * hv_volume_save stores the material.* grids as halves, each fraction within 2^-12 of its float,
 * so their sum in a voxel is off 1 by up to m * 2^-12. On load the largest fraction of each
 * voxel takes what the others leave, and the sum is 1 again, as Wu eq. 12 asks; a voxel whose
 * sum is further off than the halves explain is left as it is, for the checks to refuse. */
typedef struct sums_ctx {
    hv_volume *v;
    int m;
    const int *g;
} sums_ctx;

/* One leaf's voxels (inactive ones hold 0 in every grid: their sum is 0, so they stay 0), for up
 * to four materials. M is a constant where the function is inlined, so the loop vectorises. */
static inline __attribute__((always_inline)) void restore_leaf(int M, float *const *f)
{
    const float tol = (float)M / 4096.0f;
    /* the grids in restrict locals: a store to one cannot be taken to change another */
    float *restrict g0 = f[0], *restrict g1 = f[M > 1 ? 1 : 0], *restrict g2 = f[M > 2 ? 2 : 0],
                    *restrict g3 = f[M > 3 ? 3 : 0];
#pragma omp simd
    for (int p = 0; p < 512; ++p) {
        /* written out for M <= 4 (the conditions are constants): inner loops keep GCC from
         * vectorising */
        float x0 = g0[p], x1 = M > 1 ? g1[p] : 0, x2 = M > 2 ? g2[p] : 0, x3 = M > 3 ? g3[p] : 0;
        float sum = 0 + x0, top = x0;
        int big = 0;
        if (M > 1) {
            sum += x1;
            big = x1 > top ? 1 : big;
            top = x1 > top ? x1 : top;
        }
        if (M > 2) {
            sum += x2;
            big = x2 > top ? 2 : big;
            top = x2 > top ? x2 : top;
        }
        if (M > 3) {
            sum += x3;
            big = x3 > top ? 3 : big;
            top = x3 > top ? x3 : top;
        }
        float rest = 1.0f - (sum - top);
        big = fabsf(sum - 1.0f) <= tol ? big : -1; /* -1: the sum is left alone */
        g0[p] = big == 0 ? rest : x0;
        if (M > 1) g1[p] = big == 1 ? rest : x1;
        if (M > 2) g2[p] = big == 2 ? rest : x2;
        if (M > 3) g3[p] = big == 3 ? rest : x3;
    }
}

/* More than four materials: the same, voxel by voxel. */
static void restore_leaf_m(int m, float *const *f)
{
    const float tol = (float)m / 4096.0f;
    for (int p = 0; p < 512; ++p) {
        float sum = 0, top = f[0][p];
        int big = 0;
        for (int q = 0; q < m; ++q) {
            sum += f[q][p];
            if (f[q][p] > top) {
                big = q;
                top = f[q][p];
            }
        }
        if (fabsf(sum - 1.0f) <= tol) f[big][p] = 1.0f - (sum - top);
    }
}

HV_HOT_CLONES static hv_status restore_sums_range(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    sums_ctx *c = vctx;
    float *f[VDB_MAX_FRACTIONS];
    for (size_t l = b; l < e; ++l) {
        for (int q = 0; q < c->m; ++q) f[q] = hv_volume_leaf_float(c->v, c->g[q], l);
        switch (c->m) {
        case 2: restore_leaf(2, f); break;
        case 3: restore_leaf(3, f); break;
        case 4: restore_leaf(4, f); break;
        default: restore_leaf_m(c->m, f); break;
        }
    }
    return HV_OK;
}

static hv_status restore_sums(hv_volume *v)
{
    int g[VDB_MAX_FRACTIONS], m = 0;
    for (int i = 0; i < hv_volume_grid_count(v) && m < VDB_MAX_FRACTIONS; ++i)
        if (hv_volume_grid_type(v, i) == HV_GRID_FLOAT && is_fraction_grid(hv_volume_grid_name(v, i))) g[m++] = i;
    if (m < 2) return HV_OK;
    sums_ctx c = {v, m, g};
    return hv_parallel_for(hv_volume_leaf_count(v), 64, restore_sums_range, &c, NULL, NULL);
}

static int load_meta(void *ctx, const char *key, int kind, const char *s, double d)
{
    hv_volume *v = ((load_ctx *)ctx)->v;
    return (kind == HV_META_NUMBER ? hv_volume_meta_set_number(v, key, d) : hv_volume_meta_set_string(v, key, s)) != HV_OK;
}

static int load_grid(void *ctx, const char *name, int type)
{
    load_ctx *c = ctx;
    if (type & HV_VDB_HALF && is_fraction_grid(name)) c->half_fractions = 1;
    if (hv_grow((void **)&c->grids, &c->cap, (size_t)c->n + 1, sizeof *c->grids) != HV_OK) return 1;
    c->grids[c->n].type = (hv_grid_type)(type & ~HV_VDB_HALF);
    return !(c->grids[c->n++].name = hv_strdup(name));
}

/* Copy what the plugin loaded into v, grid by grid, each freed in the plugin once copied. */
static hv_status copy_out(hv_volume *v, void *impl, const load_ctx *c)
{
    size_t n = g_api->leaf_count(impl);
    int32_t *org = hv_malloc_array(n ? 3 * n : 3, sizeof *org);
    uint64_t *msk = hv_malloc_array(n ? n : 1, HV_LEAF_WORDS * sizeof *msk);
    void **src = hv_malloc_array(n ? n : 1, sizeof *src);
    hv_status s = org && msk && src ? HV_OK : HV_ERR_NOMEM;
    int rc = s == HV_OK && n ? g_api->leaf_topology(impl, org, msk) : 0;
    if (rc) s = hv_error_set((hv_status)rc, "OpenVDB: %s", g_api->last_error());
    if (s == HV_OK) {
        s = hv_volume_adopt_topology(v, n, org, msk);
        org = NULL; /* the volume's now */
        msk = NULL;
    }
    for (int i = 0; i < c->n && s == HV_OK; ++i) {
        int g;
        s = hv_volume_adopt_grid(v, c->grids[i].name, c->grids[i].type, &g);
        rc = s == HV_OK && n ? g_api->leaf_buffers(impl, i, src) : 0;
        if (rc) s = hv_error_set((hv_status)rc, "%s", g_api->last_error());
        size_t bytes = c->grids[i].type == HV_GRID_FLOAT ? HV_LEAF_SIZE * sizeof(float) : HV_LEAF_WORDS * sizeof(uint64_t);
        void *const *dst = s == HV_OK ? hv_volume_grid_buffers(v, g) : NULL;
        for (size_t l = 0; s == HV_OK && l < n; ++l) memcpy(dst[l], src[l], bytes);
        g_api->grid_free(impl, i);
    }
    free(org);
    free(msk);
    free(src);
    return s;
}

/* A file the native reader (vdb_read.c) leaves to OpenVDB. */
static hv_status load_openvdb(const char *path, const char *const *names, int n, hv_volume **out, int *half)
{
    hv_status s = api();
    if (s != HV_OK) return s;
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    hv_volume *v = NULL;
    s = hv_volume_create(&xf, &v);
    if (s != HV_OK) return s;
    load_ctx ctx = {v, 0, 0, 0, NULL};
    void *impl = NULL;
    int rc = g_api->load(path, names, n, hv_threads(), &impl, xf.voxel, xf.origin, load_meta, load_grid, &ctx,
                         hv_memory_budget(0), cancel_poll);
    if (rc) {
        s = rc == HV_ERR_CANCELLED ? hv_error_set(HV_ERR_CANCELLED, "%s: reading cancelled", path)
                                   : hv_error_set((hv_status)rc, "%s: %s", path, g_api->last_error());
    } else {
        hv_volume_adopt_transform(v, &xf);
        s = copy_out(v, impl, &ctx);
        g_api->destroy(impl);
    }
    for (int i = 0; i < ctx.n; ++i) free(ctx.grids[i].name);
    free(ctx.grids);
    if (s != HV_OK) {
        hv_volume_destroy(v);
        return s;
    }
    *half = ctx.half_fractions;
    *out = v;
    return HV_OK;
}

/* openvdb: 1 asks OpenVDB only, 0 the native reader first (vdb_internal.h) */
static hv_status load(const char *path, const char *const *names, int n, int openvdb, hv_volume **out)
{
    *out = NULL;
    struct stat st;
    if (stat(path, &st) != 0) return hv_error_set(HV_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (S_ISDIR(st.st_mode)) return hv_error_set(HV_ERR_IO, "%s: is a directory, not a file", path);
    FILE *fp = fopen(path, "rb");
    if (!fp) return hv_error_set(HV_ERR_IO, "%s: cannot open for reading", path);
    unsigned char magic[8] = {0};
    size_t got = fread(magic, 1, 8, fp);
    fclose(fp);
    /* OpenVDB files start with the int64 magic 0x56444220 ("VDB ") */
    if (got < 8 || !(magic[0] == 0x20 && magic[1] == 0x42 && magic[2] == 0x44 && magic[3] == 0x56))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: not an OpenVDB file (bad magic number)", path);
    hv_volume *v = NULL;
    int half = 0, declined = 0;
    hv_status s = openvdb ? HV_OK : hv_vdb_read(path, names, n, hv_memory_budget(0), &v, &half, &declined);
    if (openvdb || declined) s = load_openvdb(path, names, n, &v, &half);
    if (s != HV_OK) return s;
    hv_input_note(path);
    s = hv_volume_set_name(v, path);
    /* only with every fraction grid of the file loaded (all grids, or "material.*") */
    int all_fractions = n < 0;
    for (int i = 0; i < n; ++i) all_fractions |= strcmp(names[i], "material.*") == 0;
    if (s == HV_OK && half && all_fractions) s = restore_sums(v);
    if (s != HV_OK) {
        if (s == HV_ERR_BAD_INPUT) hv_error_prefix(s, "%s: ", path); /* a damaged file found late */
        hv_volume_destroy(v);
        return s;
    }
    *out = v;
    return HV_OK;
}

hv_status hv_volume_load(const char *path, hv_volume **out) { return load(path, NULL, -1, 0, out); }

hv_status hv_volume_load_openvdb(const char *path, const char *const *names, int n, hv_volume **out)
{
    return load(path, names, n, 1, out);
}

hv_status hv_volume_load_grids(const char *path, const char *const *names, int n, hv_volume **out)
{
    *out = NULL;
    if (n < 0 || (n > 0 && !names))
        return hv_error_set(HV_ERR_INVALID, "%s: %d grid names given", path, n);
    for (int i = 0; i < n; ++i)
        if (!names[i] || !*names[i]) return hv_error_set(HV_ERR_INVALID, "%s: grid name %d is empty", path, i + 1);
    return load(path, names, n, 0, out);
}


/* ---- surfaces (issue 28) ------------------------------------------------------------------- */

hv_status hv_vdb_surface(int nleaf, const float *const *xyz, const size_t *nv, const uint32_t *const *tri,
                         const size_t *nt, int nnode, const int *ops, const uint32_t *leaf, const uint32_t *a,
                         const uint32_t *b, double voxel, float **out_xyz, size_t *out_nv, uint32_t **out_tri,
                         size_t *out_nt)
{
    hv_status s = api();
    if (s != HV_OK) return s;
    int rc = g_api->surface(nleaf, xyz, nv, tri, nt, nnode, ops, leaf, a, b, voxel, out_xyz, out_nv, out_tri, out_nt,
                            cancel_poll);
    if (rc == HV_ERR_CANCELLED) return hv_error_set(HV_ERR_CANCELLED, "export: surface cancelled");
    if (rc) return hv_error_set((hv_status)rc, "export: the level set of the shape: %s", g_api->last_error());
    return HV_OK;
}
