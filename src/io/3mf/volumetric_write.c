/* src/io/3mf/volumetric_write.c - graded models out as 3MF packages with the Volumetric extension
 * (3MF Consortium, "3MF Volumetric & Implicit Extensions" 0.8, Part I): the exact voxel boundary as
 * the core mesh, the materials as base materials, one image3d stack of PNG sheets per material
 * fraction and derived property (and a painted model's colours, RGBA), a functionfromimage3d per
 * stack, a volumedata whose composite maps the fractions to the base materials and whose color
 * reads the colours. OPC on libzip (core/zip.c), XML with libxml2's xmlwriter. */
#include <errno.h>
#include <libxml/xmlwriter.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/zip.h"
#include "export/export_internal.h"
#include "hovox/export.h"
#include "hovox/image.h"
#include "threemf_internal.h"

/* ---- image stacks ----------------------------------------------------------------------------- */

/* One image3d stack: a material's fractions (mat >= 0), a derived property array (prop >= 0) or
 * a painted model's colours (both -1). */
typedef struct stack {
    char name[96];   /* image3d name, the folder of its sheets, and (properties) the local name */
    char unit[64];   /* properties: the SI unit ("" for none) */
    int mat, prop;
    int channels, bits; /* of its PNG sheets: 1 (grey) or 4 (RGBA); 8 or 16 */
    size_t off;      /* where its sheet starts in a worker's buffer */
    double lo, hi;   /* properties: the range over the exported voxels */
} stack;

/* [A-Za-z0-9_.-] kept, others '_'; an XML name must not start with a digit, '.' or '-'. */
static void ncname(char *dst, size_t size, const char *src, size_t n)
{
    size_t o = 0;
    if (n == 0 || !((src[0] >= 'A' && src[0] <= 'Z') || (src[0] >= 'a' && src[0] <= 'z') || src[0] == '_'))
        dst[o++] = '_';
    for (size_t i = 0; i < n && o + 1 < size; ++i) {
        char c = src[i];
        int ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '.' ||
                 c == '-';
        dst[o++] = ok ? c : '_';
    }
    dst[o] = '\0';
}

typedef struct plan3 {
    int nstacks;
    stack *stacks;
    int colour;      /* the colour stack, or -1 */
    size_t sheet;    /* bytes of one sheet of every stack (a worker's buffer) */
    size_t biggest;  /* bytes of the largest stack's sheet */
    int64_t lo[3], n[3]; /* the image box: lowest occupied voxel and voxels per axis */
    uint64_t quads;
    int bits;
    int in_memory; /* sheets kept encoded in memory until packed (else in temporary files) */
} plan3;

static void plan3_free(plan3 *p)
{
    free(p->stacks);
    memset(p, 0, sizeof *p);
}

/* Stack t's name made unique among the stacks before it (names are folders and property names). */
static void unique_name(plan3 *p, int t)
{
    stack *s = &p->stacks[t];
    for (int k = 0, dup = 1; k < t; ++k)
        if (strcmp(p->stacks[k].name, s->name) == 0) {
            char tmp[96];
            snprintf(tmp, sizeof tmp, "%.80s.%d", s->name, ++dup);
            snprintf(s->name, sizeof s->name, "%s", tmp);
            k = -1;
        }
}

/* The stacks: the materials' fractions, the property arrays (but a painted model's colour.r, .g,
 * .b), and a painted model's colours as one RGBA stack of 16 bits (linear sRGB: 8 bits would
 * lose the dark colours, more than 1/255 once back in sRGB). p->n must be set. */
static hv_status make_stacks(const ex_model *md, plan3 *p)
{
    int nprops = 0;
    for (int q = 0; q < md->nprops; ++q) nprops += !md->props[q].colour;
    p->nstacks = md->m + nprops + md->painted;
    p->colour = md->painted ? p->nstacks - 1 : -1;
    p->stacks = hv_calloc((size_t)p->nstacks, sizeof *p->stacks);
    if (!p->stacks) return HV_ERR_NOMEM;
    for (int j = 0; j < md->m; ++j) {
        stack *s = &p->stacks[j];
        snprintf(s->name, sizeof s->name, "%s", hv_material_name(md->table, j));
        s->mat = j;
        s->prop = -1;
    }
    for (int q = 0, t = md->m; q < md->nprops; ++q) {
        if (md->props[q].colour) continue;
        stack *s = &p->stacks[t];
        const char *name = md->props[q].name, *br = strchr(name, '[');
        size_t n = br ? (size_t)(br - name) : strlen(name);
        char base[200];
        snprintf(base, sizeof base, "%s%.*s", md->props[q].kind == EX_GRID ? "grid." : "", (int)n, name);
        ncname(s->name, sizeof s->name, base, strlen(base));
        if (br) {
            const char *end = strrchr(br, ']');
            snprintf(s->unit, sizeof s->unit, "%.*s", (int)(end ? end - br - 1 : (long)strlen(br + 1)), br + 1);
        }
        s->mat = -1;
        s->prop = q;
        unique_name(p, t++);
    }
    if (p->colour >= 0) {
        stack *s = &p->stacks[p->colour];
        snprintf(s->name, sizeof s->name, "colour");
        s->mat = s->prop = -1;
        unique_name(p, p->colour);
    }
    size_t pixels = (size_t)p->n[0] * (size_t)p->n[1];
    for (int t = 0; t < p->nstacks; ++t) {
        stack *s = &p->stacks[t];
        s->channels = t == p->colour ? 4 : 1;
        s->bits = t == p->colour ? 16 : p->bits;
        s->off = p->sheet;
        size_t bytes = pixels * (size_t)s->channels * (s->bits == 16 ? 2 : 1);
        p->sheet += bytes;
        p->biggest = HV_MAX(p->biggest, bytes);
    }
    return HV_OK;
}

