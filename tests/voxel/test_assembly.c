/* tests/voxel/test_assembly.c - multi-body meshes voxelized into regions (hovox/voxelize.h):
 * each region checked voxel for voxel against its body voxelized alone on the same lattice (the
 * independent reference), the first-wins overlap rule in both orders, the reported overlap,
 * the union's occupancy and surface, the regions document through a .vdb, the memory plan, and
 * single-body meshes unchanged. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/voxelize.h"
#include "support/support.h"

static hv_mesh *box(double lo, double hi)
{
    hv_mesh *m = NULL;
    double a[3] = {lo, lo, lo}, b[3] = {hi, hi, hi};
    cr_assert_eq(hv_generate_box(a, b, &m), HV_OK, "%s", hv_last_error());
    return m;
}

static hv_mesh *box3(const double lo[3], const double hi[3])
{
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_box(lo, hi, &m), HV_OK, "%s", hv_last_error());
    return m;
}

static hv_mesh *join2(hv_mesh *a, const char *na, const char *ma, hv_mesh *b, const char *nb, const char *mb)
{
    hv_mesh_part parts[2] = {{a, na, ma}, {b, nb, mb}};
    hv_mesh *j = NULL;
    cr_assert_eq(hv_mesh_join(parts, 2, &j), HV_OK, "%s", hv_last_error());
    return j;
}

static hv_volume *vox(const hv_mesh *m, const hv_transform *lattice, double size)
{
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    if (lattice) o.lattice = lattice;
    else o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = size;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_OK, "%s", hv_last_error());
    return v;
}

static int grid(const hv_volume *v, const char *name)
{
    int g = hv_volume_grid_find(v, name);
    cr_assert(g >= 0 && hv_volume_grid_type(v, g) == HV_GRID_BOOL, "no bool grid %s", name);
    return g;
}

/* Voxels where bool grid ga of a and gb of b differ (b's grid NULL: empty). Same lattice. */
static uint64_t differ(const hv_volume *a, const char *ga, const hv_volume *b, const char *gb)
{
    int ia = grid(a, ga), ib = gb ? grid(b, gb) : -1;
    uint64_t n = 0;
    hv_accessor acc;
    hv_accessor_init(&acc, b);
    const int32_t *org = hv_volume_leaf_origins(a);
    for (size_t l = 0; l < hv_volume_leaf_count(a); ++l)
        for (unsigned q = 0; q < 512; ++q) {
            int32_t x = org[3 * l] + (int32_t)(q >> 6), y = org[3 * l + 1] + (int32_t)((q >> 3) & 7),
                    z = org[3 * l + 2] + (int32_t)(q & 7);
            int va = (int)HV_BIT_GET(hv_volume_leaf_bool_c(a, ia, l), q) && HV_BIT_GET(hv_volume_leaf_mask(a, l), q);
            int vb = ib >= 0 && hv_accessor_bool(&acc, ib, x, y, z);
            n += va != vb;
        }
    /* and b's voxels a does not have at all */
    hv_accessor_init(&acc, a);
    org = hv_volume_leaf_origins(b);
    for (size_t l = 0; ib >= 0 && l < hv_volume_leaf_count(b); ++l)
        for (unsigned q = 0; q < 512; ++q) {
            int32_t x = org[3 * l] + (int32_t)(q >> 6), y = org[3 * l + 1] + (int32_t)((q >> 3) & 7),
                    z = org[3 * l + 2] + (int32_t)(q & 7);
            int vb = (int)HV_BIT_GET(hv_volume_leaf_bool_c(b, ib, l), q) && HV_BIT_GET(hv_volume_leaf_mask(b, l), q);
            n += vb && !hv_accessor_active(&acc, x, y, z);
        }
    return n;
}

static uint64_t count(const hv_volume *v, const char *g) { return hv_volume_mask_count(v, grid(v, g)); }

