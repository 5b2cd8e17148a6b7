/* src/io/3mf/mesh_read.c - 3MF meshes (3MF Core 1.3: chapters 3 "Model", 4 "Object Resources",
 * 5 "Build"; Materials and Properties extension 1.2: base materials, colour groups) read from
 * the start part streamed by the package module (package.c): objects, meshes, components nested
 * with their transforms and build items with theirs, the model unit to millimetres. Every id,
 * index, number and transform is checked where it is read, so each message carries the part,
 * line and column. Build items expand linearly; placements and triangles are bounded before
 * anything is placed. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "hovox/image.h"
#include "io/io_internal.h"
#include "mesh/mesh_internal.h"
#include "package.h"
#include "threemf_internal.h"

#define TMF_MAX_DEPTH 256          /* components within components */
#define TMF_MAX_PLACEMENTS 1000000 /* objects placed once components are expanded */
#define TMF_TRIANGLE_BYTES 128     /* a placed triangle's cost, read and welded (measured: about 100) */
#define TMF_AMPLIFY_FLOOR ((uint64_t)512 << 20)
#define TMF_AMPLIFY_RATIO 256
#define TMF_MAX_LIST HV_MAX_MIX_PARTS /* a composite's base materials, a multiproperties' layers */
#define TMF_MIX_TOLERANCE 1e-4     /* a composite's values sum to 1 within this */

enum { R_OBJECT = 1, R_BASE, R_COLOR, R_TEXTURE, R_COMPOSITE, R_MULTI, R_OTHER, R_TEX2D };
static const char *const k_group_tags[] = {"", "object", "basematerials", "colorgroup", "texture2dgroup",
                                           "compositematerials", "multiproperties", "resource", "texture2d"};
static const char *const k_child_tags[] = {"", "", "base", "color", "tex2coord", "composite", "multi", "", ""};

/* object types (3MF Core 4.1); support and other are not printed as parts */
enum { T_MODEL = 0, T_SOLIDSUPPORT, T_SUPPORT, T_SURFACE, T_OTHER };

typedef struct resource {
    int kind;
    uint64_t count; /* entries of a property group */
    size_t first;   /* property groups: their first entry; objects, texture2d: their index */
    int32_t sub;    /* a composite group's base materials (index into res) */
    size_t sfirst, sn; /* in the reader's idx: a composite group's matindices, a multiproperties' layers */
} resource;

typedef struct entry {
    char *name; /* a base material's (NULL: a colour, named by its value) */
    uint32_t rgba; /* a composite's: its bases' display colours mixed by its values */
    int32_t mat; /* the mesh material, once used; -2 before */
    size_t vfirst; /* a composite's values (in vals), a multi's pindices (in idx) */
} entry;

/* A <texture2d>: its image part and how it is addressed (Materials 6). */
typedef struct tex2d {
    char *path; /* the part, without the leading '/' */
    hv_tile tile_u, tile_v;
    hv_filter filter;
    int32_t mesh_index; /* the mesh texture, once added; -1 before, -2 not decodable */
} tex2d;

typedef struct object {
    uint64_t id;
    char *name;
    int type;
    int32_t dres, dentry;  /* default property: resource and entry (dres -1: none) */
    size_t v0, nv, t0, nt; /* its vertices and triangles in the reader's arrays */
    size_t c0, nc;         /* its components */
    uint64_t tri, nodes;   /* triangles and placements once its components are expanded */
    int depth;
} object;

typedef struct component {
    size_t obj;
    double t[12];
    int skip; /* a slicer's config says it places no part (slicer_volumes) */
} component;

typedef struct item {
    size_t obj;
    double t[12];
} item;

typedef enum where { W_TOP = 0, W_RESOURCES, W_GROUP, W_OBJECT, W_MESH, W_VERTICES, W_TRIANGLES, W_COMPONENTS, W_BUILD } where;

typedef struct reader {
    tmf_pkg *pk;
    uint64_t budget, charged;
    double unit; /* model unit to mm */
    const char *unit_name;
    hv_names ids; /* resource ids as decimal text */
    resource *res;
    size_t rcap;
    entry *entries;
    size_t nent, ecap;
    object *objs;
    size_t nobj, ocap;
    float *xyz; /* 3 per vertex */
    size_t nxyz, xcap;
    uint32_t *tri; /* 3 per triangle, object-local vertex indices */
    size_t ntri, tcap;
    int32_t *refs; /* 4 per triangle: resource (-1: none) and the entries of its three corners; NULL
                    * while no triangle has properties of its own (each has its object's default) */
    size_t rfcap;
    tex2d *texs;   /* <texture2d> resources (resource.first indexes them) */
    size_t ntex, txcap;
    double *vals;  /* the values of every composite (normalised to sum 1) */
    size_t nvals, vcap;
    uint32_t *idx; /* matindices of composite groups, layers of multiproperties, pindices of multis */
    size_t nidx, idcap;
    float *uvs;    /* 2 per <tex2coord> of every texture group */
    size_t nuv, uvcap;
    int32_t *texgroup_tex; /* per resource: a texture group's texture (index into texs), else -1 */
    size_t tgcap;
    component *comps;
    size_t ncomp, ccap;
    item *items;
    size_t nitems, icap;
    where at;
    int skip;  /* depth inside an element hovox does not read */
    int group; /* the property group being read (index into res) */
    int has_model, resources_seen, builds;
    const char *vertex_name, *triangle_name; /* "vertex", "triangle" as the parser's dictionary spells them */
    size_t bulk_nv; /* the vertices triangle_item checks indices against (tmf_xml_bulk) */
    char label[200]; /* "object 3 'name'" */
    uint64_t loose_props;  /* triangles with a pid in objects without a default one */
    char loose_first[1400]; /* where the first is */
    char slicer_note[1400]; /* the volumes of a slicer's config not read as parts (slicer_volumes) */
    /* Production extension: objects in other model parts (p:path). The part being read (NULL:
     * the root; ids are then "part|id"), the references of the root waiting for their part, and
     * the root's objects (the others are appended after them). */
    const char *part;
    hv_names parts; /* the other parts named, without the leading '/', in first-named order */
    struct pending *pend;
    size_t npend, pcap;
    size_t nroot;
} reader;

typedef struct pending {
    int is_component;
    int32_t part;   /* into parts */
    size_t index;   /* into comps or items */
    uint64_t id;
    char place[240];
} pending;

/* ---- memory: every array the reader grows is charged to half the memory budget --------------- */

static hv_status grow_to(reader *r, tmf_xml *x, void **p, size_t *cap, size_t need, size_t size);

/* Room for `need` elements; the test inline, as a million vertices and triangles each ask. */
static inline hv_status grow(reader *r, tmf_xml *x, void **p, size_t *cap, size_t need, size_t size)
{
    return need <= *cap ? HV_OK : grow_to(r, x, p, cap, need, size);
}

/* Room for `need` elements, the capacity doubled as often as it takes (so a bulk merge reaches
 * the capacity, and the charge, one element at a time would): HV_OK, HV_ERR_LIMIT (past half the
 * memory budget) or HV_ERR_NOMEM, no message. */
static hv_status room(reader *r, void **p, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap) return HV_OK;
    size_t ncap = *cap ? *cap : 64;
    while (ncap < need) ncap = ncap > SIZE_MAX / 4 ? need : ncap * 2;
    uint64_t more = (uint64_t)(ncap - *cap) * size;
    if (ncap > SIZE_MAX / size || more > r->budget / 2 - HV_MIN(r->charged, r->budget / 2)) return HV_ERR_LIMIT;
    void *q = hv_realloc_big(*p, ncap * size);
    if (!q) return HV_ERR_NOMEM;
    r->charged += more;
    *p = q;
    *cap = ncap;
    return HV_OK;
}

static hv_status grow_to(reader *r, tmf_xml *x, void **p, size_t *cap, size_t need, size_t size)
{
    hv_status s = room(r, p, cap, need, size);
    if (s == HV_ERR_LIMIT) {
        char b[32];
        return tmf_xml_bad(x, HV_ERR_LIMIT, "%s: reading this model needs more than half the memory budget (%s)",
                           r->label[0] ? r->label : "the model", hv_size_text(b, sizeof b, (double)r->budget));
    }
    return s;
}

static void reader_free(reader *r)
{
    free(r->pend);
    hv_names_free(&r->parts);
    for (size_t i = 0; i < r->nent; ++i) free(r->entries[i].name);
    for (size_t i = 0; i < r->nobj; ++i) free(r->objs[i].name);
    for (size_t i = 0; i < r->ntex; ++i) free(r->texs[i].path);
    free(r->texs);
    free(r->vals);
    free(r->idx);
    free(r->uvs);
    free(r->texgroup_tex);
    free(r->entries);
    free(r->objs);
    free(r->xyz);
    free(r->tri);
    free(r->refs);
    free(r->comps);
    free(r->items);
    free(r->res);
    hv_names_free(&r->ids);
}

/* ---- resources and references ------------------------------------------------------------ */

/* A resource's key: its id, prefixed by its model part when that is not the root. */
static int id_key(const char *part, uint64_t id, char *key, size_t size)
{
    int n = part ? snprintf(key, size, "%s|%llu", part, (unsigned long long)id) : snprintf(key, size, "%llu", (unsigned long long)id);
    return HV_MIN(n, (int)size - 1);
}

static int64_t lookup_in(const reader *r, const char *part, uint64_t id)
{
    char key[TMF_MAX_PART_NAME + 24];
    int n = id_key(part, id, key, sizeof key);
    return hv_names_find(&r->ids, key, (size_t)n);
}

static int64_t lookup(const reader *r, uint64_t id) { return lookup_in(r, r->part, id); }

static hv_status define(reader *r, tmf_xml *x, uint64_t id, int kind)
{
    char key[TMF_MAX_PART_NAME + 24];
    int n = id_key(r->part, id, key, sizeof key);
    int32_t k;
    size_t before = r->ids.n;
    hv_status s = hv_names_intern(&r->ids, key, (size_t)n, &k);
    if (s != HV_OK) return s;
    if (r->ids.n == before) return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "resource id %llu is used twice", (unsigned long long)id);
    if ((s = grow(r, x, (void **)&r->res, &r->rcap, r->ids.n, sizeof *r->res)) != HV_OK) return s;
    if ((s = grow(r, x, (void **)&r->texgroup_tex, &r->tgcap, r->ids.n, sizeof *r->texgroup_tex)) != HV_OK) return s;
    r->texgroup_tex[k] = -1;
    r->res[k].kind = kind;
    r->res[k].count = 0;
    r->res[k].first = kind == R_OBJECT ? r->nobj : kind == R_TEX2D ? r->ntex : kind == R_TEXTURE ? r->nuv / 2 : r->nent;
    return HV_OK;
}

static hv_status not_index(tmf_xml *x, const char *place, const tmf_attr *a)
{
    char q[72];
    return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: %s '%s' is not an index", place, a->local, tmf_attr_quote(a, q, sizeof q));
}

/* Extensions hovox does not read, refused by name when a file requires them or uses their
 * geometry (a mesh without its beams or slices would be another part). */