/* The sheets' samples, all stacks (a bound of their PNGs, which hold them deflated). */
static double raw_bytes(const plan3 *p) { return (double)p->sheet * (double)p->n[2]; }

/* Bytes of the writer's buffers: the mesh, per worker one sheet per stack, and the encoded sheets
 * when they stay in memory. */
static uint64_t plan_bytes(const plan3 *p)
{
    double per_worker = (double)p->sheet + 1.1 * (double)p->biggest; /* the stacks' sheets and one encoded PNG */
    double b = (double)tmf_boundary_bytes(p->quads) + per_worker * HV_MAX(1, hv_threads()) + (1 << 20);
    if (p->in_memory) b += raw_bytes(p) * 1.01 + 256.0 * (double)p->n[2] * p->nstacks;
    return b > 1.8e19 ? UINT64_MAX : (uint64_t)b;
}

/* quads: the boundary's faces when known (UINT64_MAX: count them). */
static hv_status plan3_make(const ex_model *md, const hv_export_options *opt, plan3 *p, uint64_t quads,
                            const hv_progress *progress)
{
    memset(p, 0, sizeof *p);
    if (!md->table)
        return hv_error_set(HV_ERR_INVALID, "export: a 3MF Volumetric package needs a graded model (the model has no "
                            "material table: grade it first)");
    if (md->occupied == 0)
        return hv_error_set(HV_ERR_INVALID, "export: nothing to export: no occupied voxel%s", opt->use_box ? " inside the box" : "");
    p->bits = opt->bits ? opt->bits : 8;
    double total = 1;
    for (int a = 0; a < 3; ++a) {
        p->lo[a] = md->olo[a];
        p->n[a] = md->ohi[a] - md->olo[a] + 1;
        total *= (double)p->n[a];
        if ((uint64_t)p->n[a] > HV_3MF_MAX_IMAGE_SIDE)
            return hv_error_set(HV_ERR_LIMIT, "export: the image stacks would have %lld %s, more than the 3MF Volumetric "
                                "limit of 1024^3 (spec 3.2)", (long long)p->n[a],
                                a == 0 ? "columns" : a == 1 ? "rows" : "sheets");
    }
    if (total > (double)HV_3MF_MAX_IMAGE_VOXELS)
        return hv_error_set(HV_ERR_LIMIT, "export: the image stacks would have %.4g voxels, more than the 3MF Volumetric "
                            "limit of 1024^5 (spec 3.2)", total);
    /* PNG sheets are at most 2^31 - 1 pixels wide and high */
    if (p->n[0] > 0x7fffffff || p->n[1] > 0x7fffffff)
        return hv_error_set(HV_ERR_LIMIT, "export: sheets of %lld x %lld pixels exceed PNG's limit", (long long)p->n[0],
                            (long long)p->n[1]);
    hv_status s = make_stacks(md, p);
    /* sheets in memory when even uncompressed they would take at most a quarter of the budget:
     * thousands of small temporary files cost more than their bytes */
    p->in_memory = raw_bytes(p) * 1.01 <= (double)hv_memory_budget(opt->max_memory) / 4;
    p->quads = quads;
    if (s == HV_OK && quads == UINT64_MAX) s = tmf_boundary_count(md->vol, md->occ, &p->quads, progress);
    return s;
}

static void plan3_report(const ex_model *md, const plan3 *p, hv_export_report *r)
{
    hv_buf b;
    hv_buf_init(&b);
    for (int i = 0; i < p->nstacks; ++i) hv_buf_printf(&b, "%s%s", i ? "," : "", p->stacks[i].name);
    snprintf(r->names, sizeof r->names, "%s", b.data ? b.data : "");
    hv_buf_free(&b);
    for (int a = 0; a < 3; ++a) {
        r->lo[a] = md->olo[a];
        r->hi[a] = md->ohi[a];
        r->dims[a] = p->n[a];
    }
    r->arrays = p->nstacks;
    r->bits = p->bits;
    r->colour = p->colour >= 0;
    r->cells = 2 * p->quads;
    r->points = 0;
    r->memory_bytes = plan_bytes(p);
}

hv_status ex_3mf_plan(const ex_model *md, const hv_export_options *opt, hv_export_report *r)
{
    plan3 p;
    hv_status s = plan3_make(md, opt, &p, UINT64_MAX, opt->progress);
    if (s == HV_OK) plan3_report(md, &p, r);
    plan3_free(&p);
    return s;
}

/* ---- values ----------------------------------------------------------------------------------- */

/* Fractions as integers summing to exactly maxval: each rounded down, the remainder given to the
 * largest fractional parts (ties: the lower index). Every q_j / maxval is within 1 / maxval of p_j
 * (after p is normalised, which moves it by less than 1e-4), and a consumer's division by the sum
 * (spec 5.2.2) changes nothing. */
static void quantise_fractions(const double *p, int m, unsigned maxval, unsigned *q)
{
    double sum = 0, frac[HV_MAX_MATERIALS];
    for (int j = 0; j < m; ++j) sum += p[j];
    unsigned total = 0;
    for (int j = 0; j < m; ++j) {
        double x = sum > 0 ? p[j] / sum * maxval : 0;
        if (x < 0) x = 0;
        double f = floor(x);
        q[j] = (unsigned)f;
        frac[j] = x - f;
        total += q[j];
    }
    while (total < maxval && sum > 0) {
        int best = 0;
        for (int j = 1; j < m; ++j)
            if (frac[j] > frac[best]) best = j;
        q[best]++;
        frac[best] = -1;
        total++;
    }
}

