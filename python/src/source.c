/* python/src/source.c - Python: material tables (hovox.materials), reference features (Wu 2.2:
 * hovox.point/axis/line/plane/segment with the keys of hv_frf_option_set, hovox.facets and
 * model.harmonic with hv_facet_select_option_set, model.contour/mask, model.field from a file or
 * from a NumPy array) and grading sources (hovox.ags with hv_ags_option_set, hovox.wu3 with
 * hv_wu3_option_set). A source's f may be an expression, a number, a Python callable or a
 * {"kind": ...} dict; callables are tabulated once (4,097 samples) when the source is made, with
 * the GIL held, never per voxel. */
#include "hvpy.h"

#include <math.h>

/* ---- generic handle classes -------------------------------------------------------------------- */

#define SIMPLE_CLASS(prefix, destroy)                                     \
    static int prefix##_clear(PyObject *self)                             \
    {                                                                     \
        hvpy_handle *h = (hvpy_handle *)self;                             \
        destroy(h->p);                                                    \
        h->p = NULL;                                                      \
        return 0;                                                         \
    }                                                                     \
    static void prefix##_dealloc(PyObject *self)                          \
    {                                                                     \
        if (((hvpy_handle *)self)->weakrefs) PyObject_ClearWeakRefs(self); \
        prefix##_clear(self);                                             \
        Py_TYPE(self)->tp_free(self);                                     \
    }

SIMPLE_CLASS(mats, hv_material_table_destroy)
SIMPLE_CLASS(feature, hv_frf_release)
SIMPLE_CLASS(source, hv_ags_release)

static PyObject *new_handle(PyTypeObject *type, void *p, void (*destroy)(void *))
{
    hvpy_handle *h = PyObject_New(hvpy_handle, type);
    if (!h) {
        destroy(p);
        return NULL;
    }
    h->p = p;
    h->views = h->busy = 0;
    h->weakrefs = NULL;
    return (PyObject *)h;
}

static void destroy_mats(void *p) { hv_material_table_destroy(p); }
static void destroy_frf(void *p) { hv_frf_release(p); }
static void destroy_ags(void *p) { hv_ags_release(p); }
PyObject *hvpy_new_materials(hv_material_table *t) { return new_handle(&hvpy_MaterialsType, t, destroy_mats); }
PyObject *hvpy_new_feature(hv_frf *f) { return new_handle(&hvpy_FeatureType, f, destroy_frf); }
PyObject *hvpy_new_source(hv_ags *a) { return new_handle(&hvpy_SourceType, a, destroy_ags); }

/* ==== materials ============================================================================= */

/* One material: a name, or {"name": ..., "color": "#rrggbb" | (r, g, b[, a]), <property>: value |
 * (value, "unit")} (properties in SI units unless a unit is given). */
static int mats_add_one(hv_material_table *t, PyObject *it, Py_ssize_t index, hvpy_arena *a)
{
    if (PyUnicode_Check(it)) {
        const char *name = hvpy_arena_str(a, it, "material");
        if (!name) return -1;
        hv_status s = hv_material_add(t, name, NULL, NULL);
        return s != HV_OK ? (hvpy_fail(s), -1) : 0;
    }
    if (!PyDict_Check(it)) {
        PyErr_Format(PyExc_TypeError, "material %zd: a material is a name or {'name': ..., 'color': ..., ...}", index + 1);
        return -1;
    }
    PyObject *no = PyDict_GetItemString(it, "name");
    const char *name = no ? hvpy_arena_str(a, no, "name") : NULL;
    if (!name) {
        if (!PyErr_Occurred()) hvpy_raise(HV_ERR_INVALID, "material %zd needs a name", index + 1);
        return -1;
    }
    float rgba[4], *color = NULL;
    PyObject *co = PyDict_GetItemString(it, "color");
    if (co && co != Py_None) {
        if (PyUnicode_Check(co)) {
            if (hv_color_parse(PyUnicode_AsUTF8(co), rgba) != HV_OK) return hvpy_fail(HV_ERR_INVALID), -1;
        } else {
            double c[4] = {0, 0, 0, 1};
            Py_ssize_t n = PySequence_Check(co) ? PySequence_Size(co) : -1;
            if ((n != 3 && n != 4) || hvpy_numbers(co, c, (int)n, "color") < 0) {
                if (!PyErr_Occurred() || PyErr_ExceptionMatches(PyExc_TypeError)) {
                    PyErr_Clear();
                    hvpy_raise(HV_ERR_INVALID, "material '%s': color must be (r, g, b[, a]) or '#rrggbb'", name);
                }
                return -1;
            }
            for (int k = 0; k < 4; ++k) rgba[k] = (float)c[k];
        }
        color = rgba;
    }
    int mi;
    hv_status s = hv_material_add(t, name, color, &mi);
    if (s != HV_OK) return hvpy_fail(s), -1;
    /* the properties in key order, as the Lua binding sets them: the same table gives the same
     * model from either */
    PyObject *keys = PyDict_Keys(it);
    if (!keys) return -1;
    for (Py_ssize_t i = 0; i < PyList_GET_SIZE(keys); ++i)
        if (!PyUnicode_Check(PyList_GET_ITEM(keys, i))) {
            Py_DECREF(keys);
            return hvpy_raise(HV_ERR_INVALID, "material '%s': keys must be strings", name), -1;
        }
    if (PyList_Sort(keys) < 0) {
        Py_DECREF(keys);
        return -1;
    }
    for (Py_ssize_t i = 0; i < PyList_GET_SIZE(keys); ++i) {
        PyObject *k = PyList_GET_ITEM(keys, i), *v = PyDict_GetItem(it, k);
        const char *key = PyUnicode_AsUTF8(k);
        if (!key || !v) {
            Py_DECREF(keys);
            return -1;
        }
        if (strcmp(key, "name") == 0 || strcmp(key, "color") == 0) continue;
        double value;
        const char *unit;
        if ((PyLong_Check(v) || PyFloat_Check(v)) && !PyBool_Check(v)) {
            value = PyFloat_AsDouble(v);
            unit = hv_property_si_unit(key);
        } else if (PyTuple_Check(v) && PyTuple_GET_SIZE(v) == 2 && (PyLong_Check(PyTuple_GET_ITEM(v, 0)) ||
                                                                    PyFloat_Check(PyTuple_GET_ITEM(v, 0))) &&
                   PyUnicode_Check(PyTuple_GET_ITEM(v, 1))) {
            value = PyFloat_AsDouble(PyTuple_GET_ITEM(v, 0));
            if (!(unit = hvpy_arena_str(a, PyTuple_GET_ITEM(v, 1), "unit"))) {
                Py_DECREF(keys);
                return -1;
            }
        } else {
            hvpy_raise(HV_ERR_INVALID, "material '%s': %s must be a number or (value, \"unit\") (a property; the colour is "
                       "'color'), got %s", name, key, Py_TYPE(v)->tp_name);
            Py_DECREF(keys);
            return -1;
        }
        if ((s = hv_material_set_property(t, mi, key, value, unit)) != HV_OK) {
            Py_DECREF(keys);
            return hvpy_fail(s), -1;
        }
    }
    Py_DECREF(keys);
    return 0;
}

