/* src/lua/lhovox.c - the `hovox` Lua 5.4 module: the helpers every binding file shares and the
 * module table, assembled from the per-class files (see lhovox.h for the rules they follow). */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <lauxlib.h>

#include "core/internal.h"
#include "lhovox.h"

int hv_lua_arg_error(lua_State *L, int arg, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return luaL_argerror(L, arg, msg);
}


void *hv_lua_new_ud(lua_State *L, size_t size, const char *mt)
{
    void *p = lua_newuserdatauv(L, size, 1);
    memset(p, 0, size);
    luaL_setmetatable(L, mt);
    return p;
}

void *hv_lua_check_live(lua_State *L, int arg, const char *mt)
{
    void **p = luaL_checkudata(L, arg, mt);
    if (!*p) luaL_argerror(L, arg, "object was freed");
    return p;
}

int hv_lua_numbers(lua_State *L, int idx, int arg, const char *what, double *out, int max)
{
    idx = lua_absindex(L, idx);
    if (!lua_istable(L, idx))
        return arg_error(L, arg, "%s must be a list of numbers, got %s", what, luaL_typename(L, idx));
    int n = (int)lua_rawlen(L, idx);
    if (n > max) return arg_error(L, arg, "%s has %d numbers (at most %d)", what, n, max);
    for (int i = 0; i < n; ++i) {
        int ok, t = lua_rawgeti(L, idx, i + 1);
        out[i] = lua_tonumberx(L, -1, &ok);
        lua_pop(L, 1);
        if (t != LUA_TNUMBER || !ok || !isfinite(out[i]))
            arg_error(L, arg, "%s[%d] must be a finite number", what, i + 1);
    }
    return n;
}

void hv_lua_push_vec(lua_State *L, const double *v, int n)
{
    lua_createtable(L, n, 0);
    for (int i = 0; i < n; ++i) {
        lua_pushnumber(L, v[i]);
        lua_rawseti(L, -2, i + 1);
    }
}

void *hv_lua_option_object(lua_State *L, int arg, const char *key, const char *mt, const char *what)
{
    hv_lua_field(L, arg, key);
    void **p = luaL_testudata(L, -1, mt);
    if (!p) arg_error(L, arg, "%s must be a %s", key, what);
    if (!*p) arg_error(L, arg, "%s was freed", key);
    return p;
}

/* ---- objects in use ---------------------------------------------------------------------------- */

#define MAX_FRAMES 256 /* bindings nested through callbacks; deeper ones are covered by these */

typedef struct deferred {
    void (*destroy)(void *);
    void *p;
} deferred;

/* The module's record of a state (a userdata in the registry, finalized last: created first). */
typedef struct lstate {
    uintptr_t frames[MAX_FRAMES]; /* frames of bindings entered and maybe still running */
    int nframes;
    deferred *dead; /* released while a binding ran */
    size_t ndead, cap;
    int closed;
    hv_lua_entry_fn entry;
    void *entry_user;
    hv_progress progress;
    int has_progress;
    hv_status fail_status; /* the library's last failure raised, and its text */
    char fail_text[1024];
} lstate;

static const char k_state = 0; /* its registry key (the address) */

/* The record, or NULL before the module is open; allocates nothing. */
static lstate *state_of(lua_State *L)
{
    lstate *s = lua_rawgetp(L, LUA_REGISTRYINDEX, &k_state) == LUA_TUSERDATA ? lua_touserdata(L, -1) : NULL;
    lua_pop(L, 1);
    return s;
}

/* Forget the frames that cannot be running below `here`: a running binding's frame is above
 * (at a higher address than) every frame it called. */
static void prune(lstate *s, uintptr_t here)
{
    int n = 0;
    for (int i = 0; i < s->nframes; ++i)
        if (s->frames[i] > here) s->frames[n++] = s->frames[i];
    s->nframes = n;
}

static void flush(lstate *s)
{
    /* a destroy runs no Lua code, so nothing is added meanwhile */
    for (size_t i = 0; i < s->ndead; ++i) s->dead[i].destroy(s->dead[i].p);
    s->ndead = 0;
}

void hv_lua_enter(lua_State *L, uintptr_t frame)
{
    lstate *s = state_of(L);
    if (!s) return;
    prune(s, frame);
    if (s->nframes == 0) flush(s);
    if (s->nframes < MAX_FRAMES) s->frames[s->nframes++] = frame;
    if (s->entry) s->entry(L, s->entry_user);
}

