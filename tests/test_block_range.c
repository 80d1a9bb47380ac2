/* The grid's block ranges (common/block_range.h) and what the board builds on them: every
 * range against a brute-force pass, the emptiness flags against the boxes read voxel by voxel
 * (aligned and unaligned splits, every kind of transfer function), the cache (written, read
 * back, refused when corrupt or when the file changed, off), the mapped grid (its voxels, a
 * copy handed out, the message when the file is cut short under it), the RDRAM view against
 * the copied cell, sample by sample, and an out-of-core grid's cells on disk. */
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "block_range.h"
#include "board.h"
#include "cell_store.h"
#include "cells.h"
#include "harness.h"
#include "regs.h"
#include "rng.h"
#include "sample_pipe.h"
#include "supervol.h"

#define TAIL                                                                                                           \
    "'transfer_function': {'opacity': [[0, 0], [70, 0], [140, 0.1], [255, 0.4]],"                                      \
    "  'color': [[0, 0.2, 0.3, 0.9], [255, 1, 0.9, 0.6]]},"                                                            \
    " 'camera': {'eye': [120, -160, 90], 'target': [0, 0, 0], 'up': [0, 0, 1], 'fov': 40, 'width': 32, 'height': 32}"

/* Noise (kind 0), sparse blobs of values over zeros (1), or lone voxels (2): what real volumes
 * and adversarial ones look like. */
static void fill_grid(uint8_t *v, const size_t d[3], int kind, uint64_t seed)
{
    size_t n = d[0] * d[1] * d[2];
    uint64_t s = seed;
    if (kind == 0) {
        for (size_t i = 0; i < n; i++)
            v[i] = (uint8_t)(c5_splitmix64(&s) >> 56);
        return;
    }
    memset(v, 0, n);
    if (kind == 2) { /* lone voxels: only an apron reaches them from the next cell or block */
        for (int k = 0; k < 24; k++)
            v[(size_t)(c5_uniform(&s) * (double)n)] = (uint8_t)(128 + k);
        return;
    }
    for (int b = 0; b < 6; b++) {
        size_t c[3], r = 1 + (size_t)(c5_uniform(&s) * 5);
        for (int a = 0; a < 3; a++)
            c[a] = (size_t)(c5_uniform(&s) * (double)d[a]);
        unsigned val = 1 + (unsigned)(c5_uniform(&s) * 254);
        for (size_t z = 0; z < d[2]; z++)
            for (size_t y = 0; y < d[1]; y++)
                for (size_t x = 0; x < d[0]; x++) {
                    size_t dx = x > c[0] ? x - c[0] : c[0] - x, dy = y > c[1] ? y - c[1] : c[1] - y,
                           dz = z > c[2] ? z - c[2] : c[2] - z;
                    if (dx <= r && dy <= r && dz <= r)
                        v[(z * d[1] + y) * d[0] + x] = (uint8_t)val;
                }
    }
}

static void hand_grid(c5_supervol *sv, const size_t d[3], uint8_t *v)
{
    memset(sv, 0, sizeof *sv);
    memcpy(sv->dims, d, sizeof sv->dims);
    sv->spacing = v3(1, 1, 1);
    sv->v = v;
}

/* Range of voxels [lo, hi] (inclusive) read one by one with clamp to edge. */
static void ref_range(const c5_supervol *sv, const long lo[3], const long hi[3], unsigned *mn, unsigned *mx)
{
    *mn = 255;
    *mx = 0;
    for (long z = lo[2]; z <= hi[2]; z++)
        for (long y = lo[1]; y <= hi[1]; y++)
            for (long x = lo[0]; x <= hi[0]; x++) {
                unsigned v = c5_supervol_at(sv, x, y, z);
                *mn = v < *mn ? v : *mn;
                *mx = v > *mx ? v : *mx;
            }
}

/* The flag rule (cells.c) on a range: no table entry floor(min) .. max + 1 has alpha > 0. */
static int ref_empty(const uint8_t nz[256], unsigned mn, unsigned mx)
{
    unsigned top = mx + 1 > 255 ? 255 : mx + 1;
    for (unsigned i = mn; i <= top; i++)
        if (nz[i])
            return 0;
    return 1;
}

static int ranges_match(const c5_supervol *sv, const c5_block_range *r)
{
    for (size_t bz = 0; bz < r->bdims[2]; bz++)
        for (size_t by = 0; by < r->bdims[1]; by++)
            for (size_t bx = 0; bx < r->bdims[0]; bx++) {
                size_t id = (bz * r->bdims[1] + by) * r->bdims[0] + bx, b[3] = {bx, by, bz};
                long lo[3], hi[3], alo[3], ahi[3];
                for (int a = 0; a < 3; a++) {
                    lo[a] = (long)(b[a] * 8);
                    hi[a] = (long)(b[a] * 8 + 7 < sv->dims[a] - 1 ? b[a] * 8 + 7 : sv->dims[a] - 1);
                    alo[a] = lo[a] - 1;
                    ahi[a] = (long)b[a] * 8 + 8;
                }
                unsigned mn, mx, amn, amx;
                ref_range(sv, lo, hi, &mn, &mx);
                ref_range(sv, alo, ahi, &amn, &amx);
                if (r->mn[id] != mn || r->mx[id] != mx || r->amn[id] != amn || r->amx[id] != amx) {
                    fprintf(stderr, "block %zu %zu %zu: %u..%u / %u..%u, want %u..%u / %u..%u\n", bx, by, bz,
                            r->mn[id], r->mx[id], r->amn[id], r->amx[id], mn, mx, amn, amx);
                    return 0;
                }
            }
    return 1;
}

