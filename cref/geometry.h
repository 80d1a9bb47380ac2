/* Ray-surface geometry in cref's precision, c5_real (docs/rendering-spec.md, sec. 6;
 * cref/real.h: double, or long double in the C5_CREF_LONG build). */
#ifndef C5_GEOMETRY_H
#define C5_GEOMETRY_H

#include "real.h"
#include "scene.h"

/* Ray/box: the parameter interval [t0, t1] where o + t d lies in [lo, hi] (t may be
 * negative). Returns 0 when the line misses the box. Axis-parallel rays are exact. */
int C5R(ray_box)(c5_rvec3 o, c5_rvec3 d, c5_rvec3 lo, c5_rvec3 hi, c5_real *t0, c5_real *t1);

/* Nearest hit of the ray with the surface at t in (tmin, tmax); 0 when none. */
int C5R(ray_surface)(const c5_surface *s, c5_rvec3 o, c5_rvec3 d, c5_real tmin, c5_real tmax, c5_real *t);

/* Outward normal of the surface at point p (planes, rects: their stored normal). */
c5_rvec3 C5R(surface_normal)(const c5_surface *s, c5_rvec3 p);

/* Mirror direction of d about unit normal n. */
static inline c5_rvec3 c5_reflect(c5_rvec3 d, c5_rvec3 n) { return rv3_madd(d, n, -2 * rv3_dot(d, n)); }

/* Snell refraction of unit d through unit n facing the incoming ray (d.n <= 0), with
 * eta = n_from / n_to. Returns 0 on total internal reflection. */
int C5R(refract)(c5_rvec3 d, c5_rvec3 n, c5_real eta, c5_rvec3 *out);

#endif
