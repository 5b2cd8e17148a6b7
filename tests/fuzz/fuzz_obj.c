/* tests/fuzz/fuzz_obj.c - fuzz target: any bytes through the OBJ reader (hv_mesh_parse_obj) must
 * fail cleanly, handing out no mesh, or build a mesh whose report, bodies and materials are
 * self-consistent. */
#include <stdint.h>
#include <stdlib.h>

#include "hovox/mesh.h"
#include "mesh_fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_mesh *m = NULL;
    hv_status s = hv_mesh_parse_obj(data, size, "fuzz.obj", &m);
    if (s == HV_OK) {
        fuzz_check_mesh(m);
        hv_mesh_destroy(m);
    } else if (m) {
        abort(); /* failures must not hand out a mesh */
    }
    return 0;
}
