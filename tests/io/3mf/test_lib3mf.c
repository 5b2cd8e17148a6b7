/* tests/io/3mf/test_lib3mf.c - an independent reader opens hovox's 3MF Volumetric packages: lib3mf
 * 1.8 (Debian lib3mf-dev, the 3MF Consortium's library; it predates the Volumetric extension, so it
 * reads the core mesh and must pass over the rest without error or warning). Its C API is declared
 * here (its headers are C++ only); the types follow lib3mf's NMR_WinTypes.h for GCC. Its library
 * knows no Volumetric element (no image3d, functionfromimage3d or color in lib3MF.so.1.8.1; the
 * MODELEXTENSION_VOLUMETRIC of its NMR_ModelTypes.h is an unused enum value), so the colour's part
 * of a package is checked by hand in test_volumetric.c. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "hovox/export.h"
#include "hovox/material.h"
#include "support/support.h"

typedef unsigned int LIB3MFRESULT; /* HRESULT */
typedef void L3;                   /* every lib3mf handle */
typedef struct {
    float m_fPosition[3];
} l3_vertex;
typedef struct {
    unsigned m_nIndices[3];
} l3_triangle;
extern LIB3MFRESULT lib3mf_createmodel(L3 **model);
extern LIB3MFRESULT lib3mf_release(L3 *instance);
extern LIB3MFRESULT lib3mf_getlasterror(L3 *instance, unsigned *code, const char **message);
extern LIB3MFRESULT lib3mf_model_queryreader(L3 *model, const char *kind, L3 **reader);
extern LIB3MFRESULT lib3mf_reader_readfromfileutf8(L3 *reader, const char *path);
extern LIB3MFRESULT lib3mf_reader_getwarningcount(L3 *reader, unsigned *count);
extern LIB3MFRESULT lib3mf_model_getmeshobjects(L3 *model, L3 **iterator);
extern LIB3MFRESULT lib3mf_model_getbasematerials(L3 *model, L3 **iterator);
extern LIB3MFRESULT lib3mf_resourceiterator_movenext(L3 *iterator, int *has_next);
extern LIB3MFRESULT lib3mf_resourceiterator_getcurrent(L3 *iterator, L3 **resource);
extern LIB3MFRESULT lib3mf_meshobject_getvertexcount(L3 *mesh, unsigned *count);
extern LIB3MFRESULT lib3mf_meshobject_gettrianglecount(L3 *mesh, unsigned *count);
extern LIB3MFRESULT lib3mf_meshobject_getvertices(L3 *mesh, l3_vertex *vertices, unsigned size, unsigned *count);
extern LIB3MFRESULT lib3mf_meshobject_gettriangleindices(L3 *mesh, l3_triangle *indices, unsigned size, unsigned *count);
extern LIB3MFRESULT lib3mf_basematerial_getcount(L3 *group, unsigned *count);
extern LIB3MFRESULT lib3mf_basematerial_getnameutf8(L3 *group, unsigned index, char *buffer, unsigned size,
                                                    unsigned *needed);
extern LIB3MFRESULT lib3mf_basematerial_getdisplaycolor(L3 *group, unsigned index, unsigned char *r, unsigned char *g,
                                                        unsigned char *b, unsigned char *a);

/* A 5 x 3 x 4 box of 0.25 mm voxels at origin (-1, 2, 0.5) with one voxel missing from a face
 * (a dent), two materials in a gradient along x. */
