/* src/lua/lhovox.h - the `hovox` Lua 5.4 module: modeling scripts over the C library. */
#ifndef HOVOX_LHOVOX_H
#define HOVOX_LHOVOX_H

#include <lua.h>

/* Open the module (pushes the `hovox` table). */
int luaopen_hovox(lua_State *L);

/* Sandbox: file writes by the module (and by io.open/io.output/os.remove/os.rename when
 * hv_lua_sandbox has been applied) are allowed only below `dir` (NULL: no restriction). */
void hv_lua_set_write_root(lua_State *L, const char *dir);

/* Remove os.execute, io.popen, package.loadlib and C searchers; wrap io.open, io.output,
 * os.remove, os.rename, os.tmpname to honour the write root. Call after the standard
 * libraries are open and the write root is set. */
void hv_lua_sandbox(lua_State *L);

/* Shared by the binding files: the live object behind argument `arg` (raising "bad argument"
 * when it is of another type or freed), pushing new objects, raising a library failure. */
#include "hovox/material.h"
hv_volume *hv_lua_model(lua_State *L, int arg);
hv_mesh *hv_lua_mesh(lua_State *L, int arg);
void hv_lua_push_model(lua_State *L, hv_volume *vol);
int hv_lua_fail(lua_State *L, hv_status status);
/* luaL_argerror with a printf-style message (C formats: %g for numbers). */
int hv_lua_arg_error(lua_State *L, int arg, const char *fmt, ...) HV_PRINTF(3, 4);
#define arg_error hv_lua_arg_error

/* Check that the argument at idx is an options table: a table whose keys are all named in
 * `keys` (NULL-terminated). Raises "bad argument #arg (unknown option 'x' (options: a, b,
 * ...))" otherwise, so a mistyped option never falls back to its default silently. */
void hv_lua_check_options(lua_State *L, int idx, int arg, const char *const *keys);

/* Raise "bad argument" unless writing `path` is allowed (for module functions). Returns path. */
const char *hv_lua_check_write(lua_State *L, int arg, const char *path);

/* ---- option tables (lopts.c) ------------------------------------------------------------------
 * A binding reads its options table through the library's option set: hv_lua_holder pushes a
 * holder (a table the script cannot reach) that owns private copies of every string read, alive
 * until the C function returns; hv_lua_read_options checks that argument `arg` is a plain table
 * (no metatable), refuses keys that are neither options of `set` nor in `extra` (the keys the
 * binding reads itself: objects, paths), reads each value raw, and checks the rules; any
 * refusal raises "bad argument #arg (<key> must be ...)". */
int hv_lua_holder(lua_State *L);
void hv_lua_check_plain_table(lua_State *L, int arg);
const char *hv_lua_copy_string(lua_State *L, int holder, const char *s, size_t len);
void hv_lua_read_options(lua_State *L, int arg, const hv_option_set *set, void *opts, hv_optargs *args,
                         const char *const *extra, int holder);
/* Push the raw value of field `key` of the table at `arg` (nil when arg is not a table);
 * returns its type. */
int hv_lua_field(lua_State *L, int arg, const char *key);
/* A private copy (in holder) of string field `key`, NULL when absent; raises on another type. */
const char *hv_lua_string_field(lua_State *L, int arg, const char *key, int holder);
/* Check every output path option (HV_OPT_OUT_PATH) of opts against the sandbox; call right
 * before the library call that writes them. */
void hv_lua_check_paths(lua_State *L, int arg, const hv_option_set *set, const void *opts);

#endif
