/* src/cli/cmd_export.c - `hovox export MODEL.vdb -o OUT.vti|OUT.vtu`: a graded model to VTK
 * image data or a hexahedral mesh, with derived properties, for ParaView and FEA codes. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "cli.h"
#include "hovox/export.h"

#define MAX_TABLES 64

static const char *EXPORT_HELP =
    "usage: hovox export MODEL.vdb -o OUT.vti|OUT.vtu [options]\n"
    "\n"
    "Export a model to VTK XML (appended raw binary, zlib, 64-bit headers) for ParaView and\n"
    "FEA codes. .vti: image data over the occupied voxels' bounding box (or --box), one point\n"
    "per voxel centre. .vtu: one hexahedron per occupied voxel (or NxNxN block), corner points\n"
    "shared. Arrays: occupancy, fraction.<material>, and per property the materials define\n"
    "(density, youngs_modulus, poisson_ratio, ...) <property>.voigt[<unit>] (rule of\n"
    "mixtures, sum p_j X_j) and <property>.reuss[<unit>] (inverse rule, 1 / sum p_j / X_j),\n"
    "plus <property>.table[<unit>] per --linearize table. A model without materials is\n"
    "exported as occupancy only.\n"
    "\n"
    "Options:\n"
    "  -o, --output FILE          .vti or .vtu, written atomically\n"
    "  --box X0,Y0,Z0,X1,Y1,Z1    export the voxels whose centres lie in this world box\n"
    "  --coarsen N                .vtu: one hexahedron per NxNxN block (aligned to multiples\n"
    "                             of N), fractions averaged over its occupied voxels\n"
    "  --keep majority|any        .vtu with --coarsen: keep a block when at least half of its\n"
    "                             voxels are occupied (majority, default) or any is\n"
    "  --properties voigt|reuss|both|none\n"
    "                             mixing rules for the derived properties (default both)\n"
    "  --linearize PROPERTY=FILE.csv\n"
    "                             a measured table PROPERTY(fraction of one material); CSV\n"
    "                             header 'fraction.<material>,<property>[<unit>]', then rows\n"
    "                             'fraction,value'; repeatable\n"
    "  --level N                  zlib level: 1 (fastest, default) to 9 (smallest)\n"
    "  --max-memory SIZE          refuse exports whose buffers need more (default: half of\n"
    "                             RAM), e.g. 2G\n"
    "  --dry-run                  print the plan (arrays, sizes, memory), write nothing\n"
    "  --threads N                worker threads (default: all cores)\n"
    "  -q, --quiet                no progress bar\n"
    "  -h, --help                 this text\n";

static int parse_properties(const char *s, unsigned *mix)
{
    if (strcmp(s, "voigt") == 0) *mix = HV_MIX_VOIGT;
    else if (strcmp(s, "reuss") == 0) *mix = HV_MIX_REUSS;
    else if (strcmp(s, "both") == 0) *mix = HV_MIX_VOIGT | HV_MIX_REUSS;
    else if (strcmp(s, "none") == 0) *mix = 0;
    else return cli_usage_error("export", "--properties must be voigt, reuss, both or none "
                                "(got '%s')", s);
    return 0;
}

static void print_list(const char *label, const char *csv)
{
    printf("%-12s", label);
    const char *p = csv;
    int first = 1;
    while (*p) {
        const char *c = strchr(p, ',');
        size_t n = c ? (size_t)(c - p) : strlen(p);
        printf("%s%.*s", first ? "" : ", ", (int)n, p);
        first = 0;
        p += n;
        if (*p == ',') ++p;
    }
    printf("\n");
}

int cmd_export(int argc, char **argv)
{
    enum { O_BOX = 256, O_COARSEN, O_KEEP, O_PROPS, O_LIN, O_LEVEL, O_MEM, O_DRY, O_THREADS };
    static const struct option opts[] = {
        {"output", required_argument, NULL, 'o'},     {"box", required_argument, NULL, O_BOX},
        {"coarsen", required_argument, NULL, O_COARSEN}, {"keep", required_argument, NULL, O_KEEP},
        {"properties", required_argument, NULL, O_PROPS},
        {"linearize", required_argument, NULL, O_LIN}, {"level", required_argument, NULL, O_LEVEL},
        {"max-memory", required_argument, NULL, O_MEM}, {"dry-run", no_argument, NULL, O_DRY},
        {"threads", required_argument, NULL, O_THREADS}, {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},             {NULL, 0, NULL, 0}};
    hv_export_options opt;
    hv_export_options_init(&opt);
    const char *output = NULL;
    const char *lin_spec[MAX_TABLES];
    int nlin = 0, quiet = 0, dry = 0, c, keep_given = 0;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":o:qh", opts, NULL)) != -1) {
        long n;
        unsigned long long size;
        double box[6];
        switch (c) {
        case 'o': output = optarg; break;
        case 'q': quiet = 1; break;
        case 'h': fputs(EXPORT_HELP, stdout); return EXIT_OK;
        case O_BOX:
            if (cli_parse_vec("export", "--box", optarg, 6, box)) return EXIT_USAGE;
            for (int a = 0; a < 3; ++a) {
                if (box[a] > box[a + 3])
                    return cli_usage_error("export", "--box: %c0 = %g is greater than %c1 = %g",
                                           "XYZ"[a], box[a], "XYZ"[a], box[a + 3]);
                opt.box_lo[a] = box[a];
                opt.box_hi[a] = box[a + 3];
            }
            opt.use_box = 1;
            break;
        case O_COARSEN:
            if (cli_parse_int("export", "--coarsen", optarg, 1, 4096, &n)) return EXIT_USAGE;
            opt.coarsen = (int)n;
            break;
        case O_KEEP:
            if (strcmp(optarg, "majority") == 0) opt.coarsen_rule = HV_COARSEN_MAJORITY;
            else if (strcmp(optarg, "any") == 0) opt.coarsen_rule = HV_COARSEN_ANY;
            else return cli_usage_error("export", "--keep must be majority or any (got '%s')", optarg);
            keep_given = 1;
            break;
        case O_PROPS:
            if (parse_properties(optarg, &opt.mix)) return EXIT_USAGE;
            break;
        case O_LIN:
            if (nlin == MAX_TABLES)
                return cli_usage_error("export", "--linearize: at most %d tables", MAX_TABLES);
            if (!strchr(optarg, '=') || optarg[0] == '=' || strchr(optarg, '=')[1] == '\0')
                return cli_usage_error("export", "--linearize: '%s' is not PROPERTY=FILE.csv",
                                       optarg);
            lin_spec[nlin++] = optarg;
            break;
        case O_LEVEL:
            if (cli_parse_int("export", "--level", optarg, 1, 9, &n)) return EXIT_USAGE;
            opt.zlib_level = (int)n;
            break;
        case O_MEM:
            if (cli_parse_size("export", "--max-memory", optarg, &size)) return EXIT_USAGE;
            if (size == 0) return cli_usage_error("export", "--max-memory must be positive");
            opt.max_memory = size;
            break;
        case O_DRY: dry = 1; break;
        case O_THREADS:
            if (cli_parse_int("export", "--threads", optarg, 1, 1024, &n)) return EXIT_USAGE;
            hv_set_threads((int)n);
            break;
        case ':': return cli_usage_error("export", "option '%s' needs a value", argv[optind - 1]);
        default: return cli_usage_error("export", "unknown option '%s'", argv[optind - 1]);
        }
    }
    if (optind >= argc) return cli_usage_error("export", "missing MODEL argument");
    if (argc - optind > 1)
        return cli_usage_error("export", "one MODEL at a time (got '%s' too)", argv[optind + 1]);
    if (!output) return cli_usage_error("export", "missing -o OUT.vti or OUT.vtu");
    hv_export_format fmt = hv_export_format_from_path(output);
    if (fmt == HV_EXPORT_AUTO)
        return cli_usage_error("export", "-o: '%s': unknown extension (use .vti or .vtu)", output);
    if (fmt == HV_EXPORT_VTI && opt.coarsen > 1)
        return cli_usage_error("export", "--coarsen applies to .vtu output only");
    if (keep_given && opt.coarsen == 1)
        return cli_usage_error("export", "--keep needs --coarsen N with N > 1");
    const char *model = argv[optind];

    hv_linearization *tables[MAX_TABLES];
    int ntables = 0, rc = EXIT_OK;
    hv_status s = HV_OK;
    for (int i = 0; i < nlin && s == HV_OK; ++i) {
        char prop[128];
        const char *eq = strchr(lin_spec[i], '=');
        snprintf(prop, sizeof prop, "%.*s", (int)(eq - lin_spec[i]), lin_spec[i]);
        s = hv_linearization_load(eq + 1, prop, &tables[ntables]);
        if (s == HV_OK) ++ntables;
    }
    hv_volume *vol = NULL;
    if (s == HV_OK) s = hv_volume_load(model, &vol);
    hv_export_report rep;
    memset(&rep, 0, sizeof rep);
    if (s == HV_OK) {
        opt.tables = (const hv_linearization *const *)tables;
        opt.ntables = ntables;
        cli_progress bar;
        cli_progress_init(&bar, quiet);
        hv_progress prog = {cli_progress_fn, &bar};
        opt.progress = &prog;
        if (dry) s = hv_export_plan(vol, output, &opt, &rep);
        else s = hv_export_write(vol, output, &opt, &rep);
        cli_progress_done(&bar);
        opt.progress = NULL;
        if (s != HV_OK && s != HV_ERR_IO && s != HV_ERR_CANCELLED && s != HV_ERR_UNSUPPORTED &&
            s != HV_ERR_NOMEM)
            hv_error_prefix(s, "%s: ", model);
    }
    if (s != HV_OK) {
        rc = cli_fail(s);
    } else {
        for (const char *p = rep.notes; *p;) {
            const char *nl = strchr(p, '\n');
            size_t n = nl ? (size_t)(nl - p) : strlen(p);
            fprintf(stderr, "hovox: note: %.*s\n", (int)n, p);
            p += n + (nl ? 1 : 0);
        }
        hv_transform xf = hv_volume_get_transform(vol);
        if (rep.materials) printf("model       %s (%d material%s)\n", model, rep.materials,
                                  rep.materials == 1 ? "" : "s");
        else printf("model       %s (no material table)\n", model);
        printf("voxels      %lld..%lld, %lld..%lld, %lld..%lld (index), %llu occupied, "
               "%.6g x %.6g x %.6g\n",
               (long long)rep.lo[0], (long long)rep.hi[0], (long long)rep.lo[1],
               (long long)rep.hi[1], (long long)rep.lo[2], (long long)rep.hi[2],
               (unsigned long long)rep.occupied, xf.voxel[0], xf.voxel[1], xf.voxel[2]);
        if (rep.format == HV_EXPORT_VTI)
            printf("image       %lld x %lld x %lld points\n", (long long)rep.dims[0],
                   (long long)rep.dims[1], (long long)rep.dims[2]);
        else if (opt.coarsen > 1)
            printf("mesh        %llu hexahedra (%d^3 blocks, keep %s), %llu points\n",
                   (unsigned long long)rep.cells, opt.coarsen,
                   opt.coarsen_rule == HV_COARSEN_ANY ? "any" : "majority",
                   (unsigned long long)rep.points);
        else
            printf("mesh        %llu hexahedra, %llu points\n", (unsigned long long)rep.cells,
                   (unsigned long long)rep.points);
        print_list("arrays", rep.names);
        char mem[32];
        printf("memory      about %s\n", hv_size_text(mem, sizeof mem, (double)rep.memory_bytes));
        if (!dry) printf("wrote       %s (%llu bytes)\n", output, (unsigned long long)rep.file_bytes);
    }
    hv_volume_destroy(vol);
    for (int i = 0; i < ntables; ++i) hv_linearization_destroy(tables[i]);
    return rc;
}
