/* hovox/export.h - graded models out to VTK for inspection (ParaView) and simulation (FEA):
 * .vti image data (point data over a box) and .vtu hexahedral meshes (cell data, optional
 * NxNxN coarsening), with derived physical properties (Voigt and Reuss mixing rules and
 * measured linearization tables, after the subdivision-gradients seed's missing step); and to
 * the 3MF ecosystem as a 3MF Volumetric package (.3mf; read back by hv_volume_load, see
 * hovox/threemf.h). */
#ifndef HOVOX_EXPORT_H
#define HOVOX_EXPORT_H

#include "hovox/material.h"
#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ==== mixing rules ====================================================================== */

/* Rule of mixtures (Voigt, iso-strain upper bound): sum_j p[j] * x[j] over m materials. */
HV_API double hv_property_voigt(const double *p, const double *x, int m);

/* Inverse rule of mixtures (Reuss, iso-stress lower bound): 1 / sum_j (p[j] / x[j]), terms
 * with p[j] == 0 left out. Needs x[j] > 0 where p[j] > 0 (returns 0 when x[j] <= 0 there, and
 * 0 when every p[j] is 0). */
HV_API double hv_property_reuss(const double *p, const double *x, int m);

/* ==== linearization tables ============================================================== */

/* A measured curve property(fraction of one material): samples (x_i, v_i), x strictly
 * increasing in [0, 1], at least 2; piecewise-linear between samples, constant beyond the
 * first and last sample. The mixture variable x is the volume fraction of the named material
 * in the voxel (or averaged cell); the samples are meant to be measured on printed blends of
 * that material with the others (the seed's "print targets with different mixtures and
 * measure their stiffness"). Immutable once made. */
typedef struct hv_linearization hv_linearization;

/* Make a table. property: 1-64 bytes of [A-Za-z0-9_-]; unit: SI unit text, may be NULL or
 * "" (then the material table's unit of that property is used on export, if any); material:
 * a material name. Copies everything. Errors: HV_ERR_INVALID naming the offending sample
 * ("sample 3: fraction 0.2 is not greater than the previous (0.25)"), HV_ERR_NOMEM.
 * Free with hv_linearization_destroy. */
HV_API hv_status hv_linearization_create(const char *property, const char *unit,
                                         const char *material, const double *x,
                                         const double *value, int n, hv_linearization **out);

/* Parse the CSV form (README "Linearization tables"):
 *     # comment lines start with '#'; blank lines are ignored
 *     fraction.<material>,<property>[<unit>]
 *     0,600000
 *     0.5,1.2e8
 *     1,2.5e9
 * A header, then rows of two finite numbers separated by a comma (spaces around fields and
 * CRLF line ends are allowed). `name` names the text in messages (a file name). When
 * `property` is not NULL the header's property must be the same. Errors: HV_ERR_BAD_INPUT
 * "stiff.csv: line 4: fraction 0.2 is not greater than the previous (0.25)", HV_ERR_NOMEM. */
HV_API hv_status hv_linearization_parse(const char *text, size_t len, const char *name,
                                        const char *property, hv_linearization **out);

/* Read and parse a CSV file (at most 16 MiB). Errors: those of hv_linearization_parse and
 * HV_ERR_IO (missing, unreadable). */
HV_API hv_status hv_linearization_load(const char *path, const char *property,
                                       hv_linearization **out);

/* Free a table; NULL is allowed. */
HV_API void hv_linearization_destroy(hv_linearization *lin);

/* Property value at fraction x (clamped to the sampled range). */
HV_API double hv_linearization_eval(const hv_linearization *lin, double x);

/* The inverse: the fraction that gives `value` (what a printer driver needs to turn a wanted
 * stiffness into a material probability). Needs strictly monotonic values. Errors:
 * HV_ERR_INVALID (values not strictly monotonic, or `value` outside the sampled range). */
HV_API hv_status hv_linearization_invert(const hv_linearization *lin, double value, double *x);

/* Names, owned by the table. unit is "" when none was given. */
HV_API const char *hv_linearization_property(const hv_linearization *lin);
HV_API const char *hv_linearization_unit(const hv_linearization *lin);
HV_API const char *hv_linearization_material(const hv_linearization *lin);
HV_API int hv_linearization_count(const hv_linearization *lin);

/* ==== export ============================================================================ */

