/* src/geometry/record.c - a model's geometry record (hovox/geometry.h; DESIGN.md "Geometry
 * truth", issue 28): leaves (a mesh packed and deflated, or a kind's own data) with their
 * placement, and the Boolean tree of Wu's eq. 27-30 and CSG subtract over them, kept in the
 * model's metadata. Layer 3 of README's Layout: it knows meshes and the volume store only, so
 * the voxelizer and the Booleans above it write it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "core/json.h"
#include "hovox/geometry.h"
#include "mesh/mesh_internal.h"
#include "volumes/schema.h"

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the packed mesh of a geometry leaf is written in the host's byte order: little-endian only"
#endif

#define LEAF_PREFIX "hovox.geometry.leaf."
#define PACK_MAGIC "HVM1"
#define MAX_DEPTH 1000 /* tree nesting read from a file */

typedef struct leaf_rec {
    hv_geometry_leaf info; /* info.name owned */
    uint8_t *data;         /* info.size bytes */
} leaf_rec;

struct hv_geometry {
    size_t nleaf, nnode;
    leaf_rec *leaf;
    hv_geometry_node *node;
};

static const char *const k_ops[] = {"intersect", "unite", "difference", "merge", "subtract", NULL};
static const char *const k_kinds[] = {"mesh", "field_iso", NULL};
static const hv_enum_def k_ops_enum = {"Boolean", k_ops, NULL, NULL};
static const hv_enum_def k_kinds_enum = {"leaf kind", k_kinds, NULL, NULL};

const char *hv_geometry_op_name(hv_geometry_op op)
{
    return (unsigned)op <= HV_GEOMETRY_SUBTRACT ? k_ops[op] : "?";
}

static uint64_t fnv1a(const uint8_t *p, size_t n)
{
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    return h;
}

static const double k_identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

static hv_status check_transform(const double *t)
{
    for (int i = 0; i < 12; ++i)
        if (!isfinite(t[i])) return hv_error_set(HV_ERR_INVALID, "geometry: transform entry %d is not finite (%g)", i, t[i]);
    double det = t[0] * (t[5] * t[10] - t[6] * t[9]) - t[1] * (t[4] * t[10] - t[6] * t[8]) +
                 t[2] * (t[4] * t[9] - t[5] * t[8]);
    if (!(fabs(det) > 1e-300)) return hv_error_set(HV_ERR_INVALID, "geometry: the transform is singular");
    return HV_OK;
}

void hv_geometry_destroy(hv_geometry *g)
{
    if (!g) return;
    for (size_t i = 0; i < g->nleaf; ++i) {
        free((char *)g->leaf[i].info.name);
        free(g->leaf[i].data);
    }
    free(g->leaf);
    free(g->node);
    free(g);
}

/* A record of n leaves and m nodes, zeroed. */
static hv_geometry *geometry_new(size_t nleaf, size_t nnode)
{
    hv_geometry *g = hv_calloc(1, sizeof *g);
    if (!g) return NULL;
    g->leaf = hv_calloc(nleaf ? nleaf : 1, sizeof *g->leaf);
    g->node = hv_calloc(nnode ? nnode : 1, sizeof *g->node);
    if (!g->leaf || !g->node) {
        hv_geometry_destroy(g);
        return NULL;
    }
    return g;
}

/* Leaf slot `l` takes a copy of info (name copied) and data (taken). */
static hv_status leaf_fill(leaf_rec *l, const hv_geometry_leaf *info, uint8_t *data)
{
    l->info = *info;
    l->info.name = hv_strdup(info->name ? info->name : "");
    l->data = data;
    return l->info.name ? HV_OK : HV_ERR_NOMEM;
}

