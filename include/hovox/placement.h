/* hovox/placement.h - where a mesh goes: its file's unit, the up axis, a scale, rotations about
 * any axis and a translation, turned into the one affine map hv_mesh_transform applies (3x4,
 * row-major). The same options serve the CLI (--unit, --up, --scale, --rotate, --translate), job
 * files and Lua (unit, up, scale, rotate, translate). */
#ifndef HOVOX_PLACEMENT_H
#define HOVOX_PLACEMENT_H

#include <stddef.h>

#include "hovox/core.h"
#include "hovox/mesh.h"
#include "hovox/options.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Most rotations one placement composes. */
#define HV_PLACEMENT_MAX_ROTATIONS 16

typedef struct hv_placement_rotation {
    double axis[3]; /* not normalised; never zero */
    double degrees; /* right-handed about the axis */
} hv_placement_rotation;

/* A placement, applied in this order whatever order the options were given in:
 *   1. unit: coordinates in the file's unit become millimetres (formats without units: STL,
 *      OBJ, PLY; a 3MF states its own unit and refuses --unit);
 *   2. up = y: a Y-up file turned Z-up (the same as rotate x:90: y becomes z, z becomes -y);
 *   3. scale, about the origin;
 *   4. the rotations, about axes through the origin, in the order given;
 *   5. translate (mm).
 * Zero-initialised or hv_placement_init: the identity. */
typedef struct hv_placement {
    double unit;      /* mm per file unit; 0: not given (mm) */
    int up;           /* 'z' (or 0: not given) or 'y' */
    double scale[3];  /* 0,0,0: not given */
    int nrotate;
    hv_placement_rotation rotate[HV_PLACEMENT_MAX_ROTATIONS];
    double translate[3];
} hv_placement;

HV_API void hv_placement_init(hv_placement *p);
/* 1 when any part of the placement was given (the map may still be the identity). */
HV_API int hv_placement_given(const hv_placement *p);
/* The 3x4 row-major matrix of the placement (x' = A x + t as hv_mesh_transform takes it). Exact
 * for quarter turns about x, y or z (cos and sin are 0 or +-1, not rounded). Errors:
 * HV_ERR_INVALID (a singular map: a scale of 0). */
HV_API hv_status hv_placement_matrix(const hv_placement *p, double matrix[12]);
/* The placement as the text its options read back ("unit m, up y, rotate z:30, translate
 * 1,2,3"; "" when nothing was given), into buf; returns buf. */
HV_API const char *hv_placement_describe(const hv_placement *p, char *buf, size_t size);

/* A new mesh: `mesh` placed (a copy when nothing was given), freed with hv_mesh_destroy. Errors:
 * HV_ERR_INVALID ({unit} given for a 3MF, which states its own unit; those of hv_mesh_transform),
 * HV_ERR_NOMEM. */
HV_API hv_status hv_placement_transform(const hv_placement *p, const hv_mesh *mesh, hv_mesh **out);
/* Place a mesh: *mesh is replaced by its transformed copy (the old one destroyed) unless nothing
 * was given. Errors: HV_ERR_INVALID ({unit} given for a 3MF, which states its own unit; those
 * of hv_mesh_transform), HV_ERR_NOMEM; *mesh is unchanged on failure. */
HV_API hv_status hv_placement_apply(const hv_placement *p, hv_mesh **mesh);

/* A warning for a mesh whose size suggests a wrong unit: its largest side is below 1 mm, or it
 * fits no orientation of the build volume `build` (x, y, z in mm; NULL: no upper bound). The
 * message names the mesh, its size and the likely unit with the option that gives it
 * ("bunny.stl is 0.155 x 0.153 x 0.12 mm, smaller than 1 mm: if its unit is metres, {unit} m
 * makes it 155 mm across"; for a 3MF, which states its unit, a scale from it: "if its numbers
 * are metres (the package says millimeter), {scale} 1000 makes it 155 mm across"). Returns 1 with the message recorded as the calling thread's last
 * message (as hv_error_option records it: hv_last_error, hv_error_spell), else 0. */
HV_API int hv_placement_size_warning(const hv_mesh *mesh, const double build[3]);

/* mm per unit of a unit name (mm, cm, m, in, ft, um, and the 3MF names millimeter, centimeter,
 * meter, inch, foot, micron). Errors: HV_ERR_INVALID listing the names. */
HV_API hv_status hv_placement_unit_parse(const char *name, double *mm);

/* The options as a set over an hv_placement struct: unit (a name), up (y|z), scale (S or
 * SX,SY,SZ), rotate (repeatable: "x:90", "y:-30", "30@1,1,0" = 30 degrees about (1,1,0)),
 * translate (X,Y,Z mm). */
HV_API const hv_option_set *hv_placement_option_set(void);
/* The parser of those options, for a front end that embeds them in its own set: the option's
 * offset is that of an hv_placement in the front end's struct (see HV_PLACEMENT_OPTIONS). */
HV_API hv_status hv_placement_option_parse(const hv_option *opt, void *opts, const hv_opt_value *value);

/* The five option descriptors over the hv_placement member `member` of struct `type`, under the
 * help section "Placement". */
#define HV_PLACEMENT_OPTION_(type, member, key_, meta_, flags_, help_, section_)                               \
    {.key = key_, .kind = HV_OPT_CUSTOM, .flags = flags_, .offset = offsetof(type, member), .meta = meta_,      \
     .help = help_, .section = section_, .parse = hv_placement_option_parse}
#define HV_PLACEMENT_OPTIONS(type, member)                                                                       \
    HV_PLACEMENT_OPTION_(type, member, "unit", "mm|cm|m|in", 0,                                                  \
                         "the unit of a file without one (STL, OBJ, PLY): its coordinates become mm "            \
                         "(default mm; also um, ft)", "Placement (in this order)"),                              \
    HV_PLACEMENT_OPTION_(type, member, "up", "y|z", 0,                                                           \
                         "y: the file is Y-up and is turned Z-up (rotate x:90); default z", NULL),               \
    HV_PLACEMENT_OPTION_(type, member, "scale", "S|SX,SY,SZ", 0, "scale about the origin", NULL),                \
    HV_PLACEMENT_OPTION_(type, member, "rotate", "AXIS:DEG|DEG@X,Y,Z", HV_OPT_REPEAT,                            \
                         "turn about x, y or z (x:90) or about the axis X,Y,Z through the origin (30@1,1,0), "   \
                         "degrees right-handed; repeatable, composed in the order given", NULL),                \
    HV_PLACEMENT_OPTION_(type, member, "translate", "X,Y,Z", 0, "move by X,Y,Z mm, last", NULL)

#ifdef __cplusplus
}
#endif
#endif
