/* src/lua/ltray.c - Lua: print trays (hovox/tray.h). hovox.tray{<the options of `hovox tray`>}
 * makes a Tray; tray:add{<a part's keys: model, mesh, material, name, at, z, rotation,
 * copies>}, tray:arrange{...} and tray:layers{dir = ..., ...} (the tray's options again,
 * overriding those given before, key by key). Parts are files, as in job files. The options'
 * strings are private copies kept in the tray's user value, alive as long as the tray. */
#include <string.h>

#include <lauxlib.h>

#include "core/internal.h"
#include "hovox/tray.h"
#include "hovox/viewer.h"
#include "lhovox.h"

#define MT_TRAY "hovox.Tray"

typedef struct l_tray {
    hv_tray *p;
    hv_tray_options o;
} l_tray;

/* The tray's user value: the table holding its strings. */
static int keeper(lua_State *L, int self)
{
    lua_getiuservalue(L, self, 1);
    return lua_gettop(L);
}

/* Read the tray options of the table at `arg` on top of u->o: only the keys given change. */
static void read_over(lua_State *L, l_tray *u, int arg, const char *const *extra)
{
    if (lua_isnoneornil(L, arg)) return;
    int holder = keeper(L, 1);
    hv_tray_options fresh;
    hv_lua_read_options(L, arg, hv_tray_option_set(), &fresh, extra, holder);
    const hv_option_set *set = hv_tray_option_set();
    for (int i = 0; i < set->count; ++i) {
        const char *key = set->options[i].key;
        int given = hv_lua_field(L, arg, key) != LUA_TNIL;
        lua_pop(L, 1);
        if (!given) continue;
        if (set->options[i].kind != HV_OPT_CUSTOM) {
            hv_option_copy(set, key, &u->o, &fresh);
        } else if (strcmp(key, "resin") == 0) {
            for (int k = 0; k < fresh.nresin && u->o.nresin < HV_TRAY_MAX_RESINS; ++k) u->o.resin[u->o.nresin++] = fresh.resin[k];
        } else {
            for (int k = 0; k < fresh.ncolor && u->o.ncolor < HV_TRAY_MAX_RESINS; ++k)
                u->o.resin_color[u->o.ncolor++] = fresh.resin_color[k];
        }
    }
    lua_pop(L, 1);
}

static void push_report(lua_State *L, const hv_tray_report *r)
{
    lua_createtable(L, 0, 10);
    const struct { const char *k; double v; } f[] = {
        {"width", r->width},          {"height", r->height}, {"layers", (double)r->layers},
        {"first", (double)r->first},  {"last", (double)r->last}, {"parts", r->parts},
        {"resins", r->resins},        {"memory", (double)r->memory},
        {"object_pixels", (double)r->object_pixels}, {"bytes", (double)r->bytes}};
    for (size_t i = 0; i < HV_COUNT(f); ++i) {
        lua_pushinteger(L, (lua_Integer)f[i].v);
        lua_setfield(L, -2, f[i].k);
    }
    lua_pushnumber(L, r->utilisation);
    lua_setfield(L, -2, "utilisation");
    lua_pushstring(L, r->warnings); /* a part whose size suggests a wrong unit, one line each */
    lua_setfield(L, -2, "warnings");
}

/* hovox.tray{<tray options>} -> Tray */
static int l_tray_new(lua_State *L)
{
    lua_settop(L, 1); /* the options (or nil) */
    l_tray *u = hv_lua_new_ud(L, sizeof *u, MT_TRAY);
    hv_tray_options_init(&u->o);
    lua_newtable(L);
    lua_setiuservalue(L, 2, 1);
    lua_insert(L, 1); /* the tray at 1, the options at 2 */
    if (hv_tray_create(&u->p) != HV_OK) return fail(L, HV_ERR_NOMEM);
    read_over(L, u, 2, NULL);
    lua_settop(L, 1);
    return 1;
}

/* tray:add{model = "g.vdb", mesh = "g.stl", at = {x, y}, rotation = 90, copies = 2} or {mesh =
 * "a.3mf", materials = {core = "Agilus30Black"}, ...} -> parts */
static int tray_add(lua_State *L)
{
    luaL_checktype(L, 2, LUA_TTABLE);
    CHECK(L, 1, l_tray, MT_TRAY);
    int holder = keeper(L, 1);
    hv_tray_part p;
    hv_lua_read_options(L, 2, hv_tray_part_option_set(), &p, NULL, holder);
    l_tray *u = CHECK(L, 1, l_tray, MT_TRAY);
    hv_status s = hv_tray_add(u->p, &p, NULL);
    if (s != HV_OK) return luaL_argerror(L, 2, hv_last_error());
    lua_pushinteger(L, hv_tray_part_count(u->p));
    return 1;
}

/* tray:arrange{spacing = 5, ...}: place every part (arrange = "all" unless given) and check;
 * returns the plan's report. */
static int tray_arrange(lua_State *L)
{
    l_tray *u = CHECK(L, 1, l_tray, MT_TRAY);
    u->o.arrange = 2;
    read_over(L, u, 2, NULL);
    u = CHECK(L, 1, l_tray, MT_TRAY);
    hv_tray_report r;
    hv_status s = hv_tray_plan(u->p, &u->o, hv_lua_progress(L), &r);
    if (s != HV_OK) return fail(L, s);
    push_report(L, &r);
    return 1;
}

/* tray:layers{dir = "stack", <tray options>} -> report */
static int tray_layers(lua_State *L)
{
    static const char *const extra[] = {"dir", "view", NULL};
    l_tray *u = CHECK(L, 1, l_tray, MT_TRAY);
    luaL_checktype(L, 2, LUA_TTABLE);
    read_over(L, u, 2, extra);
    lua_getfield(L, 2, "view"); /* view = true: the tray's page, DIR/index.html (hovox view) */
    if (!lua_isnil(L, -1) && !lua_isboolean(L, -1)) return luaL_error(L, "view must be true or false");
    int view = lua_toboolean(L, -1);
    lua_pop(L, 1);
    int holder = keeper(L, 1);
    const char *dir = hv_lua_out_path(L, 2, "dir", holder, u->o.dry_run ? NULL : "the stack's directory");
    hv_lua_check_paths(L, 2, hv_tray_option_set(), &u->o); /* gcvf, stl: where they are used */
    u = CHECK(L, 1, l_tray, MT_TRAY);
    u->o.finish = view ? hv_viewer_stack_finish : NULL;
    hv_tray_report r;
    hv_status s = hv_tray_write(u->p, dir, &u->o, hv_lua_progress(L), &r);
    if (s != HV_OK) return fail(L, s);
    push_report(L, &r);
    return 1;
}

static void destroy_tray(void *p) { hv_tray_destroy(p); }
static int tray_gc(lua_State *L) { return hv_lua_release(L, destroy_tray, hv_lua_take(L, MT_TRAY)), 0; }

void hv_lua_open_tray(lua_State *L, int module)
{
    static const luaL_Reg methods[] = {{"add", tray_add}, {"arrange", tray_arrange}, {"layers", tray_layers},
                                       {"free", tray_gc}, {NULL, NULL}};
    hv_lua_new_class(L, MT_TRAY, methods, tray_gc, NULL);
    static const luaL_Reg fns[] = {{"tray", l_tray_new}, {NULL, NULL}};
    lua_pushvalue(L, module);
    hv_lua_set_funcs(L, fns);
    lua_pop(L, 1);
}
