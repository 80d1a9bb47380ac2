/* What the caster's files share and tests may reach: the volume's layout, one frame's view
 * constants, the producer's task format. Not part of the public API (cast.h). */
#ifndef C5_CAST_INTERNAL_H
#define C5_CAST_INTERNAL_H

#include <pthread.h>
#include <stdint.h>

#include "cast.h"

#define C5_CAST_BSIDE (C5_CAST_BRICK + 1)              /* voxels per brick side, apron included */
#define C5_CAST_BVOX (C5_CAST_BSIDE * C5_CAST_BSIDE * C5_CAST_BSIDE)
#define C5_CAST_BSTRIDE 768                            /* 729 voxels padded to 12 cache lines */
#define C5_CAST_MAX_LEVELS 16
/* Sub-bricks: each brick's 2x2x2 octants of 4^3 cells, below the octree's leaves. Their
 * emptiness lets a worker drop a zero-opacity sample for the price of its position. */
#define C5_CAST_SUB (C5_CAST_BRICK / 2)
#define C5_CAST_SUBS 8
/* Encoded normals: octahedral map, 7 bits per coordinate; one more code for "no gradient". */
#define C5_CAST_NBITS 7
#define C5_CAST_NZERO (1 << (2 * C5_CAST_NBITS))
#define C5_CAST_NCODES (C5_CAST_NZERO + 1)

struct c5_cast_volume {
    size_t dims[3];
    double spacing[3];
    int cells[3];       /* dims - 1 per axis: the sample box is [0, cells] in voxel units */
    int nb[3];          /* bricks per axis; 0 when the volume has no thickness on some axis */
    uint8_t *bricks;    /* nb[0]*nb[1]*nb[2] bricks of C5_CAST_BSTRIDE voxels, [z][y][x] inside */
    uint16_t *normals;  /* same layout: encoded normal per voxel; NULL until built */
    uint8_t *vox;       /* the voxels as given, kept for the normals */
    int levels;         /* octree levels; level 0 are the bricks */
    int ln[C5_CAST_MAX_LEVELS][3];
    uint8_t *minmax[C5_CAST_MAX_LEVELS]; /* per node (x fastest) its min and max voxel */
    uint8_t *sub_minmax;  /* per brick, per sub-brick s = sx + 2 sy + 4 sz: min and max voxel */
    /* The last classification made without hashes (c5_cast_view_classify), for the next frame
     * whose table has the same non-zero entries: it depends on nothing else, and the views of a
     * run mostly share one transfer function. A frame copies it out under the lock. */
    struct {
        pthread_mutex_t mu;
        int valid;
        uint32_t nonzero[C5_CAST_TF_N + 1]; /* the table's running count it was made for */
        uint8_t *cls[C5_CAST_MAX_LEVELS], *kids[C5_CAST_MAX_LEVELS], *sub_mask;
    } classified;
};

static inline size_t c5_cast_brick_index(const c5_cast_volume *v, int bx, int by, int bz)
{
    return ((size_t)bz * (size_t)v->nb[1] + (size_t)by) * (size_t)v->nb[0] + (size_t)bx;
}

/* Octahedral encoding of a direction (need not be unit length; zero gives C5_CAST_NZERO). */
uint16_t c5_cast_normal_encode(double x, double y, double z);
void c5_cast_normal_decode(uint16_t code, double n[3]);

/* A segment of sample indices j0..j1 (inclusive): samples at t = j * step from the eye. */
typedef struct {
    int32_t j0, j1;
} c5_cast_seg;

/* One frame's constants, shared by the producer and the workers. Positions are in voxel
 * units (world / spacing); t is world distance from the eye. */
typedef struct {
    const c5_cast_volume *v;
    const c5_cast_tf *tf;
    const c5_cast_camera *cam;
    int w, h, k, mode, shading, prefetch, early, sub_skip;
    int wide;               /* the workers march with c5_cast_wide_span (cast_sample.h) */
    double two_over_w, two_over_h; /* 2 / w and 2 / h (c5_cast_ray_dir) */
    double step;
    double eye_v[3];        /* eye in voxel units */
    double box_hi[3];       /* cells per axis */
    float clamp_hi[3];      /* the workers' position clamp per axis (cast_sample.h) */
    double delta_v[3];      /* dilation of every box for the producer's rays, voxel units */
    double margin_t;        /* added to both ends of each segment, world units */
    int lookahead;          /* samples ahead of the current one that the brick prefetch looks at */
    uint64_t hash_r[3];     /* the universal hash's random factors, in (0, PR) */
    float (*shade)[2];      /* per normal code: diffuse and specular factors of the headlight */
    /* the octree classified through this frame's TF (c5_cast_view_classify): per node
     * C5_CAST_EMPTY, C5_CAST_MIXED or C5_CAST_SOLID (every brick below it non-empty) */
    uint8_t *cls[C5_CAST_MAX_LEVELS];
    uint8_t *kids[C5_CAST_MAX_LEVELS];  /* levels >= 1: per node, bit o set when child o exists and is not empty */
    uint64_t (*node_hash[C5_CAST_MAX_LEVELS])[C5_CAST_HASH_WORDS]; /* refine: per node, its bricks' bits */
    uint8_t *sub_mask;      /* per brick: bit s set when sub-brick s is non-empty through the TF */
    struct c5_cast_corners *corners; /* approximation: the frame's corner rays on tile borders */
} c5_cast_view;

enum { C5_CAST_EMPTY, C5_CAST_MIXED, C5_CAST_SOLID };

