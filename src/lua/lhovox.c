/* src/lua/lhovox.c - the `hovox` Lua 5.4 module: meshes, models (volumes), material tables,
 * reference features, grading sources and heterogeneous objects as userdata with methods and
 * __gc. Every binding checks its arguments first (luaL_check*, "bad argument #2 to 'add_ags'
 * (d_grad must be >= 0, got -1)"), then calls C, and raises only after C has returned: no
 * longjmp ever crosses library (or C++) frames. Lua functions given as f are tabulated once,
 * called under lua_pcall. */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <lauxlib.h>
#include <lualib.h>

#include "core/internal.h"
#include "hovox/generate.h"
#include "hovox/material.h"
#include "hovox/voxelize.h"
#include "lhovox.h"

#define MT_MESH "hovox.Mesh"
#define MT_MODEL "hovox.Model"
#define MT_MATS "hovox.Materials"
#define MT_FEATURE "hovox.Feature"
#define MT_SOURCE "hovox.Source"
#define MT_OBJECT "hovox.Object"
#define REG_ROOT "hovox.write_root"

typedef struct { hv_mesh *p; } l_mesh;
typedef struct { hv_volume *p; hv_material_table *mats; } l_model;
typedef struct { hv_material_table *p; } l_mats;
typedef struct { hv_frf *p; } l_feature;
typedef struct { hv_ags *p; } l_source;
typedef struct { hv_object *p; } l_object;

/* ---- helpers ------------------------------------------------------------------------------- */

int hv_lua_arg_error(lua_State *L, int arg, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return luaL_argerror(L, arg, msg);
}

void hv_lua_check_options(lua_State *L, int idx, int arg, const char *const *keys)
{
    luaL_checktype(L, idx, LUA_TTABLE);
    idx = lua_absindex(L, idx);
    lua_pushnil(L);
    while (lua_next(L, idx)) {
        lua_pop(L, 1);
        if (lua_type(L, -1) != LUA_TSTRING) {
            hv_lua_arg_error(L, arg, "options are named (key = value), got a %s key", luaL_typename(L, -1));
            return;
        }
        const char *k = lua_tostring(L, -1);
        int ok = 0;
        for (const char *const *q = keys; *q && !ok; ++q) ok = strcmp(k, *q) == 0;
        if (ok) continue;
        char list[400];
        size_t n = 0;
        list[0] = '\0';
        for (const char *const *q = keys; *q && n + strlen(*q) + 3 < sizeof list; ++q)
            n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", q == keys ? "" : ", ", *q);
        hv_lua_arg_error(L, arg, "unknown option '%s' (options: %s)", k, list);
        return;
    }
}

/* Raise the library's message for a failed call (after the call has returned). */
static int fail(lua_State *L, hv_status s)
{
    const char *m = hv_last_error();
    return luaL_error(L, "%s", *m ? m : hv_status_name(s));
}

static void *new_ud(lua_State *L, size_t size, const char *mt)
{
    void *p = lua_newuserdatauv(L, size, 1);
    memset(p, 0, size);
    luaL_setmetatable(L, mt);
    return p;
}

static void *check_live(lua_State *L, int arg, const char *mt)
{
    void **p = luaL_checkudata(L, arg, mt);
    if (!*p) luaL_argerror(L, arg, "object was freed");
    return p;
}

#define CHECK(L, arg, type, mt) ((type *)check_live(L, arg, mt))

/* Number field `key` of the table at `idx` (argument `arg`); `def` when absent, error when
 * required (def is NAN) or not a number. */
static double opt_number(lua_State *L, int idx, int arg, const char *key, double def)
{
    lua_getfield(L, idx, key);
    double v = def;
    if (!lua_isnil(L, -1)) {
        int ok;
        v = lua_tonumberx(L, -1, &ok);
        if (!ok)
            arg_error(L, arg, "%s must be a number, got %s", key, luaL_typename(L, -1));
        if (!isfinite(v)) arg_error(L, arg, "%s must be finite", key);
    } else if (isnan(def)) {
        arg_error(L, arg, "%s is required", key);
    }
    lua_pop(L, 1);
    return v;
}

static const char *opt_string(lua_State *L, int idx, int arg, const char *key, const char *def)
{
    lua_getfield(L, idx, key);
    const char *s = def;
    if (!lua_isnil(L, -1)) {
        if (lua_type(L, -1) != LUA_TSTRING)
            arg_error(L, arg, "%s must be a string, got %s", key, luaL_typename(L, -1));
        s = lua_tostring(L, -1); /* the table keeps it alive */
    }
    lua_pop(L, 1);
    return s;
}

static int opt_bool(lua_State *L, int idx, const char *key, int def)
{
    lua_getfield(L, idx, key);
    int v = lua_isnil(L, -1) ? def : lua_toboolean(L, -1);
    lua_pop(L, 1);
    return v;
}

/* A list of n numbers at stack index `idx`. Returns the count read (errors if longer than max). */
static int read_numbers(lua_State *L, int idx, int arg, const char *what, double *out, int max)
{
    idx = lua_absindex(L, idx);
    if (!lua_istable(L, idx))
        return arg_error(L, arg, "%s must be a list of numbers, got %s", what, luaL_typename(L, idx));
    int n = (int)lua_rawlen(L, idx);
    if (n > max) return arg_error(L, arg, "%s has %d numbers (at most %d)", what, n, max);
    for (int i = 0; i < n; ++i) {
        lua_rawgeti(L, idx, i + 1);
        int ok;
        out[i] = lua_tonumberx(L, -1, &ok);
        if (!ok || !isfinite(out[i]))
            arg_error(L, arg, "%s[%d] must be a finite number", what, i + 1);
        lua_pop(L, 1);
    }
    return n;
}

/* A 3-vector field `key` (required unless def given). */
static void opt_vec3(lua_State *L, int idx, int arg, const char *key, double out[3], const double *def)
{
    lua_getfield(L, idx, key);
    if (lua_isnil(L, -1)) {
        if (!def) arg_error(L, arg, "%s is required ({x, y, z})", key);
        memcpy(out, def, 3 * sizeof(double));
    } else if (read_numbers(L, -1, arg, key, out, 3) != 3) {
        arg_error(L, arg, "%s must have 3 numbers", key);
    }
    lua_pop(L, 1);
}

static void push_vec(lua_State *L, const double *v, int n)
{
    lua_createtable(L, n, 0);
    for (int i = 0; i < n; ++i) {
        lua_pushnumber(L, v[i]);
        lua_rawseti(L, -2, i + 1);
    }
}

/* ---- sandbox --------------------------------------------------------------------------------- */

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

/* 1 when writing `path` is allowed under the write root. */
static int write_allowed(lua_State *L, const char *path)
{
    lua_getfield(L, LUA_REGISTRYINDEX, REG_ROOT);
    const char *root = lua_tostring(L, -1);
    lua_pop(L, 1);
    if (!root) return 1;
    char dir[PATH_MAX], real[PATH_MAX];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash) {
        if (slash == dir) slash[1] = '\0';
        else *slash = '\0';
    } else {
        snprintf(dir, sizeof dir, ".");
    }
    if (!realpath(dir, real)) return 0;
    size_t n = strlen(root);
    return strncmp(real, root, n) == 0 && (real[n] == '\0' || real[n] == '/' || (n == 1 && root[0] == '/'));
}

const char *hv_lua_check_write(lua_State *L, int arg, const char *path)
{
    if (!write_allowed(L, path))
        arg_error(L, arg, "sandbox: writing '%s' outside the output directory is not allowed", path);
    return path;
}

