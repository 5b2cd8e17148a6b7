/* src/threemf/boundary.c - the exact boundary of a set of voxels as a closed, oriented, 2-manifold
 * triangle mesh: the faces between occupied and unoccupied voxels, with one vertex per voxel
 * corner and sheet of surface through it (so a 3MF consumer sees geometry equal to the voxels,
 * and no edge is shared by four triangles where voxels touch along an edge). */
#include <stdlib.h>
#include <string.h>

#include "threemf_internal.h"

/* ---- which faces meet at a corner ------------------------------------------------------------
 * The 8 voxels around a corner form a 2x2x2 block; voxel (bx, by, bz) of it is bit bx + 2 by + 4 bz
 * of the block's configuration. Its 12 inner faces are numbered a * 4 + b[a+1] + 2 b[a+2] (a the
 * normal axis, b the bits of the two voxels along the other axes, which they share). Around each
 * of the 6 half-edges leaving the corner lie 4 voxels and 4 faces; the faces of the surface among
 * them pair up, and the pairs chain into cycles around the corner: one vertex per cycle. With 2
 * faces they pair with each other. With 4 (two occupied voxels P, Q meeting only along the edge)
 * each occupied voxel's two faces pair (the voxels are apart there), unless P and Q are joined by
 * occupied voxels around both ends of the edge: then the surface would pinch at the edge (its
 * cycles at both ends pass the edge twice, and no vertex copies can make it a 2-manifold), so
 * there the faces pair around each empty voxel instead (the voxels are joined across the edge).
 * Both ends of an edge decide alike, so the pairs of an edge are the same at both its vertices. */
static int face_id(int a, const int b[3]) { return a * 4 + b[(a + 1) % 3] + 2 * b[(a + 2) % 3]; }

static int uf_find(int *p, int x)
{
    while (p[x] != x) x = p[x] = p[p[x]];
    return x;
}

static void uf_join(int *p, int x, int y)
{
    x = uf_find(p, x);
    y = uf_find(p, y);
    if (x != y) p[y] = x;
}

typedef struct bctx {
    const hv_volume *vol;
    const uint64_t *occ;
    uint64_t *counts; /* per leaf, for the count */
} bctx;

static int occ_at(const bctx *c, hv_accessor *acc, int32_t i, int32_t j, int32_t k)
{
    int64_t l = hv_accessor_leaf(acc, i, j, k);
    return l >= 0 && HV_BIT_GET(c->occ + 8 * (size_t)l, HV_LEAF_OFFSET(i, j, k));
}

/* P (ring place r0) and Q (r0 + 2) joined through a layer of the 4 voxels beside the ring. */
static int joined(const int *layer, int r0) { return layer[r0] && layer[r0 + 2] && (layer[(r0 + 1) & 3] || layer[(r0 + 3) & 3]); }