/* materials([...]) -> Materials */
static PyObject *py_materials(PyObject *self, PyObject *arg)
{
    (void)self;
    PyObject *seq = PySequence_Fast(arg, "materials takes a list of names or dicts");
    if (!seq) return NULL;
    hv_material_table *t = NULL;
    hvpy_arena a;
    PyObject *res = NULL;
    if (hvpy_arena_init(&a) < 0) goto done;
    if (PySequence_Fast_GET_SIZE(seq) == 0) {
        hvpy_raise(HV_ERR_INVALID, "give at least one material");
        goto done;
    }
    if (hv_material_table_create(&t) != HV_OK) {
        hvpy_fail(HV_ERR_NOMEM);
        goto done;
    }
    for (Py_ssize_t i = 0; i < PySequence_Fast_GET_SIZE(seq); ++i)
        if (mats_add_one(t, PySequence_Fast_GET_ITEM(seq, i), i, &a) < 0) goto done;
    res = hvpy_new_materials(t);
    t = NULL;
done:
    hv_material_table_destroy(t);
    hvpy_arena_free(&a);
    Py_DECREF(seq);
    return res;
}

static PyObject *mats_names(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_material_table *t = HVPY_MATS(self);
    if (!t) return NULL;
    int n = hv_material_count(t);
    PyObject *list = PyList_New(n);
    for (int j = 0; list && j < n; ++j) PyList_SET_ITEM(list, j, PyUnicode_FromString(hv_material_name(t, j)));
    return list;
}

static Py_ssize_t mats_len(PyObject *self)
{
    hv_material_table *t = HVPY_MATS(self);
    return t ? hv_material_count(t) : -1;
}

static PyObject *mats_count(PyObject *self, PyObject *unused)
{
    (void)unused;
    Py_ssize_t n = mats_len(self);
    return n < 0 ? NULL : PyLong_FromSsize_t(n);
}

static int mats_find(hv_material_table *t, const char *name)
{
    int m = hv_material_find(t, name);
    if (m < 0) hvpy_raise(HV_ERR_NOT_FOUND, "no material '%s'", name);
    return m;
}

static PyObject *mats_color(PyObject *self, PyObject *args)
{
    const char *name;
    if (!PyArg_ParseTuple(args, "s:color", &name)) return NULL;
    hv_material_table *t = HVPY_MATS(self);
    int m = t ? mats_find(t, name) : -1;
    if (m < 0) return NULL;
    float c[4];
    hv_material_color(t, m, c);
    return Py_BuildValue("(dddd)", (double)c[0], (double)c[1], (double)c[2], (double)c[3]);
}

static PyObject *mats_property(PyObject *self, PyObject *args)
{
    const char *name, *key;
    if (!PyArg_ParseTuple(args, "ss:property", &name, &key)) return NULL;
    hv_material_table *t = HVPY_MATS(self);
    int m = t ? mats_find(t, name) : -1;
    if (m < 0) return NULL;
    double v;
    const char *unit;
    if (!hv_material_property(t, m, key, &v, &unit)) Py_RETURN_NONE;
    return Py_BuildValue("(ds)", v, unit);
}

static PyObject *mats_repr(PyObject *self)
{
    hv_material_table *t = ((hvpy_handle *)self)->p;
    if (!t) return PyUnicode_FromString("<hovox.Materials (freed)>");
    PyObject *names = mats_names(self, NULL);
    PyObject *r = names ? PyUnicode_FromFormat("<hovox.Materials %R>", names) : NULL;
    Py_XDECREF(names);
    return r;
}

