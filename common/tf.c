#include "tf.h"

#include <math.h>

double c5_tf_eval(const double *pts, int n, int stride, int c, double x)
{
    if (n <= 0)
        return 0;
    if (x <= pts[0])
        return pts[c];
    for (int i = 1; i < n; i++) {
        const double *a = pts + (i - 1) * stride, *b = pts + i * stride;
        if (x <= b[0])
            return a[c] + (x - a[0]) / (b[0] - a[0]) * (b[c] - a[c]);
    }
    return pts[(n - 1) * stride + c];
}

void c5_tf_build(const c5_tf_desc *tf, double step, double unit, c5_tf_table *out)
{
    double ratio = step / unit;
    for (int s = 0; s < 256; s++) {
        for (int c = 0; c < 3; c++)
            out->rgba[s][c] = c5_tf_eval(&tf->color[0][0], tf->n_color, 4, c + 1, s);
        double a = c5_tf_eval(&tf->opacity[0][0], tf->n_opacity, 2, 1, s);
        /* a == 1 stays exactly 1 and a == 0 exactly 0, whatever the ratio. */
        out->rgba[s][3] = a >= 1 ? 1 : a <= 0 ? 0 : 1 - pow(1 - a, ratio);
    }
}