/* The cycle (0, 1, ...) of the surface at corner C that face `face` of the block belongs to. */
static int corner_cycle(const bctx *c, hv_accessor *acc, const int32_t C[3], int cfg, int face)
{
    int boundary[12] = {0}, parent[12];
    for (int f = 0; f < 12; ++f) parent[f] = f;
    for (int v = 0; v < 8; ++v) { /* faces between v and its neighbour across each axis */
        int b[3] = {v & 1, (v >> 1) & 1, (v >> 2) & 1};
        for (int a = 0; a < 3; ++a)
            if (((cfg >> v) & 1) != ((cfg >> (v ^ (1 << a))) & 1)) boundary[face_id(a, b)] = 1;
    }
    static const int rp[4] = {0, 1, 1, 0}, rq[4] = {0, 0, 1, 1};
    for (int e = 0; e < 3; ++e)
        for (int side = 0; side < 2; ++side) {
            int p = (e + 1) % 3, q = (e + 2) % 3;
            /* the ring of 4 voxels around the half-edge, in order, and the faces between them */
            int ring[4], near[4], faces[4];
            for (int r = 0; r < 4; ++r) {
                int b[3];
                b[e] = side;
                b[p] = rp[r];
                b[q] = rq[r];
                ring[r] = (cfg >> (b[0] + 2 * b[1] + 4 * b[2])) & 1;
                b[e] = 1 - side;
                near[r] = (cfg >> (b[0] + 2 * b[1] + 4 * b[2])) & 1;
                int r1 = (r + 1) & 3, axis = rp[r] != rp[r1] ? p : q;
                b[e] = side;
                faces[r] = face_id(axis, b);
            }
            int n = 0, first = -1, second = -1;
            for (int r = 0; r < 4; ++r)
                if (boundary[faces[r]]) {
                    if (n == 0) first = faces[r];
                    else second = faces[r];
                    ++n;
                }
            if (n == 2) {
                uf_join(parent, first, second);
                continue;
            }
            if (n != 4) continue;
            int r0 = ring[0] ? 0 : 1; /* the occupied ones are r0 and r0 + 2 */
            int flip = 0;
            if (joined(near, r0)) { /* and at the far end of the edge? */
                int far[4];
                for (int r = 0; r < 4; ++r) {
                    int32_t v[3];
                    v[e] = C[e] + (side ? 1 : -2);
                    v[p] = C[p] + rp[r] - 1;
                    v[q] = C[q] + rq[r] - 1;
                    far[r] = occ_at(c, acc, v[0], v[1], v[2]);
                }
                flip = joined(far, r0);
            }
            if (!flip) { /* each occupied voxel's two faces */
                uf_join(parent, faces[(r0 + 3) & 3], faces[r0]);
                uf_join(parent, faces[r0 + 1], faces[r0 + 2]);
            } else { /* each empty voxel's two faces */
                uf_join(parent, faces[r0], faces[r0 + 1]);
                uf_join(parent, faces[r0 + 2], faces[(r0 + 3) & 3]);
            }
        }
    int id[12], next = 0, root = uf_find(parent, face);
    for (int f = 0; f < 12; ++f) id[f] = -1;
    for (int f = 0; f < 12; ++f) {
        if (!boundary[f]) continue;
        int rf = uf_find(parent, f);
        if (id[rf] < 0) id[rf] = next++;
    }
    return boundary[face] ? id[root] : -1;
}

/* ---- counting ------------------------------------------------------------------------------ */

static const int k_dir[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};

static hv_status count_range(void *ctx, size_t b, size_t e, int thread)
{
    (void)thread;
    bctx *c = ctx;
    const int32_t *orig = hv_volume_leaf_origins(c->vol);
    hv_accessor acc;
    hv_accessor_init(&acc, c->vol);
    for (size_t l = b; l < e; ++l) {
        const uint64_t *w = c->occ + 8 * l;
        uint64_t n = 0;
        for (unsigned q = 0; q < 8; ++q)
            for (uint64_t bits = w[q]; bits; bits &= bits - 1) {
                unsigned o = q * 64 + (unsigned)__builtin_ctzll(bits);
                int32_t i = orig[3 * l] + (int32_t)(o >> 6), j = orig[3 * l + 1] + (int32_t)((o >> 3) & 7),
                        k = orig[3 * l + 2] + (int32_t)(o & 7);
                for (int d = 0; d < 6; ++d)
                    n += !occ_at(c, &acc, i + k_dir[d][0], j + k_dir[d][1], k + k_dir[d][2]);
            }
        c->counts[l] = n;
    }
    return HV_OK;
}

hv_status tmf_boundary_count(const hv_volume *vol, const uint64_t *occ, uint64_t *quads, const hv_progress *progress)
{
    *quads = 0;
    size_t nl = hv_volume_leaf_count(vol);
    bctx c = {vol, occ, hv_calloc(nl ? nl : 1, sizeof(uint64_t))};
    if (!c.counts) return HV_ERR_NOMEM;
    hv_status s = hv_parallel_for(nl, 16, count_range, &c, progress, "export mesh");
    for (size_t l = 0; l < nl && s == HV_OK; ++l) *quads += c.counts[l];
    free(c.counts);
    return s;
}

uint64_t tmf_boundary_bytes(uint64_t quads)
{
    /* every vertex lies on at least 3 quads of its sheet (a cube's corner), each quad has 4:
     * at most 4/3 vertices per quad; a vertex costs its corner (12 bytes) and hash slots (2 x 4) */
    uint64_t v = quads / 3 * 4 + 16;
    return quads * 2 * 3 * sizeof(uint32_t) + v * (3 * sizeof(int32_t) + 1) + 4 * v * sizeof(uint32_t);
}

/* ---- the mesh ------------------------------------------------------------------------------- */

