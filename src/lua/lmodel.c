/* src/lua/lmodel.c - Lua: the Model class (a volume with its grids, metadata and material
 * table): hovox.voxelize (the options of `hovox voxelize`, hv_voxelize_option_set), hovox.load,
 * saving, inspection and probing. Outputs are in loutput.c, features made from a model in
 * lsource.c. */
#include <stdlib.h>
#include <math.h>
#include <string.h>

#include <lauxlib.h>

#include "core/internal.h"
#include "hovox/model.h"
#include "hovox/colour.h"
#include "hovox/voxelize.h"
#include "lhovox.h"

int hv_lua_model_free(lua_State *L);

void hv_lua_push_model(lua_State *L, hv_volume *v)
{
    l_model *u = hv_lua_new_ud(L, sizeof *u, MT_MODEL);
    u->p = v;
}

hv_volume *hv_lua_model(lua_State *L, int arg) { return CHECK(L, arg, l_model, MT_MODEL)->p; }

/* hovox.voxelize(mesh, {<the options of `hovox voxelize`: dims = N | {X, Y, Z}, voxel_size = L |
 *   {X, Y, Z}, adjacency = 6 | 26, fill, max_memory>, like = model}) -> model */
static int l_voxelize(lua_State *L)
{
    static const char *const extra[] = {"like", NULL};
    hv_mesh *mesh = hv_lua_mesh(L, 1);
    hv_voxelize_options o;
    hv_lua_read(L, 2, hv_voxelize_option_set(), &o, extra);
    hv_transform lattice;
    if (hv_lua_field(L, 2, "like") != LUA_TNIL) {
        lattice = hv_volume_get_transform(((l_model *)hv_lua_option_object(L, 2, "like", MT_MODEL, "hovox model"))->p);
        o.lattice = &lattice;
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
    hv_volume *v;
    mesh = hv_lua_mesh(L, 1); /* again: reading the options may have run a finalizer */
    o.progress = hv_lua_progress(L);
    hv_status s = hv_voxelize(mesh, &o, &v);
    if (s != HV_OK) return fail(L, s);
    hv_lua_push_model(L, v);
    return 1;
}

/* hovox.load(path, {icc = FILE, intent = NAME, resins = "C,M,Y,K,W,CLEAR"}) -> Model: a 3MF
 * package's colour without a composite through that colour map (hv_model_load_colour) */
static int l_load(lua_State *L)
{
    const char *path = luaL_checkstring(L, 1);
    hv_colour_options co;
    hv_lua_read(L, 2, hv_colour_option_set(), &co, NULL);
    path = luaL_checkstring(L, 1); /* again: reading the options may have run a finalizer */
    hv_volume *v;
    hv_status s = hv_model_load_colour(path, &co, &v);
    if (s != HV_OK && hv_model_file_is_mesh(path)) hv_error_suffix(s, "; hovox.load_mesh reads it");
    if (s != HV_OK) return fail(L, s);
    hv_lua_push_model(L, v);
    return 1;
}

static int model_save(lua_State *L)
{
    hv_volume *vol = hv_lua_model(L, 1); /* kept alive while this runs (hv_lua_release) */
    const char *path = hv_lua_check_write(L, 2, NULL, luaL_checkstring(L, 2));
    hv_status s = hv_volume_save(vol, path);
    return s != HV_OK ? fail(L, s) : 0;
}

static int model_grids(lua_State *L)
{
    const hv_volume *vol = hv_lua_model(L, 1);
    int n = hv_volume_grid_count(vol);
    lua_createtable(L, n, 0);
    for (int g = 0; g < n; ++g) {
        lua_createtable(L, 0, 2);
        lua_pushstring(L, hv_volume_grid_name(vol, g));
        lua_setfield(L, -2, "name");
        lua_pushstring(L, hv_grid_type_name(hv_volume_grid_type(vol, g)));
        lua_setfield(L, -2, "type");
        lua_rawseti(L, -2, g + 1);
    }
    return 1;
}

static int model_voxels(lua_State *L)
{
    const hv_volume *vol = hv_lua_model(L, 1);
    const char *grid = luaL_optstring(L, 2, NULL);
    if (!grid) {
        lua_pushinteger(L, (lua_Integer)hv_volume_active_count(vol));
        return 1;
    }
    int g = hv_volume_grid_find(vol, grid);
    if (g < 0 || hv_volume_grid_type(vol, g) != HV_GRID_BOOL)
        return arg_error(L, 2, "no bool grid '%s'", grid);
    lua_pushinteger(L, (lua_Integer)hv_volume_mask_count(vol, g));
    return 1;
}

/* model:add_grid(name, function(x, y, z) return value end[, mask = "occupancy"]) -> voxels: float
 * grid `name` holding the function's value at the centre of every voxel of bool grid `mask` (world
 * coordinates, mm), e.g. a stress field to export. The function runs for every voxel first; the
 * grid is added at the end (hv_volume_grid_set), so an error leaves the model as it was. */
static int model_add_grid(lua_State *L)
{
    const char *name = luaL_checkstring(L, 2);
    luaL_checktype(L, 3, LUA_TFUNCTION);
    const char *mask = luaL_optstring(L, 4, "occupancy");
    double *xyz;
    size_t n;
    hv_status s = hv_volume_centres(hv_lua_model(L, 1), mask, &xyz, &n);
    if (s != HV_OK) return fail(L, s);
    /* buffers the garbage collector owns: an error in the function leaks nothing */
    double *p = n ? lua_newuserdatauv(L, n * 3 * sizeof *p, 0) : NULL;
    float *v = n ? lua_newuserdatauv(L, n * sizeof *v, 0) : NULL;
    if (n) memcpy(p, xyz, n * 3 * sizeof *p);
    free(xyz);
    for (size_t i = 0; i < n; ++i) {
        lua_pushvalue(L, 3);
        for (int a = 0; a < 3; ++a) lua_pushnumber(L, p[3 * i + (size_t)a]);
        lua_call(L, 3, 1);
        int ok;
        lua_Number x = lua_tonumberx(L, -1, &ok);
        if (!ok)
            return luaL_error(L, "add_grid: the function returned %s at (%f, %f, %f), not a number",
                              luaL_typename(L, -1), p[3 * i], p[3 * i + 1], p[3 * i + 2]);
        v[i] = (float)x;
        lua_pop(L, 1);
    }
    s = hv_volume_grid_set(hv_lua_model(L, 1), name, mask, v, n); /* again: the function may have freed it */
    if (s != HV_OK) return fail(L, s);
    lua_pushinteger(L, (lua_Integer)n);
    return 1;
}

static int model_transform(lua_State *L)
{
    const hv_volume *vol = hv_lua_model(L, 1);
    hv_transform xf = hv_volume_get_transform(vol);
    lua_createtable(L, 0, 2);
    hv_lua_push_vec(L, xf.voxel, 3);
    lua_setfield(L, -2, "voxel");
    hv_lua_push_vec(L, xf.origin, 3);
    lua_setfield(L, -2, "origin");
    int32_t lo[3], hi[3];
    if (hv_volume_index_bbox(vol, lo, hi)) {
        double a[3] = {lo[0], lo[1], lo[2]}, b[3] = {hi[0], hi[1], hi[2]};
        hv_lua_push_vec(L, a, 3);
        lua_setfield(L, -2, "index_min");
        hv_lua_push_vec(L, b, 3);
        lua_setfield(L, -2, "index_max");
    }
    return 1;
}

static int model_meta(lua_State *L)
{
    const hv_volume *vol = hv_lua_model(L, 1);
    const char *key = luaL_checkstring(L, 2);
    double d;
    const char *s = hv_volume_meta_string(vol, key);
    if (s) lua_pushstring(L, s);
    else if (hv_volume_meta_number(vol, key, &d)) lua_pushnumber(L, d);
    else lua_pushnil(L);
    return 1;
}

/* The model's material table (loaded from its metadata once). */
static hv_material_table *model_mats(lua_State *L, l_model *u)
{
    if (!u->mats) {
        hv_status s = hv_material_table_load(u->p, &u->mats);
        if (s != HV_OK) fail(L, s);
    }
    return u->mats;
}

static int model_probe(lua_State *L)
{
    l_model *u = CHECK(L, 1, l_model, MT_MODEL);
    double p[3];
    if (hv_lua_numbers(L, 2, 2, "point", p, 3) != 3) return luaL_argerror(L, 2, "point must be {x, y, z}");
    u = CHECK(L, 1, l_model, MT_MODEL); /* again, after the conversions */
    hv_volume *vol = u->p;
    const hv_material_table *t = model_mats(L, u);
    int m = hv_material_count(t), grids[HV_MAX_MATERIALS], inside;
    for (int j = 0; j < m; ++j) grids[j] = hv_material_grid(vol, t, j);
    double f[HV_MAX_MATERIALS];
    hv_accessor acc;
    hv_accessor_init(&acc, vol);
    hv_model_probe(&acc, t, grids, p, &inside, f);
    lua_pushboolean(L, inside);
    lua_createtable(L, m, m);
    for (int j = 0; j < m; ++j) {
        lua_pushnumber(L, f[j]);
        lua_pushvalue(L, -1);
        lua_rawseti(L, -3, j + 1);
        lua_setfield(L, -2, hv_material_name(t, j));
    }
    return 2;
}

/* hovox.colour(colour, {icc = FILE, intent = NAME, resins = "C,M,Y,K,W,CLEAR"}) -> {<resin> =
 * fraction, ... (six), de2000 = dE}: what `hovox colour` prints for one colour */
static int l_colour(lua_State *L)
{
    const char *text = luaL_checkstring(L, 1);
    float f[4];
    if (hv_color_parse(text, f) != HV_OK) return arg_error(L, 1, "%s", hv_last_error());
    hv_colour_options co;
    hv_lua_read(L, 2, hv_colour_option_set(), &co, NULL);
    hv_colour_map *map = NULL;
    hv_status s = hv_colour_map_create(&co, &map);
    if (s != HV_OK) return fail(L, s);
    uint8_t rgba[4];
    for (int k = 0; k < 4; ++k) rgba[k] = (uint8_t)lrintf(f[k] * 255.0f);
    float fr[HV_COLOUR_SLOTS];
    double want[3], got[3];
    hv_colour_map_fractions(map, rgba, fr);
    hv_colour_map_lab_of_srgb(map, rgba, want);
    hv_colour_map_lab_of_fractions(map, fr, got);
    lua_createtable(L, 0, HV_COLOUR_SLOTS + 1);
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
        lua_pushnumber(L, fr[k]);
        lua_setfield(L, -2, hv_colour_map_resin(map, k));
    }
    lua_pushnumber(L, hv_colour_delta_e2000(want, got));
    hv_colour_map_destroy(map); /* after the names were copied into the table */
    lua_setfield(L, -2, "de2000");
    return 1;
}

