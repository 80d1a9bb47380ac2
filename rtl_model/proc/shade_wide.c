/* Four samples' shading on AVX2 and FMA (shade_wide.h). Only the functions marked with the
 * target use those units, so the rest of the build stays at the baseline and c5_shade4_wide
 * decides at run time. The round-probe build (C5_ROUND_PROBE) shades sample by sample: its
 * probes sit in c5_shade_w's steps. */
#include "shade_wide.h"

#include "sample_pipe.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(C5_ROUND_PROBE)
#define C5_SHADE_WIDE 1
#else
#define C5_SHADE_WIDE 0
#endif

static void shade4_scalar(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b)
{
    for (int i = 0; i < b->n; i++) {
        c5_sample smp = {.value = 0, .grad = {b->grad[i][0], b->grad[i][1], b->grad[i][2]}};
        int64_t rgba[4] = {b->rgb[i][0], b->rgb[i][1], b->rgb[i][2], 0};
        b->sat[i] = 0;
        c5_shade_w(r, &smp, rgba, b->gpos[i], d, b->out[i], &b->sat[i], 0);
    }
}

#if C5_SHADE_WIDE

#include <immintrin.h>

int c5_shade4_wide(void)
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

#define WIDE __attribute__((target("avx2,fma")))

/* Lane i of the four, component c of an int64_t [4][3] (exact: every value is below 2^53). */
WIDE static inline __m256d lanes(const int64_t a[4][3], int c)
{
    return _mm256_set_pd((double)a[3][c], (double)a[2][c], (double)a[1][c], (double)a[0][c]);
}

WIDE static inline __m256d rne(__m256d x) { return _mm256_round_pd(x, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC); }

/* c5_geom_dot14_dirs: the exact sum (below 2^31), times 2^-14 (exact), rounded to even. */
WIDE static inline __m256d dot14(const __m256d a[3], const __m256d b[3])
{
    __m256d s = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a[0], b[0]), _mm256_mul_pd(a[1], b[1])),
                              _mm256_mul_pd(a[2], b[2]));
    return rne(_mm256_mul_pd(s, _mm256_set1_pd(0x1p-14)));
}

/* c5_geom_normalize for components below 2^25 (|v|^2 < 2^52): len = floor(sqrt(|v|^2 2^28))
 * and out = round(v 2^28 / len) half to even, each exact; the zero vector gives 0 and a
 * clear lane in *nonzero. */
WIDE static inline void normalize(const __m256d v[3], __m256d out[3], __m256d *nonzero)
{
    const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1), two28 = _mm256_set1_pd(0x1p28);
    __m256d d2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(v[0], v[0]), _mm256_mul_pd(v[1], v[1])),
                               _mm256_mul_pd(v[2], v[2]));
    __m256d x = _mm256_mul_pd(d2, two28); /* an integer below 2^80, exact */
    /* floor of the correctly rounded root is floor(sqrt(x)) or one more (the rounding is
     * monotonic and floor(sqrt(x)) is a double); len^2 - x, below 2^41 in magnitude, is
     * formed exactly by one FMA */
    __m256d len = _mm256_floor_pd(_mm256_sqrt_pd(x));
    __m256d over = _mm256_cmp_pd(_mm256_fmsub_pd(len, len, x), zero, _CMP_GT_OQ);
    len = _mm256_sub_pd(len, _mm256_and_pd(over, one));
    __m256d nz = _mm256_cmp_pd(d2, zero, _CMP_NEQ_OQ);
    len = _mm256_blendv_pd(one, len, nz); /* the zero vector divides by 1, and is cleared */
    for (int a = 0; a < 3; a++) {
        __m256d num = _mm256_mul_pd(v[a], two28);
        /* the correctly rounded quotient rounded to even: round(num / len) half to even, or
         * one off where num / len lies within a double's rounding of a half; the exact
         * remainder (|r| < 2^41) says which */
        __m256d q = rne(_mm256_div_pd(num, len));
        __m256d r2 = _mm256_mul_pd(_mm256_fnmadd_pd(q, len, num), _mm256_set1_pd(2));
        __m256d up = _mm256_and_pd(_mm256_cmp_pd(r2, len, _CMP_GT_OQ), one);
        __m256d down = _mm256_and_pd(_mm256_cmp_pd(r2, _mm256_sub_pd(zero, len), _CMP_LT_OQ), one);
        q = _mm256_add_pd(q, _mm256_sub_pd(up, down));
        out[a] = _mm256_and_pd(q, nz);
    }
    *nonzero = nz;
}

