/* src/core/zip.c - ZIP archives on libzip for every writer that packs files (the GCVF zip of
 * slice stacks, 3MF packages): reproducible bytes, ZIP64 when needed (PKWARE APPNOTE 6.3), written
 * to a temporary next to the output and renamed when complete. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <zip.h>

#include "internal.h"
#include "zip.h"

struct hv_zip {
    zip_t *za;
    FILE *fp;           /* the temporary the archive is written to (zip needs to seek back) */
    char *path, *tmp;
    zip_error_t zerr;   /* errors of the write source */
    time_t mtime;       /* local time that is 1980-01-01 00:00 in DOS time: fixed bytes */
    int level;          /* deflate level of deflated entries (6 unless set) */
    const hv_progress *progress;
    const char *stage;
    hv_status cancel;   /* why the cancel callback stopped libzip */
    char **files;       /* entry files, to name the one that could not be read */
    size_t nfiles, cap;
};

/* The archive's write side: libzip writes, seeks back to patch local headers, and commits
 * through these commands into z->fp. Nothing is read back (a new archive), so stat says "no
 * such file" and libzip starts empty. */
static zip_int64_t zip_out(void *ud, void *data, zip_uint64_t len, zip_source_cmd_t cmd)
{
    hv_zip *z = ud;
    switch (cmd) {
    case ZIP_SOURCE_SUPPORTS:
        return zip_source_make_command_bitmap(ZIP_SOURCE_OPEN, ZIP_SOURCE_READ, ZIP_SOURCE_CLOSE, ZIP_SOURCE_STAT,
                                              ZIP_SOURCE_ERROR, ZIP_SOURCE_FREE, ZIP_SOURCE_SEEK, ZIP_SOURCE_TELL,
                                              ZIP_SOURCE_SUPPORTS, ZIP_SOURCE_BEGIN_WRITE, ZIP_SOURCE_COMMIT_WRITE,
                                              ZIP_SOURCE_ROLLBACK_WRITE, ZIP_SOURCE_WRITE, ZIP_SOURCE_SEEK_WRITE,
                                              ZIP_SOURCE_TELL_WRITE, ZIP_SOURCE_REMOVE, -1);
    case ZIP_SOURCE_STAT:
        zip_error_set(&z->zerr, ZIP_ER_READ, ENOENT); /* what libzip takes for "no such file" */
        return -1;
    case ZIP_SOURCE_OPEN:
    case ZIP_SOURCE_CLOSE:
    case ZIP_SOURCE_FREE:
    case ZIP_SOURCE_ROLLBACK_WRITE:
    case ZIP_SOURCE_REMOVE:
        return 0;
    case ZIP_SOURCE_READ:
    case ZIP_SOURCE_SEEK:
    case ZIP_SOURCE_TELL:
        zip_error_set(&z->zerr, ZIP_ER_OPNOTSUPP, 0);
        return -1;
    case ZIP_SOURCE_BEGIN_WRITE:
        if (fseeko(z->fp, 0, SEEK_SET) != 0 || ftruncate(fileno(z->fp), 0) != 0) {
            zip_error_set(&z->zerr, ZIP_ER_WRITE, errno);
            return -1;
        }
        return 0;
    case ZIP_SOURCE_WRITE:
        if (len > 0 && fwrite(data, 1, (size_t)len, z->fp) != len) {
            zip_error_set(&z->zerr, ZIP_ER_WRITE, errno);
            return -1;
        }
        return (zip_int64_t)len;
    case ZIP_SOURCE_SEEK_WRITE: {
        zip_source_args_seek_t *a = ZIP_SOURCE_GET_ARGS(zip_source_args_seek_t, data, len, &z->zerr);
        if (!a) return -1;
        if (fseeko(z->fp, (off_t)a->offset, a->whence) != 0) {
            zip_error_set(&z->zerr, ZIP_ER_SEEK, errno);
            return -1;
        }
        return 0;
    }
    case ZIP_SOURCE_TELL_WRITE: {
        off_t at = ftello(z->fp);
        if (at < 0) zip_error_set(&z->zerr, ZIP_ER_TELL, errno);
        return at < 0 ? -1 : (zip_int64_t)at;
    }
    case ZIP_SOURCE_COMMIT_WRITE:
        if (fflush(z->fp) != 0 || fsync(fileno(z->fp)) != 0) {
            zip_error_set(&z->zerr, ZIP_ER_WRITE, errno);
            return -1;
        }
        return 0;
    case ZIP_SOURCE_ERROR:
        return zip_error_to_data(&z->zerr, data, len);
    default:
        zip_error_set(&z->zerr, ZIP_ER_OPNOTSUPP, 0);
        return -1;
    }
}

