/* hovox/mesh.h - triangle meshes: file input, exact vertex welding, edge adjacency, the mesh
 * report (closedness, orientation, volume, shells), and bodies: the named, separately
 * materialled parts of an assembly (3MF objects, OBJ groups), each a consecutive range of
 * facets. */
#ifndef HOVOX_MESH_H
#define HOVOX_MESH_H

#include "hovox/core.h"
#include "hovox/options.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hv_mesh hv_mesh;

typedef enum hv_mesh_format {
    HV_MESH_GENERATED = 0, /* built in memory */
    HV_MESH_STL_BINARY = 1,
    HV_MESH_STL_ASCII = 2,
    HV_MESH_3MF = 3,
    HV_MESH_OBJ = 4,
    HV_MESH_PLY_ASCII = 5,
    HV_MESH_PLY_BINARY_LE = 6,
    HV_MESH_PLY_BINARY_BE = 7
} hv_mesh_format;

/* "binary STL", "ASCII STL", "3MF", "OBJ", "ASCII PLY", "binary PLY (little-endian)", ...,
 * "generated". Static. */
HV_API const char *hv_mesh_format_name(hv_mesh_format format);
/* The key of a format in JSON, Lua and Python ("binary", "ascii", "3mf", "obj", "ply_ascii",
 * ...). Static. */
HV_API const char *hv_mesh_format_key(hv_mesh_format format);

/* What the mesh report says. Defects (open edges, flips, degenerate facets) are facts, not
 * errors: a mesh that has them still loads. */
typedef struct hv_mesh_report {
    hv_mesh_format format;
    uint64_t facets;            /* triangles as stored */
    uint64_t vertices;          /* distinct positions after exact welding */
    double bbox_min[3], bbox_max[3];
    double volume;              /* signed, from the stored winding (positive: outward) */
    double area;
    uint64_t shells;            /* connected components through shared edges */
    uint64_t open_edges;        /* edges used by one facet only */
    uint64_t nonmanifold_edges; /* edges used by three or more facets */
    uint64_t degenerate_facets; /* zero area: repeated or collinear vertices */
    uint64_t flipped_facets;    /* facets whose winding disagrees with their shell's majority */
    uint64_t normal_mismatch;   /* ASCII/binary stored normals opposite to the winding */
} hv_mesh_report;

/* 1 when the report's mesh is closed (no open or non-manifold edge) and its signed volume is
 * negative: consistently wound, but with every facet facing inward. */
HV_API int hv_mesh_report_inside_out(const hv_mesh_report *r);

/* Load an STL file. The format is decided by content: a file whose size is 84 + 50*n,
 * n being the count at byte 80, is binary; otherwise it must be ASCII ("solid" ... "endsolid").
 * Errors: HV_ERR_IO (missing, unreadable, a directory), HV_ERR_BAD_INPUT (truncated, trailing
 * data, non-finite or non-numeric coordinates, missing keywords, no facets), HV_ERR_LIMIT
 * (more than 2^31 facets), HV_ERR_NOMEM. The detail names the file, the facet or line, and
 * the value. On success *out is a new mesh, freed with hv_mesh_destroy. */
HV_API hv_status hv_mesh_load_stl(const char *path, hv_mesh **out);

/* Same from memory; `name` is used in messages only. */
HV_API hv_status hv_mesh_parse_stl(const void *data, size_t size, const char *name,
                                   hv_mesh **out);

/* Build a mesh from indexed triangles (3 floats per vertex, 3 indices per facet); vertices
 * are welded again (exact match). Errors: HV_ERR_INVALID (index out of range, non-finite
 * coordinate, no facets), HV_ERR_NOMEM. Copies the arrays. */
HV_API hv_status hv_mesh_create(const float *xyz, size_t vertex_count, const uint32_t *facets,
                                size_t facet_count, hv_mesh **out);

/* Load a mesh from any supported file, chosen by extension (case-insensitive): .stl, .3mf,
 * .obj, .ply. Errors: those of the format's reader (HV_ERR_IO, HV_ERR_BAD_INPUT naming the
 * file, the place and the value, HV_ERR_LIMIT, HV_ERR_NOMEM); HV_ERR_BAD_INPUT for another
 * extension, listing the supported ones. */
HV_API hv_status hv_mesh_load(const char *path, hv_mesh **out);

/* 1 when hv_mesh_load would take the file for a mesh (a ZIP package, a PLY header, a binary STL
 * whose facet count matches its size, a mesh extension, text starting like ASCII STL or OBJ),
 * else 0. Reads the first 4 KiB. */
