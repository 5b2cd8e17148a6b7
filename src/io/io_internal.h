/* src/io/io_internal.h - what the readers of the formats wing share: the last step of every mesh
 * reader. (Name tables, quotes for messages and file stems are in core/internal.h.) Internal. */
#ifndef HOVOX_IO_INTERNAL_H
#define HOVOX_IO_INTERNAL_H

#include "core/internal.h"
#include "mesh/mesh_internal.h"

/* ---- what the mesh readers share (mesh_read.c) ------------------------------------------ */

/* A reader's last step: the soup (9 floats per facet, finite) becomes a mesh named `name`,
 * with the bodies given (consecutive facet ranges in order; none: one body named after the
 * file) and the materials (facet_mat may be NULL). */
hv_status hv_mesh_build(const float *soup, size_t nf, const char *name, hv_mesh_format format,
                        const hv_mesh_body *bodies, size_t nbodies, const hv_mesh_material *mats,
                        size_t nmats, const int32_t *facet_mat, hv_mesh **out);

#endif
