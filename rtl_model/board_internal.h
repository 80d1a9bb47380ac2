/* The board model's state during one frame (c5_board_render), shared by the units of the board
 * top: the frame loop (board.c), the DSP's choice of the next cell (dsp/frame_sched.c), the
 * board's end of the multi-board link (board_link.c) and the statistics (board_stats.c).
 * Private to rtl_model: the public interface is board.h. */
#ifndef C5_BOARD_INTERNAL_H
#define C5_BOARD_INTERNAL_H

#include "board.h"
#include "camera.h"
#include "cell_tree_sdram.h"
#include "cells.h"
#include "mw_shadow.h"
#include "processor.h"
#include "ray_queue.h"
#include "regs.h"
#include "rq_heap.h"
#include "tree_demand.h"

/* The board clock: every modelled time is counted in its cycles. */
#define C5_BD_CLOCK_HZ 100e6

typedef struct {
    uint8_t (*pk)[C5_PACKET_BYTES];
    uint32_t *shadow;        /* beside each packet: its instrument node (tree_demand.h) */
    size_t n, head, cap;
} c5_sdram_queue; /* one cell's rays waiting in DSP SDRAM, FIFO */

typedef struct {
    const c5_scene *s;
    const c5_board_opts *o;
    const c5_board_out *keep; /* never NULL: nothing kept is all NULL */
    c5_frame_regs r;
    c5_cells cells;
    c5_rdram mem;
    c5_proc proc;
    c5_sdram_queue *q;          /* [cells] */
    int cycle_level;         /* 1: the active cell's sorter is edram, 0: heap (same ports) */
    c5_rq edram;             /* the clock-level sorter (opts.queue_model C5_QUEUE_CYCLE) */
    c5_rqh heap;             /* its equivalent model (the default) */
    uint8_t (*slot)[C5_PACKET_BYTES]; /* eDRAM packet store, indexed by the sorter's payload */
    uint32_t *slot_shadow;   /* beside each eDRAM packet: its instrument node */
    c5_tree_demand demand;   /* the Cell Tree with unbounded RAM, measured beside the DSP's */
    int group[3], ngroup[3]; /* tree_group: cells a group holds per axis, groups per axis */
    int sgroup[3], nsgroup[3]; /* the same for schedule_group */
    int cur_group;           /* the scheduled group being worked off, -1: none */
    /* Following an external schedule of cells under the certificate (docs/cell-tree.md, "The
     * certificate"): Max Work's shadow on the frame's tree, and the loads the frame may make
     * beyond Max Work's. */
    int certify;
    c5_mw_shadow shadow;
    int64_t budget;
    uint64_t queued;         /* rays in the SDRAM queues (progress) */
    uint32_t *free_slots;
    uint32_t n_free;
    uint32_t seq;            /* FIFO key */
    uint64_t *fb;            /* frame buffer, frame_acc UQ20.12 per channel */
    c5_board_stats *st;
    c5_ctree *tree;          /* opts->tree or own_tree */
    c5_ctree *own_tree;
    c5_sdram_tree *sdram;    /* opts->sdram_tree: the DSP's tree is there instead of in tree */
    int oom;
    /* Several boards (opts.link): packets for other boards' cells, waiting for the exchange;
     * while eye_probe is set, the set-up only records each pixel's first cell in px_owner. */
    uint8_t (*out_pk)[C5_PACKET_BYTES];
    uint16_t *out_dest;
    size_t n_out, cap_out;
    int eye_probe;
    uint16_t *px_owner;      /* [pixels]: the board that generates the pixel's eye ray; UINT16_MAX: unset */
    /* Asynchronous boards (link->exchange_async): each packet's time in the out-box, the
     * in-box of packets on their way (their arrival times, not decreasing from in_head), the
     * time up to which every arrival is known, the cell in RDRAM, and where the processor's
     * cycles of the current load began (emit_base: the board's time then, emit_c0: its
     * count). */
    uint64_t *out_t;
    uint8_t (*in_pk)[C5_PACKET_BYTES];
    uint64_t *in_t;
    size_t n_in, in_head, cap_in;
    uint64_t known_to;
    int resident;
    uint64_t emit_base, emit_c0;
    /* The plan across boards (opts.sched_dep): the entry waiting since, until at most; this
     * board's progress (the last entry passed, when) and the entry being loaded; every board's
     * progress as the exchanges reported it, each with when it was reached. */
    uint64_t wait_since, wake;
    int64_t progress, cur_entry;
    uint64_t progress_t;
    int64_t *seen_prog[C5_LINK_MAX_BOARDS];
    uint64_t *seen_t[C5_LINK_MAX_BOARDS];
    size_t seen_n[C5_LINK_MAX_BOARDS], seen_cap[C5_LINK_MAX_BOARDS];
    struct c5_cell_store *cstore; /* an out-of-core grid's cells on disk (cell_store.h), or NULL */
    struct c5_bd_threads *threads; /* the host's helper threads (board_threads.c), or NULL */
    unsigned long long tree_ticks; /* host time of the Cell Tree's tags (c5_ticks; stats->tree_wall_s) */
    uint32_t *slot_item;     /* with threads: beside each eDRAM packet, its item of the cell's visit */
} c5_bd;

/* c5_bd_schedule: the next entry waits (until b->wake). */
#define C5_BD_WAIT (-4)
/* The board cycles of fetching `cell` from the host. */
uint64_t c5_bd_fetch_cycles(const c5_bd *b, int cell);
/* After an exchange: every board's progress into seen_prog / seen_t. */
void c5_bd_note_reports(c5_bd *b);