typedef struct wctx {
    const ex_model *md;
    const plan3 *p;
    const char *dir;          /* the temporary directory of the sheets */
    size_t *slab_first;       /* leaves grouped by z slab: slab_leaves[slab_first[s] .. slab_first[s+1]) */
    size_t *slab_leaves;
    int64_t zslab0;           /* index of the first slab's lowest z / 8 */
    int level;
    uint8_t **png;            /* in memory: the encoded sheet of stack t, sheet k at t * sheets + k */
    size_t *png_size;
    /* property ranges, per worker then merged */
    double *lo, *hi;
    int nthreads;
    float show[HV_MAX_MATERIALS][4]; /* the materials' display colours (sRGB) */
} wctx;

static void voxel_props(const ex_model *md, size_t l, unsigned off, const double *pf, double *v)
{
    float vals[EX_MAX_ARRAYS];
    float *out[EX_MAX_ARRAYS];
    for (int q = 0; q < md->nprops; ++q) out[q] = &vals[q];
    ex_eval_props(md, pf, out, 0);
    if (md->ngrids) {
        double g[EX_MAX_ARRAYS] = {0};
        ex_grid_add(md, l, off, g);
        ex_grid_values(md, g, out, 0);
    }
    for (int q = 0; q < md->nprops; ++q) v[q] = vals[q];
}

/* Fractions of an exported voxel, checked (Wu eq. 12). */
static hv_status voxel_fractions(const ex_model *md, size_t l, unsigned n, const int32_t *o, double *pf)
{
    for (int j = 0; j < md->m; ++j) pf[j] = hv_volume_leaf_float_c(md->vol, md->grids[j], l)[n];
    return ex_check_fractions(md, pf, o[0] + (int32_t)(n >> 6), o[1] + (int32_t)((n >> 3) & 7),
                              o[2] + (int32_t)(n & 7));
}

static hv_status range_fn(void *ctx, size_t b, size_t e, int thread)
{
    wctx *c = ctx;
    const ex_model *md = c->md;
    const int32_t *orig = hv_volume_leaf_origins(md->vol);
    double *lo = c->lo + (size_t)thread * (size_t)md->nprops, *hi = c->hi + (size_t)thread * (size_t)md->nprops;
    double pf[HV_MAX_MATERIALS], v[EX_MAX_ARRAYS];
    for (size_t l = b; l < e; ++l) {
        const uint64_t *w = md->occ + 8 * l;
        for (unsigned q = 0; q < 8; ++q)
            for (uint64_t bits = w[q]; bits; bits &= bits - 1) {
                unsigned n = q * 64 + (unsigned)__builtin_ctzll(bits);
                hv_status s = voxel_fractions(md, l, n, orig + 3 * l, pf);
                if (s != HV_OK) return s;
                if (!md->nprops) continue;
                voxel_props(md, l, n, pf, v);
                for (int k = 0; k < md->nprops; ++k) {
                    if (!isfinite(v[k]))
                        return hv_error_set(HV_ERR_BAD_INPUT, "voxel (%d, %d, %d): %s is not finite",
                                            orig[3 * l] + (int)(n >> 6), orig[3 * l + 1] + (int)((n >> 3) & 7),
                                            orig[3 * l + 2] + (int)(n & 7), md->props[k].name);
                    if (v[k] < lo[k]) lo[k] = v[k];
                    if (v[k] > hi[k]) hi[k] = v[k];
                }
            }
    }
    return HV_OK;
}

static void put_sample(uint8_t *d, unsigned val, int bits)
{
    if (bits == 16) {
        d[0] = (uint8_t)(val >> 8);
        d[1] = (uint8_t)val;
    } else {
        d[0] = (uint8_t)val;
    }
}

/* A painted model's colour at a voxel as a pixel of the colour stack (16-bit RGBA): linear sRGB
 * (Volumetric 5.2.1) of the colour asked for, alpha 1 (colour.mask); under a resin core, where no
 * colour was asked for, the composition's colour, sum p_j * colour_j of the materials' display
 * colours (what a render shows there), alpha 0. */
static void colour_pixel(const wctx *c, size_t l, unsigned n, const double *pf, uint8_t *d)
{
    const ex_model *md = c->md;
    double rgb[3] = {0, 0, 0};
    int asked = hv_volume_leaf_float_c(md->vol, md->colour[3], l)[n] > 0.5f;
    for (int k = 0; k < 3; ++k) {
        if (asked) rgb[k] = hv_volume_leaf_float_c(md->vol, md->colour[k], l)[n];
        else
            for (int j = 0; j < md->m; ++j) rgb[k] += pf[j] * c->show[j][k];
        double v = rgb[k] > 0 ? (rgb[k] < 1 ? rgb[k] : 1) : 0; /* NaN: 0 */
        put_sample(d + 2 * k, (unsigned)lrint(tmf_srgb_to_linear(v) * 65535.0), 16);
    }
    put_sample(d + 6, asked ? 65535u : 0u, 16);
}

static void sheet_path(char *buf, size_t size, const char *dir, int t, int64_t k)
{
    snprintf(buf, size, "%s/s%d-%lld.png", dir, t, (long long)k);
}

