/* src/mesh/mesh_internal.h - the mesh object and its builder, shared by the file readers
 * (src/io), the generators and the slicer. */
#ifndef HOVOX_MESH_INTERNAL_H
#define HOVOX_MESH_INTERNAL_H

#include "hovox/mesh.h"
#include "core/internal.h"
#include "core/json.h"

struct hv_mesh {
    char *name;
    size_t nv, nf;
    float *xyz;       /* 3 per vertex */
    uint32_t *tri;    /* 3 per facet */
    int32_t *nbr;     /* 3 per facet */
    uint8_t *eflags;  /* per facet, bit e: edge e non-manifold */
    hv_mesh_report report;
    hv_mesh_body *bodies;     /* nbodies >= 1 once built */
    size_t nbodies;
    hv_mesh_material *mats;
    size_t nmats;
    int32_t *facet_mat;       /* nf entries, or NULL */
    /* appearance (appearance.c) */
    uint32_t *corner_rgba;    /* 3 per facet, or NULL */
    float *corner_uv;         /* 6 per facet, or NULL (then facet_tex is NULL too) */
    int32_t *facet_tex;       /* per facet a texture, -1 or HV_MESH_NO_COLOUR */
    hv_mesh_texture *tex;     /* names and pixels owned */
    size_t ntex;
    char **notes;             /* reader notes (hv_mesh_note_at) */
    size_t nnotes;
    char *file_unit;          /* hv_mesh_file_unit */
    hv_mesh_item *items;      /* hv_mesh_item_at; names owned */
    size_t nitems;
};

/* Give a mesh the file's unit (may be NULL) and build items (copied, names too). Errors:
 * HV_ERR_NOMEM. */
hv_status hv_mesh_set_file_info(hv_mesh *m, const char *unit, const hv_mesh_item *items, size_t n);

/* Add a reader note (copied). Errors: HV_ERR_NOMEM. */
hv_status hv_mesh_add_note(hv_mesh *m, const char *text);

/* Give dst (just built from src's facets [first, first + n), in order) src's appearance of
 * those facets; swap: corners 1 and 2 of every facet were exchanged (a mirror). */
hv_status hv_mesh_appearance_copy(hv_mesh *dst, const hv_mesh *src, size_t first, size_t n, int swap);
/* The appearance of parts[0..n) (meshes whose facets were concatenated into dst, in order). */
hv_status hv_mesh_appearance_join(hv_mesh *dst, const hv_mesh *const *parts, size_t n);
void hv_mesh_appearance_free(hv_mesh *m);

/* Give a mesh just built by hv_mesh_from_soup its bodies and materials (readers). Body names
 * may be NULL, empty or repeated (made unique: "body N", "NAME (2)"); first_facet is ignored
 * (bodies are consecutive, in order) and the facet counts must sum to the mesh's facets. A
 * body whose material is HV_MESH_NO_MATERIAL takes its facets' majority material when
 * facet_mat is given. Copies everything. Errors: HV_ERR_INVALID (counts), HV_ERR_NOMEM. */
hv_status hv_mesh_set_bodies(hv_mesh *m, const hv_mesh_body *bodies, size_t n,
                             const hv_mesh_material *mats, size_t nmats, const int32_t *facet_mat);

/* Build a mesh from a triangle soup (9 floats per facet, finite, checked by the caller).
 * `normals` (3 per facet) may be NULL; it only feeds report.normal_mismatch. Takes no
 * ownership. */
hv_status hv_mesh_from_soup(const float *soup, const float *normals, size_t nf, const char *name,
                            hv_mesh_format format, hv_mesh **out);

/* The mesh hv_mesh_from_soup makes of the soup that facets `tri` (3 indices per facet, each below
 * npts) over the points `xyz` (3 floats per point, finite) expand to, vertex for vertex, but
 * welding the points, not the corners. Points no facet uses are dropped. Takes no ownership. */
hv_status hv_mesh_from_indexed(const float *xyz, size_t npts, const uint32_t *tri, size_t nf,
                               const char *name, hv_mesh_format format, hv_mesh **out);

/* Append the report as a JSON object (keys of `hovox info --json`; hv_mesh_report_to_doc, see
 * volumes/schema.h); sets b->failed when out of memory. */
void hv_mesh_report_json(hv_buf *b, const char *file, const hv_mesh_report *r);

/* The document of `hovox info --json` for one mesh: the keys of hv_mesh_report_json, then
 * "materials" ([{"name", "color": "#rrggbb[aa]" or null}]) and "bodies" ([{"name", "material"
 * (a name or null), "first_facet", and the report keys of body_reports[i]}]). Sets b->failed
 * when out of memory. */
void hv_mesh_info_json(hv_buf *b, const char *file, const hv_mesh *m, const hv_mesh_report *body_reports);


/* The display colour of a material as text: "#rrggbb", "#rrggbbaa" when not opaque; buf. */
const char *hv_mesh_material_color_text(const hv_mesh_material *mat, char buf[10]);

/* The one body of a mesh built from a soup: named after the file (base name without the
 * extension) or "body 1". Called by hv_mesh_from_soup. */
hv_status hv_mesh_default_body(hv_mesh *m);
/* The index of the body named `body` (a mesh without bodies gets its default one first). Errors:
 * HV_ERR_NOT_FOUND ("gear.obj: no body 'hub' (bodies: rim, spokes)"), HV_ERR_NOMEM. */
hv_status hv_mesh_body_index(hv_mesh *m, const char *body, size_t *out);
void hv_mesh_bodies_free(hv_mesh *m);

/* hovox.mesh.json (report_json.c; volumes/schema.h): also the object of `hovox info --json`.
 * to_doc: a new object without "schema" (NULL when out of memory); from_doc: `what` names the
 * document in messages, errors HV_ERR_BAD_INPUT naming the member, HV_ERR_NOMEM. */
json_t *hv_mesh_report_to_doc(const char *file, const hv_mesh_report *r);
hv_status hv_mesh_report_from_doc(const json_t *doc, const char *what, hv_mesh_report *r);

#endif
