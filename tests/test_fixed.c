/* Fixed-point layer (rtl_model/proc/fixed.h): hand-computed values for every operation and
 * rounding mode, the extremes of every format in FORMATS, and a seeded random cross-check
 * against exact reference arithmetic written here independently (rational rounding with
 * __int128 division, overflow detected by __builtin_mul_overflow, square roots by binary
 * search). When the model adopts a new datapath format, add it to FORMATS. */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "fixed.h"
#include "harness.h"
#include "rng.h"

__extension__ typedef __int128 i128;
__extension__ typedef unsigned __int128 u128;

/* Formats whose extremes are tested. The labels are what failure messages print. */
static const c5_fx_fmt FORMATS[] = {
    {9, 12, 0, "UQ9.12"},  {1, 16, 1, "SQ1.16"}, {1, 15, 0, "UQ1.15"},
    {15, 16, 1, "SQ15.16"}, {0, 8, 0, "UQ0.8"},   {31, 31, 0, "UQ31.31 (62 bits)"},
    {0, 61, 1, "SQ0.61 (62 bits)"}, {62, 0, 0, "UQ62.0 (62 bits)"}, {0, 62, 0, "UQ0.62 (62 bits)"},
    /* the board model's datapath formats (docs/bit-layouts.md) */
    {9, 15, 0, "pos UQ9.15"}, {1, 14, 1, "dir SQ1.14"}, {2, 12, 0, "rgb UQ2.12"},
    {4, 20, 0, "step_k UQ4.20"}, {3, 15, 1, "step_vec SQ3.15"}, {0, 15, 0, "voxel_frac UQ0.15"},
    {8, 8, 0, "sample_value UQ8.8"}, {8, 8, 1, "gradient SQ8.8"}, {4, 12, 0, "light_term UQ4.12"},
    {20, 12, 0, "frame_acc UQ20.12"}, {13, 15, 1, "geom SQ13.15"}, {8, 16, 0, "gscale UQ8.16"},
    {1, 20, 0, "vscale UQ1.20"}, {4, 28, 0, "eta UQ4.28"},
};
#define N_FORMATS ((int)(sizeof FORMATS / sizeof FORMATS[0]))

static const c5_fx_fmt UQ9_12 = {9, 12, 0, "UQ9.12"};
static const c5_fx_fmt SQ1_16 = {1, 16, 1, "SQ1.16"};
static const c5_fx_fmt SQ1_15 = {1, 15, 1, "SQ1.15"};
static const c5_fx_fmt UQ1_15 = {1, 15, 0, "UQ1.15"};
static const c5_fx_fmt SQ15_16 = {15, 16, 1, "SQ15.16"};
static const c5_fx_fmt UQ0_8 = {0, 8, 0, "UQ0.8"};
static const c5_fx_fmt UQ31_31 = {31, 31, 0, "UQ31.31"};
static const c5_fx_fmt SQ0_61 = {0, 61, 1, "SQ0.61"};
static const c5_fx_fmt UQ62_0 = {62, 0, 0, "UQ62.0"};
static const c5_fx_fmt UQ0_62 = {0, 62, 0, "UQ0.62"};
static const c5_fx_fmt SQ7_0 = {7, 0, 1, "SQ7.0"};
static const c5_fx_fmt SQ15_0 = {15, 0, 1, "SQ15.0"};

static const c5_rnd RND[3] = {C5_RND_TRUNC, C5_RND_HALF_UP, C5_RND_HALF_EVEN};

#define P2(k) ((int64_t)1 << (k))

/* Evaluates `call` (an expression using the variable r) under TRUNC, HALF_UP, HALF_EVEN
 * and expects t, u, e respectively. */
#define CHECK_3(call, t, u, e)                                                              \
    do {                                                                                    \
        int64_t c5x_exp[3] = {(t), (u), (e)};                                               \
        for (int c5x_i = 0; c5x_i < 3; c5x_i++) {                                           \
            c5_rnd r = RND[c5x_i];                                                          \
            int64_t c5x_got = (call);                                                       \
            CHECK_MSG(c5x_got == c5x_exp[c5x_i], "%s [%s]: got %lld, expected %lld", #call, \
                      c5_rnd_name(r), (long long)c5x_got, (long long)c5x_exp[c5x_i]);       \
        }                                                                                   \
    } while (0)

#define CHECK_FLAGS(fl, sat, nan)                                                              \
    CHECK_MSG((fl).saturations == (uint64_t)(sat) && (fl).nans == (uint64_t)(nan),             \
              "flags saturations=%llu nans=%llu, expected %llu %llu",                        \
              (unsigned long long)(fl).saturations, (unsigned long long)(fl).nans,             \
              (unsigned long long)(sat), (unsigned long long)(nan))

/* ---- formats ---------------------------------------------------------------------- */

TEST(fixed_fmt_ranges)
{
    CHECK_INT(c5_fx_width(UQ9_12), 21);
    CHECK_INT(c5_fx_min_raw(UQ9_12), 0);
    CHECK_INT(c5_fx_max_raw(UQ9_12), 2097151);
    CHECK_INT(c5_fx_width(SQ1_16), 18);
    CHECK_INT(c5_fx_min_raw(SQ1_16), -131072);
    CHECK_INT(c5_fx_max_raw(SQ1_16), 131071);
    CHECK_INT(c5_fx_width(UQ1_15), 16);
    CHECK_INT(c5_fx_max_raw(UQ1_15), 65535);
    CHECK_INT(c5_fx_width(SQ15_16), 32);
    CHECK_INT(c5_fx_min_raw(SQ15_16), INT32_MIN);
    CHECK_INT(c5_fx_max_raw(SQ15_16), INT32_MAX);
    CHECK_INT(c5_fx_width(UQ0_8), 8);
    CHECK_INT(c5_fx_max_raw(UQ0_8), 255);
    CHECK_INT(c5_fx_width(UQ31_31), 62);
    CHECK_INT(c5_fx_max_raw(UQ31_31), 4611686018427387903LL);
    CHECK_INT(c5_fx_width(SQ0_61), 62);
    CHECK_INT(c5_fx_min_raw(SQ0_61), -2305843009213693952LL);
    CHECK_INT(c5_fx_max_raw(SQ0_61), 2305843009213693951LL);
    c5_fx_fmt sign_only = {0, 0, 1, "SQ0.0"};
    CHECK_INT(c5_fx_min_raw(sign_only), -1);
    CHECK_INT(c5_fx_max_raw(sign_only), 0);
    CHECK(c5_fx_in_range(-131072, SQ1_16));
    CHECK(!c5_fx_in_range(-131073, SQ1_16));
    CHECK(!c5_fx_in_range(131072, SQ1_16));
    CHECK(!c5_fx_in_range(-1, UQ9_12));
}

TEST(fixed_fmt_names)
{
    char b[C5_FX_FMT_STR_LEN];
    CHECK(strcmp(c5_fx_fmt_str(UQ9_12, b, sizeof b), "UQ9.12") == 0);
    CHECK(strcmp(c5_fx_fmt_str(SQ1_16, b, sizeof b), "SQ1.16") == 0);
    CHECK(strcmp(c5_fx_fmt_str(UQ0_62, b, sizeof b), "UQ0.62") == 0);
    c5_fx_fmt widest_text = {255, 255, 1, NULL};
    CHECK(strcmp(c5_fx_fmt_str(widest_text, b, sizeof b), "SQ255.255") == 0);
    CHECK(strcmp(c5_rnd_name(C5_RND_TRUNC), "trunc") == 0);
    CHECK(strcmp(c5_rnd_name(C5_RND_HALF_UP), "half-up") == 0);
    CHECK(strcmp(c5_rnd_name(C5_RND_HALF_EVEN), "half-even") == 0);
    /* A zero-initialised mode is none of the three. */
    CHECK(C5_RND_TRUNC != 0 && C5_RND_HALF_UP != 0 && C5_RND_HALF_EVEN != 0);
}

