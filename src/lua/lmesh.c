/* src/lua/lmesh.c - Lua: the Mesh class (STL in and out, the mesh report), the parametric
 * generators (hovox.generate.SHAPE{...}, the keys of hv_shape_option_set, as `hovox generate
 * SHAPE key=value`) and contour slicing (hovox.contours, the options of `hovox contours`). */
#include <math.h>
#include <string.h>

#include <lauxlib.h>

#include "core/internal.h"
#include "hovox/generate.h"
#include "hovox/layers.h"
#include "hovox/placement.h"
#include "hovox/viewer.h"
#include "hovox/slice.h"
#include "lhovox.h"
#include "mesh/mesh_internal.h"

void hv_lua_push_mesh(lua_State *L, hv_mesh *m)
{
    l_mesh *u = hv_lua_new_ud(L, sizeof *u, MT_MESH);
    u->p = m;
}

hv_mesh *hv_lua_mesh(lua_State *L, int arg) { return CHECK(L, arg, l_mesh, MT_MESH)->p; }

static int l_load_mesh(lua_State *L)
{
    const char *path = luaL_checkstring(L, 1);
    hv_mesh *m;
    hv_status s = hv_mesh_load(path, &m);
    if (s != HV_OK) return fail(L, s);
    hv_lua_push_mesh(L, m);
    return 1;
}

/* mesh:transform{unit = "m", up = "y", scale = S | {SX, SY, SZ}, rotate = "x:90" | {"x:90",
 *   "30@1,1,0", ...}, translate = {X, Y, Z}} -> a new Mesh, placed as `hovox voxelize --unit ...`
 *   places it (hovox/placement.h; the same order whatever the keys' order) */
static int mesh_transform(lua_State *L)
{
    hv_lua_mesh(L, 1);
    hv_placement p;
    hv_lua_read(L, 2, hv_placement_option_set(), &p, NULL);
    hv_mesh *out = NULL;
    hv_status s = hv_placement_transform(&p, hv_lua_mesh(L, 1), &out); /* again: reading the options may have run a finalizer */
    if (s != HV_OK) return fail(L, s);
    hv_lua_push_mesh(L, out);
    return 1;
}

/* mesh:set_material(body, material) -> the mesh: the body's material, whatever the file said
 * (hv_mesh_body_material_set; `hovox voxelize --material BODY=MATERIAL`) */
static int mesh_set_material(lua_State *L)
{
    const char *body = luaL_checkstring(L, 2), *material = luaL_checkstring(L, 3);
    hv_status s = hv_mesh_body_material_set(hv_lua_mesh(L, 1), body, material); /* the mesh after the strings */
    if (s != HV_OK) return fail(L, s);
    lua_settop(L, 1);
    return 1;
}

/* mesh:set_colour(body, colour) -> the mesh: the body in one colour ("#rrggbb", "#rrggbbaa",
 * "r,g,b[,a]"), whatever its texture or file colours said (hv_mesh_body_colour_set; `hovox
 * voxelize --colour BODY=COLOUR`) */
static int mesh_set_colour(lua_State *L)
{
    const char *body = luaL_checkstring(L, 2), *text = luaL_checkstring(L, 3);
    float f[4];
    if (hv_color_parse(text, f) != HV_OK) return arg_error(L, 3, "%s", hv_last_error());
    uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v = v << 8 | (uint32_t)lrintf(f[k] * 255.0f);
    hv_status s = hv_mesh_body_colour_set(hv_lua_mesh(L, 1), body, v); /* the mesh after the strings */
    if (s != HV_OK) return fail(L, s);
    lua_settop(L, 1);
    return 1;
}

/* mesh:layers{dir = "stack", materials = {BODY = "MATERIAL"}, voxel_size = MM, colour_depth = MM,
 *   core = RESIN|COLOUR, icc = FILE, intent = NAME, resins = "C,M,Y,K,W,CLEAR", view = true, <the
 *   options of `hovox layers`: profile, layer_height, mode, halftone, seed, layers = {first, last},
 *   max_memory, ...>} -> the report of model:layers (hv_lua_push_layers_report: its materials,
 *   and colour = {skin_voxels, mean_de2000_target, max_de2000_target, mean_de2000_achieved} when painted): the
 *   mesh printed in one step, its bodies in their materials or painted in its colours, as `hovox
 *   layers PART.3mf -o DIR [--material BODY=MATERIAL | --colour-depth MM --core ...]` prints it,
 *   the same bytes (hv_layers_write_mesh); warnings begin with the size warning (a mesh under 1 mm
 *   or larger than the printer, naming the likely unit) */
