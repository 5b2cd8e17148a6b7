/* hovox/slice.h - the geometric slicer (Wu 2.4.1): a weighted directed graph (WDG) over the
 * facets of a mesh, built once and sliced by planes z = h into closed contour loops, oriented
 * and nested; layer height planning (uniform, adaptive); contour output as SVG and CLI. */
#ifndef HOVOX_SLICE_H
#define HOVOX_SLICE_H

#include "hovox/mesh.h"
#include "hovox/options.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ==== The slicer ===========================================================================
 *
 * Nodes of the WDG are facets; an arc joins two facets sharing an edge and carries Wu's
 * weight, the sum of the local vertex subscripts of that edge in the facet it leaves:
 * v0v1 -> 1, v0v2 -> 2, v1v2 -> 3 (so the edge of weight w is the one opposite vertex 3 - w).
 * Each arc also records the weight of the same edge in the facet it enters, so a traversal
 * knows the shared edge from the weights alone, without comparing coordinates. Every facet
 * has at most three arcs: the adjacency list is a fixed array of three slots per facet.
 *
 * Slicing a plane z = h walks the arcs (Wu's depth-first traversal): from a crossing facet,
 * compute the crossing on its exit edge, follow the arc of that edge to the neighbour, whose
 * entry point is the one just computed, and repeat until back at the start: one intersection
 * per facet, the loop comes out in order, no sorting of segments. Only facets whose z-range
 * contains h are touched: facets are kept sorted by their lowest z within classes of similar
 * z-extent, so finding the crossing facets costs O(classes * log n + crossing facets).
 *
 * Degenerate cases are decided by rule:
 *  - Symbolic perturbation: a vertex with z >= h counts as ABOVE the plane, z < h as below.
 *    A facet crosses the plane when it has vertices on both sides, so exactly two of its
 *    edges cross; the topology is that of the plane h - eps for an infinitesimal eps. A
 *    vertex lying exactly on the plane gives crossings located at that vertex, and the
 *    repeated point is emitted once. Facets and edges lying in the plane (all vertices
 *    "above") are not crossed: a plane through a flat top face yields the outline of that
 *    face (the section just below it); a plane through a flat bottom face yields nothing.
 *  - Non-manifold edges (three or more facets): the traversal follows the mesh's pairing
 *    (hv_mesh_neighbors: each facet continues into a facet of opposite edge direction), so
 *    two solids touching along an edge give two loops that touch at a point.
 *  - Open meshes: a traversal that reaches an edge used by one facet only is traced back from
 *    its start to the other open edge, giving an open polyline from boundary to boundary.
 *    Gap rule: after all chains of a layer are traced, the end of each open polyline is
 *    joined to the nearest start of an open polyline (itself included) when their distance
 *    is at most hv_slice_options.close_gap, repeatedly, in chain order; a polyline whose end
 *    comes back to its own start this way becomes a closed loop (gaps counted in
 *    hv_slice_loop.gaps). Ends join starts only (chains run the same way round the solid
 *    when the facets are consistently oriented), so an unwelded triangle soup is rejoined
 *    too. Polylines left open are reported as open (not part of the area or nesting).
 *  - Loops with fewer than 3 distinct points (a plane touching an apex) or zero area, and
 *    open polylines with fewer than 2, are dropped (counted in hv_slice_stats.dropped);
 *    consecutive repeated points are removed.
 *
 * Orientation and nesting: the facets' outward normals decide which side of a loop is
 * material. Each segment votes with its length times the cosine between its facet's
 * horizontal normal and the segment's right-hand side; a loop with material on its left is
 * kept, else reversed, so a few flipped facets cannot turn a loop, and when the whole mesh is
 * inside out (negative signed volume) every vote is negated. Outer boundaries come out
 * counter-clockwise seen from +z (positive area), holes (cavities) clockwise (negative area).
 * A body inside another body, or two overlapping bodies, are both outers: filled with the
 * nonzero rule they give the union, as the voxelizer does. A loop's parent is the smallest
 * loop containing it (point in polygon by crossing number, majority over up to 5 of its
 * vertices, so a single touching point does not decide); on well-formed meshes even depths
 * are outers and odd depths holes, and a loop without a vote (all its facets degenerate)
 * takes its orientation from that parity.
 *
 * Bodies (hv_mesh_body_*): a mesh of several bodies (an assembly) is sliced body by body: each
 * body is welded alone, so no arc joins two bodies even where they share vertices or faces;
 * the gap rule joins ends of one body only; a body's loops are oriented by its own facets (an
 * inside-out body is turned alone) and nested among themselves (a loop's parent is a loop of
 * its body). Every loop records its body. Filled with the nonzero rule the loops of all bodies
 * give their union (a body nested in another adds nothing; hv_slice_rasterize also unites
 * even-odd fills body by body).
 *
 * Thread safety: a slicer is immutable after hv_slicer_create; any number of threads may
 * slice it at the same time. Results depend only on (mesh, h, options), never on the thread
 * count or on the order in which layers are sliced. */
