/* tests/voxel/test_assembly.c - multi-body meshes voxelized into regions (hovox/voxelize.h):
 * each region checked voxel for voxel against its body voxelized alone on the same lattice (the
 * independent reference), the first-wins overlap rule in both orders, the reported overlap,
 * the union's occupancy and surface, the regions document through a .vdb, the memory plan, and
 * single-body meshes unchanged. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/voxelize.h"
#include "support/support.h"

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

/* The rule checked voxel for voxel from the boxes' bounds alone: a voxel whose centre is inside
 * one or more boxes belongs to the first of them; any other voxel of the occupancy (the outer
 * skin) to the first body whose occupancy, voxelized alone on the same lattice (alone[b]), has it.
 * Also the counts: voxels per region, lost (the body's own voxels another region got), lost_to
 * (its centres an earlier body took) and the overlap (centres inside two or more boxes). */
typedef struct box_body {
    double lo[3], hi[3];
    const char *name;
} box_body;

static void check_rule(const hv_volume *v, const box_body *bx, hv_volume **alone, size_t nb, uint64_t *region_voxels)
{
    hv_transform xf = hv_volume_get_transform(v);
    int gocc = grid(v, "occupancy"), greg[8], galone[8];
    hv_accessor acc[8];
    char gname[64];
    uint64_t got[8] = {0}, own[8] = {0}, lost_to[8][8] = {{0}}, overlap = 0, occupied = 0;
    cr_assert(nb <= 8);
    for (size_t b = 0; b < nb; ++b) {
        snprintf(gname, sizeof gname, "region.%s", bx[b].name);
        greg[b] = grid(v, gname);
        galone[b] = grid(alone[b], "occupancy");
        hv_accessor_init(&acc[b], alone[b]);
        own[b] = count(alone[b], "occupancy");
    }
    const int32_t *org = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned q = 0; q < 512; ++q) {
            if (!HV_BIT_GET(hv_volume_leaf_bool_c(v, gocc, l), q) || !HV_BIT_GET(hv_volume_leaf_mask(v, l), q)) continue;
            ++occupied;
            int32_t x[3] = {org[3 * l] + (int32_t)(q >> 6), org[3 * l + 1] + (int32_t)((q >> 3) & 7),
                            org[3 * l + 2] + (int32_t)(q & 7)};
            double c[3];
            for (int a = 0; a < 3; ++a) c[a] = xf.origin[a] + x[a] * xf.voxel[a];
            int first = -1, inside = 0;
            for (size_t b = 0; b < nb; ++b) {
                int in = 1;
                for (int a = 0; a < 3; ++a) in &= c[a] > bx[b].lo[a] && c[a] < bx[b].hi[a];
                if (!in) continue;
                ++inside;
                if (first < 0) first = (int)b;
                else ++lost_to[b][first];
            }
            overlap += inside >= 2;
            for (size_t b = 0; first < 0 && b < nb; ++b)
                if (hv_accessor_bool(&acc[b], galone[b], x[0], x[1], x[2])) first = (int)b;
            cr_assert(first >= 0, "voxel (%d, %d, %d) is in no body", x[0], x[1], x[2]);
            int owners = 0;
            for (size_t b = 0; b < nb; ++b)
                if (HV_BIT_GET(hv_volume_leaf_bool_c(v, greg[b], l), q)) {
                    ++owners;
                    cr_assert_eq((int)b, first, "voxel (%d, %d, %d) at (%g, %g, %g) is in region %s, not %s", x[0], x[1],
                                 x[2], c[0], c[1], c[2], bx[b].name, bx[first].name);
                }
            cr_assert_eq(owners, 1, "voxel (%d, %d, %d) has %d regions", x[0], x[1], x[2], owners);
            ++got[first];
        }
    hv_regions *rg = NULL;
    cr_assert_eq(hv_voxelize_regions_read(v, &rg), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_regions_count(rg), nb);
    uint64_t sum = 0;
    for (size_t b = 0; b < nb; ++b) {
        const hv_region_info *g = hv_regions_at(rg, b);
        cr_assert_str_eq(g->name, bx[b].name);
        cr_assert_eq(g->voxels, got[b], "%s: %llu voxels, want %llu", g->name, (unsigned long long)g->voxels,
                     (unsigned long long)got[b]);
        cr_assert_eq(count(v, g->grid), got[b]);
        cr_assert_eq(g->lost, own[b] - got[b], "%s: lost %llu, want %llu", g->name, (unsigned long long)g->lost,
                     (unsigned long long)(own[b] - got[b]));
        size_t k = 0;
        for (size_t j = 0; j < b; ++j) {
            if (!lost_to[b][j]) continue;
            cr_assert(k < g->nlost_to, "%s: no lost_to %s", g->name, bx[j].name);
            cr_assert_eq(g->lost_to[k].region, j);
            cr_assert_eq(g->lost_to[k].voxels, lost_to[b][j], "%s lost_to %s: %llu, want %llu", g->name, bx[j].name,
                         (unsigned long long)g->lost_to[k].voxels, (unsigned long long)lost_to[b][j]);
            ++k;
        }
        cr_assert_eq(g->nlost_to, k, "%s", g->name);
        sum += g->voxels;
        if (region_voxels) region_voxels[b] = got[b];
    }
    cr_assert_eq(sum, occupied);
    cr_assert_eq(hv_regions_overlap(rg), overlap, "overlap %llu, want %llu", (unsigned long long)hv_regions_overlap(rg),
                 (unsigned long long)overlap);
    hv_regions_destroy(rg);
}

