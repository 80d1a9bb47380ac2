/* Block "composite": front-to-back compositing of one sample into the ray (c5_composite,
 * sample_pipe.h; docs/rendering-spec.md 5). In: the ray's contribution w, opacity A
 * (UQ1.15) and colour (UQ2.12, the packet's formats), the sample's alpha (UQ1.15) and
 * shaded colour c (UQ4.12), the shadow flag and max_opacity (UQ1.15). With T = 1 - A:
 * rgb' = clamp(rgb + round_he(w T alpha c / 2^45), 0, 2^14 - 1) (not for shadow rays, which
 * only attenuate), A' = A + round_he(T alpha / 2^15), done = A' >= max_opacity; sat counts
 * the clamped channels. */
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "rng.h"
#include "sample_pipe.h"

static const c5_vfield fields[] = {
    {"w", 16, 0, "UQ1.15"},         {"opa", 16, 0, "UQ1.15"},       {"rgb_r", 14, 0, "UQ2.12"},
    {"rgb_g", 14, 0, "UQ2.12"},     {"rgb_b", 14, 0, "UQ2.12"},     {"alpha", 16, 0, "UQ1.15"},
    {"c_r", 16, 0, "UQ4.12"},       {"c_g", 16, 0, "UQ4.12"},       {"c_b", 16, 0, "UQ4.12"},
    {"shadow", 1, 0, "uint"},       {"a_max", 16, 0, "UQ1.15"},     {"rgb_r_out", 14, 1, "UQ2.12"},
    {"rgb_g_out", 14, 1, "UQ2.12"}, {"rgb_b_out", 14, 1, "UQ2.12"}, {"opa_out", 16, 1, "UQ1.15"},
    {"done", 1, 1, "uint"},         {"sat", 2, 1, "uint"},
};

static const c5_vblock block = {
    "composite",
    "front-to-back compositing of a sample: the ray's w, opacity and colour, the sample's alpha and shaded "
    "colour, the shadow flag (colour ignored) and max_opacity in; colour (clamped), opacity, early "
    "termination and the number of clamped channels out (rtl_model/proc/sample_pipe.h c5_composite)",
    fields, (int)(sizeof fields / sizeof fields[0])};

static void write_io(c5_vfile *f, const void *p)
{
    const c5_composite_io *io = p;
    c5_vfile_u(f, (uint64_t)io->w);
    c5_vfile_u(f, (uint64_t)io->opa);
    for (int c = 0; c < 3; c++)
        c5_vfile_u(f, (uint64_t)io->rgb[c]);
    c5_vfile_u(f, (uint64_t)io->alpha);
    for (int c = 0; c < 3; c++)
        c5_vfile_u(f, (uint64_t)io->c[c]);
    c5_vfile_u(f, (uint64_t)io->shadow);
    c5_vfile_u(f, (uint64_t)io->a_max);
    for (int c = 0; c < 3; c++)
        c5_vfile_u(f, (uint64_t)io->rgb_out[c]);
    c5_vfile_u(f, (uint64_t)io->opa_out);
    c5_vfile_u(f, (uint64_t)io->done);
    c5_vfile_u(f, (uint64_t)io->sat);
    c5_vfile_end(f);
}

/* Runs the model's function on io's inputs, fills the outputs. */
static void run(c5_composite_io *io)
{
    c5_frame_regs r; /* c5_composite reads a_max alone */
    r.a_max = io->a_max;
    c5_bray ray = {.w = io->w, .opa = io->opa};
    memcpy(ray.rgb, io->rgb, sizeof ray.rgb);
    uint64_t sat = 0;
    io->done = c5_composite(&r, &ray, io->alpha, io->shadow ? NULL : io->c, &sat);
    memcpy(io->rgb_out, ray.rgb, sizeof io->rgb_out);
    io->opa_out = ray.opa;
    io->sat = (int)sat;
}

static void vec(c5_vfile *f, int64_t w, int64_t opa, int64_t rgb, int64_t alpha, int64_t c, int shadow, int64_t a_max)
{
    c5_composite_io io = {.w = w, .opa = opa, .alpha = alpha, .shadow = shadow, .a_max = a_max};
    for (int ch = 0; ch < 3; ch++) {
        io.rgb[ch] = rgb;
        io.c[ch] = c;
    }
    run(&io);
    write_io(f, &io);
}

/* The smallest alpha whose A' reaches a_max from opa (A' grows with alpha), 0 if none. */
static int64_t alpha_reaching(int64_t opa, int64_t a_max)
{
    for (int64_t a = 0; a <= C5_ONE15; a++)
        if (opa + c5_rshift_he((C5_ONE15 - opa) * a, 15) >= a_max)
            return a;
    return 0;
}

/* alpha 0 (nothing changes) and full (A' = 1, always done); opacity reaching max_opacity
 * exactly (the smallest alpha that does, and the one below) for several (A, max_opacity)
 * pairs, max_opacity 1 included (termination only at exact opacity 1); colour clamped at
 * its maximum per channel and in all three; full contribution of c at 16 - 2^-12; w = 0;
 * shadow rays (colour unchanged, opacity as usual, done); then random rays and samples,
 * a quarter of them shadow rays; then a black shaded colour. */
