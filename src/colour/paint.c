/* src/colour/paint.c - colour carried into the part (issue 29, item 1): every occupied voxel within
 * `depth` of the surface takes the colour of its nearest point on the mesh (exact point-triangle
 * distance, Ericson, Real-Time Collision Detection 5.1.5, found through a bounding volume hierarchy
 * of the facets, Ericson 6.2, searched from the last voxel's facet), turned into the six resin
 * fractions by the colour map (cached per distinct colour); deeper voxels take the core (a resin,
 * or a colour). Voxels are painted in parallel; the result does not depend on the threads. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "core/json.h"
#include "hovox/colour.h"
#include "hovox/material.h"
#include "hovox/mesh.h"
#include "hovox/volume.h"

/* Closest point on triangle abc to p; bary receives its weights of a, b, c. */
static void closest_on_triangle(const double p[3], const double a[3], const double b[3], const double c[3],
                                double q[3], double bary[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    for (int k = 0; k < 3; ++k) {
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ap[k] = p[k] - a[k];
        bp[k] = p[k] - b[k];
        cp[k] = p[k] - c[k];
    }
#define DOT(u, v) ((u)[0] * (v)[0] + (u)[1] * (v)[1] + (u)[2] * (v)[2])
    double d1 = DOT(ab, ap), d2 = DOT(ac, ap), d3 = DOT(ab, bp), d4 = DOT(ac, bp), d5 = DOT(ab, cp),
           d6 = DOT(ac, cp);
#undef DOT
    double u, v, w;
    if (d1 <= 0 && d2 <= 0) { u = 1; v = 0; w = 0; }
    else if (d3 >= 0 && d4 <= d3) { u = 0; v = 1; w = 0; }
    else if (d6 >= 0 && d5 <= d6) { u = 0; v = 0; w = 1; }
    else {
        double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
        if (vc <= 0 && d1 >= 0 && d3 <= 0) {
            double t = d1 / (d1 - d3);
            u = 1 - t; v = t; w = 0;
        } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
            double t = d2 / (d2 - d6);
            u = 1 - t; v = 0; w = t;
        } else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
            double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
            u = 0; v = 1 - t; w = t;
        } else {
            double den = 1 / (va + vb + vc);
            v = vb * den;
            w = vc * den;
            u = 1 - v - w;
        }
    }
    for (int k = 0; k < 3; ++k) q[k] = u * a[k] + v * b[k] + w * c[k];
    bary[0] = u;
    bary[1] = v;
    bary[2] = w;
}

/* A bounding volume hierarchy over the facets (median split of centroids along the longest
 * axis, leaves of up to 4 facets), each facet's corners copied as doubles in leaf order. */
typedef struct bvh_node {
    double lo[3], hi[3];
    uint32_t first, count; /* a leaf: facets first..first+count-1; else count 0, children first, first+1 */
} bvh_node;

typedef struct bvh {
    bvh_node *node;
    size_t nnode;
    uint32_t *facet; /* leaf order -> mesh facet */
    double *corner;  /* 9 per leaf-order facet */
} bvh;

enum { BVH_LEAF = 4, BVH_DEPTH = 64 };

static void bvh_free(bvh *b)
{
    free(b->node);
    free(b->facet);
    free(b->corner);
}

/* Partition ids[lo..hi) so the k-th smallest centroid coordinate on axis a sits at k (quickselect). */
static void select_kth(uint32_t *ids, const float *cen, int a, size_t lo, size_t hi, size_t k)
{
    while (hi - lo > 1) {
        float pivot = cen[3 * (size_t)ids[lo + (hi - lo) / 2] + (size_t)a];
        size_t i = lo, j = hi - 1;
        while (i <= j) {
            while (cen[3 * (size_t)ids[i] + (size_t)a] < pivot) ++i;
            while (cen[3 * (size_t)ids[j] + (size_t)a] > pivot) --j;
            if (i <= j) {
                uint32_t t = ids[i];
                ids[i] = ids[j];
                ids[j] = t;
                ++i;
                if (j == 0) break;
                --j;
            }
        }
        if (k <= j) hi = j + 1;
        else if (k >= i) lo = i;
        else return;
    }
}

