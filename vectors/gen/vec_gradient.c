/* Block "gradient": the gradient of one sample (c5_grad_blend, sample_pipe.h). In: the
 * three voxel_frac weights (UQ0.15), per axis the 8 corners' central differences
 * v(c + e_a) - v(c - e_a) (SQ8.0, corner k = kx + 2 ky + 4 kz, neighbour indices clamped
 * to the grid by the gather) and the gradient scale gs (UQ1.15, min spacing / spacing);
 * out: the gradient SQ8.8, per axis round_he(round_he(sum_k w_x w_y w_z d_k / 2^37) * gs
 * / 2^15). */
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "rng.h"
#include "sample_pipe.h"

#define D(a, k) {"d" #a #k, 9, 0, "sint"}
static const c5_vfield fields[] = {
    {"frac_x", 15, 0, "UQ0.15"}, {"frac_y", 15, 0, "UQ0.15"}, {"frac_z", 15, 0, "UQ0.15"},
    D(x, 0), D(x, 1), D(x, 2), D(x, 3), D(x, 4), D(x, 5), D(x, 6), D(x, 7),
    D(y, 0), D(y, 1), D(y, 2), D(y, 3), D(y, 4), D(y, 5), D(y, 6), D(y, 7),
    D(z, 0), D(z, 1), D(z, 2), D(z, 3), D(z, 4), D(z, 5), D(z, 6), D(z, 7),
    {"gs_x", 16, 0, "UQ1.15"},   {"gs_y", 16, 0, "UQ1.15"},   {"gs_z", 16, 0, "UQ1.15"},
    {"grad_x", 17, 1, "SQ8.8"},  {"grad_y", 17, 1, "SQ8.8"},  {"grad_z", 17, 1, "SQ8.8"},
};
#undef D

static const c5_vblock block = {
    "gradient",
    "gradient of a sample: voxel_frac x, y, z, per axis the 8 corners' central differences dA0..dA7 "
    "(v(c + e_A) - v(c - e_A), corner k = kx + 2 ky + 4 kz) and the gradient scale gs in, the gradient "
    "out: trilinear blend rounded to SQ8.8, times gs, rounded again (rtl_model/proc/sample_pipe.h c5_grad_blend)",
    fields, (int)(sizeof fields / sizeof fields[0])};

typedef struct {
    int64_t frac[3];
    int32_t d[3][8];
    int64_t gs[3], grad[3];
} rec;

static void write_rec(c5_vfile *f, const void *p)
{
    const rec *r = p;
    for (int a = 0; a < 3; a++)
        c5_vfile_u(f, (uint64_t)r->frac[a]);
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < 8; k++)
            c5_vfile_s(f, r->d[a][k]);
    for (int a = 0; a < 3; a++)
        c5_vfile_u(f, (uint64_t)r->gs[a]);
    for (int a = 0; a < 3; a++)
        c5_vfile_s(f, r->grad[a]);
    c5_vfile_end(f);
}

static void vec(c5_vfile *f, rec *r)
{
    c5_grad_blend(r->frac, r->d, r->gs, r->grad);
    write_rec(f, r);
}

static int32_t rand_diff(uint64_t *rng) { return (int32_t)(c5_splitmix64(rng) % 511) - 255; }

/* Every fraction triple of {0, 2^-15, 1/2, 1 - 2^-15} with one corner at the extremes
 * (+255 in x, -255 in y, +128 in z; the corner in turn; gs = 1), every fourth triple also
 * with random differences and a random gs; all differences +255 and all -255 (the range's
 * ends), gs 0 and 1; rounding ties of the scale (a blend of +-1/256 or +-3/256 times gs =
 * 1/2, to even); then random cases. */
static int directed(c5_vset *s)
{
    c5_vfile *f = c5_vfile_open(s, &block, "directed", NULL, NULL);
    if (!f)
        return -1;
    uint64_t rng = s->seed ^ 0x6772616469656e74ull; /* "gradient" */
    static const int64_t F[] = {0, 1, 1 << 14, (1 << 15) - 1};
    int t = 0;
    for (int z = 0; z < 4; z++)
        for (int y = 0; y < 4; y++)
            for (int x = 0; x < 4; x++, t++) {
                rec r = {.frac = {F[x], F[y], F[z]}, .gs = {C5_ONE15, C5_ONE15, C5_ONE15}};
                r.d[0][t % 8] = 255;
                r.d[1][t % 8] = -255;
                r.d[2][t % 8] = 128;
                vec(f, &r);
                if (t % 4)
                    continue;
                for (int a = 0; a < 3; a++) {
                    for (int k = 0; k < 8; k++)
                        r.d[a][k] = rand_diff(&rng);
                    r.gs[a] = (int64_t)(c5_splitmix64(&rng) % (C5_ONE15 + 1));
                }
                vec(f, &r);
            }
    for (int sign = 1; sign >= -1; sign -= 2)
        for (int g = 0; g <= C5_ONE15; g += C5_ONE15) {
            rec r = {.frac = {12345, 1 << 14, 32767}, .gs = {g, g, g}};
            for (int a = 0; a < 3; a++)
                for (int k = 0; k < 8; k++)
                    r.d[a][k] = 255 * sign;
            vec(f, &r);
        }
    /* frac_x = n 2^-15, d0 = 0, d1 = +-128: a blend of exactly +-n/256 (n SQ8.8 LSBs); times
     * gs = 1/2: +-0.5 and +-1.5 LSB, ties to even. */
    for (int n = 1; n <= 3; n += 2)
        for (int sign = 1; sign >= -1; sign -= 2) {
            rec r = {.frac = {n, 0, 0}, .gs = {1 << 14, 1 << 14, 1 << 14}};
            for (int a = 0; a < 3; a++)
                r.d[a][1] = 128 * sign;
            vec(f, &r);
        }
    for (long i = 0; i < s->count; i++) {
        rec r;
        for (int a = 0; a < 3; a++) {
            r.frac[a] = (int64_t)(c5_splitmix64(&rng) & 0x7fff);
            for (int k = 0; k < 8; k++)
                r.d[a][k] = rand_diff(&rng);
            r.gs[a] = i % 2 ? C5_ONE15 : (int64_t)(c5_splitmix64(&rng) % (C5_ONE15 + 1));
        }
        vec(f, &r);
    }
    c5_vfile_close(f);
    return 0;
}

/* Scene taps: a uniform sample of the frame's samples with a gradient. */
static void tap_gradient(void *ctx, const c5_corners *k, const int64_t gs[3], const int64_t grad[3])
{
    c5_vscene *v = ctx;
    rec r;
    memcpy(r.frac, k->frac, sizeof r.frac);
    memcpy(r.d, k->d, sizeof r.d);
    memcpy(r.gs, gs, sizeof r.gs);
    memcpy(r.grad, grad, sizeof r.grad);
    c5_vsample_offer(v, C5_VB_GRADIENT, &r);
}

static int tap_begin(c5_vscene *v, c5_taps *t)
{
    if (c5_vsample_begin(v, C5_VB_GRADIENT, sizeof(rec), 0x102) != 0)
        return -1;
    t->gradient = tap_gradient;
    return 0;
}

static void tap_end(c5_vscene *v) { c5_vsample_end(v, C5_VB_GRADIENT, &block, write_rec, NULL); }

const c5_vblock_gen c5_vgen_gradient = {"gradient", directed, tap_begin, tap_end};
