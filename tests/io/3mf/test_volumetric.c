/* tests/io/3mf/test_volumetric.c - 3MF Volumetric packages: export -> read back round trips (8 and 16
 * bits: occupancy identical, fractions within one quantisation step, the lattice and material table
 * back), the package checked as XML against the element and attribute names of the spec (tables of
 * "3MF Volumetric & Implicit Extensions" 0.8, Part I and Appendix B, written out here), the mesh as a
 * closed oriented 2-manifold whose volume is the voxels', a hand-written foreign package (units,
 * RGB channels, tile styles, value scaling, a build item translation, a mesh off the voxel faces),
 * and damaged or unsupported packages refused with one message naming the place. */
#include <criterion/criterion.h>
#include <jansson.h>
#include <libxml/parser.h>
#include <libxml/tree.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zip.h>

#include "core/internal.h"
#include "hovox/colour.h"
#include "hovox/export.h"
#include "hovox/image.h"
#include "hovox/material.h"
#include "hovox/model.h"
#include "hovox/threemf.h"
#include "io/3mf/threemf_internal.h"
#include "support/support.h"

#define NS_CORE "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
#define NS_VOL "http://schemas.3mf.io/3dmanufacturing/volumetric/2022/01"

/* ---- models ------------------------------------------------------------------------------------
 * Anisotropic voxels, an origin off the lattice of 0, negative indices. Shape 0: the box [LO, HI]
 * with a hole through z at i = 4, j = 4..6. Shape 1: a seeded random half of the box (voxels that
 * meet only along edges and at corners everywhere). Three materials, fractions varying per voxel. */
static const int LO[3] = {-3, 2, -5}, HI[3] = {8, 9, 1};
static const double VOX[3] = {0.5, 1.0, 2.0}, ORG[3] = {10.0, -4.0, 1.5};

static uint32_t hash3(int i, int j, int k)
{
    uint32_t h = ((uint32_t)i * 73856093u) ^ ((uint32_t)j * 19349663u) ^ ((uint32_t)k * 83492791u);
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    return h ^ (h >> 15);
}

static int occupied(int shape, int i, int j, int k)
{
    if (i < LO[0] || i > HI[0] || j < LO[1] || j > HI[1] || k < LO[2] || k > HI[2]) return 0;
    if (shape == 0) return !(i == 4 && j >= 4 && j <= 6);
    return (hash3(i, j, k) & 1023) < 520;
}

static void fractions_at(int i, int j, int k, float f[3])
{
    double a = (hash3(i + 7, j, k) % 1000) / 999.0, b = (hash3(i, j + 5, k) % 1000) / 999.0, c = 0.25 + 0.1 * (k & 3);
    double s = a + b + c;
    f[0] = (float)(a / s);
    f[1] = (float)(b / s);
    f[2] = (float)(1.0 - (double)f[0] - (double)f[1]);
}

static hv_volume *make_model(int shape)
{
    hv_transform xf = {{VOX[0], VOX[1], VOX[2]}, {ORG[0], ORG[1], ORG[2]}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK, "%s", hv_last_error());
    cr_assert_eq(t_add_box(v, LO, HI), HV_OK);
    int og, g[3];
    static const char *const names[3] = {"vero", "agilus", "clear"};
    cr_assert_eq(hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &og), HV_OK);
    for (int m = 0; m < 3; ++m) {
        char gn[40];
        snprintf(gn, sizeof gn, "material.%s", names[m]);
        cr_assert_eq(hv_volume_grid_add(v, gn, HV_GRID_FLOAT, &g[m]), HV_OK);
    }
    const int32_t *orig = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const uint64_t *act = hv_volume_leaf_mask(v, l);
        for (unsigned n = 0; n < 512; ++n) {
            if (!HV_BIT_GET(act, n)) continue;
            int i = orig[3 * l] + (int)(n >> 6), j = orig[3 * l + 1] + (int)((n >> 3) & 7), k = orig[3 * l + 2] + (int)(n & 7);
            if (!occupied(shape, i, j, k)) continue;
            hv_volume_leaf_bool(v, og, l)[n >> 6] |= 1ull << (n & 63);
            float f[3];
            fractions_at(i, j, k, f);
            for (int m = 0; m < 3; ++m) hv_volume_leaf_float(v, g[m], l)[n] = f[m];
        }
    }
    hv_material_table *t;
    cr_assert_eq(hv_material_table_create(&t), HV_OK);
    static const float rgba[3][4] = {{0.1f, 0.2f, 0.9f, 1}, {0.9f, 0.3f, 0.1f, 1}, {0.8f, 0.8f, 0.8f, 0.5f}};
    for (int m = 0; m < 3; ++m) {
        cr_assert_eq(hv_material_add(t, names[m], rgba[m], NULL), HV_OK);
        cr_assert_eq(hv_material_set_property(t, m, "density", 1100 + 100 * m, "kg/m^3"), HV_OK);
        cr_assert_eq(hv_material_set_property(t, m, "youngs_modulus", m == 1 ? 1e6 : 2e9, "Pa"), HV_OK);
    }
    cr_assert_eq(hv_material_table_store(v, t), HV_OK);
    hv_material_table_destroy(t);
    return v;
}

static uint64_t model_voxels(int shape)
{
    uint64_t n = 0;
    for (int i = LO[0]; i <= HI[0]; ++i)
        for (int j = LO[1]; j <= HI[1]; ++j)
            for (int k = LO[2]; k <= HI[2]; ++k) n += (uint64_t)occupied(shape, i, j, k);
    return n;
}

static hv_export_report export_3mf(hv_volume *v, const char *path, int bits)
{
    hv_export_options o;
    hv_export_options_init(&o);
    o.volumetric = 1;
    o.bits = bits;
    hv_export_report r;
    cr_assert_eq(hv_export_write(v, path, &o, &r), HV_OK, "%s", hv_last_error());
    cr_assert_eq(r.format, HV_EXPORT_3MF);
    return r;
}

/* ---- round trips --------------------------------------------------------------------------------- */

static void round_trip(int shape, int bits)
{
    hv_volume *v = make_model(shape);
    char name[64];
    snprintf(name, sizeof name, "rt%d_%d.3mf", shape, bits);
    const char *path = t_tmpfile(name);
    hv_export_report r = export_3mf(v, path, bits);
    cr_expect_eq(r.occupied, model_voxels(shape));
    cr_expect_eq(r.dims[0], HI[0] - LO[0] + 1);
    cr_expect_eq(r.bits, bits);
    hv_volume *back = NULL;
    cr_assert_eq(hv_model_load(path, &back), HV_OK, "%s", hv_last_error());
    hv_transform a = hv_volume_get_transform(v), b = hv_volume_get_transform(back);
    cr_assert(hv_transform_same(&a, &b), "lattice back: voxel %g %g %g origin %g %g %g", b.voxel[0], b.voxel[1],
              b.voxel[2], b.origin[0], b.origin[1], b.origin[2]);
    /* the materials, their colours and properties */
    hv_material_table *ta, *tb;
    cr_assert_eq(hv_material_table_load(v, &ta), HV_OK);
    cr_assert_eq(hv_material_table_load(back, &tb), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_material_count(tb), 3);
    int ga[3], gb[3];
    for (int m = 0; m < 3; ++m) {
        cr_expect_str_eq(hv_material_name(tb, m), hv_material_name(ta, m));
        float ca[4], cb[4];
        hv_material_color(ta, m, ca);
        hv_material_color(tb, m, cb);
        for (int c = 0; c < 4; ++c) cr_expect_float_eq(ca[c], cb[c], 1e-6);
        double x;
        cr_expect(hv_material_property(tb, m, "density", &x, NULL) && x == 1100 + 100 * m);
        ga[m] = hv_material_grid(v, ta, m);
        gb[m] = hv_material_grid(back, tb, m);
        cr_assert(gb[m] >= 0);
    }
    /* occupancy identical, fractions within a quantisation step */
    int oa = hv_volume_grid_find(v, "occupancy"), ob = hv_volume_grid_find(back, "occupancy");
    cr_assert(ob >= 0 && hv_volume_grid_type(back, ob) == HV_GRID_BOOL);
    hv_accessor aa, ab;
    hv_accessor_init(&aa, v);
    hv_accessor_init(&ab, back);
    double tol = 1.0 / (bits == 16 ? 65535.0 : 255.0) + 1e-6, worst = 0;
    uint64_t n = 0;
    for (int i = LO[0] - 2; i <= HI[0] + 2; ++i)
        for (int j = LO[1] - 2; j <= HI[1] + 2; ++j)
            for (int k = LO[2] - 2; k <= HI[2] + 2; ++k) {
                int in = hv_accessor_bool(&aa, oa, i, j, k), got = hv_accessor_bool(&ab, ob, i, j, k);
                cr_assert_eq(got, in, "voxel (%d, %d, %d): occupancy %d back, %d exported", i, j, k, got, in);
                cr_assert_eq(hv_accessor_active(&ab, i, j, k), in, "the topology is the occupancy");
                if (!in) continue;
                ++n;
                double sum = 0;
                for (int m = 0; m < 3; ++m) {
                    double fa = hv_accessor_float(&aa, ga[m], i, j, k), fb = hv_accessor_float(&ab, gb[m], i, j, k);
                    worst = fmax(worst, fabs(fa - fb));
                    sum += fb;
                }
                cr_assert_float_eq(sum, 1.0, 1e-6);
            }
    cr_expect_eq(n, model_voxels(shape));
    cr_expect(worst < tol, "largest fraction error %g, step %g", worst, tol);
    cr_expect(worst > 0, "quantised at all");
    hv_material_table_destroy(ta);
    hv_material_table_destroy(tb);
    hv_volume_destroy(back);
    hv_volume_destroy(v);
}

Test(threemf, round_trip_8_bit_box_with_hole) { round_trip(0, 8); }
Test(threemf, round_trip_16_bit_box_with_hole) { round_trip(0, 16); }
Test(threemf, round_trip_8_bit_random_voxels) { round_trip(1, 8); }
Test(threemf, round_trip_16_bit_random_voxels) { round_trip(1, 16); }

/* ---- the package as XML ------------------------------------------------------------------------- */

static char *zip_entry(const char *path, const char *name, size_t *size)
{
    int err = 0;
    zip_t *za = zip_open(path, ZIP_RDONLY, &err);
    cr_assert_not_null(za, "%s: not a zip (%d)", path, err);
    zip_stat_t st;
    if (zip_stat(za, name, 0, &st) != 0) {
        zip_discard(za);
        return NULL;
    }
    char *buf = malloc(st.size + 1);
    zip_file_t *f = zip_fopen(za, name, 0);
    cr_assert(f && zip_fread(f, buf, st.size) == (zip_int64_t)st.size);
    zip_fclose(f);
    zip_discard(za);
    buf[st.size] = '\0';
    if (size) *size = st.size;
    return buf;
}

/* The spec's elements and their attributes (Part I tables 2.2, 3.1, 3.2, 3.2.3, 5.2, 5.2.2-5.2.4,
 * 4.1.1; Appendix B): every attribute a producer may write without a namespace, then those the
 * schema requires. Attributes of other namespaces are allowed everywhere (xs:anyAttribute
 * ##other). */
typedef struct spec_elem {
    const char *name;
    const char *attrs[12];
    const char *required[6];
} spec_elem;
static const spec_elem k_spec[] = {
    {"image3d", {"id", "name"}, {"id"}},
    {"imagestack", {"rowcount", "columncount", "sheetcount"}, {"rowcount", "columncount", "sheetcount"}},
    {"imagesheet", {"path"}, {"path"}},
    {"functionfromimage3d",
     {"id", "displayname", "image3did", "valueoffset", "valuescale", "filter", "tilestyleu", "tilestylev", "tilestylew"},
     {"id", "image3did"}},
    {"volumedata", {"id"}, {"id"}},
    {"composite", {"basematerialid"}, {"basematerialid"}},
    {"materialmapping", {"functionid", "transform", "channel", "minfeaturesize", "fallbackvalue"}, {"functionid", "channel"}},
    {"property", {"functionid", "transform", "channel", "name", "required", "minfeaturesize", "fallbackvalue"},
     {"functionid", "channel", "name", "required"}},
    {"color", {"functionid", "transform", "channel", "minfeaturesize", "fallbackvalue"}, {"functionid", "channel"}},
    {"levelset",
     {"functionid", "channel", "transform", "minfeaturesize", "meshid", "meshbboxonly", "fallbackvalue", "volumeid"},
     {"functionid", "channel", "meshid"}},
};
/* 3MF Core elements hovox writes, with the attributes the core schema gives them. */
static const spec_elem k_core[] = {
    {"model", {"unit", "lang", "requiredextensions", "recommendedextensions"}, {0}},
    {"metadata", {"name", "preserve", "type"}, {"name"}},
    {"resources", {0}, {0}},
    {"basematerials", {"id"}, {"id"}},
    {"base", {"name", "displaycolor"}, {"name", "displaycolor"}},
    {"object", {"id", "type", "thumbnail", "partnumber", "name", "pid", "pindex"}, {"id"}},
    {"mesh", {0}, {0}},
    {"vertices", {0}, {0}},
    {"vertex", {"x", "y", "z"}, {"x", "y", "z"}},
    {"triangles", {0}, {0}},
    {"triangle", {"v1", "v2", "v3", "p1", "p2", "p3", "pid"}, {"v1", "v2", "v3"}},
    {"build", {0}, {0}},
    {"item", {"objectid", "transform", "partnumber"}, {"objectid"}},
};

