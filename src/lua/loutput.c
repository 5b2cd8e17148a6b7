/* src/lua/loutput.c - Lua: a model's outputs, each reading the options of its CLI command through
 * the library's option set: model:render (hv_render_option_set), model:export
 * (hv_export_option_set), model:layers (hv_layers_option_set), model:profile
 * (hv_profile_option_set). Output paths are private copies checked against the sandbox right
 * before the call that writes them. */
#include <string.h>

#include <lauxlib.h>

#include "core/internal.h"
#include "hovox/export.h"
#include "hovox/colour.h"
#include "hovox/layers.h"
#include "hovox/plot.h"
#include "hovox/profile.h"
#include "hovox/render.h"
#include "hovox/viewer.h"
#include "lhovox.h"

#define SET_INT(k, v) (lua_pushinteger(L, (lua_Integer)(v)), lua_setfield(L, -2, k))
#define SET_NUM(k, v) (lua_pushnumber(L, (v)), lua_setfield(L, -2, k))

/* model:profile{<from, to, samples, property, title, size = {w, h}, mark, y_range>, csv = "p.csv",
 *   plot = "p.png" | "p.svg"} -> {t = {...}, inside = {...}, <material> = {...}, property =
 *   {name, unit, values = {...}} (with a property)} */
static int model_profile(lua_State *L)
{
    static const char *const extra[] = {"csv", "plot", NULL};
    hv_volume *vol = hv_lua_model(L, 1);
    hv_profile_options o;
    int holder = hv_lua_read(L, 2, hv_profile_option_set(), &o, extra);
    const char *csv = hv_lua_out_path(L, 2, "csv", holder, NULL), *plot = hv_lua_out_path(L, 2, "plot", holder, NULL);
    vol = hv_lua_model(L, 1); /* again: reading the options may have run a finalizer */
    hv_profile *p;
    hv_status s = hv_profile_sample_with(vol, &o, &p);
    if (s != HV_OK) return fail(L, s);
    s = hv_profile_write_files(p, &o, csv, plot);
    if (s != HV_OK) {
        hv_profile_destroy(p);
        return fail(L, s);
    }
    int ns = hv_profile_samples(p), m = hv_profile_materials(p);
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
        lua_setfield(L, -2, hv_material_name(hv_profile_table(p), j));
    }
    const char *unit, *prop = hv_profile_property(p, &unit);
    if (prop) { /* property = {name, unit, values = {...}}: NaN where undefined */
        lua_createtable(L, 0, 3);
        lua_pushstring(L, prop);
        lua_setfield(L, -2, "name");
        lua_pushstring(L, unit);
        lua_setfield(L, -2, "unit");
        lua_createtable(L, ns, 0);
        for (int i = 0; i < ns; ++i) {
            lua_pushnumber(L, hv_profile_property_value(p, i));
            lua_rawseti(L, -2, i + 1);
        }
        lua_setfield(L, -2, "values");
        lua_setfield(L, -2, "property");
    }
    hv_profile_destroy(p);
    return 1;
}

/* model:export{path = "x.vti" | "x.vtu" | "x.3mf" | "x.stl" | "x.obj", <box, coarsen, keep, properties, linearize = {property
 *   = "table.csv", ...}, level, max_memory>} -> {points, cells, occupied, arrays, notes, bytes} */
static int model_export(lua_State *L)
{
    static const char *const extra[] = {"path", NULL};
    hv_volume *vol = hv_lua_model(L, 1);
    hv_export_options o;
    int holder = hv_lua_read(L, 2, hv_export_option_set(), &o, extra);
    const char *path = hv_lua_out_path(L, 2, "path", holder, hv_export_format_list());
    o.format = hv_export_format_from_path(path);
    vol = hv_lua_model(L, 1); /* again: reading the options may have run a finalizer */
    hv_export_report rep;
    o.progress = hv_lua_progress(L);
    hv_status s = hv_export_write(vol, path, &o, &rep);
    if (s != HV_OK) return fail(L, s);
    lua_createtable(L, 0, 6);
    SET_INT("points", rep.points);
    SET_INT("cells", rep.cells);
    SET_INT("occupied", rep.occupied);
    lua_pushstring(L, rep.names);
    lua_setfield(L, -2, "arrays");
    lua_pushstring(L, rep.notes);
    lua_setfield(L, -2, "notes");
    SET_INT("bytes", rep.file_bytes);
    return 1;
}

/* model:render{path = "x.png" | ".exr" | ".tif", <the options of `hovox render`>} */
static int model_render(lua_State *L)
{
    static const char *const extra[] = {"path", NULL};
    hv_volume *vol = hv_lua_model(L, 1);
    hv_render_options o;
    int holder = hv_lua_read(L, 2, hv_render_option_set(), &o, extra);
    const char *path = hv_lua_out_path(L, 2, "path", holder, ".png, .exr or .tif");
    vol = hv_lua_model(L, 1); /* again: reading the options may have run a finalizer */
    hv_image *img = NULL;
    hv_status s = hv_render(vol, &o, hv_lua_progress(L), &img);
    if (s == HV_OK) s = hv_image_write(img, path);
    hv_image_destroy(img);
    return s != HV_OK ? fail(L, s) : 0;
}

