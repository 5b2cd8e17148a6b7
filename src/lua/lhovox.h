/* src/lua/lhovox.h - the `hovox` Lua 5.4 module: modeling scripts over the C library.
 *
 * The binding is split by class: lhovox.c (module, shared helpers), lsandbox.c (the sandbox),
 * lmesh.c (meshes, generators, contours), lassembly.c (joining meshes into assemblies, a model's
 * regions), lmodel.c (models, voxelizing, probing), lsource.c
 * (material tables, reference features, grading sources), lobject.c (heterogeneous objects),
 * loutput.c (a model's outputs: render, export, layers, profile), lscan.c (scanned volumes) and lopts.c (option tables
 * read through the library's option sets).
 *
 * Rules every binding follows: it is entered through hv_lua_enter (the registration helpers do
 * it), so an object freed while it runs lives until it returns; check arguments first, call C,
 * raise only after C returned (no longjmp crosses library or C++ frames); options are read by key through the library's option
 * set, so every refusal names its key and says what the CLI says; every text the C call uses is
 * a private copy; class metatables are locked (__metatable), so a script reaches an object's
 * C side only through its methods. */
#ifndef HOVOX_LHOVOX_H
#define HOVOX_LHOVOX_H

#include <stdint.h>

#include <lauxlib.h>
#include <lua.h>

#include "hovox/material.h"
#include "hovox/options.h"

/* Open the module (pushes the `hovox` table). */
int luaopen_hovox(lua_State *L);

/* ---- sandbox (lsandbox.c) ---------------------------------------------------------------------
 * File writes by the module (and by io.open/io.output/os.remove/os.rename when hv_lua_sandbox
 * has been applied) are allowed only below `dir` (NULL: no restriction). */
void hv_lua_set_write_root(lua_State *L, const char *dir);
/* Remove debug, os.execute, os.tmpname, io.popen, io.tmpfile, package.loadlib and the file
 * searchers; force text-only load/loadfile/dofile; wrap io.open, io.output, os.remove and
 * os.rename to honour the write root. Call after the standard libraries are open and the
 * write root is set. */
void hv_lua_sandbox(lua_State *L);
/* Raise "bad argument" unless writing `path` is allowed: its directory resolves below the write
 * root, and when `path` itself is a symbolic link, its target does too. `field` names the option
 * of table argument `arg` that holds the path ("dir": "bad argument #1 to 'layers' (dir: sandbox:
 * ...)"), NULL when the argument is the path itself. Call on a private copy right before the C
 * call that writes. Returns path. */
const char *hv_lua_check_write(lua_State *L, int arg, const char *field, const char *path);

/* ---- objects in use, the runner's hooks (lhovox.c) -----------------------------------------------
 * Any allocation may run finalizers, and a finalizer (or a callback) may free an object
 * (obj:free(), __close, __gc) while a binding is between reading the object's C pointer and its
 * last use of it. So every binding is entered through hv_lua_enter (the methods and functions
 * registered by hv_lua_new_class, hv_lua_add_methods and hv_lua_set_funcs are wrapped in a
 * function that does it; closures with upvalues of their own call it first), which records the
 * binding's C stack frame; hv_lua_release, which every class's free and __gc go through, takes
 * the object from the script at once (its methods then say "object was freed") but destroys its C
 * side only when no binding entered before is still running (a frame above the releasing one:
 * the C stack grows down; Lua runs coroutines on the same C stack), else when the next binding
 * is entered with none running, or when the state closes. */
#define HV_LUA_FRAME() ((uintptr_t)__builtin_frame_address(0))
void hv_lua_enter(lua_State *L, uintptr_t frame);
/* Destroy p with destroy(p) now, or when no binding is running (see above). p may be NULL. */
void hv_lua_release(lua_State *L, void (*destroy)(void *), void *p);
/* Set what the runner (hovox run) wants on every binding entry: `entry` is called by
 * hv_lua_enter (it may raise: a time or memory limit passed; it may set the process-wide memory
 * cap of the call); `progress` (copied; NULL: none) is given to the library's long operations. */