static const spec_elem *find_spec(const spec_elem *t, size_t n, const char *name)
{
    for (size_t i = 0; i < n; ++i)
        if (strcmp(t[i].name, name) == 0) return &t[i];
    return NULL;
}

static int in_list(const char *const *l, size_t n, const char *s)
{
    for (size_t i = 0; i < n && l[i]; ++i)
        if (strcmp(l[i], s) == 0) return 1;
    return 0;
}

typedef struct walk {
    int vol_elems, core_elems;
    xmlNodePtr image3d[64];
    int nimage;
} walk;

static void check_node(xmlNodePtr e, walk *w)
{
    for (; e; e = e->next) {
        if (e->type != XML_ELEMENT_NODE) continue;
        cr_assert_not_null(e->ns, "<%s> has no namespace", e->name);
        const char *ns = (const char *)e->ns->href, *name = (const char *)e->name;
        const spec_elem *se = NULL;
        if (strcmp(ns, NS_VOL) == 0) {
            se = find_spec(k_spec, sizeof k_spec / sizeof *k_spec, name);
            cr_assert_not_null(se, "<v:%s> is not an element of the volumetric spec", name);
            w->vol_elems++;
            if (strcmp(name, "image3d") == 0 && w->nimage < 64) w->image3d[w->nimage++] = e;
        } else {
            cr_assert_str_eq(ns, NS_CORE, "<%s> in namespace %s", name, ns);
            se = find_spec(k_core, sizeof k_core / sizeof *k_core, name);
            cr_assert_not_null(se, "<%s> is not a 3MF core element hovox should write", name);
            w->core_elems++;
        }
        for (xmlAttrPtr a = e->properties; a; a = a->next) {
            const char *an = (const char *)a->name;
            if (a->ns && strcmp((const char *)a->ns->href, ns) != 0) {
                /* another namespace's attribute: the volumetric one on the core mesh must be volumeid */
                if (strcmp((const char *)a->ns->href, NS_VOL) == 0)
                    cr_assert(strcmp(name, "mesh") == 0 && strcmp(an, "volumeid") == 0, "v:%s on <%s>", an, name);
                continue;
            }
            cr_assert(in_list(se->attrs, 12, an), "<%s> has attribute %s, which the spec does not define", name, an);
        }
        for (int r = 0; r < 6 && se->required[r]; ++r)
            cr_assert(xmlHasProp(e, BAD_CAST se->required[r]) != NULL, "<%s> lacks required %s", name, se->required[r]);
        check_node(e->children, w);
    }
}

static int count_numbers(const char *s)
{
    int n = 0;
    while (*s) {
        char *end;
        double v = strtod(s, &end);
        if (end == s) return -1;
        if (!isfinite(v)) return -1;
        ++n;
        s = end;
        while (*s == ' ') ++s;
    }
    return n;
}

static xmlNodePtr child(xmlNodePtr e, const char *name)
{
    for (xmlNodePtr c = e ? e->children : NULL; c; c = c->next)
        if (c->type == XML_ELEMENT_NODE && strcmp((const char *)c->name, name) == 0) return c;
    return NULL;
}

static char *prop(xmlNodePtr e, const char *name) { return (char *)xmlGetProp(e, BAD_CAST name); }

Test(threemf, package_structure_and_names_follow_the_spec)
{
    hv_volume *v = make_model(1);
    const char *path = t_tmpfile("structure.3mf");
    hv_export_report r = export_3mf(v, path, 8);
    /* OPC: content types, the package relationship to the model */
    char *ct = zip_entry(path, "[Content_Types].xml", NULL), *rels = zip_entry(path, "_rels/.rels", NULL);
    cr_assert(ct && rels);
    cr_expect(strstr(ct, "Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\""));
    cr_expect(strstr(ct, "Extension=\"png\" ContentType=\"image/png\""));
    cr_expect(strstr(ct, "Extension=\"rels\""));
    cr_expect(strstr(rels, "Target=\"/3D/3dmodel.model\""));
    cr_expect(strstr(rels, "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\""));
    size_t n;
    char *model = zip_entry(path, "3D/3dmodel.model", &n);
    char *mrels = zip_entry(path, "3D/_rels/3dmodel.model.rels", NULL);
    cr_assert(model && mrels);
    xmlDocPtr doc = xmlReadMemory(model, (int)n, "3dmodel.model", NULL, XML_PARSE_NONET);
    cr_assert_not_null(doc, "the model part is well-formed XML");
    xmlNodePtr root = xmlDocGetRootElement(doc);
    cr_assert_str_eq((const char *)root->name, "model");
    char *unit = prop(root, "unit");
    cr_expect_str_eq(unit, "millimeter");
    xmlFree(unit);
    walk w;
    memset(&w, 0, sizeof w);
    check_node(root, &w);
    cr_expect(w.vol_elems > 0 && w.core_elems > 0);
    /* every image3d: one stack of sheetcount sheets, named per the OPC layout (spec 3.2.2), each a
     * part of the package with a 3D texture relationship from the model part */
    cr_expect_eq(w.nimage, r.arrays);
    for (int i = 0; i < w.nimage; ++i) {
        xmlNodePtr st = child(w.image3d[i], "imagestack");
        cr_assert_not_null(st);
        char *sc = prop(st, "sheetcount"), *nm = prop(w.image3d[i], "name");
        int sheets = atoi(sc), k = 0;
        cr_expect_eq(sheets, r.dims[2]);
        for (xmlNodePtr s = st->children; s; s = s->next) {
            if (s->type != XML_ELEMENT_NODE) continue;
            char *p = prop(s, "path"), want[200];
            snprintf(want, sizeof want, "/3D/volumetric/%s/sheet%04d.png", nm, ++k);
            cr_expect_str_eq(p, want);
            size_t pn = 0;
            char *png = zip_entry(path, p + 1, &pn);
            cr_assert_not_null(png, "%s is in the package", p);
            cr_expect(pn > 8 && memcmp(png, "\x89PNG", 4) == 0);
            char rel[300];
            snprintf(rel, sizeof rel, "Target=\"%s\"", p);
            cr_expect(strstr(mrels, rel), "%s has a relationship", p);
            free(png);
            xmlFree(p);
        }
        cr_expect_eq(k, sheets);
        xmlFree(sc);
        xmlFree(nm);
    }
    cr_expect(strstr(mrels, "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dtexture"));
    /* values: enumerations and matrices */
    xmlNodePtr res = child(root, "resources");
    int composites = 0, mappings = 0, properties = 0;
    for (xmlNodePtr e = res->children; e; e = e->next) {
        if (e->type != XML_ELEMENT_NODE) continue;
        if (strcmp((const char *)e->name, "functionfromimage3d") == 0) {
            char *f = prop(e, "filter"), *tu = prop(e, "tilestyleu");
            cr_expect(strcmp(f, "linear") == 0 || strcmp(f, "nearest") == 0);
            cr_expect(strcmp(tu, "wrap") == 0 || strcmp(tu, "mirror") == 0 || strcmp(tu, "clamp") == 0);
            xmlFree(f);
            xmlFree(tu);
        }
        if (strcmp((const char *)e->name, "volumedata") == 0)
            for (xmlNodePtr c = e->children; c; c = c->next) {
                if (c->type != XML_ELEMENT_NODE) continue;
                if (strcmp((const char *)c->name, "composite") == 0) {
                    composites++;
                    for (xmlNodePtr m = c->children; m; m = m->next) {
                        if (m->type != XML_ELEMENT_NODE) continue;
                        char *t = prop(m, "transform");
                        cr_expect_eq(count_numbers(t), 12, "ST_Matrix3D: 12 numbers");
                        xmlFree(t);
                        mappings++;
                    }
                } else if (strcmp((const char *)c->name, "property") == 0) {
                    char *nm = prop(c, "name");
                    cr_expect(strncmp(nm, "hovox:", 6) == 0, "property names are prefixed QNames");
                    xmlFree(nm);
                    properties++;
                }
            }
    }
    cr_expect_eq(composites, 1);
    cr_expect_eq(mappings, 3, "one mapping per base material");
    cr_expect_eq(properties, r.arrays - 3);
    xmlFreeDoc(doc);
    free(model);
    free(mrels);
    free(ct);
    free(rels);
    hv_volume_destroy(v);
}

/* ---- the mesh: closed, oriented, 2-manifold, the voxels' volume ------------------------------------ */

static void mesh_from_xml(const char *path, double **xyz, size_t *nv, uint32_t **tri, size_t *nt)
{
    size_t n;
    char *model = zip_entry(path, "3D/3dmodel.model", &n);
    xmlDocPtr doc = xmlReadMemory(model, (int)n, "m", NULL, XML_PARSE_NONET | XML_PARSE_HUGE);
    cr_assert_not_null(doc);
    xmlNodePtr mesh = child(child(child(xmlDocGetRootElement(doc), "resources"), "object"), "mesh");
    cr_assert_not_null(mesh);
    size_t cv = 0, ct = 0;
    for (xmlNodePtr c = child(mesh, "vertices")->children; c; c = c->next) cv += c->type == XML_ELEMENT_NODE;
    for (xmlNodePtr c = child(mesh, "triangles")->children; c; c = c->next) ct += c->type == XML_ELEMENT_NODE;
    *xyz = malloc(3 * cv * sizeof **xyz);
    *tri = malloc(3 * ct * sizeof **tri);
    size_t i = 0;
    for (xmlNodePtr c = child(mesh, "vertices")->children; c; c = c->next) {
        if (c->type != XML_ELEMENT_NODE) continue;
        static const char *const a[3] = {"x", "y", "z"};
        for (int k = 0; k < 3; ++k) {
            char *v = prop(c, a[k]);
            (*xyz)[3 * i + k] = strtod(v, NULL);
            xmlFree(v);
        }
        ++i;
    }
    i = 0;
    for (xmlNodePtr c = child(mesh, "triangles")->children; c; c = c->next) {
        if (c->type != XML_ELEMENT_NODE) continue;
        static const char *const a[3] = {"v1", "v2", "v3"};
        for (int k = 0; k < 3; ++k) {
            char *v = prop(c, a[k]);
            (*tri)[3 * i + k] = (uint32_t)strtoul(v, NULL, 10);
            xmlFree(v);
        }
        ++i;
    }
    *nv = cv;
    *nt = ct;
    xmlFreeDoc(doc);
    free(model);
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static void check_manifold(const char *path, uint64_t voxels, uint64_t *nv_out, uint64_t *nt_out)
{
    double *xyz;
    uint32_t *tri;
    size_t nv, nt;
    mesh_from_xml(path, &xyz, &nv, &tri, &nt);
    /* every directed edge once, its reverse once: closed, consistently oriented, no edge shared by 4 */
    uint64_t *e = malloc(3 * nt * sizeof *e);
    for (size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = tri[3 * t + k], b = tri[3 * t + (k + 1) % 3];
            cr_assert(a < nv && b < nv && a != b);
            e[3 * t + k] = (uint64_t)a << 32 | b;
        }
    qsort(e, 3 * nt, sizeof *e, cmp_u64);
    for (size_t i = 0; i < 3 * nt; ++i) {
        cr_assert(i == 0 || e[i] != e[i - 1], "directed edge %llu -> %llu twice", (unsigned long long)(e[i] >> 32),
                  (unsigned long long)(e[i] & 0xffffffffu));
        uint64_t rev = (e[i] & 0xffffffffu) << 32 | (e[i] >> 32);
        cr_assert_not_null(bsearch(&rev, e, 3 * nt, sizeof *e, cmp_u64), "edge without its opposite: open or flipped");
    }
    /* the enclosed volume (divergence theorem) is the voxels' */
    double vol = 0;
    for (size_t t = 0; t < nt; ++t) {
        const double *a = xyz + 3 * tri[3 * t], *b = xyz + 3 * tri[3 * t + 1], *c = xyz + 3 * tri[3 * t + 2];
        vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
    }
    double want = (double)voxels * VOX[0] * VOX[1] * VOX[2];
    cr_expect(fabs(vol - want) < 1e-6 * want, "mesh volume %.9g, voxels %.9g", vol, want);
    *nv_out = nv;
    *nt_out = nt;
    free(e);
    free(xyz);
    free(tri);
}

Test(threemf, boundary_mesh_is_a_closed_2_manifold_of_the_voxels_volume)
{
    for (int shape = 0; shape < 2; ++shape) {
        hv_volume *v = make_model(shape);
        const char *path = t_tmpfile(shape ? "mf1.3mf" : "mf0.3mf");
        hv_export_report r = export_3mf(v, path, 8);
        uint64_t nv, nt;
        check_manifold(path, model_voxels(shape), &nv, &nt);
        cr_expect_eq(nv, r.points);
        cr_expect_eq(nt, r.cells);
        hv_volume_destroy(v);
    }
}

/* Small configurations with known counts: a cube, two cubes sharing a face, an edge, a corner. */
static hv_volume *voxels_model(const int (*vox)[3], int n)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    int lo[3] = {0, 0, 0}, hi[3] = {3, 3, 3};
    cr_assert_eq(t_add_box(v, lo, hi), HV_OK);
    int og, ga;
    hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &og);
    hv_volume_grid_add(v, "material.a", HV_GRID_FLOAT, &ga);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    for (int q = 0; q < n; ++q) {
        int64_t l = hv_accessor_leaf(&acc, vox[q][0], vox[q][1], vox[q][2]);
        unsigned off = HV_LEAF_OFFSET(vox[q][0], vox[q][1], vox[q][2]);
        hv_volume_leaf_bool(v, og, (size_t)l)[off >> 6] |= 1ull << (off & 63);
        hv_volume_leaf_float(v, ga, (size_t)l)[off] = 1;
    }
    hv_material_table *t;
    hv_material_table_create(&t);
    hv_material_add(t, "a", NULL, NULL);
    hv_material_table_store(v, t);
    hv_material_table_destroy(t);
    return v;
}

