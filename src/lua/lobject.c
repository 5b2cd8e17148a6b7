/* src/lua/lobject.c - Lua: heterogeneous objects (Wu 2.2): hovox.object(model, materials),
 * grading sources added, moved and deleted, blending, the base composition, the Boolean
 * operators, evaluation into a model, and the model's outputs through an evaluation. */
#include <stdio.h>
#include <string.h>

#include <lauxlib.h>

#include "core/internal.h"
#include "lhovox.h"

static l_object *push_object(lua_State *L, hv_object *o, int mats_index)
{
    l_object *u = hv_lua_new_ud(L, sizeof *u, MT_OBJECT);
    u->p = o;
    lua_pushvalue(L, mats_index); /* keep the material table alive with the object */
    lua_setiuservalue(L, -2, 1);
    return u;
}

/* hovox.object(model[, mats][, {grid = "occupancy"}]): a model voxelized from an assembly gives one
 * region per body (hv_object_from_regions; mats, when given, must name the bodies' materials,
 * else the table is built from them); any other model, or a grid named, one region (mats
 * required). */
static int l_make_object(lua_State *L)
{
    CHECK(L, 1, l_model, MT_MODEL);
    int have_mats = luaL_testudata(L, 2, MT_MATS) != NULL, opt = have_mats ? 3 : 2;
    if (!have_mats && !lua_isnoneornil(L, 2) && !lua_istable(L, 2))
        return luaL_typeerror(L, 2, "hovox materials or an options table");
    if (have_mats) CHECK(L, 2, l_mats, MT_MATS);
    const char *grid = NULL;
    if (!lua_isnoneornil(L, opt)) {
        int holder = hv_lua_options(L, opt);
        hv_lua_check_plain_table(L, opt);
        lua_pushnil(L);
        if (lua_next(L, opt) && (lua_type(L, -2) != LUA_TSTRING || strcmp(lua_tostring(L, -2), "grid") != 0))
            return arg_error(L, opt, "unknown option '%s' (options: grid)", luaL_tolstring(L, -2, NULL));
        lua_settop(L, holder);
        grid = hv_lua_string_field(L, opt, "grid", holder);
    }
    /* the userdata first, so an allocation failure leaks nothing the library made */
    l_object *u = hv_lua_new_ud(L, sizeof *u, MT_OBJECT);
    int ou = lua_gettop(L);
    l_mats *t = hv_lua_new_ud(L, sizeof *t, MT_MATS);
    l_model *m = CHECK(L, 1, l_model, MT_MODEL); /* again: reading the options may have run a finalizer */
    const hv_material_table *given = have_mats ? CHECK(L, 2, l_mats, MT_MATS)->p : NULL;
    hv_status s = HV_ERR_NOT_FOUND;
    if (!grid) s = hv_object_from_regions(m->p, given, &t->p, &u->p);
    if (s == HV_ERR_NOT_FOUND) {
        if (!given)
            return luaL_argerror(L, 2, "materials are required (the model has no regions with materials: it was not "
                                       "voxelized from an assembly)");
        s = hv_object_create(m->p, grid ? grid : "occupancy", hv_material_count(given), &u->p);
    }
    if (s != HV_OK) return fail(L, s);
    if (!t->p) lua_pushvalue(L, 2); /* the materials given (from_regions copied them when it ran) */
    lua_setiuservalue(L, ou, 1);    /* keep the material table alive with the object */
    lua_settop(L, ou);
    return 1;
}

/* The object's material table (its user value), which the script may have freed (obj:materials()
 * closed as a to-be-closed variable). */
static hv_material_table *object_mats(lua_State *L, int idx)
{
    lua_getiuservalue(L, idx, 1);
    l_mats *t = luaL_checkudata(L, -1, MT_MATS);
    lua_pop(L, 1);
    if (!t->p) luaL_argerror(L, idx, "the object's materials were freed");
    return t->p;
}

