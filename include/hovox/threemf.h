/* hovox/threemf.h - 3MF packages with the Volumetric extension (3MF Consortium, "3MF Volumetric &
 * Implicit Extensions" 0.8) read back as graded models. Writing is an export format
 * (hovox/export.h, HV_EXPORT_3MF); hv_volume_load reads a .3mf through hv_3mf_load. */
#ifndef HOVOX_THREEMF_H
#define HOVOX_THREEMF_H

#include "hovox/mesh.h"
#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Read a 3MF package holding one object (one build item, translated at most) whose mesh carries
 * <v:volumedata> with a <v:composite> (the materials and their fractions) or a <v:color>. The
 * result is a graded model as hovox makes them:
 *   - the lattice of the image stacks: voxel (i, j, k) is column i, row (rows - 1 - j), sheet k of
 *     the stacks (continued beyond them by each function's tile styles), voxel size and origin
 *     from the <v:materialmapping> transform (all mappings must give the same lattice: an axis-
 *     aligned scale with positive diagonal and a translation), millimetres (the model's unit is
 *     converted);
 *   - bool grid "occupancy": the voxels whose centre lies inside the mesh (src/voxel's centre
 *     test: parity along x, y, z, the winding number where they disagree; for the exact voxel
 *     boundaries hovox writes, exactly the exported voxels);
 *   - float grids "material.<name>" per base material: each mapping's channel (value x valuescale
 *     + valueoffset, clamped to [0, 1]) divided by their sum at the voxel centre (spec 5.2.2; where
 *     the sum is below 1e-5 the first material gets 1);
 *   - metadata "hovox.materials.json": the base materials' names (characters hovox does not allow
 *     in a name become '_'; duplicates get a suffix) and display colours, or the table the file
 *     carries in its hovox:materials metadata when that names the same materials (properties
 *     included);
 *   - with a <v:color> (issue 29; its function a functionfromimage3d, its channel the vector
 *     "color"): float grids "colour.r", "colour.g", "colour.b" and "colour.mask", as a painted model
 *     holds them (hovox/colour.h): at each voxel centre the function sampled through the color's
 *     own transform (any affine one, on any lattice; filter, tile styles, valuescale and
 *     valueoffset as spec 2.2 says), each channel truncated to [0, 1] and turned from linear sRGB
 *     (spec 5.2.1) into the sRGB the grids hold; mask 1 everywhere, or where hovox's property
 *     hovox:colour.mask (a scalar output) is above one half, the colour 0 elsewhere; with hovox's
 *     hovox:colour metadata, "hovox.colour.json" (the profile and resins it was painted with);
 *   - with a <v:color> and no <v:composite> (a colour printer's package): the colour's stack gives
 *     the lattice when its transform is an axis-aligned scale with positive diagonal and a
 *     translation; with any other affine transform (turned, sheared, mirrored, or a picture
 *     extruded through the part) the lattice is axis-aligned cubic voxels over the mesh's box, as
 *     fine as the image's finest step (one image voxel across its planes along each image axis),
 *     each centre sampled through the colour's transform. The model is printed in the six colour
 *     resins of the default colour map (hv_colour_options_init; hv_3mf_load_colour: the caller's):
 *     each voxel's fractions those of its colour rounded to 8-bit sRGB (hv_colour_map_fractions;
 *     the white resin where the mask says no colour), "hovox.colour.json" recording that map.
 * Image sheets are PNGs of any layout and depth (grey, grey+alpha, RGB, RGBA, palette; 1 to 16
 * bits), all of a stack alike in size. Other <v:property> elements in hovox's namespace are
 * derived arrays and skipped; others and elements of other extensions are ignored unless a
 * property says required="true". Refused as unsupported (HV_ERR_UNSUPPORTED, naming the element):
 * <v:levelset>, implicit or private functions, components, several build items, rotated or scaled
 * transforms, an object without volume data, a required extension other than the volumetric one.
 * The input is hostile: sizes and counts are bounded before anything is allocated (the memory
 * budget hv_memory_budget(0)); every id and reference is checked.
 *
 * `mesh` (may be NULL) receives the object's mesh in millimetres (build item translation applied),
 * e.g. for slicing. Errors: HV_ERR_IO (cannot open), HV_ERR_BAD_INPUT ("part.3mf: 3D/3dmodel.model:
 * line 12: <v:imagestack>: rowcount 'x' is not a positive integer", "part.3mf: not a ZIP archive",
 * a missing part or referenced image, a PNG whose size differs from its stack's, a <v:color>
 * naming no function or an output it lacks, each with the element's line and column), HV_ERR_UNSUPPORTED,
 * HV_ERR_LIMIT (memory budget, image sizes beyond the spec's limits), HV_ERR_NOMEM,
 * HV_ERR_CANCELLED. On success free *vol with hv_volume_destroy and *mesh with hv_mesh_destroy. */
HV_API hv_status hv_3mf_load(const char *path, hv_volume **vol, hv_mesh **mesh);

/* hv_3mf_load with the caller's colour options (`layers --icc --intent --resins`, a tray's) for a
 * colour without a composite: its six resins' fractions through that map (NULL: the defaults); a
 * package whose composite gives the fractions ignores them. Errors: also those of
 * hv_colour_map_create (an unreadable or non-CMYK profile, resins that are not six names). */
struct hv_colour_options;
HV_API hv_status hv_3mf_load_colour(const char *path, const struct hv_colour_options *colour, hv_volume **vol,
                                    hv_mesh **mesh);

/* 1 when the model's material fractions were made on load from its colour through the caller's
 * colour map (a package's <v:color> without a <v:composite>, hv_3mf_load_colour, hv_model_load_colour;
 * its hovox.colour.json says "source": "3MF <v:color>"), else 0: a package whose composite gives the
 * fractions, an OpenVDB model. A front end whose colour options had no effect says so. */
HV_API int hv_3mf_colour_mapped(const hv_volume *vol);

/* The same from a package in memory; `name` names it in messages. */
HV_API hv_status hv_3mf_parse(const void *data, size_t size, const char *name, hv_volume **vol, hv_mesh **mesh);

/* 1 when the file starts like a ZIP archive (a 3MF package), else 0. */
HV_API int hv_3mf_sniff(const char *path);

/* 1 when the file is a 3MF package whose first object uses the Volumetric extension (a graded
 * model for hv_3mf_load), else 0 (a mesh package for hv_mesh_load, or not a package at all).
 * Reads the model part only up to its first <v:volumedata> or <object>. */
HV_API int hv_3mf_is_volumetric(const char *path);

#ifdef __cplusplus
}
#endif
#endif