Test(threemf, voxels_touching_along_an_edge_or_a_corner_get_separate_vertices)
{
    static const int one[1][3] = {{1, 1, 1}}, face[2][3] = {{1, 1, 1}, {2, 1, 1}}, edge[2][3] = {{1, 1, 1}, {2, 2, 1}},
                     corner[2][3] = {{1, 1, 1}, {2, 2, 2}}, ell[3][3] = {{1, 1, 1}, {2, 1, 1}, {2, 2, 1}};
    static const struct {
        const int (*v)[3];
        int n;
        uint64_t vertices, triangles;
    } cases[] = {{one, 1, 8, 12}, {face, 2, 12, 20}, {edge, 2, 16, 24}, {corner, 2, 16, 24}, {ell, 3, 16, 28}};
    for (size_t c = 0; c < sizeof cases / sizeof *cases; ++c) {
        hv_volume *v = voxels_model(cases[c].v, cases[c].n);
        const char *path = t_tmpfile("small.3mf");
        hv_export_options o;
        hv_export_options_init(&o);
        o.volumetric = 1;
        o.mix = 0;
        hv_export_report r;
        cr_assert_eq(hv_export_write(v, path, &o, &r), HV_OK, "%s", hv_last_error());
        cr_expect_eq(r.points, cases[c].vertices, "case %zu: %llu vertices", c, (unsigned long long)r.points);
        cr_expect_eq(r.cells, cases[c].triangles, "case %zu: %llu triangles", c, (unsigned long long)r.cells);
        double *xyz;
        uint32_t *tri;
        size_t nv, nt;
        mesh_from_xml(path, &xyz, &nv, &tri, &nt);
        /* manifold: every directed edge once */
        for (size_t a = 0; a < 3 * nt; ++a)
            for (size_t b = a + 1; b < 3 * nt; ++b) {
                uint32_t a0 = tri[a], a1 = tri[a / 3 * 3 + (a % 3 + 1) % 3];
                uint32_t b0 = tri[b], b1 = tri[b / 3 * 3 + (b % 3 + 1) % 3];
                cr_assert(!(a0 == b0 && a1 == b1), "case %zu: a directed edge twice", c);
            }
        free(xyz);
        free(tri);
        /* read back: the same voxels */
        hv_volume *back;
        cr_assert_eq(hv_model_load(path, &back), HV_OK, "%s", hv_last_error());
        cr_expect_eq(hv_volume_mask_count(back, hv_volume_grid_find(back, "occupancy")), (uint64_t)cases[c].n);
        hv_volume_destroy(back);
        hv_volume_destroy(v);
    }
}

/* ---- the writer's other promises ----------------------------------------------------------------------- */

static int count_entries(const char *dir, const char *prefix)
{
    char cmd[600];
    snprintf(cmd, sizeof cmd, "ls -A '%s' | grep -c '%s'", dir, prefix);
    char *out = NULL;
    t_run(cmd, &out);
    int n = out ? atoi(out) : -1;
    free(out);
    return n;
}

Test(threemf, export_is_deterministic_atomic_and_planned)
{
    hv_volume *v = make_model(0);
    const char *a = t_tmpfile("det1.3mf"), *b = t_tmpfile("det2.3mf");
    hv_set_threads(1);
    export_3mf(v, a, 16);
    hv_set_threads(2);
    export_3mf(v, b, 16);
    hv_set_threads(0);
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "cmp -s '%s' '%s'", a, b);
    cr_expect_eq(t_run(cmd, NULL), 0, "the same bytes on 1 and 2 threads");
    /* plan: nothing written, the same counts */
    hv_export_options o;
    hv_export_options_init(&o);
    o.volumetric = 1;
    hv_export_report p;
    const char *planned = t_tmpfile("plan.3mf");
    cr_assert_eq(hv_export_plan(v, planned, &o, &p), HV_OK, "%s", hv_last_error());
    cr_expect(!t_exists(planned));
    cr_expect(p.memory_bytes > 0 && p.cells > 0 && p.points == 0 && p.file_bytes == 0);
    /* over the budget: refused before any file */
    o.max_memory = 1000;
    hv_export_report q;
    cr_expect_eq(hv_export_write(v, planned, &o, &q), HV_ERR_LIMIT);
    cr_expect(strstr(hv_last_error(), "max_memory") != NULL, "%s", hv_last_error());
    cr_expect(!t_exists(planned));
    /* unwritable: I/O, nothing left */
    hv_export_options_init(&o);
    o.volumetric = 1;
    cr_expect_eq(hv_export_write(v, "/nonexistent-dir/x.3mf", &o, &q), HV_ERR_IO);
    hv_volume_destroy(v);
}

/* Stop at the first report of the sheets' stage (made at least once, when they are done: after the
 * fractions were checked and some sheets written). */
static int cancel_at_sheets(void *user, const char *stage, double f)
{
    (void)f;
    int *n = user;
    return strcmp(stage, "export sheets") == 0 && ++*n >= 1;
}

Test(threemf, a_cancelled_or_failed_export_leaves_nothing)
{
    hv_volume *v = make_model(1);
    const char *dir = t_tmpfile("nothing");
    cr_assert_eq(mkdir(dir, 0755), 0);
    char out[600];
    snprintf(out, sizeof out, "%s/c.3mf", dir);
    int n = 0;
    hv_progress prog = {cancel_at_sheets, &n};
    hv_export_options o;
    hv_export_options_init(&o);
    o.volumetric = 1;
    o.progress = &prog;
    hv_export_report r;
    cr_expect_eq(hv_export_write(v, out, &o, &r), HV_ERR_CANCELLED);
    cr_expect_eq(count_entries(dir, "."), 0, "no file and no temporary left");
    /* a model without materials: refused */
    hv_volume *plain = NULL;
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    hv_volume_create(&xf, &plain);
    int lo[3] = {0, 0, 0}, hi[3] = {2, 2, 2};
    t_add_box(plain, lo, hi);
    hv_export_options_init(&o);
    o.volumetric = 1;
    cr_expect_eq(hv_export_write(plain, out, &o, &r), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "material table") != NULL, "%s", hv_last_error());
    cr_expect_eq(count_entries(dir, "."), 0);
    /* bits: 8 or 16, for .3mf only */
    o.bits = 12;
    cr_expect_eq(hv_export_options_check(&o), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "bits must be 8 or 16, got 12") != NULL, "%s", hv_last_error());
    o.bits = 16;
    snprintf(out, sizeof out, "%s/c.vti", dir);
    o.volumetric = 0;
    cr_expect_eq(hv_export_write(v, out, &o, &r), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "bits applies to .3mf output only") != NULL, "%s", hv_last_error());
    /* the shape's .3mf has no image stacks: bits is the Volumetric package's */
    snprintf(out, sizeof out, "%s/c.3mf", dir);
    cr_expect_eq(hv_export_write(v, out, &o, &r), HV_ERR_INVALID);
    cr_expect(strstr(hv_last_error(), "bits applies to the Volumetric package only (.3mf with volumetric)") != NULL,
              "%s", hv_last_error());
    cr_expect_eq(count_entries(dir, "."), 0);
    hv_volume_destroy(plain);
    hv_volume_destroy(v);
}

/* ---- a foreign package ---------------------------------------------------------------------------------
 * Written by hand as another producer might: centimetres, three materials in the red, green and blue
 * channels of one RGB stack of 3 x 2 x 2, nearest filter, tile styles wrap / mirror / clamp, values
 * scaled by 2 and offset by -0.5, an optional colour element, a build item moved by 0.5 cm in x, and
 * a box mesh whose faces lie between voxel faces and centres. Lattice: 1 mm voxels from the object's
 * origin; the box x in [0.02, 0.58] cm, y in [0.01, 0.39], z in [0.04, 0.27] holds 6 x 4 x 3 voxel
 * centres, most outside the 3 x 2 x 2 image (tiled). */
static const uint8_t RGB[2][2][3][3] = { /* [sheet][row][column][channel] */
    {{{255, 0, 0}, {191, 64, 128}, {0, 255, 0}}, {{100, 200, 50}, {30, 30, 30}, {0, 0, 255}}},
    {{{128, 128, 128}, {255, 255, 0}, {10, 250, 128}}, {{200, 100, 180}, {64, 191, 90}, {0, 0, 0}}}};

static uint8_t *rgb_png(int sheet, size_t *n)
{
    png_image im;
    memset(&im, 0, sizeof im);
    im.version = PNG_IMAGE_VERSION;
    im.width = 3;
    im.height = 2;
    im.format = PNG_FORMAT_RGB;
    png_alloc_size_t size = 0;
    cr_assert(png_image_write_to_memory(&im, NULL, &size, 0, RGB[sheet], 0, NULL));
    uint8_t *buf = malloc(size);
    cr_assert(png_image_write_to_memory(&im, buf, &size, 0, RGB[sheet], 0, NULL));
    *n = size;
    return buf;
}

static const char *FOREIGN_HEAD =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    "<model unit=\"centimeter\" xml:lang=\"en-US\" xmlns=\"" NS_CORE "\" xmlns:v=\"" NS_VOL "\" requiredextensions=\"v\">\n"
    " <metadata name=\"Title\">foreign</metadata>\n"
    " <resources>\n"
    "  <basematerials id=\"5\">\n"
    "   <base name=\"PLA Red\" displaycolor=\"#FF0000\"/>\n"
    "   <base name=\"PLA Red\" displaycolor=\"#00ff00\"/>\n"
    "   <base name=\"Ag\" displaycolor=\"#0000FF80\"/>\n"
    "  </basematerials>\n";
static const char *FOREIGN_IMAGE =
    "  <v:image3d id=\"7\" name=\"mix\">\n"
    "   <v:imagestack rowcount=\"2\" columncount=\"3\" sheetcount=\"2\">\n"
    "    <v:imagesheet path=\"/3D/vol/s0.png\"/>\n"
    "    <v:imagesheet path=\"/3D/vol/s1.png\"/>\n"
    "   </v:imagestack>\n"
    "  </v:image3d>\n"
    "  <v:functionfromimage3d id=\"8\" image3did=\"7\" filter=\"nearest\" valueoffset=\"-0.5\" valuescale=\"2\" "
    "tilestyleu=\"wrap\" tilestylev=\"mirror\" tilestylew=\"clamp\"/>\n";
/* u = x / 0.3, v = y / 0.2, w = z / 0.2 (cm): 1 mm voxels */
#define T_MAP "3.3333333333333335 0 0 0 5 0 0 0 5 0 0 0"
static const char *FOREIGN_VOLUME =
    "  <v:volumedata id=\"9\">\n"
    "   <v:composite basematerialid=\"5\">\n"
    "    <v:materialmapping functionid=\"8\" channel=\"red\" transform=\"" T_MAP "\"/>\n"
    "    <v:materialmapping functionid=\"8\" channel=\"green\" transform=\"" T_MAP "\"/>\n"
    "    <v:materialmapping functionid=\"8\" channel=\"blue\" transform=\"" T_MAP "\"/>\n"
    "   </v:composite>\n"
    "   <v:color functionid=\"8\" channel=\"color\"/>\n"
    "  </v:volumedata>\n";

