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
#include "mesh_internal.h"
#include "threemf_bridge.h"

#define TMF_MAX_BYTES ((size_t)1 << 40)
#define TMF_MAX_RELS ((zip_uint64_t)1 << 20)
#define TMF_MODEL_REL "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"

/* ---- the plugin -------------------------------------------------------------------------- */

static const hv_3mf_api *g_api;
static hv_status g_api_status = HV_OK;
static char g_api_error[2048];
static pthread_once_t g_api_once = PTHREAD_ONCE_INIT;

static void load_api(void)
{
    void *sym = NULL;
    g_api_status = hv_plugin_symbol("hovox-3mf", HV_3MF_ENTRY, &sym);
    if (g_api_status == HV_OK) {
        g_api = ((hv_3mf_entry_fn)sym)();
        if (!g_api || g_api->abi != HV_3MF_ABI) {
            g_api = NULL;
            g_api_status = hv_error_set(HV_ERR_UNSUPPORTED, "the lib3mf bridge failed to initialise or has a different ABI");
        }
    }
    if (g_api_status != HV_OK) strncpy(g_api_error, hv_last_error(), sizeof g_api_error - 1);
}

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

/* Read entry i whole (keep != NULL) or only count its bytes, stopping past `limit`. */
static hv_status read_entry(package *pk, zip_uint64_t i, uint64_t limit, hv_buf *keep, uint64_t *bytes)
{
    const char *en = zip_get_name(pk->zip, i, 0);
    char q[96];
    hv_quote(q, sizeof q, en ? en : "?", en ? strlen(en) : 1);
    zip_file_t *f = zip_fopen_index(pk->zip, i, 0);
    if (!f)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: part '%s' cannot be read (libzip: %s)", pk->name, q,
                            zip_strerror(pk->zip));
    char buf[65536];
    zip_int64_t n;
    *bytes = 0;
    hv_status s = HV_OK;
    while ((n = zip_fread(f, buf, sizeof buf)) > 0) {
        *bytes += (uint64_t)n;
        if (*bytes > limit) {
            s = HV_ERR_LIMIT;
            break;
        }
        if (keep) {
            hv_buf_append(keep, buf, (size_t)n);
            if (keep->failed) {
                s = HV_ERR_NOMEM;
                break;
            }
        }
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
    hv_status s = read_entry(pk, (zip_uint64_t)rels, TMF_MAX_RELS, &text, &bytes);
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

/* Every part expanded once, counting its real size (a ZIP's declared sizes may lie): the
 * whole must fit the memory budget. The model part is kept when `model` is given. */
static hv_status package_expand(package *pk, uint64_t budget, hv_buf *model)
{
    zip_int64_t ne = zip_get_num_entries(pk->zip, 0);
    uint64_t total = 0;
    for (zip_int64_t i = 0; i < ne; ++i) {
        uint64_t bytes = 0;
        int keep = model && i == pk->model;
        hv_status s = read_entry(pk, (zip_uint64_t)i, budget - total, keep ? model : NULL, &bytes);
        if (s == HV_ERR_LIMIT) {
            char b1[32];
            return hv_error_set(HV_ERR_LIMIT,
                                "%s: the package expands to more than %s, more than reading it may take "
                                "(the memory budget allows %s)",
                                pk->name, hv_size_text(b1, sizeof b1, (double)budget), b1);
        }
        if (s != HV_OK) return s;
        total += bytes;
    }
    return HV_OK;
}

/* ---- checks of the model part ------------------------------------------------------------- */

enum { R_OBJECT = 1, R_BASE, R_COLOR, R_TEXTURE, R_COMPOSITE, R_MULTI, R_OTHER };
static const char *const k_group_tags[] = {"", "object", "basematerials", "colorgroup", "texture2dgroup",
                                           "compositematerials", "multiproperties", "resource"};
static const char *const k_child_tags[] = {"", "", "base", "color", "tex2coord", "composite", "multi", ""};

typedef struct resource {
    int kind;
    uint64_t count; /* entries of a property group */
} resource;

typedef struct model_scan {
    const char *name;
    int geometry;  /* also check vertices, triangle indices, components and items */
    hv_names ids;  /* resource ids, as decimal text */
    resource *res;
    size_t rcap;
    /* the object being read */
    uint64_t obj_id;
    int in_object;
    char obj_label[160];
    int has_pid;
    uint64_t pid;
    uint64_t nv, nt, ncomp;
    int axis_tag;  /* vertices: 1, triangles: 2 */
    int group;     /* the property group being read: index into res, or -1 */
    size_t nitems;
} model_scan;

static const resource *lookup(const model_scan *m, uint64_t id)
{
    char key[24];
    int n = snprintf(key, sizeof key, "%llu", (unsigned long long)id);
    int64_t k = hv_names_find(&m->ids, key, (size_t)n);
    return k < 0 ? NULL : &m->res[k];
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

/* A property reference: pid names a property group defined before, index within it. */
static hv_status check_ref(const model_scan *m, const char *place, uint64_t pid, const char *key, int has_index, uint64_t index)
{
    const resource *r = lookup(m, pid);
    if (!r)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: pid %llu names no property group (none has that id above it)",
                            m->name, place, (unsigned long long)pid);
    if (r->kind == R_OBJECT)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: pid %llu names an object, not a property group", m->name, place,
                            (unsigned long long)pid);
    if (r->kind == R_OTHER || !has_index) return HV_OK;
    if (index >= r->count)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: %s %llu is past the end of %s %llu (%llu entries)", m->name, place,
                            key, (unsigned long long)index, k_group_tags[r->kind], (unsigned long long)pid,
                            (unsigned long long)r->count);
    return HV_OK;
}

