/* The processor's per-sample datapath (docs/rendering-spec.md sec. 3-5), in the declared
 * formats of docs/bit-layouts.md: interpolation (sample_value UQ8.8), gradient (SQ8.8),
 * classification (tf_rgba UQ1.15), shading (normal SQ1.14, light_term and shaded_rgb
 * UQ4.12), compositing (sample_rgb UQ2.12, opacity UQ1.15). Inline: it is the model's inner
 * loop. Every step is exact integer arithmetic and one half-to-even rounding. The RDRAM
 * read (c5_gather: indices, clamping) is apart from the blends, which are pure functions of
 * the gathered corners: the hardware blocks of the golden vectors (vectors/gen/vec_*.c). */
#ifndef C5_SAMPLE_PIPE_H
#define C5_SAMPLE_PIPE_H

#include <string.h>

#include "cells.h"
#include "fxops.h"
#include "geom.h"
#include "ray.h"
#include "regs.h"
#include "taps.h"

typedef struct {
    int64_t value;   /* UQ8.8 */
    int64_t grad[3]; /* SQ8.8, scaled by s_min / s_a (proportional to the world gradient) */
} c5_sample;

static inline int clampi(int v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : v; }

/* The gather: for the sample at pos (voxel coordinates, 15 fraction bits) in the RDRAM cell, the
 * trilinear fractions and the 8 corner voxels, and (if want_grad) each corner's central
 * differences. Corner indices are clamped to the grid first, then their central-difference
 * neighbours, exactly as cref's clamp-to-edge (the ghost layers hold them). In two parts,
 * the corners (c5_gather_values) and their differences (c5_gather_diffs), so that the
 * processor reads the differences only for a sample that shades: the same reads either way. */
static inline void c5_gather_values(const c5_frame_regs *r, const c5_rdram *m, const int64_t pos[3], c5_corners *k)
{
    int i3[3], inner = 1;
    for (int a = 0; a < 3; a++) {
        int64_t x = pos[a] - (1 << (C5_POS_F - 1)); /* voxel centres at integers */
        int i = (int)(x >> C5_POS_F);
        k->frac[a] = x & ((1 << C5_POS_F) - 1);     /* voxel_frac UQ0.15 */
        i3[a] = i;
        inner &= (unsigned)i < (unsigned)(r->dims[a] - 1); /* 0 <= i, i + 1 <= dims - 1: no clamp changes an index */
    }
    ptrdiff_t sx = 1, sy, sz, o0;
    const uint8_t *v = c5_rdram_data(m, &o0, &sy, &sz);
    if (inner) {
        /* The same reads as below with the clamps left out (the model's hot path). */
        const uint8_t *b = v + (o0 + (i3[0] - m->org[0]) * sx + (i3[1] - m->org[1]) * sy + (i3[2] - m->org[2]) * sz);
        k->v[0] = b[0];
        k->v[1] = b[sx];
        k->v[2] = b[sy];
        k->v[3] = b[sx + sy];
        k->v[4] = b[sz];
        k->v[5] = b[sx + sz];
        k->v[6] = b[sy + sz];
        k->v[7] = b[sx + sy + sz];
        return;
    }
    int c[3][2];
    for (int a = 0; a < 3; a++)
        for (int kk = 0; kk < 2; kk++)
            c[a][kk] = clampi(i3[a] + kk, 0, r->dims[a] - 1) - m->org[a];
    for (int kz = 0; kz < 2; kz++)
        for (int ky = 0; ky < 2; ky++)
            for (int kx = 0; kx < 2; kx++)
                k->v[kx + 2 * ky + 4 * kz] = v[o0 + c[0][kx] * sx + c[1][ky] * sy + c[2][kz] * sz];
}

/* The differences into d[a * sa + j * sj] (corner j, axis a): c5_corners.d, or the lanes of
 * the gradient block (shade_wide.h). */
