/* src/mesh/report_json.c - the mesh report as JSON: the object of `hovox info --json` and the
 * "hovox.mesh.json" document of voxelized models (volumes/schema.h), and reading it back. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"
#include "volumes/schema.h"

static const char *const k_format_names[] = {"generated", "binary", "ascii", "3mf", "obj", "ply_ascii", "ply_binary_le", "ply_binary_be", NULL}; /* by hv_mesh_format */
static const hv_enum_def k_formats = {"mesh format", k_format_names, NULL, NULL};

static const char *const k_counts[] = {"facets", "vertices", "shells", "open_edges", "nonmanifold_edges",
                                       "degenerate_facets", "flipped_facets", "normal_mismatch"};

static uint64_t *count_field(hv_mesh_report *r, int i)
{
    uint64_t *f[] = {&r->facets, &r->vertices, &r->shells, &r->open_edges, &r->nonmanifold_edges,
                     &r->degenerate_facets, &r->flipped_facets, &r->normal_mismatch};
    return f[i];
}

json_t *hv_mesh_report_to_doc(const char *file, const hv_mesh_report *r)
{
    hv_mesh_report c = *r;
    json_t *j = json_object();
    if (!j) return NULL;
    int failed = hv_json_set(j, "file", hv_json_text(file ? file : ""));
    failed |= hv_json_set(j, "format", json_string(hv_enum_name(&k_formats, (int)r->format) ? hv_enum_name(&k_formats, (int)r->format) : "?"));
    failed |= hv_json_set(j, "facets", json_integer((json_int_t)r->facets));
    failed |= hv_json_set(j, "vertices", json_integer((json_int_t)r->vertices));
    failed |= hv_json_set(j, "bbox", json_pack("{s:o, s:o}", "min", hv_json_numbers(r->bbox_min, 3), "max",
                                                hv_json_numbers(r->bbox_max, 3)));
    failed |= hv_json_set(j, "volume", hv_json_number(r->volume));
    failed |= hv_json_set(j, "area", hv_json_number(r->area));
    for (int i = 2; i < (int)HV_COUNT(k_counts); ++i)
        failed |= hv_json_set(j, k_counts[i], json_integer((json_int_t)*count_field(&c, i)));
    failed |= hv_json_set(j, "closed", json_boolean(r->open_edges == 0 && r->nonmanifold_edges == 0));
    if (failed) {
        json_decref(j);
        return NULL;
    }
    return j;
}

hv_status hv_mesh_report_from_doc(const json_t *doc, const char *what, hv_mesh_report *r)
{
    memset(r, 0, sizeof *r);
    int format;
    hv_status s = hv_json_get_name(doc, "format", what, &k_formats, &format);
    r->format = (hv_mesh_format)format;
    for (int i = 0; i < (int)HV_COUNT(k_counts) && s == HV_OK; ++i) {
        long long n;
        s = hv_json_get_int(doc, k_counts[i], what, 0, INT64_MAX, &n);
        *count_field(r, i) = (uint64_t)n;
    }
    const json_t *bbox;
    char place[300];
    snprintf(place, sizeof place, "%s: bbox", what);
    if (s == HV_OK) s = hv_json_need(doc, "bbox", JSON_OBJECT, what, &bbox);
    if (s == HV_OK) s = hv_json_get_numbers(bbox, "min", place, r->bbox_min, 3);
    if (s == HV_OK) s = hv_json_get_numbers(bbox, "max", place, r->bbox_max, 3);
    if (s == HV_OK) s = hv_json_get_number(doc, "volume", what, &r->volume);
    if (s == HV_OK) s = hv_json_get_number(doc, "area", what, &r->area);
    return s;
}

const char *hv_mesh_format_key(hv_mesh_format format)
{
    const char *n = hv_enum_name(&k_formats, (int)format);
    return n ? n : "?";
}

const char *hv_mesh_material_color_text(const hv_mesh_material *mat, char buf[10])
{
    uint32_t c = mat->rgba;
    if ((c & 0xFF) == 0xFF) snprintf(buf, 10, "#%06x", (unsigned)(c >> 8));
    else snprintf(buf, 10, "#%08x", (unsigned)c);
    return buf;
}

int hv_mesh_report_inside_out(const hv_mesh_report *r)
{
    return r->open_edges == 0 && r->nonmanifold_edges == 0 && r->volume < 0;
}