static hv_status scan_object(model_scan *m, const xml_tag *t)
{
    const char *v;
    size_t n;
    uint64_t id = 0;
    if (xml_uint(t, "id", &id, &v, &n) <= 0)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: an object has no valid id", m->name);
    m->obj_id = id;
    m->in_object = 1;
    m->nv = m->nt = m->ncomp = 0;
    int len = snprintf(m->obj_label, sizeof m->obj_label, "object %llu", (unsigned long long)id);
    if (xml_attr(t, "name", &v, &n) && n) {
        char q[96];
        snprintf(m->obj_label + len, sizeof m->obj_label - (size_t)len, " '%s'", hv_quote(q, sizeof q, v, n));
    }
    hv_status s = define(m, id, R_OBJECT);
    if (s != HV_OK) return s;
    uint64_t pindex = 0;
    int r = xml_uint(t, "pid", &m->pid, &v, &n);
    if (r < 0) return attr_error(m, m->obj_label, "pid", v, n);
    m->has_pid = r;
    r = xml_uint(t, "pindex", &pindex, &v, &n);
    if (r < 0) return attr_error(m, m->obj_label, "pindex", v, n);
    if (m->has_pid) return check_ref(m, m->obj_label, m->pid, "pindex", r, pindex);
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
            if (r == 0)
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s has no %s", m->name, place, corner[c]);
            if (x >= m->nv)
                return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: vertex index %llu out of range (%llu vertices)", m->name,
                                    place, (unsigned long long)x, (unsigned long long)m->nv);
        }
    uint64_t pid = m->pid;
    int r = xml_uint(t, "pid", &pid, &v, &n), has_pid = m->has_pid || r > 0;
    if (r < 0) return attr_error(m, place, "pid", v, n);
    if (r > 0 && !m->has_pid)
        return hv_error_set(HV_ERR_BAD_INPUT,
                            "%s: %s sets pid %llu but its object sets none (3MF: an object whose triangles "
                            "carry properties names a default pid)",
                            m->name, place, (unsigned long long)pid);
    for (int c = 0; c < 3; ++c) {
        int rp = xml_uint(t, prop[c], &x, &v, &n);
        if (rp < 0) return attr_error(m, place, prop[c], v, n);
        if (rp == 0) continue;
        if (!has_pid)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s gives %s but neither it nor its object names a property group (pid)",
                                m->name, place, prop[c]);
        hv_status s = check_ref(m, place, pid, prop[c], 1, x);
        if (s != HV_OK) return s;
    }
    if (r > 0) {
        hv_status s = check_ref(m, place, pid, "p1", 0, 0);
        if (s != HV_OK) return s;
    }
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
    const resource *res = lookup(m, id);
    if (!res || res->kind != R_OBJECT)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s names object %llu, which is not %s", m->name, place,
                            (unsigned long long)id, what);
    return HV_OK;
}

