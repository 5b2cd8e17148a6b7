/* python/src/module.c - the `hovox._hovox` module: exceptions per status, the handle life cycle
 * (free, pins, views), NumPy arrays over C memory, long calls (GIL released, progress callbacks,
 * Ctrl-C through the library's cancel check) and the module's small functions. */
#define HVPY_MODULE_C
#include "hvpy.h"

#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>

#include "hovox/image.h"

/* ==== exceptions ======================================================================== */

PyObject *hvpy_Error, *hvpy_ClosedError;
static PyObject *g_status_exc[HV_ERR_INTERNAL + 1];

static const struct {
    const char *name;
    hv_status status;
    PyObject **base; /* a Python base besides hovox.Error (may be NULL) */
    const char *doc;
} g_exc[] = {
    {"InvalidError", HV_ERR_INVALID, &PyExc_ValueError, "A value given by the caller is out of its domain (HV_ERR_INVALID)."},
    {"BadInputError", HV_ERR_BAD_INPUT, &PyExc_ValueError, "A file or script is malformed (HV_ERR_BAD_INPUT)."},
    {"FileError", HV_ERR_IO, &PyExc_OSError, "A file could not be opened, read, written or renamed (HV_ERR_IO)."},
    {"NoMemoryError", HV_ERR_NOMEM, &PyExc_MemoryError, "An allocation failed (HV_ERR_NOMEM)."},
    {"LimitError", HV_ERR_LIMIT, NULL, "The job would exceed the memory budget or a size limit (HV_ERR_LIMIT)."},
    {"CancelledError", HV_ERR_CANCELLED, NULL, "A progress callback cancelled the call (HV_ERR_CANCELLED)."},
    {"NotFoundError", HV_ERR_NOT_FOUND, &PyExc_LookupError, "A named grid, material, key or plugin does not exist (HV_ERR_NOT_FOUND)."},
    {"UnsupportedError", HV_ERR_UNSUPPORTED, NULL, "A format or feature is not available in this build (HV_ERR_UNSUPPORTED)."},
    {"InternalError", HV_ERR_INTERNAL, NULL, "A bug, or an unexpected exception from a C++ library (HV_ERR_INTERNAL)."},
};

static PyObject *raise_message(hv_status s, const char *msg)
{
    PyObject *cls = s > HV_OK && s <= HV_ERR_INTERNAL ? g_status_exc[s] : hvpy_Error;
    PyObject *exc = PyObject_CallFunction(cls, "s", msg);
    if (!exc) return NULL;
    PyObject *code = PyLong_FromLong((long)s), *name = PyUnicode_FromString(hv_status_name(s));
    if (code && name && PyObject_SetAttrString(exc, "status", code) == 0 &&
        PyObject_SetAttrString(exc, "status_name", name) == 0)
        PyErr_SetObject(cls, exc);
    Py_XDECREF(code);
    Py_XDECREF(name);
    Py_DECREF(exc);
    return NULL;
}

PyObject *hvpy_fail(hv_status s)
{
    const char *m = hv_last_error();
    return raise_message(s, m && *m ? m : hv_status_name(s));
}

