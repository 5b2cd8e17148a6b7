/* python/src/object.c - Python: heterogeneous objects (Wu 2.2): hovox.object(model, materials),
 * grading sources added, moved and deleted, blending, the base composition, the Boolean operators
 * (also as &, |, -, +), evaluation into a model (GIL released, progress, Ctrl-C), and the model's
 * outputs through an evaluation. */
#include "hvpy.h"

static int object_clear(PyObject *self)
{
    hvpy_object *h = (hvpy_object *)self;
    hv_object_destroy(h->p);
    h->p = NULL;
    return 0;
}

static void object_dealloc(PyObject *self)
{
    if (((hvpy_handle *)self)->weakrefs) PyObject_ClearWeakRefs(self);
    object_clear(self);
    Py_CLEAR(((hvpy_object *)self)->mats);
    Py_TYPE(self)->tp_free(self);
}

static PyObject *new_object(hv_object *o, PyObject *mats)
{
    hvpy_object *h = PyObject_New(hvpy_object, &hvpy_ObjectType);
    if (!h) {
        hv_object_destroy(o);
        return NULL;
    }
    h->p = o;
    h->views = h->busy = 0;
    h->weakrefs = NULL;
    h->mats = Py_NewRef(mats); /* the material table lives as long as the object */
    return (PyObject *)h;
}

static PyObject *object_repr(PyObject *self)
{
    hv_object *o = ((hvpy_handle *)self)->p;
    if (!o) return PyUnicode_FromString("<hovox.Object (freed)>");
    return PyUnicode_FromFormat("<hovox.Object %d regions, %d materials, %llu voxels>", hv_object_region_count(o),
                                hv_object_materials(o), (unsigned long long)hv_object_voxels(o));
}

/* object(model, materials=None, grid=None) -> Object: a model voxelized from an assembly gives one
 * region per body (materials, when given, must name the bodies' materials, else the table is
 * built from them); any other model, or a grid named, one region (materials required). */
static PyObject *py_object(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static char *kwlist[] = {"model", "materials", "grid", NULL};
    PyObject *mo, *to = Py_None;
    const char *grid = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|Oz:object", kwlist, &mo, &to, &grid)) return NULL;
    hv_volume *v = HVPY_MODEL(mo);
    if (!v) return NULL;
    const hv_material_table *given = NULL;
    if (to != Py_None && !(given = HVPY_MATS(to))) return NULL;
    hv_material_table *built = NULL;
    hv_object *o = NULL;
    hv_status s = HV_ERR_NOT_FOUND;
    if (!grid) s = hv_object_from_regions(v, given, &built, &o);
    if (s == HV_ERR_NOT_FOUND) {
        if (!given)
            return hvpy_raise(HV_ERR_INVALID, "materials are required (the model has no regions with materials: it was "
                                              "not voxelized from an assembly)");
        s = hv_object_create(v, grid ? grid : "occupancy", hv_material_count(given), &o);
    }
    if (s != HV_OK) {
        hv_material_table_destroy(built);
        return hvpy_fail(s);
    }
    /* the object's own table (a copy of the one given), so the caller may free theirs */
    if (!built && hv_material_table_clone(given, &built) != HV_OK) {
        hv_object_destroy(o);
        return hvpy_fail(HV_ERR_NOMEM);
    }
    PyObject *mats = hvpy_new_materials(built);
    if (!mats) {
        hv_object_destroy(o);
        return NULL;
    }
    PyObject *r = new_object(o, mats);
    Py_DECREF(mats);
    return r;
}

/* add_ags(source=None, region=None, **source options) -> Source: to every region, or to the
 * region of that name alone; the keywords make a source as hovox.ags does */