typedef struct hv_slicer hv_slicer;

/* Build the WDG and the z-sorted facet index from a mesh. The slicer copies what it needs
 * (vertices as doubles, facets, arcs); the mesh may be destroyed afterwards.
 * Errors: HV_ERR_INVALID (mesh NULL or without facets), HV_ERR_LIMIT (more than 2^31 - 1
 * facets), HV_ERR_NOMEM, HV_ERR_CANCELLED. On success *out is a new slicer, freed with
 * hv_slicer_destroy. */
HV_API hv_status hv_slicer_create(const hv_mesh *mesh, const hv_progress *progress,
                                  hv_slicer **out);

/* Free a slicer; NULL is allowed. */
HV_API void hv_slicer_destroy(hv_slicer *slicer);

/* Facts about the graph. */
typedef struct hv_slicer_info {
    size_t facets;
    size_t arcs;            /* directed arcs (2 per shared manifold edge) */
    size_t open_edges;      /* facet edges without a neighbour (open mesh boundary) */
    size_t nonmanifold_arcs; /* arcs across edges shared by 3+ facets */
    double bbox_min[3], bbox_max[3];
} hv_slicer_info;
HV_API void hv_slicer_get_info(const hv_slicer *slicer, hv_slicer_info *info);

/* The arc of `facet` with Wu weight `weight` (1: v0v1, 2: v0v2, 3: v1v2): stores the
 * neighbouring facet in *neighbor (HV_MESH_OPEN when the edge is open) and the weight of the
 * same edge in the neighbour in *neighbor_weight (0 when open).
 * Errors: HV_ERR_INVALID (facet or weight out of range). */
HV_API hv_status hv_slicer_arc(const hv_slicer *slicer, size_t facet, int weight,
                               int32_t *neighbor, int *neighbor_weight);

/* ==== Slicing one plane ==================================================================== */

/* Default gap rule distance (mm): open polyline ends at most this far apart are joined. */
#define HV_SLICE_DEFAULT_CLOSE_GAP 2.0

typedef struct hv_slice_options {
    double close_gap; /* mm, >= 0; 0 joins only ends that coincide exactly */
} hv_slice_options;

/* Fill *options with the defaults (close_gap = HV_SLICE_DEFAULT_CLOSE_GAP). */
HV_API void hv_slice_options_init(hv_slice_options *options);

typedef struct hv_slice_loop {
    const double *xy;  /* 2 * count doubles (x0, y0, x1, y1, ...), in order; a closed loop
                        * does not repeat its first point. Owned by the slice. */
    size_t count;      /* points */
    int closed;        /* 1: closed loop, 0: open polyline */
    int orientation;   /* +1 counter-clockwise seen from +z (outer), -1 clockwise (hole),
                        * 0 open polyline */
    int parent;        /* index of the smallest loop containing this one (for a hole: its
                        * outer loop; for an island: the hole it sits in); -1 when none or
                        * open */
    int depth;         /* nesting depth: 0 outermost; -1 open */
    int gaps;          /* gaps bridged by the gap rule to close this loop (0 for a loop that
                        * closed by itself) */
    double area;       /* signed area in mm^2: > 0 outer, < 0 hole, 0 open */
    int body;          /* the mesh body whose facets made it (hv_mesh_body_at; 0 for a mesh
                        * of one body) */
} hv_slice_loop;