static void box_mesh(char *buf, size_t size, const char *mesh_attr)
{
    double lo[3] = {0.02, 0.01, 0.04}, hi[3] = {0.58, 0.39, 0.27};
    size_t at = (size_t)snprintf(buf, size, "  <object id=\"1\" type=\"model\">\n   <mesh %s>\n    <vertices>\n", mesh_attr);
    for (int c = 0; c < 8; ++c)
        at += (size_t)snprintf(buf + at, size - at, "     <vertex x=\"%g\" y=\"%g\" z=\"%g\"/>\n", c & 1 ? hi[0] : lo[0],
                               c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]);
    static const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    at += (size_t)snprintf(buf + at, size - at, "    </vertices>\n    <triangles>\n");
    for (int q = 0; q < 6; ++q)
        at += (size_t)snprintf(buf + at, size - at,
                               "     <triangle v1=\"%d\" v2=\"%d\" v3=\"%d\"/>\n     <triangle v1=\"%d\" v2=\"%d\" v3=\"%d\"/>\n",
                               quads[q][0], quads[q][1], quads[q][2], quads[q][0], quads[q][2], quads[q][3]);
    snprintf(buf + at, size - at, "    </triangles>\n   </mesh>\n  </object>\n");
}

static const char *FOREIGN_TAIL =
    " </resources>\n"
    " <build>\n  <item objectid=\"1\" transform=\"1 0 0 0 1 0 0 0 1 0.5 0 0\"/>\n </build>\n"
    "</model>\n";

static char *foreign_model(void)
{
    char mesh[4096];
    box_mesh(mesh, sizeof mesh, "v:volumeid=\"9\"");
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_printf(&b, "%s%s%s%s%s", FOREIGN_HEAD, FOREIGN_IMAGE, FOREIGN_VOLUME, mesh, FOREIGN_TAIL);
    return b.data;
}

/* Replace the first `from` in s by `to` (s malloc'd; returns the new string). */
static char *replace(char *s, const char *from, const char *to)
{
    char *p = strstr(s, from);
    cr_assert_not_null(p, "'%s' in the model", from);
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_append(&b, s, (size_t)(p - s));
    hv_buf_puts(&b, to);
    hv_buf_puts(&b, p + strlen(from));
    free(s);
    return b.data;
}

typedef struct entry {
    const char *name;
    const void *data;
    size_t size;
} entry;

static void write_zip(const char *path, const entry *e, int n)
{
    const char *names[16];
    const void *data[16];
    size_t sizes[16];
    cr_assert(n <= 16);
    for (int i = 0; i < n; ++i) {
        names[i] = e[i].name;
        data[i] = e[i].data;
        sizes[i] = e[i].size;
    }
    t_zip_write(path, names, data, sizes, n);
}

static const char *RELS =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/"
    "relationships\"><Relationship Target=\"/3D/3dmodel.model\" Id=\"r0\" "
    "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>\n";

static const char *TYPES =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/"
    "content-types\"><Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships"
    "+xml\"/><Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>"
    "<Default Extension=\"png\" ContentType=\"image/png\"/></Types>\n";

/* Write a package with this model text (and, when `sheets`, both sheets); load it. */
static hv_status load_foreign(const char *model, int sheets, const char *name, hv_volume **vol, hv_mesh **mesh)
{
    size_t n0, n1;
    uint8_t *s0 = rgb_png(0, &n0), *s1 = rgb_png(1, &n1);
    entry e[5] = {{"[Content_Types].xml", TYPES, strlen(TYPES)},
                  {"_rels/.rels", RELS, strlen(RELS)},
                  {"3D/3dmodel.model", model, strlen(model)},
                  {"3D/vol/s0.png", s0, n0},
                  {"3D/vol/s1.png", s1, n1}};
    const char *path = t_tmpfile(name);
    write_zip(path, e, 3 + sheets);
    hv_status s = hv_3mf_load(path, vol, mesh);
    free(s0);
    free(s1);
    return s;
}

/* A load that must have failed with `want`, one message holding `words` and starting with the
 * package's path (file `name`), and no model. */
static void check_refused(hv_status s, hv_volume *v, const char *from, const char *to, const char *name, hv_status want,
                          const char *words)
{
    cr_expect_eq(s, want, "'%s' -> '%s': %s (%s)", from, to, hv_status_name(s), hv_last_error());
    cr_expect(strstr(hv_last_error(), words) != NULL, "message: %s (want '%s')", hv_last_error(), words);
    cr_expect(strncmp(hv_last_error(), t_tmpfile(name), strlen(t_tmpfile(name))) == 0, "names the file: %s",
              hv_last_error());
    cr_expect_null(v);
    hv_volume_destroy(v);
}

static int64_t tile(int64_t s, int64_t n, int style)
{
    if (style == 2) return s < 0 ? 0 : s >= n ? n - 1 : s;
    if (style == 1) {
        int64_t m = ((s % (2 * n)) + 2 * n) % (2 * n);
        return m < n ? m : 2 * n - 1 - m;
    }
    return ((s % n) + n) % n;
}

Test(threemf, a_foreign_package_reads_with_units_channels_tiles_and_scaling)
{
    char *model = foreign_model();
    hv_volume *v = NULL;
    hv_mesh *mesh = NULL;
    cr_assert_eq(load_foreign(model, 2, "foreign.3mf", &v, &mesh), HV_OK, "%s", hv_last_error());
    free(model);
    hv_transform xf = hv_volume_get_transform(v);
    for (int a = 0; a < 3; ++a) cr_expect_float_eq(xf.voxel[a], 1.0, 1e-9, "1 mm voxels");
    hv_material_table *t;
    cr_assert_eq(hv_material_table_load(v, &t), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_material_count(t), 3);
    cr_expect_str_eq(hv_material_name(t, 0), "PLA_Red");
    cr_expect_str_eq(hv_material_name(t, 1), "PLA_Red_2");
    cr_expect_str_eq(hv_material_name(t, 2), "Ag");
    float c[4];
    hv_material_color(t, 2, c);
    cr_expect(c[2] == 1 && fabs(c[3] - 128 / 255.0) < 1e-6);
    int g[3];
    for (int m = 0; m < 3; ++m) g[m] = hv_material_grid(v, t, m);
    int og = hv_volume_grid_find(v, "occupancy");
    cr_expect_eq(hv_volume_mask_count(v, og), 6u * 4u * 3u, "the voxel centres inside the box");
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 3; ++k) {
                /* voxel centre in mm: the object's centre (0.05 + 0.1 i cm) moved by the item's 0.5 cm */
                double w[3] = {(0.05 + 0.1 * i + 0.5) * 10, (0.05 + 0.1 * j) * 10, (0.05 + 0.1 * k) * 10}, idx[3];
                hv_volume_world_to_index(v, w, idx);
                int32_t p[3];
                for (int a = 0; a < 3; ++a) {
                    p[a] = (int32_t)floor(idx[a] + 0.5);
                    cr_assert(fabs(idx[a] - p[a]) < 1e-6, "voxel centres on the lattice");
                }
                cr_assert(hv_accessor_bool(&acc, og, p[0], p[1], p[2]), "voxel %d %d %d inside", i, j, k);
                int col = (int)tile(i, 3, 0), vrow = (int)tile(j, 2, 1), sheet = (int)tile(k, 2, 2);
                int row = 1 - vrow; /* rows run down from the highest v */
                double val[3], sum = 0;
                for (int m = 0; m < 3; ++m) {
                    double x = RGB[sheet][row][col][m] / 255.0 * 2 - 0.5;
                    val[m] = x < 0 ? 0 : x > 1 ? 1 : x;
                    sum += val[m];
                }
                for (int m = 0; m < 3; ++m) {
                    double want = sum >= 1e-5 ? val[m] / sum : m == 0;
                    double got = hv_accessor_float(&acc, g[m], p[0], p[1], p[2]);
                    cr_expect(fabs(got - want) < 1e-6, "voxel %d %d %d material %d: %g, want %g", i, j, k, m, got, want);
                }
            }
    /* the mesh in millimetres, moved */
    const hv_mesh_report *mr = hv_mesh_get_report(mesh);
    cr_expect_float_eq(mr->bbox_min[0], 5.2, 1e-5);
    cr_expect_float_eq(mr->bbox_max[2], 2.7, 1e-5);
    hv_mesh_destroy(mesh);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
}

/* ---- colour (issue 29): a painted model's colours as <v:color> ------------------------------------------
 * A model painted as hv_colour_paint leaves it (float grids colour.r, .g, .b: the sRGB asked for;
 * colour.mask: where a colour was asked for; metadata hovox.colour.json) is exported with its
 * colours as one RGBA stack of 16 bits in linear sRGB (Volumetric 5.2.1) read by a <v:color>, the
 * mask as its alpha (property hovox:colour.mask), and read back: the colour within 1/255 per
 * channel, the mask and the record the same. */
static const char *COLOUR_JSON = "{\"icc\": \"/usr/share/color/icc/ghostscript/default_cmyk.icc\", \"intent\": "
                                 "\"perceptual\", \"resins\": [\"VeroCyan-V\", \"VeroMagenta-V\", \"VeroYellow-V\", "
                                 "\"VeroBlackPlus\", \"VeroPureWhite\", \"VeroClear\"], \"depth_mm\": 1, \"core\": "
                                 "\"agilus\"}";

/* Colours at every occupied voxel: a quarter unasked (mask 0, colour 0, as under a resin core),
 * the rest anywhere in [0, 1], one in eight very dark (below 0.02, where 8 linear bits would not do). */
static void colour_at(int i, int j, int k, float c[4])
{
    uint32_t h = hash3(i + 11, j - 3, k + 5);
    c[3] = (h & 3) != 0;
    for (int a = 0; a < 3; ++a) {
        double x = (hash3(i + a, j * 3 + a, k - 7 * a) % 100000) / 99999.0;
        c[a] = c[3] ? (float)((h >> 8 & 7) == 0 ? 0.02 * x : x) : 0.0f;
    }
}

static void paint_grids(hv_volume *v)
{
    static const char *const names[4] = {"colour.r", "colour.g", "colour.b", "colour.mask"};
    int g[4], og = hv_volume_grid_find(v, "occupancy");
    for (int a = 0; a < 4; ++a) cr_assert_eq(hv_volume_grid_add(v, names[a], HV_GRID_FLOAT, &g[a]), HV_OK);
    const int32_t *orig = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned n = 0; n < 512; ++n) {
            if (!HV_BIT_GET(hv_volume_leaf_bool(v, og, l), n)) continue;
            float c[4];
            colour_at(orig[3 * l] + (int)(n >> 6), orig[3 * l + 1] + (int)((n >> 3) & 7), orig[3 * l + 2] + (int)(n & 7), c);
            for (int a = 0; a < 4; ++a) hv_volume_leaf_float(v, g[a], l)[n] = c[a];
        }
    cr_assert_eq(hv_volume_meta_set_json(v, "hovox.colour.json", COLOUR_JSON), HV_OK);
}

/* The colour grids of two models over the box around LO..HI: the same occupancy and mask, the
 * colour within tol where it was asked for and 0 elsewhere; returns the largest difference. */
static double compare_colours(hv_volume *a, hv_volume *b, const int lo[3], const int hi[3], double tol)
{
    static const char *const names[4] = {"colour.r", "colour.g", "colour.b", "colour.mask"};
    int ga[4], gb[4], oa = hv_volume_grid_find(a, "occupancy"), ob = hv_volume_grid_find(b, "occupancy");
    for (int c = 0; c < 4; ++c) {
        ga[c] = hv_volume_grid_find(a, names[c]);
        gb[c] = hv_volume_grid_find(b, names[c]);
        cr_assert(ga[c] >= 0 && gb[c] >= 0, "grid %s back", names[c]);
        cr_assert_eq(hv_volume_grid_type(b, gb[c]), HV_GRID_FLOAT);
    }
    hv_accessor aa, ab;
    hv_accessor_init(&aa, a);
    hv_accessor_init(&ab, b);
    double worst = 0;
    uint64_t asked = 0;
    for (int i = lo[0] - 1; i <= hi[0] + 1; ++i)
        for (int j = lo[1] - 1; j <= hi[1] + 1; ++j)
            for (int k = lo[2] - 1; k <= hi[2] + 1; ++k) {
                int in = hv_accessor_bool(&aa, oa, i, j, k);
                cr_assert_eq(hv_accessor_bool(&ab, ob, i, j, k), in, "voxel (%d, %d, %d): occupancy", i, j, k);
                if (!in) continue;
                float ma = hv_accessor_float(&aa, ga[3], i, j, k), mb = hv_accessor_float(&ab, gb[3], i, j, k);
                cr_assert_eq(mb, ma > 0.5f ? 1.0f : 0.0f, "voxel (%d, %d, %d): mask %g back, %g exported", i, j, k, mb, ma);
                asked += ma > 0.5f;
                for (int c = 0; c < 3; ++c) {
                    double ca = hv_accessor_float(&aa, ga[c], i, j, k), cb = hv_accessor_float(&ab, gb[c], i, j, k);
                    if (!(ma > 0.5f)) {
                        cr_assert_eq(cb, 0.0, "voxel (%d, %d, %d): no colour asked for, %g back", i, j, k, cb);
                        continue;
                    }
                    cr_assert(fabs(ca - cb) <= tol, "voxel (%d, %d, %d) channel %d: %.6f back, %.6f exported", i, j, k,
                              c, cb, ca);
                    worst = fmax(worst, fabs(ca - cb));
                }
            }
    cr_assert_gt(asked, 0);
    return worst;
}

