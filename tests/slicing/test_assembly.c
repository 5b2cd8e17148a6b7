/* tests/slicing/test_assembly.c - contours of multi-body meshes (hovox/slice.h): each body sliced
 * from its own facets (checked against slicing the body alone), bodies that share a face, the gap
 * rule within a body, the union under both fill rules, and the contour files' per-body parts. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/layers.h"
#include "hovox/slice.h"
#include "support/support.h"

static hv_mesh *box3(double x0, double y0, double z0, double x1, double y1, double z1)
{
    double a[3] = {x0, y0, z0}, b[3] = {x1, y1, z1};
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_box(a, b, &m), HV_OK, "%s", hv_last_error());
    return m;
}

static hv_mesh *join(hv_mesh *a, const char *na, hv_mesh *b, const char *nb)
{
    hv_mesh_part parts[2] = {{a, na, NULL}, {b, nb, NULL}};
    hv_mesh *j = NULL;
    cr_assert_eq(hv_mesh_join(parts, 2, &j), HV_OK, "%s", hv_last_error());
    return j;
}

static hv_slice *slice_at(const hv_mesh *m, double z)
{
    hv_slicer *s = NULL;
    cr_assert_eq(hv_slicer_create(m, NULL, &s), HV_OK, "%s", hv_last_error());
    hv_slice *sl = NULL;
    cr_assert_eq(hv_slicer_slice(s, z, NULL, &sl), HV_OK, "%s", hv_last_error());
    hv_slicer_destroy(s);
    return sl;
}

/* Loop l of slice a has the same points as loop k of slice b. */
static void same_loop(const hv_slice *a, size_t l, const hv_slice *b, size_t k)
{
    const hv_slice_loop *p = &hv_slice_loops(a)[l], *q = &hv_slice_loops(b)[k];
    cr_assert_eq(p->count, q->count);
    cr_assert_eq(p->orientation, q->orientation);
    cr_assert_float_eq(p->area, q->area, 1e-9);
    for (size_t i = 0; i < 2 * p->count; ++i) cr_assert_eq(p->xy[i], q->xy[i]);
}

Test(slice_bodies, each_body_is_sliced_as_if_alone)
{
    hv_mesh *outer = box3(0, 0, 0, 10, 10, 10), *inner = box3(3, 3, 3, 7, 7, 7), *j = join(inner, "core", outer, "shell");
    hv_slice *s = slice_at(j, 5), *si = slice_at(inner, 5), *so = slice_at(outer, 5);
    const hv_slice_stats *st = hv_slice_get_stats(s);
    cr_assert_eq(st->loops, 2);
    cr_assert_eq(st->outers, 2, "a body inside another is an outer of its own");
    cr_assert_eq(st->holes, 0);
    const hv_slice_loop *L = hv_slice_loops(s);
    int core = L[0].body == 0 ? 0 : 1, shell = 1 - core;
    cr_assert_eq(L[core].body, 0);
    cr_assert_eq(L[shell].body, 1);
    cr_assert_eq(L[core].parent, -1, "parents are loops of the same body");
    cr_assert_eq(L[core].depth, 0);
    same_loop(s, (size_t)core, si, 0);
    same_loop(s, (size_t)shell, so, 0);
    cr_assert_eq(hv_slice_loops(si)[0].body, 0);
    cr_assert_float_eq(st->area, 100 + 16, 1e-9); /* the overlap counts once per body */
    /* both rules fill the union: the core is no hole in the shell */
    hv_raster_grid g = {40, 40, {0, 0}, {0.25, 0.25}};
    uint8_t *mask = malloc(1600);
    for (int rule = 0; rule < 2; ++rule) {
        cr_assert_eq(hv_slice_rasterize(s, &g, rule ? HV_FILL_EVENODD : HV_FILL_NONZERO, 0, mask, 0), HV_OK);
        int n = 0;
        for (int i = 0; i < 1600; ++i) n += mask[i];
        cr_assert_eq(n, 1600, "rule %d: %d pixels", rule, n);
    }
    free(mask);
    hv_slice_destroy(s);
    hv_slice_destroy(si);
    hv_slice_destroy(so);
    hv_mesh_destroy(j);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
}

Test(slice_bodies, bodies_sharing_a_face_keep_their_own_loops)
{
    /* two boxes meeting at x = 5 share four vertices and a face: welded as one mesh, their edges
     * there would be used by four facets; sliced body by body each gives its own square */
    hv_mesh *a = box3(0, 0, 0, 5, 4, 4), *b = box3(5, 0, 0, 10, 4, 4), *j = join(a, "left", b, "right");
    cr_assert_gt(hv_mesh_get_report(j)->nonmanifold_edges, 0);
    hv_slice *s = slice_at(j, 2), *sa = slice_at(a, 2), *sb = slice_at(b, 2);
    const hv_slice_stats *st = hv_slice_get_stats(s);
    cr_assert_eq(st->loops, 2);
    cr_assert_eq(st->open, 0);
    const hv_slice_loop *L = hv_slice_loops(s);
    for (size_t i = 0; i < 2; ++i) {
        cr_assert_eq(L[i].orientation, 1);
        cr_assert_float_eq(L[i].area, 20, 1e-9);
        same_loop(s, i, L[i].body == 0 ? sa : sb, 0);
    }
    cr_assert_neq(L[0].body, L[1].body);
    hv_slice_destroy(s);
    hv_slice_destroy(sa);
    hv_slice_destroy(sb);
    hv_mesh_destroy(j);
    hv_mesh_destroy(a);
    hv_mesh_destroy(b);
}

