/* python/src/opts.c - keyword arguments read through the library's option sets (hovox/options.h),
 * as the Lua binding reads its tables (src/lua/lopts.c): a keyword is the CLI's long option with
 * '_' for '-', takes the same values and is refused with the same message. Every string given to
 * the library is a private copy kept until the call ends. */
#include "hvpy.h"

#include <stdio.h>
#include <string.h>

#define MAX_VALUES 64

int hvpy_arena_init(hvpy_arena *a)
{
    a->keep = PyList_New(0);
    return a->keep ? 0 : -1;
}

void hvpy_arena_free(hvpy_arena *a) { Py_CLEAR(a->keep); }

static const char *keep_bytes(hvpy_arena *a, PyObject *b)
{
    if (PyList_Append(a->keep, b) < 0) {
        Py_DECREF(b);
        return NULL;
    }
    Py_DECREF(b);
    return PyBytes_AS_STRING(b);
}

static const char *keep_text(hvpy_arena *a, const char *s)
{
    PyObject *b = PyBytes_FromString(s);
    return b ? keep_bytes(a, b) : NULL;
}

const char *hvpy_arena_str(hvpy_arena *a, PyObject *o, const char *what)
{
    PyObject *b;
    if (PyUnicode_Check(o)) {
        b = PyUnicode_AsUTF8String(o);
        if (b && strlen(PyBytes_AS_STRING(b)) != (size_t)PyBytes_GET_SIZE(b)) {
            Py_DECREF(b);
            PyErr_Format(PyExc_ValueError, "%s must not contain NUL bytes", what);
            return NULL;
        }
    } else {
        b = hvpy_path(o, what);
    }
    return b ? keep_bytes(a, b) : NULL;
}

/* The option's key for a keyword: "from_" -> "from" (into buf). */
static const char *key_of(PyObject *k, char *buf, size_t size)
{
    const char *s = PyUnicode_Check(k) ? PyUnicode_AsUTF8(k) : NULL;
    if (!s) return NULL;
    size_t n = strlen(s);
    if (n > 1 && s[n - 1] == '_' && n < size) {
        memcpy(buf, s, n - 1);
        buf[n - 1] = '\0';
        return buf;
    }
    return s;
}

PyObject *hvpy_kw(PyObject *kw, const char *key)
{
    if (!kw) return NULL;
    PyObject *v = PyDict_GetItemString(kw, key);
    if (!v) {
        char alt[80];
        snprintf(alt, sizeof alt, "%s_", key);
        v = PyDict_GetItemString(kw, alt);
    }
    return v == Py_None ? NULL : v;
}

int hvpy_split_progress(PyObject *kw, PyObject **progress, PyObject **rest)
{
    *progress = NULL;
    *rest = kw ? PyDict_Copy(kw) : PyDict_New();
    if (!*rest) return -1;
    PyObject *p = PyDict_GetItemString(*rest, "progress");
    if (p) {
        if (p != Py_None && !PyCallable_Check(p)) {
            Py_CLEAR(*rest);
            PyErr_SetString(PyExc_TypeError, "progress must be a callable(stage, fraction) or None");
            return -1;
        }
        *progress = p == Py_None ? NULL : p;
        Py_XINCREF(*progress);
        if (PyDict_DelItemString(*rest, "progress") < 0) return -1;
    }
    return 0;
}

static int listed(const char *const *keys, const char *k)
{
    for (const char *const *q = keys; q && *q; ++q)
        if (strcmp(*q, k) == 0) return 1;
    return 0;
}

static int raise_option(void)
{
    hvpy_fail(HV_ERR_INVALID);
    return -1;
}

static int is_number(PyObject *o) { return PyLong_Check(o) || PyFloat_Check(o) || PyArray_IsScalar(o, Number); }

