/* src/cli/args.c - the command line from option descriptors: each command names its library
 * option set (hovox/options.h) and its own few options (output, --json, ...) in one cli_spec;
 * this file turns that into argument parsing, the --help text and messages that spell options
 * as the command line does (--layer-height). Values are parsed and checked by the library. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "cli.h"
#include "core/internal.h"
#include "core/json.h"
#include "hovox/mesh.h"

static const cli_spec *g_spec; /* for spelling option names in messages */

/* Common options every command takes. */
typedef struct common_opts {
    int threads;
    int quiet;
    int help;
    uint64_t max_memory;
} common_opts;

static const hv_option k_common_opts[] = {
    {.key = "threads", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .lo = 1, .hi = 1024,
     .offset = offsetof(common_opts, threads), .meta = "N", .help = "worker threads (default: the processors this process may run on)"},
    {.key = "quiet", .kind = HV_OPT_FLAG, .offset = offsetof(common_opts, quiet), .help = "no progress bar and no summary; --json and --dry-run still print, warnings and errors too"},
    {.key = "help", .kind = HV_OPT_FLAG, .offset = offsetof(common_opts, help), .help = "this text"},
    {.key = "max_memory", .kind = HV_OPT_BYTES, .offset = offsetof(common_opts, max_memory), .meta = "SIZE",
     .help = "memory the command may use, its readers included (default: half of RAM); a file or job that needs "
             "more is refused (exit 3)"},
};

/* The option `key` of a command's library or local set, or NULL. */
static const hv_option *own_option(const cli_spec *spec, const char *key, int *which)
{
    const hv_option_set *sets[2] = {spec->lib ? spec->lib() : NULL, spec->local};
    for (int k = 0; k < 2; ++k)
        for (int i = 0; sets[k] && i < sets[k]->count; ++i)
            if (strcmp(sets[k]->options[i].key, key) == 0) {
                if (which) *which = k;
                return &sets[k]->options[i];
            }
    return NULL;
}
static const hv_option_set k_common = {"common", k_common_opts, (int)HV_COUNT(k_common_opts),
                                       sizeof(common_opts), NULL, NULL, 0, NULL, NULL, NULL, 0};

static char short_of(const char *key)
{
    if (strcmp(key, "output") == 0) return 'o';
    if (strcmp(key, "quiet") == 0) return 'q';
    if (strcmp(key, "help") == 0) return 'h';
    return 0;
}

/* "layer_height" -> "layer-height" */
static void cli_name(const char *key, char *buf, size_t size)
{
    snprintf(buf, size, "%s", key);
    for (char *p = buf; *p; ++p)
        if (*p == '_') *p = '-';
}

static const char *spell(const char *key, void *user)
{
    static _Thread_local char buf[4][96];
    static _Thread_local int next;
    (void)user;
    char *b = buf[next++ & 3];
    if (short_of(key) == 'o') {
        snprintf(b, 96, "-o");
        return b;
    }
    char name[80];
    cli_name(key, name, sizeof name);
    snprintf(b, 96, "--%s", name);
    return b;
}

const char *cli_spell(const char *key) { return spell(key, NULL); }

const char *cli_message(char *buf, size_t size) { return hv_error_spell(spell, NULL, buf, size); }

