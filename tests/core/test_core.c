/* tests/core/test_core.c - status names, detail messages, JSON, buffers, atomic files and
 * the parallel loop (determinism, failure order, cancellation). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdatomic.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/internal.h"
#include "hovox/core.h"
#include "support/support.h"

Test(status, names_are_stable)
{
    cr_assert_str_eq(hv_status_name(HV_OK), "HV_OK");
    cr_assert_str_eq(hv_status_name(HV_ERR_BAD_INPUT), "HV_ERR_BAD_INPUT");
    cr_assert_str_eq(hv_status_name(HV_ERR_INTERNAL), "HV_ERR_INTERNAL");
    cr_assert_str_eq(hv_status_name((hv_status)999), "HV_ERR_UNKNOWN");
    /* append-only codes: values are part of the ABI */
    cr_assert_eq(HV_OK, 0);
    cr_assert_eq(HV_ERR_INVALID, 1);
    cr_assert_eq(HV_ERR_IO, 3);
    cr_assert_eq(HV_ERR_INTERNAL, 9);
}

Test(status, detail_message_and_prefix)
{
    cr_assert_eq(hv_error_set(HV_ERR_IO, "cannot open %s", "x.stl"), HV_ERR_IO);
    cr_assert_str_eq(hv_last_error(), "cannot open x.stl");
    cr_assert_eq(hv_error_prefix(HV_ERR_IO, "%s: ", "gear"), HV_ERR_IO);
    cr_assert_str_eq(hv_last_error(), "gear: cannot open x.stl");
    hv_error_clear();
    cr_assert_str_eq(hv_last_error(), "");
}

