/* The eight-lane gradient and shading blocks (rtl_model/proc/shade_wide.h) against
 * c5_grad_blend and c5_shade, lane by lane: the same outputs and saturation counts on random
 * inputs across every range the blocks take, on every small gradient, and where the
 * normalisations meet their ties. */
#include <math.h>
#include <string.h>

#include "geom.h"
#include "harness.h"
#include "rng.h"
#include "sample_pipe.h"
#include "shade_wide.h"

static int64_t uniform_i(uint64_t *st, int64_t lo, int64_t hi)
{
    return lo + (int64_t)(c5_splitmix64(st) % (uint64_t)(hi - lo + 1));
}

/* A unit direction in SQ1.14, as the set-up unit makes them. */
static void unit_dir(uint64_t *st, int64_t out[3])
{
    int64_t v[3];
    do {
        for (int a = 0; a < 3; a++)
            v[a] = uniform_i(st, -(1 << 20), 1 << 20);
    } while (!v[0] && !v[1] && !v[2]);
    c5_geom_normalize(v, out);
}

/* Registers: ka, kd, ks, 1..3 lights of either kind (point lights near, or now and then
 * beyond the wide path's range), and a specular table of power p. Voxel coordinates are
 * geom coordinates (gscale 1.0): a lane's vpos is its geom position. */
static void random_regs(uint64_t *st, c5_frame_regs *r)
{
    memset(r, 0, sizeof *r);
    for (int a = 0; a < 3; a++)
        r->gscale[a] = 1 << 16;
    r->ka = uniform_i(st, 0, 65535);
    r->kd = uniform_i(st, 0, 65535);
    r->ks = uniform_i(st, 0, 65535);
    r->n_lights = (int)uniform_i(st, 1, 3);
    for (int i = 0; i < r->n_lights; i++) {
        c5_light_regs *l = &r->lights[i];
        l->kind = c5_splitmix64(st) & 1 ? C5_LIGHT_POINT : C5_LIGHT_DIRECTIONAL;
        int64_t far = c5_splitmix64(st) % 8 == 0 ? (int64_t)1 << 27 : (int64_t)1 << 23;
        for (int a = 0; a < 3; a++)
            l->pos[a] = uniform_i(st, -far, far);
        unit_dir(st, l->dir);
        l->intensity = uniform_i(st, 0, 65535);
    }
    double p = 1 + 99 * c5_uniform(st);
    for (int i = 0; i <= 1 << C5_POW_BITS; i++)
        r->pow_tab[i] = (int32_t)lround(pow((double)i / (1 << C5_POW_BITS), p) * 32768);
}

/* A gradient from one of the block's regimes: zero, a few LSBs (faded, and the ties of small
 * normalisations), mid-range, the largest the gradient block makes, or along one axis. */
static void random_grad(uint64_t *st, int64_t g[3])
{
    int kind = (int)(c5_splitmix64(st) % 5);
    int64_t m = kind == 0 ? 0 : kind == 1 ? 4 : kind == 2 ? 1 << 10 : (1 << 17) - 1;
    for (int a = 0; a < 3; a++)
        g[a] = uniform_i(st, -m, m);
    if (kind == 4)
        g[1] = g[2] = 0;
}

