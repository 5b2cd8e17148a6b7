/* src/export/export_internal.h - what export.c (model, properties, .vti, the VTK plugin) and
 * hexmesh.c (the .vtu hexahedral mesh) share. Internal. */
#ifndef HOVOX_EXPORT_INTERNAL_H
#define HOVOX_EXPORT_INTERNAL_H

#include "core/internal.h"
#include "hovox/export.h"
#include "hovox/mesh.h"

typedef enum ex_kind { EX_VOIGT, EX_REUSS, EX_TABLE, EX_GRID } ex_kind;

/* One derived property array. */
typedef struct ex_prop {
    ex_kind kind;
    double x[HV_MAX_MATERIALS];  /* per-material values (mixing rules) */
    const hv_linearization *lin; /* table */
    int mat;                     /* table: the material whose fraction is the variable */
    double scale;                /* table: factor to SI units */
    int grid;                    /* grid: the model's float grid */
    int colour;                  /* 1: one of a painted model's colour.r, .g, .b, added for it
                                    (a 3MF Volumetric package carries those as its <v:color>) */
    char name[200];
} ex_prop;

/* The model as the writers see it. */
typedef struct ex_model {
    const hv_volume *vol;
    hv_material_table *table; /* NULL: no materials, occupancy only */
    int m;
    int grids[HV_MAX_MATERIALS];
    int nprops;
    ex_prop *props;
    int ngrids;               /* props of kind EX_GRID */
    int64_t lo[3], hi[3];     /* exported voxel index range (inclusive) */
    int64_t olo[3], ohi[3];   /* bounding box of the exported occupied voxels */
    size_t nleaves;
    uint64_t *occ;            /* 8 words per leaf: active, occupied and inside the box */
    uint64_t occupied;
    /* a painted model (hovox/colour.h): its float grids colour.r, .g, .b (the sRGB asked for)
     * and colour.mask (1 where a colour was asked for) */
    int painted, colour[4];
    hv_buf notes;
} ex_model;

/* The model for an export: materials, property arrays, occupied voxels inside the box (md->occ)
 * and their bounding box. Errors: those of the material table, the property arrays and
 * HV_ERR_INVALID (a box without voxel centres), HV_ERR_NOMEM. Free with ex_model_free (also
 * after a failure). */
hv_status ex_model_init(ex_model *md, const hv_volume *vol, const hv_export_options *opt);
void ex_model_free(ex_model *md);

/* The 3MF Volumetric package (src/threemf/write.c): the plan fills r (dims, triangles, stacks,
 * memory); the write, given that plan in r, claims the output's temporary, writes and renames it. */
hv_status ex_3mf_plan(const ex_model *md, const hv_export_options *opt, hv_export_report *r);
hv_status ex_3mf_write(const ex_model *md, const char *path, const hv_export_options *opt, hv_export_report *r);

/* 1 for the formats that write the shape the model records (.stl, .obj, .3mf without volumetric). */
static inline int ex_format_is_shape(hv_export_format f)
{
    return f == HV_EXPORT_STL || f == HV_EXPORT_OBJ || f == HV_EXPORT_3MF_SHAPE;
}

/* The 3MF core package of a shape (src/io/3mf/shape_write.c): mesh `m` as one object named `name`
 * (also the package's Title), unit millimeter; with a table t (may be NULL), its materials as <basematerials id="1"> and facet f
 * in material fmat[f] (the object's default: `def`); the model part deflated at `level`. Written
 * to a temporary and renamed. Errors: HV_ERR_IO, HV_ERR_NOMEM, HV_ERR_CANCELLED. */
hv_status ex_3mf_shape_write(const char *name, const hv_mesh *m, const hv_material_table *t, const int32_t *fmat,
                             int32_t def, const char *path, int level, const hv_progress *progress);

/* .stl, .obj and .3mf (shape.c): the shape the model records as a surface; r->format set by the caller.
 * cells: triangles, points: vertices, names: the recorded mesh. Errors: HV_ERR_INVALID (no shape
 * recorded), HV_ERR_UNSUPPORTED (a scanned field's shape), HV_ERR_LIMIT (a Boolean's level sets over
 * opt->max_memory), those of hv_geometry_read
 * and the mesh writers. */
hv_status ex_shape_plan(const hv_volume *vol, const hv_export_options *opt, hv_export_report *r);
hv_status ex_shape_write(const hv_volume *vol, const char *path, const hv_export_options *opt, hv_export_report *r);

/* Material fractions at an occupied voxel must be finite, in [0,1] and sum to 1 (within
 * 1e-4: they are stored as floats). HV_ERR_BAD_INPUT naming the voxel otherwise. */
/* "12.3 MiB" and the like, into buf. */

hv_status ex_check_fractions(const ex_model *md, const double *p, int32_t i, int32_t j,
                             int32_t k);
/* out[q][idx] = property q of composition p (EX_GRID arrays are left to ex_grid_values). */
void ex_eval_props(const ex_model *md, const double *p, float *const *out, size_t idx);
/* Most arrays an export writes. */
#define EX_MAX_ARRAYS (1 + 2 * HV_MAX_MATERIALS + 64)
/* out[q][idx] = the EX_GRID arrays' values g[q] (a voxel's, or a cell's average). */
void ex_grid_values(const ex_model *md, const double *g, float *const *out, size_t idx);
/* g[q] += the EX_GRID arrays' values at voxel `off` of leaf l. */
void ex_grid_add(const ex_model *md, size_t l, unsigned off, double *g);

/* The .vtu mesh: coarse cells on the lattice floor(voxel / N), kept by the rule; points are
 * the cells' corners, each once. Numbering follows sorted leaf origins, then the in-leaf
 * offset, so the result does not depend on threads. */
typedef struct ex_hexmesh {
    int n;                   /* N */
    hv_coarsen_rule rule;
    size_t ncl, nkl;         /* coarse-cell leaves, corner leaves */
    int32_t *cl_origin, *kl_origin;
    uint64_t *cl_mask, *kl_mask;     /* 8 words each: cells kept / corners used */
    uint64_t *cl_base, *kl_base;     /* first cell / point id of each leaf */
    uint16_t *kl_prefix;             /* 8 per corner leaf: set bits before each word */
    size_t clh_cap, klh_cap;         /* hash tables (origin -> leaf), power of two */
    int64_t *clh, *klh;
    uint64_t ncells, npoints;
} ex_hexmesh;

/* Count cells and points (no big buffers). */
hv_status ex_hexmesh_plan(ex_hexmesh *h, const ex_model *md, int n, hv_coarsen_rule rule,
                          const hv_progress *progress);
/* 32-bit point ids are enough (and half the memory) below 2^31 points and 2^28 cells. */
int ex_hexmesh_ids64(const ex_hexmesh *h);
/* Fill points (3 per point), connectivity (8 per cell: int64_t when conn64, else int32_t),
 * cell arrays: occupancy, m fractions, md->nprops properties (each ncells floats). */
hv_status ex_hexmesh_fill(const ex_hexmesh *h, const ex_model *md, float *points, void *conn,
                          int conn64, float *occupancy, float *const *fractions,
                          float *const *props, const hv_progress *progress);
void ex_hexmesh_free(ex_hexmesh *h);

#endif