TEST(fixed_fmt_check)
{
    c5_err e = {{0}};
    for (int i = 0; i < N_FORMATS; i++)
        CHECK_MSG(c5_fx_fmt_check(FORMATS[i], &e) == 0, "%s rejected: %s", FORMATS[i].name, e.msg);
    c5_fx_fmt too_wide = {31, 31, 1, "ray_t"}; /* 63 bits */
    CHECK_INT(c5_fx_fmt_check(too_wide, &e), -1);
    CHECK_HAS(e.msg, "ray_t");
    CHECK_HAS(e.msg, "SQ31.31");
    CHECK_HAS(e.msg, "63 bits");
    CHECK(!c5_fx_fmt_valid(too_wide));
    c5_fx_fmt empty = {0, 0, 0, NULL};
    CHECK_INT(c5_fx_fmt_check(empty, &e), -1);
    CHECK_HAS(e.msg, "0 bits");
    c5_fx_fmt bad_sign = {1, 1, 2, "odd"};
    CHECK_INT(c5_fx_fmt_check(bad_sign, &e), -1);
    CHECK_HAS(e.msg, "is_signed");
    c5_fx_fmt widest = {0, 61, 1, NULL};
    CHECK(c5_fx_fmt_valid(widest));
}

/* ---- from_double / to_double ------------------------------------------------------ */

TEST(fixed_from_double_rounding)
{
    c5_fx_flags fl = {0};
    /* Integer format: the rounding rules themselves. Columns: trunc, half-up, half-even. */
    CHECK_3(c5_fx_from_double(2.5, SQ15_0, r, &fl), 2, 3, 2);
    CHECK_3(c5_fx_from_double(-2.5, SQ15_0, r, &fl), -3, -2, -2);
    CHECK_3(c5_fx_from_double(1.5, SQ15_0, r, &fl), 1, 2, 2);
    CHECK_3(c5_fx_from_double(-1.5, SQ15_0, r, &fl), -2, -1, -2);
    CHECK_3(c5_fx_from_double(0.5, SQ15_0, r, &fl), 0, 1, 0);
    CHECK_3(c5_fx_from_double(-0.5, SQ15_0, r, &fl), -1, 0, 0);
    CHECK_3(c5_fx_from_double(3.5, SQ15_0, r, &fl), 3, 4, 4);
    CHECK_3(c5_fx_from_double(-3.5, SQ15_0, r, &fl), -4, -3, -4);
    CHECK_3(c5_fx_from_double(2.4, SQ15_0, r, &fl), 2, 2, 2);
    CHECK_3(c5_fx_from_double(-2.4, SQ15_0, r, &fl), -3, -2, -2);
    CHECK_3(c5_fx_from_double(2.6, SQ15_0, r, &fl), 2, 3, 3);
    CHECK_3(c5_fx_from_double(-2.6, SQ15_0, r, &fl), -3, -3, -3);
    /* The largest double below 1/2: x + 0.5 rounds to 1.0 in double, the true value does not. */
    CHECK_3(c5_fx_from_double(0.49999999999999994, SQ15_0, r, &fl), 0, 0, 0);
    /* Fractional format SQ1.16 (LSB 2^-16). */
    CHECK_3(c5_fx_from_double(1.0 / 3.0, SQ1_16, r, &fl), 21845, 21845, 21845);
    CHECK_3(c5_fx_from_double(-1.0 / 3.0, SQ1_16, r, &fl), -21846, -21845, -21845);
    CHECK_3(c5_fx_from_double(0x1p-17, SQ1_16, r, &fl), 0, 1, 0);      /* half an LSB */
    CHECK_3(c5_fx_from_double(3 * 0x1p-17, SQ1_16, r, &fl), 1, 2, 2);  /* 1.5 LSB */
    CHECK_3(c5_fx_from_double(-3 * 0x1p-17, SQ1_16, r, &fl), -2, -1, -2);
    CHECK_3(c5_fx_from_double(-5 * 0x1p-17, SQ1_16, r, &fl), -3, -2, -2);
    CHECK_3(c5_fx_from_double(1.5, SQ1_16, r, &fl), 98304, 98304, 98304);
    CHECK_3(c5_fx_from_double(-2.0, SQ1_16, r, &fl), -131072, -131072, -131072);
    CHECK_FLAGS(fl, 0, 0);
}

TEST(fixed_from_double_special)
{
    c5_fx_flags fl = {0};
    CHECK_INT(c5_fx_from_double(NAN, SQ1_16, C5_RND_HALF_UP, &fl), 0);
    CHECK_FLAGS(fl, 0, 1);
    CHECK_INT(c5_fx_from_double(-NAN, UQ9_12, C5_RND_TRUNC, &fl), 0);
    CHECK_FLAGS(fl, 0, 2);
    CHECK_INT(c5_fx_from_double(INFINITY, SQ1_16, C5_RND_HALF_UP, &fl), 131071);
    CHECK_FLAGS(fl, 1, 2);
    CHECK_INT(c5_fx_from_double(-INFINITY, SQ1_16, C5_RND_HALF_UP, &fl), -131072);
    CHECK_INT(c5_fx_from_double(-INFINITY, UQ9_12, C5_RND_HALF_EVEN, &fl), 0);
    CHECK_INT(c5_fx_from_double(INFINITY, SQ0_61, C5_RND_TRUNC, &fl), P2(61) - 1);
    CHECK_INT(c5_fx_from_double(DBL_MAX, UQ0_8, C5_RND_TRUNC, &fl), 255);
    CHECK_INT(c5_fx_from_double(-DBL_MAX, SQ15_16, C5_RND_TRUNC, &fl), INT32_MIN);
    CHECK_FLAGS(fl, 6, 2);
    fl = (c5_fx_flags){0};
    /* -0.0 is zero, in every mode, with nothing counted. */
    CHECK_3(c5_fx_from_double(-0.0, SQ1_16, r, &fl), 0, 0, 0);
    CHECK_3(c5_fx_from_double(-0.0, UQ0_8, r, &fl), 0, 0, 0);
    /* Denormals: floor of a tiny negative value is -1 LSB; nearest modes give 0. */
    CHECK_3(c5_fx_from_double(DBL_TRUE_MIN, SQ1_16, r, &fl), 0, 0, 0);
    CHECK_3(c5_fx_from_double(DBL_MIN / 2, SQ0_61, r, &fl), 0, 0, 0);
    CHECK_3(c5_fx_from_double(-DBL_TRUE_MIN, SQ1_16, r, &fl), -1, 0, 0);
    CHECK_3(c5_fx_from_double(-DBL_MIN / 2, SQ0_61, r, &fl), -1, 0, 0);
    CHECK_FLAGS(fl, 0, 0);
    /* ... and in an unsigned format that -1 LSB is below the range: clamped and counted. */
    CHECK_INT(c5_fx_from_double(-DBL_TRUE_MIN, UQ0_8, C5_RND_TRUNC, &fl), 0);
    CHECK_FLAGS(fl, 1, 0);
    CHECK_INT(c5_fx_from_double(-DBL_TRUE_MIN, UQ0_8, C5_RND_HALF_UP, &fl), 0);
    CHECK_FLAGS(fl, 1, 0);
    /* NULL flags are allowed. */
    CHECK_INT(c5_fx_from_double(NAN, SQ1_16, C5_RND_TRUNC, NULL), 0);
    CHECK_INT(c5_fx_from_double(INFINITY, UQ0_8, C5_RND_TRUNC, NULL), 255);
}

TEST(fixed_from_double_62bit)
{
    c5_fx_flags fl = {0};
    /* Exact powers of two up to the top of 62-bit formats. */
    CHECK_INT(c5_fx_from_double(0x1p61, UQ62_0, C5_RND_TRUNC, &fl), P2(61));
    CHECK_INT(c5_fx_from_double(-1.0, SQ0_61, C5_RND_TRUNC, &fl), -P2(61));
    CHECK_INT(c5_fx_from_double(0x1p-62, UQ0_62, C5_RND_TRUNC, &fl), 1);
    CHECK_INT(c5_fx_from_double(0x1p-63, UQ0_62, C5_RND_HALF_UP, &fl), 1);
    CHECK_INT(c5_fx_from_double(0x1p-63, UQ0_62, C5_RND_HALF_EVEN, &fl), 0);
    /* 1 - 2^-53 (the double below 1) in UQ0.62: raw 2^62 - 2^9, exact. */
    CHECK_INT(c5_fx_from_double(1.0 - 0x1p-53, UQ0_62, C5_RND_HALF_UP, &fl), P2(62) - P2(9));
    CHECK_FLAGS(fl, 0, 0);
    /* 2^62 is one LSB above UQ62.0's max; 1.0 one LSB above UQ0.62's. */
    CHECK_INT(c5_fx_from_double(0x1p62, UQ62_0, C5_RND_TRUNC, &fl), P2(62) - 1);
    CHECK_INT(c5_fx_from_double(1.0, UQ0_62, C5_RND_TRUNC, &fl), P2(62) - 1);
    CHECK_INT(c5_fx_from_double(1.0, SQ0_61, C5_RND_TRUNC, &fl), P2(61) - 1);
    /* 2^63 and beyond: outside int64 itself. */
    CHECK_INT(c5_fx_from_double(0x1p63, UQ62_0, C5_RND_TRUNC, &fl), P2(62) - 1);
    CHECK_INT(c5_fx_from_double(-0x1p63, SQ0_61, C5_RND_TRUNC, &fl), -P2(61));
    CHECK_INT(c5_fx_from_double(-0x1p64, SQ0_61, C5_RND_TRUNC, &fl), -P2(61));
    CHECK_FLAGS(fl, 6, 0);
}