static PyObject *object_add_ags(PyObject *self, PyObject *args, PyObject *kw)
{
    PyObject *src = NULL, *region = NULL;
    if (!PyArg_ParseTuple(args, "|OO:add_ags", &src, &region)) return NULL;
    PyObject *rest = kw ? PyDict_Copy(kw) : PyDict_New();
    if (!rest) return NULL;
    if (!region && (region = PyDict_GetItemString(rest, "region"))) {
        Py_INCREF(region);
        PyDict_DelItemString(rest, "region");
    } else {
        Py_XINCREF(region);
    }
    PyObject *source = NULL, *res = NULL;
    if (src && src != Py_None) {
        if (PyDict_Size(rest)) {
            PyErr_SetString(PyExc_TypeError, "add_ags: give a Source or the source's keywords, not both");
            goto done;
        }
        if (!HVPY_SOURCE(src)) goto done;
        source = Py_NewRef(src);
    } else {
        PyObject *empty = PyTuple_New(0);
        source = empty ? hvpy_make_source(empty, rest, 0) : NULL;
        Py_XDECREF(empty);
        if (!source) goto done;
    }
    hv_object *o = HVPY_OBJECT(self); /* after f ran: it may have freed the object */
    hv_ags *a = o ? HVPY_SOURCE(source) : NULL;
    if (!a) goto done;
    const char *rn = NULL;
    if (region && region != Py_None && !(rn = PyUnicode_AsUTF8(region))) goto done;
    hv_status s = rn ? hv_object_add_ags_region(o, rn, a) : hv_object_add_ags(o, a);
    res = s != HV_OK ? hvpy_fail(s) : Py_NewRef(source);
done:
    Py_XDECREF(source);
    Py_XDECREF(region);
    Py_DECREF(rest);
    return res;
}

static PyObject *object_delete_ags(PyObject *self, PyObject *arg)
{
    hv_object *o = HVPY_OBJECT(self);
    hv_ags *a = o ? HVPY_SOURCE(arg) : NULL;
    if (!a) return NULL;
    hv_status s = hv_object_delete_ags(o, a);
    return s != HV_OK ? hvpy_fail(s) : Py_NewRef(Py_None);
}

static PyObject *object_move_ags(PyObject *self, PyObject *args)
{
    PyObject *src;
    double d;
    if (!PyArg_ParseTuple(args, "Od:move_ags", &src, &d)) return NULL;
    hv_object *o = HVPY_OBJECT(self);
    hv_ags *a = o ? HVPY_SOURCE(src) : NULL;
    if (!a) return NULL;
    hv_status s = hv_object_move_ags(o, a, d);
    return s != HV_OK ? hvpy_fail(s) : Py_NewRef(Py_None);
}

static PyObject *object_set_blend(PyObject *self, PyObject *args)
{
    const char *name;
    double power = 2;
    if (!PyArg_ParseTuple(args, "s|d:set_blend", &name, &power)) return NULL;
    hv_object *o = HVPY_OBJECT(self);
    if (!o) return NULL;
    hv_blend b;
    if (hv_blend_parse(name, &b) != HV_OK) return hvpy_fail(HV_ERR_INVALID);
    hv_status s = hv_object_set_blend(o, b, power);
    return s != HV_OK ? hvpy_fail(s) : Py_NewRef(Py_None);
}

/* set_base(p, region=None): the base of every region, or of the region of that name */
static PyObject *object_set_base(PyObject *self, PyObject *args)
{
    PyObject *po;
    const char *region = NULL;
    if (!PyArg_ParseTuple(args, "O|z:set_base", &po, &region)) return NULL;
    hv_object *o = HVPY_OBJECT(self);
    if (!o) return NULL;
    int m = hv_object_materials(o);
    Py_ssize_t n = PySequence_Check(po) ? PySequence_Size(po) : -1;
    if (n != m) {
        PyErr_Clear();
        return hvpy_raise(HV_ERR_INVALID, "base has %zd values for %d materials", n < 0 ? 0 : n, m);
    }
    double p[HV_MAX_MATERIALS];
    if (hvpy_numbers(po, p, m, "base") < 0) return NULL;
    if (hv_composition_check(p, m, "base") != HV_OK) return hvpy_fail(HV_ERR_INVALID);
    int r = region ? hv_object_region_find(o, region) : -1;
    if (region && r < 0) return hvpy_raise(HV_ERR_NOT_FOUND, "the object has no region '%s'", region);
    hv_status s = region ? hv_object_set_region_base(o, r, p) : hv_object_set_base(o, p);
    return s != HV_OK ? hvpy_fail(s) : Py_NewRef(Py_None);
}

