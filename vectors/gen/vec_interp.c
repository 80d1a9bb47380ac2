/* Block "interp": trilinear interpolation of one sample (c5_interp_blend, sample_pipe.h).
 * In: the three voxel_frac weights (UQ0.15, the fraction of pos - 0.5 per axis: the weight
 * of the upper corners) and the 8 corner voxels (uint8, corner k = kx + 2 ky + 4 kz, x
 * fastest, indices already clamped to the grid by the gather); out: sample_value UQ8.8,
 * round_half_even(sum_k w_x w_y w_z v_k / 2^37) with w = 2^15 - frac or frac. */
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "rng.h"
#include "sample_pipe.h"

static const c5_vfield fields[] = {
    {"frac_x", 15, 0, "UQ0.15"}, {"frac_y", 15, 0, "UQ0.15"}, {"frac_z", 15, 0, "UQ0.15"},
    {"v0", 8, 0, "uint"},        {"v1", 8, 0, "uint"},        {"v2", 8, 0, "uint"},
    {"v3", 8, 0, "uint"},        {"v4", 8, 0, "uint"},        {"v5", 8, 0, "uint"},
    {"v6", 8, 0, "uint"},        {"v7", 8, 0, "uint"},        {"value", 16, 1, "UQ8.8"},
};

static const c5_vblock block = {"interp",
                                "trilinear interpolation: voxel_frac x, y, z (weights of the upper corners) and "
                                "the 8 corner voxels (corner k = kx + 2 ky + 4 kz) in, sample_value out "
                                "(round half to even once; rtl_model/proc/sample_pipe.h c5_interp_blend)",
                                fields, (int)(sizeof fields / sizeof fields[0])};

typedef struct {
    int64_t frac[3];
    int32_t v[8];
    int64_t value;
} rec;

static void write_rec(c5_vfile *f, const void *p)
{
    const rec *r = p;
    for (int a = 0; a < 3; a++)
        c5_vfile_u(f, (uint64_t)r->frac[a]);
    for (int j = 0; j < 8; j++)
        c5_vfile_u(f, (uint64_t)r->v[j]);
    c5_vfile_u(f, (uint64_t)r->value);
    c5_vfile_end(f);
}

/* Computes the output of the inputs through the model's function and writes the vector. */
static void vec(c5_vfile *f, int64_t fx, int64_t fy, int64_t fz, const int32_t v[8])
{
    rec r = {.frac = {fx, fy, fz}};
    memcpy(r.v, v, sizeof r.v);
    r.value = c5_interp_blend(r.frac, r.v);
    write_rec(f, &r);
}

/* Every fraction triple of {0, 1, 1/2, 1 - 2^-15} with the corners all 0, all 255, one
 * corner 255 (each in turn), and random; rounding ties (a corner difference of 64 or 192
 * at frac 2^-15: exactly half an LSB, to even down and up); then random cases. */
static int directed(c5_vset *s)
{
    c5_vfile *f = c5_vfile_open(s, &block, "directed", NULL, NULL);
    if (!f)
        return -1;
    uint64_t rng = s->seed ^ 0x696e74657270ull; /* "interp" */
    static const int64_t F[] = {0, 1, 1 << 14, (1 << 15) - 1};
    int t = 0;
    for (int z = 0; z < 4; z++)
        for (int y = 0; y < 4; y++)
            for (int x = 0; x < 4; x++, t++) {
                int32_t v[8];
                for (int j = 0; j < 8; j++)
                    v[j] = 0;
                vec(f, F[x], F[y], F[z], v);
                for (int j = 0; j < 8; j++)
                    v[j] = 255;
                vec(f, F[x], F[y], F[z], v);
                for (int j = 0; j < 8; j++)
                    v[j] = j == t % 8 ? 255 : 0;
                vec(f, F[x], F[y], F[z], v);
                for (int j = 0; j < 8; j++)
                    v[j] = (int32_t)(c5_splitmix64(&rng) & 255);
                vec(f, F[x], F[y], F[z], v);
            }
    for (int a = 0; a < 3; a++) /* ties along each axis: corner 0 and its upper neighbour */
        for (int d = 64; d < 256; d += 128)
            for (int lo = 0; lo < 2; lo++) {
                int32_t v[8] = {0};
                int up = 1 << a;
                v[0] = lo ? 255 - d : 0;
                v[up] = v[0] + d;
                int64_t fr[3] = {0, 0, 0};
                fr[a] = 1;
                vec(f, fr[0], fr[1], fr[2], v);
                v[0] = lo ? 255 : d; /* the mirror: weight 1 - 2^-15 on the upper corner */
                v[up] = v[0] - d;
                fr[a] = (1 << 15) - 1;
                vec(f, fr[0], fr[1], fr[2], v);
            }
    for (long i = 0; i < s->count; i++) {
        int32_t v[8];
        for (int j = 0; j < 8; j++)
            v[j] = (int32_t)(c5_splitmix64(&rng) & 255);
        int64_t fr[3];
        for (int a = 0; a < 3; a++)
            fr[a] = (int64_t)(c5_splitmix64(&rng) & 0x7fff);
        vec(f, fr[0], fr[1], fr[2], v);
    }
    c5_vfile_close(f);
    return 0;
}

/* Scene taps: a uniform sample of the frame's samples. */
static void tap_interp(void *ctx, const c5_corners *k, int64_t value)
{
    c5_vscene *v = ctx;
    rec r;
    memcpy(r.frac, k->frac, sizeof r.frac);
    memcpy(r.v, k->v, sizeof r.v);
    r.value = value;
    c5_vsample_offer(v, C5_VB_INTERP, &r);
}

static int tap_begin(c5_vscene *v, c5_taps *t)
{
    if (c5_vsample_begin(v, C5_VB_INTERP, sizeof(rec), 0x101) != 0)
        return -1;
    t->interp = tap_interp;
    return 0;
}

static void tap_end(c5_vscene *v) { c5_vsample_end(v, C5_VB_INTERP, &block, write_rec, NULL); }

const c5_vblock_gen c5_vgen_interp = {"interp", directed, tap_begin, tap_end};
