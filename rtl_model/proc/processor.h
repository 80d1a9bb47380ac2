/* The ray processor (FPGA): the ray set-up unit, the traversal of the cell in RDRAM with the
 * per-sample datapath, space leaping, and the hit unit that shades surface hits and spawns
 * shadow, reflected and refracted rays. Transaction level: one call processes one ray; the
 * cycles it would take are counted by the cycle model of docs/board-model.md (constants
 * below). The ray queue (ray_queue.h) is the block modelled clock by clock.
 *
 * Outputs go through c5_proc_io: rays for a cell's queue (the active cell's, or over the ray
 * bus to the DSP) and finished rays' colours for the DSP's frame buffer. */
#ifndef C5_PROCESSOR_H
#define C5_PROCESSOR_H

#include "cells.h"
#include "cref.h"
#include "ray.h"
#include "regs.h"
#include "taps.h"

/* Cycle model (docs/board-model.md). */
#define C5_CYC_ISSUE 1         /* a ray enters the pipeline */
#define C5_CYC_SAMPLE 1        /* a sample without gradient: 8 voxels, one read port cycle */
#define C5_CYC_SAMPLE_GRAD 4   /* with gradient: 32 voxels at 8 a cycle */
#define C5_CYC_LEAP 1          /* a leap over an empty block or cell */
#define C5_CYC_SURFACE_TEST 1  /* per surface and ray set-up (pipelined intersector) */
#define C5_CYC_HIT 16          /* shading a hit: normal, lights, directions (iterative units) */
#define C5_CYC_PIPELINE 24     /* pipeline fill and drain, once per cell visit */
#define C5_CACHE_LINES 256     /* voxel cache: direct-mapped, 4^3-voxel lines (16 KB) */

typedef struct {
    void *ctx;
    void (*enqueue)(void *ctx, const c5_bray *r);                       /* a ray for queue r->cell */
    void (*deliver)(void *ctx, uint32_t u, uint32_t v, const int64_t rgb[3]); /* into the frame buffer */
    /* Optional: the same ray as enqueue's, already in its packet (c5_bray_pack), with its
     * cell, node and instrument node beside it: what a replayed log hands on (ray_log.h), so
     * that the packing is the helper thread's work. NULL: the replay unpacks for enqueue. */
    void (*enqueue_packet)(void *ctx, const uint8_t pk[C5_PACKET_BYTES], uint32_t cell, uint32_t node,
                           uint32_t shadow);
} c5_proc_io;

/* Every field a uint64_t counter: summed over rays in any order (a helper thread's counters
 * are added to the board's, board_threads.c), but for the cache's hits and misses, which
 * depend on the order and which a recorded run replays (ray_log.h). */
typedef struct {
    uint64_t rays[C5_RAY_TYPES], ends[C5_END_KINDS];
    uint64_t samples, leaped, leaps, hits, setups;
    uint64_t cycles;
    uint64_t cache_hits, cache_misses;
    uint64_t saturations;
} c5_proc_stats;

typedef struct {
    const c5_frame_regs *r;
    const c5_cells *cells;
    const c5_rdram *mem;  /* the cell in RDRAM */
    int active;           /* its id, -1 before the first fetch */
    c5_proc_io io;
    const c5_taps *taps;  /* observers of the datapath (golden vectors), or NULL: set after init */
    c5_proc_stats st;
    int64_t cache_tag[C5_CACHE_LINES];
    struct c5_ray_rec *rec; /* recording the run for a replay on the board's thread (ray_log.h), or NULL */
} c5_proc;

/* The voxel cache's tag of the 4^3-voxel block holding pos: 16 bits an axis (z y x), distinct
 * for every block of any grid the model takes (C5_MODEL_MAX_GRID); and its line. */
static inline int64_t c5_cache_tag_of(const int64_t pos[3])
{
    return (pos[2] >> (C5_POS_F + 2)) << 32 | (pos[1] >> (C5_POS_F + 2)) << 16 | (pos[0] >> (C5_POS_F + 2));
}
static inline int c5_cache_line_of(int64_t tag)
{
    return (int)((tag & 7) | ((tag >> 16) & 7) << 3 | ((tag >> 32) & 3) << 6);
}

void c5_proc_init(c5_proc *p, const c5_frame_regs *r, const c5_cells *cells, const c5_rdram *mem, c5_proc_io io);

/* A new ray from origin O (geom coordinates) along unit d: finds its first hit, its first
 * sample inside the grid and its lifetime, then routes it (to a queue, or straight to the
 * hit unit when it never samples the volume). t_light: shadow rays to a point light, the
 * distance to it (geom_t), else C5_T_INF. skip: a plane/rect the ray starts on, or -1.
 * proto holds type, w, rgb, gen, u, v, node. The ray is counted as created. */
void c5_proc_new_ray(c5_proc *p, const int64_t O[3], const int64_t d[3], int64_t t_light, int skip,
                     const c5_bray *proto);

/* Processes a ray taken from the active cell's queue until it leaves the cell, ends, or is
 * handed on. */
void c5_proc_run(c5_proc *p, c5_bray *ray);

/* Block "traverse": one step of c5_proc_run's loop over the active cell, a pure function
 * of the ray's position, step vector and lifetime, the cell's box, the grid and the
 * empty flag of pos's 8^3 block (taps.h, C5_TRAV_*). */
void c5_trav_step(const c5_trav_in *in, c5_trav_out *out);

/* The hit unit (hit_unit.c): the ray's volume part is over at position pos (voxel
 * coordinates, may lie outside the grid); shade its end and spawn what it spawns. */
void c5_proc_finish(c5_proc *p, c5_bray *ray, int64_t tmin_from_pos);

#endif