static PyObject *object_boolean(PyObject *self, PyObject *other, hv_bool_op op)
{
    hv_object *a = HVPY_OBJECT(self), *b = a ? HVPY_OBJECT(other) : NULL;
    if (!b) return NULL;
    /* compositions are vectors over the same named materials, in the same order: otherwise the
     * operators would silently relabel one object's materials */
    const hv_material_table *ta = HVPY_MATS(((hvpy_object *)self)->mats), *tb = HVPY_MATS(((hvpy_object *)other)->mats);
    if (!ta || !tb) return NULL;
    for (int j = 0; j < hv_material_count(ta) && j < hv_material_count(tb); ++j)
        if (strcmp(hv_material_name(ta, j), hv_material_name(tb, j)) != 0)
            return hvpy_raise(HV_ERR_INVALID, "material %d is '%s' here and '%s' in the other object: combine objects "
                              "made with the same materials", j + 1, hv_material_name(ta, j), hv_material_name(tb, j));
    hv_object *o;
    hv_status s = hv_object_boolean(a, b, op, &o);
    return s != HV_OK ? hvpy_fail(s) : new_object(o, ((hvpy_object *)self)->mats);
}

static PyObject *object_intersect(PyObject *s, PyObject *o) { return object_boolean(s, o, HV_OP_INTERSECT); }
static PyObject *object_union(PyObject *s, PyObject *o) { return object_boolean(s, o, HV_OP_UNITE); }
static PyObject *object_difference(PyObject *s, PyObject *o) { return object_boolean(s, o, HV_OP_DIFFERENCE); }
static PyObject *object_merge(PyObject *s, PyObject *o) { return object_boolean(s, o, HV_OP_MERGE); }
static PyObject *object_subtract(PyObject *s, PyObject *o) { return object_boolean(s, o, HV_OP_SUBTRACT); }

/* Operators: & intersect, | union, - difference (Wu's), + merge */
static PyObject *binop(PyObject *a, PyObject *b, hv_bool_op op)
{
    if (!PyObject_TypeCheck(a, &hvpy_ObjectType) || !PyObject_TypeCheck(b, &hvpy_ObjectType)) Py_RETURN_NOTIMPLEMENTED;
    return object_boolean(a, b, op);
}
static PyObject *nb_and(PyObject *a, PyObject *b) { return binop(a, b, HV_OP_INTERSECT); }
static PyObject *nb_or(PyObject *a, PyObject *b) { return binop(a, b, HV_OP_UNITE); }
static PyObject *nb_sub(PyObject *a, PyObject *b) { return binop(a, b, HV_OP_DIFFERENCE); }
static PyObject *nb_add(PyObject *a, PyObject *b) { return binop(a, b, HV_OP_MERGE); }

/* The max_memory keyword as the evaluation reads it (the output's own option). */
static int max_memory(PyObject *kw, uint64_t *out)
{
    *out = 0;
    PyObject *v = hvpy_kw(kw, "max_memory");
    if (!v) return 0;
    static const hv_option mm = {.key = "max_memory", .kind = HV_OPT_BYTES};
    hv_opt_value val = {HV_VALUE_NUMBERS, NULL, NULL, 0, 0};
    double num = 0;
    if (PyUnicode_Check(v)) {
        val.type = HV_VALUE_TEXT;
        val.text = PyUnicode_AsUTF8(v);
        if (!val.text) return -1;
    } else {
        num = PyFloat_AsDouble(v);
        if (num == -1.0 && PyErr_Occurred()) return -1;
        val.numbers = &num;
        val.n = 1;
    }
    if (hv_option_set_value(&mm, out, &val) != HV_OK) return hvpy_fail(HV_ERR_INVALID), -1;
    return 0;
}

static PyObject *evaluate(PyObject *self, uint64_t maxmem, PyObject *progress)
{
    hv_object *o = HVPY_OBJECT(self);
    const hv_material_table *t = o ? HVPY_MATS(((hvpy_object *)self)->mats) : NULL;
    if (!t) return NULL;
    hvpy_call c;
    hv_volume *v = NULL;
    PyObject *pins[2] = {self, ((hvpy_object *)self)->mats};
    hvpy_begin(&c, progress, pins, 2);
    hv_status s = hv_object_evaluate(o, t, maxmem, &c.prog, &v);
    hvpy_end(&c);
    return s != HV_OK ? hvpy_call_fail(&c, s) : hvpy_call_done(&c, hvpy_new_model(v));
}

