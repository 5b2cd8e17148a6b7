/* python/src/mesh.c - Python: the Mesh class (files in and out, the report, bodies and materials,
 * vertices and facets as arrays, affine transforms), meshes from arrays, the parametric
 * generators (the keys of hv_shape_option_set, as `hovox generate SHAPE key=value`) and joining
 * meshes into an assembly. */
#include "hvpy.h"

#include "hovox/generate.h"
#include "hovox/placement.h"

static int mesh_clear(PyObject *self)
{
    hvpy_handle *h = (hvpy_handle *)self;
    hv_mesh_destroy(h->p);
    h->p = NULL;
    return 0;
}

static void mesh_dealloc(PyObject *self)
{
    if (((hvpy_handle *)self)->weakrefs) PyObject_ClearWeakRefs(self);
    mesh_clear(self);
    Py_TYPE(self)->tp_free(self);
}

PyObject *hvpy_new_mesh(hv_mesh *m)
{
    hvpy_handle *h = PyObject_New(hvpy_handle, &hvpy_MeshType);
    if (!h) {
        hv_mesh_destroy(m);
        return NULL;
    }
    h->p = m;
    h->views = h->busy = 0;
    h->weakrefs = NULL;
    return (PyObject *)h;
}

static PyObject *mesh_repr(PyObject *self)
{
    hv_mesh *m = ((hvpy_handle *)self)->p;
    if (!m) return PyUnicode_FromString("<hovox.Mesh (freed)>");
    return PyUnicode_FromFormat("<hovox.Mesh %zu facets, %zu vertices>", hv_mesh_facet_count(m), hv_mesh_vertex_count(m));
}

/* load_mesh(path) -> Mesh */
static PyObject *py_load_mesh(PyObject *self, PyObject *arg)
{
    (void)self;
    PyObject *path = hvpy_path(arg, "path");
    if (!path) return NULL;
    hv_mesh *m = NULL;
    hvpy_call c;
    hvpy_begin(&c, NULL, NULL, 0);
    hv_status s = hv_mesh_load(PyBytes_AS_STRING(path), &m);
    hvpy_end(&c);
    Py_DECREF(path);
    return s != HV_OK ? hvpy_call_fail(&c, s) : hvpy_call_done(&c, hvpy_new_mesh(m));
}

/* mesh(vertices, facets) -> Mesh from an (n, 3) float array and an (f, 3) integer array */
static PyObject *py_mesh(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static char *kwlist[] = {"vertices", "facets", NULL};
    PyObject *vo, *fo;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO:mesh", kwlist, &vo, &fo)) return NULL;
    PyObject *v = hvpy_as_array(vo, NPY_FLOAT32, "vertices");
    if (!v) return NULL;
    PyObject *f = PyArray_FromAny(fo, PyArray_DescrFromType(NPY_INT64), 0, 0, NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED |
                                  NPY_ARRAY_FORCECAST, NULL);
    if (!f) {
        Py_DECREF(v);
        return NULL;
    }
    PyArrayObject *va = (PyArrayObject *)v, *fa = (PyArrayObject *)f;
    PyObject *res = NULL;
    if (PyArray_NDIM(va) != 2 || PyArray_DIM(va, 1) != 3 || PyArray_NDIM(fa) != 2 || PyArray_DIM(fa, 1) != 3) {
        PyErr_SetString(PyExc_ValueError, "vertices must be an (n, 3) array and facets an (f, 3) array");
        goto done;
    }
    size_t nv = (size_t)PyArray_DIM(va, 0), nf = (size_t)PyArray_DIM(fa, 0);
    const int64_t *fi = PyArray_DATA(fa);
    uint32_t *idx = PyMem_Malloc(nf * 3 * sizeof *idx + 1);
    if (!idx) {
        PyErr_NoMemory();
        goto done;
    }
    for (size_t i = 0; i < nf * 3; ++i) {
        if (fi[i] < 0 || (uint64_t)fi[i] >= nv) {
            PyMem_Free(idx);
            hvpy_raise(HV_ERR_INVALID, "facet %zu: vertex index %lld is out of range (%zu vertices)", i / 3,
                       (long long)fi[i], nv);
            goto done;
        }
        idx[i] = (uint32_t)fi[i];
    }
    hv_mesh *m;
    hv_status s = hv_mesh_create(PyArray_DATA(va), nv, idx, nf, &m);
    PyMem_Free(idx);
    res = s != HV_OK ? hvpy_fail(s) : hvpy_new_mesh(m);
done:
    Py_DECREF(v);
    Py_DECREF(f);
    return res;
}

