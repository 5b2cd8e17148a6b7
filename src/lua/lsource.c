/* src/lua/lsource.c - Lua: material tables (hovox.materials), reference features (Wu 2.2:
 * hovox.point/axis/line/plane/segment with the keys of hv_frf_option_set, hovox.facets and
 * model:harmonic with hv_facet_select_option_set, model:contour/mask) and grading sources
 * (hovox.ags with hv_ags_option_set, hovox.wu3 with hv_wu3_option_set). A source's f may also
 * be a Lua function or a {kind = ...} table: those are tabulated once, by hv_ags_create, with
 * the function called under lua_pcall. Tables are read raw and strings copied (lopts.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lauxlib.h>

#include "core/internal.h"
#include "lhovox.h"

/* ---- material tables ------------------------------------------------------------------------ */

static int cmp_keys(const void *a, const void *b) { return strcmp(*(const char *const *)a, *(const char *const *)b); }

/* One material: a name, or {name = ..., color = "#rrggbb" | {r, g, b[, a]}, <property> = value |
 * {value, "unit"}, ...} (properties in SI units unless a unit is given). */
static void mats_add_one(lua_State *L, hv_material_table *t, int idx, int arg, int holder)
{
    idx = lua_absindex(L, idx);
    if (lua_type(L, idx) == LUA_TSTRING) {
        size_t len;
        const char *s = lua_tolstring(L, idx, &len);
        hv_status st = hv_material_add(t, hv_lua_copy_string(L, holder, s, len), NULL, NULL);
        if (st != HV_OK) fail(L, st);
        return;
    }
    if (!lua_istable(L, idx)) luaL_argerror(L, arg, "a material is a name or {name=..., color=..., ...}");
    hv_lua_check_plain_table(L, idx);
    const char *name = hv_lua_string_in(L, idx, arg, "material: ", "name", holder);
    if (!name) luaL_argerror(L, arg, "material needs a name");
    float rgba[4], *color = NULL;
    int ct = hv_lua_field(L, idx, "color");
    if (ct == LUA_TSTRING) {
        if (hv_color_parse(lua_tostring(L, -1), rgba) != HV_OK) luaL_argerror(L, arg, hv_last_error());
        color = rgba;
    } else if (ct != LUA_TNIL) {
        double c[4] = {0, 0, 0, 1};
        if (hv_lua_numbers(L, -1, arg, "color", c, 4) < 3) luaL_argerror(L, arg, "color must be {r, g, b[, a]} or '#rrggbb'");
        for (int k = 0; k < 4; ++k) rgba[k] = (float)c[k];
        color = rgba;
    }
    lua_pop(L, 1);
    int mi;
    hv_status s = hv_material_add(t, name, color, &mi);
    if (s != HV_OK) fail(L, s);
    /* the properties in key order: a Lua table has no order of its own (its traversal follows the
     * hash seed, which changes from run to run), and the model must not depend on it */
    int nk = 0;
    lua_pushnil(L);
    while (lua_next(L, idx)) {
        lua_pop(L, 1);
        nk += lua_type(L, -1) == LUA_TSTRING;
    }
    const char **keys = lua_newuserdatauv(L, (size_t)(nk ? nk : 1) * sizeof *keys, 0); /* the keys stay anchored by the table */
    nk = 0;
    lua_pushnil(L);
    while (lua_next(L, idx)) {
        lua_pop(L, 1);
        if (lua_type(L, -1) == LUA_TSTRING) keys[nk++] = lua_tostring(L, -1);
    }
    qsort(keys, (size_t)nk, sizeof *keys, cmp_keys);
    for (int ki = 0; ki < nk; ++ki) {
        const char *key = keys[ki];
        if (strcmp(key, "name") == 0 || strcmp(key, "color") == 0) continue;
        lua_pushstring(L, key);
        lua_rawget(L, idx);
        double value = 0;
        const char *unit = NULL;
        if (lua_type(L, -1) == LUA_TNUMBER) {
            value = lua_tonumber(L, -1);
            unit = hv_property_si_unit(key);
        } else if (lua_istable(L, -1) && lua_rawlen(L, -1) == 2 && lua_rawgeti(L, -1, 1) == LUA_TNUMBER &&
                   lua_rawgeti(L, -2, 2) == LUA_TSTRING) {
            value = lua_tonumber(L, -2);
            size_t len;
            const char *u = lua_tolstring(L, -1, &len);
            unit = hv_lua_copy_string(L, holder, u, len);
            lua_pop(L, 2);
        } else {
            arg_error(L, arg, "material '%s': %s must be a number or {value, \"unit\"} (a property; the colour is "
                      "'color'), got %s", name, key, luaL_typename(L, -1));
        }
        if ((s = hv_material_set_property(t, mi, key, value, unit)) != HV_OK) fail(L, s);
        lua_pop(L, 1);
    }
    lua_pop(L, 1); /* the keys */
}

