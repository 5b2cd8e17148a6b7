/* src/plot/plot.c - line plots on cairo (see hovox/plot.h): layout with measured text, 1-2-5
 * ticks, a legend placed where it covers no data, PNG/SVG output through atomic files. Used
 * for material profiles along a line (Wu Fig. 26). */
#include <cairo-svg.h>
#include <cairo.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/plot.h"

#define FONT "DejaVu Sans"
#define MAX_SERIES 64
#define MAX_MARKERS 64
#define MAX_SPANS 1000000
#define MAX_TICKS 64
#define MIN_SIDE 100
#define MAX_SIDE 8192

/* Colours of the furniture: dark frame and text, light grid, grey spans. */
static const double C_TEXT[3] = {0.12, 0.12, 0.12};
static const double C_FRAME[3] = {0.20, 0.20, 0.20};
static const double C_GRID[3] = {0.88, 0.88, 0.88};
static const double C_SPAN[3] = {0.86, 0.86, 0.86};
static const double C_MARK[3] = {0.30, 0.30, 0.30};

typedef struct series {
    char *name;
    double *y;
    float rgba[4];
    int dashed;
    int right; /* drawn against the right-hand axis */
} series;

typedef struct marker {
    double x;
    char *label;
} marker;

typedef struct span {
    double x0, x1;
    char *label;
} span;

struct hv_plot {
    int width, height;
    double *x;
    size_t n;
    series *series;
    int nseries;
    size_t series_cap;
    marker *markers;
    int nmarkers;
    size_t marker_cap;
    span *spans;
    int nspans;
    size_t span_cap;
    char *title, *subtitle, *xlabel, *ylabel;
    double ylo, yhi;
    int yauto;
    int y2;            /* a right-hand axis */
    char *y2label;
    double y2lo, y2hi;
    int y2auto;
};

/* ---- construction ------------------------------------------------------------------------ */

hv_status hv_plot_create(int width, int height, hv_plot **out)
{
    *out = NULL;
    if (width < MIN_SIDE || width > MAX_SIDE || height < MIN_SIDE || height > MAX_SIDE)
        return hv_error_set(HV_ERR_INVALID, "plot size %d x %d: each side must be in [%d, %d]",
                            width, height, MIN_SIDE, MAX_SIDE);
    hv_plot *p = hv_calloc(1, sizeof *p);
    if (!p) return HV_ERR_NOMEM;
    p->width = width;
    p->height = height;
    p->ylo = 0.0;
    p->yhi = 1.0;
    *out = p;
    return HV_OK;
}

static void drop_series(hv_plot *p)
{
    for (int i = 0; i < p->nseries; ++i) {
        free(p->series[i].name);
        free(p->series[i].y);
    }
    p->nseries = 0;
}

void hv_plot_destroy(hv_plot *p)
{
    if (!p) return;
    drop_series(p);
    free(p->series);
    for (int i = 0; i < p->nmarkers; ++i) free(p->markers[i].label);
    free(p->markers);
    for (int i = 0; i < p->nspans; ++i) free(p->spans[i].label);
    free(p->spans);
    free(p->x);
    free(p->title);
    free(p->subtitle);
    free(p->xlabel);
    free(p->ylabel);
    free(p->y2label);
    free(p);
}

/* cairo's toy text API stops drawing on invalid UTF-8, so strings are checked on entry. */
static int utf8_valid(const char *s)
{
    const unsigned char *u = (const unsigned char *)s;
    while (*u) {
        int n;
        unsigned c = *u;
        if (c < 0x80) n = 0;
        else if (c >= 0xC2 && c <= 0xDF) n = 1;
        else if (c >= 0xE0 && c <= 0xEF) n = 2;
        else if (c >= 0xF0 && c <= 0xF4) n = 3;
        else return 0;
        unsigned cp = n == 0 ? c : n == 1 ? c & 0x1F : n == 2 ? c & 0x0F : c & 0x07;
        for (int k = 1; k <= n; ++k) {
            if ((u[k] & 0xC0) != 0x80) return 0;
            cp = (cp << 6) | (u[k] & 0x3F);
        }
        if ((n == 2 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) || (n == 3 && (cp < 0x10000 || cp > 0x10FFFF)))
            return 0;
        u += n + 1;
    }
    return 1;
}

/* Copy an optional UTF-8 string ("" and NULL give NULL). */
static hv_status text_copy(const char *s, const char *what, char **out)
{
    *out = NULL;
    if (!s || !*s) return HV_OK;
    if (!utf8_valid(s)) return hv_error_set(HV_ERR_INVALID, "plot %s is not valid UTF-8", what);
    *out = hv_strdup(s);
    return *out ? HV_OK : HV_ERR_NOMEM;
}

/* Replace a text setting: NULL keeps it, "" clears it. */
static hv_status text_replace(char **slot, const char *s, const char *what)
{
    if (!s) return HV_OK;
    char *c;
    hv_status st = text_copy(s, what, &c);
    if (st != HV_OK) return st;
    free(*slot);
    *slot = c;
    return HV_OK;
}

hv_status hv_plot_set_x(hv_plot *p, const double *x, size_t n)
{
    if (n == 0) return hv_error_set(HV_ERR_INVALID, "plot: no x values");
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < n; ++i) {
        if (!isfinite(x[i]))
            return hv_error_set(HV_ERR_INVALID, "plot: x value %zu is not finite (%g)", i, x[i]);
        lo = HV_MIN(lo, x[i]);
        hi = HV_MAX(hi, x[i]);
    }
    if (!isfinite(hi - lo))
        return hv_error_set(HV_ERR_INVALID, "plot: x range [%g, %g] is too wide", lo, hi);
    double *c = hv_malloc_array(n, sizeof *c);
    if (!c) return HV_ERR_NOMEM;
    memcpy(c, x, n * sizeof *c);
    drop_series(p);
    free(p->x);
    p->x = c;
    p->n = n;
    return HV_OK;
}

