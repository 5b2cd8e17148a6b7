/* src/core/parallel.c - thread count, a chunked parallel-for over OpenMP with progress and
 * cancellation reported on the calling thread, physical memory. */
#include <limits.h>
#include <omp.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "internal.h"

static int g_threads;

void hv_set_threads(int threads) { g_threads = threads > 0 ? threads : 0; }

int hv_threads(void)
{
    if (g_threads > 0) return g_threads;
    const char *env = getenv("HOVOX_THREADS");
    if (env && *env) {
        long n = strtol(env, NULL, 10);
        if (n > 0 && n <= 1024) return (int)n;
    }
    return hv_cpus_allowed();
}

int hv_cpus_allowed(void)
{
    /* the affinity mask, not the machine: under mpirun's default binding (one core per rank
     * when there are two ranks or fewer), taskset or a cgroup's cpuset, a thread per online
     * processor would share one core */
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) == 0) {
        int n = CPU_COUNT(&set);
        if (n > 0) return HV_MIN(n, 1024);
    }
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)HV_MIN(n, 1024) : 1;
}

uint64_t hv_physical_memory(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || size <= 0) return 0;
    return (uint64_t)pages * (uint64_t)size;
}

static int (*g_cancel_fn)(void *);
static void *g_cancel_user;

void hv_set_cancel_check(int (*fn)(void *user), void *user)
{
    g_cancel_user = user;
    g_cancel_fn = fn;
}

int hv_cancel_requested(void) { return g_cancel_fn && g_cancel_fn(g_cancel_user); }

static uint64_t g_budget_cap;

void hv_set_memory_cap(uint64_t bytes) { g_budget_cap = bytes; }

uint64_t hv_memory_budget(uint64_t requested)
{
    uint64_t b = requested ? requested : hv_physical_memory() / 2;
    if (g_budget_cap && (b == 0 || b > g_budget_cap)) b = g_budget_cap;
    return b;
}

hv_status hv_progress_report(const hv_progress *p, const char *stage, double fraction)
{
    if ((p && p->fn && p->fn(p->user, stage, HV_CLAMP(fraction, 0.0, 1.0)) != 0) || hv_cancel_requested())
        return hv_error_set(HV_ERR_CANCELLED, "%s: cancelled", stage);
    return HV_OK;
}

hv_status hv_parallel_for(size_t n, size_t grain, hv_range_fn fn, void *ctx,
                          const hv_progress *progress, const char *stage)
{
    if (n == 0) return hv_progress_report(progress, stage, 1.0);
    if (grain == 0) grain = 1;
    size_t chunks = (n + grain - 1) / grain;
    int threads = hv_threads();
    if ((size_t)threads > chunks) threads = (int)chunks;
    if (omp_in_parallel()) threads = 1; /* inside a loop over parts (an assembly's bodies): its thread alone */

    atomic_size_t next = 0, done = 0;
    atomic_int stop = 0;
    /* the failing chunk with the lowest index wins, so the message is deterministic */
    size_t fail_chunk = SIZE_MAX;
    hv_status fail_status = HV_OK;
    char fail_msg[2048] = "";
    hv_status cancel = HV_OK;

#pragma omp parallel num_threads(threads)
    {
        int t = omp_get_thread_num();
        for (;;) {
            if (atomic_load(&stop)) break;
            size_t c = atomic_fetch_add(&next, 1);
            if (c >= chunks) break;
            size_t b = c * grain, e = HV_MIN(n, b + grain);
            hv_status s = fn(ctx, b, e, t);
            if (s != HV_OK) {
#pragma omp critical(hv_parallel_fail)
                {
                    if (c < fail_chunk) {
                        fail_chunk = c;
                        fail_status = s;
                        strncpy(fail_msg, hv_last_error(), sizeof fail_msg - 1);
                    }
                }
                atomic_store(&stop, 1);
                break;
            }
            size_t d = atomic_fetch_add(&done, e - b) + (e - b);
            if (t == 0 && (progress && progress->fn ? 1 : g_cancel_fn != NULL)) {
                if (hv_progress_report(progress, stage, (double)d / (double)n) != HV_OK) {
                    cancel = HV_ERR_CANCELLED;
                    atomic_store(&stop, 1);
                }
            }
        }
    }
    if (fail_status != HV_OK) return hv_error_set(fail_status, "%s", fail_msg);
    if (cancel != HV_OK) return hv_error_set(HV_ERR_CANCELLED, "%s: cancelled", stage);
    return hv_progress_report(progress, stage, 1.0);
}
