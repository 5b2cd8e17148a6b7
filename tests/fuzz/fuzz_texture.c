/* tests/fuzz/fuzz_texture.c - fuzz target: any bytes as a texture picture (hv_rgba8_decode, PNG or
 * JPEG by signature): decoded whole within the pixel limit, or refused with a message and nothing
 * handed out; nothing crashes or leaks. */
#include <stdint.h>
#include <stdlib.h>

#include "hovox/image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_rgba8 img;
    hv_status s = hv_rgba8_decode(data, size, "fuzz.img", (uint64_t)1 << 22, &img);
    if (s == HV_OK) {
        if (!img.rgba || img.width <= 0 || img.height <= 0 ||
            (uint64_t)img.width * (uint64_t)img.height > (uint64_t)1 << 22)
            abort();
        volatile uint8_t sum = 0; /* every byte readable */
        for (size_t i = 0; i < (size_t)img.width * (size_t)img.height * 4; ++i) sum = (uint8_t)(sum + img.rgba[i]);
        (void)sum;
        if ((img.icc == NULL) != (img.icc_size == 0)) abort();
    } else if (img.rgba || img.icc) {
        abort();
    }
    hv_rgba8_free(&img);
    return 0;
}