static hv_status unsupported(tmf_xml *x, const char *what, const char *uri)
{
    static const struct {
        const char *uri, *name;
    } known[] = {{TMF_NS_BEAM, "Beam Lattice"}, {TMF_NS_SLICE, "Slice"}, {TMF_NS_PRODUCTION, "Production"},
                 {TMF_NS_SECURE, "Secure Content"}, {TMF_NS_IMPLICIT, "Implicit"}};
    const char *name = NULL;
    for (size_t i = 0; i < HV_COUNT(known) && uri; ++i)
        if (strcmp(uri, known[i].uri) == 0) name = known[i].name;
    if (name)
        return tmf_xml_bad(x, HV_ERR_UNSUPPORTED, "%s the 3MF %s extension (%s), which hovox does not read", what, name, uri);
    return tmf_xml_bad(x, HV_ERR_UNSUPPORTED, "%s the extension %s, which hovox does not read", what, uri ? uri : "?");
}

/* An index attribute: 1 and *v, 0 absent; a bad value is the error. */
static hv_status index_attr(tmf_xml *x, const char *place, const tmf_attr *a, uint64_t *v, int *found)
{
    int rc = tmf_attr_uint(a, UINT32_MAX, v);
    *found = rc > 0;
    return rc < 0 ? not_index(x, place, a) : HV_OK;
}

/* A property reference: pid names a property group defined above, index within it. */
static hv_status check_ref(reader *r, tmf_xml *x, const char *place, uint64_t pid, const char *key, uint64_t index,
                           int32_t *res, int32_t *ent)
{
    int64_t k = lookup(r, pid);
    if (k < 0)
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: pid %llu names no property group (none has that id above it)", place,
                           (unsigned long long)pid);
    const resource *g = &r->res[k];
    if (g->kind == R_OBJECT || g->kind == R_TEX2D)
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: pid %llu names %s, not a property group", place,
                           (unsigned long long)pid, g->kind == R_OBJECT ? "an object" : "a texture2d");
    if (g->kind != R_OTHER && index >= g->count)
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: %s %llu is past the end of %s %llu (%llu entries)", place, key,
                           (unsigned long long)index, k_group_tags[g->kind], (unsigned long long)pid,
                           (unsigned long long)g->count);
    *res = (int32_t)k;
    *ent = (int32_t)index;
    return HV_OK;
}

/* "#RRGGBB" or "#RRGGBBAA" (sRGB): 1 and *rgba, else 0. */
static int parse_color(const char *s, size_t n, uint32_t *rgba)
{
    if ((n != 7 && n != 9) || s[0] != '#') return 0;
    uint32_t c = 0;
    for (size_t i = 1; i < n; ++i) {
        char h = (char)(s[i] | 32);
        int d = h >= '0' && h <= '9' ? h - '0' : h >= 'a' && h <= 'f' ? h - 'a' + 10 : -1;
        if (d < 0) return 0;
        c = c << 4 | (uint32_t)d;
    }
    *rgba = n == 7 ? c << 8 | 0xFF : c;
    return 1;
}

static char *copy_text(const tmf_attr *a)
{
    char *s = hv_malloc(a->len + 1);
    if (s) {
        memcpy(s, a->value, a->len);
        s[a->len] = '\0';
    }
    return s;
}

static hv_status on_composite(reader *r, tmf_xml *x, const tmf_attr *a, int n, entry *e);
static hv_status on_multi(reader *r, tmf_xml *x, const tmf_attr *a, int n, entry *e);

/* An entry of a property group (base materials and colours keep theirs). */
static hv_status on_entry(reader *r, tmf_xml *x, const tmf_attr *a, int n)
{
    resource *g = &r->res[r->group];
    if (g->kind == R_TEXTURE) { /* u, v: any finite numbers (tiling applies outside [0, 1]) */
        double uv[2];
        static const char *const key[2] = {"u", "v"};
        for (int k = 0; k < 2; ++k)
            if (tmf_attr_double(tmf_attr_find(a, n, key[k], NULL), &uv[k]) <= 0)
                return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "texture2dgroup %s: tex2coord %llu: %s is missing or not a finite number",
                                   r->ids.names[r->group], (unsigned long long)g->count, key[k]);
        hv_status s = grow(r, x, (void **)&r->uvs, &r->uvcap, r->nuv + 2, sizeof *r->uvs);
        if (s != HV_OK) return s;
        r->uvs[r->nuv++] = (float)uv[0];
        r->uvs[r->nuv++] = (float)uv[1];
        g->count++;
        return HV_OK;
    }
    if (g->kind == R_COMPOSITE || g->kind == R_MULTI) {
        hv_status s = grow(r, x, (void **)&r->entries, &r->ecap, r->nent + 1, sizeof *r->entries);
        if (s != HV_OK) return s;
        entry *e = &r->entries[r->nent];
        memset(e, 0, sizeof *e);
        e->mat = -2;
        s = g->kind == R_COMPOSITE ? on_composite(r, x, a, n, e) : on_multi(r, x, a, n, e);
        if (s != HV_OK) return s;
        r->nent++;
        r->res[r->group].count++;
        return HV_OK;
    }
    if (g->kind != R_BASE && g->kind != R_COLOR) {
        g->count++;
        return HV_OK;
    }
    const char *key = g->kind == R_BASE ? "displaycolor" : "color";
    const tmf_attr *c = tmf_attr_find(a, n, key, NULL);
    uint32_t rgba = 0;
    if (!c || !parse_color(c->value, c->len, &rgba)) {
        char q[72];
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s %s: %s %llu: %s '%s' is not #RRGGBB or #RRGGBBAA", k_group_tags[g->kind],
                           r->ids.names[r->group], k_child_tags[g->kind], (unsigned long long)g->count, key,
                           c ? tmf_attr_quote(c, q, sizeof q) : "");
    }
    hv_status s = grow(r, x, (void **)&r->entries, &r->ecap, r->nent + 1, sizeof *r->entries);
    if (s != HV_OK) return s;
    entry *e = &r->entries[r->nent];
    e->name = NULL;
    e->vfirst = 0;
    e->rgba = rgba;
    e->mat = -2;
    const tmf_attr *nm = g->kind == R_BASE ? tmf_attr_find(a, n, "name", NULL) : NULL;
    if (nm && nm->len && !(e->name = copy_text(nm))) return HV_ERR_NOMEM;
    if (g->kind == R_BASE && !e->name) { /* named by its colour, as a colour is */
        char col[10];
        if ((rgba & 0xFF) == 0xFF) snprintf(col, sizeof col, "#%06x", (unsigned)(rgba >> 8));
        else snprintf(col, sizeof col, "#%08x", (unsigned)rgba);
        if (!(e->name = hv_strdup(col))) return HV_ERR_NOMEM;
    }
    r->nent++;
    g->count++;
    return HV_OK;
}

/* A space-separated list of at most TMF_MAX_LIST finite numbers (whole ones in [0, UINT32_MAX] when
 * `whole`): their count, -1 absent or empty or not such numbers, -2 too many. */
static int num_list(const tmf_attr *a, double *out, int whole)
{
    if (!a) return -1;
    int k = 0;
    for (size_t i = 0; i < a->len;) {
        while (i < a->len && (a->value[i] == ' ' || a->value[i] == '\t' || a->value[i] == '\r' || a->value[i] == '\n')) ++i;
        if (i == a->len) break;
        char buf[64];
        size_t j = i;
        while (j < a->len && !(a->value[j] == ' ' || a->value[j] == '\t' || a->value[j] == '\r' || a->value[j] == '\n')) ++j;
        if (j - i >= sizeof buf) return -1;
        if (k == TMF_MAX_LIST) return -2;
        memcpy(buf, a->value + i, j - i);
        buf[j - i] = '\0';
        char *end;
        double v = strtod(buf, &end);
        if (*end || !isfinite(v) || (whole && (v < 0 || v > UINT32_MAX || v != floor(v) || buf[0] == '-'))) return -1;
        out[k++] = v;
        i = j;
    }
    return k ? k : -1;
}

/* The whole-number list attribute `key` of element `place` into r->idx: *first, *count. */
static hv_status idx_list(reader *r, tmf_xml *x, const char *place, const tmf_attr *a, int n, const char *key,
                          size_t *first, size_t *count)
{
    double v[TMF_MAX_LIST];
    const tmf_attr *at = tmf_attr_find(a, n, key, NULL);
    int k = num_list(at, v, 1);
    char q[96];
    if (k == -2)
        return tmf_xml_bad(x, HV_ERR_LIMIT, "%s: %s lists more than the %d entries hovox reads", place, key, TMF_MAX_LIST);
    if (k < 0)
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: %s '%s' is not a list of indices", place, key,
                           at ? tmf_attr_quote(at, q, sizeof q) : "");
    hv_status s = grow(r, x, (void **)&r->idx, &r->idcap, r->nidx + (size_t)k, sizeof *r->idx);
    if (s != HV_OK) return s;
    *first = r->nidx;
    *count = (size_t)k;
    for (int i = 0; i < k; ++i) r->idx[r->nidx++] = (uint32_t)v[i];
    return HV_OK;
}

/* A <compositematerials>' matid (base materials defined above) and matindices (within them), or
 * a <multiproperties>' pids (property groups defined above, a material layer only first). */
static hv_status group_header(reader *r, tmf_xml *x, uint64_t id, const tmf_attr *a, int n)
{
    resource *g = &r->res[r->ids.n - 1];
    char place[80];
    snprintf(place, sizeof place, "%s %llu", k_group_tags[g->kind], (unsigned long long)id);
    if (g->kind == R_COMPOSITE) {
        uint64_t mid = 0;
        const tmf_attr *m = tmf_attr_find(a, n, "matid", NULL);
        int64_t k = tmf_attr_uint(m, UINT32_MAX, &mid) > 0 ? lookup(r, mid) : -1;
        if (k < 0 || r->res[k].kind != R_BASE) {
            char q[72];
            return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: matid '%s' names no basematerials defined above it", place,
                               m ? tmf_attr_quote(m, q, sizeof q) : "");
        }
        hv_status s = idx_list(r, x, place, a, n, "matindices", &g->sfirst, &g->sn);
        g = &r->res[r->ids.n - 1];
        g->sub = (int32_t)k;
        for (size_t i = 0; i < g->sn && s == HV_OK; ++i)
            if (r->idx[g->sfirst + i] >= r->res[k].count)
                return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: matindices: %u is past the end of basematerials %llu (%llu entries)",
                                   place, r->idx[g->sfirst + i], (unsigned long long)mid,
                                   (unsigned long long)r->res[k].count);
        return s;
    }
    if (g->kind != R_MULTI) return HV_OK;
    size_t first, cnt;
    hv_status s = idx_list(r, x, place, a, n, "pids", &first, &cnt);
    for (size_t i = 0; i < cnt && s == HV_OK; ++i) {
        int64_t k = lookup(r, r->idx[first + i]);
        int kind = k >= 0 ? r->res[k].kind : 0;
        if (kind != R_BASE && kind != R_COMPOSITE && kind != R_COLOR && kind != R_TEXTURE)
            return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: pids: %u names no basematerials, compositematerials, colorgroup or "
                               "texture2dgroup defined above it", place, r->idx[first + i]);
        if (i > 0 && (kind == R_BASE || kind == R_COMPOSITE))
            return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: pids: %s %u is layer %zu; a material layer may only be the first "
                               "(Materials 5.1)", place, k_group_tags[kind], r->idx[first + i], i + 1);
        r->idx[first + i] = (uint32_t)k; /* kept as the resource's index */
    }
    g = &r->res[r->ids.n - 1];
    g->sfirst = first;
    g->sn = cnt;
    return s;
}

