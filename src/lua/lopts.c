/* src/lua/lopts.c - option tables for the Lua binding: a table {key = value} read through the
 * library's option set (hovox/options.h), so Lua checks exactly what the CLI checks and names
 * the key in every refusal. Hostile tables are expected: only plain tables (no metatable) are
 * read, always raw (no metamethod runs while C reads them), and every text value is copied into
 * memory the script cannot reach or change, which stays alive until the C function returns. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <lauxlib.h>

#include "core/internal.h"
#include "lua/lhovox.h"

#define MAX_VALUES 64 /* numbers in one list value */

/* A private copy of a string, owned by the holder table at `holder`. */
const char *hv_lua_copy_string(lua_State *L, int holder, const char *s, size_t len)
{
    char *copy = lua_newuserdatauv(L, len + 1, 0);
    memcpy(copy, s, len);
    copy[len] = '\0';
    lua_rawseti(L, holder, (lua_Integer)lua_rawlen(L, holder) + 1);
    return copy;
}

int hv_lua_options(lua_State *L, int arg)
{
    if (lua_gettop(L) < arg) lua_settop(L, arg); /* absent options read as nil, not as the holder */
    return hv_lua_holder(L);
}

int hv_lua_holder(lua_State *L)
{
    lua_createtable(L, 8, 0);
    return lua_gettop(L);
}

void hv_lua_check_plain_table(lua_State *L, int arg)
{
    luaL_checktype(L, arg, LUA_TTABLE);
    if (lua_getmetatable(L, arg)) {
        lua_pop(L, 1);
        luaL_argerror(L, arg, "options must be a plain table (one with a metatable is refused)");
    }
}

/* Raise the library's last message as an argument error (options spelled as Lua keys). */
static int raise_option_error(lua_State *L, int arg)
{
    char msg[2048];
    snprintf(msg, sizeof msg, "%s", hv_last_error());
    return luaL_argerror(L, arg, msg);
}