/* Sheet k (z = lo + k) of every stack: filled from the leaves of its slab, then encoded. */
static hv_status sheet_fn(void *ctx, size_t b, size_t e, int thread)
{
    (void)thread;
    wctx *c = ctx;
    const ex_model *md = c->md;
    const plan3 *p = c->p;
    size_t nx = (size_t)p->n[0], ny = (size_t)p->n[1];
    unsigned maxval = p->bits == 16 ? 65535u : 255u;
    uint8_t *buf = hv_malloc(p->sheet ? p->sheet : 1);
    if (!buf) return HV_ERR_NOMEM;
    const int32_t *orig = hv_volume_leaf_origins(md->vol);
    hv_status s = HV_OK;
    hv_png_options po;
    hv_png_options_init(&po);
    po.compression = c->level;
    po.in_place = 1;
    for (size_t k = b; k < e && s == HV_OK; ++k) {
        memset(buf, 0, p->sheet);
        int64_t z = p->lo[2] + (int64_t)k;
        int64_t slab = (z >> 3) - c->zslab0;
        unsigned zl = (unsigned)(z & 7);
        for (size_t li = c->slab_first[slab]; li < c->slab_first[slab + 1] && s == HV_OK; ++li) {
            size_t l = c->slab_leaves[li];
            const uint64_t *w = md->occ + 8 * l;
            const int32_t *o = orig + 3 * l;
            for (unsigned x = 0; x < 8 && s == HV_OK; ++x)
                for (unsigned y = 0; y < 8; ++y) {
                    unsigned n = (x << 6) | (y << 3) | zl;
                    if (!HV_BIT_GET(w, n)) continue;
                    double pf[HV_MAX_MATERIALS], v[EX_MAX_ARRAYS];
                    unsigned qf[HV_MAX_MATERIALS];
                    if ((s = voxel_fractions(md, l, n, o, pf)) != HV_OK) break;
                    quantise_fractions(pf, md->m, maxval, qf);
                    if (md->nprops) voxel_props(md, l, n, pf, v);
                    size_t col = (size_t)(o[0] + (int64_t)x - p->lo[0]);
                    size_t row = (size_t)(p->lo[1] + p->n[1] - 1 - (o[1] + (int64_t)y)); /* row 0: highest y */
                    for (int t = 0; t < p->nstacks; ++t) {
                        const stack *st = &p->stacks[t];
                        uint8_t *d = buf + st->off + (row * nx + col) * (size_t)st->channels * (st->bits == 16 ? 2 : 1);
                        if (t == p->colour) {
                            colour_pixel(c, l, n, pf, d);
                        } else if (st->mat >= 0) {
                            put_sample(d, qf[st->mat], st->bits);
                        } else {
                            double r = st->hi > st->lo ? (v[st->prop] - st->lo) / (st->hi - st->lo) : 0;
                            put_sample(d, (unsigned)HV_CLAMP(floor(r * maxval + 0.5), 0.0, (double)maxval), st->bits);
                        }
                    }
                }
        }
        for (int t = 0; t < p->nstacks && s == HV_OK; ++t) {
            const stack *st = &p->stacks[t];
            po.bit_depth = st->bits;
            if (c->png) {
                size_t at = (size_t)t * (size_t)p->n[2] + k;
                s = hv_png_encode(buf + st->off, (int)nx, (int)ny, st->channels, 0, &po, &c->png[at], &c->png_size[at]);
                continue;
            }
            char path[4400];
            sheet_path(path, sizeof path, c->dir, t, (int64_t)k);
            s = hv_png_write(path, buf + st->off, (int)nx, (int)ny, st->channels, 0, &po);
        }
    }
    free(buf);
    return s;
}

/* ---- XML ------------------------------------------------------------------------------------ */

typedef struct xml_out {
    FILE *fp;
    int failed;
    int err;
} xml_out;

static int xml_write_cb(void *ctx, const char *buf, int len)
{
    xml_out *x = ctx;
    if (x->failed) return -1;
    if (len > 0 && fwrite(buf, 1, (size_t)len, x->fp) != (size_t)len) {
        x->failed = 1;
        x->err = errno;
        return -1;
    }
    return len;
}

static int xml_close_cb(void *ctx)
{
    (void)ctx;
    return 0;
}

/* A writer over x (file) or over memory (x NULL, buf). Every xmlwriter call's result is folded
 * into `bad`, so one check at the end covers the document. */
typedef struct xw {
    xmlTextWriterPtr w;
    xmlBufferPtr buf;
    int bad;
} xw;

static void x_start(xw *x, const char *name) { x->bad |= xmlTextWriterStartElement(x->w, BAD_CAST name) < 0; }
static void x_end(xw *x) { x->bad |= xmlTextWriterEndElement(x->w) < 0; }
static void x_attr(xw *x, const char *name, const char *value)
{
    x->bad |= xmlTextWriterWriteAttribute(x->w, BAD_CAST name, BAD_CAST value) < 0;
}
static void x_attr_int(xw *x, const char *name, long long v)
{
    char b[32];
    snprintf(b, sizeof b, "%lld", v);
    x_attr(x, name, b);
}
static void x_attr_num(xw *x, const char *name, double v)
{
    char b[40];
    snprintf(b, sizeof b, "%.17g", v == 0 ? 0.0 : v);
    x_attr(x, name, b);
}
static void x_text_element(xw *x, const char *name, const char *attr, const char *value, const char *text)
{
    x_start(x, name);
    if (attr) x_attr(x, attr, value);
    x->bad |= xmlTextWriterWriteString(x->w, BAD_CAST text) < 0;
    x_end(x);
}

static hv_status xw_memory(xw *x)
{
    memset(x, 0, sizeof *x);
    x->buf = xmlBufferCreate();
    if (x->buf) x->w = xmlNewTextWriterMemory(x->buf, 0);
    if (!x->w) {
        if (x->buf) xmlBufferFree(x->buf);
        return HV_ERR_NOMEM;
    }
    xmlTextWriterSetIndent(x->w, 1);
    xmlTextWriterSetIndentString(x->w, BAD_CAST " ");
    x->bad |= xmlTextWriterStartDocument(x->w, "1.0", "UTF-8", NULL) < 0;
    return HV_OK;
}