PyObject *hvpy_raise(hv_status s, const char *fmt, ...)
{
    char msg[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return raise_message(s, msg);
}

static int make_exceptions(PyObject *m)
{
    hvpy_Error = PyErr_NewExceptionWithDoc("hovox.Error", "A hovox library call failed: str(e) is the library's "
                                           "message, e.status the hv_status code, e.status_name its name.",
                                           NULL, NULL);
    if (!hvpy_Error || PyModule_AddObjectRef(m, "Error", hvpy_Error) < 0) return -1;
    for (size_t i = 0; i < sizeof g_exc / sizeof g_exc[0]; ++i) {
        char qual[64];
        snprintf(qual, sizeof qual, "hovox.%s", g_exc[i].name);
        PyObject *bases = g_exc[i].base ? PyTuple_Pack(2, hvpy_Error, *g_exc[i].base) : PyTuple_Pack(1, hvpy_Error);
        if (!bases) return -1;
        PyObject *e = PyErr_NewExceptionWithDoc(qual, g_exc[i].doc, bases, NULL);
        Py_DECREF(bases);
        if (!e) return -1;
        PyObject *code = PyLong_FromLong((long)g_exc[i].status);
        int bad = !code || PyObject_SetAttrString(e, "status", code) < 0;
        Py_XDECREF(code);
        if (bad || PyModule_AddObjectRef(m, g_exc[i].name, e) < 0) return -1;
        g_status_exc[g_exc[i].status] = e;
    }
    hvpy_ClosedError = PyErr_NewExceptionWithDoc("hovox.ClosedError", "The object was freed (free(), close() or "
                                                 "the end of a with block).", g_status_exc[HV_ERR_INVALID], NULL);
    if (!hvpy_ClosedError || PyModule_AddObjectRef(m, "ClosedError", hvpy_ClosedError) < 0) return -1;
    return 0;
}

/* ==== handles ============================================================================= */

void *hvpy_live(PyObject *o, PyTypeObject *type, const char *what)
{
    if (!PyObject_TypeCheck(o, type)) {
        PyErr_Format(PyExc_TypeError, "expected %s, got %s", what, Py_TYPE(o)->tp_name);
        return NULL;
    }
    void *p = ((hvpy_handle *)o)->p;
    if (!p) {
        PyErr_Format(hvpy_ClosedError, "%s was freed", type->tp_name);
        return NULL;
    }
    return p;
}

PyObject *hvpy_handle_free(PyObject *self, PyObject *unused)
{
    (void)unused;
    hvpy_handle *h = (hvpy_handle *)self;
    if (h->busy) return PyErr_Format(PyExc_BufferError, "cannot free %s: a call running in another thread uses it",
                                     Py_TYPE(self)->tp_name);
    if (h->views)
        return PyErr_Format(PyExc_BufferError, "cannot free %s: %zd array%s view%s its memory (delete them first)",
                            Py_TYPE(self)->tp_name, h->views, h->views == 1 ? "" : "s", h->views == 1 ? "s" : "");
    /* each type's destructor frees p (and what goes with it) and leaves it NULL */
    Py_TYPE(self)->tp_clear(self);
    Py_RETURN_NONE;
}

PyObject *hvpy_handle_enter(PyObject *self, PyObject *unused)
{
    (void)unused;
    if (!((hvpy_handle *)self)->p) return PyErr_Format(hvpy_ClosedError, "%s was freed", Py_TYPE(self)->tp_name);
    return Py_NewRef(self);
}

PyObject *hvpy_handle_exit(PyObject *self, PyObject *args)
{
    (void)args;
    PyObject *r = hvpy_handle_free(self, NULL);
    if (!r) return NULL;
    Py_DECREF(r);
    Py_RETURN_FALSE;
}

PyObject *hvpy_handle_closed(PyObject *self, void *unused)
{
    (void)unused;
    return PyBool_FromLong(((hvpy_handle *)self)->p == NULL);
}

int hvpy_add_methods(PyTypeObject *type, PyMethodDef *defs)
{
    for (PyMethodDef *d = defs; d->ml_name; ++d) {
        PyObject *descr = PyDescr_NewMethod(type, d);
        if (!descr) return -1;
        int rc = PyDict_SetItemString(type->tp_dict, d->ml_name, descr);
        Py_DECREF(descr);
        if (rc < 0) return -1;
    }
    PyType_Modified(type);
    return 0;
}

/* ==== arrays ============================================================================== */

/* The base of an array that views a handle's memory: pins the handle while it lives. */
typedef struct view_keeper {
    PyObject_HEAD
    PyObject *owner;
} view_keeper;

static void keeper_dealloc(PyObject *self)
{
    view_keeper *k = (view_keeper *)self;
    ((hvpy_handle *)k->owner)->views--;
    Py_DECREF(k->owner);
    Py_TYPE(self)->tp_free(self);
}

static PyTypeObject g_keeper_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "hovox._View",
    .tp_basicsize = sizeof(view_keeper),
    .tp_dealloc = keeper_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Keeps a hovox object alive (and pinned) while an array views its memory.",
};

