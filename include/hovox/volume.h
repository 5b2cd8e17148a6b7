/* hovox/volume.h - the volume store: a voxel transform and named float and bool grids that
 * share one sparse topology of 8x8x8 leaf blocks, kept in C (volumes/volume.c); C kernels work
 * directly on the leaf buffers. Files are OpenVDB files: hovox's own are read natively
 * (volumes/vdb_read.c), OpenVDB (a plugin, loaded on first use) writes them and reads others. */
#ifndef HOVOX_VOLUME_H
#define HOVOX_VOLUME_H

#include "hovox/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hv_volume hv_volume;

typedef enum hv_grid_type { HV_GRID_FLOAT = 1, HV_GRID_BOOL = 2 } hv_grid_type;
/* The one spelling of a grid type ("float", "bool"; "?" for a value not of the enum), used by
 * `hovox info`, Lua and Python; a static string. */
HV_API const char *hv_grid_type_name(hv_grid_type type);

/* Leaf blocks: 8x8x8 voxels, origin a multiple of 8 in index space. Inside a block the
 * voxel (x,y,z) (any integers) sits at offset HV_LEAF_OFFSET(x,y,z), z fastest (as OpenVDB).
 * Bool buffers and active masks are 8 64-bit words: offset n is bit n%64 of word n/64. */
#define HV_LEAF_LOG2 3
#define HV_LEAF_DIM 8
#define HV_LEAF_SIZE 512
#define HV_LEAF_WORDS 8
#define HV_LEAF_OFFSET(x, y, z) \
    ((((unsigned)(x) & 7u) << 6) | (((unsigned)(y) & 7u) << 3) | ((unsigned)(z) & 7u))
#define HV_BIT_GET(words, n) (((words)[(n) >> 6] >> ((n) & 63u)) & 1u)

/* Voxel (i,j,k) has its center at origin + (i*voxel[0], j*voxel[1], k*voxel[2]) (world
 * units, millimetres for meshes from STL). Voxels may be anisotropic. */
typedef struct hv_transform {
    double voxel[3];
    double origin[3];
} hv_transform;

/* ---- life cycle ------------------------------------------------------------------------ */

/* New empty volume (no grids, no active voxels). Errors: HV_ERR_INVALID (voxel size not
 * finite and > 0, origin not finite), HV_ERR_NOMEM. Free with hv_volume_destroy. */
HV_API hv_status hv_volume_create(const hv_transform *xf, hv_volume **out);

/* Free a volume; NULL is allowed. */
HV_API void hv_volume_destroy(hv_volume *vol);

/* Deep copy (grids, topology, metadata). Free with hv_volume_destroy. */
HV_API hv_status hv_volume_clone(const hv_volume *vol, hv_volume **out);

HV_API hv_transform hv_volume_get_transform(const hv_volume *vol);

/* Two transforms describe the same lattice (voxel sizes and origins equal within 1e-9 of
 * the voxel size). Grids can only be combined across volumes on the same lattice. */
HV_API int hv_transform_same(const hv_transform *a, const hv_transform *b);

/* ---- grids ----------------------------------------------------------------------------- */

HV_API int hv_volume_grid_count(const hv_volume *vol);
/* Name and type of grid g (0 <= g < count); the name is owned by the volume. */
HV_API const char *hv_volume_grid_name(const hv_volume *vol, int g);
HV_API hv_grid_type hv_volume_grid_type(const hv_volume *vol, int g);
/* Index of the named grid, or -1. */
HV_API int hv_volume_grid_find(const hv_volume *vol, const char *name);
/* Index of the named grid of that type; else -1, recording HV_ERR_NOT_FOUND "no bool grid 'x'
 * (bool grids: occupancy, surface)" (callers prefix whose: "the model has "). */
HV_API int hv_volume_grid_need(const hv_volume *vol, const char *name, hv_grid_type type);

/* Add a grid valued 0 (false) on every active voxel; *index receives its index (may be NULL).
 * Errors: HV_ERR_INVALID (empty name, name longer than 255 bytes, name already used),
 * HV_ERR_NOMEM. Leaf pointers of other grids stay valid. */
HV_API hv_status hv_volume_grid_add(hv_volume *vol, const char *name, hv_grid_type type,
                                    int *index);

/* Remove grid g; grids after it move down by one. Errors: HV_ERR_INVALID (bad index). */
HV_API hv_status hv_volume_grid_remove(hv_volume *vol, int g);

/* Rename grid g. Errors: HV_ERR_INVALID (bad index, name empty or used). */
HV_API hv_status hv_volume_grid_rename(hv_volume *vol, int g, const char *name);

