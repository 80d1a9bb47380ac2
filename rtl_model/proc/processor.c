/* The ray processor: ray set-up, routing between cells, and the traversal of the active
 * cell (processor.h). */
#include <string.h>

#include "geom.h"
#include "processor.h"
#include "ray_log.h"
#include "sample_pipe.h"
#include "shade_wide.h"
#include "value_wide.h"

void c5_proc_init(c5_proc *p, const c5_frame_regs *r, const c5_cells *cells, const c5_rdram *mem, c5_proc_io io)
{
    memset(p, 0, sizeof *p);
    p->r = r;
    p->cells = cells;
    p->mem = mem;
    p->active = -1;
    p->io = io;
    memset(p->cache_tag, 0xff, sizeof p->cache_tag);
}

static int outside_grid(const c5_frame_regs *r, const int64_t pos[3])
{
    for (int a = 0; a < 3; a++)
        if (pos[a] < 0 || pos[a] >= ((int64_t)r->dims[a] << C5_POS_F))
            return 1;
    return 0;
}

/* The step vector, narrowed with pos (widths.h): a position on the narrowed grid stays on it. */
static void step_vec(const c5_frame_regs *r, const int64_t d[3], int64_t S[3])
{
    for (int a = 0; a < 3; a++)
        S[a] = c5_narrow(c5_rshift_he(d[a] * r->step_k[a], C5_DIR_F + 20 - C5_POS_F), r->nsh[C5_W_POS]); /* SQ3.15 */
}

/* A position or direction as the set-up unit produces it, narrowed (widths.h). Both are
 * unbounded here (a position may lie outside the grid; a unit direction's rounding stays
 * in [-1, 1]), so nothing is clamped. */
static void narrow3(int64_t v[3], int s)
{
    if (s)
        for (int a = 0; a < 3; a++)
            v[a] = c5_narrow(v[a], s);
}

/* Samples until pos leaves the voxel box [lo, hi): the smallest n >= 1 with pos + n S
 * outside, exactly as n single steps would find it (an integer division, not a loop). */
static int64_t steps_to_exit(const int64_t pos[3], const int64_t S[3], const int lo[3], const int hi[3])
{
    int64_t n = INT64_MAX;
    for (int a = 0; a < 3; a++) {
        int64_t m;
        if (S[a] > 0)
            m = (((int64_t)hi[a] << C5_POS_F) - pos[a] + S[a] - 1) / S[a];
        else if (S[a] < 0)
            m = (pos[a] - ((int64_t)lo[a] << C5_POS_F)) / -S[a] + 1;
        else
            continue;
        if (m < n)
            n = m;
    }
    return n < 1 ? 1 : n;
}

/* Advances pos by n steps, n cut by the lifetime; returns the steps taken. (The lane batches'
 * n are within the lifetime already: samples_ahead counts no more.) */
static int64_t advance(int64_t pos[3], uint32_t *lifetime, const int64_t S[3], int64_t n)
{
    if (*lifetime != C5_LIFE_NONE && n > (int64_t)*lifetime)
        n = *lifetime;
    for (int a = 0; a < 3; a++)
        pos[a] += n * S[a];
    if (*lifetime != C5_LIFE_NONE)
        *lifetime -= (uint32_t)n;
    return n;
}

/* A leap of n samples, counted. */
static void leap(c5_proc *p, c5_bray *ray, const int64_t S[3], int64_t n)
{
    p->st.leaped += (uint64_t)advance(ray->pos, &ray->lifetime, S, n);
    p->st.leaps++;
    p->st.cycles += C5_CYC_LEAP;
}

/* Where a ray goes next, outside the active cell's traversal: its end, a leap over an
 * empty cell, or the queue of the cell it is in. S: the ray's step vector. */
static void route(c5_proc *p, c5_bray *ray, const int64_t S[3])
{
    const c5_frame_regs *r = p->r;
    for (;;) {
        if (ray->lifetime == 0 || outside_grid(r, ray->pos)) {
            c5_proc_finish(p, ray, -2 * (r->step_g >> 5) - 1);
            return;
        }
        int v[3] = {(int)(ray->pos[0] >> C5_POS_F), (int)(ray->pos[1] >> C5_POS_F), (int)(ray->pos[2] >> C5_POS_F)};
        int cell = c5_cell_at(p->cells, v[0], v[1], v[2]);
        if (cell != p->active && p->cells->empty[cell]) {
            int lo[3], hi[3];
            c5_cell_box(p->cells, cell, lo, hi);
            leap(p, ray, S, steps_to_exit(ray->pos, S, lo, hi));
            continue;
        }
        ray->cell = (uint32_t)cell;
        p->io.enqueue(p->io.ctx, ray);
        return;
    }
}

