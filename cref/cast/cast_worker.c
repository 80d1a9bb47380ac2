/* The workers (the paper's SPEs, sec. 5.1): march the producer's segments of each pixel's
 * ray, reconstruct trilinearly inside one brick, classify, shade, composite front to back
 * with early ray termination, and prefetch what the ray reads next (docs/caster.md, "Prefetch").
 *
 * Exactness across modes: sample j of a ray sits at t = j * step from the eye, computed from
 * j alone; a skipped sample has opacity exactly 0, and compositing such a sample adds +0 to
 * colour and opacity. So any mode that skips only such samples draws the same bits. */
#include <math.h>
#include <string.h>

#include "cast_internal.h"
#include "cast_sample.h"

/* The prefetch helpers are always inlined: GCC 12 deems a function whose body is only
 * __builtin_prefetch free of side effects and deletes its calls (-O1 and up), which left the
 * brick prefetch out of most builds until 2026-11-21 (docs/caster.md). tests/prefetch_test.sh
 * looks for them in the object file. */

/* The whole brick bi (values, and normal codes when shading). */
static inline __attribute__((always_inline)) void prefetch_brick(const c5_cast_view *vw, size_t bi)
{
    const char *b = (const char *)(vw->v->bricks + bi * C5_CAST_BSTRIDE);
#pragma GCC unroll 12 /* one prefetch per line, no loop around them */
    for (int i = 0; i < C5_CAST_BSTRIDE; i += 64)
        __builtin_prefetch(b + i);
    if (vw->shading) {
        const char *n = (const char *)(vw->v->normals + bi * C5_CAST_BSTRIDE);
        for (int i = 0; i < C5_CAST_BSTRIDE * 2; i += 64)
            __builtin_prefetch(n + i);
    }
}

/* The cell of a kept sample, issued in stage 1 of march_span, a batch (some hundred cycles)
 * before stages 2 and 3 load it. Values from the cell's first corner v: the lines of its first
 * and last corner in the two 16-byte loads of c5_cast_tri. */
static inline __attribute__((always_inline)) void prefetch_cell_values(const uint8_t *v)
{
    __builtin_prefetch(v);
    __builtin_prefetch(v + C5_CAST_DZ + C5_CAST_DY + C5_CAST_DX);
}

/* Normal codes from the cell's first n: the first and last code of each pair of rows that
 * c5_cast_shade reads. */
static inline __attribute__((always_inline)) void prefetch_cell_codes(const uint16_t *n)
{
    enum { X = C5_CAST_DX, Y = C5_CAST_DY, Z = C5_CAST_DZ };
    __builtin_prefetch(n);
    __builtin_prefetch(n + Y + X);
    __builtin_prefetch(n + Z);
    __builtin_prefetch(n + Z + Y + X);
}

/* The brick a ray is in, carried across its segments. */
typedef struct {
    c5_cast_bkey key;
    const uint8_t *b;
    const uint16_t *n;
    int hashed;             /* the refining hash drops the whole brick */
    unsigned sub;           /* the sub-bricks whose samples are marched: the non-empty ones (all
                               when not skipping), none when hashed */
} brick_state;

/* The brick coordinates of a position. */
static inline void brick_of(c5_cast_pos p, int b[3])
{
    for (int a = 0; a < 3; a++)
        b[a] = c5_cast_pos_cell(p, a) >> C5_CAST_BRICK_LOG2;
}

/* The TF entry (premultiplied colour, opacity) of the sample at p in the cell whose first
 * corner is v: its trilinear value rounded to the table's nearest 1/16. */
static inline const float *classify(const float (*rgba)[4], const uint8_t *v, c5_cast_pos p)
{
    return rgba[(int)(c5_cast_tri(v, p) * C5_CAST_TF_SCALE + 0.5f)];
}

/* Samples in flight between the stages of march_span. */
enum { BATCH = 16 };

/* Marches samples j0..j1 of one ray, compositing into acc. Returns 1 when the ray terminated
 * early. Inlined with constant `shading` and `hash` (NULL or not), so each variant's loop has
 * no test it does not need.
 *
 * In stages over batches of up to BATCH kept samples, each a loop whose iterations do not
 * wait on one another: (1) positions, bricks and prefetch, keeping the samples the sub-brick
 * mask (or the refining hash) keeps; (2) their trilinear values and TF entries, the ones with
 * a != 0 appended to a second list without a branch; (3) shading and compositing of those, in
 * order, with early termination (unshaded, (2) composites). One loop over it all made each
 * shaded sample a chain of ~100 cycles that the out-of-order window overlapped with little
 * more than one other sample. A sample with a == 0 adds +0 to the colour and leaves A, so
 * leaving it out of (3) changes no bit, nor where the ray ends; the counts stop at the
 * terminating sample as if the stages had run one sample at a time. */
