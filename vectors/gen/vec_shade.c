/* Block "shade": Phong shading of one sample (c5_shade, sample_pipe.h; docs/rendering-spec.md
 * 4.3). In: the gradient (SQ8.8), the table colour (tf_rgba r g b, UQ1.15), the sample in
 * geom coordinates (SQ13.15, for point lights) and the ray direction (SQ1.14); out:
 * shaded_rgb (UQ4.12, clamped at 65535) and how many channels the clamp hit. The
 * registers (ka, kd, ks, the lights) are a memory image per source, one value a line in
 * the order the config names (SHADE.SOURCE.regs.hex), and the specular power table
 * (2^10 + 1 entries over N.H in [0, 1], UQ1.15) another (SHADE.SOURCE.pow.hex). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "geom.h"
#include "rng.h"
#include "sample_pipe.h"

static const c5_vfield fields[] = {
    {"grad_x", 17, 0, "SQ8.8"},   {"grad_y", 17, 0, "SQ8.8"},   {"grad_z", 17, 0, "SQ8.8"},
    {"tf_r", 16, 0, "UQ1.15"},    {"tf_g", 16, 0, "UQ1.15"},    {"tf_b", 16, 0, "UQ1.15"},
    {"gpos_x", 29, 0, "SQ13.15"}, {"gpos_y", 29, 0, "SQ13.15"}, {"gpos_z", 29, 0, "SQ13.15"},
    {"dir_x", 16, 0, "SQ1.14"},   {"dir_y", 16, 0, "SQ1.14"},   {"dir_z", 16, 0, "SQ1.14"},
    {"rgb_r", 16, 1, "UQ4.12"},   {"rgb_g", 16, 1, "UQ4.12"},   {"rgb_b", 16, 1, "UQ4.12"},
    {"sat", 3, 1, "uint"},
};

static const c5_vblock block = {
    "shade",
    "Phong shading of a sample: gradient, table colour, geom position and ray direction in; shaded_rgb "
    "(clamped) and the number of clamps out (light_term k and ks, then the channels: 0 to 5); registers and power table are the images named in "
    "config (rtl_model/proc/sample_pipe.h c5_shade, docs/rendering-spec.md 4.3)",
    fields, (int)(sizeof fields / sizeof fields[0])};

static const c5_vfield reg_field[] = {{"value", 32, 0, "sint"}};
static const c5_vblock reg_block = {"shade",
                                    "shading registers, one a line (two's complement in 32 bits), in the order "
                                    "of the vectors file's config: registers, then light slots",
                                    reg_field, 1};
static const c5_vfield pow_field[] = {{"spec_pow", 16, 0, "UQ1.15"}};
static const c5_vblock pow_block = {"shade",
                                    "specular power table: line i = (i / 1024)^p, UQ1.15, read linearly "
                                    "between entries at N.H (SQ1.14) >> 4, entry 1024 for N.H >= 1",
                                    pow_field, 1};

static void write_io(c5_vfile *f, const void *p)
{
    const c5_shade_io *io = p;
    for (int a = 0; a < 3; a++)
        c5_vfile_s(f, io->grad[a]);
    for (int c = 0; c < 3; c++)
        c5_vfile_u(f, (uint64_t)io->rgba[c]);
    for (int a = 0; a < 3; a++)
        c5_vfile_s(f, io->gpos[a]);
    for (int a = 0; a < 3; a++)
        c5_vfile_s(f, io->dir[a]);
    for (int c = 0; c < 3; c++)
        c5_vfile_u(f, (uint64_t)io->rgb[c]);
    c5_vfile_u(f, (uint64_t)io->sat);
    c5_vfile_end(f);
}

/* The register and power table images of `source`, and the config naming them. */
static json_t *write_config(c5_vset *s, const char *source, const char *scene, const c5_frame_regs *r)
{
    c5_vfile *f = c5_vfile_open(s, &reg_block, source, scene, "regs");
    if (f) {
        int64_t head[4] = {r->ka, r->kd, r->ks, r->n_lights};
        for (int i = 0; i < 4; i++) {
            c5_vfile_s(f, head[i]);
            c5_vfile_end(f);
        }
        for (int i = 0; i < C5_MAX_LIGHTS; i++) {
            const c5_light_regs *l = &r->lights[i];
            int on = i < r->n_lights;
            int64_t slot[8] = {on ? l->kind : 0, l->pos[0], l->pos[1], l->pos[2], l->dir[0], l->dir[1], l->dir[2],
                               l->intensity};
            for (int k = 0; k < 8; k++) {
                c5_vfile_s(f, on ? slot[k] : 0);
                c5_vfile_end(f);
            }
        }
        c5_vfile_close(f);
    }
    if ((f = c5_vfile_open(s, &pow_block, source, scene, "pow")) != NULL) {
        for (int i = 0; i <= 1 << C5_POW_BITS; i++) {
            c5_vfile_u(f, (uint64_t)r->pow_tab[i]);
            c5_vfile_end(f);
        }
        c5_vfile_close(f);
    }
    char regs[512], pow[512];
    snprintf(regs, sizeof regs, "%s.%s.regs.hex", block.name, source);
    snprintf(pow, sizeof pow, "%s.%s.pow.hex", block.name, source);
    return json_pack("{s:s, s:[s,s,s,s], s:i, s:[s,s,s,s,s,s,s,s], s:s, s:s, s:i}", "regs_image", regs, "registers",
                     "ka UQ4.12", "kd UQ4.12", "ks UQ4.12", "n_lights uint", "light_slots", C5_MAX_LIGHTS,
                     "light_slot", "kind uint (0 point, 1 directional)", "pos_x SQ13.15 (point)",
                     "pos_y SQ13.15 (point)", "pos_z SQ13.15 (point)", "dir_x SQ1.14 (directional, towards the light)",
                     "dir_y SQ1.14 (directional)", "dir_z SQ1.14 (directional)", "intensity UQ4.12", "unused",
                     "light slots n_lights..7 are all zero", "pow_image", pow, "pow_entries",
                     (1 << C5_POW_BITS) + 1);
}

