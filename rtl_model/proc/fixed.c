/* Fixed-point arithmetic: see fixed.h for the conventions.
 *
 * Every operation follows the same three steps:
 *   1. form the exact result as a wide integer v with a known binary point (an __int128:
 *      operands are at most 62 bits, so products and aligned sums stay below 2^125 in
 *      magnitude, shifted dividends below 2^126, and anything larger is known to
 *      saturate before it is formed);
 *   2. move the binary point to the destination's, rounding per mode (round_shift,
 *      round_div, or the root's half bit);
 *   3. clamp to the destination's range, counting the clamp (clamp_to).
 * Rounding decisions are all made by round_up() from three facts: the floor quotient's
 * parity, and whether the dropped part is below, at, or above one half LSB. */
#include "fixed.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>

__extension__ typedef __int128 i128;
__extension__ typedef unsigned __int128 u128;

/* ---- formats ---------------------------------------------------------------------- */

int c5_fx_width(c5_fx_fmt f) { return (f.is_signed ? 1 : 0) + f.int_bits + f.frac_bits; }

int c5_fx_fmt_valid(c5_fx_fmt f)
{
    int w = c5_fx_width(f);
    return f.is_signed <= 1 && w >= 1 && w <= C5_FX_MAX_WIDTH;
}

int c5_fx_fmt_check(c5_fx_fmt f, c5_err *err)
{
    if (f.is_signed > 1)
        return c5_fail(err, "fixed-point format %s: is_signed must be 0 or 1, not %u",
                       f.name ? f.name : "(unnamed)", (unsigned)f.is_signed);
    int w = c5_fx_width(f);
    if (w < 1 || w > C5_FX_MAX_WIDTH) {
        char s[C5_FX_FMT_STR_LEN];
        return c5_fail(err, "fixed-point format %s %s: width %d bits, must be 1 to %d",
                       f.name ? f.name : "(unnamed)", c5_fx_fmt_str(f, s, sizeof s), w,
                       C5_FX_MAX_WIDTH);
    }
    return 0;
}

/* Magnitude bits (everything but the sign bit): the range is [-2^m or 0, 2^m - 1]. */
static int mag_bits(c5_fx_fmt f) { return f.int_bits + f.frac_bits; }

int64_t c5_fx_max_raw(c5_fx_fmt f)
{
    assert(c5_fx_fmt_valid(f));
    return (int64_t)(((uint64_t)1 << mag_bits(f)) - 1);
}

int64_t c5_fx_min_raw(c5_fx_fmt f)
{
    assert(c5_fx_fmt_valid(f));
    return f.is_signed ? -(int64_t)((uint64_t)1 << mag_bits(f)) : 0;
}

int c5_fx_in_range(int64_t raw, c5_fx_fmt f) { return raw >= c5_fx_min_raw(f) && raw <= c5_fx_max_raw(f); }

const char *c5_fx_fmt_str(c5_fx_fmt f, char *buf, size_t n)
{
    snprintf(buf, n, "%s%u.%u", f.is_signed ? "SQ" : "UQ", (unsigned)f.int_bits, (unsigned)f.frac_bits);
    return buf;
}

const char *c5_rnd_name(c5_rnd r)
{
    switch (r) {
    case C5_RND_TRUNC: return "trunc";
    case C5_RND_HALF_UP: return "half-up";
    case C5_RND_HALF_EVEN: return "half-even";
    }
    return "?";
}

static int rnd_valid(c5_rnd r) { return r == C5_RND_TRUNC || r == C5_RND_HALF_UP || r == C5_RND_HALF_EVEN; }

/* ---- the shared steps ------------------------------------------------------------- */

/* 2^k as a wide integer, 0 <= k <= 126. */
static i128 pow2(int k) { return (i128)1 << k; }

/* 1 if the floor quotient q must be incremented. odd: q is odd. cmp: the dropped part
 * compared to one half LSB (-1 below, 0 exactly half, +1 above); an exact result has
 * cmp = -1 (nothing dropped is below half). */
static int round_up(int odd, int cmp, c5_rnd rnd)
{
    switch (rnd) {
    case C5_RND_TRUNC: return 0;
    case C5_RND_HALF_UP: return cmp >= 0;
    case C5_RND_HALF_EVEN: return cmp > 0 || (cmp == 0 && odd);
    }
    assert(0);
    return 0;
}

