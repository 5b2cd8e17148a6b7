/* tests/export/test_export.c - VTK export: mixing rules against hand values, linearization
 * tables and their CSV form, and .vti/.vtu files read back with VTK's own readers (Debian's
 * python3-vtk9) and compared voxel by voxel with the analytic model they came from; atomic
 * output, cancellation, memory budget, determinism across thread counts. */
#include <criterion/criterion.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/internal.h"
#include "core/json.h"
#include "hovox/export.h"
#include "support/support.h"

/* ---- the analytic model -------------------------------------------------------------------
 * Voxels [LO, HI] are active; all are occupied except a hole at i == 4, j in 4..6. Two
 * materials: stiff = (i - LO0) / (HI0 - LO0), soft = 1 - stiff. Anisotropic voxels. */
static const int LO[3] = {-3, 2, -5}, HI[3] = {12, 9, 6};
static const double VOX[3] = {0.5, 1.0, 2.0}, ORG[3] = {10.0, -4.0, 1.5};
static const double RHO[2] = {1100, 1200}, E[2] = {1e6, 2e9}, NU[2] = {0.49, 0.35};

static int occupied(int i, int j, int k)
{
    (void)k;
    if (i < LO[0] || i > HI[0] || j < LO[1] || j > HI[1] || k < LO[2] || k > HI[2]) return 0;
    return !(i == 4 && j >= 4 && j <= 6);
}

static double stiff_at(int i) { return (double)(float)((double)(i - LO[0]) / (HI[0] - LO[0])); }
static double soft_at(int i) { return (double)(float)(1.0 - (double)(i - LO[0]) / (HI[0] - LO[0])); }

/* Activate the voxels [lo, hi] (inclusive) of a box. */
static void add_box(hv_volume *v, const int lo[3], const int hi[3])
{
    cr_assert_eq(t_add_box(v, lo, hi), HV_OK, "%s", hv_last_error());
}

/* The model; with_table = 0 gives a plain voxelized model (occupancy only). */
static hv_volume *make_model(int with_table)
{
    hv_transform xf = {{VOX[0], VOX[1], VOX[2]}, {ORG[0], ORG[1], ORG[2]}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK, "%s", hv_last_error());
    add_box(v, LO, HI);
    int og, gs = -1, gh = -1;
    cr_assert_eq(hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &og), HV_OK);
    if (with_table) {
        cr_assert_eq(hv_volume_grid_add(v, "material.soft", HV_GRID_FLOAT, &gs), HV_OK);
        cr_assert_eq(hv_volume_grid_add(v, "material.stiff", HV_GRID_FLOAT, &gh), HV_OK);
    }
    const int32_t *orig = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const uint64_t *act = hv_volume_leaf_mask(v, l);
        uint64_t *ob = hv_volume_leaf_bool(v, og, l);
        for (unsigned n = 0; n < 512; ++n) {
            if (!HV_BIT_GET(act, n)) continue;
            int i = orig[3 * l] + (int)(n >> 6), j = orig[3 * l + 1] + (int)((n >> 3) & 7),
                k = orig[3 * l + 2] + (int)(n & 7);
            if (occupied(i, j, k)) ob[n >> 6] |= 1ull << (n & 63);
            if (with_table) {
                hv_volume_leaf_float(v, gs, l)[n] = (float)soft_at(i);
                hv_volume_leaf_float(v, gh, l)[n] = (float)stiff_at(i);
            }
        }
    }
    if (with_table) {
        hv_material_table *t;
        cr_assert_eq(hv_material_table_create(&t), HV_OK);
        const char *names[2] = {"soft", "stiff"};
        for (int m = 0; m < 2; ++m) {
            cr_assert_eq(hv_material_add(t, names[m], NULL, NULL), HV_OK, "%s", hv_last_error());
            cr_assert_eq(hv_material_set_property(t, m, "density", RHO[m], "kg/m^3"), HV_OK);
            cr_assert_eq(hv_material_set_property(t, m, "youngs_modulus", E[m], "Pa"), HV_OK);
            cr_assert_eq(hv_material_set_property(t, m, "poisson_ratio", NU[m], "1"), HV_OK);
        }
        cr_assert_eq(hv_material_table_store(v, t), HV_OK, "%s", hv_last_error());
        hv_material_table_destroy(t);
    }
    return v;
}

/* ---- reading back with VTK ---------------------------------------------------------------- */

