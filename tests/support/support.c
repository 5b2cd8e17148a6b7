/* tests/support/support.c - see support.h. */
#include <png.h>
#include <zip.h>
#include <zlib.h>
#include <criterion/criterion.h>

#include "support.h"

#include "hovox/colour.h"
#include "hovox/voxelize.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

const char *t_shared(void)
{
    const char *s = getenv("HOVOX_SHARED");
    return s && *s ? s : "tests/data";
}

const char *t_mesh_path(const char *name)
{
    static char buf[4][1024];
    static int k;
    char *b = buf[k++ & 3];
    snprintf(b, sizeof buf[0], "%s/meshes/%s", t_shared(), name);
    return b;
}

static char g_tmp[256];

static void cleanup(void)
{
    if (g_tmp[0]) {
        char cmd[300];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", g_tmp);
        if (system(cmd) != 0) { /* nothing to do */ }
    }
}

const char *t_tmpdir(void)
{
    if (!g_tmp[0]) {
        snprintf(g_tmp, sizeof g_tmp, "/tmp/hovox-test-XXXXXX");
        if (!mkdtemp(g_tmp)) abort();
        atexit(cleanup);
    }
    return g_tmp;
}

const char *t_tmpfile(const char *name)
{
    static char buf[8][512];
    static int k;
    char *b = buf[k++ & 7];
    snprintf(b, sizeof buf[0], "%s/%s", t_tmpdir(), name);
    return b;
}

int t_run(const char *cmd, char **out)
{
    FILE *p = popen(cmd, "r");
    if (!p) return -1;
    size_t cap = 4096, len = 0;
    char *buf = malloc(cap);
    size_t n;
    while (buf && (n = fread(buf + len, 1, cap - len - 1, p)) > 0) {
        len += n;
        if (cap - len < 2) {
            cap *= 2;
            buf = realloc(buf, cap);
        }
    }
    if (buf) buf[len] = '\0';
    int st = pclose(p);
    if (out) *out = buf;
    else free(buf);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

int t_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

char *t_slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f, "%s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    cr_assert_not_null(s);
    cr_assert_eq(fread(s, 1, (size_t)n, f), (size_t)n, "%s: short read", path);
    s[n] = '\0';
    fclose(f);
    if (len) *len = (size_t)n;
    return s;
}

hv_mesh *t_box_mesh(const double lo[3], const double hi[3])
{
    hv_mesh *m = NULL;
    cr_assert_eq(hv_generate_box(lo, hi, &m), HV_OK, "%s", hv_last_error());
    return m;
}

hv_mesh *t_cube_mesh(double lo, double hi)
{
    double a[3] = {lo, lo, lo}, b[3] = {hi, hi, hi};
    return t_box_mesh(a, b);
}

hv_mesh *t_red_cube(double size)
{
    hv_mesh *m = t_cube_mesh(0, size);
    size_t nf = hv_mesh_facet_count(m);
    uint32_t *c = malloc(3 * nf * sizeof *c);
    cr_assert(c != NULL);
    for (size_t i = 0; i < 3 * nf; ++i) c[i] = 0xFF0000FFu;
    cr_assert_eq(hv_mesh_set_corner_colours(m, c), HV_OK);
    free(c);
    return m;
}

hv_volume *t_voxelize(const hv_mesh *m, double voxel)
{
    hv_voxelize_options o;
    hv_voxelize_options_init(&o);
    o.voxel_size[0] = o.voxel_size[1] = o.voxel_size[2] = voxel;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &o, &v), HV_OK, "%s", hv_last_error());
    return v;
}

hv_object *t_object_of(const hv_mesh *m, double voxel, int materials)
{
    hv_volume *v = t_voxelize(m, voxel);
    hv_object *obj = NULL;
    cr_assert_eq(hv_object_create(v, "occupancy", materials, &obj), HV_OK, "%s", hv_last_error());
    hv_volume_destroy(v);
    return obj;
}

hv_volume *t_painted_cube(double size, const uint32_t *rgba, size_t n, hv_mesh **mesh)
{
    hv_mesh *m = t_cube_mesh(0, size);
    size_t nf = hv_mesh_facet_count(m);
    uint32_t *c = malloc(3 * nf * sizeof *c);
    cr_assert(c != NULL);
    for (size_t f = 0; f < nf; ++f) c[3 * f] = c[3 * f + 1] = c[3 * f + 2] = rgba[f % n];
    cr_assert_eq(hv_mesh_set_corner_colours(m, c), HV_OK);
    free(c);
    hv_volume *v = t_voxelize(m, 0.5);
    hv_colour_map *map = NULL;
    cr_assert_eq(hv_colour_map_create(NULL, &map), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_colour_paint(v, m, map, 1.0, "Agilus30", NULL), HV_OK, "%s", hv_last_error());
    hv_colour_map_destroy(map);
    *mesh = m;
    return v;
}

