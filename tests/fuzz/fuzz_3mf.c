/* tests/fuzz/fuzz_3mf.c - fuzz target: any bytes as a 3MF package through hv_mesh_parse_3mf (the
 * ZIP checks, the model part scan, lib3mf in the bridge plugin, the placing of build items) must
 * fail cleanly, handing out no mesh, or build a self-consistent mesh, within a small memory
 * budget (expansion and component bombs are refused). */
#include <stdint.h>
#include <stdlib.h>

#include "hovox/mesh.h"
#include "mesh_fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_set_memory_cap(256u << 20);
    hv_mesh *m = NULL;
    hv_status s = hv_mesh_parse_3mf(data, size, "fuzz.3mf", &m);
    if (s == HV_OK) {
        fuzz_check_mesh(m);
        hv_mesh_destroy(m);
    } else if (m || s == HV_ERR_UNSUPPORTED) {
        abort(); /* failures hand out no mesh; the bridge plugin must load */
    }
    return 0;
}