typedef void (*hv_lua_entry_fn)(lua_State *L, void *user);
void hv_lua_set_runner(lua_State *L, hv_lua_entry_fn entry, void *user, const hv_progress *progress);
/* The runner's progress for a library call (NULL when none). */
const hv_progress *hv_lua_progress(lua_State *L);
/* Register each function of `fns` into the table at the top of the stack, wrapped to enter. */
void hv_lua_set_funcs(lua_State *L, const luaL_Reg *fns);

/* ---- classes and shared helpers (lhovox.c) ---------------------------------------------------- */
#define MT_MESH "hovox.Mesh"
#define MT_MODEL "hovox.Model"
#define MT_MATS "hovox.Materials"
#define MT_FEATURE "hovox.Feature"
#define MT_SOURCE "hovox.Source"
#define MT_OBJECT "hovox.Object"

typedef struct { hv_mesh *p; } l_mesh;
typedef struct { hv_volume *p; hv_material_table *mats; } l_model;
typedef struct { hv_material_table *p; } l_mats;
typedef struct { hv_frf *p; } l_feature;
typedef struct { hv_ags *p; } l_source;
typedef struct { hv_object *p; } l_object;

/* A new zeroed userdata of class `mt` (one user value) on the stack. */
void *hv_lua_new_ud(lua_State *L, size_t size, const char *mt);
/* The userdata of class `mt` at `arg`, raising "bad argument" when it is of another type or
 * was freed. */
void *hv_lua_check_live(lua_State *L, int arg, const char *mt);
#define CHECK(L, arg, type, mt) ((type *)hv_lua_check_live(L, arg, mt))
/* Option `key` of the table at `arg` as a live userdata of class `mt`, pushed (it stays on the
 * stack, anchored, while C uses it); raises "bad argument #arg (<key> must be a <what>)" or
 * "(<key> was freed)". */
void *hv_lua_option_object(lua_State *L, int arg, const char *key, const char *mt, const char *what);
/* For a class's free and __gc: the C object of the userdata of class `mt` at 1, which is left
 * freed (NULL); the caller releases what it returns (hv_lua_release; NULL allowed). */
void *hv_lua_take(lua_State *L, const char *mt);
/* Register class `name`: methods as __index (each wrapped to enter, except gc, which is the
 * class's free), gc as __gc and __close, tostring (may be NULL; wrapped), __name, and a locked
 * __metatable. */
void hv_lua_new_class(lua_State *L, const char *name, const luaL_Reg *methods, lua_CFunction gc,
                      lua_CFunction tostring);
/* Add methods to an existing class. */
void hv_lua_add_methods(lua_State *L, const char *name, const luaL_Reg *methods);
hv_volume *hv_lua_model(lua_State *L, int arg);
hv_mesh *hv_lua_mesh(lua_State *L, int arg);
void hv_lua_push_model(lua_State *L, hv_volume *vol);
void hv_lua_push_mesh(lua_State *L, hv_mesh *mesh);
/* What model:layers, mesh:layers and hovox.layers_scan return (loutput.c): {width, height, layers,
 * first, last, object_pixels, diff_mean, diff_max (compared), warnings, materials = {<name of t> =
 * {target, achieved}}, colour = {skin_voxels | printer_voxels (skin->printer_voxels),
 * mean_de2000_target, max_de2000_target, mean_de2000_achieved (halftone)} when skin}. */
struct hv_layers_report;
struct hv_colour_skin;
void hv_lua_push_layers_report(lua_State *L, const struct hv_layers_report *r, const hv_material_table *t,
                               const struct hv_colour_skin *skin);
int hv_lua_model_free(lua_State *L);
/* A grading source from the options table at `arg` (hovox.ags's keys); the caller owns it. */
hv_ags *hv_lua_source_arg(lua_State *L, int arg);
void hv_lua_push_source(lua_State *L, hv_ags *a);
/* Raise the library's message for a failed call (after the call has returned). */
int hv_lua_fail(lua_State *L, hv_status status);
/* The status of the library failure whose error text (with its place) is `message`, the last
 * one raised; HV_OK for any other error. So a runner gives a script ended by a library failure
 * the exit code the command would (3 for a plan over the memory limit). hv_lua_note_failure
 * records a failure's text again when a binding rewrites it. */
