/* A sample of the workers' inner loop: where it lies and its reconstructed value.
 *
 * Position of sample j, per axis: x = o + t d with t = j * step (single precision), clamped
 * into [0, hi] where hi is the largest float below the axis's cell count; its cell
 * i = trunc(x) and the fraction x - i in [0, 1). The clamp keeps i at most cells - 1 without
 * a second clamp on the integer. A function of j alone, so every skipping mode places a
 * sample at the same bits (docs/caster.md, "exactness").
 * Value: trilinear, as three rounds of lerp(a, b, t) = a + t (b - a): x first, then y, then z.
 *
 * Two implementations of one definition: SSE2 (x86-64's baseline), all three axes or four
 * lerps in one register, which is what makes a dropped sample cheap (position, brick change
 * and sub-brick from a dozen instructions); and the scalar one, which is the definition, the
 * fallback on other machines (or with -DC5_CAST_NO_SIMD) and what tests/test_cast.c checks
 * the SSE2 one against, bit for bit. Lane 3 of a ray is padding: o = d = hi = 0 there, so it
 * always reads cell 0. */
#ifndef C5_CAST_SAMPLE_H
#define C5_CAST_SAMPLE_H

#include <math.h>
#include <stdint.h>

#include "cast_internal.h"

#if defined(__SSE2__) && !defined(C5_CAST_NO_SIMD)
#include <emmintrin.h>
#define C5_CAST_SIMD 1
#else
#define C5_CAST_SIMD 0
#endif

/* A ray in the workers' arithmetic: voxel units, lanes x, y, z, padding. */
typedef struct {
    float o[4], d[4], hi[4];
    float step;
} c5_cast_ray;

/* The ray of pixel (px, py) and the samples jin..jout inside the volume (cast_worker.c); 0
 * when it misses the volume. */
int c5_cast_pixel_ray(const c5_cast_view *vw, int px, int py, c5_cast_ray *r, int32_t *jin, int32_t *jout);

enum {
    C5_CAST_BRICK_LOG2 = 3, /* C5_CAST_BRICK == 1 << 3 */
    C5_CAST_SUB_LOG2 = 2,   /* C5_CAST_SUB == 1 << 2 */
};
_Static_assert(C5_CAST_BRICK == 1 << C5_CAST_BRICK_LOG2 && C5_CAST_SUB == 1 << C5_CAST_SUB_LOG2,
               "cast_sample.h: brick and sub-brick sides must be these powers of two");

/* The definition: cell i[a] and fraction f[a] of sample j on each axis. The comparisons are
 * written as SSE's max/min define them (x > 0 ? x : 0, x < hi ? x : hi). */
static inline void c5_cast_pos_ref(const c5_cast_ray *r, int32_t j, int i[3], float f[3])
{
    float t = (float)j * r->step;
    for (int a = 0; a < 3; a++) {
        float x = r->o[a] + t * r->d[a];
        x = x > 0 ? x : 0;
        x = x < r->hi[a] ? x : r->hi[a];
        i[a] = (int)x;
        f[a] = x - (float)i[a];
    }
}

/* Offsets of a cell's 8 corners inside a brick: x, then y, then z. */
enum { C5_CAST_DX = 1, C5_CAST_DY = C5_CAST_BSIDE, C5_CAST_DZ = C5_CAST_BSIDE * C5_CAST_BSIDE };

static inline float c5_cast_lerp(float a, float b, float t) { return a + t * (b - a); }

/* The definition: the trilinear value of the cell whose first corner is b, at fractions f. */
static inline float c5_cast_tri_ref(const uint8_t *b, const float f[3])
{
    enum { X = C5_CAST_DX, Y = C5_CAST_DY, Z = C5_CAST_DZ };
    float x00 = c5_cast_lerp(b[0], b[X], f[0]), x10 = c5_cast_lerp(b[Y], b[Y + X], f[0]);
    float x01 = c5_cast_lerp(b[Z], b[Z + X], f[0]), x11 = c5_cast_lerp(b[Z + Y], b[Z + Y + X], f[0]);
    return c5_cast_lerp(c5_cast_lerp(x00, x10, f[1]), c5_cast_lerp(x01, x11, f[1]), f[2]);
}