hv_status hv_geometry_from_leaf(hv_leaf_kind kind, const char *name, const void *data, size_t size,
                                const double transform[12], double unit, hv_geometry **out)
{
    *out = NULL;
    if ((unsigned)kind > HV_LEAF_FIELD_ISO) return hv_error_set(HV_ERR_INVALID, "geometry: unknown leaf kind %d", (int)kind);
    if (!data || size == 0) return hv_error_set(HV_ERR_INVALID, "geometry: a leaf without data");
    if (!transform) transform = k_identity;
    hv_status s = check_transform(transform);
    if (s != HV_OK) return s;
    if (!(unit > 0) || !isfinite(unit)) unit = 1.0;
    hv_geometry *g = geometry_new(1, 1);
    uint8_t *copy = hv_malloc(size);
    if (!g || !copy) {
        free(copy);
        hv_geometry_destroy(g);
        return HV_ERR_NOMEM;
    }
    memcpy(copy, data, size);
    hv_geometry_leaf info = {kind, name, {0}, unit, size, fnv1a(copy, size)};
    memcpy(info.transform, transform, sizeof info.transform);
    g->nleaf = g->nnode = 1;
    g->node[0] = (hv_geometry_node){-1, 0, 0, 0};
    if ((s = leaf_fill(&g->leaf[0], &info, copy)) != HV_OK) {
        hv_geometry_destroy(g);
        return s;
    }
    *out = g;
    return HV_OK;
}

/* ---- packing a mesh -----------------------------------------------------------------------
 * "HVM1", u32 vertices, facets, bodies, materials, flags (bit 0: per-facet materials); the
 * vertices (3 float32 each) and facets (3 uint32 each) as hv_mesh holds them; per body u32 facet
 * count, i32 material, u32 name length, the name; per material u32 rgba, u32 has_color, u32 name
 * length, the name; with flag bit 0 an i32 material per facet. Little-endian. Vertices are
 * numbered by first use in the facets (as every hv_mesh is), so unpacking welds them back to the
 * same arrays. */

typedef struct packer {
    uint8_t *p;
    size_t n, cap;
    int failed;
} packer;

static void put(packer *k, const void *src, size_t n)
{
    if (k->failed) return;
    if (k->n + n > k->cap) {
        size_t cap = k->cap ? k->cap : 1024;
        while (cap < k->n + n) cap *= 2;
        uint8_t *p = realloc(k->p, cap);
        if (!p) {
            k->failed = 1;
            return;
        }
        k->p = p;
        k->cap = cap;
    }
    memcpy(k->p + k->n, src, n);
    k->n += n;
}

static void put_u32(packer *k, uint32_t v) { put(k, &v, 4); }

static void put_str(packer *k, const char *s)
{
    size_t n = s ? strlen(s) : 0;
    put_u32(k, (uint32_t)n);
    put(k, s, n);
}

static hv_status pack_mesh(const hv_mesh *m, uint8_t **out, size_t *size)
{
    packer k = {0};
    size_t nv = hv_mesh_vertex_count(m), nf = hv_mesh_facet_count(m), nb = hv_mesh_body_count(m),
           nm = hv_mesh_material_count(m);
    const int32_t *fm = hv_mesh_facet_materials(m);
    put(&k, PACK_MAGIC, 4);
    uint32_t head[5] = {(uint32_t)nv, (uint32_t)nf, (uint32_t)nb, (uint32_t)nm, fm ? 1u : 0u};
    put(&k, head, sizeof head);
    put(&k, hv_mesh_vertices(m), 12 * nv);
    put(&k, hv_mesh_facets(m), 12 * nf);
    for (size_t i = 0; i < nb; ++i) {
        const hv_mesh_body *b = hv_mesh_body_at(m, i);
        put_u32(&k, (uint32_t)b->facet_count);
        put_u32(&k, (uint32_t)b->material);
        put_str(&k, b->name);
    }
    for (size_t i = 0; i < nm; ++i) {
        const hv_mesh_material *mt = hv_mesh_material_at(m, i);
        put_u32(&k, mt->rgba);
        put_u32(&k, (uint32_t)mt->has_color);
        put_str(&k, mt->name);
    }
    if (fm) put(&k, fm, 4 * nf);
    if (k.failed) {
        free(k.p);
        return hv_error_set(HV_ERR_NOMEM, "geometry: out of memory packing a mesh of %zu facets", nf);
    }
    *out = k.p;
    *size = k.n;
    return HV_OK;
}

