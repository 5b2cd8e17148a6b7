/* tests/fuzz/fuzz_3mf_volumetric.c - fuzz target: any bytes through the 3MF Volumetric reader (ZIP,
 * relationships, the model part's XML, references, PNG sheets, the voxelization of the mesh) must
 * fail cleanly or give a graded model whose fractions are finite and sum to 1 on every voxel, and
 * a mesh. An input that is not a ZIP archive is taken as the model part of a package that holds the
 * sheets of tests/data/good/volumetric_box.3mf (4 x 3 grey PNGs /3D/volumetric/{cyan,agilus}/
 * sheet000{1,2}.png), so the XML reader is fuzzed past the archive's checksums. A colour read
 * (<v:color>) must be four grids of sRGB in [0, 1], the mask 0 or 1 and the colour 0 where it is
 * 0. Memory is capped at 64 MiB per input, so a package that declares more is refused. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zip.h>

#include "hovox/image.h"
#include "hovox/material.h"
#include "hovox/threemf.h"

/* A package around a model part, in memory (malloc'd), or NULL. */
static uint8_t *wrap(const uint8_t *xml, size_t n, size_t *size)
{
    static const char rels[] =
        "<?xml version=\"1.0\"?><Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">"
        "<Relationship Target=\"/3D/3dmodel.model\" Id=\"r\" "
        "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>";
    static uint8_t *png[2];
    static size_t png_size[2];
    for (int m = 0; m < 2; ++m)
        if (!png[m]) {
            uint8_t px[12];
            for (int i = 0; i < 12; ++i) px[i] = (uint8_t)(m ? 85 * (i % 4) : 255 - 85 * (i % 4));
            if (hv_png_encode(px, 4, 3, 1, 0, NULL, &png[m], &png_size[m]) != HV_OK) return NULL;
        }
    zip_error_t err;
    zip_error_init(&err);
    zip_source_t *src = zip_source_buffer_create(NULL, 0, 0, &err);
    zip_t *za = src ? zip_open_from_source(src, ZIP_TRUNCATE, &err) : NULL;
    zip_error_fini(&err);
    if (!za) {
        if (src) zip_source_free(src);
        return NULL;
    }
    zip_source_keep(src);
    struct {
        const char *name;
        const void *data;
        size_t size;
    } e[6] = {{"_rels/.rels", rels, sizeof rels - 1},
              {"3D/3dmodel.model", xml, n},
              {"3D/volumetric/cyan/sheet0001.png", png[0], png_size[0]},
              {"3D/volumetric/cyan/sheet0002.png", png[0], png_size[0]},
              {"3D/volumetric/agilus/sheet0001.png", png[1], png_size[1]},
              {"3D/volumetric/agilus/sheet0002.png", png[1], png_size[1]}};
    int ok = 1;
    for (int i = 0; i < 6 && ok; ++i) {
        zip_source_t *b = zip_source_buffer(za, e[i].data, e[i].size, 0);
        ok = b && zip_file_add(za, e[i].name, b, 0) >= 0;
        if (ok) zip_set_file_compression(za, (zip_uint64_t)i, ZIP_CM_STORE, 0);
        else if (b) zip_source_free(b);
    }
    uint8_t *out = NULL;
    if (ok && zip_close(za) == 0) {
        zip_stat_t st;
        if (zip_source_stat(src, &st) == 0 && zip_source_open(src) == 0) {
            out = malloc(st.size ? st.size : 1);
            if (out && zip_source_read(src, out, st.size) != (zip_int64_t)st.size) {
                free(out);
                out = NULL;
            }
            zip_source_close(src);
            *size = st.size;
        }
    } else {
        zip_discard(za);
    }
    zip_source_free(src);
    return out;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_set_memory_cap((uint64_t)64 << 20);
    hv_volume *v = NULL;
    hv_mesh *mesh = NULL;
    uint8_t *pkg = NULL;
    size_t pkg_size = 0;
    if (size < 2 || data[0] != 'P' || data[1] != 'K') {
        pkg = wrap(data, size, &pkg_size);
        if (!pkg) return 0;
        data = pkg;
        size = pkg_size;
    }
    hv_status s = hv_3mf_parse(data, size, "fuzz.3mf", &v, &mesh);
    free(pkg);
    if (s != HV_OK) {
        if (v || mesh) abort(); /* failures must not hand out a model */
        return 0;
    }
    hv_material_table *t = NULL;
    if (!mesh || hv_material_table_load(v, &t) != HV_OK) abort();
    int m = hv_material_count(t), g[HV_MAX_MATERIALS];
    for (int j = 0; j < m; ++j)
        if ((g[j] = hv_material_grid(v, t, j)) < 0) abort();
    int og = hv_volume_grid_find(v, "occupancy");
    if (og < 0) abort();
    static const char *const colour[4] = {"colour.r", "colour.g", "colour.b", "colour.mask"};
    int cg[4];
    for (int c = 0; c < 4; ++c) cg[c] = hv_volume_grid_find(v, colour[c]);
    if ((cg[0] < 0) != (cg[3] < 0) || (cg[1] < 0) != (cg[3] < 0) || (cg[2] < 0) != (cg[3] < 0)) abort();
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
            if (!HV_BIT_GET(hv_volume_leaf_bool_c(v, og, l), n)) continue;
            double sum = 0;
            for (int j = 0; j < m; ++j) {
                float f = hv_volume_leaf_float_c(v, g[j], l)[n];
                if (!(f >= 0 && f <= 1)) abort();
                sum += f;
            }
            if (fabs(sum - 1) > 1e-5) abort();
            /* a colour read (<v:color>): sRGB in [0, 1], 0 where none was asked for, the mask 0 or 1 */
            for (int c = 0; c < 4 && cg[3] >= 0; ++c) {
                float x = hv_volume_leaf_float_c(v, cg[c], l)[n], mask = hv_volume_leaf_float_c(v, cg[3], l)[n];
                if (!(x >= 0 && x <= 1) || (c == 3 && x != 0 && x != 1) || (mask == 0 && x != 0)) abort();
            }
        }
    hv_material_table_destroy(t);
    hv_mesh_destroy(mesh);
    hv_volume_destroy(v);
    return 0;
}