/* A <composite>: its values, one per base material of its group, non-negative, summing to 1
 * (normalised); its display colour the bases' mixed by them. */
static hv_status on_composite(reader *r, tmf_xml *x, const tmf_attr *a, int n, entry *e)
{
    const resource *g = &r->res[r->group];
    double v[TMF_MAX_LIST], sum = 0;
    const tmf_attr *at = tmf_attr_find(a, n, "values", NULL);
    int k = num_list(at, v, 0);
    char q[96];
    for (int i = 0; i < k; ++i) {
        if (v[i] < 0) k = -1;
        else sum += v[i];
    }
    if (k != (int)g->sn)
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "compositematerials %s: composite %llu: values '%s' are not %zu non-negative numbers "
                           "(one per matindices entry)", r->ids.names[r->group], (unsigned long long)g->count,
                           at ? tmf_attr_quote(at, q, sizeof q) : "", g->sn);
    if (!(fabs(sum - 1) <= TMF_MIX_TOLERANCE))
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "compositematerials %s: composite %llu: values '%s' sum to %.9g, not 1",
                           r->ids.names[r->group], (unsigned long long)g->count, tmf_attr_quote(at, q, sizeof q), sum);
    hv_status s = grow(r, x, (void **)&r->vals, &r->vcap, r->nvals + (size_t)k, sizeof *r->vals);
    if (s != HV_OK) return s;
    e->vfirst = r->nvals;
    double c[4] = {0, 0, 0, 0};
    for (int i = 0; i < k; ++i) {
        double f = v[i] / sum;
        r->vals[r->nvals++] = f;
        uint32_t b = r->entries[r->res[g->sub].first + r->idx[g->sfirst + (size_t)i]].rgba;
        for (int ch = 0; ch < 4; ++ch) c[ch] += f * (double)((b >> (24 - 8 * ch)) & 0xFFu);
    }
    e->rgba = 0;
    for (int ch = 0; ch < 4; ++ch) e->rgba = e->rgba << 8 | (uint32_t)HV_MIN(255.0, floor(c[ch] + 0.5));
    return HV_OK;
}

/* A <multi>: its pindices (absent ones 0), each within its layer's group. */
static hv_status on_multi(reader *r, tmf_xml *x, const tmf_attr *a, int n, entry *e)
{
    const resource *g = &r->res[r->group];
    char place[80];
    snprintf(place, sizeof place, "multiproperties %s: multi %llu", r->ids.names[r->group], (unsigned long long)g->count);
    size_t first = r->nidx, cnt = 0;
    hv_status s = tmf_attr_find(a, n, "pindices", NULL) ? idx_list(r, x, place, a, n, "pindices", &first, &cnt) : HV_OK;
    g = &r->res[r->group];
    if (s == HV_OK && cnt > g->sn)
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: pindices has %zu entries, pids %zu", place, cnt, g->sn);
    if (s == HV_OK) s = grow(r, x, (void **)&r->idx, &r->idcap, first + g->sn, sizeof *r->idx);
    if (s != HV_OK) return s;
    for (size_t i = 0; i < g->sn; ++i) {
        if (i >= cnt) r->idx[first + i] = 0;
        const resource *layer = &r->res[r->idx[g->sfirst + i]];
        if (r->idx[first + i] >= layer->count)
            return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: pindices: %u is past the end of %s %s (%llu entries)", place,
                               r->idx[first + i], k_group_tags[layer->kind], r->ids.names[r->idx[g->sfirst + i]],
                               (unsigned long long)layer->count);
    }
    r->nidx = first + g->sn;
    e->vfirst = first;
    return HV_OK;
}

static hv_status on_object(reader *r, tmf_xml *x, const tmf_attr *a, int n)
{
    uint64_t id = 0;
    if (tmf_attr_uint(tmf_attr_find(a, n, "id", NULL), UINT32_MAX, &id) <= 0)
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "object %zu has no valid id", r->nobj + 1);
    const tmf_attr *nm = tmf_attr_find(a, n, "name", NULL);
    int len = snprintf(r->label, sizeof r->label, "object %llu", (unsigned long long)id);
    if (nm && nm->len) {
        char q[96];
        snprintf(r->label + len, sizeof r->label - (size_t)len, " '%s'", tmf_attr_quote(nm, q, sizeof q));
    }
    hv_status s = define(r, x, id, R_OBJECT);
    if (s == HV_OK) s = grow(r, x, (void **)&r->objs, &r->ocap, r->nobj + 1, sizeof *r->objs);
    if (s != HV_OK) return s;
    object *o = &r->objs[r->nobj++];
    memset(o, 0, sizeof *o);
    o->id = id;
    o->dres = o->dentry = -1;
    o->v0 = r->nxyz / 3;
    o->t0 = r->ntri;
    o->c0 = r->ncomp;
    if (nm && nm->len && !(o->name = copy_text(nm))) return HV_ERR_NOMEM;
    for (int i = 0; i < n; ++i)
        if (a[i].uri && strcmp(a[i].uri, TMF_NS_SLICE) == 0) return unsupported(x, "the object's slices are of", a[i].uri);
    const tmf_attr *type = tmf_attr_find(a, n, "type", NULL);
    if (type) {
        static const char *const types[] = {"model", "solidsupport", "support", "surface", "other"};
        o->type = -1;
        for (int k = 0; k < 5; ++k)
            if (type->len == strlen(types[k]) && memcmp(type->value, types[k], type->len) == 0) o->type = k;
        if (o->type < 0) {
            char q[72];
            return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: type '%s' is not one of model, solidsupport, support, surface, other",
                               r->label, tmf_attr_quote(type, q, sizeof q));
        }
    }
    uint64_t pid = 0, pindex = 0;
    int has_pid, has_pindex;
    if ((s = index_attr(x, r->label, tmf_attr_find(a, n, "pid", NULL), &pid, &has_pid)) != HV_OK) return s;
    if ((s = index_attr(x, r->label, tmf_attr_find(a, n, "pindex", NULL), &pindex, &has_pindex)) != HV_OK) return s;
    if (has_pid) return check_ref(r, x, r->label, pid, "pindex", pindex, &o->dres, &o->dentry);
    return HV_OK;
}

/* local is `want`: the parser hands out a name from its dictionary, the same pointer each time,
 * so a million vertices compare a pointer, not a string (issue 26 item 2). */
static inline int named(const char *local, const char **seen, const char *want)
{
    if (local == *seen) return 1;
    if (strcmp(local, want) != 0) return 0;
    *seen = local;
    return 1;
}

/* ---- vertices and triangles in the form every producer writes them -----------------------
 * <vertex x= y= z=/> and <triangle v1= v2= v3=/>, in that order, good values: taken by these
 * alone, on the parser's thread or, for the rest of a large <vertices> or <triangles>, on others
 * (tmf_xml_bulk). Any other form, or a value in error, goes to on_vertex and on_triangle, which
 * read every form and say what is wrong. 1: taken. */
static int vertex_item(const void *arg, const tmf_attr *a, int n, void *out)
{
    (void)arg;
    float *p = out;
    if (n != 3) return 0;
    for (int k = 0; k < 3; ++k)
        if (a[k].local[0] != "xyz"[k] || a[k].local[1] || a[k].len >= 80 || !hv_parse_float(a[k].value, a[k].len, &p[k]) ||
            !isfinite(p[k]))
            return 0;
    return 1;
}

/* arg: the object's vertex count (size_t) */
static int triangle_item(const void *arg, const tmf_attr *a, int n, void *out)
{
    size_t nv = *(const size_t *)arg;
    uint32_t *t = out;
    if (n != 3) return 0;
    for (int c = 0; c < 3; ++c) {
        const char *l = a[c].local;
        uint64_t i = 0;
        if (l[0] != 'v' || l[1] != '1' + c || l[2] || tmf_attr_uint(&a[c], UINT32_MAX, &i) <= 0 || i >= nv) return 0;
        t[c] = (uint32_t)i;
    }
    return 1;
}

/* A bulk piece's vertices, or triangles, where their elements would have put them one by one. */
static int merge_vertices(void *ctx, const void *items, size_t count)
{
    reader *r = ctx;
    if (room(r, (void **)&r->xyz, &r->xcap, r->nxyz + 3 * count, sizeof *r->xyz) != HV_OK) return 0;
    memcpy(r->xyz + r->nxyz, items, 3 * count * sizeof *r->xyz);
    r->nxyz += 3 * count;
    r->objs[r->nobj - 1].nv += count;
    return 1;
}

static int merge_triangles(void *ctx, const void *items, size_t count)
{
    reader *r = ctx; /* once a triangle has properties of its own, each gets its entry: one by one */
    if (r->refs || room(r, (void **)&r->tri, &r->tcap, 3 * (r->ntri + count), sizeof *r->tri) != HV_OK) return 0;
    memcpy(r->tri + 3 * r->ntri, items, 3 * count * sizeof *r->tri);
    r->ntri += count;
    r->objs[r->nobj - 1].nt += count;
    return 1;
}

static const tmf_bulk k_vertices = {"vertex", 3, 3 * sizeof(float), vertex_item, NULL, merge_vertices};

static hv_status on_vertex(reader *r, tmf_xml *x, const tmf_attr *a, int n)
{
    static const char *const axis[] = {"x", "y", "z"};
    hv_status s = grow(r, x, (void **)&r->xyz, &r->xcap, r->nxyz + 3, sizeof *r->xyz);
    if (s != HV_OK) return s;
    object *o = &r->objs[r->nobj - 1];
    if (vertex_item(NULL, a, n, r->xyz + r->nxyz)) {
        r->nxyz += 3;
        o->nv++;
        return HV_OK;
    }
    for (int k = 0; k < 3; ++k) {
        const tmf_attr *v = k < n && a[k].local[0] == axis[k][0] && !a[k].local[1] ? &a[k] : tmf_attr_find(a, n, axis[k], NULL);
        if (!v) return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: vertex %zu has no %s", r->label, o->nv, axis[k]);
        char q[72];
        float f = 0;
        /* not strtof: a decimal parser that gives its floats several times faster (issue 26 item 2) */
        if (v->len >= 80 || !hv_parse_float(v->value, v->len, &f) || !isfinite(f))
            return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: vertex %zu: %s is not a finite number ('%s')", r->label, o->nv,
                               axis[k], tmf_attr_quote(v, q, sizeof q));
        r->xyz[r->nxyz + (size_t)k] = f;
    }
    r->nxyz += 3;
    o->nv++;
    return HV_OK;
}

/* Room for triangle r->ntri's properties; the first time, the triangles before it get their
 * objects' defaults (a million triangles without properties of their own write no 16 MB of
 * them: issue 26 item 2). */
