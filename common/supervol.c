#include "supervol.h"
#include "block_range.h"
#include "cache_dir.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <pthread.h>
#include <sys/mman.h>
#include <unistd.h>

#include "generators.h"
#include "voxsrc.h"
#include "worker_pool.h"

static const char *base_name(const char *path)
{
    const char *b = strrchr(path, '/');
    return b ? b + 1 : path;
}

/* ---- the store: sources and brick cache ------------------------------------------------- */

/* A set of the brick cache: `ways` slots, least recently used evicted, one lock. */
typedef struct {
    pthread_mutex_t lock;
    unsigned long long tick, hits, misses;
} cache_set;

struct c5_svstore {
    int n;
    c5_voxsrc *src[C5_MAX_VOLUMES];
    long off[C5_MAX_VOLUMES][3];
    unsigned fill;
    size_t budget;
    size_t nb[3];                 /* bricks per axis */
    size_t nsets, ways;
    cache_set *set;
    uint64_t *tag;                /* [nsets * ways]: brick id + 1, 0 = empty */
    unsigned long long *used;     /* [nsets * ways]: the set's tick at the last use */
    uint8_t *data;                /* [nsets * ways] bricks of C5_BRICK^3 voxels, x fastest */
    /* The grid is one uint8 file: also mapped read-only, for the board's cell reads in place
     * (c5_supervol_data); map_data NULL otherwise. */
    void *map_base;
    size_t map_len;
    const uint8_t *map_data;
};

#define BRICK_VOXELS ((size_t)1 << (3 * C5_BRICK_LOG2))
#define CACHE_WAYS 8
_Static_assert(C5_MEM_BUDGET_MIN == CACHE_WAYS * BRICK_VOXELS, "the budget's floor is one set of the cache");

static void store_free(struct c5_svstore *st)
{
    if (!st)
        return;
    for (int i = 0; i < st->n; i++)
        c5_voxsrc_close(st->src[i]);
    if (st->set)
        for (size_t i = 0; i < st->nsets; i++)
            pthread_mutex_destroy(&st->set[i].lock);
    free(st->set);
    free(st->tag);
    free(st->used);
    free(st->data);
    if (st->map_base)
        munmap(st->map_base, st->map_len);
    free(st);
}

/* Voxels [lo, hi) inside the grid from the sources: grid.fill, then each source in the
 * scene's order (a later one covers an earlier one), as the grid was always pasted. */
static int sources_read(const struct c5_svstore *st, const size_t lo[3], const size_t hi[3], uint8_t *out, size_t sy,
                        size_t sz, c5_err *err)
{
    size_t w = hi[0] - lo[0];
    int covered = 0; /* a source covers the whole box: grid.fill shows nowhere */
    for (int i = 0; i < st->n && !covered; i++) {
        const size_t *d = c5_voxsrc_dims(st->src[i]);
        covered = 1;
        for (int a = 0; a < 3; a++)
            covered &= (size_t)st->off[i][a] <= lo[a] && hi[a] <= (size_t)st->off[i][a] + d[a];
    }
    for (size_t z = lo[2]; z < hi[2] && !covered; z++)
        for (size_t y = lo[1]; y < hi[1]; y++)
            memset(out + (z - lo[2]) * sz + (y - lo[1]) * sy, (int)st->fill, w);
    for (int i = 0; i < st->n; i++) {
        const size_t *d = c5_voxsrc_dims(st->src[i]);
        size_t slo[3], shi[3];
        int empty = 0;
        for (int a = 0; a < 3; a++) {
            size_t o = (size_t)st->off[i][a];
            size_t b0 = lo[a] > o ? lo[a] : o, b1 = hi[a] < o + d[a] ? hi[a] : o + d[a];
            empty |= b0 >= b1;
            slo[a] = b0 - o;
            shi[a] = b1 - o;
        }
        if (empty)
            continue;
        uint8_t *dst = out + (slo[2] + (size_t)st->off[i][2] - lo[2]) * sz +
                       (slo[1] + (size_t)st->off[i][1] - lo[1]) * sy + (slo[0] + (size_t)st->off[i][0] - lo[0]);
        if (c5_voxsrc_read(st->src[i], slo, shi, dst, sy, sz, err) != 0)
            return -1;
    }
    return 0;
}