typedef enum hv_export_format {
    HV_EXPORT_AUTO = 0, /* by the extension of the path (any case): .vti, .vtu, .stl, .obj, and
                           .3mf: HV_EXPORT_3MF_SHAPE, or HV_EXPORT_3MF when opt->volumetric */
    HV_EXPORT_VTI = 1,  /* vtkImageData: one point per voxel centre over a box, point data */
    HV_EXPORT_VTU = 2,  /* vtkUnstructuredGrid: one VTK_HEXAHEDRON per occupied voxel (or
                           coarse block), points shared between neighbours, cell data */
    HV_EXPORT_3MF = 3,  /* 3MF package with the Volumetric extension: the exact voxel boundary
                           as the mesh, the materials as base materials, one image3d stack of
                           PNG sheets per material fraction and per derived property */
    HV_EXPORT_STL = 4,  /* the shape the model records (issue 28), binary STL: a model made from
                           one mesh writes that mesh, placed by its recorded transform */
    HV_EXPORT_OBJ = 5,  /* the same as Wavefront OBJ (hv_mesh_write_obj) */
    HV_EXPORT_3MF_SHAPE = 6 /* the same surface as a 3MF core package (what slicers read): one
                               object, the model's materials as <basematerials>, each triangle in
                               the material that dominates the model just inside it */
} hv_export_format;

/* The 3MF Volumetric extension's limits on an image stack (spec 3.2): rows, columns and
 * sheets at most 1024^3 each, at most 1024^5 voxels. */
#define HV_3MF_MAX_IMAGE_SIDE (1ull << 30)
#define HV_3MF_MAX_IMAGE_VOXELS (1ull << 50)

/* Mixing rules to derive properties with (bit flags). */
enum { HV_MIX_VOIGT = 1u, HV_MIX_REUSS = 2u };

/* When a coarse NxNxN block becomes a hexahedron (.vtu with coarsen > 1). */
typedef enum hv_coarsen_rule {
    HV_COARSEN_MAJORITY = 0, /* at least half of its N^3 voxels are occupied: the exported
                                volume stays close to the model's (boundary errors cancel) */
    HV_COARSEN_ANY = 1       /* any voxel occupied: covers every feature, grows the volume */
} hv_coarsen_rule;

/* Name of a coarsen rule ("majority", "any"), as the option takes it. Static text. */
HV_API const char *hv_coarsen_rule_name(hv_coarsen_rule rule);

#define HV_EXPORT_MAX_TABLES 64

typedef struct hv_export_options {
    hv_export_format format;
    /* Box in world units: only voxels whose centres lie inside [box_lo, box_hi] are
     * exported (.vti: the image spans exactly those voxels, also outside the model;
     * .vtu: occupied voxels outside the box count as empty). use_box = 0: the bounding box
     * of the occupied voxels. */
    int use_box;
    double box_lo[3], box_hi[3];
    int coarsen;                    /* .vtu: merge NxNxN voxel blocks (aligned to multiples of
                                       N in index space); 1 (default): one hex per voxel */
    hv_coarsen_rule coarsen_rule;   /* default HV_COARSEN_MAJORITY */
    unsigned mix;                   /* HV_MIX_* bits; default HV_MIX_VOIGT | HV_MIX_REUSS */
    const hv_linearization *const *tables; /* ntables tables (borrowed for the call) */
    int ntables;
    int nlinearize;                 /* tables loaded by the export itself from CSV files */
    struct {
        char property[64];
        const char *path;           /* borrowed for the call */
    } linearize[HV_EXPORT_MAX_TABLES];
    const char *grids;              /* float grids of the model exported as arrays of their own
                                       names: "NAME[,NAME...]" (borrowed; NULL: none), e.g. a
                                       field a script computed (hv_volume_grid_set) */
    uint64_t max_memory;            /* budget for the export's buffers; 0: half of RAM */
    int zlib_level;                 /* 1 (fastest) - 9 (smallest); 0: 1 */
    int bits;                       /* .3mf --volumetric: bits per PNG sample, 8 or 16; 0: 8 */
    int volumetric;                 /* a .3mf path (format AUTO or HV_EXPORT_3MF_SHAPE) writes the
                                       Volumetric package (HV_EXPORT_3MF) instead of the shape */
    const hv_progress *progress;    /* may be NULL */
} hv_export_options;

/* Defaults as noted above. */
HV_API void hv_export_options_init(hv_export_options *opt);

/* The export options as an option set (hovox/options.h): keys box, coarsen, keep, properties,
 * linearize (PROPERTY=FILE.csv, repeatable), grids, level, bits, volumetric, max_memory. Static
 * data. */
HV_API const hv_option_set *hv_export_option_set(void);
/* Every option's domain. Errors: HV_ERR_INVALID naming the option. */
HV_API hv_status hv_export_options_check(const hv_export_options *opt);

