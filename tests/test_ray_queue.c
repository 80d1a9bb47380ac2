/* The ray queue (rtl_model/proc/ray_queue.c): hand-written cycle traces, edge capacities and key
 * widths, the systolic structure itself, and long random runs checked cycle by cycle
 * against a naive sorted-array priority queue (the oracle) under the latency rule of
 * ray_queue.h: each cycle, pop first (elements accepted in earlier cycles), then insert. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "ray_queue.h"
#include "rng.h"

/* ---- the oracle: a sorted array, O(n) insert ------------------------------------- */

typedef struct {
    uint32_t key, payload;
    uint64_t seq; /* acceptance order: equal keys leave in this order */
} oel;

typedef struct {
    oel *a;
    uint32_t n, cap, mask;
    uint64_t seq;
    uint64_t inserts, pops, refused, masked;
} oracle;

static void oracle_init(oracle *o, uint32_t cap, uint32_t key_bits)
{
    memset(o, 0, sizeof *o);
    o->a = malloc(cap * sizeof *o->a);
    o->cap = cap;
    o->mask = key_bits == 32 ? 0xFFFFFFFFu : (1u << key_bits) - 1u;
}

static void oracle_step(oracle *o, const c5_rq_in *in, c5_rq_out *out)
{
    memset(out, 0, sizeof *out);
    out->count = o->n;
    out->empty = o->n == 0;
    int pop = in->pop_ready && o->n > 0;
    out->full = o->n == o->cap && !pop;
    out->insert_accepted = in->insert_valid && !out->full;
    uint32_t key = in->insert_key;
    if (in->insert_valid && (key & ~o->mask)) {
        o->masked++;
        key &= o->mask;
    }
    if (pop) {
        out->pop_valid = 1;
        out->pop_key = o->a[0].key;
        out->pop_payload = o->a[0].payload;
        memmove(o->a, o->a + 1, (o->n - 1) * sizeof *o->a);
        o->n--;
        o->pops++;
    }
    if (in->insert_valid && !out->full) {
        uint32_t j = o->n;
        while (j > 0 && o->a[j - 1].key > key) { /* after every equal key */
            o->a[j] = o->a[j - 1];
            j--;
        }
        o->a[j] = (oel){key, in->insert_payload, o->seq++};
        o->n++;
        o->inserts++;
    } else if (in->insert_valid) {
        o->refused++;
    }
}

/* ---- helpers ---------------------------------------------------------------------- */

static int out_equal(const c5_rq_out *a, const c5_rq_out *b)
{
    return a->pop_valid == b->pop_valid && a->pop_key == b->pop_key && a->pop_payload == b->pop_payload &&
           a->insert_accepted == b->insert_accepted && a->full == b->full && a->count == b->count &&
           a->empty == b->empty;
}

static void out_str(const c5_rq_out *o, char *buf, size_t n)
{
    snprintf(buf, n, "pop_valid=%d key=%u payload=%u accepted=%d full=%d count=%u empty=%d", o->pop_valid,
             o->pop_key, o->pop_payload, o->insert_accepted, o->full, o->count, o->empty);
}

/* The structural invariants of the sorter, from the registers (white box):
 * held is a gap-free prefix of length len, sorted by key, never fresh; a carry sits only
 * at stages 1..len, behind a held element whose key it does not undercut; the end slots are
 * empty; count = held + carries. Returns 0, or -1 after reporting. */
static int check_registers(const c5_rq *q, long cycle)
{
    uint32_t n = q->cfg.capacity, held = 0, carries = 0;
    for (uint32_t i = 0; i < n; i++) {
        const c5_rq_slot *p = &q->held[i];
        if (p->valid) {
            held++;
            if (i >= q->len || (i > 0 && !q->held[i - 1].valid) || (i > 0 && q->held[i - 1].key > p->key)) {
                c5t_failf(__FILE__, __LINE__, "cycle %ld: held[%u] (key %u) out of order or beyond len %u",
                          cycle, i, p->key, q->len);
                return -1;
            }
            if (p->fresh) {
                c5t_failf(__FILE__, __LINE__, "cycle %ld: held[%u] marked fresh", cycle, i);
                return -1;
            }
            if (p->key & ~q->key_mask) {
                c5t_failf(__FILE__, __LINE__, "cycle %ld: held[%u] key %#x wider than the key", cycle, i, p->key);
                return -1;
            }
        }
    }
    for (uint32_t i = 0; i <= n; i++) {
        const c5_rq_slot *c = &q->carry[i];
        if (!c->valid)
            continue;
        carries++;
        if (i == 0 || i == n || i > q->len || !q->held[i - 1].valid || c->key < q->held[i - 1].key) {
            c5t_failf(__FILE__, __LINE__, "cycle %ld: carry[%u] (key %u) misplaced (len %u)", cycle, i, c->key,
                      q->len);
            return -1;
        }
    }
    if (held != q->len || held + carries != q->count) {
        c5t_failf(__FILE__, __LINE__, "cycle %ld: held %u carries %u, len %u count %u", cycle, held, carries, q->len,
                  q->count);
        return -1;
    }
    return 0;
}