static PyMethodDef mats_methods[] = {
    {"names", mats_names, METH_NOARGS, "names() -> [material names] in order."},
    {"count", mats_count, METH_NOARGS, "count() -> number of materials."},
    {"color", mats_color, METH_VARARGS, "color(name) -> (r, g, b, a) in [0, 1]."},
    {"property", mats_property, METH_VARARGS, "property(name, key) -> (value, unit), or None."},
    HVPY_HANDLE_METHODS,
    {NULL, NULL, 0, NULL},
};
static PyGetSetDef handle_getset[] = {HVPY_HANDLE_GETSET, {NULL, NULL, NULL, NULL, NULL}};
static PySequenceMethods mats_seq = {.sq_length = mats_len};

PyTypeObject hvpy_MaterialsType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "hovox.Materials",
    .tp_basicsize = sizeof(hvpy_handle),
    .tp_dealloc = mats_dealloc,
    .tp_repr = mats_repr,
    .tp_as_sequence = &mats_seq,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A material table: named primitives with colours and physical properties (hovox.materials).",
    .tp_clear = mats_clear,
    .tp_weaklistoffset = offsetof(hvpy_handle, weakrefs),
    .tp_methods = mats_methods,
    .tp_getset = handle_getset,
};

/* ==== features ================================================================================ */

/* (the status first: a call sets *out before this reads it) */
static PyObject *feature_result(hv_status s, hv_frf **f) { return s != HV_OK ? hvpy_fail(s) : hvpy_new_feature(*f); }

static PyObject *make_feature(hv_frf_kind kind, PyObject *args, PyObject *kw)
{
    hv_frf *f = NULL;
    if (kind == HV_FRF_POINT && PyTuple_GET_SIZE(args) > 0) { /* point(x, y, z) or point((x, y, z)) */
        double p[3];
        PyObject *src = PyTuple_GET_SIZE(args) == 3 ? args : PyTuple_GET_ITEM(args, 0);
        if (kw && PyDict_Size(kw)) return PyErr_Format(PyExc_TypeError, "point: give the point or point=..., not both");
        if (hvpy_numbers(src, p, 3, "point") < 0) return NULL;
        return feature_result(hv_frf_point(p, &f), &f);
    }
    if (PyTuple_GET_SIZE(args) > 0)
        return PyErr_Format(PyExc_TypeError, "%s takes keyword arguments only", hv_frf_kind_name(kind));
    hv_frf_options o;
    hvpy_arena a;
    if (hvpy_arena_init(&a) < 0) return NULL;
    int rc = hvpy_read_options(kw, hv_frf_option_set(kind), &o, NULL, &a);
    PyObject *r = rc < 0 ? NULL : feature_result(hv_frf_from_options(&o, NULL, &f), &f);
    hvpy_arena_free(&a);
    return r;
}

static PyObject *py_point(PyObject *s, PyObject *a, PyObject *k) { (void)s; return make_feature(HV_FRF_POINT, a, k); }
static PyObject *py_axis(PyObject *s, PyObject *a, PyObject *k) { (void)s; return make_feature(HV_FRF_LINE, a, k); }
static PyObject *py_plane(PyObject *s, PyObject *a, PyObject *k) { (void)s; return make_feature(HV_FRF_PLANE, a, k); }
static PyObject *py_segment(PyObject *s, PyObject *a, PyObject *k) { (void)s; return make_feature(HV_FRF_SEGMENT, a, k); }
static PyObject *py_halfspace(PyObject *s, PyObject *a, PyObject *k) { (void)s; return make_feature(HV_FRF_HALFSPACE, a, k); }

static int read_select(PyObject *d, hv_facet_select *sel, hvpy_arena *a, const char *what)
{
    if (d && d != Py_None && !PyDict_Check(d)) {
        PyErr_Format(PyExc_TypeError, "%s must be a dict of facet selection options (normal, angle, box_min, box_max)", what);
        return -1;
    }
    return hvpy_read_options(d == Py_None ? NULL : d, hv_facet_select_option_set(), sel, NULL, a);
}

/* facets(mesh, normal=..., angle=10, box_min=..., box_max=...) -> Feature */
static PyObject *py_facets(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    PyObject *mo;
    if (!PyArg_ParseTuple(args, "O:facets", &mo)) return NULL;
    hv_mesh *m = HVPY_MESH(mo);
    if (!m) return NULL;
    hv_facet_select sel;
    hvpy_arena a;
    if (hvpy_arena_init(&a) < 0) return NULL;
    int rc = read_select(kw, &sel, &a, "options");
    hvpy_arena_free(&a);
    if (rc < 0) return NULL;
    hv_frf *f = NULL;
    return feature_result(hv_frf_facets(m, &sel, &f), &f);
}

static PyObject *model_contour(PyObject *self, PyObject *args)
{
    const char *grid = "occupancy";
    if (!PyArg_ParseTuple(args, "|s:contour", &grid)) return NULL;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    hv_frf *f = NULL;
    return feature_result(hv_frf_contour(v, grid, &f), &f);
}

static PyObject *model_mask(PyObject *self, PyObject *args)
{
    const char *grid;
    if (!PyArg_ParseTuple(args, "s:mask", &grid)) return NULL;
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    hv_frf *f = NULL;
    return feature_result(hv_frf_mask(v, grid, &f), &f);
}

