/* SplitMix64: the one pseudo-random stream of the project (procedural volumes, test
 * inputs, the peer benchmark's cameras). Same bits on every machine. */
#ifndef C5_RNG_H
#define C5_RNG_H

#include <stdint.h>

static inline uint64_t c5_splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1) with 53 random bits. */
static inline double c5_uniform(uint64_t *state) { return (double)(c5_splitmix64(state) >> 11) * 0x1p-53; }

#endif