/* Copy grid `src_g` of `src` into `dst` under `name` (replacing a grid of that name and type,
 * else adding one). dst's topology first grows to include src's active voxels. Values at
 * dst voxels that src does not have are 0/false. Errors: HV_ERR_INVALID (different
 * lattice, type clash), HV_ERR_NOMEM. `src` may equal `dst`. */
HV_API hv_status hv_volume_grid_copy(hv_volume *dst, const char *name, const hv_volume *src,
                                     int src_g);

/* ---- topology and leaf buffers --------------------------------------------------------- */

/* Leaves are numbered 0..count-1 in OpenVDB's tree order of their origins (by 4096^3 block,
 * then 128^3 block, then leaf, each x-major: the order files list them in). Numbers,
 * origins, masks and buffer pointers stay valid until the topology changes
 * (hv_volume_topology_*, hv_volume_grid_copy, hv_volume_load) or the volume is freed. */
HV_API size_t hv_volume_leaf_count(const hv_volume *vol);
/* 3 int32 per leaf: the index-space origin of each leaf. */
HV_API const int32_t *hv_volume_leaf_origins(const hv_volume *vol);
/* Active-voxel mask of a leaf (8 words). */
HV_API const uint64_t *hv_volume_leaf_mask(const hv_volume *vol, size_t leaf);
/* Value buffer of leaf `leaf` in float grid g (512 floats) or bool grid g (8 words).
 * NULL when the type does not match. Writing inactive voxels is allowed but meaningless. */
HV_API float *hv_volume_leaf_float(hv_volume *vol, int g, size_t leaf);
HV_API uint64_t *hv_volume_leaf_bool(hv_volume *vol, int g, size_t leaf);
HV_API const float *hv_volume_leaf_float_c(const hv_volume *vol, int g, size_t leaf);
HV_API const uint64_t *hv_volume_leaf_bool_c(const hv_volume *vol, int g, size_t leaf);

/* Number of active voxels. */
HV_API uint64_t hv_volume_active_count(const hv_volume *vol);

/* ---- fields a caller computes ------------------------------------------------------------ */

/* World coordinates of the centres of the voxels where bool grid `mask` is on (3 doubles per
 * voxel, in leaf order then in-leaf offset order: the order hv_volume_grid_set reads values in),
 * into *xyz (allocated; the caller frees it; NULL when there are none) and their count *n.
 * Errors: HV_ERR_NOT_FOUND (no bool grid `mask`), HV_ERR_NOMEM. */
HV_API hv_status hv_volume_centres(const hv_volume *vol, const char *mask, double **xyz, size_t *n);
/* Add float grid `name` holding values[i] at the i-th voxel of hv_volume_centres(vol, mask) and
 * 0 on every other active voxel: a scalar field computed by the caller (a script), e.g. for
 * export (hv_export_options grids). Nothing is added on error. Errors: HV_ERR_INVALID (name
 * empty, too long or used; n not the mask's voxel count; a value not finite, naming the voxel's
 * centre), HV_ERR_NOT_FOUND (no bool grid `mask`), HV_ERR_NOMEM. */
HV_API hv_status hv_volume_grid_set(hv_volume *vol, const char *name, const char *mask, const float *values,
                                    size_t n);

/* Dense copies over the inclusive index box [lo, hi] (for numerical code that wants arrays):
 * hv_volume_dense writes the n float grids `grids` (1 to 64) interleaved, out[((i * ny + j) * nz
 * + k) * n + c] = grid c at voxel (lo[0] + i, lo[1] + j, lo[2] + k), 0 where the voxel is not
 * active (a C-order (nx, ny, nz, n) array); hv_volume_dense_mask writes one byte per voxel, 1
 * where bool grid g is true (g = -1: where the voxel is active), else 0. `out` holds nx * ny * nz
 * (* n) values and is written whole (not read). Multi-threaded (hv_threads()), slab by slab.
 * Errors: HV_ERR_INVALID (hi < lo on an axis, a grid of another type or out of range),
 * HV_ERR_NOMEM, HV_ERR_CANCELLED (the cancel check). */
HV_API hv_status hv_volume_dense(const hv_volume *vol, const int *grids, int n, const int32_t lo[3],
                                 const int32_t hi[3], float *out);
HV_API hv_status hv_volume_dense_mask(const hv_volume *vol, int g, const int32_t lo[3], const int32_t hi[3],
                                      uint8_t *out);

/* Inclusive index bounding box of the active voxels; returns 0 (and leaves lo/hi alone) when
 * the volume is empty, 1 otherwise. */
HV_API int hv_volume_index_bbox(const hv_volume *vol, int32_t lo[3], int32_t hi[3]);

