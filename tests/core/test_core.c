/* tests/core/test_core.c - status names, detail messages, JSON (jansson helpers), enum names, atomic files and
 * the parallel loop (determinism, failure order, cancellation). */
#include <criterion/criterion.h>
#include <sched.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <stdatomic.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/internal.h"
#include "core/json.h"
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
    cr_assert_eq(hv_error_suffix(HV_ERR_IO, "; %s", "a hint"), HV_ERR_IO);
    cr_assert_str_eq(hv_last_error(), "gear: cannot open x.stl; a hint");
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
    hv_error_suffix(HV_ERR_INVALID, "%s", big);
    cr_assert_lt(strlen(hv_last_error()), 2048);
}

Test(json, parses_documents)
{
    const char *t = "{\"a\": [1, 2.5e3, -0.25], \"b\": {\"c\": \"x\\u00e9\\n\"}, \"d\": true, "
                    "\"e\": null, \"n\": 3}";
    json_t *j;
    cr_assert_eq(hv_json_parse(t, strlen(t), "doc.json", &j), HV_OK, "%s", hv_last_error());
    double a[3];
    cr_assert_eq(hv_json_get_numbers(j, "a", "doc.json", a, 3), HV_OK);
    cr_assert_float_eq(a[1], 2500.0, 1e-12);
    const json_t *b;
    cr_assert_eq(hv_json_need(j, "b", JSON_OBJECT, "doc.json", &b), HV_OK);
    const char *c;
    cr_assert_eq(hv_json_get_string(b, "c", "doc.json: b", &c), HV_OK);
    cr_assert_str_eq(c, "x\xc3\xa9\n");
    long long n;
    cr_assert_eq(hv_json_get_int(j, "n", "doc.json", 0, 10, &n), HV_OK);
    cr_assert_eq(n, 3);
    json_decref(j);
}

/* The position index (issue 26 item 5: the tray job reader's own tokenizer replaced): every value
 * and key where it starts, keys matched decoded, columns in characters as jansson counts them
 * (the same column jansson gives for a syntax error there). */
Test(json, positions_of_values_and_keys)
{
    const char *t = "{\"parts\": [\n  {\"mesh\": \"b.stl\", \"at\": [40, 4e1]},\n  {\"a\\u0062\": true, "
                    "\"\xc3\xa9\xc3\xa9\": null}],\n \"x\": {}, \"y\": [] }";
    json_t *j;
    cr_assert_eq(hv_json_parse(t, strlen(t), "job.json", &j), HV_OK, "%s", hv_last_error());
    json_decref(j);
    hv_json_where *w;
    cr_assert_eq(hv_json_where_index(t, strlen(t), &w), HV_OK, "%s", hv_last_error());
    int line, col;
    cr_assert_eq(hv_json_where_at(w, 0, 0, &line, &col), 0);
    cr_expect(line == 1 && col == 1);
    int parts = hv_json_where_member(w, 0, "parts");
    cr_assert_eq(hv_json_where_at(w, parts, 1, &line, &col), 0);
    cr_expect(line == 1 && col == 2, "key at %d:%d", line, col);
    hv_json_where_at(w, parts, 0, &line, &col);
    cr_expect(line == 1 && col == 11, "value at %d:%d", line, col);
    int p0 = hv_json_where_element(w, parts, 0), p1 = hv_json_where_element(w, parts, 1);
    hv_json_where_at(w, p0, 0, &line, &col);
    cr_expect(line == 2 && col == 3, "parts[0] at %d:%d", line, col);
    int at1 = hv_json_where_element(w, hv_json_where_member(w, p0, "at"), 1);
    hv_json_where_at(w, at1, 0, &line, &col);
    cr_expect(line == 2 && col == 32, "at[1] at %d:%d", line, col);
    int ab = hv_json_where_member(w, p1, "ab"); /* the key "a\u0062", decoded */
    cr_assert_geq(ab, 0);
    hv_json_where_at(w, ab, 1, &line, &col);
    cr_expect(line == 3 && col == 4, "ab's key at %d:%d", line, col);
    hv_json_where_at(w, hv_json_where_member(w, p1, "\xc3\xa9\xc3\xa9"), 0, &line, &col);
    cr_expect(line == 3 && col == 27, "null at %d:%d (characters, not bytes)", line, col);
    hv_json_where_at(w, hv_json_where_member(w, 0, "y"), 0, &line, &col);
    cr_expect(line == 4 && col == 16, "y at %d:%d", line, col);
    cr_expect_eq(hv_json_where_member(w, 0, "z"), -1);
    cr_expect_eq(hv_json_where_element(w, parts, 2), -1);
    cr_expect_eq(hv_json_where_member(w, -1, "parts"), -1);
    cr_expect_eq(hv_json_where_element(w, hv_json_where_member(w, 0, "x"), 0), -1);
    cr_expect_eq(hv_json_where_at(w, -1, 0, &line, &col), -1);
    hv_json_where_destroy(w);
    /* jansson puts a syntax error after the same characters in the same column */
    const char *bad = "{\"\xc3\xa9\xc3\xa9\": 1,, }";
    cr_expect_eq(hv_json_parse(bad, strlen(bad), "b.json", &j), HV_ERR_BAD_INPUT);
    cr_expect(strstr(hv_last_error(), "line 1, column 10"), "%s", hv_last_error());
    cr_expect_eq(hv_json_where_index("[1, 2", 5, &w), HV_ERR_BAD_INPUT);
    cr_expect_eq(hv_json_where_index("1 2", 3, &w), HV_ERR_BAD_INPUT);
    hv_json_where_destroy(NULL);
}