typedef struct vmap {
    uint32_t *slot; /* vertex id + 1, 0: empty */
    size_t cap;     /* power of two */
    uint8_t *comp;  /* per vertex */
    size_t vcap;
} vmap;

static uint64_t vhash(int32_t a, int32_t b, int32_t c, int comp)
{
    uint64_t h = (uint64_t)(uint32_t)a * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t)(uint32_t)b * 0xC2B2AE3D27D4EB4Full;
    h ^= (uint64_t)(uint32_t)c * 0x165667B19E3779F9ull;
    h ^= (uint64_t)comp * 0x27D4EB2F165667C5ull;
    return h ^ (h >> 31);
}

static hv_status vmap_grow(vmap *vm, tmf_boundary *m, size_t cap)
{
    uint32_t *slot = hv_calloc(cap, sizeof *slot);
    if (!slot) return HV_ERR_NOMEM;
    for (size_t v = 0; v < m->nv; ++v) {
        const int32_t *p = m->corner + 3 * v;
        size_t i = (size_t)vhash(p[0], p[1], p[2], vm->comp[v]) & (cap - 1);
        while (slot[i]) i = (i + 1) & (cap - 1);
        slot[i] = (uint32_t)v + 1;
    }
    free(vm->slot);
    vm->slot = slot;
    vm->cap = cap;
    return HV_OK;
}

static hv_status vertex_id(vmap *vm, tmf_boundary *m, int32_t a, int32_t b, int32_t c, int comp, uint32_t *id)
{
    size_t i = (size_t)vhash(a, b, c, comp) & (vm->cap - 1);
    for (; vm->slot[i]; i = (i + 1) & (vm->cap - 1)) {
        uint32_t v = vm->slot[i] - 1;
        const int32_t *p = m->corner + 3 * (size_t)v;
        if (p[0] == a && p[1] == b && p[2] == c && vm->comp[v] == comp) {
            *id = v;
            return HV_OK;
        }
    }
    if (m->nv >= UINT32_MAX - 1)
        return hv_error_set(HV_ERR_LIMIT, "export: the boundary mesh would have more than 2^32 vertices");
    if (m->nv == vm->vcap) {
        size_t ncap = vm->vcap ? vm->vcap * 2 : 1024;
        int32_t *cor = hv_realloc(m->corner, ncap * 3 * sizeof *cor);
        if (!cor) return HV_ERR_NOMEM;
        m->corner = cor;
        uint8_t *cm = hv_realloc(vm->comp, ncap);
        if (!cm) return HV_ERR_NOMEM;
        vm->comp = cm;
        vm->vcap = ncap;
    }
    size_t v = m->nv++;
    m->corner[3 * v] = a;
    m->corner[3 * v + 1] = b;
    m->corner[3 * v + 2] = c;
    vm->comp[v] = (uint8_t)comp;
    vm->slot[i] = (uint32_t)v + 1;
    *id = (uint32_t)v;
    if (2 * m->nv > vm->cap) return vmap_grow(vm, m, vm->cap * 2);
    return HV_OK;
}

void tmf_boundary_free(tmf_boundary *m)
{
    free(m->corner);
    free(m->tri);
    memset(m, 0, sizeof *m);
}