hv_status hv_plot_add_series(hv_plot *p, const char *name, const double *y, const float rgba[4],
                             int *index)
{
    if (!p->x) return hv_error_set(HV_ERR_INVALID, "plot: series '%s' added before the x values", name ? name : "");
    if (p->nseries >= MAX_SERIES)
        return hv_error_set(HV_ERR_INVALID, "plot: at most %d series", MAX_SERIES);
    for (int k = 0; k < 4; ++k)
        if (!(rgba[k] >= 0.0f && rgba[k] <= 1.0f))
            return hv_error_set(HV_ERR_INVALID, "plot: series '%s': colour component %d is %g, not in [0, 1]",
                                name ? name : "", k, (double)rgba[k]);
    for (size_t i = 0; i < p->n; ++i)
        if (isinf(y[i]))
            return hv_error_set(HV_ERR_INVALID, "plot: series '%s': y value %zu is infinite", name ? name : "", i);
    series s;
    memset(&s, 0, sizeof s);
    hv_status st = text_copy(name, "series name", &s.name);
    if (st != HV_OK) return st;
    s.y = hv_malloc_array(p->n, sizeof *s.y);
    if (!s.y || hv_grow((void **)&p->series, &p->series_cap, (size_t)p->nseries + 1, sizeof *p->series)) {
        free(s.name);
        free(s.y);
        return HV_ERR_NOMEM;
    }
    memcpy(s.y, y, p->n * sizeof *s.y);
    memcpy(s.rgba, rgba, sizeof s.rgba);
    if (index) *index = p->nseries;
    p->series[p->nseries++] = s;
    return HV_OK;
}

hv_status hv_plot_set_series_dashed(hv_plot *p, int index, int dashed)
{
    if (index < 0 || index >= p->nseries)
        return hv_error_set(HV_ERR_INVALID, "plot: no series %d (have %d)", index, p->nseries);
    p->series[index].dashed = dashed != 0;
    return HV_OK;
}

hv_status hv_plot_set_title(hv_plot *p, const char *title, const char *subtitle)
{
    hv_status st = text_replace(&p->title, title, "title");
    return st == HV_OK ? text_replace(&p->subtitle, subtitle, "subtitle") : st;
}

hv_status hv_plot_set_labels(hv_plot *p, const char *xlabel, const char *ylabel)
{
    hv_status st = text_replace(&p->xlabel, xlabel, "x label");
    return st == HV_OK ? text_replace(&p->ylabel, ylabel, "y label") : st;
}

hv_status hv_plot_set_y_range(hv_plot *p, double lo, double hi)
{
    if (isnan(lo) && isnan(hi)) {
        p->yauto = 1;
        return HV_OK;
    }
    if (!isfinite(hi - lo) || !(lo < hi))
        return hv_error_set(HV_ERR_INVALID, "plot: y range [%g, %g] must be finite with lo < hi", lo, hi);
    p->yauto = 0;
    p->ylo = lo;
    p->yhi = hi;
    return HV_OK;
}

hv_status hv_plot_set_right_axis(hv_plot *p, const char *label, double lo, double hi)
{
    int autor = isnan(lo) && isnan(hi);
    if (!autor && (!isfinite(hi - lo) || !(lo < hi)))
        return hv_error_set(HV_ERR_INVALID, "plot: right-hand y range [%g, %g] must be finite with lo < hi", lo, hi);
    hv_status st = text_replace(&p->y2label, label, "right-hand y label");
    if (st != HV_OK) return st;
    p->y2 = 1;
    p->y2auto = autor;
    p->y2lo = autor ? 0.0 : lo;
    p->y2hi = autor ? 1.0 : hi;
    return HV_OK;
}

hv_status hv_plot_set_series_right(hv_plot *p, int index, int right)
{
    if (index < 0 || index >= p->nseries)
        return hv_error_set(HV_ERR_INVALID, "plot: no series %d (have %d)", index, p->nseries);
    if (right && !p->y2) return hv_error_set(HV_ERR_INVALID, "plot: series %d put on a right-hand axis the plot does not have", index);
    p->series[index].right = right != 0;
    return HV_OK;
}

hv_status hv_plot_add_marker(hv_plot *p, double x, const char *label)
{
    if (!isfinite(x)) return hv_error_set(HV_ERR_INVALID, "plot: marker position %g is not finite", x);
    if (p->nmarkers >= MAX_MARKERS) return hv_error_set(HV_ERR_INVALID, "plot: at most %d markers", MAX_MARKERS);
    char *l;
    hv_status st = text_copy(label, "marker label", &l);
    if (st != HV_OK) return st;
    if (hv_grow((void **)&p->markers, &p->marker_cap, (size_t)p->nmarkers + 1, sizeof *p->markers)) {
        free(l);
        return HV_ERR_NOMEM;
    }
    p->markers[p->nmarkers].x = x;
    p->markers[p->nmarkers].label = l;
    ++p->nmarkers;
    return HV_OK;
}

hv_status hv_plot_add_span(hv_plot *p, double x0, double x1, const char *label)
{
    if (!isfinite(x0) || !isfinite(x1))
        return hv_error_set(HV_ERR_INVALID, "plot: span [%g, %g] is not finite", x0, x1);
    if (p->nspans >= MAX_SPANS) return hv_error_set(HV_ERR_INVALID, "plot: at most %d spans", MAX_SPANS);
    char *l;
    hv_status st = text_copy(label, "span label", &l);
    if (st != HV_OK) return st;
    if (hv_grow((void **)&p->spans, &p->span_cap, (size_t)p->nspans + 1, sizeof *p->spans)) {
        free(l);
        return HV_ERR_NOMEM;
    }
    p->spans[p->nspans].x0 = HV_MIN(x0, x1);
    p->spans[p->nspans].x1 = HV_MAX(x0, x1);
    p->spans[p->nspans].label = l;
    ++p->nspans;
    return HV_OK;
}

/* ---- text ------------------------------------------------------------------------------- */

