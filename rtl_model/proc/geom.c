/* Fixed-point geometry (geom.h). Widths: coordinates 15 fraction bits, directions 14;
 * products are formed exactly in 128 bits and rounded once. */
#include "geom.h"

#include "fxops.h"

static __int128 dot(const int64_t a[3], const int64_t b[3])
{
    return (__int128)a[0] * b[0] + (__int128)a[1] * b[1] + (__int128)a[2] * b[2];
}

/* Parameter t (15 fraction bits) of the hit with the plane through p with normal n, where it
 * may exceed tmin: 0 for a parallel line and, without the division, where num / den <= 0 and
 * tmin >= 0 (the rounded t is then at most 0). */
static int plane_t(const int64_t p[3], const int64_t n[3], const int64_t O[3], const int64_t d[3], int64_t tmin,
                   int64_t *t)
{
    __int128 den = dot(d, n); /* 28 fraction bits */
    if (den == 0)
        return 0;             /* exactly parallel: never hits */
    int64_t po[3] = {p[0] - O[0], p[1] - O[1], p[2] - O[2]};
    __int128 num = dot(po, n); /* 29 fraction bits */
    if (tmin >= 0 && (num == 0 || (num < 0) != (den < 0)))
        return 0;
    *t = c5_div_he(c5_shl128(num, 14), den);
    return 1;
}

int c5_geom_hit(const c5_surface_regs *s, const int64_t O[3], const int64_t d[3], int64_t tmin, int64_t tmax,
                int64_t *t)
{
    if (s->kind != C5_SURF_SPHERE) {
        int64_t th;
        if (!plane_t(s->p, s->n, O, d, tmin, &th) || th <= tmin || th >= tmax)
            return 0;
        if (s->kind == C5_SURF_RECT) {
            int64_t H[3], rel[3];
            c5_geom_point(O, d, th, H);
            for (int a = 0; a < 3; a++)
                rel[a] = H[a] - s->p[a];
            __int128 pu = dot(rel, s->eu), uu = dot(s->eu, s->eu);
            __int128 pv = dot(rel, s->ev), vv = dot(s->ev, s->ev);
            if (pu < 0 || pu > uu || pv < 0 || pv > vv)
                return 0;
        }
        *t = th;
        return 1;
    }
    /* |O + t d - c|^2 = r^2 with a = d.d (not exactly 1 after rounding):
     * t = (-b -+ sqrt(b^2 - a (oc.oc - r^2))) / a, b = oc.d. */
    int64_t oc[3] = {O[0] - s->p[0], O[1] - s->p[1], O[2] - s->p[2]};
    __int128 a = dot(d, d);                            /* 28 fraction bits */
    __int128 b = dot(oc, d);                           /* 29 */
    __int128 cc = dot(oc, oc) - (__int128)s->r * s->r; /* 30 */
    __int128 disc = b * b - a * cc;                    /* 58, exact */
    if (disc < 0)
        return 0;
    __int128 sq = (__int128)c5_isqrt((unsigned __int128)disc); /* 29 */
    /* (29 - 28) fraction bits after the division: shift 14 more for t's 15. */
    int64_t t1 = c5_div_he(c5_shl128(-b - sq, 14), a), t2 = c5_div_he(c5_shl128(-b + sq, 14), a);
    if (t1 > tmin && t1 < tmax) {
        *t = t1;
        return 1;
    }
    if (t2 > tmin && t2 < tmax) {
        *t = t2;
        return 1;
    }
    return 0;
}

void c5_geom_point(const int64_t O[3], const int64_t d[3], int64_t t, int64_t H[3])
{
    for (int a = 0; a < 3; a++)
        H[a] = O[a] + c5_rshift128_he((__int128)t * d[a], 14);
}

int64_t c5_geom_normalize_wide(const int64_t v[3], int64_t out[3])
{
    /* |v| with 14 extra fraction bits, then v * 2^14 / |v|. */
    uint64_t len = c5_isqrt((unsigned __int128)dot(v, v) << 28); /* frac + 14 */
    if (len == 0) {
        out[0] = out[1] = out[2] = 0;
        return 0;
    }
    for (int a = 0; a < 3; a++)
        out[a] = c5_div_he(c5_shl128(v[a], 28), (__int128)len);
    return (int64_t)(len >> 14);
}

void c5_geom_normal(const c5_surface_regs *s, const int64_t H[3], int64_t n[3])
{
    if (s->kind != C5_SURF_SPHERE) {
        n[0] = s->n[0];
        n[1] = s->n[1];
        n[2] = s->n[2];
        return;
    }
    int64_t v[3] = {H[0] - s->p[0], H[1] - s->p[1], H[2] - s->p[2]};
    c5_geom_normalize(v, n);
}

int64_t c5_geom_dot14_wide(const int64_t a[3], const int64_t b[3]) { return c5_rshift128_he(dot(a, b), 14); }

void c5_geom_reflect(const int64_t d[3], const int64_t n[3], int64_t out[3])
{
    __int128 dn = dot(d, n); /* 28 */
    int64_t r[3];
    for (int a = 0; a < 3; a++)
        r[a] = d[a] - c5_rshift128_he(2 * dn * n[a], 28);
    c5_geom_normalize(r, out);
}

int c5_geom_refract(const int64_t d[3], const int64_t n[3], int64_t eta, int64_t out[3])
{
    /* Everything in 28 fraction bits: c = -d.n, k = 1 - eta^2 (1 - c^2). */
    const __int128 one = (__int128)1 << 28;
    __int128 c = -dot(d, n);
    __int128 c2 = (c * c) >> 28;
    __int128 e2 = ((__int128)eta * eta) >> 28;
    __int128 k = one - ((e2 * (one - c2)) >> 28);
    if (k < 0)
        return 0;
    __int128 sk = (__int128)c5_isqrt((unsigned __int128)k << 28);
    __int128 coef = ((eta * c) >> 28) - sk; /* eta cos - sqrt(k) */
    int64_t t[3];
    for (int a = 0; a < 3; a++)
        t[a] = c5_rshift128_he((__int128)eta * d[a] + coef * n[a], 28);
    c5_geom_normalize(t, out);
    return 1;
}

void c5_geom_from_voxel(const c5_frame_regs *r, const int64_t p[3], int64_t g[3])
{
    /* gscale < 2^24 (UQ8.16): below 2^38 the product fits 64 bits, the same rounding. */
    if (c5_geom_small3(p, 38)) {
        for (int a = 0; a < 3; a++)
            g[a] = c5_rshift_he(p[a] * r->gscale[a], 16);
        return;
    }
    for (int a = 0; a < 3; a++)
        g[a] = c5_rshift128_he((__int128)p[a] * r->gscale[a], 16);
}

void c5_geom_to_voxel(const c5_frame_regs *r, const int64_t g[3], int64_t p[3])
{
    for (int a = 0; a < 3; a++)
        p[a] = c5_rshift128_he((__int128)g[a] * r->vscale[a], 20);
}
