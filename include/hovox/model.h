/* hovox/model.h - models from any file: the one model loader, which picks the reader by the file's
 * content. A model is a volume (hovox/volume.h) with its documents in metadata: occupancy, the
 * material fractions and their table, the grading definition, the regions of an assembly. */
#ifndef HOVOX_MODEL_H
#define HOVOX_MODEL_H

#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Load a model: an OpenVDB file (hv_volume_load), or a 3MF package with the Volumetric extension
 * (a ZIP archive; hv_3mf_load, hovox/threemf.h), told apart by their first bytes. Errors: those of
 * the reader; HV_ERR_IO (missing, unreadable, a directory), HV_ERR_BAD_INPUT (neither format:
 * "not an OpenVDB file (bad magic number)"; a mesh file, hv_mesh_sniff's, "a mesh, not a model").
 * On success free *out with hv_volume_destroy. */
HV_API hv_status hv_model_load(const char *path, hv_volume **out);

/* 1 when `path` holds a mesh rather than a model: a 3MF package without the Volumetric extension,
 * or a file that is not an OpenVDB file and that hv_mesh_sniff takes for a mesh; else 0 (also for
 * a missing file). A front end whose model load failed names its mesh loader when this says 1. */
HV_API int hv_model_file_is_mesh(const char *path);

/* hv_model_load with the caller's colour options (a tray's or `layers`' --icc, --intent, --resins;
 * NULL: the defaults) for a 3MF package's colour without a composite (hv_3mf_load_colour); an
 * OpenVDB file, and a package whose composite gives the fractions, ignore them. Errors: those of
 * hv_model_load and of hv_colour_map_create (the profile, the resins). */
struct hv_colour_options;
HV_API hv_status hv_model_load_colour(const char *path, const struct hv_colour_options *colour, hv_volume **out);

/* hv_model_load taking only the grids `names` selects from an OpenVDB file (hv_volume_load_grids); a
 * 3MF package is read whole. Errors: those of hv_model_load, HV_ERR_INVALID (n < 0,
 * an empty or NULL name). */
HV_API hv_status hv_model_load_grids(const char *path, const char *const *names, int n, hv_volume **out);

/* Check a graded model's grids against each other (hv_model_load does it on every load): every
 * voxel of the occupancy has fractions that are finite, in [0, 1] and sum to 1 (within the 2^-12
 * per material that 16-bit storage explains), and no voxel outside the occupancy holds a
 * fraction. A model without occupancy or materials passes. Errors: HV_ERR_BAD_INPUT naming the
 * model, the first bad voxel (index and world coordinates) and the value. */
HV_API hv_status hv_model_check(const hv_volume *vol);

#ifdef __cplusplus
}
#endif
#endif
