/* src/material/expr.c - arithmetic expressions in d for distribution functions f(d) (Wu 2.2:
 * "any analytical, segmental, linear or nonlinear functions"): a recursive-descent parser
 * into a small tree, evaluated only while tabulating f. Grammar:
 *   expr  := term (('+' | '-') term)*
 *   term  := unary (('*' | '/') unary)*
 *   unary := ('-' | '+') unary | power
 *   power := atom ('^' unary)?            (right-associative: 2^3^2 = 2^9)
 *   atom  := number | name | name '(' expr (',' expr)* ')' | '(' expr ')'
 * Names: d, dg, pi, e. Functions: sin cos tan asin acos atan exp log log10 sqrt abs floor ceil
 * (one argument), min max pow atan2 (two). */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "material_internal.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

enum { N_NUM, N_D, N_DG, N_NEG, N_ADD, N_SUB, N_MUL, N_DIV, N_POW, N_FN1, N_FN2 };

typedef double (*fn1_t)(double);
typedef double (*fn2_t)(double, double);

struct hv_expr {
    int op;
    double value;
    fn1_t f1;
    fn2_t f2;
    struct hv_expr *a, *b;
};

typedef struct parser {
    const char *s, *start;
    int failed;
} parser;

/* Record "column N: <pre><tok><post>" once. */
static hv_expr *fail(parser *p, const char *pre, const char *tok, size_t toklen, const char *post)
{
    if (!p->failed) {
        p->failed = 1;
        int n = (int)HV_MIN(toklen, (size_t)60);
        hv_error_set(HV_ERR_INVALID, "column %d: %s%.*s%s", (int)(p->s - p->start) + 1, pre, n, tok,
                     post);
    }
    return NULL;
}

static hv_expr *node(parser *p, int op, hv_expr *a, hv_expr *b)
{
    hv_expr *e = calloc(1, sizeof *e);
    if (!e) {
        hv_expr_free(a);
        hv_expr_free(b);
        p->failed = 1;
        hv_error_set(HV_ERR_NOMEM, "out of memory parsing an expression");
        return NULL;
    }
    e->op = op;
    e->a = a;
    e->b = b;
    return e;
}

static void skip(parser *p)
{
    while (isspace((unsigned char)*p->s)) ++p->s;
}

static hv_expr *parse_expr(parser *p, int depth);
static hv_expr *parse_unary(parser *p, int depth);

static double f_abs(double x) { return fabs(x); }

static const struct { const char *name; fn1_t f; } FN1[] = {
    {"sin", sin},   {"cos", cos},     {"tan", tan},   {"asin", asin}, {"acos", acos},
    {"atan", atan}, {"exp", exp},     {"log", log},   {"log10", log10}, {"sqrt", sqrt},
    {"abs", f_abs}, {"floor", floor}, {"ceil", ceil}};
static const struct { const char *name; fn2_t f; } FN2[] = {
    {"min", fmin}, {"max", fmax}, {"pow", pow}, {"atan2", atan2}};

static hv_expr *parse_atom(parser *p, int depth)
{
    skip(p);
    const char *tok = p->s;
    if (isdigit((unsigned char)*p->s) || (*p->s == '.' && isdigit((unsigned char)p->s[1]))) {
        char *end;
        double v = strtod(p->s, &end);
        p->s = end;
        hv_expr *e = node(p, N_NUM, NULL, NULL);
        if (e) e->value = v;
        return e;
    }
    if (isalpha((unsigned char)*p->s) || *p->s == '_') {
        while (isalnum((unsigned char)*p->s) || *p->s == '_') ++p->s;
        size_t n = (size_t)(p->s - tok);
        skip(p);
        if (*p->s == '(') {
            for (size_t i = 0; i < HV_COUNT(FN1); ++i)
                if (strlen(FN1[i].name) == n && strncmp(FN1[i].name, tok, n) == 0) {
                    ++p->s;
                    hv_expr *a = parse_expr(p, depth + 1);
                    if (!a) return NULL;
                    skip(p);
                    if (*p->s != ')') {
                        hv_expr_free(a);
                        return fail(p, "expected ')' after the argument of ", tok, n, "");
                    }
                    ++p->s;
                    hv_expr *e = node(p, N_FN1, a, NULL);
                    if (e) e->f1 = FN1[i].f;
                    return e;
                }
            for (size_t i = 0; i < HV_COUNT(FN2); ++i)
                if (strlen(FN2[i].name) == n && strncmp(FN2[i].name, tok, n) == 0) {
                    ++p->s;
                    hv_expr *a = parse_expr(p, depth + 1);
                    if (!a) return NULL;
                    skip(p);
                    if (*p->s != ',') {
                        hv_expr_free(a);
                        return fail(p, "", tok, n, " takes two arguments");
                    }
                    ++p->s;
                    hv_expr *b = parse_expr(p, depth + 1);
                    if (!b) {
                        hv_expr_free(a);
                        return NULL;
                    }
                    skip(p);
                    if (*p->s != ')') {
                        hv_expr_free(a);
                        hv_expr_free(b);
                        return fail(p, "expected ')' after the arguments of ", tok, n, "");
                    }
                    ++p->s;
                    hv_expr *e = node(p, N_FN2, a, b);
                    if (e) e->f2 = FN2[i].f;
                    return e;
                }
            p->s = tok;
            return fail(p, "unknown function '", tok, n, "'");
        }
        if (n == 1 && *tok == 'd') return node(p, N_D, NULL, NULL);
        if (n == 2 && strncmp(tok, "dg", 2) == 0) return node(p, N_DG, NULL, NULL);
        double v = 0;
        if (n == 2 && strncmp(tok, "pi", 2) == 0) v = M_PI;
        else if (n == 1 && *tok == 'e') v = M_E;
        else {
            p->s = tok;
            return fail(p, "unknown name '", tok, n, "' (use d, dg, pi, e)");
        }
        hv_expr *e = node(p, N_NUM, NULL, NULL);
        if (e) e->value = v;
        return e;
    }
    if (*p->s == '(') {
        ++p->s;
        hv_expr *e = parse_expr(p, depth + 1);
        if (!e) return NULL;
        skip(p);
        if (*p->s != ')') {
            hv_expr_free(e);
            return fail(p, "expected ')'", "", 0, "");
        }
        ++p->s;
        return e;
    }
    if (*p->s == '\0') return fail(p, "unexpected end of expression", "", 0, "");
    return fail(p, "unexpected '", p->s, 1, "'");
}

