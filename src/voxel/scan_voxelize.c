/* src/voxel/scan_voxelize.c - a model from a scan, no mesh (issue 30): a voxel is occupied when the
 * scan's level function (src/io/scan/level.c: trilinear interpolation of the samples, an iso value,
 * a range or a label set) is >= 0 at its centre, on a global lattice in world (RAS) millimetres;
 * then, as asked, components smaller than a minimum feature dropped and cavities below it filled,
 * the largest component kept, every cavity filled (6-connected components, breadth first). The
 * model records the shape as its geometry: one FIELD_ISO leaf (hovox/geometry.h). */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "core/json.h"
#include "hovox/scan.h"
#include "io/scan/scan_internal.h"
#include "voxel_internal.h"
#include "volumes/schema.h"
#include "hovox/geometry.h"

void hv_scan_voxelize_options_init(hv_scan_voxelize_options *o)
{
    memset(o, 0, sizeof *o);
    o->shape.select = HV_SCAN_SELECT_ISO;
}

#define OFF(m) offsetof(hv_scan_voxelize_options, m)
static const hv_option k_opts[] = {
    {.key = "iso", .kind = HV_OPT_NUMBER, .offset = OFF(shape.iso), .meta = "VALUE",
     .help = "the solid: where the trilinearly interpolated value is at least VALUE (e.g. 300 HU for bone)"},
    {.key = "range", .kind = HV_OPT_NUMBER, .count = 2, .offset = OFF(shape.range), .meta = "LO,HI",
     .help = "the solid where the interpolated value lies in [LO, HI]"},
    {.key = "voxel_size", .kind = HV_OPT_NUMBER, .count = 3, .flags = HV_OPT_SCALAR | HV_OPT_LO_OPEN, .lo = 0,
     .hi = 1e6, .offset = OFF(voxel_size), .meta = "L|X,Y,Z", .unit = "mm",
     .help = "voxels of size L (or per axis) on the global lattice (default: the smallest sample spacing)"},
    {.key = "keep_largest", .kind = HV_OPT_FLAG, .offset = OFF(keep_largest), .help = "keep the largest part only"},
    {.key = "fill_holes", .kind = HV_OPT_FLAG, .offset = OFF(fill_holes), .help = "fill every enclosed cavity"},
    {.key = "min_feature", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .offset = OFF(min_feature), .meta = "MM",
     .unit = "mm", .help = "drop parts and fill cavities smaller than a ball of this diameter"},
    {.key = "max_memory", .kind = HV_OPT_BYTES, .offset = OFF(max_memory), .meta = "SIZE",
     .help = "refuse jobs that would need more (default: half of RAM)"},
};
#undef OFF
static const hv_opt_rule k_rules[] = {{HV_RULE_EXCLUDES, "iso", "range", NULL, "one shape"}};

static void set_init(void *o) { hv_scan_voxelize_options_init(o); }

static hv_status set_finish(const hv_optargs *a)
{
    hv_scan_voxelize_options *o = a->opts;
    if (hv_optargs_given(a, "range")) o->shape.select = HV_SCAN_SELECT_RANGE;
    return HV_OK;
}

static const hv_option_set k_set = {"voxelize_scan", k_opts, (int)HV_COUNT(k_opts), sizeof(hv_scan_voxelize_options),
                                    set_init, k_rules, (int)HV_COUNT(k_rules), set_finish, NULL, NULL, 0};

const hv_option_set *hv_scan_voxelize_option_set(void) { return &k_set; }

typedef struct eval_ctx {
    const hv_scan_level *lv;
    uint8_t *occ;
    int64_t n[3], first[3];
    double L[3], origin[3];
} eval_ctx;

/* One z-slab (k) of the dense box: the index point moves linearly along x. */
static hv_status eval_range(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    eval_ctx *c = vctx;
    size_t nx = (size_t)c->n[0], ny = (size_t)c->n[1];
    for (size_t k = b; k < e; ++k)
        for (size_t j = 0; j < ny; ++j) {
            double w0[3] = {c->origin[0] + (double)c->first[0] * c->L[0],
                            c->origin[1] + (double)(c->first[1] + (int64_t)j) * c->L[1],
                            c->origin[2] + (double)(c->first[2] + (int64_t)k) * c->L[2]};
            double w1[3] = {w0[0] + c->L[0], w0[1], w0[2]};
            double i0[3], i1[3];
            hv_scan_level_index(c->lv, w0, i0);
            hv_scan_level_index(c->lv, w1, i1);
            double d[3] = {i1[0] - i0[0], i1[1] - i0[1], i1[2] - i0[2]};
            uint8_t *row = c->occ + (k * ny + j) * nx;
            for (size_t i = 0; i < nx; ++i) {
                double idx[3] = {i0[0] + (double)i * d[0], i0[1] + (double)i * d[1], i0[2] + (double)i * d[2]};
                row[i] = hv_scan_level_at_index(c->lv, idx) >= 0;
            }
        }
    return HV_OK;
}

