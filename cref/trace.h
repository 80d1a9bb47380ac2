/* Internal to cref: the per-frame context and the tracing of one pixel's ray tree, in
 * cref's precision c5_real (cref/real.h). */
#ifndef C5_TRACE_H
#define C5_TRACE_H

#include "cref.h"
#include "real.h"
#include "tf.h"

typedef struct {
    c5_rvec3 o, d;  /* origin, unit direction; samples at o + k * step * d, k = 0, 1, ... */
    c5_rvec3 w;     /* weight: the fraction of this ray's radiance that reaches the pixel */
    c5_real tmax;   /* shadow rays: distance to the light (INFINITY for directional) */
    int type, gen;  /* c5_ray_type; generation = reflect/refract bounces so far */
} c5_ray;

/* The classification table in c5_real: the double build uses common/tf.h's table as it
 * is (the board model builds its own from the same c5_tf_build); the long double build
 * computes the step correction again in long double (render.c). */
#ifdef C5_CREF_LONG
typedef struct {
    c5_real rgba[256][4];
} c5_rtf_table;
#else
typedef c5_tf_table c5_rtf_table;
#endif

typedef struct {
    const c5_scene *s;
    const c5_supervol *sv;
    const c5_field *field;
    c5_rtf_table tf;
    c5_real step;
    c5_real eps;        /* hits closer than this to a ray's origin are ignored */
    c5_real fade_g2;    /* |gradient|^2 from which the lights' share is whole: (1/4 value
                           step a voxel of the smallest spacing)^2 */
    int has_volume;
    int shade;          /* Phong-shade volume samples: lights present and shading on */
    c5_rvec3 box_lo, box_hi;
} c5_trace_ctx;

typedef struct {
    c5_ray *rays;
    int n, cap;
} c5_ray_stack;

/* Traces the eye ray and every ray it spawns, depth first; adds radiance into rgb[3]. */
void C5R(trace_pixel)(const c5_trace_ctx *c, const c5_ray *eye, c5_real rgb[3], c5_cref_stats *st, c5_ray_stack *stk);

/* Trilinear reconstruction at world point p (spec sec. 3), in c5_real: in the double build
 * this is cref.h's c5_supervol_sample. */
void C5R(supervol_sample)(const c5_supervol *sv, c5_rvec3 p, c5_real *value, c5_rvec3 *grad);

/* A frame (render.c), also writing each pixel's sum before it is rounded to float into raw
 * (NULL: not). c5_cref_render_into is the double build's, c5l_cref_render_into the long's. */
int c5_cref_render_into(const c5_scene *s, const c5_supervol *sv, int frame, const c5_cref_opts *opts, c5_image *out,
                        double *raw, c5_cref_stats *stats, c5_err *err);
int c5l_cref_render_into(const c5_scene *s, const c5_supervol *sv, int frame, const c5_cref_opts *opts, c5_image *out,
                         double *raw, c5_cref_stats *stats, c5_err *err);

#endif