static int l_materials(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TTABLE);
    int holder = hv_lua_options(L, 1);
    hv_material_table *t;
    if (hv_material_table_create(&t) != HV_OK) return fail(L, HV_ERR_NOMEM);
    l_mats *u = hv_lua_new_ud(L, sizeof *u, MT_MATS); /* owns t from here, so errors do not leak it */
    u->p = t;
    int n = (int)lua_rawlen(L, 1);
    if (n == 0) return luaL_argerror(L, 1, "give at least one material");
    for (int i = 1; i <= n; ++i) {
        lua_rawgeti(L, 1, i);
        mats_add_one(L, t, -1, 1, holder);
        lua_pop(L, 1);
    }
    return 1;
}

static int mats_names(lua_State *L)
{
    const hv_material_table *t = CHECK(L, 1, l_mats, MT_MATS)->p; /* kept alive while this runs */
    int n = hv_material_count(t);
    lua_createtable(L, n, 0);
    for (int j = 0; j < n; ++j) {
        lua_pushstring(L, hv_material_name(t, j));
        lua_rawseti(L, -2, j + 1);
    }
    return 1;
}

static int mats_count(lua_State *L)
{
    lua_pushinteger(L, hv_material_count(CHECK(L, 1, l_mats, MT_MATS)->p));
    return 1;
}

static int mats_find(lua_State *L, const hv_material_table *t)
{
    const char *name = luaL_checkstring(L, 2);
    int m = hv_material_find(t, name);
    if (m < 0) return arg_error(L, 2, "no material '%s'", name);
    return m;
}

static int mats_color(lua_State *L)
{
    const hv_material_table *t = CHECK(L, 1, l_mats, MT_MATS)->p;
    float c[4];
    hv_material_color(t, mats_find(L, t), c);
    double d[4] = {c[0], c[1], c[2], c[3]};
    hv_lua_push_vec(L, d, 4);
    return 1;
}

static int mats_property(lua_State *L)
{
    const hv_material_table *t = CHECK(L, 1, l_mats, MT_MATS)->p;
    int m = mats_find(L, t);
    double v;
    const char *unit;
    if (!hv_material_property(t, m, luaL_checkstring(L, 3), &v, &unit)) {
        lua_pushnil(L);
        return 1;
    }
    lua_pushnumber(L, v);
    lua_pushstring(L, unit);
    return 2;
}

static void destroy_mats(void *p) { hv_material_table_destroy(p); }
static int mats_gc(lua_State *L) { return hv_lua_release(L, destroy_mats, hv_lua_take(L, MT_MATS)), 0; }

/* ---- features ------------------------------------------------------------------------------- */

static int push_feature(lua_State *L, hv_status s, hv_frf *f)
{
    if (s != HV_OK) return fail(L, s);
    l_feature *u = hv_lua_new_ud(L, sizeof *u, MT_FEATURE);
    u->p = f;
    return 1;
}

/* hovox.point/axis/line/plane/segment{...}: upvalue 1 is the kind. hovox.point{x, y, z} also. */
static int l_feature_make(lua_State *L)
{
    hv_lua_enter(L, HV_LUA_FRAME());
    hv_frf_kind kind = (hv_frf_kind)lua_tointeger(L, lua_upvalueindex(1));
    hv_frf_options o;
    hv_frf *f = NULL;
    if (kind == HV_FRF_POINT && lua_istable(L, 1) && lua_rawlen(L, 1) == 3) {
        double p[3];
        hv_lua_numbers(L, 1, 1, "point", p, 3);
        hv_status s = hv_frf_point(p, &f);
        return push_feature(L, s, f);
    }
    luaL_checktype(L, 1, LUA_TTABLE);
    hv_lua_read(L, 1, hv_frf_option_set(kind), &o, NULL);
    hv_status s = hv_frf_from_options(&o, NULL, &f);
    return push_feature(L, s, f);
}

