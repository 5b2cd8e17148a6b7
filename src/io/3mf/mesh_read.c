/* src/mesh/threemf.c - 3MF input: the package is checked here (a ZIP that opens, a model part
 * named by the root relationships, its real expanded size within the memory budget, every
 * material reference resolvable), lib3mf reads it in the bridge plugin (threemf_bridge.cpp),
 * and the build items it delivers become bodies: vertex indices and coordinates checked,
 * transforms and the unit applied. Where lib3mf refuses a file with a message that names no
 * place, the model part is scanned again to name the object, triangle or vertex. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <zip.h>

#include "core/internal.h"
#include "core/plugin.h"
#include "io/io_internal.h"
#include "lib3mf_bridge.h"

#define TMF_MAX_RELS ((zip_uint64_t)1 << 20)
#define TMF_MODEL_REL "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"

/* ---- the plugin -------------------------------------------------------------------------- */

static hv_plugin g_3mf_plugin = HV_PLUGIN_DEF("hovox-3mf", HV_3MF_ENTRY, HV_3MF_ABI, "the lib3mf bridge");
#define g_api ((const hv_3mf_api *)g_3mf_plugin.api)

/* ---- a small XML tag scanner (relationships, and the checks lib3mf does not make) ---------- */

typedef struct xml_scan {
    const char *p, *end;
} xml_scan;

typedef struct xml_tag {
    const char *name; /* local name (after any prefix) */
    size_t nlen;
    const char *attrs, *aend;
    int close, empty;
} xml_tag;

static const char *find(const char *p, const char *end, const char *what)
{
    size_t n = strlen(what);
    while (p < end && (size_t)(end - p) >= n) {
        const char *q = memchr(p, what[0], (size_t)(end - p));
        if (!q || (size_t)(end - q) < n) return NULL;
        if (memcmp(q, what, n) == 0) return q;
        p = q + 1;
    }
    return NULL;
}

/* The next start or end tag; 0 at the end. Text, comments, processing instructions, CDATA and
 * declarations are skipped. */
