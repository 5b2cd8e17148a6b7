/* src/mesh/appearance.c - a mesh's colour (hovox/mesh.h "appearance"): corner colours, textures
 * and corner texture coordinates, carried through extract, join and transform, and the colour of
 * a point on a facet (bilinear texture sampling with the 3MF tile styles, 3MF core spec 1.3 /
 * materials extension 1.2 "Texture 2D": wrap, mirror, clamp, none). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "mesh_internal.h"

void hv_mesh_appearance_free(hv_mesh *m)
{
    for (size_t i = 0; i < m->ntex; ++i) {
        free((char *)m->tex[i].name);
        free((uint8_t *)m->tex[i].rgba);
        free((uint8_t *)m->tex[i].icc);
    }
    free(m->tex);
    free(m->corner_rgba);
    free(m->corner_uv);
    free(m->facet_tex);
    m->tex = NULL;
    m->ntex = 0;
    m->corner_rgba = NULL;
    m->corner_uv = NULL;
    m->facet_tex = NULL;
}

hv_status hv_mesh_set_corner_colours(hv_mesh *m, const uint32_t *rgba)
{
    uint32_t *c = NULL;
    if (rgba) {
        c = hv_malloc_array(m->nf, 3 * sizeof *c);
        if (!c) return HV_ERR_NOMEM;
        memcpy(c, rgba, m->nf * 3 * sizeof *c);
    }
    free(m->corner_rgba);
    m->corner_rgba = c;
    return HV_OK;
}

const uint32_t *hv_mesh_corner_colours(const hv_mesh *m) { return m->corner_rgba; }

hv_status hv_mesh_add_texture(hv_mesh *m, const char *name, const uint8_t *rgba, uint32_t width,
                              uint32_t height, hv_tile tile_u, hv_tile tile_v, hv_filter filter,
                              int32_t *index)
{
    const char *what = name ? name : "texture";
    if (!rgba || width == 0 || height == 0)
        return hv_error_set(HV_ERR_INVALID, "%s: %s: texture of %u x %u pixels", hv_mesh_name(m),
                            what, width, height);
    if ((unsigned)tile_u > HV_TILE_NONE || (unsigned)tile_v > HV_TILE_NONE ||
        (unsigned)filter > HV_FILTER_NEAREST)
        return hv_error_set(HV_ERR_INVALID, "%s: %s: tile style or filter out of range",
                            hv_mesh_name(m), what);
    if (m->ntex >= (size_t)INT32_MAX)
        return hv_error_set(HV_ERR_LIMIT, "%s: more than %d textures", hv_mesh_name(m), INT32_MAX);
    size_t bytes = (size_t)width * height;
    if (bytes > SIZE_MAX / 4 / 2)
        return hv_error_set(HV_ERR_INVALID, "%s: %s: texture of %u x %u pixels is too large",
                            hv_mesh_name(m), what, width, height);
    bytes *= 4;
    hv_mesh_texture *t = hv_realloc(m->tex, (m->ntex + 1) * sizeof *t);
    if (!t) return HV_ERR_NOMEM;
    m->tex = t;
    char *nm = hv_strdup(name ? name : "");
    uint8_t *px = hv_malloc(bytes);
    if (!nm || !px) {
        free(nm);
        free(px);
        return HV_ERR_NOMEM;
    }
    memcpy(px, rgba, bytes);
    t[m->ntex] = (hv_mesh_texture){nm, px, width, height, tile_u, tile_v, filter, NULL, 0};
    if (index) *index = (int32_t)m->ntex;
    m->ntex++;
    return HV_OK;
}

size_t hv_mesh_texture_count(const hv_mesh *m) { return m->ntex; }

hv_status hv_mesh_texture_set_icc(hv_mesh *m, size_t i, const void *icc, size_t size)
{
    if (i >= m->ntex) return hv_error_set(HV_ERR_INVALID, "%s: texture %zu out of range (%zu)", hv_mesh_name(m), i, m->ntex);
    uint8_t *c = NULL;
    if (icc && size) {
        if (!(c = hv_malloc(size))) return HV_ERR_NOMEM;
        memcpy(c, icc, size);
    }
    free((uint8_t *)m->tex[i].icc);
    m->tex[i].icc = c;
    m->tex[i].icc_size = c ? size : 0;
    return HV_OK;
}
const hv_mesh_texture *hv_mesh_texture_at(const hv_mesh *m, size_t i)
{
    return i < m->ntex ? &m->tex[i] : NULL;
}

hv_status hv_mesh_set_corner_uvs(hv_mesh *m, const float *uv, const int32_t *facet_texture)
{
    if (!uv) {
        free(m->corner_uv);
        free(m->facet_tex);
        m->corner_uv = NULL;
        m->facet_tex = NULL;
        return HV_OK;
    }
    if (!facet_texture)
        return hv_error_set(HV_ERR_INVALID, "%s: texture coordinates without facet textures",
                            hv_mesh_name(m));
    for (size_t f = 0; f < m->nf; ++f) {
        int32_t t = facet_texture[f];
        if (t == -1 || t == HV_MESH_NO_COLOUR) continue;
        if (t < 0 || (size_t)t >= m->ntex)
            return hv_error_set(HV_ERR_INVALID, "%s: facet %zu: texture %d out of range (%zu)",
                                hv_mesh_name(m), f, (int)t, m->ntex);
        const hv_mesh_texture *tx = &m->tex[t];
        for (int k = 0; k < 3; ++k) {
            float u = uv[6 * f + 2 * (size_t)k], v = uv[6 * f + 2 * (size_t)k + 1];
            if (!isfinite(u) || !isfinite(v) ||
                (tx->tile_u == HV_TILE_NONE && !(u >= 0 && u <= 1)) ||
                (tx->tile_v == HV_TILE_NONE && !(v >= 0 && v <= 1)))
                return hv_error_set(HV_ERR_BAD_INPUT,
                                    "%s: facet %zu: texture coordinate (%g, %g) %s", hv_mesh_name(m),
                                    f, (double)u, (double)v,
                                    !isfinite(u) || !isfinite(v)
                                        ? "is not finite"
                                        : "outside [0, 1] and its texture does not tile");
        }
    }
    float *c = hv_malloc_array(m->nf, 6 * sizeof *c);
    int32_t *ft = hv_malloc_array(m->nf, sizeof *ft);
    if (!c || !ft) {
        free(c);
        free(ft);
        return HV_ERR_NOMEM;
    }
    memcpy(c, uv, m->nf * 6 * sizeof *c);
    memcpy(ft, facet_texture, m->nf * sizeof *ft);
    free(m->corner_uv);
    free(m->facet_tex);
    m->corner_uv = c;
    m->facet_tex = ft;
    return HV_OK;
}

const float *hv_mesh_corner_uvs(const hv_mesh *m) { return m->corner_uv; }
const int32_t *hv_mesh_facet_textures(const hv_mesh *m) { return m->facet_tex; }

/* Does facet f have a colour (the rule of hv_mesh_colour_at)? */
static int facet_coloured(const hv_mesh *m, size_t f)
{
    int32_t t = m->facet_tex ? m->facet_tex[f] : -1;
    if (t != -1) return t >= 0;
    if (m->corner_rgba) return 1;
    return m->facet_mat && m->facet_mat[f] >= 0 && m->mats[m->facet_mat[f]].has_color;
}

