/* hovox/colour.h - colour management for full-colour printing (issue 29): an sRGB colour (or one
 * in a picture's own ICC profile) turned into fractions of the printer's six colour resins
 * (cyan, magenta, yellow, black, white, clear) through an output ICC profile (LittleCMS), and
 * back into the colour those fractions print, for the manifest's dE2000. */
#ifndef HOVOX_COLOUR_H
#define HOVOX_COLOUR_H

#include "hovox/core.h"
#include "hovox/mesh.h"
#include "hovox/options.h"
#include "hovox/volume.h"
#include "hovox/voxelize.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The six colour slots, in this order everywhere (fractions, resin maps, manifests). */
enum { HV_COLOUR_C = 0, HV_COLOUR_M, HV_COLOUR_Y, HV_COLOUR_K, HV_COLOUR_W, HV_COLOUR_CLEAR, HV_COLOUR_SLOTS };

/* ICC rendering intents (ICC.1:2010 section 6.2.2; the values are the ICC's). */
typedef enum hv_intent {
    HV_INTENT_PERCEPTUAL = 0,
    HV_INTENT_RELATIVE = 1, /* relative colorimetric */
    HV_INTENT_SATURATION = 2,
    HV_INTENT_ABSOLUTE = 3  /* absolute colorimetric */
} hv_intent;

/* The output profile hovox uses without --icc: Ghostscript's default_cmyk.icc ("Artifex CMYK SWOP
 * Profile", Debian package libgs-common), a generic offset-press CMYK. A printer's own profile
 * (Stratasys supplies them for the J-series) gives truer colour. Static. */
HV_API const char *hv_colour_default_icc(void);

/* The resin of each slot on a Stratasys J750/J850: VeroCyan-V, VeroMagenta-V, VeroYellow-V,
 * VeroBlackPlus, VeroPureWhite, VeroClear. Static; slot < HV_COLOUR_SLOTS. */
HV_API const char *hv_colour_j750_resin(int slot);

/* "perceptual", "relative", "saturation", "absolute" (and back: 0, or -1 for another name). */
HV_API const char *hv_intent_name(hv_intent intent);
HV_API int hv_intent_parse(const char *name, hv_intent *out);

typedef struct hv_colour_options {
    const char *icc;    /* output profile file; NULL: hv_colour_default_icc() */
    hv_intent intent;   /* default HV_INTENT_PERCEPTUAL */
    const char *resins; /* "C,M,Y,K,W,CLEAR": six resin names, comma-separated; NULL: the J750's */
} hv_colour_options;

/* Defaults: the default profile, perceptual, the J750 resins. */
HV_API void hv_colour_options_init(hv_colour_options *opt);
/* The options as one table for the CLI (--icc, --intent, --resins), job files and Lua. Static. */
HV_API const hv_option_set *hv_colour_option_set(void);
/* An option of hv_colour_option_set (the same key) over an hv_colour_options member of another
 * options struct (its offset is the member's; see HV_COLOUR_OPTIONS): a tray's colour map. */
HV_API hv_status hv_colour_option_parse(const hv_option *opt, void *opts, const hv_opt_value *value);
#define HV_COLOUR_OPTION_(type, member, key_, meta_, flags_, help_, section_)                                    \
    {.key = key_, .kind = HV_OPT_CUSTOM, .flags = flags_, .offset = offsetof(type, member), .meta = meta_,      \
     .help = help_, .section = section_, .parse = hv_colour_option_parse}
#define HV_COLOUR_OPTIONS(type, member, section_)                                                                \
    HV_COLOUR_OPTION_(type, member, "icc", "FILE.icc", HV_OPT_IN_PATH,                                           \
                      "the printer's output ICC profile (CMYK) the parts' colours go through (default: "        \
                      "Ghostscript's default_cmyk.icc)", section_),                                             \
    HV_COLOUR_OPTION_(type, member, "intent", "INTENT", 0,                                                       \
                      "rendering intent: perceptual (default), relative, saturation or absolute", NULL),         \
    HV_COLOUR_OPTION_(type, member, "resins", "C,M,Y,K,W,CLEAR", 0,                                              \
                      "the resins that print cyan, magenta, yellow, black, white and clear (default the "       \
                      "J750's)", NULL)

/* How deep a part is painted when nothing says (mm): `voxelize --colour-depth`, a mesh sliced in
 * one step by `layers`, a tray's part. */