/* Box entry of the line O + t d with the grid box [0, gdims) in geom coordinates. */
static int grid_range(const c5_frame_regs *r, const int64_t O[3], const int64_t d[3], int64_t *tin, int64_t *tout)
{
    int64_t t0 = INT64_MIN, t1 = INT64_MAX;
    /* |O|, |gdims - O| < 2^47 and |d| < 2^47: every numerator below 2^61, in 64 bits */
    int small = c5_geom_small3(O, 46) && c5_geom_small3(d, 47) && c5_geom_small3(r->gdims, 45);
    for (int a = 0; a < 3; a++) {
        if (d[a] == 0) {
            if (O[a] < 0 || O[a] >= r->gdims[a])
                return 0;
            continue;
        }
        int64_t ta, tb;
        if (small) { /* the same quotients: c5_div_he takes these steps for |n|, |d| < 2^62 */
            ta = c5_div_he64(-O[a] * (1 << 14), d[a]);
            tb = c5_div_he64((r->gdims[a] - O[a]) * (1 << 14), d[a]);
        } else {
            ta = c5_div_he(c5_shl128(-O[a], 14), d[a]);
            tb = c5_div_he(c5_shl128(r->gdims[a] - O[a], 14), d[a]);
        }
        if (ta > tb) {
            int64_t x = ta;
            ta = tb;
            tb = x;
        }
        t0 = ta > t0 ? ta : t0;
        t1 = tb < t1 ? tb : t1;
    }
    *tin = t0;
    *tout = t1;
    return t0 <= t1;
}

/* Samples k >= 0 with k * step < t (t in geom_t): ceil(t / step). */
static int64_t samples_before(const c5_frame_regs *r, int64_t t)
{
    if (t <= 0)
        return 0;
    /* 15 -> 20 fraction bits, the step's; below 2^57 (every finite t of the model's grid) the
     * sum stays below 2^63 (step_g < 2^24): the same quotient without a 128-bit division */
    if (t < (int64_t)1 << 57)
        return ((t << 5) + r->step_g - 1) / r->step_g;
    __int128 num = (__int128)t << 5;
    return (int64_t)((num + r->step_g - 1) / r->step_g);
}

/* Position of sample k in voxel coordinates: O + round(k step d), then to voxels. */
static void sample_pos(const c5_frame_regs *r, const int64_t O[3], const int64_t d[3], int64_t k, int64_t P[3])
{
    int64_t G[3];
    for (int a = 0; a < 3; a++)
        G[a] = O[a] + c5_rshift128_he((__int128)k * r->step_g * d[a], 20 + C5_DIR_F - 15);
    c5_geom_to_voxel(r, G, P);
    narrow3(P, r->nsh[C5_W_POS]);
}

