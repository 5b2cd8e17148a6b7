/* src/io/3mf/volumetric_read.c - 3MF packages with the Volumetric extension (3MF Consortium, "3MF
 * Volumetric & Implicit Extensions" 0.8, Part I) read back as graded models: the package and the
 * model part streamed through the 3MF package module (package.c; hostile input: every count bounded by the
 * memory budget before it grows, every id and reference checked), the object's mesh voxelized on the
 * lattice of the image stacks by src/voxel's centre test, the materials' fractions sampled from
 * the PNG sheets (hv_png_decode) and normalised as the composite element prescribes (spec 5.2.2),
 * a color element's function sampled anywhere (spec 2.2: filter, tile styles; 5.2.1: linear sRGB)
 * into the colour grids a painted model holds. */
#include <errno.h>
#include <libxml/xmlmemory.h>
#include <libxml/xmlstring.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zip.h>

#include "core/json.h"
#include "hovox/colour.h"
#include "hovox/export.h"
#include "hovox/image.h"
#include "hovox/material.h"
#include "package.h"
#include "threemf_internal.h"
#include "voxel/bitgrid.h"
#include "voxel/voxel_internal.h"

#define MAX_DEPTH 256

/* ---- what the model part holds ------------------------------------------------------------------ */

typedef enum kind {
    K_NONE = 0, K_MODEL, K_METADATA, K_RESOURCES, K_BASEMATERIALS, K_BASE, K_OBJECT, K_MESH, K_VERTICES, K_VERTEX,
    K_TRIANGLES, K_TRIANGLE, K_COMPONENTS, K_BUILD, K_ITEM, K_IMAGE3D, K_IMAGESTACK, K_IMAGESHEET, K_FUNCIMG,
    K_VOLUMEDATA, K_COMPOSITE, K_MATMAP, K_PROPERTY, K_COLOR, K_LEVELSET, K_IMPLICIT, K_RESOURCE_OTHER, K_IGNORED
} kind;

typedef struct bgroup {
    uint32_t id;
    int line, n;
    size_t cap;
    char **names;
    float *rgba; /* 4 per base */
} bgroup;

typedef struct img3d {
    uint32_t id;
    int line, stack_line, has_stack;
    char *name;
    uint64_t rows, cols, sheets;
    char **paths;
    int *lines;         /* of each imagesheet: its line and column */
    size_t npaths, cap;
    int channels, bits; /* of the first sheet decoded */
} img3d;

enum { F_IMAGE = 1, F_IMPLICIT, F_OTHER };
typedef struct func {
    uint32_t id, image3did;
    int line, kind;
    double offset, scale;
    int tile[3]; /* 0 wrap, 1 mirror, 2 clamp */
    int nearest; /* filter: 1 nearest, 0 linear */
    char elem[64];
} func;

typedef struct mapping {
    uint32_t functionid;
    int line, channel; /* 0 red, 1 green, 2 blue, 3 alpha */
    double t[12];
} mapping;

/* A <v:color>, or the <v:property> hovox:colour.mask hovox writes beside it (where a colour was
 * asked for): the function, its output and the transform to it, where it was read. */
typedef struct fieldref {
    int present, line, col;
    uint32_t functionid;
    char channel[48];
    double t[12];
} fieldref;

typedef struct voldata {
    uint32_t id, basematerialid;
    int line, composites, composite_line;
    fieldref colour, mask;
    mapping *maps;
    int nmaps;
    size_t cap;
    int refuse_line;
    char refuse[200];
} voldata;

enum { O_NONE = 0, O_MESH, O_COMPONENTS, O_LEVELSET };
typedef struct object {
    uint32_t id, volumeid;
    int line, kind, has_volumeid, mesh_line;
    size_t v0, nv, t0, nt;
} object;

typedef struct item {
    uint32_t objectid;
    int line, has_t;
    double t[12];
} item;

typedef struct resid {
    uint32_t id;
    int line;
} resid;

typedef struct rd {
    const char *name;   /* the package, for messages */
    const char *part;   /* the model part's name in the archive */
    tmf_pkg *pk;
    uint64_t budget, used;
    tmf_xml *x;         /* the parse under way, with the element being read: */
    const char *local, *uri, *qname;
    const tmf_attr *attrs;
    int nattrs, depth;
    int stack[MAX_DEPTH + 1]; /* kinds of the open elements */
    int meta, meta_line, meta_col; /* hovox metadata being read: 1 materials, 2 origin, 3 colour */
    int colour_at[2];              /* the line and column of hovox:colour */
    /* model */
    double unit;
    char *materials_json;
    char *colour_json;        /* hovox:colour, a painted model's record (hovox.colour.json) */
    double origin_meta[3];
    int has_origin;
    /* resources */
    bgroup *groups;
    size_t ngroups, gcap;
    img3d *images;
    size_t nimages, icap;
    func *funcs;
    size_t nfuncs, fcap;
    voldata *vols;
    size_t nvols, vcap;
    object *objects;
    size_t nobjects, ocap;
    item *items;
    size_t nitems, itcap;
    resid *ids;
    size_t nids, idcap;
    double *xyz; /* 3 per vertex, all meshes */
    size_t nxyz, xcap;
    uint32_t *tri; /* 3 per triangle, indices into the object's vertices */
    size_t ntri, tcap;
    int builds, resources_seen;
    const hv_colour_options *colour; /* a colour without a composite prints through it (NULL: defaults) */
    uint64_t leaf_bytes; /* what a leaf of the model will cost (hv_volume_memory_estimate) */
} rd;

/* ---- messages ------------------------------------------------------------------------------------- */

/* The line of the element being read (the parser itself reads ahead). */
static int line_of(rd *r)
{
    int line = 0, col = 0;
    if (r->x) tmf_xml_where(r->x, &line, &col);
    return line;
}

/* "part.3mf: 3D/3dmodel.model: line 12, column 7: <elem> ...", for a place recorded while the
 * element was read. */
static hv_status bad_at_col(rd *r, hv_status code, int line, int col, const char *fmt, ...) HV_PRINTF(5, 6);
static hv_status bad_at_col(rd *r, hv_status code, int line, int col, const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return hv_error_set(code, "%s: %s: line %d, column %d: %s", r->name, r->part, line, col, msg);
}

/* "part.3mf: 3D/3dmodel.model: line 12: <elem> ..." */
static hv_status bad_at(rd *r, hv_status code, int line, const char *fmt, ...) HV_PRINTF(4, 5);
static hv_status bad_at(rd *r, hv_status code, int line, const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    int now = 0, col = 0;
    if (r->x) tmf_xml_where(r->x, &now, &col);
    if (line > 0 && line == now) /* the element being read: its column too */
        return hv_error_set(code, "%s: %s: line %d, column %d: %s", r->name, r->part, line, col, msg);
    if (line > 0) return hv_error_set(code, "%s: %s: line %d: %s", r->name, r->part, line, msg);
    return hv_error_set(code, "%s: %s", r->name, msg);
}

static hv_status over_budget(rd *r, const char *what)
{
    char have[32];
    hv_size_text(have, sizeof have, (double)r->budget);
    return bad_at(r, HV_ERR_LIMIT, line_of(r), "%s: reading this file needs more than the memory budget of %s", what,
                  have);
}

static hv_status charge(rd *r, uint64_t bytes, const char *what)
{
    if (bytes > r->budget || r->used > r->budget - bytes) return over_budget(r, what);
    r->used += bytes;
    return HV_OK;
}

/* Grow an array by one element, charging the budget for what grows. */
static hv_status grow(rd *r, void **p, size_t *cap, size_t need, size_t size, const char *what)
{
    if (need <= *cap) return HV_OK;
    size_t ncap = *cap ? *cap * 2 : 16;
    while (ncap < need) ncap *= 2;
    if (ncap > SIZE_MAX / size) return over_budget(r, what);
    hv_status s = charge(r, (uint64_t)(ncap - *cap) * size, what);
    if (s != HV_OK) return s;
    void *q = hv_realloc(*p, ncap * size);
    if (!q) return HV_ERR_NOMEM;
    *p = q;
    *cap = ncap;
    return HV_OK;
}

/* ---- attributes ------------------------------------------------------------------------------------ */

static const char *elem_name(rd *r) { return r->qname ? r->qname : "?"; }

static char *attr_copy(const tmf_attr *a)
{
    if (!a) return NULL;
    return (char *)xmlStrndup((const xmlChar *)a->value, (int)HV_MIN(a->len, (size_t)INT32_MAX));
}

/* The attribute's value (NULL when absent); the caller frees with xmlFree. Unprefixed attributes
 * have no namespace. */
static char *get_attr(rd *r, const char *name)
{
    for (int i = 0; i < r->nattrs; ++i)
        if (!r->attrs[i].uri && strcmp(r->attrs[i].local, name) == 0) return attr_copy(&r->attrs[i]);
    return NULL;
}

static char *get_attr_ns(rd *r, const char *name, const char *ns)
{
    return attr_copy(tmf_attr_find(r->attrs, r->nattrs, name, ns));
}

static const char *trim(const char *s, size_t *n)
{
    while (*s == ' ' || *s == '\t' || *s == '\n' || *s == '\r') ++s;
    size_t k = strlen(s);
    while (k > 0 && (s[k - 1] == ' ' || s[k - 1] == '\t' || s[k - 1] == '\n' || s[k - 1] == '\r')) --k;
    *n = k;
    return s;
}

