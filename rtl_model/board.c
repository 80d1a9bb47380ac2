/* The board: the DSP (eye rays, SDRAM ray queues, the scheduler, the frame buffer), the
 * RDRAM fetches, the active cell's eDRAM ray queue (stepped once a clock cycle: its
 * equivalent model rq_heap.h, or the clock-level insertion sorter ray_queue.h) and the
 * processor, with the frame's cycle budget (board.h, docs/board-model.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "board.h"
#include "model_limits.h"
#include "ledger.h"
#include "mw_shadow.h"
#include "camera.h"
#include "cells.h"
#include "geom.h"
#include "processor.h"
#include "ray_queue.h"
#include "rq_heap.h"
#include "regs.h"
#include "taps.h"
#include "tree_demand.h"
#include "cell_tree_sdram.h"
#include "clock.h"

#define CLOCK_HZ 100e6
#define RDRAM_BW 800e6

typedef struct {
    uint8_t (*pk)[C5_PACKET_BYTES];
    uint32_t *shadow;        /* beside each packet: its instrument node (tree_demand.h) */
    size_t n, head, cap;
} sdram_queue; /* one cell's rays waiting in DSP SDRAM, FIFO */

typedef struct {
    const c5_scene *s;
    const c5_board_opts *o;
    c5_frame_regs r;
    c5_cells cells;
    c5_rdram mem;
    c5_proc proc;
    sdram_queue *q;          /* [cells] */
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
} board;

static int link_enqueue(board *b, const c5_bray *r);

static int push_sdram(board *b, int cell, const uint8_t pk[C5_PACKET_BYTES], uint32_t shadow)
{
    sdram_queue *q = &b->q[cell];
    if (q->n == q->cap) {
        size_t cap = q->cap ? 2 * q->cap : 256;
        void *p = realloc(q->pk, cap * C5_PACKET_BYTES);
        if (!p)
            return -1;
        q->pk = p;
        void *s = realloc(q->shadow, cap * sizeof *q->shadow);
        if (!s)
            return -1;
        q->shadow = s;
        q->cap = cap;
    }
    q->shadow[q->n] = shadow;
    memcpy(q->pk[q->n++], pk, C5_PACKET_BYTES);
    b->queued++;
    return 0;
}

static uint32_t morton(uint32_t x, uint32_t y, uint32_t z)
{
    uint32_t k = 0;
    for (int i = 0; i < 9; i++)
        k |= ((x >> i) & 1u) << (3 * i) | ((y >> i) & 1u) << (3 * i + 1) | ((z >> i) & 1u) << (3 * i + 2);
    return k;
}

static uint32_t queue_key(board *b, const c5_bray *r)
{
    if (b->o->key == C5_KEY_FIFO)
        return b->seq++;
    return morton((uint32_t)((r->pos[0] >> C5_POS_F) - b->mem.lo[0]), (uint32_t)((r->pos[1] >> C5_POS_F) - b->mem.lo[1]),
                  (uint32_t)((r->pos[2] >> C5_POS_F) - b->mem.lo[2]));
}

/* One clock cycle of the active cell's sorter, seen by the queue tap. */
static void edram_step(board *b, const c5_rq_in *in, c5_rq_out *out)
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
static uint32_t edram_count(const board *b)
{
    return b->cycle_level ? b->edram.count : b->heap.count;
}

/* A packet as it is written into a queue (eDRAM or SDRAM), seen by the packet tap. */
static void pack(board *b, const c5_bray *r, uint8_t pk[C5_PACKET_BYTES])
{
    c5_bray_pack(r, &b->cells, pk);
    const c5_taps *t = b->o->taps;
    if (t && t->packet)
        t->packet(t->ctx, pk);
}

