/* src/viewer/stack_page.c - the page of a slice stack or tray (hovox/viewer.h): the manifest, one
 * streamed read of every layer (libpng, row by row, packed as stored) that takes out what the
 * page needs pixels for - side views through the stack at chosen rows and columns, the union of
 * each part's object pixels for its outline, the palette - and the page around them. The layers
 * themselves stay where they are: the page draws them from their files. */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "hovox/image.h"
#include "viewer_internal.h"

#define OUTLINE_CELLS 1024 /* outlines are traced on at most this many cells a side */

/* A side view: a cut through the stack at one row (axis 0: an x-z image) or one column (axis 1:
 * a y-z image) of a part's box, over the part's layers. Sample k along the cut covers pixels
 * [from + k s, from + (k+1) s) and shows the middle one; layer samples likewise. Image row 0 is
 * the top (the highest layer). */
typedef struct cut {
    int part, axis, pos;
    int from, to;        /* pixels along the cut (columns for a row cut, rows for a column cut) */
    int w, h;            /* samples: along the cut, and layers */
    uint8_t **img;       /* per channel: w * h */
} cut;

typedef struct job {
    const vw_stack *S;
    const char *dir;
    int step;            /* s: sample every s-th pixel and layer */
    cut *cuts;
    int ncuts;
    /* per row of the image: the row cuts through it, and the column-cut samples it holds */
    int *row_start, *row_cut;         /* CSR: cuts at row r: row_cut[row_start[r] .. row_start[r+1]) */
    int *col_start, *col_task;        /* CSR: (cut, k) pairs, 2 ints each */
    size_t *span_start, *span;        /* CSR: the bytes of row r inside parts' boxes, [a, b) pairs:
                                         only they go into the union (a tray's plate is mostly empty) */
    /* per part: the layer sample a layer position belongs to (-1: none), from the part's l0 */
    size_t stride;                    /* bytes of a packed row */
    int threads;
    uint8_t **rowbuf;                 /* per thread */
    uint8_t **uni;                    /* per thread: OR of every layer's packed rows */
    int **lk;                         /* per thread: nparts layer samples */
    /* what the first layer of each thread saw, for warnings and the palette */
    struct tinfo {
        size_t phys_bad_at;           /* layer position + 1 of the first pHYs mismatch (0: none) */
        unsigned phys_x, phys_y;
        size_t phys_none_at;
        size_t plte_bad_at;
        int plte_n;                   /* entries of the palette first seen */
        uint8_t plte[256][3];
        size_t plte_at;               /* layer position + 1 where plte was read */
    } *ti;
} job;

/* ---- sampling ---------------------------------------------------------------------------------- */

/* the index picked by sample k of [lo, hi) at step s */
static int pick(int lo, int hi, int s, int k)
{
    int a = lo + k * s, n = HV_MIN(s, hi - a);
    return a + (n - 1) / 2;
}

static int samples(int lo, int hi, int s) { return hi > lo ? (hi - lo + s - 1) / s : 0; }

/* the sample of layer position li in [l0, l1), or -1 */
static int layer_sample(size_t l0, size_t l1, int s, size_t li)
{
    if (li < l0 || li >= l1) return -1;
    int k = (int)((li - l0) / (size_t)s);
    return (size_t)pick((int)l0, (int)l1, s, k) == li ? k : -1;
}

static unsigned packed_value(const uint8_t *row, int bd, int c)
{
    if (bd == 8) return row[c];
    size_t bit = (size_t)c * (size_t)bd;
    return (unsigned)(row[bit >> 3] >> (8 - bd - (int)(bit & 7))) & ((1u << bd) - 1u);
}

/* ---- cuts: how many, where -------------------------------------------------------------------- */

static uint64_t cut_samples(const vw_stack *S, int n, int s)
{
    uint64_t total = 0;
    for (int p = 0; p < S->nparts; ++p) {
        const vw_part *P = &S->parts[p];
        int L = samples((int)P->l0, (int)P->l1, s);
        if (!L) continue;
        int nr = HV_MIN(n, P->box[3]), nc = HV_MIN(n, P->box[2]);
        total += ((uint64_t)nr * (uint64_t)samples(0, P->box[2], s) + (uint64_t)nc * (uint64_t)samples(0, P->box[3], s)) *
                 (uint64_t)L;
    }
    return total * (uint64_t)S->channels;
}

static int span_cmp(const void *a, const void *b)
{
    const size_t *x = a, *y = b;
    return x[0] < y[0] ? -1 : x[0] > y[0];
}

/* Per row, the bytes inside the boxes of the parts that have layers, merged. */
static hv_status plan_spans(job *J)
{
    const vw_stack *S = J->S;
    int H = S->height, bd = S->bit_depth;
    size_t n = 0;
    for (int p = 0; p < S->nparts; ++p)
        if (S->parts[p].l1 > S->parts[p].l0) n += (size_t)S->parts[p].box[3];
    J->span_start = hv_calloc((size_t)H + 1, sizeof *J->span_start);
    J->span = hv_malloc_array(2 * n + 2, sizeof *J->span);
    size_t *tmp = hv_malloc_array(2 * (size_t)S->nparts + 2, sizeof *tmp);
    if (!J->span_start || !J->span || !tmp) {
        free(tmp);
        return HV_ERR_NOMEM;
    }
    size_t at = 0;
    for (int y = 0; y < H; ++y) {
        size_t k = 0;
        for (int p = 0; p < S->nparts; ++p) {
            const vw_part *P = &S->parts[p];
            if (P->l1 <= P->l0 || y < P->box[1] || y >= P->box[1] + P->box[3]) continue;
            tmp[2 * k] = (size_t)P->box[0] * (size_t)bd / 8;
            tmp[2 * k + 1] = ((size_t)(P->box[0] + P->box[2]) * (size_t)bd + 7) / 8;
            ++k;
        }
        qsort(tmp, k, 2 * sizeof *tmp, span_cmp);
        J->span_start[y] = at;
        for (size_t i = 0; i < k; ++i) {
            if (at > J->span_start[y] && tmp[2 * i] <= J->span[2 * at - 1]) {
                J->span[2 * at - 1] = HV_MAX(J->span[2 * at - 1], tmp[2 * i + 1]);
            } else {
                J->span[2 * at] = tmp[2 * i];
                J->span[2 * at + 1] = tmp[2 * i + 1];
                ++at;
            }
        }
    }
    J->span_start[H] = at;
    free(tmp);
    return HV_OK;
}

