/* Eight samples' gradients and shading on AVX2 and FMA (shade_wide.h; the lanes' arithmetic:
 * wide_lanes.h). */
#include "shade_wide.h"

#include <stdatomic.h>

#include "geom.h"
#include "sample_pipe.h"
#include "wide_lanes.h"

static void shade_lanes_scalar(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b)
{
    for (int i = 0; i < b->n; i++) {
        c5_sample smp = {.value = 0, .grad = {b->grad[i][0], b->grad[i][1], b->grad[i][2]}};
        int64_t rgba[4] = {b->rgb[0][i], b->rgb[1][i], b->rgb[2][i], 0}, g[3];
        int64_t v[3] = {b->vpos[0][i], b->vpos[1][i], b->vpos[2][i]};
        c5_geom_from_voxel(r, v, g);
        b->sat[i] = 0;
        c5_shade_w(r, &smp, rgba, g, d, b->out[i], &b->sat[i], 0);
    }
}

static void grad_lanes_scalar(const c5_frame_regs *r, c5_shade_lanes *b)
{
    for (int i = 0; i < b->n; i++) {
        int64_t frac[3];
        int32_t d[3][8];
        if (b->rows >> i & 1)
            c5_rows_diffs(&b->row[0][i], C5_SHADE_LANES, d);
        for (int a = 0; a < 3; a++) {
            frac[a] = b->frac[a][i];
            if (!(b->rows >> i & 1))
                for (int j = 0; j < 8; j++)
                    d[a][j] = b->diff[a][j][i];
        }
        c5_grad_blend(frac, d, r->gs, b->grad[i]);
    }
}

#if C5_WIDE

int c5_shade_wide_usable(void)
{
    /* asked once: every lane block checks it before its first wide instruction */
    static _Atomic int usable = -1;
    int u = atomic_load_explicit(&usable, memory_order_relaxed);
    if (u < 0) {
        __builtin_cpu_init();
        u = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
        atomic_store_explicit(&usable, u, memory_order_relaxed);
    }
    return u;
}

/* c5_geom_dot14_dirs: the exact sum (below 2^31), times 2^-14 (exact), rounded to even. */
WIDE static inline v8 dot14(const v8 a[3], const v8 b[3])
{
    return rne(mul(add(add(mul(a[0], b[0]), mul(a[1], b[1])), mul(a[2], b[2])), set1(0x1p-14)));
}

/* c5_geom_normalize for components below 2^25 (|v|^2 < 2^52): len = floor(sqrt(|v|^2 2^28))
 * and out = round(v 2^28 / len) half to even, each exact; the zero vector gives 0 and a
 * clear lane in *nonzero. */
WIDE static inline __attribute__((always_inline)) void normalize(const v8 v[3], v8 out[3], v8 *nonzero)
{
    const v8 zero = set1(0), one = set1(1), two28 = set1(0x1p28);
    v8 d2 = add(add(mul(v[0], v[0]), mul(v[1], v[1])), mul(v[2], v[2]));
    v8 x = mul(d2, two28); /* an integer below 2^80, exact */
    /* floor of the correctly rounded root is floor(sqrt(x)) or one more (the rounding is
     * monotonic and floor(sqrt(x)) is a double); len^2 - x, below 2^41 in magnitude, is
     * formed exactly by one FMA */
    v8 len = floor8(root(x));
    len = sub(len, and(gt(fmsub(len, len, x), zero), one));
    v8 nz = ne(d2, zero);
    len = blend(one, len, nz); /* the zero vector divides by 1, and is cleared */
    for (int a = 0; a < 3; a++) {
        v8 num = mul(v[a], two28);
        /* the correctly rounded quotient rounded to even: round(num / len) half to even, or
         * one off where num / len lies within half a double's spacing of a half (len near
         * 2^39 and above: a light's direction only); the exact remainder (|r| < 2^41) says
         * which */
        v8 q = rne(dvd(num, len));
        v8 r2 = mul(fnmadd(q, len, num), set1(2));
        q = add(q, sub(and(gt(r2, len), one), and(lt(r2, neg(len)), one)));
        out[a] = and(q, nz);
    }
    *nonzero = nz;
}