static size_t brick_set(const struct c5_svstore *st, uint64_t id)
{
    return (size_t)((id * 0x9E3779B97F4A7C15ull) >> 17) % st->nsets;
}

/* Voxels [lo, hi) inside the grid through the brick cache: one set locked at a time, each
 * brick's part copied out under its lock. A missing brick is read from the sources into the
 * set's least recently used slot. */
static int cached_read(const c5_supervol *sv, const size_t lo[3], const size_t hi[3], uint8_t *out, size_t sy,
                       size_t sz, c5_err *err)
{
    struct c5_svstore *st = sv->store;
    size_t b0[3], b1[3];
    for (int a = 0; a < 3; a++) {
        b0[a] = lo[a] >> C5_BRICK_LOG2;
        b1[a] = (hi[a] - 1) >> C5_BRICK_LOG2;
    }
    for (size_t bz = b0[2]; bz <= b1[2]; bz++)
        for (size_t by = b0[1]; by <= b1[1]; by++)
            for (size_t bx = b0[0]; bx <= b1[0]; bx++) {
                uint64_t id = ((uint64_t)bz * st->nb[1] + by) * st->nb[0] + bx;
                size_t si = brick_set(st, id);
                cache_set *set = &st->set[si];
                uint64_t *tag = st->tag + si * st->ways;
                unsigned long long *used = st->used + si * st->ways;
                pthread_mutex_lock(&set->lock);
                size_t way = st->ways;
                for (size_t k = 0; k < st->ways; k++)
                    if (tag[k] == id + 1) {
                        way = k;
                        break;
                    }
                if (way < st->ways) {
                    set->hits++;
                } else {
                    set->misses++;
                    way = 0;
                    for (size_t k = 1; k < st->ways && tag[way]; k++)
                        if (!tag[k] || used[k] < used[way])
                            way = k;
                    tag[way] = 0;
                    size_t org[3] = {bx << C5_BRICK_LOG2, by << C5_BRICK_LOG2, bz << C5_BRICK_LOG2}, end[3];
                    for (int a = 0; a < 3; a++)
                        end[a] = org[a] + C5_BRICK < sv->dims[a] ? org[a] + C5_BRICK : sv->dims[a];
                    if (sources_read(st, org, end, st->data + (si * st->ways + way) * BRICK_VOXELS, C5_BRICK,
                                     (size_t)C5_BRICK * C5_BRICK, err) != 0) {
                        pthread_mutex_unlock(&set->lock);
                        return -1;
                    }
                    tag[way] = id + 1;
                }
                used[way] = ++set->tick;
                const uint8_t *brick = st->data + (si * st->ways + way) * BRICK_VOXELS;
                size_t org[3] = {bx << C5_BRICK_LOG2, by << C5_BRICK_LOG2, bz << C5_BRICK_LOG2}, c0[3], c1[3];
                for (int a = 0; a < 3; a++) {
                    c0[a] = lo[a] > org[a] ? lo[a] : org[a];
                    c1[a] = hi[a] < org[a] + C5_BRICK ? hi[a] : org[a] + C5_BRICK;
                }
                for (size_t z = c0[2]; z < c1[2]; z++)
                    for (size_t y = c0[1]; y < c1[1]; y++)
                        memcpy(out + (z - lo[2]) * sz + (y - lo[1]) * sy + (c0[0] - lo[0]),
                               brick + (((z - org[2]) << C5_BRICK_LOG2) + (y - org[1])) * C5_BRICK + (c0[0] - org[0]),
                               c1[0] - c0[0]);
                pthread_mutex_unlock(&set->lock);
            }
    return 0;
}