/* The board's time (asynchronous boards): its cycles so far, waits included. */
static inline uint64_t c5_bd_clock(const c5_bd *b)
{
    return b->st->cycles_process + b->st->cycles_fetch + b->st->cycles_idle;
}

static inline size_t c5_bd_queued_in(const c5_bd *b, int c) { return b->q[c].n - b->q[c].head; }

/* board.c */
/* The group of `cell` when groups hold g[a] cells and there are ng[a] a axis. */
int c5_bd_group_of(const c5_bd *b, int cell, const int g[3], const int ng[3]);
/* The DSP tags a ray with its Cell Tree node and queues it in SDRAM; arrival: it comes from
 * another cell (a spill of the active cell's own ray is not an arrival). */
void c5_bd_dsp_queue(c5_bd *b, const c5_bray *r, int arrival);
/* Grows packets pk and their instrument nodes shadow to cap entries (board.c): 0, or -1 when
 * memory is short (what grew stays; the caller keeps its old capacity). */
int c5_bd_grow_packets(uint8_t (**pk)[C5_PACKET_BYTES], uint32_t **shadow, size_t cap);
/* The DSP's eye rays, pixel by pixel, through the processor's set-up unit. */
int c5_bd_generate_eye_rays(c5_bd *b, const c5_supervol *sv, int frame, c5_err *err);
/* Pixel px, py's eye ray from O (proto: its other fields) through processor p's set-up unit. */
void c5_bd_eye_ray(c5_proc *p, const c5_camera_basis *basis, const int64_t O[3], const c5_bray *proto, int px, int py);

/* dsp/frame_sched.c: the DSP's choice of the next cell during the frame. */
/* The queues the set-up left against the previous frame's (stale_plan.h): 1 the same rays in
 * the same cells, 0 no cell in common. */
double c5_bd_start_overlap(c5_bd *b);
/* The frame's budget, after the set-up (ledger.h). */
void c5_bd_set_budget(c5_bd *b);
/* The certificate's shadow cannot go on: Max Work on the board's queues chooses the rest. */
void c5_bd_certificate_lost(c5_bd *b);
/* Which cell to load next, or -1 when every queue is empty. */
int c5_bd_schedule(c5_bd *b, int *sched_pos);

/* board_link.c: the board's end of the link between boards (opts.link). */
/* A ray the processor hands on: during the eye-ray probe records the pixel's owner; a ray for
 * another board's cell goes into the out-box. 1: taken here. */
int c5_bd_link_enqueue(c5_bd *b, const c5_bray *r);
/* Which board generates each pixel's eye ray (px_owner). */
int c5_bd_eye_owners(c5_bd *b, const c5_supervol *sv, int frame, c5_err *err);
/* The next cell to load, exchanging with the other boards while this one's queues are empty.
 * -1: the frame is over, -2: an error (err set). */
int c5_bd_next_cell(c5_bd *b, int *sched_pos, c5_err *err);

/* board_edram.c: the active cell's eDRAM (its sorter and the packets in its slots). */
/* One clock cycle of the sorter, seen by the queue tap; its occupancy (accepted, not popped). */
void c5_bd_edram_step(c5_bd *b, const c5_rq_in *in, c5_rq_out *out);
uint32_t c5_bd_edram_count(const c5_bd *b);
/* A ray, or its packet, into the sorter: 1 if accepted. item: its item of the cell's visit, or
 * C5_BD_NO_ITEM. */
int c5_bd_edram_insert(c5_bd *b, const c5_bray *r, uint32_t item);
int c5_bd_edram_insert_packet(c5_bd *b, const uint8_t pk[C5_PACKET_BYTES], uint32_t shadow, uint32_t item);
/* Moves rays from the cell's SDRAM queue into the sorter while it has room. */
void c5_bd_refill(c5_bd *b, c5_sdram_queue *q);
/* A packet as it is written into a queue (eDRAM or SDRAM), seen by the packet tap. */
void c5_bd_pack(c5_bd *b, const c5_bray *r, uint8_t pk[C5_PACKET_BYTES]);
/* A packet on the ray bus, seen by the bus tap (pk NULL: packed from r, only when the tap is set). */
void c5_bd_bus_tap(const c5_bd *b, const c5_bray *r, const uint8_t *pk, int to_dsp);

/* board_threads.c: the host's helper threads (c5_board_opts.threads). */
#define C5_BD_NO_ITEM UINT32_MAX
/* threads - 1 helpers started (none when threads < 2). 0, or -1 out of memory (b->threads
 * stays NULL: the board's thread runs the frame alone, the same bits). */
int c5_bd_threads_init(c5_bd *b, int threads);
void c5_bd_threads_free(c5_bd *b);
/* The visit of `cell` begins: the rays in its SDRAM queue become the phase's items. */
void c5_bd_threads_cell_begin(c5_bd *b, int cell);
/* The item of the ray refill moves next into the sorter (C5_BD_NO_ITEM: none), and that it
 * was moved. */
uint32_t c5_bd_threads_refill_item(c5_bd *b);
void c5_bd_threads_refilled(c5_bd *b);
/* The popped ray is item `item`: 1 if its run was replayed from a helper's log, 0 if the
 * caller runs it. */
int c5_bd_threads_take(c5_bd *b, size_t item);
/* The visit's queues are empty: the helpers' counters join the processor's. */
void c5_bd_threads_cell_end(c5_bd *b);
/* Every pixel's eye ray with the helpers: 1, or 0 if the caller is to generate them. */
int c5_bd_threads_eye_rays(c5_bd *b, const c5_camera_basis *basis, const int64_t O[3], const c5_bray *proto);

/* board_stats.c: the frame's statistics from the processor, the queues and the trees. */
void c5_bd_collect_stats(c5_bd *b);

#endif