static void destroy_volume(void *p) { hv_volume_destroy(p); }
static void destroy_mats(void *p) { hv_material_table_destroy(p); }

/* model:paint(mesh, {colour_depth = MM (default 1), core = RESIN | COLOUR, icc = FILE, intent =
 * NAME, resins = "C,M,Y,K,W,CLEAR"}) -> the model: painted in the mesh's colours, as `hovox
 * voxelize --colour-depth` (hv_colour_mesh_paint: the body rule of mesh:layers, colour asked for);
 * the mesh is the one it was voxelized from */
static int model_paint(lua_State *L)
{
    static const char *const extra[] = {"colour_depth", "core", NULL};
    hv_lua_mesh(L, 2);
    hv_colour_options co;
    int holder = hv_lua_read(L, 3, hv_colour_option_set(), &co, extra);
    double depth = 1.0;
    if (hv_lua_field(L, 3, "colour_depth") != LUA_TNIL) {
        if (lua_type(L, -1) != LUA_TNUMBER) return arg_error(L, 3, "colour_depth must be a number (mm)");
        depth = lua_tonumber(L, -1);
    }
    lua_pop(L, 1);
    if (!(depth > 0 && depth <= 1e6)) return arg_error(L, 3, "colour_depth must be in (0, 1e6] mm, got %g", depth);
    const char *core = hv_lua_string_field(L, 3, "core", holder);
    l_model *u = CHECK(L, 1, l_model, MT_MODEL); /* again: reading the options may have run a finalizer */
    hv_mesh *mesh = hv_lua_mesh(L, 2);
    hv_colour_map *map = NULL;
    hv_status s = hv_colour_map_create(&co, &map);
    hv_colour_body_rule rule = {1, NULL, NULL};
    if (s == HV_OK) s = hv_colour_mesh_paint(u->p, mesh, map, depth, core, &rule);
    hv_colour_map_destroy(map);
    if (s != HV_OK) return fail(L, s);
    hv_material_table *t = u->mats; /* the table changed */
    u->mats = NULL;
    hv_lua_release(L, destroy_mats, t);
    lua_settop(L, 1);
    return 1;
}