/* One hand-written cycle: inputs and every expected output. */
typedef struct {
    int iv;
    uint32_t key, pay;
    int pr;
    int pv;
    uint32_t pk, pp;
    int acc, full;
    uint32_t count;
} row;

/* Steps q through the rows, checking every output and the registers each cycle. */
static int run_trace(c5_rq *q, const row *r, int n, const char *name)
{
    for (int t = 0; t < n; t++) {
        c5_rq_in in = {r[t].iv, r[t].key, r[t].pay, r[t].pr};
        c5_rq_out got, want = {r[t].pv, r[t].pk, r[t].pp, r[t].acc, r[t].full, r[t].count, r[t].count == 0};
        c5_rq_step(q, &in, &got);
        if (!out_equal(&got, &want)) {
            char g[200], w[200];
            out_str(&got, g, sizeof g);
            out_str(&want, w, sizeof w);
            c5t_failf(__FILE__, __LINE__, "%s cycle %d:\n      got  %s\n      want %s", name, t, g, w);
            return -1;
        }
        if (check_registers(q, t) != 0)
            return -1;
    }
    return 0;
}

#define TRACE(q, rows) run_trace((q), (rows), (int)(sizeof(rows) / sizeof(rows)[0]), #rows)

static c5_rq_out step(c5_rq *q, int iv, uint32_t key, uint32_t pay, int pr)
{
    c5_rq_in in = {iv, key, pay, pr};
    c5_rq_out out;
    c5_rq_step(q, &in, &out);
    return out;
}

/* ---- configuration ------------------------------------------------------------------ */

TEST(queue_init_checks_cfg)
{
    c5_rq q;
    const c5_rq_cfg bad[] = {{0, 8}, {4097, 8}, {16, 0}, {16, 33}, {0xFFFFFFFFu, 32}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        CHECK_INT(c5_rq_init(&q, &bad[i]), -1);
        CHECK(q.held == NULL && q.carry == NULL);
    }
    CHECK_INT(c5_rq_init(&q, NULL), -1);
    const c5_rq_cfg good[] = {{1, 1}, {4096, 32}, C5_RQ_CFG_DEFAULT};
    for (size_t i = 0; i < sizeof good / sizeof good[0]; i++) {
        CHECK_INT(c5_rq_init(&q, &good[i]), 0);
        CHECK_INT(q.cfg.capacity, good[i].capacity);
        CHECK_INT(q.count, 0);
        c5_rq_out o = step(&q, 0, 0, 0, 1);
        CHECK(!o.pop_valid && o.empty && !o.full && o.count == 0);
        c5_rq_free(&q);
        CHECK(q.held == NULL);
    }
    c5_rq_cfg def = C5_RQ_CFG_DEFAULT;
    CHECK_INT(def.capacity, 256);
    CHECK_INT(def.key_bits, 32);
}

/* ---- hand-written traces ------------------------------------------------------------ */

TEST(queue_trace_insert_then_pop)
{
    c5_rq q;
    c5_rq_cfg cfg = {4, 8};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    static const row rows[] = {
        /* iv key pay pr | pv pk pp acc full count */
        {0, 0, 0, 0, 0, 0, 0, 0, 0, 0},        /* idle */
        {1, 5, 100, 0, 0, 0, 0, 1, 0, 0},      /* insert 5 */
        {0, 0, 0, 1, 1, 5, 100, 0, 0, 1},      /* next cycle it pops */
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},        /* empty: no pop */
        {1, 9, 1, 0, 0, 0, 0, 1, 0, 0},        /* 9, then 4: the 4 is ahead one cycle later */
        {1, 4, 2, 0, 0, 0, 0, 1, 0, 1},
        {0, 0, 0, 1, 1, 4, 2, 0, 0, 2},
        {0, 0, 0, 0, 0, 0, 0, 0, 0, 1},        /* pop_ready 0: nothing leaves */
        {0, 0, 0, 1, 1, 9, 1, 0, 0, 1},
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},
    };
    int rc = TRACE(&q, rows);
    c5_rq_free(&q);
    CHECK_INT(rc, 0);
}

