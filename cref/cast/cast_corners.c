/* The corner rays on tile borders, walked once per frame (docs/caster.md, "Shared corners").
 *
 * With approximation, a tile's producer walks the rays through its (16/k + 1)^2 subtile
 * corners; the ones on the tile's edges are also corners of the 1 to 3 tiles beside it, which
 * other threads may produce at the same time. Each such corner has an entry here: the first
 * producer to reach it claims it, walks the ray and publishes the list and hash bits; later
 * ones copy them, and one that arrives while the walk is under way waits for it (a microsecond
 * or so; the walker never waits for anything while it holds a claim). So every corner is
 * walked exactly once, the producer's ray count is the same on every run, and a list is a
 * function of its ray alone, so the tasks are the same bits whoever walked it. A list longer
 * than an entry holds is not kept: each tile that needs it walks it again (counted each time). */
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "cast_internal.h"

enum { FREE, BUSY, READY, TOO_LONG };
enum { KEEP = 15 }; /* segments an entry holds: with the hash, 256 bytes */

typedef struct {
    int n;
    c5_cast_seg seg[KEEP];
    uint64_t hash[C5_CAST_HASH_WORDS];
} entry;

/* The states apart from the entries: a frame clears 17 kB of states (4386 corners at 256^2,
 * k = 2), not a line of each of 1.1 MB of entries (that took 0.6 ms, before any thread ran);
 * an entry is written first by the producer that walks its corner. */
struct c5_cast_corners {
    int cols, rows;         /* corners per image row and column: ceil(w / k) + 1, ceil(h / k) + 1 */
    int per_tile;           /* corner steps per tile side: C5_CAST_TILE / k */
    int n_vert;             /* entries of the vertical borders (every row of them), then horizontal */
    atomic_int *state;
    entry *e;
};

c5_cast_corners *c5_cast_corners_new(int w, int h, int k)
{
    c5_cast_corners *c = malloc(sizeof *c);
    if (!c)
        return NULL;
    c->cols = (w + k - 1) / k + 1, c->rows = (h + k - 1) / k + 1, c->per_tile = C5_CAST_TILE / k;
    int vcols = (c->cols - 1) / c->per_tile + 1, hrows = (c->rows - 1) / c->per_tile + 1;
    c->n_vert = vcols * c->rows;
    size_t n = (size_t)c->n_vert + (size_t)hrows * (size_t)c->cols;
    c->state = malloc(n * sizeof *c->state);
    c->e = malloc(n * sizeof *c->e);
    if (!c->state || !c->e) {
        c5_cast_corners_free(c);
        return NULL;
    }
    for (size_t i = 0; i < n; i++)
        atomic_init(&c->state[i], FREE);
    return c;
}

void c5_cast_corners_free(c5_cast_corners *c)
{
    if (c)
        free(c->state), free(c->e);
    free(c);
}

/* Corner (a, b) is pixel (a k, b k). A corner on a vertical tile border lives with the vertical
 * borders (tile corners included); one on a horizontal border only, with the horizontal ones. */
long c5_cast_corners_at(const c5_cast_corners *c, int a, int b)
{
    if (a % c->per_tile == 0)
        return (long)(a / c->per_tile) * c->rows + b;
    if (b % c->per_tile == 0)
        return c->n_vert + (long)(b / c->per_tile) * c->cols + a;
    return -1;
}

int c5_cast_corner_take(c5_cast_corners *c, long i, c5_cast_seg *out, uint64_t *hash)
{
    int s = FREE;
    if (atomic_compare_exchange_strong_explicit(&c->state[i], &s, BUSY, memory_order_acquire, memory_order_acquire))
        return C5_CAST_CORNER_WALK;
    while (s == BUSY) {
        sched_yield();
        s = atomic_load_explicit(&c->state[i], memory_order_acquire);
    }
    const entry *e = &c->e[i];
    if (s == TOO_LONG)
        return C5_CAST_CORNER_WALK_AGAIN;
    memcpy(out, e->seg, (size_t)e->n * sizeof *out);
    if (hash)
        memcpy(hash, e->hash, sizeof e->hash);
    return e->n;
}

void c5_cast_corner_put(c5_cast_corners *c, long i, const c5_cast_seg *seg, int n, const uint64_t *hash)
{
    int s = TOO_LONG;
    entry *e = &c->e[i];
    if (n <= KEEP) {
        e->n = n;
        memcpy(e->seg, seg, (size_t)n * sizeof *seg);
        if (hash)
            memcpy(e->hash, hash, sizeof e->hash);
        s = READY;
    }
    atomic_store_explicit(&c->state[i], s, memory_order_release);
}
