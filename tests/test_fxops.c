/* The datapath's inline primitives (rtl_model/proc/fxops.h) against the fixed-point layer they
 * specialise: the same bits for random and extreme operands of the model's formats. */
#include <stdint.h>
#include <string.h>

#include "fixed.h"
#include "fxops.h"
#include "geom.h"
#include "harness.h"
#include "rng.h"

/* Shifting right with half-to-even rounding is c5_fx_shift into a format with s fewer
 * fraction bits. */
TEST(fxops_rshift_matches_fx_shift)
{
    uint64_t rng = 7;
    c5_fx_fmt src = C5_SQ(15, 45, "src"), dst = C5_SQ(45, 15, "dst");
    for (int i = 0; i < 200000; i++) {
        int64_t x = (int64_t)(c5_splitmix64(&rng) >> 3) - ((int64_t)1 << 60);
        if (i < 6) /* the extremes and the ties */
            x = (int64_t[]){c5_fx_min_raw(src), c5_fx_max_raw(src), (int64_t)1 << 29, -((int64_t)1 << 29),
                            3 * ((int64_t)1 << 29), 0}[i];
        int64_t want = c5_fx_shift(x, src, 0, dst, C5_RND_HALF_EVEN, NULL);
        CHECK_MSG(c5_rshift_he(x, 30) == want, "x=%lld: %lld vs %lld", (long long)x, (long long)c5_rshift_he(x, 30),
                  (long long)want);
        CHECK_INT(c5_rshift128_he((__int128)x, 30), want);
    }
}

/* The branch-free rounding for every shift 1..62 over the whole int64 range, ties and the
 * extremes included, against the same rounding in 128 bits. */
TEST(fxops_rshift_every_shift_full_range)
{
    uint64_t rng = 19;
    for (int s = 1; s <= 62; s++)
        for (int i = 0; i < 20000; i++) {
            int64_t x = (int64_t)c5_splitmix64(&rng);
            if (i < 8)
                x = (int64_t[]){INT64_MIN, INT64_MAX, 0, -1, (int64_t)1 << (s - 1), -((int64_t)1 << (s - 1)),
                                3 * ((int64_t)1 << (s - 1)), -3 * ((int64_t)1 << (s - 1))}[i];
            else if (i % 3 == 0) /* a tie above some multiple of 2^s */
                x = (x & ~(((int64_t)1 << s) - 1)) | ((int64_t)1 << (s - 1));
            __int128 q = (__int128)x >> s, r = (__int128)x - q * ((__int128)1 << s), half = (__int128)1 << (s - 1);
            int64_t want = (int64_t)(q + (r > half || (r == half && (q & 1))));
            CHECK_MSG(c5_rshift_he(x, s) == want, "x=%lld s=%d: %lld vs %lld", (long long)x, s,
                      (long long)c5_rshift_he(x, s), (long long)want);
        }
}

/* The same for the 128-bit rounding, every shift 1..126 (the golden vectors' power table
 * shifts by 65), against the rounding written with its branch. */
TEST(fxops_rshift128_every_shift)
{
    uint64_t rng = 29;
    for (int s = 1; s <= 126; s++)
        for (int i = 0; i < 4000; i++) {
            __int128 x = (__int128)(((unsigned __int128)c5_splitmix64(&rng) << 64) | c5_splitmix64(&rng));
            x >>= i % 60; /* magnitudes from 2^127 down */
            __int128 half = (__int128)1 << (s - 1);
            if (i < 4 && s < 126) /* 3 half < 2^127 */
                x = (__int128[]){0, half, 3 * half, -3 * half}[i];
            else if (i % 3 == 0) /* a tie */
                x = (x & ~(((__int128)1 << s) - 1)) | half;
            __int128 q = x >> s, r = x - q * ((__int128)1 << s);
            int64_t want = (int64_t)(q + (r > half || (r == half && (q & 1))));
            CHECK_MSG(c5_rshift128_he(x, s) == want, "s=%d i=%d", s, i);
        }
}

/* The reciprocal only guides the quotient: a wrong one (off by parts in 2^20, or 2x) gives
 * the same integer as the division, ties included. */
TEST(fxops_div_inv_equals_div_whatever_the_reciprocal)
{
    uint64_t rng = 23;
    for (int i = 0; i < 300000; i++) {
        int64_t d = (int64_t)(c5_splitmix64(&rng) >> (19 + i % 40)) + 1;
        int64_t n = (int64_t)(c5_splitmix64(&rng) % ((uint64_t)d << 15)) - ((int64_t)d << 14);
        if (i % 7 == 0 && d % 2 == 0)
            n = d / 2 + d * (n / d); /* a tie */
        double inv = 1.0 / (double)d;
        if (i % 4 == 1)
            inv *= 1.0 + 1e-6;
        else if (i % 4 == 2)
            inv *= 1.0 - 1e-6;
        int64_t want = c5_div_he64(n, d);
        CHECK_MSG(c5_div_he64_inv(n, d, inv) == want, "%lld/%lld: %lld vs %lld", (long long)n, (long long)d,
                  (long long)c5_div_he64_inv(n, d, inv), (long long)want);
        if (i % 1000 == 0) /* far off: the loops walk it back */
            CHECK_INT(c5_div_he64_inv(n, d, 2.0 / (double)d), want);
    }
}

