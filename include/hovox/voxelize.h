/* hovox/voxelize.h - mesh to volume after Wu 2.1 and Huang, Yagel, Filippov, Kurzion,
 * "An Accurate Method for Voxelizing Polygon Meshes" (1998): per-triangle plane tests (face
 * slab bounded by the edge planes, edge cylinders, vertex spheres) for a 6- or 26-separating
 * surface, then the interior by flood fill (closed meshes) or ray-parity voting (meshes with
 * holes or flipped facets). */
#ifndef HOVOX_VOXELIZE_H
#define HOVOX_VOXELIZE_H

#include "hovox/mesh.h"
#include "hovox/options.h"
#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum hv_fill_mode {
    HV_FILL_AUTO = 0,  /* flood when the mesh is one closed, manifold, consistently oriented
                          shell, else vote (several shells may nest: a hollow part's cavity
                          must stay empty) */
    HV_FILL_FLOOD = 1, /* flood the outside from the grid border through non-surface voxels
                          (6-connected for adjacency 6, 26-connected for 26); the rest is inside */
    HV_FILL_VOTE = 2,  /* robust: a voxel is inside when the parity of surface crossings along
                          its x, y and z lines says inside for at least two of the three; holes
                          and flipped facets only mislead lines that pass through them */
    HV_FILL_NONE = 3   /* surface only */
} hv_fill_mode;

typedef struct hv_voxelize_options {
    int adjacency;          /* 6 (thin, no 6-connected tunnel) or 26 (no 26-connected tunnel) */
    const hv_transform *lattice; /* if set: voxelize on this lattice (its voxel size and phase;
                               the index range covers the mesh), e.g. another model's, so
                               that the two can be combined by Booleans */
    double voxel_size[3];   /* else if voxel_size[0] > 0: voxel size per axis (give all three);
                               the lattice is global: voxel centres at (n + 1/2) * size, so
                               meshes voxelized with the same size share a lattice */
    int64_t dims[3];        /* else: dims[0] > 0 and dims[1] == dims[2] == 0: voxels along the
                               longest axis (cubic voxels); all three > 0: voxels per axis
                               (Wu's (64,64,45)), voxels anisotropic when the ratios differ;
                               all 0 (default): HV_VOXELIZE_DEFAULT_DIMS on the longest axis */
    hv_fill_mode fill;
    uint64_t max_memory;    /* bytes the job may use; 0: half the physical memory */
    const hv_progress *progress;
} hv_voxelize_options;

#define HV_VOXELIZE_DEFAULT_DIMS 128

/* Defaults: adjacency 26, 128 voxels on the longest axis, HV_FILL_AUTO, half of memory. */
HV_API void hv_voxelize_options_init(hv_voxelize_options *opt);

/* The voxelizer's options as an option set (hovox/options.h): keys dims, voxel_size,
 * adjacency, fill, max_memory (a lattice is given in C as `lattice`; front ends call it
 * "like"). Static data. */
HV_API const hv_option_set *hv_voxelize_option_set(void);
/* Domains and exclusions (dims or voxel_size or lattice). Errors: HV_ERR_INVALID naming the
 * option. */
HV_API hv_status hv_voxelize_options_check(const hv_voxelize_options *opt);
/* Name <-> fill mode ("auto", "flood", "vote" (alias "winding"), "none"). */
HV_API hv_status hv_fill_mode_parse(const char *name, hv_fill_mode *out);
HV_API const hv_enum_def *hv_fill_mode_enum(void);

/* The lattice a job will use and what it will cost, computed before any voxel is touched.
 * Voxel (i,j,k) has its centre at origin + (i*voxel[0], ...); the mesh's box is covered by
 * voxels first[a] <= i < first[a] + dims[a]. With dims the grid is centred on the mesh's box
 * and first = 0; with a voxel size or a lattice, index 0 is the lattice's own (voxel centres at
 * origin + n * voxel for every model on it), so models share one index space. The surface may
 * reach one voxel beyond the box. */