static hv_status own_refs(reader *r, tmf_xml *x)
{
    int first = r->refs == NULL;
    hv_status s = grow(r, x, (void **)&r->refs, &r->rfcap, 4 * (r->ntri + 1), sizeof *r->refs);
    for (size_t i = 0; first && s == HV_OK && i < r->nobj; ++i) {
        const object *o = &r->objs[i];
        for (size_t t = o->t0; t < o->t0 + o->nt; ++t) {
            int32_t *ref = r->refs + 4 * t;
            ref[0] = o->dres;
            ref[1] = ref[2] = ref[3] = o->dentry;
        }
    }
    return s;
}

/* A triangle: corner indices within its object's vertices; its property (pid/p1, else the
 * object's default; a gradient's material is its first corner's). */
static hv_status on_triangle(reader *r, tmf_xml *x, const tmf_attr *a, int n)
{
    static const char *const corner[] = {"v1", "v2", "v3"}, *const prop[] = {"p1", "p2", "p3"};
    object *o = &r->objs[r->nobj - 1];
    char place[240]; /* written when a message needs it (a million triangles need none) */
    hv_status s = grow(r, x, (void **)&r->tri, &r->tcap, 3 * (r->ntri + 1), sizeof *r->tri);
    if (s == HV_OK && !r->refs && triangle_item(&o->nv, a, n, r->tri + 3 * r->ntri)) {
        r->ntri++;
        o->nt++;
        return HV_OK;
    }
    if (s == HV_OK && (r->refs || n > 3)) s = own_refs(r, x);
    if (s != HV_OK) return s;
    for (int c = 0; c < 3; ++c) {
        const char *l = c < n ? a[c].local : "";
        const tmf_attr *v = l[0] == 'v' && l[1] == '1' + c && !l[2] ? &a[c] : tmf_attr_find(a, n, corner[c], NULL);
        uint64_t i = 0;
        int rc = tmf_attr_uint(v, UINT32_MAX, &i);
        if (rc > 0 && i < o->nv) {
            r->tri[3 * r->ntri + (size_t)c] = (uint32_t)i;
            continue;
        }
        snprintf(place, sizeof place, "%s: triangle %zu", r->label, o->nt);
        if (rc < 0) return not_index(x, place, v);
        if (rc == 0) return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s has no %s", place, corner[c]);
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: vertex index %llu out of range (%zu vertices)", place,
                           (unsigned long long)i, o->nv);
    }
    int32_t res = o->dres, ent = o->dentry, ec[3] = {o->dentry, o->dentry, o->dentry};
    if (n > 3) { /* properties of its own */
        snprintf(place, sizeof place, "%s: triangle %zu", r->label, o->nt);
        uint64_t pid = 0, p = 0;
        int has_pid, has_p, has_p1 = 0;
        if ((s = index_attr(x, place, tmf_attr_find(a, n, "pid", NULL), &pid, &has_pid)) != HV_OK) return s;
        if (has_pid && o->dres < 0 && r->loose_props++ == 0) { /* Core 4.1.1 asks producers for a default */
            int line, col;
            tmf_xml_where(x, &line, &col);
            snprintf(r->loose_first, sizeof r->loose_first, "%s: line %d, column %d: %s", tmf_xml_pkg(x)->model, line,
                     col, place);
        }
        if (!has_pid && o->dres >= 0) pid = strtoull(r->ids.names[o->dres], NULL, 10);
        for (int c = 0; c < 3; ++c) {
            if ((s = index_attr(x, place, tmf_attr_find(a, n, prop[c], NULL), &p, &has_p)) != HV_OK) return s;
            if (!has_p) continue;
            if (!has_pid && o->dres < 0)
                return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s gives %s but neither it nor its object names a property group (pid)",
                                   place, prop[c]);
            int32_t rc, e;
            if ((s = check_ref(r, x, place, pid, prop[c], p, &rc, &e)) != HV_OK) return s;
            if (c == 0) res = rc, ent = e, has_p1 = 1, ec[0] = ec[1] = ec[2] = e;
            else ec[c] = e; /* p2, p3: their corners' (absent: p1's) */
        }
        if (has_pid && !has_p1)
            return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s sets pid %llu without p1", place, (unsigned long long)pid);
    }
    (void)ent;
    if (r->refs) {
        int32_t *ref = r->refs + 4 * r->ntri;
        ref[0] = res;
        memcpy(ref + 1, ec, sizeof ec);
    }
    r->ntri++;
    o->nt++;
    return HV_OK;
}

/* A transform attribute (3MF Core 3.3: m00 m01 m02 m10 m11 m12 m20 m21 m22 m30 m31 m32, points as
 * row vectors) as hovox's 3x4 rows; the identity when absent. Finite and not singular. */
static hv_status transform_attr(tmf_xml *x, const char *place, const tmf_attr *a, double *t)
{
    static const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    memcpy(t, id, sizeof id);
    if (!a) return HV_OK;
    double m[12];
    const char *p = a->value, *e = a->value + a->len;
    char buf[512], q[96];
    int k = 0;
    if (a->len < sizeof buf) {
        memcpy(buf, p, a->len);
        buf[a->len] = '\0';
        char *s = buf, *end;
        for (; k < 12; ++k) {
            m[k] = strtod(s, &end);
            if (end == s || !isfinite(m[k])) break;
            s = end;
        }
        while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n') ++s;
        if (k == 12 && *s) k = 13;
    }
    (void)e;
    if (k != 12)
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: transform '%s' is not 12 finite numbers", place, tmf_attr_quote(a, q, sizeof q));
    for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) t[4 * row + col] = m[3 * col + row];
        t[4 * row + 3] = m[9 + row];
    }
    double det = t[0] * (t[5] * t[10] - t[6] * t[9]) - t[1] * (t[4] * t[10] - t[6] * t[8]) + t[2] * (t[4] * t[9] - t[5] * t[8]);
    double scale = 0;
    for (int i = 0; i < 12; ++i)
        if (i % 4 != 3) scale = HV_MAX(scale, fabs(t[i]));
    if (!(fabs(det) > 1e-12 * scale * scale * scale))
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: transform '%s' is singular (determinant %g)", place,
                           tmf_attr_quote(a, q, sizeof q), det);
    return HV_OK;
}

static hv_status on_reference(reader *r, tmf_xml *x, const tmf_attr *a, int n, int is_component)
{
    char place[240];
    if (is_component) snprintf(place, sizeof place, "%s: component %zu", r->label, r->objs[r->nobj - 1].nc + 1);
    else snprintf(place, sizeof place, "build item %zu", r->nitems + 1);
    /* Production extension: p:path names the model part holding the object; another part than
     * this one is refused by name (its object ids are not this part's) */
    const tmf_attr *pp = tmf_attr_find(a, n, "path", TMF_NS_PRODUCTION);
    const char *here = r->part ? r->part : r->pk->model;
    int elsewhere = pp && !(pp->len == strlen(here) + 1 && pp->value[0] == '/' && memcmp(pp->value + 1, here, pp->len - 1) == 0);
    char q[TMF_MAX_PART_NAME + 8];
    if (elsewhere && (r->part || pp->len < 2 || pp->len >= TMF_MAX_PART_NAME || pp->value[0] != '/'))
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s: p:path '%s' %s", place, tmf_attr_quote(pp, q, sizeof q),
                           r->part ? "names another model part: only the root part's may (Production extension 2.1)"
                                   : "is not a part name");
    const tmf_attr *oa = tmf_attr_find(a, n, "objectid", NULL);
    uint64_t id = 0;
    int rc = tmf_attr_uint(oa, UINT32_MAX, &id);
    if (rc <= 0)
        return rc < 0 ? not_index(x, place, oa) : tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s has no objectid", place);
    if (elsewhere) { /* an object of another model part: resolved once that part is read */
        hv_status s = grow(r, x, (void **)&r->pend, &r->pcap, r->npend + 1, sizeof *r->pend);
        if (s != HV_OK) return s;
        pending *p = &r->pend[r->npend];
        if ((s = hv_names_intern(&r->parts, pp->value + 1, pp->len - 1, &p->part)) != HV_OK) return s;
        r->npend++;
        p->is_component = is_component;
        p->index = is_component ? r->ncomp : r->nitems;
        p->id = id;
        snprintf(p->place, sizeof p->place, "%s", place);
    }
    int64_t k = elsewhere ? -2 : lookup(r, id);
    /* a component names an object defined above its own: component graphs have no cycles */
    if (is_component && k >= 0 && r->res[k].kind == R_OBJECT && r->res[k].first == r->nobj - 1)
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s names object %llu, its own object: components may not form a cycle",
                           place, (unsigned long long)id);
    if (k != -2 && (k < 0 || r->res[k].kind != R_OBJECT))
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "%s names object %llu, which is not %s", place, (unsigned long long)id,
                           is_component ? "an object defined above it" : "an object of the resources");
    double t[12];
    hv_status s = transform_attr(x, place, tmf_attr_find(a, n, "transform", NULL), t);
    if (s != HV_OK) return s;
    size_t obj = k == -2 ? SIZE_MAX : r->res[k].first;
    if (is_component) {
        if ((s = grow(r, x, (void **)&r->comps, &r->ccap, r->ncomp + 1, sizeof *r->comps)) != HV_OK) return s;
        r->comps[r->ncomp].obj = obj;
        r->comps[r->ncomp].skip = 0;
        memcpy(r->comps[r->ncomp++].t, t, sizeof t);
        r->objs[r->nobj - 1].nc++;
    } else {
        if ((s = grow(r, x, (void **)&r->items, &r->icap, r->nitems + 1, sizeof *r->items)) != HV_OK) return s;
        r->items[r->nitems].obj = obj;
        memcpy(r->items[r->nitems++].t, t, sizeof t);
    }
    return HV_OK;
}

static hv_status required_extensions(tmf_xml *x, const tmf_attr *req)
{
    char list[1024], q[72];
    if (req->len >= sizeof list)
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "<model> requiredextensions '%s' is too long", tmf_attr_quote(req, q, sizeof q));
    memcpy(list, req->value, req->len);
    list[req->len] = '\0';
    for (char *p = list, *save = NULL, *tok; (tok = strtok_r(p, " \t\r\n", &save)); p = NULL) {
        const char *ns = tmf_xml_lookup_ns(x, tok);
        if (!ns)
            return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "<model> requiredextensions names prefix '%s', which is not declared",
                               hv_quote(q, sizeof q, tok, strlen(tok)));
        /* materials are read; the Volumetric extension's mesh is read here, its volume by hv_3mf_load */
        if (strcmp(ns, TMF_NS_MATERIAL) != 0 && strcmp(ns, TMF_NS_CORE) != 0 && strcmp(ns, TMF_NS_VOLUMETRIC) != 0 &&
            strcmp(ns, TMF_NS_PRODUCTION) != 0) /* Production: objects in other parts (p:path) are read */
            return unsupported(x, "<model> requires", ns);
    }
    return HV_OK;
}