void hv_lua_release(lua_State *L, void (*destroy)(void *), void *p)
{
    if (!p) return;
    lstate *s = state_of(L);
    if (s && !s->closed) {
        prune(s, HV_LUA_FRAME());
        if (s->nframes > 0) {
            if (s->ndead == s->cap) {
                size_t cap = s->cap ? 2 * s->cap : 16;
                deferred *d = realloc(s->dead, cap * sizeof *d);
                if (!d) return; /* kept alive: a leak, never a use after free */
                s->dead = d;
                s->cap = cap;
            }
            s->dead[s->ndead++] = (deferred){destroy, p};
            return;
        }
        flush(s);
    }
    destroy(p);
}

static int state_gc(lua_State *L)
{
    lstate *s = lua_touserdata(L, 1);
    flush(s); /* the state is closing: no binding runs */
    free(s->dead);
    s->dead = NULL;
    s->cap = 0;
    s->closed = 1;
    return 0;
}

static lstate *open_state(lua_State *L)
{
    lstate *s = state_of(L);
    if (s) return s;
    s = lua_newuserdatauv(L, sizeof *s, 0);
    memset(s, 0, sizeof *s);
    lua_createtable(L, 0, 1);
    lua_pushcfunction(L, state_gc);
    lua_setfield(L, -2, "__gc");
    lua_setmetatable(L, -2);
    lua_rawsetp(L, LUA_REGISTRYINDEX, &k_state);
    return s;
}

void hv_lua_set_runner(lua_State *L, hv_lua_entry_fn entry, void *user, const hv_progress *progress)
{
    lstate *s = open_state(L);
    s->entry = entry;
    s->entry_user = user;
    s->has_progress = progress != NULL;
    if (progress) s->progress = *progress;
}

const hv_progress *hv_lua_progress(lua_State *L)
{
    lstate *s = state_of(L);
    return s && s->has_progress ? &s->progress : NULL;
}

/* A registered function, entered: upvalue 1 is its luaL_Reg. Called directly (not through
 * lua_call), so Lua names it and counts its arguments as before. */
static int entered(lua_State *L)
{
    const luaL_Reg *r = lua_touserdata(L, lua_upvalueindex(1));
    hv_lua_enter(L, HV_LUA_FRAME());
    return r->func(L);
}

static void push_entered(lua_State *L, const luaL_Reg *r)
{
    lua_pushlightuserdata(L, (void *)r);
    lua_pushcclosure(L, entered, 1);
}

void hv_lua_set_funcs(lua_State *L, const luaL_Reg *fns)
{
    for (const luaL_Reg *r = fns; r->name; ++r) {
        push_entered(L, r);
        lua_setfield(L, -2, r->name);
    }
}

int hv_lua_fail(lua_State *L, hv_status s)
{
    const char *m = hv_last_error();
    luaL_where(L, 1);
    lua_pushfstring(L, "%s%s", lua_tostring(L, -1), *m ? m : hv_status_name(s));
    hv_lua_note_failure(L, s, lua_tostring(L, -1));
    return lua_error(L);
}

void hv_lua_note_failure(lua_State *L, hv_status s, const char *message)
{
    lstate *st = state_of(L);
    if (!st) return;
    st->fail_status = s;
    snprintf(st->fail_text, sizeof st->fail_text, "%s", message ? message : "");
}

hv_status hv_lua_failure_status(lua_State *L, const char *message)
{
    lstate *st = state_of(L);
    return st && message && st->fail_status != HV_OK && strcmp(message, st->fail_text) == 0 ? st->fail_status : HV_OK;
}

void *hv_lua_take(lua_State *L, const char *mt)
{
    void **u = luaL_checkudata(L, 1, mt);
    void *p = *u;
    *u = NULL;
    return p;
}

/* Class `name`'s methods into the table at the top of the stack (its __index), each wrapped to
 * enter except the class's free (gc), and the same functions into package.loaded[name], so an
 * argument error raised in a method called without method syntax (pcall(m.save, m, ...)) names it
 * ('hovox.Mesh.save') instead of '?': Lua looks error names up in the loaded modules. A copy of
 * the table: a script changing it changes no object's methods. */