/* A finite xs:double in the forms ST_Number allows (no "INF", "NaN", hex). */
static int parse_number(const char *text, double *out)
{
    size_t n;
    const char *s = trim(text, &n);
    if (n == 0 || n > 64) return 0;
    char buf[80];
    memcpy(buf, s, n);
    buf[n] = '\0';
    for (size_t i = 0; i < n; ++i) {
        char c = buf[i];
        if (!((c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E')) return 0;
    }
    char *end;
    errno = 0;
    double v = strtod(buf, &end);
    if (*end || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

/* A non-negative integer of at most `max` (decimal digits only). */
static int parse_uint(const char *text, uint64_t max, uint64_t *out)
{
    size_t n;
    const char *s = trim(text, &n);
    if (n == 0 || n > 20) return 0;
    uint64_t v = 0;
    for (size_t i = 0; i < n; ++i) {
        if (s[i] < '0' || s[i] > '9') return 0;
        unsigned d = (unsigned)(s[i] - '0');
        if (v > (max - d) / 10) return 0;
        v = v * 10 + d;
    }
    *out = v;
    return 1;
}

static hv_status need_attr(rd *r, const char *name, char **v)
{
    *v = get_attr(r, name);
    if (!*v) return bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> has no attribute %s", elem_name(r), name);
    return HV_OK;
}

/* ST_ResourceID: a positive integer below 2^31. */
static hv_status id_attr(rd *r, const char *name, int required, uint32_t *id, int *present)
{
    char *v = get_attr(r, name);
    if (present) *present = v != NULL;
    if (!v) return required ? bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> has no attribute %s", elem_name(r), name)
                            : HV_OK;
    uint64_t x = 0;
    int ok = parse_uint(v, 2147483647u, &x) && x > 0;
    hv_status s = ok ? HV_OK
                     : bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> %s '%.40s' is not a resource id (1 to 2^31 - 1)",
                              elem_name(r), name, v);
    *id = (uint32_t)x;
    xmlFree(v);
    return s;
}

static hv_status number_attr(rd *r, const char *name, double dflt, double *out)
{
    char *v = get_attr(r, name);
    *out = dflt;
    if (!v) return HV_OK;
    hv_status s = parse_number(v, out) ? HV_OK
                                       : bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> %s '%.40s' is not a finite number",
                                                elem_name(r), name, v);
    xmlFree(v);
    return s;
}

/* ST_Matrix3D: 12 numbers; absent: the identity. */
static hv_status matrix_attr(rd *r, const char *name, double *t, int *present)
{
    static const double id[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    memcpy(t, id, sizeof id);
    char *v = get_attr(r, name);
    if (present) *present = v != NULL;
    if (!v) return HV_OK;
    const char *p = v;
    int n = 0;
    hv_status s = HV_OK;
    while (s == HV_OK) {
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
        if (!*p) break;
        const char *e = p;
        while (*e && *e != ' ' && *e != '\t' && *e != '\n' && *e != '\r') ++e;
        char tok[80];
        size_t len = (size_t)(e - p);
        if (n == 12 || len >= sizeof tok) {
            n = 13;
            break;
        }
        memcpy(tok, p, len);
        tok[len] = '\0';
        if (!parse_number(tok, &t[n]))
            s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> %s: '%.40s' is not a finite number", elem_name(r), name, tok);
        ++n;
        p = e;
    }
    if (s == HV_OK && n != 12)
        s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> %s must hold 12 numbers", elem_name(r), name);
    xmlFree(v);
    return s;
}

static hv_status add_id(rd *r, uint32_t id)
{
    hv_status s = grow(r, (void **)&r->ids, &r->idcap, r->nids + 1, sizeof *r->ids, "resources");
    if (s == HV_OK) r->ids[r->nids++] = (resid){id, line_of(r)};
    return s;
}

static int tile_style(const char *v)
{
    if (!v || strcmp(v, "wrap") == 0) return 0;
    if (strcmp(v, "mirror") == 0) return 1;
    if (strcmp(v, "clamp") == 0) return 2;
    return -1;
}

/* ---- the elements ------------------------------------------------------------------------------------ */

static kind classify(rd *r)
{
    const char *ns = r->uri, *ln = r->local;
    if (!ln) return K_IGNORED;
    if (ns && strcmp(ns, TMF_NS_CORE) == 0) {
        static const struct {
            const char *n;
            kind k;
        } core[] = {{"model", K_MODEL},         {"metadata", K_METADATA},     {"resources", K_RESOURCES},
                    {"basematerials", K_BASEMATERIALS}, {"base", K_BASE},     {"object", K_OBJECT},
                    {"mesh", K_MESH},           {"vertices", K_VERTICES},     {"vertex", K_VERTEX},
                    {"triangles", K_TRIANGLES}, {"triangle", K_TRIANGLE},     {"components", K_COMPONENTS},
                    {"build", K_BUILD},         {"item", K_ITEM}};
        for (size_t i = 0; i < HV_COUNT(core); ++i)
            if (strcmp(ln, core[i].n) == 0) return core[i].k;
        return K_IGNORED;
    }
    if (ns && strcmp(ns, TMF_NS_VOLUMETRIC) == 0) {
        static const struct {
            const char *n;
            kind k;
        } vol[] = {{"image3d", K_IMAGE3D},       {"imagestack", K_IMAGESTACK}, {"imagesheet", K_IMAGESHEET},
                   {"functionfromimage3d", K_FUNCIMG}, {"volumedata", K_VOLUMEDATA}, {"composite", K_COMPOSITE},
                   {"materialmapping", K_MATMAP}, {"property", K_PROPERTY}, {"color", K_COLOR},
                   {"levelset", K_LEVELSET}};
        for (size_t i = 0; i < HV_COUNT(vol); ++i)
            if (strcmp(ln, vol[i].n) == 0) return vol[i].k;
        return K_IGNORED;
    }
    if (ns && strcmp(ns, TMF_NS_IMPLICIT) == 0 && strcmp(ln, "implicitfunction") == 0) return K_IMPLICIT;
    return K_IGNORED;
}

static hv_status on_model(rd *r)
{
    char *u = get_attr(r, "unit");
    r->unit = 1;
    hv_status s = HV_OK;
    if (u) {
        static const struct {
            const char *n;
            double mm;
        } units[] = {{"micron", 0.001}, {"millimeter", 1}, {"centimeter", 10}, {"inch", 25.4}, {"foot", 304.8},
                     {"meter", 1000}};
        r->unit = 0;
        for (size_t i = 0; i < HV_COUNT(units); ++i)
            if (strcmp(u, units[i].n) == 0) r->unit = units[i].mm;
        if (r->unit == 0)
            s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<model> unit '%.40s' is not micron, millimeter, centimeter, "
                       "inch, foot or meter", u);
        xmlFree(u);
    }
    char *req = s == HV_OK ? get_attr(r, "requiredextensions") : NULL;
    if (req) {
        for (char *p = req, *save = NULL, *tok; s == HV_OK && (tok = strtok_r(p, " \t\r\n", &save)); p = NULL) {
            const char *ns = tmf_xml_lookup_ns(r->x, tok);
            if (!ns)
                s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<model> requiredextensions names prefix '%.40s', which "
                           "is not declared", tok);
            else if (strcmp(ns, TMF_NS_VOLUMETRIC) != 0 && strcmp(ns, TMF_NS_MATERIAL) != 0)
                s = bad_at(r, HV_ERR_UNSUPPORTED, line_of(r), "<model> requires the extension %.200s, which hovox "
                           "does not read", ns);
        }
        xmlFree(req);
    }
    return s;
}

/* hovox's own metadata (hovox:materials, hovox:origin): its text is read at the element's end. */
static hv_status on_metadata(rd *r)
{
    char *name = get_attr(r, "name");
    if (!name) return HV_OK;
    char *colon = strchr(name, ':');
    r->meta = 0;
    if (colon) {
        *colon = '\0';
        const char *ns = tmf_xml_lookup_ns(r->x, name);
        if (ns && strcmp(ns, TMF_NS_HOVOX) == 0) {
            r->meta = strcmp(colon + 1, "materials") == 0 ? 1
                      : strcmp(colon + 1, "origin") == 0  ? 2
                      : strcmp(colon + 1, "colour") == 0  ? 3
                                                          : 0;
            tmf_xml_where(r->x, &r->meta_line, &r->meta_col);
        }
    }
    xmlFree(name);
    if (r->meta) tmf_xml_collect_text(r->x);
    return HV_OK;
}

static hv_status end_metadata(rd *r)
{
    const char *text = tmf_xml_text(r->x);
    int meta = r->meta;
    r->meta = 0;
    if (meta == 1 || meta == 3) {
        char **dst = meta == 1 ? &r->materials_json : &r->colour_json;
        if (meta == 3) {
            r->colour_at[0] = r->meta_line;
            r->colour_at[1] = r->meta_col;
        }
        free(*dst);
        *dst = hv_strdup(text);
        return *dst ? HV_OK : HV_ERR_NOMEM;
    }
    if (meta == 2) {
        double o[3];
        char extra;
        if (sscanf(text, "%lf %lf %lf %c", &o[0], &o[1], &o[2], &extra) == 3 && isfinite(o[0]) && isfinite(o[1]) &&
            isfinite(o[2])) {
            memcpy(r->origin_meta, o, sizeof o);
            r->has_origin = 1;
        } else {
            return bad_at(r, HV_ERR_BAD_INPUT, r->meta_line, "<metadata> hovox:origin '%.60s' is not three numbers", text);
        }
    }
    return HV_OK;
}

static hv_status on_basematerials(rd *r)
{
    uint32_t id;
    hv_status s = id_attr(r, "id", 1, &id, NULL);
    if (s == HV_OK) s = add_id(r, id);
    if (s == HV_OK) s = grow(r, (void **)&r->groups, &r->gcap, r->ngroups + 1, sizeof *r->groups, "base materials");
    if (s != HV_OK) return s;
    bgroup *g = &r->groups[r->ngroups++];
    memset(g, 0, sizeof *g);
    g->id = id;
    g->line = line_of(r);
    return HV_OK;
}

static int hexval(char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

static hv_status on_base(rd *r)
{
    bgroup *g = &r->groups[r->ngroups - 1];
    char *name = NULL, *color = NULL;
    hv_status s = need_attr(r, "name", &name);
    if (s == HV_OK) s = need_attr(r, "displaycolor", &color);
    float rgba[4] = {0, 0, 0, 1};
    if (s == HV_OK) {
        size_t n = strlen(color);
        int ok = (n == 7 || n == 9) && color[0] == '#';
        for (size_t i = 1; ok && i < n; ++i) ok = hexval(color[i]) >= 0;
        for (size_t c = 0; ok && c < (n - 1) / 2; ++c)
            rgba[c] = (float)(hexval(color[1 + 2 * c]) * 16 + hexval(color[2 + 2 * c])) / 255.0f;
        if (!ok) s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<base> displaycolor '%.40s' is not #RRGGBB or #RRGGBBAA", color);
    }
    if (s == HV_OK && g->n >= HV_MAX_MATERIALS)
        s = bad_at(r, HV_ERR_UNSUPPORTED, line_of(r), "<basematerials> id %u holds more than %d materials, hovox's most",
                   g->id, HV_MAX_MATERIALS);
    if (s == HV_OK) {
        size_t cap = g->cap;
        s = grow(r, (void **)&g->names, &cap, (size_t)g->n + 1, sizeof *g->names, "base materials");
        if (s == HV_OK) {
            size_t cap2 = g->cap;
            s = grow(r, (void **)&g->rgba, &cap2, (size_t)g->n + 1, 4 * sizeof *g->rgba, "base materials");
            g->cap = cap;
        }
    }
    if (s == HV_OK) s = charge(r, strlen(name) + 1, "base materials");
    if (s == HV_OK) {
        g->names[g->n] = hv_strdup(name);
        if (!g->names[g->n]) s = HV_ERR_NOMEM;
        else memcpy(g->rgba + 4 * g->n++, rgba, sizeof rgba);
    }
    xmlFree(name);
    xmlFree(color);
    return s;
}

static hv_status on_object(rd *r)
{
    uint32_t id;
    hv_status s = id_attr(r, "id", 1, &id, NULL);
    if (s == HV_OK) s = add_id(r, id);
    if (s == HV_OK) s = grow(r, (void **)&r->objects, &r->ocap, r->nobjects + 1, sizeof *r->objects, "objects");
    if (s != HV_OK) return s;
    object *o = &r->objects[r->nobjects++];
    memset(o, 0, sizeof *o);
    o->id = id;
    o->line = line_of(r);
    return HV_OK;
}

static hv_status on_mesh(rd *r)
{
    object *o = &r->objects[r->nobjects - 1];
    if (o->kind != O_NONE)
        return bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<object> id %u has more than one shape", o->id);
    o->kind = O_MESH;
    o->mesh_line = line_of(r);
    o->v0 = r->nxyz / 3;
    o->t0 = r->ntri / 3;
    char *v = get_attr_ns(r, "volumeid", TMF_NS_VOLUMETRIC);
    if (!v) v = get_attr(r, "volumeid"); /* unqualified, as the spec's own example writes it */
    if (!v) return HV_OK;
    uint64_t x = 0;
    hv_status s = parse_uint(v, 2147483647u, &x) && x > 0
                      ? HV_OK
                      : bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> volumeid '%.40s' is not a resource id", elem_name(r), v);
    xmlFree(v);
    o->volumeid = (uint32_t)x;
    o->has_volumeid = 1;
    return s;
}

static hv_status on_vertex(rd *r)
{
    object *o = &r->objects[r->nobjects - 1];
    double p[3];
    static const char *const xyz[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
        char *v = NULL;
        hv_status s = need_attr(r, xyz[a], &v);
        if (s != HV_OK) return s;
        int ok = parse_number(v, &p[a]);
        if (!ok) s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<vertex> %u: %s '%.40s' is not a finite number",
                            (unsigned)o->nv, xyz[a], v);
        xmlFree(v);
        if (s != HV_OK) return s;
    }
    if (o->nv >= UINT32_MAX) return bad_at(r, HV_ERR_LIMIT, line_of(r), "<mesh> has more than 2^32 vertices");
    hv_status s = grow(r, (void **)&r->xyz, &r->xcap, r->nxyz + 3, sizeof *r->xyz, "vertices");
    if (s != HV_OK) return s;
    memcpy(r->xyz + r->nxyz, p, sizeof p);
    r->nxyz += 3;
    o->nv++;
    return HV_OK;
}

static hv_status on_triangle(rd *r)
{
    object *o = &r->objects[r->nobjects - 1];
    uint32_t t[3];
    static const char *const vn[3] = {"v1", "v2", "v3"};
    for (int k = 0; k < 3; ++k) {
        char *v = NULL;
        hv_status s = need_attr(r, vn[k], &v);
        if (s != HV_OK) return s;
        uint64_t x = 0;
        if (!parse_uint(v, UINT32_MAX, &x))
            s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<triangle> %zu: %s '%.40s' is not a vertex index", o->nt,
                       vn[k], v);
        else if (x >= o->nv)
            s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<triangle> %zu: %s = %llu is out of range (the mesh has %zu "
                       "vertices)", o->nt, vn[k], (unsigned long long)x, o->nv);
        xmlFree(v);
        if (s != HV_OK) return s;
        t[k] = (uint32_t)x;
    }
    hv_status s = grow(r, (void **)&r->tri, &r->tcap, r->ntri + 3, sizeof *r->tri, "triangles");
    if (s != HV_OK) return s;
    memcpy(r->tri + r->ntri, t, sizeof t);
    r->ntri += 3;
    o->nt++;
    return HV_OK;
}

static hv_status on_item(rd *r)
{
    uint32_t id;
    hv_status s = id_attr(r, "objectid", 1, &id, NULL);
    if (s == HV_OK) s = grow(r, (void **)&r->items, &r->itcap, r->nitems + 1, sizeof *r->items, "build items");
    if (s != HV_OK) return s;
    item *it = &r->items[r->nitems++];
    memset(it, 0, sizeof *it);
    it->objectid = id;
    it->line = line_of(r);
    return matrix_attr(r, "transform", it->t, &it->has_t);
}

static hv_status on_image3d(rd *r)
{
    uint32_t id;
    hv_status s = id_attr(r, "id", 1, &id, NULL);
    if (s == HV_OK) s = add_id(r, id);
    if (s == HV_OK) s = grow(r, (void **)&r->images, &r->icap, r->nimages + 1, sizeof *r->images, "images");
    if (s != HV_OK) return s;
    img3d *im = &r->images[r->nimages++];
    memset(im, 0, sizeof *im);
    im->id = id;
    im->line = line_of(r);
    char *name = get_attr(r, "name");
    if (name) {
        s = charge(r, strlen(name) + 1, "images");
        if (s == HV_OK && !(im->name = hv_strdup(name))) s = HV_ERR_NOMEM;
        xmlFree(name);
    }
    return s;
}

static hv_status on_imagestack(rd *r)
{
    img3d *im = &r->images[r->nimages - 1];
    if (im->has_stack) return bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<v:image3d> id %u has more than one stack", im->id);
    im->has_stack = 1;
    im->stack_line = line_of(r);
    static const char *const names[3] = {"rowcount", "columncount", "sheetcount"};
    uint64_t *dst[3] = {&im->rows, &im->cols, &im->sheets};
    for (int a = 0; a < 3; ++a) {
        char *v = NULL;
        hv_status s = need_attr(r, names[a], &v);
        if (s != HV_OK) return s;
        uint64_t x = 0;
        if (!parse_uint(v, UINT64_MAX / 16, &x) || x == 0)
            s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> %s '%.40s' is not a positive integer", elem_name(r),
                       names[a], v);
        else if (x > HV_3MF_MAX_IMAGE_SIDE)
            s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> %s %llu exceeds the 3MF Volumetric limit of 1024^3",
                       elem_name(r), names[a], (unsigned long long)x);
        xmlFree(v);
        if (s != HV_OK) return s;
        *dst[a] = x;
    }
    double total = (double)im->rows * (double)im->cols * (double)im->sheets;
    if (total > (double)HV_3MF_MAX_IMAGE_VOXELS)
        return bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> of %.4g voxels exceeds the 3MF Volumetric limit of 1024^5",
                      elem_name(r), total);
    return HV_OK;
}

