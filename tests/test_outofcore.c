/* The out-of-core super volume (docs/out-of-core.md) against the resident one: every voxel,
 * every box (inside, across and outside the grid), every source kind (raw uint8/uint16 either
 * endianness, NRRD attached, detached and gzip, generators, several sources over the fill),
 * cref's image for 1 and 3 threads and the board model's image and counters, all with a brick
 * cache so small that it evicts all the time. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <teem/nrrd.h>

#include "board.h"
#include "board_equal.h"
#include "cells.h"
#include "cref.h"
#include "generators.h"
#include "harness.h"
#include "rng.h"
#include "supervol.h"
#include "voxsrc.h"

/* Budgets below each grid's voxel count, so that it is out of core, with a cache of one
 * brick (37x29x23 grids), two (the render scene, 70x37x30) or three (70x45x33). */
#define BRICK_BYTES ((size_t)1 << (3 * C5_BRICK_LOG2))
static size_t tiny_budget = 20000;
#define HUGE_BUDGET ((size_t)1 << 34)
/* what a scene with a volume needs besides it */
#define TAIL                                                                                                           \
    "'transfer_function': {'opacity': [[0, 0], [255, 1]], 'color': [[0, 1, 1, 1], [255, 1, 1, 1]]},"                   \
    " 'camera': {'eye': [0, 0, 100], 'target': [0, 0, 0], 'up': [0, 1, 0]}"


/* A deterministic pattern with structure at every scale (not a ramp a wrong stride hides). */
static unsigned pattern(size_t i, uint64_t seed)
{
    uint64_t s = seed ^ (i * 0x9E3779B97F4A7C15ull);
    return (unsigned)(c5_splitmix64(&s) >> 40);
}

typedef struct {
    c5_scene s;
    c5_supervol res, ooc;
} pair;

/* The scene built twice: resident and out of core (TINY_BUDGET). */
static int build_pair(const char *json, pair *p)
{
    c5_err err;
    memset(p, 0, sizeof *p);
    if (c5_scene_parse(c5t_json(json), c5t_tmpdir(), "test", &p->s, &err) != 0 ||
        c5_supervol_build_budget(&p->s, HUGE_BUDGET, &p->res, &err) != 0 ||
        c5_supervol_build_budget(&p->s, tiny_budget, &p->ooc, &err) != 0) {
        fprintf(stderr, "build: %s\n", err.msg);
        return -1;
    }
    return 0;
}

static void pair_free(pair *p)
{
    c5_supervol_free(&p->res);
    c5_supervol_free(&p->ooc);
}

/* Every voxel, and boxes of every kind, out of core against resident; 0 when all agree. */
static int same_grids(const c5_supervol *res, const c5_supervol *ooc)
{
    if (!res->v || ooc->v || !ooc->store)
        return fprintf(stderr, "same_grids: expected one resident and one out-of-core grid\n"), -1;
    for (int a = 0; a < 3; a++)
        if (res->dims[a] != ooc->dims[a])
            return -1;
    long n[3] = {(long)res->dims[0], (long)res->dims[1], (long)res->dims[2]};
    for (long k = -2; k < n[2] + 2; k++)
        for (long j = -2; j < n[1] + 2; j++)
            for (long i = -2; i < n[0] + 2; i++)
                if (c5_supervol_at(ooc, i, j, k) != c5_supervol_at(res, i, j, k)) {
                    fprintf(stderr, "voxel %ld %ld %ld: %u != %u\n", i, j, k, c5_supervol_at(ooc, i, j, k),
                            c5_supervol_at(res, i, j, k));
                    return -1;
                }
    uint64_t st = 11;
    size_t cap = (size_t)(n[0] + 80) * (size_t)(n[1] + 80) * (size_t)(n[2] + 80);
    uint8_t *a = malloc(cap), *b = malloc(cap);
    int rc = a && b ? 0 : -1;
    for (int t = 0; t < 300 && rc == 0; t++) {
        long lo[3], hi[3];
        for (int ax = 0; ax < 3; ax++) {
            /* small boxes (the brick cache), large ones (straight to the sources), some
             * reaching past the grid (clamp-to-edge) */
            long w = t % 3 == 0 ? 1 + (long)(c5_uniform(&st) * 4) : 1 + (long)(c5_uniform(&st) * (double)(n[ax] + 30));
            lo[ax] = -20 + (long)(c5_uniform(&st) * (double)(n[ax] + 30));
            hi[ax] = lo[ax] + w;
        }
        c5_err e1, e2;
        if (c5_supervol_read_box(ooc, lo, hi, a, &e1) != 0 || c5_supervol_read_box(res, lo, hi, b, &e2) != 0) {
            rc = -1;
            break;
        }
        size_t o = 0;
        for (long z = lo[2]; z < hi[2] && rc == 0; z++)
            for (long y = lo[1]; y < hi[1] && rc == 0; y++)
                for (long x = lo[0]; x < hi[0]; x++, o++)
                    if (a[o] != c5_supervol_at(res, x, y, z) || b[o] != a[o]) {
                        fprintf(stderr, "box %ld..%ld %ld..%ld %ld..%ld: voxel %ld %ld %ld differs\n", lo[0], hi[0],
                                lo[1], hi[1], lo[2], hi[2], x, y, z);
                        rc = -1;
                        break;
                    }
    }
    free(a);
    free(b);
    return rc;
}

