/* slicing/layers.c - printer slice stacks after Wu 2.4.2 ("heterogeneous object slicing with
 * geometric constraint"): per layer the WDG contour rasterised at printer resolution, material
 * from the voxel layers around the cut (eq. 31-32, z part) resampled by pixel overlap
 * interpolation, or the grading definition evaluated directly; halftoning; PNG stack. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/internal.h"
#include "core/json.h"
#include "hovox/colour.h"
#include "hovox/material.h"
#include "hovox/image.h"
#include "hovox/solid.h"
#include "hovox/voxelize.h"
#include "layers_internal.h"

/* ---- the job -------------------------------------------------------------------------------- */

#define RUN_LAYERS 8 /* consecutive layers per work unit outside error diffusion */
#define WINDOW_PAD 3 /* voxels around the printer image in the resampling window */
#define BAND_ROWS 128 /* rows of fractions a worker holds while it halftones a model's layer by blue noise */

typedef struct worker {
    int ready;
    uint8_t *mask, *out, *gray;
    float *frac, *err, *next;
    float *xtmp; /* POI x pass: float is ample for weighted means of fractions */
    int slab_k[2], slab_ok[2], slab_any[2];
    uint8_t *slab_occ[2];
    float *slab_mat[2];
    const struct slab_store *store; /* a tray part's layer: the part's shared voxel slabs (else the two above) */
    float *vimg;
    uint8_t *vstate;
    int32_t *front, *front2;
    uint8_t live[HV_MAX_MATERIALS]; /* the window image's materials not zero everywhere (voxel_image) */
    double fd[HV_MAX_MATERIALS];
    hv_accessor acc;
} worker;

typedef struct job {
    const hv_layers_options *o;
    const hv_volume *model;
    const hv_layers_source *src; /* the shape and materials from data at each pixel (a scan), or NULL */
    hv_solid *solid; /* the model's exact shape (hovox/solid.h), or the mesh given */
    char *shape_name; /* what the manifest calls the shape: the mesh given, else the recorded mesh's
                         name (a plain record) or its leaves' names joined by the tree's ops */
    hv_layer_plan *plan;
    const hv_layer *layers;
    size_t nlayers, first, last;
    hv_slice_options sopt;
    hv_raster_grid grid;
    int W, H, m;
    size_t plane;
    double bbox_min[3], bbox_max[3];
    char warnings[1024]; /* for the report, even when the plan fails */
    /* model */
    hv_material_table *table;
    int occ_grid, mat_grid[HV_MAX_MATERIALS];
    hv_transform xf;
    int32_t klo, khi; /* model's index range in z */
    int vi0, vj0, vw, vh;
    hv_poi_axis ax, ay;
    float *axw, *ayw; /* the operators' weights as floats, for the passes */
    /* the x operator padded to axl taps per column (zero weights around its own, the start moved
     * back where the row ends), so the x pass has a fixed tap count: column c reads voxels
     * axs[c] .. axs[c] + axl - 1 with weights axp[c * axl ..]; axl 0 when the row is too short */
    int axl;
    int *axs;
    float *axp;
    /* a model painted in colour with its colour.depth (depth_grid >= 0, else -1): nd 1, the depth
     * decoded as one more slab plane and carried as window plane m; per printer column and row the
     * bilinear cell of the pixel centre (first voxel bx/by, weight of the second bxt/byt) and the
     * voxels that cell and the POI taps span (bxu0..bxu1, byu0..byu1); per voxel column the printer
     * columns whose span holds it (cf..cl, none: cf > cl): see depth_band */
    int depth_grid, nd;
    float depth_mm;
    int *bx, *bxu0, *bxu1, *by, *byu0, *byu1, *cf, *cl;
    float *bxt, *byt;
    hv_object *obj;
    /* halftone */
    const uint32_t *ranks;
    int bn_off[3], bn_cached;
    uint8_t palette[3 * (HV_MAX_MATERIALS + 1)];
    int palette_size, bit_depth;
    /* output */
    int no_files;       /* a tray's part: layers are rendered into the worker, not written */
    size_t run_lo, run_hi; /* the layers this process renders (all of [first, last) alone) */
    int placed, c0, r0; /* on a plate: the image's first column and row on the plate's grid */
    size_t lift;        /* on a plate: tray layers below the part's first layer */
    hv_stack_out out; /* the stack being written (hv_layers_write) */
    /* per-layer statistics, indexed by layer - first */
    uint64_t *st_pixels, *st_count, *st_fallback;
    double *st_target, *st_dsum, *st_dmax;
    size_t *st_open;
    /* workers and progress */
    worker *workers;
    int threads;
    const hv_progress *progress;
    atomic_size_t done;
    atomic_int cancel;
    uint64_t memory, fixed_memory; /* planned peak; its part besides the workers */
} job;

static int uses_model(const hv_layers_options *o) { return o->mode != HV_LAYERS_MASK; }
static int needs_object(const hv_layers_options *o)
{
    return uses_model(o) && !o->source && (o->method == HV_LAYERS_DIRECT || o->compare);
}
/* the materials come from voxels (slabs, POI), not from a source at the pixels */
static int uses_voxels(const job *J) { return uses_model(J->o) && !J->src; }
static int ed_mode(const job *J);
/* a model's layer halftoned by blue noise, band by band (banded_layer) */
static int banded(const job *J) { return uses_voxels(J) && J->o->mode == HV_LAYERS_HALFTONE && !ed_mode(J); }

static void job_free(job *J)
{
    hv_zip_abort(J->out.zip);
    J->out.zip = NULL;
    if (J->workers) {
        for (int t = 0; t < J->threads; ++t) {
            worker *w = &J->workers[t];
            free(w->mask);
            free(w->out);
            free(w->gray);
            free(w->frac);
            free(w->err);
            free(w->next);
            free(w->xtmp);
            for (int s = 0; s < 2; ++s) {
                free(w->slab_occ[s]);
                free(w->slab_mat[s]);
            }
            free(w->vimg);
            free(w->vstate);
            free(w->front);
            free(w->front2);
        }
        free(J->workers);
    }
    hv_poi_axis_free(&J->ax);
    hv_poi_axis_free(&J->ay);
    free(J->axw);
    free(J->ayw);
    free(J->axs);
    free(J->axp);
    free(J->bx);
    free(J->bxu0);
    free(J->bxu1);
    free(J->bxt);
    free(J->by);
    free(J->byu0);
    free(J->byu1);
    free(J->byt);
    free(J->cf);
    free(J->cl);
    hv_object_destroy(J->obj);
    hv_material_table_destroy(J->table);
    hv_layer_plan_destroy(J->plan);
    hv_solid_close(J->solid);
    free(J->shape_name);
    free(J->st_pixels);
    free(J->st_count);
    free(J->st_fallback);
    free(J->st_target);
    free(J->st_dsum);
    free(J->st_dmax);
    free(J->st_open);
    free(J->out.tmp);
    memset(J, 0, sizeof *J);
}

static int ed_mode(const job *J)
{
    return J->o->mode == HV_LAYERS_HALFTONE && J->o->halftone == HV_HALFTONE_ERROR_DIFFUSION;
}

/* A worker's buffers (error diffusion's two carried planes aside) and their bytes for job J. */
enum { WB_MASK, WB_OUT, WB_GRAY, WB_FRAC, WB_XTMP, WB_OCC0, WB_OCC1, WB_MAT0, WB_MAT1, WB_VIMG, WB_VSTATE, WB_FRONT,
       WB_FRONT2, WB_COUNT };

static void worker_sizes(const job *J, uint64_t sz[WB_COUNT])
{
    uint64_t px = (uint64_t)J->W * (uint64_t)J->H, m = (uint64_t)J->m;
    memset(sz, 0, WB_COUNT * sizeof *sz);
    sz[WB_MASK] = px;
    sz[WB_OUT] = J->o->mode == HV_LAYERS_MASK ? 0 : px;       /* halftoned */
    sz[WB_GRAY] = J->o->mode == HV_LAYERS_FRACTIONS ? px : 0; /* a fraction's image */
    if (J->src && uses_model(J->o)) sz[WB_FRAC] = px * m * 4;
    if (!uses_voxels(J)) return;
    uint64_t vox = (uint64_t)J->vw * (uint64_t)J->vh;
    /* fractions: a band of rows (banded_layer), else the layer's */
    sz[WB_FRAC] = (banded(J) ? (uint64_t)J->W * (uint64_t)HV_MIN(J->H, BAND_ROWS) : px) * m * 4;
    sz[WB_XTMP] = (uint64_t)J->vh * (uint64_t)J->W * 4; /* the x pass */
    sz[WB_OCC0] = sz[WB_OCC1] = vox;                    /* two voxel slabs */
    sz[WB_MAT0] = sz[WB_MAT1] = vox * (m + (uint64_t)J->nd) * 4;
    sz[WB_VIMG] = vox * (m + (uint64_t)J->nd) * 4; /* filled image, state, fronts */
    sz[WB_VSTATE] = vox;
    sz[WB_FRONT] = sz[WB_FRONT2] = vox * 4;
}

/* Point w's buffers at buf (as worker_sizes orders them). */
static void worker_point(worker *w, void *const buf[WB_COUNT])
{
    w->mask = buf[WB_MASK];
    w->out = buf[WB_OUT];
    w->gray = buf[WB_GRAY];
    w->frac = buf[WB_FRAC];
    w->xtmp = buf[WB_XTMP];
    w->slab_occ[0] = buf[WB_OCC0];
    w->slab_occ[1] = buf[WB_OCC1];
    w->slab_mat[0] = buf[WB_MAT0];
    w->slab_mat[1] = buf[WB_MAT1];
    w->vimg = buf[WB_VIMG];
    w->vstate = buf[WB_VSTATE];
    w->front = buf[WB_FRONT];
    w->front2 = buf[WB_FRONT2];
}

static uint64_t worker_bytes(const job *J)
{
    uint64_t sz[WB_COUNT], b = (uint64_t)1 << 20; /* libpng and zlib state, contour crossings */
    worker_sizes(J, sz);
    for (int k = 0; k < WB_COUNT; ++k) b += sz[k];
    if (ed_mode(J)) b += 2 * (uint64_t)J->W * (uint64_t)J->H * (uint64_t)J->m * 4;
    return b;
}

static void mesh_warning(job *J);

/* The manifest's "mesh": the mesh given; without one, the recorded shape's leaves ("plate.stl",
 * "plate.stl subtract rod.stl"), so a plain model cut without its mesh writes the same manifest. */
static void node_text(const hv_geometry *g, size_t i, int top, hv_buf *b)
{
    const hv_geometry_node *nd = hv_geometry_node_at(g, i);
    if (nd->op < 0) {
        hv_buf_puts(b, hv_geometry_leaf_at(g, nd->leaf)->name);
        return;
    }
    if (!top) hv_buf_puts(b, "(");
    node_text(g, nd->a, 0, b);
    hv_buf_printf(b, " %s ", hv_geometry_op_name((hv_geometry_op)nd->op));
    node_text(g, nd->b, 0, b);
    if (!top) hv_buf_puts(b, ")");
}

static hv_status shape_name(job *J, const hv_volume *model, const hv_layers_options *o)
{
    if (o->mesh_name || !model || !hv_geometry_present(model)) return J->shape_name = NULL, HV_OK;
    hv_geometry *g;
    hv_status st = hv_geometry_read(model, &g);
    if (st != HV_OK) return st;
    hv_buf b;
    hv_buf_init(&b);
    if (hv_geometry_shape_is_leaf(g)) hv_buf_puts(&b, hv_geometry_leaf_at(g, 0)->name);
    else node_text(g, hv_geometry_node_count(g) - 1, 1, &b);
    hv_geometry_destroy(g);
    if (b.failed) {
        hv_buf_free(&b);
        return HV_ERR_NOMEM;
    }
    J->shape_name = b.data;
    return HV_OK;
}

/* Planning a job, in the order its checks report: the shape and the layer range, the printer
 * grid (alone or on a plate), the model's grids, the voxel window and its operators, the palette
 * and the memory budget. Each step reads what the ones before it set in J; the first failing
 * step's status is the plan's. */

/* The shape (the model's own, or the mesh given as an override that must match), the manifest's
 * name for it, the uniform layer plan over its z box and the layer range [first, last). */
