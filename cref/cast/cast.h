/* cref/cast: the streaming-model volume ray caster of Kim and JaJa (second seed paper), the
 * fast direct-volume-rendering path of cref, drawn with the peer benchmark's conventions
 * (../shared/bench/peer-vtk/README.md; docs/caster.md) so that VTK can draw the same frames.
 *
 * Stages of one frame (docs/caster.md):
 *   producer (the paper's PPE)  walks the min/max octree over bricks along the rays and emits,
 *                               per 16x16 tile, the contributing segments of sample indices;
 *   workers  (the paper's SPEs) take the tiles of their static share of the Z-order, through
 *                               one bounded buffer each, and march only those samples, with
 *                               early ray termination and brick prefetch.
 * Every mode draws the same bits as marching every sample (C5_CAST_PLAIN): skipping drops
 * only samples whose opacity is exactly zero, and sample positions come from a global index
 * along each ray, never from a running sum. */
#ifndef C5_CAST_H
#define C5_CAST_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "image.h"
#include "scene.h"

#define C5_CAST_BRICK 8          /* brick (octree leaf) side in cells; stored with a 1-voxel apron */
#define C5_CAST_TILE 16          /* image tile side in pixels */
#define C5_CAST_HASH_PR 1021     /* refining hash table size: a prime (bits per table) */
#define C5_CAST_HASH_WORDS ((C5_CAST_HASH_PR + 63) / 64)
#define C5_CAST_TF_SCALE 16      /* classification table entries per scalar unit */
#define C5_CAST_TF_N (255 * C5_CAST_TF_SCALE + 1)
#define C5_CAST_MAX_WORKERS 64
/* Early ray termination: VTK's fixed-point test 1 - A < 255/32767 (peer README). */
#define C5_CAST_OPAQUE (1.0f - 255.0f / 32767.0f)

typedef enum {
    C5_CAST_PLAIN,          /* every sample between the ray's volume entry and exit */
    C5_CAST_ESS,            /* per-ray segments from the octree (the paper without its scheme) */
    C5_CAST_APPROX,         /* segments of every k-th ray; each k x k subtile takes the union of its 4 corners' */
    C5_CAST_APPROX_REFINE,  /* approx + per-subtile hash of non-empty bricks, checked per sample */
    C5_CAST_MODES
} c5_cast_mode;

/* What the workers prefetch (docs/caster.md, "Prefetch"). Neither changes a bit of the image. */
typedef enum {
    C5_CAST_PREFETCH_OFF,
    C5_CAST_PREFETCH_CELLS,  /* the cache lines of each kept sample's cell, a batch of samples ahead */
    C5_CAST_PREFETCH_BRICKS, /* the paper's: the whole brick 8 samples ahead, on entering a brick */
    C5_CAST_PREFETCHES
} c5_cast_prefetch;

/* ---- volume: bricks with an apron, normals, the min/max octree --------------------------- */

/* uint8 voxels at VTK point positions (i*sx, j*sy, k*sz), x fastest. Opaque. */
typedef struct c5_cast_volume c5_cast_volume;

/* Bricks the voxels (copied; vox may be freed after) and builds the octree. Normals are built
 * on the first shaded frame (c5_cast_volume_normals). dims each >= 1; spacing each > 0. */
int c5_cast_volume_make(const uint8_t *vox, const size_t dims[3], const double spacing[3], c5_cast_volume **out,
                        c5_err *err);
void c5_cast_volume_free(c5_cast_volume *v);
/* Builds the encoded per-voxel normals once (not thread-safe against a running frame). */
int c5_cast_volume_normals(c5_cast_volume *v, c5_err *err);

/* ---- classification ------------------------------------------------------------------- */

/* The transfer function sampled every 1/C5_CAST_TF_SCALE scalar, opacity corrected for the
 * step (a = 1 - (1 - a_tf)^(step / unit)), colour premultiplied: {a r, a g, a b, a}. A sample
 * takes the entry nearest its interpolated scalar. nonzero[i] counts the entries below i with
 * a != 0, so that a scalar range is empty in O(1): the octree is built once per volume, and a
 * new transfer function only needs a new table. */
typedef struct {
    float rgba[C5_CAST_TF_N][4];
    uint32_t nonzero[C5_CAST_TF_N + 1];
    uint8_t lit[C5_CAST_TF_N + 3]; /* 1 where rgba[i][3] != 0: a table that stays in L1 for the
                                      eight-sample loop's 32-bit gathers (3 bytes of padding) */
    float ambient, diffuse, specular, specular_power;
} c5_cast_tf;

/* step and unit in world units (unit <= 0: the smallest spacing). -1 with a message for a
 * table that is not finite or not in [0,1]. */
int c5_cast_tf_build(const c5_tf_desc *tf, double step, double unit, c5_cast_tf *out, c5_err *err);
/* 1 when every scalar in [lo, hi] (voxel values) classifies to opacity 0. */
static inline int c5_cast_tf_empty(const c5_cast_tf *t, unsigned lo, unsigned hi)
{
    return t->nonzero[hi * C5_CAST_TF_SCALE + 1] == t->nonzero[lo * C5_CAST_TF_SCALE];
}

