/* The processor's geometry unit, in fixed point: hits on planes, rectangles and spheres,
 * normals, reflection, refraction (docs/rendering-spec.md sec. 6). Coordinates are geom_coord
 * SQ13.15 (world / min spacing, relative to the grid origin), ray parameters geom_t SQ13.15
 * (geom units along the direction), directions SQ1.14. Every operation is an exact integer
 * computation followed by one rounding, half to even. */
#ifndef C5_GEOM_H
#define C5_GEOM_H

#include <stdint.h>

#include "regs.h"

#define C5_T_INF INT64_MAX

/* Nearest hit of the ray O + t d with surface s for t in (tmin, tmax). 1 and *t, or 0. */
int c5_geom_hit(const c5_surface_regs *s, const int64_t O[3], const int64_t d[3], int64_t tmin, int64_t tmax,
                int64_t *t);
/* H = O + t d. */
void c5_geom_point(const int64_t O[3], const int64_t d[3], int64_t t, int64_t H[3]);
/* Outward unit normal of s at H, SQ1.14. */
void c5_geom_normal(const c5_surface_regs *s, const int64_t H[3], int64_t n[3]);
/* v (any fixed-point scale) normalised to SQ1.14; returns |v| in v's own scale, 0 (and
 * out = 0) for the zero vector. */
int64_t c5_geom_normalize(const int64_t v[3], int64_t out[3]);
/* Dot product of two SQ1.14 vectors, SQ1.14 (rounded). */
int64_t c5_geom_dot14(const int64_t a[3], const int64_t b[3]);
/* Mirror of d about unit n, renormalised. */
void c5_geom_reflect(const int64_t d[3], const int64_t n[3], int64_t out[3]);
/* Snell refraction of d through n facing the ray (d.n <= 0), eta = n_from / n_to as
 * UQ4.28; 0 on total internal reflection. */
int c5_geom_refract(const int64_t d[3], const int64_t n[3], int64_t eta, int64_t out[3]);
/* voxel coordinates (15 fraction bits, any sign) <-> geom coordinates (SQ13.15). */
void c5_geom_from_voxel(const c5_frame_regs *r, const int64_t p[3], int64_t g[3]);
void c5_geom_to_voxel(const c5_frame_regs *r, const int64_t g[3], int64_t p[3]);

#endif
