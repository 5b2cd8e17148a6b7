/* python/src/model.c - Python: the Model class (a volume with its grids, metadata and material
 * table): hovox.voxelize (the options of `hovox voxelize`), hovox.load, saving, inspection,
 * probing at points given as arrays, fields computed by the caller (add_grid), and the model as
 * NumPy arrays: dense over a box (fractions, occupancy, any grid; hv_volume_dense) and sparse
 * (the leaf table, viewed without a copy where a grid's buffers are contiguous). Outputs are in
 * output.c, features made from a model in source.c. */
#include "hvpy.h"

#include <math.h>
#include <stdlib.h>

#include "hovox/colour.h"
#include "hovox/model.h"
#include "hovox/voxelize.h"

static int model_clear(PyObject *self)
{
    hvpy_model *h = (hvpy_model *)self;
    hv_volume_destroy(h->p);
    hv_material_table_destroy(h->mats);
    h->p = NULL;
    h->mats = NULL;
    return 0;
}

static void model_dealloc(PyObject *self)
{
    if (((hvpy_handle *)self)->weakrefs) PyObject_ClearWeakRefs(self);
    model_clear(self);
    Py_TYPE(self)->tp_free(self);
}

PyObject *hvpy_new_model(hv_volume *v)
{
    hvpy_model *h = PyObject_New(hvpy_model, &hvpy_ModelType);
    if (!h) {
        hv_volume_destroy(v);
        return NULL;
    }
    h->p = v;
    h->views = h->busy = 0;
    h->weakrefs = NULL;
    h->mats = NULL;
    return (PyObject *)h;
}

hv_material_table *hvpy_model_mats(hvpy_model *m)
{
    if (!m->mats) {
        hv_status s = hv_material_table_load(m->p, &m->mats);
        if (s != HV_OK) {
            hvpy_fail(s);
            return NULL;
        }
    }
    return m->mats;
}

static PyObject *model_repr(PyObject *self)
{
    hv_volume *v = ((hvpy_handle *)self)->p;
    if (!v) return PyUnicode_FromString("<hovox.Model (freed)>");
    return PyUnicode_FromFormat("<hovox.Model %d grids, %llu active voxels>", hv_volume_grid_count(v),
                                (unsigned long long)hv_volume_active_count(v));
}

/* voxelize(mesh, *, like=None, progress=None, **options of `hovox voxelize`) -> Model */
static PyObject *py_voxelize(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static const char *const extra[] = {"like", NULL};
    PyObject *mo;
    if (!PyArg_ParseTuple(args, "O:voxelize", &mo)) return NULL;
    hv_mesh *mesh = HVPY_MESH(mo);
    if (!mesh) return NULL;
    PyObject *progress, *rest;
    if (hvpy_split_progress(kw, &progress, &rest) < 0) return NULL;
    hv_voxelize_options o;
    hvpy_arena a;
    PyObject *res = NULL, *like = NULL;
    if (hvpy_arena_init(&a) < 0) goto done;
    if (hvpy_read_options(rest, hv_voxelize_option_set(), &o, extra, &a) < 0) goto done;
    hv_transform lattice;
    if ((like = hvpy_kw(rest, "like"))) {
        hv_volume *lv = HVPY_MODEL(like);
        if (!lv) goto done;
        lattice = hv_volume_get_transform(lv);
        o.lattice = &lattice;
        if (hv_voxelize_options_check(&o) != HV_OK) {
            hvpy_fail(HV_ERR_INVALID);
            goto done;
        }
    }
    hvpy_call c;
    hv_volume *v = NULL;
    hvpy_begin(&c, progress, &mo, 1);
    o.progress = &c.prog;
    hv_status s = hv_voxelize(mesh, &o, &v);
    hvpy_end(&c);
    res = s != HV_OK ? hvpy_call_fail(&c, s) : hvpy_call_done(&c, hvpy_new_model(v));
done:
    hvpy_arena_free(&a);
    Py_XDECREF(progress);
    Py_DECREF(rest);
    return res;
}