TEST(fixed_to_double)
{
    CHECK(c5_fx_to_double(-131072, SQ1_16) == -2.0);
    CHECK(c5_fx_to_double(131071, SQ1_16) == 2.0 - 0x1p-16);
    CHECK(c5_fx_to_double(2097151, UQ9_12) == 512.0 - 0x1p-12);
    CHECK(c5_fx_to_double(1, UQ9_12) == 0x1p-12);
    CHECK(c5_fx_to_double(255, UQ0_8) == 1.0 - 0x1p-8);
    CHECK(c5_fx_to_double(INT32_MIN, SQ15_16) == -32768.0);
    CHECK(c5_fx_to_double(-P2(61), SQ0_61) == -1.0);
    CHECK(c5_fx_to_double(1, UQ0_62) == 0x1p-62);
    /* Wider than 53 bits: rounded to the nearest double, as documented. */
    CHECK(c5_fx_to_double(P2(62) - 1, UQ62_0) == 0x1p62);
    CHECK(c5_fx_to_double(P2(62) - 1, UQ0_62) == 1.0);
    /* Round trip through double is exact for every format of at most 53 bits. */
    for (int i = 0; i < N_FORMATS; i++) {
        c5_fx_fmt f = FORMATS[i];
        if (c5_fx_width(f) > 53)
            continue;
        int64_t v[4] = {c5_fx_min_raw(f), c5_fx_max_raw(f), 1, c5_fx_max_raw(f) / 3};
        for (int j = 0; j < 4; j++)
            CHECK_MSG(c5_fx_from_double(c5_fx_to_double(v[j], f), f, C5_RND_TRUNC, NULL) == v[j],
                      "%s: raw %lld does not round-trip", f.name, (long long)v[j]);
    }
}

/* ---- the extremes of every format ------------------------------------------------- */

TEST(fixed_extremes_every_format)
{
    for (int i = 0; i < N_FORMATS; i++) {
        c5_fx_fmt f = FORMATS[i];
        int64_t lo = c5_fx_min_raw(f), hi = c5_fx_max_raw(f);
        for (int ri = 0; ri < 3; ri++) {
            c5_rnd r = RND[ri];
            c5_fx_flags fl = {0};
            /* min and max themselves: no saturation */
            CHECK_MSG(c5_fx_convert(hi, f, f, r, &fl) == hi, "%s: max", f.name);
            CHECK_MSG(c5_fx_convert(lo, f, f, r, &fl) == lo, "%s: min", f.name);
            CHECK_MSG(c5_fx_add(hi, f, 0, f, f, r, &fl) == hi, "%s: max + 0", f.name);
            CHECK_MSG(c5_fx_sub(lo, f, 0, f, f, r, &fl) == lo, "%s: min - 0", f.name);
            CHECK_MSG(c5_fx_add(hi - 1, f, 1, f, f, r, &fl) == hi, "%s: max-1 + 1 LSB", f.name);
            CHECK_MSG(fl.saturations == 0, "%s [%s]: spurious saturation", f.name, c5_rnd_name(r));
            /* max + 1 LSB and min - 1 LSB: clamped and counted, once each */
            CHECK_MSG(c5_fx_add(hi, f, 1, f, f, r, &fl) == hi, "%s: max + 1 LSB", f.name);
            CHECK_MSG(fl.saturations == 1, "%s: max + 1 LSB not counted", f.name);
            CHECK_MSG(c5_fx_sub(lo, f, 1, f, f, r, &fl) == lo, "%s: min - 1 LSB", f.name);
            CHECK_MSG(fl.saturations == 2, "%s: min - 1 LSB not counted", f.name);
            /* the same through from_double, where the value is an exact double */
            double above = ldexp(1.0, f.int_bits); /* max + 1 LSB */
            CHECK_MSG(c5_fx_from_double(above, f, r, &fl) == hi && fl.saturations == 3,
                      "%s: from_double(max + 1 LSB)", f.name);
            double below = f.is_signed ? -above - ldexp(1.0, -f.frac_bits) : -ldexp(1.0, -f.frac_bits);
            if (f.is_signed && c5_fx_width(f) > 53)
                below = -2 * above; /* min - 1 LSB is not a double there; go further out */
            CHECK_MSG(c5_fx_from_double(below, f, r, &fl) == lo && fl.saturations == 4,
                      "%s: from_double(min - 1 LSB)", f.name);
            /* max + max always saturates; min + min only for signed formats */
            CHECK_MSG(c5_fx_add(hi, f, hi, f, f, r, &fl) == hi && fl.saturations == 5,
                      "%s: max + max", f.name);
            CHECK_MSG(c5_fx_add(lo, f, lo, f, f, r, &fl) == lo && fl.saturations == 5u + f.is_signed,
                      "%s: min + min", f.name);
            /* min - max and max - min */
            CHECK_MSG(c5_fx_sub(lo, f, hi, f, f, r, &fl) == lo && fl.saturations == 6u + f.is_signed,
                      "%s: min - max", f.name);
            CHECK_MSG(c5_fx_sub(hi, f, lo, f, f, r, &fl) == hi && fl.saturations == 6u + 2 * f.is_signed,
                      "%s: max - min", f.name);
            CHECK_MSG(fl.nans == 0, "%s: nans counted", f.name);
        }
    }
}

/* max*max and min*min of each format into the same format. Hand values:
 * UQ9.12  ~512^2, SQ1.16 ~2^2 and (-2)^2 = 4, UQ1.15 ~2^2, SQ15.16 ~2^30, UQ31.31 ~2^62,
 *         UQ62.0 ~2^124: all above max -> max, counted.
 * UQ0.8   (255/256)^2 = 65025/65536 = 254.0039 LSB -> 254 in every mode.
 * SQ0.61  (1 - 2^-61)^2 = 1 - 2^-60 + 2^-122 -> raw 2^61 - 2 (+ 2^-61 LSB, dropped);
 *         (-1)^2 = 1 -> one LSB above max -> max, counted.
 * UQ0.62  (1 - 2^-62)^2 = 1 - 2^-61 + 2^-124 -> raw 2^62 - 2. */
TEST(fixed_mul_extremes)
{
    struct {
        c5_fx_fmt f;
        int64_t maxmax, minmin;
        int sat_maxmax, sat_minmin;
    } t[] = {
        {UQ9_12, 2097151, 0, 1, 0},
        {SQ1_16, 131071, 131071, 1, 1},
        {UQ1_15, 65535, 0, 1, 0},
        {SQ15_16, INT32_MAX, INT32_MAX, 1, 1},
        {UQ0_8, 254, 0, 0, 0},
        {UQ31_31, P2(62) - 1, 0, 1, 0},
        {SQ0_61, P2(61) - 2, P2(61) - 1, 0, 1},
        {UQ62_0, P2(62) - 1, 0, 1, 0},
        {UQ0_62, P2(62) - 2, 0, 0, 0},
    };
    for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
        c5_fx_fmt f = t[i].f;
        int64_t lo = c5_fx_min_raw(f), hi = c5_fx_max_raw(f);
        for (int ri = 0; ri < 3; ri++) {
            c5_fx_flags fl = {0};
            int64_t got = c5_fx_mul(hi, f, hi, f, f, RND[ri], &fl);
            CHECK_MSG(got == t[i].maxmax && fl.saturations == (uint64_t)t[i].sat_maxmax,
                      "%s max*max [%s]: %lld (sat %llu)", f.name, c5_rnd_name(RND[ri]),
                      (long long)got, (unsigned long long)fl.saturations);
            fl = (c5_fx_flags){0};
            got = c5_fx_mul(lo, f, lo, f, f, RND[ri], &fl);
            CHECK_MSG(got == t[i].minmin && fl.saturations == (uint64_t)t[i].sat_minmin,
                      "%s min*min [%s]: %lld (sat %llu)", f.name, c5_rnd_name(RND[ri]),
                      (long long)got, (unsigned long long)fl.saturations);
        }
    }
    /* Into a destination wide enough, the product is exact: UQ9.12^2 -> UQ18.24. */
    c5_fx_fmt uq18_24 = {18, 24, 0, "UQ18.24"};
    CHECK_INT(c5_fx_mul(2097151, UQ9_12, 2097151, UQ9_12, uq18_24, C5_RND_TRUNC, NULL),
              2097151LL * 2097151LL);
    /* SQ0.61: min * max = -(1 - 2^-61), exact. */
    CHECK_INT(c5_fx_mul(-P2(61), SQ0_61, P2(61) - 1, SQ0_61, SQ0_61, C5_RND_TRUNC, NULL), -(P2(61) - 1));
}

