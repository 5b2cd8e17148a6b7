// tests/voxel/test_oracle.cpp - the voxelizer against OpenVDB's own tools::meshToVolume on
// the same transform: no voxel deeper than 1.5 voxels inside the oracle's surface may be
// missing from `occupancy`, and no occupied voxel may lie more than 1.5 voxels outside.
#include <criterion/criterion.h>

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <cmath>
#include <string>
#include <vector>

extern "C" {
#include "hovox/generate.h"
#include "hovox/voxelize.h"
#include "support/support.h"
}

static openvdb::FloatGrid::Ptr oracle(const hv_mesh *m, const hv_transform &xf, float interior)
{
    auto x = openvdb::math::Transform::createLinearTransform(xf.voxel[0]);
    x->postTranslate(openvdb::Vec3d(xf.origin[0], xf.origin[1], xf.origin[2]));
    // the mesh adapter hands meshToVolume index-space points
    std::vector<openvdb::Vec3s> pts;
    std::vector<openvdb::Vec3I> tris;
    const float *v = hv_mesh_vertices(m);
    for (size_t i = 0; i < hv_mesh_vertex_count(m); ++i)
        pts.emplace_back(x->worldToIndex(openvdb::Vec3d(v[3 * i], v[3 * i + 1], v[3 * i + 2])));
    const uint32_t *t = hv_mesh_facets(m);
    for (size_t f = 0; f < hv_mesh_facet_count(m); ++f) tris.emplace_back(t[3 * f], t[3 * f + 1], t[3 * f + 2]);
    openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> mesh(pts, tris);
    // signed distance in voxel units inside out to `interior` voxels, 3 outside
    return openvdb::tools::meshToVolume<openvdb::FloatGrid>(mesh, *x, 3.0f, interior);
}

static void compare(const hv_mesh *m, int adjacency, int64_t dims, const char *what)
{
    openvdb::initialize();
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.adjacency = adjacency;
    o.dims[0] = dims;
    hv_volume *vol = nullptr;
    cr_assert_eq(hv_voxelize(m, &o, &vol), HV_OK, "%s", hv_last_error());
    hv_transform xf = hv_volume_get_transform(vol);
    cr_assert(xf.voxel[0] == xf.voxel[1] && xf.voxel[1] == xf.voxel[2]);
    auto sdf = oracle(m, xf, float(dims));
    auto acc = sdf->getConstAccessor();
    const double L = xf.voxel[0], tol = 1.5 * L;
    int g = hv_volume_grid_find(vol, "occupancy");
    hv_accessor va;
    hv_accessor_init(&va, vol);
    int32_t lo[3], hi[3];
    cr_assert(hv_volume_index_bbox(vol, lo, hi));
    long missing = 0, outside = 0, checked = 0;
    for (int i = lo[0] - 3; i <= hi[0] + 3; ++i)
        for (int j = lo[1] - 3; j <= hi[1] + 3; ++j)
            for (int k = lo[2] - 3; k <= hi[2] + 3; ++k) {
                openvdb::Coord c(i, j, k);
                float d = acc.getValue(c); // world units; background outside the band
                bool on = acc.isValueOn(c);
                bool occ = hv_accessor_bool(&va, g, i, j, k) != 0;
                if (on || d < 0) ++checked;
                if (d < -tol && !occ) ++missing;
                if (occ && (on ? d > tol : d > 0)) ++outside;
            }
    hv_volume_destroy(vol);
    cr_assert_gt(checked, 100, "%s: oracle empty", what);
    cr_assert_eq(missing, 0, "%s (adjacency %d, %lld): %ld voxels deeper than 1.5 voxels inside are "
                 "missing", what, adjacency, (long long)dims, missing);
    cr_assert_eq(outside, 0, "%s (adjacency %d, %lld): %ld occupied voxels lie more than 1.5 voxels "
                 "outside", what, adjacency, (long long)dims, outside);
}

Test(oracle, shared_meshes, .timeout = 240)
{
    const char *files[] = {"helical_gear.stl", "bunny_1500.stl", "bolt_colored_header.stl"};
    for (const char *f : files) {
        hv_mesh *m = nullptr;
        cr_assert_eq(hv_mesh_load_stl(t_mesh_path(f), &m), HV_OK, "%s", hv_last_error());
        compare(m, 26, 96, f);
        compare(m, 6, 96, f);
        hv_mesh_destroy(m);
    }
}

Test(oracle, analytic_shapes, .timeout = 240)
{
    hv_mesh *ms[3];
    double z[3] = {0, 0, 0}, hi[3] = {40, 30, 20}, c[3] = {0.4, 0.1, -0.3};
    cr_assert_eq(hv_generate_sphere(c, 10, 64, 32, &ms[0]), HV_OK);
    cr_assert_eq(hv_generate_box_with_hole(z, hi, 8, 64, &ms[1]), HV_OK);
    cr_assert_eq(hv_generate_torus(z, 20, 6, 64, 32, &ms[2]), HV_OK);
    const char *names[3] = {"sphere", "box with a hole", "torus"};
    for (int i = 0; i < 3; ++i) {
        compare(ms[i], 26, 128, names[i]);
        compare(ms[i], 6, 80, names[i]);
        hv_mesh_destroy(ms[i]);
    }
}
