/* tests/fuzz/fuzz_json.c - fuzz target: the JSON readers hovox has (jansson underneath): every
 * model metadata document (schema check and deserialiser) and the stack manifest must reject
 * or read any bytes without crashing or leaking. */
#include <stdint.h>
#include <stdlib.h>

#include "slicing/layers_internal.h"
#include "volumes/schema.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"
#include "mesh/mesh_internal.h"
#include "voxel/voxel_internal.h"
#include "material/material_internal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A small model for the grading definition: a bool grid "occupancy" over one leaf, a float
 * grid "distance.0". NULL when the OpenVDB plugin is not there (libFuzzer builds). */
static hv_volume *lattice(void)
{
    static hv_volume *v;
    static int tried;
    if (tried) return v;
    tried = 1;
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    int32_t origin[3] = {0, 0, 0};
    uint64_t mask[8];
    for (int i = 0; i < 8; ++i) mask[i] = ~0ull;
    int g;
    if (hv_volume_create(&xf, &v) != HV_OK || hv_volume_topology_add(v, 1, origin, mask) != HV_OK ||
        hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &g) != HV_OK ||
        hv_volume_grid_add(v, "distance.0", HV_GRID_FLOAT, NULL) != HV_OK) {
        hv_volume_destroy(v);
        v = NULL;
        return NULL;
    }
    uint64_t *b = hv_volume_leaf_bool(v, g, 0);
    for (int i = 0; i < 8; ++i) b[i] = ~0ull;
    return v;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *text = (const char *)data;
    for (int d = 0; d < HV_DOC_COUNT; ++d) {
        json_t *doc;
        if (hv_schema_doc_parse((hv_schema_doc)d, text, size, &doc) != HV_OK) continue;
        const char *what = hv_schema_key((hv_schema_doc)d);
        if (d == HV_DOC_MESH) {
            hv_mesh_report r;
            hv_mesh_report_from_doc(doc, what, &r);
        } else if (d == HV_DOC_VOXELIZE) {
            hv_voxelize_record rec;
            hv_voxelize_from_doc(doc, what, &rec);
        } else if (d == HV_DOC_MATERIALS) {
            hv_material_table *t = NULL;
            if (hv_material_table_from_doc(doc, what, &t) == HV_OK) {
                char *again = NULL; /* what reads must write */
                if (hv_material_table_to_json(t, &again) != HV_OK) abort();
                free(again);
            }
            hv_material_table_destroy(t);
        } else if (d == HV_DOC_REGIONS) {
            hv_regions *r = NULL;
            if (hv_regions_from_doc(doc, what, &r) == HV_OK) {
                json_t *again = hv_regions_to_doc(r, 1.0); /* what reads must write */
                if (!again) abort();
                json_decref(again);
            }
            hv_regions_destroy(r);
        } else if (lattice()) {
            hv_object *o = NULL;
            json_t *again = NULL;
            hv_status s = hv_object_from_doc(doc, lattice(), &o) == HV_OK ? hv_object_to_doc(o, &again) : HV_OK;
            if (s != HV_OK && s != HV_ERR_LIMIT) abort(); /* what reads must write (up to the source limit) */
            json_decref(again);
            hv_object_destroy(o);
        }
        json_decref(doc);
    }
    hv_stack_manifest_check(text, size);
    return 0;
}
