/* src/cli/cmd_profile.c - `hovox profile MODEL.vdb --from X,Y,Z --to X,Y,Z -o PROFILE.csv
 * [--plot PROFILE.png]`: material fractions along a line (Wu Fig. 26) as CSV and a plot. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "core/internal.h"
#include "cli.h"
#include "hovox/profile.h"

static const char *PROFILE_HELP =
    "usage: hovox profile MODEL.vdb --from X,Y,Z --to X,Y,Z [--samples N] -o PROFILE.csv\n"
    "                     [--plot PROFILE.png] [options]\n"
    "\n"
    "Material fractions of a graded model along the segment from --from to --to (Wu\n"
    "Fig. 26): N evenly spaced samples, both ends included, each probed as 'hovox probe'\n"
    "does. The CSV has a header 't,x,y,z,inside,<material names...>' and one row per\n"
    "sample; t is the distance from --from (mm). The plot shows each material's fraction\n"
    "against t in the material's colour, with the stretches outside the object shaded.\n"
    "\n"
    "Options:\n"
    "  --from X,Y,Z        start of the line (world coordinates, mm)\n"
    "  --to X,Y,Z          end of the line\n"
    "  --samples N         samples along the line, 2..10000000 (default 200)\n"
    "  -o, --output FILE   the CSV to write; '-' writes it to stdout\n"
    "  --plot FILE         the plot to write: .png or .svg (give -o, --plot or both)\n"
    "  --title TEXT        plot title (default 'Material fractions along a line')\n"
    "  --size W,H          plot size in pixels (default 900,560; each 100..8192)\n"
    "  --mark T[=LABEL]    a dashed vertical line at distance T along the line, e.g. a\n"
    "                      grading source's d- and d- + dg (repeatable, up to 64)\n"
    "  --y-range LO,HI     y axis range of the plot (default 0,1); 'auto': the data range\n"
    "  -q, --quiet         print nothing on success\n"
    "  -h, --help          this text\n"
    "\n"
    "Outputs are written under temporary names and renamed together at the end, so a failed\n"
    "run leaves neither file.\n";

#define MAX_MARKS 64

static int materials_error(const char *model, hv_status s)
{
    if (s == HV_ERR_NOT_FOUND) {
        fprintf(stderr, "hovox: %s: model has no materials: grade it first (hovox grade)\n", model);
        return EXIT_BAD_INPUT;
    }
    return cli_fail(hv_error_prefix(s, "%s: ", model));
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcasecmp(s + n - k, suffix) == 0;
}

typedef struct mark {
    double t;
    const char *label; /* points into argv */
} mark;

static int parse_mark(const char *s, mark *mk)
{
    const char *eq = strchr(s, '=');
    size_t n = eq ? (size_t)(eq - s) : strlen(s);
    char num[64];
    if (n == 0 || n >= sizeof num)
        return cli_usage_error("profile", "--mark: '%s' is not T or T=LABEL", s);
    memcpy(num, s, n);
    num[n] = '\0';
    if (cli_parse_double("profile", "--mark", num, &mk->t)) return EXIT_USAGE;
    mk->label = eq && eq[1] ? eq + 1 : NULL;
    return 0;
}

static int parse_size(const char *s, int size[2])
{
    double v[2];
    if (cli_parse_vec("profile", "--size", s, 2, v)) return EXIT_USAGE;
    for (int a = 0; a < 2; ++a) {
        if (v[a] != floor(v[a]) || v[a] < 100 || v[a] > 8192)
            return cli_usage_error("profile", "--size: '%s' must be two integers in [100, 8192]", s);
        size[a] = (int)v[a];
    }
    return 0;
}

static void print_summary(const hv_profile *p, const char *csv, const char *plot)
{
    double a[3], b[3];
    hv_profile_segment(p, a, b);
    int n = hv_profile_samples(p), in = 0;
    for (int i = 0; i < n; ++i) in += hv_profile_inside(p, i);
    const hv_material_table *t = hv_profile_table(p);
    printf("line        (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g), length %.6g mm\n", a[0], a[1], a[2],
           b[0], b[1], b[2], hv_profile_length(p));
    printf("samples     %d, %d inside the object\n", n, in);
    printf("materials   ");
    for (int k = 0; k < hv_profile_materials(p); ++k) printf(k ? ", %s" : "%s", hv_material_name(t, k));
    printf("\n");
    if (csv) printf("wrote       %s\n", csv);
    if (plot) printf("wrote       %s\n", plot);
}

