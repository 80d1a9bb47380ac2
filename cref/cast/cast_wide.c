/* The sample loop eight samples at a time (AVX2), for CPUs that have it
 * (docs/caster.md, "Eight samples at a time").
 *
 * The same definition as cast_sample.h, lane by lane: position x = o + t d with t = j * step,
 * clamped into [0, hi]; the cell and fraction; the three rounds of lerps; the table index.
 * Each lane does the operations of the scalar definition in its order and precision: the
 * functions target AVX2 but not FMA, so no multiply and add can be fused, and a sample has
 * the same bits as on the SSE2 loop. What the eight lanes change is how the work is laid out:
 * - the eight corners of a lane's cell come from four gathers of 32 bits (pairs of voxels
 *   along x), addressed per lane, so a batch may span bricks without a branch;
 * - the sub-brick bit is gathered per lane too; a batch whose lanes are all dropped costs its
 *   positions and that gather;
 * - whether a lane's entry has opacity 0 comes from a gather of tf->lit (4 KB, in L1; the
 *   entries are 64 KB); unshaded, lanes that are not kept or have opacity 0 are composited as
 *   +0, which changes no bit (premultiplied colour), and a batch with no lit lane is not
 *   composited; shaded, each lit lane is shaded and composited in turn with the SSE2 loop's
 *   own c5_cast_shade, c5_cast_lit and c5_cast_over.
 *
 * Built only on x86-64 with the SIMD twin (C5_CAST_SIMD); the functions carry their target,
 * so the rest of the build stays at the baseline and c5_cast_wide_usable decides at run time. */
#include "cast_sample.h"

#if C5_CAST_WIDE

#include <immintrin.h>

int c5_cast_wide_usable(const c5_cast_volume *v)
{
    __builtin_cpu_init();
    if (!__builtin_cpu_supports("avx2"))
        return 0;
    if (!v)
        return 1;
    /* lane offsets are signed 32-bit: the last brick's bytes must lie below 2^31 */
    size_t n = (size_t)v->nb[0] * (size_t)v->nb[1] * (size_t)v->nb[2];
    return v->bricks && n < (size_t)(INT32_MAX / C5_CAST_BSTRIDE);
}

/* a + t (b - a) per lane, as c5_cast_lerp */
__attribute__((target("avx2"))) static inline __m256 lerp8(__m256 a, __m256 b, __m256 t)
{
    return _mm256_add_ps(a, _mm256_mul_ps(t, _mm256_sub_ps(b, a)));
}

/* Voxels (lo byte, next byte) of each lane's 32 bits, as floats. */
__attribute__((target("avx2"))) static inline void pair8(__m256i g, __m256 *a, __m256 *b)
{
    const __m256i ff = _mm256_set1_epi32(0xff);
    *a = _mm256_cvtepi32_ps(_mm256_and_si256(g, ff));
    *b = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(g, 8), ff));
}

/* Eight samples' positions: cells i, fractions f, brick bi and the offset of each cell's
 * first corner in the brick array. */
typedef struct {
    __m256i i[3];
    __m256 f[3];
    __m256i bi, off;
} batch;

/* Samples j .. j + 7. Lanes past the span's end may wrap; their positions clamp into the
 * volume, so their loads are valid, and they are never kept. */