static int xml_next(xml_scan *x, xml_tag *t)
{
    for (;;) {
        const char *lt = memchr(x->p, '<', (size_t)(x->end - x->p));
        if (!lt) return 0;
        const char *skip_to = NULL;
        size_t skip_len = 0;
        if (x->end - lt >= 4 && memcmp(lt, "<!--", 4) == 0) skip_to = find(lt + 4, x->end, "-->"), skip_len = 3;
        else if (x->end - lt >= 9 && memcmp(lt, "<![CDATA[", 9) == 0) skip_to = find(lt + 9, x->end, "]]>"), skip_len = 3;
        else if (x->end - lt >= 2 && (lt[1] == '?' || lt[1] == '!')) skip_to = memchr(lt, '>', (size_t)(x->end - lt)), skip_len = 1;
        if (skip_len) {
            if (!skip_to) return 0;
            x->p = skip_to + skip_len;
            continue;
        }
        const char *p = lt + 1;
        t->close = p < x->end && *p == '/';
        if (t->close) ++p;
        const char *ns = p;
        while (p < x->end && *p != '>' && *p != '/' && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') ++p;
        const char *colon = NULL;
        for (const char *q = ns; q < p; ++q)
            if (*q == ':') colon = q;
        t->name = colon ? colon + 1 : ns;
        t->nlen = (size_t)(p - t->name);
        t->attrs = p;
        char quote = 0;
        while (p < x->end && (quote || *p != '>')) {
            if (quote && *p == quote) quote = 0;
            else if (!quote && (*p == '"' || *p == '\'')) quote = *p;
            ++p;
        }
        if (p == x->end) return 0;
        t->aend = p;
        t->empty = p > t->attrs && p[-1] == '/';
        x->p = p + 1;
        return 1;
    }
}

static int tag_is(const xml_tag *t, const char *name) { return t->nlen == strlen(name) && memcmp(t->name, name, t->nlen) == 0; }

/* The value of attribute `key` (unprefixed), 0 when absent. */
static int xml_attr(const xml_tag *t, const char *key, const char **v, size_t *n)
{
    size_t kl = strlen(key);
    const char *p = t->attrs, *e = t->aend;
    while (p < e) {
        while (p < e && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n' || *p == '/')) ++p;
        const char *ks = p;
        while (p < e && *p != '=' && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') ++p;
        const char *ke = p;
        while (p < e && *p != '=') ++p;
        if (p == e) return 0;
        ++p;
        while (p < e && *p != '"' && *p != '\'') ++p;
        if (p == e) return 0;
        char q = *p++;
        const char *vs = p;
        while (p < e && *p != q) ++p;
        if ((size_t)(ke - ks) == kl && memcmp(ks, key, kl) == 0) {
            *v = vs;
            *n = (size_t)(p - vs);
            return 1;
        }
        if (p < e) ++p;
    }
    return 0;
}

/* An attribute that must be an unsigned integer: 1 found, 0 absent, -1 not a number. */
static int xml_uint(const xml_tag *t, const char *key, uint64_t *out, const char **v, size_t *n)
{
    if (!xml_attr(t, key, v, n)) return 0;
    const char *s = *v, *e = s + *n;
    while (s < e && (*s == ' ' || *s == '\t')) ++s;
    while (e > s && (e[-1] == ' ' || e[-1] == '\t')) --e;
    if (s == e) return -1;
    uint64_t x = 0;
    for (; s < e; ++s) {
        if (*s < '0' || *s > '9' || x > UINT32_MAX) return -1;
        x = x * 10 + (uint64_t)(*s - '0');
    }
    if (x > UINT32_MAX) return -1;
    *out = x;
    return 1;
}

/* ---- the package ------------------------------------------------------------------------- */

typedef struct package {
    const char *name;
    zip_source_t *src;
    zip_t *zip;
    char model_path[512]; /* the model part, without the leading '/' */
    zip_int64_t model;    /* its entry */
} package;

static void package_close(package *pk)
{
    if (pk->zip) zip_discard(pk->zip);
    else if (pk->src) zip_source_free(pk->src);
    pk->zip = NULL;
    pk->src = NULL;
}

/* Read entry i whole (keep != NULL) or only count its bytes, stopping past `limit` (HV_ERR_LIMIT).
 * With `props`, *props is set when the text holds "pid" or "p1" (material references) or
 * "component" (components, whose expansion hovox bounds itself). */
static hv_status read_entry(package *pk, zip_uint64_t i, uint64_t limit, hv_buf *keep, int *props, uint64_t *bytes)
{
    const char *en = zip_get_name(pk->zip, i, 0);
    char q[96];
    hv_quote(q, sizeof q, en ? en : "?", en ? strlen(en) : 1);
    zip_file_t *f = zip_fopen_index(pk->zip, i, 0);
    if (!f)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: part '%s' cannot be read (libzip: %s)", pk->name, q,
                            zip_strerror(pk->zip));
    char buf[65536 + 8];
    zip_int64_t n;
    *bytes = 0;
    size_t carry = 0; /* the last bytes of the previous chunk, for a word cut in two */
    hv_status s = HV_OK;
    while ((n = zip_fread(f, buf + carry, sizeof buf - 8)) > 0) {
        *bytes += (uint64_t)n;
        if (*bytes > limit) {
            s = HV_ERR_LIMIT;
            break;
        }
        if (keep) {
            hv_buf_append(keep, buf + carry, (size_t)n);
            if (keep->failed) {
                s = HV_ERR_NOMEM;
                break;
            }
        }
        size_t len = carry + (size_t)n;
        if (props && !*props &&
            (find(buf, buf + len, "pid") || find(buf, buf + len, "p1") || find(buf, buf + len, "component")))
            *props = 1;
        carry = HV_MIN(len, (size_t)8);
        memmove(buf, buf + len - carry, carry);
    }
    if (n < 0)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: part '%s' is damaged (libzip: %s)", pk->name, q, zip_file_strerror(f));
    zip_fclose(f);
    return s;
}

static hv_status package_open(package *pk, const void *data, size_t size, const char *name)
{
    memset(pk, 0, sizeof *pk);
    pk->name = name;
    zip_error_t ze;
    zip_error_init(&ze);
    pk->src = zip_source_buffer_create(data, size, 0, &ze);
    if (!pk->src) {
        zip_error_fini(&ze);
        return HV_ERR_NOMEM;
    }
    pk->zip = zip_open_from_source(pk->src, ZIP_RDONLY, &ze);
    if (!pk->zip) {
        hv_status s = hv_error_set(HV_ERR_BAD_INPUT, "%s: not a 3MF package: not a readable ZIP archive (libzip: %s; truncated?)",
                                   name, zip_error_strerror(&ze));
        zip_error_fini(&ze);
        package_close(pk);
        return s;
    }
    zip_error_fini(&ze);
    /* the model part: the target of the root relationship of type 3dmodel */
    zip_int64_t rels = zip_name_locate(pk->zip, "_rels/.rels", ZIP_FL_NOCASE);
    if (rels < 0) {
        package_close(pk);
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: missing model part: the package has no _rels/.rels naming one", name);
    }
    hv_buf text;
    hv_buf_init(&text);
    uint64_t bytes;
    hv_status s = read_entry(pk, (zip_uint64_t)rels, TMF_MAX_RELS, &text, NULL, &bytes);
    if (s == HV_ERR_LIMIT)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: _rels/.rels is larger than %llu bytes", name, (unsigned long long)TMF_MAX_RELS);
    xml_scan x = {text.data ? text.data : "", text.data ? text.data + text.len : ""};
    xml_tag t;
    int found = 0;
    while (s == HV_OK && !found && xml_next(&x, &t)) {
        const char *v, *target;
        size_t n, tn;
        if (t.close || !tag_is(&t, "Relationship") || !xml_attr(&t, "Type", &v, &n) ||
            n != strlen(TMF_MODEL_REL) || memcmp(v, TMF_MODEL_REL, n) != 0 || !xml_attr(&t, "Target", &target, &tn))
            continue;
        found = 1;
        if (tn && target[0] == '/') ++target, --tn;
        if (tn == 0 || tn >= sizeof pk->model_path) {
            char q[96];
            s = hv_error_set(HV_ERR_BAD_INPUT, "%s: _rels/.rels names the model part '%s', not a part name", name,
                             hv_quote(q, sizeof q, target, tn));
            break;
        }
        memcpy(pk->model_path, target, tn);
        pk->model_path[tn] = '\0';
    }
    hv_buf_free(&text);
    if (s == HV_OK && !found)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: missing model part: _rels/.rels names no 3D model", name);
    if (s == HV_OK && (pk->model = zip_name_locate(pk->zip, pk->model_path, ZIP_FL_NOCASE)) < 0) {
        char q[96];
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: missing model part '/%s' (named by _rels/.rels)", name,
                         hv_quote(q, sizeof q, pk->model_path, strlen(pk->model_path)));
    }
    if (s != HV_OK) package_close(pk);
    return s;
}

/* Every part expanded once, counting its real size (a ZIP's declared sizes may lie): lib3mf
 * holds about one byte per byte of model text and hovox a mesh of the same order, so the
 * expanded package may take half of the memory budget. *props: the model part holds material
 * references. */
static hv_status package_expand(package *pk, uint64_t budget, int *props)
{
    zip_int64_t ne = zip_get_num_entries(pk->zip, 0);
    uint64_t total = 0, limit = budget / 2;
    *props = 0;
    for (zip_int64_t i = 0; i < ne; ++i) {
        uint64_t bytes = 0;
        hv_status s = read_entry(pk, (zip_uint64_t)i, limit - total, NULL, i == pk->model ? props : NULL, &bytes);
        if (s == HV_ERR_LIMIT) {
            char b1[32], b2[32];
            return hv_error_set(HV_ERR_LIMIT, "%s: the package expands to more than %s, half of the memory budget (%s)",
                                pk->name, hv_size_text(b1, sizeof b1, (double)limit),
                                hv_size_text(b2, sizeof b2, (double)budget));
        }
        if (s != HV_OK) return s;
        total += bytes;
    }
    return HV_OK;
}

/* The model part's text, once package_expand has counted it. */
static hv_status package_model(package *pk, uint64_t budget, hv_buf *xml)
{
    uint64_t bytes;
    hv_status s = read_entry(pk, (zip_uint64_t)pk->model, budget / 2, xml, NULL, &bytes);
    return s == HV_ERR_LIMIT ? hv_error_set(HV_ERR_LIMIT, "%s: the model part expands past the memory budget", pk->name) : s;
}

/* ---- the model part: references checked, materials read ---------------------------------
 * lib3mf 1.8 reads the materials extension leniently: a pid that names nothing drops the
 * property, an index past a group's end reads as another entry, and a triangle's p1 without its
 * own pid is ignored (the object's pindex applies). hovox reads the property groups and every
 * object's and triangle's references itself, in one pass over the model part, and matches
 * objects to lib3mf's by their position. The same pass, with geometry on, names the place of
 * what lib3mf refuses without one. */

enum { R_OBJECT = 1, R_BASE, R_COLOR, R_TEXTURE, R_COMPOSITE, R_MULTI, R_OTHER };
static const char *const k_group_tags[] = {"", "object", "basematerials", "colorgroup", "texture2dgroup",
                                           "compositematerials", "multiproperties", "resource"};
static const char *const k_child_tags[] = {"", "", "base", "color", "tex2coord", "composite", "multi", ""};

typedef struct resource {
    int kind;
    uint64_t count; /* entries of a property group */
    size_t first;   /* base materials and colours: their first entry; objects: their position */
} resource;

typedef struct entry {
    char *name;    /* a base material's (NULL: a colour, named by its value) */
    uint32_t rgba;
    int32_t mat;   /* the mesh material, once used; -2 before */
} entry;

typedef struct object_props {
    int32_t dres, dentry; /* default property: resource and entry (dres -1: none) */
    size_t first_ref, nt; /* its triangles' references */
    size_t first_child, nchild; /* components: the objects they place (positions in children) */
    uint64_t id;
} object_props;

typedef struct model_scan {
    const char *name;
    int geometry;  /* also check vertices, triangle indices, components and items */
    hv_names ids;  /* resource ids, as decimal text */
    resource *res;
    size_t rcap;
    entry *entries;
    size_t nent, ecap;
    object_props *objs;
    size_t nobj, ocap;
    int32_t *refs; /* 2 per triangle: resource (-1: none) and entry */
    size_t nref, fcap;
    size_t *children, nchildren, ccap; /* objects placed by components */
    size_t *items, nitem_objs, icap;   /* objects of the build items */
    /* the object being read */
    int in_object;
    char obj_label[160];
    int has_pid;
    uint64_t pid, pindex;
    uint64_t nv, nt, ncomp;
    int group;     /* the property group being read: index into res, or -1 */
    size_t nitems;
} model_scan;

static void scan_free(model_scan *m)
{
    for (size_t i = 0; i < m->nent; ++i) free(m->entries[i].name);
    free(m->entries);
    free(m->objs);
    free(m->refs);
    free(m->children);
    free(m->items);
    free(m->res);
    hv_names_free(&m->ids);
    memset(m, 0, sizeof *m);
}

static int64_t lookup(const model_scan *m, uint64_t id)
{
    char key[24];
    int n = snprintf(key, sizeof key, "%llu", (unsigned long long)id);
    return hv_names_find(&m->ids, key, (size_t)n);
}

static hv_status define(model_scan *m, uint64_t id, int kind)
{
    char key[24];
    int n = snprintf(key, sizeof key, "%llu", (unsigned long long)id);
    int32_t k;
    size_t before = m->ids.n;
    hv_status s = hv_names_intern(&m->ids, key, (size_t)n, &k);
    if (s != HV_OK) return s;
    if (m->ids.n == before)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: resource id %llu is used twice", m->name, (unsigned long long)id);
    if ((s = hv_grow((void **)&m->res, &m->rcap, m->ids.n, sizeof *m->res)) != HV_OK) return s;
    m->res[k].kind = kind;
    m->res[k].count = 0;
    m->res[k].first = m->nent;
    return HV_OK;
}

static int group_kind(const xml_tag *t)
{
    for (int k = R_BASE; k <= R_MULTI; ++k)
        if (tag_is(t, k_group_tags[k])) return k;
    return 0;
}

static hv_status attr_error(const model_scan *m, const char *place, const char *key, const char *v, size_t n)
{
    char q[72];
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: %s '%s' is not an index", m->name, place, key, hv_quote(q, sizeof q, v, n));
}

/* An attribute value with XML's character references decoded (malloc'd). */
static char *xml_text(const char *s, size_t n)
{
    char *out = hv_malloc(4 * n + 1), *o = out;
    if (!out) return NULL;
    for (size_t i = 0; i < n;) {
        if (s[i] == '&') {
            static const char *const named[][2] = {{"lt;", "<"}, {"gt;", ">"}, {"amp;", "&"}, {"quot;", "\""}, {"apos;", "'"}};
            size_t k;
            for (k = 0; k < 5; ++k) {
                size_t l = strlen(named[k][0]);
                if (n - i - 1 >= l && memcmp(s + i + 1, named[k][0], l) == 0) {
                    *o++ = named[k][1][0];
                    i += 1 + l;
                    break;
                }
            }
            if (k < 5) continue;
            if (i + 2 < n && s[i + 1] == '#') { /* &#N; or &#xH; as UTF-8 */
                int hex = s[i + 2] == 'x';
                size_t j = i + 2 + (size_t)hex;
                unsigned long c = 0;
                while (j < n && j - i < 12 && s[j] != ';') {
                    int d = s[j] >= '0' && s[j] <= '9' ? s[j] - '0' : hex && (s[j] | 32) >= 'a' && (s[j] | 32) <= 'f' ? (s[j] | 32) - 'a' + 10 : -1;
                    if (d < 0) break;
                    c = c * (hex ? 16u : 10u) + (unsigned long)d;
                    ++j;
                }
                if (j < n && s[j] == ';' && c > 0 && c < 0x110000) {
                    if (c < 0x80) *o++ = (char)c;
                    else if (c < 0x800) *o++ = (char)(0xC0 | c >> 6), *o++ = (char)(0x80 | (c & 0x3F));
                    else if (c < 0x10000)
                        *o++ = (char)(0xE0 | c >> 12), *o++ = (char)(0x80 | ((c >> 6) & 0x3F)), *o++ = (char)(0x80 | (c & 0x3F));
                    else
                        *o++ = (char)(0xF0 | c >> 18), *o++ = (char)(0x80 | ((c >> 12) & 0x3F)),
                        *o++ = (char)(0x80 | ((c >> 6) & 0x3F)), *o++ = (char)(0x80 | (c & 0x3F));
                    i = j + 1;
                    continue;
                }
            }
        }
        *o++ = s[i++];
    }
    *o = '\0';
    return out;
}

/* "#RRGGBB" or "#RRGGBBAA" (sRGB): 1 and *rgba, else 0. */
static int parse_color(const char *s, size_t n, uint32_t *rgba)
{
    if ((n != 7 && n != 9) || s[0] != '#') return 0;
    uint32_t c = 0;
    for (size_t i = 1; i < n; ++i) {
        char h = (char)(s[i] | 32);
        int d = h >= '0' && h <= '9' ? h - '0' : h >= 'a' && h <= 'f' ? h - 'a' + 10 : -1;
        if (d < 0 || s[i] == ' ') return 0;
        c = c << 4 | (uint32_t)d;
    }
    *rgba = n == 7 ? c << 8 | 0xFF : c;
    return 1;
}

/* An entry of a base material group or colour group. */
static hv_status scan_entry(model_scan *m, const xml_tag *t)
{
    resource *r = &m->res[m->group];
    const char *key = r->kind == R_BASE ? "displaycolor" : "color", *v = "";
    size_t n = 0;
    uint32_t rgba = 0;
    if (!xml_attr(t, key, &v, &n) || !parse_color(v, n, &rgba)) {
        char q[72];
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s %s: %s %llu: %s '%s' is not #RRGGBB or #RRGGBBAA", m->name,
                            k_group_tags[r->kind], m->ids.names[m->group], k_child_tags[r->kind],
                            (unsigned long long)r->count, key, hv_quote(q, sizeof q, v, n));
    }
    hv_status s = hv_grow((void **)&m->entries, &m->ecap, m->nent + 1, sizeof *m->entries);
    if (s != HV_OK) return s;
    entry *e = &m->entries[m->nent];
    e->name = NULL;
    e->rgba = rgba;
    e->mat = -2;
    if (r->kind == R_BASE && xml_attr(t, "name", &v, &n) && n && !(e->name = xml_text(v, n))) return HV_ERR_NOMEM;
    m->nent++;
    r->count++;
    return HV_OK;
}

