/* python/src/output.c - Python: a model's outputs, each reading the options of its CLI command
 * through the library's option set: model.render (hv_render_option_set; the image also as an
 * array, without a copy), model.export (hv_export_option_set), model.layers
 * (hv_layers_option_set), model.profile (hv_profile_option_set; the samples as arrays), and
 * hovox.contours (hv_contours_option_set; the loops as arrays). Long calls release the GIL. */
#include "hvpy.h"

#include <stdlib.h>

#include "hovox/export.h"
#include "hovox/image.h"
#include "hovox/colour.h"
#include "hovox/layers.h"
#include "hovox/lut.h"
#include "hovox/scan.h"
#include "hovox/plot.h"
#include "hovox/profile.h"
#include "hovox/render.h"
#include "hovox/slice.h"

/* The keywords of a call with the progress callback taken out; `path` (if not NULL) the output
 * path keyword, required when `what` is not NULL. */
typedef struct out_call {
    PyObject *progress, *rest;
    hvpy_arena a;
} out_call;

static int out_begin(out_call *oc, PyObject *kw)
{
    oc->progress = oc->rest = NULL;
    oc->a.keep = NULL;
    if (hvpy_split_progress(kw, &oc->progress, &oc->rest) < 0) return -1;
    return hvpy_arena_init(&oc->a);
}

static void out_end(out_call *oc)
{
    Py_XDECREF(oc->progress);
    Py_XDECREF(oc->rest);
    hvpy_arena_free(&oc->a);
}

/* The output path: positional argument `pos` (may be NULL) or keyword `key`. */
static const char *out_path(out_call *oc, PyObject *pos, const char *key, const char *what)
{
    PyObject *v = pos ? pos : hvpy_kw(oc->rest, key);
    if (pos && hvpy_kw(oc->rest, key)) {
        PyErr_Format(PyExc_TypeError, "%s given twice", key);
        return NULL;
    }
    if (!v) {
        if (what) hvpy_raise(HV_ERR_INVALID, "%s is required (%s)", key, what);
        return NULL;
    }
    return hvpy_arena_str(&oc->a, v, key);
}

static void image_free(PyObject *cap) { hv_image_destroy(PyCapsule_GetPointer(cap, "hovox.image")); }

/* model.render(path=None, *, progress=None, **options of `hovox render`) -> (H, W, 4) float32 RGBA,
 * premultiplied alpha (hovox.rgba8 gives the 8-bit straight-alpha pixels of the PNG); writes the
 * image to path (.png, .exr, .tif) when given */
static PyObject *model_render(PyObject *self, PyObject *args, PyObject *kw)
{
    static const char *const extra[] = {"path", NULL};
    PyObject *pos = NULL;
    if (!PyArg_ParseTuple(args, "|O:render", &pos)) return NULL;
    hv_volume *vol = HVPY_MODEL(self);
    if (!vol) return NULL;
    out_call oc;
    PyObject *res = NULL;
    if (out_begin(&oc, kw) < 0) goto done;
    hv_render_options o;
    if (hvpy_read_options(oc.rest, hv_render_option_set(), &o, extra, &oc.a) < 0) goto done;
    const char *path = out_path(&oc, pos, "path", NULL);
    if (!path && PyErr_Occurred()) goto done;
    hvpy_call c;
    hv_image *img = NULL;
    hvpy_begin(&c, oc.progress, &self, 1);
    hv_status s = hv_render(vol, &o, &c.prog, &img);
    if (s == HV_OK && path) s = hv_image_write(img, path);
    hvpy_end(&c);
    if (s != HV_OK) {
        hv_image_destroy(img);
        hvpy_call_fail(&c, s);
        goto done;
    }
    PyObject *cap = PyCapsule_New(img, "hovox.image", image_free);
    if (!cap) {
        hv_image_destroy(img);
        goto done;
    }
    npy_intp d[3] = {img->height, img->width, 4};
    PyObject *arr = PyArray_New(&PyArray_Type, 3, d, NPY_FLOAT32, NULL, img->rgba, 0, NPY_ARRAY_CARRAY, NULL);
    if (!arr || PyArray_SetBaseObject((PyArrayObject *)arr, cap) < 0) {
        if (!arr) Py_DECREF(cap);
        Py_XDECREF(arr);
        goto done;
    }
    res = hvpy_call_done(&c, arr);
done:
    out_end(&oc);
    return res;
}