int hv_mesh_has_colour(const hv_mesh *m)
{
    for (size_t f = 0; f < m->nf; ++f)
        if (facet_coloured(m, f)) return 1;
    return 0;
}

/* ---- sampling -------------------------------------------------------------------------------- */

/* A texel coordinate (pixel centres at i + 0.5 in units of pixels) folded into [0, n) by the tile
 * style. */
static double tile_coord(double x, uint32_t n, hv_tile tile)
{
    double w = (double)n;
    switch (tile) {
    case HV_TILE_WRAP:
        x = fmod(x, w);
        if (x < 0) x += w;
        break;
    case HV_TILE_MIRROR: {
        double p = fmod(x, 2 * w);
        if (p < 0) p += 2 * w;
        x = p < w ? p : 2 * w - p;
        break;
    }
    default: /* clamp; none has been checked to lie inside */
        break;
    }
    return x;
}

/* Index of a texel column/row: clamped for clamp/none, wrapped or mirrored otherwise. */
static uint32_t texel_index(long i, uint32_t n, hv_tile tile)
{
    long w = (long)n;
    if (tile == HV_TILE_WRAP) {
        i %= w;
        if (i < 0) i += w;
    } else if (tile == HV_TILE_MIRROR) {
        long p = i % (2 * w);
        if (p < 0) p += 2 * w;
        i = p < w ? p : 2 * w - 1 - p;
    } else {
        i = i < 0 ? 0 : i >= w ? w - 1 : i;
    }
    return (uint32_t)i;
}