hv_status t_add_box(hv_volume *v, const int lo[3], const int hi[3])
{
    size_t cap = 64, n = 0;
    int32_t *o = malloc(cap * 3 * sizeof *o);
    uint64_t *m = malloc(cap * 8 * sizeof *m);
    for (int bx = lo[0] & ~7; o && m && bx <= hi[0]; bx += 8)
        for (int by = lo[1] & ~7; o && m && by <= hi[1]; by += 8)
            for (int bz = lo[2] & ~7; o && m && bz <= hi[2]; bz += 8) {
                if (n == cap) {
                    cap *= 2;
                    int32_t *o2 = realloc(o, cap * 3 * sizeof *o);
                    if (o2) o = o2;
                    uint64_t *m2 = o2 ? realloc(m, cap * 8 * sizeof *m) : NULL;
                    if (m2) m = m2;
                    if (!o2 || !m2) {
                        free(o);
                        free(m);
                        return HV_ERR_NOMEM;
                    }
                }
                memset(m + 8 * n, 0, 8 * sizeof *m);
                for (int x = 0; x < 8; ++x)
                    for (int y = 0; y < 8; ++y)
                        for (int z = 0; z < 8; ++z) {
                            int p[3] = {bx + x, by + y, bz + z};
                            if (p[0] < lo[0] || p[0] > hi[0] || p[1] < lo[1] || p[1] > hi[1] ||
                                p[2] < lo[2] || p[2] > hi[2])
                                continue;
                            unsigned off = HV_LEAF_OFFSET(x, y, z);
                            m[8 * n + off / 64] |= 1ull << (off % 64);
                        }
                o[3 * n] = bx;
                o[3 * n + 1] = by;
                o[3 * n + 2] = bz;
                ++n;
            }
    hv_status s = o && m ? hv_volume_topology_add(v, n, o, m) : HV_ERR_NOMEM;
    free(o);
    free(m);
    return s;
}

/* libpng reads the file or the buffer; `what` names it in failures */
static void png_read_all(FILE *fp, const char *what, t_png *im)
{
    memset(im, 0, sizeof *im);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    cr_assert(!setjmp(png_jmpbuf(png)), "libpng failed on %s", what);
    png_init_io(png, fp);
    png_read_info(png, info);
    im->w = (int)png_get_image_width(png, info);
    im->h = (int)png_get_image_height(png, info);
    im->bit_depth = png_get_bit_depth(png, info);
    im->color_type = png_get_color_type(png, info);
    cr_assert(im->color_type == PNG_COLOR_TYPE_GRAY || im->color_type == PNG_COLOR_TYPE_PALETTE, "%s: colour type %d",
              what, im->color_type);
    png_colorp pal;
    if (png_get_PLTE(png, info, &pal, &im->npal))
        for (int i = 0; i < im->npal; ++i) {
            im->pal[3 * i] = pal[i].red;
            im->pal[3 * i + 1] = pal[i].green;
            im->pal[3 * i + 2] = pal[i].blue;
        }
    png_uint_32 rx, ry;
    int unit;
    if (png_get_pHYs(png, info, &rx, &ry, &unit) && unit == PNG_RESOLUTION_METER) {
        im->ppm_x = rx;
        im->ppm_y = ry;
    }
    if (im->bit_depth < 8) png_set_packing(png);
    png_read_update_info(png, info);
    im->px = malloc((size_t)im->w * im->h);
    for (int y = 0; y < im->h; ++y) png_read_row(png, im->px + (size_t)y * im->w, NULL);
    png_read_end(png, NULL);
    png_destroy_read_struct(&png, &info, NULL);
}

void t_png_load(const char *path, t_png *im)
{
    FILE *fp = fopen(path, "rb");
    cr_assert(fp, "cannot open %s", path);
    png_read_all(fp, path, im);
    fclose(fp);
}

void t_png_load_mem(const uint8_t *data, size_t size, t_png *im)
{
    FILE *fp = fmemopen((void *)data, size, "rb");
    cr_assert(fp, "fmemopen");
    png_read_all(fp, "a PNG in memory", im);
    fclose(fp);
}

void t_pack_rows(const uint8_t *px, int w, int h, int depth, uint8_t *rows, size_t stride)
{
    int per = 8 / depth;
    for (int r = 0; r < h; ++r) {
        uint8_t *o = rows + (size_t)r * stride;
        memset(o, 0, stride);
        for (int c = 0; c < w; ++c)
            o[c / per] |= (uint8_t)(px[(size_t)r * (size_t)w + (size_t)c] << (8 - depth * (c % per + 1)));
    }
}

size_t t_png_chunk(uint8_t *b, const char *type, const uint8_t *data, uint32_t n)
{
    b[0] = (uint8_t)(n >> 24), b[1] = (uint8_t)(n >> 16), b[2] = (uint8_t)(n >> 8), b[3] = (uint8_t)n;
    memcpy(b + 4, type, 4);
    if (n) memcpy(b + 8, data, n);
    uLong crc = crc32(crc32(0, Z_NULL, 0), b + 4, n + 4);
    b[8 + n] = (uint8_t)(crc >> 24), b[9 + n] = (uint8_t)(crc >> 16), b[10 + n] = (uint8_t)(crc >> 8),
    b[11 + n] = (uint8_t)crc;
    return 12 + n;
}

void t_zip_write(const char *path, const char *const *names, const void *const *data, const size_t *sizes, int n)
{
    int err = 0;
    zip_t *za = zip_open(path, ZIP_CREATE | ZIP_TRUNCATE, &err);
    cr_assert_not_null(za, "%s: cannot make a zip (%d)", path, err);
    for (int i = 0; i < n; ++i) {
        zip_source_t *src = zip_source_buffer(za, data[i], sizes[i], 0);
        cr_assert(src && zip_file_add(za, names[i], src, ZIP_FL_OVERWRITE) >= 0, "%s: %s", path, names[i]);
    }
    cr_assert_eq(zip_close(za), 0, "%s", path);
}
