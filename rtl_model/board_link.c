/* The board's end of the link between boards (opts.link; rtl_model/multi_board.h,
 * docs/multi-board.md): the out-box of packets for other boards' cells, the eye-ray probe
 * that decides which board generates each pixel's eye ray, and the exchanges: in rounds,
 * when this board's queues are empty; asynchronously, the in-box of packets on their way and
 * the board's clock. */
#include <stdlib.h>
#include <string.h>

#include "board_internal.h"

/* During the eye-ray probe: records the pixel's first cell's board and drops the ray. Else a
 * ray for another board's cell goes into the out-box as its packet (over the ray bus to the
 * DSP, which sends it on at the next exchange). 1: taken here. */
int c5_bd_link_enqueue(c5_bd *b, const c5_bray *r)
{
    const c5_board_link *l = b->o->link;
    if (b->eye_probe) {
        uint16_t *own = &b->px_owner[(size_t)r->v * (size_t)b->s->render.width + r->u];
        if (*own == UINT16_MAX)
            *own = l->owner[r->cell];
        return 1;
    }
    if (l->owner[r->cell] == l->self)
        return 0;
    if (b->n_out == b->cap_out) {
        size_t cap = b->cap_out ? 2 * b->cap_out : 1024;
        void *p = realloc(b->out_pk, cap * C5_PACKET_BYTES);
        if (p)
            b->out_pk = p;
        void *d = p ? realloc(b->out_dest, cap * sizeof *b->out_dest) : NULL;
        if (d)
            b->out_dest = d;
        void *t = d ? realloc(b->out_t, cap * sizeof *b->out_t) : NULL;
        if (!t) {
            b->oom = 1;
            return 1;
        }
        b->out_t = t;
        b->cap_out = cap;
    }
    c5_bray q = *r;
    q.node = C5_NODE_NONE; /* a node of this board's tree means nothing to the receiver's */
    c5_bray_pack(&q, &b->cells, b->out_pk[b->n_out]);
    /* handed on now: the processor's cycles into the current load (or the set-up) */
    b->out_t[b->n_out] = b->emit_base + (b->proc.st.cycles - b->emit_c0);
    b->out_dest[b->n_out++] = l->owner[r->cell];
    b->st->bus_packets++;
    return 1;
}

/* Which board generates each pixel's eye ray: the owner of the cell the pixel's first queued
 * ray (eye ray, or a ray it spawns before reaching the volume) is for, so that eye rays do
 * not cross the link; pixels whose rays never reach the volume: pixel index mod boards.
 * Every board's set-up unit runs this over every pixel (the same answer on every board);
 * its cycles are charged (cycles_eye_owner), its rays and colours are not kept. */
int c5_bd_eye_owners(c5_bd *b, const c5_supervol *sv, int frame, c5_err *err)
{
    const c5_board_link *l = b->o->link;
    size_t npx = (size_t)b->s->render.width * (size_t)b->s->render.height;
    if (!(b->px_owner = malloc(npx * sizeof *b->px_owner)))
        return c5_fail(err, "out of memory for the board model");
    if (l->boards <= 1) {
        memset(b->px_owner, 0, npx * sizeof *b->px_owner);
        return 0;
    }
    memset(b->px_owner, 0xff, npx * sizeof *b->px_owner);
    b->eye_probe = 1;
    int rc = c5_bd_generate_eye_rays(b, sv, frame, err);
    b->eye_probe = 0;
    b->st->cycles_eye_owner = b->proc.st.cycles;
    b->st->cycles_process += b->proc.st.cycles;
    memset(&b->proc.st, 0, sizeof b->proc.st);
    for (size_t i = 0; i < npx; i++)
        if (b->px_owner[i] == UINT16_MAX)
            b->px_owner[i] = (uint16_t)(i % (size_t)l->boards);
    return rc;
}

/* A packet from another board into this board's SDRAM queues, as a new root of its Cell
 * Tree. */
