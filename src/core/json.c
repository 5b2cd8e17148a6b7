/* src/core/json.c - a small JSON reader (RFC 8259) for metadata, manifests and tests;
 * hostile input yields a message with line and column, never a crash. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

#define JSON_MAX_DEPTH 200

typedef struct parser {
    const char *s, *end, *start;
    int failed;
} parser;

static void fail(parser *p, const char *what)
{
    if (p->failed) return;
    p->failed = 1;
    size_t line = 1, col = 1;
    for (const char *c = p->start; c < p->s && c < p->end; ++c) {
        if (*c == '\n') {
            ++line;
            col = 1;
        } else {
            ++col;
        }
    }
    hv_error_set(HV_ERR_BAD_INPUT, "line %zu, column %zu: %s", line, col, what);
}

static void skip_ws(parser *p)
{
    while (p->s < p->end && (*p->s == ' ' || *p->s == '\t' || *p->s == '\n' || *p->s == '\r'))
        ++p->s;
}

static hv_json *new_node(parser *p, hv_json_type t)
{
    hv_json *j = calloc(1, sizeof *j);
    if (!j) {
        fail(p, "out of memory");
        return NULL;
    }
    j->type = t;
    return j;
}

static int hexval(char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

static void put_utf8(hv_buf *b, unsigned cp)
{
    char u[4];
    size_t n;
    if (cp < 0x80) {
        u[0] = (char)cp;
        n = 1;
    } else if (cp < 0x800) {
        u[0] = (char)(0xC0 | (cp >> 6));
        u[1] = (char)(0x80 | (cp & 0x3F));
        n = 2;
    } else if (cp < 0x10000) {
        u[0] = (char)(0xE0 | (cp >> 12));
        u[1] = (char)(0x80 | ((cp >> 6) & 0x3F));
        u[2] = (char)(0x80 | (cp & 0x3F));
        n = 3;
    } else {
        u[0] = (char)(0xF0 | (cp >> 18));
        u[1] = (char)(0x80 | ((cp >> 12) & 0x3F));
        u[2] = (char)(0x80 | ((cp >> 6) & 0x3F));
        u[3] = (char)(0x80 | (cp & 0x3F));
        n = 4;
    }
    hv_buf_append(b, u, n);
}

static char *parse_string(parser *p)
{
    hv_buf b;
    hv_buf_init(&b);
    ++p->s; /* opening quote */
    hv_buf_append(&b, "", 0);
    while (p->s < p->end && *p->s != '"') {
        unsigned char c = (unsigned char)*p->s;
        if (c < 0x20) {
            fail(p, "control character in string");
            break;
        }
        if (c != '\\') {
            hv_buf_append(&b, p->s, 1);
            ++p->s;
            continue;
        }
        if (++p->s >= p->end) break;
        char e = *p->s++;
        switch (e) {
        case '"': hv_buf_append(&b, "\"", 1); break;
        case '\\': hv_buf_append(&b, "\\", 1); break;
        case '/': hv_buf_append(&b, "/", 1); break;
        case 'b': hv_buf_append(&b, "\b", 1); break;
        case 'f': hv_buf_append(&b, "\f", 1); break;
        case 'n': hv_buf_append(&b, "\n", 1); break;
        case 'r': hv_buf_append(&b, "\r", 1); break;
        case 't': hv_buf_append(&b, "\t", 1); break;
        case 'u': {
            unsigned cp = 0;
            for (int i = 0; i < 4; ++i) {
                int h = p->s < p->end ? hexval(*p->s) : -1;
                if (h < 0) {
                    fail(p, "bad \\u escape");
                    hv_buf_free(&b);
                    return NULL;
                }
                cp = cp * 16 + (unsigned)h;
                ++p->s;
            }
            if (cp == 0) {
                fail(p, "\\u0000 in string");
                hv_buf_free(&b);
                return NULL;
            }
            put_utf8(&b, cp);
            break;
        }
        default:
            --p->s;
            fail(p, "bad escape in string");
            hv_buf_free(&b);
            return NULL;
        }
    }
    if (p->failed) {
        hv_buf_free(&b);
        return NULL;
    }
    if (p->s >= p->end) {
        fail(p, "unterminated string");
        hv_buf_free(&b);
        return NULL;
    }
    ++p->s; /* closing quote */
    if (b.failed) {
        fail(p, "out of memory");
        hv_buf_free(&b);
        return NULL;
    }
    return b.data;
}

static hv_json *parse_value(parser *p, int depth);

