/* Hash index over bitsets (bitset_index.h). */
#include <stdlib.h>
#include <string.h>

#include "bitset_index.h"

uint64_t c5_bits_hash(const uint64_t *b, int words)
{
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (int k = 0; k < words; k++) {
        h ^= b[k];
        h *= 0xBF58476D1CE4E5B9ull;
        h ^= h >> 31;
    }
    return h;
}

int c5_bsidx_grow(c5_bsidx *x, const uint64_t *hash, long n, size_t first)
{
    size_t size = x->table ? 2 * (x->tmask + 1) : first;
    int *t = malloc(size * sizeof *t);
    if (!t)
        return -1;
    memset(t, 0xff, size * sizeof *t);
    for (long s = 0; s < n; s++) {
        size_t k = hash[s] & (size - 1);
        while (t[k] >= 0)
            k = (k + 1) & (size - 1);
        t[k] = (int)s;
    }
    free(x->table);
    x->table = t;
    x->tmask = size - 1;
    return 0;
}

size_t c5_bsidx_find(const c5_bsidx *x, const uint64_t *keys, const uint64_t *hash, int words, const uint64_t *b,
                     uint64_t h)
{
    size_t k = h & x->tmask;
    for (int s; (s = x->table[k]) >= 0; k = (k + 1) & x->tmask)
        if (hash[s] == h && memcmp(keys + (size_t)s * (size_t)words, b, (size_t)words * 8) == 0)
            return k;
    return k;
}

void c5_bsidx_free(c5_bsidx *x)
{
    free(x->table);
    x->table = NULL;
    x->tmask = 0;
}