TEST(queue_trace_insert_pop_same_cycle_empty)
{
    c5_rq q;
    c5_rq_cfg cfg = {4, 8};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    static const row rows[] = {
        {1, 7, 1, 1, 0, 0, 0, 1, 0, 0}, /* the insert is not visible to this cycle's pop */
        {1, 3, 2, 1, 1, 7, 1, 1, 0, 1}, /* 7 leaves, 3 enters */
        {1, 8, 3, 1, 1, 3, 2, 1, 0, 1}, /* 3 leaves, 8 enters: a steady stream through */
        {0, 0, 0, 1, 1, 8, 3, 0, 0, 1},
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},
    };
    int rc = TRACE(&q, rows);
    c5_rq_free(&q);
    CHECK_INT(rc, 0);
}

TEST(queue_trace_insert_pop_same_cycle_full)
{
    c5_rq q;
    c5_rq_cfg cfg = {3, 8};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    static const row rows[] = {
        {1, 5, 50, 0, 0, 0, 0, 1, 0, 0},
        {1, 1, 10, 0, 0, 0, 0, 1, 0, 1},
        {1, 3, 30, 0, 0, 0, 0, 1, 0, 2},
        {1, 4, 40, 0, 0, 0, 0, 0, 1, 3},
        {0, 0, 0, 0, 0, 0, 0, 0, 1, 3},
        {1, 0, 0, 1, 1, 1, 10, 1, 0, 3},
        {1, 9, 90, 1, 1, 0, 0, 1, 0, 3},
        {1, 2, 20, 1, 1, 3, 30, 1, 0, 3},
        {0, 0, 0, 1, 1, 2, 20, 0, 0, 3},
        {1, 6, 60, 0, 0, 0, 0, 1, 0, 2},
        {1, 7, 70, 0, 0, 0, 0, 0, 1, 3},
        {0, 0, 0, 1, 1, 5, 50, 0, 0, 3},
        {0, 0, 0, 1, 1, 6, 60, 0, 0, 2},
        {0, 0, 0, 1, 1, 9, 90, 0, 0, 1},
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},
    };
    int rc = TRACE(&q, rows);
    CHECK_INT(q.stats.refused, 2);
    CHECK_INT(q.stats.inserts, 7);
    CHECK_INT(q.stats.pops, 7);
    CHECK_INT(q.stats.max_count, 3);
    c5_rq_free(&q);
    CHECK_INT(rc, 0);
}

TEST(queue_trace_equal_keys_fifo_in_flight)
{
    c5_rq q;
    c5_rq_cfg cfg = {8, 8};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    /* Back-to-back inserts of equal keys with a smaller key among them, pops starting
     * while they still ripple. */
    static const row rows[] = {
        {1, 5, 1, 0, 0, 0, 0, 1, 0, 0},
        {1, 5, 2, 0, 0, 0, 0, 1, 0, 1},
        {1, 2, 3, 1, 1, 5, 1, 1, 0, 2},
        {1, 5, 4, 1, 1, 2, 3, 1, 0, 2},
        {1, 5, 5, 1, 1, 5, 2, 1, 0, 2},
        {0, 0, 0, 1, 1, 5, 4, 0, 0, 2},
        {0, 0, 0, 1, 1, 5, 5, 0, 0, 1},
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},
    };
    int rc = TRACE(&q, rows);
    CHECK_INT(rc, 0);
    /* Settled equal keys displaced by a smaller one must keep their order: 7a 7b 7c 7d
     * settle, then 1 pushes all four down the carry line while pops take the head. */
    static const row rows2[] = {
        {1, 7, 10, 0, 0, 0, 0, 1, 0, 0},
        {1, 7, 11, 0, 0, 0, 0, 1, 0, 1},
        {1, 7, 12, 0, 0, 0, 0, 1, 0, 2},
        {1, 7, 13, 0, 0, 0, 0, 1, 0, 3},
        {0, 0, 0, 0, 0, 0, 0, 0, 0, 4},
        {0, 0, 0, 0, 0, 0, 0, 0, 0, 4},
        {1, 1, 14, 0, 0, 0, 0, 1, 0, 4},
        {1, 7, 15, 1, 1, 1, 14, 1, 0, 5},
        {1, 1, 16, 1, 1, 7, 10, 1, 0, 5},
        {0, 0, 0, 1, 1, 1, 16, 0, 0, 5},
        {0, 0, 0, 1, 1, 7, 11, 0, 0, 4},
        {0, 0, 0, 1, 1, 7, 12, 0, 0, 3},
        {0, 0, 0, 1, 1, 7, 13, 0, 0, 2},
        {0, 0, 0, 1, 1, 7, 15, 0, 0, 1},
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},
    };
    rc = TRACE(&q, rows2);
    c5_rq_free(&q);
    CHECK_INT(rc, 0);
}

