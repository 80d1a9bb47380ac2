/* cref: the floating-point (double) reference renderer. It implements
 * docs/rendering-spec.md literally; the bit-accurate board model is judged against it.
 * c5_cref_render_long renders the same in long double, to check cref itself. */
#ifndef C5_CREF_H
#define C5_CREF_H

#include <stdint.h>

#include "image.h"
#include "scene.h"
#include "supervol.h"

typedef enum { C5_RAY_EYE, C5_RAY_SHADOW, C5_RAY_REFLECT, C5_RAY_REFRACT, C5_RAY_TYPES } c5_ray_type;

/* How every ray ended, or why a ray was never spawned. */
typedef enum {
    C5_END_OPACITY,      /* early termination: accumulated opacity reached max_opacity */
    C5_END_LEFT,         /* left the scene (background added) */
    C5_END_SURFACE,      /* ended on a surface, which may have spawned rays */
    C5_END_LIGHT,        /* shadow ray reached its light and delivered its radiance */
    C5_END_BLOCKED,      /* shadow ray stopped by an opaque surface or the volume */
    C5_CUT_BOUNCES,      /* reflect/refract ray not spawned: max_bounces reached */
    C5_CUT_WEIGHT,       /* ray not spawned: weight below min_weight */
    C5_END_KINDS
} c5_end_kind;

typedef struct {
    uint64_t rays[C5_RAY_TYPES];
    uint64_t samples;
    uint64_t ends[C5_END_KINDS];
    double wall_s;
} c5_cref_stats;

/* A scalar field in place of the super volume's trilinear reconstruction (tests use the
 * analytic Marschner-Lobb signal). value in 0..255 and its gradient per world unit. */
typedef struct c5_field {
    void (*sample)(const struct c5_field *f, c5_vec3 p, double *value, c5_vec3 *grad);
    const void *ctx;
} c5_field;

typedef struct {
    int threads;            /* <= 0: one per online CPU */
    const c5_field *field;  /* NULL: the super volume */
    /* Called as tiles of the image are taken (tiles taken so far, of how many), one call at a
     * time, for a progress line in long frames (an out-of-core grid); NULL: none. The image
     * never depends on it. */
    void (*progress)(void *ctx, int tiles_done, int tiles);
    void *progress_ctx;
} c5_cref_opts;

/* Renders frame `frame` of the scene into out (allocated here; free with c5_image_free). */
int c5_cref_render(const c5_scene *s, const c5_supervol *sv, int frame, const c5_cref_opts *opts, c5_image *out,
                   c5_cref_stats *stats, c5_err *err);

/* The same frame with cref computed in long double (x87 extended, 64-bit mantissa): cref's
 * sources compiled a second time with c5_real = long double (cref/real.h), same arguments,
 * same statistics, the image rounded to float at the end as always. What stays double:
 * the scene's and the volume's values as given, the transfer function's control points
 * interpolated at the 256 table entries (c5_tf_eval), and an analytic opts->field, called
 * at the sample point rounded to double. It measures cref's own rounding (docs/stability.md,
 * "Is cref itself stable?"); x87 arithmetic makes it several times slower. */
int c5_cref_render_long(const c5_scene *s, const c5_supervol *sv, int frame, const c5_cref_opts *opts, c5_image *out,
                        c5_cref_stats *stats, c5_err *err);

/* c5_cref_render (long_double 0) or c5_cref_render_long (1), and also each pixel's sum
 * before it is rounded to float: raw[3 * (y * w + x) + c], w * h * 3 doubles allocated by the
 * caller (the long double sums rounded to double). For measuring cref against itself below
 * the float's resolution (tests/test_cref_precision.c). */
int c5_cref_render_raw(const c5_scene *s, const c5_supervol *sv, int frame, const c5_cref_opts *opts, int long_double,
                       c5_image *out, double *raw, c5_cref_stats *stats, c5_err *err);

/* Threads a render uses for a request (<= 0: one per CPU it may run on, c5_cpus_usable),
 * within 1..256. */
int c5_cref_thread_count(int requested);

/* Sample step and opacity unit actually used (resolving the scene's defaults). */
double c5_render_step(const c5_scene *s, const c5_supervol *sv);
double c5_render_unit(const c5_scene *s, const c5_supervol *sv);

/* Trilinear reconstruction at world point p (spec sec. 3): value and gradient. */
void c5_supervol_sample(const c5_supervol *sv, c5_vec3 p, double *value, c5_vec3 *grad);

const char *c5_ray_type_name(c5_ray_type t);
const char *c5_end_kind_name(c5_end_kind k);

#endif