static hv_status on_imagesheet(rd *r)
{
    img3d *im = &r->images[r->nimages - 1];
    if (!im->has_stack) return HV_OK;
    if (im->npaths >= im->sheets)
        return bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> %zu: the imagestack has sheetcount %llu", elem_name(r),
                      im->npaths + 1, (unsigned long long)im->sheets);
    char *path = NULL;
    hv_status s = need_attr(r, "path", &path);
    if (s != HV_OK) return s;
    if (path[0] != '/' || !path[1] || strlen(path) > 1024)
        s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> path '%.60s' is not an absolute part name", elem_name(r), path);
    size_t lcap = im->cap;
    if (s == HV_OK) s = grow(r, (void **)&im->lines, &lcap, im->npaths + 1, 2 * sizeof *im->lines, "image sheets");
    if (s == HV_OK) s = grow(r, (void **)&im->paths, &im->cap, im->npaths + 1, sizeof *im->paths, "image sheets");
    if (s == HV_OK) tmf_xml_where(r->x, &im->lines[2 * im->npaths], &im->lines[2 * im->npaths + 1]);
    if (s == HV_OK) s = charge(r, strlen(path), "image sheets");
    if (s == HV_OK) {
        im->paths[im->npaths] = hv_strdup(path + 1);
        if (!im->paths[im->npaths]) s = HV_ERR_NOMEM;
        else im->npaths++;
    }
    xmlFree(path);
    return s;
}

static hv_status add_func(rd *r, int fkind, func **out)
{
    uint32_t id;
    hv_status s = id_attr(r, "id", 1, &id, NULL);
    if (s == HV_OK) s = add_id(r, id);
    if (s == HV_OK) s = grow(r, (void **)&r->funcs, &r->fcap, r->nfuncs + 1, sizeof *r->funcs, "functions");
    if (s != HV_OK) return s;
    func *f = &r->funcs[r->nfuncs++];
    memset(f, 0, sizeof *f);
    f->id = id;
    f->kind = fkind;
    f->line = line_of(r);
    snprintf(f->elem, sizeof f->elem, "%s", elem_name(r));
    *out = f;
    return HV_OK;
}

static hv_status on_funcimg(rd *r)
{
    func *f;
    hv_status s = add_func(r, F_IMAGE, &f);
    if (s == HV_OK) s = id_attr(r, "image3did", 1, &f->image3did, NULL);
    if (s == HV_OK) s = number_attr(r, "valueoffset", 0.0, &f->offset);
    if (s == HV_OK) s = number_attr(r, "valuescale", 1.0, &f->scale);
    static const char *const tiles[3] = {"tilestyleu", "tilestylev", "tilestylew"};
    for (int a = 0; a < 3 && s == HV_OK; ++a) {
        char *v = get_attr(r, tiles[a]);
        f->tile[a] = tile_style(v);
        if (f->tile[a] < 0)
            s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> %s '%.40s' is not wrap, mirror or clamp", elem_name(r),
                       tiles[a], v);
        xmlFree(v);
    }
    char *filter = s == HV_OK ? get_attr(r, "filter") : NULL;
    if (filter && strcmp(filter, "linear") != 0 && strcmp(filter, "nearest") != 0)
        s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> filter '%.40s' is not linear or nearest", elem_name(r), filter);
    if (s == HV_OK) f->nearest = filter && strcmp(filter, "nearest") == 0;
    xmlFree(filter);
    return s;
}

static hv_status on_volumedata(rd *r)
{
    uint32_t id;
    hv_status s = id_attr(r, "id", 1, &id, NULL);
    if (s == HV_OK) s = add_id(r, id);
    if (s == HV_OK) s = grow(r, (void **)&r->vols, &r->vcap, r->nvols + 1, sizeof *r->vols, "volume data");
    if (s != HV_OK) return s;
    voldata *v = &r->vols[r->nvols++];
    memset(v, 0, sizeof *v);
    v->id = id;
    v->line = line_of(r);
    return HV_OK;
}

static hv_status on_composite(rd *r)
{
    voldata *v = &r->vols[r->nvols - 1];
    if (v->composites++)
        return bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<v:volumedata> id %u has more than one composite", v->id);
    v->composite_line = line_of(r);
    return id_attr(r, "basematerialid", 1, &v->basematerialid, NULL);
}

static hv_status on_matmap(rd *r)
{
    voldata *v = &r->vols[r->nvols - 1];
    if (v->nmaps >= HV_MAX_MATERIALS)
        return bad_at(r, HV_ERR_UNSUPPORTED, line_of(r), "<v:composite> holds more than %d material mappings, hovox's "
                      "most", HV_MAX_MATERIALS);
    hv_status s = grow(r, (void **)&v->maps, &v->cap, (size_t)v->nmaps + 1, sizeof *v->maps, "material mappings");
    if (s != HV_OK) return s;
    mapping *m = &v->maps[v->nmaps++];
    memset(m, 0, sizeof *m);
    m->line = line_of(r);
    s = id_attr(r, "functionid", 1, &m->functionid, NULL);
    char *ch = NULL;
    if (s == HV_OK) s = need_attr(r, "channel", &ch);
    if (s == HV_OK) {
        static const char *const names[4] = {"red", "green", "blue", "alpha"};
        m->channel = -1;
        for (int c = 0; c < 4; ++c)
            if (strcmp(ch, names[c]) == 0) m->channel = c;
        if (m->channel < 0)
            s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<%s> channel '%.40s' is not a scalar output of a "
                       "functionfromimage3d (red, green, blue or alpha)", elem_name(r), ch);
    }
    xmlFree(ch);
    if (s == HV_OK) s = matrix_attr(r, "transform", m->t, NULL);
    return s;
}

/* A <v:color> or the hovox:colour.mask <v:property>: its function, output and transform, and
 * where it stands (the function is checked once all resources are read). */
static hv_status field_ref(rd *r, const char *what, fieldref *f)
{
    voldata *v = &r->vols[r->nvols - 1];
    if (f->present)
        return bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<v:volumedata> id %u has more than one %s", v->id, what);
    f->present = 1;
    tmf_xml_where(r->x, &f->line, &f->col);
    hv_status s = id_attr(r, "functionid", 1, &f->functionid, NULL);
    char *ch = NULL;
    if (s == HV_OK) s = need_attr(r, "channel", &ch);
    if (s == HV_OK) snprintf(f->channel, sizeof f->channel, "%s", ch);
    xmlFree(ch);
    double x;
    if (s == HV_OK) s = matrix_attr(r, "transform", f->t, NULL);
    if (s == HV_OK) s = number_attr(r, "minfeaturesize", 0.0, &x);
    if (s == HV_OK) s = number_attr(r, "fallbackvalue", 0.0, &x);
    return s;
}

static hv_status on_property(rd *r)
{
    voldata *v = &r->vols[r->nvols - 1];
    char *req = get_attr(r, "required"), *name = get_attr(r, "name");
    /* hovox's own (urn:hovox:3mf:2025): the colour mask, and properties derived from the fractions */
    int ours = 0;
    char *colon = name ? strchr(name, ':') : NULL;
    if (colon) {
        *colon = '\0';
        const char *ns = tmf_xml_lookup_ns(r->x, name);
        ours = ns && strcmp(ns, TMF_NS_HOVOX) == 0;
        *colon = ':';
    }
    hv_status s = HV_OK;
    if (ours && strcmp(colon + 1, "colour.mask") == 0) {
        s = field_ref(r, "hovox:colour.mask", &v->mask);
    } else if (!ours && req && (strcmp(req, "true") == 0 || strcmp(req, "1") == 0) && !v->refuse_line) {
        /* another's required property is a requirement hovox cannot meet */
        v->refuse_line = line_of(r);
        snprintf(v->refuse, sizeof v->refuse, "<v:property> '%.100s' is required, and hovox does not read "
                 "properties", name ? name : "?");
    }
    xmlFree(req);
    xmlFree(name);
    return s;
}

/* ---- reading the model part ----------------------------------------------------------------------------- */

static hv_status on_element(rd *r, kind k, kind parent, int depth, kind *self)
{
    *self = K_IGNORED;
    if (depth == 0) {
        if (k != K_MODEL)
            return bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "the root element is <%s>, not a 3MF <model>", elem_name(r));
        *self = K_MODEL;
        return on_model(r);
    }
    hv_status s = HV_OK;
    switch (parent) {
    case K_MODEL:
        if (k == K_METADATA) {
            s = on_metadata(r);
            *self = K_METADATA;
        }
        else if (k == K_RESOURCES && r->resources_seen++) s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "a second <resources>");
        else if (k == K_BUILD && r->builds++) s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "a second <build>");
        if (k == K_RESOURCES || k == K_BUILD) *self = k;
        break;
    case K_RESOURCES:
        switch (k) {
        case K_BASEMATERIALS: s = on_basematerials(r); break;
        case K_OBJECT: s = on_object(r); break;
        case K_IMAGE3D: s = on_image3d(r); break;
        case K_FUNCIMG: s = on_funcimg(r); break;
        case K_VOLUMEDATA: s = on_volumedata(r); break;
        case K_IMPLICIT: {
            func *f;
            s = add_func(r, F_IMPLICIT, &f);
            k = K_IGNORED;
            break;
        }
        default: { /* another extension's resource: its id still counts */
            char *id = get_attr(r, "id");
            if (id) {
                func *f;
                xmlFree(id);
                s = add_func(r, F_OTHER, &f);
            }
            k = K_IGNORED;
        }
        }
        *self = k;
        break;
    case K_BASEMATERIALS:
        if (k == K_BASE) s = on_base(r);
        break;
    case K_OBJECT:
        if (k == K_MESH) s = on_mesh(r);
        else if (k == K_COMPONENTS || k == K_LEVELSET) {
            object *o = &r->objects[r->nobjects - 1];
            if (o->kind != O_NONE)
                s = bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "<object> id %u has more than one shape", o->id);
            o->kind = k == K_COMPONENTS ? O_COMPONENTS : O_LEVELSET;
            o->mesh_line = line_of(r);
            k = K_IGNORED;
        }
        *self = k == K_MESH ? K_MESH : K_IGNORED;
        break;
    case K_MESH:
        if (k == K_VERTICES || k == K_TRIANGLES) *self = k;
        break;
    case K_VERTICES:
        if (k == K_VERTEX) s = on_vertex(r);
        break;
    case K_TRIANGLES:
        if (k == K_TRIANGLE) s = on_triangle(r);
        break;
    case K_BUILD:
        if (k == K_ITEM) s = on_item(r);
        break;
    case K_IMAGE3D:
        if (k == K_IMAGESTACK) {
            s = on_imagestack(r);
            *self = k;
        }
        break;
    case K_IMAGESTACK:
        if (k == K_IMAGESHEET) s = on_imagesheet(r);
        break;
    case K_VOLUMEDATA:
        if (k == K_COMPOSITE) {
            s = on_composite(r);
            *self = k;
        } else if (k == K_PROPERTY) {
            s = on_property(r);
        } else if (k == K_COLOR) {
            s = field_ref(r, "<v:color>", &r->vols[r->nvols - 1].colour);
        }
        break;
    case K_COMPOSITE:
        if (k == K_MATMAP) s = on_matmap(r);
        break;
    default:
        break;
    }
    return s;
}

static hv_status on_end(rd *r, kind k)
{
    if (k == K_METADATA) return end_metadata(r);
    if (k == K_IMAGESTACK) {
        img3d *im = &r->images[r->nimages - 1];
        if (im->npaths != im->sheets)
            return bad_at(r, HV_ERR_BAD_INPUT, im->stack_line, "<v:imagestack> has sheetcount %llu but %zu imagesheets",
                          (unsigned long long)im->sheets, im->npaths);
    }
    return HV_OK;
}

static hv_status sax_start(void *ctx, tmf_xml *x, const char *local, const char *uri, const tmf_attr *a, int n)
{
    rd *r = ctx;
    r->x = x;
    r->local = local;
    r->uri = uri;
    r->qname = tmf_xml_qname(x);
    r->attrs = a;
    r->nattrs = n;
    int depth = r->depth++;
    if (depth >= MAX_DEPTH) return bad_at(r, HV_ERR_BAD_INPUT, line_of(r), "elements nested more than %d deep", MAX_DEPTH);
    kind parent = depth > 0 ? (kind)r->stack[depth - 1] : K_NONE;
    kind self = K_IGNORED;
    hv_status s = HV_OK;
    if (depth == 0 || (parent != K_IGNORED && parent != K_NONE)) s = on_element(r, classify(r), parent, depth, &self);
    r->stack[depth] = (int)self;
    r->attrs = NULL;
    r->nattrs = 0;
    return s;
}

