/* python/src/hvpy.h - the `hovox._hovox` CPython extension: the C library's API for Python, with
 * NumPy arrays in and out. Split by class like the Lua binding: module.c (module, errors, long
 * calls: the GIL, progress, Ctrl-C), opts.c (keyword arguments read through the library's option
 * sets), mesh.c, model.c (models, dense and sparse arrays), source.c (materials, features,
 * sources), object.c, output.c (render, export, layers, profile, contours) and tray.c.
 *
 * Rules every binding follows: arguments are checked and converted first, the library is called
 * (with the GIL released for long calls, the objects it uses pinned so no other thread frees
 * them), and an exception is raised only after it returned, with the library's message; a freed
 * object raises hovox.ClosedError; option keywords are the CLI's long options with '_' for '-',
 * refused with the library's message; arrays that view an object's memory keep it alive and
 * pin it (free() then refuses). Adding a function: write it with these helpers and list it in
 * its file's method table. */
#ifndef HOVOX_HVPY_H
#define HOVOX_HVPY_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

/* NumPy's C API: one table for the extension, imported by module.c */
#define PY_ARRAY_UNIQUE_SYMBOL hvpy_ARRAY_API
#ifndef HVPY_MODULE_C
#define NO_IMPORT_ARRAY
#endif
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include "hovox/core.h"
#include "hovox/material.h"
#include "hovox/mesh.h"
#include "hovox/options.h"
#include "hovox/tray.h"
#include "hovox/volume.h"

/* ---- errors (module.c) ---------------------------------------------------------------------- */

/* hovox.Error and one subclass per status; ClosedError (a freed object, an InvalidError). */
extern PyObject *hvpy_Error, *hvpy_ClosedError;
/* Raise the exception of `status` with the library's last message; returns NULL. */
PyObject *hvpy_fail(hv_status status);
/* Raise the exception of `status` with a message; returns NULL. */
PyObject *hvpy_raise(hv_status status, const char *fmt, ...);

/* ---- handles ------------------------------------------------------------------------------------
 * Every class holds its C object in `p` (NULL once freed). `views` counts the arrays that view its
 * memory, `busy` the long calls running on it with the GIL released: free() refuses while either
 * is nonzero. */
#define HVPY_HANDLE \
    PyObject_HEAD \
    void *p; \
    Py_ssize_t views, busy; \
    PyObject *weakrefs

typedef struct hvpy_handle {
    HVPY_HANDLE;
} hvpy_handle;

typedef struct hvpy_model {
    HVPY_HANDLE;
    hv_material_table *mats; /* loaded from the metadata on first use */
} hvpy_model;

typedef struct hvpy_object {
    HVPY_HANDLE;
    PyObject *mats; /* the Materials object */
} hvpy_object;

typedef struct hvpy_tray {
    HVPY_HANDLE;
    hv_tray_options o;
    PyObject *keep; /* list of bytes holding o's strings */
} hvpy_tray;

extern PyTypeObject hvpy_MeshType, hvpy_ModelType, hvpy_MaterialsType, hvpy_FeatureType, hvpy_SourceType,
    hvpy_ObjectType, hvpy_TrayType;

/* The live C object of `o` if it is of `type`: raises TypeError (another type, naming `what`) or
 * hovox.ClosedError (freed) and returns NULL. */
void *hvpy_live(PyObject *o, PyTypeObject *type, const char *what);
#define HVPY_MESH(o) ((hv_mesh *)hvpy_live((o), &hvpy_MeshType, "a hovox.Mesh"))
#define HVPY_MODEL(o) ((hv_volume *)hvpy_live((o), &hvpy_ModelType, "a hovox.Model"))
#define HVPY_MATS(o) ((hv_material_table *)hvpy_live((o), &hvpy_MaterialsType, "hovox.Materials"))
#define HVPY_FEATURE(o) ((hv_frf *)hvpy_live((o), &hvpy_FeatureType, "a hovox.Feature"))
#define HVPY_SOURCE(o) ((hv_ags *)hvpy_live((o), &hvpy_SourceType, "a hovox.Source"))
#define HVPY_OBJECT(o) ((hv_object *)hvpy_live((o), &hvpy_ObjectType, "a hovox.Object"))
/* New Python objects owning a C object (destroyed on failure). */
PyObject *hvpy_new_mesh(hv_mesh *m);
PyObject *hvpy_new_model(hv_volume *v);
PyObject *hvpy_new_materials(hv_material_table *t);
PyObject *hvpy_new_feature(hv_frf *f);
PyObject *hvpy_new_source(hv_ags *a);
/* A grading source from hovox.ags's (wu3: hovox.wu3's) keywords (source.c). */
PyObject *hvpy_make_source(PyObject *args, PyObject *kw, int wu3);
/* The model's material table (loaded once); NULL with an exception when it has none. */
hv_material_table *hvpy_model_mats(hvpy_model *m);
/* free(), close() and the context manager's __exit__ for every class. */
PyObject *hvpy_handle_free(PyObject *self, PyObject *unused);
PyObject *hvpy_handle_enter(PyObject *self, PyObject *unused);
PyObject *hvpy_handle_exit(PyObject *self, PyObject *args);
PyObject *hvpy_handle_closed(PyObject *self, void *unused);
#define HVPY_HANDLE_METHODS \
    {"free", hvpy_handle_free, METH_NOARGS, "Free the C object now (also done when the object is collected)."}, \
    {"close", hvpy_handle_free, METH_NOARGS, "Same as free()."}, \
    {"__enter__", hvpy_handle_enter, METH_NOARGS, NULL}, \
    {"__exit__", hvpy_handle_exit, METH_VARARGS, NULL}