/* ---- add / sub -------------------------------------------------------------------- */

TEST(fixed_add_sub_values)
{
    c5_fx_flags fl = {0};
    /* 1.5 (SQ1.16) + 0.25 (UQ0.8) = 1.75 -> UQ9.12 raw 7168 */
    CHECK_3(c5_fx_add(98304, SQ1_16, 64, UQ0_8, UQ9_12, r, &fl), 7168, 7168, 7168);
    /* 1.5 - 0.25 = 1.25 -> SQ1.16 raw 81920 */
    CHECK_3(c5_fx_sub(98304, SQ1_16, 64, UQ0_8, SQ1_16, r, &fl), 81920, 81920, 81920);
    /* Sums in units of 2^-16 into SQ1.15 (LSB 2^-15): 3 -> 1.5 LSB, -3 -> -1.5, -5 -> -2.5. */
    CHECK_3(c5_fx_add(1, SQ1_16, 2, SQ1_16, SQ1_15, r, &fl), 1, 2, 2);
    CHECK_3(c5_fx_add(-1, SQ1_16, -2, SQ1_16, SQ1_15, r, &fl), -2, -1, -2);
    CHECK_3(c5_fx_sub(-3, SQ1_16, 2, SQ1_16, SQ1_15, r, &fl), -3, -2, -2);
    CHECK_3(c5_fx_sub(1, SQ1_16, 6, SQ1_16, SQ1_15, r, &fl), -3, -2, -2);
    /* exactly 1 LSB, and half an LSB */
    CHECK_3(c5_fx_add(1, SQ1_16, 1, SQ1_16, SQ1_15, r, &fl), 1, 1, 1);
    CHECK_3(c5_fx_add(3, SQ15_16, -2, SQ1_16, SQ1_15, r, &fl), 0, 1, 0);
    CHECK_FLAGS(fl, 0, 0);
    /* Negative result into an unsigned format: 0.25 - 0.5 -> 0, counted. */
    CHECK_3(c5_fx_sub(64, UQ0_8, 128, UQ0_8, UQ9_12, r, &fl), 0, 0, 0);
    CHECK_FLAGS(fl, 3, 0);
}

/* Alignment across the full 62-bit span: max(UQ0.62) + max(UQ62.0) = 2^62 - 2^-62.
 * Truncated to UQ62.0 that is max itself (no saturation); rounded to nearest it is 2^62,
 * one above max (saturation). The exact sum needs 124 bits. */
TEST(fixed_add_62bit_alignment)
{
    c5_fx_flags fl = {0};
    int64_t hi = P2(62) - 1;
    CHECK_INT(c5_fx_add(hi, UQ0_62, hi, UQ62_0, UQ62_0, C5_RND_TRUNC, &fl), hi);
    CHECK_FLAGS(fl, 0, 0);
    CHECK_INT(c5_fx_add(hi, UQ0_62, hi, UQ62_0, UQ62_0, C5_RND_HALF_UP, &fl), hi);
    CHECK_FLAGS(fl, 1, 0);
    CHECK_INT(c5_fx_add(hi, UQ0_62, hi, UQ62_0, UQ62_0, C5_RND_HALF_EVEN, &fl), hi);
    CHECK_FLAGS(fl, 2, 0);
    /* 2^-62 - 1 into SQ0.61: -1 + 2^-62 is half an SQ0.61 LSB above -1. */
    CHECK_3(c5_fx_sub(1, UQ0_62, 1, UQ62_0, SQ0_61, r, &fl), -P2(61), -P2(61) + 1, -P2(61));
    CHECK_FLAGS(fl, 2, 0);
}

/* ---- convert ---------------------------------------------------------------------- */

TEST(fixed_convert_widths)
{
    c5_fx_flags fl = {0};
    /* Widening is exact. */
    CHECK_3(c5_fx_convert(255, UQ0_8, UQ9_12, r, &fl), 4080, 4080, 4080);
    CHECK_3(c5_fx_convert(-131072, SQ1_16, SQ15_16, r, &fl), -131072, -131072, -131072);
    CHECK_3(c5_fx_convert(255, UQ0_8, UQ0_62, r, &fl), 255 * P2(54), 255 * P2(54), 255 * P2(54));
    CHECK_3(c5_fx_convert(-P2(61), SQ0_61, SQ15_16, r, &fl), -65536, -65536, -65536);
    CHECK_FLAGS(fl, 0, 0);
    /* Narrowing rounds: UQ9.12 -> UQ0.8 divides the raw value by 16.
     * 24 -> 1.5, 40 -> 2.5, 4087 -> 255.4375 */
    CHECK_3(c5_fx_convert(24, UQ9_12, UQ0_8, r, &fl), 1, 2, 2);
    CHECK_3(c5_fx_convert(40, UQ9_12, UQ0_8, r, &fl), 2, 3, 2);
    CHECK_3(c5_fx_convert(4087, UQ9_12, UQ0_8, r, &fl), 255, 255, 255);
    CHECK_FLAGS(fl, 0, 0);
    /* 4088 -> 255.5: rounding up gives 256, above UQ0.8's max: clamped and counted. */
    CHECK_3(c5_fx_convert(4088, UQ9_12, UQ0_8, r, &fl), 255, 255, 255);
    CHECK_FLAGS(fl, 2, 0);
    /* Range: 1.0 does not fit UQ0.8; 3.0 and -3.0 do not fit SQ1.16; negative -> unsigned. */
    CHECK_INT(c5_fx_convert(4096, UQ9_12, UQ0_8, C5_RND_TRUNC, &fl), 255);
    CHECK_INT(c5_fx_convert(3 * 65536, SQ15_16, SQ1_16, C5_RND_TRUNC, &fl), 131071);
    CHECK_INT(c5_fx_convert(-3 * 65536, SQ15_16, SQ1_16, C5_RND_TRUNC, &fl), -131072);
    CHECK_INT(c5_fx_convert(-65536, SQ1_16, UQ1_15, C5_RND_HALF_UP, &fl), 0);
    CHECK_FLAGS(fl, 6, 0);
    /* -1 LSB of SQ1.16 into UQ1.15 is -0.5 LSB: the nearest modes make it 0 (in range,
     * nothing counted), trunc makes it -1 (clamped, counted). Round first, then clamp. */
    CHECK_INT(c5_fx_convert(-1, SQ1_16, UQ1_15, C5_RND_HALF_UP, &fl), 0);
    CHECK_INT(c5_fx_convert(-1, SQ1_16, UQ1_15, C5_RND_HALF_EVEN, &fl), 0);
    CHECK_FLAGS(fl, 6, 0);
    CHECK_INT(c5_fx_convert(-1, SQ1_16, UQ1_15, C5_RND_TRUNC, &fl), 0);
    CHECK_FLAGS(fl, 7, 0);
    /* 62-bit extremes: UQ31.31 max -> UQ0.8 saturates; UQ0.62 max -> UQ0.8 is
     * 255.99999... LSB: trunc 255, nearest 256 -> clamped. */
    fl = (c5_fx_flags){0};
    CHECK_INT(c5_fx_convert(P2(62) - 1, UQ31_31, UQ0_8, C5_RND_TRUNC, &fl), 255);
    CHECK_FLAGS(fl, 1, 0);
    CHECK_3(c5_fx_convert(P2(62) - 1, UQ0_62, UQ0_8, r, &fl), 255, 255, 255);
    CHECK_FLAGS(fl, 3, 0);
    /* UQ62.0 -> UQ0.62: only 0 fits; 1 is one LSB above max. */
    CHECK_INT(c5_fx_convert(0, UQ62_0, UQ0_62, C5_RND_TRUNC, &fl), 0);
    CHECK_INT(c5_fx_convert(1, UQ62_0, UQ0_62, C5_RND_TRUNC, &fl), P2(62) - 1);
    CHECK_FLAGS(fl, 4, 0);
    /* UQ0.62 -> UQ62.0: everything below 1/2 rounds to 0; max rounds to 1 except in trunc. */
    CHECK_3(c5_fx_convert(P2(61), UQ0_62, UQ62_0, r, &fl), 0, 1, 0);
    CHECK_3(c5_fx_convert(P2(62) - 1, UQ0_62, UQ62_0, r, &fl), 0, 1, 1);
    CHECK_FLAGS(fl, 4, 0);
}