/* A smaller key inserted after larger ones that are still rippling leaves first. */
TEST(queue_trace_smaller_key_overtakes_ripples)
{
    c5_rq q;
    c5_rq_cfg cfg = {8, 8};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    static const row rows[] = {
        {1, 10, 1, 0, 0, 0, 0, 1, 0, 0},
        {1, 20, 2, 0, 0, 0, 0, 1, 0, 1},
        {1, 30, 3, 0, 0, 0, 0, 1, 0, 2}, /* 20 and 30 are in flight */
        {1, 15, 4, 1, 1, 10, 1, 1, 0, 3},
        {1, 12, 5, 1, 1, 15, 4, 1, 0, 3},
        {1, 11, 6, 1, 1, 12, 5, 1, 0, 3},
        {0, 0, 0, 1, 1, 11, 6, 0, 0, 3},
        {0, 0, 0, 1, 1, 20, 2, 0, 0, 2},
        {0, 0, 0, 1, 1, 30, 3, 0, 0, 1},
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},
    };
    int rc = TRACE(&q, rows);
    c5_rq_free(&q);
    CHECK_INT(rc, 0);
}

/* The element travels one stage per cycle: a new minimum displaces the whole line, and the
 * displaced wave is at stage k after k edges. */
TEST(queue_systolic_one_stage_per_cycle)
{
    c5_rq q;
    c5_rq_cfg cfg = {8, 8};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    for (uint32_t k = 1; k <= 5; k++)
        step(&q, 1, 10 * k, k, 0);
    for (int t = 0; t < 8; t++)
        step(&q, 0, 0, 0, 0);
    CHECK_INT(q.len, 5);
    for (uint32_t i = 0; i < 5; i++)
        CHECK_INT(q.held[i].key, 10 * (i + 1));
    /* a 60 travels to stage 5, one stage a cycle, and touches nothing on its way */
    step(&q, 1, 60, 6, 0);
    for (uint32_t k = 1; k <= 5; k++) {
        CHECK_MSG(q.carry[k].valid && q.carry[k].key == 60 && q.carry[k].fresh, "60 not at carry[%u]", k);
        for (uint32_t i = 0; i <= 8; i++)
            CHECK_MSG(i == k || !q.carry[i].valid, "stray carry[%u] with 60 at %u", i, k);
        CHECK_INT(q.count, 6);
        step(&q, 0, 0, 0, 0);
    }
    CHECK_INT(q.len, 6);
    CHECK_INT(q.held[5].key, 60);
    /* a 5 settles at stage 0; the displaced 10, 20, ... form a wave one stage a cycle */
    step(&q, 1, 5, 7, 0);
    CHECK_INT(q.held[0].key, 5);
    for (uint32_t k = 1; k <= 6; k++) {
        CHECK_MSG(q.carry[k].valid && q.carry[k].key == 10 * k && !q.carry[k].fresh, "wave not at carry[%u]", k);
        CHECK_INT(q.held[k - 1].key, k == 1 ? 5 : 10 * (k - 1));
        step(&q, 0, 0, 0, 0);
    }
    CHECK_INT(q.len, 7);
    for (uint32_t i = 0; i <= 8; i++)
        CHECK(!q.carry[i].valid);
    for (uint32_t i = 1; i < 7; i++)
        CHECK_INT(q.held[i].key, 10 * i);
    c5_rq_free(&q);
}

/* The timing diagram of docs/ray-queue.md, register by register. Each stage is written
 * "carry|held" as in the document: "25*" fresh carry, "20>" displaced carry, "." empty. */
static int stages_are(const c5_rq *q, const char *want, int cycle)
{
    char got[128] = "", cell[24];
    for (uint32_t i = 0; i < 4; i++) {
        const c5_rq_slot *c = &q->carry[i], *h = &q->held[i];
        char cs[8] = "", hs[8] = ".";
        if (c->valid)
            snprintf(cs, sizeof cs, "%u%c", c->key, c->fresh ? '*' : '>');
        if (h->valid)
            snprintf(hs, sizeof hs, "%u", h->key);
        snprintf(cell, sizeof cell, "%s%s|%s", i ? " " : "", cs, hs);
        strcat(got, cell);
    }
    if (strcmp(got, want) != 0) {
        c5t_failf(__FILE__, __LINE__, "t%d: registers \"%s\", want \"%s\"", cycle, got, want);
        return -1;
    }
    return 0;
}

