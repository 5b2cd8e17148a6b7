/* volumes/volume.c - the volume store: grid names, the shared topology (a leaf table in OpenVDB's
 * tree order with a block hash), one buffer per leaf and grid, cached accessors, trilinear
 * sampling, mask algebra, metadata. Everything here is C and knows no file format: .vdb files
 * are read and written by the formats wing (src/io/vdb). */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "hovox/volume.h"
#include "core/json.h"
#include "volume_internal.h"

/* Leaf buffers live in slabs, a few per grid: one allocation instead of one per leaf. */
typedef struct slab {
    unsigned char *base;
    size_t leaves; /* capacity */
} slab;

typedef struct grid_entry {
    char *name;
    hv_grid_type type;
    void **leaves; /* buffer per leaf (HV_LEAF_SIZE floats or HV_LEAF_WORDS words), in the slabs */
    slab *slabs;
    size_t nslabs, scap;
} grid_entry;

typedef struct meta_entry {
    char *key;
    int is_number;
    char *str;
    double num;
} meta_entry;

typedef struct hash_slot {
    int32_t key[3];
    int64_t leaf; /* -1: empty */
} hash_slot;

struct hv_volume {
    hv_transform xf;
    int ngrids;
    size_t gcap;
    grid_entry *grids;
    /* the shared topology: leaves in OpenVDB's tree order (hv_leaf_order) */
    size_t nleaves;
    int32_t *origins; /* 3 per leaf */
    uint64_t *masks;  /* HV_LEAF_WORDS per leaf */
    size_t hcap;      /* power of two */
    hash_slot *hash;
    /* metadata, sorted by key */
    int nmeta;
    size_t mcap;
    meta_entry *meta;
    char *name; /* the file it was loaded from, for messages (NULL: none) */
};

#define MASK(v, l) ((v)->masks + (size_t)(l) * HV_LEAF_WORDS)

/* ---- leaf order and table --------------------------------------------------------------- */

/* OpenVDB's tree order (5-4-3 trees): root children by their 4096-aligned origin, x then y then
 * z (signed); inside, the 32^3 and then the 16^3 child offsets, x-major. Files list leaves in
 * this order, and keeping it keeps every sum over leaves as it was with OpenVDB underneath. */
int hv_leaf_order(const int32_t *a, const int32_t *b)
{
    for (int k = 0; k < 3; ++k) {
        int32_t x = a[k] >> 12, y = b[k] >> 12; /* arithmetic shift: floor division */
        if (x != y) return x < y ? -1 : 1;
    }
    uint32_t p = (((uint32_t)a[0] >> 7 & 31u) << 22) | (((uint32_t)a[1] >> 7 & 31u) << 17) |
                 (((uint32_t)a[2] >> 7 & 31u) << 12) | (((uint32_t)a[0] >> 3 & 15u) << 8) |
                 (((uint32_t)a[1] >> 3 & 15u) << 4) | ((uint32_t)a[2] >> 3 & 15u);
    uint32_t q = (((uint32_t)b[0] >> 7 & 31u) << 22) | (((uint32_t)b[1] >> 7 & 31u) << 17) |
                 (((uint32_t)b[2] >> 7 & 31u) << 12) | (((uint32_t)b[0] >> 3 & 15u) << 8) |
                 (((uint32_t)b[1] >> 3 & 15u) << 4) | ((uint32_t)b[2] >> 3 & 15u);
    return p < q ? -1 : p > q;
}

static uint64_t hash3(int32_t x, int32_t y, int32_t z)
{
    uint64_t h = (uint64_t)(uint32_t)(x >> 3) * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t)(uint32_t)(y >> 3) * 0xC2B2AE3D27D4EB4Full;
    h ^= (uint64_t)(uint32_t)(z >> 3) * 0x165667B19E3779F9ull;
    return h ^ (h >> 29);
}

static int64_t hash_find(const hv_volume *v, int32_t x, int32_t y, int32_t z)
{
    if (!v->hcap) return -1;
    size_t m = v->hcap - 1;
    for (size_t i = (size_t)hash3(x, y, z) & m;; i = (i + 1) & m) {
        const hash_slot *s = &v->hash[i];
        if (s->leaf < 0) return -1;
        if (s->key[0] == x && s->key[1] == y && s->key[2] == z) return s->leaf;
    }
}

static size_t hash_cap(size_t n)
{
    size_t cap = 16;
    while (cap < 2 * n) cap *= 2;
    return cap;
}

/* Fill `hash` (cap slots) with the leaves of v. */
static void hash_fill(hv_volume *v, hash_slot *hash, size_t cap)
{
    for (size_t i = 0; i < cap; ++i) hash[i].leaf = -1;
    for (size_t l = 0; l < v->nleaves; ++l) {
        const int32_t *o = v->origins + 3 * l;
        for (size_t i = (size_t)hash3(o[0], o[1], o[2]) & (cap - 1);; i = (i + 1) & (cap - 1)) {
            if (hash[i].leaf < 0) {
                memcpy(hash[i].key, o, sizeof hash[i].key);
                hash[i].leaf = (int64_t)l;
                break;
            }
        }
    }
    free(v->hash);
    v->hash = hash;
    v->hcap = cap;
}

static size_t leaf_bytes(hv_grid_type t)
{
    return t == HV_GRID_FLOAT ? HV_LEAF_SIZE * sizeof(float) : HV_LEAF_WORDS * sizeof(uint64_t);
}

/* A slab of n zeroed leaf buffers of type t (calloc: a large one is mapped by malloc and its
 * pages fault in where the buffers are first written, on every thread that writes them). 0 when
 * out of memory. */
static int slab_new(slab *sl, hv_grid_type t, size_t n)
{
    sl->leaves = n;
    sl->base = hv_calloc(n ? n : 1, leaf_bytes(t));
    return sl->base != NULL;
}

static void slab_free(slab *sl) { free(sl->base); }

static void storage_free(grid_entry *e)
{
    for (size_t i = 0; i < e->nslabs; ++i) slab_free(&e->slabs[i]);
    free(e->slabs);
    free(e->leaves);
    e->slabs = NULL;
    e->leaves = NULL;
    e->nslabs = e->scap = 0;
}

/* Append a slab of n zeroed leaf buffers to e, their addresses into ptrs[0..n-1]. 0 when out of
 * memory (e unchanged). */
