/* src/lua/lscan.c - Lua: scanner and simulation volumes (hovox/scan.h, hovox/lut.h; issue 30).
 * hovox.scan_info(path) reports a volume as `hovox info` does; hovox.voxelize_scan(path, {...})
 * makes a model with no mesh, as `hovox voxelize VOLUME` does, its materials from a lookup table
 * (lut = TABLE.csv; a colour table through icc = PROFILE.icc). The model prints with
 * model:layers{...} (its contours from the data at printer resolution); hovox.layers_scan(path, {...})
 * prints the volume straight from its data as `hovox layers VOLUME` does, the same bytes. */
#include <stdlib.h>
#include <string.h>

#include <lauxlib.h>

#include "core/internal.h"
#include "hovox/colour.h"
#include "hovox/layers.h"
#include "hovox/lut.h"
#include "hovox/scan.h"
#include "hovox/viewer.h"
#include "io/scan/scan_internal.h"
#include "lhovox.h"

/* A private copy of the path argument, in holder. */
static const char *path_arg(lua_State *L, int arg, int holder)
{
    size_t n;
    const char *s = luaL_checklstring(L, arg, &n);
    if (strlen(s) != n) arg_error(L, arg, "a path must not hold a NUL byte");
    return hv_lua_copy_string(L, holder, s, n);
}

/* hovox.scan_info(path, {max_memory = SIZE}) -> {format, sample_type, encoding, unit, files, dims = {i, j, k},
 *   spacing = {...}, axes = "RAS", affine = {12}, bbox_min, bbox_max, value_min, value_max, slope, intercept} */
static int l_scan_info(lua_State *L)
{
    static const char *const extra[] = {NULL};
    hv_scan_options o;
    int holder = hv_lua_read(L, 2, hv_scan_option_set(), &o, extra);
    const char *path = path_arg(L, 1, holder);
    hv_scan *scan = NULL;
    hv_status s = hv_scan_load(path, &o, &scan);
    if (s != HV_OK) return fail(L, s);
    const hv_scan_info *in = hv_scan_get_info(scan);
    size_t d[3];
    double dims[3], m[12], sp[3], lo[3], hi[3];
    char axes[4];
    hv_scan_dims(scan, d);
    hv_scan_affine(scan, m);
    hv_scan_geometry(scan, sp, axes, lo, hi);
    for (int a = 0; a < 3; ++a) dims[a] = (double)d[a];
    lua_createtable(L, 0, 16);
    const struct { const char *k, *v; } texts[] = {{"format", in->format_name}, {"sample_type", in->sample_type},
                                                   {"encoding", in->encoding}, {"unit", in->unit},
                                                   {"space", in->space},       {"axes", axes}};
    for (size_t i = 0; i < HV_COUNT(texts); ++i) {
        lua_pushstring(L, texts[i].v);
        lua_setfield(L, -2, texts[i].k);
    }
    const struct { const char *k; double v; } nums[] = {{"value_min", in->value_min}, {"value_max", in->value_max},
                                                        {"slope", in->slope},         {"intercept", in->intercept},
                                                        {"files", (double)in->files}};
    for (size_t i = 0; i < HV_COUNT(nums); ++i) {
        lua_pushnumber(L, nums[i].v);
        lua_setfield(L, -2, nums[i].k);
    }
    const struct { const char *k; const double *v; int n; } vecs[] = {
        {"dims", dims, 3}, {"spacing", sp, 3}, {"affine", m, 12}, {"bbox_min", lo, 3}, {"bbox_max", hi, 3}};
    for (size_t i = 0; i < HV_COUNT(vecs); ++i) {
        hv_lua_push_vec(L, vecs[i].v, vecs[i].n);
        lua_setfield(L, -2, vecs[i].k);
    }
    hv_scan_destroy(scan);
    return 1;
}

/* The labels list of option table `arg` into a userdata array pushed on the stack (anchored while C
 * runs); *n of them. Raises unless a list of 1 to 65536 integers of 32 bits. */
