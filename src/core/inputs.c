/* src/core/inputs.c - what a command reads, so that it never writes over it (issue 32 item 8): readers
 * note the files they open, writers check their target before they create it and again before
 * they rename it into place. Files are compared by device and inode (any path, symbolic link or
 * hard link to an input is the input); a directory that is written whole must not hold an input. */
#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "internal.h"

typedef struct input_file {
    dev_t dev;
    ino_t ino;
    char *path; /* as given, for messages */
    char *real; /* realpath, for the directory check */
} input_file;

static pthread_mutex_t g_lock = PTHREAD_MUTEX_INITIALIZER;
static int g_on; /* a front end started a command (hv_inputs_reset) */
static input_file *g_inputs;
static size_t g_count, g_cap;

void hv_input_note(const char *path)
{
    struct stat st;
    if (!path || stat(path, &st) != 0 || !S_ISREG(st.st_mode)) return; /* devices and pipes are read in place */
    pthread_mutex_lock(&g_lock);
    int known = !g_on;
    for (size_t i = 0; i < g_count && !known; ++i) known = g_inputs[i].dev == st.st_dev && g_inputs[i].ino == st.st_ino;
    if (!known && hv_grow((void **)&g_inputs, &g_cap, g_count + 1, sizeof *g_inputs) == HV_OK) {
        input_file *f = &g_inputs[g_count];
        f->dev = st.st_dev;
        f->ino = st.st_ino;
        f->path = hv_strdup(path);
        f->real = realpath(path, NULL);
        if (f->path) ++g_count;
        else free(f->real);
    }
    pthread_mutex_unlock(&g_lock);
}

void hv_inputs_reset(void)
{
    pthread_mutex_lock(&g_lock);
    for (size_t i = 0; i < g_count; ++i) {
        free(g_inputs[i].path);
        free(g_inputs[i].real);
    }
    free(g_inputs);
    g_inputs = NULL;
    g_count = g_cap = 0;
    g_on = 1;
    pthread_mutex_unlock(&g_lock);
}

/* 1 when real lies inside the directory dir (both real paths). */
static int inside(const char *real, const char *dir)
{
    size_t n = strlen(dir);
    return strncmp(real, dir, n) == 0 && (real[n] == '/' || (n == 1 && dir[0] == '/'));
}

hv_status hv_output_check(const char *path, int is_dir)
{
    struct stat st;
    if (!path || stat(path, &st) != 0) return HV_OK; /* nothing there yet: no input can be it */
    char *dir = is_dir && S_ISDIR(st.st_mode) ? realpath(path, NULL) : NULL;
    hv_status s = HV_OK;
    pthread_mutex_lock(&g_lock);
    for (size_t i = 0; i < g_count && s == HV_OK; ++i) {
        const input_file *f = &g_inputs[i];
        if (f->dev == st.st_dev && f->ino == st.st_ino)
            s = strcmp(f->path, path) == 0
                    ? hv_error_set(HV_ERR_INVALID, "%s: is an input of this command: refusing to write over it", path)
                    : hv_error_set(HV_ERR_INVALID, "%s: is %s, an input of this command: refusing to write over it",
                                   path, f->path);
        else if (dir && f->real && inside(f->real, dir))
            s = hv_error_set(HV_ERR_INVALID, "%s: holds %s, an input of this command: refusing to replace it", path,
                             f->path);
    }
    pthread_mutex_unlock(&g_lock);
    free(dir);
    return s;
}
