/* src/cli/cmd_export.c - `hovox export MODEL.vdb -o OUT.vti|OUT.vtu|OUT.3mf|OUT.stl|OUT.obj`: a
 * graded model to VTK image data or a hexahedral mesh, with derived properties, for ParaView and
 * FEA codes, the shape the model records as a surface (.stl, .obj, a 3MF core .3mf), or a 3MF
 * Volumetric package (.3mf --volumetric) of its voxels. The options are the library's
 * (hv_export_option_set). */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "core/internal.h"
#include "hovox/model.h"
#include "hovox/export.h"

typedef struct export_cli {
    const char *output;
    int dry_run;
} export_cli;

static hv_status check_vtk_path(const hv_option *o, const void *opts)
{
    const char *path = *(const char *const *)((const char *)opts + o->offset);
    if (hv_export_format_from_path(path) != HV_EXPORT_AUTO) return HV_OK;
    return hv_error_option(HV_ERR_INVALID, "{output} '%s' has an unknown extension (use %s)", path,
                           hv_export_format_list());
}

static const hv_option k_local_opts[] = {
    {.key = "output", .kind = HV_OPT_STRING, .flags = HV_OPT_REQUIRED | HV_OPT_OUT_PATH,
     .offset = offsetof(export_cli, output), .meta = "FILE", .check = check_vtk_path,
     .help = ".vti, .vtu, .3mf, .stl or .obj, written atomically", .section = "Output"},
    {.key = "dry_run", .kind = HV_OPT_FLAG, .offset = offsetof(export_cli, dry_run),
     .help = "print the plan (arrays, sizes, memory), write nothing"},
};
static const hv_option_set k_local = CLI_LOCAL_SET("export", k_local_opts, export_cli);


static void print_list(const char *label, const char *csv)
{
    printf("%-12s", label);
    for (const char *p = csv; *p;) {
        const char *c = strchr(p, ',');
        size_t n = c ? (size_t)(c - p) : strlen(p);
        printf("%s%.*s", p == csv ? "" : ", ", (int)n, p);
        p += n + (c ? 1 : 0);
    }
    printf("\n");
}

static void report(const char *model, const hv_volume *vol, const hv_export_options *opt, const export_cli *c,
                   const hv_export_report *rep)
{
    for (const char *p = rep->notes; *p;) {
        const char *nl = strchr(p, '\n');
        size_t n = nl ? (size_t)(nl - p) : strlen(p);
        fprintf(stderr, "hovox: note: %.*s\n", (int)n, p);
        p += n + (nl ? 1 : 0);
    }
    if (rep->format == HV_EXPORT_STL || rep->format == HV_EXPORT_OBJ || rep->format == HV_EXPORT_3MF_SHAPE) {
        printf("model       %s\n", model);
        printf("shape       %s\n", rep->names);
        if (rep->cells)
            printf("mesh        %llu triangles, %llu vertices\n", (unsigned long long)rep->cells,
                   (unsigned long long)rep->points);
        else
            printf("mesh        counted when made\n");
        char mem[32];
        printf("memory      about %s\n", hv_size_text(mem, sizeof mem, (double)rep->memory_bytes));
        if (!c->dry_run) printf("wrote       %s (%llu bytes)\n", c->output, (unsigned long long)rep->file_bytes);
        return;
    }
    hv_transform xf = hv_volume_get_transform(vol);
    if (rep->materials)
        printf("model       %s (%d material%s)\n", model, rep->materials, rep->materials == 1 ? "" : "s");
    else
        printf("model       %s (no material table)\n", model);
    printf("voxels      %lld..%lld, %lld..%lld, %lld..%lld (index), %llu occupied, %.6g x %.6g x %.6g\n",
           (long long)rep->lo[0], (long long)rep->hi[0], (long long)rep->lo[1], (long long)rep->hi[1],
           (long long)rep->lo[2], (long long)rep->hi[2], (unsigned long long)rep->occupied, xf.voxel[0], xf.voxel[1],
           xf.voxel[2]);
    if (rep->format == HV_EXPORT_3MF) {
        if (rep->points)
            printf("mesh        %llu triangles, %llu vertices (the exact voxel boundary)\n", (unsigned long long)rep->cells,
                   (unsigned long long)rep->points);
        else
            printf("mesh        %llu triangles (the exact voxel boundary)\n", (unsigned long long)rep->cells);
        printf("images      %d stacks of %lld %d-bit sheets of %lld x %lld pixels\n", rep->arrays - rep->colour,
               (long long)rep->dims[2], rep->bits, (long long)rep->dims[0], (long long)rep->dims[1]);
        if (rep->colour)
            printf("colour      <v:color> of the colours asked for: stack colour, 16-bit RGBA sheets (linear sRGB)\n");
    } else if (rep->format == HV_EXPORT_VTI)
        printf("image       %lld x %lld x %lld points\n", (long long)rep->dims[0], (long long)rep->dims[1],
               (long long)rep->dims[2]);
    else if (opt->coarsen > 1)
        printf("mesh        %llu hexahedra (%d^3 blocks, keep %s), %llu points\n", (unsigned long long)rep->cells,
               opt->coarsen, hv_coarsen_rule_name(opt->coarsen_rule), (unsigned long long)rep->points);
    else
        printf("mesh        %llu hexahedra, %llu points\n", (unsigned long long)rep->cells,
               (unsigned long long)rep->points);
    print_list(rep->format == HV_EXPORT_3MF ? "stacks" : "arrays", rep->names);
    char mem[32];
    printf("memory      about %s\n", hv_size_text(mem, sizeof mem, (double)rep->memory_bytes));
    if (!c->dry_run) printf("wrote       %s (%llu bytes)\n", c->output, (unsigned long long)rep->file_bytes);
}