/* model.harmonic(mesh, one, zero, domain="occupancy"): one and zero are facet selections (dicts) */
static PyObject *model_harmonic(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"mesh", "one", "zero", "domain", NULL};
    PyObject *mo, *one_d, *zero_d;
    const char *domain = "occupancy";
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OOO|s:harmonic", kwlist, &mo, &one_d, &zero_d, &domain)) return NULL;
    hv_volume *v = HVPY_MODEL(self);
    hv_mesh *m = v ? HVPY_MESH(mo) : NULL;
    if (!m) return NULL;
    hv_facet_select one, zero;
    hvpy_arena a;
    if (hvpy_arena_init(&a) < 0) return NULL;
    int rc = read_select(one_d, &one, &a, "one") < 0 || read_select(zero_d, &zero, &a, "zero") < 0 ? -1 : 0;
    hvpy_arena_free(&a);
    if (rc < 0) return NULL;
    PyObject *pins[2] = {self, mo};
    hvpy_call c;
    hv_frf *f = NULL;
    hvpy_begin(&c, NULL, pins, 2);
    hv_status s = hv_frf_harmonic(v, domain, m, &one, &zero, &f);
    hvpy_end(&c);
    return s != HV_OK ? hvpy_call_fail(&c, s) : hvpy_call_done(&c, hvpy_new_feature(f));
}

static PyObject *field_report(const hv_frf *f)
{
    hv_field_report r;
    hv_frf_field_report(f, &r);
    return Py_BuildValue("{s:d,s:d,s:d,s:d,s:K,s:K}", "lo", r.lo, "hi", r.hi, "file_lo", r.file_lo, "file_hi", r.file_hi,
                         "voxels", (unsigned long long)r.voxels, "filled", (unsigned long long)r.filled);
}

/* model.field(file=..., array=..., outside="refuse") or model.field(values=array, spacing=...,
 * origin=..., name=None, outside=..., grid="occupancy") -> (Feature, report) */
static PyObject *model_field(PyObject *self, PyObject *args, PyObject *kw)
{
    if (PyTuple_GET_SIZE(args) > 0) return PyErr_Format(PyExc_TypeError, "field takes keyword arguments only");
    hv_volume *v = HVPY_MODEL(self);
    if (!v) return NULL;
    hv_frf_options o;
    hvpy_arena a;
    if (hvpy_arena_init(&a) < 0) return NULL;
    PyObject *values = hvpy_kw(kw, "values"), *res = NULL, *arr = NULL;
    hv_frf *f = NULL;
    hv_status s;
    hvpy_call c;
    if (!values) {
        if (hvpy_kw(kw, "spacing") || hvpy_kw(kw, "origin") || hvpy_kw(kw, "name") || hvpy_kw(kw, "grid")) {
            hvpy_raise(HV_ERR_INVALID, "spacing, origin, name and grid go with values=array (a file gives its own)");
            goto done;
        }
        if (hvpy_read_options(kw, hv_frf_option_set(HV_FRF_FIELD), &o, NULL, &a) < 0) goto done;
        hvpy_begin(&c, NULL, &self, 1);
        s = hv_frf_from_options(&o, v, &f);
        hvpy_end(&c);
    } else {
        /* the array's own keywords; outside is read as the file's is (its enum) */
        static const char *const keys[] = {"values", "spacing", "origin", "name", "grid", "outside", NULL};
        PyObject *k, *val;
        Py_ssize_t pos = 0;
        while (PyDict_Next(kw, &pos, &k, &val)) {
            const char *ks = PyUnicode_Check(k) ? PyUnicode_AsUTF8(k) : NULL;
            int known = 0;
            for (int i = 0; ks && keys[i]; ++i) known |= strcmp(ks, keys[i]) == 0;
            if (!known) {
                hvpy_raise(HV_ERR_INVALID, "unknown option '%s' (options of a field from an array: values, spacing, "
                           "origin, name, grid, outside)", ks ? ks : "?");
                goto done;
            }
        }
        o.outside = HV_FIELD_REFUSE;
        PyObject *out_o = hvpy_kw(kw, "outside");
        if (out_o) {
            int rule;
            if (!PyUnicode_Check(out_o)) {
                hvpy_raise(HV_ERR_INVALID, "outside must be 'refuse' or 'nearest'");
                goto done;
            }
            if (hv_enum_parse(hv_field_outside_enum(), PyUnicode_AsUTF8(out_o), &rule) != HV_OK) {
                hvpy_fail(HV_ERR_INVALID);
                goto done;
            }
            o.outside = rule;
        }
        PyObject *x = PyArray_FromAny(values, NULL, 3, 3, NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED, NULL);
        if (!x) goto done;
        int t = PyArray_TYPE((PyArrayObject *)x);
        arr = t == NPY_FLOAT32 || t == NPY_FLOAT64 ? x : PyArray_Cast((PyArrayObject *)x, NPY_FLOAT64);
        if (arr != x) Py_DECREF(x);
        if (!arr) goto done;
        hv_field_grid g;
        g.values = PyArray_DATA((PyArrayObject *)arr);
        g.double_values = PyArray_TYPE((PyArrayObject *)arr) == NPY_FLOAT64;
        for (int ax = 0; ax < 3; ++ax) g.dims[ax] = (int64_t)PyArray_DIM((PyArrayObject *)arr, ax);
        PyObject *sp = hvpy_kw(kw, "spacing"), *org = hvpy_kw(kw, "origin"), *nm = hvpy_kw(kw, "name"),
                 *gr = hvpy_kw(kw, "grid");
        if (!sp) {
            hvpy_raise(HV_ERR_INVALID, "values=array needs spacing (and origin, default (0, 0, 0))");
            goto done;
        }
        if (PyFloat_Check(sp) || PyLong_Check(sp)) {
            g.spacing[0] = g.spacing[1] = g.spacing[2] = PyFloat_AsDouble(sp);
        } else if (hvpy_numbers(sp, g.spacing, 3, "spacing") < 0) {
            goto done;
        }
        g.origin[0] = g.origin[1] = g.origin[2] = 0;
        if (org && hvpy_numbers(org, g.origin, 3, "origin") < 0) goto done;
        const char *name = nm ? hvpy_arena_str(&a, nm, "name") : NULL, *grid = gr ? hvpy_arena_str(&a, gr, "grid") : NULL;
        if ((nm && !name) || (gr && !grid)) goto done;
        hvpy_begin(&c, NULL, &self, 1);
        s = hv_frf_field_grid(v, grid, &g, name, (hv_field_outside)o.outside, &f);
        hvpy_end(&c);
    }
    if (s != HV_OK) {
        hvpy_call_fail(&c, s);
        goto done;
    }
    PyObject *feat = hvpy_new_feature(f), *rep = feat ? field_report(f) : NULL;
    res = rep ? hvpy_call_done(&c, Py_BuildValue("(NN)", feat, rep)) : NULL;
    if (!rep) Py_XDECREF(feat);
done:
    Py_XDECREF(arr);
    hvpy_arena_free(&a);
    return res;
}