static hv_status on_model(reader *r, tmf_xml *x, const tmf_attr *a, int n)
{
    static const char *const units[] = {"micron", "millimeter", "centimeter", "inch", "foot", "meter"};
    static const double mm[] = {0.001, 1.0, 10.0, 25.4, 304.8, 1000.0};
    r->has_model = 1;
    const tmf_attr *req = tmf_attr_find(a, n, "requiredextensions", NULL);
    hv_status s = req ? required_extensions(x, req) : HV_OK;
    if (s != HV_OK) return s;
    const tmf_attr *u = tmf_attr_find(a, n, "unit", NULL);
    if (!u) return HV_OK;
    for (int k = 0; k < 6; ++k)
        if (u->len == strlen(units[k]) && memcmp(u->value, units[k], u->len) == 0) {
            r->unit = mm[k];
            r->unit_name = units[k];
            return HV_OK;
        }
    char q[72];
    return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "<model> unit '%s' is not one of micron, millimeter, centimeter, inch, foot, meter",
                       tmf_attr_quote(u, q, sizeof q));
}

static int group_kind(const char *local)
{
    for (int k = R_BASE; k <= R_MULTI; ++k)
        if (strcmp(local, k_group_tags[k]) == 0) return k;
    return 0;
}

/* A <texture2d> (Materials 6): path, content type, tile styles, filter. */
static hv_status on_texture2d(reader *r, tmf_xml *x, uint64_t id, const tmf_attr *a, int n)
{
    char q[96];
    const tmf_attr *path = tmf_attr_find(a, n, "path", NULL), *ct = tmf_attr_find(a, n, "contenttype", NULL);
    if (!path || path->len < 2 || path->len >= TMF_MAX_PART_NAME || path->value[0] != '/')
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "texture2d %llu: path '%s' is not a part name", (unsigned long long)id,
                           path ? tmf_attr_quote(path, q, sizeof q) : "");
    /* media types compare without case (RFC 7231 3.1.1.1) */
    int png = ct && ct->len == 9 && strncasecmp(ct->value, "image/png", 9) == 0;
    if (!png && !(ct && ct->len == 10 && strncasecmp(ct->value, "image/jpeg", 10) == 0))
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "texture2d %llu: contenttype '%s' is not image/png or image/jpeg",
                           (unsigned long long)id, ct ? tmf_attr_quote(ct, q, sizeof q) : "");
    hv_status s = define(r, x, id, R_TEX2D);
    if (s == HV_OK) s = grow(r, x, (void **)&r->texs, &r->txcap, r->ntex + 1, sizeof *r->texs);
    if (s != HV_OK) return s;
    tex2d *t = &r->texs[r->ntex];
    memset(t, 0, sizeof *t);
    t->mesh_index = -1;
    static const char *const tiles[] = {"wrap", "mirror", "clamp", "none"};
    static const char *const filters[] = {"auto", "linear", "nearest"};
    const char *keys[3] = {"tilestyleu", "tilestylev", "filter"};
    int val[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        const tmf_attr *v = tmf_attr_find(a, n, keys[k], NULL);
        if (!v) continue;
        const char *const *names = k < 2 ? tiles : filters;
        int nn = k < 2 ? 4 : 3;
        val[k] = -1;
        for (int i = 0; i < nn; ++i)
            if (v->len == strlen(names[i]) && memcmp(v->value, names[i], v->len) == 0) val[k] = i;
        if (val[k] < 0)
            return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "texture2d %llu: %s '%s' is not one of %s", (unsigned long long)id, keys[k],
                               tmf_attr_quote(v, q, sizeof q), k < 2 ? "wrap, mirror, clamp, none" : "auto, linear, nearest");
    }
    t->tile_u = (hv_tile)val[0];
    t->tile_v = (hv_tile)val[1];
    t->filter = (hv_filter)val[2];
    if (!(t->path = hv_malloc(path->len))) return HV_ERR_NOMEM;
    memcpy(t->path, path->value + 1, path->len - 1);
    t->path[path->len - 1] = '\0';
    r->ntex++;
    return HV_OK;
}

/* A <texture2dgroup>'s texid: a <texture2d> defined above. */
static hv_status texgroup_texture(reader *r, tmf_xml *x, uint64_t id, const tmf_attr *a, int n)
{
    uint64_t tid = 0;
    const tmf_attr *t = tmf_attr_find(a, n, "texid", NULL);
    int64_t k = tmf_attr_uint(t, UINT32_MAX, &tid) > 0 ? lookup(r, tid) : -1;
    if (k < 0 || r->res[k].kind != R_TEX2D) {
        char q[72];
        return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "texture2dgroup %llu: texid '%s' names no texture2d defined above it",
                           (unsigned long long)id, t ? tmf_attr_quote(t, q, sizeof q) : "");
    }
    r->texgroup_tex[r->ids.n - 1] = (int32_t)r->res[k].first;
    return HV_OK;
}

static hv_status on_resource(reader *r, tmf_xml *x, const char *local, const char *uri, const tmf_attr *a, int n)
{
    if (uri && strcmp(uri, TMF_NS_SLICE) == 0) return unsupported(x, "<slicestack> is of", uri);
    if (strcmp(local, "object") == 0) {
        r->at = W_OBJECT;
        return on_object(r, x, a, n);
    }
    int kind = group_kind(local);
    uint64_t id;
    r->skip = 1; /* another extension's resource: its id still counts */
    if (tmf_attr_uint(tmf_attr_find(a, n, "id", NULL), UINT32_MAX, &id) <= 0) return HV_OK;
    if (strcmp(local, "texture2d") == 0) return on_texture2d(r, x, id, a, n);
    hv_status s = define(r, x, id, kind ? kind : R_OTHER);
    if (s == HV_OK && kind == R_TEXTURE) s = texgroup_texture(r, x, id, a, n);
    if (s == HV_OK && (kind == R_COMPOSITE || kind == R_MULTI)) s = group_header(r, x, id, a, n);
    if (s == HV_OK && kind) {
        r->skip = 0;
        r->at = W_GROUP;
        r->group = (int)(r->ids.n - 1);
    }
    return s;
}

static hv_status on_start(void *ctx, tmf_xml *x, const char *local, const char *uri, const tmf_attr *a, int n)
{
    (void)uri;
    reader *r = ctx;
    if (r->skip) {
        r->skip++;
        return HV_OK;
    }
    switch (r->at) {
    case W_VERTICES:
        if (named(local, &r->vertex_name, "vertex")) return on_vertex(r, x, a, n);
        break;
    case W_TRIANGLES:
        if (named(local, &r->triangle_name, "triangle")) return on_triangle(r, x, a, n);
        break;
    case W_TOP:
        if (!r->has_model) {
            if (strcmp(local, "model") != 0)
                return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "the root element is <%s>, not a 3MF <model>", local);
            return on_model(r, x, a, n);
        }
        if (strcmp(local, "resources") == 0) {
            if (r->resources_seen++) return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "a second <resources>");
            r->at = W_RESOURCES;
            return HV_OK;
        }
        if (strcmp(local, "build") == 0) {
            if (r->builds++) return tmf_xml_bad(x, HV_ERR_BAD_INPUT, "a second <build>");
            r->at = W_BUILD;
            return HV_OK;
        }
        break;
    case W_RESOURCES: return on_resource(r, x, local, uri, a, n);
    case W_GROUP:
        if (strcmp(local, k_child_tags[r->res[r->group].kind]) == 0) return on_entry(r, x, a, n);
        break;
    case W_OBJECT:
        if (strcmp(local, "mesh") == 0) {
            r->at = W_MESH;
            return HV_OK;
        }
        if (strcmp(local, "components") == 0) {
            r->at = W_COMPONENTS;
            return HV_OK;
        }
        break;
    case W_MESH:
        if (strcmp(local, "vertices") == 0) {
            r->at = W_VERTICES;
            tmf_xml_bulk(x, &k_vertices);
        } else if (strcmp(local, "triangles") == 0) {
            r->at = W_TRIANGLES;
            r->bulk_nv = r->objs[r->nobj - 1].nv; /* fixed while its triangles are read */
            tmf_bulk b = {"triangle", 3, 3 * sizeof(uint32_t), triangle_item, &r->bulk_nv, merge_triangles};
            tmf_xml_bulk(x, &b);
        }
        else if (uri && strcmp(uri, TMF_NS_BEAM) == 0) return unsupported(x, "<beamlattice> is of", uri);
        else break;
        return HV_OK;
    case W_COMPONENTS:
        if (strcmp(local, "component") == 0) return on_reference(r, x, a, n, 1);
        break;
    case W_BUILD:
        if (strcmp(local, "item") == 0) return on_reference(r, x, a, n, 0);
        break;
    }
    r->skip = 1; /* an element hovox does not read, with all inside it */
    return HV_OK;
}

static hv_status on_end(void *ctx, tmf_xml *x, const char *local, const char *uri)
{
    (void)x, (void)local, (void)uri;
    reader *r = ctx;
    if (r->skip) {
        r->skip--;
        return HV_OK;
    }
    static const where up[] = {[W_TOP] = W_TOP,       [W_RESOURCES] = W_TOP,     [W_GROUP] = W_RESOURCES,
                               [W_OBJECT] = W_RESOURCES, [W_MESH] = W_OBJECT,   [W_VERTICES] = W_MESH,
                               [W_TRIANGLES] = W_MESH, [W_COMPONENTS] = W_OBJECT, [W_BUILD] = W_TOP};
    /* the end of an element read at this level (vertex, triangle, entry, component, item) stays */
    if ((r->at == W_VERTICES && named(local, &r->vertex_name, "vertex")) ||
        (r->at == W_TRIANGLES && named(local, &r->triangle_name, "triangle")) ||
        (r->at == W_COMPONENTS && strcmp(local, "component") == 0) || (r->at == W_BUILD && strcmp(local, "item") == 0) ||
        (r->at == W_GROUP && strcmp(local, k_child_tags[r->res[r->group].kind]) == 0) || (r->at == W_TOP))
        return HV_OK;
    if (r->at == W_OBJECT) r->label[0] = '\0';
    r->at = up[r->at];
    return HV_OK;
}

/* ---- expansion: what the build items place, linear in objects and components -------------- */

static hv_status expand_counts(reader *r, const char *name, uint64_t max_tri, uint64_t *placed)
{
    const uint64_t cap = UINT64_MAX / 4;
    /* components name objects above them, or (the root's) objects of other parts, read after it */
    for (size_t j = 0; j < r->nobj; ++j) {
        size_t i = j < r->nobj - r->nroot ? r->nroot + j : j - (r->nobj - r->nroot);
        object *o = &r->objs[i];
        o->tri = o->nt;
        o->nodes = 1;
        for (size_t c = 0; c < o->nc; ++c) {
            const object *k = &r->objs[r->comps[o->c0 + c].obj];
            o->tri = HV_MIN(cap, o->tri + k->tri);
            o->nodes = HV_MIN(cap, o->nodes + k->nodes);
            o->depth = HV_MAX(o->depth, k->depth + 1);
        }
        if (o->depth > TMF_MAX_DEPTH)
            return hv_error_set(HV_ERR_LIMIT, "%s: object %llu nests components deeper than %d levels", name,
                                (unsigned long long)o->id, TMF_MAX_DEPTH);
    }
    uint64_t t = 0, nodes = 0;
    for (size_t i = 0; i < r->nitems; ++i) {
        const object *o = &r->objs[r->items[i].obj];
        if (o->type == T_SUPPORT || o->type == T_OTHER) continue;
        t = HV_MIN(cap, t + o->tri);
        nodes = HV_MIN(cap, nodes + o->nodes);
    }
    if (nodes > TMF_MAX_PLACEMENTS)
        return hv_error_set(HV_ERR_LIMIT, "%s: the build items place objects more than %d times once their components are expanded",
                            name, TMF_MAX_PLACEMENTS);
    if (t > max_tri)
        return hv_error_set(HV_ERR_LIMIT, "%s: the build items hold more than %llu triangles once their components are placed",
                            name, (unsigned long long)max_tri);
    *placed = t;
    return HV_OK;
}