static hv_status job_plan_shape(job *J, const hv_mesh *mesh, const hv_volume *model, const hv_layers_options *o)
{
    hv_status st = HV_OK;
    if (J->src) { /* a source brings its box and its name (a scan, issue 30) */
        if (mesh || model) return hv_error_set(HV_ERR_INVALID, "layers: a source and a model or mesh");
        memcpy(J->bbox_min, J->src->bbox_min, sizeof J->bbox_min);
        memcpy(J->bbox_max, J->src->bbox_max, sizeof J->bbox_max);
        if (J->src->name && !(J->shape_name = hv_strdup(J->src->name))) return HV_ERR_NOMEM;
    } else {
        if (!mesh && !model) return hv_error_set(HV_ERR_INVALID, "layers: no model and no mesh");
        if (uses_model(o) && !model)
            return hv_error_set(HV_ERR_INVALID,
                                "layers: %s mode needs a graded model (only mask mode works from the mesh alone)",
                                hv_layers_mode_name(o->mode));
        /* the shape: the model's own (issue 28), a mesh given only as an override that must match */
        st = hv_solid_for_model(model, mesh, "layers", o->model_name, o->mesh_name, NULL, &J->solid);
        if (st != HV_OK) return st;
        hv_solid_bbox(J->solid, J->bbox_min, J->bbox_max);
        if (mesh) mesh_warning(J);
        if ((st = shape_name(J, model, o)) != HV_OK) return st;
    }
    hv_slice_options_init(&J->sopt);
    J->sopt.close_gap = o->close_gap;
    st = hv_layer_plan_uniform(J->bbox_min[2], J->bbox_max[2], 0, o->layer_height, &J->plan);
    if (st != HV_OK) return st;
    J->nlayers = hv_layer_plan_count(J->plan);
    J->layers = hv_layer_plan_layers(J->plan);
    if (J->nlayers == 0)
        return hv_error_set(HV_ERR_INVALID, "%s: the mesh is %g mm high: no layer of %g mm has its middle inside it",
                            o->mesh_name ? o->mesh_name : "layers", J->bbox_max[2] - J->bbox_min[2],
                            o->layer_height);
    J->first = o->first;
    J->last = o->last ? o->last : J->nlayers;
    if (J->first >= J->nlayers || J->last > J->nlayers || J->first >= J->last)
        return hv_error_option(HV_ERR_INVALID, "%s: {layers} %zu:%zu is outside the %zu layers of the plan (0:%zu)",
                               o->model_name ? o->model_name : o->mesh_name ? o->mesh_name : "layers", o->first,
                               J->last, J->nlayers, J->nlayers);
    return HV_OK;
}

/* The printer grid (J->W, H, plane, grid) over the shape's xy box plus the margin and the
 * threshold band; on a plate (pl), the part's box on the plate's pixel grid, which must lie on
 * the plate (J->placed, c0, r0, lift). */
static hv_status job_plan_grid(job *J, const hv_layers_options *o, const hv_layers_place *pl)
{
    const double *bmin = J->bbox_min, *bmax = J->bbox_max;
    double sx = 25.4 / o->dpi[0], py = 25.4 / o->dpi[1];
    double mx = (double)o->margin + ceil(o->threshold / sx), my = (double)o->margin + ceil(o->threshold / py);
    double wd = ceil((bmax[0] - bmin[0]) / sx - 1e-9) + 2 * mx;
    double hd = ceil((bmax[1] - bmin[1]) / py - 1e-9) + 2 * my;
    double gx = bmin[0] - mx * sx, gy = bmax[1] + my * py;
    if (pl) {
        /* the part's box on the plate's pixel grid: pixel (c, r) of the plate covers x in
         * [c sx, (c+1) sx) and y in (plate_y - (r+1) py, plate_y - r py] */
        double tx = pl->x - 0.5 * (bmin[0] + bmax[0]);
        double ty = pl->y - 0.5 * (bmin[1] + bmax[1]);
        double bx0 = bmin[0] + tx, bx1 = bmax[0] + tx;
        double by0 = bmin[1] + ty, by1 = bmax[1] + ty;
        if (bx0 < -1e-9 || by0 < -1e-9 || bx1 > pl->plate_x + 1e-9 || by1 > pl->plate_y + 1e-9)
            return hv_error_option(HV_ERR_INVALID, "{place} %g,%g puts the part off the %s plate: its box spans x %.4g..%.4g, "
                                   "y %.4g..%.4g mm (the plate is %g x %g mm)", pl->x, pl->y, pl->plate, bx0, bx1,
                                   by0, by1, pl->plate_x, pl->plate_y);
        double c0 = floor((bmin[0] + tx) / sx + 1e-9) - mx, c1 = ceil((bmax[0] + tx) / sx - 1e-9) + mx;
        double r0 = floor((pl->plate_y - (bmax[1] + ty)) / py + 1e-9) - my;
        double r1 = ceil((pl->plate_y - (bmin[1] + ty)) / py - 1e-9) + my;
        if (fabs(c0) > 1e9 || fabs(r0) > 1e9) return hv_error_set(HV_ERR_INVALID, "layers: the placement is off any plate");
        wd = HV_MAX(c1 - c0, 1.0);
        hd = HV_MAX(r1 - r0, 1.0);
        gx = c0 * sx - tx;
        gy = pl->plate_y - r0 * py - ty;
        J->placed = 1;
        J->c0 = (int)c0;
        J->r0 = (int)r0;
        J->lift = pl->lift;
    }
    wd = HV_MAX(wd, 1.0);
    hd = HV_MAX(hd, 1.0);
    if (wd > (double)(1 << 30) || hd > (double)(1 << 30) || wd * hd > 4e12)
        return hv_error_set(HV_ERR_LIMIT, "layers: the image would be %.0f x %.0f pixels", wd, hd);
    J->W = (int)wd;
    J->H = (int)hd;
    J->plane = (size_t)J->W * (size_t)J->H;
    J->grid.width = J->W;
    J->grid.height = J->H;
    J->grid.pixel[0] = sx;
    J->grid.pixel[1] = -py;
    J->grid.origin[0] = gx;
    J->grid.origin[1] = gy;
    return HV_OK;
}

/* The model's material table and its grids (J->table, m, occ_grid, mat_grid): a graded model
 * with an occupied voxel. Only for the modes that read the model. */
static hv_status job_plan_materials(job *J, const hv_volume *model)
{
    hv_status st = hv_material_table_load(model, &J->table);
    if (st == HV_ERR_NOT_FOUND)
        return hv_error_option(HV_ERR_BAD_INPUT, "the model has no materials (grade it first with 'hovox grade'; "
                                              "{mode} mask needs none)");
    if (st != HV_OK) return st;
    J->m = hv_material_count(J->table);
    if (J->m < 1 || J->m > HV_MAX_MATERIALS)
        return hv_error_set(HV_ERR_BAD_INPUT, "the model's material table holds %d materials", J->m);
    J->occ_grid = hv_volume_grid_find(model, "occupancy");
    if (J->occ_grid < 0 || hv_volume_grid_type(model, J->occ_grid) != HV_GRID_BOOL)
        return hv_error_set(HV_ERR_BAD_INPUT, "the model has no bool grid 'occupancy'");
    for (int j = 0; j < J->m; ++j) {
        J->mat_grid[j] = hv_material_grid(model, J->table, j);
        if (J->mat_grid[j] < 0)
            return hv_error_set(HV_ERR_BAD_INPUT, "the model has no grid 'material.%s'", hv_material_name(J->table, j));
    }
    if (hv_volume_mask_count(model, J->occ_grid) == 0)
        return hv_error_set(HV_ERR_BAD_INPUT, "the model has no occupied voxel");
    J->depth_grid = hv_colour_depth_grid(model, &J->depth_mm);
    J->nd = J->depth_grid >= 0;
    return HV_OK;
}

/* A source's material table (no grids: it gives the fractions at the pixels itself). */
static hv_status job_plan_source_materials(job *J)
{
    if (!J->src->table) return hv_error_set(HV_ERR_INVALID, "layers: the source has no materials");
    hv_status st = hv_material_table_clone(J->src->table, &J->table);
    if (st != HV_OK) return st;
    J->m = hv_material_count(J->table);
    if (J->m < 1 || J->m > HV_MAX_MATERIALS)
        return hv_error_set(HV_ERR_BAD_INPUT, "the source's material table holds %d materials", J->m);
    return HV_OK;
}

/* The model's transform and z index range (J->xf, klo, khi); the shape must lie inside the
 * model's voxels, one voxel of tolerance. */
static hv_status job_plan_fit(job *J, const hv_volume *model)
{
    hv_transform xf = hv_volume_get_transform(model);
    J->xf = xf;
    int32_t lo[3], hi[3];
    if (!hv_volume_index_bbox(model, lo, hi)) return hv_error_set(HV_ERR_BAD_INPUT, "the model is empty");
    J->klo = lo[2];
    J->khi = hi[2];
    for (int a = 0; a < 3; ++a) {
        double wlo = xf.origin[a] + ((double)lo[a] - 1.5) * xf.voxel[a];
        double whi = xf.origin[a] + ((double)hi[a] + 1.5) * xf.voxel[a];
        if (J->bbox_min[a] < wlo || J->bbox_max[a] > whi)
            return hv_error_set(HV_ERR_BAD_INPUT,
                                "the mesh (%c from %g to %g) is not inside the model's voxels (%c from %g to %g): "
                                "mesh and model do not match",
                                "xyz"[a], J->bbox_min[a], J->bbox_max[a], "xyz"[a], wlo + xf.voxel[a],
                                whi - xf.voxel[a]);
    }
    return HV_OK;
}

/* The voxel window under the printer image (J->vi0, vj0, vw, vh, WINDOW_PAD around it) and the
 * composed POI operators from it to the printer grid (J->ax, ay, their float weights axw, ayw
 * and the x operator padded to a fixed tap count axl, axs, axp when the row is long enough). */
static hv_status job_plan_window(job *J, const hv_layers_options *o)
{
    const hv_transform *xf = &J->xf;
    double sx = 25.4 / o->dpi[0], py = 25.4 / o->dpi[1];
    double a = (J->grid.origin[0] - xf->origin[0]) / xf->voxel[0];
    double b = (J->grid.origin[0] + J->W * sx - xf->origin[0]) / xf->voxel[0];
    double i0 = floor(a + 0.5) - WINDOW_PAD, i1 = floor(b + 0.5) + WINDOW_PAD;
    double c = (J->grid.origin[1] - J->H * py - xf->origin[1]) / xf->voxel[1];
    double d = (J->grid.origin[1] - xf->origin[1]) / xf->voxel[1];
    double j0 = floor(c + 0.5) - WINDOW_PAD, j1 = floor(d + 0.5) + WINDOW_PAD;
    if (i1 - i0 + 1 > (double)(1 << 24) || j1 - j0 + 1 > (double)(1 << 24) || fabs(i0) > 2e9 || fabs(j0) > 2e9)
        return hv_error_set(HV_ERR_LIMIT, "%s: the voxel window is %.0f x %.0f voxels (at most 2^24 a side)",
                            o->model_name ? o->model_name : "layers", i1 - i0 + 1, j1 - j0 + 1);
    J->vi0 = (int)i0;
    J->vj0 = (int)j0;
    J->vw = (int)(i1 - i0 + 1);
    J->vh = (int)(j1 - j0 + 1);
    hv_status st = hv_poi_axis_chain(xf->origin[0] + (i0 - 0.5) * xf->voxel[0], xf->voxel[0], J->vw, J->grid.origin[0],
                                     sx, J->W, o->poi_step, &J->ax);
    if (st == HV_OK)
        st = hv_poi_axis_chain(xf->origin[1] + (j0 - 0.5) * xf->voxel[1], xf->voxel[1], J->vh, J->grid.origin[1], -py,
                               J->H, o->poi_step, &J->ay);
    if (st != HV_OK) return hv_error_prefix(st, "%s: ", o->model_name ? o->model_name : "layers");
    size_t nx = J->ax.off[J->ax.n_out - 1] + (size_t)J->ax.len[J->ax.n_out - 1];
    size_t ny = J->ay.off[J->ay.n_out - 1] + (size_t)J->ay.len[J->ay.n_out - 1];
    J->axw = hv_malloc_array(nx, sizeof *J->axw);
    J->ayw = hv_malloc_array(ny, sizeof *J->ayw);
    if (!J->axw || !J->ayw) return HV_ERR_NOMEM;
    for (size_t i = 0; i < nx; ++i) J->axw[i] = (float)J->ax.w[i];
    for (size_t i = 0; i < ny; ++i) J->ayw[i] = (float)J->ay.w[i];
    int L = 0;
    for (int x = 0; x < J->W; ++x) L = HV_MAX(L, J->ax.len[x]);
    if (L > J->vw) return HV_OK;
    J->axs = hv_malloc_array((size_t)J->W, sizeof *J->axs);
    J->axp = hv_malloc_array((size_t)J->W * (size_t)L, sizeof *J->axp);
    if (!J->axs || !J->axp) return HV_ERR_NOMEM;
    J->axl = L;
    for (int x = 0; x < J->W; ++x) {
        int from = HV_MIN(J->ax.start[x], J->vw - L), at = J->ax.start[x] - from;
        J->axs[x] = from;
        float *wp = J->axp + (size_t)x * (size_t)L;
        for (int k = 0; k < L; ++k)
            wp[k] = k >= at && k - at < J->ax.len[x] ? J->axw[J->ax.off[x] + (size_t)(k - at)] : 0.0f;
    }
    return HV_OK;
}

/* One axis of depth_band's cells: for each of the n printer cells (centres at o + (c + 0.5) * p)
 * the first voxel of its bilinear pair (voxel centres at vo + (v0 + i) * h, i < nv), the second's
 * weight, and the voxels the pair and the POI taps of ax span. */
