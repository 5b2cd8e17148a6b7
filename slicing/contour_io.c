/* slicing/contour_io.c - contour files: SVG (one group per layer, mm user units) and the
 * Common Layer Interface 2.0 (ASCII or binary), streamed layer by layer and written atomically. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "slice_internal.h"

struct hv_contour_writer {
    hv_atomic_file af;
    hv_contour_format format;
    size_t layers, added;
    char *buf; /* text of the layer being written */
    size_t len, cap;
    int failed;
    size_t nbodies; /* > 1: an assembly, its loops labelled by body */
    char **bodies;
};

/* ---- text buffer with fast fixed-point numbers -------------------------------------------- */

static void need(hv_contour_writer *w, size_t n)
{
    if (w->failed || w->len + n <= w->cap) return;
    if (hv_grow((void **)&w->buf, &w->cap, w->len + n, 1) != HV_OK) w->failed = 1;
}

static void put(hv_contour_writer *w, const char *s, size_t n)
{
    need(w, n);
    if (w->failed) return;
    memcpy(w->buf + w->len, s, n);
    w->len += n;
}

static void puts_(hv_contour_writer *w, const char *s) { put(w, s, strlen(s)); }

static void printf_(hv_contour_writer *w, const char *fmt, ...) HV_PRINTF(2, 3);
static void printf_(hv_contour_writer *w, const char *fmt, ...)
{
    char tmp[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (n > 0) put(w, tmp, (size_t)HV_MIN((size_t)n, sizeof tmp - 1));
}

/* v rounded to 6 decimals, trailing zeros (and a bare point) dropped: "12.5", "-0.000125",
 * "40". Integer arithmetic: printf is the bottleneck of big contour files otherwise. */
static void num(hv_contour_writer *w, double v)
{
    need(w, 32);
    if (w->failed) return;
    char *p = w->buf + w->len;
    if (!(fabs(v) < 9e12)) { /* beyond the fixed-point range (not reached for real meshes) */
        int n = snprintf(p, 32, "%.6f", v);
        w->len += (size_t)(n > 0 ? HV_MIN(n, 31) : 0);
        return;
    }
    long long q = llround(v * 1e6);
    if (q < 0) {
        *p++ = '-';
        q = -q;
    }
    unsigned long long ip = (unsigned long long)q / 1000000u, fp = (unsigned long long)q % 1000000u;
    char d[24];
    int k = 0;
    do {
        d[k++] = (char)('0' + ip % 10);
        ip /= 10;
    } while (ip);
    while (k) *p++ = d[--k];
    if (fp) {
        *p++ = '.';
        char f[6];
        for (int i = 5; i >= 0; --i) {
            f[i] = (char)('0' + fp % 10);
            fp /= 10;
        }
        int last = 5;
        while (f[last] == '0') --last;
        for (int i = 0; i <= last; ++i) *p++ = f[i];
    }
    w->len = (size_t)(p - w->buf);
}

static hv_status flush(hv_contour_writer *w)
{
    if (w->failed) return hv_error_set(HV_ERR_NOMEM, "%s: out of memory formatting contours", w->af.path);
    if (w->len && fwrite(w->buf, 1, w->len, w->af.fp) != w->len)
        return hv_error_set(HV_ERR_IO, "%s: write failed: %s", w->af.path, strerror(errno));
    w->len = 0;
    return HV_OK;
}

static void xml_escaped(hv_contour_writer *w, const char *s)
{
    for (; *s; ++s) {
        switch (*s) {
        case '&': puts_(w, "&amp;"); break;
        case '<': puts_(w, "&lt;"); break;
        case '>': puts_(w, "&gt;"); break;
        case '"': puts_(w, "&quot;"); break;
        default:
            if ((unsigned char)*s < 0x20) put(w, "_", 1); /* not allowed in XML 1.0 */
            else put(w, s, 1);
        }
    }
}

static void put_u16(hv_contour_writer *w, unsigned v)
{
    unsigned char b[2] = {(unsigned char)(v & 255), (unsigned char)(v >> 8)};
    put(w, (const char *)b, 2);
}

static void put_i32(hv_contour_writer *w, int32_t v)
{
    uint32_t u = (uint32_t)v;
    unsigned char b[4] = {(unsigned char)u, (unsigned char)(u >> 8), (unsigned char)(u >> 16),
                          (unsigned char)(u >> 24)};
    put(w, (const char *)b, 4);
}

static void put_f32(hv_contour_writer *w, double v)
{
    float f = (float)v;
    uint32_t u;
    memcpy(&u, &f, 4);
    put_i32(w, (int32_t)u);
}

/* ---- open / add / close ------------------------------------------------------------------ */

static void writer_free(hv_contour_writer *w);

hv_status hv_contour_format_for_path(const char *path, int binary, hv_contour_format *out)
{
    int svg = hv_has_extension(path, ".svg"), cli = hv_has_extension(path, ".cli");
    if (!svg && !cli)
        return hv_error_option(HV_ERR_INVALID, "{output} '%s' has an unknown extension (use .svg or .cli)", path);
    if (svg && binary) return hv_error_option(HV_ERR_INVALID, "{binary} needs a .cli output, not '%s'", path);
    *out = svg ? HV_CONTOUR_SVG : binary ? HV_CONTOUR_CLI_BINARY : HV_CONTOUR_CLI_ASCII;
    return HV_OK;
}

hv_status hv_contour_writer_open(const char *path, hv_contour_format format, size_t layers,
                                 const double lo[3], const double hi[3], const char *label,
                                 hv_contour_writer **out)
{
    return hv_contour_writer_open_bodies(path, format, layers, lo, hi, label, NULL, 0, out);
}

/* A label on one CLI header line (control characters become '_'), or `fallback` when empty. */
static void cli_label(hv_contour_writer *w, const char *s, const char *fallback)
{
    char lab[256];
    size_t k = 0;
    for (; *s && k + 1 < sizeof lab; ++s) lab[k++] = (unsigned char)*s < 0x20 ? '_' : *s;
    lab[k] = '\0';
    puts_(w, lab[0] ? lab : fallback);
}

hv_status hv_contour_writer_open_bodies(const char *path, hv_contour_format format, size_t layers,
                                        const double lo[3], const double hi[3], const char *label,
                                        const char *const *bodies, size_t nbodies, hv_contour_writer **out)
{
    if (!out) return hv_error_set(HV_ERR_INVALID, "hv_contour_writer_open: out is NULL");
    *out = NULL;
    if (!path || !lo || !hi)
        return hv_error_set(HV_ERR_INVALID, "hv_contour_writer_open: path and box are required");
    if (format != HV_CONTOUR_SVG && format != HV_CONTOUR_CLI_ASCII && format != HV_CONTOUR_CLI_BINARY)
        return hv_error_set(HV_ERR_INVALID, "%s: unknown contour format %d", path, (int)format);
    for (int a = 0; a < 3; ++a)
        if (!isfinite(lo[a]) || !isfinite(hi[a]))
            return hv_error_set(HV_ERR_INVALID, "%s: bounding box is not finite", path);
    if (format != HV_CONTOUR_SVG && layers >= (size_t)INT32_MAX)
        return hv_error_set(HV_ERR_LIMIT, "%s: %zu layers do not fit a CLI file", path, layers);
    if (nbodies > 1 && !bodies) return hv_error_set(HV_ERR_INVALID, "%s: %zu bodies without names", path, nbodies);
    if (nbodies > (size_t)INT32_MAX - 1) return hv_error_set(HV_ERR_LIMIT, "%s: %zu bodies", path, nbodies);
    hv_contour_writer *w = hv_calloc(1, sizeof *w);
    if (!w) return HV_ERR_NOMEM;
    w->format = format;
    w->layers = layers;
    if (nbodies > 1) {
        if (!(w->bodies = hv_calloc(nbodies, sizeof *w->bodies))) {
            free(w);
            return HV_ERR_NOMEM;
        }
        w->nbodies = nbodies;
        for (size_t b = 0; b < nbodies; ++b)
            if (!(w->bodies[b] = hv_strdup(bodies[b] ? bodies[b] : ""))) {
                writer_free(w);
                return HV_ERR_NOMEM;
            }
    }
    hv_status st = hv_atomic_open(&w->af, path, "wb");
    if (st != HV_OK) {
        writer_free(w);
        return st;
    }
    if (!label) label = "";
    if (format == HV_CONTOUR_SVG) {
        double m = 1.0; /* margin, mm */
        double x0 = lo[0] - m, y0 = lo[1] - m, W = hi[0] - lo[0] + 2 * m, H = hi[1] - lo[1] + 2 * m;
        puts_(w, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                 "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"");
        num(w, W);
        puts_(w, "mm\" height=\"");
        num(w, H);
        puts_(w, "mm\" viewBox=\"");
        num(w, x0);
        puts_(w, " ");
        num(w, -(y0 + H)); /* y is flipped by the group below */
        puts_(w, " ");
        num(w, W);
        puts_(w, " ");
        num(w, H);
        puts_(w, "\">\n<title>");
        xml_escaped(w, label);
        puts_(w, "</title>\n<desc>hovox contours; 1 user unit = 1 mm; seen from +z (y up); one group "
                 "per layer: data-z is the cut height, data-bottom/data-top the layer slab; "
                 "outer loops counter-clockwise, holes clockwise, fill-rule nonzero</desc>\n"
                 "<style>.loops{fill:#3a7bd5;fill-opacity:0.25;stroke:#1d3f73;stroke-width:0.05}"
                 ".open{fill:none;stroke:#d62728;stroke-width:0.1}</style>\n"
                 "<g transform=\"scale(1,-1)\">\n");
    } else {
        puts_(w, "$$HEADERSTART\n");
        puts_(w, format == HV_CONTOUR_CLI_BINARY ? "$$BINARY\n" : "$$ASCII\n");
        puts_(w, "$$UNITS/00000001.000000\n$$VERSION/200\n");
        if (w->nbodies > 1) /* one part per body: polylines carry their body's id */
            for (size_t b = 0; b < w->nbodies; ++b) {
                printf_(w, "$$LABEL/%zu,", b + 1);
                cli_label(w, w->bodies[b], "body");
                put(w, "\n", 1);
            }
        else {
            puts_(w, "$$LABEL/1,");
            cli_label(w, label, "part");
            put(w, "\n", 1);
        }
        printf_(w, "$$DIMENSION/%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", lo[0], lo[1], lo[2], hi[0], hi[1],
                hi[2]);
        printf_(w, "$$LAYERS/%06zu\n", layers);
        puts_(w, format == HV_CONTOUR_CLI_BINARY ? "$$HEADEREND" : "$$HEADEREND\n$$GEOMETRYSTART\n");
    }
    st = flush(w);
    if (st != HV_OK) {
        hv_contour_writer_abort(w);
        return st;
    }
    *out = w;
    return HV_OK;
}

static void svg_layer(hv_contour_writer *w, const hv_layer *L, const hv_slice *sl)
{
    size_t idx = w->added;
    printf_(w, "<g id=\"layer-%zu\" class=\"layer\" data-index=\"%zu\" data-z=\"", idx, idx);
    num(w, L->z);
    puts_(w, "\" data-bottom=\"");
    num(w, L->bottom);
    puts_(w, "\" data-top=\"");
    num(w, L->top);
    puts_(w, "\">\n");
    size_t n = hv_slice_loop_count(sl);
    const hv_slice_loop *loops = hv_slice_loops(sl);
    /* an assembly: one path per body (data-body), each body's loops filled by themselves */
    for (size_t b = 0; b < HV_MAX(w->nbodies, (size_t)1); ++b) {
        for (int pass = 0; pass < 2; ++pass) {
            int any = 0;
            for (size_t i = 0; i < n; ++i) {
                const hv_slice_loop *lp = &loops[i];
                if (lp->closed != (pass == 0) || (w->nbodies > 1 && (size_t)lp->body != b)) continue;
                if (!any && w->nbodies > 1) {
                    puts_(w, pass == 0 ? "<path class=\"loops\" fill-rule=\"nonzero\" data-body=\""
                                       : "<path class=\"open\" data-body=\"");
                    xml_escaped(w, w->bodies[b]);
                    puts_(w, "\" d=\"M");
                } else {
                    puts_(w, any ? " M" : pass == 0 ? "<path class=\"loops\" fill-rule=\"nonzero\" d=\"M"
                                                    : "<path class=\"open\" d=\"M");
                }
                any = 1;
                for (size_t k = 0; k < lp->count; ++k) {
                    put(w, " ", 1);
                    num(w, lp->xy[2 * k]);
                    put(w, " ", 1);
                    num(w, lp->xy[2 * k + 1]);
                }
                if (lp->closed) puts_(w, " Z");
            }
            if (any) puts_(w, "\"/>\n");
        }
    }
    puts_(w, "</g>\n");
}

static void cli_ascii_layer(hv_contour_writer *w, const hv_layer *L, const hv_slice *sl)
{
    puts_(w, "$$LAYER/");
    num(w, L->top);
    put(w, "\n", 1);
    size_t n = hv_slice_loop_count(sl);
    const hv_slice_loop *loops = hv_slice_loops(sl);
    for (size_t i = 0; i < n; ++i) {
        const hv_slice_loop *lp = &loops[i];
        int dir = !lp->closed ? 2 : lp->orientation > 0 ? 1 : 0;
        size_t np = lp->count + (lp->closed ? 1 : 0);
        printf_(w, "$$POLYLINE/%d,%d,%zu", w->nbodies > 1 ? lp->body + 1 : 1, dir, np);
        for (size_t k = 0; k < np; ++k) {
            size_t q = k % lp->count;
            put(w, ",", 1);
            num(w, lp->xy[2 * q]);
            put(w, ",", 1);
            num(w, lp->xy[2 * q + 1]);
        }
        put(w, "\n", 1);
    }
}

static void cli_binary_layer(hv_contour_writer *w, const hv_layer *L, const hv_slice *sl)
{
    put_u16(w, 127);
    put_f32(w, L->top);
    size_t n = hv_slice_loop_count(sl);
    const hv_slice_loop *loops = hv_slice_loops(sl);
    for (size_t i = 0; i < n; ++i) {
        const hv_slice_loop *lp = &loops[i];
        int dir = !lp->closed ? 2 : lp->orientation > 0 ? 1 : 0;
        size_t np = lp->count + (lp->closed ? 1 : 0);
        put_u16(w, 130);
        put_i32(w, w->nbodies > 1 ? lp->body + 1 : 1);
        put_i32(w, dir);
        put_i32(w, (int32_t)HV_MIN(np, (size_t)INT32_MAX));
        for (size_t k = 0; k < np; ++k) {
            size_t q = k % lp->count;
            put_f32(w, lp->xy[2 * q]);
            put_f32(w, lp->xy[2 * q + 1]);
        }
    }
}

hv_status hv_contour_writer_add(hv_contour_writer *w, const hv_layer *L, const hv_slice *sl)
{
    if (!w || !L || !sl)
        return hv_error_set(HV_ERR_INVALID, "hv_contour_writer_add: writer, layer and slice are required");
    if (w->format != HV_CONTOUR_SVG && w->added >= w->layers)
        return hv_error_set(HV_ERR_INVALID, "%s: more than the %zu layers announced", w->af.path,
                            w->layers);
    if (w->format == HV_CONTOUR_SVG) svg_layer(w, L, sl);
    else if (w->format == HV_CONTOUR_CLI_ASCII) cli_ascii_layer(w, L, sl);
    else cli_binary_layer(w, L, sl);
    ++w->added;
    return flush(w);
}

static void writer_free(hv_contour_writer *w)
{
    for (size_t b = 0; b < w->nbodies; ++b) free(w->bodies[b]);
    free(w->bodies);
    free(w->buf);
    free(w);
}

hv_status hv_contour_writer_close(hv_contour_writer *w)
{
    if (!w) return HV_OK;
    hv_status st = HV_OK;
    if (w->format != HV_CONTOUR_SVG && w->added != w->layers)
        st = hv_error_set(HV_ERR_INVALID, "%s: %zu layers written, %zu announced", w->af.path,
                          w->added, w->layers);
    if (st == HV_OK) {
        if (w->format == HV_CONTOUR_SVG) puts_(w, "</g>\n</svg>\n");
        else if (w->format == HV_CONTOUR_CLI_ASCII) puts_(w, "$$GEOMETRYEND\n");
        st = flush(w);
    }
    if (st == HV_OK) st = hv_atomic_commit(&w->af);
    else hv_atomic_abort(&w->af);
    writer_free(w);
    return st;
}

void hv_contour_writer_abort(hv_contour_writer *w)
{
    if (!w) return;
    hv_atomic_abort(&w->af);
    writer_free(w);
}