hv_status tmf_boundary_build(const hv_volume *vol, const uint64_t *occ, uint64_t quads, tmf_boundary *m,
                             const hv_progress *progress)
{
    memset(m, 0, sizeof *m);
    if (quads > (uint64_t)SIZE_MAX / 48)
        return hv_error_set(HV_ERR_LIMIT, "export: %llu boundary faces", (unsigned long long)quads);
    vmap vm = {NULL, 0, NULL, 0};
    size_t cap = 1024;
    while (cap < (quads / 3 * 4 + 16) * 2 && cap < ((size_t)1 << 62)) cap *= 2;
    m->tri = hv_malloc_array((size_t)quads ? (size_t)quads * 2 : 1, 3 * sizeof(uint32_t));
    hv_status s = m->tri ? vmap_grow(&vm, m, cap) : HV_ERR_NOMEM;
    bctx c = {vol, occ, NULL};
    const int32_t *orig = hv_volume_leaf_origins(vol);
    size_t nl = hv_volume_leaf_count(vol);
    hv_accessor acc;
    hv_accessor_init(&acc, vol);
    uint64_t made = 0;
    for (size_t l = 0; l < nl && s == HV_OK; ++l) {
        if ((l & 255) == 0 && (s = hv_progress_report(progress, "export mesh", (double)l / (double)nl)) != HV_OK) break;
        const uint64_t *w = occ + 8 * l;
        for (unsigned q = 0; q < 8 && s == HV_OK; ++q)
            for (uint64_t bits = w[q]; bits && s == HV_OK; bits &= bits - 1) {
                unsigned o = q * 64 + (unsigned)__builtin_ctzll(bits);
                int32_t v[3] = {orig[3 * l] + (int32_t)(o >> 6), orig[3 * l + 1] + (int32_t)((o >> 3) & 7),
                                orig[3 * l + 2] + (int32_t)(o & 7)};
                int open = 0;
                for (int d = 0; d < 6; ++d)
                    if (!occ_at(&c, &acc, v[0] + k_dir[d][0], v[1] + k_dir[d][1], v[2] + k_dir[d][2])) open |= 1 << d;
                if (!open) continue;
                /* the 3x3x3 neighbourhood: bit (dx+1) + 3 (dy+1) + 9 (dz+1) */
                uint32_t nb = 0;
                for (int dz = -1; dz <= 1; ++dz)
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx)
                            if (occ_at(&c, &acc, v[0] + dx, v[1] + dy, v[2] + dz))
                                nb |= 1u << ((dx + 1) + 3 * (dy + 1) + 9 * (dz + 1));
                for (int d = 0; d < 6 && s == HV_OK; ++d) {
                    if (!(open >> d & 1)) continue;
                    int a = d >> 1, plus = d & 1, u = (a + 1) % 3, vv = (a + 2) % 3;
                    /* the quad's corners, counter-clockwise seen from outside (e_u x e_v = e_a) */
                    int cu[4], cv[4];
                    static const int pu[4] = {0, 1, 1, 0}, pv[4] = {0, 0, 1, 1};
                    for (int r = 0; r < 4; ++r) {
                        int rr = plus ? r : (4 - r) & 3; /* reversed for the face on the - side */
                        cu[r] = pu[rr];
                        cv[r] = pv[rr];
                    }
                    uint32_t id[4];
                    for (int r = 0; r < 4 && s == HV_OK; ++r) {
                        int cc[3]; /* the corner, relative to the voxel's lowest corner */
                        cc[a] = plus;
                        cc[u] = cu[r];
                        cc[vv] = cv[r];
                        int cfg = 0;
                        for (int bb = 0; bb < 8; ++bb) {
                            int ox = cc[0] + (bb & 1) - 1, oy = cc[1] + ((bb >> 1) & 1) - 1,
                                oz = cc[2] + ((bb >> 2) & 1) - 1;
                            cfg |= (int)((nb >> ((ox + 1) + 3 * (oy + 1) + 9 * (oz + 1))) & 1u) << bb;
                        }
                        int bv[3] = {1 - cc[0], 1 - cc[1], 1 - cc[2]}; /* the voxel's place in the block */
                        int32_t corner[3] = {v[0] + cc[0], v[1] + cc[1], v[2] + cc[2]};
                        int comp = corner_cycle(&c, &acc, corner, cfg, face_id(a, bv));
                        if (comp < 0) {
                            s = hv_error_set(HV_ERR_INTERNAL, "export: boundary face without a corner sheet");
                            break;
                        }
                        s = vertex_id(&vm, m, v[0] + cc[0], v[1] + cc[1], v[2] + cc[2], comp, &id[r]);
                    }
                    if (s != HV_OK) break;
                    if (made >= quads) {
                        s = hv_error_set(HV_ERR_INTERNAL, "export: more boundary faces than counted");
                        break;
                    }
                    uint32_t *t = m->tri + 6 * made++;
                    t[0] = id[0], t[1] = id[1], t[2] = id[2];
                    t[3] = id[0], t[4] = id[2], t[5] = id[3];
                }
            }
    }
    if (s == HV_OK && made != quads)
        s = hv_error_set(HV_ERR_INTERNAL, "export: %llu boundary faces, %llu counted", (unsigned long long)made,
                         (unsigned long long)quads);
    m->nt = (size_t)made * 2;
    free(vm.slot);
    free(vm.comp);
    if (s == HV_OK) s = hv_progress_report(progress, "export mesh", 1.0);
    return s;
}
