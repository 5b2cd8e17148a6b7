/* src/mesh/bodies.c - bodies and materials of a mesh (hovox/mesh.h): the named parts of an
 * assembly as consecutive facet ranges, the materials a file names, extraction of one body as
 * its own mesh, joining meshes into an assembly, and hv_mesh_load's choice of reader. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "mesh_internal.h"

const char *hv_mesh_format_name(hv_mesh_format f)
{
    switch (f) {
    case HV_MESH_STL_BINARY: return "binary STL";
    case HV_MESH_STL_ASCII: return "ASCII STL";
    case HV_MESH_3MF: return "3MF";
    case HV_MESH_OBJ: return "OBJ";
    case HV_MESH_PLY_ASCII: return "ASCII PLY";
    case HV_MESH_PLY_BINARY_LE: return "binary PLY (little-endian)";
    case HV_MESH_PLY_BINARY_BE: return "binary PLY (big-endian)";
    case HV_MESH_GENERATED: break;
    }
    return "generated";
}

/* The body names given so far (taken) and, per name asked for (bases), the next suffix to try. */
typedef struct namer {
    hv_names taken, bases;
    size_t *next;
    size_t cap;
} namer;

static void namer_free(namer *nm)
{
    hv_names_free(&nm->taken);
    hv_names_free(&nm->bases);
    free(nm->next);
}

/* A unique copy of `want` among the names already given (nm->taken, which gets it too):
 * "body N" when empty, "NAME (k)" when taken, k the smallest free from 2. Hash sets, and the
 * search for k resumes where the last one for the same name stopped (every smaller k is taken
 * and names are never given back): linear in the bodies, which may be 10^5 copies of one name
 * (a 3MF of 20,000 build items took 60 s to name). */
static char *unique_name(namer *nm, const char *want, size_t index)
{
    char buf[64];
    if (!want || !*want) {
        snprintf(buf, sizeof buf, "body %zu", index + 1);
        want = buf;
    }
    size_t len = strlen(want) + 32;
    char *s = malloc(len);
    int32_t slot, base;
    if (!s) return NULL;
    snprintf(s, len, "%s", want);
    if (hv_names_find(&nm->taken, s, strlen(s)) >= 0) {
        size_t known = nm->bases.n;
        if (hv_names_intern(&nm->bases, want, strlen(want), &base) != HV_OK ||
            hv_grow((void **)&nm->next, &nm->cap, (size_t)base + 1, sizeof *nm->next) != HV_OK) {
            free(s);
            return NULL;
        }
        if ((size_t)base == known) nm->next[base] = 2; /* a name asked for again the first time */
        size_t k = nm->next[base];
        for (snprintf(s, len, "%s (%zu)", want, k); hv_names_find(&nm->taken, s, strlen(s)) >= 0;)
            snprintf(s, len, "%s (%zu)", want, ++k);
        nm->next[base] = k + 1;
    }
    if (hv_names_intern(&nm->taken, s, strlen(s), &slot) != HV_OK) {
        free(s);
        return NULL;
    }
    return s;
}

static void bodies_free(hv_mesh *m)
{
    for (size_t i = 0; i < m->nbodies; ++i) free((char *)m->bodies[i].name);
    for (size_t i = 0; i < m->nmats; ++i) {
        free((char *)m->mats[i].name);
        for (size_t k = 0; k < m->mats[i].nparts; ++k) free((char *)m->mats[i].parts[k].material);
        free((hv_mesh_mix_part *)m->mats[i].parts);
    }
    free(m->bodies);
    free(m->mats);
    free(m->facet_mat);
    m->bodies = NULL;
    m->mats = NULL;
    m->facet_mat = NULL;
    m->nbodies = m->nmats = 0;
}

/* A mixture's parts copied into dst (dst->nparts counts those copied, for bodies_free). */
static hv_status mix_copy(hv_mesh_material *dst, const hv_mesh_material *src)
{
    if (!src->nparts) return HV_OK;
    hv_mesh_mix_part *p = hv_calloc(src->nparts, sizeof *p);
    if (!p) return HV_ERR_NOMEM;
    dst->parts = p;
    for (size_t k = 0; k < src->nparts; ++k) {
        if (!(p[k].material = hv_strdup(src->parts[k].material))) return HV_ERR_NOMEM;
        p[k].fraction = src->parts[k].fraction;
        dst->nparts = k + 1;
    }
    return HV_OK;
}

void hv_mesh_bodies_free(hv_mesh *m) { bodies_free(m); }

