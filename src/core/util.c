/* src/core/util.c - checked allocation, growable strings, whole-file reads, atomic writes. */
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "internal.h"

const char *hv_basename(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

void *hv_malloc(size_t size)
{
    void *p = malloc(size ? size : 1);
    if (!p) hv_error_set(HV_ERR_NOMEM, "out of memory (allocating %zu bytes)", size);
    return p;
}

void *hv_calloc(size_t count, size_t size)
{
    void *p = calloc(count ? count : 1, size ? size : 1);
    if (!p) hv_error_set(HV_ERR_NOMEM, "out of memory (allocating %zu x %zu bytes)", count, size);
    return p;
}

void *hv_realloc(void *p, size_t size)
{
    void *q = realloc(p, size ? size : 1);
    if (!q) hv_error_set(HV_ERR_NOMEM, "out of memory (allocating %zu bytes)", size);
    return q;
}

/* 1 when count*size fits in size_t, else 0 with HV_ERR_LIMIT recorded */
static int array_fits(size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size) {
        hv_error_set(HV_ERR_LIMIT, "array of %zu x %zu bytes exceeds the address space", count,
                     size);
        return 0;
    }
    return 1;
}

void *hv_malloc_array(size_t count, size_t size)
{
    return array_fits(count, size) ? hv_malloc(count * size) : NULL;
}

void *hv_malloc_big(size_t count, size_t size)
{
    if (!array_fits(count, size)) return NULL;
    size_t bytes = count * size, huge = (size_t)2 << 20;
    if (bytes < 4 * huge) return hv_malloc(bytes);
    void *p = NULL;
    if (posix_memalign(&p, huge, bytes) != 0) {
        hv_error_set(HV_ERR_NOMEM, "out of memory (allocating %zu bytes)", bytes);
        return NULL;
    }
#ifdef MADV_HUGEPAGE
    (void)madvise(p, bytes, MADV_HUGEPAGE); /* advice only: without it, 4 KiB pages */
#endif
    return p;
}

void *hv_realloc_big(void *p, size_t size)
{
    void *q = hv_realloc(p, size);
#ifdef MADV_HUGEPAGE
    size_t huge = (size_t)2 << 20;
    if (q && size >= 4 * huge) { /* the whole 2 MiB pages inside it (pages touched before stay as they are) */
        uintptr_t a = ((uintptr_t)q + huge - 1) & ~(uintptr_t)(huge - 1), e = ((uintptr_t)q + size) & ~(uintptr_t)(huge - 1);
        if (e > a) (void)madvise((void *)a, e - a, MADV_HUGEPAGE);
    }
#endif
    return q;
}

void *hv_calloc_big(size_t count, size_t size)
{
    void *p = hv_malloc_big(count, size);
    if (p) memset(p, 0, count * size);
    return p;
}

char *hv_strdup(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = hv_malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

hv_status hv_grow(void **p, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap) return HV_OK;
    size_t c = *cap ? *cap : 16;
    while (c < need) {
        if (c > SIZE_MAX / 2 / size) return hv_error_set(HV_ERR_LIMIT, "array too large");
        c *= 2;
    }
    void *q = hv_realloc(*p, c * size);
    if (!q) return HV_ERR_NOMEM;
    *p = q;
    *cap = c;
    return HV_OK;
}

/* ---- hv_buf ---------------------------------------------------------------------------- */

void hv_buf_init(hv_buf *b) { memset(b, 0, sizeof *b); }

void hv_buf_free(hv_buf *b)
{
    free(b->data);
    hv_buf_init(b);
}

void hv_buf_put_escaped(hv_buf *b, const char *s)
{
    for (; *s; ++s) {
        switch (*s) {
        case '&': hv_buf_puts(b, "&amp;"); break;
        case '<': hv_buf_puts(b, "&lt;"); break;
        case '>': hv_buf_puts(b, "&gt;"); break;
        case '"': hv_buf_puts(b, "&quot;"); break;
        case '\'': hv_buf_puts(b, "&#39;"); break;
        default: hv_buf_append(b, s, 1);
        }
    }
}

