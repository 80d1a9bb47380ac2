/* The datapath vector blocks (vectors/gen/vec_{interp,gradient,classify,shade,composite,
 * traverse}.c): a small set is generated (directed files and one tapped scene), read back
 * from its hex text through the manifest's field list, and every vector is recomputed
 * through the model's function (and, for the blends and the table, an independent exact
 * evaluation); each directed file must hold its named corner cases. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "harness.h"
#include "processor.h"
#include "sample_pipe.h"

extern const c5_vblock_gen c5_vgen_interp, c5_vgen_gradient, c5_vgen_classify, c5_vgen_shade, c5_vgen_composite,
    c5_vgen_traverse;

#define COUNT 24
#define SCENE "dp"

static const char *scene_json =
    "{\"volumes\": [{\"generator\": \"blobs\", \"dims\": [24, 20, 16], \"count\": 4, \"seed\": 2}],"
    " \"transfer_function\": {\"opacity\": [[0, 0], [60, 0], [120, 0.3], [255, 0.8]],"
    "   \"color\": [[0, 0.2, 0.4, 0.9], [255, 1, 0.8, 0.3]],"
    "   \"shading\": {\"ambient\": 0.2, \"diffuse\": 0.9, \"specular\": 0.6, \"specular_power\": 12}},"
    " \"lights\": [{\"type\": \"directional\", \"direction\": [-0.3, 0.5, -1], \"intensity\": 1.2},"
    "   {\"type\": \"point\", \"position\": [40, -30, 30], \"intensity\": 0.8}],"
    " \"camera\": {\"eye\": [60, -50, 40], \"target\": [0, 0, 0], \"width\": 16, \"height\": 16}}";

/* Writes the directed files of one block and the scene's files of every block into the
 * case's temporary directory; returns the directory, NULL on failure. */
static const char *generate(const c5_vblock_gen *g)
{
    static char dir[600];
    snprintf(dir, sizeof dir, "%s/set", c5t_tmpdir());
    c5_err err;
    c5_vset set;
    if (c5_vset_init(&set, dir, 7, COUNT, &err) != 0 || g->directed(&set) != 0)
        return NULL;
    static c5_scene s;
    c5_supervol sv = {0};
    int cells[3] = {2, 1, 1};
    json_t *rec = NULL;
    if (c5_scene_parse(scene_json, NULL, "t", &s, &err) == 0 && c5_supervol_build(&s, &sv, &err) == 0)
        rec = c5_vec_scene(&set, SCENE, &s, &sv, cells);
    c5_supervol_free(&sv);
    if (!rec) {
        c5_vset_abort(&set);
        return NULL;
    }
    json_decref(rec);
    return c5_vset_finish(&set, NULL) == 0 ? dir : NULL;
}

/* One file read back: rows x columns of raw values (sign-extended for signed fields). */
typedef struct {
    int n;
    const char *name[64];
    long rows;
    int64_t *v;
    json_t *entry;
} table;

static json_t *manifest_entry(const char *dir, const char *file)
{
    char path[800];
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    json_t *m = json_load_file(path, 0, NULL), *f, *hit = NULL;
    size_t i;
    json_array_foreach(json_object_get(m, "files"), i, f) {
        const char *name = json_string_value(json_object_get(f, "file"));
        if (name && !strcmp(name, file))
            hit = json_incref(f);
    }
    json_decref(m);
    return hit;
}

