/* Reservoir sampling (reservoir.h). */
#include "reservoir.h"

#include <stdlib.h>
#include <string.h>

#include "rng.h"

int c5_res_init(c5_reservoir *r, size_t rec_size, size_t cap, uint64_t seed)
{
    memset(r, 0, sizeof *r);
    r->rec_size = rec_size;
    r->cap = cap;
    r->rng = seed;
    r->index = malloc((cap ? cap : 1) * sizeof *r->index);
    r->data = malloc((cap ? cap : 1) * rec_size);
    if (!r->index || !r->data) {
        c5_res_free(r);
        return -1;
    }
    return 0;
}

void c5_res_offer(c5_reservoir *r, const void *rec)
{
    uint64_t i = r->seen++;
    size_t slot;
    if (r->n < r->cap) {
        slot = r->n++;
    } else {
        uint64_t j = c5_splitmix64(&r->rng) % (i + 1); /* modulo bias < 2^-40: irrelevant */
        if (j >= r->cap)
            return;
        slot = (size_t)j;
    }
    r->index[slot] = i;
    memcpy(r->data + slot * r->rec_size, rec, r->rec_size);
}

void c5_res_sort(c5_reservoir *r)
{
    /* Insertion sort by index through a permutation: cap is at most a few thousand. */
    unsigned char *tmp = malloc(r->rec_size);
    if (!tmp)
        return; /* only the order is lost; callers sort small reservoirs */
    for (size_t i = 1; i < r->n; i++) {
        uint64_t k = r->index[i];
        memcpy(tmp, r->data + i * r->rec_size, r->rec_size);
        size_t j = i;
        for (; j > 0 && r->index[j - 1] > k; j--) {
            r->index[j] = r->index[j - 1];
            memcpy(r->data + j * r->rec_size, r->data + (j - 1) * r->rec_size, r->rec_size);
        }
        r->index[j] = k;
        memcpy(r->data + j * r->rec_size, tmp, r->rec_size);
    }
    free(tmp);
}

void c5_res_free(c5_reservoir *r)
{
    free(r->index);
    free(r->data);
    memset(r, 0, sizeof *r);
}