static hv_status bvh_build(bvh *b, const hv_mesh *m)
{
    size_t nf = hv_mesh_facet_count(m);
    const float *v = hv_mesh_vertices(m);
    const uint32_t *t = hv_mesh_facets(m);
    memset(b, 0, sizeof *b);
    if (nf == 0) return HV_OK;
    float *cen = hv_malloc_array(nf, 3 * sizeof *cen);
    b->facet = hv_malloc_array(nf, sizeof *b->facet);
    b->node = hv_malloc_array(2 * nf, sizeof *b->node);
    b->corner = hv_malloc_array(nf, 9 * sizeof *b->corner);
    if (!cen || !b->facet || !b->node || !b->corner) {
        free(cen);
        return HV_ERR_NOMEM;
    }
    for (size_t f = 0; f < nf; ++f) {
        b->facet[f] = (uint32_t)f;
        for (int a = 0; a < 3; ++a)
            cen[3 * f + (size_t)a] = (v[3 * (size_t)t[3 * f] + (size_t)a] + v[3 * (size_t)t[3 * f + 1] + (size_t)a] +
                                      v[3 * (size_t)t[3 * f + 2] + (size_t)a]) / 3.0f;
    }
    /* nodes in preorder-ish: a node's two children are made together, so they sit side by side */
    struct { size_t node, lo, hi; } stack[BVH_DEPTH * 2 + 2];
    int top = 0;
    b->nnode = 1;
    stack[top].node = 0;
    stack[top].lo = 0;
    stack[top++].hi = nf;
    while (top > 0) {
        --top;
        size_t ni = stack[top].node, lo = stack[top].lo, hi = stack[top].hi;
        bvh_node *n = &b->node[ni];
        double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int a = 0; a < 3; ++a) {
            n->lo[a] = INFINITY;
            n->hi[a] = -INFINITY;
        }
        for (size_t q = lo; q < hi; ++q) {
            size_t f = b->facet[q];
            for (int a = 0; a < 3; ++a) {
                for (int k = 0; k < 3; ++k) {
                    double x = v[3 * (size_t)t[3 * f + (size_t)k] + (size_t)a];
                    n->lo[a] = x < n->lo[a] ? x : n->lo[a];
                    n->hi[a] = x > n->hi[a] ? x : n->hi[a];
                }
                double c = cen[3 * f + (size_t)a];
                clo[a] = c < clo[a] ? c : clo[a];
                chi[a] = c > chi[a] ? c : chi[a];
            }
        }
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (chi[a] - clo[a] > chi[axis] - clo[axis]) axis = a;
        /* a leaf when small, or when the centroids cannot be told apart, or the stack would overflow */
        if (hi - lo <= BVH_LEAF || !(chi[axis] > clo[axis]) || top >= BVH_DEPTH * 2) {
            n->first = (uint32_t)lo;
            n->count = (uint32_t)(hi - lo);
            continue;
        }
        size_t mid = lo + (hi - lo) / 2;
        select_kth(b->facet, cen, axis, lo, hi, mid);
        n->first = (uint32_t)b->nnode;
        n->count = 0;
        b->nnode += 2;
        stack[top].node = n->first;
        stack[top].lo = lo;
        stack[top++].hi = mid;
        stack[top].node = n->first + 1u;
        stack[top].lo = mid;
        stack[top++].hi = hi;
    }
    free(cen);
    for (size_t q = 0; q < nf; ++q)
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a)
                b->corner[9 * q + (size_t)(3 * k + a)] = v[3 * (size_t)t[3 * (size_t)b->facet[q] + (size_t)k] + (size_t)a];
    return HV_OK;
}

static double box_d2(const bvh_node *n, const double p[3])
{
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
        double e = p[a] < n->lo[a] ? n->lo[a] - p[a] : p[a] > n->hi[a] ? p[a] - n->hi[a] : 0;
        d2 += e * e;
    }
    return d2;
}

typedef struct hit {
    double d2;     /* squared distance; the bound while searching */
    size_t q;      /* leaf-order facet, SIZE_MAX for none */
    double bary[3];
} hit;

/* Facet q (leaf order) against p: kept when nearer, or as near with a smaller mesh facet number,
 * so the answer is the minimum of (distance, facet) whatever the order facets were tried in. */
static void try_facet(const bvh *b, size_t q, const double p[3], hit *h)
{
    const double *c = b->corner + 9 * q;
    double x[3], w[3];
    closest_on_triangle(p, c, c + 3, c + 6, x, w);
    double d2 = (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]) + (x[2] - p[2]) * (x[2] - p[2]);
    if (d2 < h->d2 || (d2 == h->d2 && (h->q == SIZE_MAX || b->facet[q] < b->facet[h->q]))) {
        h->d2 = d2;
        h->q = q;
        memcpy(h->bary, w, sizeof w);
    }
}