/* Voxels [lo, hi) inside the grid, from wherever they are. */
static int core_read(const c5_supervol *sv, const size_t lo[3], const size_t hi[3], uint8_t *out, size_t sy, size_t sz,
                     c5_err *err)
{
    if (sv->v) {
        size_t w = hi[0] - lo[0];
        for (size_t z = lo[2]; z < hi[2]; z++)
            for (size_t y = lo[1]; y < hi[1]; y++)
                memcpy(out + (z - lo[2]) * sz + (y - lo[1]) * sy,
                       sv->v + (z * sv->dims[1] + y) * sv->dims[0] + lo[0], w);
        return 0;
    }
    if (!sv->store)
        return c5_fail(err, "the grid's voxels are not here (a shell: the host holds them)");
    size_t n = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    if (n >= C5_SV_DIRECT_VOXELS && sv->store->map_data) {
        /* one mapped file: its rows copied (no read of the bytes around them, no system call
         * a row); the reader drops the pages when it is done with the span
         * (c5_supervol_done_reading) */
        const uint8_t *d = sv->store->map_data;
        size_t w = hi[0] - lo[0];
        for (size_t z = lo[2]; z < hi[2]; z++)
            for (size_t y = lo[1]; y < hi[1]; y++)
                memcpy(out + (z - lo[2]) * sz + (y - lo[1]) * sy, d + (z * sv->dims[1] + y) * sv->dims[0] + lo[0], w);
        return 0;
    }
    if (n >= C5_SV_DIRECT_VOXELS)
        return sources_read(sv->store, lo, hi, out, sy, sz, err);
    return cached_read(sv, lo, hi, out, sy, sz, err);
}

static long clampl(long i, size_t n) { return i < 0 ? 0 : i >= (long)n ? (long)n - 1 : i; }

int c5_supervol_read_box(const c5_supervol *sv, const long lo[3], const long hi[3], uint8_t *out, c5_err *err)
{
    size_t w[3], clo[3], chi[3];
    int inside = 1;
    for (int a = 0; a < 3; a++) {
        if (hi[a] <= lo[a])
            return 0;
        w[a] = (size_t)(hi[a] - lo[a]);
        clo[a] = (size_t)clampl(lo[a], sv->dims[a]);
        chi[a] = (size_t)clampl(hi[a] - 1, sv->dims[a]) + 1;
        inside &= lo[a] >= 0 && hi[a] <= (long)sv->dims[a];
    }
    if (inside)
        return core_read(sv, clo, chi, out, w[0], w[0] * w[1], err);
    /* the part inside the grid, then every voxel of the box from its clamped position */
    size_t cw[3] = {chi[0] - clo[0], chi[1] - clo[1], chi[2] - clo[2]}, n = cw[0] * cw[1] * cw[2];
    uint8_t small[4096], *tmp = n <= sizeof small ? small : malloc(n);
    if (!tmp)
        return c5_fail(err, "out of memory for a box of %zu voxels", n);
    int rc = core_read(sv, clo, chi, tmp, cw[0], cw[0] * cw[1], err);
    /* Along x a row is the edge voxel before the grid, the grid's span, the edge voxel after
     * it: two fills and one copy (a clamp per voxel was most of a cell fetch's cost). */
    long nx = (long)sv->dims[0], wx = (long)w[0], la = lo[0] < 0 ? -lo[0] : 0, lb = nx - lo[0];
    la = la > wx ? wx : la;
    lb = lb > wx ? wx : lb < la ? la : lb;
    size_t xa = (size_t)la, xb = (size_t)lb;
    if (rc == 0)
        for (size_t z = 0; z < w[2]; z++)
            for (size_t y = 0; y < w[1]; y++) {
                const uint8_t *src = tmp + ((size_t)clampl(lo[2] + (long)z, sv->dims[2]) - clo[2]) * cw[0] * cw[1] +
                                     ((size_t)clampl(lo[1] + (long)y, sv->dims[1]) - clo[1]) * cw[0];
                uint8_t *dst = out + (z * w[1] + y) * w[0];
                memset(dst, src[0], xa);
                if (xb > xa)
                    memcpy(dst + xa, src + (size_t)(lo[0] + (long)xa) - clo[0], xb - xa);
                memset(dst + xb, src[cw[0] - 1], w[0] - xb);
            }
    if (tmp != small)
        free(tmp);
    return rc;
}