/* Walk the model part: property groups with their sizes, objects, and (geometry) vertices,
 * triangles, components and build items, each checked; the first defect is the error. */
static hv_status scan_model(const char *name, const char *xml, size_t len, int geometry)
{
    model_scan m;
    memset(&m, 0, sizeof m);
    m.name = name;
    m.geometry = geometry;
    m.group = -1;
    hv_names_init(&m.ids);
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
            if (tag_is(&t, "object")) m.in_object = 0;
            else if (m.group >= 0 && group_kind(&t)) m.group = -1;
            else if (depth_other && --depth_other == 0) m.group = -1;
            continue;
        }
        if (m.group >= 0) { /* inside a property group: count its entries */
            if (depth_other) {
                if (!t.empty) ++depth_other;
                continue;
            }
            if (tag_is(&t, k_child_tags[m.res[m.group].kind])) m.res[m.group].count++;
            continue;
        }
        if (tag_is(&t, "object")) {
            s = scan_object(&m, &t);
            if (t.empty) m.in_object = 0;
        } else if (m.in_object && tag_is(&t, "vertex")) {
            if (geometry) s = scan_vertex(&m, &t);
            else m.nv++;
        } else if (m.in_object && tag_is(&t, "triangle")) {
            s = scan_triangle(&m, &t);
        } else if (m.in_object && tag_is(&t, "component")) {
            if (geometry) s = scan_reference(&m, &t, "an object defined above it");
        } else if (!m.in_object && tag_is(&t, "item")) {
            if (geometry) s = scan_reference(&m, &t, "an object of the resources");
        } else if (in_resources && !m.in_object) {
            const char *v;
            size_t n;
            uint64_t id;
            int kind = group_kind(&t);
            if (xml_uint(&t, "id", &id, &v, &n) <= 0) continue;
            if ((s = define(&m, id, kind ? kind : R_OTHER)) != HV_OK) break;
            if (!t.empty) {
                m.group = (int)(m.ids.n - 1);
                depth_other = kind ? 0 : 1;
            }
        }
    }
    hv_names_free(&m.ids);
    free(m.res);
    return s;
}

/* ---- the items lib3mf delivers ------------------------------------------------------------ */

typedef struct tmf_build {
    const char *name;
    double scale; /* model unit to mm */
    float *soup;
    int32_t *fmat;
    size_t nf, scap, mcap;
    int any_material;
    hv_mesh_body *bodies;
    size_t nb, bcap;
    size_t item;
    hv_names mats;
    uint32_t *rgba;
    size_t rcap;
    float *placed; /* one instance's vertices, placed */
    size_t pcap;
    hv_status failed;
} tmf_build;

/* Drop the current body when it holds no facet (an object with an empty mesh). */
static void close_body(tmf_build *b)
{
    if (b->nb && b->bodies[b->nb - 1].facet_count == 0) free((char *)b->bodies[--b->nb].name);
}

static int sink_begin(void *ctx, int unit)
{
    static const double k_mm[] = {0.001, 1.0, 10.0, 25.4, 304.8, 1000.0}; /* lib3mf's units */
    tmf_build *b = ctx;
    if (unit < 0 || unit > 5)
        return b->failed = hv_error_set(HV_ERR_BAD_INPUT, "%s: unknown unit (lib3mf unit %d)", b->name, unit);
    b->scale = k_mm[unit];
    return HV_OK;
}

static int sink_item(void *ctx, size_t item, const char *name, int32_t material)
{
    tmf_build *b = ctx;
    close_body(b);
    hv_status s = hv_grow((void **)&b->bodies, &b->bcap, b->nb + 1, sizeof *b->bodies);
    char *copy = s == HV_OK ? hv_strdup(name) : NULL;
    if (!copy) return b->failed = HV_ERR_NOMEM;
    hv_mesh_body *body = &b->bodies[b->nb++];
    body->name = copy;
    body->material = material;
    body->first_facet = b->nf;
    body->facet_count = 0;
    b->item = item;
    return HV_OK;
}