hv_status hv_mesh_set_bodies(hv_mesh *m, const hv_mesh_body *bodies, size_t n,
                             const hv_mesh_material *mats, size_t nmats, const int32_t *facet_mat)
{
    size_t total = 0;
    for (size_t i = 0; i < n; ++i) {
        if (bodies[i].facet_count == 0 || bodies[i].facet_count > m->nf - total)
            return hv_error_set(HV_ERR_INVALID, "%s: body %zu: %zu facets do not fit the mesh's %zu",
                                hv_mesh_name(m), i + 1, bodies[i].facet_count, m->nf);
        if (bodies[i].material != HV_MESH_NO_MATERIAL &&
            (bodies[i].material < 0 || (size_t)bodies[i].material >= nmats))
            return hv_error_set(HV_ERR_INVALID, "%s: body %zu: material %d out of range (%zu)",
                                hv_mesh_name(m), i + 1, (int)bodies[i].material, nmats);
        total += bodies[i].facet_count;
    }
    if (n == 0 || total != m->nf)
        return hv_error_set(HV_ERR_INVALID, "%s: bodies hold %zu facets, the mesh %zu",
                            hv_mesh_name(m), total, m->nf);
    if (facet_mat)
        for (size_t f = 0; f < m->nf; ++f)
            if (facet_mat[f] != HV_MESH_NO_MATERIAL &&
                (facet_mat[f] < 0 || (size_t)facet_mat[f] >= nmats))
                return hv_error_set(HV_ERR_INVALID, "%s: facet %zu: material %d out of range (%zu)",
                                    hv_mesh_name(m), f, (int)facet_mat[f], nmats);
    hv_mesh tmp = {0};
    namer taken;
    memset(&taken, 0, sizeof taken);
    hv_names_init(&taken.taken);
    hv_names_init(&taken.bases);
    tmp.bodies = hv_calloc(n, sizeof *tmp.bodies);
    tmp.mats = nmats ? hv_calloc(nmats, sizeof *tmp.mats) : NULL;
    tmp.facet_mat = facet_mat ? hv_malloc_array(m->nf, sizeof *tmp.facet_mat) : NULL;
    if (!tmp.bodies || (nmats && !tmp.mats) || (facet_mat && !tmp.facet_mat)) goto nomem;
    for (size_t i = 0; i < nmats; ++i) {
        tmp.mats[i] = mats[i];
        tmp.mats[i].name = hv_strdup(mats[i].name ? mats[i].name : "");
        tmp.mats[i].nparts = 0;
        tmp.mats[i].parts = NULL;
        tmp.nmats = i + 1;
        if (!tmp.mats[i].name || mix_copy(&tmp.mats[i], &mats[i]) != HV_OK) goto nomem;
    }
    if (facet_mat) memcpy(tmp.facet_mat, facet_mat, m->nf * sizeof *facet_mat);
    size_t first = 0;
    for (size_t i = 0; i < n; ++i) {
        hv_mesh_body *b = &tmp.bodies[i];
        *b = bodies[i];
        b->first_facet = first;
        first += b->facet_count;
        b->name = unique_name(&taken, bodies[i].name, i);
        tmp.nbodies = i + 1;
        if (!b->name) goto nomem;
        if (b->material == HV_MESH_NO_MATERIAL && facet_mat && nmats) {
            size_t *cnt = hv_calloc(nmats, sizeof *cnt);
            if (!cnt) goto nomem;
            for (size_t f = b->first_facet; f < b->first_facet + b->facet_count; ++f)
                if (facet_mat[f] >= 0) cnt[facet_mat[f]]++;
            size_t best = 0;
            for (size_t k = 0; k < nmats; ++k)
                if (cnt[k] > best) {
                    best = cnt[k];
                    b->material = (int32_t)k;
                }
            free(cnt);
        }
    }
    namer_free(&taken);
    bodies_free(m);
    m->bodies = tmp.bodies;
    m->nbodies = tmp.nbodies;
    m->mats = tmp.mats;
    m->nmats = tmp.nmats;
    m->facet_mat = tmp.facet_mat;
    return HV_OK;
nomem:
    namer_free(&taken);
    bodies_free(&tmp);
    return HV_ERR_NOMEM;
}

hv_status hv_mesh_body_index(hv_mesh *m, const char *body, size_t *out)
{
    if (m->nbodies == 0) {
        hv_status s = hv_mesh_default_body(m);
        if (s != HV_OK) return s;
    }
    size_t b = 0;
    while (b < m->nbodies && strcmp(m->bodies[b].name, body) != 0) ++b;
    if (b == m->nbodies) {
        hv_buf list;
        hv_buf_init(&list);
        for (size_t i = 0; i < m->nbodies && i < 20; ++i) hv_buf_printf(&list, "%s%s", i ? ", " : "", m->bodies[i].name);
        if (m->nbodies > 20) hv_buf_printf(&list, ", ... (%zu in all)", m->nbodies);
        const char *name = hv_mesh_name(m);
        hv_status s = hv_error_set(HV_ERR_NOT_FOUND, "%s: no body '%s' (bodies: %s)", *name ? name : "the mesh", body,
                                   list.data && !list.failed ? list.data : "?");
        hv_buf_free(&list);
        return s;
    }
    *out = b;
    return HV_OK;
}

