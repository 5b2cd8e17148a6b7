/* src/cli/cmd_run.c - `hovox run SCRIPT.lua [args...]`: a Lua 5.4 modeling script with the
 * `hovox` module, `arg` as in standalone Lua, and an optional sandbox for scripts from others.
 * A script's time and memory are bounded (--max-time, --max-memory; defaults in the sandbox):
 * Lua's heap through its allocator, the library's operations through the process-wide memory
 * cap, and time (and Ctrl-C) through an instruction hook and the library's cancel check. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <lauxlib.h>
#include <lualib.h>

#include "cli.h"
#include "core/internal.h"
#include "hovox/layers.h"
#include "lua/lhovox.h"

#define SANDBOX_MAX_TIME 600.0              /* seconds */
#define SANDBOX_MAX_MEMORY (2ull << 30)     /* bytes */

typedef struct run_cli {
    int sandbox;
    const char *output_dir;
    double max_time;
    uint64_t max_memory;
} run_cli;

static const hv_option k_local_opts[] = {
    {.key = "sandbox", .kind = HV_OPT_FLAG, .offset = offsetof(run_cli, sandbox),
     .help = "for scripts from others: no os.execute, io.popen, C modules or bytecode, no file writes outside "
             "the output directory, and time and memory limited (600 s and 2G unless given)"},
    {.key = "output_dir", .kind = HV_OPT_STRING, .offset = offsetof(run_cli, output_dir), .meta = "DIR",
     .help = "the directory sandboxed scripts may write in (default: .)"},
    {.key = "max_time", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e9, .flags = HV_OPT_LO_OPEN | HV_OPT_UNSET0,
     .offset = offsetof(run_cli, max_time), .meta = "SECONDS", .unit = "s",
     .help = "stop the script after this long (exit 3)"},
    {.key = "max_memory", .kind = HV_OPT_BYTES, .offset = offsetof(run_cli, max_memory), .meta = "SIZE",
     .help = "the most the script's Lua heap may hold, and the most any one operation it calls may plan "
             "(exit 3 beyond)"},
};
static const hv_option_set k_local = CLI_LOCAL_SET("run", k_local_opts, run_cli);

/* ---- limits ------------------------------------------------------------------------------------ */

/* The heap limit is soft up to a quarter more: crossing it is raised as an ordinary error at
 * the next hook, with the script's line (Lua calls no message handler for an allocation that
 * fails); only beyond the hard limit does an allocation fail. */
typedef struct heap {
    size_t used, limit; /* limit 0: none */
    int over;           /* the soft limit was crossed */
    int raised;         /* ... and said so */
} heap;

static heap *g_heap;

static void *limited_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    heap *h = ud;
    if (nsize == 0) {
        free(ptr);
        if (ptr) h->used -= osize;
        return NULL;
    }
    size_t old = ptr ? osize : 0;
    if (h->limit && nsize > old) {
        size_t after = h->used - old + nsize;
        if (after > h->limit) h->over = 1;
        if (after > h->limit + h->limit / 4) return NULL;
    }
    void *p = realloc(ptr, nsize);
    if (p) h->used = h->used - old + nsize;
    return p;
}

/* Every 1,000 instructions: Ctrl-C, the time limit or the memory limit end the script. */
static void stop_hook(lua_State *L, lua_Debug *ar)
{
    (void)ar;
    if (cli_interrupted()) luaL_error(L, "interrupted");
    if (cli_out_of_time()) luaL_error(L, "time limit exceeded");
    if (g_heap->over && !g_heap->raised) {
        g_heap->raised = 1;
        char need[32];
        luaL_error(L, "memory limit of %s exceeded", hv_size_text(need, sizeof need, (double)g_heap->limit));
    }
}

/* The message handler: the error with the line of the innermost Lua function, which a memory
 * error (raised inside an allocation) does not carry by itself. */
static int message(lua_State *L)
{
    const char *msg = lua_tostring(L, 1);
    if (!msg) msg = lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
    lua_Debug ar;
    for (int level = 0; lua_getstack(L, level, &ar); ++level) {
        if (!lua_getinfo(L, "Sl", &ar) || ar.currentline <= 0) continue;
        char where[256];
        snprintf(where, sizeof where, "%s:%d:", ar.short_src, ar.currentline);
        if (strncmp(msg, where, strlen(where)) != 0) lua_pushfstring(L, "%s %s", where, msg);
        else lua_pushstring(L, msg);
        return 1;
    }
    lua_pushstring(L, msg);
    return 1;
}

static int open_hovox_global(lua_State *L)
{
    luaL_requiref(L, "hovox", luaopen_hovox, 1);
    lua_pop(L, 1);
    return 0;
}

/* The exit code of a failed load or call: what stopped it decides, not its text. */
static int failure_code(int status, const heap *h)
{
    if (cli_interrupted()) return EXIT_INTERRUPTED;
    if (cli_out_of_time() || status == LUA_ERRMEM || h->over) return EXIT_RESOURCE;
    return status == LUA_ERRFILE ? EXIT_IO : EXIT_BAD_INPUT;
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
    double max_time = c->max_time > 0 ? c->max_time : sandbox ? SANDBOX_MAX_TIME : 0;
    heap h = {0, c->max_memory ? c->max_memory : sandbox ? SANDBOX_MAX_MEMORY : 0, 0, 0};
    g_heap = &h;
    cli_set_time_limit(max_time);
    hv_set_memory_cap(h.limit);
    if (sandbox) hv_set_cache_dir(""); /* the blue-noise tile stays in memory */
    lua_State *L = lua_newstate(limited_alloc, &h);
    if (!L) {
        fprintf(stderr, "hovox: out of memory creating the Lua state\n");
        return EXIT_RESOURCE;
    }
    lua_sethook(L, stop_hook, LUA_MASKCOUNT, 1000);
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
    lua_pushcfunction(L, message);
    /* a sandboxed script is text: Lua does not verify precompiled chunks */
    int st = luaL_loadfilex(L, script, sandbox ? "t" : "bt");
    if (st != LUA_OK && !strstr(lua_tostring(L, -1) ? lua_tostring(L, -1) : "", script)) {
        lua_pushfstring(L, "%s: %s", script, lua_tostring(L, -1)); /* name the script */
        lua_remove(L, -2);
    }
    if (st == LUA_OK) {
        for (int i = 1; i < argc; ++i) lua_pushstring(L, argv[i]);
        st = lua_pcall(L, argc - 1, 0, -argc - 1);
    }
    if (st != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        rc = failure_code(st, &h);
        fprintf(stderr, "hovox: %s%s\n", msg ? msg : "error",
                st == LUA_ERRMEM && h.over ? ": over the script's memory limit (--max-memory)" : "");
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
    "Errors print 'hovox: SCRIPT.lua:LINE: message' and exit 1 (3 over a limit, 130 on\n"
    "Ctrl-C). Options go before SCRIPT.\n",
    NULL, &k_local, NULL, 1, -1, "SCRIPT.lua", CLI_THREADS | CLI_STOP_AT_POS, run, NULL, NULL};
