/* src/voxel/voxel_internal.h - the interior passes of the voxelizer (fill.c). */
#ifndef HOVOX_VOXEL_INTERNAL_H
#define HOVOX_VOXEL_INTERNAL_H

#include "bitgrid.h"
#include "core/json.h"
#include "hovox/mesh.h"
#include "hovox/voxelize.h"

/* occ = everything not reachable from the grid border through non-surface voxels
 * (6-connected moves for adjacency 6, 26-connected for 26). occ must be zeroed. */
hv_status hv_fill_flood(const hv_bitgrid *surf, hv_bitgrid *occ, int adjacency,
                        const hv_progress *progress);

/* occ = surf | majority over the x, y, z lines through each voxel centre of the crossing
 * parity with the mesh; P holds the mesh vertices in grid coordinates. */
hv_status hv_fill_vote(const hv_mesh *mesh, const double *P, const hv_bitgrid *surf,
                       hv_bitgrid *occ, const hv_progress *progress);

/* in = the voxels whose centre is inside the mesh, by the vote's rule for every voxel (its even
 * lines' majority; where they tie, the majority of all three lines' parities, not the winding
 * number), surface voxels included: the centre classification of an assembly's bodies. in must
 * be zeroed; its n and lo give the lattice. */
hv_status hv_fill_centres(const hv_mesh *mesh, const double *P, hv_bitgrid *in, const hv_progress *progress);

/* Mark the voxels of grid S that the triangle p (grid coordinates: voxel centres at integers)
 * covers by Huang's tests (adjacency 26 when adj26, else 6). Thread-safe (atomic OR). */
void hv_voxel_mark_triangle(const double *p[3], int adj26, hv_bitgrid *S);

/* A volume on lattice xf from bit grids: the topology and bool grid "occupancy" are occ's voxels,
 * "surface" those of surf among them (voxelize.c; also the scan voxelizer's). */
hv_status hv_voxel_store(const hv_bitgrid *occ, const hv_bitgrid *surf, const hv_transform *xf,
                         const hv_progress *progress, hv_volume **out);

/* Approximate bytes of a mesh in memory (for planning). */
size_t mesh_bytes(const hv_mesh *m);

/* ---- regions of an assembly (regions.c) ---------------------------------------------------- */

struct hv_regions {
    size_t n;
    hv_region_info *info; /* strings and lost_to malloc'd, owned */
    uint64_t overlap;     /* voxels whose centres are inside two or more bodies */
};

/* Longest body name a region takes ("region." + name within a grid name's 255 bytes). */
#define HV_REGION_NAME_MAX 248

/* "region.<body>" (malloc'd). Errors: HV_ERR_BAD_INPUT (name too long), HV_ERR_NOMEM. */
hv_status hv_regions_grid_name(const char *body, char **out);

/* The fill HV_FILL_AUTO resolves to for a mesh with this report: flood for one closed, manifold,
 * consistently oriented shell, else the vote. */
hv_fill_mode hv_fill_auto(const hv_mesh_report *r);

/* The documents voxelization writes (volumes/schema.h). to_doc: a new object without "schema"
 * (NULL when out of memory); from_doc: `what` names the document in messages, errors
 * HV_ERR_BAD_INPUT naming the member, HV_ERR_NOMEM. */
/* hovox.voxelize.json (voxelize.c): fills the job part of rec (not rec->mesh). */
json_t *hv_voxelize_to_doc(const hv_voxel_plan *plan, int adjacency);
hv_status hv_voxelize_from_doc(const json_t *doc, const char *what, hv_voxelize_record *rec);

/* hovox.regions.json (regions.c) */
json_t *hv_regions_to_doc(const hv_regions *r, double voxel_volume);
hv_status hv_regions_from_doc(const json_t *doc, const char *what, hv_regions **out);

#endif
