/* renderer/render_internal.h - the renderer's private structures: the scene (per-voxel colour,
 * occupancy and gradient in 9^3 bricks over a two-level block table, for empty-space skipping
 * and hash-free sampling) and the camera. Not part of the public API. */
#ifndef HOVOX_RENDER_INTERNAL_H
#define HOVOX_RENDER_INTERNAL_H

#include <stdatomic.h>
#include <stdint.h>

#include "hovox/material.h"
#include "hovox/render.h"

/* One voxel of a brick, 8 bytes: colour and alpha of its composition (0 when unoccupied, so a
 * plain trilinear sum is already the occupancy-weighted sum), occupancy 0/255, and the smoothed
 * occupancy gradient (scene.c) biased by 128 (each component in [-127, 127]). */
typedef struct rvox {
    uint8_t r, g, b, a;
    uint8_t occ, gx, gy, gz;
} rvox;

/* A brick covers the 8^3 voxels of block B plus a one-voxel apron on the + sides, so the eight
 * trilinear corners of any point whose floor lies in B are in one brick. Bricks exist for every
 * block B such that B + {0,1}^3 holds an occupied voxel: elsewhere the coverage is exactly 0. */
#define RB_DIM 9
#define RB_VOX (RB_DIM * RB_DIM * RB_DIM)
#define RB_INDEX(x, y, z) (((x) * RB_DIM + (y)) * RB_DIM + (z))
#define RC_WORDS 16

/* Brick kinds: inside a solid (all 9^3 voxels occupied, zero gradient) the coverage is 1
 * everywhere; if the colour is the same too, every sample is the same and a run of them
 * composites in closed form. */
enum { RB_GENERAL = 0, RB_SOLID = 1, RB_UNIFORM = 2 };

/* Block table page: the 8^3 blocks of one 64^3-voxel macro cell. */
typedef struct rpage {
    int32_t brick[512]; /* brick index or -1 */
    int32_t occ[512];   /* index into the occupied-leaf list or -1 (used while building) */
} rpage;

#define RP_INDEX(x, y, z) ((((x) & 7) << 6) | (((y) & 7) << 3) | ((z) & 7))

/* An occupied leaf of the model: its voxels where "occupancy" holds. */
typedef struct r_occ {
    size_t leaf;     /* volume leaf number */
    int32_t blk[3];  /* block coordinates */
    int full;        /* all 512 voxels occupied */
    uint64_t mask[8];
} r_occ;

struct hv_render_scene {
    hv_transform xf;
    int materials;      /* coloured materials (0: grey occupancy-only) */
    uint64_t occupied;  /* occupied voxels */
    int empty;
    int32_t lo[3], hi[3]; /* inclusive index bbox of occupied voxels */
    /* macro grid: mdims cells from macro coordinate mlo; top[] holds a page index or -1 */
    int32_t mlo[3], mdims[3];
    int32_t *top;
    rpage *pages;
    size_t npages;
    rvox *bricks; /* nbricks slots of RB_VOX voxels */
    /* per slot, RC_WORDS words: bit n (n = HV_LEAF_OFFSET(x, y, z) of the cell whose corners are
     * voxels (x..x+1, y..y+1, z..z+1) of the brick) of words 0-7 set when all eight corners are
     * unoccupied (the coverage there is exactly 0), of words 8-15 when all are occupied with a
     * zero gradient (a sample there is a solid brick's sample) */
    uint64_t *cells;
    int32_t *brick_block; /* 3 block coordinates per brick */
    uint8_t *brick_kind;  /* RB_GENERAL, RB_SOLID or RB_UNIFORM, once filled */
    int16_t *brick_alpha; /* the alpha all occupied voxels of the brick share, or -1 */
    size_t nbricks;
    /* Bricks are filled from the model on first touch (scene.c, r_brick_fill): brick_slot[b] is
     * the slot of brick b in bricks[] once filled, -1 before, -2 while a thread fills it; slots
     * are handed out in fill order, so the memory touched is what the rays reached. A scene
     * built eagerly has every brick filled (slot b) and no model. */
    _Atomic int32_t *brick_slot;
    atomic_size_t nslots;
    const hv_volume *vol; /* the model, while bricks remain unfilled */
    r_occ *occ;           /* occupied leaves, indexed by rpage.occ */
    size_t nocc;
    int grids[HV_MAX_MATERIALS];
    float colour[HV_MAX_MATERIALS][4];
    int paint[4];  /* a painted model's grids colour.r, .g, .b, .mask (hovox/colour.h) */
    int painted;   /* all four are there: voxels show the colour asked for */
};