/* Set `key` from the Lua value at the top of the stack (not popped). Returns the status. */
static hv_status set_from_lua(lua_State *L, hv_optargs *args, const char *key, const hv_option *o, int holder)
{
    int t = lua_type(L, -1);
    hv_opt_value v = {HV_VALUE_TEXT, NULL, NULL, 0, 0};
    double nums[MAX_VALUES];
    char intbuf[32];
    switch (t) {
    case LUA_TBOOLEAN:
        v.type = HV_VALUE_BOOL;
        v.boolean = lua_toboolean(L, -1);
        return hv_optargs_set(args, key, &v);
    case LUA_TNUMBER:
        if (o && (o->kind == HV_OPT_ENUM || o->kind == HV_OPT_STRING)) {
            /* adjacency = 6: enum names may be numbers; ps = 2000: a value as the CLI reads "2000" */
            snprintf(intbuf, sizeof intbuf, "%.17g", lua_tonumber(L, -1));
            /* a string option keeps its text: the copy lives in the holder, like any string's */
            v.text = o->kind == HV_OPT_STRING ? hv_lua_copy_string(L, holder, intbuf, strlen(intbuf)) : intbuf;
            return hv_optargs_set(args, key, &v);
        }
        if (o && o->kind == HV_OPT_NUMBER && o->elem == HV_ELEM_UINT64 && lua_isinteger(L, -1)) {
            /* integers keep all 64 bits through their text */
            snprintf(intbuf, sizeof intbuf, "%lld", (long long)lua_tointeger(L, -1));
            v.text = intbuf;
            return hv_optargs_set(args, key, &v);
        }
        nums[0] = lua_tonumber(L, -1);
        v.type = HV_VALUE_NUMBERS;
        v.numbers = nums;
        v.n = 1;
        return hv_optargs_set(args, key, &v);
    case LUA_TSTRING: {
        size_t len;
        const char *s = lua_tolstring(L, -1, &len);
        if (strlen(s) != len) return hv_error_option(HV_ERR_INVALID, "{%s} must not contain NUL bytes", key);
        v.text = hv_lua_copy_string(L, holder, s, len);
        return hv_optargs_set(args, key, &v);
    }
    case LUA_TTABLE: {
        if (lua_getmetatable(L, -1)) {
            lua_pop(L, 1);
            return hv_error_option(HV_ERR_INVALID, "{%s} must be a plain table (one with a metatable is refused)", key);
        }
        int tbl = lua_gettop(L);
        lua_Integer n = (lua_Integer)lua_rawlen(L, tbl);
        if (o && (o->flags & HV_OPT_PAIRS)) { /* {k = v, ...} -> "k=v" values, in key order */
            lua_pushnil(L);
            char pair[4096];
            const char *keys[MAX_VALUES];
            int nk = 0;
            while (lua_next(L, tbl)) {
                lua_pop(L, 1);
                if (lua_type(L, -1) != LUA_TSTRING || nk == MAX_VALUES) {
                    lua_pop(L, 1);
                    return hv_error_option(HV_ERR_INVALID, "{%s} must map names to strings (at most %d)", key,
                                           MAX_VALUES);
                }
                keys[nk++] = lua_tostring(L, -1); /* anchored by the table, read before anything runs */
            }
            for (int i = 1; i < nk; ++i) /* sorted: the order does not depend on hashing */
                for (int j = i; j > 0 && strcmp(keys[j - 1], keys[j]) > 0; --j) {
                    const char *x = keys[j];
                    keys[j] = keys[j - 1];
                    keys[j - 1] = x;
                }
            for (int i = 0; i < nk; ++i) {
                lua_pushstring(L, keys[i]);
                if (lua_rawget(L, tbl) != LUA_TSTRING) {
                    lua_pop(L, 1);
                    return hv_error_option(HV_ERR_INVALID, "{%s}.%s must be a string", key, keys[i]);
                }
                snprintf(pair, sizeof pair, "%s=%s", keys[i], lua_tostring(L, -1));
                lua_pop(L, 1);
                v.text = hv_lua_copy_string(L, holder, pair, strlen(pair));
                hv_status s = hv_optargs_set(args, key, &v);
                if (s != HV_OK) return s;
            }
            return HV_OK;
        }
        if (n > 0 && o && (o->flags & HV_OPT_REPEAT) && lua_rawgeti(L, tbl, 1) != LUA_TNUMBER) {
            lua_pop(L, 1); /* a list of values: each one is given in turn */
            for (lua_Integer i = 1; i <= n; ++i) {
                lua_rawgeti(L, tbl, i);
                hv_status s = set_from_lua(L, args, key, o, holder);
                lua_pop(L, 1);
                if (s != HV_OK) return s;
            }
            return HV_OK;
        } else if (n > 0 && o && (o->flags & HV_OPT_REPEAT)) {
            lua_pop(L, 1);
        }
        if (n > MAX_VALUES) return hv_error_option(HV_ERR_INVALID, "{%s} has %lld values (at most %d)", key, (long long)n, MAX_VALUES);
        for (lua_Integer i = 1; i <= n; ++i) {
            int et = lua_rawgeti(L, tbl, i);
            nums[i - 1] = lua_tonumber(L, -1);
            lua_pop(L, 1);
            if (et != LUA_TNUMBER)
                return hv_error_option(HV_ERR_INVALID, "{%s} must be a list of numbers; item %lld is a %s", key,
                                       (long long)i, lua_typename(L, et));
        }
        v.type = HV_VALUE_NUMBERS;
        v.numbers = nums;
        v.n = (int)n;
        return hv_optargs_set(args, key, &v);
    }
    default:
        return hv_error_option(HV_ERR_INVALID, "{%s} cannot be a %s", key, lua_typename(L, t));
    }
}

static int listed(const char *const *keys, const char *k)
{
    for (const char *const *q = keys; q && *q; ++q)
        if (strcmp(*q, k) == 0) return 1;
    return 0;
}

int hv_lua_read(lua_State *L, int arg, const hv_option_set *set, void *opts, const char *const *extra)
{
    int holder = hv_lua_options(L, arg);
    hv_lua_read_options(L, arg, set, opts, extra, holder);
    return holder;
}

