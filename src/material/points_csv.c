/* src/material/points_csv.c - points for probing from a CSV file of x,y,z rows (README "hovox
 * probe"), read by hv_csv_each_row: a header line allowed, blank lines and '#' comments skipped,
 * CRLF accepted; every refusal names the file, the line and the field. A parser of files from
 * others: fuzzed with the other text readers. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/material.h"

#define MAX_POINTS_FILE (256u << 20)

/* A field (trimmed by hv_csv_each_row) as a finite number; 0 when it is not one. */
static int field_number(const char *s, double *out)
{
    if (*s == '\0' || strlen(s) > 63) return 0;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (*end != '\0' || errno == ERANGE || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

typedef struct points_ctx {
    const char *path;
    double **xyz;
    size_t *n, cap; /* cap: doubles known to be allocated */
    int rows;
} points_ctx;

static hv_status points_row(void *user, int line, char **field, int nf, const char *raw)
{
    points_ctx *c = user;
    double v[3];
    int numeric = 0;
    (void)raw;
    for (int i = 0; i < nf && i < 3; ++i) numeric += field_number(field[i], &v[i]);
    if (c->rows++ == 0 && numeric == 0 && nf == 3) return HV_OK; /* a header line */
    if (nf != 3) return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: expected 3 values x,y,z, found %d", c->path, line, nf);
    for (int i = 0; i < 3; ++i)
        if (!field_number(field[i], &v[i])) {
            size_t len = strlen(field[i]);
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: %c = '%.*s%s' is not a finite number", c->path, line,
                                "xyz"[i], (int)HV_MIN(len, 40), field[i], len > 40 ? "..." : "");
        }
    hv_status s = hv_grow((void **)c->xyz, &c->cap, 3 * (*c->n + 1), sizeof **c->xyz);
    if (s != HV_OK) return s;
    memcpy(*c->xyz + 3 * *c->n, v, sizeof v);
    ++*c->n;
    return HV_OK;
}

/* Rows through hv_csv_each_row, the one CSV row reader (core/csv_table.c). */
hv_status hv_points_parse_csv(const char *data, size_t size, const char *path, double **xyz, size_t *n)
{
    points_ctx c = {path, xyz, n, 3 * *n, 0};
    return hv_csv_each_row(data, size, path, points_row, &c);
}

hv_status hv_points_read_csv(const char *path, double **xyz, size_t *n)
{
    char *data;
    size_t size;
    hv_status s = hv_read_file(path, MAX_POINTS_FILE, &data, &size);
    if (s == HV_OK) hv_input_note(path);
    if (s != HV_OK) return s;
    s = hv_points_parse_csv(data, size, path, xyz, n);
    free(data);
    return s;
}

