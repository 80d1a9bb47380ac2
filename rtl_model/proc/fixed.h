/* Fixed-point arithmetic of the board model: every datapath of the ray processor computes
 * through these functions, so that the C model and the VHDL agree bit for bit.
 *
 * Conventions
 * - A format is UQi.f (unsigned) or SQi.f (signed, two's complement). The sign bit is NOT
 *   counted in i: SQ1.16 is 1 + 1 + 16 = 18 bits wide and holds [-2, 2 - 2^-16];
 *   UQ9.12 is 21 bits wide and holds [0, 512 - 2^-12]. Width is 1 .. 62 bits.
 * - A value is its raw integer (an int64_t): value = raw * 2^-f. A raw value outside its
 *   format's range is a bug in the caller and trips an assert().
 * - Every operation names its destination format, its rounding mode and its flags. The
 *   exact mathematical result (no intermediate rounding, no intermediate overflow) is first
 *   rounded to the destination's LSB, then clamped to the destination's range
 *   ("round, then saturate", as an RTL rounder followed by a saturator does). Nothing ever
 *   wraps around.
 * - Every clamp increments flags->saturations; results with no meaning (NaN input,
 *   0/0, sqrt of a negative number) give 0 and increment flags->nans instead. flags may be
 *   NULL. One c5_fx_flags per datapath lets the model report how often each one saturates.
 * - Only from_double / to_double touch floating point; everything else is integer
 *   arithmetic (gcc's __int128 inside fixed.c), identical on every machine. */
#ifndef C5_FIXED_H
#define C5_FIXED_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"

#define C5_FX_MAX_WIDTH 62

typedef struct {
    uint8_t int_bits, frac_bits; /* i and f of UQi.f / SQi.f */
    uint8_t is_signed;           /* 0: UQ, 1: SQ (adds one sign bit) */
    const char *name;            /* datapath label for reports ("ray_t", ...); may be NULL */
} c5_fx_fmt;

#define C5_UQ(i, f, label) ((c5_fx_fmt){(i), (f), 0, (label)})
#define C5_SQ(i, f, label) ((c5_fx_fmt){(i), (f), 1, (label)})

/* Rounding to the destination LSB. The values start at 1 so that a zero-initialised
 * (forgotten) mode trips an assert instead of silently meaning something.
 * TRUNC      floor: drop the low bits (toward -inf, also for negative two's complement).
 *            Free in hardware, but biased by -1/2 LSB on average.
 * HALF_UP    floor(x + 1/2 LSB): ties toward +inf, so -2.5 -> -2 and 2.5 -> 3. The usual
 *            hardware rounder: one constant added at the first dropped bit (often free as
 *            the carry-in of the adder before it), then drop bits. No look at the dropped
 *            bits, so no zero-detect on the critical path; bias only at exact ties.
 * HALF_EVEN  nearest, ties to the even result (convergent): -1.5 -> -2, -2.5 -> -2,
 *            2.5 -> 2. Unbiased, but needs a zero-detect over the dropped bits below the
 *            half bit plus the kept LSB: costlier. For long accumulations. */
typedef enum { C5_RND_TRUNC = 1, C5_RND_HALF_UP = 2, C5_RND_HALF_EVEN = 3 } c5_rnd;

typedef struct {
    uint64_t saturations; /* results clamped to the destination's min or max */
    uint64_t nans;        /* NaN input, 0/0, sqrt of a negative: result 0 */
} c5_fx_flags;

/* ---- formats ---------------------------------------------------------------------- */

int c5_fx_width(c5_fx_fmt f); /* is_signed + int_bits + frac_bits */
int c5_fx_fmt_valid(c5_fx_fmt f);
/* 0 if f is a legal format (width 1 .. 62, is_signed 0 or 1), else -1 with a message. */
int c5_fx_fmt_check(c5_fx_fmt f, c5_err *err);
int64_t c5_fx_min_raw(c5_fx_fmt f); /* 0 or -2^(i+f) */
int64_t c5_fx_max_raw(c5_fx_fmt f); /* 2^(i+f) - 1 */
int c5_fx_in_range(int64_t raw, c5_fx_fmt f);

/* "UQ9.12", "SQ1.16" into buf (C5_FX_FMT_STR_LEN bytes are always enough); returns buf. */
#define C5_FX_FMT_STR_LEN 16
const char *c5_fx_fmt_str(c5_fx_fmt f, char *buf, size_t n);
const char *c5_rnd_name(c5_rnd r); /* "trunc", "half-up", "half-even" */

/* ---- conversions ------------------------------------------------------------------ */

/* x * 2^f rounded per rnd, saturated. NaN -> 0 (nans); +-inf saturate (saturations);
 * -0.0 -> 0. The scaling and rounding are exact for every double, denormals included
 * (a tiny negative value truncates to -1 LSB: floor). */
int64_t c5_fx_from_double(double x, c5_fx_fmt dst, c5_rnd rnd, c5_fx_flags *flags);
/* raw * 2^-f. Exact for widths up to 53 bits; wider values are rounded to the nearest
 * double (ties to even) by the int64 -> double conversion. */
double c5_fx_to_double(int64_t raw, c5_fx_fmt f);
/* Change of format: fraction bits rounded, range saturated. */
int64_t c5_fx_convert(int64_t a, c5_fx_fmt fa, c5_fx_fmt dst, c5_rnd rnd, c5_fx_flags *flags);

/* ---- arithmetic: exact result, then rounded to dst, then saturated to dst ---------- */

int64_t c5_fx_add(int64_t a, c5_fx_fmt fa, int64_t b, c5_fx_fmt fb, c5_fx_fmt dst, c5_rnd rnd,
                  c5_fx_flags *flags);
int64_t c5_fx_sub(int64_t a, c5_fx_fmt fa, int64_t b, c5_fx_fmt fb, c5_fx_fmt dst, c5_rnd rnd,
                  c5_fx_flags *flags);
int64_t c5_fx_mul(int64_t a, c5_fx_fmt fa, int64_t b, c5_fx_fmt fb, c5_fx_fmt dst, c5_rnd rnd,
                  c5_fx_flags *flags);
/* a / b. b == 0: a > 0 -> dst max, a < 0 -> dst min (saturations); 0/0 -> 0 (nans). */
int64_t c5_fx_div(int64_t a, c5_fx_fmt fa, int64_t b, c5_fx_fmt fb, c5_fx_fmt dst, c5_rnd rnd,
                  c5_fx_flags *flags);
/* a * 2^s (s > 0: left, saturating; s < 0: right, rounded per rnd). With dst == fa this is
 * the hardware arithmetic shift. */
int64_t c5_fx_shift(int64_t a, c5_fx_fmt fa, int s, c5_fx_fmt dst, c5_rnd rnd, c5_fx_flags *flags);
/* Square root, correctly rounded per rnd (integer digit-by-digit method). Meant for
 * unsigned inputs; a negative input gives 0 and counts in nans. */
int64_t c5_fx_sqrt(int64_t a, c5_fx_fmt fa, c5_fx_fmt dst, c5_rnd rnd, c5_fx_flags *flags);

#endif
