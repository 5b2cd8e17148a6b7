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

#endif