/* One cycle of the sorter with an insert: 1 if accepted. */
static int edram_insert(board *b, const c5_bray *r)
{
    if (b->n_free == 0 || edram_count(b) >= (uint32_t)b->o->queue_capacity)
        return 0;
    uint32_t slot = b->free_slots[b->n_free - 1];
    c5_rq_in in = {.insert_valid = 1, .insert_key = queue_key(b, r), .insert_payload = slot};
    c5_rq_out out;
    edram_step(b, &in, &out);
    if (!out.insert_accepted)
        return 0;
    b->n_free--;
    pack(b, r, b->slot[slot]);
    b->slot_shadow[slot] = r->shadow;
    return 1;
}

/* Cells a group holds along an axis (`want`, at most the axis's cells; < 2: one) and the
 * groups along it. */
static void group_axis(int want, int cells, int *g, int *n)
{
    *g = want > 1 ? (want < cells ? want : cells) : 1;
    *n = (cells + *g - 1) / *g;
}

/* The group of `cell` with g cells a group per axis and ng groups per axis. */
static int group_of(const board *b, int cell, const int g[3], const int ng[3])
{
    if (g[0] * g[1] * g[2] == 1)
        return cell;
    const int *n = b->cells.n;
    int x = cell % n[0], y = cell / n[0] % n[1], z = cell / (n[0] * n[1]);
    return x / g[0] + ng[0] * (y / g[1] + ng[1] * (z / g[2]));
}

/* The Cell Tree's unit: the cell, or its group (c5_board_opts.tree_group). */
static int tree_unit(const board *b, int cell) { return group_of(b, cell, b->group, b->ngroup); }

/* The processor hands a ray on: the active cell's sorter (the ray stays in its cell, so its
 * Cell Tree node stays), else (full, or another cell) over the ray bus to the DSP, which
 * tags it with its node before queueing it in SDRAM. */
static void dsp_queue(board *b, const c5_bray *r, int arrival);

/* A packet on the ray bus, seen by the bus tap (only packed when the tap is set). */
static void bus_tap(const board *b, const c5_bray *r, const uint8_t *pk, int to_dsp)
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

static void on_enqueue(void *ctx, const c5_bray *r)
{
    board *b = ctx;
    if (b->o->moves && !b->eye_probe && (int)r->cell != b->proc.active) {
        int from = b->proc.active < 0 ? (int)r->cell : b->proc.active;
        b->o->moves[(size_t)from * (size_t)b->cells.count + r->cell]++;
    }
    if (b->o->link && link_enqueue(b, r))
        return;
    if ((int)r->cell == b->proc.active) {
        if (edram_insert(b, r))
            return;
        b->st->spills++;
    }
    bus_tap(b, r, NULL, 1);
    dsp_queue(b, r, (int)r->cell != b->proc.active);
    b->st->bus_packets++;
}

/* The DSP tags a ray with its Cell Tree node and queues it in SDRAM; arrival: it comes
 * from another cell (a spill of the active cell's own ray is not an arrival). */
static void dsp_queue(board *b, const c5_bray *r, int arrival)
{
    c5_bray q = *r;
    double t0 = c5_now_s();
    uint32_t id = C5_NODE_NONE, from_id = r->node; /* the nodes' ids in the tree's store */
    if (b->sdram) {
        /* The packet's node is its index among the nodes of the cell it was queued for, the
         * active cell (cell_tree_sdram.h); the DSP's directory gives its id. */
        int from = r->node == C5_NODE_NONE ? -1 : tree_unit(b, b->proc.active);
        from_id = from < 0 ? C5_DEMAND_NONE : c5_sdram_tree_id(b->sdram, from, r->node);
        q.node = c5_sdram_tree_tag(b->sdram, from, r->node, tree_unit(b, (int)r->cell), &id);
    } else {
        q.node = id = c5_ctree_tag(b->tree, r->node, tree_unit(b, (int)r->cell));
    }
    b->st->tree_wall_s += c5_now_s() - t0;
    /* The rays each node brings to its cell's queue (stale_plan.h); a spill of the active
     * cell's own ray is not an arrival. */
    if (b->o->node_rays && q.node != C5_NODE_NONE && arrival) {
        (b->sdram ? b->sdram->rays : b->o->node_rays)[id]++;
        b->st->node_count_ops += C5_OPS_NODE_COUNT;
    }
    if (b->certify && arrival)
        c5_mw_shadow_tag(&b->shadow, from_id, q.node == C5_NODE_NONE ? C5_DEMAND_NONE : id, (int)r->cell);
    q.shadow = c5_demand_tag(&b->demand, r->shadow, tree_unit(b, (int)r->cell));
    const c5_taps *t = b->o->taps;
    if (t && t->tree_tag)
        t->tree_tag(t->ctx, r->node, (int)r->cell, q.node);
    uint8_t pk[C5_PACKET_BYTES];
    pack(b, &q, pk);
    if (push_sdram(b, (int)r->cell, pk, q.shadow) != 0)
        b->oom = 1;
}