/* Activate voxels: for each of n blocks, origins[3b..3b+2] (multiples of 8) and masks[8b..]
 * (8 words) name voxels to add. New voxels get 0/false in every grid; voxels already active
 * keep their values. Errors: HV_ERR_INVALID (origin not a multiple of 8), HV_ERR_NOMEM. */
HV_API hv_status hv_volume_topology_add(hv_volume *vol, size_t n, const int32_t *origins,
                                        const uint64_t *masks);

/* Keep only the voxels where bool grid g is true; the others become inactive (values reset to
 * 0/false) and empty leaves are dropped. Errors: HV_ERR_INVALID (g not a bool grid). */
HV_API hv_status hv_volume_topology_restrict(hv_volume *vol, int g);

/* Grow dst's topology to include every active voxel of src (same lattice). */
HV_API hv_status hv_volume_topology_union(hv_volume *dst, const hv_volume *src);

/* ---- mask algebra on bool grids of one volume ------------------------------------------ */

typedef enum hv_mask_op {
    HV_MASK_UNION = 0,     /* dst = a | b */
    HV_MASK_INTERSECT = 1, /* dst = a & b */
    HV_MASK_DIFFERENCE = 2 /* dst = a & ~b */
} hv_mask_op;

/* dst, a, b: bool grids (dst may be a or b). Values stay inside the active topology.
 * Errors: HV_ERR_INVALID (not bool grids, bad op). */
HV_API hv_status hv_volume_mask_combine(hv_volume *vol, int dst, int a, int b, hv_mask_op op);

/* Number of true voxels in bool grid g (0 for other types). */
HV_API uint64_t hv_volume_mask_count(const hv_volume *vol, int g);

/* ---- random access --------------------------------------------------------------------- */

/* A cached accessor: remembers the last leaf it found, so nearby lookups cost a compare.
 * Lives on the caller's stack; valid while the topology is unchanged. One per thread. */
typedef struct hv_accessor {
    const hv_volume *vol;
    int32_t key[3]; /* origin of the cached leaf */
    int64_t leaf;   /* its number, or -1 */
} hv_accessor;

HV_API void hv_accessor_init(hv_accessor *acc, const hv_volume *vol);
/* Leaf holding voxel (i,j,k), or -1 when there is none. */
HV_API int64_t hv_accessor_leaf(hv_accessor *acc, int32_t i, int32_t j, int32_t k);
/* 1 when voxel (i,j,k) is active. */
HV_API int hv_accessor_active(hv_accessor *acc, int32_t i, int32_t j, int32_t k);
/* Value of float grid g at (i,j,k); 0 when inactive. */
HV_API float hv_accessor_float(hv_accessor *acc, int g, int32_t i, int32_t j, int32_t k);
/* Value of bool grid g at (i,j,k); 0 when inactive. */
HV_API int hv_accessor_bool(hv_accessor *acc, int g, int32_t i, int32_t j, int32_t k);
/* Set a value of an active voxel; HV_ERR_INVALID when (i,j,k) is not active. */
HV_API hv_status hv_accessor_set_float(hv_accessor *acc, int g, int32_t i, int32_t j,
                                       int32_t k, float value);

/* Trilinear sample of n float grids at a world point in one call. The eight voxels around
 * the point are weighted trilinearly; inactive ones are left out and the weights of the
 * active ones renormalised, so material fractions keep summing to 1 up to the boundary.
 * out[0..n-1] receive the values (0 when no neighbour is active); *coverage (may be NULL)
 * receives the summed weight of the active neighbours in [0,1], i.e. the trilinear sample of
 * the occupancy indicator. */
HV_API void hv_volume_sample(hv_accessor *acc, const int *grids, int n, const double world[3],
                             float *out, float *coverage);

/* World <-> index coordinates for this volume's transform (index coordinates are continuous;
 * voxel (i,j,k) center = index (i,j,k)). */
HV_API void hv_volume_world_to_index(const hv_volume *vol, const double world[3],
                                     double index[3]);
HV_API void hv_volume_index_to_world(const hv_volume *vol, const double index[3],
                                     double world[3]);

/* ---- metadata -------------------------------------------------------------------------- */

/* File-level metadata saved with the volume: string and number values under string keys.
 * JSON documents are strings whose key ends in ".json" by convention; hv_volume_meta_set_json
 * checks that the value parses. Setting NULL removes a key. Errors: HV_ERR_INVALID (empty key,
 * bad JSON), HV_ERR_NOMEM. */
HV_API hv_status hv_volume_meta_set_string(hv_volume *vol, const char *key, const char *value);
HV_API hv_status hv_volume_meta_set_json(hv_volume *vol, const char *key, const char *json);
HV_API hv_status hv_volume_meta_set_number(hv_volume *vol, const char *key, double value);
/* The string under key, or NULL (absent or a number). Owned by the volume; valid until the key
 * is set again. */