HV_API int hv_mesh_sniff(const char *path);

/* The extensions hv_mesh_load reads, "stl, 3mf, obj, ply". Static. */
HV_API const char *hv_mesh_load_extensions(void);

/* The readers behind hv_mesh_load, from memory (fuzzing, tests, files already read). `name`
 * names the file in messages and, without its directories and extension, the body of facets
 * no group names. All three refuse input they cannot read whole: HV_ERR_BAD_INPUT with one
 * line naming `name`, the place (line, element, object, triangle) and the value;
 * HV_ERR_LIMIT (more than 2^31 facets or 2^32 vertices, a 3MF package larger than the memory
 * budget allows), HV_ERR_NOMEM. On failure *out is NULL. Polygons are fan-triangulated around
 * their first corner (right for the convex polygons exporters write).
 *
 * OBJ: `v` (x y z, an optional w read and not used; `v x y z r g b` in [0, 1] the vertex's colour,
 * the corners' colours when every vertex has one, else a note), `f` with v, v/vt,
 * v//vn or v/vt/vn corners; indices count from 1, or back from -1 for the last vertex defined,
 * and must name a vertex (texture coordinate, normal) defined above the face. `o` and `g`
 * start a body of that name (one that holds no face is dropped, a name that comes back
 * continues its body); faces before any `o`/`g` form a body named after the file. `usemtl`
 * names the material of the faces that follow. `vt` (u [v [w]]) gives texture coordinates;
 * `vn` (counted), `s` and the other display statements are skipped; lines (`l`) and points (`p`)
 * are not read; free-form geometry and unknown statements are refused. `\` continues a
 * statement on the next line; `#` starts a comment. From memory `mtllib` is not followed
 * (materials are names only); hv_mesh_load reads the libraries beside the file: a material's
 * `Kd` (and `d`/`Tr`) becomes its display colour, its `map_Kd` (PNG or JPEG, -clamp, -o, -s) a
 * texture of the faces that use it and give every corner a `vt` (the texture replaces Kd there).
 * A library that is not there is skipped (the materials stay names only); one that cannot be
 * read, a texture that is missing or not an image, a bad value: HV_ERR_BAD_INPUT naming the
 * file, the line and the value. */
HV_API hv_status hv_mesh_parse_obj(const void *data, size_t size, const char *name, hv_mesh **out);

/* PLY 1.0, ASCII or binary of either byte order: the element vertex's x, y, z (any scalar
 * type) and the element face's list vertex_indices or vertex_index (integer count and item
 * types); other properties and elements, lists included, are skipped. Element counts are
 * checked against the bytes after the header before anything is allocated. One body, named
 * after the file. Vertex colours `red green blue [alpha]` (uchar, or float/double in [0, 1])
 * become corner colours (hv_mesh_corner_colours); other integer types, a partial set or a float
 * outside [0, 1] are refused. */
HV_API hv_status hv_mesh_parse_ply(const void *data, size_t size, const char *name, hv_mesh **out);

/* 3MF (core specification 1.3, with the materials extension's base materials and colour
 * groups), read by hovox's package module on libzip and libxml2 (streamed; messages name the
 * part, line and column). Each build item is a body: its object's mesh, or its components
 * flattened, placed by the item's and the components' transforms (12 finite numbers, not
 * singular; a mirroring one reverses the facets so the volume stays positive), named by the
 * object's name attribute ("body N" without one); items of objects of type "support" or
 * "other" are not bodies. Coordinates are converted from the model's unit to millimetres.
 * Materials: base materials by name (with their display colour) and colours ("#rrggbb",
 * "#rrggbbaa" when not opaque), per object (pid/pindex) and per triangle (pid/p1; a gradient's
 * first corner); a body's material is its object's default, else its facets' majority. Every
 * reference is checked (a pid naming no property group defined above it, an index past its
 * group's end, a component naming an object not defined above its own: HV_ERR_BAD_INPUT), and
 * so is every vertex index and coordinate. A package whose ZIP declares more than half the
 * memory budget, or a part more than 1000 times its compressed size, is refused before it
 * inflates; component trees deeper than 256 levels, 1,000,000 placements or more triangles
 * than the budget holds are refused before anything is placed (HV_ERR_LIMIT). */
HV_API hv_status hv_mesh_parse_3mf(const void *data, size_t size, const char *name, hv_mesh **out);

