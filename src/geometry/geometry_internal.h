/* src/geometry/geometry_internal.h - the leaf interface's table of kinds (hovox/solid.h): what a
 * module implements to make a kind of leaf cut by every stage. A kind's module fills one
 * hv_leaf_ops and leaf.c's table points at it (FIELD_ISO: the scanned-volume module). */
#ifndef HOVOX_GEOMETRY_INTERNAL_H
#define HOVOX_GEOMETRY_INTERNAL_H

#include "hovox/solid.h"

typedef struct hv_leaf_ops {
    hv_leaf_kind kind;
    /* Unpack leaf i of g into *state (g may be destroyed afterwards): its data, placed by its
     * transform. Errors as hv_leaf_open. */
    hv_status (*open)(const hv_geometry *g, size_t i, const hv_progress *progress, void **state);
    void (*close)(void *state);
    void (*bbox)(const void *state, double min[3], double max[3]);
    /* Closed loops at z, outers counter-clockwise and holes clockwise (hv_slice_from_loops makes
     * an hv_slice of loops made by hand). */
    hv_status (*slice)(const void *state, double z, const hv_slice_options *options, hv_slice **out);
    /* 1 inside, 0 outside; NULL: inside the outline at p's height. */
    int (*inside)(const void *state, const double p[3]);
} hv_leaf_ops;

extern const hv_leaf_ops hv_leaf_mesh_ops;
extern const hv_leaf_ops hv_leaf_field_ops; /* FIELD_ISO: field_leaf.c */

/* A MESH leaf over the caller's mesh (not copied: it must outlive the leaf), placed as it is. */
hv_status hv_leaf_wrap_mesh(const hv_mesh *mesh, const hv_progress *progress, hv_leaf **out);

/* 1 when (x, y) lies inside the closed loops of `slice` by the nonzero winding rule. */
int hv_slice_point_inside(const hv_slice *slice, double x, double y);

#endif
