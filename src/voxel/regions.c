/* src/voxel/regions.c - the regions of a voxelized assembly (hovox/voxelize.h): one per body,
 * with its material, fill, voxels, the voxels it lost and those of them earlier bodies kept where
 * they overlap, and the overlap (centres inside two or more bodies); the
 * "hovox.regions.json" document that records them in a model. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "voxel_internal.h"
#include "volumes/schema.h"

void hv_regions_destroy(hv_regions *r)
{
    if (!r) return;
    for (size_t i = 0; i < r->n; ++i) {
        free((char *)r->info[i].name);
        free((char *)r->info[i].grid);
        free((char *)r->info[i].material);
        for (size_t k = 0; k < r->info[i].nparts; ++k) free((char *)r->info[i].parts[k].material);
        free((hv_mesh_mix_part *)r->info[i].parts);
        free((hv_region_loss *)r->info[i].lost_to);
    }
    free(r->info);
    free(r);
}

size_t hv_regions_count(const hv_regions *r) { return r ? r->n : 0; }

const hv_region_info *hv_regions_at(const hv_regions *r, size_t i) { return r && i < r->n ? &r->info[i] : NULL; }

int64_t hv_regions_find(const hv_regions *r, const char *name)
{
    for (size_t i = 0; r && name && i < r->n; ++i)
        if (strcmp(r->info[i].name, name) == 0) return (int64_t)i;
    return -1;
}

uint64_t hv_regions_overlap(const hv_regions *r)
{
    return r ? r->overlap : 0;
}

hv_status hv_regions_grid_name(const char *body, char **out)
{
    *out = NULL;
    size_t n = strlen(body);
    if (n > HV_REGION_NAME_MAX)
        return hv_error_set(HV_ERR_BAD_INPUT, "body '%.40s...': its name is %zu bytes long, more than the %d a region's "
                                              "grid name allows",
                            body, n, HV_REGION_NAME_MAX);
    char *g = malloc(n + sizeof "region.");
    if (!g) return HV_ERR_NOMEM;
    memcpy(g, "region.", 7);
    memcpy(g + 7, body, n + 1);
    *out = g;
    return HV_OK;
}

/* ---- the document ------------------------------------------------------------------------- */

static int64_t find_before(const hv_regions *r, size_t end, const char *name)
{
    for (size_t i = 0; i < end; ++i)
        if (strcmp(r->info[i].name, name) == 0) return (int64_t)i;
    return -1;
}

/* A mixture as [{"material": NAME, "fraction": F}, ...] (NULL: out of memory). */
static json_t *mixture_doc(const hv_region_info *g)
{
    json_t *a = json_array();
    for (size_t k = 0; a && k < g->nparts; ++k) {
        json_t *x = json_object();
        if (!x || hv_json_set(x, "material", hv_json_text(g->parts[k].material)) ||
            hv_json_set(x, "fraction", hv_json_number(g->parts[k].fraction)) || json_array_append_new(a, x)) {
            json_decref(a);
            return NULL;
        }
    }
    return a;
}

