/* src/mesh/mesh_internal.h - the mesh object and its builder, shared by the STL reader,
 * the generators and the slicer. */
#ifndef HOVOX_MESH_INTERNAL_H
#define HOVOX_MESH_INTERNAL_H

#include "hovox/mesh.h"
#include "core/internal.h"

struct hv_mesh {
    char *name;
    size_t nv, nf;
    float *xyz;       /* 3 per vertex */
    uint32_t *tri;    /* 3 per facet */
    int32_t *nbr;     /* 3 per facet */
    uint8_t *eflags;  /* per facet, bit e: edge e non-manifold */
    hv_mesh_report report;
};

/* Build a mesh from a triangle soup (9 floats per facet, finite, checked by the caller).
 * `normals` (3 per facet) may be NULL; it only feeds report.normal_mismatch. Takes no
 * ownership. */
hv_status hv_mesh_from_soup(const float *soup, const float *normals, size_t nf, const char *name,
                            hv_mesh_format format, hv_mesh **out);

/* Append the report as a JSON object (keys of `hovox info --json`; hv_mesh_report_to_doc, see
 * volumes/schema.h); sets b->failed when out of memory. */
void hv_mesh_report_json(hv_buf *b, const char *file, const hv_mesh_report *r);

#endif
