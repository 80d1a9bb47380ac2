/* Procedural volumes: stand-ins for the papers' data sets and analytic test signals.
 * Each fills an 8-bit volume of the requested dims from normalised voxel-centre
 * coordinates p in (-1, 1)^3: p_a = 2 (i_a + 0.5) / dims_a - 1. */
#ifndef C5_GENERATORS_H
#define C5_GENERATORS_H

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

const char *c5_generator_name(c5_generator g);

#endif