static const size_t shapes[][3] = {{1, 1, 1}, {8, 8, 8}, {37, 21, 45}, {9, 17, 3}, {64, 40, 24}, {48, 32, 16}};

TEST(block_range_every_block_and_apron_brute_force)
{
    for (size_t s = 0; s < sizeof shapes / sizeof *shapes; s++)
        for (int kind = 0; kind < 3; kind++) {
            size_t n = shapes[s][0] * shapes[s][1] * shapes[s][2];
            uint8_t *v = malloc(n);
            CHECK(v != NULL);
            fill_grid(v, shapes[s], kind, 100 + s);
            c5_supervol sv;
            hand_grid(&sv, shapes[s], v);
            c5_block_range *owned;
            c5_err err;
            const c5_block_range *r = c5_block_range_of(&sv, &owned, &err);
            CHECK_MSG(r && owned == r && r->origin == C5_RANGE_COMPUTED, "%s", err.msg);
            int ok = ranges_match(&sv, r);
            c5_block_range_free(owned);
            free(v);
            CHECK_MSG(ok, "shape %zu kind %d", s, kind);
        }
}

/* The flags c5_cells_init gives against the boxes read voxel by voxel. */
static int flags_match(const c5_supervol *sv, const int n[3], const uint8_t nz[256], int *some_cells)
{
    c5_cells c;
    c5_err err;
    if (c5_cells_init(&c, sv, n, nz, &err) != 0) {
        fprintf(stderr, "cells_init: %s\n", err.msg);
        return 0;
    }
    int ok = 1;
    for (int cell = 0; cell < c.count && ok; cell++) {
        int lo[3], hi[3];
        c5_cell_box(&c, cell, lo, hi);
        long blo[3] = {lo[0] - 1, lo[1] - 1, lo[2] - 1}, bhi[3] = {hi[0], hi[1], hi[2]};
        unsigned mn, mx;
        ref_range(sv, blo, bhi, &mn, &mx);
        ok = c.empty[cell] == ref_empty(nz, mn, mx);
        *some_cells += c.empty[cell];
        if (!ok)
            fprintf(stderr, "cell %d: flag %d\n", cell, c.empty[cell]);
    }
    for (int bz = 0; bz < c.bdims[2] && ok; bz++)
        for (int by = 0; by < c.bdims[1] && ok; by++)
            for (int bx = 0; bx < c.bdims[0] && ok; bx++) {
                long blo[3] = {bx * 8L - 1, by * 8L - 1, bz * 8L - 1}, bhi[3] = {bx * 8L + 8, by * 8L + 8, bz * 8L + 8};
                unsigned mn, mx;
                ref_range(sv, blo, bhi, &mn, &mx);
                size_t id = ((size_t)bz * c.bdims[1] + by) * c.bdims[0] + bx;
                ok = c.block_empty[id] == ref_empty(nz, mn, mx);
                if (!ok)
                    fprintf(stderr, "block %d %d %d: flag %d\n", bx, by, bz, c.block_empty[id]);
            }
    c5_cells_free(&c);
    return ok;
}

TEST(cell_and_block_flags_equal_boxes_read_voxel_by_voxel)
{
    /* splits aligned to the blocks (64x40x24 in 8, 5, 3 and 2, 5, 1; 48x32x16 in 6, 4, 2) and
     * not; tables empty,
     * full, a threshold, narrow bands (the range's span, not its ends, decides) */
    static const int splits[][3] = {{1, 1, 1}, {8, 5, 3}, {2, 5, 1}, {3, 3, 5}, {2, 1, 4}, {6, 4, 2}};
    uint64_t st = 7;
    int tables = 0, some_empty = 0;
    for (size_t s = 0; s < sizeof shapes / sizeof *shapes; s++)
        for (int kind = 0; kind < 3; kind++) {
            size_t n = shapes[s][0] * shapes[s][1] * shapes[s][2];
            uint8_t *v = malloc(n);
            CHECK(v != NULL);
            fill_grid(v, shapes[s], kind, 200 + s);
            c5_supervol sv;
            hand_grid(&sv, shapes[s], v);
            for (int t = 0; t < 6; t++) {
                uint8_t nz[256];
                unsigned a = (unsigned)(c5_uniform(&st) * 256), b = a + (unsigned)(c5_uniform(&st) * 40);
                for (unsigned i = 0; i < 256; i++)
                    nz[i] = t == 0 ? 0 : t == 1 ? 1 : t == 2 ? i >= a : (i >= a && i <= b);
                for (size_t k = 0; k < sizeof splits / sizeof *splits; k++) {
                    int sp[3];
                    for (int ax = 0; ax < 3; ax++)
                        sp[ax] = splits[k][ax] < (int)shapes[s][ax] ? splits[k][ax] : (int)shapes[s][ax];
                    int ok = flags_match(&sv, sp, nz, &some_empty);
                    tables++;
                    if (!ok)
                        free(v);
                    CHECK_MSG(ok, "shape %zu kind %d table %d split %d %d %d", s, kind, t, sp[0], sp[1], sp[2]);
                }
            }
            free(v);
        }
    CHECK(tables == 6 * 3 * 6 * 6 && some_empty > 0);
}