/* model:layers{[mesh = Mesh,] dir = "stack", <the options of `hovox layers`: profile, dpi,
 *   layer_height, mode, method, halftone, seed, layers = {first, last}, threshold, fill_rule,
 *   background, compare, gcvf, force, max_memory, ...>}
 *   -> {width, height, layers, first, last, object_pixels, materials = {name = {target,
 *       achieved}}, diff_mean, diff_max, warnings} */
static int model_layers(lua_State *L)
{
    static const char *const extra[] = {"mesh", "dir", "view", NULL};
    hv_volume *vol = hv_lua_model(L, 1);
    hv_layers_options o;
    int holder = hv_lua_read(L, 2, hv_layers_option_set(), &o, extra);
    const char *dir = hv_lua_out_path(L, 2, "dir", holder, "the stack's directory");
    hv_lua_check_paths(L, 2, hv_layers_option_set(), &o);
    /* mesh: optional, an override that must be the one the model records (issue 28) */
    lua_getfield(L, 2, "mesh");
    int has_mesh = !lua_isnil(L, -1);
    lua_pop(L, 1);
    hv_mesh *mesh = has_mesh ? ((l_mesh *)hv_lua_option_object(L, 2, "mesh", MT_MESH, "hovox mesh"))->p : NULL; /* anchored */
    lua_getfield(L, 2, "view"); /* view = true: the stack's page, DIR/index.html (hovox view) */
    if (!lua_isnil(L, -1) && !lua_isboolean(L, -1)) return luaL_error(L, "view must be true or false");
    if (lua_toboolean(L, -1)) o.finish = hv_viewer_stack_finish;
    lua_pop(L, 1);
    vol = hv_lua_model(L, 1); /* again: reading the options may have run a finalizer */
    hv_layers_report rep;
    hv_colour_skin skin; /* a painted model: the skin's dE2000 in the manifest (hovox/colour.h) */
    if (hv_layers_colour_hook(&o, vol, &skin) != HV_OK) hv_error_clear();
    hv_status s = hv_layers_write(mesh, vol, dir, &o, hv_lua_progress(L), &rep);
    int coloured = skin.map != NULL;
    hv_colour_map_destroy(skin.map);
    if (s != HV_OK) return fail(L, s);
    hv_material_table *t = NULL;
    if (rep.materials > 0 && hv_material_table_load(vol, &t) != HV_OK) t = NULL;
    hv_lua_push_layers_report(L, &rep, t, coloured ? &skin : NULL);
    hv_material_table_destroy(t);
    return 1;
}

void hv_lua_push_layers_report(lua_State *L, const hv_layers_report *r, const hv_material_table *t,
                               const hv_colour_skin *skin)
{
    lua_createtable(L, 0, 11);
    if (skin) {
        lua_createtable(L, 0, 4);
        SET_INT(skin->printer_voxels ? "printer_voxels" : "skin_voxels", skin->target.voxels);
        SET_NUM("mean_de2000_target", skin->target.mean_de2000);
        SET_NUM("max_de2000_target", skin->target.max_de2000);
        if (skin->has_achieved) SET_NUM("mean_de2000_achieved", skin->achieved.mean_de2000);
        lua_setfield(L, -2, "colour");
    }
    SET_INT("width", r->width);
    SET_INT("height", r->height);
    SET_INT("layers", r->layers_total);
    SET_INT("first", r->first);
    SET_INT("last", r->last);
    SET_INT("object_pixels", r->object_pixels);
    if (r->compared) {
        SET_NUM("diff_mean", r->diff_mean);
        SET_NUM("diff_max", r->diff_max);
    }
    lua_pushstring(L, r->warnings);
    lua_setfield(L, -2, "warnings");
    lua_createtable(L, 0, r->materials);
    for (int j = 0; t && j < r->materials && j < hv_material_count(t); ++j) {
        lua_createtable(L, 0, 2);
        SET_NUM("target", r->target[j]);
        SET_NUM("achieved", r->achieved[j]);
        lua_setfield(L, -2, hv_material_name(t, j));
    }
    lua_setfield(L, -2, "materials");
}

void hv_lua_open_output(lua_State *L, int module)
{
    (void)module;
    static const luaL_Reg m[] = {{"profile", model_profile}, {"export", model_export},
                                 {"render", model_render}, {"layers", model_layers}, {NULL, NULL}};
    hv_lua_add_methods(L, MT_MODEL, m);
}