static const char *READBACK_PY =
    "import sys, json, vtk\n"
    "from vtk.util.numpy_support import vtk_to_numpy\n"
    "path = sys.argv[1]\n"
    "vti = path.endswith('.vti')\n"
    "r = vtk.vtkXMLImageDataReader() if vti else vtk.vtkXMLUnstructuredGridReader()\n"
    "r.SetFileName(path)\n"
    "r.Update()\n"
    "if r.GetErrorCode() != 0: sys.exit(3)\n"
    "d = r.GetOutput()\n"
    "out = {}\n"
    "if vti:\n"
    "    out['dims'] = list(d.GetDimensions())\n"
    "    out['origin'] = list(d.GetOrigin())\n"
    "    out['spacing'] = list(d.GetSpacing())\n"
    "    data = d.GetPointData()\n"
    "else:\n"
    "    out['points'] = vtk_to_numpy(d.GetPoints().GetData()).astype(float).ravel().tolist()\n"
    "    out['ncells'] = d.GetNumberOfCells()\n"
    "    out['conn'] = vtk_to_numpy(d.GetCells().GetConnectivityArray()).tolist()\n"
    "    out['offsets'] = vtk_to_numpy(d.GetCells().GetOffsetsArray()).tolist()\n"
    "    out['celltypes'] = sorted(set(vtk_to_numpy(d.GetCellTypesArray()).tolist()))\n"
    "    data = d.GetCellData()\n"
    "out['names'] = [data.GetArrayName(i) for i in range(data.GetNumberOfArrays())]\n"
    "out['vtktypes'] = [data.GetArray(i).GetDataTypeAsString() for i in range(data.GetNumberOfArrays())]\n"
    "out['arrays'] = [vtk_to_numpy(data.GetArray(i)).astype(float).tolist() for i in range(data.GetNumberOfArrays())]\n"
    "fd = d.GetFieldData()\n"
    "field = {}\n"
    "for i in range(fd.GetNumberOfArrays()):\n"
    "    a = fd.GetAbstractArray(i)\n"
    "    if a.IsA('vtkStringArray'): field[a.GetName()] = a.GetValue(0)\n"
    "    else: field[a.GetName()] = vtk_to_numpy(a).ravel().tolist()\n"
    "out['field'] = field\n"
    "json.dump(out, sys.stdout)\n";

typedef struct readback {
    json_t *doc;
    int narrays;
    const char *names[32];
    const char *types[32];
    double *arrays[32];
    size_t sizes[32];
} readback;

static double *to_doubles(const json_t *arr, size_t *n)
{
    cr_assert_not_null(arr);
    cr_assert(json_is_array(arr));
    size_t count = json_array_size(arr);
    double *v = malloc((count ? count : 1) * sizeof *v);
    for (size_t i = 0; i < count; ++i) v[i] = json_number_value(json_array_get(arr, i));
    *n = count;
    return v;
}

static void read_back(const char *path, readback *rb)
{
    memset(rb, 0, sizeof *rb);
    const char *py = t_tmpfile("readback.py");
    if (!t_exists(py)) {
        FILE *f = fopen(py, "w");
        cr_assert_not_null(f);
        fputs(READBACK_PY, f);
        fclose(f);
    }
    char cmd[2048], *out = NULL;
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 '%s' '%s'", py, path);
    int rc = t_run(cmd, &out);
    cr_assert_eq(rc, 0, "VTK could not read %s back (rc %d)", path, rc);
    cr_assert_eq(hv_json_parse(out, strlen(out), "readback", &rb->doc), HV_OK, "%s", hv_last_error());
    free(out);
    const json_t *names = json_object_get(rb->doc, "names"), *types = json_object_get(rb->doc, "vtktypes");
    const json_t *arrays = json_object_get(rb->doc, "arrays");
    int i = 0;
    for (; (size_t)i < json_array_size(names); ++i) {
        cr_assert_lt(i, 32);
        rb->names[i] = json_string_value(json_array_get(names, (size_t)i));
        rb->types[i] = json_string_value(json_array_get(types, (size_t)i));
        rb->arrays[i] = to_doubles(json_array_get(arrays, (size_t)i), &rb->sizes[i]);
    }
    rb->narrays = i;
}

static void readback_free(readback *rb)
{
    for (int i = 0; i < rb->narrays; ++i) free(rb->arrays[i]);
    json_decref(rb->doc);
}

static const double *array(const readback *rb, const char *name)
{
    for (int i = 0; i < rb->narrays; ++i)
        if (strcmp(rb->names[i], name) == 0) return rb->arrays[i];
    cr_assert_fail("array '%s' missing", name);
    return NULL;
}

static void assert_rel(double got, double want, double tol, const char *what, long at)
{
    double scale = fabs(want) > 1e-30 ? fabs(want) : 1.0;
    cr_assert(fabs(got - want) <= tol * scale, "%s at %ld: got %.9g, want %.9g", what, at, got,
              want);
}

static const char *EXPECTED_NAMES[] = {
    "occupancy",          "fraction.soft",           "fraction.stiff",
    "density.voigt[kg/m^3]", "density.reuss[kg/m^3]", "youngs_modulus.voigt[Pa]",
    "youngs_modulus.reuss[Pa]", "poisson_ratio.voigt[1]", "poisson_ratio.reuss[1]"};

/* Property values of a composition, computed here from the formulas (not by the library). */
static void expected_props(double soft, double stiff, double out[6])
{
    const double *X[3] = {RHO, E, NU};
    for (int q = 0; q < 3; ++q) {
        out[2 * q] = soft * X[q][0] + stiff * X[q][1];
        double inv = 0;
        if (soft > 0) inv += soft / X[q][0];
        if (stiff > 0) inv += stiff / X[q][1];
        out[2 * q + 1] = 1.0 / inv;
    }
}

static hv_status write(const hv_volume *v, const char *path, const hv_export_options *o,
                       hv_export_report *r)
{
    hv_status s = hv_export_write(v, path, o, r);
    return s;
}

/* ---- mixing rules ---------------------------------------------------------------------- */

Test(export, mixing_rules_by_hand)
{
    double p[3] = {0.25, 0.75, 0}, x[3] = {1, 3, 0};
    cr_assert_float_eq(hv_property_voigt(p, x, 3), 2.5, 1e-15);
    /* 1 / (0.25/1 + 0.75/3) = 2; the absent third material (x = 0) is left out */
    cr_assert_float_eq(hv_property_reuss(p, x, 3), 2.0, 1e-15);
    double q[2] = {0.5, 0.5}, y[2] = {0, 4};
    cr_assert_eq(hv_property_reuss(q, y, 2), 0.0); /* a phase without stiffness */
    double z[2] = {0, 0};
    cr_assert_eq(hv_property_reuss(z, y, 2), 0.0);
    /* Reuss <= Voigt for any positive mixture */
    double r[2] = {0.3, 0.7}, w[2] = {1e6, 2e9};
    cr_assert_lt(hv_property_reuss(r, w, 2), hv_property_voigt(r, w, 2));
}

