/* src/cli/cmd_run.c - `hovox run SCRIPT.lua [args...]`: a Lua 5.4 modeling script with the
 * `hovox` module, `arg` as in standalone Lua, and an optional sandbox for scripts from others.
 * A script's time and memory are bounded (--max-time, --max-memory; defaults in the sandbox),
 * and Ctrl-C or SIGTERM stop it: an instruction hook and every binding's entry raise the stop at
 * the script's line, pcall, xpcall and coroutines cannot catch it, the library's cancel check
 * stops a long operation; where none of these runs (a long pattern match, a finalizer, the
 * state's close) a watchdog thread ends the process, after removing the library's temporaries. */
#include <fcntl.h>
#include <malloc.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <lauxlib.h>
#include <lualib.h>

#if defined(__SANITIZE_ADDRESS__)
/* AddressSanitizer's count of the bytes its allocator has handed out (sanitizer/
 * allocator_interface.h, which GCC's packages do not always install) */
size_t __sanitizer_get_current_allocated_bytes(void);
#endif

#include "cli.h"
#include "core/internal.h"
#include "hovox/layers.h"
#include "lua/lhovox.h"

#define SANDBOX_MAX_TIME 600.0              /* seconds */
#define SANDBOX_MAX_MEMORY (2ull << 30)     /* bytes */
#define GRACE 0.5                           /* seconds a stopped script has to end by itself */
#define WATCH_PERIOD 0.02                   /* seconds between the watchdog's looks */


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
     .help = "the most the script may hold: its Lua heap and everything the library allocates for it (models, "
             "meshes, ...); every operation is planned against what is left (exit 3 beyond)"},
};
static const hv_option_set k_local = CLI_LOCAL_SET("run", k_local_opts, run_cli);

/* ---- what stops a script ------------------------------------------------------------------------
 * Set once (the first reason wins) by the hook, a binding's entry, the allocator or the watchdog;
 * read everywhere. */

enum { RUN = 0, STOP_INTERRUPT, STOP_TIME, STOP_MEMORY };

static atomic_int g_stop;
static _Atomic double g_stop_at;       /* monotonic seconds when it was set */
static atomic_int g_signals;           /* SIGINT and SIGTERM received */
static _Atomic double g_signal_first, g_signal_last; /* when */
static atomic_int g_reported;          /* the script's error was printed */
static struct sigaction g_prev_int, g_prev_term;

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void stop(int reason)
{
    int expected = RUN;
    if (atomic_compare_exchange_strong(&g_stop, &expected, reason)) atomic_store(&g_stop_at, now_seconds());
}

/* Counts the signals, then runs the CLI's handler (which sets the flag the library's cancel
 * check and cli_interrupted read). */
static void on_signal(int sig)
{
    double t = now_seconds(); /* clock_gettime is async-signal-safe */
    if (atomic_fetch_add(&g_signals, 1) == 0) atomic_store(&g_signal_first, t);
    atomic_store(&g_signal_last, t);
    const struct sigaction *prev = sig == SIGINT ? &g_prev_int : &g_prev_term;
    if (!(prev->sa_flags & SA_SIGINFO) && prev->sa_handler != SIG_DFL && prev->sa_handler != SIG_IGN)
        prev->sa_handler(sig);
}

static void install_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &g_prev_int);
    sigaction(SIGTERM, &sa, &g_prev_term);
}

/* ---- memory -------------------------------------------------------------------------------------
 * The script's memory is what the process holds for it beyond what it held before the script
 * began: the Lua heap, counted exactly by its allocator, and every allocation of the library (on
 * any thread). The library's share is counted exactly by the C allocator (bytes in use: a walk
 * of its free lists, too slow for every call), and in between followed by the resident size
 * (one read): its growth since the last exact count, less the Lua heap's, is taken as the
 * library's growth. An exact count is made again when that estimate passes half the limit, at
 * most every 50 ms (every 10 ms when it passes the limit), so memory freed but kept by the
 * allocator never stops a script. Under AddressSanitizer (whose shadow and quarantine make the
 * resident size meaningless) its own count of bytes handed out serves for both. */

