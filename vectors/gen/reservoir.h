/* A uniform sample of `cap` records out of a stream of unknown length (reservoir sampling,
 * Algorithm R, with the project's SplitMix64 stream): the taps keep every block's vectors
 * representative of the whole frame, not only of its first rays. Deterministic for a seed.
 * Records come back in stream order. */
#ifndef C5_RESERVOIR_H
#define C5_RESERVOIR_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    size_t rec_size, cap, n; /* record bytes, capacity, records held */
    uint64_t seen;           /* records offered */
    uint64_t rng;
    uint64_t *index;         /* stream index of each held record */
    unsigned char *data;     /* cap records */
} c5_reservoir;

/* 0, or -1 when out of memory. */
int c5_res_init(c5_reservoir *r, size_t rec_size, size_t cap, uint64_t seed);
/* Offers one record: kept (copied) with probability cap / seen. */
void c5_res_offer(c5_reservoir *r, const void *rec);
/* Sorts the held records into stream order; then record i is c5_res_at(r, i). */
void c5_res_sort(c5_reservoir *r);
static inline const void *c5_res_at(const c5_reservoir *r, size_t i) { return r->data + i * r->rec_size; }
void c5_res_free(c5_reservoir *r);

#endif