/* model.export(path, *, progress=None, **options of `hovox export`) -> report */
static PyObject *model_export(PyObject *self, PyObject *args, PyObject *kw)
{
    static const char *const extra[] = {"path", NULL};
    PyObject *pos = NULL;
    if (!PyArg_ParseTuple(args, "|O:export", &pos)) return NULL;
    hv_volume *vol = HVPY_MODEL(self);
    if (!vol) return NULL;
    out_call oc;
    PyObject *res = NULL;
    if (out_begin(&oc, kw) < 0) goto done;
    hv_export_options o;
    if (hvpy_read_options(oc.rest, hv_export_option_set(), &o, extra, &oc.a) < 0) goto done;
    const char *path = out_path(&oc, pos, "path", hv_export_format_list());
    if (!path) goto done;
    o.format = hv_export_format_from_path(path);
    hvpy_call c;
    hv_export_report rep;
    hvpy_begin(&c, oc.progress, &self, 1);
    o.progress = &c.prog;
    hv_status s = hv_export_write(vol, path, &o, &rep);
    hvpy_end(&c);
    if (s != HV_OK) {
        hvpy_call_fail(&c, s);
        goto done;
    }
    res = hvpy_call_done(&c, Py_BuildValue("{s:K,s:K,s:K,s:s,s:s,s:K}", "points", (unsigned long long)rep.points, "cells",
                                           (unsigned long long)rep.cells, "occupied", (unsigned long long)rep.occupied,
                                           "arrays", rep.names, "notes", rep.notes, "bytes",
                                           (unsigned long long)rep.file_bytes));
done:
    out_end(&oc);
    return res;
}

/* What model.layers, mesh.layers and hovox.layers_scan return, the keys of Lua's report
 * (hv_lua_push_layers_report): {width, height, layers, first, last, object_pixels, diff_mean,
 * diff_max (compared), warnings, materials = {<name of t>: {target, achieved}} (t NULL: empty),
 * colour = {skin_voxels | printer_voxels (skin->printer_voxels), mean_de2000_target,
 * max_de2000_target, mean_de2000_achieved (halftone)} when skin}. NULL: a Python error. */
static PyObject *layers_report(const hv_layers_report *r, const hv_material_table *t, const hv_colour_skin *skin)
{
    PyObject *d = Py_BuildValue("{s:i,s:i,s:n,s:n,s:n,s:K,s:s}", "width", r->width, "height", r->height, "layers",
                                (Py_ssize_t)r->layers_total, "first", (Py_ssize_t)r->first, "last",
                                (Py_ssize_t)r->last, "object_pixels", (unsigned long long)r->object_pixels,
                                "warnings", r->warnings);
    PyObject *x = NULL, *y = NULL;
    int ok = d != NULL;
    if (ok && r->compared) {
        ok = (x = PyFloat_FromDouble(r->diff_mean)) && (y = PyFloat_FromDouble(r->diff_max)) &&
             PyDict_SetItemString(d, "diff_mean", x) == 0 && PyDict_SetItemString(d, "diff_max", y) == 0;
        Py_CLEAR(x);
        Py_CLEAR(y);
    }
    PyObject *mats = ok ? PyDict_New() : NULL;
    ok = mats != NULL;
    for (int j = 0; ok && t && j < r->materials && j < hv_material_count(t); ++j) {
        ok = (x = Py_BuildValue("{s:d,s:d}", "target", r->target[j], "achieved", r->achieved[j])) &&
             PyDict_SetItemString(mats, hv_material_name(t, j), x) == 0;
        Py_CLEAR(x);
    }
    ok = ok && PyDict_SetItemString(d, "materials", mats) == 0;
    Py_XDECREF(mats);
    if (ok && skin) {
        x = Py_BuildValue("{s:K,s:d,s:d}", skin->printer_voxels ? "printer_voxels" : "skin_voxels",
                          (unsigned long long)skin->target.voxels, "mean_de2000_target", skin->target.mean_de2000,
                          "max_de2000_target", skin->target.max_de2000);
        if (x && skin->has_achieved) ok = (y = PyFloat_FromDouble(skin->achieved.mean_de2000)) &&
                                          PyDict_SetItemString(x, "mean_de2000_achieved", y) == 0;
        ok = ok && x && PyDict_SetItemString(d, "colour", x) == 0;
        Py_CLEAR(x);
        Py_CLEAR(y);
    }
    if (!ok) Py_CLEAR(d);
    return d;
}