TEST(queue_doc_timing_diagram)
{
    c5_rq q;
    c5_rq_cfg cfg = {5, 8};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    step(&q, 1, 10, 0, 0);
    step(&q, 1, 20, 0, 0);
    step(&q, 1, 30, 0, 0);
    step(&q, 0, 0, 0, 0);
    step(&q, 0, 0, 0, 0);
    CHECK(stages_are(&q, "|10 |20 |30 |.", -1) == 0);
    static const struct {
        int iv;
        uint32_t key;
        int pr, pv;
        uint32_t pk, pp, count;
        const char *regs;
    } t[] = {
        /* payloads: 0 for the preamble, 100 + cycle for the inserts below */
        {1, 25, 0, 0, 0, 0, 3, "|10 25*|20 |30 |."},
        {1, 5, 1, 1, 10, 0, 4, "|5 20>|25 30>|. |."},
        {1, 20, 1, 1, 5, 101, 4, "|20 20*|25 30>|. |."},
        {0, 0, 1, 1, 20, 0, 4, "|20 |25 30>|. |."}, /* the older 20 */
        {0, 0, 0, 0, 0, 0, 3, "|20 |25 |30 |."},
    };
    for (int i = 0; i < 5; i++) {
        c5_rq_out o = step(&q, t[i].iv, t[i].key, 100 + (uint32_t)i, t[i].pr);
        CHECK_MSG(o.pop_valid == t[i].pv && o.pop_key == t[i].pk && o.pop_payload == t[i].pp &&
                      o.count == t[i].count,
                  "t%d: pop_valid %d key %u payload %u count %u", i, o.pop_valid, o.pop_key, o.pop_payload, o.count);
        CHECK(stages_are(&q, t[i].regs, i) == 0);
    }
    /* the 20 inserted at t2 leaves after the older one */
    c5_rq_out o = step(&q, 0, 0, 0, 1);
    CHECK(o.pop_valid && o.pop_key == 20 && o.pop_payload == 102);
    c5_rq_free(&q);
}

TEST(queue_fill_to_capacity_257th_refused)
{
    c5_rq q;
    c5_rq_cfg cfg = C5_RQ_CFG_DEFAULT;
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    uint64_t s = 257;
    uint32_t keys[256];
    for (uint32_t i = 0; i < 256; i++) {
        keys[i] = (uint32_t)c5_splitmix64(&s);
        c5_rq_out o = step(&q, 1, keys[i], i, 0);
        CHECK_MSG(o.insert_accepted && !o.full && o.count == i, "insert %u: accepted %d full %d count %u", i,
                  o.insert_accepted, o.full, o.count);
    }
    CHECK_INT(q.count, 256);
    c5_rq_out o = step(&q, 1, 0, 999, 0); /* the 257th, with the smallest key of all */
    CHECK_INT(o.insert_accepted, 0);
    CHECK_INT(o.full, 1);
    CHECK_INT(o.count, 256);
    CHECK_INT(q.stats.refused, 1);
    CHECK_INT(q.stats.inserts, 256);
    CHECK_INT(q.stats.max_count, 256);
    CHECK_INT(q.count, 256);
    CHECK(check_registers(&q, -1) == 0);
    /* the refused ray is nowhere; the 256 leave in key order */
    for (uint32_t i = 1; i < 256; i++)
        for (uint32_t j = i; j > 0 && keys[j - 1] > keys[j]; j--) {
            uint32_t t = keys[j];
            keys[j] = keys[j - 1];
            keys[j - 1] = t;
        }
    for (uint32_t i = 0; i < 256; i++) {
        o = step(&q, 0, 0, 0, 1);
        CHECK_MSG(o.pop_valid && o.pop_key == keys[i] && o.pop_payload != 999, "pop %u: valid %d key %u want %u",
                  i, o.pop_valid, o.pop_key, keys[i]);
    }
    o = step(&q, 0, 0, 0, 1);
    CHECK(!o.pop_valid && o.empty);
    c5_rq_free(&q);
}

TEST(queue_drain_until_empty)
{
    c5_rq q;
    c5_rq_cfg cfg = {16, 16};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    for (uint32_t i = 0; i < 10; i++)
        step(&q, 1, (i * 7) % 10, i, 0);
    /* drain at once, with the last inserts still rippling */
    for (uint32_t i = 0; i < 10; i++) {
        c5_rq_out o = step(&q, 0, 0, 0, 1);
        CHECK_MSG(o.pop_valid && o.pop_key == i && o.count == 10 - i && !o.empty, "pop %u: valid %d key %u count %u",
                  i, o.pop_valid, o.pop_key, o.count);
        CHECK(check_registers(&q, i) == 0);
    }
    for (int i = 0; i < 3; i++) {
        c5_rq_out o = step(&q, 0, 0, 0, 1);
        CHECK(!o.pop_valid && o.pop_key == 0 && o.pop_payload == 0 && o.empty && o.count == 0);
    }
    CHECK_INT(q.stats.pops, 10);
    CHECK_INT(q.len, 0);
    c5_rq_free(&q);
}