/* load(path) -> Model (.vdb, or a 3MF Volumetric package) */
/* load(path, *, icc=None, intent=None, resins=None) -> Model: a 3MF package's colour without a
 * composite through that colour map (hv_model_load_colour) */
static PyObject *py_load(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    PyObject *arg;
    if (!PyArg_ParseTuple(args, "O:load", &arg)) return NULL;
    hv_colour_options co;
    hvpy_arena a;
    if (hvpy_arena_init(&a) < 0) return NULL;
    if (hvpy_read_options(kw, hv_colour_option_set(), &co, NULL, &a) < 0) {
        hvpy_arena_free(&a);
        return NULL;
    }
    PyObject *path = hvpy_path(arg, "path");
    if (!path) {
        hvpy_arena_free(&a);
        return NULL;
    }
    hvpy_call c;
    hv_volume *v = NULL;
    hvpy_begin(&c, NULL, NULL, 0);
    hv_status s = hv_model_load_colour(PyBytes_AS_STRING(path), &co, &v);
    if (s != HV_OK && hv_model_file_is_mesh(PyBytes_AS_STRING(path)))
        hv_error_suffix(s, "; hovox.load_mesh reads it");
    hvpy_end(&c);
    Py_DECREF(path);
    hvpy_arena_free(&a);
    return s != HV_OK ? hvpy_call_fail(&c, s) : hvpy_call_done(&c, hvpy_new_model(v));
}

static PyObject *model_save(PyObject *self, PyObject *arg)
{
    hv_volume *v = HVPY_MODEL(self);
    PyObject *path = v ? hvpy_path(arg, "path") : NULL;
    if (!path) return NULL;
    hvpy_call c;
    hvpy_begin(&c, NULL, &self, 1);
    hv_status s = hv_volume_save(v, PyBytes_AS_STRING(path));
    hvpy_end(&c);
    Py_DECREF(path);
    return s != HV_OK ? hvpy_call_fail(&c, s) : hvpy_call_done(&c, Py_NewRef(Py_None));
}

static PyObject *model_grids(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    int n = hv_volume_grid_count(v);
    PyObject *list = PyList_New(n);
    for (int g = 0; list && g < n; ++g) {
        PyObject *d = Py_BuildValue("{s:s,s:s}", "name", hv_volume_grid_name(v, g), "type",
                                    hv_grid_type_name(hv_volume_grid_type(v, g)));
        if (!d) Py_CLEAR(list);
        else PyList_SET_ITEM(list, g, d);
    }
    return list;
}

static PyObject *model_voxels(PyObject *self, PyObject *args)
{
    const char *grid = NULL;
    if (!PyArg_ParseTuple(args, "|z:voxels", &grid)) return NULL;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    if (!grid) return PyLong_FromUnsignedLongLong(hv_volume_active_count(v));
    int g = hv_volume_grid_find(v, grid);
    if (g < 0 || hv_volume_grid_type(v, g) != HV_GRID_BOOL) return hvpy_raise(HV_ERR_NOT_FOUND, "no bool grid '%s'", grid);
    return PyLong_FromUnsignedLongLong(hv_volume_mask_count(v, g));
}

static PyObject *model_transform(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    hv_transform xf = hv_volume_get_transform(v);
    PyObject *d = Py_BuildValue("{s:(ddd),s:(ddd)}", "voxel", xf.voxel[0], xf.voxel[1], xf.voxel[2], "origin",
                                xf.origin[0], xf.origin[1], xf.origin[2]);
    int32_t lo[3], hi[3];
    if (d && hv_volume_index_bbox(v, lo, hi)) {
        PyObject *a = Py_BuildValue("(iii)", lo[0], lo[1], lo[2]), *b = Py_BuildValue("(iii)", hi[0], hi[1], hi[2]);
        if (!a || !b || PyDict_SetItemString(d, "index_min", a) < 0 || PyDict_SetItemString(d, "index_max", b) < 0)
            Py_CLEAR(d);
        Py_XDECREF(a);
        Py_XDECREF(b);
    }
    return d;
}