static void read_select(lua_State *L, int arg, hv_facet_select *sel, int holder)
{
    luaL_checktype(L, arg, LUA_TTABLE);
    hv_lua_read_options(L, arg, hv_facet_select_option_set(), sel, NULL, holder);
}

static int l_facets(lua_State *L)
{
    hv_mesh *m = hv_lua_mesh(L, 1);
    int holder = hv_lua_options(L, 2);
    hv_facet_select sel;
    read_select(L, 2, &sel, holder);
    m = hv_lua_mesh(L, 1); /* again: reading the options may have run a finalizer */
    hv_frf *f = NULL;
    hv_status s = hv_frf_facets(m, &sel, &f);
    return push_feature(L, s, f);
}

static int model_contour(lua_State *L)
{
    hv_volume *v = hv_lua_model(L, 1);
    hv_frf *f = NULL;
    hv_status s = hv_frf_contour(v, luaL_optstring(L, 2, "occupancy"), &f);
    return push_feature(L, s, f);
}

static int model_mask(lua_State *L)
{
    hv_volume *v = hv_lua_model(L, 1);
    hv_frf *f = NULL;
    hv_status s = hv_frf_mask(v, luaL_checkstring(L, 2), &f);
    return push_feature(L, s, f);
}

/* model:field{file = "s.vti", array = "sigma", outside = "refuse"|"nearest"}: a field feature
 * (hv_frf_option_set(HV_FRF_FIELD)) sampled at the model's voxels; returns the feature and
 * {lo, hi, file_lo, file_hi, voxels, filled} */
static int model_field(lua_State *L)
{
    hv_volume *v = hv_lua_model(L, 1);
    luaL_checktype(L, 2, LUA_TTABLE);
    hv_frf_options o;
    int holder = hv_lua_read(L, 2, hv_frf_option_set(HV_FRF_FIELD), &o, NULL);
    (void)holder;
    v = hv_lua_model(L, 1); /* again: reading the options may have run a finalizer */
    hv_frf *f = NULL;
    hv_status s = hv_frf_from_options(&o, v, &f);
    if (s != HV_OK) return fail(L, s);
    push_feature(L, s, f);
    hv_field_report r;
    hv_frf_field_report(f, &r);
    lua_createtable(L, 0, 6);
    lua_pushnumber(L, r.lo), lua_setfield(L, -2, "lo");
    lua_pushnumber(L, r.hi), lua_setfield(L, -2, "hi");
    lua_pushnumber(L, r.file_lo), lua_setfield(L, -2, "file_lo");
    lua_pushnumber(L, r.file_hi), lua_setfield(L, -2, "file_hi");
    lua_pushinteger(L, (lua_Integer)r.voxels), lua_setfield(L, -2, "voxels");
    lua_pushinteger(L, (lua_Integer)r.filled), lua_setfield(L, -2, "filled");
    return 2;
}

/* model:harmonic(mesh, one, zero[, domain]): one and zero are facet selections */
static int model_harmonic(lua_State *L)
{
    hv_volume *v = hv_lua_model(L, 1);
    hv_mesh *m = hv_lua_mesh(L, 2);
    int holder = hv_lua_options(L, 5);
    hv_facet_select one, zero;
    read_select(L, 3, &one, holder);
    read_select(L, 4, &zero, holder);
    const char *domain = luaL_optstring(L, 5, "occupancy");
    v = hv_lua_model(L, 1); /* again: reading the options may have run a finalizer */
    m = hv_lua_mesh(L, 2);
    hv_frf *f = NULL;
    hv_status s = hv_frf_harmonic(v, domain, m, &one, &zero, &f);
    return push_feature(L, s, f);
}