__attribute__((target("avx2"))) static inline void positions(float step, const __m256 o[3], const __m256 d[3],
                                                             const __m256 hi[3], __m256i nb0, __m256i nb1, int64_t j,
                                                             batch *b)
{
    enum { Y = C5_CAST_DY, Z = C5_CAST_DZ };
    const __m256i seven = _mm256_set1_epi32(C5_CAST_BRICK - 1);
    __m256i jv = _mm256_add_epi32(_mm256_set1_epi32((int32_t)j), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    __m256 t = _mm256_mul_ps(_mm256_cvtepi32_ps(jv), _mm256_set1_ps(step));
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
        __m256 x = _mm256_add_ps(o[a], _mm256_mul_ps(t, d[a]));
        x = _mm256_min_ps(_mm256_max_ps(x, _mm256_setzero_ps()), hi[a]);
        b->i[a] = _mm256_cvttps_epi32(x);
        b->f[a] = _mm256_sub_ps(x, _mm256_cvtepi32_ps(b->i[a]));
    }
    b->bi = _mm256_add_epi32(
        _mm256_mullo_epi32(_mm256_add_epi32(_mm256_mullo_epi32(_mm256_srli_epi32(b->i[2], C5_CAST_BRICK_LOG2), nb1),
                                            _mm256_srli_epi32(b->i[1], C5_CAST_BRICK_LOG2)),
                           nb0),
        _mm256_srli_epi32(b->i[0], C5_CAST_BRICK_LOG2));
    /* brick bi * 768 + (i mod 8) . (1, 9, 81) */
    __m256i off = _mm256_add_epi32(_mm256_and_si256(b->i[0], seven),
                                   _mm256_mullo_epi32(_mm256_and_si256(b->i[1], seven), _mm256_set1_epi32(Y)));
    off = _mm256_add_epi32(off, _mm256_mullo_epi32(_mm256_and_si256(b->i[2], seven), _mm256_set1_epi32(Z)));
    b->off = _mm256_add_epi32(off, _mm256_mullo_epi32(b->bi, _mm256_set1_epi32(C5_CAST_BSTRIDE)));
}

/* A batch whose table entries are known, waiting to be composited: each lane's table index,
 * its lanes within the span, the kept ones, and the kept ones with opacity != 0 (as a bit mask
 * and as one mask word per lane). */
typedef struct {
    int32_t e[8];
    int32_t m[8]; /* all ones in a lit lane, else 0 */
    unsigned in, keep, lit;
    float f[3][8];  /* shaded frames: the fractions and ... */
    int32_t off[8]; /* ... the cell's offset, for the normal codes */
} ready;

/* A batch's counts: of its lanes in the span up to where the ray ends (in), the kept ones (upto)
 * were sampled, those of them not lit had opacity 0, and the rest were dropped. */
static inline void add_counts(c5_cast_counts *cnt, unsigned in, unsigned upto, unsigned lit)
{
    cnt->samples += (unsigned)__builtin_popcount(upto);
    cnt->zero += (unsigned)__builtin_popcount(upto & ~lit);
    cnt->sub += (unsigned)__builtin_popcount(in & ~upto);
}

/* Composites batch b into *C, adding its counts; 1 when the ray ends in it. The lanes'
 * entries in order, unlit ones as +0 (no branch on which lanes are lit); a batch that takes
 * the ray past opacity is composited again lane by lane from its start, to stop at the sample
 * where the one-sample loop stops. */
__attribute__((target("avx2"))) static inline int composite(const float (*rgba)[4], int early, const ready *b,
                                                            __m128 *acc, c5_cast_counts *cnt)
{
    const __m128 one = _mm_set1_ps(1);
    __m128 C = *acc;
    unsigned in = b->in, upto = b->keep; /* the kept lanes up to where the ray ends */
    int done = 0;
    if (b->lit) { /* else nothing to add: every kept sample has opacity 0 */
#pragma GCC unroll 8
        for (int q = 0; q < 8; q++) {
            __m128 s = _mm_and_ps(_mm_loadu_ps(rgba[b->e[q]]), _mm_broadcast_ss((const float *)&b->m[q]));
            C = _mm_add_ps(C, _mm_mul_ps(_mm_sub_ps(one, _mm_shuffle_ps(C, C, _MM_SHUFFLE(3, 3, 3, 3))), s));
        }
        if (early && _mm_cvtss_f32(_mm_shuffle_ps(C, C, 3)) > C5_CAST_OPAQUE) {
            C = *acc;
            for (unsigned rest = b->lit; rest; rest &= rest - 1) {
                int q = __builtin_ctz(rest);
                C = _mm_add_ps(C, _mm_mul_ps(_mm_sub_ps(one, _mm_shuffle_ps(C, C, _MM_SHUFFLE(3, 3, 3, 3))),
                                             _mm_loadu_ps(rgba[b->e[q]])));
                if (_mm_cvtss_f32(_mm_shuffle_ps(C, C, 3)) > C5_CAST_OPAQUE) {
                    unsigned through = (2u << q) - 1;
                    upto &= through, in &= through;
                    break;
                }
            }
            cnt->terminated++;
            done = 1;
        }
    }
    add_counts(cnt, in, upto, b->lit);
    *acc = C;
    return done;
}