hv_status hv_geometry_from_mesh(const hv_mesh *raw, const char *name, const double transform[12], double unit,
                                hv_geometry **out)
{
    *out = NULL;
    uint8_t *data = NULL;
    size_t size = 0;
    hv_status s = pack_mesh(raw, &data, &size);
    if (s != HV_OK) return s;
    s = hv_geometry_from_leaf(HV_LEAF_MESH, name ? name : hv_mesh_name(raw), data, size, transform, unit, out);
    free(data);
    return s;
}

typedef struct reader {
    const uint8_t *p;
    size_t n, at;
    int bad;
} reader;

static const void *take(reader *r, size_t n)
{
    if (r->bad || n > r->n - r->at) {
        r->bad = 1;
        return NULL;
    }
    const void *p = r->p + r->at;
    r->at += n;
    return p;
}

static uint32_t take_u32(reader *r)
{
    const void *p = take(r, 4);
    uint32_t v = 0;
    if (p) memcpy(&v, p, 4);
    return v;
}

/* A string of the packed mesh, copied (NULL and r->bad when it runs past the end). */
static char *take_str(reader *r, int *nomem)
{
    uint32_t n = take_u32(r);
    const char *p = take(r, n);
    if (!p) return NULL;
    char *s = hv_malloc((size_t)n + 1);
    if (!s) {
        *nomem = 1;
        return NULL;
    }
    memcpy(s, p, n);
    s[n] = 0;
    return s;
}

hv_status hv_geometry_leaf_mesh_raw(const hv_geometry *g, size_t i, hv_mesh **out)
{
    *out = NULL;
    if (i >= g->nleaf || g->leaf[i].info.kind != HV_LEAF_MESH)
        return hv_error_set(HV_ERR_INVALID, "geometry: leaf %zu is not a mesh", i);
    const leaf_rec *l = &g->leaf[i];
    const char *name = l->info.name;
    reader r = {l->data, l->info.size, 0, 0};
    const void *magic = take(&r, 4);
    uint32_t nv = take_u32(&r), nf = take_u32(&r), nb = take_u32(&r), nm = take_u32(&r), flags = take_u32(&r);
    if (!magic || memcmp(magic, PACK_MAGIC, 4) != 0 || r.bad)
        return hv_error_set(HV_ERR_BAD_INPUT, "recorded mesh '%s': not a packed mesh", name);
    if (nf == 0 || nf > INT32_MAX / 3 || nb == 0 || nb > nf || flags > 1 || nv > 3 * (uint64_t)nf)
        return hv_error_set(HV_ERR_BAD_INPUT, "recorded mesh '%s': damaged counts (%u vertices, %u facets, %u bodies)",
                            name, nv, nf, nb);
    const float *xyz = take(&r, 12 * (size_t)nv);
    const uint32_t *tri = take(&r, 12 * (size_t)nf);
    if (r.bad) return hv_error_set(HV_ERR_BAD_INPUT, "recorded mesh '%s': ends inside its facets", name);
    /* each material takes at least 12 bytes (colour, flag, name length): no table larger than the
     * bytes left can be filled, so none is allocated (a count of 2^32 asked for 17 GB) */
    if (nm > (r.n - r.at) / 12)
        return hv_error_set(HV_ERR_BAD_INPUT, "recorded mesh '%s': %u materials in the %zu bytes left", name, nm,
                            r.n - r.at);
    hv_mesh_body *bodies = hv_calloc(nb, sizeof *bodies);
    hv_mesh_material *mats = hv_calloc(nm ? nm : 1, sizeof *mats);
    float *soup = hv_malloc_array(nf, 9 * sizeof(float));
    int nomem = !bodies || !mats || !soup;
    uint64_t total = 0;
    for (uint32_t b = 0; b < nb && !nomem && !r.bad; ++b) {
        bodies[b].facet_count = take_u32(&r);
        bodies[b].material = (int32_t)take_u32(&r);
        bodies[b].name = take_str(&r, &nomem);
        total += bodies[b].facet_count;
        if (bodies[b].facet_count == 0 || bodies[b].material < HV_MESH_NO_MATERIAL || bodies[b].material >= (int64_t)nm)
            r.bad = 1;
    }
    for (uint32_t k = 0; k < nm && !nomem && !r.bad; ++k) {
        if (nm > r.n) {
            r.bad = 1;
            break;
        }
        mats[k].rgba = take_u32(&r);
        mats[k].has_color = take_u32(&r) != 0;
        mats[k].name = take_str(&r, &nomem);
    }
    /* the facets' materials follow the names, at any byte offset: copied out to be read as int32 */
    const void *fm_bytes = flags & 1 && !nomem ? take(&r, 4 * (size_t)nf) : NULL;
    int32_t *fm = NULL;
    if (fm_bytes && !(fm = hv_malloc_array(nf, sizeof *fm))) nomem = 1;
    if (fm) memcpy(fm, fm_bytes, 4 * (size_t)nf);
    hv_status s = HV_OK;
    if (nomem) s = HV_ERR_NOMEM;
    else if (r.bad || total != nf || r.at != r.n)
        s = hv_error_set(HV_ERR_BAD_INPUT, "recorded mesh '%s': damaged bodies or materials", name);
    for (size_t f = 0; s == HV_OK && f < nf; ++f) {
        for (int c = 0; c < 3; ++c) {
            uint32_t v = tri[3 * f + (size_t)c];
            if (v >= nv) {
                s = hv_error_set(HV_ERR_BAD_INPUT, "recorded mesh '%s': facet %zu names vertex %u of %u", name, f, v, nv);
                break;
            }
            for (int a = 0; a < 3; ++a) {
                float x = xyz[3 * (size_t)v + (size_t)a];
                if (!isfinite(x)) {
                    s = hv_error_set(HV_ERR_BAD_INPUT, "recorded mesh '%s': vertex %u has a non-finite coordinate", name, v);
                    break;
                }
                soup[9 * f + 3 * (size_t)c + (size_t)a] = x;
            }
        }
        if (fm && s == HV_OK && (fm[f] < HV_MESH_NO_MATERIAL || fm[f] >= (int64_t)nm))
            s = hv_error_set(HV_ERR_BAD_INPUT, "recorded mesh '%s': facet %zu has material %d of %u", name, f, fm[f], nm);
    }
    hv_mesh *m = NULL;
    if (s == HV_OK) s = hv_mesh_from_soup(soup, NULL, nf, name, HV_MESH_GENERATED, &m);
    if (s == HV_OK && (nb > 1 || nm > 0 || fm || strcmp(bodies[0].name, hv_mesh_body_at(m, 0)->name) != 0))
        s = hv_mesh_set_bodies(m, bodies, nb, mats, nm, fm);
    for (uint32_t b = 0; bodies && b < nb; ++b) free((char *)bodies[b].name);
    for (uint32_t k = 0; mats && k < nm; ++k) free((char *)mats[k].name);
    free(bodies);
    free(mats);
    free(soup);
    free(fm);
    if (s != HV_OK) {
        hv_mesh_destroy(m);
        return s;
    }
    *out = m;
    return HV_OK;
}

