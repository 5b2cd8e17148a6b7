/* tests/bench/bench_export.c - benchmark driver for hv_export_write: loads a model once, exports
 * it N times and prints the median wall time of the whole export and of its stages (building
 * the arrays in hovox vs VTK's writer with zlib), the file size and the planned memory. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "hovox/core.h"
#include "hovox/export.h"
#include "hovox/volume.h"

#include "bench.h"

static const char *usage =
    "usage: bench_export MODEL.vdb OUT.vti|OUT.vtu [--runs N] [--level L] [--coarsen N]\n"
    "                    [--properties voigt|reuss|both|none] [--threads T]\n"
    "  prints: total, build (hovox: cells, points, arrays) and write (VTK XML + zlib) medians\n";

/* time of the first "export write" callback: the build is done, VTK starts */
typedef struct stage_clock {
    double write_start;
} stage_clock;

static int on_progress(void *user, const char *stage, double fraction)
{
    (void)fraction;
    stage_clock *c = user;
    if (c->write_start == 0 && strcmp(stage, "export write") == 0) c->write_start = now();
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fputs(usage, stderr);
        return 2;
    }
    const char *model = argv[1], *out = argv[2];
    int runs = 3;
    hv_export_options opt;
    hv_export_options_init(&opt);
    for (int i = 3; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v) {
            fprintf(stderr, "bench_export: %s needs a value\n%s", a, usage);
            return 2;
        }
        ++i;
        if (!strcmp(a, "--runs")) runs = atoi(v);
        else if (!strcmp(a, "--level")) opt.zlib_level = atoi(v);
        else if (!strcmp(a, "--coarsen")) opt.coarsen = atoi(v);
        else if (!strcmp(a, "--threads")) hv_set_threads(atoi(v));
        else if (!strcmp(a, "--properties")) {
            opt.mix = !strcmp(v, "none") ? 0u : !strcmp(v, "voigt") ? (unsigned)HV_MIX_VOIGT
                      : !strcmp(v, "reuss") ? (unsigned)HV_MIX_REUSS
                                            : (unsigned)(HV_MIX_VOIGT | HV_MIX_REUSS);
        } else {
            fprintf(stderr, "bench_export: unknown option '%s'\n%s", a, usage);
            return 2;
        }
    }
    if (runs < 1 || runs > 1000) {
        fprintf(stderr, "bench_export: bad run count\n");
        return 2;
    }
    /* the .3mf figures are the Volumetric package's (the shape's .3mf has its own) */
    opt.volumetric = hv_export_format_from_path(out) == HV_EXPORT_3MF_SHAPE;
    double t0 = now();
    hv_volume *vol;
    hv_status s = hv_volume_load(model, &vol);
    if (s != HV_OK) {
        fprintf(stderr, "bench_export: %s\n", hv_last_error());
        return 1;
    }
    double t_load = now() - t0;
    double *total = malloc(sizeof(double) * (size_t)runs), *build = malloc(sizeof(double) * (size_t)runs),
           *write = malloc(sizeof(double) * (size_t)runs);
    hv_export_report rep;
    for (int r = 0; r < runs; ++r) {
        stage_clock clk = {0};
        hv_progress prog = {on_progress, &clk};
        opt.progress = &prog;
        double a = now();
        s = hv_export_write(vol, out, &opt, &rep);
        double b = now();
        if (s != HV_OK) {
            fprintf(stderr, "bench_export: %s\n", hv_last_error());
            hv_volume_destroy(vol);
            return 1;
        }
        total[r] = b - a;
        build[r] = (clk.write_start ? clk.write_start : b) - a;
        write[r] = b - (clk.write_start ? clk.write_start : b);
    }
    printf("model %s load %.3f s, %llu occupied voxels\n", model, t_load,
           (unsigned long long)rep.occupied);
    printf("export %s total %.3f build %.3f write %.3f (medians of %d) bytes %llu memory %llu "
           "points %llu cells %llu arrays %d\n",
           out, median(total, runs), median(build, runs), median(write, runs), runs,
           (unsigned long long)rep.file_bytes, (unsigned long long)rep.memory_bytes,
           (unsigned long long)rep.points, (unsigned long long)rep.cells, rep.arrays);
    free(total);
    free(build);
    free(write);
    hv_volume_destroy(vol);
    return 0;
}