static int slabs_add(grid_entry *e, size_t n, void **ptrs)
{
    size_t first = e->nslabs, bytes = leaf_bytes(e->type);
    if (hv_grow((void **)&e->slabs, &e->scap, first + 1, sizeof *e->slabs) != HV_OK) return 0;
    if (!slab_new(&e->slabs[first], e->type, n)) return 0;
    for (size_t l = 0; l < n; ++l) ptrs[l] = e->slabs[first].base + l * bytes;
    e->nslabs = first + 1;
    return 1;
}

/* Drop the slabs of e from index `first` on (those a failed operation added). */
static void slabs_drop(grid_entry *e, size_t first)
{
    for (size_t i = first; i < e->nslabs; ++i) slab_free(&e->slabs[i]);
    e->nslabs = first;
}

/* Give grid entry e (no storage yet) n zeroed leaf buffers. */
static hv_status storage_new(grid_entry *e, size_t n)
{
    e->leaves = hv_calloc(n ? n : 1, sizeof *e->leaves);
    if (!e->leaves || !slabs_add(e, n, e->leaves)) {
        storage_free(e);
        return hv_error_set(HV_ERR_NOMEM, "out of memory for %zu leaves of grid '%s'", n, e->name);
    }
    return HV_OK;
}

/* ---- life cycle ------------------------------------------------------------------------- */

static int transform_ok(const hv_transform *xf)
{
    for (int a = 0; a < 3; ++a)
        if (!(xf->voxel[a] > 0) || !isfinite(xf->voxel[a]) || !isfinite(xf->origin[a])) return 0;
    return 1;
}

static hv_volume *new_volume(const hv_transform *xf)
{
    hv_volume *v = hv_calloc(1, sizeof *v);
    if (v) v->xf = *xf;
    return v;
}

hv_status hv_volume_create(const hv_transform *xf, hv_volume **out)
{
    *out = NULL;
    if (!transform_ok(xf))
        return hv_error_set(HV_ERR_INVALID,
                            "voxel size (%g, %g, %g) must be positive and finite, origin finite",
                            xf->voxel[0], xf->voxel[1], xf->voxel[2]);
    hv_volume *v = new_volume(xf);
    if (!v) return HV_ERR_NOMEM;
    *out = v;
    return HV_OK;
}

static void free_meta(hv_volume *v)
{
    for (int i = 0; i < v->nmeta; ++i) {
        free(v->meta[i].key);
        free(v->meta[i].str);
    }
    free(v->meta);
    v->meta = NULL;
    v->nmeta = 0;
    v->mcap = 0;
}

void hv_volume_destroy(hv_volume *v)
{
    if (!v) return;
    for (int g = 0; g < v->ngrids; ++g) {
        free(v->grids[g].name);
        storage_free(&v->grids[g]);
    }
    free(v->grids);
    free(v->origins);
    free(v->masks);
    free(v->hash);
    free_meta(v);
    free(v->name);
    free(v);
}

const char *hv_volume_name(const hv_volume *vol) { return vol && vol->name ? vol->name : ""; }

static hv_status copy_meta(hv_volume *dst, const hv_volume *src)
{
    for (int i = 0; i < src->nmeta; ++i) {
        const meta_entry *m = &src->meta[i];
        hv_status s = m->is_number ? hv_volume_meta_set_number(dst, m->key, m->num)
                                   : hv_volume_meta_set_string(dst, m->key, m->str);
        if (s != HV_OK) return s;
    }
    return HV_OK;
}

/* Give v (no leaves yet) a copy of a topology of n leaves in tree order. */
static hv_status set_topology(hv_volume *v, size_t n, const int32_t *origins, const uint64_t *masks)
{
    int32_t *o = hv_malloc_array(n ? 3 * n : 3, sizeof *o);
    uint64_t *m = hv_malloc_array(n ? n : 1, HV_LEAF_WORDS * sizeof *m);
    if (!o || !m) {
        free(o);
        free(m);
        return HV_ERR_NOMEM;
    }
    if (n) {
        memcpy(o, origins, 3 * n * sizeof *o);
        memcpy(m, masks, n * HV_LEAF_WORDS * sizeof *m);
    }
    return hv_volume_adopt_topology(v, n, o, m);
}

/* Append a grid with n zeroed leaf buffers (n = v->nleaves). */
static hv_status push_grid(hv_volume *v, const char *name, hv_grid_type type)
{
    hv_status s = hv_grow((void **)&v->grids, &v->gcap, (size_t)v->ngrids + 1, sizeof *v->grids);
    char *copy = s == HV_OK ? hv_strdup(name) : NULL;
    if (!copy) return HV_ERR_NOMEM;
    grid_entry *e = &v->grids[v->ngrids];
    memset(e, 0, sizeof *e);
    e->name = copy;
    e->type = type;
    if ((s = storage_new(e, v->nleaves)) != HV_OK) {
        free(copy);
        return s;
    }
    ++v->ngrids;
    return HV_OK;
}

hv_status hv_volume_clone(const hv_volume *src, hv_volume **out)
{
    *out = NULL;
    hv_volume *v = new_volume(&src->xf);
    if (!v) return HV_ERR_NOMEM;
    hv_status s = set_topology(v, src->nleaves, src->origins, src->masks);
    for (int g = 0; g < src->ngrids && s == HV_OK; ++g) {
        s = push_grid(v, src->grids[g].name, src->grids[g].type);
        size_t bytes = leaf_bytes(src->grids[g].type);
        for (size_t l = 0; s == HV_OK && l < v->nleaves; ++l) memcpy(v->grids[g].leaves[l], src->grids[g].leaves[l], bytes);
    }
    if (s == HV_OK) s = copy_meta(v, src);
    if (s != HV_OK) {
        hv_volume_destroy(v);
        return s;
    }
    *out = v;
    return HV_OK;
}

hv_transform hv_volume_get_transform(const hv_volume *v) { return v->xf; }

int hv_transform_same(const hv_transform *a, const hv_transform *b)
{
    for (int i = 0; i < 3; ++i) {
        double tol = 1e-9 * a->voxel[i];
        if (fabs(a->voxel[i] - b->voxel[i]) > tol || fabs(a->origin[i] - b->origin[i]) > tol)
            return 0;
    }
    return 1;
}

/* ---- grids ------------------------------------------------------------------------------ */

int hv_volume_grid_count(const hv_volume *v) { return v->ngrids; }

const char *hv_volume_grid_name(const hv_volume *v, int g)
{
    return g >= 0 && g < v->ngrids ? v->grids[g].name : NULL;
}