static inline void c5_gather_diffs_to(const c5_frame_regs *r, const c5_rdram *m, const int64_t pos[3], int32_t *d,
                                      ptrdiff_t sa, ptrdiff_t sj)
{
    int c[3][2], lo[3][2], hi[3][2], i3[3], inner = 1;
    for (int a = 0; a < 3; a++) {
        int i = (int)((pos[a] - (1 << (C5_POS_F - 1))) >> C5_POS_F);
        i3[a] = i;
        int room = r->dims[a] - 3 > 0 ? r->dims[a] - 3 : 0;
        inner &= (unsigned)(i - 1) < (unsigned)room; /* 1 <= i, i + 2 <= dims - 1: no clamp */
    }
    ptrdiff_t sx = 1, sy, sz, o0;
    const uint8_t *v = c5_rdram_data(m, &o0, &sy, &sz);
    if (inner) {
        const uint8_t *b = v + (o0 + (i3[0] - m->org[0]) * sx + (i3[1] - m->org[1]) * sy + (i3[2] - m->org[2]) * sz);
        const uint8_t *p[8] = {b, b + sx, b + sy, b + sx + sy, b + sz, b + sx + sz, b + sy + sz, b + sx + sy + sz};
        for (int j = 0; j < 8; j++) {
            d[j * sj] = p[j][sx] - p[j][-sx];
            d[sa + j * sj] = p[j][sy] - p[j][-sy];
            d[2 * sa + j * sj] = p[j][sz] - p[j][-sz];
        }
        return;
    }
    for (int a = 0; a < 3; a++) {
        int i = i3[a];
        for (int kk = 0; kk < 2; kk++) {
            int g = clampi(i + kk, 0, r->dims[a] - 1);
            c[a][kk] = g - m->org[a];
            lo[a][kk] = clampi(g - 1, 0, r->dims[a] - 1) - m->org[a];
            hi[a][kk] = clampi(g + 1, 0, r->dims[a] - 1) - m->org[a];
        }
    }
    for (int kz = 0; kz < 2; kz++)
        for (int ky = 0; ky < 2; ky++)
            for (int kx = 0; kx < 2; kx++) {
                int j = kx + 2 * ky + 4 * kz;
                d[j * sj] = v[o0 + hi[0][kx] * sx + c[1][ky] * sy + c[2][kz] * sz] -
                            v[o0 + lo[0][kx] * sx + c[1][ky] * sy + c[2][kz] * sz];
                d[sa + j * sj] = v[o0 + c[0][kx] * sx + hi[1][ky] * sy + c[2][kz] * sz] -
                                 v[o0 + c[0][kx] * sx + lo[1][ky] * sy + c[2][kz] * sz];
                d[2 * sa + j * sj] = v[o0 + c[0][kx] * sx + c[1][ky] * sy + hi[2][kz] * sz] -
                                     v[o0 + c[0][kx] * sx + c[1][ky] * sy + lo[2][kz] * sz];
            }
}

/* The rows of x = i - 1 .. i + 2 that hold every voxel of the central differences: (dy, dz)
 * from corner 0, the x row of each corner (dy, dz in 0..1) first. */
static const int8_t C5_ROW_DY[12] = {0, 1, 0, 1, -1, 2, -1, 2, 0, 1, 0, 1};
static const int8_t C5_ROW_DZ[12] = {0, 0, 1, 1, 0, 0, 1, 1, -1, -1, 2, 2};

/* What the row reads of one cell's visit need, fixed during it (c5_rows_src_init): the
 * twelve rows' offsets from corner 0 and each axis' room, worked out once a run instead of
 * at every shaded sample. */
typedef struct {
    const uint8_t *v;   /* the RDRAM's bytes (c5_rdram_data) */
    ptrdiff_t at0;      /* v's offset of grid voxel (-1, 0, 0), where row 0 of i = (0, 0, 0) starts (may be < 0) */
    ptrdiff_t sy, sz;
    ptrdiff_t off[12];  /* row k from row 0: C5_ROW_DY[k] sy + C5_ROW_DZ[k] sz */
    unsigned room[3];   /* 1 <= i <= dims - 3, as (unsigned)(i - 1) < room */
} c5_rows_src;