static void on_deliver(void *ctx, uint32_t u, uint32_t v, const int64_t rgb[3])
{
    board *b = ctx;
    if (b->eye_probe)
        return;
    uint64_t *px = b->fb + 3 * ((size_t)v * (size_t)b->s->render.width + u);
    for (int c = 0; c < 3; c++)
        px[c] += (uint64_t)rgb[c];
}

/* The cell of group g with the most queued rays (ties: lowest id), -1: none holds a ray. */
static int busiest_in_group(const board *b, int g)
{
    int best = -1;
    size_t best_n = 0;
    for (int c = 0; c < b->cells.count; c++) {
        size_t n = b->q[c].n - b->q[c].head;
        if (n > best_n && group_of(b, c, b->sgroup, b->nsgroup) == g) {
            best = c;
            best_n = n;
        }
    }
    return best;
}

static size_t queued_in(const board *b, int c) { return b->q[c].n - b->q[c].head; }

/* The queues the set-up left against the previous frame's: the sum over cells of the
 * smaller count over the larger total (1: the same rays in the same cells; 0: no cell in
 * common). 3 DSP operations a cell (in the certificate's). */
static double start_overlap(board *b)
{
    const c5_board_opts *o = b->o;
    int n = b->cells.count;
    uint64_t both = 0, now = 0, before = 0;
    for (int c = 0; c < n; c++) {
        uint64_t q = queued_in(b, c), p = o->prev_start[c];
        both += q < p ? q : p;
        now += q;
        before += p;
    }
    b->shadow.ops += 3 * (uint64_t)n;
    uint64_t most = now > before ? now : before;
    return most ? (double)both / (double)most : 1.0;
}

/* The frame's budget, after the set-up (ledger.h). */
static void set_budget(board *b)
{
    c5_board_stats *st = b->st;
    b->budget = st->ledger_budget = c5_ledger_budget(b->o->plan, st->frame_key, st->start_overlap, &st->identical);
}

/* The shadow broke (a packet it cannot place: the tree's RAM overflowed): nothing bounds the
 * rest of the frame, and Max Work on the board's queues chooses it. */
static void certificate_lost(board *b)
{
    b->certify = 0;
    b->st->shadow_broken = 1;
}

/* Max Work's choice on the board's queues: most queued rays, ties to the lowest id (fewest:
 * the fewest-first rule); -1: every queue is empty. */
static int pick_cell(const board *b, int fewest)
{
    int best = -1;
    size_t best_n = 0;
    for (int c = 0; c < b->cells.count; c++) {
        size_t n = queued_in(b, c);
        if (n && (best < 0 || (fewest ? n < best_n : n > best_n))) {
            best = c;
            best_n = n;
        }
    }
    return best;
}

/* The next load under the certificate: the board's own choice (the schedule's next cell with
 * rays, then Max Work on its queues) while the lead (the board's loads less the shadow's steps)
 * stays within the budget, else the cell of the shadow's next step. A load of the shadow's
 * cell lets it take at least one step, so the lead never grows past the budget, and the frame
 * ends within budget + Max Work's fetches. */
