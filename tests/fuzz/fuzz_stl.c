/* tests/fuzz/fuzz_stl.c - fuzz target: any bytes through the STL parser (format detection,
 * binary and ASCII readers, welding, adjacency, report) must fail cleanly or build a mesh
 * whose report is self-consistent. */
#include <stdint.h>
#include <stdlib.h>

#include "hovox/mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_mesh *m = NULL;
    hv_status s = hv_mesh_parse_stl(data, size, "fuzz.stl", &m);
    if (s == HV_OK) {
        const hv_mesh_report *r = hv_mesh_get_report(m);
        if (r->facets != hv_mesh_facet_count(m) || r->vertices > 3 * r->facets || r->shells > r->facets) abort();
        const uint32_t *t = hv_mesh_facets(m);
        for (size_t i = 0; i < 3 * hv_mesh_facet_count(m); ++i)
            if (t[i] >= hv_mesh_vertex_count(m)) abort();
        hv_mesh_destroy(m);
    } else if (m) {
        abort(); /* failures must not hand out a mesh */
    }
    return 0;
}
