/* src/io/3mf/threemf_internal.h - what the 3MF package module (package.c), the mesh reader, the
 * Volumetric writer and reader and the exact voxel boundary mesh (boundary.c) share: namespaces,
 * OPC names. Internal. */
#ifndef HOVOX_THREEMF_INTERNAL_H
#define HOVOX_THREEMF_INTERNAL_H

#include <math.h>

#include "core/internal.h"
#include "hovox/threemf.h"
#include "hovox/volume.h"

/* XML namespaces (3MF Core 1.3; Volumetric and Implicit extensions 0.8, Part I "Document
 * Conventions"; Materials 1.2) and hovox's own, for metadata and property names. */
#define TMF_NS_CORE "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
#define TMF_NS_MATERIAL "http://schemas.microsoft.com/3dmanufacturing/material/2015/02"
#define TMF_NS_VOLUMETRIC "http://schemas.3mf.io/3dmanufacturing/volumetric/2022/01"
#define TMF_NS_IMPLICIT "http://schemas.3mf.io/3dmanufacturing/implicit/2023/12"
#define TMF_NS_HOVOX "urn:hovox:3mf:2025"
#define TMF_NS_BEAM "http://schemas.microsoft.com/3dmanufacturing/beamlattice/2017/02"
#define TMF_NS_SLICE "http://schemas.microsoft.com/3dmanufacturing/slice/2015/07"
#define TMF_NS_PRODUCTION "http://schemas.microsoft.com/3dmanufacturing/production/2015/06"
#define TMF_NS_SECURE "http://schemas.microsoft.com/3dmanufacturing/securecontent/2019/04"

/* Open Packaging Conventions: content types, relationships. */
#define TMF_NS_CONTENT_TYPES "http://schemas.openxmlformats.org/package/2006/content-types"
#define TMF_NS_RELATIONSHIPS "http://schemas.openxmlformats.org/package/2006/relationships"
#define TMF_REL_MODEL "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"
#define TMF_REL_TEXTURE "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dtexture"
#define TMF_CT_MODEL "application/vnd.ms-package.3dmanufacturing-3dmodel+xml"
#define TMF_CT_RELATIONSHIPS "application/vnd.openxmlformats-package.relationships+xml"
#define TMF_CT_PNG "image/png"

/* sRGB's transfer function and its inverse (IEC 61966-2-1, as 3MF Materials 1.2 section 1.2
 * gives them), for c in [0, 1]: a <v:color> is linear sRGB (Volumetric 5.2.1), while a painted
 * model's colour grids hold the sRGB asked for. */
static inline double tmf_srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }
static inline double tmf_linear_to_srgb(double c) { return c <= 0.0031308 ? c * 12.92 : 1.055 * pow(c, 1 / 2.4) - 0.055; }

/* libxml2 reports some errors (encodings, I/O) through its generic handler, which prints to
 * stderr: the library never prints, so readers and writers run between these two calls (the
 * handler is per thread in libxml2). */
typedef struct tmf_xml_quiet {
    void *ctx;
    void (*fn)(void *, const char *, ...);
} tmf_xml_quiet;
void tmf_xml_quiet_begin(tmf_xml_quiet *q);
void tmf_xml_quiet_end(const tmf_xml_quiet *q);

/* ---- a slicer's project config (slicer_config.c) -------------------------------------------
 * Slicers type the volumes of an object in a config of their own: PrusaSlicer keeps them all in
 * the object's one <mesh> and lists them in Metadata/Slic3r_PE_model.config, each a range of the
 * object's triangles (firstid..lastid); Bambu Studio and OrcaSlicer make each a mesh object that a
 * component of the object places, and list them in Metadata/model_settings.config (<part id> the
 * component's objectid). Only model parts are printed; a negative volume is cut from them,
 * modifiers, support blockers and enforcers are settings regions. The configs also name the
 * objects and parts (the model often does not). */