static void set_methods(lua_State *L, const char *name, const luaL_Reg *methods, lua_CFunction gc)
{
    int index = lua_gettop(L);
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    luaL_getsubtable(L, -1, name);
    for (const luaL_Reg *r = methods; r->name; ++r) {
        if (r->func == gc) lua_pushcfunction(L, r->func);
        else push_entered(L, r);
        lua_pushvalue(L, -1);
        lua_setfield(L, index, r->name);
        lua_setfield(L, -2, r->name);
    }
    lua_settop(L, index);
}

void hv_lua_new_class(lua_State *L, const char *name, const luaL_Reg *methods, lua_CFunction gc,
                      lua_CFunction tostring)
{
    open_state(L); /* before any object: finalized after all of them */
    luaL_newmetatable(L, name);
    lua_newtable(L);
    set_methods(L, name, methods, gc);
    lua_setfield(L, -2, "__index");
    lua_pushcfunction(L, gc);
    lua_setfield(L, -2, "__gc");
    lua_pushcfunction(L, gc);
    lua_setfield(L, -2, "__close");
    if (tostring) {
        /* the function's luaL_Reg lives as long as the state: one per class, kept in the metatable */
        luaL_Reg *r = lua_newuserdatauv(L, sizeof *r, 0);
        *r = (luaL_Reg){"__tostring", tostring};
        lua_setfield(L, -2, "hovox.tostring");
        push_entered(L, r);
        lua_setfield(L, -2, "__tostring");
    }
    /* getmetatable(obj) returns the name: a script cannot call __gc on an object C still uses */
    lua_pushstring(L, name);
    lua_setfield(L, -2, "__metatable");
    lua_pop(L, 1);
}

void hv_lua_add_methods(lua_State *L, const char *name, const luaL_Reg *methods)
{
    luaL_getmetatable(L, name);
    lua_getfield(L, -1, "__index");
    set_methods(L, name, methods, NULL);
    lua_pop(L, 2);
}

static int l_set_threads(lua_State *L)
{
    lua_Integer n = luaL_checkinteger(L, 1);
    if (n < 0 || n > 1024) return arg_error(L, 1, "threads must be in [0, 1024], got %lld", (long long)n);
    hv_set_threads((int)n);
    return 0;
}

/* hovox.mkdir(path): the directory and its missing parents (as mkdir -p), each one checked
 * against the sandbox before it is made; an existing directory is no error. */
static int l_mkdir(lua_State *L)
{
    size_t len;
    const char *given = luaL_checklstring(L, 1, &len);
    if (len == 0 || strlen(given) != len) return luaL_argerror(L, 1, "a directory name, without NUL bytes");
    char *p = lua_newuserdatauv(L, len + 1, 0); /* a private copy, cut at each '/' in turn */
    memcpy(p, given, len + 1);
    for (size_t i = 1; i <= len; ++i) {
        if (p[i] != '/' && p[i] != '\0') continue;
        char c = p[i];
        p[i] = '\0';
        struct stat st;
        if (stat(p, &st) != 0) {
            hv_lua_check_write(L, 1, NULL, p);
            if (mkdir(p, 0777) != 0 && errno != EEXIST)
                return luaL_error(L, "%s: cannot create the directory: %s", p, strerror(errno));
        } else if (!S_ISDIR(st.st_mode)) {
            return luaL_error(L, "%s: exists and is not a directory", p);
        }
        p[i] = c;
    }
    return 0;
}

int luaopen_hovox(lua_State *L)
{
    open_state(L); /* before any object: finalized after all of them */
    lua_newtable(L);
    int module = lua_gettop(L);
    hv_lua_open_mesh(L, module);
    hv_lua_open_model(L, module);
    hv_lua_open_sources(L, module);
    hv_lua_open_output(L, module); /* before objects: they borrow the model's output methods */
    hv_lua_open_object(L, module);
    hv_lua_open_tray(L, module);
    hv_lua_open_scan(L, module);
    hv_lua_open_assembly(L, module);
    static const luaL_Reg fns[] = {{"set_threads", l_set_threads}, {"mkdir", l_mkdir}, {NULL, NULL}};
    hv_lua_set_funcs(L, fns);
    lua_pushstring(L, hv_version());
    lua_setfield(L, module, "version");
    return 1;
}
