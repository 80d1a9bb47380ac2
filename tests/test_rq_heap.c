/* The ray queue's equivalent model (rtl_model/proc/rq_heap.c) against the clock-level sorter
 * (rtl_model/proc/ray_queue.c), side by side: every cycle's outputs, the occupancy and every
 * statistic, on random bursts and on adversarial traffic (a full queue, equal keys, pops and
 * inserts at capacity, keys too wide, idle inputs with garbage); then whole frames of every
 * built-in scene rendered with each, compared in the image, every board counter and cycle
 * count, the queue's port trace and the packet trace. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "board_equal.h"
#include "builtin_scenes.h"
#include "harness.h"
#include "ray_queue.h"
#include "rng.h"
#include "rq_heap.h"

/* ---- the two queues in lockstep ----------------------------------------------------- */

typedef struct {
    c5_rq ref; /* the clock-level sorter: the reference */
    c5_rqh eq; /* the equivalent model */
    long cycle;
    /* coverage of the traffic: what the comparisons saw */
    long refused, full_swaps, equal_pops, masked, pops;
    uint32_t last_pop_key;
    int last_pop_valid;
} pair;

static int pair_init(pair *p, uint32_t cap, uint32_t key_bits)
{
    memset(p, 0, sizeof *p);
    c5_rq_cfg cfg = {cap, key_bits};
    if (c5_rq_init(&p->ref, &cfg) != 0)
        return -1;
    if (c5_rqh_init(&p->eq, &cfg) != 0) {
        c5_rq_free(&p->ref);
        return -1;
    }
    return 0;
}

static void pair_free(pair *p)
{
    c5_rq_free(&p->ref);
    c5_rqh_free(&p->eq);
}

static int stats_equal(const c5_rq_stats *a, const c5_rq_stats *b)
{
    return a->cycles == b->cycles && a->inserts == b->inserts && a->pops == b->pops && a->refused == b->refused &&
           a->masked_keys == b->masked_keys && a->max_count == b->max_count;
}

/* One cycle of both; 0, or -1 after reporting the first difference. */
static int pair_step(pair *p, const c5_rq_in *in)
{
    c5_rq_out a, b;
    c5_rq_step(&p->ref, in, &a);
    c5_rqh_step(&p->eq, in, &b);
    long t = p->cycle++;
    if (a.pop_valid != b.pop_valid || a.pop_key != b.pop_key || a.pop_payload != b.pop_payload ||
        a.insert_accepted != b.insert_accepted || a.full != b.full || a.count != b.count || a.empty != b.empty) {
        c5t_failf(__FILE__, __LINE__,
                  "cycle %ld (cap %u): sorter pop %d key %u payload %u acc %d full %d count %u empty %d; "
                  "equivalent pop %d key %u payload %u acc %d full %d count %u empty %d",
                  t, p->ref.cfg.capacity, a.pop_valid, a.pop_key, a.pop_payload, a.insert_accepted, a.full, a.count,
                  a.empty, b.pop_valid, b.pop_key, b.pop_payload, b.insert_accepted, b.full, b.count, b.empty);
        return -1;
    }
    if (p->ref.count != p->eq.count || !stats_equal(&p->ref.stats, &p->eq.stats)) {
        c5t_failf(__FILE__, __LINE__, "cycle %ld: count %u vs %u or statistics differ", t, p->ref.count,
                  p->eq.count);
        return -1;
    }
    p->refused += in->insert_valid && !a.insert_accepted;
    p->full_swaps += a.count == p->ref.cfg.capacity && a.pop_valid && a.insert_accepted;
    p->masked += in->insert_valid && (in->insert_key & ~p->ref.key_mask);
    if (a.pop_valid) {
        p->pops++;
        p->equal_pops += p->last_pop_valid && a.pop_key == p->last_pop_key;
        p->last_pop_key = a.pop_key;
        p->last_pop_valid = 1;
    }
    return 0;
}

static int cycle(pair *p, int ins, uint32_t key, int pop)
{
    c5_rq_in in = {ins, key, (uint32_t)p->cycle, pop};
    return pair_step(p, &in);
}

static int drain(pair *p)
{
    while (p->ref.count > 0)
        if (cycle(p, 0, 0, 1) != 0)
            return -1;
    return cycle(p, 0, 0, 1); /* and a pop on the empty queue */
}

