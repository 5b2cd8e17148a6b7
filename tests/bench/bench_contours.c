/* tests/bench/bench_contours.c - benchmark driver for the WDG slicer: loads an STL, then N
 * times builds the slicer (graph + z index), plans uniform layers and slices every layer
 * (no output), and prints the median wall times of each stage and of contour extraction
 * (build + plan + slice) alone. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "hovox/core.h"
#include "hovox/slice.h"

#include "bench.h"

static const char *usage =
    "usage: bench_contours MESH.stl LAYER_HEIGHT [--runs N] [--threads T]\n"
    "  prints median seconds of: build (WDG + z index), slice (every layer), extract (both)\n";

typedef struct totals {
    size_t loops, open, points;
} totals;

static hv_status count_sink(void *user, size_t index, const hv_layer *layer, hv_slice **slice)
{
    (void)index;
    (void)layer;
    totals *t = user;
    const hv_slice_stats *st = hv_slice_get_stats(*slice);
    t->loops += st->loops;
    t->open += st->open;
    t->points += st->points;
    return HV_OK;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fputs(usage, stderr);
        return 2;
    }
    const char *path = argv[1];
    double lh = atof(argv[2]);
    int runs = 5;
    for (int i = 3; i < argc; ++i) {
        if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) runs = atoi(argv[++i]);
        else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc) hv_set_threads(atoi(argv[++i]));
        else {
            fputs(usage, stderr);
            return 2;
        }
    }
    if (runs < 1 || runs > 1000 || !(lh > 0)) {
        fputs(usage, stderr);
        return 2;
    }
    double t0 = now();
    hv_mesh *mesh = NULL;
    hv_status s = hv_mesh_load_stl(path, &mesh);
    if (s != HV_OK) {
        fprintf(stderr, "bench_contours: %s\n", hv_last_error());
        return 1;
    }
    double t_load = now() - t0;
    double *tb = calloc((size_t)runs, sizeof *tb), *ts = calloc((size_t)runs, sizeof *ts),
           *te = calloc((size_t)runs, sizeof *te);
    size_t layers = 0;
    totals tot = {0, 0, 0};
    for (int r = 0; r < runs && s == HV_OK; ++r) {
        double a = now();
        hv_slicer *sl = NULL;
        s = hv_slicer_create(mesh, NULL, &sl);
        double b = now();
        hv_layer_plan *plan = NULL;
        if (s == HV_OK) s = hv_slicer_plan_uniform(sl, 0, lh, &plan);
        memset(&tot, 0, sizeof tot);
        if (s == HV_OK) s = hv_slicer_slice_plan(sl, plan, NULL, count_sink, &tot, NULL);
        double c = now();
        layers = hv_layer_plan_count(plan);
        hv_layer_plan_destroy(plan);
        hv_slicer_destroy(sl);
        tb[r] = b - a;
        ts[r] = c - b;
        te[r] = c - a;
    }
    if (s != HV_OK) {
        fprintf(stderr, "bench_contours: %s\n", hv_last_error());
        return 1;
    }
    printf("facets %zu layers %zu loops %zu open %zu points %zu threads %d\n",
           hv_mesh_facet_count(mesh), layers, tot.loops, tot.open, tot.points, hv_threads());
    printf("load %.4f build %.4f slice %.4f extract %.4f\n", t_load, median(tb, runs),
           median(ts, runs), median(te, runs));
    free(tb);
    free(ts);
    free(te);
    hv_mesh_destroy(mesh);
    return 0;
}
