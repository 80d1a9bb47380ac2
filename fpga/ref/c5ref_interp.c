/* The interp block of the C model (rtl_model/proc/sample_pipe.h) as the live reference of
 * tb/tb_interp_live.vhd (GHDL, VHPIDIRECT through tb/c5ref_pkg.vhd): each call runs the
 * model's own block function on one transaction, as vectors/gen/vec_interp.c does for the
 * golden vectors. Integers cross as VHDL `integer`; signals in their raw fixed-point
 * integers. */
#include <stdint.h>

#include "c5ref.h"
#include "sample_pipe.h"
#include "taps.h"

int32_t c5ref_interp(int32_t fx, int32_t fy, int32_t fz, int32_t v0, int32_t v1, int32_t v2, int32_t v3,
                     int32_t v4, int32_t v5, int32_t v6, int32_t v7);

static c5ref_fault fault = C5REF_FAULT_INIT; /* the model's answer off by one in one call (c5ref.h) */

/* interp: the weights of the upper corners (UQ0.15) and corners v0..v7 (corner kx + 2 ky +
 * 4 kz) in, sample_value (UQ8.8) out. */
int32_t c5ref_interp(int32_t fx, int32_t fy, int32_t fz, int32_t v0, int32_t v1, int32_t v2, int32_t v3,
                     int32_t v4, int32_t v5, int32_t v6, int32_t v7)
{
    const int64_t frac[3] = {fx, fy, fz};
    const int32_t v[8] = {v0, v1, v2, v3, v4, v5, v6, v7};
    return (int32_t)c5_interp_blend(frac, v) ^ c5ref_faulty(&fault);
}
