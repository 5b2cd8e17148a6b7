/* src/cli/main.c - `hovox <command> [options]`: the command table, --help, --version. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

static const cli_spec *const g_commands[] = {&cmd_info,     &cmd_voxelize, &cmd_grade,  &cmd_boolean,
                                             &cmd_probe,    &cmd_profile,  &cmd_run,    &cmd_render,
                                             &cmd_contours, &cmd_layers,   &cmd_tray,   &cmd_view,
                                             &cmd_export,   &cmd_generate, &cmd_colour};

static void print_help(FILE *out)
{
    fprintf(out,
            "usage: hovox <command> [options]\n"
            "       hovox --version | --help\n"
            "\n"
            "Heterogeneous-object modeling for multi-material 3D printing.\n"
            "\n"
            "Commands:\n");
    for (size_t i = 0; i < sizeof g_commands / sizeof g_commands[0]; ++i)
        fprintf(out, "  %-10s %s\n", g_commands[i]->name, g_commands[i]->summary);
    fprintf(out,
            "\n"
            "Run 'hovox <command> --help' or 'hovox help <command>' for a command's options.\n"
            "\n"
            "Exit codes: 0 ok, 1 bad input, 2 usage, 3 resource limit, 4 I/O,\n"
            "            70 internal error, 130 interrupted.\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        print_help(stderr);
        return EXIT_USAGE;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "version") == 0) {
        if (argc > 2) {
            fprintf(stderr, "hovox: %s takes no arguments (got '%s')\n", cmd, argv[2]);
            return EXIT_USAGE;
        }
        printf("hovox %s\n", hv_version());
        return EXIT_OK;
    }
    char *help_argv[] = {NULL, "--help", NULL};
    if ((strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) && argc > 3) {
        fprintf(stderr, "hovox: %s takes one command at most (got '%s' and '%s')\n", cmd, argv[2], argv[3]);
        return EXIT_USAGE;
    }
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
        if (argc == 2) {
            print_help(stdout);
            return EXIT_OK;
        }
        cmd = help_argv[0] = argv[2]; /* `hovox help layers` is `hovox layers --help` */
    }
    for (size_t i = 0; i < sizeof g_commands / sizeof g_commands[0]; ++i)
        if (strcmp(cmd, g_commands[i]->name) == 0) {
            cli_install_signals();
            return help_argv[0] ? cli_main(g_commands[i], 2, help_argv) : cli_main(g_commands[i], argc - 1, argv + 1);
        }
    fprintf(stderr, "hovox: unknown command '%s'\nTry 'hovox --help'.\n", cmd);
    return EXIT_USAGE;
}