static hv_status sax_end(void *ctx, tmf_xml *x, const char *local, const char *uri)
{
    (void)local, (void)uri;
    rd *r = ctx;
    r->x = x;
    r->qname = tmf_xml_qname(x); /* the element ending, for messages */
    return r->depth > 0 ? on_end(r, (kind)r->stack[--r->depth]) : HV_OK;
}

static hv_status read_model(rd *r)
{
    tmf_xml_handler h = {sax_start, sax_end};
    hv_status s = tmf_xml_parse(r->pk, r->part, r->pk->inflate_cap, &h, r);
    r->x = NULL;
    if (s == HV_OK && !r->resources_seen) s = bad_at(r, HV_ERR_BAD_INPUT, 0, "%s: the model has no <resources>", r->part);
    return s;
}

/* ---- the lattice and the occupancy ---------------------------------------------------------------------------- */

typedef struct lattice {
    double t[12];      /* object -> UVW */
    uint64_t n[3];     /* columns, rows, sheets */
} lattice;

typedef struct leafmap {
    int32_t *origins; /* 3 per leaf */
    uint64_t *masks;  /* 8 per leaf */
    size_t n, cap;
    int64_t *slot;    /* leaf + 1, 0 empty */
    size_t scap;
} leafmap;

static uint64_t lhash(int32_t x, int32_t y, int32_t z)
{
    uint64_t h = (uint64_t)(uint32_t)x * 0x9E3779B97F4A7C15ull ^ (uint64_t)(uint32_t)y * 0xC2B2AE3D27D4EB4Full ^
                 (uint64_t)(uint32_t)z * 0x165667B19E3779F9ull;
    return h ^ (h >> 29);
}

static hv_status leaf_set(rd *r, leafmap *m, int32_t i, int32_t j, int32_t k)
{
    int32_t o[3] = {i & ~7, j & ~7, k & ~7};
    if (2 * (m->n + 1) > m->scap) {
        size_t ncap = m->scap ? m->scap * 2 : 1024;
        hv_status s = charge(r, (uint64_t)(ncap - m->scap) * sizeof(int64_t), "occupancy");
        if (s != HV_OK) return s;
        int64_t *slot = hv_calloc(ncap, sizeof *slot);
        if (!slot) return HV_ERR_NOMEM;
        for (size_t l = 0; l < m->n; ++l) {
            size_t h = (size_t)lhash(m->origins[3 * l], m->origins[3 * l + 1], m->origins[3 * l + 2]) & (ncap - 1);
            while (slot[h]) h = (h + 1) & (ncap - 1);
            slot[h] = (int64_t)l + 1;
        }
        free(m->slot);
        m->slot = slot;
        m->scap = ncap;
    }
    size_t h = (size_t)lhash(o[0], o[1], o[2]) & (m->scap - 1);
    for (; m->slot[h]; h = (h + 1) & (m->scap - 1)) {
        size_t l = (size_t)m->slot[h] - 1;
        if (m->origins[3 * l] == o[0] && m->origins[3 * l + 1] == o[1] && m->origins[3 * l + 2] == o[2]) {
            unsigned n = HV_LEAF_OFFSET(i, j, k);
            m->masks[8 * l + (n >> 6)] |= 1ull << (n & 63);
            return HV_OK;
        }
    }
    if (m->n == m->cap) {
        size_t ncap = m->cap ? m->cap * 2 : 256;
        /* the leaves, and what they will cost in the model */
        hv_status s = charge(r, (uint64_t)(ncap - m->cap) * (3 * sizeof(int32_t) + 8 * sizeof(uint64_t) + r->leaf_bytes),
                             "the model's voxels");
        if (s != HV_OK) return s;
        int32_t *no = hv_realloc(m->origins, ncap * 3 * sizeof *no);
        if (!no) return HV_ERR_NOMEM;
        m->origins = no;
        uint64_t *nm = hv_realloc(m->masks, ncap * 8 * sizeof *nm);
        if (!nm) return HV_ERR_NOMEM;
        m->masks = nm;
        m->cap = ncap;
    }
    size_t l = m->n++;
    memcpy(m->origins + 3 * l, o, sizeof o);
    memset(m->masks + 8 * l, 0, 8 * sizeof(uint64_t));
    unsigned n = HV_LEAF_OFFSET(i, j, k);
    m->masks[8 * l + (n >> 6)] |= 1ull << (n & 63);
    m->slot[h] = (int64_t)l + 1;
    return HV_OK;
}

static void leafmap_free(leafmap *m)
{
    free(m->origins);
    free(m->masks);
    free(m->slot);
    memset(m, 0, sizeof *m);
}

/* The voxels (lattice index space: voxel centres at integers, s = UVW * n - 1/2) whose centres lie
 * inside the mesh: crossings of the columns through voxel centres with the triangles, sorted per
 * column; a voxel is inside when an odd number of crossings lie below its centre (ray parity; a
 * last unpaired crossing of an open column is dropped). */
/* The voxels whose centres lie inside the mesh (s3: its nv vertices in lattice index coordinates,
 * voxel centres on integers), shifted by off into hovox's indices: src/voxel's centre test (its
 * three-axis parity vote, the winding number where the lines tie; Wu 2.1 as DESIGN.md). For the
 * exact voxel boundaries hovox writes (faces on half-integers) it gives back exactly the voxels
 * exported. */
static hv_status occupancy(rd *r, const double *s3, size_t nv, const uint32_t *tri, size_t nt, const int64_t *off,
                           leafmap *out, uint64_t *voxels)
{
    *voxels = 0;
    if (nt == 0) return HV_OK;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t t = 0; t < 3 * nt; ++t)
        for (int a = 0; a < 3; ++a) {
            lo[a] = HV_MIN(lo[a], s3[3 * (size_t)tri[t] + (size_t)a]);
            hi[a] = HV_MAX(hi[a], s3[3 * (size_t)tri[t] + (size_t)a]);
        }
    int64_t glo[3], gn[3];
    double cells = 1;
    for (int a = 0; a < 3; ++a) {
        glo[a] = (int64_t)floor(lo[a]) & ~(int64_t)7;
        gn[a] = (((int64_t)ceil(hi[a]) + 1 - glo[a]) + 7) & ~(int64_t)7;
        cells *= (double)gn[a];
    }
    if (cells / 8 > (double)(r->budget / 2))
        return bad_at(r, HV_ERR_LIMIT, 0, "the mesh spans %.4g voxels of the image stack's lattice: too many for the "
                      "memory budget", cells);
    hv_status s = charge(r, hv_bitgrid_bytes(gn) + nv * (3 * sizeof(double) + 3 * sizeof(float)), "occupancy");
    if (s != HV_OK) return s;
    float *xyz = hv_malloc_array(nv, 3 * sizeof *xyz);
    if (!xyz) return HV_ERR_NOMEM;
    for (size_t i = 0; i < 3 * nv; ++i) xyz[i] = (float)s3[i];
    hv_mesh *m = NULL;
    s = hv_mesh_create(xyz, nv, tri, nt, &m);
    free(xyz);
    size_t mv = s == HV_OK ? hv_mesh_vertex_count(m) : 0;
    double *P = s == HV_OK ? hv_malloc_array(mv, 3 * sizeof *P) : NULL;
    if (s == HV_OK && !P) s = HV_ERR_NOMEM;
    for (size_t i = 0; s == HV_OK && i < mv; ++i)
        for (int a = 0; a < 3; ++a) P[3 * i + (size_t)a] = (double)hv_mesh_vertices(m)[3 * i + (size_t)a] - (double)glo[a];
    hv_bitgrid g;
    memset(&g, 0, sizeof g);
    if (s == HV_OK) s = hv_bitgrid_init(&g, gn, glo);
    if (s == HV_OK) s = hv_fill_centres(m, P, &g, NULL);
    for (int64_t i = 0; s == HV_OK && i < gn[0]; ++i)
        for (int64_t j = 0; s == HV_OK && j < gn[1]; ++j) {
            const uint64_t *row = hv_bitgrid_row(&g, i, j);
            for (int64_t w = 0; s == HV_OK && w < g.words; ++w)
                for (uint64_t bits = row[w] & hv_bitgrid_valid(&g, w); bits && s == HV_OK; bits &= bits - 1) {
                    int64_t k = 64 * w + __builtin_ctzll(bits);
                    s = leaf_set(r, out, (int32_t)(glo[0] + i + off[0]), (int32_t)(glo[1] + j + off[1]),
                                 (int32_t)(glo[2] + k + off[2]));
                    ++*voxels;
                }
        }
    hv_bitgrid_free(&g);
    free(P);
    hv_mesh_destroy(m);
    return s;
}

/* ---- the fractions --------------------------------------------------------------------------------------- */

/* A lattice index s onto an image index in [0, n) by the tile style (spec 2.2): at voxel centres
 * u = (s + 1/2) / n, so wrap is s mod n, mirror reflects every other period, clamp the edge. */
static int64_t tile_index(int64_t s, int64_t n, int style)
{
    if (style == 2) return s < 0 ? 0 : s >= n ? n - 1 : s;
    if (style == 1) {
        int64_t m = s % (2 * n);
        if (m < 0) m += 2 * n;
        return m < n ? m : 2 * n - 1 - m;
    }
    int64_t m = s % n;
    return m < 0 ? m + n : m;
}

typedef struct sheet_cache {
    int64_t sheet; /* decoded sheet, -1: none */
    hv_png_pixels px;
} sheet_cache;

static hv_status read_entry(rd *r, const char *part, uint8_t **data, size_t *size)
{
    if (!tmf_pkg_has(r->pk, part))
        return bad_at(r, HV_ERR_BAD_INPUT, 0, "the image sheet /%s is missing from the package", part);
    return tmf_pkg_read(r->pk, part, r->budget - HV_MIN(r->budget, r->used), data, size);
}

static hv_status load_sheet(rd *r, img3d *im, sheet_cache *c, int64_t sheet)
{
    if (c->sheet == sheet) return HV_OK;
    hv_png_pixels_free(&c->px);
    c->sheet = -1;
    uint8_t *data = NULL;
    size_t size = 0;
    const char *part = im->paths[sheet];
    hv_status s = read_entry(r, part, &data, &size);
    if (s != HV_OK) return s;
    char label[1300];
    const int *at = im->lines + 2 * sheet;
    snprintf(label, sizeof label, "%s: %s: line %d, column %d: <v:imagesheet> /%s", r->name, r->part, at[0], at[1], part);
    s = hv_png_decode(data, size, label, (uint64_t)im->rows * im->cols * 4, &c->px);
    free(data);
    if (s == HV_ERR_LIMIT || (s == HV_OK && ((uint64_t)c->px.width != im->cols || (uint64_t)c->px.height != im->rows))) {
        uint64_t w = s == HV_OK ? (uint64_t)c->px.width : 0, h = s == HV_OK ? (uint64_t)c->px.height : 0;
        hv_png_pixels_free(&c->px);
        if (s == HV_OK)
            return bad_at_col(r, HV_ERR_BAD_INPUT, at[0], at[1], "<v:imagesheet> /%s is %llu x %llu pixels; its "
                          "<v:imagestack> has %llu columns and %llu rows", part, (unsigned long long)w,
                          (unsigned long long)h, (unsigned long long)im->cols, (unsigned long long)im->rows);
        return bad_at_col(r, HV_ERR_BAD_INPUT, at[0], at[1], "<v:imagesheet> /%s is larger than its <v:imagestack> of "
                      "%llu x %llu", part, (unsigned long long)im->cols, (unsigned long long)im->rows);
    }
    if (s != HV_OK) return s;
    if (!im->channels) {
        im->channels = c->px.channels;
        im->bits = c->px.bit_depth;
    } else if (im->channels != c->px.channels || im->bits != c->px.bit_depth) {
        hv_png_pixels_free(&c->px);
        return bad_at_col(r, HV_ERR_BAD_INPUT, at[0], at[1], "<v:imagesheet> /%s differs in pixel layout from the "
                      "sheets before it in its stack", part);
    }
    c->sheet = sheet;
    return HV_OK;
}

/* A channel of a sample normalised to [0, 1] (spec 3.2: Y gives red, green and blue; missing
 * alpha is 1). */
static double channel_value(const hv_png_pixels *px, size_t at, int ch)
{
    int n = px->channels;
    double max = px->bit_depth == 16 ? 65535.0 : 255.0;
    const uint16_t *p = px->samples + at * (size_t)n;
    int idx;
    if (ch == 3) idx = n == 2 ? 1 : n == 4 ? 3 : -1;
    else idx = n >= 3 ? ch : 0;
    return idx < 0 ? 1.0 : p[idx] / max;
}

typedef struct zleaf {
    int32_t z;
    size_t leaf;
} zleaf;

static int cmp_zleaf(const void *a, const void *b)
{
    const zleaf *p = a, *q = b;
    if (p->z != q->z) return p->z < q->z ? -1 : 1;
    return p->leaf < q->leaf ? -1 : p->leaf > q->leaf;
}