static hv_status plan_cuts(job *J, const hv_viewer_options *o, hv_viewer_report *r)
{
    const vw_stack *S = J->S;
    int n = o->cuts, s = 1;
    while (cut_samples(S, n, s) > o->max_samples && n > 4) n = HV_MAX(4, n / 2);
    while (cut_samples(S, n, s) > o->max_samples && s < (1 << 20)) s *= 2;
    J->step = s;
    int maxr = 0, maxc = 0, count = 0;
    for (int p = 0; p < S->nparts; ++p) {
        const vw_part *P = &S->parts[p];
        if (P->l1 <= P->l0) continue;
        count += HV_MIN(n, P->box[3]) + HV_MIN(n, P->box[2]);
        maxr = HV_MAX(maxr, HV_MIN(n, P->box[3]));
        maxc = HV_MAX(maxc, HV_MIN(n, P->box[2]));
    }
    r->cut_rows = maxr;
    r->cut_cols = maxc;
    r->cut_step = s;
    r->samples = cut_samples(S, n, s);
    J->cuts = hv_calloc((size_t)count + 1, sizeof *J->cuts);
    if (!J->cuts) return HV_ERR_NOMEM;
    for (int p = 0; p < S->nparts; ++p) {
        const vw_part *P = &S->parts[p];
        if (P->l1 <= P->l0) continue;
        int L = samples((int)P->l0, (int)P->l1, s);
        for (int axis = 0; axis < 2; ++axis) {
            int across = axis == 0 ? P->box[3] : P->box[2]; /* rows (axis 0) or columns to choose from */
            int along0 = axis == 0 ? P->box[0] : P->box[1], along = axis == 0 ? P->box[2] : P->box[3];
            int k = HV_MIN(n, across);
            for (int i = 0; i < k; ++i) {
                cut *c = &J->cuts[J->ncuts++];
                c->part = p;
                c->axis = axis;
                c->pos = (axis == 0 ? P->box[1] : P->box[0]) + (int)(((double)i + 0.5) * across / k);
                c->from = along0;
                c->to = along0 + along;
                c->w = samples(0, along, s);
                c->h = L;
                c->img = hv_calloc((size_t)S->channels, sizeof *c->img);
                if (!c->img) return HV_ERR_NOMEM;
                for (int ch = 0; ch < S->channels; ++ch)
                    if (!(c->img[ch] = hv_calloc((size_t)c->w * (size_t)c->h, 1))) return HV_ERR_NOMEM;
            }
        }
    }
    /* per row: row cuts, and column-cut samples */
    int H = S->height;
    J->row_start = hv_calloc((size_t)H + 1, sizeof *J->row_start);
    J->col_start = hv_calloc((size_t)H + 1, sizeof *J->col_start);
    if (!J->row_start || !J->col_start) return HV_ERR_NOMEM;
    size_t ntask = 0;
    for (int i = 0; i < J->ncuts; ++i) {
        cut *c = &J->cuts[i];
        if (c->axis == 0) {
            J->row_start[c->pos + 1]++;
        } else {
            for (int k = 0; k < c->w; ++k) J->col_start[pick(c->from, c->to, s, k) + 1]++;
            ntask += (size_t)c->w;
        }
    }
    for (int y = 0; y < H; ++y) {
        J->row_start[y + 1] += J->row_start[y];
        J->col_start[y + 1] += J->col_start[y];
    }
    J->row_cut = hv_malloc_array((size_t)J->row_start[H] + 1, sizeof *J->row_cut);
    J->col_task = hv_malloc_array(2 * ntask + 2, sizeof *J->col_task);
    int *fill = hv_calloc((size_t)H + 1, sizeof *fill), *fill2 = hv_calloc((size_t)H + 1, sizeof *fill2);
    hv_status st = J->row_cut && J->col_task && fill && fill2 ? HV_OK : HV_ERR_NOMEM;
    for (int i = 0; st == HV_OK && i < J->ncuts; ++i) {
        cut *c = &J->cuts[i];
        if (c->axis == 0) {
            J->row_cut[J->row_start[c->pos] + fill[c->pos]++] = i;
        } else {
            for (int k = 0; k < c->w; ++k) {
                int y = pick(c->from, c->to, s, k);
                int at = J->col_start[y] + fill2[y]++;
                J->col_task[2 * at] = i;
                J->col_task[2 * at + 1] = k;
            }
        }
    }
    free(fill);
    free(fill2);
    if (st == HV_OK) st = plan_spans(J);
    return st;
}

/* ---- reading a layer ----------------------------------------------------------------------------- */

typedef struct png_err {
    char msg[200];
} png_err;

static void rd_error(png_structp png, png_const_charp msg)
{
    png_err *e = png_get_error_ptr(png);
    snprintf(e->msg, sizeof e->msg, "%s", msg);
    png_longjmp(png, 1);
}