void c5_proc_new_ray(c5_proc *p, const int64_t O[3], const int64_t d_in[3], int64_t t_light, int skip,
                     const c5_bray *proto)
{
    const c5_frame_regs *r = p->r;
    c5_bray ray = *proto;
    memcpy(ray.dir, d_in, sizeof ray.dir);
    narrow3(ray.dir, r->nsh[C5_W_DIR]); /* the direction the packet carries, used for everything below */
    const int64_t *d = ray.dir;
    ray.opa = 0;
    ray.surf = C5_SURF_NONE;
    p->st.rays[ray.type]++;
    p->st.setups++;
    p->st.cycles += (uint64_t)r->n_surfaces * C5_CYC_SURFACE_TEST;
    int64_t t_end = C5_T_INF;
    /* The closest hit a ray takes (exclusive). Spawned rays leave a surface and skip
     * max(1e-6 diagonal, 1/64 min spacing) so as not to hit it again (rounding puts their
     * origin on either side of it). An eye ray starts on no surface: it takes every hit
     * from 2 geom_t LSBs (2^-14 min spacing) on. One LSB, not 0: a surface through the eye
     * gives a t within rounding of 0 (0 or 1 LSB), and cref
     * skips it (t > 1e-6 diagonal, ~1 LSB for a 16^3 grid). docs/board-model.md. */
    int64_t tmin0 = ray.type == C5_RAY_EYE ? 1 : r->eps_g;
    if (ray.type == C5_RAY_SHADOW) {
        /* Each crossing of a surface on the way to the light passes its transparency. */
        int64_t T = C5_ONE15;
        for (int i = 0; i < r->n_surfaces && T > 0; i++) {
            int64_t t, tmin = tmin0;
            while (i != skip && T > 0 && c5_geom_hit(&r->surf[i], O, d, tmin, t_light, &t)) {
                T = c5_rshift_he(T * r->surf[i].transp, 15);
                tmin = t;
            }
        }
        if (T == 0) {
            p->st.ends[C5_END_BLOCKED]++;
            return;
        }
        for (int c = 0; c < 3; c++)
            ray.rgb[c] = c5_narrow_clamp(c5_rshift_he(ray.rgb[c] * T, 15), r->nsh[C5_W_RGB], 0, C5_RGB_MAX,
                                         &p->st.saturations);
        t_end = t_light;
    } else {
        for (int i = 0; i < r->n_surfaces; i++) {
            int64_t t;
            if (i != skip && c5_geom_hit(&r->surf[i], O, d, tmin0, t_end, &t)) {
                t_end = t;
                ray.surf = (uint32_t)i;
            }
        }
    }
    int64_t tin, tout;
    if (r->has_volume && grid_range(r, O, d, &tin, &tout) && tout >= 0 && tin < t_end) {
        int64_t n_end = t_end == C5_T_INF ? INT64_MAX : samples_before(r, t_end);
        int64_t k = samples_before(r, tin) - 1, klast = samples_before(r, tout) + 1;
        if (k < 0)
            k = 0;
        for (; k <= klast && k < n_end; k++) {
            sample_pos(r, O, d, k, ray.pos);
            if (!outside_grid(r, ray.pos))
                break;
        }
        if (k <= klast && k < n_end) {
            int64_t life = n_end == INT64_MAX ? C5_LIFE_NONE : n_end - k;
            ray.lifetime = (uint32_t)(life > C5_LIFE_MAX && life != C5_LIFE_NONE ? C5_LIFE_MAX : life);
            int64_t S[3];
            step_vec(r, ray.dir, S);
            route(p, &ray, S);
            return;
        }
    }
    /* No sample in the volume: straight to the ray's end. */
    c5_geom_to_voxel(r, O, ray.pos);
    narrow3(ray.pos, r->nsh[C5_W_POS]);
    ray.lifetime = 0;
    c5_proc_finish(p, &ray, tmin0);
}

static void cache_access(c5_proc *p, int64_t tag)
{
    if (p->rec) {
        c5_rlog_access(p->rec, (uint64_t)tag);
        return;
    }
    int line = c5_cache_line_of(tag);
    if (p->cache_tag[line] == tag) {
        p->st.cache_hits++;
    } else {
        p->st.cache_misses++;
        p->cache_tag[line] = tag;
    }
}

/* trav_step's start: the ray where it stands, leaving (the outcome unless it samples or leaps). */
static inline __attribute__((always_inline)) void trav_begin(const c5_trav_in *in, c5_trav_out *o)
{
    for (int a = 0; a < 3; a++)
        o->pos[a] = in->pos[a];
    o->lifetime = in->lifetime;
    o->leaped = 0;
    o->action = C5_TRAV_LEAVE;
}

/* trav_step's end in the cell: a sample, or in the empty 8^3 block b (block coordinates) a
 * leap to the exit of the block's box within the cell. */
static inline __attribute__((always_inline)) void trav_end(const c5_trav_in *in, int empty, const int b[3],
                                                           c5_trav_out *o)
{
    if (!empty) {
        o->action = C5_TRAV_SAMPLE;
        advance(o->pos, &o->lifetime, in->S, 1);
        return;
    }
    int lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = b[a] * C5_BLOCK > in->lo[a] ? b[a] * C5_BLOCK : in->lo[a];
        hi[a] = (b[a] + 1) * C5_BLOCK < in->hi[a] ? (b[a] + 1) * C5_BLOCK : in->hi[a];
    }
    o->action = C5_TRAV_LEAP;
    o->leaped = advance(o->pos, &o->lifetime, in->S, steps_to_exit(in->pos, in->S, lo, hi));
}

/* The body of c5_trav_step, inline in c5_proc_run's per-sample loop (an out-of-line
 * call with its two structs was ~5 % of the model's instructions). */
static inline __attribute__((always_inline)) void trav_step(const c5_trav_in *in, c5_trav_out *o)
{
    trav_begin(in, o);
    if (in->lifetime == 0)
        return;
    int b[3];
    for (int a = 0; a < 3; a++) {
        if (in->pos[a] < 0 || in->pos[a] >= ((int64_t)in->dims[a] << C5_POS_F))
            return; /* outside the grid */
        int v = (int)(in->pos[a] >> C5_POS_F);
        if (v < in->lo[a] || v >= in->hi[a])
            return; /* outside the cell */
        b[a] = v / C5_BLOCK;
    }
    trav_end(in, in->block_empty, b, o);
}