/* The frame's view (cast_frame.c): -1 after c5_fail; c5_cast_view_release frees it either way. */
int c5_cast_view_setup(c5_cast_view *vw, const c5_cast_volume *v, const c5_cast_tf *tf, const c5_cast_camera *cam, int w,
                       int h, const c5_cast_opts *o, c5_err *err);

/* Classifies every octree node of vw->v through vw->tf, bottom up: a brick is empty when the
 * TF is zero over its voxels' range; a parent is empty (solid) when all its children are.
 * With `hashes`, also the OR of the hash bits of each node's bricks (levels >= 1). -1 when
 * out of memory. c5_cast_view_release frees what it allocated. */
int c5_cast_view_classify(c5_cast_view *vw, int hashes);
void c5_cast_view_release(c5_cast_view *vw);

/* Direction of the ray through image point (u, v) in pixels (pixel centres at +0.5), unit. */
void c5_cast_ray_dir(const c5_cast_view *vw, double u, double v, double d[3]);

/* A tile's work, as the producer leaves it in a worker's buffer. Units are pixels (k == 1,
 * or plain/ess) or k x k subtiles, row-major within the tile; unit u's segments are
 * seg[first[u] .. first[u+1]). */
typedef struct {
    int x0, y0;             /* tile origin in pixels */
    int units_x, units_y;   /* units per row and column */
    int unit;               /* unit side in pixels */
    uint32_t first[C5_CAST_TILE * C5_CAST_TILE + 1];
    c5_cast_seg *seg;
    uint32_t seg_cap;
    uint64_t (*hash)[C5_CAST_HASH_WORDS]; /* per unit, refine mode only */
    uint64_t rays;          /* producer rays spent on this tile */
} c5_cast_task;

#define C5_CAST_J_MAX (INT32_MAX - 1)  /* last sample index a segment may name */
#define C5_CAST_RAY_MAX 4096            /* brick intervals one ray may collect */
#define C5_CAST_CORNER_MAX 1024         /* merged index ranges one ray may keep */

/* The producer's working memory (one per producing thread). */
typedef struct {
    double t0[C5_CAST_RAY_MAX], t1[C5_CAST_RAY_MAX];
    c5_cast_seg row[2][C5_CAST_TILE + 1][C5_CAST_CORNER_MAX]; /* two rows of corner lists */
    int row_n[2][C5_CAST_TILE + 1];
    uint64_t hash[2][C5_CAST_TILE + 1][C5_CAST_HASH_WORDS];
    c5_cast_seg tmp[2][2 * C5_CAST_CORNER_MAX];
} c5_cast_scratch;
c5_cast_scratch *c5_cast_scratch_new(void);
void c5_cast_scratch_free(c5_cast_scratch *s);

/* Producer: fills t for the tile at (x0, y0). -1 only when out of memory. */
int c5_cast_produce(const c5_cast_view *vw, c5_cast_scratch *rs, int x0, int y0, c5_cast_task *t);

/* The octree walk of one ray from the eye along unit d: the intervals of t (world) where it
 * crosses the boxes, dilated by delta_v, of non-empty bricks (a solid node's box at once),
 * sorted and merged; returns their count, or -1 when more than cap intervals were met. With
 * `hash`, ORs in the hash bits of those bricks (needs c5_cast_view_classify(vw, 1)). */
int c5_cast_ray_segments(const c5_cast_view *vw, const double d[3], const double delta_v[3], double *t0, double *t1,
                         int cap, uint64_t *hash);

/* The corner rays on tile borders, each walked once per frame by whichever producer gets to
 * it first (cast_corners.c). Corner (a, b) is the ray through pixel (a k, b k). */
typedef struct c5_cast_corners c5_cast_corners;
c5_cast_corners *c5_cast_corners_new(int w, int h, int k); /* NULL when out of memory */
void c5_cast_corners_free(c5_cast_corners *c);
long c5_cast_corners_at(const c5_cast_corners *c, int a, int b); /* entry index; -1: not on a tile border */
/* Takes entry i's list into out (and its hash bits, when hash): its length, or one of these:
 * WALK: the caller has claimed the corner and must walk it and c5_cast_corner_put the result;
 * WALK_AGAIN: the list did not fit in the entry, the caller walks it for itself. */
enum { C5_CAST_CORNER_WALK = -1, C5_CAST_CORNER_WALK_AGAIN = -2 };
int c5_cast_corner_take(c5_cast_corners *c, long i, c5_cast_seg *out, uint64_t *hash);
void c5_cast_corner_put(c5_cast_corners *c, long i, const c5_cast_seg *seg, int n, const uint64_t *hash);

/* Worker: renders the tile's pixels into img, adding to the counters. */
typedef struct {
    uint64_t samples, zero, hashed, sub, terminated;
} c5_cast_counts;
void c5_cast_work(const c5_cast_view *vw, const c5_cast_task *t, float *rgb, c5_cast_counts *cnt);

/* The refining hash key of the brick at (bx, by, bz): its smallest voxel coordinates. */
static inline uint32_t c5_cast_hash_key(const c5_cast_view *vw, int bx, int by, int bz)
{
    uint64_t s = vw->hash_r[0] * (uint64_t)(bx * C5_CAST_BRICK) + vw->hash_r[1] * (uint64_t)(by * C5_CAST_BRICK) +
                 vw->hash_r[2] * (uint64_t)(bz * C5_CAST_BRICK);
    return (uint32_t)(s % C5_CAST_HASH_PR);
}

#endif