/* ---- random bursts -------------------------------------------------------------------- */

/* Phases of random length, each with its insert and pop probabilities (including never and
 * always) and key range (2 and 8 keys: many ties; full width), now and then a key too wide
 * and idle cycles with garbage on the insert port. */
static int random_pair(uint32_t cap, uint32_t key_bits, uint64_t seed, long cycles, pair *p)
{
    static const double probs[] = {0.0, 0.1, 0.5, 0.9, 1.0};
    if (pair_init(p, cap, key_bits) != 0) {
        c5t_failf(__FILE__, __LINE__, "init %u %u", cap, key_bits);
        return -1;
    }
    uint64_t s = seed;
    double p_ins = 0, p_pop = 0;
    uint32_t key_range = 1, mask = p->ref.key_mask;
    long phase_end = 0;
    for (long t = 0; t < cycles; t++) {
        if (t == phase_end) {
            phase_end = t + 1 + (long)(c5_splitmix64(&s) % (2 * cap + 50));
            p_ins = probs[c5_splitmix64(&s) % 5];
            p_pop = probs[c5_splitmix64(&s) % 5];
            uint32_t r = (uint32_t)(c5_splitmix64(&s) % 4);
            key_range = r == 0 ? 2 : r == 1 ? 8 : r == 2 ? 1000 : 0;
        }
        c5_rq_in in;
        in.insert_valid = c5_uniform(&s) < p_ins;
        in.pop_ready = c5_uniform(&s) < p_pop;
        uint64_t k = c5_splitmix64(&s);
        in.insert_key = key_range ? (uint32_t)(k % key_range) & mask : (uint32_t)k & mask;
        if ((k >> 40) % 100 == 0)
            in.insert_key |= (uint32_t)(k >> 8) & ~mask;
        in.insert_payload = (uint32_t)t;
        if (!in.insert_valid && (k & 1))
            in.insert_key = in.insert_payload = 0xDEADBEEFu;
        if (pair_step(p, &in) != 0)
            return -1;
    }
    return drain(p);
}

TEST(rq_heap_random_bursts_256)
{
    pair p;
    int rc = random_pair(256, 32, 0xB0A7Du, 200000, &p);
    long refused = p.refused, swaps = p.full_swaps, ties = p.equal_pops;
    uint32_t max = p.ref.stats.max_count;
    pair_free(&p);
    CHECK_INT(rc, 0);
    /* the bursts reach a full queue, refusals, pop + insert at capacity and ties */
    CHECK_MSG(max == 256 && refused > 1000 && swaps > 1000 && ties > 1000, "max %u refused %ld swaps %ld ties %ld",
              max, refused, swaps, ties);
    rc = random_pair(256, 12, 0x5EED2u, 100000, &p);
    long masked = p.masked;
    pair_free(&p);
    CHECK_INT(rc, 0);
    CHECK(masked > 0);
}

TEST(rq_heap_random_bursts_small_and_odd_capacities)
{
    static const uint32_t caps[] = {1, 2, 3, 4, 7, 16, 31, 64, 255, 257, 4096};
    static const uint32_t bits[] = {1, 2, 5, 32};
    uint64_t seed = 101;
    for (size_t c = 0; c < sizeof caps / sizeof caps[0]; c++)
        for (size_t b = 0; b < sizeof bits / sizeof bits[0]; b++) {
            pair p;
            int rc = random_pair(caps[c], bits[b], seed++, caps[c] > 256 ? 40000 : 15000, &p);
            uint32_t max = p.ref.stats.max_count;
            pair_free(&p);
            CHECK_MSG(rc == 0, "cap %u key_bits %u", caps[c], bits[b]);
            if (caps[c] <= 256)
                CHECK_MSG(max == caps[c], "cap %u never filled (max %u)", caps[c], max);
        }
}

/* ---- adversarial traffic -------------------------------------------------------------- */

/* A full queue: descending keys (each insert undercuts every element in flight), refused
 * inserts, then pop + insert at capacity with keys smaller, equal and larger than the head,
 * then bursts of one key while the line still ripples. */