/* Set option `key` from the Python value v. Returns the status (message set). */
static hv_status set_value(hv_optargs *args, const char *key, const hv_option *o, PyObject *v, hvpy_arena *a)
{
    hv_opt_value val = {HV_VALUE_TEXT, NULL, NULL, 0, 0};
    double nums[MAX_VALUES];
    char text[64];
    if (PyBool_Check(v)) {
        val.type = HV_VALUE_BOOL;
        val.boolean = v == Py_True;
        return hv_optargs_set(args, key, &val);
    }
    if (is_number(v) && !PyArray_Check(v)) {
        double d = PyFloat_AsDouble(v);
        if (d == -1.0 && PyErr_Occurred()) {
            PyErr_Clear();
            return hv_error_option(HV_ERR_INVALID, "{%s} must be a number", key);
        }
        int integral = PyLong_Check(v) || PyArray_IsScalar(v, Integer);
        if (o && (o->kind == HV_OPT_ENUM || o->kind == HV_OPT_STRING || (o->kind == HV_OPT_NUMBER && o->elem == HV_ELEM_UINT64 && integral))) {
            /* adjacency=6: an enum name may be a number; integers keep all 64 bits through their text */
            if (integral) {
                long long ll = PyLong_AsLongLong(v);
                if (ll == -1 && PyErr_Occurred()) {
                    PyErr_Clear();
                    snprintf(text, sizeof text, "%.17g", d);
                } else {
                    snprintf(text, sizeof text, "%lld", ll);
                }
            } else {
                snprintf(text, sizeof text, "%.17g", d);
            }
            val.text = keep_text(a, text);
            if (!val.text) return HV_ERR_NOMEM;
            return hv_optargs_set(args, key, &val);
        }
        nums[0] = d;
        val.type = HV_VALUE_NUMBERS;
        val.numbers = nums;
        val.n = 1;
        return hv_optargs_set(args, key, &val);
    }
    if (PyUnicode_Check(v) || PyObject_HasAttrString(v, "__fspath__")) {
        val.text = hvpy_arena_str(a, v, key);
        if (!val.text) {
            PyObject *t, *e, *tb;
            PyErr_Fetch(&t, &e, &tb);
            Py_XDECREF(t), Py_XDECREF(e), Py_XDECREF(tb);
            return hv_error_option(HV_ERR_INVALID, "{%s} must be text without NUL bytes", key);
        }
        return hv_optargs_set(args, key, &val);
    }
    if (PyDict_Check(v)) {
        if (!o || !(o->flags & HV_OPT_PAIRS)) return hv_error_option(HV_ERR_INVALID, "{%s} cannot be a dict", key);
        PyObject *keys = PyDict_Keys(v);
        if (!keys || PyList_Sort(keys) < 0) {
            Py_XDECREF(keys);
            PyErr_Clear();
            return hv_error_option(HV_ERR_INVALID, "{%s} must map names to strings", key);
        }
        for (Py_ssize_t i = 0; i < PyList_GET_SIZE(keys); ++i) {
            PyObject *k = PyList_GET_ITEM(keys, i), *x = PyDict_GetItem(v, k);
            if (!PyUnicode_Check(k) || !x || !PyUnicode_Check(x)) {
                Py_DECREF(keys);
                return hv_error_option(HV_ERR_INVALID, "{%s} must map names to strings", key);
            }
            PyObject *pair = PyUnicode_FromFormat("%U=%U", k, x);
            val.text = pair ? hvpy_arena_str(a, pair, key) : NULL;
            Py_XDECREF(pair);
            if (!val.text) {
                Py_DECREF(keys);
                PyErr_Clear();
                return hv_error_option(HV_ERR_INVALID, "{%s} must map names to strings without NUL bytes", key);
            }
            hv_status s = hv_optargs_set(args, key, &val);
            if (s != HV_OK) {
                Py_DECREF(keys);
                return s;
            }
        }
        Py_DECREF(keys);
        return HV_OK;
    }
    if (PySequence_Check(v)) {
        PyObject *seq = PySequence_Fast(v, "");
        if (!seq) {
            PyErr_Clear();
            return hv_error_option(HV_ERR_INVALID, "{%s} cannot be a %s", key, Py_TYPE(v)->tp_name);
        }
        Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
        if (n > 0 && o && (o->flags & HV_OPT_REPEAT) && !is_number(PySequence_Fast_GET_ITEM(seq, 0))) {
            for (Py_ssize_t i = 0; i < n; ++i) { /* a list of values: each one given in turn */
                hv_status s = set_value(args, key, o, PySequence_Fast_GET_ITEM(seq, i), a);
                if (s != HV_OK) {
                    Py_DECREF(seq);
                    return s;
                }
            }
            Py_DECREF(seq);
            return HV_OK;
        }
        if (n > MAX_VALUES) {
            Py_DECREF(seq);
            return hv_error_option(HV_ERR_INVALID, "{%s} has %zd values (at most %d)", key, n, MAX_VALUES);
        }
        for (Py_ssize_t i = 0; i < n; ++i) {
            PyObject *x = PySequence_Fast_GET_ITEM(seq, i);
            if (!is_number(x) || PyBool_Check(x)) {
                Py_DECREF(seq);
                return hv_error_option(HV_ERR_INVALID, "{%s} must be a list of numbers; item %zd is a %s", key, i + 1,
                                       Py_TYPE(x)->tp_name);
            }
            nums[i] = PyFloat_AsDouble(x);
        }
        Py_DECREF(seq);
        val.type = HV_VALUE_NUMBERS;
        val.numbers = nums;
        val.n = (int)n;
        return hv_optargs_set(args, key, &val);
    }
    return hv_error_option(HV_ERR_INVALID, "{%s} cannot be a %s", key, Py_TYPE(v)->tp_name);
}

int hvpy_read_options(PyObject *kw, const hv_option_set *set, void *opts, const char *const *extra, hvpy_arena *a)
{
    hv_optargs args;
    hv_optargs_begin(&args, set, opts);
    if (kw) {
        /* unknown keys first, so a misspelt option never falls back to its default */
        PyObject *k, *v;
        Py_ssize_t pos = 0;
        char buf[80];
        while (PyDict_Next(kw, &pos, &k, &v)) {
            const char *key = key_of(k, buf, sizeof buf);
            if (!key) {
                if (!PyErr_Occurred()) PyErr_Format(PyExc_TypeError, "option names must be strings, got %s", Py_TYPE(k)->tp_name);
                return -1;
            }
            if (hv_option_known(set, extra, key) != HV_OK) {
                hvpy_raise(HV_ERR_INVALID, "%s", hv_last_error()); /* a usage error, as the CLI's exit 2 */
                return -1;
            }
        }
        /* then the values, in the set's order (deterministic messages) */
        for (int i = 0; i < set->count; ++i) {
            const hv_option *o = &set->options[i];
            if (listed(extra, o->key)) continue; /* the binding reads it itself */
            PyObject *val = hvpy_kw(kw, o->key);
            if (val && set_value(&args, o->key, o, val, a) != HV_OK) return PyErr_Occurred() ? -1 : raise_option();
        }
        for (int i = 0; i < set->alias_count; ++i) {
            PyObject *val = hvpy_kw(kw, set->aliases[i].name);
            if (val && set_value(&args, set->aliases[i].name, NULL, val, a) != HV_OK)
                return PyErr_Occurred() ? -1 : raise_option();
        }
    }
    if (hv_optargs_finish(&args) != HV_OK) return raise_option();
    return 0;
}