void c5_supervol_read_box_or_exit(const c5_supervol *sv, const long lo[3], const long hi[3], uint8_t *out)
{
    c5_err err;
    if (c5_supervol_read_box(sv, lo, hi, out, &err) != 0) {
        fprintf(stderr, "cube5: error: %s\n", err.msg);
        exit(C5_EXIT_INPUT);
    }
}

unsigned c5_supervol_at_store(const c5_supervol *sv, long i, long j, long k)
{
    long lo[3] = {i, j, k}, hi[3] = {i + 1, j + 1, k + 1};
    uint8_t v;
    c5_supervol_read_box_or_exit(sv, lo, hi, &v);
    return v;
}

int c5_supervol_cast_refusal(const c5_supervol *sv, const char *what, c5_err *err)
{
    size_t budget = sv->store ? sv->store->budget : 0;
    return c5_fail(err, "%s: the grid of %zux%zux%zu voxels is above the memory budget (C5_MEM_BUDGET, here %zu "
                        "bytes): the caster needs the whole grid in memory; raise C5_MEM_BUDGET or render with cref",
                   what, sv->dims[0], sv->dims[1], sv->dims[2], budget);
}

void c5_supervol_cache_stats_get(const c5_supervol *sv, c5_supervol_cache_stats *out)
{
    memset(out, 0, sizeof *out);
    const struct c5_svstore *st = sv->store;
    if (!st)
        return;
    for (size_t i = 0; i < st->nsets; i++) {
        pthread_mutex_lock(&st->set[i].lock);
        out->hits += st->set[i].hits;
        out->misses += st->set[i].misses;
        pthread_mutex_unlock(&st->set[i].lock);
    }
    out->bricks = st->nsets * st->ways;
    out->bytes = out->bricks * BRICK_VOXELS;
}

/* The brick cache of `budget` bytes (at least one brick) over the grid's dims. */
static int cache_make(struct c5_svstore *st, const size_t dims[3], size_t budget, c5_err *err)
{
    for (int a = 0; a < 3; a++)
        st->nb[a] = (dims[a] + C5_BRICK - 1) >> C5_BRICK_LOG2;
    size_t slots = budget / BRICK_VOXELS;
    if (slots < 1)
        slots = 1;
    st->ways = slots < CACHE_WAYS ? slots : CACHE_WAYS;
    st->nsets = slots / st->ways;
    size_t n = st->nsets * st->ways;
    st->set = calloc(st->nsets, sizeof *st->set);
    st->tag = calloc(n, sizeof *st->tag);
    st->used = calloc(n, sizeof *st->used);
    st->data = malloc(n * BRICK_VOXELS);
    if (!st->set || !st->tag || !st->used || !st->data) {
        free(st->set);
        st->set = NULL;
        return c5_fail(err, "out of memory for a brick cache of %zu bytes (C5_MEM_BUDGET)", n * BRICK_VOXELS);
    }
    for (size_t i = 0; i < st->nsets; i++)
        pthread_mutex_init(&st->set[i].lock, NULL);
    return 0;
}

int c5_env_bytes(const char *name, size_t dflt, size_t *out, c5_err *err)
{
    const char *e = getenv(name);
    *out = dflt;
    if (!e)
        return 0;
    const char *p = e;
    unsigned long long v = 0;
    int digits = 0;
    for (; *p >= '0' && *p <= '9'; p++, digits++) {
        if (v > (~0ull - 9) / 10)
            return c5_fail(err, "%s: '%.40s' is too large", name, e);
        v = v * 10 + (unsigned)(*p - '0');
    }
    int shift = 0;
    if (*p) {
        const char *units = "KMGT", *u = strchr(units, *p == 'k' ? 'K' : *p);
        if (!u || !*u)
            shift = -1;
        else {
            shift = 10 * (int)(u - units + 1);
            p++;
            if (*p == 'i' && p[1] == 'B')
                p += 2;
            else if (*p == 'B')
                p++;
        }
    }
    if (!digits || shift < 0 || *p)
        return c5_fail(err, "%s: expected a byte count such as 268435456, 512M or 4G, got '%.40s'", name, e);
    if (v > (SIZE_MAX >> shift) || v == 0)
        return c5_fail(err, "%s: '%.40s' is %s", name, e, v ? "too large" : "zero: give at least one byte");
    *out = (size_t)(v << shift);
    return 0;
}