static int directed(c5_vset *s)
{
    c5_vfile *f = c5_vfile_open(s, &block, "directed", NULL, NULL);
    if (!f)
        return -1;
    const int64_t one = C5_ONE15, amax95 = 31130; /* 0.95 */
    vec(f, one, 0, 0, 0, 40000, 0, amax95);      /* alpha 0 */
    vec(f, one, 12345, 777, 0, 40000, 0, amax95);
    vec(f, one, 0, 0, one, 4096, 0, amax95);     /* alpha full: colour c, A' = 1 */
    vec(f, one, 20000, 100, one, 4096, 0, one);  /* ... done also with max_opacity 1 */
    static const int64_t pairs[][2] = {{0, 31130}, {0, 32768}, {16384, 31130}, {30000, 31130}, {31129, 31130},
                                       {1, 2},     {0, 1},     {12345, 20000},  {32767, 32768}, {100, 32768}};
    for (int i = 0; i < (int)(sizeof pairs / sizeof pairs[0]); i++) {
        int64_t a = alpha_reaching(pairs[i][0], pairs[i][1]);
        if (a > 0)
            vec(f, 20000, pairs[i][0], 5000, a - 1, 3000, 0, pairs[i][1]); /* just short */
        vec(f, 20000, pairs[i][0], 5000, a, 3000, 0, pairs[i][1]);         /* reaches exactly */
    }
    vec(f, one, 0, C5_RGB_MAX, 1, 32768, 0, one);       /* at the maximum, + 1 LSB: clamped */
    vec(f, one, 0, C5_RGB_MAX, 1, 16384, 0, one);       /* + 1/2 LSB: a tie, to even (+0) */
    vec(f, one, 0, C5_RGB_MAX - 1, one / 2, 65535, 0, one); /* clamped, all channels */
    vec(f, one, 0, 0, one, 65535, 0, one);              /* c 16 - 2^-12 at full weight: clamped */
    vec(f, one, 0, 0, one / 4, 65535, 0, one);          /* 4 - 2^-14 rounds to 4: clamped */
    vec(f, one, 0, 0, one / 4 - 1, 65535, 0, one);      /* just below the maximum */
    vec(f, 0, 0, 1000, one, 65535, 0, one);             /* w 0: opacity only */
    {
        c5_composite_io io = {.w = one, .opa = 0, .rgb = {C5_RGB_MAX, 0, 8000}, .alpha = one / 2,
                              .c = {8192, 65535, 10000}, .a_max = amax95};
        run(&io);
        write_io(f, &io); /* red (at its maximum) and green (+8) clamp, blue (+1.22) does not */
    }
    vec(f, one, 0, 3000, one / 2, 65535, 1, amax95); /* shadow: colour unchanged */
    vec(f, one, 20000, 3000, one, 65535, 1, amax95); /* shadow: done */
    uint64_t rng = s->seed ^ 0x636f6d706full; /* "compo" */
    for (long i = 0; i < s->count; i++) {
        c5_composite_io io;
        io.a_max = 1 + (int64_t)(c5_splitmix64(&rng) % C5_ONE15);
        if (i % 3 == 0)
            io.a_max = i % 2 ? C5_ONE15 : amax95;
        io.opa = (int64_t)(c5_splitmix64(&rng) % (uint64_t)io.a_max); /* a ray in flight: A < max */
        io.w = (int64_t)(c5_splitmix64(&rng) % (C5_ONE15 + 1));
        io.alpha = 1 + (int64_t)(c5_splitmix64(&rng) % C5_ONE15);
        io.shadow = i % 4 == 3;
        for (int ch = 0; ch < 3; ch++) {
            io.rgb[ch] = (int64_t)(c5_splitmix64(&rng) % (C5_RGB_MAX + 1));
            io.c[ch] = (int64_t)(c5_splitmix64(&rng) % 65536);
        }
        run(&io);
        write_io(f, &io);
    }
    /* Appended after the random cases, which keep their lines: a black shaded colour (a
     * black transfer-function entry shaded without a specular term). */
    vec(f, 20000, 5000, 3000, 16384, 0, 0, amax95); /* c 0: the colour stays, the opacity grows */
    vec(f, one, 20000, 100, one, 0, 0, one);       /* c 0 at full alpha: done, colour unchanged */
    c5_vfile_close(f);
    return 0;
}

/* Scene taps: a uniform sample of the frame's composited samples. */
static void tap_composite(void *ctx, const c5_composite_io *io)
{
    c5_vscene *v = ctx;
    c5_vsample_offer(v, C5_VB_COMPOSITE, io);
}

static int tap_begin(c5_vscene *v, c5_taps *t)
{
    if (c5_vsample_begin(v, C5_VB_COMPOSITE, sizeof(c5_composite_io), 0x105) != 0)
        return -1;
    t->composite = tap_composite;
    return 0;
}

static void tap_end(c5_vscene *v) { c5_vsample_end(v, C5_VB_COMPOSITE, &block, write_io, json_pack("{s:i}", "a_max", (int)v->regs->a_max)); }

const c5_vblock_gen c5_vgen_composite = {"composite", directed, tap_begin, tap_end};