PyObject *hvpy_array_view(PyObject *owner, void *data, int nd, const Py_ssize_t *dims, int typenum, int writable)
{
    npy_intp d[8];
    for (int i = 0; i < nd; ++i) d[i] = (npy_intp)dims[i];
    PyObject *arr = PyArray_New(&PyArray_Type, nd, d, typenum, NULL, data, 0, writable ? NPY_ARRAY_CARRAY : NPY_ARRAY_CARRAY_RO,
                                NULL);
    if (!arr) return NULL;
    view_keeper *k = PyObject_New(view_keeper, &g_keeper_type);
    if (!k) {
        Py_DECREF(arr);
        return NULL;
    }
    k->owner = Py_NewRef(owner);
    ((hvpy_handle *)owner)->views++;
    if (PyArray_SetBaseObject((PyArrayObject *)arr, (PyObject *)k) < 0) { /* steals k */
        Py_DECREF(arr);
        return NULL;
    }
    return arr;
}

static void capsule_free(PyObject *cap) { free(PyCapsule_GetPointer(cap, "hovox.buffer")); }

PyObject *hvpy_array_own(void *data, int nd, const Py_ssize_t *dims, int typenum)
{
    npy_intp d[8];
    for (int i = 0; i < nd; ++i) d[i] = (npy_intp)dims[i];
    PyObject *cap = PyCapsule_New(data ? data : malloc(1), "hovox.buffer", capsule_free);
    if (!cap) {
        free(data);
        return NULL;
    }
    PyObject *arr = PyArray_New(&PyArray_Type, nd, d, typenum, NULL, PyCapsule_GetPointer(cap, "hovox.buffer"), 0,
                                NPY_ARRAY_CARRAY, NULL);
    if (!arr) {
        Py_DECREF(cap);
        return NULL;
    }
    if (PyArray_SetBaseObject((PyArrayObject *)arr, cap) < 0) {
        Py_DECREF(arr);
        return NULL;
    }
    return arr;
}

PyObject *hvpy_as_array(PyObject *o, int typenum, const char *what)
{
    PyObject *a = PyArray_FromAny(o, PyArray_DescrFromType(typenum), 0, 0,
                                  NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED | NPY_ARRAY_FORCECAST, NULL);
    if (!a) {
        PyObject *t, *v, *tb;
        PyErr_Fetch(&t, &v, &tb);
        PyErr_Format(PyExc_TypeError, "%s must be an array of numbers (%S)", what, v ? v : Py_None);
        Py_XDECREF(t);
        Py_XDECREF(v);
        Py_XDECREF(tb);
    }
    return a;
}

int hvpy_numbers(PyObject *o, double *out, int n, const char *what)
{
    PyObject *seq = PySequence_Check(o) && !PyUnicode_Check(o) ? PySequence_Fast(o, "") : NULL;
    if (!seq || PySequence_Fast_GET_SIZE(seq) != n) {
        Py_XDECREF(seq);
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "%s must be a sequence of %d numbers", what, n);
        return -1;
    }
    for (int i = 0; i < n; ++i) {
        out[i] = PyFloat_AsDouble(PySequence_Fast_GET_ITEM(seq, i));
        if (out[i] == -1.0 && PyErr_Occurred()) {
            Py_DECREF(seq);
            PyErr_Clear();
            PyErr_Format(PyExc_TypeError, "%s[%d] must be a number", what, i);
            return -1;
        }
        if (!isfinite(out[i])) {
            Py_DECREF(seq);
            hvpy_raise(HV_ERR_INVALID, "%s[%d] must be a finite number, got %g", what, i, out[i]);
            return -1;
        }
    }
    Py_DECREF(seq);
    return 0;
}

PyObject *hvpy_path(PyObject *o, const char *what)
{
    PyObject *p = PyOS_FSPath(o);
    if (!p) {
        PyErr_Clear();
        return PyErr_Format(PyExc_TypeError, "%s must be a str or os.PathLike, got %s", what, Py_TYPE(o)->tp_name);
    }
    PyObject *b = NULL;
    if (PyUnicode_Check(p)) b = PyUnicode_EncodeFSDefault(p);
    else if (PyBytes_Check(p)) b = Py_NewRef(p);
    Py_DECREF(p);
    if (b && strlen(PyBytes_AS_STRING(b)) != (size_t)PyBytes_GET_SIZE(b)) {
        Py_DECREF(b);
        return PyErr_Format(PyExc_ValueError, "%s must not contain NUL bytes", what);
    }
    return b;
}

