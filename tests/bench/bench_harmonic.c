/* tests/bench/bench_harmonic.c - harmonic field solve time (issue 4, non-manifold-meshes seed
 * sec. 5): hv_harmonic on an n^3 grid, medians of R runs, on two domains:
 *   bar:    the whole grid, phi = 1 on the x = 0 face, 0 on the x = n-1 face (the exact
 *           solution is linear in x: the largest error against it is printed);
 *   sphere: a ball of radius 0.45 n, phi = 1 on the cap x < -0.8 r, 0 on the cap x > 0.8 r.
 * Usage: bench_harmonic [N] [R] [TOL] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "hovox/core.h"
#include "hovox/field.h"

#include "bench.h"

int main(int argc, char **argv)
{
    int n = argc > 1 ? atoi(argv[1]) : 128, runs = argc > 2 ? atoi(argv[2]) : 5;
    double tol = argc > 3 ? atof(argv[3]) : 1e-6;
    if (n < 8 || runs < 1 || !(tol > 0 && tol < 1)) {
        fprintf(stderr, "usage: bench_harmonic [N >= 8] [RUNS >= 1] [TOL in (0, 1)]\n");
        return 2;
    }
    int64_t dims[3] = {n, n, n};
    double spacing[3] = {1, 1, 1};
    size_t nv = (size_t)n * (size_t)n * (size_t)n;
    uint8_t *dom = malloc(nv), *lab = malloc(nv);
    float *phi = malloc(nv * sizeof *phi);
    double *times = malloc((size_t)runs * sizeof *times);
    if (!dom || !lab || !phi || !times) return fprintf(stderr, "out of memory\n"), 3;
    const char *shapes[2] = {"bar", "sphere"};
    for (int sh = 0; sh < 2; ++sh) {
        double c = (n - 1) / 2.0, r = 0.45 * n;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                for (int k = 0; k < n; ++k) {
                    size_t v = ((size_t)i * (size_t)n + (size_t)j) * (size_t)n + (size_t)k;
                    if (sh == 0) {
                        dom[v] = 1;
                        lab[v] = i == 0 ? 1 : i == n - 1 ? 2 : 0;
                    } else {
                        double dx = i - c, dy = j - c, dz = k - c;
                        dom[v] = dx * dx + dy * dy + dz * dz <= r * r;
                        lab[v] = !dom[v] ? 0 : dx < -0.8 * r ? 1 : dx > 0.8 * r ? 2 : 0;
                    }
                }
        int iters = 0;
        for (int run = 0; run < runs; ++run) {
            double t0 = now();
            hv_status s = hv_harmonic(dom, lab, dims, spacing, tol, 1000, phi, &iters, NULL, NULL);
            times[run] = now() - t0;
            if (s != HV_OK) return fprintf(stderr, "hv_harmonic: %s\n", hv_last_error()), 1;
        }
        qsort(times, (size_t)runs, sizeof *times, cmp_double);
        printf("%-6s %d^3, tol %g, %d threads: median %.3f s (min %.3f), %d CG iterations", shapes[sh], n, tol,
               hv_threads(), times[runs / 2], times[0], iters);
        if (sh == 0) {
            double err = 0;
            for (size_t v = 0; v < nv; ++v) {
                double x = (double)(v / ((size_t)n * (size_t)n));
                err = fmax(err, fabs(phi[v] - (1.0 - x / (n - 1))));
            }
            printf(", max |phi - linear| %.2g", err);
        }
        printf("\n");
    }
    free(dom);
    free(lab);
    free(phi);
    free(times);
    return 0;
}