static PyObject *report_dict(const hv_mesh_report *r)
{
    return Py_BuildValue("{s:s,s:K,s:K,s:{s:(ddd),s:(ddd)},s:d,s:d,s:K,s:K,s:K,s:K,s:K,s:K,s:O}", "format",
                         hv_mesh_format_key(r->format), "facets", (unsigned long long)r->facets, "vertices",
                         (unsigned long long)r->vertices, "bbox", "min", r->bbox_min[0], r->bbox_min[1], r->bbox_min[2],
                         "max", r->bbox_max[0], r->bbox_max[1], r->bbox_max[2], "volume", r->volume, "area", r->area,
                         "shells", (unsigned long long)r->shells, "open_edges", (unsigned long long)r->open_edges,
                         "nonmanifold_edges", (unsigned long long)r->nonmanifold_edges, "degenerate_facets",
                         (unsigned long long)r->degenerate_facets, "flipped_facets",
                         (unsigned long long)r->flipped_facets, "normal_mismatch",
                         (unsigned long long)r->normal_mismatch, "closed",
                         r->open_edges == 0 && r->nonmanifold_edges == 0 ? Py_True : Py_False);
}

static PyObject *mesh_report(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_mesh *m = HVPY_MESH(self);
    return m ? report_dict(hv_mesh_get_report(m)) : NULL;
}

static PyObject *mesh_count(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_mesh *m = HVPY_MESH(self);
    return m ? Py_BuildValue("(nn)", (Py_ssize_t)hv_mesh_facet_count(m), (Py_ssize_t)hv_mesh_vertex_count(m)) : NULL;
}

/* bodies() -> [{name, material (or None), facets, first}] (first counts from 0, as arrays do) */
static PyObject *mesh_bodies(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_mesh *m = HVPY_MESH(self);
    if (!m) return NULL;
    size_t n = hv_mesh_body_count(m);
    PyObject *list = PyList_New((Py_ssize_t)n);
    for (size_t i = 0; list && i < n; ++i) {
        const hv_mesh_body *b = hv_mesh_body_at(m, i);
        PyObject *d = Py_BuildValue("{s:s,s:z,s:n,s:n}", "name", b->name, "material",
                                    b->material >= 0 ? hv_mesh_material_at(m, (size_t)b->material)->name : NULL,
                                    "facets", (Py_ssize_t)b->facet_count, "first", (Py_ssize_t)b->first_facet);
        if (!d) Py_CLEAR(list);
        else PyList_SET_ITEM(list, (Py_ssize_t)i, d);
    }
    return list;
}

/* materials() -> [{name, color: (r, g, b, a) in [0, 1] or None}] */
static PyObject *mesh_materials(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_mesh *m = HVPY_MESH(self);
    if (!m) return NULL;
    size_t n = hv_mesh_material_count(m);
    PyObject *list = PyList_New((Py_ssize_t)n);
    for (size_t i = 0; list && i < n; ++i) {
        const hv_mesh_material *mt = hv_mesh_material_at(m, i);
        PyObject *color = Py_None;
        Py_INCREF(color);
        if (mt->has_color) {
            Py_DECREF(color);
            double c[4];
            for (int k = 0; k < 4; ++k) c[k] = (double)((mt->rgba >> (24 - 8 * k)) & 0xFF) / 255.0;
            color = Py_BuildValue("(dddd)", c[0], c[1], c[2], c[3]);
        }
        PyObject *d = color ? Py_BuildValue("{s:s,s:N}", "name", mt->name, "color", color) : NULL;
        if (!d) Py_CLEAR(list);
        else PyList_SET_ITEM(list, (Py_ssize_t)i, d);
    }
    return list;
}

/* save(path, ascii=False): STL, or OBJ for a .obj name */
static PyObject *mesh_save(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"path", "ascii", NULL};
    PyObject *po;
    int ascii = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|p:save", kwlist, &po, &ascii)) return NULL;
    hv_mesh *m = HVPY_MESH(self);
    PyObject *path = m ? hvpy_path(po, "path") : NULL;
    if (!path) return NULL;
    hvpy_call c;
    hvpy_begin(&c, NULL, &self, 1);
    hv_status s = hv_mesh_save(m, PyBytes_AS_STRING(path), ascii);
    hvpy_end(&c);
    Py_DECREF(path);
    if (s != HV_OK) return hvpy_call_fail(&c, s);
    return hvpy_call_done(&c, Py_NewRef(Py_None));
}