Test(assembly, nested_boxes_core_first_give_the_core_alone_and_the_shell_around_it)
{
    hv_mesh *outer = box(0, 10), *inner = box(3, 7);
    hv_mesh *j = join2(inner, "core", "Agilus", outer, "shell", "Vero");
    hv_volume *v = vox(j, NULL, 0.5);
    hv_transform xf = hv_volume_get_transform(v);
    hv_volume *vi = vox(inner, &xf, 0), *vo = vox(outer, &xf, 0);
    /* the reference: each body alone on the same lattice */
    cr_assert_eq(differ(v, "region.core", vi, "occupancy"), 0);
    uint64_t ni = count(vi, "occupancy"), no = count(vo, "occupancy");
    cr_assert(ni > 0 && no > ni);
    cr_assert_eq(count(v, "region.shell"), no - ni);
    cr_assert_eq(differ(v, "occupancy", vo, "occupancy"), 0);
    /* the core's surface lies in the shell's interior: the union's surface is the shell's */
    cr_assert_eq(differ(v, "surface", vo, "surface"), 0);
    hv_regions *rg = NULL;
    cr_assert_eq(hv_voxelize_regions_read(v, &rg), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_regions_count(rg), 2);
    const hv_region_info *c = hv_regions_at(rg, 0), *s = hv_regions_at(rg, 1);
    cr_assert_str_eq(c->name, "core");
    cr_assert_str_eq(c->grid, "region.core");
    cr_assert_str_eq(c->material, "Agilus");
    cr_assert_eq(c->has_color, 0);
    cr_assert_eq(c->fill, HV_FILL_FLOOD);
    cr_assert_eq(c->voxels, ni);
    cr_assert_eq(c->lost, 0);
    cr_assert_eq(c->nlost_to, 0);
    cr_assert_str_eq(s->name, "shell");
    cr_assert_str_eq(s->material, "Vero");
    cr_assert_eq(s->voxels, no - ni);
    cr_assert_eq(s->lost, ni); /* the core came first: it keeps its voxels */
    cr_assert_eq(s->nlost_to, 1);
    cr_assert_eq(s->lost_to[0].region, 0);
    cr_assert_eq(s->lost_to[0].voxels, ni);
    cr_assert_eq(hv_regions_overlap(rg), ni);
    cr_assert_eq(hv_regions_find(rg, "shell"), 1);
    cr_assert_eq(hv_regions_find(rg, "Shell"), -1);
    hv_regions_destroy(rg);
    hv_voxelize_record rec;
    cr_assert_eq(hv_voxelize_record_read(v, &rec), HV_OK, "%s", hv_last_error());
    cr_assert_eq(rec.fill, HV_FILL_FLOOD); /* every body resolved alike */
    hv_volume_destroy(v);
    hv_volume_destroy(vi);
    hv_volume_destroy(vo);
    hv_mesh_destroy(j);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
}

Test(assembly, nested_boxes_shell_first_take_every_voxel_and_the_core_reports_them_lost)
{
    hv_mesh *outer = box(0, 10), *inner = box(3, 7);
    hv_mesh *j = join2(outer, "shell", "Vero", inner, "core", "Agilus");
    hv_volume *v = vox(j, NULL, 0.5);
    hv_transform xf = hv_volume_get_transform(v);
    hv_volume *vi = vox(inner, &xf, 0), *vo = vox(outer, &xf, 0);
    uint64_t ni = count(vi, "occupancy");
    cr_assert_eq(differ(v, "region.shell", vo, "occupancy"), 0);
    cr_assert_eq(count(v, "region.core"), 0); /* kept as an empty grid */
    hv_regions *rg = NULL;
    cr_assert_eq(hv_voxelize_regions_read(v, &rg), HV_OK, "%s", hv_last_error());
    const hv_region_info *c = hv_regions_at(rg, 1);
    cr_assert_str_eq(c->name, "core");
    cr_assert_eq(c->voxels, 0);
    cr_assert_eq(c->lost, ni, "the overlap is the inner box's %llu voxels, got %llu", (unsigned long long)ni,
                 (unsigned long long)c->lost);
    cr_assert_eq(c->lost_to[0].region, 0);
    cr_assert_eq(hv_regions_overlap(rg), ni);
    hv_regions_destroy(rg);
    hv_volume_destroy(v);
    hv_volume_destroy(vi);
    hv_volume_destroy(vo);
    hv_mesh_destroy(j);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
}

