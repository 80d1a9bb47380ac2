/* The value range of every 8^3 block of a grid, made once and cached (block_range.h). */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "atomic_file.h"
#include "block_range.h"
#include "cache_dir.h"
#include "worker_pool.h"

#define MAGIC "cube5 block ranges 2\n"

static pthread_mutex_t attach_lock = PTHREAD_MUTEX_INITIALIZER;

void c5_block_range_free(c5_block_range *r)
{
    if (!r)
        return;
    free(r->mn);
    free(r->mx);
    free(r->amn);
    free(r->amx);
    free(r);
}

static size_t count(const c5_block_range *r) { return r->bdims[0] * r->bdims[1] * r->bdims[2]; }

static c5_block_range *alloc_range(const c5_supervol *sv)
{
    c5_block_range *r = calloc(1, sizeof *r);
    if (!r)
        return NULL;
    for (int a = 0; a < 3; a++)
        r->bdims[a] = (sv->dims[a] + C5_RANGE_BLOCK - 1) / C5_RANGE_BLOCK;
    r->mn = malloc(count(r));
    r->mx = malloc(count(r));
    r->amn = malloc(count(r));
    r->amx = malloc(count(r));
    if (!r->mn || !r->mx || !r->amn || !r->amx) {
        c5_block_range_free(r);
        return NULL;
    }
    return r;
}

/* Folds one row into the columns' least and greatest. Vectorised: GCC 12 at -O2 leaves this
 * loop scalar, 3x slower over a 1 GiB grid. */
#if defined(__GNUC__) && !defined(__clang__)
__attribute__((optimize("tree-vectorize")))
#endif
static void fold_row(const uint8_t *restrict p, size_t nx, uint8_t *restrict cmn, uint8_t *restrict cmx)
{
    for (size_t x = 0; x < nx; x++) {
        uint8_t v = p[x], a = cmn[x], b = cmx[x];
        cmn[x] = v < a ? v : a;
        cmx[x] = v > b ? v : b;
    }
}

/* The least and greatest of each x over rows[0..n) into cmn, cmx. */
static void fold_columns(const uint8_t *const *rows, size_t n, size_t nx, uint8_t *cmn, uint8_t *cmx)
{
    memcpy(cmn, rows[0], nx);
    memcpy(cmx, rows[0], nx);
    for (size_t k = 1; k < n; k++)
        fold_row(rows[k], nx, cmn, cmx);
}

/* Voxels [lo, hi) of an axis of n around block b: lo = 8 b - pad, hi = 8 b + 8 + pad,
 * clamped. */
static void axis_span(size_t b, size_t n, size_t pad, size_t *lo, size_t *hi)
{
    *lo = b * C5_RANGE_BLOCK >= pad ? b * C5_RANGE_BLOCK - pad : 0;
    *hi = b * C5_RANGE_BLOCK + C5_RANGE_BLOCK + pad < n ? b * C5_RANGE_BLOCK + C5_RANGE_BLOCK + pad : n;
}

/* Each block's range along x from the columns' ranges: x in axis_span(bx, nx, pad). */
static void fold_blocks(const c5_block_range *r, size_t nx, size_t pad, const uint8_t *cmn, const uint8_t *cmx,
                        uint8_t *mn, uint8_t *mx)
{
    for (size_t bx = 0; bx < r->bdims[0]; bx++) {
        size_t x0, x1;
        axis_span(bx, nx, pad, &x0, &x1);
        uint8_t a = 255, b = 0;
        for (size_t x = x0; x < x1; x++) {
            a = cmn[x] < a ? cmn[x] : a;
            b = cmx[x] > b ? cmx[x] : b;
        }
        mn[bx] = a;
        mx[bx] = b;
    }
}

/* From the grid, the rows of blocks of one layer bz, one (by, bz) at a time: the 10 x 10 rows
 * of its apron (a resident grid in place, else read into slab), their columns' ranges over
 * the 8 x 8 inner rows and over all, then each block's. 0, or -1 with err. */