static hv_json *parse_container(parser *p, int depth, int object)
{
    hv_json *j = new_node(p, object ? HV_JSON_OBJECT : HV_JSON_ARRAY);
    if (!j) return NULL;
    hv_json **tail = &j->child;
    ++p->s;
    skip_ws(p);
    if (p->s < p->end && *p->s == (object ? '}' : ']')) {
        ++p->s;
        return j;
    }
    for (;;) {
        char *key = NULL;
        skip_ws(p);
        if (object) {
            if (p->s >= p->end || *p->s != '"') {
                fail(p, "expected a string key");
                break;
            }
            key = parse_string(p);
            if (!key) break;
            skip_ws(p);
            if (p->s >= p->end || *p->s != ':') {
                free(key);
                fail(p, "expected ':'");
                break;
            }
            ++p->s;
        }
        hv_json *v = parse_value(p, depth + 1);
        if (!v) {
            free(key);
            break;
        }
        v->key = key;
        *tail = v;
        tail = &v->next;
        ++j->count;
        skip_ws(p);
        if (p->s < p->end && *p->s == ',') {
            ++p->s;
            continue;
        }
        if (p->s < p->end && *p->s == (object ? '}' : ']')) {
            ++p->s;
            return j;
        }
        fail(p, object ? "expected ',' or '}'" : "expected ',' or ']'");
        break;
    }
    hv_json_free(j);
    return NULL;
}

static hv_json *parse_value(parser *p, int depth)
{
    if (depth > JSON_MAX_DEPTH) {
        fail(p, "nesting too deep");
        return NULL;
    }
    skip_ws(p);
    if (p->s >= p->end) {
        fail(p, "unexpected end of text");
        return NULL;
    }
    char c = *p->s;
    if (c == '{' || c == '[') return parse_container(p, depth, c == '{');
    if (c == '"') {
        char *s = parse_string(p);
        if (!s) return NULL;
        hv_json *j = new_node(p, HV_JSON_STRING);
        if (!j) {
            free(s);
            return NULL;
        }
        j->string = s;
        return j;
    }
    static const struct { const char *word; hv_json_type t; double v; } words[] = {
        {"true", HV_JSON_BOOL, 1}, {"false", HV_JSON_BOOL, 0}, {"null", HV_JSON_NULL, 0}};
    for (size_t i = 0; i < HV_COUNT(words); ++i) {
        size_t n = strlen(words[i].word);
        if ((size_t)(p->end - p->s) >= n && memcmp(p->s, words[i].word, n) == 0) {
            p->s += n;
            hv_json *j = new_node(p, words[i].t);
            if (j) j->number = words[i].v;
            return j;
        }
    }
    if (c == '-' || (c >= '0' && c <= '9')) {
        const char *q = p->s;
        if (*q == '-') ++q;
        if (q >= p->end || !(*q >= '0' && *q <= '9')) {
            fail(p, "bad number");
            return NULL;
        }
        while (q < p->end && ((*q >= '0' && *q <= '9') || *q == '.' || *q == 'e' || *q == 'E' ||
                              *q == '+' || *q == '-'))
            ++q;
        char tmp[128];
        size_t n = (size_t)(q - p->s);
        if (n >= sizeof tmp) {
            fail(p, "number too long");
            return NULL;
        }
        memcpy(tmp, p->s, n);
        tmp[n] = '\0';
        char *endp;
        double v = strtod(tmp, &endp);
        if (*endp != '\0' || !isfinite(v)) {
            fail(p, "bad number");
            return NULL;
        }
        p->s = q;
        hv_json *j = new_node(p, HV_JSON_NUMBER);
        if (j) j->number = v;
        return j;
    }
    fail(p, "unexpected character");
    return NULL;
}

hv_json *hv_json_parse(const char *text, size_t len)
{
    parser p = {text, text + len, text, 0};
    hv_json *j = parse_value(&p, 0);
    if (!j) return NULL;
    skip_ws(&p);
    if (p.s != p.end) {
        fail(&p, "trailing characters after the document");
        hv_json_free(j);
        return NULL;
    }
    return j;
}

void hv_json_free(hv_json *j)
{
    while (j) {
        hv_json *next = j->next;
        hv_json_free(j->child);
        free(j->string);
        free(j->key);
        free(j);
        j = next;
    }
}

const hv_json *hv_json_get(const hv_json *obj, const char *key)
{
    if (!obj || obj->type != HV_JSON_OBJECT) return NULL;
    for (const hv_json *c = obj->child; c; c = c->next)
        if (c->key && strcmp(c->key, key) == 0) return c;
    return NULL;
}

const hv_json *hv_json_at(const hv_json *arr, size_t i)
{
    if (!arr || (arr->type != HV_JSON_ARRAY && arr->type != HV_JSON_OBJECT)) return NULL;
    const hv_json *c = arr->child;
    while (c && i--) c = c->next;
    return c;
}
