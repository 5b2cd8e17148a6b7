/* hovox/solid.h - the exact shape of a model at any height (issue 28; DESIGN.md "Geometry
 * truth"): the leaf interface every kind of leaf answers (bounding box, closed outlines at a
 * height, inside test) and the shape of a whole geometry record (hovox/geometry.h), its leaves'
 * outlines combined by the record's Boolean tree. Layers, trays, contours and surface export
 * take the shape from here. */
#ifndef HOVOX_SOLID_H
#define HOVOX_SOLID_H

#include "hovox/geometry.h"
#include "hovox/slice.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ==== the leaf interface =======================================================================
 * A leaf opened for queries. Each kind implements the same four answers (src/geometry/leaf.c
 * holds the table of kinds):
 *   MESH       the mesh placed by the leaf's transform; outlines: the WDG slicer (Wu 2.4.1,
 *              hovox/slice.h: loops oriented, outers counter-clockwise, holes clockwise,
 *              nested); inside: the point lies inside the outline at its own height.
 *   FIELD_ISO  the iso-surface of a scanned field (outlines by marching squares on the
 *              trilinearly interpolated field); provided by the scanned-volume module, else
 *              HV_ERR_UNSUPPORTED.
 * Thread safety: an opened leaf is immutable; any number of threads may query it at once. */
typedef struct hv_leaf hv_leaf;

/* Open leaf i of g (g may be destroyed afterwards). Errors: HV_ERR_INVALID (i out of range),
 * HV_ERR_BAD_INPUT (its data damaged), HV_ERR_UNSUPPORTED (a kind this build cannot cut),
 * HV_ERR_NOMEM, HV_ERR_CANCELLED. Free with hv_leaf_close. */
HV_API hv_status hv_leaf_open(const hv_geometry *g, size_t i, const hv_progress *progress, hv_leaf **out);
HV_API void hv_leaf_close(hv_leaf *leaf); /* NULL allowed */
HV_API hv_leaf_kind hv_leaf_get_kind(const hv_leaf *leaf);
/* Axis-aligned bounding box in model millimetres. */
HV_API void hv_leaf_bbox(const hv_leaf *leaf, double min[3], double max[3]);
/* The closed outlines at height z (options NULL: defaults), as an hv_slice (hovox/slice.h): loops
 * oriented and nested; a plane outside the leaf gives an empty slice. Errors: HV_ERR_INVALID (z
 * not finite, bad options), HV_ERR_NOMEM. Free with hv_slice_destroy. */
HV_API hv_status hv_leaf_slice(const hv_leaf *leaf, double z, const hv_slice_options *options, hv_slice **out);
/* 1 when p lies inside the leaf, else 0 (0 on failure to compute, which only lack of memory
 * causes). */
HV_API int hv_leaf_inside(const hv_leaf *leaf, const double p[3]);
/* MESH leaves: the placed mesh and its slicer (owned by the leaf); NULL for other kinds. */
HV_API const hv_mesh *hv_leaf_mesh(const hv_leaf *leaf);
HV_API const hv_slicer *hv_leaf_slicer(const hv_leaf *leaf);

/* ==== the solid of a record (its exact shape) ===================================================================
 * Every leaf opened, and the tree. The solid's answers follow the ops of hv_geometry_op: inside
 * is the Boolean of the leaves' inside tests, the bounding box the Boolean's bound (union of the
 * operands' boxes for unite and merge, a's box for subtract and difference, the overlap for
 * intersect). */
typedef struct hv_solid hv_solid;

/* Open every leaf of g. Errors: those of hv_leaf_open. Free with hv_solid_close. */
HV_API hv_status hv_solid_open(const hv_geometry *g, const hv_progress *progress, hv_solid **out);
HV_API void hv_solid_close(hv_solid *solid); /* NULL allowed */
HV_API size_t hv_solid_leaf_count(const hv_solid *solid);
/* Leaf i (< count); owned by the solid. */
HV_API const hv_leaf *hv_solid_leaf(const hv_solid *solid, size_t i);
/* 1 when the solid is one leaf and no Boolean: its outlines are that leaf's, unchanged. */
HV_API int hv_solid_is_plain(const hv_solid *solid);
HV_API void hv_solid_bbox(const hv_solid *solid, double min[3], double max[3]);
HV_API int hv_solid_inside(const hv_solid *solid, const double p[3]);
/* The closed outlines at height z: a plain solid's are its leaf's (hv_leaf_slice, unchanged: a
 * model cut without its mesh gives the same bytes as with it); a tree's are its leaves' closed
 * loops combined node by node with Clipper's polygon Booleans (plugins/hovox-clipper.so;
 * nonzero fill; coordinates rounded to 1 nm), outers counter-clockwise, holes clockwise, nested
 * (hv_slice_from_loops; all of body 0; open polylines of a leaf take no part). Thread-safe.
 * Errors: those of hv_leaf_slice, HV_ERR_UNSUPPORTED (no Clipper plugin), HV_ERR_NOMEM. */
HV_API hv_status hv_solid_slice(const hv_solid *solid, double z, const hv_slice_options *options, hv_slice **out);

/* A plain solid over the caller's mesh as it is (not copied: the mesh must outlive the solid).
 * Errors: those of hv_slicer_create. */
HV_API hv_status hv_solid_from_mesh(const hv_mesh *mesh, const hv_progress *progress, hv_solid **out);

/* The solid a stage (layers, tray, contours, export) cuts for a model (issue 28: the model is the
 * one truth of its shape; a mesh is an override that must match):
 *   - no mesh: the model's record (hv_geometry_read, hv_solid_open);
 *   - a mesh, and a model without a record (or none): the mesh (hv_solid_from_mesh);
 *   - both: the mesh must be the one the record holds (one mesh leaf whose placed mesh has the
 *     same vertices, facets and bodies); it is then cut as given.
 * `stage` ("layers"), `model_name` and `mesh_name` name them in messages (NULL: generic words).
 * The mesh is borrowed. Errors: HV_ERR_INVALID ("layers: holed.vdb records no geometry ...: give
 * its mesh", neither given), HV_ERR_BAD_INPUT ("layers: plate.stl differs from the shape the model
 * records (a Boolean of plate.stl, rod.stl): leave the mesh out to cut it"; a damaged record, the
 * message prefixed with the stage: the caller names the model, as for its other errors), those
 * of hv_solid_open. */
HV_API hv_status hv_solid_for_model(const hv_volume *model, const hv_mesh *mesh, const char *stage,
                                    const char *model_name, const char *mesh_name, const hv_progress *progress,
                                    hv_solid **out);


/* hv_contours_write (hovox/slice.h) for the shape a model records (issue 28): a model voxelized
 * from one mesh gives exactly hv_contours_write of that mesh; a Boolean tree is cut on uniform layers
 * (adaptive layers need one mesh: HV_ERR_INVALID), each layer's loops those of hv_solid_slice
 * (body 0). `name` is the model's file. Errors: those of hv_contours_write and
 * hv_solid_for_model (a model that records no shape: HV_ERR_INVALID). */
HV_API hv_status hv_contours_write_model(const hv_volume *model, const hv_contours_options *o, const char *name,
                                         hv_contours_layer_fn layer, void *user, const hv_progress *progress,
                                         hv_contours_summary *summary);

#ifdef __cplusplus
}
#endif
#endif