int cli_usage_error(const char *cmd, const char *fmt, ...)
{
    char msg[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    fprintf(stderr, "hovox %s: %s (see 'hovox %s --help')\n", cmd, msg, cmd);
    return EXIT_USAGE;
}

/* The last library message, spelled for the command line, as a usage error. */
static int usage_from_library(const char *cmd)
{
    char msg[2048];
    return cli_usage_error(cmd, "%s", cli_message(msg, sizeof msg));
}

/* ---- help ------------------------------------------------------------------------------------ */

/* Print `text` wrapped to 80 columns, the first line after `col` already-used columns. */
static void print_wrapped(FILE *out, const char *text, int col, int indent)
{
    const int width = 80;
    const char *p = text;
    int first = 1;
    while (*p) {
        if (!first) fprintf(out, "%*s", indent, "");
        int room = width - (first ? col : indent);
        const char *nl = strchr(p, '\n');
        int len = (int)(nl ? nl - p : (long)strlen(p));
        int take = len;
        if (take > room) {
            take = room;
            while (take > 0 && p[take] != ' ') --take;
            if (take == 0) take = room;
        }
        fprintf(out, "%.*s\n", take, p);
        p += take;
        while (*p == ' ') ++p;
        if (*p == '\n') ++p;
        first = 0;
    }
    if (first) fputc('\n', out);
}

static void print_option(FILE *out, const hv_option *o, const void *defaults, const hv_option_set *help_from)
{
    const hv_option *lib = !o->help && help_from ? hv_option_find(help_from, o->key) : NULL;
    hv_option borrowed;
    if (lib) { /* a command's stand-in for a library option: the library's words */
        borrowed = *o;
        borrowed.help = lib->help;
        borrowed.meta = o->meta ? o->meta : lib->meta;
        o = &borrowed;
    }
    char name[80], left[128];
    cli_name(o->key, name, sizeof name);
    char s = short_of(o->key);
    int has_value = o->kind != HV_OPT_FLAG;
    if (s)
        snprintf(left, sizeof left, "  -%c, --%s%s%s", s, name, has_value ? " " : "", has_value ? (o->meta ? o->meta : "X") : "");
    else
        snprintf(left, sizeof left, "  --%s%s%s", name, has_value ? " " : "", has_value ? (o->meta ? o->meta : "X") : "");
    char help[1024];
    snprintf(help, sizeof help, "%s", o->help ? o->help : "");
    if (defaults && has_value && o->help && !strstr(o->help, "default")) {
        char v[128];
        hv_option_format(o, defaults, v, sizeof v);
        int zero = strcmp(v, "0") == 0 || v[0] == '\0' || strcmp(v, "0,0") == 0 || strcmp(v, "0,0,0") == 0 ||
                   strcmp(v, "0:") == 0;
        if (!zero) snprintf(help + strlen(help), sizeof help - strlen(help), " (default %s)", v);
    }
    int col = (int)strlen(left);
    if (col > 24) {
        fprintf(out, "%s\n%*s", left, 25, "");
        print_wrapped(out, help, 25, 25);
    } else {
        fprintf(out, "%-25s", left);
        print_wrapped(out, help, 25, 25);
    }
}

static void print_aliases(FILE *out, const hv_option_set *set, const char *key)
{
    for (int i = 0; i < set->alias_count; ++i) {
        const hv_opt_alias *a = &set->aliases[i];
        if (strcmp(a->key, key) != 0) continue;
        char name[80], left[128], k[80], help[256];
        cli_name(a->name, name, sizeof name);
        cli_name(a->key, k, sizeof k);
        snprintf(left, sizeof left, "  --%s", name);
        snprintf(help, sizeof help, "the same as --%s %s", k, a->value);
        fprintf(out, "%-25s%s\n", left, help);
    }
}

/* The options of the local and library sets, grouped by help section in order of first
 * appearance (an option without a section is in the one before it in its set). */
static void print_help(const cli_spec *spec)
{
    FILE *out = stdout;
    fprintf(out, "usage: hovox %s %s\n", spec->name, spec->usage);
    if (spec->about) fprintf(out, "\n%s", spec->about);
    if (spec->more_about) fprintf(out, "%s%s", spec->about ? "" : "\n", spec->more_about());
    fputc('\n', out);
    const hv_option_set *sets[2] = {spec->lib ? spec->lib() : NULL, spec->local};
    void *defaults[2] = {NULL, NULL};
    const char *sections[128];
    int nsec = 0;
    for (int k = 0; k < 2; ++k) {
        if (!sets[k]) continue;
        defaults[k] = hv_calloc(1, sets[k]->size ? sets[k]->size : 1);
        if (defaults[k] && sets[k]->init) sets[k]->init(defaults[k]);
        const char *sec = "Options";
        for (int i = 0; i < sets[k]->count; ++i) {
            if (sets[k]->options[i].section) sec = sets[k]->options[i].section;
            int seen = 0;
            for (int q = 0; q < nsec && !seen; ++q) seen = strcmp(sections[q], sec) == 0;
            if (!seen && nsec < 128) sections[nsec++] = sec;
        }
    }
    for (int q = 0; q < nsec; ++q) {
        fprintf(out, "%s:\n", sections[q]);
        for (int k = 0; k < 2; ++k) {
            if (!sets[k]) continue;
            const char *sec = "Options";
            for (int i = 0; i < sets[k]->count; ++i) {
                const hv_option *o = &sets[k]->options[i];
                if (o->section) sec = o->section;
                if (strcmp(sec, sections[q]) != 0) continue;
                print_option(out, o, defaults[k], spec->help_from ? spec->help_from() : NULL);
                print_aliases(out, sets[k], o->key);
            }
        }
    }
    free(defaults[0]);
    free(defaults[1]);
    fprintf(out, "Other:\n");
    for (size_t i = 0; i < HV_COUNT(k_common_opts); ++i) {
        const hv_option *o = &k_common_opts[i];
        if (strcmp(o->key, "threads") == 0 && !(spec->flags & CLI_THREADS)) continue;
        if (strcmp(o->key, "quiet") == 0 && !(spec->flags & CLI_QUIET)) continue;
        if (strcmp(o->key, "max_memory") == 0 && own_option(spec, "max_memory", NULL)) continue;
        print_option(out, o, NULL, NULL);
    }
    if (spec->notes) fprintf(out, "\n%s", spec->notes);
}

/* ---- parsing --------------------------------------------------------------------------------- */

typedef struct target {
    const hv_option_set *set;
    hv_optargs *args;
} target;

/* Find the option "--name" in the targets (lib, local, common). */
static int find_long(target *t, int nt, const char *name, int *ti, const hv_option **opt, const hv_opt_alias **alias)
{
    char key[96];
    snprintf(key, sizeof key, "%s", name);
    for (char *p = key; *p; ++p)
        if (*p == '-') *p = '_';
    for (int i = 0; i < nt; ++i) {
        if (!t[i].set) continue;
        const hv_option *o = hv_option_find(t[i].set, key);
        if (o) {
            *ti = i;
            *opt = o;
            *alias = NULL;
            return 1;
        }
        for (int k = 0; k < t[i].set->alias_count; ++k)
            if (strcmp(t[i].set->aliases[k].name, key) == 0) {
                *ti = i;
                *opt = NULL;
                *alias = &t[i].set->aliases[k];
                return 1;
            }
    }
    return 0;
}

/* Levenshtein distance of two short names, capped at 99 for long ones. */
static int edit_distance(const char *a, const char *b)
{
    size_t n = strlen(a), m = strlen(b);
    if (n > 63 || m > 63) return 99;
    int row[64];
    for (size_t j = 0; j <= m; ++j) row[j] = (int)j;
    for (size_t i = 1; i <= n; ++i) {
        int diag = row[0];
        row[0] = (int)i;
        for (size_t j = 1; j <= m; ++j) {
            int up = row[j], best = diag + (a[i - 1] != b[j - 1]);
            if (up + 1 < best) best = up + 1;
            if (row[j - 1] + 1 < best) best = row[j - 1] + 1;
            diag = up;
            row[j] = best;
        }
    }
    return row[m];
}

/* The option of the command nearest to the unknown "--name" (a typo: at most 2 edits, fewer than
 * half its letters), or NULL. */
static const char *nearest_long(const target *t, int nt, const cli_spec *spec, const char *name)
{
    char key[96];
    snprintf(key, sizeof key, "%s", name);
    for (char *p = key; *p; ++p)
        if (*p == '-') *p = '_';
    const char *best = NULL;
    int bd = 3;
    for (int i = 0; i < nt; ++i)
        for (int k = 0; t[i].set && k < t[i].set->count; ++k) {
            const char *cand = t[i].set->options[k].key;
            if (t[i].set == &k_common && ((strcmp(cand, "threads") == 0 && !(spec->flags & CLI_THREADS)) ||
                                          (strcmp(cand, "quiet") == 0 && !(spec->flags & CLI_QUIET))))
                continue;
            int d = edit_distance(key, cand);
            if (d < bd && 2 * d < (int)strlen(key)) best = cand, bd = d;
        }
    return best;
}

static int find_short(target *t, int nt, char c, int *ti, const hv_option **opt)
{
    for (int i = 0; i < nt; ++i)
        for (int k = 0; t[i].set && k < t[i].set->count; ++k)
            if (short_of(t[i].set->options[k].key) == c) {
                *ti = i;
                *opt = &t[i].set->options[k];
                return 1;
            }
    return 0;
}

static int looks_numeric(const char *s)
{
    return s[0] == '-' && (s[1] == '.' || (s[1] >= '0' && s[1] <= '9'));
}

static int parse(const cli_spec *spec, int argc, char **argv, void *lib_opts, void *local_opts, cli_args *out)
{
    g_spec = spec;
    memset(out, 0, sizeof *out);
    common_opts common;
    hv_optargs cargs;
    const hv_option_set *lib = spec->lib ? spec->lib() : NULL;
    hv_optargs_begin(&cargs, &k_common, &common);
    if (lib) hv_optargs_begin(&out->lib, lib, lib_opts);
    if (spec->local) hv_optargs_begin(&out->local, spec->local, local_opts);
    target t[3] = {{spec->local, &out->local}, {lib, &out->lib}, {&k_common, &cargs}};
    out->pos = hv_calloc((size_t)argc + 1, sizeof *out->pos);
    if (!out->pos) return cli_fail(HV_ERR_NOMEM);
    int only_pos = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        int positional = only_pos || a[0] != '-' || a[1] == '\0' || ((spec->flags & CLI_NUMERIC_POS) && looks_numeric(a));
        if (positional) {
            out->pos[out->npos++] = argv[i];
            if (spec->flags & CLI_STOP_AT_POS) only_pos = 1;
            continue;
        }
        if (strcmp(a, "--") == 0) {
            only_pos = 1;
            continue;
        }
        int ti = -1;
        const hv_option *o = NULL;
        const hv_opt_alias *alias = NULL;
        const char *value = NULL;
        char name[96];
        if (a[1] == '-') {
            const char *eq = strchr(a + 2, '=');
            size_t n = eq ? (size_t)(eq - a - 2) : strlen(a + 2);
            if (n >= sizeof name) n = sizeof name - 1;
            memcpy(name, a + 2, n);
            name[n] = '\0';
            if (eq) value = eq + 1;
            if (!find_long(t, 3, name, &ti, &o, &alias)) {
                const char *near = nearest_long(t, 3, spec, name);
                if (near) return cli_usage_error(spec->name, "unknown option '%s' (did you mean '%s'?)", a, cli_spell(near));
                return cli_usage_error(spec->name, "unknown option '%s'", a);
            }
        } else {
            if (!find_short(t, 3, a[1], &ti, &o)) return cli_usage_error(spec->name, "unknown option '%.2s'", a);
            snprintf(name, sizeof name, "%c", a[1]);
            if (a[2]) {
                if (o->kind == HV_OPT_FLAG) return cli_usage_error(spec->name, "unknown option '%s'", a);
                value = a + 2;
            }
        }
        if ((o && o->kind == HV_OPT_FLAG) || alias) {
            if (value) return cli_usage_error(spec->name, "%s takes no value", a);
        } else if (!value) {
            if (i + 1 >= argc) return cli_usage_error(spec->name, "option '%s' needs a value", a);
            value = argv[++i];
        }
        if (t[ti].set == &k_common) {
            if (strcmp(o->key, "threads") == 0 && !(spec->flags & CLI_THREADS))
                return cli_usage_error(spec->name, "unknown option '%s'", a);
            if (strcmp(o->key, "quiet") == 0 && !(spec->flags & CLI_QUIET))
                return cli_usage_error(spec->name, "unknown option '%s'", a);
        }
        hv_status s;
        if (alias) {
            hv_opt_value v = {HV_VALUE_TEXT, alias->value, NULL, 0, 0};
            s = hv_optargs_set(t[ti].args, alias->key, &v);
        } else if (o->kind == HV_OPT_FLAG) {
            hv_opt_value v = {HV_VALUE_BOOL, NULL, NULL, 0, 1};
            s = hv_optargs_set(t[ti].args, o->key, &v);
        } else {
            hv_opt_value v = {HV_VALUE_TEXT, value, NULL, 0, 0};
            s = hv_optargs_set(t[ti].args, o->key, &v);
        }
        if (s != HV_OK) return usage_from_library(spec->name);
        if (common.help) {
            print_help(spec);
            return EXIT_OK;
        }
    }
    if (out->npos < spec->min_pos) return cli_usage_error(spec->name, "missing %s", spec->pos_name);
    if (spec->max_pos >= 0 && out->npos > spec->max_pos)
        return cli_usage_error(spec->name, "unexpected argument '%s'", out->pos[spec->max_pos]);
    if (spec->local && hv_optargs_finish(&out->local) != HV_OK) return usage_from_library(spec->name);
    if (lib && hv_optargs_finish(&out->lib) != HV_OK) return usage_from_library(spec->name);
    if (common.threads) hv_set_threads(common.threads);
    if ((spec->flags & CLI_THREADS) && hv_threads() > hv_cpus_allowed())
        cli_warn("%d threads on %d processor%s (this process's affinity mask): the threads will share them; "
                 "under mpirun, give each rank its cores (--map-by slot:PE=N, or --bind-to none)",
                 hv_threads(), hv_cpus_allowed(), hv_cpus_allowed() == 1 ? "" : "s");
    /* the budget caps every allocation the command plans, its readers' included (a file of a few
     * KB that expands to GB is refused before it is expanded) */
    int which = 0;
    const hv_option *mm = own_option(spec, "max_memory", &which);
    uint64_t cap = common.max_memory;
    if (mm) cap = *(const uint64_t *)((const char *)(which == 0 ? lib_opts : local_opts) + mm->offset);
    if (cap) hv_set_memory_cap(cap);
    out->quiet = common.quiet;
    return -1;
}