static uint64_t centres_in(const hv_volume *v, const double lo[3], const double hi[3])
{
    hv_transform xf = hv_volume_get_transform(v);
    int gocc = grid(v, "occupancy");
    uint64_t n = 0;
    const int32_t *org = hv_volume_leaf_origins(v);
    for (size_t l = 0; l < hv_volume_leaf_count(v); ++l)
        for (unsigned q = 0; q < 512; ++q) {
            if (!HV_BIT_GET(hv_volume_leaf_bool_c(v, gocc, l), q)) continue;
            int32_t x[3] = {org[3 * l] + (int32_t)(q >> 6), org[3 * l + 1] + (int32_t)((q >> 3) & 7),
                            org[3 * l + 2] + (int32_t)(q & 7)};
            int in = 1;
            for (int a = 0; a < 3; ++a) {
                double c = xf.origin[a] + x[a] * xf.voxel[a];
                in &= c > lo[a] && c < hi[a];
            }
            n += (uint64_t)in;
        }
    return n;
}

Test(assembly, nested_boxes_core_first_give_the_core_the_voxels_whose_centres_it_holds)
{
    hv_mesh *outer = t_cube_mesh(0, 10), *inner = t_cube_mesh(3, 7);
    hv_mesh *j = join2(inner, "core", "Agilus", outer, "shell", "Vero");
    hv_volume *v = vox(j, NULL, 0.5);
    hv_transform xf = hv_volume_get_transform(v);
    hv_volume *vi = vox(inner, &xf, 0), *vo = vox(outer, &xf, 0);
    /* a 4 mm core on the 0.5 mm lattice: 8^3 centres, against the 10^3 voxels of its surface
     * test and fill (the outward surface voxels, centres outside it, now go to the shell) */
    box_body bb[2] = {{{3, 3, 3}, {7, 7, 7}, "core"}, {{0, 0, 0}, {10, 10, 10}, "shell"}};
    hv_volume *al[2] = {vi, vo};
    uint64_t got[2];
    check_rule(v, bb, al, 2, got);
    uint64_t ni = count(vi, "occupancy"), no = count(vo, "occupancy");
    cr_assert_eq(ni, 1000);
    cr_assert_eq(got[0], 512);
    cr_assert_eq(got[1], no - 512);
    cr_assert_eq(centres_in(v, bb[0].lo, bb[0].hi), 512);
    cr_assert_eq(differ(v, "occupancy", vo, "occupancy"), 0);
    /* the core's surface lies in the shell's interior: the union's surface is the shell's */
    cr_assert_eq(differ(v, "surface", vo, "surface"), 0);
    hv_regions *rg = NULL;
    cr_assert_eq(hv_voxelize_regions_read(v, &rg), HV_OK, "%s", hv_last_error());
    const hv_region_info *c = hv_regions_at(rg, 0), *s = hv_regions_at(rg, 1);
    cr_assert_str_eq(c->grid, "region.core");
    cr_assert_str_eq(c->material, "Agilus");
    cr_assert_eq(c->has_color, 0);
    cr_assert_eq(c->fill, HV_FILL_FLOOD);
    cr_assert_eq(c->lost, 1000 - 512); /* its outward surface voxels, centres in the shell */
    cr_assert_eq(c->nlost_to, 0);
    cr_assert_str_eq(s->material, "Vero");
    cr_assert_eq(s->lost, 512);
    cr_assert_eq(s->nlost_to, 1); /* the solid 10 mm box holds the core's centres too */
    cr_assert_eq(s->lost_to[0].voxels, 512);
    cr_assert_eq(hv_regions_overlap(rg), 512);
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

Test(assembly, nested_boxes_shell_first_take_every_voxel_and_report_the_overlap)
{
    hv_mesh *outer = t_cube_mesh(0, 10), *inner = t_cube_mesh(3, 7);
    hv_mesh *j = join2(outer, "shell", "Vero", inner, "core", "Agilus");
    hv_volume *v = vox(j, NULL, 0.5);
    hv_transform xf = hv_volume_get_transform(v);
    hv_volume *vi = vox(inner, &xf, 0), *vo = vox(outer, &xf, 0);
    box_body bb[2] = {{{0, 0, 0}, {10, 10, 10}, "shell"}, {{3, 3, 3}, {7, 7, 7}, "core"}};
    hv_volume *al[2] = {vo, vi};
    uint64_t got[2];
    check_rule(v, bb, al, 2, got);
    cr_assert_eq(differ(v, "region.shell", vo, "occupancy"), 0);
    cr_assert_eq(got[1], 0);
    cr_assert_eq(count(v, "region.core"), 0); /* kept as an empty grid */
    hv_regions *rg = NULL;
    cr_assert_eq(hv_voxelize_regions_read(v, &rg), HV_OK, "%s", hv_last_error());
    const hv_region_info *c = hv_regions_at(rg, 1);
    cr_assert_eq(c->voxels, 0);
    cr_assert_eq(c->lost, 1000); /* all its voxels */
    cr_assert_eq(c->nlost_to, 1);
    cr_assert_eq(c->lost_to[0].region, 0);
    cr_assert_eq(c->lost_to[0].voxels, 512); /* of which its centres, the overlap */
    cr_assert_eq(hv_regions_overlap(rg), 512);
    hv_regions_destroy(rg);
    hv_volume_destroy(v);
    hv_volume_destroy(vi);
    hv_volume_destroy(vo);
    hv_mesh_destroy(j);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
}

Test(assembly, boxes_touching_face_to_face_split_at_the_face_with_no_overlap)
{
    double a0[3] = {0, 0, 0}, a1[3] = {4, 4, 4}, b0[3] = {4, 0, 0}, b1[3] = {8, 4, 4};
    hv_mesh *a = t_box_mesh(a0, a1), *b = t_box_mesh(b0, b1);
    for (int order = 0; order < 2; ++order) {
        hv_mesh *j = order ? join2(b, "b", "B", a, "a", "A") : join2(a, "a", "A", b, "b", "B");
        hv_volume *v = vox(j, NULL, 0.5);
        hv_transform xf = hv_volume_get_transform(v);
        hv_volume *va = vox(a, &xf, 0), *vb = vox(b, &xf, 0);
        box_body ba = {{0, 0, 0}, {4, 4, 4}, "a"}, bbb = {{4, 0, 0}, {8, 4, 4}, "b"};
        box_body bb[2] = {order ? bbb : ba, order ? ba : bbb};
        hv_volume *al[2] = {order ? vb : va, order ? va : vb};
        uint64_t got[2];
        check_rule(v, bb, al, 2, got);
        /* each its 8^3 centres plus its part of the outer skin */
        cr_assert_eq(centres_in(v, a0, a1), 512);
        cr_assert_eq(centres_in(v, b0, b1), 512);
        cr_assert(got[0] > 512 && got[1] > 512, "%llu %llu", (unsigned long long)got[0], (unsigned long long)got[1]);
        hv_regions *rg = NULL;
        cr_assert_eq(hv_voxelize_regions_read(v, &rg), HV_OK, "%s", hv_last_error());
        cr_assert_eq(hv_regions_overlap(rg), 0);
        cr_assert_eq(hv_regions_at(rg, 0)->nlost_to, 0);
        cr_assert_eq(hv_regions_at(rg, 1)->nlost_to, 0);
        cr_assert(hv_regions_at(rg, 0)->lost > 0); /* its surface voxels across the face */
        hv_regions_destroy(rg);
        hv_volume_destroy(v);
        hv_volume_destroy(va);
        hv_volume_destroy(vb);
        hv_mesh_destroy(j);
    }
    hv_mesh_destroy(a);
    hv_mesh_destroy(b);
}

Test(assembly, overlapping_boxes_split_at_the_first_and_count_the_overlap_per_pair)
{
    double a0[3] = {0, 0, 0}, a1[3] = {6, 4, 4}, b0[3] = {4, 0.5, 0.5}, b1[3] = {10, 3.5, 3.5}, c0[3] = {9, 1, 1},
           c1[3] = {12, 3, 3};
    hv_mesh *a = t_box_mesh(a0, a1), *b = t_box_mesh(b0, b1), *c = t_box_mesh(c0, c1);
    hv_mesh_part parts[3] = {{a, "a", "A"}, {b, "b", "B"}, {c, "c", NULL}};
    hv_mesh *j = NULL;
    cr_assert_eq(hv_mesh_join(parts, 3, &j), HV_OK, "%s", hv_last_error());
    hv_volume *v = vox(j, NULL, 0.25);
    hv_transform xf = hv_volume_get_transform(v);
    hv_volume *va = vox(a, &xf, 0), *vb = vox(b, &xf, 0), *vc = vox(c, &xf, 0);
    box_body bb[3] = {{{0, 0, 0}, {6, 4, 4}, "a"}, {{4, 0.5, 0.5}, {10, 3.5, 3.5}, "b"}, {{9, 1, 1}, {12, 3, 3}, "c"}};
    hv_volume *al[3] = {va, vb, vc};
    check_rule(v, bb, al, 3, NULL);
    hv_regions *rg = NULL;
    cr_assert_eq(hv_voxelize_regions_read(v, &rg), HV_OK, "%s", hv_last_error());
    const hv_region_info *ib = hv_regions_at(rg, 1), *ic = hv_regions_at(rg, 2);
    /* the overlaps' centres on the 0.25 lattice: a-b 8 x 12 x 12, b-c 4 x 8 x 8 */
    cr_assert_eq(ib->nlost_to, 1);
    cr_assert_eq(ib->lost_to[0].voxels, 8 * 12 * 12);
    cr_assert_null(ic->material);
    cr_assert_eq(ic->nlost_to, 1);
    cr_assert_eq(ic->lost_to[0].region, 1);
    cr_assert_eq(ic->lost_to[0].voxels, 4 * 8 * 8);
    cr_assert_eq(hv_regions_overlap(rg), 8 * 12 * 12 + 4 * 8 * 8);
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
    hv_mesh *outer = t_cube_mesh(0, 10), *inner = t_cube_mesh(3, 7);
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
    hv_mesh *outer = t_cube_mesh(0, 10);
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
    hv_mesh *outer = t_cube_mesh(0, 10), *inner = t_cube_mesh(3, 7);
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
    hv_mesh *outer = t_cube_mesh(0, 10), *inner = t_cube_mesh(3, 7);
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
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 0, "
         "\"lost_to\": []}, {\"name\": \"b\", \"grid\": \"region.b\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 1, "
         "\"lost_to\": [{\"region\": \"a\", \"voxels\": 2}]}]}",
         "lost_to sums to 2, more"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 3, "
         "\"lost_to\": []}]}",
         "overlap is missing"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 3, "
         "\"lost_to\": []}], \"overlap\": -1}",
         "overlap"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 0, "
         "\"lost_to\": [], \"color\": [1, 2, 0, 1]}]}",
         "color[1]"},
        {"{\"schema\": 2, \"regions\": []}", "newer"},
        /* a region's mixture (a 3MF composite): distinct materials, fractions in (0, 1] summing to 1 */
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 0, \"lost_to\": [], \"mixture\": [{\"material\": \"A\", \"fraction\": 0.5}, {\"material\": \"B\", \"fraction\": 0.4}]}]}",
         "regions[0]: the mixture's fractions sum to 0.9, not 1"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 0, \"lost_to\": [], \"mixture\": [{\"material\": \"A\", \"fraction\": 0.5}, {\"material\": \"A\", \"fraction\": 0.5}]}]}",
         "mixture[1]: material 'A' is named twice"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 0, \"lost_to\": [], \"mixture\": [{\"material\": \"A\", \"fraction\": 1.5}, {\"material\": \"B\", \"fraction\": -0.5}]}]}",
         "mixture[0]: fraction 1.5 is not in (0, 1]"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 0, \"lost_to\": [], \"mixture\": []}]}", "mixture is not a list of 1 to 64 parts"},
        {"{\"regions\": [{\"name\": \"a\", \"grid\": \"region.a\", \"fill\": \"flood\", \"voxels\": 1, \"lost\": 0, \"lost_to\": [], \"mixture\": [{\"fraction\": 1}]}]}", "mixture[0]: material"},
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

