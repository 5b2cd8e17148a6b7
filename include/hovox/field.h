/* hovox/field.h - distance and potential fields on dense voxel grids: the exact Euclidean
 * distance transform (Felzenszwalb-Huttenlocher 2012) and the harmonic field between two
 * marked regions (Laplace equation, from the non-manifold multi-material meshes seed).
 * Grids are nx*ny*nz voxels, voxel (i,j,k) at index ((i*ny)+j)*nz+k (z fastest, as in the
 * volume store's leaves), with physical spacing (sx, sy, sz) that may differ per axis. */
#ifndef HOVOX_FIELD_H
#define HOVOX_FIELD_H

#include "hovox/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Exact Euclidean distance transform: out[v] = distance, in physical units, from the centre
 * of voxel v to the centre of the nearest voxel f with feature[f] != 0 (0 on feature voxels).
 * When no voxel is a feature, every distance is INFINITY. Linear time, separable (one 1-D
 * lower-envelope pass per axis, in double precision within a row; squared distances are kept
 * in `out` as float between passes), so the result is the exact distance within a relative
 * 2e-7. Multi-threaded over rows on hv_threads() threads; the bytes written do not depend on
 * the thread count. `out` (nx*ny*nz floats, caller-owned) is the only large buffer; scratch
 * is O(threads * max(nx, ny, nz)). On any error the contents of `out` are unspecified.
 * Errors: HV_ERR_INVALID (a NULL pointer, a dimension < 1, a spacing not finite and > 0, or
 * squared distances outside the float range: spacing^2 < FLT_MIN or a grid diagonal whose
 * square overflows), HV_ERR_LIMIT (more than 2^40 voxels), HV_ERR_NOMEM, HV_ERR_CANCELLED. */
HV_API hv_status hv_edt(const uint8_t *feature, const int64_t dims[3], const double spacing[3],
                        float *out, const hv_progress *progress);

/* Harmonic field: phi solves the Laplace equation on the domain voxels (domain[v] != 0) with
 * phi = 1 on voxels labelled 1, phi = 0 on voxels labelled 2 (Dirichlet; labels outside the
 * domain are ignored, other label values mean "unlabelled"), and zero normal derivative
 * across the domain boundary (the 7-point stencil weighted by 1/spacing^2 drops faces towards
 * non-domain voxels). Solved by conjugate gradients with a geometric multigrid preconditioner
 * until the residual drops by `tol` (in (0, 1), e.g. 1e-6) relative to the right-hand side,
 * at most `max_iter` (>= 1) iterations. Domain voxels in components (6-connected) that touch
 * no label get phi = 0 and are counted in *floating (may be NULL); non-domain voxels get 0;
 * phi is clamped to [0, 1] (the exact solution obeys this maximum principle).
 * *iterations (may be NULL) receives the CG iterations used. Multi-threaded on hv_threads()
 * threads; the bytes written do not depend on the thread count. Memory: about 90 bytes per
 * voxel of the grid padded by one voxel on every side. Progress stages: "harmonic: setup",
 * then "harmonic" once per iteration (fraction = log(residual) / log(tol)).
 * On HV_ERR_LIMIT from non-convergence phi holds the last iterate; on other errors its
 * contents are unspecified.
 * Errors: HV_ERR_INVALID (a NULL pointer, dims, spacing (finite, > 0, 1/spacing^2 a normal
 * float), tol, max_iter, no domain voxel labelled 1 or none labelled 2), HV_ERR_LIMIT (more
 * than 2^40 voxels; no convergence within max_iter: the message gives the residual reached),
 * HV_ERR_NOMEM, HV_ERR_CANCELLED. */
HV_API hv_status hv_harmonic(const uint8_t *domain, const uint8_t *label, const int64_t dims[3],
                             const double spacing[3], double tol, int max_iter, float *phi,
                             int *iterations, uint64_t *floating, const hv_progress *progress);

#ifdef __cplusplus
}
#endif
#endif