/* feature.distance(point, model=None) */
static PyObject *feature_distance(PyObject *self, PyObject *args)
{
    PyObject *po, *mo = Py_None;
    if (!PyArg_ParseTuple(args, "O|O:distance", &po, &mo)) return NULL;
    hv_frf *f = HVPY_FEATURE(self);
    if (!f) return NULL;
    double p[3], d;
    if (hvpy_numbers(po, p, 3, "point") < 0) return NULL;
    hv_volume *lat = NULL;
    if (mo != Py_None && !(lat = HVPY_MODEL(mo))) return NULL;
    hv_frf_kind kind = hv_frf_get_kind(f);
    if (!lat && kind != HV_FRF_HALFSPACE && kind >= HV_FRF_CONTOUR)
        return hvpy_raise(HV_ERR_INVALID, "voxel features need the model whose lattice to use (model=...)");
    hv_status s = hv_frf_distance(f, lat, p, &d);
    return s != HV_OK ? hvpy_fail(s) : PyFloat_FromDouble(d);
}

static PyObject *feature_kind(PyObject *self, void *unused)
{
    (void)unused;
    hv_frf *f = HVPY_FEATURE(self);
    return f ? PyUnicode_FromString(hv_frf_kind_name(hv_frf_get_kind(f))) : NULL;
}

static PyObject *feature_repr(PyObject *self)
{
    hv_frf *f = ((hvpy_handle *)self)->p;
    return f ? PyUnicode_FromFormat("<hovox.Feature %s>", hv_frf_describe(f)) : PyUnicode_FromString("<hovox.Feature (freed)>");
}

static PyMethodDef feature_methods[] = {
    {"distance", feature_distance, METH_VARARGS,
     "distance(point, model=None) -> d at a world point (voxel features need the model whose lattice to use)."},
    HVPY_HANDLE_METHODS,
    {NULL, NULL, 0, NULL},
};
static PyGetSetDef feature_getset[] = {
    {"kind", feature_kind, NULL, "point, axis, plane, halfspace, segment, contour, mask, facets, harmonic or field.",
     NULL},
    HVPY_HANDLE_GETSET,
    {NULL, NULL, NULL, NULL, NULL},
};

PyTypeObject hvpy_FeatureType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "hovox.Feature",
    .tp_basicsize = sizeof(hvpy_handle),
    .tp_dealloc = feature_dealloc,
    .tp_repr = feature_repr,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A fixed reference feature (Wu 2.2): gives each point a distance d.",
    .tp_clear = feature_clear,
    .tp_weaklistoffset = offsetof(hvpy_handle, weakrefs),
    .tp_methods = feature_methods,
    .tp_getset = feature_getset,
};

/* ==== distribution functions ================================================================ */

typedef struct py_fn_ctx {
    PyObject *fn;
    PyObject *exc_type, *exc_value, *exc_tb;
} py_fn_ctx;

/* f as a Python callable: called while the source is made (the GIL is held), 4,097 times */
static double py_f(void *user, double d)
{
    py_fn_ctx *c = user;
    if (c->exc_type) return NAN;
    PyObject *r = PyObject_CallFunction(c->fn, "d", d);
    double v = r ? PyFloat_AsDouble(r) : -1.0;
    Py_XDECREF(r);
    if (!r || (v == -1.0 && PyErr_Occurred())) {
        if (r) {
            PyErr_Clear();
            PyErr_Format(PyExc_TypeError, "f(%g) returned %s, not a number", d, Py_TYPE(r)->tp_name);
        }
        PyErr_Fetch(&c->exc_type, &c->exc_value, &c->exc_tb);
        return NAN;
    }
    return v;
}

/* `points` as 2 to 100000 pairs: an (n, 2) array-like, returned as x[0..n) then y[0..n) (PyMem; the
 * caller frees), `what` naming them in refusals ("f: points must be 2 to 100000 pairs (d, f)"). */