static hv_status depth_axis(const hv_poi_axis *ax, int n, double o, double p, double vo, double h, int v0, int nv,
                            int **b, float **t, int **u0, int **u1)
{
    *b = hv_malloc_array((size_t)n, sizeof **b);
    *t = hv_malloc_array((size_t)n, sizeof **t);
    *u0 = hv_malloc_array((size_t)n, sizeof **u0);
    *u1 = hv_malloc_array((size_t)n, sizeof **u1);
    if (!*b || !*t || !*u0 || !*u1) return HV_ERR_NOMEM;
    for (int c = 0; c < n; ++c) {
        double u = (o + ((double)c + 0.5) * p - vo) / h - v0, f = floor(u);
        int i = (int)HV_CLAMP(f, 0.0, (double)HV_MAX(nv - 2, 0));
        (*b)[c] = i;
        (*t)[c] = (float)HV_CLAMP(u - i, 0.0, 1.0);
        (*u0)[c] = HV_MIN(i, ax->start[c]);
        (*u1)[c] = HV_MAX(HV_MIN(i + 1, nv - 1), ax->start[c] + ax->len[c] - 1);
    }
    return HV_OK;
}

/* depth_band's cells along x and y (a painted model with colour.depth). */
static hv_status job_plan_depth(job *J)
{
    hv_status st = depth_axis(&J->ax, J->W, J->grid.origin[0], J->grid.pixel[0], J->xf.origin[0], J->xf.voxel[0],
                              J->vi0, J->vw, &J->bx, &J->bxt, &J->bxu0, &J->bxu1);
    if (st == HV_OK)
        st = depth_axis(&J->ay, J->H, J->grid.origin[1], J->grid.pixel[1], J->xf.origin[1], J->xf.voxel[1], J->vj0,
                        J->vh, &J->by, &J->byt, &J->byu0, &J->byu1);
    if (st != HV_OK) return st;
    J->cf = hv_malloc_array((size_t)J->vw, sizeof *J->cf);
    J->cl = hv_malloc_array((size_t)J->vw, sizeof *J->cl);
    if (!J->cf || !J->cl) return HV_ERR_NOMEM;
    /* the spans' ends grow with the column (both operators' do), so those holding i are a run */
    for (int i = 0, a = 0, b = 0; i < J->vw; ++i) {
        while (a < J->W && J->bxu1[a] < i) ++a;
        while (b < J->W && J->bxu0[b] <= i) ++b;
        J->cf[i] = a;
        J->cl[i] = b - 1;
    }
    return HV_OK;
}

/* The palette (background, then the materials' colours) and the PNG bit depth. */
static void job_plan_palette(job *J, const hv_layers_options *o)
{
    if (o->mode != HV_LAYERS_HALFTONE) {
        J->bit_depth = o->mode == HV_LAYERS_MASK ? 1 : 8;
        return;
    }
    J->palette_size = J->m + 1;
    memcpy(J->palette, o->background, 3);
    for (int j = 0; j < J->m; ++j) {
        float rgba[4];
        hv_material_color(J->table, j, rgba);
        for (int k = 0; k < 3; ++k)
            J->palette[3 * (j + 1) + k] = (uint8_t)lround(HV_CLAMP(rgba[k], 0.0f, 1.0f) * 255.0f);
    }
    J->bit_depth = J->palette_size <= 2 ? 1 : J->palette_size <= 4 ? 2 : J->palette_size <= 16 ? 4 : 8;
}

/* The threads and the planned peak memory (J->memory, fixed_memory): the workers plus the
 * per-layer statistics, the blue-noise table and the operators; over the budget, HV_ERR_LIMIT. */
static hv_status job_plan_memory(job *J, const hv_layers_options *o, const hv_layers_place *pl)
{
    J->threads = pl && pl->tray ? 1 : HV_MAX(hv_threads(), 1);
    size_t count = J->last - J->first;
    uint64_t stats = (uint64_t)count * (uint64_t)(J->m * 16 + 56);
    uint64_t fixed = stats + (J->src ? J->src->memory : 0);
    if (o->mode == HV_LAYERS_HALFTONE && J->src)
        fixed += (uint64_t)HV_BLUENOISE_NX * HV_BLUENOISE_NY * HV_BLUENOISE_NZ * 4;
    if (uses_voxels(J)) {
        uint64_t weights = (uint64_t)J->ax.off[J->ax.n_out - 1] + (uint64_t)J->ax.len[J->ax.n_out - 1] +
                           (uint64_t)J->ay.off[J->ay.n_out - 1] + (uint64_t)J->ay.len[J->ay.n_out - 1];
        fixed += (uint64_t)HV_BLUENOISE_NX * HV_BLUENOISE_NY * HV_BLUENOISE_NZ * 4 + weights * 8 +
                 (uint64_t)(J->ax.n_out + J->ay.n_out) * 16 + (uint64_t)J->W * (uint64_t)(J->axl + 1) * 4;
    }
    J->fixed_memory = fixed;
    J->memory = (uint64_t)J->threads * worker_bytes(J) + fixed;
    uint64_t budget = hv_memory_budget(o->max_memory);
    char what[32];
    if (uses_model(o)) snprintf(what, sizeof what, "%d material%s", J->m, J->m > 1 ? "s" : "");
    else snprintf(what, sizeof what, "mask");
    if (budget && J->memory > budget) {
        char nt[32], bt[32];
        return hv_error_option(HV_ERR_LIMIT,
                            "layers: the job needs about %s (%d x %d pixels, %s, %d workers), more than the "
                            "budget of %s ({max_memory})",
                            hv_size_text(nt, sizeof nt, (double)J->memory), J->W, J->H, what, J->threads,
                            hv_size_text(bt, sizeof bt, (double)budget));
    }
    return HV_OK;
}

/* The grid, range, window and operators; everything except the output. */
static hv_status job_plan(job *J, const hv_mesh *mesh, const hv_volume *model,
                          const hv_layers_options *o, const hv_progress *progress, const hv_layers_place *pl)
{
    memset(J, 0, sizeof *J);
    J->o = o;
    J->model = model;
    J->src = o->source;
    J->progress = progress;
    hv_status st = hv_layers_options_check(o);
    if (st == HV_OK) st = job_plan_shape(J, mesh, model, o);
    if (st == HV_OK) st = job_plan_grid(J, o, pl);
    if (st == HV_OK && uses_model(o)) st = J->src ? job_plan_source_materials(J) : job_plan_materials(J, model);
    if (st == HV_OK && model) st = job_plan_fit(J, model);
    if (st == HV_OK && uses_voxels(J)) st = job_plan_window(J, o);
    if (st == HV_OK && uses_voxels(J) && J->nd) st = job_plan_depth(J);
    if (st != HV_OK) return st;
    job_plan_palette(J, o);
    return job_plan_memory(J, o, pl);
}

/* The voxelizer records the mesh it was given: a mesh whose box differs from that one by more
 * than a voxel is probably not the model's. A warning, not an error: a repaired or re-exported
 * mesh of the same part is fine. */
static void mesh_warning(job *J)
{
    hv_voxelize_record rec;
    if (!J->model || hv_voxelize_record_read(J->model, &rec) != HV_OK) return;
    const double *lo = rec.mesh.bbox_min, *hi = rec.mesh.bbox_max;
    hv_transform xf = hv_volume_get_transform(J->model);
    double tol = HV_MAX(xf.voxel[0], HV_MAX(xf.voxel[1], xf.voxel[2]));
    int differs = 0;
    for (int a = 0; a < 3; ++a) differs |= fabs(lo[a] - J->bbox_min[a]) > tol || fabs(hi[a] - J->bbox_max[a]) > tol;
    const char *mesh = J->o->mesh_name ? J->o->mesh_name : "the mesh";
    const char *model = *hv_volume_name(J->model) ? hv_volume_name(J->model) : J->o->model_name ? J->o->model_name : "the model";
    if (differs)
        snprintf(J->warnings, sizeof J->warnings,
                 "%s spans (%g, %g, %g)-(%g, %g, %g), but %s was voxelized from a mesh spanning (%g, %g, %g)-(%g, %g, "
                 "%g): is this its mesh?\n",
                 mesh, J->bbox_min[0], J->bbox_min[1], J->bbox_min[2], J->bbox_max[0], J->bbox_max[1], J->bbox_max[2],
                 model, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
}

static void fill_plan_report(const job *J, hv_layers_report *r)
{
    memset(r, 0, sizeof *r);
    r->width = J->W;
    r->height = J->H;
    r->pixel_mm[0] = J->grid.pixel[0];
    r->pixel_mm[1] = J->grid.pixel[1];
    r->origin_mm[0] = J->grid.origin[0];
    r->origin_mm[1] = J->grid.origin[1];
    r->layers_total = J->nlayers;
    r->first = J->first;
    r->last = J->last;
    r->materials = J->m;
    r->bit_depth = J->bit_depth;
    r->memory_bytes = J->memory;
    r->threads = J->threads;
    snprintf(r->warnings, sizeof r->warnings, "%s", J->warnings);
}

/* Failures about the model's content name its file. */
static hv_status name_model(const hv_volume *model, const hv_layers_options *o, hv_status s)
{
    const char *name = model && *hv_volume_name(model) ? hv_volume_name(model) : o ? o->model_name : NULL;
    return s == HV_ERR_BAD_INPUT && name ? hv_error_prefix(s, "%s: ", name) : s;
}

/* The placement a single stack asks for (o->placed), on its profile's plate. */
static const hv_layers_place *options_place(const hv_layers_options *o, hv_layers_place *pl)
{
    if (!o->placed) return NULL;
    const hv_printer_profile *p = hv_printer_profile_find(o->profile);
    pl->x = o->place[0];
    pl->y = o->place[1];
    p = p ? p : hv_printer_profile_at(0);
    pl->plate_y = p->build[1];
    pl->plate_x = p->build[0];
    pl->plate = p->name;
    pl->lift = 0;
    pl->tray = 0;
    return pl;
}

hv_status hv_layers_plan(const hv_mesh *mesh, const hv_volume *model, const hv_layers_options *opt,
                         hv_layers_report *report)
{
    job J;
    hv_layers_place pl;
    hv_status st = name_model(model, opt, job_plan(&J, mesh, model, opt, NULL, options_place(opt, &pl)));
    if (st == HV_OK && report) fill_plan_report(&J, report);
    else if (report) {
        memset(report, 0, sizeof *report);
        snprintf(report->warnings, sizeof report->warnings, "%s", J.warnings);
    }
    job_free(&J);
    return st;
}

/* ---- per-worker buffers ------------------------------------------------------------------- */

static hv_status worker_ready(job *J, worker *w)
{
    if (w->ready) return HV_OK;
    uint64_t sz[WB_COUNT];
    void *buf[WB_COUNT] = {0};
    worker_sizes(J, sz);
    int ok = 1;
    for (int k = 0; k < WB_COUNT; ++k) ok &= !sz[k] || (buf[k] = hv_malloc((size_t)sz[k])) != NULL;
    worker_point(w, buf);
    w->slab_ok[0] = w->slab_ok[1] = 0;
    if (ok && uses_model(J->o)) {
        size_t px = J->plane, m = (size_t)J->m;
        if (ed_mode(J)) {
            w->err = hv_calloc(px * m, sizeof *w->err);
            w->next = hv_calloc(px * m, sizeof *w->next);
            ok = w->err && w->next;
        }
        if (J->model) hv_accessor_init(&w->acc, J->model);
    }
    if (!ok) return hv_error_set(HV_ERR_NOMEM, "layers: out of memory for the buffers of a %d x %d layer", J->W, J->H);
    w->ready = 1;
    return HV_OK;
}

/* ---- material: z interpolation, extension, POI (Wu 2.4.2) ---------------------------------- */

/* Decode voxel layer k of the window into occ (vw * vh) and mat (m planes of them, then a painted
 * model's colour.depth); 1 when any voxel of it is occupied. */
static int slab_decode(const job *J, hv_accessor *acc, int32_t k, uint8_t *occ, float *mat)
{
    size_t vox = (size_t)J->vw * (size_t)J->vh;
    int any = 0;
    for (int j = 0; j < J->vh; ++j) {
        for (int i = 0; i < J->vw; ++i) {
            size_t p = (size_t)j * (size_t)J->vw + (size_t)i;
            int32_t vi = J->vi0 + i, vj = J->vj0 + j;
            int o = k >= J->klo && k <= J->khi && hv_accessor_bool(acc, J->occ_grid, vi, vj, k);
            occ[p] = (uint8_t)o;
            any |= o;
            for (int g = 0; g < J->m; ++g)
                mat[(size_t)g * vox + p] = o ? hv_accessor_float(acc, J->mat_grid[g], vi, vj, k) : 0.0f;
            if (J->nd) mat[(size_t)J->m * vox + p] = o ? hv_accessor_float(acc, J->depth_grid, vi, vj, k) : 0.0f;
        }
    }
    return any;
}

/* Decode voxel layer k of the window into the worker's slab s. */
static void slab_load(job *J, worker *w, int s, int32_t k)
{
    w->slab_any[s] = slab_decode(J, &w->acc, k, w->slab_occ[s], w->slab_mat[s]);
    w->slab_k[s] = k;
    w->slab_ok[s] = 1;
}

static int slab_find(const worker *w, int32_t k)
{
    for (int s = 0; s < 2; ++s)
        if (w->slab_ok[s] && w->slab_k[s] == k) return s;
    return -1;
}

/* Slab holding voxel layer k, loaded into the slot that does not hold `keep` when missing. */
static int slab_get(job *J, worker *w, int32_t k, int32_t keep)
{
    int s = slab_find(w, k);
    if (s >= 0) return s;
    s = slab_find(w, keep) == 0 ? 1 : 0;
    slab_load(J, w, s, k);
    return s;
}

/* A decoded voxel layer of the window (`id` names it to its store), and where a layer's voxel
 * image comes from: two of them and their weights (one, `single`, when the nearest occupied voxel
 * layer stands in for both). */
typedef struct slab_ref {
    const uint8_t *occ;
    const float *mat;
    int any;
    size_t id;
} slab_ref;
typedef struct slab_pick {
    slab_ref s0, s1;
    double w0, w1;
    int single;
} slab_pick;

/* Who holds the decoded voxel layers: `get` gives layer k and holds it until `put` (keeping
 * `keep` if it holds it; HV_ERR_NOMEM when it cannot). A worker keeps two slabs of its own; a
 * tray part's are shared by the threads that render its layers (part_slab_get). */
typedef struct slab_store {
    hv_status (*get)(job *J, void *ctx, int32_t k, int32_t keep, slab_ref *out);
    void (*put)(void *ctx, const slab_ref *r);
    void *ctx;
} slab_store;

static hv_status worker_slab_get(job *J, void *ctx, int32_t k, int32_t keep, slab_ref *out)
{
    worker *w = ctx;
    int s = slab_get(J, w, k, keep);
    *out = (slab_ref){w->slab_occ[s], w->slab_mat[s], w->slab_any[s], (size_t)s};
    return HV_OK;
}
static void worker_slab_put(void *ctx, const slab_ref *r) { (void)ctx, (void)r; }

static hv_status no_voxel(size_t index, double z)
{
    return hv_error_set(HV_ERR_BAD_INPUT, "layer %zu (z = %g): the model has no occupied voxel under the mesh's section",
                        index, z);
}

static void slabs_put(const slab_store *S, const slab_pick *p)
{
    S->put(S->ctx, &p->s0);
    if (!p->single) S->put(S->ctx, &p->s1);
}

/* The voxel layers around height z and their weights; when neither has an occupied voxel in the
 * window, the nearest voxel layer that has one. Held until slabs_put. */
static hv_status slabs_pick(job *J, const slab_store *S, size_t index, double z, slab_pick *p)
{
    double kz = (z - J->xf.origin[2]) / J->xf.voxel[2];
    double kf = floor(kz);
    int32_t k0 = (int32_t)HV_CLAMP(kf, -2e9, 2e9);
    double t = kz - kf;
    hv_status st = S->get(J, S->ctx, k0, k0 + 1, &p->s0);
    if (st != HV_OK) return st;
    if ((st = S->get(J, S->ctx, k0 + 1, k0, &p->s1)) != HV_OK) {
        S->put(S->ctx, &p->s0);
        return st;
    }
    p->w0 = 1 - t;
    p->w1 = t;
    p->single = 0;
    if ((p->s0.any && p->w0 > 0) || (p->s1.any && p->w1 > 0)) return HV_OK;
    slabs_put(S, p);
    int32_t span = J->khi - J->klo + 2;
    for (int32_t d = 0; d <= span; ++d) {
        int32_t cand[2] = {k0 - d, k0 + 1 + d};
        for (int c = 0; c < 2; ++c) {
            if (cand[c] < J->klo || cand[c] > J->khi) continue;
            slab_ref r;
            if ((st = S->get(J, S->ctx, cand[c], k0, &r)) != HV_OK) return st;
            if (!r.any) {
                S->put(S->ctx, &r);
                continue;
            }
            p->s0 = p->s1 = r;
            p->w0 = 1;
            p->w1 = 0;
            p->single = 1;
            return HV_OK;
        }
    }
    return no_voxel(index, z);
}

/* The 8-neighbours of window pixel p inside the window: their indices in nb, the count
 * returned. */
static int neighbours8(const job *J, size_t p, size_t nb[8])
{
    int i = (int)(p % (size_t)J->vw), j = (int)(p / (size_t)J->vw), n = 0;
    for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
            int a = i + di, b = j + dj;
            if ((di || dj) && a >= 0 && b >= 0 && a < J->vw && b < J->vh)
                nb[n++] = (size_t)b * (size_t)J->vw + (size_t)a;
        }
    return n;
}