static void rd_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

/* The layer file as libpng reads it. libpng inflates what is left of the image data once the last
 * row is read (and only warns), so image data going on past the image (a bomb of zeros) is refused
 * once more than 64 KiB follow the last row, as hv_png_decode refuses it. */
typedef struct layer_src {
    FILE *fp;
    uint32_t height; /* rows of the image, once known */
    size_t tail;     /* bytes read after the last row */
} layer_src;

#define LAYER_TAIL_MAX ((size_t)64 << 10)

static void rd_read(png_structp png, png_bytep out, size_t n)
{
    layer_src *s = png_get_io_ptr(png);
    if (s->height && png_get_current_row_number(png) >= s->height && (s->tail += n) > LAYER_TAIL_MAX)
        png_error(png, "image data goes on past the image (more than 64 KiB of it after the last row)");
    if (fread(out, 1, n, s->fp) != n) png_error(png, "the file ends early");
}

/* One layer's rows into the job's tables. */
static void take_row(job *J, int t, int ch, int y, const uint8_t *row)
{
    const vw_stack *S = J->S;
    uint8_t *u = J->uni[t] + (size_t)y * J->stride;
    for (size_t k = J->span_start[y]; k < J->span_start[y + 1]; ++k)
        for (size_t i = J->span[2 * k]; i < J->span[2 * k + 1]; ++i) u[i] |= row[i];
    const int *lk = J->lk[t];
    for (int i = J->row_start[y]; i < J->row_start[y + 1]; ++i) {
        cut *c = &J->cuts[J->row_cut[i]];
        int k = lk[c->part];
        if (k < 0) continue;
        uint8_t *dst = c->img[ch] + (size_t)(c->h - 1 - k) * (size_t)c->w;
        for (int x = 0; x < c->w; ++x) dst[x] = (uint8_t)packed_value(row, S->bit_depth, pick(c->from, c->to, J->step, x));
    }
    for (int i = J->col_start[y]; i < J->col_start[y + 1]; ++i) {
        cut *c = &J->cuts[J->col_task[2 * i]];
        int k = lk[c->part];
        if (k < 0) continue;
        c->img[ch][(size_t)(c->h - 1 - k) * (size_t)c->w + (size_t)J->col_task[2 * i + 1]] =
            (uint8_t)packed_value(row, S->bit_depth, c->pos);
    }
}

static hv_status read_layer(job *J, int t, size_t li, int ch)
{
    const vw_stack *S = J->S;
    const char *file = S->files[li * (size_t)S->channels + (size_t)ch];
    char path[4200];
    if ((size_t)snprintf(path, sizeof path, "%s/%s", J->dir, file) >= sizeof path)
        return hv_error_set(HV_ERR_INVALID, "%s/%s: path too long", J->dir, file);
    FILE *fp = fopen(path, "rb");
    if (!fp) return hv_error_set(HV_ERR_IO, "%s: %s (a layer listed in manifest.json)", path, strerror(errno));
    png_err e;
    e.msg[0] = '\0';
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &e, rd_error, rd_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!info) {
        png_destroy_read_struct(&png, NULL, NULL);
        fclose(fp);
        return hv_error_set(HV_ERR_NOMEM, "%s: out of memory for the PNG reader", path);
    }
    uint8_t *row = J->rowbuf[t];
    struct tinfo *ti = &J->ti[t];
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        fclose(fp);
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: not a readable PNG: %s", path, e.msg);
    }
    layer_src src = {fp, 0, 0};
    png_set_user_limits(png, (png_uint_32)S->width, (png_uint_32)S->height);
    png_set_chunk_malloc_max(png, 8u << 20);
    png_set_read_fn(png, &src, rd_read);
    png_read_info(png, info);
    png_uint_32 w = 0, h = 0;
    int bd = 0, ct = 0, il = 0;
    png_get_IHDR(png, info, &w, &h, &bd, &ct, &il, NULL, NULL);
    int want_ct = S->mode == HV_LAYERS_HALFTONE ? PNG_COLOR_TYPE_PALETTE : PNG_COLOR_TYPE_GRAY;
    const char *why = NULL;
    if (w != (png_uint_32)S->width || h != (png_uint_32)S->height) why = "size";
    else if (ct != want_ct) why = "colour type";
    else if (bd != S->bit_depth) why = "bit depth";
    else if (il != PNG_INTERLACE_NONE) why = "interlacing";
    if (why) {
        png_destroy_read_struct(&png, &info, NULL);
        fclose(fp);
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %u x %u, %d-bit %s%s, where manifest.json says %d x %d, %d-bit %s (the %s differs)",
                            path, (unsigned)w, (unsigned)h, bd,
                            ct == PNG_COLOR_TYPE_PALETTE ? "indexed" : ct == PNG_COLOR_TYPE_GRAY ? "grey" : "colour",
                            il != PNG_INTERLACE_NONE ? ", interlaced" : "", S->width, S->height, S->bit_depth,
                            want_ct == PNG_COLOR_TYPE_PALETTE ? "indexed" : "grey", why);
    }
    if (ct == PNG_COLOR_TYPE_PALETTE) {
        png_colorp pal = NULL;
        int n = 0;
        png_get_PLTE(png, info, &pal, &n);
        if (!ti->plte_at) {
            ti->plte_at = li + 1;
            ti->plte_n = n;
            for (int i = 0; i < n; ++i) {
                ti->plte[i][0] = pal[i].red;
                ti->plte[i][1] = pal[i].green;
                ti->plte[i][2] = pal[i].blue;
            }
        } else if (!ti->plte_bad_at) {
            int same = n == ti->plte_n;
            for (int i = 0; same && i < n; ++i)
                same = ti->plte[i][0] == pal[i].red && ti->plte[i][1] == pal[i].green && ti->plte[i][2] == pal[i].blue;
            if (!same) ti->plte_bad_at = li + 1;
        }
    }
    png_uint_32 rx = 0, ry = 0;
    int unit = 0;
    if (png_get_pHYs(png, info, &rx, &ry, &unit) && unit == PNG_RESOLUTION_METER) {
        double ex = 1000.0 / S->pixel_mm[0], ey = 1000.0 / fabs(S->pixel_mm[1]);
        if ((fabs((double)rx - ex) > 1.0 + 1e-3 * ex || fabs((double)ry - ey) > 1.0 + 1e-3 * ey) && !ti->phys_bad_at) {
            ti->phys_bad_at = li + 1;
            ti->phys_x = rx;
            ti->phys_y = ry;
        }
    } else if (!ti->phys_none_at) {
        ti->phys_none_at = li + 1;
    }
    src.height = h;
    for (int y = 0; y < S->height; ++y) {
        png_read_row(png, row, NULL);
        take_row(J, t, ch, y, row);
    }
    /* no png_read_end: the pixels are complete, and chunks after the image are not needed */
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    return HV_OK;
}