/* End the document and put the memory writer's text into the zip as `name` (deflated). */
static hv_status xw_to_zip(xw *x, hv_zip *z, const char *name)
{
    x->bad |= xmlTextWriterEndDocument(x->w) < 0;
    xmlFreeTextWriter(x->w);
    x->w = NULL;
    hv_status s = x->bad ? hv_error_set(HV_ERR_NOMEM, "export: writing %s failed", name)
                         : hv_zip_add_data(z, name, xmlBufferContent(x->buf), (size_t)xmlBufferLength(x->buf), 1);
    xmlBufferFree(x->buf);
    x->buf = NULL;
    return s;
}

static hv_status content_types(hv_zip *z)
{
    xw x;
    hv_status s = xw_memory(&x);
    if (s != HV_OK) return s;
    x_start(&x, "Types");
    x_attr(&x, "xmlns", TMF_NS_CONTENT_TYPES);
    static const char *const ct[3][2] = {{"rels", TMF_CT_RELATIONSHIPS}, {"model", TMF_CT_MODEL}, {"png", TMF_CT_PNG}};
    for (int i = 0; i < 3; ++i) {
        x_start(&x, "Default");
        x_attr(&x, "Extension", ct[i][0]);
        x_attr(&x, "ContentType", ct[i][1]);
        x_end(&x);
    }
    x_end(&x);
    return xw_to_zip(&x, z, "[Content_Types].xml");
}

static void sheet_part(char *buf, size_t size, const stack *st, int64_t k)
{
    snprintf(buf, size, "/3D/volumetric/%s/sheet%04lld.png", st->name, (long long)k + 1);
}

static hv_status relationships(hv_zip *z, const plan3 *p)
{
    xw x;
    hv_status s = xw_memory(&x);
    if (s != HV_OK) return s;
    x_start(&x, "Relationships");
    x_attr(&x, "xmlns", TMF_NS_RELATIONSHIPS);
    x_start(&x, "Relationship");
    x_attr(&x, "Target", "/3D/3dmodel.model");
    x_attr(&x, "Id", "rel0");
    x_attr(&x, "Type", TMF_REL_MODEL);
    x_end(&x);
    x_end(&x);
    s = xw_to_zip(&x, z, "_rels/.rels");
    if (s != HV_OK) return s;
    /* the model part's relationships: every sheet, as a 3D texture (spec 3.2.2) */
    if ((s = xw_memory(&x)) != HV_OK) return s;
    x_start(&x, "Relationships");
    x_attr(&x, "xmlns", TMF_NS_RELATIONSHIPS);
    uint64_t id = 1;
    for (int t = 0; t < p->nstacks; ++t)
        for (int64_t k = 0; k < p->n[2]; ++k) {
            char part[200], rid[32];
            sheet_part(part, sizeof part, &p->stacks[t], k);
            snprintf(rid, sizeof rid, "rel%llu", (unsigned long long)id++);
            x_start(&x, "Relationship");
            x_attr(&x, "Target", part);
            x_attr(&x, "Id", rid);
            x_attr(&x, "Type", TMF_REL_TEXTURE);
            x_end(&x);
        }
    x_end(&x);
    return xw_to_zip(&x, z, "3D/_rels/3dmodel.model.rels");
}

static void color_text(char *buf, size_t size, const float rgba[4])
{
    int c[4];
    for (int i = 0; i < 4; ++i) c[i] = (int)HV_CLAMP(floor(rgba[i] * 255.0f + 0.5f), 0.0, 255.0);
    if (c[3] == 255) snprintf(buf, size, "#%02X%02X%02X", c[0], c[1], c[2]);
    else snprintf(buf, size, "#%02X%02X%02X%02X", c[0], c[1], c[2], c[3]);
}

/* The model part's document start, its <model> element and metadata: the application, the
 * material table as JSON (skipped when it cannot be made: that status is returned, and the
 * part is then not finished), the model's origin and a painted model's colour record (the
 * profile, intent, resins, depth and core: hovox.colour.json). */
static hv_status part_metadata(xw *x, const ex_model *md, const hv_transform *xf)
{
    char *json = NULL;
    hv_status s = hv_material_table_to_json(md->table, &json);
    xmlTextWriterSetIndent(x->w, 1);
    xmlTextWriterSetIndentString(x->w, BAD_CAST " ");
    x->bad |= xmlTextWriterStartDocument(x->w, "1.0", "UTF-8", NULL) < 0;
    x_start(x, "model");
    x_attr(x, "unit", "millimeter");
    x_attr(x, "xml:lang", "en-US");
    x_attr(x, "xmlns", TMF_NS_CORE);
    x_attr(x, "xmlns:v", TMF_NS_VOLUMETRIC);
    x_attr(x, "xmlns:hovox", TMF_NS_HOVOX);
    char text[256];
    snprintf(text, sizeof text, "hovox %s", hv_version());
    x_text_element(x, "metadata", "name", "Application", text);
    if (s == HV_OK) x_text_element(x, "metadata", "name", "hovox:materials", json);
    snprintf(text, sizeof text, "%.17g %.17g %.17g", xf->origin[0], xf->origin[1], xf->origin[2]);
    x_text_element(x, "metadata", "name", "hovox:origin", text);
    const char *colour = md->painted ? hv_volume_meta_string(md->vol, "hovox.colour.json") : NULL;
    if (colour) x_text_element(x, "metadata", "name", "hovox:colour", colour);
    free(json);
    return s;
}

/* <basematerials id="1">: each material's name and display colour. */
static void part_materials(xw *x, const ex_model *md)
{
    char text[256];
    x_start(x, "basematerials");
    x_attr(x, "id", "1");
    for (int j = 0; j < md->m; ++j) {
        float rgba[4];
        hv_material_color(md->table, j, rgba);
        color_text(text, sizeof text, rgba);
        x_start(x, "base");
        x_attr(x, "name", hv_material_name(md->table, j));
        x_attr(x, "displaycolor", text);
        x_end(x);
    }
    x_end(x);
}