/* model.layers([mesh,] dir, *, progress=None, **options of `hovox layers`) -> report */
static PyObject *model_layers(PyObject *self, PyObject *args, PyObject *kw)
{
    static const char *const extra[] = {"mesh", "dir", NULL};
    PyObject *mo = NULL, *pos = NULL;
    if (!PyArg_ParseTuple(args, "|OO:layers", &mo, &pos)) return NULL;
    hv_volume *vol = HVPY_MODEL(self);
    if (!vol) return NULL;
    out_call oc;
    PyObject *res = NULL;
    if (out_begin(&oc, kw) < 0) goto done;
    hv_layers_options o;
    if (hvpy_read_options(oc.rest, hv_layers_option_set(), &o, extra, &oc.a) < 0) goto done;
    if (!mo) mo = hvpy_kw(oc.rest, "mesh");
    else if (hvpy_kw(oc.rest, "mesh")) {
        PyErr_SetString(PyExc_TypeError, "mesh given twice");
        goto done;
    }
    /* the mesh is optional (issue 28): the model records its shape; model.layers(dir=...),
     * model.layers(None, dir) and model.layers("dir") cut that, a mesh given must match it */
    if (mo && !pos && (PyUnicode_Check(mo) || PyBytes_Check(mo) || PyObject_HasAttrString(mo, "__fspath__"))) {
        pos = mo;
        mo = NULL;
    }
    if (mo == Py_None) mo = NULL;
    hv_mesh *mesh = mo ? HVPY_MESH(mo) : NULL;
    if (mo && !mesh) goto done;
    const char *dir = out_path(&oc, pos, "dir", "the stack's directory");
    if (!dir) goto done;
    hvpy_call c;
    hv_layers_report rep;
    PyObject *pins[2] = {self, mo};
    hv_colour_skin skin; /* a painted model: the skin's dE2000 in the manifest, as the CLI writes it */
    if (hv_layers_colour_hook(&o, vol, &skin) != HV_OK) hv_error_clear();
    hvpy_begin(&c, oc.progress, pins, mo ? 2 : 1);
    hv_status s = hv_layers_write(mesh, vol, dir, &o, &c.prog, &rep);
    hvpy_end(&c);
    if (s != HV_OK) {
        hv_colour_map_destroy(skin.map);
        hvpy_call_fail(&c, s);
        goto done;
    }
    hv_material_table *t = NULL;
    if (rep.materials > 0 && hv_material_table_load(vol, &t) != HV_OK) t = NULL;
    PyObject *d = layers_report(&rep, t, skin.map ? &skin : NULL);
    hv_material_table_destroy(t);
    hv_colour_map_destroy(skin.map);
    res = d ? hvpy_call_done(&c, d) : NULL;
done:
    out_end(&oc);
    return res;
}

/* model.profile(*, csv=None, plot=None, **options of `hovox profile`) -> {t, xyz, inside, fractions,
 * materials, property} */
