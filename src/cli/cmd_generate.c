/* src/cli/cmd_generate.c - `hovox generate SHAPE [key=value ...] -o OUT.stl`: parametric closed
 * meshes (test shapes, the bench input, Wu's shaft and gear). Shapes and their parameters are
 * the library's (hv_shape_option_set). */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "core/internal.h"
#include "hovox/generate.h"

typedef struct generate_cli {
    const char *output;
    int ascii;
} generate_cli;

static const hv_option k_local_opts[] = {
    CLI_OUTPUT(generate_cli, "OUT.stl", "where to write (written atomically)", HV_OPT_REQUIRED),
    {.key = "ascii", .kind = HV_OPT_FLAG, .offset = offsetof(generate_cli, ascii), .help = "ASCII STL instead of binary"},
};
static const hv_option_set k_local = CLI_LOCAL_SET("generate", k_local_opts, generate_cli);


/* "  sphere     center=0,0,0 radius=10 ..." for the help text */
static const char *shapes_text(void)
{
    static hv_buf b; /* built once, kept for the process */
    if (b.data) return b.data;
    hv_buf_init(&b);
    hv_buf_puts(&b, "Write a closed, consistently oriented mesh (millimetres). Shapes and keys (defaults):\n");
    for (int i = 0; i < hv_shape_count(); ++i) {
        const hv_option_set *set = hv_shape_option_set(i);
        hv_shape_params d;
        set->init(&d);
        hv_buf_printf(&b, "  %-10s %s:\n             ", hv_shape_name(i), hv_shape_about(i));
        int col = 13;
        for (int k = 0; k < set->count; ++k) {
            char v[96], item[160];
            const hv_option *o = &set->options[k];
            hv_option_format(o, &d, v, sizeof v);
            int unset = (o->flags & HV_OPT_UNSET0) && (strcmp(v, "0") == 0 || strcmp(v, "0,0,0") == 0);
            int n = unset ? snprintf(item, sizeof item, " [%s]", o->key) : snprintf(item, sizeof item, " %s=%s", o->key, v);
            if (col + n > 88) {
                hv_buf_puts(&b, "\n             ");
                col = 13;
            }
            hv_buf_puts(&b, item);
            col += n;
        }
        hv_buf_puts(&b, "\n");
    }
    return b.data;
}

static int build(const char *shape_name, char **kv, int nkv, const generate_cli *c)
{
    int shape = hv_shape_find(shape_name);
    if (shape < 0) return cli_usage_error("generate", "%s", hv_last_error()); /* names the shapes */
    hv_shape_params p;
    hv_optargs args;
    hv_optargs_begin(&args, hv_shape_option_set(shape), &p);
    for (int i = 0; i < nkv; ++i) {
        char *eq = strchr(kv[i], '=');
        if (!eq) return cli_usage_error("generate", "parameter '%s' is not key=value", kv[i]);
        *eq = '\0';
        hv_opt_value v = {HV_VALUE_TEXT, eq + 1, NULL, 0, 0};
        hv_status s = hv_optargs_set(&args, kv[i], &v);
        if (s == HV_ERR_NOT_FOUND)
            return cli_usage_error("generate", "shape '%s' has no parameter '%s'", shape_name, kv[i]);
        if (s != HV_OK) return cli_usage_error("generate", "%s", hv_last_error());
    }
    if (hv_optargs_finish(&args) != HV_OK) return cli_usage_error("generate", "%s", hv_last_error());
    hv_mesh *mesh = NULL;
    hv_status s = hv_generate_shape(shape, &p, &mesh);
    if (s == HV_OK) s = hv_mesh_write_stl(mesh, c->output, c->ascii);
    hv_mesh_destroy(mesh);
    return s == HV_OK ? EXIT_OK : cli_fail(s);
}

static int run(const cli_args *args, void *lib, void *local)
{
    (void)lib;
    return build(args->pos[0], args->pos + 1, args->npos - 1, local);
}

const cli_spec cmd_generate = {"generate", "write a parametric closed mesh (sphere, gear, knot, ...)",
                               "SHAPE [key=value ...] -o OUT.stl [--ascii]", NULL, NULL, &k_local,
                               "Vectors are X,Y,Z (center=0,0,5). A box takes max=X,Y,Z, or its size from min as\n"
                               "size=X,Y,Z or sx=, sy=, sz=.\n",
                               1, -1, "SHAPE", 0, run, shapes_text, NULL};