HV_API const char *hv_volume_meta_string(const hv_volume *vol, const char *key);
/* 1 and *value when key holds a number, else 0. */
HV_API int hv_volume_meta_number(const hv_volume *vol, const char *key, double *value);
/* Number of keys, and the i-th key (sorted), for listing. */
HV_API int hv_volume_meta_count(const hv_volume *vol);
HV_API const char *hv_volume_meta_key(const hv_volume *vol, int i);

/* ---- files ----------------------------------------------------------------------------- */

/* Save as an OpenVDB file: one FloatGrid or BoolGrid per grid, in grid order, with the
 * transform and the metadata at file level, and the grid offsets of OpenVDB's io::File format
 * (hv_volume_load_grids can then skip grids). Material fractions (float grids named
 * "material.*", values in [0, 1]) are stored as 16-bit half floats, as OpenVDB's
 * saveFloatAsHalf stores them (every reader gets floats back): a loaded fraction differs from
 * the saved one by at most 2^-12 (2.4e-4; relative 2^-11), well under a printer's 8-bit step,
 * and the files are a third to a half smaller. Other float grids keep 32 bits. Written to a temporary name in the same
 * directory, every write, the flush and the close checked, synced to disk and renamed when
 * complete: a full disk leaves no file (and an older one under the name stays). Ctrl-C (the
 * cancel check) stops it. OpenVDB writes the file, holding one grid at a time as its own
 * tree. Errors: HV_ERR_INVALID (a name not ending in .vdb, other than a special file such as
 * /dev/null), HV_ERR_IO, HV_ERR_NOMEM, HV_ERR_CANCELLED, HV_ERR_UNSUPPORTED (no OpenVDB
 * plugin). */
HV_API hv_status hv_volume_save(const hv_volume *vol, const char *path);

/* Load a model: an OpenVDB file, or a 3MF package with the Volumetric extension (a ZIP archive,
 * told apart by its first bytes; read by hv_3mf_load, hovox/threemf.h, with its errors).
 * OpenVDB: float, double, int32 and bool grids are read (doubles and ints become
 * float grids, mask grids bool grids); every grid must use the same axis-aligned linear
 * transform; the topology is the union of the grids' active voxels (active tiles are
 * expanded to voxels). Every read is checked: a file that ends early or is damaged is refused
 * at once. Active tiles are costed from the tree's structure before they are expanded: more
 * than the memory budget (hv_memory_budget(0)) is refused, saying how much. Errors:
 * HV_ERR_IO (missing, unreadable), HV_ERR_BAD_INPUT (not a VDB file, truncated, corrupt, no
 * grids, mixed or rotated transforms, unsupported grid type), HV_ERR_LIMIT, HV_ERR_NOMEM,
 * HV_ERR_CANCELLED, HV_ERR_UNSUPPORTED (no OpenVDB plugin, for a file the native reader leaves
 * to OpenVDB). The files hovox writes are read without OpenVDB (volumes/vdb_read.c, with the
 * same result bit for bit); the rest, and any file that is damaged, go to OpenVDB. */
HV_API hv_status hv_volume_load(const char *path, hv_volume **out);
/* Load only the grids `names` selects (n entries: a grid name, or a prefix followed by '*',
 * "material.*" selecting every grid whose name starts with "material."), with the file's
 * metadata, as hv_volume_load would load them: the topology is the union of the selected grids'
 * active voxels. A selector that matches nothing is not an error (hv_volume_grid_find then says
 * -1); when nothing matches, the volume has no grids, no voxels and the unit lattice. Files
 * hovox writes hold OpenVDB's grid offsets, so grids not selected are skipped, not read; other
 * files (OpenVDB streams, hovox files from before) are read whole and the grids not selected
 * dropped. Errors: those of hv_volume_load; HV_ERR_INVALID (n < 0, an empty or NULL name). */
HV_API hv_status hv_volume_load_grids(const char *path, const char *const *names, int n, hv_volume **out);
/* The path a volume was loaded from ("" for one made in memory), for messages; owned by the
 * volume. */
HV_API const char *hv_volume_name(const hv_volume *vol);

/* ---- memory ---------------------------------------------------------------------------- */

/* Bytes the volume holds now (leaf buffers, tree nodes, caches). */
HV_API uint64_t hv_volume_memory_bytes(const hv_volume *vol);

/* Bytes a volume with `leaves` leaf blocks and the given grids would take: for planning a
 * job before running it. */
HV_API uint64_t hv_volume_memory_estimate(uint64_t leaves, int float_grids, int bool_grids);

#ifdef __cplusplus
}
#endif
#endif
