/* slicing/contour_job.c - a contour job (hovox/slice.h hv_contours_write): plan a mesh's layers,
 * slice them with the weighted directed graph (Wu 2.4.1) and write a contour file (SVG or CLI,
 * contour_io.c) and a directory of per-layer SVGs, all or nothing. The CLI's `hovox contours`
 * and Lua's hovox.contours are this one function. */
#include <stdio.h>
#include <stdlib.h>

#include "core/internal.h"
#include "hovox/slice.h"
#include "hovox/solid.h"

typedef struct job {
    hv_contour_writer *writer;
    const char *dir, *label;
    const char *const *bodies; /* names of an assembly's bodies (nbodies > 1) */
    size_t nbodies;
    const double *lo, *hi;
    hv_contours_layer_fn layer;
    void *user;
    hv_contours_summary sum;
} job;

static hv_status one_svg(const job *j, size_t index, const hv_layer *layer, const hv_slice *slice)
{
    char path[4096];
    int n = snprintf(path, sizeof path, "%s/layer-%05zu.svg", j->dir, index);
    if (n < 0 || (size_t)n >= sizeof path) return hv_error_set(HV_ERR_IO, "%s: directory name too long", j->dir);
    hv_contour_writer *w = NULL;
    hv_status s = hv_contour_writer_open_bodies(path, HV_CONTOUR_SVG, 1, j->lo, j->hi, j->label, j->bodies, j->nbodies, &w);
    if (s == HV_OK) s = hv_contour_writer_add(w, layer, slice);
    if (s == HV_OK) s = hv_contour_writer_close(w);
    else hv_contour_writer_abort(w);
    return s;
}

static hv_status sink(void *user, size_t index, const hv_layer *layer, hv_slice **slice)
{
    job *j = user;
    const hv_slice_stats *st = hv_slice_get_stats(*slice);
    j->sum.loops += st->loops;
    j->sum.holes += st->holes;
    j->sum.open += st->open;
    j->sum.gaps_closed += st->gaps_closed;
    j->sum.dropped += st->dropped;
    hv_status s = j->writer ? hv_contour_writer_add(j->writer, layer, *slice) : HV_OK;
    if (s == HV_OK && j->dir) s = one_svg(j, index, layer, *slice);
    if (s == HV_OK && j->layer) s = j->layer(j->user, index, layer, *slice);
    return s;
}

hv_status hv_contours_write(const hv_mesh *mesh, const hv_contours_options *o, const char *name,
                            hv_contours_layer_fn layer, void *user, const hv_progress *progress,
                            hv_contours_summary *summary)
{
    static const char *const svg_files[] = {"layer-*.svg", NULL};
    static const hv_outdir_rules svg_dir = {"per-layer SVG directory", NULL, NULL, svg_files, 0, 0};
    if (!mesh || !o) return hv_error_set(HV_ERR_INVALID, "hv_contours_write: mesh and options are required");
    hv_status s = hv_contours_options_check(o);
    if (s != HV_OK) return s;
    job j = {NULL, NULL, name ? hv_basename(name) : "hovox", NULL, 0, NULL, NULL, layer, user, {0}};
    size_t nb = hv_mesh_body_count(mesh);
    const char **bodies = nb > 1 ? hv_calloc(nb, sizeof *bodies) : NULL;
    if (nb > 1 && !bodies) return HV_ERR_NOMEM;
    for (size_t b = 0; bodies && b < nb; ++b) bodies[b] = hv_mesh_body_at(mesh, b)->name;
    j.bodies = bodies;
    j.nbodies = nb;
    hv_slicer *slicer = NULL;
    hv_layer_plan *plan = NULL;
    char *tmpdir = NULL;
    hv_slicer_info info;
    s = hv_slicer_create(mesh, progress, &slicer);
    if (s == HV_OK && (s = hv_slicer_plan(slicer, o, &plan)) != HV_OK && name) hv_error_prefix(s, "%s: ", name);
    if (s == HV_OK) {
        hv_slicer_get_info(slicer, &info);
        j.lo = info.bbox_min;
        j.hi = info.bbox_max;
        j.sum.layers = hv_layer_plan_count(plan);
        for (int a = 0; a < 3; ++a) {
            j.sum.bbox_min[a] = info.bbox_min[a];
            j.sum.bbox_max[a] = info.bbox_max[a];
        }
    }
    if (s == HV_OK && j.sum.layers == 0)
        s = hv_error_set(HV_ERR_INVALID, "%s%sthe mesh is %g mm high: no layer of %g mm has its middle inside it",
                         name ? name : "", name ? ": " : "", info.bbox_max[2] - info.bbox_min[2],
                         o->adaptive[0] > 0 ? o->adaptive[0] : o->layer_height);
    hv_contour_format fmt;
    if (s == HV_OK && o->output && (s = hv_contour_format_for_path(o->output, o->binary, &fmt)) == HV_OK)
        s = hv_contour_writer_open_bodies(o->output, fmt, j.sum.layers, info.bbox_min, info.bbox_max, j.label, j.bodies,
                                          j.nbodies, &j.writer);
    if (s == HV_OK && o->per_layer) s = hv_outdir_begin(o->per_layer, &svg_dir, 0, &tmpdir);
    j.dir = tmpdir;
    hv_slice_options so;
    hv_slice_options_init(&so);
    so.close_gap = o->close_gap;
    if (s == HV_OK) s = hv_slicer_slice_plan(slicer, plan, &so, sink, &j, progress);
    if (s == HV_OK) s = hv_contour_writer_close(j.writer);
    else hv_contour_writer_abort(j.writer);
    if (s == HV_OK && tmpdir && (s = hv_outdir_commit(tmpdir, o->per_layer, &svg_dir, 0)) != HV_OK && o->output)
        remove(o->output); /* the file is ours by now: the job leaves both or neither */
    if (s != HV_OK && tmpdir) hv_outdir_abort(tmpdir);
    free(tmpdir);
    hv_layer_plan_destroy(plan);
    hv_slicer_destroy(slicer);
    free(bodies);
    if (s == HV_OK && summary) *summary = j.sum;
    return s;
}

