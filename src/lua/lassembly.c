/* src/lua/lassembly.c - Lua: assemblies (hovox/mesh.h bodies, hovox/voxelize.h regions):
 * hovox.join_meshes (meshes joined into one multi-body mesh, a body per part) and
 * model:regions() (the regions a model voxelized from an assembly records). */
#include <stdio.h>
#include <string.h>

#include <lauxlib.h>

#include "core/internal.h"
#include "hovox/voxelize.h"
#include "lhovox.h"

#define MAX_PARTS 100000

/* hovox.join_meshes{ {mesh = m, name = "core", material = "Agilus"}, ... } -> mesh with one body
 * per part, in order (hv_mesh_join); name and material may be left out. */
static int l_join_meshes(lua_State *L)
{
    hv_lua_check_plain_table(L, 1);
    lua_settop(L, 1);
    int holder = hv_lua_holder(L);
    lua_Integer n = (lua_Integer)lua_rawlen(L, 1);
    if (n < 1) return luaL_argerror(L, 1, "give at least one part {mesh = ..., name = ..., material = ...}");
    if (n > MAX_PARTS) return arg_error(L, 1, "%lld parts (at most %d)", (long long)n, MAX_PARTS);
    hv_mesh_part *parts = lua_newuserdatauv(L, (size_t)n * sizeof *parts, 0); /* freed by the collector */
    int base = lua_gettop(L);
    if (!lua_checkstack(L, (int)n + 8)) return luaL_error(L, "too many parts");
    for (lua_Integer i = 1; i <= n; ++i) {
        if (lua_rawgeti(L, 1, i) != LUA_TTABLE || lua_getmetatable(L, -1))
            return arg_error(L, 1, "part %lld must be a plain table {mesh = ..., name = ..., material = ...}", (long long)i);
        int e = lua_gettop(L);
        lua_pushnil(L);
        while (lua_next(L, e)) {
            const char *k = lua_type(L, -2) == LUA_TSTRING ? lua_tostring(L, -2) : NULL;
            if (!k || (strcmp(k, "mesh") && strcmp(k, "name") && strcmp(k, "material")))
                return arg_error(L, 1, "part %lld: unknown key '%s' (keys: mesh, name, material)", (long long)i,
                                 k ? k : luaL_typename(L, -2));
            lua_pop(L, 1);
        }
        hv_lua_field(L, e, "mesh");
        l_mesh *u = luaL_testudata(L, -1, MT_MESH);
        if (!u) return arg_error(L, 1, "part %lld: mesh must be a hovox mesh", (long long)i);
        char where[48];
        snprintf(where, sizeof where, "part %lld: ", (long long)i);
        parts[i - 1].name = hv_lua_string_in(L, e, 1, where, "name", holder);
        parts[i - 1].material = hv_lua_string_in(L, e, 1, where, "material", holder);
        lua_replace(L, e); /* the mesh stays anchored in the part's slot */
    }
    /* the meshes now: nothing runs between here and the join (reading may have run a finalizer) */
    for (lua_Integer i = 1; i <= n; ++i) {
        l_mesh *u = lua_touserdata(L, base + (int)i);
        if (!u->p) return arg_error(L, 1, "part %lld: mesh was freed", (long long)i);
        parts[i - 1].mesh = u->p;
    }
    hv_mesh *out;
    hv_status s = hv_mesh_join(parts, (size_t)n, &out);
    if (s != HV_OK) return fail(L, s);
    hv_lua_push_mesh(L, out);
    return 1;
}

/* Builds the regions table (under lua_pcall: a failed allocation comes back to model_regions,
 * which frees the regions first). */
static int push_regions(lua_State *L)
{
    const hv_regions *rg = lua_touserdata(L, 1);
    size_t n = hv_regions_count(rg);
    lua_createtable(L, (int)n, 0);
    for (size_t i = 0; i < n; ++i) {
        const hv_region_info *g = hv_regions_at(rg, i);
        lua_createtable(L, 0, 9);
        lua_pushstring(L, g->name);
        lua_setfield(L, -2, "name");
        lua_pushstring(L, g->grid);
        lua_setfield(L, -2, "grid");
        if (g->material) {
            lua_pushstring(L, g->material);
            lua_setfield(L, -2, "material");
        }
        if (g->has_color) {
            double c[4] = {g->rgba[0], g->rgba[1], g->rgba[2], g->rgba[3]};
            hv_lua_push_vec(L, c, 4);
            lua_setfield(L, -2, "color");
        }
        lua_pushstring(L, hv_fill_mode_name(g->fill));
        lua_setfield(L, -2, "fill");
        lua_pushinteger(L, (lua_Integer)g->voxels);
        lua_setfield(L, -2, "voxels");
        lua_pushinteger(L, (lua_Integer)g->lost);
        lua_setfield(L, -2, "lost");
        lua_createtable(L, 0, (int)g->nlost_to);
        for (size_t k = 0; k < g->nlost_to; ++k) {
            lua_pushinteger(L, (lua_Integer)g->lost_to[k].voxels);
            lua_setfield(L, -2, hv_regions_at(rg, g->lost_to[k].region)->name);
        }
        lua_setfield(L, -2, "lost_to");
        lua_rawseti(L, -2, (lua_Integer)i + 1);
    }
    return 1;
}

/* model:regions() -> { {name, grid, material, color, fill, voxels, lost, lost_to = {NAME = voxels}},
 * ... } in body order; {} for a model not voxelized from an assembly. */
static int model_regions(lua_State *L)
{
    hv_volume *v = hv_lua_model(L, 1);
    hv_regions *rg = NULL;
    hv_status s = hv_voxelize_regions_read(v, &rg);
    if (s == HV_ERR_NOT_FOUND) {
        lua_newtable(L);
        return 1;
    }
    if (s != HV_OK) return fail(L, s);
    lua_pushcfunction(L, push_regions);
    lua_pushlightuserdata(L, rg);
    int rc = lua_pcall(L, 1, 1, 0);
    hv_regions_destroy(rg);
    if (rc != LUA_OK) return lua_error(L);
    return 1;
}

void hv_lua_open_assembly(lua_State *L, int module)
{
    static const luaL_Reg model_methods[] = {{"regions", model_regions}, {NULL, NULL}};
    hv_lua_add_methods(L, MT_MODEL, model_methods);
    static const luaL_Reg fns[] = {{"join_meshes", l_join_meshes}, {NULL, NULL}};
    lua_pushvalue(L, module);
    hv_lua_set_funcs(L, fns);
    lua_pop(L, 1);
}
