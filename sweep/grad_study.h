/* The gradient study (docs/accuracy.md, "Gradients"): a scene whose volume is one smooth
 * generator (blobs, cloud, marschner_lobb) filling the grid, rendered three ways and each
 * image measured against the same scene rendered from the unquantised field the generator
 * samples (its value and gradient in double, at a quarter of the step):
 *   central  cref as it is: the trilinear blend of central differences (docs/rendering-spec.md
 *            sec. 3);
 *   spline   cref with the cubic B-spline's derivative over the 4^3 voxels around the sample
 *            instead (a wider support, twice the voxels a shaded sample reads), under the
 *            same shading: the alternative the board's gradient unit was measured against;
 *   board    the board model.
 * Two figures per image: PSNR against the reference (docs/compare.md), and the fine-scale
 * error, the RMS of (image - reference) minus its own 5x5 mean: what stays of the error
 * after its slowly varying part, the shading's rings and terraces. */
#ifndef C5_GRAD_STUDY_H
#define C5_GRAD_STUDY_H

#include "err.h"
#include "image.h"
#include "scene.h"
#include "supervol.h"

enum { C5_GS_CENTRAL, C5_GS_SPLINE, C5_GS_BOARD, C5_GS_N };

typedef struct {
    double psnr_db[C5_GS_N], fine[C5_GS_N];
    c5_image img[C5_GS_N], ref; /* kept when the caller asks (keep_images), else empty */
} c5_grad_study;

/* 1 when the scene's volume is one smooth generator filling the grid (the study applies). */
int c5_grad_study_applies(const c5_scene *s, const c5_supervol *sv);

/* Runs the study at the scene's render settings (frame 0). 0, or -1 with err (a scene the
 * study does not apply to, a render that fails). keep_images: the five images stay in r
 * (free with c5_grad_study_free). */
int c5_grad_study_run(const c5_scene *s, const c5_supervol *sv, int keep_images, c5_grad_study *r, c5_err *err);
void c5_grad_study_free(c5_grad_study *r);

/* The fine-scale error of test against ref (same size): RMS over every channel of the
 * pixels at least 2 from the border of d - mean5x5(d), d = test - ref. */
double c5_fine_error(const c5_image *ref, const c5_image *test);

#endif
