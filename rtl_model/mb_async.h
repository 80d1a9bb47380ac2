/* The asynchronous link between boards (docs/multi-board.md, "Asynchronous boards"): each
 * board runs on its own clock and a packet travels as soon as it is handed on, through the
 * sender's port, the switch and the receiver's port. Private to the multi-board layer.
 *
 * The model:
 *  - a port moves one 32-byte packet in 32 / bandwidth; the sender's port takes its packets
 *    in the order they were handed on, the receiver's in the order they reach the switch
 *    (ties: by sender), each after the one before;
 *  - a packet reaches the switch `latency` after it leaves the sender's port; it has arrived
 *    when the receiver's port has taken it.
 * Times inside the link are ticks of 1/256 board cycle, so that a packet's time on a fast
 * link (0.1 cycle on PCIe 4.0 x16) is not rounded to a whole cycle; a board sees an arrival
 * at the next whole cycle.
 *
 * The simulation (conservative, with the latency as its lookahead): at each exchange every
 * board sends the packets it has handed on so far and reports the earliest time it may send
 * again (c5_link_report.next, or a packet on its way to it arriving sooner); B is the least of
 * them. Any packet not yet sent is handed on after B and reaches the switch after B +
 * latency, so each receiver's port takes, in their order at the switch, the packets that
 * reach it by then, and every board knows each arrival up to B + lookahead. Every board takes part in
 * every exchange, so the transport's collectives match; the exchanges are the simulation's,
 * not the boards': the boards' times come from the model only, so the results are the same
 * for any transport and any number of processes. */
#ifndef C5_MB_ASYNC_H
#define C5_MB_ASYNC_H

#include "multi_board.h"

#define C5_MB_TICKS 256 /* link ticks a board cycle */

/* What travels beside each packet in the simulation (in a 32-byte record of its own): when it
 * reaches the switch (ticks) and when it was handed on (cycles). */
typedef struct {
    uint64_t at_switch, sent;
} c5_mb_wire;

/* A packet on its way to this board. */
typedef struct {
    uint64_t at_switch, sent; /* when it reaches the switch (ticks), when it was handed on (cycles) */
    uint64_t i;               /* the order received */
    size_t slot;              /* its bytes in c5_mb_async.wait */
} c5_mb_arrival;

typedef struct {
    const c5_mb_transport *t;
    uint64_t ser, lat;        /* ticks: a packet's time on a port, the switch's latency */
    uint64_t lookahead;       /* board cycles: the least time a packet takes, at least 1 */
    uint64_t tx_free, rx_free; /* ticks: when each of this board's ports is next free */
    uint64_t tx_busy, rx_busy; /* ticks each port worked */
    uint64_t last_arrival;    /* cycles: arrivals are handed to the board in order */
    uint64_t exchanges;
    c5_link_report *all;      /* [boards] */
    uint8_t (*rec)[C5_PACKET_BYTES]; /* [n sent] each packet's times, sent beside it */
    size_t cap_rec;
    uint64_t received;        /* packets received so far: their order */
    uint8_t (*wait)[C5_PACKET_BYTES]; /* [n_wait] packets not yet through the receiver's port */
    c5_mb_arrival *order;     /* [n_wait] them, by the time they reach the switch */
    size_t n_wait;
    uint8_t (*spare)[C5_PACKET_BYTES];
    uint8_t (*in)[C5_PACKET_BYTES]; /* [n_in] through the port, in the order they arrive */
    uint64_t *t_in;
    size_t n_in, cap_in;
} c5_mb_async;

/* For t's boards under the link of ms (link_bw, link_latency_s). 0, or -1 with a message. */
int c5_mb_async_init(c5_mb_async *a, const c5_mb_transport *t, const c5_mb_stats *ms, c5_err *err);
void c5_mb_async_free(c5_mb_async *a);

/* c5_board_link.exchange_async, ctx a c5_mb_async. */
int c5_mb_async_exchange(void *ctx, const c5_link_report *me, const uint8_t (*out)[C5_PACKET_BYTES],
                         const uint16_t *dest, const uint64_t *t_out, size_t n_out,
                         const uint8_t (**in)[C5_PACKET_BYTES], const uint64_t **t_in, size_t *n_in,
                         uint64_t *bound, c5_err *err);

/* c5_board_link.reports: every board's report at the last exchange. */
const c5_link_report *c5_mb_async_reports(void *ctx);

#endif