static double *read_pairs(PyObject *points, const char *what, const char *pair, int *n)
{
    PyObject *arr = hvpy_as_array(points, NPY_FLOAT64, what);
    if (!arr) return NULL;
    PyArrayObject *pa = (PyArrayObject *)arr;
    double *xy = NULL;
    if (PyArray_NDIM(pa) != 2 || PyArray_DIM(pa, 1) != 2 || PyArray_DIM(pa, 0) < 2 || PyArray_DIM(pa, 0) > 100000) {
        hvpy_raise(HV_ERR_INVALID, "%s: points must be 2 to 100000 pairs %s", what, pair);
    } else if (!(xy = PyMem_Malloc((size_t)PyArray_DIM(pa, 0) * 2 * sizeof *xy))) {
        PyErr_NoMemory();
    } else {
        *n = (int)PyArray_DIM(pa, 0);
        const double *src = PyArray_DATA(pa);
        for (int i = 0; i < *n; ++i) xy[i] = src[2 * i], xy[*n + i] = src[2 * i + 1];
    }
    Py_DECREF(arr);
    return xy;
}

/* f given as {"kind": ..., params} or {"kind": "table", "points": [(d, f), ...]} */
static hv_status f_dict(PyObject *d, hvpy_arena *a, hv_dfn **out)
{
    static const char *const extra[] = {"points", NULL};
    hv_dfn_options o;
    if (hvpy_read_options(d, hv_dfn_option_set(), &o, extra, a) < 0) return HV_ERR_INVALID;
    PyObject *pts = hvpy_kw(d, "points");
    if ((pts != NULL) != (o.kind == HV_DFN_TABLE)) {
        hvpy_raise(HV_ERR_INVALID, o.kind == HV_DFN_TABLE ? "f of kind table needs points = [(d, f), ...]"
                                                          : "only f of kind table takes points");
        return HV_ERR_INVALID;
    }
    if (!pts) {
        hv_status s = hv_dfn_from_options(&o, out);
        if (s != HV_OK) hvpy_fail(s);
        return s;
    }
    int n;
    double *xy = read_pairs(pts, "f", "(d, f)", &n);
    if (!xy) return HV_ERR_INVALID;
    hv_status s = hv_dfn_table(xy, xy + n, n, out);
    if (s != HV_OK) hvpy_fail(s);
    PyMem_Free(xy);
    return s;
}

/* ==== sources ====================================================================================== */

/* calibration={"property": ..., "unit": ..., "points": [(t, value), ...]} (a file name is read by the
 * option set) */
static hv_calibration *calibration_dict(PyObject *d, hvpy_arena *a)
{
    PyObject *k, *v;
    Py_ssize_t pos = 0;
    while (PyDict_Next(d, &pos, &k, &v)) {
        const char *ks = PyUnicode_Check(k) ? PyUnicode_AsUTF8(k) : NULL;
        if (!ks || (strcmp(ks, "property") && strcmp(ks, "unit") && strcmp(ks, "points"))) {
            hvpy_raise(HV_ERR_INVALID, "calibration: unknown key '%s' (keys: property, unit, points)", ks ? ks : "?");
            return NULL;
        }
    }
    PyObject *po = PyDict_GetItemString(d, "property"), *uo = PyDict_GetItemString(d, "unit"),
             *pts = PyDict_GetItemString(d, "points");
    const char *prop = po ? hvpy_arena_str(a, po, "calibration: property") : NULL;
    const char *unit = uo && uo != Py_None ? hvpy_arena_str(a, uo, "calibration: unit") : NULL;
    if (!prop || (uo && uo != Py_None && !unit)) {
        if (!PyErr_Occurred()) hvpy_raise(HV_ERR_INVALID, "calibration table needs property = \"<name>\"");
        return NULL;
    }
    if (!pts) {
        hvpy_raise(HV_ERR_INVALID, "calibration: points must be 2 to 100000 pairs (t, value)");
        return NULL;
    }
    int n;
    double *tv = read_pairs(pts, "calibration", "(t, value)", &n);
    if (!tv) return NULL;
    hv_calibration *c = NULL;
    hv_status s = hv_calibration_create(prop, unit, tv, tv + n, n, &c);
    if (s != HV_OK) hvpy_fail(s);
    PyMem_Free(tv);
    return c;
}