Test(json, typed_members_name_the_key)
{
    const char *t = "{\"a\": [1, \"x\"], \"s\": \"bogus\", \"n\": 2.5, \"big\": 70}";
    json_t *j;
    cr_assert_eq(hv_json_parse(t, strlen(t), "doc.json", &j), HV_OK);
    double v[3];
    const char *str;
    long long n;
    int k;
    static const char *const names[] = {"nearest", "idw", NULL};
    cr_assert_eq(hv_json_get_numbers(j, "a", "doc.json", v, 3), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "doc.json: a has 2 values, not 3");
    cr_assert_eq(hv_json_get_numbers(j, "a", "doc.json", v, 2), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "doc.json: a[1] is a string, not a number");
    cr_assert_eq(hv_json_get_string(j, "zz", "doc.json", &str), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "doc.json: zz is missing");
    cr_assert_eq(hv_json_get_number(j, "s", "doc.json", v), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "doc.json: s is a string, not a number");
    cr_assert_eq(hv_json_get_int(j, "n", "doc.json", 0, 10, &n), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "doc.json: n is 2.5, not an integer in [0, 10]");
    cr_assert_eq(hv_json_get_int(j, "big", "doc.json", 1, 64, &n), HV_ERR_BAD_INPUT);
    static const hv_enum_def blend = {"blend", names, NULL, NULL};
    cr_assert_eq(hv_json_get_name(j, "s", "doc.json", &blend, &k), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "doc.json: s \"bogus\" is not one of nearest or idw");
    json_decref(j);
}

Test(json, rejects_malformed_with_position)
{
    static const char *bad[] = {"", "{", "[1,]", "{\"a\" 1}", "\"abc", "tru", "[1] 2", "{\"a\": 01x}",
                                "\"\\q\"", "[nan]", "{\"a\": 1, \"a\": 2}", "[\"\\u0000\"]", "[1e400]", "3"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        json_t *j = NULL;
        cr_assert_eq(hv_json_parse(bad[i], strlen(bad[i]), "doc.json", &j), HV_ERR_BAD_INPUT, "accepted '%s'", bad[i]);
        cr_assert_null(j);
        cr_assert(strncmp(hv_last_error(), "doc.json: line 1, column ", 25) == 0, "%s", hv_last_error());
    }
    /* the line and column of jansson's message, on a later line */
    const char *t = "{\"a\": 1,\n  \"b\" 2}";
    json_t *j;
    cr_assert_eq(hv_json_parse(t, strlen(t), "m.json", &j), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "m.json: line 2, column 7: ':' expected near '2'");
    /* deep nesting is refused, not a stack overflow */
    char deep[5001];
    memset(deep, '[', 5000);
    deep[5000] = '\0';
    cr_assert_eq(hv_json_parse(deep, 5000, "deep.json", &j), HV_ERR_BAD_INPUT);
    cr_assert(strstr(hv_last_error(), "depth") != NULL, "%s", hv_last_error());
}