/* Lanes 0..n-1 of b from c5_shade: 1 where every output and count is the same. */
static int same_as_c5_shade(const c5_frame_regs *r, const int64_t d[3], const c5_shade_lanes *b, char *why, size_t n)
{
    for (int i = 0; i < b->n; i++) {
        c5_sample smp = {.value = 0, .grad = {b->grad[i][0], b->grad[i][1], b->grad[i][2]}};
        int64_t rgba[4] = {b->rgb[0][i], b->rgb[1][i], b->rgb[2][i], 0}, out[3], g[3];
        uint64_t sat = 0;
        int64_t v[3] = {b->vpos[0][i], b->vpos[1][i], b->vpos[2][i]};
        c5_geom_from_voxel(r, v, g);
        c5_shade(r, &smp, rgba, g, d, out, &sat);
        if (memcmp(out, b->out[i], sizeof out) || sat != b->sat[i]) {
            snprintf(why, n, "lane %d, grad (%lld %lld %lld): (%lld %lld %lld) sat %llu, c5_shade (%lld %lld %lld) sat %llu",
                     i, (long long)b->grad[i][0], (long long)b->grad[i][1], (long long)b->grad[i][2],
                     (long long)b->out[i][0], (long long)b->out[i][1], (long long)b->out[i][2],
                     (unsigned long long)b->sat[i], (long long)out[0], (long long)out[1], (long long)out[2],
                     (unsigned long long)sat);
            return 0;
        }
    }
    return 1;
}

TEST(shade_wide_is_c5_shade_on_random_samples)
{
    static c5_frame_regs r;
    uint64_t st = 0x5eed5;
    long wide = 0, fallback = 0, saturated = 0, cases = 0;
    char why[400];
    for (int frame = 0; frame < 200; frame++) {
        random_regs(&st, &r);
        int64_t d[3];
        unit_dir(&st, d);
        for (int k = 0; k < 100; k++) {
            c5_shade_lanes b = {.n = (int)uniform_i(&st, 1, C5_SHADE_LANES)};
            for (int i = 0; i < b.n; i++) {
                random_grad(&st, b.grad[i]);
                for (int a = 0; a < 3; a++) {
                    b.vpos[a][i] = (int32_t)uniform_i(&st, -(1 << 22), 1 << 22);
                    b.rgb[a][i] = (int32_t)uniform_i(&st, 0, 32768);
                }
            }
            c5_shade_lanes w = b;
            if (c5_shade_wide_only(&r, d, &w) == 0) {
                wide++;
                CHECK_MSG(same_as_c5_shade(&r, d, &w, why, sizeof why), "frame %d case %d, wide: %s", frame, k, why);
                for (int i = 0; i < w.n; i++)
                    saturated += w.sat[i] > 0;
            } else {
                fallback++;
            }
            c5_shade_wide(&r, d, &b); /* the caller's function, whichever way it goes */
            CHECK_MSG(same_as_c5_shade(&r, d, &b, why, sizeof why), "frame %d case %d: %s", frame, k, why);
            cases++;
        }
    }
    if (c5_shade_wide_usable()) {
        /* most cases on the wide path; the far point lights on the lanes' own */
        CHECK_MSG(wide > cases / 2 && fallback > 0 && saturated > 0, "wide %ld, fallback %ld of %ld, saturated %ld",
                  wide, fallback, cases, saturated);
    } else {
        CHECK(wide == 0);
        printf("note: this host has no AVX2 and FMA: only c5_shade_wide's lane-by-lane path is checked\n");
    }
}

TEST(shade_wide_is_c5_shade_on_every_small_gradient)
{
    /* every gradient in [-6, 6]^3, eight at a time, under a point and a directional light:
     * small vectors are where a normalised component lies exactly on a half */
    static c5_frame_regs r;
    uint64_t st = 77;
    random_regs(&st, &r);
    r.n_lights = 2;
    r.lights[0].kind = C5_LIGHT_POINT;
    r.lights[1].kind = C5_LIGHT_DIRECTIONAL;
    for (int a = 0; a < 3; a++)
        r.lights[0].pos[a] = (a + 1) << 20;
    const int64_t views[3][3] = {{0, 0, -(1 << 14)}, {1 << 14, 0, 0}, {9459, -9459, 9459}};
    char why[400];
    long lanes = 0;
    for (int vi = 0; vi < 3; vi++) {
        c5_shade_lanes b = {0};
        for (int x = -6; x <= 6; x++)
            for (int y = -6; y <= 6; y++)
                for (int z = -6; z <= 6; z++) {
                    int i = b.n++;
                    int64_t g[3] = {x, y, z};
                    for (int a = 0; a < 3; a++) {
                        b.grad[i][a] = g[a];
                        b.vpos[a][i] = (x * 7 + y * 3 + z) * 4096;
                        b.rgb[a][i] = 20000 + 1000 * a;
                    }
                    if (b.n == C5_SHADE_LANES || (x == 6 && y == 6 && z == 6)) {
                        c5_shade_lanes w = b;
                        int ran = c5_shade_wide_only(&r, views[vi], &w);
                        CHECK(ran == 0 || !c5_shade_wide_usable());
                        if (ran == 0) {
                            CHECK_MSG(same_as_c5_shade(&r, views[vi], &w, why, sizeof why), "view %d: %s", vi, why);
                            lanes += w.n;
                        }
                        b.n = 0;
                    }
                }
    }
    CHECK(lanes == 3 * 13 * 13 * 13 || !c5_shade_wide_usable());
}