static int receive(c5_bd *b, const uint8_t pk[C5_PACKET_BYTES], c5_err *err)
{
    const c5_board_link *l = b->o->link;
    c5_bray r;
    c5_bray_unpack(pk, &b->cells, &r);
    if ((int)r.cell >= b->cells.count || l->owner[r.cell] != l->self)
        return c5_fail(err, "board %d received a ray for cell %u, which it does not own", l->self, r.cell);
    r.node = C5_NODE_NONE;
    r.shadow = C5_DEMAND_NONE;
    c5_bd_dsp_queue(b, &r, 1);
    b->st->link_received++;
    return 0;
}

/* This board's queues are empty: one exchange with the other boards; the packets received
 * are queued in SDRAM as new roots of this board's Cell Tree. 1: go on, 0: the frame is over. */
static int link_round(c5_bd *b, c5_err *err)
{
    const c5_board_link *l = b->o->link;
    c5_board_stats *st = b->st;
    st->cycles = st->cycles_process + st->cycles_fetch;
    const uint8_t (*in)[C5_PACKET_BYTES] = NULL;
    size_t n_in = 0;
    int more = l->exchange(l->ctx, (const uint8_t (*)[C5_PACKET_BYTES])b->out_pk, b->out_dest, b->n_out, st, &in,
                           &n_in, err);
    st->link_sent += b->n_out;
    st->link_rounds++;
    b->n_out = 0;
    if (more < 0)
        return -1;
    for (size_t i = 0; i < n_in; i++)
        if (receive(b, in[i], err) != 0)
            return -1;
    if (b->oom)
        return c5_fail(err, "out of memory for the DSP's SDRAM ray queues");
    return more;
}

/* Asynchronous: the packets of the in-box that have arrived by `now` into the queues. */
static int deliver(c5_bd *b, uint64_t now, c5_err *err)
{
    for (; b->in_head < b->n_in && b->in_t[b->in_head] <= now; b->in_head++)
        if (receive(b, b->in_pk[b->in_head], err) != 0)
            return -1;
    if (b->in_head == b->n_in)
        b->in_head = b->n_in = 0;
    return b->oom ? c5_fail(err, "out of memory for the DSP's SDRAM ray queues") : 0;
}

/* Asynchronous: the packets on their way to this board, after those already there (the link
 * hands them over in the order they arrive). */
static int inbox_add(c5_bd *b, const uint8_t (*in)[C5_PACKET_BYTES], const uint64_t *t_in, size_t n, c5_err *err)
{
    if (b->in_head) {
        size_t rest = b->n_in - b->in_head;
        if (rest) {
            memmove(b->in_pk, b->in_pk + b->in_head, rest * C5_PACKET_BYTES);
            memmove(b->in_t, b->in_t + b->in_head, rest * sizeof *b->in_t);
        }
        b->n_in = rest;
        b->in_head = 0;
    }
    if (b->n_in + n > b->cap_in) {
        size_t cap = b->cap_in ? b->cap_in : 1024;
        while (cap < b->n_in + n)
            cap *= 2;
        void *p = realloc(b->in_pk, cap * C5_PACKET_BYTES);
        if (p)
            b->in_pk = p;
        void *t = p ? realloc(b->in_t, cap * sizeof *b->in_t) : NULL;
        if (!t)
            return c5_fail(err, "out of memory for the link's in-box");
        b->in_t = t;
        b->cap_in = cap;
    }
    if (!n)
        return 0;
    memcpy(b->in_pk + b->n_in, in, n * C5_PACKET_BYTES);
    memcpy(b->in_t + b->n_in, t_in, n * sizeof *t_in);
    b->n_in += n;
    return 0;
}

