/* src/cli/pending.c - weak fallbacks for commands whose modules are being built in parallel;
 * a module's real cmd_* overrides these. Removed once every command has landed. */
#include <stdio.h>

#include "cli.h"

static int pending(const char *name)
{
    fprintf(stderr, "hovox: '%s' is not available in this build yet\n", name);
    return EXIT_USAGE;
}

#define PENDING(fn, name) \
    __attribute__((weak)) int fn(int argc, char **argv) { (void)argc; (void)argv; return pending(name); }

PENDING(cmd_voxelize, "voxelize")
PENDING(cmd_run, "run")
PENDING(cmd_probe, "probe")
PENDING(cmd_profile, "profile")
PENDING(cmd_grade, "grade")
PENDING(cmd_render, "render")
PENDING(cmd_contours, "contours")
PENDING(cmd_layers, "layers")
PENDING(cmd_export, "export")
