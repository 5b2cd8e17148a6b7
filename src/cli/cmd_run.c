/* src/cli/cmd_run.c - `hovox run SCRIPT.lua [args...]`: a Lua 5.4 modeling script with the
 * `hovox` module, `arg` as in standalone Lua, and an optional sandbox for scripts from others. */
#include <stdio.h>
#include <sys/stat.h>
#include <string.h>

#include <lauxlib.h>
#include <lualib.h>

#include "lua/lhovox.h"
#include "cli.h"

typedef struct run_cli {
    int sandbox;
    const char *output_dir;
} run_cli;

static const hv_option k_local_opts[] = {
    {.key = "sandbox", .kind = HV_OPT_FLAG, .offset = offsetof(run_cli, sandbox),
     .help = "for scripts from others: no os.execute, io.popen, C modules, and no file writes outside the output "
             "directory"},
    {.key = "output_dir", .kind = HV_OPT_STRING, .offset = offsetof(run_cli, output_dir), .meta = "DIR",
     .help = "the directory sandboxed scripts may write in (default: .)"},
};
static const hv_option_set k_local = CLI_LOCAL_SET("run", k_local_opts, run_cli);


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

/* argv[0] is the script, argv[1..argc-1] its arguments */
static int run_script(const run_cli *c, char **argv, int argc)
{
    const char *script = argv[0], *outdir = c->output_dir ? c->output_dir : ".";
    int sandbox = c->sandbox;
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
    lua_createtable(L, argc, 1);
    lua_pushstring(L, "hovox run");
    lua_rawseti(L, -2, -1);
    for (int i = 0; i < argc; ++i) {
        lua_pushstring(L, argv[i]);
        lua_rawseti(L, -2, i);
    }
    lua_setglobal(L, "arg");
    int rc = EXIT_OK;
    lua_pushcfunction(L, traceback);
    /* a sandboxed script is text: Lua does not verify precompiled chunks */
    int ls = luaL_loadfilex(L, script, sandbox ? "t" : "bt");
    if (ls != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        rc = ls == LUA_ERRFILE ? EXIT_IO : ls == LUA_ERRMEM ? EXIT_RESOURCE : EXIT_BAD_INPUT;
        fprintf(stderr, "hovox: %s\n", msg ? msg : "cannot load the script");
    } else {
        for (int i = 1; i < argc; ++i) lua_pushstring(L, argv[i]);
        if (lua_pcall(L, argc - 1, 0, -argc - 1) != LUA_OK) {
            const char *msg = lua_tostring(L, -1);
            fprintf(stderr, "hovox: %s\n", msg ? msg : "error");
            rc = EXIT_BAD_INPUT;
        }
    }
    fflush(stdout);
    lua_close(L);
    return rc;
}

static int run(const cli_args *args, void *lib, void *local)
{
    (void)lib;
    return run_script(local, args->pos, args->npos);
}

const cli_spec cmd_run = {
    "run", "run a Lua modeling script", "[options] SCRIPT.lua [args...]",
    "Run a Lua 5.4 modeling script. The module is available as the global `hovox` and via\n"
    "require('hovox'); the script's arguments are in `arg` (arg[0] is the script).\n"
    "Errors print 'hovox: SCRIPT.lua:LINE: message' and exit 1. Options go before SCRIPT.\n",
    NULL, &k_local, NULL, 1, -1, "SCRIPT.lua", CLI_THREADS | CLI_STOP_AT_POS, run, NULL};