static int run(const char *model, hv_export_options *opt, const export_cli *c, int quiet)
{
    /* the format and the tables are checked before the model is read */
    opt->format = hv_export_format_from_path(c->output);
    if (opt->format == HV_EXPORT_3MF_SHAPE && opt->volumetric) opt->format = HV_EXPORT_3MF;
    hv_status s = hv_export_options_check(opt);
    for (int i = 0; i < opt->nlinearize && s == HV_OK; ++i) {
        hv_linearization *t = NULL;
        s = hv_linearization_load(opt->linearize[i].path, opt->linearize[i].property, &t);
        hv_linearization_destroy(t);
    }
    if (s != HV_OK) return cli_fail(s);
    hv_volume *vol = NULL;
    s = hv_model_load(model, &vol);
    if (s != HV_OK) return cli_fail(s);
    hv_export_report rep;
    memset(&rep, 0, sizeof rep);
    cli_progress bar;
    cli_progress_init(&bar, quiet);
    hv_progress prog = {cli_progress_fn, &bar};
    opt->progress = &prog;
    s = c->dry_run ? hv_export_plan(vol, c->output, opt, &rep) : hv_export_write(vol, c->output, opt, &rep);
    cli_progress_done(&bar);
    opt->progress = NULL;
    if (s == HV_OK) report(model, vol, opt, c, &rep);
    hv_volume_destroy(vol);
    return s == HV_OK ? EXIT_OK : cli_fail(s);
}

static int run_cli(const cli_args *args, void *lib, void *local) { return run(args->pos[0], lib, local, args->quiet); }

const cli_spec cmd_export = {
    "export", "export a model to VTK (.vti image data, .vtu hexahedra), its shape (.stl, .obj, .3mf) or 3MF Volumetric",
    "MODEL.vdb -o OUT.vti|OUT.vtu|OUT.stl|OUT.obj|OUT.3mf [--volumetric] [options]",
    "Export a model to VTK XML (appended raw binary, zlib, 64-bit headers) for ParaView and\n"
    "FEA codes. .vti: image data over the occupied voxels' bounding box (or --box), one point\n"
    "per voxel centre. .vtu: one hexahedron per occupied voxel (or NxNxN block), corner points\n"
    "shared. Arrays: occupancy, fraction.<material>, and per property the materials define\n"
    "(density, youngs_modulus, poisson_ratio, ...) <property>.voigt[<unit>] (rule of\n"
    "mixtures, sum p_j X_j) and <property>.reuss[<unit>] (inverse rule, 1 / sum p_j / X_j),\n"
    "plus <property>.table[<unit>] per --linearize table. A model without materials is\n"
    "exported as occupancy only.\n"
    ".stl, .obj, .3mf: the shape the model records, not its voxels: a model voxelized from one\n"
    "mesh writes that mesh placed as recorded (exact, no stair steps); a Boolean of meshes, a\n"
    "narrow-band level set of 0.05 mm voxels per mesh combined by the model's Booleans and\n"
    "meshed at adaptivity 0 (OpenVDB), watertight. .3mf is a 3MF core package for slicers: the\n"
    "materials as base materials, each triangle in the material that dominates the model just\n"
    "inside it. Only --max-memory and --level apply.\n"
    ".3mf --volumetric: a 3MF package with the Volumetric extension: the exact voxel boundary\n"
    "as the mesh (mm), the materials as base materials, one image3d stack of PNG sheets per\n"
    "material fraction and per derived property (8 or 16 bits, --bits), a volumedata whose\n"
    "composite maps the fractions to the base materials; hovox reads it back as a graded model.\n",
    hv_export_option_set, &k_local, NULL, 1, 1, "MODEL argument", CLI_THREADS | CLI_QUIET | CLI_POS_FILES, run_cli, NULL, NULL};