/* As composite, shaded: each lit lane's headlight factors from its cell's 8 normal codes
 * (c5_cast_shade, the SSE2 loop's own), in order, with early termination per sample. */
__attribute__((target("avx2"))) static inline int composite_shaded(const c5_cast_view *vw, const ready *b,
                                                                   __m128 *acc, c5_cast_counts *cnt)
{
    const float(*rgba)[4] = vw->tf->rgba;
    const uint16_t *normals = vw->v->normals;
    __m128 C = *acc;
    unsigned in = b->in, upto = b->keep;
    int done = 0;
    for (unsigned rest = b->lit; rest; rest &= rest - 1) {
        int q = __builtin_ctz(rest);
        c5_cast_pos p;
        p.i = _mm_setzero_si128();
        p.f = _mm_setr_ps(b->f[0][q], b->f[1][q], b->f[2][q], 0);
        C = c5_cast_over(C, c5_cast_lit(rgba[b->e[q]], c5_cast_shade(vw->shade, normals + b->off[q], p)));
        if (vw->early && c5_cast_rgba_alpha(C) > C5_CAST_OPAQUE) {
            unsigned through = (2u << q) - 1;
            upto &= through, in &= through;
            cnt->terminated++;
            done = 1;
            break;
        }
    }
    add_counts(cnt, in, upto, b->lit);
    *acc = C;
    return done;
}

/* Software-pipelined: batch n + 1's positions are computed (and its cells prefetched) while
 * batch n's voxels are read, and batch n's entries are composited after batch n + 1's are
 * known, so that the serial compositing of one batch overlaps the gathers of the next. A
 * batch's counts are added only once the batches before it have not ended the ray. */