/* c5_spec_pow of N.H in (0, 2^14] (other lanes: any value, not used) from the table. */
WIDE static inline __m256d spec_pow4(const c5_frame_regs *r, __m256d ndh)
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

WIDE static inline v8 spec_pow(const c5_frame_regs *r, v8 ndh)
{
    return (v8){{spec_pow4(r, ndh.h[0]), spec_pow4(r, ndh.h[1])}};
}

/* rshift128_he(x fade, s) for 0 <= x < 2^50, 0 <= fade <= 2^15, s in 41..42: x = xh 2^24 + xl,
 * xh fade = aq 2^(s-24) + ar, so that x fade / 2^s = aq + b / 2^s with b = ar 2^24 + xl fade
 * below 2^(s+1): every term exact, and the rounding to even on aq's parity. */
WIDE static inline __attribute__((always_inline)) v8 faded(v8 x, v8 fade, int s)
{
    const v8 one = set1(1), half = set1(0.5);
    v8 xh = floor8(mul(x, set1(0x1p-24))), xl = sub(x, mul(xh, set1(0x1p24)));
    v8 a = mul(xh, fade), sc = set1((double)(1 << (s - 24)));
    v8 aq = floor8(mul(a, set1(1.0 / (double)(1 << (s - 24))))), ar = sub(a, mul(aq, sc));
    v8 f = mul(add(mul(ar, set1(0x1p24)), mul(xl, fade)), set1(1.0 / (double)((int64_t)1 << s)));
    v8 fl = floor8(f), frac = sub(f, fl), base = add(aq, fl);
    v8 odd = sub(base, mul(floor8(mul(base, half)), set1(2)));
    v8 tie = and(eq(frac, half), gt(odd, set1(0)));
    return add(base, and(blend(gt(frac, half), tie, tie), one));
}

/* v clamped to [0, 65535], and the count (1 if clamped) added to sat */
WIDE static inline v8 clamp16(v8 v, v8 *sat)
{
    const v8 lo = set1(0), hi = set1(65535);
    v8 under = lt(v, lo), over = gt(v, hi);
    *sat = add(*sat, and(blend(over, under, under), set1(1)));
    return blend(blend(v, hi, over), lo, under);
}

/* Every component below 2^25 in magnitude: the lanes normalise in doubles. */
WIDE static inline int in_range(const v8 v[3])
{
    v8 ok = set1(-1.0);
    for (int a = 0; a < 3; a++)
        ok = and(ok, lt(mag(v[a]), set1(0x1p25)));
    return (_mm256_movemask_pd(ok.h[0]) & _mm256_movemask_pd(ok.h[1])) == 15;
}

WIDE static int normalize_wide(const int64_t v[C5_SHADE_LANES][3], int64_t out[C5_SHADE_LANES][3])
{
    v8 in[3] = {lanes(v, 0), lanes(v, 1), lanes(v, 2)}, o[3], nz;
    if (!in_range(in))
        return -1;
    normalize(in, o, &nz);
    for (int a = 0; a < 3; a++) {
        double d[8];
        _mm256_storeu_pd(d, o[a].h[0]);
        _mm256_storeu_pd(d + 4, o[a].h[1]);
        for (int i = 0; i < 8; i++)
            out[i][a] = (int64_t)d[i];
    }
    return 0;
}

/* The lanes of an int32_t [3][8] field with lanes n..7 made lane 0's (they are computed
 * and dropped: copies keep them within every range lane 0 is in), in registers. */