static int compute_layer(const c5_supervol *sv, c5_block_range *r, size_t bz, uint8_t *cmn, uint8_t *cmx,
                         uint8_t *slab, c5_err *err)
{
    enum { A = C5_RANGE_BLOCK + 2 };
    size_t nx = sv->dims[0], ny = sv->dims[1], nz = sv->dims[2];
    const uint8_t *inner[C5_RANGE_BLOCK * C5_RANGE_BLOCK], *outer[A * A];
    for (size_t by = 0; by < r->bdims[1]; by++) {
        size_t z0, z1, y0, y1;
        axis_span(bz, nz, 1, &z0, &z1);
        axis_span(by, ny, 1, &y0, &y1);
        if (!sv->v) {
            long lo[3] = {0, (long)y0, (long)z0}, hi[3] = {(long)nx, (long)y1, (long)z1};
            if (c5_supervol_read_box(sv, lo, hi, slab, err) != 0)
                return -1;
        }
        size_t ni = 0, no = 0;
        for (size_t z = z0; z < z1; z++)
            for (size_t y = y0; y < y1; y++) {
                const uint8_t *row = sv->v ? sv->v + (z * ny + y) * nx : slab + ((z - z0) * (y1 - y0) + y - y0) * nx;
                outer[no++] = row;
                if (z / C5_RANGE_BLOCK == bz && y / C5_RANGE_BLOCK == by)
                    inner[ni++] = row;
            }
        size_t base = (bz * r->bdims[1] + by) * r->bdims[0];
        fold_columns(inner, ni, nx, cmn, cmx);
        fold_blocks(r, nx, 0, cmn, cmx, r->mn + base, r->mx + base);
        fold_columns(outer, no, nx, cmn, cmx);
        fold_blocks(r, nx, 1, cmn, cmx, r->amn + base, r->amx + base);
    }
    /* out of core, a mapped file's planes of this layer are done with */
    long lo[3] = {0, 0, (long)(bz * C5_RANGE_BLOCK) - 1},
         hi[3] = {(long)nx, (long)ny, (long)((bz + 1) * C5_RANGE_BLOCK) + 1};
    c5_supervol_done_reading(sv, lo, hi);
    return 0;
}

/* The layers on the host's cores, each worker with its own buffers; each layer writes its own
 * blocks, so the ranges do not depend on the threads. */
typedef struct {
    const c5_supervol *sv;
    c5_block_range *r;
    uint8_t *buf[16];   /* per worker: cmn, cmx, slab */
    int *rc;            /* [layers] */
    c5_err *err;        /* [layers] */
} layers_job;

static void layer_job(void *ctx, size_t bz, int worker)
{
    layers_job *j = ctx;
    size_t nx = j->sv->dims[0];
    uint8_t *b = j->buf[worker];
    j->rc[bz] = compute_layer(j->sv, j->r, bz, b, b + nx, b + 2 * nx, &j->err[bz]);
}

static int compute(const c5_supervol *sv, c5_block_range *r, c5_err *err)
{
    enum { A = C5_RANGE_BLOCK + 2 };
    size_t nx = sv->dims[0], layers = r->bdims[2];
    int threads = c5_pool_cpus() < 16 ? c5_pool_cpus() : 16;
    c5_pool *pool = c5_pool_new(threads);
    layers_job j = {.sv = sv, .r = r, .rc = calloc(layers, sizeof *j.rc), .err = calloc(layers, sizeof *j.err)};
    int rc = pool && j.rc && j.err ? 0 : -1;
    for (int w = 0; rc == 0 && w < c5_pool_threads(pool); w++)
        if (!(j.buf[w] = malloc(2 * nx + (sv->v ? 0 : nx * A * A))))
            rc = -1;
    if (rc != 0) {
        c5_fail(err, "out of memory for the grid's block ranges");
    } else {
        c5_pool_run(pool, layers, 1, layer_job, &j);
        for (size_t bz = 0; bz < layers && rc == 0; bz++)
            if (j.rc[bz] != 0) {
                *err = j.err[bz];
                rc = -1;
            }
    }
    for (int w = 0; w < 16; w++)
        free(j.buf[w]);
    free(j.rc);
    free(j.err);
    c5_pool_free(pool);
    return rc;
}