typedef struct hv_slice_stats {
    double z;           /* the plane */
    size_t loops;       /* closed loops (outers + holes) */
    size_t outers, holes;
    size_t open;        /* open polylines left after the gap rule */
    size_t gaps_closed; /* gaps bridged by the gap rule in this slice */
    size_t dropped;     /* chains dropped for having fewer than 3 (closed) or 2 (open)
                         * distinct points */
    size_t points;      /* over all loops and polylines */
    size_t facets;      /* facets crossing the plane */
    double area;        /* total: outer areas minus hole areas (mm^2); where bodies overlap,
                         * the overlap counts once per body */
} hv_slice_stats;

/* One sliced plane: loops then open polylines. Opaque; read through the accessors. */
typedef struct hv_slice hv_slice;

/* Slice the plane z = h (options NULL = defaults). Any thread may call this concurrently on
 * the same slicer. A plane outside the mesh gives an empty slice.
 * Errors: HV_ERR_INVALID (h not finite, close_gap negative or not finite), HV_ERR_NOMEM.
 * On success *out is a new slice, freed with hv_slice_destroy. */
HV_API hv_status hv_slicer_slice(const hv_slicer *slicer, double h,
                                 const hv_slice_options *options, hv_slice **out);

/* Free a slice; NULL is allowed. */
HV_API void hv_slice_destroy(hv_slice *slice);

/* A slice of the plane z from closed loops made elsewhere (a Boolean of outlines, the iso-lines
 * of a field): loop i is count[i] points at xy[i] (x0, y0, x1, y1, ...; the first not repeated),
 * counter-clockwise for an outer boundary and clockwise for a hole, as the slicer gives them;
 * all of body 0. They are copied, consecutive repeated points removed, nested as the slicer
 * nests its loops (parent, depth) and kept in their direction; loops of fewer than 3 distinct
 * points or zero area are dropped (stats.dropped). stats.facets is 0. Errors: HV_ERR_INVALID (a
 * coordinate not finite, z not finite), HV_ERR_NOMEM. Free with hv_slice_destroy. */
HV_API hv_status hv_slice_from_loops(double z, const double *const *xy, const size_t *count, size_t n,
                                     hv_slice **out);

/* Number of entries in hv_slice_loops: the closed loops come first (hv_slice_stats.loops of
 * them, in traversal order of their lowest-numbered facet), then the open polylines. */
HV_API size_t hv_slice_loop_count(const hv_slice *slice);
/* The loops; owned by the slice, valid until hv_slice_destroy. */
HV_API const hv_slice_loop *hv_slice_loops(const hv_slice *slice);
/* The statistics; owned by the slice. */
HV_API const hv_slice_stats *hv_slice_get_stats(const hv_slice *slice);

/* ==== Layer planning =======================================================================
 *
 * A layer is the slab [bottom, top]; it is cut at its mid-height z = (bottom + top) / 2, so
 * the contour is the section halfway through the material it stands for (the staircase
 * error is split evenly above and below). Layers start at the mesh's lowest z. The last
 * layer is the one whose mid-height is still below the mesh's highest z: the printed height
 * is the mesh height rounded to the nearest layer boundary. */
typedef struct hv_layer {
    double bottom, top; /* mm */
    double z;           /* where the layer is cut: (bottom + top) / 2 */
} hv_layer;

typedef struct hv_layer_plan hv_layer_plan;

/* Largest number of layers a plan may hold. */
#define HV_LAYER_PLAN_MAX 10000000

/* Uniform layers: the first layer `first_height` thick (<= 0: same as `height`), then layers
 * `height` thick. Boundaries are computed as zmin + first + i * height (no accumulated
 * rounding). Errors: HV_ERR_INVALID (height not finite or <= 0, first_height not finite),
 * HV_ERR_LIMIT (more than HV_LAYER_PLAN_MAX layers, naming the count), HV_ERR_NOMEM.
 * *out is freed with hv_layer_plan_destroy. */