static PyObject *meta_value(hv_volume *v, const char *key)
{
    double d;
    const char *s = hv_volume_meta_string(v, key);
    if (s) return PyUnicode_FromString(s);
    if (hv_volume_meta_number(v, key, &d)) return PyFloat_FromDouble(d);
    Py_RETURN_NONE;
}

static PyObject *model_meta(PyObject *self, PyObject *args)
{
    const char *key = NULL;
    if (!PyArg_ParseTuple(args, "|s:meta", &key)) return NULL;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    if (key) return meta_value(v, key);
    PyObject *d = PyDict_New(); /* every key */
    for (int i = 0; d && i < hv_volume_meta_count(v); ++i) {
        PyObject *x = meta_value(v, hv_volume_meta_key(v, i));
        if (!x || PyDict_SetItemString(d, hv_volume_meta_key(v, i), x) < 0) Py_CLEAR(d);
        Py_XDECREF(x);
    }
    return d;
}

/* materials() -> Materials (a copy of the model's table), or None for a model not graded */
static PyObject *model_materials(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    hv_material_table *t;
    hv_status s = hv_material_table_load(v, &t);
    if (s == HV_ERR_NOT_FOUND) Py_RETURN_NONE;
    return s != HV_OK ? hvpy_fail(s) : hvpy_new_materials(t);
}

/* probe(points) -> (inside, fractions): for one point (x, y, z): a bool and {name: fraction};
 * for an (n, 3) array: an (n,) bool array and an (n, m) float64 array (hv_model_probe, as `hovox
 * probe`). */
static PyObject *model_probe(PyObject *self, PyObject *arg)
{
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    hv_material_table *t = hvpy_model_mats((hvpy_model *)self);
    if (!t) return NULL;
    PyObject *a = hvpy_as_array(arg, NPY_FLOAT64, "points");
    if (!a) return NULL;
    PyArrayObject *pa = (PyArrayObject *)a;
    int single = PyArray_NDIM(pa) == 1;
    if (!((single && PyArray_DIM(pa, 0) == 3) || (PyArray_NDIM(pa) == 2 && PyArray_DIM(pa, 1) == 3))) {
        Py_DECREF(a);
        return PyErr_Format(PyExc_ValueError, "points must be (x, y, z) or an (n, 3) array");
    }
    size_t n = single ? 1 : (size_t)PyArray_DIM(pa, 0);
    const double *xyz = PyArray_DATA(pa);
    for (size_t i = 0; i < 3 * n; ++i)
        if (!isfinite(xyz[i])) {
            Py_DECREF(a);
            return hvpy_raise(HV_ERR_INVALID, "point %zu: coordinate %zu is %g (not finite)", i / 3, i % 3, xyz[i]);
        }
    int m = hv_material_count(t), grids[HV_MAX_MATERIALS];
    for (int j = 0; j < m; ++j) grids[j] = hv_material_grid(v, t, j);
    Py_ssize_t fd[2] = {(Py_ssize_t)n, m}, id[1] = {(Py_ssize_t)n};
    double *f = malloc(n * (size_t)m * sizeof *f + 1);
    uint8_t *in = malloc(n + 1);
    if (!f || !in) {
        free(f), free(in);
        Py_DECREF(a);
        return PyErr_NoMemory();
    }
    hvpy_call c;
    hvpy_begin(&c, NULL, &self, 1);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    for (size_t i = 0; i < n; ++i) {
        int inside;
        hv_model_probe(&acc, t, grids, xyz + 3 * i, &inside, f + i * (size_t)m);
        in[i] = (uint8_t)(inside != 0);
    }
    hvpy_end(&c);
    Py_DECREF(a);
    if (single) {
        PyObject *d = PyDict_New();
        for (int j = 0; d && j < m; ++j) {
            PyObject *x = PyFloat_FromDouble(f[j]);
            if (!x || PyDict_SetItemString(d, hv_material_name(t, j), x) < 0) Py_CLEAR(d);
            Py_XDECREF(x);
        }
        PyObject *r = d ? Py_BuildValue("(ON)", in[0] ? Py_True : Py_False, d) : NULL;
        free(f), free(in);
        return r;
    }
    PyObject *ia = hvpy_array_own(in, 1, id, NPY_BOOL), *fa = ia ? hvpy_array_own(f, 2, fd, NPY_FLOAT64) : NULL;
    if (!ia) free(f);
    if (!fa) {
        Py_XDECREF(ia);
        return NULL;
    }
    return Py_BuildValue("(NN)", ia, fa);
}

