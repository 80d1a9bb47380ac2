/* The datapath blocks of the C model (rtl_model/proc/sample_pipe.h) as live references for GHDL
 * (fpga/tb/c5ref_pkg.vhd): each call runs the model's own block function on one
 * transaction, as vectors/gen does for the golden vectors. Integers cross as VHDL
 * `integer`; signals in their raw fixed-point integers. */
#include <stdint.h>
#include <string.h>

#include "c5ref.h"
#include "sample_pipe.h"
#include "taps.h"

int32_t c5ref_interp(int32_t fx, int32_t fy, int32_t fz, int32_t v0, int32_t v1, int32_t v2, int32_t v3,
                     int32_t v4, int32_t v5, int32_t v6, int32_t v7);
int32_t c5ref_gr_set(int32_t k, int32_t v);
int32_t c5ref_gr_run(int32_t axis);
int32_t c5ref_cl_table(int32_t i, int32_t ch, int32_t v);
int32_t c5ref_cl_run(int32_t value, int32_t ch);
int32_t c5ref_cp_set(int32_t k, int32_t v);
int32_t c5ref_cp_run(void);
int32_t c5ref_cp_out(int32_t k);

static long runs, fault = -2; /* the model's answer is off by one in this call (c5ref.h); -2: not read yet */

static int faulty(void)
{
    if (fault == -2)
        fault = c5ref_fault_step();
    return runs++ == fault;
}

/* interp: the weights of the upper corners (UQ0.15) and corners v0..v7 (corner kx + 2 ky +
 * 4 kz) in, sample_value (UQ8.8) out. */
int32_t c5ref_interp(int32_t fx, int32_t fy, int32_t fz, int32_t v0, int32_t v1, int32_t v2, int32_t v3,
                     int32_t v4, int32_t v5, int32_t v6, int32_t v7)
{
    const int64_t frac[3] = {fx, fy, fz};
    const int32_t v[8] = {v0, v1, v2, v3, v4, v5, v6, v7};
    return (int32_t)c5_interp_blend(frac, v) ^ faulty();
}

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
        gr_out[0] ^= faulty();
    }
    return axis >= 0 && axis < 3 ? (int32_t)gr_out[axis] : 0;
}

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
        cl_out[0] ^= faulty();
    }
    return ch >= 0 && ch < 4 ? (int32_t)cl_out[ch] : 0;
}

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
    cio.opa_out = ray.opa ^ faulty();
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
