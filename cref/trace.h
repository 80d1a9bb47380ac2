/* Internal to cref: the per-frame context and the tracing of one pixel's ray tree. */
#ifndef C5_TRACE_H
#define C5_TRACE_H

#include "cref.h"
#include "tf.h"

typedef struct {
    c5_vec3 o, d;   /* origin, unit direction; samples at o + k * step * d, k = 0, 1, ... */
    c5_vec3 w;      /* weight: the fraction of this ray's radiance that reaches the pixel */
    double tmax;    /* shadow rays: distance to the light (INFINITY for directional) */
    int type, gen;  /* c5_ray_type; generation = reflect/refract bounces so far */
} c5_ray;

typedef struct {
    const c5_scene *s;
    const c5_supervol *sv;
    const c5_field *field;
    c5_tf_table tf;
    double step;
    double eps;         /* hits closer than this to a ray's origin are ignored */
    double grad_eps;    /* |gradient| below this counts as zero (ambient only) */
    int has_volume;
    int shade;          /* Phong-shade volume samples: lights present and shading on */
    c5_vec3 box_lo, box_hi;
} c5_trace_ctx;

typedef struct {
    c5_ray *rays;
    int n, cap;
} c5_ray_stack;

/* Traces the eye ray and every ray it spawns, depth first; adds radiance into rgb[3]. */
void c5_trace_pixel(const c5_trace_ctx *c, const c5_ray *eye, double rgb[3], c5_cref_stats *st, c5_ray_stack *stk);

#endif
