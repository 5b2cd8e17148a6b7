/* src/export/vtk_bridge.h - the function table between the C exporter (src/export) and the
 * VTK bridge plugin (src/export/vtk_bridge.cpp, built as plugins/hovox-vtk.so). Internal. The
 * plugin does not link libhovox: it gets plain arrays and returns hovox status values; on
 * failure its last_error() holds the message. No C++ exception crosses this table. */
#ifndef HOVOX_VTK_BRIDGE_H
#define HOVOX_VTK_BRIDGE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HV_VTK_ABI 3

/* Array element types. HV_VTK_STRING: `data` is one NUL-terminated string (count 1). */
enum { HV_VTK_UINT8 = 1, HV_VTK_INT32 = 2, HV_VTK_FLOAT32 = 3, HV_VTK_STRING = 4 };

typedef struct hv_vtk_array {
    const char *name;
    int type;
    int components;   /* values per tuple */
    int64_t tuples;
    const void *data; /* tuples * components values, borrowed (not copied when possible) */
} hv_vtk_array;

/* Progress of the writer in [0,1], from the calling thread; nonzero cancels. */
typedef int (*hv_vtk_progress_fn)(void *user, double fraction);

typedef struct hv_vtk_write_opts {
    int zlib_level; /* 1-9 */
    hv_vtk_progress_fn progress;
    void *user;
    int nfield;
    const hv_vtk_array *field; /* field data */
} hv_vtk_write_opts;

/* What hv_vtk_api.probe found in the file. */
typedef struct hv_vtk_probe_info {
    int components;     /* of the array */
    int cell_data;      /* 1: the array is cell data */
    double range[2];    /* min and max of the array in the file */
    int64_t points, cells;
} hv_vtk_probe_info;

typedef struct hv_vtk_api {
    int abi;
    const char *(*last_error)(void);
    /* vtkImageData with dims[0] x dims[1] x dims[2] points (x fastest), origin = world
     * position of point 0, spacing; arrays are point data. */
    int (*write_image)(const char *path, const int64_t dims[3], const double origin[3],
                       const double spacing[3], int narrays, const hv_vtk_array *arrays,
                       const hv_vtk_write_opts *opts);
    /* vtkUnstructuredGrid of ncells VTK_HEXAHEDRON cells: points (3 floats each),
     * connectivity (8 point ids per cell, VTK order; int32_t when conn64 == 0, else
     * int64_t); arrays are cell data. */
    int (*write_hexes)(const char *path, int64_t npoints, const float *points, int64_t ncells,
                       const void *connectivity, int conn64, int narrays,
                       const hv_vtk_array *arrays, const hv_vtk_write_opts *opts);
    /* Read a .vti (vtkImageData) or .vtu (vtkUnstructuredGrid) file, told apart by the
     * extension, and probe its array `array` (point data, else cell data) at n points (3
     * doubles each, world coordinates): out[i] the value and valid[i] = 1 where a cell of the
     * data set holds point i (vtkProbeFilter: image data interpolated trilinearly, an
     * unstructured grid by its cells' interpolation functions; cell data takes the cell's value),
     * else 0. info (see hv_vtk_probe_info) is filled before the probe. Errors: E_IO (cannot
     * open), E_BAD_INPUT (not readable as that format, no such array: the message lists the
     * arrays, not 1 component), E_NOMEM. */
    int (*probe)(const char *path, const char *array, int64_t n, const double *points, float *out,
                 uint8_t *valid, hv_vtk_probe_info *info);
} hv_vtk_api;


/* The plugin's one exported symbol. */
typedef const hv_vtk_api *(*hv_vtk_entry_fn)(void);
#define HV_VTK_ENTRY "hv_vtk_plugin_v1"

#ifndef __cplusplus
#include "hovox/core.h"
/* The C side: the plugin's function table, loaded on first use (once per process). Errors:
 * HV_ERR_UNSUPPORTED (plugin missing or of another ABI). Defined in vtk_plugin.c. */
hv_status hv_vtk_bridge(const hv_vtk_api **api);
#endif

#ifdef __cplusplus
}
#endif
#endif
