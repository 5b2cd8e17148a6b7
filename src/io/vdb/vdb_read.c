/* volumes/vdb_read.c - hovox's own reader for the OpenVDB files it writes, so that loading a
 * model does not load OpenVDB (the bridge plugin's start-up alone is 35 ms: Debian's libopenvdb
 * binds its 64,000 symbols at load). Anything else is left to the bridge (volume.c falls back).
 *
 * The format, as OpenVDB 10 writes it (openvdb/io/Archive.cc, GridDescriptor.cc, Compression.h
 * and .cc, tree/RootNode.h, InternalNode.h, LeafNode.h, LeafNodeBool.h, math/Maps.h), all
 * little-endian:
 *   header     int64 magic 0x56444220, uint32 file version (222..224 here), uint32 library
 *              major and minor, uint8 "has grid offsets" (1 here), 36-byte UUID text
 *              (8-4-4-4-12 hex digits: OpenVDB refuses a file whose UUID is not);
 *   metadata   int32 count, then per entry: string key, string type name, uint32 size, value
 *              (a string is uint32 length + bytes);
 *   grids      int32 count, then per grid: descriptor (unique name, type name with a
 *              "_HalfFloat" suffix when stored as halves, instance parent, int64 grid, block
 *              and end positions), then at the grid position: uint32 compression flags (zip 1,
 *              active mask 2, blosc 4), the grid's metadata, the transform (map type name, then
 *              for (Uniform)ScaleTranslateMap translation and scale and three derived vectors,
 *              six Vec3d), the topology up to the block position, the leaf buffers up to the
 *              end position;
 *   topology   int32 buffer count 1; the root's background, uint32 tile and child counts,
 *              tiles (coordinates, value, active byte), children (coordinates, node); an
 *              internal node: child mask, value mask, its tile values (compressed values,
 *              below), its children in mask order; a leaf: its value mask;
 *   buffers    per leaf in tree order: a float leaf's value mask and compressed values; a bool
 *              leaf's value mask, origin and value mask of 512 bits;
 *   compressed values: int8 code; for codes 2, 4, 5 one or two inactive values (4 bytes even
 *              for halves); for codes 3, 4, 5 a selection mask; then the values - only the
 *              active ones when the active-mask flag is set and the code is not 6 - as 2-byte
 *              halves or 4-byte floats, in a chunk: with zip or blosc an int64 n, then n
 *              compressed bytes (n > 0) or -n raw bytes; without, the raw bytes. No values
 *              stored as halves: no chunk at all (HalfWriter).
 * Every read is bounded by the file and every count checked; nothing is trusted. */
#include <blosc.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "core/internal.h"
#include "volumes/volume_internal.h"
#include "vdb_internal.h"

enum { C_ZIP = 1, C_MASK = 2, C_BLOSC = 4 };
enum { V_MIN = 222, V_MAX = 224 }; /* node-mask compression .. multi-pass I/O */
enum { DECLINE = 1 };              /* internal: leave the file to OpenVDB */

/* ---- reading the file: bounded cursors --------------------------------------------------- */

/* A cursor on the file for the header and descriptors (small reads). */
typedef struct fcur {
    int fd;
    uint64_t size, at;
    int bad;
} fcur;

static void fget(fcur *c, void *dst, size_t n)
{
    if (c->bad || n > c->size - c->at) {
        c->bad = 1;
        memset(dst, 0, n);
        return;
    }
    unsigned char *p = dst;
    for (size_t done = 0; done < n;) {
        ssize_t r = pread(c->fd, p + done, n - done, (off_t)(c->at + done));
        if (r <= 0) {
            if (r < 0 && errno == EINTR) continue;
            c->bad = 1;
            memset(dst, 0, n);
            return;
        }
        done += (size_t)r;
    }
    c->at += n;
}