/* 0, or -1 when the file is missing, not in the manifest, or a line is malformed. */
static int load(const char *dir, const char *file, table *t)
{
    memset(t, 0, sizeof *t);
    if (!(t->entry = manifest_entry(dir, file)))
        return -1;
    json_t *fields = json_object_get(t->entry, "fields"), *fd;
    size_t i;
    int width[64], sgn[64];
    json_array_foreach(fields, i, fd) {
        const char *fmt = json_string_value(json_object_get(fd, "format"));
        t->name[t->n] = json_string_value(json_object_get(fd, "name"));
        width[t->n] = (int)json_integer_value(json_object_get(fd, "width"));
        sgn[t->n] = !strncmp(fmt, "SQ", 2) || !strcmp(fmt, "sint");
        t->n++;
    }
    char path[800], line[2048];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    long cap = 0;
    while (fgets(line, sizeof line, f)) {
        if (t->rows == cap) {
            cap = cap ? 2 * cap : 256;
            t->v = realloc(t->v, (size_t)cap * (size_t)t->n * sizeof *t->v);
        }
        char *p = line;
        for (int c = 0; c < t->n; c++) {
            char *end;
            uint64_t x = strtoull(p, &end, 16);
            if ((int)(end - p) != (width[c] + 3) / 4 || (*end != ' ' && *end != '\n')) {
                fclose(f);
                return -1;
            }
            if (sgn[c] && (x >> (width[c] - 1)) & 1)
                x |= ~0ull << width[c];
            t->v[t->rows * t->n + c] = (int64_t)x;
            p = end + 1;
        }
        t->rows++;
    }
    fclose(f);
    return 0;
}

static void unload(table *t)
{
    free(t->v);
    json_decref(t->entry);
}

#define AT(t, r, c) ((t)->v[(r) * (t)->n + (c)])

/* round_he(num / 2^s) computed independently of fxops.h (floor division, then the tie). */
static int64_t he(__int128 num, int s)
{
    __int128 d = (__int128)1 << s, q = num / d, r = num % d;
    if (r < 0) {
        q--;
        r += d;
    }
    if (2 * r > d || (2 * r == d && (q & 1)))
        q++;
    return (int64_t)q;
}

static __int128 tri_sum(const int64_t fr[3], const int64_t v[8])
{
    __int128 s = 0;
    for (int k = 0; k < 8; k++) {
        __int128 w = 1;
        for (int a = 0; a < 3; a++)
            w *= (k >> a) & 1 ? fr[a] : 32768 - fr[a];
        s += w * v[k];
    }
    return s;
}

TEST(vec_interp_recomputes)
{
    const char *dir = generate(&c5_vgen_interp);
    CHECK(dir);
    const char *files[] = {"interp.directed.hex", "interp." SCENE ".hex"};
    for (int fi = 0; fi < 2; fi++) {
        table t;
        CHECK_MSG(load(dir, files[fi], &t) == 0, "cannot read %s", files[fi]);
        CHECK_INT(t.n, 12);
        CHECK(t.rows > 0 && (fi == 0 || t.rows <= COUNT));
        int half = 0;
        for (long r = 0; r < t.rows; r++) {
            int64_t fr[3], v[8], x[8];
            int32_t v32[8];
            for (int a = 0; a < 3; a++)
                fr[a] = AT(&t, r, a);
            for (int k = 0; k < 8; k++)
                v32[k] = (int32_t)(v[k] = x[k] = AT(&t, r, 3 + k));
            int64_t out = AT(&t, r, 11);
            CHECK_INT(out, c5_interp_blend(fr, v32));
            CHECK_INT(out, he(tri_sum(fr, x), 37));
            half += (tri_sum(fr, x) & (((__int128)1 << 37) - 1)) == (__int128)1 << 36;
        }
        if (fi == 0)
            CHECK_MSG(half >= 4, "directed interp has %d exact rounding ties", half);
        unload(&t);
    }
}

TEST(vec_gradient_recomputes)
{
    const char *dir = generate(&c5_vgen_gradient);
    CHECK(dir);
    const char *files[] = {"gradient.directed.hex", "gradient." SCENE ".hex"};
    for (int fi = 0; fi < 2; fi++) {
        table t;
        CHECK_MSG(load(dir, files[fi], &t) == 0, "cannot read %s", files[fi]);
        CHECK_INT(t.n, 33);
        CHECK(t.rows > 0);
        int extremes = 0;
        for (long r = 0; r < t.rows; r++) {
            int64_t fr[3], gs[3], grad[3], d64[3][8];
            int32_t d[3][8];
            for (int a = 0; a < 3; a++) {
                fr[a] = AT(&t, r, a);
                for (int k = 0; k < 8; k++)
                    d64[a][k] = d[a][k] = (int32_t)AT(&t, r, 3 + 8 * a + k);
                gs[a] = AT(&t, r, 27 + a);
            }
            c5_grad_blend(fr, d, gs, grad);
            for (int a = 0; a < 3; a++) {
                CHECK_INT(AT(&t, r, 30 + a), grad[a]);
                CHECK_INT(AT(&t, r, 30 + a), he((__int128)he(tri_sum(fr, d64[a]), 37) * gs[a], 15));
            }
            extremes += AT(&t, r, 30) == 255 * 256 && AT(&t, r, 31) == 255 * 256;
        }
        if (fi == 0)
            CHECK_MSG(extremes >= 1, "directed gradient lacks the all +255 case");
        unload(&t);
    }
}