void c5_trav_step(const c5_trav_in *in, c5_trav_out *o) { trav_step(in, o); }

/* The empty flag of the 8^3 block holding pos, 0 outside the grid. */
static int block_empty_at(const c5_cells *cl, const int dims[3], const int64_t pos[3])
{
    for (int a = 0; a < 3; a++)
        if (pos[a] < 0 || pos[a] >= ((int64_t)dims[a] << C5_POS_F))
            return 0;
    int b[3] = {(int)(pos[0] >> C5_POS_F) / C5_BLOCK, (int)(pos[1] >> C5_POS_F) / C5_BLOCK,
                (int)(pos[2] >> C5_POS_F) / C5_BLOCK};
    return cl->block_empty[((size_t)b[2] * cl->bdims[1] + b[1]) * cl->bdims[0] + b[0]];
}

/* trav_step with block_empty_at's flag, for a cell whose box lies in the grid (0 <= lo,
 * hi <= dims): a position in the box is then in the grid, and the flag is read at the voxel
 * found. The same decision in one pass, for the runs no traverse tap watches. */
static inline __attribute__((always_inline)) void trav_in_box(const c5_trav_in *in, const c5_cells *cl,
                                                              c5_trav_out *o)
{
    trav_begin(in, o);
    if (in->lifetime == 0)
        return;
    int b[3];
    for (int a = 0; a < 3; a++) {
        int64_t v = in->pos[a] >> C5_POS_F;
        if ((uint64_t)(v - in->lo[a]) >= (uint64_t)(in->hi[a] - in->lo[a]))
            return; /* outside the cell */
        b[a] = (int)v / C5_BLOCK;
    }
    trav_end(in, cl->block_empty[((size_t)b[2] * cl->bdims[1] + b[1]) * cl->bdims[0] + b[0]], b, o);
}

/* Whether trav_step decides "sample" at pos with the lifetime left: in the grid, in the
 * cell, in a block that is not empty. */
static int samples_at(const c5_trav_in *in, const c5_cells *cl, const int64_t pos[3])
{
    for (int a = 0; a < 3; a++) {
        if (pos[a] < 0 || pos[a] >= ((int64_t)in->dims[a] << C5_POS_F))
            return 0;
        int v = (int)(pos[a] >> C5_POS_F);
        if (v < in->lo[a] || v >= in->hi[a])
            return 0;
    }
    return !block_empty_at(cl, in->dims, pos);
}

/* The most samples_ahead looks ahead: a ray that ends early wastes no more block walks. */
#define AHEAD_MAX 64

/* After a step that samples at in->pos: how many of the following steps trav_step is
 * known to decide "sample" as well. Until pos + n S leaves the box of its 8^3 block within
 * the cell (steps_to_exit, exact), every position stays in the grid, in the cell and in
 * the same non-empty block; the first position past the box starts the next block's run if
 * trav_step samples there too (samples_at), and so on up to AHEAD_MAX. Only the lifetime
 * cuts the runs: the sample at pos leaves lifetime - 1, and step k needs lifetime - k > 0. */
static int64_t samples_ahead(const c5_trav_in *in, const c5_cells *cl)
{
    int64_t at[3] = {in->pos[0], in->pos[1], in->pos[2]}, n = 0;
    int64_t life = in->lifetime == C5_LIFE_NONE ? INT64_MAX : (int64_t)in->lifetime;
    for (;;) {
        int lo[3], hi[3];
        for (int a = 0; a < 3; a++) {
            int b = (int)(at[a] >> C5_POS_F) / C5_BLOCK;
            lo[a] = b * C5_BLOCK > in->lo[a] ? b * C5_BLOCK : in->lo[a];
            hi[a] = (b + 1) * C5_BLOCK < in->hi[a] ? (b + 1) * C5_BLOCK : in->hi[a];
            hi[a] = hi[a] < in->dims[a] ? hi[a] : in->dims[a];
        }
        n += steps_to_exit(at, in->S, lo, hi); /* the first step from in->pos outside the box */
        if (n >= life || n > AHEAD_MAX)
            break;
        for (int a = 0; a < 3; a++)
            at[a] = in->pos[a] + n * in->S[a];
        if (!samples_at(in, cl, at))
            break;
    }
    n -= 1;
    return n < life - 1 ? n : life - 1;
}