static int32_t *labels_arg(lua_State *L, int arg, size_t *n)
{
    if (hv_lua_field(L, arg, "labels") != LUA_TTABLE || lua_getmetatable(L, -1))
        arg_error(L, arg, "labels must be a list of integers");
    lua_Unsigned len = lua_rawlen(L, -1);
    if (len < 1 || len > 65536) arg_error(L, arg, "labels must name 1 to 65536 labels, got %llu", (unsigned long long)len);
    int32_t *v = lua_newuserdatauv(L, (size_t)len * sizeof *v, 0);
    for (lua_Unsigned i = 1; i <= len; ++i) {
        lua_rawgeti(L, -2, (lua_Integer)i);
        int isint = 0;
        lua_Integer x = lua_tointegerx(L, -1, &isint);
        if (!isint || x < INT32_MIN || x > INT32_MAX)
            arg_error(L, arg, "labels[%llu] must be an integer of 32 bits", (unsigned long long)i);
        v[i - 1] = (int32_t)x;
        lua_pop(L, 1);
    }
    lua_remove(L, -2); /* the list; the array stays */
    *n = (size_t)len;
    return v;
}

/* The shape of option table 2: one of iso, range (read with the options) or labels (a list, pushed on
 * the stack while C runs). */
static void shape_arg(lua_State *L, hv_scan_voxelize_options *o)
{
    int picks = 0;
    static const char *const shapes[] = {"iso", "range", "labels"};
    for (int k = 0; k < 3; ++k) {
        picks += hv_lua_field(L, 2, shapes[k]) != LUA_TNIL;
        lua_pop(L, 1);
    }
    if (picks != 1) arg_error(L, 2, "a scanned volume needs one of iso, range or labels");
    if (hv_lua_field(L, 2, "labels") != LUA_TNIL) {
        lua_pop(L, 1);
        o->shape.select = HV_SCAN_SELECT_LABELS;
        o->shape.labels = labels_arg(L, 2, &o->shape.label_count);
    } else {
        lua_pop(L, 1);
    }
}

/* hovox.voxelize_scan(path, {iso = V | range = {LO, HI} | labels = {A, B, ...}, voxel_size = L | {X, Y, Z},
 *   keep_largest, fill_holes, min_feature, max_memory, lut = TABLE.csv, icc = PROFILE.icc}) -> model */
static int l_voxelize_scan(lua_State *L)
{
    static const char *const extra[] = {"labels", "lut", "icc", NULL};
    hv_scan_voxelize_options o;
    int holder = hv_lua_read(L, 2, hv_scan_voxelize_option_set(), &o, extra);
    const char *path = path_arg(L, 1, holder);
    const char *lut_path = hv_lua_string_field(L, 2, "lut", holder);
    const char *icc = hv_lua_string_field(L, 2, "icc", holder);
    shape_arg(L, &o);
    if (icc && !lut_path) arg_error(L, 2, "icc is for a colour lookup table (lut)");
    o.progress = hv_lua_progress(L);
    hv_lut *lut = NULL;
    hv_colour_map *map = NULL;
    hv_scan *scan = NULL;
    hv_volume *vol = NULL;
    hv_status s = lut_path ? hv_lut_load(lut_path, &lut) : HV_OK;
    if (s == HV_OK && lut && hv_lut_kind_of(lut) == HV_LUT_COLOUR) {
        hv_colour_options co;
        hv_colour_options_init(&co);
        if (icc) co.icc = icc;
        s = hv_colour_map_create(&co, &map);
    }
    hv_scan_options so = {o.max_memory};
    if (s == HV_OK) s = hv_scan_load(path, &so, &scan);
    if (s == HV_OK) s = hv_lut_scan_model(scan, &o, lut, map, &vol, NULL);
    hv_scan_destroy(scan);
    hv_colour_map_destroy(map);
    hv_lut_destroy(lut);
    if (s != HV_OK) return fail(L, s);
    hv_lua_push_model(L, vol);
    return 1;
}

/* The keys of `set` and then `more` (NULL-terminated) into keys (at most n - 1), NULL-terminated:
 * the keys another set of the same table reads. */
static void keys_of(const hv_option_set *set, const char *const *more, const char **keys, size_t n)
{
    size_t k = 0;
    for (int i = 0; i < set->count && k + 1 < n; ++i) keys[k++] = set->options[i].key;
    for (size_t i = 0; more[i] && k + 1 < n; ++i) keys[k++] = more[i];
    keys[k] = NULL;
}

