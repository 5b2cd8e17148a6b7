/* python/src/tray.c - Python: print trays (hovox/tray.h). hovox.tray(**options of `hovox tray`)
 * makes a Tray; tray.add(**part keys: model, mesh, material, name, at, z, rotation, copies),
 * tray.arrange(**options) and tray.layers(dir, **options) (the tray's options again, overriding
 * those given before, key by key). Parts are files, as in job files. The options' strings are kept
 * in the tray's list, alive as long as the tray. */
#include "hvpy.h"

static int tray_clear(PyObject *self)
{
    hvpy_tray *h = (hvpy_tray *)self;
    hv_tray_destroy(h->p);
    h->p = NULL;
    return 0;
}

static void tray_dealloc(PyObject *self)
{
    if (((hvpy_handle *)self)->weakrefs) PyObject_ClearWeakRefs(self);
    tray_clear(self);
    Py_CLEAR(((hvpy_tray *)self)->keep);
    Py_TYPE(self)->tp_free(self);
}

/* Read the tray options of kw on top of t->o: only the keys given change. */
static int read_over(hvpy_tray *t, PyObject *kw, const char *const *extra)
{
    if (!kw) return 0;
    hvpy_arena a = {t->keep};
    hv_tray_options fresh;
    if (hvpy_read_options(kw, hv_tray_option_set(), &fresh, extra, &a) < 0) return -1;
    const hv_option_set *set = hv_tray_option_set();
    for (int i = 0; i < set->count; ++i) {
        const char *key = set->options[i].key;
        if (!hvpy_kw(kw, key)) continue;
        if (set->options[i].kind != HV_OPT_CUSTOM) {
            hv_option_copy(set, key, &t->o, &fresh);
        } else if (strcmp(key, "resin") == 0) {
            for (int k = 0; k < fresh.nresin && t->o.nresin < HV_TRAY_MAX_RESINS; ++k) t->o.resin[t->o.nresin++] = fresh.resin[k];
        } else {
            for (int k = 0; k < fresh.ncolor && t->o.ncolor < HV_TRAY_MAX_RESINS; ++k)
                t->o.resin_color[t->o.ncolor++] = fresh.resin_color[k];
        }
    }
    return 0;
}

static PyObject *report_dict(const hv_tray_report *r)
{
    return Py_BuildValue("{s:i,s:i,s:n,s:n,s:n,s:i,s:i,s:K,s:K,s:K,s:d,s:s}", "width", r->width, "height", r->height, "layers",
                         (Py_ssize_t)r->layers, "first", (Py_ssize_t)r->first, "last", (Py_ssize_t)r->last, "parts",
                         r->parts, "resins", r->resins, "memory", (unsigned long long)r->memory, "object_pixels",
                         (unsigned long long)r->object_pixels, "bytes", (unsigned long long)r->bytes, "utilisation",
                         r->utilisation, "warnings", r->warnings);
}

/* tray(**options) -> Tray */
static PyObject *py_tray(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    if (PyTuple_GET_SIZE(args) > 0) return PyErr_Format(PyExc_TypeError, "tray takes keyword arguments only");
    hvpy_tray *t = PyObject_New(hvpy_tray, &hvpy_TrayType);
    if (!t) return NULL;
    t->p = NULL;
    t->views = t->busy = 0;
    t->weakrefs = NULL;
    hv_tray_options_init(&t->o);
    t->keep = PyList_New(0);
    hv_tray *tr = NULL;
    if (!t->keep || hv_tray_create(&tr) != HV_OK) {
        int nomem = t->keep != NULL;
        Py_DECREF(t);
        return nomem ? hvpy_fail(HV_ERR_NOMEM) : NULL;
    }
    t->p = tr;
    if (read_over(t, kw, NULL) < 0) {
        Py_DECREF(t);
        return NULL;
    }
    return (PyObject *)t;
}

/* tray.add(model=..., mesh=..., at=(x, y), rotation=90, copies=2, ...) -> parts */
static PyObject *tray_add(PyObject *self, PyObject *args, PyObject *kw)
{
    if (PyTuple_GET_SIZE(args) > 0) return PyErr_Format(PyExc_TypeError, "add takes keyword arguments only");
    hvpy_tray *t = (hvpy_tray *)self;
    hv_tray *tr = hvpy_live(self, &hvpy_TrayType, "a hovox.Tray");
    if (!tr) return NULL;
    hvpy_arena a = {t->keep};
    hv_tray_part p;
    if (hvpy_read_options(kw, hv_tray_part_option_set(), &p, NULL, &a) < 0) return NULL;
    hv_status s = hv_tray_add(tr, &p, NULL);
    return s != HV_OK ? hvpy_fail(s) : PyLong_FromLong(hv_tray_part_count(tr));
}

