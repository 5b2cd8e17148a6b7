/* src/core/outdir.c - output directories written whole (see internal.h): a job writes into a
 * hidden temporary sibling and renames it into place when complete; an existing directory is
 * replaced only when everything in it is what such a job writes. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <fnmatch.h>
#include <ftw.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "internal.h"

/* parent directory and last component of `dir` (trailing slashes ignored); caller frees */
static hv_status split_path(const char *dir, char **parent, char **name)
{
    size_t n = strlen(dir);
    while (n > 1 && dir[n - 1] == '/') --n;
    if (n == 0) return hv_error_set(HV_ERR_INVALID, "empty output directory name");
    size_t s = n;
    while (s > 0 && dir[s - 1] != '/') --s;
    *name = hv_malloc(n - s + 1);
    *parent = hv_malloc(s + 2);
    if (!*name || !*parent) {
        free(*name);
        free(*parent);
        return HV_ERR_NOMEM;
    }
    memcpy(*name, dir + s, n - s);
    (*name)[n - s] = '\0';
    if (s == 0) {
        strcpy(*parent, ".");
    } else {
        memcpy(*parent, dir, s);
        (*parent)[s] = '\0';
    }
    if (strcmp(*name, ".") == 0 || strcmp(*name, "..") == 0 || strcmp(*name, "/") == 0) {
        free(*name);
        free(*parent);
        return hv_error_set(HV_ERR_INVALID, "%s: name the output directory itself (not . or ..)", dir);
    }
    return HV_OK;
}

/* "<parent>/.<name>.<tag>-<pid>" */
static char *sibling(const char *dir, const char *tag, long pid)
{
    char *parent = NULL, *name = NULL;
    if (split_path(dir, &parent, &name) != HV_OK) return NULL;
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_printf(&b, "%s%s.%s.%s-%ld", parent, strcmp(parent, ".") == 0 ? "/" : "", name, tag, pid);
    free(parent);
    free(name);
    if (b.failed) {
        hv_buf_free(&b);
        return NULL;
    }
    return b.data;
}

static int rm_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb;
    (void)ftw;
    if (flag == FTW_DP) rmdir(path);
    else unlink(path);
    return 0;
}

void hv_remove_tree(const char *path)
{
    if (path && *path) nftw(path, rm_entry, 16, FTW_DEPTH | FTW_PHYS);
}

/* Remove the temporaries of jobs on `dir` whose process is gone (killed, or crashed), and our
 * own leftovers: "<parent>/.<name>.tmp-<pid>" and ".old-<pid>". */
static void remove_stale(const char *dir)
{
    char *parent = NULL, *name = NULL;
    if (split_path(dir, &parent, &name) != HV_OK) {
        hv_error_clear();
        return;
    }
    DIR *d = opendir(parent);
    size_t nl = strlen(name);
    for (struct dirent *e; d && (e = readdir(d)) != NULL;) {
        const char *s = e->d_name;
        if (s[0] != '.' || strncmp(s + 1, name, nl) != 0 || s[1 + nl] != '.') continue;
        const char *tag = s + 2 + nl;
        if (strncmp(tag, "tmp-", 4) != 0 && strncmp(tag, "old-", 4) != 0) continue;
        char *end = NULL;
        long pid = strtol(tag + 4, &end, 10);
        if (!end || *end || pid <= 0) continue;
        if (pid != (long)getpid() && !(kill((pid_t)pid, 0) != 0 && errno == ESRCH)) continue;
        hv_buf p;
        hv_buf_init(&p);
        hv_buf_printf(&p, "%s/%s", parent, s);
        if (!p.failed) hv_remove_tree(p.data);
        hv_buf_free(&p);
    }
    if (d) closedir(d);
    free(parent);
    free(name);
}

static int matches(const hv_outdir_rules *r, const char *file)
{
    for (const char *const *p = r->files; p && *p; ++p)
        if (fnmatch(*p, file, 0) == 0) return 1;
    return 0;
}

/* Is everything under `path` (depth levels of subdirectories allowed) a file the rules name?
 * Stores the first entry that is not in `foreign` (relative to the top). */
static int all_ours(const hv_outdir_rules *r, const char *path, const char *rel, int depth,
                    hv_buf *foreign)
{
    DIR *d = opendir(path);
    if (!d) {
        hv_buf_puts(foreign, rel[0] ? rel : ".");
        return 0;
    }
    int ok = 1;
    for (struct dirent *e; ok && (e = readdir(d)) != NULL;) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
        hv_buf full, sub;
        hv_buf_init(&full);
        hv_buf_init(&sub);
        hv_buf_printf(&full, "%s/%s", path, e->d_name);
        hv_buf_printf(&sub, "%s%s%s", rel, rel[0] ? "/" : "", e->d_name);
        struct stat sb;
        if (full.failed || sub.failed || lstat(full.data, &sb) != 0) {
            ok = 0;
        } else if (S_ISDIR(sb.st_mode)) {
            if (depth > 0) ok = all_ours(r, full.data, sub.data, depth - 1, foreign);
            else ok = 0;
        } else {
            ok = S_ISREG(sb.st_mode) && matches(r, e->d_name);
        }
        if (!ok && foreign->len == 0) hv_buf_puts(foreign, sub.failed ? e->d_name : sub.data);
        hv_buf_free(&full);
        hv_buf_free(&sub);
    }
    closedir(d);
    return ok;
}