/* 6-connected components of the voxels whose value is `v`: label[p] = component + 1 (0 for
 * others); sizes[c] voxels, border[c] 1 when it touches the box's faces. */
typedef struct comps {
    uint32_t *label;
    uint64_t *size;
    uint8_t *border;
    size_t n;
} comps;

static void comps_free(comps *c)
{
    free(c->label);
    free(c->size);
    free(c->border);
    memset(c, 0, sizeof *c);
}

static hv_status components(const uint8_t *occ, const int64_t n[3], uint8_t v, comps *c)
{
    memset(c, 0, sizeof *c);
    size_t nx = (size_t)n[0], ny = (size_t)n[1], nz = (size_t)n[2], total = nx * ny * nz;
    c->label = hv_calloc_big(total, sizeof *c->label);
    size_t *queue = hv_malloc_big(total, sizeof *queue);
    size_t cap = 0;
    hv_status st = c->label && queue ? HV_OK : HV_ERR_NOMEM;
    for (size_t p = 0; p < total && st == HV_OK; ++p) {
        if (occ[p] != v || c->label[p]) continue;
        if (c->n == UINT32_MAX - 1) {
            st = hv_error_set(HV_ERR_LIMIT, "more than 2^32 components");
            break;
        }
        if ((st = hv_grow((void **)&c->size, &cap, c->n + 1, sizeof *c->size)) != HV_OK) break;
        size_t cap2 = cap;
        uint8_t *nb = realloc(c->border, cap2);
        if (!nb) {
            st = hv_error_set(HV_ERR_NOMEM, "out of memory");
            break;
        }
        c->border = nb;
        uint32_t id = (uint32_t)++c->n;
        size_t head = 0, tail = 0;
        queue[tail++] = p;
        c->label[p] = id;
        uint64_t count = 0;
        int border = 0;
        while (head < tail) {
            size_t q = queue[head++];
            ++count;
            size_t x = q % nx, y = q / nx % ny, z = q / nx / ny;
            if (x == 0 || y == 0 || z == 0 || x == nx - 1 || y == ny - 1 || z == nz - 1) border = 1;
            size_t nbs[6];
            int m = 0;
            if (x > 0) nbs[m++] = q - 1;
            if (x + 1 < nx) nbs[m++] = q + 1;
            if (y > 0) nbs[m++] = q - nx;
            if (y + 1 < ny) nbs[m++] = q + nx;
            if (z > 0) nbs[m++] = q - nx * ny;
            if (z + 1 < nz) nbs[m++] = q + nx * ny;
            for (int k = 0; k < m; ++k)
                if (occ[nbs[k]] == v && !c->label[nbs[k]]) {
                    c->label[nbs[k]] = id;
                    queue[tail++] = nbs[k];
                }
        }
        c->size[id - 1] = count;
        c->border[id - 1] = (uint8_t)border;
    }
    free(queue);
    if (st != HV_OK) comps_free(c);
    return st;
}

/* Set voxels of components chosen by keep[c] == 0 to `to`. */
static void comps_apply(uint8_t *occ, size_t total, const comps *c, const uint8_t *drop, uint8_t to)
{
    for (size_t p = 0; p < total; ++p)
        if (c->label[p] && drop[c->label[p] - 1]) occ[p] = to;
}