void hv_buf_append(hv_buf *b, const char *s, size_t n)
{
    if (b->failed) return;
    if (b->len + n + 1 > b->cap) {
        size_t c = b->cap ? b->cap : 256;
        while (c < b->len + n + 1) c *= 2;
        char *d = realloc(b->data, c);
        if (!d) {
            b->failed = 1;
            hv_error_set(HV_ERR_NOMEM, "out of memory (text of %zu bytes)", c);
            return;
        }
        b->data = d;
        b->cap = c;
    }
    memcpy(b->data + b->len, s, n);
    b->len += n;
    b->data[b->len] = '\0';
}

void hv_buf_puts(hv_buf *b, const char *s) { hv_buf_append(b, s, strlen(s)); }

void hv_buf_vprintf(hv_buf *b, const char *fmt, va_list ap)
{
    char small[256];
    va_list ap2;
    va_copy(ap2, ap);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    if (n < 0) {
        va_end(ap2);
        return;
    }
    if ((size_t)n < sizeof small) {
        hv_buf_append(b, small, (size_t)n);
    } else {
        char *big = malloc((size_t)n + 1);
        if (big) {
            vsnprintf(big, (size_t)n + 1, fmt, ap2);
            hv_buf_append(b, big, (size_t)n);
            free(big);
        } else {
            b->failed = 1;
        }
    }
    va_end(ap2);
}

void hv_buf_printf(hv_buf *b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    hv_buf_vprintf(b, fmt, ap);
    va_end(ap);
}

/* ---- files ----------------------------------------------------------------------------- */

hv_status hv_read_file(const char *path, size_t max, char **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    int fd = open(path, O_RDONLY);
    if (fd < 0) return hv_error_set(HV_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int e = errno;
        close(fd);
        return hv_error_set(HV_ERR_IO, "%s: cannot stat: %s", path, strerror(e));
    }
    if (S_ISDIR(st.st_mode)) {
        close(fd);
        return hv_error_set(HV_ERR_IO, "%s: is a directory, not a file", path);
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return hv_error_set(HV_ERR_IO, "%s: not a regular file", path);
    }
    if ((uint64_t)st.st_size > max) {
        close(fd);
        return hv_error_set(HV_ERR_LIMIT, "%s: file of %lld bytes exceeds the limit of %zu bytes",
                            path, (long long)st.st_size, max);
    }
    size_t n = (size_t)st.st_size;
    char *buf = malloc(n + 1);
    if (!buf) {
        close(fd);
        return hv_error_set(HV_ERR_NOMEM, "%s: out of memory reading %zu bytes", path, n);
    }
    size_t got = 0;
    while (got < n) {
        ssize_t r = read(fd, buf + got, n - got);
        if (r < 0) {
            if (errno == EINTR) continue;
            int e = errno;
            free(buf);
            close(fd);
            return hv_error_set(HV_ERR_IO, "%s: read failed: %s", path, strerror(e));
        }
        if (r == 0) break;
        got += (size_t)r;
    }
    close(fd);
    buf[got] = '\0';
    *data = buf;
    *size = got;
    return HV_OK;
}

static atomic_uint g_temp_counter;