/* ---- mul -------------------------------------------------------------------------- */

TEST(fixed_mul_values)
{
    c5_fx_flags fl = {0};
    /* SQ3.2 operands (LSB 1/4) into SQ7.0: ties in both directions. */
    c5_fx_fmt sq3_2 = {3, 2, 1, "SQ3.2"};
    CHECK_3(c5_fx_mul(5, sq3_2, 8, sq3_2, SQ7_0, r, &fl), 2, 3, 2);     /* 1.25 * 2 = 2.5 */
    CHECK_3(c5_fx_mul(-5, sq3_2, 8, sq3_2, SQ7_0, r, &fl), -3, -2, -2); /* -2.5 */
    CHECK_3(c5_fx_mul(-3, sq3_2, 8, sq3_2, SQ7_0, r, &fl), -2, -1, -2); /* -1.5 */
    CHECK_3(c5_fx_mul(3, sq3_2, 8, sq3_2, SQ7_0, r, &fl), 1, 2, 2);     /* 1.5 */
    CHECK_3(c5_fx_mul(3, sq3_2, -3, sq3_2, SQ7_0, r, &fl), -1, -1, -1); /* -0.5625 */
    /* (21845 * 2^-16)^2 = 7281.55 LSB of SQ1.16 */
    CHECK_3(c5_fx_mul(21845, SQ1_16, 21845, SQ1_16, SQ1_16, r, &fl), 7281, 7282, 7282);
    CHECK_3(c5_fx_mul(-21845, SQ1_16, 21845, SQ1_16, SQ1_16, r, &fl), -7282, -7282, -7282);
    /* Mixed formats: 1.5 (SQ1.16) * 100.25 (UQ9.12) = 150.375 -> SQ15.16 */
    CHECK_3(c5_fx_mul(98304, SQ1_16, 410624, UQ9_12, SQ15_16, r, &fl), 9854976, 9854976, 9854976);
    CHECK_FLAGS(fl, 0, 0);
    /* 1.5 * -1.5 = -2.25 is below SQ1.16's min */
    CHECK_INT(c5_fx_mul(98304, SQ1_16, -98304, SQ1_16, SQ1_16, C5_RND_HALF_UP, &fl), -131072);
    /* A negative product into an unsigned format */
    CHECK_INT(c5_fx_mul(-1, SQ1_16, 1, SQ1_16, UQ9_12, C5_RND_TRUNC, &fl), 0);
    CHECK_FLAGS(fl, 2, 0);
    /* ... but -2^-32 rounds to 0 in the nearest modes before the clamp: nothing counted. */
    CHECK_INT(c5_fx_mul(-1, SQ1_16, 1, SQ1_16, UQ9_12, C5_RND_HALF_UP, &fl), 0);
    CHECK_FLAGS(fl, 2, 0);
    /* Products far below the LSB: the shift of 2^-122 down to SQ0.0 (124 bits) */
    c5_fx_fmt sq0_0 = {0, 0, 1, "SQ0.0"};
    CHECK_3(c5_fx_mul(1, SQ0_61, 1, SQ0_61, sq0_0, r, &fl), 0, 0, 0);
    CHECK_3(c5_fx_mul(-1, SQ0_61, 1, SQ0_61, sq0_0, r, &fl), -1, 0, 0);
    CHECK_3(c5_fx_mul(1, UQ0_62, 1, UQ0_62, UQ62_0, r, &fl), 0, 0, 0);
    CHECK_FLAGS(fl, 2, 0);
}

/* ---- div -------------------------------------------------------------------------- */

TEST(fixed_div_values)
{
    c5_fx_flags fl = {0};
    int64_t one = 65536; /* 1.0 in SQ1.16 / SQ15.16 */
    CHECK_3(c5_fx_div(one, SQ1_16, 3 * one, SQ15_16, SQ1_16, r, &fl), 21845, 21845, 21845);
    CHECK_3(c5_fx_div(-one, SQ1_16, 3 * one, SQ15_16, SQ1_16, r, &fl), -21846, -21845, -21845);
    CHECK_3(c5_fx_div(one, SQ1_16, -3 * one, SQ15_16, SQ1_16, r, &fl), -21846, -21845, -21845);
    /* Integer ties: 5/2, -5/2, 5/-2, -3/2, -7/2 */
    CHECK_3(c5_fx_div(5, SQ7_0, 2, SQ7_0, SQ7_0, r, &fl), 2, 3, 2);
    CHECK_3(c5_fx_div(-5, SQ7_0, 2, SQ7_0, SQ7_0, r, &fl), -3, -2, -2);
    CHECK_3(c5_fx_div(5, SQ7_0, -2, SQ7_0, SQ7_0, r, &fl), -3, -2, -2);
    CHECK_3(c5_fx_div(-3, SQ7_0, 2, SQ7_0, SQ7_0, r, &fl), -2, -1, -2);
    CHECK_3(c5_fx_div(-7, SQ7_0, -2, SQ7_0, SQ7_0, r, &fl), 3, 4, 4);
    /* Exact: 100.25 / 0.25 = 401 */
    CHECK_3(c5_fx_div(410624, UQ9_12, 64, UQ0_8, UQ9_12, r, &fl), 401 * 4096, 401 * 4096, 401 * 4096);
    CHECK_FLAGS(fl, 0, 0);
    /* Overflow: 1.0 / 2^-16 = 65536 is beyond SQ1.16 and SQ15.16 */
    CHECK_INT(c5_fx_div(one, SQ1_16, 1, SQ1_16, SQ1_16, C5_RND_TRUNC, &fl), 131071);
    CHECK_INT(c5_fx_div(one, SQ1_16, 1, SQ1_16, SQ15_16, C5_RND_TRUNC, &fl), INT32_MAX);
    CHECK_INT(c5_fx_div(-one, SQ1_16, 1, SQ1_16, SQ15_16, C5_RND_TRUNC, &fl), INT32_MIN);
    CHECK_FLAGS(fl, 3, 0);
    /* 62-bit operands, dividend scale 2^124: max(UQ62.0) / 2^-62 saturates without
     * forming the 186-bit dividend. */
    CHECK_INT(c5_fx_div(P2(62) - 1, UQ62_0, 1, UQ0_62, UQ0_62, C5_RND_TRUNC, &fl), P2(62) - 1);
    CHECK_INT(c5_fx_div(-P2(61), SQ0_61, 1, UQ0_62, SQ0_61, C5_RND_TRUNC, &fl), -P2(61));
    CHECK_FLAGS(fl, 5, 0);
    /* ... with the sign of the quotient, not of the dividend: max(UQ62.0) / -2^-16 */
    CHECK_INT(c5_fx_div(P2(62) - 1, UQ62_0, -1, SQ1_16, SQ0_61, C5_RND_TRUNC, &fl), -P2(61));
    CHECK_INT(c5_fx_div(-P2(61), SQ0_61, -1, SQ1_16, SQ0_61, C5_RND_TRUNC, &fl), P2(61) - 1);
    fl = (c5_fx_flags){0};
    /* 1 / (1 - 2^-62) into UQ1.60 = 2^60 (1 + 2^-62 + ...) raw: 2^60 + 0.25 -> 2^60. */
    c5_fx_fmt uq1_60 = {1, 60, 0, "UQ1.60"};
    CHECK_3(c5_fx_div(1, UQ62_0, P2(62) - 1, UQ0_62, uq1_60, r, &fl), P2(60), P2(60), P2(60));
    /* 2^-62 / (2^62 - 1) into UQ0.62: ~2^-124, far below half an LSB */
    CHECK_3(c5_fx_div(1, UQ0_62, P2(62) - 1, UQ62_0, UQ0_62, r, &fl), 0, 0, 0);
    CHECK_FLAGS(fl, 0, 0);
}