/* centres(mask="occupancy") -> (n, 3) float64: the voxel centres, in the order add_grid reads */
static PyObject *model_centres(PyObject *self, PyObject *args)
{
    const char *mask = "occupancy";
    if (!PyArg_ParseTuple(args, "|s:centres", &mask)) return NULL;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    double *xyz = NULL;
    size_t n = 0;
    hv_status s = hv_volume_centres(v, mask, &xyz, &n);
    if (s != HV_OK) return hvpy_fail(s);
    Py_ssize_t d[2] = {(Py_ssize_t)n, 3};
    return hvpy_array_own(xyz, 2, d, NPY_FLOAT64);
}

/* add_grid(name, values, mask="occupancy") -> voxels: float grid `name` holding values[i] at the
 * i-th centre of centres(mask); values is an array of that length or a callable taking the (n, 3)
 * centres and returning it. Nothing is added on error. */
static PyObject *model_add_grid(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"name", "values", "mask", NULL};
    const char *name, *mask = "occupancy";
    PyObject *vals;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "sO|s:add_grid", kwlist, &name, &vals, &mask)) return NULL;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    PyObject *given = Py_NewRef(vals);
    if (PyCallable_Check(vals)) {
        Py_DECREF(given);
        double *xyz = NULL;
        size_t n = 0;
        hv_status s = hv_volume_centres(v, mask, &xyz, &n);
        if (s != HV_OK) return hvpy_fail(s);
        Py_ssize_t d[2] = {(Py_ssize_t)n, 3};
        PyObject *pts = hvpy_array_own(xyz, 2, d, NPY_FLOAT64);
        if (!pts) return NULL;
        given = PyObject_CallOneArg(vals, pts);
        Py_DECREF(pts);
        if (!given) return NULL;
        if (!(v = HVPY_MODEL(self))) { /* the callable may have freed it */
            Py_DECREF(given);
            return NULL;
        }
    }
    PyObject *a = hvpy_as_array(given, NPY_FLOAT32, "values");
    Py_DECREF(given);
    if (!a) return NULL;
    if (((hvpy_handle *)self)->busy) {
        Py_DECREF(a);
        return PyErr_Format(PyExc_BufferError, "add_grid: a call running in another thread uses the model");
    }
    hv_status s = hv_volume_grid_set(v, name, mask, PyArray_DATA((PyArrayObject *)a), (size_t)PyArray_SIZE((PyArrayObject *)a));
    npy_intp n = PyArray_SIZE((PyArrayObject *)a);
    Py_DECREF(a);
    return s != HV_OK ? hvpy_fail(s) : PyLong_FromSsize_t((Py_ssize_t)n);
}

/* The index box of `box` ((x0, y0, z0), (x1, y1, z1)) in world units: the voxels whose centres
 * lie inside it; None: the active voxels' bounding box. -1 with an exception. */
