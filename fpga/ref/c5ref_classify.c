/* The classify block of the C model (rtl_model/proc/sample_pipe.h) as the live reference of
 * tb/tb_classify_live.vhd (GHDL, VHPIDIRECT through tb/c5ref_pkg.vhd): each call runs the
 * model's own block function on one transaction, as vectors/gen/vec_classify.c does for the
 * golden vectors. Integers cross as VHDL `integer`; signals in their raw fixed-point
 * integers. */
#include <stdint.h>

#include "c5ref.h"
#include "sample_pipe.h"
#include "taps.h"

int32_t c5ref_cl_table(int32_t i, int32_t ch, int32_t v);
int32_t c5ref_cl_run(int32_t value, int32_t ch);

static c5ref_fault fault = C5REF_FAULT_INIT; /* the model's answer off by one in one call (c5ref.h) */

/* classify: the transfer-function table written entry by entry (i 0..255, ch r g b a,
 * UQ1.15), then channel ch of a sample value's lookup (the lookup runs for ch 0). */
static c5_frame_regs cl_regs;
static int64_t cl_out[4];

int32_t c5ref_cl_table(int32_t i, int32_t ch, int32_t v)
{
    if (i < 0 || i > 255 || ch < 0 || ch > 3)
        return -1;
    cl_regs.tf[i][ch] = v;
    return 0;
}

int32_t c5ref_cl_run(int32_t value, int32_t ch)
{
    if (ch == 0) {
        c5_classify(&cl_regs, value, cl_out);
        cl_out[0] ^= c5ref_faulty(&fault);
    }
    return ch >= 0 && ch < 4 ? (int32_t)cl_out[ch] : 0;
}