TEST(fixed_div_by_zero)
{
    c5_fx_flags fl = {0};
    CHECK_3(c5_fx_div(1, SQ1_16, 0, SQ1_16, SQ1_16, r, &fl), 131071, 131071, 131071);
    CHECK_FLAGS(fl, 3, 0);
    CHECK_3(c5_fx_div(-1, SQ1_16, 0, UQ9_12, SQ15_16, r, &fl), INT32_MIN, INT32_MIN, INT32_MIN);
    CHECK_FLAGS(fl, 6, 0);
    CHECK_INT(c5_fx_div(-1, SQ1_16, 0, UQ9_12, UQ9_12, C5_RND_TRUNC, &fl), 0);
    CHECK_FLAGS(fl, 7, 0);
    CHECK_INT(c5_fx_div(P2(62) - 1, UQ62_0, 0, UQ62_0, UQ0_62, C5_RND_TRUNC, &fl), P2(62) - 1);
    CHECK_FLAGS(fl, 8, 0);
    /* 0/0: no meaningful value, 0, counted as a NaN */
    CHECK_3(c5_fx_div(0, SQ1_16, 0, SQ1_16, SQ1_16, r, &fl), 0, 0, 0);
    CHECK_FLAGS(fl, 8, 3);
    /* 0 / x is 0 with nothing counted, even when x is tiny */
    CHECK_INT(c5_fx_div(0, UQ62_0, 1, UQ0_62, UQ0_62, C5_RND_TRUNC, &fl), 0);
    CHECK_FLAGS(fl, 8, 3);
    CHECK_INT(c5_fx_div(5, SQ1_16, 0, SQ1_16, SQ1_16, C5_RND_TRUNC, NULL), 131071);
}

/* ---- shift ------------------------------------------------------------------------ */

TEST(fixed_shift_values)
{
    c5_fx_flags fl = {0};
    /* Right shifts round: 3 >> 1 = 1.5, -3 >> 1 = -1.5, -5 >> 1 = -2.5, 5 >> 2 = 1.25 */
    CHECK_3(c5_fx_shift(3, SQ1_16, -1, SQ1_16, r, &fl), 1, 2, 2);
    CHECK_3(c5_fx_shift(-3, SQ1_16, -1, SQ1_16, r, &fl), -2, -1, -2);
    CHECK_3(c5_fx_shift(-5, SQ1_16, -1, SQ1_16, r, &fl), -3, -2, -2);
    CHECK_3(c5_fx_shift(5, SQ1_16, -2, SQ1_16, r, &fl), 1, 1, 1);
    CHECK_3(c5_fx_shift(-6, SQ1_16, -2, SQ1_16, r, &fl), -2, -1, -2);
    /* Left shifts are exact while they fit: 0.75 << 1 = 1.5; -1 << 1 = -2 = min */
    CHECK_3(c5_fx_shift(49152, SQ1_16, 1, SQ1_16, r, &fl), 98304, 98304, 98304);
    CHECK_3(c5_fx_shift(-65536, SQ1_16, 1, SQ1_16, r, &fl), -131072, -131072, -131072);
    CHECK_INT(c5_fx_shift(7, SQ1_16, 0, SQ1_16, C5_RND_TRUNC, &fl), 7);
    CHECK_FLAGS(fl, 0, 0);
    /* ... and saturate when they do not: 1.0 << 1 = 2.0 > max; -1 LSB << 17 < min */
    CHECK_INT(c5_fx_shift(65536, SQ1_16, 1, SQ1_16, C5_RND_TRUNC, &fl), 131071);
    CHECK_INT(c5_fx_shift(-1, SQ1_16, 18, SQ1_16, C5_RND_TRUNC, &fl), -131072);
    CHECK_INT(c5_fx_shift(1, UQ0_62, 62, UQ0_62, C5_RND_TRUNC, &fl), P2(62) - 1);
    CHECK_FLAGS(fl, 3, 0);
    CHECK_INT(c5_fx_shift(-1, SQ1_16, 17, SQ1_16, C5_RND_TRUNC, &fl), -131072); /* exactly min */
    CHECK_INT(c5_fx_shift(1, UQ0_62, 61, UQ0_62, C5_RND_TRUNC, &fl), P2(61));
    CHECK_FLAGS(fl, 3, 0);
    /* Huge shifts: no undefined behaviour, same answers as any shift beyond the width */
    CHECK_INT(c5_fx_shift(1, SQ1_16, INT_MAX, SQ1_16, C5_RND_TRUNC, &fl), 131071);
    CHECK_INT(c5_fx_shift(-1, SQ1_16, 1000, SQ1_16, C5_RND_TRUNC, &fl), -131072);
    CHECK_INT(c5_fx_shift(1, SQ1_16, 63, SQ1_16, C5_RND_TRUNC, &fl), 131071);
    CHECK_INT(c5_fx_shift(-1, SQ0_61, 64, SQ0_61, C5_RND_TRUNC, &fl), -P2(61));
    CHECK_INT(c5_fx_shift(1, UQ0_62, 65, UQ0_62, C5_RND_TRUNC, &fl), P2(62) - 1);
    CHECK_FLAGS(fl, 8, 0);
    fl = (c5_fx_flags){0};
    CHECK_3(c5_fx_shift(131071, SQ1_16, INT_MIN, SQ1_16, r, &fl), 0, 0, 0);
    CHECK_3(c5_fx_shift(-1, SQ1_16, -1000, SQ1_16, r, &fl), -1, 0, 0);
    CHECK_3(c5_fx_shift(-P2(61), SQ0_61, -1, SQ0_61, r, &fl), -P2(60), -P2(60), -P2(60));
    CHECK_3(c5_fx_shift(-P2(61), SQ0_61, -62, SQ0_61, r, &fl), -1, 0, 0); /* -0.5 LSB */
    CHECK_3(c5_fx_shift(-P2(61) + 1, SQ0_61, -62, SQ0_61, r, &fl), -1, 0, 0);
    CHECK_3(c5_fx_shift(-P2(61), SQ0_61, -61, SQ0_61, r, &fl), -1, -1, -1); /* exact */
    CHECK_3(c5_fx_shift(-P2(61), SQ0_61, -123, SQ0_61, r, &fl), -1, 0, 0);
    CHECK_3(c5_fx_shift(P2(61) - 1, SQ0_61, -61, SQ0_61, r, &fl), 0, 1, 1); /* 1 - 2^-61 */
    CHECK_FLAGS(fl, 0, 0);
    /* Into another format: 2^-16 << 16 = 1 in SQ15.0 */
    CHECK_INT(c5_fx_shift(1, SQ1_16, 16, SQ15_0, C5_RND_TRUNC, &fl), 1);
    CHECK_FLAGS(fl, 0, 0);
}

/* ---- sqrt ------------------------------------------------------------------------- */