typedef enum font_role { F_TITLE, F_SUBTITLE, F_LABEL, F_TICK, F_LEGEND, F_MARKER } font_role;

static const double FONT_SIZE[] = {17.0, 12.5, 14.0, 12.0, 12.5, 11.5};

/* Unhinted metrics keep the layout a linear function of the scale and identical between the
 * measuring surface and every output surface. */
static void set_font_options(cairo_t *cr)
{
    cairo_font_options_t *fo = cairo_font_options_create();
    cairo_font_options_set_hint_metrics(fo, CAIRO_HINT_METRICS_OFF);
    cairo_font_options_set_hint_style(fo, CAIRO_HINT_STYLE_SLIGHT);
    cairo_font_options_set_antialias(fo, CAIRO_ANTIALIAS_GRAY);
    cairo_set_font_options(cr, fo);
    cairo_font_options_destroy(fo);
}

static void use_font(cairo_t *cr, font_role r, double scale, double shrink)
{
    cairo_select_font_face(cr, FONT, CAIRO_FONT_SLANT_NORMAL,
                           r == F_TITLE ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, FONT_SIZE[r] * scale * shrink);
}

static double text_w(cairo_t *cr, const char *s)
{
    cairo_text_extents_t e;
    cairo_text_extents(cr, s, &e);
    return e.x_advance;
}

static double line_h(cairo_t *cr)
{
    cairo_font_extents_t fe;
    cairo_font_extents(cr, &fe);
    return fe.ascent + fe.descent;
}

/* Draw s with its advance box anchored at (x, y): ax = 0 left, 0.5 centre, 1 right; ay = 0
 * top, 0.5 middle, 1 bottom of the ascent+descent box. */
static void text_at(cairo_t *cr, const char *s, double x, double y, double ax, double ay)
{
    cairo_font_extents_t fe;
    cairo_font_extents(cr, &fe);
    double w = text_w(cr, s);
    cairo_move_to(cr, x - ax * w, y - ay * (fe.ascent + fe.descent) + fe.ascent);
    cairo_show_text(cr, s);
}

/* ---- ticks ------------------------------------------------------------------------------ */

/* Smallest 1-2-5 multiple of a power of ten that is >= raw. */
static double nice_step(double raw)
{
    if (!(raw > 0) || !isfinite(raw)) return 1.0;
    double mag = pow(10.0, floor(log10(raw)));
    double f = raw / mag;
    double n = f <= 1.0 + 1e-9 ? 1.0 : f <= 2.0 + 1e-9 ? 2.0 : f <= 5.0 + 1e-9 ? 5.0 : 10.0;
    return n * mag;
}

static double next_step(double step) { return nice_step(step * 1.5); }

typedef struct axis {
    double view[2];      /* data range mapped onto the plot area */
    double step;         /* tick step */
    int nticks;          /* ticks at first + k*step, k < nticks */
    double first;
    int decimals;        /* -1: %g */
    double label_w_max;  /* widest tick label */
} axis;

static double tick_value(const axis *a, int k)
{
    double v = a->first + (double)k * a->step;
    return fabs(v) < a->step * 1e-9 ? 0.0 : v;
}

/* Tick k's label; negative numbers get a proper minus sign (U+2212). */
static void tick_label(const axis *a, int k, char *buf, size_t size)
{
    double v = tick_value(a, k);
    char num[64];
    if (a->decimals < 0) snprintf(num, sizeof num, "%g", fabs(v));
    else snprintf(num, sizeof num, "%.*f", a->decimals, fabs(v));
    snprintf(buf, size, "%s%s", v < 0 ? "\xe2\x88\x92" : "", num);
}

/* Ticks for the step: every multiple of step inside [lo, hi]. */
static void axis_ticks(axis *a, double lo, double hi, double step)
{
    a->step = step;
    a->first = ceil(lo / step - 1e-9) * step;
    double n = floor((hi - a->first) / step + 1e-9) + 1; /* clamped before the cast */
    a->nticks = n >= MAX_TICKS ? MAX_TICKS : n > 0 ? (int)n : 0;
    double big = HV_MAX(fabs(lo), fabs(hi));
    int d = step >= 1.0 ? 0 : (int)ceil(-log10(step) - 1e-9);
    a->decimals = (d > 6 || big >= 1e7) ? -1 : d;
}

static void axis_measure(axis *a, cairo_t *cr)
{
    char buf[80];
    a->label_w_max = 0;
    for (int k = 0; k < a->nticks; ++k) {
        tick_label(a, k, buf, sizeof buf);
        a->label_w_max = HV_MAX(a->label_w_max, text_w(cr, buf));
    }
}

/* ---- layout ----------------------------------------------------------------------------- */

typedef struct box {
    double x, y, w, h;
} box;

typedef struct legend_entry {
    const char *text;
    int series; /* index, or -1 for a span entry */
} legend_entry;

typedef struct layout {
    double s;                     /* scale of fonts and lines */
    double left, top, right, bottom;
    axis xa, ya, y2a;             /* y2a: the right-hand axis (nticks 0 when none) */
    legend_entry entries[MAX_SERIES + 16];
    int nentries;
    box legend;                   /* w == 0: no legend */
    double legend_row, legend_pad, swatch_w;
    box mlabel[MAX_MARKERS];      /* label boxes of markers (w == 0: none) */
    int mvisible[MAX_MARKERS];
} layout;

static double map_x(const layout *L, double x)
{
    return L->left + (x - L->xa.view[0]) / (L->xa.view[1] - L->xa.view[0]) * (L->right - L->left);
}

static double map_y_on(const layout *L, const axis *a, double y)
{
    return L->bottom - (y - a->view[0]) / (a->view[1] - a->view[0]) * (L->bottom - L->top);
}

static double map_y(const layout *L, double y) { return map_y_on(L, &L->ya, y); }

/* The y axis series sr is drawn against. */
static const axis *series_axis(const layout *L, const series *sr) { return sr->right ? &L->y2a : &L->ya; }