/* Asynchronous: one exchange of the simulation (c5_board_link.exchange_async). */
static int link_sync(c5_bd *b, uint64_t now, uint64_t wake, c5_err *err)
{
    const c5_board_link *l = b->o->link;
    c5_link_report me = {UINT64_MAX, b->progress, b->progress_t};
    if (b->queued) /* waiting for another board's progress not yet known: it may load at once */
        me.next = wake != UINT64_MAX && wake > now ? wake : now;
    if (b->in_head < b->n_in && b->in_t[b->in_head] < me.next)
        me.next = b->in_t[b->in_head];
    size_t n_in = 0;
    const uint8_t (*in)[C5_PACKET_BYTES] = NULL;
    const uint64_t *t_in = NULL;
    uint64_t bound = 0;
    int more = l->exchange_async(l->ctx, &me, (const uint8_t (*)[C5_PACKET_BYTES])b->out_pk, b->out_dest, b->out_t,
                                 b->n_out, &in, &t_in, &n_in, &bound, err);
    if (more < 0)
        return -1;
    b->st->link_rounds++;
    b->st->link_sent += b->n_out; /* the exchange sent them all */
    b->n_out = 0;
    if (inbox_add(b, in, t_in, n_in, err) != 0)
        return -1;
    b->known_to = bound > UINT64_MAX - l->lookahead ? UINT64_MAX : bound + l->lookahead;
    if (l->reports)
        c5_bd_note_reports(b);
    return more;
}

/* Asynchronous: the next cell to load at the board's clock, once every packet that can have
 * arrived by then is known; with every queue empty the board waits for the next arrival. */
static int next_async(c5_bd *b, int *sched_pos, c5_err *err)
{
    for (;;) {
        uint64_t now = c5_bd_clock(b), wake = UINT64_MAX;
        if (deliver(b, now, err) != 0)
            return -2;
        if (b->queued && now <= b->known_to) {
            int c = c5_bd_schedule(b, sched_pos);
            if (c != C5_BD_WAIT)
                return c;
            wake = b->wake;
        }
        uint64_t arrival = b->in_head < b->n_in ? b->in_t[b->in_head] : UINT64_MAX;
        uint64_t until = arrival < wake ? arrival : wake;
        if ((!b->queued || (wake != UINT64_MAX && wake > now)) && until <= b->known_to) {
            b->st->cycles_idle += until - now;
            continue;
        }
        int more = link_sync(b, now, wake, err);
        if (more <= 0)
            return more < 0 ? -2 : -1;
    }
}

/* The next cell to load; with several boards, exchanges while this board's queues are empty
 * (so a followed schedule is not run through while rays are still on their way). -1: the
 * frame is over, -2: an error (err set). */
int c5_bd_next_cell(c5_bd *b, int *sched_pos, c5_err *err)
{
    if (!b->o->link)
        return c5_bd_schedule(b, sched_pos);
    if (b->o->link->exchange_async)
        return next_async(b, sched_pos, err);
    while (!b->queued) {
        int more = link_round(b, err);
        if (more <= 0)
            return more < 0 ? -2 : -1;
    }
    return c5_bd_schedule(b, sched_pos);
}


void c5_bd_note_reports(c5_bd *b)
{
    const c5_board_link *l = b->o->link;
    const c5_link_report *all = l->reports(l->ctx);
    for (int k = 0; k < l->boards && k < C5_LINK_MAX_BOARDS; k++) {
        int64_t p = all[k].progress;
        if (p < 0 || (b->seen_n[k] && b->seen_prog[k][b->seen_n[k] - 1] >= p))
            continue;
        if (b->seen_n[k] == b->seen_cap[k]) {
            size_t cap = b->seen_cap[k] ? 2 * b->seen_cap[k] : 64;
            int64_t *pp = realloc(b->seen_prog[k], cap * sizeof *pp);
            if (pp)
                b->seen_prog[k] = pp;
            uint64_t *tt = pp ? realloc(b->seen_t[k], cap * sizeof *tt) : NULL;
            if (!tt) {
                b->oom = 1;
                return;
            }
            b->seen_t[k] = tt;
            b->seen_cap[k] = cap;
        }
        b->seen_prog[k][b->seen_n[k]] = p;
        b->seen_t[k][b->seen_n[k]++] = all[k].progress_t;
    }
}
