/* src/io/3mf/shape_write.c - the shape a model records as a 3MF core package (3MF Core 1.3 with the
 * materials extension's base materials; issue 28): one object, its triangles in the model's
 * materials, what every slicer reads. The Volumetric package of the voxels is volumetric_write.c. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/zip.h"
#include "export/export_internal.h"
#include "hovox/material.h"
#include "threemf_internal.h"

static void base_materials(hv_buf *b, const hv_material_table *t)
{
    hv_buf_puts(b, "  <basematerials id=\"1\">\n");
    for (int j = 0; j < hv_material_count(t); ++j) {
        float rgba[4];
        int c[4];
        hv_material_color(t, j, rgba);
        for (int i = 0; i < 4; ++i) c[i] = (int)HV_CLAMP(floor(rgba[i] * 255.0f + 0.5f), 0.0, 255.0);
        hv_buf_puts(b, "   <base name=\"");
        hv_buf_put_escaped(b, hv_material_name(t, j));
        hv_buf_printf(b, "\" displaycolor=\"#%02X%02X%02X%02X\"/>\n", c[0], c[1], c[2], c[3]);
    }
    hv_buf_puts(b, "  </basematerials>\n");
}

/* %.9g round-trips a float; -0 printed as 0 */
static void coord(hv_buf *b, const char *name, float v)
{
    hv_buf_printf(b, " %s=\"%.9g\"", name, v == 0 ? 0.0 : (double)v);
}

static hv_status model_part(hv_buf *b, const char *name, const hv_mesh *m, const hv_material_table *t,
                            const int32_t *fmat, int32_t def, const hv_progress *progress)
{
    hv_buf_printf(b, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                     "<model unit=\"millimeter\" xml:lang=\"en-US\" xmlns=\"%s\">\n"
                     " <metadata name=\"Application\">hovox %s</metadata>\n"
                     " <metadata name=\"Title\">",
                  TMF_NS_CORE, hv_version());
    hv_buf_put_escaped(b, name);
    hv_buf_puts(b, "</metadata>\n <resources>\n");
    if (t) base_materials(b, t);
    hv_buf_puts(b, "  <object id=\"2\" type=\"model\" name=\"");
    hv_buf_put_escaped(b, name);
    hv_buf_puts(b, "\"");
    if (t) hv_buf_printf(b, " pid=\"1\" pindex=\"%d\"", (int)def);
    hv_buf_puts(b, ">\n   <mesh>\n    <vertices>\n");
    const float *p = hv_mesh_vertices(m);
    size_t nv = hv_mesh_vertex_count(m), nf = hv_mesh_facet_count(m);
    hv_status s = HV_OK;
    for (size_t v = 0; v < nv && s == HV_OK; ++v) {
        hv_buf_puts(b, "     <vertex");
        coord(b, "x", p[3 * v]);
        coord(b, "y", p[3 * v + 1]);
        coord(b, "z", p[3 * v + 2]);
        hv_buf_puts(b, "/>\n");
        if ((v & 0xffff) == 0xffff) s = hv_progress_report(progress, "export write", 0.4 * (double)v / (double)(nv + nf));
    }
    hv_buf_puts(b, "    </vertices>\n    <triangles>\n");
    const uint32_t *f = hv_mesh_facets(m);
    for (size_t i = 0; i < nf && s == HV_OK; ++i) {
        hv_buf_printf(b, "     <triangle v1=\"%u\" v2=\"%u\" v3=\"%u\"", f[3 * i], f[3 * i + 1], f[3 * i + 2]);
        /* a triangle in the object's material says nothing: p1 only where it differs */
        if (t && fmat && fmat[i] != HV_MESH_NO_MATERIAL && fmat[i] != def) hv_buf_printf(b, " pid=\"1\" p1=\"%d\"", (int)fmat[i]);
        hv_buf_puts(b, "/>\n");
        if ((i & 0xffff) == 0xffff)
            s = hv_progress_report(progress, "export write", 0.4 * (double)(nv + i) / (double)(nv + nf));
    }
    hv_buf_puts(b, "    </triangles>\n   </mesh>\n  </object>\n </resources>\n"
                   " <build>\n  <item objectid=\"2\"/>\n </build>\n</model>\n");
    return s;
}

hv_status ex_3mf_shape_write(const char *name, const hv_mesh *m, const hv_material_table *t, const int32_t *fmat,
                             int32_t def, const char *path, int level, const hv_progress *progress)
{
    static const char content_types[] =
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        "<Types xmlns=\"" TMF_NS_CONTENT_TYPES "\">\n"
        " <Default Extension=\"rels\" ContentType=\"" TMF_CT_RELATIONSHIPS "\"/>\n"
        " <Default Extension=\"model\" ContentType=\"" TMF_CT_MODEL "\"/>\n"
        "</Types>\n";
    static const char rels[] = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                               "<Relationships xmlns=\"" TMF_NS_RELATIONSHIPS "\">\n"
                               " <Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" Type=\"" TMF_REL_MODEL "\"/>\n"
                               "</Relationships>\n";
    hv_zip *z = NULL;
    hv_status s = hv_zip_open(path, &z); /* first: an unwritable place fails before any work */
    hv_buf b;
    hv_buf_init(&b);
    if (s == HV_OK) s = model_part(&b, name, m, t, fmat, def, progress);
    if (s == HV_OK && (b.failed || !b.data)) s = HV_ERR_NOMEM;
    if (s == HV_OK) s = hv_zip_add_data(z, "[Content_Types].xml", content_types, sizeof content_types - 1, 1);
    if (s == HV_OK) s = hv_zip_add_data(z, "_rels/.rels", rels, sizeof rels - 1, 1);
    if (s == HV_OK) {
        hv_zip_set_level(z, level);
        s = hv_zip_add_owned(z, "3D/3dmodel.model", b.data, b.len, 1); /* the text is not copied */
        hv_buf_init(&b);
    }
    hv_buf_free(&b);
    if (s == HV_OK) s = hv_zip_write(z, progress, "export write");
    if (s == HV_OK) {
        s = hv_zip_commit(z);
        z = NULL;
    }
    if (z) hv_zip_abort(z);
    return s;
}