typedef struct heap {
    size_t used;                 /* the Lua heap */
    size_t limit;                /* 0: none */
    _Atomic size_t c_bytes;      /* the library's share: the estimate */
    pthread_mutex_t lock;        /* the rest is measure()'s (the main thread and the watchdog) */
    size_t c0, rss0;             /* bytes in use and resident size before the script */
    size_t exact_c, exact_rss, exact_lua; /* the last exact count, the resident size and heap then */
    double exact_at;
} heap;

static heap *g_heap;

#if !defined(__SANITIZE_ADDRESS__)
static int g_statm = -1; /* /proc/self/statm, kept open: one pread per count */
#endif

static size_t resident_bytes(void)
{
#if defined(__SANITIZE_ADDRESS__)
    return __sanitizer_get_current_allocated_bytes();
#else
    char buf[128];
    if (g_statm < 0) g_statm = open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
    ssize_t n = g_statm >= 0 ? pread(g_statm, buf, sizeof buf - 1, 0) : -1;
    if (n <= 0) return 0;
    buf[n] = '\0';
    unsigned long long size = 0, resident = 0;
    if (sscanf(buf, "%llu %llu", &size, &resident) != 2) return 0;
    return (size_t)resident * (size_t)sysconf(_SC_PAGESIZE);
#endif
}

static size_t allocated_bytes(void)
{
#if defined(__SANITIZE_ADDRESS__)
    return __sanitizer_get_current_allocated_bytes();
#else
    struct mallinfo2 mi = mallinfo2();
    return mi.uordblks + mi.hblkhd;
#endif
}

static size_t minus(size_t a, size_t b) { return a > b ? a - b : 0; }

static void exact_count(heap *h, size_t rss, double now)
{
    size_t lua = h->used;
    h->exact_c = minus(allocated_bytes(), h->c0 + lua);
    h->exact_rss = rss;
    h->exact_lua = lua;
    h->exact_at = now;
}

static void heap_start(heap *h)
{
    pthread_mutex_init(&h->lock, NULL);
    h->c0 = allocated_bytes();
    h->rss0 = resident_bytes();
    h->exact_rss = h->rss0;
    h->exact_at = now_seconds();
}

/* Update the library's share (see above); any thread. Returns the script's total. */
static size_t measure(heap *h)
{
    pthread_mutex_lock(&h->lock);
    double now = now_seconds();
    size_t rss = resident_bytes(), lua = h->used;
    /* signed: the resident size falls when a big block is given back */
    double grown = ((double)rss - (double)h->exact_rss) - ((double)lua - (double)h->exact_lua);
    double est = (double)h->exact_c + grown;
    size_t c = est > 0 ? (size_t)est : 0;
    double age = now - h->exact_at;
    if ((c + lua > h->limit && age > 0.01) || (c + lua > h->limit / 2 && age > 0.05)) {
        exact_count(h, rss, now);
        c = h->exact_c;
    }
    atomic_store(&h->c_bytes, c);
    pthread_mutex_unlock(&h->lock);
    return c + lua;
}

static size_t total(heap *h) { return h->used + atomic_load(&h->c_bytes); }

/* Lua's heap, within what the limit leaves: crossing the limit stops the script (at the next
 * hook, with its line); an allocation beyond a quarter more fails. */
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
        size_t after = total(h) - old + nsize;
        if (after > h->limit) stop(STOP_MEMORY);
        if (after > h->limit + h->limit / 4) return NULL;
    }
    void *p = realloc(ptr, nsize);
    if (p) h->used = h->used - old + nsize;
    return p;
}

/* ---- stopping the script at its line ---------------------------------------------------------- */

static const char *stop_text(char *buf, size_t size, int reason)
{
    if (reason == STOP_INTERRUPT) return "interrupted";
    if (reason == STOP_TIME) return "time limit exceeded";
    char need[32];
    snprintf(buf, size, "memory limit of %s exceeded", hv_size_text(need, sizeof need, (double)g_heap->limit));
    return buf;
}

