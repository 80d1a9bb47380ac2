/* The datapath's integer primitives, inline for the per-sample loop. Each is the exact
 * operation of fixed.h specialised to raw integers (the tests check them against c5_fx_*):
 * the exact result first, then one rounding, then (where the caller asks) saturation. */
#ifndef C5_FXOPS_H
#define C5_FXOPS_H

#include <stdint.h>

#include "round_probe.h"

/* x * 2^s for any sign (a left shift of a negative value is undefined in C). */
static inline int64_t c5_shl(int64_t x, int s) { return x * ((int64_t)1 << s); }
static inline __int128 c5_shl128(__int128 x, int s) { return x * ((__int128)1 << s); }

/* floor(x / 2^s) rounded half to even; s in 1..62. Arithmetic on negatives too. */
static inline int64_t c5_rshift_he(int64_t x, int s)
{
    /* Without a branch (the rounding direction is data, which a predictor guesses badly in
     * the sample loop): with r in [0, 2^s), r + half - 1 + (q & 1) reaches 2^s exactly when
     * r > half, or r == half and q is odd; it stays below 2^(s + 1) and 2^63. */
    int64_t q = x >> s; /* floor */
    int64_t r = x & (((int64_t)1 << s) - 1);
    int64_t half = (int64_t)1 << (s - 1);
    C5_ROUND_NOTE(r == 0, (r > half) - (r < half), q & 1);
    return q + ((r + half - 1 + (q & 1)) >> s);
}

/* The same on a 128-bit product, s in 1..126, also without a branch (the composite and the
 * shading round three to five products a sample this way). */
static inline int64_t c5_rshift128_he(__int128 x, int s)
{
    __int128 q = x >> s;
    __int128 r = x & (((__int128)1 << s) - 1);
    __int128 half = (__int128)1 << (s - 1);
    C5_ROUND_NOTE(r == 0, (r > half) - (r < half), q & 1);
    return (int64_t)(q + ((r + half - 1 + (q & 1)) >> s));
}

/* round(n / d) half to even for |n|, |d| < 2^62, d != 0 (no negation or 2 r can overflow):
 * the steps of c5_div_he in 64 bits, for callers that know their ranges. */
static inline int64_t c5_div_he64(int64_t n, int64_t d)
{
    if (d < 0)
        n = -n, d = -d;
    int64_t q = n / d, r = n % d;
    int64_t neg = r >> 63; /* C truncates toward zero: make it floor, without a branch */
    q += neg;
    r += d & neg;
    int64_t twice = 2 * r;
    C5_ROUND_NOTE(r == 0, (twice > d) - (twice < d), q & 1);
    return q + ((twice > d) | ((twice == d) & q & 1));
}

/* c5_div_he64(n, d) for d > 0 and |n / d| < 2^40, with inv ~ 1 / d given: the quotient from
 * a double product, checked or corrected on the exact remainder, so the result is the same
 * integer whatever inv's error. One division shared by a vector's three components instead
 * of three integer divisions: the shading normalises three vectors a sample. */
static inline int64_t c5_div_he64_inv(int64_t n, int64_t d, double inv)
{
    /* The double product rounded to the nearest integer (adding and taking away 1.5 * 2^52
     * rounds a double below 2^51 to an integer): when its remainder is less than half the
     * divisor either way it is round(n / d); a tie and an estimate further off take the
     * steps below, which move a truncated estimate until 0 <= r < d. */
    const double magic = 0x1.8p52, e = (double)n * inv;
    int64_t q = (int64_t)((e + magic) - magic), r = n - q * d, twice = 2 * r;
    if (twice < d && twice > -d) {
        C5_ROUND_NOTE(r == 0, r > 0 ? -1 : 1, 0);
        return q;
    }
    q = (int64_t)e, r = n - q * d;
    /* One step each way without a branch (the truncation leaves r < 0 for every negative
     * quotient: the sign of a normal's component is data), then the loops for an estimate
     * further off, which the model's never is. */
    int64_t neg = r >> 63;
    q += neg;
    r += d & neg;
    int64_t over = -(int64_t)(r >= d);
    q -= over;
    r -= d & over;
    while (r < 0) {
        q--;
        r += d;
    }
    while (r >= d) {
        q++;
        r -= d;
    }
    twice = 2 * r;
    C5_ROUND_NOTE(r == 0, (twice > d) - (twice < d), q & 1);
    return q + ((twice > d) | ((twice == d) & q & 1));
}