Test(slice_bodies, the_gap_rule_joins_ends_of_one_body_only)
{
    /* the same open box twice (a side facet missing), as two bodies: each closes on itself */
    hv_mesh *a = box3(0, 0, 0, 4, 4, 4);
    size_t nf = hv_mesh_facet_count(a);
    uint32_t *f = malloc(3 * nf * sizeof *f);
    memcpy(f, hv_mesh_facets(a), 3 * nf * sizeof *f);
    /* drop one facet of a vertical side */
    const float *v = hv_mesh_vertices(a);
    size_t drop = nf;
    for (size_t k = 0; k < nf && drop == nf; ++k) {
        float z0 = v[3 * f[3 * k] + 2], z1 = v[3 * f[3 * k + 1] + 2], z2 = v[3 * f[3 * k + 2] + 2];
        if (!(z0 == z1 && z1 == z2)) drop = k;
    }
    memmove(f + 3 * drop, f + 3 * drop + 3, 3 * (nf - drop - 1) * sizeof *f);
    hv_mesh *open = NULL;
    cr_assert_eq(hv_mesh_create(v, hv_mesh_vertex_count(a), f, nf - 1, &open), HV_OK);
    free(f);
    hv_mesh *j = join(open, "one", open, "two");
    hv_slice *s = slice_at(j, 2), *so = slice_at(open, 2);
    cr_assert_eq(hv_slice_get_stats(so)->loops, 1);
    cr_assert_eq(hv_slice_get_stats(so)->gaps_closed, 1);
    const hv_slice_stats *st = hv_slice_get_stats(s);
    cr_assert_eq(st->loops, 2);
    cr_assert_eq(st->gaps_closed, 2);
    const hv_slice_loop *L = hv_slice_loops(s);
    cr_assert_neq(L[0].body, L[1].body);
    same_loop(s, 0, so, 0);
    same_loop(s, 1, so, 0);
    hv_slice_destroy(s);
    hv_slice_destroy(so);
    hv_mesh_destroy(j);
    hv_mesh_destroy(open);
    hv_mesh_destroy(a);
}


static size_t occurrences(const char *text, const char *what)
{
    size_t n = 0;
    for (const char *p = strstr(text, what); p; p = strstr(p + 1, what)) ++n;
    return n;
}

Test(slice_bodies, contour_files_give_each_body_its_part)
{
    hv_mesh *outer = box3(0, 0, 0, 10, 10, 10), *inner = box3(3, 3, 3, 7, 7, 7), *j = join(inner, "core", outer, "sh<ell");
    hv_contours_options o;
    hv_contours_options_init(&o);
    o.layer_height = 2;
    const char *cli = t_tmpfile("a.cli"), *svg = t_tmpfile("a.svg");
    o.output = cli;
    cr_assert_eq(hv_contours_write(j, &o, "a.obj", NULL, NULL, NULL, NULL), HV_OK, "%s", hv_last_error());
    o.output = svg;
    cr_assert_eq(hv_contours_write(j, &o, "a.obj", NULL, NULL, NULL, NULL), HV_OK, "%s", hv_last_error());
    char *c = t_slurp(cli, NULL), *g = t_slurp(svg, NULL);
    cr_assert(strstr(c, "$$LABEL/1,core\n$$LABEL/2,sh<ell\n"), "%s", c);
    /* 5 layers cut at z = 1, 3, 5, 7, 9: the shell in each, the core at 5 and 7 (a plane through
     * a top face gives its outline, through a bottom face nothing) */
    cr_assert_eq(occurrences(c, "$$POLYLINE/2,1,"), 5, "%s", c);
    cr_assert_eq(occurrences(c, "$$POLYLINE/1,1,"), 2, "%s", c);
    cr_assert_eq(occurrences(g, "data-body=\"sh&lt;ell\""), 5);
    cr_assert_eq(occurrences(g, "data-body=\"core\""), 2);
    free(c);
    free(g);
    /* one body: the file as before */
    o.output = cli;
    cr_assert_eq(hv_contours_write(outer, &o, "outer.stl", NULL, NULL, NULL, NULL), HV_OK, "%s", hv_last_error());
    c = t_slurp(cli, NULL);
    cr_assert(strstr(c, "$$LABEL/1,outer.stl\n"), "%s", c);
    cr_assert_eq(occurrences(c, "$$POLYLINE/1,1,"), 5);
    free(c);
    hv_mesh_destroy(j);
    hv_mesh_destroy(inner);
    hv_mesh_destroy(outer);
}