/* ---- putting it together --------------------------------------------------------------------------------- */

typedef struct used {
    const object *obj;
    const voldata *vd;
    const bgroup *bg;
    const func *f[HV_MAX_MATERIALS];
    img3d *im[HV_MAX_MATERIALS];
    const func *cf, *mf; /* the colour's function and the colour mask's (NULL: none) */
    img3d *cim, *mim;
    int mask_channel;    /* the mask's output: 0 red, 1 green, 2 blue, 3 alpha */
    int lattice_line;    /* the element whose transform gives the lattice */
    double shift[3];     /* the build item's translation */
} used;

/* The fractions of the voxels of leaf l at height z, from the decoded sheets. */
static void fill_layer(const used *u, hv_volume *v, const int *grid, size_t l, int64_t z, const int64_t *off,
                       const sheet_cache *cache, const int *cache_of)
{
    int m = u->bg->n;
    const int32_t *o = hv_volume_leaf_origins(v) + 3 * l;
    const uint64_t *mask = hv_volume_leaf_mask(v, l);
    float *dst[HV_MAX_MATERIALS];
    for (int j = 0; j < m; ++j) dst[j] = hv_volume_leaf_float(v, grid[j], l);
    for (unsigned x = 0; x < 8; ++x)
        for (unsigned y = 0; y < 8; ++y) {
            unsigned n = (x << 6) | (y << 3) | (unsigned)(z & 7);
            if (!HV_BIT_GET(mask, n)) continue;
            int64_t si = o[0] + (int64_t)x - off[0], sj = o[1] + (int64_t)y - off[1];
            double val[HV_MAX_MATERIALS], sum = 0;
            for (int j = 0; j < m; ++j) {
                const img3d *im = u->im[j];
                int64_t col = tile_index(si, (int64_t)im->cols, u->f[j]->tile[0]);
                int64_t row = (int64_t)im->rows - 1 - tile_index(sj, (int64_t)im->rows, u->f[j]->tile[1]);
                double c = channel_value(&cache[cache_of[j]].px, (size_t)row * im->cols + (size_t)col,
                                         u->vd->maps[j].channel);
                c = c * u->f[j]->scale + u->f[j]->offset;
                val[j] = c > 1 ? 1 : c > 0 ? c : 0; /* NaN, < 0: 0 (spec 5.2.3) */
                sum += val[j];
            }
            for (int j = 0; j < m; ++j) dst[j][n] = sum >= 1e-5 ? (float)(val[j] / sum) : (j == 0 ? 1.0f : 0.0f);
        }
}

static const void *find_res(const void *arr, size_t n, size_t size, uint32_t id)
{
    for (size_t i = 0; i < n; ++i) {
        const void *e = (const char *)arr + i * size;
        if (*(const uint32_t *)e == id) return e;
    }
    return NULL;
}

static int cmp_resid(const void *a, const void *b)
{
    const resid *p = a, *q = b;
    if (p->id != q->id) return p->id < q->id ? -1 : 1;
    return p->line - q->line;
}

static int near_zero(double v, double scale) { return fabs(v) <= 1e-12 * scale; }

static const char *const k_scalars[4] = {"red", "green", "blue", "alpha"};

/* The function a <v:color> (vector: its output must be color) or the colour mask (a scalar output)
 * names, and its image stack, every sheet in the package: *ch the scalar's channel. */
static hv_status resolve_field(rd *r, const fieldref *fr, const char *elem, int vector, const func **fo, img3d **io,
                               int *ch)
{
    const func *f = find_res(r->funcs, r->nfuncs, sizeof *r->funcs, fr->functionid);
    if (!f) return bad_at_col(r, HV_ERR_BAD_INPUT, fr->line, fr->col, "%s functionid %u names no function", elem, fr->functionid);
    if (f->kind != F_IMAGE)
        return bad_at_col(r, HV_ERR_UNSUPPORTED, fr->line, fr->col, "%s functionid %u is a <%s> (line %d): only "
                          "functionfromimage3d is supported", elem, fr->functionid, f->elem, f->line);
    *ch = -1;
    for (int c = 0; c < 4 && !vector; ++c)
        if (strcmp(fr->channel, k_scalars[c]) == 0) *ch = c;
    if (vector ? strcmp(fr->channel, "color") != 0 : *ch < 0)
        return bad_at_col(r, HV_ERR_BAD_INPUT, fr->line, fr->col, "%s channel '%s' is not a %s output of the "
                          "<v:functionfromimage3d> on line %d (%s)", elem, fr->channel, vector ? "vector" : "scalar",
                          f->line, vector ? "color; red, green, blue and alpha are scalars" : "red, green, blue or alpha");
    img3d *im = (img3d *)find_res(r->images, r->nimages, sizeof *r->images, f->image3did);
    if (!im) return bad_at(r, HV_ERR_BAD_INPUT, f->line, "<%s> image3did %u names no <v:image3d>", f->elem, f->image3did);
    if (!im->has_stack)
        return bad_at(r, HV_ERR_UNSUPPORTED, im->line, "<v:image3d> %u has no <v:imagestack> (other image kinds are "
                      "not supported)", im->id);
    for (size_t k = 0; k < im->npaths; ++k)
        if (!tmf_pkg_has(r->pk, im->paths[k]))
            return bad_at_col(r, HV_ERR_BAD_INPUT, im->lines[2 * k], im->lines[2 * k + 1],
                              "<v:imagesheet> /%s is missing from the package", im->paths[k]);
    *fo = f;
    *io = im;
    return HV_OK;
}

/* A transform hovox can take a lattice from: an axis-aligned scale with positive diagonal and a
 * translation. */
static int axis_aligned(const double *t)
{
    double big = 0;
    for (int k = 0; k < 12; ++k) big = HV_MAX(big, fabs(t[k]));
    return t[0] > 0 && t[4] > 0 && t[8] > 0 && near_zero(t[1], big) && near_zero(t[2], big) && near_zero(t[3], big) &&
           near_zero(t[5], big) && near_zero(t[6], big) && near_zero(t[7], big);
}

/* A lattice for a colour whose transform is not an axis-aligned scale (the spec allows any affine
 * one, 2.2 and 6): axis-aligned cubic voxels over the mesh's box, as fine as the image's finest
 * step - one image voxel along image axis b spans 1/(n_b |grad w_b|) object units across its
 * planes (a w_b that does not vary, as a picture extruded through the part, sets none) - so every
 * voxel centre samples the function through the colour's own transform, as a mapping's lattice
 * samples a colour of its own. */
static hv_status colour_lattice(rd *r, const used *u, const double *t, lattice *lat)
{
    const object *o = u->obj;
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, h = HUGE_VAL, ext = 0;
    for (size_t v = 0; v < o->nv; ++v)
        for (int a = 0; a < 3; ++a) {
            double x = r->xyz[3 * (o->v0 + v) + (size_t)a];
            lo[a] = fmin(lo[a], x);
            hi[a] = fmax(hi[a], x);
        }
    const uint64_t n[3] = {u->cim->cols, u->cim->rows, u->cim->sheets};
    for (int b = 0; b < 3; ++b) {
        double g = sqrt(t[b] * t[b] + t[3 + b] * t[3 + b] + t[6 + b] * t[6 + b]) * (double)n[b];
        if (g > 0 && isfinite(g)) h = fmin(h, 1.0 / g);
    }
    for (int a = 0; a < 3; ++a) ext = fmax(ext, hi[a] - lo[a]);
    if (!(h < HUGE_VAL)) h = ext / 64; /* one colour everywhere: any voxels carry it */
    if (!(h > 0 && isfinite(h)))
        return bad_at_col(r, HV_ERR_BAD_INPUT, u->vd->colour.line, u->vd->colour.col, "<v:color> transform gives "
                          "image voxels of %g object units", h);
    for (int a = 0; a < 3; ++a) {
        double na = fmax(1, ceil((hi[a] - lo[a]) / h));
        if (!(na < 1e9))
            return bad_at_col(r, HV_ERR_LIMIT, u->vd->colour.line, u->vd->colour.col, "<v:color> transform: the "
                              "mesh spans %.4g of the image's voxels: too many to sample", na);
        lat->n[a] = (uint64_t)na;
        for (int b = 0; b < 3; ++b) lat->t[3 * a + b] = a == b ? 1.0 / (h * na) : 0;
        lat->t[9 + a] = -lo[a] / (h * na);
    }
    return HV_OK;
}

/* Volume data with a colour and no composite (another producer's colour): the colour's stack gives
 * the lattice when its transform is an axis-aligned scale, else colour_lattice does; the model is
 * printed in the six colour resins (colour_resins). */
static hv_status resolve_colour_alone(rd *r, used *u, lattice *lat)
{
    const voldata *vd = u->vd;
    int ch;
    hv_status s = resolve_field(r, &vd->colour, "<v:color>", 1, &u->cf, &u->cim, &ch);
    if (s == HV_OK && vd->mask.present)
        s = resolve_field(r, &vd->mask, "<v:property> hovox:colour.mask", 0, &u->mf, &u->mim, &u->mask_channel);
    if (s != HV_OK) return s;
    u->lattice_line = vd->colour.line;
    if (!axis_aligned(vd->colour.t)) return colour_lattice(r, u, vd->colour.t, lat);
    memcpy(lat->t, vd->colour.t, sizeof lat->t);
    lat->n[0] = u->cim->cols;
    lat->n[1] = u->cim->rows;
    lat->n[2] = u->cim->sheets;
    return HV_OK;
}

static hv_status resolve(rd *r, used *u, lattice *lat)
{
    memset(u, 0, sizeof *u);
    if (r->nids) qsort(r->ids, r->nids, sizeof *r->ids, cmp_resid);
    for (size_t i = 1; i < r->nids; ++i)
        if (r->ids[i].id == r->ids[i - 1].id)
            return bad_at(r, HV_ERR_BAD_INPUT, r->ids[i].line, "resource id %u is used twice (also on line %d)", r->ids[i].id,
                          r->ids[i - 1].line);
    if (r->nitems == 0) return bad_at(r, HV_ERR_BAD_INPUT, 0, "%s: the <build> has no <item>", r->part);
    if (r->nitems > 1)
        return bad_at(r, HV_ERR_UNSUPPORTED, r->items[1].line, "<item>: the build has %zu items; hovox reads a package "
                      "of one object", r->nitems);
    const item *it = &r->items[0];
    u->obj = find_res(r->objects, r->nobjects, sizeof *r->objects, it->objectid);
    if (!u->obj)
        return bad_at(r, HV_ERR_BAD_INPUT, it->line, "<item> objectid %u names no <object>", it->objectid);
    if (it->has_t) {
        const double *t = it->t;
        if (!(t[0] == 1 && t[4] == 1 && t[8] == 1 && t[1] == 0 && t[2] == 0 && t[3] == 0 && t[5] == 0 && t[6] == 0 &&
              t[7] == 0))
            return bad_at(r, HV_ERR_UNSUPPORTED, it->line, "<item> transform rotates or scales the object; hovox reads "
                          "translations only");
        for (int a = 0; a < 3; ++a) u->shift[a] = t[9 + a];
    }
    const object *o = u->obj;
    if (o->kind == O_COMPONENTS)
        return bad_at(r, HV_ERR_UNSUPPORTED, o->mesh_line, "<components> of object %u: hovox reads one mesh object", o->id);
    if (o->kind == O_LEVELSET)
        return bad_at(r, HV_ERR_UNSUPPORTED, o->mesh_line, "<v:levelset> of object %u: level-set shapes are not "
                      "supported", o->id);
    if (o->kind != O_MESH) return bad_at(r, HV_ERR_BAD_INPUT, o->line, "<object> %u has no mesh", o->id);
    if (!o->has_volumeid)
        return bad_at(r, HV_ERR_UNSUPPORTED, o->mesh_line, "<mesh> of object %u carries no volume data (v:volumeid): "
                      "nothing graded to read (voxelize the mesh instead)", o->id);
    if (o->nt == 0) return bad_at(r, HV_ERR_BAD_INPUT, o->mesh_line, "<mesh> of object %u has no triangles", o->id);
    u->vd = find_res(r->vols, r->nvols, sizeof *r->vols, o->volumeid);
    if (!u->vd)
        return bad_at(r, HV_ERR_BAD_INPUT, o->mesh_line, "<mesh> volumeid %u names no <v:volumedata>", o->volumeid);
    const voldata *vd = u->vd;
    if (vd->refuse_line) return bad_at(r, HV_ERR_UNSUPPORTED, vd->refuse_line, "%s", vd->refuse);
    if (!vd->composites && vd->colour.present) return resolve_colour_alone(r, u, lat);
    if (!vd->composites)
        return bad_at(r, HV_ERR_UNSUPPORTED, vd->line, "<v:volumedata> %u has no <v:composite> and no <v:color>: hovox "
                      "reads material compositions and colours", vd->id);
    u->lattice_line = vd->maps ? vd->maps[0].line : vd->line;
    u->bg = find_res(r->groups, r->ngroups, sizeof *r->groups, vd->basematerialid);
    if (!u->bg)
        return bad_at(r, HV_ERR_BAD_INPUT, vd->composite_line, "<v:composite> basematerialid %u names no "
                      "<basematerials>", vd->basematerialid);
    if (vd->nmaps < 1 || vd->nmaps != u->bg->n)
        return bad_at(r, HV_ERR_BAD_INPUT, vd->composite_line, "<v:composite> has %d materialmappings for the %d base "
                      "materials of <basematerials> %u", vd->nmaps, u->bg->n, u->bg->id);
    for (int j = 0; j < vd->nmaps; ++j) {
        const mapping *m = &vd->maps[j];
        const func *f = find_res(r->funcs, r->nfuncs, sizeof *r->funcs, m->functionid);
        if (!f) return bad_at(r, HV_ERR_BAD_INPUT, m->line, "<v:materialmapping> functionid %u names no function", m->functionid);
        if (f->kind != F_IMAGE)
            return bad_at(r, HV_ERR_UNSUPPORTED, m->line, "<v:materialmapping> functionid %u is a <%s> (line %d): only "
                          "functionfromimage3d is supported", m->functionid, f->elem, f->line);
        img3d *im = (img3d *)find_res(r->images, r->nimages, sizeof *r->images, f->image3did);
        if (!im) return bad_at(r, HV_ERR_BAD_INPUT, f->line, "<%s> image3did %u names no <v:image3d>", f->elem, f->image3did);
        if (!im->has_stack)
            return bad_at(r, HV_ERR_UNSUPPORTED, im->line, "<v:image3d> %u has no <v:imagestack> (other image kinds are "
                          "not supported)", im->id);
        u->f[j] = f;
        u->im[j] = im;
        /* the transform: an axis-aligned scale with positive diagonal, and a translation */
        const double *t = m->t;
        if (!axis_aligned(t))
            return bad_at(r, HV_ERR_UNSUPPORTED, m->line, "<v:materialmapping> transform is not an axis-aligned scale "
                          "and translation (rotations, shears and mirrors are not supported)");
        uint64_t n[3] = {im->cols, im->rows, im->sheets};
        if (j == 0) {
            memcpy(lat->t, t, sizeof lat->t);
            memcpy(lat->n, n, sizeof lat->n);
            continue;
        }
        /* every mapping samples the same voxel centres */
        for (int a = 0; a < 3; ++a) {
            double s0 = lat->t[4 * a] * (double)lat->n[a], s1 = t[4 * a] * (double)n[a];
            double c0 = lat->t[9 + a] * (double)lat->n[a], c1 = t[9 + a] * (double)n[a];
            if (fabs(s0 - s1) > 1e-9 * s0 || fabs((c0 - c1) / s0) > 1e-6)
                return bad_at(r, HV_ERR_UNSUPPORTED, m->line, "<v:materialmapping> samples another voxel lattice than "
                              "the first mapping (line %d): hovox needs one lattice", vd->maps[0].line);
        }
    }
    /* every sheet of the stacks in use is in the package */
    for (int j = 0; j < vd->nmaps; ++j)
        for (size_t k = 0; k < u->im[j]->npaths; ++k)
            if (!tmf_pkg_has(r->pk, u->im[j]->paths[k]))
                return bad_at_col(r, HV_ERR_BAD_INPUT, u->im[j]->lines[2 * k], u->im[j]->lines[2 * k + 1],
                                  "<v:imagesheet> /%s is missing from the package", u->im[j]->paths[k]);
    /* the colour, and where it was asked for (a mask without a colour means nothing) */
    int ch;
    hv_status s = HV_OK;
    if (vd->colour.present) s = resolve_field(r, &vd->colour, "<v:color>", 1, &u->cf, &u->cim, &ch);
    if (s == HV_OK && vd->colour.present && vd->mask.present)
        s = resolve_field(r, &vd->mask, "<v:property> hovox:colour.mask", 0, &u->mf, &u->mim, &u->mask_channel);
    return s;
}