HV_API hv_status hv_slicer_plan_uniform(const hv_slicer *slicer, double first_height,
                                        double height, hv_layer_plan **out);
/* The same over the height range [zmin, zmax] of any part (a solid's, hovox/solid.h).
 * Errors: as hv_slicer_plan_uniform; HV_ERR_INVALID (zmin, zmax not finite or zmax < zmin). */
HV_API hv_status hv_layer_plan_uniform(double zmin, double zmax, double first_height, double height,
                                       hv_layer_plan **out);

/* Adaptive layers by the cusp-height criterion (Dolenc & Makela 1994; Wu 2.4.1 "adaptive
 * slicing"): a facet with unit normal n tolerates a layer of height cusp / |n_z| (the
 * staircase step measured along its normal stays below `cusp`), so nearly horizontal
 * surfaces get thin layers and vertical walls thick ones. A layer starting at z takes the
 * largest height h <= max_height that every facet reaching into (z, z + h) tolerates:
 * h = min over facets f overlapping (z, z + max_height) of max(tolerance_f, zmin_f - z),
 * clamped to [min_height, max_height]. A flat face therefore ends a layer exactly at its
 * height when it lies at least min_height above the layer's bottom. Zero-area facets are
 * ignored. cusp <= 0 means cusp = min_height. first_height > 0 fixes the first layer.
 * Errors: HV_ERR_INVALID (not 0 < min_height <= max_height, values not finite),
 * HV_ERR_LIMIT, HV_ERR_NOMEM. *out is freed with hv_layer_plan_destroy. */
HV_API hv_status hv_slicer_plan_adaptive(const hv_slicer *slicer, double first_height,
                                         double min_height, double max_height, double cusp,
                                         hv_layer_plan **out);

/* A contour job's layers and contours, as one set of options. */
typedef struct hv_contours_options {
    double layer_height; /* uniform layers (mm), or 0 with adaptive */
    double adaptive[3];  /* adaptive layers: min, max, cusp (cusp 0: min); min 0: uniform */
    double first_layer;  /* 0: as the others */
    double close_gap;    /* the gap rule (default HV_SLICE_DEFAULT_CLOSE_GAP) */
    int binary;          /* contour files in binary CLI (needs a .cli output) */
    const char *output;  /* hv_contours_write: the contour file (.svg or .cli), or NULL */
    const char *per_layer; /* hv_contours_write: a directory of one SVG per layer
                            * (layer-00000.svg, ...), or NULL */
} hv_contours_options;

HV_API void hv_contours_options_init(hv_contours_options *o);
/* As an option set (hovox/options.h): keys layer_height, adaptive ("MIN,MAX[,CUSP]"),
 * first_layer, close_gap, binary, output, per_layer (output paths: the front end keeps the
 * strings alive). Static data. */
HV_API const hv_option_set *hv_contours_option_set(void);
/* Domains; exactly one of layer_height and adaptive. Errors: HV_ERR_INVALID naming the option. */
HV_API hv_status hv_contours_options_check(const hv_contours_options *o);
/* hv_slicer_plan_uniform or hv_slicer_plan_adaptive as the options say; their errors. */
HV_API hv_status hv_slicer_plan(const hv_slicer *slicer, const hv_contours_options *o,
                                hv_layer_plan **out);

/* A plan from explicit layers (copied): each needs finite bottom < top with
 * bottom <= z <= top, and z strictly increasing from layer to layer.
 * Errors: HV_ERR_INVALID (naming the layer and value), HV_ERR_LIMIT, HV_ERR_NOMEM. */
HV_API hv_status hv_layer_plan_create(const hv_layer *layers, size_t count,
                                      hv_layer_plan **out);

HV_API size_t hv_layer_plan_count(const hv_layer_plan *plan);
/* The layers, bottom to top; owned by the plan. */
HV_API const hv_layer *hv_layer_plan_layers(const hv_layer_plan *plan);
/* Free a plan; NULL is allowed. */
HV_API void hv_layer_plan_destroy(hv_layer_plan *plan);

/* ==== Slicing every layer of a plan ======================================================== */