TEST(queue_reset)
{
    c5_rq q;
    c5_rq_cfg cfg = {8, 8};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    for (uint32_t i = 0; i < 9; i++)
        step(&q, 1, 100 - i, i, 0); /* the 9th is refused; carries are in flight */
    step(&q, 1, 0x1FF, 0, 0);      /* a masked key */
    CHECK(q.count == 8 && q.stats.refused == 2 && q.stats.masked_keys == 1);
    int in_flight = 0;
    for (uint32_t i = 0; i <= 8; i++)
        in_flight += q.carry[i].valid;
    CHECK(in_flight > 0);
    c5_rq_reset(&q);
    CHECK_INT(q.count, 0);
    CHECK_INT(q.len, 0);
    CHECK(q.stats.cycles == 0 && q.stats.inserts == 0 && q.stats.pops == 0 && q.stats.refused == 0 &&
          q.stats.masked_keys == 0 && q.stats.max_count == 0);
    for (uint32_t i = 0; i < 8; i++)
        CHECK(!q.held[i].valid && !q.carry[i].valid);
    CHECK(!q.carry[8].valid);
    CHECK_INT(q.cfg.capacity, 8);
    static const row rows[] = {
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},
        {1, 42, 7, 0, 0, 0, 0, 1, 0, 0},
        {0, 0, 0, 1, 1, 42, 7, 0, 0, 1},
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},
    };
    int rc = TRACE(&q, rows);
    CHECK_INT(q.stats.cycles, 4);
    c5_rq_free(&q);
    CHECK_INT(rc, 0);
}

/* ---- edge capacities and key widths ------------------------------------------------ */

TEST(queue_capacity_1)
{
    c5_rq q;
    c5_rq_cfg cfg = {1, 8};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    static const row rows[] = {
        {1, 9, 1, 1, 0, 0, 0, 1, 0, 0}, /* insert + pop on empty */
        {1, 3, 2, 0, 0, 0, 0, 0, 1, 1}, /* full: refused even though 3 < 9 */
        {1, 3, 3, 1, 1, 9, 1, 1, 0, 1}, /* pop + insert on full */
        {1, 4, 4, 1, 1, 3, 3, 1, 0, 1},
        {0, 0, 0, 0, 0, 0, 0, 0, 1, 1},
        {0, 0, 0, 1, 1, 4, 4, 0, 0, 1},
        {1, 5, 5, 0, 0, 0, 0, 1, 0, 0},
        {0, 0, 0, 1, 1, 5, 5, 0, 0, 1},
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},
    };
    int rc = TRACE(&q, rows);
    CHECK_INT(q.stats.refused, 1);
    CHECK_INT(q.stats.max_count, 1);
    c5_rq_free(&q);
    CHECK_INT(rc, 0);
}

TEST(queue_capacity_2)
{
    c5_rq q;
    c5_rq_cfg cfg = {2, 8};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    static const row rows[] = {
        {1, 8, 1, 0, 0, 0, 0, 1, 0, 0},
        {1, 2, 2, 0, 0, 0, 0, 1, 0, 1}, /* 2 displaces 8 into the carry line */
        {1, 1, 3, 0, 0, 0, 0, 0, 1, 2}, /* refused while 8 still ripples */
        {1, 1, 4, 1, 1, 2, 2, 1, 0, 2},
        {1, 8, 5, 1, 1, 1, 4, 1, 0, 2}, /* equal to the held 8: behind it */
        {1, 0, 6, 1, 1, 8, 1, 1, 0, 2},
        {0, 0, 0, 1, 1, 0, 6, 0, 0, 2},
        {0, 0, 0, 1, 1, 8, 5, 0, 0, 1},
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},
    };
    int rc = TRACE(&q, rows);
    c5_rq_free(&q);
    CHECK_INT(rc, 0);
}

TEST(queue_key_width_1_bit)
{
    c5_rq q;
    c5_rq_cfg cfg = {8, 1};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    static const row rows[] = {
        {1, 1, 1, 0, 0, 0, 0, 1, 0, 0},
        {1, 0, 2, 0, 0, 0, 0, 1, 0, 1},
        {1, 1, 3, 0, 0, 0, 0, 1, 0, 2},
        {1, 2, 4, 0, 0, 0, 0, 1, 0, 3}, /* too wide: masked to 0 */
        {1, 3, 5, 0, 0, 0, 0, 1, 0, 4}, /* masked to 1 */
        {1, 0, 6, 0, 0, 0, 0, 1, 0, 5},
        {0, 0, 0, 1, 1, 0, 2, 0, 0, 6},
        {0, 0, 0, 1, 1, 0, 4, 0, 0, 5},
        {0, 0, 0, 1, 1, 0, 6, 0, 0, 4},
        {0, 0, 0, 1, 1, 1, 1, 0, 0, 3},
        {0, 0, 0, 1, 1, 1, 3, 0, 0, 2},
        {0, 0, 0, 1, 1, 1, 5, 0, 0, 1},
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},
    };
    int rc = TRACE(&q, rows);
    CHECK_INT(q.stats.masked_keys, 2);
    CHECK_INT(rc, 0);
    /* a wide key counts even when the insert is refused, never when insert_valid is 0 */
    for (int i = 0; i < 8; i++)
        step(&q, 1, 0, 0, 0);
    step(&q, 1, 0xFFFFFFFFu, 0, 0);
    step(&q, 0, 0xFFFFFFFFu, 0, 0);
    CHECK_INT(q.stats.masked_keys, 3);
    CHECK_INT(q.stats.refused, 1);
    c5_rq_free(&q);
}

