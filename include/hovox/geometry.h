/* hovox/geometry.h - the geometry truth of a model (issue 28; DESIGN.md "Geometry truth"): the
 * shapes a model came from (its leaves: meshes, embedded and compressed, or the iso-surface of
 * a scanned field), each with its placement, and the tree of Booleans applied to them. The
 * voxels say which material is where; this record says where the surface is, exactly, so that
 * layers, trays, contours and surface export cut the leaves and combine their outlines with the
 * same tree (hovox/solid.h) and a Boolean reaches the print. */
#ifndef HOVOX_GEOMETRY_H
#define HOVOX_GEOMETRY_H

#include "hovox/mesh.h"
#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What a leaf holds. MESH: a triangle mesh (hovox's own packing of hv_mesh: vertices, facets,
 * bodies and materials). FIELD_ISO: the iso-surface of a scanned field (its data defined by
 * the module that reads scanned volumes). */
typedef enum hv_leaf_kind {
    HV_LEAF_MESH = 0,
    HV_LEAF_FIELD_ISO = 1
} hv_leaf_kind;

/* The Booleans of the tree, with the values and meanings of hv_bool_op (hovox/material.h), and
 * the shape each leaves (materials are the voxels' business):
 *   INTERSECT   O1 n O2
 *   UNITE       O1 u O2
 *   DIFFERENCE  O1        (Wu's difference keeps O1: H2's material fills the overlap)
 *   MERGE       O1 u O2
 *   SUBTRACT    O1 - O2   (CSG) */
typedef enum hv_geometry_op {
    HV_GEOMETRY_INTERSECT = 0,
    HV_GEOMETRY_UNITE = 1,
    HV_GEOMETRY_DIFFERENCE = 2,
    HV_GEOMETRY_MERGE = 3,
    HV_GEOMETRY_SUBTRACT = 4
} hv_geometry_op;

/* Name of an op ("intersect", "unite", "difference", "merge", "subtract"; "?" otherwise). */
HV_API const char *hv_geometry_op_name(hv_geometry_op op);

/* A model's geometry record: leaves and a Boolean tree over them. Opaque, immutable once made. */
typedef struct hv_geometry hv_geometry;

typedef struct hv_geometry_leaf {
    hv_leaf_kind kind;
    const char *name;      /* where it came from ("plate.stl"); owned by the record */
    double transform[12];  /* raw coordinates -> model millimetres, row-major 3x4 as in
                              hv_mesh_transform (unit and placement included) */
    double unit;           /* millimetres per raw unit, for information (the transform holds it) */
    size_t size;           /* bytes of raw data */
    uint64_t hash;         /* FNV-1a 64 of the raw data: equal leaves share it */
} hv_geometry_leaf;

/* A node of the tree: a leaf (op < 0, `leaf` its index) or a Boolean of nodes a and b (both
 * earlier in the node list). The root is the last node. */
typedef struct hv_geometry_node {
    int op;        /* -1: a leaf; else an hv_geometry_op */
    uint32_t leaf; /* op < 0 */
    uint32_t a, b; /* op >= 0 */
} hv_geometry_node;

/* A record of one MESH leaf: `raw` as read from its file (copied and packed), `name` its source
 * (may be NULL: the mesh's name), `transform` NULL for the identity, unit <= 0 for 1.
 * Errors: HV_ERR_INVALID (a transform entry not finite, its 3x3 part singular), HV_ERR_NOMEM.
 * Free with hv_geometry_destroy. */
HV_API hv_status hv_geometry_from_mesh(const hv_mesh *raw, const char *name, const double transform[12],
                                       double unit, hv_geometry **out);
/* A record of one leaf of any kind from its raw data (copied); for kinds whose module packs its
 * own data (FIELD_ISO). Errors: HV_ERR_INVALID (kind, transform, size 0), HV_ERR_NOMEM. */
HV_API hv_status hv_geometry_from_leaf(hv_leaf_kind kind, const char *name, const void *data, size_t size,
                                       const double transform[12], double unit, hv_geometry **out);
/* The record of a Boolean: a's leaves, then b's that a does not hold (same kind, data and
 * transform), and the node op(a's root, b's root). Errors: HV_ERR_INVALID (op), HV_ERR_NOMEM. */