/* A scene of one raw file, the whole grid: its voxels mapped. */
static int build_file_scene(const char *name, c5_scene *s, c5_supervol *sv, size_t budget)
{
    char json[512];
    c5_err err;
    snprintf(json, sizeof json, "{'grid': {'center': [0, 0, 0], 'size': 80}, 'volumes': [{'file': '%s'}], " TAIL "}",
             name);
    if (c5_scene_parse(c5t_json(json), c5t_tmpdir(), "test", s, &err) != 0 ||
        c5_supervol_build_budget(s, budget, sv, &err) != 0) {
        fprintf(stderr, "build: %s\n", err.msg);
        return -1;
    }
    return 0;
}

/* The file's modification time set `ago` seconds back. */
static int age_file(const char *path, long ago)
{
    struct timespec ts[2] = {{0, UTIME_OMIT}, {time(NULL) - ago, 0}};
    return utimensat(AT_FDCWD, path, ts, 0);
}

/* The 37x21x45 grid of `kind` (fill_grid) written to NAME in the test's folder and made `age`
 * seconds old (0: just written); 0 on success. */
static int grid_file(const char *name, int kind, uint64_t seed, long age)
{
    static const size_t d[3] = {37, 21, 45};
    size_t n = d[0] * d[1] * d[2];
    uint8_t *v = malloc(n);
    if (!v)
        return -1;
    fill_grid(v, d, kind, seed);
    int rc = c5t_write_file(c5t_path(0, name), NULL, v, n);
    free(v);
    return rc != 0 ? -1 : age ? age_file(c5t_path(0, name), age) : 0;
}

/* The test's own cache folder (inside its temporary folder). */
static const char *test_cache(void)
{
    static char cache[1024];
    snprintf(cache, sizeof cache, "%s/cache", c5t_tmpdir());
    return cache;
}

static int same_arrays(const c5_block_range *a, const c5_block_range *b)
{
    size_t n = a->bdims[0] * a->bdims[1] * a->bdims[2];
    return !memcmp(a->bdims, b->bdims, sizeof a->bdims) && !memcmp(a->mn, b->mn, n) && !memcmp(a->mx, b->mx, n) &&
           !memcmp(a->amn, b->amn, n) && !memcmp(a->amx, b->amx, n);
}

/* The one file in dir, or "" */
static void only_file(const char *dir, char *out, size_t n)
{
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "ls %s", dir);
    FILE *p = popen(cmd, "r");
    char name[256] = "";
    if (p && fgets(name, sizeof name, p))
        name[strcspn(name, "\n")] = 0;
    if (p)
        pclose(p);
    snprintf(out, n, "%s/%s", dir, name);
}

TEST(block_range_cache_written_read_refused_off)
{
    static const size_t d[3] = {37, 21, 45};
    size_t n = d[0] * d[1] * d[2];
    uint8_t *v = malloc(n);
    CHECK(v != NULL);
    fill_grid(v, d, 1, 31);
    const char *raw = c5t_path(0, "g_37x21x45_uint8.raw");
    CHECK(c5t_write_file(raw, NULL, v, n) == 0);
    CHECK(age_file(raw, 100) == 0); /* a file written just now has no identity yet */
    const char *cache = test_cache();
    setenv("C5_CACHE_DIR", cache, 1);
    c5_supervol ref;
    hand_grid(&ref, d, v);
    c5_block_range *want;
    c5_err err;
    CHECK(c5_block_range_of(&ref, &want, &err) != NULL);
    c5_range_origin seen[5];
    int ok = 1;
    for (int run = 0; run < 5 && ok; run++) {
        if (run == 2) { /* the cache file cut short: made again */
            char f[1400];
            only_file(cache, f, sizeof f);
            ok &= truncate(f, 100) == 0;
        }
        if (run == 3) { /* the volume changed (new voxels, a later mtime): another file's cache */
            v[n / 2] ^= 0x5a;
            ok &= c5t_write_file(raw, NULL, v, n) == 0 && age_file(raw, 50) == 0;
            c5_block_range_free(want);
            ok &= c5_block_range_of(&ref, &want, &err) != NULL;
        }
        if (run == 4)
            setenv("C5_CACHE_DIR", "off", 1);
        c5_scene s;
        c5_supervol sv;
        ok &= build_file_scene("g_37x21x45_uint8.raw", &s, &sv, (size_t)1 << 30) == 0;
        ok &= sv.map_base != NULL && sv.file_id[0] && !memcmp(sv.v, v, n);
        c5_block_range *owned;
        const c5_block_range *r = c5_block_range_of(&sv, &owned, &err);
        ok &= r != NULL && owned == NULL && sv.ranges == r && c5_block_range_of(&sv, &owned, &err) == r;
        if (r) {
            seen[run] = r->origin;
            ok &= same_arrays(r, want);
        }
        c5_supervol_free(&sv);
    }
    unsetenv("C5_CACHE_DIR");
    c5_block_range_free(want);
    free(v);
    CHECK(ok);
    CHECK(seen[0] == C5_RANGE_CACHED_NOW && seen[1] == C5_RANGE_FROM_CACHE && seen[2] == C5_RANGE_CACHED_NOW &&
          seen[3] == C5_RANGE_CACHED_NOW && seen[4] == C5_RANGE_COMPUTED);
}