/* round(n / d) half to even, d != 0. A negative divisor is moved to the numerator first:
 * the floor-and-remainder steps below need d > 0 (with d < 0 they gave 1 for 0 / d and
 * -2 for 10 / -3, 1 LSB off in plane and grid-range t). */
static inline int64_t c5_div_he(__int128 n, __int128 d)
{
    /* The same steps in 64 bits when |n|, |d| < 2^62: the quotient is the same integer,
     * and a 128-bit division is a libgcc call (__divmodti4) several times slower, in
     * every ray's set-up and surface hit. */
    if ((unsigned __int128)(n + ((__int128)1 << 62)) < ((unsigned __int128)1 << 63) &&
        (unsigned __int128)(d + ((__int128)1 << 62)) < ((unsigned __int128)1 << 63))
        return c5_div_he64((int64_t)n, (int64_t)d);
    if (d < 0)
        n = -n, d = -d;
    __int128 q = n / d, r = n % d;
    if (r < 0) { /* C truncates toward zero: make it floor */
        q--;
        r += d;
    }
    __int128 twice = 2 * r;
    C5_ROUND_NOTE(r == 0, (twice > d) - (twice < d), q & 1);
    if (twice > d || (twice == d && (q & 1)))
        q++;
    return (int64_t)q;
}

/* floor(sqrt(x)) for x >= 0, exact (the digit-by-digit result, found from a double guess). */
static inline uint64_t c5_isqrt(unsigned __int128 x)
{
    /* Below 2^62 the same search in 64 bits (r <= 2^31, so (r + 1)^2 < 2^63): the 128-bit
     * conversion to double and the 128-bit products are libgcc calls and wide multiplies
     * in every normal the shading computes. */
    if (x < ((unsigned __int128)1 << 62)) {
        uint64_t x64 = (uint64_t)x, r = (uint64_t)__builtin_sqrt((double)x64);
        while (r * r > x64)
            r--;
        while ((r + 1) * (r + 1) <= x64)
            r++;
        return r;
    }
    uint64_t r = (uint64_t)__builtin_sqrt((double)x);
    while ((unsigned __int128)r * r > x)
        r--;
    while ((unsigned __int128)(r + 1) * (r + 1) <= x)
        r++;
    return r;
}

static inline int64_t c5_clamp64(int64_t v, int64_t lo, int64_t hi, uint64_t *sat)
{
    if (v < lo) {
        (*sat)++;
        C5_SAT_NOTE(C5_EV_SAT_LO);
        return lo;
    }
    if (v > hi) {
        (*sat)++;
        C5_SAT_NOTE(C5_EV_SAT_HI);
        return hi;
    }
    return v;
}

/* A narrowed signal (widths.h): x rounded half to even to a multiple of 2^s, s the fraction
 * bits dropped (shipped - width); s = 0, the shipped width, returns x untouched. */
static inline int64_t c5_narrow(int64_t x, int s) { return s ? c5_shl(c5_rshift_he(x, s), s) : x; }

/* The same, then clamped (and counted) to [lo, hi] with hi taken down to a multiple of 2^s:
 * the range of the narrowed format in its container (lo is 0 or -2^n, already a multiple). */
static inline int64_t c5_narrow_clamp(int64_t x, int s, int64_t lo, int64_t hi, uint64_t *sat)
{
    if (!s)
        return x;
    return c5_clamp64(c5_narrow(x, s), lo, hi & ~(((int64_t)1 << s) - 1), sat);
}

#endif
