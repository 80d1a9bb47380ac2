/* cref's arithmetic type. cref's sources (render.c, trace.c, sample.c, geometry.c) are
 * compiled twice from one text (Makefile):
 *   as they are: c5_real is double and c5_rvec3 is c5_vec3, the reference renderer
 *     c5_cref_render, with the same symbols and bits as before this header existed;
 *   with -DC5_CREF_LONG: c5_real is long double (x87 extended, 64-bit mantissa), every
 *     external symbol of cref c5l_ instead of c5_ (C5R) and the entry point
 *     c5_cref_render_long: the same renderer one precision up, to measure cref's own
 *     rounding (docs/stability.md, "Is cref itself stable?").
 * The sources include <tgmath.h> after every other header, so sqrt, floor, pow, ... take
 * the precision of their arguments. */
#ifndef C5_CREF_REAL_H
#define C5_CREF_REAL_H

#include <math.h>

#include "vec.h"

#ifdef C5_CREF_LONG
typedef long double c5_real;
typedef struct {
    long double x, y, z;
} c5_rvec3;
#define C5R(name) c5l_##name
#define C5_CREF_RENDER c5_cref_render_long
#define C5_REAL_SQRT sqrtl
#define C5_REAL_FMAX fmaxl
#define C5_REAL_PI 3.141592653589793238462643383279502884L
static inline c5_rvec3 rv3_of(c5_vec3 a) { return (c5_rvec3){a.x, a.y, a.z}; }
static inline c5_vec3 rv3_to_double(c5_rvec3 a) { return v3((double)a.x, (double)a.y, (double)a.z); }
#else
typedef double c5_real;
typedef c5_vec3 c5_rvec3;
#define C5R(name) c5_##name
#define C5_CREF_RENDER c5_cref_render
#define C5_REAL_SQRT sqrt
#define C5_REAL_FMAX fmax
#define C5_REAL_PI M_PI
static inline c5_rvec3 rv3_of(c5_vec3 a) { return a; }
static inline c5_vec3 rv3_to_double(c5_rvec3 a) { return a; }
#endif

/* common/vec.h's operations in c5_real: in the double build the same expressions, so the
 * same bits. */
static inline c5_rvec3 rv3(c5_real x, c5_real y, c5_real z) { return (c5_rvec3){x, y, z}; }
static inline c5_rvec3 rv3_add(c5_rvec3 a, c5_rvec3 b) { return rv3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline c5_rvec3 rv3_sub(c5_rvec3 a, c5_rvec3 b) { return rv3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline c5_rvec3 rv3_mul(c5_rvec3 a, c5_rvec3 b) { return rv3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline c5_rvec3 rv3_scale(c5_rvec3 a, c5_real s) { return rv3(a.x * s, a.y * s, a.z * s); }
static inline c5_rvec3 rv3_madd(c5_rvec3 a, c5_rvec3 b, c5_real s)
{
    return rv3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s);
}
static inline c5_real rv3_dot(c5_rvec3 a, c5_rvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline c5_rvec3 rv3_cross(c5_rvec3 a, c5_rvec3 b)
{
    return rv3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline c5_real rv3_len(c5_rvec3 a) { return C5_REAL_SQRT(rv3_dot(a, a)); }
/* Returns the zero vector for a zero input rather than NaN. */
static inline c5_rvec3 rv3_norm(c5_rvec3 a)
{
    c5_real l = rv3_len(a);
    return l > 0 ? rv3_scale(a, 1 / l) : rv3(0, 0, 0);
}
static inline c5_real rv3_maxc(c5_rvec3 a) { return C5_REAL_FMAX(a.x, C5_REAL_FMAX(a.y, a.z)); }
static inline c5_real rv3_comp(c5_rvec3 a, int i) { return i == 0 ? a.x : i == 1 ? a.y : a.z; }

#endif