enum { ABSENT, EMPTY, OURS, FOREIGN, NOT_DIR };

static int classify(const char *dir, const hv_outdir_rules *r, hv_buf *foreign)
{
    struct stat sb;
    if (stat(dir, &sb) != 0) return ABSENT;
    if (!S_ISDIR(sb.st_mode)) return NOT_DIR;
    DIR *d = opendir(dir);
    if (!d) return FOREIGN;
    int empty = 1;
    for (struct dirent *e; (e = readdir(d)) != NULL;)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) {
            empty = 0;
            break;
        }
    closedir(d);
    if (empty) return EMPTY;
    if (r->marker) {
        hv_buf p;
        hv_buf_init(&p);
        hv_buf_printf(&p, "%s/%s", dir, r->marker);
        char *text = NULL;
        size_t size = 0;
        int marked = !p.failed && hv_read_file(p.data, 1 << 30, &text, &size) == HV_OK &&
                     (!r->marker_ok || r->marker_ok(text, size));
        hv_error_clear();
        free(text);
        hv_buf_free(&p);
        if (!marked) return FOREIGN;
    }
    return all_ours(r, dir, "", r->subdirs ? 1 : 0, foreign) ? OURS : FOREIGN;
}

static hv_status refuse(const char *dir, const hv_outdir_rules *r, int kind, const hv_buf *foreign)
{
    if (kind == NOT_DIR) return hv_error_set(HV_ERR_IO, "%s: exists and is not a directory", dir);
    if (foreign->len > 0)
        return hv_error_set(HV_ERR_IO, "%s: holds '%s', which is not part of a hovox %s; refusing to replace it",
                            dir, foreign->data, r->what);
    return hv_error_set(HV_ERR_IO, "%s: directory exists and is not empty (not a hovox %s; refusing to replace it)",
                        dir, r->what);
}

hv_status hv_outdir_begin(const char *dir, const hv_outdir_rules *r, int force, char **tmp)
{
    *tmp = NULL;
    hv_status refused = hv_output_check(dir, 1);
    if (refused != HV_OK) return refused;
    hv_buf foreign;
    hv_buf_init(&foreign);
    int kind = classify(dir, r, &foreign);
    hv_status s = HV_OK;
    if (kind == NOT_DIR || kind == FOREIGN) s = refuse(dir, r, kind, &foreign);
    else if (kind == OURS && r->need_force && !force)
        s = hv_error_option(HV_ERR_IO, "%s: a %s exists there ({force} replaces it)", dir, r->what);
    hv_buf_free(&foreign);
    if (s != HV_OK) return s;
    char *t = sibling(dir, "tmp", (long)getpid());
    if (!t) return hv_error_set(HV_ERR_NOMEM, "out of memory");
    remove_stale(dir);
    if (mkdir(t, 0777) != 0) {
        s = hv_error_set(HV_ERR_IO, "%s: cannot create the output directory: %s", dir, strerror(errno));
        free(t);
        return s;
    }
    *tmp = t;
    return HV_OK;
}

hv_status hv_outdir_commit(const char *tmp, const char *dir, const hv_outdir_rules *r, int force)
{
    /* the files were written without a sync each: one sync of the file system makes them all
     * durable before the rename publishes them */
    int fd = open(tmp, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0 || syncfs(fd) != 0) {
        hv_status s = hv_error_set(HV_ERR_IO, "%s: cannot sync %s before renaming it: %s", dir, tmp, strerror(errno));
        if (fd >= 0) close(fd);
        return s;
    }
    close(fd);
    hv_buf foreign;
    hv_buf_init(&foreign);
    int kind = classify(dir, r, &foreign);
    hv_buf_free(&foreign);
    hv_status refused = hv_output_check(dir, 1);
    if (refused != HV_OK) return refused;
    if (kind == OURS && (force || !r->need_force)) {
        char *old = sibling(dir, "old", (long)getpid());
        if (!old) return hv_error_set(HV_ERR_NOMEM, "out of memory");
        hv_remove_tree(old);
        if (rename(dir, old) != 0) {
            hv_status s = hv_error_set(HV_ERR_IO, "%s: cannot move the old %s aside: %s", dir, r->what, strerror(errno));
            free(old);
            return s;
        }
        if (rename(tmp, dir) != 0) {
            hv_status s = hv_error_set(HV_ERR_IO, "%s: cannot rename %s to it: %s", dir, tmp, strerror(errno));
            if (rename(old, dir) != 0) { /* leave the old one where the user can find it */ }
            free(old);
            return s;
        }
        hv_remove_tree(old);
        free(old);
        return HV_OK;
    }
    if (kind != ABSENT && kind != EMPTY)
        return hv_error_set(HV_ERR_IO, "%s: appeared while the %s was written; not replaced", dir, r->what);
    if (rename(tmp, dir) != 0)
        return hv_error_set(HV_ERR_IO, "%s: cannot rename %s to it: %s", dir, tmp, strerror(errno));
    return HV_OK;
}

void hv_outdir_abort(const char *tmp) { hv_remove_tree(tmp); }