WIDE static inline void lanes3(const int32_t f[3][C5_SHADE_LANES], int n, v8 out[3])
{
    __m256i used = lanes_below(n);
    for (int a = 0; a < 3; a++) {
        __m256i x = _mm256_loadu_si256((const __m256i *)f[a]);
        out[a] = lanes_i(_mm256_blendv_epi8(_mm256_permutevar8x32_epi32(x, _mm256_setzero_si256()), x, used));
    }
}

/* The shading of the lanes' gradients g (lanes n..7: any gradient in range). */
WIDE static int shade_core(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b, const v8 g[3])
{
    v8 gp[3], rgb[3];
    int point = 0;
    for (int li = 0; li < r->n_lights; li++)
        point |= r->lights[li].kind == C5_LIGHT_POINT;
    if (point) {
        /* c5_geom_from_voxel: below 2^28 times gscale below 2^24 (UQ8.16), the product is exact,
         * and the half-to-even shift by 16 a multiplication by 2^-16 and a round to even */
        v8 vp[3], ok = set1(-1.0);
        lanes3(b->vpos, b->n, vp);
        for (int a = 0; a < 3; a++) {
            if (r->gscale[a] >= 1 << 24)
                return -1;
            ok = and(ok, lt(mag(vp[a]), set1(0x1p28)));
            gp[a] = rne(mul(mul(vp[a], set1((double)r->gscale[a])), set1(0x1p-16)));
        }
        if ((_mm256_movemask_pd(ok.h[0]) & _mm256_movemask_pd(ok.h[1])) != 15)
            return -1;
    }
    lanes3(b->rgb, b->n, rgb);
    const v8 zero = set1(0);
    v8 mg[3], n[3], v[3], nz;
    if (!in_range(g))
        return -1;
    v8 m2 = add(add(mul(g[0], g[0]), mul(g[1], g[1])), mul(g[2], g[2]));
    for (int a = 0; a < 3; a++) {
        mg[a] = neg(g[a]);
        v[a] = set1((double)-d[a]);
    }
    normalize(mg, n, &nz);
    /* two-sided: the normal faces the viewer */
    v8 flip = lt(dot14(n, v), zero);
    for (int a = 0; a < 3; a++)
        n[a] = blend(n[a], neg(n[a]), flip);
    v8 diff = zero, spec = zero;
    for (int li = 0; li < r->n_lights; li++) {
        const c5_light_regs *l = &r->lights[li];
        v8 L[3], h[3], H[3], lz, hz;
        if (l->kind == C5_LIGHT_POINT) {
            v8 to[3];
            for (int a = 0; a < 3; a++)
                to[a] = sub(set1((double)l->pos[a]), gp[a]);
            if (!in_range(to))
                return -1;
            normalize(to, L, &lz);
        } else {
            for (int a = 0; a < 3; a++)
                L[a] = set1((double)l->dir[a]);
        }
        v8 ndl = dot14(n, L), lit = gt(ndl, zero), intensity = set1((double)l->intensity);
        diff = add(diff, and(mul(intensity, ndl), lit));
        for (int a = 0; a < 3; a++)
            h[a] = add(L[a], v[a]);
        normalize(h, H, &hz);
        v8 ndh = dot14(n, H);
        v8 lit_spec = and(and(lit, hz), gt(ndh, zero));
        spec = add(spec, and(mul(intensity, spec_pow(r, ndh)), lit_spec));
    }
    /* c5_shade_finish: the light terms (m2 = 0 gives diff = spec = fade = 0, so k = ka and
     * ks = 0 without a case of its own), then the channels */
    v8 fade = blend(set1(C5_ONE15), mul(m2, set1(2)), lt(m2, set1(16384))), sat = zero;
    v8 k = clamp16(add(set1((double)r->ka), faded(mul(set1((double)r->kd), diff), fade, 26 + 15)), &sat);
    v8 ks = clamp16(faded(mul(set1((double)r->ks), spec), fade, 27 + 15), &sat);
    v8 out[3];
    for (int c = 0; c < 3; c++)
        out[c] = clamp16(add(rne(mul(mul(rgb[c], k), set1(0x1p-15))), ks), &sat);
    double o[3][8], sats[8];
    for (int h = 0; h < 2; h++) {
        for (int c = 0; c < 3; c++)
            _mm256_storeu_pd(o[c] + 4 * h, out[c].h[h]);
        _mm256_storeu_pd(sats + 4 * h, sat.h[h]);
    }
    for (int i = 0; i < b->n; i++) {
        for (int c = 0; c < 3; c++)
            b->out[i][c] = (int64_t)o[c][i];
        b->sat[i] = (uint64_t)sats[i];
    }
    return 0;
}