Test(threemf_colour, arbitrary_colours_come_back_within_1_255)
{
    for (int bits = 8; bits <= 16; bits += 8) {
        hv_volume *v = make_model(1);
        paint_grids(v);
        const char *path = t_tmpfile("colours.3mf");
        hv_export_report r = export_3mf(v, path, bits);
        cr_expect_eq(r.colour, 1);
        hv_volume *plain = make_model(1);
        hv_export_report rp = export_3mf(plain, t_tmpfile("plain.3mf"), bits);
        hv_volume_destroy(plain);
        cr_expect_eq(rp.colour, 0);
        cr_expect_eq(r.arrays, rp.arrays + 1, "one more stack, the colour (not colour.r, .g, .b as properties)");
        cr_expect(strstr(r.names, ",colour") && !strstr(r.names, "grid.colour"), "%s", r.names);
        hv_volume *back = NULL;
        cr_assert_eq(hv_model_load(path, &back), HV_OK, "%s", hv_last_error());
        double worst = compare_colours(v, back, LO, HI, 1.0 / 255);
        /* 16 linear bits: within 12.92 / 65535 / 2 in sRGB, at the dark end where the curve is steepest */
        cr_expect(worst < 1.0e-4, "%d bits: largest colour error %g", bits, worst);
        cr_expect(worst > 0, "quantised at all");
        const char *json = hv_volume_meta_string(back, "hovox.colour.json");
        cr_assert_not_null(json, "the record back");
        json_error_t e;
        json_t *want = json_loads(COLOUR_JSON, 0, &e), *got = json_loads(json, 0, &e);
        cr_expect(want && got && json_equal(want, got), "record %s", json);
        json_decref(want);
        json_decref(got);
        hv_volume_destroy(back);
        hv_volume_destroy(v);
    }
}

/* A 16-bit RGBA PNG read by libpng (an independent reader): its size and samples. */
typedef struct png_mem {
    const uint8_t *data;
    size_t size, at;
} png_mem;

static void png_mem_read(png_structp png, png_bytep out, png_size_t n)
{
    png_mem *m = png_get_io_ptr(png);
    if (m->at + n > m->size) png_error(png, "truncated");
    memcpy(out, m->data + m->at, n);
    m->at += n;
}

static uint16_t *read_rgba16(const uint8_t *data, size_t size, unsigned *w, unsigned *h)
{
    png_mem m = {data, size, 0};
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    cr_assert(png && info);
    png_set_read_fn(png, &m, png_mem_read);
    png_read_info(png, info);
    cr_assert_eq(png_get_color_type(png, info), PNG_COLOR_TYPE_RGB_ALPHA, "an RGBA sheet");
    cr_assert_eq(png_get_bit_depth(png, info), 16, "of 16 bits");
    *w = png_get_image_width(png, info);
    *h = png_get_image_height(png, info);
    uint16_t *px = malloc((size_t)*w * *h * 8);
    for (unsigned y = 0; y < *h; ++y) {
        uint8_t row[8 * 64];
        cr_assert(*w <= 64);
        png_read_row(png, row, NULL);
        for (unsigned x = 0; x < 4 * *w; ++x) px[(size_t)y * 4 * *w + x] = (uint16_t)(row[2 * x] << 8 | row[2 * x + 1]);
    }
    png_destroy_read_struct(&png, &info, NULL);
    return px;
}

/* Does the relationships part hold a <Relationship Target="part"> of the 3D Texture type? */
static int texture_relationship(const char *rels, const char *part)
{
    char target[300];
    snprintf(target, sizeof target, "Target=\"%s\"", part);
    const char *at = strstr(rels, target);
    if (!at) return 0;
    const char *b = at, *e = strstr(at, "/>");
    while (b > rels && strncmp(b, "<Relationship", 13) != 0) --b;
    char elem[600];
    snprintf(elem, sizeof elem, "%.*s", e ? (int)(e - b) : 0, b);
    return strstr(elem, "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dtexture\"") != NULL;
}

static double lin(double c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }

/* lib3mf 1.8 predates the Volumetric extension (it reads the mesh and passes over the rest: see
 * test_lib3mf.c), so the colour's part of the package is checked here by hand against the spec:
 * the element and attribute names (check_node), volumedata's order (composite, color, property:
 * Appendix B), the colour image3d's OPC parts (3D Texture relationships, PNG content type), each
 * sheet a 16-bit RGBA PNG of the stack's size whose pixels hold the voxels' linear sRGB. */
Test(threemf_colour, the_colour_part_of_the_package_follows_the_spec)
{
    hv_volume *v = make_model(0);
    paint_grids(v);
    const char *path = t_tmpfile("colour_structure.3mf");
    hv_export_report r = export_3mf(v, path, 8);
    size_t n;
    char *model = zip_entry(path, "3D/3dmodel.model", &n), *mrels = zip_entry(path, "3D/_rels/3dmodel.model.rels", NULL);
    char *ct = zip_entry(path, "[Content_Types].xml", NULL);
    cr_expect(strstr(ct, "Extension=\"png\" ContentType=\"image/png\""));
    xmlDocPtr doc = xmlReadMemory(model, (int)n, "3dmodel.model", NULL, XML_PARSE_NONET);
    cr_assert_not_null(doc);
    xmlNodePtr root = xmlDocGetRootElement(doc), res = child(root, "resources");
    walk w;
    memset(&w, 0, sizeof w);
    check_node(root, &w);
    /* the record as metadata hovox:colour */
    int record = 0;
    for (xmlNodePtr e = root->children; e; e = e->next) {
        if (e->type != XML_ELEMENT_NODE || strcmp((const char *)e->name, "metadata") != 0) continue;
        char *nm = prop(e, "name");
        if (strcmp(nm, "hovox:colour") == 0) {
            xmlChar *text = xmlNodeGetContent(e);
            record = strcmp((const char *)text, COLOUR_JSON) == 0;
            xmlFree(text);
        }
        xmlFree(nm);
    }
    cr_expect(record, "metadata hovox:colour holds the record");
    /* the volume data: composite, color, properties, the mask last */
    xmlNodePtr vd = child(res, "volumedata"), kids[16];
    int nk = 0;
    for (xmlNodePtr c = vd->children; c && nk < 16; c = c->next)
        if (c->type == XML_ELEMENT_NODE) kids[nk++] = c;
    cr_assert_eq(nk, 1 + 1 + (r.arrays - 3 - 1) + 1, "composite, color, a property per property stack, the mask");
    cr_expect_str_eq((const char *)kids[0]->name, "composite");
    cr_expect_str_eq((const char *)kids[1]->name, "color");
    for (int i = 2; i < nk; ++i) cr_expect_str_eq((const char *)kids[i]->name, "property");
    char *cfn = prop(kids[1], "functionid"), *cch = prop(kids[1], "channel"), *ctr = prop(kids[1], "transform");
    char *mfn = prop(kids[nk - 1], "functionid"), *mch = prop(kids[nk - 1], "channel"), *mnm = prop(kids[nk - 1], "name");
    char *mreq = prop(kids[nk - 1], "required"), *mtr = prop(kids[nk - 1], "transform");
    char *mapt = prop(child(kids[0], "materialmapping"), "transform");
    cr_expect_str_eq(cch, "color", "the vector output (spec 2.2)");
    cr_expect_str_eq(mch, "alpha");
    cr_expect_str_eq(mnm, "hovox:colour.mask");
    cr_expect_str_eq(mreq, "false");
    cr_expect_str_eq(mfn, cfn);
    cr_expect_str_eq(ctr, mapt, "the colour samples the fractions' lattice");
    cr_expect_str_eq(mtr, mapt);
    /* its function: nearest (no blend with the empty pixels at the skin), clamp; its image3d "colour" */
    xmlNodePtr fn = NULL, im = NULL;
    for (xmlNodePtr e = res->children; e; e = e->next) {
        if (e->type != XML_ELEMENT_NODE) continue;
        char *id = prop(e, "id");
        if (id && strcmp((const char *)e->name, "functionfromimage3d") == 0 && strcmp(id, cfn) == 0) fn = e;
        xmlFree(id);
    }
    cr_assert_not_null(fn, "<v:color> names a functionfromimage3d");
    char *filter = prop(fn, "filter"), *imid = prop(fn, "image3did"), *scale = prop(fn, "valuescale"),
         *offset = prop(fn, "valueoffset");
    cr_expect_str_eq(filter, "nearest");
    cr_expect(strcmp(scale, "1") == 0 && strcmp(offset, "0") == 0);
    for (xmlNodePtr e = res->children; e; e = e->next) {
        if (e->type != XML_ELEMENT_NODE || strcmp((const char *)e->name, "image3d") != 0) continue;
        char *id = prop(e, "id");
        if (strcmp(id, imid) == 0) im = e;
        xmlFree(id);
    }
    cr_assert_not_null(im);
    char *imname = prop(im, "name");
    cr_expect_str_eq(imname, "colour");
    xmlNodePtr st = child(im, "imagestack");
    char *rc = prop(st, "rowcount"), *cc = prop(st, "columncount"), *sc = prop(st, "sheetcount");
    cr_expect(atoi(cc) == r.dims[0] && atoi(rc) == r.dims[1] && atoi(sc) == r.dims[2]);
    /* every sheet: a part with a 3D Texture relationship, a 16-bit RGBA PNG of the stack's size; the
     * pixel of voxel (i, j, k) at column i - lo, row hi - j (row 0: the highest y), sheet k - lo */
    hv_material_table *t;
    cr_assert_eq(hv_material_table_load(v, &t), HV_OK);
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    int og = hv_volume_grid_find(v, "occupancy"), gc[4], gm[3];
    static const char *const names[4] = {"colour.r", "colour.g", "colour.b", "colour.mask"};
    for (int c = 0; c < 4; ++c) gc[c] = hv_volume_grid_find(v, names[c]);
    for (int m = 0; m < 3; ++m) gm[m] = hv_material_grid(v, t, m);
    int k = 0, checked = 0;
    for (xmlNodePtr s = st->children; s; s = s->next) {
        if (s->type != XML_ELEMENT_NODE) continue;
        char *p = prop(s, "path"), want[200];
        snprintf(want, sizeof want, "/3D/volumetric/colour/sheet%04d.png", k + 1);
        cr_expect_str_eq(p, want);
        cr_expect(texture_relationship(mrels, p), "%s has a 3D Texture relationship", p);
        size_t pn;
        char *png = zip_entry(path, p + 1, &pn);
        cr_assert_not_null(png, "%s in the package", p);
        unsigned pw, ph;
        uint16_t *px = read_rgba16((const uint8_t *)png, pn, &pw, &ph);
        cr_assert(pw == (unsigned)r.dims[0] && ph == (unsigned)r.dims[1], "%s: %u x %u", p, pw, ph);
        for (unsigned y = 0; y < ph; ++y)
            for (unsigned x = 0; x < pw; ++x) {
                int i = (int)r.lo[0] + (int)x, j = (int)r.hi[1] - (int)y, kk = (int)r.lo[2] + k;
                const uint16_t *q = px + 4 * ((size_t)y * pw + x);
                if (!hv_accessor_bool(&acc, og, i, j, kk)) {
                    cr_assert(!q[0] && !q[1] && !q[2] && !q[3], "empty voxel (%d, %d, %d): 0", i, j, kk);
                    continue;
                }
                int asked = hv_accessor_float(&acc, gc[3], i, j, kk) > 0.5f;
                cr_assert_eq(q[3], asked ? 65535 : 0, "voxel (%d, %d, %d): alpha %u", i, j, kk, q[3]);
                for (int c = 0; c < 3; ++c) {
                    double want_c = 0;
                    if (asked) {
                        want_c = hv_accessor_float(&acc, gc[c], i, j, kk);
                    } else { /* the composition's colour, as a render shows it */
                        for (int m = 0; m < 3; ++m) {
                            float col[4];
                            hv_material_color(t, m, col);
                            want_c += hv_accessor_float(&acc, gm[m], i, j, kk) * col[c];
                        }
                    }
                    double got = q[c] / 65535.0;
                    cr_assert(fabs(got - lin(want_c)) <= 0.51 / 65535 + 1e-6, "voxel (%d, %d, %d) channel %d: %.6f, "
                              "want linear %.6f", i, j, kk, c, got, lin(want_c));
                }
                ++checked;
            }
        free(px);
        free(png);
        xmlFree(p);
        ++k;
    }
    cr_expect_eq(k, r.dims[2]);
    cr_expect_eq((uint64_t)checked, model_voxels(0));
    hv_material_table_destroy(t);
    xmlFree(rc), xmlFree(cc), xmlFree(sc), xmlFree(imname), xmlFree(filter), xmlFree(imid), xmlFree(scale);
    xmlFree(offset), xmlFree(cfn), xmlFree(cch), xmlFree(ctr), xmlFree(mfn), xmlFree(mch), xmlFree(mnm), xmlFree(mreq);
    xmlFree(mtr), xmlFree(mapt);
    xmlFreeDoc(doc);
    free(model);
    free(mrels);
    free(ct);
    hv_volume_destroy(v);
}