/* A property reference: pid names a property group defined before, index within it; the
 * resolved (resource, entry) in *res, *ent. */
static hv_status check_ref(const model_scan *m, const char *place, uint64_t pid, const char *key, uint64_t index,
                           int32_t *res, int32_t *ent)
{
    int64_t k = lookup(m, pid);
    if (k < 0)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: pid %llu names no property group (none has that id above it)",
                            m->name, place, (unsigned long long)pid);
    const resource *r = &m->res[k];
    if (r->kind == R_OBJECT)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: pid %llu names an object, not a property group", m->name, place,
                            (unsigned long long)pid);
    if (r->kind != R_OTHER && index >= r->count)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: %s %llu is past the end of %s %llu (%llu entries)", m->name, place,
                            key, (unsigned long long)index, k_group_tags[r->kind], (unsigned long long)pid,
                            (unsigned long long)r->count);
    *res = (int32_t)k;
    *ent = (int32_t)index;
    return HV_OK;
}

static hv_status scan_object(model_scan *m, const xml_tag *t)
{
    const char *v;
    size_t n;
    uint64_t id = 0;
    if (xml_uint(t, "id", &id, &v, &n) <= 0)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: object %zu has no valid id", m->name, m->nobj + 1);
    m->in_object = 1;
    m->nv = m->nt = m->ncomp = 0;
    int len = snprintf(m->obj_label, sizeof m->obj_label, "object %llu", (unsigned long long)id);
    if (xml_attr(t, "name", &v, &n) && n) {
        char q[96];
        snprintf(m->obj_label + len, sizeof m->obj_label - (size_t)len, " '%s'", hv_quote(q, sizeof q, v, n));
    }
    hv_status s = define(m, id, R_OBJECT);
    if (s == HV_OK) s = hv_grow((void **)&m->objs, &m->ocap, m->nobj + 1, sizeof *m->objs);
    if (s != HV_OK) return s;
    m->res[m->ids.n - 1].first = m->nobj;
    object_props *o = &m->objs[m->nobj++];
    o->dres = o->dentry = -1;
    o->first_ref = m->nref;
    o->nt = 0;
    o->first_child = m->nchildren;
    o->nchild = 0;
    o->id = id;
    m->pindex = 0;
    int r = xml_uint(t, "pid", &m->pid, &v, &n);
    if (r < 0) return attr_error(m, m->obj_label, "pid", v, n);
    m->has_pid = r;
    r = xml_uint(t, "pindex", &m->pindex, &v, &n);
    if (r < 0) return attr_error(m, m->obj_label, "pindex", v, n);
    if (m->has_pid) return check_ref(m, m->obj_label, m->pid, "pindex", m->pindex, &o->dres, &o->dentry);
    return HV_OK;
}

