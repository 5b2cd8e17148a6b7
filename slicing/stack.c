/* slicing/stack.c - the slice stack on disk: a temporary directory renamed into place when
 * complete (nothing half-written under the final name), and a minimal ZIP writer (PKWARE
 * APPNOTE 6.3.x: local headers, central directory, end record; raw deflate and CRC-32 from
 * zlib) for the GrabCAD voxel-print (GCVF) archive. */
#include <dirent.h>
#include <errno.h>
#include <ftw.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "../src/core/internal.h"
#include "layers_internal.h"

/* ---- directories -------------------------------------------------------------------------- */

/* parent directory and last component of `dir` (trailing slashes ignored); caller frees */
static hv_status split_path(const char *dir, char **parent, char **name)
{
    size_t n = strlen(dir);
    while (n > 1 && dir[n - 1] == '/') --n;
    if (n == 0) return hv_error_set(HV_ERR_INVALID, "layers: empty output directory name");
    size_t s = n;
    while (s > 0 && dir[s - 1] != '/') --s;
    *name = hv_malloc(n - s + 1);
    *parent = hv_malloc(s + 2);
    if (!*name || !*parent) {
        free(*name);
        free(*parent);
        return HV_ERR_NOMEM;
    }
    memcpy(*name, dir + s, n - s);
    (*name)[n - s] = '\0';
    if (s == 0) strcpy(*parent, ".");
    else {
        memcpy(*parent, dir, s);
        (*parent)[s] = '\0';
    }
    if (strcmp(*name, ".") == 0 || strcmp(*name, "..") == 0 || strcmp(*name, "/") == 0) {
        free(*name);
        free(*parent);
        return hv_error_set(HV_ERR_INVALID, "%s: name the output directory itself (not . or ..)", dir);
    }
    return HV_OK;
}

static char *sibling(const char *dir, const char *tag)
{
    char *parent = NULL, *name = NULL;
    if (split_path(dir, &parent, &name) != HV_OK) return NULL;
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_printf(&b, "%s%s.%s.%s-%ld", parent, strcmp(parent, ".") == 0 ? "/" : "", name, tag, (long)getpid());
    free(parent);
    free(name);
    if (b.failed) {
        hv_buf_free(&b);
        return NULL;
    }
    return b.data;
}

static int rm_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb;
    (void)ftw;
    if (flag == FTW_DP) rmdir(path);
    else unlink(path);
    return 0;
}

static void remove_tree(const char *path)
{
    if (path && *path) nftw(path, rm_entry, 16, FTW_DEPTH | FTW_PHYS);
}

/* 0: absent; 1: empty directory; 2: a hovox stack; 3: other non-empty directory; 4: not a
 * directory */
static int classify(const char *dir)
{
    struct stat sb;
    if (stat(dir, &sb) != 0) return 0;
    if (!S_ISDIR(sb.st_mode)) return 4;
    DIR *d = opendir(dir);
    if (!d) return 3;
    int empty = 1;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
        empty = 0;
        break;
    }
    closedir(d);
    if (empty) return 1;
    hv_buf p;
    hv_buf_init(&p);
    hv_buf_printf(&p, "%s/manifest.json", dir);
    char *text = NULL;
    size_t size = 0;
    int stack = 0;
    if (!p.failed && hv_read_file(p.data, 1 << 30, &text, &size) == HV_OK)
        stack = strstr(text, "\"generator\": \"hovox") != NULL;
    hv_error_clear();
    free(text);
    hv_buf_free(&p);
    return stack ? 2 : 3;
}

hv_status hv_stack_begin(const char *dir, int force, char **tmp)
{
    *tmp = NULL;
    /* layer paths are built in 4200-byte buffers: "<tmp>/<material>/layer-NNNNN.png" */
    if (strlen(dir) > 3900) return hv_error_set(HV_ERR_INVALID, "layers: output directory name of %zu bytes is too long", strlen(dir));
    int kind = classify(dir);
    if (kind == 4) return hv_error_set(HV_ERR_IO, "%s: exists and is not a directory", dir);
    if (kind == 3)
        return hv_error_set(HV_ERR_IO, "%s: directory exists and is not empty (not a hovox stack; "
                                       "refusing to replace it)", dir);
    if (kind == 2 && !force)
        return hv_error_set(HV_ERR_IO, "%s: a stack exists there (--force, or force = true in Lua, replaces it)", dir);
    char *t = sibling(dir, "tmp");
    if (!t) return hv_error_set(HV_ERR_NOMEM, "out of memory");
    remove_tree(t); /* a leftover of an earlier process with our pid */
    if (mkdir(t, 0777) != 0) {
        hv_status s = hv_error_set(HV_ERR_IO, "%s: cannot create the output directory: %s", dir, strerror(errno));
        free(t);
        return s;
    }
    *tmp = t;
    return HV_OK;
}