/* Loads SOURCE's table image into r->tf. */
static int load_tf(const char *dir, const char *source, c5_frame_regs *r)
{
    char name[256];
    snprintf(name, sizeof name, "classify.%s.tf.hex", source);
    table t;
    if (load(dir, name, &t) != 0 || t.rows != 256 || t.n != 4) {
        unload(&t);
        return -1;
    }
    for (int i = 0; i < 256; i++)
        for (int c = 0; c < 4; c++)
            r->tf[i][c] = (int32_t)AT(&t, i, c);
    unload(&t);
    return 0;
}

TEST(vec_classify_recomputes_from_its_table_image)
{
    const char *dir = generate(&c5_vgen_classify);
    CHECK(dir);
    const char *src[] = {"directed", SCENE};
    static c5_frame_regs r;
    for (int fi = 0; fi < 2; fi++) {
        memset(&r, 0, sizeof r);
        CHECK_MSG(load_tf(dir, src[fi], &r) == 0, "no table image for %s", src[fi]);
        char name[256], img[256];
        snprintf(name, sizeof name, "classify.%s.hex", src[fi]);
        snprintf(img, sizeof img, "classify.%s.tf.hex", src[fi]);
        table t;
        CHECK(load(dir, name, &t) == 0);
        const char *cfg = json_string_value(json_object_get(json_object_get(t.entry, "config"), "tf_image"));
        CHECK(cfg && !strcmp(cfg, img));
        int top = 0, crossings = 0;
        for (long k = 0; k < t.rows; k++) {
            int64_t value = AT(&t, k, 0), rgba[4];
            c5_classify(&r, value, rgba);
            int i = (int)(value >> 8) > 254 ? 254 : (int)(value >> 8);
            int64_t f = (int)(value >> 8) > 254 ? 256 : value & 255;
            for (int c = 0; c < 4; c++) {
                CHECK_INT(AT(&t, k, 1 + c), rgba[c]);
                CHECK_INT(AT(&t, k, 1 + c), he((__int128)r.tf[i][c] * 256 + (__int128)(r.tf[i + 1][c] - r.tf[i][c]) * f, 8));
            }
            if (value > 255 * 256) {
                top++;
                for (int c = 0; c < 4; c++)
                    CHECK_INT(AT(&t, k, 1 + c), r.tf[255][c]);
            }
            crossings += (value & 255) == 255;
        }
        if (fi == 0) {
            CHECK_MSG(top >= 2, "directed classify lacks the top clamp (value > 255.0)");
            CHECK_MSG(crossings >= 255, "directed classify has %d values just below an entry", crossings);
            int zero = 0, full = 0, steep = 0;
            for (int i = 0; i < 256; i++)
                for (int c = 0; c < 4; c++) {
                    zero += r.tf[i][c] == 0;
                    full += r.tf[i][c] == C5_ONE15;
                    steep += i < 255 && abs(r.tf[i + 1][c] - r.tf[i][c]) == C5_ONE15;
                }
            CHECK(zero > 0 && full > 0 && steep > 0);
        }
        unload(&t);
    }
}