/* Material names hovox accepts: [A-Za-z0-9_-], 1-64 bytes, unique. */
static void material_names(const bgroup *g, char (*out)[72])
{
    for (int j = 0; j < g->n; ++j) {
        const char *s = g->names[j];
        size_t o = 0;
        for (size_t i = 0; s[i] && o < 64; ++i) {
            char c = s[i];
            out[j][o++] = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_'
                              ? c
                              : '_';
        }
        if (o == 0) out[j][o++] = 'm';
        out[j][o] = '\0';
        for (int k = 0, dup = 1; k < j; ++k)
            if (strcmp(out[k], out[j]) == 0) {
                char tmp[72];
                snprintf(tmp, sizeof tmp, "%.56s_%d", out[j], ++dup);
                memcpy(out[j], tmp, sizeof tmp);
                k = -1;
            }
    }
}

static hv_status build_table(rd *r, const used *u, hv_material_table **out)
{
    *out = NULL;
    char names[HV_MAX_MATERIALS][72];
    material_names(u->bg, names);
    if (r->materials_json) { /* hovox's own table, when it names the same materials */
        hv_material_table *t = NULL;
        if (hv_material_table_from_json(r->materials_json, &t) == HV_OK && hv_material_count(t) == u->bg->n) {
            int same = 1;
            for (int j = 0; j < u->bg->n && same; ++j) same = strcmp(hv_material_name(t, j), names[j]) == 0;
            if (same) {
                *out = t;
                return HV_OK;
            }
        }
        hv_material_table_destroy(t);
        hv_error_clear();
    }
    hv_material_table *t;
    hv_status s = hv_material_table_create(&t);
    for (int j = 0; j < u->bg->n && s == HV_OK; ++j) s = hv_material_add(t, names[j], u->bg->rgba + 4 * j, NULL);
    if (s != HV_OK) {
        hv_material_table_destroy(t);
        return s;
    }
    *out = t;
    return HV_OK;
}

/* the hovox lattice of an image stack: voxel size and origin in mm, and OFF with hovox index = lattice
   index + OFF (with the origin hovox wrote, its own lattice comes back) */
static hv_status lattice_transform(rd *r, const used *u, const lattice *lat, hv_transform *xf, int64_t off[3])
{
    const double *t = lat->t;
    for (int a = 0; a < 3; ++a) {
        double L = 1.0 / (t[4 * a] * (double)lat->n[a]);           /* object units */
        double c0 = (-t[9 + a] / t[4 * a] + 0.5 * L + u->shift[a]) * r->unit; /* centre of s = 0, mm */
        xf->voxel[a] = L * r->unit;
        if (!(xf->voxel[a] > 0 && isfinite(xf->voxel[a]) && isfinite(c0)))
            return bad_at(r, HV_ERR_BAD_INPUT, u->lattice_line, "<%s> transform gives voxels of %g mm",
                          u->bg ? "v:materialmapping" : "v:color", xf->voxel[a]);
        double k = r->has_origin ? floor((c0 - r->origin_meta[a]) / xf->voxel[a] + 0.5) : floor(c0 / xf->voxel[a]);
        if (r->has_origin && fabs((c0 - r->origin_meta[a]) / xf->voxel[a] - k) > 1e-6) k = floor(c0 / xf->voxel[a]);
        if (!(fabs(k) < 1e9)) k = 0;
        off[a] = (int64_t)k;
        xf->origin[a] = r->has_origin && fabs((c0 - r->origin_meta[a]) / xf->voxel[a] - k) <= 1e-6
                           ? r->origin_meta[a]
                            : c0 - k * xf->voxel[a];
    }
    return HV_OK;
}

/* object O's mesh, in millimetres */
static hv_status object_mesh(rd *r, const used *u, hv_mesh **mesh)
{
    const object *o = u->obj;
    hv_status s = HV_OK;
    float *xyz = hv_malloc_array(o->nv, 3 * sizeof(float));
    if (!xyz) s = HV_ERR_NOMEM;
    for (size_t k = 0; s == HV_OK && k < o->nv; ++k)
        for (int a = 0; a < 3; ++a)
            xyz[3 * k + (size_t)a] = (float)((r->xyz[3 * (o->v0 + k) + (size_t)a] + u->shift[a]) * r->unit);
    if (s == HV_OK) s = hv_mesh_create(xyz, o->nv, r->tri + 3 * o->t0, o->nt, mesh);
    if (s != HV_OK && s != HV_ERR_NOMEM) s = bad_at(r, HV_ERR_BAD_INPUT, o->mesh_line, "<mesh>: %s", hv_last_error());
    free(xyz);
    return s;
}

/* ---- the colour ----------------------------------------------------------------------------------------- */

/* A function sampled anywhere (spec 2.2): its stack's decoded sheets kept in a few slots, the
 * least recently used one decoded again. */
enum { SAMPLER_SLOTS = 4 };
typedef struct sampler {
    const func *f;
    img3d *im;
    const double *t; /* object -> the function's UVW (the element's transform) */
    sheet_cache slot[SAMPLER_SLOTS];
    uint64_t last[SAMPLER_SLOTS], tick;
    sheet_cache *all; /* per sheet of the stack: a slab's sheets decoded beforehand (colour_slab), or NULL */
    int shared;       /* read from `all` alone (threads sample at once): a sheet not there is a bug */
} sampler;

static hv_status sampler_init(rd *r, sampler *sp, const func *f, img3d *im, const double *t)
{
    memset(sp, 0, sizeof *sp);
    sp->f = f;
    sp->im = im;
    sp->t = t;
    for (int i = 0; i < SAMPLER_SLOTS; ++i) sp->slot[i].sheet = -1;
    uint64_t sheet = im->rows * im->cols; /* each at most 1024^3: below 2^60 */
    if (sheet > UINT64_MAX / (SAMPLER_SLOTS * 4 * sizeof(uint16_t))) return over_budget(r, "image sheets");
    return charge(r, sheet * SAMPLER_SLOTS * 4 * sizeof(uint16_t), "image sheets");
}

static void sampler_free(sampler *sp)
{
    for (int i = 0; i < SAMPLER_SLOTS; ++i) hv_png_pixels_free(&sp->slot[i].px);
    for (size_t k = 0; sp->all && k < sp->im->sheets; ++k) hv_png_pixels_free(&sp->all[k].px);
    free(sp->all);
    sp->all = NULL;
}

static hv_status sampler_sheet(rd *r, sampler *sp, int64_t k, const hv_png_pixels **px)
{
    if (sp->all && sp->all[k].sheet == k) {
        *px = &sp->all[k].px;
        return HV_OK;
    }
    if (sp->shared) return hv_error_set(HV_ERR_INTERNAL, "3MF colour: sheet %lld was not decoded", (long long)k);
    int victim = 0;
    for (int i = 0; i < SAMPLER_SLOTS; ++i) {
        if (sp->slot[i].sheet == k) {
            sp->last[i] = ++sp->tick;
            *px = &sp->slot[i].px;
            return HV_OK;
        }
        if (sp->last[i] < sp->last[victim]) victim = i;
    }
    sp->last[victim] = ++sp->tick;
    *px = &sp->slot[victim].px;
    return load_sheet(r, sp->im, &sp->slot[victim], k);
}

/* The function's R, G, B and A (spec 3.2's table) at object point x, scaled and offset (2.2). The
 * point's UVW as image indices (voxel centres on integers; rows run down from the highest v, ties
 * of "nearest" go to the lower index), each tap's index tiled by the tile style, "linear"
 * trilinear between the eight around it. */
static void axis_taps(const sampler *sp, const double x[3], int b, int64_t idx[2], double wt[2])
{
    const double *t = sp->t;
    const int64_t n = (int64_t)(b == 0 ? sp->im->cols : b == 1 ? sp->im->rows : sp->im->sheets);
    double w = x[0] * t[b] + x[1] * t[3 + b] + x[2] * t[6 + b] + t[9 + b];
    double q = (b == 1 ? 1 - w : w) * (double)n - 0.5;
    q = q > -1e15 && q < 1e15 ? q : q > 0 ? 1e15 : -1e15; /* far off (and NaN): an edge */
    double f0 = sp->f->nearest ? ceil(q - 0.5) : floor(q), fr = sp->f->nearest ? 0 : q - f0;
    idx[0] = tile_index((int64_t)f0, n, sp->f->tile[b]);
    idx[1] = tile_index((int64_t)f0 + 1, n, sp->f->tile[b]);
    wt[0] = 1 - fr;
    wt[1] = fr;
}

static hv_status sample_rgba(rd *r, sampler *sp, const double x[3], double out[4])
{
    const img3d *im = sp->im;
    int64_t idx[3][2];
    double wt[3][2];
    for (int b = 0; b < 3; ++b) axis_taps(sp, x, b, idx[b], wt[b]);
    double acc[4] = {0, 0, 0, 0};
    for (int kz = 0; kz < 2; ++kz) {
        if (wt[2][kz] == 0) continue;
        const hv_png_pixels *px = NULL;
        hv_status s = sampler_sheet(r, sp, idx[2][kz], &px);
        if (s != HV_OK) return s;
        for (int ky = 0; ky < 2; ++ky)
            for (int kx = 0; kx < 2; ++kx) {
                double w = wt[2][kz] * wt[1][ky] * wt[0][kx];
                if (w == 0) continue;
                size_t at = (size_t)idx[1][ky] * im->cols + (size_t)idx[0][kx];
                for (int c = 0; c < 4; ++c) acc[c] += w * channel_value(px, at, c);
            }
    }
    for (int c = 0; c < 4; ++c) out[c] = acc[c] * sp->f->scale + sp->f->offset;
    return HV_OK;
}

