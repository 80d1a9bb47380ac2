/* The composite block of the C model (rtl_model/proc/sample_pipe.h) as the live reference of
 * tb/tb_composite_live.vhd (GHDL, VHPIDIRECT through tb/c5ref_pkg.vhd): each call runs the
 * model's own block function on one transaction, as vectors/gen/vec_composite.c does for the
 * golden vectors. Integers cross as VHDL `integer`; signals in their raw fixed-point
 * integers. */
#include <stdint.h>
#include <string.h>

#include "c5ref.h"
#include "sample_pipe.h"
#include "taps.h"

int32_t c5ref_cp_set(int32_t k, int32_t v);
int32_t c5ref_cp_run(void);
int32_t c5ref_cp_out(int32_t k);

static c5ref_fault fault = C5REF_FAULT_INIT; /* the model's answer off by one in one call (c5ref.h) */

/* composite: inputs set one by one (k: 0 w, 1 opa, 2..4 rgb, 5 alpha, 6..8 c, 9 shadow,
 * 10 a_max), one run, outputs read (k: 0..2 rgb_out, 3 opa_out, 4 done, 5 sat). */
static c5_composite_io cio;

int32_t c5ref_cp_set(int32_t k, int32_t v)
{
    int64_t *in[] = {&cio.w, &cio.opa, &cio.rgb[0], &cio.rgb[1], &cio.rgb[2], &cio.alpha,
                     &cio.c[0], &cio.c[1], &cio.c[2], NULL, &cio.a_max};
    if (k == 9)
        cio.shadow = v != 0;
    else if (k >= 0 && k <= 10)
        *in[k] = v;
    else
        return -1;
    return 0;
}

int32_t c5ref_cp_run(void)
{
    c5_frame_regs r; /* c5_composite reads a_max alone */
    r.a_max = cio.a_max;
    c5_bray ray = {.w = cio.w, .opa = cio.opa};
    memcpy(ray.rgb, cio.rgb, sizeof ray.rgb);
    uint64_t sat = 0;
    cio.done = c5_composite(&r, &ray, cio.alpha, cio.shadow ? NULL : cio.c, &sat);
    memcpy(cio.rgb_out, ray.rgb, sizeof cio.rgb_out);
    cio.opa_out = ray.opa ^ c5ref_faulty(&fault);
    cio.sat = (int)sat;
    return 0;
}

int32_t c5ref_cp_out(int32_t k)
{
    switch (k) {
    case 0: case 1: case 2: return (int32_t)cio.rgb_out[k];
    case 3: return (int32_t)cio.opa_out;
    case 4: return cio.done;
    case 5: return cio.sat;
    default: return 0;
    }
}