/* tray.arrange(**options): place every part (arrange='all' unless given) and check -> report */
static PyObject *tray_arrange(PyObject *self, PyObject *args, PyObject *kw)
{
    if (PyTuple_GET_SIZE(args) > 0) return PyErr_Format(PyExc_TypeError, "arrange takes keyword arguments only");
    hvpy_tray *t = (hvpy_tray *)self;
    hv_tray *tr = hvpy_live(self, &hvpy_TrayType, "a hovox.Tray");
    if (!tr) return NULL;
    PyObject *progress, *rest;
    if (hvpy_split_progress(kw, &progress, &rest) < 0) return NULL;
    t->o.arrange = 2;
    PyObject *res = NULL;
    if (read_over(t, rest, NULL) == 0) {
        hvpy_call c;
        hv_tray_report r;
        hvpy_begin(&c, progress, &self, 1);
        hv_status s = hv_tray_plan(tr, &t->o, &c.prog, &r);
        hvpy_end(&c);
        res = s != HV_OK ? hvpy_call_fail(&c, s) : hvpy_call_done(&c, report_dict(&r));
    }
    Py_XDECREF(progress);
    Py_DECREF(rest);
    return res;
}

/* tray.layers(dir, **options) -> report */
static PyObject *tray_layers(PyObject *self, PyObject *args, PyObject *kw)
{
    static const char *const extra[] = {"dir", NULL};
    PyObject *pos = NULL;
    if (!PyArg_ParseTuple(args, "|O:layers", &pos)) return NULL;
    hvpy_tray *t = (hvpy_tray *)self;
    hv_tray *tr = hvpy_live(self, &hvpy_TrayType, "a hovox.Tray");
    if (!tr) return NULL;
    PyObject *progress, *rest;
    if (hvpy_split_progress(kw, &progress, &rest) < 0) return NULL;
    PyObject *res = NULL;
    if (read_over(t, rest, extra) == 0) {
        PyObject *dv = pos ? pos : hvpy_kw(rest, "dir");
        hvpy_arena a = {t->keep};
        const char *dir = dv ? hvpy_arena_str(&a, dv, "dir") : NULL;
        if (!dir && !PyErr_Occurred() && !t->o.dry_run) hvpy_raise(HV_ERR_INVALID, "dir is required (the stack's directory)");
        if (!PyErr_Occurred()) {
            hvpy_call c;
            hv_tray_report r;
            hvpy_begin(&c, progress, &self, 1);
            hv_status s = hv_tray_write(tr, dir, &t->o, &c.prog, &r);
            hvpy_end(&c);
            res = s != HV_OK ? hvpy_call_fail(&c, s) : hvpy_call_done(&c, report_dict(&r));
        }
    }
    Py_XDECREF(progress);
    Py_DECREF(rest);
    return res;
}

static PyObject *tray_count(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_tray *tr = hvpy_live(self, &hvpy_TrayType, "a hovox.Tray");
    return tr ? PyLong_FromLong(hv_tray_part_count(tr)) : NULL;
}

#define KW(f) (PyCFunction)(void (*)(void))(f), METH_VARARGS | METH_KEYWORDS
static PyMethodDef tray_methods[] = {
    {"add", KW(tray_add),
     "add(model=None, mesh=..., material=None, name=None, at=None, z=0, rotation=0, copies=1) -> parts: a part, as "
     "in job files (files are read when the tray is planned)."},
    {"arrange", KW(tray_arrange), "arrange(**tray options) -> report: place every part and check the tray."},
    {"layers", KW(tray_layers), "layers(dir, *, progress=None, **tray options) -> report: write the stack."},
    {"count", tray_count, METH_NOARGS, "count() -> parts added."},
    HVPY_HANDLE_METHODS,
    {NULL, NULL, 0, NULL},
};
static PyGetSetDef tray_getset[] = {HVPY_HANDLE_GETSET, {NULL, NULL, NULL, NULL, NULL}};

PyTypeObject hvpy_TrayType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "hovox.Tray",
    .tp_basicsize = sizeof(hvpy_tray),
    .tp_dealloc = tray_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A print tray: parts placed on a printer's plate and written as one stack (hovox.tray).",
    .tp_clear = tray_clear,
    .tp_weaklistoffset = offsetof(hvpy_tray, weakrefs),
    .tp_methods = tray_methods,
    .tp_getset = tray_getset,
};

PyMethodDef hvpy_tray_functions[] = {
    {"tray", KW(py_tray),
     "tray(**options of `hovox tray` (profile, mode, seed, spacing, arrange, layers, gcvf, force, dry_run, resin={...}, "
     "resin_color={...}, max_memory)) -> Tray."},
    {NULL, NULL, 0, NULL},
};

int hvpy_init_tray(PyObject *m)
{
    if (PyType_Ready(&hvpy_TrayType) < 0) return -1;
    return PyModule_AddObjectRef(m, "Tray", (PyObject *)&hvpy_TrayType);
}