static PyObject *model_profile(PyObject *self, PyObject *args, PyObject *kw)
{
    static const char *const extra[] = {"csv", "plot", NULL};
    if (PyTuple_GET_SIZE(args) > 0) return PyErr_Format(PyExc_TypeError, "profile takes keyword arguments only");
    hv_volume *vol = HVPY_MODEL(self);
    if (!vol) return NULL;
    out_call oc;
    PyObject *res = NULL;
    hv_profile *p = NULL;
    if (out_begin(&oc, kw) < 0) goto done;
    if (oc.progress) {
        PyErr_SetString(PyExc_TypeError, "profile takes no progress callback");
        goto done;
    }
    hv_profile_options o;
    if (hvpy_read_options(oc.rest, hv_profile_option_set(), &o, extra, &oc.a) < 0) goto done;
    const char *csv = out_path(&oc, NULL, "csv", NULL), *plot = PyErr_Occurred() ? NULL : out_path(&oc, NULL, "plot", NULL);
    if (PyErr_Occurred()) goto done;
    hvpy_call c;
    hvpy_begin(&c, NULL, &self, 1);
    hv_status s = hv_profile_sample_with(vol, &o, &p);
    if (s == HV_OK) s = hv_profile_write_files(p, &o, csv, plot);
    hvpy_end(&c);
    if (s != HV_OK) {
        hvpy_call_fail(&c, s);
        goto done;
    }
    int ns = hv_profile_samples(p), m = hv_profile_materials(p);
    npy_intp d1[1] = {ns}, d3[2] = {ns, 3}, dm[2] = {ns, m};
    PyObject *t = PyArray_EMPTY(1, d1, NPY_FLOAT64, 0), *xyz = PyArray_EMPTY(2, d3, NPY_FLOAT64, 0),
             *in = PyArray_EMPTY(1, d1, NPY_BOOL, 0), *fr = PyArray_EMPTY(2, dm, NPY_FLOAT64, 0),
             *names = PyList_New(m);
    if (!t || !xyz || !in || !fr || !names) {
        Py_XDECREF(t), Py_XDECREF(xyz), Py_XDECREF(in), Py_XDECREF(fr), Py_XDECREF(names);
        goto done;
    }
    for (int i = 0; i < ns; ++i) {
        ((double *)PyArray_DATA((PyArrayObject *)t))[i] = hv_profile_t(p, i);
        hv_profile_position(p, i, (double *)PyArray_DATA((PyArrayObject *)xyz) + 3 * i);
        ((npy_bool *)PyArray_DATA((PyArrayObject *)in))[i] = (npy_bool)(hv_profile_inside(p, i) != 0);
        memcpy((double *)PyArray_DATA((PyArrayObject *)fr) + (size_t)i * (size_t)m, hv_profile_fractions(p, i),
               (size_t)m * sizeof(double));
    }
    for (int j = 0; j < m; ++j) PyList_SET_ITEM(names, j, PyUnicode_FromString(hv_material_name(hv_profile_table(p), j)));
    PyObject *dict = Py_BuildValue("{s:N,s:N,s:N,s:N,s:N}", "t", t, "xyz", xyz, "inside", in, "fractions", fr,
                                   "materials", names);
    const char *unit, *prop = hv_profile_property(p, &unit);
    if (dict && prop) {
        PyObject *vals = PyArray_EMPTY(1, d1, NPY_FLOAT64, 0);
        for (int i = 0; vals && i < ns; ++i) ((double *)PyArray_DATA((PyArrayObject *)vals))[i] = hv_profile_property_value(p, i);
        PyObject *pd = vals ? Py_BuildValue("{s:s,s:s,s:N}", "name", prop, "unit", unit, "values", vals) : NULL;
        if (!pd || PyDict_SetItemString(dict, "property", pd) < 0) Py_CLEAR(dict);
        Py_XDECREF(pd);
    }
    res = dict ? hvpy_call_done(&c, dict) : NULL;
done:
    hv_profile_destroy(p);
    out_end(&oc);
    return res;
}

/* ---- contours ------------------------------------------------------------------------------------- */

typedef struct contour_run {
    hvpy_call *call;
    PyObject *list;
    int keep_loops;
    const hv_mesh *mesh;
} contour_run;

static PyObject *layer_dict(const contour_run *r, const hv_layer *layer, const hv_slice *slice)
{
    const hv_slice_stats *st = hv_slice_get_stats(slice);
    PyObject *d = Py_BuildValue("{s:d,s:d,s:d,s:d,s:n,s:n,s:n}", "z", layer->z, "bottom", layer->bottom, "top", layer->top,
                                "area", st->area, "loops", (Py_ssize_t)st->loops, "holes", (Py_ssize_t)st->holes, "open",
                                (Py_ssize_t)st->open);
    if (!d || !r->keep_loops) return d;
    size_t n = hv_slice_loop_count(slice);
    const hv_slice_loop *loops = hv_slice_loops(slice);
    PyObject *list = PyList_New((Py_ssize_t)n);
    for (size_t i = 0; list && i < n; ++i) {
        const hv_slice_loop *lp = &loops[i];
        npy_intp dims[2] = {(npy_intp)lp->count, 2};
        PyObject *pts = PyArray_EMPTY(2, dims, NPY_FLOAT64, 0);
        if (pts) memcpy(PyArray_DATA((PyArrayObject *)pts), lp->xy, lp->count * 2 * sizeof(double));
        const hv_mesh_body *b = hv_mesh_body_at(r->mesh, (size_t)lp->body);
        PyObject *ld = pts ? Py_BuildValue("{s:N,s:O,s:i,s:n,s:d,s:s}", "points", pts, "closed", lp->closed ? Py_True : Py_False,
                                           "orientation", lp->orientation, "parent", (Py_ssize_t)lp->parent, "area",
                                           lp->area, "body", b ? b->name : "")
                           : NULL;
        if (!ld) Py_CLEAR(list);
        else PyList_SET_ITEM(list, (Py_ssize_t)i, ld);
    }
    if (!list || PyDict_SetItemString(d, "contours", list) < 0) Py_CLEAR(d);
    Py_XDECREF(list);
    return d;
}