static hv_status scan_vertex(model_scan *m, const xml_tag *t)
{
    static const char *const axis[] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
        const char *v;
        size_t n;
        char buf[80], q[72];
        if (!xml_attr(t, axis[a], &v, &n))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: vertex %llu has no %s", m->name, m->obj_label,
                                (unsigned long long)m->nv, axis[a]);
        char *endp = buf;
        float x = 0;
        if (n < sizeof buf) {
            memcpy(buf, v, n);
            buf[n] = '\0';
            x = strtof(buf, &endp);
        }
        if (n >= sizeof buf || n == 0 || endp != buf + n || !isfinite(x))
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: vertex %llu: %s is not a finite number ('%s')", m->name,
                                m->obj_label, (unsigned long long)m->nv, axis[a], hv_quote(q, sizeof q, v, n));
    }
    m->nv++;
    return HV_OK;
}

static hv_status scan_triangle(model_scan *m, const xml_tag *t)
{
    static const char *const corner[] = {"v1", "v2", "v3"}, *const prop[] = {"p1", "p2", "p3"};
    char place[224];
    snprintf(place, sizeof place, "%s: triangle %llu", m->obj_label, (unsigned long long)m->nt);
    const char *v;
    size_t n;
    uint64_t x;
    if (m->geometry)
        for (int c = 0; c < 3; ++c) {
            int r = xml_uint(t, corner[c], &x, &v, &n);
            if (r < 0) return attr_error(m, place, corner[c], v, n);
            if (r == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s has no %s", m->name, place, corner[c]);
            if (x >= m->nv)
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: vertex index %llu out of range (%llu vertices)", m->name,
                                    place, (unsigned long long)x, (unsigned long long)m->nv);
        }
    object_props *o = &m->objs[m->nobj - 1];
    int32_t res = o->dres, ent = o->dentry; /* no property of its own: the object's */
    uint64_t pid = m->pid;
    int r = xml_uint(t, "pid", &pid, &v, &n);
    if (r < 0) return attr_error(m, place, "pid", v, n);
    if (r > 0 && !m->has_pid)
        return hv_error_set(HV_ERR_BAD_INPUT,
                            "%s: %s sets pid %llu but its object sets none (3MF: an object whose triangles "
                            "carry properties names a default pid)",
                            m->name, place, (unsigned long long)pid);
    int has_p1 = 0;
    for (int c = 0; c < 3; ++c) {
        int rp = xml_uint(t, prop[c], &x, &v, &n);
        if (rp < 0) return attr_error(m, place, prop[c], v, n);
        if (rp == 0) continue;
        if (!m->has_pid)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s gives %s but neither it nor its object names a property group (pid)",
                                m->name, place, prop[c]);
        int32_t rc, ec;
        hv_status s = check_ref(m, place, pid, prop[c], x, &rc, &ec);
        if (s != HV_OK) return s;
        if (c == 0) { /* a gradient's material: its first corner's */
            res = rc;
            ent = ec;
            has_p1 = 1;
        }
    }
    if (r > 0 && !has_p1)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s sets pid %llu without p1", m->name, place, (unsigned long long)pid);
    if (!m->geometry) {
        hv_status s = hv_grow((void **)&m->refs, &m->fcap, 2 * (m->nref + 1), sizeof *m->refs);
        if (s != HV_OK) return s;
        m->refs[2 * m->nref] = res;
        m->refs[2 * m->nref + 1] = ent;
        m->nref++;
    }
    o->nt++;
    m->nt++;
    return HV_OK;
}