static int certified_next(board *b, int *pos)
{
    const c5_board_opts *o = b->o;
    c5_mw_shadow *sh = &b->shadow;
    int next = c5_mw_shadow_advance(sh);
    int64_t lead = (int64_t)b->st->fetches - (int64_t)sh->steps;
    if (sh->broken || (next < 0 && b->queued)) {
        certificate_lost(b); /* nothing bounds the rest: Max Work on the board's queues */
        *pos = o->schedule_len;
        return -3;
    }
    if (lead > b->st->lead_max)
        b->st->lead_max = lead;
    while (*pos < o->schedule_len && !queued_in(b, o->schedule[*pos])) {
        (*pos)++;
        b->st->sched_skipped++;
    }
    if (next < 0)
        return -1;
    int in_sched = *pos < o->schedule_len;
    if (lead + 1 <= b->budget) {
        if (in_sched) {
            b->st->sched_loads++;
            return o->schedule[(*pos)++];
        }
        b->st->sched_fallback++;
        return pick_cell(b, 0);
    }
    if (in_sched && !b->st->sched_switches++) {
        b->st->switched_at_load = (int64_t)b->st->fetches;
        b->st->switch_reason = C5_SWITCH_BUDGET;
        b->st->switch_value = (double)lead;
    }
    b->st->shadow_loads++;
    return next;
}

/* Which cell to load next, or -1 when every queue is empty. */
static int schedule(board *b, int *sched_pos)
{
    const c5_board_opts *o = b->o;
    if (o->sched == C5_SCHED_EXTERNAL && b->sgroup[0] * b->sgroup[1] * b->sgroup[2] > 1) {
        for (;;) {
            int c = b->cur_group < 0 ? -1 : busiest_in_group(b, b->cur_group);
            if (c >= 0) {
                b->st->sched_loads++;
                return c;
            }
            if (*sched_pos >= o->schedule_len)
                break;
            b->cur_group = o->schedule[(*sched_pos)++];
            if (busiest_in_group(b, b->cur_group) < 0)
                b->st->sched_skipped++;
        }
        b->st->sched_fallback++;
    } else if (o->sched == C5_SCHED_EXTERNAL) {
        int c = b->certify ? certified_next(b, sched_pos) : -3;
        if (c != -3)
            return c;
        while (*sched_pos < o->schedule_len) {
            int c = o->schedule[(*sched_pos)++];
            if (b->q[c].n > b->q[c].head) {
                b->st->sched_loads++;
                return c;
            }
            b->st->sched_skipped++;
        }
        b->st->sched_fallback++; /* undone below when no queue holds a ray */
    }
    int best = pick_cell(b, o->sched == C5_SCHED_MINWORK);
    if (best < 0 && o->sched == C5_SCHED_EXTERNAL)
        b->st->sched_fallback--;
    return best;
}

/* Moves rays from the cell's SDRAM queue into the sorter while it has room. */
static void refill(board *b, sdram_queue *q)
{
    while (q->head < q->n && edram_count(b) < (uint32_t)b->o->queue_capacity) {
        c5_bray r;
        c5_bray_unpack(q->pk[q->head], &b->cells, &r);
        r.shadow = q->shadow[q->head];
        if (!edram_insert(b, &r))
            break;
        bus_tap(b, &r, q->pk[q->head], 0);
        q->head++;
        b->queued--;
        b->st->bus_packets++;
    }
    if (q->head == q->n)
        q->head = q->n = 0;
}

/* Processes the active cell until its queue (eDRAM and spilled SDRAM part) is empty. */
static void process_cell(board *b, int cell)
{
    sdram_queue *q = &b->q[cell];
    for (;;) {
        refill(b, q);
        if (edram_count(b) == 0)
            break;
        c5_rq_in in = {.pop_ready = 1};
        c5_rq_out out;
        edram_step(b, &in, &out);
        c5_bray r;
        c5_bray_unpack(b->slot[out.pop_payload], &b->cells, &r);
        r.shadow = b->slot_shadow[out.pop_payload];
        b->free_slots[b->n_free++] = out.pop_payload;
        b->st->queue_pops++;
        c5_proc_run(&b->proc, &r);
    }
}