static int index_box(hv_volume *v, PyObject *box, int32_t lo[3], int32_t hi[3])
{
    if (!box || box == Py_None) {
        if (!hv_volume_index_bbox(v, lo, hi)) {
            hvpy_raise(HV_ERR_INVALID, "the model has no active voxels (give a box)");
            return -1;
        }
        return 0;
    }
    double b[6];
    PyObject *seq = PySequence_Fast(box, "box must be ((x0, y0, z0), (x1, y1, z1))");
    if (!seq) return -1;
    int bad = PySequence_Fast_GET_SIZE(seq) != 2 || hvpy_numbers(PySequence_Fast_GET_ITEM(seq, 0), b, 3, "box[0]") < 0 ||
              hvpy_numbers(PySequence_Fast_GET_ITEM(seq, 1), b + 3, 3, "box[1]") < 0;
    Py_DECREF(seq);
    if (bad) {
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "box must be ((x0, y0, z0), (x1, y1, z1))");
        return -1;
    }
    double il[3], ih[3];
    hv_volume_world_to_index(v, b, il);
    hv_volume_world_to_index(v, b + 3, ih);
    for (int k = 0; k < 3; ++k) {
        double a = ceil(fmin(il[k], ih[k]) - 1e-9), c = floor(fmax(il[k], ih[k]) + 1e-9);
        if (a < -1e9 || c > 1e9) {
            hvpy_raise(HV_ERR_INVALID, "box: axis %d spans more than 10^9 voxels", k);
            return -1;
        }
        if (c < a) {
            hvpy_raise(HV_ERR_INVALID, "box holds no voxel centre along axis %d", k);
            return -1;
        }
        lo[k] = (int32_t)a;
        hi[k] = (int32_t)c;
    }
    return 0;
}

static PyObject *model_index_box(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"box", NULL};
    PyObject *box = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|O:index_box", kwlist, &box)) return NULL;
    hv_volume *v = HVPY_MODEL(self);
    int32_t lo[3], hi[3];
    if (!v || index_box(v, box, lo, hi) < 0) return NULL;
    return Py_BuildValue("((iii)(iii))", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
}

/* Dense arrays over a box: grids (float, n of them; nd 4) or one mask (bool grid or -1; nd 3). */
static PyObject *dense(PyObject *self, PyObject *box, const int *grids, int n, int mask_grid)
{
    hv_volume *v = HVPY_MODEL(self);
    int32_t lo[3], hi[3];
    if (!v || index_box(v, box, lo, hi) < 0) return NULL;
    npy_intp d[4] = {(npy_intp)hi[0] - lo[0] + 1, (npy_intp)hi[1] - lo[1] + 1, (npy_intp)hi[2] - lo[2] + 1, n};
    PyObject *arr = PyArray_EMPTY(grids ? 4 : 3, d, grids ? NPY_FLOAT32 : NPY_BOOL, 0);
    if (!arr) return NULL;
    hvpy_call c;
    hvpy_begin(&c, NULL, &self, 1);
    hv_status s = grids ? hv_volume_dense(v, grids, n, lo, hi, PyArray_DATA((PyArrayObject *)arr))
                        : hv_volume_dense_mask(v, mask_grid, lo, hi, PyArray_DATA((PyArrayObject *)arr));
    hvpy_end(&c);
    if (s != HV_OK) {
        Py_DECREF(arr);
        return hvpy_call_fail(&c, s);
    }
    return hvpy_call_done(&c, arr);
}

/* fractions(box=None) -> (nx, ny, nz, m) float32 */
static PyObject *model_fractions(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"box", NULL};
    PyObject *box = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|O:fractions", kwlist, &box)) return NULL;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    hv_material_table *t = hvpy_model_mats((hvpy_model *)self);
    if (!t) return NULL;
    int m = hv_material_count(t), grids[HV_MAX_MATERIALS];
    for (int j = 0; j < m; ++j) grids[j] = hv_material_grid(v, t, j);
    return dense(self, box, grids, m, -1);
}

/* occupancy(box=None) -> (nx, ny, nz) bool: the "occupancy" grid (the active voxels without one) */
static PyObject *model_occupancy(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"box", NULL};
    PyObject *box = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|O:occupancy", kwlist, &box)) return NULL;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    int g = hv_volume_grid_find(v, "occupancy");
    if (g >= 0 && hv_volume_grid_type(v, g) != HV_GRID_BOOL) g = -1;
    return dense(self, box, NULL, 0, g);
}