static hv_status scan_reference(model_scan *m, const xml_tag *t, const char *what)
{
    const char *v;
    size_t n;
    uint64_t id;
    char place[224];
    if (m->in_object) snprintf(place, sizeof place, "%s: component %llu", m->obj_label, (unsigned long long)++m->ncomp);
    else snprintf(place, sizeof place, "build item %zu", ++m->nitems);
    int r = xml_uint(t, "objectid", &id, &v, &n);
    if (r <= 0) return r < 0 ? attr_error(m, place, "objectid", v, n) : hv_error_set(HV_ERR_BAD_INPUT, "%s: %s has no objectid", m->name, place);
    int64_t k = lookup(m, id);
    if (k < 0 || m->res[k].kind != R_OBJECT)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s names object %llu, which is not %s", m->name, place,
                            (unsigned long long)id, what);
    size_t obj = m->res[k].first;
    hv_status s;
    if (m->in_object) {
        if ((s = hv_grow((void **)&m->children, &m->ccap, m->nchildren + 1, sizeof *m->children)) != HV_OK) return s;
        m->children[m->nchildren++] = obj;
        m->objs[m->nobj - 1].nchild++;
    } else {
        if ((s = hv_grow((void **)&m->items, &m->icap, m->nitem_objs + 1, sizeof *m->items)) != HV_OK) return s;
        m->items[m->nitem_objs++] = obj;
    }
    return HV_OK;
}