/* The directed registers: ka 1/8, kd 3.5, ks 1; a directional light straight along +z
 * (intensity 4), a point light at (64, 32, 100) (1.5) and a directional light along
 * (1, 1, 0) / sqrt 2 (0.5); power 8, the table computed exactly: round(i^8 / 2^65). */
static void directed_regs(c5_frame_regs *r)
{
    r->ka = 512;
    r->kd = 14336;
    r->ks = 4096;
    r->n_lights = 3;
    r->lights[0] = (c5_light_regs){.kind = C5_LIGHT_DIRECTIONAL, .dir = {0, 0, 1 << 14}, .intensity = 16384};
    r->lights[1] = (c5_light_regs){
        .kind = C5_LIGHT_POINT, .pos = {64 << 15, 32 << 15, (int64_t)100 << 15}, .intensity = 6144};
    r->lights[2] = (c5_light_regs){.kind = C5_LIGHT_DIRECTIONAL, .dir = {11585, 11585, 0}, .intensity = 2048};
    for (int i = 0; i <= 1 << C5_POW_BITS; i++) {
        __int128 x = (__int128)i * i; /* i^8 with 80 fraction bits */
        x = x * x;
        x = x * x;
        r->pow_tab[i] = (int32_t)c5_rshift128_he(x, 80 - 15);
    }
}

static void vec(c5_vfile *f, const c5_frame_regs *r, const int64_t g[3], const int64_t rgb[3], const int64_t gpos[3],
                const int64_t d[3])
{
    c5_shade_io io = {.rgba = {rgb[0], rgb[1], rgb[2], C5_ONE15}};
    c5_sample smp = {0};
    for (int a = 0; a < 3; a++) {
        io.grad[a] = smp.grad[a] = g[a];
        io.gpos[a] = gpos[a];
        io.dir[a] = d[a];
    }
    uint64_t sat = 0;
    c5_shade(r, &smp, io.rgba, io.gpos, io.dir, io.rgb, &sat);
    io.sat = (int)sat;
    write_io(f, &io);
}