hv_status hv_stack_commit(const char *tmp, const char *dir, int force)
{
    int kind = classify(dir);
    if (kind == 2 && force) {
        char *old = sibling(dir, "old");
        if (!old) return hv_error_set(HV_ERR_NOMEM, "out of memory");
        remove_tree(old);
        if (rename(dir, old) != 0) {
            hv_status s = hv_error_set(HV_ERR_IO, "%s: cannot move the old stack aside: %s", dir, strerror(errno));
            free(old);
            return s;
        }
        if (rename(tmp, dir) != 0) {
            hv_status s = hv_error_set(HV_ERR_IO, "%s: cannot rename %s to it: %s", dir, tmp, strerror(errno));
            if (rename(old, dir) != 0) { /* leave the old stack where the user can find it */ }
            free(old);
            return s;
        }
        remove_tree(old);
        free(old);
        return HV_OK;
    }
    if (kind == 2 || kind == 3 || kind == 4)
        return hv_error_set(HV_ERR_IO, "%s: appeared while the stack was written; not replaced", dir);
    if (rename(tmp, dir) != 0)
        return hv_error_set(HV_ERR_IO, "%s: cannot rename %s to it: %s", dir, tmp, strerror(errno));
    return HV_OK;
}

void hv_stack_abort(const char *tmp) { remove_tree(tmp); }

/* ---- ZIP ------------------------------------------------------------------------------------ */

typedef struct zip_entry {
    char *name;
    uint32_t crc, csize, usize, offset;
    uint16_t method;
} zip_entry;

struct hv_zip {
    FILE *fp;
    const char *path;
    uint64_t pos;
    zip_entry *e;
    size_t n, cap;
};

#define ZIP_DOS_DATE 0x0021 /* 1980-01-01 */
#define ZIP_DOS_TIME 0x0000

static void le16(uint8_t *p, unsigned v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}
static void le32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; ++i) p[i] = (uint8_t)(v >> (8 * i));
}

static hv_status zwrite(hv_zip *z, const void *d, size_t n)
{
    if (n && fwrite(d, 1, n, z->fp) != n)
        return hv_error_set(HV_ERR_IO, "%s: write failed: %s", z->path, strerror(errno));
    z->pos += n;
    return HV_OK;
}

hv_status hv_zip_open(FILE *fp, const char *path, hv_zip **out)
{
    *out = NULL;
    hv_zip *z = hv_calloc(1, sizeof *z);
    if (!z) return HV_ERR_NOMEM;
    z->fp = fp;
    z->path = path;
    *out = z;
    return HV_OK;
}

void hv_zip_free(hv_zip *z)
{
    if (!z) return;
    for (size_t i = 0; i < z->n; ++i) free(z->e[i].name);
    free(z->e);
    free(z);
}