WIDE static int shade_wide(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b)
{
    int64_t grad[8][3];
    for (int i = 0; i < 8; i++) /* unused lanes repeat lane 0 */
        for (int a = 0; a < 3; a++)
            grad[i][a] = b->grad[i < b->n ? i : 0][a];
    v8 g[3] = {lanes(grad, 0), lanes(grad, 1), lanes(grad, 2)};
    return shade_core(r, d, b, g);
}

/* The lanes' differences, corner j of axis a in d[a][j]: from the rows in the lanes that have
 * them (the subtractions of c5_rows_diffs), from diff in the others. */
WIDE static inline __attribute__((always_inline)) void diff_lanes(const c5_shade_lanes *b, __m256i d[3][8])
{
    /* every lane in use has its rows (the usual case): diff is not read */
    int all = b->rows == (1u << b->n) - 1;
    for (int a = 0; a < 3; a++)
        for (int j = 0; j < 8; j++)
            d[a][j] = all ? _mm256_setzero_si256() : _mm256_loadu_si256((const __m256i *)b->diff[a][j]);
    if (!b->rows)
        return;
    const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128), byte = _mm256_set1_epi32(255);
    __m256i use = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32((int)b->rows), bit), bit);
    __m256i row[C5_SHADE_ROWS];
    for (int k = 0; k < C5_SHADE_ROWS; k++)
        row[k] = _mm256_loadu_si256((const __m256i *)b->row[k]);
#define BYTE(dy, dz, x) _mm256_and_si256(_mm256_srli_epi32(row[c5_row_at(dy, dz)], 8 * (x)), byte)
#pragma GCC unroll 8
    for (int j = 0; j < 8; j++) {
        int kx = j & 1, ky = j >> 1 & 1, kz = j >> 2;
        __m256i dx = _mm256_sub_epi32(BYTE(ky, kz, kx + 2), BYTE(ky, kz, kx));
        __m256i dy = _mm256_sub_epi32(BYTE(ky + 1, kz, kx + 1), BYTE(ky - 1, kz, kx + 1));
        __m256i dz = _mm256_sub_epi32(BYTE(ky, kz + 1, kx + 1), BYTE(ky, kz - 1, kx + 1));
        d[0][j] = _mm256_blendv_epi8(d[0][j], dx, use);
        d[1][j] = _mm256_blendv_epi8(d[1][j], dy, use);
        d[2][j] = _mm256_blendv_epi8(d[2][j], dz, use);
    }
#undef BYTE
}

/* c5_grad_blend of lanes 0..n-1 (lanes n..7: 0): per axis sum_j w_j d_j with w_j the product
 * of the corner's three fractions, taken as z (y (x d)): the same integer as the blend's in
 * any order, and every partial sum within 255 2^45 < 2^53, so exact; then the two
 * half-to-even shifts as multiplications by powers of 2 and rounds to even. */