/* Issue 32 item 10: without a memory limit given, a package may not grow by repetition
 * (components, items) beyond 512 MiB or 256 times its own size: a 400 kB file placing a strip
 * 1024 times took 6 GB and a minute. A limit given (--max-memory) allows what it holds. */
static hv_status check_amplification(const reader *r, const char *name, size_t size, uint64_t placed)
{
    uint64_t need = placed * TMF_TRIANGLE_BYTES, allow = HV_MAX(TMF_AMPLIFY_FLOOR, (uint64_t)size * TMF_AMPLIFY_RATIO);
    if (hv_memory_cap() || placed <= r->ntri || need <= allow) return HV_OK;
    char b1[32], b2[32], b3[32];
    return hv_error_set(HV_ERR_LIMIT,
                        "%s: the build items place %llu triangles from %zu stored (repeated by components and items): "
                        "reading them needs about %s, more than a package of %s may expand to without a memory limit "
                        "(%s); give one (--max-memory) to read it",
                        name, (unsigned long long)placed, r->ntri, hv_size_text(b1, sizeof b1, (double)need),
                        hv_size_text(b2, sizeof b2, (double)size), hv_size_text(b3, sizeof b3, (double)allow));
}

typedef struct build {
    reader *r;
    const char *name;
    float *pts;    /* the points placed: each placement's vertices its triangles use, placed */
    size_t npts;
    uint32_t *tri; /* 3 per facet: indices into pts */
    uint32_t *stamp, *slot; /* per vertex of an object: the placement that placed it, and where */
    uint32_t placement;
    int as_read; /* pts and tri are the one object's as read (as_read): not placed, not freed here */
    int32_t *fmat;
    size_t nf;
    int any_material;
    uint32_t *corner; /* 3 per facet: colour-group colours (DESIGN-ROUND: the mesh appearance) */
    float *uv;        /* 6 per facet */
    int32_t *ftex;    /* per facet: a texture (index into texs), -1 none */
    int any_colour, any_texture;
    hv_names mats;
    uint32_t *rgba;
    size_t rcap;
    size_t *mixat; /* per material: its first part in mix and their count (0: not a mixture) */
    size_t mxcap;
    hv_mesh_mix_part *mix;
    size_t nmix, mixcap;
    hv_mesh_body *bodies; /* one per item of a mesh object, one per mesh object an item of
                           * components places (issue 27: an assembly's parts keep their
                           * materials) */
    size_t nb, bcap;
    int32_t item_mat; /* the item's object's default material: its parts' without their own */
} build;

/* A multiproperties' entry as the layer that gives what is asked: its material layer (the
 * first, when base materials or composites), else its first colour layer, else its first texture
 * layer (Materials 5: blending several colour layers is not done); *res -1 when none gives it. */
static void multi_layer(const reader *r, int32_t *res, int32_t *ent, int material)
{
    const resource *g = &r->res[*res];
    const entry *e = &r->entries[g->first + (size_t)*ent];
    int32_t best = -1, at = 0;
    int rank = 0; /* material: 1 a material layer; appearance: 2 a colour layer, 1 a texture layer */
    for (size_t i = 0; i < g->sn; ++i) {
        int32_t k = (int32_t)r->idx[g->sfirst + i];
        int kind = r->res[k].kind;
        int q = material ? kind == R_BASE || kind == R_COMPOSITE : kind == R_COLOR ? 2 : kind == R_TEXTURE ? 1 : 0;
        if (q > rank) {
            rank = q;
            best = k;
            at = (int32_t)r->idx[e->vfirst + i];
        }
    }
    *res = best;
    *ent = at;
}

/* Material k of the build a mixture: the composite's base materials (distinct names, their
 * fractions added) and values. */
static hv_status mix_record(build *b, const resource *g, const entry *e, int32_t k)
{
    const reader *r = b->r;
    hv_status s = hv_grow((void **)&b->mixat, &b->mxcap, 2 * ((size_t)k + 1), sizeof *b->mixat);
    if (s == HV_OK) s = hv_grow((void **)&b->mix, &b->mixcap, b->nmix + g->sn, sizeof *b->mix);
    if (s != HV_OK) return s;
    size_t first = b->nmix;
    for (size_t i = 0; i < g->sn; ++i) {
        const entry *base = &r->entries[r->res[g->sub].first + r->idx[g->sfirst + i]];
        const char *name = base->name;
        double f = r->vals[e->vfirst + i];
        size_t j = first;
        while (j < b->nmix && strcmp(b->mix[j].material, name) != 0) ++j;
        if (j == b->nmix) b->mix[b->nmix++] = (hv_mesh_mix_part){name, 0};
        b->mix[j].fraction += f;
    }
    size_t w = first; /* parts of fraction 0 are no parts */
    for (size_t j = first; j < b->nmix; ++j)
        if (b->mix[j].fraction > 0) b->mix[w++] = b->mix[j];
    b->nmix = w;
    b->mixat[2 * k] = first;
    b->mixat[2 * k + 1] = w - first;
    return HV_OK;
}

/* The mesh material of a property reference (-1: none, or a property that is not a material):
 * a base material, a colour, a composite (a mixture named "composite ID#INDEX"), a multi's
 * material layer. */
static hv_status material_of(build *b, int32_t res, int32_t ent, int32_t *mat)
{
    *mat = -1;
    if (res >= 0 && b->r->res[res].kind == R_MULTI) multi_layer(b->r, &res, &ent, 1);
    if (res < 0) return HV_OK;
    const resource *g = &b->r->res[res];
    if (g->kind != R_BASE && g->kind != R_COLOR && g->kind != R_COMPOSITE) return HV_OK;
    entry *e = &b->r->entries[g->first + (size_t)ent];
    if (e->mat >= 0) {
        *mat = e->mat;
        return HV_OK;
    }
    char col[48];
    const char *name = e->name;
    if (g->kind == R_COMPOSITE) {
        snprintf(col, sizeof col, "composite %s#%d", b->r->ids.names[res], (int)ent);
        name = col;
    } else if (!name) { /* a colour is named by its value */
        if ((e->rgba & 0xFF) == 0xFF) snprintf(col, sizeof col, "#%06x", (unsigned)(e->rgba >> 8));
        else snprintf(col, sizeof col, "#%08x", (unsigned)e->rgba);
        name = col;
    }
    size_t before = b->mats.n;
    hv_status s = hv_names_intern(&b->mats, name, strlen(name), &e->mat);
    if (s == HV_OK && b->mats.n != before && (s = hv_grow((void **)&b->rgba, &b->rcap, b->mats.n, sizeof *b->rgba)) == HV_OK)
        b->rgba[e->mat] = e->rgba; /* base materials of the same name are one material: the first colour */
    if (s == HV_OK && b->mats.n != before && (s = hv_grow((void **)&b->mixat, &b->mxcap, 2 * b->mats.n, sizeof *b->mixat)) == HV_OK) {
        b->mixat[2 * (size_t)e->mat] = b->mixat[2 * (size_t)e->mat + 1] = 0;
        if (g->kind == R_COMPOSITE) s = mix_record(b, g, e, e->mat);
    }
    *mat = e->mat;
    return s;
}

/* Facet b->nf's colours (a colour group: one per corner; base materials and composites: their
 * display colours; a multi: its colour layer, else its texture layer, else its material layer)
 * and texture coordinates (a texture group), corners 1 and 2 swapped as the placement swapped
 * them. */
static void appearance_of(build *b, const int32_t *ref, int flip)
{
    const reader *r = b->r;
    size_t f = b->nf;
    if (!b->corner) return;
    b->ftex[f] = -1;
    memset(b->corner + 3 * f, 0, 3 * sizeof *b->corner);
    memset(b->uv + 6 * f, 0, 6 * sizeof *b->uv);
    if (ref[0] < 0) return;
    for (int c = 0; c < 3; ++c) {
        int32_t res = ref[0], e = ref[1 + (flip && c ? 3 - c : c)];
        if (r->res[res].kind == R_MULTI) {
            int32_t mres = res, me = e;
            multi_layer(r, &res, &e, 0);
            if (res < 0) multi_layer(r, &mres, &me, 1), res = mres, e = me;
            if (res < 0) return;
        }
        const resource *g = &r->res[res];
        if (g->kind == R_COLOR || g->kind == R_BASE || g->kind == R_COMPOSITE) {
            b->corner[3 * f + (size_t)c] = r->entries[g->first + (size_t)e].rgba;
            b->any_colour |= g->kind == R_COLOR;
        } else if (g->kind == R_TEXTURE) {
            memcpy(b->uv + 6 * f + 2 * (size_t)c, r->uvs + 2 * (g->first + (size_t)e), 2 * sizeof(float));
            b->ftex[f] = r->texgroup_tex[res];
            b->any_texture = 1;
        }
    }
}

static void compose(const double *a, const double *b, double *out) /* out = a after b */
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 4; ++j)
            out[4 * i + j] = a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j] + (j == 3 ? a[4 * i + 3] : 0);
    }
}

/* Facet b->nf's material, and the next facet. The materials are written from the first facet
 * that has one (those before it none): a model without them touches no 4 MB of -1s a million facets. */
static void facet_material(build *b, int32_t mat)
{
    if (mat >= 0 && !b->any_material) {
        for (size_t f = 0; f < b->nf; ++f) b->fmat[f] = -1;
        b->any_material = 1;
    }
    if (b->any_material) b->fmat[b->nf] = mat;
    b->nf++;
}

/* The object's triangles placed by t: a vertex is placed once per placement, when a triangle
 * first uses it (vertices no triangle uses cost nothing), so the points never outnumber the
 * corners; hv_mesh_build_indexed welds them into the mesh the corners would give. */