/* The definition of the shading blend: per corner k of the cell (normal codes n[corner k]),
 * the table's pair (diffuse, specular), both blended in the order of c5_cast_tri_ref. */
static inline void c5_cast_shade_ref(const float (*tab)[2], const uint16_t *n, const float f[3], float out[2])
{
    enum { X = C5_CAST_DX, Y = C5_CAST_DY, Z = C5_CAST_DZ };
    static const int corner[8] = {0, X, Y, Y + X, Z, Z + X, Z + Y, Z + Y + X};
    for (int c = 0; c < 2; c++) {
        float v[8];
        for (int k = 0; k < 8; k++)
            v[k] = tab[n[corner[k]]][c];
        float x00 = c5_cast_lerp(v[0], v[1], f[0]), x10 = c5_cast_lerp(v[2], v[3], f[0]);
        float x01 = c5_cast_lerp(v[4], v[5], f[0]), x11 = c5_cast_lerp(v[6], v[7], f[0]);
        out[c] = c5_cast_lerp(c5_cast_lerp(x00, x10, f[1]), c5_cast_lerp(x01, x11, f[1]), f[2]);
    }
}

/* The definition of a shaded colour: from the TF's premultiplied (c0, c1, c2, a) and the
 * headlight's factors k (diffuse, specular), c = c k[0] + a k[1] per channel; a unchanged. */
static inline void c5_cast_lit_ref(const float e[4], const float k[2], float out[4])
{
    float ks = e[3] * k[1];
    for (int c = 0; c < 3; c++)
        out[c] = e[c] * k[0] + ks;
    out[3] = e[3];
}

/* The definition of front-to-back compositing: with T = 1 - A, each of C0, C1, C2, A gains
 * T times the sample's c0, c1, c2, a. A sample with a == 0 has colour 0 (premultiplied) and
 * adds +0 to each: leaving it out changes no bit. */
static inline void c5_cast_over_ref(float acc[4], const float c[4])
{
    float T = 1 - acc[3];
    for (int ch = 0; ch < 4; ch++)
        acc[ch] += T * c[ch];
}

/* A position as the loop carries it: cells and fractions, per lane. */
#if C5_CAST_SIMD
typedef struct {
    __m128i i;
    __m128 f;
} c5_cast_pos;

static inline c5_cast_pos c5_cast_pos_at(const c5_cast_ray *r, int32_t j)
{
    __m128 t = _mm_set1_ps((float)j * r->step);
    __m128 x = _mm_add_ps(_mm_loadu_ps(r->o), _mm_mul_ps(t, _mm_loadu_ps(r->d)));
    x = _mm_min_ps(_mm_max_ps(x, _mm_setzero_ps()), _mm_loadu_ps(r->hi));
    c5_cast_pos p;
    p.i = _mm_cvttps_epi32(x);
    p.f = _mm_sub_ps(x, _mm_cvtepi32_ps(p.i));
    return p;
}
static inline int c5_cast_pos_cell(c5_cast_pos p, int a)
{
    return _mm_cvtsi128_si32(a == 0 ? p.i : a == 1 ? _mm_shuffle_epi32(p.i, 1) : _mm_shuffle_epi32(p.i, 2));
}
static inline float c5_cast_pos_frac(c5_cast_pos p, int a)
{
    return _mm_cvtss_f32(a == 0 ? p.f : a == 1 ? _mm_shuffle_ps(p.f, p.f, 1) : _mm_shuffle_ps(p.f, p.f, 2));
}
/* The brick coordinates (cells >> 3) as one comparable word per lane. */
typedef __m128i c5_cast_bkey;
static inline c5_cast_bkey c5_cast_pos_bkey(c5_cast_pos p) { return _mm_srli_epi32(p.i, C5_CAST_BRICK_LOG2); }
static inline int c5_cast_bkey_eq(c5_cast_bkey a, c5_cast_bkey b)
{
    return _mm_movemask_epi8(_mm_cmpeq_epi32(a, b)) == 0xffff;
}
static inline c5_cast_bkey c5_cast_bkey_none(void) { return _mm_set1_epi32(-1); }
/* Sub-brick s = sx + 2 sy + 4 sz: bit 2 of each cell index, moved to the sign and gathered. */
static inline unsigned c5_cast_pos_sub(c5_cast_pos p)
{
    return (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_slli_epi32(p.i, 31 - C5_CAST_SUB_LOG2)));
}
/* Offset of the cell's first corner inside its brick: (i mod 8) . (1, 9, 81). The products
 * come from one 16-bit multiply-add (every factor fits in 16 bits), then a lane sum. */