WIDE static void grad_lanes(const c5_frame_regs *r, c5_shade_lanes *b, v8 g[3])
{
    const v8 one = set1(1 << 15);
    v8 w[3][2];
    for (int a = 0; a < 3; a++) {
        w[a][1] = lanes32(b->frac[a]);
        w[a][0] = sub(one, w[a][1]);
    }
    __m256i d[3][8];
    diff_lanes(b, d);
    __m256i used = lanes_below(b->n);
    v8 keep = {{_mm256_castsi256_pd(_mm256_cvtepi32_epi64(_mm256_castsi256_si128(used))),
                _mm256_castsi256_pd(_mm256_cvtepi32_epi64(_mm256_extracti128_si256(used, 1)))}};
    for (int a = 0; a < 3; a++) {
        v8 yb[2];
        for (int cz = 0; cz < 2; cz++) {
            v8 xa[2];
            for (int cy = 0; cy < 2; cy++) {
                int j = 2 * cy + 4 * cz;
                xa[cy] = add(mul(w[0][0], lanes_i(d[a][j])), mul(w[0][1], lanes_i(d[a][j + 1])));
            }
            yb[cz] = add(mul(w[1][0], xa[0]), mul(w[1][1], xa[1]));
        }
        v8 blend = rne(mul(add(mul(w[2][0], yb[0]), mul(w[2][1], yb[1])), set1(0x1p-37)));
        g[a] = and(rne(mul(mul(blend, set1((double)r->gs[a])), set1(0x1p-15))), keep);
    }
}

/* grad of lanes 0..n-1 from the lanes */
WIDE static void store_grad(c5_shade_lanes *b, const v8 g[3])
{
    for (int a = 0; a < 3; a++) {
        double o[8];
        _mm256_storeu_pd(o, g[a].h[0]);
        _mm256_storeu_pd(o + 4, g[a].h[1]);
        for (int i = 0; i < b->n; i++)
            b->grad[i][a] = (int64_t)o[i];
    }
}

WIDE static void grad_wide(const c5_frame_regs *r, c5_shade_lanes *b)
{
    v8 g[3];
    grad_lanes(r, b, g);
    store_grad(b, g);
}

WIDE static void grad_shade_wide(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b)
{
    v8 g[3];
    grad_lanes(r, b, g);
    if (shade_core(r, d, b, g) != 0) {
        store_grad(b, g);
        shade_lanes_scalar(r, d, b);
    }
}

void c5_grad_shade_wide(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b)
{
    if (c5_shade_wide_usable() && b->n >= 1 && b->n <= C5_SHADE_LANES) {
        grad_shade_wide(r, d, b);
        return;
    }
    grad_lanes_scalar(r, b);
    shade_lanes_scalar(r, d, b);
}

/* The checks before any instruction of the wide units runs. */
int c5_shade_wide_only(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b)
{
    return c5_shade_wide_usable() && b->n >= 1 && b->n <= C5_SHADE_LANES ? shade_wide(r, d, b) : -1;
}

int c5_shade_wide_normalize(const int64_t v[C5_SHADE_LANES][3], int64_t out[C5_SHADE_LANES][3])
{
    return c5_shade_wide_usable() ? normalize_wide(v, out) : -1;
}

void c5_grad_wide(const c5_frame_regs *r, c5_shade_lanes *b)
{
    if (c5_shade_wide_usable())
        grad_wide(r, b);
    else
        grad_lanes_scalar(r, b);
}

#else

void c5_grad_wide(const c5_frame_regs *r, c5_shade_lanes *b) { grad_lanes_scalar(r, b); }

void c5_grad_shade_wide(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b)
{
    grad_lanes_scalar(r, b);
    shade_lanes_scalar(r, d, b);
}

int c5_shade_wide_usable(void) { return 0; }

int c5_shade_wide_only(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b)
{
    (void)r, (void)d, (void)b;
    return -1;
}

int c5_shade_wide_normalize(const int64_t v[C5_SHADE_LANES][3], int64_t out[C5_SHADE_LANES][3])
{
    (void)v, (void)out;
    return -1;
}

#endif

void c5_shade_wide(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b)
{
    if (c5_shade_wide_only(r, d, b) != 0)
        shade_lanes_scalar(r, d, b);
}