/* Loads SOURCE's register and power table images into r. */
static int load_shade_regs(const char *dir, const char *source, c5_frame_regs *r)
{
    char name[256];
    table t;
    snprintf(name, sizeof name, "shade.%s.regs.hex", source);
    if (load(dir, name, &t) != 0 || t.rows != 4 + 8 * C5_MAX_LIGHTS) {
        unload(&t);
        return -1;
    }
    r->ka = AT(&t, 0, 0);
    r->kd = AT(&t, 1, 0);
    r->ks = AT(&t, 2, 0);
    r->n_lights = (int)AT(&t, 3, 0);
    for (int i = 0; i < C5_MAX_LIGHTS; i++) {
        c5_light_regs *l = &r->lights[i];
        const int64_t *s = &t.v[4 + 8 * i];
        l->kind = (int)s[0];
        for (int a = 0; a < 3; a++) {
            l->pos[a] = s[1 + a];
            l->dir[a] = s[4 + a];
        }
        l->intensity = s[7];
    }
    unload(&t);
    snprintf(name, sizeof name, "shade.%s.pow.hex", source);
    if (load(dir, name, &t) != 0 || t.rows != (1 << C5_POW_BITS) + 1) {
        unload(&t);
        return -1;
    }
    for (int i = 0; i <= 1 << C5_POW_BITS; i++)
        r->pow_tab[i] = (int32_t)AT(&t, i, 0);
    unload(&t);
    return 0;
}

TEST(vec_shade_recomputes_from_its_register_images)
{
    const char *dir = generate(&c5_vgen_shade);
    CHECK(dir);
    const char *src[] = {"directed", "bright", SCENE};
    const int lights[] = {3, 1, 2};
    static c5_frame_regs r;
    for (int fi = 0; fi < 3; fi++) {
        memset(&r, 0, sizeof r);
        CHECK_MSG(load_shade_regs(dir, src[fi], &r) == 0, "no register images for %s", src[fi]);
        CHECK(r.n_lights == lights[fi]);
        char name[256];
        snprintf(name, sizeof name, "shade.%s.hex", src[fi]);
        table t;
        CHECK(load(dir, name, &t) == 0);
        CHECK_INT(t.n, 16);
        CHECK(t.rows > 0);
        int zero = 0, sat3 = 0, sat5 = 0, flipped = 0, faded = 0;
        long whole = -1; /* the directed row of gradient (-256, 0, 0) */
        for (long k = 0; k < t.rows && fi == 0; k++)
            if (AT(&t, k, 0) == -256 && AT(&t, k, 1) == 0 && AT(&t, k, 2) == 0 && whole < 0)
                whole = k;
        for (long k = 0; k < t.rows; k++) {
            c5_sample smp = {0};
            int64_t rgba[4] = {AT(&t, k, 3), AT(&t, k, 4), AT(&t, k, 5), C5_ONE15}, gpos[3], d[3], out[3];
            for (int a = 0; a < 3; a++) {
                smp.grad[a] = AT(&t, k, a);
                gpos[a] = AT(&t, k, 6 + a);
                d[a] = AT(&t, k, 9 + a);
            }
            uint64_t sat = 0;
            c5_shade(&r, &smp, rgba, gpos, d, out, &sat);
            for (int c = 0; c < 3; c++)
                CHECK_MSG(AT(&t, k, 12 + c) == out[c], "%s line %ld: channel %d %lld, recomputed %lld", name, k + 1, c,
                          (long long)AT(&t, k, 12 + c), (long long)out[c]);
            CHECK_INT(AT(&t, k, 15), sat);
            int64_t m2 = smp.grad[0] * smp.grad[0] + smp.grad[1] * smp.grad[1] + smp.grad[2] * smp.grad[2];
            if (m2 == 0) { /* ambient only: c * ka */
                zero++;
                for (int c = 0; c < 3; c++)
                    CHECK_INT(AT(&t, k, 12 + c), he((__int128)rgba[c] * r.ka, 15));
            }
            /* Along -x below |g| = 1/2 the lights' share is 4 |g|^2 of the whole one's (the
             * row of (-256, 0, 0), the same other inputs, nothing clamped), within the
             * roundings of k, ks and the channel. */
            if (fi == 0 && whole >= 0 && k < whole && m2 > 0 && m2 < 16384 && smp.grad[1] == 0 && smp.grad[2] == 0 &&
                smp.grad[0] < 0) {
                faded++;
                for (int c = 0; c < 3; c++) {
                    double amb = (double)he((__int128)rgba[c] * r.ka, 15), full = (double)AT(&t, whole, 12 + c);
                    double want = amb + (double)m2 / 16384 * (full - amb);
                    CHECK_MSG(fabs((double)AT(&t, k, 12 + c) - want) <= 2, "line %ld channel %d: %lld, fade wants %.1f",
                              k + 1, c, (long long)AT(&t, k, 12 + c), want);
                }
            }
            sat5 += sat == 5; /* light_term k and ks, then the three channels */
            sat3 += out[0] == 65535 && out[1] == 65535 && out[2] == 65535 && sat >= 3; /* every channel clamped */
            flipped += smp.grad[2] == 256 && d[2] < 0 && smp.grad[0] == 0 && smp.grad[1] == 0;
        }
        if (fi == 0)
            CHECK_MSG(zero >= 2 && faded >= 4 && sat3 >= 1 && flipped == 1,
                      "directed shade: %d zero-gradient, %d faded, %d saturated, %d flipped", zero, faded, sat3, flipped);
        if (fi == 1)
            CHECK_MSG(sat5 >= 1, "bright shade: no vector clamps all five (%d)", sat5);
        unload(&t);
    }
}