/* Runs on the calling thread, in layer order (hv_contours_write's contract): the GIL is taken for
 * the layer's dict. */
static hv_status contour_layer(void *user, size_t index, const hv_layer *layer, const hv_slice *slice)
{
    (void)index;
    contour_run *r = user;
    hvpy_call_enter_python(r->call);
    PyObject *d = layer_dict(r, layer, slice);
    int ok = d && PyList_Append(r->list, d) == 0;
    Py_XDECREF(d);
    if (!ok && !r->call->exc_type) PyErr_Fetch(&r->call->exc_type, &r->call->exc_value, &r->call->exc_tb);
    hvpy_call_leave_python(r->call);
    return ok ? HV_OK : hv_error_set(HV_ERR_NOMEM, "out of memory for the layers' dicts");
}

/* contours(mesh, *, loops=True, progress=None, **options of `hovox contours`) -> [{z, bottom, top, area,
 * loops, holes, open, contours: [{points (k, 2), closed, orientation, parent, area, body}]}] */
static PyObject *py_contours(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static const char *const extra[] = {"loops", NULL};
    PyObject *mo;
    if (!PyArg_ParseTuple(args, "O:contours", &mo)) return NULL;
    hv_mesh *mesh = HVPY_MESH(mo);
    if (!mesh) return NULL;
    out_call oc;
    PyObject *res = NULL;
    if (out_begin(&oc, kw) < 0) goto done;
    hv_contours_options o;
    if (hvpy_read_options(oc.rest, hv_contours_option_set(), &o, extra, &oc.a) < 0) goto done;
    PyObject *lo = hvpy_kw(oc.rest, "loops");
    contour_run run = {NULL, PyList_New(0), !lo || PyObject_IsTrue(lo), mesh};
    if (!run.list) goto done;
    hvpy_call c;
    run.call = &c;
    hvpy_begin(&c, oc.progress, &mo, 1);
    hv_status s = hv_contours_write(mesh, &o, NULL, contour_layer, &run, &c.prog, NULL);
    hvpy_end(&c);
    if (s != HV_OK) {
        Py_DECREF(run.list);
        hvpy_call_fail(&c, s);
        goto done;
    }
    res = hvpy_call_done(&c, run.list);
done:
    out_end(&oc);
    return res;
}

/* model.layer(mesh, index, **options of `hovox layers`) -> the printer layer `index` as an array:
 * written as a one-layer stack (the bytes of the full stack's layer) and read back, by the
 * package's Python side (hovox._support.layer_image) */
static PyObject *model_layer(PyObject *self, PyObject *args, PyObject *kw)
{
    PyObject *mod = PyImport_ImportModule("hovox._support");
    PyObject *fn = mod ? PyObject_GetAttrString(mod, "layer_image") : NULL;
    Py_XDECREF(mod);
    if (!fn) return NULL;
    PyObject *head = PyTuple_Pack(1, self), *full = head ? PySequence_Concat(head, args) : NULL;
    Py_XDECREF(head);
    PyObject *r = full ? PyObject_Call(fn, full, kw) : NULL;
    Py_XDECREF(full);
    Py_DECREF(fn);
    return r;
}