/* A vector of components below 2^25 whose x quotient v_x 2^28 / len lies within 1..3 units of
 * 1 / (2 len) of a half (below half a double's spacing there once len passes 2^39): len = floor(|v| 2^14) is chosen first so that 2^29 v_x - m = (2k + 1)
 * len for a small m, then y and z so that |v|^2 2^28 falls in [len^2, (len + 1)^2). 0 if the
 * search gives up. */
static int near_tie(uint64_t *st, int64_t v[3])
{
    for (int tries = 0; tries < 50; tries++) {
        int64_t k = uniform_i(st, 9600, 11400), x = uniform_i(st, (1 << 25) - (1 << 22), (1 << 25) - 300000), len = 0;
        for (int step = 0; step < 200000 && !len; step++, x++)
            for (int m = -3; m <= 3 && !len; m++)
                if (m && (((__int128)x << 29) - m) % (2 * k + 1) == 0)
                    len = (int64_t)((((__int128)x << 29) - m) / (2 * k + 1));
        if (!len)
            continue;
        x--;
        __int128 lo = ((__int128)len * len + ((__int128)1 << 28) - 1) >> 28,
                 hi = ((__int128)(len + 1) * (len + 1) + ((__int128)1 << 28) - 1) >> 28; /* |v|^2 in [lo, hi) */
        __int128 rest_lo = lo - (__int128)x * x, rest_hi = hi - (__int128)x * x;
        if (rest_lo <= 0)
            continue;
        int64_t y0 = (int64_t)sqrtl((long double)rest_lo / 2) + uniform_i(st, 0, 1 << 16);
        for (int64_t y = y0; y < y0 + 200000 && (__int128)y * y < rest_lo; y++) {
            __int128 need = rest_lo - (__int128)y * y;
            int64_t z = need > 0 ? (int64_t)sqrtl((long double)need) : 0;
            while ((__int128)z * z < need)
                z++;
            while (z > 0 && (__int128)(z - 1) * (z - 1) >= need)
                z--;
            if ((__int128)y * y + (__int128)z * z < rest_hi && y < (1 << 25) && z < (1 << 25)) {
                v[0] = x, v[1] = y, v[2] = z;
                return 1;
            }
        }
    }
    return 0;
}

