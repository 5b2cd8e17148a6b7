/* tests/support/support.h - helpers shared by the unit tests: where the shared material is,
 * temporary directories, running a command and capturing its output, box topologies. */
#ifndef HOVOX_TEST_SUPPORT_H
#define HOVOX_TEST_SUPPORT_H

#include <stddef.h>
#include <stdint.h>

#include "hovox/generate.h"
#include "hovox/material.h"
#include "hovox/mesh.h"
#include "hovox/volume.h"

/* Directory holding meshes/ ($HOVOX_SHARED, default "tests/data": copies of the shared meshes). */
const char *t_shared(void);
/* "<shared>/meshes/<name>" in a static buffer. */
const char *t_mesh_path(const char *name);
/* A fresh temporary directory (removed at exit). */
const char *t_tmpdir(void);
/* "<tmpdir>/<name>" in a rotating static buffer. */
const char *t_tmpfile(const char *name);
/* Run a shell command; returns its exit status and, if out != NULL, its stdout (malloc'd). */
int t_run(const char *cmd, char **out);
/* Does a file exist? */
int t_exists(const char *path);
/* A whole file, NUL-terminated (malloc'd; *len gets its size when len != NULL); asserts. */
char *t_slurp(const char *path, size_t *len);
/* The closed box [lo, hi] (hv_generate_box), and the cube [lo, hi]^3; assert. */
hv_mesh *t_box_mesh(const double lo[3], const double hi[3]);
hv_mesh *t_cube_mesh(double lo, double hi);
/* The cube [0, size]^3 with every corner coloured opaque red (0xFF0000FF, RGBA); asserts. */
hv_mesh *t_red_cube(double size);
/* m voxelized in cubic voxels of `voxel` mm (hv_voxelize, its other options the defaults); asserts. */
hv_volume *t_voxelize(const hv_mesh *m, double voxel);
/* An object of `materials` materials over m's occupancy voxelized at `voxel` mm (hv_object_create;
 * the voxels are the object's to keep); asserts. */
hv_object *t_object_of(const hv_mesh *m, double voxel, int materials);
/* The cube [0, size]^3 (12 facets, two to a face) painted for real: facet f coloured rgba[f % n],
 * voxelized at 0.5 mm and painted 1 mm deep over an Agilus30 core through the default colour map
 * (hv_colour_paint). *mesh gets the cube (the caller destroys both); asserts. */
hv_volume *t_painted_cube(double size, const uint32_t *rgba, size_t n, hv_mesh **mesh);
/* Activate the voxels [lo, hi] (inclusive index box) of v, leaf block by leaf block. Returns
 * hv_volume_topology_add's status (HV_ERR_NOMEM when the blocks cannot be listed). */
hv_status t_add_box(hv_volume *v, const int lo[3], const int hi[3]);

/* A grey or indexed PNG read by libpng (an independent reader), one byte per pixel; free px. */
typedef struct t_png {
    int w, h, bit_depth, color_type;
    uint8_t *px; /* one byte per pixel: grey value or palette index */
    int npal;
    uint8_t pal[3 * 256];
    unsigned long ppm_x, ppm_y;
} t_png;
void t_png_load(const char *path, t_png *im);
/* The same from a PNG in memory. */
void t_png_load_mem(const uint8_t *data, size_t size, t_png *im);
/* Pixels of 1, 2 or 4 bits (w x h, one a byte) in PNG's packing, the first pixel in the most
 * significant bits, rows `stride` bytes apart (padding zeroed). */
void t_pack_rows(const uint8_t *px, int w, int h, int depth, uint8_t *rows, size_t stride);
/* A PNG chunk (length, type, n bytes of data, CRC) written at b; returns its size (12 + n). For tests
 * that build damaged PNGs by hand. */
size_t t_png_chunk(uint8_t *b, const char *type, const uint8_t *data, uint32_t n);

/* A ZIP archive at path holding n entries (name, data, size), as a hand-made 3MF package; asserts. */
void t_zip_write(const char *path, const char *const *names, const void *const *data, const size_t *sizes, int n);

#endif