TEST(fixed_sqrt_values)
{
    c5_fx_flags fl = {0};
    CHECK_3(c5_fx_sqrt(0, UQ9_12, UQ9_12, r, &fl), 0, 0, 0);
    CHECK_3(c5_fx_sqrt(4 * 4096, UQ9_12, UQ9_12, r, &fl), 8192, 8192, 8192); /* sqrt 4 = 2 */
    CHECK_3(c5_fx_sqrt(2 * 4096, UQ9_12, UQ9_12, r, &fl), 5792, 5793, 5793); /* 5792.62 */
    /* Ties exist: sqrt(1/4) = 1/2 and sqrt(9/4) = 3/2 into an integer format */
    c5_fx_fmt uq2_2 = {2, 2, 0, "UQ2.2"}, uq2_0 = {2, 0, 0, "UQ2.0"};
    CHECK_3(c5_fx_sqrt(1, uq2_2, uq2_0, r, &fl), 0, 1, 0);
    CHECK_3(c5_fx_sqrt(9, uq2_2, uq2_0, r, &fl), 1, 2, 2);
    CHECK_3(c5_fx_sqrt(4, uq2_2, uq2_0, r, &fl), 1, 1, 1);
    /* A signed format with a nonnegative value is fine: sqrt(1.5625) = 1.25 */
    CHECK_3(c5_fx_sqrt(102400, SQ1_16, UQ1_15, r, &fl), 40960, 40960, 40960);
    CHECK_FLAGS(fl, 0, 0);
    /* sqrt(2^62 - 1) = 2^31 - 2^-32...: trunc 2^31 - 1 fits UQ31.0; nearest is 2^31: clamped */
    c5_fx_fmt uq31_0 = {31, 0, 0, "UQ31.0"};
    CHECK_3(c5_fx_sqrt(P2(62) - 1, UQ62_0, uq31_0, r, &fl), P2(31) - 1, P2(31) - 1, P2(31) - 1);
    CHECK_FLAGS(fl, 2, 0);
    /* Negative input: 0, counted as a NaN */
    CHECK_INT(c5_fx_sqrt(-1, SQ1_16, UQ1_15, C5_RND_HALF_UP, &fl), 0);
    CHECK_FLAGS(fl, 2, 1);
    /* Results far beyond any format saturate before the 188-bit radicand is formed:
     * sqrt(2^62 - 1) with 62 fraction bits in the result */
    CHECK_INT(c5_fx_sqrt(P2(62) - 1, UQ62_0, UQ0_62, C5_RND_TRUNC, &fl), P2(62) - 1);
    CHECK_FLAGS(fl, 3, 1);
}

/* Reference square root, independent of the library's digit-by-digit method: binary search
 * on comparisons of s^2 with a 2^e (exact in u128; an overflowing side is the larger). */
static int cmp_sq(u128 s, uint64_t a, int e)
{
    u128 sq = s * s, lhs = sq, rhs = a;
    if (e >= 0) {
        if (a != 0 && (e >= 128 || __builtin_mul_overflow(rhs, (u128)1 << e, &rhs)))
            return -1; /* a 2^e >= 2^128 > s^2 */
        if (a == 0)
            rhs = 0;
    } else {
        if (-e >= 127 || __builtin_mul_overflow(sq, (u128)1 << -e, &lhs))
            return sq ? 1 : (a ? -1 : 0);
    }
    return lhs < rhs ? -1 : lhs > rhs;
}

/* The expected raw sqrt of a (fa) in dst, rounded per rnd and saturated; *sat set when the
 * result clamps. Search bound 2^62 + 1 exceeds every max, so a clamp is still seen. */
static int64_t ref_sqrt(int64_t a, c5_fx_fmt fa, c5_fx_fmt dst, c5_rnd rnd, int *sat)
{
    int e = 2 * dst.frac_bits - fa.frac_bits; /* result^2 = a 2^e */
    u128 lo = 0, hi = ((u128)1 << 62) + 1;    /* floor root in [lo, hi] */
    while (lo < hi) {
        u128 mid = lo + (hi - lo + 1) / 2;
        if (cmp_sq(mid, (uint64_t)a, e) <= 0)
            lo = mid;
        else
            hi = mid - 1;
    }
    u128 root = lo;
    /* nearest: compare (root + 1/2)^2 = (2 root + 1)^2 / 4 with a 2^e */
    int c = cmp_sq(2 * root + 1, (uint64_t)a, e + 2); /* <0: above half, 0: tie */
    if (rnd == C5_RND_HALF_UP && c <= 0)
        root++;
    if (rnd == C5_RND_HALF_EVEN && (c < 0 || (c == 0 && root % 2 == 1)))
        root++;
    *sat = root > (u128)c5_fx_max_raw(dst);
    return *sat ? c5_fx_max_raw(dst) : (int64_t)root;
}

TEST(fixed_sqrt_extremes)
{
    c5_fx_fmt dsts[] = {UQ9_12, UQ1_15, UQ0_8, UQ31_31, SQ15_16, UQ0_62, UQ62_0, {16, 16, 0, "UQ16.16"}};
    int n_dst = (int)(sizeof dsts / sizeof dsts[0]);
    int checked = 0, clamps = 0;
    for (int i = 0; i < N_FORMATS; i++) {
        c5_fx_fmt f = FORMATS[i];
        int64_t hi = c5_fx_max_raw(f);
        int64_t xs[] = {0, 1, 2, 3, 4, hi, hi - 1, hi / 2, hi / 3, hi / 4};
        for (int d = 0; d < n_dst; d++)
            for (size_t k = 0; k < sizeof xs / sizeof xs[0]; k++)
                for (int ri = 0; ri < 3; ri++) {
                    c5_fx_flags fl = {0};
                    int sat;
                    int64_t want = ref_sqrt(xs[k], f, dsts[d], RND[ri], &sat);
                    int64_t got = c5_fx_sqrt(xs[k], f, dsts[d], RND[ri], &fl);
                    CHECK_MSG(got == want && fl.saturations == (uint64_t)sat,
                              "sqrt(%lld %s) -> %s [%s]: got %lld, expected %lld (sat %d)",
                              (long long)xs[k], f.name, dsts[d].name, c5_rnd_name(RND[ri]),
                              (long long)got, (long long)want, sat);
                    checked++;
                    clamps += sat;
                }
    }
    CHECK(checked == N_FORMATS * n_dst * 10 * 3);
    CHECK(clamps > 0);
    /* The reference itself, on hand values: floor sqrt(2) in UQ9.12 */
    int sat;
    CHECK_INT(ref_sqrt(8192, UQ9_12, UQ9_12, C5_RND_TRUNC, &sat), 5792);
    CHECK_INT(ref_sqrt(1, (c5_fx_fmt){2, 2, 0, NULL}, (c5_fx_fmt){2, 0, 0, NULL}, C5_RND_HALF_EVEN, &sat), 0);
    CHECK_INT(ref_sqrt(1, (c5_fx_fmt){2, 2, 0, NULL}, (c5_fx_fmt){2, 0, 0, NULL}, C5_RND_HALF_UP, &sat), 1);
}

/* ---- randomised cross-check ------------------------------------------------------- */

/* n / d (d > 0) rounded per rnd, from the definition: the two neighbours and their
 * distances. */
static i128 ref_round(i128 n, i128 d, c5_rnd rnd)
{
    i128 below = n / d;
    if (below * d > n)
        below--; /* floor */
    i128 dist_lo = n - below * d, dist_hi = d - dist_lo;
    if (dist_lo == 0 || rnd == C5_RND_TRUNC)
        return below;
    if (dist_lo != dist_hi)
        return dist_lo < dist_hi ? below : below + 1;
    if (rnd == C5_RND_HALF_UP)
        return below + 1;
    return below % 2 == 0 ? below : below + 1;
}

/* The value v 2^k brought to dst: *sat set if clamped. */
static int64_t ref_finish(i128 v, int k, c5_fx_fmt dst, c5_rnd rnd, int *sat)
{
    i128 r;
    int64_t lo = c5_fx_min_raw(dst), hi = c5_fx_max_raw(dst);
    if (k >= 0) {
        if (k >= 127 || __builtin_mul_overflow(v, (i128)1 << k, &r))
            r = v > 0 ? (i128)hi + 1 : (i128)lo - 1; /* far out: any value beyond the range */
        if (v == 0)
            r = 0;
    } else {
        r = ref_round(v, (i128)1 << -k, rnd);
    }
    *sat = r > hi || r < lo;
    return r > hi ? hi : r < lo ? lo : (int64_t)r;
}

/* Half of the formats come from FORMATS (the ones the model uses), half are random. */
static c5_fx_fmt rand_fmt(uint64_t *s)
{
    uint64_t x = c5_splitmix64(s);
    if (x % 2)
        return FORMATS[(x >> 8) % N_FORMATS];
    c5_fx_fmt f = {0, 0, (uint8_t)((x >> 1) & 1), "random"};
    int w = 1 + (int)((x >> 2) % C5_FX_MAX_WIDTH);
    if (w == 1)
        f.is_signed = 0;
    int mag = w - f.is_signed;
    f.int_bits = (uint8_t)((x >> 16) % (uint64_t)(mag + 1));
    f.frac_bits = (uint8_t)(mag - f.int_bits);
    return f;
}