static void x_range(const hv_plot *p, double r[2])
{
    r[0] = r[1] = p->x[0];
    for (size_t i = 1; i < p->n; ++i) {
        r[0] = HV_MIN(r[0], p->x[i]);
        r[1] = HV_MAX(r[1], p->x[i]);
    }
    if (r[1] - r[0] <= 1e-12 * HV_MAX(1.0, fabs(r[0]))) {
        double d = HV_MAX(0.5, fabs(r[0]) * 0.05);
        r[0] -= d;
        r[1] += d;
    }
}

/* y ticks and view for a plot area of height h: the left axis (right = 0) over [lo, hi] or, with
 * autor, the data of its series; the same for the right-hand axis. */
static void y_axis(const hv_plot *p, layout *L, double h, int right)
{
    axis *a = right ? &L->y2a : &L->ya;
    int target = (int)HV_MAX(2.0, floor(h / (45.0 * L->s)));
    double lo = right ? p->y2lo : p->ylo, hi = right ? p->y2hi : p->yhi;
    if (right ? p->y2auto : p->yauto) {
        double mn = INFINITY, mx = -INFINITY;
        for (int s = 0; s < p->nseries; ++s)
            for (size_t i = 0; i < p->n && p->series[s].right == right; ++i) {
                double v = p->series[s].y[i];
                if (isnan(v)) continue;
                mn = HV_MIN(mn, v);
                mx = HV_MAX(mx, v);
            }
        if (!(mn <= mx)) {
            mn = 0.0;
            mx = 1.0;
        } else if (!isfinite(mx - mn)) {
            mn = HV_MAX(mn, -1e307);
            mx = HV_MIN(mx, 1e307);
        } else if (mx - mn <= 1e-12 * HV_MAX(1.0, fabs(mx))) {
            double d = HV_MAX(0.5, fabs(mx) * 0.1);
            mn -= d;
            mx += d;
        }
        double step = nice_step((mx - mn) / target);
        /* the tolerance absorbs float noise in the data (fractions are 32-bit floats) */
        lo = floor(mn / step + 1e-6) * step;
        hi = ceil(mx / step - 1e-6) * step;
    }
    double step = nice_step((hi - lo) / target);
    axis_ticks(a, lo, hi, step);
    double pad = 0.03 * (hi - lo);
    a->view[0] = lo - pad;
    a->view[1] = hi + pad;
}

/* x ticks for a plot area of width w: the 1-2-5 step giving about 80 px (scaled) per tick,
 * widened until the labels keep 16 px (scaled) apart. */
static void x_axis(const hv_plot *p, layout *L, cairo_t *cr, double w)
{
    axis *a = &L->xa;
    x_range(p, a->view);
    double range = a->view[1] - a->view[0];
    int target = (int)HV_MAX(2.0, floor(w / (80.0 * L->s)));
    double step = nice_step(range / target);
    use_font(cr, F_TICK, L->s, 1.0);
    for (int iter = 0; iter < 30; ++iter) {
        axis_ticks(a, a->view[0], a->view[1], step);
        axis_measure(a, cr);
        if (a->nticks < 2 || a->label_w_max + 16.0 * L->s <= step / range * w) break;
        step = next_step(step);
    }
}

/* Does segment (x0,y0)-(x1,y1) meet box b? (Liang-Barsky clipping.) */
static int segment_hits(const box *b, double x0, double y0, double x1, double y1)
{
    double t0 = 0.0, t1 = 1.0, dx = x1 - x0, dy = y1 - y0;
    double pp[4] = {-dx, dx, -dy, dy};
    double qq[4] = {x0 - b->x, b->x + b->w - x0, y0 - b->y, b->y + b->h - y0};
    for (int i = 0; i < 4; ++i) {
        if (pp[i] == 0.0) {
            if (qq[i] < 0.0) return 0;
            continue;
        }
        double r = qq[i] / pp[i];
        if (pp[i] < 0.0) {
            if (r > t1) return 0;
            if (r > t0) t0 = r;
        } else {
            if (r < t0) return 0;
            if (r < t1) t1 = r;
        }
    }
    return 1;
}

static int boxes_overlap(const box *a, const box *b)
{
    return a->x < b->x + b->w && b->x < a->x + a->w && a->y < b->y + b->h && b->y < a->y + a->h;
}

/* Would the legend at box b (inflated by a margin) cover a line, a marker or its label? */
static int legend_collides(const hv_plot *p, const layout *L, const box *b)
{
    double m = 3.0 * L->s;
    box g = {b->x - m, b->y - m, b->w + 2 * m, b->h + 2 * m};
    for (int s = 0; s < p->nseries; ++s) {
        const double *y = p->series[s].y;
        const axis *a = series_axis(L, &p->series[s]);
        for (size_t i = 0; i < p->n; ++i) {
            if (isnan(y[i])) continue;
            double x0 = map_x(L, p->x[i]), y0 = map_y_on(L, a, HV_CLAMP(y[i], a->view[0], a->view[1]));
            int next = i + 1 < p->n && !isnan(y[i + 1]);
            double x1 = x0, y1 = y0;
            if (next) {
                x1 = map_x(L, p->x[i + 1]);
                y1 = map_y_on(L, a, HV_CLAMP(y[i + 1], a->view[0], a->view[1]));
            }
            if (segment_hits(&g, x0, y0, x1, y1)) return 1;
        }
    }
    for (int k = 0; k < p->nmarkers; ++k) {
        if (!L->mvisible[k]) continue;
        double x = map_x(L, p->markers[k].x);
        if (segment_hits(&g, x, L->top, x, L->bottom)) return 1;
        if (L->mlabel[k].w > 0 && boxes_overlap(&g, &L->mlabel[k])) return 1;
    }
    return 0;
}

/* Marker label boxes centred over their lines just above the plot area, so they never hide
 * data; a label that would overlap an earlier one moves up a row. Returns the rows used. */