static inline void c5_rows_src_init(const c5_frame_regs *r, const c5_rdram *m, c5_rows_src *s)
{
    ptrdiff_t o0;
    s->v = c5_rdram_data(m, &o0, &s->sy, &s->sz);
    s->at0 = o0 - 1 - m->org[0] - m->org[1] * s->sy - m->org[2] * s->sz;
    for (int k = 0; k < 12; k++)
        s->off[k] = C5_ROW_DY[k] * s->sy + C5_ROW_DZ[k] * s->sz;
    for (int a = 0; a < 3; a++)
        s->room[a] = r->dims[a] - 3 > 0 ? (unsigned)(r->dims[a] - 3) : 0;
}

/* The rows into row[k * stride] (k < 12, a voxel a byte, x = i - 1 lowest), where no index
 * needs a clamp (1 <= i, i + 2 <= dims - 1 on every axis: the same voxels c5_gather_diffs_to
 * reads, and those beside them in x, all in the cell's box): 1, else 0 and nothing read. */
static inline int c5_gather_rows_at(const c5_rows_src *s, const int64_t pos[3], uint32_t *row, ptrdiff_t stride)
{
    int i3[3];
    for (int a = 0; a < 3; a++) {
        int i = (int)((pos[a] - (1 << (C5_POS_F - 1))) >> C5_POS_F);
        if ((unsigned)(i - 1) >= s->room[a])
            return 0;
        i3[a] = i;
    }
    const uint8_t *b = s->v + (s->at0 + i3[0] + i3[1] * s->sy + i3[2] * s->sz);
    for (int k = 0; k < 12; k++) {
        uint32_t w;
        memcpy(&w, b + s->off[k], 4); /* one load: the voxels in memory order */
#if __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
        w = __builtin_bswap32(w);
#endif
        row[k * stride] = w;
    }
    return 1;
}

/* The row (C5_ROW_DY, C5_ROW_DZ) = (dy, dz), as C5_ROW_OF[dy + 1][dz + 1] (0 where there is none). */
static const int8_t C5_ROW_OF[4][4] = {{0, 4, 6, 0}, {8, 0, 2, 10}, {9, 1, 3, 11}, {0, 5, 7, 0}};
static inline int c5_row_at(int dy, int dz) { return C5_ROW_OF[dy + 1][dz + 1]; }

/* The central differences (c5_corners.d) from the rows of c5_gather_rows_at (row[k * stride]). */
static inline void c5_rows_diffs(const uint32_t *row, ptrdiff_t stride, int32_t d[3][8])
{
#define C5_ROW_BYTE(dy, dz, x) ((int32_t)(row[c5_row_at(dy, dz) * stride] >> (8 * (x)) & 255))
    for (int kz = 0; kz < 2; kz++)
        for (int ky = 0; ky < 2; ky++)
            for (int kx = 0; kx < 2; kx++) {
                int j = kx + 2 * ky + 4 * kz;
                d[0][j] = C5_ROW_BYTE(ky, kz, kx + 2) - C5_ROW_BYTE(ky, kz, kx);
                d[1][j] = C5_ROW_BYTE(ky + 1, kz, kx + 1) - C5_ROW_BYTE(ky - 1, kz, kx + 1);
                d[2][j] = C5_ROW_BYTE(ky, kz + 1, kx + 1) - C5_ROW_BYTE(ky, kz - 1, kx + 1);
            }
#undef C5_ROW_BYTE
}

static inline void c5_gather_diffs(const c5_frame_regs *r, const c5_rdram *m, const int64_t pos[3], c5_corners *k)
{
    c5_gather_diffs_to(r, m, pos, &k->d[0][0], 8, 1);
}

static inline void c5_gather(const c5_frame_regs *r, const c5_rdram *m, const int64_t pos[3], int want_grad,
                             c5_corners *k)
{
    c5_gather_values(r, m, pos, k);
    if (want_grad)
        c5_gather_diffs(r, m, pos, k);
}