/* Queue the untouched neighbours of p (state 0 -> 2) on list. */
static size_t queue_neighbours(const job *J, uint8_t *state, size_t p, int32_t *list, size_t n)
{
    size_t nb[8];
    int k = neighbours8(J, p, nb);
    for (int t = 0; t < k; ++t)
        if (state[nb[t]] == 0) {
            state[nb[t]] = 2;
            list[n++] = (int32_t)nb[t];
        }
    return n;
}

/* Mean of the assigned 8-neighbours, ring by ring from the covered pixels outwards: every
 * window pixel gets a composition, the covered ones keep theirs (the live materials' planes only:
 * a mean of zeros stays zero). */
static void extend(job *J, worker *w)
{
    int m = J->m, g_of[HV_MAX_MATERIALS + 1], nl = 0;
    for (int g = 0; g < m; ++g)
        if (w->live[g]) g_of[nl++] = g;
    if (J->nd) g_of[nl++] = m; /* a painted model's depth */
    size_t vox = (size_t)J->vw * (size_t)J->vh, nf = 0;
    uint8_t *state = w->vstate; /* 1 assigned, 2 queued, 0 untouched */
    for (size_t p = 0; p < vox; ++p)
        if (state[p] == 1) nf = queue_neighbours(J, state, p, w->front, nf);
    while (nf) {
        for (size_t f = 0; f < nf; ++f) {
            size_t p = (size_t)w->front[f], nb[8];
            int k = neighbours8(J, p, nb), n = 0;
            double acc[HV_MAX_MATERIALS + 1] = {0};
            for (int t = 0; t < k; ++t) {
                if (state[nb[t]] != 1) continue;
                ++n;
                for (int l = 0; l < nl; ++l) acc[l] += w->vimg[(size_t)g_of[l] * vox + nb[t]];
            }
            for (int l = 0; l < nl; ++l) w->vimg[(size_t)g_of[l] * vox + p] = (float)(acc[l] / HV_MAX(n, 1));
        }
        size_t n2 = 0;
        for (size_t f = 0; f < nf; ++f) state[w->front[f]] = 1;
        for (size_t f = 0; f < nf; ++f) n2 = queue_neighbours(J, state, (size_t)w->front[f], w->front2, n2);
        int32_t *t = w->front;
        w->front = w->front2;
        w->front2 = t;
        nf = n2;
    }
}

/* Which materials the covered window pixels hold anywhere (w->live): one that is zero at each is
 * zero after the extension and the resampling too (means and sums of zeros with weights >= 0), so
 * its fractions are written as zeros instead of computed (a painted part's clear resin under an
 * opaque texture, its black outside the darkest colours, a graded part's materials where the
 * layer holds none of them). -0 counts as zero: the halftone cannot tell the two apart. With no
 * covered pixel every material is live, as before. */
static void mark_live(job *J, worker *w)
{
    size_t vox = (size_t)J->vw * (size_t)J->vh;
    int any = 0;
    for (int g = 0; g < J->m; ++g) w->live[g] = 0;
    for (size_t p = 0; p < vox; ++p) any |= w->vstate[p] == 1;
    for (int g = 0; g < J->m; ++g) {
        const float *v = w->vimg + (size_t)g * vox;
        for (size_t p = 0; p < vox && !w->live[g]; ++p) w->live[g] = !any || (w->vstate[p] == 1 && v[p] != 0);
    }
}

/* voxel_image's z part for a painted model with its colour.depth: the depth linear in z; where the
 * two voxel layers lie on both sides of the colour depth, the composition of the one on the side the
 * depth at z says (skin when <= the depth), so the change is sharp in z at the depth itself, not
 * spread over a voxel; elsewhere linear as for any model. */
static void depth_z(job *J, worker *w, const slab_pick *pk)
{
    size_t vox = (size_t)J->vw * (size_t)J->vh;
    int m = J->m;
    double w0 = pk->w0, w1 = pk->w1;
    const uint8_t *o0 = pk->s0.occ, *o1 = pk->s1.occ;
    const float *m0 = pk->s0.mat, *m1 = pk->s1.mat, *d0 = m0 + (size_t)m * vox, *d1 = m1 + (size_t)m * vox;
    float D = J->depth_mm, *dz = w->vimg + (size_t)m * vox;
    for (size_t p = 0; p < vox; ++p) {
        double c0 = o0[p] ? w0 : 0, c1 = o1[p] ? w1 : 0, cov = c0 + c1;
        if (!(cov > 0)) {
            w->vstate[p] = 0;
            continue;
        }
        w->vstate[p] = 1;
        float d = (float)((c0 * d0[p] + c1 * d1[p]) / cov);
        int skin0 = d0[p] <= D, skin1 = d1[p] <= D;
        dz[p] = d;
        if (c0 > 0 && c1 > 0 && skin0 != skin1) {
            const float *from = (skin0 == (d <= D)) ? m0 : m1;
            for (int g = 0; g < m; ++g) w->vimg[(size_t)g * vox + p] = from[(size_t)g * vox + p];
            continue;
        }
        for (int g = 0; g < m; ++g)
            w->vimg[(size_t)g * vox + p] = (float)((c0 * m0[(size_t)g * vox + p] + c1 * m1[(size_t)g * vox + p]) / cov);
    }
}

/* The window image at height z: linear in z between the voxel layers around it (from the
 * worker's own slabs, or w->store's) over the occupied voxels (renormalised by the coverage), then
 * extended. */
static hv_status voxel_image(job *J, worker *w, size_t index, double z)
{
    size_t vox = (size_t)J->vw * (size_t)J->vh;
    int m = J->m;
    slab_store own = {worker_slab_get, worker_slab_put, w};
    const slab_store *S = w->store ? w->store : &own;
    slab_pick pk;
    hv_status st = slabs_pick(J, S, index, z, &pk);
    if (st != HV_OK) return st;
    double w0 = pk.w0, w1 = pk.w1;
    const uint8_t *o0 = pk.s0.occ, *o1 = pk.s1.occ;
    const float *m0 = pk.s0.mat, *m1 = pk.s1.mat;
    if (J->nd) depth_z(J, w, &pk);
    else
        for (size_t p = 0; p < vox; ++p) {
            double c0 = o0[p] ? w0 : 0, c1 = o1[p] ? w1 : 0, cov = c0 + c1;
            if (cov > 0) {
                w->vstate[p] = 1;
                for (int g = 0; g < m; ++g)
                    w->vimg[(size_t)g * vox + p] =
                        (float)((c0 * m0[(size_t)g * vox + p] + c1 * m1[(size_t)g * vox + p]) / cov);
            } else {
                w->vstate[p] = 0;
            }
        }
    slabs_put(S, &pk);
    mark_live(J, w);
    extend(J, w);
    if (J->nd) { /* the voxels' sides for depth_band, in the extension's state (all 1 after it) */
        const float *d = w->vimg + (size_t)m * vox;
        for (size_t p = 0; p < vox; ++p) w->vstate[p] = d[p] <= J->depth_mm ? 1 : 2;
    }
    return HV_OK;
}

/* the x pass over columns c0..c1 of one voxel row s into t, L taps a column */
#define XPASS(L)                                                                                                   \
    for (int c = c0; c <= c1; ++c) {                                                                               \
        const float *wt = J->axp + (size_t)c * (L);                                                               \
        const float *p = s + J->axs[c];                                                                            \
        float acc = 0;                                                                                             \
        for (int k = 0; k < (L); ++k) acc += wt[k] * p[k];                                                         \
        t[c] = acc;                                                                                                \
    }

/* The depth at (i + tx, j + ty) of the window's depth plane dv, bilinear `lin`, where a crease may
 * cross the cell (two faces equally near: the core's edges): each corner's plane continued from
 * outside the cell (its steps from the voxels beyond it along x and y; at the window's edge the
 * cell's own step; each at most a voxel: a distance grows no faster), the least of the four, and
 * the larger of that and the bilinear value. Exact on a plane and at such a crease; where the
 * distance is curved the other way (a concave edge of the part), bilinear. */