static inline int c5_cast_pos_off(c5_cast_pos p)
{
    __m128i m = _mm_madd_epi16(_mm_and_si128(p.i, _mm_set1_epi32(C5_CAST_BRICK - 1)),
                               _mm_set_epi32(0, C5_CAST_BSIDE * C5_CAST_BSIDE, C5_CAST_BSIDE, 1));
    m = _mm_add_epi32(m, _mm_shuffle_epi32(m, 0x4e));
    m = _mm_add_epi32(m, _mm_shuffle_epi32(m, 0xb1));
    return _mm_cvtsi128_si32(m);
}
/* The trilinear value at p of the cell whose first corner is b: two 16-byte loads (the brick
 * stride's padding keeps them inside the brick: 637 + 81 + 16 <= 768) bring the 8 corners
 * into one register; the four x lerps, then two y lerps, run lane-parallel. */
_Static_assert((C5_CAST_BRICK - 1) * (1 + C5_CAST_DY + C5_CAST_DZ) + C5_CAST_DZ + 16 <= C5_CAST_BSTRIDE,
               "cast_sample.h: the trilinear unit's 16-byte loads must stay inside a brick");
static inline float c5_cast_tri(const uint8_t *b, c5_cast_pos p)
{
    const __m128i zero = _mm_setzero_si128();
    __m128i v0 = _mm_loadu_si128((const __m128i *)b), v1 = _mm_loadu_si128((const __m128i *)(b + C5_CAST_DZ));
    /* bytes b0 b1 b9 b10 | b81 b82 b90 b91: each load's first pair beside its pair one row up */
    __m128i w0 = _mm_unpacklo_epi16(v0, _mm_srli_si128(v0, C5_CAST_DY));
    __m128i w1 = _mm_unpacklo_epi16(v1, _mm_srli_si128(v1, C5_CAST_DY));
    __m128i q = _mm_unpacklo_epi8(_mm_unpacklo_epi32(w0, w1), zero);
    __m128 lo = _mm_cvtepi32_ps(_mm_unpacklo_epi16(q, zero)), hi = _mm_cvtepi32_ps(_mm_unpackhi_epi16(q, zero));
    __m128 e = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0)); /* corners 0 2 4 6 */
    __m128 o = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1)); /* corners 1 3 5 7 */
    __m128 x = _mm_add_ps(e, _mm_mul_ps(_mm_shuffle_ps(p.f, p.f, 0), _mm_sub_ps(o, e))); /* x00 x10 x01 x11 */
    __m128 ye = _mm_shuffle_ps(x, x, _MM_SHUFFLE(2, 0, 2, 0)), yo = _mm_shuffle_ps(x, x, _MM_SHUFFLE(3, 1, 3, 1));
    __m128 y = _mm_add_ps(ye, _mm_mul_ps(_mm_shuffle_ps(p.f, p.f, _MM_SHUFFLE(1, 1, 1, 1)), _mm_sub_ps(yo, ye)));
    __m128 y1 = _mm_shuffle_ps(y, y, 1), fz = _mm_shuffle_ps(p.f, p.f, 2);
    return _mm_cvtss_f32(_mm_add_ss(y, _mm_mul_ss(fz, _mm_sub_ss(y1, y))));
}
/* The shading blend with both channels side by side: lanes (diffuse, specular) of two
 * corners at a time, then the same x, y, z rounds as the definition. Lanes 0 and 1 of the
 * result: the diffuse and specular factors. */