static hv_status cleanup(uint8_t *occ, const int64_t n[3], const hv_scan_voxelize_options *o, double vv,
                         hv_scan_voxelize_report *rep)
{
    size_t total = (size_t)n[0] * (size_t)n[1] * (size_t)n[2];
    comps c;
    hv_status st = HV_OK;
    if (o->min_feature > 0) {
        double vmin = M_PI / 6.0 * o->min_feature * o->min_feature * o->min_feature;
        if ((st = components(occ, n, 1, &c)) != HV_OK) return st;
        uint8_t *drop = hv_calloc(c.n ? c.n : 1, 1);
        if (!drop) st = HV_ERR_NOMEM;
        for (size_t k = 0; k < c.n && drop; ++k)
            if ((double)c.size[k] * vv < vmin) drop[k] = 1, rep->dropped_parts++, rep->dropped_voxels += c.size[k];
        if (drop) comps_apply(occ, total, &c, drop, 0);
        free(drop);
        comps_free(&c);
        if (st != HV_OK) return st;
        if ((st = components(occ, n, 0, &c)) != HV_OK) return st;
        drop = hv_calloc(c.n ? c.n : 1, 1);
        if (!drop) st = HV_ERR_NOMEM;
        for (size_t k = 0; k < c.n && drop; ++k)
            if (!c.border[k] && (double)c.size[k] * vv < vmin)
                drop[k] = 1, rep->filled_cavities++, rep->filled_voxels += c.size[k];
        if (drop) comps_apply(occ, total, &c, drop, 1);
        free(drop);
        comps_free(&c);
        if (st != HV_OK) return st;
    }
    if (o->keep_largest) {
        if ((st = components(occ, n, 1, &c)) != HV_OK) return st;
        size_t best = 0;
        for (size_t k = 1; k < c.n; ++k)
            if (c.size[k] > c.size[best]) best = k;
        uint8_t *drop = hv_calloc(c.n ? c.n : 1, 1);
        if (!drop) st = HV_ERR_NOMEM;
        for (size_t k = 0; k < c.n && drop; ++k)
            if (k != best) drop[k] = 1, rep->dropped_parts++, rep->dropped_voxels += c.size[k];
        if (drop) comps_apply(occ, total, &c, drop, 0);
        free(drop);
        comps_free(&c);
        if (st != HV_OK) return st;
    }
    if (o->fill_holes) {
        if ((st = components(occ, n, 0, &c)) != HV_OK) return st;
        uint8_t *drop = hv_calloc(c.n ? c.n : 1, 1);
        if (!drop) st = HV_ERR_NOMEM;
        for (size_t k = 0; k < c.n && drop; ++k)
            if (!c.border[k]) drop[k] = 1, rep->filled_cavities++, rep->filled_voxels += c.size[k];
        if (drop) comps_apply(occ, total, &c, drop, 1);
        free(drop);
        comps_free(&c);
    }
    return st;
}

/* The geometry record: one FIELD_ISO leaf, the samples and the shape, placed by the scan's affine. */
static hv_status record(const hv_scan *scan, const hv_scan_shape *shape, hv_volume *vol)
{
    uint8_t *data;
    size_t size;
    double m[12];
    hv_scan_affine(scan, m);
    hv_status st = hv_scan_pack(scan, shape, &data, &size);
    if (st != HV_OK) return st;
    hv_geometry *g = NULL;
    st = hv_geometry_from_leaf(HV_LEAF_FIELD_ISO, hv_basename(hv_scan_name(scan)), data, size, m, 1.0, &g);
    free(data);
    if (st == HV_OK) st = hv_geometry_write(g, vol);
    hv_geometry_destroy(g);
    return st;
}