TEST(mapped_grid_detach_and_cut_short_file)
{
    static const size_t d[3] = {37, 21, 45};
    size_t n = d[0] * d[1] * d[2];
    uint8_t *v = malloc(n);
    CHECK(v != NULL);
    fill_grid(v, d, 0, 41);
    CHECK(c5t_write_file(c5t_path(0, "m_37x21x45_uint8.raw"), NULL, v, n) == 0);
    c5_scene s;
    c5_supervol sv;
    CHECK(build_file_scene("m_37x21x45_uint8.raw", &s, &sv, (size_t)1 << 30) == 0);
    CHECK(sv.map_base != NULL && !memcmp(sv.v, v, n));
    uint8_t *copy = c5_supervol_detach(&sv); /* the caster frees what it is handed */
    CHECK(copy != NULL && !memcmp(copy, v, n) && sv.v == NULL && sv.map_base == NULL);
    free(copy);
    /* another process cuts the file short under the mapping: the message of a failed read */
    CHECK(build_file_scene("m_37x21x45_uint8.raw", &s, &sv, (size_t)1 << 30) == 0);
    int fds[2];
    CHECK(pipe(fds) == 0);
    pid_t pid = fork();
    if (pid == 0) {
        dup2(fds[1], 2);
        if (truncate(c5t_path(0, "m_37x21x45_uint8.raw"), 0) != 0)
            _exit(9);
        volatile unsigned sum = 0;
        for (size_t i = 0; i < n; i += 4096)
            sum += sv.v[i];
        _exit(0);
    }
    close(fds[1]);
    char msg[512] = "";
    ssize_t got = read(fds[0], msg, sizeof msg - 1);
    msg[got > 0 ? got : 0] = 0;
    close(fds[0]);
    int status;
    waitpid(pid, &status, 0);
    c5_supervol_free(&sv);
    free(v);
    CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 2, "status %d", status);
    CHECK_MSG(strstr(msg, "m_37x21x45_uint8.raw: read failed: the file ends early") != NULL, "%s", msg);
}

TEST(rdram_view_reads_what_the_copied_cell_holds)
{
    static const size_t d[3] = {37, 21, 45};
    size_t n = d[0] * d[1] * d[2];
    uint8_t *v = malloc(n);
    CHECK(v != NULL);
    fill_grid(v, d, 0, 51);
    c5_supervol sv;
    hand_grid(&sv, d, v);
    c5_frame_regs r;
    memset(&r, 0, sizeof r);
    for (int a = 0; a < 3; a++)
        r.dims[a] = (int)d[a];
    uint8_t nz[256];
    memset(nz, 1, sizeof nz);
    c5_cells c;
    c5_err err;
    int split[3] = {3, 2, 4}, bad = 0;
    CHECK(c5_cells_init(&c, &sv, split, nz, &err) == 0);
    uint64_t st = 5;
    for (int cell = 0; cell < c.count; cell++) {
        c5_rdram cp = {.cell = -1}, vw = {.cell = -1};
        if (c5_rdram_load(&cp, &c, &sv, cell, &err) != 0 || c5_rdram_view(&vw, &c, &sv, cell, &err) != 0 ||
            vw.view == NULL) {
            bad++;
            break;
        }
        for (int t = 0; t < 2000; t++) {
            int64_t pos[3];
            for (int a = 0; a < 3; a++) /* anywhere in the cell, its faces' voxels included */
                pos[a] = (int64_t)((cp.lo[a] + c5_uniform(&st) * (cp.hi[a] - cp.lo[a])) * 32768.0);
            c5_corners k1, k2;
            memset(&k1, 0, sizeof k1);
            memset(&k2, 0, sizeof k2);
            c5_gather(&r, &cp, pos, 1, &k1);
            c5_gather(&r, &vw, pos, 1, &k2);
            bad += memcmp(&k1, &k2, sizeof k1) != 0;
        }
        c5_rdram_free(&cp);
        c5_rdram_free(&vw);
    }
    c5_cells_free(&c);
    free(v);
    CHECK_INT(bad, 0);
}

