/* tests/io/reader_check.h - what the OBJ, PLY and 3MF reader tests share: the STL reader as
 * the reference on the same mesh, the report compared field by field, a refusal checked for
 * its status and exact message. */
#ifndef HOVOX_TEST_READER_CHECK_H
#define HOVOX_TEST_READER_CHECK_H

#include <criterion/criterion.h>
#include <string.h>

#include "hovox/mesh.h"
#include "support/support.h"

/* A shared mesh through the STL reader: the reference. */
static inline hv_mesh *stl_reference(const char *name)
{
    hv_mesh *m = NULL;
    cr_assert_eq(hv_mesh_load_stl(t_mesh_path(name), &m), HV_OK, "%s", hv_last_error());
    return m;
}

/* Same report as the reference, but for the format and the stored normals (STL only). */
static inline void same_report(const hv_mesh *got, const hv_mesh *ref, double volume_tol)
{
    const hv_mesh_report *a = hv_mesh_get_report(got), *b = hv_mesh_get_report(ref);
    cr_assert_eq(a->facets, b->facets);
    cr_assert_eq(a->vertices, b->vertices);
    cr_assert_eq(a->shells, b->shells);
    cr_assert_eq(a->open_edges, b->open_edges);
    cr_assert_eq(a->nonmanifold_edges, b->nonmanifold_edges);
    cr_assert_eq(a->degenerate_facets, b->degenerate_facets);
    cr_assert_eq(a->flipped_facets, b->flipped_facets);
    if (volume_tol == 0) {
        cr_assert_eq(a->volume, b->volume, "volume %.17g vs %.17g", a->volume, b->volume);
        cr_assert_eq(a->area, b->area);
        for (int k = 0; k < 3; ++k) {
            cr_assert_eq(a->bbox_min[k], b->bbox_min[k]);
            cr_assert_eq(a->bbox_max[k], b->bbox_max[k]);
        }
    } else {
        cr_assert_float_eq(a->volume, b->volume, volume_tol * (b->volume < 0 ? -b->volume : b->volume));
    }
}

/* parse(text) must fail with `status` and exactly `message`, handing out no mesh. */
typedef hv_status (*t_parse_fn)(const void *, size_t, const char *, hv_mesh **);
static inline void refused(t_parse_fn parse, const char *name, const void *data, size_t size, hv_status status,
                           const char *message)
{
    hv_mesh *m = (hv_mesh *)1;
    hv_status s = parse(data, size, name, &m);
    cr_assert_eq(s, status, "%s: status %d (%s)", name, (int)s, hv_last_error());
    cr_assert_null(m, "%s: a mesh on failure", name);
    cr_assert_str_eq(hv_last_error(), message);
}

#endif
