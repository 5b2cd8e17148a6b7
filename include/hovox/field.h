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
 * lower-envelope pass per axis, in double precision), multi-threaded over rows on
 * hv_threads() threads, deterministic. `out` (nx*ny*nz floats) is the only large buffer;
 * scratch is O(threads * max(nx, ny, nz)).
 * Errors: HV_ERR_INVALID (a dimension < 1, spacing not finite and > 0), HV_ERR_LIMIT (more than
 * 2^40 voxels), HV_ERR_NOMEM, HV_ERR_CANCELLED. */
HV_API hv_status hv_edt(const uint8_t *feature, const int64_t dims[3], const double spacing[3],
                        float *out, const hv_progress *progress);

/* Harmonic field: phi solves the Laplace equation on the domain voxels (domain[v] != 0) with
 * phi = 1 on voxels labelled 1, phi = 0 on voxels labelled 2 (Dirichlet; labels outside the
 * domain are ignored), and zero normal derivative across the domain boundary (the 7-point
 * stencil weighted by 1/spacing^2 drops faces towards non-domain voxels). Solved by conjugate
 * gradients with a multigrid preconditioner until the residual drops by `tol` (e.g. 1e-6)
 * relative to the right-hand side, at most `max_iter` iterations. Domain voxels in components
 * that touch no label get phi = 0 and are counted in *floating (may be NULL); non-domain voxels
 * get 0. *iterations (may be NULL) receives the iterations used.
 * Errors: HV_ERR_INVALID (dims, spacing, no voxel labelled 1 or none labelled 2 in the
 * domain), HV_ERR_LIMIT (no convergence within max_iter: the message gives the residual
 * reached), HV_ERR_NOMEM, HV_ERR_CANCELLED. */
HV_API hv_status hv_harmonic(const uint8_t *domain, const uint8_t *label, const int64_t dims[3],
                             const double spacing[3], double tol, int max_iter, float *phi,
                             int *iterations, uint64_t *floating, const hv_progress *progress);

#ifdef __cplusplus
}
#endif
#endif