/* grid(name, box=None) -> (nx, ny, nz) float32 or bool */
static PyObject *model_grid(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"name", "box", NULL};
    const char *name;
    PyObject *box = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "s|O:grid", kwlist, &name, &box)) return NULL;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    int g = hv_volume_grid_find(v, name);
    if (g < 0) return hvpy_raise(HV_ERR_NOT_FOUND, "no grid '%s'", name);
    if (hv_volume_grid_type(v, g) == HV_GRID_BOOL) return dense(self, box, NULL, 0, g);
    PyObject *arr = dense(self, box, &g, 1, -1);
    if (!arr) return NULL;
    PyArray_Dims shape = {PyArray_DIMS((PyArrayObject *)arr), 3};
    PyObject *r = PyArray_Newshape((PyArrayObject *)arr, &shape, NPY_CORDER);
    Py_DECREF(arr);
    return r;
}

/* leaves(grid=None) -> (origins (L, 3) int32, masks (L, 8) uint64, values): the sparse store,
 * leaf by leaf in OpenVDB's tree order; values (L, 8, 8, 8) float32 for a float grid, (L, 8)
 * uint64 bit words for a bool grid, None without a grid. Views (read-only, keeping the model
 * alive) where the buffers are contiguous, else copies. */
static PyObject *leaf_array(PyObject *self, hv_volume *v, int g, size_t nl)
{
    int is_float = g >= 0 && hv_volume_grid_type(v, g) == HV_GRID_FLOAT;
    size_t per = is_float ? HV_LEAF_SIZE * sizeof(float) : HV_LEAF_WORDS * sizeof(uint64_t);
    const void *first = nl == 0 ? NULL : g < 0 ? (const void *)hv_volume_leaf_mask(v, 0)
                                  : is_float ? (const void *)hv_volume_leaf_float_c(v, g, 0)
                                             : (const void *)hv_volume_leaf_bool_c(v, g, 0);
    int contiguous = 1;
    for (size_t l = 1; l < nl && contiguous; ++l) {
        const void *p = g < 0 ? (const void *)hv_volume_leaf_mask(v, l)
                      : is_float ? (const void *)hv_volume_leaf_float_c(v, g, l)
                                 : (const void *)hv_volume_leaf_bool_c(v, g, l);
        contiguous = (const char *)p == (const char *)first + l * per;
    }
    Py_ssize_t fd[4] = {(Py_ssize_t)nl, 8, 8, 8}, bd[2] = {(Py_ssize_t)nl, 8};
    if (contiguous && nl)
        return is_float ? hvpy_array_view(self, (void *)first, 4, fd, NPY_FLOAT32, 0)
                        : hvpy_array_view(self, (void *)first, 2, bd, NPY_UINT64, 0);
    char *copy = malloc(nl * per + 1);
    if (!copy) return PyErr_NoMemory();
    for (size_t l = 0; l < nl; ++l) {
        const void *p = g < 0 ? (const void *)hv_volume_leaf_mask(v, l)
                      : is_float ? (const void *)hv_volume_leaf_float_c(v, g, l)
                                 : (const void *)hv_volume_leaf_bool_c(v, g, l);
        memcpy(copy + l * per, p, per);
    }
    PyObject *a = is_float ? hvpy_array_own(copy, 4, fd, NPY_FLOAT32) : hvpy_array_own(copy, 2, bd, NPY_UINT64);
    if (a) PyArray_CLEARFLAGS((PyArrayObject *)a, NPY_ARRAY_WRITEABLE);
    return a;
}

static PyObject *model_leaves(PyObject *self, PyObject *args)
{
    const char *grid = NULL;
    if (!PyArg_ParseTuple(args, "|z:leaves", &grid)) return NULL;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    int g = -1;
    if (grid && (g = hv_volume_grid_find(v, grid)) < 0) return hvpy_raise(HV_ERR_NOT_FOUND, "no grid '%s'", grid);
    size_t nl = hv_volume_leaf_count(v);
    Py_ssize_t od[2] = {(Py_ssize_t)nl, 3};
    npy_intp z3[2] = {0, 3}, z8[2] = {0, 8}, zf[4] = {0, 8, 8, 8};
    PyObject *origins = nl ? hvpy_array_view(self, (void *)hv_volume_leaf_origins(v), 2, od, NPY_INT32, 0)
                           : PyArray_ZEROS(2, z3, NPY_INT32, 0);
    PyObject *masks = origins ? (nl ? leaf_array(self, v, -1, nl) : PyArray_ZEROS(2, z8, NPY_UINT64, 0)) : NULL;
    PyObject *values = NULL;
    if (masks) {
        if (!grid) values = Py_NewRef(Py_None);
        else if (nl) values = leaf_array(self, v, g, nl);
        else if (hv_volume_grid_type(v, g) == HV_GRID_FLOAT) values = PyArray_ZEROS(4, zf, NPY_FLOAT32, 0);
        else values = PyArray_ZEROS(2, z8, NPY_UINT64, 0);
    }
    if (!values) {
        Py_XDECREF(origins);
        Py_XDECREF(masks);
        return NULL;
    }
    return Py_BuildValue("(NNN)", origins, masks, values);
}

