/* src/core/error.c - status names and the per-thread detail message. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "hovox/core.h"

#define HV_ERROR_MAX 2048

static _Thread_local char g_message[HV_ERROR_MAX];

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

void hv_error_clear(void) { g_message[0] = '\0'; }

hv_status hv_error_set(hv_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(g_message, sizeof g_message, fmt, ap);
    va_end(ap);
    return status;
}

hv_status hv_error_prefix(hv_status status, const char *fmt, ...)
{
    char prefix[HV_ERROR_MAX], old[HV_ERROR_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(prefix, sizeof prefix, fmt, ap);
    va_end(ap);
    memcpy(old, g_message, sizeof old);
    size_t n = strlen(prefix), m = strlen(old);
    if (n > HV_ERROR_MAX - 1) n = HV_ERROR_MAX - 1;
    if (m > HV_ERROR_MAX - 1 - n) m = HV_ERROR_MAX - 1 - n;
    memcpy(g_message, prefix, n);
    memcpy(g_message + n, old, m);
    g_message[n + m] = '\0';
    return status;
}

const char *hv_version(void) { return HV_VERSION_STRING; }