int c5_mem_budget(size_t *out, c5_err *err)
{
    if (c5_env_bytes("C5_MEM_BUDGET", C5_MEM_BUDGET_DEFAULT, out, err) != 0)
        return -1;
    if (*out < C5_MEM_BUDGET_MIN)
        return c5_fail(err, "C5_MEM_BUDGET: '%.40s' is below the least a grid is held in, %zu bytes (%d bricks of "
                            "%d^3 voxels: the 2x2x2 voxels of one sample may lie in 8)",
                       getenv("C5_MEM_BUDGET"), (size_t)C5_MEM_BUDGET_MIN, CACHE_WAYS, C5_BRICK);
    return 0;
}

/* The rule of docs/scene-format.md ("Spacing"): the scene's grid.spacing when given, else
 * the spacing the volume files state (every file that states one must state the same: the
 * grid has one), else (1, 1, 1). */
static int resolve_spacing(const c5_scene *s, const double file_sp[][3], c5_supervol *out, c5_err *err)
{
    if (s->grid.has_spacing) {
        snprintf(out->spacing_source, sizeof out->spacing_source, "scene");
        return 0;
    }
    int from = -1;
    for (int i = 0; i < s->n_volumes; i++) {
        const double *sp = file_sp[i];
        if (!(sp[0] > 0))
            continue;
        if (from < 0) {
            from = i;
            continue;
        }
        const double *f = file_sp[from];
        for (int a = 0; a < 3; a++)
            if (fabs(sp[a] - f[a]) > 1e-9 * fmax(sp[a], f[a]))
                return c5_fail(err, "%s: spacing %g %g %g differs from %s's %g %g %g: the grid has one spacing "
                                    "(give grid.spacing in the scene)", s->volumes[i].path, sp[0], sp[1], sp[2],
                               s->volumes[from].path, f[0], f[1], f[2]);
    }
    if (from < 0) {
        snprintf(out->spacing_source, sizeof out->spacing_source, "default");
        return 0;
    }
    out->spacing = v3(file_sp[from][0], file_sp[from][1], file_sp[from][2]);
    snprintf(out->spacing_source, sizeof out->spacing_source, "file %s", base_name(s->volumes[from].path));
    return 0;
}

/* A resident grid is read from its sources in slabs of SLAB z planes, on every core
 * (c5_pool_cpus): a generated volume's voxels are each a function of their place, a file's
 * are read with pread, so the bytes do not depend on the slabs or the threads. A failure is
 * the first failing slab's, in z order, whichever thread met it first. */
#define SLAB 4

typedef struct {
    const struct c5_svstore *st;
    const size_t *dims;
    uint8_t *v;
    int *rc;     /* [slabs] */
    c5_err *err; /* [slabs] */
} slab_job;

static void read_slab(void *ctx, size_t i, int worker)
{
    slab_job *j = ctx;
    (void)worker;
    size_t z = i * SLAB, plane = j->dims[0] * j->dims[1];
    size_t lo[3] = {0, 0, z}, hi[3] = {j->dims[0], j->dims[1], z + SLAB < j->dims[2] ? z + SLAB : j->dims[2]};
    j->rc[i] = sources_read(j->st, lo, hi, j->v + z * plane, j->dims[0], plane, &j->err[i]);
}

