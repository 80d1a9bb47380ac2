/* The model's host-speed paths change no bit. Without taps the processor skips work no bit
 * depends on (the gradient of a sample that does not shade; trav_step's checks on steps
 * known to sample, processor.c samples_ahead); the geometry takes 64-bit paths for small
 * operands (geom.h). Whole frames of every built-in scene with no taps, with every tap, and
 * with every tap but the traversal's, compared in every counter, cycle count and the image,
 * and the datapath's transactions of the last two compared call by call; then the 64-bit
 * geometry against the 128-bit on random and boundary operands; the RDRAM load (rows
 * copied whole inside the grid) against the clamped voxel, byte by byte. */
#include <stdint.h>
#include <string.h>

#include "board.h"
#include "board_equal.h"
#include "builtin_scenes.h"
#include "cells.h"
#include "geom.h"
#include "harness.h"
#include "rng.h"

/* ---- whole frames ----------------------------------------------------------------- */

/* FNV-1a over every datapath transaction the taps see, and how many. */
typedef struct {
    uint64_t h, calls, traverse_calls;
} seen;

static void mix(seen *s, const void *p, size_t n)
{
    const uint8_t *b = p;
    for (size_t i = 0; i < n; i++)
        s->h = (s->h ^ b[i]) * 0x100000001b3ull;
    s->calls++;
}

static void t_interp(void *ctx, const c5_corners *k, int64_t value)
{
    int64_t w[12] = {k->frac[0], k->frac[1], k->frac[2], value};
    for (int j = 0; j < 8; j++)
        w[4 + j] = k->v[j];
    mix(ctx, w, sizeof w);
}

static void t_gradient(void *ctx, const c5_corners *k, const int64_t gs[3], const int64_t grad[3])
{
    int64_t w[30] = {gs[0], gs[1], gs[2], grad[0], grad[1], grad[2]};
    for (int a = 0; a < 3; a++)
        for (int j = 0; j < 8; j++)
            w[6 + 8 * a + j] = k->d[a][j];
    mix(ctx, w, sizeof w);
}

static void t_classify(void *ctx, int64_t value, const int64_t rgba[4])
{
    int64_t w[5] = {value, rgba[0], rgba[1], rgba[2], rgba[3]};
    mix(ctx, w, sizeof w);
}

static void t_shade(void *ctx, const c5_shade_io *io)
{
    int64_t w[17] = {io->sat};
    for (int a = 0; a < 3; a++) {
        w[1 + a] = io->grad[a];
        w[4 + a] = io->gpos[a];
        w[7 + a] = io->dir[a];
        w[10 + a] = io->rgb[a];
    }
    for (int ch = 0; ch < 4; ch++)
        w[13 + ch] = io->rgba[ch];
    mix(ctx, w, sizeof w);
}

static void t_composite(void *ctx, const c5_composite_io *io)
{
    int64_t w[15] = {io->w, io->opa, io->alpha, io->a_max, io->shadow, io->opa_out, io->done, io->sat};
    for (int ch = 0; ch < 3; ch++) {
        w[8 + ch] = io->rgb[ch];
        w[11 + ch] = io->c[ch];
    }
    w[14] = io->rgb_out[0] + 3 * io->rgb_out[1] + 7 * io->rgb_out[2];
    mix(ctx, w, sizeof w);
}

static void t_traverse(void *ctx, const c5_trav_in *in, const c5_trav_out *out)
{
    (void)in;
    (void)out;
    ((seen *)ctx)->traverse_calls++;
}

/* which: 0 no taps, 1 every datapath tap, 2 every one but the traversal's. */
static int render(const c5_scene *s, const c5_supervol *sv, c5_board_opts o, int which, c5_image *img,
                  c5_board_stats *st, seen *sn)
{
    memset(sn, 0, sizeof *sn);
    sn->h = 0xcbf29ce484222325ull;
    c5_taps taps = {.ctx = sn, .interp = t_interp, .gradient = t_gradient, .classify = t_classify,
                    .shade = t_shade, .composite = t_composite, .traverse = which == 1 ? t_traverse : NULL};
    o.taps = which ? &taps : NULL;
    c5_err err;
    if (c5_board_render(s, sv, 0, &o, img, st, &err) != 0) {
        c5t_failf(__FILE__, __LINE__, "render: %s", err.msg);
        return -1;
    }
    return 0;
}