/* Per stack t: its image3d (id 2 + 2t, the sheets in order) and the function reading it (id
 * 3 + 2t; a property stack's values scaled back from [0, 1] to [lo, hi]). The colour's filter is
 * nearest: every point inside the mesh (the voxels' exact boundary) lies in an exported voxel's
 * cell and takes its colour, where linear would blend the skin with the empty pixels around
 * it (the fractions need not care: the composite divides by their sum). */
static void part_functions(xw *x, const plan3 *p)
{
    for (int t = 0; t < p->nstacks; ++t) {
        const stack *st = &p->stacks[t];
        x_start(x, "v:image3d");
        x_attr_int(x, "id", 2 + 2 * t);
        x_attr(x, "name", st->name);
        x_start(x, "v:imagestack");
        x_attr_int(x, "rowcount", p->n[1]);
        x_attr_int(x, "columncount", p->n[0]);
        x_attr_int(x, "sheetcount", p->n[2]);
        for (int64_t k = 0; k < p->n[2]; ++k) {
            char part[200];
            sheet_part(part, sizeof part, st, k);
            x_start(x, "v:imagesheet");
            x_attr(x, "path", part);
            x_end(x);
        }
        x_end(x);
        x_end(x);
        x_start(x, "v:functionfromimage3d");
        x_attr_int(x, "id", 3 + 2 * t);
        x_attr(x, "displayname", st->name);
        x_attr_int(x, "image3did", 2 + 2 * t);
        x_attr(x, "filter", t == p->colour ? "nearest" : "linear");
        x_attr_num(x, "valueoffset", st->prop >= 0 ? st->lo : 0.0);
        x_attr_num(x, "valuescale", st->prop >= 0 ? st->hi - st->lo : 1.0);
        x_attr(x, "tilestyleu", "clamp");
        x_attr(x, "tilestylev", "clamp");
        x_attr(x, "tilestylew", "clamp");
        x_end(x);
    }
}

/* <v:volumedata id=volume_id>: the composite of the material stacks, the colour (channel color:
 * red, green, blue), a property per property stack, and the colour's alpha as property
 * hovox:colour.mask (where a colour was asked for), each through the transform from object
 * millimetres to the images' UVW. */
static void part_volumedata(xw *x, const plan3 *p, const hv_transform *xf, int volume_id)
{
    /* object millimetres to UVW: u = (x - x0) / (columns * Lx) with x0 the image's lowest face,
     * so voxel centres land on pixel centres (v: rows from the highest y, spec 3.2 Figure 3-1) */
    char matrix[512];
    double sc[3], tr[3];
    for (int a = 0; a < 3; ++a) {
        sc[a] = 1.0 / ((double)p->n[a] * xf->voxel[a]);
        tr[a] = -(xf->origin[a] + ((double)p->lo[a] - 0.5) * xf->voxel[a]) * sc[a];
    }
    snprintf(matrix, sizeof matrix, "%.17g 0 0 0 %.17g 0 0 0 %.17g %.17g %.17g %.17g", sc[0], sc[1], sc[2],
             tr[0] == 0 ? 0.0 : tr[0], tr[1] == 0 ? 0.0 : tr[1], tr[2] == 0 ? 0.0 : tr[2]);
    x_start(x, "v:volumedata");
    x_attr_int(x, "id", volume_id);
    x_start(x, "v:composite");
    x_attr(x, "basematerialid", "1");
    for (int t = 0; t < p->nstacks; ++t) {
        if (p->stacks[t].mat < 0) continue;
        x_start(x, "v:materialmapping");
        x_attr_int(x, "functionid", 3 + 2 * t);
        x_attr(x, "channel", "red");
        x_attr(x, "transform", matrix);
        x_end(x);
    }
    x_end(x);
    if (p->colour >= 0) {
        x_start(x, "v:color");
        x_attr_int(x, "functionid", 3 + 2 * p->colour);
        x_attr(x, "channel", "color");
        x_attr(x, "transform", matrix);
        x_end(x);
    }
    for (int t = 0; t < p->nstacks; ++t) {
        const stack *st = &p->stacks[t];
        if (st->prop < 0) continue;
        char qname[128];
        snprintf(qname, sizeof qname, "hovox:%s", st->name);
        x_start(x, "v:property");
        x_attr_int(x, "functionid", 3 + 2 * t);
        x_attr(x, "channel", "red");
        x_attr(x, "transform", matrix);
        x_attr(x, "name", qname);
        x_attr(x, "required", "false");
        if (st->unit[0]) x_attr(x, "hovox:unit", st->unit);
        x_end(x);
    }
    if (p->colour >= 0) {
        x_start(x, "v:property");
        x_attr_int(x, "functionid", 3 + 2 * p->colour);
        x_attr(x, "channel", "alpha");
        x_attr(x, "transform", matrix);
        x_attr(x, "name", "hovox:colour.mask");
        x_attr(x, "required", "false");
        x_end(x);
    }
    x_end(x);
}

/* The boundary mesh's <vertices> (voxel corners in millimetres) and <triangles>, reporting
 * progress; stops at the first failing status s (given or from the progress callback). */