static hv_status read_layers(void *ctx, size_t begin, size_t end, int t)
{
    job *J = ctx;
    const vw_stack *S = J->S;
    for (size_t li = begin; li < end; ++li) {
        for (int p = 0; p < S->nparts; ++p) J->lk[t][p] = layer_sample(S->parts[p].l0, S->parts[p].l1, J->step, li);
        for (int ch = 0; ch < S->channels; ++ch) {
            hv_status s = read_layer(J, t, li, ch);
            if (s != HV_OK) return s;
        }
    }
    return HV_OK;
}

/* ---- outlines ---------------------------------------------------------------------------------- */

static hv_status part_outline(const job *J, const vw_part *P, json_t **out)
{
    const vw_stack *S = J->S;
    *out = NULL;
    int w = P->box[2], h = P->box[3];
    int b = (HV_MAX(w, h) + OUTLINE_CELLS - 1) / OUTLINE_CELLS;
    int gw = (w + b - 1) / b, gh = (h + b - 1) / b;
    uint8_t *cells = hv_calloc((size_t)gw * (size_t)gh, 1);
    if (!cells) return HV_ERR_NOMEM;
    const uint8_t *u = J->uni[0];
    for (int y = 0; y < h; ++y) {
        const uint8_t *row = u + (size_t)(P->box[1] + y) * J->stride;
        for (int x = 0; x < w; ++x)
            if (packed_value(row, S->bit_depth, P->box[0] + x)) cells[(size_t)(y / b) * (size_t)gw + (size_t)(x / b)] = 1;
    }
    int32_t *xy = NULL;
    size_t *starts = NULL, nl = 0;
    hv_status s = vw_outline_trace(cells, gw, gh, &xy, &starts, &nl);
    free(cells);
    json_t *loops = s == HV_OK ? json_array() : NULL;
    if (s == HV_OK && !loops) s = HV_ERR_NOMEM;
    for (size_t i = 0; s == HV_OK && i < nl; ++i) {
        json_t *a = json_array();
        if (!a || json_array_append_new(loops, a)) {
            s = hv_error_set(HV_ERR_NOMEM, "out of memory for an outline");
            break;
        }
        for (size_t k = starts[i]; k < starts[i + 1]; ++k) {
            int x = P->box[0] + HV_MIN(xy[2 * k] * b, w), y = P->box[1] + HV_MIN(xy[2 * k + 1] * b, h);
            if (json_array_append_new(a, json_integer(x)) || json_array_append_new(a, json_integer(y))) {
                s = hv_error_set(HV_ERR_NOMEM, "out of memory for an outline");
                break;
            }
        }
    }
    free(xy);
    free(starts);
    if (s != HV_OK) json_decref(loops);
    else *out = loops;
    return s;
}

/* ---- the page's data ---------------------------------------------------------------------------- */

static json_t *str_array(const char *const *v, size_t n, size_t stride)
{
    json_t *a = json_array();
    for (size_t i = 0; a && i < n; ++i)
        if (json_array_append_new(a, hv_json_text(v[i * stride]))) {
            json_decref(a);
            return NULL;
        }
    return a;
}

