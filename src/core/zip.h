/* src/core/zip.h - ZIP archives written with libzip (core/zip.c): the GCVF zip of slice stacks
 * and 3MF packages. Internal. */
#ifndef HOVOX_ZIP_H
#define HOVOX_ZIP_H

#include "hovox/core.h"

/* ZIP archives on libzip (ZIP64 when needed), written for reproducible bytes: every entry
 * dated 1980-01-01 00:00 with mode 0644, stored or deflated as asked.
 * hv_zip_open creates a temporary next to `path` (for a special path such as a FIFO or
 * /dev/null, in $TMPDIR: zip needs to seek), so an unwritable place fails before any work.
 * Entries are only recorded until hv_zip_write: hv_zip_add_data copies its bytes,
 * hv_zip_add_file keeps the file's name and reads it then (no file held open or in memory;
 * about 0.5 KiB per entry). hv_zip_write writes the archive to the temporary and syncs it,
 * reporting `stage` progress and polling hv_cancel_requested; hv_zip_commit renames it into
 * place (copies it, for a special path) and frees z; hv_zip_abort removes it and frees z.
 * Errors: HV_ERR_IO naming the archive and libzip's reason, or the entry file that cannot be
 * read; HV_ERR_NOMEM; HV_ERR_CANCELLED or the progress callback's status. After an error the
 * caller calls hv_zip_abort. Not thread-safe. hv_zip_set_level sets the deflate level (1-9,
 * default 6) of the entries added after it. */
typedef struct hv_zip hv_zip;
hv_status hv_zip_open(const char *path, hv_zip **out);
void hv_zip_set_level(hv_zip *z, int level);
hv_status hv_zip_add_data(hv_zip *z, const char *name, const void *data, size_t size, int deflate);
/* As hv_zip_add_data, taking `data` (malloc'd) instead of copying it: freed by the archive, also
 * on failure. */
hv_status hv_zip_add_owned(hv_zip *z, const char *name, void *data, size_t size, int deflate);
hv_status hv_zip_add_file(hv_zip *z, const char *name, const char *file, int deflate);
hv_status hv_zip_write(hv_zip *z, const hv_progress *progress, const char *stage);
hv_status hv_zip_commit(hv_zip *z);
void hv_zip_abort(hv_zip *z);

#endif