static hv_status part_mesh(xw *x, const tmf_boundary *mesh, const hv_transform *xf, const hv_progress *progress,
                           hv_status s)
{
    x_start(x, "vertices");
    for (size_t v = 0; v < mesh->nv && !x->bad && s == HV_OK; ++v) {
        const int32_t *c = mesh->corner + 3 * v;
        static const char *const xyz[3] = {"x", "y", "z"};
        x_start(x, "vertex");
        for (int a = 0; a < 3; ++a) {
            char b[40];
            double w = xf->origin[a] + ((double)c[a] - 0.5) * xf->voxel[a];
            snprintf(b, sizeof b, "%.9g", w == 0 ? 0.0 : w);
            x_attr(x, xyz[a], b);
        }
        x_end(x);
        if ((v & 0xffff) == 0xffff)
            s = hv_progress_report(progress, "export write", 0.5 * (double)v / (double)(mesh->nv + mesh->nt));
    }
    x_end(x);
    x_start(x, "triangles");
    for (size_t t = 0; t < mesh->nt && !x->bad && s == HV_OK; ++t) {
        static const char *const vn[3] = {"v1", "v2", "v3"};
        x_start(x, "triangle");
        for (int k = 0; k < 3; ++k) x_attr_int(x, vn[k], mesh->tri[3 * t + (size_t)k]);
        x_end(x);
        if ((t & 0xffff) == 0xffff)
            s = hv_progress_report(progress, "export write",
                                   0.5 * (double)(mesh->nv + t) / (double)(mesh->nv + mesh->nt));
    }
    x_end(x);
    return s;
}

/* The model part (spec Part I; ids: 1 base materials, 2 + 2t image3d and 3 + 2t function of
 * stack t, then the volume data and the object). */
static hv_status model_part(const ex_model *md, const plan3 *p, const tmf_boundary *mesh, const char *file,
                            const hv_progress *progress)
{
    FILE *fp = fopen(file, "wb");
    if (!fp) return hv_error_set(HV_ERR_IO, "%s: cannot write: %s", file, strerror(errno));
    xml_out xo = {fp, 0, 0};
    xw x = {NULL, NULL, 0};
    xmlOutputBufferPtr ob = xmlOutputBufferCreateIO(xml_write_cb, xml_close_cb, &xo, NULL);
    if (ob) x.w = xmlNewTextWriter(ob);
    if (!x.w) {
        if (ob) xmlOutputBufferClose(ob);
        fclose(fp);
        return HV_ERR_NOMEM;
    }
    hv_transform xf = hv_volume_get_transform(md->vol);
    hv_status s = part_metadata(&x, md, &xf);
    x_start(&x, "resources");
    part_materials(&x, md);
    part_functions(&x, p);
    int volume_id = 2 + 2 * p->nstacks, object_id = volume_id + 1;
    part_volumedata(&x, p, &xf, volume_id);
    x_start(&x, "object");
    x_attr_int(&x, "id", object_id);
    x_attr(&x, "type", "model");
    x_start(&x, "mesh");
    x_attr_int(&x, "v:volumeid", volume_id);
    s = part_mesh(&x, mesh, &xf, progress, s);
    x_end(&x); /* mesh */
    x_end(&x); /* object */
    x_end(&x); /* resources */
    x_start(&x, "build");
    x_start(&x, "item");
    x_attr_int(&x, "objectid", object_id);
    x_end(&x);
    x_end(&x);
    x_end(&x); /* model */
    x.bad |= xmlTextWriterEndDocument(x.w) < 0;
    xmlFreeTextWriter(x.w); /* flushes and closes the output buffer */
    int bad = ferror(fp) || fflush(fp) != 0;
    int e = errno;
    bad |= fclose(fp) != 0;
    if (s != HV_OK) return s;
    if (xo.failed || bad) return hv_error_set(HV_ERR_IO, "%s: write failed: %s", file, strerror(xo.failed ? xo.err : e));
    if (x.bad) return hv_error_set(HV_ERR_NOMEM, "export: writing the 3MF model part failed");
    return HV_OK;
}

/* ---- the package ------------------------------------------------------------------------------ */

static hv_status group_leaves(const ex_model *md, const plan3 *p, wctx *c)
{
    size_t nl = hv_volume_leaf_count(md->vol);
    int64_t z0 = p->lo[2] >> 3, z1 = (p->lo[2] + p->n[2] - 1) >> 3;
    size_t nslab = (size_t)(z1 - z0 + 1);
    c->zslab0 = z0;
    c->slab_first = hv_calloc(nslab + 1, sizeof(size_t));
    c->slab_leaves = hv_malloc_array(nl ? nl : 1, sizeof(size_t));
    if (!c->slab_first || !c->slab_leaves) return HV_ERR_NOMEM;
    const int32_t *orig = hv_volume_leaf_origins(md->vol);
    for (size_t l = 0; l < nl; ++l) {
        const uint64_t *w = md->occ + 8 * l;
        if (!(w[0] | w[1] | w[2] | w[3] | w[4] | w[5] | w[6] | w[7])) continue;
        c->slab_first[(orig[3 * l + 2] >> 3) - z0 + 1]++;
    }
    for (size_t i = 0; i < nslab; ++i) c->slab_first[i + 1] += c->slab_first[i];
    size_t *fill = hv_malloc_array(nslab ? nslab : 1, sizeof(size_t));
    if (!fill) return HV_ERR_NOMEM;
    memcpy(fill, c->slab_first, nslab * sizeof(size_t));
    for (size_t l = 0; l < nl; ++l) {
        const uint64_t *w = md->occ + 8 * l;
        if (!(w[0] | w[1] | w[2] | w[3] | w[4] | w[5] | w[6] | w[7])) continue;
        c->slab_leaves[fill[(orig[3 * l + 2] >> 3) - z0]++] = l;
    }
    free(fill);
    return HV_OK;
}