static int feature_distance(lua_State *L)
{
    hv_frf *feat = CHECK(L, 1, l_feature, MT_FEATURE)->p; /* kept alive while this runs */
    double p[3];
    if (hv_lua_numbers(L, 2, 2, "point", p, 3) != 3) return luaL_argerror(L, 2, "point must be {x, y, z}");
    hv_volume *lat = lua_isnoneornil(L, 3) ? NULL : hv_lua_model(L, 3);
    hv_frf_kind kind = hv_frf_get_kind(feat);
    if (!lat && kind != HV_FRF_HALFSPACE && kind >= HV_FRF_CONTOUR)
        return luaL_argerror(L, 3, "voxel features need the model whose lattice to use");
    double d;
    hv_status s = hv_frf_distance(feat, lat, p, &d);
    if (s != HV_OK) return fail(L, s);
    lua_pushnumber(L, d);
    return 1;
}

static void release_feature(void *p) { hv_frf_release(p); }
static int feature_gc(lua_State *L) { return hv_lua_release(L, release_feature, hv_lua_take(L, MT_FEATURE)), 0; }

static int feature_tostring(lua_State *L)
{
    l_feature *u = luaL_checkudata(L, 1, MT_FEATURE);
    lua_pushfstring(L, "hovox.Feature %s", u->p ? hv_frf_describe(u->p) : "(freed)");
    return 1;
}

/* ---- distribution functions ------------------------------------------------------------------ */

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
    }
    return ok ? v : NAN;
}

/* Field "points" of the table at idx: n {x, y} pairs, returned as x[0..n) then y[0..n) in a
 * userdata left on the stack (freed by Lua, even on errors); `what` names them in refusals. */
static double *read_pairs(lua_State *L, int idx, int arg, const char *what, int *n)
{
    int t = hv_lua_field(L, idx, "points");
    *n = (int)lua_rawlen(L, -1);
    if (t != LUA_TTABLE || *n < 2 || *n > 100000) arg_error(L, arg, "%s: points must be 2 to 100000 pairs", what);
    double *xy = lua_newuserdatauv(L, (size_t)*n * 2 * sizeof(double), 0);
    for (int i = 0; i < *n; ++i) {
        lua_rawgeti(L, -2, i + 1);
        double pt[2];
        if (!lua_istable(L, -1) || hv_lua_numbers(L, -1, arg, "point", pt, 2) != 2)
            arg_error(L, arg, "%s: points[%d] must be a pair of numbers", what, i + 1);
        xy[i] = pt[0];
        xy[*n + i] = pt[1];
        lua_pop(L, 1);
    }
    return xy;
}

/* f = {kind = ..., <its parameters> | points = {{d, f}, ...}} through hv_dfn_option_set */
static hv_status f_table(lua_State *L, int idx, int arg, int holder, hv_dfn **out)
{
    static const char *const extra[] = {"points", NULL};
    hv_dfn_options o;
    hv_lua_read_nested(L, idx, arg, hv_dfn_option_set(), &o, extra, holder);
    int pt = hv_lua_field(L, idx, "points");
    if ((pt != LUA_TNIL) != (o.kind == HV_DFN_TABLE))
        arg_error(L, arg, o.kind == HV_DFN_TABLE ? "f of kind table needs points = {{d, f}, ...}" : "only f of kind table takes points");
    lua_pop(L, 1);
    if (pt == LUA_TNIL) return hv_dfn_from_options(&o, out);
    int n;
    double *d = read_pairs(L, idx, arg, "f", &n);
    hv_status s = hv_dfn_table(d, d + n, n, out);
    lua_pop(L, 2);
    return s;
}

/* Field f of the table at arg, when it is not an expression (those the option set reads): a
 * number (constant), a function or a {kind = ...} table. Lua functions leave a registry
 * reference in ctx (released by the caller). */
static hv_dfn *read_f(lua_State *L, int arg, lua_fn_ctx *ctx, int holder)
{
    hv_dfn *out = NULL;
    hv_status s = HV_OK;
    switch (hv_lua_field(L, arg, "f")) {
    case LUA_TNIL: break;
    case LUA_TSTRING: {
        size_t len;
        const char *e = lua_tolstring(L, -1, &len);
        s = hv_dfn_expr(hv_lua_copy_string(L, holder, e, len), &out);
        break;
    }
    case LUA_TNUMBER: s = hv_dfn_linear(0, lua_tonumber(L, -1), &out); break;
    case LUA_TFUNCTION:
        lua_pushvalue(L, -1);
        ctx->L = L;
        ctx->ref = luaL_ref(L, LUA_REGISTRYINDEX);
        s = hv_dfn_function(lua_f, ctx, "lua function", &out);
        break;
    case LUA_TTABLE: s = f_table(L, lua_gettop(L), arg, holder, &out); break;
    default: arg_error(L, arg, "f must be an expression, a function or {kind=...}, got %s", luaL_typename(L, -1));
    }
    lua_pop(L, 1);
    if (s != HV_OK) luaL_argerror(L, arg, hv_last_error());
    return out;
}