enum { TMF_VOLUME_PART = 0, TMF_VOLUME_NEGATIVE, TMF_VOLUME_MODIFIER, TMF_VOLUME_BLOCKER, TMF_VOLUME_ENFORCER };
typedef struct tmf_slicer_volume {
    uint64_t object;      /* the object's id in the root model */
    uint64_t part;        /* Bambu: the id of the object its component places; 0: PrusaSlicer's range */
    uint64_t first, last; /* PrusaSlicer: the object's triangles first..last */
    int kind;             /* TMF_VOLUME_* */
    char name[36];        /* (a 16 MiB config holds at most 400,000 volumes: 30 MB) */
} tmf_slicer_volume;
typedef struct tmf_slicer_config {
    const char *part, *slicer; /* the config read ("Metadata/Slic3r_PE_model.config"), its slicer; NULL: none */
    tmf_slicer_volume *vols;
    size_t nvols, cap;
    struct tmf_slicer_name {
        uint64_t object, part; /* part 0: the object's own name */
        char name[128];
    } *names;
    size_t nnames, ncap;
    char unread[512]; /* why a config the package holds was not read ("": read, or none) */
} tmf_slicer_config;
struct tmf_pkg;
/* The package's slicer config, if it holds one (none: c->part NULL). A config that is not
 * well-formed is not read (the model is read as the specification says) and `unread` says why.
 * Errors: HV_ERR_NOMEM only. Free with tmf_slicer_config_free. */
hv_status tmf_slicer_config_read(struct tmf_pkg *pk, tmf_slicer_config *c);
void tmf_slicer_config_free(tmf_slicer_config *c);
const char *tmf_slicer_volume_kind(int kind); /* "modifier" */

/* ---- the exact voxel boundary (boundary.c) --------------------------------------------------
 * The faces between occupied and unoccupied voxels, two triangles each, wound outward (counter-
 * clockwise seen from outside). Vertices sit on voxel corners: corner (a, b, c) is the lowest
 * corner of voxel (a, b, c), at index coordinates (a - 1/2, b - 1/2, c - 1/2). A corner where
 * the surface touches itself (voxels meeting only along an edge or at the corner) gets one vertex
 * per sheet of surface through it (voxels meeting along an edge are apart there, unless they are
 * joined around both ends of the edge: see boundary.c), so every edge has exactly two triangles:
 * the mesh is a closed, oriented 2-manifold (checked on 8,300 random voxel sets). Vertices are numbered in the
 * order of first use, faces in leaf order, then in-leaf offset, then -x, +x, -y, +y, -z, +z: the
 * mesh depends only on the voxels. */
typedef struct tmf_boundary {
    size_t nv, nt;
    int32_t *corner; /* 3 per vertex */
    uint32_t *tri;   /* 3 per triangle */
} tmf_boundary;

/* Quads of the boundary of the voxels set in occ (8 words per leaf of vol, as ex_model's occ).
 * Multi-threaded. Errors: HV_ERR_CANCELLED. */
hv_status tmf_boundary_count(const hv_volume *vol, const uint64_t *occ, uint64_t *quads,
                             const hv_progress *progress);
/* Build the mesh (quads: tmf_boundary_count's result, sizes the arrays). Errors: HV_ERR_NOMEM,
 * HV_ERR_LIMIT (2^32 vertices or more), HV_ERR_CANCELLED. Free with tmf_boundary_free (also
 * after a failure). */
hv_status tmf_boundary_build(const hv_volume *vol, const uint64_t *occ, uint64_t quads, tmf_boundary *m,
                             const hv_progress *progress);
void tmf_boundary_free(tmf_boundary *m);
/* Bytes tmf_boundary_build needs at most for a boundary of `quads` quads. */
uint64_t tmf_boundary_bytes(uint64_t quads);

/* The most the Volumetric reader decodes of a colour slab's image sheets ahead, for its threads
 * (volumetric_read.c colour_slab; 1 GiB, and never past a quarter of the memory budget left);
 * past it one thread samples through a few sheets. The tests lower it to compare the two ways. */
extern uint64_t tmf_colour_sheets_max;

#endif