TEST(rq_heap_full_queue_descending_and_swaps)
{
    pair p;
    CHECK_INT(pair_init(&p, 256, 32), 0);
    int rc = 0;
    for (uint32_t i = 0; i < 256 && rc == 0; i++)
        rc = cycle(&p, 1, 1000000 - 7 * i, 0);
    for (int i = 0; i < 5 && rc == 0; i++)
        rc = cycle(&p, 1, (uint32_t)i, 0); /* refused */
    static const uint32_t swap_keys[] = {0, 999999, 0xFFFFFFFFu, 500000, 500000, 1, 0xFFFFFFFFu, 0};
    for (int r = 0; r < 300 && rc == 0; r++)
        rc = cycle(&p, 1, swap_keys[r % 8], 1);
    for (int r = 0; r < 600 && rc == 0; r++)
        rc = cycle(&p, 1, 42, r % 3 == 0); /* ties: acceptance order decides */
    if (rc == 0)
        rc = drain(&p);
    long refused = p.refused, swaps = p.full_swaps, ties = p.equal_pops;
    pair_free(&p);
    CHECK_INT(rc, 0);
    CHECK(refused > 5 && swaps >= 300 && ties > 100);
}

/* Equal keys only, and keys that alternate between the extremes: the tie rule and the
 * widest comparisons, with the queue filling and emptying in bursts. */
TEST(rq_heap_ties_and_extremes_in_bursts)
{
    for (int pattern = 0; pattern < 4; pattern++) {
        pair p;
        CHECK_INT(pair_init(&p, 64, 32), 0);
        int rc = 0;
        uint64_t s = 9 + (uint64_t)pattern;
        for (long t = 0; t < 20000 && rc == 0; t++) {
            int burst = (t / 100) % 3;               /* fill, mixed, drain */
            int ins = burst == 0 ? 1 : burst == 1 ? (int)(t & 1) : 0;
            int pop = burst == 0 ? (t % 7 == 0) : burst == 1 ? (int)((t >> 1) & 1) : 1;
            uint32_t key = pattern == 0   ? 7
                           : pattern == 1 ? ((t & 1) ? 0xFFFFFFFFu : 0)
                           : pattern == 2 ? (uint32_t)(t % 5) /* sawtooth */
                                          : (uint32_t)(c5_splitmix64(&s) % 3);
            rc = cycle(&p, ins, key, pop);
        }
        if (rc == 0)
            rc = drain(&p);
        long ties = p.equal_pops, refused = p.refused;
        pair_free(&p);
        CHECK_MSG(rc == 0, "pattern %d", pattern);
        CHECK_MSG(ties > 100 && refused > 0, "pattern %d: ties %ld refused %ld", pattern, ties, refused);
    }
}

/* Reset: both return to power-on, and acceptance order starts again. */
TEST(rq_heap_reset_and_refusals)
{
    c5_rqh q;
    c5_rq_cfg bad[] = {{0, 32}, {4097, 32}, {16, 0}, {16, 33}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        CHECK_INT(c5_rqh_init(&q, &bad[i]), -1);
        CHECK(q.a == NULL);
    }
    CHECK_INT(c5_rqh_init(&q, NULL), -1);
    pair p;
    CHECK_INT(pair_init(&p, 8, 4), 0);
    int rc = 0;
    for (int i = 0; i < 12 && rc == 0; i++)
        rc = cycle(&p, 1, (uint32_t)(i % 3), i % 4 == 3);
    c5_rq_reset(&p.ref);
    c5_rqh_reset(&p.eq);
    int zero = p.eq.count == 0 && p.eq.stats.cycles == 0 && stats_equal(&p.ref.stats, &p.eq.stats);
    for (int i = 0; i < 40 && rc == 0; i++)
        rc = cycle(&p, i < 20, (uint32_t)(i % 2), i >= 10);
    pair_free(&p);
    CHECK_INT(rc, 0);
    CHECK(zero);
}

/* ---- whole frames --------------------------------------------------------------------- */

/* FNV-1a over the queue's ports every cycle and over every packet written to a queue. */
typedef struct {
    uint64_t queue, packets, cycles;
} trace;

static void fnv(uint64_t *h, const void *p, size_t n)
{
    const uint8_t *b = p;
    for (size_t i = 0; i < n; i++)
        *h = (*h ^ b[i]) * 0x100000001b3ull;
}