/* ---- sources ------------------------------------------------------------------------------------ */

static int push_source(lua_State *L, hv_ags *a)
{
    l_source *u = hv_lua_new_ud(L, sizeof *u, MT_SOURCE);
    u->p = a;
    return 1;
}

static void release_calibration(void *p) { hv_calibration_release(p); }

static int calibration_box_gc(lua_State *L)
{
    hv_calibration **box = lua_touserdata(L, 1);
    if (box) {
        hv_lua_release(L, release_calibration, *box);
        *box = NULL;
    }
    return 0;
}

/* calibration = {property = "youngs_modulus", unit = "MPa", points = {{t, value}, ...}} (a file
 * name is read by the option set). Release with hv_calibration_release. */
static hv_calibration *calibration_table(lua_State *L, int idx, int arg, int holder)
{
    idx = lua_absindex(L, idx);
    if (lua_getmetatable(L, idx)) arg_error(L, arg, "calibration must be a plain table (one with a metatable is refused)");
    const char *prop = hv_lua_string_in(L, idx, arg, "calibration: ", "property", holder);
    const char *unit = hv_lua_string_in(L, idx, arg, "calibration: ", "unit", holder);
    if (!prop) luaL_argerror(L, arg, "calibration table needs property = \"<name>\"");
    int n;
    double *tv = read_pairs(L, idx, arg, "calibration", &n);
    hv_calibration *c = NULL;
    hv_status s = hv_calibration_create(prop, unit, tv, tv + n, n, &c);
    lua_pop(L, 2);
    if (s != HV_OK) luaL_argerror(L, arg, hv_last_error());
    return c;
}

/* A source from the table at `arg`: the keys of the set (wu3: hv_wu3_option_set, else
 * hv_ags_option_set), feature = a hovox feature, f and a calibration given as a table read
 * here. */
static hv_ags *source_from_table(lua_State *L, int arg, int wu3)
{
    static const char *const extra[] = {"feature", "f", NULL};
    static const char *const extra_cal[] = {"feature", "f", "calibration", NULL};
    luaL_checktype(L, arg, LUA_TTABLE);
    int holder = hv_lua_holder(L);
    hv_ags_options o;
    int cal_table = 0;
    if (!wu3) {
        cal_table = hv_lua_field(L, arg, "calibration") == LUA_TTABLE;
        lua_pop(L, 1);
    }
    hv_lua_read_options(L, arg, wu3 ? hv_wu3_option_set() : hv_ags_option_set(), &o, cal_table ? extra_cal : extra,
                        holder);
    if (cal_table) {
        /* the table is owned by a userdata on the stack (released by its __gc), so an error
         * below does not leak it; the source keeps its own reference */
        hv_calibration **box = lua_newuserdatauv(L, sizeof *box, 0);
        *box = NULL;
        lua_createtable(L, 0, 1);
        lua_pushcfunction(L, calibration_box_gc);
        lua_setfield(L, -2, "__gc");
        lua_setmetatable(L, -2);
        hv_lua_field(L, arg, "calibration");
        *box = calibration_table(L, -1, arg, holder);
        lua_pop(L, 1);
        o.calibration_table = *box;
    }
    hv_frf *feature = ((l_feature *)hv_lua_option_object(L, arg, "feature", MT_FEATURE,
                                                               "hovox feature (hovox.axis{...}, model:contour(), ...)"))->p;
    lua_fn_ctx ctx = {L, LUA_NOREF, 0, ""};
    hv_dfn *f = read_f(L, arg, &ctx, holder);
    hv_ags *a = NULL;
    hv_status s = wu3 ? hv_ags_wu3_from_options(feature, &o, f, &a) : hv_ags_from_options(feature, &o, f, &a);
    hv_dfn_destroy(f);
    if (ctx.ref != LUA_NOREF) luaL_unref(L, LUA_REGISTRYINDEX, ctx.ref);
    lua_pop(L, cal_table ? 3 : 2); /* the feature, the calibration's box, the holder */
    if (ctx.failed) arg_error(L, arg, "f failed: %s", ctx.msg);
    if (s != HV_OK) luaL_argerror(L, arg, hv_last_error());
    return a;
}