static float depth_cell_ridge(const job *J, const float *dv, int i, int j, float tx, float ty, float lin)
{
    size_t vw = (size_t)J->vw;
    float hx = (float)J->xf.voxel[0], hy = (float)J->xf.voxel[1], best = INFINITY;
#define DV(a, b) dv[(size_t)(b) * vw + (size_t)(a)]
    for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
            int x = i + a, y = j + b, xo = a ? x + 1 : x - 1, yo = b ? y + 1 : y - 1;
            float d = DV(x, y);
            float gx = xo >= 0 && xo < J->vw ? (a ? DV(xo, y) - d : d - DV(xo, y)) : DV(i + 1, y) - DV(i, y);
            float gy = yo >= 0 && yo < J->vh ? (b ? DV(x, yo) - d : d - DV(x, yo)) : DV(x, j + 1) - DV(x, j);
            gx = fminf(fmaxf(gx, -hx), hx);
            gy = fminf(fmaxf(gy, -hy), hy);
            best = fminf(best, d + gx * (tx - (float)a) + gy * (ty - (float)b));
        }
#undef DV
    return fmaxf(lin, best);
}

/* Pixel (r, c) of a painted model in the colour depth's band (its bilinear cell or POI taps hold
 * voxels of both sides): its side by the depth at its centre, bilinear in the window's depth
 * (exact where the surface is flat: the composed POI operator is not, it is off by up to 0.09 mm
 * from 0.5 mm voxels to the J750's pitch), and its fractions the bilinear mean of the cell's
 * voxels on that side alone (renormalised; none with weight: the POI value stays). */
static void depth_pixel(job *J, worker *w, float *frac, size_t plane, size_t q, int r, int c, const int *live, int nl)
{
    size_t vox = (size_t)J->vw * (size_t)J->vh, vw = (size_t)J->vw;
    size_t p0 = (size_t)J->by[r] * vw + (size_t)J->bx[c];
    size_t at[4] = {p0, p0 + 1, p0 + vw, p0 + vw + 1};
    float tx = J->bxt[c], ty = J->byt[r], D = J->depth_mm;
    float wt[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty}, d = 0, own = 0;
    const float *dv = w->vimg + (size_t)J->m * vox;
    for (int k = 0; k < 4; ++k) d += wt[k] * dv[at[k]];
    /* the crease rule only raises the depth, by at most a voxel along each axis (the least corner
     * plane is at most the least corner's depth, <= d, and two steps of a voxel): the side it can
     * change is that of a depth at most that far below D */
    if (d <= D && d > D - (float)(J->xf.voxel[0] + J->xf.voxel[1]))
        d = depth_cell_ridge(J, dv, J->bx[c], J->by[r], tx, ty, d);
    int skin = d <= D;
    for (int k = 0; k < 4; ++k) {
        if ((dv[at[k]] <= D) != skin) wt[k] = 0;
        own += wt[k];
    }
    if (!(own > 0)) return;
    for (int k = 0; k < 4; ++k) wt[k] /= own;
    for (int l = 0; l < nl; ++l) {
        const float *v = w->vimg + (size_t)live[l] * vox;
        frac[(size_t)live[l] * plane + q] = wt[0] * v[at[0]] + wt[1] * v[at[1]] + wt[2] * v[at[2]] + wt[3] * v[at[3]];
    }
}

/* The pixels of rows r0..r1 (columns c0..c1) in the colour depth's band, through depth_pixel. Per
 * row the sides of the voxels (w->vstate: 1 skin, 2 core) or-ed over the rows its cells span, one
 * byte per voxel column; only the pixels whose span holds a column of both sides, or two neighbours
 * of different sides, are looked at (those that span voxel column i are J->cf[i] .. J->cl[i]). */
static void depth_band(job *J, worker *w, float *frac, size_t plane, int rbase, int r0, int r1, int c0, int c1)
{
    size_t W = (size_t)J->W, vw = (size_t)J->vw;
    uint8_t *co = (uint8_t *)w->xtmp; /* free after the passes */
    int ilo = J->bxu0[c0], ihi = J->bxu1[c1], live[HV_MAX_MATERIALS], nl = 0;
    size_t n = (size_t)(ihi - ilo + 1);
    for (int g = 0; g < J->m; ++g)
        if (w->live[g]) live[nl++] = g;
    for (int r = r0; r <= r1; ++r) {
        const uint8_t *mrow = w->mask + (size_t)r * W;
        if (!memchr(mrow + c0, 1, (size_t)(c1 - c0 + 1))) continue;
        memcpy(co, w->vstate + (size_t)J->byu0[r] * vw + (size_t)ilo, n);
        for (int j = J->byu0[r] + 1; j <= J->byu1[r]; ++j) {
            const uint8_t *b = w->vstate + (size_t)j * vw + (size_t)ilo;
#pragma omp simd
            for (size_t i = 0; i < n; ++i) co[i] |= b[i];
        }
        int next = c0; /* the first pixel not looked at */
        for (int i = ilo; i <= ihi; ++i) {
            uint8_t a = co[i - ilo];
            if (a != 3 && (i == ihi || (a | co[i + 1 - ilo]) != 3)) continue;
            int cb = HV_MIN(c1, J->cl[i]);
            for (int c = HV_MAX(next, J->cf[i]); c <= cb; ++c) {
                uint8_t o = 0;
                for (int k = J->bxu0[c]; k <= J->bxu1[c]; ++k) o |= co[k - ilo];
                if (o == 3 && mrow[c])
                    depth_pixel(J, w, frac, plane, (size_t)(r - rbase) * W + (size_t)c, r, c, live, nl);
            }
            next = HV_MAX(next, cb + 1);
        }
    }
}

/* POI of the window image onto the object pixels of rows r0..r1 (columns c0..c1 hold all of
 * them): into frac, m planes of `plane` floats whose row 0 is layer row rbase. */
HV_HOT_CLONES static void resample_layer(job *J, worker *w, float *frac, size_t plane, int rbase, int r0, int r1,
                                         int c0, int c1)
{
    size_t vox = (size_t)J->vw * (size_t)J->vh, W = (size_t)J->W, n = (size_t)(c1 - c0 + 1);
    const hv_poi_axis *ax = &J->ax, *ay = &J->ay;
    int jlo = J->vh, jhi = -1;
    for (int r = r0; r <= r1; ++r) {
        jlo = HV_MIN(jlo, ay->start[r]);
        jhi = HV_MAX(jhi, ay->start[r] + ay->len[r] - 1);
    }
    for (int g = 0; g < J->m; ++g) {
        const float *src = w->vimg + (size_t)g * vox;
        float *dst = frac + (size_t)g * plane;
        if (!w->live[g]) { /* zero in the window image: zero wherever the passes would write */
            for (int r = r0; r <= r1; ++r)
                if (memchr(w->mask + (size_t)r * W + (size_t)c0, 1, n))
                    memset(dst + (size_t)(r - rbase) * W + (size_t)c0, 0, n * sizeof *dst);
            continue;
        }
        /* x pass over the voxel rows the object rows need */
        for (int j = jlo; j <= jhi; ++j) {
            const float *s = src + (size_t)j * (size_t)J->vw;
            float *t = w->xtmp + (size_t)j * W;
            /* a fixed tap count unrolls; a zero weight adds +0, leaving every sum as it was */
            switch (J->axl) {
            case 2: XPASS(2); break;
            case 3: XPASS(3); break;
            case 4: XPASS(4); break;
            default:
                for (int c = c0; c <= c1; ++c) {
                    const float *wt = J->axw + ax->off[c];
                    const float *p = s + ax->start[c];
                    float acc = 0;
                    for (int k = 0; k < ax->len[c]; ++k) acc += wt[k] * p[k];
                    t[c] = acc;
                }
            }
        }
        /* y pass, row by row over contiguous memory, straight into the plane; two and three
         * taps in one sweep (the same sums in the same order as tap after tap) */
        for (int r = r0; r <= r1; ++r) {
            const uint8_t *mrow = w->mask + (size_t)r * W;
            if (!memchr(mrow + c0, 1, n)) continue;
            const float *wt = J->ayw + ay->off[r];
            const float *restrict b0 = w->xtmp + (size_t)ay->start[r] * W + (size_t)c0;
            float *restrict d = dst + (size_t)(r - rbase) * W + (size_t)c0;
            float w0 = wt[0];
            int len = ay->len[r];
            if (len == 2) {
                const float *restrict b1 = b0 + W;
                float w1 = wt[1];
#pragma omp simd
                for (size_t c = 0; c < n; ++c) d[c] = w0 * b0[c] + w1 * b1[c];
                continue;
            }
            if (len == 3) {
                const float *restrict b1 = b0 + W, *restrict b2 = b1 + W;
                float w1 = wt[1], w2 = wt[2];
#pragma omp simd
                for (size_t c = 0; c < n; ++c) d[c] = w0 * b0[c] + w1 * b1[c] + w2 * b2[c];
                continue;
            }
#pragma omp simd
            for (size_t c = 0; c < n; ++c) d[c] = w0 * b0[c];
            for (int k = 1; k < len; ++k) {
                const float *restrict bk = b0 + (size_t)k * W;
                float wk = wt[k];
#pragma omp simd
                for (size_t c = 0; c < n; ++c) d[c] += wk * bk[c];
            }
        }
    }
    /* every operator row sums to 1 and the window image sums to 1 per pixel, so the fractions
     * sum to 1 up to float rounding: no renormalisation pass */
    if (J->nd) depth_band(J, w, frac, plane, rbase, r0, r1, c0, c1);
}

/* How far the resampled fractions are from the direct evaluation over a layer, summed row by row. */
typedef struct direct_sums {
    double dsum, dmax;
    uint64_t fallback;
} direct_sums;

/* Direct evaluation at the object pixel centres of rows r0..r1; compares with (and with DIRECT
 * replaces) the resampled fractions in frac (m planes of `plane` floats, row 0 layer row rbase). */
static void direct_rows(job *J, worker *w, float *frac, size_t plane, int rbase, double z, int r0, int r1, int c0,
                        int c1, direct_sums *ds)
{
    size_t W = (size_t)J->W;
    for (int r = r0; r <= r1; ++r)
        for (int c = c0; c <= c1; ++c) {
            size_t p = (size_t)r * W + (size_t)c, q = (size_t)(r - rbase) * W + (size_t)c;
            if (!w->mask[p]) continue;
            double pt[3] = {J->grid.origin[0] + ((double)c + 0.5) * J->grid.pixel[0],
                            J->grid.origin[1] + ((double)r + 0.5) * J->grid.pixel[1], z};
            int inside = 0;
            hv_object_sample(J->obj, pt, &inside, w->fd);
            if (!inside) {
                ++ds->fallback;
                continue;
            }
            double d = 0;
            for (int g = 0; g < J->m; ++g) d = HV_MAX(d, fabs(w->fd[g] - (double)frac[(size_t)g * plane + q]));
            ds->dsum += d;
            ds->dmax = HV_MAX(ds->dmax, d);
            if (J->o->method == HV_LAYERS_DIRECT)
                for (int g = 0; g < J->m; ++g) frac[(size_t)g * plane + q] = (float)w->fd[g];
        }
}

static void direct_store(job *J, size_t li, const direct_sums *ds)
{
    if (li == SIZE_MAX) return;
    J->st_dsum[li] = ds->dsum;
    J->st_dmax[li] = ds->dmax;
    J->st_fallback[li] = ds->fallback;
}

/* ---- one layer ------------------------------------------------------------------------------ */

static hv_status write_png(job *J, const char *path, const uint8_t *px, int palette)
{
    hv_png_options po;
    hv_png_options_init(&po);
    po.compression = J->o->compression;
    po.dpi[0] = J->o->dpi[0];
    po.dpi[1] = J->o->dpi[1];
    po.bit_depth = palette ? J->bit_depth : J->o->mode == HV_LAYERS_MASK ? 1 : 8;
    po.in_place = 1; /* the stack's temporary directory is synced once and renamed whole */
    if (palette) {
        po.palette = J->palette;
        po.palette_size = J->palette_size;
    }
    return hv_png_write(path, px, J->W, J->H, 1, 0, &po);
}

static void layer_file(const job *J, char *buf, size_t size, const char *sub, size_t index)
{
    hv_stack_layer_path(&J->out, sub, index, buf, size);
}

/* The statistics of layer li (SIZE_MAX: none), then its file unless a tray renders it. */
static hv_status halftone_done(job *J, worker *w, size_t index, size_t li, const uint64_t *counts, const double *tsum)
{
    if (li == SIZE_MAX) return HV_OK;
    memcpy(J->st_count + li * (size_t)J->m, counts, (size_t)J->m * sizeof *counts);
    memcpy(J->st_target + li * (size_t)J->m, tsum, (size_t)J->m * sizeof *tsum);
    if (J->no_files) return HV_OK;
    char path[4200];
    layer_file(J, path, sizeof path, NULL, index);
    return write_png(J, path, w->out, 1);
}

/* A model's layer halftoned by blue noise BAND_ROWS rows at a time (issue 32 item 21): a band's
 * fractions resampled, compared with the direct evaluation and halftoned, so a worker holds a band
 * of fractions, not the layer's (12 bytes a pixel with three materials, against the mask's and the
 * output's one each). Every sum runs row by row in the same order as over the whole layer, and a
 * band's noise rows are the layer's: the same pixels and statistics. */
