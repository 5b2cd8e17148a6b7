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

#define HV_VTK_ABI 2

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
} hv_vtk_api;

/* The plugin's one exported symbol. */
typedef const hv_vtk_api *(*hv_vtk_entry_fn)(void);
#define HV_VTK_ENTRY "hv_vtk_plugin_v1"

#ifdef __cplusplus
}
#endif
#endif