#define HV_COLOUR_DEPTH_DEFAULT 1.0

typedef struct hv_colour_map hv_colour_map;

/* A colour map: sRGB (LittleCMS's built-in sRGB) to the output profile's CMYK with the intent,
 * then to the six fractions:
 *   the ink coverages c, m, y, k in [0, 1] from the profile; with T = c + m + y + k, the colour's
 *   remaining lightness is white, W = max(0, 1 - T), and coverage beyond 100 % (a rich black) is
 *   scaled to fit (each ink / T, W = 0), so the colour part sums to 1; alpha a then scales the
 *   colour part and Clear = 1 - a.
 * Errors: HV_ERR_IO (the profile file cannot be read), HV_ERR_BAD_INPUT ("FILE: not an ICC
 * profile", "FILE: an RGB profile where a CMYK output profile is needed", another colour space
 * or class; an intent the profile cannot serve), HV_ERR_INVALID (an intent out of range, resins
 * that are not six non-empty names), HV_ERR_NOMEM. *out is freed with hv_colour_map_destroy. */
HV_API hv_status hv_colour_map_create(const hv_colour_options *opt, hv_colour_map **out);
HV_API void hv_colour_map_destroy(hv_colour_map *map);

/* The profile's file, its description ("Artifex CMYK SWOP Profile"), the intent, the resin of a
 * slot. Owned by the map. */
HV_API const char *hv_colour_map_icc(const hv_colour_map *map);
HV_API const char *hv_colour_map_description(const hv_colour_map *map);
HV_API hv_intent hv_colour_map_intent(const hv_colour_map *map);
HV_API const char *hv_colour_map_resin(const hv_colour_map *map, int slot);

/* The fractions (C, M, Y, K, W, Clear; each in [0, 1], summing to 1) of an sRGB colour with
 * straight alpha. Cached per distinct colour: safe to call from many threads at once. */
HV_API void hv_colour_map_fractions(hv_colour_map *map, const uint8_t rgba[4], float out[HV_COLOUR_SLOTS]);

/* An input profile for colours that are not sRGB (a texture's embedded profile): *id receives a
 * number for hv_colour_map_fractions_in (0 is sRGB). Errors: HV_ERR_BAD_INPUT (`name`: not an
 * ICC profile, or not an RGB or grey one), HV_ERR_LIMIT (more than 255 input profiles),
 * HV_ERR_NOMEM. Not thread-safe with the calls below: add inputs first. */
HV_API hv_status hv_colour_map_add_input(hv_colour_map *map, const void *icc, size_t size, const char *name,
                                         int *id);
/* As hv_colour_map_fractions for a colour in input profile `id` (0: sRGB). */
HV_API void hv_colour_map_fractions_in(hv_colour_map *map, int id, const uint8_t rgba[4],
                                       float out[HV_COLOUR_SLOTS]);
/* A colour in input profile `id` as sRGB (relative colorimetric; 0 or an unknown id: as given):
 * the colour asked for, which renders show and the dE2000 measures against. Thread-safe. */
HV_API void hv_colour_map_srgb_in(const hv_colour_map *map, int id, const uint8_t rgba[4], uint8_t srgb[3]);

/* Colour carried into a part: every voxel of `model`'s "occupancy" within `depth` mm of `mesh`'s
 * surface takes the colour of its nearest point on the mesh (exact point-triangle distance; the
 * colour by hv_mesh_colour_at) as the map's six fractions; a voxel deeper, or nearest to a facet
 * without colour, takes the core: 100 % of resin `core` (one of the map's six, or a seventh
 * material), or when core_rgba is given the fractions of that colour (straight RGBA in [0, 1]).
 * Adds the float grids "material.<resin>" and stores the material table (the six resins with
 * display colours, then the core). The printer has six slots: a core resin that is not one of
 * the six takes one, so a colour role gives way (Clear when no voxel uses it, else K when none
 * does, else the lesser used of the two; clear folds into white, black into equal cyan, magenta
 * and yellow) and the model has six materials (hv_colour_paint_note says which gave way). The
 * mesh must be the one the model was voxelized from, in the
 * same coordinates. Errors: HV_ERR_INVALID (depth not > 0, neither core nor core_rgba),
 * HV_ERR_NOT_FOUND (no occupancy grid), those of hv_volume_grid_set and hv_material_add (a grid
 * or material already there), HV_ERR_NOMEM. `hovox voxelize --colour-depth` calls it. */
