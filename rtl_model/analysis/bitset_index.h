/* A hash index over an arena of fixed-width bitsets (entry s: words 64-bit words at
 * keys + s * words, its hash at hash[s]): open addressing, linear probing, a power-of-two
 * table of entry numbers (-1: empty). The exact search's states (tree_exact.c) and the
 * projection memo (tree_bound.c) both find bitsets again through it; the owners keep the
 * arenas. Deterministic: the hash depends on the bits only. */
#ifndef C5_BITSET_INDEX_H
#define C5_BITSET_INDEX_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    int *table;
    size_t tmask;
} c5_bsidx;

uint64_t c5_bits_hash(const uint64_t *b, int words);
/* Rebuilds the table at twice its size (the first time: `first` slots, a power of two)
 * over entries 0..n-1. 0, or -1 when out of memory (the old table stays). */
int c5_bsidx_grow(c5_bsidx *x, const uint64_t *hash, long n, size_t first);
/* The slot holding the entry with bits b (hash h), or the empty slot where it would go. */
size_t c5_bsidx_find(const c5_bsidx *x, const uint64_t *keys, const uint64_t *hash, int words, const uint64_t *b,
                     uint64_t h);
/* Grows the table when a store leaves it more than half full. */
static inline int c5_bsidx_after_store(c5_bsidx *x, const uint64_t *hash, long n)
{
    return (size_t)n * 2 > x->tmask + 1 ? c5_bsidx_grow(x, hash, n, 0) : 0;
}
void c5_bsidx_free(c5_bsidx *x);

#endif
