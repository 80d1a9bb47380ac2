/* Shading of the C model (c5_shade, rtl_model/proc/sample_pipe.h) as a live reference for GHDL
 * (tb/c5ref_pkg.vhd). The registers and the specular power table are drawn from the
 * testbench's seed here, and read by the testbench word by word to write them into the
 * block (the order of the shade vectors' regs image: ka kd ks n_lights, then 8 light slots
 * of kind pos_x..z dir_x..z intensity, zero past n_lights). Per sample: the ray's direction
 * made a unit vector as the model's geometry does (c5ref_sh_dir), the inputs set, one run. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "c5ref.h"
#include "geom.h"
#include "rng.h"
#include "sample_pipe.h"

int32_t c5ref_sh_setup(int32_t seed);
int32_t c5ref_sh_reg(int32_t addr);
int32_t c5ref_sh_pow(int32_t i);
int32_t c5ref_sh_reg_set(int32_t addr, int32_t v);
int32_t c5ref_sh_pow_set(int32_t i, int32_t v);
int32_t c5ref_sh_dir(int32_t x, int32_t y, int32_t z, int32_t a);
int32_t c5ref_sh_set(int32_t k, int32_t v);
int32_t c5ref_sh_run(int32_t k);

static c5_frame_regs regs;
static int64_t in_grad[3], in_tf[4], in_gpos[3], in_dir[3], out_rgb[3];
static uint64_t out_sat;
static long runs, fault = -1; /* this sample's rgb_r is off by one (c5ref.h) */

static int64_t draw(uint64_t *s, int64_t lo, int64_t hi) /* lo <= x <= hi */
{
    return lo + (int64_t)(c5_splitmix64(s) % (uint64_t)(hi - lo + 1));
}

/* Registers and power table from `seed`: ka, kd, ks in their light_term ranges, 1 to 8 lights
 * (point lights within the volume's first 256 voxels, directional ones towards a random unit
 * vector), intensities up to 4.0, the table (i / 1024)^p for p from 1 to 64. */
int32_t c5ref_sh_setup(int32_t seed)
{
    uint64_t s = (uint64_t)seed * 0x9e3779b97f4a7c15ull;
    memset(&regs, 0, sizeof regs);
    regs.ka = draw(&s, 0, 4096);
    regs.kd = draw(&s, 0, 16384);
    regs.ks = draw(&s, 0, 8192);
    regs.n_lights = (int)draw(&s, 1, C5_MAX_LIGHTS);
    for (int i = 0; i < regs.n_lights; i++) {
        c5_light_regs *l = &regs.lights[i];
        l->kind = c5_splitmix64(&s) & 1 ? C5_LIGHT_DIRECTIONAL : C5_LIGHT_POINT;
        int64_t v[3];
        for (int a = 0; a < 3; a++) {
            l->pos[a] = draw(&s, 0, (int64_t)256 << 15);
            v[a] = draw(&s, -32768, 32767);
        }
        if (v[0] == 0 && v[1] == 0 && v[2] == 0)
            v[2] = 1;
        c5_geom_normalize(v, l->dir);
        l->intensity = draw(&s, 0, 16384);
    }
    double p = (double)draw(&s, 1, 64);
    for (int i = 0; i <= 1 << C5_POW_BITS; i++)
        regs.pow_tab[i] = (int32_t)lround(pow((double)i / (1 << C5_POW_BITS), p) * 32768.0);
    runs = 0;
    fault = c5ref_fault_step();
    return regs.n_lights;
}

int32_t c5ref_sh_reg(int32_t addr)
{
    const int64_t head[4] = {regs.ka, regs.kd, regs.ks, regs.n_lights};
    if (addr >= 0 && addr < 4)
        return (int32_t)head[addr];
    int i = (addr - 4) / 8, k = (addr - 4) % 8;
    if (addr < 4 || i >= C5_MAX_LIGHTS || i >= regs.n_lights)
        return 0;
    const c5_light_regs *l = &regs.lights[i];
    const int64_t slot[8] = {l->kind, l->pos[0], l->pos[1], l->pos[2], l->dir[0], l->dir[1], l->dir[2], l->intensity};
    return (int32_t)slot[k];
}

int32_t c5ref_sh_pow(int32_t i) { return i >= 0 && i <= 1 << C5_POW_BITS ? regs.pow_tab[i] : 0; }

/* The registers and the power table written one by one, at the addresses c5ref_sh_reg and
 * c5ref_sh_pow read (a vector set's images SHADE.SOURCE.regs.hex and .pow.hex, line by
 * line): the coverage replays the golden shading vectors with them. -1 outside. */
int32_t c5ref_sh_reg_set(int32_t addr, int32_t v)
{
    int64_t *head[4] = {&regs.ka, &regs.kd, &regs.ks, NULL};
    if (addr == 3 && v >= 0 && v <= C5_MAX_LIGHTS) {
        regs.n_lights = v;
        return 0;
    }
    if (addr >= 0 && addr < 3) {
        *head[addr] = v;
        return 0;
    }
    int i = (addr - 4) / 8, k = (addr - 4) % 8;
    if (addr < 4 || i >= C5_MAX_LIGHTS)
        return -1;
    c5_light_regs *l = &regs.lights[i];
    int64_t *slot[8] = {NULL, &l->pos[0], &l->pos[1], &l->pos[2], &l->dir[0], &l->dir[1], &l->dir[2], &l->intensity};
    if (k == 0)
        l->kind = v; /* the image's code (vectors/gen/vec_shade.c) */
    else
        *slot[k] = v;
    return 0;
}

int32_t c5ref_sh_pow_set(int32_t i, int32_t v)
{
    if (i < 0 || i > 1 << C5_POW_BITS)
        return -1;
    regs.pow_tab[i] = v;
    return 0;
}

/* Component a of (x, y, z) made a unit vector (SQ1.14), as the model's rays are. */
int32_t c5ref_sh_dir(int32_t x, int32_t y, int32_t z, int32_t a)
{
    int64_t v[3] = {x, y, z}, d[3];
    if (!x && !y && !z)
        v[2] = 1;
    c5_geom_normalize(v, d);
    return a >= 0 && a < 3 ? (int32_t)d[a] : 0;
}

/* k: 0..2 grad (SQ8.8), 3..5 tf r g b (UQ1.15), 6..8 gpos (SQ13.15), 9..11 dir (SQ1.14). */
int32_t c5ref_sh_set(int32_t k, int32_t v)
{
    int64_t *in[12] = {&in_grad[0], &in_grad[1], &in_grad[2], &in_tf[0], &in_tf[1], &in_tf[2],
                       &in_gpos[0], &in_gpos[1], &in_gpos[2], &in_dir[0], &in_dir[1], &in_dir[2]};
    if (k < 0 || k >= 12)
        return -1;
    *in[k] = v;
    return 0;
}

/* k -1: runs the sample; k 0..2: its rgb (UQ4.12), k 3: its clamps. */
int32_t c5ref_sh_run(int32_t k)
{
    if (k == -1) {
        c5_sample smp = {0};
        memcpy(smp.grad, in_grad, sizeof smp.grad);
        in_tf[3] = C5_ONE15;
        out_sat = 0;
        c5_shade(&regs, &smp, in_tf, in_gpos, in_dir, out_rgb, &out_sat);
        out_rgb[0] ^= runs++ == fault;
    }
    return k >= 0 && k < 3 ? (int32_t)out_rgb[k] : k == 3 ? (int32_t)out_sat : 0;
}
