/* Block "ray_queue": the 256-entry pipelined insertion sorter (rtl_model/proc/ray_queue.h), one
 * vector per clock cycle, starting right after reset: the cycle's inputs, then the outputs
 * of that cycle. A testbench applies the inputs, compares the outputs, then clocks. */
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "ray_queue.h"
#include "rng.h"

#define PAYLOAD_BITS 32
#define COUNT_BITS 9 /* 0..256 */

static const c5_vfield fields[] = {
    {"insert_valid", 1, 0, "uint"},   {"insert_key", 32, 0, "uint"},  {"insert_payload", PAYLOAD_BITS, 0, "uint"},
    {"pop_ready", 1, 0, "uint"},      {"pop_valid", 1, 1, "uint"},    {"pop_key", 32, 1, "uint"},
    {"pop_payload", PAYLOAD_BITS, 1, "uint"}, {"insert_accepted", 1, 1, "uint"}, {"full", 1, 1, "uint"},
    {"count", COUNT_BITS, 1, "uint"}, {"empty", 1, 1, "uint"},
};

const c5_vblock c5_vblock_ray_queue = {"ray_queue",
                                "insertion-sorter ray queue, one clock cycle per vector from reset "
                                "(capacity 256, 32-bit keys, 32-bit payload; docs/ray-queue.md)",
                                fields, (int)(sizeof fields / sizeof fields[0])};

static void write_cycle(c5_vfile *f, const c5_rq_in *in, const c5_rq_out *o)
{
    c5_vfile_u(f, in->insert_valid != 0);
    c5_vfile_u(f, in->insert_valid ? in->insert_key : 0);
    c5_vfile_u(f, in->insert_valid ? in->insert_payload : 0);
    c5_vfile_u(f, in->pop_ready != 0);
    c5_vfile_u(f, (uint64_t)o->pop_valid);
    c5_vfile_u(f, o->pop_key);
    c5_vfile_u(f, o->pop_payload);
    c5_vfile_u(f, (uint64_t)o->insert_accepted);
    c5_vfile_u(f, (uint64_t)o->full);
    c5_vfile_u(f, o->count);
    c5_vfile_u(f, (uint64_t)o->empty);
    c5_vfile_end(f);
}

static json_t *config(void)
{
    return json_pack("{s:i, s:i, s:i}", "capacity", C5_RQ_DEFAULT_CAPACITY, "key_bits", 32, "payload_bits",
                     PAYLOAD_BITS);
}

typedef struct {
    c5_rq q;
    c5_vfile *f;
    uint32_t payload; /* a fresh payload per insert: the cycle's number */
} trace;

static void cycle(trace *t, int ins, uint32_t key, int pop)
{
    c5_rq_in in = {.insert_valid = ins, .insert_key = ins ? key : 0, .insert_payload = ins ? t->payload : 0,
                   .pop_ready = pop};
    c5_rq_out o;
    c5_rq_step(&t->q, &in, &o);
    write_cycle(t->f, &in, &o);
    t->payload++;
}

static void drain(trace *t)
{
    while (t->q.count > 0)
        cycle(t, 0, 0, 1);
}

/* Phases, each from an empty queue: descending keys; equal keys inserted while others
 * ripple and popped at once (stability in flight); extreme keys; a full queue: 256 inserts
 * back to back, refused inserts (spill), pop + insert while full, pops on an empty queue;
 * then random traffic with many ties. */
static int directed(c5_vset *s)
{
    trace t = {0};
    c5_rq_cfg cfg = C5_RQ_CFG_DEFAULT;
    if (c5_rq_init(&t.q, &cfg) != 0)
        return c5_fail(s->err, "out of memory for the ray queue");
    t.f = c5_vfile_open(s, &c5_vblock_ray_queue, "directed", NULL, NULL);
    if (!t.f) {
        c5_rq_free(&t.q);
        return -1;
    }
    uint64_t rng = s->seed ^ 0x71756575ull; /* "queue" */
    cycle(&t, 0, 0, 0); /* idle after reset */
    cycle(&t, 0, 0, 1); /* pop on an empty queue */
    for (uint32_t k = 5; k-- > 0;)
        cycle(&t, 1, 10 * k, 0);
    cycle(&t, 0, 0, 0);
    drain(&t);
    static const uint32_t ties[] = {7, 7, 3, 7, 3, 9, 7, 3, 3, 7, 0, 7};
    for (unsigned i = 0; i < sizeof ties / sizeof ties[0]; i++)
        cycle(&t, 1, ties[i], i % 3 == 2);
    drain(&t);
    cycle(&t, 1, 0xFFFFFFFFu, 0);
    cycle(&t, 1, 0, 0);
    cycle(&t, 1, 0xFFFFFFFFu, 1);
    cycle(&t, 1, 0, 1);
    drain(&t);
    for (uint32_t i = 0; i < C5_RQ_DEFAULT_CAPACITY; i++)
        cycle(&t, 1, (uint32_t)(c5_splitmix64(&rng) % 64), 0);
    for (int i = 0; i < 3; i++)
        cycle(&t, 1, (uint32_t)i, 0); /* full: refused */
    for (int i = 0; i < 8; i++)
        cycle(&t, 1, (uint32_t)(c5_splitmix64(&rng) % 64), 1); /* full, pop + insert: accepted */
    for (int i = 0; i < 16; i++)
        cycle(&t, i % 2, 5, i % 2 == 0);
    drain(&t);
    cycle(&t, 0, 0, 1);
    for (long i = 0; i < s->count; i++) {
        uint64_t r = c5_splitmix64(&rng);
        int ins = (r & 7) < 5, pop = ((r >> 3) & 7) < 3;
        uint32_t key = (r >> 8) & 1 ? (uint32_t)((r >> 16) % 16) : (uint32_t)(r >> 32);
        cycle(&t, ins, key, pop);
    }
    drain(&t);
    c5_vfile_set(t.f, "config", config());
    c5_vfile_close(t.f);
    c5_rq_free(&t.q);
    return 0;
}

/* Scene taps: the first 4 x `count` cycles of the board's sorter in the frame (a trace must
 * be contiguous from reset, so no sampling; the first `count` cycles are mostly the eye
 * rays filling it). */
typedef struct {
    c5_vfile *f;
    uint64_t cycles;
} tap_state;

static void tap_queue(void *ctx, const c5_rq_in *in, const c5_rq_out *out)
{
    c5_vscene *v = ctx;
    tap_state *st = v->st[C5_VB_QUEUE];
    if (st->cycles++ < 4 * (uint64_t)v->set->count)
        write_cycle(st->f, in, out);
}

static int tap_begin(c5_vscene *v, c5_taps *t)
{
    tap_state *st = calloc(1, sizeof *st);
    if (!st)
        return -1;
    st->f = c5_vfile_open(v->set, &c5_vblock_ray_queue, v->scene, v->scene, NULL);
    if (!st->f) {
        free(st);
        return -1;
    }
    v->st[C5_VB_QUEUE] = st;
    t->queue = tap_queue;
    return 0;
}

static void tap_end(c5_vscene *v)
{
    tap_state *st = v->st[C5_VB_QUEUE];
    c5_vfile_set(st->f, "config", config());
    c5_vfile_set(st->f, "offered", json_integer((json_int_t)st->cycles));
    c5_vfile_close(st->f);
    free(st);
    v->st[C5_VB_QUEUE] = NULL;
}

const c5_vblock_gen c5_vgen_queue = {"ray_queue", directed, tap_begin, tap_end};