static PyMethodDef model_output_methods[] = {
    {"layer", (PyCFunction)(void (*)(void))model_layer, METH_VARARGS | METH_KEYWORDS,
     "layer(mesh, index, **options of `hovox layers`) -> printer layer `index` as an array, the bytes the stack's "
     "PNG holds: (H, W) uint8 palette indices (halftone: 0 background, j + 1 material j), (H, W) 0/1 (mask), or "
     "(m, H, W) uint8 fractions (round(255 p))."},
    {"render", (PyCFunction)(void (*)(void))model_render, METH_VARARGS | METH_KEYWORDS,
     "render(path=None, *, progress=None, **options of `hovox render` (size, surface, flat, view, eye, target, up, "
     "ortho, fov, step, density, clip, clip_box, background, aa, max_memory, ...)) -> (H, W, 4) float32 RGBA with "
     "premultiplied alpha (no copy); writes .png, .exr or .tif when path is given."},
    {"export", (PyCFunction)(void (*)(void))model_export, METH_VARARGS | METH_KEYWORDS,
     "export(path, *, progress=None, **options of `hovox export` (box, coarsen, keep, properties, linearize, grids, "
     "level, bits, max_memory)) -> {points, cells, occupied, arrays, notes, bytes}: .vti, .vtu or a 3MF Volumetric "
     ".3mf."},
    {"layers", (PyCFunction)(void (*)(void))model_layers, METH_VARARGS | METH_KEYWORDS,
     "layers(mesh, dir, *, progress=None, **options of `hovox layers` (profile, dpi, layer_height, mode, method, "
     "halftone, seed, layers=(first, last), threshold, fill_rule, background, compare, gcvf, force, max_memory, ...)) "
     "-> {width, height, layers, first, last, object_pixels, materials: {name: {target, achieved}}, diff_mean, "
     "diff_max (compare), warnings, and colour={skin_voxels, mean_de2000_target, max_de2000_target, "
     "mean_de2000_achieved} when painted}."},
    {"profile", (PyCFunction)(void (*)(void))model_profile, METH_VARARGS | METH_KEYWORDS,
     "profile(*, from_=..., to=..., samples=200, property=None, title=None, size=None, mark=None, y_range=None, "
     "csv=None, plot=None) -> {t, xyz, inside, fractions (n, m), materials, property}: material fractions along a "
     "line; writes the CSV and a PNG or SVG plot when named."},
    {NULL, NULL, 0, NULL},
};

/* The keys of sets a and b and of `more` (NULL-terminated) into keys (n entries), NULL-terminated: what
 * a third set of the same keywords leaves to the others. */
static void keys_but(const hv_option_set *a, const hv_option_set *b, const char *const *more, const char **keys, size_t n)
{
    size_t k = 0;
    for (int i = 0; i < a->count && k + 1 < n; ++i) keys[k++] = a->options[i].key;
    for (int i = 0; i < b->count && k + 1 < n; ++i) keys[k++] = b->options[i].key;
    for (size_t i = 0; more[i] && k + 1 < n; ++i) keys[k++] = more[i];
    keys[k] = NULL;
}

/* labels=[A, B, ...] into the shape (the array in *out, freed by the caller). */
static int labels_kw(PyObject *v, hv_scan_voxelize_options *so, int32_t **out)
{
    PyObject *seq = PySequence_Fast(v, "labels must be a sequence of integers");
    if (!seq) return -1;
    Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
    if (n < 1 || n > 65536) {
        Py_DECREF(seq);
        hvpy_raise(HV_ERR_INVALID, "labels must name 1 to 65536 labels, got %zd", n);
        return -1;
    }
    *out = malloc((size_t)n * sizeof **out);
    if (!*out) {
        Py_DECREF(seq);
        PyErr_NoMemory();
        return -1;
    }
    for (Py_ssize_t i = 0; i < n; ++i) {
        PyObject *x = PySequence_Fast_GET_ITEM(seq, i);
        long long l = PyLong_Check(x) ? PyLong_AsLongLong(x) : INT64_MAX;
        if (l < INT32_MIN || l > INT32_MAX) {
            PyErr_Clear();
            Py_DECREF(seq);
            hvpy_raise(HV_ERR_INVALID, "labels[%zd] must be an integer of 32 bits", i);
            return -1;
        }
        (*out)[i] = (int32_t)l;
    }
    Py_DECREF(seq);
    so->shape.select = HV_SCAN_SELECT_LABELS;
    so->shape.labels = *out;
    so->shape.label_count = (size_t)n;
    return 0;
}

/* hovox.layers_scan(path, dir, *, iso=V | range=(LO, HI) | labels=[A, B, ...], lut=None, icc, intent,
 * resins, keep_largest, fill_holes, min_feature, voxel_size, progress=None, **options of `hovox layers`)
 * -> the report of Model.layers: a scanned volume printed as `hovox layers VOLUME` prints it, the same
 * bytes (hv_layers_write_scan: straight from its data, or through its model with a clean-up) */
