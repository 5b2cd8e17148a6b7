/* tests/slicing/test_zip.c - the GCVF archive writer (slicing/stack.c on libzip): entries read
 * back by libzip's reader and checked by Info-ZIP's `unzip -t` (independent readers), ZIP64
 * past 65,535 entries, fixed dates and modes, nothing left behind on failure. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <zip.h>

#include "core/internal.h"
#include "slicing/layers_internal.h"
#include "support/support.h"

static void write_bytes(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    cr_assert(f);
    fputs(text, f);
    fclose(f);
}

static char *read_entry(zip_t *za, const char *name, zip_uint64_t *size)
{
    zip_stat_t st;
    cr_assert_eq(zip_stat(za, name, 0, &st), 0, "no entry %s", name);
    char *buf = malloc(st.size + 1);
    zip_file_t *f = zip_fopen(za, name, 0);
    cr_assert(f);
    cr_assert_eq(zip_fread(f, buf, st.size), (zip_int64_t)st.size);
    zip_fclose(f);
    buf[st.size] = 0;
    *size = st.size;
    return buf;
}

/* the number of entries named in the ZIP64 end record, or -1 when the archive has none */
static long long zip64_entries(const char *path)
{
    FILE *f = fopen(path, "rb");
    cr_assert(f);
    fseek(f, 0, SEEK_END);
    long end = ftell(f);
    long from = end > 4096 ? end - 4096 : 0;
    unsigned char buf[4096];
    fseek(f, from, SEEK_SET);
    size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    for (size_t i = 0; i + 56 <= n; ++i)
        if (buf[i] == 0x50 && buf[i + 1] == 0x4b && buf[i + 2] == 6 && buf[i + 3] == 6) {
            unsigned long long v = 0;
            for (int k = 7; k >= 0; --k) v = v << 8 | buf[i + 32 + k]; /* total entries */
            return (long long)v;
        }
    return -1;
}

Test(zip, entries_read_back_with_fixed_dates_modes_and_methods)
{
    const char *path = t_tmpfile("a.zip");
    const char *file = t_tmpfile("layer.bin");
    write_bytes(file, "PNG-ish bytes that are stored");
    static char xml[4000];
    for (size_t i = 0; i + 1 < sizeof xml; ++i) xml[i] = "<GCVF/>\n"[i % 8];
    hv_zip *z;
    cr_assert_eq(hv_zip_open(path, &z), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_zip_add_data(z, "ConfigFile.xml", xml, strlen(xml), 1), HV_OK);
    cr_assert_eq(hv_zip_add_file(z, "layer_0.png", file, 0), HV_OK);
    cr_expect_not(t_exists(path), "nothing under the final name before the commit");
    cr_assert_eq(hv_zip_write(z, NULL, "zip"), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_zip_commit(z), HV_OK, "%s", hv_last_error());

    int err;
    zip_t *za = zip_open(path, ZIP_RDONLY | ZIP_CHECKCONS, &err);
    cr_assert(za, "libzip cannot read it back (%d)", err);
    cr_expect_eq(zip_get_num_entries(za, 0), 2);
    zip_uint64_t n;
    char *x = read_entry(za, "ConfigFile.xml", &n);
    cr_expect_eq(n, strlen(xml));
    cr_expect_str_eq(x, xml);
    free(x);
    char *l = read_entry(za, "layer_0.png", &n);
    cr_expect_str_eq(l, "PNG-ish bytes that are stored");
    free(l);
    zip_stat_t st;
    zip_stat(za, "ConfigFile.xml", 0, &st);
    cr_expect_eq(st.comp_method, ZIP_CM_DEFLATE);
    cr_expect_lt(st.comp_size, st.size);
    zip_stat(za, "layer_0.png", 0, &st);
    cr_expect_eq(st.comp_method, ZIP_CM_STORE);
    struct tm *tm = localtime(&st.mtime);
    cr_expect_eq(tm->tm_year, 80);
    cr_expect_eq(tm->tm_mon, 0);
    cr_expect_eq(tm->tm_mday, 1);
    zip_uint8_t os;
    zip_uint32_t attr;
    cr_assert_eq(zip_file_get_external_attributes(za, 1, 0, &os, &attr), 0);
    cr_expect_eq(os, ZIP_OPSYS_UNIX);
    cr_expect_eq(attr >> 16, 0100644u);
    zip_close(za);

    char cmd[600];
    snprintf(cmd, sizeof cmd, "unzip -tq '%s' >/dev/null 2>&1", path);
    cr_expect_eq(t_run(cmd, NULL), 0, "unzip -t rejects the archive");

    /* the same entries give the same bytes */
    const char *again = t_tmpfile("b.zip");
    cr_assert_eq(hv_zip_open(again, &z), HV_OK);
    cr_assert_eq(hv_zip_add_data(z, "ConfigFile.xml", xml, strlen(xml), 1), HV_OK);
    cr_assert_eq(hv_zip_add_file(z, "layer_0.png", file, 0), HV_OK);
    cr_assert_eq(hv_zip_write(z, NULL, "zip"), HV_OK);
    cr_assert_eq(hv_zip_commit(z), HV_OK);
    snprintf(cmd, sizeof cmd, "cmp -s '%s' '%s'", path, again);
    cr_expect_eq(t_run(cmd, NULL), 0, "two archives of the same entries differ");
}