/* A region's "mixture": distinct material names, fractions in (0, 1] summing to 1 within 1e-4. */
static hv_status mixture_from_doc(const json_t *e, const char *place, hv_region_info *g)
{
    const json_t *a = json_object_get(e, "mixture");
    if (!a) return HV_OK;
    size_t n = json_array_size(a);
    if (!json_is_array(a) || n == 0 || n > HV_MAX_MIX_PARTS)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: mixture is not a list of 1 to %d parts", place, HV_MAX_MIX_PARTS);
    hv_mesh_mix_part *p = hv_calloc(n, sizeof *p);
    if (!p) return HV_ERR_NOMEM;
    g->parts = p;
    double sum = 0;
    char where[340];
    for (size_t k = 0; k < n; ++k) {
        const json_t *x = json_array_get(a, k);
        const char *m;
        double f;
        snprintf(where, sizeof where, "%s: mixture[%zu]", place, k);
        hv_status s = hv_json_get_string(x, "material", where, &m);
        if (s == HV_OK) s = hv_json_get_number(x, "fraction", where, &f);
        if (s != HV_OK) return s;
        if (!(f > 0 && f <= 1)) return hv_error_set(HV_ERR_BAD_INPUT, "%s: fraction %g is not in (0, 1]", where, f);
        for (size_t j = 0; j < k; ++j)
            if (strcmp(p[j].material, m) == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: material '%s' is named twice", where, m);
        if (!(p[k].material = hv_strdup(m))) return HV_ERR_NOMEM;
        p[k].fraction = f;
        g->nparts = k + 1;
        sum += f;
    }
    if (!(fabs(sum - 1) <= 1e-4)) return hv_error_set(HV_ERR_BAD_INPUT, "%s: the mixture's fractions sum to %.9g, not 1", place, sum);
    return HV_OK;
}

json_t *hv_regions_to_doc(const hv_regions *r, double vv)
{
    json_t *list = json_array();
    int failed = !list;
    for (size_t i = 0; i < r->n && !failed; ++i) {
        const hv_region_info *g = &r->info[i];
        json_t *e = json_object(), *lost = json_array();
        failed = !e || !lost;
        for (size_t k = 0; k < g->nlost_to && !failed; ++k) {
            json_t *x = json_object();
            failed = !x || hv_json_set(x, "region", hv_json_text(r->info[g->lost_to[k].region].name)) ||
                     hv_json_set(x, "voxels", json_integer((json_int_t)g->lost_to[k].voxels)) ||
                     json_array_append_new(lost, x);
        }
        if (!failed) {
            failed |= hv_json_set(e, "name", hv_json_text(g->name));
            failed |= hv_json_set(e, "grid", hv_json_text(g->grid));
            failed |= hv_json_set(e, "material", g->material ? hv_json_text(g->material) : json_null());
            if (g->nparts) failed |= hv_json_set(e, "mixture", mixture_doc(g));
            if (g->has_color) {
                json_t *c = json_array();
                for (int k = 0; k < 4 && c; ++k)
                    if (json_array_append_new(c, hv_json_float(g->rgba[k]))) {
                        json_decref(c);
                        c = NULL;
                    }
                failed |= hv_json_set(e, "color", c);
            }
            failed |= hv_json_set(e, "fill", json_string(hv_fill_mode_name(g->fill)));
            failed |= hv_json_set(e, "voxels", json_integer((json_int_t)g->voxels));
            failed |= hv_json_set(e, "lost", json_integer((json_int_t)g->lost));
            failed |= hv_json_set(e, "lost_to", lost);
            lost = NULL;
            failed |= json_array_append(list, e) != 0;
        }
        json_decref(lost);
        json_decref(e);
    }
    json_t *doc = NULL;
    if (!failed) {
        uint64_t ov = hv_regions_overlap(r);
        doc = json_object();
        if (doc && (hv_json_set(doc, "regions", json_incref(list)) |
                    hv_json_set(doc, "overlap", json_integer((json_int_t)ov)) |
                    hv_json_set(doc, "overlap_volume", hv_json_number((double)ov * vv)))) {
            json_decref(doc);
            doc = NULL;
        }
    }
    json_decref(list);
    return doc;
}

hv_status hv_regions_from_doc(const json_t *doc, const char *what, hv_regions **out)
{
    *out = NULL;
    const json_t *list;
    hv_status s = hv_json_need(doc, "regions", JSON_ARRAY, what, &list);
    if (s != HV_OK) return s;
    size_t n = json_array_size(list);
    if (n == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: regions is empty", what);
    hv_regions *r = hv_calloc(1, sizeof *r);
    if (!r || !(r->info = hv_calloc(n, sizeof *r->info))) {
        free(r);
        return HV_ERR_NOMEM;
    }
    char place[300];
    for (size_t i = 0; i < n && s == HV_OK; ++i) {
        const json_t *e = json_array_get(list, i), *lost, *mat;
        hv_region_info *g = &r->info[i];
        r->n = i + 1;
        snprintf(place, sizeof place, "%s: regions[%zu]", what, i);
        const char *name, *grid;
        long long voxels, nlost;
        int fill;
        if ((s = hv_json_get_string(e, "name", place, &name)) != HV_OK ||
            (s = hv_json_get_string(e, "grid", place, &grid)) != HV_OK ||
            (s = hv_json_get_name(e, "fill", place, hv_fill_mode_enum(), &fill)) != HV_OK ||
            (s = hv_json_get_int(e, "voxels", place, 0, INT64_MAX, &voxels)) != HV_OK ||
            (s = hv_json_get_int(e, "lost", place, 0, INT64_MAX, &nlost)) != HV_OK ||
            (s = hv_json_need(e, "lost_to", JSON_ARRAY, place, &lost)) != HV_OK)
            break;
        if (find_before(r, i, name) >= 0) {
            s = hv_error_set(HV_ERR_BAD_INPUT, "%s: name '%s' is used by an earlier region", place, name);
            break;
        }
        if (!(g->name = hv_strdup(name)) || !(g->grid = hv_strdup(grid))) {
            s = HV_ERR_NOMEM;
            break;
        }
        g->fill = (hv_fill_mode)fill;
        g->voxels = (uint64_t)voxels;
        g->lost = (uint64_t)nlost;
        mat = json_object_get(e, "material");
        if (mat && !json_is_null(mat)) {
            const char *m;
            if ((s = hv_json_get_string(e, "material", place, &m)) != HV_OK) break;
            if (!(g->material = hv_strdup(m))) {
                s = HV_ERR_NOMEM;
                break;
            }
        }
        if ((s = mixture_from_doc(e, place, g)) != HV_OK) break;
        if (json_object_get(e, "color")) {
            double c[4];
            if ((s = hv_json_get_numbers(e, "color", place, c, 4)) != HV_OK) break;
            for (int k = 0; k < 4; ++k) {
                if (!(c[k] >= 0 && c[k] <= 1)) {
                    s = hv_error_set(HV_ERR_BAD_INPUT, "%s: color[%d] is %g, not in [0, 1]", place, k, c[k]);
                    break;
                }
                g->rgba[k] = (float)c[k];
            }
            if (s != HV_OK) break;
            g->has_color = 1;
        }
        size_t nl = json_array_size(lost);
        hv_region_loss *to = nl ? hv_calloc(nl, sizeof *to) : NULL;
        if (nl && !to) {
            s = HV_ERR_NOMEM;
            break;
        }
        g->lost_to = to;
        g->nlost_to = nl;
        uint64_t sum = 0;
        for (size_t k = 0; k < nl && s == HV_OK; ++k) {
            const json_t *x = json_array_get(lost, k);
            char where[340];
            snprintf(where, sizeof where, "%s: lost_to[%zu]", place, k);
            const char *other;
            long long v;
            if ((s = hv_json_get_string(x, "region", where, &other)) != HV_OK ||
                (s = hv_json_get_int(x, "voxels", where, 0, INT64_MAX, &v)) != HV_OK)
                break;
            int64_t j = find_before(r, i, other);
            if (j < 0) {
                s = hv_error_set(HV_ERR_BAD_INPUT, "%s: region '%s' is not an earlier region", where, other);
                break;
            }
            to[k].region = (size_t)j;
            to[k].voxels = (uint64_t)v;
            sum += (uint64_t)v;
        }
        if (s == HV_OK && sum > g->lost)
            s = hv_error_set(HV_ERR_BAD_INPUT, "%s: lost is %llu but lost_to sums to %llu, more", place,
                             (unsigned long long)g->lost, (unsigned long long)sum);
    }
    long long ov = 0;
    if (s == HV_OK) s = hv_json_get_int(doc, "overlap", what, 0, INT64_MAX, &ov);
    r->overlap = (uint64_t)ov;
    if (s != HV_OK) {
        hv_regions_destroy(r);
        return s;
    }
    *out = r;
    return HV_OK;
}

hv_status hv_voxelize_regions_read(const hv_volume *model, hv_regions **out)
{
    *out = NULL;
    json_t *doc;
    hv_status s = hv_schema_doc_read(model, HV_DOC_REGIONS, &doc);
    if (s == HV_ERR_NOT_FOUND)
        return hv_error_set(HV_ERR_NOT_FOUND, "the model has no regions (it was not voxelized from an assembly)");
    if (s == HV_OK) s = hv_regions_from_doc(doc, hv_schema_key(HV_DOC_REGIONS), out);
    json_decref(doc);
    return s;
}
