/* src/viewer/model_page.c - the page of a graded model (hovox/viewer.h): orthogonal slices of the
 * occupancy and the material fractions through voxel centres, packed per axis into atlas images
 * (8-bit grey: 255 p), which the page composites as sum p_j colour_j / sum p_j (the colour
 * hv_render gives a voxel, Wu 2.3) and reads under the pointer; and a few renders. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/image.h"
#include "hovox/material.h"
#include "hovox/render.h"
#include "viewer_internal.h"

/* in-plane axes of a slice normal to axis a: image x runs along u, image y down along -v */
static const int k_u[3] = {1, 0, 0}, k_v[3] = {2, 2, 1};

typedef struct mjob {
    const hv_volume *vol;
    int occ;          /* bool grid "occupancy", or -1: every active voxel is occupied */
    int m;
    int grid[64];     /* float grid of each material */
    int32_t lo[3], dims[3];
    int q;            /* in-plane step */
    int a;            /* the axis being filled */
    int n;            /* slices of axis a */
    int *slice;       /* their indices (from lo[a]) */
    int pw, ph, cols; /* a slice's samples, and tiles per atlas row */
    uint8_t **atlas;  /* m + 1 images: occupancy, then each material */
    size_t aw;        /* atlas width */
} mjob;

static int pick(int n, int q, int k)
{
    int a = k * q, c = HV_MIN(q, n - a);
    return a + (c - 1) / 2;
}

static int samples(int n, int q) { return (n + q - 1) / q; }

static hv_status fill_slices(void *ctx, size_t begin, size_t end, int thread)
{
    (void)thread;
    mjob *J = ctx;
    hv_accessor acc;
    hv_accessor_init(&acc, J->vol);
    int a = J->a, ua = k_u[a], va = k_v[a];
    for (size_t s = begin; s < end; ++s) {
        size_t tx = (s % (size_t)J->cols) * (size_t)J->pw, ty = (s / (size_t)J->cols) * (size_t)J->ph;
        for (int y = 0; y < J->ph; ++y)
            for (int x = 0; x < J->pw; ++x) {
                int32_t ijk[3];
                ijk[a] = J->lo[a] + J->slice[s];
                ijk[ua] = J->lo[ua] + pick(J->dims[ua], J->q, x);
                ijk[va] = J->lo[va] + pick(J->dims[va], J->q, J->ph - 1 - y);
                size_t at = (ty + (size_t)y) * J->aw + tx + (size_t)x;
                int on = J->occ >= 0 ? hv_accessor_bool(&acc, J->occ, ijk[0], ijk[1], ijk[2])
                                     : hv_accessor_active(&acc, ijk[0], ijk[1], ijk[2]);
                J->atlas[0][at] = on ? 255 : 0;
                for (int j = 0; j < J->m; ++j) {
                    float p = on ? hv_accessor_float(&acc, J->grid[j], ijk[0], ijk[1], ijk[2]) : 0.0f;
                    p = p > 0 ? (p < 1 ? p : 1) : 0; /* NaN and negatives count as 0, as the renderer's */
                    J->atlas[1 + j][at] = (uint8_t)lrintf(255.0f * p);
                }
            }
    }
    return HV_OK;
}

/* Occupied box and mean fractions over the occupied voxels, from the leaves. */
static int occupied(const mjob *J, int32_t lo[3], int32_t hi[3], double *mean, uint64_t *count)
{
    size_t nl = hv_volume_leaf_count(J->vol);
    const int32_t *org = hv_volume_leaf_origins(J->vol);
    uint64_t n = 0;
    for (int j = 0; j < J->m; ++j) mean[j] = 0;
    for (size_t l = 0; l < nl; ++l) {
        const uint64_t *act = hv_volume_leaf_mask(J->vol, l);
        const uint64_t *occ = J->occ >= 0 ? hv_volume_leaf_bool_c(J->vol, J->occ, l) : NULL;
        for (unsigned o = 0; o < HV_LEAF_SIZE; ++o) {
            if (!HV_BIT_GET(act, o) || (occ && !HV_BIT_GET(occ, o))) continue;
            int32_t p[3] = {org[3 * l] + (int32_t)(o >> 6), org[3 * l + 1] + (int32_t)((o >> 3) & 7),
                            org[3 * l + 2] + (int32_t)(o & 7)};
            for (int k = 0; k < 3; ++k) {
                if (!n || p[k] < lo[k]) lo[k] = p[k];
                if (!n || p[k] > hi[k]) hi[k] = p[k];
            }
            for (int j = 0; j < J->m; ++j) {
                float v = hv_volume_leaf_float_c(J->vol, J->grid[j], l)[o];
                mean[j] += v > 0 ? (v < 1 ? v : 1) : 0;
            }
            ++n;
        }
    }
    for (int j = 0; j < J->m && n; ++j) mean[j] /= (double)n;
    *count = n;
    return n > 0;
}