/* ---- generators per box --------------------------------------------------------------- */

TEST(ooc_generators_per_box_equal_whole)
{
    const c5_generator gens[] = {C5_GEN_MARSCHNER_LOBB, C5_GEN_BLOBS, C5_GEN_CLOUD,
                                 C5_GEN_SPHERE, C5_GEN_CONSTANT, C5_GEN_RAMP};
    for (size_t g = 0; g < sizeof gens / sizeof gens[0]; g++) {
        c5_volume_desc d = {.kind = C5_SRC_GENERATOR, .generator = gens[g], .gen_dims = {37, 29, 23}, .f_m = 6,
                            .alpha = 0.25, .radius = 0.4, .value = 200, .count = 12, .seed = 5, .axis = (int)g % 3};
        uint8_t whole[37 * 29 * 23], box[37 * 29 * 23];
        c5_generate(&d, whole);
        c5_gen_state gs;
        c5_gen_prepare(&d, &gs);
        uint64_t st = g + 1;
        for (int t = 0; t < 40; t++) {
            size_t lo[3], hi[3];
            for (int a = 0; a < 3; a++) {
                lo[a] = (size_t)(c5_uniform(&st) * (double)d.gen_dims[a]);
                hi[a] = lo[a] + 1 + (size_t)(c5_uniform(&st) * (double)(d.gen_dims[a] - lo[a]));
            }
            size_t sy = hi[0] - lo[0] + 3, sz = sy * (hi[1] - lo[1]); /* a row stride wider than the box */
            c5_generate_box(&d, &gs, lo, hi, box, sy, sz);
            for (size_t z = lo[2]; z < hi[2]; z++)
                for (size_t y = lo[1]; y < hi[1]; y++)
                    for (size_t x = lo[0]; x < hi[0]; x++)
                        CHECK_MSG(box[(z - lo[2]) * sz + (y - lo[1]) * sy + x - lo[0]] ==
                                      whole[(z * 29 + y) * 37 + x],
                                  "%s: voxel %zu %zu %zu of box %d", c5_generator_name(gens[g]), x, y, z, t);
        }
    }
}

/* ---- several sources over the fill ------------------------------------------------------ */