TEST(queue_key_width_32_bits)
{
    c5_rq q;
    c5_rq_cfg cfg = {4, 32};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    static const row rows[] = {
        {1, 0xFFFFFFFFu, 1, 0, 0, 0, 0, 1, 0, 0},
        {1, 0xFFFFFFFFu, 2, 0, 0, 0, 0, 1, 0, 1},
        {1, 0, 3, 0, 0, 0, 0, 1, 0, 2},
        {1, 0xFFFFFFFEu, 4, 1, 1, 0, 3, 1, 0, 3},
        {1, 0x80000000u, 5, 1, 1, 0xFFFFFFFEu, 4, 1, 0, 3},
        {0, 0, 0, 1, 1, 0x80000000u, 5, 0, 0, 3},
        {0, 0, 0, 1, 1, 0xFFFFFFFFu, 1, 0, 0, 2},
        {0, 0, 0, 1, 1, 0xFFFFFFFFu, 2, 0, 0, 1},
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0},
    };
    int rc = TRACE(&q, rows);
    CHECK_INT(q.stats.masked_keys, 0);
    c5_rq_free(&q);
    CHECK_INT(rc, 0);
}

/* ---- random runs against the oracle ------------------------------------------------- */

typedef struct {
    uint64_t cycles, insert_cycles, masked, refused, full_swaps;
    uint32_t max_count;
} run_info;

/* Random bursts: each phase picks insert and pop probabilities (including always/never)
 * and a key range (narrow ranges make many equal keys). Checks every cycle's outputs and
 * registers against the oracle; returns 0 or -1 after reporting. */
static int random_run(uint32_t cap, uint32_t key_bits, uint64_t seed, long cycles, run_info *info)
{
    static const double probs[] = {0.0, 0.1, 0.5, 0.9, 1.0};
    c5_rq q;
    c5_rq_cfg cfg = {cap, key_bits};
    if (c5_rq_init(&q, &cfg) != 0) {
        c5t_failf(__FILE__, __LINE__, "init %u %u", cap, key_bits);
        return -1;
    }
    oracle o;
    oracle_init(&o, cap, key_bits);
    uint64_t s = seed;
    double p_ins = 0, p_pop = 0;
    uint32_t key_range = 1;
    long phase_end = 0;
    int rc = 0;
    memset(info, 0, sizeof *info);
    uint32_t mask = key_bits == 32 ? 0xFFFFFFFFu : (1u << key_bits) - 1u;
    for (long t = 0; t < cycles && rc == 0; t++) {
        if (t == phase_end) {
            phase_end = t + 1 + (long)(c5_splitmix64(&s) % 200);
            p_ins = probs[c5_splitmix64(&s) % 5];
            p_pop = probs[c5_splitmix64(&s) % 5];
            uint32_t r = (uint32_t)(c5_splitmix64(&s) % 4);
            key_range = r == 0 ? 2 : r == 1 ? 8 : r == 2 ? 1000 : 0; /* 0: full width */
        }
        c5_rq_in in;
        in.insert_valid = c5_uniform(&s) < p_ins;
        in.pop_ready = c5_uniform(&s) < p_pop;
        uint64_t k = c5_splitmix64(&s);
        in.insert_key = key_range ? (uint32_t)(k % key_range) & mask : (uint32_t)k & mask;
        if ((k >> 40) % 100 == 0)
            in.insert_key |= (uint32_t)(k >> 8) & ~mask; /* now and then too wide */
        in.insert_payload = (uint32_t)t;
        if (!in.insert_valid && (k & 1)) /* idle inputs must be ignored */
            in.insert_key = in.insert_payload = 0xDEADBEEFu;
        c5_rq_out got, want;
        c5_rq_step(&q, &in, &got);
        oracle_step(&o, &in, &want);
        info->insert_cycles += in.insert_valid != 0;
        info->full_swaps += got.count == cap && got.pop_valid && got.insert_accepted;
        if (!out_equal(&got, &want)) {
            char g[200], w[200];
            out_str(&got, g, sizeof g);
            out_str(&want, w, sizeof w);
            c5t_failf(__FILE__, __LINE__, "cap %u key_bits %u cycle %ld:\n      got  %s\n      want %s", cap,
                      key_bits, t, g, w);
            rc = -1;
        } else if (q.count != o.n) {
            c5t_failf(__FILE__, __LINE__, "cycle %ld: count %u, oracle %u", t, q.count, o.n);
            rc = -1;
        } else {
            rc = check_registers(&q, t);
        }
    }
    if (rc == 0) {
        /* statistics and conservation: everything accepted was popped or is still inside */
        info->cycles = q.stats.cycles;
        info->masked = q.stats.masked_keys;
        info->refused = q.stats.refused;
        info->max_count = q.stats.max_count;
        if (q.stats.cycles != (uint64_t)cycles || q.stats.inserts != o.inserts || q.stats.pops != o.pops ||
            q.stats.refused != o.refused || q.stats.masked_keys != o.masked ||
            q.stats.inserts != q.stats.pops + q.count || q.stats.inserts + q.stats.refused != info->insert_cycles) {
            c5t_failf(__FILE__, __LINE__,
                      "stats: cycles %llu inserts %llu pops %llu refused %llu masked %llu count %u; oracle inserts "
                      "%llu pops %llu refused %llu masked %llu; insert cycles %llu",
                      (unsigned long long)q.stats.cycles, (unsigned long long)q.stats.inserts,
                      (unsigned long long)q.stats.pops, (unsigned long long)q.stats.refused,
                      (unsigned long long)q.stats.masked_keys, q.count, (unsigned long long)o.inserts,
                      (unsigned long long)o.pops, (unsigned long long)o.refused, (unsigned long long)o.masked,
                      (unsigned long long)info->insert_cycles);
            rc = -1;
        }
    }
    /* drain: the remaining elements leave in oracle order */
    while (rc == 0 && o.n > 0) {
        c5_rq_in in = {0, 0, 0, 1};
        c5_rq_out got, want;
        c5_rq_step(&q, &in, &got);
        oracle_step(&o, &in, &want);
        if (!out_equal(&got, &want)) {
            c5t_failf(__FILE__, __LINE__, "drain: key %u payload %u, oracle %u %u", got.pop_key, got.pop_payload,
                      want.pop_key, want.pop_payload);
            rc = -1;
        }
    }
    if (rc == 0 && (q.count != 0 || q.stats.inserts != q.stats.pops)) {
        c5t_failf(__FILE__, __LINE__, "after the drain: count %u inserts %llu pops %llu", q.count,
                  (unsigned long long)q.stats.inserts, (unsigned long long)q.stats.pops);
        rc = -1;
    }
    c5_rq_free(&q);
    free(o.a);
    return rc;
}