hv_status hv_zip_add(hv_zip *z, const char *name, const void *data, size_t size, int level)
{
    size_t nlen = strlen(name);
    if (nlen == 0 || nlen > 0xffff) return hv_error_set(HV_ERR_INVALID, "%s: bad entry name", z->path);
    if (z->n >= 0xffff)
        return hv_error_set(HV_ERR_LIMIT, "%s: more than 65535 entries need ZIP64, which is not written", z->path);
    if (size > 0xfffffffful || z->pos > 0xfffffffful)
        return hv_error_set(HV_ERR_LIMIT, "%s: archive beyond 4 GiB needs ZIP64, which is not written", z->path);
    hv_status st = hv_grow((void **)&z->e, &z->cap, z->n + 1, sizeof *z->e);
    if (st != HV_OK) return st;
    uint32_t crc = (uint32_t)crc32(0L, Z_NULL, 0);
    /* crc32 takes uInt lengths: feed large buffers in pieces */
    for (size_t o = 0; o < size;) {
        size_t k = HV_MIN(size - o, (size_t)1 << 30);
        crc = (uint32_t)crc32(crc, (const Bytef *)data + o, (uInt)k);
        o += k;
    }
    uint8_t *comp = NULL;
    size_t csize = size;
    uint16_t method = 0;
    if (level > 0 && size > 0) {
        z_stream s;
        memset(&s, 0, sizeof s);
        if (deflateInit2(&s, level, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK)
            return hv_error_set(HV_ERR_NOMEM, "%s: zlib initialisation failed", z->path);
        uLong bound = deflateBound(&s, (uLong)size);
        comp = hv_malloc(bound);
        if (!comp) {
            deflateEnd(&s);
            return HV_ERR_NOMEM;
        }
        s.next_in = (Bytef *)(uintptr_t)data;
        s.avail_in = (uInt)size;
        s.next_out = comp;
        s.avail_out = (uInt)bound;
        int rc = deflate(&s, Z_FINISH);
        size_t got = s.total_out;
        deflateEnd(&s);
        if (rc == Z_STREAM_END && got < size) {
            csize = got;
            method = 8;
        }
    }
    uint8_t h[30];
    le32(h, 0x04034b50);
    le16(h + 4, 20);
    le16(h + 6, 0);
    le16(h + 8, method);
    le16(h + 10, ZIP_DOS_TIME);
    le16(h + 12, ZIP_DOS_DATE);
    le32(h + 14, crc);
    le32(h + 18, (uint32_t)csize);
    le32(h + 22, (uint32_t)size);
    le16(h + 26, (unsigned)nlen);
    le16(h + 28, 0);
    zip_entry *e = &z->e[z->n];
    e->offset = (uint32_t)z->pos;
    e->crc = crc;
    e->csize = (uint32_t)csize;
    e->usize = (uint32_t)size;
    e->method = method;
    e->name = hv_strdup(name);
    if (!e->name) {
        free(comp);
        return HV_ERR_NOMEM;
    }
    z->n++;
    st = zwrite(z, h, sizeof h);
    if (st == HV_OK) st = zwrite(z, name, nlen);
    if (st == HV_OK) st = zwrite(z, method ? comp : data, csize);
    free(comp);
    if (st == HV_OK && z->pos > 0xfffffffful)
        st = hv_error_set(HV_ERR_LIMIT, "%s: archive beyond 4 GiB needs ZIP64, which is not written", z->path);
    return st;
}

hv_status hv_zip_finish(hv_zip *z)
{
    hv_status st = HV_OK;
    uint64_t cd = z->pos;
    for (size_t i = 0; i < z->n && st == HV_OK; ++i) {
        zip_entry *e = &z->e[i];
        size_t nlen = strlen(e->name);
        uint8_t h[46];
        le32(h, 0x02014b50);
        le16(h + 4, 0x0314); /* made by: Unix, spec 2.0 */
        le16(h + 6, 20);
        le16(h + 8, 0);
        le16(h + 10, e->method);
        le16(h + 12, ZIP_DOS_TIME);
        le16(h + 14, ZIP_DOS_DATE);
        le32(h + 16, e->crc);
        le32(h + 20, e->csize);
        le32(h + 24, e->usize);
        le16(h + 28, (unsigned)nlen);
        le16(h + 30, 0);
        le16(h + 32, 0);
        le16(h + 34, 0);
        le16(h + 36, 0);
        le32(h + 38, (uint32_t)0100644 << 16); /* regular file, rw-r--r-- */
        le32(h + 42, e->offset);
        st = zwrite(z, h, sizeof h);
        if (st == HV_OK) st = zwrite(z, e->name, nlen);
    }
    uint64_t cdsize = z->pos - cd;
    if (st == HV_OK && (z->pos > 0xfffffffful))
        st = hv_error_set(HV_ERR_LIMIT, "%s: archive beyond 4 GiB needs ZIP64, which is not written", z->path);
    if (st == HV_OK) {
        uint8_t h[22];
        le32(h, 0x06054b50);
        le16(h + 4, 0);
        le16(h + 6, 0);
        le16(h + 8, (unsigned)z->n);
        le16(h + 10, (unsigned)z->n);
        le32(h + 12, (uint32_t)cdsize);
        le32(h + 16, (uint32_t)cd);
        le16(h + 20, 0);
        st = zwrite(z, h, sizeof h);
    }
    hv_zip_free(z);
    return st;
}