TEST(ooc_sources_offsets_fill_every_voxel_and_box)
{
    uint8_t raw[37 * 29 * 23];
    for (size_t i = 0; i < sizeof raw; i++)
        raw[i] = (uint8_t)pattern(i, 1);
    CHECK(c5t_write_file(c5t_path(0, "a_37x29x23_uint8.raw"), NULL, raw, sizeof raw) == 0);
    pair p;
    tiny_budget = 3 * BRICK_BYTES;
    CHECK(build_pair("{'grid': {'dims': [70, 45, 33], 'fill': 17},"
                     " 'volumes': [{'file': 'a_37x29x23_uint8.raw', 'offset': [3, 2, 1]},"
                     "             {'generator': 'cloud', 'dims': [20, 20, 20], 'seed': 4, 'offset': [30, 10, 5]},"
                     "             {'generator': 'ramp', 'dims': [9, 40, 7], 'axis': 1, 'offset': [61, 5, 26]}],"
                     " " TAIL "}",
                     &p) == 0);
    CHECK_INT(p.ooc.dims[0], 70);
    /* the grid by hand: the fill, then each volume pasted in the scene's order (the cloud
     * covers part of the file) */
    static uint8_t want[70 * 45 * 33], cloud[20 * 20 * 20], ramp[9 * 40 * 7];
    memset(want, 17, sizeof want);
    c5_generate(&p.s.volumes[1], cloud);
    c5_generate(&p.s.volumes[2], ramp);
    const struct {
        const uint8_t *v;
        size_t d[3], o[3];
    } put[3] = {{raw, {37, 29, 23}, {3, 2, 1}}, {cloud, {20, 20, 20}, {30, 10, 5}}, {ramp, {9, 40, 7}, {61, 5, 26}}};
    for (int i = 0; i < 3; i++)
        for (size_t z = 0; z < put[i].d[2]; z++)
            for (size_t y = 0; y < put[i].d[1]; y++)
                for (size_t x = 0; x < put[i].d[0]; x++)
                    want[((z + put[i].o[2]) * 45 + y + put[i].o[1]) * 70 + x + put[i].o[0]] =
                        put[i].v[(z * put[i].d[1] + y) * put[i].d[0] + x];
    CHECK(!memcmp(p.res.v, want, sizeof want));
    CHECK(same_grids(&p.res, &p.ooc) == 0);
    c5_supervol_cache_stats cs;
    c5_supervol_cache_stats_get(&p.ooc, &cs);
    tiny_budget = 20000;
    CHECK_INT(cs.bricks, 3);
    CHECK_MSG(cs.misses > 12, "%llu misses for 12 bricks: no eviction tested", cs.misses);
    CHECK(!strcmp(p.ooc.source_label[1], p.res.source_label[1]));
    pair_free(&p);
}

/* ---- uint16 windows, either byte order ----------------------------------------------- */

TEST(ooc_uint16_auto_and_explicit_window)
{
    enum { N = 37 * 29 * 23 };
    static uint8_t le[2 * N], be[2 * N];
    unsigned mn = 65535, mx = 0;
    for (size_t i = 0; i < N; i++) {
        unsigned v = 300 + pattern(i, 2) % 3000;
        mn = v < mn ? v : mn;
        mx = v > mx ? v : mx;
        le[2 * i] = (uint8_t)v, le[2 * i + 1] = (uint8_t)(v >> 8);
        be[2 * i] = (uint8_t)(v >> 8), be[2 * i + 1] = (uint8_t)v;
    }
    CHECK(c5t_write_file(c5t_path(0, "w_37x29x23_uint16.raw"), NULL, le, sizeof le) == 0);
    CHECK(c5t_write_file(c5t_path(1, "b.raw"), NULL, be, sizeof be) == 0);
    char json[600];
    pair a, b, c;
    CHECK(build_pair("{'volumes': [{'file': 'w_37x29x23_uint16.raw'}],"
                     " " TAIL "}", &a) == 0);
    snprintf(json, sizeof json, "{'volumes': [{'file': 'w_37x29x23_uint16.raw', 'window': [%u, %u]}],"
             " " TAIL "}", mn, mx);
    CHECK(build_pair(json, &b) == 0);
    snprintf(json, sizeof json, "{'volumes': [{'file': 'b.raw', 'dims': [37, 29, 23], 'type': 'uint16',"
             " 'endian': 'big', 'window': [%u, %u]}], " TAIL "}",
             mn, mx);
    CHECK(build_pair(json, &c) == 0);
    CHECK(same_grids(&a.res, &a.ooc) == 0);
    CHECK(same_grids(&a.res, &b.ooc) == 0); /* the auto window is the file's min..max */
    CHECK(same_grids(&a.res, &c.ooc) == 0); /* big-endian, the same values */
    char want[80];
    snprintf(want, sizeof want, "window [%u, %u]", mn, mx);
    CHECK_MSG(strstr(a.ooc.source_label[0], want) != NULL, "%s", a.ooc.source_label[0]);
    /* the window's own definition, voxel by voxel */
    for (size_t i = 0; i < N; i += 97) {
        unsigned v = (unsigned)(le[2 * i] | le[2 * i + 1] << 8);
        double x = floor((v - (double)mn) * (255.0 / (mx - (double)mn)) + 0.5);
        CHECK_INT(a.ooc.v == NULL ? c5_supervol_at(&a.ooc, (long)(i % 37), (long)(i / 37 % 29), (long)(i / (37 * 29))) : 0,
                  (unsigned)(x < 0 ? 0 : x > 255 ? 255 : x));
    }
    pair_free(&a);
    pair_free(&b);
    pair_free(&c);
}

