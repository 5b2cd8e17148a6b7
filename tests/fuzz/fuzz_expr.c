/* tests/fuzz/fuzz_expr.c - fuzz target: distribution-function expressions (`hovox grade --f`,
 * Lua f strings) must parse or fail with a message, and evaluate without crashing. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/material.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    hv_dfn *f = NULL;
    if (hv_dfn_expr(text, &f) == HV_OK) {
        for (int i = 0; i <= 8; ++i) (void)hv_dfn_eval(f, i * 1.25, 10);
        hv_dfn_destroy(f);
    } else if (f || !*hv_last_error()) {
        abort(); /* a failure sets a message and hands out nothing */
    }
    free(text);
    return 0;
}