const char *hv_size_text(char *buf, size_t size, double bytes)
{
    static const char *const unit[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB"};
    int u = 0;
    while (bytes >= 1024.0 && u < 5) {
        bytes /= 1024.0;
        ++u;
    }
    if (u == 0) snprintf(buf, size, "%.0f bytes", bytes);
    else snprintf(buf, size, "%.1f %s", bytes, unit[u]);
    return buf;
}

/* Remove our own temporaries of `base` in `dir` left by processes that are gone (killed in
 * the middle of a write): ".<base>.tmp-<pid>-<n>", regular files of a dead pid only. */
static void clean_stale(const char *dir, size_t dirlen, const char *base)
{
    char d[4096];
    snprintf(d, sizeof d, "%.*s", (int)(dirlen ? dirlen : 1), dirlen ? dir : ".");
    DIR *dp = opendir(d);
    if (!dp) return;
    char prefix[512];
    int plen = snprintf(prefix, sizeof prefix, ".%s.tmp-", base);
    if (plen <= 0 || (size_t)plen >= sizeof prefix) {
        closedir(dp);
        return;
    }
    struct dirent *e;
    while ((e = readdir(dp))) {
        if (strncmp(e->d_name, prefix, (size_t)plen) != 0) continue;
        char *end;
        long pid = strtol(e->d_name + plen, &end, 10);
        if (pid <= 0 || *end != '-' || pid == (long)getpid()) continue;
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue; /* alive, or not ours to judge */
        char full[4600];
        snprintf(full, sizeof full, "%s/%s", d, e->d_name);
        struct stat st;
        if (lstat(full, &st) != 0) continue;
        if (S_ISREG(st.st_mode)) unlink(full);
        else if (S_ISDIR(st.st_mode)) hv_remove_tree(full); /* a writer's scratch directory */
    }
    closedir(dp);
}

hv_status hv_fsync_path(const char *path)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return hv_error_set(HV_ERR_IO, "%s: cannot open to sync: %s", path, strerror(errno));
    int rc = fsync(fd), e = errno;
    close(fd);
    if (rc != 0 && e != EINVAL && e != EROFS) /* special files cannot sync: nothing to lose */
        return hv_error_set(HV_ERR_IO, "%s: writing to disk failed: %s", path, strerror(e));
    return HV_OK;
}

char *hv_temp_path(const char *path)
{
    const char *base = hv_basename(path);
    size_t dirlen = (size_t)(base - path);
    const char *dir = path;
    if (hv_path_is_special(path)) { /* not next to /dev/null: in $TMPDIR, copied by hv_temp_commit */
        const char *t = getenv("TMPDIR");
        dir = t && *t ? t : "/tmp";
        dirlen = strlen(dir);
    }
    if (dir == path) clean_stale(dir, dirlen, base);
    size_t n = dirlen + strlen(base) + 66;
    char *tmp = hv_malloc(n);
    if (!tmp) return NULL;
    snprintf(tmp, n, "%.*s%s.%s.tmp-%ld-%u", (int)dirlen, dir,
             dir != path && dirlen > 0 && dir[dirlen - 1] != '/' ? "/" : "", base, (long)getpid(),
             atomic_fetch_add(&g_temp_counter, 1u));
    hv_temp_track(tmp);
    return tmp;
}

/* ---- temporaries in progress ------------------------------------------------------------------ */

typedef struct temp_entry {
    char *path;
    double since; /* monotonic seconds when tracked */
} temp_entry;

static pthread_mutex_t g_temps_lock = PTHREAD_MUTEX_INITIALIZER;
static temp_entry *g_temps;
static size_t g_ntemps, g_temps_cap;

static double monotonic_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void hv_temp_track(const char *path)
{
    char *copy = strdup(path);
    if (!copy) return;
    double now = monotonic_seconds();
    pthread_mutex_lock(&g_temps_lock);
    if (g_ntemps == g_temps_cap) {
        /* forget the names that are gone (renamed into place or removed); a name is tracked
         * before its file is made, so only those older than a second */
        size_t n = 0;
        struct stat st;
        for (size_t i = 0; i < g_ntemps; ++i) {
            if (now - g_temps[i].since > 1.0 && lstat(g_temps[i].path, &st) != 0) free(g_temps[i].path);
            else g_temps[n++] = g_temps[i];
        }
        g_ntemps = n;
        if (2 * n >= g_temps_cap) { /* still half full: grow */
            size_t cap = g_temps_cap ? 2 * g_temps_cap : 32;
            temp_entry *t = realloc(g_temps, cap * sizeof *t);
            if (t) {
                g_temps = t;
                g_temps_cap = cap;
            }
        }
    }
    if (g_ntemps < g_temps_cap) g_temps[g_ntemps++] = (temp_entry){copy, now};
    else free(copy);
    pthread_mutex_unlock(&g_temps_lock);
}