/* ---- cameras -------------------------------------------------------------------------- */

/* A pinhole camera: the ray through pixel (px, py) of a w x h image (py = 0 the top row) is
 * normalize(f + ((2(px+0.5)/w - 1) tan_half) right + ((1 - 2(py+0.5)/h) tan_half) up). */
typedef struct {
    double eye[3], focal[3], f[3], right[3], up[3];
    double tan_half; /* tan(vertical view angle / 2); the image is square */
} c5_cast_camera;

/* ---- rendering ------------------------------------------------------------------------ */

typedef struct {
    c5_cast_mode mode;
    int k;             /* approximation interval in pixels: 1, 2, 4, 8 or 16; 0: c5_cast_default_k */
    int workers;       /* worker threads, 1..C5_CAST_MAX_WORKERS */
    int producer;      /* the calling thread produces tiles into the workers' buffers: 1; 0: it does
                          not, the workers produce every tile themselves (needs self_produce); -1:
                          auto, 1 while there are fewer workers than online CPUs (docs/caster.md) */
    int shading;       /* headlight Blinn-Phong, two-sided (peer README) */
    c5_cast_prefetch prefetch;
    int sub_bricks;    /* skipping modes: drop samples in sub-bricks the TF leaves empty */
    int self_produce;  /* a worker whose buffer is empty produces its next tile itself */
    int early_termination;
    double step;       /* sample distance in world units; 0: the smallest spacing */
    int queue_depth;   /* bounded buffer entries per worker (the paper's 4-entry mailbox); 0: 4 */
    int wide;          /* eight samples at a time (AVX2, cast_wide.c; not with approx+refine or the
                          brick prefetch) where the CPU has it: -1 auto (default), 0 never, 1 always
                          (refused where it cannot run). Same bits either way. */
} c5_cast_opts;

void c5_cast_opts_default(c5_cast_opts *o);

typedef struct {
    double frame_s;                              /* wall time of the frame */
    double producer_s;                           /* production time: the producer's busy time (waits for
                                                    buffer space excluded) plus the workers' own */
    double producer_wait_s;                      /* producer blocked on a full buffer */
    double worker_s[C5_CAST_MAX_WORKERS];        /* each worker's rendering time (waits, own production excluded) */
    double worker_wait_s[C5_CAST_MAX_WORKERS];   /* each worker blocked on an empty buffer */
    int workers, k;
    int producer;             /* the calling thread produced (opts.producer resolved) */
    int wide;                 /* the workers marched eight samples at a time (opts.wide resolved) */
    uint64_t tiles;
    uint64_t tiles_self;      /* of `tiles`, those the workers produced themselves */
    uint64_t producer_rays;   /* rays the producer traversed */
    uint64_t segments;        /* segments emitted (per pixel or per subtile) */
    uint64_t samples;         /* samples reconstructed and classified */
    uint64_t samples_hashed;  /* samples dropped by the refining hash */
    uint64_t samples_zero;    /* of `samples`, those with opacity 0 */
    uint64_t samples_sub;     /* samples dropped as lying in an empty sub-brick (opacity 0) */
    uint64_t rays_terminated; /* rays ended by early termination */
} c5_cast_stats;

/* Percent standard deviation of the workers' busy times (the paper's Figure 12). */
double c5_cast_load_imbalance(const c5_cast_stats *st);

/* The k Proposition 1 allows for this view: the largest of 16, 8, 4, 2, 1 whose rays, k
 * pixels apart on the image plane through the focal point, are at most half a brick apart
 * there, provided the eye is farther from that plane than the volume's far end (else 1). */
int c5_cast_prop1_k(const c5_cast_volume *v, const c5_cast_camera *cam, int w, int h);
/* The k a frame takes unless told (c5_cast_opts.k 0): Proposition 1's, raised to at least
 * C5_CAST_K_LOW and capped at C5_CAST_K_HIGH (docs/caster.md, "Proposition 1's k and the
 * default k"). */
#define C5_CAST_K_LOW 4
#define C5_CAST_K_HIGH 8
int c5_cast_default_k(const c5_cast_volume *v, const c5_cast_camera *cam, int w, int h);

/* Renders one w x h view into out (allocated here when out->rgb is NULL, else it must be
 * w x h). Same bits for any worker count, queue depth, prefetch, sub-brick and wide setting, k
 * and mode. */
int c5_cast_render(const c5_cast_volume *v, const c5_cast_tf *tf, const c5_cast_camera *cam, int w, int h,
                   const c5_cast_opts *o, c5_image *out, c5_cast_stats *st, c5_err *err);

const char *c5_cast_mode_name(c5_cast_mode m);
/* "plain", "ess", "approx", "approx+refine"; -1 for anything else. */
int c5_cast_mode_parse(const char *s, c5_cast_mode *m);
const char *c5_cast_prefetch_name(c5_cast_prefetch p);
/* "off", "cells", "bricks"; -1 for anything else. */
int c5_cast_prefetch_parse(const char *s, c5_cast_prefetch *p);

#endif