/* Serialise, parse back, and return the text (caller frees). */
static char *dump_checked(json_t *doc)
{
    char *text = hv_json_dump(doc);
    cr_assert_not_null(text);
    json_t *back;
    cr_assert_eq(hv_json_parse(text, strlen(text), "dump", &back), HV_OK, "%s: %s", text, hv_last_error());
    cr_assert(json_equal(doc, back), "%s does not read back", text);
    json_decref(back);
    return text;
}

Test(json, writer_layout_and_numbers)
{
    json_t *doc = json_pack("{s:o, s:o, s:o, s:o, s:o, s:o, s:o, s:o, s:o}", "s", hv_json_text("q\"\\\t\x01/"), "i",
                            hv_json_number(2.0), "tenth", hv_json_number(0.1), "third", hv_json_number(1.0 / 3.0),
                            "nan", hv_json_number(NAN), "big", hv_json_number(1e21), "neg", hv_json_number(-2.5e-7),
                            "f", hv_json_float(0.3f), "a", json_pack("[i, {s:b}]", 1, "t", 1));
    char *text = dump_checked(doc);
    cr_assert_str_eq(text, "{\"s\": \"q\\\"\\\\\\t\\u0001/\", \"i\": 2, \"tenth\": 0.1, \"third\": 0.3333333333333333, "
                           "\"nan\": null, \"big\": 1e+21, \"neg\": -2.5e-07, \"f\": 0.3, \"a\": [1, {\"t\": true}]}");
    free(text);
    json_decref(doc);
}

/* Significant digits of the number at s (up to an exponent or the end of the token). */
static int significant_digits(const char *s)
{
    int n = 0, started = 0;
    for (; *s && *s != 'e' && *s != ']' && *s != ','; ++s) {
        if (*s >= '1' && *s <= '9') started = 1;
        if (started && *s >= '0' && *s <= '9') ++n;
    }
    return n;
}

Test(json, numbers_round_trip)
{
    /* doubles read back exactly; floats (hv_json_float) read back as the same float in at
     * most 9 significant digits */
    uint64_t x = 88172645463325252ull;
    for (int i = 0; i < 20000; ++i) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;
        double d;
        uint64_t bits = x;
        memcpy(&d, &bits, sizeof d);
        if (!isfinite(d)) continue;
        float f = (float)((double)(x >> 11) / 9007199254740992.0 * (i % 2 ? 1e3 : 1e-3));
        json_t *a = json_pack("[o, o]", hv_json_number(d), hv_json_float(f));
        char *text = hv_json_dump(a);
        json_t *b;
        cr_assert_eq(hv_json_parse(text, strlen(text), "n", &b), HV_OK, "%s", text);
        cr_assert_eq(json_number_value(json_array_get(b, 0)), d, "%s", text);
        cr_assert_eq((float)json_number_value(json_array_get(b, 1)), f, "%s", text);
        cr_assert_leq(significant_digits(strchr(text, ',') + 2), 9, "%s", text);
        free(text);
        json_decref(a);
        json_decref(b);
    }
}

Test(json, text_that_is_not_utf8)
{
    json_t *s = hv_json_text("a\xff" "b\xc3\xa9");
    cr_assert_str_eq(json_string_value(s), "a\xef\xbf\xbd" "b\xc3\xa9");
    json_decref(s);
}