static void tap_queue(void *ctx, const c5_rq_in *in, const c5_rq_out *out)
{
    trace *t = ctx;
    uint32_t w[11] = {(uint32_t)in->insert_valid, in->insert_key,        in->insert_payload, (uint32_t)in->pop_ready,
                      (uint32_t)out->pop_valid,   out->pop_key,          out->pop_payload,   (uint32_t)out->insert_accepted,
                      (uint32_t)out->full,        out->count,            (uint32_t)out->empty};
    fnv(&t->queue, w, sizeof w);
    t->cycles++;
}

static void tap_packet(void *ctx, const uint8_t *pk)
{
    trace *t = ctx;
    fnv(&t->packets, pk, C5_PACKET_BYTES);
}

static int render(const c5_scene *s, const c5_supervol *sv, c5_board_opts o, c5_queue_model m, c5_image *img,
                  c5_board_stats *st, trace *t)
{
    memset(t, 0, sizeof *t);
    t->queue = t->packets = 0xcbf29ce484222325ull;
    c5_taps taps = {.ctx = t, .queue = tap_queue, .packet = tap_packet};
    o.taps = &taps;
    o.queue_model = m;
    c5_err err;
    if (c5_board_render(s, sv, 0, &o, img, st, &err) != 0) {
        c5t_failf(__FILE__, __LINE__, "render: %s", err.msg);
        return -1;
    }
    return 0;
}

/* Every built-in scene at 64x64, with 8 cells and Morton keys (the default board), one cell
 * and FIFO keys, and 27 cells with an 8-entry queue (spills at every turn): the same bits
 * whichever model steps the queue. The variants must fill the queue and spill. */
TEST(rq_heap_whole_frames_every_builtin_scene)
{
    const c5_board_opts variants[] = {
        {.cells = {2, 2, 2}},
        {.cells = {0, 0, 0}, .key = C5_KEY_FIFO}, /* the fewest cells */
        {.cells = {3, 3, 3}, .queue_capacity = 8},
    };
    uint64_t spills = 0, full = 0;
    for (const c5_builtin_scene *bs = c5_builtin_scenes; bs->name; bs++) {
        c5_scene s;
        c5_supervol sv;
        c5_err err;
        CHECK_MSG(c5_scene_parse(bs->json, NULL, "test", &s, &err) == 0 && c5_supervol_build(&s, &sv, &err) == 0,
                  "%s: %s", bs->name, err.msg);
        s.render.width = s.render.height = 64;
        for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
            c5_image ia, ib;
            c5_board_stats sa, sb;
            trace ta, tb;
            int ok = render(&s, &sv, variants[v], C5_QUEUE_CYCLE, &ia, &sa, &ta) == 0;
            if (ok && render(&s, &sv, variants[v], 0, &ib, &sb, &tb) != 0) {
                c5_image_free(&ia);
                ok = 0;
            }
            if (!ok) {
                c5_supervol_free(&sv);
                return;
            }
            char what[80];
            snprintf(what, sizeof what, "%s variant %zu", bs->name, v);
            int same = c5t_board_stats_equal(what, &sa, &sb) == 0;
            int same_img = c5t_same_image(&ia, &ib);
            c5_image_free(&ia);
            c5_image_free(&ib);
            spills += sa.spills;
            full += sa.queue_max == (uint32_t)(variants[v].queue_capacity ? variants[v].queue_capacity : 256);
            if (!same || !same_img || ta.cycles != tb.cycles || ta.queue != tb.queue || ta.packets != tb.packets) {
                c5_supervol_free(&sv);
                CHECK_MSG(same, "%s: counters differ", what);
                CHECK_MSG(same_img, "%s: images differ", what);
                CHECK_MSG(ta.cycles == tb.cycles, "%s: queue cycles %llu vs %llu", what,
                          (unsigned long long)ta.cycles, (unsigned long long)tb.cycles);
                CHECK_MSG(ta.queue == tb.queue, "%s: queue port traces differ", what);
                CHECK_MSG(ta.packets == tb.packets, "%s: packet traces differ", what);
            }
        }
        c5_supervol_free(&sv);
    }
    CHECK_MSG(spills > 0 && full >= 4, "spills %llu, frames with a full queue %llu", (unsigned long long)spills,
              (unsigned long long)full);
}
