/* tests/fuzz/fuzz_3mf.c - fuzz target: any bytes through hv_mesh_parse_3mf (the package module's
 * ZIP, relationship and content-type checks, the streamed model part, the placing of build items) must fail cleanly,
 * handing out no mesh, or build a self-consistent mesh, within a small memory budget
 * (expansion and component bombs are refused). Bytes that start with "PK" are a package as
 * they are; any others are the model part's XML, packed here with the content types and root
 * relationships (stored, uncompressed), so that mutations reach the XML instead of breaking
 * the deflate streams. */
#include <stdint.h>
#include <stdlib.h>

#include "hovox/mesh.h"
#include "mesh_fuzz_check.h"
#include "threemf_fuzz_pack.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_set_memory_cap(256u << 20);
    uint8_t *packed;
    data = fuzz_3mf_input(data, &size, ZIP_CM_STORE, &packed);
    if (!data) return 0;
    /* HV_ERR_UNSUPPORTED is a clean refusal (an extension hovox does not read): the reader has
     * no plugin since the package module replaced lib3mf */
    fuzz_mesh_parse(hv_mesh_parse_3mf, data, size, "fuzz.3mf");
    free(packed);
    return 0;
}