const char *hv_grid_type_name(hv_grid_type type)
{
    switch (type) {
    case HV_GRID_FLOAT: return "float";
    case HV_GRID_BOOL: return "bool";
    }
    return "?";
}

hv_grid_type hv_volume_grid_type(const hv_volume *v, int g)
{
    return g >= 0 && g < v->ngrids ? v->grids[g].type : (hv_grid_type)0;
}

int hv_volume_grid_find(const hv_volume *v, const char *name)
{
    for (int g = 0; g < v->ngrids; ++g)
        if (strcmp(v->grids[g].name, name) == 0) return g;
    return -1;
}

int hv_volume_grid_need(const hv_volume *v, const char *name, hv_grid_type type)
{
    int g = hv_volume_grid_find(v, name);
    if (g >= 0 && v->grids[g].type == type) return g;
    hv_buf names;
    hv_buf_init(&names);
    for (int k = 0; k < v->ngrids; ++k)
        if (v->grids[k].type == type) hv_buf_printf(&names, "%s%s", names.len ? ", " : "", v->grids[k].name);
    const char *t = hv_grid_type_name(type);
    hv_error_set(HV_ERR_NOT_FOUND, "no %s grid '%s' (%s grids: %s)", t, name, t,
                 names.len && !names.failed ? names.data : "none");
    hv_buf_free(&names);
    return -1;
}

static hv_status check_name(const hv_volume *v, const char *name)
{
    size_t n = name ? strlen(name) : 0;
    if (n == 0 || n > 255)
        return hv_error_set(HV_ERR_INVALID, "grid name must have 1 to 255 bytes (got %zu)", n);
    if (hv_volume_grid_find(v, name) >= 0)
        return hv_error_set(HV_ERR_INVALID, "grid '%s' already exists", name);
    return HV_OK;
}

hv_status hv_volume_grid_add(hv_volume *v, const char *name, hv_grid_type type, int *index)
{
    hv_status s = check_name(v, name);
    if (s != HV_OK) return s;
    if (type != HV_GRID_FLOAT && type != HV_GRID_BOOL)
        return hv_error_set(HV_ERR_INVALID, "grid '%s': unknown type %d", name, (int)type);
    if ((s = push_grid(v, name, type)) != HV_OK) return s;
    if (index) *index = v->ngrids - 1;
    return HV_OK;
}

hv_status hv_volume_grid_remove(hv_volume *v, int g)
{
    if (g < 0 || g >= v->ngrids)
        return hv_error_set(HV_ERR_INVALID, "no grid with index %d (volume has %d)", g, v->ngrids);
    free(v->grids[g].name);
    storage_free(&v->grids[g]);
    memmove(&v->grids[g], &v->grids[g + 1], (size_t)(v->ngrids - g - 1) * sizeof *v->grids);
    --v->ngrids;
    return HV_OK;
}

hv_status hv_volume_grid_rename(hv_volume *v, int g, const char *name)
{
    if (g < 0 || g >= v->ngrids)
        return hv_error_set(HV_ERR_INVALID, "no grid with index %d (volume has %d)", g, v->ngrids);
    if (strcmp(v->grids[g].name, name ? name : "") == 0) return HV_OK;
    hv_status s = check_name(v, name);
    if (s != HV_OK) return s;
    char *copy = hv_strdup(name);
    if (!copy) return HV_ERR_NOMEM;
    free(v->grids[g].name);
    v->grids[g].name = copy;
    return HV_OK;
}

hv_status hv_volume_grid_copy(hv_volume *dst, const char *name, const hv_volume *src, int sg)
{
    if (sg < 0 || sg >= src->ngrids)
        return hv_error_set(HV_ERR_INVALID, "no grid with index %d (volume has %d)", sg,
                            src->ngrids);
    if (!hv_transform_same(&dst->xf, &src->xf))
        return hv_error_set(HV_ERR_INVALID,
                            "cannot copy grid '%s': the volumes have different voxel lattices",
                            src->grids[sg].name);
    hv_grid_type type = src->grids[sg].type;
    int dg = hv_volume_grid_find(dst, name);
    if (dst == src && dg == sg) return HV_OK;
    if (dg >= 0 && dst->grids[dg].type != type)
        return hv_error_set(HV_ERR_INVALID, "grid '%s' exists with another type", name);
    hv_status s;
    if (dst != src) {
        s = hv_volume_topology_union(dst, src);
        if (s != HV_OK) return s;
    }
    if (dg < 0) {
        s = hv_volume_grid_add(dst, name, type, &dg);
        if (s != HV_OK) return s;
    }
    /* zero the destination, then copy src's active values leaf by leaf */
    for (size_t l = 0; l < dst->nleaves; ++l) {
        if (type == HV_GRID_FLOAT) memset(dst->grids[dg].leaves[l], 0, HV_LEAF_SIZE * sizeof(float));
        else memset(dst->grids[dg].leaves[l], 0, HV_LEAF_WORDS * sizeof(uint64_t));
    }
    for (size_t l = 0; l < src->nleaves; ++l) {
        const int32_t *o = src->origins + 3 * l;
        int64_t dl = dst == src ? (int64_t)l : hash_find(dst, o[0], o[1], o[2]);
        if (dl < 0) return hv_error_set(HV_ERR_INTERNAL, "grid copy: topology union incomplete");
        const uint64_t *m = MASK(src, l);
        if (type == HV_GRID_FLOAT) {
            const float *sb = src->grids[sg].leaves[l];
            float *db = dst->grids[dg].leaves[dl];
            for (unsigned n = 0; n < HV_LEAF_SIZE; ++n)
                if (HV_BIT_GET(m, n)) db[n] = sb[n];
        } else {
            const uint64_t *sb = src->grids[sg].leaves[l];
            uint64_t *db = dst->grids[dg].leaves[dl];
            for (int w = 0; w < HV_LEAF_WORDS; ++w) db[w] = sb[w] & m[w];
        }
    }
    return HV_OK;
}

/* ---- topology --------------------------------------------------------------------------- */

size_t hv_volume_leaf_count(const hv_volume *v) { return v->nleaves; }
const int32_t *hv_volume_leaf_origins(const hv_volume *v) { return v->origins; }
const uint64_t *hv_volume_leaf_mask(const hv_volume *v, size_t l) { return MASK(v, l); }

float *hv_volume_leaf_float(hv_volume *v, int g, size_t l)
{
    return v->grids[g].type == HV_GRID_FLOAT ? (float *)v->grids[g].leaves[l] : NULL;
}

