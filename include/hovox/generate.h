/* hovox/generate.h - parametric closed meshes: analytic test shapes (sphere, box, box with a
 * through hole, torus, cylinder), the bench input (tube around a torus knot) and Wu's
 * sample parts (shaft, spur/helical gear with a bore). All outputs are closed, 2-manifold,
 * consistently oriented (outward normals), in millimetres. */
#ifndef HOVOX_GENERATE_H
#define HOVOX_GENERATE_H

#include "hovox/mesh.h"
#include "hovox/options.h"

#ifdef __cplusplus
extern "C" {
#endif

/* UV sphere: `segments` around z (>= 3), `rings` from pole to pole (>= 2).
 * Errors: HV_ERR_INVALID (radius <= 0, counts out of range), HV_ERR_NOMEM. */
HV_API hv_status hv_generate_sphere(const double center[3], double radius, int segments,
                                    int rings, hv_mesh **out);

/* Axis-aligned box [lo, hi]. */
HV_API hv_status hv_generate_box(const double lo[3], const double hi[3], hv_mesh **out);

/* Box [lo, hi] with a cylindrical through hole along z, centred in x and y, of radius
 * `hole_radius` (less than half the smaller side), polygon with `segments` (a multiple of 8,
 * >= 8) vertices. */
HV_API hv_status hv_generate_box_with_hole(const double lo[3], const double hi[3],
                                           double hole_radius, int segments, hv_mesh **out);

/* Torus around the z axis through `center`: major radius R, minor radius r < R. */
HV_API hv_status hv_generate_torus(const double center[3], double R, double r, int segments_u,
                                   int segments_v, hv_mesh **out);

/* Cylinder along axis 0, 1 or 2 starting at `base`, of `length` and `radius`. */
HV_API hv_status hv_generate_cylinder(const double base[3], int axis, double length,
                                      double radius, int segments, hv_mesh **out);

/* Tube of radius `tube` around the (p,q) torus knot of radii R, r (p, q coprime), with
 * `segments_u` samples along the knot and `segments_v` around the tube: 2*u*v facets. */
HV_API hv_status hv_generate_torus_knot(int p, int q, double R, double r, double tube,
                                        int segments_u, int segments_v, hv_mesh **out);

/* Gear with a bore, axis z, bottom at z = 0: `teeth` trapezoidal teeth between root radius
 * and tip radius, bore radius (0 for none, else < root radius), height, and a helix twist
 * (radians of rotation from bottom to top; 0 for a spur gear). `segments_per_tooth` (>= 8)
 * angular samples per tooth, `layers` (>= 1) slices in z. */
HV_API hv_status hv_generate_gear(int teeth, double root_radius, double tip_radius,
                                  double bore_radius, double height, double twist,
                                  int segments_per_tooth, int layers, hv_mesh **out);

/* ==== shapes by name ========================================================================
 *
 * Every shape above by name, with its parameters as an option set (hovox/options.h), so the
 * CLI (`hovox generate SHAPE key=value`), Lua (hovox.generate.SHAPE{...}) and job files read
 * the same keys, defaults and ranges. Shapes: sphere (center or cx, cy, cz; radius, segments,
 * rings), box (min; max, or size or sx, sy, sz from min; hole, segments), holed-box (a box
 * with other defaults), torus (center, R, r, segments, rings), cylinder (base, axis, length,
 * radius, segments), knot (facets, p, q, R, r, tube, segments_around), gear (teeth, root, tip,
 * bore, height, twist, segments, layers). */
typedef struct hv_shape_params {
    double center[3], base[3], min[3], max[3], size[3]; /* size 0: use max */
    double radius, hole, R, r, length, root, tip, bore, height, twist, tube, facets;
    int segments, rings, axis, teeth, layers, p, q, segments_around;
} hv_shape_params;

/* Number of shapes; index of a shape by name (-1: none, the message "unknown shape 'x' (shapes:
 * sphere, box, ...)" recorded); name and a one-line description. */
HV_API int hv_shape_count(void);
HV_API int hv_shape_find(const char *name);
HV_API const char *hv_shape_name(int shape);
HV_API const char *hv_shape_about(int shape);
/* The shape's parameters (init gives its defaults). Static data; NULL for a bad index. */
HV_API const hv_option_set *hv_shape_option_set(int shape);
/* Build shape `shape` from params. Errors: HV_ERR_INVALID (a parameter out of its domain,
 * named; the shape's own constraints, e.g. r < R), HV_ERR_NOMEM. */
HV_API hv_status hv_generate_shape(int shape, const hv_shape_params *params, hv_mesh **out);

#ifdef __cplusplus
}
#endif
#endif
