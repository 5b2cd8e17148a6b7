/* tests/fuzz/mesh_fuzz_check.h - what the mesh reader fuzz targets check of every mesh a reader
 * builds: the report agrees with the arrays, every index is in range, every coordinate finite,
 * the bodies tile the facets with unique names, and every material reference is valid. */
#ifndef HOVOX_FUZZ_MESH_CHECK_H
#define HOVOX_FUZZ_MESH_CHECK_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/mesh.h"

static inline void fuzz_check_mesh(const hv_mesh *m)
{
    const hv_mesh_report *r = hv_mesh_get_report(m);
    size_t nf = hv_mesh_facet_count(m), nv = hv_mesh_vertex_count(m);
    if (r->facets != nf || r->vertices != nv || nv > 3 * nf || r->shells > nf || nf == 0) abort();
    const uint32_t *t = hv_mesh_facets(m);
    for (size_t i = 0; i < 3 * nf; ++i)
        if (t[i] >= nv) abort();
    const float *x = hv_mesh_vertices(m);
    for (size_t i = 0; i < 3 * nv; ++i)
        if (!isfinite(x[i])) abort();
    size_t nb = hv_mesh_body_count(m), nm = hv_mesh_material_count(m), next = 0;
    if (nb == 0) abort();
    for (size_t b = 0; b < nb; ++b) {
        const hv_mesh_body *body = hv_mesh_body_at(m, b);
        if (body->first_facet != next || body->facet_count == 0 || !body->name[0]) abort();
        if (body->material != HV_MESH_NO_MATERIAL && (body->material < 0 || (size_t)body->material >= nm)) abort();
        if (hv_mesh_body_find(m, body->name) != (int64_t)b) abort(); /* names are unique */
        next += body->facet_count;
    }
    if (next != nf) abort();
    const int32_t *fm = hv_mesh_facet_materials(m);
    for (size_t f = 0; fm && f < nf; ++f)
        if (fm[f] != HV_MESH_NO_MATERIAL && (fm[f] < 0 || (size_t)fm[f] >= nm)) abort();
    for (size_t k = 0; k < nm; ++k)
        if (!hv_mesh_material_at(m, k)->name) abort();
}

/* One input through a reader's parse function: a failure hands out no mesh, a success builds a
 * mesh fuzz_check_mesh accepts. Returns the reader's status. */
typedef hv_status (*fuzz_mesh_parser)(const void *data, size_t size, const char *name, hv_mesh **out);
static inline hv_status fuzz_mesh_parse(fuzz_mesh_parser parse, const void *data, size_t size, const char *name)
{
    hv_mesh *m = NULL;
    hv_status s = parse(data, size, name, &m);
    if (s == HV_OK) {
        fuzz_check_mesh(m);
        hv_mesh_destroy(m);
    } else if (m) {
        abort(); /* failures must not hand out a mesh */
    }
    return s;
}

#endif