uint64_t *hv_volume_leaf_bool(hv_volume *v, int g, size_t l)
{
    return v->grids[g].type == HV_GRID_BOOL ? (uint64_t *)v->grids[g].leaves[l] : NULL;
}

const float *hv_volume_leaf_float_c(const hv_volume *v, int g, size_t l)
{
    return v->grids[g].type == HV_GRID_FLOAT ? (const float *)v->grids[g].leaves[l] : NULL;
}

const uint64_t *hv_volume_leaf_bool_c(const hv_volume *v, int g, size_t l)
{
    return v->grids[g].type == HV_GRID_BOOL ? (const uint64_t *)v->grids[g].leaves[l] : NULL;
}

static uint64_t popcount8(const uint64_t *w)
{
    uint64_t c = 0;
    for (int i = 0; i < HV_LEAF_WORDS; ++i) c += (uint64_t)__builtin_popcountll(w[i]);
    return c;
}

uint64_t hv_volume_active_count(const hv_volume *v)
{
    uint64_t c = 0;
    for (size_t l = 0; l < v->nleaves; ++l) c += popcount8(MASK(v, l));
    return c;
}

int hv_volume_index_bbox(const hv_volume *v, int32_t lo[3], int32_t hi[3])
{
    int any = 0;
    int32_t a[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, b[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
    for (size_t l = 0; l < v->nleaves; ++l) {
        const int32_t *o = v->origins + 3 * l;
        const uint64_t *m = MASK(v, l);
        /* cheap reject: the leaf cannot move the box */
        if (any && o[0] >= a[0] && o[0] + 7 <= b[0] && o[1] >= a[1] && o[1] + 7 <= b[1] &&
            o[2] >= a[2] && o[2] + 7 <= b[2])
            continue;
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            if (!HV_BIT_GET(m, n)) continue;
            int32_t p[3] = {o[0] + (int32_t)(n >> 6), o[1] + (int32_t)((n >> 3) & 7),
                            o[2] + (int32_t)(n & 7)};
            for (int k = 0; k < 3; ++k) {
                if (p[k] < a[k]) a[k] = p[k];
                if (p[k] > b[k]) b[k] = p[k];
            }
            any = 1;
        }
    }
    if (any) {
        memcpy(lo, a, sizeof a);
        memcpy(hi, b, sizeof b);
    }
    return any;
}

/* New blocks of a topology_add, sorted into tree order (equal origins next to each other). */
typedef struct new_block {
    const int32_t *o;
    size_t b;
} new_block;

static int new_block_cmp(const void *x, const void *y)
{
    const new_block *a = x, *b = y;
    int c = hv_leaf_order(a->o, b->o);
    return c ? c : (a->b > b->b) - (a->b < b->b);
}

static int same_origin(const int32_t *a, const int32_t *b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

hv_status hv_volume_topology_add(hv_volume *v, size_t n, const int32_t *origins,
                                 const uint64_t *masks)
{
    for (size_t b = 0; b < n; ++b)
        for (int k = 0; k < 3; ++k)
            if (origins[3 * b + k] & 7)
                return hv_error_set(HV_ERR_INVALID,
                                    "block %zu: origin (%d, %d, %d) is not a multiple of 8", b,
                                    origins[3 * b], origins[3 * b + 1], origins[3 * b + 2]);
    /* 1. the blocks without a leaf yet, sorted; every allocation is made before v changes */
    size_t nnew = 0, nuniq = 0;
    new_block *nb = NULL;
    for (size_t b = 0; b < n; ++b)
        nnew += hash_find(v, origins[3 * b], origins[3 * b + 1], origins[3 * b + 2]) < 0;
    if (nnew) {
        nb = hv_malloc_array(nnew, sizeof *nb);
        if (!nb) return HV_ERR_NOMEM;
        size_t k = 0;
        for (size_t b = 0; b < n; ++b)
            if (hash_find(v, origins[3 * b], origins[3 * b + 1], origins[3 * b + 2]) < 0) nb[k++] = (new_block){origins + 3 * b, b};
        qsort(nb, nnew, sizeof *nb, new_block_cmp);
        for (size_t i = 0; i < nnew; ++i) nuniq += i == 0 || !same_origin(nb[i].o, nb[i - 1].o);
    }
    size_t total = v->nleaves + nuniq;
    int32_t *org = NULL;
    uint64_t *msk = NULL;
    hash_slot *hash = NULL;
    void ***tables = NULL;
    size_t *first = NULL; /* per grid, its first slab of the new leaves */
    size_t cap = hash_cap(total);
    if (nuniq) {
        org = hv_malloc_array(3 * total, sizeof *org);
        msk = hv_calloc(total, HV_LEAF_WORDS * sizeof *msk);
        hash = hv_malloc_array(cap, sizeof *hash);
        tables = hv_calloc((size_t)v->ngrids + 1, sizeof *tables);
        first = hv_calloc((size_t)v->ngrids + 1, sizeof *first);
        int ok = org && msk && hash && tables && first, made = 0;
        for (int g = 0; ok && g < v->ngrids; ++g) {
            grid_entry *e = &v->grids[g];
            tables[g] = hv_calloc(total, sizeof(void *));
            first[g] = e->nslabs;
            /* the new leaves' buffers go to the end of the table; the merge below moves them */
            ok = tables[g] && slabs_add(e, nuniq, tables[g] + v->nleaves);
            made = ok ? g + 1 : g;
        }
        if (!ok) {
            for (int g = 0; g < made; ++g) slabs_drop(&v->grids[g], first[g]);
            for (int g = 0; tables && g < v->ngrids; ++g) free(tables[g]);
            free(tables);
            free(first);
            free(org);
            free(msk);
            free(hash);
            free(nb);
            return HV_ERR_NOMEM;
        }
    }
    /* 2. blocks on leaves that exist: their new voxels start at 0 in every grid */
    for (size_t b = 0; b < n; ++b) {
        int64_t l = hash_find(v, origins[3 * b], origins[3 * b + 1], origins[3 * b + 2]);
        if (l < 0) continue;
        uint64_t *m = MASK(v, l);
        for (int w = 0; w < HV_LEAF_WORDS; ++w) {
            uint64_t add = masks[HV_LEAF_WORDS * b + (size_t)w] & ~m[w];
            if (!add) continue;
            m[w] |= add;
            for (int g = 0; g < v->ngrids; ++g) {
                if (v->grids[g].type == HV_GRID_BOOL) {
                    ((uint64_t *)v->grids[g].leaves[l])[w] &= ~add;
                } else {
                    float *f = v->grids[g].leaves[l];
                    for (uint64_t a = add; a; a &= a - 1) f[w * 64 + __builtin_ctzll(a)] = 0.0f;
                }
            }
        }
    }
    if (!nuniq) return HV_OK;
    /* 3. merge the new leaves (sorted) into the table (sorted) */
    size_t i = 0, j = 0, k = 0, u = 0; /* old leaf, new block, output, new leaf */
    while (i < v->nleaves || j < nnew) {
        int take_new = i == v->nleaves || (j < nnew && hv_leaf_order(nb[j].o, v->origins + 3 * i) < 0);
        if (!take_new) {
            memcpy(org + 3 * k, v->origins + 3 * i, 3 * sizeof *org);
            memcpy(msk + HV_LEAF_WORDS * k, MASK(v, i), HV_LEAF_WORDS * sizeof *msk);
            for (int g = 0; g < v->ngrids; ++g) tables[g][k] = v->grids[g].leaves[i];
            ++i;
        } else {
            memcpy(org + 3 * k, nb[j].o, 3 * sizeof *org);
            size_t e = j;
            for (; e < nnew && same_origin(nb[e].o, nb[j].o); ++e)
                for (int w = 0; w < HV_LEAF_WORDS; ++w)
                    msk[HV_LEAF_WORDS * k + (size_t)w] |= masks[HV_LEAF_WORDS * nb[e].b + (size_t)w];
            j = e;
            /* new leaves take the zeroed buffers from the end of the table, in turn; an old leaf
             * never reads a slot at or past v->nleaves + u before it is moved */
            for (int g = 0; g < v->ngrids; ++g) {
                void *buf = tables[g][v->nleaves + u];
                tables[g][v->nleaves + u] = NULL;
                tables[g][k] = buf;
            }
            ++u;
        }
        ++k;
    }
    free(nb);
    for (int g = 0; g < v->ngrids; ++g) {
        grid_entry *e = &v->grids[g];
        free(e->leaves);
        e->leaves = tables[g];
    }
    free(tables);
    free(first);
    free(v->origins);
    free(v->masks);
    v->origins = org;
    v->masks = msk;
    v->nleaves = total;
    hash_fill(v, hash, cap);
    return HV_OK;
}

/* When fewer than half of a grid's slab buffers are in use (after a restrict), its n leaves
 * move to one new slab and the old ones go; without memory for it, they stay where they are. */
static void compact(grid_entry *e, size_t n)
{
    size_t held = 0;
    for (size_t i = 0; i < e->nslabs; ++i) held += e->slabs[i].leaves;
    if (held <= 2 * n + 256) return;
    grid_entry fresh = {.type = e->type};
    void **ptrs = hv_malloc_array(n ? n : 1, sizeof *ptrs);
    if (!ptrs || !slabs_add(&fresh, n, ptrs)) {
        free(ptrs);
        free(fresh.slabs);
        return;
    }
    size_t bytes = leaf_bytes(e->type);
    for (size_t l = 0; l < n; ++l) {
        memcpy(ptrs[l], e->leaves[l], bytes);
        e->leaves[l] = ptrs[l];
    }
    free(ptrs);
    slabs_drop(e, 0);
    free(e->slabs);
    e->slabs = fresh.slabs;
    e->nslabs = fresh.nslabs;
    e->scap = fresh.scap;
}

hv_status hv_volume_topology_restrict(hv_volume *v, int g)
{
    if (g < 0 || g >= v->ngrids || v->grids[g].type != HV_GRID_BOOL)
        return hv_error_set(HV_ERR_INVALID, "topology restrict: grid %d is not a bool grid", g);
    size_t k = 0;
    for (size_t l = 0; l < v->nleaves; ++l) {
        uint64_t *m = MASK(v, l), keep = 0;
        const uint64_t *on = v->grids[g].leaves[l];
        uint64_t drop[HV_LEAF_WORDS];
        for (int w = 0; w < HV_LEAF_WORDS; ++w) {
            drop[w] = m[w] & ~on[w];
            m[w] &= on[w];
            keep |= m[w];
        }
        if (!keep) continue; /* an empty leaf goes, as OpenVDB's pruneInactive drops it */
        for (int q = 0; q < v->ngrids; ++q) { /* voxels that go inactive are reset to 0 */
            if (v->grids[q].type == HV_GRID_BOOL) {
                uint64_t *b = v->grids[q].leaves[l];
                for (int w = 0; w < HV_LEAF_WORDS; ++w) b[w] &= ~drop[w];
            } else {
                float *f = v->grids[q].leaves[l];
                for (int w = 0; w < HV_LEAF_WORDS; ++w)
                    for (uint64_t a = drop[w]; a; a &= a - 1) f[w * 64 + __builtin_ctzll(a)] = 0.0f;
            }
        }
        if (k != l) {
            memcpy(v->origins + 3 * k, v->origins + 3 * l, 3 * sizeof *v->origins);
            memcpy(MASK(v, k), m, HV_LEAF_WORDS * sizeof *m);
            for (int q = 0; q < v->ngrids; ++q) v->grids[q].leaves[k] = v->grids[q].leaves[l];
        }
        ++k;
    }
    if (k == v->nleaves) return HV_OK;
    v->nleaves = k;
    /* the hash is refilled in place: it only ever shrinks here */
    hash_slot *hash = v->hash;
    v->hash = NULL;
    hash_fill(v, hash, v->hcap);
    for (int q = 0; q < v->ngrids; ++q) compact(&v->grids[q], k);
    return HV_OK;
}

hv_status hv_volume_topology_union(hv_volume *dst, const hv_volume *src)
{
    if (!hv_transform_same(&dst->xf, &src->xf))
        return hv_error_set(HV_ERR_INVALID, "topology union: the volumes have different lattices");
    if (dst == src) return HV_OK;
    return hv_volume_topology_add(dst, src->nleaves, src->origins, src->masks);
}

/* ---- masks ------------------------------------------------------------------------------ */

hv_status hv_volume_mask_combine(hv_volume *v, int dst, int a, int b, hv_mask_op op)
{
    int gs[3] = {dst, a, b};
    for (int i = 0; i < 3; ++i)
        if (gs[i] < 0 || gs[i] >= v->ngrids || v->grids[gs[i]].type != HV_GRID_BOOL)
            return hv_error_set(HV_ERR_INVALID, "mask combine: grid %d is not a bool grid", gs[i]);
    if (op != HV_MASK_UNION && op != HV_MASK_INTERSECT && op != HV_MASK_DIFFERENCE)
        return hv_error_set(HV_ERR_INVALID, "mask combine: unknown operation %d", (int)op);
    for (size_t l = 0; l < v->nleaves; ++l) {
        const uint64_t *wa = v->grids[a].leaves[l], *wb = v->grids[b].leaves[l];
        uint64_t *wd = v->grids[dst].leaves[l];
        const uint64_t *m = MASK(v, l);
        for (int w = 0; w < HV_LEAF_WORDS; ++w) {
            uint64_t r = op == HV_MASK_UNION ? (wa[w] | wb[w])
                         : op == HV_MASK_INTERSECT ? (wa[w] & wb[w]) : (wa[w] & ~wb[w]);
            wd[w] = r & m[w];
        }
    }
    return HV_OK;
}

uint64_t hv_volume_mask_count(const hv_volume *v, int g)
{
    if (g < 0 || g >= v->ngrids || v->grids[g].type != HV_GRID_BOOL) return 0;
    uint64_t c = 0;
    for (size_t l = 0; l < v->nleaves; ++l) {
        const uint64_t *w = v->grids[g].leaves[l];
        for (int i = 0; i < HV_LEAF_WORDS; ++i)
            c += (uint64_t)__builtin_popcountll(w[i] & MASK(v, l)[i]);
    }
    return c;
}

/* ---- accessors -------------------------------------------------------------------------- */

void hv_accessor_init(hv_accessor *acc, const hv_volume *v)
{
    acc->vol = v;
    acc->key[0] = acc->key[1] = acc->key[2] = INT32_MIN;
    acc->leaf = -1;
}

int64_t hv_accessor_leaf(hv_accessor *acc, int32_t i, int32_t j, int32_t k)
{
    int32_t x = i & ~7, y = j & ~7, z = k & ~7;
    if (x != acc->key[0] || y != acc->key[1] || z != acc->key[2]) {
        acc->key[0] = x;
        acc->key[1] = y;
        acc->key[2] = z;
        acc->leaf = hash_find(acc->vol, x, y, z);
    }
    return acc->leaf;
}

int hv_accessor_active(hv_accessor *acc, int32_t i, int32_t j, int32_t k)
{
    int64_t l = hv_accessor_leaf(acc, i, j, k);
    return l >= 0 && HV_BIT_GET(MASK(acc->vol, l), HV_LEAF_OFFSET(i, j, k));
}

float hv_accessor_float(hv_accessor *acc, int g, int32_t i, int32_t j, int32_t k)
{
    int64_t l = hv_accessor_leaf(acc, i, j, k);
    if (l < 0) return 0.0f;
    unsigned n = HV_LEAF_OFFSET(i, j, k);
    if (!HV_BIT_GET(MASK(acc->vol, l), n)) return 0.0f;
    return ((const float *)acc->vol->grids[g].leaves[l])[n];
}

int hv_accessor_bool(hv_accessor *acc, int g, int32_t i, int32_t j, int32_t k)
{
    int64_t l = hv_accessor_leaf(acc, i, j, k);
    if (l < 0) return 0;
    unsigned n = HV_LEAF_OFFSET(i, j, k);
    const uint64_t *w = acc->vol->grids[g].leaves[l];
    return (int)(HV_BIT_GET(MASK(acc->vol, l), n) & HV_BIT_GET(w, n));
}

hv_status hv_accessor_set_float(hv_accessor *acc, int g, int32_t i, int32_t j, int32_t k,
                                float value)
{
    int64_t l = hv_accessor_leaf(acc, i, j, k);
    unsigned n = HV_LEAF_OFFSET(i, j, k);
    if (l < 0 || !HV_BIT_GET(MASK(acc->vol, l), n))
        return hv_error_set(HV_ERR_INVALID, "voxel (%d, %d, %d) is not active", i, j, k);
    ((float *)acc->vol->grids[g].leaves[l])[n] = value;
    return HV_OK;
}

void hv_volume_world_to_index(const hv_volume *v, const double w[3], double idx[3])
{
    for (int a = 0; a < 3; ++a) idx[a] = (w[a] - v->xf.origin[a]) / v->xf.voxel[a];
}

void hv_volume_index_to_world(const hv_volume *v, const double idx[3], double w[3])
{
    for (int a = 0; a < 3; ++a) w[a] = v->xf.origin[a] + idx[a] * v->xf.voxel[a];
}

void hv_volume_sample(hv_accessor *acc, const int *grids, int n, const double world[3], float *out,
                      float *coverage)
{
    const hv_volume *v = acc->vol;
    double idx[3];
    hv_volume_world_to_index(v, world, idx);
    int32_t i0[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
        double fl = floor(idx[a]);
        if (!(fl > -2e9 && fl < 2e9)) { /* far outside or NaN */
            for (int g = 0; g < n; ++g) out[g] = 0.0f;
            if (coverage) *coverage = 0.0f;
            return;
        }
        i0[a] = (int32_t)fl;
        f[a] = idx[a] - fl;
    }
    double acc_v[64] = {0};
    double wsum = 0.0;
    int m = n < 64 ? n : 64;
    for (int c = 0; c < 8; ++c) {
        int32_t p[3] = {i0[0] + (c >> 2), i0[1] + ((c >> 1) & 1), i0[2] + (c & 1)};
        double w = ((c >> 2) ? f[0] : 1 - f[0]) * (((c >> 1) & 1) ? f[1] : 1 - f[1]) *
                   ((c & 1) ? f[2] : 1 - f[2]);
        if (w <= 0.0) continue;
        int64_t l = hv_accessor_leaf(acc, p[0], p[1], p[2]);
        if (l < 0) continue;
        unsigned off = HV_LEAF_OFFSET(p[0], p[1], p[2]);
        if (!HV_BIT_GET(MASK(v, l), off)) continue;
        wsum += w;
        for (int g = 0; g < m; ++g) acc_v[g] += w * ((const float *)v->grids[grids[g]].leaves[l])[off];
    }
    for (int g = 0; g < m; ++g) out[g] = wsum > 0 ? (float)(acc_v[g] / wsum) : 0.0f;
    if (coverage) *coverage = (float)wsum;
}

/* ---- metadata --------------------------------------------------------------------------- */

static int meta_index(const hv_volume *v, const char *key, int *found)
{
    int lo = 0, hi = v->nmeta;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        int c = strcmp(v->meta[mid].key, key);
        if (c == 0) {
            *found = 1;
            return mid;
        }
        if (c < 0) lo = mid + 1;
        else hi = mid;
    }
    *found = 0;
    return lo;
}

static hv_status meta_put(hv_volume *v, const char *key, const char *str, const double *num)
{
    if (!key || !*key) return hv_error_set(HV_ERR_INVALID, "metadata key must not be empty");
    int found;
    int i = meta_index(v, key, &found);
    if (!str && !num) { /* remove */
        if (found) {
            free(v->meta[i].key);
            free(v->meta[i].str);
            memmove(&v->meta[i], &v->meta[i + 1], (size_t)(v->nmeta - i - 1) * sizeof *v->meta);
            --v->nmeta;
        }
        return HV_OK;
    }
    char *s = NULL;
    if (str && !(s = hv_strdup(str))) return HV_ERR_NOMEM;
    if (!found) {
        char *k = hv_strdup(key);
        if (!k || hv_grow((void **)&v->meta, &v->mcap, (size_t)v->nmeta + 1, sizeof *v->meta)) {
            free(k);
            free(s);
            return HV_ERR_NOMEM;
        }
        memmove(&v->meta[i + 1], &v->meta[i], (size_t)(v->nmeta - i) * sizeof *v->meta);
        v->meta[i].key = k;
        v->meta[i].str = NULL;
        ++v->nmeta;
    }
    free(v->meta[i].str);
    v->meta[i].str = s;
    v->meta[i].is_number = num != NULL;
    v->meta[i].num = num ? *num : 0.0;
    return HV_OK;
}

hv_status hv_volume_meta_set_string(hv_volume *v, const char *key, const char *value)
{
    return meta_put(v, key, value, NULL);
}

hv_status hv_volume_meta_set_json(hv_volume *v, const char *key, const char *json)
{
    if (json) {
        char what[300];
        snprintf(what, sizeof what, "metadata '%s'", key);
        json_t *j;
        hv_status s = hv_json_parse(json, strlen(json), what, &j);
        if (s != HV_OK) return s == HV_ERR_BAD_INPUT ? HV_ERR_INVALID : s;
        json_decref(j);
    }
    return meta_put(v, key, json, NULL);
}

hv_status hv_volume_meta_set_number(hv_volume *v, const char *key, double value)
{
    return meta_put(v, key, NULL, &value);
}

const char *hv_volume_meta_string(const hv_volume *v, const char *key)
{
    int found;
    int i = meta_index(v, key, &found);
    return found && !v->meta[i].is_number ? v->meta[i].str : NULL;
}

int hv_volume_meta_number(const hv_volume *v, const char *key, double *value)
{
    int found;
    int i = meta_index(v, key, &found);
    if (!found || !v->meta[i].is_number) return 0;
    *value = v->meta[i].num;
    return 1;
}

int hv_volume_meta_count(const hv_volume *v) { return v->nmeta; }

const char *hv_volume_meta_key(const hv_volume *v, int i)
{
    return i >= 0 && i < v->nmeta ? v->meta[i].key : NULL;
}

/* ---- what the file readers use (volume_internal.h) -------------------------------------- */

hv_status hv_volume_adopt_grid(hv_volume *v, const char *name, hv_grid_type type, int *index)
{
    /* unnamed or duplicate grids get a unique name */
    char buf[300];
    if (!*name || hv_volume_grid_find(v, name) >= 0)
        snprintf(buf, sizeof buf, "%.255s%sgrid%d", name, *name ? "." : "", v->ngrids);
    else
        snprintf(buf, sizeof buf, "%s", name);
    hv_status s = push_grid(v, buf, type);
    if (s == HV_OK && index) *index = v->ngrids - 1;
    return s;
}

void hv_volume_adopt_transform(hv_volume *v, const hv_transform *xf) { v->xf = *xf; }

hv_status hv_volume_adopt_topology(hv_volume *v, size_t n, int32_t *origins, uint64_t *masks)
{
    free(v->origins);
    free(v->masks);
    v->origins = origins;
    v->masks = masks;
    v->nleaves = n;
    size_t cap = hash_cap(n);
    hash_slot *hash = hv_malloc_array(cap, sizeof *hash);
    if (!hash) return HV_ERR_NOMEM;
    hash_fill(v, hash, cap);
    return HV_OK;
}

void *const *hv_volume_grid_buffers(const hv_volume *v, int g)
{
    return g >= 0 && g < v->ngrids ? v->grids[g].leaves : NULL;
}

hv_status hv_volume_set_name(hv_volume *v, const char *name)
{
    char *n = hv_strdup(name);
    if (!n) return HV_ERR_NOMEM;
    free(v->name);
    v->name = n;
    return HV_OK;
}

/* ---- memory ----------------------------------------------------------------------------- */

uint64_t hv_volume_memory_bytes(const hv_volume *v)
{
    /* the slabs of leaf buffers, their tables, the topology and its hash */
    uint64_t b = sizeof *v + v->nleaves * (3 * sizeof(int32_t) + HV_LEAF_WORDS * sizeof(uint64_t));
    for (int g = 0; g < v->ngrids; ++g) {
        const grid_entry *e = &v->grids[g];
        for (size_t i = 0; i < e->nslabs; ++i) b += e->slabs[i].leaves * leaf_bytes(e->type);
        b += v->nleaves * sizeof(void *);
    }
    b += v->hcap * sizeof(hash_slot);
    return b;
}

uint64_t hv_volume_memory_estimate(uint64_t leaves, int float_grids, int bool_grids)
{
    /* What an OpenVDB tree took, kept as a bound on the C store: float 2152 B per leaf, bool
     * 160 B, topology 80 B and tables 64 B + 8 B per grid, 3% more. The C store takes
     * 2048 + 8 B per float leaf, 64 + 8 B per bool leaf (buffers in slabs, a pointer), 76 B of
     * topology and 32 to 64 B of hash per leaf (hv_volume_memory_bytes); slabs left half
     * empty by a restrict are compacted. A save holds one grid more while OpenVDB writes it. */
    uint64_t per_leaf = (uint64_t)float_grids * 2152u + (uint64_t)bool_grids * 160u + 80u +
                        64u + 8u * (uint64_t)(float_grids + bool_grids);
    return leaves * per_leaf + leaves * per_leaf / 32u + (1u << 20);
}

/* ---- fields a caller computes ------------------------------------------------------------ */

static hv_status mask_grid(const hv_volume *vol, const char *mask, int *g)
{
    *g = hv_volume_grid_find(vol, mask ? mask : "");
    if (*g < 0 || hv_volume_grid_type(vol, *g) != HV_GRID_BOOL)
        return hv_error_set(HV_ERR_NOT_FOUND, "the model has no bool grid '%s'", mask ? mask : "");
    return HV_OK;
}

static void centre(const hv_transform *xf, const int32_t *o, unsigned n, double p[3])
{
    int32_t v[3] = {o[0] + (int32_t)(n >> 6), o[1] + (int32_t)((n >> 3) & 7), o[2] + (int32_t)(n & 7)};
    for (int a = 0; a < 3; ++a) p[a] = xf->origin[a] + v[a] * xf->voxel[a];
}

hv_status hv_volume_centres(const hv_volume *vol, const char *mask, double **xyz, size_t *n)
{
    *xyz = NULL;
    *n = 0;
    int g;
    hv_status s = mask_grid(vol, mask, &g);
    if (s != HV_OK) return s;
    uint64_t count = hv_volume_mask_count(vol, g);
    if (count == 0) return HV_OK;
    double *p = hv_malloc_array((size_t)count, 3 * sizeof *p);
    if (!p) return HV_ERR_NOMEM;
    hv_transform xf = hv_volume_get_transform(vol);
    const int32_t *org = hv_volume_leaf_origins(vol);
    size_t i = 0;
    for (size_t l = 0; l < hv_volume_leaf_count(vol); ++l) {
        const uint64_t *a = hv_volume_leaf_mask(vol, l), *b = hv_volume_leaf_bool_c(vol, g, l);
        for (unsigned q = 0; q < 8; ++q)
            for (uint64_t w = a[q] & b[q]; w; w &= w - 1) centre(&xf, org + 3 * l, q * 64 + (unsigned)__builtin_ctzll(w), p + 3 * i++);
    }
    *xyz = p;
    *n = (size_t)count;
    return HV_OK;
}

hv_status hv_volume_grid_set(hv_volume *vol, const char *name, const char *mask, const float *values, size_t n)
{
    int g;
    hv_status s = mask_grid(vol, mask, &g);
    if (s != HV_OK) return s;
    uint64_t count = hv_volume_mask_count(vol, g);
    if ((uint64_t)n != count)
        return hv_error_set(HV_ERR_INVALID, "grid '%s': %zu values for the %llu voxels of '%s'", name ? name : "", n,
                            (unsigned long long)count, mask);
    hv_transform xf = hv_volume_get_transform(vol);
    const int32_t *org = hv_volume_leaf_origins(vol);
    size_t i = 0; /* every value finite before anything is added */
    for (size_t l = 0; l < hv_volume_leaf_count(vol); ++l) {
        const uint64_t *a = hv_volume_leaf_mask(vol, l), *b = hv_volume_leaf_bool_c(vol, g, l);
        for (unsigned q = 0; q < 8; ++q)
            for (uint64_t w = a[q] & b[q]; w; w &= w - 1, ++i)
                if (!isfinite(values[i])) {
                    double p[3];
                    centre(&xf, org + 3 * l, q * 64 + (unsigned)__builtin_ctzll(w), p);
                    return hv_error_set(HV_ERR_INVALID, "grid '%s': the value at (%g, %g, %g) is not finite (%g)", name, p[0],
                                        p[1], p[2], (double)values[i]);
                }
    }
    int fg;
    if ((s = hv_volume_grid_add(vol, name, HV_GRID_FLOAT, &fg)) != HV_OK) return s;
    g = hv_volume_grid_find(vol, mask); /* indices are stable on add, but look again */
    i = 0;
    for (size_t l = 0; l < hv_volume_leaf_count(vol); ++l) {
        const uint64_t *a = hv_volume_leaf_mask(vol, l), *b = hv_volume_leaf_bool_c(vol, g, l);
        float *f = hv_volume_leaf_float(vol, fg, l);
        for (unsigned q = 0; q < 8; ++q)
            for (uint64_t w = a[q] & b[q]; w; w &= w - 1) f[q * 64 + (unsigned)__builtin_ctzll(w)] = values[i++];
    }
    return HV_OK;
}

int hv_volume_identical(const hv_volume *a, const hv_volume *b, char *why, size_t len)
{
#define DIFFER(...) return snprintf(why, len, __VA_ARGS__), 0
    if (memcmp(&a->xf, &b->xf, sizeof a->xf) != 0) DIFFER("transforms differ");
    if (a->ngrids != b->ngrids) DIFFER("%d grids against %d", a->ngrids, b->ngrids);
    if (a->nleaves != b->nleaves) DIFFER("%zu leaves against %zu", a->nleaves, b->nleaves);
    if (a->nleaves && (memcmp(a->origins, b->origins, 3 * a->nleaves * sizeof *a->origins) != 0 ||
                       memcmp(a->masks, b->masks, HV_LEAF_WORDS * a->nleaves * sizeof *a->masks) != 0))
        DIFFER("leaf origins or masks differ");
    for (int g = 0; g < a->ngrids; ++g) {
        if (strcmp(a->grids[g].name, b->grids[g].name) != 0 || a->grids[g].type != b->grids[g].type)
            DIFFER("grid %d: '%s' against '%s'", g, a->grids[g].name, b->grids[g].name);
        for (size_t l = 0; l < a->nleaves; ++l)
            if (memcmp(a->grids[g].leaves[l], b->grids[g].leaves[l], leaf_bytes(a->grids[g].type)) != 0)
                DIFFER("grid '%s', leaf %zu at (%d, %d, %d): values differ", a->grids[g].name, l, a->origins[3 * l],
                       a->origins[3 * l + 1], a->origins[3 * l + 2]);
    }
    if (a->nmeta != b->nmeta) DIFFER("%d metadata entries against %d", a->nmeta, b->nmeta);
    for (int i = 0; i < a->nmeta; ++i) {
        const meta_entry *x = &a->meta[i], *y = &b->meta[i];
        if (strcmp(x->key, y->key) != 0 || x->is_number != y->is_number ||
            (x->is_number ? memcmp(&x->num, &y->num, sizeof x->num) != 0 : strcmp(x->str, y->str) != 0))
            DIFFER("metadata '%s' differs", x->key);
    }
#undef DIFFER
    if (len) why[0] = 0;
    return 1;
}
