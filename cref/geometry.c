/* Ray-surface geometry (geometry.h), in c5_real. */
#include "geometry.h"

#include <tgmath.h>

int C5R(ray_box)(c5_rvec3 o, c5_rvec3 d, c5_rvec3 lo, c5_rvec3 hi, c5_real *t0, c5_real *t1)
{
    c5_real a = -INFINITY, b = INFINITY;
    for (int i = 0; i < 3; i++) {
        c5_real oi = rv3_comp(o, i), di = rv3_comp(d, i), l = rv3_comp(lo, i), h = rv3_comp(hi, i);
        if (di == 0) {
            /* Parallel to this slab: inside it for every t, or never. */
            if (oi < l || oi > h)
                return 0;
            continue;
        }
        c5_real ta = (l - oi) / di, tb = (h - oi) / di;
        if (ta > tb) {
            c5_real t = ta;
            ta = tb;
            tb = t;
        }
        a = ta > a ? ta : a;
        b = tb < b ? tb : b;
    }
    if (a > b)
        return 0;
    *t0 = a;
    *t1 = b;
    return 1;
}

static int ray_plane(c5_rvec3 p, c5_rvec3 n, c5_rvec3 o, c5_rvec3 d, c5_real *t)
{
    c5_real den = rv3_dot(d, n);
    if (den == 0)
        return 0; /* exactly parallel: a grazing ray never hits */
    *t = rv3_dot(rv3_sub(p, o), n) / den;
    return 1;
}

int C5R(ray_surface)(const c5_surface *s, c5_rvec3 o, c5_rvec3 d, c5_real tmin, c5_real tmax, c5_real *t)
{
    c5_real th;
    switch (s->kind) {
    case C5_SURF_PLANE:
        if (!ray_plane(rv3_of(s->point), rv3_of(s->normal), o, d, &th))
            return 0;
        break;
    case C5_SURF_RECT: {
        if (!ray_plane(rv3_of(s->point), rv3_of(s->normal), o, d, &th))
            return 0;
        c5_rvec3 q = rv3_sub(rv3_madd(o, d, th), rv3_of(s->point));
        c5_rvec3 u = rv3_of(s->u), v = rv3_of(s->v);
        c5_real a = rv3_dot(q, u) / rv3_dot(u, u), b = rv3_dot(q, v) / rv3_dot(v, v);
        if (a < 0 || a > 1 || b < 0 || b > 1)
            return 0;
        break;
    }
    case C5_SURF_SPHERE: {
        c5_rvec3 oc = rv3_sub(o, rv3_of(s->point));
        c5_real r = s->radius;
        c5_real b = rv3_dot(oc, d), c = rv3_dot(oc, oc) - r * r;
        c5_real disc = b * b - c;
        if (disc < 0)
            return 0;
        c5_real sq = sqrt(disc);
        th = -b - sq;
        if (th <= tmin)
            th = -b + sq;
        break;
    }
    default:
        return 0;
    }
    if (!(th > tmin && th < tmax))
        return 0;
    *t = th;
    return 1;
}

c5_rvec3 C5R(surface_normal)(const c5_surface *s, c5_rvec3 p)
{
    if (s->kind == C5_SURF_SPHERE)
        return rv3_scale(rv3_sub(p, rv3_of(s->point)), 1 / (c5_real)s->radius);
    return rv3_of(s->normal);
}

int C5R(refract)(c5_rvec3 d, c5_rvec3 n, c5_real eta, c5_rvec3 *out)
{
    c5_real cos_i = -rv3_dot(d, n);
    c5_real k = 1 - eta * eta * (1 - cos_i * cos_i);
    /* A k that is not >= 0 (negative, or NaN when eta^2 overflows and meets a zero sine)
     * is total internal reflection, and so is a direction that does not normalise to a
     * finite unit vector: no NaN ray leaves a surface, whatever eta is. */
    if (!(k >= 0))
        return 0;
    c5_rvec3 t = rv3_add(rv3_scale(d, eta), rv3_scale(n, eta * cos_i - sqrt(k)));
    c5_real len = rv3_len(t);
    if (!(len > 0 && isfinite(len)))
        return 0;
    *out = rv3_scale(t, 1 / len);
    return 1;
}