typedef __m128 c5_cast_light;
static inline c5_cast_light c5_cast_shade(const float (*tab)[2], const uint16_t *n, c5_cast_pos p)
{
    enum { X = C5_CAST_DX, Y = C5_CAST_DY, Z = C5_CAST_DZ };
#define C5_PAIRS(a, b) _mm_loadh_pi(_mm_loadl_pi(_mm_setzero_ps(), (const __m64 *)tab[n[a]]), (const __m64 *)tab[n[b]])
    __m128 a0 = C5_PAIRS(0, Y), b0 = C5_PAIRS(X, Y + X), a1 = C5_PAIRS(Z, Z + Y), b1 = C5_PAIRS(Z + X, Z + Y + X);
#undef C5_PAIRS
    __m128 fx = _mm_shuffle_ps(p.f, p.f, 0);
    __m128 x0 = _mm_add_ps(a0, _mm_mul_ps(fx, _mm_sub_ps(b0, a0))); /* x00, x10 (pairs) */
    __m128 x1 = _mm_add_ps(a1, _mm_mul_ps(fx, _mm_sub_ps(b1, a1))); /* x01, x11 */
    __m128 c = _mm_movelh_ps(x0, x1), d = _mm_movehl_ps(x1, x0);   /* x00 x01 | x10 x11 */
    __m128 y = _mm_add_ps(c, _mm_mul_ps(_mm_shuffle_ps(p.f, p.f, _MM_SHUFFLE(1, 1, 1, 1)), _mm_sub_ps(d, c)));
    __m128 y1 = _mm_movehl_ps(y, y);
    return _mm_add_ps(y, _mm_mul_ps(_mm_shuffle_ps(p.f, p.f, _MM_SHUFFLE(2, 2, 2, 2)), _mm_sub_ps(y1, y)));
}
static inline float c5_cast_light_factor(c5_cast_light k, int c)
{
    return _mm_cvtss_f32(c == 0 ? k : _mm_shuffle_ps(k, k, 1));
}

/* A colour (c0, c1, c2, a) and the accumulated (C0, C1, C2, A): one register each. */
typedef __m128 c5_cast_rgba;
static inline c5_cast_rgba c5_cast_rgba_load(const float e[4]) { return _mm_loadu_ps(e); }
static inline c5_cast_rgba c5_cast_rgba_zero(void) { return _mm_setzero_ps(); }
static inline float c5_cast_rgba_at(c5_cast_rgba c, int ch)
{
    float v[4];
    _mm_storeu_ps(v, c);
    return v[ch];
}
/* As c5_cast_lit_ref, lane by lane; lane 3 (a) passes through untouched. */
static inline c5_cast_rgba c5_cast_lit(const float e[4], c5_cast_light k)
{
    __m128 ev = _mm_loadu_ps(e), a = _mm_shuffle_ps(ev, ev, _MM_SHUFFLE(3, 3, 3, 3));
    __m128 ks = _mm_mul_ps(a, _mm_shuffle_ps(k, k, _MM_SHUFFLE(1, 1, 1, 1)));
    __m128 c = _mm_add_ps(_mm_mul_ps(ev, _mm_shuffle_ps(k, k, 0)), ks);   /* c0 c1 c2 x */
    __m128 t = _mm_shuffle_ps(c, ev, _MM_SHUFFLE(3, 3, 2, 2));           /* c2 c2 a a */
    return _mm_shuffle_ps(c, t, _MM_SHUFFLE(2, 0, 1, 0));                /* c0 c1 c2 a */
}
/* As c5_cast_over_ref, four lanes at once. */
static inline c5_cast_rgba c5_cast_over(c5_cast_rgba acc, c5_cast_rgba c)
{
    __m128 T = _mm_sub_ps(_mm_set1_ps(1), _mm_shuffle_ps(acc, acc, _MM_SHUFFLE(3, 3, 3, 3)));
    return _mm_add_ps(acc, _mm_mul_ps(T, c));
}
static inline float c5_cast_rgba_alpha(c5_cast_rgba c) { return _mm_cvtss_f32(_mm_shuffle_ps(c, c, 3)); }
#else
typedef struct {
    int i[3];
    float f[3];
} c5_cast_pos;

