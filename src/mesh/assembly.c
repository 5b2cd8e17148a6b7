/* src/mesh/assembly.c - assemblies out and moved (hovox/mesh.h): a multi-body mesh written as
 * OBJ (one `o` group and `usemtl` per body), and an affine transform that keeps the bodies and
 * materials (a part turned on a tray keeps its bodies). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "mesh_internal.h"

/* A name on one OBJ line: control characters (a newline would end the statement) become '_'. */
static void put_name(FILE *fp, const char *s)
{
    for (; *s; ++s) fputc((unsigned char)*s < 0x20 || *s == 0x7f ? '_' : *s, fp);
}

hv_status hv_mesh_write_obj(const hv_mesh *m, const char *path)
{
    if (hv_check_extension(path, ".obj", "a mesh") != HV_OK) return HV_ERR_INVALID;
    hv_atomic_file af;
    hv_status s = hv_atomic_open(&af, path, "wb");
    if (s != HV_OK) return s;
    FILE *fp = af.fp;
    fprintf(fp, "# written by hovox: %zu bodies, %zu vertices, %zu facets\n", m->nbodies, m->nv, m->nf);
    for (size_t i = 0; i < m->nv; ++i)
        fprintf(fp, "v %.9g %.9g %.9g\n", (double)m->xyz[3 * i], (double)m->xyz[3 * i + 1], (double)m->xyz[3 * i + 2]);
    int active = 0; /* a usemtl is in effect: OBJ carries it over to the next group */
    for (size_t b = 0; b < m->nbodies; ++b) {
        const hv_mesh_body *body = &m->bodies[b];
        fputs("o ", fp);
        put_name(fp, body->name);
        fputc('\n', fp);
        if (body->material != HV_MESH_NO_MATERIAL) {
            fputs("usemtl ", fp);
            put_name(fp, m->mats[body->material].name);
            fputc('\n', fp);
            active = 1;
        } else if (active) {
            fputs("usemtl\n", fp); /* no material from here on */
            active = 0;
        }
        for (size_t f = body->first_facet; f < body->first_facet + body->facet_count; ++f)
            fprintf(fp, "f %lu %lu %lu\n", (unsigned long)m->tri[3 * f] + 1, (unsigned long)m->tri[3 * f + 1] + 1,
                    (unsigned long)m->tri[3 * f + 2] + 1);
    }
    return hv_atomic_commit(&af);
}

hv_status hv_mesh_save(const hv_mesh *m, const char *path, int ascii)
{
    if (hv_has_extension(path, ".obj")) return hv_mesh_write_obj(m, path);
    return hv_mesh_write_stl(m, path, ascii);
}

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
    if (s != HV_OK) {
        hv_mesh_destroy(*out);
        *out = NULL;
    }
    return s;
}