/* evaluate(max_memory=None, progress=None) -> Model */
static PyObject *object_evaluate(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"max_memory", "progress", NULL};
    PyObject *mm = NULL, *progress = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|$OO:evaluate", kwlist, &mm, &progress)) return NULL;
    uint64_t maxmem;
    if (max_memory(kw, &maxmem) < 0) return NULL;
    if (progress && progress != Py_None && !PyCallable_Check(progress))
        return PyErr_Format(PyExc_TypeError, "progress must be a callable(stage, fraction) or None");
    return evaluate(self, maxmem, progress);
}

/* obj.NAME(...): evaluate (max_memory and progress from the keywords), call the model's method of
 * that name with the same arguments, free the model */
static PyObject *via_model(PyObject *self, const char *name, PyObject *args, PyObject *kw, int drop_max_memory)
{
    uint64_t maxmem;
    if (max_memory(kw, &maxmem) < 0) return NULL;
    PyObject *progress = hvpy_kw(kw, "progress");
    PyObject *model = evaluate(self, maxmem, progress);
    if (!model) return NULL;
    PyObject *rest = kw ? PyDict_Copy(kw) : NULL, *res = NULL;
    if (rest && drop_max_memory && PyDict_GetItemString(rest, "max_memory")) PyDict_DelItemString(rest, "max_memory");
    if (rest && drop_max_memory && PyDict_GetItemString(rest, "progress")) PyDict_DelItemString(rest, "progress");
    PyObject *meth = PyObject_GetAttrString(model, name);
    if (meth) res = PyObject_Call(meth, args, rest);
    Py_XDECREF(meth);
    Py_XDECREF(rest);
    /* free the evaluation now unless an array returned still views it (then it goes with the array) */
    if (((hvpy_handle *)model)->views == 0) {
        PyObject *t, *v, *tb;
        PyErr_Fetch(&t, &v, &tb);
        PyObject *r = hvpy_handle_free(model, NULL);
        Py_XDECREF(r);
        PyErr_Clear();
        PyErr_Restore(t, v, tb);
    }
    Py_DECREF(model);
    return res;
}

#define VIA(name, drop) \
    static PyObject *object_##name(PyObject *self, PyObject *args, PyObject *kw) { return via_model(self, #name, args, kw, drop); }
VIA(render, 0)
VIA(export, 0)
VIA(layers, 0)
VIA(profile, 1)
VIA(probe, 1)
VIA(save, 1)
VIA(fractions, 1)
VIA(layer, 0)

static PyObject *object_regions(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_object *o = HVPY_OBJECT(self);
    if (!o) return NULL;
    int n = hv_object_region_count(o), m = hv_object_materials(o);
    PyObject *list = PyList_New(n);
    double base[HV_MAX_MATERIALS];
    for (int r = 0; list && r < n; ++r) {
        hv_object_region_base(o, r, base);
        PyObject *b = PyList_New(m);
        for (int j = 0; b && j < m; ++j) PyList_SET_ITEM(b, j, PyFloat_FromDouble(base[j]));
        PyObject *d = b ? Py_BuildValue("{s:K,s:i,s:z,s:N}", "voxels", (unsigned long long)hv_object_region_voxels(o, r),
                                        "sources", hv_object_region_ags_count(o, r), "name",
                                        hv_object_region_name(o, r), "base", b)
                        : NULL;
        if (!d) Py_CLEAR(list);
        else PyList_SET_ITEM(list, r, d);
    }
    return list;
}

static PyObject *object_materials(PyObject *self, PyObject *unused)
{
    (void)unused;
    if (!HVPY_OBJECT(self)) return NULL;
    return Py_NewRef(((hvpy_object *)self)->mats);
}

static PyObject *object_voxels(PyObject *self, PyObject *unused)
{
    (void)unused;
    hv_object *o = HVPY_OBJECT(self);
    return o ? PyLong_FromUnsignedLongLong(hv_object_voxels(o)) : NULL;
}

