/* Ray-surface geometry in double precision (docs/rendering-spec.md, sec. 6). */
#ifndef C5_GEOMETRY_H
#define C5_GEOMETRY_H

#include "scene.h"

/* Ray/box: the parameter interval [t0, t1] where o + t d lies in [lo, hi] (t may be
 * negative). Returns 0 when the line misses the box. Axis-parallel rays are exact. */
int c5_ray_box(c5_vec3 o, c5_vec3 d, c5_vec3 lo, c5_vec3 hi, double *t0, double *t1);

/* Nearest hit of the ray with the surface at t in (tmin, tmax); 0 when none. */
int c5_ray_surface(const c5_surface *s, c5_vec3 o, c5_vec3 d, double tmin, double tmax, double *t);

/* Outward normal of the surface at point p (planes, rects: their stored normal). */
c5_vec3 c5_surface_normal(const c5_surface *s, c5_vec3 p);

/* Mirror direction of d about unit normal n. */
static inline c5_vec3 c5_reflect(c5_vec3 d, c5_vec3 n) { return v3_madd(d, n, -2 * v3_dot(d, n)); }

/* Snell refraction of unit d through unit n facing the incoming ray (d.n <= 0), with
 * eta = n_from / n_to. Returns 0 on total internal reflection. */
int c5_refract(c5_vec3 d, c5_vec3 n, double eta, c5_vec3 *out);

#endif