PyObject *hvpy_make_source(PyObject *args, PyObject *kw, int wu3)
{
    static const char *const extra[] = {"feature", "f", NULL};
    static const char *const extra_cal[] = {"feature", "f", "calibration", NULL};
    if (PyTuple_GET_SIZE(args) > 0) return PyErr_Format(PyExc_TypeError, "%s takes keyword arguments only", wu3 ? "wu3" : "ags");
    PyObject *cal = wu3 ? NULL : hvpy_kw(kw, "calibration");
    int cal_dict = cal && PyDict_Check(cal);
    hv_ags_options o;
    hvpy_arena a;
    hv_calibration *table = NULL;
    hv_dfn *f = NULL;
    py_fn_ctx ctx = {NULL, NULL, NULL, NULL};
    PyObject *res = NULL;
    if (hvpy_arena_init(&a) < 0) return NULL;
    if (hvpy_read_options(kw, wu3 ? hv_wu3_option_set() : hv_ags_option_set(), &o, cal_dict ? extra_cal : extra, &a) < 0)
        goto done;
    if (cal_dict) {
        if (!(table = calibration_dict(cal, &a))) goto done;
        o.calibration_table = table;
    }
    PyObject *fo = hvpy_kw(kw, "feature");
    if (!fo || !PyObject_TypeCheck(fo, &hvpy_FeatureType)) {
        hvpy_raise(HV_ERR_INVALID, "feature must be a hovox feature (hovox.axis(...), model.contour(), ...)");
        goto done;
    }
    hv_frf *feat = HVPY_FEATURE(fo);
    if (!feat) goto done;
    PyObject *fv = hvpy_kw(kw, "f");
    hv_status s = HV_OK;
    if (fv) {
        if (PyUnicode_Check(fv)) {
            const char *e = hvpy_arena_str(&a, fv, "f");
            if (!e) goto done;
            s = hv_dfn_expr(e, &f);
        } else if ((PyLong_Check(fv) || PyFloat_Check(fv)) && !PyBool_Check(fv)) {
            s = hv_dfn_linear(0, PyFloat_AsDouble(fv), &f);
        } else if (PyDict_Check(fv)) {
            if (f_dict(fv, &a, &f) != HV_OK) goto done;
        } else if (PyCallable_Check(fv)) {
            ctx.fn = fv;
            s = hv_dfn_function(py_f, &ctx, "python function", &f);
        } else {
            hvpy_raise(HV_ERR_INVALID, "f must be an expression, a number, a callable or {'kind': ...}, got %s",
                       Py_TYPE(fv)->tp_name);
            goto done;
        }
        if (s != HV_OK) {
            hvpy_fail(s);
            goto done;
        }
    }
    hv_ags *src = NULL;
    s = wu3 ? hv_ags_wu3_from_options(feat, &o, f, &src) : hv_ags_from_options(feat, &o, f, &src);
    if (ctx.exc_type) { /* the callable's own exception */
        hv_ags_release(src);
        PyErr_Restore(ctx.exc_type, ctx.exc_value, ctx.exc_tb); /* steals all three */
        ctx.exc_type = ctx.exc_value = ctx.exc_tb = NULL;
        goto done;
    }
    res = s != HV_OK ? hvpy_fail(s) : hvpy_new_source(src);
done:
    Py_XDECREF(ctx.exc_type);
    Py_XDECREF(ctx.exc_value);
    Py_XDECREF(ctx.exc_tb);
    hv_dfn_destroy(f);
    hv_calibration_release(table);
    hvpy_arena_free(&a);
    return res;
}

static PyObject *py_ags(PyObject *s, PyObject *a, PyObject *k) { (void)s; return hvpy_make_source(a, k, 0); }
static PyObject *py_wu3(PyObject *s, PyObject *a, PyObject *k) { (void)s; return hvpy_make_source(a, k, 1); }

/* source.eval(d) -> m fractions (a list), or an (n, m) float64 array for an array of d */
static PyObject *source_eval(PyObject *self, PyObject *arg)
{
    hv_ags *a = HVPY_SOURCE(self);
    if (!a) return NULL;
    int m = hv_ags_materials(a);
    double p[HV_MAX_MATERIALS];
    if (PyFloat_Check(arg) || PyLong_Check(arg)) {
        hv_ags_eval(a, PyFloat_AsDouble(arg), p);
        PyObject *list = PyList_New(m);
        for (int j = 0; list && j < m; ++j) PyList_SET_ITEM(list, j, PyFloat_FromDouble(p[j]));
        return list;
    }
    PyObject *arr = hvpy_as_array(arg, NPY_FLOAT64, "d");
    if (!arr) return NULL;
    size_t n = (size_t)PyArray_SIZE((PyArrayObject *)arr);
    double *out = malloc(n * (size_t)m * sizeof *out + 1);
    if (!out) {
        Py_DECREF(arr);
        return PyErr_NoMemory();
    }
    const double *d = PyArray_DATA((PyArrayObject *)arr);
    for (size_t i = 0; i < n; ++i) hv_ags_eval(a, d[i], out + i * (size_t)m);
    Py_DECREF(arr);
    Py_ssize_t dims[2] = {(Py_ssize_t)n, m};
    return hvpy_array_own(out, 2, dims, NPY_FLOAT64);
}

static PyObject *source_ranges(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_ags *a = HVPY_SOURCE(self);
    if (!a) return NULL;
    double r[3];
    hv_ags_ranges(a, &r[0], &r[1], &r[2]);
    return Py_BuildValue("(ddd)", r[0], r[1], r[2]);
}

static PyObject *source_moved(PyObject *self, PyObject *arg)
{
    hv_ags *a = HVPY_SOURCE(self);
    if (!a) return NULL;
    double d = PyFloat_AsDouble(arg);
    if (d == -1.0 && PyErr_Occurred()) return NULL;
    hv_ags *b;
    hv_status s = hv_ags_moved(a, d, &b);
    return s != HV_OK ? hvpy_fail(s) : hvpy_new_source(b);
}

static PyObject *source_name(PyObject *self, void *unused)
{
    (void)unused;
    hv_ags *a = HVPY_SOURCE(self);
    if (!a) return NULL;
    const char *n = hv_ags_name(a);
    if (!n) Py_RETURN_NONE;
    return PyUnicode_FromString(n);
}

static PyObject *source_feature(PyObject *self, void *unused)
{
    (void)unused;
    hv_ags *a = HVPY_SOURCE(self);
    return a ? hvpy_new_feature(hv_frf_retain((hv_frf *)hv_ags_frf(a))) : NULL;
}

static PyMethodDef source_methods[] = {
    {"eval", source_eval, METH_O, "eval(d) -> the composition at distance d (a list), or (n, m) for an array of d."},
    {"ranges", source_ranges, METH_NOARGS, "ranges() -> (d_neg, d_grad, d_pos)."},
    {"moved", source_moved, METH_O, "moved(d_neg) -> a copy with d- replaced (Wu's move operator)."},
    HVPY_HANDLE_METHODS,
    {NULL, NULL, 0, NULL},
};
static PyGetSetDef source_getset[] = {
    {"name", source_name, NULL, "The source's name, or None.", NULL},
    {"feature", source_feature, NULL, "The source's reference feature.", NULL},
    HVPY_HANDLE_GETSET,
    {NULL, NULL, NULL, NULL, NULL},
};