/* The files a command reads: its positional arguments (CLI_POS_FILES) and its input options. */
static int inputs_of(const cli_spec *spec, const cli_args *a, const hv_option_set *const sets[2],
                     void *const opts[2], const char **out, int max)
{
    int n = 0;
    for (int i = 0; (spec->flags & CLI_POS_FILES) && i < a->npos && n < max; ++i) out[n++] = a->pos[i];
    for (int k = 0; k < 2; ++k)
        for (int i = 0; sets[k] && i < sets[k]->count && n < max; ++i) {
            const hv_option *o = &sets[k]->options[i];
            const char *v = o->kind == HV_OPT_STRING && (o->flags & HV_OPT_IN_PATH)
                                ? *(const char *const *)((const char *)opts[k] + o->offset)
                                : NULL;
            if (v) out[n++] = v;
        }
    return n;
}

static int ends_with_ci(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcasecmp(s + n - k, suffix) == 0;
}

/* Every output: an extension that fits what is written (an option whose placeholder names one,
 * "MODEL.vdb"), and never the same file as an input (voxelize in.stl -o in.stl would replace
 * the mesh). */
static int check_outputs(const cli_spec *spec, const cli_args *a, const hv_option_set *const sets[2],
                         void *const opts[2])
{
    const char *in[64];
    int nin = inputs_of(spec, a, sets, opts, in, 64);
    for (int k = 0; k < 2; ++k)
        for (int i = 0; sets[k] && i < sets[k]->count; ++i) {
            const hv_option *o = &sets[k]->options[i];
            if (o->kind != HV_OPT_STRING || !(o->flags & HV_OPT_OUT_PATH)) continue;
            const char *path = *(const char *const *)((const char *)opts[k] + o->offset);
            if (!path || strcmp(path, "-") == 0 || hv_path_is_special(path)) continue;
            const char *dot = o->meta ? strrchr(o->meta, '.') : NULL;
            if (dot && !strchr(dot, '|') && !ends_with_ci(path, dot))
                return cli_usage_error(spec->name, "%s '%s' must end in %s (it is written as that format)",
                                       cli_spell(o->key), path, dot);
            struct stat so, si;
            if (stat(path, &so) != 0) continue;
            for (int j = 0; j < nin; ++j)
                if (stat(in[j], &si) == 0 && si.st_dev == so.st_dev && si.st_ino == so.st_ino)
                    return cli_usage_error(spec->name, "%s '%s' is the input '%s': refusing to write over it",
                                           cli_spell(o->key), path, in[j]);
        }
    return -1;
}

