/* The interpolation and classification blocks of eight samples at once (value_wide.h). */
#include "value_wide.h"

#include "sample_pipe.h"
#include "shade_wide.h"
#include "wide_lanes.h"

#if C5_WIDE

/* One table channel (entries at ch0[4 i]) at entry idx / 4, fraction f. */
WIDE static inline __m256i classify_lanes(const int32_t *ch0, __m256i idx, __m256i f)
{
    __m256i t0 = _mm256_i32gather_epi32(ch0, idx, 4), t1 = _mm256_i32gather_epi32(ch0 + 4, idx, 4);
    __m256i x = _mm256_add_epi32(_mm256_slli_epi32(t0, 8), _mm256_mullo_epi32(_mm256_sub_epi32(t1, t0), f));
    __m256i q = _mm256_srai_epi32(x, 8), rem = _mm256_and_si256(x, _mm256_set1_epi32(255));
    __m256i up = _mm256_add_epi32(rem, _mm256_add_epi32(_mm256_set1_epi32(127), _mm256_and_si256(q, _mm256_set1_epi32(1))));
    return _mm256_add_epi32(q, _mm256_srai_epi32(up, 8));
}

/* The blend and the classification (value_wide.h says why they are exact). */
WIDE static int value_wide(const c5_frame_regs *r, const c5_rdram *m, const int64_t pos[3], const int64_t S[3],
                           int n, c5_value_lanes *o)
{
    ptrdiff_t sy, sz, o0;
    const uint8_t *v = c5_rdram_data(m, &o0, &sy, &sz);
    /* The first and last sample bound every lane's corner indices (each is monotone along the
     * ray): none needs a clamp, x has one voxel more either side for the four-byte reads
     * below, and the largest offset read fits in 32 bits. */
    int64_t top = o0 + 2;
    for (int a = 0; a < 3; a++) {
        int64_t i0 = (pos[a] - (1 << (C5_POS_F - 1))) >> C5_POS_F;
        int64_t i1 = (pos[a] + (n - 1) * S[a] - (1 << (C5_POS_F - 1))) >> C5_POS_F;
        int64_t lo = i0 < i1 ? i0 : i1, hi = i0 < i1 ? i1 : i0;
        if (a == 0 ? lo < 1 || hi > r->dims[0] - 3 : lo < 0 || hi > r->dims[a] - 2)
            return -1;
        top += (hi + 1 - m->org[a]) * (a == 0 ? 1 : a == 1 ? sy : sz);
    }
    if (top >= INT32_MAX)
        return -1;
    /* Positions below 2^28 (C5_MODEL_MAX_GRID voxels of 2^15): 32-bit lanes; the lanes past n
     * repeat the last sample. */
    __m256i j = _mm256_min_epi32(_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), _mm256_set1_epi32(n - 1));
    __m256i off = _mm256_set1_epi32((int)(o0 - 1)), t[3];
    int32_t fr[3][8]; /* the fractions; o is written only at the end, after every refusal */
    for (int a = 0; a < 3; a++) {
        __m256i p = _mm256_add_epi32(_mm256_set1_epi32((int32_t)pos[a]), _mm256_mullo_epi32(j, _mm256_set1_epi32((int32_t)S[a])));
        t[a] = _mm256_srli_epi32(p, C5_POS_F + 2); /* c5_cache_tag_of's fields: 4^3 voxels */
        __m256i x = _mm256_sub_epi32(p, _mm256_set1_epi32(1 << (C5_POS_F - 1)));
        _mm256_storeu_si256((__m256i *)fr[a], _mm256_and_si256(x, _mm256_set1_epi32((1 << C5_POS_F) - 1)));
        __m256i i = _mm256_sub_epi32(_mm256_srai_epi32(x, C5_POS_F), _mm256_set1_epi32(m->org[a]));
        off = _mm256_add_epi32(off, a == 0 ? i : _mm256_mullo_epi32(i, _mm256_set1_epi32((int32_t)(a == 1 ? sy : sz))));
    }
    /* Per lane the four voxels x = i - 1 .. i + 2 of each corner row (y, z): the corners are
     * its bytes 1 and 2. */
    const int *base = (const int *)(const void *)v;
    __m256i row[4];
    for (int k = 0; k < 4; k++)
        row[k] = _mm256_i32gather_epi32(base, _mm256_add_epi32(off, _mm256_set1_epi32((int)((k & 1) * sy + (k >> 1) * sz))), 1);
    __m256i c[8];
    for (int k = 0; k < 8; k++)
        c[k] = _mm256_and_si256(_mm256_srli_epi32(row[k >> 1], 8 + 8 * (k & 1)), _mm256_set1_epi32(255));
    const v8 one = set1(1 << C5_POS_F);
    v8 w1[3], w0[3];
    for (int a = 0; a < 3; a++) {
        w1[a] = lanes32(fr[a]);
        w0[a] = sub(one, w1[a]);
    }
    v8 xy[4] = {mul(w0[0], w0[1]), mul(w1[0], w0[1]), mul(w0[0], w1[1]), mul(w1[0], w1[1])};
    v8 sum = set1(0);
    for (int k = 0; k < 8; k++)
        sum = add(sum, mul(mul(xy[k & 3], k < 4 ? w0[2] : w1[2]), lanes_i(c[k])));
    v8 val = rne(mul(sum, set1(0x1p-37)));
    __m256i value = _mm256_set_m128i(_mm256_cvtpd_epi32(val.h[1]), _mm256_cvtpd_epi32(val.h[0]));
    __m256i i = _mm256_srai_epi32(value, 8), f = _mm256_and_si256(value, _mm256_set1_epi32(255));
    __m256i over = _mm256_cmpgt_epi32(i, _mm256_set1_epi32(254));
    i = _mm256_blendv_epi8(i, _mm256_set1_epi32(254), over);
    f = _mm256_blendv_epi8(f, _mm256_set1_epi32(256), over);
    /* Each channel as c5_classify_channels: linear between entries i and i + 1, rounded half
     * to even by 8 bits (every intermediate below 2^24); the colour where any lane has an
     * opacity, the only lanes that read it. */
    __m256i idx = _mm256_slli_epi32(i, 2);
    __m256i alpha = classify_lanes(&r->tf[0][3], idx, f);
    _mm256_storeu_si256((__m256i *)o->value, value);
    _mm256_storeu_si256((__m256i *)o->alpha, alpha);
    _mm256_storeu_si256((__m256i *)o->frac[0], _mm256_loadu_si256((const __m256i *)fr[0]));
    _mm256_storeu_si256((__m256i *)o->frac[1], _mm256_loadu_si256((const __m256i *)fr[1]));
    _mm256_storeu_si256((__m256i *)o->frac[2], _mm256_loadu_si256((const __m256i *)fr[2]));
    __m256i yx = _mm256_or_si256(_mm256_slli_epi32(t[1], 16), t[0]);
    for (int h = 0; h < 2; h++) {
        __m128i lo = h ? _mm256_extracti128_si256(yx, 1) : _mm256_castsi256_si128(yx);
        __m128i z = h ? _mm256_extracti128_si256(t[2], 1) : _mm256_castsi256_si128(t[2]);
        __m256i tag = _mm256_or_si256(_mm256_slli_epi64(_mm256_cvtepu32_epi64(z), 32), _mm256_cvtepu32_epi64(lo));
        _mm256_storeu_si256((__m256i *)(o->tag + 4 * h), tag);
    }
    o->lit = (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(alpha, _mm256_setzero_si256()))) &
             ((1u << n) - 1);
    if (o->lit)
        for (int ch = 0; ch < 3; ch++)
            _mm256_storeu_si256((__m256i *)o->rgb[ch], classify_lanes(&r->tf[0][ch], idx, f));
    return 0;
}

int c5_value_wide(const c5_frame_regs *r, const c5_rdram *m, const int64_t pos[3], const int64_t S[3], int n,
                  c5_value_lanes *o)
{
    return c5_shade_wide_usable() && n >= 1 && n <= C5_VALUE_LANES ? value_wide(r, m, pos, S, n, o) : -1;
}

#else

int c5_value_wide(const c5_frame_regs *r, const c5_rdram *m, const int64_t pos[3], const int64_t S[3], int n,
                  c5_value_lanes *o)
{
    (void)r, (void)m, (void)pos, (void)S, (void)n, (void)o;
    return -1;
}

#endif
