/* The processor's geometry unit, in fixed point: hits on planes, rectangles and spheres,
 * normals, reflection, refraction (docs/rendering-spec.md sec. 6). Coordinates are geom_coord
 * SQ13.15 (world / min spacing, relative to the grid origin), ray parameters geom_t SQ13.15
 * (geom units along the direction), directions SQ1.14. Every operation is an exact integer
 * computation followed by one rounding, half to even. */
#ifndef C5_GEOM_H
#define C5_GEOM_H

#include <stdint.h>

#include "fxops.h"
#include "regs.h"

#define C5_T_INF INT64_MAX

/* Nearest hit of the ray O + t d with surface s for t in (tmin, tmax). 1 and *t, or 0. */
int c5_geom_hit(const c5_surface_regs *s, const int64_t O[3], const int64_t d[3], int64_t tmin, int64_t tmax,
                int64_t *t);
/* H = O + t d. */
void c5_geom_point(const int64_t O[3], const int64_t d[3], int64_t t, int64_t H[3]);
/* Outward unit normal of s at H, SQ1.14. */
void c5_geom_normal(const c5_surface_regs *s, const int64_t H[3], int64_t n[3]);
/* -2^k <= a[i] < 2^k for the three components (a ^ (a >> 63) is a, or -a - 1 for a < 0). */
static inline int c5_geom_small3(const int64_t a[3], int k)
{
    uint64_t m = (uint64_t)(a[0] ^ (a[0] >> 63)) | (uint64_t)(a[1] ^ (a[1] >> 63)) | (uint64_t)(a[2] ^ (a[2] >> 63));
    return m < ((uint64_t)1 << k);
}

/* c5_geom_normalize and c5_geom_dot14 on any input, in 128 bits. */
int64_t c5_geom_normalize_wide(const int64_t v[3], int64_t out[3]);
int64_t c5_geom_dot14_wide(const int64_t a[3], const int64_t b[3]);

/* v (any fixed-point scale) normalised to SQ1.14; returns |v| in v's own scale, 0 (and
 * out = 0) for the zero vector. |v| with 14 extra fraction bits, then v * 2^14 / |v|.
 * Inline for the shading (three a sample and light): components in [-2^30, 2^30) (every normal,
 * light and half vector the processor forms) take the same integers in 64 bits (|v|^2 <=
 * 3 * 2^60, v * 2^28 <= 2^58, the length < 2^45), the rest c5_geom_normalize_wide. The
 * root: a double guess, then the two loops that end on floor(sqrt) whatever the guess. */
static inline int64_t c5_geom_normalize(const int64_t v[3], int64_t out[3])
{
    if (!c5_geom_small3(v, 30))
        return c5_geom_normalize_wide(v, out);
    int64_t d2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    if (d2 == 0) {
        out[0] = out[1] = out[2] = 0;
        return 0;
    }
    unsigned __int128 x = (unsigned __int128)d2 << 28;
    double root = __builtin_sqrt((double)d2) * 16384.0;
    /* The quotients' guide from the guess, not from the exact root: the division then runs
     * beside the root's correction instead of after it (c5_div_he64_inv's result does not
     * depend on the guide; |v * 2^28 / len| <= 2^14). */
    double inv = 1.0 / root;
    uint64_t len = (uint64_t)root;
    while ((unsigned __int128)len * len > x)
        len--;
    while ((unsigned __int128)(len + 1) * (len + 1) <= x)
        len++; /* >= 2^14: d2 >= 1 */
    for (int a = 0; a < 3; a++)
        out[a] = c5_div_he64_inv(c5_shl(v[a], 28), (int64_t)len, inv);
    return (int64_t)(len >> 14);
}

/* c5_geom_dot14 of two directions, each a unit vector in SQ1.14 by its format (a normalised
 * vector, a ray's or a light's direction: components within 2^15): the exact sum fits 64
 * bits, so the shading's dot products take no range check. */
static inline int64_t c5_geom_dot14_dirs(const int64_t a[3], const int64_t b[3])
{
    return c5_rshift_he(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], 14);
}

/* Dot product of two SQ1.14 vectors, SQ1.14 (rounded). Components in [-2^30, 2^30): the exact
 * sum in 64 bits (<= 3 * 2^60), else c5_geom_dot14_wide. */
static inline int64_t c5_geom_dot14(const int64_t a[3], const int64_t b[3])
{
    if (!c5_geom_small3(a, 30) || !c5_geom_small3(b, 30))
        return c5_geom_dot14_wide(a, b);
    return c5_rshift_he(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], 14);
}
/* Mirror of d about unit n, renormalised. */
void c5_geom_reflect(const int64_t d[3], const int64_t n[3], int64_t out[3]);
/* Snell refraction of d through n facing the ray (d.n <= 0), eta = n_from / n_to as
 * UQ4.28; 0 on total internal reflection. */
int c5_geom_refract(const int64_t d[3], const int64_t n[3], int64_t eta, int64_t out[3]);
/* voxel coordinates (15 fraction bits, any sign) <-> geom coordinates (SQ13.15). */
void c5_geom_from_voxel(const c5_frame_regs *r, const int64_t p[3], int64_t g[3]);
void c5_geom_to_voxel(const c5_frame_regs *r, const int64_t g[3], int64_t p[3]);

#endif