enum { NX = 5, NY = 3, NZ = 4 };
static hv_volume *make_box(void)
{
    hv_transform xf = {{0.25, 0.25, 0.25}, {-1, 2, 0.5}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK, "%s", hv_last_error());
    int lo[3] = {0, 0, 0}, hi[3] = {NX - 1, NY - 1, NZ - 1};
    cr_assert_eq(t_add_box(v, lo, hi), HV_OK);
    int og, ga, gb;
    hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &og);
    hv_volume_grid_add(v, "material.rigid", HV_GRID_FLOAT, &ga);
    hv_volume_grid_add(v, "material.rubber", HV_GRID_FLOAT, &gb);
    const int32_t *orig = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned n = 0; n < 512; ++n) {
            if (!HV_BIT_GET(hv_volume_leaf_mask(v, l), n)) continue;
            int i = orig[3 * l] + (int)(n >> 6), j = orig[3 * l + 1] + (int)((n >> 3) & 7), k = orig[3 * l + 2] + (int)(n & 7);
            if (i == 2 && j == 0 && k == NZ - 1) continue; /* the dent */
            hv_volume_leaf_bool(v, og, l)[n >> 6] |= 1ull << (n & 63);
            hv_volume_leaf_float(v, ga, l)[n] = (float)i / (NX - 1);
            hv_volume_leaf_float(v, gb, l)[n] = 1.0f - (float)i / (NX - 1);
        }
    hv_material_table *t;
    hv_material_table_create(&t);
    const float red[4] = {1, 0, 0, 1}, blue[4] = {0, 0, 1, 1};
    hv_material_add(t, "rigid", red, NULL);
    hv_material_add(t, "rubber", blue, NULL);
    hv_material_table_store(v, t);
    hv_material_table_destroy(t);
    return v;
}

static L3 *read_3mf(const char *path)
{
    L3 *model = NULL, *reader = NULL;
    cr_assert_eq(lib3mf_createmodel(&model), 0);
    cr_assert_eq(lib3mf_model_queryreader(model, "3mf", &reader), 0);
    LIB3MFRESULT rc = lib3mf_reader_readfromfileutf8(reader, path);
    if (rc != 0) {
        unsigned code = 0;
        const char *msg = "?";
        lib3mf_getlasterror(reader, &code, &msg);
        cr_assert_fail("lib3mf cannot read %s: 0x%x, %u %s", path, rc, code, msg);
    }
    unsigned warnings = 99;
    cr_assert_eq(lib3mf_reader_getwarningcount(reader, &warnings), 0);
    cr_expect_eq(warnings, 0, "lib3mf warns %u times", warnings);
    lib3mf_release(reader);
    return model;
}

/* The box painted (issue 29): colour grids as hv_colour_paint leaves them, so the package carries a
 * <v:color> over one more (RGBA) stack, which lib3mf must pass over like the rest. */
static void paint_box(hv_volume *v)
{
    static const char *const names[4] = {"colour.r", "colour.g", "colour.b", "colour.mask"};
    int g[4], og = hv_volume_grid_find(v, "occupancy");
    for (int c = 0; c < 4; ++c) cr_assert_eq(hv_volume_grid_add(v, names[c], HV_GRID_FLOAT, &g[c]), HV_OK);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned n = 0; n < 512; ++n) {
            if (!HV_BIT_GET(hv_volume_leaf_bool(v, og, l), n)) continue;
            for (int c = 0; c < 4; ++c) hv_volume_leaf_float(v, g[c], l)[n] = c == 3 ? 1.0f : (float)((n * (c + 3)) % 7) / 6;
        }
}

