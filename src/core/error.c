/* src/core/error.c - status names and the per-thread detail message. A message may name
 * options (hv_error_option): they are kept marked so each front end can spell them its own way
 * (hv_error_spell). */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "hovox/core.h"
#include "hovox/options.h"

#define HV_ERROR_MAX 2048
#define MARK '\x1f' /* around an option key in g_marked */

static _Thread_local char g_message[HV_ERROR_MAX];
static _Thread_local char g_marked[HV_ERROR_MAX]; /* "" when the message names no option */

const char *hv_status_name(hv_status status)
{
    switch (status) {
    case HV_OK: return "HV_OK";
    case HV_ERR_INVALID: return "HV_ERR_INVALID";
    case HV_ERR_BAD_INPUT: return "HV_ERR_BAD_INPUT";
    case HV_ERR_IO: return "HV_ERR_IO";
    case HV_ERR_NOMEM: return "HV_ERR_NOMEM";
    case HV_ERR_LIMIT: return "HV_ERR_LIMIT";
    case HV_ERR_CANCELLED: return "HV_ERR_CANCELLED";
    case HV_ERR_NOT_FOUND: return "HV_ERR_NOT_FOUND";
    case HV_ERR_UNSUPPORTED: return "HV_ERR_UNSUPPORTED";
    case HV_ERR_INTERNAL: return "HV_ERR_INTERNAL";
    }
    return "HV_ERR_UNKNOWN";
}

const char *hv_last_error(void) { return g_message; }

void hv_error_clear(void)
{
    g_message[0] = '\0';
    g_marked[0] = '\0';
}

hv_status hv_error_set(hv_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(g_message, sizeof g_message, fmt, ap);
    va_end(ap);
    g_marked[0] = '\0';
    return status;
}

static int is_key_char(char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; }

hv_status hv_error_option(hv_status status, const char *fmt, ...)
{
    /* {key} and {%s} -> MARK key MARK in the format, then format the values */
    char f[HV_ERROR_MAX];
    size_t n = 0;
    for (const char *p = fmt; *p && n + 2 < sizeof f; ++p) {
        if (p[0] == '{' && p[1] == '%' && p[2] == 's' && p[3] == '}') { /* {%s}: a key as an argument */
            f[n++] = MARK;
            f[n++] = '%';
            f[n++] = 's';
            f[n++] = MARK;
            p += 3;
            continue;
        }
        if (*p == '{') {
            const char *q = p + 1;
            while (is_key_char(*q)) ++q;
            if (*q == '}' && q > p + 1 && n + (size_t)(q - p) + 2 < sizeof f) {
                f[n++] = MARK;
                memcpy(f + n, p + 1, (size_t)(q - p - 1));
                n += (size_t)(q - p - 1);
                f[n++] = MARK;
                p = q;
                continue;
            }
        }
        f[n++] = *p;
    }
    f[n] = '\0';
    va_list ap;
    va_start(ap, fmt);
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
#endif
    vsnprintf(g_marked, sizeof g_marked, f, ap);
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
    va_end(ap);
    size_t m = 0;
    for (const char *p = g_marked; *p; ++p)
        if (*p != MARK) g_message[m++] = *p;
    g_message[m] = '\0';
    return status;
}

int hv_last_error_names_option(void) { return g_marked[0] == MARK; }

const char *hv_error_spell(hv_spell_fn spell, void *user, char *buf, size_t size)
{
    if (!size) return buf;
    if (!g_marked[0]) {
        snprintf(buf, size, "%s", g_message);
        return buf;
    }
    size_t n = 0;
    for (const char *p = g_marked; *p && n + 1 < size;) {
        if (*p != MARK) {
            buf[n++] = *p++;
            continue;
        }
        const char *q = strchr(p + 1, MARK);
        if (!q) break;
        char key[128];
        size_t k = (size_t)(q - p - 1) < sizeof key - 1 ? (size_t)(q - p - 1) : sizeof key - 1;
        memcpy(key, p + 1, k);
        key[k] = '\0';
        const char *s = spell ? spell(key, user) : NULL;
        if (!s) s = key;
        for (; *s && n + 1 < size; ++s) buf[n++] = *s;
        p = q + 1;
    }
    buf[n] = '\0';
    return buf;
}

/* Context added before (at_end 0) or after the current message, marked copy included. */
static void add_context(int at_end, const char *fmt, va_list ap) HV_PRINTF(2, 0);
static void add_context(int at_end, const char *fmt, va_list ap)
{
    char text[HV_ERROR_MAX], old[HV_ERROR_MAX];
    vsnprintf(text, sizeof text, fmt, ap);
    for (int k = 0; k < 2; ++k) {
        char *msg = k ? g_marked : g_message;
        if (k && !g_marked[0]) break;
        memcpy(old, msg, sizeof old);
        const char *a = at_end ? old : text, *b = at_end ? text : old;
        size_t n = strlen(a), m = strlen(b);
        if (n > HV_ERROR_MAX - 1) n = HV_ERROR_MAX - 1;
        if (m > HV_ERROR_MAX - 1 - n) m = HV_ERROR_MAX - 1 - n;
        memmove(msg, a, n);
        memcpy(msg + n, b, m);
        msg[n + m] = '\0';
    }
}

hv_status hv_error_prefix(hv_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    add_context(0, fmt, ap);
    va_end(ap);
    return status;
}

hv_status hv_error_suffix(hv_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    add_context(1, fmt, ap);
    va_end(ap);
    return status;
}

const char *hv_version(void) { return HV_VERSION_STRING; }