hv_status hv_mesh_body_material_set(hv_mesh *m, const char *body, const char *material)
{
    if (!material || !*material) return hv_error_set(HV_ERR_INVALID, "%s: body '%s': empty material name", hv_mesh_name(m), body);
    size_t b = 0;
    hv_status found = hv_mesh_body_index(m, body, &b);
    if (found != HV_OK) return found;
    size_t k = 0;
    while (k < m->nmats && strcmp(m->mats[k].name, material) != 0) ++k;
    hv_mesh_body *bodies = hv_malloc_array(m->nbodies, sizeof *bodies);
    hv_mesh_material *mats = hv_malloc_array(m->nmats + 1, sizeof *mats);
    if (!bodies || !mats) {
        free(bodies);
        free(mats);
        return HV_ERR_NOMEM;
    }
    memcpy(bodies, m->bodies, m->nbodies * sizeof *bodies);
    if (m->nmats) memcpy(mats, m->mats, m->nmats * sizeof *mats);
    size_t nmats = m->nmats;
    if (k == nmats) mats[nmats++] = (hv_mesh_material){material, 0, 0, 0, NULL};
    bodies[b].material = (int32_t)k;
    hv_status s = hv_mesh_set_bodies(m, bodies, m->nbodies, mats, nmats, m->facet_mat);
    free(bodies);
    free(mats);
    return s;
}

/* The single body of a mesh built without bodies: named after the file (its base name without
 * the extension), or "body 1". */
hv_status hv_mesh_default_body(hv_mesh *m)
{
    char *stem = hv_file_stem(m->name);
    if (!stem) return HV_ERR_NOMEM;
    hv_mesh_body b = {stem, HV_MESH_NO_MATERIAL, 0, m->nf, 0};
    hv_status s = hv_mesh_set_bodies(m, &b, 1, NULL, 0, NULL);
    free(stem);
    return s;
}

size_t hv_mesh_body_count(const hv_mesh *m) { return m->nbodies; }
const hv_mesh_body *hv_mesh_body_at(const hv_mesh *m, size_t i)
{
    return i < m->nbodies ? &m->bodies[i] : NULL;
}
int64_t hv_mesh_body_find(const hv_mesh *m, const char *name)
{
    for (size_t i = 0; i < m->nbodies; ++i)
        if (strcmp(m->bodies[i].name, name) == 0) return (int64_t)i;
    return -1;
}
size_t hv_mesh_material_count(const hv_mesh *m) { return m->nmats; }
const hv_mesh_material *hv_mesh_material_at(const hv_mesh *m, size_t i)
{
    return i < m->nmats ? &m->mats[i] : NULL;
}
const int32_t *hv_mesh_facet_materials(const hv_mesh *m) { return m->facet_mat; }

/* The facets [first, first + n) of m as a soup (9 floats per facet). */
static float *soup_of(const hv_mesh *m, size_t first, size_t n)
{
    float *soup = hv_malloc_array(n, 9 * sizeof(float));
    if (!soup) return NULL;
    for (size_t f = 0; f < n; ++f)
        for (int k = 0; k < 3; ++k)
            memcpy(soup + 9 * f + 3 * (size_t)k, m->xyz + 3 * (size_t)m->tri[3 * (first + f) + (size_t)k],
                   3 * sizeof(float));
    return soup;
}

hv_status hv_mesh_body_extract(const hv_mesh *m, size_t i, hv_mesh **out)
{
    *out = NULL;
    if (i >= m->nbodies)
        return hv_error_set(HV_ERR_INVALID, "%s: no body %zu (%zu bodies)", hv_mesh_name(m), i,
                            m->nbodies);
    const hv_mesh_body *b = &m->bodies[i];
    float *soup = soup_of(m, b->first_facet, b->facet_count);
    if (!soup) return HV_ERR_NOMEM;
    hv_buf name;
    hv_buf_init(&name);
    hv_buf_puts(&name, hv_mesh_name(m));
    if (m->nbodies > 1) hv_buf_printf(&name, "%s%s", *hv_mesh_name(m) ? "#" : "", b->name);
    hv_status s = name.failed ? HV_ERR_NOMEM
                              : hv_mesh_from_soup(soup, NULL, b->facet_count, name.data,
                                                  m->report.format, out);
    free(soup);
    hv_buf_free(&name);
    if (s != HV_OK) return s;
    hv_mesh_body one = *b;
    s = hv_mesh_set_bodies(*out, &one, 1, m->mats, m->nmats,
                           m->facet_mat ? m->facet_mat + b->first_facet : NULL);
    if (s == HV_OK) s = hv_mesh_appearance_copy(*out, m, b->first_facet, b->facet_count, 0);
    if (s != HV_OK) {
        hv_mesh_destroy(*out);
        *out = NULL;
    }
    return s;
}