/* The nearest facet to p no farther than sqrt(h->d2) (h->q SIZE_MAX: none); `guess` (a facet near
 * the last voxel, or SIZE_MAX) tightens the bound first. Boxes farther than the bound are skipped;
 * as near are kept, so ties resolve by try_facet's rule. */
static void bvh_nearest(const bvh *b, const double p[3], size_t guess, hit *h)
{
    if (b->nnode == 0) return;
    if (guess != SIZE_MAX) try_facet(b, guess, p, h);
    uint32_t stack[BVH_DEPTH * 2 + 4];
    int top = 0;
    if (box_d2(&b->node[0], p) > h->d2) return;
    stack[top++] = 0;
    while (top > 0) {
        const bvh_node *n = &b->node[stack[--top]];
        if (n->count) {
            for (uint32_t q = n->first; q < n->first + n->count; ++q)
                if (q != guess) try_facet(b, q, p, h);
            continue;
        }
        double dl = box_d2(&b->node[n->first], p), dr = box_d2(&b->node[n->first + 1], p);
        uint32_t near = n->first, far = n->first + 1;
        if (dr < dl) {
            double t = dl;
            dl = dr;
            dr = t;
            near = n->first + 1;
            far = n->first;
        }
        if (dr <= h->d2) stack[top++] = far;
        if (dl <= h->d2) stack[top++] = near;
    }
}

/* What painting used, for the manifest's dE2000 with the same profile (hv_colour_map_for_model). */
static hv_status record(hv_volume *vol, const hv_colour_map *map, double depth, const char *core, const float *core_rgba,
                        int gives, double share)
{
    char hex[10];
    if (!core) {
        unsigned c[3];
        for (int k = 0; k < 3; ++k) c[k] = (unsigned)lrintf(core_rgba[k] * 255.0f);
        snprintf(hex, sizeof hex, "#%02x%02x%02x", c[0] & 255u, c[1] & 255u, c[2] & 255u);
    }
    json_t *doc = json_object(), *resins = json_array();
    int bad = !doc || !resins;
    for (int k = 0; k < HV_COLOUR_SLOTS && !bad; ++k)
        bad |= json_array_append_new(resins, hv_json_text(hv_colour_map_resin(map, k)));
    bad |= hv_json_set(doc, "icc", hv_json_text(hv_colour_map_icc(map)));
    bad |= hv_json_set(doc, "description", hv_json_text(hv_colour_map_description(map)));
    bad |= hv_json_set(doc, "intent", json_string(hv_intent_name(hv_colour_map_intent(map))));
    bad |= hv_json_set(doc, "resins", resins);
    bad |= hv_json_set(doc, "depth_mm", hv_json_number(depth));
    bad |= hv_json_set(doc, "core", hv_json_text(core ? core : hex));
    if (gives >= 0) { /* six slots: a role gave way to the core (see give_way) */
        json_t *g = json_object();
        bad |= !g;
        bad |= hv_json_set(g, "resin", hv_json_text(hv_colour_map_resin(map, gives)));
        bad |= hv_json_set(g, "into", hv_json_text(gives == HV_COLOUR_CLEAR ? hv_colour_map_resin(map, HV_COLOUR_W)
                                                                              : "cyan, magenta and yellow"));
        bad |= hv_json_set(g, "share", hv_json_number(share));
        bad |= hv_json_set(doc, "gives_way", g);
    }
    char *text = bad ? NULL : hv_json_dump(doc);
    json_decref(doc);
    if (!text) return hv_error_set(HV_ERR_NOMEM, "out of memory");
    hv_status s = hv_volume_meta_set_json(vol, "hovox.colour.json", text);
    free(text);
    return s;
}

/* A thread's cache in front of the map's (which locks): the last fractions of each of 1024
 * colour slots, so a texture's texels convert once and most look-ups take no lock. */
enum { FRONT = 1024 };
typedef struct front {
    uint64_t key[FRONT]; /* the input profile and the rgba bytes; valid[] says whether the slot holds one */
    uint8_t valid[FRONT];
    float f[FRONT][HV_COLOUR_SLOTS];
} front;