#define TMF_MAX_DEPTH 256               /* components within components */
#define TMF_MAX_PLACEMENTS 1000000      /* objects placed once components are expanded */

/* What the build items expand to, from the model part alone, before lib3mf reads it: lib3mf
 * 1.8 walks component trees in time proportional to the objects they place (a package of a
 * few kB placing one object 2^30 times takes it minutes) and recursively (a chain of 100,000
 * components overflows its stack). */
static hv_status check_expansion(const model_scan *m, uint64_t max_triangles)
{
    uint64_t *tri = hv_calloc(m->nobj + 1, sizeof *tri), *nodes = hv_calloc(m->nobj + 1, sizeof *nodes);
    int *depth = hv_calloc(m->nobj + 1, sizeof *depth);
    hv_status s = tri && nodes && depth ? HV_OK : HV_ERR_NOMEM;
    const uint64_t cap = UINT64_MAX / 4;
    for (size_t i = 0; i < m->nobj && s == HV_OK; ++i) { /* components name objects above them */
        const object_props *o = &m->objs[i];
        tri[i] = o->nt;
        nodes[i] = 1;
        for (size_t c = 0; c < o->nchild; ++c) {
            size_t k = m->children[o->first_child + c];
            tri[i] = HV_MIN(cap, tri[i] + tri[k]);
            nodes[i] = HV_MIN(cap, nodes[i] + nodes[k]);
            depth[i] = HV_MAX(depth[i], depth[k] + 1);
        }
        if (depth[i] > TMF_MAX_DEPTH)
            s = hv_error_set(HV_ERR_LIMIT, "%s: object %llu nests components deeper than %d levels", m->name,
                             (unsigned long long)o->id, TMF_MAX_DEPTH);
    }
    uint64_t t = 0, n = 0;
    for (size_t i = 0; i < m->nitem_objs && s == HV_OK; ++i) {
        t = HV_MIN(cap, t + tri[m->items[i]]);
        n = HV_MIN(cap, n + nodes[m->items[i]]);
    }
    if (s == HV_OK && n > TMF_MAX_PLACEMENTS)
        s = hv_error_set(HV_ERR_LIMIT, "%s: the build items place objects more than %d times once their components are expanded",
                         m->name, TMF_MAX_PLACEMENTS);
    if (s == HV_OK && t > max_triangles)
        s = hv_error_set(HV_ERR_LIMIT, "%s: the build items hold more than %llu triangles once their components are placed",
                         m->name, (unsigned long long)max_triangles);
    free(tri);
    free(nodes);
    free(depth);
    return s;
}

/* Walk the model part: property groups with their entries, objects with their references,
 * and (geometry) vertices, triangle indices, components and build items, each checked; the
 * first defect is the error. Without geometry, *m keeps the materials (scan_free). */
static hv_status scan_model(model_scan *m, const char *name, const char *xml, size_t len, int geometry)
{
    memset(m, 0, sizeof *m);
    m->name = name;
    m->geometry = geometry;
    m->group = -1;
    hv_names_init(&m->ids);
    xml_scan x = {xml, xml + len};
    xml_tag t;
    hv_status s = HV_OK;
    int in_resources = 0, depth_other = 0;
    while (s == HV_OK && xml_next(&x, &t)) {
        if (tag_is(&t, "resources")) {
            in_resources = !t.close;
            continue;
        }
        if (t.close) {
            if (tag_is(&t, "object")) m->in_object = 0;
            else if (m->group >= 0 && group_kind(&t)) m->group = -1;
            else if (depth_other && --depth_other == 0) m->group = -1;
            continue;
        }
        if (m->group >= 0) { /* inside a property group: its entries */
            if (depth_other) {
                if (!t.empty) ++depth_other;
                continue;
            }
            int kind = m->res[m->group].kind;
            if (!tag_is(&t, k_child_tags[kind])) continue;
            if (kind == R_BASE || kind == R_COLOR) s = scan_entry(m, &t);
            else m->res[m->group].count++;
            continue;
        }
        if (tag_is(&t, "object")) {
            s = scan_object(m, &t);
            if (t.empty) m->in_object = 0;
        } else if (m->in_object && tag_is(&t, "vertex")) {
            if (geometry) s = scan_vertex(m, &t);
            else m->nv++;
        } else if (m->in_object && tag_is(&t, "triangle")) {
            s = scan_triangle(m, &t);
        } else if (m->in_object && tag_is(&t, "component")) {
            s = scan_reference(m, &t, "an object defined above it");
        } else if (!m->in_object && tag_is(&t, "item")) {
            s = scan_reference(m, &t, "an object of the resources");
        } else if (in_resources && !m->in_object) {
            const char *v;
            size_t n;
            uint64_t id;
            int kind = group_kind(&t);
            if (xml_uint(&t, "id", &id, &v, &n) <= 0) continue;
            if ((s = define(m, id, kind ? kind : R_OTHER)) != HV_OK) break;
            if (!t.empty) {
                m->group = (int)(m->ids.n - 1);
                depth_other = kind ? 0 : 1;
            }
        }
    }
    if (s != HV_OK || geometry) scan_free(m);
    return s;
}

