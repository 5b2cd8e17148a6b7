/* src/lua/lhovox.c - the `hovox` Lua 5.4 module: the helpers every binding file shares and the
 * module table, assembled from the per-class files (see lhovox.h for the rules they follow). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

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

int hv_lua_fail(lua_State *L, hv_status s)
{
    const char *m = hv_last_error();
    return luaL_error(L, "%s", *m ? m : hv_status_name(s));
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

void *hv_lua_take(lua_State *L, const char *mt)
{
    void **u = luaL_checkudata(L, 1, mt);
    void *p = *u;
    *u = NULL;
    return p;
}

/* A copy of class `name`'s methods in package.loaded[name], so an argument error raised in a
 * method called without method syntax (pcall(m.save, m, ...)) names it ('hovox.Mesh.save')
 * instead of '?': Lua looks error names up in the loaded modules. A copy: a script changing it
 * changes no object's methods. */
static void name_methods(lua_State *L, const char *name, const luaL_Reg *methods)
{
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    luaL_getsubtable(L, -1, name);
    luaL_setfuncs(L, methods, 0);
    lua_pop(L, 2);
}

void hv_lua_new_class(lua_State *L, const char *name, const luaL_Reg *methods, lua_CFunction gc,
                      lua_CFunction tostring)
{
    name_methods(L, name, methods);
    luaL_newmetatable(L, name);
    lua_newtable(L);
    luaL_setfuncs(L, methods, 0);
    lua_setfield(L, -2, "__index");
    lua_pushcfunction(L, gc);
    lua_setfield(L, -2, "__gc");
    lua_pushcfunction(L, gc);
    lua_setfield(L, -2, "__close");
    if (tostring) {
        lua_pushcfunction(L, tostring);
        lua_setfield(L, -2, "__tostring");
    }
    /* getmetatable(obj) returns the name: a script cannot call __gc on an object C still uses */
    lua_pushstring(L, name);
    lua_setfield(L, -2, "__metatable");
    lua_pop(L, 1);
}

void hv_lua_add_methods(lua_State *L, const char *name, const luaL_Reg *methods)
{
    name_methods(L, name, methods);
    luaL_getmetatable(L, name);
    lua_getfield(L, -1, "__index");
    luaL_setfuncs(L, methods, 0);
    lua_pop(L, 2);
}

static int l_set_threads(lua_State *L)
{
    lua_Integer n = luaL_checkinteger(L, 1);
    if (n < 0 || n > 1024) return arg_error(L, 1, "threads must be in [0, 1024], got %lld", (long long)n);
    hv_set_threads((int)n);
    return 0;
}

int luaopen_hovox(lua_State *L)
{
    lua_newtable(L);
    int module = lua_gettop(L);
    hv_lua_open_mesh(L, module);
    hv_lua_open_model(L, module);
    hv_lua_open_sources(L, module);
    hv_lua_open_output(L, module); /* before objects: they borrow the model's output methods */
    hv_lua_open_object(L, module);
    hv_lua_open_tray(L, module);
    hv_lua_open_assembly(L, module);
    lua_pushcfunction(L, l_set_threads);
    lua_setfield(L, module, "set_threads");
    lua_pushstring(L, hv_version());
    lua_setfield(L, module, "version");
    return 1;
}