static uint64_t fetch_cycles(const c5_board_opts *o, size_t bytes)
{
    double bw = o->host_bw > 0 ? o->host_bw : 132e6;
    double lat = o->host_latency_s > 0 ? o->host_latency_s : o->host_latency_s < 0 ? 0 : 1e-3;
    double s = lat + (double)bytes / fmin(bw, RDRAM_BW);
    return (uint64_t)ceil(s * CLOCK_HZ);
}

/* The DSP's eye rays, pixel by pixel, through the processor's set-up unit. */
static int generate_eye_rays(board *b, const c5_supervol *sv, int frame, c5_err *err)
{
    const c5_scene *s = b->s;
    c5_camera cam = b->o->camera ? *b->o->camera : c5_scene_camera_at(s, frame);
    c5_camera_basis basis;
    int64_t O[3];
    if (c5_camera_basis_make(&cam, s->render.width, s->render.height, frame, &basis, err) != 0 ||
        c5_regs_geom_point(cam.eye, sv, O, "the eye", err) != 0)
        return -1;
    c5_bray proto = {.w = C5_ONE15, .type = C5_RAY_EYE, .node = C5_NODE_NONE, .shadow = C5_DEMAND_NONE};
    for (int py = 0; py < basis.h; py++)
        for (int px = 0; px < basis.w; px++) {
            if (b->px_owner && !b->eye_probe && b->px_owner[(size_t)py * (size_t)basis.w + (size_t)px] != b->o->link->self)
                continue;
            int64_t d[3];
            c5_regs_unit14(c5_camera_pixel_dir(&basis, px, py), d);
            proto.u = (uint32_t)px;
            proto.v = (uint32_t)py;
            c5_proc_new_ray(&b->proc, O, d, C5_T_INF, -1, &proto);
        }
    return 0;
}

static void board_free(board *b)
{
    if (b->q)
        for (int c = 0; c < b->cells.count; c++)
            free(b->q[c].pk), free(b->q[c].shadow);
    free(b->q);
    free(b->slot);
    free(b->slot_shadow);
    c5_demand_free(&b->demand);
    free(b->free_slots);
    free(b->fb);
    c5_rq_free(&b->edram);
    c5_rqh_free(&b->heap);
    free(b->own_tree);
    c5_mw_shadow_free(&b->shadow);
    free(b->out_pk);
    free(b->out_dest);
    free(b->px_owner);
    c5_rdram_free(&b->mem);
    c5_cells_free(&b->cells);
}

/* A volume-less grid still needs one (empty) cell for the tables. */
static const c5_supervol *grid_or_dummy(const c5_supervol *sv, c5_supervol *dummy, uint8_t *voxel)
{
    if (!c5_supervol_empty(sv))
        return sv;
    memset(dummy, 0, sizeof *dummy);
    dummy->dims[0] = dummy->dims[1] = dummy->dims[2] = 1;
    dummy->spacing = v3(1, 1, 1);
    *voxel = 0;
    dummy->v = voxel;
    return dummy;
}

/* ---- Several boards (opts.link; rtl_model/multi_board.h, docs/multi-board.md) ---------- */

/* During the eye-ray probe: records the pixel's first cell's board and drops the ray. Else a
 * ray for another board's cell goes into the out-box as its packet (over the ray bus to the
 * DSP, which sends it on at the next exchange). 1: taken here. */
static int link_enqueue(board *b, const c5_bray *r)
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
static int eye_owners(board *b, const c5_supervol *sv, int frame, c5_err *err)
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
    int rc = generate_eye_rays(b, sv, frame, err);
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
static int link_round(board *b, c5_err *err)
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
        dsp_queue(b, &r, 1);
    }
    st->link_received += n_in;
    if (b->oom)
        return c5_fail(err, "out of memory for the DSP's SDRAM ray queues");
    return more;
}