/* ==== long calls ==========================================================================
 * Ctrl-C: while any long call runs, SIGINT sets a flag the library's cancel check reads (set once,
 * at import); the running calls stop with HV_ERR_CANCELLED. When the last one ends, Python's
 * handler is back and the signal is raised again, so Python handles it as it would have
 * (KeyboardInterrupt, or the script's own handler). */

static volatile sig_atomic_t g_interrupted;
static int g_active; /* long calls running; changed with the GIL held */
static struct sigaction g_old_int;
static int g_hooked;

static void on_sigint(int sig)
{
    (void)sig;
    g_interrupted = 1;
}

static int cancel_check(void *user)
{
    (void)user;
    return g_interrupted != 0;
}

static int progress_cb(void *user, const char *stage, double fraction)
{
    hvpy_call *c = user;
    if (!c->callback || c->exc_type) return c->exc_type != NULL;
    PyEval_RestoreThread(c->save);
    PyObject *r = PyObject_CallFunction(c->callback, "sd", stage, fraction);
    int stop = 0;
    if (!r) {
        PyErr_Fetch(&c->exc_type, &c->exc_value, &c->exc_tb);
        if (!c->exc_type) c->exc_type = Py_NewRef(PyExc_SystemError);
        stop = 1;
    } else {
        stop = r == Py_True;
        Py_DECREF(r);
    }
    c->save = PyEval_SaveThread();
    return stop;
}

void hvpy_begin(hvpy_call *c, PyObject *progress, PyObject *const *pins, int npins)
{
    memset(c, 0, sizeof *c);
    /* a call is one command: what it reads it may not write over; what earlier calls read, it may
     * (a model loaded, changed and saved in place) */
    hv_inputs_reset();
    c->callback = progress && progress != Py_None ? progress : NULL;
    Py_XINCREF(c->callback);
    c->prog.fn = progress_cb;
    c->prog.user = c;
    for (int i = 0; i < npins && i < HVPY_MAX_PINS; ++i)
        if (pins[i]) {
            c->pins[c->npins] = (hvpy_handle *)pins[i];
            Py_INCREF(pins[i]);
            c->pins[c->npins++]->busy++;
        }
    if (g_active++ == 0) {
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_sigint;
        sigemptyset(&sa.sa_mask);
        g_hooked = 0;
        if (sigaction(SIGINT, NULL, &g_old_int) == 0 && g_old_int.sa_handler != SIG_IGN &&
            sigaction(SIGINT, &sa, NULL) == 0)
            g_hooked = 1;
    }
    c->save = PyEval_SaveThread();
}

void hvpy_call_enter_python(hvpy_call *c) { PyEval_RestoreThread(c->save); }
void hvpy_call_leave_python(hvpy_call *c) { c->save = PyEval_SaveThread(); }

static int g_forward; /* a Ctrl-C to hand to Python once no call runs */

void hvpy_end(hvpy_call *c)
{
    PyEval_RestoreThread(c->save);
    if (--g_active == 0) {
        if (g_hooked) sigaction(SIGINT, &g_old_int, NULL);
        g_hooked = 0;
        if (g_interrupted) {
            g_interrupted = 0;
            g_forward = 1;
        }
    }
    for (int i = 0; i < c->npins; ++i) {
        c->pins[i]->busy--;
        Py_DECREF((PyObject *)c->pins[i]);
    }
    c->npins = 0;
    Py_CLEAR(c->callback);
}

/* Hand a Ctrl-C that came during the calls to Python's handler; 1 when an exception is now set. */
static int forward_interrupt(void)
{
    if (!g_forward) return 0;
    g_forward = 0;
    raise(SIGINT);
    return PyErr_CheckSignals() < 0;
}