/* The shape a model records (issue 28): a plain record is its mesh's job above; a Boolean tree is
 * cut layer by layer (hv_solid_slice: every leaf's loops combined by Clipper) on uniform layers. */
hv_status hv_contours_write_model(const hv_volume *model, const hv_contours_options *o, const char *name,
                                  hv_contours_layer_fn layer, void *user, const hv_progress *progress,
                                  hv_contours_summary *summary)
{
    static const char *const svg_files[] = {"layer-*.svg", NULL};
    static const hv_outdir_rules svg_dir = {"per-layer SVG directory", NULL, NULL, svg_files, 0, 0};
    if (!model || !o) return hv_error_set(HV_ERR_INVALID, "hv_contours_write_model: model and options are required");
    hv_status s = hv_contours_options_check(o);
    if (s != HV_OK) return s;
    hv_solid *solid = NULL;
    if ((s = hv_solid_for_model(model, NULL, "contours", name, NULL, progress, &solid)) != HV_OK)
        return name && s == HV_ERR_BAD_INPUT ? hv_error_prefix(s, "%s: ", name) : s;
    if (hv_solid_is_plain(solid) && hv_leaf_mesh(hv_solid_leaf(solid, 0))) {
        s = hv_contours_write(hv_leaf_mesh(hv_solid_leaf(solid, 0)), o, name, layer, user, progress, summary);
        hv_solid_close(solid);
        return s;
    }
    if (o->adaptive[0] > 0) {
        hv_solid_close(solid);
        return hv_error_option(HV_ERR_INVALID, "%s: {adaptive} layers follow one mesh's facets; this model records a Boolean of "
                               "several: give {layer_height}", name ? name : "contours");
    }
    job j = {NULL, NULL, name ? hv_basename(name) : "hovox", NULL, 0, NULL, NULL, layer, user, {0}};
    double lo[3], hi[3];
    hv_solid_bbox(solid, lo, hi);
    j.lo = lo;
    j.hi = hi;
    hv_layer_plan *plan = NULL;
    char *tmpdir = NULL;
    s = hv_layer_plan_uniform(lo[2], hi[2], o->first_layer, o->layer_height, &plan);
    if (s == HV_OK) {
        j.sum.layers = hv_layer_plan_count(plan);
        for (int a = 0; a < 3; ++a) {
            j.sum.bbox_min[a] = lo[a];
            j.sum.bbox_max[a] = hi[a];
        }
        if (j.sum.layers == 0)
            s = hv_error_set(HV_ERR_INVALID, "%s%sthe part is %g mm high: no layer of %g mm has its middle inside it",
                             name ? name : "", name ? ": " : "", hi[2] - lo[2], o->layer_height);
    }
    hv_contour_format fmt;
    if (s == HV_OK && o->output && (s = hv_contour_format_for_path(o->output, o->binary, &fmt)) == HV_OK)
        s = hv_contour_writer_open(o->output, fmt, j.sum.layers, lo, hi, j.label, &j.writer);
    if (s == HV_OK && o->per_layer) s = hv_outdir_begin(o->per_layer, &svg_dir, 0, &tmpdir);
    j.dir = tmpdir;
    hv_slice_options so;
    hv_slice_options_init(&so);
    so.close_gap = o->close_gap;
    const hv_layer *L = plan ? hv_layer_plan_layers(plan) : NULL;
    for (size_t i = 0; s == HV_OK && i < j.sum.layers; ++i) {
        hv_slice *sl = NULL;
        s = hv_solid_slice(solid, L[i].z, &so, &sl);
        if (s == HV_OK) s = sink(&j, i, &L[i], &sl);
        hv_slice_destroy(sl);
        if (s == HV_OK && progress && progress->fn &&
            progress->fn(progress->user, "contours", (double)(i + 1) / (double)j.sum.layers))
            s = hv_error_set(HV_ERR_CANCELLED, "cancelled");
    }
    if (s == HV_OK) s = hv_contour_writer_close(j.writer);
    else hv_contour_writer_abort(j.writer);
    if (s == HV_OK && tmpdir && (s = hv_outdir_commit(tmpdir, o->per_layer, &svg_dir, 0)) != HV_OK && o->output)
        remove(o->output);
    if (s != HV_OK && tmpdir) hv_outdir_abort(tmpdir);
    free(tmpdir);
    hv_layer_plan_destroy(plan);
    hv_solid_close(solid);
    if (s == HV_OK && summary) *summary = j.sum;
    return s;
}