static int resident_read(const struct c5_svstore *st, const size_t dims[3], uint8_t *v, c5_err *err)
{
    size_t slabs = (dims[2] + SLAB - 1) / SLAB;
    slab_job j = {.st = st, .dims = dims, .v = v, .rc = calloc(slabs, sizeof *j.rc), .err = calloc(slabs, sizeof *j.err)};
    int threads = c5_pool_cpus() < (int)slabs ? c5_pool_cpus() : (int)slabs;
    c5_pool *pool = j.rc && j.err ? c5_pool_new(threads) : NULL;
    int rc = 0;
    if (!pool) {
        rc = c5_fail(err, "grid: out of memory for reading its sources");
    } else {
        c5_pool_run(pool, slabs, 1, read_slab, &j);
        for (size_t i = 0; i < slabs && rc == 0; i++)
            if (j.rc[i] != 0) {
                *err = j.err[i];
                rc = -1;
            }
    }
    c5_pool_free(pool);
    free(j.rc);
    free(j.err);
    return rc;
}

int c5_supervol_build(const c5_scene *s, c5_supervol *out, c5_err *err)
{
    size_t budget, cache_max;
    if (c5_mem_budget(&budget, err) != 0 || c5_cache_max(&cache_max, err) != 0 || c5_pool_threads_env(err) != 0) {
        memset(out, 0, sizeof *out);
        return -1;
    }
    return c5_supervol_build_budget(s, budget, out, err);
}

static void grid_identity(const struct c5_svstore *st, c5_supervol *out)
{
    size_t used = (size_t)snprintf(out->grid_id, sizeof out->grid_id, "grid %zu %zu %zu fill %u", out->dims[0],
                                   out->dims[1], out->dims[2], st->fill);
    for (int i = 0; i < st->n; i++) {
        char id[320];
        if (c5_voxsrc_identity(st->src[i], id, sizeof id) != 0 || used >= sizeof out->grid_id) {
            out->grid_id[0] = 0;
            return;
        }
        used += (size_t)snprintf(out->grid_id + used, sizeof out->grid_id - used, "\n%s at %ld %ld %ld", id,
                                 st->off[i][0], st->off[i][1], st->off[i][2]);
    }
    if (used >= sizeof out->grid_id)
        out->grid_id[0] = 0;
}

