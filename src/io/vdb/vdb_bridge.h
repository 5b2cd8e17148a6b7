/* volumes/vdb_bridge.h - the function table between the C volume store (volume.c) and the
 * OpenVDB bridge plugin (vdb_bridge.cpp, built as plugins/hovox-vdb.so). Internal: callers
 * use hovox/volume.h. Every entry returns an hv_status; on failure the plugin's last_error()
 * holds the message. No C++ exception crosses this table. */
#ifndef HOVOX_VDB_BRIDGE_H
#define HOVOX_VDB_BRIDGE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HV_VDB_ABI 7

enum { HV_META_STRING = 0, HV_META_NUMBER = 1 };

/* Called by load for each file-level metadata entry and each grid (in file order); a float
 * grid the file stored as 16-bit half floats has HV_VDB_HALF added to its type. */
enum { HV_VDB_HALF = 0x100 };
typedef int (*hv_vdb_meta_cb)(void *ctx, const char *key, int kind, const char *s, double d);
typedef int (*hv_vdb_grid_cb)(void *ctx, const char *name, int type);
/* Polled while a file is read or written: nonzero stops it (status 6, cancelled). */
typedef int (*hv_vdb_cancel_fn)(void);

/* The volume store (volume.c) is C; the plugin writes its volumes as OpenVDB files and reads
 * the files the native reader (vdb_read.c) leaves to it. */
typedef struct hv_vdb_api {
    int abi;
    const char *(*last_error)(void);
    /* save: the voxel transform, n leaves (origins in tree order, 8-word masks), and ngrids
     * grids of type types[g] (1 float, 2 bool) whose leaf l has buffer buffers[g][l]; inactive
     * voxels are written as 0. Every write, the flush and the close are checked (a full disk
     * is status 3); the file holds grid offsets (io::File's format), so loads can skip grids.
     * Float grid g is stored as 16-bit half floats where half[g] is nonzero (OpenVDB's
     * saveFloatAsHalf: every reader gets floats back). One grid at a time is held as an
     * OpenVDB tree. */
    int (*save)(const char *path, const double voxel[3], const double origin[3], size_t n, const int32_t *origins,
                const uint64_t *masks, int ngrids, const char *const *names, const int *types,
                const unsigned char *half, const void *const *const *buffers, int nmeta, const char *const *keys,
                const int *kinds, const char *const *strings, const double *numbers, hv_vdb_cancel_fn cancel);
    /* load: a file that ends early or is damaged is status 2; grids whose active voxels would
     * take more than max_bytes once expanded are refused before expanding (status 5). Only the
     * grids `want` selects are loaded (nwant entries, each a name or a prefix followed by '*';
     * nwant < 0: every grid); with grid offsets in the file the others are not read, and the
     * selected ones are read on up to `threads` threads. *out holds the grids, on one topology
     * (the union of theirs), until destroy; the caller copies them out with the entries below. */
    int (*load)(const char *path, const char *const *want, int nwant, int threads, void **out,
                double voxel[3], double origin[3], hv_vdb_meta_cb meta_cb, hv_vdb_grid_cb grid_cb,
                void *ctx, uint64_t max_bytes, hv_vdb_cancel_fn cancel);
    /* a loaded volume: its leaves in tree order (origins, masks: 3 int32 and 8 words each), the
     * buffer of each leaf in grid g (floats or 8 words; valid until grid_free or destroy) */
    size_t (*leaf_count)(const void *impl);
    int (*leaf_topology)(const void *impl, int32_t *origins, uint64_t *masks);
    int (*leaf_buffers)(void *impl, int g, void **buffers);
    void (*grid_free)(void *impl, int g);
    void (*destroy)(void *impl);
    /* the surface of a Boolean tree of meshes (hv_vdb_surface, vdb_internal.h): level sets, CSG,
     * volumeToMesh; the outputs malloc'd */
    int (*surface)(int nleaf, const float *const *xyz, const size_t *nv, const uint32_t *const *tri, const size_t *nt,
                   int nnode, const int *ops, const uint32_t *leaf, const uint32_t *a, const uint32_t *b, double voxel,
                   float **out_xyz, size_t *out_nv, uint32_t **out_tri, size_t *out_nt, hv_vdb_cancel_fn cancel);
    /* at most n threads (n >= 1; hv_threads()) for everything OpenVDB runs until the next call
     * (TBB's max_allowed_parallelism); 0, or a status (out of memory) */
    int (*threads)(int n);
} hv_vdb_api;

/* The plugin's one exported symbol. */
typedef const hv_vdb_api *(*hv_vdb_entry_fn)(void);
#define HV_VDB_ENTRY "hv_vdb_plugin_v1"

#ifdef __cplusplus
}
#endif
#endif