/* The 8 trilinear weights (45 fraction bits) of the fractions, corner k = kx + 2 ky + 4 kz. */
static inline void c5_tri_weights(const int64_t frac[3], int64_t wt[8])
{
    /* Written out: (w_x w_y) w_z, the products of the loop over j in the same order,
     * with the four x-y products formed once instead of twice. */
    const int64_t one = 1 << C5_POS_F;
    const int64_t x0 = one - frac[0], x1 = frac[0], y0 = one - frac[1], y1 = frac[1];
    const int64_t z0 = one - frac[2], z1 = frac[2];
    const int64_t xy0 = x0 * y0, xy1 = x1 * y0, xy2 = x0 * y1, xy3 = x1 * y1;
    wt[0] = xy0 * z0;
    wt[1] = xy1 * z0;
    wt[2] = xy2 * z0;
    wt[3] = xy3 * z0;
    wt[4] = xy0 * z1;
    wt[5] = xy1 * z1;
    wt[6] = xy2 * z1;
    wt[7] = xy3 * z1;
}

/* sum_j wt[j] v[j], exact (|wt v| < 2^53, eight terms), written out: the sum is the same
 * integer in any order, and -O2 leaves the loop rolled. */
static inline int64_t c5_dot8(const int64_t wt[8], const int32_t v[8])
{
    return ((wt[0] * v[0] + wt[1] * v[1]) + (wt[2] * v[2] + wt[3] * v[3])) +
           ((wt[4] * v[4] + wt[5] * v[5]) + (wt[6] * v[6] + wt[7] * v[7]));
}

/* The blends on precomputed weights (the model computes them once for both). */
static inline int64_t c5_interp_blend_w(const int64_t wt[8], const int32_t v[8])
{
    C5_ROUND_AT(C5_RS_INTERP_VALUE);
    return c5_rshift_he(c5_dot8(wt, v), 45 - 8);
}

static inline void c5_grad_blend_w(const int64_t wt[8], const int32_t d[3][8], const int64_t gs[3], int64_t grad[3])
{
    for (int a = 0; a < 3; a++) {
        C5_ROUND_AT(C5_RS_GRAD_BLEND);
        int64_t blend = c5_rshift_he(c5_dot8(wt, d[a]), 45 - 8);
        C5_ROUND_AT(C5_RS_GRAD_SCALE);
        grad[a] = c5_rshift_he(blend * gs[a], 15);
    }
}

/* Block "interp": the trilinear blend of the corners (voxels 0..255) with the fractions
 * (UQ0.15), rounded once to sample_value UQ8.8. */
static inline int64_t c5_interp_blend(const int64_t frac[3], const int32_t v[8])
{
    int64_t wt[8];
    c5_tri_weights(frac, wt);
    return c5_interp_blend_w(wt, v);
}

/* Block "gradient": per axis the trilinear blend of the corners' central differences
 * (SQ8.0), rounded to SQ8.8, then scaled by gs (UQ1.15) and rounded again to SQ8.8. */
static inline void c5_grad_blend(const int64_t frac[3], const int32_t d[3][8], const int64_t gs[3], int64_t grad[3])
{
    int64_t wt[8];
    c5_tri_weights(frac, wt);
    c5_grad_blend_w(wt, d, gs, grad);
}

/* Trilinear value and (if want_grad) gradient at pos (voxel coordinates, 15 fraction bits), read from
 * the RDRAM cell: the gather, then the blends. */
static inline void c5_interp(const c5_frame_regs *r, const c5_rdram *m, const int64_t pos[3], int want_grad,
                             c5_sample *out)
{
    c5_corners k;
    int64_t wt[8];
    c5_gather(r, m, pos, want_grad, &k);
    c5_tri_weights(k.frac, wt);
    out->value = c5_interp_blend_w(wt, k.v);
    if (want_grad)
        c5_grad_blend_w(wt, k.d, r->gs, out->grad);
}

