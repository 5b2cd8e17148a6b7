/* src/lua/lextra.c - Lua methods contributed by modules outside the material core (profile
 * plots, rendering, contours, printer layers, export), registered into the `hovox` module and
 * the Model class by luaopen_hovox. Same rules as lhovox.c: check arguments, call C, raise
 * after C returns. */
#include <math.h>
#include <string.h>

#include <lauxlib.h>

#include "core/internal.h"
#include "hovox/export.h"
#include "hovox/layers.h"
#include "hovox/plot.h"
#include "hovox/profile.h"
#include "hovox/render.h"
#include "hovox/slice.h"
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
    static const char *const keys[] = {"from", "to", "samples", "csv", "plot", "title", "width", "height", NULL};
    hv_volume *vol = check_model(L, 1);
    hv_lua_check_options(L, 2, 2, keys);
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

/* ---- contours ------------------------------------------------------------------------------ */

typedef struct contour_run {
    lua_State *L;
    hv_contour_writer *writer;
    int keep_loops;
    int table; /* stack index of the result list */
} contour_run;

static void push_loops(lua_State *L, const hv_slice *slice)
{
    size_t n = hv_slice_loop_count(slice);
    const hv_slice_loop *loops = hv_slice_loops(slice);
    lua_createtable(L, (int)n, 0);
    for (size_t i = 0; i < n; ++i) {
        const hv_slice_loop *lp = &loops[i];
        lua_createtable(L, 0, 6);
        lua_createtable(L, (int)lp->count, 0);
        for (size_t k = 0; k < lp->count; ++k) {
            lua_createtable(L, 2, 0);
            lua_pushnumber(L, lp->xy[2 * k]);
            lua_rawseti(L, -2, 1);
            lua_pushnumber(L, lp->xy[2 * k + 1]);
            lua_rawseti(L, -2, 2);
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
        lua_rawseti(L, -2, (lua_Integer)i + 1);
    }
}

/* Runs on the calling thread, in layer order (hv_slicer_slice_plan's sink contract). */
static hv_status contour_sink(void *user, size_t index, const hv_layer *layer, hv_slice **slice)
{
    contour_run *r = user;
    lua_State *L = r->L;
    const hv_slice_stats *st = hv_slice_get_stats(*slice);
    if (!lua_checkstack(L, 8)) return hv_error_set(HV_ERR_NOMEM, "Lua stack exhausted");
    lua_createtable(L, 0, 9);
    lua_pushnumber(L, layer->z);
    lua_setfield(L, -2, "z");
    lua_pushnumber(L, layer->bottom);
    lua_setfield(L, -2, "bottom");
    lua_pushnumber(L, layer->top);
    lua_setfield(L, -2, "top");
    lua_pushnumber(L, st->area);
    lua_setfield(L, -2, "area");
    lua_pushinteger(L, (lua_Integer)st->loops);
    lua_setfield(L, -2, "loops");
    lua_pushinteger(L, (lua_Integer)st->holes);
    lua_setfield(L, -2, "holes");
    lua_pushinteger(L, (lua_Integer)st->open);
    lua_setfield(L, -2, "open");
    if (r->keep_loops) {
        push_loops(L, *slice);
        lua_setfield(L, -2, "contours");
    }
    lua_rawseti(L, r->table, (lua_Integer)index + 1);
    return r->writer ? hv_contour_writer_add(r->writer, layer, *slice) : HV_OK;
}

/* hovox.contours(mesh, {layer_height = H, first_layer = H0, adaptive = {min, max[, cusp]},
 *                       output = "x.svg" | "x.cli", binary = false, loops = true})
 *   -> { {z, bottom, top, area, loops, holes, open, contours = { {points, closed,
 *        orientation, parent, area}, ... }}, ... } */
static int l_contours(lua_State *L)
{
    static const char *const keys[] = {"layer_height", "first_layer", "adaptive", "output", "binary", "loops", NULL};
    hv_mesh *mesh = hv_lua_mesh(L, 1);
    hv_lua_check_options(L, 2, 2, keys);
    lua_getfield(L, 2, "layer_height");
    double h = luaL_optnumber(L, -1, 0);
    lua_pop(L, 1);
    double ad[3] = {0, 0, 0};
    lua_getfield(L, 2, "adaptive");
    int adaptive = lua_istable(L, -1);
    if (adaptive) {
        for (int i = 0; i < 3; ++i) {
            lua_rawgeti(L, -1, i + 1);
            ad[i] = lua_isnil(L, -1) && i == 2 ? 0 : luaL_checknumber(L, -1);
            lua_pop(L, 1);
        }
        if (ad[2] == 0) ad[2] = ad[0];
        if (!(ad[0] > 0 && ad[1] >= ad[0])) return arg_error(L, 2, "adaptive must be {min, max[, cusp]} with 0 < min <= max");
    }
    lua_pop(L, 1);
    if (!adaptive && !(h > 0)) return arg_error(L, 2, "layer_height must be > 0, got %g", h);
    lua_getfield(L, 2, "first_layer");
    double first = luaL_optnumber(L, -1, adaptive ? ad[0] : h);
    lua_pop(L, 1);
    if (!(first > 0)) return arg_error(L, 2, "first_layer must be > 0, got %g", first);
    const char *output = get_path(L, 2, "output");
    lua_getfield(L, 2, "binary");
    int binary = lua_toboolean(L, -1);
    lua_pop(L, 1);
    lua_getfield(L, 2, "loops");
    int keep = lua_isnil(L, -1) ? 1 : lua_toboolean(L, -1);
    lua_pop(L, 1);
    hv_contour_format fmt = HV_CONTOUR_SVG;
    if (output) {
        size_t n = strlen(output);
        if (n > 4 && strcmp(output + n - 4, ".cli") == 0) fmt = binary ? HV_CONTOUR_CLI_BINARY : HV_CONTOUR_CLI_ASCII;
        else if (!(n > 4 && strcmp(output + n - 4, ".svg") == 0)) return arg_error(L, 2, "output must end in .svg or .cli");
    }
    hv_slicer *slicer = NULL;
    hv_layer_plan *plan = NULL;
    hv_status s = hv_slicer_create(mesh, NULL, &slicer);
    if (s == HV_OK)
        s = adaptive ? hv_slicer_plan_adaptive(slicer, first, ad[0], ad[1], ad[2], &plan)
                     : hv_slicer_plan_uniform(slicer, first, h, &plan);
    lua_createtable(L, plan ? (int)HV_MIN(hv_layer_plan_count(plan), (size_t)1 << 20) : 0, 0);
    contour_run run = {L, NULL, keep, lua_gettop(L)};
    if (s == HV_OK && output) {
        hv_slicer_info info;
        hv_slicer_get_info(slicer, &info);
        s = hv_contour_writer_open(output, fmt, hv_layer_plan_count(plan), info.bbox_min, info.bbox_max, "hovox",
                                   &run.writer);
    }
    hv_slice_options so;
    hv_slice_options_init(&so);
    if (s == HV_OK) s = hv_slicer_slice_plan(slicer, plan, &so, contour_sink, &run, NULL);
    if (run.writer) {
        if (s == HV_OK) s = hv_contour_writer_close(run.writer);
        else hv_contour_writer_abort(run.writer);
    }
    hv_layer_plan_destroy(plan);
    hv_slicer_destroy(slicer);
    if (s != HV_OK) return fail(L, s);
    return 1;
}

/* ---- export ------------------------------------------------------------------------------- */

/* model:export{path = "x.vti" | "x.vtu", box = {x0,y0,z0,x1,y1,z1}, coarsen = N,
 *              keep = "majority" | "any", properties = "both" | "voigt" | "reuss" | "none",
 *              linearize = {youngs_modulus = "table.csv", ...}, level = 1..9,
 *              max_memory = bytes} -> {points, cells, occupied, arrays = "a,b,...", bytes} */
static int model_export(lua_State *L)
{
    static const char *const keys[] = {"path", "box", "coarsen", "keep", "properties", "linearize", "level", "max_memory", NULL};
    hv_volume *vol = check_model(L, 1);
    hv_lua_check_options(L, 2, 2, keys);
    const char *path = get_path(L, 2, "path");
    if (!path) return arg_error(L, 2, "path is required (.vti or .vtu)");
    hv_export_options o;
    hv_export_options_init(&o);
    o.format = hv_export_format_from_path(path);
    lua_getfield(L, 2, "box");
    if (!lua_isnil(L, -1)) {
        if (!lua_istable(L, -1) || lua_rawlen(L, -1) != 6) return arg_error(L, 2, "box must be {x0, y0, z0, x1, y1, z1}");
        for (int i = 0; i < 6; ++i) {
            lua_rawgeti(L, -1, i + 1);
            double v = luaL_checknumber(L, -1);
            if (i < 3) o.box_lo[i] = v;
            else o.box_hi[i - 3] = v;
            lua_pop(L, 1);
        }
        o.use_box = 1;
    }
    lua_pop(L, 1);
    lua_getfield(L, 2, "coarsen");
    lua_Integer n = luaL_optinteger(L, -1, o.coarsen);
    lua_pop(L, 1);
    if (n < 1 || n > 1024) return arg_error(L, 2, "coarsen must be in [1, 1024], got %lld", (long long)n);
    o.coarsen = (int)n;
    lua_getfield(L, 2, "keep");
    const char *keep = luaL_optstring(L, -1, "majority");
    lua_pop(L, 1);
    if (strcmp(keep, "majority") == 0) o.coarsen_rule = HV_COARSEN_MAJORITY;
    else if (strcmp(keep, "any") == 0) o.coarsen_rule = HV_COARSEN_ANY;
    else return arg_error(L, 2, "keep must be majority or any, got '%s'", keep);
    lua_getfield(L, 2, "properties");
    const char *props = luaL_optstring(L, -1, "both");
    lua_pop(L, 1);
    if (strcmp(props, "both") == 0) o.mix = HV_MIX_VOIGT | HV_MIX_REUSS;
    else if (strcmp(props, "voigt") == 0) o.mix = HV_MIX_VOIGT;
    else if (strcmp(props, "reuss") == 0) o.mix = HV_MIX_REUSS;
    else if (strcmp(props, "none") == 0) o.mix = 0;
    else return arg_error(L, 2, "properties must be both, voigt, reuss or none, got '%s'", props);
    lua_getfield(L, 2, "level");
    lua_Integer level = luaL_optinteger(L, -1, 1);
    lua_pop(L, 1);
    if (level < 1 || level > 9) return arg_error(L, 2, "level must be in [1, 9], got %lld", (long long)level);
    o.zlib_level = (int)level;
    lua_getfield(L, 2, "max_memory");
    o.max_memory = (uint64_t)luaL_optnumber(L, -1, 0);
    lua_pop(L, 1);
    /* linearization tables: loaded before anything is written; freed on every path */
    hv_linearization *tables[32];
    int nt = 0;
    hv_status s = HV_OK;
    lua_getfield(L, 2, "linearize");
    if (lua_istable(L, -1)) {
        lua_pushnil(L);
        while (s == HV_OK && lua_next(L, -2)) {
            if (lua_type(L, -2) != LUA_TSTRING || lua_type(L, -1) != LUA_TSTRING || nt == 32) {
                lua_pop(L, 2);
                for (int i = 0; i < nt; ++i) hv_linearization_destroy(tables[i]);
                return arg_error(L, 2, "linearize must map property names to CSV files (at most 32)");
            }
            s = hv_linearization_load(lua_tostring(L, -1), lua_tostring(L, -2), &tables[nt]);
            if (s == HV_OK) ++nt;
            lua_pop(L, 1);
        }
        if (s != HV_OK) lua_pop(L, 1); /* the key left by the interrupted traversal */
    }
    lua_pop(L, 1);
    hv_export_report rep;
    if (s == HV_OK) {
        o.tables = (const hv_linearization *const *)tables;
        o.ntables = nt;
        s = hv_export_write(vol, path, &o, &rep);
    }
    for (int i = 0; i < nt; ++i) hv_linearization_destroy(tables[i]);
    if (s != HV_OK) return fail(L, s);
    lua_createtable(L, 0, 6);
    lua_pushinteger(L, (lua_Integer)rep.points);
    lua_setfield(L, -2, "points");
    lua_pushinteger(L, (lua_Integer)rep.cells);
    lua_setfield(L, -2, "cells");
    lua_pushinteger(L, (lua_Integer)rep.occupied);
    lua_setfield(L, -2, "occupied");
    lua_pushstring(L, rep.names);
    lua_setfield(L, -2, "arrays");
    lua_pushstring(L, rep.notes);
    lua_setfield(L, -2, "notes");
    lua_pushinteger(L, (lua_Integer)rep.file_bytes);
    lua_setfield(L, -2, "bytes");
    return 1;
}

/* ---- render -------------------------------------------------------------------------------- */

static void opt_vec(lua_State *L, int idx, const char *key, double *out, int n, int *set)
{
    lua_getfield(L, idx, key);
    if (!lua_isnil(L, -1)) {
        if (!lua_istable(L, -1) || (int)lua_rawlen(L, -1) != n)
            arg_error(L, 2, "%s must be a list of %d numbers", key, n);
        for (int i = 0; i < n; ++i) {
            lua_rawgeti(L, -1, i + 1);
            int ok;
            out[i] = lua_tonumberx(L, -1, &ok);
            if (!ok || !isfinite(out[i])) arg_error(L, 2, "%s[%d] must be a finite number", key, i + 1);
            lua_pop(L, 1);
        }
        if (set) *set = 1;
    }
    lua_pop(L, 1);
}

/* model:render{path = "x.png"|".exr"|".tif", <the options of hv_render_option_set(): size,
 *              background, aa, mode (surface = true, volume = true), flat, density, step,
 *              tf_low, tf_high, view, eye, target, up, ortho, fov, clip, clip_box,
 *              cut_opacity>} -- the options of `hovox render` */
static int model_render(lua_State *L)
{
    static const char *const extra[] = {"path", NULL};
    hv_volume *vol = check_model(L, 1);
    int holder = hv_lua_holder(L);
    hv_render_options o;
    hv_optargs args;
    hv_lua_read_options(L, 2, hv_render_option_set(), &o, &args, extra, holder);
    const char *path = hv_lua_string_field(L, 2, "path", holder);
    if (!path) return arg_error(L, 2, "path is required (.png, .exr or .tif)");
    hv_lua_check_write(L, 2, path);
    hv_image *img = NULL;
    hv_status s = hv_render(vol, &o, NULL, &img);
    if (s == HV_OK) s = hv_image_write(img, path);
    hv_image_destroy(img);
    if (s != HV_OK) return fail(L, s);
    return 0;
}

/* ---- printer layers ------------------------------------------------------------------------ */

/* model:layers{mesh = Mesh, dir = "stack", profile = "j750" | dpi = {x, y}, layer_height = H,
 *              mode = "halftone"|"fractions"|"mask", method = "resample"|"direct",
 *              halftone = "bluenoise"|"error", seed = N, layers = {first, last}, threshold,
 *              fill_rule = "nonzero"|"evenodd", background = "#000000", compare = bool,
 *              gcvf = "stack.zip", force = bool, max_memory}
 *   -> {width, height, layers, first, last, object_pixels, materials = {name = {target,
 *       achieved}}, diff_mean, diff_max} -- the options of `hovox layers` */
static int model_layers(lua_State *L)
{
    static const char *const keys[] = {"mesh", "dir", "profile", "dpi", "layer_height", "mode", "method", "halftone", "seed", "layers", "threshold", "fill_rule", "background", "compare", "gcvf", "force", "max_memory", NULL};
    hv_volume *vol = check_model(L, 1);
    hv_lua_check_options(L, 2, 2, keys);
    lua_getfield(L, 2, "mesh");
    hv_mesh *mesh = hv_lua_mesh(L, -1);
    lua_pop(L, 1); /* the options table keeps the mesh alive */
    lua_getfield(L, 2, "dir");
    const char *dir = lua_tostring(L, -1);
    lua_pop(L, 1);
    if (!dir) return arg_error(L, 2, "dir is required (the stack's directory)");
    hv_lua_check_write(L, 2, dir);
    const char *gcvf = get_path(L, 2, "gcvf");
    hv_layers_options o;
    hv_layers_options_init(&o);
    o.gcvf_path = gcvf;
    /* the printer: a profile (default j750; layer_height may override its height), or a
     * generic one from dpi = {x, y} and layer_height -- as in `hovox layers` */
    lua_getfield(L, 2, "profile");
    const char *prof = luaL_optstring(L, -1, NULL);
    lua_pop(L, 1);
    lua_getfield(L, 2, "dpi");
    int have_dpi = !lua_isnil(L, -1);
    lua_pop(L, 1);
    if (prof && have_dpi) return arg_error(L, 2, "profile and dpi exclude each other");
    if (have_dpi) {
        double dpi[2] = {0, 0};
        opt_vec(L, 2, "dpi", dpi, 2, NULL);
        lua_getfield(L, 2, "layer_height");
        o.layer_height = luaL_optnumber(L, -1, 0);
        lua_pop(L, 1);
        if (!(dpi[0] > 0 && dpi[1] > 0 && o.layer_height > 0))
            return arg_error(L, 2, "dpi = {x, y} needs values > 0 and layer_height > 0");
        o.profile = "custom";
        o.dpi[0] = dpi[0];
        o.dpi[1] = dpi[1];
    } else {
        const hv_printer_profile *p = hv_printer_profile_find(prof ? prof : "j750");
        if (!p) return arg_error(L, 2, "unknown printer profile '%s' (j750, j850, or dpi and layer_height)", prof);
        o.profile = p->name;
        o.dpi[0] = p->dpi[0];
        o.dpi[1] = p->dpi[1];
        lua_getfield(L, 2, "layer_height");
        o.layer_height = luaL_optnumber(L, -1, p->layer_height);
        lua_pop(L, 1);
        if (!(o.layer_height > 0)) return arg_error(L, 2, "layer_height must be > 0");
    }
    struct { const char *key; const char *const *names; int *out; } choices[] = {
        {"mode", (const char *const[]){"halftone", "fractions", "mask", NULL}, (int *)&o.mode},
        {"method", (const char *const[]){"resample", "direct", NULL}, (int *)&o.method},
        {"halftone", (const char *const[]){"bluenoise", "error", NULL}, (int *)&o.halftone},
        {"fill_rule", (const char *const[]){"nonzero", "evenodd", NULL}, (int *)&o.fill_rule}};
    for (size_t c = 0; c < sizeof choices / sizeof choices[0]; ++c) {
        lua_getfield(L, 2, choices[c].key);
        if (!lua_isnil(L, -1)) {
            const char *v = luaL_checkstring(L, -1);
            int k = 0;
            while (choices[c].names[k] && strcmp(choices[c].names[k], v) != 0) ++k;
            if (!choices[c].names[k]) return arg_error(L, 2, "%s: invalid option '%s'", choices[c].key, v);
            *choices[c].out = k;
        }
        lua_pop(L, 1);
    }
    lua_getfield(L, 2, "seed");
    o.seed = (uint64_t)luaL_optinteger(L, -1, 0);
    lua_pop(L, 1);
    lua_getfield(L, 2, "threshold");
    o.threshold = luaL_optnumber(L, -1, 0);
    lua_pop(L, 1);
    if (!(o.threshold >= 0)) return arg_error(L, 2, "threshold must be >= 0");
    double range[2] = {0, 0};
    opt_vec(L, 2, "layers", range, 2, NULL);
    if (range[0] < 0 || range[1] < 0 || (range[1] > 0 && range[1] <= range[0]))
        return arg_error(L, 2, "layers must be {first, last} with 0 <= first < last (last exclusive)");
    o.first = (size_t)range[0];
    o.last = (size_t)range[1];
    lua_getfield(L, 2, "background");
    if (!lua_isnil(L, -1)) {
        float c[4];
        if (hv_color_parse(luaL_checkstring(L, -1), c) != HV_OK) return arg_error(L, 2, "%s", hv_last_error());
        for (int k = 0; k < 3; ++k) o.background[k] = (uint8_t)(c[k] * 255.0f + 0.5f);
    }
    lua_pop(L, 1);
    lua_getfield(L, 2, "compare");
    o.compare = lua_toboolean(L, -1);
    lua_pop(L, 1);
    lua_getfield(L, 2, "force");
    o.force = lua_toboolean(L, -1);
    lua_pop(L, 1);
    lua_getfield(L, 2, "max_memory");
    o.max_memory = (uint64_t)luaL_optnumber(L, -1, 0);
    lua_pop(L, 1);
    hv_layers_report rep;
    hv_status s = hv_layers_write(mesh, o.mode == HV_LAYERS_MASK ? NULL : vol, dir, &o, NULL, &rep);
    if (s != HV_OK) return fail(L, s);
    lua_createtable(L, 0, 10);
    lua_pushinteger(L, rep.width);
    lua_setfield(L, -2, "width");
    lua_pushinteger(L, rep.height);
    lua_setfield(L, -2, "height");
    lua_pushinteger(L, (lua_Integer)rep.layers_total);
    lua_setfield(L, -2, "layers");
    lua_pushinteger(L, (lua_Integer)rep.first);
    lua_setfield(L, -2, "first");
    lua_pushinteger(L, (lua_Integer)rep.last);
    lua_setfield(L, -2, "last");
    lua_pushinteger(L, (lua_Integer)rep.object_pixels);
    lua_setfield(L, -2, "object_pixels");
    if (rep.compared) {
        lua_pushnumber(L, rep.diff_mean);
        lua_setfield(L, -2, "diff_mean");
        lua_pushnumber(L, rep.diff_max);
        lua_setfield(L, -2, "diff_max");
    }
    lua_createtable(L, 0, rep.materials);
    hv_material_table *t = NULL;
    if (rep.materials > 0 && hv_material_table_load(vol, &t) == HV_OK) {
        for (int j = 0; j < rep.materials && j < hv_material_count(t); ++j) {
            lua_createtable(L, 0, 2);
            lua_pushnumber(L, rep.target[j]);
            lua_setfield(L, -2, "target");
            lua_pushnumber(L, rep.achieved[j]);
            lua_setfield(L, -2, "achieved");
            lua_setfield(L, -2, hv_material_name(t, j));
        }
    }
    hv_material_table_destroy(t);
    lua_setfield(L, -2, "materials");
    return 1;
}

const luaL_Reg *hv_lua_model_extra(void)
{
    static const luaL_Reg m[] = {{"profile", model_profile}, {"export", model_export},
                                 {"render", model_render}, {"layers", model_layers}, {NULL, NULL}};
    return m;
}

const luaL_Reg *hv_lua_module_extra(void)
{
    static const luaL_Reg m[] = {{"contours", l_contours}, {NULL, NULL}};
    return m;
}