static PyObject *py_layers_scan(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static const char *const own[] = {"dir", "labels", "lut", NULL};
    PyObject *path_o = NULL, *pos = NULL;
    if (!PyArg_ParseTuple(args, "O|O:layers_scan", &path_o, &pos)) return NULL;
    out_call oc;
    PyObject *res = NULL;
    int32_t *labels = NULL;
    hv_lut *lut = NULL;
    hv_colour_map *map = NULL;
    hv_scan *scan = NULL;
    hv_material_table *t = NULL;
    if (out_begin(&oc, kw) < 0) goto done;
    const char *keys_l[192], *keys_s[192], *keys_c[192];
    keys_but(hv_scan_voxelize_option_set(), hv_colour_option_set(), own, keys_l, sizeof keys_l / sizeof *keys_l);
    keys_but(hv_layers_option_set(), hv_colour_option_set(), own, keys_s, sizeof keys_s / sizeof *keys_s);
    keys_but(hv_layers_option_set(), hv_scan_voxelize_option_set(), own, keys_c, sizeof keys_c / sizeof *keys_c);
    hv_layers_options o;
    hv_scan_voxelize_options so;
    hv_colour_options co;
    if (hvpy_read_options(oc.rest, hv_layers_option_set(), &o, keys_l, &oc.a) < 0 ||
        hvpy_read_options(oc.rest, hv_scan_voxelize_option_set(), &so, keys_s, &oc.a) < 0 ||
        hvpy_read_options(oc.rest, hv_colour_option_set(), &co, keys_c, &oc.a) < 0)
        goto done;
    const char *path = hvpy_arena_str(&oc.a, path_o, "path");
    if (!path) goto done;
    const char *dir = out_path(&oc, pos, "dir", "the stack's directory");
    if (!dir) goto done;
    PyObject *lv = hvpy_kw(oc.rest, "lut");
    const char *lut_path = lv ? hvpy_arena_str(&oc.a, lv, "lut") : NULL;
    if (lv && !lut_path) goto done;
    int picks = (hvpy_kw(oc.rest, "iso") != NULL) + (hvpy_kw(oc.rest, "range") != NULL) + (hvpy_kw(oc.rest, "labels") != NULL);
    if (picks != 1) {
        hvpy_raise(HV_ERR_INVALID, "a scanned volume needs one of iso, range or labels");
        goto done;
    }
    if (hvpy_kw(oc.rest, "labels") && labels_kw(hvpy_kw(oc.rest, "labels"), &so, &labels) < 0) goto done;
    if (!lut_path && o.mode != HV_LAYERS_MASK) {
        hvpy_raise(HV_ERR_INVALID, "a scanned volume's materials come from lut=TABLE.csv (or print its shape alone with "
                                   "mode=\"mask\")");
        goto done;
    }
    o.model_name = path; /* as the CLI names it: the manifest's shape and model */
    hvpy_call c;
    hv_layers_report rep;
    hv_colour_skin skin;
    hvpy_begin(&c, oc.progress, NULL, 0);
    hv_scan_options sopt = {o.max_memory};
    hv_status s = lut_path ? hv_lut_load(lut_path, &lut) : HV_OK;
    if (s == HV_OK && lut && hv_lut_kind_of(lut) == HV_LUT_COLOUR) s = hv_colour_map_create(&co, &map);
    if (s == HV_OK) s = hv_scan_load(path, &sopt, &scan);
    if (s == HV_OK) s = hv_layers_write_scan(scan, &so, lut, map, dir, &o, &c.prog, &rep, &skin, &t);
    hvpy_end(&c);
    if (s != HV_OK) {
        hvpy_call_fail(&c, s);
        goto done;
    }
    PyObject *d = layers_report(&rep, t, skin.map ? &skin : NULL);
    res = d ? hvpy_call_done(&c, d) : NULL;
done:
    hv_material_table_destroy(t);
    hv_scan_destroy(scan);
    hv_colour_map_destroy(map);
    hv_lut_destroy(lut);
    free(labels);
    out_end(&oc);
    return res;
}

PyMethodDef hvpy_output_functions[] = {
    {"layers_scan", (PyCFunction)(void (*)(void))py_layers_scan, METH_VARARGS | METH_KEYWORDS,
     "layers_scan(path, dir, *, iso=V | range=(LO, HI) | labels=[A, B, ...], lut=None, icc, intent, resins, "
     "keep_largest, fill_holes, min_feature, voxel_size, progress=None, **options of `hovox layers`) -> the report "
     "of Model.layers (and colour={printer_voxels, mean_de2000_target, max_de2000_target, mean_de2000_achieved} for "
     "a colour table): a scanned volume (NIfTI, NRRD, MetaImage, a DICOM directory) printed as `hovox layers "
     "VOLUME` prints it, the same bytes: straight from its data, or through its model with a clean-up."},
    {"contours", (PyCFunction)(void (*)(void))py_contours, METH_VARARGS | METH_KEYWORDS,
     "contours(mesh, *, loops=True, progress=None, **options of `hovox contours` (layer_height, first_layer, "
     "adaptive, close_gap, binary, output, per_layer)) -> [{z, bottom, top, area, loops, holes, open, contours: "
     "[{points (k, 2) array, closed, orientation, parent (-1: none), area, body}]}]."},
    {NULL, NULL, 0, NULL},
};