static void opens_the_box(int painted)
{
    hv_volume *v = make_box();
    if (painted) paint_box(v);
    const char *path = t_tmpfile(painted ? "painted_box.3mf" : "box.3mf");
    hv_export_options o;
    hv_export_options_init(&o);
    o.volumetric = 1;
    o.bits = 16;
    hv_export_report r;
    cr_assert_eq(hv_export_write(v, path, &o, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(r.colour, painted);
    L3 *model = read_3mf(path);
    L3 *it = NULL, *mesh = NULL;
    cr_assert_eq(lib3mf_model_getmeshobjects(model, &it), 0);
    int has = 0, meshes = 0;
    while (lib3mf_resourceiterator_movenext(it, &has) == 0 && has) {
        cr_assert_eq(lib3mf_resourceiterator_getcurrent(it, &mesh), 0);
        ++meshes;
        unsigned nv = 0, nt = 0;
        lib3mf_meshobject_getvertexcount(mesh, &nv);
        lib3mf_meshobject_gettrianglecount(mesh, &nt);
        /* the counts hovox reports, and the box's by hand: its surface is 2 (5x3 + 3x4 + 5x4) = 94 faces;
         * the dent on an edge takes 2 and opens 4: 96 quads, 192 triangles; corners (6 x 4 x 5) minus the
         * (4 x 2 x 3) inner ones = 96, plus the 2 at the bottom of the dent (Euler: 98 - 288 + 192 = 2) */
        cr_expect_eq(nv, r.points);
        cr_expect_eq(nt, r.cells);
        cr_expect_eq(nt, 192u);
        cr_expect_eq(nv, 98u);
        l3_vertex *vx = calloc(nv, sizeof *vx);
        unsigned got = 0;
        cr_assert_eq(lib3mf_meshobject_getvertices(mesh, vx, nv, &got), 0);
        /* the bounding box is the voxels' outer faces */
        float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
        for (unsigned i = 0; i < got; ++i)
            for (int a = 0; a < 3; ++a) {
                lo[a] = fminf(lo[a], vx[i].m_fPosition[a]);
                hi[a] = fmaxf(hi[a], vx[i].m_fPosition[a]);
            }
        const double want_lo[3] = {-1.125, 1.875, 0.375}, want_hi[3] = {-1.125 + NX * 0.25, 1.875 + NY * 0.25, 0.375 + NZ * 0.25};
        for (int a = 0; a < 3; ++a) {
            cr_expect_float_eq(lo[a], want_lo[a], 1e-6);
            cr_expect_float_eq(hi[a], want_hi[a], 1e-6);
        }
        l3_triangle *idx = calloc(nt, sizeof *idx);
        unsigned tn = 0;
        cr_assert_eq(lib3mf_meshobject_gettriangleindices(mesh, idx, nt, &tn), 0);
        cr_expect_eq(tn, nt);
        for (unsigned i = 0; i < tn; ++i)
            for (int k = 0; k < 3; ++k) cr_assert(idx[i].m_nIndices[k] < nv);
        free(idx);
        free(vx);
        lib3mf_release(mesh); /* each getcurrent hands out a new reference */
    }
    cr_expect_eq(meshes, 1);
    lib3mf_release(it);
    /* the base materials, names and colours */
    cr_assert_eq(lib3mf_model_getbasematerials(model, &it), 0);
    L3 *group = NULL;
    cr_assert(lib3mf_resourceiterator_movenext(it, &has) == 0 && has);
    cr_assert_eq(lib3mf_resourceiterator_getcurrent(it, &group), 0);
    unsigned count = 0;
    lib3mf_basematerial_getcount(group, &count);
    cr_expect_eq(count, 2u);
    char name[64];
    unsigned need = 0;
    cr_assert_eq(lib3mf_basematerial_getnameutf8(group, 1, name, sizeof name, &need), 0);
    cr_expect_str_eq(name, "rubber");
    unsigned char c[4];
    cr_assert_eq(lib3mf_basematerial_getdisplaycolor(group, 0, &c[0], &c[1], &c[2], &c[3]), 0);
    cr_expect(c[0] == 255 && c[1] == 0 && c[2] == 0 && c[3] == 255);
    lib3mf_release(group);
    lib3mf_release(it);
    lib3mf_release(model);
    hv_volume_destroy(v);
}

Test(lib3mf, opens_the_package_and_reads_the_core_mesh_and_base_materials) { opens_the_box(0); }
Test(lib3mf, opens_a_package_with_colour_and_reads_the_same) { opens_the_box(1); }

/* ---- the shape's 3MF core package (issue 28) ------------------------------------------------------
 * A plate 8 x 4 x 2 and a rod of radius 1 (64 sides) through it, voxelized at 0.25 mm, the rod in
 * material B. CSG subtract exported as .3mf: lib3mf reads one mesh, every edge in two triangles
 * (once each way), bounding box within 0.05 mm of 0..8 x 0..4 x 0..2, volume within 0.5% of
 * 64 - 2 x the 64-gon's area. Wu's difference keeps the plate's shape and puts B in the overlap:
 * the triangles lib3mf reads as B are those on the top and bottom faces inside the disc. */
extern LIB3MFRESULT lib3mf_meshobject_createpropertyhandler(L3 *mesh, L3 **handler);
extern LIB3MFRESULT lib3mf_propertyhandler_getbasematerial(L3 *handler, unsigned index, unsigned *group,
                                                           unsigned *material);

#include "hovox/generate.h"

static hv_object *part(hv_mesh *m, double b)
{
    hv_object *obj = t_object_of(m, 0.25, 2);
    double p[2] = {1 - b, b};
    cr_assert_eq(hv_object_set_base(obj, p), HV_OK, "%s", hv_last_error());
    hv_mesh_destroy(m);
    return obj;
}

typedef struct shape_read {
    unsigned nv, nt;
    l3_vertex *vx;
    l3_triangle *tri;
    unsigned *mat; /* per triangle: base material index, or ~0u without one */
} shape_read;

static void read_shape(hv_bool_op op, const char *name, shape_read *out)
{
    double lo[3] = {0, 0, 0}, hi[3] = {8, 4, 2}, base[3] = {4, 2, -1};
    hv_mesh *pm = NULL, *rm = NULL;
    cr_assert_eq(hv_generate_box(lo, hi, &pm), HV_OK);
    cr_assert_eq(hv_generate_cylinder(base, 2, 4, 1, 64, &rm), HV_OK);
    hv_object *a = part(pm, 0), *b = part(rm, 1), *h = NULL;
    cr_assert_eq(hv_object_boolean(a, b, op, &h), HV_OK, "%s", hv_last_error());
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_parse("A,B", NULL, NULL, 0, &t), HV_OK, "%s", hv_last_error());
    hv_volume *v = NULL;
    cr_assert_eq(hv_object_evaluate(h, t, 0, NULL, &v), HV_OK, "%s", hv_last_error());
    const char *path = t_tmpfile(name);
    hv_export_report r;
    cr_assert_eq(hv_export_write(v, path, NULL, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(r.format, HV_EXPORT_3MF_SHAPE);
    L3 *model = read_3mf(path), *it = NULL, *mesh = NULL, *ph = NULL;
    cr_assert_eq(lib3mf_model_getmeshobjects(model, &it), 0);
    int has = 0;
    cr_assert(lib3mf_resourceiterator_movenext(it, &has) == 0 && has);
    cr_assert_eq(lib3mf_resourceiterator_getcurrent(it, &mesh), 0);
    lib3mf_meshobject_getvertexcount(mesh, &out->nv);
    lib3mf_meshobject_gettrianglecount(mesh, &out->nt);
    cr_expect_eq(out->nt, r.cells);
    cr_expect_eq(out->nv, r.points);
    out->vx = calloc(out->nv, sizeof *out->vx);
    out->tri = calloc(out->nt, sizeof *out->tri);
    out->mat = calloc(out->nt, sizeof *out->mat);
    unsigned got = 0;
    cr_assert_eq(lib3mf_meshobject_getvertices(mesh, out->vx, out->nv, &got), 0);
    cr_assert_eq(lib3mf_meshobject_gettriangleindices(mesh, out->tri, out->nt, &got), 0);
    cr_assert_eq(lib3mf_meshobject_createpropertyhandler(mesh, &ph), 0);
    for (unsigned i = 0; i < out->nt; ++i) {
        unsigned g = 0, k = 0;
        cr_assert_eq(lib3mf_propertyhandler_getbasematerial(ph, i, &g, &k), 0);
        out->mat[i] = g ? k : ~0u;
    }
    cr_expect_not(lib3mf_resourceiterator_movenext(it, &has) == 0 && has, "one mesh object");
    lib3mf_release(ph);
    lib3mf_release(mesh);
    lib3mf_release(it);
    lib3mf_release(model);
    hv_volume_destroy(v);
    hv_material_table_destroy(t);
    hv_object_destroy(a);
    hv_object_destroy(b);
    hv_object_destroy(h);
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* every directed edge once and its reverse once: closed and consistently oriented */
static void expect_watertight(const shape_read *s)
{
    size_t n = 3 * (size_t)s->nt;
    uint64_t *e = malloc(n * sizeof *e);
    for (unsigned i = 0; i < s->nt; ++i)
        for (int k = 0; k < 3; ++k)
            e[3 * i + k] = (uint64_t)s->tri[i].m_nIndices[k] << 32 | s->tri[i].m_nIndices[(k + 1) % 3];
    qsort(e, n, sizeof *e, cmp_u64);
    size_t twice = 0, unmatched = 0;
    for (size_t i = 0; i < n; ++i) {
        if (i + 1 < n && e[i + 1] == e[i]) ++twice;
        uint64_t rev = e[i] << 32 | e[i] >> 32;
        if (!bsearch(&rev, e, n, sizeof *e, cmp_u64)) ++unmatched;
    }
    cr_expect_eq(twice, 0, "%zu directed edges twice", twice);
    cr_expect_eq(unmatched, 0, "%zu edges in one triangle only", unmatched);
    free(e);
}

static double volume_and_box(const shape_read *s, double lo[3], double hi[3])
{
    for (int a = 0; a < 3; ++a) lo[a] = 1e30, hi[a] = -1e30;
    for (unsigned i = 0; i < s->nv; ++i)
        for (int a = 0; a < 3; ++a) {
            lo[a] = fmin(lo[a], s->vx[i].m_fPosition[a]);
            hi[a] = fmax(hi[a], s->vx[i].m_fPosition[a]);
        }
    double v6 = 0;
    for (unsigned i = 0; i < s->nt; ++i) {
        const float *p = s->vx[s->tri[i].m_nIndices[0]].m_fPosition, *q = s->vx[s->tri[i].m_nIndices[1]].m_fPosition,
                    *r = s->vx[s->tri[i].m_nIndices[2]].m_fPosition;
        v6 += (double)p[0] * ((double)q[1] * r[2] - (double)q[2] * r[1]) - (double)p[1] * ((double)q[0] * r[2] - (double)q[2] * r[0]) +
              (double)p[2] * ((double)q[0] * r[1] - (double)q[1] * r[0]);
    }
    return v6 / 6;
}

Test(lib3mf, reads_the_shape_of_a_boolean_watertight_in_its_materials, .timeout = 120)
{
    const double gon = 0.5 * 64 * sin(2 * M_PI / 64); /* the rod's section, radius 1 */
    for (int k = 0; k < 2; ++k) {
        hv_bool_op op = k == 0 ? HV_OP_SUBTRACT : HV_OP_DIFFERENCE;
        shape_read s;
        read_shape(op, k == 0 ? "subtract.3mf" : "difference.3mf", &s);
        expect_watertight(&s);
        double lo[3], hi[3], want_hi[3] = {8, 4, 2};
        double vol = volume_and_box(&s, lo, hi), want = k == 0 ? 64 - 2 * gon : 64;
        for (int a = 0; a < 3; ++a) {
            cr_expect(fabs(lo[a]) <= 0.05, "op %d: box min %g on axis %d", op, lo[a], a);
            cr_expect(fabs(hi[a] - want_hi[a]) <= 0.05, "op %d: box max %g on axis %d", op, hi[a], a);
        }
        cr_expect(fabs(vol - want) <= 0.005 * want, "op %d: volume %g, want %g", op, vol, want);
        /* materials: subtract keeps the plate's A everywhere; difference shows B where the rod met
         * the top and bottom faces, A elsewhere. Where materials meet is the voxels' business (0.25 mm,
         * the rod's surface voxels B): a band of 1.5 voxels about the circle is left unchecked */
        const double band = 1.5 * 0.25;
        size_t wrong = 0, b_tris = 0;
        for (unsigned i = 0; i < s.nt; ++i) {
            double c[3] = {0, 0, 0};
            for (int v = 0; v < 3; ++v)
                for (int a = 0; a < 3; ++a) c[a] += s.vx[s.tri[i].m_nIndices[v]].m_fPosition[a] / 3.0;
            double d = hypot(c[0] - 4, c[1] - 2);
            int cap = fabs(c[2]) < 1e-3 || fabs(c[2] - 2) < 1e-3;
            cr_assert_neq(s.mat[i], ~0u, "triangle %u has no material", i);
            b_tris += s.mat[i] == 1;
            if (k == 0 ? s.mat[i] != 0 : cap && d < 1 - band ? s.mat[i] != 1 : d > 1 + band || !cap ? s.mat[i] != 0 : 0)
                ++wrong;
        }
        cr_expect_eq(wrong, 0, "op %d: %zu triangles in the wrong material (%zu in B)", op, wrong, b_tris);
        if (k == 1) cr_expect_gt(b_tris, 0);
        free(s.vx);
        free(s.tri);
        free(s.mat);
    }
}