PyObject *hvpy_call_fail(hvpy_call *c, hv_status s)
{
    if (c->exc_type) { /* the progress callback's own exception */
        PyErr_Restore(c->exc_type, c->exc_value, c->exc_tb);
        c->exc_type = c->exc_value = c->exc_tb = NULL;
        forward_interrupt();
        return NULL;
    }
    if (s == HV_ERR_CANCELLED && forward_interrupt()) return NULL;
    return hvpy_fail(s);
}

PyObject *hvpy_call_done(hvpy_call *c, PyObject *result)
{
    (void)c;
    if (result && g_forward) {
        g_forward = 0;
        raise(SIGINT); /* Python's eval loop handles it at the next instruction */
    }
    return result;
}

/* ==== module functions ===================================================================== */

static PyObject *py_set_threads(PyObject *self, PyObject *arg)
{
    (void)self;
    long n = PyLong_AsLong(arg);
    if (n == -1 && PyErr_Occurred()) return NULL;
    if (n < 0 || n > 1024) return hvpy_raise(HV_ERR_INVALID, "threads must be in [0, 1024], got %ld", n);
    hv_set_threads((int)n);
    Py_RETURN_NONE;
}

static PyObject *py_threads(PyObject *self, PyObject *unused)
{
    (void)self, (void)unused;
    return PyLong_FromLong(hv_threads());
}

static PyObject *py_status_name(PyObject *self, PyObject *arg)
{
    (void)self;
    long n = PyLong_AsLong(arg);
    if (n == -1 && PyErr_Occurred()) return NULL;
    return PyUnicode_FromString(hv_status_name((hv_status)n));
}

/* read_png(path, indices=False) -> (H, W) or (H, W, C) uint8 (uint16 for 16-bit files); a palette
 * image as RGB(A), or as its indices */
static PyObject *py_read_png(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static char *kwlist[] = {"path", "indices", NULL};
    PyObject *arg;
    int indices = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|p:read_png", kwlist, &arg, &indices)) return NULL;
    PyObject *path = hvpy_path(arg, "path");
    if (!path) return NULL;
    PyObject *data = NULL;
    FILE *f = fopen(PyBytes_AS_STRING(path), "rb");
    if (!f) {
        hvpy_raise(HV_ERR_IO, "%s: cannot open: %s", PyBytes_AS_STRING(path), strerror(errno));
        Py_DECREF(path);
        return NULL;
    }
    char buf[65536];
    size_t got;
    PyObject *parts = PyBytes_FromStringAndSize(NULL, 0);
    while (parts && (got = fread(buf, 1, sizeof buf, f)) > 0) {
        PyObject *chunk = PyBytes_FromStringAndSize(buf, (Py_ssize_t)got);
        if (!chunk) {
            Py_CLEAR(parts);
            break;
        }
        PyBytes_ConcatAndDel(&parts, chunk);
    }
    int err = ferror(f);
    fclose(f);
    data = parts;
    if (!data || err) {
        Py_XDECREF(data);
        if (err) hvpy_raise(HV_ERR_IO, "%s: read failed", PyBytes_AS_STRING(path));
        Py_DECREF(path);
        return NULL;
    }
    hv_png_pixels px;
    memset(&px, 0, sizeof px);
    hv_status s = hv_png_decode_flags(PyBytes_AS_STRING(data), (size_t)PyBytes_GET_SIZE(data), PyBytes_AS_STRING(path),
                                      (uint64_t)1 << 34, indices ? HV_PNG_PALETTE_INDICES : 0, &px);
    Py_DECREF(data);
    Py_DECREF(path);
    if (s != HV_OK) return hvpy_fail(s);
    size_t n = (size_t)px.width * (size_t)px.height * (size_t)px.channels;
    Py_ssize_t dims[3] = {px.height, px.width, px.channels};
    int nd = px.channels == 1 ? 2 : 3;
    if (px.bit_depth == 16) return hvpy_array_own(px.samples, nd, dims, NPY_UINT16);
    uint8_t *b = malloc(n ? n : 1);
    if (!b) {
        hv_png_pixels_free(&px);
        return PyErr_NoMemory();
    }
    for (size_t i = 0; i < n; ++i) b[i] = (uint8_t)px.samples[i];
    hv_png_pixels_free(&px);
    return hvpy_array_own(b, nd, dims, NPY_UINT8);
}

