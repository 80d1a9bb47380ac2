/* Block "traverse": one step of the processor's loop over the active cell (c5_trav_step,
 * processor.h). In: the ray's position (voxel coordinates with 15 fraction bits, signed
 * and one bit wider than the packet's UQ9.15: a step or a leap carries it up to 8 voxels
 * outside the grid), its step vector (step_vec SQ3.15) and lifetime (12 bits, 4095:
 * unbounded), the cell's voxel box [lo, hi), the grid's dims and the empty flag of the
 * 8^3 block holding pos (0 when pos is outside the grid). Out: the action (0 sample: then
 * pos' = pos + S, lifetime' = lifetime - 1 unless 4095; 1 leap: pos is in an empty block,
 * the ray advances `leaped` = min(n, lifetime) steps without sampling, n the smallest
 * count that carries pos out of the block's box clipped to the cell; 2 leave: lifetime 0,
 * or pos outside the grid or the cell, the ray is routed on unchanged). */
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "fxops.h"
#include "geom.h"
#include "model_limits.h"
#include "processor.h"
#include "regs.h"
#include "rng.h"

/* Widths and formats from spec/layouts.toml (signals grid_pos, step_vec, grid_coord). */
#define POS C5_SIG_GRID_POS_WIDTH, 0, C5_SIG_GRID_POS_FORMAT
#define POS_OUT C5_SIG_GRID_POS_WIDTH, 1, C5_SIG_GRID_POS_FORMAT
#define STEP C5_SIG_STEP_VEC_WIDTH, 0, C5_SIG_STEP_VEC_FORMAT
#define GRID C5_SIG_GRID_COORD_WIDTH, 0, C5_SIG_GRID_COORD_FORMAT
#define LEAPED_BITS 19 /* a leap crosses at most 8 voxels = 2^18 steps of 2^-15 */

static const c5_vfield fields[] = {
    {"pos_x", POS},          {"pos_y", POS},           {"pos_z", POS},
    {"step_x", STEP},        {"step_y", STEP},         {"step_z", STEP},
    {"lifetime", 12, 0, "uint"},
    {"cell_lo_x", GRID},     {"cell_lo_y", GRID},      {"cell_lo_z", GRID},
    {"cell_hi_x", GRID},     {"cell_hi_y", GRID},      {"cell_hi_z", GRID},
    {"dims_x", GRID},        {"dims_y", GRID},         {"dims_z", GRID},
    {"block_empty", 1, 0, "uint"},
    {"action", 2, 1, "uint"}, {"leaped", LEAPED_BITS, 1, "uint"},
    {"pos_x_out", POS_OUT},  {"pos_y_out", POS_OUT},   {"pos_z_out", POS_OUT},
    {"lifetime_out", 12, 1, "uint"},
};

static const c5_vblock block = {
    "traverse",
    "one step of the processor's traversal loop: position, step vector, lifetime, the cell's box, the grid "
    "and the empty flag of pos's 8^3 block in; the action (0 sample, 1 leap, 2 leave the cell), the samples "
    "leaped, the new position and lifetime out (rtl_model/proc/processor.h c5_trav_step)",
    fields, (int)(sizeof fields / sizeof fields[0])};

typedef struct {
    c5_trav_in in;
    c5_trav_out out;
} rec;

static void write_rec(c5_vfile *f, const void *p)
{
    const rec *r = p;
    for (int a = 0; a < 3; a++)
        c5_vfile_s(f, r->in.pos[a]);
    for (int a = 0; a < 3; a++)
        c5_vfile_s(f, r->in.S[a]);
    c5_vfile_u(f, r->in.lifetime);
    for (int a = 0; a < 3; a++)
        c5_vfile_u(f, (uint64_t)r->in.lo[a]);
    for (int a = 0; a < 3; a++)
        c5_vfile_u(f, (uint64_t)r->in.hi[a]);
    for (int a = 0; a < 3; a++)
        c5_vfile_u(f, (uint64_t)r->in.dims[a]);
    c5_vfile_u(f, (uint64_t)r->in.block_empty);
    c5_vfile_u(f, (uint64_t)r->out.action);
    c5_vfile_u(f, (uint64_t)r->out.leaped);
    for (int a = 0; a < 3; a++)
        c5_vfile_s(f, r->out.pos[a]);
    c5_vfile_u(f, r->out.lifetime);
    c5_vfile_end(f);
}

static json_t *config(void)
{
    return json_pack("{s:{s:i, s:i, s:i}, s:i}", "actions", "sample", C5_TRAV_SAMPLE, "leap", C5_TRAV_LEAP, "leave",
                     C5_TRAV_LEAVE, "block", C5_BLOCK);
}

typedef struct {
    int lo[3], hi[3], dims[3];
} box;