/* "bright": registers that saturate light_term: ka 1/4, kd 4, ks 4 and one directional
 * light along +z of intensity 8 (each below the 16 the frame set-up allows, regs.c), the
 * same power table. A normal facing both the light and the viewer gives k = 1/4 + 32 and
 * ks = 32: both clamp at 16 - 2^-12, and every channel with a non-zero table colour then
 * clamps too (the specular term alone fills it). The directed registers above cannot: their
 * lights sum to intensity 6, so ks * spec stays at or below 6.0. */
static int bright(c5_vset *s)
{
    c5_frame_regs *r = calloc(1, sizeof *r);
    if (!r)
        return c5_fail(s->err, "out of memory");
    directed_regs(r); /* for its power table; the registers and lights are replaced */
    memset(r->lights, 0, sizeof r->lights);
    r->ka = 1024;
    r->kd = 16384;
    r->ks = 16384;
    r->n_lights = 1;
    r->lights[0] = (c5_light_regs){.kind = C5_LIGHT_DIRECTIONAL, .dir = {0, 0, 1 << 14}, .intensity = 32768};
    json_t *cfg = write_config(s, "bright", NULL, r);
    c5_vfile *f = c5_vfile_open(s, &block, "bright", NULL, NULL);
    if (!f) {
        json_decref(cfg);
        free(r);
        return -1;
    }
    const int64_t gz[3] = {0, 0, -256}, down[3] = {0, 0, -(1 << 14)}, p[3] = {20 << 15, 40 << 15, 10 << 15};
    const int64_t white[3] = {C5_ONE15, C5_ONE15, C5_ONE15}, dim[3] = {1, 1, 1}, green0[3] = {C5_ONE15, 0, 8192};
    const int64_t tilt[3] = {0, 181, -181}, zero_g[3] = {0, 0, 0};
    vec(f, r, gz, white, p, down);     /* sat 5: k, ks and the three channels */
    vec(f, r, gz, dim, p, down);       /* sat 5 with the least table colour, 2^-15: 2 LSB over ks */
    vec(f, r, gz, green0, p, down);    /* sat 4: a black channel stays at ks, 16 - 2^-12 */
    vec(f, r, tilt, white, p, down);   /* N.L = N.H = 1/sqrt 2: k clamps, ks (2.0) does not, the channels do */
    vec(f, r, zero_g, white, p, down); /* zero gradient: ka only, no clamp */
    c5_vfile_set(f, "config", cfg);
    c5_vfile_close(f);
    free(r);
    return 0;
}

#define P(x, y, z) {(int64_t)(x) << 15, (int64_t)(y) << 15, (int64_t)(z) << 15}

/* The zero gradient (ambient alone) and the lights' fade, min(4 |g|^2, 1), along -x (N =
 * +x: two lights lit, nothing clamped): |g| = 0, 1/256, 1/16, 1/4, 127/256 (fading), 1/2
 * and 1 (whole), and one gradient off the axes; a normal facing the viewer and the same gradient negated (back-facing,
 * flipped: the same result); N.H = 1 exactly (the power table's last entry) and just
 * below; every light behind (N.L < 0, and N.L = 0 exactly for the third light); a point
 * light at the sample (L = 0); saturation of every channel and of one; random cases
 * (gradients across SQ8.8, unit directions, positions in a 256^3 box); then a black table
 * colour, gradients of +-255.0 along the axes, a sample at the origin. "bright": sat 5. */