static json_t *color_text(const uint8_t rgb[3])
{
    char c[8];
    snprintf(c, sizeof c, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
    return json_string(c);
}

/* palette entries: index, name, colour (from the layers' PLTE for indexed stacks) */
static json_t *palette_doc(const vw_stack *S, const struct tinfo *ti)
{
    json_t *a = json_array();
    if (!a) return NULL;
    int fail = 0;
    if (S->mode == HV_LAYERS_HALFTONE) {
        const json_t *tp = S->tray ? json_object_get(S->doc, "palette") : NULL;
        const json_t *mats = S->tray ? NULL : json_object_get(S->doc, "materials");
        for (int i = 0; i < ti->plte_n; ++i) {
            const char *name = i == 0 ? (S->tray ? "no material" : "background") : NULL;
            if (tp && i < (int)json_array_size(tp)) {
                const json_t *rn = json_object_get(json_array_get(tp, (size_t)i), "resin");
                if (json_is_string(rn)) name = json_string_value(rn);
            }
            for (size_t j = 0; mats && j < json_array_size(mats); ++j) {
                const json_t *m = json_array_get(mats, j);
                if (json_integer_value(json_object_get(m, "palette_index")) == i)
                    name = json_string_value(json_object_get(m, "name"));
            }
            json_t *e = json_object();
            fail |= !e || json_array_append_new(a, e);
            if (!e) break;
            fail |= hv_json_set(e, "index", json_integer(i));
            fail |= hv_json_set(e, "name", name ? hv_json_text(name) : json_null());
            fail |= hv_json_set(e, "color", color_text(ti->plte[i]));
        }
    } else if (S->mode == HV_LAYERS_MASK) {
        static const uint8_t k[2][3] = {{0, 0, 0}, {255, 255, 255}};
        for (int i = 0; i < 2; ++i) {
            json_t *e = json_object();
            fail |= !e || json_array_append_new(a, e);
            if (!e) break;
            fail |= hv_json_set(e, "index", json_integer(i));
            fail |= hv_json_set(e, "name", json_string(i ? "object" : "background"));
            fail |= hv_json_set(e, "color", color_text(k[i]));
        }
    }
    if (fail) {
        json_decref(a);
        return NULL;
    }
    return a;
}

/* the manifest's scalar members, for the page's summary */
static json_t *info_doc(const vw_stack *S)
{
    static const char *const keys[] = {"generator", "profile", "mode", "method", "halftone", "seed", "mesh", "model",
                                       "fill_rule", "threshold_mm", "poi_step", "object_pixels", "layers_total",
                                       "utilisation", "resin_colors_note", NULL};
    json_t *o = json_object();
    for (int i = 0; o && keys[i]; ++i) {
        const json_t *v = json_object_get(S->doc, keys[i]);
        if (v && (json_is_string(v) || json_is_number(v)) && json_object_set(o, keys[i], (json_t *)v)) {
            json_decref(o);
            return NULL;
        }
    }
    return o;
}

static hv_status encode_cut(const job *J, const struct tinfo *ti, const cut *c, int ch, hv_buf *uri)
{
    const vw_stack *S = J->S;
    hv_png_options po;
    hv_png_options_init(&po);
    po.compression = 9;
    po.bit_depth = S->bit_depth;
    uint8_t pal[256 * 3];
    if (S->mode == HV_LAYERS_HALFTONE) { /* the layers' palette, padded to the bit depth (a value past it shows black) */
        int n = 1 << S->bit_depth;
        memset(pal, 0, sizeof pal);
        memcpy(pal, ti->plte, (size_t)ti->plte_n * 3);
        po.palette = pal;
        po.palette_size = n;
    }
    uint8_t *png = NULL;
    size_t size = 0;
    hv_status s = hv_png_encode(c->img[ch], c->w, c->h, 1, 0, &po, &png, &size);
    if (s == HV_OK) vw_data_uri(uri, "image/png", png, size);
    free(png);
    return s;
}

/* The page's parts: name, copy, box, layers, the manifest's info and the outline; *fail set
 * when out of memory for the document; errors of the outline. */
static hv_status parts_doc(const job *J, json_t *d, int *fail)
{
    const vw_stack *S = J->S;
    json_t *parts = json_array();
    *fail |= hv_json_set(d, "parts", parts);
    for (int p = 0; !*fail && p < S->nparts; ++p) {
        const vw_part *P = &S->parts[p];
        json_t *e = json_object();
        *fail |= !e || json_array_append_new(parts, e);
        if (*fail) break;
        double lay[2] = {(double)P->l0, (double)P->l1};
        *fail |= hv_json_set(e, "name", hv_json_text(P->name));
        *fail |= hv_json_set(e, "copy", json_integer(P->copy));
        *fail |= hv_json_set(e, "box_px", json_pack("[iiii]", P->box[0], P->box[1], P->box[2], P->box[3]));
        *fail |= hv_json_set(e, "layers", hv_json_numbers(lay, 2));
        if (P->info) *fail |= hv_json_set(e, "info", json_deep_copy(P->info));
        json_t *ol = NULL;
        hv_status s = part_outline(J, P, &ol);
        if (s != HV_OK) return s;
        *fail |= hv_json_set(e, "outline", ol);
    }
    return HV_OK;
}

/* The page's side views: each cut's place and its images, one per channel; *fail as above. */
static hv_status cuts_doc(const job *J, const struct tinfo *ti, json_t *d, int *fail)
{
    const vw_stack *S = J->S;
    json_t *cuts = json_array();
    *fail |= hv_json_set(d, "cuts", cuts);
    *fail |= hv_json_set(d, "cut_step", json_integer(J->step));
    for (int i = 0; !*fail && i < J->ncuts; ++i) {
        const cut *c = &J->cuts[i];
        const vw_part *P = &S->parts[c->part];
        json_t *e = json_object(), *imgs = json_array();
        *fail |= !e || json_array_append_new(cuts, e);
        if (*fail) break;
        *fail |= hv_json_set(e, "part", json_integer(c->part));
        *fail |= hv_json_set(e, "axis", json_string(c->axis == 0 ? "row" : "col"));
        *fail |= hv_json_set(e, "pos", json_integer(c->pos));
        *fail |= hv_json_set(e, "from", json_integer(c->from));
        *fail |= hv_json_set(e, "to", json_integer(c->to));
        *fail |= hv_json_set(e, "l0", json_integer((json_int_t)P->l0));
        *fail |= hv_json_set(e, "l1", json_integer((json_int_t)P->l1));
        *fail |= hv_json_set(e, "w", json_integer(c->w));
        *fail |= hv_json_set(e, "h", json_integer(c->h));
        *fail |= hv_json_set(e, "images", imgs);
        for (int ch = 0; !*fail && ch < S->channels; ++ch) {
            hv_buf uri;
            hv_buf_init(&uri);
            hv_status s = encode_cut(J, ti, c, ch, &uri);
            if (s == HV_OK && uri.failed) s = HV_ERR_NOMEM;
            if (s != HV_OK) {
                hv_buf_free(&uri);
                return s;
            }
            *fail |= json_array_append_new(imgs, json_string(uri.data));
            hv_buf_free(&uri);
        }
    }
    return HV_OK;
}

static hv_status build_doc(const job *J, const struct tinfo *ti, const char *title, const char *base,
                           const hv_viewer_report *r, json_t **out)
{
    const vw_stack *S = J->S;
    json_t *d = json_object();
    if (!d) return HV_ERR_NOMEM;
    static const char *const modes[] = {"halftone", "fractions", "mask"};
    int fail = 0;
    fail |= hv_json_set(d, "kind", json_string(S->tray ? "tray" : "stack"));
    fail |= hv_json_set(d, "title", hv_json_text(title));
    fail |= hv_json_set(d, "mode", json_string(modes[S->mode]));
    fail |= hv_json_set(d, "width", json_integer(S->width));
    fail |= hv_json_set(d, "height", json_integer(S->height));
    fail |= hv_json_set(d, "bit_depth", json_integer(S->bit_depth));
    fail |= hv_json_set(d, "pixel_mm", hv_json_numbers(S->pixel_mm, 2));
    fail |= hv_json_set(d, "origin_mm", hv_json_numbers(S->origin_mm, 2));
    fail |= hv_json_set(d, "dpi", hv_json_numbers(S->dpi, 2));
    fail |= hv_json_set(d, "layer_height_mm", hv_json_number(S->layer_height));
    fail |= hv_json_set(d, "base", hv_json_text(base));
    fail |= hv_json_set(d, "info", info_doc(S));
    json_t *idx = json_array(), *z = json_array(), *files = json_array();
    fail |= hv_json_set(d, "index", idx);
    fail |= hv_json_set(d, "z_mm", z);
    fail |= hv_json_set(d, "files", files);
    for (size_t i = 0; !fail && i < S->nlayers; ++i) {
        fail |= json_array_append_new(idx, json_integer((json_int_t)S->index[i]));
        fail |= json_array_append_new(z, hv_json_number(S->z[i]));
    }
    for (int ch = 0; !fail && ch < S->channels; ++ch)
        fail |= json_array_append_new(files, str_array(S->files + ch, S->nlayers, (size_t)S->channels)) != 0;
    if (S->mode == HV_LAYERS_FRACTIONS) {
        json_t *chs = json_array();
        fail |= hv_json_set(d, "channels", chs);
        for (int ch = 0; !fail && ch < S->channels; ++ch) {
            json_t *e = json_object();
            fail |= !e || json_array_append_new(chs, e);
            if (fail) break;
            fail |= hv_json_set(e, "name", hv_json_text(S->channel[ch]));
            fail |= hv_json_set(e, "color", color_text(S->channel_rgb[ch]));
        }
    }
    fail |= hv_json_set(d, "palette", palette_doc(S, ti));
    if (!S->tray) { /* the manifest's materials: name, colour, target, achieved */
        const json_t *mats = json_object_get(S->doc, "materials");
        json_t *a = json_array();
        fail |= hv_json_set(d, "materials", a);
        for (size_t j = 0; !fail && j < json_array_size(mats); ++j) {
            const json_t *m = json_array_get(mats, j);
            json_t *e = json_object();
            fail |= !e || json_array_append_new(a, e);
            if (fail) break;
            static const char *const keys[] = {"name", "color", "palette_index", "target", "achieved", NULL};
            for (int k = 0; keys[k]; ++k) {
                const json_t *v = json_object_get(m, keys[k]);
                if (v && (json_is_string(v) || json_is_number(v))) fail |= json_object_set(e, keys[k], (json_t *)v);
            }
        }
    }
    if (!fail) {
        hv_status st = parts_doc(J, d, &fail);
        if (st == HV_OK && !fail) st = cuts_doc(J, ti, d, &fail);
        if (st != HV_OK) {
            json_decref(d);
            return st;
        }
    }
    json_t *warn = json_array();
    fail |= hv_json_set(d, "warnings", warn);
    for (const char *p = r->warnings; !fail && *p;) {
        const char *nl = strchr(p, '\n');
        size_t n = nl ? (size_t)(nl - p) : strlen(p);
        fail |= json_array_append_new(warn, json_stringn(p, n));
        p += n + (nl ? 1 : 0);
    }
    if (fail) {
        json_decref(d);
        return hv_error_set(HV_ERR_NOMEM, "out of memory for the page's data");
    }
    *out = d;
    return HV_OK;
}

/* ---- paths ---------------------------------------------------------------------------------------- */

/* The stack directory as the page reaches it: relative to the page's directory, ending in '/' ("" when
 * they are the same). */
static hv_status relative_base(const char *stack_dir, const char *html_path, char *out, size_t size)
{
    char a[PATH_MAX], b[PATH_MAX], pd[PATH_MAX];
    snprintf(pd, sizeof pd, "%s", html_path);
    char *slash = strrchr(pd, '/');
    if (slash == pd) pd[1] = '\0';
    else if (slash) *slash = '\0';
    else snprintf(pd, sizeof pd, ".");
    if (!realpath(stack_dir, a)) return hv_error_set(HV_ERR_IO, "%s: %s", stack_dir, strerror(errno));
    if (!realpath(pd, b)) return hv_error_set(HV_ERR_IO, "%s: %s (the page's directory)", pd, strerror(errno));
    /* the common leading components */
    size_t i = 0, common = 0;
    while (a[i] && a[i] == b[i]) {
        if (a[i] == '/') common = i;
        ++i;
    }
    if ((!a[i] || a[i] == '/') && !b[i]) common = i;      /* b is a or a prefix directory of a */
    else if (!a[i] && b[i] == '/') common = i;          /* a is a prefix directory of b */
    hv_buf o;
    hv_buf_init(&o);
    for (const char *p = b + common; *p; ++p)
        if (*p == '/') hv_buf_puts(&o, "../");
    const char *rest = a + common;
    while (*rest == '/') ++rest;
    if (*rest) hv_buf_printf(&o, "%s/", rest);
    hv_status s = o.failed ? HV_ERR_NOMEM : HV_OK;
    if (s == HV_OK && o.len >= size) s = hv_error_set(HV_ERR_INVALID, "%s: too far from the page's directory", stack_dir);
    if (s == HV_OK) snprintf(out, size, "%s", o.data ? o.data : "");
    hv_buf_free(&o);
    return s;
}

/* ---- the page -------------------------------------------------------------------------------------- */

static void job_free(job *J)
{
    for (int i = 0; J->cuts && i < J->ncuts; ++i) {
        for (int ch = 0; J->cuts[i].img && ch < J->S->channels; ++ch) free(J->cuts[i].img[ch]);
        free(J->cuts[i].img);
    }
    free(J->cuts);
    free(J->row_start);
    free(J->row_cut);
    free(J->col_start);
    free(J->col_task);
    free(J->span_start);
    free(J->span);
    for (int t = 0; t < J->threads; ++t) {
        if (J->rowbuf) free(J->rowbuf[t]);
        if (J->uni) free(J->uni[t]);
        if (J->lk) free(J->lk[t]);
    }
    free(J->rowbuf);
    free(J->uni);
    free(J->lk);
    free(J->ti);
}

static const char *dir_title(const char *dir, char *buf, size_t size)
{
    snprintf(buf, size, "%s", dir);
    size_t n = strlen(buf);
    while (n > 1 && buf[n - 1] == '/') buf[--n] = '\0';
    return hv_basename(buf);
}

/* The readers' buffers: a union image and a row per thread, within the memory budget; the cuts. */
static hv_status job_alloc(job *J, const char *stack_dir, const hv_viewer_options *opt, hv_viewer_report *rep)
{
    const vw_stack *S = J->S;
    hv_status s = HV_OK;
    /* the readers' memory: a union image and a row per thread */
    uint64_t need = (uint64_t)J->threads * ((uint64_t)J->stride * (uint64_t)S->height + J->stride) + opt->max_samples;
    uint64_t budget = hv_memory_budget(0);
    if (need > budget) {
        char a[32], b[32];
        s = hv_error_set(HV_ERR_LIMIT, "%s: reading %d x %d layers on %d threads needs %s, over the budget of %s", stack_dir,
                         S->width, S->height, J->threads, hv_size_text(a, sizeof a, (double)need),
                         hv_size_text(b, sizeof b, (double)budget));
    }
    if (s == HV_OK) s = plan_cuts(J, opt, rep);
    if (s == HV_OK) {
        J->rowbuf = hv_calloc((size_t)J->threads, sizeof *J->rowbuf);
        J->uni = hv_calloc((size_t)J->threads, sizeof *J->uni);
        J->lk = hv_calloc((size_t)J->threads, sizeof *J->lk);
        J->ti = hv_calloc((size_t)J->threads, sizeof *J->ti);
        s = J->rowbuf && J->uni && J->lk && J->ti ? HV_OK : HV_ERR_NOMEM;
        for (int t = 0; s == HV_OK && t < J->threads; ++t) {
            J->rowbuf[t] = hv_malloc(J->stride + 16);
            J->uni[t] = hv_calloc_big(J->stride * (size_t)S->height, 1);
            J->lk[t] = hv_calloc((size_t)S->nparts + 1, sizeof **J->lk);
            if (!J->rowbuf[t] || !J->uni[t] || !J->lk[t]) s = HV_ERR_NOMEM;
        }
    }
    return s;
}

/* The threads' findings merged: the union images into the first, and what they saw (palette,
 * pHYs), by layer order, as the page's warnings. */
static void merge_threads(job *J, struct tinfo *all, hv_viewer_report *rep)
{
    const vw_stack *S = J->S;
    for (int t = 1; t < J->threads; ++t)
        for (int y = 0; y < S->height; ++y)
            for (size_t k = J->span_start[y]; k < J->span_start[y + 1]; ++k)
                for (size_t i = J->span[2 * k]; i < J->span[2 * k + 1]; ++i)
                    J->uni[0][(size_t)y * J->stride + i] |= J->uni[t][(size_t)y * J->stride + i];
    for (int t = 0; t < J->threads; ++t) {
        const struct tinfo *ti = &J->ti[t];
#define EARLIER(f) (ti->f && (!all->f || ti->f < all->f))
        if (EARLIER(plte_at)) {
            all->plte_at = ti->plte_at;
            all->plte_n = ti->plte_n;
            memcpy(all->plte, ti->plte, sizeof all->plte);
        }
        if (EARLIER(phys_bad_at)) {
            all->phys_bad_at = ti->phys_bad_at;
            all->phys_x = ti->phys_x;
            all->phys_y = ti->phys_y;
        }
        if (EARLIER(phys_none_at)) all->phys_none_at = ti->phys_none_at;
#undef EARLIER
    }
    /* a thread's palette differing from the first one's counts too */
    for (int t = 0; t < J->threads; ++t) {
        const struct tinfo *ti = &J->ti[t];
        size_t bad = ti->plte_bad_at;
        if (ti->plte_at && (ti->plte_n != all->plte_n || memcmp(ti->plte, all->plte, (size_t)all->plte_n * 3)))
            bad = bad ? HV_MIN(bad, ti->plte_at) : ti->plte_at;
        if (bad && (!all->plte_bad_at || bad < all->plte_bad_at)) all->plte_bad_at = bad;
    }
    if (all->phys_bad_at)
        vw_warn(rep, "%s: pHYs says %u x %u pixels per metre, manifest.json's pixel_mm %g x %g mm (%.0f x %.0f per metre); "
                      "the page draws the manifest's",
                S->files[(all->phys_bad_at - 1) * (size_t)S->channels], all->phys_x, all->phys_y, S->pixel_mm[0],
                fabs(S->pixel_mm[1]), 1000.0 / S->pixel_mm[0], 1000.0 / fabs(S->pixel_mm[1]));
    if (all->phys_none_at)
        vw_warn(rep, "%s: no pHYs (physical pixel size); the page draws manifest.json's pixel_mm",
                S->files[(all->phys_none_at - 1) * (size_t)S->channels]);
    if (all->plte_bad_at)
        vw_warn(rep, "%s: its palette differs from %s's; the page draws each layer with its own, the side views with the first",
                S->files[all->plte_bad_at - 1], S->files[all->plte_at - 1]);
}

hv_status hv_viewer_stack_write(const char *stack_dir, const char *html_path, const hv_viewer_options *opt,
                                const hv_progress *progress, hv_viewer_report *report)
{
    hv_viewer_options defaults;
    hv_viewer_report rep;
    memset(&rep, 0, sizeof rep);
    if (!stack_dir) return hv_error_set(HV_ERR_INVALID, "viewer: no stack directory");
    hv_status s = vw_page_begin(&opt, &defaults, html_path);
    if (s != HV_OK) return s;
    struct stat sb;
    if (stat(stack_dir, &sb) != 0) return hv_error_set(HV_ERR_IO, "%s: %s", stack_dir, strerror(errno));
    if (!S_ISDIR(sb.st_mode)) return hv_error_set(HV_ERR_BAD_INPUT, "%s: not a directory (a slice stack is one)", stack_dir);
    char mpath[4200];
    if ((size_t)snprintf(mpath, sizeof mpath, "%s/manifest.json", stack_dir) >= sizeof mpath)
        return hv_error_set(HV_ERR_INVALID, "%s: path too long", stack_dir);
    if (stat(mpath, &sb) != 0 && errno == ENOENT)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: not a slice stack (no manifest.json; hovox layers and hovox tray write one)",
                            stack_dir);
    char *text = NULL;
    size_t size = 0;
    if ((s = hv_read_file(mpath, (size_t)256 << 20, &text, &size)) != HV_OK) return s;
    vw_stack S;
    s = vw_stack_parse(text, size, mpath, &S);
    free(text);
    if (s != HV_OK) return s;
    rep.kind = S.tray ? HV_VIEWER_TRAY : HV_VIEWER_STACK;
    static const char *const modes[] = {"halftone", "fractions", "mask"};
    rep.mode = modes[S.mode];
    rep.width = S.width;
    rep.height = S.height;
    rep.pixel_mm[0] = S.pixel_mm[0];
    rep.pixel_mm[1] = S.pixel_mm[1];
    rep.layers = S.nlayers;
    rep.channels = S.channels;
    rep.parts = S.nparts;
    s = relative_base(stack_dir, html_path, rep.base, sizeof rep.base);

    job J;
    memset(&J, 0, sizeof J);
    J.S = &S;
    J.dir = stack_dir;
    J.stride = ((size_t)S.width * (size_t)S.bit_depth + 7) / 8;
    J.threads = HV_MAX(1, hv_threads());
    if (s == HV_OK) s = job_alloc(&J, stack_dir, opt, &rep);
    if (s == HV_OK) s = hv_progress_report(progress, "view", 0.0);
    if (s == HV_OK) s = hv_parallel_for(S.nlayers, 1, read_layers, &J, progress, "view");
    if (s == HV_OK) s = hv_progress_report(progress, "view", 1.0);
    struct tinfo all;
    memset(&all, 0, sizeof all);
    if (s == HV_OK) merge_threads(&J, &all, &rep);
    json_t *doc = NULL;
    char tbuf[1024];
    const char *title = opt->title ? opt->title : dir_title(stack_dir, tbuf, sizeof tbuf);
    if (s == HV_OK) s = build_doc(&J, &all, title, rep.base, &rep, &doc);
    char *data = NULL;
    if (s == HV_OK && !(data = vw_json_for_script(doc))) s = HV_ERR_NOMEM;
    json_decref(doc);
    if (s == HV_OK) s = vw_page_write(html_path, title, data, &rep.bytes);
    free(data);
    job_free(&J);
    vw_stack_free(&S);
    if (report) *report = rep;
    return s;
}

hv_status hv_viewer_stack_finish(void *user, const char *tmp, const char *dir, const hv_progress *progress)
{
    char page[4200], title[1024];
    if (!tmp || !dir) return hv_error_set(HV_ERR_INVALID, "viewer: no stack directory");
    if ((size_t)snprintf(page, sizeof page, "%s/index.html", tmp) >= sizeof page)
        return hv_error_set(HV_ERR_INVALID, "%s: path too long", tmp);
    hv_viewer_options o;
    hv_viewer_options_init(&o);
    o.title = dir_title(dir, title, sizeof title);
    return hv_viewer_stack_write(tmp, page, &o, progress, user);
}
