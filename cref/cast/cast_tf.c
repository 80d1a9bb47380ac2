/* The caster's classification table (cast.h c5_cast_tf): the piecewise-linear transfer
 * function every 1/16 scalar, VTK's opacity correction and premultiplied colour, and the
 * running count of non-zero entries that decides an octree node's emptiness in O(1). */
#include <math.h>

#include "cast.h"
#include "tf.h"

int c5_cast_tf_build(const c5_tf_desc *tf, double step, double unit, c5_cast_tf *out, c5_err *err)
{
    if (!(step > 0) || !isfinite(step))
        return c5_fail(err, "cast: sample step must be finite and > 0 (got %g)", step);
    if (!(unit > 0) || !isfinite(unit))
        return c5_fail(err, "cast: opacity unit distance must be finite and > 0 (got %g)", unit);
    if (tf->n_opacity < 1 || tf->n_color < 1)
        return c5_fail(err, "cast: the transfer function needs opacity and colour points");
    double expo = step / unit;
    out->nonzero[0] = 0;
    for (int i = 0; i < C5_CAST_TF_N; i++) {
        double s = (double)i / C5_CAST_TF_SCALE;
        double a = c5_tf_eval(&tf->opacity[0][0], tf->n_opacity, 2, 1, s);
        /* a == 0 stays exactly 0: pow(1, x) is 1 */
        double ac = a >= 1 ? 1 : 1 - pow(1 - a, expo);
        double rgb[3];
        for (int c = 0; c < 3; c++)
            rgb[c] = c5_tf_eval(&tf->color[0][0], tf->n_color, 4, c + 1, s);
        if (!(ac >= 0 && ac <= 1) || !(rgb[0] >= 0 && rgb[0] <= 1) || !(rgb[1] >= 0 && rgb[1] <= 1) ||
            !(rgb[2] >= 0 && rgb[2] <= 1))
            return c5_fail(err, "cast: transfer function at scalar %g is outside [0,1]", s);
        for (int c = 0; c < 3; c++)
            out->rgba[i][c] = (float)(ac * rgb[c]);
        out->rgba[i][3] = (float)ac;
        out->nonzero[i + 1] = out->nonzero[i] + (out->rgba[i][3] != 0);
        out->lit[i] = out->rgba[i][3] != 0;
    }
    out->lit[C5_CAST_TF_N] = out->lit[C5_CAST_TF_N + 1] = out->lit[C5_CAST_TF_N + 2] = 0;
    out->ambient = (float)tf->ambient, out->diffuse = (float)tf->diffuse;
    out->specular = (float)tf->specular, out->specular_power = (float)tf->specular_power;
    return 0;
}