#define HVPY_HANDLE_GETSET {"closed", hvpy_handle_closed, NULL, "True once freed.", NULL}

/* ---- arrays ---------------------------------------------------------------------------------------- */

/* A NumPy array viewing `data` (read-only unless writable), kept alive by `owner` (a handle: its
 * `views` count pins it until the array dies) or by a capsule that frees `data` (owner NULL: `data`
 * is the array's own, freed with free()). New reference, or NULL with an exception (data freed
 * when it was the array's own). */
PyObject *hvpy_array_view(PyObject *owner, void *data, int nd, const Py_ssize_t *dims, int typenum, int writable);
PyObject *hvpy_array_own(void *data, int nd, const Py_ssize_t *dims, int typenum);
/* A C-contiguous array of `typenum` from any array-like (a view when it already is one, else a
 * copy); NULL with an exception. */
PyObject *hvpy_as_array(PyObject *o, int typenum, const char *what);
/* Exactly `n` finite numbers from a sequence; -1 with an exception naming `what`. */
int hvpy_numbers(PyObject *o, double *out, int n, const char *what);
/* A str or os.PathLike as UTF-8 bytes (new reference); NULL with TypeError naming `what`. */
PyObject *hvpy_path(PyObject *o, const char *what);
/* Add methods to a type after PyType_Ready (the classes gather methods from several files). */
int hvpy_add_methods(PyTypeObject *type, PyMethodDef *defs);

/* ---- long calls (module.c) ----------------------------------------------------------------------------
 * hvpy_begin pins the handles given, installs the Ctrl-C handler (the library's cancel check
 * sees it) and releases the GIL; hvpy_end takes the GIL back, restores the handler and unpins.
 * `call.prog` is the hv_progress to pass to the library: it calls `progress(stage, fraction)`
 * with the GIL held; a callback that raises stops the call and its exception propagates, one that
 * returns True cancels it. After a failed call, hvpy_call_fail raises: the callback's exception,
 * KeyboardInterrupt (Ctrl-C), or the library's error. */
#define HVPY_MAX_PINS 4
typedef struct hvpy_call {
    PyThreadState *save;
    PyObject *callback;
    PyObject *exc_type, *exc_value, *exc_tb;
    hv_progress prog;
    hvpy_handle *pins[HVPY_MAX_PINS];
    int npins;
} hvpy_call;
void hvpy_begin(hvpy_call *c, PyObject *progress, PyObject *const *pins, int npins);
void hvpy_end(hvpy_call *c);
/* The GIL around Python code run from inside a long call (a per-layer callback). */
void hvpy_call_enter_python(hvpy_call *c);
void hvpy_call_leave_python(hvpy_call *c);
PyObject *hvpy_call_fail(hvpy_call *c, hv_status s);
/* After a successful call: NULL with KeyboardInterrupt pending when Ctrl-C came in its last
 * instant (the caller then drops its result), else returns `result`. */
PyObject *hvpy_call_done(hvpy_call *c, PyObject *result);

/* ---- options (opts.c) ---------------------------------------------------------------------------------
 * Strings read from options live in an arena until the call ends (or, for a tray, in its list). */
typedef struct hvpy_arena {
    PyObject *keep; /* list of bytes objects */
} hvpy_arena;
int hvpy_arena_init(hvpy_arena *a);
void hvpy_arena_free(hvpy_arena *a);
const char *hvpy_arena_str(hvpy_arena *a, PyObject *str_or_path, const char *what);
/* Read the keyword arguments `kw` (may be NULL) into opts through `set` (the struct initialised by
 * set->init first): a key is an option of the set (or an alias), with a trailing '_' dropped
 * (from_ is from); keys listed in `extra` are left to the caller (read them with hvpy_kw); None
 * means "not given". Values: bool, int, float, str or os.PathLike, a sequence of numbers (a
 * vector, a range), a sequence of strings for a repeatable option, a dict {KEY: VALUE} for a
 * KEY=VALUE option. Refusals raise hovox.InvalidError with the library's message ("step must be in
 * ..."), an unknown key with the list of options. Returns 0, or -1 with an exception. */
int hvpy_read_options(PyObject *kw, const hv_option_set *set, void *opts, const char *const *extra, hvpy_arena *a);
/* Keyword `key` of kw (trailing '_' form accepted), borrowed, NULL when absent or None. */
PyObject *hvpy_kw(PyObject *kw, const char *key);
/* An explicit "progress" keyword (callable or None) taken out of kw: a new dict without it in *rest. */
int hvpy_split_progress(PyObject *kw, PyObject **progress, PyObject **rest);

/* ---- registration (one per file) ---------------------------------------------------------------------- */
int hvpy_init_mesh(PyObject *m);
int hvpy_init_model(PyObject *m);
int hvpy_init_source(PyObject *m);
int hvpy_init_object(PyObject *m);
int hvpy_init_tray(PyObject *m);
int hvpy_init_output(PyObject *m); /* after model and object: adds their output methods */
extern PyMethodDef hvpy_mesh_functions[], hvpy_model_functions[], hvpy_source_functions[], hvpy_object_functions[],
    hvpy_output_functions[], hvpy_tray_functions[];

#endif