int c5_supervol_build_budget(const c5_scene *s, size_t budget, c5_supervol *out, c5_err *err)
{
    memset(out, 0, sizeof *out);
    out->spacing = s->grid.spacing;
    out->origin = s->grid.origin;
    if (s->n_volumes == 0)
        return 0;

    struct c5_svstore *st = calloc(1, sizeof *st);
    if (!st)
        return c5_fail(err, "out of memory for the grid's sources");
    st->fill = s->grid.fill;
    double file_sp[C5_MAX_VOLUMES][3];
    size_t need[3] = {0, 0, 0};
    int rc = -1;
    for (int i = 0; i < s->n_volumes; i++) {
        if (c5_voxsrc_open(&s->volumes[i], &st->src[i], err) != 0)
            goto done;
        st->n++;
        const size_t *dims = c5_voxsrc_dims(st->src[i]);
        memcpy(st->off[i], s->volumes[i].offset, sizeof st->off[i]);
        out->n_sources++;
        for (int a = 0; a < 3; a++)
            if ((size_t)s->volumes[i].offset[a] + dims[a] > need[a])
                need[a] = (size_t)s->volumes[i].offset[a] + dims[a];
    }
    for (int a = 0; a < 3; a++) {
        out->dims[a] = s->grid.dims[a] ? s->grid.dims[a] : need[a];
        if (need[a] > out->dims[a]) {
            c5_fail(err, "grid.dims: the volumes need %zux%zux%zu voxels, the grid has %zux%zux%zu", need[0], need[1],
                    need[2], s->grid.dims[0], s->grid.dims[1], s->grid.dims[2]);
            goto done;
        }
    }
    size_t n;
    if (c5_dims_product(out->dims, &n) != 0) {
        c5_fail(err, "grid: %zux%zux%zu voxels is too large", out->dims[0], out->dims[1], out->dims[2]);
        goto done;
    }
    /* the grid's size is settled and within its limits: now the files' data (checks,
     * inflating, the window pass) */
    for (int i = 0; i < st->n; i++) {
        if (c5_voxsrc_prepare(st->src[i], err) != 0)
            goto done;
        memcpy(file_sp[i], c5_voxsrc_spacing(st->src[i]), sizeof file_sp[i]);
        snprintf(out->source_label[i], sizeof out->source_label[i], "%s", c5_voxsrc_label(st->src[i]));
    }
    if (resolve_spacing(s, file_sp, out, err) != 0)
        goto done;
    if (s->grid.size > 0) {
        c5_vec3 ext = v3(out->dims[0] * out->spacing.x, out->dims[1] * out->spacing.y, out->dims[2] * out->spacing.z);
        out->spacing = v3_scale(out->spacing, s->grid.size / v3_maxc(ext));
    }
    if (s->grid.has_center) {
        c5_vec3 half = v3(out->dims[0] * out->spacing.x / 2, out->dims[1] * out->spacing.y / 2,
                          out->dims[2] * out->spacing.z / 2);
        out->origin = v3_sub(s->grid.center, half);
    }
    /* Bounded work per ray: the step (render.step, else the smallest spacing) against the
     * diagonal. A tiny step, or one spacing far below the others, would ask for ~1e11
     * samples per ray. */
    c5_vec3 ext = v3(out->dims[0] * out->spacing.x, out->dims[1] * out->spacing.y, out->dims[2] * out->spacing.z);
    double step = s->render.step > 0 ? s->render.step : c5_supervol_min_spacing(out);
    double samples = v3_len(ext) / step;
    if (!(samples <= C5_MAX_RAY_SAMPLES)) {
        /* name what set the step: the scene's render.step, else the spacing, which is the
         * scene's grid.spacing or a volume file's own */
        char key[200] = "render.step";
        if (!(s->render.step > 0))
            snprintf(key, sizeof key, "%s%s", strcmp(out->spacing_source, "scene") ? "the spacing of " : "grid.",
                     strcmp(out->spacing_source, "scene") ? out->spacing_source : "spacing");
        c5_fail(err, "%s%s%s: a ray across the grid (%g world units) takes %g samples of %g; at most %d (a larger "
                "render.step, or spacing components closer to each other)",
                s->source, *s->source ? ": " : "", key, v3_len(ext), samples, step, C5_MAX_RAY_SAMPLES);
        goto done;
    }
    int one_source = st->n == 1 && !st->off[0][0] && !st->off[0][1] && !st->off[0][2] &&
                     !memcmp(c5_voxsrc_dims(st->src[0]), out->dims, sizeof out->dims);
    if (!one_source || c5_voxsrc_is_generator(st->src[0]) ||
        c5_voxsrc_identity(st->src[0], out->file_id, sizeof out->file_id) != 0)
        out->file_id[0] = 0;
    grid_identity(st, out);
    if (n <= budget && one_source) {
        const uint8_t *data;
        if (c5_voxsrc_map(st->src[0], &out->map_base, &out->map_len, &data) == 0) {
            out->v = (uint8_t *)data; /* PROT_READ: a write would fault, never reach the file */
            rc = 0;
            goto done;
        }
    }
    if (n <= budget) {
        out->v = malloc(n);
        if (!out->v) {
            c5_fail(err, "grid: out of memory for %zu voxels (C5_MEM_BUDGET is %zu bytes)", n, budget);
            goto done;
        }
        rc = resident_read(st, out->dims, out->v, err);
        goto done;
    }
    st->budget = budget;
    if (cache_make(st, out->dims, budget, err) != 0)
        goto done;
    if (one_source && c5_voxsrc_map(st->src[0], &st->map_base, &st->map_len, &st->map_data) != 0)
        st->map_data = NULL; /* the board copies its cells from the sources instead */
    out->store = st;
    st = NULL;
    rc = 0;
done:
    store_free(st);
    if (rc != 0) {
        if (out->map_base)
            munmap(out->map_base, out->map_len);
        else
            free(out->v);
        out->v = NULL;
        out->map_base = NULL;
        out->store = NULL;
    }
    return rc;
}