TEST(shade_wide_normalize_is_c5_geom_normalize_near_its_ties)
{
    /* random vectors of every size the block normalises, and vectors built so that a quotient
     * lies within a double's rounding of a half (a light's direction only: len above 2^37),
     * where the double quotient rounds to the wrong side and the exact remainder corrects it */
    if (!c5_shade_wide_usable()) {
        printf("note: this host has no AVX2 and FMA: the wide normalisation is not run\n");
        return;
    }
    uint64_t st = 91;
    int64_t v[C5_SHADE_LANES][3], out[C5_SHADE_LANES][3];
    long corrected = 0, built = 0;
    for (int round = 0; round < 4000; round++) {
        for (int i = 0; i < C5_SHADE_LANES; i++) {
            int64_t m = (int64_t)1 << uniform_i(&st, 0, 24);
            for (int a = 0; a < 3; a++)
                v[i][a] = uniform_i(&st, -m, m);
        }
        if (round % 40 == 0) /* a lane built near a tie, its signs and axes shuffled */
            for (int i = 0; i < 2; i++) {
                int64_t t[3];
                if (!near_tie(&st, t))
                    continue;
                built++;
                int rot = (int)uniform_i(&st, 0, 2);
                for (int a = 0; a < 3; a++)
                    v[i][(a + rot) % 3] = c5_splitmix64(&st) & 1 ? -t[a] : t[a];
                int64_t len = (int64_t)c5_isqrt((unsigned __int128)((__int128)t[0] * t[0] + (__int128)t[1] * t[1] +
                                                                     (__int128)t[2] * t[2]) << 28);
                double e = (double)(t[0] * ((int64_t)1 << 28)) / (double)len;
                corrected += (int64_t)nearbyint(e) != c5_div_he((__int128)t[0] << 28, len);
            }
        CHECK(c5_shade_wide_normalize(v, out) == 0);
        for (int i = 0; i < C5_SHADE_LANES; i++) {
            int64_t want[3];
            c5_geom_normalize(v[i], want);
            CHECK_MSG(!memcmp(want, out[i], sizeof want), "round %d lane %d: (%lld %lld %lld) -> (%lld %lld %lld), "
                      "c5_geom_normalize (%lld %lld %lld)", round, i, (long long)v[i][0], (long long)v[i][1],
                      (long long)v[i][2], (long long)out[i][0], (long long)out[i][1], (long long)out[i][2],
                      (long long)want[0], (long long)want[1], (long long)want[2]);
        }
    }
    CHECK_MSG(built >= 100 && corrected > 0, "%ld built near a tie, %ld where the double quotient rounds wrong", built,
              corrected);
}

TEST(grad_wide_is_c5_grad_blend)
{
    /* the gradient block in lanes against c5_grad_blend: random differences and fractions, the
     * largest differences either way with the fractions at their ends, and all-zero lanes;
     * lanes of voxel rows among lanes of differences */
    static c5_frame_regs r;
    memset(&r, 0, sizeof r);
    uint64_t st = 5;
    long lanes_checked = 0, row_lanes = 0;
    for (int round = 0; round < 3000; round++) {
        for (int a = 0; a < 3; a++)
            r.gs[a] = round % 7 == 0 ? C5_ONE15 : uniform_i(&st, 1, C5_ONE15);
        c5_shade_lanes b = {.n = (int)uniform_i(&st, 1, C5_SHADE_LANES)};
        int kind = round % 4;
        for (int i = 0; i < b.n; i++)
            for (int a = 0; a < 3; a++) {
                b.frac[a][i] = kind == 1 ? (c5_splitmix64(&st) & 1 ? 0 : C5_ONE15 - 1)
                                         : (int32_t)uniform_i(&st, 0, C5_ONE15 - 1);
                for (int j = 0; j < 8; j++)
                    b.diff[a][j][i] = kind == 1   ? (c5_splitmix64(&st) & 1 ? 255 : -255)
                                      : kind == 2 ? 0
                                      : kind == 3 ? (int32_t)uniform_i(&st, -2, 2)
                                                  : (int32_t)uniform_i(&st, -255, 255);
            }
        /* in half the rounds some lanes give voxel rows instead (c5_gather_rows_at) */
        if (round % 2)
            for (int i = 0; i < b.n; i++)
                if (c5_splitmix64(&st) & 1) {
                    b.rows |= 1u << i;
                    for (int k = 0; k < C5_SHADE_ROWS; k++)
                        b.row[k][i] = kind == 1 ? (c5_splitmix64(&st) & 1 ? 0xff00ff00u : 0x00ff00ffu)
                                                : (uint32_t)c5_splitmix64(&st);
                }
        c5_grad_wide(&r, &b);
        for (int i = 0; i < b.n; i++) {
            int64_t frac[3], want[3];
            int32_t d[3][8];
            for (int a = 0; a < 3; a++) {
                frac[a] = b.frac[a][i];
                for (int j = 0; j < 8; j++)
                    d[a][j] = b.diff[a][j][i];
            }
            if (b.rows >> i & 1) {
                c5_rows_diffs(&b.row[0][i], C5_SHADE_LANES, d);
                row_lanes++;
            }
            c5_grad_blend(frac, d, r.gs, want);
            CHECK_MSG(!memcmp(want, b.grad[i], sizeof want), "round %d lane %d: (%lld %lld %lld), c5_grad_blend (%lld %lld %lld)",
                      round, i, (long long)b.grad[i][0], (long long)b.grad[i][1], (long long)b.grad[i][2],
                      (long long)want[0], (long long)want[1], (long long)want[2]);
            lanes_checked++;
        }
    }
    CHECK(lanes_checked > 3000 * 3 && row_lanes > 1000);
}