TEST(board_fast_paths_same_bits_every_builtin_scene)
{
    const c5_board_opts variants[] = {
        {.cells = {2, 2, 2}},
        {.cells = {0, 0, 0}}, /* the fewest cells: one up to 256 voxels a side */
        {.cells = {3, 2, 4}, .key = C5_KEY_FIFO},
    };
    uint64_t samples = 0, traverse_calls = 0;
    for (const c5_builtin_scene *bs = c5_builtin_scenes; bs->name; bs++) {
        c5_scene s;
        c5_supervol sv;
        c5_err err;
        CHECK_MSG(c5_scene_parse(bs->json, NULL, "test", &s, &err) == 0 && c5_supervol_build(&s, &sv, &err) == 0,
                  "%s: %s", bs->name, err.msg);
        s.render.width = s.render.height = 64;
        /* the variants, then the first with a point light at the camera's target casting
         * shadows (its shadow rays end at the light, in the volume: their lifetimes count),
         * then without lights (rays that sample and do not shade) */
        size_t n_variants = sizeof variants / sizeof variants[0];
        for (size_t v = 0; v < n_variants + 2; v++) {
            c5_scene sc = s;
            if (v == n_variants)
                sc.lights[0] = (c5_light){.kind = C5_LIGHT_POINT, .position = s.camera.target, .intensity = 1,
                                                .shadows = 1};
            if (v == n_variants + 1)
                sc.n_lights = 0;
            c5_image img[3];
            c5_board_stats st[3];
            seen sn[3];
            int n = 0;
            while (n < 3 && render(&sc, &sv, variants[v < n_variants ? v : 0], n, &img[n], &st[n], &sn[n]) == 0)
                n++;
            int ok = n == 3;
            char what[3][96];
            for (int i = 1; ok && i < 3; i++) {
                snprintf(what[i], sizeof what[i], "%s variant %zu%s, taps %d against none", bs->name,
                         v < n_variants ? v : 0, v < n_variants ? "" : v == n_variants ? " shadowed" : " unlit", i);
                ok = c5t_board_stats_equal(what[i], &st[0], &st[i]) == 0;
                if (ok && !c5t_same_image(&img[0], &img[i])) {
                    c5t_failf(__FILE__, __LINE__, "%s: images differ", what[i]);
                    ok = 0;
                }
            }
            if (ok && (sn[1].h != sn[2].h || sn[1].calls != sn[2].calls)) {
                c5t_failf(__FILE__, __LINE__, "%s variant %zu: datapath transactions differ with the traverse tap",
                          bs->name, v);
                ok = 0;
            }
            if (ok) {
                samples += st[0].samples;
                traverse_calls += sn[1].traverse_calls;
            }
            for (int i = 0; i < n; i++)
                c5_image_free(&img[i]);
            if (!ok) {
                c5_supervol_free(&sv);
                return;
            }
        }
        c5_supervol_free(&sv);
    }
    /* the frames sample, and far more steps than cells visit: runs of known samples exist */
    CHECK_MSG(samples > 100000 && traverse_calls > samples, "samples %llu, traversal steps %llu",
              (unsigned long long)samples, (unsigned long long)traverse_calls);
}

/* The Cell Tree's tags timed (cube5 schedule's build host_s) and not: the same frame, and a
 * tag time only where asked for. */