static int sb_io_open(lua_State *L)
{
    const char *path = luaL_checkstring(L, 1), *mode = luaL_optstring(L, 2, "r");
    if (strpbrk(mode, "wa+")) hv_lua_check_write(L, 1, path);
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

static int sb_io_output(lua_State *L)
{
    if (lua_type(L, 1) == LUA_TSTRING) hv_lua_check_write(L, 1, lua_tostring(L, 1));
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

static int sb_os_path(lua_State *L)
{
    int n = (int)lua_tointeger(L, lua_upvalueindex(2));
    for (int i = 1; i <= n; ++i) hv_lua_check_write(L, i, luaL_checkstring(L, i));
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

/* ---- Mesh -------------------------------------------------------------------------------- */

static void push_mesh(lua_State *L, hv_mesh *m)
{
    l_mesh *u = new_ud(L, sizeof *u, MT_MESH);
    u->p = m;
}

static int l_load_mesh(lua_State *L)
{
    const char *path = luaL_checkstring(L, 1);
    hv_mesh *m;
    hv_status s = hv_mesh_load_stl(path, &m);
    if (s != HV_OK) return fail(L, s);
    push_mesh(L, m);
    return 1;
}

static void push_report(lua_State *L, const hv_mesh_report *r)
{
    lua_createtable(L, 0, 14);
    lua_pushstring(L, r->format == HV_MESH_STL_BINARY ? "binary" : r->format == HV_MESH_STL_ASCII ? "ascii" : "generated");
    lua_setfield(L, -2, "format");
#define SETI(k, v) (lua_pushinteger(L, (lua_Integer)(v)), lua_setfield(L, -2, k))
    SETI("facets", r->facets);
    SETI("vertices", r->vertices);
    SETI("shells", r->shells);
    SETI("open_edges", r->open_edges);
    SETI("nonmanifold_edges", r->nonmanifold_edges);
    SETI("degenerate_facets", r->degenerate_facets);
    SETI("flipped_facets", r->flipped_facets);
    SETI("normal_mismatch", r->normal_mismatch);
#undef SETI
    lua_pushnumber(L, r->volume);
    lua_setfield(L, -2, "volume");
    lua_pushnumber(L, r->area);
    lua_setfield(L, -2, "area");
    lua_createtable(L, 0, 2);
    push_vec(L, r->bbox_min, 3);
    lua_setfield(L, -2, "min");
    push_vec(L, r->bbox_max, 3);
    lua_setfield(L, -2, "max");
    lua_setfield(L, -2, "bbox");
    lua_pushboolean(L, r->open_edges == 0 && r->nonmanifold_edges == 0);
    lua_setfield(L, -2, "closed");
}

static int mesh_report(lua_State *L)
{
    l_mesh *u = CHECK(L, 1, l_mesh, MT_MESH);
    push_report(L, hv_mesh_get_report(u->p));
    return 1;
}

static int mesh_save(lua_State *L)
{
    l_mesh *u = CHECK(L, 1, l_mesh, MT_MESH);
    const char *path = hv_lua_check_write(L, 2, luaL_checkstring(L, 2));
    int ascii = lua_istable(L, 3) ? opt_bool(L, 3, "ascii", 0) : 0;
    hv_status s = hv_mesh_write_stl(u->p, path, ascii);
    return s != HV_OK ? fail(L, s) : 0;
}

static int mesh_count(lua_State *L)
{
    l_mesh *u = CHECK(L, 1, l_mesh, MT_MESH);
    lua_pushinteger(L, (lua_Integer)hv_mesh_facet_count(u->p));
    lua_pushinteger(L, (lua_Integer)hv_mesh_vertex_count(u->p));
    return 2;
}

static int mesh_gc(lua_State *L)
{
    l_mesh *u = luaL_checkudata(L, 1, MT_MESH);
    hv_mesh_destroy(u->p);
    u->p = NULL;
    return 0;
}

static int mesh_tostring(lua_State *L)
{
    l_mesh *u = luaL_checkudata(L, 1, MT_MESH);
    if (!u->p) lua_pushliteral(L, "hovox.Mesh (freed)");
    else lua_pushfstring(L, "hovox.Mesh (%d facets)", (int)hv_mesh_facet_count(u->p));
    return 1;
}

/* ---- generators --------------------------------------------------------------------------- */

static int opt_int_range(lua_State *L, int idx, int arg, const char *key, int def, int lo, int hi)
{
    double v = opt_number(L, idx, arg, key, def);
    if (v != floor(v) || v < lo || v > hi)
        arg_error(L, arg, "%s must be an integer in [%d, %d], got %g", key, lo, hi, v);
    return (int)v;
}

static int gen_table_arg(lua_State *L)
{
    if (lua_isnoneornil(L, 1)) lua_newtable(L), lua_replace(L, 1);
    luaL_checktype(L, 1, LUA_TTABLE);
    return 1;
}

static int g_sphere(lua_State *L)
{
    gen_table_arg(L);
    double z[3] = {0, 0, 0}, c[3];
    opt_vec3(L, 1, 1, "center", c, z);
    double r = opt_number(L, 1, 1, "radius", 10);
    int seg = opt_int_range(L, 1, 1, "segments", 64, 3, 100000), rings = opt_int_range(L, 1, 1, "rings", 32, 2, 100000);
    hv_mesh *m;
    hv_status s = hv_generate_sphere(c, r, seg, rings, &m);
    if (s != HV_OK) return fail(L, s);
    push_mesh(L, m);
    return 1;
}

static int g_box(lua_State *L)
{
    gen_table_arg(L);
    double lo[3], hi[3], z[3] = {0, 0, 0}, o[3] = {20, 20, 20};
    opt_vec3(L, 1, 1, "min", lo, z);
    opt_vec3(L, 1, 1, "max", hi, o);
    hv_mesh *m;
    hv_status s;
    lua_getfield(L, 1, "hole");
    int holed = !lua_isnil(L, -1);
    lua_pop(L, 1);
    if (holed)
        s = hv_generate_box_with_hole(lo, hi, opt_number(L, 1, 1, "hole", 0),
                                      opt_int_range(L, 1, 1, "segments", 64, 8, 100000), &m);
    else
        s = hv_generate_box(lo, hi, &m);
    if (s != HV_OK) return fail(L, s);
    push_mesh(L, m);
    return 1;
}

static int g_torus(lua_State *L)
{
    gen_table_arg(L);
    double z[3] = {0, 0, 0}, c[3];
    opt_vec3(L, 1, 1, "center", c, z);
    hv_mesh *m;
    hv_status s = hv_generate_torus(c, opt_number(L, 1, 1, "R", 20), opt_number(L, 1, 1, "r", 6),
                                    opt_int_range(L, 1, 1, "segments", 96, 3, 100000),
                                    opt_int_range(L, 1, 1, "rings", 48, 3, 100000), &m);
    if (s != HV_OK) return fail(L, s);
    push_mesh(L, m);
    return 1;
}

static int g_cylinder(lua_State *L)
{
    gen_table_arg(L);
    double z[3] = {0, 0, 0}, b[3];
    opt_vec3(L, 1, 1, "base", b, z);
    hv_mesh *m;
    hv_status s = hv_generate_cylinder(b, opt_int_range(L, 1, 1, "axis", 0, 0, 2), opt_number(L, 1, 1, "length", 150),
                                       opt_number(L, 1, 1, "radius", 27.5),
                                       opt_int_range(L, 1, 1, "segments", 128, 3, 1000000), &m);
    if (s != HV_OK) return fail(L, s);
    push_mesh(L, m);
    return 1;
}

static int g_gear(lua_State *L)
{
    gen_table_arg(L);
    hv_mesh *m;
    hv_status s = hv_generate_gear(opt_int_range(L, 1, 1, "teeth", 24, 3, 10000), opt_number(L, 1, 1, "root", 34.5),
                                   opt_number(L, 1, 1, "tip", 39.45), opt_number(L, 1, 1, "bore", 9.54),
                                   opt_number(L, 1, 1, "height", 39.45), opt_number(L, 1, 1, "twist", 0),
                                   opt_int_range(L, 1, 1, "segments", 12, 8, 10000),
                                   opt_int_range(L, 1, 1, "layers", 1, 1, 100000), &m);
    if (s != HV_OK) return fail(L, s);
    push_mesh(L, m);
    return 1;
}

static int g_knot(lua_State *L)
{
    gen_table_arg(L);
    int nv = opt_int_range(L, 1, 1, "segments_around", 64, 3, 100000);
    int nu = (int)(opt_number(L, 1, 1, "facets", 200000) / (2.0 * nv));
    hv_mesh *m;
    hv_status s = hv_generate_torus_knot(opt_int_range(L, 1, 1, "p", 2, 1, 1000), opt_int_range(L, 1, 1, "q", 3, 1, 1000),
                                         opt_number(L, 1, 1, "R", 30), opt_number(L, 1, 1, "r", 12),
                                         opt_number(L, 1, 1, "tube", 5), nu, nv, &m);
    if (s != HV_OK) return fail(L, s);
    push_mesh(L, m);
    return 1;
}

/* ---- Model -------------------------------------------------------------------------------- */

static l_model *push_model(lua_State *L, hv_volume *v)
{
    l_model *u = new_ud(L, sizeof *u, MT_MODEL);
    u->p = v;
    return u;
}

static int l_voxelize(lua_State *L)
{
    l_mesh *mesh = CHECK(L, 1, l_mesh, MT_MESH);
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    hv_transform lattice;
    if (!lua_isnoneornil(L, 2)) {
        static const char *const keys[] = {"dims", "voxel_size", "like", "adjacency", "fill", "max_memory", NULL};
        hv_lua_check_options(L, 2, 2, keys);
        int adj = opt_int_range(L, 2, 2, "adjacency", 26, 6, 26);
        if (adj != 6 && adj != 26) return arg_error(L, 2, "adjacency must be 6 or 26, got %d", adj);
        o.adjacency = adj;
        lua_getfield(L, 2, "dims");
        if (lua_isnumber(L, -1)) {
            double d = lua_tonumber(L, -1);
            if (d < 1 || d > 2147483647.0 || d != floor(d))
                return arg_error(L, 2, "dims must be a positive integer, got %g", d);
            o.dims[0] = (int64_t)d;
        } else if (lua_istable(L, -1)) {
            double d[3];
            if (read_numbers(L, -1, 2, "dims", d, 3) != 3) return luaL_argerror(L, 2, "dims must be N or {X, Y, Z}");
            for (int a = 0; a < 3; ++a) {
                if (d[a] < 1 || d[a] != floor(d[a])) return luaL_argerror(L, 2, "dims must be positive integers");
                o.dims[a] = (int64_t)d[a];
            }
        } else if (!lua_isnil(L, -1)) {
            return arg_error(L, 2, "dims must be a number or {X, Y, Z}, got %s", luaL_typename(L, -1));
        }
        lua_pop(L, 1);
        lua_getfield(L, 2, "voxel_size");
        if (lua_isnumber(L, -1)) {
            double v = lua_tonumber(L, -1);
            if (!(v > 0)) return arg_error(L, 2, "voxel_size must be > 0, got %g", v);
            o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = v;
        } else if (lua_istable(L, -1)) {
            if (read_numbers(L, -1, 2, "voxel_size", o.voxel_size, 3) != 3)
                return luaL_argerror(L, 2, "voxel_size must be L or {X, Y, Z}");
        }
        lua_pop(L, 1);
        lua_getfield(L, 2, "like");
        if (!lua_isnil(L, -1)) {
            l_model *like = CHECK(L, -1, l_model, MT_MODEL);
            lattice = hv_volume_get_transform(like->p);
            o.lattice = &lattice;
        }
        lua_pop(L, 1);
        const char *fill = opt_string(L, 2, 2, "fill", "auto");
        if (strcmp(fill, "auto") == 0) o.fill = HV_FILL_AUTO;
        else if (strcmp(fill, "flood") == 0) o.fill = HV_FILL_FLOOD;
        else if (strcmp(fill, "vote") == 0 || strcmp(fill, "winding") == 0) o.fill = HV_FILL_VOTE;
        else if (strcmp(fill, "none") == 0) o.fill = HV_FILL_NONE;
        else return arg_error(L, 2, "fill must be auto, flood, vote or none, got '%s'", fill);
        o.max_memory = (uint64_t)opt_number(L, 2, 2, "max_memory", 0);
    }
    hv_volume *v;
    hv_status s = hv_voxelize(mesh->p, &o, &v);
    if (s != HV_OK) return fail(L, s);
    push_model(L, v);
    return 1;
}

static int l_load(lua_State *L)
{
    const char *path = luaL_checkstring(L, 1);
    hv_volume *v;
    hv_status s = hv_volume_load(path, &v);
    if (s != HV_OK) return fail(L, s);
    push_model(L, v);
    return 1;
}

static int model_save(lua_State *L)
{
    l_model *u = CHECK(L, 1, l_model, MT_MODEL);
    const char *path = hv_lua_check_write(L, 2, luaL_checkstring(L, 2));
    hv_status s = hv_volume_save(u->p, path);
    return s != HV_OK ? fail(L, s) : 0;
}

static int model_grids(lua_State *L)
{
    l_model *u = CHECK(L, 1, l_model, MT_MODEL);
    int n = hv_volume_grid_count(u->p);
    lua_createtable(L, n, 0);
    for (int g = 0; g < n; ++g) {
        lua_createtable(L, 0, 2);
        lua_pushstring(L, hv_volume_grid_name(u->p, g));
        lua_setfield(L, -2, "name");
        lua_pushstring(L, hv_volume_grid_type(u->p, g) == HV_GRID_BOOL ? "bool" : "float");
        lua_setfield(L, -2, "type");
        lua_rawseti(L, -2, g + 1);
    }
    return 1;
}

static int model_voxels(lua_State *L)
{
    l_model *u = CHECK(L, 1, l_model, MT_MODEL);
    const char *grid = luaL_optstring(L, 2, NULL);
    if (!grid) {
        lua_pushinteger(L, (lua_Integer)hv_volume_active_count(u->p));
        return 1;
    }
    int g = hv_volume_grid_find(u->p, grid);
    if (g < 0 || hv_volume_grid_type(u->p, g) != HV_GRID_BOOL)
        return arg_error(L, 2, "no bool grid '%s'", grid);
    lua_pushinteger(L, (lua_Integer)hv_volume_mask_count(u->p, g));
    return 1;
}

static int model_transform(lua_State *L)
{
    l_model *u = CHECK(L, 1, l_model, MT_MODEL);
    hv_transform xf = hv_volume_get_transform(u->p);
    lua_createtable(L, 0, 2);
    push_vec(L, xf.voxel, 3);
    lua_setfield(L, -2, "voxel");
    push_vec(L, xf.origin, 3);
    lua_setfield(L, -2, "origin");
    int32_t lo[3], hi[3];
    if (hv_volume_index_bbox(u->p, lo, hi)) {
        double a[3] = {lo[0], lo[1], lo[2]}, b[3] = {hi[0], hi[1], hi[2]};
        push_vec(L, a, 3);
        lua_setfield(L, -2, "index_min");
        push_vec(L, b, 3);
        lua_setfield(L, -2, "index_max");
    }
    return 1;
}

static int model_meta(lua_State *L)
{
    l_model *u = CHECK(L, 1, l_model, MT_MODEL);
    const char *key = luaL_checkstring(L, 2);
    double d;
    const char *s = hv_volume_meta_string(u->p, key);
    if (s) lua_pushstring(L, s);
    else if (hv_volume_meta_number(u->p, key, &d)) lua_pushnumber(L, d);
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
    if (read_numbers(L, 2, 2, "point", p, 3) != 3) return luaL_argerror(L, 2, "point must be {x, y, z}");
    hv_material_table *t = model_mats(L, u);
    int m = hv_material_count(t), grids[HV_MAX_MATERIALS], inside;
    for (int j = 0; j < m; ++j) grids[j] = hv_material_grid(u->p, t, j);
    double f[HV_MAX_MATERIALS];
    hv_accessor acc;
    hv_accessor_init(&acc, u->p);
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

static int model_free(lua_State *L)
{
    l_model *u = luaL_checkudata(L, 1, MT_MODEL);
    hv_volume_destroy(u->p);
    hv_material_table_destroy(u->mats);
    u->p = NULL;
    u->mats = NULL;
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

static int mats_add_one(lua_State *L, hv_material_table *t, int idx, int arg)
{
    idx = lua_absindex(L, idx);
    const char *name = NULL;
    if (lua_type(L, idx) == LUA_TSTRING) {
        name = lua_tostring(L, idx);
        hv_status s = hv_material_add(t, name, NULL, NULL);
        return s != HV_OK ? fail(L, s) : 0;
    }
    if (!lua_istable(L, idx)) return luaL_argerror(L, arg, "a material is a name or {name=..., color=..., ...}");
    name = opt_string(L, idx, arg, "name", NULL);
    if (!name) return luaL_argerror(L, arg, "material needs a name");
    float rgba[4], *color = NULL;
    lua_getfield(L, idx, "color");
    if (lua_type(L, -1) == LUA_TSTRING) {
        if (hv_color_parse(lua_tostring(L, -1), rgba) != HV_OK) return luaL_argerror(L, arg, hv_last_error());
        color = rgba;
    } else if (lua_istable(L, -1)) {
        double c[4] = {0, 0, 0, 1};
        int n = read_numbers(L, -1, arg, "color", c, 4);
        if (n < 3) return luaL_argerror(L, arg, "color must be {r, g, b[, a]} or '#rrggbb'");
        for (int k = 0; k < 4; ++k) rgba[k] = (float)c[k];
        color = rgba;
    }
    lua_pop(L, 1);
    int mi;
    hv_status s = hv_material_add(t, name, color, &mi);
    if (s != HV_OK) return fail(L, s);
    /* every other numeric field is a property; units for the known ones */
    /* every other field is a property: a number (SI unit for the known ones) or {value, "unit"} */
    lua_pushnil(L);
    while (lua_next(L, idx)) {
        if (lua_type(L, -2) != LUA_TSTRING) {
            lua_pop(L, 1);
            continue;
        }
        const char *key = lua_tostring(L, -2), *unit = "";
        if (strcmp(key, "name") == 0 || strcmp(key, "color") == 0) {
            lua_pop(L, 1);
            continue;
        }
        double value = 0;
        const char *tn = luaL_typename(L, -1);
        if (lua_type(L, -1) == LUA_TNUMBER) {
            value = lua_tonumber(L, -1);
            unit = hv_property_si_unit(key);
        } else if (lua_istable(L, -1) && lua_rawlen(L, -1) == 2 && lua_rawgeti(L, -1, 1) == LUA_TNUMBER &&
                   lua_rawgeti(L, -2, 2) == LUA_TSTRING) {
            value = lua_tonumber(L, -2);
            unit = lua_tostring(L, -1);
            lua_pop(L, 2);
        } else {
            return arg_error(L, arg, "material '%s': %s must be a number or {value, \"unit\"} (a property; "
                             "the colour is 'color'), got %s", name, key, tn);
        }
        if ((s = hv_material_set_property(t, mi, key, value, unit)) != HV_OK) {
            lua_pop(L, 2);
            return fail(L, s);
        }
        lua_pop(L, 1);
    }
    return 0;
}

static int l_materials(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TTABLE);
    hv_material_table *t;
    if (hv_material_table_create(&t) != HV_OK) return fail(L, HV_ERR_NOMEM);
    l_mats *u = new_ud(L, sizeof *u, MT_MATS); /* owns t from here, so errors do not leak it */
    u->p = t;
    int n = (int)lua_rawlen(L, 1);
    if (n == 0) return luaL_argerror(L, 1, "give at least one material");
    for (int i = 1; i <= n; ++i) {
        lua_rawgeti(L, 1, i);
        mats_add_one(L, t, -1, 1);
        lua_pop(L, 1);
    }
    return 1;
}

static int mats_names(lua_State *L)
{
    l_mats *u = CHECK(L, 1, l_mats, MT_MATS);
    int n = hv_material_count(u->p);
    lua_createtable(L, n, 0);
    for (int j = 0; j < n; ++j) {
        lua_pushstring(L, hv_material_name(u->p, j));
        lua_rawseti(L, -2, j + 1);
    }
    return 1;
}

static int mats_count(lua_State *L)
{
    l_mats *u = CHECK(L, 1, l_mats, MT_MATS);
    lua_pushinteger(L, hv_material_count(u->p));
    return 1;
}

static int mats_color(lua_State *L)
{
    l_mats *u = CHECK(L, 1, l_mats, MT_MATS);
    const char *name = luaL_checkstring(L, 2);
    int m = hv_material_find(u->p, name);
    if (m < 0) return arg_error(L, 2, "no material '%s'", name);
    float c[4];
    hv_material_color(u->p, m, c);
    double d[4] = {c[0], c[1], c[2], c[3]};
    push_vec(L, d, 4);
    return 1;
}

static int mats_property(lua_State *L)
{
    l_mats *u = CHECK(L, 1, l_mats, MT_MATS);
    const char *name = luaL_checkstring(L, 2), *key = luaL_checkstring(L, 3);
    int m = hv_material_find(u->p, name);
    if (m < 0) return arg_error(L, 2, "no material '%s'", name);
    double v;
    const char *unit;
    if (!hv_material_property(u->p, m, key, &v, &unit)) {
        lua_pushnil(L);
        return 1;
    }
    lua_pushnumber(L, v);
    lua_pushstring(L, unit);
    return 2;
}

static int mats_gc(lua_State *L)
{
    l_mats *u = luaL_checkudata(L, 1, MT_MATS);
    hv_material_table_destroy(u->p);
    u->p = NULL;
    return 0;
}

/* ---- Features ---------------------------------------------------------------------------- */

static int push_feature(lua_State *L, hv_status s, hv_frf *f)
{
    if (s != HV_OK) return fail(L, s);
    l_feature *u = new_ud(L, sizeof *u, MT_FEATURE);
    u->p = f;
    return 1;
}

static int l_axis(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TTABLE);
    double o[3], d[3], z[3] = {0, 0, 0};
    opt_vec3(L, 1, 1, "origin", o, z);
    opt_vec3(L, 1, 1, "direction", d, NULL);
    if (d[0] == 0 && d[1] == 0 && d[2] == 0) return luaL_argerror(L, 1, "direction must not be zero");
    hv_frf *f;
    hv_status s = hv_frf_line(o, d, &f);
    return push_feature(L, s, f);
}

static int l_plane(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TTABLE);
    double p[3], n[3], z[3] = {0, 0, 0};
    opt_vec3(L, 1, 1, "point", p, z);
    opt_vec3(L, 1, 1, "normal", n, NULL);
    if (n[0] == 0 && n[1] == 0 && n[2] == 0) return luaL_argerror(L, 1, "normal must not be zero");
    hv_frf *f;
    hv_status s = hv_frf_plane(p, n, &f);
    return push_feature(L, s, f);
}

static int l_point(lua_State *L)
{
    double p[3];
    if (lua_istable(L, 1) && lua_rawlen(L, 1) == 3) read_numbers(L, 1, 1, "point", p, 3);
    else {
        luaL_checktype(L, 1, LUA_TTABLE);
        opt_vec3(L, 1, 1, "point", p, NULL);
    }
    hv_frf *f;
    hv_status s = hv_frf_point(p, &f);
    return push_feature(L, s, f);
}

static int l_segment(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TTABLE);
    double a[3], b[3];
    opt_vec3(L, 1, 1, "from", a, NULL);
    opt_vec3(L, 1, 1, "to", b, NULL);
    hv_frf *f;
    hv_status s = hv_frf_segment(a, b, &f);
    return push_feature(L, s, f);
}

static void read_select(lua_State *L, int idx, int arg, hv_facet_select *sel)
{
    memset(sel, 0, sizeof *sel);
    luaL_checktype(L, idx, LUA_TTABLE);
    lua_getfield(L, idx, "normal");
    sel->use_normal = !lua_isnil(L, -1);
    lua_pop(L, 1);
    if (sel->use_normal) {
        opt_vec3(L, idx, arg, "normal", sel->normal, NULL);
        sel->angle_deg = opt_number(L, idx, arg, "angle", 10);
        if (!(sel->angle_deg >= 0 && sel->angle_deg <= 180)) luaL_argerror(L, arg, "angle must be in [0, 180] degrees");
    }
    lua_getfield(L, idx, "box_min");
    sel->use_box = !lua_isnil(L, -1);
    lua_pop(L, 1);
    if (sel->use_box) {
        opt_vec3(L, idx, arg, "box_min", sel->box_lo, NULL);
        opt_vec3(L, idx, arg, "box_max", sel->box_hi, NULL);
    }
    if (!sel->use_normal && !sel->use_box) luaL_argerror(L, arg, "select facets by normal= (and angle=) and/or box_min=, box_max=");
}

static int l_facets(lua_State *L)
{
    l_mesh *m = CHECK(L, 1, l_mesh, MT_MESH);
    hv_facet_select sel;
    read_select(L, 2, 2, &sel);
    hv_frf *f;
    hv_status s = hv_frf_facets(m->p, &sel, &f);
    return push_feature(L, s, f);
}

static int model_contour(lua_State *L)
{
    l_model *u = CHECK(L, 1, l_model, MT_MODEL);
    const char *grid = luaL_optstring(L, 2, "occupancy");
    hv_frf *f;
    hv_status s = hv_frf_contour(u->p, grid, &f);
    return push_feature(L, s, f);
}

static int model_mask(lua_State *L)
{
    l_model *u = CHECK(L, 1, l_model, MT_MODEL);
    const char *grid = luaL_checkstring(L, 2);
    hv_frf *f;
    hv_status s = hv_frf_mask(u->p, grid, &f);
    return push_feature(L, s, f);
}

static int model_harmonic(lua_State *L)
{
    l_model *u = CHECK(L, 1, l_model, MT_MODEL);
    l_mesh *m = CHECK(L, 2, l_mesh, MT_MESH);
    hv_facet_select one, zero;
    read_select(L, 3, 3, &one);
    read_select(L, 4, 4, &zero);
    const char *domain = luaL_optstring(L, 5, "occupancy");
    hv_frf *f;
    hv_status s = hv_frf_harmonic(u->p, domain, m->p, &one, &zero, &f);
    return push_feature(L, s, f);
}

static int feature_distance(lua_State *L)
{
    l_feature *u = CHECK(L, 1, l_feature, MT_FEATURE);
    double p[3];
    if (read_numbers(L, 2, 2, "point", p, 3) != 3) return luaL_argerror(L, 2, "point must be {x, y, z}");
    l_model *lat = lua_isnoneornil(L, 3) ? NULL : CHECK(L, 3, l_model, MT_MODEL);
    if (!lat && hv_frf_get_kind(u->p) >= HV_FRF_CONTOUR)
        return luaL_argerror(L, 3, "voxel features need the model whose lattice to use");
    double d;
    hv_status s = hv_frf_distance(u->p, lat ? lat->p : NULL, p, &d);
    if (s != HV_OK) return fail(L, s);
    lua_pushnumber(L, d);
    return 1;
}

static int feature_gc(lua_State *L)
{
    l_feature *u = luaL_checkudata(L, 1, MT_FEATURE);
    hv_frf_release(u->p);
    u->p = NULL;
    return 0;
}

static int feature_tostring(lua_State *L)
{
    l_feature *u = luaL_checkudata(L, 1, MT_FEATURE);
    lua_pushfstring(L, "hovox.Feature %s", u->p ? hv_frf_describe(u->p) : "(freed)");
    return 1;
}

/* ---- Sources (AGS) ----------------------------------------------------------------------- */

typedef struct lua_fn_ctx {
    lua_State *L;
    int ref;
    int failed;
    char msg[512];
} lua_fn_ctx;

/* f as a Lua function: called under lua_pcall during tabulation only. */
static double lua_f(void *user, double d)
{
    lua_fn_ctx *c = user;
    if (c->failed) return NAN;
    lua_rawgeti(c->L, LUA_REGISTRYINDEX, c->ref);
    lua_pushnumber(c->L, d);
    if (lua_pcall(c->L, 1, 1, 0) != LUA_OK) {
        c->failed = 1;
        snprintf(c->msg, sizeof c->msg, "%s", lua_tostring(c->L, -1) ? lua_tostring(c->L, -1) : "error in f");
        lua_pop(c->L, 1);
        return NAN;
    }
    int ok;
    double v = lua_tonumberx(c->L, -1, &ok);
    lua_pop(c->L, 1);
    if (!ok) {
        c->failed = 1;
        snprintf(c->msg, sizeof c->msg, "f(%g) returned a non-number", d);
        return NAN;
    }
    return v;
}

/* Parse f (string, function or {kind=...}) at stack index idx into *out. Lua functions leave
 * a registry reference in ctx (released by the caller). */
static void read_f(lua_State *L, int idx, int arg, lua_fn_ctx *ctx, hv_dfn **out)
{
    hv_status s = HV_OK;
    *out = NULL;
    idx = lua_absindex(L, idx);
    switch (lua_type(L, idx)) {
    case LUA_TSTRING:
        if (hv_dfn_expr(lua_tostring(L, idx), out) != HV_OK) luaL_argerror(L, arg, hv_last_error());
        return;
    case LUA_TNUMBER: {
        double v = lua_tonumber(L, idx);
        s = hv_dfn_linear(0, v, out);
        break;
    }
    case LUA_TFUNCTION:
        lua_pushvalue(L, idx);
        ctx->L = L;
        ctx->ref = luaL_ref(L, LUA_REGISTRYINDEX);
        s = hv_dfn_function(lua_f, ctx, "lua function", out);
        break;
    case LUA_TTABLE: {
        const char *kind = opt_string(L, idx, arg, "kind", NULL);
        if (!kind) luaL_argerror(L, arg, "f table needs kind = linear|sine|power|smoothstep|table");
        if (strcmp(kind, "linear") == 0)
            s = hv_dfn_linear(opt_number(L, idx, arg, "a", 1), opt_number(L, idx, arg, "b", 0), out);
        else if (strcmp(kind, "sine") == 0)
            s = hv_dfn_sine(opt_number(L, idx, arg, "k", NAN), opt_number(L, idx, arg, "amplitude", 1),
                            opt_number(L, idx, arg, "phase", 0), opt_number(L, idx, arg, "offset", 0), out);
        else if (strcmp(kind, "power") == 0)
            s = hv_dfn_power(opt_number(L, idx, arg, "p", NAN), out);
        else if (strcmp(kind, "smoothstep") == 0)
            s = hv_dfn_smoothstep(out);
        else if (strcmp(kind, "table") == 0) {
            lua_getfield(L, idx, "points");
            if (!lua_istable(L, -1)) luaL_argerror(L, arg, "table f needs points = {{d, f}, ...}");
            int n = (int)lua_rawlen(L, -1);
            if (n < 2 || n > 100000) luaL_argerror(L, arg, "table f needs 2 or more points");
            double *d = malloc((size_t)n * 2 * sizeof(double));
            if (!d) luaL_error(L, "out of memory");
            for (int i = 0; i < n; ++i) {
                lua_rawgeti(L, -1, i + 1);
                double pt[2];
                if (!lua_istable(L, -1) || read_numbers(L, -1, arg, "point", pt, 2) != 2) {
                    free(d);
                    arg_error(L, arg, "points[%d] must be {d, f}", i + 1);
                }
                d[i] = pt[0];
                d[n + i] = pt[1];
                lua_pop(L, 1);
            }
            lua_pop(L, 1);
            s = hv_dfn_table(d, d + n, n, out);
            free(d);
        } else {
            arg_error(L, arg, "unknown f kind '%s'", kind);
        }
        break;
    }
    default:
        arg_error(L, arg, "f must be an expression, a function or {kind=...}, got %s",
                                              luaL_typename(L, idx));
    }
    if (s != HV_OK) luaL_argerror(L, arg, hv_last_error());
}

static int push_source(lua_State *L, hv_ags *a)
{
    l_source *u = new_ud(L, sizeof *u, MT_SOURCE);
    u->p = a;
    return 1;
}

/* Make an AGS from the table at `idx` (argument number `arg`, function name for messages). */
static hv_ags *source_from_table(lua_State *L, int idx, int arg)
{
    static const char *const keys[] = {"feature", "d_neg", "d_grad", "d_pos", "f", "ms", "me", "name", NULL};
    hv_lua_check_options(L, idx, arg, keys);
    lua_getfield(L, idx, "feature");
    l_feature *feat = luaL_testudata(L, -1, MT_FEATURE);
    if (!feat || !feat->p) luaL_argerror(L, arg, "feature must be a hovox feature (hovox.axis{...}, model:contour(), ...)");
    lua_pop(L, 1);
    double dn = opt_number(L, idx, arg, "d_neg", 0), dg = opt_number(L, idx, arg, "d_grad", 0),
           dp = opt_number(L, idx, arg, "d_pos", 0);
    if (dn < 0) arg_error(L, arg, "d_neg must be >= 0, got %g", dn);
    if (dg < 0) arg_error(L, arg, "d_grad must be >= 0, got %g", dg);
    if (dp < 0) arg_error(L, arg, "d_pos must be >= 0, got %g", dp);
    double ms[HV_MAX_MATERIALS], me[HV_MAX_MATERIALS];
    lua_getfield(L, idx, "ms");
    int nm = read_numbers(L, -1, arg, "ms", ms, HV_MAX_MATERIALS);
    lua_pop(L, 1);
    lua_getfield(L, idx, "me");
    int ne = read_numbers(L, -1, arg, "me", me, HV_MAX_MATERIALS);
    lua_pop(L, 1);
    if (nm != ne || nm == 0) arg_error(L, arg, "ms has %d values and me %d", nm, ne);
    if (hv_composition_check(ms, nm, "ms") != HV_OK || hv_composition_check(me, nm, "me") != HV_OK)
        luaL_argerror(L, arg, hv_last_error());
    const char *name = opt_string(L, idx, arg, "name", NULL);
    hv_dfn *f = NULL;
    lua_fn_ctx ctx = {L, LUA_NOREF, 0, ""};
    lua_getfield(L, idx, "f");
    if (!lua_isnil(L, -1)) read_f(L, -1, arg, &ctx, &f);
    else if (dg > 0) hv_dfn_expr("d/dg", &f);
    lua_pop(L, 1);
    hv_ags_desc d = {feat->p, dn, dg, dp, f, ms, me, nm, name};
    hv_ags *a = NULL;
    hv_status s = hv_ags_create(&d, &a);
    hv_dfn_destroy(f);
    if (ctx.ref != LUA_NOREF) luaL_unref(L, LUA_REGISTRYINDEX, ctx.ref);
    if (ctx.failed) arg_error(L, arg, "f failed: %s", ctx.msg);
    if (s != HV_OK) luaL_argerror(L, arg, hv_last_error());
    return a;
}

static int l_ags(lua_State *L)
{
    hv_ags *a = source_from_table(L, 1, 1);
    return push_source(L, a);
}

/* hovox.wu3{feature, d_neg, d_grad, d_pos, f, c}: Wu's 3-material distance-field paradigm
 * (eq. 13), P = [f, 1 - f - c, c] over the gradient range, checking 0 <= f <= 1 - c. */
static int l_wu3(lua_State *L)
{
    static const char *const keys[] = {"feature", "d_neg", "d_grad", "d_pos", "f", "c", NULL};
    hv_lua_check_options(L, 1, 1, keys);
    lua_getfield(L, 1, "feature");
    l_feature *feat = luaL_testudata(L, -1, MT_FEATURE);
    if (!feat || !feat->p) return luaL_argerror(L, 1, "feature must be a hovox feature (hovox.axis{...}, ...)");
    lua_pop(L, 1);
    double dn = opt_number(L, 1, 1, "d_neg", 0), dg = opt_number(L, 1, 1, "d_grad", 0),
           dp = opt_number(L, 1, 1, "d_pos", 0), c = opt_number(L, 1, 1, "c", 0);
    if (dn < 0 || dg < 0 || dp < 0)
        return arg_error(L, 1, "d_neg, d_grad and d_pos must be >= 0, got %g, %g, %g", dn, dg, dp);
    if (!(c >= 0 && c <= 1)) return arg_error(L, 1, "c must be in [0, 1], got %g", c);
    hv_dfn *f = NULL;
    lua_fn_ctx ctx = {L, LUA_NOREF, 0, ""};
    lua_getfield(L, 1, "f");
    if (lua_isnil(L, -1)) return luaL_argerror(L, 1, "f is required (Wu eq. 13: P = [f, 1 - f - c, c])");
    read_f(L, -1, 1, &ctx, &f);
    lua_pop(L, 1);
    hv_ags *a = NULL;
    hv_status s = hv_ags_wu3(feat->p, dn, dg, dp, f, c, &a);
    hv_dfn_destroy(f);
    if (ctx.ref != LUA_NOREF) luaL_unref(L, LUA_REGISTRYINDEX, ctx.ref);
    if (ctx.failed) return arg_error(L, 1, "f failed: %s", ctx.msg);
    if (s != HV_OK) return luaL_argerror(L, 1, hv_last_error());
    return push_source(L, a);
}

static int source_eval(lua_State *L)
{
    l_source *u = CHECK(L, 1, l_source, MT_SOURCE);
    double d = luaL_checknumber(L, 2), p[HV_MAX_MATERIALS];
    hv_ags_eval(u->p, d, p);
    push_vec(L, p, hv_ags_materials(u->p));
    return 1;
}

static int source_ranges(lua_State *L)
{
    l_source *u = CHECK(L, 1, l_source, MT_SOURCE);
    double a, b, c;
    hv_ags_ranges(u->p, &a, &b, &c);
    lua_pushnumber(L, a);
    lua_pushnumber(L, b);
    lua_pushnumber(L, c);
    return 3;
}

static int source_moved(lua_State *L)
{
    l_source *u = CHECK(L, 1, l_source, MT_SOURCE);
    double dn = luaL_checknumber(L, 2);
    if (!(dn >= 0)) return arg_error(L, 2, "d_neg must be >= 0, got %g", dn);
    hv_ags *b;
    hv_status s = hv_ags_moved(u->p, dn, &b);
    if (s != HV_OK) return fail(L, s);
    return push_source(L, b);
}

static int source_gc(lua_State *L)
{
    l_source *u = luaL_checkudata(L, 1, MT_SOURCE);
    hv_ags_release(u->p);
    u->p = NULL;
    return 0;
}

/* ---- Objects -------------------------------------------------------------------------------- */

static l_object *push_object(lua_State *L, hv_object *o, int mats_index)
{
    l_object *u = new_ud(L, sizeof *u, MT_OBJECT);
    u->p = o;
    lua_pushvalue(L, mats_index); /* keep the material table alive with the object */
    lua_setiuservalue(L, -2, 1);
    return u;
}

static int l_make_object(lua_State *L)
{
    l_model *m = CHECK(L, 1, l_model, MT_MODEL);
    l_mats *t = CHECK(L, 2, l_mats, MT_MATS);
    const char *grid = "occupancy";
    if (lua_istable(L, 3)) grid = opt_string(L, 3, 3, "grid", "occupancy");
    hv_object *o;
    hv_status s = hv_object_create(m->p, grid, hv_material_count(t->p), &o);
    if (s != HV_OK) return fail(L, s);
    push_object(L, o, 2);
    return 1;
}

static hv_material_table *object_mats(lua_State *L, int idx)
{
    lua_getiuservalue(L, idx, 1);
    l_mats *t = luaL_checkudata(L, -1, MT_MATS);
    lua_pop(L, 1);
    return t->p;
}

static int object_add_ags(lua_State *L)
{
    l_object *u = CHECK(L, 1, l_object, MT_OBJECT);
    hv_ags *a;
    if (luaL_testudata(L, 2, MT_SOURCE)) {
        a = hv_ags_retain(CHECK(L, 2, l_source, MT_SOURCE)->p);
        lua_pushvalue(L, 2);
    } else {
        a = source_from_table(L, 2, 2);
        push_source(L, hv_ags_retain(a));
    }
    if (hv_ags_materials(a) != hv_object_materials(u->p)) {
        hv_ags_release(a);
        return arg_error(L, 2, "the source has %d materials, the object %d",
                                                   hv_ags_materials(a), hv_object_materials(u->p));
    }
    hv_status s = hv_object_add_ags(u->p, a);
    hv_ags_release(a);
    if (s != HV_OK) return fail(L, s);
    return 1; /* the source */
}

static int object_delete_ags(lua_State *L)
{
    l_object *u = CHECK(L, 1, l_object, MT_OBJECT);
    l_source *a = CHECK(L, 2, l_source, MT_SOURCE);
    hv_status s = hv_object_delete_ags(u->p, a->p);
    return s != HV_OK ? fail(L, s) : 0;
}

static int object_move_ags(lua_State *L)
{
    l_object *u = CHECK(L, 1, l_object, MT_OBJECT);
    l_source *a = CHECK(L, 2, l_source, MT_SOURCE);
    double dn = luaL_checknumber(L, 3);
    if (!(dn >= 0)) return arg_error(L, 3, "d_neg must be >= 0, got %g", dn);
    hv_status s = hv_object_move_ags(u->p, a->p, dn);
    return s != HV_OK ? fail(L, s) : 0;
}

static int object_set_blend(lua_State *L)
{
    l_object *u = CHECK(L, 1, l_object, MT_OBJECT);
    static const char *const names[] = {"nearest", "idw", NULL};
    int b = luaL_checkoption(L, 2, NULL, names);
    double power = luaL_optnumber(L, 3, 2);
    if (!(power > 0)) return arg_error(L, 3, "power must be > 0, got %g", power);
    hv_status s = hv_object_set_blend(u->p, b ? HV_BLEND_IDW : HV_BLEND_NEAREST, power);
    return s != HV_OK ? fail(L, s) : 0;
}

static int object_set_base(lua_State *L)
{
    l_object *u = CHECK(L, 1, l_object, MT_OBJECT);
    double p[HV_MAX_MATERIALS];
    int n = read_numbers(L, 2, 2, "base", p, HV_MAX_MATERIALS);
    if (n != hv_object_materials(u->p))
        return arg_error(L, 2, "base has %d values for %d materials", n, hv_object_materials(u->p));
    if (hv_composition_check(p, n, "base") != HV_OK) return luaL_argerror(L, 2, hv_last_error());
    hv_status s = hv_object_set_base(u->p, p);
    return s != HV_OK ? fail(L, s) : 0;
}

static int object_boolean(lua_State *L, hv_bool_op op)
{
    l_object *a = CHECK(L, 1, l_object, MT_OBJECT), *b = CHECK(L, 2, l_object, MT_OBJECT);
    /* compositions are vectors over the same named materials, in the same order: otherwise
     * the operators would silently relabel one object's materials */
    const hv_material_table *ta = object_mats(L, 1), *tb = object_mats(L, 2);
    int na = hv_material_count(ta), nb = hv_material_count(tb);
    for (int j = 0; j < na && j < nb; ++j)
        if (strcmp(hv_material_name(ta, j), hv_material_name(tb, j)) != 0)
            return arg_error(L, 1, "material %d is '%s' here and '%s' in the other object: combine "
                             "objects made with the same materials", j + 1, hv_material_name(ta, j),
                             hv_material_name(tb, j));
    hv_object *o;
    hv_status s = hv_object_boolean(a->p, b->p, op, &o);
    if (s != HV_OK) return fail(L, s);
    lua_getiuservalue(L, 1, 1);
    push_object(L, o, lua_gettop(L));
    return 1;
}

static int object_intersect(lua_State *L) { return object_boolean(L, HV_OP_INTERSECT); }
static int object_union(lua_State *L) { return object_boolean(L, HV_OP_UNITE); }
static int object_difference(lua_State *L) { return object_boolean(L, HV_OP_DIFFERENCE); }
static int object_merge(lua_State *L) { return object_boolean(L, HV_OP_MERGE); }
static int object_subtract(lua_State *L) { return object_boolean(L, HV_OP_SUBTRACT); }

static int object_evaluate(lua_State *L)
{
    l_object *u = CHECK(L, 1, l_object, MT_OBJECT);
    uint64_t maxmem = 0;
    if (lua_istable(L, 2)) maxmem = (uint64_t)opt_number(L, 2, 2, "max_memory", 0);
    hv_material_table *t = object_mats(L, 1);
    hv_volume *v;
    hv_status s = hv_object_evaluate(u->p, t, maxmem, NULL, &v);
    if (s != HV_OK) return fail(L, s);
    push_model(L, v);
    return 1;
}

/* obj:render{...}, obj:export{...}, obj:layers{...}, obj:profile{...}, obj:probe(...),
 * obj:save(path): evaluate the object into a model (max_memory from the options table), call
 * the model's method of that name (upvalue 1) with the same arguments, and free the model. */
static int object_as_model(lua_State *L)
{
    CHECK(L, 1, l_object, MT_OBJECT);
    int base = lua_gettop(L);
    lua_pushcfunction(L, object_evaluate);
    lua_pushvalue(L, 1);
    if (base >= 2 && lua_istable(L, 2)) lua_pushvalue(L, 2);
    else lua_pushnil(L);
    lua_call(L, 2, 1); /* the model, at base + 1 */
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_pushvalue(L, base + 1);
    for (int i = 2; i <= base; ++i) lua_pushvalue(L, i);
    int rc = lua_pcall(L, base, LUA_MULTRET, 0);
    lua_pushcfunction(L, model_free);
    lua_pushvalue(L, base + 1);
    lua_call(L, 1, 0);
    if (rc == LUA_OK) return lua_gettop(L) - (base + 1);
    /* the method ran without a name or a script line of its own: give the error both, as
     * if the user had called it on the model ("#2" of the model call is "#1" of obj:name) */
    const char *msg = lua_tostring(L, -1), *name = lua_tostring(L, lua_upvalueindex(2));
    luaL_where(L, 1);
    const char *where = lua_tostring(L, -1);
    int n = 0, used = 0;
    if (msg && sscanf(msg, "bad argument #%d to '?'%n", &n, &used) == 1 && used > 0)
        lua_pushfstring(L, "%sbad argument #%d to '%s'%s", where, n - 1, name, msg + used);
    else if (msg && strncmp(msg, where, strlen(where)) != 0)
        lua_pushfstring(L, "%s%s", where, msg);
    else
        lua_pushvalue(L, -2);
    return lua_error(L);
}

static int object_regions(lua_State *L)
{
    l_object *u = CHECK(L, 1, l_object, MT_OBJECT);
    int n = hv_object_region_count(u->p);
    lua_createtable(L, n, 0);
    for (int r = 0; r < n; ++r) {
        lua_createtable(L, 0, 2);
        lua_pushinteger(L, (lua_Integer)hv_object_region_voxels(u->p, r));
        lua_setfield(L, -2, "voxels");
        lua_pushinteger(L, hv_object_region_ags_count(u->p, r));
        lua_setfield(L, -2, "sources");
        lua_rawseti(L, -2, r + 1);
    }
    return 1;
}

static int object_voxels(lua_State *L)
{
    l_object *u = CHECK(L, 1, l_object, MT_OBJECT);
    lua_pushinteger(L, (lua_Integer)hv_object_voxels(u->p));
    return 1;
}

static int object_gc(lua_State *L)
{
    l_object *u = luaL_checkudata(L, 1, MT_OBJECT);
    hv_object_destroy(u->p);
    u->p = NULL;
    return 0;
}

/* ---- shared with the other binding files ------------------------------------------------- */

hv_volume *hv_lua_model(lua_State *L, int arg) { return CHECK(L, arg, l_model, MT_MODEL)->p; }
hv_mesh *hv_lua_mesh(lua_State *L, int arg) { return CHECK(L, arg, l_mesh, MT_MESH)->p; }
void hv_lua_push_model(lua_State *L, hv_volume *vol) { push_model(L, vol); }
int hv_lua_fail(lua_State *L, hv_status status) { return fail(L, status); }

/* ---- module -------------------------------------------------------------------------------- */

static int l_set_threads(lua_State *L)
{
    lua_Integer n = luaL_checkinteger(L, 1);
    if (n < 0 || n > 1024) return arg_error(L, 1, "threads must be in [0, 1024], got %lld", (long long)n);
    hv_set_threads((int)n);
    return 0;
}

static void new_class(lua_State *L, const char *name, const luaL_Reg *methods, lua_CFunction gc, lua_CFunction tostring)
{
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
    lua_pushstring(L, name);
    lua_setfield(L, -2, "__name");
    lua_pop(L, 1);
}

/* Methods added by other modules (render, profile, contours, layers, export) register
 * themselves through these tables. */
const luaL_Reg *hv_lua_model_extra(void);
const luaL_Reg *hv_lua_module_extra(void);

int luaopen_hovox(lua_State *L)
{
    static const luaL_Reg mesh_m[] = {{"report", mesh_report}, {"save", mesh_save}, {"count", mesh_count},
                                      {"free", mesh_gc}, {NULL, NULL}};
    static const luaL_Reg model_m[] = {{"save", model_save},         {"grids", model_grids},
                                       {"voxels", model_voxels},     {"transform", model_transform},
                                       {"meta", model_meta},         {"probe", model_probe},
                                       {"contour", model_contour},   {"mask", model_mask},
                                       {"harmonic", model_harmonic}, {"free", model_free},
                                       {NULL, NULL}};
    static const luaL_Reg mats_m[] = {{"names", mats_names}, {"count", mats_count}, {"color", mats_color},
                                      {"property", mats_property}, {NULL, NULL}};
    static const luaL_Reg feat_m[] = {{"distance", feature_distance}, {NULL, NULL}};
    static const luaL_Reg src_m[] = {{"eval", source_eval}, {"ranges", source_ranges}, {"moved", source_moved},
                                     {NULL, NULL}};
    static const luaL_Reg obj_m[] = {{"add_ags", object_add_ags},     {"delete_ags", object_delete_ags},
                                     {"move_ags", object_move_ags},   {"set_blend", object_set_blend},
                                     {"set_base", object_set_base},   {"intersect", object_intersect},
                                     {"union", object_union},         {"difference", object_difference},
                                     {"merge", object_merge},         {"subtract", object_subtract},
                                     {"evaluate", object_evaluate},   {"regions", object_regions},
                                     {"voxels", object_voxels},       {"free", object_gc},
                                     {NULL, NULL}};
    new_class(L, MT_MESH, mesh_m, mesh_gc, mesh_tostring);
    new_class(L, MT_MODEL, model_m, model_free, model_tostring);
    new_class(L, MT_MATS, mats_m, mats_gc, NULL);
    new_class(L, MT_FEATURE, feat_m, feature_gc, feature_tostring);
    new_class(L, MT_SOURCE, src_m, source_gc, NULL);
    new_class(L, MT_OBJECT, obj_m, object_gc, NULL);
    /* methods from other modules */
    luaL_getmetatable(L, MT_MODEL);
    lua_getfield(L, -1, "__index");
    luaL_setfuncs(L, hv_lua_model_extra(), 0);
    /* the object gets the model's output methods, through an evaluation */
    static const char *const via_model[] = {"render", "export", "layers", "profile", "probe", "save"};
    luaL_getmetatable(L, MT_OBJECT);
    lua_getfield(L, -1, "__index");
    for (size_t i = 0; i < sizeof via_model / sizeof *via_model; ++i) {
        lua_getfield(L, -3, via_model[i]);
        lua_pushstring(L, via_model[i]);
        lua_pushcclosure(L, object_as_model, 2);
        lua_setfield(L, -2, via_model[i]);
    }
    lua_pop(L, 4);

    static const luaL_Reg gen[] = {{"sphere", g_sphere}, {"box", g_box},   {"torus", g_torus},
                                   {"cylinder", g_cylinder}, {"gear", g_gear}, {"knot", g_knot},
                                   {NULL, NULL}};
    static const luaL_Reg fns[] = {{"load_mesh", l_load_mesh}, {"voxelize", l_voxelize}, {"load", l_load},
                                   {"materials", l_materials}, {"axis", l_axis},         {"line", l_axis},
                                   {"plane", l_plane},         {"point", l_point},       {"segment", l_segment},
                                   {"facets", l_facets},       {"ags", l_ags},           {"wu3", l_wu3},           {"object", l_make_object},
                                   {"set_threads", l_set_threads}, {NULL, NULL}};
    luaL_newlib(L, fns);
    luaL_setfuncs(L, hv_lua_module_extra(), 0);
    luaL_newlib(L, gen);
    lua_setfield(L, -2, "generate");
    lua_pushstring(L, hv_version());
    lua_setfield(L, -2, "version");
    return 1;
}