TEST(queue_random_vs_oracle_256)
{
    run_info info;
    CHECK_INT(random_run(256, 32, 0xC0BE5u, 100000, &info), 0);
    CHECK(info.masked == 0); /* 32-bit keys cannot be too wide */
    /* the bursts fill the queue: refusals and insert+pop at capacity happen */
    CHECK(info.max_count == 256 && info.refused > 100 && info.full_swaps > 100);
    CHECK_INT(random_run(256, 12, 0x5EED1u, 100000, &info), 0);
    CHECK(info.masked > 0);
    CHECK(info.max_count == 256 && info.refused > 100 && info.full_swaps > 100);
}

TEST(queue_random_vs_oracle_small)
{
    static const uint32_t caps[] = {1, 2, 3, 5, 17, 64};
    static const uint32_t bits[] = {1, 2, 3, 32};
    uint64_t seed = 77;
    run_info info;
    for (size_t c = 0; c < sizeof caps / sizeof caps[0]; c++)
        for (size_t b = 0; b < sizeof bits / sizeof bits[0]; b++)
            CHECK_MSG(random_run(caps[c], bits[b], seed++, 20000, &info) == 0, "cap %u key_bits %u", caps[c],
                      bits[b]);
}

/* The random runs really reach the interesting states: full with refusals, many equal
 * keys, simultaneous insert and pop at capacity. Guards against a generator that never
 * tests anything. */
TEST(queue_random_coverage)
{
    c5_rq q;
    c5_rq_cfg cfg = {5, 2};
    CHECK_INT(c5_rq_init(&q, &cfg), 0);
    uint64_t s = 3;
    long full_swaps = 0, refused = 0, equal_pops = 0;
    uint32_t last_key = 0xFFFFFFFFu;
    for (long t = 0; t < 20000; t++) {
        c5_rq_in in = {c5_uniform(&s) < 0.6, (uint32_t)(c5_splitmix64(&s) & 3), (uint32_t)t, c5_uniform(&s) < 0.5};
        c5_rq_out o;
        c5_rq_step(&q, &in, &o);
        full_swaps += o.count == 5 && o.pop_valid && o.insert_accepted;
        refused += in.insert_valid && !o.insert_accepted;
        if (o.pop_valid) {
            equal_pops += o.pop_key == last_key;
            last_key = o.pop_key;
        }
    }
    CHECK(full_swaps > 100 && refused > 100 && equal_pops > 1000);
    CHECK_INT(q.stats.refused, refused);
    c5_rq_free(&q);
}