/* Fill brick b (or wait for the thread filling it); returns its slot. */
int32_t r_brick_fill(const hv_render_scene *s, int32_t b);

/* Slot of brick b (voxels s->bricks + slot * RB_VOX, cells s->cells + slot * RC_WORDS), filled
 * on first use; its kind is then s->brick_kind[b], its alpha s->brick_alpha[b]. */
static inline size_t r_brick_slot(const hv_render_scene *s, int32_t b)
{
    int32_t slot = atomic_load_explicit(&s->brick_slot[b], memory_order_acquire);
    if (slot < 0) slot = r_brick_fill(s, b);
    return (size_t)slot;
}

/* floor(a / 2^s) for negative a too */
static inline int32_t r_floor_shift(int32_t a, int s)
{
    return a >= 0 ? a >> s : -((-a + (1 << s) - 1) >> s);
}

/* Brick of block (bx,by,bz), or NULL. */
static inline const rvox *r_brick(const hv_render_scene *s, int32_t bx, int32_t by, int32_t bz)
{
    int32_t mx = r_floor_shift(bx, 3) - s->mlo[0], my = r_floor_shift(by, 3) - s->mlo[1],
            mz = r_floor_shift(bz, 3) - s->mlo[2];
    if (mx < 0 || my < 0 || mz < 0 || mx >= s->mdims[0] || my >= s->mdims[1] || mz >= s->mdims[2])
        return NULL;
    int32_t p = s->top[((int64_t)mx * s->mdims[1] + my) * s->mdims[2] + mz];
    if (p < 0) return NULL;
    int32_t b = s->pages[p].brick[RP_INDEX(bx, by, bz)];
    return b < 0 ? NULL : s->bricks + r_brick_slot(s, b) * RB_VOX;
}

/* Nonzero: the ray caster's general variant, not the one for this machine's instruction set
 * (raycast.c; the tests check that both give the same pixels). */
extern int r_render_base;

/* ---- camera ----------------------------------------------------------------------------- */

typedef struct rcam {
    double eye[3];          /* perspective: centre of projection; ortho: on the start plane */
    double fwd[3], right[3], up[3]; /* orthonormal */
    int ortho;
    double half_w, half_h;  /* perspective: tangents of the half angles; ortho: world half sizes */
    int width, height;
} rcam;

/* Set up the camera of `opt` for scene `s` (fitting when asked). Errors: HV_ERR_INVALID. */
hv_status r_camera_setup(const hv_render_scene *s, const hv_render_options *opt, rcam *cam);
/* World ray through continuous image position (x, y) in pixels (0,0 = top-left corner):
 * origin o, unit direction d. */
void r_camera_ray(const rcam *cam, double x, double y, double o[3], double d[3]);

/* A rectangle {x0, y0, x1, y1} of continuous image positions outside which every ray of the
 * camera misses the world box [lo, hi]; 0 when there is none to give (perspective with the box
 * reaching beside or behind the eye). */
int r_camera_footprint(const rcam *cam, const double lo[3], const double hi[3], double rect[4]);

/* The world bounding box corners of a scene (occupied voxel cells). */
void r_scene_box(const hv_render_scene *s, double lo[3], double hi[3]);

#endif