void c5_supervol_free(c5_supervol *sv)
{
    if (sv->map_base)
        munmap(sv->map_base, sv->map_len);
    else
        free(sv->v);
    store_free(sv->store);
    c5_block_range_free(sv->ranges);
    memset(sv, 0, sizeof *sv);
}

const uint8_t *c5_supervol_data(const c5_supervol *sv)
{
    return sv->v ? sv->v : sv->store ? sv->store->map_data : NULL;
}

/* madvise over the pages of voxels [lo, hi) of a mapped out-of-core grid: per z plane (the
 * kernel reads ahead what a plane's rows span), or the whole span at once. */
static void advise_box(const c5_supervol *sv, const long lo[3], const long hi[3], int advice, int per_plane)
{
    if (sv->v || !sv->store || !sv->store->map_data)
        return;
    const struct c5_svstore *st = sv->store;
    size_t nx = sv->dims[0], plane = nx * sv->dims[1], page = (size_t)sysconf(_SC_PAGESIZE);
    size_t l[3], h[3];
    for (int a = 0; a < 3; a++) {
        l[a] = lo[a] < 0 ? 0 : (size_t)lo[a];
        h[a] = hi[a] > (long)sv->dims[a] ? sv->dims[a] : (size_t)hi[a];
        if (l[a] >= h[a])
            return;
    }
    uintptr_t base = (uintptr_t)st->map_data;
    for (size_t z = l[2]; z < h[2]; z = per_plane ? z + 1 : h[2]) {
        uintptr_t a = base + z * plane + l[1] * nx + l[0];
        uintptr_t b = base + (per_plane ? z : h[2] - 1) * plane + (h[1] - 1) * nx + h[0];
        a &= ~(uintptr_t)(page - 1);
        b = (b + page - 1) & ~(uintptr_t)(page - 1);
        if (a < (uintptr_t)st->map_base)
            a = (uintptr_t)st->map_base;
        if (b > (uintptr_t)st->map_base + st->map_len)
            b = (uintptr_t)st->map_base + st->map_len;
        madvise((void *)a, b - a, advice);
    }
}

void c5_supervol_will_read(const c5_supervol *sv, const long lo[3], const long hi[3])
{
    advise_box(sv, lo, hi, MADV_WILLNEED, 1);
}

void c5_supervol_done_reading(const c5_supervol *sv, const long lo[3], const long hi[3])
{
    advise_box(sv, lo, hi, MADV_DONTNEED, 0);
}

uint8_t *c5_supervol_detach(c5_supervol *sv)
{
    uint8_t *v = sv->v;
    if (sv->map_base) {
        size_t n = sv->dims[0] * sv->dims[1] * sv->dims[2];
        if ((v = malloc(n)) != NULL)
            memcpy(v, sv->v, n);
    } else {
        sv->v = NULL;
    }
    c5_supervol_free(sv);
    return v;
}
void c5_supervol_marschner_lobb(const c5_supervol *sv, double f_m, double alpha, c5_vec3 p, double *value,
                                c5_vec3 *grad)
{
    double ext[3] = {sv->dims[0] * sv->spacing.x, sv->dims[1] * sv->spacing.y, sv->dims[2] * sv->spacing.z};
    double q[3] = {2 * (p.x - sv->origin.x) / ext[0] - 1, 2 * (p.y - sv->origin.y) / ext[1] - 1,
                   2 * (p.z - sv->origin.z) / ext[2] - 1};
    *value = 255 * c5_marschner_lobb(q[0], q[1], q[2], f_m, alpha);
    if (grad) {
        double g[3];
        c5_marschner_lobb_grad(q[0], q[1], q[2], f_m, alpha, g);
        *grad = v3(255 * g[0] * 2 / ext[0], 255 * g[1] * 2 / ext[1], 255 * g[2] * 2 / ext[2]);
    }
}
