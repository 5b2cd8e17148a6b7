/* tests/material/test_field.c - field features (issue 18): an analytic field f = x + 2y written
 * here as VTK XML text (.vti image data, .vtu hexahedra: an independent writer) and as a .vdb
 * float grid, read back at the voxel centres; the graded fractions must be the grading formula
 * evaluated on the analytic field. Bad fields are refused with one message each. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"
#include "support/support.h"

static double field(double x, double y) { return x + 2 * y; }

/* Image data over [x0, x0 + (nx-1) h] x ..., spacing h (not the voxel size: trilinear sampling
 * between the points is exercised, exact for a linear field). */
static void write_vti(const char *path, double x0, double y0, double z0, int nx, int ny, int nz, double h)
{
    FILE *fp = fopen(path, "w");
    cr_assert_not_null(fp);
    fprintf(fp, "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                "<ImageData WholeExtent=\"0 %d 0 %d 0 %d\" Origin=\"%.17g %.17g %.17g\" Spacing=\"%.17g %.17g %.17g\">\n"
                "<Piece Extent=\"0 %d 0 %d 0 %d\">\n<PointData Scalars=\"f\">\n",
            nx - 1, ny - 1, nz - 1, x0, y0, z0, h, h, h, nx - 1, ny - 1, nz - 1);
    fprintf(fp, "<DataArray type=\"Float64\" Name=\"f\" format=\"ascii\">\n");
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) fprintf(fp, "%.17g\n", field(x0 + i * h, y0 + j * h));
    fprintf(fp, "</DataArray>\n<DataArray type=\"Float32\" Name=\"vec\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for (int q = 0; q < nx * ny * nz; ++q) fprintf(fp, "1 2 3\n");
    fprintf(fp, "</DataArray>\n</PointData>\n<CellData>\n</CellData>\n</Piece>\n</ImageData>\n</VTKFile>\n");
    fclose(fp);
}