static int sign_of(i128 v) { return (v > 0) - (v < 0); }

/* floor(v / 2^d), 1 <= d <= 126, |v| < 2^125. Written without >> on a negative value
 * (implementation-defined in C) so that it means the same everywhere. */
static i128 floor_shift(i128 v, int d) { return v >= 0 ? v >> d : -((-v - 1) >> d) - 1; }

/* v / 2^d rounded per rnd, d >= 0, |v| < 2^125. */
static i128 round_shift(i128 v, int d, c5_rnd rnd)
{
    if (d == 0)
        return v;
    if (d > 126) {
        /* |v| / 2^d < 1/4: only the sign matters, and +-1 / 2^2 = +-1/4 rounds alike. */
        v = sign_of(v);
        d = 2;
    }
    i128 q = floor_shift(v, d);
    i128 rem = v - q * pow2(d); /* dropped bits, 0 <= rem < 2^d */
    i128 half = pow2(d - 1);
    int cmp = rem < half ? -1 : rem > half;
    return q + round_up(q % 2 != 0, cmp, rnd);
}

/* n / den rounded per rnd, den > 0, |n| < 2^126, den < 2^124 (so 2 r < 2^125). */
static i128 round_div(i128 n, i128 den, c5_rnd rnd)
{
    i128 q = n / den, r = n % den; /* C truncates toward zero: make it floor */
    if (r < 0) {
        q -= 1;
        r += den;
    }
    i128 twice = 2 * r; /* 0 <= 2r < 2 den */
    int cmp = twice < den ? -1 : twice > den;
    return q + round_up(q % 2 != 0, cmp, rnd);
}

static void count_sat(c5_fx_flags *flags)
{
    if (flags)
        flags->saturations++;
}

static void count_nan(c5_fx_flags *flags)
{
    if (flags)
        flags->nans++;
}

/* Clamp an already rounded raw value to dst. */
static int64_t clamp_to(i128 v, c5_fx_fmt dst, c5_fx_flags *flags)
{
    int64_t lo = c5_fx_min_raw(dst), hi = c5_fx_max_raw(dst);
    if (v > hi) {
        count_sat(flags);
        return hi;
    }
    if (v < lo) {
        count_sat(flags);
        return lo;
    }
    return (int64_t)v;
}

/* The saturated result for an exact value too large in magnitude for any format. */
static int64_t sat_by_sign(int sign, c5_fx_fmt dst, c5_fx_flags *flags)
{
    if (sign == 0)
        return 0;
    count_sat(flags);
    return sign > 0 ? c5_fx_max_raw(dst) : c5_fx_min_raw(dst);
}

/* v * 2^k, exact value with |v| < 2^125, brought to dst: k >= 0 shifts left (no rounding,
 * range checked before shifting so nothing overflows), k < 0 shifts right with rounding. */
static int64_t finish(i128 v, int k, c5_fx_fmt dst, c5_rnd rnd, c5_fx_flags *flags)
{
    if (k < 0)
        return clamp_to(round_shift(v, -k, rnd), dst, flags);
    if (v == 0)
        return 0;
    if (k > 62) /* |v| >= 1, so |v| 2^k > 2^62: beyond every format */
        return sat_by_sign(sign_of(v), dst, flags);
    /* In range iff ceil(min / 2^k) <= v <= floor(max / 2^k). */
    i128 hi = c5_fx_max_raw(dst) >> k;
    i128 lo = -((-(i128)c5_fx_min_raw(dst)) >> k);
    if (v > hi || v < lo)
        return sat_by_sign(sign_of(v), dst, flags);
    return (int64_t)(v * pow2(k));
}

static int bit_length(uint64_t x) { return x ? 64 - __builtin_clzll(x) : 0; }

static uint64_t magnitude(int64_t a) { return a < 0 ? (uint64_t)0 - (uint64_t)a : (uint64_t)a; }

#define CHECK_OPERAND(a, fa) assert(c5_fx_fmt_valid(fa) && c5_fx_in_range((a), (fa)))
#define CHECK_DST(dst, rnd) assert(c5_fx_fmt_valid(dst) && rnd_valid(rnd))