/* Runs the step on (pos, S, lifetime, the box, the flag) and writes the vector; next (if
 * not NULL) receives the new position, to chain the step after. */
static void vec(c5_vfile *f, const box *b, const int64_t pos[3], const int64_t S[3], uint32_t life, int empty,
                int64_t *next)
{
    rec r;
    memset(&r, 0, sizeof r);
    for (int a = 0; a < 3; a++) {
        r.in.pos[a] = pos[a];
        r.in.S[a] = S[a];
        r.in.lo[a] = b->lo[a];
        r.in.hi[a] = b->hi[a];
        r.in.dims[a] = b->dims[a];
    }
    r.in.lifetime = life;
    r.in.block_empty = empty;
    c5_trav_step(&r.in, &r.out);
    write_rec(f, &r);
    if (next)
        memcpy(next, r.out.pos, sizeof r.out.pos);
}

static void at(int64_t p[3], double x, double y, double z)
{
    p[0] = (int64_t)(x * 32768);
    p[1] = (int64_t)(y * 32768);
    p[2] = (int64_t)(z * 32768);
}

/* A grid of 40 x 33 x 20 voxels; cell W the whole grid, cell B inside it off the block
 * grid (its 8^3 blocks are clipped to it). Lifetime 0, 1, 4094 and 4095 (unbounded); pos
 * on both sides of every grid face (sample / leave); a sample and a leap out through every
 * grid face, each followed by the step outside (leave); pos on both sides of every face of
 * cell B, and leaps out of it (then leave the cell, not the grid); a leap landing exactly on
 * a block boundary; a leap cut by the lifetime and one ending exactly with it; the longest
 * leap (S = 2^-15 across a whole block: 2^18 steps), unbounded and cut; step vectors with
 * zero components, all negative, and the extreme codes of SQ3.15; then random steps in
 * random grids and cells (a tenth anywhere near the grid; lifetimes 0, small, any and
 * unbounded); then the largest steps the frame set-up makes, 1,023- and 1-voxel axes with a
 * step to the largest SQ10.15 position, a step onto the grid's corner. */
static const box GRID_W = {{0, 0, 0}, {40, 33, 20}, {40, 33, 20}};
static const box CELL_B = {{5, 9, 3}, {21, 26, 13}, {40, 33, 20}};