/* Table lookup, linear between entries floor(s) and floor(s) + 1 (254/255 at s = 255), of
 * channels ch0 .. ch1 - 1. */
static inline void c5_classify_channels(const c5_frame_regs *r, int64_t value, int ch0, int ch1, int64_t rgba[4])
{
    int i = (int)(value >> 8);
    int64_t f = value & 255;
    if (i > 254) {
        i = 254;
        f = 256;
    }
    C5_ROUND_AT(C5_RS_CLASSIFY_LERP);
    for (int ch = ch0; ch < ch1; ch++)
        rgba[ch] = c5_rshift_he((int64_t)r->tf[i][ch] * 256 + ((int64_t)r->tf[i + 1][ch] - r->tf[i][ch]) * f, 8);
}

static inline void c5_classify(const c5_frame_regs *r, int64_t value, int64_t rgba[4])
{
    c5_classify_channels(r, value, 0, 4, rgba);
}

/* (N.H)^p from the table, linear between its 2^10 + 1 entries (N.H in SQ1.14, > 0). */
static inline int64_t c5_spec_pow(const c5_frame_regs *r, int64_t ndh)
{
    if (ndh >= (1 << 14))
        return r->pow_tab[1 << C5_POW_BITS];
    int i = (int)(ndh >> 4);
    int64_t f = ndh & 15;
    C5_ROUND_AT(C5_RS_SHADE_POW);
    return c5_rshift_he((int64_t)r->pow_tab[i] * 16 + ((int64_t)r->pow_tab[i + 1] - r->pow_tab[i]) * f, 4);
}

/* The light term of a shaded sample from its sums over the lights (diff, 26 fraction bits;
 * spec, 27) and |g|^2 (m2, 16): then each channel of the table colour (UQ1.15) lit, into
 * shaded_rgb (UQ4.12). The integer steps that end c5_shade_w, shared with the eight-lane
 * block (shade_wide.h). */
static inline void c5_shade_finish(const c5_frame_regs *r, int64_t m2, int64_t diff, int64_t spec,
                                   const int64_t rgb[3], int64_t out[3], uint64_t *sat)
{
    int64_t k, ks = 0; /* light_term UQ4.12 */
    if (m2 == 0) {
        k = r->ka;
    } else {
        /* The lights' share fades in with the gradient: fade = min(4 |g|^2, 1) (UQ1.15; g is
         * the blend of central differences, two value steps a voxel per unit), whole from a
         * quarter of a value step a voxel, so that a gradient near zero, whose direction is
         * the data's noise, cannot switch a sample between ambient and fully lit. */
        const int64_t fade = m2 < 16384 ? 2 * m2 : C5_ONE15;
        /* light_term is UQ4.12, saturating (spec/layouts.toml): 8 lights of intensity
         * 15.9 would give ~2000. */
        C5_ROUND_AT(C5_RS_SHADE_K);
        k = c5_clamp64(r->ka + c5_rshift128_he((__int128)(r->kd * diff) * fade, 26 + 15), 0, 65535, sat);
        C5_ROUND_AT(C5_RS_SHADE_KS);
        ks = c5_clamp64(c5_rshift128_he((__int128)(r->ks * spec) * fade, 27 + 15), 0, 65535, sat);
    }
    C5_ROUND_AT(C5_RS_SHADE_CHANNEL);
    for (int ch = 0; ch < 3; ch++)
        out[ch] = c5_clamp64(c5_rshift_he(rgb[ch] * k, 15) + ks, 0, 65535, sat);
}

/* Phong shading of the table colour (UQ1.15) into shaded_rgb (UQ4.12). gpos: the sample
 * in geom coordinates (for point lights), d: the ray direction. nsh_normal: fraction bits
 * the gradient normal is narrowed by (widths.h; 0 shipped, see c5_shade). */