typedef struct hv_voxel_plan {
    hv_transform xf;
    int64_t first[3];
    int64_t dims[3];
    hv_fill_mode fill;       /* AUTO resolved */
    uint64_t memory_bytes;   /* estimated peak */
} hv_voxel_plan;

/* Plan a job. Errors: HV_ERR_INVALID (adjacency not 6/26, voxel size or dims not positive and
 * finite, a flat mesh with dims on a zero-extent axis), HV_ERR_LIMIT (more than 2^31 voxels on
 * an axis, or the estimate exceeds max_memory: the message says how much it needs). */
HV_API hv_status hv_voxelize_plan(const hv_mesh *mesh, const hv_voxelize_options *opt,
                                  hv_voxel_plan *plan);

/* Voxelize. The new volume has bool grids "occupancy" (surface and interior; also the shared
 * topology) and "surface" (the voxels the plane tests produced), and metadata
 * "hovox.mesh.json" (the mesh report) and "hovox.voxelize.json" (adjacency, fill, dims).
 * Multi-threaded over triangles and rows; the result does not depend on the thread count.
 * Errors: those of hv_voxelize_plan, HV_ERR_NOMEM, HV_ERR_CANCELLED, HV_ERR_UNSUPPORTED (no
 * OpenVDB bridge). Free the volume with hv_volume_destroy. */
HV_API hv_status hv_voxelize(const hv_mesh *mesh, const hv_voxelize_options *opt,
                             hv_volume **out);

/* Name of a fill mode ("auto", "flood", "vote", "none"; "?" for other values). */
HV_API const char *hv_fill_mode_name(hv_fill_mode mode);

/* What hv_voxelize records in a model, in metadata "hovox.mesh.json" and "hovox.voxelize.json"
 * (hv_object_evaluate carries both over into graded models). */
typedef struct hv_voxelize_record {
    hv_mesh_report mesh;  /* the voxelized mesh's report (bounding box, volume, defects) */
    int adjacency;        /* 6 or 26 */
    hv_fill_mode fill;    /* as resolved: flood, vote or none */
    int64_t first[3];     /* the plan's index box (hv_voxel_plan) */
    int64_t dims[3];
    double voxel[3];      /* voxel size */
} hv_voxelize_record;

/* Read the record of a model. Documents written by older hovox versions (without a schema
 * version) are read as version 1. Errors: HV_ERR_NOT_FOUND (no record: the model was not made
 * by hv_voxelize), HV_ERR_BAD_INPUT (a document is malformed, names an unknown value or has a
 * schema version this hovox does not read; the message names the key and the member). */
HV_API hv_status hv_voxelize_record_read(const hv_volume *model, hv_voxelize_record *out);

/* ---- assemblies --------------------------------------------------------------------------
 * A mesh with more than one body (hv_mesh_body_count > 1: an assembly) voxelizes on one
 * lattice, planned from the whole mesh's box as for one body. Each body is voxelized alone on
 * that lattice (HV_FILL_AUTO decided from the body's own report, hv_mesh_body_extract) and its
 * voxels become bool grid "region.<body name>". A voxel belongs to the body that contains its
 * centre, in two passes in mesh order: (1) a voxel whose centre is inside one or more bodies
 * goes to the first of them (where bodies overlap, the first keeps the voxels); (2) a voxel of
 * the occupancy whose centre is inside no body (the outer skin: surface voxels whose centres
 * lie outside) goes to the first body whose voxels have it. A body's centres are its interior
 * voxels and those of its surface voxels whose centre the vote's crossing parities put inside
 * (for every fill). "overlap" counts the voxels whose centres are inside two or more bodies;
 * a body's "lost" voxels are its own voxels (surface and interior, as if voxelized alone) that
 * another region got, and "lost_to" the part of them whose centres are inside the body too,
 * per earlier body that kept them (so lost_to sums to at most lost). "occupancy" is the union
 * of the bodies; "surface" holds the bodies' surface voxels that lie in no body's interior (the
 * surface of the union: a body nested in another adds none). The metadata
 * "hovox.voxelize.json" records the fill as resolved when every body resolved alike, else
 * "auto"; "hovox.regions.json" records the regions (hv_voxelize_regions_read). A mesh with one
 * body voxelizes as it always did: no region grid, no regions document (a material it names is
 * not recorded). The plan (hv_voxelize_plan) keeps HV_FILL_AUTO for an assembly (each body
 * decides when it is voxelized) and estimates the memory of the whole job: a body's working
 * grids, the union's five, each body's leaf blocks kept until the second pass and one bool grid
 * per region in the volume. */

