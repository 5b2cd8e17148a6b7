/* volumes/volume_internal.h - what the native OpenVDB reader (vdb_read.c) needs from the volume
 * store (volume.c). Internal: callers use hovox/volume.h. */
#ifndef HOVOX_VOLUME_INTERNAL_H
#define HOVOX_VOLUME_INTERNAL_H

#include "hovox/volume.h"

/* OpenVDB's tree order of leaf origins (5-4-3 trees): <0, 0 or >0 as a comes before, with or
 * after b. Leaf tables are kept in this order. */
int hv_leaf_order(const int32_t *a, const int32_t *b);

/* Give an empty volume (no leaves yet) its topology: n leaves in tree order, origins (3 int32
 * each) and masks (8 words each), both allocated with malloc; the volume takes them (also on
 * failure: HV_ERR_NOMEM leaves them with the volume, freed with it). */
hv_status hv_volume_adopt_topology(hv_volume *v, size_t n, int32_t *origins, uint64_t *masks);

/* Set the lattice of a volume that has no leaves yet. */
void hv_volume_adopt_transform(hv_volume *v, const hv_transform *xf);

/* Append a grid of zeroed leaf buffers (one per leaf of the topology: adopt the topology
 * first); *index (may be NULL) receives its index. An empty or used name is made unique
 * ("name.grid3"). Errors: HV_ERR_NOMEM. */
hv_status hv_volume_adopt_grid(hv_volume *v, const char *name, hv_grid_type type, int *index);

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
 * the native reader skipped; and whether two volumes are the same bit for bit (transform,
 * leaves, grids and their values, metadata), else 0 with what differs in why. */
hv_status hv_volume_load_openvdb(const char *path, const char *const *names, int n, hv_volume **out);
int hv_volume_identical(const hv_volume *a, const hv_volume *b, char *why, size_t len);

#endif
