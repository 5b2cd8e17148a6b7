/* src/core/plugin.c - the one plugin loader (plugin.h): finds plugins/hovox-<name>.so, resolves its
 * entry point once per process and checks the ABI of the table it returns. */
#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "internal.h"
#include "plugin.h"


#ifndef HV_PLUGIN_BUILD_DIR
#define HV_PLUGIN_BUILD_DIR ""
#endif

static void *try_open(const char *dir, const char *name, hv_buf *tried)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/%s.so", dir, name);
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char *e = dlerror();
        /* keep the loader's reason when the file exists: that is the useful one */
        if (access(path, F_OK) == 0) hv_buf_printf(tried, " %s (%s);", path, e ? e : "?");
        else hv_buf_printf(tried, " %s (missing);", path);
    }
    return h;
}

hv_status hv_plugin_symbol(const char *name, const char *symbol, void **out)
{
    *out = NULL;
    hv_buf tried;
    hv_buf_init(&tried);
    void *h = NULL;
    const char *env = getenv("HOVOX_PLUGIN_DIR");
    if (env && *env) h = try_open(env, name, &tried);
    char exe[PATH_MAX] = "";
    if (!h) {
        ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
        if (n > 0) {
            exe[n] = '\0';
            char *slash = strrchr(exe, '/');
            if (slash) *slash = '\0';
            static const char *const rel[] = {"/plugins", "/../plugins", "/../lib/hovox/plugins"};
            for (size_t i = 0; i < HV_COUNT(rel) && !h; ++i) {
                char dir[PATH_MAX];
                snprintf(dir, sizeof dir, "%s%s", exe, rel[i]);
                h = try_open(dir, name, &tried);
            }
        }
    }
    if (!h) {
        /* the file that holds the library (libhovox.so, or a program or Python extension linked
         * with libhovox.a): a package ships its plugins beside it */
        Dl_info info;
        char dir[PATH_MAX];
        if (dladdr((void *)hv_plugin_symbol, &info) && info.dli_fname && realpath(info.dli_fname, dir)) {
            *strrchr(dir, '/') = '\0';
            size_t len = strlen(dir);
            /* a program's own directory was tried above */
            if (strcmp(dir, exe) != 0 && len + sizeof "/plugins" <= sizeof dir) {
                memcpy(dir + len, "/plugins", sizeof "/plugins");
                h = try_open(dir, name, &tried);
            }
        }
    }
    if (!h && HV_PLUGIN_BUILD_DIR[0]) h = try_open(HV_PLUGIN_BUILD_DIR, name, &tried);
    if (!h) {
        hv_status s = hv_error_set(HV_ERR_UNSUPPORTED, "plugin %s not found; tried:%s", name,
                                   tried.data ? tried.data : " nothing");
        hv_buf_free(&tried);
        return s;
    }
    hv_buf_free(&tried);
    void *sym = dlsym(h, symbol);
    if (!sym) return hv_error_set(HV_ERR_UNSUPPORTED, "plugin %s has no symbol %s", name, symbol);
    *out = sym;
    return HV_OK;
}

static pthread_mutex_t g_plugin_lock = PTHREAD_MUTEX_INITIALIZER;

static void plugin_load(hv_plugin *p)
{
    void *sym = NULL;
    p->status = hv_plugin_symbol(p->file, p->entry, &sym);
    if (p->status == HV_OK) {
        const void *api = ((const void *(*)(void))sym)();
        if (!api || *(const int *)api != p->abi)
            p->status = hv_error_set(HV_ERR_UNSUPPORTED, "%s failed to initialise or has a different ABI", p->what);
        else
            p->api = api;
    }
    if (p->status != HV_OK) snprintf(p->error, sizeof p->error, "%s", hv_last_error());
}

hv_status hv_plugin_api(hv_plugin *p, const void **api)
{
    pthread_mutex_lock(&g_plugin_lock);
    if (!p->tried) {
        plugin_load(p);
        p->tried = 1;
    }
    pthread_mutex_unlock(&g_plugin_lock);
    *api = p->api;
    if (p->status != HV_OK) return hv_error_set(p->status, "%s", p->error);
    return HV_OK;
}