/* What an earlier region kept of a body's voxels whose centres are inside the body. */
typedef struct hv_region_loss {
    size_t region;   /* index of the earlier region */
    uint64_t voxels;
} hv_region_loss;

typedef struct hv_region_info {
    const char *name;      /* the body's name */
    const char *grid;      /* "region.<name>" */
    const char *material;  /* the body's material as the file names it; NULL: none */
    size_t nparts;         /* the material a mixture (a 3MF composite): its base materials and */
    const hv_mesh_mix_part *parts; /* fractions (summing to 1), which the graded model takes */
    int has_color;
    float rgba[4];         /* the material's display colour in [0,1] when has_color */
    hv_fill_mode fill;     /* as resolved for this body (flood, vote or none) */
    uint64_t voxels;       /* voxels of the region */
    uint64_t lost;         /* the body's own voxels (as voxelized alone) that other regions got */
    size_t nlost_to;
    const hv_region_loss *lost_to; /* its centres an earlier region kept (the overlap), per earlier
                                    * region that kept some, in region order; sum <= lost */
} hv_region_info;

typedef struct hv_regions hv_regions;

/* The regions of a model voxelized from an assembly (its "hovox.regions.json", carried into
 * graded models). Errors: HV_ERR_NOT_FOUND (not an assembly), HV_ERR_BAD_INPUT (a malformed
 * document naming the member, a schema version this hovox does not read), HV_ERR_NOMEM. Free
 * with hv_regions_destroy; everything it points to is owned by it. */
HV_API hv_status hv_voxelize_regions_read(const hv_volume *model, hv_regions **out);
HV_API size_t hv_regions_count(const hv_regions *regions);
/* Region i < count, in mesh order; owned by `regions`. */
HV_API const hv_region_info *hv_regions_at(const hv_regions *regions, size_t i);
/* The region of this exact name, or -1. */
HV_API int64_t hv_regions_find(const hv_regions *regions, const char *name);
/* Voxels whose centres are inside two or more bodies (where bodies overlap), each counted once. */
HV_API uint64_t hv_regions_overlap(const hv_regions *regions);
HV_API void hv_regions_destroy(hv_regions *regions); /* NULL allowed */

/* A graded model straight from a mesh, in its bodies' materials (one step from a part to a stack,
 * issue 27): the mesh voxelized by `opt` (an assembly into a region per body, as above), then
 * every region 100% its body's material, or its body's mixture (a 3MF composite), evaluated as
 * hovox/material.h's hv_object_from_regions and hv_object_evaluate would (under opt->max_memory;
 * materials named by hv_material_name_from, in first-use order, in the file's colours). Give
 * bodies their materials first with hv_mesh_body_material_set. Errors: HV_ERR_INVALID (a body
 * without a material, naming it and the option {material}), those of hv_voxelize and
 * hv_object_evaluate. Free *out with hv_volume_destroy. */
/* The voxels for hv_mesh_model: opt->voxel_size set to `pitch` (say the printer's coarsest pitch),
 * coarsened by 5/4 until the plan (filled in) needs at most `budget` bytes (at most 60 times).
 * Errors: HV_ERR_INVALID (pitch not positive and finite), HV_ERR_LIMIT (nothing fits), those of
 * hv_voxelize_plan. */
HV_API hv_status hv_mesh_model_voxels(const hv_mesh *mesh, double pitch, uint64_t budget, hv_voxelize_options *opt,
                                      hv_voxel_plan *plan);
HV_API hv_status hv_mesh_model(const hv_mesh *mesh, const hv_voxelize_options *opt, const hv_progress *progress,
                               hv_volume **out);

#ifdef __cplusplus
}
#endif
#endif
