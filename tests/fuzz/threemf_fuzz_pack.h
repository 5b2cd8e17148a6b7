/* tests/fuzz/threemf_fuzz_pack.h - what the 3MF fuzz targets wrap XML in: a package in memory
 * with the content types, the root relationships and the bytes as its model part, so that
 * mutations reach the XML instead of breaking the ZIP. */
#ifndef HOVOX_FUZZ_THREEMF_PACK_H
#define HOVOX_FUZZ_THREEMF_PACK_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <zip.h>

static const char k_fuzz_3mf_types[] =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/"
    "content-types\"><Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships"
    "+xml\"/><Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>"
    "</Types>";
static const char k_fuzz_3mf_rels[] =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships xmlns=\"http://schemas.openxmlformats.org/package/"
    "2006/relationships\"><Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" Type=\"http://schemas.microsoft."
    "com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>";

/* Add a member compressed by `method` (ZIP_CM_STORE, ZIP_CM_DEFLATE at level 1); 0 or -1. */
static inline int fuzz_3mf_add(zip_t *z, const char *name, const void *data, size_t size, int method)
{
    zip_source_t *s = zip_source_buffer(z, data, size, 0);
    if (!s) return -1;
    zip_int64_t i = zip_file_add(z, name, s, ZIP_FL_OVERWRITE);
    if (i < 0) {
        zip_source_free(s);
        return -1;
    }
    return zip_set_file_compression(z, (zip_uint64_t)i, method, method == ZIP_CM_STORE ? 0 : 1);
}

/* A package holding `xml` as its model part, every member compressed by `method`, in memory
 * (malloc'd, *len bytes), or NULL. */
static inline uint8_t *fuzz_3mf_package(const uint8_t *xml, size_t size, int method, size_t *len)
{
    zip_error_t ze;
    zip_error_init(&ze);
    zip_source_t *src = zip_source_buffer_create(NULL, 0, 0, &ze);
    uint8_t *out = NULL;
    if (!src) return NULL;
    zip_source_keep(src);
    zip_t *z = zip_open_from_source(src, ZIP_TRUNCATE, &ze);
    if (z && fuzz_3mf_add(z, "[Content_Types].xml", k_fuzz_3mf_types, sizeof k_fuzz_3mf_types - 1, method) == 0 &&
        fuzz_3mf_add(z, "_rels/.rels", k_fuzz_3mf_rels, sizeof k_fuzz_3mf_rels - 1, method) == 0 &&
        fuzz_3mf_add(z, "3D/3dmodel.model", xml, size, method) == 0 && zip_close(z) == 0) {
        z = NULL;
        if (zip_source_open(src) == 0) { /* libzip's way to the bytes of an archive in memory */
            zip_int64_t n = -1;
            if (zip_source_seek(src, 0, SEEK_END) == 0) n = zip_source_tell(src);
            if (n > 0 && zip_source_seek(src, 0, SEEK_SET) == 0 && (out = malloc((size_t)n)) &&
                zip_source_read(src, out, (zip_uint64_t)n) == n) {
                *len = (size_t)n;
            } else {
                free(out);
                out = NULL;
            }
            zip_source_close(src);
        }
    }
    if (z) zip_discard(z);
    zip_source_free(src);
    zip_error_fini(&ze);
    return out;
}

/* The bytes a 3MF target parses: `data` as it is when it starts with "PK" (a package), else a
 * package made of it (*packed: free it; *size updated), or NULL when none could be made. */
static inline const uint8_t *fuzz_3mf_input(const uint8_t *data, size_t *size, int method, uint8_t **packed)
{
    *packed = NULL;
    if (*size >= 2 && data[0] == 'P' && data[1] == 'K') return data;
    *packed = fuzz_3mf_package(data, *size, method, size);
    return *packed;
}

#endif