typedef struct paint_job {
    const bvh *tree;
    const hv_mesh *mesh;
    hv_colour_map *map;
    const double *xyz;
    size_t n;
    double band2; /* searched this far (squared): the depth and two voxels, for colour.depth */
    int nmat, core_slot;
    const float *core_rgba, *corefr;
    double depth2; /* the colour depth, squared: a voxel no farther from the surface is skin */
    float depth_f, far; /* the colour depth as the grid compares it; the depth beyond the band */
    float *val;
    front *cache; /* one per thread */
    const int *tex_input; /* per texture its input profile in the map (0: sRGB) */
} paint_job;

static void fractions(front *c, hv_colour_map *map, int id, const uint8_t c8[4], float out[HV_COLOUR_SLOTS])
{
    uint32_t rgba = (uint32_t)c8[0] << 24 | (uint32_t)c8[1] << 16 | (uint32_t)c8[2] << 8 | c8[3];
    uint64_t key = (uint64_t)id << 32 | rgba;
    size_t j = (size_t)(((rgba ^ (uint32_t)id * 0x9E3779B9u) * 2654435761u) >> 22) & (FRONT - 1);
    if (!c->valid[j] || c->key[j] != key) {
        hv_colour_map_fractions_in(map, id, c8, c->f[j]);
        c->key[j] = key;
        c->valid[j] = 1;
    }
    memcpy(out, c->f[j], sizeof c->f[j]);
}

/* colour.depth of a voxel d mm from the surface: its side of the depth kept when rounded to a float
 * (the stack compares the float with the float depth), `far` beyond the band. */
static float skin_depth(const paint_job *J, double d, int skin)
{
    float f = d < J->far ? (float)d : J->far;
    if (skin && f > J->depth_f) f = J->depth_f;
    if (!skin && f <= J->depth_f) f = nextafterf(J->depth_f, INFINITY);
    return f;
}

static hv_status paint_range(void *ctx, size_t begin, size_t end, int thread)
{
    const paint_job *J = ctx;
    size_t guess = SIZE_MAX, n = J->n;
    for (size_t i = begin; i < end; ++i) {
        float fr[HV_COLOUR_SLOTS + 1] = {0}, rgba[4], want[4] = {0, 0, 0, 0};
        hit h = {J->band2, SIZE_MAX, {0, 0, 0}};
        bvh_nearest(J->tree, J->xyz + 3 * i, guess, &h);
        if (h.q != SIZE_MAX) guess = h.q;
        /* the nearest facet within the band is the nearest within the depth when it is that near
         * (the bound only prunes; ties go by try_facet's rule either way) */
        int skin = h.q != SIZE_MAX && h.d2 <= J->depth2;
        J->val[(size_t)(J->nmat + 4) * n + i] = skin_depth(J, h.q != SIZE_MAX ? sqrt(h.d2) : INFINITY, skin);
        if (skin && hv_mesh_colour_at(J->mesh, J->tree->facet[h.q], h.bary, rgba)) {
            uint8_t c8[4];
            for (int k = 0; k < 4; ++k) c8[k] = (uint8_t)lrintf(rgba[k] * 255.0f);
            /* a texture's colours are in its embedded profile, when it has one */
            const int32_t *ft = hv_mesh_facet_textures(J->mesh);
            int32_t tex = ft ? ft[J->tree->facet[h.q]] : -1;
            int id = tex >= 0 && J->tex_input ? J->tex_input[tex] : 0;
            fractions(&J->cache[thread], J->map, id, c8, fr);
            uint8_t s8[3];
            hv_colour_map_srgb_in(J->map, id, c8, s8);
            for (int k = 0; k < 3; ++k) want[k] = s8[k] / 255.0f;
            want[3] = 1;
        } else if (J->core_rgba) {
            memcpy(fr, J->corefr, HV_COLOUR_SLOTS * sizeof *fr);
            memcpy(want, J->core_rgba, 3 * sizeof *want);
            want[3] = 1;
        } else {
            fr[J->core_slot >= 0 ? J->core_slot : HV_COLOUR_SLOTS] = 1;
        }
        for (int k = 0; k < J->nmat; ++k) J->val[(size_t)k * n + i] = fr[k];
        for (int k = 0; k < 4; ++k) J->val[(size_t)(J->nmat + k) * n + i] = want[k];
    }
    return HV_OK;
}