static int mesh_layers(lua_State *L)
{
    const hv_option_set *ls = hv_layers_option_set(), *ms = hv_layers_mesh_option_set();
    const char *own[40]; /* the step's keys, read by the second read */
    int k = 0;
    own[k++] = "dir";
    own[k++] = "view";
    for (int i = 0; i < ms->count && k < 39; ++i) own[k++] = ms->options[i].key;
    own[k] = NULL;
    hv_lua_mesh(L, 1);
    hv_layers_options o;
    int holder = hv_lua_read(L, 2, ls, &o, own);
    const char *theirs[160]; /* the layers' keys, read above: known to the second read */
    int n = 0;
    for (int i = 0; i < ls->count && n < 150; ++i) theirs[n++] = ls->options[i].key;
    for (int i = 0; i < ls->alias_count && n < 150; ++i) theirs[n++] = ls->aliases[i].name;
    theirs[n++] = "dir";
    theirs[n++] = "view";
    theirs[n] = NULL;
    hv_layers_mesh_options mo;
    hv_lua_read_options(L, 2, ms, &mo, theirs, holder);
    const char *dir = hv_lua_out_path(L, 2, "dir", holder, "the stack's directory");
    lua_getfield(L, 2, "view"); /* view = true: the stack's page, DIR/index.html (hovox view) */
    if (!lua_isnil(L, -1) && !lua_isboolean(L, -1)) return luaL_error(L, "view must be true or false");
    if (lua_toboolean(L, -1)) o.finish = hv_viewer_stack_finish;
    lua_pop(L, 1);
    hv_lua_check_paths(L, 2, ls, &o); /* gcvf: where it is used */
    hv_mesh *mesh = hv_lua_mesh(L, 1); /* again: reading the options may have run a finalizer */
    hv_layers_report rep;
    hv_colour_skin skin;
    hv_material_table *t = NULL;
    hv_status s = hv_layers_write_mesh(mesh, &mo, dir, &o, hv_lua_progress(L), &rep, &skin, &t);
    int coloured = skin.map != NULL;
    hv_colour_map_destroy(skin.map);
    if (s != HV_OK) return fail(L, s);
    hv_lua_push_layers_report(L, &rep, t, coloured ? &skin : NULL); /* skin: its figures only */
    hv_material_table_destroy(t);
    return 1;
}

static void push_report(lua_State *L, const hv_mesh_report *r)
{
    lua_createtable(L, 0, 14);
    lua_pushstring(L, hv_mesh_format_key(r->format)); /* as in `hovox info --json` */
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
    hv_lua_push_vec(L, r->bbox_min, 3);
    lua_setfield(L, -2, "min");
    hv_lua_push_vec(L, r->bbox_max, 3);
    lua_setfield(L, -2, "max");
    lua_setfield(L, -2, "bbox");
    lua_pushboolean(L, r->open_edges == 0 && r->nonmanifold_edges == 0);
    lua_setfield(L, -2, "closed");
}

static int mesh_report(lua_State *L)
{
    push_report(L, hv_mesh_get_report(hv_lua_mesh(L, 1))); /* the mesh lives while this runs */
    return 1;
}

/* mesh:bodies(): { {name, material (a name, or nil), facets, first (counting from 1)}, ... } */
static int mesh_bodies(lua_State *L)
{
    const hv_mesh *m = CHECK(L, 1, l_mesh, MT_MESH)->p;
    size_t n = hv_mesh_body_count(m);
    lua_createtable(L, (int)n, 0);
    for (size_t i = 0; i < n; ++i) {
        const hv_mesh_body *b = hv_mesh_body_at(m, i);
        lua_createtable(L, 0, 4);
        lua_pushstring(L, b->name);
        lua_setfield(L, -2, "name");
        if (b->material >= 0) {
            lua_pushstring(L, hv_mesh_material_at(m, (size_t)b->material)->name);
            lua_setfield(L, -2, "material");
        }
        lua_pushinteger(L, (lua_Integer)b->facet_count);
        lua_setfield(L, -2, "facets");
        lua_pushinteger(L, (lua_Integer)b->first_facet + 1);
        lua_setfield(L, -2, "first");
        lua_rawseti(L, -2, (lua_Integer)i + 1);
    }
    return 1;
}

/* mesh:materials(): { {name, color = {r, g, b, a} (0 to 1) or nil}, ... } */
static int mesh_materials(lua_State *L)
{
    const hv_mesh *m = CHECK(L, 1, l_mesh, MT_MESH)->p;
    size_t n = hv_mesh_material_count(m);
    lua_createtable(L, (int)n, 0);
    for (size_t i = 0; i < n; ++i) {
        const hv_mesh_material *mt = hv_mesh_material_at(m, i);
        lua_createtable(L, 0, 2);
        lua_pushstring(L, mt->name);
        lua_setfield(L, -2, "name");
        if (mt->has_color) {
            double c[4];
            for (int k = 0; k < 4; ++k) c[k] = (double)((mt->rgba >> (24 - 8 * k)) & 0xFF) / 255.0;
            hv_lua_push_vec(L, c, 4);
            lua_setfield(L, -2, "color");
        }
        lua_rawseti(L, -2, (lua_Integer)i + 1);
    }
    return 1;
}

