/* src/material/points_csv.c - points for probing from a CSV file of x,y,z rows (README "hovox
 * probe"): a header line allowed, blank lines and '#' comments skipped, CRLF accepted; every
 * refusal names the file, the line and the field. A parser of files from others: fuzzed with
 * the other text readers. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/material.h"

#define MAX_POINTS_FILE (256u << 20)

/* A field with blanks trimmed, as a finite number; 0 when it is not one. */
static int field_number(const char *s, size_t len, double *out)
{
    while (len && (*s == ' ' || *s == '\t')) ++s, --len;
    while (len && (s[len - 1] == ' ' || s[len - 1] == '\t')) --len;
    if (len == 0 || len > 63) return 0;
    char buf[64];
    memcpy(buf, s, len);
    buf[len] = '\0';
    char *end;
    errno = 0;
    double v = strtod(buf, &end);
    if (*end != '\0' || errno == ERANGE || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

/* "'text'" of a field, blanks trimmed, long ones cut, for messages. */
static void field_shown(const char *s, size_t len, char *out, size_t size)
{
    while (len && (*s == ' ' || *s == '\t')) ++s, --len;
    while (len && (s[len - 1] == ' ' || s[len - 1] == '\t')) --len;
    snprintf(out, size, "'%.*s%s'", (int)HV_MIN(len, 40), s, len > 40 ? "..." : "");
}

hv_status hv_points_parse_csv(const char *data, size_t size, const char *path, double **xyz, size_t *n)
{
    int line = 0, rows = 0;
    hv_status rc = HV_OK;
    size_t cap = 3 * *n; /* doubles known to be allocated */
    const char *p = data, *end = data + size;
    while (p < end && rc == HV_OK) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *le = nl ? nl : end;
        ++line;
        size_t len = (size_t)(le - p);
        if (len && p[len - 1] == '\r') --len;
        size_t k = 0;
        while (k < len && (p[k] == ' ' || p[k] == '\t')) ++k;
        if (k < len && p[k] != '#') {
            /* split into fields */
            const char *f[4];
            size_t fl[4];
            int nf = 0;
            const char *q = p, *qe = p + len;
            for (;;) {
                const char *c = memchr(q, ',', (size_t)(qe - q));
                const char *fe = c ? c : qe;
                if (nf < 4) {
                    f[nf] = q;
                    fl[nf] = (size_t)(fe - q);
                }
                ++nf;
                if (!c) break;
                q = c + 1;
            }
            double v[3];
            int numeric = 0;
            for (int i = 0; i < nf && i < 3; ++i) numeric += field_number(f[i], fl[i], &v[i]);
            if (rows == 0 && numeric == 0 && nf == 3) {
                /* a header line */
            } else if (nf != 3) {
                rc = hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: expected 3 values x,y,z, found %d", path, line, nf);
            } else {
                for (int i = 0; i < 3 && rc == HV_OK; ++i)
                    if (!field_number(f[i], fl[i], &v[i])) {
                        char shown[64];
                        field_shown(f[i], fl[i], shown, sizeof shown);
                        rc = hv_error_set(HV_ERR_BAD_INPUT, "%s: line %d: %c = %s is not a finite number", path,
                                          line, "xyz"[i], shown);
                    }
                if (rc == HV_OK && (rc = hv_grow((void **)xyz, &cap, 3 * (*n + 1), sizeof **xyz)) == HV_OK) {
                    memcpy(*xyz + 3 * *n, v, sizeof v);
                    ++*n;
                }
            }
            ++rows;
        }
        p = nl ? nl + 1 : end;
    }
    return rc;
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