/* The taps of one sample (only called with taps): the gather and blends, the table. */
static void tap_sample(const c5_taps *t, const c5_corners *k, const c5_sample *smp, int grad, const int64_t gs[3],
                       const int64_t rgba[4])
{
    if (t->interp)
        t->interp(t->ctx, k, smp->value);
    if (grad && t->gradient)
        t->gradient(t->ctx, k, gs, smp->grad);
    if (t->classify)
        t->classify(t->ctx, smp->value, rgba);
}

static void shade_tapped(const c5_taps *t, const c5_frame_regs *r, const c5_sample *smp, const int64_t rgba[4],
                         const int64_t gpos[3], const int64_t d[3], int64_t c[3], uint64_t *sat)
{
    uint64_t sat0 = *sat;
    c5_shade_w(r, smp, rgba, gpos, d, c, sat, r->nsh[C5_W_NORMAL]);
    if (!t->shade)
        return;
    c5_shade_io io;
    for (int a = 0; a < 3; a++) {
        io.grad[a] = smp->grad[a];
        io.gpos[a] = gpos[a];
        io.dir[a] = d[a];
        io.rgb[a] = c[a];
    }
    for (int ch = 0; ch < 4; ch++)
        io.rgba[ch] = rgba[ch];
    io.sat = (int)(*sat - sat0);
    t->shade(t->ctx, &io);
}

static int composite_tapped(const c5_taps *t, const c5_frame_regs *r, c5_bray *ray, int64_t alpha,
                            const int64_t c[3], int shadow, uint64_t *sat)
{
    c5_composite_io io = {.w = ray->w, .opa = ray->opa, .alpha = alpha, .a_max = r->a_max, .shadow = shadow};
    for (int ch = 0; ch < 3; ch++) {
        io.rgb[ch] = ray->rgb[ch];
        io.c[ch] = c[ch];
    }
    uint64_t sat0 = *sat;
    int done = c5_composite(r, ray, alpha, shadow ? NULL : c, sat);
    if (t->composite) {
        for (int ch = 0; ch < 3; ch++)
            io.rgb_out[ch] = ray->rgb[ch];
        io.opa_out = ray->opa;
        io.done = done;
        io.sat = (int)(*sat - sat0);
        t->composite(t->ctx, &io);
    }
    return done;
}

/* The compositing results narrowed (widths.h), after c5_composite (the block at the shipped
 * widths): opacity and colour, then early termination on the narrowed opacity. */
static int narrow_composited(const c5_frame_regs *r, c5_bray *ray, uint64_t *sat)
{
    ray->opa = c5_narrow_clamp(ray->opa, r->nsh[C5_W_OPACITY], 0, 65535, sat);
    for (int ch = 0; ch < 3; ch++)
        ray->rgb[ch] = c5_narrow_clamp(ray->rgb[ch], r->nsh[C5_W_RGB], 0, C5_RGB_MAX, sat);
    return ray->opa >= r->a_max;
}

/* A run's samples taken but not yet composited, while they wait for their shaded samples to
 * fill the lanes of c5_grad_wide and c5_shade_wide. What each sample does to the processor's
 * state (the voxel cache, the counters) waits with it, and is done in order when they are
 * composited, up to the sample that ends the ray: so the state is what sample-by-sample
 * processing leaves. (A ray that ends is delivered and not read again: its position and
 * lifetime stay where the run left them.) */
#define PENDING_MAX 32
typedef struct {
    int n;                     /* samples */
    int64_t tag[PENDING_MAX];  /* each one's cache tag */
    c5_shade_lanes lit;        /* the shaded ones' inputs, then their colours */
    int at[C5_SHADE_LANES];    /* a shaded one's place among the samples */
    int64_t alpha[C5_SHADE_LANES]; /* its opacity */
    c5_rows_src rows;          /* the cell's rows, set up at the run's first shaded sample */
    int rows_ready;
} pending;

/* A ray whose opacity reached the limit: a shadow ray is blocked, another delivered. */
static void opaque_end(c5_proc *p, const c5_bray *ray, int shadow)
{
    if (shadow) {
        p->st.ends[C5_END_BLOCKED]++;
    } else {
        p->io.deliver(p->io.ctx, ray->u, ray->v, ray->rgb);
        p->st.ends[C5_END_OPACITY]++;
    }
}

/* The pending samples composited in order: 1 if one of them ended the ray (delivered). The
 * cache accesses of the samples up to each shaded one, then its compositing. */