Test(json, lines_layout)
{
    json_t *doc = json_pack("{s:s, s:[i, i], s:[], s:[{s:i}, {s:i}], s:{s:[f]}}", "generator", "hovox", "range", 0, 2,
                            "materials", "layers", "index", 0, "index", 1, "bbox", "min", 0.5);
    char *text = hv_json_dump_lines(doc);
    cr_assert_str_eq(text, "{\n  \"generator\": \"hovox\",\n  \"range\": [0, 2],\n  \"materials\": [],\n"
                           "  \"layers\": [\n    {\"index\": 0},\n    {\"index\": 1}\n  ],\n"
                           "  \"bbox\": {\"min\": [0.5]}\n}\n");
    free(text);
    json_decref(doc);
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

Test(files, paths_below_a_root_follow_directories_and_links)
{
    char real[PATH_MAX], root[1024], out[2048], in[2048], link_out[4096], link_in[4096], outside[4096], dotdot[4096];
    cr_assert_not_null(realpath(t_tmpdir(), real));
    cr_assert_lt(strlen(real), sizeof root);
    memcpy(root, real, strlen(real) + 1); /* shorter than root: checked above */
    snprintf(out, sizeof out, "%s/below_root", root);
    snprintf(in, sizeof in, "%s/below_root/sub", root);
    mkdir(out, 0755);
    mkdir(in, 0755);
    snprintf(link_out, sizeof link_out, "%s/up", in);
    snprintf(link_in, sizeof link_in, "%s/side", in);
    snprintf(outside, sizeof outside, "%s/x.png", root);
    snprintf(dotdot, sizeof dotdot, "%s/../x.png", in);
    unlink(link_out);
    unlink(link_in);
    cr_assert_eq(symlink(outside, link_out), 0);
    cr_assert_eq(symlink("x.png", link_in), 0);
    cr_assert(hv_path_below(out, in));
    cr_assert(!hv_path_below(out, link_in), "a dangling link is refused: where it leads cannot be resolved");
    char beside[4096];
    snprintf(beside, sizeof beside, "%s/x.png", in);
    FILE *f = fopen(beside, "w");
    cr_assert_not_null(f);
    fclose(f);
    cr_assert(hv_path_below(out, link_in), "a link to a file beside it stays below");
    cr_assert(!hv_path_below(out, link_out), "a link leading out is refused");
    cr_assert(!hv_path_below(out, outside));
    cr_assert(hv_path_below(out, dotdot), "sub/../x.png is below");
    char up2[4096];
    snprintf(up2, sizeof up2, "%s/../../x.png", in);
    cr_assert(!hv_path_below(out, up2));
    char prefix[4096];
    snprintf(prefix, sizeof prefix, "%s/below_root2/x", root); /* a name that merely starts like root */
    cr_assert(!hv_path_below(out, prefix));
    cr_assert(!hv_path_below(out, "/nonexistent-dir/x"));
    /* issue 32.4: the root itself, however spelt, is no name below it (a directory written there
     * makes its temporary beside it); a subdirectory so spelt is */
    static const char *const self[] = {"/", "/.", "/./", "//", "/.//./", "/sub/..", "/."};
    for (size_t i = 0; i < sizeof self / sizeof *self; ++i) {
        char p[4096];
        snprintf(p, sizeof p, "%s%s", out, self[i]);
        cr_assert(!hv_path_below(out, p), "%s names the root", p);
    }
    static const char *const sub[] = {"/sub/", "/sub/.", "/sub//./", "/new/"};
    for (size_t i = 0; i < sizeof sub / sizeof *sub; ++i) {
        char p[4096];
        snprintf(p, sizeof p, "%s%s", out, sub[i]);
        cr_assert(hv_path_below(out, p), "%s is below the root", p);
    }
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

/* issue 32 item 22: the default thread count is the affinity mask's, not the machine's (mpirun
 * binds a rank to one core when there are two ranks or fewer); Criterion runs each test in its
 * own process, so the mask set here goes with it */
Test(threads, default_follows_the_affinity_mask)
{
    cpu_set_t set;
    CPU_ZERO(&set);
    cr_assert_eq(sched_getaffinity(0, sizeof set, &set), 0);
    int first = -1;
    for (int c = 0; c < CPU_SETSIZE && first < 0; ++c)
        if (CPU_ISSET(c, &set)) first = c;
    cr_assert_geq(first, 0);
    unsetenv("HOVOX_THREADS");
    hv_set_threads(0);
    cr_assert_eq(hv_cpus_allowed(), CPU_COUNT(&set));
    cr_assert_eq(hv_threads(), CPU_COUNT(&set));
    CPU_ZERO(&set);
    CPU_SET(first, &set);
    cr_assert_eq(sched_setaffinity(0, sizeof set, &set), 0);
    cr_assert_eq(hv_cpus_allowed(), 1);
    cr_assert_eq(hv_threads(), 1, "one core allowed: one thread");
    hv_set_threads(3); /* an explicit count is kept (the CLI warns) */
    cr_assert_eq(hv_threads(), 3);
    hv_set_threads(0);
}