void hv_temp_remove_all(void)
{
    pthread_mutex_lock(&g_temps_lock); /* never unlocked: the process is ending */
    for (size_t i = 0; i < g_ntemps; ++i) {
        /* renamed first: the writer, still running, either renamed it into place before (a
         * complete output: left alone) or can no longer (nor add to it by its name) */
        char gone[PATH_MAX];
        struct stat st;
        if (snprintf(gone, sizeof gone, "%s-ended", g_temps[i].path) >= (int)sizeof gone ||
            rename(g_temps[i].path, gone) != 0)
            continue;
        for (int tries = 0; tries < 100 && lstat(gone, &st) == 0; ++tries) hv_remove_tree(gone);
    }
}

hv_status hv_temp_commit(const char *tmp, const char *path)
{
    if (!hv_path_is_special(path)) {
        hv_status s = hv_output_check(path, 0);
        if (s != HV_OK) {
            unlink(tmp);
            return s;
        }
        if (rename(tmp, path) == 0) return HV_OK;
        return hv_error_set(HV_ERR_IO, "%s: cannot rename into place: %s", path, strerror(errno));
    }
    /* a device, FIFO or socket: stream the bytes into it, never replace it */
    FILE *in = fopen(tmp, "rb"), *out = in ? fopen(path, "wb") : NULL;
    hv_status s = HV_OK;
    if (!in || !out) {
        s = hv_error_set(HV_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    } else {
        char buf[1 << 16];
        size_t n;
        while ((n = fread(buf, 1, sizeof buf, in)) > 0)
            if (fwrite(buf, 1, n, out) != n) {
                s = hv_error_set(HV_ERR_IO, "%s: write failed: %s", path, strerror(errno));
                break;
            }
        if (s == HV_OK && ferror(in)) s = hv_error_set(HV_ERR_IO, "%s: read failed", tmp);
    }
    if (out && fclose(out) != 0 && s == HV_OK)
        s = hv_error_set(HV_ERR_IO, "%s: write failed: %s", path, strerror(errno));
    if (in) fclose(in);
    unlink(tmp);
    return s;
}

int hv_path_is_special(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}

static int resolved_below(const char *real, const char *root)
{
    size_t n = strlen(root);
    return strncmp(real, root, n) == 0 && (real[n] == '\0' || real[n] == '/' || (n == 1 && root[0] == '/'));
}

int hv_path_below(const char *root, const char *path)
{
    char dir[PATH_MAX], real[PATH_MAX], norm[PATH_MAX];
    if (strlen(path) >= sizeof dir) return 0;
    /* what a writer makes of the name: "out/", "out/." and "out/./" name out itself, whose
     * temporary (a stack's ".out.tmp-PID") is made beside it, in its parent */
    snprintf(norm, sizeof norm, "%s", path);
    for (size_t n = strlen(norm);;) {
        while (n > 1 && norm[n - 1] == '/') norm[--n] = '\0';
        if (n >= 2 && norm[n - 1] == '.' && norm[n - 2] == '/') norm[--n] = '\0';
        else break;
    }
    const char *last = hv_basename(norm);
    if (!*last || strcmp(last, ".") == 0 || strcmp(last, "..") == 0) return 0; /* not a name of its own */
    path = norm;
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash) {
        if (slash == dir) slash[1] = '\0';
        else *slash = '\0';
    } else {
        snprintf(dir, sizeof dir, ".");
    }
    if (!realpath(dir, real) || !resolved_below(real, root)) return 0;
    struct stat st;
    if (lstat(path, &st) == 0 && S_ISLNK(st.st_mode)) return realpath(path, real) && resolved_below(real, root);
    return 1;
}

