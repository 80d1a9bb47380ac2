#include "geometry.h"

int c5_ray_box(c5_vec3 o, c5_vec3 d, c5_vec3 lo, c5_vec3 hi, double *t0, double *t1)
{
    double a = -INFINITY, b = INFINITY;
    for (int i = 0; i < 3; i++) {
        double oi = v3_comp(o, i), di = v3_comp(d, i), l = v3_comp(lo, i), h = v3_comp(hi, i);
        if (di == 0) {
            /* Parallel to this slab: inside it for every t, or never. */
            if (oi < l || oi > h)
                return 0;
            continue;
        }
        double ta = (l - oi) / di, tb = (h - oi) / di;
        if (ta > tb) {
            double t = ta;
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

static int ray_plane(c5_vec3 p, c5_vec3 n, c5_vec3 o, c5_vec3 d, double *t)
{
    double den = v3_dot(d, n);
    if (den == 0)
        return 0; /* exactly parallel: a grazing ray never hits */
    *t = v3_dot(v3_sub(p, o), n) / den;
    return 1;
}

int c5_ray_surface(const c5_surface *s, c5_vec3 o, c5_vec3 d, double tmin, double tmax, double *t)
{
    double th;
    switch (s->kind) {
    case C5_SURF_PLANE:
        if (!ray_plane(s->point, s->normal, o, d, &th))
            return 0;
        break;
    case C5_SURF_RECT: {
        if (!ray_plane(s->point, s->normal, o, d, &th))
            return 0;
        c5_vec3 q = v3_sub(v3_madd(o, d, th), s->point);
        double a = v3_dot(q, s->u) / v3_dot(s->u, s->u), b = v3_dot(q, s->v) / v3_dot(s->v, s->v);
        if (a < 0 || a > 1 || b < 0 || b > 1)
            return 0;
        break;
    }
    case C5_SURF_SPHERE: {
        c5_vec3 oc = v3_sub(o, s->point);
        double b = v3_dot(oc, d), c = v3_dot(oc, oc) - s->radius * s->radius;
        double disc = b * b - c;
        if (disc < 0)
            return 0;
        double sq = sqrt(disc);
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

c5_vec3 c5_surface_normal(const c5_surface *s, c5_vec3 p)
{
    if (s->kind == C5_SURF_SPHERE)
        return v3_scale(v3_sub(p, s->point), 1 / s->radius);
    return s->normal;
}

int c5_refract(c5_vec3 d, c5_vec3 n, double eta, c5_vec3 *out)
{
    double cos_i = -v3_dot(d, n);
    double k = 1 - eta * eta * (1 - cos_i * cos_i);
    if (k < 0)
        return 0;
    *out = v3_norm(v3_add(v3_scale(d, eta), v3_scale(n, eta * cos_i - sqrt(k))));
    return 1;
}