TEST(mapped_grid_renders_as_out_of_core)
{
    CHECK(grid_file("o_37x21x45_uint8.raw", 1, 61, 0) == 0);
    setenv("C5_CACHE_DIR", "off", 1);
    c5_scene s;
    c5_supervol res, ooc;
    CHECK(build_file_scene("o_37x21x45_uint8.raw", &s, &res, (size_t)1 << 30) == 0);
    CHECK(build_file_scene("o_37x21x45_uint8.raw", &s, &ooc, 20000) == 0);
    CHECK(res.map_base != NULL && ooc.store != NULL);
    int ok = 1;
    for (int cells = 1; cells <= 3 && ok; cells++) {
        c5_image a, b;
        c5_board_stats sa, sb;
        c5_err err;
        c5_board_opts o = {.cells = {cells, cells, cells}};
        ok &= c5_board_render(&s, &res, 0, &o, &a, &sb, &err) == 0;
        ok &= c5_board_render(&s, &ooc, 0, &o, &b, &sa, &err) == 0;
        ok &= !memcmp(a.rgb, b.rgb, sizeof(float) * 3 * (size_t)a.w * (size_t)a.h) && sa.cycles == sb.cycles &&
              sa.samples == sb.samples && sa.samples_leaped == sb.samples_leaped && sa.cache_hits == sb.cache_hits &&
              sa.fetches == sb.fetches && sa.samples > 0 && sa.samples_leaped > 0;
        c5_image_free(&a);
        c5_image_free(&b);
    }
    unsetenv("C5_CACHE_DIR");
    c5_supervol_free(&res);
    c5_supervol_free(&ooc);
    CHECK(ok);
}

/* ---- an out-of-core grid's cells on disk (rtl_model/mem/cell_store.h) ------------------- */

static int file_and_generator_scene(c5_scene *s, c5_supervol *sv, size_t budget)
{
    c5_err err;
    const char *json = "{'grid': {'center': [0, 0, 0], 'size': 80, 'fill': 3},"
                       " 'volumes': [{'file': 'c_37x21x45_uint8.raw', 'offset': [2, 4, 3]},"
                       "  {'generator': 'blobs', 'dims': [30, 33, 30], 'count': 6, 'seed': 2, 'offset': [30, 0, 0]}],"
                       " " TAIL "}";
    if (c5_scene_parse(c5t_json(json), c5t_tmpdir(), "test", s, &err) != 0 ||
        c5_supervol_build_budget(s, budget, sv, &err) != 0) {
        fprintf(stderr, "build: %s\n", err.msg);
        return -1;
    }
    return 0;
}

TEST(cell_store_holds_each_cell_made_once_refused_when_stale)
{
    CHECK(grid_file("c_37x21x45_uint8.raw", 0, 71, 0) == 0);
    const char *cache = test_cache();
    setenv("C5_CACHE_DIR", cache, 1);
    c5_scene s;
    c5_supervol ooc, res;
    /* a file written just now: no identity, so no store (it could be rewritten unseen) */
    CHECK(file_and_generator_scene(&s, &ooc, 20000) == 0);
    CHECK(ooc.store != NULL && !ooc.grid_id[0]);
    c5_supervol_free(&ooc);
    CHECK(age_file(c5t_path(0, "c_37x21x45_uint8.raw"), 100) == 0);
    CHECK(file_and_generator_scene(&s, &ooc, 20000) == 0 && file_and_generator_scene(&s, &res, 1 << 30) == 0);
    CHECK(ooc.store != NULL && ooc.grid_id[0] && res.v != NULL);
    c5_cells c;
    c5_err err;
    uint8_t nz[256];
    memset(nz, 1, sizeof nz);
    int split[3] = {2, 3, 2}, ok = 1, cached[4] = {-1, -1, -1, -1};
    CHECK(c5_cells_init(&c, &ooc, split, nz, &err) == 0);
    for (int run = 0; run < 4 && ok; run++) {
        if (run == 2) { /* the cache file cut short: made again */
            char f[1400];
            only_file(cache, f, sizeof f);
            ok &= strstr(f, "/cells-") != NULL && truncate(f, 5000) == 0;
        }
        if (run == 3)
            setenv("C5_CACHE_DIR", "off", 1);
        c5_cell_store *cs;
        ok &= c5_cell_store_open(&ooc, &c, &cs, &err) == 0;
        if (run == 3) {
            ok &= cs == NULL; /* the caller copies each cell */
            break;
        }
        ok &= cs != NULL;
        if (!cs)
            break;
        cached[run] = c5_cell_store_was_cached(cs);
        for (int cell = 0; cell < c.count && ok; cell++) {
            c5_rdram m = {.cell = -1};
            ok &= c5_rdram_load(&m, &c, &res, cell, &err) == 0 &&
                  !memcmp(c5_cell_store_cell(cs, cell), m.v, c5_cell_bytes(&c, cell));
            c5_cell_store_release(cs, cell);
            c5_rdram_free(&m);
        }
        c5_cell_store_close(cs);
    }
    c5_cell_store *none;
    setenv("C5_CACHE_DIR", cache, 1);
    ok &= c5_cell_store_open(&res, &c, &none, &err) == 0 && none == NULL; /* resident: read in place */
    unsetenv("C5_CACHE_DIR");
    c5_cells_free(&c);
    c5_supervol_free(&ooc);
    c5_supervol_free(&res);
    CHECK(ok);
    CHECK(cached[0] == 0 && cached[1] == 1 && cached[2] == 0);
}