hv_status hv_lua_failure_status(lua_State *L, const char *message);
void hv_lua_note_failure(lua_State *L, hv_status status, const char *message);
/* luaL_argerror with a printf-style message (C formats: %g for numbers). */
int hv_lua_arg_error(lua_State *L, int arg, const char *fmt, ...) HV_PRINTF(3, 4);
#define arg_error hv_lua_arg_error
#define fail hv_lua_fail
/* A list of at most `max` finite numbers at stack index idx (a positional argument, not an
 * option). Returns the count. */
int hv_lua_numbers(lua_State *L, int idx, int arg, const char *what, double *out, int max);
void hv_lua_push_vec(lua_State *L, const double *v, int n);

/* ---- option tables (lopts.c) ------------------------------------------------------------------
 * A binding reads its options table through the library's option set: hv_lua_options pads the
 * stack to `arg` and pushes a holder (a table the script cannot reach) that owns private copies
 * of every string read, alive until the C function returns; hv_lua_read_options checks that
 * argument `arg` is a plain table (no metatable) or nil, refuses keys that are neither options
 * of `set` nor in `extra` (the keys the binding reads itself: objects, paths), reads each value
 * raw, and checks the rules; any refusal raises "bad argument #arg (<key> must be ...)". */
int hv_lua_options(lua_State *L, int arg);
int hv_lua_holder(lua_State *L);
void hv_lua_check_plain_table(lua_State *L, int arg);
const char *hv_lua_copy_string(lua_State *L, int holder, const char *s, size_t len);
void hv_lua_read_options(lua_State *L, int arg, const hv_option_set *set, void *opts, const char *const *extra,
                         int holder);
/* The same for a table at stack index idx nested in argument `arg` (refusals name arg). */
void hv_lua_read_nested(lua_State *L, int idx, int arg, const hv_option_set *set, void *opts, const char *const *extra,
                        int holder);
/* The usual start of a binding: hv_lua_options(L, arg), then hv_lua_read_options. Returns the
 * holder. */
int hv_lua_read(lua_State *L, int arg, const hv_option_set *set, void *opts, const char *const *extra);
/* Push the raw value of field `key` of the table at `arg` (nil when arg is not a table);
 * returns its type. */
int hv_lua_field(lua_State *L, int arg, const char *key);
/* A private copy (in holder) of string field `key`, NULL when absent; raises on another type. */
const char *hv_lua_string_field(lua_State *L, int arg, const char *key, int holder);
/* The same for a table nested in argument `arg` (at stack index tbl); errors name argument `arg`,
 * prefixed by `where` ("part 2: "). */
const char *hv_lua_string_in(lua_State *L, int tbl, int arg, const char *where, const char *key, int holder);
/* The same for an output path: required when `what` is not NULL ("path is required (<what>)"),
 * checked against the sandbox. */
const char *hv_lua_out_path(lua_State *L, int arg, const char *key, int holder, const char *what);
/* Check every output path option (HV_OPT_OUT_PATH) of opts against the sandbox; call right
 * before the library call that writes them. */
void hv_lua_check_paths(lua_State *L, int arg, const hv_option_set *set, const void *opts);

/* ---- registration (one per binding file) ------------------------------------------------------
 * Each creates its classes and sets its functions into the module table at `module`. */
void hv_lua_open_mesh(lua_State *L, int module);
void hv_lua_open_model(lua_State *L, int module);
void hv_lua_open_sources(lua_State *L, int module);
void hv_lua_open_output(lua_State *L, int module);
void hv_lua_open_object(lua_State *L, int module);
void hv_lua_open_tray(lua_State *L, int module);
void hv_lua_open_scan(lua_State *L, int module);
void hv_lua_open_assembly(lua_State *L, int module); /* after the model's class */

#endif