void hv_lua_read_nested(lua_State *L, int idx, int arg, const hv_option_set *set, void *opts, const char *const *extra,
                        int holder)
{
    hv_optargs a, *args = &a;
    hv_optargs_begin(args, set, opts);
    if (lua_isnoneornil(L, idx)) {
        if (hv_optargs_finish(args) != HV_OK) raise_option_error(L, arg);
        return;
    }
    idx = lua_absindex(L, idx);
    if (lua_type(L, idx) != LUA_TTABLE) luaL_typeerror(L, arg, "table");
    if (lua_getmetatable(L, idx)) luaL_argerror(L, arg, "options must be a plain table (one with a metatable is refused)");
    /* unknown keys first, so a misspelt option never falls back to its default */
    lua_pushnil(L);
    while (lua_next(L, idx)) {
        lua_pop(L, 1);
        if (lua_type(L, -1) != LUA_TSTRING) {
            hv_lua_arg_error(L, arg, "options are named (key = value), got a %s key", luaL_typename(L, -1));
            return;
        }
        if (hv_option_known(set, extra, lua_tostring(L, -1)) == HV_OK) continue;
        hv_lua_arg_error(L, arg, "%s", hv_last_error());
        return;
    }
    /* then the values, in the set's order (deterministic messages) */
    for (int i = 0; i < set->count; ++i) {
        const hv_option *o = &set->options[i];
        if (listed(extra, o->key)) continue; /* the binding reads it itself (a function, an object) */
        lua_pushstring(L, o->key);
        if (lua_rawget(L, idx) != LUA_TNIL && set_from_lua(L, args, o->key, o, holder) != HV_OK) {
            lua_pop(L, 1);
            raise_option_error(L, arg);
            return;
        }
        lua_pop(L, 1);
    }
    for (int i = 0; i < set->alias_count; ++i) {
        lua_pushstring(L, set->aliases[i].name);
        if (lua_rawget(L, idx) != LUA_TNIL && set_from_lua(L, args, set->aliases[i].name, NULL, holder) != HV_OK) {
            lua_pop(L, 1);
            raise_option_error(L, arg);
            return;
        }
        lua_pop(L, 1);
    }
    if (hv_optargs_finish(args) != HV_OK) raise_option_error(L, arg);
}

void hv_lua_read_options(lua_State *L, int arg, const hv_option_set *set, void *opts, const char *const *extra,
                         int holder)
{
    hv_lua_read_nested(L, arg, arg, set, opts, extra, holder);
}

int hv_lua_field(lua_State *L, int arg, const char *key)
{
    arg = lua_absindex(L, arg);
    if (lua_type(L, arg) != LUA_TTABLE) {
        lua_pushnil(L);
        return LUA_TNIL;
    }
    lua_pushstring(L, key);
    return lua_rawget(L, arg);
}

const char *hv_lua_string_in(lua_State *L, int tbl, int arg, const char *where, const char *key, int holder)
{
    int t = hv_lua_field(L, tbl, key);
    const char *copy = NULL;
    if (t == LUA_TSTRING) {
        size_t len;
        const char *s = lua_tolstring(L, -1, &len);
        if (strlen(s) != len) hv_lua_arg_error(L, arg, "%s%s must not contain NUL bytes", where, key);
        copy = hv_lua_copy_string(L, holder, s, len);
    } else if (t != LUA_TNIL) {
        hv_lua_arg_error(L, arg, "%s%s must be a string, got %s", where, key, lua_typename(L, t));
    }
    lua_pop(L, 1);
    return copy;
}

const char *hv_lua_string_field(lua_State *L, int arg, const char *key, int holder)
{
    return hv_lua_string_in(L, arg, arg, "", key, holder);
}

const char *hv_lua_out_path(lua_State *L, int arg, const char *key, int holder, const char *what)
{
    const char *path = hv_lua_string_field(L, arg, key, holder);
    if (!path && what) hv_lua_arg_error(L, arg, "%s is required (%s)", key, what);
    return path ? hv_lua_check_write(L, arg, key, path) : NULL;
}

void hv_lua_check_paths(lua_State *L, int arg, const hv_option_set *set, const void *opts)
{
    for (int i = 0; i < set->count; ++i) {
        const hv_option *o = &set->options[i];
        if (o->kind != HV_OPT_STRING || !(o->flags & HV_OPT_OUT_PATH)) continue;
        const char *path = *(const char *const *)((const char *)opts + o->offset);
        if (path) hv_lua_check_write(L, arg, o->key, path);
    }
}