static int mesh_save(lua_State *L)
{
    l_mesh *u = CHECK(L, 1, l_mesh, MT_MESH);
    const char *path = hv_lua_check_write(L, 2, NULL, luaL_checkstring(L, 2));
    int ascii = 0;
    if (!lua_isnoneornil(L, 3)) {
        hv_lua_check_plain_table(L, 3);
        if (hv_lua_field(L, 3, "ascii") != LUA_TNIL) ascii = lua_toboolean(L, -1);
        lua_pop(L, 1);
        lua_pushnil(L);
        if (lua_next(L, 3) && (lua_type(L, -2) != LUA_TSTRING || strcmp(lua_tostring(L, -2), "ascii") != 0))
            return arg_error(L, 3, "unknown option '%s' (options: ascii)", luaL_tolstring(L, -2, NULL));
    }
    u = CHECK(L, 1, l_mesh, MT_MESH); /* again: reading the options may have run a finalizer */
    hv_status s = hv_mesh_save(u->p, path, ascii); /* .obj keeps the bodies */
    return s != HV_OK ? fail(L, s) : 0;
}

static int mesh_count(lua_State *L)
{
    const hv_mesh *m = hv_lua_mesh(L, 1);
    lua_pushinteger(L, (lua_Integer)hv_mesh_facet_count(m));
    lua_pushinteger(L, (lua_Integer)hv_mesh_vertex_count(m));
    return 2;
}

static void destroy_mesh(void *p) { hv_mesh_destroy(p); }
static int mesh_gc(lua_State *L) { return hv_lua_release(L, destroy_mesh, hv_lua_take(L, MT_MESH)), 0; }

static int mesh_tostring(lua_State *L)
{
    l_mesh *u = luaL_checkudata(L, 1, MT_MESH);
    if (!u->p) lua_pushliteral(L, "hovox.Mesh (freed)");
    else lua_pushfstring(L, "hovox.Mesh (%d facets)", (int)hv_mesh_facet_count(u->p));
    return 1;
}

/* ---- generators ---------------------------------------------------------------------------- */

/* hovox.generate.SHAPE{key = value, ...}; upvalue 1: the shape's index */
static int l_generate(lua_State *L)
{
    hv_lua_enter(L, HV_LUA_FRAME());
    int shape = (int)lua_tointeger(L, lua_upvalueindex(1));
    hv_shape_params p;
    hv_lua_read(L, 1, hv_shape_option_set(shape), &p, NULL);
    hv_mesh *m;
    hv_status s = hv_generate_shape(shape, &p, &m);
    if (s != HV_OK) return fail(L, s);
    hv_lua_push_mesh(L, m);
    return 1;
}

/* ---- contours ------------------------------------------------------------------------------ */

typedef struct contour_run {
    lua_State *L;
    int keep_loops;
    int table; /* stack index of the result list */
    const hv_mesh *mesh;
} contour_run;

static void push_loops(lua_State *L, const hv_slice *slice, const hv_mesh *mesh)
{
    size_t n = hv_slice_loop_count(slice);
    const hv_slice_loop *loops = hv_slice_loops(slice);
    lua_createtable(L, (int)n, 0);
    for (size_t i = 0; i < n; ++i) {
        const hv_slice_loop *lp = &loops[i];
        lua_createtable(L, 0, 6);
        lua_createtable(L, (int)lp->count, 0);
        for (size_t k = 0; k < lp->count; ++k) {
            hv_lua_push_vec(L, lp->xy + 2 * k, 2);
            lua_rawseti(L, -2, (lua_Integer)k + 1);
        }
        lua_setfield(L, -2, "points");
        lua_pushboolean(L, lp->closed);
        lua_setfield(L, -2, "closed");
        lua_pushinteger(L, lp->orientation);
        lua_setfield(L, -2, "orientation");
        lua_pushinteger(L, lp->parent >= 0 ? lp->parent + 1 : 0);
        lua_setfield(L, -2, "parent");
        lua_pushnumber(L, lp->area);
        lua_setfield(L, -2, "area");
        const hv_mesh_body *b = hv_mesh_body_at(mesh, (size_t)lp->body);
        lua_pushstring(L, b ? b->name : "");
        lua_setfield(L, -2, "body");
        lua_rawseti(L, -2, (lua_Integer)i + 1);
    }
}