static uint32_t fu32(fcur *c)
{
    unsigned char b[4];
    fget(c, b, 4);
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static int64_t fi64(fcur *c)
{
    uint64_t lo = fu32(c), hi = fu32(c);
    return (int64_t)(lo | hi << 32);
}

/* A string of at most `max` bytes with no NUL in it, as a C string (NULL: bad or no memory,
 * *nomem says which). */
static char *fstr(fcur *c, uint32_t max, int *nomem)
{
    uint32_t n = fu32(c);
    if (c->bad || n > max || n > c->size - c->at) {
        c->bad = 1;
        return NULL;
    }
    char *s = hv_malloc((size_t)n + 1);
    if (!s) {
        *nomem = 1;
        return NULL;
    }
    fget(c, s, n);
    s[n] = 0;
    if (c->bad || memchr(s, 0, n)) {
        free(s);
        c->bad = 1;
        return NULL;
    }
    return s;
}

/* A cursor on bytes in memory (a grid's topology or buffers). */
typedef struct mcur {
    const unsigned char *p;
    size_t n, at;
    int bad;
} mcur;

static const unsigned char *mtake(mcur *c, size_t n)
{
    if (c->bad || n > c->n - c->at) {
        c->bad = 1;
        return NULL;
    }
    const unsigned char *p = c->p + c->at;
    c->at += n;
    return p;
}

static uint32_t get_u32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static uint32_t mu32(mcur *c)
{
    const unsigned char *b = mtake(c, 4);
    return b ? get_u32(b) : 0;
}

static int64_t mi64(mcur *c)
{
    const unsigned char *b = mtake(c, 8);
    return b ? (int64_t)((uint64_t)get_u32(b) | (uint64_t)get_u32(b + 4) << 32) : 0;
}

static double mf64(mcur *c)
{
    const unsigned char *b = mtake(c, 8);
    double d = 0;
    if (b) memcpy(&d, b, 8); /* x86-64 and every platform hovox builds on are little-endian */
    return d;
}

/* The string at the cursor equals `s`. */
static int mstr_is(mcur *c, const char *s)
{
    uint32_t n = mu32(c);
    const unsigned char *b = mtake(c, n);
    return b && n == strlen(s) && memcmp(b, s, n) == 0;
}

static void *read_range(int fd, uint64_t off, uint64_t n, int *nomem)
{
    unsigned char *buf = hv_malloc(n ? (size_t)n : 1);
    if (!buf) {
        *nomem = 1;
        return NULL;
    }
    for (uint64_t done = 0; done < n;) {
        ssize_t r = pread(fd, buf + done, (size_t)(n - done), (off_t)(off + done));
        if (r <= 0) {
            if (r < 0 && errno == EINTR) continue;
            free(buf);
            return NULL;
        }
        done += (uint64_t)r;
    }
    return buf;
}

/* ---- values ------------------------------------------------------------------------------ */

static float g_half[65536];
static pthread_once_t g_half_once = PTHREAD_ONCE_INIT;

/* IEEE binary16 to binary32, exactly (what Imath's half does). */
static void half_table(void)
{
    for (uint32_t h = 0; h < 65536; ++h) {
        uint32_t sign = (h >> 15) << 31, e = (h >> 10) & 31, m = h & 1023, f;
        if (e == 0 && m == 0) {
            f = sign;
        } else if (e == 0) { /* subnormal: normalise */
            int k = -1;
            do {
                ++k;
                m <<= 1;
            } while (!(m & 1024));
            f = sign | (uint32_t)(112 - k) << 23 | (m & 1023) << 13;
        } else if (e == 31) {
            f = sign | 0x7f800000u | m << 13;
        } else {
            f = sign | (e + 112) << 23 | m << 13;
        }
        memcpy(&g_half[h], &f, 4);
    }
}

/* One chunk of `bytes` bytes at the cursor into dst (NULL: skipped), as Compression.h's
 * readData: with zip or blosc an int64 n, then n compressed bytes or -n raw ones. */
static int chunk(mcur *c, uint32_t comp, void *dst, size_t bytes)
{
    if (!(comp & (C_ZIP | C_BLOSC))) {
        const unsigned char *b = mtake(c, bytes);
        if (b && dst) memcpy(dst, b, bytes);
        return b != NULL || bytes == 0;
    }
    int64_t n = mi64(c);
    if (c->bad) return 0;
    if (n <= 0) {
        if (0 - (uint64_t)n != bytes) return 0; /* -n without overflow at INT64_MIN */
        const unsigned char *b = mtake(c, bytes);
        if (b && dst) memcpy(dst, b, bytes);
        return b != NULL || bytes == 0;
    }
    const unsigned char *b = mtake(c, (size_t)n);
    if (!b) return 0;
    if (comp & C_BLOSC) { /* blosc stores even 0 bytes with its 16-byte header */
        size_t nbytes = 0;
        if (blosc_cbuffer_validate(b, (size_t)n, &nbytes) != 0 || nbytes != bytes) return 0;
        return !dst || bytes == 0 || blosc_decompress_ctx(b, dst, bytes, 1) == (int)bytes;
    }
    if (bytes == 0) return 0; /* zip writes 0 bytes raw */
    if (!dst) return 1;
    uLongf len = (uLongf)bytes;
    return uncompress(dst, &len, b, (uLong)n) == Z_OK && len == bytes;
}

static unsigned popcount_words(const unsigned char *mask, size_t words)
{
    unsigned c = 0;
    for (size_t w = 0; w < words; ++w) {
        uint64_t x;
        memcpy(&x, mask + 8 * w, 8);
        c += (unsigned)__builtin_popcountll(x);
    }
    return c;
}

/* Skip compressed values: `count` entries of `esize` bytes on disk, the node's value mask having
 * `active` bits, a selection mask of count/8 bytes. With `scratch` (count * esize bytes) the
 * values are decompressed there, so that a damaged chunk is found as OpenVDB would find it. */
static int skip_values(mcur *c, uint32_t comp, size_t count, unsigned active, size_t esize, size_t vsize,
                       void *scratch)
{
    const unsigned char *code = mtake(c, 1);
    if (!code || *code > 6) return 0;
    if (*code == 2 || *code == 4 || *code == 5) mtake(c, *code == 5 ? 2 * vsize : vsize);
    if (*code >= 3 && *code <= 5) mtake(c, count / 8);
    size_t n = (comp & C_MASK) && *code != 6 ? active : count;
    /* HalfWriter writes nothing at all for no values (a float chunk of 0 bytes still has its
     * length, and with blosc a header) */
    if (esize == 2 && n == 0) return !c->bad;
    return !c->bad && chunk(c, comp, scratch, n * esize);
}

/* ---- a grid ------------------------------------------------------------------------------ */

typedef struct grid_in {
    char *name;
    int is_bool, half;
    int64_t pos, block, end;
    int32_t index; /* hovox.index, INT32_MAX without */
    int name_ok;   /* its "name" entry is a string equal to the descriptor's name */
    int saved_half; /* "_HalfFloat" on its type (g->half: a float grid stored so) */
    uint32_t comp;
    double voxel[3], origin[3];
    unsigned char *bytes; /* [pos, end) of the file */
    /* leaves in tree order */
    size_t nleaves, lcap;
    int32_t *origins;
    uint64_t *masks;
    size_t *records; /* offset of each leaf's buffer record in bytes */
} grid_in;

static void grid_free(grid_in *g)
{
    free(g->name);
    free(g->bytes);
    free(g->origins);
    free(g->masks);
    free(g->records);
}

static int add_leaf(grid_in *g, const int32_t o[3], const unsigned char *mask, int *nomem)
{
    if (g->nleaves == g->lcap) {
        size_t cap = g->lcap ? 2 * g->lcap : 256;
        int32_t *no = realloc(g->origins, cap * 3 * sizeof *no);
        if (no) g->origins = no;
        uint64_t *nm = realloc(g->masks, cap * 8 * sizeof *nm);
        if (nm) g->masks = nm;
        if (!no || !nm) {
            *nomem = 1;
            return 0;
        }
        g->lcap = cap;
    }
    memcpy(g->origins + 3 * g->nleaves, o, 3 * sizeof *o);
    memcpy(g->masks + 8 * g->nleaves, mask, 64);
    ++g->nleaves;
    return 1;
}

/* OpenVDB's DelayedLoadMetadata ("__delayedload", per-leaf masks and compressed sizes, written
 * with float grids) as its readValue reads it: uint32 count; uint32 n and then a blosc buffer of
 * n bytes holding count mask bytes (padded with zeros to 128 bytes when shorter), or (n = 0) the
 * count bytes raw; uint32 n again, then UINT32_MAX for no sizes, a blosc buffer of count int64
 * (padded alike), or (0) those raw. OpenVDB reads what
 * it reads whatever the size before it says; a value that does not fill its size exactly is left
 * to OpenVDB. */
static int delayed_load(mcur *c, uint32_t size)
{
    if (size == 0) return 1;
    size_t start = c->at;
    uint32_t count = mu32(c);
    /* one entry per leaf, and each leaf takes 64 bytes of the grid: more is damage, and would
     * have OpenVDB (and this reader) allocate far beyond the file */
    if (count > c->n / 64 + 1) return 0;
    for (int part = 0; part < 2 && !c->bad; ++part) {
        uint32_t n = mu32(c);
        size_t each = part == 0 ? 1 : 8;
        if (part == 1 && n == UINT32_MAX) break;
        if (n == 0) {
            if ((uint64_t)count * each > c->n - c->at) return 0;
            mtake(c, (size_t)count * each);
            continue;
        }
        const unsigned char *b = mtake(c, n);
        size_t nbytes = 0;
        /* OpenVDB pads buffers under 128 bytes to 128 before compressing (StreamCompression) */
        uint64_t want = (uint64_t)count * each;
        if (!b || blosc_cbuffer_validate(b, n, &nbytes) != 0 || nbytes < 1 || !(nbytes == want || (nbytes == 128 && want <= 128)))
            return 0;
        void *tmp = hv_malloc(nbytes ? nbytes : 1);
        int ok = tmp && (nbytes == 0 || blosc_decompress_ctx(b, tmp, nbytes, 1) == (int)nbytes);
        free(tmp);
        if (!ok) return 0;
    }
    return !c->bad && c->at - start == size;
}

/* The size of a fixed-size metadata type OpenVDB registers (it reads that many bytes whatever the
 * size before the value says); 0 for string and __delayedload; -1 for a type hovox leaves to
 * OpenVDB. */
static int meta_type_size(const unsigned char *t, uint32_t n)
{
    static const struct {
        const char *name;
        int size;
    } types[] = {{"bool", 1},   {"double", 8}, {"float", 4},  {"int32", 4},  {"int64", 8},  {"vec2i", 8},
                 {"vec2s", 8},  {"vec2d", 16}, {"vec3i", 12}, {"vec3s", 12}, {"vec3d", 24}, {"vec4i", 16},
                 {"vec4s", 16}, {"vec4d", 32}, {"mat4s", 64}, {"mat4d", 128}, {"string", 0}, {"__delayedload", 0}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; ++i)
        if (strlen(types[i].name) == n && memcmp(types[i].name, t, n) == 0) return types[i].size;
    return -1;
}

/* Metadata of a grid: hovox.index and name are the entries read; every entry must be of a known
 * type and fill its size exactly. */
static int grid_meta(mcur *c, grid_in *g)
{
    enum { MAX_ENTRIES = 256 }; /* hovox's grids carry 8 */
    size_t keys[MAX_ENTRIES];   /* where each key is, to refuse one given twice */
    int32_t n = (int32_t)mu32(c);
    if (n < 0 || n > MAX_ENTRIES) return 0;
    g->name_ok = 0;
    for (int32_t i = 0; i < n && !c->bad; ++i) {
        size_t key = c->at;
        /* an empty key, or one given twice (OpenVDB's MetaMap throws on both, or on a second
         * type for it), is left to OpenVDB */
        uint32_t kn = mu32(c);
        const unsigned char *k = mtake(c, kn);
        if (!k || kn == 0) return 0;
        for (int32_t j = 0; j < i; ++j) {
            const unsigned char *o = c->p + keys[j];
            if (get_u32(o) == kn && memcmp(o + 4, k, kn) == 0) return 0;
        }
        keys[i] = key;
        c->at = key;
        int is_index = mstr_is(c, "hovox.index");
        c->at = key;
        int is_name = mstr_is(c, "name");
        uint32_t tn = mu32(c);
        const unsigned char *t = mtake(c, tn);
        uint32_t size = mu32(c);
        if (!t || c->bad) return 0;
        int fixed = meta_type_size(t, tn);
        if (fixed < 0 || (fixed > 0 && size != (uint32_t)fixed)) return 0;
        if (tn == 13 && memcmp(t, "__delayedload", 13) == 0) {
            if (!delayed_load(c, size)) return 0;
            continue;
        }
        const unsigned char *v = mtake(c, size);
        if (v && is_index) g->index = fixed == 4 && tn == 5 && memcmp(t, "int32", 5) == 0 ? (int32_t)get_u32(v) : INT32_MAX;
        if (v && is_name) g->name_ok = fixed == 0 && tn == 6 && size == strlen(g->name) && memcmp(v, g->name, size) == 0;
    }
    /* OpenVDB names a grid by its "name" entry, not by its descriptor: the two must agree */
    return !c->bad && g->name_ok;
}

/* The transform: an axis-aligned (uniform) scale and translation, positive and finite. */
static int grid_transform(mcur *c, grid_in *g)
{
    uint32_t n = mu32(c);
    const unsigned char *t = mtake(c, n);
    if (!t) return 0;
    int uniform = n == 24 && memcmp(t, "UniformScaleTranslateMap", 24) == 0;
    if (!uniform && !(n == 17 && memcmp(t, "ScaleTranslateMap", 17) == 0)) return 0;
    for (int a = 0; a < 3; ++a) g->origin[a] = mf64(c);
    for (int a = 0; a < 3; ++a) g->voxel[a] = mf64(c);
    mtake(c, 4 * 24); /* voxel size, inverse scale, its square, inverse twice the scale */
    for (int a = 0; a < 3; ++a) {
        if (!(g->voxel[a] > 0) || g->voxel[a] > 1e300 || !(g->origin[a] == g->origin[a]) ||
            g->origin[a] > 1e300 || g->origin[a] < -1e300)
            return 0;
        g->origin[a] += 0.0; /* -0 is +0, as OpenVDB's affine matrix gives it */
    }
    /* OpenVDB refuses a nearly singular map (its determinant under about 3e-15) */
    if (g->voxel[0] * g->voxel[1] * g->voxel[2] < 1e-12) return 0;
    return !c->bad;
}

#define COORD_LIMIT (1 << 30) /* the bridge refuses voxels beyond index 2^30 */

static int coord_ok(int32_t x) { return x >= -COORD_LIMIT && x <= COORD_LIMIT - 8; }

/* The first set bit at or after `from` in a mask of `bits` bits (little-endian bytes, as node
 * masks are saved), or `bits`. */
static unsigned next_bit(const unsigned char *mask, unsigned bits, unsigned from)
{
    while (from < bits) {
        uint64_t w;
        memcpy(&w, mask + (from >> 6) * 8, 8);
        w >>= from & 63;
        if (w) return from + (unsigned)__builtin_ctzll(w);
        from = (from | 63) + 1;
    }
    return bits;
}

/* An internal node of `bits` entries: its child mask (returned), its value mask (no active
 * tiles: else NULL) and its tile values, checked and skipped. */
static const unsigned char *node_header(mcur *c, uint32_t comp, unsigned bits, size_t esize, size_t vsize, void *scratch)
{
    const unsigned char *child = mtake(c, bits / 8), *value = mtake(c, bits / 8);
    if (!child || !value || popcount_words(value, bits / 64)) return NULL;
    return skip_values(c, comp, bits, 0, esize, vsize, scratch) ? child : NULL;
}

/* The topology: leaves and their masks, in tree order; no active tiles. */
static int grid_topology(mcur *c, grid_in *g, void *scratch, int *nomem)
{
    const size_t vsize = g->is_bool ? 1 : 4, esize = g->is_bool ? 1 : g->half ? 2 : 4;
    if (mu32(c) != 1) return 0; /* buffer count */
    const unsigned char *bg = mtake(c, vsize);
    if (!bg) return 0;
    for (size_t i = 0; i < vsize; ++i) /* background 0 / false: inactive values are 0 */
        if (bg[i]) return 0;
    uint32_t tiles = mu32(c), children = mu32(c);
    for (uint32_t t = 0; t < tiles && !c->bad; ++t) {
        mtake(c, 12 + vsize);
        const unsigned char *active = mtake(c, 1);
        if (!active || *active) return 0;
    }
    int32_t prev[3] = {0, 0, 0};
    for (uint32_t r = 0; r < children && !c->bad; ++r) {
        const unsigned char *k = mtake(c, 12);
        if (!k) return 0;
        int32_t ro[3] = {(int32_t)get_u32(k), (int32_t)get_u32(k + 4), (int32_t)get_u32(k + 8)};
        for (int a = 0; a < 3; ++a)
            if (ro[a] & 4095) return 0;
        if (r && hv_leaf_order(prev, ro) >= 0) return 0; /* the root's children come sorted */
        memcpy(prev, ro, sizeof prev);
        const unsigned char *child5 = node_header(c, g->comp, 32768, esize, vsize, scratch);
        if (!child5) return 0;
        for (unsigned i = next_bit(child5, 32768, 0); i < 32768; i = next_bit(child5, 32768, i + 1)) {
            int32_t io[3] = {ro[0] + (int32_t)((i >> 10) & 31) * 128, ro[1] + (int32_t)((i >> 5) & 31) * 128,
                             ro[2] + (int32_t)(i & 31) * 128};
            const unsigned char *child4 = node_header(c, g->comp, 4096, esize, vsize, scratch);
            if (!child4) return 0;
            for (unsigned j = next_bit(child4, 4096, 0); j < 4096; j = next_bit(child4, 4096, j + 1)) {
                int32_t lo[3] = {io[0] + (int32_t)((j >> 8) & 15) * 8, io[1] + (int32_t)((j >> 4) & 15) * 8,
                                 io[2] + (int32_t)(j & 15) * 8};
                const unsigned char *m = mtake(c, 64);
                if (!m || !coord_ok(lo[0]) || !coord_ok(lo[1]) || !coord_ok(lo[2])) return 0;
                if (!add_leaf(g, lo, m, nomem)) return 0;
            }
        }
    }
    return !c->bad;
}

/* The buffer records: where each leaf's starts, each mask equal to the topology's, the last
 * ending where the grid ends. */
static int grid_records(mcur *c, grid_in *g, int *nomem)
{
    g->records = hv_malloc_array(g->nleaves ? g->nleaves : 1, sizeof *g->records);
    if (!g->records) {
        *nomem = 1;
        return 0;
    }
    const size_t esize = g->half ? 2 : 4;
    for (size_t l = 0; l < g->nleaves && !c->bad; ++l) {
        g->records[l] = c->at;
        const unsigned char *m = mtake(c, 64);
        if (!m || memcmp(m, g->masks + 8 * l, 64) != 0) return 0;
        if (g->is_bool) {
            const unsigned char *o = mtake(c, 12);
            if (!o || (int32_t)get_u32(o) != g->origins[3 * l] || (int32_t)get_u32(o + 4) != g->origins[3 * l + 1] ||
                (int32_t)get_u32(o + 8) != g->origins[3 * l + 2])
                return 0;
            mtake(c, 64);
        } else if (!skip_values(c, g->comp, 512, popcount_words(m, 8), esize, 4, NULL)) {
            return 0;
        }
    }
    return !c->bad && c->at == c->n;
}

/* ---- decoding leaves, in parallel ---------------------------------------------------------- */

typedef struct decode_ctx {
    const grid_in *g;
    hv_volume *v; /* its topology is every grid's (checked) */
    int index;    /* the grid in v */
    const unsigned char *buffers; /* the grid's bytes from its block position */
    size_t nbuffers;
} decode_ctx;

static int decode_float(const grid_in *g, mcur *c, const uint64_t *mask, float *dst)
{
    mtake(c, 64);
    const unsigned char *code = mtake(c, 1);
    if (!code) return 0;
    /* inactive values, as readCompressedValues restores them (background 0: +0 or -0) */
    float in0 = *code == 0 ? 0.0f : -0.0f, in1 = 0.0f;
    if (*code == 2 || *code == 4 || *code == 5) {
        const unsigned char *b = mtake(c, *code == 5 ? 8 : 4);
        if (!b) return 0;
        memcpy(&in0, b, 4);
        if (*code == 5) memcpy(&in1, b + 4, 4);
    }
    const unsigned char *sel = *code >= 3 && *code <= 5 ? mtake(c, 64) : NULL;
    int packed = (g->comp & C_MASK) && *code != 6;
    unsigned active = 0;
    for (int w = 0; w < 8; ++w) active += (unsigned)__builtin_popcountll(mask[w]);
    size_t count = packed ? active : 512;
    float vals[512];
    uint16_t halves[512];
    if (!(g->half && count == 0) && /* see skip_values */
        !chunk(c, g->comp, g->half ? (void *)halves : (void *)vals, count * (g->half ? 2 : 4)))
        return 0;
    if (g->half)
        for (size_t i = 0; i < count; ++i) vals[i] = g_half[halves[i]];
    if (!packed) {
        memcpy(dst, vals, sizeof vals);
        return 1;
    }
    /* inactive values first, then the active ones scattered to their places */
    for (unsigned n = 0; n < 512; ++n) dst[n] = in0;
    if (sel)
        for (unsigned n = 0; n < 512; ++n)
            if (sel[n >> 3] >> (n & 7) & 1) dst[n] = in1;
    unsigned k = 0;
    for (unsigned w = 0; w < 8; ++w)
        for (uint64_t m = mask[w]; m; m &= m - 1) dst[w * 64 + (unsigned)__builtin_ctzll(m)] = vals[k++];
    return 1;
}

static hv_status decode_range(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    decode_ctx *d = vctx;
    const grid_in *g = d->g;
    for (size_t l = b; l < e; ++l) {
        size_t end = l + 1 < g->nleaves ? g->records[l + 1] : d->nbuffers;
        mcur c = {d->buffers + g->records[l], end - g->records[l], 0, 0};
        void *buf = g->is_bool ? (void *)hv_volume_leaf_bool(d->v, d->index, l) : (void *)hv_volume_leaf_float(d->v, d->index, l);
        int ok;
        if (g->is_bool) {
            mtake(&c, 64 + 12);
            const unsigned char *v = mtake(&c, 64);
            ok = v != NULL;
            if (ok) memcpy(buf, v, 64);
        } else {
            ok = decode_float(g, &c, hv_volume_leaf_mask(d->v, l), buf);
        }
        if (!ok) return HV_ERR_BAD_INPUT; /* no message: the caller declines */
    }
    return HV_OK;
}

/* ---- the file ------------------------------------------------------------------------------ */

/* The header's UUID as OpenVDB reads it (boost's operator>>): 8-4-4-4-12 hex digits, either
 * case; anything else fails the read. */
static int uuid_ok(const unsigned char *u)
{
    for (int i = 0; i < 36; ++i) {
        int dash = i == 8 || i == 13 || i == 18 || i == 23;
        unsigned char c = u[i];
        int hex = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
        if (dash ? c != '-' : !hex) return 0;
    }
    return 1;
}

static int selected(const char *name, const char *const *want, int n)
{
    if (n < 0) return 1;
    for (int i = 0; i < n; ++i) {
        size_t len = strlen(want[i]);
        if (len && want[i][len - 1] == '*' ? strncmp(name, want[i], len - 1) == 0 : strcmp(name, want[i]) == 0)
            return 1;
    }
    return 0;
}

static int index_cmp(const void *x, const void *y)
{
    const grid_in *a = *(grid_in *const *)x, *b = *(grid_in *const *)y;
    if (a->index != b->index) return a->index < b->index ? -1 : 1;
    return a->pos < b->pos ? -1 : a->pos > b->pos; /* stable: file order */
}

/* File metadata into v: strings and numbers (double, float, int32, int64), as the bridge. */
static int file_meta(fcur *c, hv_volume *v, int *nomem)
{
    int32_t n = (int32_t)fu32(c);
    if (c->bad || n < 0) return 0;
    for (int32_t i = 0; i < n; ++i) {
        char *key = fstr(c, 1u << 16, nomem), *type = key ? fstr(c, 64, nomem) : NULL;
        uint32_t size = fu32(c);
        int ok = key && type && *key && !c->bad && size <= c->size - c->at;
        /* a key given twice: OpenVDB keeps one; leave it to OpenVDB */
        double d;
        ok = ok && !hv_volume_meta_string(v, key) && !hv_volume_meta_number(v, key, &d);
        hv_status s = HV_OK;
        if (ok && strcmp(type, "string") == 0) {
            char *str = hv_malloc((size_t)size + 1);
            if (!str) *nomem = 1;
            if (str) {
                fget(c, str, size);
                str[size] = 0;
                ok = !c->bad && !memchr(str, 0, size);
                if (ok) s = hv_volume_meta_set_string(v, key, str);
                free(str);
            }
            ok = ok && str;
        } else if (ok) {
            unsigned char b[8] = {0};
            int num = (strcmp(type, "double") == 0 && size == 8) || (strcmp(type, "int64") == 0 && size == 8) ||
                      (strcmp(type, "float") == 0 && size == 4) || (strcmp(type, "int32") == 0 && size == 4);
            ok = num;
            if (ok) fget(c, b, size);
            if (ok && !c->bad) {
                int64_t i64;
                int32_t i32;
                float f;
                memcpy(&d, b, 8);
                memcpy(&i64, b, 8);
                memcpy(&i32, b, 4);
                memcpy(&f, b, 4);
                d = type[0] == 'd' ? d : type[0] == 'f' ? (double)f : strcmp(type, "int64") == 0 ? (double)i64 : (double)i32;
                s = hv_volume_meta_set_number(v, key, d);
            }
        }
        free(key);
        free(type);
        if (s == HV_ERR_NOMEM) *nomem = 1;
        if (!ok || s != HV_OK || c->bad) return 0;
    }
    return 1;
}

/* Read grid g's header, topology and buffer records from its bytes. */
static int grid_parse(grid_in *g, int *nomem)
{
    mcur c = {g->bytes, (size_t)(g->block - g->pos), 0, 0};
    g->comp = mu32(&c);
    if ((g->comp & ~7u) || (g->comp & C_ZIP && g->comp & C_BLOSC)) return 0;
    g->index = INT32_MAX;
    float *scratch = hv_malloc(32768 * sizeof *scratch); /* an internal node's tile values */
    if (!scratch) {
        *nomem = 1;
        return 0;
    }
    int ok = grid_meta(&c, g) && grid_transform(&c, g) && grid_topology(&c, g, scratch, nomem) && c.at == c.n;
    free(scratch);
    if (!ok) return 0;
    mcur b = {g->bytes + (g->block - g->pos), (size_t)(g->end - g->block), 0, 0};
    return grid_records(&b, g, nomem);
}

/* The grid descriptors: each grid follows its own, the next descriptor at the grid's end. The
 * grids `want` selects keep their names (*nsel counts them). 0 when the file is not one this
 * reader takes (OpenVDB then reads it or says what is wrong). */
static int read_descriptors(fcur *c, grid_in *grids, int ngrids, const char *const *want, int nwant, int *nsel,
                            int *nomem)
{
    int ok = 1;
    for (int i = 0; ok && i < ngrids; ++i) {
        char *name = fstr(c, 255, nomem), *type = name ? fstr(c, 64, nomem) : NULL,
             *parent = type ? fstr(c, 0, nomem) : NULL;
        int64_t pos = fi64(c), block = fi64(c), end = fi64(c);
        ok = parent && !c->bad && *name && !strchr(name, 0x1e) && pos == (int64_t)c->at && block >= pos &&
             end >= block && (uint64_t)end <= c->size;
        /* the "_HalfFloat" suffix goes with every grid saved "as half", bool ones too, whose
         * values it does not change */
        int is_float = ok && strncmp(type, "Tree_float_5_4_3", 16) == 0;
        int is_bool = ok && strncmp(type, "Tree_bool_5_4_3", 15) == 0;
        const char *rest = is_float ? type + 16 : is_bool ? type + 15 : "?";
        int is_half = strcmp(rest, "_HalfFloat") == 0;
        ok = ok && (is_float || is_bool) && (*rest == 0 || is_half);
        for (int k = 0; ok && k < i; ++k)
            if (grids[k].name && strcmp(grids[k].name, name) == 0) ok = 0; /* a name twice */
        free(type);
        free(parent);
        if (!ok) {
            free(name);
            break;
        }
        grid_in *g = &grids[i];
        g->pos = pos;
        g->block = block;
        g->end = end;
        g->is_bool = is_bool;
        g->half = is_float && is_half;
        g->saved_half = is_half; /* the bridge's half flag, for any grid type */
        if (selected(name, want, nwant)) {
            g->name = name;
            ++*nsel;
        } else {
            free(name);
            g->name = NULL;
        }
        c->at = (uint64_t)end;
    }
    return ok;
}

/* Whether the selected grids share one transform and one topology. */
static int same_lattice(grid_in *const *order, int nsel)
{
    for (int i = 1; i < nsel; ++i) {
        const grid_in *a = order[0], *b = order[i];
        int same = memcmp(a->voxel, b->voxel, sizeof a->voxel) == 0 && memcmp(a->origin, b->origin, sizeof a->origin) == 0 &&
             a->nleaves == b->nleaves &&
             (a->nleaves == 0 || (memcmp(a->origins, b->origins, 3 * a->nleaves * sizeof *a->origins) == 0 &&
                                  memcmp(a->masks, b->masks, 8 * a->nleaves * sizeof *a->masks) == 0));
        if (!same) return 0;
    }
    return 1;
}

/* The volume: the lattice, the topology, then each grid's leaves decoded. *ok = 0 when a leaf
 * does not decode (the file goes to OpenVDB, which says what is wrong). */
static hv_status fill_volume(const char *path, hv_volume *v, grid_in *const *order, int nsel, int *half, int *ok)
{
    grid_in *f = order[0];
    hv_transform xf;
    memcpy(xf.voxel, f->voxel, sizeof xf.voxel);
    memcpy(xf.origin, f->origin, sizeof xf.origin);
    hv_volume_adopt_transform(v, &xf);
    hv_status s = hv_volume_adopt_topology(v, f->nleaves, f->origins, f->masks);
    f->origins = NULL; /* the volume's now (also on failure) */
    f->masks = NULL;
    if (s != HV_OK) return s;
    size_t n = hv_volume_leaf_count(v);
    for (int i = 0; i < nsel; ++i) {
        grid_in *g = order[i];
        int index;
        if ((s = hv_volume_adopt_grid(v, g->name, g->is_bool ? HV_GRID_BOOL : HV_GRID_FLOAT, &index)) != HV_OK)
            return s;
        decode_ctx d = {g, v, index, g->bytes + (g->block - g->pos), (size_t)(g->end - g->block)};
        hv_status r = hv_parallel_for(n, 256, decode_range, &d, NULL, NULL);
        if (r == HV_ERR_CANCELLED) return hv_error_set(HV_ERR_CANCELLED, "%s: reading cancelled", path);
        if (r != HV_OK) { /* a leaf that does not decode: OpenVDB says what is wrong */
            *ok = 0;
            return HV_OK;
        }
        if (g->saved_half && strncmp(g->name, "material.", 9) == 0) *half = 1;
        free(g->bytes);
        g->bytes = NULL;
    }
    return HV_OK;
}

hv_status hv_vdb_read(const char *path, const char *const *want, int nwant, uint64_t budget, hv_volume **out,
                      int *half, int *declined)
{
    *out = NULL;
    *half = 0;
    *declined = 0;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        if (fd >= 0) close(fd);
        *declined = 1;
        return HV_OK;
    }
    pthread_once(&g_half_once, half_table);
    fcur c = {fd, (uint64_t)st.st_size, 0, 0};
    hv_status s = HV_OK;
    int nomem = 0, ok = 1, ngrids = 0, nsel = 0;
    grid_in *grids = NULL, **order = NULL;
    hv_volume *v = NULL;
    hv_transform unit = {{1, 1, 1}, {0, 0, 0}};
    if (hv_volume_create(&unit, &v) != HV_OK) {
        nomem = 1;
        goto done;
    }
    /* header */
    int64_t magic = fi64(&c);
    uint32_t version = fu32(&c);
    fu32(&c);
    fu32(&c);
    unsigned char offsets = 0, uuid[36];
    fget(&c, &offsets, 1);
    fget(&c, uuid, 36);
    ok = !c.bad && magic == 0x56444220 && version >= V_MIN && version <= V_MAX && offsets == 1 && uuid_ok(uuid);
    ok = ok && file_meta(&c, v, &nomem);
    ngrids = ok ? (int32_t)fu32(&c) : 0;
    /* hovox writes tens of grids; more (and the quadratic name check) is left to OpenVDB */
    ok = ok && !c.bad && ngrids > 0 && ngrids <= 4096 && (uint64_t)ngrids <= c.size / 16;
    if (ok && !(grids = hv_calloc((size_t)ngrids, sizeof *grids))) nomem = 1;
    if (ok && grids) ok = read_descriptors(&c, grids, ngrids, want, nwant, &nsel, &nomem);
    if (!ok || nomem) goto done;
    /* the selected grids: parsed, in hovox.index order, on one transform and one topology */
    order = hv_calloc((size_t)nsel + 1, sizeof *order);
    if (!order) {
        nomem = 1;
        goto done;
    }
    nsel = 0;
    uint64_t need = 0;
    for (int i = 0; ok && i < ngrids; ++i) {
        grid_in *g = &grids[i];
        if (!g->name) continue;
        if (hv_cancel_requested()) {
            s = hv_error_set(HV_ERR_CANCELLED, "%s: reading cancelled", path);
            goto done;
        }
        g->bytes = read_range(fd, (uint64_t)g->pos, (uint64_t)(g->end - g->pos), &nomem);
        ok = g->bytes && grid_parse(g, &nomem);
        if (ok) {
            /* the bridge's budget: what the grid takes once loaded (expanded_bytes) */
            uint64_t voxels = 0;
            for (size_t w = 0; w < 8 * g->nleaves; ++w) voxels += (uint64_t)__builtin_popcountll(g->masks[w]);
            need += ((voxels + 511) / 512 + g->nleaves) * ((g->is_bool ? 200u : 2200u) + 200u);
            ok = !budget || need <= budget;
        }
        order[nsel++] = g;
    }
    if (!ok || nomem) goto done;
    qsort(order, (size_t)nsel, sizeof *order, index_cmp);
    ok = ok && same_lattice(order, nsel);
    if (!ok) goto done;
    if (nsel) s = fill_volume(path, v, order, nsel, half, &ok);
done:
    for (int i = 0; grids && i < ngrids; ++i) grid_free(&grids[i]);
    free(grids);
    free(order);
    close(fd);
    if (nomem || s == HV_ERR_NOMEM) s = hv_error_set(HV_ERR_NOMEM, "%s: out of memory reading the file", path);
    if (s != HV_OK || !ok) {
        hv_volume_destroy(v);
        if (s == HV_OK) *declined = 1;
        return s;
    }
    *out = v;
    return HV_OK;
}