static hv_status banded_layer(job *J, worker *w, size_t index, size_t li, int r0, int r1, int c0, int c1,
                              uint64_t pixels)
{
    const hv_layer *L = &J->layers[index];
    size_t W = (size_t)J->W;
    uint64_t counts[HV_MAX_MATERIALS] = {0};
    double tsum[HV_MAX_MATERIALS] = {0};
    direct_sums ds = {0, 0, 0};
    if (pixels) {
        hv_status st = voxel_image(J, w, index, L->z);
        if (st != HV_OK) return st;
    }
    /* the rows without object pixels (every row of an empty layer) */
    memset(w->out, 0, (size_t)HV_MIN(r0, J->H) * W);
    if (r1 >= r0) memset(w->out + (size_t)(r1 + 1) * W, 0, (size_t)(J->H - 1 - r1) * W);
    for (int rb = r0; rb <= r1; rb += BAND_ROWS) {
        int re = HV_MIN(rb + BAND_ROWS - 1, r1), n = re - rb + 1;
        size_t plane = W * (size_t)n;
        resample_layer(J, w, w->frac, plane, rb, rb, re, c0, c1);
        if (J->obj) direct_rows(J, w, w->frac, plane, rb, L->z, rb, re, c0, c1, &ds);
        int off[3] = {J->bn_off[0], J->bn_off[1] + rb, J->bn_off[2]};
        hv_halftone_bluenoise(w->frac, J->m, J->W, n, w->mask + (size_t)rb * W, J->ranks, off, index,
                              w->out + (size_t)rb * W, counts, tsum);
    }
    if (J->obj) direct_store(J, li, &ds);
    return halftone_done(J, w, index, li, counts, tsum);
}

/* Process global layer `index`; write it unless it is a pre-roll layer of error diffusion. */
static hv_status do_layer(job *J, worker *w, size_t index, int write)
{
    const hv_layer *L = &J->layers[index];
    size_t li = write ? index - J->first : SIZE_MAX;
    hv_status st;
    if (J->src) { /* the mask and the fractions at the pixel centres at once */
        st = J->src->layer(J->src, L->z, &J->grid, w->mask, uses_model(J->o) ? w->frac : NULL, J->plane);
        if (st != HV_OK) return st;
    } else {
        hv_slice *slice = NULL;
        st = hv_solid_slice(J->solid, L->z, &J->sopt, &slice);
        if (st != HV_OK) return st;
        st = hv_slice_rasterize(slice, &J->grid, J->o->fill_rule, J->o->threshold, w->mask, 0);
        if (write) J->st_open[li] = hv_slice_get_stats(slice)->open;
        hv_slice_destroy(slice);
        if (st != HV_OK) return st;
    }
    /* bounding box of the object pixels */
    int r0 = J->H, r1 = -1, c0 = J->W, c1 = -1;
    uint64_t pixels = 0;
    for (int r = 0; r < J->H; ++r) {
        const uint8_t *row = w->mask + (size_t)r * (size_t)J->W;
        const uint8_t *a = memchr(row, 1, (size_t)J->W);
        if (!a) continue;
        int ca = (int)(a - row), cb = (int)((const uint8_t *)memrchr(row, 1, (size_t)J->W) - row);
        uint32_t n = 0; /* the mask is 0 or 1 */
#pragma omp simd reduction(+ : n)
        for (int c = ca; c <= cb; ++c) n += row[c];
        pixels += n;
        r0 = HV_MIN(r0, r);
        r1 = r;
        c0 = HV_MIN(c0, ca);
        c1 = HV_MAX(c1, cb);
    }
    if (write) J->st_pixels[li] = pixels;
    char path[4200];
    if (J->o->mode == HV_LAYERS_MASK) {
        if (!write || J->no_files) return HV_OK;
        layer_file(J, path, sizeof path, NULL, index);
        return write_png(J, path, w->mask, 0);
    }
    if (banded(J)) return banded_layer(J, w, index, li, r0, r1, c0, c1, pixels);
    if (pixels && !J->src) {
        st = voxel_image(J, w, index, L->z);
        if (st != HV_OK) return st;
        resample_layer(J, w, w->frac, J->plane, 0, r0, r1, c0, c1);
        if (J->obj) {
            direct_sums ds = {0, 0, 0};
            direct_rows(J, w, w->frac, J->plane, 0, L->z, r0, r1, c0, c1, &ds);
            direct_store(J, li, &ds);
        }
    }
    if (J->o->mode == HV_LAYERS_FRACTIONS) {
        if (!write || J->no_files) return HV_OK;
        double *tg = J->st_target + li * (size_t)J->m;
        for (int g = 0; g < J->m && st == HV_OK; ++g) {
            const float *f = w->frac + (size_t)g * J->plane;
            double sum = 0;
            for (size_t p = 0; p < J->plane; ++p) {
                if (w->mask[p]) {
                    sum += f[p];
                    w->gray[p] = (uint8_t)lrintf(HV_CLAMP(f[p], 0.0f, 1.0f) * 255.0f);
                } else {
                    w->gray[p] = 0;
                }
            }
            tg[g] = sum;
            layer_file(J, path, sizeof path, hv_material_name(J->table, g), index);
            st = write_png(J, path, w->gray, 0);
        }
        return st;
    }
    uint64_t counts[HV_MAX_MATERIALS] = {0};
    double tsum[HV_MAX_MATERIALS] = {0};
    if (ed_mode(J) && index % HV_HALFTONE_BLOCK == 0)
        hv_halftone_diffuse_start(w->frac, J->m, J->W, J->H, w->mask, &w->err, &w->next, J->o->seed,
                                  index / HV_HALFTONE_BLOCK, (int)(index & 1), w->out);
    if (ed_mode(J))
        hv_halftone_diffuse(w->frac, J->m, J->W, J->H, w->mask, w->err, w->next, (int)(index & 1), w->out, counts,
                            tsum);
    else
        hv_halftone_bluenoise(w->frac, J->m, J->W, J->H, w->mask, J->ranks, J->bn_off, index, w->out, counts, tsum);
    if (ed_mode(J)) {
        float *t = w->err;
        w->err = w->next;
        w->next = t;
    }
    return halftone_done(J, w, index, li, counts, tsum);
}

static hv_status layer_done(job *J, int t)
{
    size_t d = atomic_fetch_add(&J->done, 1) + 1;
    if (t == 0 && J->progress && J->progress->fn) {
        if (hv_progress_report(J->progress, "layers", (double)d / (double)(J->run_hi - J->run_lo)) != HV_OK) {
            atomic_store(&J->cancel, 1);
            return HV_ERR_CANCELLED;
        }
    }
    return HV_OK;
}

static hv_status unit_range(void *ctx, size_t b, size_t e, int t)
{
    job *J = ctx;
    worker *w = &J->workers[t];
    hv_status st = worker_ready(J, w);
    for (size_t u = b; u < e && st == HV_OK; ++u) {
        size_t lo, hi, from;
        if (ed_mode(J)) {
            size_t block = J->run_lo / HV_HALFTONE_BLOCK + u;
            lo = block * HV_HALFTONE_BLOCK;
            hi = HV_MIN(lo + HV_HALFTONE_BLOCK, J->run_hi);
            from = HV_MAX(lo, J->run_lo); /* layers before `from` are recomputed, not written */
        } else {
            lo = J->run_lo + u * RUN_LAYERS;
            hi = HV_MIN(lo + RUN_LAYERS, J->run_hi);
            from = lo;
        }
        for (size_t i = lo; i < hi && st == HV_OK; ++i) {
            if (atomic_load(&J->cancel)) return hv_error_set(HV_ERR_CANCELLED, "layers: cancelled");
            st = do_layer(J, w, i, i >= from);
            if (st == HV_OK && i >= from) st = layer_done(J, t);
        }
    }
    if (st != HV_OK) atomic_store(&J->cancel, 1);
    return st;
}

/* ---- manifest and GCVF ------------------------------------------------------------------------ */

static json_t *pair(double x, double y)
{
    double v[2] = {x, y};
    return hv_json_numbers(v, 2);
}

static void color_hex(char out[8], const uint8_t *rgb) { snprintf(out, 8, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]); }

/* A name, or null when the caller gave none (the Lua API). */
static json_t *name_or_null(const char *s) { return s ? hv_json_text(s) : json_null(); }

/* The manifest's document (NULL: out of memory). */
static json_t *manifest_doc(const job *J, const hv_layers_report *r)
{
    const hv_layers_options *o = J->o;
    json_t *doc = json_object();
    if (!doc) return NULL;
    char gen[64], hex[8];
    snprintf(gen, sizeof gen, "hovox %s", hv_version());
    int failed = hv_json_set(doc, "generator", json_string(gen));
    failed |= hv_json_set(doc, "mode", json_string(hv_layers_mode_name(o->mode)));
    if (uses_model(o))
        failed |= hv_json_set(doc, "method", json_string(hv_layers_method_name(J->src ? HV_LAYERS_DIRECT : o->method)));
    if (o->mode == HV_LAYERS_HALFTONE) {
        failed |= hv_json_set(doc, "halftone", json_string(hv_halftone_method_name(o->halftone)));
        /* JSON integers are 64-bit signed in jansson: larger seeds are written as reals */
        failed |= hv_json_set(doc, "seed", o->seed <= INT64_MAX ? json_integer((json_int_t)o->seed)
                                                                : json_real((double)o->seed));
    }
    failed |= hv_json_set(doc, "profile", hv_json_text(o->profile ? o->profile : "custom"));
    failed |= hv_json_set(doc, "dpi", pair(o->dpi[0], o->dpi[1]));
    failed |= hv_json_set(doc, "layer_height_mm", hv_json_number(o->layer_height));
    failed |= hv_json_set(doc, "width", json_integer(J->W));
    failed |= hv_json_set(doc, "height", json_integer(J->H));
    failed |= hv_json_set(doc, "bit_depth", json_integer(J->bit_depth));
    failed |= hv_json_set(doc, "pixel_mm", pair(J->grid.pixel[0], J->grid.pixel[1]));
    failed |= hv_json_set(doc, "origin_mm", pair(J->grid.origin[0], J->grid.origin[1]));
    if (J->placed) { /* the image's first column and row on the plate's pixel grid */
        json_t *pl = json_object();
        failed |= hv_json_set(pl, "column", json_integer(J->c0));
        failed |= hv_json_set(pl, "row", json_integer(J->r0));
        failed |= hv_json_set(doc, "plate", pl);
    }
    failed |= hv_json_set(doc, "fill_rule", json_string(hv_fill_rule_name(o->fill_rule)));
    failed |= hv_json_set(doc, "threshold_mm", hv_json_number(o->threshold));
    if (uses_model(o)) failed |= hv_json_set(doc, "poi_step", hv_json_number(o->poi_step));
    failed |= hv_json_set(doc, "mesh", name_or_null(o->mesh_name ? o->mesh_name : J->shape_name));
    if (J->model || J->src) failed |= hv_json_set(doc, "model", name_or_null(o->model_name));
    failed |= hv_json_set(doc, "bbox_mm", json_pack("{s:o, s:o}", "min", hv_json_numbers(J->bbox_min, 3), "max",
                                                    hv_json_numbers(J->bbox_max, 3)));
    if (o->mode == HV_LAYERS_HALFTONE) {
        color_hex(hex, o->background);
        failed |= hv_json_set(doc, "background", json_pack("{s:i, s:s}", "palette_index", 0, "color", hex));
    }
    json_t *mats = json_array();
    failed |= !mats;
    for (int g = 0; g < J->m && !failed; ++g) {
        const char *name = hv_material_name(J->table, g);
        float rgba[4];
        hv_material_color(J->table, g, rgba);
        uint8_t rgb[3];
        for (int k = 0; k < 3; ++k) rgb[k] = (uint8_t)lround(HV_CLAMP(rgba[k], 0.0f, 1.0f) * 255.0f);
        color_hex(hex, rgb);
        json_t *m = json_pack("{s:o}", "name", hv_json_text(name));
        failed |= !m;
        if (o->mode == HV_LAYERS_HALFTONE) failed |= hv_json_set(m, "palette_index", json_integer(g + 1));
        if (o->mode == HV_LAYERS_FRACTIONS) failed |= hv_json_set(m, "dir", hv_json_text(name));
        failed |= hv_json_set(m, "color", json_string(hex));
        failed |= hv_json_set(m, "target", hv_json_number(r->target[g]));
        if (o->mode == HV_LAYERS_HALFTONE) failed |= hv_json_set(m, "achieved", hv_json_number(r->achieved[g]));
        failed |= json_array_append_new(mats, m);
    }
    failed |= hv_json_set(doc, "materials", mats);
    failed |= hv_json_set(doc, "object_pixels", json_integer((json_int_t)r->object_pixels));
    if (r->compared)
        failed |= hv_json_set(doc, "compare",
                              json_pack("{s:s, s:o, s:o, s:I}", "what",
                                        "max over materials of |resample - direct| per object pixel", "mean",
                                        hv_json_number(r->diff_mean), "max", hv_json_number(r->diff_max),
                                        "direct_fallback_pixels", (json_int_t)r->direct_fallback));
    failed |= hv_json_set(doc, "layers_total", json_integer((json_int_t)J->nlayers));
    failed |= hv_json_set(doc, "range", json_pack("[I, I]", (json_int_t)J->first, (json_int_t)J->last));
    json_t *layers = json_array();
    failed |= !layers;
    for (size_t i = J->first; i < J->last && !failed; ++i) {
        char file[300];
        json_t *L = json_pack("{s:I}", "index", (json_int_t)i);
        failed |= !L;
        if (o->mode == HV_LAYERS_FRACTIONS) {
            /* "file" as in every mode (the first material's layer), "files" all of them */
            snprintf(file, sizeof file, "%s/layer-%05zu.png", J->m ? hv_material_name(J->table, 0) : "", i);
            failed |= hv_json_set(L, "file", hv_json_text(file));
            json_t *files = json_object();
            failed |= !files;
            for (int g = 0; g < J->m && !failed; ++g) {
                snprintf(file, sizeof file, "%s/layer-%05zu.png", hv_material_name(J->table, g), i);
                failed |= hv_json_set(files, hv_material_name(J->table, g), hv_json_text(file));
            }
            failed |= hv_json_set(L, "files", files);
        } else {
            snprintf(file, sizeof file, "layer-%05zu.png", i);
            failed |= hv_json_set(L, "file", json_string(file));
        }
        /* ten significant digits: 5.4135, not the 5.413500000000001 of the summation */
        char z[32];
        snprintf(z, sizeof z, "%.10g", J->layers[i].z);
        failed |= hv_json_set(L, "z_mm", hv_json_number(strtod(z, NULL)));
        failed |= json_array_append_new(layers, L);
    }
    failed |= hv_json_set(doc, "layers", layers);
    return hv_stack_manifest_done(doc, failed);
}