/* The reason to stop now, if any (Ctrl-C, the time limit, the memory limit). */
static int should_stop(void)
{
    if (atomic_load(&g_stop) == RUN) {
        if (cli_interrupted() || atomic_load(&g_signals)) stop(STOP_INTERRUPT);
        else if (cli_out_of_time()) stop(STOP_TIME);
        else if (g_heap->limit && total(g_heap) > g_heap->limit) stop(STOP_MEMORY);
    }
    return atomic_load(&g_stop);
}

static int raise_stop(lua_State *L, int reason)
{
    char buf[64];
    return luaL_error(L, "%s", stop_text(buf, sizeof buf, reason));
}

/* Every 1,000 instructions; raised again at every call once stopped. */
static void stop_hook(lua_State *L, lua_Debug *ar)
{
    (void)ar;
    int reason = should_stop();
    if (reason) raise_stop(L, reason);
}

/* On entry to every binding (before it reads anything): the stop, then the memory left to the
 * call as the cap of every operation's plan. */
static void binding_entry(lua_State *L, void *user)
{
    heap *h = user;
    /* a count at most a millisecond old: what an operation that short can allocate is little */
    static double last;
    double now = now_seconds();
    if (h->limit && now - last > 0.001) {
        measure(h);
        last = now;
    }
    int reason = should_stop();
    if (reason) raise_stop(L, reason);
    if (h->limit) {
        size_t t = total(h);
        hv_set_memory_cap(t < h->limit ? h->limit - t : 1);
    }
}

/* The library's cancel check, on the thread that called it. */
static int cancel_check(void *user)
{
    (void)user;
    return should_stop() != RUN;
}

/* pcall, xpcall, coroutine.resume and coroutine.close as the originals (upvalue 1), except that
 * a failure while the script is being stopped is raised again: the stop cannot be caught. */
static int after_protected(lua_State *L, int status, lua_KContext base)
{
    (void)status;
    int reason = atomic_load(&g_stop);
    if (reason && lua_gettop(L) > (int)base && lua_type(L, (int)base + 1) == LUA_TBOOLEAN &&
        !lua_toboolean(L, (int)base + 1))
        return raise_stop(L, reason);
    return lua_gettop(L) - (int)base;
}

static int protected_call(lua_State *L)
{
    int base = lua_gettop(L);
    lua_pushvalue(L, lua_upvalueindex(1));
    for (int i = 1; i <= base; ++i) lua_pushvalue(L, i);
    lua_callk(L, base, LUA_MULTRET, base, after_protected);
    return after_protected(L, LUA_OK, base);
}