/* One hexahedron per cell of a regular grid, point data f and cell data fc (f at the centre). */
static void write_vtu(const char *path, double x0, double y0, double z0, int nx, int ny, int nz, double h)
{
    FILE *fp = fopen(path, "w");
    cr_assert_not_null(fp);
    int np = (nx + 1) * (ny + 1) * (nz + 1), nc = nx * ny * nz;
    fprintf(fp, "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
                "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"%d\" NumberOfCells=\"%d\">\n"
                "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n", np, nc);
    for (int k = 0; k <= nz; ++k)
        for (int j = 0; j <= ny; ++j)
            for (int i = 0; i <= nx; ++i) fprintf(fp, "%.17g %.17g %.17g\n", x0 + i * h, y0 + j * h, z0 + k * h);
    fprintf(fp, "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
#define P(i, j, k) (((k) * (ny + 1) + (j)) * (nx + 1) + (i))
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                fprintf(fp, "%d %d %d %d %d %d %d %d\n", P(i, j, k), P(i + 1, j, k), P(i + 1, j + 1, k), P(i, j + 1, k),
                        P(i, j, k + 1), P(i + 1, j, k + 1), P(i + 1, j + 1, k + 1), P(i, j + 1, k + 1));
#undef P
    fprintf(fp, "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for (int c = 1; c <= nc; ++c) fprintf(fp, "%d\n", 8 * c);
    fprintf(fp, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for (int c = 0; c < nc; ++c) fprintf(fp, "12\n");
    fprintf(fp, "</DataArray>\n</Cells>\n<PointData>\n<DataArray type=\"Float64\" Name=\"f\" format=\"ascii\">\n");
    for (int k = 0; k <= nz; ++k)
        for (int j = 0; j <= ny; ++j)
            for (int i = 0; i <= nx; ++i) fprintf(fp, "%.17g\n", field(x0 + i * h, y0 + j * h));
    fprintf(fp, "</DataArray>\n</PointData>\n<CellData>\n<DataArray type=\"Float64\" Name=\"fc\" format=\"ascii\">\n");
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) fprintf(fp, "%.17g\n", field(x0 + (i + 0.5) * h, y0 + (j + 0.5) * h));
    fprintf(fp, "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    fclose(fp);
}

/* A 20 x 10 x 6 box at 0.5 mm voxels (its skin reaches about a voxel beyond the box). */
static hv_volume *box_model(void)
{
    double lo[3] = {0, 0, 0}, hi[3] = {20, 10, 6};
    hv_mesh *mesh;
    cr_assert_eq(hv_generate_box(lo, hi, &mesh), HV_OK);
    hv_voxelize_options vo;
    hv_voxelize_options_init(&vo);
    vo.voxel_size[0] = vo.voxel_size[1] = vo.voxel_size[2] = 0.5;
    hv_volume *v;
    cr_assert_eq(hv_voxelize(mesh, &vo, &v), HV_OK, "%s", hv_last_error());
    hv_mesh_destroy(mesh);
    return v;
}

/* Grade with the field (d- = 4, dg = 30, f = d/dg, A -> B) and compare every voxel's fraction of
 * B with the formula on the analytic field at the voxel centre. Returns the worst error. */
static double grade_and_check(hv_volume *model, hv_frf *frf, double (*want_d)(double, double, double))
{
    hv_material_table *t;
    cr_assert_eq(hv_material_table_create(&t), HV_OK);
    cr_assert_eq(hv_material_add(t, "A", NULL, NULL), HV_OK);
    cr_assert_eq(hv_material_add(t, "B", NULL, NULL), HV_OK);
    hv_dfn *f;
    cr_assert_eq(hv_dfn_expr("d/dg", &f), HV_OK);
    double ms[2] = {1, 0}, me[2] = {0, 1};
    hv_ags_desc d = {frf, 4, 30, 0, f, ms, me, 2, NULL};
    hv_ags *a;
    cr_assert_eq(hv_ags_create(&d, &a), HV_OK, "%s", hv_last_error());
    hv_object *o;
    cr_assert_eq(hv_object_create(model, "occupancy", 2, &o), HV_OK);
    cr_assert_eq(hv_object_add_ags(o, a), HV_OK);
    hv_volume *out;
    cr_assert_eq(hv_object_evaluate(o, t, 0, NULL, &out), HV_OK, "%s", hv_last_error());
    hv_transform xf = hv_volume_get_transform(out);
    int gb = hv_material_grid(out, t, 1);
    const int32_t *org = hv_volume_leaf_origins(out);
    double worst = 0;
    size_t n = 0;
    for (size_t l = 0; l < hv_volume_leaf_count(out); ++l) {
        const uint64_t *mask = hv_volume_leaf_mask(out, l);
        for (unsigned q = 0; q < HV_LEAF_SIZE; ++q) {
            if (!HV_BIT_GET(mask, q)) continue;
            double p[3] = {xf.origin[0] + (org[3 * l] + (int)(q >> 6)) * xf.voxel[0],
                           xf.origin[1] + (org[3 * l + 1] + (int)((q >> 3) & 7)) * xf.voxel[1],
                           xf.origin[2] + (org[3 * l + 2] + (int)(q & 7)) * xf.voxel[2]};
            double dd = want_d(p[0], p[1], p[2]);
            double want = fmin(fmax((dd - 4) / 30, 0.0), 1.0);
            worst = fmax(worst, fabs(hv_volume_leaf_float_c(out, gb, l)[q] - want));
            ++n;
        }
    }
    cr_assert_gt(n, 5000);
    hv_volume_destroy(out);
    hv_object_destroy(o);
    hv_ags_release(a);
    hv_dfn_destroy(f);
    hv_material_table_destroy(t);
    return worst;
}

static double exact(double x, double y, double z)
{
    (void)z;
    return field(x, y);
}

Test(field, analytic_vti_reproduces_the_formula)
{
    hv_volume *model = box_model();
    const char *path = t_tmpfile("f.vti");
    write_vti(path, -2.1, -1.9, -1.7, 36, 21, 15, 0.7); /* covers the model with its skin */
    hv_frf *frf;
    cr_assert_eq(hv_frf_field_file(model, NULL, path, "f", HV_FIELD_REFUSE, &frf), HV_OK, "%s", hv_last_error());
    hv_field_report r;
    cr_assert(hv_frf_field_report(frf, &r));
    cr_assert_eq(r.filled, 0);
    cr_assert_float_eq(r.file_lo, field(-2.1, -1.9), 1e-9);
    cr_assert(r.lo < 0 && r.lo >= r.file_lo && r.hi <= r.file_hi && r.hi > 40, "range %g %g", r.lo, r.hi);
    double worst = grade_and_check(model, frf, exact);
    cr_assert(worst < 2e-5, "worst fraction error %g", worst);
    hv_frf_release(frf);
    hv_volume_destroy(model);
}

Test(field, vtu_point_and_cell_data)
{
    hv_volume *model = box_model();
    const char *path = t_tmpfile("f.vtu");
    write_vtu(path, -2, -2, -2, 12, 7, 5, 2.0);
    hv_frf *frf;
    cr_assert_eq(hv_frf_field_file(model, NULL, path, "f", HV_FIELD_REFUSE, &frf), HV_OK, "%s", hv_last_error());
    double worst = grade_and_check(model, frf, exact); /* hexahedra interpolate a linear field exactly */
    cr_assert(worst < 2e-5, "point data: worst fraction error %g", worst);
    hv_frf_release(frf);
    cr_assert_eq(hv_frf_field_file(model, NULL, path, "fc", HV_FIELD_REFUSE, &frf), HV_OK, "%s", hv_last_error());
    /* cell data: the cell's value, f at the centre of the 2 mm cell holding the voxel: within
     * (1 + 2) * 1 mm of the point's f, so within 3/30 in fraction, and not exact */
    worst = grade_and_check(model, frf, exact);
    cr_assert(worst <= 0.1 + 1e-6 && worst > 0.01, "cell data: worst fraction error %g", worst);
    hv_frf_release(frf);
    hv_volume_destroy(model);
}

Test(field, vdb_float_grid)
{
    hv_volume *model = box_model();
    /* a float grid on a coarser lattice (1 mm voxels), f = x + 2y at its voxel centres */
    hv_transform xf = {{1, 1, 1}, {0.5, 0.5, 0.5}};
    hv_volume *v;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    int lo[3] = {-3, -3, -3}, hi[3] = {22, 12, 8};
    cr_assert_eq(t_add_box(v, lo, hi), HV_OK);
    int g;
    cr_assert_eq(hv_volume_grid_add(v, "sigma", HV_GRID_FLOAT, &g), HV_OK);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    for (int i = lo[0]; i <= hi[0]; ++i)
        for (int j = lo[1]; j <= hi[1]; ++j)
            for (int k = lo[2]; k <= hi[2]; ++k)
                cr_assert_eq(hv_accessor_set_float(&acc, g, i, j, k, (float)field(0.5 + i, 0.5 + j)), HV_OK);
    const char *path = t_tmpfile("f.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
    hv_volume_destroy(v);
    hv_frf *frf;
    cr_assert_eq(hv_frf_field_file(model, NULL, path, "sigma", HV_FIELD_REFUSE, &frf), HV_OK, "%s", hv_last_error());
    double worst = grade_and_check(model, frf, exact);
    cr_assert(worst < 2e-5, "worst fraction error %g", worst);
    hv_frf_release(frf);
    cr_assert_eq(hv_frf_field_file(model, NULL, path, "tau", HV_FIELD_REFUSE, &frf), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "no float grid 'tau' (float grids: sigma)"), "%s", hv_last_error());
    hv_volume_destroy(model);
}

/* Half the model outside the field: refused with the count, or filled from the nearest covered
 * voxel (for f = x + 2y cut at x = xc, the nearest covered value along x keeps y: f(xc', y)). */
Test(field, uncovered_voxels_are_refused_or_filled)
{
    hv_volume *model = box_model();
    const char *path = t_tmpfile("half.vti");
    write_vti(path, -2.1, -1.9, -1.7, 15, 21, 15, 0.7); /* x up to 7.7 */
    hv_frf *frf = NULL;
    cr_assert_eq(hv_frf_field_file(model, NULL, path, "f", HV_FIELD_REFUSE, &frf), HV_ERR_BAD_INPUT);
    cr_assert_null(frf);
    cr_assert(strstr(hv_last_error(), "lie outside it"), "%s", hv_last_error());
    cr_assert_eq(hv_frf_field_file(model, NULL, path, "f", HV_FIELD_NEAREST, &frf), HV_OK, "%s", hv_last_error());
    hv_field_report r;
    cr_assert(hv_frf_field_report(frf, &r));
    cr_assert_gt(r.filled, r.voxels / 3);
    double p[3] = {15.25, 5.25, 3.25}, d;
    cr_assert_eq(hv_frf_distance(frf, model, p, &d), HV_OK);
    cr_assert_float_eq(d, field(7.25, 5.25), 1e-4, "filled value %g", d); /* last covered voxel centre x = 7.25 */
    hv_frf_release(frf);
    hv_volume_destroy(model);
}

Test(field, bad_fields_one_message_each)
{
    hv_volume *model = box_model();
    const char *path = t_tmpfile("g.vti");
    write_vti(path, -2.1, -1.9, -1.7, 36, 21, 15, 0.7);
    hv_frf *frf = NULL;
    cr_assert_eq(hv_frf_field_file(model, NULL, path, "sigma", HV_FIELD_REFUSE, &frf), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "no array 'sigma' (arrays: f (point), vec (point))"), "%s", hv_last_error());
    cr_assert_eq(hv_frf_field_file(model, NULL, path, "vec", HV_FIELD_REFUSE, &frf), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "array 'vec' has 3 components; a field feature needs a scalar (1)"), "%s",
              hv_last_error());
    const char *far = t_tmpfile("far.vti");
    write_vti(far, 100, 100, 100, 5, 5, 5, 1);
    cr_assert_eq(hv_frf_field_file(model, NULL, far, "f", HV_FIELD_NEAREST, &frf), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "covers none of the model's"), "%s", hv_last_error());
    cr_assert_eq(hv_frf_field_file(model, NULL, t_tmpfile("missing.vti"), "f", HV_FIELD_REFUSE, &frf), HV_ERR_IO);
    const char *junk = t_tmpfile("junk.vti");
    FILE *fp = fopen(junk, "w");
    fputs("not xml at all\n", fp);
    fclose(fp);
    cr_assert_eq(hv_frf_field_file(model, NULL, junk, "f", HV_FIELD_REFUSE, &frf), HV_ERR_BAD_INPUT);
    cr_assert_eq(hv_frf_field_file(model, NULL, "x.nrrd", "f", HV_FIELD_REFUSE, &frf), HV_ERR_UNSUPPORTED);
    cr_assert_null(frf);
    hv_volume_destroy(model);
}