/* ---- NRRD: attached raw, detached raw, gzip ------------------------------------------ */

static int save_nrrd(const char *path, void *data, int type, const size_t sizes[3], int gzip)
{
    Nrrd *n = nrrdNew();
    NrrdIoState *nio = nrrdIoStateNew();
    int rc = nrrdWrap_nva(n, data, type, 3, sizes);
    if (rc == 0) {
        nio->encoding = gzip ? nrrdEncodingGzip : nrrdEncodingRaw;
        rc = nrrdSave(path, n, nio);
    }
    if (rc != 0)
        free(biffGetDone(NRRD));
    nrrdIoStateNix(nio);
    nrrdNix(n);
    return rc;
}

TEST(ooc_nrrd_attached_detached_gzip)
{
    enum { N = 37 * 29 * 23 };
    static uint8_t u8[N];
    static uint16_t u16[N];
    for (size_t i = 0; i < N; i++) {
        u8[i] = (uint8_t)pattern(i, 3);
        u16[i] = (uint16_t)(1000 + pattern(i, 3) * 9);
    }
    const size_t sizes[3] = {37, 29, 23};
    CHECK(c5t_write_file(c5t_path(0, "ref_37x29x23_uint8.raw"), NULL, u8, N) == 0);
    CHECK(save_nrrd(c5t_path(1, "att.nrrd"), u8, nrrdTypeUChar, sizes, 0) == 0);
    CHECK(save_nrrd(c5t_path(2, "gz.nrrd"), u8, nrrdTypeUChar, sizes, 1) == 0);
    CHECK(save_nrrd(c5t_path(3, "gz16.nrrd"), u16, nrrdTypeUShort, sizes, 1) == 0);
    CHECK(save_nrrd(c5t_path(4, "att16.nrrd"), u16, nrrdTypeUShort, sizes, 0) == 0);
    /* detached, with a byte skip before the data */
    uint8_t skipped[5 + N];
    memset(skipped, 0xEE, 5);
    memcpy(skipped + 5, u8, N);
    CHECK(c5t_write_file(c5t_path(5, "det.data"), NULL, skipped, sizeof skipped) == 0);
    CHECK(c5t_write_file(c5t_path(6, "det.nhdr"),
                     "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 37 29 23\nspacings: 1 1 1\nencoding: raw\n"
                     "byte skip: 5\ndata file: det.data\n",
                     NULL, 0) == 0);
    const char *files[] = {"att.nrrd", "gz.nrrd", "det.nhdr"};
    pair ref;
    CHECK(build_pair("{'volumes': [{'file': 'ref_37x29x23_uint8.raw'}],"
                     " " TAIL "}", &ref) == 0);
    CHECK(same_grids(&ref.res, &ref.ooc) == 0);
    for (int f = 0; f < 3; f++) {
        char json[300];
        snprintf(json, sizeof json, "{'volumes': [{'file': '%s'}], " TAIL "}", files[f]);
        pair p;
        CHECK_MSG(build_pair(json, &p) == 0, "%s", files[f]);
        CHECK_MSG(same_grids(&ref.res, &p.ooc) == 0, "%s", files[f]);
        CHECK_MSG(!memcmp(ref.res.v, p.res.v, N), "%s", files[f]);
        pair_free(&p);
    }
    /* uint16: gzip and raw NRRD give the same windowed grid */
    pair g16, r16;
    CHECK(build_pair("{'volumes': [{'file': 'gz16.nrrd'}], " TAIL "}", &g16) == 0);
    CHECK(build_pair("{'volumes': [{'file': 'att16.nrrd'}], " TAIL "}", &r16) == 0);
    CHECK(same_grids(&r16.res, &g16.ooc) == 0);
    CHECK(same_grids(&g16.res, &r16.ooc) == 0);
    pair_free(&g16);
    pair_free(&r16);
    pair_free(&ref);
}

