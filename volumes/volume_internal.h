/* volumes/volume_internal.h - what the .vdb readers and writer (src/io/vdb) need from the volume
 * store (volume.c) beyond hovox/volume.h. Internal. */
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

/* The buffers of grid g, one per leaf in leaf order (HV_LEAF_SIZE floats or HV_LEAF_WORDS words
 * each); NULL when g is not a grid. Owned by the volume. */
void *const *hv_volume_grid_buffers(const hv_volume *v, int g);

/* Record the file a volume was loaded from (hv_volume_name). Errors: HV_ERR_NOMEM. */
hv_status hv_volume_set_name(hv_volume *v, const char *name);

/* For tests and the fuzz harness: whether two volumes are the same bit for bit (transform,
 * leaves, grids and their values, metadata), else 0 with what differs in why. */
int hv_volume_identical(const hv_volume *a, const hv_volume *b, char *why, size_t len);

#endif
