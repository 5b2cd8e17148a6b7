/* src/core/internal.h - helpers shared by hovox modules (not part of the public API):
 * growable buffers, enum names, whole-file reads, atomic writes, plugins and a parallel-for
 * over OpenMP that reports progress from the calling thread (JSON: core/json.h). */
#ifndef HOVOX_INTERNAL_H
#define HOVOX_INTERNAL_H

#include <stdarg.h>
#include <stdio.h>

#include "hovox/core.h"
#include "hovox/options.h"

#ifdef __cplusplus
extern "C" {
#endif

#define HV_MIN(a, b) ((a) < (b) ? (a) : (b))
#define HV_MAX(a, b) ((a) > (b) ? (a) : (b))
#define HV_CLAMP(x, lo, hi) ((x) < (lo) ? (lo) : (x) > (hi) ? (hi) : (x))
#define HV_COUNT(a) (sizeof(a) / sizeof((a)[0]))

/* Hot kernels built twice, for AVX2 (8-wide, gathers) and the x86-64 baseline, chosen at load
 * time (GCC function multiversioning via ifunc). Off elsewhere and under sanitizers. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__gnu_linux__) && \
    !defined(__SANITIZE_ADDRESS__) && !defined(HV_NO_CLONES)
#define HV_HOT_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define HV_HOT_CLONES
#endif

/* File name without directories, for messages. */
const char *hv_basename(const char *path);

/* ---- allocation: NULL on failure with HV_ERR_NOMEM recorded ---------------------------- */
void *hv_malloc(size_t size);
void *hv_calloc(size_t count, size_t size);
void *hv_realloc(void *p, size_t size);
/* count*size with overflow check; on overflow records HV_ERR_LIMIT and returns NULL. */
void *hv_malloc_array(size_t count, size_t size);
/* As hv_malloc_array, for arrays of many MiB filled once and then swept (dense fields): backed
 * by transparent huge pages where the system allows them, so first touch costs one page fault
 * per 2 MiB instead of one per 4 KiB (on this project's VMs the faults were a fifth of a
 * contour grading's time). Freed with free(). Not zeroed. */
void *hv_malloc_big(size_t count, size_t size);
/* As hv_realloc, for arrays that grow to many MiB as they are filled (a reader's vertices): the
 * new memory past 2 MiB boundaries on huge pages where the system allows, as hv_malloc_big. */
void *hv_realloc_big(void *p, size_t size);
/* hv_malloc_big, zeroed (for buffers written sparsely, such as images). */
void *hv_calloc_big(size_t count, size_t size);
char *hv_strdup(const char *s);
/* hv_image_create (image.c) without clearing the pixels, for a caller that writes every one
 * (the renderer): the memory is first touched where the pixels are written, on the threads
 * that render them, not all at once before. */
struct hv_image;
hv_status hv_image_create_unset(int width, int height, struct hv_image **out);
/* Grow *p (holding *cap elements of `size`) to hold at least `need`. */
hv_status hv_grow(void **p, size_t *cap, size_t need, size_t size);

/* ---- growable string --------------------------------------------------------------------- */
typedef struct hv_buf {
    char *data; /* NUL-terminated when non-NULL */
    size_t len, cap;
    int failed; /* an append ran out of memory; data holds what fit */
} hv_buf;
void hv_buf_init(hv_buf *b);
void hv_buf_free(hv_buf *b);
void hv_buf_append(hv_buf *b, const char *s, size_t n);
void hv_buf_puts(hv_buf *b, const char *s);
void hv_buf_printf(hv_buf *b, const char *fmt, ...) HV_PRINTF(2, 3);
void hv_buf_vprintf(hv_buf *b, const char *fmt, va_list ap);
/* Append s with the five characters XML and HTML reserve as entities (&amp; &lt; &gt; &quot; &#39;). */
void hv_buf_put_escaped(hv_buf *b, const char *s);
/* Base64 (RFC 4648, '=' padding; base64.c): append the encoding of size bytes to b (b->failed on
 * no memory), and decode len characters into a new buffer (*out: free; *size its bytes).
 * decode errors: HV_ERR_BAD_INPUT (a length not a multiple of 4, a character not base64),
 * HV_ERR_NOMEM. */
void hv_base64_append(hv_buf *b, const uint8_t *data, size_t size);
hv_status hv_base64_decode(const char *text, size_t len, uint8_t **out, size_t *size);

/* ---- names ------------------------------------------------------------------------------- */

/* ---- files ------------------------------------------------------------------------------ */
/* Read a whole file (NUL appended, not counted). Errors: HV_ERR_IO naming the path and errno
 * text (missing, directory, unreadable), HV_ERR_LIMIT (> max bytes), HV_ERR_NOMEM. */
hv_status hv_read_file(const char *path, size_t max, char **data, size_t *size);

/* Atomic output: open "<dir>/.<name>.tmp-<pid>-<n>" for writing; commit renames it to path,
 * abort removes it. Temporary files of a killed process never carry the final name. */
typedef struct hv_atomic_file {
    FILE *fp;
    char *path;
    char *tmp; /* NULL when writing straight to a special file (/dev/null, a FIFO, a tty) */
} hv_atomic_file;
hv_status hv_atomic_open(hv_atomic_file *af, const char *path, const char *mode);
hv_status hv_atomic_commit(hv_atomic_file *af); /* fflush, fsync, close, rename; each checked */
/* fsync a file written by another writer (a C++ library) before it is renamed into place.
 * Errors: HV_ERR_IO. */
hv_status hv_fsync_path(const char *path);
void hv_atomic_abort(hv_atomic_file *af);
/* `size` bytes written to `path` atomically (temporary, fsync, rename). Errors: HV_ERR_IO. */
hv_status hv_atomic_write(const char *path, const void *data, size_t size);
/* Write `size` bytes under `path` itself: for files inside a directory that is synced once and
 * renamed whole (slice stacks). Every write, the flush and the close are checked; on failure
 * the file is removed. */
hv_status hv_write_in_place(const char *path, const void *data, size_t size);
/* s[0..len) as a float, exactly as strtof reads it (the same value, the same strings taken and
 * refused, but for white space after the number, taken as strtof takes it before: an XML
 * number's), much faster for the plain decimals files hold (src/core/numparse.c). Returns 1 when
 * all len bytes are one number and white space around it (*out set), else 0. */
int hv_parse_float(const char *s, size_t len, float *out);
/* "512 bytes", "8.8 KiB", "1.5 GiB" (binary units, one decimal) into buf; returns buf. */
const char *hv_size_text(char *buf, size_t size, double bytes);
/* A temporary path next to `path` (caller frees), for writers that take a path; for a
 * special `path` (see below) one in $TMPDIR (default /tmp). Temporaries of the same name left
 * by processes that died (".<name>.tmp-<pid>-<n>" of a gone pid, files or directories) are
 * removed first. */
char *hv_temp_path(const char *path);
/* Temporaries in progress, for a process that must end at once (hovox run's watchdog: a script
 * stuck where it cannot be stopped, a second Ctrl-C): hv_temp_path and hv_outdir_begin track
 * the names they hand out (before the file or directory is made); hv_temp_remove_all removes
 * every one still there and keeps the list locked, so no thread makes another before the process
 * exits. Thread-safe; names committed or removed are forgotten as the list grows. */
void hv_temp_track(const char *path);
void hv_temp_remove_all(void);
/* Puts a finished temporary file in place: rename, or for a special `path` copy its bytes
 * there and remove `tmp`. Errors: HV_ERR_IO naming `path` (then `tmp` is left to the caller
 * when the rename failed, removed otherwise). */
hv_status hv_temp_commit(const char *tmp, const char *path);
/* 1 when `path` ends in `ext` (with its dot: ".stl"), case-insensitive. */
int hv_has_extension(const char *path, const char *ext);
/* HV_ERR_INVALID unless `path` ends in `ext` (case-insensitive) or is a special file: an output
 * named for another format ("m.stl" for a model) is refused before anything is written. */
hv_status hv_check_extension(const char *path, const char *ext, const char *what);
/* 1 when `path` exists and is not a regular file (a device, FIFO, socket): such targets are
 * written in place, never replaced by a rename. */
int hv_path_is_special(const char *path);
/* 1 when writing `path` stays below the directory `root` (an absolute, resolved path, as
 * realpath gives): the directory of `path` resolves below root, and when `path` itself is a
 * symbolic link its target does too (writers follow links: a link inside root must not lead
 * out of it). Trailing "/" and "/." are dropped first, as writers of directories drop them (so
 * "root/" names root itself, whose temporary would be made outside it), and a name whose last
 * part is "." or ".." is refused. A sandbox's rule; checked on the text the writer then uses. */
int hv_path_below(const char *root, const char *path);

/* ---- CSV text (csv_table.c) ------------------------------------------------------------------
 * Rows of comma-separated fields: blank lines and lines starting with '#' skipped, spaces and
 * tabs around each field trimmed, CRLF accepted, a NUL byte refused ("f.csv: line 3: NUL byte in
 * text"), at most HV_CSV_MAX_FIELDS fields a row. fn gets each row's line number, its fields
 * (NUL-terminated, writable) and the trimmed line (cut to 159 bytes, for messages); a status
 * other than HV_OK stops the reading and is returned. Errors: those, HV_ERR_BAD_INPUT,
 * HV_ERR_NOMEM. */
#define HV_CSV_MAX_FIELDS 80
typedef hv_status (*hv_csv_row_fn)(void *user, int line, char **field, int n, const char *raw);
hv_status hv_csv_each_row(const char *text, size_t len, const char *name, hv_csv_row_fn fn, void *user);

/* ---- two-column CSV tables (csv_table.c) -----------------------------------------------------
 * A header line "<first>,<property>[<unit>]" then rows "x,value": blank lines and lines starting
 * with '#' skipped, spaces trimmed, CRLF accepted, a NUL byte refused, numbers finite. The
 * property is 1-64 characters of [A-Za-z0-9_-], the unit (optional) at most 32 bytes. */
typedef struct hv_csv_table_form {
    const char *name;                 /* prefixes every message: the file */
    int (*first_ok)(const char *a);   /* 1 when the first header field is right ("t") */
    const char *header;               /* the header's form, for messages: "'t,<property>[<unit>]'" */
    const char *xname;                /* column 1 in messages: "t", "fraction" */
    int max_rows;
} hv_csv_table_form;
typedef struct hv_csv_table {
    char first[80], property[65], unit[33];
    int header_line;
    size_t n;
    double *x, *v; /* n each */
    int *lines;    /* each row's line */
} hv_csv_table;
/* Errors: HV_ERR_BAD_INPUT ("f.csv: line 3: E 'nan' is not a finite number", "f.csv: line 1:
 * header 'a,b' is not <header>", "f.csv: empty: no header line <header>", "a header and no
 * rows"), HV_ERR_NOMEM; on error *t holds nothing. Free with hv_csv_table_free. */
hv_status hv_csv_table_parse(const char *text, size_t len, const hv_csv_table_form *form, hv_csv_table *t);
void hv_csv_table_free(hv_csv_table *t);

/* ---- output directories written whole (outdir.c) ----------------------------------------
 * A job that writes a directory of files (a slice stack, per-layer SVGs) writes them into
 * "<parent>/.<name>.tmp-<pid>" and renames that into place when complete, so nothing
 * half-written ever appears under the final name; a killed job leaves only the hidden
 * temporary, which the next job on the same directory removes once that process is gone.
 * An existing directory is replaced only when everything in it is what such a job writes. */
typedef struct hv_outdir_rules {
    const char *what;               /* "stack", "per-layer SVG directory": for messages */
    const char *marker;             /* a file that must exist and that marker_ok accepts, or NULL */
    int (*marker_ok)(const char *text, size_t size); /* 1: the marker's content (NUL-terminated)
                                       says the directory is ours (e.g. a parsed manifest); NULL:
                                       any content */
    const char *const *files;       /* NULL-terminated fnmatch patterns of the files written */
    int subdirs;                    /* 1: one level of subdirectories of such files */
    int need_force;                 /* replacing an existing one needs the option {force} */
} hv_outdir_rules;
/* Check that dir is absent, an empty directory or (force, or !need_force) one of ours, clear
 * stale temporaries, and create the temporary (*tmp, malloc'd). Errors: HV_ERR_IO naming dir
 * (and the first entry that is not ours), HV_ERR_INVALID (dir is "." or ".."), NOMEM. */
hv_status hv_outdir_begin(const char *dir, const hv_outdir_rules *rules, int force, char **tmp);
/* Put tmp in place of dir (replacing an empty dir or one of ours). Errors: HV_ERR_IO. */
hv_status hv_outdir_commit(const char *tmp, const char *dir, const hv_outdir_rules *rules, int force);
/* Remove the temporary directory and everything in it (best effort). */
void hv_outdir_abort(const char *tmp);
/* Remove a directory tree (or a file) without following links (best effort). */
void hv_remove_tree(const char *path);

/* ---- plugins ---------------------------------------------------------------------------- */
/* ---- parallel loops ---------------------------------------------------------------------- */
/* Call fn(ctx, begin, end, thread) over [0, n) in chunks of `grain` on hv_threads() threads.
 * Progress (stage, done/n) is reported from the calling thread; a cancel stops handing out
 * chunks and returns HV_ERR_CANCELLED. fn returns HV_OK or a status (with its message set on
 * its own thread); the first failure by chunk order is returned, its message copied to the
 * calling thread. Results must not depend on which thread ran which chunk. */
typedef hv_status (*hv_range_fn)(void *ctx, size_t begin, size_t end, int thread);
hv_status hv_parallel_for(size_t n, size_t grain, hv_range_fn fn, void *ctx,
                          const hv_progress *progress, const char *stage);

/* Report progress from the calling thread; returns HV_ERR_CANCELLED (message set) on cancel. */
hv_status hv_progress_report(const hv_progress *p, const char *stage, double fraction);

/* ---- names (names.c) --------------------------------------------------------------------- */

/* A set of names, each with the index of its first insertion (bodies, materials). */
typedef struct hv_names {
    char **names; /* n, in insertion order; owned */
    size_t n, cap;
    int64_t *slots; /* open addressing: index + 1, 0 empty */
    size_t nslots;
} hv_names;
void hv_names_init(hv_names *t);
void hv_names_free(hv_names *t);
/* The index of the name s[0..n), or -1. */
int64_t hv_names_find(const hv_names *t, const char *s, size_t n);
/* The index of the name s[0..n), inserted when new. Errors: NOMEM, LIMIT. */
hv_status hv_names_intern(hv_names *t, const char *s, size_t n, int32_t *index);

/* A printable copy of s[0..n) for messages (control and non-ASCII bytes as '?', "..." when
 * cut to fit cap); returns buf. */
const char *hv_quote(char *buf, size_t cap, const char *s, size_t n);

/* The base name of a file without its extension ("part" for "dir/part.obj"); malloc'd. */
char *hv_file_stem(const char *name);


#ifdef __cplusplus
}
#endif
#endif