/* transform(matrix) -> Mesh: x' = A x + t, matrix 3x4 [A | t] or 4x4 (last row 0 0 0 1), or 12 numbers */
static PyObject *mesh_transform(PyObject *self, PyObject *arg)
{
    hv_mesh *m = HVPY_MESH(self);
    if (!m) return NULL;
    PyObject *a = hvpy_as_array(arg, NPY_FLOAT64, "matrix");
    if (!a) return NULL;
    PyArrayObject *arr = (PyArrayObject *)a;
    npy_intp size = PyArray_SIZE(arr);
    double mat[12];
    const double *d = PyArray_DATA(arr);
    if (size == 12) {
        memcpy(mat, d, sizeof mat);
    } else if (size == 16 && PyArray_NDIM(arr) == 2) {
        if (d[12] != 0 || d[13] != 0 || d[14] != 0 || d[15] != 1) {
            Py_DECREF(a);
            return hvpy_raise(HV_ERR_INVALID, "matrix: a 4x4 matrix must end with the row 0, 0, 0, 1 (an affine map)");
        }
        memcpy(mat, d, sizeof mat);
    } else {
        Py_DECREF(a);
        return PyErr_Format(PyExc_ValueError, "matrix must be 3x4 [A | t], 4x4 or 12 numbers");
    }
    Py_DECREF(a);
    hv_mesh *out;
    hv_status s = hv_mesh_transform(m, mat, &out);
    return s != HV_OK ? hvpy_fail(s) : hvpy_new_mesh(out);
}

/* place(unit=, up=, scale=, rotate=, translate=) -> Mesh placed as `hovox voxelize --unit ...` places
 * it (hovox/placement.h: unit, up, scale, rotations in order, translate, whatever the keys' order) */
static PyObject *mesh_place(PyObject *self, PyObject *args, PyObject *kw)
{
    if (PyTuple_GET_SIZE(args) != 0)
        return PyErr_Format(PyExc_TypeError, "place() takes keywords only: unit, up, scale, rotate, translate");
    hvpy_arena a;
    if (hvpy_arena_init(&a) != 0) return NULL;
    hv_placement p;
    if (hvpy_read_options(kw, hv_placement_option_set(), &p, NULL, &a) != 0) {
        hvpy_arena_free(&a);
        return NULL;
    }
    hv_mesh *m = HVPY_MESH(self); /* after reading the options: they may have run Python code */
    hv_mesh *out = NULL;
    hv_status s = m ? hv_placement_transform(&p, m, &out) : HV_ERR_INVALID;
    hvpy_arena_free(&a);
    if (!m) return NULL;
    return s != HV_OK ? hvpy_fail(s) : hvpy_new_mesh(out);
}

static PyObject *mesh_vertices(PyObject *self, void *unused)
{
    (void)unused;
    hv_mesh *m = HVPY_MESH(self);
    if (!m) return NULL;
    Py_ssize_t dims[2] = {(Py_ssize_t)hv_mesh_vertex_count(m), 3};
    return hvpy_array_view(self, (void *)hv_mesh_vertices(m), 2, dims, NPY_FLOAT32, 0);
}

static PyObject *mesh_facets(PyObject *self, void *unused)
{
    (void)unused;
    hv_mesh *m = HVPY_MESH(self);
    if (!m) return NULL;
    Py_ssize_t dims[2] = {(Py_ssize_t)hv_mesh_facet_count(m), 3};
    return hvpy_array_view(self, (void *)hv_mesh_facets(m), 2, dims, NPY_UINT32, 0);
}

static PyObject *mesh_name(PyObject *self, void *unused)
{
    (void)unused;
    hv_mesh *m = HVPY_MESH(self);
    return m ? PyUnicode_FromString(hv_mesh_name(m)) : NULL;
}

