/* src/mesh/threemf_bridge.h - the function table between the 3MF reader (threemf.c) and the
 * lib3mf bridge plugin (threemf_bridge.cpp, built as plugins/hovox-3mf.so and loaded on the
 * first 3MF read). Internal: callers use hv_mesh_parse_3mf. Entries return hv_status values;
 * on failure the plugin's last_error() holds the message. No C++ exception crosses this table.
 * The plugin does not link libhovox: it hands over lib3mf's arrays as they are, and the C side
 * checks every index and coordinate. Materials are not read through lib3mf (1.8 drops or
 * replaces references it cannot resolve and ignores a triangle's p1 without its own pid): the
 * C side reads them from the model part and matches objects by their position in it. */
#ifndef HOVOX_3MF_BRIDGE_H
#define HOVOX_3MF_BRIDGE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HV_3MF_ABI 2

/* One mesh object placed by a build item (components flattened, depth first, in order). */
typedef struct hv_3mf_instance {
    size_t item;             /* the build item, from 0 */
    size_t object;           /* the mesh object's position among the model's objects, from 0 */
    const char *object_name; /* its name attribute ("" without one) */
    size_t nv, nt;
    const float *xyz;        /* nv x 3, as stored */
    const uint32_t *tri;     /* nt x 3, as stored (unchecked) */
    double transform[12];    /* rows of a 3x4 matrix: x' = T[0] x + T[1] y + T[2] z + T[3], ... */
} hv_3mf_instance;

typedef struct hv_3mf_sink {
    void *ctx;
    /* The package was read: its unit (as hv_3mf_info.unit) and number of objects. Nonzero
     * stops the read with that status (its message set by the sink), as for the others. */
    int (*begin)(void *ctx, int unit, size_t objects);
    /* A build item starts: its object's position among the objects and name ("" without one). */
    int (*item)(void *ctx, size_t item, size_t object, const char *name);
    int (*instance)(void *ctx, const hv_3mf_instance *inst);
} hv_3mf_sink;

typedef struct hv_3mf_info {
    int unit;                    /* lib3mf's unit: 0 micron, 1 mm, 2 cm, 3 inch, 4 foot, 5 metre */
    size_t items, skipped_items; /* build items; those of objects of type support or other */
    uint32_t error_code;         /* lib3mf's code when it refused the package */
} hv_3mf_info;

typedef struct hv_3mf_api {
    int abi;
    const char *(*last_error)(void);
    /* Read a package from memory and deliver its build items in order. A package whose items
     * flatten to more than max_triangles is refused (HV_ERR_LIMIT) before anything is
     * delivered; one lib3mf refuses is HV_ERR_BAD_INPUT with info->error_code set. */
    int (*read)(const void *data, size_t size, uint64_t max_triangles, const hv_3mf_sink *sink,
                hv_3mf_info *info);
} hv_3mf_api;

/* The plugin's one exported symbol. */
typedef const hv_3mf_api *(*hv_3mf_entry_fn)(void);
#define HV_3MF_ENTRY "hv_3mf_plugin_v1"

#ifdef __cplusplus
}
#endif
#endif
