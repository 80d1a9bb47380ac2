/* Block "packet": the ray packet codec. One vector = every field of a packet and the
 * 256-bit packet they pack into; a testbench checks both directions (pack and unpack).
 * The field list is the generated layout's (spec/layouts.toml), nothing is restated here. */
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "c5_layouts.h"
#include "rng.h"

static const c5_vfield fields[] = {
#define X(m, lsb, w, sgn, fmt) {#m, w, 0, fmt},
    C5_RAY_PACKET_FIELDS_FORMAT(X)
#undef X
    {"packet", C5_RAY_PACKET_WIDTH, 1, "bits"},
};
#define N_DATA ((int)(sizeof fields / sizeof fields[0]) - 1)

static const c5_vblock block = {
    "packet", "ray packet codec: the fields (in) and the 256-bit packet (out) they pack into; unpack is the inverse",
    fields, N_DATA + 1};

/* Sets field k of p from raw bits (sign-extended for signed fields). */
static void set_field(c5_ray_packet_t *p, int k, uint64_t raw)
{
    int i = 0;
#define X(m, lsb, w, sgn)                                                                          \
    if (i++ == k) {                                                                                \
        raw &= (w) == 64 ? ~0ull : ((1ull << (w)) - 1);                                            \
        p->m = (__typeof__(p->m))((sgn) ? c5_lay_sext(raw, w) : (int64_t)raw);                      \
    }
    C5_RAY_PACKET_FIELDS(X)
#undef X
}

static void write_packet(c5_vfile *f, const void *pk)
{
    c5_ray_packet_t p;
    c5_ray_packet_unpack(pk, &p);
#define X(m, lsb, w, sgn) c5_vfile_u(f, (uint64_t)p.m);
    C5_RAY_PACKET_FIELDS(X)
#undef X
    c5_vfile_bytes(f, pk);
    c5_vfile_end(f);
}

static void write_fields(c5_vfile *f, const c5_ray_packet_t *p)
{
    uint8_t pk[C5_RAY_PACKET_BYTES];
    c5_ray_packet_pack(p, pk);
    write_packet(f, pk);
}

/* All zero; each field all ones alone; for signed fields also the most negative value
 * alone; a walking one through every bit of every field; all ones; then random packets. */
static int directed(c5_vset *s)
{
    c5_vfile *f = c5_vfile_open(s, &block, "directed", NULL, NULL);
    if (!f)
        return -1;
    c5_ray_packet_t p;
    memset(&p, 0, sizeof p);
    write_fields(f, &p);
    for (int k = 0; k < N_DATA; k++) {
        memset(&p, 0, sizeof p);
        set_field(&p, k, ~0ull);
        write_fields(f, &p);
        if (!strncmp(fields[k].format, "SQ", 2)) {
            set_field(&p, k, 1ull << (fields[k].width - 1));
            write_fields(f, &p);
        }
    }
    for (int k = 0; k < N_DATA; k++)
        for (unsigned b = 0; b < fields[k].width; b++) {
            memset(&p, 0, sizeof p);
            set_field(&p, k, 1ull << b);
            write_fields(f, &p);
        }
    for (int k = 0; k < N_DATA; k++)
        set_field(&p, k, ~0ull);
    write_fields(f, &p);
    uint64_t rng = s->seed ^ 0x7061636b6574ull; /* "packet" */
    for (long i = 0; i < s->count; i++) {
        for (int k = 0; k < N_DATA; k++)
            set_field(&p, k, c5_splitmix64(&rng));
        write_fields(f, &p);
    }
    c5_vfile_close(f);
    return 0;
}

/* Scene taps: a uniform sample of the packets written into the queues. */
static void tap_packet(void *ctx, const uint8_t *pk)
{
    c5_vscene *v = ctx;
    c5_vsample_offer(v, C5_VB_PACKET, pk);
}

static int tap_begin(c5_vscene *v, c5_taps *t)
{
    if (c5_vsample_begin(v, C5_VB_PACKET, C5_RAY_PACKET_BYTES, 1) != 0)
        return -1;
    t->packet = tap_packet;
    return 0;
}

static void tap_end(c5_vscene *v) { c5_vsample_end(v, C5_VB_PACKET, &block, write_packet, NULL); }

const c5_vblock_gen c5_vgen_packet = {"packet", directed, tap_begin, tap_end};
