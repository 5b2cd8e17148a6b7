/* src/core/base64.c - base64 (RFC 4648, standard alphabet, '=' padding): the images a viewer page
 * carries inside, and the leaves a model's geometry record embeds in its metadata. */
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"

static const char k_b64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

void hv_base64_append(hv_buf *b, const uint8_t *data, size_t size)
{
    if (b->failed) return;
    size_t need = b->len + (size + 2) / 3 * 4 + 1;
    if (need > b->cap) {
        size_t cap = b->cap ? b->cap : 64;
        while (cap < need) cap *= 2;
        char *p = realloc(b->data, cap);
        if (!p) {
            b->failed = 1;
            hv_error_set(HV_ERR_NOMEM, "out of memory for %zu bytes of base64", need);
            return;
        }
        b->data = p;
        b->cap = cap;
    }
    char *o = b->data + b->len;
    size_t i = 0;
    for (; i + 3 <= size; i += 3) {
        uint32_t v = (uint32_t)data[i] << 16 | (uint32_t)data[i + 1] << 8 | data[i + 2];
        *o++ = k_b64[v >> 18];
        *o++ = k_b64[v >> 12 & 63];
        *o++ = k_b64[v >> 6 & 63];
        *o++ = k_b64[v & 63];
    }
    if (i < size) {
        uint32_t v = (uint32_t)data[i] << 16 | (i + 1 < size ? (uint32_t)data[i + 1] << 8 : 0);
        *o++ = k_b64[v >> 18];
        *o++ = k_b64[v >> 12 & 63];
        *o++ = i + 1 < size ? k_b64[v >> 6 & 63] : '=';
        *o++ = '=';
    }
    *o = '\0';
    b->len = (size_t)(o - b->data);
}

static int b64_value(unsigned char c)
{
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
}

hv_status hv_base64_decode(const char *text, size_t len, uint8_t **out, size_t *size)
{
    *out = NULL;
    *size = 0;
    if (len % 4) return hv_error_set(HV_ERR_BAD_INPUT, "base64 text of %zu characters (not a multiple of 4)", len);
    size_t pad = len && text[len - 1] == '=' ? (len > 1 && text[len - 2] == '=' ? 2 : 1) : 0;
    size_t n = len / 4 * 3 - pad;
    uint8_t *d = hv_malloc(n ? n : 1);
    if (!d) return HV_ERR_NOMEM;
    size_t o = 0;
    for (size_t i = 0; i < len; i += 4) {
        int v[4];
        for (int k = 0; k < 4; ++k) {
            int last = i + 4 == len;
            v[k] = last && k >= 4 - (int)pad ? 0 : b64_value((unsigned char)text[i + (size_t)k]);
            if (v[k] < 0) {
                free(d);
                return hv_error_set(HV_ERR_BAD_INPUT, "base64: character %zu is not base64", i + (size_t)k);
            }
        }
        uint32_t w = (uint32_t)v[0] << 18 | (uint32_t)v[1] << 12 | (uint32_t)v[2] << 6 | (uint32_t)v[3];
        uint8_t bytes[3] = {(uint8_t)(w >> 16), (uint8_t)(w >> 8), (uint8_t)w};
        for (int k = 0; k < 3 && o < n; ++k) d[o++] = bytes[k];
    }
    *out = d;
    *size = n;
    return HV_OK;
}