Test(status, long_messages_are_truncated_not_overflowed)
{
    char big[5000];
    memset(big, 'a', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    hv_error_set(HV_ERR_INVALID, "%s", big);
    hv_error_prefix(HV_ERR_INVALID, "%s", big);
    cr_assert_lt(strlen(hv_last_error()), 2048);
}

Test(json, parses_documents)
{
    const char *t = "{\"a\": [1, 2.5e3, -0.25], \"b\": {\"c\": \"x\\u00e9\\n\"}, \"d\": true, "
                    "\"e\": null}";
    hv_json *j = hv_json_parse(t, strlen(t));
    cr_assert_not_null(j);
    const hv_json *a = hv_json_get(j, "a");
    cr_assert_eq(a->type, HV_JSON_ARRAY);
    cr_assert_eq(a->count, 3);
    cr_assert_float_eq(hv_json_at(a, 1)->number, 2500.0, 1e-12);
    cr_assert_str_eq(hv_json_get(hv_json_get(j, "b"), "c")->string, "x\xc3\xa9\n");
    cr_assert_eq(hv_json_get(j, "d")->type, HV_JSON_BOOL);
    cr_assert_eq(hv_json_get(j, "e")->type, HV_JSON_NULL);
    cr_assert_null(hv_json_get(j, "zz"));
    hv_json_free(j);
}

Test(json, rejects_malformed_with_position)
{
    static const char *bad[] = {"", "{", "[1,]", "{\"a\" 1}", "\"abc", "tru", "[1] 2",
                                "{\"a\": 01x}", "\"\\q\"", "[nan]"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        hv_json *j = hv_json_parse(bad[i], strlen(bad[i]));
        cr_assert_null(j, "accepted '%s'", bad[i]);
        cr_assert(strstr(hv_last_error(), "line 1, column") != NULL, "%s", hv_last_error());
    }
    /* deep nesting is refused, not a stack overflow */
    char deep[2001];
    memset(deep, '[', 2000);
    deep[2000] = '\0';
    cr_assert_null(hv_json_parse(deep, 2000));
    cr_assert(strstr(hv_last_error(), "nesting too deep") != NULL);
}

Test(buf, json_writer_round_trips)
{
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_puts(&b, "[");
    hv_buf_json_string(&b, "q\"\\\t\x01");
    hv_buf_puts(&b, ", ");
    hv_buf_json_number(&b, 0.1);
    hv_buf_puts(&b, ", ");
    hv_buf_json_number(&b, 1.0 / 3.0);
    hv_buf_puts(&b, ", ");
    hv_buf_json_number(&b, NAN);
    hv_buf_puts(&b, "]");
    cr_assert_str_eq(b.data, "[\"q\\\"\\\\\\t\\u0001\", 0.1, 0.3333333333333333, null]");
    hv_json *j = hv_json_parse(b.data, b.len);
    cr_assert_not_null(j);
    cr_assert_eq(hv_json_at(j, 2)->number, 1.0 / 3.0);
    hv_json_free(j);
    hv_buf_free(&b);
}

Test(files, atomic_write_commits_or_leaves_nothing)
{
    const char *path = t_tmpfile("atomic.txt");
    hv_atomic_file af;
    cr_assert_eq(hv_atomic_open(&af, path, "w"), HV_OK);
    fputs("hello", af.fp);
    cr_assert(!t_exists(path), "final name visible before commit");
    cr_assert_eq(hv_atomic_commit(&af), HV_OK);
    char *data;
    size_t n;
    cr_assert_eq(hv_read_file(path, 100, &data, &n), HV_OK);
    cr_assert_str_eq(data, "hello");
    free(data);

    const char *p2 = t_tmpfile("aborted.txt");
    cr_assert_eq(hv_atomic_open(&af, p2, "w"), HV_OK);
    fputs("partial", af.fp);
    hv_atomic_abort(&af);
    cr_assert(!t_exists(p2));
    char cmd[600];
    snprintf(cmd, sizeof cmd, "ls -a '%s' | grep -c tmp", t_tmpdir());
    char *out;
    t_run(cmd, &out);
    cr_assert_str_eq(out, "0\n", "temporary files left behind");
    free(out);
}

Test(files, temp_commit_renames_files_and_streams_into_special_ones)
{
    /* a regular target: the temporary sits next to it and is renamed */
    const char *path = t_tmpfile("commit.bin");
    char *tmp = hv_temp_path(path);
    cr_assert_not_null(tmp);
    cr_assert_eq(strncmp(tmp, t_tmpdir(), strlen(t_tmpdir())), 0, "%s not beside %s", tmp, path);
    FILE *f = fopen(tmp, "wb");
    fputs("payload", f);
    fclose(f);
    cr_assert_eq(hv_temp_commit(tmp, path), HV_OK);
    cr_assert(t_exists(path) && !t_exists(tmp));
    free(tmp);

    /* /dev/null: the temporary goes to $TMPDIR, is copied in, removed, /dev/null stays */
    setenv("TMPDIR", t_tmpdir(), 1);
    tmp = hv_temp_path("/dev/null");
    cr_assert_not_null(tmp);
    cr_assert_eq(strncmp(tmp, t_tmpdir(), strlen(t_tmpdir())), 0, "%s not in TMPDIR", tmp);
    f = fopen(tmp, "wb");
    fputs("payload", f);
    fclose(f);
    cr_assert_eq(hv_temp_commit(tmp, "/dev/null"), HV_OK);
    cr_assert(!t_exists(tmp));
    struct stat st;
    cr_assert(stat("/dev/null", &st) == 0 && S_ISCHR(st.st_mode), "/dev/null was replaced");
    free(tmp);

    /* a missing temporary is an I/O error naming the target */
    cr_assert_eq(hv_temp_commit(t_tmpfile("no-such.tmp"), path), HV_ERR_IO);
    cr_assert(strstr(hv_last_error(), "commit.bin") != NULL, "%s", hv_last_error());
}

Test(files, read_errors_name_the_path)
{
    char *d;
    size_t n;
    cr_assert_eq(hv_read_file("/nonexistent/x", 10, &d, &n), HV_ERR_IO);
    cr_assert(strstr(hv_last_error(), "/nonexistent/x") != NULL);
    cr_assert_eq(hv_read_file("/tmp", 10, &d, &n), HV_ERR_IO);
    cr_assert(strstr(hv_last_error(), "is a directory") != NULL);
    cr_assert_eq(hv_read_file("/proc/self/exe", 10, &d, &n), HV_ERR_LIMIT);
}

typedef struct sum_ctx {
    double *partial;
    size_t grain;
    atomic_int calls;
} sum_ctx;

static hv_status sum_range(void *c, size_t b, size_t e, int t)
{
    (void)t;
    sum_ctx *s = c;
    double acc = 0;
    for (size_t i = b; i < e; ++i) acc += 1.0 / (double)(i + 1);
    s->partial[b / s->grain] = acc;
    atomic_fetch_add(&s->calls, 1);
    return HV_OK;
}

Test(parallel, deterministic_for_any_thread_count)
{
    double results[3];
    int threads[3] = {1, 2, 5};
    for (int k = 0; k < 3; ++k) {
        hv_set_threads(threads[k]);
        double partial[100] = {0};
        sum_ctx s = {partial, 1000, 0};
        cr_assert_eq(hv_parallel_for(100000, 1000, sum_range, &s, NULL, "sum"), HV_OK);
        cr_assert_eq(atomic_load(&s.calls), 100);
        double total = 0;
        for (int i = 0; i < 100; ++i) total += partial[i];
        results[k] = total;
    }
    hv_set_threads(0);
    cr_assert_eq(results[0], results[1]);
    cr_assert_eq(results[0], results[2]);
}

static hv_status fail_range(void *c, size_t b, size_t e, int t)
{
    (void)c;
    (void)e;
    (void)t;
    if (b >= 30) return hv_error_set(HV_ERR_BAD_INPUT, "chunk at %zu failed", b);
    return HV_OK;
}

Test(parallel, first_failure_by_chunk_wins)
{
    hv_set_threads(4);
    cr_assert_eq(hv_parallel_for(100, 10, fail_range, NULL, NULL, "x"), HV_ERR_BAD_INPUT);
    /* chunks 30, 40, ... may all fail; the reported one is the lowest that ran and failed */
    cr_assert(strncmp(hv_last_error(), "chunk at ", 9) == 0, "%s", hv_last_error());
    hv_set_threads(0);
}

static int cancel_half(void *user, const char *stage, double f)
{
    (void)stage;
    ++*(int *)user;
    return f >= 0.5;
}

static hv_status slow_range(void *c, size_t b, size_t e, int t)
{
    (void)c;
    (void)b;
    (void)e;
    (void)t;
    usleep(200);
    return HV_OK;
}

Test(parallel, progress_cancels)
{
    int calls = 0;
    hv_progress p = {cancel_half, &calls};
    hv_set_threads(1);
    cr_assert_eq(hv_parallel_for(1000, 10, slow_range, NULL, &p, "work"), HV_ERR_CANCELLED);
    cr_assert_gt(calls, 0);
    cr_assert_str_eq(hv_last_error(), "work: cancelled");
    hv_set_threads(0);
}

Test(threads, environment_and_override)
{
    hv_set_threads(3);
    cr_assert_eq(hv_threads(), 3);
    hv_set_threads(0);
    cr_assert_geq(hv_threads(), 1);
    cr_assert_gt(hv_physical_memory(), 1u << 20);
    cr_assert_str_eq(hv_version(), HV_VERSION_STRING);
}
