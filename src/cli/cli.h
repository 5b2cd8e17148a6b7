/* src/cli/cli.h - shared pieces of the hovox command line: the command table, error
 * reporting with documented exit codes, option parsing helpers, the progress bar. The CLI
 * is the only part of hovox that prints or exits. */
#ifndef HOVOX_CLI_H
#define HOVOX_CLI_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "hovox/core.h"
#include "hovox/options.h"

/* Exit codes (README "Exit codes"). */
enum {
    EXIT_OK = 0,
    EXIT_BAD_INPUT = 1,
    EXIT_USAGE = 2,
    EXIT_RESOURCE = 3,
    EXIT_IO = 4,
    EXIT_INTERNAL = 70,
    EXIT_INTERRUPTED = 130
};


/* ---- a command's options (args.c) -----------------------------------------------------------
 * A command is described by a cli_spec: its usage line and text, the library's option set of
 * the operation (values parsed and checked by the library) and a set of its own (output file,
 * --json, --dry-run: options with no meaning outside the command line). cli_parse builds the
 * parser and the --help text from them; --threads, -q/--quiet and -h/--help are common. */
enum {
    CLI_THREADS = 1,     /* takes --threads N */
    CLI_QUIET = 2,       /* takes -q/--quiet */
    CLI_NUMERIC_POS = 4, /* "-1.5,0,2" is a positional argument, not an option */
    CLI_STOP_AT_POS = 8, /* everything from the first positional argument on is positional */
    CLI_POS_FILES = 16   /* positional arguments are files the command reads */
};
/* Outputs (options flagged HV_OPT_OUT_PATH) are checked before the command runs: an extension
 * named by the placeholder ("MODEL.vdb": .vdb) must end the path, and no output may be a file
 * the command reads (positional files, options flagged HV_OPT_IN_PATH). */


typedef struct cli_args {
    hv_optargs lib, local;     /* what was given (hv_optargs_given) */
    char **pos;                /* positional arguments (argv pointers) */
    int npos;
    int quiet;
} cli_args;

typedef struct cli_spec {
    const char *name;          /* "render" */
    const char *summary;       /* one line for 'hovox --help' */
    const char *usage;         /* after "usage: hovox <name> " (may hold more lines) */
    const char *about;         /* paragraphs before the options, or NULL */
    const hv_option_set *(*lib)(void); /* the operation's options, or NULL */
    const hv_option_set *local; /* the command's own options, or NULL */
    const char *notes;         /* text after the options, or NULL */
    int min_pos, max_pos;      /* positional arguments (max -1: any number) */
    const char *pos_name;      /* "MODEL argument": "missing MODEL argument" */
    unsigned flags;            /* CLI_* */
    /* Run the command on parsed options; returns the exit code. */
    int (*run)(const cli_args *args, void *lib_opts, void *local_opts);
    const char *(*more_about)(void); /* appended to about, or NULL (text built at run time) */
    /* Where a local option without help text takes its help (and placeholder) from: the
     * library's set of the same key (grade's source options stand in for hv_ags_option_set's). */
    const hv_option_set *(*help_from)(void);
} cli_spec;

/* Parse argv[1..] (argv[0] is the command name) and run the command: its option structs are
 * allocated by their sets' sizes and initialised by them. Returns the exit code (help: 0; a
 * usage error printed: 2). */
int cli_main(const cli_spec *spec, int argc, char **argv);
/* 1 when the option `key` (library or local) was given. */
int cli_given(const cli_args *a, const char *key);
/* An option's command-line spelling ("layer_height" -> "--layer-height", "output" -> "-o"). */
const char *cli_spell(const char *key);
/* The last library message with options spelled for the command line; into buf. */
const char *cli_message(char *buf, size_t size);

/* The command's own options, declared like the library's: a local struct and a table. */
#define CLI_LOCAL_SET(name, opts, type) \
    {name, opts, (int)(sizeof(opts) / sizeof((opts)[0])), sizeof(type), NULL, NULL, 0, NULL, NULL, NULL, 0}
#define CLI_OUTPUT(type, meta_, help_, flags_)                                                   \
    {.key = "output", .kind = HV_OPT_STRING, .flags = (flags_) | HV_OPT_OUT_PATH,                  \
     .offset = offsetof(type, output), .meta = meta_, .help = help_, .section = "Output"}
#define CLI_JSON(type, help_) {.key = "json", .kind = HV_OPT_FLAG, .offset = offsetof(type, json), .help = help_}