/* GCVF: ConfigFile.xml's materials with their RGBA and voxel counts (stack.c writes the rest). */
static void gcvf_of(const job *J, const hv_layers_report *r, hv_gcvf *g)
{
    const hv_layers_options *o = J->o;
    hv_gcvf_init(g, o->dpi, o->layer_height, J->W, J->H, J->first, J->last, J->bit_depth,
                 o->mode == HV_LAYERS_MASK ? 2 : J->palette_size);
    if (o->mode == HV_LAYERS_HALFTONE) memcpy(g->background, o->background, 3);
    if (o->mode == HV_LAYERS_MASK) {
        hv_gcvf_add(g, "model", (const uint8_t *)"\xff\xff\xff", r->object_pixels);
        return;
    }
    for (int k = 0; k < J->m; ++k) {
        uint64_t cnt = 0;
        for (size_t li = 0; li < J->last - J->first; ++li) cnt += J->st_count[li * (size_t)J->m + (size_t)k];
        hv_gcvf_add(g, hv_material_name(J->table, k), J->palette + 3 * (k + 1), cnt);
    }
}

/* ---- the job ---------------------------------------------------------------------------------- */

static hv_status job_prepare_output(job *J)
{
    const hv_layers_options *o = J->o;
    size_t count = J->last - J->first, m = (size_t)HV_MAX(J->m, 1);
    J->st_pixels = hv_calloc(count, sizeof *J->st_pixels);
    J->st_count = hv_calloc(count * m, sizeof *J->st_count);
    J->st_fallback = hv_calloc(count, sizeof *J->st_fallback);
    J->st_target = hv_calloc(count * m, sizeof *J->st_target);
    J->st_dsum = hv_calloc(count, sizeof *J->st_dsum);
    J->st_dmax = hv_calloc(count, sizeof *J->st_dmax);
    J->st_open = hv_calloc(count, sizeof *J->st_open);
    J->workers = hv_calloc((size_t)J->threads, sizeof *J->workers);
    if (!J->st_pixels || !J->st_count || !J->st_fallback || !J->st_target || !J->st_dsum || !J->st_dmax ||
        !J->st_open || !J->workers)
        return HV_ERR_NOMEM;
    if (o->gcvf_path && o->mode == HV_LAYERS_HALFTONE) {
        /* GrabCAD tells materials apart by colour */
        for (int a = 0; a < J->palette_size; ++a)
            for (int b = a + 1; b < J->palette_size; ++b)
                if (memcmp(J->palette + 3 * a, J->palette + 3 * b, 3) == 0)
                    return hv_error_option(HV_ERR_INVALID,
                                        "layers: %s and %s have the same colour #%02x%02x%02x; GCVF tells materials apart "
                                        "by colour (change the colours or {background})",
                                        a ? hv_material_name(J->table, a - 1) : "the background",
                                        hv_material_name(J->table, b - 1), J->palette[3 * a], J->palette[3 * a + 1],
                                        J->palette[3 * a + 2]);
    }
    hv_status st = HV_OK;
    if (needs_object(o)) {
        st = hv_object_from_model(J->model, &J->obj);
        if (st == HV_ERR_NOT_FOUND)
            return hv_error_option(HV_ERR_BAD_INPUT, "the model carries no grading definition (hovox.object.json): "
                                                  "{method} direct and {compare} need a model made by 'hovox grade'");
        if (st != HV_OK) return st;
        if (hv_object_materials(J->obj) != J->m)
            return hv_error_set(HV_ERR_BAD_INPUT, "the grading definition has %d materials, the model %d",
                                hv_object_materials(J->obj), J->m);
        st = hv_object_prepare(J->obj, J->progress);
        if (st != HV_OK) return st;
    }
    if (o->mode == HV_LAYERS_HALFTONE && o->halftone == HV_HALFTONE_BLUE_NOISE) {
        st = hv_bluenoise_tile(o->cache_dir, J->progress, &J->ranks, &J->bn_cached);
        if (st != HV_OK) return st;
        hv_bluenoise_offsets(o->seed, J->bn_off);
        if (J->placed) { /* the pattern is the plate's: a part shows the pixels a tray gives it */
            J->bn_off[0] = (int)(((J->bn_off[0] + J->c0) % HV_BLUENOISE_NX + HV_BLUENOISE_NX) % HV_BLUENOISE_NX);
            J->bn_off[1] = (int)(((J->bn_off[1] + J->r0) % HV_BLUENOISE_NY + HV_BLUENOISE_NY) % HV_BLUENOISE_NY);
            J->bn_off[2] = (int)((J->bn_off[2] + J->lift) % HV_BLUENOISE_NZ);
        }
    }
    return st;
}

/* ---- several processes -------------------------------------------------------------------------- */

/* Layer costs from the contours: each layer's object pixels (its contour area over the pixel
 * area) plus a fiftieth of the image for the empty pixels. */
typedef struct cost_job {
    job *J;
    double *cost;
} cost_job;

static hv_status cost_range(void *ctx, size_t b, size_t e, int t)
{
    (void)t;
    cost_job *c = ctx;
    job *J = c->J;
    double px = J->grid.pixel[0] * -J->grid.pixel[1];
    for (size_t i = b; i < e; ++i) {
        if (J->src) { /* no contours: every layer alike */
            c->cost[i] = (double)J->plane;
            continue;
        }
        hv_slice *slice = NULL;
        hv_status st = hv_solid_slice(J->solid, J->layers[J->first + i].z, &J->sopt, &slice);
        if (st != HV_OK) return st;
        c->cost[i] = hv_slice_get_stats(slice)->area / px + 0.02 * (double)J->plane;
        hv_slice_destroy(slice);
    }
    return HV_OK;
}

/* The plan's fingerprint: image, layers and their heights, materials, halftoning, and each
 * layer's estimated cost (which the mesh's contours give). */
static uint64_t job_hash(const job *J, const double *cost)
{
    const hv_layers_options *o = J->o;
    uint64_t h = HV_PLAN_HASH0;
    int64_t v[] = {J->W, J->H, J->m, (int64_t)J->first, (int64_t)J->last, o->mode, o->halftone, (int64_t)o->seed,
                   J->placed, J->c0, J->r0, J->bit_depth};
    h = hv_plan_hash(h, v, sizeof v);
    h = hv_plan_hash(h, J->grid.pixel, sizeof J->grid.pixel);
    for (size_t i = J->first; i < J->last; ++i) h = hv_plan_hash(h, &J->layers[i].z, sizeof J->layers[i].z);
    for (int g = 0; J->table && g < J->m; ++g) {
        const char *name = hv_material_name(J->table, g);
        h = hv_plan_hash(h, name, strlen(name) + 1);
    }
    h = hv_plan_hash(h, J->palette, sizeof J->palette);
    return hv_plan_hash(h, cost, (J->last - J->first) * sizeof *cost);
}

/* The ranges of `size` processes, their shares of the cost, the plan's fingerprint (hash: NULL
 * when not wanted). */
static hv_status job_partition(job *J, int size, size_t *ranges, double *share, uint64_t *hash)
{
    size_t n = J->last - J->first;
    double *cost = hv_malloc_array(n, sizeof *cost);
    hv_status st = cost ? HV_OK : HV_ERR_NOMEM;
    cost_job c = {J, cost};
    if (st == HV_OK) st = hv_parallel_for(n, 16, cost_range, &c, NULL, "layers");
    if (st == HV_OK) {
        hv_dist_partition(cost, J->first, J->last, ed_mode(J) ? HV_HALFTONE_BLOCK : RUN_LAYERS, size, ranges);
        if (hash) *hash = job_hash(J, cost);
        double total = 0;
        for (size_t i = 0; i < n; ++i) total += cost[i];
        for (int r = 0; share && r < size; ++r) {
            double part = 0;
            for (size_t i = ranges[2 * r]; i < ranges[2 * r + 1]; ++i) part += cost[i - J->first];
            share[r] = total > 0 ? part / total : 0;
        }
    }
    free(cost);
    return st;
}

static hv_status dist_share(job *J, const hv_dist *D)
{
    size_t *ranges = hv_malloc_array((size_t)D->size * 2, sizeof *ranges);
    uint64_t hash = 0;
    hv_status st = ranges ? job_partition(J, D->size, ranges, NULL, &hash) : HV_ERR_NOMEM;
    st = hv_dist_same_plan(D, hash, st);
    if (st == HV_OK) {
        J->run_lo = ranges[2 * D->rank];
        J->run_hi = ranges[2 * D->rank + 1];
    }
    free(ranges);
    return st;
}

hv_status hv_layers_partition(const hv_mesh *mesh, const hv_volume *model, const hv_layers_options *o, int ranks,
                              size_t *ranges, double *share)
{
    job J;
    hv_layers_place pl;
    if (ranks < 1) return hv_error_set(HV_ERR_INVALID, "layers: %d processes", ranks);
    hv_status st = name_model(model, o, job_plan(&J, mesh, model, o, NULL, options_place(o, &pl)));
    if (st == HV_OK) st = job_partition(&J, ranks, ranges, share, NULL);
    job_free(&J);
    return st;
}

/* Every process's per-layer statistics into rank 0's: each layer is one process's, the others
 * hold zeros there, so the sums are exact (counts below 2^53). */
static hv_status dist_gather(job *J, const hv_dist *D)
{
    size_t n = J->last - J->first, m = (size_t)HV_MAX(J->m, 1), per = 6 + 2 * m;
    double *v = hv_calloc(n * per, sizeof *v);
    if (!v) return HV_ERR_NOMEM;
    for (size_t li = 0; li < n; ++li) {
        double *p = v + li * per;
        p[0] = (double)J->st_pixels[li];
        p[1] = (double)J->st_fallback[li];
        p[2] = J->st_dsum[li];
        p[3] = J->st_dmax[li];
        p[4] = (double)J->st_open[li];
        for (size_t g = 0; g < m && J->m; ++g) {
            p[6 + g] = (double)J->st_count[li * m + g];
            p[6 + m + g] = J->st_target[li * m + g];
        }
    }
    D->sum_to_root(D->ctx, v, n * per);
    if (D->rank == 0)
        for (size_t li = 0; li < n; ++li) {
            const double *p = v + li * per;
            J->st_pixels[li] = (uint64_t)p[0];
            J->st_fallback[li] = (uint64_t)p[1];
            J->st_dsum[li] = p[2];
            J->st_dmax[li] = p[3];
            J->st_open[li] = (size_t)p[4];
            for (size_t g = 0; g < m && J->m; ++g) {
                J->st_count[li * m + g] = (uint64_t)p[6 + g];
                J->st_target[li * m + g] = p[6 + m + g];
            }
        }
    free(v);
    return HV_OK;
}