/* rgba8(image) -> (H, W, 4) uint8, straight alpha, from a render's (H, W, 4) float32 premultiplied
 * image (hv_image_to_rgba8) */
static PyObject *py_rgba8(PyObject *self, PyObject *arg)
{
    (void)self;
    PyObject *a = hvpy_as_array(arg, NPY_FLOAT32, "image");
    if (!a) return NULL;
    PyArrayObject *img = (PyArrayObject *)a;
    if (PyArray_NDIM(img) != 3 || PyArray_DIM(img, 2) != 4 || PyArray_DIM(img, 0) < 1 || PyArray_DIM(img, 1) < 1 ||
        PyArray_DIM(img, 0) > 65535 || PyArray_DIM(img, 1) > 65535) {
        Py_DECREF(a);
        return PyErr_Format(PyExc_ValueError, "image must be an (H, W, 4) array (as render() returns)");
    }
    hv_image im = {(int)PyArray_DIM(img, 1), (int)PyArray_DIM(img, 0), (float *)PyArray_DATA(img)};
    size_t n = (size_t)im.width * (size_t)im.height * 4;
    uint8_t *out = malloc(n);
    if (!out) {
        Py_DECREF(a);
        return PyErr_NoMemory();
    }
    hv_image_to_rgba8(&im, out);
    Py_DECREF(a);
    Py_ssize_t dims[3] = {im.height, im.width, 4};
    return hvpy_array_own(out, 3, dims, NPY_UINT8);
}

static PyMethodDef g_functions[] = {
    {"set_threads", py_set_threads, METH_O, "set_threads(n): worker threads of the multi-threaded kernels (0: all cores)."},
    {"threads", py_threads, METH_NOARGS, "threads() -> the worker threads in use."},
    {"status_name", py_status_name, METH_O, "status_name(code) -> 'HV_ERR_...'."},
    {"read_png", (PyCFunction)(void (*)(void))py_read_png, METH_VARARGS | METH_KEYWORDS,
     "read_png(path, indices=False) -> array: a PNG's samples, (H, W) for grey, else (H, W, C); uint8, or uint16 for "
     "16-bit files (hovox's hostile-input decoder); a palette image as RGB(A), or with indices=True as its palette "
     "indices (H, W)."},
    {"rgba8", py_rgba8, METH_O,
     "rgba8(image) -> (H, W, 4) uint8 with straight alpha, from render()'s premultiplied float image (what the PNG "
     "file holds)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef g_module = {
    PyModuleDef_HEAD_INIT, "hovox._hovox",
    "The hovox C library for Python (see the package hovox for the documented API).", -1, NULL, NULL, NULL, NULL, NULL,
};

static int add_functions(PyObject *m, PyMethodDef *defs)
{
    return PyModule_AddFunctions(m, defs);
}

PyMODINIT_FUNC PyInit__hovox(void)
{
    import_array();
    PyObject *m = PyModule_Create(&g_module);
    if (!m) return NULL;
    if (PyType_Ready(&g_keeper_type) < 0 || make_exceptions(m) < 0 || hvpy_init_mesh(m) < 0 ||
        hvpy_init_model(m) < 0 || hvpy_init_source(m) < 0 || hvpy_init_object(m) < 0 || hvpy_init_tray(m) < 0 ||
        hvpy_init_output(m) < 0 || add_functions(m, g_functions) < 0 || add_functions(m, hvpy_mesh_functions) < 0 ||
        add_functions(m, hvpy_model_functions) < 0 || add_functions(m, hvpy_source_functions) < 0 ||
        add_functions(m, hvpy_object_functions) < 0 || add_functions(m, hvpy_output_functions) < 0 ||
        add_functions(m, hvpy_tray_functions) < 0 || PyModule_AddStringConstant(m, "version", hv_version()) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    hv_set_cancel_check(cancel_check, NULL);
    return m;
}