int hv_lua_model_free(lua_State *L)
{
    l_model *u = luaL_checkudata(L, 1, MT_MODEL);
    hv_volume *v = u->p;
    hv_material_table *t = u->mats;
    u->p = NULL;
    u->mats = NULL;
    hv_lua_release(L, destroy_volume, v);
    hv_lua_release(L, destroy_mats, t);
    return 0;
}

static int model_tostring(lua_State *L)
{
    l_model *u = luaL_checkudata(L, 1, MT_MODEL);
    if (!u->p) lua_pushliteral(L, "hovox.Model (freed)");
    else lua_pushfstring(L, "hovox.Model (%d grids, %I active voxels)", hv_volume_grid_count(u->p),
                         (lua_Integer)hv_volume_active_count(u->p));
    return 1;
}

/* ---- Materials ---------------------------------------------------------------------------- */

void hv_lua_open_model(lua_State *L, int module)
{
    static const luaL_Reg methods[] = {{"save", model_save},     {"grids", model_grids}, {"voxels", model_voxels},
                                       {"transform", model_transform}, {"meta", model_meta},   {"probe", model_probe},
                                       {"add_grid", model_add_grid}, {"paint", model_paint},
                                       {"free", hv_lua_model_free}, {NULL, NULL}};
    static const luaL_Reg fns[] = {{"voxelize", l_voxelize}, {"load", l_load}, {"colour", l_colour}, {NULL, NULL}};
    hv_lua_new_class(L, MT_MODEL, methods, hv_lua_model_free, model_tostring);
    lua_pushvalue(L, module);
    hv_lua_set_funcs(L, fns);
    lua_pop(L, 1);
}