/* Receives the layers in order (index 0, 1, 2, ...) on the thread that called
 * hv_slicer_slice_plan. *slice is owned by the caller of the sink during the call and freed
 * after it returns; a sink that wants to keep it sets *slice = NULL and frees it later with
 * hv_slice_destroy. A status other than HV_OK stops the run, which returns that status
 * (the sink sets the message with hv_error_set). */
typedef hv_status (*hv_slice_sink_fn)(void *user, size_t index, const hv_layer *layer,
                                      hv_slice **slice);

/* Slice every layer of `plan` at its z, multi-threaded (hv_threads() workers) over windows
 * of consecutive layers, handing each finished layer to `sink` in order; only a window of
 * slices is held in memory at a time, so memory does not grow with the number of layers.
 * Deterministic: identical to hv_slicer_slice at each z. `progress` (may be NULL) is called
 * on the calling thread with stage "contours"; a nonzero return cancels.
 * Errors: HV_ERR_INVALID (NULL plan or sink, bad options), HV_ERR_NOMEM, HV_ERR_CANCELLED,
 * or what the sink returned. */
HV_API hv_status hv_slicer_slice_plan(const hv_slicer *slicer, const hv_layer_plan *plan,
                                      const hv_slice_options *options, hv_slice_sink_fn sink,
                                      void *user, const hv_progress *progress);

/* ==== Contour files ========================================================================
 *
 * SVG: one <svg> whose user unit is 1 mm (width/height in mm, viewBox over the mesh's xy
 * bounding box); y points up as seen from +z (an outer group flips the axis with
 * transform="scale(1,-1)", coordinates in the paths are the true x, y). One
 * <g id="layer-N" class="layer" data-index="N" data-z="..." data-bottom="..." data-top="...">
 * per layer holding one <path class="loops"> with all closed loops (fill-rule="evenodd",
 * outer loops counter-clockwise, holes clockwise) and, when there are any, one
 * <path class="open"> with the open polylines (no fill, red stroke).
 *
 * CLI (Common Layer Interface 2.0), units mm ($$UNITS/00000001.000000): header
 * $$HEADERSTART, $$ASCII or $$BINARY, $$UNITS, $$VERSION/200, $$LABEL/1,<label>,
 * $$DIMENSION/xmin,ymin,zmin,xmax,ymax,zmax, $$LAYERS/n, $$HEADEREND. Per the CLI convention
 * $$LAYER/z gives the TOP of a layer, and the thickness of a layer is the difference to the
 * previous one; the first layer's thickness is given by a leading "zero layer" at the
 * bottom of the first layer without polylines (counted in $$LAYERS; an empty plan has
 * $$LAYERS/000000 and no layer). Polylines:
 * $$POLYLINE/1,dir,n,x1,y1,...,xn,yn with dir 1 = counter-clockwise (outer), 0 = clockwise
 * (hole), 2 = open; closed polylines repeat their first point at the end (n counts it).
 * ASCII: $$GEOMETRYSTART ... $$GEOMETRYEND, numbers rounded to 6 decimals with trailing
 * zeros dropped ("12.5", "40"). Binary: after
 * $$HEADEREND, little-endian commands: uint16 127 (layer, long) + float32 z; uint16 130
 * (polyline, long) + int32 id, dir, n + float32 x, y per point. */
typedef enum hv_contour_format {
    HV_CONTOUR_SVG = 0,
    HV_CONTOUR_CLI_ASCII = 1,
    HV_CONTOUR_CLI_BINARY = 2
} hv_contour_format;

/* The format a contour file's name asks for: .svg, or .cli (binary CLI when `binary`), case
 * aside. Errors: HV_ERR_INVALID ("output 'x.txt' has an unknown extension (use .svg or .cli)",
 * "binary needs a .cli output, not 'x.svg'"). */
HV_API hv_status hv_contour_format_for_path(const char *path, int binary, hv_contour_format *out);

typedef struct hv_contour_writer hv_contour_writer;