static hv_expr *parse_power(parser *p, int depth)
{
    hv_expr *a = parse_atom(p, depth);
    if (!a) return NULL;
    skip(p);
    if (*p->s == '^') {
        ++p->s;
        hv_expr *b = parse_unary(p, depth + 1);
        if (!b) {
            hv_expr_free(a);
            return NULL;
        }
        return node(p, N_POW, a, b);
    }
    return a;
}

static hv_expr *parse_unary(parser *p, int depth)
{
    if (depth > 200) return fail(p, "expression nested too deeply", "", 0, "");
    skip(p);
    if (*p->s == '-' || *p->s == '+') {
        int neg = *p->s == '-';
        ++p->s;
        hv_expr *a = parse_unary(p, depth + 1);
        if (!a) return NULL;
        return neg ? node(p, N_NEG, a, NULL) : a;
    }
    return parse_power(p, depth);
}

static hv_expr *parse_term(parser *p, int depth)
{
    hv_expr *a = parse_unary(p, depth);
    while (a) {
        skip(p);
        if (*p->s != '*' && *p->s != '/') break;
        int op = *p->s == '*' ? N_MUL : N_DIV;
        ++p->s;
        hv_expr *b = parse_unary(p, depth);
        if (!b) {
            hv_expr_free(a);
            return NULL;
        }
        a = node(p, op, a, b);
    }
    return a;
}

static hv_expr *parse_expr(parser *p, int depth)
{
    if (depth > 200) return fail(p, "expression nested too deeply", "", 0, "");
    hv_expr *a = parse_term(p, depth);
    while (a) {
        skip(p);
        if (*p->s != '+' && *p->s != '-') break;
        int op = *p->s == '+' ? N_ADD : N_SUB;
        ++p->s;
        hv_expr *b = parse_term(p, depth);
        if (!b) {
            hv_expr_free(a);
            return NULL;
        }
        a = node(p, op, a, b);
    }
    return a;
}

hv_status hv_expr_parse(const char *text, hv_expr **out)
{
    *out = NULL;
    parser p = {text, text, 0};
    hv_expr *e = parse_expr(&p, 0);
    if (!e) return p.failed ? HV_ERR_INVALID : hv_error_set(HV_ERR_INVALID, "empty expression");
    skip(&p);
    if (*p.s) {
        hv_expr_free(e);
        fail(&p, "unexpected '", p.s, 1, "' after the expression");
        return HV_ERR_INVALID;
    }
    *out = e;
    return HV_OK;
}

double hv_expr_eval(const hv_expr *e, double d, double dg)
{
    switch (e->op) {
    case N_NUM: return e->value;
    case N_D: return d;
    case N_DG: return dg;
    case N_NEG: return -hv_expr_eval(e->a, d, dg);
    case N_ADD: return hv_expr_eval(e->a, d, dg) + hv_expr_eval(e->b, d, dg);
    case N_SUB: return hv_expr_eval(e->a, d, dg) - hv_expr_eval(e->b, d, dg);
    case N_MUL: return hv_expr_eval(e->a, d, dg) * hv_expr_eval(e->b, d, dg);
    case N_DIV: return hv_expr_eval(e->a, d, dg) / hv_expr_eval(e->b, d, dg);
    case N_POW: return pow(hv_expr_eval(e->a, d, dg), hv_expr_eval(e->b, d, dg));
    case N_FN1: return e->f1(hv_expr_eval(e->a, d, dg));
    case N_FN2: return e->f2(hv_expr_eval(e->a, d, dg), hv_expr_eval(e->b, d, dg));
    }
    return NAN;
}

void hv_expr_free(hv_expr *e)
{
    if (!e) return;
    hv_expr_free(e->a);
    hv_expr_free(e->b);
    free(e);
}