Test(assembly, overlapping_boxes_split_at_the_first_and_count_the_overlap_per_pair)
{
    double a0[3] = {0, 0, 0}, a1[3] = {6, 4, 4}, b0[3] = {4, 0.5, 0.5}, b1[3] = {10, 3.5, 3.5}, c0[3] = {9, 1, 1},
           c1[3] = {12, 3, 3};
    hv_mesh *a = box3(a0, a1), *b = box3(b0, b1), *c = box3(c0, c1);
    hv_mesh_part parts[3] = {{a, "a", "A"}, {b, "b", "B"}, {c, "c", NULL}};
    hv_mesh *j = NULL;
    cr_assert_eq(hv_mesh_join(parts, 3, &j), HV_OK, "%s", hv_last_error());
    hv_volume *v = vox(j, NULL, 0.25);
    hv_transform xf = hv_volume_get_transform(v);
    hv_volume *va = vox(a, &xf, 0), *vb = vox(b, &xf, 0), *vc = vox(c, &xf, 0);
    cr_assert_eq(differ(v, "region.a", va, "occupancy"), 0);
    /* b's region: b's voxels that a does not have; its loss: those a has */
    uint64_t nb = count(vb, "occupancy"), nab = nb - (uint64_t)0, shared = 0;
    hv_accessor acc;
    hv_accessor_init(&acc, va);
    const int32_t *org = hv_volume_leaf_origins(vb);
    int gb = grid(vb, "occupancy"), ga = grid(va, "occupancy");
    for (size_t l = 0; l < hv_volume_leaf_count(vb); ++l)
        for (unsigned q = 0; q < 512; ++q)
            if (HV_BIT_GET(hv_volume_leaf_bool_c(vb, gb, l), q) &&
                hv_accessor_bool(&acc, ga, org[3 * l] + (int32_t)(q >> 6), org[3 * l + 1] + (int32_t)((q >> 3) & 7),
                                 org[3 * l + 2] + (int32_t)(q & 7)))
                ++shared;
    (void)nab;
    cr_assert(shared > 0);
    cr_assert_eq(count(v, "region.b"), nb - shared);
    hv_regions *rg = NULL;
    cr_assert_eq(hv_voxelize_regions_read(v, &rg), HV_OK, "%s", hv_last_error());
    const hv_region_info *ib = hv_regions_at(rg, 1), *ic = hv_regions_at(rg, 2);
    cr_assert_eq(ib->lost, shared);
    cr_assert_eq(ib->nlost_to, 1);
    cr_assert_eq(ib->lost_to[0].voxels, shared);
    /* c overlaps b only */
    cr_assert_null(ic->material);
    cr_assert(ic->lost > 0);
    cr_assert_eq(ic->nlost_to, 1);
    cr_assert_eq(ic->lost_to[0].region, 1);
    cr_assert_eq(ic->voxels + ic->lost, count(vc, "occupancy"));
    cr_assert_eq(hv_regions_overlap(rg), shared + ic->lost);
    cr_assert_eq(count(v, "occupancy"), count(v, "region.a") + count(v, "region.b") + count(v, "region.c"));
    hv_regions_destroy(rg);
    hv_volume_destroy(v);
    hv_volume_destroy(va);
    hv_volume_destroy(vb);
    hv_volume_destroy(vc);
    hv_mesh_destroy(j);
    hv_mesh_destroy(a);
    hv_mesh_destroy(b);
    hv_mesh_destroy(c);
}

Test(assembly, the_regions_survive_a_vdb_round_trip)
{
    hv_mesh *outer = box(0, 10), *inner = box(3, 7);
    hv_mesh *j = join2(inner, "core", "Agilus", outer, "shell", "Vero");
    hv_volume *v = vox(j, NULL, 1), *w = NULL;
    const char *path = t_tmpfile("assembly.vdb");
    cr_assert_eq(hv_volume_save(v, path), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_volume_load(path, &w), HV_OK, "%s", hv_last_error());
    cr_assert_eq(differ(v, "region.core", w, "region.core"), 0);
    cr_assert_eq(differ(v, "region.shell", w, "region.shell"), 0);
    cr_assert_str_eq(hv_volume_meta_string(v, "hovox.regions.json"), hv_volume_meta_string(w, "hovox.regions.json"));
    hv_regions *rg = NULL;
    cr_assert_eq(hv_voxelize_regions_read(w, &rg), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_regions_count(rg), 2);
    hv_regions_destroy(rg);
    hv_volume_destroy(v);
    hv_volume_destroy(w);
    hv_mesh_destroy(j);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
}

Test(assembly, a_single_body_has_no_regions_and_the_same_voxels)
{
    hv_mesh *outer = box(0, 10);
    hv_mesh_part p = {outer, "only", "Vero"};
    hv_mesh *j = NULL;
    cr_assert_eq(hv_mesh_join(&p, 1, &j), HV_OK, "%s", hv_last_error());
    hv_volume *v = vox(j, NULL, 0.5), *w = vox(outer, NULL, 0.5);
    cr_assert_eq(hv_volume_grid_count(v), 2);
    cr_assert_eq(differ(v, "occupancy", w, "occupancy"), 0);
    cr_assert_eq(differ(v, "surface", w, "surface"), 0);
    cr_assert_null(hv_volume_meta_string(v, "hovox.regions.json"));
    hv_regions *rg = (hv_regions *)1;
    cr_assert_eq(hv_voxelize_regions_read(v, &rg), HV_ERR_NOT_FOUND);
    cr_assert_null(rg);
    hv_volume_destroy(v);
    hv_volume_destroy(w);
    hv_mesh_destroy(j);
    hv_mesh_destroy(outer);
}