hv_status hv_scan_voxelize(const hv_scan *scan, const hv_scan_voxelize_options *o, hv_volume **out,
                           hv_scan_voxelize_report *report)
{
    *out = NULL;
    hv_scan_voxelize_report rep;
    memset(&rep, 0, sizeof rep);
    if (!scan || !o) return hv_error_set(HV_ERR_INVALID, "hv_scan_voxelize: NULL argument");
    if (!(o->min_feature >= 0) || !isfinite(o->min_feature))
        return hv_error_option(HV_ERR_INVALID, "{min_feature} must be a length >= 0 mm, got %g", o->min_feature);
    hv_scan_level lv;
    hv_status st = hv_scan_level_init(scan, &o->shape, &lv);
    if (st != HV_OK) return st;
    double sp[3], lo[3], hi[3];
    char axes[4];
    hv_scan_geometry(scan, sp, axes, lo, hi);
    double L[3];
    for (int a = 0; a < 3; ++a) {
        L[a] = o->voxel_size[0] > 0 ? o->voxel_size[a] : fmin(sp[0], fmin(sp[1], sp[2]));
        if (!(L[a] > 0) || !isfinite(L[a])) {
            hv_scan_level_free(&lv);
            return hv_error_option(HV_ERR_INVALID, "{voxel_size} must be above 0 mm, got %g", L[a]);
        }
    }
    /* the global lattice: voxel centres at (n + 1/2) L, as hv_voxelize's with a voxel size */
    int64_t first[3], n[3];
    double totald = 1;
    for (int a = 0; a < 3; ++a) {
        double f = floor(lo[a] / L[a] - 0.5), l = ceil(hi[a] / L[a] - 0.5);
        if (!(l - f < 2147483647.0)) {
            hv_scan_level_free(&lv);
            return hv_error_option(HV_ERR_LIMIT, "%s: voxels of %g mm: more than 2^31 on an axis ({voxel_size})",
                                   hv_scan_name(scan), L[a]);
        }
        first[a] = (int64_t)f;
        n[a] = (int64_t)(l - f) + 1;
        /* bit grids in whole 8^3 blocks */
        int64_t b0 = first[a] >= 0 ? first[a] / 8 * 8 : -((-first[a] + 7) / 8 * 8);
        n[a] += first[a] - b0;
        first[a] = b0;
        n[a] = (n[a] + 7) / 8 * 8;
        totald *= (double)n[a];
    }
    uint64_t total = totald > 1e15 ? (uint64_t)1e15 : (uint64_t)totald;
    int post = o->keep_largest || o->fill_holes || o->min_feature > 0;
    size_t sd[3];
    hv_scan_dims(scan, sd);
    /* the dense mask, components' labels and queue, two bit grids, the store; and the record's
     * copies of the samples (packed, deflated, base64) */
    uint64_t need = total * (1 + (post ? 12 : 0)) + total / 4 + total / 8 * 3 +
                    (uint64_t)sd[0] * sd[1] * sd[2] * 4 * 3;
    uint64_t budget = hv_memory_budget(o->max_memory);
    if (budget && need > budget) {
        char a[32], b[32];
        hv_scan_level_free(&lv);
        return hv_error_option(HV_ERR_LIMIT, "%s: voxelizing at %lld x %lld x %lld voxels of %g mm needs about %s, more than the limit of %s ({max_memory})",
                               hv_scan_name(scan), (long long)n[0], (long long)n[1], (long long)n[2], L[0],
                               hv_size_text(a, sizeof a, (double)need), hv_size_text(b, sizeof b, (double)budget));
    }
    uint8_t *occ = hv_malloc_big((size_t)total, 1);
    if (!occ) {
        hv_scan_level_free(&lv);
        return HV_ERR_NOMEM;
    }
    eval_ctx ec = {&lv, occ, {n[0], n[1], n[2]}, {first[0], first[1], first[2]}, {L[0], L[1], L[2]},
                   {L[0] / 2, L[1] / 2, L[2] / 2}};
    st = hv_parallel_for((size_t)n[2], 1, eval_range, &ec, o->progress, "voxelize");
    hv_scan_level_free(&lv);
    double vv = L[0] * L[1] * L[2];
    if (st == HV_OK && post) st = cleanup(occ, n, o, vv, &rep);
    hv_bitgrid B, S;
    memset(&B, 0, sizeof B);
    memset(&S, 0, sizeof S);
    if (st == HV_OK) st = hv_bitgrid_init(&B, n, first);
    if (st == HV_OK) st = hv_bitgrid_init(&S, n, first);
    size_t nx = (size_t)n[0], ny = (size_t)n[1], nz = (size_t)n[2];
    /* dense (x fastest) -> bit rows along z; surface: occupied with an empty 6-neighbour */
    for (size_t k = 0; k < nz && st == HV_OK; ++k)
        for (size_t j = 0; j < ny; ++j)
            for (size_t i = 0; i < nx; ++i) {
                size_t p = (k * ny + j) * nx + i;
                if (!occ[p]) continue;
                ++rep.occupied;
                hv_bitgrid_row(&B, (int64_t)i, (int64_t)j)[k >> 6] |= 1ull << (k & 63);
                int edge = i == 0 || j == 0 || k == 0 || i + 1 == nx || j + 1 == ny || k + 1 == nz;
                if (edge || !occ[p - 1] || !occ[p + 1] || !occ[p - nx] || !occ[p + nx] || !occ[p - nx * ny] ||
                    !occ[p + nx * ny]) {
                    hv_bitgrid_row(&S, (int64_t)i, (int64_t)j)[k >> 6] |= 1ull << (k & 63);
                    ++rep.surface;
                }
            }
    free(occ);
    hv_transform xf = {{L[0], L[1], L[2]}, {L[0] / 2, L[1] / 2, L[2] / 2}};
    hv_volume *vol = NULL;
    if (st == HV_OK) st = hv_voxel_store(&B, &S, &xf, o->progress, &vol);
    hv_bitgrid_free(&B);
    hv_bitgrid_free(&S);
    for (int a = 0; a < 3; ++a) {
        rep.first[a] = first[a];
        rep.dims[a] = n[a];
        rep.voxel[a] = L[a];
    }
    rep.volume = (double)rep.occupied * vv;
    if (st == HV_OK) st = record(scan, &o->shape, vol);
    if (st == HV_OK) st = hv_volume_meta_set_string(vol, HV_META_HOVOX_VERSION, hv_version());
    if (st != HV_OK) {
        hv_volume_destroy(vol);
        return st;
    }
    *out = vol;
    if (report) *report = rep;
    return HV_OK;
}