hv_status hv_geometry_leaf_mesh(const hv_geometry *g, size_t i, hv_mesh **out)
{
    hv_mesh *raw;
    hv_status s = hv_geometry_leaf_mesh_raw(g, i, &raw);
    if (s != HV_OK || memcmp(g->leaf[i].info.transform, k_identity, sizeof k_identity) == 0) {
        *out = s == HV_OK ? raw : NULL;
        return s;
    }
    s = hv_mesh_transform(raw, g->leaf[i].info.transform, out);
    hv_mesh_destroy(raw);
    return s;
}

/* ---- accessors --------------------------------------------------------------------------------- */

size_t hv_geometry_leaf_count(const hv_geometry *g) { return g->nleaf; }
const hv_geometry_leaf *hv_geometry_leaf_at(const hv_geometry *g, size_t i) { return i < g->nleaf ? &g->leaf[i].info : NULL; }
const uint8_t *hv_geometry_leaf_data(const hv_geometry *g, size_t i) { return i < g->nleaf ? g->leaf[i].data : NULL; }
size_t hv_geometry_node_count(const hv_geometry *g) { return g->nnode; }
const hv_geometry_node *hv_geometry_node_at(const hv_geometry *g, size_t i) { return i < g->nnode ? &g->node[i] : NULL; }
int hv_geometry_is_plain(const hv_geometry *g) { return g->nleaf == 1 && g->nnode == 1; }