Test(assembly, the_plan_counts_the_regions_and_refuses_over_the_limit)
{
    hv_mesh *outer = box(0, 10), *inner = box(3, 7);
    hv_mesh *j = join2(inner, "core", "Agilus", outer, "shell", "Vero");
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = 0.1;
    hv_voxel_plan pj, po;
    cr_assert_eq(hv_voxelize_plan(j, &o, &pj), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_voxelize_plan(outer, &o, &po), HV_OK, "%s", hv_last_error());
    cr_assert_eq(pj.fill, HV_FILL_AUTO); /* decided per body */
    cr_assert_eq(po.fill, HV_FILL_FLOOD);
    for (int a = 0; a < 3; ++a) cr_assert_eq(pj.dims[a], po.dims[a]);
    cr_assert(pj.memory_bytes > po.memory_bytes, "%llu vs %llu", (unsigned long long)pj.memory_bytes,
              (unsigned long long)po.memory_bytes);
    o.max_memory = pj.memory_bytes - 1;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(j, &o, &v), HV_ERR_LIMIT);
    cr_assert_null(v);
    cr_assert(strstr(hv_last_error(), "max_memory") || strstr(hv_last_error(), "limit"), "%s", hv_last_error());
    hv_mesh_destroy(j);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
}

Test(assembly, an_open_body_votes_while_a_closed_one_floods)
{
    hv_mesh *outer = box(0, 10), *inner = box(3, 7);
    /* the inner box without its last facet: open */
    size_t nv = hv_mesh_vertex_count(inner), nf = hv_mesh_facet_count(inner);
    hv_mesh *open = NULL;
    cr_assert_eq(hv_mesh_create(hv_mesh_vertices(inner), nv, hv_mesh_facets(inner), nf - 1, &open), HV_OK);
    hv_mesh *j = join2(outer, "shell", "Vero", open, "core", "Agilus");
    hv_volume *v = vox(j, NULL, 0.5);
    hv_regions *rg = NULL;
    cr_assert_eq(hv_voxelize_regions_read(v, &rg), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_regions_at(rg, 0)->fill, HV_FILL_FLOOD);
    cr_assert_eq(hv_regions_at(rg, 1)->fill, HV_FILL_VOTE);
    hv_voxelize_record rec;
    cr_assert_eq(hv_voxelize_record_read(v, &rec), HV_OK, "%s", hv_last_error());
    cr_assert_eq(rec.fill, HV_FILL_AUTO); /* the bodies resolved differently */
    hv_regions_destroy(rg);
    hv_volume_destroy(v);
    hv_mesh_destroy(j);
    hv_mesh_destroy(open);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
}

Test(assembly, damaged_regions_documents_are_refused_naming_the_member)
{
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    hv_volume *v = NULL;
    cr_assert_eq(hv_volume_create(&xf, &v), HV_OK, "%s", hv_last_error());
    static const struct {
        const char *doc, *want;
    } cases[] = {
        {"{\"schema\": 1}", "regions is missing"},
        {"{\"regions\": []}", "regions is empty"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": -1, \"lost\": 0, "
         "\"lost_to\": []}]}",
         "voxels"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"pour\", \"voxels\": 1, \"lost\": 0, "
         "\"lost_to\": []}]}",
         "fill"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 2, "
         "\"lost_to\": [{\"region\": \"a\", \"voxels\": 2}]}]}",
         "not an earlier region"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 0, "
         "\"lost_to\": []}, {\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 0, "
         "\"lost_to\": []}]}",
         "used by an earlier region"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 3, "
         "\"lost_to\": []}]}",
         "lost_to sums to 0"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 0, "
         "\"lost_to\": [], \"color\": [1, 2, 0, 1]}]}",
         "color[1]"},
        {"{\"schema\": 2, \"regions\": []}", "newer"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        cr_assert_eq(hv_volume_meta_set_string(v, "hovox.regions.json", cases[i].doc), HV_OK);
        hv_regions *rg = NULL;
        cr_assert_eq(hv_voxelize_regions_read(v, &rg), HV_ERR_BAD_INPUT, "case %zu", i);
        cr_assert_null(rg);
        cr_assert(strstr(hv_last_error(), cases[i].want), "case %zu: %s", i, hv_last_error());
        cr_assert(strstr(hv_last_error(), "hovox.regions.json"), "case %zu: %s", i, hv_last_error());
    }
    hv_volume_destroy(v);
}