hv_ags *hv_lua_source_arg(lua_State *L, int arg) { return source_from_table(L, arg, 0); }
void hv_lua_push_source(lua_State *L, hv_ags *a) { push_source(L, a); }

static int l_ags(lua_State *L) { return push_source(L, source_from_table(L, 1, 0)); }
/* hovox.wu3{feature, d_neg, d_grad, d_pos, f, c}: Wu's 3-material distance-field paradigm
 * (eq. 13), P = [f, 1 - f - c, c] over the gradient range */
static int l_wu3(lua_State *L) { return push_source(L, source_from_table(L, 1, 1)); }

static int source_eval(lua_State *L)
{
    const hv_ags *a = CHECK(L, 1, l_source, MT_SOURCE)->p;
    double d = luaL_checknumber(L, 2), p[HV_MAX_MATERIALS];
    hv_ags_eval(a, d, p);
    hv_lua_push_vec(L, p, hv_ags_materials(a));
    return 1;
}

static int source_ranges(lua_State *L)
{
    l_source *u = CHECK(L, 1, l_source, MT_SOURCE);
    double r[3];
    hv_ags_ranges(u->p, &r[0], &r[1], &r[2]);
    for (int i = 0; i < 3; ++i) lua_pushnumber(L, r[i]);
    return 3;
}

static int source_moved(lua_State *L)
{
    const hv_ags *a = CHECK(L, 1, l_source, MT_SOURCE)->p;
    double d_neg = luaL_checknumber(L, 2);
    hv_ags *b;
    hv_status s = hv_ags_moved(a, d_neg, &b);
    if (s != HV_OK) return fail(L, s);
    return push_source(L, b);
}

static void release_source(void *p) { hv_ags_release(p); }
static int source_gc(lua_State *L) { return hv_lua_release(L, release_source, hv_lua_take(L, MT_SOURCE)), 0; }

void hv_lua_open_sources(lua_State *L, int module)
{
    static const luaL_Reg mats_m[] = {{"names", mats_names}, {"count", mats_count}, {"color", mats_color},
                                      {"property", mats_property}, {NULL, NULL}};
    static const luaL_Reg feat_m[] = {{"distance", feature_distance}, {NULL, NULL}};
    static const luaL_Reg src_m[] = {{"eval", source_eval}, {"ranges", source_ranges}, {"moved", source_moved},
                                     {NULL, NULL}};
    static const luaL_Reg model_m[] = {{"contour", model_contour}, {"mask", model_mask}, {"field", model_field},
                                       {"harmonic", model_harmonic}, {NULL, NULL}};
    static const luaL_Reg fns[] = {{"materials", l_materials}, {"facets", l_facets}, {"ags", l_ags},
                                   {"wu3", l_wu3}, {NULL, NULL}};
    hv_lua_new_class(L, MT_MATS, mats_m, mats_gc, NULL);
    hv_lua_new_class(L, MT_FEATURE, feat_m, feature_gc, feature_tostring);
    hv_lua_new_class(L, MT_SOURCE, src_m, source_gc, NULL);
    hv_lua_add_methods(L, MT_MODEL, model_m);
    lua_pushvalue(L, module);
    hv_lua_set_funcs(L, fns);
    lua_pop(L, 1);
    static const struct { const char *name; hv_frf_kind kind; } kinds[] = {
        {"point", HV_FRF_POINT}, {"axis", HV_FRF_LINE}, {"line", HV_FRF_LINE}, {"plane", HV_FRF_PLANE},
        {"halfspace", HV_FRF_HALFSPACE}, {"segment", HV_FRF_SEGMENT}};
    for (size_t i = 0; i < HV_COUNT(kinds); ++i) {
        lua_pushinteger(L, kinds[i].kind);
        lua_pushcclosure(L, l_feature_make, 1);
        lua_setfield(L, module, kinds[i].name);
    }
}