TEST(grad_shade_wide_is_the_blocks_in_turn)
{
    /* the gradient and shading in one pass (the processor's) against c5_grad_blend, then
     * c5_shade at the geom position c5_geom_from_voxel makes of the voxel position: random
     * differences (some lanes as voxel rows), positions anywhere below 2^28 and beyond it now
     * and then (the lanes' own path), scales up to the largest */
    static c5_frame_regs r;
    uint64_t st = 8;
    long lanes_checked = 0, wide = 0;
    char why[400];
    for (int round = 0; round < 3000; round++) {
        random_regs(&st, &r);
        /* geom positions mostly near the lights (a spacing near 1), now and then the largest
         * scale */
        for (int a = 0; a < 3; a++) {
            r.gs[a] = uniform_i(&st, 1, C5_ONE15);
            r.gscale[a] = round % 5 == 0 ? (1 << 24) - 1 : uniform_i(&st, 1 << 15, 1 << 17);
        }
        int64_t d[3];
        unit_dir(&st, d);
        c5_shade_lanes b = {.n = (int)uniform_i(&st, 1, C5_SHADE_LANES)};
        for (int i = 0; i < b.n; i++) {
            for (int a = 0; a < 3; a++) {
                b.frac[a][i] = (int32_t)uniform_i(&st, 0, C5_ONE15 - 1);
                for (int j = 0; j < 8; j++)
                    b.diff[a][j][i] = (int32_t)uniform_i(&st, -255, 255);
                int64_t m = round % 50 == 0 ? INT32_MAX : round % 5 == 1 ? (1 << 28) - 1 : 1 << 22;
                b.vpos[a][i] = (int32_t)uniform_i(&st, round % 3 ? 0 : -m, m);
                b.rgb[a][i] = (int32_t)uniform_i(&st, 0, 32768);
            }
            if (c5_splitmix64(&st) & 1) {
                b.rows |= 1u << i;
                for (int k = 0; k < C5_SHADE_ROWS; k++)
                    b.row[k][i] = (uint32_t)c5_splitmix64(&st);
            }
        }
        c5_shade_lanes w = b;
        c5_grad_wide(&r, &w);
        if (c5_shade_wide_only(&r, d, &w) == 0) { /* the geom positions made in the lanes */
            CHECK_MSG(same_as_c5_shade(&r, d, &w, why, sizeof why), "round %d, wide: %s", round, why);
            wide++;
        }
        c5_grad_shade_wide(&r, d, &b);
        memcpy(b.grad, w.grad, sizeof b.grad); /* grad: written only on the lane-by-lane path */
        CHECK_MSG(same_as_c5_shade(&r, d, &b, why, sizeof why), "round %d: %s", round, why);
        lanes_checked += b.n;
    }
    CHECK_MSG(lanes_checked > 3000 * 3 && (wide > 1000 || !c5_shade_wide_usable()), "lanes %ld, rounds on the wide path %ld",
              lanes_checked, wide);
}