/* Open a contour file for `layers` layers (the CLI header states the count; the SVG needs
 * none) over the bounding box bbox_min/bbox_max (mm; x and y size the SVG, all three go to
 * $$DIMENSION). `label` (may be NULL) names the part ($$LABEL, SVG <title>). The file is
 * written under a temporary name and renamed by hv_contour_writer_close.
 * Errors: HV_ERR_INVALID (bad format, non-finite box), HV_ERR_IO (naming the path), NOMEM.
 * *out is finished with hv_contour_writer_close or hv_contour_writer_abort. */
HV_API hv_status hv_contour_writer_open(const char *path, hv_contour_format format,
                                        size_t layers, const double bbox_min[3],
                                        const double bbox_max[3], const char *label,
                                        hv_contour_writer **out);

/* hv_contour_writer_open for the loops of an assembly: `bodies` names its n bodies (copied; the
 * loops' hv_slice_loop.body indexes them). CLI: one part per body, "$$LABEL/k,<name>" for body
 * k - 1, each polyline with its body's id k; SVG: per layer one <path class="loops"
 * data-body="<name>"> (and one "open" path) per body that has loops there. n <= 1: exactly
 * hv_contour_writer_open. Errors: those of hv_contour_writer_open; HV_ERR_INVALID (n > 1
 * without names). */
HV_API hv_status hv_contour_writer_open_bodies(const char *path, hv_contour_format format,
                                               size_t layers, const double bbox_min[3],
                                               const double bbox_max[3], const char *label,
                                               const char *const *bodies, size_t n,
                                               hv_contour_writer **out);

/* Append one layer (in increasing order). The slice's loops are written as they are
 * (open polylines included). Errors: HV_ERR_INVALID (more layers than announced),
 * HV_ERR_IO (write failed, naming the path), HV_ERR_NOMEM. */
HV_API hv_status hv_contour_writer_add(hv_contour_writer *writer, const hv_layer *layer,
                                       const hv_slice *slice);

/* Finish the file and rename it to its final name; frees the writer in every case.
 * Errors: HV_ERR_INVALID (fewer layers than announced), HV_ERR_IO; on error no file is left
 * under the final name. NULL is allowed (returns HV_OK). */
HV_API hv_status hv_contour_writer_close(hv_contour_writer *writer);

/* Drop the file being written (nothing is left on disk) and free the writer; NULL allowed. */
HV_API void hv_contour_writer_abort(hv_contour_writer *writer);

/* ==== A contour job: a mesh sliced into files =============================================== */

typedef struct hv_contours_summary {
    size_t layers;                 /* in the plan */
    size_t loops, holes, open, gaps_closed, dropped; /* over all layers (hv_slice_stats) */
    double bbox_min[3], bbox_max[3]; /* the mesh's bounding box (mm) */
} hv_contours_summary;

/* Called for every layer in order, after it was written to the files; `slice` is borrowed for
 * the call. A status other than HV_OK stops the job (set the message with hv_error_set). */
typedef hv_status (*hv_contours_layer_fn)(void *user, size_t index, const hv_layer *layer,
                                          const hv_slice *slice);

/* Plan the layers of `mesh` as `o` says and slice every one (hv_slicer_slice_plan): into
 * o->output (the format from its name, hv_contour_format_for_path), into o->per_layer (one SVG
 * per layer, the directory written whole: hv_outdir rules, an existing directory replaced only
 * when it holds nothing but layer SVGs), and to `layer` (may be NULL). Nothing is left under a
 * final name when the job fails. `name` (may be NULL) is the mesh's file: it prefixes errors
 * about the mesh, and its base name labels the files ("hovox" when NULL). `summary` (may be
 * NULL) receives the counts. Progress stage "contours".
 * Errors: HV_ERR_INVALID (options; a mesh with no layer: "the mesh is H mm high: no layer of
 * T mm has its middle inside it"), HV_ERR_LIMIT (too many layers), HV_ERR_IO (naming the
 * file), HV_ERR_NOMEM, HV_ERR_CANCELLED, or what `layer` returned. */
HV_API hv_status hv_contours_write(const hv_mesh *mesh, const hv_contours_options *o, const char *name,
                                   hv_contours_layer_fn layer, void *user,
                                   const hv_progress *progress, hv_contours_summary *summary);

#ifdef __cplusplus
}
#endif
#endif