/* hovox.layers_scan(path, {iso = V | range = {LO, HI} | labels = {A, B, ...}, lut = TABLE.csv, icc, intent,
 *   resins, keep_largest, fill_holes, min_feature, voxel_size, dir = "stack", view = true, <the options of
 *   `hovox layers`>}) -> what model:layers returns: the volume printed as `hovox layers VOLUME` prints it
 *   (issue 30 item 3): straight from its data (no model; hv_scan_source), or, with a clean-up, a
 *   threshold, the direct method or a comparison, through its model made in memory. The same bytes as
 *   the CLI: the same calls in the same order. */
static int l_layers_scan(lua_State *L)
{
    static const char *const own[] = {"dir", "view", "labels", "lut", NULL};
    const char *keys_l[160], *keys_s[160], *keys_c[160];
    const char *const scan_more[] = {"icc", "intent", "resins", "dir", "view", "labels", "lut", NULL};
    const char *const colour_more[] = {"dir", "view", "labels", "lut", NULL};
    hv_layers_options o;
    hv_scan_voxelize_options so;
    hv_colour_options co;
    {
        const char *tmp[160];
        keys_of(hv_scan_voxelize_option_set(), own, tmp, 80);
        keys_of(hv_colour_option_set(), tmp, keys_l, HV_COUNT(keys_l));
        keys_of(hv_layers_option_set(), scan_more, tmp, 120);
        keys_of(hv_colour_option_set(), tmp, keys_s, HV_COUNT(keys_s));
        keys_of(hv_layers_option_set(), colour_more, tmp, 120);
        keys_of(hv_scan_voxelize_option_set(), tmp, keys_c, HV_COUNT(keys_c));
    }
    int holder = hv_lua_read(L, 2, hv_layers_option_set(), &o, keys_l);
    hv_lua_read_options(L, 2, hv_scan_voxelize_option_set(), &so, keys_s, holder);
    hv_lua_read_options(L, 2, hv_colour_option_set(), &co, keys_c, holder);
    const char *path = path_arg(L, 1, holder);
    const char *dir = hv_lua_out_path(L, 2, "dir", holder, "the stack's directory");
    hv_lua_check_paths(L, 2, hv_layers_option_set(), &o);
    const char *lut_path = hv_lua_string_field(L, 2, "lut", holder);
    shape_arg(L, &so);
    if (!lut_path && o.mode != HV_LAYERS_MASK)
        arg_error(L, 2, "a scanned volume's materials come from lut = TABLE.csv (or print its shape alone with "
                        "mode = \"mask\")");
    lua_getfield(L, 2, "view"); /* view = true: the stack's page, DIR/index.html (hovox view) */
    if (!lua_isnil(L, -1) && !lua_isboolean(L, -1)) return luaL_error(L, "view must be true or false");
    if (lua_toboolean(L, -1)) o.finish = hv_viewer_stack_finish;
    lua_pop(L, 1);
    o.model_name = path; /* as the CLI names it: the manifest's shape and model */
    hv_lut *lut = NULL;
    hv_colour_map *map = NULL;
    hv_scan *scan = NULL;
    hv_scan_options sopt = {o.max_memory};
    hv_status s = lut_path ? hv_lut_load(lut_path, &lut) : HV_OK;
    if (s == HV_OK && lut && hv_lut_kind_of(lut) == HV_LUT_COLOUR) s = hv_colour_map_create(&co, &map);
    if (s == HV_OK) s = hv_scan_load(path, &sopt, &scan);
    hv_layers_report rep;
    hv_colour_skin skin;
    hv_material_table *t = NULL;
    if (s == HV_OK) s = hv_layers_write_scan(scan, &so, lut, map, dir, &o, hv_lua_progress(L), &rep, &skin, &t);
    int coloured = s == HV_OK && skin.map != NULL;
    hv_scan_destroy(scan);
    hv_colour_map_destroy(map);
    hv_lut_destroy(lut);
    if (s != HV_OK) return fail(L, s);
    hv_lua_push_layers_report(L, &rep, t, coloured ? &skin : NULL); /* skin: its figures only */
    hv_material_table_destroy(t);
    return 1;
}

void hv_lua_open_scan(lua_State *L, int module)
{
    static const luaL_Reg fns[] = {{"scan_info", l_scan_info},
                                   {"voxelize_scan", l_voxelize_scan},
                                   {"layers_scan", l_layers_scan},
                                   {NULL, NULL}};
    lua_pushvalue(L, module);
    hv_lua_set_funcs(L, fns);
    lua_pop(L, 1);
}