/* The next cell to load; with several boards, exchanges while this board's queues are empty
 * (so a followed schedule is not run through while rays are still on their way). -1: the
 * frame is over, -2: an error (err set). */
static int next_cell(board *b, int *sched_pos, c5_err *err)
{
    if (!b->o->link)
        return schedule(b, sched_pos);
    while (!b->queued) {
        int more = link_round(b, err);
        if (more <= 0)
            return more < 0 ? -2 : -1;
    }
    return schedule(b, sched_pos);
}

int c5_board_render(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *opts,
                    c5_image *out, c5_board_stats *stats, c5_err *err)
{
    double start = c5_now_s();
    memset(stats, 0, sizeof *stats);
    c5_board_opts o = *opts;
    for (int a = 0; a < 3; a++)
        if (o.cells[a] < 1)
            o.cells[a] = 0;
    c5_model_auto_split(sv->dims, o.cells); /* < 1: the fewest cells that fit the packet */
    if (!o.key)
        o.key = C5_KEY_MORTON;
    if (!o.sched)
        o.sched = C5_SCHED_MAXWORK;
    if (!o.queue_capacity)
        o.queue_capacity = C5_RQ_DEFAULT_CAPACITY;
    if (c5_supervol_empty(sv))
        o.cells[0] = o.cells[1] = o.cells[2] = 1;

    board b = {.s = s, .o = &o, .st = stats};
    c5_camera frame_cam = o.camera ? *o.camera : c5_scene_camera_at(s, frame);
    stats->frame_key = c5_frame_key(&frame_cam, s->render.width, s->render.height);
    b.mem.cell = -1;
    if (c5_regs_build(s, sv, &o, &b.r, err) != 0)
        return -1;
    int units = 1; /* what the schedule's entries name: cells, or groups */
    for (int a = 0; a < 3; a++) {
        group_axis(o.tree_group[a], o.cells[a], &b.group[a], &b.ngroup[a]);
        group_axis(o.schedule_group[a], o.cells[a], &b.sgroup[a], &b.nsgroup[a]);
        units *= b.nsgroup[a];
    }
    b.cur_group = -1;
    const char *unit = b.sgroup[0] * b.sgroup[1] * b.sgroup[2] > 1 ? "group" : "cell";
    if (o.sched == C5_SCHED_EXTERNAL)
        for (int i = 0; i < o.schedule_len; i++)
            if (o.schedule[i] < 0 || o.schedule[i] >= units)
                return c5_fail(err, "schedule entry %d: %s %d is outside the %d %ss of the split", i, unit,
                               o.schedule[i], units, unit);
    c5_supervol dummy;
    uint8_t voxel;
    const c5_supervol *grid = grid_or_dummy(sv, &dummy, &voxel);
    uint8_t alpha_nz[256];
    for (int i = 0; i < 256; i++)
        alpha_nz[i] = b.r.tf[i][3] > 0;
    c5_rq_cfg qcfg = {(uint32_t)o.queue_capacity, 32};
    size_t npx = (size_t)s->render.width * (size_t)s->render.height;
    const c5_board_host *host = c5_supervol_empty(sv) ? NULL : o.host;
    if ((host ? c5_cells_init_flags(&b.cells, grid->dims, o.cells, host->cell_empty, host->block_empty, err)
              : c5_cells_init(&b.cells, grid, o.cells, alpha_nz, err)) != 0)
        return -1;
    b.q = calloc((size_t)b.cells.count, sizeof *b.q);
    b.slot = malloc((size_t)o.queue_capacity * C5_PACKET_BYTES);
    b.slot_shadow = malloc((size_t)o.queue_capacity * sizeof *b.slot_shadow);
    b.free_slots = malloc((size_t)o.queue_capacity * sizeof *b.free_slots);
    b.fb = calloc(npx * 3, sizeof *b.fb);
    b.tree = o.tree;
    b.sdram = o.sdram_tree;
    if (!b.tree && (b.tree = b.own_tree = malloc(sizeof *b.own_tree)) != NULL)
        c5_ctree_init(b.tree, 0);
    b.cycle_level = o.queue_model == C5_QUEUE_CYCLE;
    if (!b.q || !b.slot || !b.slot_shadow || !b.free_slots || !b.fb || !b.tree || c5_demand_init(&b.demand) != 0 ||
        (b.cycle_level ? c5_rq_init(&b.edram, &qcfg) : c5_rqh_init(&b.heap, &qcfg)) != 0) {
        board_free(&b);
        return c5_fail(err, "out of memory for the board model (or queue capacity %d outside 1..%u)",
                       o.queue_capacity, C5_RQ_MAX_CAPACITY);
    }
    stats->switched_at_load = -1;
    stats->start_overlap = -1;
    if (o.moves)
        memset(o.moves, 0, (size_t)b.cells.count * (size_t)b.cells.count * sizeof *o.moves);
    if (o.node_rays)
        memset(o.node_rays, 0, C5_TREE_SLOTS * sizeof *o.node_rays);
    if (o.sched == C5_SCHED_EXTERNAL && o.stale_check >= 0 && !o.link && b.sgroup[0] * b.sgroup[1] * b.sgroup[2] == 1 &&
        b.group[0] * b.group[1] * b.group[2] == 1) {
        if (c5_mw_shadow_init(&b.shadow, b.cells.count, b.sdram ? c5_sdram_tree_max_nodes(b.sdram) : 0) != 0) {
            board_free(&b);
            return c5_fail(err, "out of memory for the board model");
        }
        b.certify = stats->certified = 1;
    }
    for (uint32_t i = 0; i < (uint32_t)o.queue_capacity; i++)
        b.free_slots[b.n_free++] = (uint32_t)o.queue_capacity - 1 - i;
    c5_proc_init(&b.proc, &b.r, &b.cells, &b.mem, (c5_proc_io){&b, on_enqueue, on_deliver});
    b.proc.taps = o.taps;
    stats->stages = b.r.st;
    stats->cells = b.cells.count;

    if (o.link && (o.taps || eye_owners(&b, sv, frame, err) != 0)) {
        board_free(&b);
        return o.taps ? c5_fail(err, "several boards: taps (golden vectors) are for one board") : -1;
    }
    if (generate_eye_rays(&b, sv, frame, err) != 0) {
        board_free(&b);
        return -1;
    }
    if (o.sched == C5_SCHED_EXTERNAL && o.prev_start && o.prev_start_len == b.cells.count)
        stats->start_overlap = start_overlap(&b);
    if (b.certify)
        set_budget(&b);
    if (o.start_counts)
        for (int c = 0; c < b.cells.count; c++)
            o.start_counts[c] = (uint32_t)queued_in(&b, c);
    /* Rays that never reach the volume were finished by the set-up: the first visit. */
    uint64_t proc_cycles = b.proc.st.cycles, bus = stats->bus_packets;
    stats->cycles_process += proc_cycles > bus ? proc_cycles : bus;
    int sched_pos = 0, cell = -1;
    while (!b.oom && (cell = next_cell(&b, &sched_pos, err)) >= 0) {
        if ((host ? c5_rdram_place(&b.mem, &b.cells, cell, err) != 0 ||
                        host->fetch(host->ctx, cell, b.mem.v, c5_cell_bytes(&b.cells, cell), err) != 0
                  : c5_rdram_load(&b.mem, &b.cells, grid, cell, err) != 0)) {
            board_free(&b);
            return -1;
        }
        size_t bytes = c5_cell_bytes(&b.cells, cell);
        stats->fetches++;
        if (o.fetch_log && stats->fetches <= (uint64_t)o.fetch_log_cap)
            o.fetch_log[stats->fetches - 1] = cell;
        stats->fetch_bytes += bytes;
        stats->cycles_fetch += fetch_cycles(&o, bytes);
        if (b.certify)
            c5_mw_shadow_load(&b.shadow, cell);
        b.proc.active = cell;
        uint64_t c0 = b.proc.st.cycles, p0 = stats->bus_packets;
        process_cell(&b, cell);
        uint64_t work = b.proc.st.cycles - c0 + C5_CYC_PIPELINE, moved = stats->bus_packets - p0;
        stats->cycles_process += work > moved ? work : moved; /* the bus runs beside the pipeline */
        if (o.progress)
            o.progress(o.progress_ctx, &(c5_board_progress){stats->fetches, b.queued});
    }
    if (b.certify && !b.oom && cell == -1) {
        if (c5_mw_shadow_advance(&b.shadow) >= 0 || b.shadow.broken)
            certificate_lost(&b); /* the shadow cannot finish with every queue empty: a model bug */
        else
            stats->shadow_steps = b.shadow.steps;
    }
    stats->shadow_ops = b.shadow.ops;
    if (b.oom || cell == -2) {
        board_free(&b);
        return cell == -2 ? -1 : c5_fail(err, "out of memory for the DSP's SDRAM ray queues");
    }
    if (c5_image_alloc(out, s->render.width, s->render.height, err) != 0) {
        board_free(&b);
        return -1;
    }
    /* frame_acc is UQ20.12: 32 bits a channel. Far beyond any scene's light, but a clamp
     * here would be counted, never wrapped. */
    if (o.frame_acc)
        memcpy(o.frame_acc, b.fb, npx * 3 * sizeof *b.fb);
    for (size_t i = 0; i < npx * 3; i++) {
        if (b.fb[i] > UINT32_MAX && !o.link) { /* several boards: their sum is clamped */
            b.fb[i] = UINT32_MAX;
            b.proc.st.saturations++;
        }
        out->rgb[i] = (float)ldexp((double)b.fb[i], -C5_RGB_F);
    }
    if (o.taps && o.taps->frame)
        o.taps->frame(o.taps->ctx, b.fb, s->render.width, s->render.height);

    const c5_proc_stats *ps = &b.proc.st;
    memcpy(stats->rays, ps->rays, sizeof stats->rays);
    memcpy(stats->ends, ps->ends, sizeof stats->ends);
    stats->samples = ps->samples;
    stats->samples_leaped = ps->leaped;
    stats->cache_hits = ps->cache_hits;
    stats->cache_misses = ps->cache_misses;
    stats->saturations = ps->saturations;
    stats->queue_max = b.cycle_level ? b.edram.stats.max_count : b.heap.stats.max_count;
    stats->tree_nodes = b.tree->nodes;
    stats->tree_slots = b.tree->used;
    stats->tree_overflow = b.tree->overflow;
    stats->tree_demand_nodes = b.demand.oom ? 0 : b.demand.n;
    stats->tree_demand_slots = b.demand.oom ? 0 : c5_demand_slots(&b.demand, C5_TREE_CHILDREN);
    stats->tree_demand_slots6 = b.demand.oom ? 0 : c5_demand_slots(&b.demand, 6);
    stats->tree_demand_sum_maxgen = c5_demand_sum_maxgen(&b.demand);
    stats->tree_tags = b.tree->tags;
    stats->tree_reads = b.tree->reads;
    stats->tree_writes = b.tree->writes;
    if (b.sdram) {
        const c5_sdram_tree *t = b.sdram;
        stats->tree_sdram = 1;
        stats->tree_nodes = t->t.n;
        stats->tree_slots = (uint32_t)t->slots;
        stats->tree_overflow = t->overflow || t->t.oom;
        stats->tree_tags = t->tags;
        stats->tree_reads = t->reads + t->dir_reads;
        stats->tree_writes = t->writes;
        stats->tree_sdram_bytes = c5_sdram_tree_bytes_used(t);
        stats->tree_cell_nodes_max = t->max_index;
    }
    stats->cycles = stats->cycles_process + stats->cycles_fetch;
    stats->board_s = (double)stats->cycles / CLOCK_HZ;
    board_free(&b);
    stats->wall_s = c5_now_s() - start;
    return 0;
}