int hv_geometry_shape_is_leaf(const hv_geometry *g)
{
    if (g->nleaf != 1) return 0;
    for (size_t i = 0; i < g->nnode; ++i)
        if (g->node[i].op == HV_GEOMETRY_SUBTRACT) return 0;
    return 1;
}

/* ---- Booleans ---------------------------------------------------------------------------------- */

static int same_leaf(const leaf_rec *x, const leaf_rec *y)
{
    return x->info.kind == y->info.kind && x->info.size == y->info.size && x->info.hash == y->info.hash &&
           memcmp(x->info.transform, y->info.transform, sizeof x->info.transform) == 0 &&
           memcmp(x->data, y->data, x->info.size) == 0;
}

static hv_status leaf_copy(leaf_rec *dst, const leaf_rec *src)
{
    uint8_t *d = hv_malloc(src->info.size);
    if (!d) return HV_ERR_NOMEM;
    memcpy(d, src->data, src->info.size);
    hv_status s = leaf_fill(dst, &src->info, d);
    return s;
}

hv_status hv_geometry_combine(const hv_geometry *a, const hv_geometry *b, hv_geometry_op op, hv_geometry **out)
{
    *out = NULL;
    if ((unsigned)op > HV_GEOMETRY_SUBTRACT) return hv_error_set(HV_ERR_INVALID, "geometry: unknown Boolean %d", (int)op);
    hv_geometry *g = geometry_new(a->nleaf + b->nleaf, a->nnode + b->nnode + 1);
    uint32_t *map = hv_malloc_array(b->nleaf ? b->nleaf : 1, sizeof *map);
    hv_status s = g && map ? HV_OK : HV_ERR_NOMEM;
    for (size_t i = 0; i < a->nleaf && s == HV_OK; ++i, ++g->nleaf) s = leaf_copy(&g->leaf[i], &a->leaf[i]);
    for (size_t j = 0; j < b->nleaf && s == HV_OK; ++j) {
        size_t k = 0;
        while (k < g->nleaf && !same_leaf(&g->leaf[k], &b->leaf[j])) ++k;
        if (k == g->nleaf && (s = leaf_copy(&g->leaf[k], &b->leaf[j])) == HV_OK) ++g->nleaf;
        map[j] = (uint32_t)k;
    }
    if (s == HV_OK) {
        memcpy(g->node, a->node, a->nnode * sizeof *g->node);
        for (size_t i = 0; i < b->nnode; ++i) {
            hv_geometry_node n = b->node[i];
            if (n.op < 0) {
                n.leaf = map[n.leaf];
            } else {
                n.a += (uint32_t)a->nnode;
                n.b += (uint32_t)a->nnode;
            }
            g->node[a->nnode + i] = n;
        }
        g->node[a->nnode + b->nnode] = (hv_geometry_node){(int)op, 0, (uint32_t)a->nnode - 1,
                                                          (uint32_t)(a->nnode + b->nnode) - 1};
        g->nnode = a->nnode + b->nnode + 1;
    }
    free(map);
    if (s != HV_OK) {
        hv_geometry_destroy(g);
        return s;
    }
    *out = g;
    return HV_OK;
}

hv_status hv_geometry_transformed(const hv_geometry *g, const double m[12], hv_geometry **out)
{
    *out = NULL;
    hv_status s = check_transform(m);
    if (s != HV_OK) return s;
    hv_geometry *r = geometry_new(g->nleaf, g->nnode);
    if (!r) return HV_ERR_NOMEM;
    for (size_t i = 0; i < g->nleaf && s == HV_OK; ++i) {
        leaf_rec moved = g->leaf[i];
        const double *t = g->leaf[i].info.transform;
        for (int row = 0; row < 3; ++row)
            for (int c = 0; c < 4; ++c)
                moved.info.transform[4 * row + c] = m[4 * row] * t[c] + m[4 * row + 1] * t[4 + c] +
                                                    m[4 * row + 2] * t[8 + c] + (c == 3 ? m[4 * row + 3] : 0.0);
        if ((s = check_transform(moved.info.transform)) == HV_OK && (s = leaf_copy(&r->leaf[i], &moved)) == HV_OK)
            ++r->nleaf;
    }
    if (s == HV_OK) {
        memcpy(r->node, g->node, g->nnode * sizeof *r->node);
        r->nnode = g->nnode;
        *out = r;
    } else {
        hv_geometry_destroy(r);
    }
    return s;
}