__attribute__((target("avx2"))) int c5_cast_wide_span(const c5_cast_view *vw, const c5_cast_ray *r, int32_t j0,
                                                       int32_t j1, c5_cast_rgba *acc, c5_cast_counts *cnt)
{
    enum { X = C5_CAST_DX, Y = C5_CAST_DY, Z = C5_CAST_DZ };
    const float(*rgba)[4] = vw->tf->rgba;
    const c5_cast_volume *v = vw->v;
    const uint8_t *bricks = v->bricks, *sub_mask = vw->sub_mask, *lit = vw->tf->lit;
    const uint16_t *normals = v->normals;
    const int skip = vw->sub_skip, early = vw->early, shading = vw->shading;
    const int cells = vw->prefetch == C5_CAST_PREFETCH_CELLS;
    const __m256 o[3] = {_mm256_set1_ps(r->o[0]), _mm256_set1_ps(r->o[1]), _mm256_set1_ps(r->o[2])};
    const __m256 d[3] = {_mm256_set1_ps(r->d[0]), _mm256_set1_ps(r->d[1]), _mm256_set1_ps(r->d[2])};
    const __m256 hi[3] = {_mm256_set1_ps(r->hi[0]), _mm256_set1_ps(r->hi[1]), _mm256_set1_ps(r->hi[2])};
    const __m256i nb0 = _mm256_set1_epi32(v->nb[0]), nb1 = _mm256_set1_epi32(v->nb[1]);
    const __m256i one = _mm256_set1_epi32(1), lane_bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    const __m256 scale = _mm256_set1_ps((float)C5_CAST_TF_SCALE), half = _mm256_set1_ps(0.5f);
    __m128 C = *acc;
    ready rd[2];
    int pending = -1; /* the slot of rd waiting to be composited */
    batch bt[2]; /* this batch and the next, by turns */
    int now = 0;
    positions(r->step, o, d, hi, nb0, nb1, j0, &bt[0]);
    for (int64_t jb = j0; jb <= j1; jb += 8, now ^= 1) {
        int64_t left = j1 - jb + 1;
        unsigned in = left >= 8 ? 0xffu : (1u << left) - 1; /* lanes within the span */
        const batch *b = &bt[now];
        if (jb + 8 <= j1) /* the next batch's positions */
            positions(r->step, o, d, hi, nb0, nb1, jb + 8, &bt[now ^ 1]);
        if (cells && jb + 8 <= j1) { /* and its cells, a batch before they are read */
            int32_t a[8];
            _mm256_storeu_si256((__m256i *)a, bt[now ^ 1].off);
#pragma GCC unroll 8
            for (int q = 0; q < 8; q++) {
                __builtin_prefetch(bricks + a[q]);
                __builtin_prefetch(bricks + a[q] + Z + Y + X);
            }
            if (shading) /* the normal codes' rows c5_cast_shade reads */
                for (int q = 0; q < 8; q++) {
                    const uint16_t *n = normals + a[q];
                    __builtin_prefetch(n);
                    __builtin_prefetch(n + Y + X);
                    __builtin_prefetch(n + Z);
                    __builtin_prefetch(n + Z + Y + X);
                }
        }
        unsigned keep = in;
        if (skip) {
            /* sub-brick s = sx + 2 sy + 4 sz; its bit in the brick's mask (sub_mask has 3 bytes
             * of padding for the 32-bit gather) */
            __m256i s = _mm256_and_si256(_mm256_srli_epi32(b->i[0], C5_CAST_SUB_LOG2), one);
            s = _mm256_or_si256(s, _mm256_slli_epi32(_mm256_and_si256(_mm256_srli_epi32(b->i[1], C5_CAST_SUB_LOG2), one), 1));
            s = _mm256_or_si256(s, _mm256_slli_epi32(_mm256_and_si256(_mm256_srli_epi32(b->i[2], C5_CAST_SUB_LOG2), one), 2));
            __m256i m = _mm256_i32gather_epi32((const int *)sub_mask, b->bi, 1);
            __m256i bit = _mm256_slli_epi32(_mm256_srlv_epi32(m, s), 31);
            keep &= (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(bit));
        }
        int slot = pending == 0;
        ready *cur = &rd[slot];
        cur->in = in, cur->keep = keep;
        if (keep) {
            const __m256i off = b->off;
            const __m256 *f = b->f;
            __m256 c[8];
            pair8(_mm256_i32gather_epi32((const int *)bricks, off, 1), &c[0], &c[1]);
            pair8(_mm256_i32gather_epi32((const int *)(bricks + Y), off, 1), &c[2], &c[3]);
            pair8(_mm256_i32gather_epi32((const int *)(bricks + Z), off, 1), &c[4], &c[5]);
            pair8(_mm256_i32gather_epi32((const int *)(bricks + Z + Y), off, 1), &c[6], &c[7]);
            __m256 x00 = lerp8(c[0], c[1], f[0]), x10 = lerp8(c[2], c[3], f[0]);
            __m256 x01 = lerp8(c[4], c[5], f[0]), x11 = lerp8(c[6], c[7], f[0]);
            __m256 val = lerp8(lerp8(x00, x10, f[1]), lerp8(x01, x11, f[1]), f[2]);
            __m256i idx = _mm256_cvttps_epi32(_mm256_add_ps(_mm256_mul_ps(val, scale), half));
            __m256i nz = _mm256_slli_epi32(_mm256_i32gather_epi32((const int *)lit, idx, 1), 31); /* lit[idx] */
            cur->lit = keep & (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(nz));
            __m256i bits = _mm256_and_si256(_mm256_set1_epi32((int)cur->lit), lane_bit);
            _mm256_storeu_si256((__m256i *)cur->m, _mm256_cmpeq_epi32(bits, lane_bit));
            if (shading) {
                for (int a = 0; a < 3; a++)
                    _mm256_storeu_ps(cur->f[a], f[a]);
                _mm256_storeu_si256((__m256i *)cur->off, off);
            }
            _mm256_storeu_si256((__m256i *)cur->e, idx);
        }
        if (pending >= 0 && (shading ? composite_shaded(vw, &rd[pending], &C, cnt)
                                     : composite(rgba, early, &rd[pending], &C, cnt))) {
            *acc = C;
            return 1;
        }
        pending = -1;
        if (keep)
            pending = slot;
        else
            cnt->sub += (unsigned)__builtin_popcount(in);
    }
    int done = pending >= 0 && (shading ? composite_shaded(vw, &rd[pending], &C, cnt)
                                        : composite(rgba, early, &rd[pending], &C, cnt));
    *acc = C;
    return done;
}

#endif