int cmd_profile(int argc, char **argv)
{
    enum { O_FROM = 256, O_TO, O_SAMPLES, O_PLOT, O_TITLE, O_SIZE, O_MARK, O_YRANGE };
    static const struct option opts[] = {
        {"from", required_argument, NULL, O_FROM},       {"to", required_argument, NULL, O_TO},
        {"samples", required_argument, NULL, O_SAMPLES}, {"output", required_argument, NULL, 'o'},
        {"plot", required_argument, NULL, O_PLOT},       {"title", required_argument, NULL, O_TITLE},
        {"size", required_argument, NULL, O_SIZE},       {"mark", required_argument, NULL, O_MARK},
        {"y-range", required_argument, NULL, O_YRANGE},  {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},                {NULL, 0, NULL, 0}};
    double from[3], to[3], yr[2] = {0.0, 1.0};
    int have_from = 0, have_to = 0, quiet = 0, size[2] = {900, 560}, nmarks = 0, c;
    long samples = 200;
    const char *csv = NULL, *plot = NULL, *title = NULL;
    mark marks[MAX_MARKS];
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":o:qh", opts, NULL)) != -1) {
        switch (c) {
        case O_FROM:
            if (cli_parse_vec("profile", "--from", optarg, 3, from)) return EXIT_USAGE;
            have_from = 1;
            break;
        case O_TO:
            if (cli_parse_vec("profile", "--to", optarg, 3, to)) return EXIT_USAGE;
            have_to = 1;
            break;
        case O_SAMPLES:
            if (cli_parse_int("profile", "--samples", optarg, 2, 10000000L, &samples)) return EXIT_USAGE;
            break;
        case 'o': csv = optarg; break;
        case O_PLOT:
            if (!ends_with(optarg, ".png") && !ends_with(optarg, ".svg"))
                return cli_usage_error("profile", "--plot: '%s': unknown extension (use .png or .svg)", optarg);
            plot = optarg;
            break;
        case O_TITLE: title = optarg; break;
        case O_SIZE:
            if (parse_size(optarg, size)) return EXIT_USAGE;
            break;
        case O_MARK:
            if (nmarks >= MAX_MARKS) return cli_usage_error("profile", "--mark: at most %d markers", MAX_MARKS);
            if (parse_mark(optarg, &marks[nmarks])) return EXIT_USAGE;
            ++nmarks;
            break;
        case O_YRANGE:
            if (strcmp(optarg, "auto") == 0) {
                yr[0] = yr[1] = NAN;
            } else {
                if (cli_parse_vec("profile", "--y-range", optarg, 2, yr)) return EXIT_USAGE;
                if (!(yr[0] < yr[1]))
                    return cli_usage_error("profile", "--y-range: '%s' needs LO < HI", optarg);
            }
            break;
        case 'q': quiet = 1; break;
        case 'h': fputs(PROFILE_HELP, stdout); return EXIT_OK;
        case ':': return cli_usage_error("profile", "option '%s' needs a value", argv[optind - 1]);
        default: return cli_usage_error("profile", "unknown option '%s'", argv[optind - 1]);
        }
    }
    if (optind >= argc) return cli_usage_error("profile", "missing MODEL argument");
    if (argc - optind > 1)
        return cli_usage_error("profile", "one MODEL at a time (got '%s' too)", argv[optind + 1]);
    if (!have_from) return cli_usage_error("profile", "missing --from X,Y,Z");
    if (!have_to) return cli_usage_error("profile", "missing --to X,Y,Z");
    if (from[0] == to[0] && from[1] == to[1] && from[2] == to[2])
        return cli_usage_error("profile", "--from and --to are the same point");
    if (!csv && !plot) return cli_usage_error("profile", "missing -o PROFILE.csv (or --plot PROFILE.png)");
    if (title && !*title) title = NULL;
    const char *model = argv[optind];
    int to_stdout = csv && strcmp(csv, "-") == 0;

    hv_volume *vol;
    hv_status s = hv_volume_load(model, &vol);
    if (s != HV_OK) return cli_fail(s);
    hv_profile *prof;
    s = hv_profile_sample(vol, from, to, (int)samples, &prof);
    hv_volume_destroy(vol);
    if (s != HV_OK) return s == HV_ERR_INVALID ? cli_fail(s) : materials_error(model, s);

    /* everything that can fail on content is done before anything is written */
    hv_plot *pl = NULL;
    if (plot) {
        s = hv_profile_plot(prof, size[0], size[1], &pl);
        if (s == HV_OK && title) s = hv_plot_set_title(pl, title, NULL); /* keeps the subtitle */
        if (s == HV_OK) s = hv_plot_set_y_range(pl, yr[0], yr[1]);
        for (int k = 0; k < nmarks && s == HV_OK; ++k) s = hv_plot_add_marker(pl, marks[k].t, marks[k].label);
    }
    /* both files are written under temporary names and renamed at the end */
    hv_atomic_file fcsv = {NULL, NULL, NULL}, fplot = {NULL, NULL, NULL};
    if (s == HV_OK && csv && !to_stdout) s = hv_atomic_open(&fcsv, csv, "w");
    if (s == HV_OK && plot) s = hv_atomic_open(&fplot, plot, "wb");
    if (s == HV_OK && fcsv.fp && (s = hv_profile_write_csv_stream(prof, fcsv.fp)) != HV_OK)
        s = hv_error_prefix(s, "%s: ", csv);
    if (s == HV_OK && fplot.fp) {
        s = ends_with(plot, ".svg") ? hv_plot_write_svg_stream(pl, fplot.fp) : hv_plot_write_png_stream(pl, fplot.fp);
        if (s != HV_OK) s = hv_error_prefix(s, "%s: ", plot);
    }
    if (s == HV_OK && fcsv.fp) s = hv_atomic_commit(&fcsv);
    if (s == HV_OK && fplot.fp) s = hv_atomic_commit(&fplot);
    if (s != HV_OK) {
        if (fcsv.fp) hv_atomic_abort(&fcsv);
        if (fplot.fp) hv_atomic_abort(&fplot);
    }
    if (s == HV_OK && to_stdout) s = hv_profile_write_csv_stream(prof, stdout);
    if (s == HV_OK && !quiet && !to_stdout) print_summary(prof, csv, plot);
    hv_plot_destroy(pl);
    hv_profile_destroy(prof);
    return s == HV_OK ? EXIT_OK : cli_fail(s);
}