/* c5_spec_pow of N.H in (0, 2^14] (other lanes: any value, not used) from the table. */
WIDE static inline __m256d spec_pow(const c5_frame_regs *r, __m256d ndh)
{
    __m256d big = _mm256_cmp_pd(ndh, _mm256_set1_pd(16384), _CMP_GE_OQ);
    __m256d clamped = _mm256_max_pd(_mm256_min_pd(ndh, _mm256_set1_pd(16383)), _mm256_setzero_pd());
    __m128i x = _mm256_cvttpd_epi32(clamped);
    __m128i i = _mm_srai_epi32(x, 4), f = _mm_and_si128(x, _mm_set1_epi32(15));
    __m128i a = _mm_i32gather_epi32(r->pow_tab, i, 4), b = _mm_i32gather_epi32(r->pow_tab + 1, i, 4);
    /* pow_tab[i] 16 + (pow_tab[i + 1] - pow_tab[i]) f (below 2^21), then >> 4 half to even */
    __m128i s = _mm_add_epi32(_mm_slli_epi32(a, 4), _mm_mullo_epi32(_mm_sub_epi32(b, a), f));
    __m128i q = _mm_srai_epi32(s, 4), rem = _mm_and_si128(s, _mm_set1_epi32(15));
    q = _mm_add_epi32(q, _mm_srai_epi32(_mm_add_epi32(_mm_add_epi32(rem, _mm_set1_epi32(7)),
                                                      _mm_and_si128(q, _mm_set1_epi32(1))), 4));
    __m256d p = _mm256_cvtepi32_pd(q);
    return _mm256_blendv_pd(p, _mm256_set1_pd((double)r->pow_tab[1 << C5_POW_BITS]), big);
}

/* Every component below 2^25 in magnitude: the lanes normalise in doubles. */
WIDE static inline int in_range(const __m256d v[3])
{
    const __m256d lim = _mm256_set1_pd(0x1p25), sign = _mm256_set1_pd(-0.0);
    __m256d ok = _mm256_set1_pd(-1.0);
    for (int a = 0; a < 3; a++)
        ok = _mm256_and_pd(ok, _mm256_cmp_pd(_mm256_andnot_pd(sign, v[a]), lim, _CMP_LT_OQ));
    return _mm256_movemask_pd(ok) == 15;
}

WIDE int c5_shade4_wide_only(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b)
{
    if (!c5_shade4_wide() || b->n < 1 || b->n > 4)
        return -1;
    int64_t grad[4][3], gpos[4][3];
    for (int i = 0; i < 4; i++) /* unused lanes repeat lane 0 */
        for (int a = 0; a < 3; a++) {
            grad[i][a] = b->grad[i < b->n ? i : 0][a];
            gpos[i][a] = b->gpos[i < b->n ? i : 0][a];
        }
    const __m256d zero = _mm256_setzero_pd();
    __m256d g[3] = {lanes(grad, 0), lanes(grad, 1), lanes(grad, 2)}, mg[3], n[3], v[3], nz;
    if (!in_range(g))
        return -1;
    __m256d m2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(g[0], g[0]), _mm256_mul_pd(g[1], g[1])),
                               _mm256_mul_pd(g[2], g[2]));
    for (int a = 0; a < 3; a++) {
        mg[a] = _mm256_sub_pd(zero, g[a]);
        v[a] = _mm256_set1_pd((double)-d[a]);
    }
    normalize(mg, n, &nz);
    /* two-sided: the normal faces the viewer */
    __m256d flip = _mm256_cmp_pd(dot14(n, v), zero, _CMP_LT_OQ);
    for (int a = 0; a < 3; a++)
        n[a] = _mm256_blendv_pd(n[a], _mm256_sub_pd(zero, n[a]), flip);
    __m256d diff = zero, spec = zero;
    for (int li = 0; li < r->n_lights; li++) {
        const c5_light_regs *l = &r->lights[li];
        __m256d L[3], h[3], H[3], lz, hz;
        if (l->kind == C5_LIGHT_POINT) {
            __m256d to[3];
            for (int a = 0; a < 3; a++)
                to[a] = _mm256_sub_pd(_mm256_set1_pd((double)l->pos[a]), lanes(gpos, a));
            if (!in_range(to))
                return -1;
            normalize(to, L, &lz);
        } else {
            for (int a = 0; a < 3; a++)
                L[a] = _mm256_set1_pd((double)l->dir[a]);
        }
        __m256d ndl = dot14(n, L), lit = _mm256_cmp_pd(ndl, zero, _CMP_GT_OQ);
        __m256d intensity = _mm256_set1_pd((double)l->intensity);
        diff = _mm256_add_pd(diff, _mm256_and_pd(_mm256_mul_pd(intensity, ndl), lit));
        for (int a = 0; a < 3; a++)
            h[a] = _mm256_add_pd(L[a], v[a]);
        normalize(h, H, &hz);
        __m256d ndh = dot14(n, H);
        __m256d lit_spec = _mm256_and_pd(_mm256_and_pd(lit, hz), _mm256_cmp_pd(ndh, zero, _CMP_GT_OQ));
        spec = _mm256_add_pd(spec, _mm256_and_pd(_mm256_mul_pd(intensity, spec_pow(r, ndh)), lit_spec));
    }
    double m2s[4], diffs[4], specs[4];
    _mm256_storeu_pd(m2s, m2);
    _mm256_storeu_pd(diffs, diff);
    _mm256_storeu_pd(specs, spec);
    for (int i = 0; i < b->n; i++) {
        b->sat[i] = 0;
        c5_shade_finish(r, (int64_t)m2s[i], (int64_t)diffs[i], (int64_t)specs[i], b->rgb[i], b->out[i], &b->sat[i]);
    }
    return 0;
}

#else

int c5_shade4_wide(void) { return 0; }

int c5_shade4_wide_only(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b)
{
    (void)r, (void)d, (void)b;
    return -1;
}

#endif

void c5_shade4(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b)
{
    if (c5_shade4_wide_only(r, d, b) != 0)
        shade4_scalar(r, d, b);
}