static int composite_pending(c5_proc *p, c5_bray *ray, pending *q, uint64_t cycles)
{
    int n = q->n, lit = q->lit.n, i = 0;
    if (lit)
        c5_grad_shade_wide(p->r, ray->dir, &q->lit);
    q->n = q->lit.n = 0;
    q->lit.rows = 0;
    for (int j = 0; j < lit; j++) {
        for (; i <= q->at[j]; i++)
            cache_access(p, q->tag[i]);
        p->st.saturations += q->lit.sat[j];
        if (c5_composite(p->r, ray, q->alpha[j], q->lit.out[j], &p->st.saturations)) {
            p->st.samples += (uint64_t)i;
            p->st.cycles += (uint64_t)i * cycles;
            opaque_end(p, ray, 0); /* a shaded run: not a shadow ray */
            return 1;
        }
    }
    for (; i < n; i++)
        cache_access(p, q->tag[i]);
    p->st.samples += (uint64_t)n;
    p->st.cycles += (uint64_t)n * cycles;
    return 0;
}

/* Pending sample i (at pos) with alpha > 0 into the next lane of the shading: the voxels of
 * its gradient (rows, or differences where a clamp is due), its fractions and table colour
 * (axis or channel a at [a * stride]) and position. */
static inline __attribute__((always_inline)) void pend_lit(pending *q, const c5_frame_regs *r, const c5_rdram *m,
                                                           int i, const int64_t pos[3], const int32_t *frac,
                                                           const int32_t *rgb, ptrdiff_t stride, int64_t alpha)
{
    int lane = q->lit.n++;
    if (!q->rows_ready) {
        c5_rows_src_init(r, m, &q->rows);
        q->rows_ready = 1;
    }
    if (c5_gather_rows_at(&q->rows, pos, &q->lit.row[0][lane], C5_SHADE_LANES))
        q->lit.rows |= 1u << lane;
    else
        c5_gather_diffs_to(r, m, pos, &q->lit.diff[0][0][lane], 8 * C5_SHADE_LANES, C5_SHADE_LANES);
    for (int a = 0; a < 3; a++) {
        q->lit.frac[a][lane] = frac[a * stride];
        q->lit.vpos[a][lane] = (int32_t)pos[a];
        q->lit.rgb[a][lane] = rgb[a * stride];
    }
    q->at[lane] = i;
    q->alpha[lane] = alpha;
}

/* The fewest samples a run takes through c5_value_wide. */
#define VALUE_LANES_MIN 4

/* The n samples of c5_value_wide's lanes (at ray->pos + j S) made pending in order, as
 * c5_proc_run's per-sample path does, and the ray moved past them: 1 if the ray ended. A
 * stretch at a time up to the sample that fills the shading's lanes or the pending samples
 * (then they are composited); only the shaded samples need their own positions. */
static int pend_values(c5_proc *p, c5_bray *ray, pending *q, const c5_value_lanes *vl, int n, const int64_t S[3],
                       uint64_t cycles)
{
    const c5_frame_regs *r = p->r;
    for (int j0 = 0; j0 < n;) {
        int take = n - j0 < PENDING_MAX - q->n ? n - j0 : PENDING_MAX - q->n;
        unsigned lit = vl->lit >> j0 & ((1u << take) - 1);
        int room = C5_SHADE_LANES - q->lit.n;
        for (unsigned x = lit; x; x &= x - 1)
            if (--room == 0) { /* the sample that fills the lanes ends the stretch */
                take = __builtin_ctz(x) + 1;
                lit &= (1u << take) - 1;
                break;
            }
        for (int b = 0; b < take; b++)
            q->tag[q->n + b] = vl->tag[j0 + b];
        for (; lit; lit &= lit - 1) {
            int b = __builtin_ctz(lit), j = j0 + b;
            int64_t at[3] = {ray->pos[0] + j * S[0], ray->pos[1] + j * S[1], ray->pos[2] + j * S[2]};
            pend_lit(q, r, p->mem, q->n + b, at, &vl->frac[0][j], &vl->rgb[0][j], C5_VALUE_LANES, vl->alpha[j]);
        }
        q->n += take;
        j0 += take;
        if ((q->lit.n == C5_SHADE_LANES || q->n == PENDING_MAX) && composite_pending(p, ray, q, cycles))
            return 1;
    }
    advance(ray->pos, &ray->lifetime, S, n);
    return 0;
}

/* The n samples of c5_value_wide's lanes (at ray->pos + j S) of a run that does not shade (a
 * shadow ray, or no light), composited one by one as c5_proc_run's per-sample path does, and
 * the ray moved past them: 1 if the ray ended. */
