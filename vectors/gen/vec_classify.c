/* Block "classify": the transfer-function lookup of one sample (c5_classify,
 * sample_pipe.h). In: sample_value UQ8.8; out: tf_rgba, 4 x UQ1.15, linear between table
 * entries i = floor(value) and i + 1 with the 8 fraction bits f, rounded once half to even:
 * round_he((tf[i] * 256 + (tf[i+1] - tf[i]) * f) / 256); for i > 254 (value >= 255.0) the
 * top clamp i = 254, f = 256 (entry 255 exactly). The table (256 entries of 4 x UQ1.15,
 * alpha step-corrected) is a memory image per source: CLASSIFY.SOURCE.tf.hex, named in
 * the vectors file's config. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "rng.h"
#include "sample_pipe.h"

static const c5_vfield fields[] = {
    {"value", 16, 0, "UQ8.8"}, {"r", 16, 1, "UQ1.15"}, {"g", 16, 1, "UQ1.15"},
    {"b", 16, 1, "UQ1.15"},    {"a", 16, 1, "UQ1.15"},
};

static const c5_vblock block = {"classify",
                                "transfer-function lookup: sample_value in, tf_rgba out, linear between entries "
                                "floor(value) and floor(value) + 1, rounded once half to even, top clamp "
                                "(value >= 255.0: entry 255); the table is the image named in config "
                                "(rtl_model/proc/sample_pipe.h c5_classify)",
                                fields, (int)(sizeof fields / sizeof fields[0])};

static const c5_vfield tf_fields[] = {
    {"r", 16, 0, "UQ1.15"}, {"g", 16, 0, "UQ1.15"}, {"b", 16, 0, "UQ1.15"}, {"a", 16, 0, "UQ1.15"}};
static const c5_vblock tf_block = {"classify",
                                   "transfer-function table: line i = entry i (scalar i), r g b a UQ1.15, alpha "
                                   "step-corrected (docs/rendering-spec.md 4.2)",
                                   tf_fields, 4};

typedef struct {
    int64_t value, rgba[4];
} rec;

static void write_rec(c5_vfile *f, const void *p)
{
    const rec *r = p;
    c5_vfile_u(f, (uint64_t)r->value);
    for (int c = 0; c < 4; c++)
        c5_vfile_u(f, (uint64_t)r->rgba[c]);
    c5_vfile_end(f);
}

/* Writes the table image of `source`; the vectors file's config names it. */
static json_t *write_table(c5_vset *s, const char *source, const char *scene, const int32_t tf[256][4])
{
    c5_vfile *f = c5_vfile_open(s, &tf_block, source, scene, "tf");
    if (!f)
        return json_null();
    for (int i = 0; i < 256; i++) {
        for (int c = 0; c < 4; c++)
            c5_vfile_u(f, (uint64_t)tf[i][c]);
        c5_vfile_end(f);
    }
    c5_vfile_close(f);
    char name[512];
    snprintf(name, sizeof name, "%s.%s.tf.hex", block.name, source);
    return json_pack("{s:s, s:i}", "tf_image", name, "entries", 256);
}

/* The directed table: r a ramp 0 .. 1 (odd steps: rounding ties at f = 128); g steep steps
 * (0 -> full scale and back, a one-entry spike, alternating 1 / full - 1 entries); b
 * random; a zero below 32 (transparent), a ramp, full scale, random, then 0 at 254 and
 * full scale at 255 (the top clamp reads entry 255 alone). */
static void directed_table(uint64_t *rng, int32_t tf[256][4])
{
    for (int i = 0; i < 256; i++) {
        tf[i][0] = (int32_t)((i * 2 * C5_ONE15 + 255) / 510); /* round(i / 255) */
        int g = (i >= 64 && i < 128) || i == 160 || i >= 224 ? C5_ONE15 : 0;
        if (i >= 192 && i < 224)
            g = i % 2 ? C5_ONE15 - 1 : 1;
        tf[i][1] = g;
        tf[i][2] = (int32_t)(c5_splitmix64(rng) % (C5_ONE15 + 1));
        int a = i < 32 ? 0 : i < 96 ? (i - 32) * 512 : i < 128 ? C5_ONE15 : (int)(c5_splitmix64(rng) % (C5_ONE15 + 1));
        if (i == 254)
            a = 0;
        if (i == 255)
            a = C5_ONE15;
        tf[i][3] = a;
    }
}

static void vec(c5_vfile *f, const c5_frame_regs *r, int64_t value)
{
    rec x = {.value = value};
    c5_classify(r, value, x.rgba);
    write_rec(f, &x);
}

/* Every entry i: value i - 2^-8 (just below the boundary), i (on it), i + 2^-8 and
 * i + 1/2 (the half way tie); the top: 255.0 (the largest interpolated value) and the
 * clamp above it up to the field's maximum; then random values. */
static int directed(c5_vset *s)
{
    c5_frame_regs *r = calloc(1, sizeof *r);
    if (!r)
        return c5_fail(s->err, "out of memory");
    uint64_t rng = s->seed ^ 0x636c617373ull; /* "class" */
    directed_table(&rng, r->tf);
    json_t *cfg = write_table(s, "directed", NULL, r->tf);
    c5_vfile *f = c5_vfile_open(s, &block, "directed", NULL, NULL);
    if (!f) {
        json_decref(cfg);
        free(r);
        return -1;
    }
    for (int i = 0; i < 256; i++) {
        if (i > 0)
            vec(f, r, i * 256 - 1);
        vec(f, r, i * 256);
        vec(f, r, i * 256 + 1);
        vec(f, r, i * 256 + 128);
    }
    static const int64_t top[] = {255 * 256 - 128, 255 * 256, 255 * 256 + 1, 255 * 256 + 128, 65535};
    for (int i = 0; i < (int)(sizeof top / sizeof top[0]); i++)
        vec(f, r, top[i]);
    for (long i = 0; i < s->count; i++)
        vec(f, r, (int64_t)(c5_splitmix64(&rng) % (255 * 256 + 1)));
    c5_vfile_set(f, "config", cfg);
    c5_vfile_close(f);
    free(r);
    return 0;
}

/* Scene taps: a uniform sample of the frame's samples; the table is the frame's. */
static void tap_classify(void *ctx, int64_t value, const int64_t rgba[4])
{
    c5_vscene *v = ctx;
    rec r = {.value = value};
    memcpy(r.rgba, rgba, sizeof r.rgba);
    c5_vsample_offer(v, C5_VB_CLASSIFY, &r);
}

static int tap_begin(c5_vscene *v, c5_taps *t)
{
    if (c5_vsample_begin(v, C5_VB_CLASSIFY, sizeof(rec), 0x103) != 0)
        return -1;
    t->classify = tap_classify;
    return 0;
}

static void tap_end(c5_vscene *v) { c5_vsample_end(v, C5_VB_CLASSIFY, &block, write_rec, write_table(v->set, v->scene, v->scene, v->regs->tf)); }

const c5_vblock_gen c5_vgen_classify = {"classify", directed, tap_begin, tap_end};