TEST(board_out_of_core_from_the_cell_store_as_resident)
{
    CHECK(grid_file("c_37x21x45_uint8.raw", 1, 81, 100) == 0);
    const char *cache = test_cache();
    c5_scene s;
    c5_supervol ooc, res;
    CHECK(file_and_generator_scene(&s, &ooc, 20000) == 0 && file_and_generator_scene(&s, &res, 1 << 30) == 0);
    int ok = 1;
    /* the cells from the store (twice: made, then cached), and copied with the cache off */
    for (int k = 0; k < 3 && ok; k++) {
        setenv("C5_CACHE_DIR", k < 2 ? cache : "off", 1);
        for (int cells = 1; cells <= 3 && ok; cells++) {
            c5_image a, b;
            c5_board_stats sa, sb;
            c5_err err;
            int sched[64];
            for (int i = 0; i < 64; i++)
                sched[i] = i % (cells * cells * cells);
            /* Max Work, and a schedule known before the frame (its next cell prefetched) */
            c5_board_opts o = {.cells = {cells, cells, cells}};
            if (cells == 2)
                o.sched = C5_SCHED_EXTERNAL, o.schedule = sched, o.schedule_len = 64;
            ok &= c5_board_render(&s, &res, 0, &o, &a, &sa, &err) == 0;
            ok &= c5_board_render(&s, &ooc, 0, &o, &b, &sb, &err) == 0;
            ok &= !memcmp(a.rgb, b.rgb, sizeof(float) * 3 * (size_t)a.w * (size_t)a.h) && sa.cycles == sb.cycles &&
                  sa.samples == sb.samples && sa.samples_leaped == sb.samples_leaped &&
                  sa.cache_hits == sb.cache_hits && sa.fetches == sb.fetches && sa.samples > 0;
            c5_image_free(&a);
            c5_image_free(&b);
        }
    }
    unsetenv("C5_CACHE_DIR");
    c5_supervol_free(&ooc);
    c5_supervol_free(&res);
    CHECK(ok);
}

TEST(generated_grid_ranges_follow_its_voxels)
{
    /* A generated grid has no file identity: its ranges are made from its voxels each time,
     * never kept, so a caller that changes them after the build sees its own (the
     * stability scenes do). */
    setenv("C5_CACHE_DIR", test_cache(), 1);
    int ok = 1;
    for (int run = 0; run < 2 && ok; run++) {
        c5_scene s;
        c5_supervol sv;
        c5_err err;
        ok &= c5_scene_parse(c5t_json("{'volumes': [{'generator': 'constant', 'dims': [16, 16, 16], 'value': 0}], "
                                      TAIL "}"),
                             c5t_tmpdir(), "test", &s, &err) == 0 &&
              c5_supervol_build(&s, &sv, &err) == 0;
        if (!ok)
            break;
        ok &= sv.file_id[0] == 0;
        if (run == 1)
            memset(sv.v, 255, 16 * 16 * 16);
        uint8_t nz[256] = {0};
        nz[255] = 1;
        c5_cells c;
        int split[3] = {2, 2, 2};
        ok &= c5_cells_init(&c, &sv, split, nz, &err) == 0;
        ok &= c.empty[0] == (run == 0) && c.block_empty[0] == (run == 0) && sv.ranges == NULL;
        c5_cells_free(&c);
        c5_supervol_free(&sv);
    }
    unsetenv("C5_CACHE_DIR");
    CHECK(ok);
}