/* A field given as an array (hv_frf_field_grid) is the same field as the same samples written to a
 * .vti (point data): bit for bit here, where every voxel centre has cell coordinates that are binary
 * fractions; the report gives the array's range; voxels outside follow the rule; bad arrays are
 * refused. */
Test(field, array_equals_the_same_samples_in_a_vti)
{
    hv_volume *model = box_model(); /* 0.5 mm voxels: centres at (n + 1/2) 0.5 */
    int nx = 48, ny = 28, nz = 20;
    double x0 = -2.125, y0 = -2.125, z0 = -2.125, h = 0.5;
    double *vals = malloc(sizeof(double) * (size_t)(nx * ny * nz));
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j)
            for (int k = 0; k < nz; ++k)
                vals[(i * ny + j) * nz + k] = field(x0 + i * h, y0 + j * h) + 0.37 * sin(1.3 * i + 0.7 * j * k);
    const char *path = t_tmpfile("a.vti");
    FILE *fp = fopen(path, "w");
    cr_assert_not_null(fp);
    fprintf(fp, "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                "<ImageData WholeExtent=\"0 %d 0 %d 0 %d\" Origin=\"%.17g %.17g %.17g\" Spacing=\"%.17g %.17g %.17g\">\n"
                "<Piece Extent=\"0 %d 0 %d 0 %d\">\n<PointData Scalars=\"f\">\n"
                "<DataArray type=\"Float64\" Name=\"f\" format=\"ascii\">\n",
            nx - 1, ny - 1, nz - 1, x0, y0, z0, h, h, h, nx - 1, ny - 1, nz - 1);
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) fprintf(fp, "%.17g\n", vals[(i * ny + j) * nz + k]);
    fprintf(fp, "</DataArray>\n</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n");
    fclose(fp);
    hv_frf *ff, *fa;
    cr_assert_eq(hv_frf_field_file(model, NULL, path, "f", HV_FIELD_REFUSE, &ff), HV_OK, "%s", hv_last_error());
    hv_field_grid g = {vals, 1, {nx, ny, nz}, {h, h, h}, {x0, y0, z0}};
    cr_assert_eq(hv_frf_field_grid(model, NULL, &g, "f", HV_FIELD_REFUSE, &fa), HV_OK, "%s", hv_last_error());
    hv_field_report rf, ra;
    cr_assert(hv_frf_field_report(ff, &rf) && hv_frf_field_report(fa, &ra));
    cr_assert(ra.file_lo == rf.file_lo && ra.file_hi == rf.file_hi && ra.lo == rf.lo && ra.hi == rf.hi);
    cr_assert_eq(ra.voxels, rf.voxels);
    cr_assert_str_eq(hv_frf_describe(fa), "field(f)");
    double *xyz;
    size_t n;
    cr_assert_eq(hv_volume_centres(model, "occupancy", &xyz, &n), HV_OK);
    for (size_t i = 0; i < n; i += 3) {
        double da, df;
        cr_assert_eq(hv_frf_distance(fa, model, xyz + 3 * i, &da), HV_OK);
        cr_assert_eq(hv_frf_distance(ff, model, xyz + 3 * i, &df), HV_OK);
        cr_assert(da == df, "voxel %zu: array %.9g, file %.9g", i, da, df);
    }
    free(xyz);
    hv_frf_release(fa);
    /* float values, a partial array: refused, then filled by the nearest rule */
    float *v32 = malloc(sizeof(float) * (size_t)(nx * ny * nz));
    for (int q = 0; q < nx * ny * nz; ++q) v32[q] = (float)vals[q];
    hv_field_grid part = {v32, 0, {nx / 2, ny, nz}, {h, h, h}, {x0, y0, z0}};
    cr_assert_eq(hv_frf_field_grid(model, NULL, &part, NULL, HV_FIELD_REFUSE, &fa), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "array covers ") && strstr(hv_last_error(), "lie outside it"), "%s",
              hv_last_error());
    cr_assert_eq(hv_frf_field_grid(model, NULL, &part, NULL, HV_FIELD_NEAREST, &fa), HV_OK, "%s", hv_last_error());
    cr_assert(hv_frf_field_report(fa, &ra) && ra.filled > 0 && ra.filled < ra.voxels);
    hv_frf_release(fa);
    v32[5] = NAN;
    cr_assert_eq(hv_frf_field_grid(model, NULL, &part, "s", HV_FIELD_NEAREST, &fa), HV_ERR_INVALID);
    cr_assert(strstr(hv_last_error(), "field s: the value at [0, 0, 5] is nan"), "%s", hv_last_error());
    hv_field_grid bad = {vals, 1, {nx, 0, nz}, {h, h, h}, {x0, y0, z0}};
    cr_assert_eq(hv_frf_field_grid(model, NULL, &bad, NULL, HV_FIELD_REFUSE, &fa), HV_ERR_INVALID);
    bad.dims[1] = ny;
    bad.spacing[2] = 0;
    cr_assert_eq(hv_frf_field_grid(model, NULL, &bad, NULL, HV_FIELD_REFUSE, &fa), HV_ERR_INVALID);
    bad.spacing[2] = h;
    cr_assert_eq(hv_frf_field_grid(model, "nope", &bad, NULL, HV_FIELD_REFUSE, &fa), HV_ERR_NOT_FOUND);
    free(v32);
    free(vals);
    hv_frf_release(ff);
    hv_volume_destroy(model);
}