static int place_marker_labels(const hv_plot *p, layout *L, cairo_t *cr)
{
    use_font(cr, F_MARKER, L->s, 1.0);
    double h = line_h(cr) + 2.0 * L->s, gap = 3.0 * L->s;
    int rows = 0;
    for (int k = 0; k < p->nmarkers; ++k) {
        double x = p->markers[k].x;
        L->mvisible[k] = x >= L->xa.view[0] && x <= L->xa.view[1];
        L->mlabel[k].w = 0;
        if (!L->mvisible[k] || !p->markers[k].label) continue;
        double w = text_w(cr, p->markers[k].label) + 4.0 * L->s;
        box b = {map_x(L, x) - w / 2, L->top - gap - h, w, h};
        b.x = HV_CLAMP(b.x, 2.0 * L->s, p->width - 2.0 * L->s - w);
        int row = 0;
        for (; row < 16; ++row) {
            int clash = 0;
            for (int j = 0; j < k && !clash; ++j)
                clash = L->mlabel[j].w > 0 && boxes_overlap(&b, &L->mlabel[j]);
            if (!clash) break;
            b.y -= h;
        }
        rows = HV_MAX(rows, row + 1);
        L->mlabel[k] = b;
    }
    return rows;
}

/* One layout pass with `marker_rows` rows of marker labels reserved above the plot area;
 * returns the rows the labels need. */
static int layout_pass(const hv_plot *p, cairo_t *cr, layout *L, int marker_rows)
{
    memset(L, 0, sizeof *L);
    double W = p->width, H = p->height;
    double s = HV_CLAMP(sqrt(W * H / (900.0 * 560.0)), 0.75, 8.0);
    L->s = s;
    double pad = 12.0 * s, tick_len = 5.0 * s;

    /* vertical: title block, marker labels, plot area, tick labels, x label */
    double top = pad;
    if (p->title) {
        use_font(cr, F_TITLE, s, 1.0);
        top += line_h(cr) + 2.0 * s;
    }
    if (p->subtitle) {
        use_font(cr, F_SUBTITLE, s, 1.0);
        top += line_h(cr) + 2.0 * s;
    }
    top += (p->title || p->subtitle) ? 10.0 * s : 6.0 * s;
    if (marker_rows > 0) {
        use_font(cr, F_MARKER, s, 1.0);
        top += marker_rows * (line_h(cr) + 2.0 * s) + 3.0 * s;
    }
    use_font(cr, F_TICK, s, 1.0);
    double tick_h = line_h(cr);
    double bottom = pad + tick_len + 4.0 * s + tick_h;
    double label_h = 0;
    if (p->xlabel || p->ylabel || p->y2label) {
        use_font(cr, F_LABEL, s, 1.0);
        label_h = line_h(cr);
    }
    if (p->xlabel) bottom += label_h + 6.0 * s;
    L->top = round(top);
    L->bottom = round(H - bottom);
    y_axis(p, L, L->bottom - L->top, 0);
    if (p->y2) y_axis(p, L, L->bottom - L->top, 1);
    use_font(cr, F_TICK, s, 1.0);
    axis_measure(&L->ya, cr);
    if (p->y2) axis_measure(&L->y2a, cr);
    /* the right-hand axis: ticks, tick labels and its label, like the left one mirrored */
    double right_axis = p->y2 ? tick_len + 4.0 * s + L->y2a.label_w_max + (p->y2label ? 8.0 * s + label_h : 0.0) : 0.0;

    /* horizontal: y label, tick labels, plot area, room for the last x label (or legend) */
    double left = pad + (p->ylabel ? label_h + 8.0 * s : 0.0) + L->ya.label_w_max + 4.0 * s + tick_len;
    L->left = round(left);
    double right = pad + 20.0 * s + right_axis;
    for (int pass = 0; pass < 2; ++pass) {
        L->right = round(W - right);
        x_axis(p, L, cr, L->right - L->left);
        /* the last tick label is centred on its tick and must not leave the image */
        double over = 0;
        if (L->xa.nticks > 0) {
            char buf[80];
            tick_label(&L->xa, L->xa.nticks - 1, buf, sizeof buf);
            double last = map_x(L, tick_value(&L->xa, L->xa.nticks - 1));
            over = last + 0.5 * text_w(cr, buf) - L->right;
        }
        right = pad + HV_MAX(right_axis, over);
    }

    /* legend entries: named series, then one per distinct span label */
    for (int i = 0; i < p->nseries; ++i)
        if (p->series[i].name) L->entries[L->nentries++] = (legend_entry){p->series[i].name, i};
    for (int i = 0; i < p->nspans && L->nentries < (int)HV_COUNT(L->entries); ++i) {
        const char *t = p->spans[i].label;
        int seen = !t;
        for (int e = 0; e < L->nentries && !seen; ++e)
            seen = L->entries[e].series < 0 && strcmp(L->entries[e].text, t) == 0;
        if (!seen) L->entries[L->nentries++] = (legend_entry){t, -1};
    }
    int rows = place_marker_labels(p, L, cr);
    if (L->nentries == 0) return rows;

    use_font(cr, F_LEGEND, s, 1.0);
    double tw = 0;
    for (int e = 0; e < L->nentries; ++e) tw = HV_MAX(tw, text_w(cr, L->entries[e].text));
    L->legend_row = 1.45 * line_h(cr);
    L->legend_pad = 8.0 * s;
    L->swatch_w = 26.0 * s;
    double lw = 2 * L->legend_pad + L->swatch_w + 7.0 * s + tw;
    double lh = 2 * L->legend_pad + L->nentries * L->legend_row - (L->legend_row - line_h(cr));
    double m = 10.0 * s;
    double l = L->left, r = L->right, t = L->top, b = L->bottom;
    box cand[8] = {{r - m - lw, t + m, lw, lh},           {l + m, t + m, lw, lh},
                   {r - m - lw, b - m - lh, lw, lh},      {l + m, b - m - lh, lw, lh},
                   {r - m - lw, (t + b - lh) / 2, lw, lh}, {l + m, (t + b - lh) / 2, lw, lh},
                   {(l + r - lw) / 2, t + m, lw, lh},     {(l + r - lw) / 2, b - m - lh, lw, lh}};
    if (lw + 2 * m <= r - l && lh + 2 * m <= b - t)
        for (int c = 0; c < 8; ++c)
            if (!legend_collides(p, L, &cand[c])) {
                L->legend = cand[c];
                L->legend.x = round(L->legend.x);
                L->legend.y = round(L->legend.y);
                return rows;
            }
    /* every inside place covers data: the legend goes to the right of the plot area */
    double gap = 14.0 * s + right_axis;
    L->right = round(W - pad - lw - gap);
    x_axis(p, L, cr, L->right - L->left);
    rows = place_marker_labels(p, L, cr);
    L->legend = (box){L->right + gap, L->top, lw, lh};
    return rows;
}