PyTypeObject hvpy_SourceType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "hovox.Source",
    .tp_basicsize = sizeof(hvpy_handle),
    .tp_dealloc = source_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "An active grading source (Wu 2.2): a feature, ranges d-, dg, d+, f, Ms and Me (hovox.ags, hovox.wu3).",
    .tp_clear = source_clear,
    .tp_weaklistoffset = offsetof(hvpy_handle, weakrefs),
    .tp_methods = source_methods,
    .tp_getset = source_getset,
};

PyMethodDef hvpy_source_functions[] = {
    {"materials", py_materials, METH_O,
     "materials([name or {'name', 'color', <property>: value or (value, 'unit')}, ...]) -> Materials (density "
     "kg/m^3, youngs_modulus Pa, poisson_ratio get their SI units)."},
    {"point", (PyCFunction)(void (*)(void))py_point, METH_VARARGS | METH_KEYWORDS,
     "point(x, y, z) or point(point=(x, y, z)) -> Feature."},
    {"axis", (PyCFunction)(void (*)(void))py_axis, METH_VARARGS | METH_KEYWORDS,
     "axis(origin=(x, y, z), direction=(x, y, z)) -> Feature (an infinite line; also hovox.line)."},
    {"line", (PyCFunction)(void (*)(void))py_axis, METH_VARARGS | METH_KEYWORDS, "line(origin=..., direction=...): axis."},
    {"plane", (PyCFunction)(void (*)(void))py_plane, METH_VARARGS | METH_KEYWORDS,
     "plane(point=(x, y, z), normal=(x, y, z)) -> Feature."},
    {"halfspace", (PyCFunction)(void (*)(void))py_halfspace, METH_VARARGS | METH_KEYWORDS,
     "halfspace(point=(x, y, z), normal=(x, y, z)) -> Feature: the signed distance to the plane (negative behind "
     "it), so a source on it may take d_neg < 0."},
    {"segment", (PyCFunction)(void (*)(void))py_segment, METH_VARARGS | METH_KEYWORDS,
     "segment(from_=(x, y, z), to=(x, y, z)) -> Feature."},
    {"facets", (PyCFunction)(void (*)(void))py_facets, METH_VARARGS | METH_KEYWORDS,
     "facets(mesh, normal=..., angle=10, box_min=..., box_max=...) -> Feature: distance to a group of facets."},
    {"ags", (PyCFunction)(void (*)(void))py_ags, METH_VARARGS | METH_KEYWORDS,
     "ags(feature=..., d_neg=..., d_grad=..., d_pos=... or ranges=(...), f=..., ms=..., me=..., name=None, "
     "calibration=None, property_grading=None, ps=None, pe=None, log=False) -> Source (the source options of "
     "`hovox grade`); f: an expression in d (and dg), a number, a callable (tabulated once) or {'kind': ...}."},
    {"wu3", (PyCFunction)(void (*)(void))py_wu3, METH_VARARGS | METH_KEYWORDS,
     "wu3(feature=..., d_neg=..., d_grad=..., d_pos=..., f=..., c=...) -> Source of Wu's 3-material paradigm "
     "(eq. 13)."},
    {NULL, NULL, 0, NULL},
};

static PyMethodDef model_source_methods[] = {
    {"contour", model_contour, METH_VARARGS, "contour(grid='occupancy') -> Feature: depth below the model's boundary."},
    {"mask", model_mask, METH_VARARGS, "mask(grid) -> Feature: distance to the true voxels of a bool grid."},
    {"field", (PyCFunction)(void (*)(void))model_field, METH_VARARGS | METH_KEYWORDS,
     "field(file=..., array=..., outside='refuse') or field(values=array, spacing=..., origin=(0, 0, 0), name=None, "
     "outside='refuse', grid='occupancy') -> (Feature, {lo, hi, file_lo, file_hi, voxels, filled}): a scalar field "
     "(its value is d) from a .vti/.vtu/.vdb file or from an (nx, ny, nz) array of point samples at origin + (i, j, "
     "k) * spacing, sampled as a .vti's point data."},
    {"harmonic", (PyCFunction)(void (*)(void))model_harmonic, METH_VARARGS | METH_KEYWORDS,
     "harmonic(mesh, one, zero, domain='occupancy') -> Feature: the harmonic field between two facet selections "
     "(dicts of normal, angle, box_min, box_max)."},
    {NULL, NULL, 0, NULL},
};

int hvpy_init_source(PyObject *m)
{
    if (PyType_Ready(&hvpy_MaterialsType) < 0 || PyType_Ready(&hvpy_FeatureType) < 0 ||
        PyType_Ready(&hvpy_SourceType) < 0 || hvpy_add_methods(&hvpy_ModelType, model_source_methods) < 0)
        return -1;
    if (PyModule_AddObjectRef(m, "Materials", (PyObject *)&hvpy_MaterialsType) < 0 ||
        PyModule_AddObjectRef(m, "Feature", (PyObject *)&hvpy_FeatureType) < 0 ||
        PyModule_AddObjectRef(m, "Source", (PyObject *)&hvpy_SourceType) < 0)
        return -1;
    return 0;
}
