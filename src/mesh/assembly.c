/* src/mesh/assembly.c - assemblies moved (hovox/mesh.h): an affine transform that keeps the bodies
 * and materials (a part turned on a tray keeps its bodies) and its appearance. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "mesh_internal.h"

hv_status hv_mesh_transform(const hv_mesh *m, const double a[12], hv_mesh **out)
{
    *out = NULL;
    for (int k = 0; k < 12; ++k)
        if (!isfinite(a[k])) return hv_error_set(HV_ERR_INVALID, "mesh transform: entry %d is not finite (%g)", k, a[k]);
    double det = a[0] * (a[5] * a[10] - a[6] * a[9]) - a[1] * (a[4] * a[10] - a[6] * a[8]) +
                 a[2] * (a[4] * a[9] - a[5] * a[8]);
    if (!(det != 0)) return hv_error_set(HV_ERR_INVALID, "mesh transform: the matrix is singular");
    float *soup = hv_malloc_array(m->nf, 9 * sizeof(float));
    if (!soup) return HV_ERR_NOMEM;
    for (size_t f = 0; f < m->nf; ++f)
        for (int k = 0; k < 3; ++k) {
            /* a mirror turns the winding: swap two vertices so facets stay outward */
            int kk = det < 0 && k > 0 ? 3 - k : k;
            const float *p = m->xyz + 3 * (size_t)m->tri[3 * f + (size_t)kk];
            float *q = soup + 9 * f + 3 * (size_t)k;
            for (int r = 0; r < 3; ++r) {
                double v = a[4 * r] * p[0] + a[4 * r + 1] * p[1] + a[4 * r + 2] * p[2] + a[4 * r + 3];
                if (!(fabs(v) <= 3.4e38)) {
                    free(soup);
                    return hv_error_set(HV_ERR_INVALID, "mesh transform: vertex %u leaves the float range",
                                        m->tri[3 * f + (size_t)kk]);
                }
                q[r] = (float)v;
            }
        }
    hv_status s = hv_mesh_from_soup(soup, NULL, m->nf, hv_mesh_name(m), m->report.format, out);
    free(soup);
    if (s == HV_OK) s = hv_mesh_set_bodies(*out, m->bodies, m->nbodies, m->mats, m->nmats, m->facet_mat);
    if (s == HV_OK) s = hv_mesh_appearance_copy(*out, m, 0, m->nf, det < 0);
    if (s != HV_OK) {
        hv_mesh_destroy(*out);
        *out = NULL;
    }
    return s;
}
