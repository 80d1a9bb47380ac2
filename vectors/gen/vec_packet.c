/* Block "packet": the ray packet codec. One vector = every field of a packet and the
 * 256-bit packet they pack into; a testbench checks both directions (pack and unpack).
 * The field list is the generated layout's (spec/layouts.toml), nothing is restated here. */
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "c5_layouts.h"
#include "reservoir.h"
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

static void write_packet(c5_vfile *f, const uint8_t pk[C5_RAY_PACKET_BYTES])
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
    c5_res_offer(v->st[C5_VB_PACKET], pk);
}

static int tap_begin(c5_vscene *v, c5_taps *t)
{
    c5_reservoir *r = malloc(sizeof *r);
    if (!r || c5_res_init(r, C5_RAY_PACKET_BYTES, (size_t)v->set->count, v->seed ^ 1) != 0) {
        free(r);
        return -1;
    }
    v->st[C5_VB_PACKET] = r;
    t->packet = tap_packet;
    return 0;
}

static void tap_end(c5_vscene *v)
{
    c5_reservoir *r = v->st[C5_VB_PACKET];
    c5_vfile *f = c5_vfile_open(v->set, &block, v->scene, v->scene, NULL);
    if (f) {
        c5_res_sort(r);
        for (size_t i = 0; i < r->n; i++)
            write_packet(f, c5_res_at(r, i));
        c5_vfile_set(f, "offered", json_integer((json_int_t)r->seen));
        c5_vfile_close(f);
    }
    c5_res_free(r);
    free(r);
    v->st[C5_VB_PACKET] = NULL;
}

const c5_vblock_gen c5_vgen_packet = {"packet", directed, tap_begin, tap_end};