/* A source that changes under the reader: a clear error, not a crash or stale voxels. */
TEST(ooc_file_shrunk_after_open_fails_cleanly)
{
    uint8_t raw[37 * 29 * 23];
    for (size_t i = 0; i < sizeof raw; i++)
        raw[i] = (uint8_t)pattern(i, 6);
    const char *path = c5t_path(0, "s_37x29x23_uint8.raw");
    CHECK(c5t_write_file(path, NULL, raw, sizeof raw) == 0);
    c5_volume_desc d = {.kind = C5_SRC_FILE};
    snprintf(d.path, sizeof d.path, "%s", path);
    c5_voxsrc *s;
    c5_err err;
    CHECK_MSG(c5_voxsrc_open(&d, &s, &err) == 0, "%s", err.msg);
    CHECK(c5t_write_file(path, NULL, raw, 100) == 0); /* truncated in place */
    uint8_t out[37 * 29];
    size_t lo[3] = {0, 0, 10}, hi[3] = {37, 29, 11};
    int rc = c5_voxsrc_read(s, lo, hi, out, 37, 37 * 29, &err);
    c5_voxsrc_close(s);
    CHECK_INT(rc, -1);
    CHECK_MSG(strstr(err.msg, "s_37x29x23_uint8.raw: read failed") != NULL, "%s", err.msg);
}

/* ---- renderers ---------------------------------------------------------------------------- */

static const char *render_scene =
    "{'grid': {'center': [0, 0, 0], 'size': 80, 'fill': 3},"
    " 'volumes': [{'file': 'r_37x29x23_uint8.raw', 'offset': [2, 4, 3]},"
    "             {'generator': 'blobs', 'dims': [40, 33, 30], 'count': 6, 'seed': 2, 'offset': [30, 0, 0]}],"
    " 'transfer_function': {'opacity': [[0, 0], [60, 0], [120, 0.08], [255, 0.3]],"
    "   'color': [[0, 0.2, 0.3, 0.9], [255, 1, 0.9, 0.6]],"
    "   'shading': {'ambient': 0.3, 'diffuse': 0.7, 'specular': 0.3, 'specular_power': 20}},"
    " 'lights': [{'type': 'directional', 'direction': [-0.4, 0.3, -1], 'shadows': true}],"
    " 'surfaces': [{'type': 'rect', 'corner': [-100, -100, -30], 'u': [200, 0, 0], 'v': [0, 200, 0],"
    "   'material': {'reflectivity': 0.4}}],"
    " 'camera': {'eye': [120, -160, 90], 'target': [0, 0, 0], 'up': [0, 0, 1], 'fov': 40, 'width': 40, 'height': 40},"
    " 'render': {'max_bounces': 2}}";

static int render_pair(pair *p)
{
    uint8_t raw[37 * 29 * 23];
    for (size_t i = 0; i < sizeof raw; i++)
        raw[i] = (uint8_t)(pattern(i, 8) & 0xFF);
    if (c5t_write_file(c5t_path(0, "r_37x29x23_uint8.raw"), NULL, raw, sizeof raw) != 0)
        return -1;
    tiny_budget = 2 * BRICK_BYTES;
    int rc = build_pair(render_scene, p);
    tiny_budget = 20000;
    return rc;
}

static int same_image(const c5_image *a, const c5_image *b)
{
    return a->w == b->w && a->h == b->h && !memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->w * a->h);
}

TEST(ooc_cref_image_bit_identical_any_threads)
{
    pair p;
    CHECK(render_pair(&p) == 0);
    c5_image ref, img;
    c5_cref_stats st;
    c5_err err;
    c5_cref_opts one = {.threads = 1, .field = NULL}, three = {.threads = 3, .field = NULL};
    CHECK(c5_cref_render(&p.s, &p.res, 0, &one, &ref, &st, &err) == 0);
    uint64_t samples = st.samples;
    CHECK_MSG(samples > 10000, "%llu samples: the volume is not in view", (unsigned long long)samples);
    CHECK(c5_cref_render(&p.s, &p.ooc, 0, &one, &img, &st, &err) == 0);
    CHECK(same_image(&ref, &img));
    CHECK_INT(st.samples, samples);
    c5_image_free(&img);
    CHECK(c5_cref_render(&p.s, &p.ooc, 0, &three, &img, &st, &err) == 0);
    CHECK(same_image(&ref, &img));
    c5_image_free(&img);
    c5_supervol_cache_stats cs;
    c5_supervol_cache_stats_get(&p.ooc, &cs);
    CHECK_MSG(cs.misses > 20, "%llu misses: no eviction tested", cs.misses);
    c5_image_free(&ref);
    pair_free(&p);
}

