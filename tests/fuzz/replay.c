/* tests/fuzz/replay.c - runs a fuzz target over corpus files (the regression half of fuzzing,
 * part of `make test` and `make sanitize`); libFuzzer builds (`make fuzz`) use their own main. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int main(int argc, char **argv)
{
    int n = 0;
    for (int i = 1; i < argc; ++i) {
        FILE *fp = fopen(argv[i], "rb");
        if (!fp) continue; /* directories and the like */
        size_t cap = 1 << 16, len = 0, got;
        uint8_t *buf = malloc(cap);
        while (buf && (got = fread(buf + len, 1, cap - len, fp)) > 0) {
            len += got;
            if (len == cap) buf = realloc(buf, cap *= 2);
        }
        fclose(fp);
        if (!buf) return 2;
        LLVMFuzzerTestOneInput(buf, len);
        free(buf);
        ++n;
    }
    printf("%d inputs replayed\n", n);
    return 0;
}
