/* src/core/plugin.h - the one plugin loader: each C++ library sits in a plugin
 * (plugins/hovox-<name>.so) whose entry point returns a table of functions starting with its ABI
 * version. A plugin is loaded on first use, once per process, from $HOVOX_PLUGIN_DIR, next to the
 * executable (plugins/, ../plugins/, ../lib/hovox/plugins/) or the build tree. Internal. */
#ifndef HOVOX_CORE_PLUGIN_H
#define HOVOX_CORE_PLUGIN_H

#include "hovox/core.h"

/* A plugin's description and load state; define one per plugin with HV_PLUGIN_DEF and keep it
 * static. Every API table begins with `int abi`. */
typedef struct hv_plugin {
    const char *file;  /* "hovox-vdb" */
    const char *entry; /* the entry point's symbol: const void *(*)(void) returning the table */
    int abi;           /* the table's abi member must equal this */
    const char *what;  /* "OpenVDB bridge", for messages */
    int tried;
    hv_status status;
    const void *api;
    char error[2048];
} hv_plugin;

#define HV_PLUGIN_DEF(file, entry, abi, what) {file, entry, abi, what, 0, HV_OK, NULL, {0}}

/* The plugin's API table in *api, loading the plugin on the first call (thread-safe). The same
 * failure is reported on every call: HV_ERR_UNSUPPORTED (the plugin is missing, has no entry
 * point, failed to initialise or has another ABI), with the places tried. */
hv_status hv_plugin_api(hv_plugin *p, const void **api);

/* The symbol `symbol` of plugin `name` (the library found as hv_plugin_api finds it).
 * Errors: HV_ERR_UNSUPPORTED. */
hv_status hv_plugin_symbol(const char *name, const char *symbol, void **out);

#endif