/* ---- bodies and materials ------------------------------------------------------------------
 * Every mesh has at least one body. A body is a consecutive range of facets, in file order:
 * a 3MF build item's object (with its components), an OBJ `o` or `g` group, a whole STL or
 * PLY file. Names are unique within a mesh and never empty (a file that gives none or a
 * repeated one gets "body N", N counted from 1, or "NAME (2)"). The report of the whole mesh
 * (hv_mesh_get_report) treats all facets as one mesh; hv_mesh_body_extract gives a body's own.
 *
 * Materials are the ones the file names (3MF base materials, 3MF colours as "#RRGGBB" when
 * they carry no name, OBJ `usemtl` names), in first-use order. A facet's material is an index
 * into them or HV_MESH_NO_MATERIAL; a body's material is the one most of its facets use
 * (ties: the lowest index), or the object's default in 3MF. */
#define HV_MESH_NO_MATERIAL (-1)

/* One base material of a mixture and its volume fraction; a mixture has at most
 * HV_MAX_MIX_PARTS of them. */
#define HV_MAX_MIX_PARTS 64
typedef struct hv_mesh_mix_part {
    const char *material; /* the base material's name; owned by the mesh */
    double fraction;      /* in (0, 1] */
} hv_mesh_mix_part;

/* A material is either one of its own (nparts 0) or a mixture of base materials (a 3MF
 * composite: nparts >= 1, distinct names, fractions summing to 1 within 1e-4, normalised to
 * exactly 1 when read). A mixture's name is its own ("composite ID#I", or the file's); voxelize
 * gives a mixture's voxels the base materials' fractions, never the mixture's name. */
typedef struct hv_mesh_material {
    const char *name;  /* owned by the mesh */
    uint32_t rgba;     /* display colour 0xRRGGBBAA when has_color */
    int has_color;
    size_t nparts;                 /* 0: not a mixture */
    const hv_mesh_mix_part *parts; /* nparts of them; owned by the mesh */
} hv_mesh_material;

typedef struct hv_mesh_body {
    const char *name;      /* owned by the mesh */
    int32_t material;      /* index into the mesh's materials, or HV_MESH_NO_MATERIAL */
    size_t first_facet;    /* facets [first_facet, first_facet + facet_count) */
    size_t facet_count;    /* >= 1 */
    int coloured;          /* given a colour by hv_mesh_body_colour_set: painted whatever its material */
} hv_mesh_body;

HV_API size_t hv_mesh_body_count(const hv_mesh *mesh);
/* Body i < hv_mesh_body_count; owned by the mesh. */
HV_API const hv_mesh_body *hv_mesh_body_at(const hv_mesh *mesh, size_t i);
/* The body with this exact name, or -1. */
HV_API int64_t hv_mesh_body_find(const hv_mesh *mesh, const char *name);
HV_API size_t hv_mesh_material_count(const hv_mesh *mesh);
HV_API const hv_mesh_material *hv_mesh_material_at(const hv_mesh *mesh, size_t i);
/* Per facet: material index or HV_MESH_NO_MATERIAL; NULL when the file names no material. */
HV_API const int32_t *hv_mesh_facet_materials(const hv_mesh *mesh);

/* A new mesh holding body i alone: its facets welded again, its own adjacency and report,
 * one body of the same name and material, the materials and textures of the whole mesh, the
 * body's corner colours and texture coordinates, name
 * "MESH#BODY" (just MESH when there is one body). Errors: HV_ERR_INVALID (i out of range),
 * HV_ERR_NOMEM. */
HV_API hv_status hv_mesh_body_extract(const hv_mesh *mesh, size_t i, hv_mesh **out);

/* Give the body named `body` the material `material` (the mesh's material of that name, else a
 * new one without a colour), whatever it had: `--material BODY=NAME` of voxelize, Lua's
 * mesh:set_material. A mesh read without bodies has one, named after its file. Errors:
 * HV_ERR_NOT_FOUND ("gear.obj: no body 'hub' (bodies: rim, spokes)"), HV_ERR_INVALID (an empty
 * material name), HV_ERR_NOMEM; the mesh is unchanged on failure. */
HV_API hv_status hv_mesh_body_material_set(hv_mesh *mesh, const char *body, const char *material);

/* Bodies' materials as the options give them: "BODY=MATERIAL" texts (borrowed), in the order
 * given. One rule for `--material BODY=MATERIAL` (voxelize, layers), a tray part's "materials":
 * {"BODY": "MATERIAL"} (job files, Lua, Python) and Lua's and Python's materials = {BODY =
 * MATERIAL}. Zero-initialised: none. */