static void texel(const hv_mesh_texture *t, long x, long y, float out[4])
{
    uint32_t i = texel_index(x, t->width, t->tile_u), j = texel_index(y, t->height, t->tile_v);
    const uint8_t *p = t->rgba + 4 * ((size_t)j * t->width + i);
    for (int c = 0; c < 4; ++c) out[c] = (float)p[c] / 255.0f;
}

static void sample(const hv_mesh_texture *t, double u, double v, float out[4])
{
    /* u = 0 is the left edge, v = 1 the top edge (row 0) */
    double x = tile_coord(u * t->width, t->width, t->tile_u);
    double y = tile_coord((1.0 - v) * t->height, t->height, t->tile_v);
    if (t->filter == HV_FILTER_NEAREST) {
        texel(t, (long)floor(x), (long)floor(y), out);
        return;
    }
    double fx = x - 0.5, fy = y - 0.5;
    long x0 = (long)floor(fx), y0 = (long)floor(fy);
    float ax = (float)(fx - (double)x0), ay = (float)(fy - (double)y0);
    float a[4], b[4], c[4], d[4];
    texel(t, x0, y0, a);
    texel(t, x0 + 1, y0, b);
    texel(t, x0, y0 + 1, c);
    texel(t, x0 + 1, y0 + 1, d);
    for (int k = 0; k < 4; ++k)
        out[k] = (a[k] * (1 - ax) + b[k] * ax) * (1 - ay) + (c[k] * (1 - ax) + d[k] * ax) * ay;
}

int hv_mesh_colour_at(const hv_mesh *m, size_t f, const double bary[3], float rgba[4])
{
    if (f >= m->nf) return 0;
    int32_t t = m->facet_tex ? m->facet_tex[f] : -1;
    if (t == HV_MESH_NO_COLOUR) return 0;
    if (t >= 0) {
        const float *uv = m->corner_uv + 6 * f;
        double u = bary[0] * uv[0] + bary[1] * uv[2] + bary[2] * uv[4];
        double v = bary[0] * uv[1] + bary[1] * uv[3] + bary[2] * uv[5];
        sample(&m->tex[t], u, v, rgba);
        return 1;
    }
    if (m->corner_rgba) {
        const uint32_t *c = m->corner_rgba + 3 * f;
        for (int k = 0; k < 4; ++k) {
            int sh = 24 - 8 * k;
            double s = bary[0] * ((c[0] >> sh) & 255) + bary[1] * ((c[1] >> sh) & 255) +
                       bary[2] * ((c[2] >> sh) & 255);
            rgba[k] = (float)(s / 255.0);
        }
        return 1;
    }
    if (m->facet_mat && m->facet_mat[f] >= 0 && m->mats[m->facet_mat[f]].has_color) {
        uint32_t c = m->mats[m->facet_mat[f]].rgba;
        for (int k = 0; k < 4; ++k) rgba[k] = (float)((c >> (24 - 8 * k)) & 255) / 255.0f;
        return 1;
    }
    return 0;
}