TEST(board_tree_timing_changes_no_bit)
{
    c5_scene s;
    c5_supervol sv;
    c5_err err;
    CHECK_MSG(c5_scene_parse(c5_builtin_scenes[0].json, NULL, "test", &s, &err) == 0 &&
                  c5_supervol_build(&s, &sv, &err) == 0, "%s", err.msg);
    s.render.width = s.render.height = 48;
    c5_image img[2];
    c5_board_stats st[2];
    seen sn[2];
    for (int timed = 0; timed < 2; timed++)
        CHECK(render(&s, &sv, (c5_board_opts){.cells = {2, 2, 2}, .time_tree = timed}, 0, &img[timed], &st[timed],
                     &sn[timed]) == 0);
    CHECK(c5t_board_stats_equal("timed against not", &st[0], &st[1]) == 0);
    CHECK(c5t_same_image(&img[0], &img[1]));
    CHECK(st[1].tree_tags > 0);
    CHECK_MSG(st[0].tree_wall_s == 0 && st[1].tree_wall_s > 0, "tree_wall_s %g untimed, %g timed", st[0].tree_wall_s,
              st[1].tree_wall_s);
    for (int i = 0; i < 2; i++)
        c5_image_free(&img[i]);
    c5_supervol_free(&sv);
}

/* ---- the geometry's 64-bit paths -------------------------------------------------- */

/* A component of 0 to 35 bits of either sign, now and then exactly at a boundary of the
 * 64-bit paths (2^30 - 1, 2^30, 2^30 + 1). */
static int64_t component(uint64_t *s)
{
    uint64_t r = c5_splitmix64(s);
    int bits = (int)(r % 36);
    int64_t v = bits ? (int64_t)((r >> 8) & (((uint64_t)1 << bits) - 1)) : 0;
    switch ((r >> 60) & 7) {
    case 0: v = (int64_t)1 << 30; break;
    case 1: v = ((int64_t)1 << 30) + 1; break;
    case 2: v = ((int64_t)1 << 30) - 1; break;
    default: break;
    }
    return (r >> 59) & 1 ? -v : v;
}

TEST(geom_normalize_and_dot_64_bit_paths_equal_the_128_bit)
{
    uint64_t s = 0x6E0;
    long fast = 0;
    for (long i = 0; i < 400000; i++) {
        int64_t v[3] = {component(&s), component(&s), component(&s)}, w[3];
        int64_t a[3], b[3];
        for (int k = 0; k < 3; k++)
            w[k] = component(&s) >> (c5_splitmix64(&s) % 24); /* unit-vector sizes too */
        int64_t la = c5_geom_normalize(v, a), lb = c5_geom_normalize_wide(v, b);
        CHECK_MSG(la == lb && a[0] == b[0] && a[1] == b[1] && a[2] == b[2],
                  "normalize (%lld %lld %lld): %lld (%lld %lld %lld) vs %lld (%lld %lld %lld)", (long long)v[0],
                  (long long)v[1], (long long)v[2], (long long)la, (long long)a[0], (long long)a[1],
                  (long long)a[2], (long long)lb, (long long)b[0], (long long)b[1], (long long)b[2]);
        CHECK_MSG(c5_geom_dot14(v, w) == c5_geom_dot14_wide(v, w), "dot14 (%lld %lld %lld).(%lld %lld %lld)",
                  (long long)v[0], (long long)v[1], (long long)v[2], (long long)w[0], (long long)w[1],
                  (long long)w[2]);
        CHECK(c5_geom_dot14(a, w) == c5_geom_dot14_wide(a, w));
        fast += c5_geom_small3(v, 30);
    }
    CHECK(fast > 10000 && fast < 390000); /* both paths taken */
    /* the edges of the 64-bit range: every component at -2^30 or 2^30 - 1 */
    for (int m = 0; m < 8; m++) {
        int64_t v[3], a[3], b[3];
        for (int k = 0; k < 3; k++)
            v[k] = (m >> k) & 1 ? -((int64_t)1 << 30) : ((int64_t)1 << 30) - 1;
        CHECK(c5_geom_small3(v, 30));
        v[m % 3] = (m >> (m % 3)) & 1 ? -((int64_t)1 << 30) - 1 : (int64_t)1 << 30;
        CHECK(!c5_geom_small3(v, 30));
        v[m % 3] = (m >> (m % 3)) & 1 ? -((int64_t)1 << 30) : ((int64_t)1 << 30) - 1;
        CHECK_INT(c5_geom_normalize(v, a), c5_geom_normalize_wide(v, b));
        CHECK(a[0] == b[0] && a[1] == b[1] && a[2] == b[2]);
        CHECK_INT(c5_geom_dot14(v, v), c5_geom_dot14_wide(v, v));
    }
    int64_t zero[3] = {0, 0, 0}, out[3] = {1, 1, 1};
    CHECK_INT(c5_geom_normalize(zero, out), 0);
    CHECK(out[0] == 0 && out[1] == 0 && out[2] == 0);
}

