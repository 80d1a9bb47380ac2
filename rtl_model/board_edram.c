/* The active cell's eDRAM on the board: its ray queue (stepped once a clock cycle: the
 * equivalent model rq_heap.h, or the clock-level insertion sorter ray_queue.h), the packets
 * in its slots, the keys they are sorted by, and its feed from the cell's SDRAM queue; the
 * packet and bus taps (board_internal.h, docs/board-model.md). */
#include <string.h>

#include "board_internal.h"
#include "c5_layouts.h"
#include "taps.h"

static uint32_t morton(uint32_t x, uint32_t y, uint32_t z)
{
    uint32_t k = 0;
    for (int i = 0; i < 9; i++)
        k |= ((x >> i) & 1u) << (3 * i) | ((y >> i) & 1u) << (3 * i + 1) | ((z >> i) & 1u) << (3 * i + 2);
    return k;
}

static uint32_t queue_key(c5_bd *b, const c5_bray *r)
{
    if (b->o->key == C5_KEY_FIFO)
        return b->seq++;
    return morton((uint32_t)((r->pos[0] >> C5_POS_F) - b->mem.lo[0]), (uint32_t)((r->pos[1] >> C5_POS_F) - b->mem.lo[1]),
                  (uint32_t)((r->pos[2] >> C5_POS_F) - b->mem.lo[2]));
}

/* queue_key of a packet queued for the active cell: its position is from the cell's corner,
 * mem.lo, so the voxel offsets are the position fields' integer parts. */
static uint32_t packet_key(c5_bd *b, const uint8_t pk[C5_PACKET_BYTES])
{
    if (b->o->key == C5_KEY_FIFO)
        return b->seq++;
    c5_ray_packet_t f;
    c5_ray_packet_unpack(pk, &f);
    return morton((uint32_t)(f.pos_x >> C5_POS_F), (uint32_t)(f.pos_y >> C5_POS_F), (uint32_t)(f.pos_z >> C5_POS_F));
}

/* One clock cycle of the active cell's sorter, seen by the queue tap. */
void c5_bd_edram_step(c5_bd *b, const c5_rq_in *in, c5_rq_out *out)
{
    if (b->cycle_level)
        c5_rq_step(&b->edram, in, out);
    else
        c5_rqh_step(&b->heap, in, out);
    const c5_taps *t = b->o->taps;
    if (t && t->queue)
        t->queue(t->ctx, in, out);
}

/* The sorter's occupancy (elements accepted and not popped). */
uint32_t c5_bd_edram_count(const c5_bd *b)
{
    return b->cycle_level ? b->edram.count : b->heap.count;
}

/* A packet as it is written into a queue (eDRAM or SDRAM), seen by the packet tap. */
void c5_bd_pack(c5_bd *b, const c5_bray *r, uint8_t pk[C5_PACKET_BYTES])
{
    c5_bray_pack(r, &b->cells, pk);
    const c5_taps *t = b->o->taps;
    if (t && t->packet)
        t->packet(t->ctx, pk);
}

/* One cycle of the sorter with an insert of ray r (pk NULL) or of packet pk queued for the
 * active cell, with key and instrument node `shadow`: 1 if accepted. item: the ray's item of
 * the cell's visit (board_threads.c), or C5_BD_NO_ITEM. */
static int sorter_insert(c5_bd *b, const c5_bray *r, const uint8_t *pk, uint32_t key, uint32_t shadow,
                         uint32_t item)
{
    uint32_t slot = b->free_slots[b->n_free - 1];
    c5_rq_in in = {.insert_valid = 1, .insert_key = key, .insert_payload = slot};
    c5_rq_out out;
    c5_bd_edram_step(b, &in, &out);
    if (!out.insert_accepted)
        return 0;
    b->n_free--;
    if (pk)
        memcpy(b->slot[slot], pk, C5_PACKET_BYTES);
    else
        c5_bd_pack(b, r, b->slot[slot]);
    b->slot_shadow[slot] = shadow;
    if (b->slot_item)
        b->slot_item[slot] = item;
    return 1;
}

static int sorter_full(const c5_bd *b) { return b->n_free == 0 || c5_bd_edram_count(b) >= (uint32_t)b->o->queue_capacity; }

/* A ray into the active cell's sorter: 1 if accepted. */
int c5_bd_edram_insert(c5_bd *b, const c5_bray *r, uint32_t item)
{
    return !sorter_full(b) && sorter_insert(b, r, NULL, queue_key(b, r), r->shadow, item);
}

/* A packet queued for the active cell into its sorter: 1 if accepted. */
int c5_bd_edram_insert_packet(c5_bd *b, const uint8_t pk[C5_PACKET_BYTES], uint32_t shadow, uint32_t item)
{
    return !sorter_full(b) && sorter_insert(b, NULL, pk, packet_key(b, pk), shadow, item);
}

/* A packet on the ray bus, seen by the bus tap (only packed when the tap is set). */
void c5_bd_bus_tap(const c5_bd *b, const c5_bray *r, const uint8_t *pk, int to_dsp)
{
    const c5_taps *t = b->o->taps;
    if (!t || !t->bus)
        return;
    uint8_t own[C5_PACKET_BYTES];
    if (!pk) {
        c5_bray_pack(r, &b->cells, own);
        pk = own;
    }
    t->bus(t->ctx, pk, to_dsp);
}

/* Moves rays from the cell's SDRAM queue into the sorter while it has room. The packet goes
 * in as it is (pack(unpack(p)) is p: every queued packet was packed), unless a tap watches
 * the packets written and the bus. */
void c5_bd_refill(c5_bd *b, c5_sdram_queue *q)
{
    const int as_is = !b->o->taps;
    while (q->head < q->n && c5_bd_edram_count(b) < (uint32_t)b->o->queue_capacity) {
        const uint8_t *pk = q->pk[q->head];
        uint32_t item = b->threads ? c5_bd_threads_refill_item(b) : C5_BD_NO_ITEM;
        if (as_is) {
            if (!c5_bd_edram_insert_packet(b, pk, q->shadow[q->head], item))
                break;
        } else {
            c5_bray r;
            c5_bray_unpack(pk, &b->cells, &r);
            r.shadow = q->shadow[q->head];
            if (!c5_bd_edram_insert(b, &r, item))
                break;
            c5_bd_bus_tap(b, &r, pk, 0);
        }
        if (b->threads)
            c5_bd_threads_refilled(b);
        q->head++;
        b->queued--;
        b->st->bus_packets++;
    }
    if (q->head == q->n)
        q->head = q->n = 0;
}