/* What the ranges are kept by: a file's identity; an out-of-core grid's (its voxels are only
 * in its sources, which nobody changes through it); "" for any other grid, whose voxels the
 * caller may change after the build. */
static const char *identity(const c5_supervol *sv)
{
    return sv->file_id[0] ? sv->file_id : !sv->v && sv->store ? sv->grid_id : "";
}

static void header(const c5_supervol *sv, const c5_block_range *r, char *out, size_t n)
{
    snprintf(out, n, MAGIC "%s\nblock %d bdims %zu %zu %zu\n", identity(sv), C5_RANGE_BLOCK, r->bdims[0], r->bdims[1],
             r->bdims[2]);
}

/* 0: r filled from the cache file; -1: none, or not this grid's (it is then made again). */
static int cache_read(const char *path, const char *want, c5_block_range *r)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    size_t hl = strlen(want), n = count(r);
    char *got = malloc(hl + 1);
    int ok = got && fread(got, 1, hl, f) == hl && !memcmp(got, want, hl) && fread(r->mn, 1, n, f) == n &&
             fread(r->mx, 1, n, f) == n && fread(r->amn, 1, n, f) == n && fread(r->amx, 1, n, f) == n &&
             fgetc(f) == EOF;
    free(got);
    fclose(f);
    return ok ? 0 : -1;
}

/* 0: written. A cache that cannot be written costs the next run the pass, nothing else. */
static int cache_write(const char *dir, const char *path, const char *head, const c5_block_range *r)
{
    c5_afile a;
    c5_err e;
    if (c5_cache_make_room(dir, strlen(head) + 4 * count(r)) != 0 || c5_afile_open(&a, path, &e) != 0)
        return -1;
    c5_afile_write(&a, head, strlen(head));
    c5_afile_write(&a, r->mn, count(r));
    c5_afile_write(&a, r->mx, count(r));
    c5_afile_write(&a, r->amn, count(r));
    c5_afile_write(&a, r->amx, count(r));
    return c5_afile_commit(&a, &e);
}

/* A file's grid: the cache's copy if it is this file's, else made and cached. */
static c5_block_range *make_for_file(const c5_supervol *sv, c5_err *err)
{
    c5_block_range *r = alloc_range(sv);
    if (!r) {
        c5_fail(err, "out of memory for the grid's block ranges");
        return NULL;
    }
    char dir[3072], path[3200], head[sizeof sv->grid_id + 128];
    header(sv, r, head, sizeof head);
    int cached = c5_cache_dir(dir, sizeof dir) == 0;
    if (cached) {
        snprintf(path, sizeof path, "%s/ranges-%016llx.bin", dir, (unsigned long long)c5_cache_hash(head));
        if (cache_read(path, head, r) == 0) {
            c5_cache_touch(path);
            r->origin = C5_RANGE_FROM_CACHE;
            return r;
        }
    }
    if (compute(sv, r, err) != 0) {
        c5_block_range_free(r);
        return NULL;
    }
    r->origin = cached && cache_write(dir, path, head, r) == 0 ? C5_RANGE_CACHED_NOW : C5_RANGE_COMPUTED;
    return r;
}

const c5_block_range *c5_block_range_of(const c5_supervol *sv, c5_block_range **owned, c5_err *err)
{
    *owned = NULL;
    if (!identity(sv)[0]) {
        c5_block_range *r = alloc_range(sv);
        if (!r) {
            c5_fail(err, "out of memory for the grid's block ranges");
            return NULL;
        }
        if (compute(sv, r, err) != 0) {
            c5_block_range_free(r);
            return NULL;
        }
        return *owned = r;
    }
    pthread_mutex_lock(&attach_lock);
    c5_supervol *w = (c5_supervol *)sv; /* the ranges are a cache of the grid's own: not its state */
    if (!w->ranges)
        w->ranges = make_for_file(sv, err);
    const c5_block_range *r = w->ranges;
    pthread_mutex_unlock(&attach_lock);
    return r;
}