/* ---- in a model -------------------------------------------------------------------------------- */

static void leaf_key(const hv_geometry_leaf *l, char *buf, size_t n)
{
    snprintf(buf, n, LEAF_PREFIX "%016llx", (unsigned long long)l->hash);
}

int hv_geometry_present(const hv_volume *model)
{
    return hv_volume_meta_string(model, hv_schema_key(HV_DOC_GEOMETRY)) != NULL;
}

static json_t *node_doc(const hv_geometry *g, size_t i)
{
    const hv_geometry_node *n = &g->node[i];
    if (n->op < 0) return json_integer(n->leaf);
    json_t *o = json_object();
    if (o && (hv_json_set(o, "op", json_string(k_ops[n->op])) | hv_json_set(o, "a", node_doc(g, n->a)) |
              hv_json_set(o, "b", node_doc(g, n->b)))) {
        json_decref(o);
        return NULL;
    }
    return o;
}

/* Remove the record's document and every leaf key from v. */
static hv_status remove_record(hv_volume *v)
{
    hv_status s = hv_volume_meta_set_string(v, hv_schema_key(HV_DOC_GEOMETRY), NULL);
    for (int i = hv_volume_meta_count(v) - 1; i >= 0 && s == HV_OK; --i) {
        const char *key = hv_volume_meta_key(v, i);
        if (strncmp(key, LEAF_PREFIX, strlen(LEAF_PREFIX)) == 0) s = hv_volume_meta_set_string(v, key, NULL);
    }
    return s;
}

static hv_status leaf_store(const leaf_rec *l, hv_volume *model)
{
    char key[64];
    leaf_key(&l->info, key, sizeof key);
    uLongf zn = compressBound((uLong)l->info.size);
    uint8_t *z = hv_malloc(zn);
    if (!z) return HV_ERR_NOMEM;
    /* level 1: level 9 takes ten times as long (1.3 s against 0.09 s for a 200k-facet mesh) to save 2% */
    if (compress2(z, &zn, l->data, (uLong)l->info.size, 1) != Z_OK) {
        free(z);
        return hv_error_set(HV_ERR_NOMEM, "geometry: zlib failed on leaf '%s'", l->info.name);
    }
    hv_buf b;
    hv_buf_init(&b);
    hv_base64_append(&b, z, zn);
    free(z);
    hv_status s = b.failed ? HV_ERR_NOMEM : hv_volume_meta_set_string(model, key, b.data);
    hv_buf_free(&b);
    return s;
}

hv_status hv_geometry_write(const hv_geometry *g, hv_volume *model)
{
    hv_status s = remove_record(model);
    if (s != HV_OK || !g) return s;
    json_t *doc = json_object(), *leaves = json_array();
    int bad = !doc || !leaves;
    for (size_t i = 0; i < g->nleaf && !bad; ++i) {
        const hv_geometry_leaf *l = &g->leaf[i].info;
        char key[64], hash[24];
        leaf_key(l, key, sizeof key);
        snprintf(hash, sizeof hash, "%016llx", (unsigned long long)l->hash);
        json_t *o = json_object();
        bad = !o || hv_json_set(o, "kind", json_string(k_kinds[l->kind])) | hv_json_set(o, "name", hv_json_text(l->name)) |
                        hv_json_set(o, "transform", hv_json_numbers(l->transform, 12)) |
                        hv_json_set(o, "unit", hv_json_number(l->unit)) |
                        hv_json_set(o, "size", json_integer((json_int_t)l->size)) | hv_json_set(o, "hash", json_string(hash)) |
                        hv_json_set(o, "data", json_string(key));
        if (!bad) bad = json_array_append_new(leaves, o) != 0;
        else json_decref(o);
        if (!bad && (s = leaf_store(&g->leaf[i], model)) != HV_OK) break;
    }
    if (s != HV_OK) {
        json_decref(doc);
        json_decref(leaves);
        return s;
    }
    if (bad || hv_json_set(doc, "leaves", leaves) | hv_json_set(doc, "tree", node_doc(g, g->nnode - 1))) {
        json_decref(doc);
        return hv_error_set(HV_ERR_NOMEM, "geometry: out of memory writing the record");
    }
    return hv_schema_doc_write(model, HV_DOC_GEOMETRY, doc);
}