/* The printer's six slots (issue 29: a colour shares them with graded materials): a core resin
 * that is not one of the six colour resins takes a slot, so one colour role gives way. Clear when
 * no voxel uses it (opaque colours), else black when none uses it, else the lesser used of the
 * two; its fractions fold into what prints nearest: clear into white (a translucent colour
 * printed opaque), black into equal cyan, magenta and yellow (process black). Returns the slot,
 * and in *share its mean fraction over the voxels that had a colour. */
static int give_way(float *val, size_t n, const float *want_mask, double *share)
{
    double used[HV_COLOUR_SLOTS] = {0}, coloured = 0;
    for (size_t i = 0; i < n; ++i) {
        coloured += want_mask[i] > 0.5f;
        for (int k = 0; k < HV_COLOUR_SLOTS; ++k) used[k] += val[(size_t)k * n + i];
    }
    int g = used[HV_COLOUR_CLEAR] == 0 ? HV_COLOUR_CLEAR
            : used[HV_COLOUR_K] == 0   ? HV_COLOUR_K
            : used[HV_COLOUR_CLEAR] <= used[HV_COLOUR_K] ? HV_COLOUR_CLEAR : HV_COLOUR_K;
    *share = coloured > 0 ? used[g] / coloured : 0;
    float *gv = val + (size_t)g * n;
    for (size_t i = 0; i < n; ++i) {
        if (gv[i] == 0) continue;
        if (g == HV_COLOUR_CLEAR) {
            val[(size_t)HV_COLOUR_W * n + i] += gv[i];
        } else {
            for (int k = HV_COLOUR_C; k <= HV_COLOUR_Y; ++k) val[(size_t)k * n + i] += gv[i] / 3.0f;
        }
        gv[i] = 0;
    }
    return g;
}

hv_status hv_colour_paint(hv_volume *vol, const hv_mesh *mesh, hv_colour_map *map, double depth, const char *core,
                          const float *core_rgba)
{
    if (!(depth > 0)) return hv_error_set(HV_ERR_INVALID, "colour depth must be > 0 mm, got %g", depth);
    if (!core && !core_rgba) return hv_error_set(HV_ERR_INVALID, "colour paint: no core resin or colour");
    double *xyz = NULL;
    size_t n = 0;
    float *val = NULL;
    front *cache = NULL;
    hv_status s = hv_volume_centres(vol, "occupancy", &xyz, &n);
    if (s != HV_OK) return s;
    bvh tree;
    if ((s = bvh_build(&tree, mesh)) != HV_OK) goto done;
    int core_slot = -1; /* core a resin among the six */
    for (int k = 0; core && k < HV_COLOUR_SLOTS; ++k)
        if (strcmp(core, hv_colour_map_resin(map, k)) == 0) core_slot = k;
    int nmat = HV_COLOUR_SLOTS + (core && core_slot < 0 ? 1 : 0);
    /* the fractions, then the requested colour: r, g, b and the mask of voxels that have one, then
     * the depth */
    val = hv_malloc_array(n ? n : 1, (size_t)(nmat + 5) * sizeof *val);
    cache = hv_calloc((size_t)hv_threads(), sizeof *cache);
    if (!val || !cache) {
        s = HV_ERR_NOMEM;
        goto done;
    }
    float corefr[HV_COLOUR_SLOTS] = {0};
    if (core_rgba) {
        uint8_t c8[4];
        for (int k = 0; k < 4; ++k) c8[k] = (uint8_t)lrintf(core_rgba[k] * 255.0f);
        hv_colour_map_fractions(map, c8, corefr);
    }
    /* textures with an embedded ICC profile: their colours go through it (inputs of the map) */
    int *tex_input = NULL;
    size_t ntex = hv_mesh_texture_count(mesh);
    if (ntex && !(tex_input = hv_calloc(ntex, sizeof *tex_input))) {
        s = HV_ERR_NOMEM;
        goto done;
    }
    for (size_t t = 0; t < ntex && s == HV_OK; ++t) {
        const hv_mesh_texture *tx = hv_mesh_texture_at(mesh, t);
        if (tx->icc) s = hv_colour_map_add_input(map, tx->icc, tx->icc_size, tx->name, &tex_input[t]);
    }
    if (s != HV_OK) {
        free(tex_input);
        goto done;
    }
    /* colour.depth: exact within the depth and two voxels (the largest edge) beyond it, so the
     * voxels around a printer pixel at the depth on either side have their true distances */
    hv_transform xf = hv_volume_get_transform(vol);
    double h = HV_MAX(xf.voxel[0], HV_MAX(xf.voxel[1], xf.voxel[2]));
    paint_job job = {.tree = &tree, .mesh = mesh, .map = map, .xyz = xyz, .n = n,
                     .band2 = (depth + 2 * h) * (depth + 2 * h), .nmat = nmat, .core_slot = core_slot,
                     .core_rgba = core_rgba, .corefr = corefr, .depth2 = depth * depth, .depth_f = (float)depth,
                     .far = (float)(depth + 3 * h), .val = val, .cache = cache, .tex_input = tex_input};
    /* voxels come in leaf order, so a chunk is a compact block and the last voxel's facet a close bound */
    if (n) s = hv_parallel_for(n, 4096, paint_range, &job, NULL, NULL);
    free(tex_input);
    if (s != HV_OK) goto done;
    double share = 0;
    int gives = nmat > HV_COLOUR_SLOTS ? give_way(val, n, val + (size_t)(nmat + 3) * n, &share) : -1;
    /* display colours of slots whose resins the resin table does not know (it colours the J750's) */
    static const float k_show[HV_COLOUR_SLOTS][4] = {{0, 0.6f, 0.9f, 1}, {0.9f, 0, 0.5f, 1}, {1, 0.9f, 0, 1},
                                                      {0.1f, 0.1f, 0.1f, 1}, {1, 1, 1, 1}, {0.8f, 0.9f, 1, 0.3f}};
    hv_material_table *tab = NULL;
    s = hv_material_table_create(&tab);
    for (int k = 0; k < nmat && s == HV_OK; ++k)
        if (k != gives)
            s = hv_material_add(tab, k < HV_COLOUR_SLOTS ? hv_colour_map_resin(map, k) : core,
                                k < HV_COLOUR_SLOTS && !hv_resin_find(hv_colour_map_resin(map, k)) ? k_show[k] : NULL,
                                NULL);
    for (int k = 0; k < nmat && s == HV_OK; ++k) {
        if (k == gives) continue;
        char name[160];
        snprintf(name, sizeof name, "material.%s", k < HV_COLOUR_SLOTS ? hv_colour_map_resin(map, k) : core);
        s = hv_volume_grid_set(vol, name, "occupancy", val + (size_t)k * n, n);
    }
    static const char *const k_want[5] = {"colour.r", "colour.g", "colour.b", "colour.mask", "colour.depth"};
    for (int k = 0; k < 5 && s == HV_OK; ++k) s = hv_volume_grid_set(vol, k_want[k], "occupancy", val + (size_t)(nmat + k) * n, n);
    if (s == HV_OK) s = hv_material_table_store(vol, tab);
    if (s == HV_OK) s = record(vol, map, depth, core, core_rgba, gives, share);
    hv_material_table_destroy(tab);
done:
    free(val);
    free(cache);
    bvh_free(&tree);
    free(xyz);
    return s;
}

