/* Procedural volumes: stand-ins for the papers' data sets and analytic test signals.
 * Each fills an 8-bit volume of the requested dims from normalised voxel-centre
 * coordinates p in (-1, 1)^3: p_a = 2 (i_a + 0.5) / dims_a - 1. */
#ifndef C5_GENERATORS_H
#define C5_GENERATORS_H

#include <stddef.h>
#include <stdint.h>

#include "scene.h"

/* The Marschner-Lobb signal rho in [0, 1] at p in [-1, 1]^3 (Marschner and Lobb 1994):
 * rho = (1 - sin(pi z / 2) + alpha (1 + cos(2 pi f_m cos(pi r / 2)))) / (2 (1 + alpha)),
 * r = sqrt(x^2 + y^2). Voxels hold round(255 rho). */
double c5_marschner_lobb(double x, double y, double z, double f_m, double alpha);
/* Its gradient with respect to p. */
void c5_marschner_lobb_grad(double x, double y, double z, double f_m, double alpha, double g[3]);

/* Fills out (d->gen_dims voxels, x fastest) from the generator description. */
void c5_generate(const c5_volume_desc *d, uint8_t *out);

/* What a generator computes once from its parameters (the blobs of C5_GEN_BLOBS). */
#define C5_GEN_MAX_BLOBS 256
typedef struct {
    double c[3], inv_s2, amp;
} c5_gen_blob;
typedef struct {
    int n_blobs;
    c5_gen_blob blobs[C5_GEN_MAX_BLOBS];
} c5_gen_state;
void c5_gen_prepare(const c5_volume_desc *d, c5_gen_state *g);
/* The field a smooth generator (marschner_lobb, blobs, cloud) quantises, at any p in
 * [-1, 1]^3, unquantised (voxels hold round(255 u) clamped to 0..255); NAN for the others.
 * The analytic reference of the shading study (docs/accuracy.md, "Gradients"). */
double c5_gen_unit(const c5_volume_desc *d, const c5_gen_state *g, const double p[3]);
/* Voxels [lo, hi) of the generated volume (hi <= gen_dims), each by its own definition, so
 * any box holds the same bits as the whole volume there: voxel (x, y, z) of the box at
 * out[(z - lo[2]) sz + (y - lo[1]) sy + x - lo[0]]. Thread-safe (g is only read). */
void c5_generate_box(const c5_volume_desc *d, const c5_gen_state *g, const size_t lo[3], const size_t hi[3],
                     uint8_t *out, size_t sy, size_t sz);

const char *c5_generator_name(c5_generator g);
/* When this code was compiled: part of a generated volume's identity (voxsrc.h), so that what
 * a cache keeps of one build's voxels is not taken for another's. */
const char *c5_generators_build(void);

#endif