/* The <v:color> of a package read into grids colour.r, .g, .b (the sRGB asked for: the colour is
 * linear sRGB, spec 5.2.1, each channel truncated to [0, 1]) and colour.mask (hovox's property
 * hovox:colour.mask above one half; 1 everywhere without it), as a painted model holds them. */
typedef struct colour_job {
    sampler col, mask;
    int has_mask, mask_shared; /* the mask is the colour's sample's channel (same function and transform) */
    int mask_channel;
    int grid[4];
    const lattice *lat;
    const int64_t *off;
    uint64_t allowance; /* bytes a slab's decoded sheets may take (charged), else one thread's LRU */
    rd *r;
    hv_volume *v;
    const zleaf *zl; /* the slab being sampled */
    int32_t z0;
} colour_job;

uint64_t tmf_colour_sheets_max = (uint64_t)1 << 30;

static hv_status colour_begin(rd *r, const used *u, const lattice *lat, const int64_t *off, hv_volume *v, colour_job *cj)
{
    const voldata *vd = u->vd;
    memset(cj, 0, sizeof *cj);
    cj->lat = lat;
    cj->off = off;
    static const char *const k_grids[4] = {"colour.r", "colour.g", "colour.b", "colour.mask"};
    hv_status s = HV_OK;
    for (int k = 0; k < 4 && s == HV_OK; ++k) s = hv_volume_grid_add(v, k_grids[k], HV_GRID_FLOAT, &cj->grid[k]);
    if (s == HV_OK) s = sampler_init(r, &cj->col, u->cf, u->cim, vd->colour.t);
    cj->has_mask = u->mf != NULL;
    cj->mask_channel = u->mask_channel;
    cj->mask_shared = cj->has_mask && u->mf == u->cf && memcmp(vd->mask.t, vd->colour.t, sizeof vd->mask.t) == 0;
    if (s == HV_OK && cj->has_mask && !cj->mask_shared) s = sampler_init(r, &cj->mask, u->mf, u->mim, vd->mask.t);
    /* a slab's sheets decoded once for all threads: a quarter of what is left of the budget, at most
     * tmf_colour_sheets_max */
    uint64_t left = r->budget - HV_MIN(r->budget, r->used);
    cj->allowance = HV_MIN(left / 4, tmf_colour_sheets_max);
    if (s == HV_OK && charge(r, cj->allowance, "image sheets") != HV_OK) {
        hv_error_clear();
        cj->allowance = 0;
    }
    cj->r = r;
    cj->v = v;
    return s;
}

static void colour_end(colour_job *cj)
{
    sampler_free(&cj->col);
    sampler_free(&cj->mask);
}

static double unit_clamp(double v) { return v > 0 ? (v < 1 ? v : 1) : 0; /* NaN: 0 */ }

/* The centre of voxel (i, j) of the leaf at origin o, at height z, in object coordinates: from its
 * lattice index (voxel centres on integers). */
static void voxel_centre(const colour_job *cj, const int32_t *o, unsigned i, unsigned j, int64_t z, double x[3])
{
    const double *t = cj->lat->t;
    int64_t s3[3] = {o[0] + (int64_t)i - cj->off[0], o[1] + (int64_t)j - cj->off[1], z - cj->off[2]};
    for (int a = 0; a < 3; ++a) x[a] = (((double)s3[a] + 0.5) / (double)cj->lat->n[a] - t[9 + a]) / t[4 * a];
}

/* The colour of the voxels of leaf l at height z. */
static hv_status colour_layer(rd *r, colour_job *cj, hv_volume *v, size_t l, int64_t z)
{
    const int32_t *o = hv_volume_leaf_origins(v) + 3 * l;
    const uint64_t *on = hv_volume_leaf_mask(v, l);
    float *dst[4];
    for (int k = 0; k < 4; ++k) dst[k] = hv_volume_leaf_float(v, cj->grid[k], l);
    for (unsigned i = 0; i < 8; ++i)
        for (unsigned j = 0; j < 8; ++j) {
            unsigned n = (i << 6) | (j << 3) | (unsigned)(z & 7);
            if (!HV_BIT_GET(on, n)) continue;
            double x[3], rgba[4], m[4];
            voxel_centre(cj, o, i, j, z, x);
            hv_status s = sample_rgba(r, &cj->col, x, rgba);
            if (s == HV_OK && cj->has_mask && !cj->mask_shared) s = sample_rgba(r, &cj->mask, x, m);
            if (s != HV_OK) return s;
            double mask = !cj->has_mask ? 1 : unit_clamp(cj->mask_shared ? rgba[cj->mask_channel] : m[cj->mask_channel]);
            int asked = mask > 0.5;
            for (int c = 0; c < 3; ++c) dst[c][n] = asked ? (float)tmf_linear_to_srgb(unit_clamp(rgba[c])) : 0.0f;
            dst[3][n] = asked ? 1.0f : 0.0f;
        }
    return HV_OK;
}

/* Mark the sheets of sp the voxels of a slab's leaves sample (the taps sample_rgba reads along w). */
static void mark_sheets(const colour_job *cj, const sampler *sp, const zleaf *zl, size_t n, int32_t z0, uint8_t *need)
{
    for (size_t li = 0; li < n; ++li) {
        const int32_t *o = hv_volume_leaf_origins(cj->v) + 3 * zl[li].leaf;
        const uint64_t *on = hv_volume_leaf_mask(cj->v, zl[li].leaf);
        for (int64_t z = z0; z < (int64_t)z0 + 8; ++z)
            for (unsigned i = 0; i < 8; ++i)
                for (unsigned j = 0; j < 8; ++j) {
                    if (!HV_BIT_GET(on, (i << 6) | (j << 3) | (unsigned)(z & 7))) continue;
                    double x[3], wt[2];
                    int64_t idx[2];
                    voxel_centre(cj, o, i, j, z, x);
                    axis_taps(sp, x, 2, idx, wt);
                    for (int k = 0; k < 2; ++k)
                        if (wt[k] != 0) need[idx[k]] = 1;
                }
    }
}

/* Decode the sheets of sp a slab needs, in ascending order, into sp->all (those it no longer needs
 * freed). */
static hv_status slab_sheets(colour_job *cj, sampler *sp, const uint8_t *need)
{
    if (!sp->all) {
        if (!(sp->all = hv_calloc(sp->im->sheets, sizeof *sp->all))) return HV_ERR_NOMEM;
        for (size_t k = 0; k < sp->im->sheets; ++k) sp->all[k].sheet = -1;
    }
    for (size_t k = 0; k < sp->im->sheets; ++k)
        if (!need[k] && sp->all[k].sheet >= 0) {
            hv_png_pixels_free(&sp->all[k].px);
            sp->all[k].sheet = -1;
        }
    for (size_t k = 0; k < sp->im->sheets; ++k) {
        if (!need[k] || sp->all[k].sheet == (int64_t)k) continue;
        sp->all[k].sheet = -1;
        hv_status s = load_sheet(cj->r, sp->im, &sp->all[k], (int64_t)k);
        if (s != HV_OK) return s;
    }
    return HV_OK;
}

static hv_status colour_chunk(void *ctx, size_t begin, size_t end, int thread)
{
    (void)thread;
    colour_job *cj = ctx;
    for (size_t li = begin; li < end; ++li)
        for (int64_t z = cj->z0; z < (int64_t)cj->z0 + 8; ++z) {
            hv_status s = colour_layer(cj->r, cj, cj->v, cj->zl[li].leaf, z);
            if (s != HV_OK) return s;
        }
    return HV_OK;
}

/* The colour of a slab's leaves (issue 29 item 4: on the library's threads). The sheets its voxels
 * sample are decoded first, on this thread, in ascending order (the package is read by one thread;
 * a damaged sheet is reported the same way whatever the threads), then the leaves are sampled in
 * parallel, reading them alone; each voxel's colour is computed as before, so the model does not
 * depend on the thread count. When the sheets would take more than cj->allowance, one thread
 * samples through its few least-recently-used sheets (the colour's reader before). */
static hv_status colour_slab(colour_job *cj, const zleaf *zl, size_t n, int32_t z0)
{
    sampler *sp[2] = {&cj->col, cj->has_mask && !cj->mask_shared ? &cj->mask : NULL};
    uint64_t bytes = 0;
    hv_status s = HV_OK;
    uint8_t *need[2] = {NULL, NULL};
    for (int q = 0; q < 2 && s == HV_OK; ++q) {
        if (!sp[q]) continue;
        if (!(need[q] = hv_calloc(sp[q]->im->sheets, 1))) s = HV_ERR_NOMEM;
        if (s == HV_OK) mark_sheets(cj, sp[q], zl, n, z0, need[q]);
        for (size_t k = 0; s == HV_OK && k < sp[q]->im->sheets; ++k)
            bytes += need[q][k] ? (uint64_t)sp[q]->im->rows * sp[q]->im->cols * 4 * sizeof(uint16_t) : 0;
    }
    int shared = s == HV_OK && bytes <= cj->allowance;
    for (int q = 0; q < 2 && shared && s == HV_OK; ++q)
        if (sp[q]) s = slab_sheets(cj, sp[q], need[q]);
    for (int q = 0; q < 2; ++q)
        if (sp[q]) sp[q]->shared = shared;
    cj->zl = zl;
    cj->z0 = z0;
    if (s == HV_OK) s = shared ? hv_parallel_for(n, 4, colour_chunk, cj, NULL, NULL) : colour_chunk(cj, 0, n, 0);
    for (int q = 0; q < 2; ++q) {
        if (sp[q]) sp[q]->shared = 0;
        free(need[q]);
    }
    return s;
}

/* ---- the model ------------------------------------------------------------------------------------------- */

/* The model's voxels: the mesh's voxel centres on the stacks' lattice, as its topology and bool
 * grid "occupancy"; *off: hovox index = lattice index + off. */
static hv_status model_voxels(rd *r, const used *u, const lattice *lat, int64_t off[3], hv_volume **vol)
{
    const object *o = u->obj;
    const double *t = lat->t;
    *vol = NULL;
    /* vertices in lattice index space, and the world lattice */
    double *s3 = NULL;
    hv_status s = charge(r, (uint64_t)o->nv * 3 * sizeof(double), "vertices");
    if (s == HV_OK && !(s3 = hv_malloc_array(o->nv, 3 * sizeof(double)))) s = HV_ERR_NOMEM;
    for (size_t v = 0; v < o->nv && s == HV_OK; ++v)
        for (int a = 0; a < 3; ++a) {
            double x = r->xyz[3 * (o->v0 + v) + (size_t)a];
            double w = (t[4 * a] * x + t[9 + a]) * (double)lat->n[a] - 0.5;
            if (!(fabs(w) < 1e9))
                s = bad_at(r, HV_ERR_LIMIT, o->mesh_line, "<mesh> vertex %zu lies %.4g voxels from the image stack's "
                           "lattice origin: too far to voxelize", v, w);
            s3[3 * v + (size_t)a] = w;
        }
    hv_transform xf;
    if (s == HV_OK) s = lattice_transform(r, u, lat, &xf, off);
    leafmap lm;
    memset(&lm, 0, sizeof lm);
    uint64_t voxels = 0;
    r->leaf_bytes = hv_volume_memory_estimate(1024, (u->bg ? u->bg->n : HV_COLOUR_SLOTS) + (u->cf ? 4 : 0), 1) / 1024;
    if (s == HV_OK) s = occupancy(r, s3, o->nv, r->tri + 3 * o->t0, o->nt, off, &lm, &voxels);
    free(s3);
    if (s == HV_OK && voxels == 0)
        s = bad_at(r, HV_ERR_BAD_INPUT, o->mesh_line, "<mesh> of object %u holds no voxel centre of the image stack's "
                   "lattice", o->id);
    hv_volume *v = NULL;
    int og = -1;
    if (s == HV_OK) s = hv_volume_create(&xf, &v);
    if (s == HV_OK) s = hv_volume_topology_add(v, lm.n, lm.origins, lm.masks);
    leafmap_free(&lm);
    if (s == HV_OK) s = hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &og);
    size_t nl = s == HV_OK ? hv_volume_leaf_count(v) : 0;
    for (size_t l = 0; l < nl; ++l) memcpy(hv_volume_leaf_bool(v, og, l), hv_volume_leaf_mask(v, l), 8 * sizeof(uint64_t));
    if (s != HV_OK) {
        hv_volume_destroy(v);
        return s;
    }
    *vol = v;
    return HV_OK;
}

/* The fractions (and the colour, when the package has one) of every voxel, sampled from the
 * sheets layer by layer; a stack's decoded sheet is kept while its layer lasts. */