#define HV_BODY_MATERIALS_MAX 64
typedef struct hv_body_materials {
    int n;
    const char *pair[HV_BODY_MATERIALS_MAX];
} hv_body_materials;
/* The options' parser (an hv_option of kind CUSTOM, flags REPEAT | PAIRS, whose offset is that of
 * an hv_body_materials in the options struct): one BODY=MATERIAL value, both sides non-empty,
 * at most HV_BODY_MATERIALS_MAX. Errors: HV_ERR_INVALID (set with hv_error_option). */
HV_API hv_status hv_body_materials_option_parse(const hv_option *opt, void *opts, const hv_opt_value *value);
/* Each body its material, in order (hv_mesh_body_material_set). Errors: those of
 * hv_mesh_body_material_set (a body the mesh does not have, listing its bodies). */
HV_API hv_status hv_body_materials_apply(const hv_body_materials *materials, hv_mesh *mesh);

/* Body i's own report: its facets as a mesh of their own (hv_mesh_body_extract), or the
 * whole mesh's report when it has one body. Errors: HV_ERR_INVALID (i out of range),
 * HV_ERR_NOMEM. */
HV_API hv_status hv_mesh_body_report(const hv_mesh *mesh, size_t i, hv_mesh_report *out);

/* Join meshes into one multi-body mesh, one body per part in order: all of the part's facets
 * (whatever bodies it has) become one body. Materials are the distinct `material` names, in
 * order. Each part's appearance comes along (its textures appended, renumbered); a part whose
 * colour came from its materials keeps it as corner colours, and the facets of a part without
 * colour, when others have some, are HV_MESH_NO_COLOUR. The result is named "" (generated). Errors: HV_ERR_INVALID (n == 0, a NULL mesh),
 * HV_ERR_NOMEM. */
typedef struct hv_mesh_part {
    const hv_mesh *mesh;
    const char *name;     /* NULL: "body N" */
    const char *material; /* NULL: none */
} hv_mesh_part;
HV_API hv_status hv_mesh_join(const hv_mesh_part *parts, size_t n, hv_mesh **out);

/* ---- appearance ----------------------------------------------------------------------------
 * Besides its per-facet materials a mesh may carry colour: per facet corner colours, textures,
 * and per facet corner texture coordinates. A facet's colour is its texture (facet_texture >=
 * 0) sampled at the UV interpolated over the facet; else its corner colours (interpolated)
 * when set; else its material's colour (has_color); else none. Facets are in file order
 * (welding never reorders them), so readers set these after building the mesh.
 * hv_mesh_body_extract, hv_mesh_join and hv_mesh_transform carry them (a mirror that swaps two
 * corners of a facet swaps their colours and UVs too). */
typedef enum hv_tile { HV_TILE_WRAP = 0, HV_TILE_MIRROR, HV_TILE_CLAMP, HV_TILE_NONE } hv_tile;
typedef enum hv_filter { HV_FILTER_AUTO = 0, HV_FILTER_LINEAR, HV_FILTER_NEAREST } hv_filter;
typedef struct hv_mesh_texture {
    const char *name;       /* where it came from ("3D/Textures/skin.png", "skin.png"); owned by the mesh */
    const uint8_t *rgba;    /* width*height*4 bytes, 8-bit sRGB + alpha, row 0 = top of image (v = 1) */
    uint32_t width, height;
    hv_tile tile_u, tile_v;
    hv_filter filter;
    const uint8_t *icc;     /* the ICC profile the picture embeds (PNG iCCP, JPEG APP2), its colours'
                               space; NULL: sRGB. Owned by the mesh */
    size_t icc_size;
} hv_mesh_texture;

/* Per facet corner 0xRRGGBBAA (3 per facet, facet order), copied; NULL clears them.
 * Errors: HV_ERR_NOMEM. */
HV_API hv_status hv_mesh_set_corner_colours(hv_mesh *mesh, const uint32_t *rgba);
/* The corner colours (3 per facet), owned by the mesh; NULL: none. */
HV_API const uint32_t *hv_mesh_corner_colours(const hv_mesh *mesh);

/* Add a texture: copies the name and the pixels (width*height*4 bytes, row 0 the top);
 * *index (may be NULL) receives its index, counted from 0 in the order added. Errors:
 * HV_ERR_INVALID (a zero or too large size, NULL pixels, a tile or filter out of range),
 * HV_ERR_LIMIT (more than 2^31 - 1 textures), HV_ERR_NOMEM. */
