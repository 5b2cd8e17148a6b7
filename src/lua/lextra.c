/* src/lua/lextra.c - Lua methods contributed by modules outside the material core (profile
 * plots, rendering, contours, printer layers, export), registered into the `hovox` module and
 * the Model class by luaopen_hovox. Same rules as lhovox.c: check arguments, call C, raise
 * after C returns. */
#include <math.h>
#include <string.h>

#include <lauxlib.h>

#include "../core/internal.h"
#include "hovox/profile.h"
#include "lhovox.h"

const luaL_Reg *hv_lua_model_extra(void);
const luaL_Reg *hv_lua_module_extra(void);

#define check_model hv_lua_model
#define fail hv_lua_fail

static void get_vec3(lua_State *L, int idx, const char *key, double out[3])
{
    lua_getfield(L, idx, key);
    if (!lua_istable(L, -1) || lua_rawlen(L, -1) != 3)
        arg_error(L, 2, "%s must be {x, y, z}", key);
    for (int i = 0; i < 3; ++i) {
        lua_rawgeti(L, -1, i + 1);
        int ok;
        out[i] = lua_tonumberx(L, -1, &ok);
        if (!ok || !isfinite(out[i])) arg_error(L, 2, "%s[%d] must be a finite number", key, i + 1);
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
}

static const char *get_path(lua_State *L, int idx, const char *key)
{
    lua_getfield(L, idx, key);
    const char *s = NULL;
    if (!lua_isnil(L, -1)) {
        if (lua_type(L, -1) != LUA_TSTRING) arg_error(L, 2, "%s must be a file name", key);
        s = hv_lua_check_write(L, 2, lua_tostring(L, -1));
    }
    lua_pop(L, 1);
    return s; /* kept alive by the options table */
}

/* model:profile{from = {x,y,z}, to = {x,y,z}, samples = 200, csv = "p.csv", plot = "p.png",
 *               title = "...", width = 900, height = 540} -> {t = {...}, inside = {...},
 *               <material> = {...}, ...} */
static int model_profile(lua_State *L)
{
    hv_volume *vol = check_model(L, 1);
    luaL_checktype(L, 2, LUA_TTABLE);
    double from[3], to[3];
    get_vec3(L, 2, "from", from);
    get_vec3(L, 2, "to", to);
    lua_getfield(L, 2, "samples");
    lua_Integer n = luaL_optinteger(L, -1, 200);
    lua_pop(L, 1);
    if (n < 2 || n > 10000000) return arg_error(L, 2, "samples must be in [2, 10000000], got %lld", (long long)n);
    const char *csv = get_path(L, 2, "csv"), *plot = get_path(L, 2, "plot");
    lua_getfield(L, 2, "title");
    const char *title = lua_tostring(L, -1);
    lua_pop(L, 1);
    lua_getfield(L, 2, "width");
    lua_Integer w = luaL_optinteger(L, -1, 900);
    lua_pop(L, 1);
    lua_getfield(L, 2, "height");
    lua_Integer h = luaL_optinteger(L, -1, 540);
    lua_pop(L, 1);
    if (w < 200 || w > 8000 || h < 150 || h > 8000) return luaL_argerror(L, 2, "plot size out of range (200..8000 x 150..8000)");

    hv_profile *p;
    hv_status s = hv_profile_sample(vol, from, to, (int)n, &p);
    if (s != HV_OK) return fail(L, s);
    if (csv) s = hv_profile_write_csv(p, csv);
    if (s == HV_OK && plot) {
        hv_plot *pl = NULL;
        s = hv_profile_plot(p, (int)w, (int)h, &pl);
        if (s == HV_OK && title) s = hv_plot_set_title(pl, title, NULL);
        if (s == HV_OK) s = hv_plot_write_png(pl, plot);
        hv_plot_destroy(pl);
    }
    if (s != HV_OK) {
        hv_profile_destroy(p);
        return fail(L, s);
    }
    int ns = hv_profile_samples(p), m = hv_profile_materials(p);
    const hv_material_table *t = hv_profile_table(p);
    lua_createtable(L, 0, 2 + m);
    lua_createtable(L, ns, 0);
    lua_createtable(L, ns, 0);
    for (int i = 0; i < ns; ++i) {
        lua_pushnumber(L, hv_profile_t(p, i));
        lua_rawseti(L, -3, i + 1);
        lua_pushboolean(L, hv_profile_inside(p, i));
        lua_rawseti(L, -2, i + 1);
    }
    lua_setfield(L, -3, "inside");
    lua_setfield(L, -2, "t");
    for (int j = 0; j < m; ++j) {
        lua_createtable(L, ns, 0);
        for (int i = 0; i < ns; ++i) {
            lua_pushnumber(L, hv_profile_fractions(p, i)[j]);
            lua_rawseti(L, -2, i + 1);
        }
        lua_setfield(L, -2, hv_material_name(t, j));
    }
    hv_profile_destroy(p);
    return 1;
}

const luaL_Reg *hv_lua_model_extra(void)
{
    static const luaL_Reg m[] = {{"profile", model_profile}, {NULL, NULL}};
    return m;
}

const luaL_Reg *hv_lua_module_extra(void)
{
    static const luaL_Reg m[] = {{NULL, NULL}};
    return m;
}
