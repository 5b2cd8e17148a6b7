/* src/mesh/report_json.c - the mesh report as JSON (for `hovox info --json` and the
 * "hovox.mesh.json" metadata of voxelized models). */
#include "core/internal.h"
#include "mesh_internal.h"

static void vec3(hv_buf *b, const double *v)
{
    hv_buf_puts(b, "[");
    for (int a = 0; a < 3; ++a) {
        if (a) hv_buf_puts(b, ", ");
        hv_buf_json_number(b, (double)(float)v[a] == v[a] ? (double)(float)v[a] : v[a]);
    }
    hv_buf_puts(b, "]");
}

void hv_mesh_report_json(hv_buf *b, const char *file, const hv_mesh_report *r)
{
    hv_buf_puts(b, "{\"file\": ");
    hv_buf_json_string(b, file);
    hv_buf_printf(b, ", \"format\": \"%s\"",
                  r->format == HV_MESH_STL_BINARY  ? "binary"
                  : r->format == HV_MESH_STL_ASCII ? "ascii"
                                                   : "generated");
    hv_buf_printf(b, ", \"facets\": %llu, \"vertices\": %llu", (unsigned long long)r->facets,
                  (unsigned long long)r->vertices);
    hv_buf_puts(b, ", \"bbox\": {\"min\": ");
    vec3(b, r->bbox_min);
    hv_buf_puts(b, ", \"max\": ");
    vec3(b, r->bbox_max);
    hv_buf_puts(b, "}, \"volume\": ");
    hv_buf_json_number(b, r->volume);
    hv_buf_puts(b, ", \"area\": ");
    hv_buf_json_number(b, r->area);
    hv_buf_printf(b,
                  ", \"shells\": %llu, \"open_edges\": %llu, \"nonmanifold_edges\": %llu, "
                  "\"degenerate_facets\": %llu, \"flipped_facets\": %llu, "
                  "\"normal_mismatch\": %llu, \"closed\": %s}",
                  (unsigned long long)r->shells, (unsigned long long)r->open_edges,
                  (unsigned long long)r->nonmanifold_edges,
                  (unsigned long long)r->degenerate_facets,
                  (unsigned long long)r->flipped_facets, (unsigned long long)r->normal_mismatch,
                  r->open_edges == 0 && r->nonmanifold_edges == 0 ? "true" : "false");
}
