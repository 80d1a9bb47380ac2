/* Classification: the scene's piecewise-linear transfer function sampled into a 256-entry
 * RGBA table, with opacity corrected for the sample step (docs/rendering-spec.md, sec. 4). */
#ifndef C5_TF_H
#define C5_TF_H

#include "scene.h"

typedef struct {
    double rgba[256][4]; /* colour not premultiplied; alpha already corrected for the step */
} c5_tf_table;

/* Piecewise-linear value at x of control points pts[i] = (x_i, v_i...), component c (1-based
 * among the values); clamped to the first/last point outside their range. */
double c5_tf_eval(const double *pts, int n, int stride, int c, double x);

/* Table entry s holds the TF at scalar s; alpha' = 1 - (1 - alpha)^(step / unit). */
void c5_tf_build(const c5_tf_desc *tf, double step, double unit, c5_tf_table *out);

/* RGBA at a continuous scalar s in [0, 255]: linear between entries floor(s) and floor(s)+1. */
static inline void c5_tf_lookup(const c5_tf_table *t, double s, double rgba[4])
{
    s = s < 0 ? 0 : s > 255 ? 255 : s;
    int i = (int)s;
    if (i > 254)
        i = 254;
    double f = s - i;
    for (int c = 0; c < 4; c++)
        rgba[c] = t->rgba[i][c] + f * (t->rgba[i + 1][c] - t->rgba[i][c]);
}

#endif