/* ---- the items lib3mf delivers ------------------------------------------------------------ */

typedef struct tmf_build {
    const char *name;
    model_scan *props; /* the materials read from the model part, or NULL: none */
    double scale;      /* model unit to mm */
    float *soup;
    int32_t *fmat;
    size_t nf, scap, mcap;
    int any_material;
    hv_mesh_body *bodies;
    size_t nb, bcap;
    hv_names mats;
    uint32_t *rgba;
    size_t rcap;
    float *placed; /* one instance's vertices, placed */
    size_t pcap;
    hv_status failed;
} tmf_build;

/* The mesh material of a property reference (-1: none, or one that is not a material). */
static int32_t material_of(tmf_build *b, int32_t res, int32_t ent, hv_status *s)
{
    *s = HV_OK;
    if (res < 0) return -1;
    const resource *r = &b->props->res[res];
    if (r->kind != R_BASE && r->kind != R_COLOR) return -1; /* textures, composites, ...: no material */
    entry *e = &b->props->entries[r->first + (size_t)ent];
    if (e->mat >= 0) return e->mat;
    char col[10];
    const char *name = e->name;
    if (!name) { /* a colour is named by its value */
        if ((e->rgba & 0xFF) == 0xFF) snprintf(col, sizeof col, "#%06x", (unsigned)(e->rgba >> 8));
        else snprintf(col, sizeof col, "#%08x", (unsigned)e->rgba);
        name = col;
    }
    size_t before = b->mats.n;
    *s = hv_names_intern(&b->mats, name, strlen(name), &e->mat);
    if (*s == HV_OK && b->mats.n != before && (*s = hv_grow((void **)&b->rgba, &b->rcap, b->mats.n, sizeof *b->rgba)) == HV_OK)
        b->rgba[e->mat] = e->rgba; /* base materials of the same name are one material: the first colour */
    return *s == HV_OK ? e->mat : -1;
}

/* Drop the current body when it holds no facet (an object with an empty mesh). */
static void close_body(tmf_build *b)
{
    if (b->nb && b->bodies[b->nb - 1].facet_count == 0) free((char *)b->bodies[--b->nb].name);
}

static int sink_begin(void *ctx, int unit, size_t objects)
{
    static const double k_mm[] = {0.001, 1.0, 10.0, 25.4, 304.8, 1000.0}; /* lib3mf's units */
    tmf_build *b = ctx;
    if (unit < 0 || unit > 5)
        return b->failed = hv_error_set(HV_ERR_BAD_INPUT, "%s: unknown unit (lib3mf unit %d)", b->name, unit);
    b->scale = k_mm[unit];
    if (b->props && b->props->nobj != objects)
        return b->failed = hv_error_set(HV_ERR_BAD_INPUT,
                                        "%s: lib3mf reads %zu objects where the model part holds %zu: their "
                                        "materials cannot be matched",
                                        b->name, objects, b->props->nobj);
    return HV_OK;
}

static int sink_item(void *ctx, size_t item, size_t object, const char *name)
{
    tmf_build *b = ctx;
    (void)item;
    close_body(b);
    hv_status s = hv_grow((void **)&b->bodies, &b->bcap, b->nb + 1, sizeof *b->bodies);
    char *copy = s == HV_OK ? hv_strdup(name) : NULL;
    if (!copy) return b->failed = HV_ERR_NOMEM;
    hv_mesh_body *body = &b->bodies[b->nb++];
    body->name = copy;
    body->material = HV_MESH_NO_MATERIAL; /* its object's default, else its facets' majority */
    body->first_facet = b->nf;
    body->facet_count = 0;
    if (b->props) {
        const object_props *o = &b->props->objs[object];
        body->material = material_of(b, o->dres, o->dentry, &s);
        if (s != HV_OK) return b->failed = s;
    }
    return HV_OK;
}

static int sink_instance(void *ctx, const hv_3mf_instance *in)
{
    tmf_build *b = ctx;
    char where[256];
    if (in->object_name[0]) snprintf(where, sizeof where, "object '%.160s' (build item %zu)", in->object_name, in->item + 1);
    else snprintf(where, sizeof where, "the object of build item %zu", in->item + 1);
    const object_props *so = b->props ? &b->props->objs[in->object] : NULL;
    if (so && so->nt != in->nt)
        return b->failed = hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: lib3mf reads %zu triangles where the model part holds %zu",
                                        b->name, where, in->nt, so->nt);
    for (int k = 0; k < 12; ++k)
        if (!isfinite(in->transform[k]))
            return b->failed = hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: its transform has a non-finite entry", b->name, where);
    hv_status s = hv_grow((void **)&b->placed, &b->pcap, 3 * in->nv, sizeof *b->placed);
    if (s == HV_OK) s = hv_grow((void **)&b->soup, &b->scap, 9 * (b->nf + in->nt), sizeof *b->soup);
    if (s == HV_OK) s = hv_grow((void **)&b->fmat, &b->mcap, b->nf + in->nt, sizeof *b->fmat);
    if (s != HV_OK) return b->failed = s;
    const double *T = in->transform;
    for (size_t v = 0; v < in->nv; ++v) {
        const float *p = in->xyz + 3 * v;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            return b->failed = hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: vertex %zu has a non-finite coordinate", b->name, where, v);
        for (int r = 0; r < 3; ++r) {
            double x = (T[4 * r] * p[0] + T[4 * r + 1] * p[1] + T[4 * r + 2] * p[2] + T[4 * r + 3]) * b->scale;
            float fx = (float)x;
            if (!isfinite(fx))
                return b->failed = hv_error_set(HV_ERR_BAD_INPUT,
                                                "%s: %s: vertex %zu leaves the float range once placed (%g)", b->name,
                                                where, v, x);
            b->placed[3 * v + (size_t)r] = fx;
        }
    }
    for (size_t t = 0; t < in->nt; ++t) {
        float *dst = b->soup + 9 * (b->nf + t);
        for (int c = 0; c < 3; ++c) {
            uint32_t i = in->tri[3 * t + (size_t)c];
            if (i >= in->nv)
                return b->failed = hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: triangle %zu: vertex index %u out of range (%zu vertices)",
                                                b->name, where, t, i, in->nv);
            memcpy(dst + 3 * c, b->placed + 3 * (size_t)i, 3 * sizeof(float));
        }
        int32_t mat = -1;
        if (so) {
            const int32_t *ref = b->props->refs + 2 * (so->first_ref + t);
            if ((mat = material_of(b, ref[0], ref[1], &s)) < 0 && s != HV_OK) return b->failed = s;
        }
        b->fmat[b->nf + t] = mat;
        if (mat >= 0) b->any_material = 1;
    }
    b->nf += in->nt;
    b->bodies[b->nb - 1].facet_count += in->nt;
    return HV_OK;
}

