/* hovox/core.h - status codes, error details, progress callbacks, threads, version.
 * Every fallible hovox call returns an hv_status and records a detail message that names
 * the file, the place and the value; the library never prints and never exits. */
#ifndef HOVOX_CORE_H
#define HOVOX_CORE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define HV_API __attribute__((visibility("default")))
#define HV_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define HV_API
#define HV_PRINTF(f, a)
#endif

#define HV_VERSION_MAJOR 0
#define HV_VERSION_MINOR 1
#define HV_VERSION_PATCH 0
#define HV_VERSION_STRING "0.1.0"

/* Status codes. Append-only: a code's value never changes once released. */
typedef enum hv_status {
    HV_OK = 0,
    HV_ERR_INVALID = 1,     /* a value given by the caller or a user is out of its domain */
    HV_ERR_BAD_INPUT = 2,   /* a file or script is malformed */
    HV_ERR_IO = 3,          /* a file could not be opened, read, written or renamed */
    HV_ERR_NOMEM = 4,       /* an allocation failed */
    HV_ERR_LIMIT = 5,       /* the job would exceed the memory budget or a size limit */
    HV_ERR_CANCELLED = 6,   /* a progress callback asked to stop */
    HV_ERR_NOT_FOUND = 7,   /* a named grid, material, key or plugin does not exist */
    HV_ERR_UNSUPPORTED = 8, /* a format or feature is not available in this build */
    HV_ERR_INTERNAL = 9     /* a bug, or an unexpected exception from a C++ library */
} hv_status;

/* Name of a status ("HV_ERR_BAD_INPUT"); "HV_ERR_UNKNOWN" for values not listed above. */
HV_API const char *hv_status_name(hv_status status);

/* The detail message of the last failure on the calling thread ("" when none).
 * The pointer stays valid until the next hovox call on this thread. */
HV_API const char *hv_last_error(void);

/* Record a failure on the calling thread and return `status` (for `return hv_error_set(...)`).
 * Used by hovox modules and by code that extends hovox; never prints. */
HV_API hv_status hv_error_set(hv_status status, const char *fmt, ...) HV_PRINTF(2, 3);

/* Prefix the current detail message with context ("gear.stl: " + message). Returns status. */
HV_API hv_status hv_error_prefix(hv_status status, const char *fmt, ...) HV_PRINTF(2, 3);

/* Append to the current detail message (a front end's own hint: "; hovox.load_mesh reads it").
 * Returns status. */
HV_API hv_status hv_error_suffix(hv_status status, const char *fmt, ...) HV_PRINTF(2, 3);

/* Forget the calling thread's detail message. */
HV_API void hv_error_clear(void);

/* Progress: long operations call `fn` from the thread that called them (never from a
 * worker), with a short stage name and a fraction in [0,1]. A nonzero return cancels the
 * operation, which then returns HV_ERR_CANCELLED and leaves no partial output. */
typedef int (*hv_progress_fn)(void *user, const char *stage, double fraction);
typedef struct hv_progress {
    hv_progress_fn fn; /* may be NULL */
    void *user;
} hv_progress;

/* A process-wide cancel check (Ctrl-C, a time limit): long operations call fn from the thread
 * that called them, as often as they report progress (whether or not they were given a
 * progress callback), and stop with HV_ERR_CANCELLED when it returns nonzero. NULL removes it.
 * Set it before starting work; not thread-safe against running operations. */
HV_API void hv_set_cancel_check(int (*fn)(void *user), void *user);
/* 1 when the cancel check asks to stop. */
HV_API int hv_cancel_requested(void);

/* Worker threads used by the multi-threaded kernels. 0 (the default) means: the value of
 * the environment variable HOVOX_THREADS if set, else hv_cpus_allowed(). Results never depend
 * on the thread count. */
HV_API void hv_set_threads(int threads);
HV_API int hv_threads(void);
/* The processors this process may run on: the size of its affinity mask (sched_getaffinity;
 * mpirun's binding, taskset, a cpuset), else the online processors; 1 to 1024. */
HV_API int hv_cpus_allowed(void);

/* Physical memory of the machine in bytes (0 when unknown); used for default budgets. */
HV_API uint64_t hv_physical_memory(void);

/* The memory budget of one operation: `requested` bytes (an option's max_memory), or half of
 * the physical memory when 0; never above the process-wide cap when one is set. */
HV_API uint64_t hv_memory_budget(uint64_t requested);
/* A process-wide cap on every operation's budget (0: none), e.g. a sandboxed script's limit.
 * Set it before starting work. */
HV_API void hv_set_memory_cap(uint64_t bytes);
/* The cap hv_set_memory_cap set (0: none): readers allow hostile amplification (a small file
 * that expands to gigabytes) only when a limit was given. */
HV_API uint64_t hv_memory_cap(void);

/* What a command reads, so that it never writes over it: every reader of a user's file (meshes,
 * models, fields, tables, job files) notes it; every writer refuses a target that is a noted input
 * (the same device and inode: through any path, symbolic or hard link) or, for a directory it
 * replaces whole, a directory holding one (HV_ERR_INVALID: "out.vdb: is an input of this
 * command: refusing to write over it"), before it creates anything and again before it renames
 * into place. The record is process-wide and kept from the first hv_inputs_reset on, which a
 * front end calls where a command starts: the CLI once, a script or Python at each call (so one
 * call is one command: a model loaded by one call may be saved over by a later one). A program
 * using the library without calling it keeps every write it asks for. */
HV_API void hv_input_note(const char *path);
HV_API hv_status hv_output_check(const char *path, int is_dir);
HV_API void hv_inputs_reset(void);

/* Library version string, e.g. "0.1.0". */
HV_API const char *hv_version(void);

#ifdef __cplusplus
}
#endif
#endif