#define KEY "hovox.geometry.json"

/* The leaf's data from its metadata key: base64, inflated to exactly `size` bytes, hash checked. */
static hv_status leaf_load(const hv_volume *model, leaf_rec *l, const char *key)
{
    const char *name = l->info.name;
    const char *text = hv_volume_meta_string(model, key);
    if (!text)
        return hv_error_set(HV_ERR_BAD_INPUT, KEY ": the geometry tree refers to %s '%s' (%s), which the model does not hold",
                            k_kinds[l->info.kind], name, key);
    uint8_t *z;
    size_t zn;
    hv_status s = hv_base64_decode(text, strlen(text), &z, &zn);
    if (s != HV_OK) return s == HV_ERR_NOMEM ? s : hv_error_prefix(s, KEY ": leaf '%s': ", name);
    l->data = hv_malloc(l->info.size);
    if (!l->data) {
        free(z);
        return HV_ERR_NOMEM;
    }
    uLongf n = (uLongf)l->info.size;
    int zs = uncompress(l->data, &n, z, (uLong)zn);
    free(z);
    if (zs == Z_MEM_ERROR) return HV_ERR_NOMEM;
    if (zs != Z_OK || n != l->info.size)
        return hv_error_set(HV_ERR_BAD_INPUT, KEY ": leaf '%s': the recorded data is damaged (%s)", name,
                            zs == Z_OK ? "shorter than recorded" : zs == Z_BUF_ERROR ? "longer than recorded" : "zlib");
    if (fnv1a(l->data, l->info.size) != l->info.hash)
        return hv_error_set(HV_ERR_BAD_INPUT, KEY ": leaf '%s': the recorded data is damaged (its hash differs)", name);
    return HV_OK;
}