static int directed(c5_vset *s)
{
    c5_frame_regs *r = calloc(1, sizeof *r);
    if (!r)
        return c5_fail(s->err, "out of memory");
    directed_regs(r);
    json_t *cfg = write_config(s, "directed", NULL, r);
    c5_vfile *f = c5_vfile_open(s, &block, "directed", NULL, NULL);
    if (!f) {
        json_decref(cfg);
        free(r);
        return -1;
    }
    static const int64_t zero_g[][3] = {{0, 0, 0},    {-1, 0, 0},   {-16, 0, 0},  {-64, 0, 0},
                                        {-127, 0, 0}, {-128, 0, 0}, {-256, 0, 0}, {9, -9, 9}};
    const int64_t rgb0[3] = {C5_ONE15, 16384, 1}, p0[3] = P(10, 10, 10), down[3] = {0, 0, -(1 << 14)},
                  up[3] = {0, 0, 1 << 14};
    for (int i = 0; i < (int)(sizeof zero_g / sizeof zero_g[0]); i++)
        vec(f, r, zero_g[i], rgb0, p0, down);
    const int64_t rgb1[3] = {8192, 16384, 4096}, p1[3] = P(20, 40, 10), gz[3] = {0, 0, -256}, gzn[3] = {0, 0, 256};
    vec(f, r, gz, rgb1, p1, down);  /* N = V = L0: N.H = 1 */
    vec(f, r, gzn, rgb1, p1, down); /* back-facing: flipped, the same */
    static const int64_t tilt[][3] = {{-1, 0, -256}, {-8, 0, -256}, {-64, 0, -256}, {0, 64, -256}};
    for (int i = 0; i < 4; i++)
        vec(f, r, tilt[i], rgb1, p1, down);
    const int64_t white[3] = {C5_ONE15, C5_ONE15, C5_ONE15}, p2[3] = P(64, 32, 10);
    vec(f, r, gz, white, p2, up);                 /* every light behind: ka only */
    const int64_t at_light[3] = P(64, 32, 100);
    vec(f, r, gz, rgb1, at_light, down);          /* L1 = 0 */
    vec(f, r, gz, white, p1, down);               /* every channel saturates */
    const int64_t one_sat[3] = {C5_ONE15, 0, 8192};
    vec(f, r, gz, one_sat, p1, down);             /* red saturates */
    uint64_t rng = s->seed ^ 0x7368616465ull; /* "shade" */
    for (long i = 0; i < s->count; i++) {
        int64_t g[3], rgb[3], gpos[3], dv[3], d[3];
        do {
            for (int a = 0; a < 3; a++)
                dv[a] = (int64_t)(c5_splitmix64(&rng) % 65536) - 32768;
        } while (c5_geom_normalize(dv, d) == 0);
        int small = i % 4 == 0; /* a quarter near the zero-gradient threshold */
        for (int a = 0; a < 3; a++) {
            g[a] = small ? (int64_t)(c5_splitmix64(&rng) % 49) - 24 : (int64_t)(c5_splitmix64(&rng) % 131072) - 65536;
            rgb[a] = (int64_t)(c5_splitmix64(&rng) % (C5_ONE15 + 1));
            gpos[a] = (int64_t)(c5_splitmix64(&rng) % ((uint64_t)256 << 15));
        }
        vec(f, r, g, rgb, gpos, d);
    }
    /* Appended after the random cases, which keep their lines. A black table colour: */
    const int64_t black[3] = {0, 0, 0}, origin[3] = {0, 0, 0};
    vec(f, r, zero_g[0], black, p0, down); /* zero gradient (ka only): every shaded channel 0 */
    vec(f, r, gz, black, p2, up);          /* every light behind (ka only): 0 */
    vec(f, r, gz, black, p1, down);        /* facing the lights: the specular term alone */
    /* The gradient block's extremes, +-255.0 an axis, seen along the axes (unit directions
     * +-1 exactly, the other components 0), each with one black channel. */
    static const int64_t gext[][3] = {{65280, 0, 0}, {-65280, 0, 0}, {0, 65280, 0},
                                      {0, -65280, 0}, {0, 0, 65280},  {0, 0, -65280}};
    static const int64_t axis_dir[][3] = {{-(1 << 14), 0, 0}, {1 << 14, 0, 0}, {0, -(1 << 14), 0},
                                          {0, 1 << 14, 0},    {0, 0, -(1 << 14)}, {0, 0, 1 << 14}};
    static const int64_t one_black[][3] = {{0, 20000, 30000}, {30000, 20000, 0}, {20000, 0, 30000},
                                           {0, 0, 30000},     {30000, 0, 0},     {0, 30000, 0}};
    for (int i = 0; i < 6; i++)
        vec(f, r, gext[i], one_black[i], p1, axis_dir[i]); /* grad_* min/max, dir_* +-1, a black channel */
    vec(f, r, gext[4], rgb1, origin, down); /* a sample at the grid's origin: gpos 0 on every axis */
    /* Rounding ties inside the shading (the rnd.* points of spec/coverage.toml), found by
     * search under these registers: a component exactly half an LSB between two codes, with
     * an even quotient (kept) and an odd one (rounded up to even). The normal -g / len(g)
     * (this gradient has both); a point light's direction (L1 from these positions); the half
     * vector (V one LSB off L0 = +z, so len(L0 + V) = 2 exactly); N.V, N.L and N.H. Each row:
     * gradient, table colour, geom position, direction. */
    static const int64_t ties[][4][3] = {
        {{-4318, -49826, -42352}, {16384, 16384, 16384}, P(64, 32, 90), {0, 0, -16384}},     /* normal */
        {{20000, 30000, -40000}, {16384, 16384, 16384}, {1872466, 1390327, 3069012}, {0, 0, -16384}}, /* L kept */
        {{20000, 30000, -40000}, {16384, 16384, 16384}, {3457687, 2217008, 3455070}, {0, 0, -16384}}, /* L up */
        {{20000, 30000, -40000}, {16384, 16384, 16384}, P(64, 32, 90), {1, -1, -16384}},     /* H kept */
        {{20000, 30000, -40000}, {16384, 16384, 16384}, P(64, 32, 90), {1, 0, -16384}},      /* H up */
        {{-455, 278, 119}, {2313, 20416, 15796}, {6523680, 1272128, 4782481}, {-9602, 12716, -3814}}, /* N.V kept */
        {{-113, 531, -49}, {1886, 17897, 8763}, {4897265, 7710638, 2396550}, {2823, 14726, -6604}},   /* N.V up */
        {{11861, 54834, 45344}, {10345, 15413, 23084}, {7299478, 2763761, 1306325}, {-4701, -9364, 12595}}, /* N.L kept */
        {{10294, 52693, -15124}, {390, 12242, 24701}, {7718053, 4062811, 4735272}, {-15571, -4369, 2627}}, /* N.L up */
        {{-36, 291, -382}, {10202, 31289, 26810}, {8050633, 7352196, 6224899}, {2966, 11695, -11084}}, /* N.H kept */
        {{29399, 19837, -30229}, {17089, 17069, 5778}, {2257981, 1567581, 8160361}, {7507, 6357, 13102}}, /* N.H up */
    };
    for (int i = 0; i < (int)(sizeof ties / sizeof ties[0]); i++)
        vec(f, r, ties[i][0], ties[i][1], ties[i][2], ties[i][3]);
    c5_vfile_set(f, "config", cfg);
    c5_vfile_close(f);
    free(r);
    return bright(s);
}

/* Scene taps: a uniform sample of the frame's shaded samples; the registers are the frame's. */
static void tap_shade(void *ctx, const c5_shade_io *io)
{
    c5_vscene *v = ctx;
    c5_vsample_offer(v, C5_VB_SHADE, io);
}

static int tap_begin(c5_vscene *v, c5_taps *t)
{
    if (c5_vsample_begin(v, C5_VB_SHADE, sizeof(c5_shade_io), 0x104) != 0)
        return -1;
    t->shade = tap_shade;
    return 0;
}

static void tap_end(c5_vscene *v) { c5_vsample_end(v, C5_VB_SHADE, &block, write_io, write_config(v->set, v->scene, v->scene, v->regs)); }

const c5_vblock_gen c5_vgen_shade = {"shade", directed, tap_begin, tap_end};