static inline c5_cast_pos c5_cast_pos_at(const c5_cast_ray *r, int32_t j)
{
    c5_cast_pos p;
    c5_cast_pos_ref(r, j, p.i, p.f);
    return p;
}
static inline int c5_cast_pos_cell(c5_cast_pos p, int a) { return p.i[a]; }
static inline float c5_cast_pos_frac(c5_cast_pos p, int a) { return p.f[a]; }
typedef uint64_t c5_cast_bkey;
static inline c5_cast_bkey c5_cast_pos_bkey(c5_cast_pos p)
{
    return (uint64_t)(p.i[0] >> C5_CAST_BRICK_LOG2) | (uint64_t)(p.i[1] >> C5_CAST_BRICK_LOG2) << 21 |
           (uint64_t)(p.i[2] >> C5_CAST_BRICK_LOG2) << 42;
}
static inline int c5_cast_bkey_eq(c5_cast_bkey a, c5_cast_bkey b) { return a == b; }
static inline c5_cast_bkey c5_cast_bkey_none(void) { return UINT64_MAX; }
static inline unsigned c5_cast_pos_sub(c5_cast_pos p)
{
    return (unsigned)((p.i[0] >> C5_CAST_SUB_LOG2 & 1) | (p.i[1] >> C5_CAST_SUB_LOG2 & 1) << 1 |
                      (p.i[2] >> C5_CAST_SUB_LOG2 & 1) << 2);
}
static inline int c5_cast_pos_off(c5_cast_pos p)
{
    return (p.i[0] & (C5_CAST_BRICK - 1)) + C5_CAST_BSIDE * (p.i[1] & (C5_CAST_BRICK - 1)) +
           C5_CAST_BSIDE * C5_CAST_BSIDE * (p.i[2] & (C5_CAST_BRICK - 1));
}
static inline float c5_cast_tri(const uint8_t *b, c5_cast_pos p) { return c5_cast_tri_ref(b, p.f); }
typedef struct {
    float k[2];
} c5_cast_light;
static inline c5_cast_light c5_cast_shade(const float (*tab)[2], const uint16_t *n, c5_cast_pos p)
{
    c5_cast_light k;
    c5_cast_shade_ref(tab, n, p.f, k.k);
    return k;
}
static inline float c5_cast_light_factor(c5_cast_light k, int c) { return k.k[c]; }

typedef struct {
    float v[4];
} c5_cast_rgba;
static inline c5_cast_rgba c5_cast_rgba_load(const float e[4]) { return (c5_cast_rgba){{e[0], e[1], e[2], e[3]}}; }
static inline c5_cast_rgba c5_cast_rgba_zero(void) { return (c5_cast_rgba){{0, 0, 0, 0}}; }
static inline float c5_cast_rgba_at(c5_cast_rgba c, int ch) { return c.v[ch]; }
static inline c5_cast_rgba c5_cast_lit(const float e[4], c5_cast_light k)
{
    c5_cast_rgba c;
    c5_cast_lit_ref(e, k.k, c.v);
    return c;
}
static inline c5_cast_rgba c5_cast_over(c5_cast_rgba acc, c5_cast_rgba c)
{
    c5_cast_over_ref(acc.v, c.v);
    return acc;
}
static inline float c5_cast_rgba_alpha(c5_cast_rgba c) { return c.v[3]; }
#endif

/* The sample loop eight samples at a time (cast_wide.c; AVX2, chosen at run time): x86-64
 * with the SIMD twin only. */
#if C5_CAST_SIMD && defined(__x86_64__) && defined(__GNUC__)
#define C5_CAST_WIDE 1
/* 1 when this CPU (and its OS) runs AVX2 and, v not NULL, v's bricks are addressable by the
 * loop's 32-bit lane offsets. */
int c5_cast_wide_usable(const c5_cast_volume *v);
/* As march_span of cast_worker.c, without the refining hash: marches samples
 * j0..j1 into acc; 1 when the ray terminated early. */
int c5_cast_wide_span(const c5_cast_view *vw, const c5_cast_ray *r, int32_t j0, int32_t j1, c5_cast_rgba *acc,
                      c5_cast_counts *cnt);
#else
#define C5_CAST_WIDE 0
static inline int c5_cast_wide_usable(const c5_cast_volume *v) { return (void)v, 0; }
#endif

/* The largest float below `cells` (>= 1): an axis's clamp bound, hi[a] of c5_cast_ray. */
static inline float c5_cast_clamp_hi(int cells) { return nextafterf((float)cells, 0); }

#endif
