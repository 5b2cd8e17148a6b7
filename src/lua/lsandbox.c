/* src/lua/lsandbox.c - the sandbox of `hovox run --sandbox` (README "Sandbox"): scripts from
 * others write only below the output directory (every path checked when it is used, on the
 * string the call received, symbolic links followed as the writer would), cannot run programs,
 * load C code or bytecode, or reach the debug library. Time and memory limits are set by the
 * runner (src/cli/cmd_run.c). */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <lauxlib.h>

#include "core/internal.h"
#include "lhovox.h"

#define REG_ROOT "hovox.write_root"

void hv_lua_set_write_root(lua_State *L, const char *dir)
{
    if (dir) {
        char real[PATH_MAX];
        lua_pushstring(L, realpath(dir, real) ? real : dir);
    } else {
        lua_pushnil(L);
    }
    lua_setfield(L, LUA_REGISTRYINDEX, REG_ROOT);
}

/* 1 when writing `path` is allowed under the write root (hv_path_below), or there is none. */
static int write_allowed(lua_State *L, const char *path)
{
    lua_getfield(L, LUA_REGISTRYINDEX, REG_ROOT);
    const char *root = lua_tostring(L, -1);
    int ok = !root || hv_path_below(root, path); /* root is anchored in the registry */
    lua_pop(L, 1);
    return ok;
}

const char *hv_lua_check_write(lua_State *L, int arg, const char *field, const char *path)
{
    /* a call of a script is one command: what earlier calls read may be written now (a model
     * loaded, changed and saved in place), what this call reads may not */
    hv_inputs_reset();
    if (!write_allowed(L, path))
        arg_error(L, arg, "%s%ssandbox: writing '%s' outside the output directory is not allowed", field ? field : "",
                  field ? ": " : "", path);
    return path;
}

static int sb_io_open(lua_State *L)
{
    const char *path = luaL_checkstring(L, 1), *mode = luaL_optstring(L, 2, "r");
    if (strpbrk(mode, "wa+")) hv_lua_check_write(L, 1, NULL, path);
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

static int sb_io_output(lua_State *L)
{
    if (lua_type(L, 1) == LUA_TSTRING) hv_lua_check_write(L, 1, NULL, lua_tostring(L, 1));
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

static int sb_os_path(lua_State *L)
{
    int n = (int)lua_tointeger(L, lua_upvalueindex(2));
    for (int i = 1; i <= n; ++i) hv_lua_check_write(L, i, NULL, luaL_checkstring(L, i));
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

static int sb_denied(lua_State *L)
{
    return luaL_error(L, "sandbox: %s is not available", lua_tostring(L, lua_upvalueindex(1)));
}

static void deny(lua_State *L, const char *lib, const char *name)
{
    if (lua_getglobal(L, lib) != LUA_TTABLE) {
        lua_pop(L, 1);
        return;
    }
    lua_pushfstring(L, "%s.%s", lib, name);
    lua_pushcclosure(L, sb_denied, 1);
    lua_setfield(L, -2, name);
    lua_pop(L, 1);
}

static void wrap(lua_State *L, const char *lib, const char *name, lua_CFunction fn, int nargs_checked)
{
    if (lua_getglobal(L, lib) != LUA_TTABLE) {
        lua_pop(L, 1);
        return;
    }
    lua_getfield(L, -1, name);
    if (nargs_checked >= 0) {
        lua_pushinteger(L, nargs_checked);
        lua_pushcclosure(L, fn, 2);
    } else {
        lua_pushcclosure(L, fn, 1);
    }
    lua_setfield(L, -2, name);
    lua_pop(L, 1);
}

/* load/loadfile with the mode forced to text: Lua does not verify precompiled chunks, so
 * crafted bytecode is a way out of any sandbox. Upvalue 1: the original; `mode_arg` is the
 * position of the mode argument (3 for load, 2 for loadfile). */
static int sb_text_only(lua_State *L)
{
    int mode_arg = (int)lua_tointeger(L, lua_upvalueindex(2));
    int n = lua_gettop(L) < mode_arg + 1 ? mode_arg + 1 : lua_gettop(L);
    lua_settop(L, n);
    lua_pushstring(L, "t");
    lua_replace(L, mode_arg);
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, n, LUA_MULTRET);
    return lua_gettop(L);
}

/* dofile(name) as loadfile(name, "t") then call */
static int sb_dofile(lua_State *L)
{
    const char *name = luaL_optstring(L, 1, NULL);
    lua_settop(L, 1);
    if (luaL_loadfilex(L, name, "t") != LUA_OK) return lua_error(L);
    lua_call(L, 0, LUA_MULTRET);
    return lua_gettop(L) - 1;
}

void hv_lua_sandbox(lua_State *L)
{
    /* debug reaches every upvalue (the real io.open inside its wrapper) and every local */
    lua_pushnil(L);
    lua_setglobal(L, "debug");
    if (lua_getglobal(L, "package") == LUA_TTABLE && lua_getfield(L, -1, "loaded") == LUA_TTABLE) {
        lua_pushnil(L);
        lua_setfield(L, -2, "debug");
    }
    lua_settop(L, 0);
    static const char *const loaders[] = {"load", "loadfile"};
    for (int i = 0; i < 2; ++i) {
        lua_getglobal(L, loaders[i]);
        lua_pushinteger(L, i == 0 ? 3 : 2);
        lua_pushcclosure(L, sb_text_only, 2);
        lua_setglobal(L, loaders[i]);
    }
    lua_pushcfunction(L, sb_dofile);
    lua_setglobal(L, "dofile");
    deny(L, "os", "execute");
    deny(L, "os", "tmpname");
    deny(L, "io", "popen");
    deny(L, "io", "tmpfile");
    deny(L, "package", "loadlib");
    wrap(L, "io", "open", sb_io_open, -1);
    wrap(L, "io", "output", sb_io_output, -1);
    wrap(L, "os", "remove", sb_os_path, 1);
    wrap(L, "os", "rename", sb_os_path, 2);
    /* require finds preloaded modules only: no C modules, and no Lua files either (the file
     * searcher accepts precompiled chunks) */
    if (lua_getglobal(L, "package") == LUA_TTABLE) {
        lua_pushstring(L, "");
        lua_setfield(L, -2, "cpath");
        lua_pushstring(L, "");
        lua_setfield(L, -2, "path");
        lua_getfield(L, -1, "searchers");
        if (lua_istable(L, -1))
            for (int k = 4; k >= 2; --k) {
                lua_pushnil(L);
                lua_rawseti(L, -2, k);
            }
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
}