/* A cube `size` mm across painted 1 mm deep around an Agilus30 core, a colour per facet pair. */
static hv_volume *pairs_cube(double size, hv_mesh **m)
{
    static const uint32_t k_pair[12] = {0xE03020FFu, 0xE03020FFu, 0x20B040FFu, 0x20B040FFu, 0x3050E0FFu, 0x3050E0FFu,
                                        0xF0E020FFu, 0xF0E020FFu, 0x10D0D0FFu, 0x10D0D0FFu, 0x501020FFu, 0x501020FFu};
    return t_painted_cube(size, k_pair, 12, m);
}

/* A cube painted for real (hv_colour_paint, 1 mm deep around an Agilus30 core, a colour per facet
 * pair) comes back painted: the colours within 1/255, the same mask, the fractions within 1/255,
 * the record, so the colour map and the skin's dE2000 are made again from the package. */
Test(threemf_colour, a_painted_cube_comes_back_painted)
{
    hv_mesh *m = NULL;
    hv_volume *v = pairs_cube(6, &m);
    const char *path = t_tmpfile("painted.3mf");
    hv_export_report r = export_3mf(v, path, 8);
    cr_expect_eq(r.colour, 1);
    hv_volume *back = NULL;
    cr_assert_eq(hv_model_load(path, &back), HV_OK, "%s", hv_last_error());
    int lo[3] = {(int)r.lo[0], (int)r.lo[1], (int)r.lo[2]}, hi[3] = {(int)r.hi[0], (int)r.hi[1], (int)r.hi[2]};
    double worst = compare_colours(v, back, lo, hi, 1.0 / 255);
    cr_expect(worst < 1.0e-4, "largest colour error %g", worst);
    /* the fractions, within a step of 8 bits */
    hv_material_table *ta, *tb;
    cr_assert_eq(hv_material_table_load(v, &ta), HV_OK);
    cr_assert_eq(hv_material_table_load(back, &tb), HV_OK);
    cr_assert_eq(hv_material_count(tb), hv_material_count(ta));
    hv_accessor aa, ab;
    hv_accessor_init(&aa, v);
    hv_accessor_init(&ab, back);
    int og = hv_volume_grid_find(v, "occupancy");
    double fworst = 0;
    for (int i = lo[0]; i <= hi[0]; ++i)
        for (int j = lo[1]; j <= hi[1]; ++j)
            for (int k = lo[2]; k <= hi[2]; ++k) {
                if (!hv_accessor_bool(&aa, og, i, j, k)) continue;
                for (int q = 0; q < hv_material_count(ta); ++q) {
                    cr_assert_str_eq(hv_material_name(tb, q), hv_material_name(ta, q));
                    double fa = hv_accessor_float(&aa, hv_material_grid(v, ta, q), i, j, k);
                    double fb = hv_accessor_float(&ab, hv_material_grid(back, tb, q), i, j, k);
                    fworst = fmax(fworst, fabs(fa - fb));
                }
            }
    cr_expect(fworst <= 1.0 / 255 + 1e-6, "largest fraction error %g", fworst);
    /* the record: the same map, the same skin, the same dE2000 within what 8-bit fractions move */
    cr_expect_str_eq(hv_volume_meta_string(back, "hovox.colour.json"), hv_volume_meta_string(v, "hovox.colour.json"));
    hv_colour_map *ma = NULL, *mb = NULL;
    cr_assert_eq(hv_colour_map_for_model(v, &ma), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_colour_map_for_model(back, &mb), HV_OK, "%s", hv_last_error());
    hv_colour_skin_report ra, rb;
    cr_assert_eq(hv_colour_skin_error(v, ma, NULL, &ra), HV_OK);
    cr_assert_eq(hv_colour_skin_error(back, mb, NULL, &rb), HV_OK, "%s", hv_last_error());
    cr_expect_eq(rb.voxels, ra.voxels);
    cr_expect(fabs(rb.mean_de2000 - ra.mean_de2000) < 0.05, "mean dE2000 %g back, %g exported", rb.mean_de2000,
              ra.mean_de2000);
    hv_colour_map_destroy(ma);
    hv_colour_map_destroy(mb);
    hv_material_table_destroy(ta);
    hv_material_table_destroy(tb);
    hv_volume_destroy(back);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}

/* ---- colour as other producers write it ----------------------------------------------------------------
 * The spec's sampling written out again: the tile style on each UVW coordinate (2.2's formulas),
 * pixel centres at (index + 1/2) / n with V's index counted from the bottom row, "nearest" the
 * lower index on a tie, "linear" trilinear over the taps around (taps beyond an edge wrapped,
 * mirrored or clamped like the coordinate). */
static double tile_coord(double s, int style)
{
    if (style == 0) return s - floor(s);
    if (style == 1) return 1 - fabs(s - 2 * floor(s / 2) - 1);
    return fmin(1, fmax(0, s));
}

static int tap_index(int i, int n, int style)
{
    if (style == 0) return ((i % n) + n) % n;
    if (style == 1) return i < 0 ? -1 - i : i >= n ? 2 * n - 1 - i : i;
    return i < 0 ? 0 : i >= n ? n - 1 : i;
}

typedef double (*texel_fn)(int col, int row, int sheet, int ch); /* row: counted from the top */

static double spec_sample(texel_fn texel, const int n[3], const int tile[3], int nearest, const double uvw[3], int ch)
{
    double p[3];
    for (int b = 0; b < 3; ++b) p[b] = tile_coord(uvw[b], tile[b]) * n[b] - 0.5;
    if (nearest) {
        int i[3];
        for (int b = 0; b < 3; ++b) i[b] = tap_index((int)ceil(p[b] - 0.5), n[b], tile[b]);
        return texel(i[0], n[1] - 1 - i[1], i[2], ch);
    }
    double acc = 0;
    for (int d = 0; d < 8; ++d) {
        double w = 1;
        int i[3];
        for (int b = 0; b < 3; ++b) {
            int up = (d >> b) & 1;
            double f = p[b] - floor(p[b]);
            w *= up ? f : 1 - f;
            i[b] = tap_index((int)floor(p[b]) + up, n[b], tile[b]);
        }
        acc += w * texel(i[0], n[1] - 1 - i[1], i[2], ch);
    }
    return acc;
}

static double srgb(double c) { return c <= 0.0031308 ? c * 12.92 : 1.055 * pow(c, 1 / 2.4) - 0.055; }

static double rgb8_texel(int col, int row, int sheet, int ch) { return RGB[sheet][row][col][ch] / 255.0; }

/* the tint stack: 4 columns, 3 rows, 2 sheets of RGBA, 16 bits */
static uint16_t tint_value(int col, int row, int sheet, int ch)
{
    return (uint16_t)(hash3(col * 5 + ch, row + 17 * ch, sheet * 3 + 1) & 0xffffu);
}
static double tint_texel(int col, int row, int sheet, int ch) { return tint_value(col, row, sheet, ch) / 65535.0; }

static uint8_t *tint_png(int sheet, size_t *n)
{
    uint8_t px[3 * 4 * 8];
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col)
            for (int ch = 0; ch < 4; ++ch) {
                uint16_t v = tint_value(col, row, sheet, ch);
                px[(row * 4 + col) * 8 + 2 * ch] = (uint8_t)(v >> 8);
                px[(row * 4 + col) * 8 + 2 * ch + 1] = (uint8_t)v;
            }
    hv_png_options o;
    hv_png_options_init(&o);
    o.bit_depth = 16;
    uint8_t *data = NULL;
    cr_assert_eq(hv_png_encode(px, 4, 3, 4, 0, &o, &data, n), HV_OK);
    return data;
}

static const char *TINT =
    "  <v:image3d id=\"20\" name=\"tint\">\n"
    "   <v:imagestack rowcount=\"3\" columncount=\"4\" sheetcount=\"2\">\n"
    "    <v:imagesheet path=\"/Textures/tint/z0.png\"/>\n"
    "    <v:imagesheet path=\"/Textures/tint/layer-two.png\"/>\n"
    "   </v:imagestack>\n"
    "  </v:image3d>\n"
    "  <v:functionfromimage3d id=\"21\" image3did=\"20\" filter=\"linear\" valueoffset=\"0.05\" valuescale=\"0.9\" "
    "tilestyleu=\"mirror\" tilestylev=\"wrap\" tilestylew=\"clamp\"/>\n"
    "  <v:volumedata id=\"9\">";
/* turned a quarter about z and scaled: u = 2.5 y + 0.1, v = 1.2 - 2.5 x, w = 2 z + 0.05 (cm) */
static const double TINT_T[12] = {0, -2.5, 0, 2.5, 0, 0, 0, 0, 2, 0.1, 1.2, 0.05};
#define TINT_COLOR "   <v:color functionid=\"21\" channel=\"color\" transform=\"0 -2.5 0 2.5 0 0 0 0 2 0.1 1.2 0.05\"/>\n"

/* The foreign package with its colour replaced by `tint` (NULL: as it is), read; with the tint
 * stack's sheets in the package (under names of their own). */
static hv_status load_tinted(const char *model, const char *name, hv_volume **vol)
{
    size_t n[4];
    uint8_t *s0 = rgb_png(0, &n[0]), *s1 = rgb_png(1, &n[1]), *t0 = tint_png(0, &n[2]), *t1 = tint_png(1, &n[3]);
    entry e[7] = {{"[Content_Types].xml", TYPES, strlen(TYPES)}, {"_rels/.rels", RELS, strlen(RELS)},
                  {"3D/3dmodel.model", model, strlen(model)},   {"3D/vol/s0.png", s0, n[0]},
                  {"3D/vol/s1.png", s1, n[1]},                  {"Textures/tint/z0.png", t0, n[2]},
                  {"Textures/tint/layer-two.png", t1, n[3]}};
    const char *path = t_tmpfile(name);
    write_zip(path, e, 7);
    hv_status s = hv_3mf_load(path, vol, NULL);
    free(s0), free(s1), free(t0), free(t1);
    return s;
}

/* The colour of the foreign package's 6 x 4 x 3 voxels against the spec's sampling: (a) its
 * <v:color> on the RGB stack the composite reads (8 bits, nearest, tile styles, scale 2 and
 * offset -0.5, no transform: UVW = object centimetres); (b) a colour of its own on another
 * lattice: an RGBA stack of 16 bits named in a folder of its own, linear, turned a quarter about
 * z. The model holds the sRGB of the linear colour, truncated to [0, 1]; no mask: asked everywhere. */
static void check_foreign_colour(hv_volume *v, texel_fn texel, const int n[3], const int tile[3], int nearest,
                                 const double *T, double scale, double offset)
{
    static const char *const names[4] = {"colour.r", "colour.g", "colour.b", "colour.mask"};
    int g[4];
    for (int c = 0; c < 4; ++c) {
        g[c] = hv_volume_grid_find(v, names[c]);
        cr_assert(g[c] >= 0, "grid %s", names[c]);
    }
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    double lo = 1, hi = 0;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 3; ++k) {
                double x[3] = {0.05 + 0.1 * i, 0.05 + 0.1 * j, 0.05 + 0.1 * k}, w[3], idx[3], uvw[3];
                for (int a = 0; a < 3; ++a) w[a] = (x[a] + (a == 0 ? 0.5 : 0)) * 10;
                hv_volume_world_to_index(v, w, idx);
                int32_t p[3];
                for (int a = 0; a < 3; ++a) p[a] = (int32_t)floor(idx[a] + 0.5);
                for (int b = 0; b < 3; ++b)
                    uvw[b] = T ? x[0] * T[b] + x[1] * T[3 + b] + x[2] * T[6 + b] + T[9 + b] : x[b];
                cr_expect_eq(hv_accessor_float(&acc, g[3], p[0], p[1], p[2]), 1.0f);
                for (int c = 0; c < 3; ++c) {
                    double want = srgb(fmin(1, fmax(0, spec_sample(texel, n, tile, nearest, uvw, c) * scale + offset)));
                    double got = hv_accessor_float(&acc, g[c], p[0], p[1], p[2]);
                    cr_expect(fabs(got - want) < 2e-6, "voxel %d %d %d channel %d: %.6f, want %.6f", i, j, k, c, got, want);
                    lo = fmin(lo, want);
                    hi = fmax(hi, want);
                }
            }
    cr_expect(hi - lo > 0.3, "colours that differ (%g .. %g)", lo, hi);
}