TEST(ooc_board_model_image_and_counters_identical)
{
    pair p;
    CHECK(render_pair(&p) == 0);
    for (int cells = 1; cells <= 2; cells++) {
        c5_image a, b;
        c5_board_stats sa, sb;
        c5_err err;
        c5_board_opts o = {.cells = {cells, cells, cells}};
        CHECK_MSG(c5_board_render(&p.s, &p.res, 0, &o, &a, &sa, &err) == 0, "%s", err.msg);
        CHECK_MSG(c5_board_render(&p.s, &p.ooc, 0, &o, &b, &sb, &err) == 0, "%s", err.msg);
        CHECK(same_image(&a, &b));
        CHECK(sa.cycles == sb.cycles && sa.fetches == sb.fetches && sa.fetch_bytes == sb.fetch_bytes &&
              sa.samples == sb.samples && sa.samples_leaped == sb.samples_leaped && sa.cache_hits == sb.cache_hits &&
              sa.cache_misses == sb.cache_misses && sa.bus_packets == sb.bus_packets && sa.spills == sb.spills);
        CHECK(sa.samples_leaped > 0); /* the emptiness flags matter here */
        /* out of core on helper threads, every ray they run replayed: the same frame */
        c5_image c;
        c5_board_stats sc;
        c5_board_opts ot = o;
        ot.threads = 3;
        ot.threads_replay_all = 1;
        CHECK_MSG(c5_board_render(&p.s, &p.ooc, 0, &ot, &c, &sc, &err) == 0, "%s", err.msg);
        CHECK(same_image(&a, &c));
        CHECK(c5t_board_stats_equal("out of core, 3 threads", &sa, &sc) == 0);
        CHECK(sc.helper_runs > 0);
        c5_image_free(&c);
        c5_image_free(&a);
        c5_image_free(&b);
    }
    /* the flags and a fetched cell directly */
    c5_cells ca, cb;
    uint8_t nz[256];
    for (int i = 0; i < 256; i++)
        nz[i] = i >= 64;
    c5_err err;
    int n[3] = {2, 3, 2};
    CHECK(c5_cells_init(&ca, &p.res, n, nz, &err) == 0);
    CHECK(c5_cells_init(&cb, &p.ooc, n, nz, &err) == 0);
    CHECK(!memcmp(ca.empty, cb.empty, (size_t)ca.count));
    CHECK(!memcmp(ca.block_empty, cb.block_empty, c5_cells_blocks(&ca)));
    int some = 0, none = 0;
    for (size_t i = 0; i < c5_cells_blocks(&ca); i++)
        some |= ca.block_empty[i], none |= !ca.block_empty[i];
    CHECK(some && none);
    for (int cell = 0; cell < ca.count; cell++) {
        c5_rdram ra = {.cell = -1}, rb = {.cell = -1};
        CHECK(c5_rdram_load(&ra, &ca, &p.res, cell, &err) == 0);
        CHECK(c5_rdram_load(&rb, &cb, &p.ooc, cell, &err) == 0);
        CHECK(!memcmp(ra.v, rb.v, c5_cell_bytes(&ca, cell)));
        c5_rdram_free(&ra);
        c5_rdram_free(&rb);
    }
    c5_cells_free(&ca);
    c5_cells_free(&cb);
    pair_free(&p);
}

/* ---- the budget ------------------------------------------------------------------------- */