static PyMethodDef mesh_methods[] = {
    {"report", mesh_report, METH_NOARGS,
     "report() -> dict: facets, vertices, bbox {min, max}, volume, area, shells, open_edges, nonmanifold_edges, "
     "degenerate_facets, flipped_facets, normal_mismatch, closed, format (as `hovox info --json`)."},
    {"count", mesh_count, METH_NOARGS, "count() -> (facets, vertices)."},
    {"bodies", mesh_bodies, METH_NOARGS,
     "bodies() -> [{name, material (or None), facets, first (its first facet, from 0)}] in file order."},
    {"materials", mesh_materials, METH_NOARGS,
     "materials() -> [{name, color ((r, g, b, a) in [0, 1], or None)}] in the order first used."},
    {"save", (PyCFunction)(void (*)(void))mesh_save, METH_VARARGS | METH_KEYWORDS,
     "save(path, ascii=False): binary (or ASCII) STL, or OBJ for a .obj name (a group and usemtl per body)."},
    {"transform", mesh_transform, METH_O,
     "transform(matrix) -> Mesh moved by x' = A x + t (matrix 3x4 [A | t] or 4x4 affine), bodies kept; a mirror "
     "keeps facets outward."},
    {"place", (PyCFunction)(void (*)(void))mesh_place, METH_VARARGS | METH_KEYWORDS,
     "place(unit='m', up='y', scale=S or (SX, SY, SZ), rotate='x:90' or ['x:90', '30@1,1,0'], translate=(X, Y, Z)) "
     "-> Mesh placed as `hovox voxelize --unit ... --translate` places it: unit, up, scale, rotations in order, "
     "translate."},
    HVPY_HANDLE_METHODS,
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef mesh_getset[] = {
    {"vertices", mesh_vertices, NULL, "(n, 3) float32 array of the welded vertices (a read-only view).", NULL},
    {"facets", mesh_facets, NULL, "(f, 3) uint32 array of vertex indices, counter-clockwise from outside (a view).",
     NULL},
    {"name", mesh_name, NULL, "Where the mesh came from ('' when generated).", NULL},
    HVPY_HANDLE_GETSET,
    {NULL, NULL, NULL, NULL, NULL},
};

PyTypeObject hvpy_MeshType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "hovox.Mesh",
    .tp_basicsize = sizeof(hvpy_handle),
    .tp_dealloc = mesh_dealloc,
    .tp_repr = mesh_repr,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A triangle mesh (welded, with adjacency and its report); from hovox.load_mesh, hovox.mesh, "
              "hovox.generate or hovox.join_meshes.",
    .tp_clear = mesh_clear,
    .tp_weaklistoffset = offsetof(hvpy_handle, weakrefs),
    .tp_methods = mesh_methods,
    .tp_getset = mesh_getset,
};

/* ---- generators ------------------------------------------------------------------------------- */

/* generate(shape, **params) -> Mesh */
static PyObject *py_generate(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    const char *name;
    if (!PyArg_ParseTuple(args, "s:generate", &name)) return NULL;
    int shape = hv_shape_find(name);
    if (shape < 0) return hvpy_raise(HV_ERR_INVALID, "%s", hv_last_error()); /* names the shapes */
    hv_shape_params p;
    hvpy_arena a;
    if (hvpy_arena_init(&a) < 0) return NULL;
    int rc = hvpy_read_options(kw, hv_shape_option_set(shape), &p, NULL, &a);
    hvpy_arena_free(&a);
    if (rc < 0) return NULL;
    hv_mesh *m;
    hv_status s;
    Py_BEGIN_ALLOW_THREADS
    s = hv_generate_shape(shape, &p, &m);
    Py_END_ALLOW_THREADS
    return s != HV_OK ? hvpy_fail(s) : hvpy_new_mesh(m);
}

/* shapes() -> {name: (about, [keys])} */
static PyObject *py_shapes(PyObject *self, PyObject *unused)
{
    (void)self, (void)unused;
    PyObject *d = PyDict_New();
    for (int i = 0; d && i < hv_shape_count(); ++i) {
        const hv_option_set *set = hv_shape_option_set(i);
        PyObject *keys = PyList_New(set->count);
        for (int k = 0; keys && k < set->count; ++k) PyList_SET_ITEM(keys, k, PyUnicode_FromString(set->options[k].key));
        PyObject *v = keys ? Py_BuildValue("(sN)", hv_shape_about(i), keys) : NULL;
        if (!v || PyDict_SetItemString(d, hv_shape_name(i), v) < 0) Py_CLEAR(d);
        Py_XDECREF(v);
    }
    return d;
}