TEST(out_of_core_generated_grid_ranges_kept_and_cached)
{
    /* out of core, a generated grid's voxels are only in its generator: its ranges are kept
     * by its identity, so a later run does not generate the grid again to make them */
    setenv("C5_CACHE_DIR", test_cache(), 1);
    const char *json = "{'volumes': [{'generator': 'blobs', 'dims': [40, 36, 44], 'count': 5, 'seed': 4}], " TAIL "}";
    c5_scene s;
    c5_supervol res;
    c5_err err;
    CHECK(c5_scene_parse(c5t_json(json), c5t_tmpdir(), "test", &s, &err) == 0 &&
          c5_supervol_build_budget(&s, 1 << 30, &res, &err) == 0);
    c5_block_range *want;
    CHECK(c5_block_range_of(&res, &want, &err) != NULL && want != NULL); /* resident: not kept */
    c5_range_origin seen[2] = {C5_RANGE_COMPUTED, C5_RANGE_COMPUTED};
    int ok = 1;
    for (int run = 0; run < 2; run++) {
        c5_supervol ooc;
        ok &= c5_supervol_build_budget(&s, 20000, &ooc, &err) == 0 && ooc.store && ooc.grid_id[0];
        c5_block_range *owned;
        const c5_block_range *r = ok ? c5_block_range_of(&ooc, &owned, &err) : NULL;
        ok &= r != NULL && owned == NULL && ooc.ranges == r && same_arrays(r, want);
        if (r)
            seen[run] = r->origin;
        c5_supervol_free(&ooc);
    }
    unsetenv("C5_CACHE_DIR");
    c5_block_range_free(want);
    c5_supervol_free(&res);
    CHECK(ok);
    CHECK(seen[0] == C5_RANGE_CACHED_NOW && seen[1] == C5_RANGE_FROM_CACHE);
}

/* Bytes of cube5's cache files in dir whose names start with prefix; -1 when path is absent. */
static long long cache_bytes(const char *dir, const char *prefix)
{
    char cmd[1300];
    snprintf(cmd, sizeof cmd, "cat %s/%s*.bin 2>/dev/null | wc -c", dir, prefix);
    FILE *p = popen(cmd, "r");
    long long n = -1;
    if (p && fscanf(p, "%lld", &n) != 1)
        n = -1;
    if (p)
        pclose(p);
    return n;
}

/* The store of the scene's out-of-core grid at split n: 1 made, 2 found in the cache, 0 none. */
static int store_at(const c5_supervol *sv, int n)
{
    c5_cells c;
    c5_err err;
    uint8_t nz[256];
    memset(nz, 1, sizeof nz);
    int split[3] = {n, n, 1}, rc = 0;
    if (c5_cells_init(&c, sv, split, nz, &err) != 0)
        return -1;
    c5_cell_store *cs;
    if (c5_cell_store_open(sv, &c, &cs, &err) == 0 && cs)
        rc = c5_cell_store_was_cached(cs) ? 2 : 1;
    c5_cell_store_close(cs);
    c5_cells_free(&c);
    usleep(20000); /* the next file's time is later than this one's */
    return rc;
}

TEST(cache_holds_at_most_c5_cache_max_least_recently_used_out)
{
    CHECK(grid_file("c_37x21x45_uint8.raw", 0, 91, 100) == 0);
    const char *cache = test_cache();
    setenv("C5_CACHE_DIR", cache, 1);
    c5_scene s;
    c5_supervol sv;
    CHECK(file_and_generator_scene(&s, &sv, 20000) == 0 && sv.grid_id[0]);
    /* each store's size with no cap */
    long long size[4];
    for (int k = 1; k <= 3; k++) {
        char cmd[1200];
        snprintf(cmd, sizeof cmd, "rm -f %s/cells-*.bin", cache);
        CHECK(system(cmd) == 0 && store_at(&sv, k) == 1);
        size[k] = cache_bytes(cache, "cells-");
    }
    long long ranges = cache_bytes(cache, "ranges-");
    CHECK(ranges > 0 && size[1] > 0 && size[2] > 0 && size[3] > 0);
    char cmd[1200], max[64];
    snprintf(cmd, sizeof cmd, "rm -f %s/cells-*.bin", cache);
    CHECK(system(cmd) == 0);
    /* room for two stores, not three and the ranges: the third makes the least recently used
     * files go, the ranges (kept in memory since, not read again) and store 2 (store 1 was
     * used after it) */
    snprintf(max, sizeof max, "%lld", size[1] + size[2] + size[3] - 1);
    setenv("C5_CACHE_MAX", max, 1);
    int r1 = store_at(&sv, 1), r2 = store_at(&sv, 2), r1b = store_at(&sv, 1), r3 = store_at(&sv, 3);
    long long after = cache_bytes(cache, "cells-"), ranges_after = cache_bytes(cache, "ranges-");
    int r2b = store_at(&sv, 2), r1c = store_at(&sv, 1); /* 2 makes 1 go, then 1 makes 3 go */
    long long last = cache_bytes(cache, "cells-");
    /* a store larger than the cap is not made: the frame copies its cells */
    snprintf(max, sizeof max, "%lld", size[1] / 2);
    setenv("C5_CACHE_MAX", max, 1);
    int too_big = store_at(&sv, 3);
    setenv("C5_CACHE_MAX", "lots", 1);
    c5_supervol bad;
    c5_err err;
    int refused = c5_supervol_build(&s, &bad, &err) != 0 && strstr(err.msg, "C5_CACHE_MAX: expected a byte count");
    unsetenv("C5_CACHE_MAX");
    unsetenv("C5_CACHE_DIR");
    c5_supervol_free(&sv);
    CHECK_MSG(r1 == 1 && r2 == 1 && r1b == 2 && r3 == 1, "%d %d %d %d", r1, r2, r1b, r3);
    CHECK(after == size[1] + size[3] && ranges_after == 0);
    CHECK_MSG(r2b == 1 && r1c == 1 && last == size[1] + size[2], "%d %d %lld", r2b, r1c, last);
    CHECK(too_big == 0);
    CHECK(refused);
}