static hv_status place_mesh(build *b, const object *o, const double *t)
{
    reader *r = b->r;
    double det = t[0] * (t[5] * t[10] - t[6] * t[9]) - t[1] * (t[4] * t[10] - t[6] * t[8]) + t[2] * (t[4] * t[9] - t[5] * t[8]);
    int flip = det < 0; /* Core 4.1: a mirror keeps the sign of the volume */
    uint32_t mark = ++b->placement; /* placements are at most TMF_MAX_PLACEMENTS */
    const int32_t dflt[4] = {o->dres, o->dentry, o->dentry, o->dentry}; /* no triangle has properties of its own */
    for (size_t f = 0; f < o->nt && b->as_read; ++f) { /* its points and triangles are there: their properties */
        int32_t mat;
        const int32_t *ref = r->refs ? r->refs + 4 * (o->t0 + f) : dflt;
        hv_status s = material_of(b, ref[0], ref[1], &mat);
        if (s != HV_OK) return s;
        appearance_of(b, ref, 0);
        facet_material(b, mat);
    }
    for (size_t f = 0; f < o->nt && !b->as_read; ++f) {
        const uint32_t *tri = r->tri + 3 * (o->t0 + f);
        uint32_t *dst = b->tri + 3 * b->nf;
        for (int c = 0; c < 3; ++c) {
            uint32_t i = tri[flip && c ? 3 - c : c];
            if (b->stamp[i] != mark) {
                const float *p = r->xyz + 3 * (o->v0 + i);
                float *q = b->pts + 3 * b->npts;
                for (int k = 0; k < 3; ++k) {
                    double v = (t[4 * k] * p[0] + t[4 * k + 1] * p[1] + t[4 * k + 2] * p[2] + t[4 * k + 3]) * r->unit;
                    float fv = (float)v;
                    if (!isfinite(fv))
                        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: triangle %zu leaves the float range once placed (%g)",
                                            b->name, o->name ? o->name : "an object", f, v);
                    q[k] = fv;
                }
                b->stamp[i] = mark;
                b->slot[i] = (uint32_t)b->npts++;
            }
            dst[c] = b->slot[i];
        }
        int32_t mat;
        const int32_t *ref = r->refs ? r->refs + 4 * (o->t0 + f) : dflt;
        hv_status s = material_of(b, ref[0], ref[1], &mat);
        if (s != HV_OK) return s;
        appearance_of(b, ref, flip);
        facet_material(b, mat);
    }
    return HV_OK;
}

/* The facets placed since `first` as a body of their own: named after the mesh object `o` (the
 * mesh makes repeated names unique: "peg", "peg (2)"), in its default material, else the item's,
 * else its facets' majority (hv_mesh_build). */
static hv_status add_body(build *b, const object *o, size_t first)
{
    if (b->nf == first) return HV_OK; /* an object placing no triangle is no body */
    hv_status s = hv_grow((void **)&b->bodies, &b->bcap, b->nb + 1, sizeof *b->bodies);
    if (s != HV_OK) return s;
    int32_t mat;
    if ((s = material_of(b, o->dres, o->dentry, &mat)) != HV_OK) return s;
    hv_mesh_body *body = &b->bodies[b->nb++];
    memset(body, 0, sizeof *body);
    body->name = o->name ? o->name : "";
    body->material = mat >= 0 ? mat : b->item_mat;
    body->first_facet = first;
    body->facet_count = b->nf - first;
    return HV_OK;
}

/* Depth-first over components with an explicit stack (depth is bounded by TMF_MAX_DEPTH); with
 * `split`, each mesh object placed is a body of its own. */
static hv_status place(build *b, size_t obj, const double *t, int split)
{
    typedef struct frame {
        size_t obj, next;
        double t[12];
    } frame;
    frame *stack = hv_malloc((TMF_MAX_DEPTH + 2) * sizeof *stack);
    if (!stack) return HV_ERR_NOMEM;
    int top = 0;
    stack[0].obj = obj;
    stack[0].next = 0;
    memcpy(stack[0].t, t, sizeof stack[0].t);
    size_t first = b->nf;
    hv_status s = place_mesh(b, &b->r->objs[obj], t);
    if (s == HV_OK && split) s = add_body(b, &b->r->objs[obj], first);
    while (s == HV_OK && top >= 0) {
        frame *f = &stack[top];
        const object *o = &b->r->objs[f->obj];
        if (f->next == o->nc) {
            --top;
            continue;
        }
        const component *c = &b->r->comps[o->c0 + f->next++];
        const object *k = &b->r->objs[c->obj];
        /* as an item of them: a support mesh is not filled (Core 4.1: "MUST NOT fill this mesh"),
         * and Core 4.1 expects one as a component of the object it supports; "other" is not output */
        if (k->type == T_SUPPORT || k->type == T_OTHER || c->skip) continue;
        frame *g = &stack[++top];
        g->obj = c->obj;
        g->next = 0;
        compose(f->t, c->t, g->t);
        first = b->nf;
        s = place_mesh(b, &b->r->objs[c->obj], g->t);
        if (s == HV_OK && split) s = add_body(b, &b->r->objs[c->obj], first);
    }
    free(stack);
    return s;
}

/* A texture's image as 8-bit RGBA, row 0 the top (PNG's order). */
/* A <texture2d>'s picture, PNG or JPEG (by its bytes; the one decoder of OBJ textures too,
 * hv_rgba8_decode), as a texture of the mesh. */
static hv_status load_texture(reader *r, const char *name, tex2d *t, hv_mesh *m)
{
    uint8_t *data = NULL;
    size_t size = 0;
    char label[TMF_MAX_PART_NAME + 64];
    snprintf(label, sizeof label, "%s: texture /%s", name, t->path);
    hv_status s = tmf_pkg_read(r->pk, t->path, r->budget / 4, &data, &size);
    hv_rgba8 img;
    memset(&img, 0, sizeof img);
    if (s == HV_OK) s = hv_rgba8_decode(data, size, label, r->budget / 32, &img);
    free(data);
    if (s == HV_OK)
        s = hv_mesh_add_texture(m, t->path, img.rgba, (uint32_t)img.width, (uint32_t)img.height, t->tile_u, t->tile_v,
                                t->filter, &t->mesh_index);
    if (s == HV_OK && img.icc) /* its colours' space (painting converts through it) */
        s = hv_mesh_texture_set_icc(m, (size_t)t->mesh_index, img.icc, img.icc_size);
    hv_rgba8_free(&img);
    return s;
}

/* The colours and textures the facets carry, given to the mesh (hovox/mesh.h, appearance).
 * Facets of a colour-less property keep their material's display colour as corner colours. */
static hv_status set_appearance(build *b, hv_mesh *m)
{
    reader *r = b->r;
    hv_status s = HV_OK;
    for (size_t f = 0; f < b->nf && s == HV_OK; ++f) {
        int32_t t = b->ftex[f];
        if (t < 0) continue;
        if (r->texs[t].mesh_index == -1) s = load_texture(r, b->name, &r->texs[t], m);
        b->ftex[f] = r->texs[t].mesh_index >= 0 ? r->texs[t].mesh_index : -1;
    }
    const hv_mesh_material *mats = NULL;
    int no_colour = 0;
    for (size_t f = 0; f < b->nf && s == HV_OK; ++f) { /* facets without a colour of their own */
        uint32_t *c = b->corner + 3 * f;
        if (c[0] || c[1] || c[2] || b->ftex[f] >= 0) continue;
        int32_t mat = b->any_material ? b->fmat[f] : -1;
        mats = mat >= 0 ? hv_mesh_material_at(m, (size_t)mat) : NULL;
        if (mats && mats->has_color) c[0] = c[1] = c[2] = mats->rgba;
        else if (b->ftex[f] == -1) b->ftex[f] = HV_MESH_NO_COLOUR, no_colour = 1;
    }
    if (s == HV_OK) s = hv_mesh_set_corner_colours(m, b->corner);
    if (s == HV_OK && (hv_mesh_texture_count(m) || no_colour)) s = hv_mesh_set_corner_uvs(m, b->uv, b->ftex);
    return s;
}

/* One build item placing one mesh object as it lies (the identity, bit for bit, in millimetres):
 * its points and triangles as read are what place_mesh would make of them, in another order
 * that hv_mesh_build_indexed's welding and numbering by first use do not see, so they are handed
 * over as they are, not copied (issue 26: a 1M-facet model's points and triangles, 18 MB). The
 * one difference, -0 placed as +0 (p + 0 * q + 0), is made here. */
static int as_read(reader *r)
{
    static const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    if (r->nitems != 1 || r->unit != 1.0 || memcmp(r->items[0].t, id, sizeof id) != 0) return 0;
    const object *o = &r->objs[r->items[0].obj];
    if (o->nc != 0 || o->nt == 0 || o->type == T_SUPPORT || o->type == T_OTHER) return 0;
    float *p = r->xyz + 3 * o->v0;
    for (size_t i = 0; i < 3 * o->nv; ++i)
        if (p[i] == 0) p[i] = 0;
    return 1;
}

static hv_status assemble(reader *r, const char *name, hv_mesh **out)
{
    build b;
    memset(&b, 0, sizeof b);
    b.r = r;
    b.name = name;
    hv_names_init(&b.mats);
    uint64_t nf = 0, skipped = 0;
    size_t maxv = 1;
    for (size_t i = 0; i < r->nobj; ++i) maxv = HV_MAX(maxv, r->objs[i].nv);
    for (size_t i = 0; i < r->nitems; ++i) {
        const object *o = &r->objs[r->items[i].obj];
        if (o->type == T_SUPPORT || o->type == T_OTHER) skipped++;
        else nf += o->tri;
    }
    hv_mesh_item *items = hv_calloc(r->nitems + 1, sizeof *items);
    if ((b.as_read = as_read(r))) {
        const object *o = &r->objs[r->items[0].obj];
        b.pts = r->xyz + 3 * o->v0;
        b.npts = o->nv;
        b.tri = r->tri + 3 * o->t0;
    } else {
        b.pts = hv_malloc_big((size_t)HV_MAX(nf, 1) * 9, sizeof *b.pts); /* pages touched as placed */
        b.tri = hv_malloc_big((size_t)HV_MAX(nf, 1) * 3, sizeof *b.tri);
        b.stamp = hv_calloc(maxv, sizeof *b.stamp);
        b.slot = hv_malloc_array(maxv, sizeof *b.slot);
    }
    b.fmat = hv_malloc_big((size_t)HV_MAX(nf, 1), sizeof *b.fmat);
    int appearance = 0; /* colour or texture groups: the facets' appearance is kept */
    for (size_t k = 0; k < r->ids.n; ++k) appearance |= r->res[k].kind == R_COLOR || r->res[k].kind == R_TEXTURE;
    if (appearance) {
        b.corner = hv_malloc_big((size_t)HV_MAX(nf, 1) * 3, sizeof *b.corner);
        b.uv = hv_malloc_big((size_t)HV_MAX(nf, 1) * 6, sizeof *b.uv);
        b.ftex = hv_malloc_big((size_t)HV_MAX(nf, 1), sizeof *b.ftex);
    }
    hv_status s = items && b.pts && b.tri && ((b.stamp && b.slot) || b.as_read) && b.fmat && (!appearance || (b.corner && b.uv && b.ftex)) ? HV_OK : HV_ERR_NOMEM;
    for (size_t i = 0; i < r->nitems && s == HV_OK; ++i) {
        const object *o = &r->objs[r->items[i].obj];
        items[i].body = -1;
        items[i].object_id = o->id;
        items[i].object_name = o->name ? o->name : "";
        memcpy(items[i].transform, r->items[i].t, sizeof items[i].transform);
        if (o->type == T_SUPPORT || o->type == T_OTHER) continue;
        size_t first = b.nf, nb = b.nb;
        /* its object's default (named first), else its facets' majority; an item of components
         * is a body per mesh object it places, each in its own default, else the item's */
        if ((s = material_of(&b, o->dres, o->dentry, &b.item_mat)) != HV_OK) break;
        s = place(&b, r->items[i].obj, r->items[i].t, o->nc > 0);
        if (s == HV_OK && o->nc == 0) s = add_body(&b, o, first);
        if (s != HV_OK || b.nb == nb) continue; /* an item placing no triangle is no body */
        items[i].body = (int64_t)nb;
        items[i].bodies = b.nb - nb;
    }
    size_t nb = b.nb;
    hv_mesh_body *bodies = b.bodies;
    if (s == HV_OK && nb == 0)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: no build item places a mesh (%zu items%s)", name, r->nitems,
                         skipped ? ", those of support and other objects not read" : "");
    hv_mesh_material *mats = s == HV_OK && b.mats.n ? hv_calloc(b.mats.n, sizeof *mats) : NULL;
    if (s == HV_OK && b.mats.n && !mats) s = HV_ERR_NOMEM;
    for (size_t k = 0; s == HV_OK && k < b.mats.n; ++k) {
        mats[k].name = b.mats.names[k];
        mats[k].rgba = b.rgba[k];
        mats[k].has_color = 1;
        mats[k].nparts = b.mixat[2 * k + 1];
        mats[k].parts = b.mix ? b.mix + b.mixat[2 * k] : NULL; /* no composite: no mix (NULL + 0 is undefined) */
    }
    if (s == HV_OK)
        s = hv_mesh_build_indexed(b.pts, b.npts, b.tri, b.nf, name, HV_MESH_3MF, bodies, nb, mats, b.mats.n,
                                  b.any_material ? b.fmat : NULL, out);
    if (s == HV_OK && (b.any_colour || b.any_texture)) s = set_appearance(&b, *out);
    if (s == HV_OK) s = hv_mesh_set_file_info(*out, r->unit_name ? r->unit_name : "millimeter", items, r->nitems);
    if (s != HV_OK && *out) {
        hv_mesh_destroy(*out);
        *out = NULL;
    }
    free(b.corner);
    free(b.uv);
    free(b.ftex);
    free(mats);
    free(items);
    free(bodies);
    if (!b.as_read) {
        free(b.pts);
        free(b.tri);
    }
    free(b.stamp);
    free(b.slot);
    free(b.fmat);
    free(b.rgba);
    free(b.mixat);
    free(b.mix);
    hv_names_free(&b.mats);
    return s;
}

