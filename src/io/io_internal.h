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

/* The same from facets over points (3 indices per facet, each below npts): the mesh is the one
 * hv_mesh_build makes of the soup they expand to (hv_mesh_from_indexed), welded faster. */
hv_status hv_mesh_build_indexed(const float *xyz, size_t npts, const uint32_t *tri, size_t nf, const char *name,
                                hv_mesh_format format, const hv_mesh_body *bodies, size_t nbodies,
                                const hv_mesh_material *mats, size_t nmats, const int32_t *facet_mat, hv_mesh **out);

/* ---- Wavefront material libraries (mtl.c) ------------------------------------------------ */

typedef struct hv_mtl_material {
    char *name;
    char *lib_path;     /* the library file it came from (hv_mtl_parse's name) */
    size_t line;        /* of its newmtl */
    int has_kd;
    float kd[3];        /* Kd, read as sRGB-encoded values in [0, 1] */
    float alpha;        /* d, or 1 - Tr; 1 when neither is given */
    char *map;          /* map_Kd's file as written, or NULL */
    size_t map_line;
    hv_tile tile;       /* -clamp on: HV_TILE_CLAMP; else HV_TILE_WRAP (the MTL default) */
    float offset[2], scale[2]; /* -o, -s: u' = u * scale + offset */
} hv_mtl_material;

typedef struct hv_mtl {
    hv_mtl_material *m;
    size_t n, cap;
} hv_mtl;

/* Append the materials of one .mtl file held in memory (`name` in messages). Errors:
 * HV_ERR_BAD_INPUT (a value not a finite number or out of range, a statement before newmtl, an
 * unknown map_Kd option, Kd spectral/xyz), HV_ERR_NOMEM. Free with hv_mtl_free. */
hv_status hv_mtl_parse(const void *data, size_t size, const char *name, hv_mtl *out);
void hv_mtl_free(hv_mtl *t);
/* The first material of that name, or NULL. */
const hv_mtl_material *hv_mtl_find(const hv_mtl *t, const char *name);

/* The OBJ reader; read_files: `mtllib` files and their textures are read, relative to the
 * directory of `name` (hv_mesh_load), else skipped (hv_mesh_parse_obj, from memory). */
hv_status hv_obj_parse(const void *data, size_t size, const char *name, int read_files, hv_mesh **out);

/* Wavefront text (OBJ and its MTL libraries): the next blank-separated token of [*p, e) into
 * [*ts, *te); 0 at the end of the statement or at a comment ('#'). */
static inline int hv_io_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
/* Per-vertex colours (0xRRGGBBAA) as the corner colours of the mesh's facets: corner c of
 * triangle t is vertex tri[3t+c], and triangle t is facet where[t] (NULL: facet t). PLY and
 * OBJ vertex colours. */
hv_status hv_io_vertex_colours(hv_mesh *m, const uint32_t *vcol, const uint32_t *tri, size_t nt, const size_t *where);

static inline int hv_io_next_token(const char **p, const char *e, const char **ts, const char **te)
{
    const char *s = *p;
    while (s < e && hv_io_blank(*s)) ++s;
    if (s == e || *s == '#') {
        *p = e;
        return 0;
    }
    *ts = s;
    while (s < e && !hv_io_blank(*s)) ++s;
    *te = s;
    *p = s;
    return 1;
}

#endif