/* ---- conversions ------------------------------------------------------------------ */

int64_t c5_fx_from_double(double x, c5_fx_fmt dst, c5_rnd rnd, c5_fx_flags *flags)
{
    CHECK_DST(dst, rnd);
    if (isnan(x)) {
        count_nan(flags);
        return 0;
    }
    /* y = x 2^f is exact (a power-of-two scale; overflow gives inf, handled below). Outside
     * +-2^63 it is beyond every format; inside, floor(y) fits an int64 and y - floor(y) is
     * exact, so the rounding below sees the true fraction. */
    double y = ldexp(x, dst.frac_bits);
    if (y >= 0x1p63)
        return sat_by_sign(1, dst, flags);
    if (y < -0x1p63)
        return sat_by_sign(-1, dst, flags);
    double fl = floor(y), frac = y - fl;
    int64_t q = (int64_t)fl;
    int cmp = frac < 0.5 ? -1 : frac > 0.5;
    return clamp_to((i128)q + round_up(q % 2 != 0, cmp, rnd), dst, flags);
}

double c5_fx_to_double(int64_t raw, c5_fx_fmt f)
{
    CHECK_OPERAND(raw, f);
    return ldexp((double)raw, -(int)f.frac_bits);
}

int64_t c5_fx_convert(int64_t a, c5_fx_fmt fa, c5_fx_fmt dst, c5_rnd rnd, c5_fx_flags *flags)
{
    CHECK_OPERAND(a, fa);
    CHECK_DST(dst, rnd);
    return finish(a, dst.frac_bits - fa.frac_bits, dst, rnd, flags);
}

/* ---- arithmetic ------------------------------------------------------------------- */

/* a + sign_b * b: both aligned exactly to the finer binary point (at most 62 + 62 bits,
 * so the sum stays below 2^125), then brought to dst. */
static int64_t add_sub(int64_t a, c5_fx_fmt fa, int64_t b, c5_fx_fmt fb, int sign_b, c5_fx_fmt dst,
                       c5_rnd rnd, c5_fx_flags *flags)
{
    CHECK_OPERAND(a, fa);
    CHECK_OPERAND(b, fb);
    CHECK_DST(dst, rnd);
    int f = fa.frac_bits > fb.frac_bits ? fa.frac_bits : fb.frac_bits;
    i128 sum = (i128)a * pow2(f - fa.frac_bits) + sign_b * ((i128)b * pow2(f - fb.frac_bits));
    return finish(sum, dst.frac_bits - f, dst, rnd, flags);
}

int64_t c5_fx_add(int64_t a, c5_fx_fmt fa, int64_t b, c5_fx_fmt fb, c5_fx_fmt dst, c5_rnd rnd,
                  c5_fx_flags *flags)
{
    return add_sub(a, fa, b, fb, 1, dst, rnd, flags);
}

int64_t c5_fx_sub(int64_t a, c5_fx_fmt fa, int64_t b, c5_fx_fmt fb, c5_fx_fmt dst, c5_rnd rnd,
                  c5_fx_flags *flags)
{
    return add_sub(a, fa, b, fb, -1, dst, rnd, flags);
}

/* The exact product has fa + fb fraction bits and magnitude at most 2^62 * 2^62. */
int64_t c5_fx_mul(int64_t a, c5_fx_fmt fa, int64_t b, c5_fx_fmt fb, c5_fx_fmt dst, c5_rnd rnd,
                  c5_fx_flags *flags)
{
    CHECK_OPERAND(a, fa);
    CHECK_OPERAND(b, fb);
    CHECK_DST(dst, rnd);
    i128 p = (i128)a * b;
    return finish(p, dst.frac_bits - fa.frac_bits - fb.frac_bits, dst, rnd, flags);
}

/* raw result = a 2^(fd + fb - fa) / b, rounded. With k = fd + fb - fa >= 0 the dividend
 * a 2^k is formed only when it stays below 2^126; otherwise |quotient| >= 2^126 / 2^62 =
 * 2^64, beyond every format, and the result saturates. With k < 0 the divisor b 2^-k is
 * at most 62 + 62 bits. */
