/* tests/fuzz/fuzz_3mf.c - fuzz target: any bytes through hv_mesh_parse_3mf (the package module's
 * ZIP, relationship and content-type checks, the streamed model part, the placing of build items) must fail cleanly,
 * handing out no mesh, or build a self-consistent mesh, within a small memory budget
 * (expansion and component bombs are refused). Bytes that start with "PK" are a package as
 * they are; any others are the model part's XML, packed here with the content types and root
 * relationships (stored, uncompressed), so that mutations reach the XML instead of breaking
 * the deflate streams. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zip.h>

#include "hovox/mesh.h"
#include "mesh_fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char k_types[] =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/"
    "content-types\"><Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships"
    "+xml\"/><Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>"
    "</Types>";
static const char k_rels[] =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships xmlns=\"http://schemas.openxmlformats.org/package/"
    "2006/relationships\"><Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" Type=\"http://schemas.microsoft."
    "com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>";

static int add(zip_t *z, const char *name, const void *data, size_t size)
{
    zip_source_t *s = zip_source_buffer(z, data, size, 0);
    if (!s) return -1;
    zip_int64_t i = zip_file_add(z, name, s, ZIP_FL_OVERWRITE);
    if (i < 0) {
        zip_source_free(s);
        return -1;
    }
    return zip_set_file_compression(z, (zip_uint64_t)i, ZIP_CM_STORE, 0);
}

/* A package holding `xml` as its model part, in memory (malloc'd), or NULL. */
static uint8_t *package(const uint8_t *xml, size_t size, size_t *len)
{
    zip_error_t ze;
    zip_error_init(&ze);
    zip_source_t *src = zip_source_buffer_create(NULL, 0, 0, &ze);
    uint8_t *out = NULL;
    if (!src) return NULL;
    zip_source_keep(src);
    zip_t *z = zip_open_from_source(src, ZIP_TRUNCATE, &ze);
    if (z && add(z, "[Content_Types].xml", k_types, sizeof k_types - 1) == 0 &&
        add(z, "_rels/.rels", k_rels, sizeof k_rels - 1) == 0 && add(z, "3D/3dmodel.model", xml, size) == 0 &&
        zip_close(z) == 0) {
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

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_set_memory_cap(256u << 20);
    uint8_t *packed = NULL;
    if (size < 2 || data[0] != 'P' || data[1] != 'K') {
        packed = package(data, size, &size);
        if (!packed) return 0;
        data = packed;
    }
    /* HV_ERR_UNSUPPORTED is a clean refusal (an extension hovox does not read): the reader has
     * no plugin since the package module replaced lib3mf */
    fuzz_mesh_parse(hv_mesh_parse_3mf, data, size, "fuzz.3mf");
    free(packed);
    return 0;
}
