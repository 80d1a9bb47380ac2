/* Eight lanes of doubles on the host's AVX2 and FMA units: the arithmetic the model's wide
 * blocks share (shade_wide.c, value_wide.c). Only functions marked WIDE use those units, so
 * the rest of the build stays at the baseline and c5_shade_wide_usable decides at run time.
 * The round-probe build (C5_ROUND_PROBE) has no wide blocks: its probes sit in the scalar
 * steps. Include from a .c file only. */
#ifndef C5_WIDE_LANES_H
#define C5_WIDE_LANES_H

#if defined(__x86_64__) && defined(__GNUC__) && !defined(C5_ROUND_PROBE)
#define C5_WIDE 1
#else
#define C5_WIDE 0
#endif

#if C5_WIDE

#include <immintrin.h>

#define WIDE __attribute__((target("avx2,fma")))

/* Eight lanes as two registers: every step is written once and done on both. */
typedef struct {
    __m256d h[2];
} v8;

#define V8_1(name, expr)                                                                                       \
    WIDE static inline v8 name(v8 a)                                                                           \
    {                                                                                                          \
        v8 o;                                                                                                  \
        for (int k = 0; k < 2; k++) {                                                                          \
            __m256d x = a.h[k];                                                                                \
            o.h[k] = (expr);                                                                                   \
        }                                                                                                      \
        return o;                                                                                              \
    }
#define V8_2(name, expr)                                                                                       \
    WIDE static inline v8 name(v8 a, v8 b)                                                                     \
    {                                                                                                          \
        v8 o;                                                                                                  \
        for (int k = 0; k < 2; k++) {                                                                          \
            __m256d x = a.h[k], y = b.h[k];                                                                    \
            o.h[k] = (expr);                                                                                   \
        }                                                                                                      \
        return o;                                                                                              \
    }
V8_2(add, _mm256_add_pd(x, y))
V8_2(sub, _mm256_sub_pd(x, y))
V8_2(mul, _mm256_mul_pd(x, y))
V8_2(dvd, _mm256_div_pd(x, y))
V8_2(and, _mm256_and_pd(x, y))
V8_2(gt, _mm256_cmp_pd(x, y, _CMP_GT_OQ))
V8_2(lt, _mm256_cmp_pd(x, y, _CMP_LT_OQ))
V8_2(ne, _mm256_cmp_pd(x, y, _CMP_NEQ_OQ))
V8_2(eq, _mm256_cmp_pd(x, y, _CMP_EQ_OQ))
V8_1(root, _mm256_sqrt_pd(x))
V8_1(floor8, _mm256_floor_pd(x))
V8_1(rne, _mm256_round_pd(x, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC))
V8_1(neg, _mm256_sub_pd(_mm256_setzero_pd(), x))
V8_1(mag, _mm256_andnot_pd(_mm256_set1_pd(-0.0), x))

WIDE static inline v8 set1(double v) { return (v8){{_mm256_set1_pd(v), _mm256_set1_pd(v)}}; }
/* where m, b; else a */
WIDE static inline v8 blend(v8 a, v8 b, v8 m)
{
    return (v8){{_mm256_blendv_pd(a.h[0], b.h[0], m.h[0]), _mm256_blendv_pd(a.h[1], b.h[1], m.h[1])}};
}
/* a b - c and c - a b, each rounded once */
WIDE static inline v8 fmsub(v8 a, v8 b, v8 c)
{
    return (v8){{_mm256_fmsub_pd(a.h[0], b.h[0], c.h[0]), _mm256_fmsub_pd(a.h[1], b.h[1], c.h[1])}};
}
WIDE static inline v8 fnmadd(v8 a, v8 b, v8 c)
{
    return (v8){{_mm256_fnmadd_pd(a.h[0], b.h[0], c.h[0]), _mm256_fnmadd_pd(a.h[1], b.h[1], c.h[1])}};
}

/* Component c of lanes 0..7 of an int64_t [8][3] (exact: every value is below 2^53). */
WIDE static inline v8 lanes(const int64_t a[8][3], int c)
{
    return (v8){{_mm256_set_pd((double)a[3][c], (double)a[2][c], (double)a[1][c], (double)a[0][c]),
                 _mm256_set_pd((double)a[7][c], (double)a[6][c], (double)a[5][c], (double)a[4][c])}};
}


/* Eight lanes of 32-bit integers (exact). */
WIDE static inline v8 lanes_i(__m256i x)
{
    return (v8){{_mm256_cvtepi32_pd(_mm256_castsi256_si128(x)), _mm256_cvtepi32_pd(_mm256_extracti128_si256(x, 1))}};
}

/* All ones in 32-bit lanes 0..n-1, zero in the others. */
WIDE static inline __m256i lanes_below(int n)
{
    return _mm256_cmpgt_epi32(_mm256_set1_epi32(n), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
}

/* Eight lanes of an int32_t [8] row (exact). */
WIDE static inline v8 lanes32(const int32_t *row) { return lanes_i(_mm256_loadu_si256((const __m256i *)row)); }

#endif

#endif
