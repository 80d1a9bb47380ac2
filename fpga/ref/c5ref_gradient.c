/* The gradient block of the C model (rtl_model/proc/sample_pipe.h) as the live reference of
 * tb/tb_gradient_live.vhd (GHDL, VHPIDIRECT through tb/c5ref_pkg.vhd): each call runs the
 * model's own block function on one transaction, as vectors/gen/vec_gradient.c does for the
 * golden vectors. Integers cross as VHDL `integer`; signals in their raw fixed-point
 * integers. */
#include <stdint.h>

#include "c5ref.h"
#include "sample_pipe.h"
#include "taps.h"

int32_t c5ref_gr_set(int32_t k, int32_t v);
int32_t c5ref_gr_run(int32_t axis);

static c5ref_fault fault = C5REF_FAULT_INIT; /* the model's answer off by one in one call (c5ref.h) */

/* gradient: inputs set one by one (k: 0..2 frac, 3..26 the differences d[axis][corner] as
 * 3 + 8 axis + corner, 27..29 gs), then each axis's gradient (SQ8.8) read by
 * c5ref_gr_run(axis), which runs the blend when axis is 0. */
static int64_t gr_frac[3], gr_gs[3], gr_out[3];
static int32_t gr_d[3][8];

int32_t c5ref_gr_set(int32_t k, int32_t v)
{
    if (k >= 0 && k < 3)
        gr_frac[k] = v;
    else if (k >= 3 && k < 27)
        gr_d[(k - 3) / 8][(k - 3) % 8] = v;
    else if (k >= 27 && k < 30)
        gr_gs[k - 27] = v;
    else
        return -1;
    return 0;
}

int32_t c5ref_gr_run(int32_t axis)
{
    if (axis == 0) {
        c5_grad_blend(gr_frac, gr_d, gr_gs, gr_out);
        gr_out[0] ^= c5ref_faulty(&fault);
    }
    return axis >= 0 && axis < 3 ? (int32_t)gr_out[axis] : 0;
}
