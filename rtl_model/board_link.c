/* The board's end of the link between boards (opts.link; rtl_model/multi_board.h,
 * docs/multi-board.md): the out-box of packets for other boards' cells, the eye-ray probe
 * that decides which board generates each pixel's eye ray, and the exchange when this
 * board's queues are empty. */
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
        if (!d) {
            b->oom = 1;
            return 1;
        }
        b->out_dest = d;
        b->cap_out = cap;
    }
    c5_bray q = *r;
    q.node = C5_NODE_NONE; /* a node of this board's tree means nothing to the receiver's */
    c5_bray_pack(&q, &b->cells, b->out_pk[b->n_out]);
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
    for (size_t i = 0; i < n_in; i++) {
        c5_bray r;
        c5_bray_unpack(in[i], &b->cells, &r);
        if ((int)r.cell >= b->cells.count || l->owner[r.cell] != l->self)
            return c5_fail(err, "board %d received a ray for cell %u, which it does not own", l->self, r.cell);
        r.node = C5_NODE_NONE;
        r.shadow = C5_DEMAND_NONE;
        c5_bd_dsp_queue(b, &r, 1);
    }
    st->link_received += n_in;
    if (b->oom)
        return c5_fail(err, "out of memory for the DSP's SDRAM ray queues");
    return more;
}

/* The next cell to load; with several boards, exchanges while this board's queues are empty
 * (so a followed schedule is not run through while rays are still on their way). -1: the
 * frame is over, -2: an error (err set). */
int c5_bd_next_cell(c5_bd *b, int *sched_pos, c5_err *err)
{
    if (!b->o->link)
        return c5_bd_schedule(b, sched_pos);
    while (!b->queued) {
        int more = link_round(b, err);
        if (more <= 0)
            return more < 0 ? -2 : -1;
    }
    return c5_bd_schedule(b, sched_pos);
}