HV_API hv_status hv_mesh_add_texture(hv_mesh *mesh, const char *name, const uint8_t *rgba,
                                     uint32_t width, uint32_t height, hv_tile tile_u,
                                     hv_tile tile_v, hv_filter filter, int32_t *index);
HV_API size_t hv_mesh_texture_count(const hv_mesh *mesh);
/* Texture i's colours are in the ICC profile `icc` (size bytes, copied; NULL clears it): the
 * picture's embedded profile, which painting converts them through (hovox/colour.h). Errors:
 * HV_ERR_INVALID (i out of range), HV_ERR_NOMEM. */
HV_API hv_status hv_mesh_texture_set_icc(hv_mesh *mesh, size_t i, const void *icc, size_t size);
/* Texture i < hv_mesh_texture_count (else NULL); owned by the mesh. */
HV_API const hv_mesh_texture *hv_mesh_texture_at(const hv_mesh *mesh, size_t i);

/* uv: 6 floats per facet (u, v per corner), finite; facet_texture: per facet a texture index or
 * -1 (none; or HV_MESH_NO_COLOUR); both copied. NULL uv clears both (facet_texture is then
 * ignored). Errors: HV_ERR_INVALID (uv given without facet_texture, an index that names no
 * texture), HV_ERR_BAD_INPUT (a textured facet's coordinate not finite, or outside [0, 1] along
 * an axis its texture tiles HV_TILE_NONE: "NAME: facet F: texture coordinate (u, v) outside
 * [0, 1] and texture T does not tile"), HV_ERR_NOMEM. */
HV_API hv_status hv_mesh_set_corner_uvs(hv_mesh *mesh, const float *uv, const int32_t *facet_texture);
/* Owned by the mesh; NULL: none. */
HV_API const float *hv_mesh_corner_uvs(const hv_mesh *mesh);
HV_API const int32_t *hv_mesh_facet_textures(const hv_mesh *mesh);

/* In facet_texture: a facet with no colour at all, even though the mesh has corner colours
 * (hv_mesh_join gives it to the facets of parts without colour). */
#define HV_MESH_NO_COLOUR (-2)

/* Give the body named `body` one flat colour (0xRRGGBBAA, straight alpha), whatever its texture,
 * corner or material colours said (`--colour BODY=COLOUR` of voxelize);
 * the other facets keep their colours (a material's colour moves into corner colours); the body is
 * marked coloured, so the body rule paints it (hv_colour_mesh_bodies). Errors:
 * HV_ERR_NOT_FOUND ("gear.obj: no body 'hub' (bodies: rim, spokes)"), HV_ERR_NOMEM; the mesh is
 * unchanged on failure. */
HV_API hv_status hv_mesh_body_colour_set(hv_mesh *mesh, const char *body, uint32_t rgba);

/* Does any facet have a colour (by the rule above: a texture, corner colours, a material with a
 * display colour)? */
HV_API int hv_mesh_has_colour(const hv_mesh *mesh);

/* ---- reader notes ----------------------------------------------------------------------------
 * What a reader accepted but a person should know, one line each ("file: place: what"), in the
 * order found (a 3MF object whose triangles carry properties without a default pid). The CLI
 * prints them as warnings. Owned by the mesh; derived meshes (extract, join, transform) carry
 * none. */
HV_API size_t hv_mesh_note_count(const hv_mesh *mesh);
HV_API const char *hv_mesh_note_at(const hv_mesh *mesh, size_t i); /* i < count */

/* ---- what the file says about placement (3MF) ---------------------------------------------
 * The unit its coordinates were given in (3MF <model unit>: "micron", "millimeter", ...,
 * converted to mm on reading; NULL when the format names none) and its build items in file
 * order: the body each became (-1: an item of a support or other object, or one that places no
 * triangle), its object's id and name, and its transform (3x4 rows as hv_mesh_transform's, in
 * the file's unit; the identity when the item has none). Owned by the mesh; derived meshes
 * (extract, join, transform) carry none. */