/* Issue 32 item 20: small bodies run a thread each and are folded in file order, so many bodies
 * give the same regions on one thread or three, voxel for voxel, with the same counts; some boxes
 * overlap their neighbours (the first keeps the overlap) and one is open (it votes). */
Test(assembly, many_small_bodies_give_the_same_regions_on_any_number_of_threads)
{
    enum { N = 30 };
    hv_mesh *m[N];
    hv_mesh_part parts[N];
    char names[N][16];
    for (int i = 0; i < N; ++i) {
        double x = 3.0 * (i % 6), y = 3.0 * (i / 6);
        m[i] = t_cube_mesh(0, 4); /* 4 mm boxes at a 3 mm pitch: each overlaps its neighbours */
        hv_mesh *moved = NULL;
        const double at[12] = {1, 0, 0, x, 0, 1, 0, y, 0, 0, 1, 0.25 * i};
        cr_assert_eq(hv_mesh_transform(m[i], at, &moved), HV_OK, "%s", hv_last_error());
        hv_mesh_destroy(m[i]);
        if (i == 7) { /* open: without its last facet */
            cr_assert_eq(hv_mesh_create(hv_mesh_vertices(moved), hv_mesh_vertex_count(moved), hv_mesh_facets(moved),
                                        hv_mesh_facet_count(moved) - 1, &m[i]),
                         HV_OK);
            hv_mesh_destroy(moved);
        } else m[i] = moved;
        snprintf(names[i], sizeof names[i], "b%d", i);
        parts[i] = (hv_mesh_part){m[i], names[i], NULL};
    }
    hv_mesh *j = NULL;
    cr_assert_eq(hv_mesh_join(parts, N, &j), HV_OK, "%s", hv_last_error());
    hv_volume *v[2];
    const int threads[2] = {1, 3};
    for (int t = 0; t < 2; ++t) {
        hv_set_threads(threads[t]);
        v[t] = vox(j, NULL, 0.5);
    }
    hv_set_threads(0);
    hv_regions *r[2];
    for (int t = 0; t < 2; ++t) cr_assert_eq(hv_voxelize_regions_read(v[t], &r[t]), HV_OK, "%s", hv_last_error());
    cr_assert_eq(differ(v[0], "occupancy", v[1], "occupancy"), 0);
    cr_assert_eq(differ(v[0], "surface", v[1], "surface"), 0);
    uint64_t total = 0;
    for (int i = 0; i < N; ++i) {
        const hv_region_info *a = hv_regions_at(r[0], (size_t)i), *b = hv_regions_at(r[1], (size_t)i);
        cr_assert_str_eq(a->name, names[i]);
        cr_assert_eq(differ(v[0], a->grid, v[1], b->grid), 0, "%s", a->name);
        cr_assert_eq(a->voxels, b->voxels, "%s", a->name);
        cr_assert_eq(a->lost, b->lost, "%s", a->name);
        cr_assert_eq(a->nlost_to, b->nlost_to, "%s", a->name);
        for (size_t k = 0; k < a->nlost_to; ++k) {
            cr_assert_eq(a->lost_to[k].region, b->lost_to[k].region);
            cr_assert_eq(a->lost_to[k].voxels, b->lost_to[k].voxels);
        }
        cr_assert_eq(a->fill, i == 7 ? HV_FILL_VOTE : HV_FILL_FLOOD, "%s", a->name);
        total += a->voxels;
    }
    cr_assert(hv_regions_at(r[0], 1)->nlost_to > 0); /* the overlap is real */
    cr_assert_eq(total, count(v[0], "occupancy")); /* the regions partition the occupancy */
    cr_assert_eq(hv_regions_overlap(r[0]), hv_regions_overlap(r[1]));
    for (int t = 0; t < 2; ++t) {
        hv_regions_destroy(r[t]);
        hv_volume_destroy(v[t]);
    }
    hv_mesh_destroy(j);
    for (int i = 0; i < N; ++i) hv_mesh_destroy(m[i]);
}