Test(zip, more_than_65535_entries_get_zip64_records, .timeout = 120)
{
    const char *path = t_tmpfile("many.zip");
    const char *file = t_tmpfile("tiny.png");
    write_bytes(file, "x");
    enum { N = 70000 };
    hv_zip *z;
    cr_assert_eq(hv_zip_open(path, &z), HV_OK);
    char name[32];
    for (int i = 0; i < N; ++i) {
        snprintf(name, sizeof name, "layer_%d.png", i);
        cr_assert_eq(hv_zip_add_file(z, name, file, 0), HV_OK, "%s", hv_last_error());
    }
    cr_assert_eq(hv_zip_write(z, NULL, "zip"), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_zip_commit(z), HV_OK);
    cr_expect_eq(zip64_entries(path), N, "no ZIP64 end record counting the entries");

    int err;
    zip_t *za = zip_open(path, ZIP_RDONLY | ZIP_CHECKCONS, &err);
    cr_assert(za, "libzip cannot read it back (%d)", err);
    cr_expect_eq(zip_get_num_entries(za, 0), N);
    zip_uint64_t n;
    char *last = read_entry(za, "layer_69999.png", &n);
    cr_expect_str_eq(last, "x");
    free(last);
    zip_close(za);
    char cmd[600];
    snprintf(cmd, sizeof cmd, "unzip -tq '%s' >/dev/null 2>&1", path);
    cr_expect_eq(t_run(cmd, NULL), 0, "unzip -t rejects the ZIP64 archive");
}

Test(zip, failures_leave_nothing)
{
    hv_zip *z;
    /* an unwritable place fails at open, before any work */
    cr_expect_eq(hv_zip_open("/nonexistent-dir/x.zip", &z), HV_ERR_IO);
    cr_expect(strstr(hv_last_error(), "/nonexistent-dir/x.zip"), "%s", hv_last_error());

    /* an entry file that is gone by the time the archive is written */
    const char *path = t_tmpfile("gone.zip");
    const char *file = t_tmpfile("gone.png");
    write_bytes(file, "soon gone");
    cr_assert_eq(hv_zip_open(path, &z), HV_OK);
    hv_status s = hv_zip_add_file(z, "layer_0.png", file, 0);
    if (s == HV_OK) {
        remove(file);
        s = hv_zip_write(z, NULL, "zip");
    }
    cr_expect_eq(s, HV_ERR_IO);
    cr_expect(strstr(hv_last_error(), "gone"), "%s", hv_last_error());
    hv_zip_abort(z);
    cr_expect_not(t_exists(path));
    char cmd[600];
    snprintf(cmd, sizeof cmd, "ls -A '%s' | grep -c tmp", t_tmpdir());
    char *out = NULL;
    t_run(cmd, &out);
    cr_expect_str_eq(out, "0\n", "a temporary was left behind");
    free(out);

    /* a missing entry file is named when added */
    cr_assert_eq(hv_zip_open(path, &z), HV_OK);
    s = hv_zip_add_file(z, "layer_1.png", t_tmpfile("never-there.png"), 0);
    if (s == HV_OK) s = hv_zip_write(z, NULL, "zip");
    cr_expect_eq(s, HV_ERR_IO);
    cr_expect(strstr(hv_last_error(), "never-there.png"), "%s", hv_last_error());
    hv_zip_abort(z);
    cr_expect_not(t_exists(path));
}
