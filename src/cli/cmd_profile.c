/* src/cli/cmd_profile.c - `hovox profile MODEL.vdb --from X,Y,Z --to X,Y,Z -o PROFILE.csv
 * [--plot PROFILE.png]`: material fractions along a line (Wu Fig. 26) as CSV and a plot. The
 * options are the library's (hv_profile_option_set). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "cli.h"
#include "core/internal.h"
#include "hovox/model.h"
#include "hovox/plot.h"
#include "hovox/profile.h"

typedef struct profile_cli {
    const char *output, *plot;
} profile_cli;

static hv_status check_plot_path(const hv_option *o, const void *opts)
{
    return hv_plot_path_check(*(const char *const *)((const char *)opts + o->offset));
}

static const hv_option k_local_opts[] = {
    CLI_OUTPUT(profile_cli, "PROFILE.csv", "the CSV to write; '-' writes it to stdout", 0),
    {.key = "plot", .kind = HV_OPT_STRING, .flags = HV_OPT_OUT_PATH, .offset = offsetof(profile_cli, plot),
     .meta = "FILE", .check = check_plot_path, .help = "the plot to write: .png or .svg (give -o, --plot or both)"},
};
static const hv_option_set k_local = CLI_LOCAL_SET("profile", k_local_opts, profile_cli);


static void report(const hv_profile *p, const char *csv, const char *plot)
{
    double a[3], b[3];
    hv_profile_segment(p, a, b);
    int n = hv_profile_samples(p), in = 0;
    for (int i = 0; i < n; ++i) in += hv_profile_inside(p, i);
    const hv_material_table *t = hv_profile_table(p);
    printf("line        (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g), length %.6g mm\n", a[0], a[1], a[2], b[0], b[1],
           b[2], hv_profile_length(p));
    printf("samples     %d, %d inside the object\n", n, in);
    printf("materials   ");
    for (int k = 0; k < hv_profile_materials(p); ++k) printf(k ? ", %s" : "%s", hv_material_name(t, k));
    printf("\n");
    const char *unit, *prop = hv_profile_property(p, &unit);
    if (prop) {
        double lo = INFINITY, hi = -INFINITY;
        int k = 0;
        for (int i = 0; i < n; ++i) {
            double v = hv_profile_property_value(p, i);
            if (isnan(v)) continue;
            lo = fmin(lo, v);
            hi = fmax(hi, v);
            ++k;
        }
        if (k) printf("property    %s: %.6g to %.6g%s%s at %d samples\n", prop, lo, hi, *unit ? " " : "", unit, k);
        else printf("property    %s: defined at no sample (no sample lies on the table's source's Ms -> Me)\n", prop);
    }
    if (csv) printf("wrote       %s\n", csv);
    if (plot) printf("wrote       %s\n", plot);
}

static int run(const char *model, const hv_profile_options *o, const profile_cli *c, int quiet)
{
    int to_stdout = c->output && strcmp(c->output, "-") == 0;
    hv_volume *vol;
    hv_status s = hv_model_load(model, &vol);
    if (s != HV_OK) return cli_fail(s);
    hv_profile *prof;
    s = hv_profile_sample_with(vol, o, &prof);
    hv_volume_destroy(vol);
    if (s != HV_OK) return cli_fail(s == HV_ERR_INVALID ? s : hv_error_prefix(s, "%s: ", model));
    if (s == HV_OK) s = hv_profile_write_files(prof, o, to_stdout ? NULL : c->output, c->plot);
    if (s == HV_OK && to_stdout) s = hv_profile_write_csv_stream(prof, stdout);
    if (s == HV_OK && !quiet && !to_stdout) report(prof, c->output, c->plot);
    hv_profile_destroy(prof);
    return s == HV_OK ? EXIT_OK : cli_fail(s);
}

static int run_cli(const cli_args *args, void *lib, void *local)
{
    const profile_cli *c = local;
    if (!c->output && !c->plot) return cli_usage_error("profile", "missing -o PROFILE.csv (or --plot PROFILE.png)");
    return run(args->pos[0], lib, c, args->quiet);
}

const cli_spec cmd_profile = {
    "profile", "material fractions along a line, as CSV and a plot",
    "MODEL.vdb --from X,Y,Z --to X,Y,Z [--samples N] -o PROFILE.csv\n"
    "                     [--plot PROFILE.png] [--property NAME] [options]",
    "Material fractions of a graded model along the segment from --from to --to (Wu\n"
    "Fig. 26): N evenly spaced samples, both ends included, each probed as 'hovox probe'\n"
    "does. The CSV has a header 't,x,y,z,inside,<material names...>' and one row per\n"
    "sample; t is the distance from --from (mm). The plot shows each material's fraction\n"
    "against t in the material's colour, with the stretches outside the object shaded.\n"
    "--property NAME adds the property from the calibration table stored with the model's\n"
    "grading source: a column NAME[UNIT] (nan where the composition is not on that source's\n"
    "Ms -> Me) and a curve on a right-hand axis. A model without such a table, or with\n"
    "several different ones, is refused (exit 1).\n",
    hv_profile_option_set, &k_local,
    "Outputs are written under temporary names and renamed together at the end, so a failed\n"
    "run leaves neither file. With -q nothing is printed on success.\n",
    1, 1, "MODEL argument", CLI_QUIET | CLI_POS_FILES, run_cli, NULL, NULL};
