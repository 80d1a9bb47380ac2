/* The asynchronous link (rtl_model/mb_async.h) between board 0 and a scripted board 1: the
 * sender's port, the receiver's port in the order packets reach the switch, the packets held
 * back beyond what the boards know, the bound, the end. Times worked by hand from the model's
 * rules: 125 MB/s and 50 us, so a packet takes 25.6 cycles (6,554 ticks, rounded up) on a port
 * and 5,000 cycles (1,280,000 ticks) through the switch. */
#include <string.h>

#include "harness.h"
#include "mb_async.h"

enum { SER = 6554, LAT = 1280000, T = C5_MB_TICKS };

/* Board 1's side of each collective, and what board 0 gave. */
typedef struct {
    c5_link_report peer;         /* board 1's report */
    uint8_t pk[8][C5_PACKET_BYTES]; /* board 1's packets for board 0 */
    c5_mb_wire wire[8];
    size_t n;
    int calls;                   /* alltoall calls: packets, then their records */
    c5_link_report mine;         /* board 0's report as the link gave it */
    c5_mb_wire sent[8];          /* board 0's records */
    size_t n_sent;
    uint8_t rec[8][C5_PACKET_BYTES];
} script;

static int alltoall(void *ctx, const uint8_t (*out)[C5_PACKET_BYTES], const uint16_t *dest, size_t n_out,
                    const uint8_t (**in)[C5_PACKET_BYTES], size_t *n_in, c5_err *err)
{
    (void)dest, (void)err;
    script *s = ctx;
    if (s->calls++ % 2 == 0) {
        *in = (const uint8_t (*)[C5_PACKET_BYTES])s->pk;
    } else {
        for (size_t i = 0; i < n_out && i < 8; i++)
            memcpy(&s->sent[i], out[i], sizeof s->sent[i]);
        s->n_sent = n_out;
        for (size_t i = 0; i < s->n; i++) {
            memset(s->rec[i], 0, C5_PACKET_BYTES);
            memcpy(s->rec[i], &s->wire[i], sizeof s->wire[i]);
        }
        *in = (const uint8_t (*)[C5_PACKET_BYTES])s->rec;
    }
    *n_in = s->n;
    return 0;
}

static int allgather(void *ctx, const void *mine, size_t bytes, void *all, c5_err *err)
{
    (void)err;
    script *s = ctx;
    memcpy(&s->mine, mine, bytes);
    memcpy(all, mine, bytes);
    memcpy((char *)all + bytes, &s->peer, bytes);
    return 0;
}

static int sum_u64(void *ctx, uint64_t *v, size_t n, c5_err *err)
{
    (void)ctx, (void)v, (void)n, (void)err;
    return 0;
}

static void setup(script *s, c5_mb_transport *t, c5_mb_async *a)
{
    memset(s, 0, sizeof *s);
    *t = (c5_mb_transport){s, 0, 2, alltoall, allgather, sum_u64};
    c5_mb_stats ms = {.link_bw = 125e6, .link_latency_s = 50e-6};
    c5_err err;
    CHECK(c5_mb_async_init(a, t, &ms, &err) == 0);
    CHECK_INT(a->ser, SER);
    CHECK_INT(a->lat, LAT);
    CHECK_INT(a->lookahead, 5000);
}

static uint64_t up(uint64_t ticks) { return (ticks + T - 1) / T; }

TEST(mb_async_sender_port_in_order_handed_on)
{
    script s;
    c5_mb_transport t;
    c5_mb_async a;
    setup(&s, &t, &a);
    uint8_t out[3][C5_PACKET_BYTES] = {{1}, {2}, {3}};
    uint16_t dest[3] = {1, 1, 1};
    uint64_t when[3] = {100, 100, 5000};
    c5_link_report me = {.next = 100, .progress = -1};
    s.peer = (c5_link_report){.next = UINT64_MAX, .progress = -1};
    size_t n_in;
    const uint8_t (*in)[C5_PACKET_BYTES];
    const uint64_t *t_in;
    uint64_t bound;
    c5_err err;
    CHECK_INT(c5_mb_async_exchange(&a, &me, (const uint8_t (*)[C5_PACKET_BYTES])out, dest, when, 3, &in, &t_in,
                                   &n_in, &bound, &err),
              1);
    CHECK_INT(s.n_sent, 3); /* every packet handed on so far leaves */
    CHECK_INT(s.sent[0].at_switch, 100 * T + SER + LAT);
    CHECK_INT(s.sent[1].at_switch, 100 * T + 2 * SER + LAT); /* behind the first on the port */
    CHECK_INT(s.sent[2].at_switch, 5000 * T + SER + LAT);    /* the port was free again */
    CHECK_INT(s.sent[2].sent, 5000);
    CHECK_INT(a.tx_busy, 3 * SER);
    CHECK_INT(bound, 100);
    CHECK_INT(n_in, 0);
    c5_mb_async_free(&a);
}

