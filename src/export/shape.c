/* src/export/shape.c - the model's shape as a surface (issue 28, "Geometry truth"): .stl and .obj
 * exports write the shape the model records, not its voxels. A model whose shape is one recorded
 * mesh (a plain model, or a Boolean of a mesh with itself) is written as that mesh, placed by its
 * transform: exact, watertight when the source was, no stair steps. */
#include <string.h>
#include <sys/stat.h>

#include "export_internal.h"
#include "hovox/geometry.h"
#include "hovox/mesh.h"

/* The surface of the shape `vol` records; *out owned by the caller. */
static hv_status shape_mesh(const hv_volume *vol, hv_mesh **out)
{
    *out = NULL;
    if (!hv_geometry_present(vol))
        return hv_error_set(HV_ERR_INVALID, "export: the model records no shape (made before hovox recorded the "
                                            "meshes a model comes from): export its mesh, or .3mf for the voxels");
    hv_geometry *g = NULL;
    hv_status s = hv_geometry_read(vol, &g);
    if (s != HV_OK) return hv_error_prefix(s, "export: ");
    if (!hv_geometry_shape_is_leaf(g)) {
        s = hv_error_set(HV_ERR_UNSUPPORTED, "%s: export: the model's shape is a Boolean of %zu recorded shapes; "
                                             "its surface as .stl or .obj is not supported yet (.3mf writes the voxels)",
                         hv_volume_name(vol), hv_geometry_leaf_count(g));
    } else if (hv_geometry_leaf_at(g, 0)->kind != HV_LEAF_MESH) {
        s = hv_error_set(HV_ERR_UNSUPPORTED, "%s: export: the model's shape is a scanned field's iso-surface; .stl "
                                             "and .obj export recorded meshes only", hv_volume_name(vol));
    } else {
        s = hv_geometry_leaf_mesh(g, 0, out);
        if (s != HV_OK) s = hv_error_prefix(s, "export: ");
    }
    hv_geometry_destroy(g);
    return s;
}

static void shape_report(const hv_mesh *m, hv_export_report *r)
{
    r->cells = hv_mesh_facet_count(m);
    r->points = hv_mesh_vertex_count(m);
    /* the mesh as held, about 12 bytes per vertex and 12 per facet, plus the writer's buffer */
    r->memory_bytes = (uint64_t)(12 * r->points + 12 * r->cells) + (1u << 16);
    snprintf(r->names, sizeof r->names, "%s", hv_mesh_name(m));
    snprintf(r->notes, sizeof r->notes, "%s", "");
}

hv_status ex_shape_plan(const hv_volume *vol, hv_export_report *r)
{
    hv_mesh *m = NULL;
    hv_status s = shape_mesh(vol, &m);
    if (s == HV_OK) shape_report(m, r);
    hv_mesh_destroy(m);
    return s;
}

hv_status ex_shape_write(const hv_volume *vol, const char *path, hv_export_report *r)
{
    hv_mesh *m = NULL;
    hv_status s = shape_mesh(vol, &m);
    if (s == HV_OK) {
        shape_report(m, r);
        s = r->format == HV_EXPORT_OBJ ? hv_mesh_write_obj(m, path) : hv_mesh_write_stl(m, path, 0);
    }
    struct stat st;
    if (s == HV_OK) r->file_bytes = stat(path, &st) == 0 ? (uint64_t)st.st_size : 0;
    hv_mesh_destroy(m);
    return s;
}