static int32_t sink_material(void *ctx, const char *name, uint32_t rgba)
{
    tmf_build *b = ctx;
    int32_t k;
    size_t before = b->mats.n;
    hv_status s = hv_names_intern(&b->mats, name, strlen(name), &k);
    if (s == HV_OK && b->mats.n != before && (s = hv_grow((void **)&b->rgba, &b->rcap, b->mats.n, sizeof *b->rgba)) == HV_OK)
        b->rgba[k] = rgba; /* base materials of the same name are one material: the first colour */
    if (s != HV_OK) return -(int32_t)(b->failed = s);
    return k;
}

static int sink_instance(void *ctx, const hv_3mf_instance *in)
{
    tmf_build *b = ctx;
    char where[256];
    if (in->object_name[0]) snprintf(where, sizeof where, "object '%.160s' (build item %zu)", in->object_name, in->item + 1);
    else snprintf(where, sizeof where, "the object of build item %zu", in->item + 1);
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
        b->fmat[b->nf + t] = in->mat[t];
        if (in->mat[t] >= 0) b->any_material = 1;
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

static int text_has(const hv_buf *b, const char *what) { return b->data && find(b->data, b->data + b->len, what) != NULL; }

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
    s = package_expand(&pk, budget, &xml);
    package_close(&pk);
    if (s == HV_OK) s = scan_model(name, xml.data ? xml.data : "", xml.len, 1);
    hv_buf_free(&xml);
    if (s != HV_OK) return s;
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: lib3mf: %s", name, msg);
}

hv_status hv_mesh_parse_3mf(const void *data, size_t size, const char *name, hv_mesh **out)
{
    *out = NULL;
    if (size == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: empty file (0 bytes)", name);
    /* lib3mf holds about one byte per byte of model text and hovox a mesh of the same order:
     * the expanded package may take half of the budget */
    uint64_t budget = hv_memory_budget(0) / 2;
    package pk;
    hv_status s = package_open(&pk, data, size, name);
    if (s != HV_OK) return s;
    hv_buf xml;
    hv_buf_init(&xml);
    s = package_expand(&pk, budget, &xml);
    package_close(&pk);
    /* lib3mf reads material references leniently (a pid naming nothing drops the property, an
     * index past a group's end reads as another entry): every one is checked first */
    if (s == HV_OK && (text_has(&xml, "pid") || text_has(&xml, "p1")))
        s = scan_model(name, xml.data, xml.len, 0);
    hv_buf_free(&xml);
    if (s != HV_OK) return s;
    pthread_once(&g_api_once, load_api);
    if (g_api_status != HV_OK)
        return hv_error_set(HV_ERR_UNSUPPORTED, "%s: reading 3MF needs the lib3mf bridge: %s", name, g_api_error);
    tmf_build b;
    memset(&b, 0, sizeof b);
    b.name = name;
    hv_names_init(&b.mats);
    hv_3mf_sink sink = {&b, sink_begin, sink_item, sink_material, sink_instance};
    hv_3mf_info info;
    uint64_t max_tri = HV_MIN((uint64_t)INT32_MAX / 3, hv_memory_budget(0) / 128);
    int rc = g_api->read(data, size, max_tri, &sink, &info);
    if (b.failed != HV_OK) s = b.failed; /* a sink's own message */
    else if (rc == HV_ERR_BAD_INPUT && info.error_code) s = diagnose(data, size, name, g_api->last_error(), budget);
    else if (rc != HV_OK) s = hv_error_set((hv_status)rc, "%s: %s", name, g_api->last_error());
    if (s == HV_OK) s = finish(&b, &info, out);
    build_free(&b);
    return s;
}

hv_status hv_mesh_load_3mf(const char *path, hv_mesh **out)
{
    *out = NULL;
    char *data;
    size_t size;
    hv_status s = hv_read_file(path, TMF_MAX_BYTES, &data, &size);
    if (s != HV_OK) return s;
    s = hv_mesh_parse_3mf(data, size, path, out);
    free(data);
    return s;
}