/* mesh.layers(dir, *, materials={BODY: MATERIAL}, voxel_size=MM, colour_depth=MM, core=RESIN|COLOUR,
 * icc=FILE, intent=NAME, resins="C,M,Y,K,W,CLEAR", progress=None, **options of `hovox layers`) ->
 * the report of model.layers (layers_report; colour when painted): the mesh printed
 * in one step, its bodies in their materials or painted in its colours, as `hovox layers PART.3mf
 * -o DIR` prints it, the same bytes (hv_layers_write_mesh) */
static PyObject *mesh_layers(PyObject *self, PyObject *args, PyObject *kw)
{
    const hv_option_set *ls = hv_layers_option_set(), *ms = hv_layers_mesh_option_set();
    const char *own[40]; /* the step's keys, read by the second read */
    int k = 0;
    own[k++] = "dir";
    for (int i = 0; i < ms->count && k < 39; ++i) own[k++] = ms->options[i].key;
    own[k] = NULL;
    PyObject *pos = NULL;
    if (!PyArg_ParseTuple(args, "|O:layers", &pos)) return NULL;
    if (!HVPY_MESH(self)) return NULL;
    out_call oc;
    PyObject *res = NULL;
    if (out_begin(&oc, kw) < 0) goto done;
    hv_layers_options o;
    if (hvpy_read_options(oc.rest, ls, &o, own, &oc.a) < 0) goto done;
    const char *theirs[160]; /* the layers' keys, read above: known to the second read */
    int n = 0;
    for (int i = 0; i < ls->count && n < 150; ++i) theirs[n++] = ls->options[i].key;
    for (int i = 0; i < ls->alias_count && n < 150; ++i) theirs[n++] = ls->aliases[i].name;
    theirs[n++] = "dir";
    theirs[n] = NULL;
    hv_layers_mesh_options mo;
    if (hvpy_read_options(oc.rest, ms, &mo, theirs, &oc.a) < 0) goto done;
    const char *dir = out_path(&oc, pos, "dir", "the stack's directory");
    if (!dir) goto done;
    hv_mesh *mesh = HVPY_MESH(self); /* after reading the options: they may have run Python code */
    if (!mesh) goto done;
    hvpy_call c;
    hv_layers_report rep;
    hv_colour_skin skin;
    hvpy_begin(&c, oc.progress, &self, 1);
    hv_material_table *t = NULL;
    hv_status s = hv_layers_write_mesh(mesh, &mo, dir, &o, &c.prog, &rep, &skin, &t);
    hvpy_end(&c);
    if (s != HV_OK) { /* skin and t are empty */
        hvpy_call_fail(&c, s);
        goto done;
    }
    PyObject *d = layers_report(&rep, t, skin.map ? &skin : NULL); /* the painted skin's figures, as the manifest's */
    hv_material_table_destroy(t);
    hv_colour_map_destroy(skin.map);
    res = d ? hvpy_call_done(&c, d) : NULL;
done:
    out_end(&oc);
    return res;
}

static PyMethodDef mesh_output_methods[] = {
    {"layers", (PyCFunction)(void (*)(void))mesh_layers, METH_VARARGS | METH_KEYWORDS,
     "layers(dir, *, materials={BODY: MATERIAL}, voxel_size=MM, colour_depth=MM, core=RESIN|COLOUR, icc=FILE, "
     "intent=NAME, resins='C,M,Y,K,W,CLEAR', progress=None, **options of `hovox layers`) -> {width, height, layers, "
     "first, last, object_pixels, materials: {name: {target, achieved}}, warnings, and colour={skin_voxels, "
     "mean_de2000_target, max_de2000_target, mean_de2000_achieved} when painted}: the mesh printed in one step, each body in its material (as `hovox "
     "layers PART.3mf --material BODY=MATERIAL`) or painted in its colours (a coloured mesh, or colour_depth or "
     "core given: as `hovox layers PART.obj --colour-depth MM`); warnings begin with the size warning."},
    {NULL, NULL, 0, NULL}};

int hvpy_init_output(PyObject *m)
{
    (void)m;
    if (hvpy_add_methods(&hvpy_MeshType, mesh_output_methods) < 0) return -1;
    return hvpy_add_methods(&hvpy_ModelType, model_output_methods);
}