int cli_main(const cli_spec *spec, int argc, char **argv)
{
    hv_inputs_reset(); /* one command: it never writes over what it reads (hovox/core.h) */
    const hv_option_set *lib = spec->lib ? spec->lib() : NULL;
    void *lib_opts = lib ? hv_calloc(1, lib->size) : NULL;
    void *local_opts = spec->local ? hv_calloc(1, spec->local->size) : NULL;
    cli_args args;
    memset(&args, 0, sizeof args);
    int rc = (lib && !lib_opts) || (spec->local && !local_opts) ? cli_fail(HV_ERR_NOMEM)
                                                                : parse(spec, argc, argv, lib_opts, local_opts, &args);
    const hv_option_set *const sets[2] = {lib, spec->local};
    void *const opts[2] = {lib_opts, local_opts};
    if (rc < 0) rc = check_outputs(spec, &args, sets, opts);
    if (rc < 0) rc = spec->run(&args, lib_opts, local_opts);
    free(args.pos);
    free(lib_opts);
    free(local_opts);
    return rc;
}

const struct hv_dist *cli_dist;
int (*cli_failed_here)(void);

int cli_fail(hv_status s)
{
    if (cli_failed_here && !cli_failed_here()) return cli_exit_code(s); /* another process said why */
    char msg[2048];
    const char *m = cli_message(msg, sizeof msg);
    if (s == HV_ERR_INVALID && hv_last_error_names_option() && g_spec) return cli_usage_error(g_spec->name, "%s", m);
    if (s == HV_ERR_CANCELLED && cli_interrupted()) m = "interrupted";
    else if (s == HV_ERR_CANCELLED && cli_out_of_time()) {
        m = "time limit exceeded";
        s = HV_ERR_LIMIT;
    }
    fprintf(stderr, "hovox: %s\n", *m ? m : hv_status_name(s));
    return cli_exit_code(s);
}