/* The grid's and cell B's faces, lifetimes, leaps and the step vectors' extreme codes. */
static void geometry_cases(c5_vfile *f)
{
    const box W = GRID_W, B = CELL_B;
    const uint32_t NONE = C5_LIFE_NONE;
    const int64_t S1[3] = {3000, -1200, 700};
    int64_t p[3], q[3];
    at(p, 10.5, 10.5, 10.5);
    vec(f, &W, p, S1, 0, 0, NULL);    /* lifetime 0: leave */
    vec(f, &W, p, S1, 0, 1, NULL);    /* ... also in an empty block */
    vec(f, &W, p, S1, NONE, 0, NULL); /* unbounded: stays 4095 */
    vec(f, &W, p, S1, 1, 0, NULL);    /* the last sample: 0 */
    vec(f, &W, p, S1, C5_LIFE_MAX, 0, NULL);
    for (int a = 0; a < 3; a++) { /* both sides of the grid's faces */
        const int64_t side[4] = {0, -1, ((int64_t)W.dims[a] << 15) - 1, (int64_t)W.dims[a] << 15};
        for (int k = 0; k < 4; k++) {
            at(q, 10.5, 10.5, 10.5);
            q[a] = side[k];
            vec(f, &W, q, S1, 100, 0, NULL);
        }
    }
    for (int a = 0; a < 3; a++) /* a sample, then a leap, out through each grid face, and the step after */
        for (int dirn = -1; dirn <= 1; dirn += 2) {
            int64_t S[3] = {211, -97, 53};
            S[a] = dirn * 9000;
            at(q, 10.5, 10.5, 10.5);
            q[a] = dirn > 0 ? ((int64_t)W.dims[a] << 15) - 4000 : 4000;
            vec(f, &W, q, S, 50, 0, p); /* sample: pos' outside */
            vec(f, &W, p, S, 49, 0, NULL); /* leave */
            at(q, 10.5, 10.5, 10.5);
            /* in the block at the face: [0, 8) or the last one, clipped to the grid */
            q[a] = dirn > 0 ? ((int64_t)((W.dims[a] - 1) / C5_BLOCK * C5_BLOCK) << 15) + 10000 : 108000;
            vec(f, &W, q, S, NONE, 1, p); /* leap: pos' outside the grid */
            vec(f, &W, p, S, NONE, 0, NULL); /* leave (the flag is 0 outside the grid) */
        }
    for (int a = 0; a < 3; a++) { /* both sides of cell B's faces, inside the grid */
        const int64_t side[4] = {(int64_t)B.lo[a] << 15, ((int64_t)B.lo[a] << 15) - 1, ((int64_t)B.hi[a] << 15) - 1,
                                 (int64_t)B.hi[a] << 15};
        for (int k = 0; k < 4; k++) {
            at(q, 10.5, 12.5, 7.5);
            q[a] = side[k];
            vec(f, &B, q, S1, 100, k % 2, NULL);
        }
    }
    /* leaps in B's corner block, [0, 8) x [8, 16) x [0, 8) clipped to [5, 8) x [9, 16) x [3, 8) */
    const int64_t Sx[3] = {32768, 0, 0}, Snx[3] = {-32768, 0, 0}, Sneg[3] = {-3000, -4000, -5000};
    at(q, 5, 12, 5);
    vec(f, &B, q, Sx, NONE, 1, NULL); /* lands exactly on x = 8, the next block */
    at(q, 7, 12, 5);
    vec(f, &B, q, Snx, NONE, 1, p); /* out through the cell's face x = 5, to x = 4 */
    vec(f, &B, p, Snx, NONE, 0, NULL); /* leave the cell, not the grid */
    at(q, 7.9, 15.9, 7.9);
    vec(f, &B, q, Sneg, NONE, 1, NULL);
    vec(f, &B, q, Sneg, 3, 1, NULL); /* cut by the lifetime: 3 of 8 */
    vec(f, &B, q, Sneg, 8, 1, NULL); /* the lifetime ends with the leap: 0 */
    const int64_t Sy[3] = {0, -7000, 0}, Sz[3] = {0, 0, 3}, Syz[3] = {0, 2000, -2000};
    at(q, 6.5, 10.5, 4.5);
    vec(f, &B, q, Sy, NONE, 1, NULL);
    vec(f, &B, q, Sz, NONE, 1, NULL);
    vec(f, &B, q, Syz, NONE, 1, NULL);
    vec(f, &B, q, Sy, NONE, 0, NULL);
    vec(f, &B, q, Sneg, 20, 0, NULL);
    const int64_t Smin[3] = {1, 0, 0};
    at(q, 8, 12.5, 12.5);
    vec(f, &W, q, Smin, NONE, 1, NULL);        /* 2^18 steps */
    vec(f, &W, q, Smin, C5_LIFE_MAX, 1, NULL); /* cut at 4094 */
    const int64_t Smax[3] = {-(1 << 18), (1 << 18) - 1, 0};
    at(q, 20.5, 20.5, 12.5);
    vec(f, &W, q, Smax, NONE, 0, NULL);
    vec(f, &W, q, Smax, NONE, 1, NULL);
}

/* Random steps in random grids and cells. */
static void random_cases(c5_vfile *f, const c5_vset *s)
{
    int64_t q[3];
    uint64_t rng = s->seed ^ 0x7472617665ull; /* "trave" */
    for (long i = 0; i < s->count; i++) {
        box b;
        for (int a = 0; a < 3; a++) {
            b.dims[a] = 1 + (int)(c5_splitmix64(&rng) % 512);
            int x = (int)(c5_splitmix64(&rng) % (uint64_t)b.dims[a]);
            int y = (int)(c5_splitmix64(&rng) % (uint64_t)b.dims[a]);
            b.lo[a] = x < y ? x : y;
            b.hi[a] = (x < y ? y : x) + 1;
        }
        int in_grid = 1;
        for (int a = 0; a < 3; a++) { /* in the cell or up to 2 voxels around it, a tenth anywhere near the grid */
            int64_t lo = ((int64_t)b.lo[a] - 2) * 32768, hi = ((int64_t)b.hi[a] + 2) * 32768;
            if (i % 10 == 9) {
                lo = -((int64_t)8 << 15);
                hi = ((int64_t)b.dims[a] + 8) << 15;
            }
            q[a] = lo + (int64_t)(c5_splitmix64(&rng) % (uint64_t)(hi - lo));
            in_grid &= q[a] >= 0 && q[a] < ((int64_t)b.dims[a] << 15);
        }
        int64_t S[3], dv[3], d[3];
        do { /* as step_vec: a unit direction times step_k (UQ4.20), below 8 voxels, mostly below 1 */
            for (int a = 0; a < 3; a++)
                dv[a] = (int64_t)(c5_splitmix64(&rng) % 65536) - 32768;
            c5_geom_normalize(dv, d);
            uint64_t kmax = i % 4 == 0 ? ((uint64_t)8 << 20) - 1 : (uint64_t)1 << 20;
            int64_t k = 1 + (int64_t)(c5_splitmix64(&rng) % kmax);
            for (int a = 0; a < 3; a++)
                S[a] = c5_rshift_he(d[a] * k, C5_DIR_F + 20 - C5_POS_F);
        } while (S[0] == 0 && S[1] == 0 && S[2] == 0);
        uint64_t lr = c5_splitmix64(&rng);
        uint32_t life;
        switch (lr % 8) {
        case 0: life = 0; break;
        case 1: case 2: life = (uint32_t)(lr >> 8) % 16; break;
        case 3: case 4: life = C5_LIFE_NONE; break;
        default: life = (uint32_t)(lr >> 8) % C5_LIFE_NONE; break;
        }
        int empty = in_grid && (c5_splitmix64(&rng) & 1);
        vec(f, &b, q, S, life, empty, NULL);
    }
}