typedef struct layer_args {
    contour_run *run;
    size_t index;
    const hv_layer *layer;
    const hv_slice *slice;
} layer_args;

/* Builds one layer's table; runs under lua_pcall, so a failed allocation (the script's memory
 * limit) returns to contour_layer instead of unwinding through the library's frames. */
static int push_layer(lua_State *L)
{
    const layer_args *a = lua_touserdata(L, 1);
    const hv_slice_stats *st = hv_slice_get_stats(a->slice);
    lua_createtable(L, 0, 9);
    const struct { const char *k; double v; } f[] = {{"z", a->layer->z}, {"bottom", a->layer->bottom},
                                                     {"top", a->layer->top}, {"area", st->area},
                                                     {"loops", (double)st->loops}, {"holes", (double)st->holes},
                                                     {"open", (double)st->open}};
    for (size_t i = 0; i < HV_COUNT(f); ++i) {
        if (i >= 4) lua_pushinteger(L, (lua_Integer)f[i].v);
        else lua_pushnumber(L, f[i].v);
        lua_setfield(L, -2, f[i].k);
    }
    if (a->run->keep_loops) {
        push_loops(L, a->slice, a->run->mesh);
        lua_setfield(L, -2, "contours");
    }
    lua_rawseti(L, 2, (lua_Integer)a->index + 1); /* the result list, argument 2 */
    return 0;
}

/* Runs on the calling thread, in layer order (hv_contours_write's contract). */
static hv_status contour_layer(void *user, size_t index, const hv_layer *layer, const hv_slice *slice)
{
    contour_run *r = user;
    lua_State *L = r->L;
    layer_args a = {r, index, layer, slice};
    if (!lua_checkstack(L, 8)) return hv_error_set(HV_ERR_NOMEM, "Lua stack exhausted");
    lua_pushcfunction(L, push_layer); /* a light C function and a light userdata: no allocation */
    lua_pushlightuserdata(L, &a);
    lua_pushvalue(L, r->table);
    if (lua_pcall(L, 2, 0, 0) == LUA_OK) return HV_OK;
    lua_pop(L, 1);
    return hv_error_set(HV_ERR_NOMEM, "out of memory for the layers' tables (the script's memory limit)");
}

/* hovox.contours(mesh, {<the options of hv_contours_option_set: layer_height, adaptive = {min,
 *   max[, cusp]}, first_layer, close_gap, binary, output = "x.svg" | "x.cli", per_layer = DIR>,
 *   loops = true})
 *   -> { {z, bottom, top, area, loops, holes, open, contours = { {points, closed,
 *        orientation, parent, area, body}, ... }}, ... }; body: the name of the mesh body the loop
 *        belongs to */
static int l_contours(lua_State *L)
{
    static const char *const extra[] = {"loops", NULL};
    hv_mesh *mesh = hv_lua_mesh(L, 1);
    hv_contours_options o;
    hv_lua_read(L, 2, hv_contours_option_set(), &o, extra);
    int keep = hv_lua_field(L, 2, "loops") == LUA_TNIL || lua_toboolean(L, -1);
    lua_pop(L, 1);
    hv_lua_check_paths(L, 2, hv_contours_option_set(), &o);
    mesh = hv_lua_mesh(L, 1); /* again: reading the options may have run a finalizer */
    lua_newtable(L);
    contour_run run = {L, keep, lua_gettop(L), mesh};
    hv_status s = hv_contours_write(mesh, &o, NULL, contour_layer, &run, hv_lua_progress(L), NULL);
    return s != HV_OK ? fail(L, s) : 1;
}

void hv_lua_open_mesh(lua_State *L, int module)
{
    static const luaL_Reg methods[] = {{"report", mesh_report},       {"save", mesh_save},     {"count", mesh_count},
                                       {"bodies", mesh_bodies},       {"materials", mesh_materials},
                                       {"free", mesh_gc},             {"transform", mesh_transform},
                                       {"set_material", mesh_set_material}, {"set_colour", mesh_set_colour},
                                       {"layers", mesh_layers},        {NULL, NULL}};
    static const luaL_Reg fns[] = {{"load_mesh", l_load_mesh}, {"contours", l_contours}, {NULL, NULL}};
    hv_lua_new_class(L, MT_MESH, methods, mesh_gc, mesh_tostring);
    lua_pushvalue(L, module);
    hv_lua_set_funcs(L, fns);
    lua_pop(L, 1);
    lua_createtable(L, 0, hv_shape_count());
    for (int i = 0; i < hv_shape_count(); ++i) {
        lua_pushinteger(L, i);
        lua_pushcclosure(L, l_generate, 1);
        lua_setfield(L, -2, hv_shape_name(i));
    }
    lua_setfield(L, module, "generate");
}