/* ---- linearization tables ------------------------------------------------------------- */

Test(export, linearization_eval_and_invert)
{
    double x[3] = {0, 0.5, 1}, v[3] = {1e6, 5e7, 2e9};
    hv_linearization *lin;
    cr_assert_eq(hv_linearization_create("youngs_modulus", "Pa", "stiff", x, v, 3, &lin), HV_OK,
                 "%s", hv_last_error());
    cr_assert_float_eq(hv_linearization_eval(lin, 0.25), 0.5 * (1e6 + 5e7), 1e-6);
    cr_assert_float_eq(hv_linearization_eval(lin, 0.75), 0.5 * (5e7 + 2e9), 1e-6);
    cr_assert_eq(hv_linearization_eval(lin, 0.5), 5e7);
    cr_assert_eq(hv_linearization_eval(lin, -1), 1e6);
    cr_assert_eq(hv_linearization_eval(lin, 2), 2e9);
    double f;
    cr_assert_eq(hv_linearization_invert(lin, 0.5 * (5e7 + 2e9), &f), HV_OK);
    cr_assert_float_eq(f, 0.75, 1e-12);
    cr_assert_eq(hv_linearization_invert(lin, 3e9, &f), HV_ERR_INVALID);
    cr_assert_str_eq(hv_linearization_material(lin), "stiff");
    cr_assert_str_eq(hv_linearization_unit(lin), "Pa");
    cr_assert_eq(hv_linearization_count(lin), 3);
    hv_linearization_destroy(lin);
    hv_linearization_destroy(NULL);

    double bumpy[3] = {1, 3, 2};
    cr_assert_eq(hv_linearization_create("e", NULL, "a", x, bumpy, 3, &lin), HV_OK);
    cr_assert_eq(hv_linearization_invert(lin, 2.5, &f), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "not strictly monotonic"), "%s", hv_last_error());
    hv_linearization_destroy(lin);

    double bad[3] = {0, 0.5, 0.5};
    cr_assert_eq(hv_linearization_create("e", NULL, "a", bad, v, 3, &lin), HV_ERR_INVALID);
    cr_assert_str_eq(hv_last_error(), "linearization of e: sample 3: fraction 0.5 is not greater "
                                      "than the previous (0.5)");
    cr_assert_null(lin);
    cr_assert_eq(hv_linearization_create("e", NULL, "a", x, v, 1, &lin), HV_ERR_INVALID);
    cr_assert_eq(hv_linearization_create("e f", NULL, "a", x, v, 3, &lin), HV_ERR_INVALID);
}