static inline __attribute__((always_inline)) int march_span(const c5_cast_view *vw, const c5_cast_ray *r, int32_t j0,
                                                            int32_t j1, int32_t jout, const uint64_t *hash,
                                                            const int shading, c5_cast_rgba *acc, brick_state *bs,
                                                            c5_cast_counts *cnt)
{
    const float(*rgba)[4] = vw->tf->rgba;
    const float(*shade)[2] = vw->shade;
    const int cells = vw->prefetch == C5_CAST_PREFETCH_CELLS, bricks = vw->prefetch == C5_CAST_PREFETCH_BRICKS;
    const int early = vw->early, lookahead = vw->lookahead;
    c5_cast_rgba C = *acc;
    c5_cast_bkey bkey = bs->key;
    struct {
        c5_cast_pos p;
        const uint8_t *v;  /* the cell's first corner */
        const uint16_t *n; /* its normal codes */
        int32_t j;
        uint32_t hashed; /* hashed drops of this batch before this sample */
    } kept[BATCH];
    const float *lit[BATCH]; /* TF entries with a != 0 ... */
    int from[BATCH];         /* ... and their index in kept */
    int done = 0;
    for (int32_t j = j0; j <= j1 && !done;) {
        int32_t jb = j;
        int m = 0;
        uint32_t hashed = 0;
        for (; j <= j1; j++) {
            c5_cast_pos p = c5_cast_pos_at(r, j);
            c5_cast_bkey key = c5_cast_pos_bkey(p);
            if (!c5_cast_bkey_eq(key, bkey)) {
                bkey = key;
                int bc[3];
                brick_of(p, bc);
                size_t bi = c5_cast_brick_index(vw->v, bc[0], bc[1], bc[2]);
                bs->b = vw->v->bricks + bi * C5_CAST_BSTRIDE;
                if (shading)
                    bs->n = vw->v->normals + bi * C5_CAST_BSTRIDE;
                bs->sub = vw->sub_skip ? vw->sub_mask[bi] : 0xffu;
                if (hash) {
                    uint32_t hk = c5_cast_hash_key(vw, bc[0], bc[1], bc[2]);
                    bs->hashed = !(hash[hk / 64] >> (hk % 64) & 1);
                    bs->sub = bs->hashed ? 0 : bs->sub;
                }
                if (bricks) {
                    int nc[3];
                    brick_of(c5_cast_pos_at(r, j + lookahead < jout ? j + lookahead : jout), nc);
                    if (nc[0] != bc[0] || nc[1] != bc[1] || nc[2] != bc[2])
                        prefetch_brick(vw, c5_cast_brick_index(vw->v, nc[0], nc[1], nc[2]));
                }
            }
            /* one test drops both: a hashed brick's samples and an empty sub-brick's (the TF is
             * zero over its range: opacity 0) */
            if (!(bs->sub >> c5_cast_pos_sub(p) & 1)) {
                if (hash)
                    hashed += (unsigned)bs->hashed;
                continue;
            }
            int off = c5_cast_pos_off(p);
            kept[m].p = p, kept[m].v = bs->b + off, kept[m].j = j;
            if (cells)
                prefetch_cell_values(kept[m].v);
            if (shading) {
                kept[m].n = bs->n + off;
                if (cells)
                    prefetch_cell_codes(kept[m].n);
            }
            if (hash)
                kept[m].hashed = hashed;
            if (++m == BATCH) {
                j++;
                break;
            }
        }
        int nz = 0, last = -1; /* nz of the m kept are non-zero; last: the one the ray ended at */
        if (!shading) { /* nothing to wait for after the TF entry: (2) composites */
            for (int q = 0; q < m; q++) {
                const float *e = classify(rgba, kept[q].v, kept[q].p);
                C = c5_cast_over(C, c5_cast_rgba_load(e));
                nz += e[3] != 0;
                if (early && c5_cast_rgba_alpha(C) > C5_CAST_OPAQUE) {
                    last = q;
                    break;
                }
            }
        }
        for (int q = 0; shading && q < m; q++) {
            const float *e = classify(rgba, kept[q].v, kept[q].p);
            lit[nz] = e, from[nz] = q;
            nz += e[3] != 0;
        }
        for (int s = 0; shading && s < nz; s++) {
            int q = from[s];
            C = c5_cast_over(C, c5_cast_lit(lit[s], c5_cast_shade(shade, kept[q].n, kept[q].p)));
            if (early && c5_cast_rgba_alpha(C) > C5_CAST_OPAQUE) {
                last = q, nz = s + 1;
                break;
            }
        }
        int32_t jend = j; /* positions jb..jend-1 were looked at */
        if (last >= 0) { /* the counts stop at the terminating sample */
            cnt->terminated++;
            done = 1;
            jend = kept[last].j + 1, hashed = hash ? kept[last].hashed : 0, m = last + 1;
        }
        cnt->samples += (unsigned)m, cnt->zero += (unsigned)(m - nz), cnt->hashed += hashed;
        cnt->sub += (unsigned)(jend - jb - m) - hashed;
    }
    bs->key = bkey;
    *acc = C;
    return done;
}