TEST(fxops_div_matches_fx_div)
{
    uint64_t rng = 11;
    c5_fx_fmt f = C5_SQ(30, 0, "int");
    for (int i = 0; i < 200000; i++) {
        int64_t n = (int64_t)(c5_splitmix64(&rng) >> 34) - ((int64_t)1 << 29);
        int64_t d = (int64_t)(c5_splitmix64(&rng) >> 50) + 1;
        if (i % 5 == 0)
            d = 2; /* exact ties */
        if (i % 2)
            d = -d; /* plane and grid-range t divide by negative direction components */
        int64_t want = c5_fx_div(n, f, d, f, f, C5_RND_HALF_EVEN, NULL);
        CHECK_MSG(c5_div_he(n, d) == want, "%lld/%lld: %lld vs %lld", (long long)n, (long long)d,
                  (long long)c5_div_he(n, d), (long long)want);
    }
    CHECK_INT(c5_div_he(0, -7), 0);
    CHECK_INT(c5_div_he(10, -3), -3);
    CHECK_INT(c5_div_he(-5, -2), 2); /* 2.5: the even neighbour */
}

TEST(fxops_isqrt_is_the_floor_of_the_root)
{
    uint64_t rng = 3;
    for (int i = 0; i < 100000; i++) {
        unsigned __int128 x = ((unsigned __int128)c5_splitmix64(&rng) << (i % 27)) ^ c5_splitmix64(&rng);
        if (i < 4)
            x = (unsigned __int128[]){0, 1, ((unsigned __int128)1 << 90) - 1, (unsigned __int128)UINT64_MAX}[i];
        uint64_t r = c5_isqrt(x);
        CHECK((unsigned __int128)r * r <= x);
        CHECK((unsigned __int128)(r + 1) * (r + 1) > x);
    }
}

TEST(fxops_clamp_counts_every_saturation)
{
    uint64_t sat = 0;
    CHECK_INT(c5_clamp64(5, 0, 4, &sat), 4);
    CHECK_INT(c5_clamp64(-1, 0, 4, &sat), 0);
    CHECK_INT(c5_clamp64(4, 0, 4, &sat), 4);
    CHECK_INT(c5_clamp64(0, 0, 4, &sat), 0);
    CHECK_INT(sat, 2);
}

TEST(geom_hit_plane_is_the_division_and_the_range)
{
    /* a plane's hit against t = round(num 2^14 / den) kept in (tmin, tmax): the behind-the-
     * eye shortcut without the division changes no answer, for tmin either side of 0 */
    uint64_t st = 21;
    long hits = 0, behind = 0, near_behind = 0;
    for (int i = 0; i < 200000; i++) {
        c5_surface_regs s = {.kind = C5_SURF_PLANE};
        int64_t O[3], d[3], v[3];
        for (int a = 0; a < 3; a++) {
            s.p[a] = (int64_t)(c5_splitmix64(&st) % (1u << 24)) - (1 << 23);
            O[a] = (int64_t)(c5_splitmix64(&st) % (1u << 24)) - (1 << 23);
            v[a] = (int64_t)(c5_splitmix64(&st) % (1u << 20)) - (1 << 19);
        }
        if (i % 7 == 0)
            memcpy(O, s.p, sizeof O); /* the eye on the plane: num 0 */
        else if (i % 3 == 0)      /* near it: t within a few thousand LSBs either side */
            for (int a = 0; a < 3; a++)
                O[a] = s.p[a] + (int64_t)(c5_splitmix64(&st) % 4096) - 2048;
        c5_geom_normalize(v, s.n);
        for (int a = 0; a < 3; a++)
            v[a] = (int64_t)(c5_splitmix64(&st) % (1u << 20)) - (1 << 19);
        c5_geom_normalize(v, d);
        int64_t tmin = i % 3 == 0 ? -(int64_t)(c5_splitmix64(&st) % 4096) : (int64_t)(c5_splitmix64(&st) % 4);
        __int128 den = 0, num = 0;
        for (int a = 0; a < 3; a++) {
            den += (__int128)d[a] * s.n[a];
            num += (__int128)(s.p[a] - O[a]) * s.n[a];
        }
        int64_t want_t = den ? c5_div_he(c5_shl128(num, 14), den) : 0, t = 0;
        int want = den != 0 && want_t > tmin && want_t < C5_T_INF;
        int got = c5_geom_hit(&s, O, d, tmin, C5_T_INF, &t);
        CHECK_MSG(got == want && (!got || t == want_t), "case %d: hit %d t %lld, by division %d t %lld", i, got,
                  (long long)t, want, (long long)want_t);
        hits += want;
        behind += den && want_t <= 0;
        near_behind += den && want_t <= 0 && want_t > tmin;
    }
    CHECK_MSG(hits > 50000 && behind > 50000 && near_behind > 1000, "hits %ld, behind %ld, behind within tmin < 0: %ld",
              hits, behind, near_behind);
}