static void build_free(tmf_build *b)
{
    for (size_t i = 0; i < b->nb; ++i) free((char *)b->bodies[i].name);
    free(b->bodies);
    free(b->soup);
    free(b->fmat);
    free(b->rgba);
    free(b->placed);
    hv_names_free(&b->mats);
}

static hv_status finish(tmf_build *b, const hv_3mf_info *info, hv_mesh **out)
{
    close_body(b);
    if (b->nb == 0)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: no build item places a mesh (%zu items%s)", b->name, info->items,
                            info->skipped_items ? ", those of support and other objects not read" : "");
    hv_mesh_material *mats = b->mats.n ? hv_calloc(b->mats.n, sizeof *mats) : NULL;
    if (b->mats.n && !mats) return HV_ERR_NOMEM;
    for (size_t k = 0; k < b->mats.n; ++k) {
        mats[k].name = b->mats.names[k];
        mats[k].rgba = b->rgba[k];
        mats[k].has_color = 1;
    }
    hv_status s = hv_mesh_build(b->soup, b->nf, b->name, HV_MESH_3MF, b->bodies, b->nb, mats, b->mats.n,
                                b->any_material ? b->fmat : NULL, out);
    free(mats);
    return s;
}

/* ---- reading ----------------------------------------------------------------------------- */

/* lib3mf refused the package: name the place when a scan of the model part finds it. */
static hv_status diagnose(const void *data, size_t size, const char *name, const char *lib_message, uint64_t budget)
{
    char msg[1024];
    snprintf(msg, sizeof msg, "%s", lib_message);
    package pk;
    hv_status s = package_open(&pk, data, size, name);
    if (s != HV_OK) return s;
    hv_buf xml;
    hv_buf_init(&xml);
    int props;
    s = package_expand(&pk, budget, &props);
    if (s == HV_OK) s = package_model(&pk, budget, &xml);
    package_close(&pk);
    model_scan m;
    if (s == HV_OK) s = scan_model(&m, name, xml.data ? xml.data : "", xml.len, 1);
    hv_buf_free(&xml);
    if (s != HV_OK) return s;
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: lib3mf: %s", name, msg);
}

hv_status hv_mesh_parse_3mf(const void *data, size_t size, const char *name, hv_mesh **out)
{
    *out = NULL;
    if (size == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: empty file (0 bytes)", name);
    uint64_t budget = hv_memory_budget(0);
    package pk;
    hv_status s = package_open(&pk, data, size, name);
    if (s != HV_OK) return s;
    int refs = 0;
    s = package_expand(&pk, budget, &refs);
    model_scan props;
    int have_props = 0;
    uint64_t max_tri = HV_MIN((uint64_t)INT32_MAX / 3, budget / 128);
    if (s == HV_OK && refs) { /* without pid, p1 or components: no material, one object per item */
        hv_buf xml;
        hv_buf_init(&xml);
        s = package_model(&pk, budget, &xml);
        if (s == HV_OK) s = scan_model(&props, name, xml.data ? xml.data : "", xml.len, 0);
        have_props = s == HV_OK;
        hv_buf_free(&xml);
        if (s == HV_OK) s = check_expansion(&props, max_tri);
    }
    package_close(&pk);
    if (s == HV_OK) {
        const void *api = NULL;
        if (hv_plugin_api(&g_3mf_plugin, &api) != HV_OK)
            s = hv_error_set(HV_ERR_UNSUPPORTED, "%s: reading 3MF needs the lib3mf bridge: %s", name, hv_last_error());
    }
    if (s != HV_OK) {
        if (have_props) scan_free(&props);
        return s;
    }
    tmf_build b;
    memset(&b, 0, sizeof b);
    b.name = name;
    b.props = have_props ? &props : NULL;
    hv_names_init(&b.mats);
    hv_3mf_sink sink = {&b, sink_begin, sink_item, sink_instance};
    hv_3mf_info info;
    int rc = g_api->read(data, size, max_tri, &sink, &info);
    if (b.failed != HV_OK) s = b.failed; /* a sink's own message */
    else if (rc == HV_ERR_BAD_INPUT && info.error_code) s = diagnose(data, size, name, g_api->last_error(), budget);
    else if (rc != HV_OK) s = hv_error_set((hv_status)rc, "%s: %s", name, g_api->last_error());
    if (s == HV_OK) s = finish(&b, &info, out);
    build_free(&b);
    if (have_props) scan_free(&props);
    return s;
}