/* The ray o + t d (voxel units per world t; inv[a] = 1/d[a], unused where d[a] == 0) against
 * the box [lo, hi]: 1 and its entry and exit t (entry clamped to t >= 0), or 0 on a miss. */
static int slab(const double o[3], const double d[3], const double inv[3], const double lo[3],
                               const double hi[3], double *tn, double *tf)
{
    double a = 0, b = 1.0 / 0.0;
    for (int i = 0; i < 3; i++) {
        if (d[i] == 0) {
            if (o[i] < lo[i] || o[i] > hi[i])
                return 0;
            continue;
        }
        double s0 = (lo[i] - o[i]) * inv[i], s1 = (hi[i] - o[i]) * inv[i];
        if (s0 > s1) {
            double s = s0;
            s0 = s1, s1 = s;
        }
        a = s0 > a ? s0 : a;
        b = s1 < b ? s1 : b;
    }
    *tn = a, *tf = b;
    return a <= b;
}

int c5_cast_pixel_ray(const c5_cast_view *vw, int px, int py, c5_cast_ray *r, int32_t *jin, int32_t *jout)
{
    const c5_cast_volume *v = vw->v;
    if (!v->bricks)
        return 0;
    double d[3], o[3], dv[3], inv[3], tin, tout, lo[3] = {0, 0, 0};
    c5_cast_ray_dir(vw, px + 0.5, py + 0.5, d);
    for (int a = 0; a < 3; a++) {
        o[a] = vw->eye_v[a];
        dv[a] = d[a] / v->spacing[a];
        inv[a] = dv[a] != 0 ? 1 / dv[a] : 0;
    }
    *r = (c5_cast_ray){.o = {(float)o[0], (float)o[1], (float)o[2], 0},
                       .d = {(float)dv[0], (float)dv[1], (float)dv[2], 0},
                       .hi = {vw->clamp_hi[0], vw->clamp_hi[1], vw->clamp_hi[2], 0},
                       .step = (float)vw->step};
    if (!slab(o, dv, inv, lo, vw->box_hi, &tin, &tout))
        return 0;
    double jd_in = ceil(tin / vw->step), jd_out = floor(tout / vw->step);
    if (jd_out > C5_CAST_J_MAX)
        jd_out = C5_CAST_J_MAX;
    if (jd_in > jd_out)
        return 0;
    *jin = (int32_t)jd_in, *jout = (int32_t)jd_out;
    return 1;
}

static void march(const c5_cast_view *vw, int px, int py, const c5_cast_seg *seg, int nseg, const uint64_t *hash,
                  float out[3], c5_cast_counts *cnt)
{
    out[0] = out[1] = out[2] = 0;
    c5_cast_ray r;
    int32_t jin, jout;
    if (!nseg || !c5_cast_pixel_ray(vw, px, py, &r, &jin, &jout)) /* nothing to march: no ray set-up either */
        return;
    c5_cast_rgba acc = c5_cast_rgba_zero();
    brick_state bs = {c5_cast_bkey_none(), NULL, NULL, 0, 0xffu};
    for (int s = 0; s < nseg; s++) {
        int32_t j0 = seg[s].j0 > jin ? seg[s].j0 : jin, j1 = seg[s].j1 < jout ? seg[s].j1 : jout;
        int stop;
#if C5_CAST_WIDE
        if (vw->wide)
            stop = c5_cast_wide_span(vw, &r, j0, j1, &acc, cnt);
        else
#endif
        if (vw->shading)
            stop = hash ? march_span(vw, &r, j0, j1, jout, hash, 1, &acc, &bs, cnt)
                        : march_span(vw, &r, j0, j1, jout, NULL, 1, &acc, &bs, cnt);
        else
            stop = hash ? march_span(vw, &r, j0, j1, jout, hash, 0, &acc, &bs, cnt)
                        : march_span(vw, &r, j0, j1, jout, NULL, 0, &acc, &bs, cnt);
        if (stop)
            break;
    }
    for (int c = 0; c < 3; c++)
        out[c] = c5_cast_rgba_at(acc, c);
}

void c5_cast_work(const c5_cast_view *vw, const c5_cast_task *t, float *rgb, c5_cast_counts *cnt)
{
    int u = 0;
    for (int uy = 0; uy < t->units_y; uy++)
        for (int ux = 0; ux < t->units_x; ux++, u++) {
            const c5_cast_seg *seg = t->seg + t->first[u];
            int nseg = (int)(t->first[u + 1] - t->first[u]);
            const uint64_t *hash = vw->mode == C5_CAST_APPROX_REFINE ? t->hash[u] : NULL;
            int px0 = t->x0 + ux * t->unit, py0 = t->y0 + uy * t->unit;
            for (int py = py0; py < py0 + t->unit && py < vw->h; py++)
                for (int px = px0; px < px0 + t->unit && px < vw->w && px < t->x0 + C5_CAST_TILE; px++)
                    march(vw, px, py, seg, nseg, hash, rgb + 3 * ((size_t)py * vw->w + px), cnt);
        }
}