HV_API hv_status hv_colour_paint(hv_volume *model, const hv_mesh *mesh, hv_colour_map *map, double depth,
                                 const char *core, const float *core_rgba);

/* What painting keeps beside the fractions (issue 29): float grids "colour.r", "colour.g",
 * "colour.b" (the requested sRGB colour, in [0, 1]) and "colour.mask" (1 where a colour was asked
 * for: the skin, and a colour core; 0 under a resin core), "colour.depth" (each voxel's distance
 * to the surface in mm, exact up to the depth plus two voxels (the largest edge), the depth plus
 * three voxels beyond; a voxel painted as skin holds at most the depth as a float, one deeper more),
 * and metadata hovox.colour.json (the profile, intent, resins, depth and core). The render shows
 * those colours; the stack manifest their dE2000; layers and trays put the change from skin to
 * core at the depth per printer pixel (hv_colour_depth_grid).
 * The colour map painting used, made again from the model's record. Errors: HV_ERR_NOT_FOUND
 * (the model is not painted), HV_ERR_BAD_INPUT (a damaged record), those of
 * hv_colour_map_create (the profile no longer readable). *out is freed with
 * hv_colour_map_destroy. */
HV_API hv_status hv_colour_map_for_model(const hv_volume *model, hv_colour_map **out);

/* A painted model's colour.depth grid (its index) with the depth painted (*depth_mm, as a float:
 * a voxel is skin when its value is <= it); -1 when the model has no such grid or no record of the
 * depth (painted before the grid, or a Volumetric package's colour): then the stack interpolates
 * the fractions across the depth as any other. Never fails. */
HV_API int hv_colour_depth_grid(const hv_volume *model, float *depth_mm);

typedef struct hv_colour_skin_report {
    uint64_t voxels;                /* occupied voxels with a requested colour */
    double mean_de2000, max_de2000; /* over them */
} hv_colour_skin_report;
/* CIEDE2000 between each such voxel's requested colour and what its six fractions print (each
 * multiplied by scale[k] when scale is given, then normalised: a halftone's achieved over target
 * share per resin), both through `map` (hv_colour_map_lab_of_srgb, _of_fractions). Errors:
 * HV_ERR_NOT_FOUND (no colour grids), NOMEM, CANCELLED. */
HV_API hv_status hv_colour_skin_error(const hv_volume *model, const hv_colour_map *map,
                                      const double scale[HV_COLOUR_SLOTS], hv_colour_skin_report *out);
/* hv_colour_skin_error for n scales at once (scales[s] NULL: the fractions as they are), into
 * out[0 .. n): the voxels read and each requested colour's Lab made once, the dE2000 on
 * hv_threads() threads; the same figures as n calls. Errors: HV_ERR_NOT_FOUND (no colour grids),
 * NOMEM, CANCELLED. */
HV_API hv_status hv_colour_skin_errors(const hv_volume *model, const hv_colour_map *map, int n,
                                       const double *const *scales, hv_colour_skin_report *out);
/* The same over weighted samples in place of a model's voxels (a scan printed from a colour lookup
 * table, issue 30: its tabulated values): sample i asks for the sRGB colour rgb[3i .. 3i+2] and prints
 * the fractions fractions[6i .. 6i+5] at weight[i] printer voxels (weight 0: left out); out->voxels
 * sums the weights, the mean is weighted. Never fails (HV_OK). */
HV_API hv_status hv_colour_samples_error(const hv_colour_map *map, size_t n, const uint8_t *rgb, const float *fractions,
                                         const uint64_t *weight, const double scale[HV_COLOUR_SLOTS],
                                         hv_colour_skin_report *out);

/* A stack manifest hook (hv_stack_manifest_fn of hovox/layers.h; user an hv_colour_skin whose
 * model and map the caller sets, or map and samples in place of the model): adds "colour" {icc,
 * description, intent, skin_voxels (samples: printer_voxels), mean_de2000_target,
 * max_de2000_target, and mean_de2000_achieved when the manifest's materials have "achieved"
 * (halftone): the fractions scaled per resin by achieved / target}, and fills target, achieved,
 * has_achieved and printer_voxels. */
