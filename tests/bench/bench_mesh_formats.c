/* tests/bench/bench_mesh_formats.c - writes one mesh (read from an STL) as OBJ, binary PLY and
 * 3MF (the 3MF by lib3mf's own writer), the inputs of the mesh-format bench
 * (scripts/bench/12-mesh-formats.sh): the same facets in each format, so the readers' times
 * compare. Usage: bench_mesh_formats MESH.stl OUT_STEM (writes OUT_STEM.obj, .ply, .3mf). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/core.h"
#include "hovox/mesh.h"
#include "support/lib3mf_c.h"

static int write_obj(const hv_mesh *m, const char *path)
{
    FILE *fp = fopen(path, "w");
    if (!fp) return 1;
    const float *x = hv_mesh_vertices(m);
    const uint32_t *t = hv_mesh_facets(m);
    fprintf(fp, "# %zu facets, written by bench_mesh_formats\no knot\n", hv_mesh_facet_count(m));
    for (size_t v = 0; v < hv_mesh_vertex_count(m); ++v)
        fprintf(fp, "v %.9g %.9g %.9g\n", (double)x[3 * v], (double)x[3 * v + 1], (double)x[3 * v + 2]);
    for (size_t f = 0; f < hv_mesh_facet_count(m); ++f)
        fprintf(fp, "f %u %u %u\n", t[3 * f] + 1, t[3 * f + 1] + 1, t[3 * f + 2] + 1);
    return fclose(fp) != 0;
}

static int write_ply(const hv_mesh *m, const char *path)
{
    FILE *fp = fopen(path, "wb");
    if (!fp) return 1;
    size_t nv = hv_mesh_vertex_count(m), nf = hv_mesh_facet_count(m);
    fprintf(fp, "ply\nformat binary_little_endian 1.0\nelement vertex %zu\nproperty float x\nproperty float y\n"
                "property float z\nelement face %zu\nproperty list uchar int vertex_indices\nend_header\n",
            nv, nf);
    fwrite(hv_mesh_vertices(m), sizeof(float), 3 * nv, fp); /* x86: little-endian already */
    const uint32_t *t = hv_mesh_facets(m);
    for (size_t f = 0; f < nf; ++f) {
        unsigned char rec[13] = {3};
        memcpy(rec + 1, t + 3 * f, 12);
        fwrite(rec, 1, sizeof rec, fp);
    }
    return fclose(fp) != 0;
}

static int write_3mf(const hv_mesh *m, const char *path)
{
    l3mf model = NULL, mesh = NULL, item = NULL, writer = NULL;
    if (lib3mf_createmodel(&model) || lib3mf_model_addmeshobject(model, &mesh) ||
        lib3mf_object_setnameutf8(mesh, "knot") ||
        lib3mf_meshobject_setgeometry(mesh, hv_mesh_vertices(m), (unsigned)hv_mesh_vertex_count(m), hv_mesh_facets(m),
                                      (unsigned)hv_mesh_facet_count(m)) ||
        lib3mf_model_addbuilditem(model, mesh, NULL, &item) || lib3mf_model_querywriter(model, "3mf", &writer) ||
        lib3mf_writer_writetofileutf8(writer, path))
        return 1;
    lib3mf_release(writer);
    lib3mf_release(model);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fputs("usage: bench_mesh_formats MESH.stl OUT_STEM\n", stderr);
        return 2;
    }
    hv_mesh *m;
    if (hv_mesh_load(argv[1], &m) != HV_OK) {
        fprintf(stderr, "bench_mesh_formats: %s\n", hv_last_error());
        return 1;
    }
    char path[4096];
    static const char *const ext[] = {"obj", "ply", "3mf"};
    int (*const writers[])(const hv_mesh *, const char *) = {write_obj, write_ply, write_3mf};
    for (int k = 0; k < 3; ++k) {
        snprintf(path, sizeof path, "%s.%s", argv[2], ext[k]);
        if (writers[k](m, path)) {
            fprintf(stderr, "bench_mesh_formats: cannot write %s\n", path);
            return 1;
        }
    }
    hv_mesh_destroy(m);
    return 0;
}