/* `key` was given on the command line (library or local option). */
int cli_given(const cli_args *a, const char *key)
{
    return (a->lib.set && hv_optargs_given(&a->lib, key)) || (a->local.set && hv_optargs_given(&a->local, key));
}

void cli_mesh_notes(const hv_mesh *mesh)
{
    for (size_t i = 0; mesh && i < hv_mesh_note_count(mesh); ++i) cli_warn("%s", hv_mesh_note_at(mesh, i));
}

void cli_warn(const char *fmt, ...)
{
    /* one write per warning: the ranks of hovox-mpi share a stderr, and a line written in pieces
     * interleaves with theirs */
    char line[2048];
    int n = snprintf(line, sizeof line, "hovox: warning: ");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line + n, sizeof line - (size_t)n - 1, fmt, ap);
    va_end(ap);
    size_t len = strlen(line);
    line[len++] = '\n';
    fflush(stderr);
    fwrite(line, 1, len, stderr);
}

/* ---- JSON on stdout ------------------------------------------------------------------------ */

void cli_json_begin(cli_json *j)
{
    j->obj = json_object();
    j->failed = !j->obj;
}

static void add(cli_json *j, const char *key, json_t *v) { j->failed |= !j->obj || hv_json_set(j->obj, key, v) != 0; }

