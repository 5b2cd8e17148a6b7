/* tests/fuzz/fuzz_lua_options.c - fuzz target: Lua option tables built from the bytes (known and
 * unknown keys; booleans, numbers, strings, lists, nested tables, tables with metatables) read
 * through every library option set by the binding's reader, under lua_pcall: each must be
 * taken or refused with a Lua error, never crash or leak. */
#include <stdint.h>
#include <string.h>

#include <lauxlib.h>
#include <lualib.h>

#include "hovox/export.h"
#include "hovox/generate.h"
#include "hovox/layers.h"
#include "hovox/material.h"
#include "hovox/profile.h"
#include "hovox/render.h"
#include "hovox/slice.h"
#include "hovox/voxelize.h"
#include "lua/lhovox.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef struct cursor {
    const uint8_t *p;
    size_t n;
} cursor;

static int next(cursor *c) { return c->n ? (--c->n, *c->p++) : -1; }

static const hv_option_set *pick_set(int k)
{
    switch (k % 9) {
    case 0: return hv_render_option_set();
    case 1: return hv_layers_option_set();
    case 2: return hv_voxelize_option_set();
    case 3: return hv_export_option_set();
    case 4: return hv_profile_option_set();
    case 5: return hv_contours_option_set();
    case 6: return hv_ags_option_set();
    case 7: return hv_facet_select_option_set();
    default: return hv_shape_option_set(k % hv_shape_count());
    }
}

static void push_value(lua_State *L, cursor *c, int depth)
{
    int t = next(c);
    char s[64];
    switch (t < 0 ? 0 : t % 8) {
    case 0: lua_pushboolean(L, t & 8); break;
    case 1: lua_pushinteger(L, (lua_Integer)(int8_t)next(c) * 1000 + next(c)); break;
    case 2: {
        double d = 0;
        for (int i = 0; i < 8; ++i) ((uint8_t *)&d)[i] = (uint8_t)next(c);
        lua_pushnumber(L, d);
        break;
    }
    case 3: {
        int len = next(c) % 24, i = 0;
        for (; i < len; ++i) {
            int ch = next(c);
            s[i] = (char)(ch < 0 ? 'x' : ch);
        }
        lua_pushlstring(L, s, (size_t)i);
        break;
    }
    case 4: /* a list of numbers */
    case 5: {
        int len = next(c) % 9;
        lua_createtable(L, len, 0);
        for (int i = 1; i <= len; ++i) {
            if (depth < 3 && t % 8 == 5) push_value(L, c, depth + 1);
            else lua_pushnumber(L, (double)(int8_t)next(c) / 4.0);
            lua_rawseti(L, -2, i);
        }
        break;
    }
    case 6: /* a table with a metatable */
        lua_newtable(L);
        lua_newtable(L);
        lua_setmetatable(L, -2);
        break;
    default: lua_pushstring(L, t & 8 ? "halftone" : "#ff0000"); break;
    }
}

static int read_all(lua_State *L)
{
    const hv_option_set *set = lua_touserdata(L, 1);
    union {
        hv_render_options r;
        hv_layers_options l;
        hv_voxelize_options v;
        hv_export_options e;
        hv_profile_options p;
        hv_contours_options c;
        hv_ags_options a;
        hv_facet_select f;
        hv_shape_params s;
    } opts;
    static const char *const extra[] = {"path", "mesh", NULL};
    int holder = hv_lua_holder(L);
    hv_lua_read_options(L, 2, set, &opts, extra, holder);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    cursor c = {data, size};
    lua_State *L = luaL_newstate();
    if (!L) return 0;
    const hv_option_set *set = pick_set(next(&c) & 0xff);
    lua_pushcfunction(L, read_all);
    lua_pushlightuserdata(L, (void *)set);
    lua_newtable(L);
    for (int k = 0; k < 12 && c.n; ++k) {
        int which = next(&c);
        if (which < 0) break;
        if (which % 5 == 0) lua_pushfstring(L, "key%d", which); /* an unknown key */
        else lua_pushstring(L, set->options[which % set->count].key);
        push_value(L, &c, 0);
        lua_rawset(L, -3);
    }
    (void)lua_pcall(L, 2, 0, 0);
    lua_close(L);
    return 0;
}