typedef struct hv_colour_skin {
    const hv_volume *model;
    hv_colour_map *map;
    hv_colour_skin_report target, achieved;
    int has_achieved;
    /* without a model: hv_colour_samples_error's samples (borrowed) */
    size_t samples;
    const uint8_t *rgb;
    const float *fractions;
    const uint64_t *weight;
    /* set by the hook with target: 1 when its voxels are printer voxels (the samples), 0 a
       model's skin voxels (still 0 when a front end clears model afterwards) */
    int printer_voxels;
} hv_colour_skin;
HV_API hv_status hv_colour_manifest_hook(void *user, void *manifest);

/* What painting had to give way for the six slots, as one line for a person ("VeroClear gave way
 * to the core Agilus30 (six slots): no painted voxel used it; folded into VeroPureWhite"), into
 * buf (size bytes). Returns 1 when a role gave way, 0 when none did or the model is not painted
 * (buf then ""). */
HV_API int hv_colour_paint_note(const hv_volume *model, char *buf, size_t size);

/* hv_colour_paint with the core as text, as the CLI (--core) and Lua give it: a colour when it
 * reads as one (hv_color_parse), else a resin; NULL: the map's white resin. Also refuses a mesh
 * without any colour (HV_ERR_BAD_INPUT "NAME: no colour to paint ..."). */
HV_API hv_status hv_colour_paint_text(hv_volume *model, const hv_mesh *mesh, hv_colour_map *map, double depth,
                                      const char *core);

/* The body rule's inputs (issue 29): whether the user asked for colour, and which material names
 * the caller prints in a resin beside the printer's table (hv_resin_find). is_resin (may be NULL:
 * the table alone) gets the name a body's material takes in a model (hv_material_name_from of the
 * file's text: "PLA Blue" -> "PLA_Blue") and returns 1 when the caller prints that material in a
 * resin: a tray's MATERIAL=RESIN mapping (`--resin`, a job file's "resin" object, Lua and Python
 * `resin = {...}`) or a resin the tray adds (`--resin-color`); `user` is passed to it. A rule of
 * NULL is {0, NULL, NULL}: colour not asked, the table alone. */
typedef struct hv_colour_body_rule {
    int asked; /* the user asked for colour: a colour depth or core given */
    int (*is_resin)(void *user, const char *material);
    void *user;
} hv_colour_body_rule;

/* Which bodies print in their colours (issue 29 item 2), one rule for `layers MESH`, a tray's
 * mesh part, `voxelize --colour-depth`, Lua (mesh:layers, model:paint) and Python; paint[i] (may
 * be NULL; one per body) is 1 for body i painted, 0 for one that prints in its material; returns
 * how many are painted. After the 3MF specifications: a colour group's entries ("#rrggbb") are
 * colour and nothing else (Materials extension ch. 2), and a body without a material takes
 * colour: painted. A body given a colour by the user (hv_mesh_body_colour_set, `voxelize --colour
 * BODY=COLOUR`, Lua mesh:colour) is painted. A composite is a mixture of materials: printed in
 * it. A base material is what its body is made of (the core specification keeps its displaycolor
 * for rendering: "a producer MUST NOT assume that displaycolor has any effect on the printed
 * part"): printed in it, unless rule->asked and it is no resin (neither of the printer's table nor
 * the caller's, rule->is_resin) - then its colours (its display colour, or a texture or colours on
 * its facets) paint it. An OBJ's materials are its MTL's appearances (Kd, map_Kd): painted,
 * unless one is a resin. A body whose material is a resin always stays in the resin. */
HV_API size_t hv_colour_mesh_bodies(const hv_mesh *mesh, const hv_colour_body_rule *rule, uint8_t *paint);

/* Does the mesh print in its colours when nothing else says (the one rule of `layers MESH` and
 * a tray's mesh part)? 1 when it has colour (a texture, corner colours such as PLY vertex colours
 * or 3MF colour groups, material colours) and a body takes it unasked (hv_colour_mesh_bodies with
 * rule->asked taken as 0; rule's is_resin as given, may be NULL): a coloured mesh, or an assembly
 * with a colour-group body beside bodies of resins. 0 for an assembly whose bodies are all made of
 * materials (base materials, composites, resins), and for a mesh without colour. */
HV_API int hv_colour_mesh_paints(const hv_mesh *mesh, const hv_colour_body_rule *rule);