void hv_zip_abort(hv_zip *z)
{
    if (!z) return;
    if (z->za) zip_discard(z->za); /* frees the sources, writes nothing */
    if (z->fp) fclose(z->fp);
    if (z->tmp) unlink(z->tmp);
    zip_error_fini(&z->zerr);
    for (size_t i = 0; i < z->nfiles; ++i) free(z->files[i]);
    free(z->files);
    free(z->path);
    free(z->tmp);
    free(z);
}

hv_status hv_zip_open(const char *path, hv_zip **out)
{
    *out = NULL;
    if (path && hv_output_check(path, 0) != HV_OK) return HV_ERR_INVALID;
    hv_zip *z = hv_calloc(1, sizeof *z);
    if (!z) return HV_ERR_NOMEM;
    zip_error_init(&z->zerr);
    struct tm t = {.tm_year = 80, .tm_mon = 0, .tm_mday = 1, .tm_isdst = -1};
    z->mtime = mktime(&t);
    z->level = 6;
    z->path = hv_strdup(path);
    z->tmp = z->path ? hv_temp_path(path) : NULL;
    if (!z->tmp) {
        hv_zip_abort(z);
        return HV_ERR_NOMEM;
    }
    /* created now, so that a place we cannot write fails before any work */
    z->fp = fopen(z->tmp, "w+b");
    if (!z->fp) {
        hv_status s = hv_error_set(HV_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
        free(z->tmp);
        z->tmp = NULL;
        hv_zip_abort(z);
        return s;
    }
    zip_source_t *src = zip_source_function_create(zip_out, z, &z->zerr);
    zip_error_t err;
    zip_error_init(&err);
    if (src) z->za = zip_open_from_source(src, ZIP_CREATE | ZIP_TRUNCATE, &err);
    if (!z->za) {
        hv_status s = hv_error_set(HV_ERR_IO, "%s: %s", path, zip_error_strerror(src ? &err : &z->zerr));
        if (src) zip_source_free(src);
        zip_error_fini(&err);
        hv_zip_abort(z);
        return s;
    }
    zip_error_fini(&err);
    *out = z;
    return HV_OK;
}

static hv_status zip_fail(hv_zip *z, const char *what)
{
    zip_error_t *e = zip_get_error(z->za);
    if (zip_error_code_zip(e) == ZIP_ER_MEMORY) return HV_ERR_NOMEM;
    return hv_error_set(HV_ERR_IO, "%s: %s%s%s", z->path, what ? what : "", what ? ": " : "", zip_error_strerror(e));
}

static hv_status zip_place(hv_zip *z, const char *name, zip_source_t *src, int deflate)
{
    if (!src) return zip_fail(z, name);
    zip_int64_t idx = zip_file_add(z->za, name, src, ZIP_FL_ENC_UTF_8);
    if (idx < 0) {
        zip_source_free(src);
        return zip_fail(z, name);
    }
    zip_uint64_t i = (zip_uint64_t)idx;
    if (zip_set_file_compression(z->za, i, deflate ? ZIP_CM_DEFLATE : ZIP_CM_STORE, deflate ? (zip_uint32_t)z->level : 0) != 0 ||
        zip_file_set_mtime(z->za, i, z->mtime, 0) != 0 ||
        zip_file_set_external_attributes(z->za, i, 0, ZIP_OPSYS_UNIX, (zip_uint32_t)0100644 << 16) != 0)
        return zip_fail(z, name);
    return HV_OK;
}

void hv_zip_set_level(hv_zip *z, int level) { z->level = level >= 1 && level <= 9 ? level : 6; }

hv_status hv_zip_add_data(hv_zip *z, const char *name, const void *data, size_t size, int deflate)
{
    void *copy = hv_malloc(size ? size : 1);
    if (!copy) return HV_ERR_NOMEM;
    memcpy(copy, data, size);
    zip_source_t *src = zip_source_buffer(z->za, copy, size, 1);
    if (!src) free(copy);
    return zip_place(z, name, src, deflate);
}

hv_status hv_zip_add_owned(hv_zip *z, const char *name, void *data, size_t size, int deflate)
{
    zip_source_t *src = zip_source_buffer(z->za, data, size, 1);
    if (!src) free(data);
    return zip_place(z, name, src, deflate);
}

hv_status hv_zip_add_file(hv_zip *z, const char *name, const char *file, int deflate)
{
    /* libzip opens the file only while it copies it, in hv_zip_write */
    hv_status s = hv_grow((void **)&z->files, &z->cap, z->nfiles + 1, sizeof *z->files);
    if (s != HV_OK) return s;
    if (!(z->files[z->nfiles] = hv_strdup(file))) return HV_ERR_NOMEM;
    z->nfiles++;
    zip_source_t *src = zip_source_file(z->za, file, 0, -1);
    if (!src) {
        zip_error_t *e = zip_get_error(z->za);
        if (zip_error_code_zip(e) == ZIP_ER_MEMORY) return HV_ERR_NOMEM;
        return hv_error_set(HV_ERR_IO, "%s: cannot read: %s", file, zip_error_strerror(e));
    }
    return zip_place(z, name, src, deflate);
}

static void zip_progress(zip_t *za, double fraction, void *ud)
{
    (void)za;
    hv_zip *z = ud;
    if (z->cancel == HV_OK && z->progress)
        z->cancel = hv_progress_report(z->progress, z->stage, fraction);
}

static int zip_cancel(zip_t *za, void *ud)
{
    (void)za;
    hv_zip *z = ud;
    if (z->cancel == HV_OK && hv_cancel_requested()) z->cancel = hv_error_set(HV_ERR_CANCELLED, "cancelled");
    return z->cancel != HV_OK;
}

hv_status hv_zip_write(hv_zip *z, const hv_progress *progress, const char *stage)
{
    z->progress = progress;
    z->stage = stage;
    zip_register_progress_callback_with_state(z->za, 0.001, zip_progress, NULL, z);
    zip_register_cancel_callback_with_state(z->za, zip_cancel, NULL, z);
    if (zip_close(z->za) == 0) {
        z->za = NULL;
        return z->cancel;
    }
    if (z->cancel != HV_OK) return z->cancel;
    /* libzip does not say which entry failed: name the first entry file that cannot be read */
    for (size_t i = 0; i < z->nfiles; ++i) {
        FILE *f = fopen(z->files[i], "rb");
        if (!f) {
            int e = errno;
            return hv_error_set(HV_ERR_IO, "%s: cannot read %s: %s", z->path, z->files[i], strerror(e));
        }
        fclose(f);
    }
    return zip_fail(z, NULL);
}

hv_status hv_zip_commit(hv_zip *z)
{
    hv_status s = HV_OK;
    if (z->za) s = hv_error_set(HV_ERR_INTERNAL, "%s: committed before it was written", z->path);
    if (s == HV_OK && fclose(z->fp) != 0) s = hv_error_set(HV_ERR_IO, "%s: write failed: %s", z->path, strerror(errno));
    z->fp = NULL;
    if (s == HV_OK) {
        s = hv_temp_commit(z->tmp, z->path);
        if (s == HV_OK) {
            free(z->tmp);
            z->tmp = NULL;
        }
    }
    hv_zip_abort(z);
    return s;
}