/* What an export wrote (or would write). */
typedef struct hv_export_report {
    hv_export_format format;
    int64_t lo[3], hi[3];    /* .vti: voxel index range of the image (inclusive); .vtu, .3mf:
                                the bounding box of the exported occupied voxels */
    int64_t dims[3];         /* .vti: points per axis; .3mf: columns, rows and sheets of every
                                image stack (x, y, z voxels); .vtu: 0 */
    uint64_t points;         /* .vti: dims product; .vtu: hexahedron corner points; .3mf: mesh
                                vertices (0 for a plan: known once the mesh is welded) */
    uint64_t cells;          /* .vtu: hexahedra; .3mf, .stl, .obj: mesh triangles; .vti: 0 */
    uint64_t occupied;       /* occupied voxels inside the box */
    int materials;           /* 0 when the model has no material table (occupancy only) */
    int arrays;              /* data arrays written (occupancy, fractions, properties); .3mf:
                                image stacks (fractions, properties) */
    int bits;                /* .3mf: bits per PNG sample (of the fraction and property stacks) */
    int colour;              /* .3mf: 1 when the package carries a painted model's colours (a
                                <v:color> over one more stack, "colour": 16-bit RGBA sheets) */
    uint64_t memory_bytes;   /* planned bytes of the export's buffers */
    uint64_t file_bytes;     /* size of the file written (0 for a plan) */
    char names[2048];        /* the data array names, comma-separated (.3mf: the image stacks) */
    char notes[1024];        /* why properties were left out, one per line ("" if none) */
} hv_export_report;

