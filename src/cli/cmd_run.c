/* src/cli/cmd_run.c - `hovox run SCRIPT.lua [args...]`: a Lua 5.4 modeling script with the
 * `hovox` module, `arg` as in standalone Lua, and an optional sandbox for scripts from others. */
#include <getopt.h>
#include <stdio.h>
#include <sys/stat.h>
#include <string.h>

#include <lauxlib.h>
#include <lualib.h>

#include "lua/lhovox.h"
#include "cli.h"

static const char *RUN_HELP =
    "usage: hovox run [options] SCRIPT.lua [args...]\n"
    "\n"
    "Run a Lua 5.4 modeling script. The module is available as the global `hovox` and via\n"
    "require('hovox'); the script's arguments are in `arg` (arg[0] is the script).\n"
    "Errors print 'hovox: SCRIPT.lua:LINE: message' and exit 1.\n"
    "\n"
    "Options (before SCRIPT):\n"
    "  --sandbox          for scripts from others: no os.execute, io.popen, C modules, and\n"
    "                     no file writes outside the output directory\n"
    "  --output-dir DIR   the directory sandboxed scripts may write in (default: .)\n"
    "  --threads N        worker threads (default: all cores)\n"
    "  -h, --help         this text\n";

static int traceback(lua_State *L)
{
    const char *msg = lua_tostring(L, 1);
    if (!msg) msg = lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
    lua_pushstring(L, msg); /* plain message: the position is already in it */
    return 1;
}

static int open_hovox_global(lua_State *L)
{
    luaL_requiref(L, "hovox", luaopen_hovox, 1);
    lua_pop(L, 1);
    return 0;
}

int cmd_run(int argc, char **argv)
{
    enum { O_SANDBOX = 256, O_OUTDIR, O_THREADS };
    static const struct option opts[] = {{"sandbox", no_argument, NULL, O_SANDBOX},
                                         {"output-dir", required_argument, NULL, O_OUTDIR},
                                         {"threads", required_argument, NULL, O_THREADS},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    int sandbox = 0, c;
    const char *outdir = ".";
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "+h", opts, NULL)) != -1) {
        long n;
        switch (c) {
        case O_SANDBOX: sandbox = 1; break;
        case O_OUTDIR: outdir = optarg; break;
        case O_THREADS:
            if (cli_parse_int("run", "--threads", optarg, 1, 1024, &n)) return EXIT_USAGE;
            hv_set_threads((int)n);
            break;
        case 'h': fputs(RUN_HELP, stdout); return EXIT_OK;
        case ':': return cli_usage_error("run", "option '%s' needs a value", argv[optind - 1]);
        default: return cli_usage_error("run", "unknown option '%s'", argv[optind - 1]);
        }
    }
    if (optind >= argc) return cli_usage_error("run", "missing SCRIPT.lua");
    const char *script = argv[optind];
    struct stat od;
    if (sandbox && (stat(outdir, &od) != 0 || !S_ISDIR(od.st_mode))) {
        fprintf(stderr, "hovox: %s: the sandbox's output directory does not exist (create it first)\n", outdir);
        return EXIT_IO;
    }
    lua_State *L = luaL_newstate();
    if (!L) {
        fprintf(stderr, "hovox: out of memory creating the Lua state\n");
        return EXIT_RESOURCE;
    }
    luaL_openlibs(L);
    open_hovox_global(L);
    if (sandbox) {
        hv_lua_set_write_root(L, outdir);
        hv_lua_sandbox(L);
    }
    /* arg: the script at 0, its arguments from 1, the interpreter before */
    lua_createtable(L, argc - optind, 1);
    lua_pushstring(L, "hovox run");
    lua_rawseti(L, -2, -1);
    for (int i = optind; i < argc; ++i) {
        lua_pushstring(L, argv[i]);
        lua_rawseti(L, -2, i - optind);
    }
    lua_setglobal(L, "arg");
    int rc = EXIT_OK;
    lua_pushcfunction(L, traceback);
    if (luaL_loadfile(L, script) != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        /* a missing file is I/O; anything else a bad script */
        rc = msg && strstr(msg, "cannot open") ? EXIT_IO : EXIT_BAD_INPUT;
        fprintf(stderr, "hovox: %s\n", msg ? msg : "cannot load the script");
    } else {
        for (int i = optind + 1; i < argc; ++i) lua_pushstring(L, argv[i]);
        if (lua_pcall(L, argc - optind - 1, 0, -(argc - optind) - 1) != LUA_OK) {
            const char *msg = lua_tostring(L, -1);
            fprintf(stderr, "hovox: %s\n", msg ? msg : "error");
            rc = EXIT_BAD_INPUT;
        }
    }
    fflush(stdout);
    lua_close(L);
    return rc;
}
