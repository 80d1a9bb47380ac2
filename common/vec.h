/* Double-precision 3-vectors: the arithmetic of the reference renderer and the scene. */
#ifndef C5_VEC_H
#define C5_VEC_H

#include <math.h>

typedef struct {
    double x, y, z;
} c5_vec3;

static inline c5_vec3 v3(double x, double y, double z) { return (c5_vec3){x, y, z}; }
static inline c5_vec3 v3_add(c5_vec3 a, c5_vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline c5_vec3 v3_sub(c5_vec3 a, c5_vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline c5_vec3 v3_mul(c5_vec3 a, c5_vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline c5_vec3 v3_scale(c5_vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline c5_vec3 v3_madd(c5_vec3 a, c5_vec3 b, double s) { return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s); }
static inline double v3_dot(c5_vec3 a, c5_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline c5_vec3 v3_cross(c5_vec3 a, c5_vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double v3_len(c5_vec3 a) { return sqrt(v3_dot(a, a)); }
/* Returns the zero vector for a zero input rather than NaN. */
static inline c5_vec3 v3_norm(c5_vec3 a)
{
    double l = v3_len(a);
    return l > 0 ? v3_scale(a, 1.0 / l) : v3(0, 0, 0);
}
static inline double v3_maxc(c5_vec3 a) { return fmax(a.x, fmax(a.y, a.z)); }
static inline double v3_comp(c5_vec3 a, int i) { return i == 0 ? a.x : i == 1 ? a.y : a.z; }

#endif