/* ---- reading ------------------------------------------------------------------------------- */

/* Production extension: the model parts the root's p:paths name, each read once (its ids its
 * own, its build ignored, its unit the root's), then those references resolved. */
static hv_status read_other_parts(reader *r, const char *name, const tmf_xml_handler *h)
{
    r->nroot = r->nobj;
    double unit = r->unit;
    hv_status s = HV_OK;
    for (size_t i = 0; i < r->parts.n && s == HV_OK; ++i) {
        const char *part = r->parts.names[i];
        size_t items = r->nitems;
        r->part = part;
        r->at = W_TOP;
        r->skip = 0;
        r->group = -1;
        r->has_model = r->resources_seen = r->builds = 0;
        s = tmf_xml_parse(r->pk, part, r->pk->inflate_cap, h, r);
        r->nitems = items; /* a part's own build places nothing (Production 2.1) */
        if (s == HV_OK && r->unit != unit)
            s = hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: its unit is not the root model's (%s)", name, part,
                             r->unit_name ? r->unit_name : "millimeter");
    }
    r->part = NULL;
    for (size_t i = 0; i < r->npend && s == HV_OK; ++i) {
        const pending *p = &r->pend[i];
        const char *part = r->parts.names[p->part];
        int64_t k = lookup_in(r, part, p->id);
        if (k < 0 || r->res[k].kind != R_OBJECT)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: %s names object %llu of /%s, which that part does not define",
                                name, r->pk->model, p->place, (unsigned long long)p->id, part);
        if (p->is_component) r->comps[p->index].obj = r->res[k].first;
        else r->items[p->index].obj = r->res[k].first;
    }
    return s;
}

static int by_first(const void *a, const void *b)
{
    uint64_t x = ((const tmf_slicer_volume *)a)->first, y = ((const tmf_slicer_volume *)b)->first;
    return (x > y) - (x < y);
}

/* The root model's object `id` (a mesh or components object), or NULL. */
static object *root_object(reader *r, uint64_t id)
{
    int64_t k = lookup_in(r, NULL, id);
    return k >= 0 && r->res[k].kind == R_OBJECT ? &r->objs[r->res[k].first] : NULL;
}

/* A slicer's volumes (slicer_config.c) that it prints as no part (a negative volume is cut out,
 * which hovox does not do: the note says so; modifiers, support blockers and enforcers are
 * settings regions) are not read: PrusaSlicer's ranges of an object's triangles are dropped
 * before anything is counted, Bambu's components are skipped when placed. An object without a
 * name of its own takes the config's (Bambu's parts: the objects their components place). */
static hv_status slicer_volumes(reader *r, const char *name)
{
    tmf_slicer_config c;
    hv_status s = tmf_slicer_config_read(r->pk, &c);
    if (s != HV_OK) return s;
    if (c.unread[0])
        snprintf(r->slicer_note, sizeof r->slicer_note, "%s (the config is not read: every volume is read as a part)", c.unread);
    for (size_t i = 0; i < c.nnames && s == HV_OK; ++i) {
        object *o = root_object(r, c.names[i].object);
        for (size_t k = 0; o && c.names[i].part && k < o->nc; ++k) { /* Bambu: the part's own object */
            object *p = &r->objs[r->comps[o->c0 + k].obj];
            if (p->id == c.names[i].part && p->nc == 0) {
                o = p;
                break;
            }
        }
        if (o && (!c.names[i].part || o->nc == 0) && !o->name && c.names[i].name[0] &&
            !(o->name = hv_strdup(c.names[i].name)))
            s = HV_ERR_NOMEM;
    }
    uint8_t *drop = NULL;
    size_t dropped = 0, negative = 0, nvol = 0, nrange = 0;
    char first[200] = "";
    for (size_t i = 0; i < c.nvols; ++i) { /* ranges as the reader's triangles, sorted below */
        tmf_slicer_volume *v = &c.vols[i];
        object *o = root_object(r, v->object);
        size_t hit = 0;
        if (v->kind == TMF_VOLUME_PART || !o) continue;
        if (v->part) /* Bambu: the components placing that object */
            for (size_t k = 0; k < o->nc; ++k) {
                component *cp = &r->comps[o->c0 + k];
                if (r->objs[cp->obj].id != v->part || cp->skip) continue;
                cp->skip = 1;
                dropped += r->objs[cp->obj].nt;
                hit = 1;
            }
        else if (o->nc == 0 && v->last < o->nt) { /* PrusaSlicer: a range of a mesh object */
            c.vols[nrange].first = o->t0 + v->first; /* vols[nrange] is at or before v */
            c.vols[nrange++].last = o->t0 + v->last;
            hit = 1;
        }
        if (!hit) continue; /* not this model's */
        negative += v->kind == TMF_VOLUME_NEGATIVE;
        if (nvol++ == 0)
            snprintf(first, sizeof first, "%s '%s' of object %llu", tmf_slicer_volume_kind(v->kind), v->name,
                     (unsigned long long)v->object);
    }
    if (nrange && !(drop = hv_calloc(r->ntri, 1))) s = HV_ERR_NOMEM;
    if (drop) { /* each triangle marked once however the ranges overlap (a config of many volumes) */
        qsort(c.vols, nrange, sizeof *c.vols, by_first);
        uint64_t next = 0;
        for (size_t i = 0; i < nrange; ++i)
            for (uint64_t t = HV_MAX(next, c.vols[i].first); t <= c.vols[i].last; ++t, next = t) drop[t] = 1, ++dropped;
        size_t j = 0; /* keep the others, in order: objects' triangles lie in object order */
        for (size_t i = 0; i < r->nobj; ++i) {
            object *o = &r->objs[i];
            size_t t0 = j;
            for (size_t t = o->t0; t < o->t0 + o->nt; ++t) {
                if (drop[t]) continue;
                memmove(r->tri + 3 * j, r->tri + 3 * t, 3 * sizeof *r->tri);
                if (r->refs) memmove(r->refs + 4 * j, r->refs + 4 * t, 4 * sizeof *r->refs);
                ++j;
            }
            o->t0 = t0;
            o->nt = j - t0;
        }
        r->ntri = j;
    }
    if (nvol && s == HV_OK) {
        char many[64] = "";
        if (nvol > 1) snprintf(many, sizeof many, " and %zu more volume%s", nvol - 1, nvol == 2 ? "" : "s");
        snprintf(r->slicer_note, sizeof r->slicer_note,
                 "%s: %s: the %s%s, no part of the print in %s: %zu triangle%s not read%s", name, c.part, first, many,
                 c.slicer, dropped, dropped == 1 ? "" : "s",
                 negative ? " (a negative volume is not cut out of the parts, as the slicer cuts it)" : "");
    }
    free(drop);
    tmf_slicer_config_free(&c);
    return s;
}

hv_status hv_mesh_parse_3mf(const void *data, size_t size, const char *name, hv_mesh **out)
{
    *out = NULL;
    tmf_pkg pk;
    hv_status s = tmf_pkg_open(&pk, data, size, NULL, name);
    if (s != HV_OK) return s;
    reader r;
    memset(&r, 0, sizeof r);
    r.pk = &pk;
    r.budget = pk.budget;
    r.unit = 1;
    r.group = -1;
    hv_names_init(&r.ids);
    hv_names_init(&r.parts);
    tmf_xml_handler h = {on_start, on_end};
    s = tmf_xml_parse(&pk, pk.model, pk.inflate_cap, &h, &r);
    if (s == HV_OK && !r.resources_seen) s = hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: the model has no <resources>", name, pk.model);
    if (s == HV_OK) s = read_other_parts(&r, name, &h);
    if (s == HV_OK) s = slicer_volumes(&r, name);
    uint64_t max_tri = HV_MIN((uint64_t)INT32_MAX / 3, pk.budget / TMF_TRIANGLE_BYTES);
    uint64_t placed = 0;
    if (s == HV_OK) s = expand_counts(&r, name, max_tri, &placed);
    if (s == HV_OK) s = check_amplification(&r, name, size, placed);
    if (s == HV_OK) s = assemble(&r, name, out);
    if (s == HV_OK && r.loose_props) {
        char note[2048];
        snprintf(note, sizeof note,
                 "%s: %s sets a pid though its object names no default pid (3MF Core 4.1.1 asks producers for one); "
                 "%llu triangle%s so: read with their own properties, the other triangles of such objects with none",
                 name, r.loose_first, (unsigned long long)r.loose_props, r.loose_props == 1 ? "" : "s");
        s = hv_mesh_add_note(*out, note);
        if (s != HV_OK) {
            hv_mesh_destroy(*out);
            *out = NULL;
        }
    }
    if (s == HV_OK && r.slicer_note[0] && (s = hv_mesh_add_note(*out, r.slicer_note)) != HV_OK) {
        hv_mesh_destroy(*out);
        *out = NULL;
    }
    reader_free(&r);
    tmf_pkg_close(&pk);
    return s;
}