/* Write `vol` (a graded model: bool grid "occupancy", float grids "material.<name>" and the
 * material table; or a plain voxelized model, exported as occupancy only) to `path`.
 *
 * Arrays (point data in .vti, cell data in .vtu), in this order:
 *   "occupancy"                 .vti: uint8 0/1; .vtu: float, occupied fraction of the cell
 *   "fraction.<material>"       float, per material in table order (0 outside the model;
 *                               .vtu: averaged over the cell's occupied voxels)
 *   "<property>.voigt[<unit>]"  float, per property every material defines with one unit
 *   "<property>.reuss[<unit>]"  (e.g. "youngs_modulus.voigt[Pa]"), in the order of the first
 *                               material's properties; derived from the (averaged)
 *                               fractions; 0 outside the model; [<unit>] left out when the
 *                               unit is ""
 *   "<property>.table[<unit>]"  one per linearization table
 *   "<grid>"                    float, one per name in opt->grids: the float grid's value at
 *                               the voxel (.vtu: averaged over the cell's occupied voxels),
 *                               0 outside the model
 * Field data: "hovox.materials.json" (the material table) when graded; .vti also
 * "hovox.index_lo" (int32 x3: the voxel index of point 0).
 * .vti: point (x,y,z) is voxel lo + (x,y,z), origin = its centre, spacing = voxel size.
 * .vtu: coarse cell c covers voxels c*N .. c*N+N-1 per axis; its corners sit on voxel faces,
 * points are float32 world coordinates, connectivity is int32 below 2^31 points (else int64).
 * Occupancy is bool grid "occupancy" (all active voxels when there is none). Fractions of
 * exported occupied voxels must be finite and sum to 1 within 1e-4 (Wu eq. 12).
 *
 * The file is VTK XML, appended raw binary, zlib-compressed, 64-bit headers; written to a
 * temporary name in the same directory (claimed before any work, so an unwritable place
 * fails at once) and renamed when complete, so a failure leaves no file. `report` (may be
 * NULL) is filled. Multi-threaded; the file does not depend on the thread count. Progress
 * stages: "export cells", "export points" (.vtu), "export fill", "export write".
 *
 * .stl, .obj, .3mf (HV_EXPORT_STL, _OBJ, _3MF_SHAPE): the shape the model records, not its
 * voxels (issue 28): a model made from one mesh writes that mesh placed by its recorded transform;
 * a Boolean of meshes, a narrow-band level set of 0.05 mm voxels per mesh combined by the tree
 * and meshed (OpenVDB), watertight. The 3MF core package (3MF Core 1.3, unit millimeter) holds
 * one object of that mesh; with a material table, the materials as <basematerials id="1">
 * (names, display colours), each triangle's material the one with the largest fraction at the
 * point half a voxel inside it (hv_model_probe; where that point is outside the model, at the
 * triangle's centroid), the object's default the one most triangles have; the model part
 * deflated at opt->zlib_level (0: 1). Only max_memory and level apply; a model that records no shape is refused (HV_ERR_INVALID).
 *
 * .3mf with opt->volumetric (HV_EXPORT_3MF; 3MF Core 1.3 with the Volumetric extension 0.8,
 * namespaces and names as its spec): an
 * OPC package ([Content_Types].xml, _rels/.rels, 3D/3dmodel.model and its relationships
 * 3D/_rels/3dmodel.model.rels to every PNG sheet, type 3dtexture) holding
 *   - one object whose mesh is the exact boundary of the exported occupied voxels (the faces
 *     between occupied and unoccupied voxels, two triangles each, outward, one vertex per
 *     voxel corner and surface sheet: voxels meeting only along an edge or at a corner get
 *     separate vertices there, so every edge has exactly two triangles), unit millimeter;
 *   - the material table as <basematerials> (names; display colours #RRGGBB[AA]);
 *   - per material an <v:image3d> named after it with an <v:imagestack> of PNG sheets
 *     /3D/volumetric/<name>/sheetNNNN.png (grey, opt->bits bits; column = x, row 0 = the
 *     highest y, sheet 0001 = the lowest z) over the occupied voxels' bounding box, 0 outside
 *     the model; the fractions of a voxel are rounded so that they sum to exactly 2^bits - 1;
 *   - per stack a <v:functionfromimage3d> (filter linear, tilestyles clamp);
 *   - a <v:volumedata> with a <v:composite> (basematerialid: the base materials) of one
 *     <v:materialmapping> per material (channel red, transform: model millimetres to the
 *     stack's UVW so that voxel centres fall on pixel centres), and one <v:property> per
 *     derived property array (name "hovox:<array>" in the namespace urn:hovox:3mf:2025, SI
 *     units, the unit in attribute hovox:unit; required="false"; the values scaled into the
 *     sheets by valueoffset and valuescale);
 *   - a painted model's colours (hovox/colour.h: grids colour.r, .g, .b, .mask) as a
 *     <v:color channel="color"> over one more stack, "colour": RGBA PNGs of 16 bits whatever
 *     opt->bits, RGB the linear sRGB (spec 5.2.1) of the colour asked for, or under a resin
 *     core (mask 0) of the composition's display colour, alpha the mask, read as the property
 *     hovox:colour.mask (channel alpha); its function's filter is nearest (every point inside
 *     the mesh takes its voxel's colour); report->colour is then 1 (the colour grids are not
 *     written as properties);
 *   - metadata Application, hovox:materials (the material table as JSON), hovox:origin and, for
 *     a painted model, hovox:colour (hovox.colour.json: profile, intent, resins, depth, core).
 * The sheets are written to a temporary directory next to the file first and packed
 * (stored); the model part is deflated at opt->zlib_level. Progress stages: "export mesh",
 * "export sheets", "export write". A model without materials is refused (HV_ERR_INVALID).
 * Errors: HV_ERR_INVALID (unknown extension, bad options, box without voxel centres,
 * nothing occupied to export as .vtu, a grid named twice or clashing with another
 * array), HV_ERR_BAD_INPUT (fractions that do not sum to 1,
 * corrupt material table), HV_ERR_NOT_FOUND (a table's material is not in the model, no float grid of a name in
 * grids: the message lists the model's float grids),
 * HV_ERR_LIMIT (buffers over max_memory; the message says how much is needed),
 * HV_ERR_IO (cannot write or rename), HV_ERR_UNSUPPORTED (VTK plugin missing),
 * HV_ERR_NOMEM, HV_ERR_CANCELLED, HV_ERR_INTERNAL; for .3mf also HV_ERR_LIMIT naming the 3MF
 * Volumetric limit an image stack would exceed. */
HV_API hv_status hv_export_write(const hv_volume *vol, const char *path,
                                 const hv_export_options *opt, hv_export_report *report);

/* Fill `report` with what hv_export_write would write (counts, arrays, memory; file_bytes 0),
 * without writing or loading VTK. `path` only selects the format when opt->format is AUTO.
 * Errors: those of hv_export_write except HV_ERR_IO, HV_ERR_UNSUPPORTED and the fraction
 * check (fractions are read only while writing); the budget is not applied. */
HV_API hv_status hv_export_plan(const hv_volume *vol, const char *path,
                                const hv_export_options *opt, hv_export_report *report);

/* Format named by a path's extension: HV_EXPORT_VTI, HV_EXPORT_VTU, HV_EXPORT_3MF_SHAPE (.3mf),
 * HV_EXPORT_STL, HV_EXPORT_OBJ or HV_EXPORT_AUTO (none of them). */
HV_API hv_export_format hv_export_format_from_path(const char *path);

/* The extensions hv_export_format_from_path knows, as a person reads them (".vti, .vtu, .3mf, .stl
 * or .obj"): the one list the CLI's and Lua's messages name. Static text. */
HV_API const char *hv_export_format_list(void);

#ifdef __cplusplus
}
#endif
#endif