void hv_mesh_info_json(hv_buf *b, const char *file, const hv_mesh *m, const hv_mesh_report *body_reports)
{
    json_t *j = hv_mesh_report_to_doc(file, hv_mesh_get_report(m));
    json_t *mats = json_array(), *bodies = json_array();
    int failed = !j || !mats || !bodies;
    int any = 0; /* the mesh is inside out when a body is (the whole's volume sums them) */
    for (size_t i = 0; i < hv_mesh_body_count(m); ++i) any |= hv_mesh_report_inside_out(&body_reports[i]);
    if (!failed) failed |= hv_json_set(j, "inside_out", json_boolean(any));
    if (!failed && hv_mesh_file_unit(m)) failed |= hv_json_set(j, "unit", json_string(hv_mesh_file_unit(m)));
    if (!failed && hv_mesh_item_count(m)) { /* the file's build items (3MF) */
        json_t *items = json_array();
        failed |= !items || hv_json_set(j, "items", items);
        for (size_t i = 0; !failed && i < hv_mesh_item_count(m); ++i) {
            const hv_mesh_item *it = hv_mesh_item_at(m, i);
            json_t *o = json_object(), *t = json_array();
            failed |= !o || !t || json_array_append_new(items, o) != 0;
            if (failed) {
                json_decref(t);
                break;
            }
            failed |= hv_json_set(o, "object", json_integer((json_int_t)it->object_id));
            failed |= hv_json_set(o, "name", hv_json_text(it->object_name));
            failed |= hv_json_set(o, "body", it->body >= 0 ? hv_json_text(hv_mesh_body_at(m, (size_t)it->body)->name) : json_null());
            json_t *names = json_array(); /* an item of components: one body per mesh object it places */
            for (size_t k = 0; names && it->body >= 0 && k < it->bodies; ++k)
                failed |= json_array_append_new(names, hv_json_text(hv_mesh_body_at(m, (size_t)it->body + k)->name)) != 0;
            failed |= !names || hv_json_set(o, "bodies", names);
            for (int k = 0; k < 12; ++k) failed |= json_array_append_new(t, json_real(it->transform[k])) != 0;
            failed |= hv_json_set(o, "transform", t);
        }
    }
    for (size_t k = 0; !failed && k < hv_mesh_material_count(m); ++k) {
        const hv_mesh_material *mt = hv_mesh_material_at(m, k);
        char col[10];
        json_t *o = json_object();
        failed |= !o || json_array_append_new(mats, o) != 0;
        if (failed) break;
        failed |= hv_json_set(o, "name", hv_json_text(mt->name));
        failed |= hv_json_set(o, "color", mt->has_color ? json_string(hv_mesh_material_color_text(mt, col)) : json_null());
        if (mt->nparts) { /* a mixture: {"BASE": fraction, ...} */
            json_t *mix = json_object();
            failed |= !mix || hv_json_set(o, "mixture", mix);
            for (size_t q = 0; !failed && q < mt->nparts; ++q)
                failed |= hv_json_set(mix, mt->parts[q].material, hv_json_number(mt->parts[q].fraction));
        }
    }
    for (size_t i = 0; !failed && i < hv_mesh_body_count(m); ++i) {
        const hv_mesh_body *bd = hv_mesh_body_at(m, i);
        json_t *o = json_object(), *r = hv_mesh_report_to_doc("", &body_reports[i]);
        failed |= !o || !r || json_array_append_new(bodies, o) != 0;
        if (failed) {
            json_decref(r);
            break;
        }
        failed |= hv_json_set(o, "name", hv_json_text(bd->name));
        failed |= hv_json_set(o, "material", bd->material >= 0 ? hv_json_text(hv_mesh_material_at(m, (size_t)bd->material)->name)
                                                                : json_null());
        failed |= hv_json_set(o, "first_facet", json_integer((json_int_t)bd->first_facet));
        failed |= hv_json_set(o, "inside_out", json_boolean(hv_mesh_report_inside_out(&body_reports[i])));
        const char *key;
        json_t *v;
        json_object_foreach(r, key, v) {
            if (strcmp(key, "file") != 0) failed |= hv_json_set(o, key, json_incref(v));
        }
        json_decref(r);
    }
    if (!failed) {
        failed |= hv_json_set(j, "materials", mats);
        failed |= hv_json_set(j, "bodies", bodies);
        mats = bodies = NULL;
    }
    char *text = failed ? NULL : hv_json_dump(j);
    json_decref(j);
    json_decref(mats);
    json_decref(bodies);
    if (text) hv_buf_puts(b, text);
    else b->failed = 1;
    free(text);
}

void hv_mesh_report_json(hv_buf *b, const char *file, const hv_mesh_report *r)
{
    json_t *j = hv_mesh_report_to_doc(file, r);
    char *text = j ? hv_json_dump(j) : NULL;
    json_decref(j);
    if (text) hv_buf_puts(b, text);
    else b->failed = 1;
    free(text);
}