/* ---- carried through extract, transform and join --------------------------------------------- */

/* Append src's textures to dst. */
static hv_status copy_textures(hv_mesh *dst, const hv_mesh *src)
{
    for (size_t i = 0; i < src->ntex; ++i) {
        const hv_mesh_texture *t = &src->tex[i];
        hv_status s = hv_mesh_add_texture(dst, t->name, t->rgba, t->width, t->height, t->tile_u,
                                          t->tile_v, t->filter, NULL);
        if (s == HV_OK && t->icc) s = hv_mesh_texture_set_icc(dst, dst->ntex - 1, t->icc, t->icc_size);
        if (s != HV_OK) return s;
    }
    return HV_OK;
}

hv_status hv_mesh_appearance_copy(hv_mesh *dst, const hv_mesh *src, size_t first, size_t n, int swap)
{
    hv_status s = copy_textures(dst, src);
    if (s != HV_OK) return s;
    if (src->corner_rgba) {
        dst->corner_rgba = hv_malloc_array(n, 3 * sizeof *dst->corner_rgba);
        if (!dst->corner_rgba) return HV_ERR_NOMEM;
        for (size_t f = 0; f < n; ++f)
            for (int k = 0; k < 3; ++k) {
                int kk = swap && k > 0 ? 3 - k : k;
                dst->corner_rgba[3 * f + (size_t)k] = src->corner_rgba[3 * (first + f) + (size_t)kk];
            }
    }
    if (src->corner_uv) {
        dst->corner_uv = hv_malloc_array(n, 6 * sizeof *dst->corner_uv);
        dst->facet_tex = hv_malloc_array(n, sizeof *dst->facet_tex);
        if (!dst->corner_uv || !dst->facet_tex) return HV_ERR_NOMEM;
        memcpy(dst->facet_tex, src->facet_tex + first, n * sizeof *dst->facet_tex);
        for (size_t f = 0; f < n; ++f)
            for (int k = 0; k < 3; ++k) {
                int kk = swap && k > 0 ? 3 - k : k;
                memcpy(dst->corner_uv + 6 * f + 2 * (size_t)k,
                       src->corner_uv + 6 * (first + f) + 2 * (size_t)kk, 2 * sizeof(float));
            }
    }
    return HV_OK;
}

hv_status hv_mesh_appearance_join(hv_mesh *dst, const hv_mesh *const *parts, size_t n)
{
    int any_rgba = 0, any_uv = 0, any_colour = 0;
    for (size_t i = 0; i < n; ++i) {
        any_rgba |= parts[i]->corner_rgba != NULL;
        any_uv |= parts[i]->corner_uv != NULL;
        any_colour |= hv_mesh_has_colour(parts[i]);
    }
    if (!any_colour) return HV_OK;
    /* Joined facets lose their materials (hv_mesh_join names one per part), so a part coloured
     * by its materials keeps its colour as corner colours. */
    int need_rgba = any_rgba;
    for (size_t i = 0; i < n && !need_rgba; ++i)
        need_rgba = !parts[i]->corner_rgba && hv_mesh_has_colour(parts[i]) &&
                    parts[i]->facet_mat != NULL;
    if (need_rgba) {
        dst->corner_rgba = hv_malloc_array(dst->nf, 3 * sizeof *dst->corner_rgba);
        if (!dst->corner_rgba) return HV_ERR_NOMEM;
    }
    int need_uv = any_uv || need_rgba; /* the uv table marks the facets without colour */
    if (need_uv) {
        dst->corner_uv = hv_calloc(dst->nf, 6 * sizeof *dst->corner_uv);
        dst->facet_tex = hv_malloc_array(dst->nf, sizeof *dst->facet_tex);
        if (!dst->corner_uv || !dst->facet_tex) return HV_ERR_NOMEM;
    }
    size_t at = 0;
    for (size_t i = 0; i < n; ++i) {
        const hv_mesh *p = parts[i];
        int32_t base = (int32_t)dst->ntex;
        hv_status s = copy_textures(dst, p);
        if (s != HV_OK) return s;
        for (size_t f = 0; f < p->nf; ++f, ++at) {
            int32_t t = p->facet_tex ? p->facet_tex[f] : -1;
            if (need_uv) {
                if (p->corner_uv) memcpy(dst->corner_uv + 6 * at, p->corner_uv + 6 * f, 6 * sizeof(float));
                dst->facet_tex[at] = t >= 0 ? t + base : t;
            }
            if (!need_rgba) continue;
            uint32_t *c = dst->corner_rgba + 3 * at;
            if (p->corner_rgba) {
                memcpy(c, p->corner_rgba + 3 * f, 3 * sizeof *c);
                continue;
            }
            float col[4];
            double one[3] = {1, 0, 0};
            if (t < 0 && hv_mesh_colour_at(p, f, one, col)) { /* a material's flat colour */
                uint32_t v = 0;
                for (int k = 0; k < 4; ++k) v = v << 8 | (uint32_t)lrintf(col[k] * 255.0f);
                c[0] = c[1] = c[2] = v;
            } else {
                c[0] = c[1] = c[2] = 0;
                if (t == -1) dst->facet_tex[at] = HV_MESH_NO_COLOUR;
            }
        }
    }
    return HV_OK;
}

