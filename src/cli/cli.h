/* src/cli/cli.h - shared pieces of the hovox command line: the command table, error
 * reporting with documented exit codes, option parsing helpers, the progress bar. The CLI
 * is the only part of hovox that prints or exits. */
#ifndef HOVOX_CLI_H
#define HOVOX_CLI_H

#include <stdio.h>

#include "hovox/core.h"

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

typedef struct cli_command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} cli_command;

/* Print "hovox: <detail>" for a failed library call and return its exit code. */
int cli_fail(hv_status status);
/* Print "hovox <cmd>: <message>" and "Try 'hovox <cmd> --help'." and return EXIT_USAGE. */
int cli_usage_error(const char *cmd, const char *fmt, ...) HV_PRINTF(2, 3);
/* Map a status to its exit code. */
int cli_exit_code(hv_status status);

/* Parse helpers: return 0 and store, or print a usage error naming the option and return
 * EXIT_USAGE. */
int cli_parse_double(const char *cmd, const char *opt, const char *s, double *out);
int cli_parse_int(const char *cmd, const char *opt, const char *s, long lo, long hi, long *out);
/* Exactly n comma-separated numbers ("1,2,3"). */
int cli_parse_vec(const char *cmd, const char *opt, const char *s, int n, double *out);
/* A byte size with optional K/M/G/T suffix (powers of 1024). */
int cli_parse_size(const char *cmd, const char *opt, const char *s, unsigned long long *out);

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

/* Commands */
int cmd_info(int argc, char **argv);
int cmd_generate(int argc, char **argv);
int cmd_voxelize(int argc, char **argv);
int cmd_grade(int argc, char **argv);
int cmd_probe(int argc, char **argv);
int cmd_profile(int argc, char **argv);
int cmd_run(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_contours(int argc, char **argv);
int cmd_layers(int argc, char **argv);
int cmd_export(int argc, char **argv);

#endif