/* Print "hovox: warning: <message>" on stderr. */
void cli_warn(const char *fmt, ...) HV_PRINTF(1, 2);

/* A mesh reader's notes (hv_mesh_note_at), each as a warning; mesh may be NULL. */
struct hv_mesh;
void cli_mesh_notes(const struct hv_mesh *mesh);
/* "bodies      painted: badge; in their materials: base (Agilus30Black)\n" into said when an
 * assembly's bodies do not all take colour (hv_colour_mesh_bodies, colour `asked` or not). */
struct hv_buf;
void cli_describe_bodies(const struct hv_mesh *mesh, int asked, struct hv_buf *said);

/* A JSON object printed on stdout as one line: {"key": value, ...} (jansson, round-trip
 * numbers). cli_json_end prints it; with lines_key, `lines` (records already in JSON, each
 * starting on a new line) follow as a member of that name. Returns 0, or the exit code of a
 * failure it printed (out of memory). */
typedef struct cli_json {
    struct json_t *obj;
    int failed;
} cli_json;
void cli_json_begin(cli_json *j);
void cli_json_str(cli_json *j, const char *key, const char *value);
void cli_json_num(cli_json *j, const char *key, double value);
void cli_json_int(cli_json *j, const char *key, long long value);
void cli_json_nums(cli_json *j, const char *key, const double *v, int n);
void cli_json_ints(cli_json *j, const char *key, const int64_t *v, int n);
int cli_json_end(cli_json *j, const char *lines_key, const char *lines);

/* Print "hovox: <detail>" for a failed library call and return its exit code; a refusal of an
 * option value (HV_ERR_INVALID naming an option) is a usage error instead (exit 2). */
int cli_fail(hv_status status);

/* Print "hovox <cmd>: <message> (see 'hovox <cmd> --help')" on one line; returns EXIT_USAGE. */
int cli_usage_error(const char *cmd, const char *fmt, ...) HV_PRINTF(2, 3);
/* Several processes (hovox-mpi): the collectives the stack commands pass to the library, and
 * whether a failure happened in this process (cli_fail prints only then). NULL in hovox. */
extern const struct hv_dist *cli_dist;
extern int (*cli_failed_here)(void);
/* Map a status to its exit code. */
int cli_exit_code(hv_status status);

/* A progress callback drawing a bar on stderr when it is a terminal (hv_progress.user =
 * the bar state); quiet otherwise. It also cancels after SIGINT/SIGTERM. */
typedef struct cli_progress {
    int enabled;
    double last_draw;
    char stage[32];
    int drawn;
} cli_progress;
void cli_progress_init(cli_progress *p, int quiet);
int cli_progress_fn(void *user, const char *stage, double fraction);
void cli_progress_done(cli_progress *p);
/* Install SIGINT/SIGTERM handlers that set a flag the progress callback turns into a cancel. */
void cli_install_signals(void);
int cli_interrupted(void);
/* A time limit for the whole command (seconds from now; 0: none): past it, long operations are
 * cancelled as by Ctrl-C, and cli_out_of_time says so. */
void cli_set_time_limit(double seconds);
int cli_out_of_time(void);

/* --view of layers and tray: hv_viewer_stack_finish writes the page into the report given as its
 * user pointer; this prints its warnings and a "page" line once the stack is written (nothing when
 * no page was written; no "page" line when quiet, -q). */
#include "hovox/viewer.h"
void cli_view_report(const hv_viewer_report *r, const char *dir, int quiet);

/* ---- placement (place.c) ---------------------------------------------------------------------
 * Load a mesh and place it (hovox/placement.h), then warn when its size suggests a wrong unit
 * (build: the printer's build volume; NULL: the largest built-in one). Errors: those of
 * hv_mesh_load and hv_placement_apply; *out is NULL then. */
#include "hovox/placement.h"
hv_status cli_mesh_load_placed(const char *path, const hv_placement *place, const double build[3], hv_mesh **out);
/* The size warning alone (a mesh placed otherwise). */
void cli_warn_mesh_size(const hv_mesh *mesh, const double build[3]);

/* Commands */
extern const cli_spec cmd_info, cmd_generate, cmd_boolean, cmd_voxelize, cmd_grade, cmd_probe, cmd_profile, cmd_run,
    cmd_render, cmd_contours, cmd_layers, cmd_tray, cmd_view, cmd_export, cmd_colour;

#endif