static inline void c5_shade_w(const c5_frame_regs *r, const c5_sample *s, const int64_t rgba[4], const int64_t gpos[3],
                              const int64_t d[3], int64_t out[3], uint64_t *sat, int nsh_normal)
{
    const int64_t *g = s->grad;
    int64_t m2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2]; /* 16 fraction bits */
    int64_t diff = 0, spec = 0;                            /* 26 and 27 fraction bits */
    if (m2 != 0) {
        int64_t mg[3] = {-g[0], -g[1], -g[2]}, n[3], v[3] = {-d[0], -d[1], -d[2]};
        C5_ROUND_AT(C5_RS_SHADE_NORMAL);
        c5_geom_normalize(mg, n);
        if (nsh_normal)
            for (int a = 0; a < 3; a++)
                n[a] = c5_narrow(n[a], nsh_normal); /* a unit vector: stays in SQ1.14 */
        C5_ROUND_AT(C5_RS_SHADE_FACING);
        if (c5_geom_dot14_dirs(n, v) < 0)
            for (int a = 0; a < 3; a++)
                n[a] = -n[a]; /* two-sided: the normal faces the viewer */
        for (int i = 0; i < r->n_lights; i++) {
            const c5_light_regs *l = &r->lights[i];
            int64_t L[3], h[3], H[3];
            if (l->kind == C5_LIGHT_POINT) {
                int64_t to[3] = {l->pos[0] - gpos[0], l->pos[1] - gpos[1], l->pos[2] - gpos[2]};
                C5_ROUND_AT(C5_RS_SHADE_LIGHT_DIR);
                c5_geom_normalize(to, L);
            } else {
                L[0] = l->dir[0], L[1] = l->dir[1], L[2] = l->dir[2];
            }
            C5_ROUND_AT(C5_RS_SHADE_NDL);
            int64_t ndl = c5_geom_dot14_dirs(n, L);
            if (ndl <= 0)
                continue;
            diff += l->intensity * ndl;
            for (int a = 0; a < 3; a++)
                h[a] = L[a] + v[a];
            C5_ROUND_AT(C5_RS_SHADE_HALF);
            if (c5_geom_normalize(h, H) == 0)
                continue;
            C5_ROUND_AT(C5_RS_SHADE_NDH);
            int64_t ndh = c5_geom_dot14_dirs(n, H);
            if (ndh > 0)
                spec += l->intensity * c5_spec_pow(r, ndh);
        }
    }
    c5_shade_finish(r, m2, diff, spec, rgba, out, sat);
}

/* The block at the shipped widths (golden vectors, vectors/gen/vec_shade.c). */
static inline void c5_shade(const c5_frame_regs *r, const c5_sample *s, const int64_t rgba[4], const int64_t gpos[3],
                            const int64_t d[3], int64_t out[3], uint64_t *sat)
{
    c5_shade_w(r, s, rgba, gpos, d, out, sat, 0);
}

/* Front-to-back compositing of one sample into the ray (spec sec. 5). Returns 1 when the
 * ray terminates early. Shadow rays only attenuate (c == NULL). */
static inline int c5_composite(const c5_frame_regs *r, c5_bray *ray, int64_t alpha, const int64_t c[3],
                               uint64_t *sat)
{
    int64_t t = C5_ONE15 - ray->opa; /* transmittance */
    if (c) {
        int64_t wta = ray->w * t * alpha; /* 45 fraction bits, < 2^46 */
        C5_ROUND_AT(C5_RS_COMPOSITE_RGB);
        /* c is shaded_rgb (UQ4.12, <= 65535: c5_shade_w saturates it), so wta c < 2^62 */
        for (int ch = 0; ch < 3; ch++)
            ray->rgb[ch] = c5_clamp64(ray->rgb[ch] + c5_rshift_he(wta * c[ch], 45), 0, C5_RGB_MAX, sat);
    }
    C5_ROUND_AT(C5_RS_COMPOSITE_OPA);
    ray->opa += c5_rshift_he(t * alpha, 15);
    return ray->opa >= r->a_max;
}

#endif