#define KW(f) (PyCFunction)(void (*)(void))(f), METH_VARARGS | METH_KEYWORDS
static PyMethodDef object_methods[] = {
    {"add_ags", KW(object_add_ags),
     "add_ags(source=None, region=None, **source keywords) -> Source: Wu's AGS add (eq. 24) on every region, or on "
     "the region of that name; keywords make the source as hovox.ags does."},
    {"delete_ags", object_delete_ags, METH_O, "delete_ags(source): Wu's AGS delete (eq. 25)."},
    {"move_ags", object_move_ags, METH_VARARGS, "move_ags(source, d_neg): Wu's AGS move (eq. 26)."},
    {"set_blend", object_set_blend, METH_VARARGS, "set_blend('nearest' or 'idw', power=2): the AGS union rule."},
    {"set_base", object_set_base, METH_VARARGS,
     "set_base(p, region=None): the composition where no source applies (every region's, or one region's)."},
    {"intersect", object_intersect, METH_O, "intersect(other) -> Object: H1 n H2 (Wu eq. 27; also a & b)."},
    {"union", object_union, METH_O, "union(other) -> Object: H1 u H2 (Wu eq. 28; also a | b)."},
    {"difference", object_difference, METH_O, "difference(other) -> Object: Wu's H1 - H2 (eq. 29; also a - b)."},
    {"merge", object_merge, METH_O, "merge(other) -> Object: H1 + H2 (Wu eq. 30; also a + b)."},
    {"subtract", object_subtract, METH_O, "subtract(other) -> Object: CSG subtraction (O1 - O2, G1)."},
    {"evaluate", KW(object_evaluate),
     "evaluate(max_memory=None, progress=None) -> Model: the graded model (occupancy, material.<name> grids and the "
     "grading definition)."},
    {"regions", object_regions, METH_NOARGS, "regions() -> [{voxels, sources, name, base}]."},
    {"voxels", object_voxels, METH_NOARGS, "voxels() -> the object's voxel count."},
    {"materials", object_materials, METH_NOARGS, "materials() -> the object's Materials."},
    {"render", KW(object_render), "render(...): Model.render on the object's evaluation (freed afterwards)."},
    {"export", KW(object_export), "export(...): Model.export on the object's evaluation."},
    {"layers", KW(object_layers), "layers(...): Model.layers on the object's evaluation."},
    {"profile", KW(object_profile), "profile(...): Model.profile on the object's evaluation."},
    {"probe", KW(object_probe), "probe(points): Model.probe on the object's evaluation."},
    {"save", KW(object_save), "save(path): the object's evaluation as a .vdb file."},
    {"fractions", KW(object_fractions), "fractions(box=None): Model.fractions on the object's evaluation."},
    {"layer", KW(object_layer), "layer(mesh, index, ...): Model.layer on the object's evaluation."},
    HVPY_HANDLE_METHODS,
    {NULL, NULL, 0, NULL},
};
static PyGetSetDef object_getset[] = {HVPY_HANDLE_GETSET, {NULL, NULL, NULL, NULL, NULL}};
static PyNumberMethods object_number = {.nb_and = nb_and, .nb_or = nb_or, .nb_subtract = nb_sub, .nb_add = nb_add};

PyTypeObject hvpy_ObjectType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "hovox.Object",
    .tp_basicsize = sizeof(hvpy_object),
    .tp_dealloc = object_dealloc,
    .tp_repr = object_repr,
    .tp_as_number = &object_number,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A heterogeneous object (Wu 2.2): regions (geometry, grading sources, base composition) over the "
              "materials of a table (hovox.object).",
    .tp_clear = object_clear,
    .tp_weaklistoffset = offsetof(hvpy_object, weakrefs),
    .tp_methods = object_methods,
    .tp_getset = object_getset,
};

PyMethodDef hvpy_object_functions[] = {
    {"object", KW(py_object),
     "object(model, materials=None, grid=None) -> Object: one region (the occupancy or `grid`, no source, base "
     "material 1), or one region per body for a model voxelized from an assembly."},
    {NULL, NULL, 0, NULL},
};

int hvpy_init_object(PyObject *m)
{
    if (PyType_Ready(&hvpy_ObjectType) < 0) return -1;
    return PyModule_AddObjectRef(m, "Object", (PyObject *)&hvpy_ObjectType);
}