/* Plot area, ticks, marker labels and the legend for plot p, measuring text with cr. The
 * rows of marker labels depend on the horizontal layout, which the rows do not change much:
 * a second pass (rarely a third) reserves what the first found. */
static void compute_layout(const hv_plot *p, cairo_t *cr, layout *L)
{
    int reserve = 0;
    for (int pass = 0; pass < 3; ++pass) {
        int rows = layout_pass(p, cr, L, reserve);
        if (rows <= reserve) break;
        reserve = rows;
    }
}

/* ---- drawing ---------------------------------------------------------------------------- */

static void rgb(cairo_t *cr, const double c[3]) { cairo_set_source_rgb(cr, c[0], c[1], c[2]); }

/* A crisp line width (whole pixels) and the offset that centres it on pixel rows. */
static double crisp(double w, double *off)
{
    double r = HV_MAX(1.0, round(w));
    *off = fmod(r, 2.0) == 1.0 ? 0.5 : 0.0;
    return r;
}

static int light_colour(const float c[4])
{
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2] > 0.82;
}

/* The polyline of y with breaks at NAN; an isolated sample becomes a zero-length segment, which
 * the round cap draws as a dot. */
static void series_path(const hv_plot *p, const layout *L, cairo_t *cr, const series *sr)
{
    const double *y = sr->y;
    const axis *a = series_axis(L, sr);
    for (size_t i = 0; i < p->n; ++i) {
        if (isnan(y[i])) continue;
        /* far off-chart values are pulled in to keep cairo's fixed-point coordinates sane; the
         * clip hides them either way */
        double yr = a->view[1] - a->view[0];
        double yc = HV_CLAMP(y[i], a->view[0] - 100 * yr, a->view[1] + 100 * yr);
        double px = map_x(L, p->x[i]), py = map_y_on(L, a, yc);
        int prev = i > 0 && !isnan(y[i - 1]), next = i + 1 < p->n && !isnan(y[i + 1]);
        if (!prev) {
            cairo_move_to(cr, px, py);
            if (!next) cairo_line_to(cr, px, py);
        } else {
            cairo_line_to(cr, px, py);
        }
    }
}

static void stroke_series(cairo_t *cr, const series *sr, double width, double s, int halo)
{
    if (sr->dashed) {
        double d[2] = {7.0 * s, 4.0 * s};
        cairo_set_dash(cr, d, 2, 0);
    } else {
        cairo_set_dash(cr, NULL, 0, 0);
    }
    if (halo) {
        cairo_set_source_rgb(cr, 0.45, 0.45, 0.45);
        cairo_set_line_width(cr, width + 1.5 * s);
        cairo_stroke_preserve(cr);
    }
    cairo_set_source_rgba(cr, sr->rgba[0], sr->rgba[1], sr->rgba[2], sr->rgba[3]);
    cairo_set_line_width(cr, width);
    cairo_stroke(cr);
    cairo_set_dash(cr, NULL, 0, 0);
}

/* The plot area, clipped: spans, then the grid over them, then markers and lines. */
static void draw_area(const hv_plot *p, const layout *L, cairo_t *cr, double width)
{
    double s = L->s, off, lw;
    double l = L->left, t = L->top, r = L->right, b = L->bottom;
    cairo_save(cr);
    cairo_rectangle(cr, l, t, r - l, b - t);
    cairo_clip(cr);

    rgb(cr, C_SPAN);
    for (int i = 0; i < p->nspans; ++i) {
        double x0 = HV_MAX(map_x(L, p->spans[i].x0), l), x1 = HV_MIN(map_x(L, p->spans[i].x1), r);
        if (x1 > x0) cairo_rectangle(cr, x0, t, x1 - x0, b - t);
    }
    cairo_fill(cr);

    lw = crisp(1.0 * s, &off);
    cairo_set_line_width(cr, lw);
    rgb(cr, C_GRID);
    for (int k = 0; k < L->ya.nticks; ++k) {
        double y = round(map_y(L, tick_value(&L->ya, k))) + off;
        cairo_move_to(cr, l, y);
        cairo_line_to(cr, r, y);
    }
    for (int k = 0; k < L->xa.nticks; ++k) {
        double x = round(map_x(L, tick_value(&L->xa, k))) + off;
        cairo_move_to(cr, x, t);
        cairo_line_to(cr, x, b);
    }
    cairo_stroke(cr);

    double dash[2] = {5.0 * s, 3.5 * s};
    lw = crisp(1.2 * s, &off);
    cairo_set_line_width(cr, lw);
    cairo_set_dash(cr, dash, 2, 0);
    rgb(cr, C_MARK);
    for (int k = 0; k < p->nmarkers; ++k) {
        if (!L->mvisible[k]) continue;
        double x = round(map_x(L, p->markers[k].x)) + off;
        cairo_move_to(cr, x, t);
        cairo_line_to(cr, x, b);
    }
    cairo_stroke(cr);
    cairo_set_dash(cr, NULL, 0, 0);

    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    for (int i = 0; i < p->nseries; ++i) {
        series_path(p, L, cr, &p->series[i]);
        stroke_series(cr, &p->series[i], width, s, light_colour(p->series[i].rgba));
    }
    cairo_restore(cr);

}