void cli_json_str(cli_json *j, const char *key, const char *value) { add(j, key, hv_json_text(value ? value : "")); }
void cli_json_num(cli_json *j, const char *key, double value) { add(j, key, hv_json_number(value)); }
void cli_json_int(cli_json *j, const char *key, long long value) { add(j, key, json_integer((json_int_t)value)); }
void cli_json_nums(cli_json *j, const char *key, const double *v, int n) { add(j, key, hv_json_numbers(v, (size_t)n)); }

void cli_json_ints(cli_json *j, const char *key, const int64_t *v, int n)
{
    json_t *a = json_array();
    for (int i = 0; a && i < n; ++i) j->failed |= json_array_append_new(a, json_integer((json_int_t)v[i])) != 0;
    add(j, key, a);
}

int cli_json_end(cli_json *j, const char *lines_key, const char *lines)
{
    char *text = j->failed ? NULL : hv_json_dump(j->obj);
    json_decref(j->obj);
    j->obj = NULL;
    if (!text) return cli_fail(hv_error_set(HV_ERR_NOMEM, "out of memory"));
    size_t n = strlen(text);
    if (lines_key && n >= 2) /* the members, then the records one per line before the brace */
        printf("%.*s,\n \"%s\": [%s\n ]}\n", (int)(n - 1), text, lines_key, lines ? lines : "");
    else
        printf("%s\n", text);
    free(text);
    return EXIT_OK;
}