static hv_status leaf_from_doc(const hv_volume *model, const json_t *o, size_t i, leaf_rec *l)
{
    char what[64];
    snprintf(what, sizeof what, KEY ": leaves[%zu]", i);
    const char *name, *hash, *key;
    long long size;
    int k;
    hv_status s = hv_json_get_name(o, "kind", what, &k_kinds_enum, &k);
    if (s == HV_OK) s = hv_json_get_string(o, "name", what, &name);
    if (s == HV_OK) s = hv_json_get_numbers(o, "transform", what, l->info.transform, 12);
    if (s == HV_OK) s = hv_json_get_number(o, "unit", what, &l->info.unit);
    if (s == HV_OK) s = hv_json_get_int(o, "size", what, 1, (long long)1 << 40, &size);
    if (s == HV_OK) s = hv_json_get_string(o, "hash", what, &hash);
    if (s == HV_OK) s = hv_json_get_string(o, "data", what, &key);
    if (s != HV_OK) return s;
    char *end;
    l->info.hash = strtoull(hash, &end, 16);
    if (strlen(hash) != 16 || *end) return hv_error_set(HV_ERR_BAD_INPUT, "%s: hash '%s' is not 16 hex digits", what, hash);
    char want[64];
    leaf_key(&l->info, want, sizeof want);
    if (strcmp(key, want) != 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: data '%s' is not its hash's key", what, key);
    if ((s = check_transform(l->info.transform)) != HV_OK) return hv_error_prefix(HV_ERR_BAD_INPUT, "%s: ", what);
    l->info.kind = (hv_leaf_kind)k;
    l->info.size = (size_t)size;
    if (!(l->info.name = hv_strdup(name))) return HV_ERR_NOMEM;
    return leaf_load(model, l, key);
}

/* Nodes of `doc` appended in post-order (children first). */
static hv_status node_from_doc(hv_geometry *g, const json_t *doc, size_t cap, int depth)
{
    if (depth > MAX_DEPTH) return hv_error_set(HV_ERR_BAD_INPUT, KEY ": tree: nested deeper than %d", MAX_DEPTH);
    if (g->nnode >= cap) return hv_error_set(HV_ERR_BAD_INPUT, KEY ": tree: more nodes than its leaves allow");
    hv_geometry_node n = {-1, 0, 0, 0};
    if (json_is_integer(doc)) {
        json_int_t v = json_integer_value(doc);
        if (v < 0 || (size_t)v >= g->nleaf)
            return hv_error_set(HV_ERR_BAD_INPUT, KEY ": tree: leaf %lld, but the record has %zu leaves", (long long)v, g->nleaf);
        n.leaf = (uint32_t)v;
    } else if (json_is_object(doc)) {
        int op;
        hv_status s = hv_json_get_name(doc, "op", KEY ": tree", &k_ops_enum, &op);
        const json_t *a = json_object_get(doc, "a"), *b = json_object_get(doc, "b");
        if (s == HV_OK && (!a || !b)) s = hv_error_set(HV_ERR_BAD_INPUT, KEY ": tree: a '%s' node needs \"a\" and \"b\"", k_ops[op]);
        if (s == HV_OK) s = node_from_doc(g, a, cap, depth + 1);
        n.a = (uint32_t)g->nnode - 1;
        if (s == HV_OK) s = node_from_doc(g, b, cap, depth + 1);
        n.b = (uint32_t)g->nnode - 1;
        if (s != HV_OK) return s;
        if (g->nnode >= cap) return hv_error_set(HV_ERR_BAD_INPUT, KEY ": tree: more nodes than its leaves allow");
        n.op = op;
    } else {
        return hv_error_set(HV_ERR_BAD_INPUT, KEY ": tree: a node is neither a leaf index nor an {\"op\", \"a\", \"b\"} object");
    }
    g->node[g->nnode++] = n;
    return HV_OK;
}

hv_status hv_geometry_read(const hv_volume *model, hv_geometry **out)
{
    *out = NULL;
    if (!hv_geometry_present(model)) return hv_error_set(HV_ERR_NOT_FOUND, "the model records no geometry");
    json_t *doc;
    hv_status s = hv_schema_doc_read(model, HV_DOC_GEOMETRY, &doc);
    if (s != HV_OK) return s;
    const json_t *leaves = NULL, *tree = json_object_get(doc, "tree");
    s = hv_json_need(doc, "leaves", JSON_ARRAY, KEY, &leaves);
    if (s == HV_OK && !tree) s = hv_error_set(HV_ERR_BAD_INPUT, KEY ": tree is missing");
    size_t n = s == HV_OK ? json_array_size(leaves) : 0;
    if (s == HV_OK && n == 0) s = hv_error_set(HV_ERR_BAD_INPUT, KEY ": no leaves");
    /* a tree over n leaf references has at most 2n - 1 nodes; leaves may repeat, so allow more */
    size_t cap = 4 * n + 1024;
    hv_geometry *g = s == HV_OK ? geometry_new(n, cap) : NULL;
    if (s == HV_OK && !g) s = HV_ERR_NOMEM;
    for (size_t i = 0; i < n && s == HV_OK; ++i, ++g->nleaf) s = leaf_from_doc(model, json_array_get(leaves, i), i, &g->leaf[i]);
    if (s == HV_OK) s = node_from_doc(g, tree, cap, 0);
    json_decref(doc);
    if (s != HV_OK) {
        hv_geometry_destroy(g);
        return s;
    }
    *out = g;
    return HV_OK;
}

hv_status hv_geometry_combine_models(const hv_volume *a, const hv_volume *b, hv_geometry_op op, hv_volume *out)
{
    if (!hv_geometry_present(a) || !hv_geometry_present(b)) return hv_geometry_write(NULL, out);
    hv_geometry *ga = NULL, *gb = NULL, *g = NULL;
    hv_status s = hv_geometry_read(a, &ga);
    if (s == HV_OK) s = hv_geometry_read(b, &gb);
    if (s != HV_OK && s != HV_ERR_NOMEM) s = hv_error_prefix(s, "boolean: ");
    if (s == HV_OK) s = hv_geometry_combine(ga, gb, op, &g);
    if (s == HV_OK) s = hv_geometry_write(g, out);
    hv_geometry_destroy(ga);
    hv_geometry_destroy(gb);
    hv_geometry_destroy(g);
    return s;
}