TEST(ooc_mem_budget_parse)
{
    size_t b;
    c5_err err;
    const char *ok[][2] = {{"262144", "262144"}, {"256K", "262144"}, {"3M", "3145728"}, {"2G", "2147483648"},
                           {"2GiB", "2147483648"}, {"1T", "1099511627776"}, {"512k", "524288"}};
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
        setenv("C5_MEM_BUDGET", ok[i][0], 1);
        CHECK_MSG(c5_mem_budget(&b, &err) == 0, "%s: %s", ok[i][0], err.msg);
        CHECK_MSG(b == strtoull(ok[i][1], NULL, 10), "%s: %zu", ok[i][0], b);
    }
    const char *bad[] = {"", "x", "12Q", "-5", "0", "1.5G", "99999999999999999999", "16777216T", "4G extra"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        setenv("C5_MEM_BUDGET", bad[i], 1);
        CHECK_MSG(c5_mem_budget(&b, &err) == -1, "'%s' accepted", bad[i]);
        CHECK_MSG(strstr(err.msg, "C5_MEM_BUDGET") != NULL, "%s", err.msg);
    }
    /* below one set of the brick cache: refused, the minimum stated */
    const char *small[] = {"1", "4096", "64K", "262143", "255K"};
    for (size_t i = 0; i < sizeof small / sizeof small[0]; i++) {
        setenv("C5_MEM_BUDGET", small[i], 1);
        CHECK_MSG(c5_mem_budget(&b, &err) == -1, "'%s' accepted", small[i]);
        CHECK_MSG(strstr(err.msg, "below the least a grid is held in, 262144 bytes") != NULL, "%s", err.msg);
    }
    unsetenv("C5_MEM_BUDGET");
    CHECK(c5_mem_budget(&b, &err) == 0 && b == C5_MEM_BUDGET_DEFAULT);
}

/* At the budget exactly the grid is resident, one voxel over it is out of core; the caster's
 * refusal names the budget. */
TEST(ooc_budget_boundary_and_cast_refusal)
{
    c5_scene s;
    c5_err err;
    CHECK(c5_scene_parse(c5t_json("{'volumes': [{'generator': 'sphere', 'dims': [40, 40, 40]}],"
                                  " " TAIL "}"),
                         NULL, "t", &s, &err) == 0);
    c5_supervol a, b;
    CHECK(c5_supervol_build_budget(&s, 64000, &a, &err) == 0);
    CHECK(a.v && !a.store);
    CHECK(c5_supervol_build_budget(&s, 63999, &b, &err) == 0);
    CHECK(!b.v && b.store);
    CHECK(same_grids(&a, &b) == 0);
    CHECK_INT(c5_supervol_cast_refusal(&b, "x", &err), -1);
    CHECK_MSG(strstr(err.msg, "x: the grid of 40x40x40 voxels is above the memory budget (C5_MEM_BUDGET, here 63999 "
                              "bytes)") != NULL, "%s", err.msg);
    c5_supervol_free(&a);
    c5_supervol_free(&b);
}

/* A resident grid whose voxels all differ along x: boxes wholly before, across and wholly
 * after the grid on each axis read the clamp-to-edge voxels (the row fills and copy of
 * c5_supervol_read_box). */
TEST(ooc_resident_boxes_beyond_every_face)
{
    static uint8_t vox[13 * 7 * 5];
    for (size_t i = 0; i < sizeof vox; i++)
        vox[i] = (uint8_t)(i * 7 + 3);
    c5_supervol sv = {.dims = {13, 7, 5}, .v = vox};
    const long spans[][2] = {{-9, -4}, {-3, 2}, {-2, 16}, {4, 9}, {11, 20}, {14, 19}, {0, 13}};
    uint8_t out[32 * 32 * 32];
    int bad = 0;
    for (int ax = 0; ax < 3; ax++)
        for (size_t k = 0; k < sizeof spans / sizeof spans[0]; k++) {
            long lo[3] = {1, 1, 1}, hi[3] = {5, 4, 3};
            lo[ax] = spans[k][0] * (long)sv.dims[ax] / 13;
            hi[ax] = spans[k][1] * (long)sv.dims[ax] / 13 + 1;
            c5_err err;
            CHECK(c5_supervol_read_box(&sv, lo, hi, out, &err) == 0);
            size_t o = 0;
            for (long z = lo[2]; z < hi[2]; z++)
                for (long y = lo[1]; y < hi[1]; y++)
                    for (long x = lo[0]; x < hi[0]; x++, o++)
                        bad += out[o] != c5_supervol_at(&sv, x, y, z);
        }
    CHECK_INT(bad, 0);
}
