/* tests/fuzz/fuzz_obj.c - fuzz target: any bytes through the OBJ reader (hv_mesh_parse_obj) must
 * fail cleanly, handing out no mesh, or build a mesh whose report, bodies and materials are
 * self-consistent. */
#include <stdint.h>

#include "hovox/mesh.h"
#include "mesh_fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    (void)fuzz_mesh_parse(hv_mesh_parse_obj, data, size, "fuzz.obj");
    return 0;
}