Test(export, linearization_csv)
{
    const char *good = "# stiffness of soft/stiff blends\r\n"
                       "\r\n"
                       " fraction.stiff , youngs_modulus[Pa]\r\n"
                       "0, 1e6\r\n"
                       "# a comment between rows\n"
                       "0.5 ,5e7\n"
                       "1,2e9";
    hv_linearization *lin;
    cr_assert_eq(hv_linearization_parse(good, strlen(good), "s.csv", "youngs_modulus", &lin),
                 HV_OK, "%s", hv_last_error());
    cr_assert_str_eq(hv_linearization_property(lin), "youngs_modulus");
    cr_assert_str_eq(hv_linearization_unit(lin), "Pa");
    cr_assert_str_eq(hv_linearization_material(lin), "stiff");
    cr_assert_eq(hv_linearization_count(lin), 3);
    cr_assert_float_eq(hv_linearization_eval(lin, 0.25), 0.5 * (1e6 + 5e7), 1e-6);
    hv_linearization_destroy(lin);

    struct {
        const char *text, *property, *message;
    } bad[] = {
        {"", NULL, "s.csv: empty: no header line 'fraction.<material>,<property>[<unit>]'"},
        {"stiff,e\n0,1\n1,2\n", NULL,
         "s.csv: line 1: header 'stiff,e' is not 'fraction.<material>,<property>[<unit>]' (property: 1-64 characters of [A-Za-z0-9_-]; unit: at most 32 bytes)"},
        {"fraction.a,e[Pa\n0,1\n1,2\n", NULL,
         "s.csv: line 1: header 'fraction.a,e[Pa' is not 'fraction.<material>,<property>[<unit>]' (property: 1-64 characters of [A-Za-z0-9_-]; unit: at most 32 bytes)"},
        {"fraction.a,e\n0,1\n0.5,x\n", NULL, "s.csv: line 3: e 'x' is not a finite number"},
        {"fraction.a,e\n0,1\n1,2,3\n", NULL, "s.csv: line 3: expected 2 comma-separated fields, got '1,2,3'"},
        {"fraction.a,e\n0,1\n# c\n0,2\n", NULL,
         "s.csv: line 4: fraction 0 is not greater than the previous (0)"},
        {"fraction.a,e\n0,1\n1.5,2\n", NULL, "s.csv: line 3: fraction 1.5 is outside [0, 1]"},
        {"fraction.a,e\n0.5,1\n", NULL, "s.csv: needs at least 2 samples (got 1)"},
        {"# c\nfraction.a,density\n0,1\n1,2\n", "youngs_modulus",
         "s.csv: line 2: the table is for 'density', not 'youngs_modulus'"},
        {"fraction.a,e\n0,nan\n1,2\n", NULL, "s.csv: line 2: e 'nan' is not a finite number"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        lin = (hv_linearization *)1;
        hv_status s = hv_linearization_parse(bad[i].text, strlen(bad[i].text), "s.csv",
                                             bad[i].property, &lin);
        cr_assert_eq(s, HV_ERR_BAD_INPUT, "case %zu", i);
        cr_assert_null(lin);
        cr_assert_str_eq(hv_last_error(), bad[i].message, "case %zu", i);
    }
    cr_assert_eq(hv_linearization_load("/nonexistent/s.csv", NULL, &lin), HV_ERR_IO);
}

/* ---- .vti -------------------------------------------------------------------------------- */

Test(export, vti_matches_model)
{
    hv_volume *v = make_model(1);
    hv_export_options o;
    hv_export_options_init(&o);
    hv_export_report r;
    const char *path = t_tmpfile("m.vti");
    cr_assert_eq(write(v, path, &o, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(r.format, HV_EXPORT_VTI);
    cr_assert_eq(r.arrays, 9);
    cr_assert_str_eq(r.notes, "");
    cr_assert_gt(r.file_bytes, 0u);
    struct stat st;
    cr_assert_eq(stat(path, &st), 0);
    cr_assert_eq((uint64_t)st.st_size, r.file_bytes);

    readback rb;
    read_back(path, &rb);
    cr_assert_eq(rb.narrays, 9);
    for (int i = 0; i < 9; ++i) cr_assert_str_eq(rb.names[i], EXPECTED_NAMES[i]);
    cr_assert_str_eq(rb.types[0], "unsigned char");
    cr_assert_str_eq(rb.types[1], "float");
    size_t n;
    double *dims = to_doubles(json_object_get(rb.doc, "dims"), &n);
    double *origin = to_doubles(json_object_get(rb.doc, "origin"), &n);
    double *spacing = to_doubles(json_object_get(rb.doc, "spacing"), &n);
    int nx = HI[0] - LO[0] + 1, ny = HI[1] - LO[1] + 1, nz = HI[2] - LO[2] + 1;
    cr_assert_eq((int)dims[0], nx);
    cr_assert_eq((int)dims[1], ny);
    cr_assert_eq((int)dims[2], nz);
    for (int a = 0; a < 3; ++a) {
        cr_assert_float_eq(spacing[a], VOX[a], 1e-12); /* anisotropic voxels */
        cr_assert_float_eq(origin[a], ORG[a] + LO[a] * VOX[a], 1e-12);
    }
    const json_t *field = json_object_get(rb.doc, "field");
    double *ilo = to_doubles(json_object_get(field, "hovox.index_lo"), &n);
    cr_assert_eq(n, 3u);
    for (int a = 0; a < 3; ++a) cr_assert_eq((int)ilo[a], LO[a]);
    const json_t *mj = json_object_get(field, "hovox.materials.json");
    cr_assert(json_is_string(mj));
    cr_assert(strstr(json_string_value(mj), "\"youngs_modulus\""));
    hv_material_table *back; /* the document itself, with its schema version */
    cr_assert_eq(hv_material_table_from_json(json_string_value(mj), &back), HV_OK, "%s", hv_last_error());
    cr_assert(strncmp(json_string_value(mj), "{\"schema\": 1, ", 14) == 0);
    hv_material_table_destroy(back);
    for (int i = 0; i < 9; ++i) cr_assert_eq(rb.sizes[i], (size_t)nx * ny * nz);

    const double *occ = array(&rb, "occupancy"), *fs = array(&rb, "fraction.soft"),
                 *fh = array(&rb, "fraction.stiff");
    long holes = 0;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                long idx = i + (long)nx * (j + (long)ny * k);
                int I = LO[0] + i, J = LO[1] + j, K = LO[2] + k;
                int in = occupied(I, J, K);
                holes += !in;
                cr_assert_eq((int)occ[idx], in, "occupancy at (%d,%d,%d)", I, J, K);
                double want[6] = {0, 0, 0, 0, 0, 0};
                if (in) expected_props(soft_at(I), stiff_at(I), want);
                cr_assert_eq(fs[idx], in ? (double)(float)soft_at(I) : 0.0);
                cr_assert_eq(fh[idx], in ? (double)(float)stiff_at(I) : 0.0);
                for (int q = 0; q < 6; ++q)
                    assert_rel(rb.arrays[3 + q][idx], want[q], 1e-6, EXPECTED_NAMES[3 + q], idx);
            }
    cr_assert_eq(holes, 3 * nz);
    free(dims);
    free(origin);
    free(spacing);
    free(ilo);
    readback_free(&rb);
    hv_volume_destroy(v);
}

/* Two-material mixture on a known voxel: the rule-of-mixtures formula written out. */
Test(export, rule_of_mixtures_two_materials)
{
    hv_volume *v = make_model(1);
    hv_export_options o;
    hv_export_options_init(&o);
    o.mix = HV_MIX_VOIGT;
    o.use_box = 1; /* the single voxel (7, 3, 0): stiff = 10/15 */
    for (int a = 0; a < 3; ++a) {
        int idx[3] = {7, 3, 0};
        o.box_lo[a] = o.box_hi[a] = ORG[a] + idx[a] * VOX[a];
    }
    const char *path = t_tmpfile("one.vti");
    cr_assert_eq(write(v, path, &o, NULL), HV_OK, "%s", hv_last_error());
    readback rb;
    read_back(path, &rb);
    cr_assert_eq(rb.narrays, 6);
    double p = (double)(float)(10.0 / 15.0), q = (double)(float)(5.0 / 15.0);
    cr_assert_eq(rb.sizes[0], 1u);
    assert_rel(array(&rb, "density.voigt[kg/m^3]")[0], q * 1100 + p * 1200, 1e-7, "rho", 0);
    assert_rel(array(&rb, "youngs_modulus.voigt[Pa]")[0], q * 1e6 + p * 2e9, 1e-7, "E", 0);
    assert_rel(array(&rb, "poisson_ratio.voigt[1]")[0], q * 0.49 + p * 0.35, 1e-7, "nu", 0);
    readback_free(&rb);

    o.mix = HV_MIX_REUSS;
    cr_assert_eq(write(v, path, &o, NULL), HV_OK, "%s", hv_last_error());
    read_back(path, &rb);
    assert_rel(array(&rb, "youngs_modulus.reuss[Pa]")[0], 1.0 / (q / 1e6 + p / 2e9), 1e-7, "E", 0);
    readback_free(&rb);
    hv_volume_destroy(v);
}

Test(export, linearization_table_array)
{
    hv_volume *v = make_model(1);
    double x[3] = {0, 0.5, 1}, val[3] = {1e6, 5e7, 2e9};
    hv_linearization *lin;
    cr_assert_eq(hv_linearization_create("youngs_modulus", NULL, "stiff", x, val, 3, &lin), HV_OK);
    hv_export_options o;
    hv_export_options_init(&o);
    o.mix = 0;
    const hv_linearization *tabs[1] = {lin};
    o.tables = tabs;
    o.ntables = 1;
    const char *path = t_tmpfile("lin.vti");
    hv_export_report r;
    cr_assert_eq(write(v, path, &o, &r), HV_OK, "%s", hv_last_error());
    cr_assert_str_eq(r.names, "occupancy,fraction.soft,fraction.stiff,youngs_modulus.table[Pa]");
    readback rb;
    read_back(path, &rb);
    const double *t = array(&rb, "youngs_modulus.table[Pa]"), *occ = array(&rb, "occupancy");
    int nx = HI[0] - LO[0] + 1;
    for (size_t idx = 0; idx < rb.sizes[0]; ++idx) {
        int I = LO[0] + (int)(idx % (size_t)nx);
        double f = stiff_at(I), want = 0;
        if (occ[idx] != 0) want = f <= 0.5 ? 1e6 + (f / 0.5) * (5e7 - 1e6)
                                            : 5e7 + ((f - 0.5) / 0.5) * (2e9 - 5e7);
        assert_rel(t[idx], want, 1e-6, "table", (long)idx);
    }
    readback_free(&rb);

    /* a table on a material the model does not have */
    hv_linearization *other;
    cr_assert_eq(hv_linearization_create("density", NULL, "glass", x, val, 3, &other), HV_OK);
    tabs[0] = other;
    cr_assert_eq(write(v, t_tmpfile("x.vti"), &o, NULL), HV_ERR_NOT_FOUND);
    cr_assert_str_eq(hv_last_error(), "linearization of density: material 'glass' is not in the "
                                      "model (materials: soft, stiff)");
    cr_assert(!t_exists(t_tmpfile("x.vti")));
    hv_linearization_destroy(other);
    hv_linearization_destroy(lin);
    hv_volume_destroy(v);
}

Test(export, box_beyond_model_and_no_materials)
{
    hv_volume *v = make_model(0);
    hv_export_options o;
    hv_export_options_init(&o);
    o.use_box = 1;
    /* index box [-5, 0] x [0, 3] x [6, 8]: partly outside the model */
    int lo[3] = {-5, 0, 6}, hi[3] = {0, 3, 8};
    for (int a = 0; a < 3; ++a) {
        o.box_lo[a] = ORG[a] + (lo[a] - 0.3) * VOX[a];
        o.box_hi[a] = ORG[a] + (hi[a] + 0.3) * VOX[a];
    }
    hv_export_report r;
    const char *path = t_tmpfile("box.vti");
    hv_status s = write(v, path, &o, &r);
    cr_assert_eq(s, HV_OK, "%d %s", s, hv_last_error());
    cr_assert_eq(r.materials, 0);
    cr_assert_str_eq(r.names, "occupancy");
    cr_assert_str_eq(r.notes, "the model has no material table: occupancy only\n");
    readback rb;
    read_back(path, &rb);
    cr_assert_eq(rb.narrays, 1);
    const double *occ = array(&rb, "occupancy");
    long ones = 0;
    int nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1;
    cr_assert_eq(rb.sizes[0], (size_t)(nx * ny * 3));
    for (size_t idx = 0; idx < rb.sizes[0]; ++idx) {
        int I = lo[0] + (int)(idx % (size_t)nx), J = lo[1] + (int)((idx / (size_t)nx) % (size_t)ny),
            K = lo[2] + (int)(idx / ((size_t)nx * ny));
        cr_assert_eq((int)occ[idx], occupied(I, J, K), "(%d,%d,%d)", I, J, K);
        ones += occupied(I, J, K);
    }
    cr_assert_eq(ones, 4 * 2 * 1); /* i in -3..0, j in 2..3, k = 6 */
    readback_free(&rb);

    /* a box between voxel centres */
    for (int a = 0; a < 3; ++a) o.box_lo[a] = o.box_hi[a] = ORG[a] + 0.5 * VOX[a];
    cr_assert_eq(write(v, path, &o, NULL), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "holds no voxel centre"), "%s", hv_last_error());
    hv_volume_destroy(v);
}

Test(export, bad_fractions_are_errors)
{
    hv_volume *v = make_model(1);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    int gs = hv_volume_grid_find(v, "material.soft"), gh = hv_volume_grid_find(v, "material.stiff");
    cr_assert_eq(hv_accessor_set_float(&acc, gs, 5, 6, 1, 0.25f), HV_OK);
    cr_assert_eq(hv_accessor_set_float(&acc, gh, 5, 6, 1, 0.25f), HV_OK);
    hv_export_options o;
    hv_export_options_init(&o);
    const char *path = t_tmpfile("bad.vti");
    cr_assert_eq(write(v, path, &o, NULL), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "voxel (5, 6, 1): material fractions sum to 0.5, not 1 "
                                      "(Wu eq. 12)");
    cr_assert(!t_exists(path));
    cr_assert_eq(write(v, t_tmpfile("bad.vtu"), &o, NULL), HV_ERR_BAD_INPUT);
    cr_assert(!t_exists(t_tmpfile("bad.vtu")));
    hv_volume_destroy(v);
}

/* ---- .vtu -------------------------------------------------------------------------------- */

static const int HEXV[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                               {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};

/* Check a .vtu against the model coarsened by N under a rule: expected cells, shared points,
 * VTK vertex order, averaged fractions and properties. */
static void check_vtu(const char *path, int N, int any, const int *blo, const int *bhi)
{
    readback rb;
    read_back(path, &rb);
    size_t np, nc, no;
    double *pts = to_doubles(json_object_get(rb.doc, "points"), &np);
    double *conn = to_doubles(json_object_get(rb.doc, "conn"), &nc);
    double *offs = to_doubles(json_object_get(rb.doc, "offsets"), &no);
    long ncells = (long)json_number_value(json_object_get(rb.doc, "ncells"));
    const json_t *ct = json_object_get(rb.doc, "celltypes");
    cr_assert_eq(json_array_size(ct), 1u);
    cr_assert_eq((int)json_number_value(json_array_get(ct, 0)), 12); /* VTK_HEXAHEDRON */
    cr_assert_eq(nc, (size_t)ncells * 8);
    cr_assert_eq(no, (size_t)ncells + 1);
    for (long c = 0; c <= ncells; ++c) cr_assert_eq((long)offs[c], 8 * c);
    cr_assert_eq(rb.narrays, 9);
    for (int i = 0; i < 9; ++i) cr_assert_str_eq(rb.names[i], EXPECTED_NAMES[i]);
    cr_assert_str_eq(rb.types[0], "float");

    /* expected coarse cells, by brute force over the analytic model */
    int clo[3], chi[3], cd[3];
    for (int a = 0; a < 3; ++a) {
        clo[a] = (int)floor((double)blo[a] / N);
        chi[a] = (int)floor((double)bhi[a] / N);
        cd[a] = chi[a] - clo[a] + 1;
    }
    int *seen = calloc((size_t)cd[0] * cd[1] * cd[2], sizeof *seen);
    long want_cells = 0;
    int *cnt = calloc((size_t)cd[0] * cd[1] * cd[2], sizeof *cnt);
    for (int ci = clo[0]; ci <= chi[0]; ++ci)
        for (int cj = clo[1]; cj <= chi[1]; ++cj)
            for (int ck = clo[2]; ck <= chi[2]; ++ck) {
                int c = 0;
                for (int i = ci * N; i < ci * N + N; ++i)
                    for (int j = cj * N; j < cj * N + N; ++j)
                        for (int k = ck * N; k < ck * N + N; ++k)
                            c += occupied(i, j, k) && i >= blo[0] && i <= bhi[0] && j >= blo[1] &&
                                 j <= bhi[1] && k >= blo[2] && k <= bhi[2];
                cnt[(ci - clo[0]) + cd[0] * ((cj - clo[1]) + cd[1] * (ck - clo[2]))] = c;
                want_cells += any ? c > 0 : 2 * c >= N * N * N;
            }
    cr_assert_eq(ncells, want_cells);

    /* points: each used corner once */
    long want_points = 0;
    for (int pi = clo[0]; pi <= chi[0] + 1; ++pi)
        for (int pj = clo[1]; pj <= chi[1] + 1; ++pj)
            for (int pk = clo[2]; pk <= chi[2] + 1; ++pk) {
                int used = 0;
                for (int e = 0; e < 8 && !used; ++e) {
                    int ci = pi - (e >> 2 & 1), cj = pj - (e >> 1 & 1), ck = pk - (e & 1);
                    if (ci < clo[0] || ci > chi[0] || cj < clo[1] || cj > chi[1] || ck < clo[2] ||
                        ck > chi[2])
                        continue;
                    int c = cnt[(ci - clo[0]) + cd[0] * ((cj - clo[1]) + cd[1] * (ck - clo[2]))];
                    used = any ? c > 0 : 2 * c >= N * N * N;
                }
                want_points += used;
            }
    cr_assert_eq((long)(np / 3), want_points);

    const double *occ = array(&rb, "occupancy"), *fs = array(&rb, "fraction.soft"),
                 *fh = array(&rb, "fraction.stiff");
    for (long c = 0; c < ncells; ++c) {
        /* the cell's lattice index from vertex 0, then every vertex in VTK order */
        const double *p0 = pts + 3 * (long)conn[8 * c];
        int ci[3];
        for (int a = 0; a < 3; ++a) {
            double u = ((p0[a] - ORG[a]) / VOX[a] + 0.5) / N;
            ci[a] = (int)lround(u);
            cr_assert_float_eq(u, ci[a], 1e-4);
        }
        for (int vtx = 0; vtx < 8; ++vtx) {
            const double *pv = pts + 3 * (long)conn[8 * c + vtx];
            for (int a = 0; a < 3; ++a)
                cr_assert_float_eq(pv[a], ORG[a] + ((ci[a] + HEXV[vtx][a]) * N - 0.5) * VOX[a],
                                   1e-4, "cell %ld vertex %d", c, vtx);
        }
        long slot = (ci[0] - clo[0]) + cd[0] * ((ci[1] - clo[1]) + cd[1] * (long)(ci[2] - clo[2]));
        cr_assert(ci[0] >= clo[0] && ci[0] <= chi[0] && ci[1] >= clo[1] && ci[1] <= chi[1] &&
                  ci[2] >= clo[2] && ci[2] <= chi[2]);
        cr_assert_eq(seen[slot]++, 0, "cell twice");
        int count = cnt[slot];
        cr_assert(any ? count > 0 : 2 * count >= N * N * N);
        assert_rel(occ[c], (double)count / (N * N * N), 1e-7, "occupancy", c);
        double ss = 0, sh = 0;
        for (int i = ci[0] * N; i < ci[0] * N + N; ++i)
            for (int j = ci[1] * N; j < ci[1] * N + N; ++j)
                for (int k = ci[2] * N; k < ci[2] * N + N; ++k)
                    if (occupied(i, j, k) && i >= blo[0] && i <= bhi[0] && j >= blo[1] &&
                        j <= bhi[1] && k >= blo[2] && k <= bhi[2]) {
                        ss += soft_at(i);
                        sh += stiff_at(i);
                    }
        ss /= count;
        sh /= count;
        assert_rel(fs[c], ss, 1e-6, "fraction.soft", c);
        assert_rel(fh[c], sh, 1e-6, "fraction.stiff", c);
        double want[6];
        expected_props(ss, sh, want);
        for (int q = 0; q < 6; ++q) assert_rel(rb.arrays[3 + q][c], want[q], 1e-5, EXPECTED_NAMES[3 + q], c);
    }
    free(seen);
    free(cnt);
    free(pts);
    free(conn);
    free(offs);
    readback_free(&rb);
}

Test(export, vtu_one_hex_per_voxel)
{
    hv_volume *v = make_model(1);
    hv_export_options o;
    hv_export_options_init(&o);
    hv_export_report r;
    const char *path = t_tmpfile("m.vtu");
    cr_assert_eq(write(v, path, &o, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(r.format, HV_EXPORT_VTU);
    cr_assert_eq(r.cells, r.occupied);
    cr_assert_eq(r.occupied, 16u * 8 * 12 - 3 * 12);
    check_vtu(path, 1, 0, LO, HI);
    hv_volume_destroy(v);
}

Test(export, vtu_coarsened_majority_and_any)
{
    hv_volume *v = make_model(1);
    hv_export_options o;
    hv_export_options_init(&o);
    const char *path = t_tmpfile("c.vtu");
    for (int N = 2; N <= 3; ++N) {
        o.coarsen = N;
        o.coarsen_rule = HV_COARSEN_MAJORITY;
        cr_assert_eq(write(v, path, &o, NULL), HV_OK, "%s", hv_last_error());
        check_vtu(path, N, 0, LO, HI);
        o.coarsen_rule = HV_COARSEN_ANY;
        cr_assert_eq(write(v, path, &o, NULL), HV_OK, "%s", hv_last_error());
        check_vtu(path, N, 1, LO, HI);
    }
    /* with a box cutting through blocks: voxels outside count as empty */
    o.coarsen = 2;
    o.use_box = 1;
    int blo[3] = {0, 3, -4}, bhi[3] = {6, 8, 2};
    for (int a = 0; a < 3; ++a) {
        o.box_lo[a] = ORG[a] + blo[a] * VOX[a];
        o.box_hi[a] = ORG[a] + bhi[a] * VOX[a];
    }
    cr_assert_eq(write(v, path, &o, NULL), HV_OK, "%s", hv_last_error());
    check_vtu(path, 2, 1, blo, bhi);
    /* .vti cannot be coarsened */
    cr_assert_eq(write(v, t_tmpfile("c.vti"), &o, NULL), HV_ERR_INVALID);
    hv_volume_destroy(v);
}

/* ---- output discipline ------------------------------------------------------------------ */

static int count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    cr_assert_not_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) ++n;
    closedir(d);
    return n;
}

Test(export, unwritable_paths_leave_nothing)
{
    hv_volume *v = make_model(1);
    hv_export_options o;
    hv_export_options_init(&o);
    cr_assert_eq(write(v, "/nonexistent-dir/x.vti", &o, NULL), HV_ERR_IO);
    cr_assert_str_eq(hv_last_error(), "/nonexistent-dir/x.vti: cannot write: No such file or "
                                      "directory");
    /* the final name is a directory: the rename fails after the write; no temporary stays */
    char dir[600], target[700];
    snprintf(dir, sizeof dir, "%s", t_tmpfile("out"));
    cr_assert_eq(mkdir(dir, 0777), 0);
    snprintf(target, sizeof target, "%s/x.vtu", dir);
    cr_assert_eq(mkdir(target, 0777), 0);
    cr_assert_eq(write(v, target, &o, NULL), HV_ERR_IO);
    cr_assert(strstr(hv_last_error(), "cannot rename into place"), "%s", hv_last_error());
    cr_assert_eq(count_entries(dir), 1);
    cr_assert_eq(count_entries(target), 0);
    /* unknown extension */
    cr_assert_eq(write(v, t_tmpfile("x.vtk"), &o, NULL), HV_ERR_INVALID);
    hv_volume_destroy(v);
}

static int cancel_at(void *user, const char *stage, double f)
{
    (void)f;
    return strcmp(stage, (const char *)user) == 0;
}

Test(export, cancel_leaves_nothing)
{
    hv_volume *v = make_model(1);
    hv_export_options o;
    hv_export_options_init(&o);
    char dir[600], path[700];
    snprintf(dir, sizeof dir, "%s", t_tmpfile("cancel"));
    cr_assert_eq(mkdir(dir, 0777), 0);
    const char *stages[] = {"export write", "export fill", "export cells"};
    const char *files[] = {"x.vti", "x.vti", "x.vtu"};
    for (int i = 0; i < 3; ++i) {
        hv_progress p = {cancel_at, (void *)stages[i]};
        o.progress = &p;
        snprintf(path, sizeof path, "%s/%s", dir, files[i]);
        cr_assert_eq(write(v, path, &o, NULL), HV_ERR_CANCELLED, "%s: %s", stages[i],
                     hv_last_error());
        cr_assert_eq(count_entries(dir), 0, "%s", stages[i]);
    }
    hv_volume_destroy(v);
}

Test(export, memory_budget)
{
    hv_volume *v = make_model(1);
    hv_export_options o;
    hv_export_options_init(&o);
    o.max_memory = 4096;
    hv_export_report r;
    cr_assert_eq(hv_export_plan(v, "p.vti", &o, &r), HV_OK, "%s", hv_last_error());
    /* 16 x 8 x 12 points x (1 + 4 * 8) bytes */
    cr_assert_eq(r.memory_bytes, 16u * 8 * 12 * 33);
    cr_assert_eq(r.points, 16u * 8 * 12);
    cr_assert_eq(write(v, t_tmpfile("big.vti"), &o, NULL), HV_ERR_LIMIT);
    cr_assert_str_eq(hv_last_error(), "export: the image of 16 x 8 x 12 points x 9 arrays needs "
                                      "49.5 KiB, more than the limit of 4.0 KiB (max_memory); "
                                      "export a smaller box or a .vtu");
    cr_assert_eq(write(v, t_tmpfile("big.vtu"), &o, NULL), HV_ERR_LIMIT);
    cr_assert(!t_exists(t_tmpfile("big.vti")));
    cr_assert(!t_exists(t_tmpfile("big.vtu")));
    hv_volume_destroy(v);
}

Test(export, same_bytes_for_any_thread_count)
{
    hv_volume *v = make_model(1);
    hv_export_options o;
    hv_export_options_init(&o);
    const char *ext[2] = {"vti", "vtu"};
    for (int e = 0; e < 2; ++e) {
        char a[600], b[600], cmd[1400];
        snprintf(a, sizeof a, "%s", t_tmpfile(e ? "t1.vtu" : "t1.vti"));
        snprintf(b, sizeof b, "%s", t_tmpfile(e ? "t3.vtu" : "t3.vti"));
        hv_set_threads(1);
        cr_assert_eq(write(v, a, &o, NULL), HV_OK, "%s", hv_last_error());
        hv_set_threads(3);
        cr_assert_eq(write(v, b, &o, NULL), HV_OK, "%s", hv_last_error());
        hv_set_threads(0);
        snprintf(cmd, sizeof cmd, "cmp -s '%s' '%s'", a, b);
        cr_assert_eq(t_run(cmd, NULL), 0, "%s files differ across thread counts", ext[e]);
    }
    hv_volume_destroy(v);
}

Test(export, left_out_properties_are_noted)
{
    hv_volume *v = make_model(1);
    hv_material_table *t;
    cr_assert_eq(hv_material_table_load(v, &t), HV_OK);
    /* a key only the second material has, and a zero value the inverse rule cannot take */
    cr_assert_eq(hv_material_set_property(t, 1, "hardness", 80, "ShoreA"), HV_OK);
    cr_assert_eq(hv_material_set_property(t, 0, "poisson_ratio", 0, "1"), HV_OK);
    cr_assert_eq(hv_material_table_store(v, t), HV_OK);
    hv_material_table_destroy(t);
    hv_export_options o;
    hv_export_options_init(&o);
    hv_export_report r;
    cr_assert_eq(hv_export_plan(v, "x.vtu", &o, &r), HV_OK, "%s", hv_last_error());
    cr_assert_str_eq(r.names, "occupancy,fraction.soft,fraction.stiff,density.voigt[kg/m^3],"
                              "density.reuss[kg/m^3],youngs_modulus.voigt[Pa],"
                              "youngs_modulus.reuss[Pa],poisson_ratio.voigt[1]");
    cr_assert_str_eq(r.notes, "'poisson_ratio.reuss' left out: the inverse rule needs positive "
                              "values ('soft' has 0)\n"
                              "property 'hardness' left out: material 'soft' has no value\n");
    hv_volume_destroy(v);
}
