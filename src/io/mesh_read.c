/* src/io/mesh_read.c - the last step of every mesh reader: facets grouped into bodies become a
 * mesh. */
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "io_internal.h"

/* ---- the last step of a reader ----------------------------------------------------------- */

/* Bodies and materials given to a mesh just built (destroyed on failure). */
static hv_status with_bodies(hv_mesh *m, size_t nf, const char *name, const hv_mesh_body *bodies, size_t nbodies,
                             const hv_mesh_material *mats, size_t nmats, const int32_t *facet_mat, hv_mesh **out)
{
    hv_status s = HV_OK;
    if (nbodies > 0 || nmats > 0) {
        hv_mesh_body whole = {NULL, HV_MESH_NO_MATERIAL, 0, nf, 0};
        char *stem = NULL;
        if (nbodies == 0) { /* one body named after the file, with the materials given */
            stem = hv_file_stem(name);
            if (!stem) {
                hv_mesh_destroy(m);
                return HV_ERR_NOMEM;
            }
            whole.name = stem;
            bodies = &whole;
            nbodies = 1;
        }
        s = hv_mesh_set_bodies(m, bodies, nbodies, mats, nmats, facet_mat);
        free(stem);
        if (s != HV_OK) {
            hv_mesh_destroy(m);
            return s;
        }
    }
    *out = m;
    return HV_OK;
}

hv_status hv_mesh_build(const float *soup, size_t nf, const char *name, hv_mesh_format format,
                        const hv_mesh_body *bodies, size_t nbodies, const hv_mesh_material *mats,
                        size_t nmats, const int32_t *facet_mat, hv_mesh **out)
{
    *out = NULL;
    hv_mesh *m = NULL;
    hv_status s = hv_mesh_from_soup(soup, NULL, nf, name, format, &m);
    if (s != HV_OK) return s;
    return with_bodies(m, nf, name, bodies, nbodies, mats, nmats, facet_mat, out);
}

hv_status hv_mesh_build_indexed(const float *xyz, size_t npts, const uint32_t *tri, size_t nf, const char *name,
                                hv_mesh_format format, const hv_mesh_body *bodies, size_t nbodies,
                                const hv_mesh_material *mats, size_t nmats, const int32_t *facet_mat, hv_mesh **out)
{
    *out = NULL;
    hv_mesh *m = NULL;
    hv_status s = hv_mesh_from_indexed(xyz, npts, tri, nf, name, format, &m);
    if (s != HV_OK) return s;
    return with_bodies(m, nf, name, bodies, nbodies, mats, nmats, facet_mat, out);
}

/* ---- vertex colours ------------------------------------------------------------------------ */

hv_status hv_io_vertex_colours(hv_mesh *m, const uint32_t *vcol, const uint32_t *tri, size_t nt, const size_t *where)
{
    uint32_t *corner = hv_malloc_array(nt, 3 * sizeof *corner);
    if (!corner) return HV_ERR_NOMEM;
    for (size_t t = 0; t < nt; ++t)
        for (size_t c = 0; c < 3; ++c) corner[3 * (where ? where[t] : t) + c] = vcol[tri[3 * t + c]];
    hv_status s = hv_mesh_set_corner_colours(m, corner);
    free(corner);
    return s;
}
