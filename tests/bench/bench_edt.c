/* tests/bench/bench_edt.c - benchmark driver for hv_edt: reads a raw uint8 mask of nx*ny*nz
 * bytes (z fastest), runs the distance transform N times and prints the wall time of the
 * transform alone (median, min, max); optionally writes the distances as raw float32. */
#ifndef _GNU_SOURCE
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "hovox/core.h"
#include "hovox/field.h"

#include "bench.h"

static const char *usage =
    "usage: bench_edt MASK.raw NX NY NZ [--invert] [--spacing SX,SY,SZ] [--runs N]\n"
    "                 [--threads T] [--reuse] [--out DIST.raw]\n"
    "  feature voxels are the nonzero bytes of MASK (the zero bytes with --invert, which\n"
    "  matches scipy.ndimage.distance_transform_edt(MASK)); prints the EDT time alone.\n"
    "  Each run writes a freshly allocated buffer (page faults included) unless --reuse.\n";

int main(int argc, char **argv)
{
    if (argc < 5) {
        fputs(usage, stderr);
        return 2;
    }
    const char *path = argv[1], *out_path = NULL;
    int64_t dims[3];
    double spacing[3] = {1, 1, 1};
    int runs = 1, invert = 0, reuse = 0;
    for (int a = 0; a < 3; ++a) {
        char *end;
        dims[a] = strtoll(argv[2 + a], &end, 10);
        if (*end || dims[a] < 1) {
            fprintf(stderr, "bench_edt: bad dimension '%s'\n%s", argv[2 + a], usage);
            return 2;
        }
    }
    for (int i = 5; i < argc; ++i) {
        if (!strcmp(argv[i], "--invert")) {
            invert = 1;
        } else if (!strcmp(argv[i], "--reuse")) {
            reuse = 1;
        } else if (!strcmp(argv[i], "--spacing") && i + 1 < argc) {
            if (sscanf(argv[++i], "%lf,%lf,%lf", &spacing[0], &spacing[1], &spacing[2]) != 3) {
                fprintf(stderr, "bench_edt: bad spacing '%s'\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(argv[i], "--runs") && i + 1 < argc) {
            runs = atoi(argv[++i]);
            if (runs < 1 || runs > 1000) {
                fprintf(stderr, "bench_edt: bad run count '%s'\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
            hv_set_threads(atoi(argv[++i]));
        } else if (!strcmp(argv[i], "--out") && i + 1 < argc) {
            out_path = argv[++i];
        } else {
            fprintf(stderr, "bench_edt: unknown option '%s'\n%s", argv[i], usage);
            return 2;
        }
    }
    size_t n = (size_t)dims[0] * (size_t)dims[1] * (size_t)dims[2];
    uint8_t *mask = malloc(n);
    float *dist = malloc(n * sizeof(float));
    double *times = malloc((size_t)runs * sizeof(double));
    double *cpu = malloc((size_t)runs * sizeof(double));
    if (!mask || !dist || !times || !cpu) {
        fprintf(stderr, "bench_edt: out of memory for %zu voxels\n", n);
        return 3;
    }
    FILE *fp = fopen(path, "rb");
    if (!fp || fread(mask, 1, n, fp) != n || fgetc(fp) != EOF) {
        fprintf(stderr, "bench_edt: %s: cannot read exactly %zu bytes\n", path, n);
        return 4;
    }
    fclose(fp);
    if (invert)
        for (size_t v = 0; v < n; ++v) mask[v] = !mask[v];
    for (int r = 0; r < runs; ++r) {
        /* a fresh output buffer per run unless --reuse: its first touch (page faults) is part
         * of what a caller pays, as it is in scipy's timing */
        if (!reuse && r > 0) {
            free(dist);
            dist = malloc(n * sizeof(float));
            if (!dist) {
                fprintf(stderr, "bench_edt: out of memory for %zu voxels\n", n);
                return 3;
            }
        }
        double t0 = now(), c0 = cpu_now();
        hv_status s = hv_edt(mask, dims, spacing, dist, NULL);
        times[r] = now() - t0;
        cpu[r] = cpu_now() - c0;
        if (s != HV_OK) {
            fprintf(stderr, "bench_edt: %s: %s\n", hv_status_name(s), hv_last_error());
            return 1;
        }
    }
    qsort(times, (size_t)runs, sizeof(double), cmp_double);
    qsort(cpu, (size_t)runs, sizeof(double), cmp_double);
    double med = runs % 2 ? times[runs / 2] : 0.5 * (times[runs / 2 - 1] + times[runs / 2]);
    double cmed = runs % 2 ? cpu[runs / 2] : 0.5 * (cpu[runs / 2 - 1] + cpu[runs / 2]);
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    printf("edt %lldx%lldx%lld on %d threads: median %.4f s  min %.4f  max %.4f  (%d runs)  "
           "cpu %.4f s  peak %.1f MiB\n",
           (long long)dims[0], (long long)dims[1], (long long)dims[2], hv_threads(), med,
           times[0], times[runs - 1], runs, cmed, (double)ru.ru_maxrss / 1024.0);
    if (out_path) {
        fp = fopen(out_path, "wb");
        if (!fp || fwrite(dist, sizeof(float), n, fp) != n || fclose(fp) != 0) {
            fprintf(stderr, "bench_edt: %s: cannot write\n", out_path);
            return 4;
        }
    }
    free(mask);
    free(dist);
    free(times);
    free(cpu);
    return 0;
}
