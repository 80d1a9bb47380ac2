/* The ray packet codec of the C model (the generated c5_ray_packet_pack / _unpack of
 * build/gen/c5_layouts.h) as a live reference for GHDL (tb/c5ref_pkg.vhd): the
 * testbench hands over a 256-bit packet as eight 32-bit words (word i = bytes 4i..4i+3,
 * little-endian), the model unpacks it and packs the fields again, and the testbench reads
 * back every field (in the layout's order, MSB first) and the packed words. */
#include <stdint.h>

#include "c5_layouts.h"
#include "c5ref.h"

int32_t c5ref_pk_set(int32_t i, int32_t word);
int32_t c5ref_pk_run(void);
int32_t c5ref_pk_field(int32_t k);
int32_t c5ref_pk_word(int32_t i);

static uint8_t in[C5_RAY_PACKET_BYTES], packed[C5_RAY_PACKET_BYTES];
static int64_t fields[32];
static long runs, fault = -2; /* field 0 of the model is wrong in this run (c5ref.h); -2: not read yet */

int32_t c5ref_pk_set(int32_t i, int32_t word)
{
    if (i < 0 || i >= C5_RAY_PACKET_BYTES / 4)
        return -1;
    for (int b = 0; b < 4; b++)
        in[4 * i + b] = (uint8_t)((uint32_t)word >> (8 * b));
    return 0;
}

/* Unpacks the packet set so far, packs its fields again. */
int32_t c5ref_pk_run(void)
{
    if (fault == -2)
        fault = c5ref_fault_step();
    c5_ray_packet_t f;
    c5_ray_packet_unpack(in, &f);
    c5_ray_packet_pack(&f, packed);
    int k = 0;
#define FIELD(m, lsb, width, sgn) fields[k++] = (int64_t)f.m;
    C5_RAY_PACKET_FIELDS(FIELD)
#undef FIELD
    if (runs++ == fault)
        fields[0] ^= 1;
    return k;
}

/* Field k of the last run (raw, signed fields negative), in the layout's order. */
int32_t c5ref_pk_field(int32_t k) { return k >= 0 && k < 32 ? (int32_t)fields[k] : 0; }

/* Word i of the packet the model packed in the last run. */
int32_t c5ref_pk_word(int32_t i)
{
    if (i < 0 || i >= C5_RAY_PACKET_BYTES / 4)
        return 0;
    uint32_t w = 0;
    for (int b = 0; b < 4; b++)
        w |= (uint32_t)packed[4 * i + b] << (8 * b);
    return (int32_t)w;
}