HV_API hv_status hv_geometry_combine(const hv_geometry *a, const hv_geometry *b, hv_geometry_op op,
                                     hv_geometry **out);
/* The record moved by m (row-major 3x4, as hv_mesh_transform): every leaf's transform becomes m
 * applied after it; data and tree unchanged (a tray's quarter turn of a part). Errors:
 * HV_ERR_INVALID (m or a product not finite, singular), HV_ERR_NOMEM. */
HV_API hv_status hv_geometry_transformed(const hv_geometry *g, const double m[12], hv_geometry **out);
HV_API void hv_geometry_destroy(hv_geometry *g); /* NULL allowed */

HV_API size_t hv_geometry_leaf_count(const hv_geometry *g);
/* Leaf i (< count); owned by the record. */
HV_API const hv_geometry_leaf *hv_geometry_leaf_at(const hv_geometry *g, size_t i);
/* Leaf i's raw data (uncompressed); owned by the record. */
HV_API const uint8_t *hv_geometry_leaf_data(const hv_geometry *g, size_t i);
HV_API size_t hv_geometry_node_count(const hv_geometry *g);
/* Node i (< count); the root is node count - 1. Owned by the record. */
HV_API const hv_geometry_node *hv_geometry_node_at(const hv_geometry *g, size_t i);
/* 1 when the record is one leaf and no Boolean (a model voxelized from one mesh). */
HV_API int hv_geometry_is_plain(const hv_geometry *g);
/* 1 when the shape is its one leaf's: a single leaf combined only with itself by ops other than
 * subtract (X n X = X u X = X; Wu's union of two gradings of one part, as in his gear example). */
HV_API int hv_geometry_shape_is_leaf(const hv_geometry *g);

/* MESH leaf i unpacked: the raw mesh (bodies, materials and facet order as read; named after the
 * leaf), and placed: moved by the leaf's transform (the raw mesh itself when that is the
 * identity). Errors: HV_ERR_INVALID (not a MESH leaf), HV_ERR_BAD_INPUT (damaged data: the
 * message says what), HV_ERR_NOMEM. Free with hv_mesh_destroy. */
HV_API hv_status hv_geometry_leaf_mesh_raw(const hv_geometry *g, size_t i, hv_mesh **out);
HV_API hv_status hv_geometry_leaf_mesh(const hv_geometry *g, size_t i, hv_mesh **out);

/* ---- in a model ------------------------------------------------------------------------------
 * A model holds its record in metadata: "hovox.geometry.json" (schema 1: the leaves with kind,
 * name, transform, unit, size, hash, and the key of their data; the tree as nested
 * {"op", "a", "b"} objects whose leaves are indices) and, per leaf, its raw data deflated
 * (zlib) and base64-encoded under "hovox.geometry.leaf.<hash as 16 hex digits>" (equal leaves
 * share one). So a .vdb is complete on its own, and the record rides along wherever the model's
 * metadata goes (graded models keep it; Booleans combine it). */

/* The record of `model`. Errors: HV_ERR_NOT_FOUND ("the model records no geometry": made by an
 * older hovox, or from a source without one), HV_ERR_BAD_INPUT (the document malformed, a leaf's
 * data missing ("the geometry tree refers to mesh 'rod.stl' (hovox.geometry.leaf.0123...), which
 * the model does not hold"), damaged (base64, zlib, size or hash), a tree index out of range or
 * a node before its children), HV_ERR_NOMEM. */
HV_API hv_status hv_geometry_read(const hv_volume *model, hv_geometry **out);
/* Store g in model's metadata, replacing any record it held (and its leaves' keys); NULL removes
 * the record. Errors: HV_ERR_NOMEM. */
HV_API hv_status hv_geometry_write(const hv_geometry *g, hv_volume *model);
/* Whether model holds a record (the document's key; not checked). */
HV_API int hv_geometry_present(const hv_volume *model);

/* The record of a Boolean of two models: when both hold a record, hv_geometry_combine of theirs
 * written into `out` (replacing what it held); when either holds none, out's record is removed.
 * Errors: those of hv_geometry_read (prefixed "boolean: "), HV_ERR_NOMEM. */
HV_API hv_status hv_geometry_combine_models(const hv_volume *a, const hv_volume *b, hv_geometry_op op,
                                            hv_volume *out);

#ifdef __cplusplus
}
#endif
#endif