/* The frame with outward ticks. */
static void draw_frame(const layout *L, cairo_t *cr, double tick)
{
    double s = L->s, off, lw;
    double l = L->left, t = L->top, r = L->right, b = L->bottom;
    lw = crisp(1.0 * s, &off);
    cairo_set_line_width(cr, lw);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    rgb(cr, C_FRAME);
    cairo_rectangle(cr, l + off, t + off, r - l - 2 * off, b - t - 2 * off);
    for (int k = 0; k < L->ya.nticks; ++k) {
        double y = round(map_y(L, tick_value(&L->ya, k))) + off;
        cairo_move_to(cr, l, y);
        cairo_line_to(cr, l - tick, y);
    }
    for (int k = 0; k < L->xa.nticks; ++k) {
        double x = round(map_x(L, tick_value(&L->xa, k))) + off;
        cairo_move_to(cr, x, b);
        cairo_line_to(cr, x, b + tick);
    }
    for (int k = 0; k < L->y2a.nticks; ++k) {
        double y = round(map_y_on(L, &L->y2a, tick_value(&L->y2a, k))) + off;
        cairo_move_to(cr, r, y);
        cairo_line_to(cr, r + tick, y);
    }
    cairo_stroke(cr);

}

/* Tick labels and axis labels. */
static void draw_labels(const hv_plot *p, const layout *L, cairo_t *cr, double tick)
{
    double s = L->s;
    double l = L->left, t = L->top, r = L->right, b = L->bottom;
    char buf[80];
    /* tick labels */
    rgb(cr, C_TEXT);
    use_font(cr, F_TICK, s, 1.0);
    double tick_h = line_h(cr);
    for (int k = 0; k < L->ya.nticks; ++k) {
        tick_label(&L->ya, k, buf, sizeof buf);
        text_at(cr, buf, l - tick - 4.0 * s, map_y(L, tick_value(&L->ya, k)), 1.0, 0.5);
    }
    for (int k = 0; k < L->xa.nticks; ++k) {
        tick_label(&L->xa, k, buf, sizeof buf);
        text_at(cr, buf, map_x(L, tick_value(&L->xa, k)), b + tick + 4.0 * s, 0.5, 0.0);
    }
    for (int k = 0; k < L->y2a.nticks; ++k) {
        tick_label(&L->y2a, k, buf, sizeof buf);
        text_at(cr, buf, r + tick + 4.0 * s, map_y_on(L, &L->y2a, tick_value(&L->y2a, k)), 0.0, 0.5);
    }

    /* axis labels */
    use_font(cr, F_LABEL, s, 1.0);
    if (p->xlabel) text_at(cr, p->xlabel, (l + r) / 2, b + tick + 4.0 * s + tick_h + 6.0 * s, 0.5, 0.0);
    if (p->ylabel) {
        cairo_save(cr);
        cairo_translate(cr, 12.0 * s, (t + b) / 2);
        cairo_rotate(cr, -M_PI / 2);
        text_at(cr, p->ylabel, 0, 0, 0.5, 0.0);
        cairo_restore(cr);
    }
    if (p->y2 && p->y2label) { /* read bottom to top as well, to the right of the tick labels */
        use_font(cr, F_TICK, s, 1.0);
        double x = r + tick + 4.0 * s + L->y2a.label_w_max + 8.0 * s;
        use_font(cr, F_LABEL, s, 1.0);
        cairo_save(cr);
        cairo_translate(cr, x, (t + b) / 2);
        cairo_rotate(cr, -M_PI / 2);
        text_at(cr, p->y2label, 0, 0, 0.5, 0.0);
        cairo_restore(cr);
    }

}

/* Title and subtitle, centred over the plot area, shrunk to fit it; the marker labels above it. */
static void draw_titles(const hv_plot *p, const layout *L, cairo_t *cr)
{
    double s = L->s;
    double l = L->left, r = L->right;
    double y = 12.0 * s;
    if (p->title) {
        use_font(cr, F_TITLE, s, 1.0);
        double w = text_w(cr, p->title), avail = HV_MAX(r - l, 10.0);
        double shrink = w > avail ? HV_MAX(0.6, avail / w) : 1.0;
        double h = line_h(cr);
        use_font(cr, F_TITLE, s, shrink);
        text_at(cr, p->title, (l + r) / 2, y + h * (1.0 - shrink), 0.5, 0.0);
        y += h + 2.0 * s;
    }
    if (p->subtitle) {
        use_font(cr, F_SUBTITLE, s, 1.0);
        cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
        text_at(cr, p->subtitle, (l + r) / 2, y, 0.5, 0.0);
    }

    /* marker labels above the plot area */
    use_font(cr, F_MARKER, s, 1.0);
    rgb(cr, C_MARK);
    for (int k = 0; k < p->nmarkers; ++k) {
        const box *mb = &L->mlabel[k];
        if (mb->w > 0) text_at(cr, p->markers[k].label, mb->x + mb->w / 2, mb->y + mb->h / 2, 0.5, 0.5);
    }

}

static void draw_legend(const hv_plot *p, const layout *L, cairo_t *cr, double width)
{
    double s = L->s, off, lw;
    if (L->legend.w > 0) {
        const box *g = &L->legend;
        lw = crisp(1.0 * s, &off);
        cairo_rectangle(cr, g->x + off, g->y + off, g->w - 2 * off, g->h - 2 * off);
        cairo_set_source_rgba(cr, 1, 1, 1, 0.92);
        cairo_fill_preserve(cr);
        cairo_set_source_rgb(cr, 0.75, 0.75, 0.75);
        cairo_set_line_width(cr, lw);
        cairo_stroke(cr);
        use_font(cr, F_LEGEND, s, 1.0);
        double th = line_h(cr);
        for (int e = 0; e < L->nentries; ++e) {
            double ry = g->y + L->legend_pad + e * L->legend_row, cy = ry + th / 2;
            double sx = g->x + L->legend_pad;
            if (L->entries[e].series >= 0) {
                const series *sr = &p->series[L->entries[e].series];
                cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
                cairo_move_to(cr, sx, cy);
                cairo_line_to(cr, sx + L->swatch_w, cy);
                stroke_series(cr, sr, width + 0.5 * s, s, light_colour(sr->rgba));
            } else {
                double sh = 0.8 * th;
                cairo_rectangle(cr, sx, cy - sh / 2, L->swatch_w, sh);
                rgb(cr, C_SPAN);
                cairo_fill_preserve(cr);
                cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
                cairo_set_line_width(cr, HV_MAX(1.0, s));
                cairo_stroke(cr);
            }
            rgb(cr, C_TEXT);
            text_at(cr, L->entries[e].text, sx + L->swatch_w + 7.0 * s, ry, 0.0, 0.0);
        }
    }
}