/* `model` (voxelized from `mesh`, in the same coordinates: `voxelize --colour-depth`, Lua
 * model:paint) painted body by body (hv_colour_mesh_bodies with `rule`): hv_colour_paint_text
 * (depth, core) when every body takes colour; in an assembly whose bodies do not all take it,
 * the colour is carried from the painted bodies' facets alone and every voxel of a body that
 * keeps its material (its region, hv_voxelize_regions_read) is 100 % that material or its
 * composite's mixture, with no colour asked for there; colour resins no voxel uses then leave the
 * table while it holds more than six (the printer's slots). A single body that takes colour is
 * painted exactly as hv_colour_paint_text paints it. Errors: HV_ERR_BAD_INPUT ("NAME: no body to
 * paint in its colours: shell is VeroPureWhite, core is a composite ..."), HV_ERR_NOT_FOUND (an
 * assembly's model without regions), those of hv_colour_paint_text. On failure the model may
 * hold some of the grids: destroy it. */
HV_API hv_status hv_colour_mesh_paint(hv_volume *model, const hv_mesh *mesh, hv_colour_map *map, double depth,
                                      const char *core, const hv_colour_body_rule *rule);

/* A model of `mesh` painted in its colours (one step from a coloured mesh to a stack): the mesh
 * voxelized by `vopt`, then hv_colour_mesh_paint(depth, core, rule) - the same model `voxelize
 * --colour-depth` makes on the same voxels. The bodies are checked before voxelizing. The model
 * records no shape (the caller slices it with the mesh). Errors: those of hv_colour_mesh_paint and
 * hv_voxelize. Free *out with hv_volume_destroy. */
HV_API hv_status hv_colour_mesh_model(const hv_mesh *mesh, const hv_voxelize_options *vopt, hv_colour_map *map,
                                      double depth, const char *core, const hv_colour_body_rule *rule,
                                      hv_volume **out);

/* The voxels for hv_colour_mesh_model: opt->voxel_size set to the coarser of `pitch` (say the
 * printer's coarsest) and depth / 2 (the skin two voxels deep: colour is carried from the
 * surface, so finer voxels add memory and time, little colour; 0.5 mm for the default 1 mm, about
 * the bench knot's texel), coarsened by 5/4 until the plan (filled in)
 * and the painting (about 112 bytes an occupied voxel, from the mesh's volume) need at most
 * `budget` bytes (at most 60 times). Errors: HV_ERR_INVALID (pitch or depth not positive and
 * finite), HV_ERR_LIMIT (nothing fits), those of hv_voxelize_plan. */
HV_API hv_status hv_colour_mesh_voxels(const hv_mesh *mesh, double pitch, double depth, uint64_t budget,
                                       hv_voxelize_options *opt, hv_voxel_plan *plan);

/* The same "colour" object for copies of one painted model or of one scan printed from a colour
 * table (a tray's copies of a part): sk[0 .. copies) share sk[0]'s map and its model or samples
 * (set by the caller, as for hv_colour_manifest_hook); copy c's halftone printed the m materials
 * `names` at target[c] and achieved[c] (achieved[c] NULL: no halftone); each colour resin's
 * fractions are scaled by its achieved / target. Fills each sk[c]'s target, achieved and
 * has_achieved and out[c] (jansson json_t *, owned by the caller): {icc, description, intent,
 * skin_voxels (samples: printer_voxels), mean_de2000_target, max_de2000_target, and
 * mean_de2000_achieved when achieved[c] is given, gives_way when painting gave a resin up}. The
 * requested colours are read and their Lab made once for all copies; copies whose halftones
 * printed alike share their figures. Errors: those of hv_colour_skin_errors, NOMEM (then every
 * out[c] NULL). */
HV_API hv_status hv_colour_skin_manifests(hv_colour_skin *sk, int copies, int m, const char *const *names,
                                          const double *const *target, const double *const *achieved, void **out);

/* CIE L*a*b* (D50) of an sRGB colour, and of what fractions print: the inks back through the
 * profile (CMYK to Lab, the same intent; white adds nothing, the colour part is normalised by
 * 1 - Clear). Clear-only fractions give the paper white. */
HV_API void hv_colour_map_lab_of_srgb(const hv_colour_map *map, const uint8_t rgb[3], double lab[3]);
HV_API void hv_colour_map_lab_of_fractions(const hv_colour_map *map, const float fractions[HV_COLOUR_SLOTS],
                                           double lab[3]);
/* CIEDE2000 colour difference (Sharma, Wu, Dalal 2005) of two Lab colours. */
HV_API double hv_colour_delta_e2000(const double lab1[3], const double lab2[3]);

#ifdef __cplusplus
}
#endif
#endif