/* ---- a body's colour given by the user ------------------------------------------------------- */

/* Facet f's flat colour from its material as 0xRRGGBBAA; 0 with *none set when it has none. */
static uint32_t material_colour(const hv_mesh *m, size_t f, int *none)
{
    float col[4];
    double one[3] = {1, 0, 0};
    *none = !hv_mesh_colour_at(m, f, one, col);
    uint32_t v = 0;
    for (int k = 0; k < 4 && !*none; ++k) v = v << 8 | (uint32_t)lrintf(col[k] * 255.0f);
    return v;
}

hv_status hv_mesh_body_colour_set(hv_mesh *m, const char *body, uint32_t rgba)
{
    size_t b = 0;
    hv_status s = hv_mesh_body_index(m, body, &b);
    if (s != HV_OK) return s;
    const hv_mesh_body *bd = hv_mesh_body_at(m, b);
    uint32_t *c = hv_malloc_array(m->nf, 3 * sizeof *c);
    float *uv = hv_calloc(m->nf, 6 * sizeof *uv);
    int32_t *ft = hv_malloc_array(m->nf, sizeof *ft);
    if (!c || !uv || !ft) {
        free(c);
        free(uv);
        free(ft);
        return HV_ERR_NOMEM;
    }
    if (m->corner_uv) memcpy(uv, m->corner_uv, m->nf * 6 * sizeof *uv);
    /* Corner colours now hold every flat colour: the other facets' material colours move into
     * them, facets without any are marked HV_MESH_NO_COLOUR, textured facets keep their texture. */
    for (size_t f = 0; f < m->nf; ++f) {
        int32_t t = m->facet_tex ? m->facet_tex[f] : -1;
        uint32_t *cf = c + 3 * f;
        if (f >= bd->first_facet && f - bd->first_facet < bd->facet_count) {
            cf[0] = cf[1] = cf[2] = rgba;
            ft[f] = -1;
            continue;
        }
        ft[f] = t;
        if (m->corner_rgba) {
            memcpy(cf, m->corner_rgba + 3 * f, 3 * sizeof *cf);
            continue;
        }
        int none = 1;
        cf[0] = cf[1] = cf[2] = t == -1 ? material_colour(m, f, &none) : 0;
        if (t == -1 && none) ft[f] = HV_MESH_NO_COLOUR;
    }
    free(m->corner_rgba);
    free(m->corner_uv);
    free(m->facet_tex);
    m->corner_rgba = c;
    m->corner_uv = uv;
    m->facet_tex = ft;
    m->bodies[b].coloured = 1; /* the user's colour: the body rule paints it */
    return HV_OK;
}