static hv_status sample_model(rd *r, const used *u, const lattice *lat, const int64_t off[3], hv_volume *v,
                              const hv_material_table *table)
{
    int m = u->bg ? u->bg->n : 0, grid[HV_MAX_MATERIALS];
    hv_status s = HV_OK;
    for (int j = 0; j < m && s == HV_OK; ++j) {
        char gname[80];
        snprintf(gname, sizeof gname, "material.%s", hv_material_name(table, j));
        s = hv_volume_grid_add(v, gname, HV_GRID_FLOAT, &grid[j]);
    }
    sheet_cache cache[HV_MAX_MATERIALS];
    int cache_of[HV_MAX_MATERIALS];
    for (int j = 0; j < m; ++j) {
        cache[j].sheet = -1;
        memset(&cache[j].px, 0, sizeof cache[j].px);
        cache_of[j] = j;
        for (int k = 0; k < j; ++k)
            if (u->im[k] == u->im[j]) {
                cache_of[j] = cache_of[k];
                break;
            }
    }
    if (s == HV_OK) { /* decoded sheets: one per distinct stack */
        uint64_t need = 0;
        for (int j = 0; j < m; ++j)
            if (cache_of[j] == j) need += (uint64_t)u->im[j]->rows * u->im[j]->cols * 4 * sizeof(uint16_t);
        s = charge(r, need, "image sheets");
    }
    colour_job cj;
    memset(&cj, 0, sizeof cj);
    size_t nl = s == HV_OK ? hv_volume_leaf_count(v) : 0;
    const int32_t *orig = nl ? hv_volume_leaf_origins(v) : NULL;
    /* the leaves in z order, a slab (8 layers) at a time */
    zleaf *zl = NULL;
    if (nl) {
        s = charge(r, nl * sizeof *zl, "the model's voxels");
        if (s == HV_OK && !(zl = hv_malloc_array(nl, sizeof *zl))) s = HV_ERR_NOMEM;
        if (s != HV_OK) nl = 0;
        for (size_t l = 0; l < nl; ++l) zl[l] = (zleaf){orig[3 * l + 2], l};
        if (nl) qsort(zl, nl, sizeof *zl, cmp_zleaf);
    }
    if (s == HV_OK && u->cf) s = colour_begin(r, u, lat, off, v, &cj); /* last: its sheets take what is left */
    for (size_t b = 0, e = 0; b < nl && s == HV_OK; b = e) {
        int32_t z0 = zl[b].z;
        for (e = b; e < nl && zl[e].z == z0; ++e) {}
        for (int64_t z = z0; z < (int64_t)z0 + 8 && s == HV_OK; ++z) {
            if ((s = hv_progress_report(NULL, "read 3mf", 0)) != HV_OK) break;
            for (int j = 0; j < m && s == HV_OK; ++j) {
                if (cache_of[j] != j) continue;
                int64_t sheet = tile_index(z - off[2], (int64_t)u->im[j]->sheets, u->f[j]->tile[2]);
                s = load_sheet(r, u->im[j], &cache[j], sheet);
            }
            for (size_t li = b; li < e && s == HV_OK && m; ++li) fill_layer(u, v, grid, zl[li].leaf, z, off, cache, cache_of);
        }
        if (s == HV_OK && u->cf) s = colour_slab(&cj, zl + b, e - b, z0);
    }
    free(zl);
    colour_end(&cj);
    for (int j = 0; j < m; ++j) hv_png_pixels_free(&cache[j].px);
    return s;
}

/* A colour without a composite, printed as hovox prints a painted part: in the six colour resins
 * of the caller's colour map (its profile, intent and resins; without one hovox's default,
 * hovox/colour.h: Ghostscript's default_cmyk.icc, perceptual, the J750's resins), each voxel's
 * fractions those of its colour rounded to 8-bit sRGB (the white resin where hovox:colour.mask
 * says no colour was asked for), and the map recorded as a painted model's (hovox.colour.json),
 * so layers measure the colour's dE2000 through it. Leaves on the library's threads. */
#define COLOUR_SOURCE "3MF <v:color>" /* hovox.colour.json's "source" of such a model */

typedef struct resin_job {
    hv_volume *v;
    hv_colour_map *map; /* its fractions are thread-safe */
    const int *cg, *grid;
} resin_job;

static hv_status resin_chunk(void *ctx, size_t begin, size_t end, int thread)
{
    (void)thread;
    const resin_job *j = ctx;
    for (size_t l = begin; l < end; ++l) {
        const uint64_t *on = hv_volume_leaf_mask(j->v, l);
        const float *c[4];
        for (int k = 0; k < 4; ++k) c[k] = hv_volume_leaf_float_c(j->v, j->cg[k], l);
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            if (!HV_BIT_GET(on, n)) continue;
            float f[HV_COLOUR_SLOTS] = {0};
            uint8_t rgba[4] = {0, 0, 0, 255};
            for (int k = 0; k < 3; ++k) rgba[k] = (uint8_t)lrintf(c[k][n] * 255.0f);
            if (c[3][n] > 0.5f) hv_colour_map_fractions(j->map, rgba, f);
            else f[HV_COLOUR_W] = 1;
            for (int k = 0; k < HV_COLOUR_SLOTS; ++k) hv_volume_leaf_float(j->v, j->grid[k], l)[n] = f[k];
        }
    }
    return HV_OK;
}

static hv_status colour_resins(const hv_colour_options *opt, hv_volume *v, hv_material_table **out)
{
    *out = NULL;
    hv_colour_map *map = NULL;
    hv_colour_options o;
    hv_colour_options_init(&o);
    hv_status s = hv_colour_map_create(opt ? opt : &o, &map);
    hv_material_table *t = NULL;
    if (s == HV_OK) s = hv_material_table_create(&t);
    int grid[HV_COLOUR_SLOTS], cg[4];
    static const char *const k_colour[4] = {"colour.r", "colour.g", "colour.b", "colour.mask"};
    for (int c = 0; c < 4; ++c) cg[c] = hv_volume_grid_find(v, k_colour[c]);
    for (int k = 0; k < HV_COLOUR_SLOTS && s == HV_OK; ++k) {
        char gname[160];
        snprintf(gname, sizeof gname, "material.%s", hv_colour_map_resin(map, k));
        s = hv_material_add(t, hv_colour_map_resin(map, k), NULL, NULL);
        if (s == HV_OK) s = hv_volume_grid_add(v, gname, HV_GRID_FLOAT, &grid[k]);
    }
    resin_job rj = {v, map, cg, grid};
    if (s == HV_OK) s = hv_parallel_for(hv_volume_leaf_count(v), 16, resin_chunk, &rj, NULL, NULL);
    json_t *doc = json_object(), *resins = json_array();
    int bad = !doc || !resins;
    for (int k = 0; k < HV_COLOUR_SLOTS && !bad && s == HV_OK; ++k)
        bad |= json_array_append_new(resins, hv_json_text(hv_colour_map_resin(map, k)));
    if (s == HV_OK) {
        bad |= hv_json_set(doc, "icc", hv_json_text(hv_colour_map_icc(map)));
        bad |= hv_json_set(doc, "description", hv_json_text(hv_colour_map_description(map)));
        bad |= hv_json_set(doc, "intent", json_string(hv_intent_name(hv_colour_map_intent(map))));
        bad |= hv_json_set(doc, "resins", resins);
        resins = NULL;
        bad |= hv_json_set(doc, "source", json_string(COLOUR_SOURCE));
    }
    char *text = s == HV_OK && !bad ? hv_json_dump(doc) : NULL;
    if (s == HV_OK && !text) s = HV_ERR_NOMEM;
    if (s == HV_OK) s = hv_volume_meta_set_json(v, "hovox.colour.json", text);
    free(text);
    json_decref(resins);
    json_decref(doc);
    hv_colour_map_destroy(map);
    if (s != HV_OK) {
        hv_material_table_destroy(t);
        return s;
    }
    *out = t;
    return HV_OK;
}

int hv_3mf_colour_mapped(const hv_volume *vol)
{
    const char *text = vol ? hv_volume_meta_string(vol, "hovox.colour.json") : NULL;
    json_t *doc = NULL;
    const char *source = NULL;
    int mapped = text && hv_json_parse(text, strlen(text), "hovox.colour.json", &doc) == HV_OK &&
                 hv_json_get_string(doc, "source", "hovox.colour.json", &source) == HV_OK &&
                 strcmp(source, COLOUR_SOURCE) == 0;
    json_decref(doc);
    if (text && !mapped) hv_error_clear(); /* a question, not a failure: a damaged record says nothing */
    return mapped;
}

static hv_status make_volume(rd *r, const used *u, const lattice *lat, hv_volume **vol, hv_mesh **mesh)
{
    int64_t off[3] = {0, 0, 0};
    hv_volume *v = NULL;
    hv_status s = model_voxels(r, u, lat, off, &v);
    /* the materials: the composite's, or the colour's resins */
    hv_material_table *table = NULL;
    if (s == HV_OK && u->bg && (s = build_table(r, u, &table)) != HV_OK && s != HV_ERR_NOMEM)
        s = bad_at(r, HV_ERR_BAD_INPUT, u->bg->line, "<basematerials> %u: %s", u->bg->id, hv_last_error());
    if (s == HV_OK) s = sample_model(r, u, lat, off, v, table);
    if (s == HV_OK && !u->bg) s = colour_resins(r->colour, v, &table);
    if (s == HV_OK) s = hv_material_table_store(v, table);
    hv_material_table_destroy(table);
    /* a painted model's record, with its colour */
    if (s == HV_OK && u->cf && r->colour_json && (s = hv_volume_meta_set_json(v, "hovox.colour.json", r->colour_json)) != HV_OK &&
        s != HV_ERR_NOMEM)
        s = bad_at_col(r, HV_ERR_BAD_INPUT, r->colour_at[0], r->colour_at[1], "<metadata> hovox:colour is not a JSON "
                       "document");
    if (s == HV_OK && mesh) s = object_mesh(r, u, mesh); /* the mesh, in millimetres */
    if (s != HV_OK) {
        hv_volume_destroy(v);
        return s;
    }
    *vol = v;
    return HV_OK;
}

static void rd_free(rd *r)
{
    for (size_t i = 0; i < r->ngroups; ++i) {
        for (int j = 0; j < r->groups[i].n; ++j) free(r->groups[i].names[j]);
        free(r->groups[i].names);
        free(r->groups[i].rgba);
    }
    free(r->groups);
    for (size_t i = 0; i < r->nimages; ++i) {
        for (size_t k = 0; k < r->images[i].npaths; ++k) free(r->images[i].paths[k]);
        free(r->images[i].paths);
        free(r->images[i].lines);
        free(r->images[i].name);
    }
    free(r->images);
    free(r->funcs);
    for (size_t i = 0; i < r->nvols; ++i) free(r->vols[i].maps);
    free(r->vols);
    free(r->objects);
    free(r->items);
    free(r->ids);
    free(r->xyz);
    free(r->tri);
    free(r->materials_json);
    free(r->colour_json);
}


static hv_status read_package(const void *data, size_t size, const char *path, const char *name,
                              const hv_colour_options *colour, hv_volume **vol, hv_mesh **mesh)
{
    *vol = NULL;
    if (mesh) *mesh = NULL;
    tmf_pkg pk;
    hv_status s = tmf_pkg_open(&pk, data, size, path, name);
    if (s != HV_OK) return s;
    rd r;
    memset(&r, 0, sizeof r);
    r.name = name;
    r.pk = &pk;
    r.part = pk.model;
    r.budget = pk.budget;
    r.unit = 1;
    r.colour = colour;
    s = read_model(&r);
    used u;
    lattice lat;
    if (s == HV_OK) s = resolve(&r, &u, &lat);
    if (s == HV_OK) s = make_volume(&r, &u, &lat, vol, mesh);
    rd_free(&r);
    tmf_pkg_close(&pk);
    return s;
}

hv_status hv_3mf_parse(const void *data, size_t size, const char *name, hv_volume **vol, hv_mesh **mesh)
{
    return read_package(size ? data : "", size, NULL, name, NULL, vol, mesh);
}

hv_status hv_3mf_load(const char *path, hv_volume **vol, hv_mesh **mesh)
{
    return read_package(NULL, 0, path, path, NULL, vol, mesh);
}

hv_status hv_3mf_load_colour(const char *path, const hv_colour_options *colour, hv_volume **vol, hv_mesh **mesh)
{
    return read_package(NULL, 0, path, path, colour, vol, mesh);
}

int hv_3mf_sniff(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return 0;
    unsigned char m[4] = {0};
    size_t n = fread(m, 1, 4, fp);
    fclose(fp);
    return n == 4 && m[0] == 'P' && m[1] == 'K' && (m[2] == 3 || m[2] == 5) && (m[3] == 4 || m[3] == 6);
}

/* Which reader a package needs: its model's resources are read up to the first <v:volumedata>
 * (Volumetric: 1) or the first <object> (resources come before what uses them, so a volumedata
 * after an object belongs to no first object: 0). The parse stops there; a mesh package of a
 * million facets costs its first lines only. */
static hv_status vol_sniff_start(void *ctx, tmf_xml *x, const char *local, const char *uri, const tmf_attr *attrs,
                                 int nattrs)
{
    (void)x, (void)attrs, (void)nattrs;
    int *found = ctx;
    if (uri && strcmp(uri, TMF_NS_VOLUMETRIC) == 0 && strcmp(local, "volumedata") == 0) *found = 1;
    else if (strcmp(local, "object") == 0) *found = 0;
    else return HV_OK;
    return HV_ERR_CANCELLED; /* enough read */
}

int hv_3mf_is_volumetric(const char *path)
{
    if (!hv_3mf_sniff(path)) return 0;
    tmf_pkg pk;
    if (tmf_pkg_open(&pk, NULL, 0, path, path) != HV_OK) return 0;
    int found = 0;
    tmf_xml_handler h = {vol_sniff_start, NULL};
    tmf_xml_parse(&pk, pk.model, pk.inflate_cap, &h, &found);
    tmf_pkg_close(&pk);
    return found;
}