static hv_status png_uri(const uint8_t *px, int w, int h, int channels, hv_buf *uri)
{
    hv_png_options po;
    hv_png_options_init(&po);
    po.compression = 9;
    uint8_t *png = NULL;
    size_t size = 0;
    hv_status s = hv_png_encode(px, w, h, channels, 0, &po, &png, &size);
    if (s == HV_OK) vw_data_uri(uri, "image/png", png, size);
    free(png);
    if (s == HV_OK && uri->failed) s = HV_ERR_NOMEM;
    return s;
}

static hv_status add_uri(json_t *arr, const hv_buf *uri)
{
    return json_array_append_new(arr, json_string(uri->data)) ? hv_error_set(HV_ERR_NOMEM, "out of memory for the page")
                                                                : HV_OK;
}

/* ---- renders ---------------------------------------------------------------------------------- */

static hv_status renders(const hv_volume *vol, const hv_viewer_options *o, const hv_progress *progress, json_t *out,
                         int *count)
{
    hv_render_scene *scene = NULL;
    hv_status s = hv_render_scene_create_lazy(vol, progress, &scene);
    double lo[3], hi[3];
    if (s == HV_OK && !hv_render_scene_bounds(scene, lo, hi)) s = hv_error_set(HV_ERR_BAD_INPUT, "no occupied voxels to render");
    double c[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    static const char *const names[] = {"surface", "cut-away", "translucent volume, front", "cut at mid-height, top"};
    for (int i = 0; s == HV_OK && i < 4; ++i) {
        hv_render_options ro;
        hv_render_options_init(&ro);
        ro.width = o->size[0];
        ro.height = o->size[1];
        ro.background[3] = 0; /* transparent: the page's own background shows */
        ro.mode = i == 2 ? HV_RENDER_VOLUME : HV_RENDER_SURFACE;
        ro.camera.view = i == 2 ? HV_VIEW_FRONT : i == 3 ? HV_VIEW_TOP : HV_VIEW_ISO;
        char clip[160] = "";
        if (i == 1) snprintf(clip, sizeof clip, "x>%.17g&y<%.17g", c[0], c[1]);
        if (i == 3) {
            snprintf(clip, sizeof clip, "z>%.17g", c[2]);
            ro.camera.ortho = 1;
            ro.flat = 1;
        }
        if (clip[0]) {
            s = hv_clip_parse(clip, &ro.clip[0]);
            ro.clips = 1;
        }
        hv_image *img = NULL;
        if (s == HV_OK) s = hv_render_scene_image(scene, &ro, progress, &img);
        uint8_t *px = s == HV_OK ? hv_malloc_array((size_t)img->width * (size_t)img->height, 4) : NULL;
        if (s == HV_OK && !px) s = HV_ERR_NOMEM;
        hv_buf uri;
        hv_buf_init(&uri);
        if (s == HV_OK) {
            hv_image_to_rgba8(img, px);
            s = png_uri(px, img->width, img->height, 4, &uri);
        }
        if (s == HV_OK) {
            json_t *e = json_pack("{s:s, s:i, s:i}", "name", names[i], "w", img->width, "h", img->height);
            if (!e || json_array_append_new(out, e) || hv_json_set(e, "image", json_string(uri.data)))
                s = hv_error_set(HV_ERR_NOMEM, "out of memory for the page");
            else ++*count;
        }
        hv_buf_free(&uri);
        free(px);
        hv_image_destroy(img);
    }
    hv_render_scene_destroy(scene);
    return s;
}

/* ---- the page ----------------------------------------------------------------------------------- */

/* How many slices per axis (n), at which in-plane step (returned): at most max_samples samples
 * in all, fewer slices first, then a coarser step. */
static int plan_slices(const mjob *J, uint64_t max_samples, int n[3])
{
    int q = 1;
    uint64_t ch = (uint64_t)J->m + 1;
    for (int k = 0; k < 3; ++k) n[k] = J->dims[k];
#define TOTAL()                                                                                                        \
    (ch * ((uint64_t)n[0] * (uint64_t)samples(J->dims[1], q) * (uint64_t)samples(J->dims[2], q) +                       \
           (uint64_t)n[1] * (uint64_t)samples(J->dims[0], q) * (uint64_t)samples(J->dims[2], q) +                       \
           (uint64_t)n[2] * (uint64_t)samples(J->dims[0], q) * (uint64_t)samples(J->dims[1], q)))
    while (TOTAL() > max_samples && HV_MAX(n[0], HV_MAX(n[1], n[2])) > 16)
        for (int k = 0; k < 3; ++k) n[k] = HV_MAX(1, HV_MIN(n[k], 16 + (n[k] - 16) / 2));
    while (TOTAL() > max_samples && q < (1 << 20)) q *= 2;
#undef TOTAL
    return q;
}

/* The page's materials: name, colour, mean fraction and properties ([value, unit]); nonzero
 * when out of memory. */
static int materials_json(const hv_material_table *t, int m, const double *mean, json_t *mats)
{
    int fail = 0;
    for (int j = 0; !fail && j < m; ++j) {
        float rgba[4];
        hv_material_color(t, j, rgba);
        uint8_t rgb[3];
        for (int k = 0; k < 3; ++k) rgb[k] = (uint8_t)lrintf(255.0f * HV_CLAMP(rgba[k], 0.0f, 1.0f));
        char col[8];
        snprintf(col, sizeof col, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
        json_t *e = json_object();
        fail |= !e || json_array_append_new(mats, e);
        if (fail) break;
        fail |= hv_json_set(e, "name", hv_json_text(hv_material_name(t, j)));
        fail |= hv_json_set(e, "color", json_string(col));
        fail |= hv_json_set(e, "mean", hv_json_number(mean[j]));
        json_t *props = json_object(); /* name: [value, unit] */
        fail |= hv_json_set(e, "properties", props);
        for (int k = 0; !fail && k < hv_material_property_count(t, j); ++k) {
            const char *key = hv_material_property_key(t, j, k), *unit = NULL;
            double v = 0;
            hv_material_property(t, j, key, &v, &unit);
            fail |= hv_json_set(props, key, json_pack("[o,s]", hv_json_number(v), unit ? unit : ""));
        }
    }
    return fail;
}

/* Axis a's slices (J->n of them): drawn into one atlas per channel (occupancy, then each
 * material), each a PNG data URI in the axis' entry of `axes`. */
static hv_status axis_atlas(mjob *J, int a, const char *vname, json_t *axes, const hv_progress *progress)
{
    static const char *const axis_name[3] = {"x", "y", "z"};
    hv_status s = HV_OK;
    J->a = a;
    J->pw = samples(J->dims[k_u[a]], J->q);
    J->ph = samples(J->dims[k_v[a]], J->q);
    /* tiles in a square-ish atlas */
    J->cols = HV_MAX(1, (int)ceil(sqrt((double)J->n * J->ph / J->pw)));
    J->cols = HV_MIN(J->cols, J->n);
    int rows = (J->n + J->cols - 1) / J->cols;
    J->aw = (size_t)J->cols * (size_t)J->pw;
    size_t ah = (size_t)rows * (size_t)J->ph;
    if (J->aw > 65535 || ah > 65535)
        return hv_error_set(HV_ERR_LIMIT, "%s: a %zu x %zu slice atlas is too large for a PNG page (lower max_samples)",
                            vname, J->aw, ah);
    J->slice = hv_malloc_array((size_t)J->n, sizeof *J->slice);
    J->atlas = hv_calloc((size_t)J->m + 1, sizeof *J->atlas);
    if (!J->slice || !J->atlas) s = HV_ERR_NOMEM;
    for (int c = 0; s == HV_OK && c <= J->m; ++c)
        if (!(J->atlas[c] = hv_calloc(J->aw * ah, 1))) s = HV_ERR_NOMEM;
    for (int i = 0; s == HV_OK && i < J->n; ++i) J->slice[i] = (int)(((double)i + 0.5) * J->dims[a] / J->n);
    if (s == HV_OK) s = hv_parallel_for((size_t)J->n, 1, fill_slices, J, progress, "slices");
    json_t *e = json_object(), *imgs = json_array(), *idx = json_array();
    if (s == HV_OK && (!e || json_array_append_new(axes, e) || hv_json_set(e, "images", imgs) ||
                       hv_json_set(e, "slices", idx)))
        s = hv_error_set(HV_ERR_NOMEM, "out of memory for the page");
    if (s == HV_OK) {
        int f = hv_json_set(e, "axis", json_string(axis_name[a])) | hv_json_set(e, "w", json_integer(J->pw)) |
                hv_json_set(e, "h", json_integer(J->ph)) | hv_json_set(e, "cols", json_integer(J->cols));
        for (int i = 0; i < J->n; ++i) f |= json_array_append_new(idx, json_integer(J->slice[i]));
        if (f) s = hv_error_set(HV_ERR_NOMEM, "out of memory for the page");
    }
    for (int c = 0; s == HV_OK && c <= J->m; ++c) {
        hv_buf uri;
        hv_buf_init(&uri);
        s = png_uri(J->atlas[c], (int)J->aw, (int)ah, 1, &uri);
        if (s == HV_OK) s = add_uri(imgs, &uri);
        hv_buf_free(&uri);
    }
    for (int c = 0; J->atlas && c <= J->m; ++c) free(J->atlas[c]);
    free(J->atlas);
    free(J->slice);
    J->atlas = NULL;
    J->slice = NULL;
    return s;
}

hv_status hv_viewer_model_write(const hv_volume *vol, const char *name, const char *html_path,
                                const hv_viewer_options *opt, const hv_progress *progress, hv_viewer_report *report)
{
    hv_viewer_options defaults;
    hv_viewer_report rep;
    memset(&rep, 0, sizeof rep);
    rep.kind = HV_VIEWER_MODEL;
    if (!vol) return hv_error_set(HV_ERR_INVALID, "viewer: no model");
    hv_status s = vw_page_begin(&opt, &defaults, html_path);
    if (s != HV_OK) return s;
    const char *vname = name ? name : hv_volume_name(vol);
    mjob J;
    memset(&J, 0, sizeof J);
    J.vol = vol;
    J.occ = hv_volume_grid_find(vol, "occupancy");
    if (J.occ >= 0 && hv_volume_grid_type(vol, J.occ) != HV_GRID_BOOL) J.occ = -1;
    hv_material_table *t = NULL;
    s = hv_material_table_load(vol, &t);
    if (s == HV_ERR_NOT_FOUND) { /* not graded: the occupancy alone, in grey */
        hv_error_clear();
        s = HV_OK;
    }
    if (s != HV_OK) return hv_error_prefix(s, "%s: ", vname);
    J.m = t ? hv_material_count(t) : 0;
    if (J.m > 64) {
        hv_material_table_destroy(t);
        return hv_error_set(HV_ERR_LIMIT, "%s: %d materials (a page shows at most 64)", vname, J.m);
    }
    for (int j = 0; j < J.m; ++j) J.grid[j] = hv_material_grid(vol, t, j);
    double mean[64];
    uint64_t nocc = 0;
    int32_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    if (!occupied(&J, lo, hi, mean, &nocc)) {
        hv_material_table_destroy(t);
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: the model has no occupied voxels: nothing to show", vname);
    }
    for (int k = 0; k < 3; ++k) {
        J.lo[k] = lo[k];
        J.dims[k] = (int)(hi[k] - lo[k] + 1);
        rep.dims[k] = J.dims[k];
    }
    hv_transform xf = hv_volume_get_transform(vol);
    memcpy(rep.voxel, xf.voxel, sizeof rep.voxel);
    rep.materials = J.m;
    int n[3];
    J.q = plan_slices(&J, opt->max_samples, n);
    rep.slice_step = J.q;

    json_t *doc = json_object(), *axes = json_array(), *mats = json_array(), *rends = json_array();
    int fail = !doc || hv_json_set(doc, "axes", axes) || hv_json_set(doc, "materials", mats) ||
               hv_json_set(doc, "renders", rends);
    double origin[3], vox[3], ilo[3] = {lo[0], lo[1], lo[2]};
    hv_volume_index_to_world(vol, ilo, origin);
    memcpy(vox, xf.voxel, sizeof vox);
    double dims_d[3] = {J.dims[0], J.dims[1], J.dims[2]};
    fail |= hv_json_set(doc, "kind", json_string("model"));
    fail |= hv_json_set(doc, "title", hv_json_text(opt->title ? opt->title : hv_basename(vname)));
    fail |= hv_json_set(doc, "file", hv_json_text(vname));
    fail |= hv_json_set(doc, "dims", hv_json_numbers(dims_d, 3));
    fail |= hv_json_set(doc, "voxel_mm", hv_json_numbers(vox, 3));
    fail |= hv_json_set(doc, "origin_mm", hv_json_numbers(origin, 3));
    fail |= hv_json_set(doc, "occupied", json_integer((json_int_t)nocc));
    fail |= hv_json_set(doc, "step", json_integer(J.q));
    if (!fail) fail |= materials_json(t, J.m, mean, mats);
    hv_material_table_destroy(t);
    if (fail) s = hv_error_set(HV_ERR_NOMEM, "out of memory for the page");
    for (int a = 0; s == HV_OK && a < 3; ++a) {
        J.n = n[a];
        s = axis_atlas(&J, a, vname, axes, progress);
        rep.slices[a] = J.n;
    }
    if (s == HV_OK && !opt->no_renders) s = renders(vol, opt, progress, rends, &rep.render_count);
    if (s == HV_OK) {
        json_t *warn = json_array();
        if (hv_json_set(doc, "warnings", warn)) s = HV_ERR_NOMEM;
    }
    char *data = s == HV_OK ? vw_json_for_script(doc) : NULL;
    if (s == HV_OK && !data) s = HV_ERR_NOMEM;
    json_decref(doc);
    if (s == HV_OK) s = vw_page_write(html_path, opt->title ? opt->title : hv_basename(vname), data, &rep.bytes);
    free(data);
    if (report) *report = rep;
    return s;
}
