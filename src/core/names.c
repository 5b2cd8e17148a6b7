/* src/core/names.c - a table of names (bodies, materials, grids) looked up in constant time,
 * printable quotes of input for messages, and file stems. */
#include <stdlib.h>
#include <string.h>

#include "internal.h"

/* ---- names ------------------------------------------------------------------------------- */

static uint64_t name_hash(const char *s, size_t n)
{
    uint64_t h = 1469598103934665603ull; /* FNV-1a */
    for (size_t i = 0; i < n; ++i) h = (h ^ (unsigned char)s[i]) * 1099511628211ull;
    return h;
}

void hv_names_init(hv_names *t) { memset(t, 0, sizeof *t); }

void hv_names_free(hv_names *t)
{
    for (size_t i = 0; i < t->n; ++i) free(t->names[i]);
    free(t->names);
    free(t->slots);
    memset(t, 0, sizeof *t);
}

static int64_t find_slot(const hv_names *t, const char *s, size_t n, size_t *slot)
{
    size_t mask = t->nslots - 1, i = (size_t)name_hash(s, n) & mask;
    for (;; i = (i + 1) & mask) {
        int64_t k = t->slots[i] - 1;
        if (k < 0) {
            *slot = i;
            return -1;
        }
        if (strlen(t->names[k]) == n && memcmp(t->names[k], s, n) == 0) return k;
    }
}

int64_t hv_names_find(const hv_names *t, const char *s, size_t n)
{
    size_t slot;
    return t->nslots ? find_slot(t, s, n, &slot) : -1;
}

hv_status hv_names_intern(hv_names *t, const char *s, size_t n, int32_t *index)
{
    size_t slot;
    if (t->nslots) {
        int64_t k = find_slot(t, s, n, &slot);
        if (k >= 0) {
            *index = (int32_t)k;
            return HV_OK;
        }
    }
    if (t->n >= (size_t)INT32_MAX) return hv_error_set(HV_ERR_LIMIT, "more than %d names", INT32_MAX);
    if (2 * (t->n + 1) > t->nslots) { /* keep the table at most half full */
        size_t ns = t->nslots ? 2 * t->nslots : 64;
        int64_t *slots = hv_calloc(ns, sizeof *slots);
        if (!slots) return HV_ERR_NOMEM;
        free(t->slots);
        t->slots = slots;
        t->nslots = ns;
        for (size_t k = 0; k < t->n; ++k) {
            size_t free_slot;
            (void)find_slot(t, t->names[k], strlen(t->names[k]), &free_slot);
            t->slots[free_slot] = (int64_t)k + 1;
        }
    }
    hv_status st = hv_grow((void **)&t->names, &t->cap, t->n + 1, sizeof *t->names);
    if (st != HV_OK) return st;
    char *copy = hv_malloc(n + 1);
    if (!copy) return HV_ERR_NOMEM;
    memcpy(copy, s, n);
    copy[n] = '\0';
    (void)find_slot(t, s, n, &slot);
    t->slots[slot] = (int64_t)t->n + 1;
    t->names[t->n] = copy;
    *index = (int32_t)t->n++;
    return HV_OK;
}

/* ---- messages ---------------------------------------------------------------------------- */

const char *hv_quote(char *buf, size_t cap, const char *s, size_t n)
{
    size_t k = 0, lim = cap > 4 ? cap - 4 : 0;
    for (size_t i = 0; i < n && k < lim; ++i) {
        unsigned char c = (unsigned char)s[i];
        buf[k++] = (char)(c >= 0x20 && c < 0x7F ? c : '?');
    }
    if (n > k && cap >= 4) {
        memcpy(buf + k, "...", 3);
        k += 3;
    }
    if (cap) buf[k < cap ? k : cap - 1] = '\0';
    return buf;
}

char *hv_file_stem(const char *name)
{
    char *stem = hv_strdup(name && *name ? hv_basename(name) : "");
    if (!stem) return NULL;
    char *dot = strrchr(stem, '.');
    if (dot && dot != stem) *dot = '\0';
    return stem;
}