/* obj:add_ags(src or {...}[, region]): to every region, or to the region of that name alone */
static int object_add_ags(lua_State *L)
{
    l_object *u = CHECK(L, 1, l_object, MT_OBJECT);
    const char *region = luaL_optstring(L, 3, NULL); /* anchored at 3 while C uses it */
    hv_ags *a;
    if (luaL_testudata(L, 2, MT_SOURCE)) {
        a = hv_ags_retain(CHECK(L, 2, l_source, MT_SOURCE)->p);
        lua_pushvalue(L, 2);
    } else {
        a = hv_lua_source_arg(L, 2);
        hv_lua_push_source(L, hv_ags_retain(a));
    }
    /* again: f ran script code, which may have freed the object (obj:free() in f) */
    u = luaL_checkudata(L, 1, MT_OBJECT);
    if (!u->p) {
        hv_ags_release(a);
        return luaL_argerror(L, 1, "object was freed");
    }
    hv_status s = region ? hv_object_add_ags_region(u->p, region, a) : hv_object_add_ags(u->p, a);
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

/* obj:move_ags(src, d_neg) -> the moved source, which takes src's place in the object (so
 * obj:delete_ags(moved) and obj:move_ags(moved, ...) reach it; src is no longer in it) */
static int object_move_ags(lua_State *L)
{
    hv_object *o = CHECK(L, 1, l_object, MT_OBJECT)->p; /* kept alive while this runs */
    const hv_ags *a = CHECK(L, 2, l_source, MT_SOURCE)->p;
    double d_neg = luaL_checknumber(L, 3);
    hv_lua_push_source(L, NULL); /* the userdata first: an allocation failure leaks nothing */
    l_source *moved = lua_touserdata(L, -1);
    hv_status s = hv_ags_moved(a, d_neg, &moved->p);
    if (s == HV_OK) s = hv_object_replace_ags(o, a, moved->p);
    return s != HV_OK ? fail(L, s) : 1;
}

static int object_set_blend(lua_State *L)
{
    l_object *u = CHECK(L, 1, l_object, MT_OBJECT);
    hv_blend b;
    if (hv_blend_parse(luaL_checkstring(L, 2), &b) != HV_OK) return luaL_argerror(L, 2, hv_last_error());
    double power = luaL_optnumber(L, 3, 2);
    u = CHECK(L, 1, l_object, MT_OBJECT); /* again, after the conversions */
    hv_status s = hv_object_set_blend(u->p, b, power);
    return s != HV_OK ? fail(L, s) : 0;
}

/* obj:set_base(p[, region]): the base of every region, or of the region of that name */
static int object_set_base(lua_State *L)
{
    l_object *u = CHECK(L, 1, l_object, MT_OBJECT);
    double p[HV_MAX_MATERIALS];
    int n = hv_lua_numbers(L, 2, 2, "base", p, HV_MAX_MATERIALS);
    const char *region = luaL_optstring(L, 3, NULL);
    u = CHECK(L, 1, l_object, MT_OBJECT); /* again, after the conversions */
    if (n != hv_object_materials(u->p))
        return arg_error(L, 2, "base has %d values for %d materials", n, hv_object_materials(u->p));
    if (hv_composition_check(p, n, "base") != HV_OK) return luaL_argerror(L, 2, hv_last_error());
    int r = region ? hv_object_region_find(u->p, region) : -1;
    if (region && r < 0) return arg_error(L, 3, "the object has no region '%s'", region);
    hv_status s = region ? hv_object_set_region_base(u->p, r, p) : hv_object_set_base(u->p, p);
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
    hv_object *obj = CHECK(L, 1, l_object, MT_OBJECT)->p; /* kept alive while this runs */
    uint64_t maxmem = 0;
    if (lua_istable(L, 2) && hv_lua_field(L, 2, "max_memory") != LUA_TNIL) {
        /* the output's own options table: only max_memory is the evaluation's, read by its option */
        hv_lua_check_plain_table(L, 2);
        static const hv_option mm = {.key = "max_memory", .kind = HV_OPT_BYTES};
        hv_opt_value v = {HV_VALUE_NUMBERS, NULL, NULL, 0, 0};
        double num = lua_tonumber(L, -1);
        v.numbers = &num;
        v.n = 1;
        if (lua_type(L, -1) == LUA_TSTRING) {
            v.type = HV_VALUE_TEXT;
            v.text = lua_tostring(L, -1);
        }
        if (hv_option_set_value(&mm, &maxmem, &v) != HV_OK) return luaL_argerror(L, 2, hv_last_error());
        lua_pop(L, 1);
    }
    hv_material_table *t = object_mats(L, 1);
    hv_volume *v;
    hv_status s = hv_object_evaluate(obj, t, maxmem, hv_lua_progress(L), &v);
    if (s != HV_OK) return fail(L, s);
    hv_lua_push_model(L, v);
    return 1;
}

/* obj:render{...}, obj:export{...}, obj:layers{...}, obj:profile{...}, obj:probe(...),
 * obj:save(path): evaluate the object into a model (max_memory from the options table), call
 * the model's method of that name (upvalue 1) with the same arguments, and free the model. */
static int object_as_model(lua_State *L)
{
    hv_lua_enter(L, HV_LUA_FRAME());
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
    lua_pushcfunction(L, hv_lua_model_free);
    lua_pushvalue(L, base + 1);
    lua_call(L, 1, 0);
    if (rc == LUA_OK) return lua_gettop(L) - (base + 1);
    /* the method ran without a script line of its own, under the model's name: give the error
     * the object's, as if the user had called it on the model ("#2" of the model call is "#1"
     * of obj:name) */
    const char *msg = lua_tostring(L, -1), *name = lua_tostring(L, lua_upvalueindex(2));
    hv_status failed = hv_lua_failure_status(L, msg);
    luaL_where(L, 1);
    const char *where = lua_tostring(L, -1);
    int n = 0, used = 0;
    if (msg && sscanf(msg, "bad argument #%d to '%*[^']'%n", &n, &used) == 1 && used > 0)
        lua_pushfstring(L, "%sbad argument #%d to '%s'%s", where, n - 1, name, msg + used);
    else if (msg && strncmp(msg, where, strlen(where)) != 0)
        lua_pushfstring(L, "%s%s", where, msg);
    else
        lua_pushvalue(L, -2);
    if (failed != HV_OK) hv_lua_note_failure(L, failed, lua_tostring(L, -1));
    return lua_error(L);
}

static int object_regions(lua_State *L)
{
    const hv_object *obj = CHECK(L, 1, l_object, MT_OBJECT)->p; /* kept alive while this runs */
    int n = hv_object_region_count(obj);
    lua_createtable(L, n, 0);
    double base[HV_MAX_MATERIALS];
    for (int r = 0; r < n; ++r) {
        lua_createtable(L, 0, 4);
        lua_pushinteger(L, (lua_Integer)hv_object_region_voxels(obj, r));
        lua_setfield(L, -2, "voxels");
        lua_pushinteger(L, hv_object_region_ags_count(obj, r));
        lua_setfield(L, -2, "sources");
        if (hv_object_region_name(obj, r)) {
            lua_pushstring(L, hv_object_region_name(obj, r));
            lua_setfield(L, -2, "name");
        }
        hv_object_region_base(obj, r, base);
        hv_lua_push_vec(L, base, hv_object_materials(obj));
        lua_setfield(L, -2, "base");
        lua_rawseti(L, -2, r + 1);
    }
    return 1;
}

/* obj:materials() -> the object's Materials (given to hovox.object or built from the bodies) */
static int object_materials(lua_State *L)
{
    CHECK(L, 1, l_object, MT_OBJECT);
    lua_getiuservalue(L, 1, 1);
    return 1;
}

static int object_voxels(lua_State *L)
{
    lua_pushinteger(L, (lua_Integer)hv_object_voxels(CHECK(L, 1, l_object, MT_OBJECT)->p));
    return 1;
}

static void destroy_object(void *p) { hv_object_destroy(p); }
static int object_gc(lua_State *L) { return hv_lua_release(L, destroy_object, hv_lua_take(L, MT_OBJECT)), 0; }

void hv_lua_open_object(lua_State *L, int module)
{
    static const luaL_Reg methods[] = {{"add_ags", object_add_ags},     {"delete_ags", object_delete_ags},
                                       {"move_ags", object_move_ags},   {"set_blend", object_set_blend},
                                       {"set_base", object_set_base},   {"intersect", object_intersect},
                                       {"union", object_union},         {"difference", object_difference},
                                       {"merge", object_merge},         {"subtract", object_subtract},
                                       {"evaluate", object_evaluate},   {"regions", object_regions},
                                       {"voxels", object_voxels},       {"materials", object_materials},
                                       {"free", object_gc},
                                       {NULL, NULL}};
    hv_lua_new_class(L, MT_OBJECT, methods, object_gc, NULL);
    /* the object gets the model's output methods, through an evaluation */
    static const char *const via_model[] = {"render", "export", "layers", "profile", "probe", "save"};
    luaL_getmetatable(L, MT_MODEL);
    lua_getfield(L, -1, "__index");
    luaL_getmetatable(L, MT_OBJECT);
    lua_getfield(L, -1, "__index");
    for (size_t i = 0; i < HV_COUNT(via_model); ++i) {
        lua_getfield(L, -3, via_model[i]);
        lua_pushstring(L, via_model[i]);
        lua_pushcclosure(L, object_as_model, 2);
        lua_setfield(L, -2, via_model[i]);
    }
    lua_pop(L, 4);
    static const luaL_Reg fns[] = {{"object", l_make_object}, {NULL, NULL}};
    lua_pushvalue(L, module);
    hv_lua_set_funcs(L, fns);
    lua_pop(L, 1);
}
