/* slicing/stack.c - the slice stack on disk: a temporary directory renamed into place when
 * complete (nothing half-written under the final name; src/core/outdir.c), and a minimal ZIP writer (PKWARE
 * APPNOTE 6.3.x: local headers, central directory, end record; raw deflate and CRC-32 from
 * zlib) for the GrabCAD voxel-print (GCVF) archive. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "core/internal.h"
#include "core/json.h"
#include "layers_internal.h"

/* ---- directories -------------------------------------------------------------------------- */

hv_status hv_stack_manifest_check(const char *text, size_t size)
{
    json_t *doc;
    const char *gen;
    hv_status s = hv_json_parse(text, size, "manifest.json", &doc);
    if (s == HV_OK && (s = hv_json_get_string(doc, "generator", "manifest.json", &gen)) == HV_OK &&
        strncmp(gen, "hovox", 5) != 0)
        s = hv_error_set(HV_ERR_BAD_INPUT, "manifest.json: generator is \"%s\", not hovox", gen);
    json_decref(doc);
    return s;
}

static int stack_manifest_ok(const char *text, size_t size) { return hv_stack_manifest_check(text, size) == HV_OK; }

/* What a stack holds: manifest.json (written by hovox), layer PNGs, and in fractions mode one
 * subdirectory of layer PNGs per material. */
static const char *const k_stack_files[] = {"manifest.json", "layer-*.png", NULL};
static const hv_outdir_rules k_stack = {
    "stack", "manifest.json", stack_manifest_ok, k_stack_files, 1, 1};

hv_status hv_stack_begin(const char *dir, int force, char **tmp)
{
    *tmp = NULL;
    /* layer paths are built in 4200-byte buffers: "<tmp>/<material>/layer-NNNNN.png" */
    if (strlen(dir) > 3900) return hv_error_set(HV_ERR_INVALID, "layers: output directory name of %zu bytes is too long", strlen(dir));
    return hv_outdir_begin(dir, &k_stack, force, tmp);
}

hv_status hv_stack_commit(const char *tmp, const char *dir, int force)
{
    return hv_outdir_commit(tmp, dir, &k_stack, force);
}

void hv_stack_abort(const char *tmp) { hv_outdir_abort(tmp); }

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