TEST(geom_from_voxel_64_bit_path_equals_the_128_bit)
{
    c5_frame_regs r;
    memset(&r, 0, sizeof r);
    uint64_t s = 0xF0;
    for (long i = 0; i < 200000; i++) {
        int64_t p[3], g[3];
        for (int a = 0; a < 3; a++) {
            r.gscale[a] = (int64_t)(c5_splitmix64(&s) % ((uint64_t)256 << 16));
            uint64_t x = c5_splitmix64(&s);
            int bits = (int)(x % 44);
            p[a] = (int64_t)((x >> 8) & (((uint64_t)1 << bits) - 1));
            if ((x >> 62) == 0)
                p[a] = (int64_t)1 << 38;
            if ((x >> 61) & 1)
                p[a] = -p[a];
        }
        c5_geom_from_voxel(&r, p, g);
        for (int a = 0; a < 3; a++) {
            __int128 prod = (__int128)p[a] * r.gscale[a];
            CHECK_MSG(g[a] == c5_rshift128_he(prod, 16), "from_voxel %lld * %lld", (long long)p[a],
                      (long long)r.gscale[a]);
        }
    }
}

/* ---- the RDRAM load: rows copied, ghosts clamped ---------------------------------- */

/* Every byte of every cell's RDRAM image (the cell and its ghost layers, beyond the grid's
 * faces too) is the clamped voxel c5_supervol_at reads, for splits down to cells of one
 * or two voxels. */
TEST(rdram_load_every_byte_is_the_clamped_voxel)
{
    /* A grid whose voxels differ from their neighbours everywhere, faces included. */
    c5_supervol sv;
    memset(&sv, 0, sizeof sv);
    sv.dims[0] = 21, sv.dims[1] = 17, sv.dims[2] = 13;
    sv.spacing = v3(1, 1, 1);
    uint8_t vox[21 * 17 * 13];
    for (size_t i = 0; i < sizeof vox; i++)
        vox[i] = (uint8_t)(i * 37 + i / 21 * 11 + 1);
    sv.v = vox;
    c5_err err;
    static const int splits[][3] = {{1, 1, 1}, {2, 1, 1}, {3, 2, 2}, {7, 5, 4}, {21, 17, 13}};
    uint8_t nz[256];
    memset(nz, 1, sizeof nz);
    long bytes = 0;
    for (size_t si = 0; si < sizeof splits / sizeof splits[0]; si++) {
        c5_cells cl;
        c5_rdram m = {.cell = -1};
        CHECK(c5_cells_init(&cl, &sv, splits[si], nz, &err) == 0);
        for (int cell = 0; cell < cl.count; cell++) {
            CHECK(c5_rdram_load(&m, &cl, &sv, cell, &err) == 0);
            size_t o = 0;
            for (int z = 0; z < m.ext[2]; z++)
                for (int y = 0; y < m.ext[1]; y++)
                    for (int x = 0; x < m.ext[0]; x++, o++) {
                        unsigned want = c5_supervol_at(&sv, m.org[0] + x, m.org[1] + y, m.org[2] + z);
                        CHECK_MSG(m.v[o] == want, "split %zu cell %d (%d %d %d): %u, want %u", si, cell,
                                  m.org[0] + x, m.org[1] + y, m.org[2] + z, m.v[o], want);
                    }
            bytes += (long)o;
        }
        c5_rdram_free(&m);
        c5_cells_free(&cl);
    }
    CHECK(bytes > 21 * 17 * 13 * 5);
}