/* The largest steps the frame set-up makes, the largest grid's axes, the grid's corner. */
static void extreme_cases(c5_vfile *f)
{
    const box W = GRID_W;
    const uint32_t NONE = C5_LIFE_NONE;
    int64_t p[3], q[3];
    /* Appended after the random cases, which keep their lines. The largest step component
     * the frame set-up makes: step_k below 7.99 (regs.c refuses step / spacing >= 7.99) is
     * at most round(7.99 2^20), times a unit component of +-1: |S| = 261816 (7.99 voxels). */
    const int64_t kmax = c5_regs_fx(7.99, 20, 0, ((int64_t)16 << 20) - 1);
    const int64_t smax = c5_rshift_he((int64_t)(1 << C5_DIR_F) * kmax, C5_DIR_F + 20 - C5_POS_F);
    for (int a = 0; a < 3; a++)
        for (int sg = -1; sg <= 1; sg += 2) {
            int64_t S[3] = {0, 0, 0};
            S[a] = sg * smax;
            at(q, 20.5, 16.5, 10.5);
            vec(f, &W, q, S, 100, 0, NULL); /* step_* min / max: a sample, pos' 7.99 voxels on */
        }
    {
        const int64_t S[3] = {smax, 0, 0};
        at(q, 20.5, 16.5, 10.5);
        vec(f, &W, q, S, NONE, 1, NULL); /* a leap of one step of 7.99 voxels out of its block */
    }
    for (int a = 0; a < 3; a++) { /* the largest grid's axis, the others 1 voxel */
        /* C5_MODEL_MAX_GRID one-voxel cells along a, the last one [7999, 8000): cell_lo,
         * cell_hi and dims at their largest (cell_hi / dims 1 on the other axes); a step
         * from its middle lands 1.5 - 2^-15 voxels on, outside the grid, then the leave there */
        box E = {{0, 0, 0}, {1, 1, 1}, {1, 1, 1}};
        E.lo[a] = C5_MODEL_MAX_GRID - 1;
        E.hi[a] = C5_MODEL_MAX_GRID;
        E.dims[a] = C5_MODEL_MAX_GRID;
        int64_t S[3] = {0, 0, 0};
        q[0] = q[1] = q[2] = 1 << 14;
        q[a] = ((int64_t)(C5_MODEL_MAX_GRID - 1) << 15) + (1 << 14);
        S[a] = ((int64_t)3 << 14) - 1; /* 1.5 - 2^-15 voxels */
        vec(f, &E, q, S, 100, 0, p);
        vec(f, &E, p, S, 99, 0, NULL);
    }
    const int64_t Scorner[3] = {-65536, -65536, -65536}; /* 2 voxels an axis (|S| = 3.46) */
    at(q, 2, 2, 2);
    vec(f, &W, q, Scorner, 100, 0, p);  /* pos' exactly 0 on every axis: the grid's corner */
    vec(f, &W, p, Scorner, 99, 0, NULL); /* the sample there; pos' one step outside */
}

static int directed(c5_vset *s)
{
    c5_vfile *f = c5_vfile_open(s, &block, "directed", NULL, NULL);
    if (!f)
        return -1;
    geometry_cases(f);
    random_cases(f, s);
    extreme_cases(f);
    c5_vfile_set(f, "config", config());
    c5_vfile_close(f);
    return 0;
}

/* Scene taps: a uniform sample of the frame's traversal steps. */
static void tap_traverse(void *ctx, const c5_trav_in *in, const c5_trav_out *out)
{
    c5_vscene *v = ctx;
    rec r;
    memset(&r, 0, sizeof r); /* padding too: the reservoir copies whole records */
    r.in = *in;
    r.out = *out;
    c5_vsample_offer(v, C5_VB_TRAVERSE, &r);
}

static int tap_begin(c5_vscene *v, c5_taps *t)
{
    if (c5_vsample_begin(v, C5_VB_TRAVERSE, sizeof(rec), 0x106) != 0)
        return -1;
    t->traverse = tap_traverse;
    return 0;
}

static void tap_end(c5_vscene *v) { c5_vsample_end(v, C5_VB_TRAVERSE, &block, write_rec, config()); }

const c5_vblock_gen c5_vgen_traverse = {"traverse", directed, tap_begin, tap_end};