hv_status hv_colour_paint_text(hv_volume *vol, const hv_mesh *mesh, hv_colour_map *map, double depth, const char *core)
{
    if (!hv_mesh_has_colour(mesh))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: no colour to paint (no texture, vertex, face or material colour)",
                            *hv_mesh_name(mesh) ? hv_mesh_name(mesh) : "the mesh");
    float rgba[4];
    if (core && hv_color_parse(core, rgba) == HV_OK) return hv_colour_paint(vol, mesh, map, depth, NULL, rgba);
    hv_error_clear();
    return hv_colour_paint(vol, mesh, map, depth, core ? core : hv_colour_map_resin(map, HV_COLOUR_W), NULL);
}

int hv_colour_depth_grid(const hv_volume *model, float *depth_mm)
{
    *depth_mm = 0;
    int g = hv_volume_grid_find(model, "colour.depth");
    const char *text = hv_volume_meta_string(model, "hovox.colour.json");
    if (g < 0 || hv_volume_grid_type(model, g) != HV_GRID_FLOAT || !text) return -1;
    json_t *doc = NULL;
    double d = 0;
    hv_status s = hv_json_parse(text, strlen(text), "hovox.colour.json", &doc);
    if (s == HV_OK) s = hv_json_get_number(doc, "depth_mm", "hovox.colour.json", &d);
    json_decref(doc);
    if (s != HV_OK) hv_error_clear(); /* a damaged record: hv_colour_map_for_model reports it */
    if (s != HV_OK || !(d > 0) || !isfinite(d)) return -1;
    *depth_mm = (float)d;
    return g;
}