TEST(vec_composite_recomputes)
{
    const char *dir = generate(&c5_vgen_composite);
    CHECK(dir);
    const char *files[] = {"composite.directed.hex", "composite." SCENE ".hex"};
    for (int fi = 0; fi < 2; fi++) {
        table t;
        CHECK(load(dir, files[fi], &t) == 0);
        CHECK_INT(t.n, 17);
        CHECK(t.rows > 0);
        int exact = 0, shadow = 0, clamp = 0;
        for (long k = 0; k < t.rows; k++) {
            c5_frame_regs r;
            r.a_max = AT(&t, k, 10);
            c5_bray ray = {.w = AT(&t, k, 0), .opa = AT(&t, k, 1), .rgb = {AT(&t, k, 2), AT(&t, k, 3), AT(&t, k, 4)}};
            int64_t alpha = AT(&t, k, 5), c[3] = {AT(&t, k, 6), AT(&t, k, 7), AT(&t, k, 8)};
            int sh = (int)AT(&t, k, 9);
            uint64_t sat = 0;
            int done = c5_composite(&r, &ray, alpha, sh ? NULL : c, &sat);
            for (int ch = 0; ch < 3; ch++)
                CHECK_INT(AT(&t, k, 11 + ch), ray.rgb[ch]);
            CHECK_INT(AT(&t, k, 14), ray.opa);
            CHECK_INT(AT(&t, k, 15), done);
            CHECK_INT(AT(&t, k, 16), sat);
            /* independently: A' = A + round(T alpha), done = A' >= a_max */
            int64_t opa = AT(&t, k, 1) + he((__int128)(C5_ONE15 - AT(&t, k, 1)) * alpha, 15);
            CHECK_INT(AT(&t, k, 14), opa);
            CHECK_INT(AT(&t, k, 15), opa >= r.a_max);
            exact += opa == r.a_max && done;
            if (sh) {
                shadow++;
                for (int ch = 0; ch < 3; ch++)
                    CHECK_INT(AT(&t, k, 11 + ch), AT(&t, k, 2 + ch));
            }
            clamp += AT(&t, k, 16) == 3 && AT(&t, k, 11) == C5_RGB_MAX;
        }
        if (fi == 0)
            CHECK_MSG(exact >= 5 && shadow >= 2 && clamp >= 1, "directed composite: %d exact, %d shadow, %d clamped",
                      exact, shadow, clamp);
        unload(&t);
    }
}