/* Raw values: the extremes and small values often, otherwise uniform over the range. */
static int64_t rand_raw(uint64_t *s, c5_fx_fmt f)
{
    int64_t lo = c5_fx_min_raw(f), hi = c5_fx_max_raw(f);
    uint64_t x = c5_splitmix64(s), span = (uint64_t)(hi - lo) + 1;
    switch (x % 8) {
    case 0: return lo;
    case 1: return hi;
    case 2: {
        int64_t v = (int64_t)((x >> 8) % 7) - 3;
        return v < lo ? lo : v > hi ? hi : v;
    }
    case 3: {
        int64_t v = hi - (int64_t)((x >> 8) % 3);
        return v < lo ? lo : v;
    }
    default: return lo + (int64_t)(c5_splitmix64(s) % span);
    }
}

static const char *fmt_s(c5_fx_fmt f, char *b) { return c5_fx_fmt_str(f, b, C5_FX_FMT_STR_LEN); }

TEST(fixed_random_crosscheck)
{
    uint64_t s = 0x5EED0F1C5ull; /* fixed seed: the same cases on every run and machine */
    enum { CASES = 3000 };
    uint64_t sats[5] = {0}, tie_or_round[5] = {0};
    char b1[C5_FX_FMT_STR_LEN], b2[C5_FX_FMT_STR_LEN], b3[C5_FX_FMT_STR_LEN];
    for (int op = 0; op < 5; op++) {
        for (int i = 0; i < CASES; i++) {
            c5_fx_fmt fa = rand_fmt(&s), fb = rand_fmt(&s), fd = rand_fmt(&s);
            int64_t a = rand_raw(&s, fa), b = rand_raw(&s, fb);
            c5_rnd rnd = RND[c5_splitmix64(&s) % 3];
            c5_fx_flags fl = {0};
            int sat = 0, nan = 0;
            int64_t got = 0, want = 0;
            int fmax = fa.frac_bits > fb.frac_bits ? fa.frac_bits : fb.frac_bits;
            i128 va = (i128)a * ((i128)1 << (fmax - fa.frac_bits));
            i128 vb = (i128)b * ((i128)1 << (fmax - fb.frac_bits));
            static const char *names[5] = {"add", "sub", "mul", "convert", "div"};
            switch (op) {
            case 0:
                got = c5_fx_add(a, fa, b, fb, fd, rnd, &fl);
                want = ref_finish(va + vb, fd.frac_bits - fmax, fd, rnd, &sat);
                break;
            case 1:
                got = c5_fx_sub(a, fa, b, fb, fd, rnd, &fl);
                want = ref_finish(va - vb, fd.frac_bits - fmax, fd, rnd, &sat);
                break;
            case 2:
                got = c5_fx_mul(a, fa, b, fb, fd, rnd, &fl);
                want = ref_finish((i128)a * b, fd.frac_bits - fa.frac_bits - fb.frac_bits, fd, rnd, &sat);
                break;
            case 3:
                got = c5_fx_convert(a, fa, fd, rnd, &fl);
                want = ref_finish(a, fd.frac_bits - fa.frac_bits, fd, rnd, &sat);
                break;
            case 4: {
                got = c5_fx_div(a, fa, b, fb, fd, rnd, &fl);
                /* a 2^-fa / (b 2^-fb) in units of 2^-fd = a 2^(fd+fb-fa) / b */
                int k = fd.frac_bits + fb.frac_bits - fa.frac_bits;
                if (b == 0) {
                    nan = a == 0;
                    sat = a != 0;
                    want = a > 0 ? c5_fx_max_raw(fd) : a < 0 ? c5_fx_min_raw(fd) : 0;
                    break;
                }
                /* |n| >= 2^126 with |b| <= 2^62 means |quotient| >= 2^64: beyond every format */
                i128 n = a, d = b, lim = (i128)1 << 126;
                if (k >= 0 && (__builtin_mul_overflow(n, (i128)1 << k, &n) || n >= lim || n <= -lim)) {
                    sat = 1;
                    want = (a > 0) == (b > 0) ? c5_fx_max_raw(fd) : c5_fx_min_raw(fd);
                    break;
                }
                if (k < 0)
                    d *= (i128)1 << -k;
                if (d < 0)
                    n = -n, d = -d;
                want = ref_finish(ref_round(n, d, rnd), 0, fd, rnd, &sat);
                break;
            }
            }
            CHECK_MSG(got == want && fl.saturations == (uint64_t)sat && fl.nans == (uint64_t)nan,
                      "case %d: %s(%lld %s, %lld %s) -> %s [%s]: got %lld (sat %llu nan %llu), "
                      "expected %lld (sat %d nan %d)",
                      i, names[op], (long long)a, fmt_s(fa, b1), (long long)b, fmt_s(fb, b2), fmt_s(fd, b3),
                      c5_rnd_name(rnd), (long long)got, (unsigned long long)fl.saturations,
                      (unsigned long long)fl.nans, (long long)want, sat, nan);
            sats[op] += (uint64_t)sat;
            tie_or_round[op] += !sat && want != 0;
        }
        /* The stream must exercise both the clamps and ordinary in-range results. */
        CHECK_MSG(sats[op] > CASES / 20 && tie_or_round[op] > CASES / 5,
                  "%s: %llu clamps, %llu nonzero in-range results: the random cases are too narrow",
                  op == 0 ? "add" : op == 1 ? "sub" : op == 2 ? "mul" : op == 3 ? "convert" : "div",
                  (unsigned long long)sats[op], (unsigned long long)tie_or_round[op]);
    }
}

/* Random square roots against the binary-search reference. */
TEST(fixed_random_sqrt)
{
    uint64_t s = 0xC0FFEE5A17ull;
    int clamps = 0;
    for (int i = 0; i < 2000; i++) {
        c5_fx_fmt fa = rand_fmt(&s), fd = rand_fmt(&s);
        int64_t a = rand_raw(&s, fa);
        if (a < 0)
            a = -(a + 1);
        c5_rnd rnd = RND[c5_splitmix64(&s) % 3];
        c5_fx_flags fl = {0};
        int sat;
        int64_t want = ref_sqrt(a, fa, fd, rnd, &sat);
        int64_t got = c5_fx_sqrt(a, fa, fd, rnd, &fl);
        char b1[C5_FX_FMT_STR_LEN], b2[C5_FX_FMT_STR_LEN];
        CHECK_MSG(got == want && fl.saturations == (uint64_t)sat,
                  "case %d: sqrt(%lld %s) -> %s [%s]: got %lld, expected %lld", i, (long long)a,
                  fmt_s(fa, b1), fmt_s(fd, b2), c5_rnd_name(rnd), (long long)got, (long long)want);
        clamps += sat;
    }
    CHECK(clamps > 20);
}

/* The counters count every event exactly once, accumulate, and NULL is accepted. */
TEST(fixed_flags_accumulate)
{
    c5_fx_flags fl = {0};
    for (int i = 0; i < 10; i++)
        c5_fx_add(131071, SQ1_16, 1, SQ1_16, SQ1_16, C5_RND_TRUNC, &fl);
    CHECK_FLAGS(fl, 10, 0);
    c5_fx_div(0, SQ1_16, 0, SQ1_16, SQ1_16, C5_RND_TRUNC, &fl);
    c5_fx_sqrt(-5, SQ1_16, SQ1_16, C5_RND_TRUNC, &fl);
    c5_fx_from_double(NAN, SQ1_16, C5_RND_TRUNC, &fl);
    CHECK_FLAGS(fl, 10, 3);
    /* Same results with and without flags */
    CHECK_INT(c5_fx_add(131071, SQ1_16, 1, SQ1_16, SQ1_16, C5_RND_TRUNC, NULL), 131071);
    CHECK_INT(c5_fx_mul(-131072, SQ1_16, -131072, SQ1_16, SQ1_16, C5_RND_TRUNC, NULL), 131071);
    CHECK_INT(c5_fx_sqrt(-1, SQ1_16, SQ1_16, C5_RND_TRUNC, NULL), 0);
    CHECK_INT(c5_fx_shift(65536, SQ1_16, 5, SQ1_16, C5_RND_TRUNC, NULL), 131071);
    CHECK_INT(c5_fx_convert(-1, SQ1_16, UQ0_8, C5_RND_TRUNC, NULL), 0);
    CHECK_FLAGS(fl, 10, 3);
}