/* regions() -> [{name, grid, material, color, fill, voxels, lost, lost_to: {name: voxels}}] */
static PyObject *model_regions(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    hv_regions *rg = NULL;
    hv_status s = hv_voxelize_regions_read(v, &rg);
    if (s == HV_ERR_NOT_FOUND) return PyList_New(0);
    if (s != HV_OK) return hvpy_fail(s);
    size_t n = hv_regions_count(rg);
    PyObject *list = PyList_New((Py_ssize_t)n);
    for (size_t i = 0; list && i < n; ++i) {
        const hv_region_info *g = hv_regions_at(rg, i);
        PyObject *lost = PyDict_New();
        for (size_t k = 0; lost && k < g->nlost_to; ++k) {
            PyObject *x = PyLong_FromUnsignedLongLong(g->lost_to[k].voxels);
            if (!x || PyDict_SetItemString(lost, hv_regions_at(rg, g->lost_to[k].region)->name, x) < 0) Py_CLEAR(lost);
            Py_XDECREF(x);
        }
        PyObject *color = g->has_color ? Py_BuildValue("(dddd)", g->rgba[0], g->rgba[1], g->rgba[2], g->rgba[3])
                                       : Py_NewRef(Py_None);
        PyObject *d = lost && color ? Py_BuildValue("{s:s,s:s,s:z,s:N,s:s,s:K,s:K,s:N}", "name", g->name, "grid", g->grid,
                                                    "material", g->material, "color", color, "fill",
                                                    hv_fill_mode_name(g->fill), "voxels", (unsigned long long)g->voxels,
                                                    "lost", (unsigned long long)g->lost, "lost_to", lost)
                                    : NULL;
        if (!d) {
            Py_CLEAR(list);
            break;
        }
        PyList_SET_ITEM(list, (Py_ssize_t)i, d);
    }
    hv_regions_destroy(rg);
    return list;
}