TEST(vec_traverse_recomputes)
{
    const char *dir = generate(&c5_vgen_traverse);
    CHECK(dir);
    const char *files[] = {"traverse.directed.hex", "traverse." SCENE ".hex"};
    for (int fi = 0; fi < 2; fi++) {
        table t;
        CHECK(load(dir, files[fi], &t) == 0);
        CHECK_INT(t.n, 23);
        CHECK(t.rows > 0);
        int actions[3] = {0}, life0 = 0, cut = 0, longest = 0, out_faces = 0, unbounded = 0;
        for (long k = 0; k < t.rows; k++) {
            c5_trav_in in;
            c5_trav_out o;
            for (int a = 0; a < 3; a++) {
                in.pos[a] = AT(&t, k, a);
                in.S[a] = AT(&t, k, 3 + a);
                in.lo[a] = (int)AT(&t, k, 7 + a);
                in.hi[a] = (int)AT(&t, k, 10 + a);
                in.dims[a] = (int)AT(&t, k, 13 + a);
            }
            in.lifetime = (uint32_t)AT(&t, k, 6);
            in.block_empty = (int)AT(&t, k, 16);
            c5_trav_step(&in, &o);
            CHECK_INT(AT(&t, k, 17), o.action);
            CHECK_INT(AT(&t, k, 18), o.leaped);
            for (int a = 0; a < 3; a++)
                CHECK_INT(AT(&t, k, 19 + a), o.pos[a]);
            CHECK_INT(AT(&t, k, 22), o.lifetime);
            CHECK(o.action >= 0 && o.action <= 2);
            actions[o.action]++;
            /* independently: a step moves pos by exactly leaped (or 1) times S */
            int64_t n = o.action == C5_TRAV_SAMPLE ? 1 : o.leaped;
            for (int a = 0; a < 3; a++)
                CHECK_INT(o.pos[a], in.pos[a] + n * in.S[a]);
            if (in.lifetime != C5_LIFE_NONE)
                CHECK_INT(o.lifetime, in.lifetime - n);
            life0 += in.lifetime == 0 && o.action == C5_TRAV_LEAVE;
            cut += o.action == C5_TRAV_LEAP && in.lifetime != C5_LIFE_NONE && o.lifetime == 0;
            longest += o.leaped == 1 << 18;
            unbounded += in.lifetime == C5_LIFE_NONE && o.action != C5_TRAV_LEAVE;
            if (o.action == C5_TRAV_LEAP)
                for (int a = 0; a < 3; a++)
                    out_faces += o.pos[a] < 0 || o.pos[a] >= (int64_t)in.dims[a] << 15;
        }
        if (fi == 0)
            CHECK_MSG(actions[0] && actions[1] && actions[2] && life0 >= 2 && cut >= 2 && longest == 1 && unbounded &&
                          out_faces >= 6,
                      "directed traverse: actions %d %d %d, lifetime 0 %d, cut %d, longest %d, leaps out %d",
                      actions[0], actions[1], actions[2], life0, cut, longest, out_faces);
        else
            CHECK_MSG(actions[0] > 0, "no sample step tapped in the scene");
        unload(&t);
    }
}

/* A value its field cannot carry fails the set, naming file, line, field and value, where
 * the digits alone would keep its low bits: an unsigned 10-bit field at 1024, a signed
 * 8-bit one at -129; the extremes that fit pass. */
TEST(vec_value_that_does_not_fit_fails_the_set)
{
    static const c5_vfield fl[] = {{"u", 10, 0, "uint"}, {"s", 8, 0, "SQ3.4"}};
    static const c5_vblock b = {"fit", "range check", fl, 2};
    char dir[600];
    const int64_t cases[][3] = {{1023, -128, 0}, {0, 127, 0}, {1024, 0, 1}, {0, -129, 1}, {0, 128, 1}};
    for (int i = 0; i < 5; i++) {
        c5_err err = {0};
        c5_vset set;
        snprintf(dir, sizeof dir, "%s/fit%d", c5t_tmpdir(), i); /* a failed set leaves no manifest */
        CHECK(c5_vset_init(&set, dir, 1, 1, &err) == 0);
        c5_vfile *f = c5_vfile_open(&set, &b, "directed", NULL, NULL);
        CHECK(f != NULL);
        c5_vfile_u(f, (uint64_t)cases[i][0]);
        c5_vfile_s(f, cases[i][1]);
        c5_vfile_end(f);
        c5_vfile_close(f);
        int rc = c5_vset_finish(&set, NULL);
        CHECK_MSG((rc != 0) == (cases[i][2] != 0), "case %d: finish %d", i, rc);
        if (cases[i][2])
            CHECK_MSG(strstr(err.msg, "fit.directed.hex line 1: ") && strstr(err.msg, "does not fit its"), "%s",
                      err.msg);
    }
}