static int plain_values(c5_proc *p, c5_bray *ray, const c5_value_lanes *vl, int n, const int64_t S[3],
                        uint64_t cycles, int shadow)
{
    int j = 0, done = 0;
    for (; j < n && !done; j++) {
        cache_access(p, vl->tag[j]);
        p->st.samples++;
        p->st.cycles += cycles;
        if (vl->alpha[j] > 0) {
            int64_t c[3];
            for (int ch = 0; !shadow && ch < 3; ch++)
                c[ch] = c5_rshift_he(vl->rgb[ch][j], 15 - C5_RGB_F); /* UQ1.15 -> shaded_rgb UQ4.12 */
            done = c5_composite(p->r, ray, vl->alpha[j], shadow ? NULL : c, &p->st.saturations);
        }
    }
    advance(ray->pos, &ray->lifetime, S, j);
    if (done)
        opaque_end(p, ray, shadow);
    return done;
}

/* Whether c5_proc_run takes its samples' values in lanes (c5_value_wide), and shades them in
 * lanes (c5_shade_wide) where it shades: a run without taps, at the shipped widths, on a host
 * with the wide units. */
static int values_in_lanes(const c5_frame_regs *r, const c5_taps *tp)
{
    if (tp || !c5_shade_wide_usable())
        return 0;
    for (int w = 0; w < C5_W_COUNT; w++)
        if (r->nsh[w])
            return 0;
    return 1;
}