TEST(resident_grid_same_bytes_for_1_2_and_7_threads)
{
    /* a resident grid of a file and a generator is read in slabs on every core: at 1, 2 and 7
     * threads (C5_THREADS) the bytes are those the out-of-core grid's bricks give, read on
     * one thread box by box */
    CHECK(grid_file("c_37x21x45_uint8.raw", 1, 97, 100) == 0);
    c5_scene s;
    c5_supervol ooc;
    CHECK(file_and_generator_scene(&s, &ooc, 20000) == 0 && ooc.store != NULL);
    c5_err err;
    size_t n = ooc.dims[0] * ooc.dims[1] * ooc.dims[2];
    uint8_t *want = malloc(n);
    long lo[3] = {0, 0, 0}, hi[3] = {(long)ooc.dims[0], (long)ooc.dims[1], (long)ooc.dims[2]};
    CHECK(want != NULL && c5_supervol_read_box(&ooc, lo, hi, want, &err) == 0);
    size_t seen[256] = {0}, kinds = 0;
    for (size_t i = 0; i < n; i++)
        kinds += seen[want[i]]++ == 0;
    CHECK_MSG(kinds > 20, "%zu values: the fill, the file and the blobs", kinds);
    static const char *threads[3] = {"1", "2", "7"};
    for (int k = 0; k < 3; k++) {
        setenv("C5_THREADS", threads[k], 1);
        c5_supervol res;
        int built = file_and_generator_scene(&s, &res, (size_t)1 << 30) == 0;
        CHECK_MSG(built && res.v != NULL && !memcmp(res.v, want, n), "threads %s", threads[k]);
        if (built)
            c5_supervol_free(&res);
    }
    unsetenv("C5_THREADS");
    free(want);
    c5_supervol_free(&ooc);
}

TEST(one_time_passes_same_bytes_for_1_2_and_7_threads)
{
    /* the block ranges (in parallel over layers) and the cell store (cells read in batches)
     * of an out-of-core grid, made at 1, 2 and 7 threads (C5_THREADS): the same bytes */
    CHECK(grid_file("c_37x21x45_uint8.raw", 1, 97, 100) == 0);
    c5_scene s;
    c5_supervol sv;
    CHECK(file_and_generator_scene(&s, &sv, 20000) == 0 && sv.grid_id[0]);
    c5_err err;
    uint8_t nz[256];
    memset(nz, 1, sizeof nz);
    int split[3] = {3, 2, 3}, ok = 1;
    c5_cells c;
    CHECK(c5_cells_init(&c, &sv, split, nz, &err) == 0);
    static const char *threads[3] = {"1", "2", "7"};
    c5_block_range *ranges[3] = {NULL, NULL, NULL};
    char *store[3] = {NULL, NULL, NULL};
    long long bytes[3] = {0, 0, 0};
    for (int k = 0; k < 3 && ok; k++) {
        char dir[1200], cmd[1300];
        snprintf(dir, sizeof dir, "%s/t%s", test_cache(), threads[k]);
        setenv("C5_CACHE_DIR", "off", 1);
        setenv("C5_THREADS", threads[k], 1);
        c5_supervol fresh; /* ranges made anew: none kept yet */
        ok &= file_and_generator_scene(&s, &fresh, 20000) == 0;
        c5_block_range *owned;
        fresh.grid_id[0] = 0; /* not kept: made into owned */
        ok &= c5_block_range_of(&fresh, &owned, &err) != NULL && owned != NULL;
        ranges[k] = owned;
        c5_supervol_free(&fresh);
        setenv("C5_CACHE_DIR", dir, 1);
        c5_cell_store *cs;
        ok &= c5_cell_store_open(&sv, &c, &cs, &err) == 0 && cs && !c5_cell_store_was_cached(cs);
        c5_cell_store_close(cs);
        snprintf(cmd, sizeof cmd, "cat %s/cells-*.bin", dir);
        FILE *p = popen(cmd, "r");
        size_t cap = 1 << 22, n = 0;
        store[k] = malloc(cap);
        if (p && store[k])
            n = fread(store[k], 1, cap, p);
        if (p)
            pclose(p);
        bytes[k] = (long long)n;
        ok &= n > 0 && n < cap;
    }
    unsetenv("C5_THREADS");
    unsetenv("C5_CACHE_DIR");
    for (int k = 1; k < 3 && ok; k++)
        ok &= same_arrays(ranges[0], ranges[k]) && bytes[k] == bytes[0] && !memcmp(store[0], store[k], (size_t)bytes[0]);
    for (int k = 0; k < 3; k++)
        c5_block_range_free(ranges[k]), free(store[k]);
    c5_cells_free(&c);
    c5_supervol_free(&sv);
    CHECK(ok);
}
