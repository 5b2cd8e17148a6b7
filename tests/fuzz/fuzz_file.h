/* tests/fuzz/fuzz_file.h - for fuzz targets whose reader takes a path: the input written to a
 * file of this process's own ("/tmp/hovox-fuzz-<tag>-<pid>.vdb"), its path returned, or NULL
 * when it cannot be written (the input is then skipped). The caller removes it. */
#ifndef HOVOX_FUZZ_FILE_H
#define HOVOX_FUZZ_FILE_H

#include <stdint.h>
#include <stdio.h>
#include <unistd.h>

static const char *fuzz_write_file(const char *tag, const char *ext, const uint8_t *data, size_t size)
{
    static char path[96];
    snprintf(path, sizeof path, "/tmp/hovox-fuzz-%s-%ld%s", tag, (long)getpid(), ext);
    FILE *fp = fopen(path, "wb");
    if (!fp) return NULL;
    int ok = fwrite(data, 1, size, fp) == size;
    ok &= fclose(fp) == 0;
    return ok ? path : NULL;
}

#endif