void c5_proc_run(c5_proc *p, c5_bray *ray)
{
    const c5_frame_regs *r = p->r;
    const c5_rdram *m = p->mem;
    const c5_cells *cl = p->cells;
    const c5_taps *tp = p->taps;
    int shadow = ray->type == C5_RAY_SHADOW;
    int grad = !shadow && r->st.gradients;
    int shade = grad && r->n_lights > 0;
    /* The sample's geom position feeds only a point light's direction (and the taps). */
    int want_gpos = tp != NULL;
    for (int i = 0; i < r->n_lights; i++)
        want_gpos |= r->lights[i].kind == C5_LIGHT_POINT;
    int64_t S[3];
    step_vec(r, ray->dir, S);
    p->st.cycles += C5_CYC_ISSUE;
    c5_trav_in ti;
    for (int a = 0; a < 3; a++) {
        ti.S[a] = S[a];
        ti.lo[a] = m->lo[a];
        ti.hi[a] = m->hi[a];
        ti.dims[a] = r->dims[a];
    }
    /* Steps known to sample (samples_ahead): without a traverse tap they skip trav_step's
     * checks and take its result, one step S and one lifetime less. */
    int watched = tp && tp->traverse;
    /* A traverse tap is shown trav_step's own inputs and outputs. */
    int box_in_grid = !watched;
    for (int a = 0; a < 3; a++)
        box_in_grid &= m->lo[a] >= 0 && m->hi[a] <= r->dims[a];
    int64_t ahead = 0;
    const uint64_t sample_cycles = grad ? C5_CYC_SAMPLE_GRAD : C5_CYC_SAMPLE;
    pending q;
    int lanes = values_in_lanes(r, tp), in_lanes = lanes && shade;
    q.n = q.lit.n = 0;
    q.lit.rows = 0;
    q.rows_ready = 0;
    for (;;) {
        c5_trav_out to;
        if (ahead > 0) {
            ahead--;
            to.action = C5_TRAV_SAMPLE;
            for (int a = 0; a < 3; a++)
                to.pos[a] = ray->pos[a] + S[a];
            to.lifetime = ray->lifetime == C5_LIFE_NONE ? C5_LIFE_NONE : ray->lifetime - 1;
        } else {
            for (int a = 0; a < 3; a++)
                ti.pos[a] = ray->pos[a];
            ti.lifetime = ray->lifetime;
            if (box_in_grid) {
                trav_in_box(&ti, cl, &to);
            } else {
                ti.block_empty = block_empty_at(cl, r->dims, ray->pos);
                trav_step(&ti, &to);
            }
            if (watched)
                tp->traverse(tp->ctx, &ti, &to);
            else if (to.action == C5_TRAV_SAMPLE)
                ahead = samples_ahead(&ti, cl);
        }
        if (to.action != C5_TRAV_SAMPLE && q.n && composite_pending(p, ray, &q, sample_cycles))
            return;
        if (to.action == C5_TRAV_LEAVE)
            break;
        if (to.action == C5_TRAV_LEAP) {
            for (int a = 0; a < 3; a++)
                ray->pos[a] = to.pos[a];
            ray->lifetime = to.lifetime;
            p->st.leaped += (uint64_t)to.leaped;
            p->st.leaps++;
            p->st.cycles += C5_CYC_LEAP;
            continue;
        }
        if (lanes && ahead + 1 >= VALUE_LANES_MIN) {
            int n = ahead + 1 < C5_VALUE_LANES ? (int)ahead + 1 : C5_VALUE_LANES;
            c5_value_lanes vl;
            if (c5_value_wide(r, m, ray->pos, S, n, &vl) == 0) {
                ahead -= n - 1;
                if (in_lanes ? pend_values(p, ray, &q, &vl, n, S, sample_cycles)
                             : plain_values(p, ray, &vl, n, S, sample_cycles, shadow))
                    return;
                continue;
            }
        }
        c5_corners k;
        c5_sample smp;
        int64_t wt[8];
        c5_gather_values(r, m, ray->pos, &k);
        c5_tri_weights(k.frac, wt);
        smp.value = c5_narrow_clamp(c5_interp_blend_w(wt, k.v), r->nsh[C5_W_VALUE], 0, 65535, &p->st.saturations);
        if (!in_lanes) {
            cache_access(p, c5_cache_tag_of(ray->pos));
            p->st.samples++;
            p->st.cycles += sample_cycles;
        }
        int64_t rgba[4];
        /* The opacity first: the colour of a sample with alpha 0 reaches no bit (unless a tap
         * watches it, or a narrowed width may saturate it). */
        c5_classify_channels(r, smp.value, 3, 4, rgba);
        if (rgba[3] > 0 || tp || r->nsh[C5_W_RGBA])
            c5_classify_channels(r, smp.value, 0, 3, rgba);
        if (r->nsh[C5_W_RGBA])
            for (int ch = 0; ch < 4; ch++)
                rgba[ch] = c5_narrow_clamp(rgba[ch], r->nsh[C5_W_RGBA], 0, 65535, &p->st.saturations);
        /* The gradient feeds only the shading of a sample with alpha > 0 (and the taps):
         * the processor computes it for every sample with gradients on (the cycles count
         * it), the model skips the host work where no bit depends on it. In lanes it is
         * c5_grad_wide's, from the differences read below. */
        if (grad && (tp || rgba[3] > 0) && !in_lanes) {
            c5_gather_diffs(r, m, ray->pos, &k);
            c5_grad_blend_w(wt, k.d, r->gs, smp.grad);
        }
        if (tp)
            tap_sample(tp, &k, &smp, grad, r->gs, rgba);
        if (in_lanes) {
            int i = q.n++;
            q.tag[i] = c5_cache_tag_of(ray->pos);
            if (rgba[3] > 0) {
                int32_t frac[3] = {(int32_t)k.frac[0], (int32_t)k.frac[1], (int32_t)k.frac[2]};
                int32_t rgb[3] = {(int32_t)rgba[0], (int32_t)rgba[1], (int32_t)rgba[2]};
                pend_lit(&q, r, m, i, ray->pos, frac, rgb, 1, rgba[3]);
            }
            for (int a = 0; a < 3; a++)
                ray->pos[a] = to.pos[a];
            ray->lifetime = to.lifetime;
            if ((q.lit.n == C5_SHADE_LANES || q.n == PENDING_MAX) && composite_pending(p, ray, &q, sample_cycles))
                return;
            continue;
        }
        int done = 0;
        if (rgba[3] > 0) {
            int64_t c[3];
            if (shade) {
                int64_t gpos[3] = {0, 0, 0};
                if (want_gpos)
                    c5_geom_from_voxel(r, ray->pos, gpos);
                if (tp)
                    shade_tapped(tp, r, &smp, rgba, gpos, ray->dir, c, &p->st.saturations);
                else
                    c5_shade_w(r, &smp, rgba, gpos, ray->dir, c, &p->st.saturations, r->nsh[C5_W_NORMAL]);
            } else {
                for (int ch = 0; ch < 3; ch++)
                    c[ch] = c5_rshift_he(rgba[ch], 15 - C5_RGB_F); /* UQ1.15 -> shaded_rgb UQ4.12 */
            }
            if (tp)
                done = composite_tapped(tp, r, ray, rgba[3], c, shadow, &p->st.saturations);
            else
                done = c5_composite(r, ray, rgba[3], shadow ? NULL : c, &p->st.saturations);
            if (r->nsh[C5_W_OPACITY] || r->nsh[C5_W_RGB])
                done = narrow_composited(r, ray, &p->st.saturations);
        }
        for (int a = 0; a < 3; a++)
            ray->pos[a] = to.pos[a];
        ray->lifetime = to.lifetime;
        if (done) {
            opaque_end(p, ray, shadow);
            return;
        }
    }
    route(p, ray, S);
}