Test(threemf_colour, a_foreign_colour_reads_through_its_own_function_and_lattice)
{
    char *model = foreign_model();
    hv_volume *v = NULL;
    cr_assert_eq(load_tinted(model, "foreign_colour.3mf", &v), HV_OK, "%s", hv_last_error());
    static const int rgb_n[3] = {3, 2, 2}, rgb_tile[3] = {0, 1, 2};
    check_foreign_colour(v, rgb8_texel, rgb_n, rgb_tile, 1, NULL, 2, -0.5);
    cr_expect_null(hv_volume_meta_string(v, "hovox.colour.json"), "no record: not painted by hovox");
    hv_volume_destroy(v);
    model = replace(model, "  <v:volumedata id=\"9\">", TINT);
    model = replace(model, "   <v:color functionid=\"8\" channel=\"color\"/>\n", TINT_COLOR);
    cr_assert_eq(load_tinted(model, "foreign_tint.3mf", &v), HV_OK, "%s", hv_last_error());
    static const int tint_n[3] = {4, 3, 2}, tint_tile[3] = {1, 0, 2};
    check_foreign_colour(v, tint_texel, tint_n, tint_tile, 0, TINT_T, 0.9, 0.05);
    hv_volume_destroy(v);
    free(model);
}

/* Every occupied voxel of v (the foreign mesh: a box of 0.02 .. 0.58 x 0.01 .. 0.39 x 0.04 .. 0.27 cm
 * moved 0.5 cm along x; on 1 mm voxels from its corner 6 x 4 x 2 centres inside) holds
 * the spec's sample of the colour at its centre through transform T, as sRGB (spec_sample: this
 * test's own sampler), and the six resins' fractions of that colour through the model's map;
 * at least `min` voxels. */
static void check_every_colour(hv_volume *v, texel_fn texel, const int n[3], const int tile[3], int nearest,
                               const double *T, double scale, double offset, int min)
{
    static const char *const names[3] = {"colour.r", "colour.g", "colour.b"};
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_for_model(v, &map), HV_OK, "%s", hv_last_error());
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_load(v, &t), HV_OK);
    int og = hv_volume_grid_find(v, "occupancy"), g[3], mg[HV_COLOUR_SLOTS], count = 0;
    for (int c = 0; c < 3; ++c) g[c] = hv_volume_grid_find(v, names[c]);
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) mg[k] = hv_material_grid(v, t, k);
    double worst = 0;
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l) {
        const int32_t *o = hv_volume_leaf_origins(v) + 3 * l;
        const uint64_t *in = hv_volume_leaf_bool_c(v, og, l);
        for (unsigned q = 0; q < 512; ++q) {
            if (!((in[q >> 6] >> (q & 63)) & 1u)) continue;
            double idx[3] = {o[0] + (double)(q >> 6), o[1] + (double)((q >> 3) & 7), o[2] + (double)(q & 7)}, w[3], x[3],
                   uvw[3];
            hv_volume_index_to_world(v, idx, w);
            for (int a = 0; a < 3; ++a) x[a] = w[a] / 10 - (a == 0 ? 0.5 : 0);
            for (int b = 0; b < 3; ++b) uvw[b] = x[0] * T[b] + x[1] * T[3 + b] + x[2] * T[6 + b] + T[9 + b];
            uint8_t rgba[4] = {0, 0, 0, 255};
            for (int c = 0; c < 3; ++c) {
                double want = srgb(fmin(1, fmax(0, spec_sample(texel, n, tile, nearest, uvw, c) * scale + offset)));
                double got = hv_volume_leaf_float_c(v, g[c], l)[q];
                worst = fmax(worst, fabs(got - want));
                rgba[c] = (uint8_t)lrint(want * 255);
            }
            float f[HV_COLOUR_SLOTS];
            hv_colour_map_fractions(map, rgba, f);
            for (int k = 0; k < HV_COLOUR_SLOTS; ++k)
                cr_assert_float_eq(hv_volume_leaf_float_c(v, mg[k], l)[q], f[k], 1e-6, "voxel %g %g %g resin %d", idx[0],
                                   idx[1], idx[2], k);
            ++count;
        }
    }
    cr_expect(worst < 2e-6, "colour %.3g away from the spec's sample", worst);
    cr_expect_geq(count, min, "%d voxels", count);
    hv_material_table_destroy(t);
    hv_colour_map_destroy(map);
}

/* Volume data with a colour and no composite (a colour printer's package): the colour's stack gives
 * the voxels, and the model prints in the six colour resins of the default colour map, each voxel
 * the fractions of its colour (as 8-bit sRGB), recorded so the colour map is made again. */
Test(threemf_colour, a_colour_without_a_composite_prints_in_the_colour_resins)
{
    char *model = foreign_model();
    model = replace(model, "   <v:composite basematerialid=\"5\">\n"
                           "    <v:materialmapping functionid=\"8\" channel=\"red\" transform=\"" T_MAP "\"/>\n"
                           "    <v:materialmapping functionid=\"8\" channel=\"green\" transform=\"" T_MAP "\"/>\n"
                           "    <v:materialmapping functionid=\"8\" channel=\"blue\" transform=\"" T_MAP "\"/>\n"
                           "   </v:composite>\n", "");
    char *turned = hv_strdup(model);
    model = replace(model, "<v:color functionid=\"8\" channel=\"color\"/>",
                    "<v:color functionid=\"8\" channel=\"color\" transform=\"" T_MAP "\"/>");
    hv_volume *v = NULL;
    cr_assert_eq(load_tinted(model, "colour_alone.3mf", &v), HV_OK, "%s", hv_last_error());
    static const int rgb_n[3] = {3, 2, 2}, rgb_tile[3] = {0, 1, 2};
    static const double T[12] = {3.3333333333333335, 0, 0, 0, 5, 0, 0, 0, 5, 0, 0, 0};
    check_foreign_colour(v, rgb8_texel, rgb_n, rgb_tile, 1, T, 2, -0.5);
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_for_model(v, &map), HV_OK, "%s", hv_last_error());
    cr_expect_str_eq(hv_colour_map_icc(map), hv_colour_default_icc());
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_load(v, &t), HV_OK);
    cr_assert_eq(hv_material_count(t), HV_COLOUR_SLOTS);
    int g[HV_COLOUR_SLOTS], cg[3] = {hv_volume_grid_find(v, "colour.r"), hv_volume_grid_find(v, "colour.g"),
                                     hv_volume_grid_find(v, "colour.b")};
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
        cr_expect_str_eq(hv_material_name(t, k), hv_colour_j750_resin(k));
        g[k] = hv_material_grid(v, t, k);
    }
    hv_accessor acc;
    hv_accessor_init(&acc, v);
    int og = hv_volume_grid_find(v, "occupancy"), n = 0;
    for (int i = -2; i < 20; ++i)
        for (int j = -2; j < 20; ++j)
            for (int k = -2; k < 20; ++k) {
                if (!hv_accessor_bool(&acc, og, i, j, k)) continue;
                uint8_t rgba[4] = {0, 0, 0, 255};
                for (int c = 0; c < 3; ++c) rgba[c] = (uint8_t)lrintf(hv_accessor_float(&acc, cg[c], i, j, k) * 255.0f);
                float want[HV_COLOUR_SLOTS];
                hv_colour_map_fractions(map, rgba, want);
                for (int q = 0; q < HV_COLOUR_SLOTS; ++q)
                    cr_assert_float_eq(hv_accessor_float(&acc, g[q], i, j, k), want[q], 1e-6, "voxel %d %d %d resin %d", i, j,
                                       k, q);
                ++n;
            }
    cr_expect_eq(n, 6 * 4 * 3);
    hv_material_table_destroy(t);
    hv_colour_map_destroy(map);
    hv_volume_destroy(v);
    /* turned a quarter and scaled (issue 29 item 3): axis-aligned voxels over the mesh's box as fine
     * as the image's finest step (the tint's 4 columns over 1/2.5 cm: 1 mm), each centre the spec's
     * sample of the colour through its own transform, and its fractions those of that colour */
    turned = replace(turned, "<v:color functionid=\"8\" channel=\"color\"/>", TINT_COLOR);
    turned = replace(turned, "  <v:volumedata id=\"9\">", TINT);
    cr_assert_eq(load_tinted(turned, "colour_turned.3mf", &v), HV_OK, "%s", hv_last_error());
    cr_expect_float_eq(hv_volume_get_transform(v).voxel[0], 1.0, 1e-12);
    static const int tint_n[3] = {4, 3, 2}, tint_tile[3] = {1, 0, 2};
    check_every_colour(v, tint_texel, tint_n, tint_tile, 0, TINT_T, 0.9, 0.05, 6 * 4 * 2);
    hv_volume_destroy(v);
    free(turned);
    free(model);
}

/* A bad colour is refused with one message naming the file, the element, its line and column. */
static void expect_colour_refused(const char *from, const char *to, hv_status want, const char *words)
{
    char *model = foreign_model();
    model = replace(model, "  <v:volumedata id=\"9\">", TINT);
    model = replace(model, "   <v:color functionid=\"8\" channel=\"color\"/>\n", TINT_COLOR);
    model = replace(model, from, to);
    hv_volume *v = NULL;
    hv_status s = load_tinted(model, "bad_colour.3mf", &v);
    free(model);
    check_refused(s, v, from, to, "bad_colour.3mf", want, words);
}

Test(threemf_colour, a_bad_colour_is_refused_naming_the_place)
{
    expect_colour_refused("<v:color functionid=\"21\"", "<v:color functionid=\"22\"", HV_ERR_BAD_INPUT,
                          "3D/3dmodel.model: line 30, column 92: <v:color> functionid 22 names no function");
    expect_colour_refused("channel=\"color\" transform", "channel=\"red\" transform", HV_ERR_BAD_INPUT,
                          "line 30, column 90: <v:color> channel 'red' is not a vector output of the "
                          "<v:functionfromimage3d> on line 23 (color; red, green, blue and alpha are scalars)");
    expect_colour_refused("channel=\"color\" transform", "channel=\"colour\" transform", HV_ERR_BAD_INPUT,
                          "<v:color> channel 'colour' is not a vector output");
    expect_colour_refused("  </v:volumedata>", "   <v:property name=\"h:colour.mask\" xmlns:h=\"urn:hovox:3mf:2025\" "
                          "functionid=\"21\" channel=\"color\"/>\n  </v:volumedata>", HV_ERR_BAD_INPUT,
                          "<v:property> hovox:colour.mask channel 'color' is not a scalar output");
    expect_colour_refused("  </v:volumedata>", TINT_COLOR "  </v:volumedata>", HV_ERR_BAD_INPUT,
                          "<v:volumedata> id 9 has more than one <v:color>");
    expect_colour_refused("<v:functionfromimage3d id=\"21\" image3did=\"20\"",
                          "<i:implicitfunction id=\"21\" xmlns:i=\"http://schemas.3mf.io/3dmanufacturing/implicit/2023/12\"/>"
                          "<v:functionfromimage3d id=\"23\" image3did=\"20\"", HV_ERR_UNSUPPORTED,
                          "<v:color> functionid 21 is a <i:implicitfunction>");
    /* the stack's sheets: one of another size (the RGB sheet of 3 x 2), one that is no picture */
    expect_colour_refused("/Textures/tint/layer-two.png", "/3D/vol/s1.png", HV_ERR_BAD_INPUT,
                          "line 20, column 40: <v:imagesheet> /3D/vol/s1.png is 3 x 2 pixels; its <v:imagestack> has 4 "
                          "columns and 3 rows");
    expect_colour_refused("/Textures/tint/layer-two.png", "/3D/3dmodel.model", HV_ERR_BAD_INPUT,
                          "line 20, column 43: <v:imagesheet> /3D/3dmodel.model: not a PNG (no PNG signature)");
}

/* ---- refused ---------------------------------------------------------------------------------------- */

static void expect_refused(const char *from, const char *to, hv_status want, const char *words)
{
    char *model = foreign_model();
    if (from) model = replace(model, from, to);
    hv_volume *v = NULL;
    hv_status s = load_foreign(model, 2, "refused.3mf", &v, NULL);
    free(model);
    check_refused(s, v, from, to, "refused.3mf", want, words);
}

/* Issue 26: the reader voxelizes through src/voxel (its centre vote, the winding number where the
 * lines tie), not a one-axis parity of its own: a box whose top face is missing (two triangles
 * left out, as scanners and careless exporters leave them) still gives every voxel of the box. */