int64_t c5_fx_div(int64_t a, c5_fx_fmt fa, int64_t b, c5_fx_fmt fb, c5_fx_fmt dst, c5_rnd rnd,
                  c5_fx_flags *flags)
{
    CHECK_OPERAND(a, fa);
    CHECK_OPERAND(b, fb);
    CHECK_DST(dst, rnd);
    if (b == 0) {
        /* As IEEE x/0: +-inf saturates, 0/0 is NaN. */
        if (a == 0) {
            count_nan(flags);
            return 0;
        }
        return sat_by_sign(sign_of(a), dst, flags);
    }
    if (a == 0)
        return 0;
    int k = dst.frac_bits + fb.frac_bits - fa.frac_bits;
    i128 n = a, den = b;
    if (k >= 0) {
        if (bit_length(magnitude(a)) + k > 126)
            return sat_by_sign(sign_of(a) * sign_of(b), dst, flags);
        n *= pow2(k);
    } else {
        den *= pow2(-k);
    }
    if (den < 0) {
        n = -n;
        den = -den;
    }
    return clamp_to(round_div(n, den, rnd), dst, flags);
}

int64_t c5_fx_shift(int64_t a, c5_fx_fmt fa, int s, c5_fx_fmt dst, c5_rnd rnd, c5_fx_flags *flags)
{
    CHECK_OPERAND(a, fa);
    CHECK_DST(dst, rnd);
    /* Beyond +-200 every result is the same (saturated, or rounded from below 1/2 LSB);
     * clamping s keeps the exponent arithmetic far from int overflow. */
    if (s > 200)
        s = 200;
    if (s < -200)
        s = -200;
    return finish(a, dst.frac_bits - fa.frac_bits + s, dst, rnd, flags);
}

/* floor(sqrt(x)) for x < 2^126, digit by digit: one result bit per step from two bits of
 * x, a trial subtraction kept only when it does not go negative (the restoring method of
 * a sequential hardware square-root unit); *rem = x - root^2. */
static uint64_t isqrt_u128(u128 x, u128 *rem)
{
    u128 root = 0, bit = (u128)1 << 124;
    while (bit > x)
        bit >>= 2;
    while (bit) {
        if (x >= root + bit) {
            x -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    *rem = x;
    return (uint64_t)root;
}

/* The raw result is sqrt(X) with X = a 2^(2 fd - fa). The root is taken of 4X = a 2^e,
 * e = 2 fd - fa + 2, so that h = floor(2 sqrt(X)) carries one bit below the result's LSB
 * (the half bit); the sticky bit says whether anything nonzero lies below it. If e < 0,
 * floor(sqrt(a 2^e)) = isqrt(floor(a 2^e)) (the squares of integers are integers) and the
 * bits of a shifted out join the sticky bit. If a 2^e >= 2^126, sqrt(X) >= 2^62: beyond
 * every format. */
int64_t c5_fx_sqrt(int64_t a, c5_fx_fmt fa, c5_fx_fmt dst, c5_rnd rnd, c5_fx_flags *flags)
{
    CHECK_OPERAND(a, fa);
    CHECK_DST(dst, rnd);
    if (a < 0) {
        count_nan(flags);
        return 0;
    }
    if (a == 0)
        return 0;
    int e = 2 * dst.frac_bits - fa.frac_bits + 2;
    uint64_t h; /* floor(2 sqrt(X)) */
    u128 rem;
    int sticky;
    if (e >= 0) {
        if (bit_length((uint64_t)a) + e > 126)
            return sat_by_sign(1, dst, flags);
        h = isqrt_u128((u128)a << e, &rem);
        sticky = rem != 0;
    } else {
        int m = -e; /* 1 .. 64 */
        uint64_t kept = m >= 64 ? 0 : (uint64_t)a >> m;
        uint64_t lost = m >= 64 ? (uint64_t)a : (uint64_t)a & (((uint64_t)1 << m) - 1);
        h = isqrt_u128(kept, &rem);
        sticky = rem != 0 || lost != 0;
    }
    uint64_t q = h >> 1;
    int cmp = (h & 1) == 0 ? -1 : sticky ? 1 : 0;
    return clamp_to((i128)q + round_up(q % 2 != 0, cmp, rnd), dst, flags);
}