static hv_status property_ranges(wctx *c, plan3 *p, const hv_progress *progress)
{
    const ex_model *md = c->md;
    c->nthreads = HV_MAX(1, hv_threads());
    size_t n = (size_t)c->nthreads * (size_t)(md->nprops ? md->nprops : 1);
    c->lo = hv_malloc_array(n, sizeof(double));
    c->hi = hv_malloc_array(n, sizeof(double));
    if (!c->lo || !c->hi) return HV_ERR_NOMEM;
    for (size_t i = 0; i < n; ++i) {
        c->lo[i] = INFINITY;
        c->hi[i] = -INFINITY;
    }
    /* every fraction is checked here too, before anything is written */
    hv_status s = hv_parallel_for(hv_volume_leaf_count(md->vol), 16, range_fn, c, progress, "export fill");
    if (s != HV_OK) return s;
    for (int k = 0; k < p->nstacks; ++k) {
        stack *st = &p->stacks[k];
        int q = st->prop;
        if (q < 0) continue;
        st->lo = INFINITY;
        st->hi = -INFINITY;
        for (int t = 0; t < c->nthreads; ++t) {
            st->lo = HV_MIN(st->lo, c->lo[(size_t)t * (size_t)md->nprops + (size_t)q]);
            st->hi = HV_MAX(st->hi, c->hi[(size_t)t * (size_t)md->nprops + (size_t)q]);
        }
        if (!(st->lo <= st->hi)) st->lo = st->hi = 0;
    }
    return HV_OK;
}

hv_status ex_3mf_write(const ex_model *md, const char *path, const hv_export_options *opt, hv_export_report *r)
{
    tmf_xml_quiet quiet;
    tmf_xml_quiet_begin(&quiet);
    plan3 p;
    wctx c;
    memset(&c, 0, sizeof c);
    tmf_boundary mesh;
    memset(&mesh, 0, sizeof mesh);
    hv_zip *z = NULL;
    char *dir = NULL;
    int made_dir = 0;
    hv_status s = plan3_make(md, opt, &p, r->cells / 2, opt->progress); /* counted by the plan */
    if (s == HV_OK) plan3_report(md, &p, r);
    /* the archive's temporary first: an unwritable place fails before any work */
    if (s == HV_OK) s = hv_zip_open(path, &z);
    if (s == HV_OK) {
        dir = hv_temp_path(path);
        if (!dir) s = HV_ERR_NOMEM;
        else if (mkdir(dir, 0700) != 0) s = hv_error_set(HV_ERR_IO, "%s: cannot make a temporary directory: %s", path, strerror(errno));
        else made_dir = 1;
    }
    c.md = md;
    c.p = &p;
    c.dir = dir;
    c.level = opt->zlib_level ? opt->zlib_level : 1;
    for (int j = 0; j < md->m; ++j) hv_material_color(md->table, j, c.show[j]);
    if (s == HV_OK && p.in_memory) {
        size_t n = (size_t)p.nstacks * (size_t)p.n[2];
        c.png = hv_calloc(n, sizeof *c.png);
        c.png_size = hv_calloc(n, sizeof *c.png_size);
        if (!c.png || !c.png_size) s = HV_ERR_NOMEM;
    }
    if (s == HV_OK) s = group_leaves(md, &p, &c);
    if (s == HV_OK) s = property_ranges(&c, &p, opt->progress);
    if (s == HV_OK) s = hv_parallel_for((size_t)p.n[2], 1, sheet_fn, &c, opt->progress, "export sheets");
    if (s == HV_OK) s = tmf_boundary_build(md->vol, md->occ, p.quads, &mesh, opt->progress);
    char file[4400];
    if (dir) snprintf(file, sizeof file, "%s/3dmodel.model", dir);
    if (s == HV_OK) s = model_part(md, &p, &mesh, file, opt->progress);
    if (s == HV_OK) {
        r->points = mesh.nv;
        r->cells = mesh.nt;
    }
    tmf_boundary_free(&mesh);
    /* [Content_Types].xml first, then the relationships, the model and its sheets */
    if (s == HV_OK) s = content_types(z);
    if (s == HV_OK) s = relationships(z, &p);
    if (s == HV_OK) {
        hv_zip_set_level(z, c.level);
        s = hv_zip_add_file(z, "3D/3dmodel.model", file, 1);
    }
    for (int t = 0; t < p.nstacks && s == HV_OK; ++t)
        for (int64_t k = 0; k < p.n[2] && s == HV_OK; ++k) {
            char part[200], sheet[4400];
            sheet_part(part, sizeof part, &p.stacks[t], k);
            if (c.png) {
                size_t at = (size_t)t * (size_t)p.n[2] + (size_t)k;
                s = hv_zip_add_owned(z, part + 1, c.png[at], c.png_size[at], 0);
                c.png[at] = NULL;
                continue;
            }
            sheet_path(sheet, sizeof sheet, dir, t, k);
            s = hv_zip_add_file(z, part + 1, sheet, 0);
        }
    if (s == HV_OK) s = hv_zip_write(z, opt->progress, "export write");
    if (s == HV_OK) {
        s = hv_zip_commit(z);
        z = NULL;
    }
    if (z) hv_zip_abort(z);
    if (made_dir) hv_remove_tree(dir);
    if (s == HV_OK) {
        struct stat st;
        r->file_bytes = stat(path, &st) == 0 ? (uint64_t)st.st_size : 0;
    } else {
        r->file_bytes = 0;
    }
    free(dir);
    if (c.png)
        for (size_t i = 0; i < (size_t)p.nstacks * (size_t)p.n[2]; ++i) free(c.png[i]);
    free(c.png);
    free(c.png_size);
    free(c.slab_first);
    free(c.slab_leaves);
    free(c.lo);
    free(c.hi);
    plan3_free(&p);
    tmf_xml_quiet_end(&quiet);
    return s;
}