Test(threemf, an_open_mesh_still_gives_its_voxels)
{
    char *model = foreign_model();
    model = replace(model, "     <triangle v1=\"4\" v2=\"5\" v3=\"7\"/>\n     <triangle v1=\"4\" v2=\"7\" v3=\"6\"/>\n", "");
    hv_volume *v = NULL;
    cr_assert_eq(load_foreign(model, 2, "open.3mf", &v, NULL), HV_OK, "%s", hv_last_error());
    cr_expect_eq(hv_volume_mask_count(v, hv_volume_grid_find(v, "occupancy")), 6u * 4u * 3u);
    hv_volume_destroy(v);
    free(model);
}

Test(threemf, damaged_and_unsupported_packages_are_refused_naming_the_place)
{
    expect_refused("v1=\"0\" v2=\"2\"", "v1=\"0\" v2=\"8\"", HV_ERR_BAD_INPUT,
                   "line 38, column 36: <triangle> 0: v2 = 8 is out of range (the mesh has 8 vertices)");
    expect_refused("rowcount=\"2\"", "rowcount=\"0\"", HV_ERR_BAD_INPUT, "<v:imagestack> rowcount '0' is not a positive integer");
    expect_refused("rowcount=\"2\"", "rowcount=\"3\"", HV_ERR_BAD_INPUT,
                   "line 12, column 40: <v:imagesheet> /3D/vol/s0.png is 3 x 2 pixels; its <v:imagestack> has 3 columns "
                   "and 3 rows");
    expect_refused("sheetcount=\"2\"", "sheetcount=\"3\"", HV_ERR_BAD_INPUT, "sheetcount 3 but 2 imagesheets");
    expect_refused("x=\"0.02\"", "x=\"nan\"", HV_ERR_BAD_INPUT, "<vertex> 0: x 'nan' is not a finite number");
    expect_refused("<v:volumedata id=\"9\">", "<v:volumedata id=\"7\">", HV_ERR_BAD_INPUT, "resource id 7 is used twice");
    expect_refused("functionid=\"8\" channel=\"green\"", "functionid=\"3\" channel=\"green\"", HV_ERR_BAD_INPUT,
                   "functionid 3 names no function");
    expect_refused("    <v:materialmapping functionid=\"8\" channel=\"blue\" transform=\"" T_MAP "\"/>\n", "",
                   HV_ERR_BAD_INPUT, "has 2 materialmappings for the 3 base materials");
    expect_refused("channel=\"blue\"", "channel=\"color\"", HV_ERR_BAD_INPUT, "channel 'color' is not a scalar output");
    expect_refused("3.3333333333333335 0 0 0 5 0", "3.3333333333333335 0.5 0 0 5 0", HV_ERR_UNSUPPORTED,
                   "transform is not an axis-aligned scale");
    expect_refused("v:volumeid=\"9\"", "", HV_ERR_UNSUPPORTED, "carries no volume data");
    expect_refused("<v:volumedata id=\"9\">", "<v:volumedata id=\"9\"><v:property name=\"x:temp\" xmlns:x=\"urn:x\" "
                   "functionid=\"8\" channel=\"red\" required=\"true\"/>", HV_ERR_UNSUPPORTED,
                   "<v:property> 'x:temp' is required");
    expect_refused("<v:functionfromimage3d id=\"8\" image3did=\"7\"",
                   "<i:implicitfunction id=\"8\" xmlns:i=\"http://schemas.3mf.io/3dmanufacturing/implicit/2023/12\"/>"
                   "<v:functionfromimage3d id=\"18\" image3did=\"7\"", HV_ERR_UNSUPPORTED,
                   "functionid 8 is a <i:implicitfunction>");
    expect_refused("<mesh v:volumeid=\"9\">", "<v:levelset functionid=\"8\" channel=\"red\" meshid=\"1\"/><mesh>",
                   HV_ERR_BAD_INPUT, "more than one shape");
    expect_refused("<object id=\"1\" type=\"model\">\n   <mesh v:volumeid=\"9\">",
                   "<object id=\"1\" type=\"model\"><v:levelset functionid=\"8\" channel=\"red\" meshid=\"2\"/></object>\n"
                   "  <object id=\"2\" type=\"model\">\n   <mesh v:volumeid=\"9\">",
                   HV_ERR_UNSUPPORTED, "<v:levelset> of object 1: level-set shapes are not supported");
    expect_refused("requiredextensions=\"v\"", "requiredextensions=\"v b\" xmlns:b=\"http://schemas.microsoft.com/"
                   "3dmanufacturing/beamlattice/2017/02\"", HV_ERR_UNSUPPORTED, "requires the extension");
    expect_refused("transform=\"1 0 0 0 1 0 0 0 1 0.5 0 0\"", "transform=\"0 1 0 -1 0 0 0 0 1 0 0 0\"",
                   HV_ERR_UNSUPPORTED, "<item> transform rotates or scales");
    expect_refused("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n",
                   "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!DOCTYPE model [<!ENTITY a \"b\">]>\n",
                   HV_ERR_BAD_INPUT, "DOCTYPE is not allowed");
    expect_refused("</basematerials>", "</basematerial>", HV_ERR_BAD_INPUT, "line 9, column 18: malformed XML: Opening and ending tag mismatch");
    expect_refused("unit=\"centimeter\"", "unit=\"furlong\"", HV_ERR_BAD_INPUT, "unit 'furlong'");
    /* a sheet missing from the package */
    char *model = foreign_model();
    hv_volume *v = NULL;
    cr_expect_eq(load_foreign(model, 1, "nosheet.3mf", &v, NULL), HV_ERR_BAD_INPUT);
    cr_expect(strstr(hv_last_error(), "line 13, column 40: <v:imagesheet> /3D/vol/s1.png is missing from the package"), "%s", hv_last_error());
    /* no model part; not a zip; truncated */
    entry e[2] = {{"[Content_Types].xml", TYPES, strlen(TYPES)}, {"_rels/.rels", RELS, strlen(RELS)}};
    const char *p = t_tmpfile("nomodel.3mf");
    write_zip(p, e, 2);
    cr_expect_eq(hv_3mf_load(p, &v, NULL), HV_ERR_BAD_INPUT);
    cr_expect(strstr(hv_last_error(), "missing model part '/3D/3dmodel.model' (named by _rels/.rels)"), "%s", hv_last_error());
    cr_expect_eq(hv_3mf_parse("PK\3\4abc", 7, "cut.3mf", &v, NULL), HV_ERR_BAD_INPUT);
    cr_expect(strncmp(hv_last_error(), "cut.3mf: not a 3MF package: not a readable ZIP archive", 54) == 0, "%s",
              hv_last_error());
    free(model);
}

Test(threemf, reading_stays_inside_the_memory_budget)
{
    hv_volume *big = make_model(0);
    const char *path = t_tmpfile("budget.3mf");
    export_3mf(big, path, 8);
    hv_volume_destroy(big);
    hv_set_memory_cap(64 << 10);
    hv_volume *v = NULL;
    hv_status s = hv_model_load(path, &v);
    hv_set_memory_cap(0);
    cr_expect_eq(s, HV_ERR_LIMIT, "%s", hv_last_error());
    cr_expect(strstr(hv_last_error(), "memory budget") != NULL, "%s", hv_last_error());
    cr_expect_null(v);
}

/* A tight budget keeps the sheets in temporary files instead of memory: the same bytes. */
Test(threemf, sheets_through_temporary_files_give_the_same_package)
{
    hv_transform xf = {{0.1, 0.1, 0.1}, {0, 0, 0}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK);
    int lo[3] = {0, 0, 0}, hi[3] = {63, 63, 95};
    cr_assert_eq(t_add_box(v, lo, hi), HV_OK);
    int og, g[3];
    hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, &og);
    static const char *const names[3] = {"a", "b", "c"};
    hv_material_table *t;
    hv_material_table_create(&t);
    for (int m = 0; m < 3; ++m) {
        char gn[32];
        snprintf(gn, sizeof gn, "material.%s", names[m]);
        hv_volume_grid_add(v, gn, HV_GRID_FLOAT, &g[m]);
        hv_material_add(t, names[m], NULL, NULL);
    }
    hv_material_table_store(v, t);
    hv_material_table_destroy(t);
    const int32_t *orig = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned n = 0; n < 512; ++n) {
            hv_volume_leaf_bool(v, og, l)[n >> 6] |= 1ull << (n & 63);
            float f[3];
            fractions_at(orig[3 * l] + (int)(n >> 6), orig[3 * l + 1] + (int)((n >> 3) & 7), orig[3 * l + 2] + (int)(n & 7), f);
            for (int m = 0; m < 3; ++m) hv_volume_leaf_float(v, g[m], l)[n] = f[m];
        }
    const char *a = t_tmpfile("mem.3mf"), *b = t_tmpfile("files.3mf");
    hv_export_options o;
    hv_export_options_init(&o);
    o.volumetric = 1;
    hv_export_report r;
    cr_assert_eq(hv_export_write(v, a, &o, &r), HV_OK, "%s", hv_last_error());
    /* 3 stacks of 64 x 64 x 96 bytes: more than a quarter of 3.5 MiB, so the sheets go through files */
    o.max_memory = 7u << 19;
    cr_assert_eq(hv_export_write(v, b, &o, &r), HV_OK, "%s", hv_last_error());
    cr_expect(r.memory_bytes < (7u << 19), "%llu", (unsigned long long)r.memory_bytes);
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "cmp -s '%s' '%s'", a, b);
    cr_expect_eq(t_run(cmd, NULL), 0, "the same package either way");
    cr_expect_eq(count_entries(t_tmpdir(), "tmp-"), 0, "no temporary left");
    hv_volume_destroy(v);
}

/* The colour reader's single-thread way (colour_slab, issue 26 review): when a slab's image sheets
 * would take more than its allowance, one thread samples through a few least-recently-used sheets
 * in place of the sheets decoded ahead for all threads. Forced here by lowering the allowance
 * (tmf_colour_sheets_max): to none, every slab one thread's; to one and a half sheets, the cube's
 * slab that samples one sheet decoded ahead and its slabs that sample 5 and 8 (of 4 slots) one
 * thread's. The same colour grids, bit for bit, as the threaded read on 2 threads and on 1. */
Test(threemf_colour, the_single_thread_colour_read_gives_the_threaded_colours, .timeout = 120)
{
    hv_mesh *m = NULL;
    hv_volume *v = pairs_cube(10, &m);
    const char *path = t_tmpfile("painted_slabs.3mf");
    hv_export_report r = export_3mf(v, path, 16);
    cr_assert_eq(r.colour, 1);
    const uint64_t sheet = (uint64_t)(r.hi[0] - r.lo[0] + 1) * (uint64_t)(r.hi[1] - r.lo[1] + 1) * 4 * sizeof(uint16_t);
    const uint64_t kept = tmf_colour_sheets_max;
    const struct {
        int threads;
        uint64_t max;
    } k_way[4] = {{2, kept}, {1, kept}, {2, 0}, {2, sheet + sheet / 2}};
    hv_volume *back[4] = {NULL, NULL, NULL, NULL};
    for (int w = 0; w < 4; ++w) {
        hv_set_threads(k_way[w].threads);
        tmf_colour_sheets_max = k_way[w].max;
        hv_status s = hv_model_load(path, &back[w]);
        tmf_colour_sheets_max = kept;
        hv_set_threads(0);
        cr_assert_eq(s, HV_OK, "%s", hv_last_error());
    }
    static const char *const names[4] = {"colour.r", "colour.g", "colour.b", "colour.mask"};
    size_t nl = hv_volume_leaf_count(back[0]);
    cr_assert_gt(nl, 8, "slabs of several leaves");
    for (int w = 1; w < 4; ++w) {
        cr_assert_eq(hv_volume_leaf_count(back[w]), nl);
        for (int k = 0; k < 4; ++k) {
            int ga = hv_volume_grid_find(back[0], names[k]), gb = hv_volume_grid_find(back[w], names[k]);
            cr_assert(ga >= 0 && gb >= 0, "%s", names[k]);
            for (size_t l = 0; l < nl; ++l)
                cr_assert(memcmp(hv_volume_leaf_float(back[0], ga, l), hv_volume_leaf_float(back[w], gb, l),
                                 512 * sizeof(float)) == 0,
                          "way %d (%d threads, sheets ahead at most %llu bytes): %s differs in leaf %zu", w,
                          k_way[w].threads, (unsigned long long)k_way[w].max, names[k], l);
        }
    }
    /* and they are the painted colours */
    int lo[3] = {(int)r.lo[0], (int)r.lo[1], (int)r.lo[2]}, hi[3] = {(int)r.hi[0], (int)r.hi[1], (int)r.hi[2]};
    cr_expect(compare_colours(v, back[2], lo, hi, 1.0 / 255) < 1.0e-4);
    for (int w = 0; w < 4; ++w) hv_volume_destroy(back[w]);
    hv_volume_destroy(v);
    hv_mesh_destroy(m);
}