hv_status hv_atomic_open(hv_atomic_file *af, const char *path, const char *mode)
{
    memset(af, 0, sizeof *af);
    if (hv_path_is_special(path)) { /* /dev/null, /dev/stdout, a FIFO: write in place */
        af->path = hv_strdup(path);
        if (!af->path) return HV_ERR_NOMEM;
        af->fp = fopen(path, mode);
        if (!af->fp) {
            int e = errno;
            free(af->path);
            memset(af, 0, sizeof *af);
            return hv_error_set(HV_ERR_IO, "%s: cannot write: %s", path, strerror(e));
        }
        return HV_OK;
    }
    hv_status s = hv_output_check(path, 0);
    if (s != HV_OK) return s;
    af->path = hv_strdup(path);
    af->tmp = hv_temp_path(path);
    if (!af->path || !af->tmp) {
        hv_atomic_abort(af);
        return HV_ERR_NOMEM;
    }
    af->fp = fopen(af->tmp, mode);
    if (!af->fp) {
        int e = errno;
        free(af->path);
        free(af->tmp);
        memset(af, 0, sizeof *af);
        return hv_error_set(HV_ERR_IO, "%s: cannot write: %s", path, strerror(e));
    }
    return HV_OK;
}

hv_status hv_atomic_commit(hv_atomic_file *af)
{
    /* every write, the flush, the sync and the close are checked: a full disk is an error,
     * never a short file under the final name */
    int bad = ferror(af->fp);
    int e = errno;
    if (!bad && fflush(af->fp) != 0) {
        bad = 1;
        e = errno;
    }
    if (!bad && af->tmp && fsync(fileno(af->fp)) != 0 && errno != EINVAL) {
        bad = 1;
        e = errno;
    }
    if (fclose(af->fp) != 0) {
        bad = 1;
        e = errno;
    }
    af->fp = NULL;
    if (bad) {
        hv_status s = hv_error_set(HV_ERR_IO, "%s: write failed: %s", af->path, strerror(e));
        hv_atomic_abort(af);
        return s;
    }
    if (!af->tmp) { /* a special file, written in place */
        free(af->path);
        memset(af, 0, sizeof *af);
        return HV_OK;
    }
    hv_status refused = hv_output_check(af->path, 0);
    if (refused != HV_OK) {
        hv_atomic_abort(af);
        return refused;
    }
    if (rename(af->tmp, af->path) != 0) {
        e = errno;
        hv_status s = hv_error_set(HV_ERR_IO, "%s: cannot rename into place: %s", af->path,
                                   strerror(e));
        hv_atomic_abort(af);
        return s;
    }
    free(af->path);
    free(af->tmp);
    memset(af, 0, sizeof *af);
    return HV_OK;
}

void hv_atomic_abort(hv_atomic_file *af)
{
    if (af->fp) fclose(af->fp);
    if (af->tmp) unlink(af->tmp);
    free(af->path);
    free(af->tmp);
    memset(af, 0, sizeof *af);
}

int hv_has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), k = strlen(ext);
    return n >= k && strcasecmp(path + n - k, ext) == 0;
}

hv_status hv_check_extension(const char *path, const char *ext, const char *what)
{
    if (!path || hv_path_is_special(path) || hv_has_extension(path, ext)) return HV_OK;
    return hv_error_set(HV_ERR_INVALID, "%s: %s is written as %s, which this name does not end in", path, what, ext);
}

hv_status hv_write_in_place(const char *path, const void *data, size_t size)
{
    FILE *fp = fopen(path, "wb");
    if (!fp) return hv_error_set(HV_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    int bad = size && fwrite(data, 1, size, fp) != size, e = errno;
    if (!bad && fflush(fp) != 0) {
        bad = 1;
        e = errno;
    }
    if (fclose(fp) != 0 && !bad) {
        bad = 1;
        e = errno;
    }
    if (!bad) return HV_OK;
    remove(path);
    return hv_error_set(HV_ERR_IO, "%s: write failed: %s", path, strerror(e));
}

hv_status hv_atomic_write(const char *path, const void *data, size_t size)
{
    hv_atomic_file af;
    hv_status st = hv_atomic_open(&af, path, "wb");
    if (st != HV_OK) return st;
    if (size && fwrite(data, 1, size, af.fp) != size) {
        int e = errno;
        hv_atomic_abort(&af);
        return hv_error_set(HV_ERR_IO, "%s: write failed: %s", path, strerror(e));
    }
    return hv_atomic_commit(&af);
}