hv_status hv_mesh_body_report(const hv_mesh *m, size_t i, hv_mesh_report *out)
{
    if (m->nbodies == 1 && i == 0) {
        *out = m->report;
        return HV_OK;
    }
    hv_mesh *b;
    hv_status s = hv_mesh_body_extract(m, i, &b);
    if (s != HV_OK) return s;
    *out = b->report;
    hv_mesh_destroy(b);
    return HV_OK;
}

hv_status hv_mesh_join(const hv_mesh_part *parts, size_t n, hv_mesh **out)
{
    *out = NULL;
    if (n == 0) return hv_error_set(HV_ERR_INVALID, "joining meshes: no parts");
    size_t nf = 0;
    for (size_t i = 0; i < n; ++i) {
        if (!parts[i].mesh) return hv_error_set(HV_ERR_INVALID, "joining meshes: part %zu has no mesh", i + 1);
        nf += parts[i].mesh->nf;
    }
    float *soup = hv_malloc_array(nf, 9 * sizeof(float));
    hv_mesh_body *bodies = hv_calloc(n, sizeof *bodies);
    hv_mesh_material *mats = hv_calloc(n, sizeof *mats);
    hv_status s = HV_OK;
    if (!soup || !bodies || !mats) {
        s = HV_ERR_NOMEM;
        goto done;
    }
    size_t at = 0, nmats = 0;
    for (size_t i = 0; i < n; ++i) {
        const hv_mesh *p = parts[i].mesh;
        float *part = soup_of(p, 0, p->nf);
        if (!part) {
            s = HV_ERR_NOMEM;
            goto done;
        }
        memcpy(soup + 9 * at, part, p->nf * 9 * sizeof(float));
        free(part);
        at += p->nf;
        bodies[i].name = parts[i].name;
        bodies[i].facet_count = p->nf;
        bodies[i].material = HV_MESH_NO_MATERIAL;
        if (parts[i].material) {
            size_t k = 0;
            while (k < nmats && strcmp(mats[k].name, parts[i].material) != 0) ++k;
            if (k == nmats) mats[nmats++].name = parts[i].material;
            bodies[i].material = (int32_t)k;
        }
    }
    s = hv_mesh_from_soup(soup, NULL, nf, "", HV_MESH_GENERATED, out);
    if (s == HV_OK) s = hv_mesh_set_bodies(*out, bodies, n, mats, nmats, NULL);
    if (s == HV_OK) {
        const hv_mesh **meshes = hv_malloc_array(n, sizeof *meshes);
        if (!meshes) s = HV_ERR_NOMEM;
        for (size_t i = 0; meshes && i < n; ++i) meshes[i] = parts[i].mesh;
        if (meshes) s = hv_mesh_appearance_join(*out, meshes, n);
        free(meshes);
    }
    if (s != HV_OK) {
        hv_mesh_destroy(*out);
        *out = NULL;
    }
done:
    free(soup);
    free(bodies);
    free(mats);
    return s;
}

/* ---- bodies' materials as options give them ---------------------------------------------------- */

hv_status hv_body_materials_option_parse(const hv_option *o, void *opts, const hv_opt_value *v)
{
    hv_body_materials *m = (hv_body_materials *)((char *)opts + o->offset);
    const char *eq = v->type == HV_VALUE_TEXT ? strchr(v->text, '=') : NULL;
    if (!eq || eq == v->text || !eq[1])
        return hv_error_option(HV_ERR_INVALID, "{%s} must be BODY=MATERIAL, got '%s'", o->key,
                               v->type == HV_VALUE_TEXT ? v->text : "a non-text value");
    if (m->n == HV_BODY_MATERIALS_MAX) return hv_error_option(HV_ERR_INVALID, "at most %d {%s} options", HV_BODY_MATERIALS_MAX, o->key);
    m->pair[m->n++] = v->text;
    return HV_OK;
}

hv_status hv_body_materials_apply(const hv_body_materials *materials, hv_mesh *mesh)
{
    hv_status s = HV_OK;
    for (int i = 0; i < materials->n && s == HV_OK; ++i) {
        const char *pair = materials->pair[i], *eq = strchr(pair, '=');
        char body[1024];
        snprintf(body, sizeof body, "%.*s", (int)(eq - pair), pair);
        s = hv_mesh_body_material_set(mesh, body, eq + 1);
    }
    return s;
}
