/* src/io/vdb/vdb_internal.h - the two .vdb readers: hovox's own (vdb_read.c) and OpenVDB's (through
 * the bridge, vdb_file.c). Internal: callers use hv_volume_load (hovox/volume.h). */
#ifndef HOVOX_IO_VDB_INTERNAL_H
#define HOVOX_IO_VDB_INTERNAL_H

#include "hovox/volume.h"

/* hovox's own reader for OpenVDB files (vdb_read.c): what OpenVDB's io::File writes with grid
 * offsets, format versions 222 to 224, float (also stored as half floats) and bool grids of
 * 5-4-3 trees with no active tiles, one axis-aligned transform, zip, blosc or no compression,
 * with or without active-mask compression: the files hovox writes. Loads the grids `want`
 * selects (nwant < 0: all; else names, or prefixes followed by '*') exactly as the OpenVDB
 * bridge would. A file it does not read, for any reason (another layout, a damaged file, more
 * than `budget` bytes once loaded), sets *declined and returns HV_OK: the caller then asks
 * OpenVDB, which reads the rest and says what is wrong with a damaged file. *half: a material
 * grid was stored as half floats. Errors: HV_ERR_NOMEM, HV_ERR_CANCELLED (message set). */
hv_status hv_vdb_read(const char *path, const char *const *want, int nwant, uint64_t budget, hv_volume **out,
                      int *half, int *declined);

/* For tests and the fuzz harness: hv_volume_load_grids (n < 0: every grid) with OpenVDB alone,
 * the native reader skipped. */
hv_status hv_volume_load_openvdb(const char *path, const char *const *names, int n, hv_volume **out);

/* The surface of a Boolean tree of triangle meshes (issue 28, export .stl/.obj): each of the nleaf
 * meshes (vertices in mm, nv[i] of them, nt[i] triangles) a narrow-band level set of `voxel` mm
 * (OpenVDB meshToLevelSet, 3 voxels each side), combined by the nnode nodes of the tree (ops[i] < 0:
 * leaf leaf[i]; else an hv_geometry_op of earlier nodes a[i], b[i]; the root last) with OpenVDB's
 * csgUnion / csgIntersection / csgDifference (Wu's difference keeps a), meshed by volumeToMesh at
 * adaptivity 0, quads split in two. *out_xyz and *out_tri are malloc'd; the caller frees them.
 * Errors: HV_ERR_UNSUPPORTED (no OpenVDB plugin), HV_ERR_BAD_INPUT (a malformed tree),
 * HV_ERR_NOMEM, HV_ERR_CANCELLED. */
#include <stdint.h>
hv_status hv_vdb_surface(int nleaf, const float *const *xyz, const size_t *nv, const uint32_t *const *tri,
                         const size_t *nt, int nnode, const int *ops, const uint32_t *leaf, const uint32_t *a,
                         const uint32_t *b, double voxel, float **out_xyz, size_t *out_nv, uint32_t **out_tri,
                         size_t *out_nt);

#endif