typedef struct hv_mesh_item {
    int64_t body;            /* its first body */
    size_t bodies;           /* the bodies it became, from `body` on: 1, or for an item of
                                components one per mesh object it places (each in its own
                                material), 0 with body -1 */
    uint64_t object_id;
    const char *object_name; /* "" when the object has none */
    double transform[12];
} hv_mesh_item;
HV_API const char *hv_mesh_file_unit(const hv_mesh *mesh);
HV_API size_t hv_mesh_item_count(const hv_mesh *mesh);
HV_API const hv_mesh_item *hv_mesh_item_at(const hv_mesh *mesh, size_t i); /* NULL past the end */

/* The colour of facet f at barycentric coordinates bary (weights of its corners 0, 1, 2, summing
 * to 1), by the rule above: rgba receives sRGB-encoded red, green, blue and alpha in [0, 1].
 * Textures are sampled bilinearly (HV_FILTER_AUTO, HV_FILTER_LINEAR) between pixel centres, or
 * nearest, with the texture's tile styles (HV_TILE_NONE samples as HV_TILE_CLAMP). Returns 1, or
 * 0 (rgba untouched) when the facet has no colour or f is out of range. */
HV_API int hv_mesh_colour_at(const hv_mesh *mesh, size_t f, const double bary[3], float rgba[4]);

/* Free a mesh; NULL is allowed. */
HV_API void hv_mesh_destroy(hv_mesh *mesh);

HV_API size_t hv_mesh_vertex_count(const hv_mesh *mesh);
HV_API size_t hv_mesh_facet_count(const hv_mesh *mesh);
/* 3 floats per vertex; owned by the mesh. */
HV_API const float *hv_mesh_vertices(const hv_mesh *mesh);
/* 3 vertex indices per facet (v0, v1, v2, counter-clockwise seen from outside). */
HV_API const uint32_t *hv_mesh_facets(const hv_mesh *mesh);

/* Edge adjacency: for facet f and local edge e (0: v0v1, 1: v1v2, 2: v2v0),
 * neighbors[3f+e] is the facet across that edge, or HV_MESH_OPEN when no facet shares it.
 * Around a non-manifold edge each facet is paired with one of opposite direction when
 * possible (else the first one found); hv_mesh_edge_flags tells which edges those are. */
#define HV_MESH_OPEN (-1)
HV_API const int32_t *hv_mesh_neighbors(const hv_mesh *mesh);

/* Per facet: bit e set when local edge e is non-manifold (shared by 3+ facets). */
HV_API const uint8_t *hv_mesh_edge_flags(const hv_mesh *mesh);

/* The report, computed when the mesh was built; owned by the mesh. */
HV_API const hv_mesh_report *hv_mesh_get_report(const hv_mesh *mesh);

/* Where the mesh came from ("gear.stl"; "" for generated meshes); owned by the mesh. */
HV_API const char *hv_mesh_name(const hv_mesh *mesh);

/* Write binary STL (ascii = 0) or ASCII STL (ascii = 1) atomically (temporary file renamed
 * when complete). Errors: HV_ERR_INVALID (a name not ending in .stl, other than a special
 * file), HV_ERR_IO. */
HV_API hv_status hv_mesh_write_stl(const hv_mesh *mesh, const char *path, int ascii);

/* Write Wavefront OBJ atomically: every vertex (`v`, %.9g), then per body in order an `o NAME`
 * line, a `usemtl MATERIAL` line when the body has a material (a bare `usemtl` ends the one in
 * effect before a body without one) and its facets (`f`, 1-based). Control characters in names
 * are written as '_'. No .mtl file is written: materials are names only. So an assembly keeps
 * its bodies, their order and their materials. Errors: HV_ERR_INVALID (a name not ending in
 * .obj, other than a special file), HV_ERR_IO. */
HV_API hv_status hv_mesh_write_obj(const hv_mesh *mesh, const char *path);

/* hv_mesh_write_obj for a name ending in .obj (any case), else hv_mesh_write_stl (ascii as
 * there). Errors: theirs. */
HV_API hv_status hv_mesh_save(const hv_mesh *mesh, const char *path, int ascii);

/* A new mesh with every vertex moved by the affine map x' = A x + t, `matrix` row-major 3x4
 * ({A00, A01, A02, t0, A10, ...}); welded again, with the same bodies, materials and name. A
 * mirror (det A < 0) swaps two vertices of every facet, so facets stay outward. Errors:
 * HV_ERR_INVALID (an entry not finite, A singular, a vertex beyond the float range),
 * HV_ERR_NOMEM. */
HV_API hv_status hv_mesh_transform(const hv_mesh *mesh, const double matrix[12], hv_mesh **out);

#ifdef __cplusplus
}
#endif
#endif
