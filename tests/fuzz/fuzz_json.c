/* tests/fuzz/fuzz_json.c - fuzz target: the JSON reader (metadata, manifests) must reject or
 * parse any bytes without crashing, and what it parses must be walkable. */
#include <stdint.h>
#include <stdlib.h>

#include "core/internal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static size_t walk(const hv_json *j, int depth)
{
    size_t n = 1;
    if (depth > 300) abort();
    for (const hv_json *c = j->child; c; c = c->next) n += walk(c, depth + 1);
    return n;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_json *j = hv_json_parse((const char *)data, size);
    if (j) {
        walk(j, 0);
        hv_json_free(j);
    }
    return 0;
}