TEST(mb_async_receiver_port_by_time_at_switch_and_held_beyond_the_bound)
{
    script s;
    c5_mb_transport t;
    c5_mb_async a;
    setup(&s, &t, &a);
    /* board 1's packets, received in this order: the second reaches the switch first, the
     * fourth after what the boards will know */
    uint64_t at[4] = {2000000, 1500000, 2000000, 9000000};
    for (int i = 0; i < 4; i++) {
        s.pk[i][0] = (uint8_t)(10 + i);
        s.wire[i] = (c5_mb_wire){at[i], at[i] / T - 5000};
    }
    s.n = 4;
    s.peer = (c5_link_report){.next = 20000, .progress = -1};
    c5_link_report me = {.next = 3000, .progress = -1};
    size_t n_in;
    const uint8_t (*in)[C5_PACKET_BYTES];
    const uint64_t *t_in;
    uint64_t bound;
    c5_err err;
    CHECK_INT(c5_mb_async_exchange(&a, &me, NULL, NULL, NULL, 0, &in, &t_in, &n_in, &bound, &err), 1);
    /* the bound: board 0's 3000; a packet reaching the switch after (3000 + 5000) cycles
     * waits (the fourth, at 35,156 cycles) */
    CHECK_INT(bound, 3000);
    CHECK_INT(n_in, 3);
    CHECK_INT(in[0][0], 11);
    CHECK_INT(in[1][0], 10); /* a tie at the switch: the order received */
    CHECK_INT(in[2][0], 12);
    uint64_t rx = 1500000 + SER;
    CHECK_INT(t_in[0], up(rx));
    rx = 2000000 + SER;
    CHECK_INT(t_in[1], up(rx));
    rx += SER; /* behind the one before on the port */
    CHECK_INT(t_in[2], up(rx));
    CHECK_INT(a.n_wait, 1);
    /* board 0 reported a packet still on its way no sooner than it reaches the switch */
    CHECK_INT(s.mine.next, 3000);
    /* next exchange: nothing new; board 0 idle; the held packet bounds board 0's report and
     * goes through once the bound allows it */
    s.n = 0;
    me = (c5_link_report){.next = UINT64_MAX, .progress = -1};
    s.peer = (c5_link_report){.next = UINT64_MAX, .progress = -1};
    CHECK_INT(c5_mb_async_exchange(&a, &me, NULL, NULL, NULL, 0, &in, &t_in, &n_in, &bound, &err), 1);
    CHECK_INT(s.mine.next, 9000000 / T);
    CHECK_INT(bound, 9000000 / T);
    CHECK_INT(n_in, 1);
    CHECK_INT(in[0][0], 13);
    CHECK_INT(t_in[0], up(9000000 + SER));
    /* and with nothing anywhere the frame is over */
    CHECK_INT(c5_mb_async_exchange(&a, &me, NULL, NULL, NULL, 0, &in, &t_in, &n_in, &bound, &err), 0);
    CHECK_INT(bound, UINT64_MAX);
    CHECK_INT(a.exchanges, 3);
    c5_mb_async_free(&a);
}

/* A link faster than a cycle still takes the latency: arrivals are never sooner than the
 * lookahead the simulation relies on. */
TEST(mb_async_arrival_never_sooner_than_the_lookahead)
{
    script s;
    memset(&s, 0, sizeof s);
    c5_mb_transport t = {&s, 0, 2, alltoall, allgather, sum_u64};
    c5_mb_stats ms = {.link_bw = 32e9, .link_latency_s = 1e-9}; /* 0.1 cycle */
    c5_mb_async a;
    c5_err err;
    CHECK(c5_mb_async_init(&a, &t, &ms, &err) == 0);
    CHECK_INT(a.lookahead, 1);
    s.wire[0] = (c5_mb_wire){700 * T - 100, 700}; /* the switch time rounds to before the lookahead */
    s.n = 1;
    s.peer = (c5_link_report){.next = 700, .progress = -1};
    c5_link_report me = {.next = UINT64_MAX, .progress = -1};
    size_t n_in;
    const uint8_t (*in)[C5_PACKET_BYTES];
    const uint64_t *t_in;
    uint64_t bound;
    CHECK_INT(c5_mb_async_exchange(&a, &me, NULL, NULL, NULL, 0, &in, &t_in, &n_in, &bound, &err), 1);
    CHECK_INT(n_in, 1);
    CHECK_INT(t_in[0], 701);
    c5_mb_async_free(&a);
}
