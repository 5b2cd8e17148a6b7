/* src/io/mesh_load.c - the one mesh loader: the reader is chosen by the file's content where it
 * carries a signature (a ZIP is a 3MF package, "ply" a PLY file, a binary STL has exactly 84 + 50 n
 * bytes), else by the extension, else by the text ("solid" starts an ASCII STL, OBJ statements an
 * OBJ file); and the one mesh writer choice (OBJ or STL by extension). */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "hovox/mesh.h"
#include "io_internal.h"

typedef hv_status (*parse_fn)(const void *, size_t, const char *, hv_mesh **);

/* OBJ from a file: its mtllib libraries and their textures are read beside it. */
static hv_status parse_obj_file(const void *data, size_t size, const char *name, hv_mesh **out)
{
    return hv_obj_parse(data, size, name, 1, out);
}

static const struct {
    const char *ext;
    parse_fn parse;
} k_readers[] = {{".stl", hv_mesh_parse_stl}, {".3mf", hv_mesh_parse_3mf}, {".obj", parse_obj_file},
                 {".ply", hv_mesh_parse_ply}};
enum { R_STL, R_3MF, R_OBJ, R_PLY };

const char *hv_mesh_load_extensions(void) { return "stl, 3mf, obj, ply"; }

/* The first word of the first line that is not blank or a comment, into w (cut to cap - 1). */
static void first_word(const unsigned char *d, size_t n, char *w, size_t cap)
{
    size_t i = 0;
    if (n >= 3 && d[0] == 0xEF && d[1] == 0xBB && d[2] == 0xBF) i = 3; /* UTF-8 BOM */
    for (;;) {
        while (i < n && isspace(d[i])) ++i;
        if (i < n && d[i] == '#') {
            while (i < n && d[i] != '\n') ++i;
            continue;
        }
        break;
    }
    size_t k = 0;
    while (i < n && k + 1 < cap && !isspace(d[i])) w[k++] = (char)d[i++];
    w[k] = '\0';
}

/* The reader a signature asks for, or -1 when there is none. */
static int signature(const unsigned char *d, size_t n)
{
    if (n >= 4 && d[0] == 'P' && d[1] == 'K' && d[2] == 3 && d[3] == 4) return R_3MF;
    if (n >= 4 && memcmp(d, "ply", 3) == 0 && (d[3] == '\n' || d[3] == '\r')) return R_PLY;
    if (n >= 84) {
        uint64_t count = (uint64_t)d[80] | (uint64_t)d[81] << 8 | (uint64_t)d[82] << 16 | (uint64_t)d[83] << 24;
        if (84 + 50 * count == n) return R_STL;
    }
    return -1;
}

/* The reader the text looks written for, or -1. */
static int looks_like(const unsigned char *d, size_t n)
{
    char w[16];
    first_word(d, n < 4096 ? n : 4096, w, sizeof w);
    if (strcasecmp(w, "solid") == 0) return R_STL;
    static const char *const obj[] = {"v", "vt", "vn", "vp", "f", "o", "g", "s", "mtllib", "usemtl", "l", "p"};
    for (size_t i = 0; i < HV_COUNT(obj); ++i)
        if (strcmp(w, obj[i]) == 0) return R_OBJ;
    return -1;
}

hv_status hv_mesh_load(const char *path, hv_mesh **out)
{
    *out = NULL;
    int by_ext = -1;
    for (size_t i = 0; i < HV_COUNT(k_readers); ++i)
        if (hv_has_extension(path, k_readers[i].ext)) by_ext = (int)i;
    char *data;
    size_t size;
    hv_status s = hv_read_file(path, (size_t)1 << 40, &data, &size);
    if (s == HV_OK) hv_input_note(path);
    if (s != HV_OK) return s;
    int r = signature((const unsigned char *)data, size);
    if (r < 0) r = by_ext;
    if (r < 0) r = looks_like((const unsigned char *)data, size);
    if (r < 0) {
        /* OpenVDB's int64 magic 0x56444220: a model handed to the mesh loader is told what it is */
        int vdb = size >= 4 && memcmp(data, "\x20\x42\x44\x56", 4) == 0;
        free(data);
        if (vdb)
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: an OpenVDB model, not a mesh (meshes: %s)", path,
                                hv_mesh_load_extensions());
        const char *dot = strrchr(hv_basename(path), '.');
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: unsupported mesh format '%s' (supported: %s)", path,
                            dot ? dot + 1 : "", hv_mesh_load_extensions());
    }
    s = k_readers[r].parse(data, size, path, out);
    free(data);
    return s;
}

int hv_mesh_sniff(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return 0;
    unsigned char d[4096];
    size_t n = fread(d, 1, sizeof d, fp);
    long size = fseek(fp, 0, SEEK_END) == 0 ? ftell(fp) : -1;
    fclose(fp);
    if (n >= 4 && d[0] == 'P' && d[1] == 'K' && d[2] == 3 && d[3] == 4) return 1;
    if (n >= 4 && memcmp(d, "ply", 3) == 0 && (d[3] == '\n' || d[3] == '\r')) return 1;
    if (n >= 84 && size > 0) {
        uint64_t count = (uint64_t)d[80] | (uint64_t)d[81] << 8 | (uint64_t)d[82] << 16 | (uint64_t)d[83] << 24;
        if (84 + 50 * count == (uint64_t)size) return 1;
    }
    for (size_t i = 0; i < HV_COUNT(k_readers); ++i)
        if (hv_has_extension(path, k_readers[i].ext)) return 1;
    return looks_like(d, n) >= 0;
}

hv_status hv_mesh_save(const hv_mesh *m, const char *path, int ascii)
{
    if (hv_has_extension(path, ".obj")) return hv_mesh_write_obj(m, path);
    return hv_mesh_write_stl(m, path, ascii);
}