static PyMethodDef model_methods[] = {
    {"save", model_save, METH_O, "save(path): an OpenVDB .vdb file, written atomically."},
    {"grids", model_grids, METH_NOARGS, "grids() -> [{name, type ('bool' or 'float')}]."},
    {"voxels", model_voxels, METH_VARARGS, "voxels(grid=None) -> active voxels, or the true voxels of a bool grid."},
    {"transform", model_transform, METH_NOARGS,
     "transform() -> {voxel, origin, index_min, index_max}: voxel (i, j, k) has its centre at origin + (i, j, k) * "
     "voxel (mm)."},
    {"meta", model_meta, METH_VARARGS, "meta(key=None) -> a metadata value (str, float or None); every key as a dict."},
    {"materials", model_materials, METH_NOARGS, "materials() -> the model's Materials, or None when not graded."},
    {"probe", model_probe, METH_O,
     "probe(points) -> (inside, fractions): trilinear material fractions as `hovox probe`; for (x, y, z) a bool and "
     "{material: fraction}, for an (n, 3) array an (n,) bool array and an (n, m) float64 array."},
    {"centres", model_centres, METH_VARARGS,
     "centres(mask='occupancy') -> (n, 3) float64: the centres of the voxels of a bool grid (mm), in the order "
     "add_grid reads values."},
    {"add_grid", (PyCFunction)(void (*)(void))model_add_grid, METH_VARARGS | METH_KEYWORDS,
     "add_grid(name, values, mask='occupancy') -> voxels: a float grid holding values[i] at centres(mask)[i] (values: "
     "an array, or a callable taking the (n, 3) centres), 0 on the other active voxels; export it with "
     "export(..., grids=name)."},
    {"index_box", (PyCFunction)(void (*)(void))model_index_box, METH_VARARGS | METH_KEYWORDS,
     "index_box(box=None) -> ((i0, j0, k0), (i1, j1, k1)), inclusive: the voxels the dense arrays cover; box "
     "((x0, y0, z0), (x1, y1, z1)) in mm takes the voxels whose centres lie inside it, None the active voxels' box."},
    {"fractions", (PyCFunction)(void (*)(void))model_fractions, METH_VARARGS | METH_KEYWORDS,
     "fractions(box=None) -> (nx, ny, nz, m) float32: the material fractions over index_box(box), 0 outside the "
     "model; element [i, j, k] is voxel index_box(box)[0] + (i, j, k)."},
    {"occupancy", (PyCFunction)(void (*)(void))model_occupancy, METH_VARARGS | METH_KEYWORDS,
     "occupancy(box=None) -> (nx, ny, nz) bool over index_box(box)."},
    {"grid", (PyCFunction)(void (*)(void))model_grid, METH_VARARGS | METH_KEYWORDS,
     "grid(name, box=None) -> (nx, ny, nz) float32 or bool: any grid, dense over index_box(box)."},
    {"leaves", model_leaves, METH_VARARGS,
     "leaves(grid=None) -> (origins (L, 3) int32, masks (L, 8) uint64, values): the sparse store's 8x8x8 leaves in "
     "tree order; values (L, 8, 8, 8) float32 [x, y, z] for a float grid or (L, 8) uint64 bit words for a bool grid "
     "(voxel offset x*64 + y*8 + z), None without a grid. Read-only views that keep the model alive where the "
     "buffers are contiguous, else copies."},
    {"regions", model_regions, METH_NOARGS,
     "regions() -> [{name, grid, material, color, fill, voxels, lost, lost_to}] of a model voxelized from an "
     "assembly ([] otherwise)."},
    HVPY_HANDLE_METHODS,
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef model_getset[] = {HVPY_HANDLE_GETSET, {NULL, NULL, NULL, NULL, NULL}};

PyTypeObject hvpy_ModelType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "hovox.Model",
    .tp_basicsize = sizeof(hvpy_model),
    .tp_dealloc = model_dealloc,
    .tp_repr = model_repr,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A voxel model: a lattice and named float and bool grids sharing one sparse topology, with metadata "
              "(the material table of a graded model); from hovox.voxelize, hovox.load or Object.evaluate.",
    .tp_clear = model_clear,
    .tp_weaklistoffset = offsetof(hvpy_model, weakrefs),
    .tp_methods = model_methods,
    .tp_getset = model_getset,
};

PyMethodDef hvpy_model_functions[] = {
    {"voxelize", (PyCFunction)(void (*)(void))py_voxelize, METH_VARARGS | METH_KEYWORDS,
     "voxelize(mesh, *, dims=None, voxel_size=None, adjacency=26, fill='auto', max_memory=None, like=None, "
     "progress=None) -> Model (bool grids occupancy and surface): the options of `hovox voxelize`; like=model puts "
     "it on that model's lattice."},
    {"load", (PyCFunction)(void (*)(void))py_load, METH_VARARGS | METH_KEYWORDS,
     "load(path, *, icc=None, intent=None, resins=None) -> Model from a .vdb file or a 3MF Volumetric package; a "
     "package's colour without a composite prints in the six colour resins through icc, intent, resins (default "
     "Ghostscript's default_cmyk.icc, perceptual, the J750's)."},
    {NULL, NULL, 0, NULL},
};

int hvpy_init_model(PyObject *m)
{
    if (PyType_Ready(&hvpy_ModelType) < 0) return -1;
    return PyModule_AddObjectRef(m, "Model", (PyObject *)&hvpy_ModelType);
}