static void draw(const hv_plot *p, const layout *L, cairo_t *cr)
{
    double s = L->s;
    set_font_options(cr);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    double width = HV_MAX(1.5, 2.0 * s), tick = 5.0 * s;
    draw_area(p, L, cr, width);
    draw_frame(L, cr, tick);
    draw_labels(p, L, cr, tick);
    draw_titles(p, L, cr);
    draw_legend(p, L, cr, width);
}

/* ---- output ----------------------------------------------------------------------------- */

static hv_status cairo_failed(cairo_status_t st, const char *path)
{
    if (st == CAIRO_STATUS_NO_MEMORY) return hv_error_set(HV_ERR_NOMEM, "%s: out of memory while drawing the plot", path);
    return hv_error_set(HV_ERR_INTERNAL, "%s: cairo: %s", path, cairo_status_to_string(st));
}

/* The layout is always measured on the same kind of surface, so PNG, SVG and
 * hv_plot_data_to_pixel agree to the last bit. */
static hv_status measure(const hv_plot *p, layout *L)
{
    cairo_surface_t *sf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1);
    cairo_t *cr = cairo_create(sf);
    cairo_status_t st = cairo_status(cr);
    if (st == CAIRO_STATUS_SUCCESS) {
        set_font_options(cr);
        compute_layout(p, cr, L);
        st = cairo_status(cr);
    }
    cairo_destroy(cr);
    cairo_surface_destroy(sf);
    return st == CAIRO_STATUS_SUCCESS ? HV_OK : cairo_failed(st, "plot");
}

hv_status hv_plot_data_to_pixel(const hv_plot *p, double x, double y, double px[2], double bx[4])
{
    if (!p->x) return hv_error_set(HV_ERR_INVALID, "plot: no x values");
    layout *L = hv_malloc(sizeof *L);
    if (!L) return HV_ERR_NOMEM;
    hv_status st = measure(p, L);
    if (st == HV_OK) {
        px[0] = map_x(L, x);
        px[1] = map_y(L, y);
        if (bx) {
            bx[0] = L->left;
            bx[1] = L->top;
            bx[2] = L->right;
            bx[3] = L->bottom;
        }
    }
    free(L);
    return st;
}

typedef struct sink {
    FILE *fp;
    int err;
} sink;

static cairo_status_t sink_write(void *closure, const unsigned char *data, unsigned int len)
{
    sink *k = closure;
    if (fwrite(data, 1, len, k->fp) != len) {
        k->err = errno ? errno : EIO;
        return CAIRO_STATUS_WRITE_ERROR;
    }
    return CAIRO_STATUS_SUCCESS;
}

/* Draw p onto a PNG or SVG stream. `what` names the output in messages. */
static hv_status render(const hv_plot *p, FILE *fp, int svg, const char *what)
{
    if (!p->x) return hv_error_set(HV_ERR_INVALID, "%s: the plot has no x values", what);
    layout *L = hv_malloc(sizeof *L);
    if (!L) return HV_ERR_NOMEM;
    hv_status s = measure(p, L);
    if (s != HV_OK) {
        free(L);
        return s;
    }
    sink k = {fp, 0};
    cairo_surface_t *sf = svg ? cairo_svg_surface_create_for_stream(sink_write, &k, p->width, p->height)
                              : cairo_image_surface_create(CAIRO_FORMAT_RGB24, p->width, p->height);
    cairo_t *cr = cairo_create(sf);
    draw(p, L, cr);
    cairo_status_t st = cairo_status(cr);
    cairo_destroy(cr);
    if (st == CAIRO_STATUS_SUCCESS) {
        if (svg) cairo_surface_finish(sf);
        else st = cairo_surface_write_to_png_stream(sf, sink_write, &k);
        if (st == CAIRO_STATUS_SUCCESS) st = cairo_surface_status(sf);
    }
    cairo_surface_destroy(sf);
    free(L);
    if (k.err) return hv_error_set(HV_ERR_IO, "%s: write failed: %s", what, strerror(k.err));
    if (st != CAIRO_STATUS_SUCCESS) return cairo_failed(st, what);
    return HV_OK;
}

static hv_status write_plot(const hv_plot *p, const char *path, int svg)
{
    if (!p->x) return hv_error_set(HV_ERR_INVALID, "%s: the plot has no x values", path);
    hv_atomic_file af;
    hv_status s = hv_atomic_open(&af, path, "wb");
    if (s != HV_OK) return s;
    s = render(p, af.fp, svg, path);
    if (s != HV_OK) {
        hv_atomic_abort(&af);
        return s;
    }
    return hv_atomic_commit(&af);
}

hv_status hv_plot_write_png(const hv_plot *p, const char *path) { return write_plot(p, path, 0); }

hv_status hv_plot_write_svg(const hv_plot *p, const char *path) { return write_plot(p, path, 1); }

hv_status hv_plot_write_png_stream(const hv_plot *p, FILE *fp) { return render(p, fp, 0, "plot"); }

hv_status hv_plot_write_svg_stream(const hv_plot *p, FILE *fp) { return render(p, fp, 1, "plot"); }