hv_status hv_layers_write(const hv_mesh *mesh, const hv_volume *model, const char *dir,
                          const hv_layers_options *o, const hv_progress *progress, hv_layers_report *report)
{
    if (!dir || !*dir) return hv_error_set(HV_ERR_INVALID, "layers: no output directory");
    job J;
    hv_layers_place pl;
    hv_status st = job_plan(&J, mesh, model, o, progress, options_place(o, &pl));
    hv_layers_report rep;
    memset(&rep, 0, sizeof rep);
    if (st == HV_OK) {
        fill_plan_report(&J, &rep);
        st = job_prepare_output(&J);
    }
    const hv_dist *D = o->dist;
    const char *subs[HV_MAX_MATERIALS + 1] = {NULL};
    for (int g = 0; o->mode == HV_LAYERS_FRACTIONS && st == HV_OK && g < J.m; ++g) subs[g] = hv_material_name(J.table, g);
    st = hv_stack_open(&J.out, st, dir, o->force, o->gcvf_path, subs, D);
    J.run_lo = J.first;
    J.run_hi = J.last;
    if (D && st == HV_OK) st = dist_share(&J, D); /* each process takes its share of the layers */
    if (st == HV_OK) st = hv_progress_report(progress, "layers", 0.0);
    if (st == HV_OK && J.run_hi > J.run_lo) {
        size_t units = ed_mode(&J) ? (J.run_hi - 1) / HV_HALFTONE_BLOCK - J.run_lo / HV_HALFTONE_BLOCK + 1
                                   : (J.run_hi - J.run_lo + RUN_LAYERS - 1) / RUN_LAYERS;
        atomic_store(&J.done, 0);
        atomic_store(&J.cancel, 0);
        st = hv_parallel_for(units, 1, unit_range, &J, NULL, "layers");
    }
    if (D) { /* all layers written, or every process stops; rank 0 gets the statistics */
        st = hv_dist_agree(D, st);
        if (st == HV_OK) st = dist_gather(&J, D);
    }
    if (st == HV_OK && J.out.root) {
        /* statistics, summed in layer order so they do not depend on the threads */
        size_t count = J.last - J.first;
        double dsum = 0;
        for (size_t li = 0; li < count; ++li) {
            rep.object_pixels += J.st_pixels[li];
            rep.direct_fallback += J.st_fallback[li];
            rep.open_polylines += J.st_open[li];
            dsum += J.st_dsum[li];
            rep.diff_max = HV_MAX(rep.diff_max, J.st_dmax[li]);
            for (int g = 0; g < J.m; ++g) {
                rep.target[g] += J.st_target[li * (size_t)J.m + (size_t)g];
                rep.achieved[g] += (double)J.st_count[li * (size_t)J.m + (size_t)g];
            }
        }
        double np = (double)rep.object_pixels;
        for (int g = 0; g < J.m; ++g) {
            rep.target[g] = np > 0 ? rep.target[g] / np : 0;
            rep.achieved[g] = np > 0 && o->mode == HV_LAYERS_HALFTONE ? rep.achieved[g] / np : 0;
        }
        if (J.obj) {
            uint64_t compared = rep.object_pixels - rep.direct_fallback;
            rep.compared = 1;
            rep.diff_mean = compared ? dsum / (double)compared : 0;
        }
        rep.bluenoise_cached = J.bn_cached;
        if (rep.open_polylines) {
            size_t n = strlen(rep.warnings);
            snprintf(rep.warnings + n, sizeof rep.warnings - n,
                     "%s is open: %zu contour polylines stayed open and were not filled (close_gap %g mm; a larger "
                     "gap joins wider holes)\n",
                     o->mesh_name ? o->mesh_name : "the mesh", rep.open_polylines, o->close_gap);
        }
        st = hv_progress_report(progress, "layers", 1.0);
    }
    /* rank 0 writes the manifest and the zip and renames; the others wait for it */
    json_t *doc = st == HV_OK && J.out.root ? manifest_doc(&J, &rep) : NULL;
    if (st == HV_OK && J.out.root && !doc) st = hv_error_set(HV_ERR_NOMEM, "layers: out of memory for the manifest");
    hv_gcvf g;
    gcvf_of(&J, &rep, &g);
    st = hv_stack_close(&J.out, st, dir, o->force, doc, o->manifest, o->manifest_user, &g, o->finish, o->finish_user,
                        progress);
    if (report) *report = rep;
    job_free(&J);
    return name_model(model, o, st);
}

/* ---- parts of a tray ---------------------------------------------------------------------------- */

/* A decoded voxel layer held by a tray part: the threads that render its layers read it at once
 * (decoded once, kept while later layers read it). */
typedef struct part_slab {
    int32_t k;
    int any, valid;
    int refs;      /* layers being rendered that read it */
    uint64_t used; /* when last taken (the least recently used unread slab is decoded over) */
    uint8_t *occ;
    float *mat;
} part_slab;

struct hv_layers_part {
    job J;
    hv_layers_options o; /* the job's options (J.o points here) */
    pthread_mutex_t lock; /* the slabs and the accessor */
    hv_accessor acc;
    part_slab *slab;
    size_t nslab;
    uint64_t tick;
    slab_store store;
};

static hv_status part_slab_get(job *J, void *ctx, int32_t k, int32_t keep, slab_ref *out);
static void part_slab_put(void *ctx, const slab_ref *r);

hv_status hv_layers_part_open(const hv_mesh *mesh, const hv_volume *model, const hv_layers_options *o,
                              const hv_layers_place *pl, const hv_progress *progress, hv_layers_part **out)
{
    *out = NULL;
    if (o->mode == HV_LAYERS_FRACTIONS || (o->mode == HV_LAYERS_HALFTONE && o->halftone == HV_HALFTONE_ERROR_DIFFUSION))
        return hv_error_set(HV_ERR_INVALID, "a tray's parts are halftoned with blue noise or printed as masks "
                                            "(error diffusion and fractions are per part)");
    hv_layers_part *p = hv_calloc(1, sizeof *p);
    if (!p) return HV_ERR_NOMEM;
    p->o = *o;
    pthread_mutex_init(&p->lock, NULL);
    p->store = (slab_store){part_slab_get, part_slab_put, p};
    hv_status st = job_plan(&p->J, mesh, model, &p->o, progress, pl);
    if (st == HV_OK && uses_voxels(&p->J)) hv_accessor_init(&p->acc, model);
    if (st == HV_OK) {
        p->J.no_files = 1;
        st = job_prepare_output(&p->J);
    }
    if (st != HV_OK) {
        hv_layers_part_close(p);
        return name_model(model, o, st);
    }
    *out = p;
    return HV_OK;
}

void hv_layers_part_close(hv_layers_part *p)
{
    if (!p) return;
    job_free(&p->J);
    for (size_t i = 0; i < p->nslab; ++i) {
        free(p->slab[i].occ);
        free(p->slab[i].mat);
    }
    free(p->slab);
    pthread_mutex_destroy(&p->lock);
    free(p);
}

void hv_layers_part_geometry(const hv_layers_part *p, int *c0, int *r0, int *w, int *h, size_t *layers)
{
    *c0 = p->J.c0;
    *r0 = p->J.r0;
    *w = p->J.W;
    *h = p->J.H;
    *layers = p->J.nlayers;
}

int hv_layers_part_materials(const hv_layers_part *p) { return p->J.m; }
const hv_material_table *hv_layers_part_table(const hv_layers_part *p) { return p->J.table; }
uint64_t hv_layers_part_memory(const hv_layers_part *p) { return p->J.fixed_memory; }
hv_status hv_layers_part_gather(hv_layers_part *p, const hv_dist *d) { return dist_gather(&p->J, d); }

uint64_t hv_layers_part_slab_bytes(const hv_layers_part *p)
{
    const job *J = &p->J;
    return uses_voxels(J) ? (uint64_t)J->vw * (uint64_t)J->vh * (1 + 4 * (uint64_t)(J->m + J->nd)) : 0;
}

static hv_status part_nomem(const job *J)
{
    return hv_error_set(HV_ERR_NOMEM, "layers: out of memory for the buffers of a %d x %d layer", J->W, J->H);
}

/* Voxel layer k from the part's slabs; when missing, decoded over the least recently used slab no
 * layer reads, or into a new one (so a part holds at most the slabs its layers being rendered read
 * at once: two each, three while one looks for the nearest occupied voxel layer). */
static hv_status part_slab_get(job *J, void *ctx, int32_t k, int32_t keep, slab_ref *out)
{
    (void)keep; /* a slab being read is never decoded over */
    hv_layers_part *p = ctx;
    pthread_mutex_lock(&p->lock);
    part_slab *e = NULL;
    for (size_t i = 0; i < p->nslab && !e; ++i)
        if (p->slab[i].valid && p->slab[i].k == k) e = &p->slab[i];
    for (size_t i = 0; i < p->nslab && !e; ++i)
        if (!p->slab[i].refs) e = &p->slab[i];
    if (e && !(e->valid && e->k == k))
        for (size_t i = 0; i < p->nslab; ++i)
            if (!p->slab[i].refs && p->slab[i].used < e->used) e = &p->slab[i];
    if (!e) {
        part_slab *g = hv_realloc(p->slab, (p->nslab + 1) * sizeof *g);
        size_t vox = (size_t)J->vw * (size_t)J->vh;
        if (g) {
            p->slab = g;
            e = &p->slab[p->nslab];
            memset(e, 0, sizeof *e);
            e->occ = hv_malloc(vox);
            e->mat = hv_malloc_array(vox * (size_t)HV_MAX(J->m + J->nd, 1), sizeof *e->mat);
        }
        if (!g || !e->occ || !e->mat) {
            if (e) {
                free(e->occ);
                free(e->mat);
            }
            pthread_mutex_unlock(&p->lock);
            return part_nomem(J);
        }
        ++p->nslab;
    }
    if (!(e->valid && e->k == k)) {
        e->any = slab_decode(J, &p->acc, k, e->occ, e->mat);
        e->k = k;
        e->valid = 1;
    }
    e->refs++;
    e->used = ++p->tick;
    *out = (slab_ref){e->occ, e->mat, e->any, (size_t)(e - p->slab)};
    pthread_mutex_unlock(&p->lock);
    return HV_OK;
}

static void part_slab_put(void *ctx, const slab_ref *r)
{
    hv_layers_part *p = ctx;
    pthread_mutex_lock(&p->lock);
    p->slab[r->id].refs--;
    pthread_mutex_unlock(&p->lock);
}

/* A tray thread's buffers: the printer-resolution ones of the largest part it rendered. */
struct hv_layers_scratch {
    worker w;
    void *buf[WB_COUNT];
    uint64_t cap[WB_COUNT];
};

static int is_slab(int k) { return k == WB_OCC0 || k == WB_OCC1 || k == WB_MAT0 || k == WB_MAT1; }

hv_layers_scratch *hv_layers_scratch_create(void) { return hv_calloc(1, sizeof(hv_layers_scratch)); }

void hv_layers_scratch_destroy(hv_layers_scratch *s)
{
    if (!s) return;
    for (int k = 0; k < WB_COUNT; ++k) free(s->buf[k]);
    free(s);
}

_Static_assert(WB_COUNT <= (int)HV_COUNT(((hv_layers_scratch_need *)0)->bytes), "hv_layers_scratch_need too small");

void hv_layers_scratch_need_add(hv_layers_scratch_need *n, const hv_layers_part *p)
{
    uint64_t sz[WB_COUNT];
    worker_sizes(&p->J, sz);
    for (int k = 0; k < WB_COUNT; ++k)
        if (!is_slab(k)) n->bytes[k] = HV_MAX(n->bytes[k], sz[k]);
}

uint64_t hv_layers_scratch_need_total(const hv_layers_scratch_need *n)
{
    uint64_t b = (uint64_t)1 << 20; /* contour crossings (as worker_bytes) */
    for (int k = 0; k < WB_COUNT; ++k) b += n->bytes[k];
    return b;
}

/* s's buffers grown to J's sizes (never shrunk; the slabs are the part's), w pointing at them. */
static hv_status scratch_ready(hv_layers_scratch *s, const job *J)
{
    uint64_t sz[WB_COUNT];
    worker_sizes(J, sz);
    for (int k = 0; k < WB_COUNT; ++k) {
        if (is_slab(k) || sz[k] <= s->cap[k]) continue;
        free(s->buf[k]);
        s->cap[k] = (s->buf[k] = hv_malloc((size_t)sz[k])) ? sz[k] : 0;
        if (!s->buf[k]) return part_nomem(J);
    }
    worker_point(&s->w, s->buf);
    return HV_OK;
}

hv_status hv_layers_part_render(hv_layers_part *p, hv_layers_scratch *s, size_t index, const uint8_t **pixels)
{
    job *J = &p->J;
    *pixels = NULL;
    hv_status st = scratch_ready(s, J);
    if (st != HV_OK) return st;
    s->w.store = &p->store;
    st = do_layer(J, &s->w, index, 1);
    s->w.store = NULL;
    *pixels = J->o->mode == HV_LAYERS_MASK ? s->w.mask : s->w.out;
    return st;
}

void hv_layers_part_report(const hv_layers_part *p, hv_layers_report *r)
{
    const job *J = &p->J;
    memset(r, 0, sizeof *r);
    fill_plan_report(J, r);
    for (size_t li = 0; li < J->nlayers; ++li) {
        r->object_pixels += J->st_pixels[li];
        for (int g = 0; g < J->m; ++g) {
            r->target[g] += J->st_target[li * (size_t)J->m + (size_t)g];
            r->achieved[g] += (double)J->st_count[li * (size_t)J->m + (size_t)g];
        }
    }
    double np = (double)r->object_pixels;
    for (int g = 0; g < J->m; ++g) {
        r->target[g] = np > 0 ? r->target[g] / np : 0;
        r->achieved[g] = np > 0 ? r->achieved[g] / np : 0;
    }
}