/* join_meshes([{"mesh": m, "name": ..., "material": ...} or Mesh, ...]) -> Mesh, a body per part */
static PyObject *py_join_meshes(PyObject *self, PyObject *arg)
{
    (void)self;
    PyObject *seq = PySequence_Fast(arg, "join_meshes takes a list of parts");
    if (!seq) return NULL;
    Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
    PyObject *res = NULL;
    hvpy_arena a;
    hv_mesh_part *parts = NULL;
    if (hvpy_arena_init(&a) < 0) goto done;
    if (n < 1) {
        hvpy_raise(HV_ERR_INVALID, "give at least one part {'mesh': ..., 'name': ..., 'material': ...}");
        goto done;
    }
    parts = PyMem_Calloc((size_t)n, sizeof *parts);
    if (!parts) {
        PyErr_NoMemory();
        goto done;
    }
    for (Py_ssize_t i = 0; i < n; ++i) {
        PyObject *it = PySequence_Fast_GET_ITEM(seq, i), *mo = it;
        if (PyDict_Check(it)) {
            PyObject *k, *v;
            Py_ssize_t pos = 0;
            while (PyDict_Next(it, &pos, &k, &v)) {
                const char *ks = PyUnicode_Check(k) ? PyUnicode_AsUTF8(k) : NULL;
                if (!ks || (strcmp(ks, "mesh") && strcmp(ks, "name") && strcmp(ks, "material"))) {
                    hvpy_raise(HV_ERR_INVALID, "part %zd: unknown key '%s' (keys: mesh, name, material)", i + 1,
                               ks ? ks : Py_TYPE(k)->tp_name);
                    goto done;
                }
            }
            mo = PyDict_GetItemString(it, "mesh");
            PyObject *nm = PyDict_GetItemString(it, "name"), *mat = PyDict_GetItemString(it, "material");
            char what[48];
            snprintf(what, sizeof what, "part %zd: name", i + 1);
            if (nm && nm != Py_None && !(parts[i].name = hvpy_arena_str(&a, nm, what))) goto done;
            snprintf(what, sizeof what, "part %zd: material", i + 1);
            if (mat && mat != Py_None && !(parts[i].material = hvpy_arena_str(&a, mat, what))) goto done;
        }
        if (!mo || !PyObject_TypeCheck(mo, &hvpy_MeshType)) {
            hvpy_raise(HV_ERR_INVALID, "part %zd: mesh must be a hovox.Mesh", i + 1);
            goto done;
        }
        if (!(parts[i].mesh = HVPY_MESH(mo))) goto done;
    }
    hv_mesh *out;
    hv_status s = hv_mesh_join(parts, (size_t)n, &out);
    res = s != HV_OK ? hvpy_fail(s) : hvpy_new_mesh(out);
done:
    PyMem_Free(parts);
    hvpy_arena_free(&a);
    Py_DECREF(seq);
    return res;
}

PyMethodDef hvpy_mesh_functions[] = {
    {"load_mesh", py_load_mesh, METH_O, "load_mesh(path) -> Mesh: STL, 3MF, OBJ or PLY, by extension."},
    {"mesh", (PyCFunction)(void (*)(void))py_mesh, METH_VARARGS | METH_KEYWORDS,
     "mesh(vertices, facets) -> Mesh from an (n, 3) array of points and an (f, 3) array of vertex indices "
     "(counter-clockwise from outside); welded again."},
    {"generate", (PyCFunction)(void (*)(void))py_generate, METH_VARARGS | METH_KEYWORDS,
     "generate(shape, **params) -> Mesh: a closed parametric mesh, the shapes and keys of `hovox generate`."},
    {"shapes", py_shapes, METH_NOARGS, "shapes() -> {name: (about, [parameter keys])}."},
    {"join_meshes", py_join_meshes, METH_O,
     "join_meshes(parts) -> Mesh: an assembly, one body per part in order; a part is a Mesh or "
     "{'mesh': Mesh, 'name': ..., 'material': ...}."},
    {NULL, NULL, 0, NULL},
};

int hvpy_init_mesh(PyObject *m)
{
    if (PyType_Ready(&hvpy_MeshType) < 0) return -1;
    return PyModule_AddObjectRef(m, "Mesh", (PyObject *)&hvpy_MeshType);
}