static void guard(lua_State *L, const char *lib, const char *name)
{
    int t = lib ? lua_getglobal(L, lib) : (lua_pushglobaltable(L), LUA_TTABLE);
    if (t == LUA_TTABLE && lua_getfield(L, -1, name) == LUA_TFUNCTION) {
        lua_pushcclosure(L, protected_call, 1);
        lua_setfield(L, -2, name);
    } else if (t == LUA_TTABLE) {
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
}

/* The message handler: the error with the line of the innermost Lua function, which a memory
 * error (raised inside an allocation) does not carry by itself; once stopped, the reason. */
static int message(lua_State *L)
{
    const char *msg = lua_tostring(L, 1);
    char buf[64];
    int reason = atomic_load(&g_stop);
    if (reason) msg = stop_text(buf, sizeof buf, reason);
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

/* ---- the watchdog ---------------------------------------------------------------------------------
 * Notices the signals, the time and the memory limit where no hook runs, and ends the process
 * when a stopped script has not ended GRACE seconds later, or at a second signal. */

typedef struct watchdog {
    pthread_t thread;
    atomic_int quit;
    const char *script;
    heap *h;
} watchdog;

/* A second Ctrl-C: a signal well after the first (timeout(1) and a terminal may deliver one
 * signal twice, to the process and to its group). */
static int second_signal(void)
{
    return atomic_load(&g_signals) >= 2 && atomic_load(&g_signal_last) - atomic_load(&g_signal_first) > 0.1;
}

static void end_process(const watchdog *w, int reason)
{
    hv_temp_remove_all(); /* no partial output left behind */
    if (!atomic_load(&g_reported)) {
        char buf[64], line[1024];
        int n = snprintf(line, sizeof line, "hovox: %s: %s (ended: the script did not stop%s)\n", w->script,
                         stop_text(buf, sizeof buf, reason),
                         second_signal() ? " at the first signal" : " within half a second");
        if (n > 0) {
            ssize_t wr = write(STDERR_FILENO, line, (size_t)n < sizeof line ? (size_t)n : sizeof line - 1);
            (void)wr;
        }
    }
    _exit(reason == STOP_INTERRUPT ? EXIT_INTERRUPTED : EXIT_RESOURCE);
}

static void *watch(void *arg)
{
    watchdog *w = arg;
    const struct timespec period = {0, (long)(WATCH_PERIOD * 1e9)};
    while (!atomic_load(&w->quit)) {
        nanosleep(&period, NULL);
        if (w->h->limit) measure(w->h);
        int reason = should_stop();
        if (reason && (second_signal() || now_seconds() - atomic_load(&g_stop_at) > GRACE))
            end_process(w, reason);
    }
    return NULL;
}

/* ---- progress ------------------------------------------------------------------------------------ */

/* The CLI's bar, a stage's line ended when it is complete (the script may print next). */
typedef struct run_bar {
    cli_progress bar;
    char finished[32]; /* the stage last completed: a second report of its end draws nothing */
} run_bar;

static int run_progress(void *user, const char *stage, double fraction)
{
    run_bar *b = user;
    if (fraction >= 1.0 && strncmp(b->finished, stage, sizeof b->finished - 1) == 0) return 0;
    b->finished[0] = '\0';
    int rc = cli_progress_fn(&b->bar, stage, fraction);
    if (fraction >= 1.0) {
        cli_progress_done(&b->bar);
        snprintf(b->finished, sizeof b->finished, "%s", stage);
    }
    return rc;
}

/* ---- running -------------------------------------------------------------------------------------- */

static int open_hovox_global(lua_State *L)
{
    luaL_requiref(L, "hovox", luaopen_hovox, 1);
    lua_pop(L, 1);
    return 0;
}

/* The exit code of a failed load or call: what stopped it decides, or the library failure that
 * ended the script (a plan over the memory limit: 3, as the command's), not its text. */
static int failure_code(lua_State *L, int status, const char *msg)
{
    int reason = atomic_load(&g_stop);
    if (reason == STOP_INTERRUPT || cli_interrupted()) return EXIT_INTERRUPTED;
    if (reason || cli_out_of_time() || status == LUA_ERRMEM) return EXIT_RESOURCE;
    if (status == LUA_ERRFILE) return EXIT_IO;
    hv_status failed = hv_lua_failure_status(L, msg);
    return failed == HV_ERR_LIMIT || failed == HV_ERR_NOMEM ? EXIT_RESOURCE : EXIT_BAD_INPUT;
}

/* argv[0] is the script, argv[1..argc-1] its arguments */
static int run_script(const run_cli *c, char **argv, int argc, int quiet)
{
    const char *script = argv[0], *outdir = c->output_dir ? c->output_dir : ".";
    int sandbox = c->sandbox;
    struct stat od;
    if (sandbox && (stat(outdir, &od) != 0 || !S_ISDIR(od.st_mode))) {
        fprintf(stderr, "hovox: %s: the sandbox's output directory does not exist (create it first)\n", outdir);
        return EXIT_IO;
    }
    double max_time = c->max_time > 0 ? c->max_time : sandbox ? SANDBOX_MAX_TIME : 0;
    heap h = {0};
    h.limit = c->max_memory ? c->max_memory : sandbox ? SANDBOX_MAX_MEMORY : 0;
    heap_start(&h);
    g_heap = &h;
    install_signals();
    cli_set_time_limit(max_time);
    hv_set_memory_cap(h.limit);
    hv_set_cancel_check(cancel_check, NULL);
    if (sandbox) hv_set_cache_dir(""); /* the blue-noise tile stays in memory */
    lua_State *L = lua_newstate(limited_alloc, &h);
    if (!L) {
        fprintf(stderr, "hovox: out of memory creating the Lua state\n");
        return EXIT_RESOURCE;
    }
    watchdog w = {.script = script, .h = &h};
    if (pthread_create(&w.thread, NULL, watch, &w) != 0) {
        lua_close(L);
        fprintf(stderr, "hovox: cannot start the script's watchdog thread\n");
        return EXIT_RESOURCE;
    }
    lua_sethook(L, stop_hook, LUA_MASKCOUNT, 1000);
    luaL_openlibs(L);
    open_hovox_global(L);
    run_bar bar = {0};
    cli_progress_init(&bar.bar, quiet);
    const hv_progress progress = {run_progress, &bar};
    hv_lua_set_runner(L, binding_entry, &h, &progress);
    guard(L, NULL, "pcall");
    guard(L, NULL, "xpcall");
    guard(L, "coroutine", "resume");
    guard(L, "coroutine", "close");
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
    const char *lm = st != LUA_OK ? lua_tostring(L, -1) : NULL;
    const char *at = lm ? strstr(lm, script) : NULL;
    size_t sl = strlen(script);
    if (st == LUA_ERRFILE && at && strncmp(lm, "cannot ", 7) == 0 && strncmp(at + sl, ": ", 2) == 0) {
        /* Lua's "cannot open S: reason" in hovox's form, "S: cannot open: reason" */
        char what[32];
        snprintf(what, sizeof what, "%.*s", (int)(at - lm - 1), lm);
        lua_pushfstring(L, "%s: %s: %s", script, what, at + sl + 2);
        lua_remove(L, -2);
    } else if (st != LUA_OK && !at) {
        lua_pushfstring(L, "%s: %s", script, lm ? lm : ""); /* name the script */
        lua_remove(L, -2);
    }
    if (st == LUA_OK) {
        for (int i = 1; i < argc; ++i) lua_pushstring(L, argv[i]);
        st = lua_pcall(L, argc - 1, 0, -argc - 1);
    }
    cli_progress_done(&bar.bar);
    if (st != LUA_OK) {
        const char *msg = lua_tostring(L, -1);
        char buf[64];
        rc = failure_code(L, st, msg);
        if (st == LUA_ERRMEM && atomic_load(&g_stop)) /* no message handler ran: no line to give */
            fprintf(stderr, "hovox: %s: %s\n", script, stop_text(buf, sizeof buf, atomic_load(&g_stop)));
        else
            fprintf(stderr, "hovox: %s\n", msg ? msg : "error");
        atomic_store(&g_reported, 1);
    }
    fflush(stdout);
    fflush(stderr);
    lua_close(L); /* the finalizers run under the watchdog too */
    atomic_store(&w.quit, 1);
    pthread_join(w.thread, NULL);
    hv_set_cancel_check(NULL, NULL);
    pthread_mutex_destroy(&h.lock);
    g_heap = NULL;
    return rc;
}

static int run(const cli_args *args, void *lib, void *local)
{
    (void)lib;
    return run_script(local, args->pos, args->npos, args->quiet);
}

const cli_spec cmd_run = {
    "run", "run a Lua modeling script", "[options] SCRIPT.lua [args...]",
    "Run a Lua 5.4 modeling script. The module is available as the global `hovox` and via\n"
    "require('hovox'); the script's arguments are in `arg` (arg[0] is the script).\n"
    "Errors print 'hovox: SCRIPT.lua:LINE: message' and exit 1 (3 over a limit, 130 on\n"
    "Ctrl-C). Options go before SCRIPT.\n",
    NULL, &k_local, NULL, 1, -1, "SCRIPT.lua", CLI_THREADS | CLI_QUIET | CLI_STOP_AT_POS, run, NULL, NULL};
